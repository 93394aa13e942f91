"""Scheduling on rank 0: the queue of cases, their reports, the stopping rules.

Cases are handed out costliest first by their estimated seconds on this machine
(:mod:`study.campaign.cost`, calibrated here); with a time limit a case starts only when it is
predicted to end in time; when the first k cases of a run all fail no new case starts.
"""

from __future__ import annotations

import bisect
import logging
import os
import threading
import time

from ..campaign import CampaignCase, cost
from . import calibration
from .progress import Progress


def estimated_seconds(cases: list[CampaignCase], logger: logging.Logger) -> dict[int, float]:
    """Case number -> estimated seconds on this machine (:mod:`.cost`, calibrated here).

    A case whose estimate fails keeps its reference estimate (``CampaignCase.cost``: seconds
    at the reference machine's unit costs); an estimate never stops a run.
    """
    try:
        units = calibration.calibration(logger=logger) if cases else cost.REFERENCE
    except Exception as error:  # noqa: BLE001 - the estimate orders cases, no more
        logger.warning("cost calibration unavailable (%s): reference unit costs", error)
        units = cost.REFERENCE
    found = {}
    for case in cases:
        try:
            found[case.number] = cost.seconds(case.estimated_work(), units)
        except Exception:  # noqa: BLE001
            found[case.number] = float(case.cost)
    return found


class Scheduler:
    """The queue of cases (costliest first), the reports, and the stopping rules.  Thread-safe.

    Cases are ordered by their estimated seconds on this machine (:func:`.cost.case_seconds`).
    With a time limit a case starts only when 1.25 x its estimate, times the largest ratio of
    measured to estimated time of the cases finished so far (1 before the first), fits in the
    time left; a case asked for ahead, while the rank still computes its previous one, must
    fit after that one too (its estimate scaled the same way).

    Parameters
    ----------
    todo : list of CampaignCase
        The cases to run.
    options : study.run.driver.RunOptions
        Its ``time_limit``, ``time_reserve`` and ``use_slurm_end_time``.
    max_initial_failures : int
        Stop starting cases when the first k cases all failed (0: never).
    logger : logging.Logger
        Where failures and the stop are said.
    """

    def __init__(
        self,
        todo: list[CampaignCase],
        options,
        max_initial_failures: int,
        logger: logging.Logger,
    ):
        self.seconds = estimated_seconds(todo, logger)
        # cheapest first, the next case at the end: handing one out is a pop from the end,
        # and the estimates ascend, so the costliest case that fits a time limit is a bisection
        self._stack = sorted(todo, key=lambda c: (self.seconds[c.number], -c.number))
        self._keys = [self.seconds[c.number] for c in self._stack]
        self.options = options
        self.max_initial_failures = max_initial_failures
        self.logger = logger
        self.lock = threading.Lock()
        self.running: dict[int, CampaignCase] = {}
        self.last: dict[int, int] = {}  # rank -> the number of the case handed to it last
        self.busy: set[int] = set()  # ranks with a case not reported (computing)
        self.reports: dict[str, dict] = {}  # case id -> report
        self.stopped = ""
        self.successes = 0
        self.failures = 0
        # largest measured / estimated seconds of the finished cases (None: none yet)
        self.rate: float | None = None
        self.progress = Progress(len(self._stack), sum(self.seconds.values()), logger)
        self.deadline = self._deadline()

    def _deadline(self) -> float | None:
        now = time.perf_counter()
        limits = []
        if self.options.time_limit is not None:
            limits.append(now + self.options.time_limit)
        end = os.environ.get("SLURM_JOB_END_TIME")
        if self.options.use_slurm_end_time and end:
            try:
                limits.append(now + float(end) - time.time())
            except ValueError:
                self.logger.warning("ignoring SLURM_JOB_END_TIME=%r (not a number)", end)
        return min(limits) if limits else None

    @property
    def queue(self) -> list[CampaignCase]:
        """The cases not handed out yet, in hand-out order (costliest first)."""
        return self._stack[::-1]

    def next_task(self, rank: int) -> CampaignCase | None:
        """The next case for ``rank``, or None when there is none to start.

        Time per call: O(log n) in the cases left (plus a pop near the end of a list).
        """
        with self.lock:
            if self.stopped or not self._stack:
                return None
            pick = len(self._stack) - 1
            if self.deadline is not None:
                left = self.deadline - time.perf_counter() - self.options.time_reserve
                scale = 1.25 * (1.0 if self.rate is None else self.rate)
                current = self.last.get(rank)
                if current in self.running:  # asked ahead: starts when that case ends
                    left -= scale * self.seconds[current]
                if scale > 0.0:  # the costliest case with scale x its estimate < left
                    pick = bisect.bisect_left(self._keys, left / scale) - 1
                if pick < 0:
                    self.stopped = (
                        f"time limit: {max(left, 0.0):.0f} s left before the reserve, too little "
                        f"for the {len(self._stack)} remaining case(s); re-run to resume"
                    )
                    self.logger.warning("%s", self.stopped)
                    return None
            case = self._stack.pop(pick)
            del self._keys[pick]
            self.running[case.number] = case
            self.last[rank] = case.number
            self.busy.add(rank)
            return case

    def report(self, report: dict) -> None:
        """Record the report of a finished case (and the cases its writer lost)."""
        lost = report.pop("lost", [])
        with self.lock:
            case = self.running.pop(report["number"])
            if self.last.get(report["rank"]) == case.number:  # none asked for ahead
                self.busy.discard(report["rank"])
            self.reports[case.case_id] = report
            if report["status"] == "failed":
                self.failures += 1
                self._warn_failed(case.case_id, report)
            else:
                self.successes += 1
                estimate = self.seconds[case.number]
                if estimate > 0:
                    ratio = report["case_time"] / estimate
                    self.rate = ratio if self.rate is None else max(self.rate, ratio)
            self.progress.update(report, self.seconds[case.number], len(self.busy))
            k = self.max_initial_failures
            if k and not self.stopped and self.successes == 0 and self.failures >= k:
                self.stopped = (
                    f"the first {self.failures} cases of this run all failed (last: "
                    f"{report.get('error', '?')}); fix the campaign and re-run "
                    "(max_initial_failures = 0 disables this stop)"
                )
                self.logger.error("stopping: %s", self.stopped)
        self.lose(lost)

    def lose(self, lost: list[dict]) -> None:
        """Count failed the cases whose bundle could not be written (:meth:`.CaseWriter.flush`)."""
        with self.lock:
            for item in lost:
                report = self.reports.get(item["case_id"])
                if report is None:
                    continue
                if report["status"] != "failed":
                    self.successes -= 1
                    self.failures += 1
                report.update(
                    status="failed", error=item["error"], failure_record=item["failure_record"]
                )
                self._warn_failed(item["case_id"], report)

    def _warn_failed(self, case_id: str, report: dict) -> None:
        self.logger.warning(
            "case %s [%s] failed on rank %s (%s): %s; %s",
            case_id,
            report["label"],
            report["rank"],
            report["host"],
            report.get("error", ""),
            "its failure record: python -m study status"
            if report.get("failure_record", True)
            else "no failure record was written",
        )
