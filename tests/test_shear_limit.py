"""Friction capped by a shear limit (issue 58): Orowan's law |q| <= min(mu p, m tau_c).

Checks: a sphere sliding in gross slip over an incompressible half-space (beta = 0, the
pressure stays Hertz's) carries the closed-form capped force, the error shrinking with the mesh;
a limit above mu p_0 changes nothing (Coulomb's and Cattaneo-Mindlin's answers); a force above
what the capped disks carry ends the path, told; a plastic surface asked for more shear than
it can carry ends promptly as ``surface_flow``, and the same scene with
``shear_limit = "yield"`` converges with the shear at most the top layer's yield stress; bad
input is refused by the field that is wrong.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

import solver
from solver import Case, SpecError
from solver.theory.friction import (
    capped_partial_slip,
    capped_sliding_force,
    cattaneo_stick_ratio,
)

SPHERE = {"behaviour": "rigid", "radius": 0.01}
RUBBERY = {"behaviour": "elastic", "E": 10e6, "nu": 0.5}  # incompressible: Dundurs beta = 0
STEEL = {"behaviour": "elastic", "E": 210e9, "nu": 0.3}
#: Elastic-perfectly plastic steel, k = 250 MPa.
EPP_STEEL = {
    "behaviour": "elastic-plastic", "radius": "inf", "E": 210e9, "nu": 0.3,
    "hardening": {"law": "perfect", "yield_stress": 250e6 * math.sqrt(3.0)},
}  # fmt: skip
SHEAR_YIELD = 250e6


def _table(body2: dict, path: list[dict], friction: dict, n) -> dict:
    return {
        "body1": dict(SPHERE), "body2": dict(body2), "friction": dict(friction),
        "load": {"path": path}, "grid": {"n": n},
    }  # fmt: skip


def _sliding(n: int, mu: float, cap_ratio: float) -> tuple[solver.Result, float]:
    """A rigid sphere sliding two radii over rubber, the cap ``cap_ratio mu p_0``."""
    probe = Case.from_dict(_table(RUBBERY, [{"normal_force": 0.01}], {"coefficient": mu}, n))
    hertz = probe.reference
    path = [{"normal_force": 0.01}, {"slide": [2.0 * hertz.radius, 0.0], "steps": 4}]
    cap = cap_ratio * mu * hertz.max_pressure
    friction = {"coefficient": mu, "shear_limit": cap}
    result = solver.solve(Case.from_dict(_table(RUBBERY, path, friction, n)))
    expected = capped_sliding_force(mu, hertz.max_pressure, hertz.radius, cap)
    return result, expected


@pytest.mark.validation
def test_sliding_sphere_carries_orowans_closed_form_force(validation):
    """Q = tau_c pi r_c^2 + mu (2 pi a^2 p_0 / 3)(1 - r_c^2/a^2)^(3/2), within 1 % at 64^2."""
    errors = {}
    for n in (32, 64):
        result, expected = _sliding(n, 0.6, 0.5)
        assert result.status == "converged", result.notes
        force = float(np.hypot(result.history["tangential_force_x"][-1],
                               result.history["tangential_force_y"][-1]))  # fmt: skip
        errors[n] = abs(force / expected - 1.0)
        # the cap binds: the largest traction is tau_c, well below mu p_0
        shear = np.hypot(result.shear_x, result.shear_y)
        assert shear.max() <= 0.5 * 0.6 * result.case.reference.max_pressure * (1 + 1e-12)
    assert errors[64] < 0.01
    assert errors[64] < errors[32]
    validation(
        "Orowan's capped friction: a sphere sliding over an incompressible half-space, "
        "tau_c = mu p_0 / 2",
        "Q = tau_c pi r_c^2 + mu (2 pi a^2 p_0/3)(1 - r_c^2/a^2)^(3/2)",
        f"{100 * errors[64]:.2f} % at 64^2 ({100 * errors[32]:.2f} % at 32^2)",
    )


def test_a_limit_above_mu_p0_is_coulombs_law():
    """Sliding: the force is mu P; partial slip: the tractions are Cattaneo-Mindlin's, unchanged."""
    result, expected = _sliding(32, 0.3, 1.5)
    probe = result.case.reference
    load = result.history["normal_force"][-1]
    force = result.history["tangential_force_x"][-1]
    assert math.isclose(expected, 0.3 * 2 * math.pi * probe.radius**2 * probe.max_pressure / 3)
    assert force == pytest.approx(0.3 * load, rel=1e-12)
    path = [{"normal_force": 100.0}, {"tangential_force": [20.0, 0.0], "steps": 4}]
    plain = Case.from_dict(_table(STEEL, path, {"coefficient": 0.3}, 32))
    p0 = plain.reference.max_pressure
    capped = Case.from_dict(
        _table(STEEL, path, {"coefficient": 0.3, "shear_limit": 1.5 * 0.3 * p0}, 32)
    )
    assert any("the limit caps nothing unless" in w for w in capped.warnings)  # told
    a, b = solver.solve(plain), solver.solve(capped)
    assert a.status == b.status == "converged"
    assert np.abs(b.shear_x - a.shear_x).max() <= 1e-9 * np.abs(a.shear_x).max()
    assert (a.contact_state == b.contact_state).all()


