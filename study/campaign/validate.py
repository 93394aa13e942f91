"""Checks of swept keys, swept values and the paths they set, with messages naming them."""

from __future__ import annotations

import copy
import math
import re
from collections.abc import Mapping
from typing import Any

from solver.bodies.dundurs import body1_for_beta
from solver.bodies.materials import Body
from solver.keys import MODULUS_RANGE

from .model import BETA_KEY, CASE_TABLES, Axis, CampaignError
from .naming import _is_inf, _kind


def normalise_key(written: str, where: str = "[sweep]") -> str:
    """Normalise a dotted key: ``"load.path[1].steps"`` -> ``"load.path.1.steps"``.

    Raises
    ------
    CampaignError
        If the key is empty, has empty segments or bad brackets.
    """
    key = re.sub(r"\[(\d+)\]", r".\1", written.strip())
    segments = key.split(".")
    if not key or any(not s or not re.match(r"^[A-Za-z0-9_]+$", s) for s in segments):
        raise CampaignError(
            f'{where} "{written}": not a dotted key path like "friction.coefficient" or '
            '"load.path.1.tangential_force"'
        )
    if segments[0] == "materials":
        if key != BETA_KEY:
            raise CampaignError(
                f'{where} "{written}": unknown materials key; the only one is "{BETA_KEY}"'
            )
    elif segments[0] not in CASE_TABLES:
        raise CampaignError(
            f'{where} "{written}": unknown case table "{segments[0]}"; keys start with '
            f"{', '.join(CASE_TABLES[:-1])} (or {BETA_KEY})"
        )
    return key


def _check_values(values: Any, where: str, key: str, unique: bool = True) -> list:
    if not isinstance(values, list):
        raise CampaignError(f"{where}: must be a list of values, got {values!r}")
    if not values:
        raise CampaignError(f"{where}: empty list; give at least one value")
    for value in values:
        if isinstance(value, list | dict):
            raise CampaignError(
                f"{where}: values must be numbers, strings or booleans, got {value!r}"
                + (
                    "; for a tangential force give the x component as a number"
                    if key.endswith("tangential_force")
                    else ""
                )
                + (
                    '; sweep "grid.n" as one number per value (nx = ny; the base\'s nz is '
                    'kept) and the depth as "grid.nz"'
                    if key == "grid.n"
                    else ""
                )
            )
        if isinstance(value, float) and math.isnan(value):
            raise CampaignError(f"{where}: nan is not a value")
    kinds = {_kind(v) for v in values}
    if len(kinds) > 1:
        raise CampaignError(f"{where}: mixed value types {values!r}; use one type per axis")
    if key == BETA_KEY and kinds != {"number"}:
        raise CampaignError(f"{where}: Dundurs' beta values must be numbers, got {values!r}")
    seen = []
    for value in values if unique else ():
        normal = float(value) if _is_inf(value) else value  # 1 == 1.0; no float(huge int)
        if normal in seen:
            raise CampaignError(f"{where}: value {value!r} appears twice; axis values must differ")
        seen.append(normal)
    return values


# -- paths into the base table -------------------------------------------------------------------
def _segments(key: str) -> list[str | int]:
    return [int(s) if s.isdigit() else s for s in key.split(".")]


def assign(table: dict, key: str, value: Any, owned: set[int] | None = None) -> None:
    """Set the dotted ``key`` of a case table to ``value`` (in place).

    Missing tables on the path are created; integer segments index arrays of tables.  With
    ``owned`` (the ids of the containers this table owns, ``table`` among them), copy on
    write: a table or array on the path that the table shares with others (its base) is
    copied before it is changed, and its copy added to ``owned``.

    Raises
    ------
    CampaignError
        If the path runs through a value, indexes a table or runs past an array.
    """
    node: Any = table
    segments = _segments(key)
    done: list[str] = []
    for position, segment in enumerate(segments):
        last = position == len(segments) - 1
        where = ".".join(done) or "the base table"
        if isinstance(segment, int):
            if not isinstance(node, list):
                raise CampaignError(
                    f'key "{key}": {where} is not an array of tables, cannot index it with '
                    f"{segment}"
                )
            if segment >= len(node):
                raise CampaignError(
                    f'key "{key}": index {segment} is out of range, {where} has {len(node)} '
                    "entries (indices start at 0)"
                )
            if last:
                node[segment] = value
            else:
                node = _own(node, segment, owned)
        else:
            if isinstance(node, list):
                raise CampaignError(
                    f'key "{key}": {where} is an array; give an index, e.g. "{where}.0.{segment}"'
                )
            if not isinstance(node, dict):
                raise CampaignError(f'key "{key}": {where} is a value, not a table')
            if last:
                node[segment] = value
            else:
                if segment not in node:
                    node[segment] = {}
                node = _own(node, segment, owned)
        done.append(str(segment))


