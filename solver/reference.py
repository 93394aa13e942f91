"""Closed-form reference solutions: circular and elliptic Hertz contact.

Sources: Johnson, *Contact Mechanics* (1985), §3.9 and §4.2.  Composite compliance
``A = 1/E*``; the initial gap is ``h = x^2/(2 R_x) + y^2/(2 R_y)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class HertzContact:
    """Hertz solution for a normal force.

    Attributes
    ----------
    normal_force : float
        W (N).
    semi_axis_x, semi_axis_y : float
        Semi-axes of the contact ellipse along x and y (m); equal for circular contact.
    max_pressure : float
        p_0 = 3 W / (2 pi a b) (Pa).
    approach : float
        Rigid-body approach delta (m).
    """

    normal_force: float
    semi_axis_x: float
    semi_axis_y: float
    max_pressure: float
    approach: float

    @property
    def radius(self) -> float:
        """Equivalent contact radius sqrt(a b) (m)."""
        return math.sqrt(self.semi_axis_x * self.semi_axis_y)

    @property
    def max_semi_axis(self) -> float:
        """Larger semi-axis (m)."""
        return max(self.semi_axis_x, self.semi_axis_y)

    def pressure(self, x, y):
        """Hertz pressure (Pa) at points ``x``, ``y`` (m); zero outside the ellipse."""
        import numpy as np

        rho2 = (np.asarray(x) / self.semi_axis_x) ** 2 + (np.asarray(y) / self.semi_axis_y) ** 2
        return self.max_pressure * np.sqrt(np.clip(1.0 - rho2, 0.0, None))


def complete_elliptic_integrals(k: float) -> tuple[float, float]:
    """Complete elliptic integrals K(k), E(k) of modulus ``k`` (0 <= k < 1), by the AGM."""
    a, b = 1.0, math.sqrt(1.0 - k * k)
    c = k
    power, total = 0.5, 0.5 * c * c
    while abs(c) > 1e-16 * a:
        a, b, c = 0.5 * (a + b), math.sqrt(a * b), 0.5 * (a - b)
        power *= 2.0
        total += power * c * c
    big_k = math.pi / (2.0 * a)
    return big_k, big_k * (1.0 - total)


def hertz(normal_force: float, composite_modulus: float, curvature: tuple[float, float]):
    """Hertz contact of two quadric bodies under a normal force.

    Parameters
    ----------
    normal_force : float
        W (N), > 0.
    composite_modulus : float
        E* (Pa).
    curvature : (float, float)
        Composite curvatures 1/R_x, 1/R_y (1/m), both > 0.

    Returns
    -------
    HertzContact
    """
    kx, ky = curvature
    if not (kx > 0 and ky > 0):
        raise ValueError("Hertz contact needs positive composite curvature in x and y")
    if math.isclose(kx, ky, rel_tol=1e-12):
        r_star = 1.0 / kx
        a = (3.0 * normal_force * r_star / (4.0 * composite_modulus)) ** (1.0 / 3.0)
        p0 = 3.0 * normal_force / (2.0 * math.pi * a * a)
        return HertzContact(normal_force, a, a, p0, a * a / r_star)
    # Long semi-axis along the direction of smaller curvature.  With A = k_small/2,
    # B = k_large/2 and e^2 = 1 - (b/a)^2:  B/A = (E/(1-e^2) - K)/(K - E).
    k_small, k_large = min(kx, ky), max(kx, ky)
    ratio = k_large / k_small

    def excess(e: float) -> float:
        big_k, big_e = complete_elliptic_integrals(e)
        return (big_e / (1.0 - e * e) - big_k) / (big_k - big_e) - ratio

    lo, hi = 1e-8, 1.0 - 1e-15
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if excess(mid) > 0.0:
            hi = mid
        else:
            lo = mid
    e = 0.5 * (lo + hi)
    big_k, big_e = complete_elliptic_integrals(e)
    a_long = (
        3.0
        * normal_force
        * (big_k - big_e)
        / (2.0 * math.pi * composite_modulus * e * e * 0.5 * k_small)
    ) ** (1.0 / 3.0)
    b_short = a_long * math.sqrt(1.0 - e * e)
    p0 = 3.0 * normal_force / (2.0 * math.pi * a_long * b_short)
    approach = p0 * b_short * big_k / composite_modulus
    if kx <= ky:
        return HertzContact(normal_force, a_long, b_short, p0, approach)
    return HertzContact(normal_force, b_short, a_long, p0, approach)


def hertz_force_for_pressure(
    max_pressure: float, composite_modulus: float, curvature: tuple[float, float]
) -> float:
    """Normal force W (N) whose Hertz peak pressure is ``max_pressure`` (Pa).

    p_0 scales as W^(1/3) for any ellipticity, so one unit-force evaluation suffices.
    """
    p_unit = hertz(1.0, composite_modulus, curvature).max_pressure
    return (max_pressure / p_unit) ** 3


def cattaneo_stick_ratio(tangential_force: float, friction_coefficient: float, normal_force: float):
    """Cattaneo-Mindlin stick radius c/a = (1 - Q/(mu W))^(1/3) for beta = 0."""
    return (1.0 - tangential_force / (friction_coefficient * normal_force)) ** (1.0 / 3.0)
