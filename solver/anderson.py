"""Anderson acceleration of a fixed-point iteration x = g(x) (Walker & Ni 2011, type II).

With the residual ``f(x) = g(x) - x`` and the differences ``dX``, ``dF`` of the last ``m``
iterates and residuals, the next iterate is

    x+ = x + f - (dX + dF) gamma,    gamma = argmin || f - dF gamma ||_2,

which is plain fixed-point iteration when ``m = 0``.  The history restarts when the residual
grows by more than :data:`RESTART_GROWTH` over the best seen, a safeguard against stagnation.
"""

from __future__ import annotations

import numpy as np

#: Restart the history when |f| exceeds this multiple of the smallest |f| seen.
RESTART_GROWTH = 4.0


def _dot(a: np.ndarray, b: np.ndarray) -> float:
    """Sum of a*b, without BLAS (whose threads double the CPU time of these small products)."""
    return float(np.einsum("i,i->", a.ravel(), b.ravel()))


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
    """

    def __init__(self, memory: int = 5, history_dtype=np.float64):
        self.memory = memory
        self.history_dtype = np.dtype(history_dtype)
        self._x = None
        self._f = None
        self._dx: list[np.ndarray] = []
        self._df: list[np.ndarray] = []
        self._gram = np.empty((0, 0))  # dots of the kept dF, updated as they come and go
        self._best = np.inf
        self.restarts = 0

    def __call__(self, x: np.ndarray, f: np.ndarray) -> np.ndarray:
        """Next iterate from the current one ``x`` and its residual ``f = g(x) - x``."""
        norm = np.sqrt(_dot(f, f))
        if norm > RESTART_GROWTH * self._best and self._dx:
            self._dx.clear()
            self._df.clear()
            self._gram = np.empty((0, 0))
            self.restarts += 1
        self._best = min(self._best, norm)
        if self._x is not None and self.memory > 0:
            self._dx.append(np.subtract(x, self._x, dtype=self.history_dtype))
            self._df.append(np.subtract(f, self._f, dtype=self.history_dtype))
            row = np.array([_dot(d, self._df[-1]) for d in self._df])
            m = len(self._df)
            gram = np.empty((m, m))
            gram[:-1, :-1] = self._gram
            gram[-1, :] = gram[:, -1] = row
            self._gram = gram
            if m > self.memory:
                self._dx.pop(0)
                self._df.pop(0)
                self._gram = self._gram[1:, 1:]
        self._x, self._f = x.copy(), f.copy()
        if not self._dx:
            return x + f
        # least squares through the small Gram system (m x m): no tall matrix is formed
        gram = self._gram
        rhs = np.array([_dot(d, f) for d in self._df])
        gamma = np.linalg.lstsq(gram, rhs, rcond=1e-12)[0]
        out = x + f
        work = np.empty_like(self._dx[0])  # in the history's type: no full-size float64 temporary
        for g, dx, dfi in zip(gamma, self._dx, self._df, strict=True):
            np.add(dx, dfi, out=work)
            work *= g
            out -= work
        return out
