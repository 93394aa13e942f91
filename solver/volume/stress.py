"""Stresses inside an elastic half-space loaded by piecewise-constant surface tractions.

The layer kernels of a uniformly loaded cell are the closed forms of
:mod:`solver.theory.half_space` (Love's rectangle, its Cerruti counterpart) at the cell
corners; :class:`SubsurfaceStressOperator` convolves them with the tractions layer by layer
with FFTs.  Conventions as there: ``z`` down into body 2, stresses positive in tension, in the
order :data:`STRESS_COMPONENTS` = (xx, yy, zz, yz, xz, xy).
"""

from __future__ import annotations

import functools
from typing import TYPE_CHECKING

import numpy as np

from ..numerics.fftw import empty_aligned, plan
from ..numerics.grid import IndexBox, VolumeGrid
from ..numerics.images import far_images, fold_signed, image_reach
from ..numerics.tensor import COMPONENTS
from ..numerics.threads import copy_by_rows, each
from ..theory.half_space import (
    POTENTIAL_DERIVATIVES,
    TRACTIONS,
    corner_functions,
    stress_from_potential,
    uniform_traction_stress,
)

if TYPE_CHECKING:
    import pyfftw

#: Order of the six stress components in every array returned here (:mod:`solver.numerics.tensor`).
STRESS_COMPONENTS = COMPONENTS

_AXES = {"xx": (0, 0), "yy": (1, 1), "zz": (2, 2), "yz": (1, 2), "xz": (0, 2), "xy": (0, 1)}
_TRACTION_AXIS = {"pressure": None, "shear_x": 0, "shear_y": 1}


def kernel_parity(component: str, traction: str) -> tuple[int, int]:
    """Parity (0 even, 1 odd) in x and in y of a traction-to-stress kernel.

    A component is odd in x when x appears an odd number of times among its indices and the
    traction direction.  Even-even and odd-odd kernels have real Fourier transforms, the others
    imaginary ones.
    """
    idx = list(_AXES[component])
    axis = _TRACTION_AXIS[traction]
    if axis is not None:
        idx.append(axis)
    return idx.count(0) % 2, idx.count(1) % 2


def wrap_layout(values: np.ndarray, axes: tuple[int, int], out: np.ndarray) -> np.ndarray:
    """Put offsets ``-(n-1) .. n-1`` (length ``2n - 1``) in wrap-around order of length ``2n``.

    Along both ``axes`` of ``values``, into ``out`` (length ``2n`` along them, the other axes
    as ``values``'), which is returned.  Slot ``i < n`` holds offset ``i``, slot ``2n - i``
    offset ``-i``; slot ``n`` (an offset no pair of cells has) is zero, which keeps even and
    odd kernels exactly symmetric.
    """
    values = np.moveaxis(values, axes, (0, 1))
    target = np.moveaxis(out, axes, (0, 1))
    n, m = (values.shape[0] + 1) // 2, (values.shape[1] + 1) // 2
    for to, source in ((slice(0, n), slice(n - 1, None)), (slice(n + 1, None), slice(0, n - 1))):
        target[to, :m] = values[source, m - 1 :]
        target[to, m + 1 :] = values[source, : m - 1]
        target[to, m] = 0.0
    target[n] = 0.0
    return out


def _corner_lattice(n: int, d: float) -> np.ndarray:
    """Corner coordinates ``(j + 1/2) d``, ``j = -n .. n-1``: the cell edges of all offsets."""
    return (np.arange(-n, n) + 0.5) * d


