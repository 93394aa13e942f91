"""The ``[body1]`` and ``[body2]`` tables: behaviour, elastic constants, shape, hardening.

Parses a body's table into a :class:`~solver.bodies.materials.Body` (profile, height map,
roughness, hardening law and back stress), writes it back as its normalised table
(:func:`body_spec`), and refuses the height maps and roughness the grid cannot take
(:func:`check_surfaces`).
"""

from __future__ import annotations

import dataclasses
import math
import os
from typing import Any

import numpy as np

from ..bodies.geometry import PROFILE_KEYS, PROFILES, Profile
from ..bodies.heights import (
    MAX_ROUGHNESS_LATTICE,
    MAX_SEAM_STEP,
    MIN_PERIODIC_CUTOFF_CELLS,
    PERIOD_RTOL,
    ROUGHNESS_POINTS_PER_CUTOFF,
    HeightMap,
    Roughness,
    SurfaceError,
    grid_rms_slope,
)
from ..bodies.materials import Body
from ..keys import (
    HARDENING_KEYS,
    KINEMATIC_KEYS,
    MAX_HARDENING_RATIO,
    MAX_MAP_COARSENING,
    MAX_RECALL,
    MAX_SURFACE_SLOPE,
    MODULUS_RANGE,
    PROFILE_EXPONENT_RANGE,
    PROFILE_MAX_ANGLE,
    RADIUS_RANGE,
    SWIFT_OFFSET_RANGE,
    YIELD_STRAIN_RANGE,
    required_keys,
    table_keys,
)
from ..numerics.grid import SurfaceGrid
from ..plasticity.hardening import Hardening
from .reading import (
    HARDENING,
    KINEMATIC,
    PROFILE,
    ROUGHNESS,
    SURFACE,
    SurfaceReader,
    brief,
    check_keys,
    entries,
    fail,
    integer,
    json_number,
    number,
    plain,
)


def _parse_kinematic(table: Any, path: str) -> dict:
    check_keys(table, path, table_keys(KINEMATIC), required_keys(KINEMATIC))
    law = plain(table["law"])
    if law not in KINEMATIC_KEYS:
        fail(f"{path}.law", f"must be one of {', '.join(KINEMATIC_KEYS)}, got {law!r}")
    check_keys(table, path, KINEMATIC_KEYS[law] | {"law"}, KINEMATIC_KEYS[law])
    modulus = number(table["C"], f"{path}.C", positive=True)
    recall = number(table["gamma"], f"{path}.gamma", positive=True) if "gamma" in table else 0.0
    return {"kinematic_modulus": modulus, "kinematic_recall": recall}


def _parse_profile(table: Any, path: str) -> Profile:
    check_keys(table, path, table_keys(PROFILE), required_keys(PROFILE))
    shape = plain(table["shape"])
    if shape not in PROFILES:
        fail(f"{path}.shape", f"must be one of {', '.join(PROFILES)}, got {shape!r}")
    keys = PROFILE_KEYS[shape]
    check_keys(table, path, {*keys, "shape"}, set(keys))
    if shape == "cone":
        angle = number(table["angle"], f"{path}.angle", positive=True)
        if angle > PROFILE_MAX_ANGLE:
            fail(
                f"{path}.angle",
                f"must be in (0, {PROFILE_MAX_ANGLE:g}] degrees (the surface's angle to the "
                f"tangent plane; small-slope theory), got {angle:g}",
            )
        return PROFILES[shape](angle)
    if shape == "flat_punch":
        return PROFILES[shape](
            _radius(table["radius"], f"{path}.radius", flat=False),
            _radius(table["edge_radius"], f"{path}.edge_radius", flat=False),
        )
    coefficient = number(table["coefficient"], f"{path}.coefficient", positive=True)
    exponent = number(table["exponent"], f"{path}.exponent")
    low, high = PROFILE_EXPONENT_RANGE
    if not low <= exponent <= high:
        fail(f"{path}.exponent", f"must be in [{low:g}, {high:g}], got {exponent:g}")
    if exponent == 1.0 and coefficient > 1.0:
        fail(f"{path}.coefficient", "with exponent 1 (a cone) the slope must be <= 1")
    return PROFILES[shape](coefficient, exponent)


