"""Closed forms of tangential contact: Cattaneo-Mindlin, Mindlin-Deresiewicz, Kalker's linear creep.

Sources: Johnson, *Contact Mechanics* (1985), §7.2-7.4 and §8.4; Kalker (1967, 1990).
"""

from __future__ import annotations

import math


def cattaneo_stick_ratio(tangential_force: float, friction_coefficient: float, normal_force: float):
    """Cattaneo-Mindlin stick radius c/a = (1 - Q/(mu W))^(1/3) for beta = 0."""
    return (1.0 - tangential_force / (friction_coefficient * normal_force)) ** (1.0 / 3.0)


def cattaneo_shift(
    tangential_force: float, friction_coefficient: float, normal_force: float, compliance: float
) -> float:
    """Tangential shift (m) of a Cattaneo-Mindlin contact loaded monotonically to Q (beta = 0).

    ``delta = C [1 - (1 - Q/(mu W))^(2/3)]`` with the full-slip shift ``C`` (m); for a sphere on
    a flat of shear modulus G (Johnson 1985, eq. 7.42 per body) ``C = 3 mu W (2 - nu)/(16 G a)``,
    twice that for two identical bodies.
    """
    ratio = tangential_force / (friction_coefficient * normal_force)
    return compliance * (1.0 - (1.0 - ratio) ** (2.0 / 3.0))


def mindlin_deresiewicz_terms(
    tangential_force: float,
    amplitude: float,
    friction_coefficient: float,
    normal_force: float,
    unloading: bool,
) -> list[tuple[float, float]]:
    """The traction of a Mindlin-Deresiewicz cycle between -Q* and +Q* (beta = 0) at force Q.

    A sum of Hertz-shaped terms ``q_x(r) = sum_i w_i (mu p0 / a) sqrt(c_i^2 - r^2)`` (zero past
    c_i), returned as ``[(w_i, c_i / a)]``.  Loaded to Q* (Cattaneo): ``[(1, 1), (-1, c*/a)]``,
    ``(c*/a)^3 = 1 - Q*/(mu W)``.  Unloading from Q* to Q slips back over an annulus
    ``c' < r < a``, ``(c'/a)^3 = 1 - (Q* - Q)/(2 mu W)``: the increment is twice the Cattaneo
    traction of radius c', negative, so ``[(-1, 1), (2, c'/a), (-1, c*/a)]``; reloading from
    -Q* is its mirror, ``(c'/a)^3 = 1 - (Q* + Q)/(2 mu W)`` and the signs reversed (Johnson 1985,
    section 7.4).
    """
    mu_w = friction_coefficient * normal_force
    star = cattaneo_stick_ratio(amplitude, friction_coefficient, normal_force)
    change = amplitude - tangential_force if unloading else amplitude + tangential_force
    back = (1.0 - change / (2.0 * mu_w)) ** (1.0 / 3.0)
    sign = 1.0 if unloading else -1.0
    return [(-sign, 1.0), (2.0 * sign, back), (-sign, star)]


def mindlin_deresiewicz_energy(
    amplitude: float, friction_coefficient: float, normal_force: float, compliance: float
) -> float:
    """Energy (J) dissipated per cycle of Q between -Q* and +Q* (Mindlin & Deresiewicz, beta = 0).

    The loop's branches are ``delta = +-[delta* - 2 C psi((Q* -+ Q)/(2 mu W))]`` with
    ``psi(x) = 1 - (1 - x)^(2/3)`` and ``C`` the full-slip shift of :func:`cattaneo_shift`;
    integrating their difference over Q gives, with ``x = Q*/(mu W)``,

        Delta W = 4 C mu W [6/5 - x - x (1 - x)^(2/3) - (6/5)(1 - x)^(5/3)],

    which for one body on a rigid flat is Johnson's (1985) eq. 7.64.
    """
    x = amplitude / (friction_coefficient * normal_force)
    rest = 1.0 - x
    return (
        4.0 * compliance * friction_coefficient * normal_force
        * (1.2 - x - x * rest ** (2.0 / 3.0) - 1.2 * rest ** (5.0 / 3.0))
    )  # fmt: skip


