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

import numpy as np


@functools.lru_cache(maxsize=8)
def pool(workers: int) -> concurrent.futures.ThreadPoolExecutor:
    """A pool of ``workers`` threads, made once and kept."""
    return concurrent.futures.ThreadPoolExecutor(workers, thread_name_prefix="solver")


def each(function: Callable[[Any], Any], items: Sequence, threads: int) -> list:
    """``[function(item) for item in items]``, on up to ``threads`` threads, results in order."""
    if threads <= 1 or len(items) <= 1:
        return [function(item) for item in items]
    return list(pool(min(threads, len(items))).map(function, items))


#: Rows (first cell axis) per block of :func:`by_rows`.
ROW_BLOCK = 8


def by_rows(function: Callable[[slice], Any], rows: int, threads: int) -> list:
    """``function(rows slice)`` over blocks of :data:`ROW_BLOCK` rows, results in block order.

    The blocks do not depend on the number of threads: a function that works elementwise on
    its block gives the same bits on any number of threads.
    """
    blocks = [slice(s, min(rows, s + ROW_BLOCK)) for s in range(0, rows, ROW_BLOCK)]
    return each(function, blocks, threads)


def copy_by_rows(target: np.ndarray, source: np.ndarray, threads: int, factor=None) -> None:
    """``target[...] = source`` (times ``factor`` when given) by :func:`by_rows` blocks."""

    def block(xs: slice) -> None:
        if factor is None:
            target[xs] = source[xs]
        else:
            np.multiply(source[xs], factor, out=target[xs])

    by_rows(block, len(target), threads)
