"""Contact steps: one load increment of the contact problem, normal or slip-stick.

Both steps have one signature::

    step(operators, previous, target, residual, initial) -> StepResult

- ``operators``: the case's :class:`~solver.drive.operators.CaseOperators`;
- ``previous``: the converged :class:`ContactState` of the previous increment (the memory of
  the path-dependent friction law);
- ``target``: (W, Q_x, Q_y) at the end of the increment (N); W may be 0 (unloaded);
- ``residual``: the :class:`ResidualDisplacement` of the plastic strain at this increment, or
  None (elastic bodies);
- ``initial``: a :class:`ContactState` to start the iterations from (warm start: the last
  iterate of the plasticity loop), or None to start from ``previous`` (or from Hertz).

The slip-stick step (DESIGN §3.4-3.5), for each coupling iteration:

1. normal solve for W with the extra gap ``u_z(q)`` of the current shear tractions (the
   Dundurs-beta coupling; dropped with the Goodman approximation) plus the residual print
   ``u_z^r``;
2. tangential solve for (Q_x, Q_y) with the slip increment
   ``s = K_t (q - q_{k-1}) + [u_t(p) - u_t(p_{k-1})] + [u_t^r,k - u_t^r,k-1]
   - (Delta - Delta_{k-1})``;
3. repeat while the relative pressure change exceeds ``coupling_tolerance``.

With coupling (beta != 0) these two solves are first merged into one iteration
(:func:`_merged_coupling`): the normal solve of step 1 is repeated after every Newton step of
the tangential active-set iteration instead of after a whole tangential solve, so that the
coupling converges alongside the friction problem.  On Spence's scene (70 steps) this takes
2.5x fewer tangential-operator applications than alternating whole solves, to the same
solution (tests: to 1e-4 rms; 1e-6 seen).  Where it does not converge (its split has no stick
cell: full slip, as in Spence's scene at mu = 0.01, or a sub-step's contact of a dozen cells)
the step goes on with the alternating solves above, Anderson-accelerated on the shear
tractions, from where it stopped.

Without coupling (beta = 0 or Goodman) one pass is exact, and an increment at the W of the
previous one with no residual print (a tangential stage) reuses its converged normal solution.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from ..numerics.anderson import Anderson
from ..surface.normal import NormalSolution, solve_normal
from ..surface.steady import solve_steady_tangential, upwind
from ..surface.tangential import (
    friction_bound,
    over_capacity,
    solve_tangential,
    solve_tangential_coupled,
)

if TYPE_CHECKING:
    from ..case.case import Case
    from .operators import CaseOperators


#: Inner solves of a coupling pass run at ``INEXACT`` times the last pressure change (at most
#: 1e-2): 0.03 took Spence's scene (64^2, 10 steps) from 9.3 s to 6.5 s against 0.1.
INEXACT = 0.03
#: Coupled increments start with the merged iteration (:func:`_merged_coupling`); False
#: alternates whole normal and tangential solves from the start (its fallback), for comparison.
MERGED_COUPLING = True
#: A fixed-point loop (the plasticity loop, the slip-stick coupling) whose best residual came
#: this many iterations before its last makes no progress: it stops there, told, instead of
#: iterating on to its cap.  Measured over the test suite's 2,270 plasticity loops (at
#: 151a4c3): the 2,230 converged ones set a new best at most 12 iterations after the last
#: (most at every iteration); of the 27 that ran to the cap of 100, 24 had gone 25 to 96
#: iterations without one.
STALL_WINDOW = 25


@dataclass(frozen=True)
class ResidualDisplacement:
    """What the plastic state imposes on the contact: residual surface displacements (m).

    ``z`` adds to the gap (a permanent dent of body 2 is positive); ``x``, ``y`` are the
    tangential residual displacements of body 2 relative to body 1.  ``shear_cap``: with
    ``friction.shear_limit = "yield"``, Orowan's cap ``m k`` (Pa) of every surface cell, k the
    current shear yield stress of the plastic body's top layer there
    (:func:`solver.drive.plastic_loop.yield_cap`); None otherwise.
    """

    x: np.ndarray
    y: np.ndarray
    z: np.ndarray
    shear_cap: np.ndarray | None = None


def shear_cap(case: Case, residual: ResidualDisplacement | None) -> np.ndarray | float | None:
    """The friction traction's cap (Pa) of an increment: the plastic state's or the case's.

    The cap ``m k`` of ``friction.shear_limit = "yield"`` (``residual.shear_cap``), the stress
    ``m tau_c`` of a limit given in Pa, or None (Coulomb's law alone).
    """
    if residual is not None and residual.shear_cap is not None:
        return residual.shear_cap
    return case.friction.stress_cap


@dataclass(frozen=True)
class ContactState:
    """A contact solution at the end of an increment.

    Attributes
    ----------
    pressure, shear_x, shear_y : ndarray
        Tractions on body 2 (Pa).
    shift : ndarray
        Rigid tangential shift (Delta_x, Delta_y) of body 1 relative to body 2 (m).
    pressure_slip_x, pressure_slip_y : ndarray
        Tangential displacement (m) caused by ``pressure`` (the beta term).
    residual_x, residual_y : ndarray
        Tangential residual displacement (m) from plastic strain at this state.
    shear_slip_x, shear_slip_y : ndarray or None
        Tangential displacement ``K_t q`` (m) caused by ``shear_x, shear_y`` (the next step's
        memory term), None when not computed.
    normal_force : float
        W (N) the pressure was solved for.
    normal : NormalSolution or None
        The normal solve that gave ``pressure`` (None when the pressure came from elsewhere).
    position : (float, float)
        Body 1's apex over body 2 (m): moved by sliding stages.
    """

    pressure: np.ndarray
    shear_x: np.ndarray
    shear_y: np.ndarray
    shift: np.ndarray
    pressure_slip_x: np.ndarray
    pressure_slip_y: np.ndarray
    residual_x: np.ndarray
    residual_y: np.ndarray
    shear_slip_x: np.ndarray | None = None
    shear_slip_y: np.ndarray | None = None
    normal_force: float = 0.0
    normal: NormalSolution | None = None
    position: tuple[float, float] = (0.0, 0.0)

    @classmethod
    def unloaded(cls, shape: tuple[int, int]) -> ContactState:
        """The state before the first increment: no tractions, no shift."""
        zero = np.zeros(shape)
        return cls(zero, zero, zero, np.zeros(2), zero, zero, zero, zero, zero, zero)


@dataclass(frozen=True)
class StepResult:
    """Outcome of one contact step.

    Attributes
    ----------
    state : ContactState
        The new state.
    converged : bool
        True when every solve of the step converged.
    iterations : dict of int
        ``normal``, ``slip`` (CG iterations) and ``coupling`` (slip-stick iterations).
    residual : float
        Largest final relative residual of the step's solves.
    message : str
        Empty when converged, else what failed.
    stick : ndarray of bool
        Stick cells (all contact cells in a normal step).
    approach : float
        Rigid approach delta (m); at zero force, the approach at which the bodies touch.
    friction_work : float
        Energy dissipated by friction in the step (J): ``-sum (q + q_prev)/2 . s dA``, the
        trapezoidal rule in time (0 in a normal step).
    creepage : (float, float, float) or None
        (xi, eta, spin) of a steady rolling step: given, or the creepage found for a prescribed
        force; None in other steps.
    slid_pressure, dissipation : ndarray or None
        Per cell, of a case that wears (:mod:`solver.drive.wear`): the mean pressure of the
        increment's ends times its local slip distance ``(p + p_prev)/2 |s|`` (N/m), and the
        friction energy dissipated per area ``-(q + q_prev)/2 . s`` (J/m^2); None otherwise.
    """

    state: ContactState
    converged: bool
    iterations: dict = field(default_factory=dict)
    residual: float = 0.0
    message: str = ""
    stick: np.ndarray | None = None
    approach: float = 0.0
    friction_work: float = 0.0
    creepage: tuple[float, float, float] | None = None
    slid_pressure: np.ndarray | None = None
    dissipation: np.ndarray | None = None


#: What a step's parts add up to over the increment (halves of it): its friction work and the
#: per-cell quantities that wear (None where a part has none).
ADDITIVE = ("friction_work", "slid_pressure", "dissipation")


def summed(parts, names=ADDITIVE) -> dict:
    """The sums over the steps ``parts`` of the attributes ``names``.

    None values are skipped; a name no part has is left out.
    """
    out = {}
    for name in names:
        values = [getattr(p, name) for p in parts if getattr(p, name, None) is not None]
        if values:
            out[name] = sum(values[1:], values[0])
    return out


def position_of(target: tuple) -> tuple[float, float]:
    """Body 1's apex over body 2 (m) of a step target (W, Q_x, Q_y[, p_x, p_y])."""
    return (float(target[3]), float(target[4])) if len(target) > 3 else (0.0, 0.0)


def _extra_gap(
    operators: CaseOperators, residual: ResidualDisplacement | None, position=(0.0, 0.0)
) -> np.ndarray:
    gap = operators.gap_at(position)
    if operators.wear is not None:
        gap = gap + operators.wear
    return gap if residual is None else gap + residual.z


def _start_pressure(operators: CaseOperators, force: float, *states) -> np.ndarray:
    for state in states:
        if state is not None and state.pressure.any():
            return state.pressure
    pair = operators.pair
    if pair.geometry.reference_kind is None:  # point heights only: where the gap is lowest
        gap = operators.gap
        low = np.where(gap <= np.quantile(gap, 0.05), 1.0, 0.0)
        return low * (force / (operators.surface.grid.cell_area * low.sum()))
    reference = pair.geometry.reference(force, pair.composite_modulus)
    return reference.pressure(*operators.surface.grid.mesh())


def _pressure_change(new: np.ndarray, old: np.ndarray) -> float:
    """Relative L1 change of the pressure, sum |new - old| / sum new (the coupling measure)."""
    return float(np.abs(new - old).sum() / max(new.sum(), 1e-300))


def _reusable_normal(
    previous: ContactState, force: float, position, coupled: bool, residual
) -> NormalSolution | None:
    """The previous increment's converged normal solution if this increment's is the same.

    It is when the normal problem depends on W (N) alone and W is the same: no coupling of
    the shears, no residual print, the same place.
    """
    normal = previous.normal
    if (
        coupled
        or residual is not None
        or position != previous.position
        or normal is None
        or not normal.converged
        or previous.normal_force != force
    ):
        return None
    return dataclasses.replace(normal, iterations=0, message="the previous increment's")


def _unloaded_step(previous, gap, residual, position=(0.0, 0.0)) -> StepResult:
    """Zero normal force: no tractions; the approach at which the bodies just touch."""
    zero = np.zeros_like(gap)
    res_x, res_y = (zero, zero) if residual is None else (residual.x, residual.y)
    state = ContactState(
        zero, zero, zero, previous.shift, zero, zero, res_x, res_y, zero, zero, position=position
    )
    iterations = {"normal": 0, "slip": 0, "coupling": 0}
    stick = np.zeros(gap.shape, bool)
    return StepResult(state, True, iterations, 0.0, "", stick, float(gap.min()))


def normal_step(
    operators: CaseOperators,
    previous: ContactState,
    target: tuple[float, float, float],
    residual: ResidualDisplacement | None = None,
    initial: ContactState | None = None,
) -> StepResult:
    """Frictionless (or uncoupled, unsheared) normal contact for one increment."""
    force, position = target[0], position_of(target)
    gap = _extra_gap(operators, residual, position)
    if force == 0.0:
        return _unloaded_step(previous, gap, residual, position)
    options = operators.options
    start = (
        _start_pressure(operators, force, initial)
        if initial is not None
        else _start_pressure(operators, force)  # Hertz: close for quadric bodies
    )
    solution = solve_normal(
        operators.surface,
        gap,
        force,
        initial_pressure=start,
        tolerance=options.normal_tolerance,
        max_iterations=options.normal_max_iterations,
    )
    zero = np.zeros_like(gap)
    res_x, res_y = (zero, zero) if residual is None else (residual.x, residual.y)
    state = ContactState(
        solution.pressure, zero, zero, previous.shift, zero, zero, res_x, res_y, zero, zero,
        force, solution, position,
    )  # fmt: skip
    return StepResult(
        state,
        solution.converged,
        {"normal": solution.iterations, "slip": 0, "coupling": 1},
        solution.residual,
        "" if solution.converged else f"normal solve {solution.message}",
        solution.pressure > 0,
        solution.approach,
    )


def slip_stick_step(
    operators: CaseOperators,
    previous: ContactState,
    target: tuple[float, float, float],
    residual: ResidualDisplacement | None = None,
    initial: ContactState | None = None,
    *,
    creepage: tuple[float, float] | None = None,
    spin: float = 0.0,
    shift: tuple[float, float] | None = None,
) -> StepResult:
    """Slip-stick loop for one increment (module docstring), static or rolling.

    A target position away from ``previous.position`` rolls the contact over body 2 (the gap
    moves, every other term stays at its point of body 2: Kalker's transient theory in body
    2's frame, the slip of a point the change of its displacement difference less the rigid
    slip).  ``creepage`` (xi, eta) and ``spin`` (1/m) prescribe that rigid slip of body 1
    relative to body 2 per unit distance rolled, ``(xi d, eta d) + spin d (-(y - y_c),
    x - x_c)`` over a travel d, about the contact's position (x_c, y_c) at the end of the
    increment (the march of one-cell steps then ends at the first-order steady state, spin
    included: :mod:`solver.surface.steady`); the tangential force is then a result and the
    target's ignored.  ``shift`` (m) prescribes the rigid shift at the end of the increment
    alike (displacement control, no travel).  Else the force is prescribed and the rigid
    shift a result (a ``spin`` still turns body 1).
    """
    case, surface = operators.case, operators.surface
    options = case.solver
    mu = case.friction_coefficient
    force, qx_target, qy_target = target[:3]
    position = position_of(target)
    base_gap = _extra_gap(operators, residual, position)
    if force == 0.0:
        return _unloaded_step(previous, base_gap, residual, position)
    beta = case.pair.dundurs_beta
    coupled = beta != 0.0 and not options.goodman
    zero = np.zeros_like(base_gap)
    res_x, res_y = (zero, zero) if residual is None else (residual.x, residual.y)
    # known part of the slip increment: -K_t q_{k-1} + Delta_{k-1} - u_t(p_{k-1}) + du_t^r
    if previous.shear_slip_x is None:
        prev_ux, prev_uy = surface.tangential(previous.shear_x, previous.shear_y)
    else:
        prev_ux, prev_uy = previous.shear_slip_x, previous.shear_slip_y
    known_x = -prev_ux + previous.shift[0] - previous.pressure_slip_x + res_x - previous.residual_x
    known_y = -prev_uy + previous.shift[1] - previous.pressure_slip_y + res_y - previous.residual_y
    distance = float(np.hypot(*np.subtract(position, previous.position)))
    if creepage is not None:  # the rigid shift at the end of the increment is prescribed
        shift = np.asarray(previous.shift, dtype=float) + distance * np.asarray(creepage)
    if shift is not None:  # the force is free: the rigid slip goes into the known part
        shift = np.asarray(shift, dtype=float)
        known_x, known_y = known_x - shift[0], known_y - shift[1]
    if spin and distance:  # the spin's rotation, also under a prescribed force
        # about the contact's centre at the end of the increment, where the tractions are
        # solved (the implicit step's rate; about the travel's midpoint the lateral slip
        # was off by spin d/2, +8 % on Kalker's C23 at steps of a/16)
        x, y = surface.grid.mesh()
        known_x = known_x + spin * distance * (y - position[1])
        known_y = known_y - spin * distance * (x - position[0])
    target_force = None if shift is not None else (qx_target, qy_target)

    start = initial if initial is not None else previous
    pressure = _start_pressure(operators, force, start, previous)
    qx, qy = start.shear_x, start.shear_y
    counts = {"normal": 0, "slip": 0, "coupling": 0}
    converged_all, worst, change = True, 0.0, np.inf
    messages = []
    cap = shear_cap(case, residual)
    if coupled and MERGED_COUPLING:
        tangential, normal, pxs, pys = _merged_coupling(
            operators, base_gap, force, (known_x, known_y), target_force,
            pressure, (qx, qy), counts, cap,
        )  # fmt: skip
        if tangential.converged:
            return _step_result(
                operators, previous, tangential, normal, (pxs, pys), (res_x, res_y), force,
                counts, max(normal.residual, tangential.residual), True, "", position, shift,
            )  # fmt: skip
        # fall back on alternating whole solves from where it stopped
        pressure, qx, qy = normal.pressure, tangential.shear_x, tangential.shear_y
    mixer = Anderson(options.anderson_memory)  # on the shear tractions, the coupling's state
    first = counts["coupling"]
    changes = []  # the pressure change of each pass (the coupling's residual history)
    for loop in range(1, options.coupling_max_iterations + 1):
        # Inexact fixed point: inner solves only as tight as the coupling is converged; the
        # loop ends when the pressure change is below the coupling tolerance in a pass whose
        # inner solves were at least that tight.
        inexact = min(1e-2, INEXACT * change) if coupled else 0.0
        worn = coupled or operators.wear is not None  # the gap changed: solve again
        normal = _reusable_normal(previous, force, position, worn, residual)
        if normal is None:
            extra = base_gap + surface.normal_from_shear(qx, qy) if coupled else base_gap
            normal = solve_normal(
                surface,
                extra,
                force,
                initial_pressure=pressure,
                tolerance=max(options.normal_tolerance, inexact),
                max_iterations=options.normal_max_iterations,
            )
        change = _pressure_change(normal.pressure, pressure)
        pressure = normal.pressure
        if beta == 0.0:  # the pressure shifts no surface point tangentially
            pxs, pys = zero, zero
        else:
            pxs, pys = surface.tangential_from_pressure(pressure)
        tangential = solve_tangential(
            surface,
            pressure,
            mu,
            (known_x + pxs, known_y + pys),
            target_force,
            initial=(qx, qy),
            tolerance=max(options.slip_tolerance, inexact),
            max_iterations=options.slip_max_iterations,
            shear_cap=cap,
        )
        if coupled:  # Anderson-accelerated fixed point q -> T(N(q))
            shear = np.stack((qx, qy))
            qx, qy = mixer(shear, np.stack((tangential.shear_x, tangential.shear_y)) - shear)
        else:
            qx, qy = tangential.shear_x, tangential.shear_y
        counts["normal"] += normal.iterations
        counts["slip"] += tangential.iterations
        counts["coupling"] = first + loop
        worst = max(normal.residual, tangential.residual)
        for solution, name in ((normal, "normal"), (tangential, "tangential")):
            if not solution.converged:
                converged_all = False
                messages.append(f"{name} solve {solution.message}")
        if not coupled or (
            loop > 1
            and change < options.coupling_tolerance
            and inexact <= options.coupling_tolerance  # inner solves as tight as the coupling
        ):
            break
        changes.append(change)
        best_at = int(np.argmin(changes)) + 1
        if loop - best_at >= STALL_WINDOW:
            converged_all = False
            messages.append(
                f"slip-stick loop stalled after {loop} iterations, no progress over its last "
                f"{STALL_WINDOW} (pressure change {changes[0]:.3g} at the first, "
                f"{changes[best_at - 1]:.3g} at its best, iteration {best_at}, {change:.3g} at "
                "the last)"
            )
            break
    else:
        converged_all = False
        messages.append(
            f"slip-stick loop not converged after {options.coupling_max_iterations} iterations "
            f"(pressure change {change:.3g})"
        )
    # the state is the last solve's (not the mixed iterate)
    return _step_result(
        operators, previous, tangential, normal, (pxs, pys), (res_x, res_y), force, counts,
        worst, converged_all, "; ".join(messages), position, shift,
    )  # fmt: skip


def steady_step(
    operators: CaseOperators,
    previous: ContactState,
    target: tuple[float, float, float],
    residual: ResidualDisplacement | None = None,
    initial: ContactState | None = None,
    *,
    creepage: tuple[float, float] | None,
    spin: float = 0.0,
) -> StepResult:
    """The steady state of rolling along +x at the given creepage and spin (no travel).

    ``creepage`` None: the target's tangential force (Q_x, Q_y) is prescribed and the
    creepage found with the tractions (two more unknowns of the steady solve).

    The normal problem for the target's force, then the steady tangential problem
    (:func:`solver.surface.steady.solve_steady_tangential`, the slip ``-d_x u + c`` with
    ``c = (-xi + phi y, -eta - phi x)`` about the contact's centre, the pressure's own
    tangential displacement's upwind difference added for beta != 0); with the coupling
    (beta != 0, not Goodman's approximation) the two alternate until the pressure settles.
    Warm-started from the previous increment's tractions (the creep curve's last point).
    """
    del initial  # the previous state is the start
    case, surface = operators.case, operators.surface
    options = case.solver
    force = target[0]
    position = position_of(target)
    base_gap = _extra_gap(operators, residual, position)
    if force == 0.0:
        return _unloaded_step(previous, base_gap, residual, position)
    beta = case.pair.dundurs_beta
    coupled = beta != 0.0 and not options.goodman
    x, y = surface.grid.mesh()
    given = creepage if creepage is not None else (0.0, 0.0)
    prescribed = None if creepage is not None else (target[1], target[2])
    rigid_x = -given[0] + spin * (y - position[1])
    rigid_y = -given[1] - spin * (x - position[0])
    zero = np.zeros_like(base_gap)
    pressure = _start_pressure(operators, force, previous)
    qx, qy = previous.shear_x, previous.shear_y
    pxs = pys = zero
    dx_dy = surface.grid.cell_area
    counts = {"normal": 0, "slip": 0, "coupling": 0}
    messages, change = [], np.inf
    order = options.steady_order
    cap = shear_cap(case, residual)
    for loop in range(1, options.coupling_max_iterations + 1):
        normal = _reusable_normal(previous, force, position, coupled, residual)
        if normal is None:
            extra = base_gap + surface.normal_from_shear(qx, qy) if coupled else base_gap
            normal = solve_normal(
                surface, extra, force, initial_pressure=pressure,
                tolerance=options.normal_tolerance, max_iterations=options.normal_max_iterations,
            )  # fmt: skip
        change = _pressure_change(normal.pressure, pressure)
        pressure = normal.pressure
        counts["normal"] += normal.iterations
        counts["coupling"] = loop
        if (pressure[-order:] > 0.0).any():
            message = (
                "the contact reaches the grid's leading edge (largest x): a steady solve needs "
                "free cells ahead of it; widen the grid along x"
            )
            tangential = None
            break
        bound = friction_bound(case.friction_coefficient, pressure, cap)
        if prescribed is not None and over_capacity(bound, np.divide(prescribed, dx_dy)):
            message = (
                f"the tangential force {math.hypot(*prescribed):.4g} N is at or above what the "
                f"friction can carry, {float(bound.sum()) * dx_dy:.4g} N (the sum of "
                "min(mu p, m tau_c) over the contact): lower the force or raise "
                "friction.shear_limit"
            )
            tangential = None
            break
        if beta != 0.0:  # the pressure's own tangential displacement, carried through
            pxs, pys = surface.tangential_from_pressure(pressure)
        dx = surface.grid.dx
        tangential = solve_steady_tangential(
            surface, pressure, case.friction_coefficient,
            (rigid_x + upwind(pxs, dx, order), rigid_y + upwind(pys, dx, order)),
            force=prescribed, order=order, initial=(qx, qy), tolerance=options.slip_tolerance,
            max_iterations=options.slip_max_iterations, shear_cap=cap,
        )  # fmt: skip
        qx, qy = tangential.shear_x, tangential.shear_y
        counts["slip"] += tangential.iterations
        if not coupled or (loop > 1 and change < options.coupling_tolerance):
            break
    else:
        messages.append(
            f"steady coupling not converged after {options.coupling_max_iterations} "
            f"iterations (pressure change {change:.3g})"
        )
    if tangential is None:  # refused on this pressure: no tractions, a message
        state = dataclasses.replace(previous, pressure=pressure, normal=normal)
        return StepResult(state, False, counts, np.inf, message, pressure > 0.0, normal.approach)
    for solution, name in ((normal, "normal"), (tangential, "steady tangential")):
        if not solution.converged:
            messages.append(f"{name} solve {solution.message}")
    state = ContactState(
        pressure, qx, qy, np.asarray(previous.shift, float), pxs, pys, zero, zero,
        tangential.displacement_x, tangential.displacement_y, force, normal, position,
    )  # fmt: skip
    found = tangential.creepage if creepage is None else creepage
    return StepResult(
        state, not messages, counts, max(normal.residual, tangential.residual),
        "; ".join(messages), tangential.stick, normal.approach, 0.0, (*found, spin),
    )  # fmt: skip


def sliding_step(
    operators: CaseOperators,
    previous: ContactState,
    target: tuple,
    residual: ResidualDisplacement | None = None,
    initial: ContactState | None = None,
) -> StepResult:
    """One increment of gross sliding: every contact cell slips.

    Body 1's apex moves from ``previous.position`` to the target's position over body 2.  The
    shear traction on body 2 is ``mu p`` along the motion (Amontons-Coulomb in gross slip;
    ``min(mu p, cap)`` under a shear limit, :func:`shear_cap`), so
    only the pressure is unknown: a normal solve on the gap at the new position, with the
    normal displacement of that shear (the beta coupling; Goodman's approximation drops it)
    iterated to the coupling tolerance.  The rigid shift keeps its value (the travel is the
    position); the friction work is mu times the mean normal force times the travel.
    """
    case, surface = operators.case, operators.surface
    options = case.solver
    force, position = target[0], position_of(target)
    gap = _extra_gap(operators, residual, position)
    if force == 0.0:
        return _unloaded_step(previous, gap, residual, position)
    motion = np.subtract(position, previous.position)
    length = float(np.hypot(*motion))
    ux, uy = (motion / length) if length > 0 else (0.0, 0.0)
    mu, cap = case.friction_coefficient, shear_cap(case, residual)
    coupled = mu > 0 and case.pair.dundurs_beta != 0.0 and not options.goodman
    pressure = _start_pressure(operators, force, initial, previous)
    counts = {"normal": 0, "slip": 0, "coupling": 0}
    normal, change = None, np.inf
    for _ in range(options.coupling_max_iterations if coupled else 1):
        if coupled:
            bound = friction_bound(mu, pressure, cap)
            extra = gap + surface.normal_from_shear(ux * bound, uy * bound)
        else:
            extra = gap
        normal = solve_normal(
            surface, extra, force, initial_pressure=pressure,
            tolerance=options.normal_tolerance, max_iterations=options.normal_max_iterations,
        )  # fmt: skip
        counts["normal"] += normal.iterations
        counts["coupling"] += 1
        change = _pressure_change(normal.pressure, pressure)
        pressure = normal.pressure
        if change < options.coupling_tolerance:
            break
    converged = normal.converged and (not coupled or change < options.coupling_tolerance)
    message = ""
    if not normal.converged:
        message = f"normal solve {normal.message}"
    elif not converged:
        message = (
            f"sliding coupling not converged after {counts['coupling']} passes (pressure "
            f"change {change:.3g})"
        )
    bound = friction_bound(mu, pressure, cap)
    qx, qy = ux * bound, uy * bound
    zero = np.zeros_like(gap)
    res_x, res_y = (zero, zero) if residual is None else (residual.x, residual.y)
    pxs, pys = (
        surface.tangential_from_pressure(pressure) if case.pair.dundurs_beta else (zero, zero)
    )
    state = ContactState(
        pressure, qx, qy, previous.shift, pxs, pys, res_x, res_y, None, None, force, normal,
        position,
    )  # fmt: skip
    # all the increment slips along its motion under g = min(mu p, cap): the work is the mean
    # of the friction force sum g dA at its ends times the travel (the trapezoid of the shears
    # would count a reversal's opposite shear); mu times the mean normal force without a cap
    forces = (float(np.sum(friction_bound(mu, previous.pressure, cap))), float(np.sum(bound)))
    work = 0.5 * sum(forces) * surface.grid.cell_area * length
    wear = {}
    if case.wear is not None:
        bounds = friction_bound(mu, previous.pressure, cap) + bound
        wear = {
            "slid_pressure": 0.5 * (previous.pressure + pressure) * length,
            "dissipation": 0.5 * bounds * length,
        }
    return StepResult(
        state, converged, counts, normal.residual, message, np.zeros(gap.shape, bool),
        normal.approach, work, **wear,
    )  # fmt: skip


def _step_result(
    operators, previous, tangential, normal, pressure_slip, residual, force, counts, worst,
    converged, message, position, shift=None,
) -> StepResult:  # fmt: skip
    """The slip-stick step's outcome from its last normal and tangential solves.

    ``shift``: the prescribed rigid shift (m) of a creepage increment, else the solve's.
    """
    state = ContactState(
        normal.pressure, tangential.shear_x, tangential.shear_y,
        np.array(tangential.shift if shift is None else shift), *pressure_slip, *residual,
        tangential.displacement_x, tangential.displacement_y, force, normal, position,
    )  # fmt: skip
    mean_x = 0.5 * (tangential.shear_x + previous.shear_x)
    mean_y = 0.5 * (tangential.shear_y + previous.shear_y)
    dissipation = -(mean_x * tangential.slip_x + mean_y * tangential.slip_y)
    wear = {}
    if operators.case.wear is not None:
        distance = np.hypot(tangential.slip_x, tangential.slip_y)
        wear = {
            "slid_pressure": 0.5 * (normal.pressure + previous.pressure) * distance,
            "dissipation": dissipation,
        }
    return StepResult(
        state, converged, counts, worst, message, tangential.stick, normal.approach,
        float(dissipation.sum()) * operators.case.surface_grid.cell_area, **wear,
    )  # fmt: skip


def _merged_coupling(
    operators, base_gap, force, known, shear_target, pressure, shear, counts, cap
):  # fmt: skip
    """Coupled increment in one active-set iteration (:func:`solve_tangential_coupled`).

    After every Newton step of the tangential iteration the normal problem is solved again
    with the current shear tractions' normal displacement (as tightly as the tangential
    residual and the last pressure change require); the pressure has settled when it changes
    by less than the coupling tolerance in a normal solve at least that tight.  Adds the
    iteration counts to ``counts``; returns (tangential, normal, pxs, pys): on convergence
    the normal solve the shear tractions were solved with (its pressure within the coupling
    tolerance of the tight solve that followed it), else the last one.
    """
    surface, options = operators.surface, operators.case.solver
    last = {"pressure": pressure, "change": np.inf}
    renewals = []  # (normal solution, pxs, pys) of every renewal

    def renew(qx, qy, residual):
        tight = min(1e-2, INEXACT * min(last["change"], residual))
        tolerance = max(options.normal_tolerance, tight)
        normal = solve_normal(
            surface,
            base_gap + surface.normal_from_shear(qx, qy),
            force,
            initial_pressure=last["pressure"],
            tolerance=tolerance,
            max_iterations=options.normal_max_iterations,
        )
        change = _pressure_change(normal.pressure, last["pressure"])
        pxs, pys = surface.tangential_from_pressure(normal.pressure)
        last.update(pressure=normal.pressure, change=change)
        renewals.append((normal, pxs, pys))
        counts["normal"] += normal.iterations
        counts["coupling"] += 1
        settled = (
            normal.converged
            and change < options.coupling_tolerance
            and tolerance <= options.coupling_tolerance
        )
        return normal.pressure, (known[0] + pxs, known[1] + pys), settled

    tangential = solve_tangential_coupled(
        surface,
        operators.case.friction_coefficient,
        renew,
        shear_target,
        shear,
        tolerance=options.slip_tolerance,
        max_iterations=options.slip_max_iterations // 2,
        shear_cap=cap,
    )
    counts["slip"] += tangential.iterations
    # converged: the shear tractions were solved with the pressure before the last renewal
    return tangential, *renewals[-2 if tangential.converged else -1]
