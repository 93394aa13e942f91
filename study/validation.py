"""What ``python -m study validate`` prints: a campaign's summary, estimates and warnings.

:func:`describe_campaign` (axes, counts, estimated time and memory, the costliest cases),
the warnings of :func:`memory_warnings`, :func:`path_warnings` and :func:`case_warnings`,
and :class:`ProgressLine` for a long expansion.  Imports no MPI.
"""

from __future__ import annotations

import heapq
import os
import sys
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from .campaign import Campaign


def stderr_notes():
    """A logger whose messages go to stderr as they are (what ``validate`` is doing)."""
    import logging

    notes = logging.getLogger("study.validate")
    if not notes.handlers:
        handler = logging.StreamHandler(sys.stderr)
        handler.setFormatter(logging.Formatter("%(message)s"))
        notes.addHandler(handler)
        notes.setLevel(logging.INFO)
        notes.propagate = False
    return notes


#: Load increments of a case past which ``validate`` warns (each is a contact solve, plastic
#: cases several, and a row of every history).
LONG_PATH = 10_000


def path_warnings(campaign: Campaign, limit: int = LONG_PATH) -> list[str]:
    """A warning (one line) when cases' load paths are longer than ``limit`` increments.

    The accepted maximum is :data:`solver.keys.MAX_INCREMENTS`; a long path is valid but costs
    a solve per increment, so the line says how many cases, the longest and what to change.
    """
    from solver.case.path import path_steps
    from solver.case.wear import solved_cycles

    steps = [path_steps(c.spec["load"]["path"], solved_cycles(c.spec)) for c in campaign.cases]
    long = [s for s in steps if s > limit]
    if not long:
        return []
    longest = max(range(len(steps)), key=steps.__getitem__)
    case = campaign.cases[longest]
    return [
        f"warning: {len(long)} of {len(steps)} cases have load paths of more than {limit:,} "
        f"increments; the longest, {case.case_id} [{case.label}], has {steps[longest]:,} "
        "(each increment is a contact solve, several for a plastic body, and a row of every "
        "history): fewer steps per stage or fewer cycles give the same path coarser"
    ]


def case_warnings(campaign: Campaign, shown: int = 5) -> list[str]:
    """One line per distinct case warning (:attr:`solver.Case.warnings`), the first ``shown``.

    A line names the first case that has it and how many have it; a last line counts the
    warnings not shown.
    """
    seen: dict[str, list] = {}
    for case in campaign.cases:
        for text in case.warnings:
            seen.setdefault(text, []).append(case)
    lines = [
        f"warning: {len(cases)} of {len(campaign.cases)} case(s), e.g. {cases[0].case_id} "
        f"[{cases[0].label}]: {text}"
        for text, cases in list(seen.items())[:shown]
    ]
    if len(seen) > shown:
        lines.append(f"warning: {len(seen) - shown} more case warnings like these")
    return lines


class ProgressLine:
    """``progress(done, total)`` for a campaign expansion: its rate and time left, now and then.

    Silent for an expansion that will take less than :attr:`delay` seconds (every small
    campaign).  A longer one is told at the first call (the cases checked per second so far and
    the time the rest will take at that rate), then every :attr:`every` seconds, and a last line
    gives the total time.

    Parameters
    ----------
    stream : file, optional
        Where the lines go (default stderr).
    say : callable, optional
        ``say(line)`` instead of printing (a run's logger on rank 0).
    """

    delay = 3.0
    every = 10.0

    def __init__(self, stream=None, say=None):
        import time

        self._clock = time.monotonic
        self._start = self._clock()
        self._next = self._start
        self._say = say or (lambda line: print(line, file=stream or sys.stderr, flush=True))
        self._shown = False

    def __call__(self, done: int, total: int) -> None:
        """Say a line when one is due (never for the last call: :meth:`finish` says it)."""
        from .run.progress import format_duration

        now = self._clock()
        if done <= 0 or done >= total or now < self._next:
            return
        elapsed = now - self._start
        left = elapsed * (total - done) / done
        if not self._shown and elapsed + left < self.delay:
            return
        self._next = now + self.every
        self._shown = True
        rate = f", {done / elapsed:.0f} cases/s" if elapsed > 0 else ""
        self._say(
            f"validating: {done}/{total} cases ({100 * done // total} %) in "
            f"{format_duration(elapsed)}{rate}: about {format_duration(left)} left"
        )

    def finish(self) -> None:
        """Say how long it took, if any progress line was shown."""
        from .run.progress import format_duration

        if self._shown:
            self._say(f"validating: done in {format_duration(self._clock() - self._start)}")


