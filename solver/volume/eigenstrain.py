r"""Residual stress and surface displacement of an eigenstrain (plastic strain) field.

The half-space ``z > 0`` (z into body 2) holds a piecewise-constant eigenstrain on the cells of
a :class:`~solver.numerics.grid.VolumeGrid`, components (xx, yy, zz, yz, xz, xy), tensor
values.  Chiu's (1978) construction, applied with FFTs as Liu & Wang (2005):

1. *Source*: every cell is a cuboid of uniform eigenstrain in an infinite body
   (:mod:`solver.volume.cuboid`).
2. *Image*: the mirror cuboid at ``-z`` with ``e_xz`` and ``e_yz`` negated.  Source plus image is
   symmetric about ``z = 0``: there ``u_z = 0``, ``sigma_xz = sigma_yz = 0``, and the normal
   stress ``S_zz(x, y, 0) = 2 sigma_zz^source(x, y, 0)`` remains.
3. *Boussinesq correction*: the half-space solution of a surface pressure ``p = S_zz`` (its
   values at the surface-cell centres, piecewise constant) cancels it (the pressure kernels of
   :class:`~solver.volume.stress.SubsurfaceStressOperator` at every layer).  ``S_zz`` is known
   on the grid only; the part outside is dropped, which changes the stresses by ~1e-5 of their
   maximum in the tests (an eigenstrain blob at depth 4 in a window 8 depths wide).

The 3-D convolution of source and image (symmetric in z, by DCTs and DSTs along z) runs in
:mod:`solver.volume.eigenstrain_convolution`, with the kernel spectra of
:mod:`solver.volume.eigenstrain_kernels`.

Surface residual displacements (body-2 frame, z into the body; a uniform layer of thickness h
with ``e_zz > 0`` gives ``u_z = -h e_zz``), two routes:

* ``"reciprocal"`` (default, DESIGN §3.7): ``u_k = sum_cells sigma^(k)_ij e_ij dV / dA``, with
  ``sigma^(k)`` the stress of a unit traction on one surface cell in direction k (the
  :class:`~solver.volume.stress.SubsurfaceStressOperator` kernels; a 2-D correlation per
  layer).  The surface-cell average of u, with the volume integral taken by the midpoint rule
  in each cell; nothing is truncated (lateral sums of the kernels are exact).
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

import numpy as np

from ..numerics.grid import IndexBox, VolumeGrid
from ..numerics.tensor import complete_deviator, deviator
from ..numerics.threads import by_rows, each
from .eigenstrain_convolution import (
    CHUNK_BYTES,
    SLOT,
    EigenstrainConvolution,
    depth_length,
)
from .eigenstrain_kernels import (
    COMPONENT_WEIGHTS,
    DEVIATORIC,
    EigenstrainKernels,
    _is_imaginary,
    component_name,
    kernel_plans,
    parity3,
)
from .stress import STRESS_COMPONENTS, SubsurfaceStressOperator, kernel_parity

#: Sign of each eigenstrain component in the mirror image (xz and yz flip).
IMAGE_SIGNS = np.array([1.0, 1.0, 1.0, -1.0, -1.0, 1.0])

#: The surface traction whose kernels give the displacement along each direction.
_TRACTION_OF_DIRECTION = {"x": "shear_x", "y": "shear_y", "z": "pressure"}


class EigenstrainOperator(EigenstrainKernels, EigenstrainConvolution):
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
    :class:`~solver.volume.stress.SubsurfaceStressOperator` kernels (pressure for the
    correction, both shears as well for the reciprocal displacement) and, only if the direct
    displacement route is used, its 12 per-layer kernels.
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
        if grid.periodic and (
            self.shape[:2] != grid.shape[:2] or grid.shape[0] % 2 or grid.shape[1] % 2
        ):
            raise ValueError(
                "a periodic grid's plastic box is the whole period, of an even number of cells "
                f"along x and y: got a box of {self.shape[:2]} on {grid.shape[:2]} cells"
            )
        #: Lateral FFT lengths of the box's layer transforms (twice its cells, or the period's)
        self.lengths = grid.fft_lengths(*self.shape[:2])
        #: Half of them: the kernel spectra's extents (``(hx + 1, hy + 1, M + 1)``)
        self.halves = (self.lengths[0] // 2, self.lengths[1] // 2)
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
        self._volume: list | None = None
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

    def make_plans(self) -> None:
        """Make every FFT plan a solve uses, without building kernels.

        With the ``"FFTW_MEASURE"`` planner this measures them into FFTW's wisdom
        (:mod:`solver.numerics.fftw`), which ``solver.fft_planner = "wisdom"`` then reuses.
        """
        self._volume_plans()
        self._workers()
        kernel_plans(self.halves, self.length_z, self.planner, self.threads)
        self.surface_stress.make_plans()

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
        """Per-layer 2-D transforms of the (zero-padded) eigenstrain: ``(6, Lx, Ly/2 + 1, nz)``.

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
            lx, ly = self.lengths
            out = np.empty((6, lx, ly // 2 + 1, self.shape[2]), dtype=self._complex)
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
            pa = parity3(component_name(a))
            terms[a] = []
            for b in components:
                pb = parity3(component_name(b))
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
            plans["data"][...] = spectral[SLOT[a], ..., zs]
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
        """Per-layer spectra ``(6, Lx, Ly/2 + 1, nz)`` of a box narrower than the window (kept)."""
        if self._box_spectra is None:
            (lx, ly), nz = self.lengths, self.shape[2]
            self._box_spectra = np.zeros((6, lx, ly // 2 + 1, nz), dtype=self._complex)
        return self._box_spectra

    def _surface_terms(self, outputs: list, spectra: dict, trace_free: bool) -> dict:
        """Per output component, the traction stresses' terms ``[(kernel, factor)]``.

        ``spectra`` are the tractions' surface spectra
        (:meth:`~solver.volume.stress.SubsurfaceStressOperator.surface_spectrum`); the kernels
        those of :meth:`~solver.volume.stress.SubsurfaceStressOperator.kernel_spectra`,
        combined for a trace-free route's outputs: ``sigma_xx - sigma_zz`` and ``sigma_yy -
        sigma_zz`` for xx and yy, the mean stress for ``"mean"`` (kept once built).
        ``kernel[rows] * factor[rows]`` is the layer spectra of the component's output (every
        output but the mean carries its tensor weight until the end).
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
                px, py = kernel_parity(component_name(component), traction)
                factor = ((1j * weight if (px + py) % 2 else weight) * spectrum)[:, :, None]
                terms[component].append((kernel, factor))
        return terms

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
        with ``deviatoric``, else the 21 general ones, ``(Lx/2 + 1, Ly/2 + 1, M + 1)`` each), the
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
        (lx, ly), (wx, wy) = grid.fft_lengths(bx, by), grid.fft_lengths()
        m = depth_length(nz)
        word = np.dtype(VOLUME_PRECISIONS[precision][0]).itemsize  # 8 or 4 bytes
        kernel3 = word * (lx // 2 + 1) * (ly // 2 + 1) * (m + 1)
        box_layer = word * 2 * lx * (ly // 2 + 1) * nz  # one complex per-layer spectrum
        threads = max(1, threads)  # a 2-D transform set and a row-block worker each
        buffers = threads * (box_layer + word * bx * ly * nz + 22 * CHUNK_BYTES)
        if (bx, by) != (nx, ny):
            buffers += 6 * box_layer
        layer = 8 * wx * (wy // 2 + 1) * nz  # one float64 per-layer spectrum of the window
        layers = 12 * layer * word // 8  # the six complex layer spectra, volume's precision
        tractions = 3 if displacement else 1
        kept = (20 if deviatoric else 21) * kernel3 + buffers
        # per-layer kernels in the volume's precision: the tractions' (6 each), the surface
        # S_zz's (6), the pressure's deviator in xx and yy (2)
        kept += (6 * tractions + 6 + 2) * layer * word // 8 + 8 * wx * wy * nz + 2 * layer
        evaluation = layers + 8 * 6 * bx * by * nz
        return kept + evaluation


#: Real and complex types of the 3-D eigenstrain convolution by ``solver.volume_precision``.
VOLUME_PRECISIONS = {"double": ("float64", "complex128"), "single": ("float32", "complex64")}
