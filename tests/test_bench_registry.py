"""The benchmark scenes' options: each scene takes only the options it has."""

from __future__ import annotations

import pytest

from study.bench import registry
from study.bench import shakedown as bench_shakedown


@pytest.mark.parametrize(
    ("scene", "option"),
    [
        ("hertz", {"incremental": True}), ("hertz", {"periodic": True}),
        ("rolling", {"error": True}), ("rolling", {"repeat": 0}), ("hertz", {"repeat": -1}),
        ("rough", {"error": True}),
    ],
)  # fmt: skip
def test_an_option_a_scene_does_not_take_is_refused_by_name(scene, option):
    with pytest.raises(ValueError, match="--" + next(iter(option))):
        registry.run_benchmark(scene, [8], **option)


def test_the_shakedown_scene_solves_its_campaign_case_by_the_theorem():
    """The first case of campaigns/shakedown_map.toml, by Melan's theorem: its verdict."""
    from study.campaign import load_campaign

    item = load_campaign(bench_shakedown.CAMPAIGN).cases[0]
    case = item.case()
    out = bench_shakedown._theorem(case.to_dict())
    assert out["status"] == "converged" and out["first_yield"] < out["lower"] <= out["upper"]
    p0k = case.reference.max_pressure / (case.body2.hardening.yield_stress / 3**0.5)
    assert p0k == pytest.approx(2.0, rel=1e-6)  # mu = 0.1 at p_0 = 2 k: below first yield
    assert bench_shakedown._verdict(p0k, out) == "elastic"
    assert bench_shakedown._verdict(3.0, out) == "shakes down"  # first yield < 3 k <= lower bound
    assert bench_shakedown._verdict(5.0, out) == "does not shake down"


@pytest.mark.parametrize(
    "argv",
    [
        ["bench", "rolling", "--steady", "--shapes", "7", "--sizes", "4"],
        ["bench", "rolling", "--shapes", "0.5", "--sizes", "4"],
        ["bench", "hertz", "--shapes", "0.5"],
    ],
)
def test_an_option_a_scene_does_not_take_is_one_line_and_status_2(argv, capsys):
    from study.cli import main

    assert main(argv) == 2
    error = capsys.readouterr().err
    assert error.startswith("error: --shapes") and error.count("\n") == 1


def test_a_periodic_pass_too_coarse_to_slide_a_cell_is_refused_by_name():
    with pytest.raises(ValueError, match="^--sizes: .* give 16 cells a period or more, got 8"):
        registry.run_benchmark("moving", [8, 64], periodic=True)


@pytest.mark.parametrize(
    ("option", "message"),
    [
        ({"travel": 0.5}, "^--travel: only moving --periodic"),
        ({"periodic": True, "travel": 1.5}, r"^--travel: .* in \[1/8192, 1\] .* got 1.5"),
        ({"periodic": True, "travel": 5e-324}, r"^--travel: .* got 4.94066e-324"),
        ({"periodic": True, "travel": 0.0}, r"^--travel: .* got 0"),
        ({"periodic": True, "travel": 0.25}, "^--sizes: .* 0.25 of the period .* give 4 cells"),
    ],
)
def test_the_travel_of_a_periodic_pass_is_checked_by_name(option, message):
    """A whole pass is --travel 1; any other scene, a travel outside [1/8192, 1], or a travel the
    sizes cannot slide a cell an increment is refused before anything runs."""
    with pytest.raises(ValueError, match=message):
        registry.run_benchmark("moving", [2], **option)


def test_a_table_whose_first_row_failed_keeps_the_other_rows_columns():
    from study.bench.timing import format_table

    table = format_table([{"n": 16, "status": "error: x"}, {"n": 32, "cpu_s": 1.5, "status": "ok"}])
    header, _, failed, ran = table.splitlines()
    assert header == "| n | status | cpu_s |"
    assert failed == "| 16 | error: x | - |" and ran == "| 32 | ok | 1.5 |"
