"""Timing and table helpers of the benchmarks: isolated child processes, peak memory, tables.

Every benchmark row runs in a fresh child process (:func:`isolated`) that has loaded the
solver's libraries first (:func:`load_solver`: they load on first use); its memory figure is
the growth of that process's resident set, sampled every 2 ms (:func:`peak_memory`), so codes
in C++ and in Python are measured alike.
"""

from __future__ import annotations

import math
import multiprocessing
import threading
import time
from contextlib import contextmanager


def _current_rss_mb() -> float:
    with open("/proc/self/statm") as handle:
        pages = int(handle.read().split()[1])
    return pages * 4096 / 2**20


@contextmanager
def peak_memory():
    """Sample the resident set every 2 ms; yields a dict whose ``"peak_MB"`` is the growth.

    Works for Python and C++ allocations alike (peers), unlike ``tracemalloc``.
    """
    record = {"peak_MB": 0.0}
    baseline = _current_rss_mb()
    stop = threading.Event()

    def sample():
        while not stop.is_set():
            record["peak_MB"] = max(record["peak_MB"], _current_rss_mb() - baseline)
            stop.wait(0.002)

    thread = threading.Thread(target=sample, daemon=True)
    thread.start()
    try:
        yield record
    finally:
        stop.set()
        thread.join()
        record["peak_MB"] = max(record["peak_MB"], _current_rss_mb() - baseline)


def load_solver() -> None:
    """Import what a solve imports on its first use: the solver's modules and pyFFTW.

    ``solver`` loads its modules on first use and pyFFTW at the first FFT plan, seconds on a
    slow machine: a row of a benchmark times the solve, not these imports.
    """
    import importlib

    import solver

    for name in dir(solver):  # each public name loads its module
        getattr(solver, name)
    importlib.import_module("pyfftw")


def _child(target, args, queue) -> None:
    try:
        load_solver()
        queue.put(("ok", target(*args)))
    except Exception as error:  # reported as a row, the benchmark goes on
        queue.put(("error", f"{type(error).__name__}: {error}"))


def timed_solve(table: dict):
    """Solve a case table: ``(case, result, wall s, CPU s, resident-memory growth MB)``."""
    import solver

    case = solver.Case.from_dict(table)
    with peak_memory() as memory:
        c0, t0 = time.process_time(), time.perf_counter()
        result = solver.solve(case)
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    return case, result, wall, cpu, memory["peak_MB"]


def machine() -> str:
    """The machine it runs on, in one line: CPU model, cores, memory, OS and Python."""
    import os
    import platform

    model = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as handle:
            model = next(line.split(":", 1)[1].strip() for line in handle if "model name" in line)
    except (OSError, StopIteration):
        pass
    try:
        memory = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES") / 2**30
    except (AttributeError, OSError, ValueError):
        memory = math.nan
    return (
        f"{model}, {os.cpu_count()} cores, {memory:.0f} GiB, {platform.system()} "
        f"{platform.release()}, Python {platform.python_version()}"
    )


def provenance_line(command: list[str]) -> str:
    """One Markdown sentence: the command that made a table, the date (UTC), machine, commit."""
    import datetime

    from ..run.storage import git_hash

    now = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    return (
        f"Made by `{' '.join(command)}` on {now}, on {machine()}, at commit "
        f"`{git_hash()[:12] or 'unknown'}`."
    )


@contextmanager
def recorded(path: str | None, command: list[str]):
    """Copy what the block prints to ``path`` (Markdown), headed by its provenance.

    The header says the command, the date (UTC) it started, the machine (:func:`machine`) and
    the commit, so a table in the guide says where it came from and how to make it again.
    """
    if path is None:
        yield
        return
    import contextlib
    import io
    import sys

    class _Tee(io.TextIOBase):
        def __init__(self, *streams):
            self.streams = streams

        def write(self, text):
            for stream in self.streams:
                stream.write(text)
            return len(text)

        def flush(self):
            for stream in self.streams:
                stream.flush()

    # the provenance of the code that runs, taken before it runs (a long run's files may
    # change on disk meanwhile)
    header = [provenance_line(command), ""]
    captured = io.StringIO()
    with contextlib.redirect_stdout(_Tee(sys.stdout, captured)):
        yield
    lines, previous = [], ""
    for line in captured.getvalue().splitlines():
        if line.startswith("|") != previous.startswith("|"):
            lines.append("")  # a Markdown table stands apart from the text around it
        lines.append(line)
        previous = line
    with open(path, "w") as handle:
        handle.write("\n".join(header + lines) + "\n")


def isolated(target, *args, timeout: float = 1800.0):
    """Run ``target(*args)`` in a fresh (spawned) process: ``("ok", result)`` or ``("error", why)``.

    A child that raises, dies or outlives ``timeout`` seconds is an error row, not a crash.
    """
    context = multiprocessing.get_context("spawn")
    queue = context.Queue()
    process = context.Process(target=_child, args=(target, args, queue))
    process.start()
    try:
        status, payload = queue.get(timeout=timeout)
    except Exception:
        status, payload = "error", f"no answer within {timeout:.0f} s"
    process.join(5)
    if process.is_alive():
        process.kill()
    return status, payload


def format_table(rows: list[dict]) -> str:
    """Render benchmark rows as a Markdown table (every row's columns, in order of appearance)."""
    if not rows:
        return "(no rows)"
    columns = list(dict.fromkeys(column for row in rows for column in row))
    lines = ["| " + " | ".join(columns) + " |", "|" + "---|" * len(columns)]
    for row in rows:
        cells = []
        for column in columns:
            value = row.get(column)
            if isinstance(value, float):
                cells.append("nan" if math.isnan(value) else f"{value:.4g}")
            else:
                cells.append("-" if value is None else str(value))
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)