def _parse_surface(value: Any, path: str, read_surface: SurfaceReader | None) -> HeightMap:
    """A height map: given as an object, or read by ``read_surface`` from its table."""
    value = plain(value)
    if isinstance(value, os.PathLike):  # a file name as a path: the same as its text
        value = os.fspath(value)
    if isinstance(value, dict):
        value = {k: os.fspath(v) if isinstance(v, os.PathLike) else v for k, v in value.items()}
    if isinstance(value, HeightMap):
        value.origin = {"file": f"<in memory: {value.source}>"}
        return value
    if isinstance(value, str):
        value = {"file": value}
    check_keys(value, path, table_keys(SURFACE), required_keys(SURFACE))
    kinds = [k for k in ("file", "case") if k in value]
    if len(kinds) != 1:
        fail(path, "give one of file (a height map) and case (an earlier case's dent)")
    kind = kinds[0]
    if not isinstance(value[kind], str) or not value[kind]:
        fail(f"{path}.{kind}", f"must be a file name, got {value[kind]!r}")
    origin = {kind: value[kind]}
    if "offset" in value:
        offset = entries(value["offset"], f"{path}.offset", "[dx, dy] (m)", (2,))
        origin["offset"] = [number(v, f"{path}.offset") for v in offset]
    if "spacing" in value:
        if kind == "case":
            fail(f"{path}.spacing", "a case file's coordinates give the spacing; remove it")
        form = "dx or [dx, dy] (m)"
        spacing = entries(value["spacing"], f"{path}.spacing", form, (1, 2), scalar=True)
        items = spacing if isinstance(spacing, list) else [spacing]
        origin["spacing"] = [number(v, f"{path}.spacing", positive=True) for v in items]
    if read_surface is None:
        fail(
            path,
            "a height-map file is read by the study layer: build the case with "
            "Case.from_dict(table, read_surface=study.campaign.surfaces.read_surface), or give a "
            "solver.bodies.heights.HeightMap",
        )
    try:
        surface = read_surface(origin)
    except SurfaceError as error:
        fail(path, str(error))
    if "sha256" in value and not isinstance(value["sha256"], str):
        fail(
            f"{path}.sha256",
            f"must be the map's content hash (64 hex digits, as the case file records it), got "
            f"{brief(value['sha256'])}; remove it to take the file as it is",
        )
    if "sha256" in value and value["sha256"] != surface.digest:
        fail(
            f"{path}.sha256",
            f"{value[kind]} changed since this case was written (its content hash differs); "
            "build the case again from its campaign file",
        )
    surface.origin = origin
    return surface


def _parse_roughness(table: Any, path: str) -> Roughness:
    if isinstance(table, Roughness):  # the object, read as its table (as a HeightMap is taken)
        table = {k: v for k, v in dataclasses.asdict(table).items() if v is not None}
    check_keys(table, path, table_keys(ROUGHNESS), required_keys(ROUGHNESS))
    if ("rms" in table) == ("rms_slope" in table):
        fail(path, "give one of rms (m) and rms_slope")
    hurst = number(table["hurst"], f"{path}.hurst", positive=True)
    if hurst > 1:
        fail(f"{path}.hurst", f"must be in (0, 1], got {hurst:g}")
    long = number(table["long_cutoff"], f"{path}.long_cutoff", positive=True)
    short = number(table["short_cutoff"], f"{path}.short_cutoff", positive=True)
    if not long > short:
        fail(f"{path}.long_cutoff", f"must exceed short_cutoff = {short:g} m, got {long:g}")
    rms = number(table["rms"], f"{path}.rms", positive=True) if "rms" in table else None
    slope = None
    if "rms_slope" in table:
        slope = number(table["rms_slope"], f"{path}.rms_slope", positive=True)
        if slope > MAX_SURFACE_SLOPE:
            fail(
                f"{path}.rms_slope",
                f"must be <= {MAX_SURFACE_SLOPE:g} (small-slope theory), got {slope:g}",
            )
    seed = integer(table.get("seed", 0), f"{path}.seed", 0, 2**63 - 1)
    return Roughness(hurst, long, short, rms, slope, seed)


