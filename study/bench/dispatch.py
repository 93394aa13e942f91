"""The campaign dispatcher's throughput: how many requests per second rank 0 answers.

A worker rank asks rank 0 for its next case once per case (:mod:`study.run.driver`); rank 0's
dispatcher thread answers one request at a time, so it caps a campaign's case rate.  Two
measurements, with the driver's own functions and scheduler:

- ``mpi`` (run under ``mpiexec -n K``): the real protocol over MPI, rank 0 dispatching only,
  ``K - 1`` workers whose cases take ``case_seconds`` (0: they return at once) and write
  nothing.  Prints the cases per second of the whole run.  Oversubscribed ranks on a small
  machine share its cores with the dispatcher, so this is a lower bound of its capacity.
- ``standin`` (one process): the dispatcher serves ``workers`` simulated ranks through a
  stand-in communicator that always has a request waiting and pickles every message both
  ways, as mpi4py's lowercase calls do.  What is left out is the transport: a small message
  costs microseconds on shared memory or InfiniBand, measured by ``mpi``'s ping-pong.  Prints
  rank 0's time per request, hence the rate it sustains, for queues of different lengths, with
  and without a time limit (which makes the scheduler look for a case that fits).

``python -m study.bench.dispatch standin`` and ``mpiexec -n 8 python -m study.bench.dispatch
mpi``; ``docs/dispatcher.py`` runs both over a range of ranks and writes the table.
"""

from __future__ import annotations

import argparse
import json
import logging
import os
import pickle
import sys
import time
from types import SimpleNamespace

from ..campaign.cost import Work
from ..campaign.model import CampaignCase
from ..run import driver
from ..run.scheduler import Scheduler

_REQUEST, _TASK = driver._REQUEST, driver._TASK


def synthetic_cases(count: int) -> list[CampaignCase]:
    """``count`` cases with an id, a position and a tiny predicted work (nothing to solve)."""
    work = Work(1024, 0, 1, 10.0, 0.0, 0.0, 0.0)
    return [
        CampaignCase(i, (i,), {"sample": i}, {}, f"{i:016x}", 1e-3, 0, work=work)
        for i in range(count)
    ]


def _logger() -> logging.Logger:
    """A progress logger that formats and writes every line, to the null device."""
    logger = logging.getLogger("study.bench.dispatch")
    if not logger.handlers:
        handler = logging.StreamHandler(open(os.devnull, "w"))  # noqa: SIM115 - process-long
        handler.setFormatter(logging.Formatter("%(asctime)s %(levelname)s %(message)s"))
        logger.addHandler(handler)
        logger.setLevel(logging.INFO)
        logger.propagate = False
    return logger


def _report(case: CampaignCase, rank: int) -> dict:
    return {
        "number": case.number,
        "case_id": case.case_id,
        "label": case.label,
        "rank": rank,
        "host": "bench",
        "solve_time": 0.0,
        "status": "converged",
        "case_time": 0.0,
        "lost": [],
    }


# -- over MPI --------------------------------------------------------------------------------------
def run_mpi(count: int, case_seconds: float, comm) -> dict | None:
    """The protocol over MPI: rank 0 dispatches ``count`` cases to the other ranks.

    Returns (on rank 0) the elapsed time, cases per second and the ping-pong time of a small
    message between ranks 0 and 1; None on the others.
    """
    rank, size = comm.Get_rank(), comm.Get_size()
    cases = synthetic_cases(count)
    pingpong = _pingpong(comm)
    comm.Barrier()
    if rank == 0:
        scheduler = Scheduler(cases, driver.RunOptions(), 0, _logger())
        start = time.perf_counter()
        driver._dispatch(comm, scheduler, size - 1, driver.RunOptions().poll_interval)
        elapsed = time.perf_counter() - start
        done = len(scheduler.reports)
        return {
            "ranks": size,
            "cases": done,
            "elapsed": elapsed,
            "rate": done / elapsed,
            "pingpong_us": 1e6 * pingpong,
            "case_seconds": case_seconds,
        }
    writer = SimpleNamespace(flush=lambda: [])

    def compute(case: CampaignCase) -> dict:
        if case_seconds:
            time.sleep(case_seconds)
        return _report(case, rank)

    driver._worker(comm, SimpleNamespace(cases=cases), compute, writer)
    return None


