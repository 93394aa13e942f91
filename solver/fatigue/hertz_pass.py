"""The criteria of a Hertz contact passing over a half-space, from the closed-form fields.

An independent reference for the criteria of a solved pass: the stress path of a material
point at depth z (and lateral offset y) as a Hertz contact (radius a, peak pressure p0, a
sliding traction mu p along the motion) passes along x is the contact's stationary field
at (x - X, y, z) for the contact's positions X: Hamilton's (1983) closed form for a circular
contact, McEwen's (1949) for a line contact (plane strain).  The path is sampled at
``samples`` relative positions x - X over +-``span`` a, where the field has fallen off (or
over a solved track's own extent about its contact, to compare with it: the ends of the
path count, the field falling off as (a / r)^2 only).

A fretting cycle (:func:`fretting_cycle_criteria`): a Hertz contact under a tangential force
cycled between -Q* and +Q*, Mindlin and Deresiewicz's tractions (beta = 0) at each sample of
the force, each a sum of Hertz-shaped shears whose fields are Hamilton's.
"""

from __future__ import annotations

import numpy as np

from ..theory.friction import mindlin_deresiewicz_terms
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


def fretting_cycle_criteria(
    points: tuple,
    radius: float,
    max_pressure: float,
    nu: float,
    limits: FatigueLimits,
    friction_coefficient: float,
    normal_force: float,
    amplitude: float,
    steps: int,
) -> FatigueResult:
    """The criteria of a cycle +Q* -> -Q* -> +Q* over a Hertz contact (module docstring).

    Parameters
    ----------
    points : (x, y, z)
        The field points (m), broadcastable arrays, ``z > 0``.
    radius, max_pressure : float
        Hertz's a (m) and p0 (Pa).
    nu : float
        The half-space's Poisson ratio.
    limits : FatigueLimits
        The material's fatigue limits.
    friction_coefficient, normal_force, amplitude : float
        mu, W (N) and Q* (N), Q* < mu W.
    steps : int
        Samples of each half cycle (the force at its ends, the reversals included).

    Returns
    -------
    FatigueResult
        One value per point (flattened in C order).
    """
    x, y, z = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in points))
    unit = friction_coefficient * max_pressure
    shears: dict[float, np.ndarray] = {}  # the shear field of each Hertz-shaped term's radius

    def shear(ratio: float) -> np.ndarray:
        if ratio not in shears:  # a Hertz-shaped shear of radius c, peak mu p0 c / a
            c, peak = ratio * radius, unit * ratio
            shears[ratio] = hamilton_stress(x, y, z, c, peak, nu, 1.0) - hamilton_stress(
                x, y, z, c, peak, nu, 0.0
            )
        return shears[ratio]

    normal = hamilton_stress(x, y, z, radius, max_pressure, nu)
    forces = amplitude * (1.0 - 2.0 * np.arange(1, steps + 1) / steps)  # Q* down to -Q*
    paths = []
    for unloading, half in ((True, forces), (False, -forces)):
        for force in half:
            terms = mindlin_deresiewicz_terms(
                force, amplitude, friction_coefficient, normal_force, unloading
            )
            paths.append(normal + sum(w * shear(c) for w, c in terms if c > 0.0))
    stacked = np.stack(paths, axis=-1).reshape(6, -1, 2 * steps)
    return fatigue_criteria(stacked, limits)
