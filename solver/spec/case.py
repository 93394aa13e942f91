"""Case specification: a frozen, validated description of one contact simulation.

A case is built from a TOML table or a dict (SI units) with :meth:`Case.from_dict` /
:meth:`Case.from_toml`; every rule is checked at this boundary and a violation raises
:class:`SpecError` naming the field and what to change.  :meth:`Case.to_dict` gives the
normalised table (floats where floats are meant, defaults filled in), whose hash is the case id,
so ``1`` and ``1.0`` give the same id.
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import json
import math
import os
import tomllib
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..bodies.geometry import MAX_PROFILE_SLOPE, PROFILE_KEYS, PROFILES, Geometry, Profile
from ..bodies.heights import (
    MAX_ROUGHNESS_LATTICE,
    ROUGHNESS_POINTS_PER_CUTOFF,
    HeightMap,
    Roughness,
    SurfaceError,
    grid_rms_slope,
)
from ..bodies.materials import Body, Hardening, Pair
from ..keys import (
    DEFAULT_DEPTH,
    DEFAULT_HALF_WIDTH,
    DEPTH_RANGE,
    HARDENING_KEYS,
    KINEMATIC_KEYS,
    MAX_ANDERSON_MEMORY,
    MAX_AUTO_HALF_WIDTH,
    MAX_CELL_DEPTH,
    MAX_CELLS,
    MAX_CREEPAGE,
    MAX_CYCLES,
    MAX_FFT_THREADS,
    MAX_FRICTION,
    MAX_HARDENING_RATIO,
    MAX_INCREMENTS,
    MAX_ITERATIONS,
    MAX_MAP_COARSENING,
    MAX_RECALL,
    MAX_STAGE_STEPS,
    MAX_SURFACE_SLOPE,
    MAX_TOLERANCE,
    MIN_CELLS_ACROSS,
    MIN_PLASTIC_HALF_WIDTH,
    MIN_SINGLE_PLASTIC_TOLERANCE,
    MIN_YIELD_CELLS,
    MODULUS_RANGE,
    MOVING_DEPTH_MARGIN,
    PLASTIC_WIDTH_MARGIN,
    PRESSURE_RATIO_RANGE,
    PROFILE_EXPONENT_RANGE,
    PROFILE_MAX_ANGLE,
    RADIUS_RANGE,
    SOLVER_DEFAULTS,
    SWIFT_OFFSET_RANGE,
    YIELD_DEPTH_MARGIN,
    YIELD_STRAIN_RANGE,
    required_keys,
    table_keys,
)
from ..numerics.fftw import PLANNER_FLAGS, fft_size
from ..numerics.grid import IndexBox, SurfaceGrid, VolumeGrid
from ..theory.reference import (
    HertzContact,
    first_yield_pressure,
    hertz,
    hertz_force_for_pressure,
    hertz_yield_region,
)
from ..theory.sneddon import SneddonContact, radius_for_force
from ..variables import OPTIONAL_FIELDS
from .sizing import (
    auto_depth,
    auto_plastic_half_width,
    elastic_yield_region,
    narrow_window_note,
    resolved_half_width,
    slope_index,
)

#: Equivalent plastic strain up to which the small-strain theory is trusted (the reference
#: paper stops at 2 %); also the strain of the reference flow stress of :func:`plastic_index`.
SMALL_STRAIN_LIMIT = 0.02
#: Johnson's index E* a / (R sigma_Y) of a fully plastic indentation (Johnson 1985, §6.4:
#: ~30 for a sphere; the mean pressure has reached ~3 sigma_Y): refused, small strain is void.
FULLY_PLASTIC_INDEX = 30.0
#: Johnson's index past which the case gets a note: measured here, a perfectly plastic body
#: (16^3, 10 steps) converged at every step at 9.4 (p_H = 6 sigma_Y, e_p 2 %) and no longer at
#: 12.6 (8 sigma_Y, e_p 6 %); the plastic zone outgrows the 1.5 a_H window there as well.
UNCONTAINED_PLASTIC_INDEX = 10.0


class SpecError(ValueError):
    """An invalid case specification; the message names the field and what to change."""


#: Tables of :data:`solver.keys.CASE_KEYS` the parser names more than once.
HARDENING, KINEMATIC = "bodyN.hardening", "bodyN.hardening.kinematic"
PROFILE, SURFACE, ROUGHNESS = "bodyN.profile", "bodyN.surface", "bodyN.roughness"
#: What reads a height-map file: a surface table ({"file": ..., "spacing": ...}) to a
#: :class:`~solver.bodies.heights.HeightMap` (``study.campaign.surfaces.read_surface``; solver/ reads no
#: files).
SurfaceReader = Callable[[dict], HeightMap]
STAGE, CYCLE_BLOCK = "load.path[i]", "load.path[i] (cycle block)"


def _fail(path: str, message: str) -> None:
    raise SpecError(f"{path}: {message}")


def _check_keys(table: Any, path: str, allowed: set[str], required: set[str] = frozenset()):
    if not isinstance(table, dict):
        _fail(path or "case", f"must be a table, got {type(table).__name__}")
    unknown = sorted(set(table) - allowed)
    if unknown:
        _fail(
            f"{path}.{unknown[0]}" if path else unknown[0],
            f"unknown key; allowed keys are {', '.join(sorted(allowed))}",
        )
    for key in sorted(required):
        if key not in table:
            _fail(f"{path}.{key}" if path else key, "missing required field")
    return table


def _plain(value: Any) -> Any:
    """Numpy scalars and arrays as the Python bool, int, float, str or list they hold."""
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    return value


def _brief(value: Any) -> str:
    """``repr(value)`` for a one-line message, cut to 80 characters."""
    text = " ".join(repr(value).split())
    return text if len(text) <= 80 else text[:77] + "..."


def _entries(value: Any, path: str, form: str, lengths=None, *, scalar: bool = False) -> Any:
    """A list the case takes (a pair of numbers, grid.n, output.fields): its entries, unchecked.

    Given as a list, a tuple or a 1-D numpy array alike (so all three give the same case id);
    with ``scalar``, a single value is returned as it is (the caller reads it: Q for [Q, 0],
    L for [L, L], ...).  Refused, naming ``path`` and the ``form`` it takes: a wrong number of
    entries (``lengths``: the allowed counts, None: any), nested lists, a 2-D array, a string
    or a table where a list belongs.
    """
    if isinstance(value, np.ndarray) and value.ndim > 1:
        _fail(path, f"must be {form}, got a {value.ndim}-D array of shape {value.shape}")
    value = _plain(value)
    if isinstance(value, tuple):
        value = list(value)
    if isinstance(value, list):
        if lengths is not None and len(value) not in lengths:
            _fail(path, f"must be {form}, got {len(value)} entries: {_brief(value)}")
        if any(isinstance(_plain(v), list | tuple | dict) for v in value):
            _fail(path, f"must be {form}, got nested lists or tables: {_brief(value)}")
        return value
    if not scalar or isinstance(value, str | bytes | dict | set | frozenset):
        _fail(path, f"must be {form}, got {_brief(value)}")
    return value


def _show(value: int) -> str:
    """An integer for a message: its digits, or its size when it has too many to print."""
    if abs(value) < 10**30:
        return str(value)
    return f"{'a negative' if value < 0 else 'an'} integer of {value.bit_length()} bits"


def _number(value: Any, path: str, *, positive: bool = False, allow_inf: bool = False) -> float:
    value = _plain(value)
    if isinstance(value, str) and value.lower() in ("inf", "infinity") and allow_inf:
        return math.inf
    if isinstance(value, bool) or not isinstance(value, int | float):
        hint = ' (or "inf")' if allow_inf else ""
        _fail(path, f"must be a number{hint}, got {value!r}")
    try:
        value = float(value)
    except OverflowError:  # an int beyond the float range
        _fail(path, f"must be finite, got {_show(value)}, beyond the float range")
    if math.isnan(value) or (math.isinf(value) and not allow_inf):
        _fail(path, f"must be finite, got {value!r}")
    if positive and not value > 0:
        _fail(path, f"must be > 0, got {value!r}")
    return value


def _integer(value: Any, path: str, low: int, high: int) -> int:
    value = _plain(value)
    if isinstance(value, float) and value.is_integer():
        value = int(value)
    if isinstance(value, bool) or not isinstance(value, int):
        _fail(path, f"must be an integer, got {value!r}")
    if not low <= value <= high:
        _fail(path, f"must be between {low} and {high}, got {_show(value)}")
    return value


def _parse_kinematic(table: Any, path: str) -> dict:
    _check_keys(table, path, table_keys(KINEMATIC), required_keys(KINEMATIC))
    law = _plain(table["law"])
    if law not in KINEMATIC_KEYS:
        _fail(f"{path}.law", f"must be one of {', '.join(KINEMATIC_KEYS)}, got {law!r}")
    _check_keys(table, path, KINEMATIC_KEYS[law] | {"law"}, KINEMATIC_KEYS[law])
    modulus = _number(table["C"], f"{path}.C", positive=True)
    recall = _number(table["gamma"], f"{path}.gamma", positive=True) if "gamma" in table else 0.0
    return {"kinematic_modulus": modulus, "kinematic_recall": recall}


def _parse_profile(table: Any, path: str) -> Profile:
    _check_keys(table, path, table_keys(PROFILE), required_keys(PROFILE))
    shape = _plain(table["shape"])
    if shape not in PROFILES:
        _fail(f"{path}.shape", f"must be one of {', '.join(PROFILES)}, got {shape!r}")
    keys = PROFILE_KEYS[shape]
    _check_keys(table, path, {*keys, "shape"}, set(keys))
    if shape == "cone":
        angle = _number(table["angle"], f"{path}.angle", positive=True)
        if angle > PROFILE_MAX_ANGLE:
            _fail(
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
    coefficient = _number(table["coefficient"], f"{path}.coefficient", positive=True)
    exponent = _number(table["exponent"], f"{path}.exponent")
    low, high = PROFILE_EXPONENT_RANGE
    if not low <= exponent <= high:
        _fail(f"{path}.exponent", f"must be in [{low:g}, {high:g}], got {exponent:g}")
    if exponent == 1.0 and coefficient > 1.0:
        _fail(f"{path}.coefficient", "with exponent 1 (a cone) the slope must be <= 1")
    return PROFILES[shape](coefficient, exponent)


def _parse_surface(value: Any, path: str, read_surface: SurfaceReader | None) -> HeightMap:
    """A height map: given as an object, or read by ``read_surface`` from its table."""
    value = _plain(value)
    if isinstance(value, os.PathLike):  # a file name as a path: the same as its text
        value = os.fspath(value)
    if isinstance(value, dict):
        value = {k: os.fspath(v) if isinstance(v, os.PathLike) else v for k, v in value.items()}
    if isinstance(value, HeightMap):
        value.origin = {"file": f"<in memory: {value.source}>"}
        return value
    if isinstance(value, str):
        value = {"file": value}
    _check_keys(value, path, table_keys(SURFACE), required_keys(SURFACE))
    kinds = [k for k in ("file", "case") if k in value]
    if len(kinds) != 1:
        _fail(path, "give one of file (a height map) and case (an earlier case's dent)")
    kind = kinds[0]
    if not isinstance(value[kind], str) or not value[kind]:
        _fail(f"{path}.{kind}", f"must be a file name, got {value[kind]!r}")
    origin = {kind: value[kind]}
    if "offset" in value:
        offset = _entries(value["offset"], f"{path}.offset", "[dx, dy] (m)", (2,))
        origin["offset"] = [_number(v, f"{path}.offset") for v in offset]
    if "spacing" in value:
        if kind == "case":
            _fail(f"{path}.spacing", "a case file's coordinates give the spacing; remove it")
        form = "dx or [dx, dy] (m)"
        spacing = _entries(value["spacing"], f"{path}.spacing", form, (1, 2), scalar=True)
        items = spacing if isinstance(spacing, list) else [spacing]
        origin["spacing"] = [_number(v, f"{path}.spacing", positive=True) for v in items]
    if read_surface is None:
        _fail(
            path,
            "a height-map file is read by the study layer: build the case with "
            "Case.from_dict(table, read_surface=study.campaign.surfaces.read_surface), or give a "
            "solver.bodies.heights.HeightMap",
        )
    try:
        surface = read_surface(origin)
    except SurfaceError as error:
        _fail(path, str(error))
    if "sha256" in value and not isinstance(value["sha256"], str):
        _fail(
            f"{path}.sha256",
            f"must be the map's content hash (64 hex digits, as the case file records it), got "
            f"{_brief(value['sha256'])}; remove it to take the file as it is",
        )
    if "sha256" in value and value["sha256"] != surface.digest:
        _fail(
            f"{path}.sha256",
            f"{value[kind]} changed since this case was written (its content hash differs); "
            "build the case again from its campaign file",
        )
    surface.origin = origin
    return surface


def _parse_roughness(table: Any, path: str) -> Roughness:
    if isinstance(table, Roughness):  # the object, read as its table (as a HeightMap is taken)
        table = {k: v for k, v in dataclasses.asdict(table).items() if v is not None}
    _check_keys(table, path, table_keys(ROUGHNESS), required_keys(ROUGHNESS))
    if ("rms" in table) == ("rms_slope" in table):
        _fail(path, "give one of rms (m) and rms_slope")
    hurst = _number(table["hurst"], f"{path}.hurst", positive=True)
    if hurst > 1:
        _fail(f"{path}.hurst", f"must be in (0, 1], got {hurst:g}")
    long = _number(table["long_cutoff"], f"{path}.long_cutoff", positive=True)
    short = _number(table["short_cutoff"], f"{path}.short_cutoff", positive=True)
    if not long > short:
        _fail(f"{path}.long_cutoff", f"must exceed short_cutoff = {short:g} m, got {long:g}")
    rms = _number(table["rms"], f"{path}.rms", positive=True) if "rms" in table else None
    slope = None
    if "rms_slope" in table:
        slope = _number(table["rms_slope"], f"{path}.rms_slope", positive=True)
        if slope > MAX_SURFACE_SLOPE:
            _fail(
                f"{path}.rms_slope",
                f"must be <= {MAX_SURFACE_SLOPE:g} (small-slope theory), got {slope:g}",
            )
    seed = _integer(table.get("seed", 0), f"{path}.seed", 0, 2**63 - 1)
    return Roughness(hurst, long, short, rms, slope, seed)


def _parse_hardening(table: Any, path: str) -> Hardening:
    _check_keys(table, path, table_keys(HARDENING), required_keys(HARDENING))
    law = _plain(table["law"])
    if law not in HARDENING_KEYS:
        _fail(f"{path}.law", f"must be one of {', '.join(HARDENING_KEYS)}, got {law!r}")
    _check_keys(table, path, HARDENING_KEYS[law] | {"law", "kinematic"}, HARDENING_KEYS[law])
    values = {}
    for key in HARDENING_KEYS[law]:
        values[key] = _number(table[key], f"{path}.{key}", positive=key != "modulus")
        if key == "modulus" and values[key] < 0:
            _fail(f"{path}.modulus", f"must be >= 0, got {values[key]}")
    if law == "swift":
        low, high = SWIFT_OFFSET_RANGE
        if not low <= values["C"] <= high:
            _fail(
                f"{path}.C",
                f"Swift's offset C (micro-strain) must be in [{low:g}, {high:g}], got "
                f"{values['C']:g} (the paper's steel: C = 20)",
            )
        if not values["n"] <= 1:
            _fail(f"{path}.n", f"Swift's exponent must be in (0, 1], got {values['n']:g}")
    if "kinematic" in table:
        values.update(_parse_kinematic(table["kinematic"], f"{path}.kinematic"))
    return Hardening(law=law, **values)


def _parse_body(table: Any, path: str, read_surface: SurfaceReader | None = None) -> Body:
    _check_keys(table, path, table_keys("bodyN"), required_keys("bodyN"))
    behaviour = _plain(table["behaviour"])
    if behaviour not in ("rigid", "elastic", "elastic-plastic"):
        _fail(f"{path}.behaviour", f"must be rigid, elastic or elastic-plastic, got {behaviour!r}")
    if "radius" in table and ("radius_x" in table or "radius_y" in table):
        _fail(f"{path}.radius", "give either radius or radius_x/radius_y, not both")
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
            _fail(
                f"{path}.profile",
                "a profile is axisymmetric and adds to a sphere only: give radius (or none), "
                "not radius_x / radius_y",
            )
    if behaviour == "rigid":
        for key in ("E", "nu", "hardening"):
            if key in table:
                _fail(f"{path}.{key}", "a rigid body takes no elastic or hardening data; remove it")
        return Body("rigid", rx, ry, profile=profile, surface=surface, roughness=roughness)
    for key in ("E", "nu"):
        if key not in table:
            _fail(f"{path}.{key}", f"missing required field for a {behaviour} body")
    young = _number(table["E"], f"{path}.E", positive=True)
    low, high = MODULUS_RANGE
    if not low <= young <= high:
        _fail(f"{path}.E", f"Young's modulus must be in [{low:g}, {high:g}] Pa, got {young:g}")
    nu = _number(table["nu"], f"{path}.nu")
    if not -1.0 < nu <= 0.5:
        _fail(f"{path}.nu", f"Poisson's ratio must be in (-1, 0.5], got {nu}")
    hardening = None
    if behaviour == "elastic-plastic":
        if "hardening" not in table:
            _fail(f"{path}.hardening", "missing: an elastic-plastic body needs a hardening table")
        hardening = _parse_hardening(table["hardening"], f"{path}.hardening")
        _check_yield_stress(hardening, young, f"{path}.hardening")
    elif "hardening" in table:
        _fail(f"{path}.hardening", "only elastic-plastic bodies take a hardening law")
    return Body(behaviour, rx, ry, young, nu, hardening, profile, surface, roughness)


def _radius(value: Any, path: str, flat: bool = True) -> float:
    """A radius (m): in :data:`RADIUS_RANGE`, or "inf" for a flat body where ``flat``."""
    radius = _number(value, path, positive=True, allow_inf=flat)
    low, high = RADIUS_RANGE
    if not (low <= radius <= high or math.isinf(radius)):
        flat_text = ' or "inf" (flat)' if flat else ""
        _fail(path, f"must be in [{low:g}, {high:g}] m{flat_text}, got {radius:g}")
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
        _fail(
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
            _fail(
                f"{path}.{key}",
                f"a hardening modulus must be at most {MAX_HARDENING_RATIO:g} times the body's "
                f"E = {young:g} Pa, got {value:g} Pa",
            )
    if hardening.kinematic_recall > MAX_RECALL:
        _fail(
            f"{path}.kinematic.gamma",
            f"must be at most {MAX_RECALL:g} (measured recalls are 10-1000), got "
            f"{hardening.kinematic_recall:g}",
        )


@dataclass(frozen=True)
class LoadStage:
    """One stage of the load path, ramping linearly from the previous state.

    Attributes
    ----------
    normal_force : float
        Target normal force W (N) at the end of the stage.
    tangential_force : (float, float)
        Target tangential force (Q_x, Q_y) (N) on body 2 at the end of the stage.
    steps : int
        Number of load increments of the stage.
    cycle : int
        Load cycle of the stage: 1, 2, ... inside cycle blocks (``cycles = N``; numbered on
        across blocks), 0 outside.
    travel : (float, float)
        Travel (m) of body 1's apex over body 2 during the stage: gross sliding (``slide``) or
        rolling (``roll``).
    motion : str
        ``"slide"``, ``"roll"`` or ``""`` (no travel).
    creepage : (float, float) or None
        Kalker's creepages (xi, eta) (dimensionless) of a rolling stage: the rigid slip of body
        1 relative to body 2 per unit distance rolled; the tangential force is then a result.
        ``(0, 0)`` on a stage without travel that follows one (the rigid shift held).  None:
        the tangential force is prescribed.
    spin : float
        Rigid rotation of body 1 relative to body 2 about z per unit distance rolled (1/m),
        counter-clockwise from x to y, about the contact's centre.
    """

    normal_force: float
    tangential_force: tuple[float, float]
    steps: int
    cycle: int = 0
    travel: tuple[float, float] = (0.0, 0.0)
    motion: str = ""
    creepage: tuple[float, float] | None = None
    spin: float = 0.0


def _parse_path(raw_stages: list, pair: Pair) -> tuple[list[LoadStage], list[str], list[dict]]:
    """Stages of a load path with its cycle blocks repeated, their paths, the normalised path.

    An entry ``{cycles = N, stages = [...]}`` repeats its stages N times (cycles numbered on
    from the previous block's: 1 .. N for the first); a stage without a normal (tangential)
    force keeps the previous one, also across cycles.
    """
    stages, paths, given = [], [], []
    previous = (0.0, (0.0, 0.0), False)  # (W, Q, the force free: a creepage stage before)
    total = 0  # increments so far

    def count(path: str, steps: int) -> int:
        if total + steps > MAX_INCREMENTS:
            _fail(
                path,
                f"the load path reaches {_show(total + steps)} increments (cycle blocks "
                f"repeated), more than {MAX_INCREMENTS:,}; give fewer steps per stage or fewer "
                "cycles (the memory and the time grow with every increment)",
            )
        return total + steps

    for i, raw in enumerate(raw_stages):
        path = f"load.path[{i}]"
        if isinstance(raw, dict) and "cycles" in raw:
            _check_keys(raw, path, table_keys(CYCLE_BLOCK), required_keys(CYCLE_BLOCK))
            cycles = _integer(raw["cycles"], f"{path}.cycles", 1, MAX_CYCLES)
            inner = raw["stages"]
            if isinstance(inner, tuple):
                inner = list(inner)
            if not isinstance(inner, list) or not inner:
                _fail(f"{path}.stages", "must be a non-empty array of tables ([[...stages]])")
            block, offset = [], max((stage.cycle for stage in stages), default=0)
            for cycle in range(offset + 1, offset + cycles + 1):
                if cycle == offset + 2:  # the block's increments are known: refuse before
                    per_cycle = sum(spec["steps"] for spec in block)  # repeating it
                    count(f"{path}.cycles", per_cycle * (cycles - 1))
                for j, sub in enumerate(inner):
                    where = f"{path}.stages[{j}]"
                    if isinstance(sub, dict) and "cycles" in sub:
                        _fail(f"{where}.cycles", "cycle blocks do not nest; flatten the block")
                    stage, spec = _parse_stage(sub, where, previous, pair, not stages)
                    stage = dataclasses.replace(stage, cycle=cycle)
                    stages.append(stage)
                    paths.append(where)
                    previous = _after(stage)
                    total = count(f"{where}.steps", stage.steps)
                    if cycle == offset + 1:
                        block.append(spec)
            given.append({"cycles": cycles, "stages": block})
            continue
        stage, spec = _parse_stage(raw, path, previous, pair, not stages)
        total = count(f"{path}.steps", stage.steps)
        stages.append(stage)
        paths.append(path)
        given.append(spec)
        previous = _after(stage)
    return stages, paths, given


def _after(stage: LoadStage) -> tuple:
    """What a stage leaves to the next: (W, Q, whether the force is free)."""
    free = stage.creepage is not None and stage.normal_force > 0
    return stage.normal_force, stage.tangential_force, free


def path_cycles(path: list[dict]) -> int:
    """Load cycles of a normalised load path (0 without a cycle block)."""
    return sum(entry.get("cycles", 0) for entry in path)


def path_steps(path: list[dict]) -> int:
    """Load increments of a normalised load path (:meth:`Case.to_dict`), cycles repeated."""
    return sum(
        entry["cycles"] * path_steps(entry["stages"]) if "cycles" in entry else entry["steps"]
        for entry in path
    )


def _load_number(value: Any, path: str, first: bool) -> float:
    """A load: > 0 in the first stage, >= 0 later (0 unloads the contact)."""
    value = _number(value, path, positive=first)
    if value < 0:
        _fail(path, f"must be >= 0 (0 unloads the contact), got {value!r}")
    return value


_HERTZ_ERRORS = (OverflowError, ZeroDivisionError, ValueError)


def _load_range(pair: Pair) -> str:
    """The accepted loads for a pair, as text: p_H/E*, p_H and W ranges."""
    e_star, curvature = pair.composite_modulus, pair.curvature
    ratios = PRESSURE_RATIO_RANGE
    p_low, p_high = (r * e_star for r in ratios)
    try:
        w_low, w_high = (hertz_force_for_pressure(p, e_star, curvature) for p in (p_low, p_high))
        forces = f", W in [{w_low:.3g}, {w_high:.3g}] N"
    except _HERTZ_ERRORS:
        forces = ""
    return (
        f"p_H/E* must be in [{ratios[0]:g}, {ratios[1]:g}] (small strain; E* = {e_star:.4g} Pa): "
        f"p_H in [{p_low:.3g}, {p_high:.3g}] Pa{forces} for these bodies"
    )


def _force_for_pressure(p_h: float, pair: Pair, path: str) -> float:
    """Normal force (N) of a Hertz pressure (Pa), refusing pressures outside the range."""
    e_star = pair.composite_modulus
    if p_h == 0:
        return 0.0
    low, high = (r * e_star for r in PRESSURE_RATIO_RANGE)
    if not low * (1 - 1e-12) <= p_h <= high * (1 + 1e-12):  # slack: round-off of E*
        _fail(path, f"{_load_range(pair)}; got p_H = {p_h:g} Pa")
    try:
        force = hertz_force_for_pressure(p_h, e_star, pair.curvature)
    except _HERTZ_ERRORS as error:
        force, why = math.nan, error
    else:
        why = "not finite"
    if not (math.isfinite(force) and force > 0):
        _fail(
            path,
            f"the Hertz force of p_H = {p_h:g} Pa cannot be computed ({why}); {_load_range(pair)}",
        )
    return force


@functools.lru_cache(maxsize=256)
def _profile_radius(geometry: Geometry, force: float, e_star: float) -> float:
    """Sneddon's contact radius (m) of a profiled gap under ``force`` (N).

    ValueError past the slope limit; memoised (a cyclic path checks the same forces again).
    """
    return radius_for_force(
        force, geometry.slope, e_star, geometry.breaks, geometry.start, geometry.slope_limit
    )


def _check_profile_force(force: float, pair: Pair, path: str) -> None:
    """Refuse a normal force that a profile cannot carry in the small-strain theory.

    Refused: a contact pushed past the profile's slope limit, or a mean pressure W / (pi a^2)
    over E* outside :data:`PRESSURE_RATIO_RANGE`.
    """
    geometry, e_star = pair.geometry, pair.composite_modulus
    try:
        a = _profile_radius(geometry, force, e_star)
    except ValueError:
        _fail(
            path,
            f"W = {force:g} N presses the contact out to where the surface's slope passes "
            f"{MAX_PROFILE_SLOPE:g} (radius {geometry.slope_limit:.4g} m; small-slope theory); "
            "lower the load, or blunt the profile (a smaller angle or coefficient, a larger "
            "edge_radius)",
        )
    ratio = force / (math.pi * a * a) / e_star
    low, high = PRESSURE_RATIO_RANGE
    if not low <= ratio <= high:
        _fail(
            path,
            f"W = {force:g} N gives a mean pressure of {ratio:.3g} E* on Sneddon's contact "
            f"(radius {a:.4g} m); it must be in [{low:g}, {high:g}] E* (small strain)",
        )


def _check_force(force: float, pair: Pair, path: str) -> None:
    """Refuse a non-zero normal force whose Hertz pressure is outside the accepted range."""
    if force == 0:
        return
    if pair.geometry.reference_kind == "sneddon":
        _check_profile_force(force, pair, path)
    if not pair.geometry.hertzian:  # heights only: no closed form to check against
        return
    e_star = pair.composite_modulus
    try:
        p_h = hertz(force, e_star, pair.curvature).max_pressure
    except _HERTZ_ERRORS:
        p_h = math.nan
    low, high = (r * e_star for r in PRESSURE_RATIO_RANGE)
    if not low * (1 - 1e-12) <= p_h <= high * (1 + 1e-12):  # slack: round-off of p_H
        _fail(
            path,
            f"W = {force:g} N gives a Hertz pressure p_H = {p_h:.3g} Pa "
            f"(p_H/E* = {p_h / e_star:.3g}); {_load_range(pair)}",
        )


def _check_mean_pressure(force: float, pair: Pair, size: tuple[float, float], path: str) -> None:
    """Refuse a normal force (N) whose mean pressure over a heights-only domain is out of range.

    Without a smooth shape there is no Hertz pressure to check (:func:`_check_force`); the
    nominal mean pressure W / (Lx Ly) over the domain ``size`` (m) is checked against
    :data:`PRESSURE_RATIO_RANGE` times E* (Pa) instead, as p_H / E* is (the real contact area is
    smaller, so its pressures are higher still).  An unloaded stage (0 N) is not checked; a
    stage that keeps the previous force passes when the stage that set it did.
    """
    if force == 0:
        return
    e_star, area = pair.composite_modulus, size[0] * size[1]
    ratio = force / area / e_star
    low, high = PRESSURE_RATIO_RANGE
    if not low <= ratio <= high:
        _fail(
            path,
            f"W = {force:g} N gives a mean pressure W/(Lx Ly) = {ratio:.3g} E* over the domain "
            f"({size[0]:.4g} m by {size[1]:.4g} m, E* = {e_star:.4g} Pa); it must be in "
            f"[{low:g}, {high:g}] E* (small strain): W in [{low * e_star * area:.3g}, "
            f"{high * e_star * area:.3g}] N for this domain",
        )


def _parse_stage(table: Any, path: str, previous: tuple, pair: Pair, first: bool) -> tuple:
    _check_keys(table, path, table_keys(STAGE))
    if "hertz_pressure" in table and "normal_force" in table:
        _fail(f"{path}.hertz_pressure", "give either hertz_pressure or normal_force, not both")
    given = {}
    if "hertz_pressure" in table and not pair.geometry.hertzian:
        _fail(
            f"{path}.hertz_pressure",
            "the pair has no Hertz pressure (a profile, or heights without a radius): give "
            "normal_force (N)",
        )
    if "hertz_pressure" in table:
        p_h = _load_number(table["hertz_pressure"], f"{path}.hertz_pressure", first)
        given["hertz_pressure"] = p_h
        force = _force_for_pressure(p_h, pair, f"{path}.hertz_pressure")
    elif "normal_force" in table:
        force = _load_number(table["normal_force"], f"{path}.normal_force", first)
        _check_force(force, pair, f"{path}.normal_force")
        given["normal_force"] = force
    elif first:
        _fail(path, "missing load: give hertz_pressure (Pa) or normal_force (N)")
    else:
        force = previous[0]
    if "tangential_force" in table:
        where = f"{path}.tangential_force"
        value = _entries(table["tangential_force"], where, "Q or [Qx, Qy] (N)", (2,), scalar=True)
        if isinstance(value, list):
            q = tuple(_number(v, where) for v in value)
        else:
            q = (_number(value, where), 0.0)
        given["tangential_force"] = list(q)
    else:
        q = previous[1]
    motion, travel = "", (0.0, 0.0)
    if "slide" in table and "roll" in table:
        _fail(f"{path}.roll", "a stage slides or rolls, not both: remove slide or roll")
    for key in ("slide", "roll"):
        if key not in table:
            continue
        if key == "slide" and "tangential_force" in table:
            _fail(
                f"{path}.slide",
                "a sliding stage sets the tangential force (mu W along the motion): remove "
                "tangential_force",
            )
        value = _entries(table[key], f"{path}.{key}", "[dx, dy] (m)", (2,))
        travel = tuple(_number(v, f"{path}.{key}") for v in value)
        if any(travel):  # a zero travel is no travel: the same case, the same id
            given[key] = list(travel)
            motion = key
    creepage, spin = _parse_creepage(table, path, previous, motion, given)
    if creepage is not None:  # the force is a result
        q = (0.0, 0.0)
    steps = _integer(table.get("steps", 1), f"{path}.steps", 1, MAX_STAGE_STEPS)
    given["steps"] = steps
    stage = LoadStage(force, q, steps, travel=travel, motion=motion, creepage=creepage, spin=spin)
    return stage, given


def _parse_creepage(table: Any, path: str, previous: tuple, motion: str, given: dict) -> tuple:
    """(creepage, spin) of a stage: Kalker's creepages of a rolling stage, or None (force)."""
    creep_keys = [key for key in ("creepage", "spin") if key in table]
    if creep_keys and motion != "roll":
        _fail(
            f"{path}.{creep_keys[0]}",
            "creepage and spin belong to a rolling stage: give roll = [dx, dy] (m) too"
            if motion == ""
            else "a sliding stage slips everywhere (mu p along the motion): remove "
            f"{creep_keys[0]} or roll instead of slide",
        )
    if creep_keys and "tangential_force" in table:
        _fail(
            f"{path}.tangential_force",
            "a rolling stage takes either the creepages (the force is then a result) or the "
            "tangential force (the creepage is then a result), not both",
        )
    if previous[2] and "tangential_force" in table:
        _fail(
            f"{path}.tangential_force",
            "the previous stage rolls at given creepages, so its creep force is a result, not "
            "the start of a ramp: give creepage here too, or unload (normal_force = 0) first",
        )
    if not creep_keys:
        # after a creepage stage the force stays free: the rigid shift is held (no travel) or
        # rolls on at no creepage; else the force is prescribed
        return ((0.0, 0.0) if previous[2] and "tangential_force" not in table else None), 0.0
    creepage = (0.0, 0.0)
    if "creepage" in table:
        form = "xi or [xi, eta] (dimensionless)"
        value = _entries(table["creepage"], f"{path}.creepage", form, (2,), scalar=True)
        if isinstance(value, list):
            creepage = tuple(_number(v, f"{path}.creepage") for v in value)
        else:  # a number: longitudinal (along x)
            creepage = (_number(value, f"{path}.creepage"), 0.0)
        if any(abs(v) > MAX_CREEPAGE for v in creepage):
            _fail(
                f"{path}.creepage",
                f"each creepage must be within +-{MAX_CREEPAGE:g} (a slip of that fraction of "
                f"the distance rolled is full sliding long before), got {list(creepage)}",
            )
        given["creepage"] = list(creepage)
    spin = 0.0
    if "spin" in table:
        spin = _number(table["spin"], f"{path}.spin")
        given["spin"] = spin
    return creepage, spin


@dataclass(frozen=True)
class SolverOptions:
    """Tolerances and caps of the iterative loops (all dimensionless), and FFT settings.

    Defaults: :data:`solver.keys.SOLVER_DEFAULTS`.

    ``plastic_tolerance`` bounds the last change of a step's plastic strain increment relative
    to the yield strain sigma_Y0/E; ``anderson_memory`` is the number of past iterates the
    plasticity loop and the normal-tangential coupling loop mix (0: plain fixed-point iteration).

    ``fft_planner = "estimate"`` gives FFTW plans that do not depend on timing, so a case gives
    bit-identical results in any process; ``"measure"`` plans by timing (about 15 % faster
    solves, 0.5 s more set-up per grid) and results then agree only to round-off, which
    path-dependent coupled friction cases can amplify to ~1e-4.  ``"wisdom"`` takes measured
    plans from the wisdom imported into the process (:mod:`solver.numerics.fftw`), estimate plans where
    it has none: processes with the same wisdom give bit-identical results.
    """

    normal_tolerance: float = SOLVER_DEFAULTS["normal_tolerance"]
    normal_max_iterations: int = SOLVER_DEFAULTS["normal_max_iterations"]
    slip_tolerance: float = SOLVER_DEFAULTS["slip_tolerance"]
    slip_max_iterations: int = SOLVER_DEFAULTS["slip_max_iterations"]
    coupling_tolerance: float = SOLVER_DEFAULTS["coupling_tolerance"]
    coupling_max_iterations: int = SOLVER_DEFAULTS["coupling_max_iterations"]
    goodman: bool = SOLVER_DEFAULTS["goodman"]
    max_load_ratio: float = SOLVER_DEFAULTS["max_load_ratio"]
    plastic_tolerance: float = SOLVER_DEFAULTS["plastic_tolerance"]
    plastic_max_iterations: int = SOLVER_DEFAULTS["plastic_max_iterations"]
    anderson_memory: int = SOLVER_DEFAULTS["anderson_memory"]
    fft_threads: int = SOLVER_DEFAULTS["fft_threads"]
    fft_planner: str = SOLVER_DEFAULTS["fft_planner"]
    volume_precision: str = SOLVER_DEFAULTS["volume_precision"]


_SOLVER_RULES = {
    "normal_tolerance": ("tol",),
    "normal_max_iterations": ("int",),
    "slip_tolerance": ("tol",),
    "slip_max_iterations": ("int",),
    "coupling_tolerance": ("tol",),
    "coupling_max_iterations": ("int",),
    "goodman": ("bool",),
    "max_load_ratio": ("ratio",),
    "plastic_tolerance": ("tol",),
    "plastic_max_iterations": ("int",),
    "anderson_memory": ("memory",),
    "fft_threads": ("threads",),
    "fft_planner": ("planner",),
    "volume_precision": ("precision",),
}


def _parse_solver(table: Any) -> SolverOptions:
    _check_keys(table, "solver", table_keys("solver"))
    values = {}
    for key, value in table.items():
        rule = _SOLVER_RULES[key][0]
        path = f"solver.{key}"
        if rule == "tol":
            values[key] = _number(value, path, positive=True)
            if values[key] >= MAX_TOLERANCE:
                _fail(path, f"tolerance must be < {MAX_TOLERANCE:g}, got {value}")
        elif rule == "int":
            values[key] = _integer(value, path, 1, MAX_ITERATIONS)
        elif rule == "ratio":
            values[key] = _number(value, path, positive=True, allow_inf=True)
            if values[key] <= 1.0:
                _fail(path, f'must be > 1 (or "inf" to disable sub-stepping), got {value}')
        elif rule == "planner":
            if value not in PLANNER_FLAGS:
                _fail(
                    path,
                    f'must be "estimate" (reproducible), "measure" or "wisdom" (measured plans '
                    f"saved per machine, reproducible), got {value!r}",
                )
            values[key] = value
        elif rule == "precision":
            if value not in ("double", "single"):
                _fail(path, f'must be "double" or "single", got {value!r}')
            values[key] = value
        elif rule == "threads":
            values[key] = _integer(value, path, 1, MAX_FFT_THREADS)
        elif rule == "memory":
            values[key] = _integer(value, path, 0, MAX_ANDERSON_MEMORY)
        elif not isinstance(value := _plain(value), bool):
            _fail(path, f"must be true or false, got {value!r}")
        else:
            values[key] = value
    options = SolverOptions(**values)
    if (
        options.volume_precision == "single"
        and options.plastic_tolerance < MIN_SINGLE_PLASTIC_TOLERANCE
    ):
        _fail(
            "solver.volume_precision",
            f"single precision rounds the stress to ~1e-7, too coarse for plastic_tolerance = "
            f"{options.plastic_tolerance:g}: use plastic_tolerance >= "
            f'{MIN_SINGLE_PLASTIC_TOLERANCE:g} or volume_precision = "double"',
        )
    return options


@dataclass(frozen=True)
class GridSpec:
    """Requested discretisation: cells and domain size in units of the Hertz radius.

    ``size`` (m): the domain's sides instead of ``half_width`` (point heights).

    ``depth`` None (not given) is resolved by :meth:`Case.from_dict`: the elastic yield depth
    with a margin for elastic-plastic cases (:func:`~solver.spec.sizing.auto_depth`), else
    :data:`DEFAULT_DEPTH`.
    ``depth_body1``: the depth of body 1's own volume grid when both bodies are elastic-plastic
    and different (same cells; default: ``depth`` when given, else body 1's yield depth).
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


#: Thickest layer (dz / dx) under a perfectly plastic body without a note
#: (:meth:`Case._layer_note`).
MAX_PERFECT_LAYER = 0.62
#: Solver keys of how a case is computed, not what: kept in the table, not in the case id.
EXECUTION_KEYS = ("fft_threads", "fft_planner")
#: Field outputs a case may request.
FIELD_OUTPUTS = OPTIONAL_FIELDS
#: Version of the physical model: part of every case id, so that files computed by an older
#: model are never reused (version 1: elastic-plastic bodies solved as elastic; version 2: a
#: plastic increment whose loop did not converge was kept as it was, where version 3 halves
#: it, and a sliding increment's friction work missed the step after a reversal).
MODEL_VERSION = 3


@dataclass(frozen=True)
class Case:
    """One validated contact simulation.  Build it with :meth:`from_dict` or :meth:`from_toml`.

    Attributes
    ----------
    body1, body2 : Body
        Upper (indenter) and lower bodies.
    stages : tuple of LoadStage
        Load path.
    friction_coefficient : float
        Coulomb coefficient mu (dimensionless).
    grid : GridSpec
        Discretisation.
    solver : SolverOptions
        Tolerances and iteration caps.
    fields : tuple of str
        Optional field outputs.
    spec : dict
        The normalised table (SI units); its hash is :attr:`case_id`.
    warnings : tuple of str
        What the case is built with but should be read with care (a plastic zone past the
        contained regime, :func:`plastic_index`); the solve repeats them in its notes.
    """

    body1: Body
    body2: Body
    stages: tuple[LoadStage, ...]
    friction_coefficient: float
    grid: GridSpec
    solver: SolverOptions
    fields: tuple[str, ...] = ()
    spec: dict = field(default_factory=dict, compare=False, hash=False, repr=False)
    warnings: tuple[str, ...] = field(default=(), compare=False, hash=False, repr=False)

    # -- construction -----------------------------------------------------------------------
    @classmethod
    def from_toml(cls, path: str | Path, read_surface: SurfaceReader | None = None) -> Case:
        """Read and validate a case file (TOML); ``read_surface`` as in :meth:`from_dict`."""
        with open(path, "rb") as handle:
            return cls.from_dict(tomllib.load(handle), read_surface)

    @classmethod
    def from_dict(cls, table: dict, read_surface: SurfaceReader | None = None) -> Case:
        """Validate a case table (see the README for the format) and build the case.

        ``read_surface`` reads the height-map files the bodies name (``bodyN.surface``):
        ``study.campaign.surfaces.read_surface``; without it such a case is refused.

        Raises
        ------
        SpecError
            If any field is missing, unknown, of the wrong type or non-physical.

        Notes
        -----
        Numpy scalars (``np.int64``, ``np.float32``, ``np.bool_``, ...) are taken as the Python
        values they hold; a list (a pair of numbers, ``grid.n``, ``output.fields``) may be given
        as a list, a tuple or a 1-D numpy array alike (the same case id), a file name as a
        string or a path, a roughness as its table or a :class:`~solver.bodies.heights.Roughness`; a
        boolean is never a number.
        """
        _check_keys(table, "", table_keys(""), required_keys(""))
        if table.get("model", MODEL_VERSION) != MODEL_VERSION:
            _fail(
                "model",
                f"this case was written by model version {table['model']!r}; this solver is "
                f"version {MODEL_VERSION}: remove the key to solve it with the current model",
            )
        body1 = _parse_body(table["body1"], "body1", read_surface)
        body2 = _parse_body(table["body2"], "body2", read_surface)
        if body1.rigid and body2.rigid:
            _fail("body2.behaviour", "both bodies are rigid; make at least one elastic")
        pair = Pair(body1, body2)
        kx, ky = pair.curvature
        geometry = pair.geometry
        if geometry.profiles:
            if kx != ky:
                which = "body1" if body1.profile is None else "body2"
                _fail(
                    f"{which}.radius_x",
                    "with a profile the pair must stay axisymmetric: give the other body a "
                    "radius (or none), not radius_x / radius_y",
                )
        elif kx > 0 or ky > 0 or not geometry.surfaces:
            if not (kx > 0 and ky > 0):
                _fail("body1.radius", "both bodies are flat in x or y; give a finite radius")
            if max(kx, ky) / min(kx, ky) > 100:
                _fail("body1.radius_x", "contact ellipse too slender (R_x/R_y beyond 1:100)")

        load = table["load"]
        if not isinstance(load, dict):
            _fail("load", "must be a table")
        if "path" in load:
            _check_keys(load, "load", {"path"})
            raw_stages = load["path"]
            if isinstance(raw_stages, tuple):  # a tuple of tables as a list (one spelling)
                raw_stages = list(raw_stages)
            if not isinstance(raw_stages, list) or not raw_stages:
                _fail("load.path", "must be a non-empty array of tables ([[load.path]])")
            stages, paths, given = _parse_path(raw_stages, pair)
        else:
            stage, spec = _parse_stage(load, "load", (0.0, (0.0, 0.0), False), pair, True)
            stages, paths, given = [stage], ["load"], [spec]

        friction = _check_keys(table.get("friction", {}), "friction", table_keys("friction"))
        mu = _number(friction.get("coefficient", 0.0), "friction.coefficient")
        if not 0 <= mu <= MAX_FRICTION:
            _fail(
                "friction.coefficient",
                f"must be in [0, {MAX_FRICTION:g}] (a contact sticks fully long before), got {mu}",
            )
        for stage, path in zip(stages, paths, strict=True):
            q = math.hypot(*stage.tangential_force)
            if q > 0 and q >= mu * stage.normal_force:
                _fail(
                    f"{path}.tangential_force",
                    f"|Q| = {q:g} N reaches mu W = {mu * stage.normal_force:g} N: gross sliding; "
                    "lower the tangential force or raise friction.coefficient",
                )

        grid = _parse_grid(table["grid"])
        if geometry.reference_kind is None:
            if grid.size is None:
                _fail(
                    "grid.size",
                    "no body has a smooth shape (radius or profile) whose contact radius could "
                    "scale the domain: give the domain's sides in metres, grid.size = [Lx, Ly]",
                )
            if grid.nz:
                _fail(
                    "grid.n",
                    "a volume grid is scaled by the smooth shape's contact radius; with heights "
                    "only give grid.n = [nx, ny] (no stress or plastic outputs yet)",
                )
            for stage, path in zip(stages, paths, strict=True):
                _check_mean_pressure(stage.normal_force, pair, grid.size, f"{path}.normal_force")
        moving = _slides(stages)
        if any(stage.motion == "slide" for stage in stages) and not body1.rigid:
            _fail(
                "body1.behaviour",
                "sliding takes a rigid body 1 in this release (an elastic body 1's surface "
                "moves with it: its displacements would have to follow the apex); make body 1 "
                "rigid, or roll",
            )
        rolls = any(stage.motion == "roll" for stage in stages)
        if rolls and (math.isfinite(body2.radius_x) or math.isfinite(body2.radius_y)):
            _fail(
                "body2.radius",
                "a rolling contact moves over body 2, whose curvature would stay where it is: "
                "give body 2 flat and body 1 the pair's radius (1/R = 1/R1 + 1/R2 along each "
                "axis), which the half-space contact sees alike",
            )
        for stage, path in zip(stages, paths, strict=True):
            if stage.creepage is not None and mu == 0.0 and (any(stage.creepage) or stage.spin):
                _fail(
                    f"{path}.creepage",
                    "friction.coefficient is 0: a frictionless contact has no creep force; "
                    "remove creepage and spin or give a friction coefficient",
                )
        _check_plastic_scene(body1, body2, stages, grid)
        plastics = [b for b in (body2, body1) if b.behaviour == "elastic-plastic"]
        plastic = plastics[0] if plastics else None
        force, e_star = max(stage.normal_force for stage in stages), pair.composite_modulus
        hertzian_plastic = plastics and geometry.hertzian  # else a profile (_check_plastic_scene)
        p_max = hertz(force, e_star, (kx, ky)).max_pressure if hertzian_plastic else math.nan
        ratio = max(  # unloaded stages carry no tangential force (checked above)
            (
                math.hypot(*st.tangential_force) / st.normal_force
                for st in stages
                if st.normal_force
            ),
            default=0.0,
        )
        # no window given: an elastic-plastic case's window holds its plastic box
        window_free = grid.size is None and "half_width" not in table["grid"] and not moving
        region = None  # a profile's computed elastic yield region (units of its contact radius)
        if plastic is not None and not geometry.hertzian:
            scale = _profile_radius(geometry, force, e_star)
            trial = grid
            while True:
                found = elastic_yield_region(
                    pair, _domain_half_widths(trial, scale), (grid.nx, grid.ny), force, ratio,
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
            _fail(
                "grid.plastic_half_width",
                "only an elastic-plastic body has a plastic box; leave the key out",
            )
        two_fields = len(plastics) == 2 and body1 != body2  # a volume grid each
        if grid.depth_body1 is not None and not two_fields:
            _fail(
                "grid.depth_body1",
                "only two different elastic-plastic bodies have a volume grid each; use grid.depth",
            )
        if two_fields and grid.depth_body1 is None:
            depth1 = grid.depth if grid.depth is not None else yield_depth(body1)
            grid = dataclasses.replace(grid, depth_body1=depth1)
        if grid.depth is None:
            depth = yield_depth(plastic) if plastic is not None else DEFAULT_DEPTH
            if plastic is not None and moving:
                depth *= MOVING_DEPTH_MARGIN / YIELD_DEPTH_MARGIN  # passes drive it deeper
            grid = dataclasses.replace(grid, depth=depth)
        box_key = None  # grid.plastic_half_width as the case's spec records it
        warnings = []
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
                if window_free:  # as wide as the zone asks and the cells resolve the contact
                    contact = hertz(force, e_star, (kx, ky)) if region is None else None
                    widest = resolved_half_width(grid, contact)
                    window = max(DEFAULT_HALF_WIDTH, min(zone, widest))
                    grid = dataclasses.replace(grid, half_width=window)
                    auto = grid.half_width
                if zone > grid.half_width or (window_free and zone >= MAX_AUTO_HALF_WIDTH):
                    warnings.append(narrow_window_note(grid, zone, window_free))
            chosen = grid.plastic_half_width
            if moving:  # the box covers the track: the window
                if chosen is not None:
                    _fail(
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
            given_key = next((f"grid.{k}" for k in keys if k in table["grid"]), "grid.n")
            if region is None:
                note = _plastic_regime(body, p_max, paths[peak], name)  # first: it may refuse
            else:
                note = _profile_regime(body, pair, scale, paths[peak], name)
            if note:
                warnings.append(note)
            depth = grid.depth_body1 if own else grid.depth
            _check_volume(body, depth, grid.nz, p_max, given_key, region)
        solver = _parse_solver(table.get("solver", {}))
        output = _check_keys(table.get("output", {}), "output", table_keys("output"))
        form = f"a list drawn from {list(FIELD_OUTPUTS)}"
        fields = [_plain(f) for f in _entries(output.get("fields", []), "output.fields", form)]
        if any(not isinstance(f, str) or f not in FIELD_OUTPUTS for f in fields):
            _fail("output.fields", f"must be a list drawn from {list(FIELD_OUTPUTS)}")
        if "stress" in fields and not grid.nz:
            _fail("output.fields", "stress needs a volume grid: give grid.n = [nx, ny, nz]")
        if "stress" in fields and plastic is body1 and body1 != body2:
            _fail(
                "output.fields",
                "stress is computed in body 2; with an elastic-plastic body 1 the volume is body "
                "1's: request residual_stress or plastic_strain_tensor instead",
            )
        if "stress" in fields and body2.rigid:
            _fail("output.fields", "stress is computed in body 2, which is rigid here")
        for name in ("plastic_strain_tensor", "residual_stress"):
            if name in fields and plastic is None:
                _fail("output.fields", f"{name} needs an elastic-plastic body")

        spec = {
            "model": MODEL_VERSION,
            "body1": _body_spec(body1),
            "body2": _body_spec(body2),
            "load": {"path": given},
            "friction": {"coefficient": mu},
            "grid": {
                "n": [grid.nx, grid.ny] + ([grid.nz] if grid.nz else []),
                **({"size": list(grid.size)} if grid.size else {"half_width": grid.half_width}),
                **({"depth": grid.depth} if grid.nz else {}),
                **({"depth_body1": grid.depth_body1} if grid.depth_body1 else {}),
                **({"plastic_half_width": box_key} if box_key is not None else {}),
                **({"follow_contact": grid.follow_contact} if moving else {}),
            },
            # FFT threads and planner are kept (a campaign's cases are solved from this table)
            # but change no result beyond round-off: not in the case id (EXECUTION_KEYS); the
            # volume precision only when single (the ids of double cases stay as they were)
            "solver": {
                k: _json_number(getattr(solver, k))
                for k in _SOLVER_RULES
                if k != "volume_precision" or solver.volume_precision != "double"
            },
            "output": {"fields": sorted(fields)},
        }
        case = cls(
            body1, body2, tuple(stages), mu, grid, solver, tuple(sorted(fields)), spec,
            tuple(warnings),
        )  # fmt: skip
        case._check_resolution()
        case._check_surfaces()
        notes = (case._layer_note(), case._surface_shear_note(), case._window_note())
        notes = tuple(filter(None, notes))
        if notes:
            case = dataclasses.replace(case, warnings=(*case.warnings, *notes))
        for stage, path in zip(stages, paths, strict=True):
            reach = abs(stage.spin) * case.reference.max_semi_axis if stage.spin else 0.0
            if reach > MAX_CREEPAGE:  # the spin's rigid slip at the contact's edge
                _fail(
                    f"{path}.spin",
                    f"the spin's rigid slip at the contact's edge, |spin| a = {reach:.3g}, "
                    f"must be within {MAX_CREEPAGE:g} like a creepage (a = "
                    f"{case.reference.max_semi_axis:.4g} m), got spin = {stage.spin:g} 1/m",
                )
        return case

    @property
    def symmetric_plastic(self) -> bool:
        """True for the symmetric elastic-plastic pair (seed eq. 2): identical bodies."""
        return self.body1.behaviour == "elastic-plastic" and self.body1 == self.body2

    @property
    def plastic_body(self) -> Body | None:
        """The elastic-plastic body whose plastic strain is computed, or None."""
        for body in (self.body2, self.body1):
            if body.behaviour == "elastic-plastic":
                return body
        return None

    @property
    def plastic_body1(self) -> bool:
        """True when body 1 alone is elastic-plastic: solved as :meth:`swapped`."""
        return self.body1.behaviour == "elastic-plastic" and self.body2.behaviour != (
            "elastic-plastic"
        )

    @property
    def plastic_bodies(self) -> tuple[int, ...]:
        """Bodies with a plastic strain field of their own: (2,), (2, 1) or ().

        (2, 1) for two different elastic-plastic bodies; the symmetric pair has one field
        (body 2's), and an elastic-plastic body 1 alone is solved as body 2 of :meth:`swapped`.
        """
        if self.body2.behaviour != "elastic-plastic":
            return (2,) if self.plastic_body1 else ()
        if self.body1.behaviour == "elastic-plastic" and not self.symmetric_plastic:
            return (2, 1)
        return (2,)

    def swapped(self) -> Case:
        """The same contact with the bodies relabelled (body 1 <-> body 2).

        Body 1's frame is body 2's turned by 180 degrees about x: (x, -y, -z).  A tangential
        force (Q_x, Q_y) on body 2 is (-Q_x, -Q_y) on body 1 in the common frame, so
        (-Q_x, Q_y) in its own; the surface fields mirror in y (:mod:`solver.variables`,
        ``swap_sign``).  The swapped case of the swapped case is the case itself.
        """
        table = self.to_dict()
        table["body1"], table["body2"] = table["body2"], table["body1"]
        path = table["load"]["path"]
        stages = [s for e in path for s in (e["stages"] if "cycles" in e else [e])]
        for stage in stages:
            if "tangential_force" in stage:
                qx, qy = stage["tangential_force"]
                stage["tangential_force"] = [-qx if qx else 0.0, qy]
        if any("roll" in stage for stage in stages):
            _swap_rolling(table, stages)
        return Case.from_dict(table)

    def _check_surfaces(self) -> None:
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
        grid = self.surface_grid
        hx, hy = 0.5 * grid.nx * grid.dx, 0.5 * grid.ny * grid.dy
        cell = max(grid.dx, grid.dy)
        for name, body in (("body1", self.body1), ("body2", self.body2)):
            surface = body.surface
            if surface is not None:
                where, file = f"{name}.surface", surface.source
                x0, x1, y0, y1 = surface.extent
                tol = 1e-9 * cell
                if (
                    x0 > grid.x[0] + tol
                    or x1 < grid.x[-1] - tol
                    or (y0 > grid.y[0] + tol or y1 < grid.y[-1] - tol)
                ):
                    _fail(
                        where,
                        f"{file} covers x in [{x0:.4g}, {x1:.4g}] m, y in [{y0:.4g}, {y1:.4g}] "
                        f"m, smaller than the domain's cell centres (x, y within +-"
                        f"{hx - 0.5 * grid.dx:.4g}, +-{hy - 0.5 * grid.dy:.4g} m); give a "
                        "larger map or a smaller domain (grid.size or half_width)",
                    )
                spacing = max(surface.dx, surface.dy)
                if spacing > MAX_MAP_COARSENING * cell:
                    _fail(
                        where,
                        f"{file} is too coarse for the grid: its spacing {spacing:.4g} m is "
                        f"more than {MAX_MAP_COARSENING:g} cells ({cell:.4g} m); use a finer "
                        "map or a coarser grid",
                    )
                relief = float(np.ptp(surface.height))
                if relief > 2 * max(hx, hy):
                    _fail(
                        where,
                        f"{file} has heights spanning {relief:.4g} m, more than the domain "
                        f"({2 * max(hx, hy):.4g} m): are they in metres (micrometres written as "
                        "metres)?  Heights are in metres",
                    )
                slope = _map_slope(surface, grid)
                if slope > MAX_SURFACE_SLOPE:
                    _fail(
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
                if roughness.short_cutoff < 2 * cell:
                    _fail(
                        f"{where}.short_cutoff",
                        f"{roughness.short_cutoff:.4g} m is shorter than 2 cells "
                        f"({2 * cell:.4g} m): the grid cannot carry it; raise short_cutoff or "
                        "refine the grid",
                    )
                if roughness.rms is not None and roughness.rms > 2 * max(hx, hy):
                    _fail(
                        f"{where}.rms",
                        f"{roughness.rms:.4g} m is larger than the domain "
                        f"({2 * max(hx, hy):.4g} m): is it in metres?",
                    )
                points, _ = roughness.lattice(2 * max(hx, hy))
                if points > MAX_ROUGHNESS_LATTICE:
                    _fail(
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
                        slope = roughness.realised_rms_slope(side)
                    except SurfaceError as error:
                        _fail(where, str(error))
                    if slope > MAX_SURFACE_SLOPE:
                        largest = _round_down(roughness.rms * MAX_SURFACE_SLOPE / slope)
                        _fail(
                            f"{where}.rms",
                            f"rms = {roughness.rms:.4g} m gives a realisation of rms slope "
                            f"{_above(slope)} (spectral, on its lattice), more than "
                            f"{MAX_SURFACE_SLOPE:g} (small-slope theory): give rms <= "
                            f"{largest} m, or rms_slope <= {MAX_SURFACE_SLOPE:g} instead of rms",
                        )

    def _check_resolution(self) -> None:
        reference = self.reference
        if reference is None:  # heights only: the contact's size is known after the solve
            return
        semi_min = min(reference.semi_axis_x, reference.semi_axis_y)
        half_x, half_y = self.domain_half_widths
        if self.moving and self.grid.size is not None:
            (x0, x1), (y0, y1) = self.track
            if half_x < 0.5 * (x1 - x0) + 1.05 * reference.semi_axis_x or (
                half_y < 0.5 * (y1 - y0) + 1.05 * reference.semi_axis_y
            ):
                _fail(
                    "grid.size",
                    f"the window ({2 * half_x:.4g} m by {2 * half_y:.4g} m) does not hold the "
                    f"contact along the track (x from {x0:.4g} to {x1:.4g} m, y from {y0:.4g} "
                    f"to {y1:.4g} m, contact radius {reference.max_semi_axis:.4g} m): enlarge "
                    "grid.size or leave it out (the window then covers the track)",
                )
        if half_x < 1.05 * reference.semi_axis_x or half_y < 1.05 * reference.semi_axis_y:
            _fail(
                "grid.half_width",
                f"domain cannot hold the contact: half_width = {self.grid.half_width:g} a_H; "
                "use half_width >= 1.1 (1.5 recommended)",
            )
        surface = self.surface_grid
        across = 2 * semi_min / max(surface.dx, surface.dy)
        if not across >= MIN_CELLS_ACROSS:
            # square cells of side 2 half_width a_max / n: across = n semi_min / (half_width a_max)
            n_max = max(self.grid.nx, self.grid.ny)
            need = MIN_CELLS_ACROSS * n_max / across if across > 0 else math.inf
            if self.moving and self.grid.size is None:  # the track sets the window
                (x0, x1), (y0, y1) = self.track
                key = "slide" if any(st.motion == "slide" for st in self.stages) else "roll"
                moving = {"slide": "sliding", "roll": "rolling"}[key]
                cell = 2 * semi_min / MIN_CELLS_ACROSS  # the largest cell that resolves it
                half = self.grid.half_width * reference.max_semi_axis
                counts = [math.ceil((2 * half + hi - lo) / cell) for lo, hi in ((x0, x1), (y0, y1))]
                _fail(
                    f"load.path ({key})",
                    f"mesh too coarse for the {moving} track ({x1 - x0:.4g} m along x, "
                    f"{y1 - y0:.4g} m along y, contact radius {semi_min:.4g} m): the contact "
                    f"spans {across:.3g} cells of the window over the track; shorten the "
                    f"{key}s or give more cells (n = {counts} or more, at most {MAX_CELLS} a side)",
                )
            if need <= MAX_CELLS:
                window = f"{self.grid.half_width:g} a_H"
                if self.plastic_body is not None:  # the window may have grown to hold the box
                    window += ", which holds the plastic box when half_width is not given"
                _fail(
                    "grid.n",
                    f"mesh too coarse: the contact spans {across:.3g} cells of the window "
                    f"({window}); use n >= {math.ceil(need)} (or a smaller half_width)",
                )
            scale = semi_min / (MIN_CELLS_ACROSS * reference.max_semi_axis)
            at_n = ""
            if n_max < MAX_CELLS and scale * n_max >= 1.1:
                at_n = f" (<= {scale * n_max:.4g} at n = {n_max})"
            need_text = str(math.ceil(need)) if need < 1e15 else f"{need:.3g}"
            _fail(
                "grid.half_width",
                f"mesh too coarse: the contact spans {across:.4g} cells and would need "
                f"n >= {need_text}, beyond the largest grid n = {MAX_CELLS}; reduce half_width "
                f"to <= {scale * MAX_CELLS:.4g} with n = {MAX_CELLS}{at_n} (1.5 recommended)",
            )

    # -- derived quantities ------------------------------------------------------------------
    @property
    def pair(self) -> Pair:
        """The two bodies."""
        return Pair(self.body1, self.body2)

    @property
    def max_normal_force(self) -> float:
        """Largest normal force along the load path (N)."""
        return max(stage.normal_force for stage in self.stages)

    @functools.cached_property
    def reference(self) -> HertzContact | SneddonContact | None:
        """The closed-form elastic contact at the largest normal force (computed once).

        Hertz's for quadric bodies, Sneddon's for a profile (:meth:`Geometry.reference`), of
        the smooth shape only under point heights (a first estimate); None for heights only.
        Its semi-axes scale the domain (``grid.half_width``) and the volume depth.
        """
        pair = self.pair
        if pair.geometry.reference_kind is None:
            return None
        return pair.geometry.reference(self.max_normal_force, pair.composite_modulus)

    @property
    def hertz(self) -> HertzContact:
        """Hertz reference at the largest normal force of the path (quadric bodies only)."""
        if not self.pair.geometry.hertzian:
            raise ValueError("a case with a profile has no Hertz reference; use Case.reference")
        return self.reference

    @property
    def domain_half_widths(self) -> tuple[float, float]:
        """Half-widths (m) of the surface domain along x and y (square cells)."""
        scale = self.reference.max_semi_axis if self.grid.size is None else math.nan
        if self.grid.size is not None or not self.moving:
            return _domain_half_widths(self.grid, scale)
        # the window covers the contact (half_width around it) at every position of the path
        half = self.grid.half_width * scale
        (x0, x1), (y0, y1) = self.track
        cell = max((2 * half + x1 - x0) / self.grid.nx, (2 * half + y1 - y0) / self.grid.ny)
        return 0.5 * cell * self.grid.nx, 0.5 * cell * self.grid.ny

    @property
    def surface_grid(self) -> SurfaceGrid:
        """The surface grid, centred on :attr:`window_centre`."""
        hx, hy = self.domain_half_widths
        return SurfaceGrid.centred(self.grid.nx, self.grid.ny, hx, hy, self.window_centre)

    @property
    def volume_grid(self) -> VolumeGrid | None:
        """The volume grid below the surface (in body 2), or None when nz = 0."""
        return self.volume_grid_of(2)

    @property
    def plastic_box(self) -> IndexBox | None:
        """Cells of the plastic box in the volume grid, or None for the whole window.

        Centred on the axis (the same cells in body 1's mirrored frame): the fewest cells with
        the window's parity that cover ``[-w, w]`` along x and y, ``w`` =
        ``grid.plastic_half_width`` x the largest Hertz semi-axis, and whose padded length
        (twice as many) is a fast FFT size (:func:`~solver.numerics.fftw.fft_size`); every
        layer.  None when that is the whole window.
        """
        if self.grid.plastic_half_width is None or not self.grid.nz:
            return None
        half = self.grid.plastic_half_width * self.reference.max_semi_axis
        surface = self.surface_grid
        ranges = []
        for n, d in ((surface.nx, surface.dx), (surface.ny, surface.dy)):
            cells = min(n, math.ceil(2 * half / d - 1e-9))
            cells += (n - cells) % 2  # centred: as many cells left as right
            while cells < n and fft_size(2 * cells) != 2 * cells:
                cells += 2
            ranges.append(((n - cells) // 2, (n + cells) // 2))
        if ranges == [(0, surface.nx), (0, surface.ny)]:
            return None
        return IndexBox(ranges[0], ranges[1], (0, self.grid.nz))

    def _layer_note(self) -> str | None:
        """A note for a perfectly plastic body on layers thicker than :data:`MAX_PERFECT_LAYER`.

        The cell-centre residual stress of a cell-wise eigenstrain is not negative definite:
        checkerboard patterns have a negative Rayleigh quotient (-0.20 for xx - zz alternating
        in x and z on cubic cells, +0.24 with layers half a cell thick; -0.20 for xx - yy
        alternating in x and y at any thickness), which nothing but hardening holds back.  On
        cubic cells a perfectly plastic pass stalled and strayed (ep_max 0.0088 against 0.0045
        at 16 cells across, 2026-11-26); layers of 0.62 cell and thinner gave 0.0045 every time.
        """
        body = self.plastic_body
        if body is None or self.volume_grid is None:
            return None
        hardening = body.hardening
        if hardening.law != "perfect" or hardening.kinematic:
            return None
        ratio = self.volume_grid.dz / min(self.surface_grid.dx, self.surface_grid.dy)
        if ratio <= MAX_PERFECT_LAYER:
            return None
        nz = math.ceil(self.grid.nz * ratio / MAX_PERFECT_LAYER)
        return (
            f"layers {ratio:.2g} of a cell thick (dz / dx) under a perfectly plastic body: on "
            f"such cells its plasticity loop can stall and its plastic strain stray (a cell-wise "
            f"eigenstrain's checkerboard patterns can release elastic energy there); give "
            f"grid.n = [nx, ny, nz] with nz >= {nz} (layers <= {MAX_PERFECT_LAYER:g} cell)"
        )

    def _surface_shear_note(self) -> str | None:
        """A note when a slide's shear mu p_0 exceeds what the plastic body can carry.

        A body whose flow stress is bounded (:attr:`Hardening.shear_limit`) cannot carry a
        surface shear traction above that limit: no stress field in equilibrium with it stays
        inside the yield surface, so the top layer's plastic strain is set by the layers (it
        grows as they thin) and the plasticity loop may not converge.  Said at Hertz's peak
        pressure of the largest load (plastic flow flattens the pressure, which may bring the
        shear back under the limit).
        """
        body, reference = self.plastic_body, self.reference
        mu = self.friction_coefficient
        if body is None or reference is None or not mu:
            return None
        if not any(stage.motion == "slide" for stage in self.stages):
            return None
        limit = body.hardening.shear_limit
        ratio = mu * reference.max_pressure / limit
        if ratio <= 1.0 + 1e-9:  # at the limit to rounding (mu = 0.5, p_0 = 2 k) is not past it
            return None
        return (
            f"the sliding shear mu p_0 = {ratio:.3g} x {limit / 1e6:.4g} MPa, the largest "
            f"shear stress the elastic-plastic body can carry (sigma_Y / sqrt 3 without "
            f"hardening): where the pressure stays that high no stress field in equilibrium "
            f"with the surface shear stays within yield, the top layer's plastic strain is set "
            f"by grid.nz and the plasticity loop may not converge; lower the load or "
            f"friction.coefficient below p_0 = {limit / mu / 1e6:.4g} MPa, or give the body "
            f"hardening"
        )

    def _window_unbuilt(self) -> list[str]:
        """What keeps a moving case off the window that follows the contact (none: it fits)."""
        bodies = (self.body1, self.body2)
        return [
            reason
            for reason, applies in (
                ("a given grid.size", self.grid.size is not None),
                (
                    "a height map or roughness",
                    any(b.surface is not None or b.roughness is not None for b in bodies),
                ),
                ("two elastic-plastic bodies", self.plastic_bodies not in ((), (2,))),
            )
            if applies
        ]

    def _window_note(self) -> str | None:
        """A note when a moving case asks for the window but is solved on the whole track."""
        if not self.moving or not self.grid.follow_contact:
            return None
        reasons = self._window_unbuilt()
        if not reasons:
            return None
        return (
            "every increment is solved on the whole track, not on a window that follows the "
            f"contact ({', '.join(reasons)}: the window is not built for them): the same "
            "answer, slower"
        )

    @property
    def moving_window(self) -> tuple[int, int] | None:
        """Cells (nx, ny) of the window that follows a moving contact, or None: the whole track.

        ``grid.half_width`` times the largest Hertz semi-axis on every side of the contact plus
        the travel of the longest step that starts or ends loaded (the window holds the
        contact at both ends of an increment), plus a cell for the snapping to whole cells,
        each side's cell count rounded up to a fast FFT size of the track's parity.  None
        (every increment on the whole track's window) without a moving load, with
        ``grid.follow_contact = false``, a given ``grid.size``, a height map or roughness, or
        two elastic-plastic bodies, and when the window would be the track's along both axes.
        """
        if not self.moving or not self.grid.follow_contact or self._window_unbuilt():
            return None
        travel = [0.0, 0.0]
        force = 0.0
        for stage in self.stages:
            if stage.steps and (force > 0.0 or stage.normal_force > 0.0):
                for axis in (0, 1):
                    travel[axis] = max(travel[axis], abs(stage.travel[axis]) / stage.steps)
            force = stage.normal_force
        surface = self.surface_grid
        half = self.grid.half_width * self.reference.max_semi_axis
        cells = []
        along = ((surface.nx, surface.dx, travel[0]), (surface.ny, surface.dy, travel[1]))
        for n, d, length in along:
            count = math.ceil((2.0 * half + length) / d - 1e-9) + 2
            # the track's parity: a window placed as far left as its mirror is right
            while count < n and (fft_size(2 * count) != 2 * count or (n - count) % 2):
                count += 1
            cells.append(min(n, count))
        if cells == [surface.nx, surface.ny]:
            return None
        return cells[0], cells[1]

    def volume_grid_of(self, body: int) -> VolumeGrid | None:
        """The volume grid of body ``body`` (1 or 2).

        Body 1 has its own only with two different elastic-plastic bodies
        (``grid.depth_body1``); else it is body 2's.
        """
        if not self.grid.nz:
            return None
        depth = self.grid.depth_body1 if body == 1 and self.grid.depth_body1 else self.grid.depth
        depth *= self.reference.max_semi_axis
        return VolumeGrid(self.surface_grid, self.grid.nz, depth / self.grid.nz)

    @property
    def total_steps(self) -> int:
        """Number of load increments over the whole path."""
        return sum(stage.steps for stage in self.stages)

    def step_targets(self) -> Iterator[tuple[float, float, float, float, float]]:
        """(W, Q_x, Q_y, p_x, p_y) at the end of every load increment, in order, one at a time.

        W, Q (N); p (m): body 1's apex over body 2 (``slide`` stages move it).  A generator
        (the path is never held whole): :attr:`total_steps` counts it.
        """
        w0, (qx0, qy0), (px0, py0) = 0.0, (0.0, 0.0), (0.0, 0.0)
        for stage in self.stages:
            w1, (qx1, qy1) = stage.normal_force, stage.tangential_force
            px1, py1 = px0 + stage.travel[0], py0 + stage.travel[1]
            for k in range(1, stage.steps + 1):
                f = k / stage.steps
                yield (
                    w0 + f * (w1 - w0), qx0 + f * (qx1 - qx0), qy0 + f * (qy1 - qy0),
                    px0 + f * (px1 - px0), py0 + f * (py1 - py0),
                )  # fmt: skip
            w0, qx0, qy0, px0, py0 = w1, qx1, qy1, px1, py1

    def increment_stages(self) -> Iterator[LoadStage]:
        """The stage of every load increment, in order (as :meth:`step_targets`)."""
        for stage in self.stages:
            for _ in range(stage.steps):
                yield stage

    @property
    def track(self) -> tuple[tuple[float, float], tuple[float, float]]:
        """((x_min, x_max), (y_min, y_max)) (m): the range of body 1's apex over the path.

        The origin (the apex at the start) is in it; without sliding it is that point alone.
        """
        px = py = 0.0
        xs, ys = [0.0], [0.0]
        for stage in self.stages:
            px, py = px + stage.travel[0], py + stage.travel[1]
            xs.append(px)
            ys.append(py)
        return (min(xs), max(xs)), (min(ys), max(ys))

    @property
    def window_centre(self) -> tuple[float, float]:
        """Centre (m) of the surface window: the origin, or the middle of a sliding track."""
        (x0, x1), (y0, y1) = self.track
        return 0.5 * (x0 + x1), 0.5 * (y0 + y1)

    @property
    def moving(self) -> bool:
        """True when a stage slides body 1 over body 2."""
        return _slides(self.stages)

    def step_cycles(self) -> np.ndarray:
        """Load cycle of every increment (:attr:`LoadStage.cycle`: 0 outside a cycle block)."""
        return np.repeat([stage.cycle for stage in self.stages], [s.steps for s in self.stages])

    @property
    def cycles(self) -> int:
        """Number of load cycles of the path (0 without a cycle block)."""
        return max(stage.cycle for stage in self.stages)

    @property
    def has_tangential_load(self) -> bool:
        """True when any stage prescribes a tangential force or rolls at given creepages."""
        return any(
            any(stage.tangential_force) or stage.creepage is not None for stage in self.stages
        )

    @property
    def case_id(self) -> str:
        """Content hash of the normalised specification (16 hex digits).

        Without :data:`EXECUTION_KEYS`, which change no result beyond round-off.
        """
        spec = json.loads(json.dumps(self.spec))
        spec["solver"] = {k: v for k, v in spec["solver"].items() if k not in EXECUTION_KEYS}
        for body in ("body1", "body2"):  # a map is its content, wherever its file lies
            for key in ("file", "case"):
                spec[body].get("surface", {}).pop(key, None)
        text = json.dumps(spec, sort_keys=True, separators=(",", ":"))
        return hashlib.sha256(text.encode()).hexdigest()[:16]

    def to_dict(self) -> dict:
        """The normalised case table (a deep copy); ``Case.from_dict(c.to_dict()) == c``."""
        return json.loads(json.dumps(self.spec))


def _map_slope(surface: HeightMap, grid: SurfaceGrid) -> float:
    """Rms slope of a map resampled onto a grid (:func:`~solver.bodies.heights.grid_rms_slope`).

    Memoised: a campaign's cases often share a map and a grid.
    """
    return grid_rms_slope(surface, grid.x, grid.y)


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


def _domain_half_widths(grid: GridSpec, scale: float) -> tuple[float, float]:
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


def _slides(stages) -> bool:
    """True when a stage moves body 1 over body 2 (a ``slide``)."""
    return any(any(stage.travel) for stage in stages)


def _swap_rolling(table: dict, stages: list[dict]) -> None:
    """A rolling case's table told in body 1's frame (x, -y, -z), in place (:meth:`Case.swapped`).

    Under a rolling contact the surface material of both bodies stands still in body 2's frame
    (Kalker's transient theory), so the bodies may change roles: the travel over body 1 is the
    travel over body 2, ``(dx, -dy)`` in body 1's frame; the rigid slip of the other body is
    the opposite, ``(xi, eta) -> (-xi, eta)`` with the y flip, and the spin (the rotation about
    z, which turns too) keeps its value.  The pair's curvature stays on body 1, the body the
    contact moves with (the half-space contact sees the pair's 1/R alike).
    """
    keys = ("radius", "radius_x", "radius_y")
    shapes = [{k: table[b].pop(k) for k in keys if k in table[b]} for b in ("body2", "body1")]
    table["body1"].update(shapes[0])  # the swapped-in body 2 holds body 1's former shape
    table["body2"].update(shapes[1])
    for stage in stages:
        if "roll" in stage:
            dx, dy = stage["roll"]
            stage["roll"] = [dx, -dy if dy else 0.0]
        if "creepage" in stage:
            xi, eta = stage["creepage"]
            stage["creepage"] = [-xi if xi else 0.0, eta]


def _check_plastic_scene(body1: Body, body2: Body, stages, grid: GridSpec) -> None:
    """Refuse the elastic-plastic scenes this release cannot solve (no silent elastic answer).

    Solved: one elastic-plastic body against a rigid or elastic one (frictionless: the
    plasticity loop around the normal step; with friction or a tangential load: the four
    loops; an elastic-plastic body 1 is solved with the bodies relabelled, :meth:`Case.swapped`),
    two different elastic-plastic bodies (a plastic strain field in each), and the symmetric
    pair (eq. 2) under normal load with any friction.
    """
    plastic1 = body1.behaviour == "elastic-plastic"
    plastic2 = body2.behaviour == "elastic-plastic"
    symmetric = plastic1 and body1 == body2
    if not (plastic1 or plastic2):
        return
    profiled = body1.profile is not None or body2.profile is not None
    if profiled and (plastic1 or not plastic2):
        _fail(
            "body1.behaviour",
            "with a profile, only body 2 may be elastic-plastic in this release (its box is "
            "sized from the computed elastic yield region in body 2); make body 1 rigid or "
            "elastic",
        )
    if profiled and any(b.surface or b.roughness for b in (body1, body2)):
        _fail(
            "body2.behaviour",
            "an elastic-plastic case with a profile takes no height map or roughness yet: its "
            "box is sized from the profile's elastic stress; drop one of them",
        )
    if (
        plastic1
        and not plastic2
        and (body1.surface or body1.roughness or body2.surface or body2.roughness)
    ):
        _fail(
            "body1.behaviour",
            "an elastic-plastic body 1 against an elastic or rigid body 2 is solved with the "
            "bodies relabelled, which mirrors point heights: not built yet; make the "
            "elastic-plastic body body 2",
        )
    if Pair(body1, body2).geometry.reference_kind is None:
        _fail(
            "body1.radius",
            "an elastic-plastic case needs a radius (a quadric shape under the heights): the "
            "volume depth and the plastic box are sized from the Hertz stress of the smooth "
            "shape",
        )
    if symmetric and any(
        any(stage.tangential_force) or any(stage.travel) or stage.creepage is not None
        for stage in stages
    ):
        _fail(
            "load.tangential_force",
            "a tangential load breaks the symmetry of the elastic-plastic pair (eq. 2); make "
            "one body elastic or rigid to run the four loops, or remove tangential_force",
        )
    if not grid.nz:
        _fail(
            "grid.n",
            "an elastic-plastic body needs a volume grid: give grid.n = [nx, ny, nz] "
            "(e.g. [64, 64, 64])",
        )


def _parse_grid(table: Any) -> GridSpec:
    """Parse ``[grid]``: ``n`` (nx = ny), ``[nx, ny]`` or ``[nx, ny, nz]``, and ``nz``.

    ``nz`` (the volume grid's cells in depth) may be given apart from a 1- or 2-entry ``n``,
    not as well as a 3-entry one.
    """
    _check_keys(table, "grid", table_keys("grid"), required_keys("grid"))
    n = _entries(
        table["n"], "grid.n", "an integer or [nx, ny] or [nx, ny, nz]", (2, 3), scalar=True
    )
    if isinstance(n, list):
        sizes = [_integer(v, "grid.n", 4, MAX_CELLS) for v in n]
    else:
        size = _integer(n, "grid.n", 4, MAX_CELLS)
        sizes = [size, size]
    if "nz" in table:
        if len(sizes) == 3:
            _fail(
                "grid.nz",
                f"grid.n = {n!r} already gives nz; give either grid.n = [nx, ny, nz] or "
                "grid.n with grid.nz, not both",
            )
        sizes.append(_integer(table["nz"], "grid.nz", 4, MAX_CELLS))
    nz = sizes[2] if len(sizes) == 3 else 0
    half_width = _number(
        table.get("half_width", DEFAULT_HALF_WIDTH), "grid.half_width", positive=True
    )
    size = None
    if "size" in table:
        if "half_width" in table:
            _fail("grid.size", "give either size (m) or half_width (units of a_H), not both")
        value = _entries(table["size"], "grid.size", "L or [Lx, Ly] (m)", (2,), scalar=True)
        items = value if isinstance(value, list) else [value, value]
        size = tuple(_number(v, "grid.size", positive=True) for v in items)
        if not math.isclose(size[0] / sizes[0], size[1] / sizes[1], rel_tol=1e-9):
            _fail(
                "grid.size",
                f"cells must be square: Lx/nx = {size[0] / sizes[0]:.6g} m but Ly/ny = "
                f"{size[1] / sizes[1]:.6g} m; make [Lx, Ly] proportional to [nx, ny]",
            )
    depths = {}
    for key in ("depth", "depth_body1"):
        if key in table:
            depths[key] = _number(table[key], f"grid.{key}", positive=True)
            low, high = DEPTH_RANGE
            if not low <= depths[key] <= high:
                _fail(
                    f"grid.{key}",
                    f"must be in [{low:g}, {high:g}] (units of the Hertz radius a_H), got "
                    f"{depths[key]:g}; leave it out to size the box from the yield region",
                )
    if "depth" in table and not nz:
        _fail("grid.depth", "a depth needs a volume grid: give grid.n = [nx, ny, nz]")
    plastic_half_width = None
    if "plastic_half_width" in table:
        plastic_half_width = _number(
            table["plastic_half_width"], "grid.plastic_half_width", positive=True
        )
        if not MIN_PLASTIC_HALF_WIDTH <= plastic_half_width <= half_width:
            _fail(
                "grid.plastic_half_width",
                f"must be in [{MIN_PLASTIC_HALF_WIDTH:g}, half_width = {half_width:g}] (units of "
                f"the Hertz radius a_H), got {plastic_half_width:g}; leave it out for a box sized "
                "from the yield region, or give half_width for the whole window",
            )
    follow = _plain(table.get("follow_contact", True))
    if not isinstance(follow, bool):
        _fail("grid.follow_contact", f"must be true or false, got {follow!r}")
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
    )


def _check_volume(
    body: Body, depth: float, nz: int, max_pressure: float, path: str, region=None
) -> None:
    """Refuse a plastic body's volume grid that cannot resolve its yield region.

    ``depth`` in units of a_H.  Cells at most :data:`MAX_CELL_DEPTH` thick: the Hertz von
    Mises stress peaks at 0.48 a_H, and half-a_H cells gave no plastic strain at all
    (p_H = 1.8 sigma_Y) or 40 % too little (2.9 sigma_Y).  With the frictionless Hertz yield
    region on the axis at the maximum load (:func:`~solver.theory.reference.hertz_yield_region`),
    the box must reach the depth where plasticity starts (a shallower one gives an elastic
    answer), and the region inside the box must span :data:`MIN_YIELD_CELLS` cells.  ``region``
    (top, bottom, half width, in units of the contact radius): a profile's computed region
    (:func:`~solver.spec.sizing.elastic_yield_region`) instead of Hertz's.
    """
    nu, sigma = body.nu, body.hardening.initial_yield_stress
    cell = depth / nz
    thick = f"cells {cell:.3g} a_H thick (depth {depth:g} a_H over nz = {nz})"
    if cell > MAX_CELL_DEPTH:
        _fail(
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
        _fail(
            path,
            f"the box ends at {depth:g} a_H, above the depth {start:.3g} a_H where plasticity "
            f"starts ({region}): use depth >= {bottom:.3g}, or leave it out (sized "
            "from the yield region)",
        )
    span = min(bottom, depth) - top
    if span < MIN_YIELD_CELLS * cell:
        _fail(
            path,
            f"{thick} are too coarse for the yield region ({region}: {span / cell:.2g} "
            f"cells, at least {MIN_YIELD_CELLS} needed): use "
            f"nz >= {math.ceil(MIN_YIELD_CELLS * depth / span)}",
        )


def plastic_index(body: Body, max_pressure: float) -> float:
    """Johnson's index E* a / (R sigma_Y) of an elastic-plastic body at a Hertz pressure.

    Hertz's a / R = pi p_0 / (2 E*) makes it ``pi p_0 / (2 sigma_Y)``; sigma_Y is the flow
    stress at :data:`SMALL_STRAIN_LIMIT` (the hardening the small-strain range can use).
    Johnson (1985, §6.4): first yield at ~2.5 (p_0 = 1.6 sigma_Y), a fully plastic
    indentation at ~30.
    """
    sigma = float(body.hardening.flow_stress(SMALL_STRAIN_LIMIT))
    return math.pi * max_pressure / (2.0 * sigma)


def _profile_regime(body: Body, pair: Pair, radius: float, path: str, name: str) -> str | None:
    """:func:`_plastic_regime` for a profile: Johnson's index from the slope at the contact edge."""
    sigma = float(body.hardening.flow_stress(SMALL_STRAIN_LIMIT))
    index = slope_index(pair, radius, sigma)
    told = (
        f"Johnson's index E* f'(a)/sigma_Y = {index:.3g} for {name} (the gap's slope f'(a) at "
        f"Sneddon's contact radius a = {radius:.4g} m, sigma_Y = {sigma:.4g} Pa at e_p = "
        f"{SMALL_STRAIN_LIMIT:g})"
    )
    return _regime_note(index, told, path, "lower the load or blunt the profile")


def _plastic_regime(body: Body, max_pressure: float, path: str, name: str) -> str | None:
    """Refuse a fully plastic indentation; a note (returned) past the contained regime."""
    index = plastic_index(body, max_pressure)
    sigma = float(body.hardening.flow_stress(SMALL_STRAIN_LIMIT))
    told = (
        f"Johnson's index E* a/(R sigma_Y) = pi p_H/(2 sigma_Y) = {index:.3g} for {name} "
        f"(p_H = {max_pressure:.4g} Pa, sigma_Y = {sigma:.4g} Pa at e_p = "
        f"{SMALL_STRAIN_LIMIT:g})"
    )
    lower = f"lower the load to p_H < {FULLY_PLASTIC_INDEX * 2 * sigma / math.pi:.4g} Pa"
    return _regime_note(index, told, path, lower)


def _regime_note(index: float, told: str, path: str, lower: str) -> str | None:
    """Refuse a fully plastic index; a note past the contained regime; None below."""
    if index >= FULLY_PLASTIC_INDEX:
        _fail(
            path,
            f"{told} reaches {FULLY_PLASTIC_INDEX:g}, a fully plastic indentation (Johnson 1985, "
            f"§6.4): plastic strains of tens of %, beyond the small-strain theory; {lower}",
        )
    if index > UNCONTAINED_PLASTIC_INDEX:
        return (
            f"{told} is past {UNCONTAINED_PLASTIC_INDEX:g}: the plastic zone is no longer "
            "contained (mean pressure near 3 sigma_Y), plastic strains reach several %, the "
            "edge of the small-strain theory; the plasticity loop may not converge at every "
            "step (told per step) and the zone may outgrow the box (told)"
        )
    return None


def _json_number(value):
    """Infinity as the string "inf" (valid JSON and TOML), everything else unchanged."""
    return "inf" if isinstance(value, float) and math.isinf(value) else value


def _body_spec(body: Body) -> dict:
    radius = _json_number

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
