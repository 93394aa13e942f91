"""Command line: ``python -m study {run,validate,status,assemble,report,bench} ...``.

``run`` works serially (``python -m study run FILE``) and under MPI
(``mpiexec -n N python -m study run FILE``); ``validate``, ``status`` and ``assemble`` never
import mpi4py.  Exit status: 0 success; 1 failed cases (or an early stop); 2 a bad campaign
file or command line (one message, no traceback); 3 the time limit left cases pending.
"""

from __future__ import annotations

import argparse
import os
import stat
import sys
from typing import TYPE_CHECKING

from .validation import (  # noqa: F401 - LONG_PATH: study.cli still exports it
    LONG_PATH,
    ProgressLine,
    case_warnings,
    describe_campaign,
    machine_memory,
    memory_warnings,
    path_warnings,
    stderr_notes,
)

if TYPE_CHECKING:
    from .campaign import Campaign
    from .run.driver import RunOptions

#: Environment variables that show the process was started by an MPI launcher.
_LAUNCHER_VARIABLES = (
    "PMI_RANK",
    "PMI_SIZE",
    "PMIX_RANK",
    "OMPI_COMM_WORLD_SIZE",
    "MV2_COMM_WORLD_SIZE",
    "MPI_LOCALNRANKS",
    "SLURM_STEP_NUM_TASKS",
)


