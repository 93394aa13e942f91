"""Fatigue criteria on stress paths (issue 60, first step): the smallest ball and the criteria."""

import itertools
import math

import numpy as np
import pytest

from solver.fatigue.ball import smallest_balls
from solver.fatigue.criteria import FatigueLimits, deviatoric_coordinates, fatigue_criteria

BENDING, TORSION = 400e6, 250e6  # Pa: a steel's fully reversed limits (t / f = 0.625)
LIMITS = FatigueLimits(BENDING, TORSION)


def _brute_force_radius(points: np.ndarray) -> float:
    """The smallest enclosing radius by enumeration: every subset of up to d + 1 points, the
    ball through them centred in their affine hull, the smallest one holding every point."""
    best = math.inf
    for size in range(1, points.shape[1] + 2):
        for subset in itertools.combinations(range(len(points)), size):
            chosen = points[list(subset)]
            edges = chosen[1:] - chosen[0]
            try:
                weights = np.linalg.solve(2.0 * edges @ edges.T, (edges * edges).sum(axis=1))
            except np.linalg.LinAlgError:  # degenerate subset: another covers it
                continue
            centre = chosen[0] + edges.T @ weights
            best = min(best, float(np.linalg.norm(points - centre, axis=1).max()))
    return best


def test_the_smallest_ball_matches_brute_force_on_random_paths():
    rng = np.random.default_rng(7)
    points = rng.normal(size=(40, 9, 5)) * rng.uniform(0.1, 10.0, size=(40, 1, 1))
    centres, radii, gaps = smallest_balls(points)
    assert gaps.max() <= 1e-12
    expected = np.array([_brute_force_radius(p) for p in points])
    np.testing.assert_allclose(radii, expected, rtol=1e-9)
    # every point inside, and the ball cannot shrink: some point on its surface
    distance = np.linalg.norm(points - centres[:, None, :], axis=2)
    assert np.all(distance <= radii[:, None] * (1 + 1e-12))


def test_the_deviatoric_coordinates_keep_the_norm():
    rng = np.random.default_rng(3)
    stress = rng.normal(size=(6, 50))
    s = stress.copy()
    s[:3] -= s[:3].mean(axis=0)
    norm = np.sqrt((s[:3] ** 2).sum(axis=0) + 2.0 * (s[3:] ** 2).sum(axis=0))
    np.testing.assert_allclose(
        np.linalg.norm(deviatoric_coordinates(stress), axis=0), norm, rtol=1e-12
    )


def _path(sxx, txy) -> np.ndarray:
    """A stress path (6, 1, samples) of normal stress sxx(t) and shear txy(t)."""
    out = np.zeros((6, 1, len(sxx)))
    out[0, 0], out[5, 0] = sxx, txy
    return out


T = np.linspace(0.0, 2.0 * math.pi, 361)[:-1]  # 360 samples: the quarter points included


def test_the_limits_are_their_own_criteria():
    """Fully reversed bending at f_-1 and torsion at t_-1: both factors of safety are 1."""
    for path in (_path(BENDING * np.sin(T), 0 * T), _path(0 * T, TORSION * np.sin(T))):
        result = fatigue_criteria(path, LIMITS)
        assert result.dang_van_factor[0] == pytest.approx(1.0, rel=1e-9)
        assert result.crossland_factor[0] == pytest.approx(1.0, rel=1e-9)


@pytest.mark.parametrize(("mean", "sigma", "tau"), [(0.0, 200e6, 100e6), (80e6, 150e6, 120e6)])
def test_proportional_tension_torsion_against_its_closed_forms(mean, sigma, tau):
    """sigma(t) = m + s sin t, tau(t) = t_a sin t: the deviatoric path is a segment, its ball
    has radius |s_a|: sqrt(J2,a) = sqrt(s^2/3 + t_a^2); its centre the mean, so Dang Van's
    mesoscopic shear peaks at sqrt(s^2/4 + t_a^2) where p_h = (m + s)/3."""
    result = fatigue_criteria(_path(mean + sigma * np.sin(T), tau * np.sin(T)), LIMITS)
    alpha, _ = LIMITS.crossland
    a, _ = LIMITS.dang_van
    crossland = math.sqrt(sigma**2 / 3.0 + tau**2) + alpha * (mean + sigma) / 3.0
    dang_van = math.sqrt(sigma**2 / 4.0 + tau**2) + a * (mean + sigma) / 3.0
    assert result.crossland[0] == pytest.approx(crossland, rel=1e-9)
    assert result.dang_van[0] == pytest.approx(dang_van, rel=1e-9)


@pytest.mark.parametrize(("sigma", "tau"), [(300e6, 100e6), (150e6, 160e6)])
def test_out_of_phase_bending_torsion_against_its_closed_forms(sigma, tau):
    """sigma(t) = s sin t, tau(t) = t_a cos t (90 degrees out of phase): the deviatoric path
    is an ellipse of semi-axes s/sqrt 3 and t_a (in sqrt J2), its ball the larger, centred at
    zero; Dang Van's sigma = max over u = sin t of sqrt(s^2 u^2/4 + t_a^2 (1 - u^2)) + a s u/3,
    here by a golden-section search of that expression."""
    result = fatigue_criteria(_path(sigma * np.sin(T), tau * np.cos(T)), LIMITS)
    alpha, _ = LIMITS.crossland
    a, _ = LIMITS.dang_van
    assert result.shear_amplitude[0] == pytest.approx(max(sigma / math.sqrt(3), tau), rel=1e-9)
    assert result.crossland[0] == pytest.approx(
        max(sigma / math.sqrt(3), tau) + alpha * sigma / 3.0, rel=1e-9
    )

    def g(u):
        return math.sqrt(sigma**2 * u * u / 4.0 + tau**2 * (1.0 - u * u)) + a * sigma * u / 3.0

    low, high, ratio = -1.0, 1.0, (math.sqrt(5.0) - 1.0) / 2.0
    for _ in range(200):
        left, right = high - ratio * (high - low), low + ratio * (high - low)
        low, high = (left, high) if g(left) < g(right) else (low, right)
    continuous = max(g(low), g(1.0), g(-1.0))
    # the path's samples every degree: the peak within the sampling's second-order error
    assert result.dang_van[0] == pytest.approx(continuous, rel=1e-4)
    assert result.dang_van[0] <= continuous * (1 + 1e-12)


@pytest.mark.parametrize(
    ("bending", "torsion", "what"),
    [
        (400e6, 450e6, "(1/sqrt 3, 1)"),
        (400e6, 200e6, "(1/sqrt 3, 1)"),
        (-400e6, 250e6, "positive stress"),
        (400e6, math.nan, "positive stress"),
    ],
)
def test_inconsistent_fatigue_limits_are_refused(bending, torsion, what):
    with pytest.raises(ValueError) as info:
        FatigueLimits(bending, torsion)
    assert what in str(info.value) and "\n" not in str(info.value)
