"""Sampled designs (``[sample]``) and their global sensitivity (issue 40, first step).

Independent references: Hertz's radius ``a = (3 W R / (4 E*))^(1/3)`` makes ``ln a`` linear in
``ln W``, ``ln R`` and ``ln E*``, so with log-uniform independent inputs its Sobol' indices are
the shares of the variances of those logarithms (the coefficients are all 1/3), and Morris'
elementary effects in the unit hypercube are exactly ``(1/3) ln(high / low)`` with no spread.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import xarray as xr
from study_fixtures import DESIGN_BASE as BASE
from study_fixtures import DESIGN_RANGES as RANGES

from study import bundle
from study.analysis import morris_indices, sobol_indices
from study.campaign import CampaignError, expand_campaign
from study.campaign.cost import REFERENCE
from study.campaign.sample import Distribution, parse_sample
from study.campaign.validate import normalise_key
from study.report import build_report
from study.run import storage
from study.run.assemble import assemble_to_file
from study.run.driver import run_campaign


def _log_uniform() -> dict:
    return {k: {"distribution": "log-uniform", "range": list(r)} for k, r in RANGES.items()}


def _campaign(sample: dict, **more):
    table = {"campaign": {"name": "sampled", "fields": []}, "base": BASE, "sample": sample, **more}
    return expand_campaign(table, name="sampled")


def _run(campaign, tmp_path) -> xr.Dataset:
    out = tmp_path / campaign.name
    run_campaign(campaign, out)
    with xr.open_dataset(assemble_to_file(out, campaign), engine=storage.ENGINE) as ds:
        return ds.load()


def _exact_shares() -> np.ndarray:
    """Variance shares of ln W, ln E, ln R: each log-uniform log is uniform, var = ln(h/l)^2/12."""
    variances = np.array([math.log(high / low) ** 2 / 12 for low, high in RANGES.values()])
    return variances / variances.sum()


# -- reading ---------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("sample", "message"),
    [
        ({"method": "random", "count": 4}, "sample.method"),
        ({"method": "lhs", "count": 0}, "sample.count"),
        ({"method": "sobol", "count": 12}, "take 8 or 16"),
        (
            {
                "method": "saltelli",
                "count": 8,
                "load.normal_force": {"distribution": "uniform", "range": [1.0, 2.0]},
            },
            "two sampled keys",
        ),  # fmt: skip
        (
            {"method": "lhs", "count": 4, "load.normal_force": {"distribution": "gamma"}},
            "distribution: must be one of",
        ),  # fmt: skip
        (
            {
                "method": "lhs",
                "count": 4,
                "load.normal_force": {"distribution": "uniform", "range": [2.0, 1.0]},
            },
            "low must be below high",
        ),  # fmt: skip
        (
            {
                "method": "lhs",
                "count": 4,
                "load.normal_force": {"distribution": "log-uniform", "range": [0.0, 1.0]},
            },
            "must be positive",
        ),  # fmt: skip
        (
            {
                "method": "lhs",
                "count": 4,
                "load.normal_force": {"distribution": "uniform", "range": [1.0, 2.0], "mean": 1.5},
            },
            "not a field of a uniform",
        ),  # fmt: skip
        (
            {
                "method": "morris",
                "count": 4,
                "body1.nu": {"distribution": "normal", "mean": 0.3, "std": 0.02},
                "load.normal_force": {"distribution": "uniform", "range": [1.0, 2.0]},
            },
            "give it bounds",
        ),  # fmt: skip
        (
            {
                "method": "lhs",
                "count": 4,
                "grid.n": {"distribution": "discrete", "values": [16, "32"]},
            },
            "mixed value types",
        ),  # fmt: skip
        (
            {
                "method": "lhs",
                "count": 4,
                "load.normal_force": {"distribution": "log-uniform", "range": [5e-324, 1e300]},
            },
            "overflows",
        ),  # fmt: skip
        ({"method": "lhs", "count": 4, "second_order": True}, "second_order"),
        ({"method": "lhs", "count": 4, "levels": 4}, "sample.levels"),
        ({"method": "lhs", "count": 4}, "no key to sample"),
        (
            {
                "method": "lhs",
                "count": 4,
                "bogus.key": {"distribution": "uniform", "range": [1.0, 2.0]},
            },
            'unknown case table "bogus"',
        ),  # fmt: skip
    ],
)
def test_bad_sample_tables_are_refused_by_name(sample, message):
    if message != "no key to sample" and not any(isinstance(v, dict) for v in sample.values()):
        sample = {**sample, **_log_uniform()}  # only the setting is wrong
    with pytest.raises(CampaignError, match=message):
        _campaign(sample)


def test_a_key_both_swept_and_sampled_and_a_zip_named_sample_are_refused():
    sample = {"method": "lhs", "count": 4, **_log_uniform()}
    with pytest.raises(CampaignError, match="duplicate axis"):
        _campaign(sample, sweep={"load.normal_force": [1.0, 2.0]})
    with pytest.raises(CampaignError, match=r"\[zip.sample\]"):
        _campaign(sample, zip={"sample": {"friction.coefficient": [0.1, 0.2]}})


def test_design_sizes_and_reproducibility():
    d = len(RANGES)
    sizes = {
        ("lhs", False): 10, ("sobol", False): 16, ("saltelli", False): 16 * (d + 2),
        ("saltelli", True): 16 * (2 * d + 2), ("morris", False): 10 * (d + 1),
    }  # fmt: skip
    for (method, second), rows in sizes.items():
        count = 16 if method in ("sobol", "saltelli") else 10
        sample = {"method": method, "count": count, "seed": 5, **_log_uniform()}
        if second:
            sample["second_order"] = True
        campaign = _campaign(sample)
        assert campaign.dims == ("sample",) and campaign.shape == (rows,)
        assert campaign.design.rows == rows
        again = _campaign(sample)
        other = _campaign({**sample, "seed": 6})
        assert again.design.unit == campaign.design.unit
        assert other.design.unit != campaign.design.unit
        for j, (low, high) in enumerate(RANGES.values()):
            values = np.array(campaign.design.values()[j])
            assert np.all((values >= low) & (values <= high))


def test_distributions_map_the_unit_interval():
    u = np.linspace(0.0, 1.0, 11)
    assert Distribution("uniform", 2.0, 4.0).quantile(u) == pytest.approx(2.0 + 2.0 * u)
    assert Distribution("log-uniform", 1.0, 100.0).quantile(u) == pytest.approx(100.0**u)
    # a Latin hypercube of 4000 points: the normal's mean and deviation, the discrete shares
    sample = {
        "method": "lhs", "count": 4000, "seed": 1,
        "body1.nu": {"distribution": "normal", "mean": 0.3, "std": 0.02},
        "body2.nu": {"distribution": "normal", "mean": 0.3, "std": 0.05, "bounds": [0.25, 0.4]},
        "grid.n": {"distribution": "discrete", "values": [16, 20, 24, 32]},
    }  # fmt: skip
    design = parse_sample(sample, normalise_key)
    nu1, nu2, n = (np.array(v) for v in design.values())
    assert nu1.mean() == pytest.approx(0.3, abs=1e-5) and nu1.std() == pytest.approx(0.02, rel=1e-2)
    assert nu2.min() >= 0.25 and nu2.max() <= 0.4
    from scipy.stats import truncnorm

    a, b = (0.25 - 0.3) / 0.05, (0.4 - 0.3) / 0.05
    assert nu2.mean() == pytest.approx(truncnorm.mean(a, b, loc=0.3, scale=0.05), abs=1e-4)
    assert [int(np.sum(n == v)) for v in (16, 20, 24, 32)] == [1000] * 4  # one per stratum
    assert all(isinstance(v, int) for v in design.values()[2])


def test_a_swept_key_beside_a_design_gives_one_design_per_value():
    campaign = _campaign(
        {"method": "lhs", "count": 5, **_log_uniform()}, sweep={"friction.coefficient": [0.0, 0.2]}
    )
    assert campaign.dims == ("friction_coefficient", "sample") and len(campaign.cases) == 10


def test_repeated_rows_are_one_case_computed_once(tmp_path, capsys):
    sample = {
        "method": "saltelli", "count": 8, "seed": 2,
        "load.normal_force": {"distribution": "discrete", "values": [50.0, 100.0]},
        "body1.radius": {"distribution": "discrete", "values": [0.005, 0.01]},
    }  # fmt: skip
    campaign = _campaign(sample)
    distinct = len(campaign.distinct_cases())
    assert distinct <= 4 < len(campaign.cases) == 32
    ds = _run(campaign, tmp_path)
    stored = [  # every entry of every bundle: each distinct case computed and stored once
        case_id
        for file in (tmp_path / "sampled" / "cases").glob("*" + bundle.SUFFIX)
        for case_id in bundle.read_index(file)[0]
    ]
    assert len(stored) == len(set(stored)) == distinct
    assert bool((ds["status"] == 1).all())
    force = ds["normal_force"].values
    assert force == pytest.approx(ds["load_normal_force"].values)  # every row filled, its own
    # validate and status count the distinct cases, and say how many rows the design has
    from study.cli import main
    from study.validation import describe_campaign

    text = describe_campaign(campaign, list_cases=True, calibration=REFERENCE)
    assert f"32 rows of {distinct} distinct cases" in text
    listed = [
        line.split()[0] for line in text.splitlines() if line.startswith("  ") and " s  " in line
    ]
    assert len(listed) == len(set(listed)) == distinct
    assert main(["status", str(tmp_path / "sampled")]) == 0
    line = capsys.readouterr().out.splitlines()[0]
    assert f"{distinct}/{distinct} finished" in line and "32 rows of the design" in line, line


# -- the closed-form check through the pipeline ----------------------------------------------------
@pytest.mark.validation
def test_sobol_indices_of_hertz_radius_match_the_variance_shares(tmp_path, validation):
    """Saltelli N = 128 over W, E, R log-uniform: S1 = ST = the shares, within the intervals;
    the intervals of the first 8, 32, 128 base samples shrink like 1/sqrt(N)."""
    campaign = _campaign({"method": "saltelli", "count": 128, "seed": 11, **_log_uniform()})
    ds = _run(campaign, tmp_path)
    exact = _exact_shares()
    table = sobol_indices(ds, "hertz_radius", log=True)
    for key in ("S1", "ST"):
        errors = np.abs(table[key].to_numpy() - exact)
        assert np.all(errors <= table[f"{key}_conf"].to_numpy())
    # the solver's own contact radius: the grid scales with a_H, the same indices
    solved = sobol_indices(ds, "contact_radius", log=True)
    assert np.all(np.abs(solved["S1"].to_numpy() - exact) <= solved["S1_conf"].to_numpy())
    widths = []
    for n in (8, 32, 128):
        part = ds.isel(sample=slice(0, n * (len(RANGES) + 2)))
        widths.append(sobol_indices(part, "hertz_radius", log=True)["S1_conf"].to_numpy().mean())
    ratios = [widths[0] / widths[1], widths[1] / widths[2]]
    assert all(1.4 < r < 3.0 for r in ratios)  # 2 for 1/sqrt(N) at 4x the samples
    validation(
        "Sobol' indices through the whole pipeline (study.analysis.global_sensitivity)",
        "ln a of Hertz linear in ln W, ln E*, ln R: S1 = ST = the variance shares "
        + ", ".join(f"{v:.4f}" for v in exact),
        "S1 " + ", ".join(f"{v:.4f}" for v in table["S1"])
        + " (+- " + ", ".join(f"{v:.3f}" for v in table["S1_conf"]) + ") at N = 128; "
        "interval widths at N = 8, 32, 128: " + ", ".join(f"{w:.3f}" for w in widths),
    )  # fmt: skip


def test_morris_effects_of_hertz_radius_are_exact(tmp_path):
    campaign = _campaign({"method": "morris", "count": 12, "seed": 4, **_log_uniform()})
    ds = _run(campaign, tmp_path)
    table = morris_indices(ds, "hertz_radius", log=True)
    signs = {"load.normal_force": 1.0, "body1.E": -1.0, "body1.radius": 1.0}
    for (key, (low, high)), (_, row) in zip(RANGES.items(), table.iterrows(), strict=True):
        effect = math.log(high / low) / 3.0
        assert row["mu_star"] == pytest.approx(effect, rel=1e-9)
        assert row["mu"] == pytest.approx(signs[key] * effect, rel=1e-9)
        assert row["sigma"] < 1e-9 * effect
    assert set(table["trajectories"]) == {12}


def test_unfinished_cases_leave_their_blocks_out(tmp_path):
    campaign = _campaign({"method": "saltelli", "count": 16, "seed": 1, **_log_uniform()})
    ds = _run(campaign, tmp_path)
    status = ds["status"].values.copy()
    status[[3, 7]] = 3  # two cases of the first two blocks (5 rows each) failed
    broken = ds.assign(status=(("sample",), status))
    table = sobol_indices(broken, "hertz_radius", log=True)
    assert set(table["samples"]) == {14} and set(table["left_out"]) == {2}
    assert np.all(np.isfinite(table["S1"]))
    with pytest.raises(ValueError, match="method = 'morris'"):
        morris_indices(ds, "hertz_radius")


@pytest.mark.parametrize("method", ["saltelli", "lhs"])
def test_report_draws_the_design_section(tmp_path, method, monkeypatch):
    from study.report import builder

    monkeypatch.setattr(builder, "MAX_CASE_ROWS", 30)  # past it: statistics, not every case
    count = 8 if method == "saltelli" else 12
    campaign = _campaign({"method": method, "count": count, "seed": 3, **_log_uniform()})
    out = tmp_path / campaign.name
    run_campaign(campaign, out)
    text = build_report(out).read_text()
    assert ("Over the 40 cases" in text) == (method == "saltelli")  # 12 lhs cases: one by one
    assert "## Global sensitivity" in text and "log-uniform [10, 1000]" in text
    assert ("S1_conf" in text) == (method == "saltelli")
    assert ("gives no indices" in text) == (method == "lhs")
    assert (out / f"sampled_{method}.png").is_file()
    assert "## Sensitivities" not in text  # no finite differences along the sample rows


def test_validate_shows_the_design_not_its_rows(tmp_path, capsys):
    from study.cli import main

    path = tmp_path / "design.toml"
    path.write_text(
        """
[base]
body1 = { behaviour = "elastic", radius = 0.01, E = 210e9, nu = 0.3 }
body2 = { behaviour = "rigid" }
load = { normal_force = 100.0 }
grid = { n = [16, 16] }

[sample]
method = "morris"
count = 5
"load.normal_force" = { distribution = "log-uniform", range = [10.0, 1000.0] }
"body1.radius" = { distribution = "discrete", values = [0.005, 0.01] }
"""
    )
    assert main(["validate", str(path)]) == 0
    text = capsys.readouterr().out
    assert "sample (morris design, count 5, seed 0, 15 values)" in text
    assert "log-uniform [10, 1000]" in text and "discrete 0.005, 0.01" in text
