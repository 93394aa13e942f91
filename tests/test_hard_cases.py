"""The stability atlas of hard cases (issue 58), reduced to its cheap corners.

``campaigns/hard_cases.toml`` lists the corners of a pressed and sheared sphere on perfectly
plastic steel, each with Coulomb's law alone and with ``friction.shear_limit = "yield"``.  The
reduced atlas keeps its 16^3 corners of at most 8 increments a stage (the meshes of 64^3 and
128^3 and the 500 steps run with the campaign) and checks what the atlas promises: every case
ends with a status its notes explain, Coulomb's law past the shear yield stress ends
``surface_flow`` and under the limit the same corner converges, no loop ran past its cap and
no value is NaN.  Then the campaign machinery runs four of its cases and the report draws the
atlas (status, CPU over the easy case, iterations per loop).
"""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

import solver
from study.campaign import expand_campaign
from study.report import build_report
from study.report.atlas import atlas_table
from study.run.assemble import assemble_to_file
from study.run.driver import run_campaign

ATLAS = Path(__file__).resolve().parents[1] / "campaigns" / "hard_cases.toml"


def _table() -> dict:
    with open(ATLAS, "rb") as handle:
        return tomllib.load(handle)


def _reduced(table: dict, keep) -> dict:
    """The atlas with the corners ``keep(index, entry)`` selects."""
    zipped = table["zip"]["corner"]
    count = len(next(iter(zipped.values())))
    chosen = [i for i in range(count) if keep(i, {k: v[i] for k, v in zipped.items()})]
    table["zip"]["corner"] = {k: [v[i] for i in chosen] for k, v in zipped.items()}
    return table


def _cheap(_: int, entry: dict) -> bool:
    return entry["grid.n"] == 16 and entry["load.path.0.steps"] <= 8


@pytest.fixture(scope="module")
def reduced_atlas():
    campaign = expand_campaign(_reduced(_table(), _cheap), name="hard_cases")
    return [(item, solver.solve(item.case())) for item in campaign.cases]


def test_the_reduced_atlas_ends_every_case_with_an_explained_status(reduced_atlas):
    assert len(reduced_atlas) == 18  # 9 corners of 16^3 and at most 8 steps a stage, two laws
    k = 433.0127e6 / math.sqrt(3.0)
    for item, result in reduced_atlas:
        case, coords = result.case, item.coords
        law = case.friction.shear_limit
        mu, p0 = case.friction_coefficient, case.reference.max_pressure
        if law is None and mu * p0 > 1.05 * k and mu >= 1.0:  # far past k: the surface flows
            assert result.status == "surface_flow", (coords, result.notes)
            assert len(result.history["normal_force"]) < case.total_steps
        elif law == "yield" or mu * p0 <= k:  # capped, or below k everywhere
            assert result.status == "converged", (coords, result.notes)
            assert result.history.get("surface_shear_ratio", np.zeros(1)).max() <= 1 + 1e-9
        if result.status != "converged":  # a note says why
            why = ("surface shear traction reaches", "enlarge the box", "not converged")
            assert any(w in n for n in result.notes for w in why), (coords, result.notes)
        steps = len(result.history["normal_force"])
        cap = case.solver.plastic_max_iterations
        # halving retries a failed increment at most 1 + 2 + 4 + 8 times its cap
        assert result.history["plastic_iterations"].max() <= 15 * cap
        assert steps >= 1
        for name, values in result.history.items():
            assert np.isfinite(values).all(), (coords, name)
        for values in (result.pressure, result.shear_x, result.fields["plastic_strain"]):
            assert np.isfinite(values).all(), coords


def test_the_limit_turns_every_surface_flow_corner_converged(reduced_atlas):
    """Pair each corner's two laws: where Coulomb's law flows, the limit converges."""
    by_corner: dict[tuple, dict] = {}
    for item, result in reduced_atlas:
        key = tuple((k, v) for k, v in item.coords.items() if k not in ("shear_limit", "Q"))
        by_corner.setdefault(key, {})[item.coords["shear_limit"]] = result
    flowing = [pair for pair in by_corner.values() if pair["none"].status == "surface_flow"]
    assert len(flowing) >= 2  # mu = 1 and mu = 2
    for pair in flowing:
        assert pair["yield"].status == "converged"
        assert pair["yield"].history["max_plastic_strain"].max() < 0.02


def test_the_report_draws_the_atlas(tmp_path, monkeypatch):
    """Four cases through the campaign machinery: the atlas table and its figure."""
    keep = {0, 1, 2, 3}  # the easy case and mu = 1, each law
    table = _reduced(_table(), lambda i, entry: i in keep)
    out = tmp_path / "out"
    campaign = expand_campaign(table, name="hard_cases")
    assert run_campaign(campaign, out).exit_status == 0
    assemble_to_file(out, campaign)
    import xarray as xr

    with xr.open_dataset(out / "hard_cases.nc") as dataset:
        rows = atlas_table(dataset.load())
    assert list(rows["corner"]) == ["easy case", "easy case", "mu 1", "mu 1"]
    assert list(rows["status"]) == ["converged", "converged", "surface_flow", "converged"]
    assert rows["cpu/easy"].iloc[0] == 1.0 and rows["cpu/easy"].iloc[1] == 1.0
    assert (rows["cpu_s"] > 0).all()
    assert "surface shear traction reaches" in rows["why"].iloc[2]
    assert (rows["plastic"] > 0).all()
    report = build_report(out).read_text()
    assert "## Stability atlas" in report
    assert (out / "hard_cases_atlas.png").stat().st_size > 0
