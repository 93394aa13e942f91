"""An elastic-plastic body 1 in rolling (issue 24, item 2): solved with the bodies relabelled.

Under a rolling contact the surface material of both bodies stands still in body 2's frame
(Kalker's transient theory), so the bodies may change roles: the travel, the creepages and the
spin told in body 1's frame (x, -y, -z) are ``(dx, -dy)``, ``(-xi, eta)`` and the same spin
(:meth:`solver.Case.swapped`).  Checks: that rule on elastic pairs of different materials
(beta != 0), which are solved as given, not relabelled; a frictionless roll of a plastic ball
over a rigid flat leaves the plastic strain, rut and Melan factor of a rigid ball sliding
over the plastic flat; a plastic ball under creepage is told on the common axes (forces,
tractions, fields and per-pass profiles of the plastic flat it mirrors).  Two elastic-plastic
bodies roll with a plastic strain field each (not relabelled): a flat that never yields leaves
the plastic ball's answer, and two bodies of the same steel rolling frictionless carry mirror
images of each other's plastic strain.
"""

from __future__ import annotations

import numpy as np
import pytest

import solver
from solver import Case

STEEL = {"behaviour": "elastic", "E": 210e9, "nu": 0.3}
ALUMINIUM = {"behaviour": "elastic", "E": 70e9, "nu": 0.33}
PLASTIC = {
    "behaviour": "elastic-plastic", "E": 210e9, "nu": 0.3,
    "hardening": {"law": "linear", "yield_stress": 433e6, "modulus": 20e9},
}  # fmt: skip
RADIUS = 0.01  # m, body 1's: the pair's curvature moves with the contact
P0 = 5 * 250e6  # Pa: five times the shear yield stress of PLASTIC


def _ball(body: dict) -> dict:
    return {**body, "radius": RADIUS}


def _case(body1, body2, path, n, mu=0.3) -> Case:
    return Case.from_dict(
        {
            "body1": body1, "body2": body2, "friction": {"coefficient": mu},
            "load": {"path": path}, "grid": {"n": list(n), "half_width": 1.3},
        }
    )  # fmt: skip


def _contact_radius() -> float:
    probe = {"behaviour": "rigid", "radius": RADIUS}
    return _case(probe, PLASTIC, [{"hertz_pressure": P0}], (16, 16, 16), 0.0).hertz.radius


@pytest.mark.validation
@pytest.mark.parametrize("travel", [(1.0, 0.0), (0.75, 0.5)])
def test_swapping_the_bodies_of_a_rolling_pair_is_the_same_contact(travel, validation):
    """Steel ball on aluminium against aluminium ball on steel: the swap rule, solved twice."""
    a = 0.6e-3  # m, about the contact radius at 1000 N
    roll = [travel[0] * a, travel[1] * a]

    def rolled(body1, body2, sign):
        stage = {
            "roll": [roll[0], sign * roll[1]],
            "creepage": [sign * 1e-3, 5e-4],
            "spin": 2.0,
            "steps": 12,
        }
        return solver.solve(_case(body1, body2, [{"normal_force": 1000.0}, stage], (48, 32)))

    given, swapped = rolled(_ball(STEEL), ALUMINIUM, 1.0), rolled(_ball(ALUMINIUM), STEEL, -1.0)
    assert given.status == swapped.status == "converged"
    h, g = given.history, swapped.history
    assert abs(h["tangential_force_x"][-1]) > 1.0 and abs(h["tangential_force_y"][-1]) > 1.0
    tolerance = given.case.solver.slip_tolerance
    worst = 0.0
    for name, sign in (("tangential_force_x", -1), ("tangential_force_y", 1), ("position_y", -1)):
        scale = np.abs(h[name]).max()
        assert np.allclose(h[name], sign * g[name], rtol=0, atol=10 * tolerance * scale), name
        if name != "position_y":
            worst = max(worst, float(np.abs(h[name] - sign * g[name]).max() / scale))
    validation(
        "steel ball rolling on aluminium (beta != 0) with xi, eta and spin, along x and "
        "diagonally, against aluminium ball on steel, each solved as given",
        "the same contact told in body 1's frame: travel (dx, -dy), creepage (-xi, eta), the "
        "same spin (the rule that relabels an elastic-plastic body 1)",
        worst,
    )
    if travel[1] == 0.0:  # the same cells: the tractions mirror in y
        pm = given.pressure.max()
        assert np.allclose(given.pressure, swapped.pressure[:, ::-1], rtol=0, atol=1e-6 * pm)
        assert np.allclose(given.shear_x, -swapped.shear_x[:, ::-1], rtol=0, atol=1e-5 * pm)
        assert np.allclose(given.shear_y, swapped.shear_y[:, ::-1], rtol=0, atol=1e-5 * pm)
        # the rule is not a tautology: the other signs of eta and of the spin miss it
        for creepage, spin in (([-1e-3, -5e-4], 2.0), ([-1e-3, 5e-4], -2.0)):
            stage = {"roll": roll, "creepage": creepage, "spin": spin, "steps": 12}
            other = solver.solve(
                _case(_ball(ALUMINIUM), STEEL, [{"normal_force": 1000.0}, stage], (48, 32))
            )
            assert np.abs(given.shear_y - other.shear_y[:, ::-1]).max() > 1e-2 * pm


