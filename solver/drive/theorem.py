"""A case solved by Melan's theorem, not along its load path (``method = "static_shakedown"``).

The case gives the track: its Hertz contact (the largest normal force of its loaded slides,
Hertz's p_0 and semi-axes), the shear ``mu p`` of gross sliding along x,
Poisson's ratio and the yield stress of body 2 (k = sigma_Y0 / sqrt 3), its kinematic
hardening (the back stress bound: Armstrong-Frederick's saturation, unbounded for Prager's);
the cross-section's cells follow the case's cells (a / the largest cell side, from
:data:`MIN_CELLS` to :data:`MAX_CELLS` a contact radius, the smaller semi-axis of an
ellipse).  A circular contact passes Hamilton's closed-form field, an elliptical one its
Hertz pressure on cells (:mod:`solver.theorems.loads`).  :func:`solve_static_shakedown`
returns a :class:`~solver.result.Result` of one step: the limits (histories
``static_shakedown_limit``: the program's factor on the section's points, an estimate;
``static_shakedown_lower_bound``: that factor certified between them, a lower bound;
``shakedown_upper_bound``, ``kinematic_upper_bound`` (inf: not solved),
``first_yield_limit``, ``shakedown_load_factor``), the program's residual field and where it
binds (fields on ``y_section``, ``z_section``), and on the surface the
Hertz pressure and the sliding shear the theorem passes along the track.  Status: converged
when the program is optimal, truncated when the elastic field yields outside the
cross-section's box, not converged otherwise; the reason is a note.
"""

from __future__ import annotations

import math
import time

import numpy as np

from ..case.case import Case
from ..result import SEPARATED, SLIP, Result
from ..theorems.loads import elliptical_hertz, traction_limit
from ..theorems.track import Track, TrackLimits, track_limits
from ..theory.hertz import hertz

#: Fewest and most cross-section cells a contact radius.
MIN_CELLS, MAX_CELLS = 4, 16
#: Cost of the programs on the development machine (one core; ``python -m study bench
#: shakedown`` and tests/test_koiter.py): the static program's seconds and bytes (at most, on
#: the cells a case gives), the kinematic one's per cube of its cells a contact radius
#: (4 s and 0.3 GB at 8, 31 s and 2.1 GB at 16).
STATIC_SECONDS, STATIC_BYTES = 5.0, 80 * 2**20
KINEMATIC_SECONDS, KINEMATIC_BYTES = 8e-3, 6e5


def theorem_cost(case: Case) -> tuple[float, int]:
    """Estimated seconds (one core) and bytes beyond the interpreter of a theorem case."""
    _, _, axes, _ = track_of(case)
    circular = math.isclose(axes[0], axes[1], rel_tol=1e-9)
    cube = case.solver.kinematic_cells**3 if circular else 0
    return STATIC_SECONDS + KINEMATIC_SECONDS * cube, int(STATIC_BYTES + KINEMATIC_BYTES * cube)


def track_of(case: Case) -> tuple[Track, float, tuple[float, float], float]:
    """The track of a static-shakedown case: its Track, p_0 (Pa), semi-axes (m), force (N).

    The Track's cells are those of a contact radius (the smaller semi-axis of an ellipse).
    """
    body = case.body2
    hardening = body.hardening
    force = max(s.normal_force for s in case.stages if s.motion == "slide")
    contact = hertz(force, case.pair.composite_modulus, case.pair.curvature)
    bound = None
    if hardening.kinematic:
        recall = hardening.kinematic_recall
        saturation = hardening.kinematic_modulus / recall if recall > 0.0 else math.inf
        bound = math.sqrt(2.0) * saturation / hardening.yield_stress
    grid = case.surface_grid
    cell = max(grid.dx, grid.dy, case.volume_grid.dz if case.volume_grid else 0.0)
    axes = (contact.semi_axis_x, contact.semi_axis_y)
    cells = min(MAX_CELLS, max(MIN_CELLS, round(min(axes) / cell)))
    track = Track("point", case.friction_coefficient, body.nu, cells, back_stress_bound=bound)
    return track, contact.max_pressure, axes, force


def _limits(case: Case) -> tuple[TrackLimits, float, float, float]:
    """The case's limits, the factor to p_0/k, the residual field's unit (Pa), the length (m).

    A circular contact passes Hamilton's closed-form field (:func:`track_limits`, lengths in
    a, stresses in k); an elliptical one its Hertz pressure on cells of the smaller semi-axis
    over ``cells`` (:func:`traction_limit`, factors of the load, lengths in m).
    """
    track, p0, axes, _ = track_of(case)
    k = case.body2.hardening.yield_stress / math.sqrt(3.0)
    if math.isclose(axes[0], axes[1], rel_tol=1e-9):
        cells = case.solver.kinematic_cells or None
        return track_limits(track, cells), 1.0, k, axes[0]
    pressure, shear, grid = elliptical_hertz(axes, p0, track.friction, track.cells)
    h, small = grid.dx, min(axes)
    limits = traction_limit(
        pressure, shear, grid, track.nu, k,
        depth=round(track.depth * small / h),
        width=math.ceil((axes[1] + track.width * small) / h),
        span=math.ceil(track.span * small / h),
        back_stress_bound=track.back_stress_bound,
    )  # fmt: skip
    return limits, p0 / k, 1.0, 1.0


