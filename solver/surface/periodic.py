r"""Periodic surface operators: the domain is one period of a nominally flat interface.

A field on the (nx, ny) grid of a domain ``Lx x Ly`` is one period of a doubly periodic field;
the displacements it causes are the periodic (circular) convolution with the influence of the
whole lattice of periods.  The kernels are the Fourier-space forms of the half-space solutions,
evaluated at the grid's discrete wavenumbers ``k = 2 pi (m / Lx, n / Ly)`` (Stanley & Kato
1997; the form Tamaas and most rough-contact codes use), with ``A`` the pair's compliance
(:attr:`~solver.bodies.materials.Pair.compliance`, 1/E*) and ``S`` its shear coupling:

* normal (Boussinesq): ``u_z(k) = (2 A / |k|) p(k)``;
* tangential (Cerruti): ``u_t(k) = (2 / |k|) [(A + S) I - S k k^T / |k|^2] q(k)``; along
  ``k`` it is Boussinesq's ``2 A / |k|``.  For one body, ``(1 + nu) / E = A + S`` and the
  bracket is ``(1 / (2 G)) (I - nu k k^T / |k|^2)``, the transform of Cerruti's point-force
  field (``1/r -> 2 pi / |k|``, ``x^2 / r^3 -> (2 pi / |k|)(1 - k_x^2 / |k|^2)``);
* the coupling of a pair with Dundurs' beta != 0: ``u_t(k) = 2 i (D_2 - D_1) k p(k) / |k|^2``
  with ``D_i = (1 + nu_i)(1 - 2 nu_i) / (2 E_i)`` the dilatational compliances
  (``A beta = D_1 - D_2``): Boussinesq's radial displacement ``-2 D P / (2 pi r)`` of each
  body, ``x / r^2 -> -2 pi i k_x / |k|^2``; the normal displacement of the shears is its
  transpose with the sign of :mod:`.convolution`.

The mean (``k = 0``) displacement of a periodic half-space is not defined (its lattice sum
diverges): it is set to zero, so the displacements have zero mean over the period and the rigid
approach of a contact solve takes up their mean.  These symbols are those of point values of the
continuous solution; the non-periodic operator's cell-integrated coefficients summed over the
lattice of periods (:mod:`.convolution` on a tiled domain) agree with them to a difference that
shrinks with the cell size, the coupling's sign included (``tests/test_periodic.py``).

:class:`YPeriodicSurfaceOperator` is periodic along y only (a line contact,
``grid.periodic = "y"``): the same forms on a long x period, cut back to the grid's offsets
along x (``tests/test_line_contact.py``: Hertz's plane-strain strip and Carter's rolling).
"""

from __future__ import annotations

import functools

import numpy as np

from ..bodies.materials import Pair
from ..numerics.grid import SurfaceGrid, fft_length
from .convolution import REAL_SPECTRA, SurfaceOperator, wavenumbers


def half_space_symbols(pair: Pair, kx: np.ndarray, ky: np.ndarray) -> dict[str, np.ndarray]:
    """Fourier-space kernels (m/Pa times m^2) of the module docstring at wavenumbers (rad/m).

    ``kx``, ``ky`` broadcast together; the ``k = 0`` value of every block is zero.
    """
    inverse_k = np.hypot(kx, ky)
    np.divide(1.0, inverse_k, out=inverse_k, where=inverse_k > 0)
    ratio = inverse_k * inverse_k
    compliance, coupling = pair.compliance, pair.shear_coupling
    dilatation = pair.body2.dilatational_compliance - pair.body1.dilatational_compliance
    return {
        "zz": 2.0 * compliance * inverse_k,
        "xx": 2.0 * inverse_k * (compliance + coupling - coupling * kx * kx * ratio),
        "yy": 2.0 * inverse_k * (compliance + coupling - coupling * ky * ky * ratio),
        "xy": -2.0 * inverse_k * coupling * kx * ky * ratio,
        "xp": 2j * dilatation * kx * ratio,
        "yp": 2j * dilatation * ky * ratio,
    }


class PeriodicSurfaceOperator(SurfaceOperator):
    """Relative surface displacements of a pair of half-spaces from periodic cell tractions.

    The same interface as :class:`~.convolution.SurfaceOperator` (tractions on body 2 in Pa,
    displacements of body 2 minus body 1 in m), on a grid that is one period: no padding, the
    FFTs have the grid's own lengths, and every kernel is the Fourier-space form of the module
    docstring (zero mean).
    """

    #: True: the grid is one period of the surface.
    periodic = True

    def kernel_spectrum(self, name: str) -> np.ndarray:
        """Normalised spectrum of kernel block ``name``: zz, xx, yy, xy, xp, yp (all made once)."""
        if not self._kernels:
            nx, ny = self.grid.shape
            kx, ky = wavenumbers(self.grid, (nx, ny))
            scale = 1.0 / (nx * ny)  # FFTW's backward transform is unnormalised
            for key, symbol in half_space_symbols(self.pair, kx, ky).items():
                spectrum = np.ascontiguousarray(symbol * scale)
                self._kernels[key] = spectrum if key in REAL_SPECTRA else spectrum.astype(complex)
        if name not in self._kernels:
            raise ValueError(f"unknown kernel block {name!r}; use one of {sorted(self._kernels)}")
        return self._kernels[name]

    @staticmethod
    def periodic_lengths(grid: SurfaceGrid) -> tuple[int, int]:
        """FFT lengths of the preconditioners: the period's own (exact inverses)."""
        return grid.nx, grid.ny

    @staticmethod
    def padded_lengths(grid: SurfaceGrid) -> tuple[int, int]:
        """FFT lengths of the convolution: the period's own, no padding."""
        return grid.nx, grid.ny


