"""A cyclic campaign through the study layer: per-cycle variables assembled, report section."""

import numpy as np
import pytest

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
        with storage.open_case(out, case.case_id) as one:
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
        with storage.open_case(out, case.case_id) as one:
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


def test_tractive_rolling_campaign_creep_curves(tmp_path, monkeypatch):
    """The shipped tractive-rolling campaign, coarsened (the elastic pair, two creepages, two
    passes of 16 steps): the creep force of every pass reaches the dataset, equal to the case
    file's tangential force at the pass's last rolling step; full slip is mu W; the report
    tabulates and draws the creep curves."""
    pytest.importorskip("matplotlib")
    monkeypatch.setattr("study.report.figures.DPI", 40)
    text = open("campaigns/tractive_rolling.toml").read()
    edits = {
        "cycles = 3": "cycles = 2",
        'body2 = ["steel", "steel_epp"]': 'body2 = ["steel"]',
        "[0.5e-3, 1.0e-3, 2.0e-3, 3.5e-3, 6.0e-3]": "[1.0e-3, 6.0e-3]",
        "steps = 48 ": "steps = 16 ",
    }
    for old, new in edits.items():
        assert text.count(old) == 1, old
        text = text.replace(old, new)
    text = text[: text.index("[define.steel_epp]")] + text[text.index("[[base.load.path]]") :]
    path = tmp_path / "rolling.toml"
    path.write_text(text)
    campaign = load_campaign(path)
    out = tmp_path / "out"
    assert run_campaign(campaign, out, options=RunOptions()).exit_status == 0
    ds = assemble(out, campaign)
    assert ds.creep_force_x.dims == ("body2", "xi", "cycle")
    for case in campaign.cases:
        with storage.open_case(out, case.case_id) as one:
            cycle, force = one.step_cycle.values, one.tangential_force_x.values
            moved = np.diff(one.position_x.values, prepend=0.0) != 0
            loaded = one.normal_force.values > 0
            for c in (1, 2):
                last = np.flatnonzero((cycle == c) & moved & loaded)[-1]
                assert ds.creep_force_x.isel(cycle=c - 1)[case.index] == force[last]
    mu_w = 0.3 * ds.hertz_normal_force
    ratio = (ds.creep_force_x / mu_w).isel(body2=0)
    assert 0.3 < float(ratio.isel(xi=0, cycle=-1)) < 0.7  # partial slip at 1e-3
    np.testing.assert_allclose(ratio.isel(xi=1), 1.0, atol=2e-3)  # full slip at 6e-3
    report = build_report(out).read_text()
    assert "## Creep curves" in report and "pass 2" in report
    assert (out / "tractive_rolling_creep_curves.png").stat().st_size > 1000
    assert not (out / "tractive_rolling_fretting_loops.png").exists()  # no Q - Delta loop
