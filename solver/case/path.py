"""The ``[load]`` table: the load path of stages and cycle blocks, forces, motion and creepage.

A path is a list of :class:`LoadStage` (each the state at its end and its steps); a cycle
block repeats its stages.  Loads given as a Hertz pressure or a mean pressure become forces
here; rolling and sliding stages carry their travel, creepage and spin.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from ..bodies.geometry import MAX_PROFILE_SLOPE, Geometry
from ..bodies.materials import Pair
from ..keys import (
    MAX_CREEPAGE,
    MAX_CYCLES,
    MAX_INCREMENTS,
    MAX_SHIFT,
    MAX_STAGE_STEPS,
    PRESSURE_RATIO_RANGE,
    required_keys,
    table_keys,
)
from ..theory.hertz import hertz, hertz_force_for_pressure
from ..theory.sneddon import radius_for_force

if TYPE_CHECKING:
    from .wear import Wear
from .reading import CYCLE_BLOCK, STAGE, check_keys, entries, fail, integer, number, plain, show


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
        ``"slide"``, ``"roll"``, ``"steady"`` (the steady state of rolling along +x, no
        travel) or ``""`` (no travel).
    creepage : (float, float) or None
        Kalker's creepages (xi, eta) (dimensionless) of a rolling stage: the rigid slip of body
        1 relative to body 2 per unit distance rolled; the tangential force is then a result.
        ``(0, 0)`` on a stage without travel that follows one (the rigid shift held).  None:
        the tangential force is prescribed.
    spin : float
        Rigid rotation of body 1 relative to body 2 about z per unit distance rolled (1/m),
        counter-clockwise from x to y, about the contact's centre.
    weight : int
        Load cycles the stage's cycle stands for: 1, or under ``wear.cycle_jump`` J the J
        cycles of the block it represents (the block's last solved cycle the rest), its wear
        scaled by them (under ``"auto"`` 1 here; the solve sets them).
    block : int
        Load cycles of the stage's cycle block (0 outside one).
    shift : (float, float) or None
        Target rigid tangential shift (m) of body 1 relative to body 2 at the end of the
        stage (``tangential_shift``), ramped from the shift before it; the tangential force
        is then a result.  None: not prescribed.
    """

    normal_force: float
    tangential_force: tuple[float, float]
    steps: int
    cycle: int = 0
    travel: tuple[float, float] = (0.0, 0.0)
    motion: str = ""
    creepage: tuple[float, float] | None = None
    spin: float = 0.0
    weight: int = 1
    block: int = 0
    shift: tuple[float, float] | None = None


