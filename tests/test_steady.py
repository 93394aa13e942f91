"""Steady rolling solved directly (issue 39, first step): ``steady = true`` stages.

Independent references: Kalker's linear creep coefficients C11, C22, C23 of a circular contact
(his tables, :data:`solver.theory.friction.KALKER_CIRCLE_COEFFICIENTS`) in the small-creepage
limit; the transient march of one-cell steps, whose end state the first-order scheme is by
construction, rolled long enough; full slip at mu W.  Hard cases end with a status.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import solver
from solver import SpecError
from solver.result import STICK
from solver.theory.friction import KALKER_CIRCLE_COEFFICIENTS, KALKER_ELLIPSE_COEFFICIENTS

E, NU, MU, W = 210e9, 0.25, 0.3, 1000.0
G = E / (2 * (1 + NU))
BODIES = {
    "body1": {"behaviour": "elastic", "E": E, "nu": NU, "radius": 0.025},
    "body2": {"behaviour": "elastic", "E": E, "nu": NU},
    "friction": {"coefficient": MU},
}


def _steady(stage: dict, cells: int = 8, order: int = 2, **changes) -> solver.Case:
    """Load W, then one steady stage; cells of a / ``cells`` over a grid of +-1.25 a."""
    n = round(2.5 * cells)
    table = {
        **BODIES,
        "load": {"path": [{"normal_force": W}, {"steady": True, **stage}]},
        "grid": {"n": [n, n], "half_width": 1.25},
        "solver": {"steady_order": order},
        **changes,
    }
    return solver.Case.from_dict(table)


def _coefficients(cells: int, order: int) -> tuple[float, float, float]:
    """C11, C22, C23 of a nearly adhering contact (creepage 1e-7, spin 1e-4 / m)."""
    out = []
    for stage, component in (
        ({"creepage": [1e-7, 0.0]}, "x"),
        ({"creepage": [0.0, 1e-7]}, "y"),
        ({"spin": 1e-4}, "y"),
    ):
        case = _steady(stage, cells, order)
        result = solver.solve(case)
        assert result.status == "converged"
        a = case.hertz.radius
        force = result.history[f"tangential_force_{component}"][-1]
        scale = G * a**3 * 1e-4 if "spin" in stage else G * a * a * 1e-7
        out.append(force / scale)
    return tuple(out)


@pytest.mark.validation
def test_small_creepage_gives_kalkers_coefficients_and_converges(validation):
    expected = KALKER_CIRCLE_COEFFICIENTS[NU]
    second = _coefficients(16, 2)
    errors = [c / e - 1.0 for c, e in zip(second, expected, strict=True)]
    assert abs(errors[0]) < 0.01 and abs(errors[1]) < 0.01 and abs(errors[2]) < 0.02
    first = [_coefficients(cells, 1)[0] / expected[0] - 1.0 for cells in (8, 16)]
    assert abs(first[1]) < 0.7 * abs(first[0])  # first order: the error shrinks with the cells
    validation(
        "Steady rolling solved directly, circular contact, small creepage (solver.surface.steady)",
        f"Kalker 1967: C11, C22, C23 = {expected[0]}, {expected[1]}, {expected[2]} (nu = {NU})",
        "second order at a/16: " + ", ".join(f"{e:+.2%}" for e in errors)
        + f"; first order C11 {first[0]:+.2%}, {first[1]:+.2%} at a/8, a/16",
    )  # fmt: skip


@pytest.mark.parametrize("stage", [{"creepage": [1e-9, 0.0]}, {"spin": 1e-6}])
def test_vanishing_creepage_is_solved_to_the_tolerance(stage):
    """Near full stick the force is as accurate as anywhere else.

    The residual is measured on the tractions' own size there (r |c|): on mu p, tractions a
    millionth of it passed the default tolerance with the linear solve's 3 % error.
    """
    forces = []
    for tolerance in (1e-6, 1e-11):
        result = solver.solve(_steady(stage, 8, solver={"slip_tolerance": tolerance}))
        assert result.status == "converged"
        forces.append(
            np.hypot(
                result.history["tangential_force_x"][-1], result.history["tangential_force_y"][-1]
            )
        )
    assert forces[0] == pytest.approx(forces[1], rel=1e-4)


def _ellipsoid(radius_x: float) -> dict:
    return {"behaviour": "elastic", "E": E, "nu": NU, "radius_x": radius_x, "radius_y": 0.025}


def _semi_axes(radius_x: float) -> tuple[float, float]:
    """Hertz's semi-axes (a along x, b) of body 1 with radii (radius_x, 25 mm) under W."""
    table = {
        **BODIES,
        "body1": _ellipsoid(radius_x),
        "load": {"normal_force": W},
        "grid": {"n": [600, 600]},  # fine enough for any ratio tried: only Hertz is read
    }
    hertz = solver.Case.from_dict(table).hertz
    return hertz.semi_axis_x, hertz.semi_axis_y