def _single_threaded_blas() -> None:
    """One BLAS/OpenMP thread per process: ranks own the cores, and idle BLAS threads stall."""
    for name in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ.setdefault(name, "1")


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of ``python -m study``."""
    from .run.writer import BUNDLE_SECONDS

    parser = argparse.ArgumentParser(
        prog="python -m study", description="slipstick parametric studies and benchmarks"
    )
    sub = parser.add_subparsers(dest="command", required=True)

    run = sub.add_parser(
        "run",
        help="run a campaign (serially, or under mpiexec/srun)",
        description="Run every unfinished case of a campaign, then assemble the dataset. "
        "Each rank writes its finished cases as one bundle (cases/*.bundle.h5) every few "
        "seconds.  Finished cases are skipped and failed ones retried, so re-running resumes; "
        "a corrupt bundle or case file (one that does not open or lacks its completion marker) "
        "is moved aside to <file>.corrupt and its cases computed again.  An output folder "
        "belongs to one campaign (by name): running another campaign into it is refused "
        "unless --replace is given. "
        "Exit status 0 done, 1 failed cases, 2 bad campaign, 3 time limit left cases pending.",
    )
    run.add_argument("campaign", help="campaign file (.toml)")
    run.add_argument("--out", help="output folder (default: [campaign] output or out/<name>)")
    run.add_argument("--fft-threads", type=int, help="FFTW threads per rank (run-time only)")
    run.add_argument(
        "--time-limit",
        type=float,
        metavar="SECONDS",
        help="start no case predicted to end after this many seconds (also honours "
        "SLURM_JOB_END_TIME); unstarted cases stay pending",
    )
    run.add_argument(
        "--time-reserve",
        type=float,
        default=10.0,
        metavar="SECONDS",
        help="seconds kept free before the time limit (default 10)",
    )
    run.add_argument(
        "--bundle-seconds",
        type=float,
        default=BUNDLE_SECONDS,
        metavar="SECONDS",
        help="a rank writes its finished cases as one bundle at least this often: a crash "
        f"loses at most this much finished work per rank (default {BUNDLE_SECONDS:g}; 0: every "
        "case at once)",
    )
    run.add_argument(
        "--case-timeout",
        type=float,
        metavar="SECONDS",
        help="a case running longer fails; 0 < SECONDS <= 1e7 (default [campaign] "
        "case_timeout; none)",
    )
    run.add_argument(
        "--max-initial-failures",
        type=int,
        metavar="K",
        help="stop when the first K cases all fail (0: never; default [campaign] setting or 5)",
    )
    run.add_argument(
        "--mpi",
        choices=["auto", "on", "off"],
        default="auto",
        help="use MPI (auto: when started by an MPI launcher)",
    )
    run.add_argument(
        "--dedicated-root", action="store_true", help="rank 0 only dispatches, computes nothing"
    )
    run.add_argument(
        "--replace",
        action="store_true",
        help="run into an output folder that holds another campaign, replacing its "
        "campaign.json (its case files stay; cases the new campaign shares are reused)",
    )
    run.add_argument("--no-assemble", action="store_true", help="do not assemble at the end")
    run.add_argument("-v", "--verbose", action="store_true", help="debug output on every rank")

    validate = sub.add_parser(
        "validate",
        help="expand and validate a campaign without running it (no MPI)",
        description="Expand and validate every case; print the axes, the case count and the "
        "estimated seconds (per case on one core of this machine, and for the campaign on "
        "--ranks ranks) and memory per case; warn on stderr when the largest case needs more "
        "memory than this machine has (or than it has per core), with what one MPI rank "
        "needs; a progress line on stderr every 10 s for campaigns that take longer than 3 s "
        "to validate.  Exit status 2 for a bad campaign (one line on stderr).",
    )
    validate.add_argument("campaign", help="campaign file (.toml)")
    validate.add_argument("--list", action="store_true", help="list every case")
    validate.add_argument(
        "--ranks",
        type=int,
        default=None,
        metavar="N",
        help="MPI ranks for the campaign's estimated time (default: this machine's cores)",
    )
    validate.add_argument(
        "--recalibrate",
        action="store_true",
        help="measure this machine's solver speed again for the time estimates (a few "
        "seconds; otherwise the saved calibration, measured when missing or outdated)",
    )

    status = sub.add_parser(
        "status",
        help="show how far a campaign is",
        description="Count pending, converged, not converged, truncated and failed cases.",
    )
    status.add_argument("target", metavar="FILE_OR_OUT", help="campaign file or output folder")
    status.add_argument("--out", help="output folder (with a campaign file)")

    assemble = sub.add_parser(
        "assemble",
        help="(re)build OUT/<campaign>.nc from the stored cases",
        description="Assemble the campaign dataset from the finished cases stored under "
        "OUT/cases (the ranks' bundles, and per-case files of older runs).",
    )
    assemble.add_argument("target", metavar="FILE_OR_OUT", help="campaign file or output folder")
    assemble.add_argument("--out", help="output folder (with a campaign file)")

    bench = sub.add_parser(
        "bench",
        help="benchmarks against closed forms and peer codes",
        description="Run a benchmark scene: our solver against its closed form and, with "
        "--peers, the peer codes installed here, on the same grids; prints a table (time, "
        "CPU, memory, error, iterations).",
    )
    from .bench.registry import SCENES

    bench.add_argument("scene", choices=list(SCENES), help="benchmark scene")
    bench.add_argument("--sizes", type=int, nargs="+", help="grid sizes n (cells per side)")
    bench.add_argument("--peers", action="store_true", help="also run installed peer codes")
    bench.add_argument("--repeat", type=int, default=3, help="timing repetitions (best of)")
    bench.add_argument(
        "--error",
        action="store_true",
        help="plastic: also the error of each code against the converged value (a fit over "
        "our meshes: use 3 or more sizes) and the CPU each needs for 1 %% error",
    )
    bench.add_argument(
        "--periodic",
        action="store_true",
        help="rough: the periodic rough interface with plasticity (one period of a nominally "
        "flat surface) instead of the rough sphere",
    )
    bench.add_argument(
        "--incremental",
        action="store_true",
        help="shakedown: also solve the cases incrementally (four passes each: most of an hour "
        "a case past the surface limit) beside Melan's theorem",
    )
    bench.add_argument(
        "--steady",
        action="store_true",
        help="rolling: our steady state solved directly (steady = true stages) instead of the "
        "transient march, and a 50-point creep curve both ways",
    )
    bench.add_argument(
        "--shapes",
        type=float,
        nargs="+",
        metavar="A_OVER_B",
        help="rolling --steady: the contacts' semi-axis ratios a/b (default 1 0.5 2)",
    )
    bench.add_argument(
        "--travel",
        type=float,
        metavar="FRACTION",
        help="moving --periodic: the fraction of the period the rough pass slides (default "
        "1/16; 1 is a whole pass: over an hour of CPU at 256 cells a period)",
    )
    bench.add_argument(
        "--table",
        metavar="FILE",
        help="also write what the run prints to FILE (Markdown), headed by the command, the "
        "date, the machine and the commit, for the guide's benchmark pages",
    )
    from .report import add_parser as add_report_parser

    add_report_parser(sub)
    return parser


#: Test hook (tests/test_slurm.py): every case of a ``run`` takes at least this many seconds.
TEST_CASE_SECONDS = "SLIPSTICK_TEST_CASE_SECONDS"


def _test_solve():
    """The solve of a ``run`` under the :data:`TEST_CASE_SECONDS` hook, or None (the default).

    With ``SLIPSTICK_TEST_CASE_SECONDS=s`` each solve is followed by a sleep up to ``s`` seconds
    in all, counted in the case time (which predicts the next cases' durations) but not in the
    solve time written to the case file.  The Slurm tests use it to give cases a known duration
    on any machine, so that a job's real time limit stops the run after a known number of
    cases.  Not for production runs.
    """
    value = os.environ.get(TEST_CASE_SECONDS, "")
    if not value:
        return None
    seconds = float(value)
    import time

    import solver

    def solve(case):
        start = time.perf_counter()
        result = solver.solve(case)
        time.sleep(max(0.0, seconds - (time.perf_counter() - start)))
        return result

    return solve


def run_options(args: argparse.Namespace) -> RunOptions:
    """Driver options from parsed ``run`` arguments (shared with ``slurm/slices.py``)."""
    from .run.driver import RunOptions

    return RunOptions(
        fft_threads=args.fft_threads,
        case_timeout=args.case_timeout,
        max_initial_failures=args.max_initial_failures,
        time_limit=args.time_limit,
        time_reserve=args.time_reserve,
        bundle_seconds=getattr(args, "bundle_seconds", RunOptions.bundle_seconds),
        root_computes=not getattr(args, "dedicated_root", False),
        replace=getattr(args, "replace", False),
        solve=_test_solve(),
    )


def main(argv: list[str] | None = None) -> int:
    """Entry point; returns the process exit status."""
    _single_threaded_blas()
    args = build_parser().parse_args(argv)
    if args.command == "bench":
        from .bench import run_benchmark
        from .bench.registry import BenchOptionError
        from .bench.timing import recorded

        try:
            with recorded(args.table, ["python -m study", *(argv or sys.argv[1:])]):
                return run_benchmark(
                    args.scene, args.sizes, args.peers, args.repeat, args.error, args.periodic,
                    args.incremental, args.steady, args.shapes, args.travel,
                )  # fmt: skip
        except BenchOptionError as error:
            print(f"error: {error}", file=sys.stderr)
            return 2

    from .campaign import CampaignError
    from .report import main as report_main

    handlers = {"run": _run, "validate": _validate, "status": _status, "assemble": _assemble}
    handlers["report"] = _report(report_main)
    try:
        return handlers[args.command](args)
    except CampaignError as error:
        if not getattr(error, "quiet", False):
            print(f"error: {error}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # output piped into head & co.
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 1


# -- campaign files ------------------------------------------------------------------------------
def load_campaign_file(path, progress=None, spread=None) -> Campaign:
    """:func:`study.campaign.load_campaign`, refusing anything but a regular file first.

    ``spread`` (:data:`study.campaign.expand.Spread`) builds the cases somewhere else than in
    this process alone.

    A FIFO would block the read forever and a device such as /dev/zero would fill the memory;
    a missing file or a folder gets load_campaign's own message.
    """
    from .campaign import CampaignError, load_campaign
    from .campaign.expand import serial

    try:
        mode = os.stat(path).st_mode
    except OSError:
        mode = None
    if mode is not None and not stat.S_ISDIR(mode) and not stat.S_ISREG(mode):
        kind = next(
            (
                name
                for test, name in (
                    (stat.S_ISFIFO, "a FIFO"),
                    (stat.S_ISCHR, "a character device"),
                    (stat.S_ISBLK, "a block device"),
                    (stat.S_ISSOCK, "a socket"),
                )
                if test(mode)
            ),
            "not a regular file",
        )
        raise CampaignError(f"{path}: is {kind}, expected a campaign file (.toml)")
    return load_campaign(path, progress=progress, spread=spread or serial)


# -- run -----------------------------------------------------------------------------------------
def _launched_by_mpi() -> bool:
    return any(name in os.environ for name in _LAUNCHER_VARIABLES)


def _communicator(mode: str):
    from .campaign import CampaignError

    if mode == "off" or (mode == "auto" and not _launched_by_mpi()):
        return None
    try:
        from mpi4py import MPI
    except ImportError:
        if mode == "on":
            raise CampaignError("--mpi on: mpi4py is not installed") from None
        return None
    return MPI.COMM_WORLD


def _run(args: argparse.Namespace) -> int:
    os.environ.setdefault("HDF5_USE_FILE_LOCKING", "FALSE")  # one writer per file
    from pathlib import Path

    from .campaign import CampaignError
    from .run.driver import broadcast_campaign, run_campaign
    from .run.progress import configure_logging

    comm = _communicator(args.mpi)
    rank = comm.Get_rank() if comm is not None else 0
    size = comm.Get_size() if comm is not None else 1
    logger = configure_logging(rank, size, args.verbose)
    _check_options(args)
    try:
        progress = ProgressLine(say=logger.info)  # called on rank 0 only

        def load(spread):
            found = load_campaign_file(args.campaign, progress=progress, spread=spread)
            progress.finish()
            return found

        campaign = broadcast_campaign(load, comm)
        out = Path(args.out or campaign.settings.output)
        summary = run_campaign(campaign, out, comm, run_options(args), logger)
    except CampaignError as error:
        if rank != 0:
            error.quiet = True  # rank 0 prints the one message
        raise
    except Exception:
        if size > 1:  # a bug on one rank must not leave the others waiting
            logger.critical("unexpected error, aborting all ranks", exc_info=True)
            comm.Abort(1)
        raise
    if rank == 0 and not args.no_assemble:
        path = _assemble_or_say_why(out, campaign, logger)
        if path is None:
            return max(summary.exit_status, 1)
        logger.info("assembled %s", path)
    return summary.exit_status


def _assemble_or_say_why(out, campaign, logger):
    """Assemble ``OUT/<name>.nc``; on a write or read error log one line and return None."""
    from .run import storage
    from .run.assemble import assemble_to_file

    try:
        return assemble_to_file(out, campaign)
    except (OSError, RuntimeError) as error:
        logger.error(
            "assembly of %s failed: %s",
            storage.dataset_path(out, campaign.name),
            storage.describe_write_error(error, out),
        )
        return None


def _check_options(args: argparse.Namespace) -> None:
    from .campaign import CampaignError
    from .run.writer import MAX_BUNDLE_SECONDS

    if args.fft_threads is not None and not 1 <= args.fft_threads <= 256:
        raise CampaignError(f"--fft-threads must be 1..256, got {args.fft_threads}")
    if args.time_limit is not None and args.time_limit <= 0:
        raise CampaignError(f"--time-limit must be > 0 seconds, got {args.time_limit}")
    if args.case_timeout is not None:
        from .run.driver import check_case_timeout

        check_case_timeout(args.case_timeout, "--case-timeout")
    if args.time_reserve < 0:
        raise CampaignError(f"--time-reserve must be >= 0 seconds, got {args.time_reserve}")
    seconds = getattr(args, "bundle_seconds", 0.0)
    if not 0 <= seconds <= MAX_BUNDLE_SECONDS:
        raise CampaignError(
            f"--bundle-seconds must be in [0, {MAX_BUNDLE_SECONDS:g}] seconds, got {seconds}"
        )
    if args.max_initial_failures is not None and args.max_initial_failures < 0:
        raise CampaignError(f"--max-initial-failures must be >= 0, got {args.max_initial_failures}")


# -- validate ------------------------------------------------------------------------------------
def _validate(args: argparse.Namespace) -> int:
    from .campaign.parallel import processes

    progress = ProgressLine()
    campaign = load_campaign_file(args.campaign, progress=progress, spread=processes())
    progress.finish()
    from .run import calibration as machine

    if args.ranks is not None and args.ranks < 1:
        print(f"error: --ranks: must be at least 1, got {args.ranks}", file=sys.stderr)
        return 2
    units = machine.calibration(recalibrate=args.recalibrate, logger=stderr_notes())
    ranks = args.ranks or os.cpu_count() or 1
    print(describe_campaign(campaign, list_cases=args.list, ranks=ranks, calibration=units))
    lines = memory_warnings(campaign, machine_memory(), os.cpu_count())
    lines += path_warnings(campaign) + case_warnings(campaign)
    for line in lines:
        print(line, file=sys.stderr)
    return 0


# -- status and assemble -------------------------------------------------------------------------
def _resolve(target: str, out: str | None = None):
    """(campaign, out) from a campaign file or an output folder (``--out``: another folder)."""
    from pathlib import Path

    from .campaign import CampaignError
    from .run import storage

    path = Path(target)
    if path.is_dir():
        folder = Path(out) if out else path
        return storage.read_campaign(folder), folder
    if not path.exists() and path.suffix != ".toml":
        raise CampaignError(
            f"{target}: no such output folder or campaign file; give the folder a run wrote "
            "(after the run) or the campaign's .toml file"
        )
    campaign = load_campaign_file(path)
    return campaign, Path(out or campaign.settings.output)


def _status(args: argparse.Namespace) -> int:
    from .run import storage

    campaign, out = _resolve(args.target, args.out)
    storage.remove_temporaries(out)  # of processes that are gone; live ones are left alone
    index = storage.case_index(out)
    states = storage.case_states(out, campaign, index)
    corrupt = index.corrupt
    failures = storage.read_failures(out, [i for i, s in states.items() if s == "failed"], index)
    from solver.result import SOLVE_STATUSES, STATUS_FLAGS

    counts = dict.fromkeys(STATUS_FLAGS, 0)
    for state in states.values():
        state = "failed" if state == "corrupt" else state  # its data is lost until re-run
        counts[state] = counts.get(state, 0) + 1
    total = len(states)  # distinct cases: a design's repeated rows are solved once
    rows = len(campaign.cases)
    done = sum(counts[name] for name in SOLVE_STATUSES)
    finished = ", ".join(  # "truncated" and "surface flow" only when there are such cases
        f"{counts[n]} {n.replace('_', ' ')}"
        for n in SOLVE_STATUSES
        if counts[n] or n in ("converged", "not_converged")
    )
    repeated = f"; {rows} rows of the design, {total} distinct cases" if rows > total else ""
    print(
        f"campaign {campaign.name} in {out}: {done}/{total} finished ({finished}), "
        f"{counts['failed']} failed, {counts['pending']} pending{repeated}"
    )
    for name, problem in sorted(corrupt.items()):
        if name.endswith(storage.bundle.SUFFIX):
            print(
                f"  corrupt bundle cases/{name}: {problem}; its cases count as pending (run "
                "moves it aside and computes them again)"
            )
    for case in campaign.distinct_cases():
        if states[case.case_id] == "corrupt":
            print(
                f"  corrupt {case.case_id} [{case.label}]: cases/{case.case_id}.nc "
                f"{corrupt.get(case.case_id, 'is damaged')}; run moves it aside and recomputes it"
            )
        elif states[case.case_id] == "failed":
            record = failures.get(case.case_id, {})
            print(
                f"  failed {case.case_id} [{case.label}] on rank {record.get('rank', '?')} "
                f"({record.get('host', '?')}): {record.get('error', '?').splitlines()[0]}"
            )
    path = storage.dataset_path(out, campaign.name)
    print(f"dataset: {path}" + ("" if path.exists() else " (not assembled yet)"))
    return 1 if counts["failed"] else 0


def _assemble(args: argparse.Namespace) -> int:
    from .run import storage
    from .run.progress import configure_logging

    logger = configure_logging()
    campaign, out = _resolve(args.target, args.out)
    if not (out / storage.CAMPAIGN_FILE).is_file():  # never run: nothing to assemble
        storage.read_campaign(out)  # raises its "run the campaign first"
    storage.remove_temporaries(out)  # of processes that are gone; live ones are left alone
    path = _assemble_or_say_why(out, campaign, logger)
    if path is None:
        return 1
    print(f"assembled {path}")
    return 0


def _report(report_main):
    """The ``report`` handler: one line per corrupt case file, no traceback.

    The report reads the assembled dataset and the per-case files (stick/slip maps); when a case
    file of the campaign is corrupt, the dataset is re-assembled first (the case counted failed,
    left out of the figures).
    """

    def handler(args: argparse.Namespace) -> int:
        from pathlib import Path

        from .run import storage
        from .run.progress import configure_logging

        logger = configure_logging()
        if Path(args.out).suffix == ".toml":  # a campaign file: its output folder
            args.out = str(_resolve(args.out)[1])
        out = Path(args.out)
        if out.is_dir() and (out / storage.CAMPAIGN_FILE).exists():
            campaign = storage.read_campaign(out)
            storage.remove_temporaries(out)
            ids = {case.case_id for case in campaign.cases}
            corrupt = storage.corrupt_ids(out)
            if set(corrupt) & ids or any(n.endswith(storage.bundle.SUFFIX) for n in corrupt):
                if _assemble_or_say_why(out, campaign, logger) is None:
                    return 1
        try:
            return report_main(args)
        except (OSError, RuntimeError) as error:
            logger.error("report of %s failed: %s", out, storage.describe_write_error(error, out))
            return 1

    return handler
