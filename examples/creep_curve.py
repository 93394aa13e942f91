"""Rolling with creepage: the creep force curve of two steel balls and the stick zone in front.

A ball rolls over a flat of the same steel (nu = 0.25: Dundurs' beta = 0) under W = 1000 N
(contact radius a of about 0.64 mm), mu = 0.3, at longitudinal creepages from 0.2 % of full
slip to past it.  Each creepage is a rolling stage of 6 a from a Cattaneo start (Kalker's
transient theory in body 2's frame, 16 cells across the contact, steps of a/32); its steady
creep force is the mean over the last 2 a.  The figure shows the creep force against the
normalised creepage G a^2 C11 xi / (3 mu W), with Kalker's linear theory and full slip mu W,
and the shear traction along the rolling direction at the largest partial-slip creepage with
its stick zone at the leading edge.  The script prints the computed C11 beside Kalker's table
(4.12) and the largest force beside mu W, and exits with status 1 when C11 is off by more than
3 % or the force at full slip by more than 1 %.

Run: ``python examples/creep_curve.py --out figures`` (its run time: docs/run-times.md).
"""

from __future__ import annotations

import sys

import matplotlib.pyplot as plt
import numpy as np
from _common import output_folder

import solver
from solver.theory.friction import KALKER_CIRCLE_COEFFICIENTS

E, NU, MU, W = 210e9, 0.25, 0.3, 1000.0
G = E / (2 * (1 + NU))
C11 = KALKER_CIRCLE_COEFFICIENTS[NU][0]
ACROSS = 16  # cells across the contact
TRAVEL, AVERAGE = 6.0, 2.0  # contact radii rolled, and averaged at the end
NORMALISED = (0.002, 0.1, 0.3, 0.5, 0.7, 1.0, 1.5)  # G a^2 C11 xi / (3 mu W): 1 is about full slip


def case(radius: float, xi: float) -> solver.Case:
    """Load, shear to the Johnson-Vermeulen estimate, roll TRAVEL radii at creepage ``xi``."""
    normalised = min(G * radius**2 * C11 * xi / (3 * MU * W), 1.0)
    start = 0.9 * (1 - (1 - normalised) ** 3) * MU * W
    n = (round((TRAVEL + 2.4) * ACROSS / 2), round(2.4 * ACROSS / 2))
    return solver.Case.from_dict(
        {
            "body1": {"behaviour": "elastic", "E": E, "nu": NU, "radius": 0.025},
            "body2": {"behaviour": "elastic", "E": E, "nu": NU},
            "friction": {"coefficient": MU},
            "load": {
                "path": [
                    {"normal_force": W},
                    {"tangential_force": [start, 0.0], "steps": 4},
                    {
                        "roll": [TRAVEL * radius, 0.0],
                        "creepage": [xi, 0.0],
                        "steps": round(TRAVEL * 2 * ACROSS),
                    },
                ]
            },
            "grid": {"n": list(n), "half_width": 1.2},
        }
    )


def main() -> int:
    """Roll at each creepage, print the checks, draw the figure; 0 when they pass, else 1."""
    out = output_folder(__doc__.splitlines()[0])
    probe = solver.Case.from_dict(
        {
            "body1": {"behaviour": "elastic", "E": E, "nu": NU, "radius": 0.025},
            "body2": {"behaviour": "elastic", "E": E, "nu": NU},
            "load": {"path": [{"normal_force": W}]},
            "grid": {"n": 32},
        }
    )
    a = probe.hertz.radius
    last = round(AVERAGE * 2 * ACROSS)
    creepages = [normalised * 3 * MU * W / (G * a * a * C11) for normalised in NORMALISED]
    results = [solver.solve(case(a, xi)) for xi in creepages]
    forces = [float(np.mean(r.history["tangential_force_x"][-last:])) for r in results]
    c11 = forces[0] / (G * a * a * creepages[0])
    full = forces[-1] / (MU * W)
    converged = all(r.converged for r in results)
    print(f"C11 computed {c11:.3f}, Kalker {C11:.2f}; F/(mu W) at full slip {full:.4f}")
    print(f"every stage converged: {converged}")

    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4), constrained_layout=True)
    curve = np.linspace(0, 1.6, 161)
    left.plot(NORMALISED, np.array(forces) / (MU * W), "o", label="computed (steady, 6 a)")
    left.plot(curve, 3 * curve, "k:", lw=1, label="Kalker's linear theory (C11)")
    left.axhline(1.0, color="k", lw=1, ls="--", label="full slip mu W")
    left.set(
        xlabel="normalised creepage G a^2 C11 xi / (3 mu W) (1)",
        ylabel="creep force F_x / (mu W) (1)",
        ylim=(0, 1.15),
        title=f"C11 = {c11:.3f} (Kalker {C11:.2f})",
    )
    left.legend(fontsize=8)
    partial = results[NORMALISED.index(0.3)]
    j = partial.grid.ny // 2
    x = (partial.grid.x - partial.history["position_x"][-1]) / a
    stick = partial.contact_state[:, j] == 1
    right.plot(x, partial.shear_x[:, j] / 1e6, "o-", ms=3, label="q_x (computed)")
    right.plot(x, MU * partial.pressure[:, j] / 1e6, "k--", lw=1, label="mu p (slip bound)")
    if stick.any():
        right.axvspan(x[stick].min(), x[stick].max(), color="tab:green", alpha=0.15,
                      label="stick (computed)")  # fmt: skip
    right.set(
        xlabel="x / a, rolling towards +x (1)",
        ylabel="shear traction (MPa)",
        xlim=(-1.3, 1.3),
        title="normalised creepage 0.3: stick at the leading edge",
    )
    right.legend(fontsize=8)
    fig.savefig(out / "creep_curve.png", dpi=120)
    return 0 if converged and abs(c11 / C11 - 1) < 0.03 and abs(full - 1) < 0.01 else 1


if __name__ == "__main__":
    sys.exit(main())
