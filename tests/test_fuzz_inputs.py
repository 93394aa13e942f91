"""Fuzzed bad inputs: every generated bad campaign file gets one clear message, exit status 2.

Each input is a valid campaign (an elastic sphere on a steel half-space, two friction values;
or a rigid sphere on the paper's elastic-plastic Swift steel, :data:`PLASTIC_GOOD`) with one
fault put in: a wrong type, NaN, an infinity, a huge or tiny number, an integer beyond
the float range, an unknown or a missing key, a table where a value belongs or the reverse, or a
bad swept value.  ``python -m study validate FILE`` must exit with status 2 and print exactly one
line, ``error: ...``, naming the field, on stderr (nothing on stdout, never a traceback), within
a time limit.  Most inputs go through :func:`study.cli.main` in-process (milliseconds each), a
sample through a real ``python -m study`` subprocess.
"""

from __future__ import annotations

import copy
import json
import math
import random
import subprocess
import sys
import time
from pathlib import Path

from study_fixtures import DELETE, set_path

from study.cli import main

REPO = Path(__file__).resolve().parents[1]
#: Seconds one in-process validation may take; a subprocess gets SUBPROCESS_LIMIT.
TIME_LIMIT = 2.0
SUBPROCESS_LIMIT = 30.0
#: Inputs also run through a real subprocess (a deterministic sample).
SUBPROCESS_SAMPLE = 6

GOOD = {
    "campaign": {"name": "fuzz"},
    "base": {
        "body1": {"behaviour": "elastic", "radius": 0.01, "E": 210e9, "nu": 0.3},
        "body2": {"behaviour": "elastic", "radius": "inf", "E": 210e9, "nu": 0.3},
        "load": {"hertz_pressure": 1e9, "steps": 1},
        "friction": {"coefficient": 0.1},
        "grid": {"n": 16, "half_width": 1.5},
        "solver": {"normal_tolerance": 1e-8},
    },
    "sweep": {"solver.slip_tolerance": [1e-6, 1e-7]},
}

