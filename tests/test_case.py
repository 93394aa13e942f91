"""Case validation: every rule gives a SpecError naming the field."""

import copy
import math

import pytest
from study_fixtures import DELETE, set_path

import solver
from solver import SpecError
from solver.drive.operators import PLASTIC_LOOP_ARRAYS, PLASTIC_VOLUME_ARRAYS, plastic_work_arrays
from solver.volume.eigenstrain import EigenstrainOperator

STEEL = {"E": 210e9, "nu": 0.3}


def mutate(table, path, value):
    out = copy.deepcopy(table)
    set_path(out, path, value)
    return out


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
    ("friction.coefficient", 1e300, "friction.coefficient"),
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


def test_a_campaign_table_read_as_a_case_says_so(hertz_table):
    campaign = {"base": hertz_table, "sweep": {"friction.coefficient": [0.1, 0.2]}}
    with pytest.raises(SpecError, match=r"^base: this is a campaign.*python -m study"):
        solver.Case.from_dict(campaign)


def test_a_rectangular_grid_too_narrow_for_the_contact_names_the_cells_it_needs(hertz_table):
    """Square cells: n = [64, 16] is a quarter as wide along y; the message's count holds."""
    import re

    with pytest.raises(SpecError, match=r"^grid.n: with square cells") as info:
        solver.Case.from_dict(mutate(hertz_table, "grid.n", [64, 16]))
    need = int(re.search(r"ny >= (\d+)", str(info.value)).group(1))
    solver.Case.from_dict(mutate(hertz_table, "grid.n", [64, need]))
    with pytest.raises(SpecError, match="grid.n"):
        solver.Case.from_dict(mutate(hertz_table, "grid.n", [64, need - 1]))


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
    # Swift: sigma_Y0 = B C^n (e_p = 0)
    assert case.body2.hardening.initial_yield_stress == pytest.approx(945e6 * 20**0.121, rel=1e-12)
    # rigid sphere on steel: E* = E / (1 - nu^2); Hertz (Johnson eq. 4.22-4.23):
    # a = pi p_H R / (2 E*), W = 2 pi a^2 p_H / 3 = pi^3 p_H^3 R^2 / (6 E*^2)
    e_star, p_h, radius = 210e9 / (1 - 0.3**2), 6e9, 0.015
    a = math.pi * p_h * radius / (2 * e_star)
    assert case.hertz.radius == pytest.approx(a, rel=1e-12)
    assert case.max_normal_force == pytest.approx(2 * math.pi * a * a * p_h / 3, rel=1e-12)
    assert case.max_normal_force == pytest.approx(
        math.pi**3 * p_h**3 * radius**2 / (6 * e_star**2), rel=1e-12
    )
    assert case.volume_grid.nz == 32 and case.total_steps == 10
    # the plastic case needs, above the same case solved elastic on the 2-D grid, the
    # eigenstrain operator and the plasticity loop's six-component float64 volume fields
    elastic = solver.Case.from_dict(
        mutate(
            mutate(case.to_dict(), "body2", {"radius": "inf", "behaviour": "elastic", **STEEL}),
            "grid",
            {"n": [64, 64], "half_width": 1.5},
        )
    )
    fields = int(plastic_work_arrays(case.solver) * 6 * 8 * 64 * 64 * 32)
    extra = EigenstrainOperator.memory_bytes(case.volume_grid, deviatoric=True) + fields
    assert solver.memory_estimate(case) - solver.memory_estimate(elastic) == extra
    # Anderson keeps 5/6 of a field for each of: iterate and residual, memory + 1 float32
    # differences of each (half a field), the mixing's two inputs and output
    memory = case.solver.anderson_memory
    anderson = 5 / 6 * (2 + 2 * (memory + 1) / 2 + 3)
    loop = PLASTIC_LOOP_ARRAYS + PLASTIC_VOLUME_ARRAYS  # double precision: whole fields
    assert fields == int((loop + anderson) * 48 * 2**17)


# -- extreme numbers: a SpecError naming the field, never OverflowError or NaN results ---------
def _stage(table, load):
    table["load"] = load
    return table


