"""Measure the framework's own cost on a campaign of many tiny cases; write a table.

Run from the repository's root::

    python docs/framework_scale.py --cases 20000 --before /path/to/worktree/of/an/old/commit

A sampled design (Latin hypercube over the load, the friction coefficient and body 1's
modulus) of ``--cases`` tiny elastic cases (a sphere on a half-space, 16 x 16 cells, 2 load
steps) runs under ``mpiexec -n 2`` with each code tree given (this one, and ``--before`` when
given: a ``git worktree`` of an older commit, run from its own folder so that it imports its own
code), one after the other in this run.  Per code tree the table records:

- ``validate``, ``run``, ``status`` and ``assemble`` (``--steps``; also ``start``: a run that
  starts no case, see :data:`STEPS`): wall time, CPU time (user + system of every process the
  command started, both ranks included) and peak resident memory (the largest process);
- the framework's overhead per case (``run``'s own summary: the time a case spends outside
  its solve on its rank: set-up, checks, storing, this rank's share of the writing);
- the files under ``OUT/cases`` and their size on disk.

``--repeat N`` runs every step but ``run`` N times and records the medians (a step of a
second is noise-bound on a shared machine); ``--campaign FILE`` measures a campaign file of
one's own instead of the tiny design (give ``--cases`` its number of cases, for the columns per
10^4 cases).  The table goes to ``docs/tables/framework_scale.md`` (``--table``), headed by the
command, the date, the machine and the commits.
"""

from __future__ import annotations

import argparse
import os
import platform
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
CAMPAIGN = """\
[campaign]
name = "tiny_scale"
description = "Framework cost: a tiny elastic sphere, a Latin hypercube over load, mu, modulus"

[base.body1]
behaviour = "elastic"
radius = 0.01
E = 210e9
nu = 0.3

[base.body2]
behaviour = "elastic"
radius = "inf"
E = 210e9
nu = 0.3

[base.load]
normal_force = 100.0
steps = 2

[base.grid]
n = 16
half_width = 1.5

[sample]
method = "lhs"
count = {count}
seed = 1
"load.normal_force" = {{ distribution = "log-uniform", range = [10.0, 1000.0] }}
"friction.coefficient" = {{ distribution = "uniform", range = [0.0, 0.5] }}
"body1.E" = {{ distribution = "log-uniform", range = [70e9, 400e9] }}
"""


#: Runs a command and prints, last, the CPU (s) and peak memory (KiB) of its process tree.
_WRAPPER = (
    "import resource, subprocess, sys; done = subprocess.run(sys.argv[1:]); "
    "u = resource.getrusage(resource.RUSAGE_CHILDREN); "
    "print(f'@@ {u.ru_utime + u.ru_stime} {u.ru_maxrss}'); sys.exit(done.returncode)"
)


def _step(command: list[str], cwd: Path, accept: tuple[int, ...] = (0, 1)) -> dict:
    """Wall (s), CPU (s) and peak memory (MiB, the largest process) of one command.

    The command runs under a wrapper process of its own, whose ``RUSAGE_CHILDREN`` holds the
    command's whole process tree (each process waits for its children, as mpiexec does).
    """
    env = {**os.environ, "OMP_NUM_THREADS": "1"}
    start = time.perf_counter()
    done = subprocess.run(
        [sys.executable, "-c", _WRAPPER, *command], cwd=cwd, env=env, capture_output=True,
        text=True,
    )  # fmt: skip
    wall = time.perf_counter() - start
    if done.returncode not in accept:
        raise RuntimeError(f"{command} failed:\n{done.stdout[-2000:]}{done.stderr[-2000:]}")
    cpu, peak = done.stdout.rsplit("@@ ", 1)[1].split()
    return {"wall": wall, "cpu": float(cpu), "peak": int(peak) / 1024.0, "text": done.stdout}


#: The steps measured, in order: ``start`` is a run under mpiexec that may start no case (a
#: time limit of 1 ms): reading the campaign, building its cases on the ranks, scanning the
#: output folder; it exits with status 3 (cases pending).
STEPS = ("validate", "start", "run", "status", "assemble")


def _median_step(command: list[str], cwd: Path, accept: tuple[int, ...], repeat: int) -> dict:
    """:func:`_step` ``repeat`` times: the median wall and CPU, the largest peak memory."""
    runs = [_step(command, cwd, accept) for _ in range(repeat)]
    middle = len(runs) // 2
    return {
        "wall": sorted(run["wall"] for run in runs)[middle],
        "cpu": sorted(run["cpu"] for run in runs)[middle],
        "peak": max(run["peak"] for run in runs),
        "text": runs[-1]["text"],
    }


def measure(
    tree: Path, campaign: Path, out: Path, ranks: int, steps: list[str], repeat: int = 1
) -> dict:
    """Run ``steps`` with the code of ``tree``; their costs.

    Run from ``tree``, Python imports that tree's ``solver`` and ``study``.  Every step but
    ``run`` is run ``repeat`` times (:func:`_median_step`).
    """
    python = sys.executable
    mpi = ["mpiexec", "-n", str(ranks), python, "-m", "study", "run", str(campaign)]
    start = out.with_name(out.name + "_start")
    folder = out if "run" in steps else start  # status and assemble read the run's folder
    commands = {
        "validate": [python, "-m", "study", "validate", str(campaign)],
        "start": mpi + ["--out", str(start), "--no-assemble"]
        + ["--time-limit", "0.001", "--time-reserve", "0"],
        "run": mpi + ["--out", str(out), "--no-assemble"],
        "status": [python, "-m", "study", "status", str(folder)],
        "assemble": [python, "-m", "study", "assemble", str(folder)],
    }  # fmt: skip
    found: dict = {
        name: _median_step(
            commands[name],
            tree,
            (0, 1, 3) if name in ("start", "status") else (0, 1),
            1 if name == "run" else repeat,
        )  # fmt: skip
        for name in STEPS
        if name in steps
    }
    match = re.search(r"overhead ([0-9.]+) s per case", found.get("run", {}).get("text", ""))
    files = [p for p in (out / "cases").rglob("*") if p.is_file()]
    found["overhead"] = float(match.group(1)) if match else float("nan")
    found["files"] = len(files)
    found["disk"] = sum(p.stat().st_blocks * 512 for p in files) / 2**20
    return found


