r"""Residual stress and surface displacement of an eigenstrain (plastic strain) field.

The half-space ``z > 0`` (z into body 2) holds a piecewise-constant eigenstrain on the cells of
a :class:`~solver.grid.VolumeGrid`, components (xx, yy, zz, yz, xz, xy), tensor values.  Chiu's
(1978) construction, applied with FFTs as Liu & Wang (2005):

1. *Source*: every cell is a cuboid of uniform eigenstrain in an infinite body
   (:mod:`solver.cuboid`).
2. *Image*: the mirror cuboid at ``-z`` with ``e_xz`` and ``e_yz`` negated.  Source plus image is
   symmetric about ``z = 0``: there ``u_z = 0``, ``sigma_xz = sigma_yz = 0``, and the normal
   stress ``S_zz(x, y, 0) = 2 sigma_zz^source(x, y, 0)`` remains.
3. *Boussinesq correction*: the half-space solution of a surface pressure ``p = S_zz`` (its
   values at the surface-cell centres, piecewise constant) cancels it (the pressure kernels of
   :class:`~solver.stress.SubsurfaceStressOperator` at every layer).  ``S_zz`` is known on the
   grid only; the part outside is dropped, which changes the stresses by ~1e-5 of their maximum
   in the tests (an eigenstrain blob at depth 4 in a window 8 depths wide).

Source and image are one 3-D convolution: the eigenstrain is laid out on ``2 nz`` layers (the
image, flipped in z, then the source), zero-padded to ``(2nx, 2ny, L)`` with ``L >= 3 nz - 1``, and
convolved with the cuboid kernels in wrap-around order (offsets ``-(nz - 1) .. 2nz - 1`` along
z), so the image term is the correlation in z of Liu & Wang's recipe.  Cost: 6 forward and 6
backward real 3-D FFTs of ``4 L nx ny`` points, 36 complex multiply-adds per frequency.  The 21
distinct kernel spectra (``w_ij D_ij,mn`` is symmetric) are even or odd in kx and ky, so a
quarter of each is stored.

Surface residual displacements (body-2 frame, z into the body; a uniform layer of thickness h
with ``e_zz > 0`` gives ``u_z = -h e_zz``), two routes:

* ``"reciprocal"`` (default, DESIGN §3.7): ``u_k = sum_cells sigma^(k)_ij e_ij dV / dA``, with
  ``sigma^(k)`` the stress of a unit traction on one surface cell in direction k (the
  :class:`~solver.stress.SubsurfaceStressOperator` kernels; a 2-D correlation per layer).  The
  surface-cell average of u, with the volume integral taken by the midpoint rule in each cell;
  nothing is truncated (lateral sums of the kernels are exact).
* ``"direct"``: ``u_x, u_y = 2 u^source(z = 0)`` plus the Boussinesq displacement of ``p``;
  ``u_z`` = the Boussinesq part only.  Point values at the cell centres.  Because ``p`` is
  known on the grid only and the Boussinesq kernel decays like 1/r, this route misses the
  displacement due to the pressure outside the grid, an error that shrinks only like the
  inverse window size: 3-5 % of the peak u_z for an eigenstrain blob whose depth is 1/6-1/8 of
  the grid width, but +23 % for a surface layer covering 3/4 of the grid width (+4 % and +1 %
  with the grid 2 and 4 times wider).  It cross-checks the reciprocal route: u_x, u_y agree
  to second order in the cell size.

FFT normalisation as :mod:`solver.convolution`: forward transforms unnormalised, the factor
``1/size`` folded into the stored kernel spectra.
"""

from __future__ import annotations

import concurrent.futures
import functools
import itertools
import math

import numpy as np
import pyfftw

from .cuboid import (
    DISPLACEMENT_BASE,
    STRESS_BASE,
    corner_functions,
    displacement_coefficients,
    stress_coefficients,
)
from .grid import VolumeGrid
from .influence import cell_integral
from .stress import (
    STRESS_COMPONENTS,
    IndexBox,
    SubsurfaceStressOperator,
    kernel_parity,
    wrap_layout,
)
from .tensor import WEIGHTS, deviator

#: Tensor weights of the six components in ``sigma : e`` (off-diagonal terms count twice).
COMPONENT_WEIGHTS = WEIGHTS
#: The five independent components of a deviatoric tensor (zz = -(xx + yy)).
DEVIATORIC = (0, 1, 3, 4, 5)
#: Sign of each eigenstrain component in the mirror image (xz and yz flip).
IMAGE_SIGNS = np.array([1.0, 1.0, 1.0, -1.0, -1.0, 1.0])

#: Names of the output components (the mean stress "mean" has the parity of a normal one).
_OUTPUT_NAME = dict(enumerate(STRESS_COMPONENTS))
_TRACTION_OF_DIRECTION = {"x": "shear_x", "y": "shear_y", "z": "pressure"}


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


def _parity(indices: str) -> tuple[int, int]:
    return indices.count("x") % 2, indices.count("y") % 2


def _is_imaginary(indices: str) -> bool:
    px, py = _parity(indices)
    return bool((px + py) % 2)