def test_the_capped_partial_slip_reference_is_cattaneo_mindlin_without_a_binding_cap():
    """The MDR derivation checked on its own: no binding cap gives Cattaneo-Mindlin exactly;
    a binding one carries the force it was asked for, with |q| <= tau_c."""
    mu, p0, a = 0.5, 1e9, 1e-4
    load = 2 * math.pi * a * a * p0 / 3
    c, traction = capped_partial_slip(mu, p0, a, 2 * mu * p0, 0.6 * mu * load)
    assert c / a == pytest.approx(cattaneo_stick_ratio(0.6 * mu * load, mu, load), rel=1e-10)
    r = np.linspace(0.0, a, 41)
    cattaneo = mu * p0 / a * (np.sqrt(a * a - r * r) - np.sqrt(np.clip(c * c - r * r, 0, None)))
    assert np.abs(traction(r) - cattaneo).max() <= 1e-9 * mu * p0
    tau = 0.5 * mu * p0
    force = 0.6 * capped_sliding_force(mu, p0, a, tau)
    c, traction = capped_partial_slip(mu, p0, a, tau, force)
    r = np.linspace(0.0, a, 4001)
    q = traction(r)
    assert q.max() <= tau * (1 + 1e-12)
    assert np.trapezoid(2 * math.pi * r * q, r) == pytest.approx(force, rel=1e-4)
    assert c < a * math.sqrt(1 - 0.5**2)  # the stick zone inside the capped disk here


@pytest.mark.validation
def test_partial_slip_under_a_reached_limit_against_the_axisymmetric_solution(validation):
    """Rigid sphere on an incompressible half-space, tau_c = mu p_0 / 2, Q = 0.6 of capacity."""
    mu, found = 0.5, {}
    for n in (32, 64):
        table = _table(RUBBERY, [{"normal_force": 0.01}], {"coefficient": mu}, n)
        hertz = Case.from_dict(table).reference
        p0, a = hertz.max_pressure, hertz.radius
        tau = 0.5 * mu * p0
        force = 0.6 * capped_sliding_force(mu, p0, a, tau)
        table["friction"]["shear_limit"] = tau
        table["load"]["path"].append({"tangential_force": [force, 0.0], "steps": 8})
        result = solver.solve(Case.from_dict(table))
        assert result.status == "converged", result.notes
        c, traction = capped_partial_slip(mu, p0, a, tau, force)
        radii = np.linspace(0.0, a, 401)
        x, y = result.grid.mesh()
        r = np.hypot(x, y)
        expected = np.interp(r, radii, traction(radii), right=0.0)
        contact = result.pressure > 0
        rms = np.sqrt(np.mean((result.shear_x - expected)[contact] ** 2)) / (mu * p0)
        stick = math.sqrt(result.history["stick_area"][-1] / math.pi)
        found[n] = (abs(stick / c - 1), rms, c / a)
    assert found[64][0] < found[32][0] and found[64][0] < 0.02
    assert found[64][1] < found[32][1] and found[64][1] < 0.01
    validation(
        "partial slip under a reached shear limit: rigid sphere on an incompressible "
        "half-space, tau_c = mu p_0 / 2, Q = 0.6 of the capped capacity",
        "axisymmetric solution by the method of dimensionality reduction "
        "(solver.theory.friction.capped_partial_slip, Cattaneo-Mindlin's approximation)",
        f"stick radius {100 * found[32][0]:.2f} % / {100 * found[64][0]:.2f} %, rms traction "
        f"{100 * found[32][1]:.2f} % / {100 * found[64][1]:.2f} % of mu p_0 at 32^2 / 64^2 "
        f"(c/a = {found[64][2]:.4f})",
    )