def test_a_plastic_ball_rolling_frictionless_is_a_rigid_ball_sliding_on_a_plastic_flat():
    """A moving normal load: the plastic ball's strain is the plastic flat's, mirrored in y."""
    a = _contact_radius()
    press = {"hertz_pressure": P0, "steps": 2}
    rolled = _case(
        _ball(PLASTIC), {"behaviour": "rigid"}, [press, {"roll": [3 * a, 0.0], "steps": 12}],
        (40, 16, 24), 0.0,
    )  # fmt: skip
    slid = _case(
        {"behaviour": "rigid", "radius": RADIUS}, PLASTIC,
        [press, {"slide": [3 * a, 0.0], "steps": 12}], (40, 16, 24), 0.0,
    )  # fmt: skip
    ball, flat = solver.solve(rolled), solver.solve(slid)
    assert ball.status == flat.status == "converged"
    assert any("relabelled" in note for note in ball.notes)
    peak = flat.fields["plastic_strain"].max()
    assert peak > 1e-3  # past yield along the whole track
    tolerance = 10 * slid.solver.plastic_tolerance * slid.body2.hardening.initial_yield_stress
    tolerance /= slid.body2.E
    assert np.allclose(
        ball.fields["plastic_strain"], flat.fields["plastic_strain"][:, ::-1], rtol=0,
        atol=tolerance,
    )  # fmt: skip
    rut = ball.history["residual_depth"][-1]
    assert rut > 0 and abs(rut - flat.history["residual_depth"][-1]) <= 1e-6 * rut
    assert ball.melan_factor is not None
    assert abs(ball.melan_factor - flat.melan_factor) <= 1e-6 * flat.melan_factor


def test_a_plastic_ball_under_creepage_is_told_on_the_common_axes():
    """Two passes of a plastic ball rolling with creepage on steel, told as the plastic flat
    rolled at the opposite creepage, mirrored: forces, tractions, fields, per-pass profiles."""
    a = _contact_radius()
    xi = 5e-3

    def path(sign):
        passes = {"cycles": 2, "stages": [
            {"roll": [2 * a, 0.0], "creepage": [sign * xi, 0.0], "steps": 8},
            {"hertz_pressure": 0.0}, {"roll": [-2 * a, 0.0]}, {"hertz_pressure": P0},
        ]}  # fmt: skip
        return [{"hertz_pressure": P0, "steps": 2}, passes]

    ball = solver.solve(_case(_ball(PLASTIC), STEEL, path(1.0), (32, 16, 24)))
    flat = solver.solve(_case(_ball(STEEL), PLASTIC, path(-1.0), (32, 16, 24)))
    assert ball.status == flat.status
    h, g = ball.history, flat.history
    # a creep force on body 2, a tenth of full slip's
    assert np.abs(h["tangential_force_x"]).max() > 0.1 * 0.3 * h["normal_force"].max()
    assert np.array_equal(h["tangential_force_x"], -g["tangential_force_x"])
    assert np.array_equal(h["max_plastic_strain"], g["max_plastic_strain"])
    assert np.array_equal(ball.pressure, flat.pressure[:, ::-1])
    assert np.array_equal(ball.shear_x, -flat.shear_x[:, ::-1])
    assert np.array_equal(ball.fields["plastic_strain"], flat.fields["plastic_strain"][:, ::-1])
    assert np.array_equal(
        ball.fields["cycle_rut_profile"], flat.fields["cycle_rut_profile"][:, ::-1]
    )
    assert np.array_equal(
        ball.fields["cycle_residual_stress_xx"], flat.fields["cycle_residual_stress_xx"]
    )
    per_pass = ball.to_xarray()["creep_force_x"].values
    assert np.array_equal(per_pass, -flat.to_xarray()["creep_force_x"].values)
    assert ball.melan_factor is None  # a rolling contact's shear is not Hamilton's mu p


