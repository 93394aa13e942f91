"""The elastic yield region of any smooth shape, computed: it sizes the plastic box.

For quadric bodies the volume depth and the plastic box come from Hertz's closed-form stress
(:func:`solver.theory.hertz.hertz_yield_region`).  For a profile (a cone, a flat punch, a power
law) there is no such closed form, so the region is computed the way the solver would see it
elastically: the frictionless normal contact at the largest load on a trial surface grid
(Polonsky-Keer, :func:`solver.surface.normal.solve_normal`), a sliding shear traction of the path's
largest |Q|/W times the pressure along x, and the von Mises stress of both in the body
(:class:`solver.volume.stress.SubsurfaceStressOperator`) on a trial volume, deepened until the yield
region ends above its floor.  Memoised per input.

Also the window and the box of an elastic-plastic case from that region: its depth
(:func:`auto_depth`), the box's half side (:func:`auto_plastic_half_width`) and the widest
window the cells resolve (:func:`resolved_half_width`); ``grid`` arguments are the case's
:class:`solver.case.grid.GridSpec`.  The note of a window narrower than the box is
:func:`solver.case.notes.narrow_window_note`.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..bodies.materials import Pair
from ..keys import (
    DEFAULT_DEPTH,
    DEFAULT_PERIODIC_DEPTH,
    MAX_PERIODIC_DEPTH,
    MIN_CELLS_ACROSS,
    MIN_PLASTIC_HALF_WIDTH,
    PLASTIC_WIDTH_MARGIN,
    YIELD_DEPTH_MARGIN,
)
from ..numerics.grid import SurfaceGrid, VolumeGrid
from ..numerics.tensor import von_mises
from ..surface.convolution import surface_operator
from ..surface.normal import solve_normal
from ..surface.periodic import periodic_surface_operator
from ..theory.half_space import periodic_traction_stress
from ..theory.hertz import HertzContact, hertz_yield_depth, hertz_yield_half_width
from ..volume.stress import SubsurfaceStressOperator

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


#: Layers of the periodic trial stress evaluated at once (:func:`periodic_yield_region`).
TRIAL_BATCH = 16


@functools.lru_cache(maxsize=8)
def periodic_yield_region(
    pair: Pair,
    grid: SurfaceGrid,
    force: float,
    traction_ratio: float,
    yield_stress: float,
    nu: float,
) -> YieldRegion:
    """The elastic yield region in body 2 under a periodic rough contact at ``force`` (N).

    The frictionless normal contact at the largest load on the case's own grid (one period,
    :func:`~solver.surface.periodic.periodic_surface_operator`: the asperities' contacts are
    as small as its cells, so no coarser trial), a sliding shear of ``traction_ratio`` times
    the pressure along x, and their stress from the Fourier series
    (:func:`~solver.theory.half_space.periodic_traction_stress`) on layers one cell thick,
    scanned down until twice the deepest yielding layer (a tenth of the period when none
    yields) has passed without yield, at most half the period.  ``half_width`` is 0: the box is
    the whole period.  The mean pressure's own stress (uniaxial strain) must stay below yield,
    or every depth would yield: checked by the caller.
    """
    period = (grid.nx * grid.dx, grid.ny * grid.dy)
    operator = periodic_surface_operator(grid, pair)
    gap = pair.geometry.gap(*grid.mesh(), period)
    pressure = solve_normal(operator, gap, force, tolerance=1e-8).pressure
    dz = min(grid.dx, grid.dy)
    deepest, top, k = None, None, 0
    layers = math.ceil(0.5 * min(period) / dz)
    shear = traction_ratio * pressure if traction_ratio > 0 else None
    while k < layers:
        z = (np.arange(k, min(k + TRIAL_BATCH, layers)) + 0.5) * dz
        stress = periodic_traction_stress(period, z, nu, pressure, shear)
        yielded = np.flatnonzero((von_mises(stress) > yield_stress).any(axis=(0, 1)))
        if yielded.size:
            top = k + yielded[0] if top is None else top
            deepest = k + yielded[-1]
        k += TRIAL_BATCH
        passed = k * dz > (0.1 * min(period) if deepest is None else 2.0 * (deepest + 1) * dz)
        if passed and not yielded.size:
            break
    if deepest is None:
        return YieldRegion(0.0, 0.0, 0.0, float(pressure.max()))
    return YieldRegion(float(top * dz), float((deepest + 1) * dz), 0.0, float(pressure.max()))


def periodic_depth(grid: Any, pair: Pair, force: float, ratio: float, body) -> tuple:
    """The volume depth (m) of a periodic elastic-plastic case, and its elastic yield region.

    ``grid.depth`` when given; else :data:`~solver.keys.YIELD_DEPTH_MARGIN` times the bottom of
    the elastic yield region (:func:`periodic_yield_region` at the largest force ``force``, N,
    with a sliding shear of ``ratio`` times the pressure), or
    :data:`~solver.keys.DEFAULT_PERIODIC_DEPTH` of the period when nothing yields elastically;
    at most :data:`~solver.keys.MAX_PERIODIC_DEPTH` of the period.  Returns ``(grid with the
    depth, region)``.
    """
    size = grid.size
    surface = SurfaceGrid.centred(grid.nx, grid.ny, 0.5 * size[0], 0.5 * size[1])
    sigma = body.hardening.initial_yield_stress
    region = periodic_yield_region(pair, surface, force, ratio, sigma, body.nu)
    if grid.depth is None:
        if region.bottom > 0.0:
            depth = YIELD_DEPTH_MARGIN * region.bottom
        else:
            depth = DEFAULT_PERIODIC_DEPTH * min(size)
        grid = dataclasses.replace(grid, depth=min(depth, MAX_PERIODIC_DEPTH * min(size)))
    return grid, region


def slope_index(pair: Pair, radius: float, yield_stress: float) -> float:
    """Johnson's plasticity index E* f'(a) / sigma_Y for a gap of slope f'(a) at the contact edge.

    For a sphere f'(a) = a/R (Johnson's E* a/(R Y)); for a cone tan(alpha) (E* tan(alpha)/Y);
    for any axisymmetric gap the slope at the contact radius ``radius`` (m).
    """
    slope = float(pair.geometry.slope(np.array([radius]))[0])
    return pair.composite_modulus * slope / yield_stress if math.isfinite(slope) else math.inf


def auto_depth(max_pressure: float, yield_stress: float, nu: float) -> float:
    """Volume depth (units of a_H) for an elastic-plastic body: yield depth x margin.

    The frictionless Hertz von Mises stress at the maximum load exceeds ``yield_stress`` on the
    axis down to :func:`~solver.theory.hertz.hertz_yield_depth`; the box is
    :data:`YIELD_DEPTH_MARGIN` times deeper, and never shallower than :data:`DEFAULT_DEPTH`.
    """
    depth = hertz_yield_depth(max_pressure, yield_stress, nu)
    return max(DEFAULT_DEPTH, YIELD_DEPTH_MARGIN * depth)


def auto_plastic_half_width(
    max_pressure: float,
    yield_stress: float,
    nu: float,
    traction_ratio: float,
    depth: float,
    half_width: float,
) -> float:
    """Half side (units of a_H) of the plastic box for an elastic-plastic body, at most the window.

    :data:`PLASTIC_WIDTH_MARGIN` times the largest lateral distance at which the elastic stress
    of the maximum load yields (:func:`~solver.theory.hertz.hertz_yield_half_width`, down to the
    box's ``depth``, with a sliding shear of ``traction_ratio`` = the largest |Q|/W of the
    path), never below :data:`MIN_PLASTIC_HALF_WIDTH`, rounded up to 1e-3.  Plastic flow
    spreads the zone beyond the elastic prediction by up to 14 % in the scenes measured
    (p_0 / sigma_Y0 = 1.8 to 6, linear hardening and perfectly plastic, mu = 0 and 0.5); a
    zone that still reaches the box's sides is a note and the status ``truncated``.
    """
    reach = half_width / PLASTIC_WIDTH_MARGIN + 0.05
    extent = hertz_yield_half_width(max_pressure, yield_stress, nu, traction_ratio, depth, reach)
    width = max(MIN_PLASTIC_HALF_WIDTH, PLASTIC_WIDTH_MARGIN * extent)
    return min(half_width, math.ceil(width * 1000.0 - 1e-6) / 1000.0)


def resolved_half_width(grid: Any, contact: HertzContact | None) -> float:
    """Widest window (units of the largest semi-axis) whose cells resolve the contact.

    The contact must span :data:`MIN_CELLS_ACROSS` cells across its smallest semi-axis
    (:meth:`solver.Case._check_resolution`): square cells of side 2 half_width a_max / max(nx, ny);
    rounded down to 1e-3, strictly (16 cells: 1.599, not 1.6 that round-off may not resolve).
    ``contact`` None: a profile's, axisymmetric.
    """
    ratio = 1.0
    if contact is not None:
        axes = (contact.semi_axis_x, contact.semi_axis_y)
        ratio = min(axes) / max(axes)
    widest = max(grid.nx, grid.ny) * ratio / MIN_CELLS_ACROSS
    return math.floor(widest * 1000.0 * (1.0 - 1e-9)) / 1000.0
