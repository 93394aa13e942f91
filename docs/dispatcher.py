"""Measure the campaign dispatcher's throughput and model it for 1,000 ranks; write a table.

Run from the repository's root::

    python docs/dispatcher.py [--before TREE]   # about three minutes on 2 cores

Two measurements with the driver's own dispatcher and scheduler (:mod:`study.bench.dispatch`):

- over MPI, ``mpiexec -n K`` for K = 2 to 32 ranks on this machine (oversubscribed past its
  cores), rank 0 dispatching only, the other ranks' cases returning at once: cases per second
  of the whole run, and the round trip of a small message between two ranks;
- a stand-in communicator (one process, a request always waiting from one of 999 simulated
  ranks, every message pickled both ways as mpi4py does): rank 0's time per request, for
  queues of 10^3 to 10^5 cases, with and without a time limit;
- short cases over MPI (2 and 3 ranks, each worker's case a sleep of 10 or 50 ms): cases per
  second against the ideal (workers / case time), which shows what the wait for the next case
  costs a worker; with ``--before TREE`` (a ``git worktree`` of an older commit) the same is
  run from that tree too, in the same run.

The model: rank 0 answers one request per case, so it sustains ``1 / (t_request +
t_message)`` cases per second (``t_request`` from the stand-in, ``t_message`` the round trip
measured over MPI: an upper bound of rank 0's share of it); 1,000 ranks whose cases take
``t`` seconds ask for ``1000 / t`` per second.  The table goes to ``docs/tables/dispatcher.md``.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
TABLE = ROOT / "docs" / "tables" / "dispatcher.md"
MODULE = [sys.executable, "-m", "study.bench.dispatch"]


def _lines(command: list[str], tree: Path = ROOT) -> list[dict]:
    env = {**os.environ, "OMP_NUM_THREADS": "1"}
    done = subprocess.run(command, cwd=tree, env=env, capture_output=True, text=True)
    if done.returncode:
        raise RuntimeError(f"{command} failed:\n{done.stdout[-2000:]}{done.stderr[-2000:]}")
    return [json.loads(line) for line in done.stdout.splitlines() if line.startswith("{")]


def _short_cases(trees: dict[str, Path]) -> list[str]:
    """Rows of the short-case table: cases per second against the ideal, per code tree."""
    rows = []
    for ranks in (2, 3):
        for seconds in (0.01, 0.05):
            count = round(4.0 / seconds) * (ranks - 1)  # about 4 s per worker
            ideal = (ranks - 1) / seconds
            command = ["mpiexec", "-n", str(ranks), *MODULE, "mpi", "--cases", str(count)]
            found = {
                label: _lines([*command, "--case-seconds", str(seconds)], tree)[0]["rate"]
                for label, tree in trees.items()
            }
            rows.append(
                f"| {ranks} | {1e3 * seconds:g} | {ideal:.0f} | "
                + " | ".join(f"{rate:.1f} ({rate / ideal:.0%})" for rate in found.values())
                + " |"
            )
    return rows


def main(argv: list[str] | None = None) -> int:
    """Measure, model, print and write the table."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--before", type=Path, help="a worktree of an older commit to compare")
    args = parser.parse_args(argv)
    trees = {"this commit": ROOT, **({"before": args.before} if args.before else {})}
    standin = []
    for limit in ([], ["--time-limit", "1e6"]):
        standin += _lines([*MODULE, "standin", "--cases", "1000", "10000", "100000", *limit])
    mpi = []
    for ranks in (2, 4, 8, 16, 32):
        mpi += _lines(["mpiexec", "-n", str(ranks), *MODULE, "mpi", "--cases", "4000"])
    lines = [
        "`python docs/dispatcher.py" + (" --before TREE`" if args.before else "`"),
        "",
        f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}; {platform.node()}, "
        f"{os.cpu_count()} cores, load {os.getloadavg()[0]:.2f}",
        "",
        "Stand-in communicator, 999 simulated ranks:",
        "",
        "| cases | time limit | requests | rank 0 per request (us) | requests per second |",
        "|---|---|---|---|---|",
    ]
    for row in standin:
        limit = "none" if row["time_limit"] is None else "yes"
        lines.append(
            f"| {row['cases']} | {limit} | {row['requests']} | {row['per_request_us']:.1f} | "
            f"{row['rate']:.0f} |"
        )
    lines += [
        "",
        "Over MPI on this machine (rank 0 dispatching only; 4000 cases that return at once):",
        "",
        "| ranks | cases per second | round trip of a small message (us) |",
        "|---|---|---|",
    ]
    for row in mpi:
        lines.append(f"| {row['ranks']} | {row['rate']:.0f} | {row['pingpong_us']:.1f} |")
    lines += [
        "",
        "Short cases over MPI (rank 0 dispatching only; each worker's case sleeps): cases per "
        "second (share of the ideal)"
        + (f"; before: {_commit(args.before)}" if args.before else "")
        + ":",
        "",
        "| ranks | case (ms) | ideal | " + " | ".join(trees) + " |",
        "|---|---|---|" + "---|" * len(trees),
        *_short_cases(trees),
    ]
    per_request = max(row["per_request_us"] for row in standin) * 1e-6
    message = min(row["pingpong_us"] for row in mpi) * 1e-6
    capacity = 1.0 / (per_request + message)
    lines += [
        "",
        f"Model for 1,000 ranks: rank 0 sustains 1 / ({1e6 * per_request:.1f} us + "
        f"{1e6 * message:.1f} us) = {capacity:.0f} cases per second (the slowest stand-in row "
        "and the fastest round trip here).",
        "",
        "| case time (s) | cases per second 1,000 ranks ask | share of rank 0's capacity |",
        "|---|---|---|",
    ]
    for seconds in (0.1, 1.0, 10.0):
        demand = 1000.0 / seconds
        lines.append(f"| {seconds:g} | {demand:.0f} | {demand / capacity:.2f} |")
    text = "\n".join(lines) + "\n"
    print(text)
    TABLE.write_text(text)
    return 0


def _commit(tree: Path) -> str:
    done = subprocess.run(
        ["git", "rev-parse", "--short", "HEAD"], cwd=tree, capture_output=True, text=True
    )
    return done.stdout.strip() or "?"


if __name__ == "__main__":
    sys.exit(main())
