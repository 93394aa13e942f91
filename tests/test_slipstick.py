"""Slip-stick friction: Cattaneo-Mindlin, Spence, zero shear for beta = 0, stability."""

import copy
import dataclasses
import math

import numpy as np
import pytest

import solver
from solver.case.substeps import load_substeps
from solver.drive.operators import CaseOperators
from solver.drive.steps import ContactState, slip_stick_step
from solver.theory import friction

STEEL = {"behaviour": "elastic", "E": 210e9, "nu": 0.3}
#: Spence (1975), rigid sphere on a nu = 0 half-space (beta = -0.5), mu = 0.2986 (c/a = 0.5):
#: peak pressure over the Hertz one.  His self-similar solution comes from an integral
#: equation with no closed form; the value is read from his figure (README, validation).
SPENCE_PEAK_RATIO = 1.31


def cattaneo_table(n, fraction, mu=0.3, force=1000.0):
    return {
        "body1": {"radius": 0.015, **STEEL},
        "body2": {"radius": 0.015, **STEEL},
        "load": {
            "path": [
                {"normal_force": force, "steps": 1},
                {"tangential_force": [fraction * mu * force, 0.0], "steps": 1},
            ]
        },
        "friction": {"coefficient": mu},
        "grid": {"n": n, "half_width": 1.5},
    }


def spence_table(n, mu=0.2986, steps=20, nu=0.0):
    return {
        "body1": {"radius": 0.015, "behaviour": "rigid"},
        "body2": {"radius": "inf", "behaviour": "elastic", "E": 210e9, "nu": nu},
        "load": {"normal_force": 1000.0, "steps": steps},
        "friction": {"coefficient": mu},
        "grid": {"n": n, "half_width": 1.3},
    }


def radius(area):
    return np.sqrt(np.asarray(area) / math.pi)


def cattaneo_errors(result, fraction, mu=0.3):
    h = result.history
    a = radius(h["contact_area"][-1])
    c = radius(h["stick_area"][-1])
    force = h["normal_force"][-1]
    q = fraction * mu * force
    shear_modulus = 210e9 / 2.6
    # two identical bodies: twice the single-body compliance (Johnson 1985, eq. 7.42)
    ref_a = result.case.hertz.radius
    compliance = 2 * 3 * mu * force * (2 - 0.3) / (16 * shear_modulus * ref_a)
    shift = compliance * (1 - (1 - q / (mu * force)) ** (2 / 3))
    return {
        "c_over_a": c / a,
        "c_ref": (1 - fraction) ** (1 / 3),
        "shift_error": abs(h["tangential_shift_x"][-1] / shift - 1),
    }


@pytest.mark.validation
@pytest.mark.parametrize("fraction", [0.25, 0.5, 0.75])
def test_cattaneo_mindlin(fraction, validation):
    result = solver.solve(solver.Case.from_dict(cattaneo_table(128, fraction)))
    assert result.converged, result.notes
    assert "slip_stick" in result.loops
    e = cattaneo_errors(result, fraction)
    assert abs(e["c_over_a"] - e["c_ref"]) < 0.02
    assert e["shift_error"] < 0.02
    # slip annulus: |q| = mu p; stick: |q| < mu p; force exactly Q
    magnitude = np.hypot(result.shear_x, result.shear_y)
    bound = 0.3 * result.pressure
    slip = result.contact_state == 2
    assert slip.sum() > 0
    assert np.abs(magnitude[slip] - bound[slip]).max() < 1e-9 * bound.max()
    stick = result.contact_state == 1
    assert (magnitude[stick] < bound[stick]).all()
    q = result.history["tangential_force_x"][-1]
    assert q == pytest.approx(fraction * 0.3 * 1000.0, rel=1e-10)
    assert result.history["tangential_force_y"][-1] == pytest.approx(0.0, abs=1e-9 * q)
    validation(
        "Cattaneo-Mindlin, two steel spheres, Q = 0.25 / 0.5 / 0.75 mu W, 128^2",
        "c/a = (1 - Q/(mu W))^(1/3); tangential compliance (Johnson eq. 7.42); |q| = mu p in "
        "the slip annulus",
        f"Q = {fraction} mu W: c/a {e['c_over_a'] - e['c_ref']:+.4f}, compliance "
        f"{100 * e['shift_error']:.2f} %, slip |q| - mu p within "
        f"{np.abs(magnitude[slip] - bound[slip]).max() / bound.max():.0e} mu p_max",
    )