def machine_memory() -> int | None:
    """Total memory of this machine (bytes): MemTotal of /proc/meminfo, else sysconf."""
    try:
        with open("/proc/meminfo") as handle:
            for line in handle:
                if line.startswith("MemTotal:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    try:
        return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (AttributeError, OSError, ValueError):
        return None


def memory_warnings(campaign: Campaign, total: int | None, cores: int | None) -> list[str]:
    """Warnings (one line per situation) when cases need more memory than the machine has.

    Every MPI rank holds one case at a time, so a rank needs the largest case's estimate
    (:meth:`solver.Case.memory_estimate`); the ranks per node are not known at validation,
    so the lines say what one rank needs and how many such ranks this machine holds.

    Parameters
    ----------
    campaign : Campaign
        The validated campaign.
    total : int or None
        This machine's total memory (bytes), :func:`machine_memory`; None: no warning.
    cores : int or None
        This machine's cores.
    """
    if not total or not campaign.cases:
        return []
    gib = 2.0**30
    largest = max(campaign.cases, key=lambda c: c.memory)
    need = largest.memory
    which = f"{largest.case_id} [{largest.label}]"
    if need > total:
        count = sum(1 for c in campaign.cases if c.memory > total)
        return [
            f"warning: {count} of {len(campaign.cases)} cases need more memory than this "
            f"machine has: the largest, {which}, needs ~{need / gib:.1f} GiB, the machine "
            f"{total / gib:.1f} GiB in total; each MPI rank holds one case at a time and "
            f"needs ~{need / gib:.1f} GiB, so run them on nodes with more than that per rank"
        ]
    fits = int(total // need)
    if cores and fits < cores:
        return [
            f"warning: the largest case, {which}, needs ~{need / gib:.1f} GiB; each MPI rank "
            f"holds one case at a time and needs ~{need / gib:.1f} GiB, so this machine's "
            f"{total / gib:.1f} GiB holds {fits} such rank(s), fewer than its {cores} cores: "
            f"start at most {fits} rank(s) per node of this size (or ask the scheduler for "
            f"~{need / gib:.1f} GiB per rank)"
        ]
    return []


def _seconds(value: float) -> str:
    """Seconds, and in minutes and hours too past a minute."""
    from .run.progress import format_duration

    return f"{value:.4g} s" + (f" ({format_duration(value)})" if value >= 60 else "")


def describe_campaign(
    campaign: Campaign,
    list_cases: bool = False,
    ranks: int | None = None,
    calibration=None,
) -> str:
    """Text summary of a campaign: axes, case count, estimated seconds and memory.

    Parameters
    ----------
    campaign : Campaign
        The validated campaign.
    list_cases : bool
        List every case (else the costliest 20).
    ranks : int, optional
        MPI ranks for the campaign's estimated time (default: this machine's cores).
    calibration : study.campaign.cost.Calibration, optional
        Unit costs (default: this machine's, :func:`study.run.calibration.calibration`).

    Returns
    -------
    str
        The summary; seconds are CPU seconds of one core of the calibrated machine.
    """
    from .campaign import cost, format_value
    from .campaign.sample import SAMPLE_DIM
    from .run import calibration as machine

    cases = campaign.distinct_cases()  # a design's repeated rows: one case, solved once
    count = f"{len(campaign.cases)} cases"
    if len(cases) < len(campaign.cases):
        count = f"{len(campaign.cases)} rows of {len(cases)} distinct cases (each solved once)"
    lines = [
        f"campaign {campaign.name} ({campaign.source or 'table'}): {count}, "
        f"shape {' x '.join(map(str, campaign.shape)) or '() (one case, no axes)'}, "
        f"output {campaign.settings.output}",
        "axes:" if campaign.axes else "axes: none (no [sweep], [zip] or [sample]: the base case)",
    ]
    design = campaign.design
    spread = {} if design is None else dict(zip(design.keys, design.distributions, strict=True))
    for axis in campaign.axes:
        kind = "zip" if axis.zipped else "sweep"
        if axis.name == SAMPLE_DIM and design is not None:
            kind = f"{design.method} design, count {design.count}, seed {design.seed}"
        lines.append(f"  {axis.name} ({kind}, {axis.size} values)")
        for c in axis.coordinates:
            if axis.name == SAMPLE_DIM and c.key in spread:
                values = spread[c.key].describe()
            else:
                values = ", ".join(format_value(v) for v in c.values)
            units = f" [{c.units}]" if c.units else ""
            lines.append(f"    {c.name} = {c.key}{units}: {values}")
    calibration = calibration or machine.calibration()
    ranks = ranks or os.cpu_count() or 1
    seconds = {}
    for c in cases:
        try:
            seconds[c.number] = cost.seconds(c.estimated_work(), calibration)
        except Exception:  # noqa: BLE001 - a case the model cannot read: its reference cost
            seconds[c.number] = float(c.cost)
    times = list(seconds.values())
    memory = [c.memory for c in cases]
    total = sum(times)
    wall = cost.campaign_seconds(times, ranks)
    lines.append(
        "estimated cost per case (seconds on one core of this machine, study.campaign.cost: "
        f"a count of solves and iterations x calibrated unit costs): min {min(times):.3g} s, "
        f"max {max(times):.3g} s, total {_seconds(total)}"
    )
    wisdom = any(c.spec["solver"]["fft_planner"] == "wisdom" for c in cases)
    lines.append(
        f"estimated campaign time on {ranks} rank(s): {_seconds(wall)} (costliest first onto "
        "the least-loaded rank, rank 0 computing too; MPI start-up and the dataset's assembly "
        "on top"
        + ('; and the FFT plans of fft_planner = "wisdom", measured once per grid)' if wisdom
           else ")")
    )  # fmt: skip
    lines.append(f"calibration: {machine.describe_calibration(calibration)}")
    lines.append(
        f"estimated memory per case: min {min(memory) / 2**20:.1f} MiB, "
        f"max {max(memory) / 2**20:.1f} MiB"
    )

    def costliest(case) -> tuple[float, int]:
        return -seconds[case.number], case.number

    if not list_cases and len(cases) > 20:
        lines.append("costliest 20 cases (--list for all):")
        shown = heapq.nsmallest(20, cases, key=costliest)
    else:
        shown = sorted(cases, key=costliest)
        lines.append("cases, costliest first:")
    for c in shown:
        lines.append(
            f"  {c.case_id}  {seconds[c.number]:9.3g} s  memory {c.memory / 2**20:7.1f} MiB  "
            f"{c.label}"
        )
    lines.append("valid")
    return "\n".join(lines)
