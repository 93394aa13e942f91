"""Fretting: the tangential force-displacement loop of two steel spheres under partial slip.

Two identical steel spheres (R = 15 mm, beta = 0) pressed with W = 1000 N, then a cycle block
of 3 cycles of the tangential force between -Q* and +Q* (Q* = 0.5 mu W, mu = 0.3), 10 steps per
half cycle, 48^2 cells.  The figure draws Q against the tangential shift Delta with the loop of
every cycle; the script prints the energy dissipated per cycle beside Mindlin & Deresiewicz's
closed form (Johnson 1985, eq. 7.64) and exits with status 1 if the last cycle's differs by more
than 5 %.

Run: ``python examples/fretting_loop.py --out figures`` (its run time: docs/run-times.md).
"""

from __future__ import annotations

import sys

import matplotlib.pyplot as plt
from _common import output_folder, series_style

import solver
from solver.theory.friction import mindlin_deresiewicz_energy

MU, W, FRACTION, E, NU = 0.3, 1000.0, 0.5, 210e9, 0.3
STEEL = {"behaviour": "elastic", "radius": 0.015, "E": E, "nu": NU}
AMPLITUDE = FRACTION * MU * W
CASE = {
    "body1": STEEL,
    "body2": STEEL,
    "load": {
        "path": [
            {"normal_force": W},
            {"tangential_force": [AMPLITUDE, 0.0], "steps": 10},
            {
                "cycles": 3,
                "stages": [
                    {"tangential_force": [-AMPLITUDE, 0.0], "steps": 10},
                    {"tangential_force": [AMPLITUDE, 0.0], "steps": 10},
                ],
            },
        ]
    },
    "friction": {"coefficient": MU},
    "grid": {"n": 48},
}


def main() -> int:
    """Solve, print the check, draw the figure; 0 when the check passes, else 1."""
    out = output_folder(__doc__.splitlines()[0])
    result = solver.solve(solver.Case.from_dict(CASE))
    ds = result.to_xarray()
    # full-slip shift of two identical bodies: twice one body's (Johnson 1985, eq. 7.42)
    shear_modulus = E / (2 * (1 + NU))
    full_slip = 2 * 3 * MU * W * (2 - NU) / (16 * shear_modulus * ds.attrs["hertz_radius"])
    expected = mindlin_deresiewicz_energy(AMPLITUDE, MU, W, full_slip)
    energy = ds.loop_energy.values
    for cycle, value in zip(ds.cycle.values, energy, strict=True):
        print(
            f"cycle {cycle}: dissipated {1e6 * value:.3f} uJ "
            f"(Mindlin-Deresiewicz {1e6 * expected:.3f})"
        )
    fig, ax = plt.subplots(figsize=(6, 4.5), constrained_layout=True)
    ax.plot(
        ds.tangential_shift_x * 1e6,
        ds.tangential_force_x,
        "-",
        color="0.7",
        lw=1,
        label="whole path",
    )
    cycles = ds.cycle.values
    for j, cycle in enumerate(cycles):  # the loops coincide: each its own style, all visible
        steps = ds.step_cycle == cycle
        ax.plot(
            ds.tangential_shift_x[steps] * 1e6,
            ds.tangential_force_x[steps],
            **series_style(j, len(cycles), int(steps.sum())),
            label=f"cycle {cycle}",
        )
    ax.set(xlabel="tangential shift Delta_x (um)", ylabel="tangential force Q_x (N)")
    fig.suptitle(
        f"fretting loop, Q* = {FRACTION} mu W: {1e6 * energy[-1]:.2f} uJ per cycle\n"
        "(the cycles coincide)"
    )
    ax.legend(fontsize=8)
    fig.savefig(out / "fretting_loop.png", dpi=120)
    return 0 if result.converged and abs(energy[-1] / expected - 1) < 0.05 else 1


if __name__ == "__main__":
    sys.exit(main())
