"""Melan's static shakedown theorem solved directly: the fields, the program, the limits.

Independent references: McEwen's line-contact field against quadrature of Flamant's line
loads; the residual basis against stress functions known in closed form; the line contact's
limit against the orthogonal shear of its closed-form field (Johnson & Jefferis 1963: 4.0 k);
the point contact's static limit against the pointwise upper bound and Ponter, Hearle &
Johnson's 4.7 k (an upper bound).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from solver.theorems import melan
from solver.theorems.melan import (
    certified_factors,
    deviatoric_coordinates,
    pointwise_limit,
    static_limit,
)
from solver.theorems.residual import line_basis, section_basis
from solver.theorems.track import Track, track_limits
from solver.theory.half_space import hamilton_stress, mcewen_stress

#: Ponter, Hearle & Johnson (1985): frictionless point contact, kinematic theorem (upper bound).
PONTER_POINT = 4.7


def _flamant(x: float, z: float, mu: float) -> np.ndarray:
    """(xx, zz, xz) of the Hertz line load p0 sqrt(1 - xi^2) (+ mu p along +x) by quadrature."""

    def integrand(xi, k):
        dx = x - xi
        r4 = (dx * dx + z * z) ** 2
        p = math.sqrt(max(1.0 - xi * xi, 0.0))
        q = mu * p
        parts = (
            p * dx * dx * z + q * dx**3,
            p * z**3 + q * dx * z * z,
            p * dx * z * z + q * dx * dx * z,
        )
        return -2.0 / math.pi * parts[k] / r4

    return np.array(
        [quad(integrand, -1.0, 1.0, args=(k,), limit=400, epsabs=1e-13)[0] for k in range(3)]
    )


@pytest.mark.validation
@pytest.mark.parametrize("x, z", [(0.0, 0.5), (0.3, 0.2), (-0.8, 0.4), (1.5, 0.3), (-1.2, 1.0)])
def test_mcewen_matches_flamant_quadrature(x, z, validation):
    mu, nu = 0.3, 0.25
    closed = mcewen_stress(x, z, 1.0, 1.0, nu, mu)
    quadrature = _flamant(x, z, mu)
    assert np.allclose(closed[[0, 2, 4]], quadrature, atol=1e-9)
    validation(
        "Sliding line contact's stress field (McEwen 1949), mu = 0.3",
        "quadrature of Flamant's line loads, 5 points",
        float(np.abs(closed[[0, 2, 4]] - quadrature).max() / np.abs(quadrature).max()),
    )
    assert closed[1] == pytest.approx(nu * (closed[0] + closed[2]))
    assert closed[3] == closed[5] == 0.0


def test_residual_basis_converges_to_the_stress_functions_fields():
    """psi, phi given in closed form: the basis reproduces their stresses at second order."""
    from numpy.polynomial import Polynomial as P

    width, depth = 2.0, 1.5
    t = P([0.0, 1.0])
    bump = (t * (1 - t)) ** 2 * (1 + t)  # zero with its slope at 0 and 1
    fy = bump(P([0.5, 1.0 / width]))  # of y in [-W/2, W/2]
    fz = bump(P([0.0, 1.0 / depth]))  # of z in [0, D]
    ky, kz = math.pi / width, math.pi / depth

    def phi(y, z):
        return np.sin(ky * (y + width / 2)) * np.sin(kz * z) * (1 + z)

    def exact(y, z):
        """rho (yy, zz, yz, xz, xy) of psi = fy fz and phi."""
        sy, cy = np.sin(ky * (y + width / 2)), np.cos(ky * (y + width / 2))
        sz, cz = np.sin(kz * z), np.cos(kz * z)
        return [
            fy(y) * fz.deriv(2)(z),
            fy.deriv(2)(y) * fz(z),
            -fy.deriv(1)(y) * fz.deriv(1)(z),
            -ky * cy * sz * (1 + z),
            sy * (kz * cz * (1 + z) + sz),
        ]

    errors = []
    for n in (8, 16, 32):
        ny, nz = n, round(n * depth / width)
        dy, dz = width / ny, depth / nz
        yc = (-width / 2 + (np.arange(ny) + 0.5) * dy)[:, None]
        zc = ((np.arange(nz) + 0.5) * dz)[None, :]
        yn = (-width / 2 + np.arange(1, ny) * dy)[:, None]
        zn = (np.arange(1, nz) * dz)[None, :]
        unknowns = np.concatenate(
            [phi(yn, zn).ravel(), (fy(yn) * fz(zn)).ravel(), np.zeros(ny * nz)]
        )
        rho = (section_basis(ny, nz, dy, dz) @ unknowns).reshape(6, ny, nz)[1:]
        reference = np.array(exact(yc, zc))
        scale = np.abs(reference).max()
        # with the surface points: layer 0 is z = 0, where rho_zz = rho_yz = rho_xz = 0
        top = section_basis(ny, nz, dy, dz, surface=True) @ np.concatenate([unknowns, np.zeros(ny)])
        top = top.reshape(6, ny, nz + 1)
        assert np.array_equal(top[1:, :, 1:], rho)
        assert not top[2:5, :, 0].any()
        surface = np.array(exact(yc, 0.0 * zc))[[0, 4], :, 0]
        errors.append(
            max(np.abs(rho - reference).max(), np.abs(top[[1, 5], :, 0] - surface).max()) / scale
        )
    assert errors[-1] < 0.01
    assert errors[1] < errors[0] / 3 and errors[2] < errors[1] / 3  # second order


def test_symmetric_half_gives_the_full_sections_limit():
    """The half section with the symmetry conditions on y = 0 equals the whole section."""
    h, width, depth = 0.25, 2.0, 3.0
    s = np.linspace(-3.0, 3.0, 49)
    z = (np.arange(round(depth / h)) + 0.5) * h
    factors = []
    for symmetric in (False, True):
        ny = round((1 if symmetric else 2) * width / h)
        y = (0.0 if symmetric else -width) + (np.arange(ny) + 0.5) * h
        elastic = hamilton_stress(
            -s[:, None, None], y[None, :, None], z[None, None, :], 1.0, 1.0, 0.3
        )
        basis = section_basis(ny, z.size, h, h, symmetric=symmetric)
        factors.append(static_limit(elastic, basis).factor)
    assert factors[1] == pytest.approx(factors[0], rel=1e-5)


@pytest.mark.validation
def test_line_contact_limit_is_johnson_and_jefferis_and_converges(validation):
    """Frictionless line contact: 1 / max |tau_xz| (0.25 p0), within 2 %, error shrinking."""
    z = np.linspace(1e-3, 2.0, 4001)
    x = np.linspace(-2.0, 2.0, 801)
    orthogonal = np.abs(mcewen_stress(x[:, None], z[None, :], 1.0, 1.0, 0.3)[4]).max()
    expected = 1.0 / orthogonal
    assert expected == pytest.approx(4.0, rel=1e-3)
    errors = []
    for cells in (10, 20, 40):  # centres 0.05, 0.025, 0.0125 a from the critical depth
        result = track_limits(Track("line", 0.0, 0.3, cells=cells))
        assert result.static.status == "optimal"
        errors.append(result.static.factor / expected - 1.0)
        assert result.upper == pytest.approx(expected, rel=1e-3)
    assert all(e > -1e-4 for e in errors)  # the cells sample the field: at or above the limit
    assert abs(errors[0]) < 0.02
    assert abs(errors[2]) < abs(errors[1]) / 3 < abs(errors[0]) / 9  # second order
    validation(
        "Melan's static shakedown limit, frictionless line contact (solver.theorems)",
        f"Johnson & Jefferis 1963: 1 / max |tau_xz| = {expected:.4f} k",
        "error " + ", ".join(f"{e:+.1e}" for e in errors) + " at a/10, a/20, a/40",
    )


@pytest.mark.validation
def test_point_contact_static_limit_meets_the_pointwise_bound_below_ponters(validation):
    coarse, fine = (track_limits(Track("point", 0.0, 0.3, cells=c)) for c in (4, 8))
    assert coarse.static.converged and fine.static.converged
    upper = fine.upper
    # the pointwise bound holds whatever the mesh; the static factor approaches it from above
    assert coarse.upper == pytest.approx(upper, rel=1e-3)
    assert coarse.static.factor > fine.static.factor > upper * (1.0 - 1e-4)
    assert fine.static.factor - upper < 0.6 * (coarse.static.factor - upper)
    assert upper < PONTER_POINT  # the kinematic theorem's bound lies above
    assert upper == pytest.approx(PONTER_POINT, rel=0.01)
    assert fine.upper_at[1] == pytest.approx(0.35, abs=0.02)  # on the centre plane
    assert fine.first_yield < upper
    validation(
        "Melan's static shakedown limit, frictionless point contact (solver.theorems)",
        "its pointwise upper bound; Ponter, Hearle & Johnson 1985: 4.7 k (upper bound)",
        f"static {coarse.static.factor:.4f} k, {fine.static.factor:.4f} k at a/4, a/8; upper "
        f"bound {upper:.4f} k at z = {fine.upper_at[1]:.3f} a",
    )


def test_friction_moves_the_limit_to_the_surface():
    """mu = 0.5: the surface binds, at mu p0 = k for a point contact; below 1/mu in plane strain."""
    point = track_limits(Track("point", 0.5, 0.3, cells=4))
    assert point.upper_at[1] < 1e-6
    assert point.upper == pytest.approx(point.surface_flow, rel=2e-3)
    assert point.static.factor >= point.upper * (1.0 - 1e-4)
    line = track_limits(Track("line", 0.5, 0.3, cells=10))
    assert line.upper_at[1] < 1e-6
    assert line.upper < line.surface_flow  # the out-of-plane stress of plane strain
    assert line.static.factor == pytest.approx(line.upper, rel=1e-4)  # the surface is a point


def test_bounded_back_stress_lies_between_perfect_and_unbounded():
    """Zero bound: perfect plasticity; a large one: each cell's own limit (its path in a ball).

    On a Hertz track the two nearly meet: the limit is set where the stress path alone does not
    fit the yield surface (alternating plasticity), which a back stress cannot change.
    """
    base = Track("point", 0.2, 0.3, cells=4)
    perfect = track_limits(base).static.factor
    bounded = [
        track_limits(Track("point", 0.2, 0.3, cells=4, back_stress_bound=b)).static.factor
        for b in (0.0, 0.05, 50.0)
    ]
    assert bounded[0] == pytest.approx(perfect, rel=1e-5)
    assert perfect * (1 - 1e-6) <= bounded[1] <= bounded[2] * (1 + 1e-6)
    h = 0.25
    s = base.positions(8)
    worst = min(
        pointwise_limit(base.stress(s, (i + 0.5) * h, (k + 0.5) * h), None, 1.0, 50.0)
        for i in range(3)
        for k in range(4)
    )
    assert bounded[2] == pytest.approx(worst, rel=2e-3)


def test_certified_factor_is_the_quadratics_root():
    rng = np.random.default_rng(3)
    load = rng.normal(size=(5, 7, 4))
    shift = 0.1 * rng.normal(size=(5, 4))
    radius = np.full(4, math.sqrt(2.0))
    roots = certified_factors(load, shift, radius)
    total = roots[None] * load + shift[:, None, :]
    assert np.allclose(np.sqrt(np.sum(total * total, axis=0)), math.sqrt(2.0))
    assert np.all(certified_factors(load, 10.0 * np.ones((5, 4)), radius) == 0.0)


def test_deviator_coordinates_give_the_frobenius_norm():
    rng = np.random.default_rng(1)
    stress = rng.normal(size=(6, 10))
    dev = stress.copy()
    dev[:3] -= stress[:3].mean(axis=0)
    norm = np.sqrt(np.sum(dev[:3] ** 2, axis=0) + 2.0 * np.sum(dev[3:] ** 2, axis=0))
    assert np.allclose(np.linalg.norm(deviatoric_coordinates(stress), axis=0), norm)


def test_hard_cases_end_with_a_status(monkeypatch):
    """A round cap, a box too small, a conic solver that stops: a status and a finite factor."""
    capped = track_limits(Track("point", 0.3, 0.3, cells=4)).static
    h = 0.25
    s = np.linspace(-4, 4, 65)
    z = (np.arange(16) + 0.5) * h
    y = (np.arange(8) + 0.5) * h
    elastic = hamilton_stress(
        -s[:, None, None], y[None, :, None], z[None, None, :], 1.0, 1.0, 0.3, 0.3
    )
    basis = section_basis(8, 16, h, h, symmetric=True)
    one_round = static_limit(elastic, basis, max_rounds=1)
    assert one_round.status in ("rounds", "optimal")
    if one_round.status == "rounds":
        assert math.isfinite(one_round.factor) and one_round.factor >= capped.factor * 0.99
    outside = np.concatenate([elastic[:, :, 2, :3], elastic[:, :, :3, 2]], axis=2)
    small = static_limit(
        elastic[:, :, :2, :2], section_basis(2, 2, h, h, symmetric=True), edge=outside
    )
    assert small.status == "box_too_small" and small.edge_ratio > 1.0
    monkeypatch.setattr(melan, "MAX_SOLVER_ITERATIONS", 2)
    stopped = static_limit(elastic, basis)
    assert stopped.status == "solver" and "MaxIterations" in stopped.reason
    first = float(
        certified_factors(
            deviatoric_coordinates(elastic).reshape(5, 65, -1),
            np.zeros((5, 128)),
            np.full(128, math.sqrt(2.0)),
        ).min()
    )
    assert stopped.factor == pytest.approx(first)  # first yield: a lower bound all the same
    assert not np.isnan(stopped.residual).any()


def test_track_refuses_bad_input():
    with pytest.raises(ValueError, match="contact"):
        Track("ring")
    with pytest.raises(ValueError, match="friction"):
        Track("point", friction=-0.1)
    with pytest.raises(ValueError, match="cells"):
        Track("point", cells=1)
    with pytest.raises(ValueError, match="depth"):
        Track("point", depth=0.5)
    with pytest.raises(ValueError, match="at least 2 x 2"):
        section_basis(1, 4, 1.0, 1.0)
    assert line_basis(3).shape == (18, 9)


def test_tractions_on_cells_approach_the_closed_form_route():
    """Hertz's pressure on cells (the route of solved and elliptical loads) against Hamilton's.

    The two routes discretise differently (cell-averaged load, positions a cell apart): their
    limits part at first order in the cell and meet as it shrinks.
    """
    from solver.theorems.loads import elliptical_hertz, traction_limit

    gaps = []
    for cells in (4, 8):
        pressure, shear, grid = elliptical_hertz((1.0, 1.0), 1.0, 0.0, cells)
        on_cells = traction_limit(pressure, shear, grid, 0.3, 1.0, 4 * cells, 3 * cells, 4 * cells)
        closed = track_limits(Track("point", 0.0, 0.3, cells=cells))
        assert on_cells.static.converged
        gaps.append(on_cells.static.factor / closed.static.factor - 1.0)
    assert 0.0 < gaps[1] < 0.6 * gaps[0] and gaps[1] < 0.03


def test_a_long_ellipse_tends_to_the_line_contact():
    """Frictionless ellipses long across the track: the limit falls towards the line's 4.0 k."""
    from solver.theorems.loads import elliptical_hertz, traction_limit

    limits = []
    for ratio in (1.0, 2.0, 8.0):
        pressure, shear, grid = elliptical_hertz((1.0, ratio), 1.0, 0.0, 4)
        width = int((ratio + 1.5) * 4)
        limits.append(traction_limit(pressure, shear, grid, 0.3, 1.0, 16, width, 16).static.factor)
    line = track_limits(Track("line", 0.0, 0.3, cells=4)).static.factor
    assert limits[0] > limits[1] > limits[2] > line
    assert limits[2] / line - 1.0 < 0.5 * (limits[0] / line - 1.0)


