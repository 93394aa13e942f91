"""The cost model (study.campaign.cost) and its calibration (study.run.calibration)."""

import copy
import heapq
import json
import logging
import math

import pytest
from study_fixtures import CATTANEO_BASE, small_campaign, write

import solver
import solver.drive.loops
from solver.case.substeps import load_substeps
from study.campaign import cost
from study.cli import load_campaign_file, main
from study.run import calibration as machine
from study.run.driver import RunOptions
from study.run.scheduler import Scheduler
from study.run.wisdom import machine_key

#: Made-up unit costs: what a fake calibration returns (no solves in most tests).
FAKE = cost.REFERENCE.scaled(2.0, 0.5, 1.5, machine=machine_key(), seconds=0.1, created="now")


@pytest.fixture
def cache(tmp_path, monkeypatch):
    """A fresh cache folder and a counting fake of :func:`cost.measure`."""
    monkeypatch.setenv("SLIPSTICK_CACHE", str(tmp_path / "cache"))
    calls = []

    def fake_measure(repeat=3):
        calls.append(repeat)
        return FAKE

    monkeypatch.setattr(machine, "measure", fake_measure)
    return calls


def rigid_on_steel(mu: float, n: int = 24, steps: int = 4, **grid) -> solver.Case:
    """A rigid sphere on elastic steel (beta = -0.29), frictionless or with friction ``mu``."""
    return solver.Case.from_dict(
        {
            "body1": {"radius": 0.015, "behaviour": "rigid"},
            "body2": {"radius": "inf", "behaviour": "elastic", "E": 210e9, "nu": 0.3},
            "load": {"hertz_pressure": 2e9, "steps": steps},
            "friction": {"coefficient": mu},
            "grid": {"n": n, **grid},
        }
    )


def plastic_fretting(mu: float, n: int = 16, steps: int = 3) -> solver.Case:
    """The fretting II scene (rigid sphere on Swift steel at 6 GPa) on a small box."""
    return solver.Case.from_dict(
        {
            "body1": {"radius": 0.015, "behaviour": "rigid"},
            "body2": {
                "radius": "inf",
                "behaviour": "elastic-plastic",
                "E": 210e9,
                "nu": 0.3,
                "hardening": {"law": "swift", "B": 945e6, "C": 20.0, "n": 0.121},
            },
            "load": {"hertz_pressure": 6e9, "steps": steps},
            "friction": {"coefficient": mu},
            "grid": {"n": [n, n, n]},
        }
    )


# -- counting ------------------------------------------------------------------------------------
@pytest.mark.parametrize("make", [rigid_on_steel, plastic_fretting])
def test_coupled_friction_costs_more_than_its_frictionless_twin(make):
    """beta != 0 with friction runs the slip-stick loop (and load sub-steps): costlier."""
    dry, rough = make(0.0), make(0.3)
    assert cost.features(rough)["coupled"] and not cost.features(dry)["slip_stick"]
    for units in (cost.REFERENCE, FAKE):
        assert cost.case_seconds(rough, units) > 2.0 * cost.case_seconds(dry, units)
    assert cost.reference_seconds(rough) > 2.0 * cost.reference_seconds(dry)


def test_counts_follow_cells_and_steps():
    """Frictionless elastic: CG iterations = cg x increments on Ns = 4 nx ny padded cells."""
    k = cost.COUNTS
    small, finer, longer = (
        rigid_on_steel(0.0),
        rigid_on_steel(0.0, n=48),
        rigid_on_steel(0.0, steps=8),
    )
    work = cost.count(small)
    assert work.surface_cells == 4 * 24 * 24 and work.plastic == 0.0 and work.volume_cells == 0
    assert work.normal == pytest.approx(k["cg"] * 4)
    assert cost.count(longer).normal == pytest.approx(2 * work.normal)
    assert cost.count(finer).surface_cells == 4 * work.surface_cells
    # seconds: set-up + build per cell + iterations x Ns log2 Ns
    units = cost.REFERENCE
    for case in (small, finer, longer):
        w = cost.count(case)
        ns = w.surface_cells
        expected = units.case + units.build * ns + units.normal * w.normal * ns * math.log2(ns)
        expected += units.iteration * w.normal
        assert cost.case_seconds(case, units) == pytest.approx(expected)
    assert cost.case_seconds(small) < cost.case_seconds(longer) < cost.case_seconds(finer)


