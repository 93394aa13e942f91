"""Axisymmetric profiles (cone, flat punch with rounded edges, power law) through the loops.

Expected values come from closed forms (Love's cone, Johnson 1985 §5.2; Hertz) or from Sneddon's
integrals taken here by adaptive quadrature (scipy), independently of :mod:`solver.theory.sneddon`.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import integrate, optimize

import solver
from solver import Case, SpecError
from solver.bodies.geometry import FlatPunch, Geometry, PowerLaw
from solver.theory.hertz import hertz

E_STEEL, NU_STEEL = 210e9, 0.3
ELASTIC = {"behaviour": "elastic", "E": E_STEEL, "nu": NU_STEEL}


def _table(profile: dict, force: float, n: int, **extra) -> dict:
    table = {
        "body1": {"behaviour": "rigid", "profile": profile},
        "body2": dict(ELASTIC),
        "load": {"normal_force": force},
        "grid": {"n": n, "half_width": 1.5},
    }
    table.update(extra)
    return table


def _measured(result) -> tuple[float, float]:
    """Contact radius (m, from the contact area) and approach (m) of the last step."""
    area = result.history["contact_area"][-1]
    return math.sqrt(area / math.pi), result.history["approach"][-1]


# -- Sneddon's integrals by scipy quadrature (the test's own) ----------------------------------
def _sneddon_quad(slope, a: float, e_star: float) -> tuple[float, float]:
    """(approach d, force P) of a contact of radius a; QUADPACK takes the (a - r)^(-1/2)."""
    weight = {"weight": "alg", "wvar": (0.0, -0.5), "limit": 200}
    d = a * integrate.quad(lambda r: slope(r) / math.sqrt(a + r), 0.0, a, **weight)[0]
    p = integrate.quad(lambda r: r * r * slope(r) / math.sqrt(a + r), 0.0, a, **weight)[0]
    return d, 2 * e_star * p


def _sneddon_for_force(slope, force: float, e_star: float, lo: float, hi: float):
    a = optimize.brentq(lambda x: _sneddon_quad(slope, x, e_star)[1] - force, lo, hi, xtol=1e-16)
    return a, _sneddon_quad(slope, a, e_star)[0]


# -- the solver's Sneddon module against closed forms ------------------------------------------
def test_sneddon_module_gives_hertz_and_love():
    e_star = 1.2e11
    sphere = Geometry((0.0, 0.0), (PowerLaw(1.0 / (2 * 0.01), 2.0),))  # R = 10 mm as a profile
    expected = hertz(100.0, e_star, (100.0, 100.0))
    got = sphere.reference(100.0, e_star)
    assert got.radius == pytest.approx(expected.radius, rel=1e-12)
    assert got.approach == pytest.approx(expected.approach, rel=1e-12)
    r = np.array([0.1, 0.5, 0.9]) * expected.radius
    assert np.allclose(got.pressure(r, 0 * r), expected.pressure(r, 0 * r), rtol=1e-9)

    angle = 12.0
    tan = math.tan(math.radians(angle))
    cone = Geometry((0.0, 0.0), (PowerLaw(tan, 1.0),))
    got = cone.reference(30.0, e_star)
    a = math.sqrt(2 * 30.0 / (math.pi * e_star * tan))  # P = (pi/2) E* a^2 tan(alpha)
    assert got.radius == pytest.approx(a, rel=1e-12)
    assert got.approach == pytest.approx(0.5 * math.pi * a * tan, rel=1e-12)
    r = np.array([0.05, 0.3, 0.7, 0.95]) * a
    expected_p = 0.5 * e_star * tan * np.arccosh(a / r)
    assert np.allclose(got.pressure(r, 0 * r), expected_p, rtol=2e-3)  # table interpolation


# -- the cone: Love's closed form ----------------------------------------------------------------
@pytest.fixture(scope="module")
def cone_errors():
    angle, force = 10.0, 50.0
    tan = math.tan(math.radians(angle))
    out = {}
    for n in (32, 128):
        case = Case.from_dict(_table({"shape": "cone", "angle": angle}, force, n))
        result = solver.solve(case)
        assert result.status == "converged"
        e_star = case.pair.composite_modulus
        a = math.sqrt(2 * force / (math.pi * e_star * tan))
        radius, approach = _measured(result)
        x, y = case.surface_grid.mesh()
        r = np.hypot(x, y)
        ring = (r >= 0.2 * a) & (r < a)
        exact = 0.5 * e_star * tan * np.arccosh(a / r[ring])
        mean = force / (math.pi * a * a)
        out[n] = {
            "radius": abs(radius / a - 1),
            "approach": abs(approach / (0.5 * math.pi * a * tan) - 1),
            "pressure": np.abs(result.pressure[ring] - exact).max() / mean,
        }
    return out


def test_cone_matches_love_at_128(cone_errors):
    errors = cone_errors[128]
    assert errors["radius"] < 0.01
    assert errors["approach"] < 0.01
    assert errors["pressure"] < 0.02  # of the mean pressure, for r >= 0.2 a


def test_cone_error_shrinks_with_the_mesh(cone_errors):
    for name in ("radius", "approach", "pressure"):
        assert cone_errors[128][name] < cone_errors[32][name], name


# -- flat punch with rounded edges and a power law: Sneddon's integrals ----------------------------
PUNCH = {"shape": "flat_punch", "radius": 1e-3, "edge_radius": 5e-3}
POWER = {"shape": "power", "coefficient": 1e10, "exponent": 4.0}


@pytest.mark.parametrize(
    ("profile", "shape", "radius_over_scale"),
    [(PUNCH, FlatPunch(1e-3, 5e-3), 1.3), (POWER, PowerLaw(1e10, 4.0), 1.0)],
    ids=["flat_punch", "power_k4"],
)
def test_profile_matches_sneddon_integrals(profile, shape, radius_over_scale):
    e_star = E_STEEL / (1 - NU_STEEL**2)
    target = radius_over_scale * (profile.get("radius") or 1e-4)
    force = _sneddon_quad(shape.slope, target, e_star)[1]
    a, d = _sneddon_for_force(shape.slope, force, e_star, 0.5 * target, 2 * target)
    case = Case.from_dict(_table(profile, force, 128))
    result = solver.solve(case)
    assert result.status == "converged"
    radius, approach = _measured(result)
    assert radius == pytest.approx(a, rel=0.01)
    assert approach == pytest.approx(d, rel=0.01)


def test_paraboloid_profile_is_the_sphere():
    radius = 0.01
    sphere = Case.from_dict(
        {
            "body1": {"behaviour": "rigid", "radius": radius},
            "body2": dict(ELASTIC),
            "load": {"normal_force": 20.0},
            "grid": {"n": 48, "half_width": 1.5},
        }
    )
    profile = Case.from_dict(
        _table({"shape": "power", "coefficient": 1 / (2 * radius), "exponent": 2.0}, 20.0, 48)
    )
    assert profile.reference.radius == pytest.approx(sphere.hertz.radius, rel=1e-12)
    a, b = solver.solve(sphere), solver.solve(profile)
    assert np.allclose(a.pressure, b.pressure, rtol=1e-8, atol=1e-8 * a.pressure.max())


# -- partial slip on a cone: Jaeger / Ciavarella superposition (beta = 0) -------------------------
def test_cone_partial_slip_stick_radius():
    """For identical bodies (beta = 0) q = mu [p(r; a) - p(r; c)] with P(c) = W - Q/mu, so the
    stick radius of a cone is c = a sqrt(1 - Q/(mu W)) (P grows as c^2)."""
    force, mu, ratio = 50.0, 0.4, 0.5
    table = _table({"shape": "cone", "angle": 8.0}, force, 128, friction={"coefficient": mu})
    table["body1"] = dict(ELASTIC, profile={"shape": "cone", "angle": 8.0})
    table["load"]["tangential_force"] = ratio * mu * force
    case = Case.from_dict(table)
    assert case.pair.dundurs_beta == 0.0
    result = solver.solve(case)
    assert result.status == "converged"
    a = case.reference.radius
    stick = math.sqrt(result.history["stick_area"][-1] / math.pi)
    dx = case.surface_grid.dx
    assert abs(stick - a * math.sqrt(1 - ratio)) < 1.5 * dx
    assert np.all(np.isfinite(result.shear_x))


# -- refusals --------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("edit", "field", "words"),
    [
        (lambda t: t["load"].update(hertz_pressure=1e9) or t["load"].pop("normal_force"),
         "load.hertz_pressure", "normal_force"),
        (lambda t: t["body1"]["profile"].update(angle=60.0), "body1.profile.angle", "45"),
        (lambda t: t["body1"]["profile"].update(shape="pyramid"), "body1.profile.shape", "cone"),
        (lambda t: t["body1"]["profile"].pop("angle"), "body1.profile", "angle"),
        (lambda t: t["body1"]["profile"].update(radius=1e-3), "body1.profile", "radius"),
        (lambda t: t["body1"].update(radius_x=0.01, radius_y=0.02), "body1.profile", "axisym"),
        (lambda t: t["body2"].update(radius_x=0.01, radius_y=0.02), "body2.radius_x", "axisym"),
        (lambda t: t["body1"].update(radius=1e-3) or t["load"].update(normal_force=1e9), "load",
         "slope"),
        (lambda t: t.update(body1={"behaviour": "elastic-plastic", "E": 210e9, "nu": 0.3,
                                   "hardening": {"law": "perfect", "yield_stress": 1e9},
                                   "profile": {"shape": "cone", "angle": 2.0}},
                            grid={"n": [32, 32, 32]}),
         "body1.behaviour", "only body 2"),
    ],
    ids=["hertz_pressure", "steep_cone", "unknown_shape", "missing_key", "foreign_key",
         "ellipsoid_plus_profile", "ellipsoid_partner", "slope_limit", "plastic_body1"],
)  # fmt: skip
def test_bad_profile_cases_are_refused(edit, field, words):
    table = _table({"shape": "cone", "angle": 10.0}, 50.0, 64)
    edit(table)
    with pytest.raises(SpecError) as error:
        Case.from_dict(table)
    assert field in str(error.value) and words in str(error.value)


def test_punch_load_past_the_rounded_edge_is_refused():
    e_star = E_STEEL / (1 - NU_STEEL**2)
    shape = FlatPunch(1e-3, 5e-3)
    edge = 1e-3 + 5e-3 / math.sqrt(2)  # slope 1 on the arc
    too_much = 1.01 * _sneddon_quad(shape.slope, edge, e_star)[1]
    with pytest.raises(SpecError, match="slope"):
        Case.from_dict(_table(PUNCH, too_much, 64))
    Case.from_dict(_table(PUNCH, 0.99 * too_much / 1.01, 128))


def test_profile_spec_round_trips_and_names_the_case():
    table = _table(PUNCH, 1e3, 64)
    case = Case.from_dict(table)
    again = Case.from_dict(case.to_dict())
    assert again == case and again.case_id == case.case_id
    other = Case.from_dict(_table(dict(PUNCH, edge_radius=4e-3), 1e3, 64))
    assert other.case_id != case.case_id


# -- a campaign over cone angles -------------------------------------------------------------------
CONE_CAMPAIGN = """
[campaign]
name = "cones"

