"""The slip-stick loop: normal and tangential solves alternated until the pressure settles.

For each load increment k (DESIGN §3.4-3.5):

1. normal solve for the step's normal force with the extra gap ``u_z(q)`` of the current shear
   tractions (the Dundurs-beta coupling; dropped with the Goodman approximation) plus the
   residual print ``u_z^r``;
2. tangential solve for the step's tangential force with the slip increment
   ``s = K_t (q - q_{k-1}) + [u_t(p) - u_t(p_{k-1})] + [u_t^r,k - u_t^r,k-1]
   - (Delta - Delta_{k-1})``;
3. repeat while the relative pressure change exceeds ``coupling_tolerance``.

Without coupling (beta = 0 or Goodman) one pass is exact.  The previous converged state
(p, q, Delta) is the memory of the path-dependent friction problem.  In a coupled scene an
increment that raises the normal force by more than ``solver.max_load_ratio`` is integrated in
geometric sub-steps (:func:`load_substeps`), which are not recorded as steps.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .case import Case
from .convolution import SurfaceOperator
from .normal import solve_normal
from .reference import hertz
from .result import SEPARATED, SLIP, STICK, Result
from .tangential import solve_tangential

#: Fewest increments per normal-loading stage for which the stick zone of a coupled
#: (beta != 0) scene is trusted; fewer give a path-dependence note.
MIN_COUPLED_STEPS = 20
#: First sub-step of a coupled scene loaded from zero, as a fraction of the first target.
FIRST_SUBSTEP_FRACTION = 1.0 / 64.0


def load_substeps(previous: tuple, target: tuple, max_ratio: float) -> list[tuple]:
    """Intermediate (W, Q_x, Q_y) targets so that W grows by at most ``max_ratio`` per step.

    Path-dependent coupled scenes need small relative increments while the contact grows: an
    increment that doubles the load labels the new contact ring as in a one-shot solve.  The
    sub-steps are geometric in W (from ``FIRST_SUBSTEP_FRACTION`` of the target when loading
    from zero) with the tangential force interpolated linearly in W; ``target`` itself is not
    included.
    """
    w0, w1 = previous[0], target[0]
    if not np.isfinite(max_ratio) or w1 <= w0 * max_ratio:
        return []
    start = w0 if w0 > 0 else w1 * FIRST_SUBSTEP_FRACTION
    count = int(np.ceil(np.log(w1 / start) / np.log(max_ratio)))
    loads = start * (w1 / start) ** (np.arange(count) / count)
    if w0 > 0:
        loads = loads[1:]
    out = []
    for w in loads:
        f = (w - w0) / (w1 - w0)
        out.append(
            (float(w), *(p + f * (t - p) for p, t in zip(previous[1:], target[1:], strict=True)))
        )
    return out


@dataclass
class FrictionState:
    """Converged state of the previous load increment (the memory of the friction law).

    Attributes
    ----------
    pressure, shear_x, shear_y : ndarray
        Tractions on body 2 (Pa).
    shift : ndarray
        Rigid tangential shift (Delta_x, Delta_y) of body 1 relative to body 2 (m).
    pressure_slip_x, pressure_slip_y : ndarray
        Tangential displacement (m) caused by ``pressure`` (the beta term).
    residual_x, residual_y : ndarray
        Tangential residual displacement (m) from plastic strain (zero for elastic bodies).
    """

    pressure: np.ndarray
    shear_x: np.ndarray
    shear_y: np.ndarray
    shift: np.ndarray
    pressure_slip_x: np.ndarray
    pressure_slip_y: np.ndarray
    residual_x: np.ndarray
    residual_y: np.ndarray

    @classmethod
    def unloaded(cls, shape: tuple[int, int]) -> FrictionState:
        """The state before the first increment: no tractions, no shift."""
        zero = np.zeros(shape)
        return cls(zero, zero, zero, np.zeros(2), zero, zero, zero, zero)


def slip_stick_step(
    case: Case,
    operator: SurfaceOperator,
    gap: np.ndarray,
    target: tuple[float, float, float],
    previous: FrictionState,
    *,
    residual_print: np.ndarray | None = None,
    residual_tangential: tuple[np.ndarray, np.ndarray] | None = None,
) -> tuple[FrictionState, dict]:
    """Solve one load increment with the slip-stick loop.

    Parameters
    ----------
    case : Case
        The case (friction coefficient, tolerances, Goodman flag).
    operator : SurfaceOperator
        Surface operator of the grid.
    gap : ndarray
        Initial gap (m).
    target : (float, float, float)
        (W, Q_x, Q_y) at the end of the increment (N).
    previous : FrictionState
        Converged state of the previous increment.
    residual_print : ndarray, optional
        Normal residual displacement u_z^r (m) at this increment.
    residual_tangential : (ndarray, ndarray), optional
        Tangential residual displacements (u_x^r, u_y^r) (m) at this increment.

    Returns
    -------
    state : FrictionState
        The new converged state.
    info : dict
        Iteration counts, residuals, stick mask and status of the increment.
    """
    options = case.solver
    mu = case.friction_coefficient
    force, qx_target, qy_target = target
    coupled = case.pair.dundurs_beta != 0.0 and not options.goodman
    zero = np.zeros_like(gap)
    res_x, res_y = residual_tangential if residual_tangential is not None else (zero, zero)
    base_gap = gap if residual_print is None else gap + residual_print
    # known part of the slip increment: -K_t q_{k-1} + Delta_{k-1} - u_t(p_{k-1}) + du_t^r
    prev_ux, prev_uy = operator.tangential(previous.shear_x, previous.shear_y)
    known_x = -prev_ux + previous.shift[0] - previous.pressure_slip_x + res_x - previous.residual_x
    known_y = -prev_uy + previous.shift[1] - previous.pressure_slip_y + res_y - previous.residual_y

    pressure = previous.pressure if previous.pressure.any() else None
    if pressure is None:
        pair = case.pair
        pressure = hertz(force, pair.composite_modulus, pair.curvature).pressure(
            *operator.grid.mesh()
        )
    qx, qy = previous.shear_x, previous.shear_y
    shift = previous.shift
    info = {"normal_iterations": 0, "slip_iterations": 0, "coupling_iterations": 0}
    converged_all, residual, change = True, 0.0, np.inf
    messages = []
    for loop in range(1, options.coupling_max_iterations + 1):
        # Inexact fixed point: inner solves only as tight as the coupling is converged; the
        # final pass (change below the coupling tolerance) runs at the full inner tolerances.
        inexact = min(1e-2, 0.1 * change) if coupled else 0.0
        extra = base_gap + operator.normal_from_shear(qx, qy) if coupled else base_gap
        normal = solve_normal(
            operator,
            extra,
            force,
            initial_pressure=pressure,
            tolerance=max(options.normal_tolerance, inexact),
            max_iterations=options.normal_max_iterations,
        )
        change = float(
            np.abs(normal.pressure - pressure).sum() / max(normal.pressure.sum(), 1e-300)
        )
        pressure = normal.pressure
        pxs, pys = operator.tangential_from_pressure(pressure)
        tangential = solve_tangential(
            operator,
            pressure,
            mu,
            (known_x + pxs, known_y + pys),
            (qx_target, qy_target),
            initial=(qx, qy),
            initial_shift=tuple(shift),
            tolerance=max(options.slip_tolerance, inexact),
            max_iterations=options.slip_max_iterations,
        )
        qx, qy, shift = tangential.shear_x, tangential.shear_y, np.array(tangential.shift)
        info["normal_iterations"] += normal.iterations
        info["slip_iterations"] += tangential.iterations
        info["coupling_iterations"] = loop
        residual = max(normal.residual, tangential.residual)
        for solution, name in ((normal, "normal"), (tangential, "tangential")):
            if not solution.converged:
                converged_all = False
                messages.append(f"{name} solve {solution.message}")
        if not coupled or (
            loop > 1
            and change < options.coupling_tolerance
            and inexact <= 0.1 * options.coupling_tolerance
        ):
            break
    else:
        converged_all = False
        messages.append(
            f"slip-stick loop not converged after {options.coupling_max_iterations} iterations "
            f"(pressure change {change:.3g})"
        )
    state = FrictionState(pressure, qx, qy, shift, pxs, pys, res_x, res_y)
    info.update(
        approach=normal.approach,
        stick=tangential.stick,
        residual=residual,
        converged=converged_all,
        messages=messages,
    )
    return state, info


def run_slip_stick(case: Case, operator: SurfaceOperator, gap: np.ndarray, targets: list) -> Result:
    """Run the load path of a frictional case through :func:`slip_stick_step`."""
    area = operator.grid.cell_area
    state = FrictionState.unloaded(gap.shape)
    names = (
        "normal_force", "approach", "max_pressure", "contact_area", "tangential_force_x",
        "tangential_force_y", "tangential_shift_x", "tangential_shift_y", "stick_area",
        "normal_iterations", "slip_iterations", "coupling_iterations", "residual",
        "step_converged",
    )  # fmt: skip
    history = {name: np.zeros(len(targets)) for name in names}
    notes, converged, info = [], True, {}
    coupled = case.pair.dundurs_beta != 0.0 and not case.solver.goodman
    previous_target = (0.0, 0.0, 0.0)
    for k, target in enumerate(targets):
        if coupled:
            for sub in load_substeps(previous_target, target, case.solver.max_load_ratio):
                state, _ = slip_stick_step(case, operator, gap, sub, state)
        state, info = slip_stick_step(case, operator, gap, target, state)
        previous_target = target
        history["normal_force"][k] = state.pressure.sum() * area
        history["approach"][k] = info["approach"]
        history["max_pressure"][k] = state.pressure.max()
        history["contact_area"][k] = np.count_nonzero(state.pressure) * area
        history["tangential_force_x"][k] = state.shear_x.sum() * area
        history["tangential_force_y"][k] = state.shear_y.sum() * area
        history["tangential_shift_x"][k], history["tangential_shift_y"][k] = state.shift
        history["stick_area"][k] = np.count_nonzero(info["stick"]) * area
        for name in ("normal_iterations", "slip_iterations", "coupling_iterations", "residual"):
            history[name][k] = info[name]
        history["step_converged"][k] = float(info["converged"])
        if not info["converged"]:
            converged = False
            notes.extend(f"step {k + 1}: {m}" for m in info["messages"])
    if case.pair.dundurs_beta != 0.0 and not case.solver.goodman:
        previous_force = 0.0
        for i, stage in enumerate(case.stages):
            if stage.normal_force > previous_force and stage.steps < MIN_COUPLED_STEPS:
                notes.append(
                    f"path dependence: load stage {i + 1} raises the normal force in "
                    f"{stage.steps} step(s); the stick zone of a dissimilar pair (beta != 0) "
                    f"depends on the loading path, use >= {MIN_COUPLED_STEPS} steps"
                )
            previous_force = stage.normal_force
    contact = state.pressure > 0
    contact_state = np.where(contact, np.where(info["stick"], STICK, SLIP), SEPARATED)
    return Result(
        case=case,
        grid=operator.grid,
        pressure=state.pressure,
        shear_x=state.shear_x,
        shear_y=state.shear_y,
        contact_state=contact_state.astype(np.int8),
        history=history,
        loops=("load_steps", "slip_stick", "normal", "tangential"),
        converged=converged,
        notes=notes,
    )