def _own(node: Any, segment: str | int, owned: set[int] | None) -> Any:
    """``node[segment]``, copied into ``node`` first if shared (:func:`assign`'s ``owned``)."""
    child = node[segment]
    if owned is None or id(child) in owned or not isinstance(child, dict | list):
        return child
    child = node[segment] = child.copy()
    owned.add(id(child))
    return child


# -- expansion -----------------------------------------------------------------------------------
def _copy_table(value: Any) -> Any:
    """Deep copy of a parsed TOML table (dicts, lists, immutable values): 5x copy.deepcopy."""
    if isinstance(value, dict):
        return {key: _copy_table(item) for key, item in value.items()}
    if isinstance(value, list):
        return [_copy_table(item) for item in value]
    return value


def _value(key: str, value: Any, defined: dict[str, dict]) -> Any:
    """What a swept value sets: the ``[define]`` table it names for a whole-table key.

    The table itself, shared: set it with :func:`assign`'s copy on write (``owned``).
    """
    return defined[value] if "." not in key else value


def _check_paths(base: Mapping, axes: tuple[Axis, ...], defined: dict[str, dict]) -> None:
    probe = copy.deepcopy(dict(base))
    owned = {id(probe)}
    for axis in axes:
        for coordinate in axis.coordinates:
            if coordinate.key == BETA_KEY:
                continue
            value = _value(coordinate.key, coordinate.values[0], defined)
            assign(probe, coordinate.key, value, owned)
    load = base.get("load")
    for axis in axes:
        for c in axis.coordinates:
            if c.key.startswith("load.") and not c.key.startswith("load.path"):
                if isinstance(load, Mapping) and "path" in load:
                    raise CampaignError(
                        f'key "{c.key}": the base load is a path ([[base.load.path]]); address '
                        f'a stage, e.g. "load.path.0.{c.key.split(".", 1)[1]}"'
                    )


def _apply_beta(table: dict, beta: float) -> None:
    raw1, raw2 = table.get("body1"), table.get("body2")
    if not isinstance(raw1, dict) or raw1.get("behaviour") not in ("elastic", "elastic-plastic"):
        behaviour = raw1.get("behaviour") if isinstance(raw1, dict) else None
        raise CampaignError(
            f"{BETA_KEY}: needs an elastic body1 (its E and nu are adjusted), but body1 is "
            f"{behaviour or 'missing'}; make body1 elastic in [base]"
        )
    try:
        body1 = Body("elastic", E=float(raw1["E"]), nu=float(raw1["nu"]))
        if isinstance(raw2, dict) and raw2.get("behaviour") == "rigid":
            body2 = Body("rigid")
        else:
            body2 = Body("elastic", E=float(raw2["E"]), nu=float(raw2["nu"]))
        moduli = [body1.E] + ([] if body2.rigid else [body2.E])
        if not all(MODULUS_RANGE[0] <= e <= MODULUS_RANGE[1] for e in moduli):
            raise ValueError
        if not (-1 < body1.nu <= 0.5 and (body2.rigid or -1 < body2.nu <= 0.5)):
            raise ValueError
    except (KeyError, TypeError, ValueError):
        return  # let Case.from_dict name the bad elastic constant
    try:
        young, nu = body1_for_beta(beta, body1, body2, BETA_KEY)
    except ValueError as error:
        raise CampaignError(str(error)) from None
    table["body1"] = {**raw1, "E": young, "nu": nu}  # the base's body1 is left as it was


def _explain(message: str, axes: tuple[Axis, ...]) -> str:
    """Append which axis sets the field a SpecError names, when one does."""
    field_path = message.split(":", 1)[0].strip()
    dotted = re.sub(r"\[(\d+)\]", r".\1", field_path)
    for axis in axes:
        for c in axis.coordinates:
            if c.key == dotted or c.key.startswith(dotted + "."):
                return f'{message} [set by axis "{c.key}"]'
    return message