def test_cattaneo_stick_radius_converges_with_mesh():
    errors = []
    for n in (32, 64, 128):
        e = cattaneo_errors(solver.solve(solver.Case.from_dict(cattaneo_table(n, 0.5))), 0.5)
        errors.append(abs(e["c_over_a"] - e["c_ref"]) + e["shift_error"])
    assert errors[2] < errors[0]


@pytest.mark.validation
def test_beta_zero_normal_loading_gives_no_shear(validation):
    case = solver.Case.from_dict(
        {**cattaneo_table(48, 0.5, mu=0.5), "load": {"normal_force": 1000.0, "steps": 4}}
    )
    assert case.pair.dundurs_beta == 0.0
    assert not case.needs_slip_stick  # the scene skips the loop ...
    operators = CaseOperators.build(case)
    state = ContactState.unloaded(operators.gap.shape)
    for target in case.step_targets():  # ... and running it anyway changes nothing
        step = slip_stick_step(operators, state, target)
        assert step.converged
        assert step.iterations["slip"] == 0  # nothing drives the shear: q = 0, no iteration
        state = step.state
    assert not (state.shear_x.any() or state.shear_y.any())
    assert not (state.shear_slip_x.any() or state.shear_slip_y.any())  # K_t q
    scale = 0.5 * state.pressure.max()
    assert np.abs(state.shear_x).max() < 1e-10 * scale
    assert np.abs(state.shear_y).max() < 1e-10 * scale
    validation(
        "beta = 0, normal loading, mu = 0.5, 48^2, 4 steps",
        "no shear traction (Johnson §7.1)",
        f"largest |q| {max(np.abs(state.shear_x).max(), np.abs(state.shear_y).max()) / scale:.1e} "
        "mu p_max",
    )


@pytest.mark.validation
def test_spence_self_similar_stick_zone(validation):
    result = solver.solve(solver.Case.from_dict(spence_table(64)))
    assert result.converged, result.notes
    assert abs(result.case.pair.dundurs_beta) == pytest.approx(0.5)
    h = result.history
    ratio = radius(h["stick_area"]) / radius(h["contact_area"])
    assert ratio[-1] == pytest.approx(0.50, abs=0.03)
    assert np.abs(ratio - 0.5).max() < 0.03  # self-similar over all 20 steps
    # Self-similarity (Spence 1975): under proportional loading the traction distribution
    # scales with the Hertz one, so p_max / p_H(W) is the same at every step, where
    # p_H(W) = (6 W E*^2 / (pi^3 R^2))^(1/3) and E* = E / (1 - nu^2), nu = 0 (Johnson eq. 4.23)
    force = np.asarray(h["normal_force"])
    p_hertz = (6 * force * 210e9**2 / (math.pi**3 * 0.015**2)) ** (1 / 3)
    peak = np.asarray(h["max_pressure"]) / p_hertz
    assert np.abs(peak / peak[-1] - 1).max() < 0.02  # ~16 cells across at the first step
    # and at the end it is Spence's peak ratio for beta = -0.5, mu = 0.2986 (his self-similar
    # solution has no closed form: 1.31 read from his figure, README validation table)
    x, y = result.grid.mesh()
    centre = np.unravel_index(np.argmin(x * x + y * y), x.shape)
    a_hertz = math.pi * p_hertz[-1] * 0.015 / (2 * 210e9)  # a = pi p_H R / (2 E*)
    hertz_centre = p_hertz[-1] * math.sqrt(1 - (x[centre] ** 2 + y[centre] ** 2) / a_hertz**2)
    assert hertz_centre == pytest.approx(result.case.hertz.pressure(x[centre], y[centre]))
    assert result.pressure[centre] / hertz_centre == pytest.approx(SPENCE_PEAK_RATIO, abs=0.03)
    assert not result.notes
    validation(
        "Spence: rigid sphere, nu = 0 (beta = -0.5), mu = 0.2986, 20 steps, 64^2",
        "c/a = 0.5 at every step (self-similar), p_0 = 1.31 p_H (Spence 1975, his figure)",
        f"c/a {ratio[-1]:.3f} (all steps {ratio.min():.3f}-{ratio.max():.3f}), p_0 "
        f"{result.pressure[centre] / hertz_centre:.3f} p_H",
    )


MU_CURVE = (0.05, 0.1, 0.2, 0.3, 0.5, 0.8)