def parse_path(
    raw_stages: list, pair: Pair, wear: Wear | None = None
) -> tuple[list[LoadStage], list[str], list[dict]]:
    """Stages of a load path with its cycle blocks repeated, their paths, the normalised path.

    An entry ``{cycles = N, stages = [...]}`` repeats its stages N times (cycles numbered on
    from the previous block's: 1 .. N for the first), or under a ``wear`` cycle jump as
    :meth:`Wear.solved` times, each repeat standing for cycles (:attr:`LoadStage.weight`); a stage
    without a normal (tangential) force keeps the previous one, also across cycles.
    """
    stages, paths, given = [], [], []
    previous = (0.0, (0.0, 0.0), False)  # (W, Q, the force free: a creepage stage before)
    total = 0  # increments so far

    def count(path: str, steps: int) -> int:
        if total + steps > MAX_INCREMENTS:
            fail(
                path,
                f"the load path reaches {show(total + steps)} increments (cycle blocks "
                f"repeated), more than {MAX_INCREMENTS:,}; give fewer steps per stage or fewer "
                "cycles (the memory and the time grow with every increment)",
            )
        return total + steps

    for i, raw in enumerate(raw_stages):
        path = f"load.path[{i}]"
        if isinstance(raw, dict) and "cycles" in raw:
            check_keys(raw, path, table_keys(CYCLE_BLOCK), required_keys(CYCLE_BLOCK))
            cycles = integer(raw["cycles"], f"{path}.cycles", 1, MAX_CYCLES)
            inner = raw["stages"]
            if isinstance(inner, tuple):
                inner = list(inner)
            if not isinstance(inner, list) or not inner:
                fail(f"{path}.stages", "must be a non-empty array of tables ([[...stages]])")
            block, offset = [], max((stage.cycle for stage in stages), default=0)
            weights = wear.weights(cycles) if wear else [1] * cycles
            solved = len(weights)
            for cycle, weight in enumerate(weights, start=offset + 1):
                if cycle == offset + 2:  # the block's increments are known: refuse before
                    per_cycle = sum(spec["steps"] for spec in block)  # repeating it
                    count(f"{path}.cycles", per_cycle * (solved - 1))
                for j, sub in enumerate(inner):
                    where = f"{path}.stages[{j}]"
                    if isinstance(sub, dict) and "cycles" in sub:
                        fail(f"{where}.cycles", "cycle blocks do not nest; flatten the block")
                    stage, spec = parse_stage(sub, where, previous, pair, not stages)
                    stage = dataclasses.replace(stage, cycle=cycle, weight=weight, block=cycles)
                    stages.append(stage)
                    paths.append(where)
                    previous = _after(stage)
                    total = count(f"{where}.steps", stage.steps)
                    if cycle == offset + 1:
                        block.append(spec)
            given.append({"cycles": cycles, "stages": block})
            continue
        stage, spec = parse_stage(raw, path, previous, pair, not stages)
        total = count(f"{path}.steps", stage.steps)
        stages.append(stage)
        paths.append(path)
        given.append(spec)
        previous = _after(stage)
    return stages, paths, given


def _after(stage: LoadStage) -> tuple:
    """What a stage leaves to the next: (W, Q, whether the force is free)."""
    free = (stage.creepage is not None or stage.shift is not None) and stage.normal_force > 0
    return stage.normal_force, stage.tangential_force, free


def path_cycles(path: list[dict], solved: Callable[[int], int] = int) -> int:
    """Load cycles solved of a normalised load path (0 without a cycle block).

    ``solved``: the cycles solved of a block of N (:func:`solver.case.wear.solved_cycles`;
    under an automatic jump the most).
    """
    return sum(solved(entry["cycles"]) for entry in path if "cycles" in entry)


def path_steps(path: list[dict], solved: Callable[[int], int] = int) -> int:
    """Load increments of a normalised load path (:meth:`Case.to_dict`), cycles repeated.

    ``solved``: as :func:`path_cycles`.
    """
    return sum(
        solved(entry["cycles"]) * path_steps(entry["stages"])
        if "cycles" in entry
        else entry["steps"]
        for entry in path
    )


def _load_number(value: Any, path: str, first: bool) -> float:
    """A load: > 0 in the first stage, >= 0 later (0 unloads the contact)."""
    value = number(value, path, positive=first)
    if value < 0:
        fail(path, f"must be >= 0 (0 unloads the contact), got {value!r}")
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
        fail(path, f"{_load_range(pair)}; got p_H = {p_h:g} Pa")
    try:
        force = hertz_force_for_pressure(p_h, e_star, pair.curvature)
    except _HERTZ_ERRORS as error:
        force, why = math.nan, error
    else:
        why = "not finite"
    if not (math.isfinite(force) and force > 0):
        fail(
            path,
            f"the Hertz force of p_H = {p_h:g} Pa cannot be computed ({why}); {_load_range(pair)}",
        )
    return force


