"""Case validation: every rule gives a SpecError naming the field."""

import copy

import pytest

import solver
from solver import SpecError


def mutate(table, path, value):
    out = copy.deepcopy(table)
    node = out
    keys = path.split(".")
    for key in keys[:-1]:
        node = node[key]
    if value is DELETE:
        del node[keys[-1]]
    else:
        node[keys[-1]] = value
    return out


DELETE = object()

BAD = [
    ("body2.E", -1.0, "body2.E"),
    ("body2.E", 0.0, "body2.E"),
    ("body2.E", "steel", "body2.E"),
    ("body2.nu", 0.6, "body2.nu"),
    ("body2.nu", -1.0, "body2.nu"),
    ("body2.nu", DELETE, "body2.nu"),
    ("body2.behaviour", "plastic", "body2.behaviour"),
    ("body2.colour", "red", "body2.colour"),
    ("body1.radius", -0.01, "body1.radius"),
    ("body1.radius", "inf", "body1.radius"),
    ("body1.E", 1e9, "body1.E"),
    ("body2.hardening", {"law": "swift", "B": 1, "C": 1, "n": 0.1}, "body2.hardening"),
    ("friction.coefficient", -0.1, "friction.coefficient"),
    ("friction.coefficient", True, "friction.coefficient"),
    ("load.hertz_pressure", -6e9, "load.hertz_pressure"),
    ("load.hertz_pressure", float("nan"), "load.hertz_pressure"),
    ("load.normal_force", 100.0, "load.hertz_pressure"),
    ("load.steps", 0, "load.steps"),
    ("load.steps", 2.5, "load.steps"),
    ("grid.n", 8, "grid.n"),
    ("grid.n", [64, 64, 64, 64], "grid.n"),
    ("grid.n", 10**6, "grid.n"),
    ("grid.half_width", 0.9, "grid.half_width"),
    ("grid.half_width", 40.0, "grid.n"),
    ("grid.depth", 1.0, "grid.depth"),
    ("grid", DELETE, "grid"),
    ("load", DELETE, "load"),
    ("solver", {"normal_tolerance": 2.0}, "solver.normal_tolerance"),
    ("solver", {"normal_max_iterations": 0}, "solver.normal_max_iterations"),
    ("solver", {"typo": 1}, "solver.typo"),
    ("output", {"fields": ["everything"]}, "output.fields"),
    ("extra", 1, "extra"),
]


@pytest.mark.parametrize("path,value,field", BAD, ids=[f"{b[0]}={b[1]!r}" for b in BAD])
def test_bad_input_names_the_field(hertz_table, path, value, field):
    with pytest.raises(SpecError) as info:
        solver.Case.from_dict(mutate(hertz_table, path, value))
    assert str(info.value).startswith(field), str(info.value)


def test_both_rigid_and_both_flat_rejected(hertz_table):
    with pytest.raises(SpecError, match="body2.behaviour"):
        solver.Case.from_dict(mutate(hertz_table, "body2", {"behaviour": "rigid"}))
    with pytest.raises(SpecError, match="body1.radius"):
        solver.Case.from_dict(mutate(hertz_table, "body1.radius", "inf") | {})


def test_gross_sliding_rejected(hertz_table):
    table = mutate(
        hertz_table,
        "load",
        {"path": [{"normal_force": 1000.0, "steps": 2}, {"tangential_force": [400.0, 0.0]}]},
    )
    table["friction"]["coefficient"] = 0.3
    with pytest.raises(SpecError, match=r"load.path\[1\].tangential_force"):
        solver.Case.from_dict(table)


def test_case_id_normalises_numbers(hertz_table):
    a = solver.Case.from_dict(hertz_table)
    b = solver.Case.from_dict(
        mutate(mutate(hertz_table, "body2.E", 210000000000), "load.steps", 1.0)
    )
    assert a.case_id == b.case_id
    c = solver.Case.from_dict(mutate(hertz_table, "friction.coefficient", 0.1))
    assert c.case_id != a.case_id
    assert solver.Case.from_dict(a.to_dict()).case_id == a.case_id


def test_toml_round_trip(tmp_path):
    path = tmp_path / "case.toml"
    path.write_text(
        """
[body1]
radius = 0.015
behaviour = "rigid"
[body2]
radius = "inf"
behaviour = "elastic-plastic"
E = 210e9
nu = 0.3
[body2.hardening]
law = "swift"
B = 945e6
C = 20
n = 0.121
[load]
hertz_pressure = 6e9
steps = 10
[friction]
coefficient = 0.0
[grid]
n = [64, 64, 32]
half_width = 1.5
"""
    )
    case = solver.Case.from_toml(path)
    assert case.body2.hardening.initial_yield_stress == pytest.approx(1357.9e6, rel=1e-3)
    assert case.max_normal_force == pytest.approx(4716, rel=1e-3)
    assert case.hertz.radius == pytest.approx(0.6126e-3, rel=1e-3)
    assert case.volume_grid.nz == 32
    assert case.total_steps == 10 and case.memory_estimate() > 0
