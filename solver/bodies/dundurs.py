"""Dundurs' beta as a design variable: body 1's elastic constants for a given beta.

A beta sweep holds body 2 and the composite modulus E* fixed, so the Hertz solution and the
grid are the same for every beta, and moves body 1 along its line of constant compliance
``c1 = (1 - nu1^2)/E1`` (:func:`body1_for_beta`); :func:`beta_range` is what that reaches.
"""

from __future__ import annotations

import math

from ..keys import MODULUS_RANGE
from .materials import Body


def _beta_factor(nu: float) -> float:
    """g(nu1) = (1 - 2 nu1) / (2 (1 - nu1)), through which beta depends on nu1."""
    return (1.0 - 2.0 * nu) / (2.0 * (1.0 - nu))


def _lowest_nu1(body1: Body) -> float:
    """Most negative nu1 with body 1's compliance held: where E1 reaches the smallest modulus."""
    return -math.sqrt(max(1.0 - MODULUS_RANGE[0] * body1.compliance, 0.0))


def beta_range(body1: Body, body2: Body) -> tuple[float, float]:
    """Range [low, high] of Dundurs' beta that :func:`body1_for_beta` can reach.

    Parameters
    ----------
    body1 : Body
        Elastic body 1 (its compliance ``(1 - nu1^2)/E1`` is held fixed).
    body2 : Body
        Body 2 (fixed; may be rigid).

    Returns
    -------
    (float, float)
        ``low`` is reached with ``nu1 = 0.5``; ``high`` with the most negative nu1 whose
        ``E1 = (1 - nu1^2)/c1`` is still the smallest modulus a case accepts
        (:data:`solver.keys.MODULUS_RANGE`, 1e3 Pa): ``nu1 -> -1`` would need ``E1 -> 0``.
        ``high`` lies just below the limit ``(3/4 c1 - d2)/A`` (by ~1e-9 relative for steel).
        Both ends are reachable.
    """
    c1, c2, d2 = body1.compliance, body2.compliance, body2.dilatational_compliance
    total = c1 + c2
    return -d2 / total, (_beta_factor(_lowest_nu1(body1)) * c1 - d2) / total


def body1_for_beta(
    beta: float, body1: Body, body2: Body, label: str = "beta"
) -> tuple[float, float]:
    """Body 1's (E1, nu1) that give Dundurs' beta with body 2 and E* unchanged.

    The rule: body 2 is fixed, and body 1 keeps its compliance ``c1 = (1 - nu1^2)/E1``, so the
    composite modulus E*, the Hertz solution and the grid stay the same across a beta sweep.
    With ``A = c1 + c2`` and ``d2 = (1 + nu2)(1 - 2 nu2)/(2 E2)``, beta depends on nu1 only
    through ``g(nu1) = (1 - 2 nu1)/(2 (1 - nu1)) = (beta A + d2)/c1 =: t``, which inverts to::

        nu1 = (1 - 2 t) / (2 (1 - t)),     E1 = (1 - nu1^2) / c1.

    ``g`` falls monotonically from 3/4 (nu1 -> -1) to 0 (nu1 = 1/2), so beta is reachable for
    ``-d2/A <= beta < (3/4 c1 - d2)/A``; but E1 falls to 0 as nu1 -> -1, so the upper end is
    where E1 reaches the smallest modulus a case accepts (1e3 Pa), a hair below that limit:
    :func:`beta_range` gives the closed range, both ends included.

    Parameters
    ----------
    beta : float
        Target Dundurs beta (dimensionless).
    body1 : Body
        Elastic body 1 of the base case (its E and nu set ``c1``).
    body2 : Body
        Body 2 (kept).
    label : str
        How messages name beta (a campaign passes its swept key).

    Returns
    -------
    (float, float)
        Young's modulus E1 (Pa) and Poisson's ratio nu1 of body 1.

    Raises
    ------
    ValueError
        If beta is outside the reachable range (the message gives the range, rounded inwards
        to 6 decimals so that both printed ends are reachable), or E1 would exceed the
        largest modulus accepted.
    """
    low, high = beta_range(body1, body2)
    c1, c2, d2 = body1.compliance, body2.compliance, body2.dilatational_compliance
    slack = 1e-12 * max(abs(low), abs(high), 1.0)  # round-off of beta_range itself
    if not (math.isfinite(beta) and low - slack <= beta <= high + slack):
        side = (
            "for a more negative beta make body 1 stiffer (raise body1.E in [base])"
            if beta < low
            else "for a larger beta make body 1 more compliant (lower body1.E in [base])"
        )
        shown_low, shown_high = math.ceil(low * 1e6) / 1e6, math.floor(high * 1e6) / 1e6
        raise ValueError(
            f"{label} = {beta!r} is not reachable: with body 2 fixed and E* = "
            f"{1.0 / (c1 + c2):.4g} Pa held, beta must lie in [{shown_low:.6f}, "
            f"{shown_high:.6f}] (nu1 from 0.5 down to where E1 reaches "
            f"{MODULUS_RANGE[0]:g} Pa); {side}"
        )
    nu_min = _lowest_nu1(body1)
    t = min(max((beta * (c1 + c2) + d2) / c1, 0.0), _beta_factor(nu_min))
    nu1 = max((1.0 - 2.0 * t) / (2.0 * (1.0 - t)), nu_min)
    young = max((1.0 - nu1 * nu1) / c1, MODULUS_RANGE[0])  # round-off at the upper end
    if young > MODULUS_RANGE[1]:
        raise ValueError(
            f"{label} = {beta!r} needs body1.E = {young:.4g} Pa (nu1 = {nu1:.4g}), beyond "
            f"the largest modulus accepted, {MODULUS_RANGE[1]:g} Pa; lower body1.E in [base]"
        )
    return young, nu1
