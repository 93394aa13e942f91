"""Anderson acceleration of a fixed-point iteration x = g(x) (Walker & Ni 2011, type II).

With the residual ``f(x) = g(x) - x`` and the differences ``dX``, ``dF`` of the last ``m``
iterates and residuals, the next iterate is

    x+ = x + f - (dX + dF) gamma,    gamma = argmin || f - dF gamma ||_2,

which is plain fixed-point iteration when ``m = 0``.  The history restarts when the residual
grows by more than :data:`RESTART_GROWTH` over the best seen, a safeguard against stagnation,
and when its small least-squares system is no longer finite (an iteration that overflowed:
the caller's loop then reports it, never a linear-algebra error).

Every pass over the vectors runs by chunks of :data:`CHUNK` values (all the dot products, the
differences and the mixed iterate of a chunk while it is in cache), on ``threads`` threads;
the chunks do not depend on the number of threads, nor do the results.  A vector may be given
as several arrays (segments, e.g. the independent components of a tensor field, views of it):
they are mixed where they are, without gathering them into one.
"""

from __future__ import annotations

import numpy as np

from .threads import each

#: Restart the history when |f| exceeds this multiple of the smallest |f| seen.
RESTART_GROWTH = 4.0
#: Values per chunk of the passes over the vectors.
CHUNK = 2**16


def _dots(vectors: list[np.ndarray], other: np.ndarray) -> np.ndarray:
    """``[sum(v * other) for v in vectors]`` on one chunk.

    Without BLAS, whose threads double the CPU time of these small products.
    """
    return np.array([np.einsum("i,i->", v, other) for v in vectors])


class Anderson:
    """Anderson mixing with a memory of ``memory`` iterates.

    Parameters
    ----------
    memory : int
        Number of past differences kept (0: plain fixed-point iteration).
    history_dtype : numpy dtype
        Type the differences are kept in: float32 halves the history's memory; the mixing
        coefficients then carry ~1e-7 relative rounding, which changes the next iterate, not
        the fixed point a converged iteration settles to.
    threads : int
        Threads that share the chunks (results do not depend on it).
    """

    def __init__(self, memory: int = 5, history_dtype=np.float64, threads: int = 1):
        self.memory = memory
        self.history_dtype = np.dtype(history_dtype)
        self.threads = max(1, int(threads))
        self._x: np.ndarray | None = None
        self._f: np.ndarray | None = None
        self._dx: list[np.ndarray] = []
        self._df: list[np.ndarray] = []
        self._gram = np.empty((0, 0))  # dots of the kept dF, updated as they come and go
        self._best = np.inf
        self.restarts = 0

    def _each_chunk(self, sizes: list[int], job) -> list:
        """``job(segment, its slice, the history's slice)`` over the chunks of the segments.

        Chunks of at most :data:`CHUNK` values, segment after segment; results in chunk order.
        """
        chunks, start = [], 0
        for k, size in enumerate(sizes):
            for s in range(0, size, CHUNK):
                n = min(CHUNK, size - s)
                chunks.append((k, slice(s, s + n), slice(start + s, start + s + n)))
            start += size
        return each(lambda chunk: job(*chunk), chunks, self.threads)

    def __call__(self, x, f, out=None):
        """Next iterate from the current one ``x`` and its residual ``f = g(x) - x``.

        ``x`` and ``f`` are arrays, or sequences of arrays (segments of one vector, matched
        one to one); the next iterate is returned as a new array, or written into ``out``
        (arrays shaped as ``x``'s) when given.
        """
        single = isinstance(x, np.ndarray)
        shape = x.shape if single else None
        xs = [np.ravel(a) for a in ([x] if single else x)]
        fs = [np.ravel(a) for a in ([f] if single else f)]
        if out is None:
            outs = [np.empty_like(a) for a in xs]
        else:
            if not all(a.flags.c_contiguous for a in out):
                raise ValueError("Anderson: out must be C-contiguous arrays")  # pragma: no cover
            outs = [a.reshape(-1) for a in out]
        sizes = [a.size for a in xs]
        size = sum(sizes)
        norm = np.sqrt(sum(self._each_chunk(sizes, lambda k, c, h: _dots([fs[k][c]], fs[k][c])[0])))
        if norm > RESTART_GROWTH * self._best and self._dx:
            self._dx.clear()
            self._df.clear()
            self._gram = np.empty((0, 0))
            self.restarts += 1
        self._best = min(self._best, norm)
        if self._x is not None and self.memory > 0:
            if len(self._dx) == self.memory:  # the oldest difference's arrays are reused
                dx, df = self._dx.pop(0), self._df.pop(0)
                self._gram = self._gram[1:, 1:]
            else:
                dx = np.empty(size, dtype=self.history_dtype)
                df = np.empty(size, dtype=self.history_dtype)
            self._dx.append(dx)
            self._df.append(df)
            previous_x, previous_f, history = self._x, self._f, self._df

            def differences(k: int, c: slice, h: slice) -> np.ndarray:
                np.subtract(xs[k][c], previous_x[h], out=dx[h])
                np.subtract(fs[k][c], previous_f[h], out=df[h])
                return _dots([d[h] for d in history], df[h])

            row = np.sum(self._each_chunk(sizes, differences), axis=0)
            m = len(self._df)
            gram = np.empty((m, m))
            gram[:-1, :-1] = self._gram
            gram[-1, :] = gram[:, -1] = row
            self._gram = gram
        if self._x is None:
            self._x, self._f = np.empty(size, xs[0].dtype), np.empty(size, fs[0].dtype)
        kept_x, kept_f = self._x, self._f
        history_dx, history_df = self._dx, self._df

        def keep(k: int, c: slice, h: slice) -> np.ndarray:
            kept_x[h] = xs[k][c]
            kept_f[h] = fs[k][c]
            return _dots([d[h] for d in history_df], fs[k][c])

        rhs = np.sum(self._each_chunk(sizes, keep), axis=0)

        def result():
            return outs[0].reshape(shape) if single and out is None else out

        if history_dx and not (np.isfinite(self._gram).all() and np.isfinite(rhs).all()):
            self._dx.clear()  # a history that overflowed: restart it, a plain step now
            self._df.clear()
            self._gram = np.empty((0, 0))
            self.restarts += 1
        if not history_dx:
            for a, b, o in zip(xs, fs, outs, strict=True):
                np.add(a, b, out=o)
            return result()
        # least squares through the small Gram system (m x m): no tall matrix is formed
        gamma = np.linalg.lstsq(self._gram, rhs, rcond=1e-12)[0]

        def mix(k: int, c: slice, h: slice) -> None:
            o = outs[k][c]
            np.add(xs[k][c], fs[k][c], out=o)
            work = np.empty(h.stop - h.start, dtype=self.history_dtype)
            for g, dx, dfi in zip(gamma, history_dx, history_df, strict=True):
                np.add(dx[h], dfi[h], out=work)
                work *= g
                o -= work

        self._each_chunk(sizes, mix)
        return result()