#: An elastic-plastic body 2 (the fault is in its hardening, checked before the grid).
EP_BODY2 = {"behaviour": "elastic-plastic", "radius": "inf", "E": 210e9, "nu": 0.3}
KINEMATIC = {"law": "perfect", "yield_stress": 1e9}
#: Wrong values for any number of the base table (each is refused wherever a number belongs).
WRONG_FOR_ANY_NUMBER = ["abc", {"x": 1}, True, math.nan, -math.inf, [1, 2, 3, 4, 5]]
#: Numbers out of each field's range: huge, tiny, infinite, beyond the float range.
OUT_OF_RANGE = {
    "body2.E": [1e300, 5e-324, math.inf, 10**400, -1.0, 0],
    "body1.E": [1e-300, 1e16, 1e308],
    "body1.radius": [5e-324, 1e300, -1e-3, 10**400],
    "body2.nu": [math.inf, 1e300, -1e300, 0.6, -1],
    "load.hertz_pressure": [1e120, 5e-324, math.inf, 1e300, 0, 10**400],
    "load.steps": [1e300, 0, 2.5, 10**6, -(10**30)],
    "grid.n": [1e300, 5e-324, 3, 10**18, 8193],
    "grid.half_width": [1e300, 5e-324, 1e6, 0.5, math.inf],
    "friction.coefficient": [-1e300, -5e-324, math.inf, 1e300, 5e-324, 1e-9],
    "solver.normal_tolerance": [1e300, 0.1, 0, math.inf, -1e-8],
}
#: (where the fault goes, the value (DELETE removes the key), the field the message names).
STRUCTURE = [
    ("base.colour", 1, "colour: unknown key"),
    ("base.body1.colour", "red", "body1.colour: unknown key"),
    ("base.load.colour", 1, "load.colour: unknown key"),
    ("base.grid.nzz", 8, "grid.nzz: unknown key"),
    ("base.solver.colour", 1, "solver.colour: unknown key"),
    ("base.friction.mu", 0.1, "friction.mu: unknown key"),
    ("campaign.colour", 1, "campaign.colour: unknown setting"),
    ("base.body1", DELETE, "body1: missing required field"),
    ("base.body2.E", DELETE, "body2.E: missing required field for an elastic body"),
    ("base.body2.behaviour", DELETE, "body2.behaviour: missing required field"),
    ("base.load", DELETE, "load: missing required field"),
    ("base.grid", DELETE, "grid: missing required field"),
    ("base.grid.n", DELETE, "grid.n: missing required field"),
    ("base.load.hertz_pressure", DELETE, "load: missing load"),
    ("base", DELETE, "[base]: missing"),
    ("base.body1", 5, "body1: must be a table"),
    ("base.grid", [1, 2], "grid: must be a table"),
    ("base.load", "heavy", "load: must be a table"),
    ("base.load", {"path": 5}, "load.path: must be a non-empty array"),
    ("base.load", {"path": []}, "load.path: must be a non-empty array"),
    ("base.load", {"path": [1, 2]}, "load.path[0]: must be a table"),
    ("base.solver", [1], '"solver.slip_tolerance": solver is an array'),
    ("base.friction", 0.3, "friction: must be a table"),
    ("base.body2.hardening", {"law": "swift"}, "body2.hardening"),
    ("base.grid.n", [16, 16, 16, 16], "grid.n: must be an integer or [nx, ny]"),
    ("base.grid.n", [16, "x"], "grid.n: must be an integer"),
    ("base.grid.nz", 2, "grid.nz: must be between 4 and 8192"),
    ("base.grid.nz", 1e300, "grid.nz: must be between 4 and 8192"),
    ("base.grid", {"n": [16, 16, 8], "nz": 8}, "grid.nz: grid.n = [16, 16, 8] already gives nz"),
    ("base.body1.behaviour", ["elastic"], "body1.behaviour: must be rigid, elastic or"),
    ("base.output", {"fields": "stress"}, "output.fields"),
    ("sweep", {"friction.coefficient": [math.nan]}, "nan is not a value"),
    ("sweep", {"friction.coefficient": [{"a": 1}]}, "friction.coefficient"),
    ("sweep", {"body2.E": [1e300, 210e9]}, "body2.E: Young's modulus must be in"),
    ("sweep", {"load.hertz_pressure": [1e9, 1e120]}, "load.hertz_pressure: p_H/E*"),
    ("sweep", {"grid.n": [16, 1e300]}, "grid.n: must be between 4 and 8192"),
    ("sweep", {"materials.dundurs_beta": [0.0, 0.2321428571428572]}, "materials.dundurs_beta"),
    ("sweep", {"materials.dundurs_beta": [math.inf]}, "materials.dundurs_beta"),
    ("sweep", {"body2.colour": [1, 2]}, "body2.colour: unknown key"),
    ("sweep", 5, "[sweep]: must be a table"),
    ("campaign", {"case_timeout": math.nan}, "campaign.case_timeout"),
    # cycle blocks, kinematic hardening, [define] tables
    (
        "base.load",
        {"path": [{"hertz_pressure": 1e9}, {"cycles": "many", "stages": [{}]}]},
        "load.path[1].cycles: must be an integer",
    ),
    (
        "base.load",
        {"path": [{"hertz_pressure": 1e9}, {"cycles": 10**400, "stages": [{}]}]},
        "load.path[1].cycles",
    ),
    (
        "base.load",
        {"path": [{"hertz_pressure": 1e9}, {"cycles": 2, "stages": 5}]},
        "load.path[1].stages: must be a non-empty array",
    ),
    (
        "base.load",
        {"path": [{"hertz_pressure": 1e9}, {"cycles": 2, "stages": [5]}]},
        "load.path[1].stages[0]: must be a table",
    ),
    (
        "base.load",
        {"path": [{"cycles": 2, "stages": [{"steps": 1}]}]},
        "load.path[0].stages[0]: missing load",
    ),
    (
        "base.body2",
        EP_BODY2 | {"hardening": KINEMATIC | {"kinematic": {"law": "prager", "C": math.nan}}},
        "body2.hardening.kinematic.C: must be finite",
    ),
    (
        "base.body2",
        EP_BODY2 | {"hardening": KINEMATIC | {"kinematic": 5}},
        "body2.hardening.kinematic: must be a table",
    ),
    (
        "base.body2",
        EP_BODY2 | {"nu": 0.5, "hardening": KINEMATIC},
        "body2.nu: an elastic-plastic body must be compressible, nu < 0.5",
    ),
    ("define", {"steel": 5}, "[define]: must hold named tables"),
    ("sweep", {"body1": ["nosuch"]}, "'nosuch' is not a [define.NAME] table"),
    ("campaign", {"profile_points": 10**400}, "campaign.profile_points"),
]