def _linear(yield_stress: float) -> dict:
    return {**PLASTIC, "hardening": {"law": "linear", "yield_stress": yield_stress,
                                     "modulus": 20e9}}  # fmt: skip


def _two_bodies(body2: dict, mu: float, depth: float | None = None) -> Case:
    """A plastic ball rolling 2 a on ``body2``, both volumes ``depth`` deep (a_H; default:
    sized from the yield region)."""
    a = _contact_radius()
    stage = {"roll": [2 * a, 0.0], "steps": 8, **({"creepage": [5e-3, 0.0]} if mu else {})}
    grid = {"n": [32, 16, 24], "follow_contact": False}
    if depth is not None:
        grid["depth"] = depth
        if body2["behaviour"] == "elastic-plastic":
            grid["depth_body1"] = depth
    return Case.from_dict(
        {
            "body1": _ball(_linear(433e6)), "body2": body2, "friction": {"coefficient": mu},
            "load": {"path": [{"hertz_pressure": P0, "steps": 2}, stage]}, "grid": grid,
        }
    )  # fmt: skip


@pytest.mark.validation
def test_two_plastic_bodies_roll_with_a_field_each(validation):
    """Not relabelled: body 1's plastic strain on its own volume grid, in body 2's frame."""
    depth = _two_bodies(STEEL, 0.3).swapped().grid.depth  # the relabelled case's volume
    alone = solver.solve(_two_bodies(STEEL, 0.3, depth))  # relabelled
    hard = _two_bodies(_linear(20e9), 0.3, depth)  # a flat that never yields
    assert hard.plastic_bodies == (2, 1)
    both = solver.solve(hard)
    assert alone.status == both.status == "converged"
    assert both.fields["plastic_strain"].max() == 0.0
    peak = alone.fields["plastic_strain"].max()
    assert peak > 1e-3
    assert np.allclose(
        both.fields["plastic_strain_body1"], alone.fields["plastic_strain"], rtol=0,
        atol=1e-6 * peak,
    )  # fmt: skip
    assert np.allclose(
        both.history["tangential_force_x"], alone.history["tangential_force_x"], rtol=1e-6
    )
    same = solver.solve(_two_bodies(_linear(433.000001e6), 0.0, depth))  # frictionless
    upper, lower = same.fields["plastic_strain_body1"], same.fields["plastic_strain"]
    assert lower.max() > 1e-3
    assert np.allclose(upper, lower[:, ::-1], rtol=0, atol=1e-6 * lower.max())
    relabelled = np.abs(both.fields["plastic_strain_body1"] - alone.fields["plastic_strain"])
    mirrored = np.abs(upper - lower[:, ::-1]).max() / lower.max()
    validation(
        "an elastic-plastic ball rolling with creepage over a flat that never yields (two "
        "plastic fields, 32 x 16 x 24); two balls of one steel rolling frictionless",
        "the plastic ball alone, solved with the bodies relabelled; each body's strain the "
        "other's mirrored in y",
        f"e_p within {relabelled.max() / peak:.1e} of the peak; mirrored within {mirrored:.1e}",
    )


def test_a_relabelled_diagonal_roll_keeps_the_cases_positions():
    """Solved in body 1's frame (dy -> -dy), told back: position_y is the case's own."""
    a = _contact_radius()
    case = _case(
        _ball(PLASTIC), {"behaviour": "rigid"},
        [{"hertz_pressure": P0, "steps": 2}, {"roll": [1.5 * a, 1.0 * a], "steps": 4}],
        (24, 20, 24), 0.0,
    )  # fmt: skip
    result = solver.solve(case)
    assert case.plastic_body1 and result.status in ("converged", "truncated")
    assert result.history["position_x"][-1] == pytest.approx(1.5 * a, rel=1e-12)
    assert result.history["position_y"][-1] == pytest.approx(1.0 * a, rel=1e-12)
