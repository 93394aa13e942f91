"""DC-FFT surface operators: non-periodic convolution of cell tractions with the influence kernels.

Discrete convolution–FFT (Liu, Wang & Liu 2000): a field on the (nx, ny) grid is zero-padded to
(2nx, 2ny), the kernel is laid out in wrap-around order on the same padded grid
(:meth:`solver.grid.SurfaceGrid.offsets`), and the cyclic convolution of the padded arrays, cut
back to (nx, ny), equals the linear (aperiodic) sum ``u_i = sum_j K(x_i - x_j) f_j`` exactly up to
round-off.

FFT normalisation: the forward real transform is unnormalised; the inverse is FFTW's
unnormalised backward transform, so the factor 1/(4 nx ny) is folded into the stored kernel
spectra once.  Kernel spectra and pyfftw plans are built once per operator and reused across
iterations, load steps and cases of the same grid and materials (:func:`surface_operator`).
"""

from __future__ import annotations

import functools

import numpy as np
import pyfftw

from .grid import SurfaceGrid
from .influence import surface_kernels
from .materials import Pair

_TANGENTIAL_TO_NORMAL_SIGN = -1.0  # u_z per q_x at offset d equals -(u_x per p)(d)


class SurfaceOperator:
    """Relative surface displacements of a pair of half-spaces from cell tractions.

    Parameters
    ----------
    grid : SurfaceGrid
        The surface grid.
    pair : Pair
        The two bodies.
    threads : int
        FFTW threads (1 by default; one per MPI rank is the usual choice).
    planner : str
        FFTW planner effort, ``"FFTW_ESTIMATE"`` or ``"FFTW_MEASURE"``.

    Notes
    -----
    Tractions are those acting on body 2, ``(q_x, q_y, p)`` in Pa; displacements are body 2 minus
    body 1 in m (see :mod:`solver.influence`).
    """

    def __init__(
        self, grid: SurfaceGrid, pair: Pair, threads: int = 1, planner: str = "FFTW_ESTIMATE"
    ):
        self.grid = grid
        self.pair = pair
        nx, ny = grid.shape
        self._padded = pyfftw.empty_aligned((2 * nx, 2 * ny), dtype="float64")
        self._spectrum = pyfftw.empty_aligned((2 * nx, ny + 1), dtype="complex128")
        self._output = pyfftw.empty_aligned((2 * nx, 2 * ny), dtype="float64")
        self._padded[...] = 0.0
        flags = (planner,)
        self._forward = pyfftw.FFTW(
            self._padded, self._spectrum, axes=(0, 1), flags=flags, threads=threads
        )
        self._backward = pyfftw.FFTW(
            self._spectrum,
            self._output,
            axes=(0, 1),
            direction="FFTW_BACKWARD",
            flags=(*flags, "FFTW_DESTROY_INPUT"),
            threads=threads,
        )
        self._padded[...] = 0.0
        self._kernels: dict[str, np.ndarray] = {}
        self._precondition = None
        self._planner = planner

    def kernel_spectrum(self, name: str) -> np.ndarray:
        """Normalised spectrum of kernel block ``name`` (:data:`solver.influence.COMPONENTS`)."""
        if name not in self._kernels:
            ox, oy = self.grid.offsets()
            kernels = surface_kernels(self.pair, ox, oy, self.grid.dx, self.grid.dy)
            scale = 1.0 / (4 * self.grid.nx * self.grid.ny)
            wanted = ("zz",) if name == "zz" else tuple(k for k in kernels if k != "zz")
            for key in wanted:
                self._kernels[key] = self._transform(kernels[key]) * scale
        return self._kernels[name]

    def _transform(self, padded_field: np.ndarray) -> np.ndarray:
        self._padded[...] = padded_field
        self._forward.execute()
        out = self._spectrum.copy()
        self._padded[...] = 0.0
        return out

    def spectrum(self, field: np.ndarray) -> np.ndarray:
        """Forward transform of a zero-padded (nx, ny) field (a new complex array)."""
        nx, ny = self.grid.shape
        self._padded[:nx, :ny] = field
        self._forward.execute()
        return self._spectrum.copy()

    def inverse(self, spectrum: np.ndarray) -> np.ndarray:
        """Backward transform cut to the (nx, ny) grid (a new real array)."""
        nx, ny = self.grid.shape
        self._spectrum[...] = spectrum
        self._backward.execute()
        return self._output[:nx, :ny].copy()

    def apply(self, name: str, field: np.ndarray) -> np.ndarray:
        """Convolve ``field`` (Pa) with kernel block ``name``; returns displacements (m)."""
        kernel = self.kernel_spectrum(name)
        nx, ny = self.grid.shape
        self._padded[:nx, :ny] = field
        self._forward.execute()
        np.multiply(self._spectrum, kernel, out=self._spectrum)  # in place: no temporaries
        self._backward.execute()
        return self._output[:nx, :ny].copy()

    def inverse_normal(self, displacement: np.ndarray) -> np.ndarray:
        """Approximate inverse of :meth:`normal` (a preconditioner): pressure (Pa) from u_z (m).

        Applies the inverse Boussinesq symbol |k|/(2A) with a periodic FFT on the unpadded grid,
        a quarter of the cost of :meth:`normal`; exact for periodic data and point tractions.
        """
        if self._precondition is None:
            nx, ny = self.grid.shape
            real = pyfftw.empty_aligned((nx, ny), dtype="float64")
            spectrum = pyfftw.empty_aligned((nx, ny // 2 + 1), dtype="complex128")
            forward = pyfftw.FFTW(real, spectrum, axes=(0, 1), flags=(self._planner,))
            backward = pyfftw.FFTW(
                spectrum, real, axes=(0, 1), direction="FFTW_BACKWARD",
                flags=(self._planner, "FFTW_DESTROY_INPUT"),
            )  # fmt: skip
            kx = 2 * np.pi * np.fft.fftfreq(nx, self.grid.dx)
            ky = 2 * np.pi * np.fft.rfftfreq(ny, self.grid.dy)
            symbol = np.hypot(kx[:, None], ky[None, :]) / (2 * self.pair.compliance * nx * ny)
            self._precondition = (real, spectrum, forward, backward, symbol)
        real, spectrum, forward, backward, symbol = self._precondition
        real[...] = displacement
        forward.execute()
        np.multiply(spectrum, symbol, out=spectrum)
        backward.execute()
        return real.copy()

    def normal(self, pressure: np.ndarray) -> np.ndarray:
        """u_z (m) from pressure ``p`` (Pa)."""
        return self.apply("zz", pressure)

    def displacement(
        self, shear_x: np.ndarray, shear_y: np.ndarray, pressure: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """All three relative displacements (m) from (q_x, q_y, p) (Pa)."""
        sx, sy, sp = self.spectrum(shear_x), self.spectrum(shear_y), self.spectrum(pressure)
        k = self.kernel_spectrum
        kxy = k("xy")
        ux = self.inverse(k("xx") * sx + kxy * sy + k("xp") * sp)
        uy = self.inverse(kxy * sx + k("yy") * sy + k("yp") * sp)
        s = _TANGENTIAL_TO_NORMAL_SIGN
        uz = self.inverse(s * (k("xp") * sx + k("yp") * sy) + k("zz") * sp)
        return ux, uy, uz

    def tangential(self, shear_x: np.ndarray, shear_y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(u_x, u_y) (m) from shear tractions (q_x, q_y) (Pa), the tangential block only."""
        sx, sy = self.spectrum(shear_x), self.spectrum(shear_y)
        k = self.kernel_spectrum
        kxy = k("xy")
        return self.inverse(k("xx") * sx + kxy * sy), self.inverse(kxy * sx + k("yy") * sy)

    def normal_from_shear(self, shear_x: np.ndarray, shear_y: np.ndarray) -> np.ndarray:
        """u_z (m) from shear tractions (Pa): the beta coupling term."""
        k = self.kernel_spectrum
        spec = k("xp") * self.spectrum(shear_x) + k("yp") * self.spectrum(shear_y)
        return _TANGENTIAL_TO_NORMAL_SIGN * self.inverse(spec)

    def tangential_from_pressure(self, pressure: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(u_x, u_y) (m) from pressure (Pa): the beta coupling term."""
        sp = self.spectrum(pressure)
        return self.inverse(self.kernel_spectrum("xp") * sp), self.inverse(
            self.kernel_spectrum("yp") * sp
        )

    def tangential_norm(self) -> float:
        """Largest eigenvalue (m/Pa) of the circulant tangential block, >= that of K_t."""
        k = self.kernel_spectrum
        a, b, d = k("xx"), k("xy"), k("yy")
        half = 0.5 * (a.real + d.real)
        radius = np.sqrt((0.5 * (a.real - d.real)) ** 2 + np.abs(b) ** 2)
        return float((np.abs(half) + radius).max()) * 4 * self.grid.nx * self.grid.ny

    @staticmethod
    def memory_bytes(grid: SurfaceGrid, tangential: bool) -> int:
        """Bytes held by an operator: FFT buffers plus the cached kernel spectra."""
        nx, ny = grid.shape
        real = 8 * 4 * nx * ny
        spec = 16 * 2 * nx * (ny + 1)
        return 2 * real + spec * (1 + (6 if tangential else 1))


@functools.lru_cache(maxsize=8)
def surface_operator(
    grid: SurfaceGrid, pair: Pair, threads: int = 1, planner: str = "FFTW_ESTIMATE"
) -> SurfaceOperator:
    """Cached :class:`SurfaceOperator` for a grid and a pair (reused across cases)."""
    return SurfaceOperator(grid, pair, threads=threads, planner=planner)
