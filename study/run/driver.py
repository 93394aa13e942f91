"""Campaign driver: dynamic distribution of cases over MPI ranks, failure isolation, restarts.

Rank 0 reads the campaign, every rank builds and checks a share of its cases, and rank 0 joins
them and broadcasts the campaign, or the error that stops every rank
(:func:`broadcast_campaign`).  :func:`run_campaign` then hands out the unfinished cases
costliest first (estimated seconds, :mod:`study.campaign.cost`) with a root/worker loop over
point-to-point messages: a worker sends a request carrying the report of its previous case
and receives the next case number, or None to stop.  After a case that succeeded in less than
:data:`AHEAD_BELOW` a worker asks for its next case as it starts one, so the answer waits for
it when it is done (the dispatcher's polling and the message's trip are hidden behind short
cases; long ones keep the costliest-first balance).  On rank 0 a dispatcher thread answers
the requests (polling with short sleeps, so it costs no core) while the main thread computes
cases too, so the root is not idle on small runs; the dispatcher's MPI calls are the only ones
while it runs (``MPI_THREAD_SERIALIZED`` suffices).

Each case is solved, checked for NaN/inf (a history's declaration may admit a documented
infinity or a not-computed NaN: :meth:`solver.variables.History.admits`), and kept by the rank
that computed it, which writes its finished cases as one bundle every few seconds
(:class:`.writer.CaseWriter`).  An exception
or a non-finite result makes the case *failed*: its traceback, rank and host go into the bundle
as its failure record (``python -m study status`` shows them) and the campaign goes on;
non-convergence is a result (status ``not_converged``).  When the first k cases of a run all
fail (k = ``max_initial_failures``) no new case starts.  With a time limit (or Slurm's
``SLURM_JOB_END_TIME``) a case is only started when it is predicted to finish in time; the
others stay pending for the next run.

The communicator is an argument (None: serial); only the command line names COMM_WORLD.
"""

from __future__ import annotations

import contextlib
import copy
import logging
import math
import os
import signal
import socket
import threading
import time
import traceback
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

import solver
from solver.numerics import fftw
from solver.variables import HISTORIES

from .. import bundle
from ..bundle import Entry
from ..campaign import MAX_CASE_TIMEOUT, Campaign, CampaignCase, CampaignError, Progress
from ..campaign.expand import Expansion, Part, Spread, collector_paused, serial
from ..campaign.surfaces import read_surface
from . import storage, wisdom
from .assemble import case_summary, profile_coordinate
from .progress import LOGGER_NAME, format_duration
from .scheduler import Scheduler
from .writer import BUNDLE_SECONDS, MAX_BUNDLE_SECONDS, CaseWriter, case_record, warm_up

_REQUEST, _TASK = 71, 72
#: A worker whose last case succeeded in less than this (s) asks for its next case while it
#: computes one: the wait for the answer is hidden behind the case.  After a longer case or a
#: failure it asks when done, so that the last cases of a run go to whichever rank is free
#: (costliest first) and a stop rule acts at once.
AHEAD_BELOW = 1.0

#: Exit status of a run that stopped at its time limit with cases left (re-run to resume).
EXIT_INCOMPLETE = 3


class NonFiniteResult(RuntimeError):
    """A solve returned NaN or infinite values."""


class CaseTimeout(RuntimeError):
    """A case ran longer than its time limit."""


def check_case_timeout(seconds: float | None, name: str = "case_timeout") -> None:
    """Raise :class:`CampaignError` unless ``seconds`` is None or in (0, MAX_CASE_TIMEOUT]."""
    if seconds is None:
        return
    if not (isinstance(seconds, int | float) and 0 < seconds <= MAX_CASE_TIMEOUT):
        raise CampaignError(
            f"{name}: must be a number of seconds in (0, {MAX_CASE_TIMEOUT:g}] (leave it out "
            f"for no timeout), got {seconds!r}"
        )


