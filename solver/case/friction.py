"""The ``[friction]`` table: Coulomb's coefficient and the shear limit that caps it.

Coulomb's law bounds the friction traction by ``mu p``; a metal surface cannot carry a shear
stress above its shear yield stress k, whatever the pressure (Bowden and Tabor's junctions).
``friction.shear_limit`` caps the bound, Orowan's law ``|q| <= min(mu p, m tau_c)``: a stress
tau_c (Pa) everywhere, or ``"yield"``, the current shear yield stress of the plastic body's top
layer under each cell (:func:`solver.drive.shear_cap.yield_cap`), with Orowan's factor
``m = friction.shear_factor`` in (0, 1].
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from ..keys import MAX_FRICTION, MIN_FRICTION, MIN_SHEAR_FACTOR, SHEAR_LIMIT_RANGE, table_keys
from .reading import check_keys, fail, number

#: ``friction.shear_limit`` naming the plastic body's current shear yield stress.
YIELD = "yield"
#: ``friction.shear_limit`` naming no limit (Coulomb's law alone: the case without the key), so
#: that a campaign can sweep the limit against its absence.
NO_LIMIT = "none"


@dataclass(frozen=True)
class Friction:
    """Coulomb friction, optionally capped by a shear limit (module docstring).

    Attributes
    ----------
    coefficient : float
        Coulomb's mu (dimensionless).
    shear_limit : float or "yield" or None
        tau_c (Pa), ``"yield"`` (the plastic body's current shear yield stress), or None:
        Coulomb's law alone.
    shear_factor : float
        Orowan's factor m in (0, 1] (dimensionless): the cap is ``m tau_c``.
    """

    coefficient: float = 0.0
    shear_limit: float | str | None = None
    shear_factor: float = 1.0

    @property
    def capped(self) -> bool:
        """True when a shear limit caps the traction of a contact with friction."""
        return self.shear_limit is not None and self.coefficient > 0.0

    @property
    def follows_yield(self) -> bool:
        """True when the cap is the plastic body's current shear yield stress."""
        return self.capped and self.shear_limit == YIELD

    @property
    def stress_cap(self) -> float | None:
        """``m tau_c`` (Pa) of a limit given as a stress, else None."""
        if not self.capped or self.shear_limit == YIELD:
            return None
        return self.shear_factor * float(self.shear_limit)

    def spec(self) -> dict:
        """The normalised table (the limit's keys only when given: older ids stay)."""
        table: dict[str, Any] = {"coefficient": self.coefficient}
        if self.shear_limit is not None:
            table.update(shear_limit=self.shear_limit, shear_factor=self.shear_factor)
        return table


def parse_friction(table: Any, plastic: bool) -> tuple[Friction, list[str]]:
    """The friction of a ``[friction]`` table, and its notes.

    ``plastic``: the case has an elastic-plastic body (which ``"yield"`` needs).
    """
    friction = check_keys(table, "friction", table_keys("friction"))
    mu = number(friction.get("coefficient", 0.0), "friction.coefficient")
    if not 0 <= mu <= MAX_FRICTION:
        fail(
            "friction.coefficient",
            f"must be in [0, {MAX_FRICTION:g}] (a contact sticks fully long before), got {mu}",
        )
    if 0 < mu < MIN_FRICTION:
        fail(
            "friction.coefficient",
            f"{mu:g} is frictionless to the solver's tolerances (the tangential solve's "
            f"scales underflow below {MIN_FRICTION:g}): give 0, or at least {MIN_FRICTION:g}",
        )
    if friction.get("shear_limit") == NO_LIMIT:  # the same case as without the key
        friction = {k: v for k, v in friction.items() if k != "shear_limit"}
    if "shear_limit" not in friction:
        if "shear_factor" in friction:
            fail(
                "friction.shear_factor",
                "scales friction.shear_limit, which is not given: give the limit (a stress in "
                'Pa, or "yield") or remove the factor',
            )
        return Friction(mu), []
    limit = friction["shear_limit"]
    if isinstance(limit, str):
        if limit != YIELD:
            fail(
                "friction.shear_limit",
                f'must be a stress in Pa, "yield" (the plastic body\'s shear yield stress) or '
                f'"none" (no limit), got {limit!r}',
            )
        if not plastic:
            fail(
                "friction.shear_limit",
                '"yield" is the shear yield stress of an elastic-plastic body, and both bodies '
                "are elastic or rigid here: give the limit as a stress in Pa, or make a body "
                "elastic-plastic",
            )
    else:
        limit = number(limit, "friction.shear_limit")
        low, high = SHEAR_LIMIT_RANGE
        if not low <= limit <= high:  # NaN fails too
            fail(
                "friction.shear_limit",
                f"must be a stress in [{low:g}, {high:g}] Pa (a shear strength), or "
                f'"yield"; got {limit:g}',
            )
    factor = number(friction.get("shear_factor", 1.0), "friction.shear_factor")
    if not MIN_SHEAR_FACTOR <= factor <= 1.0:  # NaN fails too
        fail(
            "friction.shear_factor",
            f"Orowan's factor m must be in (0, 1] (the cap is m times the limit), at least "
            f"{MIN_SHEAR_FACTOR:g} (below, give a smaller limit), got {factor:g}",
        )
    notes = []
    if mu == 0.0:
        notes.append(
            "friction.shear_limit caps the friction traction, and friction.coefficient is 0 "
            "(frictionless): the limit has no effect"
        )
    return Friction(mu, limit, factor), notes


def sizing_ratio(
    friction: Friction, ratio: float, max_pressure: float, shear_limits: list[float]
) -> float:
    """The largest ``|Q| / W`` the plastic box is sized for: the path's, or what the surface bears.

    ``ratio``: the path's largest ``|Q| / W``; ``max_pressure``: Hertz's peak pressure (Pa,
    NaN for a profile: the path's ratio is kept); ``shear_limits``: each plastic body's bounded
    shear limit (:attr:`Hardening.shear_limit`, inf for hardening).  A surface cannot carry a
    shear above the cap ``m tau_c``, nor (Coulomb's law alone) above a bounded body's k, whose
    passing ends the case (surface flow): the friction field the zone grows under is at most
    the capped one, whose force is ``mu W (1.5 s - 0.5 s^3)``, ``s = cap / (mu p_0)``
    (:func:`solver.theory.friction.capped_force_ratio`).  ``"yield"`` on a hardening body
    keeps the path's ratio (its k grows with the strain).
    """
    from ..theory.friction import capped_force_ratio

    mu = friction.coefficient
    if mu == 0.0 or not math.isfinite(max_pressure):
        return ratio
    caps = [k for k in shear_limits if math.isfinite(k)]
    if friction.follows_yield:
        caps = [friction.shear_factor * k for k in caps]
    if friction.stress_cap is not None:
        caps.append(friction.stress_cap)
    if not caps:
        return ratio
    return min(ratio, mu * capped_force_ratio(min(caps) / (mu * max_pressure)))


def limit_reached_note(friction: Friction, mu_p: float) -> str | None:
    """A note when a stress cap is at or above the largest Coulomb traction ``mu_p`` (Pa).

    Said of the closed-form contact's peak pressure: the limit then caps nothing unless
    plastic flow or the coupling raise the pressure.
    """
    cap = friction.stress_cap
    if cap is None or not math.isfinite(mu_p) or cap < mu_p:
        return None
    return (
        f"friction.shear_limit: m tau_c = {cap / 1e6:.4g} MPa is above mu p_0 = "
        f"{mu_p / 1e6:.4g} MPa, the largest Coulomb traction of the elastic contact: the limit "
        "caps nothing unless the pressure rises above p_0"
    )