@pytest.mark.slow
@pytest.mark.validation
def test_spence_fine_mesh_and_mu_curve(capsys, validation):
    result = solver.solve(solver.Case.from_dict(spence_table(128)))
    h = result.history
    ratio = radius(h["stick_area"]) / radius(h["contact_area"])
    assert np.abs(ratio - 0.5).max() < 0.03
    curve = []
    for mu in MU_CURVE:
        r = solver.solve(solver.Case.from_dict(spence_table(64, mu=mu, nu=0.3)))
        h = r.history
        curve.append(float(radius(h["stick_area"][-1]) / radius(h["contact_area"][-1])))
    with capsys.disabled():
        print(
            "\nSpence nu=0.3, c/a over mu:",
            dict(zip(MU_CURVE, curve, strict=True)),
        )
    assert all(b >= a - 0.03 for a, b in zip(curve, curve[1:], strict=False))  # grows with mu
    validation(
        "Spence, beta = -0.5, 128^2; and nu = 0.3 (beta = -0.286) over mu, 64^2",
        "c/a = 0.5; c/a grows with mu, 0 as mu -> 0",
        f"c/a {ratio.min():.3f}-{ratio.max():.3f} over 20 steps; nu = 0.3: "
        + ", ".join(f"mu {m}: {c:.2f}" for m, c in zip(MU_CURVE, curve, strict=True)),
    )


def test_single_step_spence_is_flagged():
    result = solver.solve(solver.Case.from_dict(spence_table(32, steps=1)))
    assert any("path dependence" in note for note in result.notes)
    assert "path dependence" in result.to_xarray().attrs["notes"]


def test_load_substeps_are_geometric_and_exclusive():
    subs = load_substeps((0.0, 0.0, 0.0), (64.0, 6.4, 0.0), 2.0)
    assert [s[0] for s in subs] == pytest.approx([1, 2, 4, 8, 16, 32])
    assert [s[1] for s in subs] == pytest.approx([0.1, 0.2, 0.4, 0.8, 1.6, 3.2])
    assert load_substeps((10.0, 0, 0), (11.0, 0, 0), 1.25) == []
    assert load_substeps((10.0, 0, 0), (5.0, 0, 0), 1.25) == []  # unloading: none
    # a smallest resolvable load moves the start up (geometric from there)
    subs = load_substeps((0.0, 0.0, 0.0), (64.0, 6.4, 0.0), 2.0, smallest=8.0)
    assert [s[0] for s in subs] == pytest.approx([8, 16, 32])


@pytest.mark.parametrize(
    "mu,nu,steps,n",
    [(0.01, 0.0, 8, 32), (2.0, 0.0, 8, 32), (0.5, 0.3, 200, 32), (2.0, 0.49, 8, 48)],
)
def test_stability_hard_cases(mu, nu, steps, n):
    result = solver.solve(solver.Case.from_dict(spence_table(n, mu=mu, steps=steps, nu=nu)))
    ds = result.to_xarray()
    for name in ("pressure", "shear_x", "shear_y"):
        assert np.isfinite(ds[name]).all()
    # every step converges, and the status says so
    assert bool(ds.step_converged.all()) and ds.attrs["status"] == "converged", result.notes
    assert len(ds.step) == steps
    # equilibrium: the pressure carries W = 1000 N (the load ramps W k / steps) ...
    cell = result.grid.dx * result.grid.dy
    assert float(ds.pressure.sum()) * cell == pytest.approx(1000.0, rel=1e-8)
    assert ds.normal_force.values == pytest.approx(1000.0 * np.arange(1, steps + 1) / steps)
    # ... no tangential load: the shear tractions balance (|sum q| << mu W) ...
    for name in ("shear_x", "shear_y"):
        assert abs(float(ds[name].sum()) * cell) < 1e-6 * mu * 1000.0
    # ... and Coulomb holds everywhere: |q| <= mu p
    magnitude = np.hypot(ds.shear_x.values, ds.shear_y.values)
    assert (
        magnitude <= mu * ds.pressure.values * (1 + 1e-9) + 1e-12 * ds.pressure.max().item()
    ).all()
    if mu == 2.0:  # high friction: almost all stick
        assert ds.stick_area[-1] / ds.contact_area[-1] > 0.8