def test_a_force_above_the_capped_capacity_ends_the_path_told():
    """Q between the capacity under the cap and mu W is gross sliding: the path ends there."""
    probe = Case.from_dict(_table(STEEL, [{"normal_force": 100.0}], {"coefficient": 0.5}, 32))
    hertz = probe.reference
    cap = 0.4 * 0.5 * hertz.max_pressure
    capacity = capped_sliding_force(0.5, hertz.max_pressure, hertz.radius, cap)
    assert capacity < 0.5 * 100.0
    path = [
        {"normal_force": 100.0},
        {"tangential_force": [0.5 * capacity, 0.0], "steps": 2},
        {"tangential_force": [0.5 * (capacity + 50.0), 0.0], "steps": 2},  # past it
        {"tangential_force": [0.5 * capacity, 0.0], "steps": 2},  # not reached
    ]
    case = Case.from_dict(_table(STEEL, path, {"coefficient": 0.5, "shear_limit": cap}, 32))
    result = solver.solve(case)
    assert result.status == "not_converged"
    steps = len(result.history["normal_force"])
    assert steps < case.total_steps  # ended, not run on
    assert result.history["step_converged"][: steps - 1].all()
    assert any(f"step {steps}: the tangential force is at or above" in n for n in result.notes)
    assert np.isfinite(result.shear_x).all()


def _fretting(mu: float, friction: dict | None = None, n: int = 16, ratio: float = 0.9):
    """A rigid sphere pressed to p_0 = 4 k on EPP steel, then a tangential force."""
    e_star = 210e9 / (1 - 0.3**2)
    p0 = 4 * SHEAR_YIELD
    a = math.pi * p0 * 0.01 / (2 * e_star)
    force = 2 / 3 * math.pi * a * a * p0
    friction = {"coefficient": mu, **(friction or {})}
    if "shear_limit" in friction:
        q = ratio * capped_sliding_force(mu, p0, a, SHEAR_YIELD)
    else:
        q = ratio * mu * force
    path = [{"hertz_pressure": p0, "steps": 3}, {"tangential_force": [q, 0.0], "steps": 6}]
    return solver.solve(Case.from_dict(_table(EPP_STEEL, path, friction, [n, n, n])))


def test_surface_flow_ends_promptly_and_the_yield_limit_converges():
    """mu = 1 at p_0 = 4 k asks the perfectly plastic surface for more than k."""
    below = _fretting(0.2)
    assert below.status == "converged", below.notes
    assert below.history["surface_shear_ratio"].max() <= 1.0
    assert not any("surface shear traction reaches" in n for n in below.notes)

    flowing = _fretting(1.0)
    assert flowing.status == "surface_flow", flowing.notes
    steps = len(flowing.history["normal_force"])
    assert steps < flowing.case.total_steps  # ended at the flow, not run on
    assert flowing.history["surface_shear_ratio"][-1] > 1.0
    assert flowing.history["step_converged"][: steps - 1].all()  # the increments kept
    assert any(n.startswith(f"step {steps}: the surface shear traction reaches")
               for n in flowing.notes)  # fmt: skip
    # the plasticity loop did not run to its cap with halvings at the flow increment
    assert flowing.history["plastic_iterations"][-1] <= flowing.case.solver.plastic_max_iterations

    capped = _fretting(1.0, {"shear_limit": "yield"})
    assert capped.status == "converged", capped.notes
    assert len(capped.history["normal_force"]) == capped.case.total_steps
    assert capped.history["surface_shear_ratio"].max() <= 1.0 + 1e-9
    assert capped.history["max_plastic_strain"].max() < 0.02  # bounded, small strain
    for field in (capped.pressure, capped.shear_x, capped.fields["plastic_strain"]):
        assert np.isfinite(field).all()


