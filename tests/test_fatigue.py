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
    centres, radii, excess = smallest_balls(points)
    assert excess.max() <= 1e-10
    expected = np.array([_brute_force_radius(p) for p in points])
    np.testing.assert_allclose(radii, expected, rtol=1e-12)
    # every point inside, and the ball cannot shrink: some point on its surface
    distance = np.linalg.norm(points - centres[:, None, :], axis=2)
    assert np.all(distance <= radii[:, None] * (1 + 1e-12))


def _conic_radius(points: np.ndarray) -> float:
    """The smallest enclosing radius as a second-order cone program (Clarabel): minimise r
    subject to ||x_i - c|| <= r, an independent solver for dense paths."""
    import clarabel
    import scipy.sparse as sp

    count, dim = points.shape
    scale = float(np.abs(points).max())
    rows, cols, values, b = [], [], [], []
    for i, point in enumerate(points / scale):  # cone i: (r, x_i - c) = b - A z
        base = i * (dim + 1)
        rows.append(base), cols.append(dim), values.append(-1.0), b.append(0.0)
        for k in range(dim):
            rows.append(base + 1 + k), cols.append(k), values.append(1.0), b.append(point[k])
    a = sp.csc_matrix((values, (rows, cols)), shape=(count * (dim + 1), dim + 1))
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    settings.tol_gap_abs = settings.tol_gap_rel = settings.tol_feas = 1e-12
    q = np.zeros(dim + 1)
    q[dim] = 1.0
    cones = [clarabel.SecondOrderConeT(dim + 1)] * count
    solution = clarabel.DefaultSolver(
        sp.csc_matrix((dim + 1, dim + 1)), q, a, np.array(b), cones, settings
    ).solve()
    return float(solution.x[dim]) * scale


def test_the_smallest_ball_of_dense_smooth_paths_matches_a_conic_solver():
    """Smooth closed paths sampled densely (random Fourier curves in 5-D, 400 samples): many
    points near the surface and nearly dependent supports, the case of stress paths."""
    rng = np.random.default_rng(11)
    t = np.linspace(0.0, 2.0 * math.pi, 400, endpoint=False)
    paths = []
    for _ in range(12):
        terms = rng.normal(size=(3, 2, 5)) / np.arange(1, 4)[:, None, None]
        paths.append(sum(np.outer(np.cos((k + 1) * t), c) + np.outer(np.sin((k + 1) * t), s)
                         for k, (c, s) in enumerate(terms)) + rng.normal(size=5))  # fmt: skip
    _, radii, excess = smallest_balls(np.array(paths))
    assert excess.max() <= 1e-10
    expected = np.array([_conic_radius(path) for path in paths])
    np.testing.assert_allclose(radii, expected, rtol=1e-7)


def test_a_ball_cut_short_says_so():
    """The insertion loop at its cap returns its ball with the farthest point's excess (the
    status as data: every point is still inside the radius returned)."""
    points = np.random.default_rng(2).normal(size=(30, 40, 5))
    centres, radii, excess = smallest_balls(points, max_insertions=1)
    assert excess.max() > 1e-3
    distance = np.linalg.norm(points - centres[:, None, :], axis=2)
    assert np.all(distance <= radii[:, None] * (1 + 1e-12))
    _, exact, solved = smallest_balls(points)
    assert solved.max() <= 1e-10 and np.all(radii >= exact * (1 - 1e-12))


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


