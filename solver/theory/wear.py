"""The limit of fretting wear in partial slip: a sphere's stick zone carries the whole load.

A sphere (composite radius R, composite modulus E*) pressed by W and fretted in partial slip
at +-Q, |Q| < mu W, wears its slip annulus c <= r <= a only.  Its stick zone, of Cattaneo and
Mindlin's radius c = a (1 - Q / (mu W))^(1/3), does not slip, so it keeps its shape.  Wear
goes on while the annulus carries pressure, and stops when it carries none: in the limit
(Ciavarella and Hills 1999) the whole load rests on the unworn stick zone, whose profile is
the sphere's r^2 / 2R inside a contact of fixed radius c.  That is Hertz's pressure of radius
c plus a rigid flat punch's:

    p(r) = (2 E* / (pi R)) sqrt(c^2 - r^2) + P / (2 pi c sqrt(c^2 - r^2)),
    P = W - W_c,  W_c = 4 E* c^3 / (3 R)     (Hertz's load for a contact of radius c)

and the approach is delta = c^2 / R + P / (2 c E*).  The annulus is worn so that it just
touches without pressure:

    h(r) = delta - r^2 / (2 R) - u(r),   c <= r,

u the surface displacement the limit pressure makes there (Johnson 1985, eq. 3.42b for the
Hertz part, and the punch's (2 P / (2 pi c E*)) arcsin(c / r)).  h is the sum of both bodies'
worn depths.  It holds where the annulus still touches in the limit; where the wear made on
the way leaves a gap (the annulus's outer part can recede) the worn depth is deeper than h.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class FrettingWearLimit:
    """The limit state of a sphere fretted in partial slip (module docstring).

    Attributes
    ----------
    stick_radius : float
        c (m): Cattaneo and Mindlin's stick radius, which the limit keeps.
    punch_load : float
        P = W - W_c (N): the part of the load carried as by a flat punch of radius c.
    approach : float
        delta (m): the bodies' approach in the limit.
    radius, composite_modulus : float
        R (m) and E* (Pa).
    """

    stick_radius: float
    punch_load: float
    approach: float
    radius: float
    composite_modulus: float

    def pressure(self, r: np.ndarray) -> np.ndarray:
        """The limit pressure (Pa) at radii ``r`` (m); 0 outside the stick zone."""
        c, e, big = self.stick_radius, self.composite_modulus, self.radius
        r = np.asarray(r, dtype=float)
        root = np.sqrt(np.maximum(c * c - r * r, 0.0))
        with np.errstate(divide="ignore"):
            punch = np.where(root > 0, self.punch_load / (2.0 * math.pi * c * root), np.inf)
        return np.where(r < c, 2.0 * e / (math.pi * big) * root + punch, 0.0)

    def displacement(self, r: np.ndarray) -> np.ndarray:
        """The surfaces' summed normal displacement (m) the limit pressure makes at ``r >= c``."""
        c, e = self.stick_radius, self.composite_modulus
        r = np.maximum(np.asarray(r, dtype=float), c)
        peak = 2.0 * e * c / (math.pi * self.radius)  # Hertz's p0 on radius c
        angle = np.arcsin(c / r)
        hertz = peak / (2.0 * c * e) * ((2 * c * c - r * r) * angle + c * np.sqrt(r * r - c * c))
        punch = self.punch_load / (math.pi * c * e) * angle
        return hertz + punch

    def worn_depth(self, r: np.ndarray) -> np.ndarray:
        """The summed worn depth (m) at ``r >= c`` that just touches in the limit.

        Negative where the limit leaves a gap without wear.
        """
        r = np.asarray(r, dtype=float)
        return self.approach - r * r / (2.0 * self.radius) - self.displacement(r)


def fretting_wear_limit(
    normal_force: float, radius: float, composite_modulus: float, force_ratio: float
) -> FrettingWearLimit:
    """The limit state of a sphere fretted in partial slip (module docstring).

    Parameters
    ----------
    normal_force : float
        W (N).
    radius : float
        The composite radius R (m).
    composite_modulus : float
        E* (Pa).
    force_ratio : float
        The fretting amplitude over the sliding force, Q / (mu W), in [0, 1).
    """
    if not 0.0 <= force_ratio < 1.0:
        raise ValueError(f"force_ratio must be in [0, 1) (partial slip), got {force_ratio!r}")
    a = (3.0 * normal_force * radius / (4.0 * composite_modulus)) ** (1.0 / 3.0)
    c = a * (1.0 - force_ratio) ** (1.0 / 3.0)
    punch = normal_force - 4.0 * composite_modulus * c**3 / (3.0 * radius)
    approach = c * c / radius + punch / (2.0 * c * composite_modulus)
    return FrettingWearLimit(c, punch, approach, radius, composite_modulus)