@pytest.mark.validation
@pytest.mark.parametrize("ratio", [0.5, 2.0])
def test_elliptical_contacts_give_kalkers_coefficients(ratio, validation):
    """a/b = 0.5 and 2: C11, C22, C23 (on c = sqrt(ab)) at 8 cells on the smaller semi-axis."""
    from scipy.optimize import brentq

    radius_x = brentq(
        lambda r: _semi_axes(r)[0] / _semi_axes(r)[1] - ratio, 0.025 / 50, 0.025 * 50, rtol=1e-10
    )
    a, b = _semi_axes(radius_x)
    c, h = math.sqrt(a * b), min(a, b) / 8
    n = [round(2.5 * a / h), round(2.5 * b / h)]
    found = []
    for stage, component in (
        ({"creepage": [1e-7, 0.0]}, "x"),
        ({"creepage": [0.0, 1e-7]}, "y"),
        ({"spin": 1e-4}, "y"),
    ):
        table = {
            **BODIES,
            "body1": _ellipsoid(radius_x),
            "load": {"path": [{"normal_force": W}, {"steady": True, **stage}]},
            "grid": {"n": n, "size": [n[0] * h, n[1] * h]},
        }
        result = solver.solve(solver.Case.from_dict(table))
        assert result.status == "converged"
        force = result.history[f"tangential_force_{component}"][-1]
        found.append(force / (G * c**3 * 1e-4 if "spin" in stage else G * c * c * 1e-7))
    expected = KALKER_ELLIPSE_COEFFICIENTS[ratio][NU]
    errors = [f / e - 1.0 for f, e in zip(found, expected, strict=True)]
    assert max(abs(e) for e in errors) < 0.01
    validation(
        f"Steady rolling solved directly, elliptical contact a/b = {ratio:g} "
        "(solver.surface.steady)",
        f"Kalker 1990, table E.3: C11, C22, C23 = {', '.join(map(str, expected))} (nu = {NU})",
        "at 8 cells on the smaller semi-axis: " + ", ".join(f"{e:+.2%}" for e in errors),
    )


def test_the_transient_march_of_one_cell_steps_ends_at_the_first_order_steady_state():
    xi = 0.001
    steady = _steady({"creepage": [xi, 0.0]}, 8, order=1)
    a, dx = steady.hertz.radius, steady.surface_grid.dx
    result = solver.solve(steady)
    force = result.history["tangential_force_x"][-1]
    travel = 8.0 * a
    march = solver.Case.from_dict(
        {
            **BODIES,
            "load": {
                "path": [
                    {"normal_force": W},
                    {"roll": [travel, 0.0], "creepage": [xi, 0.0], "steps": round(travel / dx)},
                ]
            },
            "grid": {"n": [round(10.5 * 8), 20], "half_width": 1.25},
        }
    )
    assert march.surface_grid.dx == pytest.approx(dx)
    rolled = solver.solve(march).history["tangential_force_x"]
    assert abs(rolled[-1] - force) < 0.002 * MU * W
    assert abs(rolled[-1] - force) < 0.5 * abs(rolled[-9] - force)  # still closing on it
    # the stick zone at the leading edge (+x), the slip zone behind
    x, _ = result.grid.mesh()
    assert x[result.contact_state == STICK].mean() > 0.0


