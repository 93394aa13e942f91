"""Melan's theorem for any surface load passing along x: tractions given on cells.

:func:`traction_limit` takes the tractions of a contact (a solved case's pressure and shear on
its cells, or an elliptical Hertz pressure put on cells) and passes them along x over the
half-space: the elastic field at every point of the track's cross-section and every position
comes from one subsurface-stress evaluation of the fixed load (:mod:`solver.volume.stress`:
cell-averaged Love and Cerruti kernels, DC-FFT) on a grid that reaches ``span`` cells ahead
of and behind the load, since a point at ``x`` sees the load centred at ``-x``.  The surface
points take the same kernels a thousandth of a cell deep.  The factor is a multiple of the
load given (at least 1: the load shakes down).

The load must be symmetric about the track's centre line y = 0 (a circular or elliptical
Hertz contact, a case's contact sliding along x): the cross-section is its half y >= 0
(:func:`.residual.section_basis` with ``symmetric``), and the tractions' grid is centred on
y = 0 with an even number of cells across.
"""

from __future__ import annotations

import math

import numpy as np

from ..numerics.grid import SurfaceGrid, VolumeGrid
from ..volume.stress import SubsurfaceStressOperator
from .melan import (
    SURFACE_SHIFTS,
    certified_factors,
    deviatoric_coordinates,
    likeliest_cells,
    pointwise_limit,
    static_limit,
)
from .residual import section_basis
from .track import CANDIDATES, TrackLimits

#: Depth of the surface points, in cells (the kernels need z > 0).
SURFACE_DEPTH = 1e-3


def traction_limit(
    pressure: np.ndarray,
    shear_x: np.ndarray | None,
    grid: SurfaceGrid,
    nu: float,
    shear_yield: float,
    depth: int,
    width: int,
    span: int,
    back_stress_bound: float | None = None,
) -> TrackLimits:
    """Melan's factor of a traction field passing along x (a multiple of the load given).

    Parameters
    ----------
    pressure, shear_x : ndarray
        ``(nx, ny)`` tractions on the body (Pa) on ``grid`` (``shear_x`` None for none); the
        shear across the track (q_y) is not taken.
    grid : SurfaceGrid
        Their cells: centred on y = 0 with ``ny`` even, square (``dx == dy``) or not.
    nu : float
        Poisson's ratio.
    shear_yield : float
        k (Pa).
    depth, width : int
        Cross-section cells in depth (of ``dy``) and across the half y >= 0.
    span : int
        Cells of travel ahead of and behind the load's grid (the positions).
    back_stress_bound : float, optional
        As :func:`.melan.static_limit` (in units of k).

    Returns
    -------
    TrackLimits
        As multiples of the load given (the residual field in Pa): the static limit (its
        ``lower`` too: certified on every point and position the pointwise bounds see), the
        smallest pointwise bound over
        the cells likeliest to bind and the surface points (on the cells' stress paths), first
        yield on the cells, the factor at which the largest surface shear reaches k; the
        section's y and z (m; z = 0 the surface points).
    """
    nx, ny = grid.shape
    if ny % 2 or not math.isclose(grid.centre[1], 0.0, abs_tol=1e-12 * grid.dy):
        raise ValueError("the tractions' grid must be centred on y = 0 with an even ny")
    if width < 2 or depth < 2 or span < 1:
        raise ValueError(f"width, depth (>= 2) and span (>= 1) cells, got {width}, {depth}, {span}")
    half = max(width + 1, ny // 2)  # one column past the box: the edge check
    big = SurfaceGrid(nx + 2 * span, 2 * half, grid.dx, grid.dy, (grid.centre[0], 0.0))
    scale = float(np.abs(pressure).max())
    if not scale > 0.0:
        raise ValueError("the pressure must be positive somewhere")

    def placed(values):
        out = np.zeros(big.shape)
        out[span : span + nx, half - ny // 2 : half + ny // 2] = values / scale
        return out

    tractions = {"pressure": placed(pressure)}
    if shear_x is not None and np.any(shear_x):
        tractions["shear_x"] = placed(shear_x)
    fields = []
    for layers, dz in ((1, 2.0 * SURFACE_DEPTH * grid.dy), (depth + 1, grid.dy)):
        operator = SubsurfaceStressOperator(VolumeGrid(big, layers, dz), nu)
        fields.append(operator.stress(**tractions))
    surface, inside = fields  # (6, NX, NY, 1), (6, NX, NY, depth + 1)
    columns = slice(half, half + width)  # y >= 0, the box's half
    elastic = np.concatenate([surface[:, :, columns], inside[:, :, columns, :depth]], axis=3)
    edge = np.concatenate(
        [inside[:, :, half : half + width + 1, depth], inside[:, :, half + width, : depth + 1]],
        axis=2,
    )
    basis = section_basis(width, depth, grid.dy, grid.dy, symmetric=True, surface=True)
    k = shear_yield / scale
    static = static_limit(elastic, basis, k, back_stress_bound, edge)
    static.residual = static.residual * scale  # in Pa
    y = (np.arange(width) + 0.5) * grid.dy
    z = np.concatenate([[0.0], (np.arange(depth) + 0.5) * grid.dy])
    cells = likeliest_cells(elastic, static.binding, CANDIDATES)
    cells += [(j, 0) for j in range(width)]  # the surface points
    bounds = [
        pointwise_limit(
            elastic[:, :, j, layer], SURFACE_SHIFTS if layer == 0 else None, k, back_stress_bound
        )
        for j, layer in cells
    ]
    best = int(np.argmin(bounds))
    load = deviatoric_coordinates(elastic).reshape(5, elastic.shape[1], -1)
    radius = np.full(load.shape[2], math.sqrt(2.0) * k)
    first = float(certified_factors(load, np.zeros((5, load.shape[2])), radius).min())
    shear = float(np.abs(tractions["shear_x"]).max()) if "shear_x" in tractions else 0.0
    flow = k / shear if shear > 0.0 else math.inf
    at = (float(y[cells[best][0]]), float(z[cells[best][1]]))
    # the pointwise bounds sample the program's own points and positions: certified there
    return TrackLimits(static, float(bounds[best]), at, first, flow, y, z, lower=static.factor)


def elliptical_hertz(
    semi_axes: tuple[float, float], max_pressure: float, friction: float, cells: int
) -> tuple[np.ndarray, np.ndarray, SurfaceGrid]:
    """Hertz's elliptical pressure (and the sliding shear mu p) on square cells.

    ``cells`` across the smaller semi-axis; the grid covers the ellipse with one cell to
    spare, centred on the origin with an even number of cells each way.
    """
    a, b = semi_axes
    h = min(a, b) / cells
    nx, ny = (2 * math.ceil(s / h) + 2 for s in (a, b))
    grid = SurfaceGrid(nx, ny, h, h)
    x, y = np.meshgrid(grid.x, grid.y, indexing="ij")
    pressure = max_pressure * np.sqrt(np.clip(1.0 - (x / a) ** 2 - (y / b) ** 2, 0.0, None))
    return pressure, friction * pressure, grid


__all__ = ["SURFACE_DEPTH", "elliptical_hertz", "traction_limit"]