def _parse_hardening(table: Any, path: str) -> Hardening:
    check_keys(table, path, table_keys(HARDENING), required_keys(HARDENING))
    law = plain(table["law"])
    if law not in HARDENING_KEYS:
        fail(f"{path}.law", f"must be one of {', '.join(HARDENING_KEYS)}, got {law!r}")
    check_keys(table, path, HARDENING_KEYS[law] | {"law", "kinematic"}, HARDENING_KEYS[law])
    values = {}
    for key in HARDENING_KEYS[law]:
        values[key] = number(table[key], f"{path}.{key}", positive=key != "modulus")
        if key == "modulus" and values[key] < 0:
            fail(f"{path}.modulus", f"must be >= 0, got {values[key]}")
    if law == "swift":
        low, high = SWIFT_OFFSET_RANGE
        if not low <= values["C"] <= high:
            fail(
                f"{path}.C",
                f"Swift's offset C (micro-strain) must be in [{low:g}, {high:g}], got "
                f"{values['C']:g} (the paper's steel: C = 20)",
            )
        if not values["n"] <= 1:
            fail(f"{path}.n", f"Swift's exponent must be in (0, 1], got {values['n']:g}")
    if "kinematic" in table:
        values.update(_parse_kinematic(table["kinematic"], f"{path}.kinematic"))
    return Hardening(law=law, **values)


def parse_body(table: Any, path: str, read_surface: SurfaceReader | None = None) -> Body:
    """The :class:`Body` of a ``[bodyN]`` table; height-map files read by ``read_surface``."""
    check_keys(table, path, table_keys("bodyN"), required_keys("bodyN"))
    behaviour = plain(table["behaviour"])
    if behaviour not in ("rigid", "elastic", "elastic-plastic"):
        fail(f"{path}.behaviour", f"must be rigid, elastic or elastic-plastic, got {behaviour!r}")
    if "radius" in table and ("radius_x" in table or "radius_y" in table):
        fail(f"{path}.radius", "give either radius or radius_x/radius_y, not both")
    if "radius" in table:
        rx = ry = _radius(table["radius"], f"{path}.radius")
    else:
        rx = _radius(table.get("radius_x", "inf"), f"{path}.radius_x")
        ry = _radius(table.get("radius_y", "inf"), f"{path}.radius_y")
    surface = roughness = None
    if "surface" in table:
        surface = _parse_surface(table["surface"], f"{path}.surface", read_surface)
    if "roughness" in table:
        roughness = _parse_roughness(table["roughness"], f"{path}.roughness")
    profile = None
    if "profile" in table:
        profile = _parse_profile(table["profile"], f"{path}.profile")
        if rx != ry:
            fail(
                f"{path}.profile",
                "a profile is axisymmetric and adds to a sphere only: give radius (or none), "
                "not radius_x / radius_y",
            )
    if behaviour == "rigid":
        for key in ("E", "nu", "hardening"):
            if key in table:
                fail(f"{path}.{key}", "a rigid body takes no elastic or hardening data; remove it")
        return Body("rigid", rx, ry, profile=profile, surface=surface, roughness=roughness)
    for key in ("E", "nu"):
        if key not in table:
            fail(f"{path}.{key}", f"missing required field for an {behaviour} body")
    young = number(table["E"], f"{path}.E", positive=True)
    low, high = MODULUS_RANGE
    if not low <= young <= high:
        fail(f"{path}.E", f"Young's modulus must be in [{low:g}, {high:g}] Pa, got {young:g}")
    nu = number(table["nu"], f"{path}.nu")
    if not -1.0 < nu <= 0.5:
        fail(f"{path}.nu", f"Poisson's ratio must be in (-1, 0.5], got {nu}")
    hardening = None
    if behaviour == "elastic-plastic":
        if nu == 0.5:
            fail(
                f"{path}.nu",
                "an elastic-plastic body must be compressible, nu < 0.5: its eigenstrain's "
                "stress takes Lame's lambda = 2 G nu / (1 - 2 nu), infinite at 0.5",
            )
        if "hardening" not in table:
            fail(f"{path}.hardening", "missing: an elastic-plastic body needs a hardening table")
        hardening = _parse_hardening(table["hardening"], f"{path}.hardening")
        _check_yield_stress(hardening, young, f"{path}.hardening")
    elif "hardening" in table:
        fail(f"{path}.hardening", "only elastic-plastic bodies take a hardening law")
    return Body(behaviour, rx, ry, young, nu, hardening, profile, surface, roughness)


def _radius(value: Any, path: str, flat: bool = True) -> float:
    """A radius (m): in :data:`RADIUS_RANGE`, or "inf" for a flat body where ``flat``."""
    radius = number(value, path, positive=True, allow_inf=flat)
    low, high = RADIUS_RANGE
    if not (low <= radius <= high or math.isinf(radius)):
        flat_text = ' or "inf" (flat)' if flat else ""
        fail(path, f"must be in [{low:g}, {high:g}] m{flat_text}, got {radius:g}")
    return radius


