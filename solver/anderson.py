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
the chunks do not depend on the number of threads, nor do the results.
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

    def _each_chunk(self, size: int, job) -> list:
        """``job(chunk slice)`` over the chunks of ``size`` values, results in chunk order."""
        chunks = [slice(s, min(size, s + CHUNK)) for s in range(0, size, CHUNK)]
        return each(job, chunks, self.threads)

    def __call__(self, x: np.ndarray, f: np.ndarray) -> np.ndarray:
        """Next iterate from the current one ``x`` and its residual ``f = g(x) - x``."""
        shape = x.shape
        x, f = np.ravel(x), np.ravel(f)
        size = x.size
        norm = np.sqrt(sum(self._each_chunk(size, lambda c: _dots([f[c]], f[c])[0])))
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

            def differences(c: slice) -> np.ndarray:
                np.subtract(x[c], previous_x[c], out=dx[c])
                np.subtract(f[c], previous_f[c], out=df[c])
                return _dots([d[c] for d in history], df[c])

            row = np.sum(self._each_chunk(size, differences), axis=0)
            m = len(self._df)
            gram = np.empty((m, m))
            gram[:-1, :-1] = self._gram
            gram[-1, :] = gram[:, -1] = row
            self._gram = gram
        if self._x is None:
            self._x, self._f = np.empty_like(x), np.empty_like(f)
        kept_x, kept_f = self._x, self._f
        history_dx, history_df = self._dx, self._df

        def keep(c: slice) -> np.ndarray:
            kept_x[c] = x[c]
            kept_f[c] = f[c]
            return _dots([d[c] for d in history_df], f[c])

        rhs = np.sum(self._each_chunk(size, keep), axis=0)
        out = np.empty_like(x)
        if history_dx and not (np.isfinite(self._gram).all() and np.isfinite(rhs).all()):
            self._dx.clear()  # a history that overflowed: restart it, a plain step now
            self._df.clear()
            self._gram = np.empty((0, 0))
            self.restarts += 1
        if not history_dx:
            np.add(x, f, out=out)
            return out.reshape(shape)
        # least squares through the small Gram system (m x m): no tall matrix is formed
        gamma = np.linalg.lstsq(self._gram, rhs, rcond=1e-12)[0]

        def mix(c: slice) -> None:
            np.add(x[c], f[c], out=out[c])
            work = np.empty(c.stop - c.start, dtype=self.history_dtype)
            for g, dx, dfi in zip(gamma, history_dx, history_df, strict=True):
                np.add(dx[c], dfi[c], out=work)
                work *= g
                out[c] -= work

        self._each_chunk(size, mix)
        return out.reshape(shape)
