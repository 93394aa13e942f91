"""The dispatcher on rank 0 (study.run.driver, study.run.scheduler) under many ranks."""

import logging

import pytest

from study.bench import dispatch
from study.campaign import cost
from study.run import scheduler as scheduler_module
from study.run.driver import RunOptions
from study.run.scheduler import Scheduler


@pytest.fixture(autouse=True)
def _reference_units(monkeypatch):
    """Estimates at the reference unit costs: no calibration of this machine."""
    monkeypatch.setattr(scheduler_module.calibration, "calibration", lambda **_: cost.REFERENCE)


@pytest.mark.parametrize("time_limit", [None, 1e6])
def test_every_case_is_handed_out_once_to_many_ranks(time_limit):
    found = dispatch.run_standin(500, 37, time_limit)
    assert found["handed_out"] == list(range(500))
    assert found["requests"] == 500 + 2 * 37  # a request per case, a first one, a final one


def test_the_costliest_case_that_fits_the_time_left_starts(monkeypatch):
    """The bisection picks what a scan of the queue (costliest first) would pick."""
    cases = dispatch.synthetic_cases(300)
    seconds = {c.number: float((7 * c.number) % 50) for c in cases}  # ties included
    monkeypatch.setattr(scheduler_module, "estimated_seconds", lambda todo, logger: seconds)
    options = RunOptions(time_limit=1e6, time_reserve=0.0, use_slurm_end_time=False)
    scheduler = Scheduler(cases, options, 0, logging.getLogger("test"))
    order = [c.number for c in scheduler.queue]
    assert order == sorted(seconds, key=lambda n: (-seconds[n], n))
    for rank, left in enumerate((1e6, 30.0, 12.6, 1.3, 0.5)):  # idle ranks
        scheduler.deadline = scheduler_module.time.perf_counter() + left
        fits = [c for c in scheduler.queue if 1.25 * seconds[c.number] < left]
        picked = scheduler.next_task(rank)
        if not fits:
            assert picked is None and scheduler.stopped.startswith("time limit")
            break
        assert picked.number == fits[0].number


def test_a_case_asked_for_ahead_must_fit_after_the_one_running(monkeypatch):
    """A rank computing a case gets the next only if both fit the time left, one after the other."""
    cases = dispatch.synthetic_cases(4)
    seconds = {0: 10.0, 1: 8.0, 2: 4.0, 3: 1.0}
    monkeypatch.setattr(scheduler_module, "estimated_seconds", lambda todo, logger: seconds)
    options = RunOptions(time_limit=1e6, time_reserve=0.0, use_slurm_end_time=False)
    scheduler = Scheduler(cases, options, 0, logging.getLogger("test"))
    scheduler.deadline = scheduler_module.time.perf_counter() + 20.0
    first = scheduler.next_task(1)  # 1.25 x 10 s fits in 20 s
    assert first.number == 0 and scheduler.busy == {1}
    ahead = scheduler.next_task(1)  # after 12.5 s: 7.5 s left, 1.25 x 4 s fits, 1.25 x 8 s not
    assert ahead.number == 2
    other = scheduler.next_task(2)  # an idle rank: 20 s left, the costliest that fits
    assert other.number == 1 and scheduler.busy == {1, 2}
    report = dispatch._report(first, 1)
    scheduler.report(report)
    assert scheduler.busy == {1, 2}  # rank 1 goes on with the case it asked for ahead
    scheduler.report(dispatch._report(ahead, 1))
    assert scheduler.busy == {2}
