"""Reading a case table: the error it raises and the checks every table's parser shares.

:class:`SpecError` names the field and what to change; :func:`check_keys` refuses unknown and
missing keys (from :data:`solver.keys.CASE_KEYS`); :func:`number`, :func:`integer`,
:func:`entries` and :func:`plain` take numpy scalars, tuples and arrays as the Python values
they hold.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Set
from typing import Any

import numpy as np

from ..bodies.heights import HeightMap


class SpecError(ValueError):
    """An invalid case specification; the message names the field and what to change."""


#: Tables of :data:`solver.keys.CASE_KEYS` the parser names more than once.
HARDENING, KINEMATIC = "bodyN.hardening", "bodyN.hardening.kinematic"


PROFILE, SURFACE, ROUGHNESS = "bodyN.profile", "bodyN.surface", "bodyN.roughness"


#: What reads a height-map file: a surface table ({"file": ..., "spacing": ...}) to a
#: :class:`~solver.bodies.heights.HeightMap` (``study.campaign.surfaces.read_surface``; solver/
#: reads no files).
SurfaceReader = Callable[[dict], HeightMap]


STAGE, CYCLE_BLOCK = "load.path[i]", "load.path[i] (cycle block)"


def fail(path: str, message: str) -> None:
    """Raise :class:`SpecError` for the field ``path``."""
    raise SpecError(f"{path}: {message}")


def check_keys(table: Any, path: str, allowed: Set[str], required: Set[str] = frozenset()):
    """The table itself, once its keys are all allowed and the required ones given."""
    if not isinstance(table, dict):
        fail(path or "case", f"must be a table, got {type(table).__name__}")
    unknown = sorted(set(table) - allowed)
    if unknown:
        fail(
            f"{path}.{unknown[0]}" if path else unknown[0],
            f"unknown key; allowed keys are {', '.join(sorted(allowed))}",
        )
    for key in sorted(required):
        if key not in table:
            fail(f"{path}.{key}" if path else key, "missing required field")
    return table


def plain(value: Any) -> Any:
    """Numpy scalars and arrays as the Python bool, int, float, str or list they hold."""
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    return value


def brief(value: Any) -> str:
    """``repr(value)`` for a one-line message, cut to 80 characters."""
    text = " ".join(repr(value).split())
    return text if len(text) <= 80 else text[:77] + "..."


def entries(value: Any, path: str, form: str, lengths=None, *, scalar: bool = False) -> Any:
    """A list the case takes (a pair of numbers, grid.n, output.fields): its entries, unchecked.

    Given as a list, a tuple or a 1-D numpy array alike (so all three give the same case id);
    with ``scalar``, a single value is returned as it is (the caller reads it: Q for [Q, 0],
    L for [L, L], ...).  Refused, naming ``path`` and the ``form`` it takes: a wrong number of
    entries (``lengths``: the allowed counts, None: any), nested lists, a 2-D array, a string
    or a table where a list belongs.
    """
    if isinstance(value, np.ndarray) and value.ndim > 1:
        fail(path, f"must be {form}, got a {value.ndim}-D array of shape {value.shape}")
    value = plain(value)
    if isinstance(value, tuple):
        value = list(value)
    if isinstance(value, list):
        if lengths is not None and len(value) not in lengths:
            fail(path, f"must be {form}, got {len(value)} entries: {brief(value)}")
        if any(isinstance(plain(v), list | tuple | dict) for v in value):
            fail(path, f"must be {form}, got nested lists or tables: {brief(value)}")
        return value
    if not scalar or isinstance(value, str | bytes | dict | set | frozenset):
        fail(path, f"must be {form}, got {brief(value)}")
    return value


def show(value: int) -> str:
    """An integer for a message: its digits, or its size when it has too many to print."""
    if abs(value) < 10**30:
        return str(value)
    return f"{'a negative' if value < 0 else 'an'} integer of {value.bit_length()} bits"


def number(value: Any, path: str, *, positive: bool = False, allow_inf: bool = False) -> float:
    """A float from a number (not a boolean), named ``path`` in the error."""
    value = plain(value)
    if isinstance(value, str) and value.lower() in ("inf", "infinity") and allow_inf:
        return math.inf
    if isinstance(value, bool) or not isinstance(value, int | float):
        hint = ' (or "inf")' if allow_inf else ""
        fail(path, f"must be a number{hint}, got {value!r}")
    try:
        value = float(value)
    except OverflowError:  # an int beyond the float range
        fail(path, f"must be finite, got {show(value)}, beyond the float range")
    if math.isnan(value) or (math.isinf(value) and not allow_inf):
        fail(path, f"must be finite, got {value!r}")
    if positive and not value > 0:
        fail(path, f"must be > 0, got {value!r}")
    return value


def integer(value: Any, path: str, low: int, high: int) -> int:
    """An int in [low, high] from an integer (or a whole float), named ``path`` in the error."""
    value = plain(value)
    if isinstance(value, float) and value.is_integer():
        value = int(value)
    if isinstance(value, bool) or not isinstance(value, int):
        fail(path, f"must be an integer, got {value!r}")
    if not low <= value <= high:
        fail(path, f"must be between {low} and {high}, got {show(value)}")
    return value


def json_number(value):
    """Infinity as the string "inf" (valid JSON and TOML), everything else unchanged."""
    return "inf" if isinstance(value, float) and math.isinf(value) else value