def _commit(tree: Path) -> str:
    done = subprocess.run(
        ["git", "rev-parse", "--short", "HEAD"], cwd=tree, capture_output=True, text=True
    )
    return done.stdout.strip() or "?"


def main(argv: list[str] | None = None) -> int:
    """Measure each code tree; print and write the table."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--cases", type=int, default=20000, help="cases of the design")
    parser.add_argument("--ranks", type=int, default=2, help="MPI ranks of the run")
    parser.add_argument("--before", type=Path, help="code tree of an older commit to compare")
    parser.add_argument(
        "--table", type=Path, default=ROOT / "docs" / "tables" / "framework_scale.md"
    )
    parser.add_argument(
        "--steps", default="validate,run,status,assemble",
        help=f"comma-separated steps to measure, of {', '.join(STEPS)}",
    )  # fmt: skip
    parser.add_argument(
        "--repeat", type=int, default=1,
        help="runs of each step but run (the table gives the medians: short steps are noisy)",
    )  # fmt: skip
    parser.add_argument(
        "--campaign", type=Path,
        help="measure this campaign file instead of the tiny design (--cases is then its count)",
    )  # fmt: skip
    args = parser.parse_args(argv)
    if args.repeat < 1:
        parser.error(f"--repeat: give 1 or more, got {args.repeat}")
    if args.campaign is not None and not args.campaign.is_file():
        parser.error(f"--campaign: no such file {args.campaign}")
    steps = [step for step in args.steps.split(",") if step]
    if not steps or set(steps) - set(STEPS):
        parser.error(f"--steps: give some of {', '.join(STEPS)}, got {args.steps!r}")
    trees = ([("before", args.before.resolve())] if args.before else []) + [("after", ROOT)]
    rows = []
    with tempfile.TemporaryDirectory(prefix="framework_scale_") as folder:
        if args.campaign is not None:
            campaign = args.campaign.resolve()
        else:
            campaign = Path(folder) / "tiny_scale.toml"
            campaign.write_text(CAMPAIGN.format(count=args.cases))
        for label, tree in trees:
            out = Path(folder) / f"out_{label}"
            print(f"{label}: {tree} ({_commit(tree)}), {args.cases} cases", flush=True)
            found = measure(tree, campaign, out, args.ranks, steps, args.repeat)
            rows.append((label, _commit(tree), found))
            shutil.rmtree(out, ignore_errors=True)
            shutil.rmtree(out.with_name(out.name + "_start"), ignore_errors=True)
    scene = (
        f"the campaign {args.campaign.name} ({args.cases} cases)"
        if args.campaign
        else f"{args.cases} tiny elastic cases (16 x 16 cells, 2 steps)"
    )
    lines = [
        f"`python docs/framework_scale.py --cases {args.cases}"
        + (f" --campaign {args.campaign}" if args.campaign else "")
        + (f" --steps {args.steps}" if steps != ["validate", "run", "status", "assemble"] else "")
        + (f" --repeat {args.repeat}" if args.repeat > 1 else "")
        + (" --before <worktree>`" if args.before else "`"),
        "",
        f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}; {platform.node()}, "
        f"{os.cpu_count()} cores, load {os.getloadavg()[0]:.2f}; {scene} on {args.ranks} ranks"
        + (f"; medians of {args.repeat} runs of each step but run" if args.repeat > 1 else ""),
        "",
        "| code | commit | step | wall (s) | CPU (s) | peak memory (MiB) |",
        "|---|---|---|---|---|---|",
    ]
    for label, commit, found in rows:
        for step in (step for step in STEPS if step in found):
            one = found[step]
            lines.append(
                f"| {label} | {commit} | {step} | {one['wall']:.1f} | {one['cpu']:.1f} | "
                f"{one['peak']:.0f} |"
            )
    per = 1e4 / args.cases
    scaled = [step for step in ("validate", "start", "status", "assemble") if step in steps]
    head = ["code", "commit"]
    if "run" in steps:
        head += ["overhead per case (ms)", "files in cases/", "disk (MiB)"]
    head += ["assembly per case (ms)"] if "assemble" in steps else []
    head += [f"{step} per 10^4 cases (s)" for step in scaled]
    lines += ["", "| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for label, commit, found in rows:
        cells = [label, commit]
        if "run" in steps:
            cells += [f"{1e3 * found['overhead']:.1f}", str(found["files"]), f"{found['disk']:.1f}"]
        if "assemble" in steps:
            cells.append(f"{1e3 * found['assemble']['wall'] / args.cases:.2f}")
        cells += [f"{per * found[step]['wall']:.2f}" for step in scaled]
        lines.append("| " + " | ".join(cells) + " |")
    text = "\n".join(lines) + "\n"
    print(text)
    args.table.write_text(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
