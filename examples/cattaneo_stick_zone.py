"""Partial slip (Cattaneo-Mindlin): shear traction and stick zone of two steel spheres.

Two identical steel spheres (R = 15 mm, so Dundurs' beta = 0) pressed together with W = 1000 N,
then sheared with Q = 0.5 mu W (mu = 0.3).  The figure shows the shear traction along x through
the centre against the closed form (mu p_0 / a) [sqrt(a^2 - r^2) - sqrt(c^2 - r^2)] and the
stick zone r < c with c / a = (1 - Q / (mu W))^(1/3); the script prints the computed and exact
c / a and exits with status 1 if they differ by more than 0.02.

Run: ``python examples/cattaneo_stick_zone.py --out figures`` (its run time: docs/run-times.md).
"""

from __future__ import annotations

import math
import sys

import matplotlib.pyplot as plt
import numpy as np
from _common import output_folder

import solver
from solver.theory.friction import cattaneo_stick_ratio

MU, W, FRACTION = 0.3, 1000.0, 0.5
STEEL = {"behaviour": "elastic", "radius": 0.015, "E": 210e9, "nu": 0.3}
CASE = {
    "body1": STEEL,
    "body2": STEEL,
    "load": {"path": [{"normal_force": W}, {"tangential_force": [FRACTION * MU * W, 0.0]}]},
    "friction": {"coefficient": MU},
    "grid": {"n": 96, "half_width": 1.5},
}


def main() -> int:
    """Solve, print the check, draw the figure; 0 when the check passes, else 1."""
    out = output_folder(__doc__.splitlines()[0])
    result = solver.solve(solver.Case.from_dict(CASE))
    a_h = result.case.hertz.radius
    a = math.sqrt(result.history["contact_area"][-1] / math.pi)
    c = math.sqrt(result.history["stick_area"][-1] / math.pi)
    exact = cattaneo_stick_ratio(FRACTION * MU * W, MU, W)
    print(f"c/a computed {c / a:.4f}, Cattaneo-Mindlin {exact:.4f}, converged {result.converged}")

    j = result.grid.ny // 2
    x = result.grid.x
    r = np.linspace(-1.3, 1.3, 521) * a_h
    p0 = result.case.hertz.max_pressure
    c_h = exact * a_h
    closed = (
        MU
        * p0
        / a_h
        * (np.sqrt(np.clip(a_h**2 - r**2, 0, None)) - np.sqrt(np.clip(c_h**2 - r**2, 0, None)))
    )
    fig, ax = plt.subplots(figsize=(6, 4), constrained_layout=True)
    ax.plot(x / a_h, result.shear_x[:, j] / 1e6, "o", ms=3, label="computed q_x")
    ax.plot(r / a_h, closed / 1e6, "k-", lw=1, label="Cattaneo-Mindlin")
    ax.plot(x / a_h, MU * result.pressure[:, j] / 1e6, "--", lw=1, label="mu p (slip bound)")
    ax.axvspan(-c / a_h, c / a_h, color="tab:green", alpha=0.12, label="stick zone (computed)")
    ax.set(
        xlabel="x / a_H (1)",
        ylabel="shear traction (MPa)",
        title=f"Q = {FRACTION} mu W, mu = {MU}: c/a = {c / a:.3f} (exact {exact:.3f})",
    )
    ax.legend(fontsize=8)
    fig.savefig(out / "cattaneo_stick_zone.png", dpi=120)
    return 0 if abs(c / a - exact) < 0.02 else 1


if __name__ == "__main__":
    sys.exit(main())