def test_plastic_counts_grow_with_load_and_box():
    """More plasticity iterations past yield; the volume work grows with the box."""
    low, high = plastic_fretting(0.0), plastic_fretting(0.0)
    f = cost.features(low)
    assert f["plastic_bodies"] == 1 and f["box"] == [16, 16, 16]
    less = cost.count_features({**f, "pmax_over_flow": 2.0})
    more = cost.count_features({**f, "pmax_over_flow": 6.0})
    assert more.plastic > less.plastic >= f["steps"]  # at least one iteration per increment
    assert cost.count(high).volume_cells == 8 * 16**3
    bigger = cost.count(plastic_fretting(0.0, n=24))
    assert cost.seconds(bigger) > cost.seconds(cost.count(low))


def test_coupled_substeps_as_the_solver_adds_them(monkeypatch):
    """A coupled case's load sub-steps are counted as its solve adds them."""
    coarse, fine = rigid_on_steel(0.3, n=16, steps=2), rigid_on_steel(0.3, steps=40)
    assert cost.features(coarse)["substeps"] > cost.features(fine)["substeps"] >= 0
    assert cost.features(rigid_on_steel(0.0))["substeps"] == 0
    added = []

    def counted(*args, **kwargs):
        added.append(load_substeps(*args, **kwargs))
        return added[-1]

    monkeypatch.setattr(solver.drive.loops, "load_substeps", counted)
    assert solver.solve(coarse).status == "converged"
    assert sum(map(len, added)) == cost.features(coarse)["substeps"]


# -- campaign time -------------------------------------------------------------------------------
def dynamic_schedule(times: list[float], ranks: int) -> float:
    """The driver's hand-out simulated: costliest first, to whichever rank is free first."""
    clock = [(0.0, rank) for rank in range(ranks)]
    end = 0.0
    for value in sorted(times, reverse=True):
        free, rank = heapq.heappop(clock)
        heapq.heappush(clock, (free + value, rank))
        end = max(end, free + value)
    return end


@pytest.mark.parametrize("ranks", [1, 2, 3, 7])
def test_campaign_time_is_list_scheduling(ranks):
    times = [5.0, 1.0, 3.0, 3.0, 2.0, 8.0, 0.5, 4.0, 4.0, 1.5]
    assert cost.campaign_seconds(times, ranks) == pytest.approx(dynamic_schedule(times, ranks))
    assert cost.campaign_seconds(times, 1) == pytest.approx(sum(times))
    assert cost.campaign_seconds(times, 100) == pytest.approx(max(times))
    # rank 0 only dispatching: one computing rank fewer
    assert cost.campaign_seconds(times, 3, root_computes=False) == pytest.approx(
        dynamic_schedule(times, 2)
    )


# -- calibration cache ---------------------------------------------------------------------------
def test_calibration_is_written_reused_and_refreshed(cache, tmp_path):
    first = machine.calibration()
    path = machine.calibration_file()
    assert first == FAKE and len(cache) == 1 and path.is_file()
    assert path.parent.parent == tmp_path / "cache"  # the wisdom's cache folder
    assert machine.calibration() == FAKE and len(cache) == 1  # reused
    assert machine.load() == FAKE
    data = json.loads(path.read_text())
    for key, value in (("format", machine.FORMAT + 1), ("model", cost.MODEL + 1)):
        changed = {**data, key: value}
        path.write_text(json.dumps(changed))
        assert machine.load() is None
        machine.calibration()
        assert json.loads(path.read_text())[key] == data[key]  # measured again and rewritten
    assert len(cache) == 3
    path.write_text("{not json")
    assert machine.calibration() == FAKE and len(cache) == 4
    machine.calibration(recalibrate=True)
    assert len(cache) == 5


def test_unwritable_cache_still_gives_unit_costs(cache, tmp_path, monkeypatch, caplog):
    blocker = tmp_path / "file"
    blocker.write_text("")
    monkeypatch.setenv("SLIPSTICK_CACHE", str(blocker / "below"))
    with caplog.at_level(logging.WARNING, logger="test_cost"):
        assert machine.calibration(logger=logging.getLogger("test_cost")) == FAKE
    assert "not saved" in caplog.text


def test_measure_times_the_solver(monkeypatch, tmp_path):
    """The real calibration: positive, finite unit costs from small solves (a few seconds)."""
    monkeypatch.setenv("SLIPSTICK_CACHE", str(tmp_path))
    found = machine.measure(repeat=1, processes=1)
    for name in ("case", "build", "normal", "slip", "iteration", "passes", "plastic", "volume"):
        value = getattr(found, name)
        assert math.isfinite(value) and value > 0, name
    assert found.seconds > 0 and found.machine != "reference"
    machine.save(found)
    assert machine.load() == found


