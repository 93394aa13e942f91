"""``solver.method = "static_shakedown"``: a case solved by Melan's theorem, run and reported.

The limits come from :mod:`solver.theorems` (tested against closed forms in
``tests/test_theorems.py``); here: the case gives the theorem the right track, the result says
what it holds, the inputs the theorem cannot take are refused, a campaign runs and reports.
"""

from __future__ import annotations

import copy
import math

import numpy as np
import pytest
import xarray as xr
from study_fixtures import write

import solver
from solver.drive.theorem import track_of
from solver.result import STATUS_FLAGS
from solver.theorems.track import track_limits
from study import analysis
from study.campaign import load_campaign
from study.report import build_report
from study.report import theorem as report_theorem
from study.run import storage
from study.run.assemble import assemble_to_file
from study.run.driver import RunOptions, run_campaign

SIGMA_Y = 433.0127e6  # k = 250 MPa
#: A rigid sphere sliding over elastic-perfectly plastic steel at p_0 = 3.2 k, cells of a/4.
TABLE = {
    "body1": {"behaviour": "rigid", "radius": 0.01},
    "body2": {
        "behaviour": "elastic-plastic", "radius": "inf", "E": 210e9, "nu": 0.3,
        "hardening": {"law": "perfect", "yield_stress": SIGMA_Y},
    },
    "friction": {"coefficient": 0.3},
    "grid": {"n": [48, 16, 12]},
    "load": {"path": [{"hertz_pressure": 0.8e9, "steps": 1}, {"slide": [1e-4, 0.0], "steps": 1}]},
    "solver": {"method": "static_shakedown"},
}  # fmt: skip


def _table(**changes) -> dict:
    table = copy.deepcopy(TABLE)
    for path, value in changes.items():
        *keys, last = path.split("__")
        target = table
        for key in keys:
            target = target[key]
        target[last] = value
    return table


def test_a_case_gives_the_theorem_its_track_and_reports_the_limits():
    case = solver.Case.from_dict(_table())
    track, p0, (a, b), _ = track_of(case)
    assert a == b and p0 == pytest.approx(0.8e9) and track.friction == 0.3 and track.nu == 0.3
    assert track.cells == round(a / case.surface_grid.dx)
    result = solver.solve(case)
    assert result.status == "converged" and result.loops == ("static_shakedown",)
    expected = track_limits(track, case.solver.kinematic_cells)
    h = result.history
    assert h["static_shakedown_limit"][0] == expected.static.factor
    assert h["shakedown_upper_bound"][0] == expected.upper
    assert h["kinematic_upper_bound"][0] == expected.kinematic.factor
    assert expected.kinematic.converged and math.isfinite(expected.kinematic.factor)
    k = SIGMA_Y / math.sqrt(3.0)
    assert h["static_shakedown_lower_bound"][0] == expected.lower
    assert h["shakedown_load_factor"][0] == pytest.approx(expected.lower * k / p0)
    data = result.to_xarray()
    assert data["static_residual_stress"].dims == ("component", "y_section", "z_section")
    assert float(data["z_section"][0]) == 0.0 and data["y_section"].attrs["units"] == "m"
    assert np.abs(data["static_residual_stress"]).max() > 0.1 * k  # in Pa, not in units of k
    assert int(data["static_binding"].sum()) >= 1
    assert data["pressure"].max() == pytest.approx(p0, rel=0.05)  # Hertz's, on the cells


def test_the_method_is_in_the_case_id_only_when_not_incremental():
    incremental = _table(solver={})
    ids = {solver.Case.from_dict(incremental).case_id}
    ids.add(solver.Case.from_dict(_table(solver={"method": "incremental"})).case_id)
    assert len(ids) == 1
    assert solver.Case.from_dict(_table()).case_id not in ids
    assert "method" not in solver.Case.from_dict(incremental).spec["solver"]


