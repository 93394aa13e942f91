"""Shakedown classification of a cyclic elastic-plastic load path, from its per-cycle gains.

A load path with a cycle block repeats a load (a fretting cycle, a pass of a moving contact,
see :mod:`solver.result`).  Melan's and Koiter's theorems sort the long-run response of an
elastic-plastic body under repeated loads into four regimes (Johnson 1985, §9.5; Williams 2005):

``elastic``
    the body never yields (equivalent plastic strain nowhere above
    :data:`solver.variables.PLASTIC_ZONE_THRESHOLD`);
``elastic_shakedown``
    it yields, but residual stresses (and hardening) make later cycles elastic: the plastic
    strain gained per cycle falls below :data:`SHAKEDOWN_TOLERANCE` of the largest cycle's gain
    (or below the plastic-zone threshold);
``plastic_shakedown``
    every cycle yields, but the plastic strain tensor returns to its start: the net change of
    the last cycle is below :data:`CLOSED_CYCLE_FRACTION` of the strain it gained (alternating
    plasticity, low-cycle fatigue);
``ratchetting``
    every cycle adds a steady net plastic strain, at least that fraction of its gain and at
    least :data:`STEADY_NET` of the cycle before's (incremental collapse: wear, rolling contact
    fatigue).

Two measures per cycle are the evidence (:data:`solver.variables.CYCLE_QUANTITIES`): the
equivalent plastic strain gained (``plastic_strain_increment``: accumulated, it grows in a
closed plastic cycle too) and the equivalent strain of the plastic strain tensor's change
(``net_plastic_strain_increment``: zero for a closed cycle).  A cycle's gain is *steady* when it
is at least :data:`STEADY_DECAY` of the cycle before's; a gain that still falls faster, without
having reached the tolerance, is ``undetermined`` (give more cycles), as is a path that did not
converge or has fewer than :data:`MIN_CYCLES` cycles.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from ..numerics.tensor import contract, deviator, von_mises
from ..variables import PLASTIC_ZONE_THRESHOLD
from .half_space import hamilton_stress, mcewen_stress

#: The classes and their flags (CF ``flag_values`` / ``flag_meanings`` of ``shakedown``).
SHAKEDOWN_FLAGS = {
    "undetermined": 0,
    "elastic": 1,
    "elastic_shakedown": 2,
    "plastic_shakedown": 3,
    "ratchetting": 4,
}
#: Elastic shakedown: the last cycle gains less than this fraction of the largest cycle's gain.
SHAKEDOWN_TOLERANCE = 1e-3
#: A steady cycle gains at least this fraction of the cycle before's.
STEADY_DECAY = 0.5
#: Ratchetting: the net tensor change of a cycle is at least this fraction of the one before's
#: (a steady rate of incremental collapse, not a transient that is still dying out).
STEADY_NET = 0.9
#: A closed plastic cycle's net tensor change is below this fraction of its accumulated gain.
CLOSED_CYCLE_FRACTION = 0.1
#: Fewest cycles for a classification other than ``elastic``.
MIN_CYCLES = 2
#: Cycles the net change's trend is fitted over (a geometric rate, least squares in log).
TREND_CYCLES = 3
#: Net-change fractions within these multiples of :data:`CLOSED_CYCLE_FRACTION` are near the
#: threshold: the reason says so, with the trend that decides.
NEAR_THRESHOLD = (0.5, 2.0)


@dataclass(frozen=True)
class Shakedown:
    """The regime of a cyclic elastic-plastic path and why.

    Attributes
    ----------
    regime : str
        A key of :data:`SHAKEDOWN_FLAGS`.
    reason : str
        One sentence with the numbers the regime rests on.
    net_fraction : float
        The last cycle's net tensor change over its gain (NaN before a steady gain).
    net_trend : float
        The net change's rate per cycle fitted over the last :data:`TREND_CYCLES` cycles
        (below 1: it falls; NaN with fewer than two).
    more_cycles : int
        Cycles the trend needs to bring the net change under :data:`CLOSED_CYCLE_FRACTION` of
        the gain, when the regime waits on it (0 otherwise).
    """

    regime: str
    reason: str
    net_fraction: float = math.nan
    net_trend: float = math.nan
    more_cycles: int = 0

    @property
    def flag(self) -> int:
        """The regime's flag (:data:`SHAKEDOWN_FLAGS`)."""
        return SHAKEDOWN_FLAGS[self.regime]