EXTREME = [
    # (path, value, field named, words of the range in the message)
    ("load.hertz_pressure", 1e120, "load.hertz_pressure", "p_H/E* must be in [1e-09, 1]"),
    ("load.hertz_pressure", 1e-300, "load.hertz_pressure", "p_H/E* must be in [1e-09, 1]"),
    ("body1.radius", 5e-324, "body1.radius", "[1e-09, 1e+06] m"),
    ("body1.radius", 1e7, "body1.radius", "[1e-09, 1e+06] m"),
    ("body2.E", 1e300, "body2.E", "[1000, 1e+15] Pa"),
    ("body2.E", 1e-300, "body2.E", "[1000, 1e+15] Pa"),
    ("body2.E", 10**400, "body2.E", "must be finite"),
    ("load", {"normal_force": 1e300}, "load.normal_force", "W in ["),
    ("load", {"normal_force": 5e-324}, "load.normal_force", "W in ["),
    (
        "load",
        {"path": [{"normal_force": 1000.0}, {"normal_force": 1e300}]},
        "load.path[1].normal_force",
        "p_H/E* must be in",
    ),
]


@pytest.mark.parametrize(
    "path,value,field,words", EXTREME, ids=[f"{e[0]}={e[1]!r}"[:40] for e in EXTREME]
)
def test_extreme_numbers_name_the_field_and_range(hertz_table, path, value, field, words):
    with pytest.raises(SpecError) as info:
        solver.Case.from_dict(mutate(hertz_table, path, value))
    message = str(info.value)
    assert message.startswith(field + ":") and words in message, message


def test_load_bounds_follow_from_hertz(hertz_table):
    """The accepted loads are p_H/E* in [1e-9, 1], both ends included (E* = E/(1 - nu^2))."""
    e_star = 210e9 / (1 - 0.3**2)
    for ratio in (1e-9, 1.0):
        case = solver.Case.from_dict(mutate(hertz_table, "load.hertz_pressure", ratio * e_star))
        assert case.hertz.max_pressure == pytest.approx(ratio * e_star, rel=1e-12)
        # the same load as a force: W = pi^3 p_H^3 R^2 / (6 E*^2)
        force = math.pi**3 * (ratio * e_star) ** 3 * 0.015**2 / (6 * e_star**2)
        again = solver.Case.from_dict(mutate(hertz_table, "load", {"normal_force": force}))
        assert again.hertz.max_pressure == pytest.approx(ratio * e_star, rel=1e-12)
    for ratio in (0.999e-9, 1.001):
        with pytest.raises(SpecError, match=r"^load.hertz_pressure: p_H/E\* must be in"):
            solver.Case.from_dict(mutate(hertz_table, "load.hertz_pressure", ratio * e_star))
    # the moduli bounds are inclusive: E = 1e3 Pa and 1e15 Pa with a load inside the range
    for young in (1e3, 1e15):
        table = mutate(hertz_table, "body2.E", young)
        table["load"]["hertz_pressure"] = 0.01 * young / (1 - 0.3**2)
        assert solver.Case.from_dict(table).body2.E == young


def test_unloading_to_zero_still_accepted(hertz_table):
    load = {"path": [{"hertz_pressure": 6e9}, {"normal_force": 0.0}, {"hertz_pressure": 3e9}]}
    case = solver.Case.from_dict(mutate(hertz_table, "load", load))
    assert [s.normal_force for s in case.stages][1] == 0.0
    assert case.stages[2].normal_force == pytest.approx(case.stages[0].normal_force / 8)


def test_swift_yield_stress_overflow_names_the_hardening(hertz_table):
    body = {"radius": "inf", "behaviour": "elastic-plastic", **STEEL}
    body["hardening"] = {"law": "swift", "B": 1e303, "C": 1e7, "n": 1.0}  # B C^n is inf
    table = mutate(hertz_table, "body2", body)
    table["grid"]["n"] = [64, 64, 32]
    with pytest.raises(SpecError, match=r"^body2.hardening.B: the initial yield stress B C\^n"):
        solver.Case.from_dict(table)