#: Kalker's table E.3 (1990) of the linear creep coefficients (C11, C22, C23) of an elliptical
#: contact of semi-axes a (along the rolling direction x) and b, on ``c = sqrt(a b)``
#: (``F_x = G c^2 C11 xi``, ``F_y = G c^2 C22 eta + G c^3 C23 phi``), in two halves keyed by
#: ``g = min(a/b, b/a)``: :data:`KALKER_TABLE_A_BELOW_B` for a <= b (g = a/b),
#: :data:`KALKER_TABLE_A_ABOVE_B` for a >= b (g = b/a), each ``{g: {nu: (C11, C22, C23)}}``
#: for g = 0.1, 0.2, ..., 1 and nu = 0, 0.25, 0.5 (the row g = 1, the circle, in both).
#: Source: J. J. Kalker (1990), *Three-dimensional elastic bodies in rolling contact*, Kluwer,
#: appendix E, table E.3 (the circle's row as in Johnson, *Contact Mechanics* (1985), §8.4),
#: transcribed from CONTACT's sources (Vollebregt & Kalker, ``src/m_hertz.f90``, subroutine
#: ``linrol``, version 2023): numbers from the table, not derived here.  An older copy of
#: CONTACT's table has C23 = 1.15 for a/b = 0.8, nu = 0.25, a typo for 1.25 (the column rises
#: 1.14, 1.25, 1.36 and the steady solver gives 1.25); the solver's own steady states
#: (:mod:`solver.surface.steady`) match the table within about 1 % at every node g >= 0.4.
KALKER_TABLE_A_BELOW_B = {
    0.1: {0.0: (2.51, 2.51, 0.334), 0.25: (3.31, 2.52, 0.473), 0.5: (4.85, 2.53, 0.731)},
    0.2: {0.0: (2.59, 2.59, 0.483), 0.25: (3.37, 2.63, 0.603), 0.5: (4.81, 2.66, 0.809)},
    0.3: {0.0: (2.68, 2.68, 0.607), 0.25: (3.44, 2.75, 0.715), 0.5: (4.80, 2.81, 0.889)},
    0.4: {0.0: (2.78, 2.78, 0.720), 0.25: (3.53, 2.88, 0.823), 0.5: (4.82, 2.98, 0.977)},
    0.5: {0.0: (2.88, 2.88, 0.827), 0.25: (3.62, 3.01, 0.929), 0.5: (4.83, 3.14, 1.07)},
    0.6: {0.0: (2.98, 2.98, 0.930), 0.25: (3.72, 3.14, 1.03), 0.5: (4.91, 3.31, 1.18)},
    0.7: {0.0: (3.09, 3.09, 1.03), 0.25: (3.81, 3.28, 1.14), 0.5: (4.97, 3.48, 1.29)},
    0.8: {0.0: (3.19, 3.19, 1.13), 0.25: (3.91, 3.41, 1.25), 0.5: (5.05, 3.65, 1.40)},
    0.9: {0.0: (3.29, 3.29, 1.23), 0.25: (4.01, 3.54, 1.36), 0.5: (5.12, 3.82, 1.51)},
    1.0: {0.0: (3.40, 3.40, 1.33), 0.25: (4.12, 3.67, 1.47), 0.5: (5.20, 3.98, 1.63)},
}
KALKER_TABLE_A_ABOVE_B = {
    0.1: {0.0: (10.7, 10.7, 12.2), 0.25: (11.7, 12.8, 14.6), 0.5: (12.9, 16.0, 18.0)},
    0.2: {0.0: (6.96, 6.96, 5.72), 0.25: (7.78, 8.14, 6.63), 0.5: (8.82, 9.79, 7.89)},
    0.3: {0.0: (5.57, 5.57, 3.79), 0.25: (6.34, 6.40, 4.32), 0.5: (7.34, 7.51, 5.01)},
    0.4: {0.0: (4.84, 4.84, 2.88), 0.25: (5.57, 5.48, 3.24), 0.5: (6.57, 6.31, 3.70)},
    0.5: {0.0: (4.37, 4.37, 2.35), 0.25: (5.10, 4.90, 2.62), 0.5: (6.11, 5.56, 2.96)},
    0.6: {0.0: (4.06, 4.06, 2.01), 0.25: (4.78, 4.50, 2.23), 0.5: (5.80, 5.04, 2.50)},
    0.7: {0.0: (3.82, 3.82, 1.76), 0.25: (4.54, 4.21, 1.95), 0.5: (5.58, 4.67, 2.18)},
    0.8: {0.0: (3.65, 3.65, 1.58), 0.25: (4.36, 3.99, 1.75), 0.5: (5.42, 4.39, 1.94)},
    0.9: {0.0: (3.51, 3.51, 1.44), 0.25: (4.22, 3.81, 1.59), 0.5: (5.30, 4.16, 1.77)},
    1.0: {0.0: (3.40, 3.40, 1.33), 0.25: (4.12, 3.67, 1.47), 0.5: (5.20, 3.98, 1.63)},
}
#: The Poisson's ratios of Kalker's table and the range of g = min(a/b, b/a) it covers.
KALKER_TABLE_NU = (0.0, 0.25, 0.5)
KALKER_TABLE_G = (0.1, 1.0)