#: A valid elastic-plastic campaign: a rigid sphere on the paper's Swift steel at 4 GPa.
PLASTIC_GOOD = {
    "campaign": {"name": "fuzz_plastic"},
    "base": {
        "body1": {"behaviour": "rigid", "radius": 0.015},
        "body2": EP_BODY2 | {"hardening": {"law": "swift", "B": 945e6, "C": 20.0, "n": 0.121}},
        "load": {"hertz_pressure": 4e9, "steps": 2},
        "grid": {"n": [16, 16, 16]},
    },
    "sweep": {"friction.coefficient": [0.0, 0.3]},
}
SWIFT = PLASTIC_GOOD["base"]["body2"]["hardening"]
PERFECT = {"law": "perfect", "yield_stress": 1e9}
LINEAR = {"law": "linear", "yield_stress": 1e9, "modulus": 10e9}
_LONG_STAGES = [{"tangential_force": 10.0, "steps": 100_000}, {"steps": 100_000}]
#: Faults put into :data:`PLASTIC_GOOD`: the volume box, the hardening laws, kinematic
#: hardening, cycle blocks, the path length and the plastic regime (where, value, message).
PLASTIC_FAULTS = [
    # the volume box (depth in units of a_H, cells that resolve the yield region)
    ("base.grid.depth", 1e6, "grid.depth: must be in [0.05, 20]"),
    ("base.grid.depth", 1e-9, "grid.depth: must be in [0.05, 20]"),
    ("base.grid.depth", 10.0, "grid.depth: cells 0.625 a_H thick"),
    ("base.grid.depth", 30.0, "grid.depth: must be in"),
    ("base.grid.depth", 100, "grid.depth: must be in"),
    ("base.grid.depth", 0.3, "grid.depth: the box ends at 0.3 a_H"),
    ("base.grid.depth", -1.0, "grid.depth: must be > 0"),
    ("base.grid.depth", "deep", "grid.depth: must be a number"),
    ("base.grid.depth", math.inf, "grid.depth: must be finite"),
    ("base.grid.depth_body1", 3.0, "grid.depth_body1: only two elastic-plastic"),
    ("base.grid.plastic_half_width", 5.0, "grid.plastic_half_width: must be in [0.25, half_width"),
    ("base.grid.plastic_half_width", 0.1, "grid.plastic_half_width: must be in [0.25"),
    ("base.grid.plastic_half_width", -1.0, "grid.plastic_half_width: must be > 0"),
    ("base.grid.plastic_half_width", "wide", "grid.plastic_half_width: must be a number"),
    ("base.solver", {"volume_precision": "half"}, 'solver.volume_precision: must be "double"'),
    ("base.solver", {"volume_precision": 32}, 'solver.volume_precision: must be "double"'),
    (
        "base.solver",
        {"volume_precision": "single", "plastic_tolerance": 1e-8},
        "solver.volume_precision: single precision rounds",
    ),
    ("base.grid.depth_body1", 1e6, "grid.depth_body1: must be in"),
    ("base.grid.n", [16, 16, 4], "grid.n: cells 0.416 a_H thick"),
    ("sweep", {"grid.nz": [16, 4]}, "grid.n: cells"),
    ("sweep", {"grid.depth": [1.5, 50.0]}, "grid.depth: must be in"),
    # hardening laws: yield stresses and parameters bounded relative to E
    ("base.body2.hardening", PERFECT | {"yield_stress": 5e-324}, "hardening.yield_stress: the"),
    ("base.body2.hardening", PERFECT | {"yield_stress": 1e-300}, "hardening.yield_stress: the"),
    ("base.body2.hardening", PERFECT | {"yield_stress": 1e12}, "hardening.yield_stress: the"),
    ("base.body2.hardening", SWIFT | {"B": 5e-324}, "body2.hardening.B: the initial yield"),
    ("base.body2.hardening", SWIFT | {"C": 1e-300}, "body2.hardening.C: Swift's offset"),
    ("base.body2.hardening", SWIFT | {"C": 1e300}, "body2.hardening.C: Swift's offset"),
    ("base.body2.hardening", SWIFT | {"n": 5.0}, "body2.hardening.n: Swift's exponent"),
    ("base.body2.hardening", SWIFT | {"n": -0.1}, "body2.hardening.n: must be > 0"),
    ("base.body2.hardening", SWIFT | {"n": math.nan}, "body2.hardening.n: must be finite"),
    ("base.body2.hardening", LINEAR | {"modulus": 1e300}, "hardening.modulus: a hardening"),
    ("base.body2.hardening", LINEAR | {"modulus": -1.0}, "hardening.modulus: must be >= 0"),
    ("base.body2.hardening", {"law": "voce"}, "body2.hardening.law: must be one of"),
    ("base.body2.hardening", DELETE, "body2.hardening: missing"),
    # kinematic hardening
    (
        "base.body2.hardening",
        PERFECT | {"kinematic": {"law": "prager", "C": 1e300}},
        "body2.hardening.kinematic.C: a hardening modulus",
    ),
    (
        "base.body2.hardening",
        PERFECT | {"kinematic": {"law": "armstrong-frederick", "C": 200e9, "gamma": 1e300}},
        "body2.hardening.kinematic.gamma: must be at most",
    ),
    (
        "base.body2.hardening",
        PERFECT | {"kinematic": {"law": "armstrong-frederick", "C": 200e9, "gamma": -1.0}},
        "body2.hardening.kinematic.gamma: must be > 0",
    ),
    (
        "base.body2.hardening",
        PERFECT | {"kinematic": {"law": "chaboche", "C": 1e9}},
        "body2.hardening.kinematic.law: must be one of",
    ),
    (
        "base.body2.hardening",
        PERFECT | {"kinematic": {"law": "prager"}},
        "body2.hardening.kinematic.C: missing",
    ),
    # cycle blocks and the length of the path
    (
        "base.load",
        {"path": [{"hertz_pressure": 4e9}, {"cycles": 10_000, "stages": _LONG_STAGES}]},
        "load.path[1].cycles: the load path reaches",
    ),
    (
        "base.load",
        {"path": [{"hertz_pressure": 4e9, "steps": 100_000}] * 11},
        "load.path[10].steps: the load path reaches",
    ),
    (
        "base.load",
        {"path": [{"hertz_pressure": 4e9}, {"cycles": 0, "stages": [{"normal_force": 0.0}]}]},
        "load.path[1].cycles: must be between 1 and",
    ),
    (
        "base.load",
        {"path": [{"hertz_pressure": 4e9}, {"cycles": 2, "stages": [{"cycles": 2}]}]},
        "load.path[1].stages[0].cycles: cycle blocks do not nest",
    ),
    (
        "base.load",
        {"path": [{"hertz_pressure": 4e9}, {"cycles": 2, "stages": [{"steps": 0}]}]},
        "load.path[1].stages[0].steps: must be between 1 and",
    ),
    # past the small-strain theory: a fully plastic indentation
    ("base.body2.hardening", PERFECT | {"yield_stress": 0.2e9}, "load: Johnson's index"),
    ("sweep", {"load.hertz_pressure": [4e9, 80e9]}, "load: Johnson's index"),
]