def solve_static_shakedown(case: Case) -> Result:
    """Melan's static limit of the case's sliding track, with its upper bound and first yield."""
    start = time.perf_counter()
    _, p0, axes, force = track_of(case)
    k = case.body2.hardening.yield_stress / math.sqrt(3.0)
    limits, factor, unit, length = _limits(case)
    static = limits.static
    notes = [*case.warnings, f"static shakedown ({static.status}): {static.reason}"]
    if limits.lower < static.factor:
        y, z, s = limits.lower_at
        notes.append(
            f"certified lower bound {limits.lower * factor:.5g} (the program's field checked "
            f"between its points and positions; binds at y = {y * length:.3g}, "
            f"z = {z * length:.3g}, load at x = {s * length:.3g})"
        )
    kinematic = math.inf  # no bound
    if limits.kinematic is not None:
        notes.append(f"kinematic bound ({limits.kinematic.status}): {limits.kinematic.reason}")
        kinematic = limits.kinematic.factor
    elif case.solver.kinematic_cells:
        notes.append("kinematic bound: not solved for an elliptical contact (circular only)")
    history = {
        "normal_force": np.array([force]),
        "max_pressure": np.array([p0]),
        "static_shakedown_limit": np.array([static.factor * factor]),
        "static_shakedown_lower_bound": np.array([limits.lower * factor]),
        "shakedown_upper_bound": np.array([limits.upper * factor]),
        "kinematic_upper_bound": np.array([kinematic * factor]),
        "first_yield_limit": np.array([limits.first_yield * factor]),
        "shakedown_load_factor": np.array([limits.lower * factor * k / p0]),
        "program_iterations": np.array([float(static.solver_iterations)]),
        "step_converged": np.array([1.0 if static.converged else 0.0]),
    }
    grid = case.surface_grid
    x, y = np.meshgrid(grid.x, grid.y, indexing="ij")
    ellipse = (x / axes[0]) ** 2 + (y / axes[1]) ** 2
    pressure = p0 * np.sqrt(np.clip(1.0 - ellipse, 0.0, None))
    fields = {
        "static_residual_stress": static.residual * unit,
        "static_binding": static.binding.astype(np.int8),
    }
    result = Result(
        case=case,
        grid=grid,
        pressure=pressure,
        shear_x=case.friction_coefficient * pressure,
        shear_y=np.zeros_like(pressure),
        contact_state=np.where(pressure > 0.0, SLIP, SEPARATED).astype(np.int8),
        history=history,
        loops=("static_shakedown",),
        converged=static.status in ("optimal", "box_too_small"),
        notes=notes,
        fields=fields,
        truncated=static.status == "box_too_small",
        section=(limits.y * length, limits.z * length),
    )
    result.wall_time = time.perf_counter() - start
    return result


def conformed_limit(result: Result) -> TrackLimits:
    """Melan's factor of a solved sliding case's final tractions, passed along its track.

    The pressure and shear the case carried last (on the print it made, when the print is in
    the gap) as the load of the static theorem (:func:`solver.theorems.loads.traction_limit`,
    body 2 elastic-perfectly plastic or kinematic as in the case), on the case's cells: a
    factor of at least 1 says the contact as it has conformed shakes down under its own load.
    The case's grid must be centred on the track (y = 0, an even number of cells across).
    """
    case = result.case
    if result.pressure.max() <= 0.0:
        raise ValueError("the case ends unloaded: no tractions to pass along the track")
    track = track_of(case)[0]
    grid = result.grid
    k = case.body2.hardening.yield_stress / math.sqrt(3.0)
    extent = np.flatnonzero(result.pressure.max(axis=0) > 0.0)  # the contact's columns
    small = 0.5 * (extent[-1] - extent[0] + 1) * grid.dy  # half its width across the track
    return traction_limit(
        result.pressure, result.shear_x, grid, track.nu, k,
        depth=round(track.depth * small / grid.dy),
        width=math.ceil((small + track.width * small) / grid.dy),
        span=math.ceil(track.span * small / grid.dx),
        back_stress_bound=track.back_stress_bound,
    )  # fmt: skip


__all__ = [
    "MAX_CELLS",
    "MIN_CELLS",
    "conformed_limit",
    "solve_static_shakedown",
    "theorem_cost",
    "track_of",
]
