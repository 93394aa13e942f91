"""Closed-form reference solutions: circular and elliptic Hertz contact.

Sources: Johnson, *Contact Mechanics* (1985), §3.9 and §4.2.  Composite compliance
``A = 1/E*``; the initial gap is ``h = x^2/(2 R_x) + y^2/(2 R_y)``.
"""

from __future__ import annotations

import functools
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


#: Rounds of the arithmetic-geometric mean at most (it needs fewer than 10 for k < 1 - 1e-15).
AGM_ROUNDS = 64


def complete_elliptic_integrals(k: float) -> tuple[float, float]:
    """Complete elliptic integrals K(k), E(k) of modulus ``k`` (0 <= k < 1), by the AGM.

    The AGM converges quadratically (a handful of rounds for any k < 1); it stops when ``c``
    is at round-off, or after :data:`AGM_ROUNDS` rounds (where a and b differ by an ulp).
    """
    if not 0.0 <= k < 1.0:
        raise ValueError(f"the modulus k must be in [0, 1), got {k!r}")
    a, b = 1.0, math.sqrt(1.0 - k * k)
    c = k
    power, total = 0.5, 0.5 * c * c
    for _ in range(AGM_ROUNDS):
        if abs(c) <= 1e-16 * a:
            break
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


def hertz_axis_stress(depth_over_radius, nu: float):
    """Stresses on the axis below a circular Hertz contact, over p_0 (Johnson 1985, eq. 3.45).

    Parameters
    ----------
    depth_over_radius : float or ndarray
        z / a (dimensionless), z > 0 into the body.
    nu : float
        Poisson's ratio of the body.

    Returns
    -------
    radial, axial, von_mises : ndarray
        ``sigma_r = sigma_theta``, ``sigma_z`` and the von Mises stress ``|sigma_r - sigma_z|``,
        each divided by p_0 (compression negative).
    """
    import numpy as np

    return _axis_stress(_axis_parts(np.asarray(depth_over_radius, dtype=float)), nu)


def _axis_parts(zeta):
    """The parts of :func:`hertz_axis_stress` that do not depend on nu, at depths ``zeta``."""
    import numpy as np

    return 1.0 - zeta * np.arctan2(1.0, zeta), 0.5 / (1.0 + zeta * zeta), -1.0 / (1.0 + zeta * zeta)


def _axis_stress(parts: tuple, nu: float):
    """(radial, axial, von Mises) over p_0 from :func:`_axis_parts`."""
    import numpy as np

    radial_unit, radial_extra, axial = parts
    radial = -(1.0 + nu) * radial_unit + radial_extra
    return radial, axial, np.abs(radial - axial)


@functools.lru_cache(maxsize=4)
def _axis_samples(stop: float, count: int) -> tuple:
    """Depths ``linspace(0, stop, count)``, their parts and coarse samples, built once.

    The parts are :func:`_axis_parts`; the coarse samples :func:`_coarse_samples`.
    """
    import numpy as np

    zeta = np.linspace(0.0, stop, count)
    parts = _axis_parts(zeta)
    return zeta, parts, _coarse_samples(zeta, parts)


#: Stride of the coarse samples of :func:`_axis_search`.
_AXIS_STRIDE = 64


def _axis_search(parts, coarse: tuple, nu: float, level: float | None = None):
    """The samples of the axis von Mises stress that can reach ``level`` (or the maximum).

    Returns ``(index, stress)``: sorted sample indices and their stress over p_0, exactly as
    :func:`_axis_stress` gives it over every sample (the same operations on each element), for
    every sample that can be at or above ``level`` (``None``: at or above the largest coarse
    value, so the maximum and its first sample are among them).

    Every :data:`_AXIS_STRIDE`-th sample is evaluated first.  On an interval ``[z0, z1]``
    between two of them the stress moves by at most ``L (z1 - z0)``, with
    ``L = |1 + nu| g(z0) + 3 m / (1 + m^2)^2``: ``g(z) = atan(1/z) - z / (1 + z^2)``, the
    slope of ``zeta atan(1/zeta)``, falls with z (``g' = -2 / (1 + z^2)^2``), and
    ``3 z / (1 + z^2)^2``, the slope of ``1.5 / (1 + z^2)``, peaks at ``z = 1/sqrt(3)``
    (``m`` is that point held in the interval).  Only the intervals whose ends come within
    that of the level are sampled in full: some thousands of samples instead of 2 10^5.
    """
    import numpy as np

    coarse, rough_parts, bend, hump, width = coarse
    rough = _axis_stress(rough_parts, nu)[2]
    reach = 1.01 * (abs(1.0 + nu) * bend + hump) * width + 1e-12  # a margin for round-off
    if level is None:
        level = float(rough.max())
    open_ = np.flatnonzero(np.maximum(rough[:-1], rough[1:]) + reach >= level)
    # runs of adjacent open intervals, each sampled in full with its ends
    cut = np.flatnonzero(np.diff(open_) > 1)
    runs = [(run[0], run[-1]) for run in np.split(open_, cut + 1) if run.size]
    pieces, start = [], 0  # in order: the coarse samples before a run, then the run in full
    for first, last in runs:
        pieces += [coarse[start:first], np.arange(coarse[first], coarse[last + 1] + 1)]
        start = last + 2
    index = np.concatenate([*pieces, coarse[start:]])
    return index, _axis_stress(tuple(p[index] for p in parts), nu)[2]