@pytest.mark.parametrize(
    ("friction", "body2", "field", "words"),
    [
        ({"coefficient": 0.3, "shear_limit": 0.0}, EPP_STEEL, "friction.shear_limit", "stress"),
        ({"coefficient": 0.3, "shear_limit": -1e8}, EPP_STEEL, "friction.shear_limit", "stress"),
        ({"coefficient": 0.3, "shear_limit": math.nan}, EPP_STEEL, "friction.shear_limit", ""),
        ({"coefficient": 0.3, "shear_limit": "k"}, EPP_STEEL, "friction.shear_limit", "yield"),
        ({"coefficient": 0.3, "shear_limit": "yield"}, STEEL, "friction.shear_limit",
         "elastic-plastic"),
        ({"coefficient": 0.3, "shear_limit": 1e8, "shear_factor": 0.0}, STEEL,
         "friction.shear_factor", "(0, 1]"),
        ({"coefficient": 0.3, "shear_limit": 1e8, "shear_factor": 1.5}, STEEL,
         "friction.shear_factor", "(0, 1]"),
        ({"coefficient": 0.3, "shear_factor": 0.5}, STEEL, "friction.shear_factor", "not given"),
    ],
)  # fmt: skip
def test_bad_shear_limits_are_refused_by_their_field(friction, body2, field, words):
    body2 = dict(body2, radius="inf")
    n = [16, 16, 16] if body2["behaviour"] == "elastic-plastic" else 32
    table = _table(body2, [{"normal_force": 100.0}], friction, n)
    with pytest.raises(SpecError, match="^" + re.escape(field)) as error:
        Case.from_dict(table)
    assert words in str(error.value)
    assert "\n" not in str(error.value)


def test_a_limit_without_friction_is_noted_and_changes_nothing():
    table = _table(STEEL, [{"normal_force": 100.0}], {"shear_limit": 1e8}, 32)
    case = Case.from_dict(table)
    assert any("has no effect" in w for w in case.warnings)
    plain = Case.from_dict(_table(STEEL, [{"normal_force": 100.0}], {}, 32))
    assert np.array_equal(solver.solve(case).pressure, solver.solve(plain).pressure)


def test_a_case_without_a_limit_keeps_its_id():
    """The limit's keys enter the case table only when given (older ids stay)."""
    case = Case.from_dict(_table(STEEL, [{"normal_force": 100.0}], {"coefficient": 0.3}, 32))
    assert case.spec["friction"] == {"coefficient": 0.3}


def test_surface_flow_of_a_plastic_body_1_is_told_with_the_bodies_relabelled():
    """The relabelled solve (body 1 elastic-plastic) keeps the status and where the path ended."""
    e_star = 210e9 / (1 - 0.3**2)
    p0 = 4 * SHEAR_YIELD
    a = math.pi * p0 * 0.01 / (2 * e_star)
    force = 2 / 3 * math.pi * a * a * p0
    path = [{"hertz_pressure": p0, "steps": 3},
            {"tangential_force": [0.9 * 1.0 * force, 0.0], "steps": 6}]  # fmt: skip
    table = {
        "body1": dict(EPP_STEEL, radius=0.01), "body2": {"behaviour": "rigid", "radius": "inf"},
        "friction": {"coefficient": 1.0}, "load": {"path": path}, "grid": {"n": [16, 16, 16]},
    }  # fmt: skip
    result = solver.solve(Case.from_dict(table))
    assert result.status == "surface_flow", result.notes
    assert len(result.history["normal_force"]) < result.case.total_steps


def test_the_limit_holds_on_a_periodic_rough_interface():
    """One period of a rough elastic-perfectly plastic surface sheared at mu = 0.8: Coulomb's
    law alone asks its spots for more than k and ends at that increment; under the limit the
    shear stops at k and the path converges."""
    k = 1e9 / math.sqrt(3.0)
    body2 = {
        "behaviour": "elastic-plastic", "radius": "inf", "E": 210e9, "nu": 0.3,
        "hardening": {"law": "perfect", "yield_stress": 1e9},
        "roughness": {"hurst": 0.8, "long_cutoff": 5e-5, "short_cutoff": 2.5e-5, "rms": 5e-8,
                      "seed": 1},
    }  # fmt: skip
    path = [{"normal_force": 2.0, "steps": 3},
            {"normal_force": 2.0, "tangential_force": [0.8, 0.0], "steps": 4}]  # fmt: skip
    results = {}
    for limit in ("none", "yield"):
        table = {
            "body1": {"behaviour": "rigid", "radius": "inf"}, "body2": body2,
            "friction": {"coefficient": 0.8, "shear_limit": limit}, "load": {"path": path},
            "grid": {"n": [32, 32, 16], "size": 1e-4, "depth": 1.25e-5, "periodic": True},
        }  # fmt: skip
        results[limit] = solver.solve(Case.from_dict(table))
    plain, capped = results["none"], results["yield"]
    assert plain.status == "surface_flow", plain.notes
    assert len(plain.history["normal_force"]) < plain.case.total_steps
    assert capped.status == "converged", capped.notes
    assert np.hypot(capped.shear_x, capped.shear_y).max() <= k * (1 + 1e-9)
    assert capped.history["tangential_force_x"][-1] == pytest.approx(0.8, rel=1e-9)