def test_a_solved_pass_matches_the_closed_form_pass_converging_with_the_cells():
    """A frictionless Hertz contact passing over steel: the solver's subsurface field of the
    pressed contact, read along x as the pass's path at each depth (a steady pass), gives Dang
    Van's and Crossland's maxima and their depths; against the same criteria on Hamilton's
    closed-form field at the same points (solver.fatigue.hertz_pass), within 2 % at 96 cells
    and closer than at 48."""
    import solver
    from solver.fatigue.criteria import steady_pass_criteria
    from solver.fatigue.hertz_pass import hertz_pass_criteria

    steel = {"behaviour": "elastic", "E": 210e9, "nu": 0.3}
    errors = []
    for n in (48, 96):
        table = {
            "body1": {**steel, "radius": 0.01},
            "body2": steel,
            "load": {"normal_force": 100.0},
            "grid": {"n": [n, n, 24], "half_width": 4.0, "depth": 1.5},
            "output": {"fields": ["stress"]},
        }
        result = solver.solve(solver.Case.from_dict(table))
        case = result.case
        a, p0 = case.reference.radius, case.reference.max_pressure
        _, y = case.surface_grid.mesh()
        j = int(np.argmin(np.abs(y[0])))  # the line nearest the contact's path
        found, _ = steady_pass_criteria(result.fields["stress"][:, :, j : j + 1, :], LIMITS)
        z = result.depth
        expected = hertz_pass_criteria(a, p0, 0.3, LIMITS, z, span=4.0, lateral=y[0, j])
        for name in ("dang_van", "crossland"):
            got, want = getattr(found, name), getattr(expected, name)
            assert got.argmax() == want.argmax()  # the same critical depth
            errors.append(abs(got.max() / want.max() - 1.0))
    (dv48, c48), (dv96, c96) = errors[:2], errors[2:]
    assert max(dv96, c96) < 0.02 and c96 < c48 and dv96 <= dv48 + 1e-3


def test_the_critical_point_rises_to_the_surface_as_friction_grows():
    """Hamilton's sliding Hertz field (closed form): Dang Van's critical depth is below the
    surface (about 0.58 a) without friction and at the surface from mu = 0.3 on (the sliding
    traction's surface tension), its value growing with mu."""
    from solver.fatigue.hertz_pass import hertz_pass_criteria

    a, p0 = 1e-4, 1.5e9
    z = np.linspace(0.02, 1.5, 75) * a
    depths, values = [], []
    for mu in (0.0, 0.1, 0.2, 0.3, 0.4):
        result = hertz_pass_criteria(a, p0, 0.3, LIMITS, z, mu)
        depths.append(z[result.dang_van.argmax()] / a)
        values.append(result.dang_van.max())
    assert 0.5 < depths[0] < 0.65 and depths[-2] == depths[-1] == z[0] / a
    assert np.all(np.diff(values) > 0)


def test_a_frictionless_roll_tells_the_fatigue_of_the_same_slide():
    """Rolling without friction moves the same Hertz pressure as sliding without friction:
    the same fatigue fields (to the solves' tolerance), and the coarse pass told."""
    results = [_sliding_pass(0.0, [96, 72, 24], motion)[0] for motion in ("slide", "roll")]
    slid, rolled = (r.fields["dang_van_stress"] for r in results)
    assert np.abs(slid - rolled).max() < 1e-6 * slid.max()
    assert any(note.startswith("fatigue: the pass is sampled at 8.8") for note in results[1].notes)


def _extent(result, a: float) -> tuple[float, float]:
    """The track's cells along x about the contact's last position, in contact radii."""
    x, end = result.case.surface_grid.x, result.history["position_x"][-1]
    return (x[0] - end) / a, (x[-1] - end) / a


def _sliding_pass(mu: float, n: list, motion: str = "slide") -> tuple:
    """A rigid sphere slid (or rolled) over incompressible steel (beta = 0: Hertz's pressure)
    with the [fatigue] table: the result, the contact radius, p0, the line nearest y = 0 and
    its y."""
    import solver

    table = {
        "body1": {"behaviour": "rigid", "radius": 0.01},
        "body2": {"behaviour": "elastic", "E": 210e9, "nu": 0.5},
        "load": {"path": [{"normal_force": 100.0}, {motion: [4e-4, 0.0], "steps": 8}]},
        "friction": {"coefficient": mu},
        "grid": {"n": n, "half_width": 4.0, "depth": 1.5},
        "fatigue": {"bending_limit": BENDING, "torsion_limit": TORSION},
    }
    result = solver.solve(solver.Case.from_dict(table))
    assert result.status == "converged"
    case = result.case
    _, y = case.surface_grid.mesh()
    j = int(np.argmin(np.abs(y[0])))
    return result, case.reference.radius, case.reference.max_pressure, j, y[0, j]