def _pingpong(comm, rounds: int = 2000) -> float:
    """Seconds of one small-message round trip between ranks 0 and 1 (pickled, as the driver)."""
    rank = comm.Get_rank()
    message = ([{"number": 1, "case_id": "0" * 16, "status": "converged"}], [], False)
    comm.Barrier()
    start = time.perf_counter()
    for _ in range(rounds):
        if rank == 0:
            comm.send(message, dest=1, tag=_REQUEST)
            comm.recv(source=1, tag=_TASK)
        elif rank == 1:
            comm.recv(source=0, tag=_REQUEST)
            comm.send(1, dest=0, tag=_TASK)
    return (time.perf_counter() - start) / rounds


# -- the stand-in ----------------------------------------------------------------------------------
class StandIn:
    """A communicator for ``driver._dispatch``: ``workers`` ranks, a request always waiting.

    Each request carries the report of the rank's previous case (pickled, as mpi4py sends it);
    each answer is pickled too.  A rank told to stop sends its final message next.
    """

    def __init__(self, workers: int, cases: list[CampaignCase]):
        self.workers = workers
        self.by_number = {case.number: case for case in cases}
        self.previous: dict[int, int | None] = dict.fromkeys(range(1, workers + 1))
        self.stopping: set[int] = set()
        self.turn = 0
        self.requests = 0

    def Iprobe(self, source=None, tag=None, status=None) -> bool:  # noqa: N802 - mpi4py's name
        """A request is always waiting: from the next rank in turn."""
        self.turn = self.turn % self.workers + 1
        status.Set_source(self.turn)  # an mpi4py Status: the dispatcher reads its source
        return True

    def recv(self, source: int, tag: int):
        """The rank's request: the report of its previous case, or its final message."""
        self.requests += 1
        number = self.previous[source]
        reports = [] if number is None else [_report(self.by_number[number], source)]
        final = source in self.stopping
        return pickle.loads(pickle.dumps((reports, [], final)))

    def send(self, number, dest: int, tag: int) -> None:
        """The answer: the rank's next case number, or None to stop."""
        number = pickle.loads(pickle.dumps(number))
        if number is None:
            self.stopping.add(dest)
        self.previous[dest] = number


def run_standin(count: int, workers: int, time_limit: float | None) -> dict:
    """Rank 0's time per request serving ``workers`` simulated ranks ``count`` cases."""
    cases = synthetic_cases(count)
    options = driver.RunOptions(time_limit=time_limit, use_slurm_end_time=False)
    scheduler = Scheduler(cases, options, 0, _logger())
    comm = StandIn(workers, cases)
    start = time.perf_counter()
    driver._dispatch(comm, scheduler, workers, 0.0)
    elapsed = time.perf_counter() - start
    return {
        "workers": workers,
        "cases": count,
        "handed_out": sorted(report["number"] for report in scheduler.reports.values()),
        "time_limit": time_limit,
        "requests": comm.requests,
        "per_request_us": 1e6 * elapsed / comm.requests,
        "rate": comm.requests / elapsed,
    }


def main(argv: list[str] | None = None) -> int:
    """``standin`` or ``mpi``; prints one JSON line per measurement."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("mode", choices=["standin", "mpi"])
    parser.add_argument("--cases", type=int, nargs="+", default=[10000])
    parser.add_argument("--workers", type=int, default=999, help="standin: simulated ranks")
    parser.add_argument("--time-limit", type=float, help="standin: the run's time limit (s)")
    parser.add_argument("--case-seconds", type=float, default=0.0, help="mpi: each case's time")
    args = parser.parse_args(argv)
    if args.mode == "standin":
        for count in args.cases:
            found = run_standin(count, args.workers, args.time_limit)
            found["handed_out"] = len(found["handed_out"])
            print(json.dumps(found), flush=True)
        return 0
    from mpi4py import MPI

    for count in args.cases:
        found = run_mpi(count, args.case_seconds, MPI.COMM_WORLD)
        if found is not None:
            print(json.dumps(found), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