#: Kalker's linear creep coefficients (C11, C22, C23) of a circular contact by Poisson's ratio
#: (the table's row g = 1).
KALKER_CIRCLE_COEFFICIENTS = dict(KALKER_TABLE_A_BELOW_B[1.0])

#: Kalker's linear creep coefficients (C11, C22, C23) of elliptical contacts of semi-axes a
#: (along the rolling direction x) and b, per Poisson's ratio, on ``c = sqrt(a b)``:
#: ``F_x = G c^2 C11 xi``, ``F_y = G c^2 C22 eta + G c^3 C23 phi``; the table's rows a/b = 0.5
#: and b/a = 0.5.
KALKER_ELLIPSE_COEFFICIENTS = {0.5: KALKER_TABLE_A_BELOW_B[0.5], 2.0: KALKER_TABLE_A_ABOVE_B[0.5]}


def kalker_coefficients(nu: float, a_over_b: float) -> tuple[float, float, float]:
    """Kalker's linear creep coefficients (C11, C22, C23) interpolated in his table E.3.

    ``F_x = G a b C11 xi``, ``F_y = G a b C22 eta + G (a b)^(3/2) C23 phi`` (``G`` the pair's
    shear modulus, Pa; ``a``, ``b`` the semi-axes along and across the rolling direction, m;
    ``xi``, ``eta`` the creepages, 1; ``phi`` the spin, 1/m).  Interpolated as CONTACT's
    ``linrol`` does: linear in ``g = min(a/b, b/a)`` between the rows of the half of the table
    that holds the ratio (:data:`KALKER_TABLE_A_BELOW_B` for a/b <= 1,
    :data:`KALKER_TABLE_A_ABOVE_B` for a/b > 1), then in nu by the parabola through the three
    columns nu = 0, 0.25, 0.5 of 1/C (the coefficients' flexibilities); a table node is
    returned as tabulated.  The parabola in 1/C reproduces the steady solver's circle at
    nu = 0.3 and 0.4 to within 0.1 %, where linear interpolation of C11 in nu is 0.9 % and
    1.2 % high.

    Parameters
    ----------
    nu : float
        Poisson's ratio of the pair (1), in [0, 0.5].
    a_over_b : float
        Ratio of the semi-axis a along the rolling direction to the semi-axis b across it (1),
        in [0.1, 10].

    Returns
    -------
    (float, float, float)
        C11, C22, C23 (1).

    Raises
    ------
    ValueError
        If ``nu`` or ``a_over_b`` is outside the table (or not a finite number).
    """
    nu, a_over_b = float(nu), float(a_over_b)
    low, high = KALKER_TABLE_NU[0], KALKER_TABLE_NU[-1]
    if not low <= nu <= high:  # also refuses NaN
        raise ValueError(f"Kalker's table covers Poisson's ratios {low} to {high}, not {nu}")
    g_min = KALKER_TABLE_G[0]
    if not g_min <= a_over_b <= 1.0 / g_min:
        raise ValueError(
            f"Kalker's table covers semi-axis ratios a/b from {g_min} to {1.0 / g_min:g}, "
            f"not {a_over_b}"
        )
    table = KALKER_TABLE_A_BELOW_B if a_over_b <= 1.0 else KALKER_TABLE_A_ABOVE_B
    g = min(a_over_b, 1.0 / a_over_b)
    rows = sorted(table)
    upper = next((k for k, row in enumerate(rows) if row >= g), len(rows) - 1)
    lower = max(upper - 1, 0)
    g0, g1 = rows[lower], rows[upper]
    weight = 0.0 if g1 == g0 else (g - g0) / (g1 - g0)
    if weight <= 1e-12 * g1 or abs(1.0 - weight) <= 1e-12:  # on a row (round-off of b/a)
        columns = table[g0 if weight < 0.5 else g1]
    else:
        columns = {
            n: tuple((1.0 - weight) * c0 + weight * c1
                     for c0, c1 in zip(table[g0][n], table[g1][n], strict=True))
            for n in KALKER_TABLE_NU
        }  # fmt: skip
    if nu in columns:
        return tuple(float(c) for c in columns[nu])
    n0, n1, n2 = KALKER_TABLE_NU
    lagrange = (
        (nu - n1) * (nu - n2) / ((n0 - n1) * (n0 - n2)),
        (nu - n0) * (nu - n2) / ((n1 - n0) * (n1 - n2)),
        (nu - n0) * (nu - n1) / ((n2 - n0) * (n2 - n1)),
    )
    return tuple(
        1.0 / sum(w / columns[n][i] for w, n in zip(lagrange, KALKER_TABLE_NU, strict=True))
        for i in range(3)
    )