#: Files no table can be written as: (id, TOML text, text the message must contain).
_GOOD_SWEEP = '[sweep]\n"solver.slip_tolerance" = [1e-6, 1e-7]\n'
RAW = [
    ("int of 5000 digits", "a = " + "1" * 5000 + "\n", "not valid TOML"),
    ("int of 400 digits swept", _GOOD_SWEEP.replace("1e-7", "1" + "0" * 400), "slip_tolerance"),
    ("steps of 400 digits", '[sweep]\n"load.steps" = [' + "9" * 400 + "]\n", "load.steps"),
    ("unterminated table", "[sweep\n", "not valid TOML"),
    ("not UTF-8", 'a = "\udcff"\n', "not valid TOML"),
    ("nan in a zip", '[zip]\n"grid.n" = [16, nan]\n"load.steps" = [1, 2]\n', "nan is not"),
]


def _inputs() -> list[tuple[str, str, str]]:
    """(id, campaign file text, text the message must contain), in a fixed order."""
    out = []
    for field in OUT_OF_RANGE:
        for value in WRONG_FOR_ANY_NUMBER:
            out.append((f"{field}={value!r}", field, value, f"{field}:"))
    for field, values in OUT_OF_RANGE.items():
        for value in values:
            out.append((f"{field}={str(value)[:12]}", field, value, f"{field}:"))
    cases = []
    for name, field, value, expected in out:
        table = copy.deepcopy(GOOD)
        set_path(table, f"base.{field}", value)
        cases.append((name, to_toml(table), expected))
    for where, value, expected in STRUCTURE:
        table = copy.deepcopy(GOOD)
        set_path(table, where, value)
        name = f"{where}={'<deleted>' if value is DELETE else repr(value)[:20]}"
        cases.append((name, to_toml(table), expected))
    for where, value, expected in PLASTIC_FAULTS:
        table = copy.deepcopy(PLASTIC_GOOD)
        set_path(table, where, value)
        name = f"plastic {where}={'<deleted>' if value is DELETE else repr(value)[:20]}"
        cases.append((name, to_toml(table), expected))
    base = to_toml({key: value for key, value in GOOD.items() if key != "sweep"})
    for name, text, expected in RAW:
        cases.append(
            (name, text if name.startswith(("int of 5000", "not UTF")) else text + base, expected)
        )
    return cases