def test_a_sliding_case_tells_its_fatigue_under_the_pass():
    """[fatigue] on a frictionless sliding sphere: the fields dang_van_stress and
    crossland_stress over (y, z) against Hamilton's closed-form pass at the same points (within
    2.5 %, the same critical depths), the smallest factors of safety the limits over their
    maxima, at the depths told, and in the case's attributes."""
    from solver.fatigue.hertz_pass import hertz_pass_criteria

    result, a, p0, j, y0 = _sliding_pass(0.0, [96, 72, 24])
    reference = hertz_pass_criteria(
        a, p0, 0.4999, LIMITS, result.depth, span=_extent(result, a), lateral=y0
    )
    for name in ("dang_van", "crossland"):
        field = result.fields[f"{name}_stress"]
        assert field.shape == (72, 24)
        got, want = field[j], getattr(reference, name)
        assert got.argmax() == want.argmax()
        assert got.max() == pytest.approx(want.max(), rel=0.025)
        assert result.fatigue[f"{name}_factor"] == pytest.approx(TORSION / field.max(), rel=1e-12)
        worst = np.unravel_index(field.argmax(), field.shape)
        assert result.fatigue[f"{name}_depth"] == result.depth[worst[1]]
    attrs = result.to_xarray().attrs
    assert attrs["dang_van_factor"] == result.fatigue["dang_van_factor"]


def test_with_friction_the_solved_pass_is_critical_at_the_surface():
    """mu = 0.3: the solved pass's Dang Van maximum is in the top layer, as Hamilton's; below
    three cells (dx = 0.11 a) its profile is within 3 % of the closed form, above them low (the
    tractions constant on cells: the field at depths below a cell's width is their average)."""
    from solver.fatigue.hertz_pass import hertz_pass_criteria

    result, a, p0, j, y0 = _sliding_pass(0.3, [96, 72, 48])
    reference = hertz_pass_criteria(
        a, p0, 0.4999, LIMITS, result.depth, 0.3, span=_extent(result, a), lateral=y0
    )
    got, want = result.fields["dang_van_stress"][j], reference.dang_van
    assert got.argmax() == want.argmax() == 0
    deep = result.depth > 3 * result.case.surface_grid.dx
    np.testing.assert_allclose(got[deep], want[deep], rtol=0.03)
    assert got[0] < want[0]


def _rolled_line(cells: int, mu: float) -> tuple:
    """A steel cylinder (R = 50 mm) rolled steadily over steel with [fatigue], b = 1 mm,
    ``cells`` across the strip, the domain +-4 b: free rolling without friction, full slip
    (traction mu p) with it.  The result and the closed-form pass at its layers, over the
    same extent of the field."""
    import solver
    from solver.fatigue.hertz_pass import hertz_pass_criteria

    e, nu, radius, b = 210e9, 0.3, 0.05, 1e-3
    per_length = math.pi * e / (2 * (1 - nu * nu)) * b * b / (4 * radius)
    dx, nx, ny = 2 * b / cells, 4 * cells, 4
    roll = {"steady": True, "creepage": [1.0 if mu else 0.0, 0.0]}
    table = {
        "body1": {"behaviour": "elastic", "E": e, "nu": nu, "radius_x": radius},
        "body2": {"behaviour": "elastic", "E": e, "nu": nu},
        "friction": {"coefficient": mu},
        "load": {"path": [{"normal_force": per_length * ny * dx}, roll]},
        "grid": {"n": [nx, ny, cells], "size": [nx * dx, ny * dx], "periodic": "y", "depth": 2.0},
        "fatigue": {"bending_limit": BENDING, "torsion_limit": TORSION},
    }
    result = solver.solve(solver.Case.from_dict(table))
    assert result.status == "converged"
    half_width, p0, _ = result.case.line_contact
    assert half_width == pytest.approx(b, rel=1e-12)
    reach = 0.5 * nx * dx / b  # the field's extent about the contact, in half-widths
    reference = hertz_pass_criteria(
        b, p0, nu, LIMITS, result.depth, mu, line=True, span=reach, samples=4001
    )
    return result, reference


