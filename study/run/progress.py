"""Rank-aware logging and the campaign progress line.

Every log line carries ``[rank/size]``; non-root ranks log warnings only unless asked to be
verbose.  :class:`Progress` prints one line per finished case on the root (cases done/total,
failures, elapsed, ETA), which reads well in a batch log: no carriage returns, no bars.
"""

from __future__ import annotations

import logging
import sys
import time

LOGGER_NAME = "study"


class _RankFilter(logging.Filter):
    def __init__(self, rank: int, size: int):
        super().__init__()
        self.tag = f"{rank}/{size}"

    def filter(self, record: logging.LogRecord) -> bool:
        record.rank = self.tag
        return True


def configure_logging(rank: int = 0, size: int = 1, verbose: bool = False) -> logging.Logger:
    """Set up the ``study`` logger for this rank and return it.

    Parameters
    ----------
    rank, size : int
        This process's rank and the communicator size.
    verbose : bool
        Debug output on every rank (default: info on rank 0, warnings elsewhere).
    """
    logger = logging.getLogger(LOGGER_NAME)
    for handler in list(logger.handlers):
        logger.removeHandler(handler)
    handler = logging.StreamHandler(sys.stdout)
    handler.addFilter(_RankFilter(rank, size))
    handler.setFormatter(
        logging.Formatter("%(asctime)s [%(rank)s] %(levelname)s %(message)s", "%H:%M:%S")
    )
    logger.addHandler(handler)
    logger.propagate = False
    if verbose:
        logger.setLevel(logging.DEBUG)
    else:
        logger.setLevel(logging.INFO if rank == 0 else logging.WARNING)
    return logger


def format_duration(seconds: float) -> str:
    """``1h02m03s`` / ``2m03s`` / ``4.2s``."""
    if seconds != seconds or seconds == float("inf"):
        return "?"
    if seconds < 60:
        return f"{seconds:.1f}s"
    minutes, secs = divmod(int(round(seconds)), 60)
    hours, minutes = divmod(minutes, 60)
    return f"{hours}h{minutes:02d}m{secs:02d}s" if hours else f"{minutes}m{secs:02d}s"


class Progress:
    """Counts finished cases and estimates the time left from their estimated costs.

    Parameters
    ----------
    total : int
        Cases this run has to compute.
    total_cost : float
        Sum of their cost estimates.
    logger : logging.Logger
        Where progress lines go (rank 0).
    """

    def __init__(self, total: int, total_cost: float, logger: logging.Logger):
        self.total = total
        self.total_cost = total_cost
        self.logger = logger
        self.start = time.perf_counter()
        self.done = 0
        self.failed = 0
        self.cost_done = 0.0

    @property
    def elapsed(self) -> float:
        """Seconds since the start."""
        return time.perf_counter() - self.start

    def eta(self) -> float:
        """Seconds left, assuming time proportional to estimated cost."""
        if self.done >= self.total:
            return 0.0
        if self.cost_done <= 0:
            return float("nan")
        return self.elapsed * (self.total_cost - self.cost_done) / self.cost_done

    def update(self, report: dict, cost: float, running: int) -> None:
        """Record a finished case and log the progress line."""
        self.done += 1
        self.cost_done += cost
        failed = report["status"] == "failed"
        self.failed += failed
        detail = report["status"]
        if failed:
            detail += f" ({report.get('error', '')})"
        self.logger.info(
            "%d/%d done, %d failed, %d running | elapsed %s, ETA %s | case %s [%s] %s "
            "in %.2fs on rank %s%s",
            self.done,
            self.total,
            self.failed,
            running,
            format_duration(self.elapsed),
            format_duration(self.eta()),
            report["case_id"],
            report.get("label", ""),
            detail,
            report.get("case_time", float("nan")),
            report.get("rank", "?"),
            # the solver's notes (warnings, path dependence): shown, not only in the case file
            f" | notes: {report['notes']}" if report.get("notes") else "",
        )