def _brute_force_certified(track, static, y, z, factor):
    """Largest yield ratio of the program's field, bilinear, on the halfway lattice, fine s."""
    from solver.theorems.residual import interpolate_section
    from solver.theorems.track import BOUND_POSITIONS, DEVIATOR_MIRROR_SIGNS, SURFACE

    z0 = np.concatenate([[0.0], z[1:]])
    fine_y = np.sort(np.concatenate([[0.0], y, 0.5 * (y[:-1] + y[1:])]))
    fine_z = np.sort(np.concatenate([z0, 0.5 * (z0[:-1] + z0[1:])]))
    s = track.positions(BOUND_POSITIONS)
    shifts = deviatoric_coordinates(static.residual)
    worst = 0.0
    for py in fine_y:
        shift = interpolate_section(shifts, y, z0, py, fine_z, DEVIATOR_MIRROR_SIGNS)
        path = deviatoric_coordinates(track.stress(s[:, None], py, np.maximum(fine_z, SURFACE)))
        total = factor * path + shift[:, None, :]
        worst = max(worst, float(np.sqrt(np.sum(total * total, axis=0)).max()) / math.sqrt(2))
    return worst


@pytest.mark.parametrize("mu", [0.0, 0.5])
def test_the_certified_lower_bound_holds_between_the_samples_and_under_the_upper_bound(mu):
    """The estimate can lie above the pointwise bound; the certified bound cannot."""
    track = Track("point", mu, 0.3, cells=4)
    limits = track_limits(track)
    assert limits.lower <= limits.upper
    assert limits.lower <= limits.static.factor
    z = np.concatenate([[0.0], limits.z[1:]])
    # within yield everywhere it was checked at the bound, at yield somewhere (the root)
    ratio = _brute_force_certified(track, limits.static, limits.y, z, limits.lower)
    assert ratio <= 1.0 + 1e-9