def _check_yield_stress(hardening: Hardening, young: float, path: str) -> None:
    """Initial yield strain (Swift: B C^n / E) in :data:`YIELD_STRAIN_RANGE`; moduli bounded."""
    if hardening.law == "swift":
        try:
            sigma = hardening.B * hardening.C**hardening.n
        except OverflowError:
            sigma = math.inf
        formula, where = f"B C^n = {hardening.B:g} x {hardening.C:g}^{hardening.n:g}", "B"
    else:
        sigma, formula, where = hardening.yield_stress, "yield_stress", "yield_stress"
    low, high = YIELD_STRAIN_RANGE
    if not (math.isfinite(sigma) and low * young <= sigma <= high * young):
        fail(
            f"{path}.{where}",
            f"the initial yield stress {formula} = {sigma:g} Pa must be between {low:g} and "
            f"{high:g} times the body's E = {young:g} Pa, i.e. in [{low * young:.4g}, "
            f"{high * young:.4g}] Pa",
        )
    for key, value in (
        ("modulus", hardening.modulus),
        ("kinematic.C", hardening.kinematic_modulus),
    ):
        if value > MAX_HARDENING_RATIO * young:
            fail(
                f"{path}.{key}",
                f"a hardening modulus must be at most {MAX_HARDENING_RATIO:g} times the body's "
                f"E = {young:g} Pa, got {value:g} Pa",
            )
    if hardening.kinematic_recall > MAX_RECALL:
        fail(
            f"{path}.kinematic.gamma",
            f"must be at most {MAX_RECALL:g} (measured recalls are 10-1000), got "
            f"{hardening.kinematic_recall:g}",
        )


def body_spec(body: Body) -> dict:
    """A body's normalised table (what :meth:`solver.Case.to_dict` records)."""
    radius = json_number

    out: dict[str, Any] = {"behaviour": body.behaviour}
    if body.radius_x == body.radius_y:
        out["radius"] = radius(body.radius_x)
    else:
        out["radius_x"], out["radius_y"] = radius(body.radius_x), radius(body.radius_y)
    if body.profile is not None:
        out["profile"] = body.profile.spec()
    if body.surface is not None:
        out["surface"] = dict(body.surface.origin, sha256=body.surface.digest)
    if body.roughness is not None:
        r = body.roughness
        out["roughness"] = {
            "hurst": r.hurst,
            "long_cutoff": r.long_cutoff,
            "short_cutoff": r.short_cutoff,
            **({"rms": r.rms} if r.rms is not None else {"rms_slope": r.rms_slope}),
            "seed": r.seed,
        }
    if not body.rigid:
        out["E"], out["nu"] = body.E, body.nu
    if body.hardening is not None:
        h = body.hardening
        out["hardening"] = {"law": h.law} | {k: getattr(h, k) for k in HARDENING_KEYS[h.law]}
        if h.kinematic:  # only then: isotropic cases keep their ids
            law = "armstrong-frederick" if h.kinematic_recall > 0 else "prager"
            out["hardening"]["kinematic"] = {"law": law, "C": h.kinematic_modulus} | (
                {"gamma": h.kinematic_recall} if h.kinematic_recall > 0 else {}
            )
    return out


def _map_slope(
    surface: HeightMap, grid: SurfaceGrid, period: tuple[float, float] | None = None
) -> float:
    """Rms slope of a map resampled onto a grid (:func:`~solver.bodies.heights.grid_rms_slope`).

    Memoised: a campaign's cases often share a map and a grid.
    """
    return grid_rms_slope(surface, grid.x, grid.y, period)


