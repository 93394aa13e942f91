"""The ``[wear]`` table: the worn surface fed back into the contact.

After every increment each worn body loses a depth of material at each surface cell,

    archard:  dh = k p |s|          (k in 1/Pa = m^3 per N per m slid)
    energy:   dh = alpha (-q . s)   (alpha in 1/Pa = m^3 per J dissipated, Fouvry's law)

with ``s`` the local slip increment of the increment, ``p`` and ``q`` the means of the pressure
and the shear traction at its two ends (the trapezoid in time, as the friction work is summed).
A stick cell does not slip, so it does not wear.  The depths of both bodies add to the gap
between them (each surface recedes), increment after increment.  A rigid body wears as well:
its shape, not its elasticity, is what the wear changes.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from ..keys import (
    MAX_CYCLES,
    PRESSURE_CHANGE,
    PRESSURE_CHANGE_RANGE,
    SOLVED_CYCLES,
    WEAR_COEFFICIENT_RANGE,
    WEAR_LAWS,
    table_keys,
)
from .reading import check_keys, fail, integer, number


@dataclass(frozen=True)
class Wear:
    """A wear law and each body's coefficient (module docstring).

    Attributes
    ----------
    law : str
        ``"archard"`` (the depth per pressure and distance slid) or ``"energy"`` (per friction
        energy dissipated).
    body1, body2 : float
        The bodies' coefficients k or alpha (1/Pa); 0: the body does not wear.
    cycle_jump : int or "auto"
        Load cycles one solved cycle stands for (:attr:`LoadStage.weight`), or ``"auto"``:
        set cycle by cycle by :class:`solver.drive.wear.CycleJumps`.
    pressure_change : float
        Under ``"auto"``: the largest relative change of the pressure a jump may make.
    solved_cycles : int
        Under ``"auto"``: the most cycles solved per cycle block.
    """

    law: str
    body1: float = 0.0
    body2: float = 0.0
    cycle_jump: int | str = 1
    pressure_change: float = PRESSURE_CHANGE
    solved_cycles: int = SOLVED_CYCLES

    @property
    def auto(self) -> bool:
        """The jumps are set as the cycles are solved (``cycle_jump = "auto"``)."""
        return self.cycle_jump == "auto"

    def solved(self, cycles: int) -> int:
        """The cycles solved of a block of ``cycles`` (under ``"auto"``: the most)."""
        if self.auto:
            return min(cycles, self.solved_cycles)
        return -(-cycles // self.cycle_jump)

    def weights(self, cycles: int) -> list[int]:
        """The cycles each solved cycle of a block of ``cycles`` stands for.

        A jump J: J each, the last the rest.  ``"auto"``: 1 each until the solve sets them.
        """
        solved = self.solved(cycles)
        if self.auto:
            return [1] * solved
        return [self.cycle_jump] * (solved - 1) + [cycles - self.cycle_jump * (solved - 1)]

    @property
    def bodies(self) -> tuple[int, ...]:
        """The bodies that wear (1, 2)."""
        return tuple(b for b, k in ((1, self.body1), (2, self.body2)) if k > 0.0)

    def coefficient(self, body: int) -> float:
        """Body ``body``'s coefficient (1/Pa)."""
        return self.body1 if body == 1 else self.body2

    def spec(self) -> dict:
        """The normalised table (the jump only when there is one)."""
        table = {"law": self.law, "body1": self.body1, "body2": self.body2}
        if self.auto:
            rule = {"pressure_change": self.pressure_change, "solved_cycles": self.solved_cycles}
            return table | {"cycle_jump": "auto"} | rule
        return table | ({"cycle_jump": self.cycle_jump} if self.cycle_jump > 1 else {})


def solved_cycles(spec: dict) -> Callable[[int], int]:
    """The cycles solved of a block of N, for a normalised case table (its wear's jump)."""
    wear = spec.get("wear")
    return parse_wear(wear).solved if wear else (lambda cycles: cycles)


