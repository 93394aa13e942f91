"""Hertz contact: the computed pressure of a rigid sphere on steel against the closed form.

A rigid sphere (R = 15 mm) pressed on a steel half-space to a Hertz pressure of 2 GPa, solved
on 32^2, 64^2 and 128^2 cells; the figure overlays the pressure along x through the centre on
Hertz's p_0 sqrt(1 - r^2/a^2) and prints the peak-pressure error per mesh, which falls with the
square of the cell size.  Exits with status 1 if the finest error exceeds 0.1 %.

Run: ``python examples/hertz_pressure.py --out figures`` (its run time: docs/run-times.md).
"""

from __future__ import annotations

import sys

import matplotlib.pyplot as plt
import numpy as np
from _common import output_folder, series_style

import solver

CASE = {
    "body1": {"behaviour": "rigid", "radius": 0.015},
    "body2": {"behaviour": "elastic", "radius": "inf", "E": 210e9, "nu": 0.3},
    "load": {"hertz_pressure": 2e9},
    "grid": {"half_width": 1.5},
}


def main() -> int:
    """Solve, print the check, draw the figure; 0 when the check passes, else 1."""
    out = output_folder(__doc__.splitlines()[0])
    fig, ax = plt.subplots(figsize=(6, 4), constrained_layout=True)
    errors = []
    meshes = (32, 64, 128)
    for j, n in enumerate(meshes):
        result = solver.solve(solver.Case.from_dict({**CASE, "grid": {**CASE["grid"], "n": n}}))
        hertz = result.case.hertz
        x = result.grid.x
        row = result.pressure[:, result.grid.ny // 2]  # the row nearest y = 0
        errors.append(abs(result.pressure.max() / hertz.max_pressure - 1))
        # the meshes coincide: each its own colour, marker and line style, shifted markers
        style = series_style(j, len(meshes), len(x))
        ax.plot(x / hertz.radius, row / 1e9, **style, label=f"{n}^2 cells")
        print(f"n = {n:4d}: p_max error {errors[-1]:.2e}, converged {result.converged}")
    r = np.linspace(-1.5, 1.5, 601) * hertz.radius
    ax.plot(r / hertz.radius, hertz.pressure(r, 0.0) / 1e9, "-", color="0.6", lw=4, zorder=1,
            label="Hertz")  # fmt: skip
    ax.set(
        xlabel="x / a_H (1)",
        ylabel="contact pressure (GPa)",
        title="rigid sphere on steel, p_H = 2 GPa",
    )
    ax.legend()
    fig.savefig(out / "hertz_pressure.png", dpi=120)
    return 0 if errors[-1] < 1e-3 and errors[-1] < errors[0] else 1


if __name__ == "__main__":
    sys.exit(main())
