"""Steady rolling solved directly: Carter's cylinder, and a wheel on a worn, conformal rail.

Left: a 50 mm steel cylinder rolling on flat steel (a line contact: ``grid.periodic = "y"``,
Hertz half-width b = 1 mm, mu = 0.3), one creep curve of 24 steady states from xi = 0 to past
Carter's full slip ``xi = mu b / R``, beside Carter's closed form ``F / (mu w) = 1 - (1 - xi R
/ (mu b))^2``.  Right: a wheel on a worn rail, the gap given point by point (a height map:
the wheel's 460 mm radius along the rolling direction, a transverse profile worn nearly
conformal, flat over 4 mm and rising as the fourth power beyond), 40 kN, mu = 0.3: the shear
traction over mu p and the stick area at the creepage where the creep force is half mu W.
The script prints Carter's largest error over the curve and exits with status 1 when it
passes 1 % of mu w, or when a solve does not converge.

Run: ``python examples/steady_rolling.py --out figures`` (its run time: docs/run-times.md).
"""

from __future__ import annotations

import math
import sys
import tempfile
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
from _common import output_folder

import solver
from solver.theory.line import carter_force_ratio, hertz_line
from study.campaign.surfaces import read_surface

E, NU, MU = 210e9, 0.3, 0.3
E_STAR = E / (2 * (1 - NU * NU))
STEEL = {"behaviour": "elastic", "E": E, "nu": NU}


def carter_curve() -> tuple[np.ndarray, np.ndarray, float, bool]:
    """The cylinder's creep curve: creepage over full slip's, F / (mu w), Carter's error."""
    radius, half_width, across = 0.05, 1e-3, 64
    per_length = math.pi * E_STAR * half_width**2 / (4 * radius)  # N/m: b = 1 mm
    cell = 2 * half_width / across
    nx, ny = round(1.3 * across), 4
    saturation = MU * half_width / radius
    case = solver.Case.from_dict(
        {
            "body1": {**STEEL, "radius_x": radius},
            "body2": STEEL,
            "friction": {"coefficient": MU},
            "load": {
                "path": [
                    {"normal_force": per_length * ny * cell},  # the force on the period Ly
                    {"steady": True, "creepage": [1.2 * saturation, 0.0], "steps": 24},
                ]
            },
            "grid": {"n": [nx, ny], "size": [nx * cell, ny * cell], "periodic": "y"},
        }
    )
    result = solver.solve(case)
    b, _ = hertz_line(per_length, E_STAR, radius)
    xi = result.history["creepage_x"][1:]
    ratio = result.history["tangential_force_x"][1:] / (MU * per_length * ny * cell)
    carter = np.array([carter_force_ratio(v, MU, b, radius) for v in xi])
    return xi / saturation, ratio, float(np.abs(ratio - carter).max()), result.converged


def worn_rail(folder: Path):
    """The wheel on the worn rail: a creep curve, and the state at half mu W."""
    wheel, flat, rise, force = 0.46, 2e-3, 4e-3, 40e3  # m, m, m, N
    spacing = 25e-6
    side = np.arange(-11e-3, 11e-3 + spacing / 2, spacing)
    along = across = side
    x, y = np.meshgrid(along, across)  # height[j, i] at (x[i], y[j])
    beyond = np.clip(np.abs(y) - flat, 0.0, None)
    gap = x * x / (2 * wheel) + 1e-4 * (beyond / rise) ** 4  # 0.1 mm at 4 mm past the flat
    np.save(folder / "worn.npy", gap)
    table = {
        "body1": {**STEEL, "surface": {"file": str(folder / "worn.npy"), "spacing": spacing}},
        "body2": STEEL,
        "friction": {"coefficient": MU},
        "load": {
            "path": [
                {"normal_force": force},
                {"steady": True, "creepage": [3e-3, 0.0], "steps": 12},
            ]
        },
        "grid": {"n": [80, 80], "size": [20e-3, 20e-3]},
    }
    curve = solver.solve(solver.Case.from_dict(table, read_surface))
    ratio = curve.history["tangential_force_x"][1:] / (MU * force)
    xi = curve.history["creepage_x"][1:]
    half = float(np.interp(0.5, ratio, xi))  # the creepage of half mu W
    table["load"]["path"][1] = {"steady": True, "creepage": [half, 0.0]}
    state = solver.solve(solver.Case.from_dict(table, read_surface))
    return half, state, curve.converged and state.converged


def main() -> int:
    """Solve both, print the check, draw the figure; 0 when it passes, else 1."""
    out = output_folder(__doc__.splitlines()[0])
    xi_n, ratio, error, line_ok = carter_curve()
    with tempfile.TemporaryDirectory() as folder:
        half, state, worn_ok = worn_rail(Path(folder))
    print(f"Carter: largest creep-force error {100 * error:.2f} % of mu w over the curve")
    print(f"worn rail: half mu W at a creepage of {1e3 * half:.3f} per mille")
    print(f"every solve converged: {line_ok and worn_ok}")

    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.2), constrained_layout=True)
    curve = np.linspace(0.0, 1.2, 121)
    left.plot(curve, [carter_force_ratio(v, 1.0, 1.0, 1.0) for v in curve], "k-", lw=1,
              label="Carter 1926 (closed form)")  # fmt: skip
    left.plot(xi_n, ratio, "o", ms=4, label="steady solves (64 cells across)")
    left.set(
        xlabel="creepage over full slip's, xi R / (mu b) (1)",
        ylabel="creep force F_x / (mu w) (1)",
        title=f"cylinder (line contact): within {100 * error:.2f} % of Carter",
    )
    left.legend(fontsize=8)
    x, y = state.grid.mesh()
    bound = MU * state.pressure
    share = np.divide(np.hypot(state.shear_x, state.shear_y), bound, out=np.zeros_like(bound),
                      where=bound > 0)  # fmt: skip
    shown = np.where(state.pressure > 0, share, np.nan)
    image = right.pcolormesh(x * 1e3, y * 1e3, shown, vmin=0, vmax=1, cmap="viridis")
    right.contour(x * 1e3, y * 1e3, (state.contact_state == 1).astype(float), [0.5],
                  colors="w", linewidths=1.5)  # fmt: skip
    right.set(
        xlabel="x (mm), rolling towards +x",
        ylabel="y (mm), across the rail",
        aspect="equal",
        xlim=(-6, 6),
        ylim=(-6, 6),
        title=f"worn rail, xi = {1e3 * half:.2f} per mille (half mu W): stick outlined",
    )
    fig.colorbar(image, ax=right, label="|q| / (mu p) (1)")
    fig.savefig(out / "steady_rolling.png", dpi=120)
    return 0 if line_ok and worn_ok and error < 0.01 else 1


if __name__ == "__main__":
    sys.exit(main())