@pytest.mark.parametrize("xi_n", [0.1, 0.3, 0.6])
def test_the_march_rolled_4a_from_a_cattaneo_start_agrees_within_half_a_percent(xi_n):
    """Acceptance: the transient rolled 4 a and the steady solve within 0.5 % of mu W.

    The march starts shifted to 0.9 of the Johnson-Vermeulen force (deliberately off) and
    rolls in steps of one cell: its discretisation is the first-order steady scheme's.
    """
    a = _steady({"creepage": [1e-7, 0.0]}, 8).hertz.radius
    xi = xi_n * 3 * MU * W / (G * a * a * KALKER_CIRCLE_COEFFICIENTS[NU][0])
    steady = _steady({"creepage": [xi, 0.0]}, 8, order=1)
    force = solver.solve(steady).history["tangential_force_x"][-1]
    start = 0.9 * (1.0 - (1.0 - xi_n) ** 3) * MU * W
    travel, dx = 4.0 * a, steady.surface_grid.dx
    path = [
        {"normal_force": W},
        {"tangential_force": [start, 0.0], "steps": 4},
        {"roll": [travel, 0.0], "creepage": [xi, 0.0], "steps": round(travel / dx)},
    ]
    march = solver.Case.from_dict(
        {**BODIES, "load": {"path": path}, "grid": {"n": [52, 20], "half_width": 1.25}}
    )
    assert march.surface_grid.dx == pytest.approx(dx)
    rolled = solver.solve(march)
    assert rolled.status == "converged"
    assert abs(rolled.history["tangential_force_x"][-1] - force) < 0.005 * MU * W


def test_a_prescribed_force_finds_the_creepage_that_gives_it():
    """The force of a creepage-given steady state, prescribed: the same creepage comes back.

    Solved to a relative residual of 1e-10 (the default 1e-6 bounds the force's error by
    1e-6 rms(mu p), a few 1e-7 of this force).
    """
    tight = {"solver": {"slip_tolerance": 1e-10, "steady_order": 2}}
    given = solver.solve(_steady({"creepage": [0.002, 0.001], "steps": 2}, 8, **tight))
    force = [float(given.history[f"tangential_force_{c}"][-1]) for c in "xy"]
    found = solver.solve(_steady({"tangential_force": force, "steps": 2}, 8, **tight))
    assert found.status == "converged"
    assert found.history["creepage_x"][-1] == pytest.approx(0.002, rel=1e-6)
    assert found.history["creepage_y"][-1] == pytest.approx(0.001, rel=1e-5)
    assert found.history["tangential_force_x"][-1] == pytest.approx(force[0], rel=1e-8)
    assert given.history["creepage_x"][1] == pytest.approx(0.001)  # the ramp's midpoint
    # half the force needs less than half the creepage (the curve bends over)
    assert 0.0 < found.history["creepage_x"][1] < 0.5 * 0.002


def test_a_prescribed_force_with_spin_finds_the_creepage_that_gives_it():
    """Creepage and spin given, then their force prescribed with the same spin ramp: the
    creepage comes back at every point of the ramp, and the spin is recorded as given."""
    tight = {"solver": {"slip_tolerance": 1e-10, "steady_order": 2}}
    spin = 3.0  # 1/m: spin a = 1.7e-3, a third of the lateral force
    given = _steady({"creepage": [0.001, 0.0005], "spin": spin, "steps": 2}, 8, **tight)
    given = solver.solve(given)
    force = [float(given.history[f"tangential_force_{c}"][-1]) for c in "xy"]
    found = solver.solve(_steady({"tangential_force": force, "spin": spin, "steps": 2}, 8, **tight))
    assert found.status == "converged"
    assert found.history["creepage_x"][-1] == pytest.approx(0.001, rel=1e-6)
    assert found.history["creepage_y"][-1] == pytest.approx(0.0005, rel=1e-5)
    np.testing.assert_array_equal(found.history["spin"], given.history["spin"])
    assert found.history["spin"][1] == pytest.approx(0.5 * spin)  # ramped like a creepage
    # without the spin the same force takes another lateral creepage
    plain = solver.solve(_steady({"tangential_force": force, "steps": 1}, 8, **tight))
    assert plain.history["creepage_y"][-1] > 0.0005 * 1.2


