"""The plastic part of a campaign report: table, overlaid profiles, load curves, sections."""

import math
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from study_fixtures import pair_campaign, write

from study import analysis
from study.campaign import load_campaign
from study.report import build_report
from study.report import plastic as report_plastic
from study.run.driver import RunOptions, run_campaign

PAIRS = pair_campaign(
    "friction = { coefficient = 0.3 }\ngrid = { n = [16, 16, 16] }\n"
    "load = { hertz_pressure = 6e9, steps = 2 }",
    '{ law = "swift", B = 945e6, C = 20.0, n = 0.121 }',
    '[sweep]\n"load.hertz_pressure" = [4e9, 6e9]\n\n[alias]\n"load.hertz_pressure" = "p_h"\n',
)


@pytest.fixture(scope="module")
def pairs(tmp_path_factory):
    folder = tmp_path_factory.mktemp("report_plastic")
    campaign = load_campaign(write(folder, PAIRS))
    assert run_campaign(campaign, folder / "out", options=RunOptions()).exit_status == 0
    return folder / "out"


def test_plastic_report_table_and_figures(pairs, monkeypatch):
    pytest.importorskip("matplotlib")
    monkeypatch.setattr("study.report.figures.DPI", 40)
    from matplotlib.figure import Figure

    saved, savefig = {}, Figure.savefig

    def capture(self, path, *args, **kwargs):
        saved[Path(path).name] = self
        return savefig(self, path, *args, **kwargs)

    monkeypatch.setattr(Figure, "savefig", capture)
    report = build_report(pairs)
    # the 3 pairs overlaid: each its own (marker, line style); ratios labelled (1), not [Pa]
    for name in ("pairs_plastic_profiles.png", "pairs_load_curves.png"):
        for ax in saved[name].axes:
            styles = {
                line.get_gid(): (line.get_marker(), line.get_linestyle())
                for line in ax.get_lines()
                if str(line.get_gid()).startswith("series ")
            }
            assert len(styles) in (0, 3) and len(set(styles.values())) == len(styles), name
            for label in (ax.get_xlabel(), ax.get_ylabel()):
                assert "[" not in label and (" / " not in label or label.endswith("(1)")), label
    text = report.read_text()
    assert "## Plastic response" in text
    for name in ("plastic_profiles", "load_curves", "plastic_sections"):
        png = pairs / f"pairs_{name}.png"
        assert png.stat().st_size > 1000 and f"({png.name})" in text
    with xr.open_dataset(pairs / "pairs.nc") as ds:
        table = report_plastic.plastic_table(ds.load())
        assert len(table) == 6 and set(table["status"]) == {"converged"}
        cases = [ds.isel(p_h=i, pair=j) for i in range(2) for j in range(3)]  # C order
        for (_, row), case in zip(table.iterrows(), cases, strict=True):
            assert (row["p_h"], row["body2"]) == (float(case.p_h), str(case.body2.values))
            p_h = float(case.hertz_pressure)
            assert row["p_max/p_H"] == pytest.approx(float(case.max_pressure) / p_h, rel=1e-12)
            if row["body2"] == "steel":  # the elastic pair has no plastic strain
                assert math.isnan(row["ep_max_%"])
                assert row["p_max/p_H"] == pytest.approx(1.0, abs=0.02)
            else:
                assert row["ep_max_%"] == pytest.approx(100 * float(case.max_plastic_strain))
                assert row["p_max/p_H"] < 0.99  # plastic flattening
    # the paper's ordering at each load: E-EP above EP-EP in pressure and plastic strain
    for p_h in (4e9, 6e9):
        rows = table[table["p_h"] == p_h].set_index("body1")
        assert rows.loc["steel", "p_max/p_H"].max() > rows.loc["swift", "p_max/p_H"]
        assert np.nanmax(rows.loc["steel", "ep_max_%"]) > rows.loc["swift", "ep_max_%"]


def test_overlay_and_refinement_axes(pairs):
    with xr.open_dataset(pairs / "pairs.nc") as ds:
        assert report_plastic.overlay_dim(ds) == "pair"  # the named axis
        assert analysis.mesh_axes(ds) == []
        assert [labels for labels, _ in report_plastic.shown_cases(ds)][1] == {
            "p_h": 4e9,
            "body1": "steel",
            "body2": "swift",
        }


def test_zones_are_cell_intervals():
    x = np.arange(6) + 0.5
    state = np.array([1, 1, 2, 2, 1, 0])
    assert report_plastic._zones(x, state, 1) == [(0.0, 2.0), (4.0, 5.0)]
    assert report_plastic._zones(x, state, 2) == [(2.0, 4.0)]
    assert report_plastic._zones(x, np.full(6, 2), 2) == [(0.0, 6.0)]
