"""Measure how long the documented commands take; write ``docs/tables/timings.md``.

Run from the repository's root::

    python docs/timings.py                  # the quick commands (a few minutes on 2 cores)
    python docs/timings.py --only quickstart
    python docs/timings.py --long           # also the long campaigns (over an hour)

Each command runs in a fresh output folder (a temporary one) ``--repeat`` times (default 3);
the table records the median wall time, the median CPU time of the command and every process
it started (user + system, over all MPI ranks, start-up included), the date, the machine and
the commit.  The measurements are kept in ``docs/tables/timings.json``: a command not measured
in this run keeps its earlier row with its date, so the long campaigns' rows stay until someone
re-runs them.  Other pages link to the table instead of stating times of their own
(``tests/test_docs.py`` fails when they do).
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import platform
import resource
import shlex
import statistics
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "docs" / "tables" / "timings.json"
TABLE = ROOT / "docs" / "tables" / "timings.md"


@dataclass(frozen=True)
class Command:
    """A documented command; ``{out}`` is replaced by a fresh output folder."""

    name: str
    what: str
    shown: str  #: as the docs show it
    run: str  #: as measured ({out}: a fresh folder)
    long: bool = False


def _campaign(name: str, what: str, long: bool = False) -> Command:
    shown = f"mpiexec -n 2 python -m study run campaigns/{name}.toml"
    return Command(name, what, shown, shown + " --out {out}/" + name, long)


def _example(name: str, what: str) -> Command:
    shown = f"python examples/{name}.py --out figures"
    return Command(f"examples/{name}.py", what, shown, f"python examples/{name}.py --out {{out}}")


COMMANDS: tuple[Command, ...] = (
    _campaign("quickstart", "the quickstart campaign: 25 elastic cases with friction"),
    _example("hertz_pressure", "Hertz pressure on three meshes"),
    _example("cattaneo_stick_zone", "Cattaneo-Mindlin partial slip"),
    _example("friction_sweep", "a 6-case campaign over mu"),
    _example("plastic_indentation", "plastic indentation at 24^3"),
    _example("fretting_loop", "3 fretting cycles"),
    _example("creep_curve", "the creep curve of a rolling ball"),
    _example("steady_rolling", "steady creep curves: Carter's cylinder, a worn rail"),
    _example("your_surface", "two height maps pressed"),
    _campaign("convergence_hertz", "mesh convergence against Hertz, 20 cases up to 768^2"),
    _campaign("convergence_cattaneo", "mesh convergence of Cattaneo-Mindlin, 28 cases"),
    _campaign("fretting_ii", "fretting II, 5 cases at 48^3", long=True),
    _campaign("paper_load_sweep", "the paper's load sweep, 20 cases at 32^3", long=True),
    _campaign("paper_sphere_8gpa", "the paper's 8 GPa spheres, 6 cases at 48^3", long=True),
    _campaign("convergence_plastic_steps", "load-step convergence, 10 cases", long=True),
    _campaign("convergence_plastic", "mesh/steps/box convergence, 48 cases to 96^3", long=True),
    _campaign("shakedown_kinematic", "4 sliding cases, Prager hardening", long=True),
    _campaign("shakedown_armstrong_frederick", "4 sliding cases, Armstrong-Frederick", long=True),
    _campaign("shakedown_frictionless", "7 sliding cases, ten passes", long=True),
    _campaign("shakedown_limit", "6 sliding cases, 8 and 16 steps a pass", long=True),
    _campaign("shakedown_map", "the 12-case shakedown map", long=True),
    _campaign("tractive_rolling", "10 rolling cases, three passes", long=True),
    Command(
        "slurm-test",
        "the Slurm integration test (a one-node cluster; root)",
        "python -m pytest -m slurm",
        "python -m pytest -m slurm -q -p no:cacheprovider",
        long=True,
    ),
)
BY_NAME = {command.name: command for command in COMMANDS}


def measure(command: Command, repeat: int) -> dict:
    """Run a command ``repeat`` times in fresh folders; wall and CPU medians and ranges."""
    walls, cpus = [], []
    load = os.getloadavg()[0]  # the machine is shared: its load before the runs
    env = os.environ | {"MPLBACKEND": "Agg"}
    for _ in range(repeat):
        with tempfile.TemporaryDirectory() as out:
            argv = shlex.split(command.run.format(out=out))
            argv = [sys.executable if a == "python" else a for a in argv]
            before = resource.getrusage(resource.RUSAGE_CHILDREN)
            start = time.perf_counter()
            done = subprocess.run(argv, cwd=ROOT, env=env, capture_output=True, text=True)
            wall = time.perf_counter() - start
            after = resource.getrusage(resource.RUSAGE_CHILDREN)
            if done.returncode != 0:
                raise SystemExit(f"{command.shown} failed:\n{done.stdout[-2000:]}{done.stderr}")
        walls.append(wall)
        cpus.append(after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime)
        print(f"{command.name}: {wall:.1f} s wall, {cpus[-1]:.1f} s CPU", flush=True)
    commit = subprocess.run(
        ["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True, text=True
    ).stdout.strip()
    return {
        "command": command.shown,
        "what": command.what,
        "wall_s": round(statistics.median(walls), 1),
        "cpu_s": round(statistics.median(cpus), 1),
        "wall_range_s": [round(min(walls), 1), round(max(walls), 1)],
        "runs": repeat,
        "date": datetime.date.today().isoformat(),
        "machine": f"{platform.machine()}, {os.cpu_count()} cores, load {load:.1f}",
        "commit": commit or "(unknown)",
        "how": "docs/timings.py",
    }


def _duration(seconds: float | None) -> str:
    if seconds is None:
        return "-"
    if seconds < 60:
        return f"{seconds:.1f} s" if seconds < 10 else f"{seconds:.0f} s"
    minutes, rest = divmod(round(seconds), 60)
    return f"{minutes} min {rest} s" if minutes < 60 else f"{minutes // 60} h {minutes % 60} min"


def render(data: dict) -> str:
    """The Markdown table of every recorded command, in the order of :data:`COMMANDS`."""
    lines = [
        "<!-- Written by `python docs/timings.py` from docs/tables/timings.json; do not edit. -->",
        "",
        "| command | what | wall | CPU | runs (wall range) | measured | how |",
        "|---|---|---|---|---|---|---|",
    ]
    names = [c.name for c in COMMANDS if c.name in data] + sorted(set(data) - set(BY_NAME))
    for name in names:
        row = data[name]
        spread = row.get("wall_range_s")
        runs = f"{row.get('runs', 1)}" + (
            f" ({_duration(spread[0])} - {_duration(spread[1])})"
            if spread and row.get("runs", 1) > 1
            else ""
        )
        when = f"{row['date']}, {row.get('machine', '')}".rstrip(", ")
        if row.get("commit"):
            when += f", {row['commit']}"
        lines.append(
            f"| `{row['command']}` | {row['what']} | {_duration(row.get('wall_s'))} | "
            f"{_duration(row.get('cpu_s'))} | {runs} | {when} | {row['how']} |"
        )
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    """Measure the chosen commands, update the JSON record and write the table."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n", 1)[0])
    parser.add_argument("--only", nargs="+", metavar="NAME", help=f"some of {sorted(BY_NAME)}")
    parser.add_argument("--long", action="store_true", help="also the long campaigns")
    parser.add_argument("--repeat", type=int, default=3, help="runs per command (3)")
    parser.add_argument("--render", action="store_true", help="only rewrite the table")
    args = parser.parse_args(argv)
    data = json.loads(DATA.read_text()) if DATA.exists() else {}
    unknown = set(args.only or ()) - set(BY_NAME)
    if unknown:
        parser.error(f"unknown command(s) {sorted(unknown)}")
    if not args.render:
        for command in COMMANDS:
            if (args.only and command.name not in args.only) or (
                not args.only and command.long and not args.long
            ):
                continue
            data[command.name] = measure(command, args.repeat)
            DATA.write_text(json.dumps(data, indent=2) + "\n")
    TABLE.write_text(render(data))
    print(f"wrote {TABLE.relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