@pytest.mark.validation
def test_spin_at_zero_force_takes_kalkers_lateral_creepage(validation):
    """A free contact (zero tangential force) spinning at small phi creeps laterally by
    eta = -C23 a phi / C22 (Kalker's linear theory): no lateral force.

    Against the grid's own coefficients (from creepage and spin solved alone) to the
    tolerance (the force and spin enter linearly near full stick), and against Kalker's
    table within 1 %, closer at a/16 than at a/8.
    """
    c22, c23 = KALKER_CIRCLE_COEFFICIENTS[NU][1:]
    spin = 1e-2  # 1/m: linear
    errors = []
    for cells in (8, 16):
        case = _steady({"tangential_force": [0.0, 0.0], "spin": spin}, cells)
        result = solver.solve(case)
        assert result.status == "converged"
        a = case.hertz.radius
        eta = result.history["creepage_y"][-1]
        assert abs(result.history["creepage_x"][-1]) < 1e-6 * abs(eta)
        own = _coefficients(cells, 2)
        assert eta == pytest.approx(-own[2] * a * spin / own[1], rel=2e-4)
        errors.append(eta / (-c23 * a * spin / c22) - 1.0)
    assert abs(errors[1]) < abs(errors[0]) < 0.01
    validation(
        "Steady rolling at a prescribed force with spin (solver.surface.steady)",
        f"Kalker 1967: zero force at spin phi gives eta = -C23 a phi / C22 (nu = {NU})",
        f"eta {errors[0]:+.2%} at a/8, {errors[1]:+.2%} at a/16 (second order)",
    )


def test_the_march_at_a_prescribed_force_and_spin_ends_at_the_steady_creepage():
    """Rolled 4 a in one-cell steps at the force and spin of a first-order steady state (from
    a Cattaneo start at that force), the march's creepage (its shift per distance rolled)
    ends at the steady creepage."""
    xi, spin = (0.001, 0.0005), 3.0
    steady = _steady({"creepage": list(xi), "spin": spin}, 8, order=1)
    a, dx = steady.hertz.radius, steady.surface_grid.dx
    result = solver.solve(steady)
    force = [float(result.history[f"tangential_force_{c}"][-1]) for c in "xy"]
    travel = 4.0 * a
    path = [
        {"normal_force": W},
        {"tangential_force": force, "steps": 4},
        {"roll": [travel, 0.0], "tangential_force": force, "spin": spin,
         "steps": round(travel / dx)},
    ]  # fmt: skip
    march = solver.Case.from_dict(
        {**BODIES, "load": {"path": path}, "grid": {"n": [52, 20], "half_width": 1.25}}
    )
    assert march.surface_grid.dx == pytest.approx(dx)
    rolled = solver.solve(march)
    assert rolled.status == "converged"
    for component, target in zip("xy", xi, strict=True):
        creep = np.diff(rolled.history[f"tangential_shift_{component}"]) / dx
        assert creep[-1] == pytest.approx(target, rel=1e-3)
        assert abs(creep[-1] - target) < 0.5 * abs(creep[-17] - target)  # closing on it


def test_a_creep_curve_rises_to_mu_w():
    case = _steady({"creepage": [0.004, 0.0], "steps": 8}, 8)
    result = solver.solve(case)
    force = result.history["tangential_force_x"][1:] / (MU * W)
    assert result.status == "converged"
    assert np.all(np.diff(force) > 0.0) and force[-1] < 1.0 + 1e-9
    full = solver.solve(_steady({"creepage": [0.05, 0.0]}, 8))
    assert full.history["tangential_force_x"][-1] == pytest.approx(MU * W, rel=2e-3)
    assert (full.contact_state != STICK).all()


