"""Bring your own surface: a height-map file pressed by a sphere, smooth and rough.

Writes two netCDF height maps the way a profilometer export would be converted (a variable
``height(y, x)`` in metres over coordinates ``x``, ``y`` in metres): a flat surface, and the same
surface with a measured-like roughness (here made by ``solver.bodies.heights.Roughness``, rms 0.2
um). Each map is body 2's surface under a rigid sphere (R = 15 mm, 60 N, steel).  The flat map must
give Hertz's peak pressure within 0.5 % (a check of the file's sign and units); the rough one
shows the contact breaking into spots.  The figure: the rough heights, and the pressure on the
smooth and the rough map.  Exits with status 1 if the check fails.

Run: ``python examples/your_surface.py --out figures`` (its run time: docs/run-times.md).
"""

from __future__ import annotations

import sys

import matplotlib.pyplot as plt
import numpy as np
import xarray as xr
from _common import output_folder

import solver
from solver.bodies.heights import Roughness
from study.campaign.surfaces import read_surface


def write_map(path, x, y, height) -> None:
    """A height map as the solver reads it: height(y, x) and x, y in metres."""
    xr.Dataset(
        {"height": (("y", "x"), height, {"units": "m", "long_name": "surface height"})},
        coords={"x": ("x", x, {"units": "m"}), "y": ("y", y, {"units": "m"})},
    ).to_netcdf(path)


def draw(heights, flat, rough, extent, spots: int):
    """The figure: the rough heights, and the pressure on the flat and on the rough map.

    Each panel's title names the field; its quantity and unit are on its colour bar, under the
    panel, so no title runs into a colour bar.

    Parameters
    ----------
    heights, flat, rough : numpy.ndarray
        The rough map's heights (m) and the pressures (Pa) on the flat and the rough map,
        indexed (x, y).
    extent : sequence of float
        ``(x0, x1, y0, y1)`` of the grid over a_H.
    spots : int
        Contact spots of the rough map.

    Returns
    -------
    matplotlib.figure.Figure
        The figure.
    """
    fig, axes = plt.subplots(1, 3, figsize=(12, 4.6), layout="constrained")
    panels = [
        (heights * 1e6, "rough map: heights", "height (um)", "RdBu_r"),
        (flat / 1e9, "flat map: pressure", "pressure (GPa)", "viridis"),
        (rough / 1e9, f"rough map: pressure, {spots} spots", "pressure (GPa)", "viridis"),
    ]
    for ax, (field, title, label, cmap) in zip(axes, panels, strict=True):
        image = ax.imshow(field.T, origin="lower", extent=extent, cmap=cmap)
        ax.set(title=title, xlabel="x / a_H (1)", ylabel="y / a_H (1)")
        fig.colorbar(image, ax=ax, location="bottom", shrink=0.8, aspect=30, label=label)
    fig.suptitle("a height map pressed by a rigid sphere (R = 15 mm, 60 N)")
    return fig


def main() -> int:
    """Write the maps, solve, print the check, draw the figure; 0 when the check passes."""
    out = output_folder(__doc__.splitlines()[0])
    # a 1 mm x 1 mm map sampled every 2 um (the solver's cells are about 3.4 um here)
    x = y = np.linspace(-0.5e-3, 0.5e-3, 501)
    xx, yy = np.meshgrid(x, y)  # (y, x), as in the file
    rough = Roughness(hurst=0.8, long_cutoff=2e-4, short_cutoff=2e-5, rms=2e-7, seed=3)
    write_map(out / "flat.nc", x, y, np.zeros_like(xx))
    write_map(out / "rough.nc", x, y, rough.sample(xx, yy))

    results = {}
    for name in ("flat", "rough"):
        table = {
            "body1": {"behaviour": "rigid", "radius": 0.015},
            "body2": {"behaviour": "elastic", "E": 210e9, "nu": 0.3,
                      "surface": str(out / f"{name}.nc")},
            "load": {"normal_force": 60.0},
            "grid": {"n": 128, "half_width": 1.5},
        }  # fmt: skip
        case = solver.Case.from_dict(table, read_surface)
        results[name] = solver.solve(case)
    hertz = results["flat"].case.hertz
    error = abs(results["flat"].pressure.max() / hertz.max_pressure - 1)
    spots = int(results["rough"].history["contact_spots"][-1])
    print(f"flat map: p_max {results['flat'].pressure.max() / 1e9:.3f} GPa, Hertz "
          f"{hertz.max_pressure / 1e9:.3f} GPa (error {error:.2e})")  # fmt: skip
    area = [results[name].history["contact_area"][-1] for name in ("rough", "flat")]
    print(f"rough map: p_max {results['rough'].pressure.max() / 1e9:.3f} GPa, "
          f"{spots} contact spots, real area {area[0] / area[1]:.2f} of the smooth")  # fmt: skip

    grid = results["rough"].grid
    extent = np.array([grid.x[0], grid.x[-1], grid.y[0], grid.y[-1]]) / hertz.radius
    heights = results["rough"].fields["initial_gap"] - results["flat"].fields["initial_gap"]
    fig = draw(heights, results["flat"].pressure, results["rough"].pressure, extent, spots)
    fig.savefig(out / "your_surface.png", dpi=120)
    ok = error < 5e-3 and all(r.converged for r in results.values()) and spots > 1
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
