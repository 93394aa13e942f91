"""The window that follows a moving contact (solver.drive.window) against the whole track.

Every increment of a sliding or rolling case is solved on a window of the track's cells placed
at the contact; ``grid.follow_contact = false`` solves it on the whole track.  Elastic: the
same answer to the solvers' tolerances (the convolutions are exact for tractions inside the
window).  Elastic-plastic: the same within the window's truncation of the increment's
Boussinesq correction.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import solver
from solver.case.case import Case
from solver.case.reading import SpecError
from solver.drive.operators import CaseOperators
from solver.drive.plastic_loop import PlasticState
from solver.drive.window import Follower
from solver.variables import PLASTIC_ZONE_THRESHOLD

YIELD = 433.0127e6  # Pa: k = 250 MPa
RIGID = {"behaviour": "rigid", "radius": 0.01}
STEEL = {"behaviour": "elastic", "radius": "inf", "E": 210e9, "nu": 0.3}
PLASTIC = {
    **STEEL, "behaviour": "elastic-plastic", "hardening": {"law": "perfect", "yield_stress": YIELD},
}  # fmt: skip


def _pair(table: dict) -> dict[bool, Case]:
    out = {}
    for follow in (True, False):
        grid = {**table["grid"], "follow_contact": follow}
        out[follow] = Case.from_dict({**table, "grid": grid})
    return out


def _radius(table: dict) -> float:
    probe = {**table, "load": {"hertz_pressure": table["load"]["path"][0]["hertz_pressure"]}}
    return Case.from_dict({**probe, "grid": {"n": [16, 16, 16]}}).hertz.radius


def test_elastic_rolling_on_the_window_is_the_whole_tracks():
    """A ball rolling 3 a with creepage on steel (beta != 0): forces and tractions agree."""
    ball = {"behaviour": "elastic", "radius": 0.01, "E": 70e9, "nu": 0.33}
    table = {
        "body1": ball, "body2": STEEL, "friction": {"coefficient": 0.3},
        "load": {"path": [{"hertz_pressure": 1e9}]}, "grid": {"n": [72, 24]},
    }  # fmt: skip
    a = _radius(table)
    table["load"]["path"].append({"roll": [3 * a, 0.0], "creepage": [1e-3, 0.0], "steps": 24})
    cases = _pair(table)
    follows, track = cases[True], cases[False]
    assert follows.moving_window is not None and follows.moving_window[0] < 72
    assert track.moving_window is None and follows.case_id != track.case_id
    a_result, b_result = solver.solve(follows), solver.solve(track)
    assert a_result.status == b_result.status == "converged"
    tolerance = follows.solver.slip_tolerance * b_result.pressure.max()
    for name in ("pressure", "shear_x", "shear_y"):
        assert np.allclose(getattr(a_result, name), getattr(b_result, name), atol=tolerance, rtol=0)
    force = b_result.history["tangential_force_x"]
    assert abs(force[-1]) > 0.1 * 0.3 * b_result.history["normal_force"][-1]
    difference = np.abs(a_result.history["tangential_force_x"] - force).max()
    assert difference <= 1e-5 * np.abs(force).max()  # 6e-7 seen


def test_plastic_pass_on_the_window_is_the_whole_tracks():
    """Frictionless pass below the shakedown limit (p_0 = 4.5 k): the plastic strain, the rut
    and the pressure of the window's solve within 1e-3 of the whole track's maxima."""
    table = {
        "body1": RIGID, "body2": PLASTIC, "friction": {"coefficient": 0.0},
        "solver": {"plastic_tolerance": 1e-6},
        "load": {"path": [{"hertz_pressure": 4.5 * YIELD / math.sqrt(3.0), "steps": 2}]},
    }  # fmt: skip
    a = _radius({**table, "grid": {}})
    cell = a / 5.0
    table["load"]["path"].append({"slide": [4 * a, 0.0], "steps": 16})
    table["grid"] = {"n": [math.ceil(7 * a / cell), math.ceil(3 * a / cell), 12]}
    cases = _pair(table)
    assert cases[True].moving_window[0] < cases[True].grid.nx
    follows, track = (solver.solve(cases[f]) for f in (True, False))
    assert follows.status == track.status == "converged"
    assert follows.history["max_plastic_strain"][-1] > 1e-3  # it yields
    for name in ("plastic_strain", "residual_displacement_z"):
        reference = track.fields[name]
        difference = np.abs(follows.fields[name] - reference).max()
        assert difference <= 1e-3 * np.abs(reference).max(), name
    assert np.abs(follows.pressure - track.pressure).max() <= 1e-3 * track.pressure.max()


def test_flow_cut_off_by_the_window_is_found_on_its_inner_sides_only():
    table = {
        "body1": RIGID, "body2": PLASTIC, "friction": {"coefficient": 0.0},
        "load": {"path": [{"hertz_pressure": 4.5 * YIELD / math.sqrt(3.0), "steps": 2}]},
    }  # fmt: skip
    a = _radius({**table, "grid": {}})
    table["load"]["path"].append({"slide": [6 * a, 0.0], "steps": 24})
    table["grid"] = {"n": [48, 16, 12]}
    case = Case.from_dict(table)
    follower = Follower(CaseOperators.build(case))
    shape = (*case.moving_window, 12)
    before = PlasticState.virgin(shape, case.moving_window)
    gained = np.zeros(shape)
    gained[0] = gained[-1] = 2 * PLASTIC_ZONE_THRESHOLD  # both x sides
    after = PlasticState(before.strain, gained, before.displacement)
    follower.offset = (3, 0)  # inside the track along x; the track's own faces along y
    assert follower.sides_reached(before, after) == ["x"]
    follower.offset = (0, 0)  # the track's first cells: only the far side is the window's
    assert follower.sides_reached(before, after) == ["x"]
    gained[1:-1] = 0.0
    gained[-1] = 0.0
    assert follower.sides_reached(before, after) == []
    gained[1:-1, 0] = 2 * PLASTIC_ZONE_THRESHOLD  # the y sides are the track's faces here
    assert follower.sides_reached(before, after) == []


def test_follow_contact_is_a_moving_case_key():
    static = {
        "body1": RIGID, "body2": STEEL, "load": {"hertz_pressure": 1e9}, "grid": {"n": 32},
    }  # fmt: skip
    assert "follow_contact" not in Case.from_dict(static).spec["grid"]  # ids unchanged
    for bad in ("yes", 1, None):
        with pytest.raises(SpecError, match="grid.follow_contact"):
            Case.from_dict({**static, "grid": {"n": 32, "follow_contact": bad}})


def test_a_moving_case_the_window_is_not_built_for_is_told_it_runs_on_the_track():
    """A given grid.size (or a height map, roughness, two plastic bodies): the whole track."""
    a = _radius({"body1": RIGID, "body2": STEEL, "load": {"path": [{"hertz_pressure": 1e9}]}})
    table = {
        "body1": RIGID, "body2": STEEL, "friction": {"coefficient": 0.3},
        "load": {"path": [{"hertz_pressure": 1e9}, {"slide": [4 * a, 0.0], "steps": 4}]},
    }  # fmt: skip
    sized = Case.from_dict({**table, "grid": {"n": [96, 32], "size": [7.5 * a, 2.5 * a]}})
    assert sized.moving_window is None
    assert any("whole track" in note and "grid.size" in note for note in sized.warnings)
    scaled = Case.from_dict({**table, "grid": {"n": [96, 32]}})
    assert scaled.moving_window is not None
    assert not any("whole track" in note for note in scaled.warnings)
    told = Case.from_dict({**table, "grid": {"n": [96, 32], "follow_contact": False}})
    assert not any("whole track" in note for note in told.warnings)  # asked for