@contextlib.contextmanager
def _time_limit(seconds: float | None):
    """Raise :class:`CaseTimeout` in the block after ``seconds`` (main thread only, POSIX)."""
    if (
        not seconds
        or not 0 < seconds <= MAX_CASE_TIMEOUT  # refused by validation; never overflow here
        or threading.current_thread() is not threading.main_thread()
        or not hasattr(signal, "setitimer")
    ):
        yield
        return

    def expire(signum, frame):
        raise CaseTimeout(f"the case ran longer than its time limit of {seconds:g} s")

    previous = signal.signal(signal.SIGALRM, expire)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


@dataclass(frozen=True)
class RunOptions:
    """How to run a campaign.

    Attributes
    ----------
    fft_threads : int, optional
        FFTW threads per rank; overrides ``[campaign] fft_threads``.  Applied at run time only:
        the case ids (file names) keep the campaign's specification, so a re-run with another
        thread count resumes.
    case_timeout : float, optional
        Seconds after which a case is abandoned as failed (default ``[campaign]
        case_timeout``; none).  Uses SIGALRM, so it works where cases run in the main thread
        (all ranks here).
    max_initial_failures : int, optional
        Stop starting cases when the first k cases of this run all failed (0: never); default
        ``[campaign] max_initial_failures``.
    time_limit : float, optional
        Seconds this run may take; no case is started that is predicted to end later.
    time_reserve : float
        Seconds kept free before the time limit (and before ``SLURM_JOB_END_TIME``) for
        assembly and shutdown.
    use_slurm_end_time : bool
        Also respect ``SLURM_JOB_END_TIME`` (epoch seconds) when it is set.
    root_computes : bool
        Rank 0 computes cases too (in its main thread, beside the dispatcher thread).
    replace : bool
        Run into an output folder that holds another campaign (another name), replacing its
        ``campaign.json``; refused otherwise (:func:`study.run.storage.prepare_output`).
    poll_interval : float
        Longest sleep (s) of the dispatcher between checks for requests.
    bundle_seconds : float
        Longest time (s) a rank keeps finished cases in memory before writing them as a bundle
        (:class:`.writer.CaseWriter`): a crash loses at most this much finished work per rank.
    solve : callable, optional
        The solve function (default :func:`solver.solve`); tests inject failures with it.
    """

    fft_threads: int | None = None
    case_timeout: float | None = None
    max_initial_failures: int | None = None
    time_limit: float | None = None
    time_reserve: float = 10.0
    use_slurm_end_time: bool = True
    root_computes: bool = True
    replace: bool = False
    poll_interval: float = 0.005
    bundle_seconds: float = BUNDLE_SECONDS
    solve: Callable | None = None


@dataclass
class RunSummary:
    """Outcome of :func:`run_campaign` (the same on every rank).

    Attributes
    ----------
    campaign, out : str
        Campaign name and output folder.
    total : int
        Cases in the campaign.
    skipped : int
        Cases finished by earlier runs (not recomputed).
    converged, not_converged, truncated, surface_flow, failed : int
        Cases of this run by outcome (:attr:`solver.Result.status`).
    pending : int
        Cases with neither a (complete) result nor a failure (recorded, or of this run) at
        the end.
    failed_total : int
        Cases whose latest attempt failed (this run or an earlier one), at the end; a case of
        this run whose failure record could not be written (a full disk) counts too.
    stopped : str
        Why the run stopped starting cases early ("" when it ran out of cases).
    elapsed : float
        Wall time of the run (s).
    per_rank : dict
        Cases computed by each rank.
    overhead : float
        Mean time (s) per case spent outside the solve on the computing rank (case set-up,
        checks, dataset building, compressed atomic write); NaN when no case was solved (and
        not said in :meth:`describe`).
    """

    campaign: str
    out: str
    total: int
    skipped: int = 0
    converged: int = 0
    not_converged: int = 0
    truncated: int = 0
    surface_flow: int = 0
    failed: int = 0
    pending: int = 0
    failed_total: int = 0
    stopped: str = ""
    elapsed: float = 0.0
    per_rank: dict = field(default_factory=dict)
    overhead: float = 0.0

    @property
    def exit_status(self) -> int:
        """0 all cases finished; 1 failures or an early stop; 3 cases left by the time limit."""
        if self.failed_total or (self.stopped and not self.stopped.startswith("time")):
            return 1
        if self.pending:
            return EXIT_INCOMPLETE
        return 0

    def describe(self) -> str:
        """One-paragraph summary for the log."""
        ranks = ", ".join(f"rank {r}: {n}" for r, n in sorted(self.per_rank.items()))
        cut = (
            f"{self.truncated} truncated (the plastic zone at a face of its box, or the contact "
            "at the surface domain's edge: each case's notes say which), "
            if self.truncated
            else ""
        )
        if self.surface_flow:
            cut += f"{self.surface_flow} surface flow (the surface shear past the body's limit), "
        overhead = "" if math.isnan(self.overhead) else f"overhead {self.overhead:.4f} s per case; "
        text = (
            f"campaign {self.campaign}: {self.total} cases; this run {self.converged} converged, "
            f"{self.not_converged} not converged, {cut}{self.failed} failed; {self.skipped} "
            f"finished earlier; {self.pending} pending, {self.failed_total} failed in all; elapsed "
            f"{format_duration(self.elapsed)} ({ranks or 'no cases computed'}); {overhead}"
            f"output {self.out}"
        )
        if self.stopped:
            text += f"\nstopped early: {self.stopped}"
        return text