def _coarse_samples(zeta, parts: tuple) -> tuple:
    """The coarse samples of :func:`_axis_search` on depths ``zeta``, and their intervals.

    ``(indices, their parts, g(z0), 3 m / (1 + m^2)^2, z1 - z0)`` (:func:`_axis_search`).
    """
    import numpy as np

    coarse = np.arange(0, zeta.size, _AXIS_STRIDE)
    if coarse[-1] != zeta.size - 1:
        coarse = np.append(coarse, zeta.size - 1)
    z0, z1 = zeta[coarse[:-1]], zeta[coarse[1:]]
    bend = np.arctan2(1.0, z0) - z0 / (1.0 + z0 * z0)
    m = np.clip(1.0 / math.sqrt(3.0), z0, z1)
    hump = 3.0 * m / (1.0 + m * m) ** 2
    return coarse, tuple(p[coarse] for p in parts), bend, hump, z1 - z0


@functools.lru_cache(maxsize=64)  # a case asks twice: for its depth and for its volume check
def hertz_yield_region(max_pressure: float, yield_stress: float, nu: float) -> tuple[float, float]:
    """Depths z / a (top, bottom) between which the Hertz von Mises stress on the axis yields.

    The elastic prediction of the plastic zone on the contact axis (frictionless Hertz contact):
    the von Mises stress ``|sigma_r - sigma_z|`` exceeds ``yield_stress`` for ``top <= z / a <=
    bottom`` (one interval: the stress rises from 0.2 p_0 at the surface (nu = 0.3) to its
    maximum at 0.48 a and decays below).  ``(0, 0)`` when the contact stays elastic
    (``max_pressure`` below :func:`first_yield_pressure`); ``top`` is 0 when the surface yields.

    Parameters
    ----------
    max_pressure : float
        Hertz peak pressure p_0 (Pa).
    yield_stress : float
        Initial yield stress sigma_Y0 (Pa).
    nu : float
        Poisson's ratio.
    """
    zeta, parts, coarse = _axis_samples(20.0, 200001)
    ratio = yield_stress / max_pressure
    index, stress = _axis_search(parts, coarse, nu, ratio)
    above = index[stress - ratio >= 0]
    if above.size == 0:
        return 0.0, 0.0

    def crossing(k: int) -> float:  # linear interpolation between samples k and k + 1
        e0, e1 = _axis_stress(tuple(p[[k, k + 1]] for p in parts), nu)[2] - ratio
        return float(zeta[k] + e0 / (e0 - e1) * (zeta[k + 1] - zeta[k]))

    first, last = above[0], min(above[-1], zeta.size - 2)
    return (0.0 if first == 0 else crossing(first - 1)), crossing(last)


def hertz_yield_depth(max_pressure: float, yield_stress: float, nu: float) -> float:
    """Deepest z / a on the axis where the Hertz von Mises stress reaches ``yield_stress``.

    The bottom of :func:`hertz_yield_region`; 0 when the contact stays elastic.

    Parameters
    ----------
    max_pressure : float
        Hertz peak pressure p_0 (Pa).
    yield_stress : float
        Initial yield stress sigma_Y0 (Pa).
    nu : float
        Poisson's ratio.
    """
    return hertz_yield_region(max_pressure, yield_stress, nu)[1]


def hertz_yield_half_width(
    max_pressure: float,
    yield_stress: float,
    nu: float,
    traction_ratio: float = 0.0,
    depth: float = 3.0,
    reach: float = 3.0,
) -> float:
    """Largest lateral distance x / a or y / a where the elastic von Mises stress yields.

    The elastic prediction of the plastic zone's half width: the stress of a Hertz pressure
    with a sliding shear ``q_x = traction_ratio p``
    (:func:`solver.theory.half_space.hamilton_stress`, closed form) is sampled every 0.02 a in the
    planes ``y = 0`` and ``x = 0`` for ``0 < z <= depth``, ``|x|, |y|`` on the multiples of
    0.02 a up to ``reach`` (or the one past it); the largest
    ``|x|`` or ``|y|`` where the von Mises stress reaches ``yield_stress`` is returned (0 when
    nothing yields, ``reach`` when the region reaches the sampled edge).

    Parameters
    ----------
    max_pressure : float
        Hertz peak pressure p_0 (Pa).
    yield_stress : float
        Initial yield stress sigma_Y0 (Pa).
    nu : float
        Poisson's ratio.
    traction_ratio : float
        Shear over pressure of the sliding traction (dimensionless; 0: frictionless).
    depth, reach : float
        Sampled depth and half width (units of the contact radius a).
    """
    return _yield_half_width(
        round(yield_stress / max_pressure, 12), nu, traction_ratio, depth, reach
    )