@functools.lru_cache(maxsize=256)
def profile_radius(geometry: Geometry, force: float, e_star: float) -> float:
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
        a = profile_radius(geometry, force, e_star)
    except ValueError:
        fail(
            path,
            f"W = {force:g} N presses the contact out to where the surface's slope passes "
            f"{MAX_PROFILE_SLOPE:g} (radius {geometry.slope_limit:.4g} m; small-slope theory); "
            "lower the load, or blunt the profile (a smaller angle or coefficient, a larger "
            "edge_radius)",
        )
    ratio = force / (math.pi * a * a) / e_star
    low, high = PRESSURE_RATIO_RANGE
    if not low <= ratio <= high:
        fail(
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
        fail(
            path,
            f"W = {force:g} N gives a Hertz pressure p_H = {p_h:.3g} Pa "
            f"(p_H/E* = {p_h / e_star:.3g}); {_load_range(pair)}",
        )


def check_mean_pressure(force: float, pair: Pair, size: tuple[float, float], path: str) -> None:
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
        fail(
            path,
            f"W = {force:g} N gives a mean pressure W/(Lx Ly) = {ratio:.3g} E* over the domain "
            f"({size[0]:.4g} m by {size[1]:.4g} m, E* = {e_star:.4g} Pa); it must be in "
            f"[{low:g}, {high:g}] E* (small strain): W in [{low * e_star * area:.3g}, "
            f"{high * e_star * area:.3g}] N for this domain",
        )


def parse_stage(table: Any, path: str, previous: tuple, pair: Pair, first: bool) -> tuple:
    """One stage of a ``[[load.path]]`` table and its normalised table, after ``previous``."""
    check_keys(table, path, table_keys(STAGE))
    if "hertz_pressure" in table and "normal_force" in table:
        fail(f"{path}.hertz_pressure", "give either hertz_pressure or normal_force, not both")
    given = {}
    if "hertz_pressure" in table and not pair.geometry.hertzian:
        fail(
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
        fail(path, "missing load: give hertz_pressure (Pa) or normal_force (N)")
    else:
        force = previous[0]
    if "tangential_force" in table:
        where = f"{path}.tangential_force"
        value = entries(table["tangential_force"], where, "Q or [Qx, Qy] (N)", (2,), scalar=True)
        if isinstance(value, list):
            q = tuple(number(v, where) for v in value)
        else:
            q = (number(value, where), 0.0)
        given["tangential_force"] = list(q)
    else:
        q = previous[1]
    motion, travel = "", (0.0, 0.0)
    if "slide" in table and "roll" in table:
        fail(f"{path}.roll", "a stage slides or rolls, not both: remove slide or roll")
    for key in ("slide", "roll"):
        if key not in table:
            continue
        if key == "slide" and "tangential_force" in table:
            fail(
                f"{path}.slide",
                "a sliding stage sets the tangential force (mu W along the motion): remove "
                "tangential_force",
            )
        value = entries(table[key], f"{path}.{key}", "[dx, dy] (m)", (2,))
        travel = tuple(number(v, f"{path}.{key}") for v in value)
        if any(travel):  # a zero travel is no travel: the same case, the same id
            given[key] = list(travel)
            motion = key
    if "steady" in table and not isinstance(plain(table["steady"]), bool):
        fail(f"{path}.steady", f"must be true or false, got {table['steady']!r}")
    if plain(table.get("steady", False)):
        if motion:
            fail(
                f"{path}.{motion}",
                "a steady stage has no travel (the steady state of rolling along +x is solved "
                f"directly): remove {motion}",
            )
        if not {"creepage", "spin", "tangential_force"} & set(table):
            fail(
                f"{path}.steady",
                "a steady stage rolls at given creepage or spin, or at a given tangential "
                "force: give them",
            )
        motion = "steady"
        given["steady"] = True
    shift = _parse_shift(table, path, motion, given)
    creepage, spin = (None, 0.0) if shift else _parse_creepage(table, path, previous, motion, given)
    if creepage is not None or shift is not None:  # the force is a result
        q = (0.0, 0.0)
    steps = integer(table.get("steps", 1), f"{path}.steps", 1, MAX_STAGE_STEPS)
    given["steps"] = steps
    stage = LoadStage(force, q, steps, travel=travel, motion=motion, creepage=creepage, spin=spin)
    return dataclasses.replace(stage, shift=shift), given


def _parse_shift(table: Any, path: str, motion: str, given: dict) -> tuple | None:
    """The prescribed tangential shift (m) of a stage, or None (module docstring)."""
    if "tangential_shift" not in table:
        return None
    where = f"{path}.tangential_shift"
    clash = [k for k in ("tangential_force", "creepage", "spin") if k in table] + [motion] * bool(
        motion
    )
    if clash:
        fail(
            where,
            f"a prescribed shift makes the tangential force a result; it does not go with "
            f"{clash[0]}: remove one of the two (a stroke that moves the contact is a slide)",
        )
    value = entries(table["tangential_shift"], where, "dx or [dx, dy] (m)", (2,), scalar=True)
    values = value if isinstance(value, list) else [value, 0.0]
    shift = tuple(number(v, where) for v in values)
    given["tangential_shift"] = list(shift)
    return shift


def _parse_creepage(table: Any, path: str, previous: tuple, motion: str, given: dict) -> tuple:
    """(creepage, spin) of a stage: Kalker's creepages of a rolling stage, or None (force)."""
    creep_keys = [key for key in ("creepage", "spin") if key in table]
    if creep_keys and motion not in ("roll", "steady"):
        fail(
            f"{path}.{creep_keys[0]}",
            "creepage and spin belong to a rolling stage: give roll = [dx, dy] (m) too, or "
            "steady = true (the steady state)"
            if motion == ""
            else "a sliding stage slips everywhere (mu p along the motion): remove "
            f"{creep_keys[0]} or roll instead of slide",
        )
    if "creepage" in table and "tangential_force" in table:
        fail(
            f"{path}.tangential_force",
            "a rolling stage takes either the creepages (the force is then a result) or the "
            "tangential force (the creepage is then a result), not both; a spin goes with "
            "either",
        )
    if previous[2] and "tangential_force" in table:
        fail(
            f"{path}.tangential_force",
            "the previous stage rolls at given creepages or prescribes tangential_shift, so "
            "its tangential force is a result, not the start of a ramp: give creepage or "
            "tangential_shift here too, or unload (normal_force = 0) first",
        )
    if not creep_keys:
        # after a creepage stage the force stays free: the rigid shift is held (no travel) or
        # rolls on at no creepage; else the force is prescribed
        return ((0.0, 0.0) if previous[2] and "tangential_force" not in table else None), 0.0
    # with a prescribed force the creepage is a result, the spin still given
    creepage = None if "tangential_force" in table else (0.0, 0.0)
    if "creepage" in table:
        form = "xi or [xi, eta] (dimensionless)"
        value = entries(table["creepage"], f"{path}.creepage", form, (2,), scalar=True)
        if isinstance(value, list):
            creepage = tuple(number(v, f"{path}.creepage") for v in value)
        else:  # a number: longitudinal (along x)
            creepage = (number(value, f"{path}.creepage"), 0.0)
        if any(abs(v) > MAX_CREEPAGE for v in creepage):
            fail(
                f"{path}.creepage",
                f"each creepage must be within +-{MAX_CREEPAGE:g} (a slip of that fraction of "
                f"the distance rolled is full sliding long before), got {list(creepage)}",
            )
        given["creepage"] = list(creepage)
    spin = 0.0
    if "spin" in table:
        spin = number(table["spin"], f"{path}.spin")
        given["spin"] = spin
    return creepage, spin


def slides(stages) -> bool:
    """True when a stage moves body 1 over body 2 (a ``slide``)."""
    return any(any(stage.travel) for stage in stages)


def tangential_load(stages) -> bool:
    """True when a stage prescribes a tangential force or shift, or creepages or spin."""
    return any(
        any(stage.tangential_force) or stage.creepage is not None or stage.spin or stage.shift
        for stage in stages
    )


def shears(stages) -> bool:
    """True when a stage loads the contact tangentially: a force, a creepage or spin, a travel."""
    return tangential_load(stages) or slides(stages)


def symmetric_pair(body1, body2, stages) -> bool:
    """True for the symmetric elastic-plastic pair (seed eq. 2).

    Identical elastic-plastic bodies under normal load only: their plastic strain fields
    coincide (one field, the print doubled).  A tangential load (:func:`shears`) breaks the
    symmetry: then each body has its own field.
    """
    return body1.behaviour == "elastic-plastic" and body1 == body2 and not shears(stages)


def swap_rolling(table: dict, stages: list[dict]) -> None:
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


def check_driven_stages(stages, paths, mu: float, pair: Pair, scene: str) -> None:
    """Refuse creepage, spin or tangential_shift without friction, and what shifts cannot do.

    ``scene``: "" or why a prescribed shift is not built for the case (an elastic-plastic body,
    the periodic mode).  A shift past :data:`MAX_SHIFT` of the smaller Hertz semi-axis would
    move the contact, which the fixed shapes do not.
    """
    for stage, path in zip(stages, paths, strict=True):
        creeps = stage.creepage is not None and any(stage.creepage)
        if mu == 0.0 and (creeps or stage.spin or stage.shift):
            key = "tangential_shift" if stage.shift else "creepage" if creeps else "spin"
            fail(
                f"{path}.{key}",
                "friction.coefficient is 0: a frictionless contact carries no tangential force; "
                f"remove {key} or give a friction coefficient",
            )
        if stage.shift is None:
            continue
        if scene:
            fail(f"{path}.tangential_shift", f"a prescribed shift is not built yet {scene}")
        if not pair.geometry.hertzian:  # no contact size to bound the shift by
            fail(
                f"{path}.tangential_shift",
                "a prescribed shift is built for quadric bodies (a sphere, an ellipsoid, a "
                "cylinder), whose contact size bounds it; with a profile or heights prescribe "
                "tangential_force",
            )
        if stage.normal_force > 0:
            semi = hertz(stage.normal_force, pair.composite_modulus, pair.curvature)
            largest = MAX_SHIFT * min(semi.semi_axis_x, semi.semi_axis_y)
            if math.hypot(*stage.shift) > largest:
                fail(
                    f"{path}.tangential_shift",
                    f"|shift| = {math.hypot(*stage.shift):.3g} m passes {MAX_SHIFT:g} of the "
                    f"contact's semi-axis ({largest:.3g} m): the shapes would have to move; "
                    "slide the stroke instead (load.path[i].slide with a rigid body 1)",
                )


def creep_ramp(stages) -> Iterator[tuple[tuple[float, float], float]]:
    """((xi, eta), spin) of every increment of a steady stage, None for others, in order.

    A steady stage ramps linearly from the previous steady stage's creepage and spin (from
    zero after any other stage): its increments are the points of a creep curve.  A
    steady stage at a prescribed force gives ``(None, spin)``, its spin ramped alike: the
    creepage is a result, and the next stage's creepage ramps from zero.
    """
    start = ((0.0, 0.0), 0.0)
    for stage in stages:
        if stage.motion != "steady":
            start = ((0.0, 0.0), 0.0)
            yield from (None for _ in range(stage.steps))
            continue
        (xi0, eta0), spin0 = start
        if stage.creepage is None:  # a prescribed force: the creepage is a result
            for k in range(1, stage.steps + 1):
                yield None, spin0 + k / stage.steps * (stage.spin - spin0)
            start = ((0.0, 0.0), stage.spin)
            continue
        xi1, eta1 = stage.creepage
        for k in range(1, stage.steps + 1):
            f = k / stage.steps
            yield (
                (xi0 + f * (xi1 - xi0), eta0 + f * (eta1 - eta0)),
                spin0 + f * (stage.spin - spin0),
            )
        start = (stage.creepage, stage.spin)