def _lattice_corner_sums(cx, cy, cz, names, chunk: int = 16) -> dict:
    """Corner sums of the cuboid corner functions over a lattice of corner coordinates.

    ``cx``, ``cy``, ``cz`` are increasing 1-D corner coordinates ``x - x'_corner``.  Entry
    ``(i, j, k)`` of each result, shape ``(len(cx) - 1, len(cy) - 1, len(cz) - 1)``, is the
    alternating sum over the corners ``(cx[i:i+2], cy[j:j+2], cz[k:k+2])``: the field of a
    cuboid of one lattice cell at the offset of that cell's centre.  Computed in slabs of
    ``chunk`` x-rows to bound the temporaries.
    """
    out = {name: np.empty((len(cx) - 1, len(cy) - 1, len(cz) - 1)) for name in names}
    for i0 in range(0, len(cx) - 1, chunk):
        i1 = min(len(cx) - 1, i0 + chunk)
        f = corner_functions(
            cx[i0 : i1 + 1, None, None], cy[None, :, None], cz[None, None, :], names
        )
        for name in names:
            v = f[name]
            out[name][i0:i1] = np.diff(np.diff(np.diff(v, axis=0), axis=1), axis=2)
    return out


class EigenstrainOperator:
    """Residual stress and surface displacement of a cell-wise eigenstrain in a half-space.

    Parameters
    ----------
    grid : VolumeGrid
        Cells carrying the eigenstrain; stresses are returned at their centres, surface
        displacements at the centres of the surface cells.
    E : float
        Young's modulus of the half-space (Pa).
    nu : float
        Poisson's ratio.
    threads : int
        FFTW threads.
    planner : str
        FFTW planner effort (``"FFTW_ESTIMATE"``, the project's reproducible default, or
        ``"FFTW_MEASURE"``).
    surface_stress : SubsurfaceStressOperator, optional
        The traction-to-stress operator of the same grid and Poisson's ratio, shared with the
        caller (its kernels serve the Boussinesq correction and the reciprocal displacements);
        built here if omitted.

    Notes
    -----
    Kernels are built on first use (:meth:`prepare` builds them explicitly): 21 quarter 3-D
    spectra ``(nx + 1, ny + 1, L/2 + 1)`` for the stress, float per-layer 2-D spectra for the
    surface traction (6), the :class:`~solver.stress.SubsurfaceStressOperator` kernels
    (pressure for the correction, both shears as well for the reciprocal displacement) and,
    only if the direct displacement route is used, its 12 per-layer kernels.
    :meth:`memory_bytes` states the peak (within 3 % of the measured one, 32^3 to 128^3).
    Measured on one core: 64^3 cells, setup 5-7 s, stress 0.4-0.6 s, displacement 0.05-0.08 s,
    peak 0.56 GB; 128^3, 40-60 s, 5-6 s, 0.8 s, 4.4 GB (``python -m study.bench.subsurface``).
    """

    def __init__(
        self,
        grid: VolumeGrid,
        E: float,
        nu: float,
        threads: int = 1,
        planner: str = "FFTW_ESTIMATE",
        surface_stress: SubsurfaceStressOperator | None = None,
        box: IndexBox | None = None,
        precision: str = "double",
    ):
        if precision not in VOLUME_PRECISIONS:
            raise ValueError(f"precision must be one of {list(VOLUME_PRECISIONS)}: {precision!r}")
        self.precision = precision
        self._real, self._complex = VOLUME_PRECISIONS[precision]
        self.grid = grid
        self.box = IndexBox.full(grid) if box is None else box
        self.box.validate(grid)
        if self.box.z != (0, grid.nz):
            raise ValueError(f"the plastic box spans every layer, not {self.box.z}")
        #: Cells of the plastic box: where the eigenstrain lives and its stress is evaluated.
        self.shape = self.box.shape
        self.E = float(E)
        self.nu = float(nu)
        self.shear_modulus = self.E / (2.0 * (1.0 + self.nu))
        self.threads = threads
        self.planner = planner
        self.length_z = fft_size(3 * grid.nz - 1)
        if surface_stress is None:
            surface_stress = SubsurfaceStressOperator(grid, nu, threads=threads, planner=planner)
        elif surface_stress.grid != grid or surface_stress.nu != self.nu:
            raise ValueError("surface_stress must be built on the same grid and Poisson's ratio")
        self.surface_stress = surface_stress
        self._volume: tuple | None = None
        self._inputs: dict[int, np.ndarray] = {}
        self._work: list | None = None
        self._stress_spectra: dict | None = None
        self._deviatoric_spectra: dict | None = None
        self._surface_kernels: dict | None = None

    # -- setup -----------------------------------------------------------------------------

    def prepare(self, stress: bool = True, displacement: bool = True, direct: bool = False) -> None:
        """Build kernels and FFT plans now rather than on first use.

        Parameters
        ----------
        stress : bool
            Kernels of the stress of a trace-free (plastic) eigenstrain (3-D cuboid spectra,
            surface traction, pressure kernels); an eigenstrain with a trace builds its own on
            first use.
        displacement : bool
            Kernels of the reciprocal surface-displacement route (all traction kernels).
        direct : bool
            Kernels of the direct surface-displacement route.
        """
        if stress:
            self._deviatoric_kernels()
            self._surface_layer_kernels()
            self.surface_stress.kernel_spectra("pressure")
        if displacement:
            for traction in ("pressure", "shear_x", "shear_y"):
                self.surface_stress.kernel_spectra(traction)
        if direct:
            self._surface_layer_kernels(displacement=True)

    def _volume_plans(self) -> dict[str, pyfftw.FFTW]:
        """Pruned 3-D transforms of the padded volume, one axis at a time (built once).

        The padded eigenstrain ``(2nx, 2ny, L)`` is zero outside ``(nx, ny, 2nz)`` and only
        ``(nx, ny, nz)`` of the padded stress is wanted, so the forward transform runs along z
        on the ``nx ny`` data columns only (``"z"``), along y on the ``nx`` data rows
        (``"y"``), then along x (``"x"``); the backward one along x, along y on ``nx`` rows,
        then along z on ``nx ny`` columns (``"-x"``, ``"-y"``, ``"-z"``): about 0.6 of the
        work of the whole 3-D transform, the same values.  ``columns`` ``(nx, ny, L)`` holds
        the eigenstrain columns in and the stress columns out; ``spectrum`` ``(2nx, 2ny,
        L/2 + 1)`` is the product accumulator.  The forward plans are pointed at each input
        slot in turn.
        """
        if self._volume is None:
            nx, ny, _ = self.shape
            columns = pyfftw.empty_aligned((nx, ny, self.length_z), dtype=self._real)
            spectrum = pyfftw.empty_aligned(
                (2 * nx, 2 * ny, self.length_z // 2 + 1), dtype=self._complex
            )
            plan = functools.partial(pyfftw.FFTW, flags=(self.planner,), threads=self.threads)
            back = functools.partial(plan, direction="FFTW_BACKWARD")
            self._volume = {
                "z": plan(columns, spectrum[:nx, :ny], axes=(2,)),
                "y": plan(spectrum[:nx], spectrum[:nx], axes=(1,)),
                "x": plan(spectrum, spectrum, axes=(0,)),
                "-x": back(spectrum, spectrum, axes=(0,)),
                "-y": back(spectrum[:nx], spectrum[:nx], axes=(1,)),
                "-z": plan(
                    spectrum[:nx, :ny],
                    columns,
                    axes=(2,),
                    direction="FFTW_BACKWARD",
                    flags=(self.planner, "FFTW_DESTROY_INPUT"),
                ),
            }
            columns[...] = 0.0
        return self._volume

    def _build_spectra(self, combinations: dict) -> dict:
        """Quarter spectra of linear combinations of the cuboid kernels (normalised).

        ``combinations`` maps a key to ``(coefficients, parity)``: the coefficients of the
        :data:`~solver.cuboid.STRESS_BASE` functions followed by the one of the eigenstress
        inside the source cell (a delta at offset 0: a flat spectrum), and the parity in x and
        y of the kernel.  A kernel even or odd in x and in y has a spectrum even or odd in kx and
        ky, so only ``kx <= nx``, ``ky <= ny`` is stored, shape ``(nx + 1, ny + 1, L/2 + 1)``:
        a quarter of the full spectrum.  Each base function is transformed once and added to
        every combination that uses it; nothing else is kept.
        """
        g = self.grid.surface
        nx, ny, nz = self.shape
        length = self.length_z
        spectrum_out = self._volume_plans()["-x"].input_array  # the accumulator, free here
        kernel_in = pyfftw.empty_aligned((2 * nx, 2 * ny, length), dtype=self._real)
        forward = pyfftw.FFTW(
            kernel_in, spectrum_out, axes=(0, 1, 2), flags=(self.planner,), threads=self.threads
        )  # a whole 3-D transform: kernels fill the padded volume (freed on return)
        scale = 1.0 / (4 * nx * ny * length)
        quarter = (slice(0, nx + 1), slice(0, ny + 1))
        shape = (nx + 1, ny + 1, length // 2 + 1)
        spectra = {
            key: np.full(shape, coefficients[-1] * scale, dtype=self._complex)
            for key, (coefficients, _) in combinations.items()
        }
        cx = (np.arange(-nx, nx) + 0.5) * g.dx
        cy = (np.arange(-ny, ny) + 0.5) * g.dy
        first = 2 * nz - length  # most negative z offset (in layers)
        cz = (np.arange(first - 1, 2 * nz) + 0.5) * self.grid.dz
        work = np.empty(shape, dtype=self._complex)
        for group in _base_groups(STRESS_BASE):
            sums = _lattice_corner_sums(cx, cy, cz, group)
            for name in group:
                b = STRESS_BASE.index(name)
                kernel = wrap_layout(wrap_layout(sums.pop(name), 0), 1)
                forward.input_array[...] = np.roll(kernel, first, axis=2)
                del kernel
                forward.execute()
                spectrum = forward.output_array[quarter]
                for key, (coefficients, parity) in combinations.items():
                    c = coefficients[b]
                    if abs(c) <= 1e-14 * np.abs(coefficients[:-1]).max():
                        continue  # zero, or zero up to the round-off of a combination
                    if _parity(name[1:]) != parity:
                        raise AssertionError("cuboid kernel of mixed parity")  # pragma: no cover
                    np.multiply(spectrum, c * scale, out=work)
                    spectra[key] += work
        return spectra

    def _unit_stress_coefficients(self) -> np.ndarray:
        """``D[ij, mn]``: stress ij of a unit eigenstrain mn, over the base functions and inside.

        Shape ``(6, 6, len(STRESS_BASE) + 1)``; the last entry is the eigenstress inside the
        source cell.  Taken from the symmetric weighted form ``w_ij D_ij,mn`` (ij <= mn).
        """
        coef, inside = stress_coefficients(self.shear_modulus, self.nu)
        unit = np.empty((6, 6, len(STRESS_BASE) + 1))
        for ij, mn in itertools.product(range(6), repeat=2):
            lo, hi = min(ij, mn), max(ij, mn)
            ratio = COMPONENT_WEIGHTS[lo] / COMPONENT_WEIGHTS[ij]
            unit[ij, mn, :-1] = ratio * coef[lo, hi]
            unit[ij, mn, -1] = -ratio * inside[lo, hi]
        return unit

    def _stress_kernels(self) -> dict:
        """Quarter spectra ``S[(ij, mn)] = w_ij D_ij,mn`` (symmetric), ij <= mn: any eigenstrain.

        Built on first use by :meth:`stress` of an eigenstrain with a trace; the plasticity
        loop's trace-free eigenstrains use :meth:`_deviatoric_kernels` only.
        """
        if self._stress_spectra is None:
            unit = self._unit_stress_coefficients()
            self._stress_spectra = self._build_spectra(
                {
                    (ij, mn): (
                        COMPONENT_WEIGHTS[ij] * unit[ij, mn],
                        _parity(STRESS_COMPONENTS[ij] + STRESS_COMPONENTS[mn]),
                    )
                    for ij in range(6)
                    for mn in range(ij, 6)
                }
            )
        return self._stress_spectra

    def _deviatoric_kernels(self) -> dict:
        """Quarter spectra for a trace-free eigenstrain: deviatoric stress and mean stress.

        Inputs are the five independent components :data:`DEVIATORIC` of a deviatoric tensor
        (``zz = -(xx + yy)``).  ``K[(a, b)]`` gives the deviatoric stress,
        ``s_a = sum_b K[a, b] * e_b`` (``K = P_out D P_in``); ``K[("mean", b)]`` the mean stress
        ``tr(sigma)/3``, for the full stress.  Each combination keeps the parity of ``a + b``
        (xx, yy and zz share theirs), so quarters suffice.  25 products and 10 volume
        transforms per deviatoric evaluation instead of 36 and 12; 30 kernels kept instead of 21
        + 25.
        """
        if self._deviatoric_spectra is None:
            unit = self._unit_stress_coefficients()
            # e_zz = -(e_xx + e_yy): a unit e_xx or e_yy comes with e_zz = -1
            unit_in = unit.copy()
            unit_in[:, :2] -= unit[:, 2:3]
            mean = unit_in[:3].mean(axis=0)
            combinations = {}
            for b in DEVIATORIC:
                parity = _parity(STRESS_COMPONENTS[b])
                combinations["mean", b] = (mean[b], parity)
                for a in DEVIATORIC:
                    values = unit_in[a, b] - mean[b] if a in (0, 1) else unit_in[a, b]
                    pair = _parity(STRESS_COMPONENTS[a] + STRESS_COMPONENTS[b])
                    combinations[a, b] = (values, pair)
            self._deviatoric_spectra = self._build_spectra(combinations)
        return self._deviatoric_spectra

    def _surface_layer_kernels(self, displacement: bool = False) -> dict:
        """Per-layer 2-D spectra of the surface fields of source + image (normalised).

        ``"zz"``: ``S_zz = 2 sigma_zz^source(z = 0)`` per unit e_mn, shape
        ``(6, 2nx, ny + 1, nz)`` (float, parity-typed), always built.  With ``displacement``
        also ``"x"``, ``"y"``: ``2 u_x``, ``2 u_y`` of the source at z = 0, and ``"bx"``,
        ``"by"``, ``"bz"``: the Boussinesq surface displacement per unit pressure on a cell
        (complex ``(2nx, ny + 1)``) - the kernels of the direct route.
        """
        kernels = self._surface_kernels if self._surface_kernels is not None else {}
        if "zz" in kernels and (not displacement or "x" in kernels):
            return kernels
        g = self.grid.surface
        nx, ny, nz = self.grid.shape
        gmod, nu = self.shear_modulus, self.nu
        cx = (np.arange(-nx, nx) + 0.5) * g.dx
        cy = (np.arange(-ny, ny) + 0.5) * g.dy
        cz = -np.arange(nz, -1, -1) * self.grid.dz  # -nz dz .. 0, increasing
        coef, inside = stress_coefficients(gmod, nu)
        ucoef = displacement_coefficients(gmod, nu)
        zz = STRESS_COMPONENTS.index("zz")
        names = []
        if "zz" not in kernels:
            names += [n for n in STRESS_BASE if np.any(coef[zz, :, STRESS_BASE.index(n)] != 0.0)]
        if displacement:
            names += list(DISPLACEMENT_BASE)
        sums = _lattice_corner_sums(cx, cy, cz, names)
        # z offsets ascending: -(nz - 1/2) dz .. -dz/2, i.e. layers nz-1 .. 0: flip to layer order
        sums = {k: v[:, :, ::-1] for k, v in sums.items()}
        forward, _ = self.surface_stress.batched_transforms(nz)
        scale = 1.0 / (4 * nx * ny)

        def spectrum_of(field: np.ndarray, indices: str) -> np.ndarray:
            forward.input_array[...] = wrap_layout(wrap_layout(field, 0), 1)
            forward.execute()
            out = forward.output_array
            part = out.imag if _is_imaginary(indices) else out.real
            return part * scale

        if "zz" not in kernels:
            kernels["zz"] = np.empty((6, 2 * nx, ny + 1, nz))
            for mn, comp in enumerate(STRESS_COMPONENTS):
                field = 2.0 * sum(
                    coef[zz, mn, STRESS_BASE.index(n)] * sums[n]
                    for n in STRESS_BASE
                    if n in sums and coef[zz, mn, STRESS_BASE.index(n)] != 0.0
                )
                # the field point z = 0+ lies inside the first layer's source cell
                field[nx - 1, ny - 1, 0] -= 2.0 * inside[zz, mn]
                kernels["zz"][mn] = spectrum_of(field, "zz" + comp)
        if displacement:
            for i, axis in enumerate("xy"):
                kernels[axis] = np.empty((6, 2 * nx, ny + 1, nz))
                for mn, comp in enumerate(STRESS_COMPONENTS):
                    field = 2.0 * sum(
                        ucoef[i, mn, b] * sums[n]
                        for b, n in enumerate(DISPLACEMENT_BASE)
                        if ucoef[i, mn, b] != 0.0
                    )
                    kernels[axis][mn] = spectrum_of(field, axis + comp)
            # Boussinesq surface displacement of a unit pressure on one cell (single body)
            ox, oy = g.offsets()
            b_z = (1.0 - nu * nu) / (math.pi * self.E) * cell_integral("inv_r", ox, oy, g.dx, g.dy)
            b_t = -(1.0 + nu) * (1.0 - 2.0 * nu) / (2.0 * math.pi * self.E)
            b_x = b_t * cell_integral("x_r2", ox, oy, g.dx, g.dy)
            b_y = b_t * cell_integral("y_r2", ox, oy, g.dx, g.dy)
            for key, field in (("bz", b_z), ("bx", b_x), ("by", b_y)):
                field = field.copy()
                field[nx, :] = 0.0
                field[:, ny] = 0.0
                kernels[key] = self.surface_stress.surface_spectrum(field) * scale
        forward.input_array[...] = 0.0
        self._surface_kernels = kernels
        return kernels

    # -- application -----------------------------------------------------------------------

    def on_window(self, values: np.ndarray, outside: float = 0.0) -> np.ndarray:
        """A field on the plastic box's cells (last three axes) put on the whole volume grid.

        Cells outside the box take ``outside`` (0 for plastic strain, which the box holds all
        of; NaN for what is not computed there).  The array itself when the box is the grid.
        """
        if self.shape == self.grid.shape:
            return values
        out = np.full(values.shape[:-3] + self.grid.shape, outside)
        out[(...,) + self.box.slices] = values
        return out

    def _check(self, eigenstrain: np.ndarray) -> np.ndarray:
        eigenstrain = np.asarray(eigenstrain, dtype=float)
        if eigenstrain.shape != (6,) + self.shape:
            raise ValueError(
                f"eigenstrain must have the plastic box's shape (6, nx, ny, nz) = "
                f"{(6,) + self.shape}, got {eigenstrain.shape}"
            )
        return eigenstrain

    def layer_spectra(self, eigenstrain: np.ndarray) -> np.ndarray:
        """Per-layer 2-D transforms of the zero-padded eigenstrain: ``(6, 2nx, ny + 1, nz)``.

        The plastic box's eigenstrain sits at its place in the surface window (``nx``, ``ny``
        the window's cells): the surface fields it makes are the window's.
        """
        eigenstrain = self._check(eigenstrain)
        forward, _ = self.surface_stress.batched_transforms(self.grid.nz)
        out = np.empty((6,) + forward.output_array.shape, dtype=complex)
        buffer = forward.input_array
        buffer[...] = 0.0
        sx, sy, _ = self.box.slices
        for mn in range(6):
            buffer[sx, sy, :] = eigenstrain[mn]
            forward.execute()
            out[mn] = forward.output_array
        buffer[...] = 0.0
        return out

    def _correction_pressure(self, layers: np.ndarray) -> np.ndarray:
        """Pressure ``S_zz(x, y, 0)`` (Pa) that the Boussinesq correction must carry."""
        kernels = self._surface_layer_kernels()["zz"]
        total = None
        for mn, comp in enumerate(STRESS_COMPONENTS):
            factor = 1j if _is_imaginary("zz" + comp) else 1.0
            term = (layers[mn] * kernels[mn]).sum(axis=-1) * factor
            total = term if total is None else total + term
        return self._inverse_surface(total)

    def _inverse_surface(self, spectrum: np.ndarray) -> np.ndarray:
        """Backward 2-D transform of a normalised spectrum, cut to ``(nx, ny)``."""
        return self.surface_stress.surface_inverse(spectrum)

    def stress(self, eigenstrain: np.ndarray) -> np.ndarray:
        """Residual stress at the cell centres.

        Parameters
        ----------
        eigenstrain : ndarray
            ``(6, nx, ny, nz)`` eigenstrain (plastic strain) tensor components, order
            (xx, yy, zz, yz, xz, xy).

        Returns
        -------
        ndarray
            ``(6, nx, ny, nz)`` residual stress (Pa), same component order.
        """
        eigenstrain = self._check(eigenstrain)
        return self._stress(eigenstrain, self.layer_spectra(eigenstrain))

    def surface_displacement(
        self, eigenstrain: np.ndarray, method: str = "reciprocal"
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Residual surface displacements ``(u_x, u_y, u_z)`` (m) at the surface cell centres.

        Parameters
        ----------
        eigenstrain : ndarray
            ``(6, nx, ny, nz)`` eigenstrain tensor components.
        method : {"reciprocal", "direct"}
            ``"reciprocal"`` (default): Betti's theorem with the surface-traction stress kernels
            (surface-cell averages, midpoint rule in the volume; exact lateral sums, nothing
            truncated).  ``"direct"``: source + image at z = 0 plus the Boussinesq displacement
            of the correction pressure, which is only known on the grid: the pressure outside
            the grid is missing, an error that decays with the window size (a cross-check).

        Returns
        -------
        tuple of ndarray
            Three ``(nx, ny)`` arrays, body-2 frame (z into the body).
        """
        eigenstrain = self._check(eigenstrain)
        layers = self.layer_spectra(eigenstrain)
        if method == "reciprocal":
            return self._reciprocal_displacement(layers)
        if method != "direct":
            raise ValueError(f"unknown method {method!r}; use 'reciprocal' or 'direct'")
        return self._direct_displacement(layers, self._correction_pressure(layers))

    def evaluate(
        self, eigenstrain: np.ndarray
    ) -> tuple[np.ndarray, tuple[np.ndarray, np.ndarray, np.ndarray]]:
        """Residual stress and surface displacement (reciprocal route), sharing transforms.

        Returns
        -------
        stress : ndarray
            ``(6, nx, ny, nz)`` (Pa).
        displacement : tuple of ndarray
            ``(u_x, u_y, u_z)``, each ``(nx, ny)`` (m).
        """
        eigenstrain = self._check(eigenstrain)
        layers = self.layer_spectra(eigenstrain)
        return self._stress(eigenstrain, layers), self._reciprocal_displacement(layers)

    def displacement_from_layers(self, layers: np.ndarray) -> tuple:
        """Surface displacements (reciprocal route) from :meth:`layer_spectra` (m)."""
        return self._reciprocal_displacement(layers)

    def stress_with_tractions(
        self, eigenstrain: np.ndarray, layers: np.ndarray, tractions: dict[str, np.ndarray]
    ) -> np.ndarray:
        """Residual stress plus the stress of surface tractions on the half-space (Pa).

        The tractions (``pressure``, ``shear_x``, ``shear_y``, ``(nx, ny)`` arrays in Pa, as
        :meth:`solver.stress.SubsurfaceStressOperator.stress`) share the per-layer transforms
        of the residual stress's Boussinesq correction: one pass instead of two.

        Parameters
        ----------
        eigenstrain : ndarray
            ``(6, nx, ny, nz)`` eigenstrain.
        layers : ndarray
            Its :meth:`layer_spectra`.
        tractions : dict
            Surface tractions on the half-space.
        """
        return self._stress(self._check(eigenstrain), layers, tractions)

    def deviatoric_stress_with_tractions(
        self, eigenstrain: np.ndarray, layers: np.ndarray, tractions: dict[str, np.ndarray]
    ) -> np.ndarray:
        """Deviator of :meth:`stress_with_tractions` for a deviatoric (plastic) eigenstrain (Pa).

        What a von Mises return mapping needs, at about 70 % of the cost: five components in
        and out of the volume convolution (:meth:`_deviatoric_kernels`).  ``eigenstrain`` must
        be trace-free (its zz component is taken as ``-(xx + yy)``).
        """
        return self._stress(self._check(eigenstrain), layers, tractions, deviatoric=True)

    def _stress(
        self,
        eigenstrain: np.ndarray,
        layers: np.ndarray,
        tractions: dict | None = None,
        deviatoric: bool = False,
    ) -> np.ndarray:
        """Residual stress (plus the stress of ``tractions``); its deviator with ``deviatoric``.

        A trace-free eigenstrain (every plastic strain) goes through the five deviatoric
        components and the :meth:`_deviatoric_kernels`; one with a trace through all six and
        the :meth:`_stress_kernels`.  Evaluated on the plastic box's cells.
        """
        nx, ny, nz = self.shape
        plans = self._volume_plans()
        trace = np.abs(eigenstrain[0] + eigenstrain[1] + eigenstrain[2]).max()
        trace_free = deviatoric or trace <= 1e-12 * np.abs(eigenstrain).max()
        components = DEVIATORIC if trace_free else tuple(range(6))
        # source and image in one padded column: image layers 0..nz-1 (flipped), source
        # nz..2nz-1, zeros below (the backward transform of the last call left its output)
        columns = plans["z"].input_array
        columns[:, :, 2 * nz :] = 0.0
        inputs = {}
        for mn in components:
            columns[:, :, nz : 2 * nz] = eigenstrain[mn]
            columns[:, :, :nz] = IMAGE_SIGNS[mn] * eigenstrain[mn, :, :, ::-1]
            target = inputs[mn] = self._input_spectrum(mn)  # transformed straight into its slot
            target[:nx, ny:] = 0.0
            target[nx:] = 0.0
            plans["z"].update_arrays(columns, target[:nx, :ny])
            plans["y"].update_arrays(target[:nx], target[:nx])
            plans["x"].update_arrays(target, target)
            for axis in "zyx":
                plans[axis].execute()
        accumulator = plans["-x"].input_array
        if trace_free:
            kernels = self._deviatoric_kernels()
            outputs = [*DEVIATORIC, *([] if deviatoric else ["mean"])]
        else:
            kernels = self._stress_kernels()
            outputs = list(range(6))
        out = np.zeros((6, nx, ny, nz))
        mean = None
        workers = self._workers()
        for ij in outputs:
            terms = [
                (
                    kernels[ij, mn] if trace_free else kernels[min(ij, mn), max(ij, mn)],
                    inputs[mn],
                    _parity(
                        ("xx" if ij == "mean" else STRESS_COMPONENTS[ij]) + STRESS_COMPONENTS[mn]
                    ),
                )
                for mn in components
            ]
            if len(workers) > 1:
                share = functools.partial(self._accumulate, accumulator, terms)
                list(_pool(len(workers)).map(share, workers))
            else:
                self._accumulate(accumulator, terms, workers[0])
            for axis in ("-x", "-y", "-z"):
                plans[axis].execute()
            field = columns[:, :, nz : 2 * nz]
            if ij == "mean":
                mean = field.copy()
            else:
                out[ij] = field if trace_free else field / COMPONENT_WEIGHTS[ij]
        if trace_free:
            out[2] = -(out[0] + out[1])
        if mean is not None:
            out[:3] += mean
        tractions = dict(tractions or {})
        pressure = self._correction_pressure(layers)
        if tractions.get("pressure") is not None:
            pressure = pressure + tractions["pressure"]
        tractions["pressure"] = pressure
        spectra = {
            name: self.surface_stress.surface_spectrum(values)
            for name, values in tractions.items()
            if values is not None
        }
        surface = self.surface_stress.stress_from_spectra(spectra, self.box)
        out += deviator(surface) if deviatoric else surface
        return out

    def _workers(self) -> list[tuple[list[tuple], np.ndarray]]:
        """Row blocks of the padded spectrum dealt to :attr:`threads` workers, with work arrays.

        Each block is ``(rows, kernel_rows, mirrored)``: spectrum rows ``kx`` and the rows of the
        stored quarter kernel that hold them (``2nx - kx`` for the mirrored half).  Blocks of
        about :data:`CHUNK_BYTES` of spectrum keep the accumulator and the worker's own work
        array (one block: the products are never held whole) in cache while the terms of a
        component are summed.
        """
        if self._work is None:
            nx, ny, _ = self.shape
            depth = self.length_z // 2 + 1
            itemsize = np.dtype(self._complex).itemsize
            size = max(1, CHUNK_BYTES // (itemsize * 2 * ny * depth))
            blocks = []
            for start in range(0, nx + 1, size):
                stop = min(nx + 1, start + size)
                blocks.append((slice(start, stop), slice(start, stop), False))
            for start in range(nx + 1, 2 * nx, size):
                stop = min(2 * nx, start + size)
                # rows kx in [start, stop) hold kernel rows 2nx - kx, from 2nx - start down
                blocks.append((slice(start, stop), slice(2 * nx - start, 2 * nx - stop, -1), True))
            count = max(1, min(self.threads, len(blocks)))
            self._work = [
                (blocks[w::count], np.empty((size, ny + 1, depth), dtype=self._complex))
                for w in range(count)
            ]
        return self._work

    def _accumulate(self, acc: np.ndarray, terms: list, worker: tuple) -> None:
        """``acc = sum_terms kernel * input`` over a worker's row blocks (full spectrum layout).

        ``terms`` are ``(quarter kernel, input spectrum, (px, py))``: the kernel's parity in x
        and y gives its sign in the mirrored quadrants.  Same operations in the same order per
        element whatever the blocks: results do not depend on the number of threads.
        """
        blocks, buffer = worker
        ny = self.shape[1]
        cols = ((slice(0, ny + 1), slice(0, ny + 1), False),
                (slice(ny + 1, 2 * ny), slice(ny - 1, 0, -1), True))  # fmt: skip
        for xs, kxs, mirrored_x in blocks:
            rows = xs.stop - xs.start
            for ys, kys, mirrored_y in cols:
                target = acc[xs, ys]
                work = buffer[:rows, : ys.stop - ys.start]
                for n, (kernel, values, (px, py)) in enumerate(terms):
                    negative = (px and mirrored_x) != (py and mirrored_y)
                    if n == 0:
                        np.multiply(kernel[kxs, kys], values[xs, ys], out=target)
                        if negative:
                            np.negative(target, out=target)
                    else:
                        np.multiply(kernel[kxs, kys], values[xs, ys], out=work)
                        (np.subtract if negative else np.add)(target, work, out=target)

    def _input_spectrum(self, component: int) -> np.ndarray:
        """The aligned spectrum slot of one padded eigenstrain component (kept).

        Made on first use: a trace-free eigenstrain needs five (zz is -(xx + yy)).
        """
        if component not in self._inputs:
            shape = self._volume_plans()["-x"].input_array.shape
            self._inputs[component] = pyfftw.empty_aligned(shape, dtype=self._complex)
        return self._inputs[component]

    def _direct_displacement(self, layers: np.ndarray, pressure: np.ndarray) -> tuple:
        kernels = self._surface_layer_kernels(displacement=True)
        p_spec = self.surface_stress.surface_spectrum(pressure)
        result = []
        for axis in "xyz":
            total = kernels["b" + axis] * p_spec
            if axis != "z":
                for mn, comp in enumerate(STRESS_COMPONENTS):
                    factor = 1j if _is_imaginary(axis + comp) else 1.0
                    total = total + factor * (layers[mn] * kernels[axis][mn]).sum(axis=-1)
            result.append(self._inverse_surface(total))
        return tuple(result)

    def _reciprocal_displacement(self, layers: np.ndarray) -> tuple:
        dz = self.grid.dz
        result = []
        for axis in "xyz":
            traction = _TRACTION_OF_DIRECTION[axis]
            kernels = self.surface_stress.kernel_spectra(traction)  # real, (6, 2nx, ny + 1, nz)
            # sum over the layers of every component at once, on the real and imaginary parts
            # (no complex temporaries): sums[c] = sum_z layers[c] kernels[c]
            sums = np.einsum("cxyz,cxyz->cxy", layers.real, kernels) + 1j * np.einsum(
                "cxyz,cxyz->cxy", layers.imag, kernels
            )
            total = 0.0
            for mn, comp in enumerate(STRESS_COMPONENTS):
                px, py = kernel_parity(comp, traction)
                # correlation: conjugate kernel spectrum (i K -> -i K)
                factor = -1j if (px + py) % 2 else 1.0
                total = total + sums[mn] * (factor * COMPONENT_WEIGHTS[mn] * dz)
            result.append(self._inverse_surface(total))
        return tuple(result)

    # -- bookkeeping -----------------------------------------------------------------------

    @staticmethod
    def memory_bytes(
        grid: VolumeGrid,
        displacement: bool = True,
        deviatoric: bool = False,
        box: tuple[int, int] | None = None,
        precision: str = "double",
    ) -> int:
        """Approximate peak bytes of an operator in use (kept data plus one stress evaluation).

        Kept: the quarter 3-D kernel spectra of the plastic box (30 for trace-free eigenstrains
        with ``deviatoric``, else the 21 general ones), one padded real ``(2nx, 2ny, L)`` FFT
        buffer and one spectrum of the box, the window's per-layer surface-traction and
        traction-to-stress kernels (pressure, plus both shears with ``displacement``) and its
        batched 2-D FFT buffers.  One evaluation: the transformed inputs (5 or 6), 6 per-layer
        eigenstrain spectra, the output.  Setup transients (kernel construction) stay below
        the evaluation's share.  ``box``: the plastic box's cells ``(nx, ny)`` (default: the
        window's); ``precision``: of the 3-D parts (:data:`VOLUME_PRECISIONS`).
        """
        nx, ny, nz = grid.shape
        bx, by = box or (nx, ny)
        length = fft_size(3 * nz - 1)
        half = length // 2 + 1
        word = np.dtype(VOLUME_PRECISIONS[precision][0]).itemsize  # 8 or 4 bytes
        spec3 = 2 * word * 4 * bx * by * half
        quarter3 = 2 * word * (bx + 1) * (by + 1) * half
        real3 = word * bx * by * length  # the data columns of the pruned transforms
        layer = 8 * 2 * nx * (ny + 1) * nz  # one float per-layer spectrum of the window
        tractions = 3 if displacement else 1
        kept = (30 if deviatoric else 21) * quarter3 + real3 + spec3
        kept += (6 * tractions + 6) * layer + 8 * 4 * nx * ny * nz + 2 * layer
        evaluation = (5 if deviatoric else 6) * spec3 + 12 * layer + 8 * 6 * bx * by * nz
        return kept + evaluation


#: Real and complex types of the 3-D eigenstrain convolution by ``solver.volume_precision``.
VOLUME_PRECISIONS = {"double": ("float64", "complex128"), "single": ("float32", "complex64")}

#: Bytes of spectrum per row block of the spectral products
#: (:meth:`EigenstrainOperator._workers`).
CHUNK_BYTES = 2**18


@functools.lru_cache(maxsize=4)
def _pool(workers: int) -> concurrent.futures.ThreadPoolExecutor:
    """Worker threads for the spectral products (numpy releases the GIL in its loops)."""
    return concurrent.futures.ThreadPoolExecutor(workers, thread_name_prefix="eigenstrain")


def _base_groups(names) -> list[list[str]]:
    """Group base functions that share a transcendental (one asinh or atan) to evaluate once."""
    groups: dict[str, list[str]] = {}
    for name in names:
        letters = name[1:]
        counts = {a: letters.count(a) for a in "xyz"}
        if name[0] == "d" and len(letters) == 2:
            key = (
                ("t" + letters[0])
                if letters[0] == letters[1]
                else "a" + (set("xyz") - set(letters)).pop()
            )
        elif sorted(counts.values()) == [0, 1, 3]:
            key = "a" + next(a for a in "xyz" if counts[a] == 0)
        elif max(counts.values()) == 4:
            key = "t" + next(a for a in "xyz" if counts[a] == 4)
        else:
            key = "rational"
        groups.setdefault(key, []).append(name)
    return list(groups.values())