@pytest.mark.parametrize(
    "stage, changes",
    [
        ({"creepage": [1.0, 0.0]}, {}),  # full slip at the largest creepage
        ({"spin": 50.0}, {}),  # spin alone, past saturation (about 15 / m)
        (
            {"creepage": [0.002, 0.0]},
            {"body1": {"behaviour": "rigid", "radius": 0.025}},  # beta = -0.29: coupled
        ),
        (
            {"creepage": [0.002, 0.0]},
            {"body2": {"behaviour": "rigid"}},  # beta = +0.33: a steel ball on a rigid flat
        ),
        # a prescribed force near saturation with a spin past its own, and one with beta != 0
        ({"tangential_force": [0.99 * MU * W, 0.0], "spin": 50.0}, {}),
        (
            {"tangential_force": [0.5 * MU * W, 0.0], "spin": 20.0},
            {"body1": {"behaviour": "rigid", "radius": 0.025}},
        ),
    ],
)
def test_hard_cases_end_with_a_status(stage, changes):
    result = solver.solve(_steady(stage, 8, **changes))
    assert result.status in ("converged", "not_converged")
    for values in result.history.values():
        assert not np.isnan(np.asarray(values, float)).any()
    assert result.status == "converged"
    assert math.hypot(*(result.history[f"tangential_force_{c}"][-1] for c in "xy")) <= (
        MU * W * (1 + 1e-6)
    )


def test_a_contact_at_the_leading_edge_is_told_not_solved():
    table = {
        **BODIES,
        "load": {"path": [{"normal_force": W}, {"steady": True, "creepage": [0.001, 0.0]}]},
        "grid": {"n": [22, 22], "half_width": 1.1},  # row centres 0.95 a and 1.05 a
    }
    result = solver.solve(solver.Case.from_dict(table))
    assert result.status == "not_converged"
    assert any("leading edge" in note for note in result.notes)


@pytest.mark.parametrize(
    "stage, key",
    [
        ({"roll": [1e-4, 0.0], "creepage": [0.001, 0.0]}, "roll"),
        ({}, "steady"),
        ({"tangential_force": [10.0, 0.0], "creepage": [0.001, 0.0]}, "tangential_force"),
        ({"creepage": [0.001, 0.0], "steady": "yes"}, "steady"),
    ],
)
def test_bad_steady_stages_are_refused_by_name(stage, key):
    table = {
        **BODIES,
        "load": {"path": [{"normal_force": W}, {"steady": True, **stage}]},
        "grid": {"n": [20, 20]},
    }
    with pytest.raises(SpecError, match=rf"load.path\[1\].{key}"):
        solver.Case.from_dict(table)


def test_the_steady_order_without_a_steady_stage_is_refused():
    table = {**BODIES, "load": {"normal_force": W}, "grid": {"n": [20, 20]}}
    table["solver"] = {"steady_order": 1}
    with pytest.raises(SpecError, match="solver.steady_order: only a steady stage"):
        solver.Case.from_dict(table)


def test_an_elastic_plastic_body_is_refused_a_steady_stage():
    body = {"behaviour": "elastic-plastic", "E": E, "nu": NU}
    body["hardening"] = {"law": "perfect", "yield_stress": 1e9}
    table = {
        **BODIES,
        "body2": body,
        "load": {"path": [{"normal_force": W}, {"steady": True, "creepage": [0.001, 0.0]}]},
        "grid": {"n": [20, 20, 16]},
    }
    with pytest.raises(SpecError, match="load.path: a steady rolling stage .* elastic bodies"):
        solver.Case.from_dict(table)


def test_a_rounded_flat_punch_rolls_steadily_too():
    """Any shape the normal solver takes: a flat punch with rounded edges (a profile)."""
    punch = {"shape": "flat_punch", "radius": 0.3e-3, "edge_radius": 0.02}
    table = {
        **BODIES,
        "body1": {"behaviour": "elastic", "E": E, "nu": NU, "profile": punch},
        "load": {"path": [{"normal_force": W}, {"steady": True, "creepage": [0.002, 0.0]}]},
        "grid": {"n": [48, 48], "half_width": 1.3},
    }
    result = solver.solve(solver.Case.from_dict(table))
    assert result.status == "converged"
    assert 0.0 < result.history["tangential_force_x"][-1] < MU * W
    x, _ = result.grid.mesh()
    assert x[result.contact_state == STICK].mean() > 0.0  # stick at the leading edge


