"""The window and volume grids of an open (not periodic) case, sized and checked.

An elastic-plastic case without ``grid.depth``, ``grid.plastic_half_width`` or (when it can
grow) ``grid.half_width`` gets them from its elastic yield region: Hertz's closed form for
quadric bodies, a trial elastic solve for a profile (:mod:`.sizing`); then each plastic body's
regime is told (:mod:`.notes`) and its volume grid checked (:mod:`.grid`).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping, Sequence

from ..bodies.materials import Body, Pair
from ..keys import (
    DEFAULT_DEPTH,
    DEFAULT_HALF_WIDTH,
    MAX_AUTO_HALF_WIDTH,
    MIN_PLASTIC_HALF_WIDTH,
    MOVING_DEPTH_MARGIN,
    PLASTIC_WIDTH_MARGIN,
    YIELD_DEPTH_MARGIN,
)
from ..theory.hertz import hertz
from .grid import GridSpec, check_volume, domain_half_widths
from .notes import more_cells_note, narrow_window_note, plastic_regime, profile_regime
from .path import LoadStage, profile_radius, symmetric_pair
from .reading import fail
from .sizing import (
    auto_depth,
    auto_plastic_half_width,
    elastic_yield_region,
    resolved_half_width,
)


def size_open_volume(
    given: Mapping,
    grid: GridSpec,
    pair: Pair,
    stages: Sequence[LoadStage],
    paths: Sequence[str],
    force: float,
    ratio: float,
    p_max: float,
    moving: bool,
) -> tuple[GridSpec, float | None, list[str]]:
    """The grid with its depths, window and plastic box sized; the box key; notes.

    Parameters
    ----------
    given : mapping
        The ``[grid]`` table as given (which keys the user set).
    grid : GridSpec
        The parsed grid.
    pair : Pair
        The bodies.
    stages, paths : sequences
        The load stages and where each was given.
    force : float
        The largest normal force (N).
    ratio : float
        The largest ``|Q| / W`` of the path.
    p_max : float
        Hertz's peak pressure at ``force`` (Pa) for quadric plastic bodies, else NaN.
    moving : bool
        True when a stage slides.

    Returns
    -------
    (GridSpec, float or None, list of str)
        The sized grid; ``grid.plastic_half_width`` as the case's spec records it (None:
        not recorded); the notes (a window narrower than the plastic box, plastic regimes).

    Raises
    ------
    SpecError
        If a key is given that the case does not take, or a plastic body's regime or volume
        grid is refused.
    """
    body1, body2 = pair.body1, pair.body2
    geometry, e_star, (kx, ky) = pair.geometry, pair.composite_modulus, pair.curvature
    plastics = [b for b in (body2, body1) if b.behaviour == "elastic-plastic"]
    plastic = plastics[0] if plastics else None
    box_key, warnings = None, []
    # no window given: an elastic-plastic case's window holds its plastic box
    window_free = grid.size is None and "half_width" not in given and not moving
    region = None  # a profile's computed elastic yield region (units of its contact radius)
    if plastic is not None and not geometry.hertzian:
        scale = profile_radius(geometry, force, e_star)
        trial = grid
        while True:
            found = elastic_yield_region(
                pair, domain_half_widths(trial, scale), (grid.nx, grid.ny), force, ratio,
                plastic.hardening.initial_yield_stress, plastic.nu, scale,
            )  # fmt: skip
            region = (found.top / scale, found.bottom / scale, found.half_width / scale)
            # a box wider than the domain: look again on a wider trial domain
            wider = min(MAX_AUTO_HALF_WIDTH, 1.5 * trial.half_width)
            clipped = PLASTIC_WIDTH_MARGIN * region[2] >= trial.half_width
            if not (clipped and wider > trial.half_width):
                break
            trial = dataclasses.replace(trial, half_width=wider)
        p_max = found.max_pressure

    def yield_depth(body: Body) -> float:
        if region is not None:
            return max(DEFAULT_DEPTH, YIELD_DEPTH_MARGIN * region[1])
        return auto_depth(p_max, body.hardening.initial_yield_stress, body.nu)

    def auto_width(body: Body, depth: float, window: float) -> float:
        if region is not None:
            width = max(MIN_PLASTIC_HALF_WIDTH, PLASTIC_WIDTH_MARGIN * region[2])
            return min(window, math.ceil(width * 1000.0 - 1e-6) / 1000.0)
        return auto_plastic_half_width(
            p_max, body.hardening.initial_yield_stress, body.nu, ratio, depth, window
        )

    if grid.plastic_half_width is not None and plastic is None:
        fail(
            "grid.plastic_half_width",
            "only an elastic-plastic body has a plastic box; leave the key out",
        )
    # a volume grid each: two different elastic-plastic bodies, or identical ones sheared
    two_fields = len(plastics) == 2 and not symmetric_pair(body1, body2, stages)
    if grid.depth_body1 is not None and not two_fields:
        fail(
            "grid.depth_body1",
            "only two elastic-plastic bodies with a plastic strain field each (different, or "
            "loaded tangentially) have a volume grid each; use grid.depth",
        )
    if two_fields and grid.depth_body1 is None:
        depth1 = grid.depth if grid.depth is not None else yield_depth(body1)
        grid = dataclasses.replace(grid, depth_body1=depth1)
    if grid.depth is None:
        depth = yield_depth(plastic) if plastic is not None else DEFAULT_DEPTH
        if plastic is not None and moving:
            depth *= MOVING_DEPTH_MARGIN / YIELD_DEPTH_MARGIN  # passes drive it deeper
        grid = dataclasses.replace(grid, depth=depth)
    if plastic is not None:

        def box_width(window: float) -> float:
            return max(
                auto_width(
                    body,
                    grid.depth_body1 if body is body1 and two_fields else grid.depth,
                    window,
                )  # fmt: skip
                for body in plastics
            )

        auto = box_width(grid.half_width)
        if auto >= grid.half_width and not moving:  # the box fills the window: is it wider?
            zone = box_width(MAX_AUTO_HALF_WIDTH)
            if window_free:  # as wide as the zone asks, the contact resolved as the cells do
                contact = hertz(force, e_star, (kx, ky)) if region is None else None
                given_cells = (grid.nx, grid.ny)
                grid = _cells_for(grid, min(zone, MAX_AUTO_HALF_WIDTH), contact)
                window = max(DEFAULT_HALF_WIDTH, min(zone, resolved_half_width(grid, contact)))
                grid = dataclasses.replace(grid, half_width=window)
                # the box a rebuild from the spec (the window then given) finds: the same case
                auto = box_width(grid.half_width)
                if (grid.nx, grid.ny) != given_cells:
                    warnings.append(more_cells_note(given_cells, grid, zone))
            if zone > grid.half_width or (window_free and zone >= MAX_AUTO_HALF_WIDTH):
                warnings.append(narrow_window_note(grid, zone, window_free))
        elif moving and auto >= grid.half_width and grid.size is None:
            zone = box_width(MAX_AUTO_HALF_WIDTH)  # beside the track: the box is the window
            if zone > grid.half_width:
                warnings.append(narrow_window_note(grid, zone, False, moving=True))
        chosen = grid.plastic_half_width
        if moving:  # the box covers the track: the window
            if chosen is not None:
                fail(
                    "grid.plastic_half_width",
                    "a sliding case's plastic box is the whole window (it covers the "
                    "track); leave the key out",
                )
            auto = grid.half_width
        width = auto if chosen is None else chosen
        # the whole window given while the automatic box is narrower: said in the spec
        box_key = width if width < grid.half_width or auto < grid.half_width else None
        grid = dataclasses.replace(
            grid, plastic_half_width=width if width < grid.half_width else None
        )
    peak = max(range(len(stages)), key=lambda i: stages[i].normal_force)
    for body, name in ((body2, "body 2"), (body1, "body 1")):
        if body.behaviour != "elastic-plastic" or (name == "body 1" and body1 == body2):
            continue
        own = name == "body 1" and two_fields  # body 1's own volume grid
        keys = ("depth_body1", "depth") if own else ("depth",)  # what sets its depth
        given_key = next((f"grid.{k}" for k in keys if k in given), "grid.n")
        if region is None:
            note = plastic_regime(body, p_max, paths[peak], name)  # first: it may refuse
        else:
            note = profile_regime(body, pair, scale, paths[peak], name)
        if note:
            warnings.append(note)
        depth = grid.depth_body1 if own else grid.depth
        check_volume(body, depth, grid.nz, p_max, given_key, region)
    return grid, box_key, warnings


def _cells_for(grid: GridSpec, window: float, contact) -> GridSpec:
    """The grid with cells enough for a window of half side ``window`` (units of a_H).

    The cells the window is resolved by (:func:`resolved_half_width`: the contact
    :data:`~solver.keys.MIN_CELLS_ACROSS` cells across) are kept, so that a window sized to
    hold the plastic zone predicted is never held back below it by the cells given: nx and
    ny grow in proportion (the cell's shape kept) where the cells given resolve a narrower
    window; the grid as given otherwise.
    """
    scale = window / resolved_half_width(grid, contact)
    while scale > 1.0:
        grid = dataclasses.replace(
            grid, nx=math.ceil(grid.nx * scale - 1e-9), ny=math.ceil(grid.ny * scale - 1e-9)
        )
        scale = window / resolved_half_width(grid, contact)
    return grid