def layer_kernels(
    grid: VolumeGrid, nu: float, traction: str, layers, threads: int = 1
) -> np.ndarray:
    """Traction-to-stress kernels of the grid's cells at the given layers, wrap-around layout.

    Parameters
    ----------
    grid : VolumeGrid
        The volume grid (cell sizes and depths).
    nu : float
        Poisson's ratio.
    traction : {"pressure", "shear_x", "shear_y"}
        Unit traction on one surface cell.
    layers : sequence of int
        Layer indices.
    threads : int
        Threads that share the layers.

    Returns
    -------
    ndarray
        Shape ``(6, Lx, Ly, len(layers))`` (:meth:`~solver.numerics.grid.VolumeGrid.fft_lengths`):
        stress (Pa per Pa) at offset ``(i dx, j dy)`` in slot ``(i mod Lx, j mod Ly)`` (slots
        nx, ny zero when padded; the periodised kernel's own offsets on a periodic grid).
    """
    s = grid.surface
    if grid.periodic:  # the offsets the periodic images reach
        reach = image_reach(s.nx), image_reach(s.ny)
        cx = (np.arange(-reach[0] - 1, reach[0] + 1) + 0.5) * s.dx
        cy = (np.arange(-reach[1] - 1, reach[1] + 1) + 0.5) * s.dy
        cx, cy = cx[:, None], cy[None, :]
    else:
        cx = _corner_lattice(s.nx, s.dx)[:, None]
        cy = _corner_lattice(s.ny, s.dy)[None, :]
    names = POTENTIAL_DERIVATIVES[traction]
    layers = list(layers)
    out = np.empty((6, *grid.fft_lengths(), len(layers)))

    def layer(n: int) -> None:
        z = float(grid.z[layers[n]])
        f = corner_functions(cx, cy, z, names)
        w = {name: np.diff(np.diff(v, axis=0), axis=1) for name, v in f.items()}
        sigma = stress_from_potential(w, z, nu, traction)
        if grid.periodic:
            mean = uniform_traction_stress(traction, nu)
            parities = [kernel_parity(c, traction) for c in STRESS_COMPONENTS]
            out[..., n] = _periodised(sigma, s.nx, s.ny, mean, parities)
        else:
            wrap_layout(sigma, (1, 2), out[..., n])

    each(layer, range(len(layers)), threads)
    return out


def _periodised(
    kernels: np.ndarray, nx: int, ny: int, mean: np.ndarray, parities: list
) -> np.ndarray:
    """Kernels ``(6, 2Lx + 1, 2Ly + 1)`` at signed offsets made periodic, at ``-(n-1) .. n-1``.

    Folded over the periodic images (:mod:`solver.numerics.images`), the far images' first
    and second orders added (``parities``: (x, y) per component,
    :func:`~solver.numerics.images.far_images`), each component's sum over one period set to
    ``mean`` (the response to a uniform traction: the far images' share of the mean, which the
    truncated sum misses).  Returns ``(6, nx, ny)``: offsets ``0 .. n - 1``, the circular
    convolution's own layout.
    """
    period = fold_signed(fold_signed(kernels, nx, 1), ny, 2)
    for c, parity in enumerate(parities):
        edges = {"x": kernels[c, -3:, :], "y": np.swapaxes(kernels[c, :, -3:], 0, 1)}
        period[c] += far_images(edges, parity, nx, ny)
    period += ((mean - period.sum(axis=(1, 2))) / (nx * ny))[:, None, None]
    return period