STEADY_CAMPAIGN = """
[campaign]
name = "steady"
output = "out"

[base]
grid = { n = [20, 20], half_width = 1.25 }
body1 = { behaviour = "elastic", radius = 0.025, E = 210e9, nu = 0.25 }
body2 = { behaviour = "elastic", E = 210e9, nu = 0.25 }
friction = { coefficient = 0.3 }

[[base.load.path]]
normal_force = 1000.0

[[base.load.path]]
steady = true
creepage = [0.004, 0.0]
steps = 6

[sweep]
"friction.coefficient" = [0.2, 0.4]
"""


def test_a_campaign_of_steady_creep_curves_assembles_and_reports(tmp_path):
    import xarray as xr
    from study_fixtures import write

    from study.campaign import load_campaign
    from study.report import build_report
    from study.run.assemble import assemble_to_file
    from study.run.driver import RunOptions, run_campaign

    campaign = load_campaign(write(tmp_path, STEADY_CAMPAIGN))
    assert run_campaign(campaign, tmp_path / "out", options=RunOptions()).exit_status == 0
    dataset = assemble_to_file(tmp_path / "out")
    with xr.open_dataset(dataset) as data:
        xi = data["creepage_x_history"].sel(friction_coefficient=0.2).values
        force = data["tangential_force_x_history"].sel(friction_coefficient=0.2).values
    assert xi[1:] == pytest.approx(0.004 * np.arange(1, 7) / 6)
    assert np.all(np.diff(force[1:]) > 0.0) and force[-1] <= 0.2 * W * (1 + 1e-9)
    text = build_report(tmp_path / "out").read_text()
    assert "## Steady creep curves" in text
    assert (tmp_path / "out" / "steady_steady_creep_curves.png").exists()


def _small_operator(cells: int, size: float):
    """A surface operator of the scene's pair on ``cells`` x ``cells`` cells of ``size`` (m)."""
    from solver.bodies.materials import Body, Pair
    from solver.numerics.grid import SurfaceGrid
    from solver.surface.convolution import SurfaceOperator

    steel = Body("elastic", E=E, nu=NU)
    grid = SurfaceGrid.centred(cells, cells, 0.5 * size * cells, 0.5 * size * cells)
    return SurfaceOperator(grid, Pair(steel, steel))


@pytest.mark.parametrize("order", [1, 2])
def test_undo_upwind_inverts_the_upwind_difference(order):
    from solver.surface.steady import undo_upwind, upwind

    rng = np.random.default_rng(3)
    u = rng.standard_normal((30, 7))
    u[-order:] = 0.0  # zero ahead of the grid's leading rows
    assert np.allclose(undo_upwind(upwind(u, 0.1, order), 0.1, order), u, atol=1e-12)


def _circle(cells: int, order: int = 2, width: float = 1.25):
    """A small operator of ``width`` contact diameters, a circular contact of ``cells`` across
    and its steady operator."""
    from solver.surface.steady import SteadyOperator

    operator = _small_operator(round(width * cells), 1e-3 / cells)
    x, y = operator.grid.mesh()
    contact = np.hypot(x, y) < 0.5e-3
    return operator, contact, SteadyOperator(operator, contact, order)


