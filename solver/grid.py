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
    """

    nx: int
    ny: int
    dx: float
    dy: float

    @classmethod
    def centred(cls, nx: int, ny: int, half_width_x: float, half_width_y: float) -> SurfaceGrid:
        """Grid covering [-half_width_x, half_width_x] x [-half_width_y, half_width_y] (m)."""
        return cls(nx, ny, 2.0 * half_width_x / nx, 2.0 * half_width_y / ny)

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
        return (np.arange(self.nx) - 0.5 * (self.nx - 1)) * self.dx

    @property
    def y(self) -> np.ndarray:
        """Cell-centre y coordinates (m)."""
        return (np.arange(self.ny) - 0.5 * (self.ny - 1)) * self.dy

    def mesh(self) -> tuple[np.ndarray, np.ndarray]:
        """Cell-centre coordinates as two (nx, ny) arrays (m), ``indexing="ij"``."""
        return np.meshgrid(self.x, self.y, indexing="ij")

    def offsets(self) -> tuple[np.ndarray, np.ndarray]:
        """Centre-to-centre offsets of the (2nx, 2ny) wrap-around convolution layout (m).

        Index ``i < nx`` holds offset ``i dx``, index ``2nx - i`` holds ``-i dx``; index ``nx``
        (an offset no pair of cells has) is set to ``nx dx`` and its kernel value is never used.
        """
        ix = np.fft.fftfreq(2 * self.nx, 1.0 / (2 * self.nx))
        iy = np.fft.fftfreq(2 * self.ny, 1.0 / (2 * self.ny))
        ix[self.nx] = self.nx
        iy[self.ny] = self.ny
        return np.meshgrid(ix * self.dx, iy * self.dy, indexing="ij")


@dataclass(frozen=True)
class VolumeGrid:
    """Surface grid plus ``nz`` cell-centred layers of thickness ``dz`` (m) below it."""

    surface: SurfaceGrid
    nz: int
    dz: float

    @property
    def z(self) -> np.ndarray:
        """Layer-centre depths (m), positive into body 2."""
        return (np.arange(self.nz) + 0.5) * self.dz

    @property
    def shape(self) -> tuple[int, int, int]:
        """(nx, ny, nz)."""
        return (self.surface.nx, self.surface.ny, self.nz)
