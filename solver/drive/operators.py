"""One bundle of operators per case: surface, subsurface stress and eigenstrain, built once.

All three are built with the case's FFT planner and threads and share what they can: the
eigenstrain operator uses the same :class:`~solver.volume.stress.SubsurfaceStressOperator` (its
kernels serve both the stress of the tractions and the residual surface displacements).  Bundles are
cached per (grid, materials, FFT settings), so cases of a campaign on the same grid reuse them;
the volume operators of the last case only (they can take gigabytes).
:meth:`CaseOperators.memory_bytes` states what a case's bundle and work arrays hold, for the
study scheduler.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..bodies.materials import Pair
from ..case.case import Case
from ..case.options import SolverOptions
from ..numerics.fftw import PLANNER_FLAGS
from ..numerics.grid import SurfaceGrid, VolumeGrid
from ..surface.convolution import SurfaceOperator, surface_operator
from ..surface.periodic import periodic_surface_operator, y_periodic_surface_operator
from ..surface.steady import SteadyOperator
from ..volume.eigenstrain import VOLUME_PRECISIONS, EigenstrainOperator
from ..volume.plane_strain import PlaneStrainStressOperator
from ..volume.stress import SubsurfaceStressOperator
from .fatigue import CYCLE_BLOCK_BYTES, CYCLE_BLOCK_COPIES, reads_cycle


def planner_flag(options: SolverOptions) -> str:
    """FFTW planner flag of ``solver.fft_planner`` (:data:`solver.numerics.fftw.PLANNER_FLAGS`)."""
    return PLANNER_FLAGS[options.fft_planner]


def initial_gap(case: Case) -> np.ndarray:
    """The undeformed gap (m) on the surface grid (:meth:`~solver.bodies.geometry.Geometry.gap`)."""
    period = case.grid.size if case.grid.periodic else None
    return case.pair.geometry.gap(*case.surface_grid.mesh(), period)


#: Volume operators by (grid, body, FFT threads, planner, with eigenstrain), of the last case
#: built only: they can take gigabytes, and a rank solving cases on different volume grids in
#: turn must not hold the operators of each (:meth:`CaseOperators.memory_bytes` is per case).
_VOLUME_OPERATORS: dict[tuple, tuple] = {}


def _volume_operators(keys: list[tuple]) -> list[tuple]:
    """(stress, eigenstrain or None) for each key, reusing the last case's; drops the others."""
    for key in [k for k in _VOLUME_OPERATORS if k not in keys]:
        del _VOLUME_OPERATORS[key]
    out = []
    for key in keys:
        if key not in _VOLUME_OPERATORS:
            grid, body, threads, planner, eigenstrain, box, precision = key
            real = VOLUME_PRECISIONS[precision][0]  # kernels kept in the volume's precision
            stress = SubsurfaceStressOperator(
                grid, body.nu, threads=threads, planner=planner, dtype=real
            )
            plastic = None
            if eigenstrain:
                plastic = EigenstrainOperator(
                    grid, body.E, body.nu, threads=threads, planner=planner,
                    surface_stress=stress, box=box, precision=precision,
                )  # fmt: skip
            _VOLUME_OPERATORS[key] = (stress, plastic)
        out.append(_VOLUME_OPERATORS[key])
    return out