def test_the_mechanisms_mesh_is_a_theorem_key():
    """In every static case's id (its default too); refused by the incremental method."""
    default = solver.Case.from_dict(_table())
    assert default.spec["solver"]["kinematic_cells"] == 8
    off = solver.Case.from_dict(_table(solver={"method": "static_shakedown", "kinematic_cells": 0}))
    assert off.case_id != default.case_id
    assert "kinematic_cells" not in solver.Case.from_dict(_table(solver={})).spec["solver"]
    with pytest.raises(ValueError, match="solver.kinematic_cells"):
        solver.Case.from_dict(_table(solver={"kinematic_cells": 4}))
    with pytest.raises(ValueError, match="solver.kinematic_cells"):
        solver.Case.from_dict(_table(solver={"method": "static_shakedown", "kinematic_cells": 99}))
    result = solver.solve(off)
    assert result.history["kinematic_upper_bound"][0] == math.inf
    assert not any(note.startswith("kinematic") for note in result.notes)


def test_kinematic_hardening_bounds_the_back_stress():
    hardening = {
        "law": "perfect", "yield_stress": SIGMA_Y,
        "kinematic": {"law": "armstrong-frederick", "C": 20e9, "gamma": 200.0},
    }  # fmt: skip
    case = solver.Case.from_dict(_table(body2__hardening=hardening))
    track = track_of(case)[0]
    assert track.back_stress_bound == pytest.approx(math.sqrt(2.0) * (20e9 / 200.0) / SIGMA_Y)
    prager = {**hardening, "kinematic": {"law": "prager", "C": 20e9}}
    assert math.isinf(
        track_of(solver.Case.from_dict(_table(body2__hardening=prager)))[0].back_stress_bound
    )
    perfect = solver.solve(solver.Case.from_dict(_table()))
    kinematic = solver.solve(case)
    assert kinematic.status == "converged"
    limit = kinematic.history["static_shakedown_limit"][0]
    assert limit >= perfect.history["static_shakedown_limit"][0] * (1.0 - 1e-6)


def test_an_elliptical_contact_lies_between_the_line_and_the_circle():
    """Frictionless, the contact long across the track: between 4.0 k (a line) and the circle."""
    from solver.theorems.loads import elliptical_hertz, traction_limit

    table = _table(friction={"coefficient": 0.0})
    table["body1"] = {"behaviour": "rigid", "radius_x": 0.01, "radius_y": 0.04}
    table["grid"] = {"n": [48, 48, 12]}
    case = solver.Case.from_dict(table)
    track, p0, (a, b), _ = track_of(case)
    assert b > 1.5 * a
    result = solver.solve(case)
    assert result.status == "converged"
    limit = result.history["static_shakedown_limit"][0]
    # the circle on the same cells and route (Hertz's pressure on cells of a / cells)
    pressure, shear, grid = elliptical_hertz((1.0, 1.0), 1.0, 0.0, track.cells)
    c = track.cells
    circle = traction_limit(pressure, shear, grid, 0.3, 1.0, 4 * c, 3 * c, 4 * c).static.factor
    assert 4.0 < limit < circle
    assert result.history["first_yield_limit"][0] < limit
    assert result.history["kinematic_upper_bound"][0] == math.inf  # not built: said so
    assert any("not solved for an elliptical contact" in note for note in result.notes)
    assert result.fields["static_residual_stress"].shape[1:] == (
        result.section[0].size,
        result.section[1].size,
    )


@pytest.mark.parametrize(
    "changes, key, words",
    [
        ({"solver": {"method": "melan"}}, "solver.method", "must be one of"),
        (
            {"solver": {"method": "static_shakedown", "residual_print": "in_gap"}},
            "solver.residual_print",
            "leave the key out",
        ),
        (
            {"body2__hardening": {"law": "linear", "yield_stress": SIGMA_Y, "modulus": 1e9}},
            "body2.hardening.law",
            "isotropic hardening",
        ),
        (
            {
                "load": {
                    "path": [
                        {"hertz_pressure": 0.8e9, "steps": 1},
                        {"hertz_pressure": 0.0, "steps": 1},
                        {"slide": [1e-4, 0.0], "steps": 1},
                    ]
                }
            },
            "solver.method",
            "slide the loaded contact along x",
        ),
        (
            {
                "load": {
                    "path": [
                        {"hertz_pressure": 0.8e9, "steps": 1},
                        {"slide": [0.0, 1e-4], "steps": 1},
                    ]
                },
                "grid": {"n": [48, 48, 12]},
            },
            "solver.method",
            "along x",
        ),
        (
            {"body2__behaviour": "elastic", "body2__hardening": None},
            "solver.method",
            "elastic-plastic body 2",
        ),
    ],
)
def test_what_the_theorem_cannot_take_is_refused(changes, key, words):
    table = _table(**changes)
    if table["body2"].get("hardening") is None:
        table["body2"].pop("hardening", None)
    with pytest.raises(solver.SpecError) as raised:
        solver.Case.from_dict(table)
    assert key in str(raised.value) and words in str(raised.value)


