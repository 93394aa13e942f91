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
"""

from __future__ import annotations

import functools

import numpy as np

from ..bodies.materials import Pair
from ..numerics.grid import SurfaceGrid
from .convolution import REAL_SPECTRA, SurfaceOperator, wavenumbers


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
            inverse_k = np.hypot(kx, ky)
            np.divide(1.0, inverse_k, out=inverse_k, where=inverse_k > 0)
            ratio = inverse_k * inverse_k
            scale = 1.0 / (nx * ny)  # FFTW's backward transform is unnormalised
            compliance, coupling = self.pair.compliance, self.pair.shear_coupling
            bodies = (self.pair.body1, self.pair.body2)
            dilatation = bodies[1].dilatational_compliance - bodies[0].dilatational_compliance
            symbols = {
                "zz": 2.0 * compliance * inverse_k,
                "xx": 2.0 * inverse_k * (compliance + coupling - coupling * kx * kx * ratio),
                "yy": 2.0 * inverse_k * (compliance + coupling - coupling * ky * ky * ratio),
                "xy": -2.0 * inverse_k * coupling * kx * ky * ratio,
                "xp": 2j * dilatation * kx * ratio,
                "yp": 2j * dilatation * ky * ratio,
            }
            for key, symbol in symbols.items():
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


@functools.lru_cache(maxsize=8)
def periodic_surface_operator(
    grid: SurfaceGrid, pair: Pair, threads: int = 1, planner: str = "FFTW_ESTIMATE"
) -> PeriodicSurfaceOperator:
    """Cached :class:`PeriodicSurfaceOperator` for a period's grid and a pair."""
    return PeriodicSurfaceOperator(grid, pair, threads=threads, planner=planner)