def parse_wear(table: Any) -> Wear:
    """The wear of a ``[wear]`` table (its own rules; the case's are in :class:`Case`)."""
    wear = check_keys(table, "wear", table_keys("wear"))
    if "law" not in wear:
        fail("wear.law", f"is required: one of {', '.join(WEAR_LAWS)}")
    law = wear["law"]
    if law not in WEAR_LAWS:
        fail(
            "wear.law",
            f"must be one of {', '.join(repr(x) for x in WEAR_LAWS)} (archard: dh = k p |s|; "
            f"energy: dh = alpha q . s), got {law!r}",
        )
    low, high = WEAR_COEFFICIENT_RANGE
    coefficients = {}
    for body in ("body1", "body2"):
        value = number(wear.get(body, 0.0), f"wear.{body}")
        if not (value == 0.0 or low <= value <= high):  # NaN fails too
            fail(
                f"wear.{body}",
                f"the {law} coefficient of {body} must be 0 (it does not wear) or in "
                f"[{low:g}, {high:g}] 1/Pa, got {value:g}",
            )
        coefficients[body] = value
    if not any(coefficients.values()):
        fail("wear", "no body wears: give wear.body1 or wear.body2 a positive coefficient (1/Pa)")
    jump = wear.get("cycle_jump", 1)
    if isinstance(jump, str) and jump != "auto":
        fail("wear.cycle_jump", f'must be an integer (cycles) or "auto", got {jump!r}')
    if jump != "auto":
        jump = integer(jump, "wear.cycle_jump", 1, MAX_CYCLES)
        for key in ("pressure_change", "solved_cycles"):
            if key in wear:
                fail(f"wear.{key}", 'sets the automatic jump: give it with cycle_jump = "auto"')
        return Wear(law, **coefficients, cycle_jump=jump)
    change = number(wear.get("pressure_change", PRESSURE_CHANGE), "wear.pressure_change")
    low, high = PRESSURE_CHANGE_RANGE
    if not low <= change <= high:
        fail(
            "wear.pressure_change",
            f"must be in [{low:g}, {high:g}] (a fraction of the peak pressure), got {change:g}",
        )
    solved = integer(wear.get("solved_cycles", SOLVED_CYCLES), "wear.solved_cycles", 2, MAX_CYCLES)
    return Wear(law, **coefficients, cycle_jump=jump, pressure_change=change, solved_cycles=solved)


def check_wear_case(wear: Wear, stages, mu: float) -> None:
    """Refuse a case whose wear the solver cannot honour (each with the key to change).

    ``stages``: the load stages; ``mu``: Coulomb's coefficient.  An elastic-plastic body 1
    is solved as body 2 (:meth:`Case.swapped`), its wear with it.
    """
    if any(s.motion == "steady" for s in stages):
        fail(
            "wear",
            "a steady rolling stage has no increments over which the surface could wear: "
            "roll the contact transiently (load.path[i].roll) instead",
        )
    moving = any(s.motion in ("slide", "roll") for s in stages)
    if wear.body1 > 0.0 and any(s.motion == "roll" for s in stages):
        fail(
            "wear.body1",
            "a rolling body 1 brings new surface into the contact as it turns (a wheel's "
            "circumference), which is not built yet: let body 2 wear (wear.body2)",
        )
    slips = moving or any(math.hypot(*s.tangential_force) > 0.0 or s.shift for s in stages)
    if not slips:
        fail(
            "wear",
            "no stage of load.path slips (a tangential_force or tangential_shift, a slide or a "
            "roll), so nothing "
            "wears: add such a stage or remove the table",
        )
    if wear.cycle_jump != 1 and not any(s.cycle for s in stages):
        fail(
            "wear.cycle_jump",
            "the path has no cycle block (load.path[i] = {cycles = N, stages = [...]}) to jump "
            "over: add one, or leave the key out",
        )
    if wear.law == "energy" and mu == 0.0:
        fail(
            "wear.law",
            '"energy" wears by the friction energy, and friction.coefficient is 0 '
            '(frictionless): give a coefficient, or law = "archard"',
        )