CAMPAIGN = """
[campaign]
name = "theorem"

[base]
grid = { n = [48, 16, 12] }
body1 = { behaviour = "rigid", radius = 0.01 }
solver = { method = "static_shakedown" }
friction = { coefficient = 0.0 }

[base.body2]
behaviour = "elastic-plastic"
radius = "inf"
E = 210e9
nu = 0.3
hardening = { law = "perfect", yield_stress = 433.0127e6 }

[[base.load.path]]
hertz_pressure = 0.8e9
steps = 1

[[base.load.path]]
slide = [1e-4, 0.0]
steps = 1

[sweep]
"friction.coefficient" = [0.0, 0.5]
"""


@pytest.fixture(scope="module")
def theorem_campaign(tmp_path_factory):
    folder = tmp_path_factory.mktemp("theorem")
    campaign = load_campaign(write(folder, CAMPAIGN))
    assert run_campaign(campaign, folder / "out", options=RunOptions()).exit_status == 0
    assemble_to_file(folder / "out")
    return folder / "out"


def test_a_theorem_campaign_assembles_and_reports(theorem_campaign):
    with xr.open_dataset(theorem_campaign / "theorem.nc") as raw:
        dataset = analysis.with_derived(raw.load())
    assert report_theorem.is_theorem(dataset)
    table = report_theorem.theorem_table(dataset)
    assert list(table["mu"]) == [0.0, 0.5]
    cases = storage.read_campaign(theorem_campaign).cases
    frictionless, sliding = (track_of(item.case())[0] for item in cases)
    assert (frictionless.friction, sliding.friction) == (0.0, 0.5)
    frictionless_limits = track_limits(frictionless)
    assert table["static estimate p0/k"].iloc[0] == pytest.approx(frictionless_limits.static.factor)
    assert table["lower bound p0/k"].iloc[0] == pytest.approx(frictionless_limits.lower)
    assert table["upper p0/k"].iloc[1] == pytest.approx(track_limits(sliding).upper)
    report = build_report(theorem_campaign)
    text = report.read_text()
    assert "## Static shakedown" in text and "## Profiles" not in text
    assert (theorem_campaign / "theorem_static_shakedown_map.png").exists()


def test_a_printed_lower_bound_never_exceeds_an_upper_bound_of_its_case(theorem_campaign):
    """The report's lower bound lies under both upper bounds of its row, the estimate may not."""
    with xr.open_dataset(theorem_campaign / "theorem.nc") as raw:
        dataset = analysis.with_derived(raw.load())
    table = report_theorem.theorem_table(dataset)
    lower = table[report_theorem.LOWER]
    assert lower.notna().all() and (table["bracket"] == "ok").all()
    for upper in report_theorem.UPPER:
        assert (lower <= table[upper]).all(), table[[report_theorem.LOWER, upper]]
    assert (lower <= table["static estimate p0/k"]).all()
    # a row whose lower bound lies above an upper bound is withheld, not printed as one
    finished = analysis.finished_cases
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(
            report_theorem.analysis,
            "finished_cases",
            lambda data: [
                (
                    labels,
                    number,
                    case.assign(static_shakedown_lower_bound=case["shakedown_upper_bound"] * 1.01),
                )
                for labels, number, case in finished(data)
            ],
        )
        withheld = report_theorem.theorem_table(dataset)
    assert withheld[report_theorem.LOWER].isna().all()
    assert withheld["bracket"].str.startswith("withheld").all()