def _toml_value(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, list):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    if isinstance(value, dict):
        items = ", ".join(f"{json.dumps(k)} = {_toml_value(v)}" for k, v in value.items())
        return "{ " + items + " }"
    raise TypeError(value)


def to_toml(table: dict) -> str:
    """A campaign table as TOML: scalars first, then one [table] per top-level table."""
    lines = [
        f"{json.dumps(k)} = {_toml_value(v)}" for k, v in table.items() if not isinstance(v, dict)
    ]
    for name, inner in table.items():
        if isinstance(inner, dict):
            lines.append(f"[{name}]")
            lines += [f"{json.dumps(k)} = {_toml_value(v)}" for k, v in inner.items()]
    return "\n".join(lines) + "\n"


INPUTS = _inputs()


def test_the_generator_makes_enough_distinct_bad_files_and_a_good_one(tmp_path, capsys):
    texts = {text for _, text, _ in INPUTS}
    assert len(INPUTS) >= 50 and len(texts) == len(INPUTS)
    good = tmp_path / "good.toml"
    good.write_text(to_toml(GOOD))
    assert main(["validate", str(good)]) == 0  # the unmutated campaign is valid
    assert capsys.readouterr().out.strip().endswith("valid")
    good.write_text(to_toml(PLASTIC_GOOD))
    assert main(["validate", str(good)]) == 0  # so is the elastic-plastic one, without a warning
    assert capsys.readouterr().err == ""
    assert len(PLASTIC_FAULTS) >= 30


def _check(status: int, out: str, err: str, expected: str, name: str) -> None:
    assert status == 2, f"{name}: exit {status}\n{out}{err}"
    assert out == "", f"{name}: {out}"
    assert "Traceback" not in err, f"{name}: {err}"
    assert err.startswith("error: ") and err.count("\n") == 1, f"{name}: {err!r}"
    assert expected in err, f"{name}: expected {expected!r} in {err!r}"


def test_every_bad_input_one_line_naming_the_field(tmp_path, capsys):
    slowest = 0.0
    for number, (name, text, expected) in enumerate(INPUTS):
        path = tmp_path / f"bad{number}.toml"
        path.write_bytes(text.encode(errors="surrogateescape"))
        start = time.perf_counter()
        status = main(["validate", str(path)])
        elapsed = time.perf_counter() - start
        slowest = max(slowest, elapsed)
        captured = capsys.readouterr()
        _check(status, captured.out, captured.err, expected, name)
        assert elapsed < TIME_LIMIT, f"{name}: {elapsed:.2f} s"
    assert slowest < TIME_LIMIT


def test_a_sample_through_python_m_study(tmp_path):
    sample = random.Random(20261123).sample(INPUTS, SUBPROCESS_SAMPLE)
    for number, (name, text, expected) in enumerate(sample):
        path = tmp_path / f"bad{number}.toml"
        path.write_bytes(text.encode(errors="surrogateescape"))
        done = subprocess.run(
            [sys.executable, "-m", "study", "validate", str(path)],
            capture_output=True,
            text=True,
            cwd=REPO,
            timeout=SUBPROCESS_LIMIT,
        )
        _check(done.returncode, done.stdout, done.stderr, expected, name)
