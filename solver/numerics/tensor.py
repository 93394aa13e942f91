"""Symmetric 3x3 tensors stored as six components: the one convention of the whole solver.

Every stress or strain array is shaped ``(6, ...)`` with the components in the order
:data:`COMPONENTS` = (xx, yy, zz, yz, xz, xy), *tensor* values (a shear strain ``e_xz`` is half
the engineering strain ``gamma_xz``).  Double contractions weigh the three off-diagonal
components twice (:data:`WEIGHTS`): ``a : b = sum_c WEIGHTS[c] a[c] b[c]``.

Definitions (J2 plasticity)::

    dev(a)        = a - tr(a)/3 I
    |a|           = sqrt(a : a)
    von Mises     = sqrt(3/2) |dev(sigma)|          (= sqrt(3 J2))
    equivalent e  = sqrt(2/3) |e|                    (e deviatoric, e.g. a plastic strain)

so that a uniaxial stress ``sigma`` has von Mises value ``|sigma|`` and a plastic strain
``diag(e, -e/2, -e/2)`` has equivalent value ``|e|``.
"""

from __future__ import annotations

import numpy as np

from .threads import by_rows

#: Component order of every ``(6, ...)`` tensor array.
COMPONENTS = ("xx", "yy", "zz", "yz", "xz", "xy")
#: Weights of the components in a double contraction (off-diagonal terms count twice).
WEIGHTS = np.array([1.0, 1.0, 1.0, 2.0, 2.0, 2.0])
#: Component index pairs (i, j) of :data:`COMPONENTS`, 0 = x, 1 = y, 2 = z.
INDEX_PAIRS = ((0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1))
#: Component signs under the reflection y -> -y (components with one y index change sign).
Y_REFLECTION = np.array([-1.0 if (i == 1) != (j == 1) else 1.0 for i, j in INDEX_PAIRS])


def _weights(ndim: int) -> np.ndarray:
    return WEIGHTS.reshape((6,) + (1,) * (ndim - 1))


def trace(a: np.ndarray) -> np.ndarray:
    """Trace ``a_xx + a_yy + a_zz``, shape ``a.shape[1:]``."""
    return a[0] + a[1] + a[2]


def deviator(a: np.ndarray) -> np.ndarray:
    """Deviatoric part ``a - tr(a)/3 I`` (a new ``(6, ...)`` array)."""
    out = np.array(a, dtype=float, copy=True)
    mean = trace(a) / 3.0
    out[:3] -= mean
    return out


def complete_deviator(a: np.ndarray, threads: int = 1) -> None:
    """Set ``a[2] = -(a[0] + a[1])`` in place: zz of a deviatoric tensor from xx and yy.

    By row blocks of the axis after the components (:func:`~solver.numerics.threads.by_rows`), on
    ``threads`` threads; the same bits on any number.
    """

    def block(xs: slice) -> None:
        np.add(a[0, xs], a[1, xs], out=a[2, xs])
        np.negative(a[2, xs], out=a[2, xs])

    by_rows(block, a.shape[1], threads)


def contract(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Double contraction ``a : b``, shape ``a.shape[1:]``."""
    return np.einsum("c...,c...->...", _weights(a.ndim) * a, b)


def norm(a: np.ndarray) -> np.ndarray:
    """Frobenius norm ``sqrt(a : a)``, shape ``a.shape[1:]``."""
    return np.sqrt(contract(a, a))


def von_mises(stress: np.ndarray) -> np.ndarray:
    """Von Mises equivalent stress ``sqrt(3/2) |dev(sigma)|`` (units of ``stress``)."""
    return np.sqrt(1.5) * norm(deviator(stress))


def equivalent_strain(strain: np.ndarray) -> np.ndarray:
    """Equivalent value ``sqrt(2/3) |e|`` of a deviatoric strain (e.g. a plastic strain)."""
    return np.sqrt(2.0 / 3.0) * norm(strain)


def to_matrix(a: np.ndarray) -> np.ndarray:
    """Full ``(..., 3, 3)`` matrices of a ``(6, ...)`` array (for tests and rotations)."""
    out = np.empty(a.shape[1:] + (3, 3))
    for c, (i, j) in enumerate(INDEX_PAIRS):
        out[..., i, j] = a[c]
        out[..., j, i] = a[c]
    return out


def from_matrix(m: np.ndarray) -> np.ndarray:
    """The ``(6, ...)`` array of symmetric ``(..., 3, 3)`` matrices."""
    return np.stack([m[..., i, j] for i, j in INDEX_PAIRS])