def classify(
    gain: np.ndarray, net: np.ndarray, largest_strain: float, converged: bool = True
) -> Shakedown:
    """The shakedown regime of a cyclic path from its per-cycle plastic strain gains.

    Parameters
    ----------
    gain : ndarray
        Equivalent plastic strain gained per cycle (1), largest over the volume.
    net : ndarray
        Equivalent strain of the plastic strain tensor's change per cycle (1), largest over
        the volume.
    largest_strain : float
        Largest equivalent plastic strain (1) over the whole path, cycles or not.
    converged : bool
        Whether every increment of the path converged.

    Returns
    -------
    Shakedown
    """
    gain, net = np.asarray(gain, float), np.asarray(net, float)
    count = gain.size
    if not converged:
        return Shakedown("undetermined", "the path did not converge")
    if largest_strain <= PLASTIC_ZONE_THRESHOLD:
        return Shakedown(
            "elastic", f"largest equivalent plastic strain {largest_strain:.3g}, nowhere yielded"
        )
    if count < MIN_CYCLES:
        return Shakedown("undetermined", f"{count} cycle(s): at least {MIN_CYCLES} are needed")
    last, largest = float(gain[-1]), float(gain.max())
    gains = ", ".join(f"{g:.3g}" for g in gain)
    if last <= max(SHAKEDOWN_TOLERANCE * largest, PLASTIC_ZONE_THRESHOLD):
        return Shakedown(
            "elastic_shakedown",
            f"the last cycle gains {last:.3g} (the largest {largest:.3g}; per cycle: {gains})",
        )
    before = float(gain[-2])
    if last < STEADY_DECAY * before:
        return Shakedown(
            "undetermined",
            f"the gain per cycle still falls ({before:.3g} then {last:.3g}) above "
            f"{SHAKEDOWN_TOLERANCE:g} of the largest ({largest:.3g}): give more cycles",
        )
    closed = float(net[-1]) / last
    trend = net_trend(net)
    near = NEAR_THRESHOLD[0] <= closed / CLOSED_CYCLE_FRACTION < NEAR_THRESHOLD[1]
    evidence = (
        f"net change {float(net[-1]):.3g} = {closed:.2g} of the gain (closed below "
        f"{CLOSED_CYCLE_FRACTION:g}{', near it' if near else ''}), falling at {trend:.2g} per "
        f"cycle over the last {min(TREND_CYCLES, count)}"
    )
    if closed >= CLOSED_CYCLE_FRACTION and net[-1] < STEADY_NET * net[-2]:
        more = 0
        if 0.0 < trend < 1.0:  # geometric: net_k = net_last trend^k reaches the threshold
            more = math.ceil(math.log(CLOSED_CYCLE_FRACTION / closed) / math.log(trend))
        return Shakedown(
            "undetermined",
            f"steady gain {last:.3g} per cycle, but its net change still falls ({net[-2]:.3g} "
            f"then {net[-1]:.3g}): closed cycles or ratchetting, give more cycles"
            + (f" (about {more} more at this rate)" if more else "")
            + f"; {evidence}",
            closed, trend, more,
        )  # fmt: skip
    regime = "plastic_shakedown" if closed < CLOSED_CYCLE_FRACTION else "ratchetting"
    return Shakedown(
        regime,
        f"steady gain {last:.3g} per cycle (the one before {before:.3g}; per cycle: {gains}); "
        f"{evidence}",
        closed, trend,
    )  # fmt: skip


def net_trend(net: np.ndarray) -> float:
    """Geometric rate of the net change per cycle over the last :data:`TREND_CYCLES` cycles.

    The slope of ``log net`` against the cycle by least squares, exponentiated: 1 steady,
    below 1 falling; NaN with fewer than two positive values.
    """
    last = np.asarray(net, float)[-TREND_CYCLES:]
    last = last[last > 0.0]
    if last.size < 2:
        return math.nan
    slope = np.polyfit(np.arange(last.size), np.log(last), 1)[0]
    return float(np.exp(slope))


def shakedown_variable(regime: Shakedown | np.ndarray, dims: tuple[str, ...] = ()) -> tuple:
    """The CF flag variable ``shakedown``: ``(dims, flags, attrs)`` for an xarray dataset.

    ``regime`` is one :class:`Shakedown` (no ``dims``) or an integer array of flags over a
    campaign's ``dims``.
    """
    flags = regime.flag if isinstance(regime, Shakedown) else np.asarray(regime, np.int8)
    attrs = {
        "long_name": "shakedown regime of the cyclic path (solver.theory.shakedown)",
        "flag_values": np.array(list(SHAKEDOWN_FLAGS.values()), np.int8),
        "flag_meanings": " ".join(SHAKEDOWN_FLAGS),
    }
    if isinstance(regime, Shakedown):
        attrs["reason"] = regime.reason
        attrs.update(
            net_fraction=regime.net_fraction, net_trend=regime.net_trend,
            more_cycles=regime.more_cycles,
        )  # fmt: skip
    return dims, np.int8(flags) if not dims else flags, attrs


