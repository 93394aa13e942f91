"""Bodies, their constitutive behaviour, and the composite elastic constants of a pair.

Body 1 is the upper body (the indenter), body 2 the lower one; ``z`` points down, into body 2.
A rigid body contributes nothing to the compliances.  All quantities are SI (Pa, m).

Composite constants (DESIGN §3.1, seed eq. 1)::

    A     = (1 - nu1^2)/E1 + (1 - nu2^2)/E2              = 1/E*
    beta  = [(1+nu1)(1-2nu1)/(2E1) - (1+nu2)(1-2nu2)/(2E2)] / A
    C     = (1+nu1) nu1/E1 + (1+nu2) nu2/E2               (tangential x^2/r^3 term)
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import Literal

import numpy as np

from ..plasticity.hardening import Hardening
from .geometry import Geometry, Profile
from .heights import HeightMap, Roughness

Behaviour = Literal["rigid", "elastic", "elastic-plastic"]


@dataclass(frozen=True)
class Body:
    """One contacting body.

    Parameters
    ----------
    behaviour : {"rigid", "elastic", "elastic-plastic"}
        Constitutive behaviour.
    radius_x, radius_y : float
        Principal radii of curvature (m) in the x-z and y-z planes; ``math.inf`` for flat.
    E : float
        Young's modulus (Pa); ignored for rigid bodies.
    nu : float
        Poisson's ratio; ignored for rigid bodies.
    hardening : Hardening or None
        Hardening law, required for ``elastic-plastic``.
    profile : Profile or None
        An axisymmetric profile added to the quadric (:mod:`solver.bodies.geometry`).
    surface : HeightMap or None
        A height map added to the shape (:mod:`solver.bodies.heights`).
    roughness : Roughness or None
        A random roughness added to the shape (:mod:`solver.bodies.heights`).
    """

    behaviour: Behaviour
    radius_x: float = math.inf
    radius_y: float = math.inf
    E: float = math.inf
    nu: float = 0.0
    hardening: Hardening | None = None
    profile: Profile | None = None
    surface: HeightMap | None = None
    roughness: Roughness | None = None

    @property
    def rigid(self) -> bool:
        """True when the body does not deform."""
        return self.behaviour == "rigid"

    @property
    def compliance(self) -> float:
        """(1 - nu^2)/E (1/Pa); zero for a rigid body."""
        return 0.0 if self.rigid else (1.0 - self.nu**2) / self.E

    @property
    def dilatational_compliance(self) -> float:
        """(1 + nu)(1 - 2 nu)/(2 E) (1/Pa); zero for a rigid body."""
        return 0.0 if self.rigid else (1.0 + self.nu) * (1.0 - 2.0 * self.nu) / (2.0 * self.E)

    @property
    def shear_compliance(self) -> float:
        """(1 + nu) nu/E (1/Pa), the x^2/r^3 coefficient of the Cerruti solution."""
        return 0.0 if self.rigid else (1.0 + self.nu) * self.nu / self.E

    @property
    def shear_modulus(self) -> float:
        """G = E/(2(1 + nu)) (Pa); infinite for a rigid body."""
        return math.inf if self.rigid else self.E / (2.0 * (1.0 + self.nu))


def _shape(body: Body) -> Geometry:
    """One body's own shape, as a :class:`Geometry` of its heights alone."""
    surfaces = tuple(s for s in (body.surface, body.roughness) if s is not None)
    profiles = (body.profile,) if body.profile is not None else ()
    return Geometry((1.0 / body.radius_x, 1.0 / body.radius_y), profiles, surfaces)


@dataclass(frozen=True)
class Pair:
    """The two contacting bodies and their composite constants (each computed once)."""

    body1: Body
    body2: Body

    @functools.cached_property
    def compliance(self) -> float:
        """A = 1/E* (1/Pa)."""
        return self.body1.compliance + self.body2.compliance

    @property
    def composite_modulus(self) -> float:
        """E* = 1/A (Pa)."""
        return 1.0 / self.compliance

    @property
    def dundurs_beta(self) -> float:
        """Dundurs' beta (seed eq. 1), positive when body 2 is the stiffer in dilatation."""
        return (
            self.body1.dilatational_compliance - self.body2.dilatational_compliance
        ) / self.compliance

    @property
    def shear_coupling(self) -> float:
        """C = sum (1 + nu_i) nu_i / E_i (1/Pa), tangential-tangential cross coefficient."""
        return self.body1.shear_compliance + self.body2.shear_compliance

    @property
    def rolling_shear_modulus(self) -> float:
        """Kalker's combined shear modulus G (Pa), 2/G = 1/G1 + 1/G2 (a rigid body adds 0)."""
        return 2.0 / (1.0 / self.body1.shear_modulus + 1.0 / self.body2.shear_modulus)

    @property
    def rolling_poisson_ratio(self) -> float:
        """Kalker's combined Poisson's ratio nu (1), nu/G = (nu1/G1 + nu2/G2) / 2."""
        bodies = (self.body1, self.body2)
        weighted = sum(body.nu / body.shear_modulus for body in bodies)
        return 0.5 * self.rolling_shear_modulus * weighted

    @functools.cached_property
    def curvature(self) -> tuple[float, float]:
        """Composite curvatures (1/R_x, 1/R_y) (1/m) of the initial gap."""
        return (
            1.0 / self.body1.radius_x + 1.0 / self.body2.radius_x,
            1.0 / self.body1.radius_y + 1.0 / self.body2.radius_y,
        )

    def gap(
        self,
        x: np.ndarray,
        y: np.ndarray,
        position: tuple[float, float],
        period: tuple[float, float] | None = None,
    ) -> np.ndarray:
        """Initial gap (m) at ``x``, ``y`` (m) with body 1's apex at ``position`` (m) over body 2.

        At the origin this is :meth:`Geometry.gap` of :attr:`geometry` (bit for bit); elsewhere
        body 1's shape is evaluated at (x - px, y - py), body 2's where it is.  ``period`` (m):
        the heights are periodic (``grid.periodic``), body 1's shift wraps around.
        """
        px, py = position
        if px == 0.0 and py == 0.0:
            return self.geometry.gap(x, y, period)
        upper, lower = (_shape(body) for body in (self.body1, self.body2))
        return upper.gap(x - px, y - py, period) + lower.gap(x, y, period)

    def heights(self, body: int, x, y, period: tuple[float, float] | None = None) -> np.ndarray:
        """Body ``body``'s (1 or 2) own share of the initial gap (m) at ``x``, ``y`` (m)."""
        return _shape(self.body1 if body == 1 else self.body2).gap(x, y, period)

    @functools.cached_property
    def geometry(self) -> Geometry:
        """The initial gap of the pair: quadric part and both bodies' profiles."""
        bodies = (self.body1, self.body2)
        profiles = tuple(b.profile for b in bodies if b.profile is not None)
        surfaces = tuple(s for b in bodies for s in (b.surface, b.roughness) if s is not None)
        return Geometry(self.curvature, profiles, surfaces)