def test_extreme_beta_with_tangential_load_and_unloading():
    table = spence_table(32, mu=0.4, nu=0.0)
    table["load"] = {
        "path": [
            {"normal_force": 1000.0, "steps": 8},
            {"tangential_force": [300.0, 100.0], "steps": 4},
            {"tangential_force": [-300.0, 0.0], "steps": 4},
            {"normal_force": 800.0, "steps": 2},
        ]
    }
    result = solver.solve(solver.Case.from_dict(table))
    h = result.history
    assert len(h["normal_force"]) == 18
    assert h["tangential_force_x"][11] == pytest.approx(300.0, rel=1e-8)
    assert h["tangential_force_y"][11] == pytest.approx(100.0, rel=1e-8)
    assert h["tangential_force_x"][15] == pytest.approx(-300.0, rel=1e-8)
    assert h["normal_force"][-1] == pytest.approx(800.0, rel=1e-10)
    # reversal: the shift changes sign with the force
    assert h["tangential_shift_x"][11] > 0 > h["tangential_shift_x"][15]
    assert np.isfinite(result.pressure).all() and result.converged, result.notes


def test_goodman_drops_the_normal_coupling():
    table = spence_table(32, steps=4)
    table["solver"] = {"goodman": True}
    result = solver.solve(solver.Case.from_dict(table))
    frictionless = copy.deepcopy(table)
    frictionless["friction"]["coefficient"] = 0.0
    reference = solver.solve(solver.Case.from_dict(frictionless))
    np.testing.assert_allclose(
        result.pressure, reference.pressure, atol=1e-6 * reference.pressure.max()
    )
    assert np.abs(result.shear_x).max() > 0.01 * result.pressure.max()


def test_friction_dataset_layout():
    ds = solver.solve(solver.Case.from_dict(cattaneo_table(32, 0.5))).to_xarray()
    for name in (
        "shear_x",
        "shear_y",
        "contact_state",
        "tangential_force_x",
        "tangential_force_y",
        "tangential_shift_x",
        "tangential_shift_y",
        "stick_area",
        "slip_iterations",
    ):
        assert name in ds and "long_name" in ds[name].attrs
    assert ds.contact_state.dtype == np.int8
    assert list(ds.contact_state.attrs["flag_values"]) == [0, 1, 2]
    assert ds.contact_state.attrs["flag_meanings"] == "separated stick slip"
    assert "slip_stick" in ds.attrs["loops"]
    assert ds.shear_x.attrs["units"] == "Pa"


def test_mindlin_deresiewicz_energy_is_the_loop_area():
    # the closed form against a quadrature of the two loop branches it integrates
    mu, force, compliance, amplitude = 0.3, 1000.0, 2e-6, 120.0
    psi = lambda x: 1 - (1 - x) ** (2 / 3)  # noqa: E731
    q = np.linspace(-amplitude, amplitude, 20001)
    peak = compliance * psi(amplitude / (mu * force))
    down = peak - 2 * compliance * psi((amplitude - q) / (2 * mu * force))
    up = -peak + 2 * compliance * psi((q + amplitude) / (2 * mu * force))
    area = np.trapezoid(down - up, q)
    assert friction.mindlin_deresiewicz_energy(amplitude, mu, force, compliance) == pytest.approx(
        area, rel=1e-7
    )


@pytest.mark.validation
def test_fretting_loop_energy_matches_mindlin_deresiewicz(validation):
    """Two identical spheres (beta = 0), Q: 0 -> +Q* -> -Q* -> +Q*: the last cycle's loop area."""
    mu, fraction, force, steps = 0.3, 0.5, 1000.0, 20
    amplitude = fraction * mu * force
    errors = []
    for n in (32, 64):
        table = cattaneo_table(n, fraction, mu=mu, force=force)
        table["load"]["path"][1:] = [
            {"tangential_force": [sign * amplitude, 0.0], "steps": steps} for sign in (1, -1, 1)
        ]
        result = solver.solve(solver.Case.from_dict(table))
        assert result.converged, result.notes
        h = result.history
        cycle = slice(steps, None)  # from the end of the first +Q* stage
        area = abs(np.trapezoid(h["tangential_force_x"][cycle], h["tangential_shift_x"][cycle]))
        shear_modulus = 210e9 / 2.6
        # two identical bodies: twice the single-body full-slip shift (Johnson 1985, eq. 7.42)
        full_slip = 2 * 3 * mu * force * (2 - 0.3) / (16 * shear_modulus * result.case.hertz.radius)
        expected = friction.mindlin_deresiewicz_energy(amplitude, mu, force, full_slip)
        errors.append(abs(area / expected - 1))
    assert errors[1] < errors[0]
    assert errors[1] < 0.01
    validation(
        "fretting loop, two steel spheres (beta = 0), Q: 0 -> +Q* -> -Q* -> +Q*, "
        "Q* = 0.5 mu W, 20 steps per stage, 32^2 / 64^2",
        "energy per cycle, Mindlin & Deresiewicz (Johnson eq. 7.64)",
        f"{100 * errors[0]:.2f} % / {100 * errors[1]:.2f} % (magnitude)",
    )