#: Lengths of the x periods the y-periodic kernels are cut from, in padded lengths: the modes
#: that vary along y (their kernels decay over the y period) and the mode uniform along y
#: (plane strain, a logarithmic kernel).  Images a period D away change the kernels' slope
#: within the grid by O((Lx / D)^2).
X_EXTENSION, X_EXTENSION_PLANE = 8, 512


def _odd_trend(column: np.ndarray, period: int) -> np.ndarray:
    """Slope (per cell) of the odd part of a periodic kernel column between P/4 and P/2.

    A kernel odd in x that tends to constants of opposite signs (the plane-strain coupling's
    ``sgn x``) has, as a zero-mean periodic function, the slope ``-2c/P`` everywhere but at its
    jump; this slope, subtracted, restores the aperiodic kernel (even kernels have no odd part).
    """
    first, last = period // 4, period // 2 - 1
    odd = 0.5 * (column[[first, last]] - column[[period - first, period - last]])
    return (odd[1] - odd[0]) / (last - first)


class YPeriodicSurfaceOperator(SurfaceOperator):
    """Relative surface displacements of a surface periodic along y and open along x.

    The grid is one period along y (``Ly = ny dy``) and the whole surface along x: the
    tractions vanish beyond it in x (a line contact along y: a cylinder's, a roller's).  The
    convolution is circular along y and linear along x (zero-padded as in
    :class:`~.convolution.SurfaceOperator`, FFT lengths ``(Lx, ny)``).  The kernels are the
    module's Fourier-space forms on a long x period (:data:`X_EXTENSION` padded lengths for
    the modes that vary along y, :data:`X_EXTENSION_PLANE` for the uniform one), transformed
    back along x and cut to the offsets the grid has.  As on a periodic grid, the displacement
    of a load uniform along y is defined up to a constant only (the plane-strain kernel is
    logarithmic; here it has zero mean over its long period): the rigid approach of a contact
    solve takes it up.
    """

    def kernel_spectrum(self, name: str) -> np.ndarray:
        """Normalised spectrum of kernel block ``name``: zz, xx, yy, xy, xp, yp (all made once)."""
        if not self._kernels:
            nx, ny = self.grid.shape
            lx = self.lengths[0]
            mixed: dict[str, np.ndarray] = {}  # kernels at x offsets, per mode along y
            ky_all = 2 * np.pi * np.fft.fftfreq(ny, self.grid.dy)[None, :]
            for factor, modes in ((X_EXTENSION, slice(1, None)), (X_EXTENSION_PLANE, slice(0, 1))):
                period = fft_length(factor * lx)
                kx = 2 * np.pi * np.fft.fftfreq(period, self.grid.dx)[:, None]
                for key, symbol in half_space_symbols(self.pair, kx, ky_all[:, modes]).items():
                    along = np.fft.ifft(symbol, axis=0)
                    if modes.start == 0:  # the plane mode: undo the period's odd linear trend
                        along = (
                            along
                            - _odd_trend(along, period)[:, None]
                            * ((np.arange(period) + period // 2) % period - period // 2)[:, None]
                        )
                    out = mixed.setdefault(key, np.zeros((lx, ny), dtype=complex))
                    out[:nx, modes] = along[:nx]
                    out[lx - nx + 1 :, modes] = along[period - nx + 1 :]
            scale = 1.0 / (lx * ny)  # FFTW's backward transform is unnormalised
            for key, values in mixed.items():
                kernel = np.fft.ifft(values, axis=1).real
                spectrum = self._transform(kernel) * scale
                if key in REAL_SPECTRA:
                    spectrum = np.ascontiguousarray(spectrum.real)
                self._kernels[key] = spectrum
        if name not in self._kernels:
            raise ValueError(f"unknown kernel block {name!r}; use one of {sorted(self._kernels)}")
        return self._kernels[name]

    @staticmethod
    def periodic_lengths(grid: SurfaceGrid) -> tuple[int, int]:
        """FFT lengths of the preconditioners: smooth along x, the period's own along y."""
        return fft_length(grid.nx), grid.ny

    @staticmethod
    def padded_lengths(grid: SurfaceGrid) -> tuple[int, int]:
        """FFT lengths of the convolution: zero-padded along x, the period's own along y."""
        return fft_length(2 * grid.nx - 1), grid.ny


@functools.lru_cache(maxsize=8)
def periodic_surface_operator(
    grid: SurfaceGrid, pair: Pair, threads: int = 1, planner: str = "FFTW_ESTIMATE"
) -> PeriodicSurfaceOperator:
    """Cached :class:`PeriodicSurfaceOperator` for a period's grid and a pair."""
    return PeriodicSurfaceOperator(grid, pair, threads=threads, planner=planner)


@functools.lru_cache(maxsize=8)
def y_periodic_surface_operator(
    grid: SurfaceGrid, pair: Pair, threads: int = 1, planner: str = "FFTW_ESTIMATE"
) -> YPeriodicSurfaceOperator:
    """Cached :class:`YPeriodicSurfaceOperator` for a grid (one period along y) and a pair."""
    return YPeriodicSurfaceOperator(grid, pair, threads=threads, planner=planner)
