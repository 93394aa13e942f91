"""Worker threads shared by the solver's parallel loops (``solver.fft_threads``).

numpy and FFTW release the GIL in their loops, so Python threads run them side by side.  Every
parallel loop of the solver splits its work into pieces that do not depend on the number of
threads and combines their results in a fixed order: results are the same to the bit on one
thread or several.
"""

from __future__ import annotations

import concurrent.futures
import functools
from collections.abc import Callable, Sequence
from typing import Any


@functools.lru_cache(maxsize=8)
def pool(workers: int) -> concurrent.futures.ThreadPoolExecutor:
    """A pool of ``workers`` threads, made once and kept."""
    return concurrent.futures.ThreadPoolExecutor(workers, thread_name_prefix="solver")


def each(function: Callable[[Any], Any], items: Sequence, threads: int) -> list:
    """``[function(item) for item in items]``, on up to ``threads`` threads, results in order."""
    if threads <= 1 or len(items) <= 1:
        return [function(item) for item in items]
    return list(pool(min(threads, len(items))).map(function, items))