def test_uncoupled_tangential_stage_reuses_the_normal_solution():
    """beta = 0: a tangential stage at fixed W solves no normal problem again, and its pressure
    is the normal contact solution of that W; a stage that also changes W solves anew."""
    table = cattaneo_table(32, 0.5)
    table["load"]["path"][1]["steps"] = 4
    table["load"]["path"].append({"normal_force": 1500.0, "tangential_force": [0.0, 0.0]})
    case = solver.Case.from_dict(table)
    result = solver.solve(case)
    assert result.converged
    h = result.history
    assert h["normal_iterations"][0] > 0
    assert np.all(h["normal_iterations"][1:5] == 0)  # W = 1000 N throughout
    assert h["normal_iterations"][5] > 0  # W = 1500 N: a new normal problem
    operators = CaseOperators.build(case)
    fresh = solver.surface.normal.solve_normal(operators.surface, operators.gap, 1500.0)
    assert np.abs(result.pressure - fresh.pressure).max() < 1e-6 * fresh.pressure.max()
    assert h["approach"][5] == pytest.approx(fresh.approach, rel=1e-6)
    assert np.all(h["approach"][1:5] == h["approach"][0])


def test_state_carries_the_tangential_displacement_of_its_shear():
    """The next increment's memory term K_t q_{k-1} is taken from the state: it must equal a
    fresh convolution of the state's shear tractions."""
    case = solver.Case.from_dict(cattaneo_table(32, 0.5))
    operators = CaseOperators.build(case)
    state = ContactState.unloaded(operators.gap.shape)
    for target in case.step_targets():
        state = slip_stick_step(operators, state, target).state
    ux, uy = operators.surface.tangential(state.shear_x, state.shear_y)
    scale = np.abs(ux).max()
    assert np.abs(state.shear_slip_x - ux).max() < 1e-12 * scale
    assert np.abs(state.shear_slip_y - uy).max() < 1e-12 * scale


def test_extrapolated_start_only_for_a_repeated_increment():
    from solver.drive.loops import _extrapolated

    shape = (4, 4)
    rng = np.random.default_rng(1)
    older = dataclasses.replace(ContactState.unloaded(shape), shear_x=rng.random(shape))
    state = dataclasses.replace(older, shear_x=rng.random(shape), shear_y=rng.random(shape))
    step = np.array([0.0, 10.0, 0.0])
    start = _extrapolated(state, (older, step), step)
    assert np.array_equal(start.shear_x, 2 * state.shear_x - older.shear_x)
    assert np.array_equal(start.pressure, state.pressure)
    assert _extrapolated(state, (older, step), 2 * step) is None  # a different increment
    assert _extrapolated(state, None, step) is None


def test_substep_iterations_are_counted(monkeypatch):
    """The iteration histories include the sub-steps of a coupled scene: their sums equal what
    the normal and tangential solvers reported over the whole solve."""
    import solver.drive.steps as steps

    reported = {"normal": [], "slip": []}

    def counting(function, key):
        def wrapper(*args, **kwargs):
            solution = function(*args, **kwargs)
            reported[key].append(solution.iterations)
            return solution

        return wrapper

    for name, key in (
        ("solve_normal", "normal"),
        ("solve_tangential", "slip"),
        ("solve_tangential_coupled", "slip"),
    ):
        monkeypatch.setattr(steps, name, counting(getattr(steps, name), key))
    result = solver.solve(solver.Case.from_dict(spence_table(24, steps=4)))
    assert result.converged
    h = result.history
    assert len(reported["normal"]) > h["coupling_iterations"][-1]  # sub-steps ran
    assert h["slip_iterations"].sum() == sum(reported["slip"])
    assert h["normal_iterations"].sum() == sum(reported["normal"])
    assert h["coupling_iterations"].sum() == len(reported["normal"])


