"""Measure the campaign dispatcher's throughput and model it for 1,000 ranks; write a table.

Run from the repository's root::

    python docs/dispatcher.py              # about two minutes on 2 cores

Two measurements with the driver's own dispatcher and scheduler (:mod:`study.bench.dispatch`):

- over MPI, ``mpiexec -n K`` for K = 2 to 32 ranks on this machine (oversubscribed past its
  cores), rank 0 dispatching only, the other ranks' cases returning at once: cases per second
  of the whole run, and the round trip of a small message between two ranks;
- a stand-in communicator (one process, a request always waiting from one of 999 simulated
  ranks, every message pickled both ways as mpi4py does): rank 0's time per request, for
  queues of 10^3 to 10^5 cases, with and without a time limit.

The model: rank 0 answers one request per case, so it sustains ``1 / (t_request +
t_message)`` cases per second (``t_request`` from the stand-in, ``t_message`` the round trip
measured over MPI: an upper bound of rank 0's share of it); 1,000 ranks whose cases take
``t`` seconds ask for ``1000 / t`` per second.  The table goes to ``docs/tables/dispatcher.md``.
"""

from __future__ import annotations

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


def _lines(command: list[str]) -> list[dict]:
    env = {**os.environ, "OMP_NUM_THREADS": "1"}
    done = subprocess.run(command, cwd=ROOT, env=env, capture_output=True, text=True)
    if done.returncode:
        raise RuntimeError(f"{command} failed:\n{done.stdout[-2000:]}{done.stderr[-2000:]}")
    return [json.loads(line) for line in done.stdout.splitlines() if line.startswith("{")]


def main() -> int:
    """Measure, model, print and write the table."""
    standin = []
    for limit in ([], ["--time-limit", "1e6"]):
        standin += _lines([*MODULE, "standin", "--cases", "1000", "10000", "100000", *limit])
    mpi = []
    for ranks in (2, 4, 8, 16, 32):
        mpi += _lines(["mpiexec", "-n", str(ranks), *MODULE, "mpi", "--cases", "4000"])
    lines = [
        "`python docs/dispatcher.py`",
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


if __name__ == "__main__":
    sys.exit(main())
