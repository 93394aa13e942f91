r"""Residual stress and surface displacement of an eigenstrain (plastic strain) field.

The half-space ``z > 0`` (z into body 2) holds a piecewise-constant eigenstrain on the cells of
a :class:`~solver.numerics.grid.VolumeGrid`, components (xx, yy, zz, yz, xz, xy), tensor values.  Chiu's
(1978) construction, applied with FFTs as Liu & Wang (2005):

1. *Source*: every cell is a cuboid of uniform eigenstrain in an infinite body
   (:mod:`solver.volume.cuboid`).
2. *Image*: the mirror cuboid at ``-z`` with ``e_xz`` and ``e_yz`` negated.  Source plus image is
   symmetric about ``z = 0``: there ``u_z = 0``, ``sigma_xz = sigma_yz = 0``, and the normal
   stress ``S_zz(x, y, 0) = 2 sigma_zz^source(x, y, 0)`` remains.
3. *Boussinesq correction*: the half-space solution of a surface pressure ``p = S_zz`` (its
   values at the surface-cell centres, piecewise constant) cancels it (the pressure kernels of
   :class:`~solver.volume.stress.SubsurfaceStressOperator` at every layer).  ``S_zz`` is known on the
   grid only; the part outside is dropped, which changes the stresses by ~1e-5 of their maximum
   in the tests (an eigenstrain blob at depth 4 in a window 8 depths wide).

Source and image are one 3-D convolution, symmetric in z.  Source plus image is a column of
``2 nz`` cells even in z (xx, yy, zz, xy) or odd (yz, xz) about the surface, and every cuboid
kernel is even or odd in its z offset, so the z direction is a symmetric convolution (Martucci
1994) of period ``2M`` with ``M >= 2 nz`` (no wrap-around reaches an offset the layers have;
M even, :func:`depth_length`): the column goes through a DCT-II (even) or DST-II (odd) of
length M, the kernel's offsets ``0 .. M`` through a DCT-I or DST-I, their product through a
DCT-III or DST-III back, all real.  The data's DCTs and DSTs are real FFTs of length M of the
reordered column (Makhoul 1980), both planes (real and imaginary parts) in one call: FFTW's
own real-to-real transforms of these lengths were 1.7 to 3.8 times slower.
The data first go through per-layer 2-D transforms of the box zero-padded to ``(2nx, 2ny)``
(the layer spectra the surface terms use as well), then the z transforms; each kernel is even
or odd in x and y too, so its spectrum is real up to a power of i: stored real, for ``kx <=
nx``, ``ky <= ny`` (the mirrored kx by parity), ``(nx + 1, ny + 1, M + 1)``, and multiplied
with the real and imaginary planes of the inputs apart.  Per output component: 5 (trace-free)
or 6 real multiply-adds per frequency and plane; the spectrum has ``2nx (ny + 1) (M + 1)``
frequencies.  The 21 general kernels (``w_ij D_ij,mn`` is symmetric) or the 20 of a trace-free
eigenstrain (15 of a symmetric 5 x 5 deviatoric operator and 5 of the mean stress) are kept.
The convolution runs by blocks of kx rows: each block's inputs are transformed in z,
multiplied and transformed back while they are in cache, and its outputs replace its inputs.

Surface residual displacements (body-2 frame, z into the body; a uniform layer of thickness h
with ``e_zz > 0`` gives ``u_z = -h e_zz``), two routes:

* ``"reciprocal"`` (default, DESIGN §3.7): ``u_k = sum_cells sigma^(k)_ij e_ij dV / dA``, with
  ``sigma^(k)`` the stress of a unit traction on one surface cell in direction k (the
  :class:`~solver.volume.stress.SubsurfaceStressOperator` kernels; a 2-D correlation per layer).  The
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

FFT normalisation as :mod:`solver.surface.convolution`: forward transforms unnormalised, the factor
``1/size`` folded into the stored kernel spectra.
"""

from __future__ import annotations

import functools
import itertools
import math
from dataclasses import dataclass

import numpy as np
import pyfftw

from ..numerics.fftw import fft_size, plan
from ..numerics.grid import IndexBox, VolumeGrid
from ..numerics.tensor import WEIGHTS, complete_deviator, deviator
from ..numerics.threads import by_rows, each
from ..surface.influence import cell_integral
from .cuboid import (
    DISPLACEMENT_BASE,
    STRESS_BASE,
    corner_functions,
    displacement_coefficients,
    stress_coefficients,
)
from .stress import STRESS_COMPONENTS, SubsurfaceStressOperator, kernel_parity, wrap_layout

#: Tensor weights of the six components in ``sigma : e`` (off-diagonal terms count twice).
COMPONENT_WEIGHTS = WEIGHTS
#: The five independent components of a deviatoric tensor (zz = -(xx + yy)).
DEVIATORIC = (0, 1, 3, 4, 5)
#: Sign of each eigenstrain component in the mirror image (xz and yz flip).
IMAGE_SIGNS = np.array([1.0, 1.0, 1.0, -1.0, -1.0, 1.0])

#: Names of the output components (the mean stress "mean" has the parity of a normal one).
_OUTPUT_NAME = dict(enumerate(STRESS_COMPONENTS))
_TRACTION_OF_DIRECTION = {"x": "shear_x", "y": "shear_y", "z": "pressure"}


def _parity(indices: str) -> tuple[int, int]:
    return indices.count("x") % 2, indices.count("y") % 2


def _is_imaginary(indices: str) -> bool:
    px, py = _parity(indices)
    return bool((px + py) % 2)


def _parity3(indices: str) -> tuple[int, int, int]:
    """Parity (0 even, 1 odd) in x, y and z of a kernel or field with these tensor indices."""
    return indices.count("x") % 2, indices.count("y") % 2, indices.count("z") % 2


def _name(component) -> str:
    """Index letters of a stress component (an index, or ``"mean"``: a normal one)."""
    return "xx" if component == "mean" else STRESS_COMPONENTS[component]


def _rotation(component) -> int:
    """1 when a component's x-y transform carries a factor i (odd in exactly one of x, y)."""
    px, py, _ = _parity3(_name(component))
    return (px + py) % 2


