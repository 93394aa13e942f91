"""Shapes of the contacting bodies and the initial gap of a pair.

A body's surface is a quadric (radii of curvature, :class:`~solver.bodies.materials.Body`) plus, at
most, one analytic axisymmetric profile (a :class:`Cone`, a :class:`FlatPunch` with rounded
edges, or a :class:`PowerLaw`), plus heights given point by point (a height map, a random
roughness: :mod:`solver.bodies.heights`).  Heights are measured away from the other body (a sphere's
sag ``r^2/(2R)``), in metres, from the body's apex on the z axis; the initial gap of a pair is
the sum of both bodies' heights (:class:`Geometry`).

The closed-form reference a case is scaled by (its contact radius sets the domain in units of
``half_width``) is that of the smooth part: Hertz's for quadric pairs, Sneddon's
(:mod:`solver.theory.sneddon`) for axisymmetric pairs with a profile, none for a gap made of point
heights only (the domain is then given in metres): :meth:`Geometry.reference`.  With point
heights it is a first estimate, not the answer.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ..keys import MAX_SURFACE_SLOPE
from ..theory import sneddon
from ..theory.hertz import HertzContact, hertz

#: Largest surface slope (dz/dr) a profile may have inside the contact (:mod:`solver.keys`).
MAX_PROFILE_SLOPE = MAX_SURFACE_SLOPE
#: Slope of a flat punch's side beyond its rounded edge (the gap keeps growing there; no
#: accepted load brings it into contact, :meth:`FlatPunch.height`).
PUNCH_SIDE_SLOPE = 10.0


@dataclass(frozen=True)
class Cone:
    """A cone: h = r tan(angle).

    Parameters
    ----------
    angle : float
        Angle between the cone's surface and the tangent plane (degrees), in (0, 45].
    """

    angle: float
    shape: ClassVar[str] = "cone"
    breaks: ClassVar[tuple[float, ...]] = ()  # radii (m) where the curvature jumps
    start: ClassVar[float] = 0.0  # radius (m) up to which the profile is flat
    extent: ClassVar[float] = math.inf  # largest radius (m) of the smooth profile

    @property
    def _tan(self) -> float:
        return math.tan(math.radians(self.angle))

    def height(self, r: np.ndarray) -> np.ndarray:
        """Height h(r) (m) at radii ``r`` (m)."""
        return self._tan * np.asarray(r, dtype=float)

    def slope(self, r: np.ndarray) -> np.ndarray:
        """dh/dr (dimensionless)."""
        return np.full(np.shape(r), self._tan)

    def curvature(self, r: np.ndarray) -> np.ndarray:
        """d^2h/dr^2 (1/m)."""
        return np.zeros(np.shape(r))

    def spec(self) -> dict:
        """The profile's table (SI units, angle in degrees)."""
        return {"shape": self.shape, "angle": self.angle}


