"""Closed forms of tangential contact: Cattaneo-Mindlin, Mindlin-Deresiewicz, Kalker's linear creep.

Sources: Johnson, *Contact Mechanics* (1985), §7.2-7.4 and §8.4; Kalker (1967, 1990).
"""

from __future__ import annotations


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


#: Kalker's linear creep coefficients of a circular contact (a/b = 1) by Poisson's ratio:
#: (C11, C22, C23).  Kalker (1967), *On the rolling contact of two elastic bodies in the
#: presence of dry friction*, thesis, Delft, as tabulated in Johnson, *Contact Mechanics*
#: (1985), §8.4 and in Kalker (1990), *Three-dimensional elastic bodies in rolling contact*,
#: Table E.3 (the same numbers are in CONTACT's sources): numbers from those tables, not
#: derived here.
KALKER_CIRCLE_COEFFICIENTS = {
    0.0: (3.40, 3.40, 1.33),
    0.25: (4.12, 3.67, 1.47),
    0.5: (5.20, 3.98, 1.63),
}


#: Kalker's linear creep coefficients (C11, C22, C23) of elliptical contacts of semi-axes a
#: (along the rolling direction x) and b, per Poisson's ratio, on ``c = sqrt(a b)``:
#: ``F_x = G c^2 C11 xi``, ``F_y = G c^2 C22 eta + G c^3 C23 phi``.  Kalker (1990), *Three-
#: dimensional elastic bodies in rolling contact*, table E.3 (as CONTACT's sources tabulate it),
#: the rows a/b = 0.5 and b/a = 0.5.
KALKER_ELLIPSE_COEFFICIENTS = {
    0.5: {0.0: (2.88, 2.88, 0.827), 0.25: (3.62, 3.01, 0.929), 0.5: (4.83, 3.14, 1.07)},
    2.0: {0.0: (4.37, 4.37, 2.35), 0.25: (5.10, 4.90, 2.62), 0.5: (6.11, 5.56, 2.96)},
}


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
    signs of :mod:`solver.spec.case` (the force on body 2 points along the rigid slip of body 1; a
    positive spin turns x towards y and pushes body 2 towards +y, as tested).  Valid where the
    contact nearly adheres (a force well below ``mu W``); ``nu`` one of
    :data:`KALKER_CIRCLE_COEFFICIENTS`.
    """
    c11, c22, c23 = KALKER_CIRCLE_COEFFICIENTS[nu]
    scale = shear_modulus * radius * radius
    return scale * c11 * creepage[0], scale * (c22 * creepage[1] + c23 * radius * spin)
