"""Uniform cell-centred grids on the contact surface and in the volume below it.

The surface grid is centred on the first contact point (the origin): cell ``i`` along x has its
centre at ``x_i = (i - (nx - 1)/2) dx``.  The volume grid adds ``nz`` layers of thickness ``dz``
below the surface (z into body 2), cell centres at ``z_k = (k + 1/2) dz``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class SurfaceGrid:
    """Cell-centred surface grid.

    Parameters
    ----------
    nx, ny : int
        Number of cells along x and y.
    dx, dy : float
        Cell sizes (m).
    centre : (float, float)
        Coordinates (m) of the grid's centre (the origin but for a sliding track's window).
    """

    nx: int
    ny: int
    dx: float
    dy: float
    centre: tuple[float, float] = (0.0, 0.0)

    @classmethod
    def centred(
        cls,
        nx: int,
        ny: int,
        half_width_x: float,
        half_width_y: float,
        centre: tuple[float, float] = (0.0, 0.0),
    ) -> SurfaceGrid:
        """Grid covering ``centre`` +- half_width_x along x, +- half_width_y along y (m)."""
        return cls(nx, ny, 2.0 * half_width_x / nx, 2.0 * half_width_y / ny, centre)

    @property
    def shape(self) -> tuple[int, int]:
        """(nx, ny)."""
        return (self.nx, self.ny)

    @property
    def cell_area(self) -> float:
        """Dx * dy (m^2)."""
        return self.dx * self.dy

    @property
    def x(self) -> np.ndarray:
        """Cell-centre x coordinates (m)."""
        return self.centre[0] + (np.arange(self.nx) - 0.5 * (self.nx - 1)) * self.dx

    @property
    def y(self) -> np.ndarray:
        """Cell-centre y coordinates (m)."""
        return self.centre[1] + (np.arange(self.ny) - 0.5 * (self.ny - 1)) * self.dy

    def mesh(self) -> tuple[np.ndarray, np.ndarray]:
        """Cell-centre coordinates as two (nx, ny) arrays (m), ``indexing="ij"``."""
        return np.meshgrid(self.x, self.y, indexing="ij")

    def offsets(self, lengths: tuple[int, int] | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Centre-to-centre offsets of the wrap-around convolution layout (m).

        The layout has ``lengths`` = (Lx, Ly) >= (2nx - 1, 2ny - 1) points, (2nx, 2ny) by
        default.  Index ``i < nx`` holds offset ``i dx``, index ``Lx - i`` holds ``-i dx``; the
        indices in between (offsets no pair of cells has) hold ``nx dx`` and their kernel values
        multiply only the zero padding.
        """
        lx, ly = lengths if lengths is not None else (2 * self.nx, 2 * self.ny)
        if lx < 2 * self.nx - 1 or ly < 2 * self.ny - 1:
            raise ValueError(f"padded lengths {(lx, ly)} too short for the grid {self.shape}")
        return np.meshgrid(
            _wrapped(self.nx, lx) * self.dx, _wrapped(self.ny, ly) * self.dy, indexing="ij"
        )


def _wrapped(n: int, length: int) -> np.ndarray:
    """Cell offsets (in cells) of a wrap-around layout of ``length`` points for ``n`` cells."""
    index = np.full(length, float(n))
    index[:n] = np.arange(n)
    index[length - n + 1 :] = -np.arange(n - 1, 0, -1)
    return index


def fft_length(minimum: int) -> int:
    """Smallest even 5-smooth integer (2^a 3^b 5^c, a >= 1) >= ``minimum``: fast for FFTW.

    A padded length with a large prime factor (2 x 92 = 184 = 8 x 23) costs FFTW's estimated
    plans twice as much as 192, and odd lengths (189 = 27 x 7) three times as much.
    """
    length = max(int(minimum), 2)
    length += length % 2
    while True:
        rest = length
        for prime in (2, 3, 5):
            while rest % prime == 0:
                rest //= prime
        if rest == 1:
            return length
        length += 2


@dataclass(frozen=True)
class VolumeGrid:
    """Surface grid plus ``nz`` cell-centred layers of thickness ``dz`` (m) below it.

    ``periodic``: the surface grid is one period of a laterally periodic body (its kernels are
    periodised, :mod:`solver.numerics.images`).
    """

    surface: SurfaceGrid
    nz: int
    dz: float
    periodic: bool = False

    @property
    def z(self) -> np.ndarray:
        """Layer-centre depths (m), positive into body 2."""
        return (np.arange(self.nz) + 0.5) * self.dz

    @property
    def shape(self) -> tuple[int, int, int]:
        """(nx, ny, nz)."""
        return (self.surface.nx, self.surface.ny, self.nz)

    def fft_lengths(self, nx: int | None = None, ny: int | None = None) -> tuple[int, int]:
        """Lateral FFT lengths of the layer convolutions of ``nx x ny`` cells (default: all).

        Zero-padded to twice the cells (a linear convolution), or the cells themselves on a
        periodic grid (a circular one: the period's kernels are periodic).
        """
        nx = self.surface.nx if nx is None else nx
        ny = self.surface.ny if ny is None else ny
        return (nx, ny) if self.periodic else (2 * nx, 2 * ny)


@dataclass(frozen=True)
class IndexBox:
    """Half-open index ranges ``[start, stop)`` of a sub-box of a volume grid.

    Parameters
    ----------
    x, y, z : (int, int)
        Cell-index ranges along x, y and z (layers).
    """

    x: tuple[int, int]
    y: tuple[int, int]
    z: tuple[int, int]

    @classmethod
    def full(cls, grid: VolumeGrid) -> IndexBox:
        """The whole grid."""
        nx, ny, nz = grid.shape
        return cls((0, nx), (0, ny), (0, nz))

    @property
    def shape(self) -> tuple[int, int, int]:
        """Number of cells along x, y, z."""
        return (self.x[1] - self.x[0], self.y[1] - self.y[0], self.z[1] - self.z[0])

    @property
    def slices(self) -> tuple[slice, slice, slice]:
        """Slices selecting the box from an ``(nx, ny, nz)`` array."""
        return (slice(*self.x), slice(*self.y), slice(*self.z))

    def validate(self, grid: VolumeGrid) -> None:
        """Raise ValueError unless the box is a non-empty part of ``grid``."""
        for (lo, hi), n, axis in zip((self.x, self.y, self.z), grid.shape, "xyz", strict=True):
            if not 0 <= lo < hi <= n:
                raise ValueError(f"box range {axis}={lo, hi} is empty or outside [0, {n}]")


def fft_size(n: int) -> int:
    """Smallest integer >= n whose prime factors are 2, 3, 5 and 7 (fast FFTW sizes)."""
    m = max(1, n)
    while True:
        k = m
        for p in (2, 3, 5, 7):
            while k % p == 0:
                k //= p
        if k == 1:
            return m
        m += 1