# -- the cases built on every rank, joined on rank 0, then broadcast ---------------------------
def broadcast_campaign(load: Callable[[Spread], Campaign | None], comm=None) -> Campaign | None:
    """Load and validate a campaign with every rank's help; broadcast it (or its error).

    Rank 0 calls ``load(spread)``: it reads the file, and the cases are built by every rank,
    a share each (:data:`study.campaign.expand.Spread`; 10^5 cases take tens of seconds in
    one process), then joined and checked on rank 0.  The other ranks wait asleep in between.

    Parameters
    ----------
    load : callable
        ``load(spread)`` returns the campaign (or None), raising :class:`CampaignError` for a
        bad file; called on rank 0, it passes ``spread`` to
        :func:`study.campaign.load_campaign`.
    comm : mpi4py communicator, optional
        None for a serial run.

    Returns
    -------
    Campaign or None
        On every rank: what ``load`` returned.

    Raises
    ------
    CampaignError
        On every rank, with rank 0's message, when the campaign is bad.
    """
    with collector_paused():  # 10^5 cases unpickled, a tenth of the time without its passes
        return _broadcast(load, comm)


def _broadcast(load: Callable[[Spread], Campaign | None], comm) -> Campaign | None:
    """:func:`broadcast_campaign`'s work, with the cyclic garbage collector paused."""
    if comm is None or comm.Get_size() == 1:
        return load(serial)
    if comm.Get_rank() != 0:
        while True:
            _quiet_barrier(comm)  # asleep while rank 0 reads and joins
            message = comm.bcast(None, root=0)
            if message[0] != "part":
                break
            comm.gather(_safe_part(*message[1:], comm.Get_rank()), root=0)
        if message[0] == "error":
            raise CampaignError(message[1])
        return message[1]

    def spread(expansion: Expansion, progress: Progress | None) -> list[Part]:
        n = min(comm.Get_size(), max(1, expansion.total // MIN_RANK_CASES))
        _quiet_barrier(comm)
        comm.bcast(("part", expansion, n), root=0)
        parts = comm.gather(_safe_part(expansion, n, 0, progress), root=0)
        for k, part in enumerate(parts[:n]):
            if isinstance(part, str):
                raise RuntimeError(f"building share {k} of {n} of the cases: {part}")
        return parts[:n]

    original: BaseException | None = None
    try:
        payload: tuple = ("ok", load(spread))
    except CampaignError as error:
        payload = ("error", str(error))
    except Exception as error:  # a bug must not leave the other ranks waiting
        original = error
        payload = ("error", f"{type(error).__name__}: {error}")
    _quiet_barrier(comm)
    comm.bcast(payload, root=0)
    if original is not None:
        raise original
    if payload[0] == "error":
        raise CampaignError(payload[1])
    return payload[1]


#: Fewest cases per rank worth a share of the expansion (a share costs a message each way).
MIN_RANK_CASES = 100


def _safe_part(
    expansion: Expansion, n: int, k: int, progress: Progress | None = None
) -> Part | str | None:
    """Share ``k`` of ``n`` (None past ``n``), or the text of the error that stopped it."""
    if k >= n:
        return None
    try:
        return expansion.part(k, n, progress)
    except Exception as error:  # every rank must reach the gather
        return f"{type(error).__name__}: {error}"


# -- one case ------------------------------------------------------------------------------------
def solver_case(case: CampaignCase, fft_threads: int | None = None) -> solver.Case:
    """The case to solve: the campaign case with the run's FFT threads (when given)."""
    spec = case.spec
    threads = fft_threads or spec["solver"].get("fft_threads", 1)
    if threads != spec["solver"].get("fft_threads", 1):
        spec = copy.deepcopy(spec)
        spec["solver"]["fft_threads"] = threads
    return solver.Case.from_dict(spec, read_surface)


def _non_finite(result: solver.Result) -> list[str]:
    """Names of the result's arrays holding NaN or inf that their declaration does not admit.

    A history declared with an infinity or a not-computed value
    (:meth:`solver.variables.History.admits`: the kinematic bound not solved, inf) keeps it.
    """
    arrays = {
        "pressure": result.pressure,
        "shear_x": result.shear_x,
        "shear_y": result.shear_y,
    }
    bad = [name for name, values in arrays.items() if not np.all(np.isfinite(values))]
    for name, values in result.history.items():
        declared = HISTORIES.get(name)
        ok = declared.admits(values) if declared is not None else np.isfinite(values)
        if not np.all(ok):
            bad.append(f"history {name}")
    return bad


def run_case(
    campaign: Campaign,
    case: CampaignCase,
    writer: CaseWriter,
    *,
    rank: int = 0,
    fft_threads: int | None = None,
    solve: Callable | None = None,
    timeout: float | None = None,
) -> dict[str, Any]:
    """Solve one case and hand its result (or failure record) to the rank's writer.

    Never raises ``Exception``.

    Parameters
    ----------
    campaign : Campaign
        The campaign (settings).
    case : CampaignCase
        The case.
    writer : CaseWriter
        This rank's bundle writer (:mod:`study.run.writer`).
    rank : int
        This rank (reported).
    fft_threads : int, optional
        FFTW threads for this solve (not part of the case id).
    solve : callable, optional
        Solve function, default :func:`solver.solve`.
    timeout : float, optional
        Seconds after which the solve is abandoned (the case fails with :class:`CaseTimeout`).

    Returns
    -------
    dict
        Report: number, case_id, label, status (converged, not_converged, truncated, failed),
        rank, host, case_time (s, including this rank's share of the writing) and solve_time
        (s), error (one line, when failed), lost (the cases whose bundle could not be written,
        :meth:`.CaseWriter.flush`).
    """
    start = time.perf_counter()
    started = storage.now()
    host = socket.gethostname()
    report: dict[str, Any] = {
        "number": case.number,
        "case_id": case.case_id,
        "label": case.label,
        "rank": rank,
        "host": host,
        "solve_time": 0.0,
    }
    logger = logging.getLogger(LOGGER_NAME)
    logger.debug("case %s [%s] starts", case.case_id, case.label)
    storage.reset_peak_rss()  # peak_rss: this case's peak, not the rank's earlier cases
    try:
        with warnings.catch_warnings(record=True) as caught, _time_limit(timeout):
            warnings.simplefilter("default")  # each warning once per place and case
            to_solve = solver_case(case, fft_threads)
            result = (solve or solver.solve)(to_solve)
        bad = _non_finite(result)
        if bad:
            raise NonFiniteResult(f"NaN or inf in the result: {', '.join(bad)}")
        report["solve_time"] = float(result.wall_time)
        history = result.history
        attrs = storage.case_provenance(
            case,
            started=started,
            finished=storage.now(),
            solve_time=float(result.wall_time),
            time_before_write=time.perf_counter() - start,
            fft_threads=int(to_solve.solver.fft_threads),
            peak_rss=storage.peak_rss_bytes(),
            normal_iterations_total=_total(history, "normal_iterations"),
            slip_iterations_total=_total(history, "slip_iterations"),
            coupling_iterations_total=_total(history, "coupling_iterations"),
            warnings="; ".join(sorted({f"{w.category.__name__}: {w.message}" for w in caught}))[
                :2000
            ],
        )
        record = case_record(result, campaign.settings.fields, {**writer.shared, **attrs})
        summary = case_summary(record, profile_coordinate(campaign.settings))
        entry = Entry(case.case_id, result.status, record=record, summary=summary)
        report["status"] = result.status
        report["notes"] = "; ".join(result.notes)
    except Exception as error:
        report["status"] = "failed"
        report["error"] = f"{type(error).__name__}: {error}".splitlines()[0][:500]
        failure = {
            "case_id": case.case_id,
            "coordinates": case.coords,
            "error": f"{type(error).__name__}: {error}",
            "traceback": traceback.format_exc(),
            "rank": rank,
            "host": host,
            "pid": os.getpid(),
            "started": started,
            "elapsed": time.perf_counter() - start,
            "slipstick_version": solver.__version__,
            "spec": case.spec,
        }
        entry = Entry(case.case_id, "failed", failure=failure)
        report["failure_record"] = True
        logger.debug("case %s failed: %s", case.case_id, report["error"])
    report["lost"] = writer.add(entry)
    report["case_time"] = time.perf_counter() - start
    return report


def _total(history: dict, name: str) -> int:
    return int(np.sum(history[name])) if name in history else 0


# -- the run -------------------------------------------------------------------------------------
def run_campaign(
    campaign: Campaign,
    out: str | Path,
    comm=None,
    options: RunOptions | None = None,
    logger: logging.Logger | None = None,
) -> RunSummary:
    """Compute every unfinished case of a campaign, distributed over the ranks of ``comm``.

    Call it on every rank of ``comm`` with the same campaign (see :func:`broadcast_campaign`).

    Parameters
    ----------
    campaign : Campaign
        The validated campaign.
    out : str or Path
        Output folder (shared by all ranks).
    comm : mpi4py communicator, optional
        None (or a size-1 communicator) runs serially.
    options : RunOptions, optional
        Run settings.
    logger : logging.Logger, optional
        Default: the ``study`` logger.

    Returns
    -------
    RunSummary
        The same on every rank.

    Raises
    ------
    CampaignError
        On every rank, when rank 0 cannot prepare the output folder.
    """
    options = options or RunOptions()
    logger = logger or logging.getLogger(LOGGER_NAME)
    rank = comm.Get_rank() if comm is not None else 0
    size = comm.Get_size() if comm is not None else 1
    out = Path(out)
    start = time.perf_counter()
    fft_threads = options.fft_threads or campaign.settings.fft_threads
    k = options.max_initial_failures
    if k is None:
        k = campaign.settings.max_initial_failures

    timeout = options.case_timeout or campaign.settings.case_timeout
    check_case_timeout(timeout)  # the same on every rank: all raise together
    if not 0.0 <= options.bundle_seconds <= MAX_BUNDLE_SECONDS:  # NaN included
        raise CampaignError(
            f"bundle_seconds: must be in [0, {MAX_BUNDLE_SECONDS:g}] seconds, got "
            f"{options.bundle_seconds!r}"
        )

    warm_up()  # the storage library's import, before the time limit's clock starts
    scheduler = None
    message: tuple = ("ok", None)
    if rank == 0:
        try:
            storage.prepare_output(out, campaign, replace=options.replace)
            _quarantine_corrupt(campaign, out, logger)
            finished = storage.finished_ids(out)
            todo = [c for c in campaign.distinct_cases() if c.case_id not in finished]
            scheduler = Scheduler(todo, options, k, logger)
            distinct = len(campaign.distinct_cases())
            logger.info(
                "campaign %s: %d cases, %d finished earlier, %d to run on %d rank(s)%s -> %s",
                campaign.name,
                distinct,
                distinct - len(todo),
                len(todo),
                size,
                "" if size == 1 or options.root_computes else " (rank 0 dispatches only)",
                out,
            )
        except CampaignError as error:
            message = ("error", str(error))
    if size > 1:
        _quiet_barrier(comm)  # asleep while rank 0 reads the folder and orders the cases
        message = comm.bcast(message, root=0)
    if message[0] == "error":
        raise CampaignError(message[1])
    _share_wisdom(comm, scheduler, fft_threads, logger)

    shared = storage.run_provenance(campaign, rank=rank, size=size)
    writer = CaseWriter(out, shared, seconds=options.bundle_seconds)

    def compute(case: CampaignCase) -> dict:
        return run_case(
            campaign,
            case,
            writer,
            rank=rank,
            fft_threads=fft_threads,
            solve=options.solve,
            timeout=timeout,
        )

    if size == 1:
        _serve_self(scheduler, compute, writer)
    elif rank == 0:
        root_computes = options.root_computes and _threads_allowed()
        if not root_computes and options.root_computes:
            logger.warning("MPI thread support below SERIALIZED: rank 0 only dispatches")
        _root(comm, scheduler, compute, writer, root_computes, options.poll_interval)
    else:
        _worker(comm, campaign, compute, writer)

    summary = None
    if rank == 0:
        summary = _summarise(campaign, out, scheduler, time.perf_counter() - start)
    if size > 1:
        _quiet_barrier(comm)
        summary = comm.bcast(summary, root=0)
    if rank == 0:
        logger.info("%s", summary.describe())
    return summary


def _share_wisdom(comm, scheduler, fft_threads: int | None, logger: logging.Logger) -> None:
    """Every rank imports the same FFTW wisdom before its first case (``fft_planner = "wisdom"``).

    Rank 0 loads this machine's, measures the plans of the grids it lacks and saves it
    (:func:`.wisdom.prepare`), then hands it to the others.  A failure costs the measured plans
    (estimate ones everywhere instead), never the campaign.
    """
    data = None
    if scheduler is not None:  # rank 0
        try:
            cases = [  # only those that ask for measured plans
                solver_case(case, fft_threads)
                for case in scheduler.queue
                if case.spec["solver"]["fft_planner"] == "wisdom"
            ]
            data = wisdom.prepare(cases, logger)
        except Exception as error:  # noqa: BLE001 - the plans are an optimisation
            logger.warning("FFT plans not measured (%s): estimate plans instead", error)
    if comm is not None and comm.Get_size() > 1:
        _quiet_barrier(comm)  # asleep while rank 0 measures plans
        data = comm.bcast(data, root=0)
        if comm.Get_rank() != 0 and data is not None:
            fftw.import_wisdom(data)


def _quarantine_corrupt(campaign: Campaign, out: Path, logger: logging.Logger) -> None:
    """Move corrupt bundles and the campaign's corrupt case files aside, to be computed again."""
    wanted = {case.case_id: case for case in campaign.cases}
    for name, problem in sorted(storage.corrupt_ids(out).items()):
        is_bundle = name.endswith(bundle.SUFFIX)
        if not is_bundle and name not in wanted:
            continue
        what = f"bundle {name}" if is_bundle else f"case {name} [{wanted[name].label}]"
        try:
            moved = storage.quarantine(out, name)
        except OSError as error:
            raise CampaignError(
                f"{storage.cases_dir(out)}: corrupt {what} ({problem}) that cannot be moved "
                f"aside: {error.strerror or error}"
            ) from None
        logger.warning(
            "%s: corrupt, %s; moved to cases/%s, computing %s again",
            what,
            problem,
            moved.name,
            "its cases" if is_bundle else "it",
        )


def _serve_self(scheduler: Scheduler, compute: Callable, writer: CaseWriter) -> None:
    """Compute cases from the queue until it is empty, then write what the writer keeps."""
    try:
        while (case := scheduler.next_task(0)) is not None:
            scheduler.report(compute(case))
    finally:
        scheduler.lose(writer.flush())


def _threads_allowed() -> bool:
    try:
        from mpi4py import MPI

        return MPI.Query_thread() >= MPI.THREAD_SERIALIZED
    except Exception:
        return False


def _root(
    comm, scheduler: Scheduler, compute: Callable, writer: CaseWriter, computes: bool, poll: float
) -> None:
    workers = comm.Get_size() - 1
    if not computes:
        _dispatch(comm, scheduler, workers, poll)
        return
    failure: list[BaseException] = []

    def dispatcher() -> None:
        try:
            _dispatch(comm, scheduler, workers, poll)
        except BaseException as error:  # never leave the workers waiting
            failure.append(error)
            logging.getLogger(LOGGER_NAME).critical(
                "dispatcher failed, aborting: %s", traceback.format_exc()
            )
            comm.Abort(1)

    thread = threading.Thread(target=dispatcher, name="study-dispatcher", daemon=True)
    thread.start()
    _serve_self(scheduler, compute, writer)
    thread.join()
    if failure:
        raise failure[0]


def _dispatch(comm, scheduler: Scheduler, workers: int, poll: float) -> None:
    """Answer the workers' requests until each has sent its final message.

    A request is ``(reports, lost, final)``: the reports of the worker's cases finished since
    its last request, the cases its writer lost, and whether the worker is done (it has
    written what it kept, after it was told to stop).  Every other request gets one answer.
    """
    from mpi4py import MPI

    status = MPI.Status()
    active = workers
    sleep = 0.0002
    while active:
        if not comm.Iprobe(source=MPI.ANY_SOURCE, tag=_REQUEST, status=status):
            time.sleep(sleep)
            sleep = min(2.0 * sleep, poll)
            continue
        sleep = 0.0002
        source = status.Get_source()
        reports, lost, final = comm.recv(source=source, tag=_REQUEST)
        for report in reports:
            scheduler.report(report)
        scheduler.lose(lost)
        if final:
            active -= 1
            continue
        case = scheduler.next_task(source)
        comm.send(None if case is None else case.number, dest=source, tag=_TASK)


def _worker(comm, campaign: Campaign, compute: Callable, writer: CaseWriter) -> None:
    """Compute the cases rank 0 hands out, then send the final message (:func:`_dispatch`).

    The request for the next case goes out as a case starts when the case before succeeded in
    less than :data:`AHEAD_BELOW`, else when the case is done; either way a request carries
    the reports not sent yet.
    """
    by_number = {case.number: case for case in campaign.cases}
    unsent: list[dict] = []

    def ask():
        comm.send((unsent[:], [], False), dest=0, tag=_REQUEST)
        unsent.clear()
        return comm.irecv(source=0, tag=_TASK)

    last = None
    ahead = ask()
    try:
        while (number := ahead.wait()) is not None:
            ahead = None
            if last is not None and last["status"] != "failed" and last["case_time"] < AHEAD_BELOW:
                ahead = ask()
            last = compute(by_number[number])
            unsent.append(last)
            if ahead is None:
                ahead = ask()
        ahead = None
    finally:
        comm.send((unsent, writer.flush(), True), dest=0, tag=_REQUEST)
        if ahead is not None:  # answered before the final message is read (same source)
            ahead.wait()


def _quiet_barrier(comm, interval: float = 0.01) -> None:
    """A barrier that sleeps while it waits (a blocking one spins a core in MPICH)."""
    request = comm.Ibarrier()
    while not request.Test():
        time.sleep(interval)


def _summarise(campaign: Campaign, out: Path, scheduler: Scheduler, elapsed: float) -> RunSummary:
    finished, failed = storage.finished_ids(out), storage.failed_ids(out)
    ids = {c.case_id for c in campaign.cases}
    reports = list(scheduler.reports.values())
    # a failure of this run counts even when its record could not be written (a full disk)
    failed = (failed | {r["case_id"] for r in reports if r["status"] == "failed"}) - finished
    per_rank: dict[int, int] = {}
    for report in reports:
        per_rank[report["rank"]] = per_rank.get(report["rank"], 0) + 1
    computed = [r for r in reports if r["status"] != "failed"]
    overhead = (
        sum(r["case_time"] - r["solve_time"] for r in computed) / len(computed)
        if computed
        else math.nan
    )
    return RunSummary(
        campaign=campaign.name,
        out=str(out),
        total=len(ids),
        skipped=len(ids) - scheduler.progress.total,
        converged=sum(r["status"] == "converged" for r in reports),
        not_converged=sum(r["status"] == "not_converged" for r in reports),
        truncated=sum(r["status"] == "truncated" for r in reports),
        surface_flow=sum(r["status"] == "surface_flow" for r in reports),
        failed=sum(r["status"] == "failed" for r in reports),
        pending=len(ids - finished - failed),
        failed_total=len(ids & failed),
        stopped=scheduler.stopped,
        elapsed=elapsed,
        per_rank=per_rank,
        overhead=overhead,
    )
