"""Split a campaign into N deterministic slices (one per Slurm array task), then merge them.

    [srun] python slurm/slices.py run CAMPAIGN --out OUT --slice K --slices N [study run opts]
    python slurm/slices.py merge CAMPAIGN --out OUT

``run`` computes slice K of N into ``OUT/slices/K`` (its own output folder: concurrent array
tasks never share a folder, since a starting run clears the temporaries of its folder).  Slice
K holds the cases at positions K, K + N, K + 2N, ... of the campaign sorted costliest first (ties
by case number), so slices have similar cost and depend only on the campaign file.  It resumes
like ``study run``: finished cases of ``OUT/slices/K`` and of ``OUT/cases`` are skipped.

``merge`` (the dependent final job) writes ``OUT/campaign.json`` for the whole campaign,
hard-links (or copies) every finished case file of ``OUT/slices/*`` into ``OUT/cases`` and
assembles ``OUT/<name>.nc``.  It is idempotent; run it again after resubmitting array tasks.
Exit status of both: 0 every case (of the slice / campaign) finished, 1 failures, 2 bad
campaign or command line, 3 cases pending (resubmit).
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import shutil
import sys
from pathlib import Path

SLICES_DIR = "slices"


def slice_cases(campaign, index: int, count: int) -> tuple:
    """The cases of slice ``index`` of ``count`` (costliest-first round robin), in case order."""
    ordered = sorted(campaign.distinct_cases(), key=lambda c: (-c.cost, c.number))
    return tuple(sorted(ordered[index::count], key=lambda c: c.number))


def slice_folder(out: str | Path, index: int) -> Path:
    """Output folder of slice ``index``."""
    return Path(out) / SLICES_DIR / str(index)


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="slurm/slices.py", description=__doc__.split("\n")[0])
    sub = parser.add_subparsers(dest="command", required=True)
    run = sub.add_parser("run", help="compute one slice (under srun/mpiexec or serially)")
    run.add_argument("campaign")
    run.add_argument("--out", required=True)
    run.add_argument("--slice", type=int, required=True, dest="index")
    run.add_argument("--slices", type=int, required=True, dest="count")
    run.add_argument("--fft-threads", type=int)
    run.add_argument("--time-limit", type=float)
    run.add_argument("--time-reserve", type=float, default=10.0)
    run.add_argument("--case-timeout", type=float)
    run.add_argument("--max-initial-failures", type=int)
    run.add_argument("--mpi", choices=["auto", "on", "off"], default="auto")
    run.add_argument("-v", "--verbose", action="store_true")
    merge = sub.add_parser("merge", help="merge the slices into OUT and assemble")
    merge.add_argument("campaign")
    merge.add_argument("--out", required=True)
    return parser


def _run(args: argparse.Namespace) -> int:
    from study import cli
    from study.campaign import CampaignError, load_campaign
    from study.run import storage
    from study.run.driver import broadcast_campaign, run_campaign
    from study.run.progress import configure_logging

    os.environ.setdefault("HDF5_USE_FILE_LOCKING", "FALSE")
    if not 0 <= args.index < args.count:
        raise CampaignError(f"--slice must be in 0..{args.count - 1}, got {args.index}")
    comm = cli._communicator(args.mpi)
    rank = comm.Get_rank() if comm is not None else 0
    size = comm.Get_size() if comm is not None else 1
    logger = configure_logging(rank, size, args.verbose)
    out = Path(args.out)
    folder = slice_folder(out, args.index)

    def load(spread):
        campaign = load_campaign(args.campaign, spread=spread)
        done = storage.finished_ids(out)  # merged by an earlier final step
        cases = tuple(
            c for c in slice_cases(campaign, args.index, args.count) if c.case_id not in done
        )
        logger.info(
            "slice %d of %d: %d cases (%d already merged into %s)",
            args.index,
            args.count,
            len(slice_cases(campaign, args.index, args.count)),
            len(slice_cases(campaign, args.index, args.count)) - len(cases),
            out,
        )
        if not cases:
            return None
        return dataclasses.replace(campaign, cases=cases)

    try:
        campaign = broadcast_campaign(load, comm)
        if campaign is None:
            return 0
        summary = run_campaign(campaign, folder, comm, cli.run_options(args), logger)
    except CampaignError as error:
        if rank != 0:
            error.quiet = True
        raise
    return summary.exit_status


def merge(campaign, out: str | Path) -> dict[str, int]:
    """Link the files of every slice that hold cases ``out`` lacks; returns counts by state.

    A slice's bundles (and the per-case files of older versions) are hard-linked into
    ``OUT/cases`` under their own names (copied where links are not possible), each
    atomically; ``linked`` counts the cases they add.
    """
    from study.run import storage

    out = Path(out)
    storage.prepare_output(out, campaign)
    wanted = {c.case_id for c in campaign.cases}
    target = storage.cases_dir(out)
    linked = 0
    for folder in sorted((out / SLICES_DIR).glob("*")):
        if not storage.cases_dir(folder).is_dir():
            continue
        have = storage.case_index(out)
        index = storage.case_index(folder)
        new = (set(index.results) & wanted) - set(have.results)
        failed = (set(index.failures) & wanted) - set(have.results) - set(have.failures)
        files = {index.results[i][0].path for i in new} | {index.failures[i].path for i in failed}
        for source in sorted(files):
            final = target / source.name
            if final.exists():
                continue
            temporary = target / f"{final.name}.tmp{os.getpid()}"
            try:
                os.link(source, temporary)
            except OSError:
                shutil.copy2(source, temporary)
            os.replace(temporary, final)
        linked += len(new)
    index = storage.case_index(out)
    finished, failed = set(index.results) & wanted, set(index.failures) & wanted
    return {
        "linked": linked,
        "finished": len(finished),
        "failed": len(failed),
        "pending": len(wanted - finished - failed),
    }


def _merge(args: argparse.Namespace) -> int:
    from study.campaign import load_campaign
    from study.run.assemble import assemble_to_file

    campaign = load_campaign(args.campaign)
    counts = merge(campaign, args.out)
    path = assemble_to_file(args.out, campaign)
    print(
        f"merged {counts['linked']} new case(s) into {args.out}: {counts['finished']}/"
        f"{len(campaign.distinct_cases())} finished, {counts['failed']} failed, "
        f"{counts['pending']} pending; assembled {path}"
    )
    if counts["failed"]:
        return 1
    return 3 if counts["pending"] else 0


def main(argv: list[str] | None = None) -> int:
    """Entry point; returns the exit status."""
    for name in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ.setdefault(name, "1")
    args = _parser().parse_args(argv)
    from study.campaign import CampaignError

    try:
        return _run(args) if args.command == "run" else _merge(args)
    except CampaignError as error:
        if not getattr(error, "quiet", False):
            print(f"error: {error}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