def _rotation_sign(a, b, parity_xy: tuple[int, int]) -> float:
    """``(-i)^(px + py) / i^(r_a + r_b)``: +-1, the sign of a stored real kernel spectrum.

    A kernel of x-y parity ``(px, py)`` has the 2-D transform ``(-i)^(px + py) R``;
    stored is ``K / i^(r_a + r_b)``, so that inputs turned by ``i^r_b`` and outputs by
    ``i^r_a`` (:meth:`EigenstrainOperator._stress`) see real kernels only.
    """
    value = (-1j) ** sum(parity_xy) / 1j ** (_rotation(a) + _rotation(b))
    if abs(value.imag) > 1e-12:
        raise AssertionError("kernel parity and component rotations disagree")  # pragma: no cover
    return value.real


def _lattice_corner_sums(cx, cy, cz, names, chunk: int = 16, threads: int = 1) -> dict:
    """Corner sums of the cuboid corner functions over a lattice of corner coordinates.

    ``cx``, ``cy``, ``cz`` are increasing 1-D corner coordinates ``x - x'_corner``.  Entry
    ``(i, j, k)`` of each result, shape ``(len(cx) - 1, len(cy) - 1, len(cz) - 1)``, is the
    alternating sum over the corners ``(cx[i:i+2], cy[j:j+2], cz[k:k+2])``: the field of a
    cuboid of one lattice cell at the offset of that cell's centre.  Computed in slabs of
    ``chunk`` x-rows to bound the temporaries, shared by ``threads`` threads.
    """
    out = {name: np.empty((len(cx) - 1, len(cy) - 1, len(cz) - 1)) for name in names}

    def slab(i0: int) -> None:
        i1 = min(len(cx) - 1, i0 + chunk)
        f = corner_functions(
            cx[i0 : i1 + 1, None, None], cy[None, :, None], cz[None, None, :], names
        )
        for name in names:
            v = f[name]
            out[name][i0:i1] = np.diff(np.diff(np.diff(v, axis=0), axis=1), axis=2)

    each(slab, range(0, len(cx) - 1, chunk), threads)
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
    Kernels are built on first use (:meth:`prepare` builds them explicitly): 20 (trace-free)
    or 21 real 3-D spectra ``(nx + 1, ny + 1, M + 1)`` for the stress, float per-layer 2-D
    spectra for the surface traction (6), the
    :class:`~solver.volume.stress.SubsurfaceStressOperator` kernels (pressure for the correction, both
    shears as well for the reciprocal displacement) and, only if the direct displacement route
    is used, its 12 per-layer kernels.
    :meth:`memory_bytes` states the peak; ``python -m study.bench.subsurface`` measures
    setup, stress and displacement times and the peak against it.
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
        #: M, the half period of the symmetric depth convolution (>= 2 nz; module docstring)
        self.length_z = depth_length(grid.nz)
        if surface_stress is None:
            surface_stress = SubsurfaceStressOperator(grid, nu, threads=threads, planner=planner)
        elif surface_stress.grid != grid or surface_stress.nu != self.nu:
            raise ValueError("surface_stress must be built on the same grid and Poisson's ratio")
        self.surface_stress = surface_stress
        self._volume: tuple | None = None
        self._work: list | None = None
        self._stress_spectra: dict | None = None
        self._deviatoric_spectra: dict | None = None
        self._surface_kernels: dict | None = None
        self._surface_combinations: dict[tuple, np.ndarray] = {}
        self._box_spectra: np.ndarray | None = None

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

    def _layer_pieces(self) -> list[slice]:
        """The box's layers cut into :data:`LAYER_PIECES` runs (the 2-D transforms' pieces)."""
        bounds = np.linspace(0, self.shape[2], LAYER_PIECES + 1).round().astype(int)
        return [slice(a, b) for a, b in itertools.pairwise(bounds) if b > a]

    def _volume_plans(self) -> list[dict]:
        """FFT plans and buffers of the per-layer 2-D transforms of the box, one set per thread.

        Each set maps a piece's layer count ``h`` (:meth:`_layer_pieces`) to its plans:
        ``"data"`` ``(2nx, ny + 1, h)`` complex holds per-layer 2-D spectra of the box: the
        forward transform of the data rows (``"y"`` on the box's ``nx`` rows of ``"rows"``,
        then ``"x"``) writes there; on the way back ``"-x"``, ``"-y"`` bring a stress
        component's spectra back to the box's cells in ``"rows"`` ``(nx, 2ny, h)``.  The
        depth convolution between them runs by row blocks (:meth:`_workers`).  With several
        threads each set (single-threaded plans: the same plans as one thread's) transforms
        its share of the pieces (:meth:`_each_component`).
        """
        if self._volume is None:
            nx, ny, _ = self.shape
            make = functools.partial(plan, planner=self.planner, threads=1)
            depths = sorted({zs.stop - zs.start for zs in self._layer_pieces()})
            self._volume = []
            for _ in range(max(1, self.threads)):
                sets = {}
                for h in depths:
                    data = pyfftw.empty_aligned((2 * nx, ny + 1, h), dtype=self._complex)
                    rows = pyfftw.empty_aligned((nx, 2 * ny, h), dtype=self._real)
                    sets[h] = {
                        "data": data,
                        "rows": rows,
                        "y": make(rows, data[:nx], axes=(1,)),
                        "x": make(data, data, axes=(0,)),
                        "-x": make(data, data, axes=(0,), direction="FFTW_BACKWARD"),
                        "-y": make(
                            data[:nx],
                            rows,
                            axes=(1,),
                            direction="FFTW_BACKWARD",
                            extra=("FFTW_DESTROY_INPUT",),
                        ),
                    }
                    data[...] = 0.0
                    rows[...] = 0.0
                self._volume.append(sets)
        return self._volume

    def _each_component(self, components, job) -> None:
        """``job(component, layers, plans)`` for every component and piece of layers.

        The pieces (each component's :meth:`_layer_pieces`, ``layers`` a slice of them) are
        dealt to the plan sets of :meth:`_volume_plans` (one thread each; ``plans`` those of
        the piece's layer count): five components in ten pieces share evenly between two
        threads.  One thread transforms the same pieces with the same plans, so which set
        transforms a piece changes no bit.
        """
        sets = self._volume_plans()
        pieces = [(c, zs) for c in components for zs in self._layer_pieces()]

        def share(w: int) -> None:
            for component, zs in pieces[w :: len(sets)]:
                job(component, zs, sets[w][zs.stop - zs.start])

        each(share, range(min(len(sets), len(pieces))), len(sets))

    def _forward_layers(self, eigenstrain: np.ndarray, components, out: np.ndarray) -> None:
        """``out[c]``: the per-layer 2-D spectra of the box's ``eigenstrain[c]`` (zero-padded)."""
        nx, ny, _ = self.shape

        def job(c, zs: slice, plans: dict) -> None:
            rows, data = plans["rows"], plans["data"]
            rows[:, ny:] = 0.0  # the last inverse transform left its output
            rows[:, :ny] = eigenstrain[c, ..., zs]
            plans["y"].execute()
            data[nx:] = 0.0
            plans["x"].execute()
            out[c, ..., zs] = data

        self._each_component(components, job)

    def _build_spectra(self, combinations: dict) -> dict:
        """Real spectra of linear combinations of the cuboid kernels (normalised).

        ``combinations`` maps a key ``(a, b)`` (output and input component names; ``"mean"``
        counts as a normal component) to the coefficients of the
        :data:`~solver.volume.cuboid.STRESS_BASE` functions followed by the one of the eigenstress
        inside the source cell (a delta at offset 0: a flat spectrum).  Each kernel has a
        parity in x, y and z: its z offsets ``0 .. M`` go through a DCT-I (even) or DST-I
        (odd), then the x and y offsets through a 2-D FFT, whose value is ``i^(r_a + r_b)``
        times a real array (``r`` the x-y rotation of a component, :func:`_rotation`): that
        array is stored, for ``kx <= nx``, ``ky <= ny`` and the ``M + 1`` z frequencies,
        shape ``(nx + 1, ny + 1, M + 1)``.  Each base function is transformed once and added
        to every combination that uses it; nothing else is kept.
        """
        g = self.grid.surface
        nx, ny, nz = self.shape
        m = self.length_z
        lattice, along_z, spectrum, z_plans, xy_plans = self._kernel_plans()
        scale = 1.0 / (2 * m * 4 * nx * ny)
        shape = (nx + 1, ny + 1, m + 1)
        spectra = {key: np.empty(shape, dtype=self._real) for key in combinations}

        def start(key: tuple) -> None:
            inside = combinations[key][-1]  # nonzero only where a and b have one parity
            sign = _rotation_sign(*key, (0, 0)) if inside else 0.0
            spectra[key][...] = sign * inside * scale

        each(start, list(combinations), self.threads)
        # offsets 0 .. n - 1 in x and y: the negative ones follow by the kernel's parity
        cx = (np.arange(-1, nx) + 0.5) * g.dx
        cy = (np.arange(-1, ny) + 0.5) * g.dy
        cz = (np.arange(-1, m + 1) + 0.5) * self.grid.dz  # z offsets 0 .. M
        works = [np.empty(shape) for _ in range(max(1, self.threads))]
        lattice[nx] = 0.0
        lattice[:, ny] = 0.0  # offset n: no pair of cells has it
        for group in _base_groups(STRESS_BASE):
            sums = _lattice_corner_sums(cx, cy, cz, group, threads=self.threads)
            for name in group:
                base = STRESS_BASE.index(name)
                px, py, pz = _parity3(name[1:])
                lattice[:nx, :ny] = sums.pop(name)
                along_z[..., 0] = along_z[..., m] = 0.0  # the DST-I leaves the ends
                z_plans[pz].execute()
                # the 2-D DFT (period 2n) of a kernel of parity (px, py) is (-i)^(px + py)
                # times its DCT-I (even) / DST-I (odd) along x and y: that real array is kept
                spectrum[...] = 0.0  # a DST-I leaves the frequencies 0 and n
                xy_plans[px, py].execute()
                terms = []  # (key, factor) of the combinations this base function enters
                for (a, b), coefficients in combinations.items():
                    c = coefficients[base]
                    if abs(c) <= 1e-14 * np.abs(coefficients[:-1]).max():
                        continue  # zero, or zero up to the round-off of a combination
                    if _parity3(_name(a) + _name(b)) != (px, py, pz):
                        raise AssertionError("cuboid kernel of mixed parity")  # pragma: no cover
                    terms.append(((a, b), c * scale * _rotation_sign(a, b, (px, py))))

                def add(w: int, terms=terms) -> None:  # each combination on one thread
                    for key, factor in terms[w :: len(works)]:
                        np.multiply(spectrum, factor, out=works[w])
                        spectra[key] += works[w]

                each(add, range(len(works)), len(works))
        return spectra

    def _kernel_plans(self) -> tuple:
        """Buffers and plans of the kernel transforms (:meth:`_build_spectra`; freed after).

        ``(lattice, along_z, spectrum, {parity in z: DCT-I or DST-I plan}, {(parity in x,
        parity in y): DCT-I / DST-I plan along x and y})``, every buffer ``(nx + 1, ny + 1, M +
        1)`` real: offsets (then frequencies) ``0 .. n`` of the kernels' even or odd halves.
        """
        nx, ny, _ = self.shape
        m = self.length_z
        lattice, along_z, spectrum = (
            pyfftw.empty_aligned((nx + 1, ny + 1, m + 1), dtype="float64") for _ in range(3)
        )
        make = functools.partial(plan, planner=self.planner, threads=self.threads)
        z_plans = {
            0: make(lattice, along_z, axes=(2,), direction="FFTW_REDFT00"),
            1: make(lattice[..., 1:m], along_z[..., 1:m], axes=(2,), direction="FFTW_RODFT00"),
        }
        kinds = {0: (slice(None), "FFTW_REDFT00"), 1: (slice(1, None), "FFTW_RODFT00")}
        xy_plans = {}
        for px, py in itertools.product((0, 1), repeat=2):
            (sx, kx), (sy, ky) = kinds[px], kinds[py]
            sx = slice(sx.start, nx if px else None)
            sy = slice(sy.start, ny if py else None)
            xy_plans[px, py] = make(
                along_z[sx, sy], spectrum[sx, sy], axes=(0, 1), direction=[kx, ky]
            )
        return lattice, along_z, spectrum, z_plans, xy_plans

    def make_plans(self) -> None:
        """Make every FFT plan a solve uses, without building kernels.

        With the ``"FFTW_MEASURE"`` planner this measures them into FFTW's wisdom
        (:mod:`solver.numerics.fftw`), which ``solver.fft_planner = "wisdom"`` then reuses.
        """
        self._volume_plans()
        self._workers()
        self._kernel_plans()
        self.surface_stress.make_plans()

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
        """Spectra ``S[(ij, mn)] = w_ij D_ij,mn`` (symmetric), ij <= mn: any eigenstrain.

        Built on first use by :meth:`stress` of an eigenstrain with a trace; the plasticity
        loop's trace-free eigenstrains use :meth:`_deviatoric_kernels` only.
        """
        if self._stress_spectra is None:
            unit = self._unit_stress_coefficients()
            self._stress_spectra = self._build_spectra(
                {
                    (ij, mn): COMPONENT_WEIGHTS[ij] * unit[ij, mn]
                    for ij in range(6)
                    for mn in range(ij, 6)
                }
            )
        return self._stress_spectra

    def _deviatoric_kernels(self) -> dict:
        """Spectra for a trace-free eigenstrain: deviatoric stress and mean stress.

        Inputs are the five independent components :data:`DEVIATORIC` of a deviatoric tensor
        (``zz = -(xx + yy)``).  Outputs ``u_a = w_a t_a`` with ``t_xx = sigma_xx - sigma_zz``,
        ``t_yy = sigma_yy - sigma_zz`` and the shear stresses for the others (``w_a`` the
        tensor weight, 2 for shear): ``u_a = sum_b K[a, b] e_b`` has a symmetric matrix
        (``sigma : e`` is a symmetric bilinear form, and ``t`` with ``w`` are its components
        conjugate to the five ``e_b``), so the 15 kernels ``a <= b`` serve all 25 products; the
        deviator follows as ``s_xx = t_xx - (t_xx + t_yy)/3``, ``s_yy = t_yy - (t_xx + t_yy)/3``,
        ``s_zz = -(t_xx + t_yy)/3``.  ``K[("mean", b)]`` gives the mean stress ``tr(sigma)/3``,
        for the full stress.  Each combination keeps the parity of ``a + b`` (xx, yy and zz
        share theirs), so real spectra suffice.  25 products and 10 volume transforms per
        deviatoric evaluation instead of 36 and 12; 20 kernels kept instead of 21 + 25.
        """
        if self._deviatoric_spectra is None:
            unit = self._unit_stress_coefficients()
            # e_zz = -(e_xx + e_yy): a unit e_xx or e_yy comes with e_zz = -1
            unit_in = unit.copy()
            unit_in[:, :2] -= unit[:, 2:3]
            mean = unit_in[:3].mean(axis=0)
            combinations = {}
            for i, a in enumerate(DEVIATORIC):
                combinations["mean", a] = mean[a]
                t = unit_in[a] - unit_in[2] if a in (0, 1) else unit_in[a]
                for b in DEVIATORIC[i:]:
                    combinations[a, b] = COMPONENT_WEIGHTS[a] * t[b]
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
        forward, _ = self.surface_stress.batched_transforms(nz)
        scale = 1.0 / (4 * nx * ny)

        def lattice_sums(names: list[str]) -> dict:
            sums = _lattice_corner_sums(cx, cy, cz, names, threads=self.threads)
            # z offsets ascending: -(nz - 1/2) dz .. -dz/2, layers nz-1 .. 0: to layer order
            return {k: v[:, :, ::-1] for k, v in sums.items()}

        def spectrum_of(field: np.ndarray, indices: str) -> np.ndarray:
            wrap_layout(field, (0, 1), forward.input_array)
            forward.execute()
            out = forward.output_array
            part = out.imag if _is_imaginary(indices) else out.real
            return part * scale

        if "zz" not in kernels:
            # S_zz of every component, one base function at a time (each transformed once and
            # added where it enters: the lattices of all of them are never held at once)
            field = kernels["zz"] = np.zeros((6, 2 * nx, ny + 1, nz), dtype=self._real)
            used = [n for n in STRESS_BASE if np.any(coef[zz, :, STRESS_BASE.index(n)] != 0.0)]
            for group in _base_groups(used):
                sums = lattice_sums(group)
                for name in group:
                    b = STRESS_BASE.index(name)
                    # its parity is that of S_zz of each component it enters
                    spectrum = spectrum_of(sums.pop(name), name[1:])
                    for mn in range(6):
                        if coef[zz, mn, b] != 0.0:
                            field[mn] += 2.0 * coef[zz, mn, b] * spectrum
            for mn, comp in enumerate(STRESS_COMPONENTS):
                # the field point z = 0+ lies inside the first layer's source cell: a delta at
                # offset 0 of layer 0, a flat (real) spectrum
                if inside[zz, mn] != 0.0:
                    assert not _is_imaginary("zz" + comp)
                    field[mn, :, :, 0] -= 2.0 * inside[zz, mn] * scale
        if displacement:
            sums = lattice_sums(list(DISPLACEMENT_BASE))
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

        Five transforms for a trace-free eigenstrain (zz is -(xx + yy)), else six; complex64
        in single precision.

        The plastic box's eigenstrain sits at its place in the surface window (``nx``, ``ny``
        the window's cells): the surface fields it makes are the window's.
        """
        eigenstrain = self._check(eigenstrain)
        trace_free = self._trace_free(eigenstrain)
        components = DEVIATORIC if trace_free else range(6)
        nx, ny, _ = self.shape
        if self.shape == self.grid.shape and self.precision == "double":
            # the box is the window: the volume's own transforms, which skip the zero rows
            # (y on the nx data rows, then x)
            out = np.empty((6, 2 * nx, ny + 1, self.shape[2]), dtype=self._complex)
            self._forward_layers(eigenstrain, components, out)
        else:
            forward, _ = self.surface_stress.batched_transforms(self.grid.nz)
            # kept in the volume's precision (the transform itself is double)
            out = np.empty((6,) + forward.output_array.shape, dtype=self._complex)
            buffer = forward.input_array
            buffer[...] = 0.0
            sx, sy, _ = self.box.slices
            for mn in components:
                buffer[sx, sy, :] = eigenstrain[mn]
                forward.execute()
                out[mn] = forward.output_array
            buffer[...] = 0.0
        if trace_free:  # a plastic strain: zz is -(xx + yy)
            complete_deviator(out, self.threads)
        return out

    def _correction_pressure(self, layers: np.ndarray) -> np.ndarray:
        """Pressure ``S_zz(x, y, 0)`` (Pa) that the Boussinesq correction must carry."""
        (sums,) = self._layer_sums(layers, self._surface_layer_kernels()["zz"])
        total = 0.0
        for mn, comp in enumerate(STRESS_COMPONENTS):
            total = total + sums[mn] * (1j if _is_imaginary("zz" + comp) else 1.0)
        return self._inverse_surface(total)

    def _trace_free(self, eigenstrain: np.ndarray) -> bool:
        """True when ``|e_xx + e_yy + e_zz| <= 1e-12 max |e|`` everywhere (a plastic strain).

        By row blocks on the threads, without full-size temporaries.
        """

        def block(xs: slice) -> tuple[float, float]:
            part = eigenstrain[:, xs]
            trace = np.add(part[0], part[1])
            trace += part[2]
            return max(trace.max(), -trace.min()), max(part.max(), -part.min())

        parts = self._by_rows(block, eigenstrain.shape[1])
        return max(p[0] for p in parts) <= 1e-12 * max(p[1] for p in parts)

    def _by_rows(self, function, rows: int) -> list:
        """:func:`~solver.numerics.threads.by_rows` on this operator's threads."""
        return by_rows(function, rows, self.threads)

    def _layer_sums(self, layers: np.ndarray, *kernel_sets: np.ndarray) -> list[np.ndarray]:
        """``sums[c] = sum_z layers[c] kernels[c]`` for each set of real kernels.

        Real and imaginary parts at once, as the product of a kernel's row ``(nz)`` with the
        layers' ``(nz, 2)`` (their complex values seen as pairs of reals: no copy), by row
        blocks; every set is summed while a block of ``layers`` is in cache (one pass over
        them).
        """
        shape = kernel_sets[0].shape[:3]
        out = [np.empty(shape, dtype=complex) for _ in kernel_sets]
        layers = np.ascontiguousarray(layers)
        pairs = layers.view(layers.real.dtype).reshape(layers.shape + (2,))

        def block(xs: slice) -> None:
            values = pairs[:, xs]
            for sums, kernels in zip(out, kernel_sets, strict=True):
                product = np.matmul(kernels[:, xs, :, None, :], values)[..., 0, :]
                sums.real[:, xs] = product[..., 0]
                sums.imag[:, xs] = product[..., 1]

        self._by_rows(block, shape[1])
        return out

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
        return self._stress(eigenstrain, self.layer_spectra(eigenstrain), consume=True)

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
        displacement = self._reciprocal_displacement(layers)
        return self._stress(eigenstrain, layers, consume=True), displacement

    def displacement_from_layers(self, layers: np.ndarray) -> tuple:
        """Surface displacements (reciprocal route) from :meth:`layer_spectra` (m)."""
        return self._reciprocal_displacement(layers)

    def stress_with_tractions(
        self,
        eigenstrain: np.ndarray,
        layers: np.ndarray,
        tractions: dict[str, np.ndarray],
        consume: bool = False,
    ) -> np.ndarray:
        """Residual stress plus the stress of surface tractions on the half-space (Pa).

        The tractions (``pressure``, ``shear_x``, ``shear_y``, ``(nx, ny)`` arrays in Pa, as
        :meth:`solver.volume.stress.SubsurfaceStressOperator.stress`) share the per-layer transforms
        of the residual stress's Boussinesq correction: one pass instead of two.

        Parameters
        ----------
        eigenstrain : ndarray
            ``(6, nx, ny, nz)`` eigenstrain.
        layers : ndarray
            Its :meth:`layer_spectra`.
        tractions : dict
            Surface tractions on the half-space.
        consume : bool
            ``layers`` may be overwritten (saves a copy of them; they are garbage after).
        """
        return self._stress(self._check(eigenstrain), layers, tractions, consume=consume)

    def deviatoric_stress_with_tractions(
        self,
        eigenstrain: np.ndarray,
        layers: np.ndarray,
        tractions: dict[str, np.ndarray],
        consume: bool = False,
    ) -> np.ndarray:
        """Deviator of :meth:`stress_with_tractions` for a deviatoric (plastic) eigenstrain (Pa).

        What a von Mises return mapping needs, at about 70 % of the cost: five components in
        and out of the volume convolution (:meth:`_deviatoric_kernels`).  ``eigenstrain`` must
        be trace-free (its zz component is taken as ``-(xx + yy)``); ``consume`` as there.
        """
        return self._stress(
            self._check(eigenstrain), layers, tractions, deviatoric=True, consume=consume
        )

    def _stress(
        self,
        eigenstrain: np.ndarray,
        layers: np.ndarray,
        tractions: dict | None = None,
        deviatoric: bool = False,
        consume: bool = False,
    ) -> np.ndarray:
        """Residual stress (plus the stress of ``tractions``); its deviator with ``deviatoric``.

        A trace-free eigenstrain (every plastic strain) goes through the five deviatoric
        components and the :meth:`_deviatoric_kernels`; one with a trace through all six and
        the :meth:`_stress_kernels`.  Evaluated on the plastic box's cells.

        The box's per-layer spectra (``layers`` when the box is the window, else transformed
        here) go through the depth convolution by row blocks (:meth:`_convolve`): each
        block's inputs are transformed in z, multiplied and transformed back, and its output
        spectra replace its inputs in place, so no 3-D spectrum is ever held whole.
        ``consume``: ``layers`` may be overwritten (else copied first).
        """
        nx, ny, nz = self.shape
        trace_free = deviatoric or self._trace_free(eigenstrain)
        components = DEVIATORIC if trace_free else tuple(range(6))
        shared = self.shape == self.grid.shape  # the box is the window: its layer spectra
        tractions = dict(tractions or {})
        pressure = self._correction_pressure(layers)  # before the layers are overwritten
        if tractions.get("pressure") is not None:
            pressure = pressure + tractions["pressure"]
        tractions["pressure"] = pressure
        spectra = {
            name: self.surface_stress.surface_spectrum(values)
            for name, values in tractions.items()
            if values is not None
        }
        if shared:
            spectral = layers if consume else layers.copy()
        else:
            spectral = self._box_layers()
            self._forward_layers(eigenstrain, components, spectral)
        if trace_free:
            kernels = self._deviatoric_kernels()
            outputs = [*DEVIATORIC, *([] if deviatoric else ["mean"])]
        else:
            kernels = self._stress_kernels()
            outputs = list(range(6))
        terms = {}
        for a in outputs:
            pa = _parity3(_name(a))
            terms[a] = []
            for b in components:
                pb = _parity3(_name(b))
                terms[a].append(
                    (
                        kernels[(a, b) if a == "mean" else (min(a, b), max(a, b))],
                        b,
                        pb[2] and not pa[2],  # odd data, odd kernel, even output: -S H
                        (pa[0] + pb[0]) % 2,  # the kernel's parity in x (mirrored rows)
                    )
                )
        # the traction stresses join the residual ones in the layer spectra (no transforms of
        # their own, in the volume's precision) when the box is the window
        surface = self._surface_terms(outputs, spectra, trace_free) if shared else {}
        job = functools.partial(self._convolve, spectral, components, terms, surface)
        workers = self._workers()
        each(job, workers, len(workers))
        out = np.zeros((6, nx, ny, nz), dtype=self._real)  # float32 when single
        mean = np.empty((nx, ny, nz), dtype=self._real) if "mean" in outputs else None

        def inverse(a, zs: slice, plans: dict) -> None:
            plans["data"][...] = spectral[_SLOT[a], ..., zs]
            plans["-x"].execute()
            plans["-y"].execute()
            field = plans["rows"][:, :ny]
            if a == "mean":
                mean[..., zs] = field
            else:  # u_a = w_a t_a (trace-free) or w_a sigma_a (general)
                np.divide(field, COMPONENT_WEIGHTS[a], out=out[a, ..., zs])

        self._each_component(outputs, inverse)

        def normal(xs: slice) -> None:  # by rows: the normal stresses' last terms
            o = out[:, xs]
            if trace_free:  # the deviator from t_xx, t_yy (:meth:`_deviatoric_kernels`)
                np.add(o[0], o[1], out=o[2])
                o[2] /= -3.0
                o[0] += o[2]
                o[1] += o[2]
            if mean is not None:
                o[:3] += mean[xs]

        self._by_rows(normal, nx)
        if not shared:
            stress = self.surface_stress.stress_from_spectra(spectra, self.box)
            out += deviator(stress) if deviatoric else stress
        return out

    def _box_layers(self) -> np.ndarray:
        """Per-layer spectra ``(6, 2nx, ny + 1, nz)`` of a box narrower than the window (kept)."""
        if self._box_spectra is None:
            nx, ny, nz = self.shape
            self._box_spectra = np.zeros((6, 2 * nx, ny + 1, nz), dtype=self._complex)
        return self._box_spectra

    def _surface_terms(self, outputs: list, spectra: dict, trace_free: bool) -> dict:
        """Per output component, the traction stresses' terms ``[(kernel, factor)]``.

        ``spectra`` are the tractions' surface spectra
        (:meth:`~solver.volume.stress.SubsurfaceStressOperator.surface_spectrum`); the kernels those of
        :meth:`~solver.volume.stress.SubsurfaceStressOperator.kernel_spectra`, combined for a
        trace-free route's outputs: ``sigma_xx - sigma_zz`` and ``sigma_yy - sigma_zz`` for xx
        and yy, the mean stress for ``"mean"`` (kept once built).  ``kernel[rows] *
        factor[rows]`` is the layer spectra of the component's output (every output but the
        mean carries its tensor weight until the end).
        """
        terms = {}
        for component in outputs:
            weight = 1.0 if component == "mean" else COMPONENT_WEIGHTS[component]
            terms[component] = []
            for traction, spectrum in spectra.items():
                kernels = self.surface_stress.kernel_spectra(traction)
                if component == "mean" or (trace_free and component in (0, 1)):
                    key = (traction, component)
                    if key not in self._surface_combinations:
                        if component == "mean":
                            combined = (kernels[0] + kernels[1] + kernels[2]) / 3.0
                        else:
                            combined = kernels[component] - kernels[2]
                        self._surface_combinations[key] = combined
                    kernel = self._surface_combinations[key]
                else:
                    kernel = kernels[component]
                px, py = kernel_parity(_name(component), traction)
                factor = ((1j * weight if (px + py) % 2 else weight) * spectrum)[:, :, None]
                terms[component].append((kernel, factor))
        return terms

    def _convolve(
        self, spectral: np.ndarray, components, terms: dict, surface: dict, worker: _Worker
    ) -> None:
        """The depth convolution of a worker's row blocks, in place in ``spectral``.

        Per block: the DCT-II/DST-II of every input component's real and imaginary parts
        (turned by ``i^r``, :meth:`_forward_z`), then per output component the products with
        the real kernels (:meth:`_accumulate`), the DCT-III/DST-III back (:meth:`_backward_z`),
        the traction stresses' terms (``surface``), into the output's slot of ``spectral``
        (:data:`_SLOT`).  The same operations in the same order per element whatever the
        blocks and threads: results do not depend on the number of threads.
        """
        for xs, kxs, mirrored in worker.blocks:
            r = xs.stop - xs.start
            transforms = worker.plans[r]
            for b in components:
                self._forward_z(b, spectral[b, xs], worker, transforms, worker.inputs[b, :, :r])
            for a, products in terms.items():
                acc = worker.acc[:, :r]
                self._accumulate(acc, worker.work[:, :r], products, worker.inputs, r, kxs, mirrored)
                target = spectral[_SLOT[a], xs]
                self._backward_z(a, acc, worker, transforms, target)
                for kernel, factor in surface.get(a, ()):
                    work = worker.surface[:r]
                    np.multiply(kernel[xs], factor[xs], out=work)
                    target += work

    def _forward_z(
        self, component, layers: np.ndarray, worker: _Worker, transforms: dict, target: np.ndarray
    ) -> None:
        """The z transform of a block's per-layer spectra ``layers``, turned by ``i^r``: an input.

        A DCT-II (component even in z: source and image add up to an even column) or DST-II
        (odd) of length M of the real and of the imaginary part, into ``target`` ``(2, rows,
        ny + 1, M + 1)``, planes real and imaginary; a component with rotation 1
        (:func:`_rotation`) is multiplied by i, ``(re, im) -> (-im, re)``.  The z slot the
        transform does not write (M for even components, 0 for odd) stays zero.

        Both planes at once through one real FFT of length M (Makhoul 1980): the column
        reordered (even layers, then the odd ones backwards; a DST-II is the DCT-II of the
        column with its odd layers negated, read backwards), transformed, and turned by
        ``2 exp(-i pi k / 2M)``: ``Y_k = Re T_k``, ``Y_(M-k) = -Im T_k``.  Only the box's
        layers are written into the reordered column (the zero padding stays zero).
        """
        m = self.length_z
        half = m // 2
        odd = _parity3(_name(component))[2]
        turned = _rotation(component)
        transform = transforms["rfft"]
        column, spectrum = transform.input_array, transform.output_array
        for plane, part in ((turned, layers.real), (1 - turned, layers.imag)):
            sign = -1.0 if (turned and plane == 0) else 1.0
            evens, odds = self._reordered(column[plane])
            np.multiply(part[..., 0::2], sign, out=evens)
            np.multiply(part[..., 1::2], -sign if odd else sign, out=odds)
        transform.execute()
        np.multiply(spectrum, worker.twiddle_forward, out=spectrum)
        if odd:  # slots 1 .. M hold Y_(M-1), ..., Y_0
            np.negative(spectrum.imag[..., 1:half], out=target[..., 1:half])
            target[..., half:] = spectrum.real[..., half::-1]
        else:  # slots 0 .. M-1 hold Y_0, ..., Y_(M-1)
            target[..., : half + 1] = spectrum.real
            np.negative(spectrum.imag[..., half - 1 : 0 : -1], out=target[..., half + 1 : m])

    def _backward_z(
        self, component, acc: np.ndarray, worker: _Worker, transforms: dict, target: np.ndarray
    ) -> None:
        """Inverse z transform of a block's accumulator into its layers ``target``, turned by i^r.

        DCT-III (output even in z) or DST-III (odd) of length M of each plane, the first
        ``nz`` values (the box's layers); a component with rotation 1 is multiplied by i on
        the way: ``(A0, A1) -> (-A1, A0)``.  Through one inverse real FFT of length M
        (Makhoul 1980): the half spectrum ``exp(i pi k / 2M) (X_k - i X_(M-k))`` (``X_M =
        0``; a DST-III is the DCT-III of the reversed input, its odd outputs negated), whose
        inverse is the output reordered (even layers, then the odd ones backwards).
        """
        m = self.length_z
        half = m // 2
        odd = _parity3(_name(component))[2]
        turned = _rotation(component)
        transform = transforms["irfft"]
        spectrum, column = transform.input_array, transform.output_array
        if odd:  # X_k = acc[M - k]
            spectrum.real[...] = acc[..., m : half - 1 : -1]
            np.negative(acc[..., 1 : half + 1], out=spectrum.imag[..., 1:])
        else:
            spectrum.real[...] = acc[..., : half + 1]
            np.negative(acc[..., m - 1 : half - 1 : -1], out=spectrum.imag[..., 1:])
        spectrum.imag[..., 0] = 0.0
        np.multiply(spectrum, worker.twiddle_backward, out=spectrum)
        transform.execute()
        planes = (target.imag, target.real) if turned else (target.real, target.imag)
        for plane, part in enumerate(planes):
            sign = -1.0 if (turned and plane == 1) else 1.0
            evens, odds = self._reordered(column[plane])
            np.multiply(evens, sign, out=part[..., 0::2])
            np.multiply(odds, -sign if odd else sign, out=part[..., 1::2])

    def _reordered(self, column: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Where a reordered column (last axis, length M) holds the box's layers (views).

        Makhoul's order: the even layers 0, 2, 4, ... first, the odd ones 1, 3, 5, ... from the
        end backwards (slots M - 1, M - 2, ...); the slots between stay the zero padding.
        """
        m, nz = self.length_z, self.shape[2]
        return column[..., : (nz + 1) // 2], column[..., m - 1 : m - 1 - nz // 2 : -1]

    def _workers(self) -> list[_Worker]:
        """Row blocks of the spectrum dealt to :attr:`threads` workers, with their buffers.

        Each block is ``(rows, kernel_rows, mirrored)``: spectrum rows ``kx`` and the rows of the
        stored kernel that hold them (``2nx - kx`` for the mirrored half).  Blocks of about
        :data:`CHUNK_BYTES` of spectrum per plane keep a block's z transforms, products and
        accumulator in cache; every worker has its own buffers and z plans (one thread each:
        the workers are the parallelism), made here, before any thread runs.
        """
        if self._work is None:
            nx, ny, _ = self.shape
            m = self.length_z
            row = (ny + 1) * (m + 1) * np.dtype(self._real).itemsize
            size = max(1, min(nx, CHUNK_BYTES // row))
            blocks = []
            for start in range(0, nx + 1, size):
                stop = min(nx + 1, start + size)
                blocks.append((slice(start, stop), slice(start, stop), False))
            for start in range(nx + 1, 2 * nx, size):
                stop = min(2 * nx, start + size)
                # rows kx in [start, stop) hold kernel rows 2nx - kx, from 2nx - start down
                blocks.append((slice(start, stop), slice(2 * nx - start, 2 * nx - stop, -1), True))
            count = max(1, min(self.threads, len(blocks)))
            self._work = [self._worker(blocks[w::count], size) for w in range(count)]
        return self._work

    def _worker(self, blocks: list, size: int) -> _Worker:
        """A worker's buffers and z plans for blocks of at most ``size`` rows."""
        _, ny, nz = self.shape
        m = self.length_z
        half = m // 2
        empty = functools.partial(pyfftw.empty_aligned, dtype=self._real)
        padded = empty((2, size, ny + 1, m))  # reordered input columns, zero past the layers
        column = empty((2, size, ny + 1, m))  # reordered output columns
        spectrum = pyfftw.empty_aligned((2, size, ny + 1, half + 1), dtype=self._complex)
        inputs = empty((6, 2, size, ny + 1, m + 1))
        acc = empty((2, size, ny + 1, m + 1))
        make = functools.partial(plan, planner=self.planner, threads=1, axes=(3,))
        plans = {}
        for r in sorted({xs.stop - xs.start for xs, _, _ in blocks}):
            plans[r] = {
                "rfft": make(padded[:, :r], spectrum[:, :r]),
                "irfft": make(
                    spectrum[:, :r],
                    column[:, :r],
                    direction="FFTW_BACKWARD",
                    extra=("FFTW_DESTROY_INPUT",),
                ),
            }
        padded[...] = 0.0
        inputs[...] = 0.0
        k = np.arange(half + 1)
        twiddles = (
            (2.0 * np.exp(-0.5j * np.pi * k / m)).astype(self._complex),
            np.exp(0.5j * np.pi * k / m).astype(self._complex),
        )
        surface = np.empty((size, ny + 1, nz), dtype=complex)
        return _Worker(blocks, plans, *twiddles, inputs, acc, empty(acc.shape), surface)

    def _accumulate(
        self,
        acc: np.ndarray,
        work: np.ndarray,
        products: list,
        inputs: np.ndarray,
        rows: int,
        kxs: slice,
        mirrored: bool,
    ) -> None:
        """``acc = sum (+-) kernel * input`` over one block's rows, both planes.

        ``products`` are ``(kernel, component, negative, px)``: a real kernel (broadcast over
        the real and imaginary planes), the input component (its turned transform in
        ``inputs``, one slot per component), the sign of the z rule and the kernel's parity
        in x, which gives its sign in the mirrored rows.
        """
        for n, (kernel, b, negative, px) in enumerate(products):
            values = inputs[b, :, :rows]
            minus = bool(negative) != bool(px and mirrored)
            if n == 0:
                np.multiply(kernel[kxs], values, out=acc)
                if minus:
                    np.negative(acc, out=acc)
            else:
                np.multiply(kernel[kxs], values, out=work)
                (np.subtract if minus else np.add)(acc, work, out=acc)

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
        tractions = [_TRACTION_OF_DIRECTION[axis] for axis in "xyz"]
        # sum over the layers of every component of every traction's kernels (real, (6, 2nx,
        # ny + 1, nz)) in one pass over the layers: sums[c] = sum_z layers[c] kernels[c]
        all_sums = self._layer_sums(
            layers, *(self.surface_stress.kernel_spectra(t) for t in tractions)
        )
        result = []
        for traction, sums in zip(tractions, all_sums, strict=True):
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
        threads: int = 1,
    ) -> int:
        """Approximate peak bytes of an operator in use (kept data plus one stress evaluation).

        Kept: the real 3-D kernel spectra of the plastic box (20 for trace-free eigenstrains
        with ``deviatoric``, else the 21 general ones, ``(nx + 1, ny + 1, M + 1)`` each), the
        per-layer 2-D transform buffers of the box, a box narrower than the window's own six
        layer spectra, the row-block workers' buffers (about 22 :data:`CHUNK_BYTES` each, one
        per thread), the window's per-layer surface-traction and traction-to-stress kernels
        (pressure, plus both shears with ``displacement``; in the volume's precision) and its
        batched 2-D FFT buffers.
        One evaluation: the six per-layer eigenstrain spectra of the window (the depth
        convolution writes its outputs over them), the output.  Setup transients (kernel
        construction) stay below the evaluation's share.  ``box``: the plastic box's cells
        ``(nx, ny)`` (default: the window's); ``precision``: of the 3-D parts
        (:data:`VOLUME_PRECISIONS`).
        """
        nx, ny, nz = grid.shape
        bx, by = box or (nx, ny)
        m = depth_length(nz)
        word = np.dtype(VOLUME_PRECISIONS[precision][0]).itemsize  # 8 or 4 bytes
        kernel3 = word * (bx + 1) * (by + 1) * (m + 1)
        box_layer = word * 2 * 2 * bx * (by + 1) * nz  # one complex per-layer spectrum
        threads = max(1, threads)  # a 2-D transform set and a row-block worker each
        buffers = threads * (box_layer + word * bx * 2 * by * nz + 22 * CHUNK_BYTES)
        if (bx, by) != (nx, ny):
            buffers += 6 * box_layer
        layer = 8 * 2 * nx * (ny + 1) * nz  # one float64 per-layer spectrum of the window
        layers = 12 * layer * word // 8  # the six complex layer spectra, volume's precision
        tractions = 3 if displacement else 1
        kept = (20 if deviatoric else 21) * kernel3 + buffers
        # per-layer kernels in the volume's precision: the tractions' (6 each), the surface
        # S_zz's (6), the pressure's deviator in xx and yy (2)
        kept += (6 * tractions + 6 + 2) * layer * word // 8 + 8 * 4 * nx * ny * nz + 2 * layer
        evaluation = layers + 8 * 6 * bx * by * nz
        return kept + evaluation