@dataclass
class CaseOperators:
    """Operators and fixed data of one case.

    Attributes
    ----------
    case : Case
        The case.
    surface : SurfaceOperator
        Relative surface displacements of the pair from tractions.
    gap : ndarray
        Undeformed gap (m).
    stress : SubsurfaceStressOperator or PlaneStrainStressOperator or None
        Stress in body 2 from surface tractions (with a volume grid; plane strain in a line
        contact).
    eigenstrain : EigenstrainOperator or None
        Residual stress and surface displacement of plastic strain in body 2 (elastic-plastic
        cases only).
    stress1, eigenstrain1 : optional
        The same for body 1 when both bodies are elastic-plastic and different (each in its
        own frame, z into body 1).
    local : CaseOperators or None
        The bundle on the window that follows a moving contact (:attr:`Case.moving_window`
        cells, body 2's volume under it), placed by :meth:`at`; None without one.
    wear : ndarray or None
        The bodies' worn depths summed (m) on this bundle's grid, added to the gap of every
        solve (:mod:`solver.drive.wear`); None: nothing wears.
    """

    case: Case
    surface: SurfaceOperator
    gap: np.ndarray
    stress: SubsurfaceStressOperator | PlaneStrainStressOperator | None = None
    eigenstrain: EigenstrainOperator | None = None
    stress1: SubsurfaceStressOperator | None = None
    eigenstrain1: EigenstrainOperator | None = None
    local: CaseOperators | None = None
    wear: np.ndarray | None = None
    _moved: tuple | None = field(default=None, init=False, repr=False)

    def gap_at(self, position: tuple[float, float]) -> np.ndarray:
        """Undeformed gap (m) with body 1's apex at ``position`` (m) over body 2 (sliding).

        On the surface operator's grid; :attr:`gap` at the origin; the last other position's
        gap is kept.
        """
        if position[0] == 0.0 and position[1] == 0.0:
            return self.gap
        key = (float(position[0]), float(position[1]))
        if self._moved is None or self._moved[0] != key:
            period = self.case.grid.size if self.case.grid.periodic else None
            self._moved = (key, self.case.pair.gap(*self.surface.grid.mesh(), key, period))
        return self._moved[1]

    def at(self, grid: SurfaceGrid) -> CaseOperators:
        """The bundle on a grid of the same cells placed elsewhere (the same kernels).

        The surface operator is placed there (:meth:`SurfaceOperator.place`): the bundle it
        came from is there too from now on.

        The window that follows a moving contact (:mod:`solver.drive.window`) is :attr:`local`
        placed at the contact, increment by increment.
        """
        surface = self.surface.place(grid)
        gap = self.case.pair.geometry.gap(*grid.mesh())
        return CaseOperators(self.case, surface, gap, self.stress, self.eigenstrain)

    def volume(self, body: int) -> tuple[SubsurfaceStressOperator, EigenstrainOperator]:
        """(stress, eigenstrain) operators of body ``body`` (1 or 2)."""
        return (self.stress1, self.eigenstrain1) if body == 1 else (self.stress, self.eigenstrain)

    @property
    def options(self) -> SolverOptions:
        """Tolerances and caps."""
        return self.case.solver

    @property
    def pair(self) -> Pair:
        """The two bodies."""
        return self.case.pair

    @classmethod
    def build(cls, case: Case) -> CaseOperators:
        """The bundle a case needs (volume operators only with a volume grid in use)."""
        options = case.solver
        planner = planner_flag(options)
        build_surface = (
            periodic_surface_operator
            if case.grid.periodic
            else y_periodic_surface_operator
            if case.grid.periodic_y
            else surface_operator
        )
        surface = build_surface(case.surface_grid, case.pair, options.fft_threads, planner)
        plastic_case = case.plastic_body is not None
        keys = []
        threads, box, precision = options.fft_threads, case.plastic_box, options.volume_precision
        line_stress = None  # a line contact's plane-strain stresses (elastic bodies only)
        if case.grid.periodic_y and ("stress" in case.fields or case.fatigue is not None):
            line_stress = PlaneStrainStressOperator(case.volume_grid, case.body2.nu)
        elif plastic_case or "stress" in case.fields or case.fatigue is not None:
            volume = case.volume_grid
            keys.append((volume, case.body2, threads, planner, plastic_case, box, precision))
        if 1 in case.plastic_bodies:
            volume1 = case.volume_grid_of(1)
            keys.append((volume1, case.body1, threads, planner, True, box, precision))
        window = case.moving_window
        if window is not None:  # the volume under the window that follows the contact
            grid = SurfaceGrid(*window, case.surface_grid.dx, case.surface_grid.dy)
            if case.volume_grid is not None:
                local_volume = VolumeGrid(grid, case.volume_grid.nz, case.volume_grid.dz)
                key = (local_volume, case.body2, threads, planner, plastic_case, None, precision)
                keys.append(key)
        volumes = _volume_operators(keys)
        local = None
        if window is not None:
            stress, plastic = volumes.pop() if case.volume_grid is not None else (None, None)
            local_surface = surface_operator(grid, case.pair, options.fft_threads, planner)
            gap = case.pair.geometry.gap(*grid.mesh())
            local = cls(case, local_surface, gap, stress, plastic)
        volumes += [(None, None)] * (2 - len(volumes))
        (stress, plastic), (stress1, plastic1) = volumes
        stress = stress if line_stress is None else line_stress
        return cls(case, surface, initial_gap(case), stress, plastic, stress1, plastic1, local)

    @staticmethod
    def memory_bytes(case: Case) -> int:
        """Peak bytes the bundle and the solver's work arrays are expected to need.

        The interpreter with numpy and pyfftw (:data:`PROCESS_BYTES`), the surface operator
        and ~40 surface work arrays (a steady rolling solve's boxes too); with a volume grid
        the stress operator (kernels of the tractions in use) and an evaluated stress field;
        for elastic-plastic cases the eigenstrain operator and the plasticity loop's arrays
        (plastic strain and its increment, trial stress, Anderson history:
        :func:`plastic_work_arrays` six-component fields).
        """
        nx, ny = case.grid.nx, case.grid.ny
        tangential = case.friction_coefficient > 0
        total = PROCESS_BYTES + SurfaceOperator.memory_bytes(case.surface_grid, tangential)
        total += 8 * nx * ny * 40 + 8 * 16 * case.total_steps
        volume = case.volume_grid
        window = case.moving_window
        if any(stage.motion == "steady" for stage in case.stages):  # the contact's boxes
            total += SteadyOperator.memory_bytes(case.surface_grid)
        if window is not None:  # the window's own surface operator
            cells_grid = SurfaceGrid(*window, case.surface_grid.dx, case.surface_grid.dy)
            total += SurfaceOperator.memory_bytes(cells_grid, tangential)
        if case.plastic_body is not None:
            box = case.plastic_box.shape[:2] if case.plastic_box else (nx, ny)
            cells = 8 * 6 * box[0] * box[1] * volume.nz
            bodies = len(case.plastic_bodies)
            total += bodies * EigenstrainOperator.memory_bytes(
                volume,
                deviatoric=True,
                box=box,
                precision=case.solver.volume_precision,
                threads=case.solver.fft_threads,
            )
            if window is not None:  # the loop on the window; the track's fields kept apart
                local = VolumeGrid(SurfaceGrid(*window, 1.0, 1.0), volume.nz, 1.0)
                total += EigenstrainOperator.memory_bytes(
                    local, deviatoric=True, precision=case.solver.volume_precision,
                    threads=case.solver.fft_threads,
                )  # fmt: skip
                total += TRACK_FIELDS * cells
                cells = 8 * 6 * window[0] * window[1] * volume.nz
            work = plastic_work_arrays(case.solver, box=case.plastic_box is not None)
            total += int(bodies * work * cells)
            pair = (case.body1, case.body2)
            kinematic = sum(b.hardening is not None and b.hardening.kinematic for b in pair)
            total += 2 * kinematic * cells  # back stress before and after the increment
        if reads_cycle(case):  # a cycle's paths, a block of layers at a time
            samples = max(sum(s.steps for s in case.stages if s.cycle == case.cycles), 1)
            per_layer = 48 * samples * nx * ny
            total += CYCLE_BLOCK_COPIES * per_layer * max(1, CYCLE_BLOCK_BYTES // per_layer)
            total += 3 * 8 * nx * ny * samples  # the cycle's tractions
        if case.plastic_body is None and ("stress" in case.fields or case.fatigue is not None):
            tractions = 3 if tangential else 1
            kind = PlaneStrainStressOperator if case.grid.periodic_y else SubsurfaceStressOperator
            total += kind.memory_bytes(volume, tractions)
            total += 2 * 8 * 7 * nx * ny * volume.nz
        return total


#: Resident memory of a rank's interpreter besides its case: 118 MiB measured on 2026-11-25
#: (Linux, Python 3.11.7, numpy 2) when pyFFTW still loaded dask, xarray and pandas.  Kept as
#: a margin for the study's own libraries: a worker rank of tiny cases peaks at 100 MiB since
#: (2026-11-28), a process that only solves at about 67 MiB.
PROCESS_BYTES = 118 * 2**20
#: Six-component float64 volume fields the plasticity loop holds at once besides Anderson's:
#: previous strain, increment, strain (rewritten in place), the last step's increment (the next
#: step's start) and the return mapping's temporaries (about one; 128^3 measured 2026-11-25:
#: estimate 8 % above the peak).
PLASTIC_LOOP_ARRAYS = 5
#: Six-component fields in the volume's precision (half a field each when single): the trial
#: stress (returned in place), the residual stress evaluation's output, the returned
#: increment, the change, and the best iterate's stress and increment.
PLASTIC_VOLUME_ARRAYS = 6
#: More when the plastic box is narrower than the window: the traction stress and its deviator
#: (with the box as the window they join the residual stress's layer spectra).
BOX_SURFACE_ARRAYS = 2


#: Six-component float64 fields of the track a case solved on the window that follows its
#: contact (:mod:`solver.drive.window`) holds besides the window's loop: the plastic strain and its
#: copy as the window's goes back in, the frozen residual stress and its evaluation's output.
TRACK_FIELDS = 4


def plastic_work_arrays(options: SolverOptions, box: bool = False) -> float:
    """Six-component float64 volume fields held at once by the plasticity loop of one body.

    :data:`PLASTIC_LOOP_ARRAYS`, :data:`PLASTIC_VOLUME_ARRAYS` (halves in single precision),
    :data:`BOX_SURFACE_ARRAYS` with a plastic ``box``, and Anderson's share, on the five
    independent components of the increment (5/6 of a field each): its last iterate and
    residual, the differences of ``memory + 1`` iterates and residuals in float32 (half a field
    each), and the mixing's two inputs and its output.
    """
    anderson = 5 / 6 * (2 + (options.anderson_memory + 1) + 3)
    volume = PLASTIC_VOLUME_ARRAYS * (0.5 if options.volume_precision == "single" else 1.0)
    surface = BOX_SURFACE_ARRAYS if box else 0
    return PLASTIC_LOOP_ARRAYS + volume + surface + anderson


def memory_estimate(case: Case) -> int:
    """Peak memory (bytes) a case's solve is expected to need, for the study scheduler.

    :meth:`CaseOperators.memory_bytes`: the bundle and the solver's work arrays; a case solved
    by the shakedown theorems: the interpreter and the programs
    (:func:`~solver.drive.theorem.theorem_cost`).
    """
    if case.solver.method == "static_shakedown":
        from .theorem import theorem_cost  # its linear programs' libraries only when needed

        return PROCESS_BYTES + theorem_cost(case)[1]
    return CaseOperators.memory_bytes(case)