def test_a_rolled_line_contact_matches_mcewens_pass_converging_with_the_cells():
    """Frictionless rolling of a cylinder (grid.periodic = "y", plane-strain volume): Dang
    Van's and Crossland's smallest factors against the criteria on McEwen's closed-form field
    within 2 % at 32, 64 and 128 cells across, the same critical depth (within a layer or
    0.04 b), Crossland's error shrinking with the cells."""
    errors = {}
    for cells in (32, 64, 128):
        result, reference = _rolled_line(cells, 0.0)
        for name in ("dang_van", "crossland"):
            want = getattr(reference, f"{name}_factor")
            worst = int(want.argmin())
            got = result.fatigue[f"{name}_factor"]
            errors[name, cells] = abs(got / want[worst] - 1.0)
            depth = result.fatigue[f"{name}_depth"]
            # the criteria are flat about their maxima: within a layer or 0.04 b
            tolerance = max(1.01 * result.case.volume_grid.dz, 0.04e-3)
            assert abs(depth - result.depth[worst]) <= tolerance
            assert 0.4 < depth / 1e-3 < 0.7  # below the surface (McEwen: about 0.5 b)
        assert result.fields["dang_van_stress"].shape == (4, cells)
    assert max(errors.values()) < 0.02, errors
    assert errors["crossland", 128] < errors["crossland", 64] < errors["crossland", 32], errors


def test_a_line_contact_rolled_in_full_slip_is_critical_at_the_surface():
    """mu = 0.3 in full slip: the critical point of both criteria is the top layer, as in
    McEwen's sliding field; Dang Van's top-layer error falls with the cells (cell-constant
    tractions under-resolve the surface's field)."""
    errors = []
    for cells in (32, 64):
        result, reference = _rolled_line(cells, 0.3)
        top = result.depth[0]
        for name in ("dang_van", "crossland"):
            assert result.fatigue[f"{name}_depth"] == top
            assert getattr(reference, f"{name}_factor").argmin() == 0
        errors.append(abs(result.fatigue["dang_van_factor"] / reference.dang_van_factor[0] - 1))
    assert errors[1] < 0.7 * errors[0] and errors[1] < 0.05, errors


def test_a_line_contact_without_rolling_has_no_pass():
    import solver

    table = {
        "body1": {"behaviour": "elastic", "E": 210e9, "nu": 0.3, "radius_x": 0.05},
        "body2": {"behaviour": "elastic", "E": 210e9, "nu": 0.3},
        "load": {"normal_force": 100.0},
        "grid": {"n": [64, 4, 16], "size": [4e-3, 2.5e-4], "periodic": "y"},
        "fatigue": {"bending_limit": BENDING, "torsion_limit": TORSION},
    }
    with pytest.raises(solver.SpecError, match="^fatigue: .*steady = true"):
        solver.Case.from_dict(table)
    del table["fatigue"]
    table["output"] = {"fields": ["stress"]}  # the plane-strain field, without the criteria
    result = solver.solve(solver.Case.from_dict(table))
    stress = result.fields["stress"]
    assert stress.shape == (6, 64, 4, 16) and stress[2].min() < 0.0


