"""The load-step loop: runs, for every increment of the load path, only the loops the scene needs.

| scene                                              | loops                         |
|----------------------------------------------------|-------------------------------|
| frictionless, or beta = 0 with no tangential load   | load_steps + normal           |
| friction with beta != 0 or a tangential load        | load_steps + slip_stick       |

(DESIGN §3.8; the plasticity loop joins in a later release.)
"""

from __future__ import annotations

import time

import numpy as np

from .case import Case
from .convolution import surface_operator
from .normal import solve_normal
from .reference import hertz
from .result import SEPARATED, SLIP, STICK, Result


def initial_gap(case: Case) -> np.ndarray:
    """Undeformed gap h_i = x^2/(2 R_x) + y^2/(2 R_y) (m) on the case's surface grid."""
    kx, ky = case.pair.curvature
    x, y = case.surface_grid.mesh()
    return 0.5 * (kx * x * x + ky * y * y)


def planner_flag(case: Case) -> str:
    """FFTW planner flag of the case's ``solver.fft_planner``."""
    return "FFTW_MEASURE" if case.solver.fft_planner == "measure" else "FFTW_ESTIMATE"


def needs_slip_stick(case: Case) -> bool:
    """True when friction couples to the normal problem (beta != 0) or a shear load exists."""
    if case.friction_coefficient == 0.0:
        return False
    return case.pair.dundurs_beta != 0.0 or case.has_tangential_load


def solve(case: Case) -> Result:
    """Solve a case over its whole load path.

    Parameters
    ----------
    case : Case
        A validated case.

    Returns
    -------
    Result
        Final tractions, per-step histories and status; non-convergence is reported in
        ``Result.converged`` and ``Result.notes``, never raised.
    """
    start = time.perf_counter()
    result = _solve_surface(case)
    if "stress" in case.fields:
        from .stress import subsurface_operator, von_mises

        operator = subsurface_operator(
            case.volume_grid, case.body2.nu, case.solver.fft_threads, planner_flag(case)
        )
        result.stress = operator.stress(result.pressure, result.shear_x, result.shear_y)
        result.von_mises = von_mises(result.stress)
        result.depth = case.volume_grid.z
    result.wall_time = time.perf_counter() - start
    return result


def _solve_surface(case: Case) -> Result:
    """The contact solution on the surface (all load steps), without field outputs."""
    grid = case.surface_grid
    operator = surface_operator(grid, case.pair, case.solver.fft_threads, planner_flag(case))
    gap = initial_gap(case)
    targets = case.step_targets()
    if needs_slip_stick(case):
        from .slipstick import run_slip_stick

        return run_slip_stick(case, operator, gap, targets)

    history = {k: np.zeros(len(targets)) for k in _NORMAL_HISTORY}
    notes: list[str] = []
    pressure = None
    area = grid.cell_area
    pair, mesh = case.pair, grid.mesh()
    all_converged = True
    for k, (force, _, _) in enumerate(targets):
        # Quadric bodies: the Hertz pressure of this force is a close first guess.
        initial = hertz(force, pair.composite_modulus, pair.curvature).pressure(*mesh)
        solution = solve_normal(
            operator,
            gap,
            force,
            initial_pressure=initial,
            tolerance=case.solver.normal_tolerance,
            max_iterations=case.solver.normal_max_iterations,
        )
        pressure = solution.pressure
        if not solution.converged:
            all_converged = False
            notes.append(f"step {k + 1}: normal solve {solution.message}")
        history["normal_force"][k] = pressure.sum() * area
        history["approach"][k] = solution.approach
        history["max_pressure"][k] = pressure.max()
        history["contact_area"][k] = np.count_nonzero(pressure) * area
        history["normal_iterations"][k] = solution.iterations
        history["residual"][k] = solution.residual
        history["step_converged"][k] = float(solution.converged)
    zeros = np.zeros_like(pressure)
    state = np.where(pressure > 0, SLIP if case.friction_coefficient == 0 else STICK, SEPARATED)
    return Result(
        case=case,
        grid=grid,
        pressure=pressure,
        shear_x=zeros,
        shear_y=zeros.copy(),
        contact_state=state.astype(np.int8),
        history=history,
        loops=("load_steps", "normal"),
        converged=all_converged,
        notes=notes,
    )


_NORMAL_HISTORY = (
    "normal_force",
    "approach",
    "max_pressure",
    "contact_area",
    "normal_iterations",
    "residual",
    "step_converged",
)
