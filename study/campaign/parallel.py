"""Expanding a large campaign in several processes (``python -m study validate``).

Building and checking a case is Python work of a fraction of a millisecond (several with an
elastic-plastic body), so a design of 10^5 cases takes tens of seconds in one process.
:func:`processes` gives a :data:`~study.campaign.expand.Spread` that builds the expansion in
shares of :data:`SHARE` cases: the calling process builds the first, timed, and starts
workers when the rest would take it longer than :data:`WORKER_SECONDS` each; then it and the
workers each take the next share when done with one, so a worker's start-up or a busy core
costs no balance.

A worker is ``python -m study.campaign.parallel`` with the same code tree: it reads the
pickled expansion on its input, then share numbers, and writes each built part on its output.
It inherits neither the caller's threads nor an MPI library, and never runs the caller's main
script.  A worker that fails for any reason costs time, not the result: the shares it left
are built in the calling process.
"""

from __future__ import annotations

import itertools
import math
import os
import pickle
import subprocess
import sys
import threading
import time
from collections.abc import Callable
from pathlib import Path

from .expand import Expansion, Part, Spread, collector_paused, serial
from .model import Progress

#: Cases per share: the calling process and the workers each take the next share when done.
SHARE = 500
#: Seconds of building a worker process must have to be worth starting (its start-up, about a
#: second of imports, on another core): the first share's time times the shares left, per
#: worker.
WORKER_SECONDS = 1.0


def _start() -> subprocess.Popen | None:
    """A worker process of this code tree (None if it cannot be started)."""
    root = str(Path(__file__).resolve().parents[2])  # the tree this package is imported from
    paths = [root, *filter(None, [os.environ.get("PYTHONPATH")])]
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(paths)}
    try:
        return subprocess.Popen(
            [sys.executable, "-m", __name__], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
            env=env,
        )  # fmt: skip
    except (OSError, ValueError, TypeError):  # no executable, no pipes: build it here
        return None


def _serve(expansion: Expansion, take: Callable[[], int], n: int, parts: list) -> None:
    """Start a worker and feed it the next share numbers until none are left.

    Runs in a thread of the calling process; keeps the parts the worker returns.
    """
    worker = _start()
    if worker is None:
        return
    try:
        pickle.dump(expansion, worker.stdin, protocol=pickle.HIGHEST_PROTOCOL)
        while (k := take()) < n:
            pickle.dump((k, n), worker.stdin)
            worker.stdin.flush()
            parts[k] = pickle.load(worker.stdout)
    except (EOFError, pickle.UnpicklingError, OSError):
        pass  # the calling process builds whatever this worker left undone
    finally:
        for stream in (worker.stdin, worker.stdout):
            try:
                stream.close()
            except OSError:
                pass
        worker.wait()


def processes(workers: int | None = None) -> Spread:
    """A spread over ``workers`` processes (the caller's and workers - 1 more).

    Parameters
    ----------
    workers : int, optional
        Processes in all; the cores of this machine by default.  Fewer when the shares left
        after the first would take less than :data:`WORKER_SECONDS` per worker (none for a
        campaign of one share).
    """
    workers = workers or os.cpu_count() or 1

    def spread(expansion: Expansion, progress: Progress | None) -> list[Part]:
        with collector_paused():  # the workers' parts unpickled without the collector's passes
            return _spread(expansion, progress)

    def _spread(expansion: Expansion, progress: Progress | None) -> list[Part]:
        total = expansion.total
        n = -(-total // SHARE)
        if workers < 2 or n < 2:
            return serial(expansion, progress)
        parts: list[Part | None] = [None] * n
        clock = time.perf_counter()
        parts[0] = expansion.part(0, n)
        if progress is not None:
            progress(total // n, total)
        rest = (time.perf_counter() - clock) * (n - 1)  # the shares left, built here
        helpers = min(workers - 1, math.floor(rest / WORKER_SECONDS))
        numbers, lock = itertools.count(1), threading.Lock()

        def take() -> int:
            with lock:
                return next(numbers)

        feeders = [
            # daemons: an interrupted caller does not wait for the shares left
            threading.Thread(target=_serve, args=(expansion, take, n, parts), daemon=True)
            for _ in range(helpers)
        ]
        for feeder in feeders:
            feeder.start()
        while (k := take()) < n:
            parts[k] = expansion.part(k, n)
            if progress is not None:
                progress(min(total, (k + 1) * total // n), total)
        for feeder in feeders:
            feeder.join()
        return [part if part is not None else expansion.part(k, n) for k, part in enumerate(parts)]

    return spread


def _work() -> None:
    """A worker's job: read the expansion, then build each share asked for until the end."""
    expansion = pickle.load(sys.stdin.buffer)
    channel, sys.stdout = sys.stdout.buffer, sys.stderr  # a stray print must not mix in
    while True:
        try:
            k, n = pickle.load(sys.stdin.buffer)
        except EOFError:
            return
        pickle.dump(expansion.part(k, n), channel)
        channel.flush()


if __name__ == "__main__":
    _work()