def test_a_perturbed_programs_factor_is_rechecked_between_the_sampled_positions():
    """A residual field scaled away from the optimum: the certified factor falls to the root
    of the worst point and position of the fine check, which the program's own samples miss."""
    import copy

    from solver.theorems.track import certified_limit

    track = Track("point", 0.5, 0.3, cells=4)
    limits = track_limits(track)
    perturbed = copy.copy(limits.static)
    perturbed.residual = 1.3 * limits.static.residual
    program_positions = track.positions(2.0 * track.cells)
    lower, (py, pz, s) = certified_limit(
        track, perturbed, limits.y, limits.z, program_positions, limits.upper_at
    )
    z = np.concatenate([[0.0], limits.z[1:]])
    assert lower < limits.lower
    ratio = _brute_force_certified(track, perturbed, limits.y, z, lower)
    assert ratio == pytest.approx(1.0, abs=1e-9)  # binds at the fine check's worst pair
    # the program's own points and positions alone would have certified a larger factor
    on_samples = certified_factors(
        deviatoric_coordinates(
            track.stress(program_positions[:, None, None], limits.y[None, :, None],
                         np.maximum(limits.z, 1e-9)[None, None, :])
        ).reshape(5, program_positions.size, -1),
        deviatoric_coordinates(perturbed.residual).reshape(5, -1),
        np.full(limits.y.size * limits.z.size, math.sqrt(2.0)),
    ).min()  # fmt: skip
    assert on_samples > lower
    assert not np.isclose(program_positions, s).any() or py not in limits.y
