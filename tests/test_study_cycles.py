"""A cyclic campaign through the study layer: per-cycle variables assembled, report section."""

import numpy as np
import pytest
import xarray as xr

from study.campaign import load_campaign
from study.report import build_report
from study.run import storage
from study.run.assemble import assemble
from study.run.driver import RunOptions, run_campaign

CAMPAIGN = "campaigns/fretting_cycles.toml"


@pytest.fixture(scope="module")
def cycles_out(tmp_path_factory):
    """The shipped fretting-cycles campaign, coarsened: 16^3, 2 cycles, 4 steps per stage."""
    folder = tmp_path_factory.mktemp("cycles")
    text = open(CAMPAIGN).read()
    text = text.replace("n = [32, 32, 32]", "n = [16, 16, 16]").replace("cycles = 5", "cycles = 2")
    text = text.replace("steps = 16", "steps = 4").replace("steps = 8", "steps = 2")
    path = folder / "cycles.toml"
    path.write_text(text)
    campaign = load_campaign(path)
    out = folder / "out"
    assert run_campaign(campaign, out, options=RunOptions()).exit_status == 0
    return campaign, out


def test_per_cycle_variables_are_assembled_from_the_case_files(cycles_out):
    campaign, out = cycles_out
    ds = assemble(out, campaign)
    assert ds.cycle.values.tolist() == [1, 2]
    assert ds.loop_energy.dims == ("loading", "cycle")
    for case in campaign.cases:
        with xr.open_dataset(storage.case_path(out, case.case_id)) as one:
            row = ds.isel(loading=case.index[0])
            for name in ("loop_energy", "cycle_friction_work", "plastic_strain_increment"):
                np.testing.assert_array_equal(row[name].values, one[name].values)
    # a larger amplitude dissipates more, and the plastic strain grows less in cycle 2
    energy = ds.loop_energy.isel(cycle=-1).values
    assert energy[1] > energy[0] and energy[3] > energy[2]
    gained = ds.plastic_strain_increment.values
    assert np.all(gained[:, 1] <= gained[:, 0])
    # the body has shaken down by cycle 2: the loop area is the friction work (1 %)
    last = ds.isel(cycle=-1)
    np.testing.assert_allclose(last.cycle_friction_work, last.loop_energy, rtol=0.01)


def test_cycle_report_builds(cycles_out, monkeypatch):
    pytest.importorskip("matplotlib")
    monkeypatch.setattr("study.report.figures.DPI", 40)
    _, out = cycles_out
    text = build_report(out).read_text()
    assert "## Load cycles" in text
    for name in ("fretting_loops", "cycles"):
        png = out / f"fretting_cycles_{name}.png"
        assert png.stat().st_size > 1000 and f"({png.name})" in text


def test_normal_load_cycles_report(tmp_path, monkeypatch):
    """The shipped repeated-indentation campaign, coarsened (2 cycles): a cycle section without
    fretting loops (no tangential load) but with the plastic strain and residual stress panels."""
    pytest.importorskip("matplotlib")
    monkeypatch.setattr("study.report.figures.DPI", 40)
    text = open("campaigns/repeated_indentation.toml").read()
    text = text.replace("n = [28, 28, 28]", "n = [26, 26, 26]").replace("cycles = 5", "cycles = 2")
    path = tmp_path / "indent.toml"
    path.write_text(text.replace("steps = 6", "steps = 3"))
    campaign = load_campaign(path)
    out = tmp_path / "out"
    assert run_campaign(campaign, out, options=RunOptions()).exit_status == 0
    report = build_report(out).read_text()
    assert "## Load cycles" in report and "| hardening | status | cycles |" in report
    assert (out / "repeated_indentation_cycles.png").stat().st_size > 1000
    assert not (out / "repeated_indentation_fretting_loops.png").exists()
    ds = assemble(out, campaign)
    assert ds.plastic_strain_increment.dims == ("hardening", "cycle")
    assert "loop_energy" not in ds


def test_shakedown_campaign_regimes_and_map(tmp_path, monkeypatch):
    """The shipped frictionless shakedown campaign, coarsened (two pressures, three passes): the
    regime of every case file reaches the dataset with its reason, and the report draws the map."""
    pytest.importorskip("matplotlib")
    monkeypatch.setattr("study.report.figures.DPI", 40)
    text = open("campaigns/shakedown_frictionless.toml").read().replace("cycles = 10", "cycles = 3")
    pressures = "[1.20e9, 1.30e9, 1.40e9, 1.50e9, 1.60e9, 1.70e9, 1.80e9]"
    assert text.count(pressures) == 2
    path = tmp_path / "shakedown.toml"
    path.write_text(text.replace(pressures, "[0.6e9, 1.4e9]"))
    campaign = load_campaign(path)
    out = tmp_path / "out"
    assert run_campaign(campaign, out, options=RunOptions()).exit_status == 0
    ds = assemble(out, campaign)
    assert ds.shakedown.dims == ("pressure",)
    for case in campaign.cases:
        with xr.open_dataset(storage.case_path(out, case.case_id)) as one:
            row = ds.isel(pressure=case.index[0])
            assert int(row.shakedown) == int(one.shakedown)
            assert str(row.shakedown_reason.values) == one.shakedown.attrs["reason"]
    meanings = ds.shakedown.attrs["flag_meanings"].split()
    flags = list(ds.shakedown.attrs["flag_values"])
    regimes = [meanings[flags.index(f)] for f in ds.shakedown.values]
    assert regimes[0] == "elastic"  # 2.4 k: below first yield (2.79 k)
    assert regimes[1] != "elastic"  # 5.6 k: yields
    np.testing.assert_allclose(ds.hertz_pressure / ds.shear_yield_stress, [2.4, 5.6], rtol=1e-6)
    report = build_report(out).read_text()
    assert "## Shakedown" in report and "p0/k" in report and "elastic" in report
    assert (out / "shakedown_frictionless_shakedown_map.png").stat().st_size > 1000