[base]
body1 = { behaviour = "rigid", profile = { shape = "cone", angle = 10.0 } }
body2 = { behaviour = "elastic", radius = "inf", E = 210e9, nu = 0.3 }
load = { normal_force = 50.0, steps = 2 }
grid = { n = 48, half_width = 1.5 }

[sweep]
"body1.profile.angle" = [5.0, 10.0]

[alias]
"body1.profile.angle" = "angle"
"""


def test_campaign_sweeps_cone_angle_and_assembles_sneddon_references(tmp_path):
    from study.campaign import load_campaign
    from study.run.assemble import assemble
    from study.run.driver import run_campaign

    path = tmp_path / "cones.toml"
    path.write_text(CONE_CAMPAIGN)
    campaign = load_campaign(path)
    out = tmp_path / "out"
    assert run_campaign(campaign, out).exit_status == 0
    ds = assemble(out)
    assert ds.angle.attrs["units"] == "degree" and "cone angle" in ds.angle.attrs["long_name"]
    tan = np.tan(np.radians(ds.angle.values))
    e_star = E_STEEL / (1 - NU_STEEL**2)
    love = np.sqrt(2 * 50.0 / (math.pi * e_star * tan))
    np.testing.assert_allclose(ds.sneddon_radius.values, love, rtol=1e-10)
    assert np.all(np.abs(ds.contact_radius.values / love - 1) < 0.03)
    assert "hertz_radius" not in ds  # no Hertz reference is claimed for a cone


# -- elastic-plastic bodies under a profile: the box from the computed yield region -------------
LINEAR_STEEL = {
    "behaviour": "elastic-plastic", "E": E_STEEL, "nu": NU_STEEL,
    "hardening": {"law": "linear", "yield_stress": 1.0e9, "modulus": 10e9},
}  # fmt: skip


def test_plastic_paraboloid_sized_numerically_matches_the_sphere_sized_by_hertz():
    """The same physics twice: a sphere (box from Hertz's closed-form stress) and the equal
    paraboloid profile (box from the computed elastic stress) give the same box and answer."""
    radius = 0.015
    path = [{"hertz_pressure": 3.0e9, "steps": 4}, {"normal_force": 0.0, "steps": 1}]
    sphere = Case.from_dict({
        "body1": {"behaviour": "rigid", "radius": radius}, "body2": LINEAR_STEEL,
        "load": {"path": path}, "grid": {"n": [32, 32, 32], "half_width": 1.5},
    })  # fmt: skip
    path = [{"normal_force": sphere.max_normal_force, "steps": 4}, path[1]]
    power = {"shape": "power", "coefficient": 1 / (2 * radius), "exponent": 2.0}
    profile = Case.from_dict({
        "body1": {"behaviour": "rigid", "profile": power}, "body2": LINEAR_STEEL,
        "load": {"path": path}, "grid": {"n": [32, 32, 32], "half_width": 1.5},
    })  # fmt: skip
    assert profile.grid.depth == pytest.approx(sphere.grid.depth, rel=0.05)
    assert profile.grid.plastic_half_width == pytest.approx(sphere.grid.plastic_half_width, 0.05)
    a, b = solver.solve(sphere), solver.solve(profile)
    assert a.status == b.status == "converged"
    for name in ("max_plastic_strain", "residual_depth"):
        assert b.history[name][-1] == pytest.approx(a.history[name][-1], rel=0.01), name


def test_plastic_cone_yields_at_the_tip_and_the_box_holds_the_zone():
    table = _table({"shape": "cone", "angle": 2.0}, 5.0, 32)
    table.update(body2=LINEAR_STEEL, grid={"n": [32, 32, 32], "half_width": 2.0})
    table["load"] = {"path": [{"normal_force": 5.0, "steps": 4}, {"normal_force": 0.0}]}
    case = Case.from_dict(table)
    from solver.case.sizing import elastic_yield_region

    a = case.reference.radius
    region = elastic_yield_region(
        case.pair, case.domain_half_widths, (32, 32), 5.0, 0.0, 1.0e9, NU_STEEL, a
    )
    assert region.top == 0.0 and region.bottom > 0  # the singular tip yields at the surface
    result = solver.solve(case)
    assert result.status == "converged", result.notes  # converged, not truncated
    assert result.history["residual_depth"][-1] > 0
