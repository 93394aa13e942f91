"""Gross-slip wear of an axisymmetric contact by the method of dimensionality reduction (MDR).

An independent reference for :mod:`solver.drive.wear`: Popov and Heß's MDR (Popov and Heß
2015, *Method of dimensionality reduction in contact mechanics and friction*, Springer; its
use for wear: Dimaki, Dmitriev, Chai and Popov 2016, Tribology International 93, 2016) maps
the frictionless normal contact of an axisymmetric gap f(r) on an elastic half-space
(composite modulus E*) onto a row of independent springs of stiffness E* dx along x, with
the equivalent gap

    g(x) = |x| int_0^|x| f'(r) / sqrt(x^2 - r^2) dr = x int_0^(pi/2) f'(x sin t) dt.

Pressed by W, the contact radius a and the approach d = g(a) solve
W = 2 E* int_0^a (d - g(x)) dx, and the pressure is

    p(r) = (E* / pi) int_r^a g'(x) / sqrt(x^2 - r^2) dx
         = (E* / pi) int_0^sqrt(a^2 - r^2) g'(x) / x du,   x = sqrt(r^2 + u^2).

In gross slip with every contact point slipping s per cycle (a stroke small beside a) Archard's
law wears the gap by k s p(r) per cycle: integrated here by explicit steps of a fraction of a
cycle count, each solving the contact of the current gap.  Exact for axisymmetric contact
without the shear's coupling to the pressure (Dundurs' beta = 0).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: Points of the quadratures in t and u.
QUADRATURE = 200


@dataclass(frozen=True)
class MdrWear:
    """The worn state of :func:`mdr_gross_slip_wear`.

    Attributes
    ----------
    radius : numpy.ndarray
        r (m), the radial grid.
    worn_depth : numpy.ndarray
        The depth worn (m) at each r: the gap's growth.
    pressure : numpy.ndarray
        The pressure (Pa) at each r at the end.
    contact_radius : float
        a (m) at the end.
    """

    radius: np.ndarray
    worn_depth: np.ndarray
    pressure: np.ndarray
    contact_radius: float


def equivalent_gap(r: np.ndarray, gap: np.ndarray, x: np.ndarray) -> np.ndarray:
    """MDR's g(x) (m) of the axisymmetric gap ``gap`` (m) at radii ``r`` (module docstring)."""
    slope = np.gradient(gap, r)
    t = (np.arange(QUADRATURE) + 0.5) * (0.5 * math.pi / QUADRATURE)  # midpoint rule
    inner = np.interp(np.outer(x, np.sin(t)), r, slope)
    return x * inner.sum(axis=1) * (0.5 * math.pi / QUADRATURE)


def _contact(x: np.ndarray, g: np.ndarray, force: float, modulus: float) -> float:
    """The contact radius a (m) at which 2 E* int_0^a (g(a) - g(x)) dx = W (bisection)."""

    def pressed(a: float) -> float:
        inside = x <= a
        depth = np.interp(a, x, g) - g[inside]
        return 2.0 * modulus * float(np.trapezoid(depth, x[inside])) if inside.sum() > 1 else 0.0

    low, high = x[1], x[-1]
    if pressed(high) < force:
        raise ValueError("the radial grid is too short for the load: raise its extent")
    for _ in range(80):
        middle = 0.5 * (low + high)
        low, high = (middle, high) if pressed(middle) < force else (low, middle)
    return 0.5 * (low + high)


def mdr_pressure(r: np.ndarray, x: np.ndarray, g: np.ndarray, a: float, modulus: float):
    """The pressure (Pa) at radii ``r`` of MDR's gap ``g`` at ``x`` in contact over ``a``."""
    slope = np.gradient(g, x)
    out = np.zeros_like(r)
    share = (np.arange(QUADRATURE) + 0.5) / QUADRATURE
    for i, radius in enumerate(r):
        if radius >= a:
            continue
        u = share * math.sqrt(a * a - radius * radius)
        xs = np.sqrt(radius * radius + u * u)
        out[i] = modulus / math.pi * float(np.sum(np.interp(xs, x, slope) / xs)) * (u[1] - u[0])
    return out


def mdr_gross_slip_wear(
    radius: float,
    normal_force: float,
    modulus: float,
    wear_per_pressure: float,
    cycles: float,
    steps: int = 400,
    points: int = 1200,
) -> MdrWear:
    """A sphere's gross-slip wear by MDR (module docstring).

    Parameters
    ----------
    radius : float
        The sphere's radius R (m): the gap r^2 / 2R.
    normal_force : float
        W (N).
    modulus : float
        E* (Pa).
    wear_per_pressure : float
        k s: the depth worn per cycle per pressure (m/Pa), Archard's k (1/Pa) times the slip
        s of a cycle (m).
    cycles : float
        The cycles worn.
    steps, points : int
        The explicit steps and the radial grid's points.
    """
    a0 = (3.0 * normal_force * radius / (4.0 * modulus)) ** (1.0 / 3.0)
    r = np.linspace(0.0, 3.0 * a0, points)
    worn = np.zeros_like(r)
    for _ in range(steps):
        gap = r * r / (2.0 * radius) + worn
        g = equivalent_gap(r, gap, r)
        a = _contact(r, g, normal_force, modulus)
        pressure = mdr_pressure(r, r, g, a, modulus)
        worn = worn + wear_per_pressure * (cycles / steps) * pressure
    gap = r * r / (2.0 * radius) + worn
    g = equivalent_gap(r, gap, r)
    a = _contact(r, g, normal_force, modulus)
    return MdrWear(r, worn, mdr_pressure(r, r, g, a, modulus), a)