@pytest.mark.parametrize("order", [1, 2])
@pytest.mark.parametrize("cells", [7, 16])
def test_the_steady_operator_is_the_upwind_difference_of_the_displacement(order, cells):
    """On the contact's box: ``A v`` equals :func:`upwind` of ``K_t v`` on the grid."""
    from solver.surface.steady import upwind

    operator, contact, steady = _circle(cells, order, 1.5)  # off the last rows
    rng = np.random.default_rng(cells)
    v = rng.standard_normal((2, int(contact.sum())))
    field = np.zeros((2, *contact.shape))
    field[:, contact] = v
    expected = np.array(
        [upwind(u, operator.grid.dx, order)[contact] for u in operator.tangential(*field)]
    )
    assert np.allclose(steady.apply(v), expected, rtol=0, atol=1e-12 * np.abs(expected).max())
    order_ = rng.permutation(v.shape[1])  # the same in any order of the cells
    permuted = steady.apply(v[:, order_], steady.positions(order_))
    assert np.allclose(permuted, expected[:, order_], rtol=0, atol=1e-12 * np.abs(expected).max())
    unit = np.zeros_like(field)
    unit[0, contact.shape[0] // 2, contact.shape[1] // 2] = 1.0
    centre = upwind(operator.tangential(*unit)[0], operator.grid.dx, order)
    assert steady.diagonal == pytest.approx(centre[contact.shape[0] // 2, contact.shape[1] // 2])


def _stick_iterations(cells: int) -> tuple[int, int]:
    """GMRES applications of a stick-only steady system ``A q = c`` on a circle of ``cells``
    across, plain and right-preconditioned by the whole plane's inverse of ``A``."""
    from solver.surface.steady import gmres

    _, contact, steady = _circle(cells)
    n = int(contact.sum())

    def plain(v):
        return steady.apply(v.reshape(2, n)).ravel()

    def preconditioned(v):
        return plain(steady.inverse(v.reshape(2, n)).ravel())

    rhs = np.concatenate([np.ones(n), np.zeros(n)])
    products = gmres(plain, rhs, 1e-6, 60, 5000)[1]
    solution, fewer = gmres(preconditioned, rhs, 1e-6, 60, 5000)
    assert np.linalg.norm(preconditioned(solution) - rhs) < 1e-6 * np.linalg.norm(rhs)
    return products, fewer


def test_the_preconditioner_keeps_the_iterations_from_growing_with_the_mesh():
    (plain16, pre16), (plain32, pre32) = _stick_iterations(16), _stick_iterations(32)
    assert plain32 > 1.5 * plain16  # plain: they grow with the mesh
    assert pre32 < 1.4 * pre16 and pre32 < 0.25 * plain32, (plain16, pre16, plain32, pre32)


def test_gmres_solves_a_nonsymmetric_system_within_its_tolerance_and_budget():
    from solver.surface.steady import gmres

    rng = np.random.default_rng(5)
    n = 80
    matrix = np.eye(n) + 0.3 * rng.standard_normal((n, n)) / np.sqrt(n)
    matrix[np.triu_indices(n, 1)] *= 2.0  # not symmetric
    rhs = rng.standard_normal(n)
    x, products = gmres(lambda v: matrix @ v, rhs, 1e-10, 15, 1000)  # restarted
    assert np.linalg.norm(matrix @ x - rhs) <= 1e-10 * np.linalg.norm(rhs) * (1 + 1e-6)
    assert products < 200
    x, products = gmres(lambda v: matrix @ v, rhs, 1e-14, 10, 7)  # the budget caps it
    assert products == 7


def test_a_window_given_by_size_too_small_for_the_contact_names_grid_size():
    """A ``grid.size`` window that cannot hold the contact is told as such, with the size
    that would (the half_width it did not give is not blamed)."""
    from study.bench.rolling import steady_table

    table = steady_table(16, (1e-3, 0.0))
    soft = {**table, "body2": {"behaviour": "elastic", "E": 70e9, "nu": 0.33}}
    with pytest.raises(SpecError, match=r"grid\.size: the window .* cannot hold") as error:
        solver.Case.from_dict(soft)
    need = [float(v) for v in str(error.value).split("grid.size >= [")[1].split("]")[0].split(",")]
    semi = solver.Case.from_dict({**soft, "grid": {"n": 40}}).reference
    assert need == pytest.approx([2.2 * semi.semi_axis_x, 2.2 * semi.semi_axis_y], rel=1e-3)
    solver.Case.from_dict({**soft, "grid": {"n": 40, "size": need}})  # that window is accepted