def _check_periodic_map(surface: HeightMap, period: tuple[float, float], where: str) -> None:
    """Refuse a map that is not one period of a periodic surface.

    Its span (N dx, M dy) must be the period, and its opposite edges must join: the rms step
    across a seam at most :data:`MAX_SEAM_STEP` times the rms step between neighbouring points
    inside.
    """
    file = surface.source
    if not np.allclose(surface.period, period, rtol=PERIOD_RTOL):
        fail(
            where,
            f"{file} spans {surface.period[0]:.6g} m by {surface.period[1]:.6g} m as one period "
            f"(points x spacing), not the period grid.size = [{period[0]:.6g}, "
            f"{period[1]:.6g}] m; give grid.size its span",
        )
    height = surface.height  # (y, x)
    for axis, along in ((1, "x"), (0, "y")):
        inside = np.sqrt(np.mean(np.diff(height, axis=axis) ** 2))
        first, last = np.take(height, 0, axis=axis), np.take(height, -1, axis=axis)
        seam = np.sqrt(np.mean((first - last) ** 2))
        if seam > MAX_SEAM_STEP * inside:
            fail(
                where,
                f"{file} is not periodic along {along}: its opposite edges differ by "
                f"{seam:.3g} m rms, {seam / max(inside, 1e-300):.3g} times the step between "
                f"neighbouring points inside (at most {MAX_SEAM_STEP:g}); give a periodic map "
                "(or window it) for grid.periodic",
            )


def _above(value: float, limit: float = MAX_SURFACE_SLOPE) -> str:
    """``value`` (> ``limit``) to 3 significant digits, or as many more as show it above."""
    for digits in range(3, 17):
        text = f"{value:.{digits}g}"
        if float(text) > limit:
            return text
    return repr(value)


def _round_down(value: float) -> str:
    """A positive number rounded down to 3 significant digits, as text (a bound that passes)."""
    if not (math.isfinite(value) and value > 0):
        return f"{value:.3g}"
    unit = 10.0 ** (math.floor(math.log10(value)) - 2)
    return f"{math.floor(value / unit * (1 + 1e-12)) * unit:.3g}"