@dataclass(frozen=True)
class FlatPunch:
    """A flat punch of face radius ``radius`` whose edge is rounded with ``edge_radius``.

    h = 0 for r <= b, and the circular arc h = rho - sqrt(rho^2 - (r - b)^2) beyond, up to
    r = b + rho where the arc turns vertical; further out the side is a steep cone (slope
    :data:`PUNCH_SIDE_SLOPE`), which no accepted load reaches.

    Parameters
    ----------
    radius : float
        Radius b of the flat face (m).
    edge_radius : float
        Radius rho of the rounded edge (m).
    """

    radius: float
    edge_radius: float
    shape: ClassVar[str] = "flat_punch"

    @property
    def breaks(self) -> tuple[float, ...]:
        """Radii (m) where the curvature jumps."""
        return (self.radius,)

    def height(self, r: np.ndarray) -> np.ndarray:
        """Height h(r) (m) at radii ``r`` (m)."""
        b, rho = self.radius, self.edge_radius
        s = np.clip(np.asarray(r, dtype=float) - b, 0.0, None)
        arc = rho - np.sqrt(np.clip(rho * rho - s * s, 0.0, None))
        return np.where(s < rho, arc, rho + PUNCH_SIDE_SLOPE * (s - rho))

    def slope(self, r: np.ndarray) -> np.ndarray:
        """dh/dr (dimensionless), inside the arc (r < b + rho)."""
        s = np.clip(np.asarray(r, dtype=float) - self.radius, 0.0, None)
        return s / np.sqrt(self.edge_radius**2 - s * s)

    def curvature(self, r: np.ndarray) -> np.ndarray:
        """d^2h/dr^2 (1/m), inside the arc; 0 on the face."""
        s = np.asarray(r, dtype=float) - self.radius
        rho2 = self.edge_radius**2
        return np.where(s > 0, rho2 / np.sqrt(rho2 - np.clip(s, 0, None) ** 2) ** 3, 0.0)

    @property
    def start(self) -> float:
        """Radius (m) up to which the profile is flat: the face."""
        return self.radius

    @property
    def extent(self) -> float:
        """Largest radius (m) of the smooth profile: where the arc turns vertical."""
        return self.radius + self.edge_radius

    def spec(self) -> dict:
        """The profile's table (SI units)."""
        return {"shape": self.shape, "radius": self.radius, "edge_radius": self.edge_radius}


@dataclass(frozen=True)
class PowerLaw:
    """A power-law profile h = A r^k.

    Parameters
    ----------
    coefficient : float
        A (m^(1-k)).
    exponent : float
        k, in [1, 8] (1: a cone, 2: a paraboloid of radius 1/(2A)).
    """

    coefficient: float
    exponent: float
    shape: ClassVar[str] = "power"
    breaks: ClassVar[tuple[float, ...]] = ()
    start: ClassVar[float] = 0.0
    extent: ClassVar[float] = math.inf

    def height(self, r: np.ndarray) -> np.ndarray:
        """Height h(r) (m) at radii ``r`` (m)."""
        return self.coefficient * np.abs(np.asarray(r, dtype=float)) ** self.exponent

    def slope(self, r: np.ndarray) -> np.ndarray:
        """dh/dr (dimensionless)."""
        k = self.exponent
        return k * self.coefficient * np.abs(np.asarray(r, dtype=float)) ** (k - 1.0)

    def curvature(self, r: np.ndarray) -> np.ndarray:
        """d^2h/dr^2 (1/m) (r > 0)."""
        k = self.exponent
        if k == 1.0:
            return np.zeros(np.shape(r))
        return k * (k - 1.0) * self.coefficient * np.abs(np.asarray(r, dtype=float)) ** (k - 2.0)

    def spec(self) -> dict:
        """The profile's table (SI units)."""
        return {"shape": self.shape, "coefficient": self.coefficient, "exponent": self.exponent}


Profile = Cone | FlatPunch | PowerLaw
#: Profile shapes by name (``bodyN.profile.shape``) and the keys each takes.
PROFILES: dict[str, type] = {"cone": Cone, "flat_punch": FlatPunch, "power": PowerLaw}
PROFILE_KEYS: dict[str, tuple[str, ...]] = {
    "cone": ("angle",),
    "flat_punch": ("radius", "edge_radius"),
    "power": ("coefficient", "exponent"),
}


