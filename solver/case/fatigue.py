"""The ``[fatigue]`` table: Dang Van's and Crossland's criteria of body 2 under a pass.

The criteria (:mod:`solver.fatigue.criteria`) read the stress path of every material point of
body 2 as the contact passes; a steady pass gives it from one snapshot of the moving load's
field (:func:`~solver.fatigue.criteria.steady_pass_criteria`), so a case with the table must
move its contact (a ``slide`` or ``roll`` stage, or the steady state of rolling) or cycle its
load (a cycle block: the last cycle's increments are each point's path) over a volume grid
(plane strain in a line contact, ``grid.periodic = "y"``).
"""

from __future__ import annotations

from typing import Any

from ..fatigue.criteria import FatigueLimits
from ..keys import FATIGUE_LIMIT_RANGE, required_keys, table_keys
from .reading import check_keys, fail, number


def parse_fatigue(table: Any) -> FatigueLimits:
    """Body 2's fatigue limits of a ``[fatigue]`` table (module docstring)."""
    table = check_keys(table, "fatigue", table_keys("fatigue"), required_keys("fatigue"))
    low, high = FATIGUE_LIMIT_RANGE
    limits = []
    for key in ("bending_limit", "torsion_limit"):
        value = number(table[key], f"fatigue.{key}", positive=True)
        if not low <= value <= high:
            fail(f"fatigue.{key}", f"must be in [{low:g}, {high:g}] Pa (a stress amplitude)")
        limits.append(value)
    bending, torsion = limits
    try:
        return FatigueLimits(bending, torsion)
    except ValueError as error:
        fail("fatigue.torsion_limit", str(error))


def check_fatigue_case(stages, volume: bool, periodic: bool, plastic_body1: bool) -> None:
    """Refuse a case whose pass the criteria cannot read (each with the key to change)."""
    if not any(stage.motion in ("slide", "roll", "steady") or stage.cycle for stage in stages):
        fail(
            "fatigue",
            "the criteria read the stress path of a pass or a load cycle: give a stage that "
            "slides or rolls (load.path[i].slide, roll, or steady = true) or a cycle block "
            "(cycles = N), or remove the table",
        )
    if not volume:
        fail("grid.n", "the fatigue criteria read body 2's volume: give grid.n = [nx, ny, nz]")
    if periodic or plastic_body1:
        what = "in periodic mode" if periodic else "with an elastic-plastic body 1"
        fail("fatigue", f"the fatigue criteria are not built yet {what}")
