"""The rough-interface part of a campaign report: a periodic elastic-plastic rough period."""

import numpy as np
import pytest
import xarray as xr
from study_fixtures import write

from solver.drive.record import spot_areas
from study import analysis
from study.campaign import load_campaign
from study.report import build_report, builder
from study.report import rough as report_rough
from study.run import storage
from study.run.assemble import assemble_to_file
from study.run.driver import RunOptions, run_campaign

#: Two realisations of a rough period on elastic-plastic steel, loaded in 2 steps and unloaded
#: (64^2 x 16 cells, layers half a cell thick: seconds a case).
ROUGH = """
[campaign]
name = "rough"

[base]
body1 = { behaviour = "rigid", radius = "inf" }
grid = { n = [64, 64, 16], size = 1e-4, depth = 1.25e-5, periodic = true }

[base.body2]
behaviour = "elastic-plastic"
radius = "inf"
E = 210e9
nu = 0.3
hardening = { law = "linear", yield_stress = 1e9, modulus = 10e9 }
roughness = { hurst = 0.8, long_cutoff = 2.5e-5, short_cutoff = 1.25e-5, rms = 5e-8, seed = 1 }

[[base.load.path]]
normal_force = 4.0
steps = 2

[[base.load.path]]
normal_force = 0.0
steps = 1

[sweep]
"body2.roughness.seed" = [1, 2]
"""


@pytest.fixture(scope="module")
def rough(tmp_path_factory):
    folder = tmp_path_factory.mktemp("report_rough")
    campaign = load_campaign(write(folder, ROUGH))
    assert run_campaign(campaign, folder / "out", options=RunOptions()).exit_status == 0
    assemble_to_file(folder / "out")
    return folder / "out"


def test_the_rough_section_tabulates_the_case_files(rough):
    with xr.open_dataset(rough / "rough.nc") as raw:
        dataset = analysis.with_derived(raw.load())
    table = report_rough.rough_table(dataset, rough)
    assert len(table) == 2
    index = storage.case_index(rough)
    for (_, row), case_id in zip(table.iterrows(), dataset["case_id"].values.ravel(), strict=True):
        with storage.open_case(rough, str(case_id), index=index) as case:
            fraction = case["contact_fraction"].values
            peak = int(np.argmax(case["normal_force"].values))
            assert row["contact_%"] == pytest.approx(100 * fraction[peak])
            assert row["p_mean_MPa"] == pytest.approx(4.0 / 1e-8 / 1e6)
            assert row["ep_max_%"] == pytest.approx(100 * case["max_plastic_strain"].max())
            before, after = case["initial_gap"].values, case["residual_gap"].values
            assert row["residual_rms_nm"] == pytest.approx(1e9 * after.std())
            # the print is the residual displacement of the plastic strain, into body 2
            assert np.allclose(after - before, case["residual_displacement_z"].values)
            assert case["mean_separation"].values[-1] > case["mean_separation"].values[peak]
            # every step's spots are on record: those of the largest load, though it ends unloaded
            areas = case["spot_areas"].values[peak]
            areas = areas[np.isfinite(areas)]
            assert areas.size == int(case["contact_spots"].values[peak])
            period = 1e-4 * 1e-4
            assert areas.sum() == pytest.approx(fraction[peak] * period)
            assert np.all(np.diff(areas) <= 0.0)
            assert not np.isfinite(case["spot_areas"].values[-1]).any()  # unloaded: no spot
        assert row["residual_rms_nm"] < row["gap_rms_nm"]  # the asperities flattened
        assert row["largest_spot_%"] == pytest.approx(100 * areas[0] / areas.sum())


def test_the_rough_report_draws_its_figures(rough, monkeypatch):
    pytest.importorskip("matplotlib")
    monkeypatch.setattr("study.report.figures.DPI", 40)
    text = build_report(rough).read_text()
    assert "## Rough interface" in text and "## Plastic response" not in text
    # a period has no approach or central dent to speak of; headers say their reduction
    quantities = next(line for line in text.splitlines() if line.startswith("- quantities:"))
    assert "max_pressure" in quantities
    assert all(name not in text for name in builder.NOT_PERIODIC)
    assert all(f"| {label} |" in text for label in report_rough.column_labels().values())
    for name in ("load_curves", "residual_topography", "spot_sizes"):  # spots: at the peak
        assert (rough / f"rough_{name}.png").exists()
        assert f"rough_{name}.png" in text


def test_spot_areas_join_across_the_period():
    mask = np.zeros((6, 6), dtype=bool)
    mask[0, 2] = mask[-1, 2] = True  # one spot split by the x seam
    mask[3, 3] = True
    assert list(spot_areas(mask, 2.0, periodic=True)) == [4.0, 2.0]
    assert list(spot_areas(mask, 2.0)) == [2.0, 2.0, 2.0]
    assert spot_areas(np.zeros((4, 4), dtype=bool), 1.0).size == 0
