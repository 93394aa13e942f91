"""The elastic yield region of any smooth shape, computed: it sizes the plastic box.

For quadric bodies the volume depth and the plastic box come from Hertz's closed-form stress
(:func:`solver.reference.hertz_yield_region`).  For a profile (a cone, a flat punch, a power
law) there is no such closed form, so the region is computed the way the solver would see it
elastically: the frictionless normal contact at the largest load on a trial surface grid
(Polonsky-Keer, :func:`solver.normal.solve_normal`), a sliding shear traction of the path's
largest |Q|/W times the pressure along x, and the von Mises stress of both in the body
(:class:`solver.stress.SubsurfaceStressOperator`) on a trial volume, deepened until the yield
region ends above its floor.  Memoised per input.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from .convolution import surface_operator
from .grid import SurfaceGrid, VolumeGrid
from .materials import Pair
from .normal import solve_normal
from .stress import SubsurfaceStressOperator, von_mises

#: Trial volume: cells in depth, first depth (units of the contact radius) and deepest.
TRIAL_LAYERS = 48
TRIAL_DEPTH = 3.0
MAX_TRIAL_DEPTH = 24.0
#: Largest trial surface grid side (cells).
TRIAL_CELLS = 64


@dataclass(frozen=True)
class YieldRegion:
    """Where the elastic stress of the largest load exceeds the initial yield stress.

    Attributes
    ----------
    top, bottom : float
        Shallowest and deepest yielding cell faces (m); both 0 when nothing yields.
    half_width : float
        Largest |x| or |y| of a yielding cell's outer face (m).
    max_pressure : float
        Peak pressure of the elastic contact on the trial grid (Pa).
    """

    top: float
    bottom: float
    half_width: float
    max_pressure: float


@functools.lru_cache(maxsize=32)
def elastic_yield_region(
    pair: Pair,
    half_widths: tuple[float, float],
    cells: tuple[int, int],
    force: float,
    traction_ratio: float,
    yield_stress: float,
    nu: float,
    radius: float,
) -> YieldRegion:
    """The elastic yield region in body 2 of ``pair`` under ``force`` (N).

    Parameters
    ----------
    pair : Pair
        The bodies (their gap, :meth:`Pair.geometry`).
    half_widths : (float, float)
        Half sides (m) of the case's surface domain.
    cells : (int, int)
        Its cells; the trial grid has at most :data:`TRIAL_CELLS` per side, square cells.
    force : float
        Largest normal force of the path (N).
    traction_ratio : float
        Largest |Q|/W of the path: a sliding shear of that fraction of the pressure along x.
    yield_stress : float
        Initial yield stress sigma_Y0 (Pa).
    nu : float
        Poisson's ratio of the body.
    radius : float
        Contact radius scale (m): the trial volume starts :data:`TRIAL_DEPTH` of it deep.
    """
    scale = min(1.0, TRIAL_CELLS / max(cells))
    nx, ny = (max(8, round(n * scale)) for n in cells)
    cell = 2 * max(half_widths) / max(cells) / scale
    grid = SurfaceGrid(nx, ny, cell, cell)
    operator = surface_operator(grid, pair)
    gap = pair.geometry.gap(*grid.mesh())
    pressure = solve_normal(operator, gap, force, tolerance=1e-8).pressure
    shear = traction_ratio * pressure if traction_ratio > 0 else None
    depth = TRIAL_DEPTH * radius
    while True:
        volume = VolumeGrid(grid, TRIAL_LAYERS, depth / TRIAL_LAYERS)
        stress = SubsurfaceStressOperator(volume, nu).stress(pressure, shear)
        yielded = von_mises(stress) > yield_stress
        layers = np.flatnonzero(yielded.any(axis=(0, 1)))
        if not layers.size or layers[-1] < TRIAL_LAYERS - 1 or depth >= MAX_TRIAL_DEPTH * radius:
            break
        depth *= 2.0
    if not layers.size:
        return YieldRegion(0.0, 0.0, 0.0, float(pressure.max()))
    dz = volume.dz
    columns = yielded.any(axis=2)
    ix, iy = np.nonzero(columns)
    reach = max(np.abs(grid.x[ix]).max() + 0.5 * grid.dx, np.abs(grid.y[iy]).max() + 0.5 * grid.dy)
    return YieldRegion(
        float(layers[0] * dz), float((layers[-1] + 1) * dz), float(reach), float(pressure.max())
    )


def slope_index(pair: Pair, radius: float, yield_stress: float) -> float:
    """Johnson's plasticity index E* f'(a) / sigma_Y for a gap of slope f'(a) at the contact edge.

    For a sphere f'(a) = a/R (Johnson's E* a/(R Y)); for a cone tan(alpha) (E* tan(alpha)/Y);
    for any axisymmetric gap the slope at the contact radius ``radius`` (m).
    """
    slope = float(pair.geometry.slope(np.array([radius]))[0])
    return pair.composite_modulus * slope / yield_stress if math.isfinite(slope) else math.inf