def check_surfaces(case) -> None:
    """Refuse height maps and roughness the grid cannot take, or too steep for the theory.

    A map must cover the domain's cell centres, be at most :data:`MAX_MAP_COARSENING`
    cells coarse and span fewer metres of height than the domain is wide; a roughness's
    short cutoff must span 2 cells and its lattice fit :data:`MAX_ROUGHNESS_LATTICE`.

    Slopes (small-slope theory, :data:`MAX_SURFACE_SLOPE` as for profiles), each point
    height on its own (a body's map and roughness, both bodies' surfaces, are checked
    apart), measured on what the solver sees:

    * a height map: the rms slope of its heights resampled at the grid's cell centres (at
      the start of the path), by forward differences between neighbouring cells
      (:func:`~solver.bodies.heights.grid_rms_slope`);
    * a roughness given by ``rms``: the rms slope of its realisation, spectral on its own
      lattice (:meth:`~solver.bodies.heights.Roughness.realised_rms_slope`, the measure
      ``rms_slope`` is given in, so the largest rms that passes is rms x limit / slope);
      computed only when the bound ``rms 2 pi / short_cutoff`` passes the limit.  One
      given by ``rms_slope`` has that slope, checked when parsed.
    """
    grid = case.surface_grid
    hx, hy = 0.5 * grid.nx * grid.dx, 0.5 * grid.ny * grid.dy
    cell = max(grid.dx, grid.dy)
    period = case.grid.size if case.grid.periodic else None
    for name, body in (("body1", case.body1), ("body2", case.body2)):
        surface = body.surface
        if surface is not None:
            where, file = f"{name}.surface", surface.source
            x0, x1, y0, y1 = surface.extent
            tol = 1e-9 * cell
            if period is not None:
                _check_periodic_map(surface, period, where)
            elif (
                x0 > grid.x[0] + tol
                or x1 < grid.x[-1] - tol
                or (y0 > grid.y[0] + tol or y1 < grid.y[-1] - tol)
            ):
                fail(
                    where,
                    f"{file} covers x in [{x0:.4g}, {x1:.4g}] m, y in [{y0:.4g}, {y1:.4g}] "
                    f"m, smaller than the domain's cell centres (x, y within +-"
                    f"{hx - 0.5 * grid.dx:.4g}, +-{hy - 0.5 * grid.dy:.4g} m); give a "
                    "larger map or a smaller domain (grid.size or half_width)",
                )
            spacing = max(surface.dx, surface.dy)
            if spacing > MAX_MAP_COARSENING * cell:
                fail(
                    where,
                    f"{file} is too coarse for the grid: its spacing {spacing:.4g} m is "
                    f"more than {MAX_MAP_COARSENING:g} cells ({cell:.4g} m); use a finer "
                    "map or a coarser grid",
                )
            relief = float(np.ptp(surface.height))
            if relief > 2 * max(hx, hy):
                fail(
                    where,
                    f"{file} has heights spanning {relief:.4g} m, more than the domain "
                    f"({2 * max(hx, hy):.4g} m): are they in metres (micrometres written as "
                    "metres)?  Heights are in metres",
                )
            slope = _map_slope(surface, grid)
            if slope > MAX_SURFACE_SLOPE:
                fail(
                    where,
                    f"{file} resampled onto the grid has an rms slope of {_above(slope)} "
                    f"(finite differences between cells), more than {MAX_SURFACE_SLOPE:g} "
                    "(small-slope theory; a steeper map gives one-cell spots of unphysical "
                    "pressure): "
                    f"scale its heights by at most {_round_down(MAX_SURFACE_SLOPE / slope)} "
                    "or smooth it (are the heights in metres?)",
                )
        roughness = body.roughness
        if roughness is not None:
            where = f"{name}.roughness"
            if period is not None and roughness.short_cutoff < MIN_PERIODIC_CUTOFF_CELLS * cell:
                fail(
                    f"{where}.short_cutoff",
                    f"{roughness.short_cutoff:.4g} m spans fewer than "
                    f"{MIN_PERIODIC_CUTOFF_CELLS} cells ({MIN_PERIODIC_CUTOFF_CELLS * cell:.4g} m) "
                    "of the period: its asperities would be one or two cells wide; raise "
                    "short_cutoff or refine the grid",
                )
            if roughness.short_cutoff < 2 * cell:
                fail(
                    f"{where}.short_cutoff",
                    f"{roughness.short_cutoff:.4g} m is shorter than 2 cells "
                    f"({2 * cell:.4g} m): the grid cannot carry it; raise short_cutoff or "
                    "refine the grid",
                )
            if roughness.rms is not None and roughness.rms > 2 * max(hx, hy):
                fail(
                    f"{where}.rms",
                    f"{roughness.rms:.4g} m is larger than the domain "
                    f"({2 * max(hx, hy):.4g} m): is it in metres?",
                )
            if period is not None:  # the period's own lattice
                if not math.isclose(period[0], period[1], rel_tol=PERIOD_RTOL):
                    fail(
                        "grid.size",
                        f"a periodic roughness needs a square period, got {list(period)} m: "
                        "give grid.size = L (and n = [nx, nx])",
                    )
                if roughness.long_cutoff > period[0] * (1 + PERIOD_RTOL):
                    fail(
                        f"{where}.long_cutoff",
                        f"{roughness.long_cutoff:.4g} m is longer than the period "
                        f"({period[0]:.4g} m): no wavelength longer than the period exists on "
                        "it; lower long_cutoff or enlarge grid.size",
                    )
                points, _ = roughness.lattice(period[0], periodic=True)
            else:
                points, _ = roughness.lattice(2 * max(hx, hy))
            if points > MAX_ROUGHNESS_LATTICE:
                fail(
                    f"{where}.short_cutoff",
                    f"the roughness lattice (spacing short_cutoff/"
                    f"{ROUGHNESS_POINTS_PER_CUTOFF}, side long_cutoff x 2^k over the "
                    f"domain) would need {points} points per side, more than "
                    f"{MAX_ROUGHNESS_LATTICE}; raise short_cutoff or lower long_cutoff",
                )
            if roughness.rms is not None and roughness.slope_bound() > MAX_SURFACE_SLOPE:
                # the lattice the solver samples (Roughness.sample): over the cell centres
                side = 2.0 * float(max(np.abs(grid.x).max(), np.abs(grid.y).max())) + 1e-300
                try:
                    if period is None:
                        slope = roughness.realised_rms_slope(side)
                    else:
                        slope = roughness.realised_rms_slope(period[0], periodic=True)
                except SurfaceError as error:
                    fail(where, str(error))
                if slope > MAX_SURFACE_SLOPE:
                    largest = _round_down(roughness.rms * MAX_SURFACE_SLOPE / slope)
                    fail(
                        f"{where}.rms",
                        f"rms = {roughness.rms:.4g} m gives a realisation of rms slope "
                        f"{_above(slope)} (spectral, on its lattice), more than "
                        f"{MAX_SURFACE_SLOPE:g} (small-slope theory): give rms <= "
                        f"{largest} m, or rms_slope <= {MAX_SURFACE_SLOPE:g} instead of rms",
                    )
