"""The criteria of a Hertz contact passing over a half-space, from the closed-form fields.

An independent reference for the criteria of a solved pass: the stress path of a material
point at depth z (and lateral offset y) as a Hertz contact (radius a, peak pressure p0, a
sliding traction mu p along the motion) passes along x is the contact's stationary field
at (x - X, y, z) for the contact's positions X: Hamilton's (1983) closed form for a circular
contact, McEwen's (1949) for a line contact (plane strain).  The path is sampled at
``samples`` relative positions x - X over +-``span`` a, where the field has fallen off (or
over a solved track's own extent about its contact, to compare with it: the ends of the
path count, the field falling off as (a / r)^2 only).
"""

from __future__ import annotations

import numpy as np

from ..theory.half_space import hamilton_stress, mcewen_stress
from .criteria import FatigueLimits, FatigueResult, fatigue_criteria


def hertz_pass_criteria(
    radius: float,
    max_pressure: float,
    nu: float,
    limits: FatigueLimits,
    depths: np.ndarray,
    friction_coefficient: float = 0.0,
    line: bool = False,
    span: float | tuple[float, float] = 6.0,
    samples: int = 1201,
    lateral: float = 0.0,
) -> FatigueResult:
    """Dang Van's and Crossland's criteria at ``depths`` (m) (module docstring).

    Parameters
    ----------
    radius : float
        a (m): the contact radius (half-width of a line contact).
    max_pressure : float
        p0 (Pa).
    nu : float
        The half-space's Poisson ratio.
    limits : FatigueLimits
        The material's fatigue limits.
    depths : numpy.ndarray
        z (m), > 0.
    friction_coefficient : float
        mu of the sliding traction q_x = mu p.
    line : bool
        A line contact (plane strain) instead of a circular one.
    span, samples : float or (float, float), int
        The points' positions x - X relative to the contact: ``samples`` over +-``span`` a, or
        over ``span[0]`` a to ``span[1]`` a (a solved track's extent about its contact).
    lateral : float
        y (m) of the points off the path of the contact's centre (a circular contact).
    """
    low, high = (-span, span) if np.isscalar(span) else span
    relative = np.linspace(low * radius, high * radius, samples)
    x, z = np.meshgrid(relative, np.asarray(depths, dtype=float), indexing="ij")
    if line:
        stress = mcewen_stress(x, z, radius, max_pressure, nu, friction_coefficient)
    else:
        y = np.full_like(x, lateral)
        stress = hamilton_stress(x, y, z, radius, max_pressure, nu, friction_coefficient)
    return fatigue_criteria(np.moveaxis(stress, 1, 2), limits)  # (6, depths, samples)