# -- validate and the driver ---------------------------------------------------------------------
MIXED = """
[campaign]
name = "frictions"

[sweep]
"friction.coefficient" = [0.0, 0.3]
"grid.n" = [16, 24]

[base]
body1 = { behaviour = "rigid", radius = 0.015 }
body2 = { behaviour = "elastic", radius = "inf", E = 210e9, nu = 0.3 }
load = { hertz_pressure = 2e9, steps = 2 }
"""


def test_validate_prints_seconds_and_the_campaign_time(cache, tmp_path, capsys):
    path = write(tmp_path, MIXED, "frictions.toml")
    assert main(["validate", str(path), "--ranks", "3"]) == 0
    out = capsys.readouterr().out
    campaign = load_campaign_file(path)
    times = [cost.case_seconds(c.case(), FAKE) for c in campaign.cases]
    wall = cost.campaign_seconds(times, 3)
    assert f"estimated campaign time on 3 rank(s): {wall:.4g} s" in out
    assert f"total {sum(times):.4g} s" in out and "estimated cost per case" in out
    first = max(campaign.cases, key=lambda c: cost.case_seconds(c.case(), FAKE))
    listed = [
        line.split()[0] for line in out.splitlines() if line.startswith("  ") and " s " in line
    ]
    assert listed[0] == first.case_id and first.coords["friction_coefficient"] == 0.3
    assert "calibration:" in out and len(cache) == 1
    assert main(["validate", str(path), "--recalibrate"]) == 0 and len(cache) == 2
    assert main(["validate", str(path), "--ranks", "0"]) == 2


def test_scheduler_orders_by_estimated_seconds(cache, tmp_path):
    campaign = load_campaign_file(write(tmp_path, MIXED, "frictions.toml"))
    scheduler = Scheduler(list(campaign.cases), RunOptions(), 0, logging.getLogger("test"))
    expected = {c.number: cost.case_seconds(c.case(), FAKE) for c in campaign.cases}
    assert scheduler.seconds == pytest.approx(expected)
    order = [c.number for c in scheduler.queue]
    assert order == sorted(expected, key=lambda number: (-expected[number], number))


def test_time_limit_uses_seconds_before_any_case(cache, tmp_path):
    """No case starts whose estimate (x 1.25) exceeds the time left, even the first one."""
    campaign = load_campaign_file(write(tmp_path, MIXED, "frictions.toml"))
    cases = list(campaign.cases)
    seconds = {c.number: cost.case_seconds(c.case(), FAKE) for c in cases}
    cheapest = min(seconds.values())
    options = RunOptions(time_limit=0.5 * cheapest, time_reserve=0.0, use_slurm_end_time=False)
    scheduler = Scheduler(cases, options, 0, logging.getLogger("test"))
    assert scheduler.next_task(0) is None and scheduler.stopped.startswith("time limit")
    # with room for the cheapest case only, that one starts first
    options = RunOptions(time_limit=1e4, time_reserve=0.0, use_slurm_end_time=False)
    scheduler = Scheduler(cases, options, 0, logging.getLogger("test"))
    scheduler.deadline = None
    first = scheduler.next_task(0)
    assert seconds[first.number] == max(seconds.values())
    # a finished case that took 10 x its estimate scales the later predictions
    scheduler.report(
        {
            "number": first.number,
            "case_id": first.case_id,
            "status": "converged",
            "case_time": 10 * seconds[first.number],
            "rank": 0,
        }
    )
    assert scheduler.rate == pytest.approx(10.0)


def test_small_campaign_cost_is_reference_seconds(tmp_path):
    """``CampaignCase.cost``: machine-independent, the seconds at the reference unit costs."""
    campaign = load_campaign_file(small_campaign(tmp_path))
    for case in campaign.cases:
        assert case.cost == pytest.approx(cost.reference_seconds(case.case()))
    cattaneo = copy.deepcopy(CATTANEO_BASE)
    assert "tangential_force" in cattaneo


@pytest.mark.parametrize("across", [16, 48])
def test_a_steady_creep_curve_is_priced_by_its_own_applications(across):
    """The predicted tangential applications of a steady stage (its own count, not a static
    increment's) within a factor 2 of what the solver records."""
    from study.bench.rolling import creepage, steady_table

    case = solver.Case.from_dict(steady_table(across, (creepage(1.0), 0.0), 2, 12))
    predicted = cost.count(case).slip
    measured = float(solver.solve(case).history["slip_iterations"].sum())
    assert 0.5 < predicted / measured < 2.0, (predicted, measured)