@dataclass(frozen=True)
class Geometry:
    """The initial gap of a pair: a quadric part plus the bodies' axisymmetric profiles.

    Parameters
    ----------
    curvature : (float, float)
        Composite curvatures (1/R_x, 1/R_y) (1/m) of the quadric part.
    profiles : tuple
        The profiles of both bodies (:data:`Profile`), on the common z axis.
    surfaces : tuple
        Point heights of both bodies (:class:`~solver.bodies.heights.HeightMap`,
        :class:`~solver.bodies.heights.Roughness`).
    """

    curvature: tuple[float, float]
    profiles: tuple = ()
    surfaces: tuple = ()

    @property
    def reference_kind(self) -> str | None:
        """The closed form of the smooth part: "hertz", "sneddon", or None (none)."""
        if self.profiles:
            return "sneddon"
        kx, ky = self.curvature
        return "hertz" if kx > 0 and ky > 0 else None

    @property
    def hertzian(self) -> bool:
        """True when the smooth part is a quadric: Hertz's closed form is the reference."""
        return self.reference_kind == "hertz"

    @property
    def exact(self) -> bool:
        """True when the reference is the exact elastic answer (no point heights)."""
        return not self.surfaces

    def gap(
        self, x: np.ndarray, y: np.ndarray, period: tuple[float, float] | None = None
    ) -> np.ndarray:
        """Initial gap h(x, y) (m) at points ``x``, ``y`` (m).

        ``period`` (m): the heights are one period of a periodic surface (``grid.periodic``).
        """
        kx, ky = self.curvature
        h = 0.5 * (kx * x * x + ky * y * y)
        if self.profiles:
            r = np.hypot(x, y)
            for profile in self.profiles:
                h = h + profile.height(r)
        for surface in self.surfaces:
            h = h + surface.sample(x, y, period)
        return h

    # -- the axisymmetric gap (profiles; the quadric part then circular) ----------------------
    def slope(self, r: np.ndarray) -> np.ndarray:
        """dh/dr (dimensionless) of an axisymmetric gap."""
        out = self.curvature[0] * np.asarray(r, dtype=float)
        for profile in self.profiles:
            out = out + profile.slope(r)
        return out

    def second_derivative(self, r: np.ndarray) -> np.ndarray:
        """d^2h/dr^2 (1/m) of an axisymmetric gap."""
        out = np.full(np.shape(r), self.curvature[0])
        for profile in self.profiles:
            out = out + profile.curvature(r)
        return out

    @property
    def breaks(self) -> tuple[float, ...]:
        """Radii (m) where the curvature of the gap jumps."""
        return tuple(sorted({b for p in self.profiles for b in p.breaks}))

    @property
    def start(self) -> float:
        """Radius (m) within which the gap is flat (contact at any load)."""
        return max((p.start for p in self.profiles), default=0.0)

    @property
    def slope_limit(self) -> float:
        """Largest contact radius (m): where the gap's slope reaches :data:`MAX_PROFILE_SLOPE`."""
        extent = min((p.extent for p in self.profiles), default=math.inf)
        lo = self.start
        if float(self.slope(np.array([lo]))[0]) > MAX_PROFILE_SLOPE:
            return lo
        hi = extent if math.isfinite(extent) else max(2.0 * lo, 1e-9)
        while math.isinf(extent) and float(self.slope(np.array([hi]))[0]) <= MAX_PROFILE_SLOPE:
            if hi > 1e9:
                return math.inf  # a cone below the limit and no sphere: never steeper
            hi *= 2.0
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            if float(self.slope(np.array([mid]))[0]) <= MAX_PROFILE_SLOPE:
                lo = mid
            else:
                hi = mid
            if hi - lo <= 1e-14 * hi:
                break
        return lo

    def reference(self, force: float, e_star: float) -> HertzContact | sneddon.SneddonContact:
        """The closed-form elastic contact of the smooth part under ``force`` (N).

        Hertz's for a quadric gap, Sneddon's for an axisymmetric gap with a profile; ``e_star``
        the composite modulus (Pa).  Raises ValueError when Sneddon's contact would pass
        :attr:`slope_limit`, or when there is no smooth part (:attr:`reference_kind` None).
        """
        if self.reference_kind is None:
            raise ValueError("a gap of point heights only has no closed-form reference")
        if self.hertzian:
            return hertz(force, e_star, self.curvature)
        return sneddon.contact(
            force, self.slope, self.second_derivative, e_star, self.breaks, self.start,
            self.slope_limit,
        )  # fmt: skip

    def force_at_radius(self, radius: float, e_star: float) -> float:
        """Normal force (N) whose Sneddon contact has radius ``radius`` (m): a profile's.

        0 without a profile (point heights only, :attr:`reference_kind` None).
        """
        if self.reference_kind != "sneddon":
            return 0.0
        return sneddon.force(max(radius, self.start), self.slope, e_star, self.breaks)