class SubsurfaceStressOperator:
    """Stresses at the volume-grid cell centres from piecewise-constant surface tractions.

    Per layer a 2-D DC-FFT (Liu, Wang & Liu 2000): tractions zero-padded to ``(Lx, Ly) = (2nx,
    2ny)``, kernels (:func:`layer_kernels`, closed forms) in wrap-around order, one batched FFTW
    transform over the layers; on a periodic grid a circular convolution, ``(Lx, Ly) = (nx,
    ny)`` and the periodised kernels (:meth:`~solver.numerics.grid.VolumeGrid.fft_lengths`).

    Parameters
    ----------
    grid : VolumeGrid
        Surface cells (loads) and layers (field points).
    nu : float
        Poisson's ratio of the half-space.
    threads : int
        FFTW threads.
    planner : str
        FFTW planner effort (``"FFTW_MEASURE"`` or ``"FFTW_ESTIMATE"``).
    dtype : str
        Float type the kernel spectra are kept in (``"float32"`` halves them: the single
        precision of an elastic-plastic case's volume parts).

    Notes
    -----
    FFT normalisation: forward real transforms unnormalised, the backward one FFTW's
    unnormalised inverse; ``1/(Lx Ly)`` is folded into the stored kernel spectra.  By parity
    every kernel spectrum is purely real or purely imaginary (:func:`kernel_parity`), so one
    float64 array ``(Lx, Ly/2 + 1, nz)`` is stored per (traction, component): the cache of all
    18 costs ``18 * 8 Lx (Ly/2 + 1) nz`` bytes (:meth:`memory_bytes`).  Spectra are built on
    first use per traction and reused for every later call.
    """

    def __init__(
        self,
        grid: VolumeGrid,
        nu: float,
        threads: int = 1,
        planner: str = "FFTW_ESTIMATE",
        dtype: str = "float64",
    ):
        self.grid = grid
        self.nu = float(nu)
        self.dtype = np.dtype(dtype)
        self.threads = threads
        self.planner = planner
        #: Lateral FFT lengths (Lx, Ly): twice the cells, or the period's own
        self.lengths = grid.fft_lengths()
        lx, ly = self.lengths
        self._surface_in = empty_aligned((lx, ly), dtype="float64")
        self._surface_out = empty_aligned((lx, ly // 2 + 1), dtype="complex128")
        self._surface_fft = plan(
            self._surface_in, self._surface_out, axes=(0, 1), planner=planner, threads=threads
        )
        self._surface_in[...] = 0.0
        self._surface_spec = empty_aligned((lx, ly // 2 + 1), dtype="complex128")
        self._surface_real = empty_aligned((lx, ly), dtype="float64")
        self._surface_ifft = plan(
            self._surface_spec,
            self._surface_real,
            axes=(0, 1),
            direction="FFTW_BACKWARD",
            planner=planner,
            threads=threads,
            extra=("FFTW_DESTROY_INPUT",),
        )
        self._spectra: dict[str, np.ndarray] = {}
        self._batched: dict[int, tuple] = {}

    # -- kernels ---------------------------------------------------------------------------

    def kernel_spectra(self, traction: str) -> np.ndarray:
        """Stored spectra of one traction's kernels, shape ``(6, Lx, Ly/2 + 1, nz)`` float64.

        Entry ``c`` is the real part (even-even and odd-odd kernels) or the imaginary part
        (mixed parity) of the normalised transform of component ``c`` (:func:`kernel_parity`).
        """
        if traction not in self._spectra:
            if traction not in TRACTIONS:
                raise ValueError(f"unknown traction {traction!r}; use one of {TRACTIONS}")
            lx, ly = self.lengths
            nz = self.grid.nz
            spectra = np.empty((6, lx, ly // 2 + 1, nz), dtype=self.dtype)
            scale = 1.0 / (lx * ly)
            chunk = self._kernel_chunk()
            for k0 in range(0, nz, chunk):
                layers = range(k0, min(nz, k0 + chunk))
                kernels = layer_kernels(self.grid, self.nu, traction, layers, self.threads)
                forward = self.batched_transforms(len(layers))[0]
                for c, comp in enumerate(STRESS_COMPONENTS):
                    copy_by_rows(forward.input_array, kernels[c], self.threads)
                    forward.execute()
                    px, py = kernel_parity(comp, traction)
                    part = forward.output_array.imag if (px + py) % 2 else forward.output_array.real
                    target = spectra[c, :, :, layers.start : layers.stop]
                    copy_by_rows(target, part, self.threads, scale)
            self._spectra[traction] = spectra
        return self._spectra[traction]

    def _kernel_chunk(self) -> int:
        """Layers per batch of the kernel transforms (about 32 MiB of kernels at once)."""
        g = self.grid.surface
        return max(1, min(self.grid.nz, 2**22 // (4 * g.nx * g.ny)))

    def make_plans(self) -> None:
        """Make every FFT plan this operator uses (:mod:`solver.numerics.fftw`), nothing else."""
        nz, chunk = self.grid.nz, self._kernel_chunk()
        for nlayers in {nz, chunk, nz % chunk or chunk}:
            self.batched_transforms(nlayers)

    def batched_transforms(self, nlayers: int) -> tuple[pyfftw.FFTW, pyfftw.FFTW]:
        """Batched forward and backward 2-D transforms over ``nlayers`` layers (cached).

        Arrays: real ``(Lx, Ly, nlayers)`` (the forward input and the backward output share
        it) and complex ``(Lx, Ly/2 + 1, nlayers)``; the transforms run over the first two axes.
        """
        if nlayers not in self._batched:
            lx, ly = self.lengths
            real = empty_aligned((lx, ly, nlayers), dtype="float64")
            spec = empty_aligned((lx, ly // 2 + 1, nlayers), dtype="complex128")
            options = {"planner": self.planner, "threads": self.threads}
            forward = plan(real, spec, axes=(0, 1), **options)
            backward = plan(
                spec,
                real,
                axes=(0, 1),
                direction="FFTW_BACKWARD",
                extra=("FFTW_DESTROY_INPUT",),
                **options,
            )
            self._batched[nlayers] = (forward, backward)
        return self._batched[nlayers]

    def surface_spectrum(self, field: np.ndarray) -> np.ndarray:
        """Forward transform of a surface field (a new ``(Lx, Ly/2 + 1)`` complex array).

        ``field`` is either an ``(nx, ny)`` field, zero-padded here, or a full ``(Lx, Ly)``
        array (a kernel in wrap-around order; the same on a periodic grid).
        """
        nx, ny = self.grid.surface.shape
        if field.shape == self.lengths:
            self._surface_in[...] = field
            self._surface_fft.execute()
            self._surface_in[...] = 0.0
        else:
            self._surface_in[:nx, :ny] = field
            self._surface_fft.execute()
        return self._surface_out.copy()

    def surface_inverse(self, spectrum: np.ndarray) -> np.ndarray:
        """Backward transform of a normalised ``(Lx, Ly/2 + 1)`` spectrum, cut to ``(nx, ny)``."""
        nx, ny = self.grid.surface.shape
        self._surface_spec[...] = spectrum
        self._surface_ifft.execute()
        return self._surface_real[:nx, :ny].copy()

    # -- application -----------------------------------------------------------------------

    def stress_from_spectra(
        self, spectra: dict[str, np.ndarray], box: IndexBox | None = None
    ) -> np.ndarray:
        """Stresses (Pa) from traction spectra ``{traction: surface_spectrum(t)}``."""
        box = box or IndexBox.full(self.grid)
        box.validate(self.grid)
        k0, k1 = box.z
        sx, sy, _ = box.slices
        kernels = {traction: self.kernel_spectra(traction) for traction in spectra}  # build first
        out = np.empty((6,) + box.shape)
        _, backward = self.batched_transforms(k1 - k0)
        acc = backward.input_array
        tmp = np.empty(acc.shape, dtype=complex) if len(spectra) > 1 else None
        for c, comp in enumerate(STRESS_COMPONENTS):
            for n, (traction, spectrum) in enumerate(spectra.items()):
                kernel = kernels[traction][c, :, :, k0:k1]
                px, py = kernel_parity(comp, traction)
                factor = (1j * spectrum if (px + py) % 2 else spectrum)[:, :, None]
                if n == 0:
                    np.multiply(kernel, factor, out=acc)
                else:
                    np.multiply(kernel, factor, out=tmp)
                    acc += tmp
            backward.execute()
            out[c] = backward.output_array[sx, sy, :]
        return out

    def stress(
        self,
        pressure: np.ndarray | None = None,
        shear_x: np.ndarray | None = None,
        shear_y: np.ndarray | None = None,
        box: IndexBox | None = None,
    ) -> np.ndarray:
        """Stresses at the cell centres from surface tractions.

        Parameters
        ----------
        pressure, shear_x, shear_y : ndarray or None
            ``(nx, ny)`` tractions on the body (Pa): p (+z into the body), q_x, q_y; None for
            zero.
        box : IndexBox or None
            Sub-box of cells where stresses are wanted (default: the whole grid).

        Returns
        -------
        ndarray
            ``(6,) + box.shape`` stresses (Pa), components :data:`STRESS_COMPONENTS`.
        """
        fields = {"pressure": pressure, "shear_x": shear_x, "shear_y": shear_y}
        spectra = {k: self.surface_spectrum(v) for k, v in fields.items() if v is not None}
        if not spectra:
            raise ValueError("stress needs at least one of pressure, shear_x, shear_y")
        return self.stress_from_spectra(spectra, box)

    @staticmethod
    def memory_bytes(grid: VolumeGrid, tractions: int = 3, dtype: str = "float64") -> int:
        """Bytes of the kernel cache for ``tractions`` traction types, plus FFT buffers."""
        nz = grid.nz
        lx, ly = grid.fft_lengths()
        half = lx * (ly // 2 + 1) * nz  # entries of one per-layer half spectrum
        spectra = tractions * 6 * np.dtype(dtype).itemsize * half
        buffers = 8 * lx * ly * nz + 16 * half + 8 * half
        return spectra + buffers


@functools.lru_cache(maxsize=4)
def subsurface_operator(
    grid: VolumeGrid, nu: float, threads: int = 1, planner: str = "FFTW_ESTIMATE"
) -> SubsurfaceStressOperator:
    """Cached :class:`SubsurfaceStressOperator` for a grid and Poisson's ratio."""
    return SubsurfaceStressOperator(grid, nu, threads=threads, planner=planner)
