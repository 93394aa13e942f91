"""Messages that point the right way (issue 57, item 6): each names the field and what to do.

A first user met these messages pointing elsewhere: a periodic case without heights was told
to give a finite radius (which periodic mode refuses), a steady stage on a periodic grid to
remove slide and roll (it has neither), a sampled key was called a "swept key", an elastic case
cut by the domain's edge was summarised as "plastic zone cut by the box".
"""

from __future__ import annotations

import math

import pytest
from study_fixtures import NORMAL_BASE, write

import solver
from study.campaign import CampaignError, load_campaign
from study.run.driver import RunSummary

PERIOD = 1e-3  # m
ROUGH = {"hurst": 0.8, "long_cutoff": 2.5e-4, "short_cutoff": 1.25e-4, "rms": 0.5e-6, "seed": 3}


def periodic(body2: dict, **load) -> dict:
    return {
        "body1": {"behaviour": "rigid"},
        "body2": {"behaviour": "elastic", "E": 210e9, "nu": 0.3, **body2},
        "load": {"normal_force": 5.0, **load},
        "grid": {"n": [64, 64], "size": [PERIOD, PERIOD], "periodic": True},
    }


def refusal(table: dict) -> str:
    with pytest.raises(solver.SpecError) as info:
        solver.Case.from_dict(table)
    return str(info.value)


def test_a_periodic_case_without_heights_is_asked_for_heights_not_a_radius():
    message = refusal(periodic({}))
    assert message == (
        "grid.periodic: a periodic domain is one period of a rough flat surface: give body 1 or "
        "body 2 a roughness table or a surface (a height map); radii are refused there (a smooth "
        "sphere: leave grid.periodic out)"
    )
    # and the suggestion works: the same table with a roughness is a case
    assert solver.Case.from_dict(periodic({"roughness": ROUGH})).grid.periodic


def test_a_steady_stage_on_a_periodic_grid_is_told_to_remove_steady():
    stages = [{"normal_force": 5.0}, {"steady": True, "creepage": [1e-3, 0.0], "steps": 2}]
    table = periodic({"roughness": ROUGH})
    table["load"] = {"path": stages}
    table["friction"] = {"coefficient": 0.3}
    assert refusal(table) == (
        "load.path: a periodic case is pressed (with friction and tangential forces) or slid, "
        'not rolled: remove steady (steady rolling of a line contact: grid.periodic = "y")'
    )
    stages[1] = {"roll": [1e-4, 0.0], "creepage": [1e-3, 0.0], "steps": 2}
    assert refusal(table).endswith("not rolled: remove roll")


SAMPLED = """
[campaign]
name = "design"

[sample]
method = "lhs"
count = 4
"{key}" = {{ distribution = "uniform", range = [0.1, 0.3] }}
"load.hertz_pressure" = {{ distribution = "uniform", range = [1e9, 2e9] }}
"""


def test_a_misspelt_sampled_key_is_called_sampled(tmp_path):
    path = write(tmp_path, SAMPLED.format(key="friction.coeficient") + NORMAL_BASE)
    with pytest.raises(CampaignError) as info:
        load_campaign(path)
    assert str(info.value) == (
        'sampled key "friction.coeficient": friction.coeficient: unknown key; allowed keys are '
        "coefficient, shear_factor, shear_limit"
    )


def test_an_alias_of_no_axis_names_the_keys_of_every_kind(tmp_path):
    text = SAMPLED.format(key="friction.coefficient") + '[alias]\n"grid.n" = "cells"\n'
    with pytest.raises(CampaignError) as info:
        load_campaign(write(tmp_path, text + NORMAL_BASE))
    assert str(info.value) == (
        '[alias] "grid.n": not a key of [sweep], [zip] or [sample]; those are '
        "friction.coefficient, load.hertz_pressure"
    )


def test_a_truncated_case_is_not_summarised_as_a_plastic_zone_only():
    summary = RunSummary(campaign="c", out="o", total=2, converged=1, truncated=1)
    text = summary.describe()
    assert "1 truncated (the plastic zone at a face of its box, or the contact at the surface " in (
        text
    )
    assert "domain's edge: each case's notes say which)" in text
    assert "cut by the box" not in text


def test_a_sphere_of_metres_meant_as_millimetres_gets_a_note():
    e_star = 210e9 / (1 - 0.3**2)
    notes = {}
    for radius in (0.01, 10.0):
        case = solver.Case.from_dict(
            {
                "body1": {"behaviour": "rigid", "radius": radius},
                "body2": {"behaviour": "elastic", "E": 210e9, "nu": 0.3},
                "load": {"hertz_pressure": 1e9},
                "grid": {"n": 32},
            }
        )
        notes[radius] = [w for w in case.warnings if "lengths are in metres" in w]
    contact = math.pi * 1e9 * 10.0 / (2 * e_star)  # Hertz: a = pi p0 R / (2 E*)
    assert notes[0.01] == []
    assert notes[10.0] == [
        f"body1.radius = 10 m: the contact radius is {1e3 * contact:.3g} mm; lengths are in "
        "metres (a 10 mm sphere is radius = 0.01): solved as given"
    ]
