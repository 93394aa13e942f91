"""``solver.residual_print = "ignored"``: the print is recorded but the contact does not see it."""

from __future__ import annotations

import numpy as np
import pytest

import solver

#: A rigid sphere pressed into elastic-perfectly plastic steel past first yield (p_0 = 5 k),
#: lifted, pressed again.
TABLE = {
    "body1": {"behaviour": "rigid", "radius": 0.01},
    "body2": {
        "behaviour": "elastic-plastic", "radius": "inf", "E": 210e9, "nu": 0.3,
        "hardening": {"law": "perfect", "yield_stress": 433.0127e6},
    },
    "grid": {"n": [24, 24, 12]},
    "load": {
        "path": [
            {"hertz_pressure": 1.25e9, "steps": 2},
            {"hertz_pressure": 0.0, "steps": 1},
            {"hertz_pressure": 1.25e9, "steps": 2},
        ]
    },
}  # fmt: skip


def _solve(print_: str | None):
    table = {**TABLE, "solver": {"residual_print": print_}} if print_ else TABLE
    return solver.solve(solver.Case.from_dict(table))


def test_an_ignored_print_leaves_the_contact_elastic():
    """Ignored, the tractions are the elastic body's on every loading; in the gap, flattened."""
    in_gap, ignored = _solve(None), _solve("ignored")
    elastic_body = {"behaviour": "elastic", "radius": "inf", "E": 210e9, "nu": 0.3}
    elastic = solver.solve(solver.Case.from_dict({**TABLE, "body2": elastic_body}))
    assert in_gap.status == ignored.status == elastic.status == "converged"
    assert ignored.fields["plastic_strain"].max() > 1e-3  # it yields all the same
    dent = ignored.fields["residual_displacement_z"]
    assert dent.max() > 1e-3 * ignored.case.reference.approach  # and the print is recorded
    for step in (1, 4):  # the end of each loading
        expected = elastic.history["max_pressure"][step]
        assert ignored.history["max_pressure"][step] == pytest.approx(expected, rel=1e-6)
        assert ignored.history["contact_area"][step] == elastic.history["contact_area"][step]
        # the print in the gap flattens the pressure (the contact conforms to the dent)
        assert in_gap.history["max_pressure"][step] < 0.9 * expected
    assert np.allclose(
        ignored.pressure, elastic.pressure, rtol=0, atol=1e-6 * elastic.pressure.max()
    )


def test_the_choice_is_in_the_case_id_and_needs_a_plastic_body():
    default = solver.Case.from_dict(TABLE)
    ignored = solver.Case.from_dict({**TABLE, "solver": {"residual_print": "ignored"}})
    assert default.case_id != ignored.case_id
    assert "residual_print" not in default.spec["solver"]
    elastic = {**TABLE, "body2": {"behaviour": "elastic", "radius": "inf", "E": 210e9, "nu": 0.3}}
    with pytest.raises(solver.SpecError, match="solver.residual_print"):
        solver.Case.from_dict({**elastic, "solver": {"residual_print": "ignored"}})
    with pytest.raises(solver.SpecError, match="must be one of"):
        solver.Case.from_dict({**TABLE, "solver": {"residual_print": "partly"}})


def _passes(print_: str, p0k: float) -> solver.Result:
    """Two frictionless passes of campaigns/shakedown_limit.toml's scene at p_0 = p0k k."""
    import tomllib
    from pathlib import Path

    path = Path(__file__).resolve().parents[1] / "campaigns" / "shakedown_limit.toml"
    table = tomllib.loads(path.read_text())["base"]
    pressure = p0k * 433.0127e6 / 3**0.5
    table["load"]["path"][0]["hertz_pressure"] = pressure
    table["load"]["path"][1]["stages"][3]["hertz_pressure"] = pressure
    table["load"]["path"][1]["cycles"] = 2
    table["solver"] = {"residual_print": print_}
    return solver.solve(solver.Case.from_dict(table))


def test_the_conformed_contact_shakes_down_under_a_higher_nominal_load():
    """Melan's factor of the final tractions: Hertz's limit with the print ignored; higher in it.

    Ignored, the case's final tractions are Hertz's (on its cells): their factor times p_0/k
    is the theorem's limit of the Hertz load, to the cells' discretisation.  In the gap, the
    print flattens the pressure: the contact carries less than p_0 at its peak and the same
    nominal load shakes down with room to spare.
    """
    from solver.drive.theorem import conformed_limit
    from solver.theorems.track import Track, track_limits

    p0k = 5.0
    ignored, in_gap = _passes("ignored", p0k), _passes("in_gap", p0k)
    k = 433.0127e6 / 3**0.5
    hertz_limit = track_limits(Track("point", 0.0, 0.3, cells=8)).static.factor
    elastic = conformed_limit(ignored).static
    assert elastic.converged
    assert elastic.factor * p0k == pytest.approx(hertz_limit, rel=0.05)
    assert elastic.factor < 1.0  # p_0 = 5 k is past the classical limit
    conformed = conformed_limit(in_gap).static
    assert conformed.converged
    assert in_gap.pressure.max() < 0.85 * p0k * k  # the print flattens the pressure
    assert conformed.factor > 1.0 > elastic.factor
