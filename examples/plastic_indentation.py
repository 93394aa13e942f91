"""Elastic-plastic indentation: plastic zone under a rigid sphere and the dent it leaves.

A rigid sphere (R = 15 mm) pressed into a Swift-hardening steel (the reference paper's
B = 945 MPa, C = 20, n = 0.121; first yield at p_H = 2.2 GPa) to a Hertz pressure of 5 GPa in
4 steps, then lifted off, on 24^3 cells.  Left: the equivalent plastic strain in the x-z plane
through the contact centre at the maximum load (the volume box is sized from the yield region);
right: the residual dent along x.  The script prints e_p,max, its depth (Johnson: first yield
at 0.48 a) and the dent depth, and exits with status 1 if a step did not converge.

Run: ``python examples/plastic_indentation.py --out figures`` (its run time: docs/run-times.md).
"""

from __future__ import annotations

import sys

import matplotlib.pyplot as plt
from _common import output_folder

import solver

CASE = {
    "body1": {"behaviour": "rigid", "radius": 0.015},
    "body2": {
        "behaviour": "elastic-plastic",
        "radius": "inf",
        "E": 210e9,
        "nu": 0.3,
        "hardening": {"law": "swift", "B": 945e6, "C": 20.0, "n": 0.121},
    },
    "load": {"path": [{"hertz_pressure": 5e9, "steps": 4}, {"normal_force": 0.0, "steps": 1}]},
    "grid": {"n": [24, 24, 24]},
}


def main() -> int:
    """Solve, print the check, draw the figure; 0 when the check passes, else 1."""
    out = output_folder(__doc__.splitlines()[0])
    result = solver.solve(solver.Case.from_dict(CASE))
    ds = result.to_xarray()
    a = ds.attrs["hertz_radius"]
    loaded = int(ds.normal_force.argmax("step"))
    print(
        f"status {result.status}; e_p,max {100 * float(ds.max_plastic_strain[loaded]):.3f} % at "
        f"z = {float(ds.max_plastic_strain_depth[loaded]) / a:.2f} a_H; dent after unloading "
        f"{1e6 * float(ds.residual_depth[-1]):.2f} um"
    )
    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4), constrained_layout=True)
    # the field is the final one (after unloading: the plastic strain stays)
    section = ds.plastic_strain.sel(y=0.0, method="nearest") * 100
    mesh = left.contourf(ds.x / a, ds.z / a, section.T, levels=12, cmap="viridis")
    left.invert_yaxis()
    fig.colorbar(mesh, ax=left, label="equivalent plastic strain (%)")
    left.set(
        xlabel="x / a_H (1)", ylabel="depth z / a_H (1)", title="plastic strain, section y = 0"
    )
    dent = ds.residual_displacement_z.sel(y=0.0, method="nearest") * 1e6
    right.plot(ds.x / a, -dent, "o-", ms=3)
    right.set(
        xlabel="x / a_H (1)", ylabel="surface height (um)", title="residual dent after unloading"
    )
    fig.savefig(out / "plastic_indentation.png", dpi=120)
    return 0 if result.converged else 1


if __name__ == "__main__":
    sys.exit(main())
