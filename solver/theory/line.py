r"""Line contact (plane strain): Hertz's cylinder and Carter's steady rolling.

Two elastic bodies uniform along y (cylinders along y, or a cylinder on a flat) pressed by a
force ``w`` per unit length (N/m), composite modulus ``E*`` (1/E* = sum (1 - nu_i^2)/E_i) and
composite radius ``R`` (1/R = 1/R_1 + 1/R_2) in the x-z plane.

**Hertz** (Johnson 1985, §4.3): a strip ``|x| < b`` with

    b^2 = 4 w R / (pi E*),    p(x) = p_0 sqrt(1 - x^2 / b^2),    p_0 = 2 w / (pi b) = b E* / (2 R).

**Carter** (1926; Johnson 1985, §8.3): steady rolling along +x of two bodies of the same
material (no normal-tangential coupling) at the longitudinal creepage ``xi``, Coulomb friction
``mu``.  With the steady slip ``s = -d_x u_x - xi`` (the signs of
:mod:`solver.surface.steady`) and the plane-strain relative displacement
``d_x u_x(x) = -(2 / (pi E*)) PV int q(t) / (x - t) dt``, the traction on body 2

    q(x) = sgn(xi) mu p_0 [sqrt(1 - x^2 / b^2) - (c / b) sqrt(1 - (x - d)^2 / c^2)]

(the second term inside the stick strip ``|x - d| < c`` only, ``d = b - c``: the stick strip
touches the leading edge) makes ``d_x u_x = -2 mu p_0 d / (b E*) = -mu d / R`` constant there:
the slip vanishes when ``d = |xi| R / mu``.  So ``c / b = 1 - |xi| R / (mu b)`` and the creep
force ``F = sgn(xi) mu w (1 - (c / b)^2)`` up to full slip at ``|xi| = mu b / R``.  (Derived
here from the two principal values ``PV int sqrt(1 - t^2/b^2) / (x - t) dt = pi x / b``.)
"""

from __future__ import annotations

import math

import numpy as np


def hertz_line(force_per_length: float, composite_modulus: float, radius: float):
    """Hertz's line contact: half-width ``b`` (m) and peak pressure ``p_0`` (Pa).

    Parameters
    ----------
    force_per_length : float
        w (N/m), > 0.
    composite_modulus : float
        E* (Pa).
    radius : float
        Composite radius R (m) in the plane of the section.

    Returns
    -------
    (float, float)
        ``(b, p_0)``.
    """
    half_width = math.sqrt(4.0 * force_per_length * radius / (math.pi * composite_modulus))
    return half_width, 2.0 * force_per_length / (math.pi * half_width)


def carter_stick_ratio(
    creepage: float, friction_coefficient: float, half_width: float, radius: float
) -> float:
    """Carter's stick-strip half-width over the contact's, ``c / b`` (0 in full slip)."""
    return max(1.0 - abs(creepage) * radius / (friction_coefficient * half_width), 0.0)


def carter_force_ratio(
    creepage: float, friction_coefficient: float, half_width: float, radius: float
) -> float:
    """Carter's creep force over ``mu w`` (signed with the creepage): ``1 - (c / b)^2``."""
    ratio = carter_stick_ratio(creepage, friction_coefficient, half_width, radius)
    return math.copysign(1.0 - ratio * ratio, creepage)


def carter_traction(
    x: np.ndarray,
    creepage: float,
    friction_coefficient: float,
    half_width: float,
    radius: float,
    max_pressure: float,
) -> np.ndarray:
    """Carter's shear traction q_x (Pa) on body 2 at ``x`` (m), rolling along +x (module)."""
    x = np.asarray(x, dtype=float)
    b, mu = half_width, friction_coefficient
    c = carter_stick_ratio(creepage, mu, b, radius) * b
    full = np.sqrt(np.clip(1.0 - (x / b) ** 2, 0.0, None))
    if c > 0.0:
        full = full - (c / b) * np.sqrt(np.clip(1.0 - ((x - (b - c)) / c) ** 2, 0.0, None))
    return math.copysign(1.0, creepage) * mu * max_pressure * full


__all__ = ["carter_force_ratio", "carter_stick_ratio", "carter_traction", "hertz_line"]
