"""Frictionless contact of an axisymmetric profile on an elastic half-space (Sneddon 1965).

For a rigid-equivalent profile ``f(r)`` (the initial gap, m; ``f(0) = 0``, non-decreasing) pressed
by a normal force, the contact is a disc of radius ``a``, and with ``E*`` the composite modulus
(Sneddon, *Int. J. Engng Sci.* 3 (1965) 47; Johnson 1985 §5.2)::

    approach   d(a) = a    int_0^a f'(r) / sqrt(a^2 - r^2) dr
    force      P(a) = 2 E* int_0^a r^2 f'(r) / sqrt(a^2 - r^2) dr
    pressure   p(r) = (E*/pi) int_r^a g'(s) / sqrt(s^2 - r^2) ds,   g(s) = d(s)

(``g`` is the approach as a function of the radius: the "equivalent one-dimensional profile" of
the method of dimensionality reduction).  With ``r = a sin(phi)`` and ``s = r cosh(t)`` the
integrals are smooth and are taken by Gauss-Legendre quadrature, split where the profile's
curvature jumps (``breaks``).  Checks: a sphere (f' = r/R) gives Hertz, a cone (f' = tan alpha)
Love's ``P = (pi/2) E* a^2 tan(alpha)``, ``d = (pi/2) a tan(alpha)``,
``p = (E* tan(alpha)/2) arccosh(a/r)`` (tests/test_profiles.py).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

#: Gauss-Legendre nodes per smooth piece of an integral.
NODES = 48
_X, _W = np.polynomial.legendre.leggauss(NODES)

Slope = Callable[[np.ndarray], np.ndarray]


def _gauss(func: Callable[[np.ndarray], np.ndarray], cuts: list[float]) -> float:
    """Integral of ``func`` (vectorised) over [cuts[0], cuts[-1]], one rule per piece."""
    total = 0.0
    for lo, hi in zip(cuts[:-1], cuts[1:], strict=True):
        if hi > lo:
            half = 0.5 * (hi - lo)
            total += half * float(np.dot(_W, func(lo + half * (_X + 1.0))))
    return total


def _angle_cuts(a: float, breaks: tuple[float, ...]) -> list[float]:
    """Pieces of [0, pi/2] in phi = asin(r/a) at the break radii inside the disc."""
    inner = sorted(math.asin(b / a) for b in breaks if 0.0 < b < a)
    return [0.0, *inner, 0.5 * math.pi]


def approach(a: float, slope: Slope, breaks: tuple[float, ...] = ()) -> float:
    """Rigid-body approach d (m) of a contact of radius ``a`` (m)."""
    return a * _gauss(lambda phi: slope(a * np.sin(phi)), _angle_cuts(a, breaks))


def force(a: float, slope: Slope, e_star: float, breaks: tuple[float, ...] = ()) -> float:
    """Normal force P (N) of a contact of radius ``a`` (m); ``e_star`` (Pa)."""

    def integrand(phi):
        s = np.sin(phi)
        return s * s * slope(a * s)

    return 2.0 * e_star * a * a * _gauss(integrand, _angle_cuts(a, breaks))


def radius_for_force(
    load: float,
    slope: Slope,
    e_star: float,
    breaks: tuple[float, ...] = (),
    start: float = 0.0,
    limit: float = math.inf,
) -> float:
    """Contact radius (m) carrying ``load`` (N): P(a) = load by bisection on a in (start, limit).

    ``start`` is the radius below which the profile carries nothing (a flat face), ``limit`` the
    largest radius the profile allows.  Raises ValueError when the load needs a radius at or
    beyond ``limit``.
    """
    lo = start
    hi = min(2.0 * start if start > 0 else 1e-9, limit)
    while force(hi, slope, e_star, breaks) < load:
        if hi >= min(limit, 1e9):
            raise ValueError(f"the load needs a contact radius beyond {min(limit, 1e9):g} m")
        lo, hi = hi, min(2.0 * hi, limit)
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if force(mid, slope, e_star, breaks) < load:
            lo = mid
        else:
            hi = mid
        if hi - lo <= 1e-15 * hi:
            break
    return 0.5 * (lo + hi)


def pressure(
    r: np.ndarray,
    a: float,
    slope: Slope,
    curvature: Slope,
    e_star: float,
    breaks: tuple[float, ...] = (),
) -> np.ndarray:
    """Contact pressure (Pa) at radii ``r`` (m) of a contact of radius ``a``; 0 for r >= a.

    ``curvature`` is f''(r) (1/m).  At r = 0 the value is that at r = 1e-6 a (a cone's pressure
    grows as -log r there).  One quadrature per radius: give a radial table, not a grid.
    """

    def g_prime(s: np.ndarray) -> np.ndarray:  # d/ds of s int_0^{pi/2} f'(s sin phi) dphi
        out = np.empty(s.shape)
        for i, radius in enumerate(s):
            out[i] = _gauss(
                lambda phi, q=radius: (
                    slope(q * np.sin(phi)) + q * np.sin(phi) * curvature(q * np.sin(phi))
                ),
                _angle_cuts(radius, breaks),
            )
        return out

    flat = np.asarray(r, dtype=float)
    out = np.zeros(flat.shape)
    for index, radius in np.ndenumerate(flat):
        radius = max(abs(radius), 1e-6 * a)
        if radius >= a:
            continue
        top = math.acosh(a / radius)
        cuts = sorted({0.0, top, *(math.acosh(b / radius) for b in breaks if radius < b < a)})
        integral = _gauss(lambda t, q=radius: g_prime(q * np.cosh(t)), cuts)
        out[index] = e_star / math.pi * integral
    return out


@dataclass(frozen=True)
class SneddonContact:
    """Sneddon's solution for an axisymmetric gap under a normal force.

    Attributes
    ----------
    normal_force : float
        W (N).
    radius : float
        Contact radius a (m).
    approach : float
        Rigid-body approach d (m).
    mean_pressure : float
        W / (pi a^2) (Pa).
    table_radius, table_pressure : ndarray
        The pressure (Pa) on a radial table (m) that :meth:`pressure` interpolates.
    """

    normal_force: float
    radius: float
    approach: float
    mean_pressure: float
    table_radius: np.ndarray = field(compare=False, repr=False, default=None)
    table_pressure: np.ndarray = field(compare=False, repr=False, default=None)

    @property
    def semi_axis_x(self) -> float:
        """The contact radius (m): the disc's semi-axis along x."""
        return self.radius

    @property
    def semi_axis_y(self) -> float:
        """The contact radius (m): the disc's semi-axis along y."""
        return self.radius

    @property
    def max_semi_axis(self) -> float:
        """The contact radius (m)."""
        return self.radius

    def pressure(self, x, y):
        """Pressure (Pa) at points ``x``, ``y`` (m), interpolated in r; zero outside the disc."""
        r = np.hypot(np.asarray(x, dtype=float), np.asarray(y, dtype=float))
        return np.interp(r, self.table_radius, self.table_pressure, right=0.0)


#: Radii of the pressure table of :func:`contact`, in units of the contact radius.
TABLE_RADII = np.concatenate([[1e-3], np.linspace(0.01, 1.0, 100)])


def contact(
    load: float,
    slope: Slope,
    curvature: Slope,
    e_star: float,
    breaks: tuple[float, ...] = (),
    start: float = 0.0,
    limit: float = math.inf,
) -> SneddonContact:
    """Sneddon's contact under ``load`` (N) for the profile of ``slope`` and ``curvature``.

    Arguments as in :func:`radius_for_force` and :func:`pressure`.
    """
    a = radius_for_force(load, slope, e_star, breaks, start, limit)
    radii = TABLE_RADII * a
    return SneddonContact(
        load,
        a,
        approach(a, slope, breaks),
        load / (math.pi * a * a),
        radii,
        pressure(radii, a, slope, curvature, e_star, breaks),
    )