@functools.lru_cache(maxsize=256)
def _yield_half_width(ratio: float, nu: float, traction: float, depth: float, reach: float):
    import numpy as np

    from ..numerics.tensor import von_mises
    from .half_space import stress_from_potential

    rows = len(np.arange(_YIELD_STEP / 2, depth + _YIELD_STEP / 2, _YIELD_STEP))

    def yielded(columns: slice, across, down, w) -> np.ndarray:
        """|x| or |y| of the yielded samples of these columns (all rows)."""
        w = {k: v[columns] for k, v in w.items()}
        stress = stress_from_potential(w, down[columns], nu, "pressure")
        if traction != 0.0:  # as solver.theory.half_space.hamilton_stress, p0 = a = 1
            stress = stress + traction * stress_from_potential(w, down[columns], nu, "shear_x")
        return np.abs(across[columns][von_mises(math.pi * 1.0 * stress) >= ratio])

    # The columns from both sides inwards, a block at a time: the first yielded columns
    # found are the outermost (every column left is nearer the axis); each column's values
    # are those of the whole plane's (elementwise).
    extent = 0.0
    for plane in range(2):
        across, down, w = _unit_potential(reach, rows, plane)
        count, middle = across.shape[0], across.shape[0] // 2
        for start in range(0, middle + 1, _YIELD_BLOCK):
            left = slice(start, min(start + _YIELD_BLOCK, middle + 1))
            right = slice(max(count - start - _YIELD_BLOCK, middle + 1), count - start)
            found = np.concatenate(
                [yielded(left, across, down, w), yielded(right, across, down, w)]
            )
            if found.size:
                extent = max(extent, float(found.max()))
                break
    return min(extent, reach)


#: Sampling step (units of a) of :func:`hertz_yield_half_width`.
_YIELD_STEP = 0.02
#: Columns of a plane :func:`hertz_yield_half_width` evaluates at a time, on each side.
_YIELD_BLOCK = 16
#: (reach, plane) -> (rows, lateral samples, depths, potential derivatives) of the largest
#: depth asked so far: the Hertz potential's derivatives on the sampled plane, which depend on
#: neither the load, the material nor the traction, so a design's cases share them.
_POTENTIALS: dict[tuple[float, int], tuple] = {}


def _unit_potential(reach: float, rows: int, plane: int):
    """Sample points and Hertz potential derivatives (a = 1) on a plane, the first ``rows`` depths.

    ``plane`` 0: y = 0, 1: x = 0.  Each value depends on its own point only (elementwise), so
    the first rows of a deeper sampling are those of a shallower one.
    """
    import numpy as np

    from .half_space import _hertz_radial_derivatives, _w_from_radial

    cached = _POTENTIALS.get((reach, plane))
    if cached is None or cached[0] < rows:
        step = _YIELD_STEP
        # one lattice whatever the reach (x = k step): a zone inside two reaches has one
        # extent, so a box sized within a window equals the zone that sized the window
        reaches = math.ceil(reach / step - 1e-9)
        lateral = step * np.arange(-reaches, reaches + 1)
        z = np.arange(step / 2, step * (rows - 0.5) + step / 2, step)[:rows]
        across, down = np.meshgrid(lateral, z, indexing="ij")
        x, y = (across, 0.0 * across) if plane == 0 else (0.0 * across, across)
        e = _hertz_radial_derivatives(x * x + y * y, down, 1.0)
        cached = (rows, across, down, _w_from_radial(e, x, y))
        _POTENTIALS[(reach, plane)] = cached
    _, across, down, w = cached
    return across[:, :rows], down[:, :rows], {k: v[:, :rows] for k, v in w.items()}


def first_yield_pressure(yield_stress: float, nu: float) -> tuple[float, float]:
    """Hertz peak pressure at first yield (frictionless) and the depth z / a where it starts.

    Returns ``(p_0, z/a)``: for nu = 0.3, p_0 = sigma_Y0 / 0.620 at z = 0.481 a (Johnson 1985).
    """
    import numpy as np

    zeta, parts, coarse = _axis_samples(3.0, 300001)
    index, stress = _axis_search(parts, coarse, nu)
    k = int(np.argmax(stress))  # the first of the largest, as over every sample
    return yield_stress / float(stress[k]), float(zeta[index[k]])


#: Independent axisymmetric finite-element solution (small strain) quoted by the project's
#: plasticity issue: rigid sphere R = 15 mm, frictionless, on E = 210 GPa, nu = 0.3 steel with
#: Swift hardening B = 945 MPa, C = 20, n = 0.121, loaded to W = 11179 N (p_H = 8 GPa) and
#: unloaded.  Lengths over a_H, strain dimensionless, pressure in Pa, dent in m.
FE_SWIFT_8GPA = {
    "max_pressure": 5.70e9,
    "contact_radius_over_a": 1.080,
    "max_plastic_strain": 0.0136,
    "max_plastic_strain_depth_over_a": 0.55,
    "plastic_zone_depth_over_a": 2.11,
    "residual_depth": 8.48e-6,
}