def sliding_first_yield(
    friction_coefficient: float, nu: float, contact: str = "point"
) -> tuple[float, float, float]:
    """First yield (von Mises) under a sliding Hertz contact, from its closed-form field.

    The largest von Mises stress of :func:`solver.theory.half_space.hamilton_stress` (a point
    contact: pressure p_0 and shear ``mu p`` along +x, over the plane y = 0) or of
    :func:`~solver.theory.half_space.mcewen_stress` (a line contact, plane strain), found on a
    grid of a/200 (x from -1.5 a to 1.5 a, depth from 1e-4 a to 1.2 a) and refined on a grid
    of a/20000 around the best point.

    Parameters
    ----------
    friction_coefficient : float
        mu (1).
    nu : float
        Poisson's ratio of the yielding body.
    contact : str
        ``"point"`` (a sphere) or ``"line"`` (a cylinder).

    Returns
    -------
    (float, float, float)
        ``p_0 / k`` at first yield (k = sigma_Y / sqrt 3, the shear yield stress) and the point
        ``(x / a, z / a)`` where it starts: below the surface for small mu (2.79 k at 0.48 a
        for a point contact, mu = 0, nu = 0.3, as :func:`solver.theory.hertz.first_yield_pressure`),
        on the surface at the trailing edge once mu is past about 0.3.
    """
    if contact not in ("point", "line"):
        raise ValueError(f"contact must be 'point' or 'line', got {contact!r}")
    x = np.linspace(-1.5, 1.5, 601)
    z = np.concatenate([[1e-4, 1e-3], np.linspace(0.005, 1.2, 240)])
    for _ in range(2):
        xs, zs = np.meshgrid(x, z, indexing="ij")
        if contact == "point":
            stress = hamilton_stress(xs, 0.0 * xs, zs, 1.0, 1.0, nu, friction_coefficient)
        else:
            stress = mcewen_stress(xs, zs, 1.0, 1.0, nu, friction_coefficient)
        equivalent = von_mises(stress)
        i, j = np.unravel_index(int(np.argmax(equivalent)), equivalent.shape)
        best = (float(xs[i, j]), float(zs[i, j]))
        x = np.linspace(best[0] - 0.01, best[0] + 0.01, 201)
        z = np.linspace(max(best[1] - 0.01, 1e-4), best[1] + 0.01, 201)
    return math.sqrt(3.0) / float(equivalent[i, j]), best[0], best[1]


def melan_factor(
    residual: np.ndarray, elastic: Iterable[np.ndarray], yield_stress: np.ndarray | float
) -> float:
    """Largest load factor for which a residual stress field proves shakedown (Melan 1938).

    Melan's static theorem: the body shakes down if one time-independent residual stress field
    ``rho`` keeps ``lambda sigma_e(t) + rho`` inside the yield surface everywhere at every load
    ``sigma_e(t)`` of the cycle.  For von Mises, ``|dev(lambda s + r)|^2 = 2/3 sigma_Y^2`` is a
    quadratic in lambda at each point; the field is admissible up to the smaller root's
    complement, the largest root, and the factor is its least value over points and loads.

    Parameters
    ----------
    residual : ndarray
        ``(6, ...)`` residual stress (Pa), :mod:`solver.numerics.tensor` order.
    elastic : iterable of ndarray
        The elastic stress fields ``(6, ...)`` (Pa) of the load at each of its positions.
    yield_stress : ndarray or float
        Yield stress (Pa) at each point (the current flow stress) or one for all.

    Returns
    -------
    float
        The factor lambda* (1): the case's load times lambda* is the lower bound this residual
        field gives; 0 where the residual field alone yields.
    """
    rho = deviator(residual)
    limit = (2.0 / 3.0) * np.asarray(yield_stress, float) ** 2
    c = contract(rho, rho) - limit
    if np.any(c > 0.0):
        return 0.0
    best = math.inf
    for field in elastic:
        s = deviator(field)
        a = contract(s, s)
        b = contract(s, rho)
        loaded = a > 0.0
        # the positive root of a l^2 + 2 b l + c = 0 (c <= 0, a > 0)
        roots = (-b[loaded] + np.sqrt(b[loaded] ** 2 - a[loaded] * c[loaded])) / a[loaded]
        if roots.size:
            best = min(best, float(roots.min()))
    return best
