"""The ``[grid]`` table and the resolution checks: cells, window, depth, plastic box.

:class:`GridSpec` holds the grid as given (in units of the contact radius); the window and
box a case without them gets are sized in :mod:`.sizing` and :mod:`.case`;
:func:`check_resolution` and :func:`check_volume` refuse a mesh too coarse for the contact
or for the yield region.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from ..bodies.materials import Body
from ..keys import (
    DEFAULT_HALF_WIDTH,
    DEPTH_RANGE,
    MAX_CELL_DEPTH,
    MAX_CELLS,
    MAX_PERIODIC_DEPTH,
    MIN_CELLS_ACROSS,
    MIN_PLASTIC_HALF_WIDTH,
    MIN_YIELD_CELLS,
    SIZE_RANGE,
    required_keys,
    table_keys,
)
from ..theory.hertz import first_yield_pressure, hertz_yield_region
from .reading import check_keys, entries, fail, integer, number, plain


@dataclass(frozen=True)
class GridSpec:
    """Requested discretisation: cells and domain size in units of the Hertz radius.

    ``size`` (m): the domain's sides instead of ``half_width`` (point heights).

    ``depth`` None (not given) is resolved by :meth:`Case.from_dict`: the elastic yield depth
    with a margin for elastic-plastic cases (:func:`~solver.case.sizing.auto_depth`), else
    :data:`DEFAULT_DEPTH`.
    ``depth_body1``: the depth of body 1's own volume grid when both bodies are elastic-plastic
    and different (same cells; default: ``depth`` when given, else body 1's yield depth).
    ``periodic``: one period in x and y; ``periodic_y``: one period along y only (a line
    contact; ``grid.periodic = "y"``).
    """

    nx: int
    ny: int
    nz: int = 0
    half_width: float = DEFAULT_HALF_WIDTH
    depth: float | None = None
    depth_body1: float | None = None
    plastic_half_width: float | None = None
    size: tuple[float, float] | None = None
    follow_contact: bool = True
    periodic: bool = False
    periodic_y: bool = False


def parse_grid(table: Any) -> GridSpec:
    """Parse ``[grid]``: ``n`` (nx = ny), ``[nx, ny]`` or ``[nx, ny, nz]``, and ``nz``.

    ``nz`` (the volume grid's cells in depth) may be given apart from a 1- or 2-entry ``n``,
    not as well as a 3-entry one.
    """
    check_keys(table, "grid", table_keys("grid"), required_keys("grid"))
    n = entries(table["n"], "grid.n", "an integer or [nx, ny] or [nx, ny, nz]", (2, 3), scalar=True)
    if isinstance(n, list):
        sizes = [integer(v, "grid.n", 4, MAX_CELLS) for v in n]
    else:
        size = integer(n, "grid.n", 4, MAX_CELLS)
        sizes = [size, size]
    if "nz" in table:
        if len(sizes) == 3:
            fail(
                "grid.nz",
                f"grid.n = {n!r} already gives nz; give either grid.n = [nx, ny, nz] or "
                "grid.n with grid.nz, not both",
            )
        sizes.append(integer(table["nz"], "grid.nz", 4, MAX_CELLS))
    nz = sizes[2] if len(sizes) == 3 else 0
    half_width = number(
        table.get("half_width", DEFAULT_HALF_WIDTH), "grid.half_width", positive=True
    )
    size = None
    if "size" in table:
        if "half_width" in table:
            fail("grid.size", "give either size (m) or half_width (units of a_H), not both")
        value = entries(table["size"], "grid.size", "L or [Lx, Ly] (m)", (2,), scalar=True)
        items = value if isinstance(value, list) else [value, value]
        size = tuple(number(v, "grid.size", positive=True) for v in items)
        low, high = SIZE_RANGE
        if not all(low <= side <= high for side in size):
            fail(
                "grid.size",
                f"sides must be in [{low:g}, {high:g}] m, got {list(size)}: give the domain's "
                "sides in metres (1 mm is 1e-3)",
            )
        if not math.isclose(size[0] / sizes[0], size[1] / sizes[1], rel_tol=1e-9):
            fail(
                "grid.size",
                f"cells must be square: Lx/nx = {size[0] / sizes[0]:.6g} m but Ly/ny = "
                f"{size[1] / sizes[1]:.6g} m; make [Lx, Ly] proportional to [nx, ny]",
            )
    periodic = plain(table.get("periodic", False))
    periodic_y = periodic == "y"
    if not (isinstance(periodic, bool) or periodic_y):
        fail("grid.periodic", f'must be true, false or "y" (along y only), got {periodic!r}')
    periodic = periodic is True
    if (periodic or periodic_y) and size is None:
        fail("grid.periodic", "the period is the domain: give its sides, grid.size = [Lx, Ly] (m)")
    depths = {}
    for key in ("depth", "depth_body1"):
        if key in table:
            depths[key] = number(table[key], f"grid.{key}", positive=True)
            low, high = DEPTH_RANGE
            if periodic and key == "depth":  # metres, a cell to a fraction of the period
                deepest = MAX_PERIODIC_DEPTH * min(size)
                cell = min(size[0] / sizes[0], size[1] / sizes[1])
                if depths[key] < cell:
                    fail(
                        "grid.depth",
                        f"a periodic case's depth is in metres, at least a surface cell "
                        f"({cell:.4g} m), got {depths[key]:g}: an asperity's plastic zone "
                        "spans cells; leave the depth out (sized from the elastic yield region)",
                    )
                if depths[key] > deepest:
                    fail(
                        "grid.depth",
                        f"a periodic case's depth is in metres, at most {MAX_PERIODIC_DEPTH:g} "
                        f"of the period ({deepest:.4g} m), got {depths[key]:g}: the periodic "
                        "kernels sum the nearest periods only; use a larger period, or leave "
                        "the depth out (sized from the elastic yield region)",
                    )
            elif not low <= depths[key] <= high:
                fail(
                    f"grid.{key}",
                    f"must be in [{low:g}, {high:g}] (units of the Hertz radius a_H), got "
                    f"{depths[key]:g}; leave it out to size the box from the yield region",
                )
    if "depth" in table and not nz:
        fail("grid.depth", "a depth needs a volume grid: give grid.n = [nx, ny, nz]")
    plastic_half_width = None
    if "plastic_half_width" in table:
        plastic_half_width = number(
            table["plastic_half_width"], "grid.plastic_half_width", positive=True
        )
        if not MIN_PLASTIC_HALF_WIDTH <= plastic_half_width <= half_width:
            fail(
                "grid.plastic_half_width",
                f"must be in [{MIN_PLASTIC_HALF_WIDTH:g}, half_width = {half_width:g}] (units of "
                f"the Hertz radius a_H), got {plastic_half_width:g}; leave it out for a box sized "
                "from the yield region, or give half_width for the whole window",
            )
    follow = plain(table.get("follow_contact", True))
    if not isinstance(follow, bool):
        fail("grid.follow_contact", f"must be true or false, got {follow!r}")
    return GridSpec(
        sizes[0],
        sizes[1],
        nz,
        half_width,
        depths.get("depth"),
        depths.get("depth_body1"),
        plastic_half_width,
        size,
        follow,
        periodic,
        periodic_y,
    )


def domain_half_widths(grid: GridSpec, scale: float) -> tuple[float, float]:
    """Half-widths (m) of the surface domain, square cells.

    ``grid.size``, else ``half_width`` x ``scale`` (m) along the longer side.
    """
    if grid.size is not None:
        return 0.5 * grid.size[0], 0.5 * grid.size[1]
    half = grid.half_width * scale
    if grid.nx == grid.ny:
        return half, half
    cell = 2 * half / max(grid.nx, grid.ny)
    return 0.5 * cell * grid.nx, 0.5 * cell * grid.ny


def check_volume(
    body: Body, depth: float, nz: int, max_pressure: float, path: str, region=None
) -> None:
    """Refuse a plastic body's volume grid that cannot resolve its yield region.

    ``depth`` in units of a_H.  Cells at most :data:`MAX_CELL_DEPTH` thick: the Hertz von
    Mises stress peaks at 0.48 a_H, and half-a_H cells gave no plastic strain at all
    (p_H = 1.8 sigma_Y) or 40 % too little (2.9 sigma_Y).  With the frictionless Hertz yield
    region on the axis at the maximum load (:func:`~solver.theory.hertz.hertz_yield_region`),
    the box must reach the depth where plasticity starts (a shallower one gives an elastic
    answer), and the region inside the box must span :data:`MIN_YIELD_CELLS` cells.  ``region``
    (top, bottom, half width, in units of the contact radius): a profile's computed region
    (:func:`~solver.case.sizing.elastic_yield_region`) instead of Hertz's.
    """
    nu, sigma = body.nu, body.hardening.initial_yield_stress
    cell = depth / nz
    thick = f"cells {cell:.3g} a_H thick (depth {depth:g} a_H over nz = {nz})"
    if cell > MAX_CELL_DEPTH:
        fail(
            path,
            f"{thick} cannot resolve a plastic zone (at most {MAX_CELL_DEPTH:g} a_H): use "
            f"nz >= {math.ceil(depth / MAX_CELL_DEPTH)}",
        )
    if region is None:
        top, bottom = hertz_yield_region(max_pressure, sigma, nu)
        start = first_yield_pressure(sigma, nu)[1]
        told = f"the Hertz yield region at p_H = {max_pressure:.4g} Pa spans"
    else:
        top, bottom, _ = region
        start = top
        told = "the computed elastic yield region spans"
    if bottom == 0.0:  # the elastic field does not yield (friction may, near the surface)
        return
    region = f"{told} {top:.3g}-{bottom:.3g} a_H"
    if depth < start:
        fail(
            path,
            f"the box ends at {depth:g} a_H, above the depth {start:.3g} a_H where plasticity "
            f"starts ({region}): use depth >= {bottom:.3g}, or leave it out (sized "
            "from the yield region)",
        )
    require_yield_cells(path, thick, region, top, bottom, depth, cell)


def require_yield_cells(
    path: str, thick: str, region: str, top: float, bottom: float, depth: float, cell: float
) -> None:
    """Refuse layers too thick for the yield region: fewer than :data:`MIN_YIELD_CELLS` across.

    ``top``, ``bottom`` the region's, ``depth`` the box's, ``cell`` a layer's thickness (any one
    unit); ``thick`` and ``region`` describe the layers and the region in the message.
    """
    span = min(bottom, depth) - top
    if span < MIN_YIELD_CELLS * cell:
        fail(
            path,
            f"{thick} are too coarse for the yield region ({region}: {span / cell:.2g} "
            f"cells, at least {MIN_YIELD_CELLS} needed): use "
            f"nz >= {math.ceil(MIN_YIELD_CELLS * depth / max(span, 1e-300))}",
        )


def check_resolution(case) -> None:
    """Refuse a window that cannot hold the contact, or cells too coarse to resolve it."""
    reference = case.reference
    if reference is None:  # heights only: the contact's size is known after the solve
        return
    semi_min = min(reference.semi_axis_x, reference.semi_axis_y)
    half_x, half_y = case.domain_half_widths
    if case.moving and case.grid.size is not None:
        (x0, x1), (y0, y1) = case.track
        if half_x < 0.5 * (x1 - x0) + 1.05 * reference.semi_axis_x or (
            half_y < 0.5 * (y1 - y0) + 1.05 * reference.semi_axis_y
        ):
            fail(
                "grid.size",
                f"the window ({2 * half_x:.4g} m by {2 * half_y:.4g} m) does not hold the "
                f"contact along the track (x from {x0:.4g} to {x1:.4g} m, y from {y0:.4g} "
                f"to {y1:.4g} m, contact radius {reference.max_semi_axis:.4g} m): enlarge "
                "grid.size or leave it out (the window then covers the track)",
            )
    if half_x < 1.05 * reference.semi_axis_x or half_y < 1.05 * reference.semi_axis_y:
        if case.grid.size is not None:  # the user's window, not half_width's
            need = [2.2 * semi for semi in (reference.semi_axis_x, reference.semi_axis_y)]
            fail(
                "grid.size",
                f"the window ({2 * half_x:.4g} m by {2 * half_y:.4g} m) cannot hold the "
                f"contact (semi-axes {reference.semi_axis_x:.4g} m along x, "
                f"{reference.semi_axis_y:.4g} m along y): use grid.size >= "
                f"[{need[0]:.4g}, {need[1]:.4g}] m, or give half_width instead",
            )
        nx, ny = case.grid.nx, case.grid.ny
        if nx != ny and not case.moving:  # square cells: the short side is half_width n / n_max
            axis, short, long = ("y", ny, nx) if nx > ny else ("x", nx, ny)
            half = min(half_x, half_y) / reference.max_semi_axis
            semi = reference.semi_axis_y if axis == "y" else reference.semi_axis_x
            need = math.ceil(short * 1.05 * semi / min(half_x, half_y))
            fix = f"n{axis} >= {need}" if need <= long else f"n = {long} (square)"
            fail(
                "grid.n",
                f"with square cells, n = [{nx}, {ny}] makes the window {half:.3g} a_H wide along "
                f"{axis} (half-width), too narrow for the contact (semi-axis "
                f"{semi / reference.max_semi_axis:.3g} a_H): use {fix}, or a larger half_width",
            )
        fail(
            "grid.half_width",
            f"domain cannot hold the contact: half_width = {case.grid.half_width:g} a_H; "
            "use half_width >= 1.1 (1.5 recommended)",
        )
    surface = case.surface_grid
    across = 2 * semi_min / max(surface.dx, surface.dy)
    if not across >= MIN_CELLS_ACROSS:
        # square cells of side 2 half_width a_max / n: across = n semi_min / (half_width a_max)
        n_max = max(case.grid.nx, case.grid.ny)
        need = MIN_CELLS_ACROSS * n_max / across if across > 0 else math.inf
        if case.moving and case.grid.size is None:  # the track sets the window
            (x0, x1), (y0, y1) = case.track
            key = "slide" if any(st.motion == "slide" for st in case.stages) else "roll"
            moving = {"slide": "sliding", "roll": "rolling"}[key]
            cell = 2 * semi_min / MIN_CELLS_ACROSS  # the largest cell that resolves it
            half = case.grid.half_width * reference.max_semi_axis
            counts = [math.ceil((2 * half + hi - lo) / cell) for lo, hi in ((x0, x1), (y0, y1))]
            counts += [case.grid.nz] if case.grid.nz else []  # the volume's cells kept
            fail(
                f"load.path ({key})",
                f"mesh too coarse for the {moving} track ({x1 - x0:.4g} m along x, "
                f"{y1 - y0:.4g} m along y, contact radius {semi_min:.4g} m): the contact "
                f"spans {across:.3g} cells of the window over the track; shorten the "
                f"{key}s or give more cells (n = {counts} or more, at most {MAX_CELLS} a side)",
            )
        if need <= MAX_CELLS:
            window = f"{case.grid.half_width:g} a_H"
            if case.plastic_body is not None:  # the window may have grown to hold the box
                window += ", which holds the plastic box when half_width is not given"
            fail(
                "grid.n",
                f"mesh too coarse: the contact spans {across:.3g} cells of the window "
                f"({window}); use n >= {math.ceil(need)} (or a smaller half_width)",
            )
        scale = semi_min / (MIN_CELLS_ACROSS * reference.max_semi_axis)
        at_n = ""
        if n_max < MAX_CELLS and scale * n_max >= 1.1:
            at_n = f" (<= {scale * n_max:.4g} at n = {n_max})"
        need_text = str(math.ceil(need)) if need < 1e15 else f"{need:.3g}"
        fail(
            "grid.half_width",
            f"mesh too coarse: the contact spans {across:.4g} cells and would need "
            f"n >= {need_text}, beyond the largest grid n = {MAX_CELLS}; reduce half_width "
            f"to <= {scale * MAX_CELLS:.4g} with n = {MAX_CELLS}{at_n} (1.5 recommended)",
        )
