r"""Periodic images of a convolution kernel: the kernel of a laterally periodic grid.

A field that repeats with period ``n`` cells, convolved with a kernel ``K`` of the infinite
plane, is the circular convolution of one period with the periodised kernel
``P(d) = sum_m K(d + m n)``, given at the offsets ``0 .. n - 1`` (the operators of a periodic
grid convolve with FFTs of the period's own lengths, :meth:`~.grid.VolumeGrid.fft_lengths`).

The sum is taken over the :data:`IMAGES` nearest periods on each side, centred on each offset:
``P(d) = sum_t w(t) K(t)`` over ``t = d (mod n)`` with ``|t| <= (IMAGES + 1/2) n``, ``w = 1``
inside and ``1/2`` on the two ends (they meet at ``d = n/2``), so that ``P`` is exactly periodic
and keeps the parity of ``K``.  What the far periods add is nearly uniform over one period:
the kernels' users replace the period's sum of ``P`` (its mean mode) by its exact value, the
response to a laterally uniform source, and :func:`far_images` adds the far periods' first-
and second-order variation over the period from the kernel at the lattice's edge (the
divergence theorem).  What remains of the truncation is measured in
``tests/test_periodic_volume.py`` (4e-4 of the peak against 9 x 9 copies, one period each
side).
"""

from __future__ import annotations

import numpy as np

#: Periods summed on each side of the central one, per lateral axis.
IMAGES = 1


def image_reach(n: int) -> int:
    """Largest offset (cells) the periodised kernel of a period of ``n`` cells reads."""
    return int((2 * IMAGES + 1) * n // 2)


def _weight(t: np.ndarray, n: int) -> np.ndarray:
    """``w(t)``: 1 inside the reach, 1/2 on its ends, 0 beyond."""
    twice, limit = 2 * np.abs(t), (2 * IMAGES + 1) * n
    return np.where(twice < limit, 1.0, np.where(twice == limit, 0.5, 0.0))


def fold_signed(values: np.ndarray, n: int, axis: int) -> np.ndarray:
    """Periodise a kernel given at the signed offsets ``-L .. L`` along ``axis``.

    ``L = image_reach(n)`` (``values`` has ``2 L + 1`` entries along ``axis``); returns the
    offsets ``0 .. n - 1`` of one period.
    """
    reach = image_reach(n)
    values = np.moveaxis(np.asarray(values), axis, 0)
    if values.shape[0] != 2 * reach + 1:
        raise ValueError(f"need offsets -{reach} .. {reach} along axis {axis}")
    t = np.arange(-reach, reach + 1)
    weighted = values * _weight(t, n).reshape((-1,) + (1,) * (values.ndim - 1))
    out = np.zeros((n,) + values.shape[1:], dtype=np.result_type(values, float))
    np.add.at(out, t % n, weighted)
    return np.moveaxis(out, 0, axis)


def fold_nonnegative(
    values: np.ndarray, n: int, odd: bool, axis: int, start: int = 0, out: np.ndarray | None = None
) -> np.ndarray:
    """Periodise a kernel of known parity given at the offsets ``start .. start + len - 1``.

    The negative offsets follow from the parity (``K(-t) = -K(t)`` when ``odd``).  The
    contributions are added to ``out`` (offsets ``0 .. n - 1`` along ``axis``; zeros when not
    given), so that a kernel computed in slabs of offsets can be folded slab by slab; together
    the slabs must cover ``0 .. image_reach(n)``.  Returns ``out``.
    """
    if out is None:
        shape = list(np.shape(values))
        shape[axis] = n
        out = np.zeros(shape, dtype=np.result_type(values, float))
    target = np.moveaxis(out, axis, 0)  # a view: what is added to it lands in ``out``
    values = np.moveaxis(np.asarray(values), axis, 0)
    t = np.arange(start, start + values.shape[0])
    w = _weight(t, n).reshape((-1,) + (1,) * (values.ndim - 1))
    np.add.at(target, t % n, w * values)
    positive = t > 0  # the mirrored offset -t (t = 0 is its own mirror)
    np.add.at(target, (-t[positive]) % n, (-w if odd else w)[positive] * values[positive])
    return out


def centred_offsets(n: int) -> np.ndarray:
    """The offsets ``0 .. n - 1`` of one period as their centred representatives (cells).

    ``i`` below ``n/2``, ``i - n`` above, 0 at ``n/2`` itself (where the two images of a ramp
    cancel): the lever of :func:`far_gradient`'s correction.
    """
    d = np.arange(n)
    d = np.where(2 * d < n, d, d - n)
    return np.where(2 * d == -n, 0, d)


def far_gradient(edge: np.ndarray, nx: int, ny: int) -> np.ndarray:
    """Lattice sum of a kernel's x-gradient over the periodic images beyond the reach.

    ``edge``: the kernel at the offset ``+image_reach(nx)`` in x, at every y offset ``-Ly ..
    Ly`` along its first axis (other axes: components, layers...).  For a kernel odd in x and
    even in y the images beyond the reach add ``d_x sum_m dK/dx(m)`` to the periodised kernel
    at the (centred) offset ``d_x``, at first order, a ramp the truncated sum misses; with
    ``sum_m`` taken as the integral over the plane outside the reach's rectangle per period
    area, the divergence theorem gives ``-(2 / (nx ny)) sum_y w(y) K(reach, y)`` (trapezoidal
    weights): returned, per cell of offset.  Even kernels have no first-order term.
    """
    weights = np.ones(edge.shape[0])
    weights[[0, -1]] = 0.5
    return -2.0 / (nx * ny) * np.tensordot(weights, edge, axes=(0, 0))


def signed(values: np.ndarray, odd: bool, axis: int = 0) -> np.ndarray:
    """A kernel at the offsets ``0 .. L`` along ``axis`` extended to ``-L .. L`` by parity."""
    values = np.moveaxis(np.asarray(values), axis, 0)
    mirror = values[:0:-1] * (-1.0 if odd else 1.0)
    return np.moveaxis(np.concatenate([mirror, values]), 0, axis)


def far_images(edges: dict, parity: tuple[int, int], nx: int, ny: int) -> np.ndarray:
    """What the periodic images beyond the reach add to a periodised kernel, but its mean.

    ``edges``: ``"x"`` the kernel at the x offsets ``reach - 2, reach - 1, reach`` (first axis)
    and every signed y offset (second axis), ``"y"`` likewise with x and y exchanged; further
    axes are carried (layers, z offsets).  ``parity``: (x, y), 1 odd.  First order for a
    kernel odd along one axis (:func:`far_gradient` times the centred offset), second order
    for an even one (half the images' sum of the curvature times the offset squared, the
    edges' slopes one-sided to second order); an odd-odd kernel's terms cancel.  Returns the
    correction on the ``(nx, ny)`` offsets of one period (broadcast over the carried axes).
    """
    odd_x, odd_y = parity
    dx = centred_offsets(nx).reshape((-1, 1) + (1,) * (edges["x"].ndim - 2))
    dy = centred_offsets(ny).reshape((1, -1) + (1,) * (edges["y"].ndim - 2))
    if odd_x and odd_y:
        return np.zeros(())
    if odd_x:
        return far_gradient(edges["x"][-1], nx, ny) * dx
    if odd_y:
        return far_gradient(edges["y"][-1], ny, nx) * dy
    slope = {a: 1.5 * e[-1] - 2.0 * e[-2] + 0.5 * e[-3] for a, e in edges.items()}
    along_x = far_gradient(slope["x"], nx, ny) * dx**2
    return 0.5 * (along_x + far_gradient(slope["y"], ny, nx) * dy**2)