def test_half_width_advice_respects_the_largest_grid(hertz_table):
    from solver.keys import MAX_CELLS, MIN_CELLS_ACROSS

    with pytest.raises(SpecError) as info:
        solver.Case.from_dict(mutate(hertz_table, "grid.half_width", 1e6))
    message = str(info.value)
    assert message.startswith("grid.half_width: mesh too coarse"), message
    assert f"n = {MAX_CELLS}" in message and "n >= 10000000," in message
    assert "use n >=" not in message  # no advice beyond the largest grid
    # the advised half_width: n semi-axis / (10 a) = 8192 / 10 for a circle, 64 / 10 at n = 64
    limit = MAX_CELLS / MIN_CELLS_ACROSS
    assert f"reduce half_width to <= {limit:.4g} with n = {MAX_CELLS}" in message
    assert f"(<= {64 / MIN_CELLS_ACROSS:.4g} at n = 64)" in message
    table = mutate(mutate(hertz_table, "grid.half_width", limit), "grid.n", MAX_CELLS)
    assert solver.Case.from_dict(table).grid.half_width == limit  # the advice works
    with pytest.raises(SpecError, match="^grid.half_width: mesh too coarse"):
        solver.Case.from_dict(mutate(table, "grid.half_width", limit * 1.001))
    # within the largest grid the advice is still a mesh size
    with pytest.raises(SpecError, match=r"^grid.n: mesh too coarse.*use n >= 400 "):
        solver.Case.from_dict(mutate(hertz_table, "grid.half_width", 40.0))


def test_numpy_scalars_are_accepted_as_python_values(hertz_table):
    np = pytest.importorskip("numpy")
    plain = solver.Case.from_dict(hertz_table)
    table = copy.deepcopy(hertz_table)
    table["grid"]["n"] = np.int64(64)
    table["grid"]["half_width"] = np.float64(1.6)
    table["body2"]["nu"] = np.float64(0.3)
    table["load"]["hertz_pressure"] = np.float32(6e9)  # exactly representable
    table["load"]["steps"] = np.int32(1)
    table["solver"] = {"goodman": np.bool_(False), "normal_max_iterations": np.uint16(2000)}
    case = solver.Case.from_dict(table)
    assert case.case_id == plain.case_id
    assert type(case.grid.nx) is int and type(case.stages[0].steps) is int
    young = solver.Case.from_dict(mutate(hertz_table, "body2.E", np.float32(210e9))).body2.E
    assert young == float(np.float32(210e9)) and type(young) is float
    assert solver.Case.from_dict(mutate(hertz_table, "grid.n", np.array([64, 64]))) == plain
    # a boolean is never a number, numpy's neither
    for path in ("friction.coefficient", "body2.E", "grid.n"):
        with pytest.raises(SpecError, match=f"^{path}: must be"):
            solver.Case.from_dict(mutate(hertz_table, path, np.bool_(True)))


def test_grid_nz_key(hertz_table):
    plastic = mutate(
        hertz_table,
        "body2",
        {
            "radius": "inf",
            "behaviour": "elastic-plastic",
            **STEEL,
            "hardening": {"law": "swift", "B": 945e6, "C": 20, "n": 0.121},
        },
    )
    full = solver.Case.from_dict(mutate(plastic, "grid.n", [64, 64, 32]))
    apart = solver.Case.from_dict(mutate(plastic, "grid", {"n": 64, "nz": 32, "half_width": 1.6}))
    pair = solver.Case.from_dict(
        mutate(plastic, "grid", {"n": [64, 64], "nz": 32, "half_width": 1.6})
    )
    assert apart.case_id == full.case_id and apart.volume_grid.nz == 32
    assert pair.grid == apart.grid and pair.to_dict()["grid"]["n"] == [64, 64, 32]
    with pytest.raises(SpecError, match=r"^grid.nz: grid.n = \[64, 64, 32\] already gives nz"):
        solver.Case.from_dict(mutate(plastic, "grid", {"n": [64, 64, 32], "nz": 16}))
    with pytest.raises(SpecError, match="^grid.nz: must be between 4 and 8192"):
        solver.Case.from_dict(mutate(plastic, "grid", {"n": 64, "nz": 2}))
