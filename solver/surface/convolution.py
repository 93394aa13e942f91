"""DC-FFT surface operators: non-periodic convolution of cell tractions with the influence kernels.

Discrete convolution–FFT (Liu, Wang & Liu 2000): a field on the (nx, ny) grid is zero-padded to
(Lx, Ly), the smallest 7-smooth lengths >= (2nx - 1, 2ny - 1)
(:func:`solver.numerics.grid.fft_length`), the kernel is laid out in wrap-around order on the same
padded grid (:meth:`solver.numerics.grid.SurfaceGrid.offsets`), and the cyclic convolution of the
padded arrays, cut back to (nx, ny), equals the linear (aperiodic) sum ``u_i = sum_j K(x_i - x_j)
f_j`` exactly up to round-off.

FFT normalisation: the forward real transform is unnormalised; the inverse is FFTW's
unnormalised backward transform, so the factor 1/(Lx Ly) is folded into the stored kernel
spectra once.  Kernel spectra and pyfftw plans are built once per operator and reused across
iterations, load steps and cases of the same grid and materials (:func:`surface_operator`).
"""

from __future__ import annotations

import functools

import numpy as np

from ..bodies.materials import Pair
from ..numerics.fftw import empty_aligned, plan
from ..numerics.grid import SurfaceGrid, fft_length
from .influence import COMPONENTS, surface_kernels

