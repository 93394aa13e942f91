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
from solver.theory.friction import capped_sliding_force

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
    a, b = solver.solve(plain), solver.solve(capped)
    assert a.status == b.status == "converged"
    assert np.abs(b.shear_x - a.shear_x).max() <= 1e-9 * np.abs(a.shear_x).max()
    assert (a.contact_state == b.contact_state).all()


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