def test_a_friction_above_the_theorems_range_is_refused_at_validation():
    with pytest.raises(solver.SpecError) as raised:
        solver.Case.from_dict(_table(friction={"coefficient": 1.5}))
    assert str(raised.value) == (
        "friction.coefficient: static_shakedown's theorems take 0 <= mu <= 1, got 1.5: give a "
        "coefficient of at most 1 or use the incremental method"
    )
    assert solver.Case.from_dict(_table(friction={"coefficient": 1.0})).friction_coefficient == 1


UNSOLVED_KINEMATIC = CAMPAIGN.replace(
    'solver = { method = "static_shakedown" }',
    'solver = { method = "static_shakedown", kinematic_cells = 0 }',
).replace('"friction.coefficient" = [0.0, 0.5]', '"friction.coefficient" = [0.5]')


def test_a_declared_infinity_is_data_and_an_undeclared_nan_a_failure(tmp_path):
    """kinematic_cells = 0: the kinematic bound is inf (declared), the case finishes with it."""
    from solver.variables import HISTORIES

    assert HISTORIES["kinematic_upper_bound"].infinite
    assert HISTORIES["static_shakedown_lower_bound"].infinite is None
    campaign = load_campaign(write(tmp_path, UNSOLVED_KINEMATIC))
    out = tmp_path / "out"
    summary = run_campaign(campaign, out, options=RunOptions())
    assert summary.exit_status == 0 and summary.converged == 1 and summary.failed == 0
    assemble_to_file(out)
    with xr.open_dataset(out / "theorem.nc") as raw:
        dataset = raw.load()
    ((_, _, case),) = analysis.finished_cases(dataset)
    assert int(case["status"]) == STATUS_FLAGS["converged"]
    assert np.isposinf(float(case["kinematic_upper_bound"]))
    assert np.isfinite(float(case["static_shakedown_lower_bound"]))

    solved = solver.solve(campaign.cases[0].case())

    def broken(to_solve):  # the same result with a value no declaration admits
        result = copy.copy(solved)
        result.history = {**solved.history, "static_shakedown_lower_bound": np.array([np.nan])}
        return result

    failed = tmp_path / "failed"
    summary = run_campaign(campaign, failed, options=RunOptions(solve=broken))
    assert summary.failed == 1 and summary.converged == 0
    (record,) = [storage.read_failure(failed, i) for i in storage.failed_ids(failed)]
    assert "history static_shakedown_lower_bound" in str(record)
    assert "kinematic_upper_bound" not in str(record.get("error", ""))


def test_a_theorem_case_file_from_before_the_certified_lower_bound_is_not_reused():
    """Model version 5 changed what a static_shakedown case computes (the certified lower bound
    that shakedown_load_factor follows): its id carries version 5, a file of version 4 is
    refused for it; the same scene solved incrementally takes version 7 (its plasticity loops
    stop when they stall), with friction or without, and an elastic one the oldest version."""
    from solver.case.case import MODEL_CHANGES, MODEL_VERSION, OLDEST_MODEL

    theorem = solver.Case.from_dict(_table())
    assert theorem.spec["model"] == 5 <= MODEL_VERSION and "static_shakedown" in MODEL_CHANGES[5]
    table = theorem.to_dict()
    table["model"] = 4
    with pytest.raises(solver.SpecError, match=r"^model: .*version 5 changed how it is solved"):
        solver.Case.from_dict(table)
    incremental = _table()
    del incremental["solver"]
    assert (
        solver.Case.from_dict(incremental).spec["model"] == 7 and "no progress" in MODEL_CHANGES[7]
    )
    incremental["friction"] = {"coefficient": 0.0}
    assert solver.Case.from_dict(incremental).spec["model"] == 7
    incremental["body2"] = {
        key: value for key, value in incremental["body2"].items() if key != "hardening"
    } | {"behaviour": "elastic"}
    assert solver.Case.from_dict(incremental).spec["model"] == OLDEST_MODEL