#: Kernel blocks with real spectra (even, or odd in both x and y).
REAL_SPECTRA = ("zz", "xx", "yy", "xy")
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
    body 1 in m (see :mod:`solver.surface.influence`).
    """

    #: False: the grid is the whole surface, the tractions vanish outside it (DC-FFT).
    periodic = False

    def __init__(
        self, grid: SurfaceGrid, pair: Pair, threads: int = 1, planner: str = "FFTW_ESTIMATE"
    ):
        self.grid = grid
        self.pair = pair
        self.lengths = self.padded_lengths(grid)
        lx, ly = self.lengths
        self._padded = empty_aligned((lx, ly), dtype="float64")
        self._spectrum = empty_aligned((lx, ly // 2 + 1), dtype="complex128")
        self._output = empty_aligned((lx, ly), dtype="float64")
        self._padded[...] = 0.0
        self._forward = plan(
            self._padded, self._spectrum, axes=(0, 1), planner=planner, threads=threads
        )
        self._backward = plan(
            self._spectrum,
            self._output,
            axes=(0, 1),
            direction="FFTW_BACKWARD",
            planner=planner,
            threads=threads,
            extra=("FFTW_DESTROY_INPUT",),
        )
        self._padded[...] = 0.0
        self._kernels: dict[str, np.ndarray] = {}
        self._precondition = None
        self._batches: dict[tuple[int, int], tuple] = {}
        self._tangential_precondition = None
        self._diagonal = None
        self.planner = planner

    def place(self, grid: SurfaceGrid) -> SurfaceOperator:
        """Put this operator's cells at another place: ``grid``, the same cells (returns self).

        The convolution depends on the cells' offsets only (kernels, plans and preconditioners
        stay); the grid's place serves the coordinates (:meth:`SurfaceGrid.mesh`): the window
        that follows a moving contact (:mod:`solver.drive.window`) is placed anew every increment.
        """
        if (grid.nx, grid.ny, grid.dx, grid.dy) != (
            self.grid.nx, self.grid.ny, self.grid.dx, self.grid.dy
        ):  # fmt: skip
            raise ValueError(f"a placed grid must have the same cells: {grid} vs {self.grid}")
        self.grid = grid
        return self

    def kernel_spectrum(self, name: str) -> np.ndarray:
        """Normalised spectrum of kernel block ``name`` (:data:`.influence.COMPONENTS`).

        The offsets no pair of cells has are set to zero, so each kernel keeps its parity in x
        and y over the whole wrap-around layout: the even ``zz``, ``xx``, ``yy`` and the odd-odd
        ``xy`` then have real spectra, stored as real arrays (half the work per product).
        """
        if name not in self._kernels:
            ox, oy = self.grid.offsets(self.lengths)
            wanted = ("zz",) if name == "zz" else tuple(k for k in COMPONENTS if k != "zz")
            kernels = surface_kernels(self.pair, ox, oy, self.grid.dx, self.grid.dy, wanted)
            nx, ny = self.grid.shape
            (lx, ly), scale = self.lengths, 1.0 / (self.lengths[0] * self.lengths[1])
            for key in wanted:
                kernel = np.array(kernels[key], dtype=float)
                kernel[nx : lx - nx + 1, :] = 0.0
                kernel[:, ny : ly - ny + 1] = 0.0
                spectrum = self._transform(kernel) * scale
                if key in REAL_SPECTRA:
                    spectrum = np.ascontiguousarray(spectrum.real)
                self._kernels[key] = spectrum
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

        Applies the inverse Boussinesq symbol |k|/(2A) with a periodic FFT on the grid (extended
        to the smooth lengths :meth:`periodic_lengths`), a quarter of the cost of :meth:`normal`;
        exact for periodic data and point tractions.
        """
        if self._precondition is None:
            real, spectrum, forward, backward, kx, ky = self._periodic_plans(())
            nx, ny = real.shape
            symbol = np.hypot(kx, ky) / (2 * self.pair.compliance * nx * ny)
            self._precondition = (real, spectrum, forward, backward, symbol)
        real, spectrum, forward, backward, symbol = self._precondition
        nx, ny = self.grid.shape
        real[...] = 0.0
        real[:nx, :ny] = displacement
        forward.execute()
        np.multiply(spectrum, symbol, out=spectrum)
        backward.execute()
        return real[:nx, :ny].copy()

    def _periodic_plans(self, batch: tuple[int, ...]) -> tuple:
        """Buffers, FFT plans and wavenumbers (rad/m) of the periodic preconditioners.

        On :meth:`periodic_lengths`, with leading ``batch`` axes; kx, ky broadcast together.
        """
        nx, ny = self.periodic_lengths(self.grid)
        axes = (len(batch), len(batch) + 1)
        real = empty_aligned((*batch, nx, ny), dtype="float64")
        spectrum = empty_aligned((*batch, nx, ny // 2 + 1), dtype="complex128")
        forward = plan(real, spectrum, axes=axes, planner=self.planner)
        backward = plan(
            spectrum, real, axes=axes, direction="FFTW_BACKWARD", planner=self.planner,
            extra=("FFTW_DESTROY_INPUT",),
        )  # fmt: skip
        return real, spectrum, forward, backward, *wavenumbers(self.grid, (nx, ny))

    def inverse_tangential(
        self, displacement_x: np.ndarray, displacement_y: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """Approximate inverse of :meth:`tangential` (a preconditioner): shear (Pa) from u_t (m).

        :func:`cerruti_inverse` applied with periodic FFTs on the grid (extended like
        :meth:`inverse_normal`).
        """
        if self._tangential_precondition is None:
            real, spectrum, forward, backward, kx, ky = self._periodic_plans((2,))
            nx, ny = real.shape[1:]
            work = np.empty(spectrum.shape[1:], dtype=complex)
            symbols = cerruti_inverse(self.pair, kx, ky, nx * ny)
            self._tangential_precondition = (real, spectrum, work, forward, backward, *symbols)
        real, spectrum, work, forward, backward, cxx, cyy, cxy = self._tangential_precondition
        nx, ny = self.grid.shape
        real[...] = 0.0
        real[0, :nx, :ny] = displacement_x
        real[1, :nx, :ny] = displacement_y
        forward.execute()
        sx, sy = spectrum
        np.multiply(cxy, sx, out=work)
        sx *= cxx
        sx += cxy * sy
        sy *= cyy
        sy += work
        backward.execute()
        return real[0, :nx, :ny].copy(), real[1, :nx, :ny].copy()

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

    def batch_transforms(self, lengths: tuple[int, int] | None = None) -> tuple:
        """Buffers and FFT plans for two fields at once, made once per ``lengths``.

        ``(padded, spectrum, work, output, forward, backward)``: ``padded`` (2, Lx, Ly), zero
        where no field is written (fields are written into its (nx, ny) corner), ``spectrum``
        and ``work`` (2, Lx, Ly // 2 + 1), ``output`` (2, Lx, Ly); ``forward`` transforms
        ``padded`` into ``spectrum``, ``backward`` ``spectrum`` into ``output`` (destroying
        ``spectrum``).  The padded lengths' (the default) serve :meth:`tangential`; others
        serve :class:`solver.surface.steady.SteadyOperator` (on the contact's box).
        """
        lengths = self.lengths if lengths is None else tuple(lengths)
        if lengths in self._batches:
            return self._batches[lengths]
        lx, ly = lengths
        padded = empty_aligned((2, lx, ly), dtype="float64")
        spectrum = empty_aligned((2, lx, ly // 2 + 1), dtype="complex128")
        work = empty_aligned((2, lx, ly // 2 + 1), dtype="complex128")
        output = empty_aligned((2, lx, ly), dtype="float64")
        forward = plan(padded, spectrum, axes=(1, 2), planner=self.planner)
        backward = plan(
            spectrum, output, axes=(1, 2), direction="FFTW_BACKWARD", planner=self.planner,
            extra=("FFTW_DESTROY_INPUT",),
        )  # fmt: skip
        padded[...] = 0.0  # after planning, which may write into the arrays
        self._batches[lengths] = (padded, spectrum, work, output, forward, backward)
        return self._batches[lengths]

    def tangential(self, shear_x: np.ndarray, shear_y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(u_x, u_y) (m) from shear tractions (q_x, q_y) (Pa), the tangential block only.

        The slip-stick loop's inner operator: both components go through one batched transform
        pair on preallocated buffers, and the 2x2 spectral product is formed in place.
        """
        padded, spectrum, work, output, forward, backward = self.batch_transforms()
        k = self.kernel_spectrum
        nx, ny = self.grid.shape
        padded[0, :nx, :ny] = shear_x
        padded[1, :nx, :ny] = shear_y
        forward.execute()
        sx, sy = spectrum
        np.multiply(k("xy"), sy, out=work[0])
        np.multiply(k("xy"), sx, out=work[1])
        sx *= k("xx")
        sx += work[0]
        sy *= k("yy")
        sy += work[1]
        backward.execute()
        return output[0, :nx, :ny].copy(), output[1, :nx, :ny].copy()

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

    def tangential_diagonal(self) -> float:
        """Self-compliance (m/Pa) of a cell: u_x at a cell per unit q_x on it (larger of x, y)."""
        if self._diagonal is None:
            nx, ny = self.grid.shape
            unit = np.zeros(self.grid.shape)
            unit[nx // 2, ny // 2] = 1.0
            xx = self.tangential(unit, np.zeros_like(unit))[0][nx // 2, ny // 2]
            yy = self.tangential(np.zeros_like(unit), unit)[1][nx // 2, ny // 2]
            self._diagonal = float(max(xx, yy))
        return self._diagonal

    def tangential_norm(self) -> float:
        """Largest eigenvalue (m/Pa) of the circulant tangential block, >= that of K_t."""
        k = self.kernel_spectrum
        a, b, d = k("xx"), k("xy"), k("yy")
        half = 0.5 * (a.real + d.real)
        radius = np.sqrt((0.5 * (a.real - d.real)) ** 2 + np.abs(b) ** 2)
        return float((np.abs(half) + radius).max()) * self.lengths[0] * self.lengths[1]

    @staticmethod
    def periodic_lengths(grid: SurfaceGrid) -> tuple[int, int]:
        """FFT lengths of the periodic preconditioners: the grid's, rounded up to smooth ones."""
        return fft_length(grid.nx), fft_length(grid.ny)

    @staticmethod
    def padded_lengths(grid: SurfaceGrid) -> tuple[int, int]:
        """Zero-padded FFT lengths (Lx, Ly) of the DC-FFT (module docstring)."""
        return fft_length(2 * grid.nx - 1), fft_length(2 * grid.ny - 1)

    @staticmethod
    def memory_bytes(grid: SurfaceGrid, tangential: bool) -> int:
        """Bytes held by an operator: FFT buffers plus the cached kernel spectra."""
        lx, ly = SurfaceOperator.padded_lengths(grid)
        real = 8 * lx * ly
        spec = 16 * lx * (ly // 2 + 1)
        pair = 4 * real + 4 * spec if tangential else 0  # batched buffers of :meth:`tangential`
        kernels = spec // 2 * (4 if tangential else 1) + (2 * spec if tangential else 0)
        return 2 * real + spec + kernels + pair


def cerruti_inverse(
    pair: Pair, kx: np.ndarray, ky: np.ndarray, cells: int = 1
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The inverse of the pair's periodic tangential symbol over ``cells``: (c_xx, c_yy, c_xy).

    The periodic symbol of the tangential block is ``(2/|k|) [(A + S) I - S k k^T/k^2]``
    (Cerruti; ``A`` the pair's compliance (1/Pa), ``S`` its shear coupling, so that along ``k``
    it is Boussinesq's ``2A/|k|``); its inverse is
    ``(|k|/2) [k k^T/(k^2 A) + (I - k k^T/k^2)/(A + S)]`` (Pa/m; zero at ``k = 0``), at
    wavenumbers ``kx``, ``ky`` (rad/m, broadcast together), divided by ``cells`` (the FFT's
    size: FFTW's backward transform is unnormalised).
    """
    k2 = kx * kx + ky * ky
    along = 1.0 / pair.compliance
    across = 1.0 / (pair.compliance + pair.shear_coupling)
    ratio = np.divide(1.0, k2, out=np.zeros_like(k2), where=k2 > 0)
    factor = 0.5 * np.sqrt(k2) / cells
    cxx = factor * (across + (along - across) * kx * kx * ratio)
    cyy = factor * (across + (along - across) * ky * ky * ratio)
    cxy = factor * (along - across) * kx * ky * ratio
    return cxx, cyy, cxy


def wavenumbers(grid: SurfaceGrid, lengths: tuple[int, int]) -> tuple[np.ndarray, np.ndarray]:
    """Wavenumbers kx (column) and ky (row, real-FFT half) (rad/m) of FFTs of ``lengths``."""
    kx = 2 * np.pi * np.fft.fftfreq(lengths[0], grid.dx)[:, None]
    ky = 2 * np.pi * np.fft.rfftfreq(lengths[1], grid.dy)[None, :]
    return kx, ky


@functools.lru_cache(maxsize=8)
def surface_operator(
    grid: SurfaceGrid, pair: Pair, threads: int = 1, planner: str = "FFTW_ESTIMATE"
) -> SurfaceOperator:
    """Cached :class:`SurfaceOperator` for a grid and a pair (reused across cases)."""
    return SurfaceOperator(grid, pair, threads=threads, planner=planner)
