"""Loops that make no progress stop, told, instead of iterating on to their caps (issue 58).

A tolerance below round-off cannot be reached: the plasticity loop and the slip-stick coupling
then make no progress, and each must stop :data:`~solver.drive.steps.STALL_WINDOW` iterations
after its best, with its residual's history in the message and a diagnosis note, far below
the caps given (1000), with finite fields.  The same cases at the default tolerances converge.
"""

from __future__ import annotations

import copy
import re

import numpy as np
import pytest

import solver
from solver.drive.steps import STALL_WINDOW

CAP = 1000
PLASTIC = {
    "body1": {"behaviour": "rigid", "radius": 0.01},
    "body2": {
        "behaviour": "elastic-plastic",
        "E": 210e9,
        "nu": 0.3,
        "hardening": {"law": "linear", "yield_stress": 1e9, "modulus": 10e9},
    },
    "load": {"hertz_pressure": 3e9, "steps": 2},
    "grid": {"n": [16, 16, 16]},
}
COUPLED = {
    "body1": {"behaviour": "rigid", "radius": 0.01},
    "body2": {"behaviour": "elastic", "E": 210e9, "nu": 0.3},  # beta = 0.29 with the rigid
    "friction": {"coefficient": 0.3},
    "load": {"path": [{"hertz_pressure": 1e9, "steps": 2}, {"tangential_force": 2.0, "steps": 2}]},
    "grid": {"n": [32, 32]},
}


def _solve(table: dict, **options) -> solver.Result:
    table = copy.deepcopy(table)
    table["solver"] = options
    return solver.solve(solver.Case.from_dict(table))


def _stalled(result: solver.Result, loop: str) -> None:
    messages = [note for note in result.notes if "did not converge" in note or "step " in note]
    assert result.status == "not_converged"
    assert any(f"{loop} loop stalled" in m for m in messages), result.notes
    assert any(f"no progress over its last {STALL_WINDOW}" in m for m in messages)
    assert any(m.startswith("diagnosis:") and "stalled" in m for m in result.notes)
    for name, values in result.history.items():
        assert np.all(np.isfinite(values)), name


@pytest.mark.parametrize(
    ("table", "key", "loop", "history"),
    [
        (PLASTIC, "plastic", "plasticity", "plastic_iterations"),
        (COUPLED, "coupling", "slip-stick", "coupling_iterations"),
    ],
    ids=["plasticity", "coupling"],
)
def test_a_loop_that_cannot_reach_its_tolerance_stops_told_far_below_its_cap(
    table, key, loop, history
):
    default = _solve(table)
    assert default.status == "converged"
    stuck = _solve(table, **{f"{key}_tolerance": 1e-300, f"{key}_max_iterations": CAP})
    _stalled(stuck, loop)
    # each loop stopped STALL_WINDOW after its best, far below the cap
    stops = [int(n) for n in re.findall(r"loop stalled after (\d+) iterations", str(stuck.notes))]
    assert stops and max(stops) < CAP // 4, stops
    if key == "plastic":  # a stalled increment and its halves (4 attempts), all bounded
        assert STALL_WINDOW < stuck.history[history].max() < CAP, stuck.history[history]