def kalker_linear_force(
    creepage: tuple[float, float],
    shear_modulus: float,
    radius: float,
    nu: float,
    spin: float = 0.0,
) -> tuple[float, float]:
    """Kalker's linear creep force (N) on body 2 of a circular contact at small creepage.

    ``F_x = G a^2 C11 xi``, ``F_y = G a^2 C22 eta + G a^3 C23 phi`` (``G`` the pair's shear
    modulus, 2/G = 1/G1 + 1/G2; ``a`` the contact radius; ``phi`` the spin, 1/m), with the
    signs of :mod:`solver.case.case` (the force on body 2 points along the rigid slip of body 1; a
    positive spin turns x towards y and pushes body 2 towards +y, as tested).  Valid where the
    contact nearly adheres (a force well below ``mu W``); ``nu`` one of
    :data:`KALKER_CIRCLE_COEFFICIENTS`.
    """
    c11, c22, c23 = KALKER_CIRCLE_COEFFICIENTS[nu]
    scale = shear_modulus * radius * radius
    return scale * c11 * creepage[0], scale * (c22 * creepage[1] + c23 * radius * spin)


def capped_sliding_force(
    friction_coefficient: float, max_pressure: float, radius: float, shear_cap: float
) -> float:
    """Friction force (N) of a Hertz contact in gross slip under Orowan's law, ``min(mu p, tau_c)``.

    With ``p = p_0 sqrt(1 - r^2/a^2)`` the traction is ``tau_c`` inside the radius
    ``r_c`` where ``mu p = tau_c``, ``r_c^2 = a^2 (1 - (tau_c / (mu p_0))^2)``, and ``mu p``
    outside it; integrating over the circle,

        Q = tau_c pi r_c^2 + mu (2 pi a^2 p_0 / 3) (1 - r_c^2 / a^2)^(3/2),

    which is ``mu P`` (``P = 2 pi a^2 p_0 / 3``) when ``tau_c >= mu p_0`` (``r_c = 0``) and tends
    to ``tau_c pi a^2`` as mu grows.  Exact for a sliding sphere whose pressure stays Hertz's
    (Dundurs beta = 0, e.g. a rigid sphere on an incompressible half-space); it also bounds
    the tangential force a static contact under that pressure can carry.
    """
    mu, p0, a = friction_coefficient, max_pressure, radius
    return mu * 2.0 * math.pi * a * a * p0 / 3.0 * capped_force_ratio(shear_cap / (mu * p0))


def capped_force_ratio(cap_ratio: float) -> float:
    """``Q / (mu P)`` of :func:`capped_sliding_force` at ``s = tau_c / (mu p_0)``: 1.5 s - 0.5 s^3.

    With ``r_c^2 = a^2 (1 - s^2)`` the closed form divides by ``mu P`` to
    ``(3/2) s (1 - s^2) + s^3``, independent of the radius (and the same on a Hertz ellipse,
    whose areas scale by ``a b`` alike); 1 for ``s >= 1``.
    """
    s = min(max(cap_ratio, 0.0), 1.0)
    return 1.5 * s - 0.5 * s**3