@pytest.mark.parametrize("path", ["spence", "shear_reversal_unloading"])
def test_merged_coupling_equals_alternating_solves(monkeypatch, path):
    """beta != 0: the merged iteration (the pressure renewed after every Newton step of the
    tangential solve) converges to the solution of alternating whole solves, to the
    tolerances, falling back on them at most once (the first sub-step of Spence's scene, a
    contact of a dozen cells whose split has no stick cell)."""
    import solver.drive.steps as steps

    if path == "spence":
        table = spence_table(40, steps=10)
    else:
        table = spence_table(40, mu=0.5)
        table["load"] = {
            "path": [
                {"normal_force": 1000.0, "steps": 10},
                {"tangential_force": [150.0, 0.0], "steps": 5},
                {"tangential_force": [-100.0, 50.0], "steps": 5},
                {"normal_force": 400.0, "steps": 4},
            ]
        }
    case = solver.Case.from_dict(table)
    monkeypatch.setattr(steps, "MERGED_COUPLING", False)
    alternating = solver.solve(case)
    monkeypatch.setattr(steps, "MERGED_COUPLING", True)
    outcomes = []
    original = steps.solve_tangential_coupled

    def recording(*args, **kwargs):
        solution = original(*args, **kwargs)
        outcomes.append(solution.converged)
        return solution

    monkeypatch.setattr(steps, "solve_tangential_coupled", recording)
    merged = solver.solve(case)
    assert alternating.converged and merged.converged
    assert len(outcomes) >= 10 and outcomes.count(False) <= 1  # the fallbacks

    def rms_difference(a, b):
        return np.sqrt(np.mean((a - b) ** 2) / np.mean(a**2))

    for name in ("pressure", "shear_x", "shear_y"):
        a, b = getattr(alternating, name), getattr(merged, name)
        if a.any():
            assert rms_difference(a, b) < 1e-4, name
    h_a, h_m = alternating.history, merged.history
    assert np.allclose(h_m["tangential_shift_x"], h_a["tangential_shift_x"], rtol=1e-4, atol=1e-12)
    assert np.allclose(h_m["approach"], h_a["approach"], rtol=1e-6)
    assert abs(np.sum(merged.contact_state == 1) - np.sum(alternating.contact_state == 1)) <= 4
    assert h_m["slip_iterations"].sum() < h_a["slip_iterations"].sum()


def test_the_force_projection_stays_finite_when_no_cell_can_carry_the_force():
    """Every friction bound 0 (no pressure left) and a tangential force asked: the projection's
    force multiplier had no slope to follow and went to inf (NaN tractions, seen in a 50-pass
    rolling run); it now stops there, finite, and the force it misses is the caller's residual."""
    import warnings

    from solver.surface.tangential import project_onto_feasible

    z = np.ones((4, 4))
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # an invalid value or overflow fails the test
        qx, qy, multiplier = project_onto_feasible(
            z, 0 * z, np.zeros((4, 4)), np.array([1.0, 0.0]), np.zeros(2)
        )
    assert np.isfinite(multiplier).all() and not qx.any() and not qy.any()
    z = np.linspace(0.1, 1.0, 16).reshape(4, 4)  # bounds that can carry it: the force is met
    bound = np.full((4, 4), 0.5)
    qx, qy, _ = project_onto_feasible(z, 0 * z, bound, np.array([2.0, 0.0]), np.zeros(2))
    assert qx.sum() == pytest.approx(2.0, rel=1e-12) and np.all(np.hypot(qx, qy) <= bound + 1e-15)


def test_a_ramp_a_steady_stage_follows_is_not_flagged():
    """A steady rolling state does not depend on the path to it: no path-dependence note."""
    from solver.drive.record import path_dependence_notes

    soft = {"behaviour": "elastic", "E": 70e9, "nu": 0.3}
    table = {
        "body1": {"behaviour": "elastic", "radius": 0.05, "E": 210e9, "nu": 0.3},
        "body2": soft, "friction": {"coefficient": 0.3}, "grid": {"n": [20, 20]},
        "load": {"path": [{"normal_force": 3000.0}, {"steady": True, "creepage": [1e-3, 0.0]}]},
    }  # fmt: skip
    assert path_dependence_notes(solver.Case.from_dict(table)) == []
    table["load"]["path"] += [{"normal_force": 0.0}, {"normal_force": 4000.0}]
    notes = path_dependence_notes(solver.Case.from_dict(table))  # the ramp after it is
    assert len(notes) == 1 and "load stage 4 (1 step)" in notes[0], notes