def _fretted_sphere(n: int, steps: int, cycles: int = 2, **change) -> tuple:
    """Steel spheres (nu = 0: beta = 0 and Mindlin's circular stick zone exact), W = 100 N,
    mu = 0.3, the tangential force cycled between +-0.6 mu W with [fatigue]: the result and
    the closed-form cycle's criteria at its cells."""
    import solver
    from solver.fatigue.hertz_pass import fretting_cycle_criteria

    steel = {"behaviour": "elastic", "E": 210e9, "nu": 0.0}
    mu, force = 0.3, 100.0
    amplitude = 0.6 * mu * force
    cycle = [{"tangential_force": [sign * amplitude, 0.0], "steps": steps} for sign in (-1, 1)]
    table = {
        "body1": {**steel, "radius": 0.01},
        "body2": steel,
        "friction": {"coefficient": mu},
        "load": {"path": [{"normal_force": force},
                          {"tangential_force": [amplitude, 0.0], "steps": max(1, steps // 2)},
                          {"cycles": cycles, "stages": cycle}]},
        "grid": {"n": [n, n, n // 3], "half_width": 1.5, "depth": 1.0},
        "fatigue": {"bending_limit": BENDING, "torsion_limit": TORSION},
    } | change  # fmt: skip
    result = solver.solve(solver.Case.from_dict(table))
    assert result.status == "converged"
    case = result.case
    a, p0 = case.reference.radius, case.reference.max_pressure
    x, y = case.surface_grid.mesh()
    points = (x[:, :, None], y[:, :, None], result.depth[None, None, :])
    reference = fretting_cycle_criteria(points, a, p0, 0.0, LIMITS, mu, force, amplitude, steps)
    return result, reference, a


def test_a_fretting_cycle_is_read_as_each_points_own_path():
    """A sphere fretted between +-0.6 mu W (no motion: each cell's path is the last cycle's
    increments): Dang Van's and Crossland's fields over (x, y, z) against the criteria on
    Mindlin and Deresiewicz's closed-form tractions (Hamilton's fields) at the same cells and
    force samples: below three cells' depth within 1 % at 32 cells and closer at 64; the
    smallest factor at the contact's edge (|x| about a) in the top layer, as fretting fatigue
    is known to start."""
    errors = []
    for n in (32, 64):
        result, reference, a = _fretted_sphere(n, 16)
        deep = result.depth > 3 * result.case.surface_grid.dx
        worst = []
        for name in ("dang_van", "crossland"):
            got = result.fields[f"{name}_cycle_stress"]
            want = getattr(reference, name).reshape(got.shape)
            worst.append(np.abs(got - want)[..., deep].max() / want[..., deep].max())
            assert result.fatigue[f"{name}_factor"] == pytest.approx(TORSION / got.max())
            assert result.fatigue[f"{name}_depth"] == result.depth[0]
            assert 0.85 < abs(result.fatigue[f"{name}_x"]) / a < 1.05
        errors.append(max(worst))
        assert not [note for note in result.notes if note.startswith("fatigue")]
    assert errors[0] < 0.01 and errors[1] < errors[0], errors


def test_a_coarsely_sampled_or_unsettled_cycle_is_told():
    """A cycle of two increments is told coarse; a cycle that still gains plastic strain (a
    linearly hardening body 2 fretted at p0 = 4.2 k, mu = 0.25, +-0.8 mu W) is told not
    shaken down, with the strain it gained."""
    import solver

    result, _, _ = _fretted_sphere(24, 1, cycles=1)
    assert any("the cycle is sampled at 2 increments" in note for note in result.notes)
    hardening = {"law": "linear", "yield_stress": 900e6, "modulus": 10e9}
    amplitude = 0.8 * 0.25 * 100.0
    cycle = [{"tangential_force": [sign * amplitude, 0.0], "steps": 4} for sign in (-1, 1)]
    table = {
        "body1": {"behaviour": "elastic", "E": 210e9, "nu": 0.3, "radius": 0.005},
        "body2": {"behaviour": "elastic-plastic", "E": 210e9, "nu": 0.3, "hardening": hardening},
        "friction": {"coefficient": 0.25},
        "load": {"path": [{"normal_force": 100.0},
                          {"tangential_force": [amplitude, 0.0], "steps": 4},
                          {"cycles": 2, "stages": cycle}]},
        "grid": {"n": [24, 24, 16]},
        "fatigue": {"bending_limit": BENDING, "torsion_limit": TORSION},
    }  # fmt: skip
    result = solver.solve(solver.Case.from_dict(table))
    gained = result.history["cycle_plastic_strain"][-1]
    assert result.status == "converged" and gained > 1e-6
    assert f"fatigue: the last cycle gained {gained:.2g} equivalent plastic strain" in " ".join(
        result.notes
    )
    assert result.fatigue["dang_van_factor"] > 0


def test_fatigue_the_solver_cannot_read_is_refused():
    import solver

    steel = {"behaviour": "elastic", "E": 210e9, "nu": 0.3}
    base = {
        "body1": {**steel, "radius": 0.01},
        "body2": steel,
        "load": {"normal_force": 100.0},
        "grid": {"n": [32, 32, 16]},
        "fatigue": {"bending_limit": BENDING, "torsion_limit": TORSION},
    }
    for change, where, what in (
        ({}, "fatigue", "give a stage that slides or rolls (load.path[i].slide, roll, or "
                        "steady = true) or a cycle block"),
        ({"fatigue": {"bending_limit": BENDING}}, "fatigue", "torsion_limit"),
        ({"fatigue": {"bending_limit": BENDING, "torsion_limit": 2 * BENDING}},
         "fatigue.torsion_limit", "(1/sqrt 3, 1)"),
        ({"fatigue": {"bending_limit": -BENDING, "torsion_limit": TORSION}},
         "fatigue.bending_limit", "> 0"),
        ({"fatigue": {"bending_limit": 1e300, "torsion_limit": 6e299}},
         "fatigue.bending_limit", "must be in [100000, 1e+10] Pa"),
        ({"fatigue": {"bending_limit": "400 MPa", "torsion_limit": TORSION}},
         "fatigue.bending_limit", "must be a number"),
    ):  # fmt: skip
        with pytest.raises(solver.SpecError) as info:
            solver.Case.from_dict(base | change)
        message = str(info.value)
        assert message.startswith(f"{where}") and what in message and "\n" not in message


def test_a_residual_stress_acts_through_its_hydrostatic_part_alone():
    """A constant residual stress added to a path shifts its deviatoric part, which the ball's
    centre takes up: Crossland's amplitude and Dang Van's mesoscopic shear are unchanged, and
    the criteria move by alpha p_h^r and a p_h^r exactly."""
    from solver.fatigue.criteria import steady_pass_criteria

    rng = np.random.default_rng(5)
    stress = rng.normal(size=(6, 40, 7, 3)) * 1e8  # (6, nx, ny, nz)
    residual = rng.normal(size=(6, 7, 3)) * 1e8
    bare, _ = steady_pass_criteria(stress, LIMITS)
    loaded, _ = steady_pass_criteria(stress, LIMITS, residual)
    hydrostatic = residual[:3].sum(axis=0).ravel() / 3.0
    alpha, _ = LIMITS.crossland
    a, _ = LIMITS.dang_van
    np.testing.assert_allclose(loaded.shear_amplitude, bare.shear_amplitude, rtol=1e-9)
    np.testing.assert_allclose(loaded.crossland - bare.crossland, alpha * hydrostatic, atol=1e-3)
    np.testing.assert_allclose(loaded.dang_van - bare.dang_van, a * hydrostatic, atol=1e-3)


def test_a_shaken_down_track_is_judged_with_its_residual_stress():
    """A frictionless rigid sphere slid three times over elastic-perfectly plastic steel at
    p0 = 4.4 k (above first yield, below the shakedown limit): the strain gained per pass
    falls, and under the last pass the track's compressive residual stress raises both factors
    of safety above the elastic body's under the same load."""
    import solver
    from solver.result import cycle_summary

    k = 250e6

    def table(body2: dict, cycles: int) -> dict:
        again = {"hertz_pressure": 4.4 * k, "steps": 2}
        stages = [{"slide": [2e-4, 0.0], "steps": 8}, {"hertz_pressure": 0.0},
                  {"slide": [-2e-4, 0.0]}, again]  # fmt: skip
        return {
            "body1": {"behaviour": "rigid", "radius": 0.01},
            "body2": {"E": 210e9, "nu": 0.3, **body2},
            "load": {"path": [again, {"cycles": cycles, "stages": stages}]},
            "friction": {"coefficient": 0.0},
            "grid": {"n": [64, 32, 24]},
            "solver": {"plastic_tolerance": 1e-4},
            "fatigue": {"bending_limit": BENDING, "torsion_limit": TORSION},
        }

    perfect = {"law": "perfect", "yield_stress": math.sqrt(3.0) * k}
    body = {"behaviour": "elastic-plastic", "hardening": perfect}
    plastic = solver.solve(solver.Case.from_dict(table(body, 3)))
    elastic = solver.solve(solver.Case.from_dict(table({"behaviour": "elastic"}, 1)))
    assert plastic.status == elastic.status == "converged"
    gained = cycle_summary(plastic.history)["plastic_strain_increment"]
    assert gained[0] > 5 * gained[1] > 25 * gained[2] > 0
    for name in ("dang_van_factor", "crossland_factor"):
        assert plastic.fatigue[name] > 1.1 * elastic.fatigue[name]


def test_a_sampled_design_sweeps_the_fatigue_limits(tmp_path):
    """[sample] over fatigue.torsion_limit: each case gets its own limit (the [fatigue]
    table is a case table of the campaign files, declared once in solver.keys)."""
    from study_fixtures import write

    from study.campaign import load_campaign

    text = """
[campaign]
name = "sampled"

[base]
body1 = { behaviour = "rigid", radius = 0.01 }
body2 = { behaviour = "elastic", E = 210e9, nu = 0.5 }
grid = { n = [64, 48, 16], half_width = 4.0, depth = 1.5 }
fatigue = { bending_limit = 400e6, torsion_limit = 250e6 }

[[base.load.path]]
normal_force = 100.0

[[base.load.path]]
slide = [4e-4, 0.0]
steps = 4

[sample]
method = "sobol"
count = 8
seed = 1
"fatigue.torsion_limit" = { distribution = "uniform", range = [240e6, 300e6] }
"""
    campaign = load_campaign(write(tmp_path, text))
    limits = [case.spec["fatigue"]["torsion_limit"] for case in campaign.cases]
    assert len(set(limits)) == 8 and 240e6 <= min(limits) and max(limits) <= 300e6


FATIGUE_CAMPAIGN = """
[campaign]
name = "tired"

[base]
grid = { n = [40, 20, 16] }
body1 = { behaviour = "rigid", radius = 0.01 }
solver = { plastic_tolerance = 1e-4 }
fatigue = { bending_limit = 400e6, torsion_limit = 250e6 }
friction = { coefficient = 0.0 }

[base.body2]
behaviour = "elastic-plastic"
E = 210e9
nu = 0.3
hardening = { law = "perfect", yield_stress = 433.0127e6 }

[[base.load.path]]
hertz_pressure = 0.85e9
steps = 2

[[base.load.path]]
cycles = 2
stages = [{ slide = [0.2e-3, 0.0], steps = 6 }, { hertz_pressure = 0.0 },
          { slide = [-0.2e-3, 0.0] }, { hertz_pressure = 0.85e9, steps = 2 }]

[[base.load.path]]
slide = [0.05e-3, 0.0]
steps = 2

[sweep]
"friction.coefficient" = [0.0, 0.2, 0.45]
"""


def test_the_report_maps_the_fatigue_beside_the_shakedown_regime(tmp_path):
    """A small fatigue map (p0 = 3.4 k, mu = 0, 0.2 and 0.45, two passes and a last slide):
    the report's table repeats each case's factors, the map is drawn, and the case past
    mu p0 = k (surface flow in its first pass) has no pass and no factor, told in its notes."""
    from study_fixtures import write

    from study.campaign import load_campaign
    from study.report import build_report
    from study.run import storage
    from study.run.assemble import assemble_to_file
    from study.run.driver import RunOptions, run_campaign

    out = tmp_path / "out"
    campaign = load_campaign(write(tmp_path, FATIGUE_CAMPAIGN))
    run_campaign(campaign, out, options=RunOptions())
    assemble_to_file(out)
    text = build_report(out).read_text()
    section = text[text.index("## Fatigue under the pass") :]
    section = section[: section.index("\n## ", 5)].splitlines()  # to the next section
    rows = [line for line in section if line.startswith("| 0")]
    assert len(rows) == 2  # the surface-flow case has no factor
    import xarray as xr

    with xr.open_dataset(storage.dataset_path(out, "tired")) as data:
        factors = data["dang_van_factor"].values
        notes = data["notes"].values
    assert np.isfinite(factors[:2]).all() and np.isnan(factors[2])
    assert "fatigue: not evaluated" in str(notes[2])
    for row, factor in zip(rows, factors[:2], strict=True):
        assert float(row.split("|")[2]) == pytest.approx(factor, rel=1e-4)
    assert (out / "tired_fatigue_map.png").stat().st_size > 10_000


FRETTING_CAMPAIGN = """
[campaign]
name = "fretted"

[base]
grid = { n = [24, 24, 8] }
body1 = { behaviour = "elastic", E = 210e9, nu = 0.0, radius = 0.01 }
body2 = { behaviour = "elastic", E = 210e9, nu = 0.0 }
friction = { coefficient = 0.3 }
fatigue = { bending_limit = 400e6, torsion_limit = 250e6 }

[[base.load.path]]
normal_force = 100.0

[[base.load.path]]
tangential_force = 9.0
steps = 4

[[base.load.path]]
cycles = 2
stages = [{ tangential_force = -9.0, steps = 8 }, { tangential_force = 9.0, steps = 8 }]
"""


def test_a_fretting_campaign_reports_where_its_cycle_is_critical(tmp_path):
    """Two fretted spheres (+-0.3 mu W), W = 100 and 200 N: the dataset holds the cycle's
    fields over (x, y, z) and where along x each factor is; the report's fatigue table gives
    it over the contact radius (within two cells of the contact's edge)."""
    import xarray as xr
    from study_fixtures import write

    from study.campaign import load_campaign
    from study.report import build_report
    from study.run import storage
    from study.run.assemble import assemble_to_file
    from study.run.driver import RunOptions, run_campaign

    out = tmp_path / "out"
    text = FRETTING_CAMPAIGN + '\n[sweep]\n"load.path.0.normal_force" = [100.0, 200.0]\n'
    run_campaign(load_campaign(write(tmp_path, text)), out, options=RunOptions())
    assemble_to_file(out)
    with xr.open_dataset(storage.dataset_path(out, "fretted")) as data:
        where = data["dang_van_x"].values / data["hertz_radius"].values
        first = str(data["case_id"].values.ravel()[0])
    case = storage.open_case(out, first)
    assert case["dang_van_cycle_stress"].dims == ("x", "y", "z")
    assert np.all(np.abs(np.abs(where) - 1.0) < 0.25), where  # two cells (0.125 a) of the edge
    report = build_report(out).read_text()
    header = next(line for line in report.splitlines() if "dang_van_x/a" in line)
    assert "crossland_x/a" in header