def _capped_line_load(x, mu_p0: float, a: float, cap: float):
    """The MDR line load ``q1(x) = 2 int_0^T g(sqrt(x^2 + t^2)) dt`` of ``g = min(mu p, cap)``.

    ``T = sqrt(a^2 - x^2)``; the cap binds for ``t < t0 = sqrt(r_c^2 - x^2)``, and the rest is
    the integral of ``(mu p_0 / a) sqrt(T^2 - t^2)``.  Also returns its slope ``q1'(x)``,
    ``-2 x (mu p_0 / a)(pi/2 - asin(t0 / T))`` (``g'`` is zero where the cap binds).
    """
    import numpy as np

    x = np.abs(np.asarray(x, dtype=float))
    r_c2 = a * a * (1.0 - min(cap / mu_p0, 1.0) ** 2)
    big_t = np.sqrt(np.maximum(a * a - x * x, 0.0))
    t0 = np.minimum(np.sqrt(np.maximum(r_c2 - x * x, 0.0)), big_t)
    ratio = np.divide(t0, big_t, out=np.zeros_like(big_t), where=big_t > 0)
    angle = np.arcsin(np.clip(ratio, 0.0, 1.0))
    tail = math.pi * big_t**2 / 4 - 0.5 * (t0 * np.sqrt(big_t**2 - t0**2) + big_t**2 * angle)
    load = 2.0 * (cap * t0 + mu_p0 / a * tail)
    slope = -2.0 * x * mu_p0 / a * (0.5 * math.pi - angle)
    return load, slope


def capped_partial_slip(
    friction_coefficient: float,
    max_pressure: float,
    radius: float,
    shear_cap: float,
    force: float,
):
    """Stick radius (m) and traction (Pa) of a Hertz contact in partial slip under Orowan's law.

    A tangential force ``Q`` below the capacity :func:`capped_sliding_force` on a Hertz pressure
    (Dundurs beta = 0), with the slip traction ``g = min(mu p, tau_c)``.  Derived with the
    method of dimensionality reduction (Popov and Hess) under Cattaneo and Mindlin's
    axisymmetric approximation (the tangential displacement of an x-directed traction taken
    with the 1/rho kernel of the normal problem, which the Hertzian parts satisfy exactly):
    the full-slip traction ``g`` maps to the line load ``q1_g(x) = 2 int_x^a r g(r) /
    sqrt(r^2 - x^2) dr``; every spring of the stick zone ``|x| < c`` has the shift of the
    rigid body, so ``q1(x) = q1_g(max(|x|, c))``.  Hence

        Q = 2 [c q1_g(c) + int_c^a q1_g(x) dx],
        q(r) = g(r) for r >= c,   q(r) = -(1/pi) int_c^a q1_g'(x) / sqrt(x^2 - r^2) dx for r < c,

    ``c`` found from ``Q`` (``Q`` falls from the capacity at ``c = 0`` to 0 at ``c = a``).
    Without a binding cap (``tau_c >= mu p_0``) this is Cattaneo-Mindlin's
    ``c^3 = a^3 (1 - Q / (mu P))``, ``q = (mu p_0 / a)(sqrt(a^2 - r^2) - sqrt(c^2 - r^2))``.

    Returns
    -------
    (float, callable)
        The stick radius c (m) and ``traction(r)`` (Pa) for an array of radii (m).
    """
    import numpy as np
    from scipy.integrate import quad
    from scipy.optimize import brentq

    mu_p0, a, cap = friction_coefficient * max_pressure, radius, shear_cap

    def line(x):
        return float(_capped_line_load(x, mu_p0, a, cap)[0])

    def carried(c):
        return 2.0 * (c * line(c) + quad(line, c, a, limit=200)[0])

    capacity = carried(0.0)
    if not 0.0 < force < capacity:
        raise ValueError(f"force {force:g} N must be in (0, {capacity:g}) N, the capacity")
    c = brentq(lambda s: carried(s) - force, 0.0, a, xtol=1e-14 * a)

    def traction(r):
        r = np.abs(np.asarray(r, dtype=float))
        g = np.minimum(mu_p0 * np.sqrt(np.clip(1.0 - (r / a) ** 2, 0.0, None)), cap)
        out = np.where(r < a, g, 0.0)
        for i in np.flatnonzero(r.ravel() < c):
            ri = r.flat[i]

            def integrand(x, ri=ri):
                return -float(_capped_line_load(x, mu_p0, a, cap)[1]) / math.sqrt(x * x - ri * ri)

            out.flat[i] = quad(integrand, c, a, limit=200)[0] / math.pi
        return out

    return c, traction