def depth_length(nz: int) -> int:
    """M, the half period of the symmetric depth convolution of ``nz`` layers.

    The smallest even fast FFT length (:func:`~solver.numerics.fftw.fft_size`) of at least ``2 nz``:
    even for the real FFTs of length M that carry the z transforms (Makhoul 1980).
    """
    return 2 * fft_size(nz)


#: Real and complex types of the 3-D eigenstrain convolution by ``solver.volume_precision``.
VOLUME_PRECISIONS = {"double": ("float64", "complex128"), "single": ("float32", "complex64")}

#: Slot of each output component in the per-layer spectra it replaces (the mean stress takes
#: zz's, which a trace-free route does not transform).
_SLOT = {0: 0, 1: 1, 2: 2, 3: 3, 4: 4, 5: 5, "mean": 2}


@dataclass
class _Worker:
    """One worker of the depth convolution: its row blocks, z plans (by rows) and buffers.

    ``plans[rows]``: the real FFTs of length M along z, ``"rfft"`` from the reordered input
    columns (zero after the box's layers) into a half spectrum, ``"irfft"`` from it into the
    reordered output columns (columns ``(2, rows, ny + 1, M)`` real, planes real and
    imaginary; the spectrum ``(2, rows, ny + 1, M/2 + 1)`` complex, shared);
    ``twiddle_forward``, ``twiddle_backward`` the turns of the spectra ``2 exp(-i pi k /
    2M)``, ``exp(i pi k / 2M)`` (:meth:`EigenstrainOperator._forward_z`); ``inputs`` ``(6,
    2, rows, ny + 1, M + 1)``: the turned z transforms of each component, planes real and
    imaginary; ``acc`` and ``work`` ``(2, rows, ny + 1, M + 1)``; ``surface`` ``(rows, ny +
    1, nz)`` complex: the traction terms.
    """

    blocks: list
    plans: dict
    twiddle_forward: np.ndarray
    twiddle_backward: np.ndarray
    inputs: np.ndarray
    acc: np.ndarray
    work: np.ndarray
    surface: np.ndarray


#: Pieces of layers each component's per-layer 2-D transforms are cut into
#: (:meth:`EigenstrainOperator._each_component`): the five deviatoric components in ten pieces
#: share evenly between two threads.
LAYER_PIECES = 2

#: Bytes per plane of a row block of the depth convolution
#: (:meth:`EigenstrainOperator._workers`).
CHUNK_BYTES = 2**18


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
