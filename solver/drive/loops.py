"""The load-path driver: runs, for every increment of the load path, only the loops the scene needs.

=================================================  ============================================
scene                                              loops (``Result.loops``)
=================================================  ============================================
elastic, frictionless or beta = 0, no shear load   load_steps, normal
elastic, friction, beta != 0 or a tangential load  load_steps, slip_stick, normal, tangential
elastic-plastic body 2, frictionless               load_steps, plasticity, normal, return_mapping
elastic-plastic body 2 with friction (fretting)    load_steps, plasticity, slip_stick, normal,
                                                   tangential, return_mapping
symmetric EP-EP pair (seed eq. 2), any friction    load_steps, plasticity, normal_symmetric,
                                                   return_mapping
=================================================  ============================================

(DESIGN §3.8.)  Every increment calls one contact step (:mod:`solver.drive.steps`), wrapped by the
plasticity loop (:mod:`solver.drive.plastic_loop`) in elastic-plastic scenes.  The driver owns the
sub-stepping of coupled friction scenes (:mod:`solver.case.substeps`; a sub-step's iterations
and friction work count in its step, its state is not recorded), the
per-step histories (declared in :mod:`solver.variables`) and the notes.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import time
from collections.abc import Callable

import numpy as np

from ..bodies.heights import isotropic_spectrum
from ..case.case import Case
from ..case.notes import SMALL_STRAIN_LIMIT
from ..case.substeps import load_substeps, substep_floor
from ..keys import MIN_CELLS_ACROSS
from ..numerics.grid import IndexBox, VolumeGrid
from ..numerics.tensor import equivalent_strain, von_mises
from ..result import SEPARATED, SLIP, STICK, SURFACE_FLOW_NOTE, TRUNCATED_NOTES, Result
from ..surface.tangential import friction_bound, over_capacity
from ..variables import BODY1_SUFFIX, CYCLE_PLASTIC_HISTORIES, HISTORIES, PLASTIC_BODY_HISTORIES
from .fatigue import cycle_fatigue, pass_fatigue, reads_cycle, residual_field, track_residual
from .operators import CaseOperators
from .plastic_loop import (
    PlasticState,
    PlasticStepResult,
    mirror,
    plastic_step,
    top_layer,
    yield_cap,
)
from .record import (
    CONTACT_HISTORY,
    FRICTION_HISTORY,
    ITERATION_HISTORY,
    PERIODIC_HISTORY,
    PERIODIC_PLASTIC_HISTORY,
    PLASTIC_FRICTION_HISTORY,
    PLASTIC_HISTORY,
    STEADY_HISTORY,
    WEAR_HISTORY,
    box_faces_reached,
    cells_across,
    count_iterations,
    cycle_end,
    failure_advice,
    failure_notes,
    melan,
    on_common_axes,
    path_dependence_notes,
    plastic_fields,
    record,
    record_plastic,
    record_touching,
    shear_excess,
    spot_areas,
    touches_edge,
)
from .steps import (
    ADDITIVE,
    ContactState,
    StepResult,
    normal_step,
    position_of,
    shear_cap,
    sliding_step,
    slip_stick_step,
    steady_step,
    summed,
)
from .wear import WornSurfaces
from .window import Follower, shifted

#: Halvings of an increment whose plasticity loop does not converge (down to 1/8 of it).
MAX_SPLITS = 3
#: A surface shear above the bounded shear limit by more than this fraction is surface flow
#: (a slip cell capped at the limit sits on it to rounding).
FLOW_MARGIN = 1e-6


def scene(case: Case) -> tuple[tuple[str, ...], Callable[..., StepResult]]:
    """The loops a case runs and its contact step.

    A sliding increment runs :func:`~solver.drive.steps.sliding_step` instead (``sliding`` in
    loops); a rolling one the contact step at the moved position (``rolling``).
    """
    loops, step = _scene(case)
    motions = tuple(
        name
        for name, kind in (("sliding", "slide"), ("rolling", "roll"), ("steady_rolling", "steady"))
        if any(stage.motion == kind for stage in case.stages)
    )  # fmt: skip
    return (*loops[:1], *motions, *loops[1:]), step


def _increment_step(
    contact_step, stage, moving: bool, creep=None, shift=None
) -> Callable[..., StepResult]:
    """The contact step of one increment of ``stage``: sliding, rolling (creepage) or static.

    ``creep``: the increment's (creepage, spin) of a steady stage (:meth:`Case.creep_ramp`);
    ``shift``: its prescribed rigid shift (m) of a ``tangential_shift`` stage.
    """
    if stage.motion == "steady":
        return functools.partial(steady_step, creepage=creep[0], spin=creep[1])
    if moving and stage.motion == "slide":
        return sliding_step
    if (stage.creepage is not None or stage.spin) and contact_step is slip_stick_step:
        return functools.partial(slip_stick_step, creepage=stage.creepage, spin=stage.spin)
    if shift is not None:  # displacement control
        return functools.partial(slip_stick_step, shift=shift)
    return contact_step


def _scene(case: Case) -> tuple[tuple[str, ...], Callable[..., StepResult]]:
    if case.plastic_body is not None:
        if case.needs_slip_stick:
            loops = ("load_steps", "plasticity", "slip_stick", "normal", "tangential")
            return (*loops, "return_mapping"), slip_stick_step
        normal = "normal_symmetric" if case.symmetric_plastic else "normal"
        return ("load_steps", "plasticity", normal, "return_mapping"), normal_step
    if case.needs_slip_stick:
        return ("load_steps", "slip_stick", "normal", "tangential"), slip_stick_step
    return ("load_steps", "normal"), normal_step


def _halving_plastic_step(
    operators: CaseOperators,
    step_of: Callable[..., StepResult],
    state: ContactState,
    plastic_state: tuple[PlasticState, ...],
    start: tuple,
    target: tuple,
    guess: np.ndarray | None,
    before_guess: np.ndarray | None = None,
    splits: int = 0,
    past_model: Callable[..., str] | None = None,
) -> PlasticStepResult:
    """An increment of the plasticity loop, halved where its loop does not converge.

    A load increment (or a travel: under a moving load the plastic strain is laid down where
    the contact passes) whose fixed point the loop cannot reach from the last state is retried
    as two halves from the same state, down to 1/2^:data:`MAX_SPLITS` of it.  A converged
    increment is untouched (the same bits as without halving).  The halves' iterations,
    friction work (and what wears) and plastic increments add up; a half that still fails is
    the answer, not converged, with its message (the whole increment's best iterate when the
    first half fails, so that the state is always the target's).
    ``past_model(state, plastic, target)`` (:func:`_past_model`): an increment past what the
    model can carry is not halved (its end state is past it whatever the path to it).
    """
    step = plastic_step(operators, step_of, state, plastic_state, target, guess, before_guess)
    if step.converged or splits == MAX_SPLITS:
        return step
    if past_model is not None and past_model(step.contact.state, step.plastic, target):
        return step
    middle = tuple(0.5 * (a + b) for a, b in zip(start, target, strict=True))
    half = None if guess is None else 0.5 * guess
    first = _halving_plastic_step(
        operators, step_of, state, plastic_state, start, middle, half, None, splits + 1,
        past_model,
    )  # fmt: skip
    if not first.converged:  # the whole increment's best iterate: the state at the target
        return dataclasses.replace(step, iterations=step.iterations + first.iterations)
    second = _halving_plastic_step(
        operators, step_of, first.contact.state, first.plastic, middle, target,
        first.increment, None, splits + 1, past_model,
    )  # fmt: skip
    iterations = {
        key: step.contact.iterations.get(key, 0)
        + first.contact.iterations.get(key, 0)
        + second.contact.iterations.get(key, 0)
        for key in second.contact.iterations
    }
    contact = dataclasses.replace(
        second.contact,
        iterations=iterations,
        **summed((first.contact, second.contact), ADDITIVE),
    )
    return dataclasses.replace(
        second,
        contact=contact,
        increment=first.increment + second.increment,
        iterations=step.iterations + first.iterations + second.iterations,
        residual=max(first.residual, second.residual),
    )


def _past_model(
    operators: CaseOperators, state: ContactState, plastic: tuple[PlasticState, ...], target: tuple
) -> str:
    """Why an increment lies past what the model can carry ("" when it does not).

    ``"surface_flow"``: the surface shear passes the plastic body's bounded shear limit
    (:func:`shear_excess` above 1); ``"gross_sliding"``: the prescribed tangential force is at
    or above what the friction disks, capped by ``friction.shear_limit``, can carry.  Halving
    such an increment cannot help: its end state is past the model whatever the path to it.
    """
    case = operators.case
    if plastic and shear_excess(case, state) > 1.0 + FLOW_MARGIN:
        return "surface_flow"
    if case.friction.capped and state.normal is not None:
        cap = shear_cap(case, None)
        if case.friction.follows_yield:
            cap = yield_cap(operators, top_layer(plastic))
        bound = friction_bound(case.friction_coefficient, state.pressure, cap)
        if over_capacity(bound, np.asarray(target[1:3]) / operators.surface.grid.cell_area):
            return "gross_sliding"
    return ""


def _placed(
    follower: Follower | None,
    operators: CaseOperators,
    state: ContactState,
    plastic: tuple[PlasticState, ...],
    start: tuple,
    target: tuple,
) -> tuple[CaseOperators, ContactState, tuple[PlasticState, ...], tuple[int, int]]:
    """What an increment is solved with: the case's operators and states, or the window's.

    With a window that follows the contact (:mod:`solver.drive.window`): its operators placed for
    the increment, the state moved into it, the plastic state on it, the cells it moved by.
    """
    if follower is None:
        return operators, state, plastic, (0, 0)
    return follower.enter(state, plastic, start, target)


def _left(
    follower: Follower | None,
    track: tuple[PlasticState, ...],
    window: tuple[PlasticState, ...],
) -> tuple[PlasticState, ...]:
    """The plastic state after an increment (the window's put back into the track's)."""
    return window if follower is None else follower.leave(track, window)


def _moved(increment: np.ndarray, cells_x: float, cells_y: float) -> np.ndarray:
    """``increment`` (..., nx, ny, nz) moved by (cells_x, cells_y) cells, zero where it enters.

    Linear between the two whole-cell shifts on either side along each axis: the start of a
    sliding increment's plasticity loop from the last increment's plastic strain pattern.
    """
    out = increment
    for axis, cells in ((-3, cells_x), (-2, cells_y)):
        whole = math.floor(cells)
        part = cells - whole
        out = (1.0 - part) * shifted(out, (whole,), (axis,)) + part * shifted(
            out, (whole + 1,), (axis,)
        )
    return out


def _on_track(follower: Follower | None, values: np.ndarray) -> np.ndarray:
    """A window's surface field on the whole track's grid (unchanged without a window)."""
    return values if follower is None else follower.on_track(values)


#: The worn depth fields of the swapped bodies, relabelled.
_WORN = {"wear_depth": "wear_depth_body1", "wear_depth_body1": "wear_depth"}


def _relabelled(result: Result, case: Case) -> Result:
    """The result of ``case.swapped()`` told for ``case``, the bodies relabelled.

    Every field goes on the common axes (:func:`on_common_axes`), every history takes its
    ``swap_sign``.
    """
    mirrored = on_common_axes
    history = {name: values * HISTORIES[name].swap_sign for name, values in result.history.items()}
    return Result(
        case,
        result.grid,
        mirrored("pressure", result.pressure),
        mirrored("shear_x", result.shear_x),
        mirrored("shear_y", result.shear_y),
        mirror(result.contact_state),
        history,
        result.loops,
        result.converged,
        ["solved with the bodies relabelled (the elastic-plastic body 1 as body 2)", *result.notes],
        result.wall_time,
        {_WORN.get(name, name): mirrored(name, values) for name, values in result.fields.items()},
        result.depth,
        result.depth_body1,
        result.truncated,
        result.melan_factor,  # of the plastic body's own residual stress, either label
        surface_flow=result.surface_flow,
    )


# -- the driver ------------------------------------------------------------------------------------
def solve(case: Case) -> Result:
    """Solve a case over its whole load path.

    Parameters
    ----------
    case : Case
        A validated case.

    Returns
    -------
    Result
        Final tractions, fields, per-step histories and status; non-convergence is reported in
        ``Result.converged`` and ``Result.notes``, never raised; its CPU time
        (:attr:`Result.cpu_time`).
    """
    cpu = time.process_time()
    result = _solve(case)
    result.cpu_time = time.process_time() - cpu
    return result


def _solve(case: Case) -> Result:
    """:func:`solve` without the CPU time."""
    if case.solver.method == "static_shakedown":
        from .theorem import solve_static_shakedown  # scipy.optimize: for this method only

        return solve_static_shakedown(case)
    if case.plastic_body1:
        return _relabelled(solve(case.swapped()), case)
    start = time.perf_counter()
    operators = CaseOperators.build(case)
    loops, contact_step = scene(case)
    plastic = case.plastic_body is not None
    targets = case.step_targets()
    names = CONTACT_HISTORY
    if contact_step is slip_stick_step or (case.moving and case.friction_coefficient > 0):
        names += FRICTION_HISTORY
    if any(stage.motion == "steady" for stage in case.stages):
        names += STEADY_HISTORY
    if case.moving:
        names += ("position_x", "position_y")
    if case.grid.periodic:
        names += PERIODIC_HISTORY
    worn = WornSurfaces(case, operators.gap.shape) if case.wear is not None else None
    names += WEAR_HISTORY if worn is not None else ()
    jumps = worn.jumps if worn is not None else None
    if plastic:
        names += PLASTIC_HISTORY + (PERIODIC_PLASTIC_HISTORY if case.grid.periodic else ())
        names += PLASTIC_FRICTION_HISTORY if "friction_work" in names else ()
        if 1 in case.plastic_bodies:
            names += tuple(name + BODY1_SUFFIX for name in PLASTIC_BODY_HISTORIES)
    names += ("residual", "step_converged")
    cycles = case.step_cycles()
    if case.cycles:
        names += ("step_cycle",)
        names += CYCLE_PLASTIC_HISTORIES if plastic else ()
        names += ("cycle_topography_rms",) if plastic and case.grid.periodic else ()
    total = case.total_steps
    history = {name: np.zeros(total) for name in names}
    step_spots: list[np.ndarray] = []  # periodic: the spot areas of each step
    if case.cycles:
        history["step_cycle"][:] = cycles
    volume: VolumeGrid | None = case.volume_grid
    area = case.surface_grid.cell_area

    follower = Follower(operators) if operators.local is not None else None
    state = follower.unloaded() if follower else ContactState.unloaded(operators.gap.shape)
    box = case.plastic_box or (IndexBox.full(volume) if volume is not None else None)
    plastic_state = tuple(
        PlasticState.virgin(box.shape, case.surface_grid.shape) for _ in case.plastic_bodies
    )
    notes: list[str] = list(case.warnings)
    converged = True
    coupled = contact_step is slip_stick_step and case.pair.dundurs_beta != 0.0
    coupled = coupled and not case.solver.goodman
    previous_target = (0.0, 0.0, 0.0, 0.0, 0.0)
    moving = False
    grid = case.surface_grid
    smallest = substep_floor(case)
    guess, direction = None, 0.0
    previous = None  # (plastic increment, load increment) of the step before the last
    faces_noted = edge_noted = False
    ended = None  # (increment, why, note) of a path ended past the model (_past_model)
    failures: list[tuple[int, str]] = []  # (step, what did not converge)
    outcome = None
    cycle_start = None
    shifted = (None, None, 0)  # a shift stage, the shift at its start, its increments so far
    cycle_profiles: dict[str, list] = {}  # CYCLE_PROFILES at the end of every cycle
    # the last cycle's tractions, each increment's, when the criteria read a cycle's paths
    cycle_read = (0, []) if reads_cycle(case) else None
    loaded_positions: set[tuple[float, float, float, float]] = set()  # (p_x, p_y, sign_x, sign_y)
    before = None  # (state, load increment) of the step before the last (elastic predictor)
    creeps = case.creep_ramp()
    for k, (target, stage) in enumerate(zip(targets, case.increment_stages(), strict=True)):
        creep = next(creeps)
        before_cycle = functools.partial(_on_track, follower, state.pressure)
        if jumps is not None and jumps.skip(k, before_cycle):
            continue  # an automatic jump covered the block's cycles
        work = worn_volume = 0.0  # friction work and wear of the step, sub-steps included
        sub_iterations = dict.fromkeys((*ITERATION_HISTORY.values(), "plastic_iterations"), 0)
        if plastic and cycles[k] and (k == 0 or cycles[k] != cycles[k - 1]):
            cycle_start = [(p.equivalent.copy(), p.strain.copy()) for p in plastic_state]
        if plastic:
            new_direction = np.sign(target[0] - previous_target[0])
            if new_direction != direction:
                guess = previous = None
            direction = new_direction
        moving = position_of(target) != position_of(previous_target)
        if stage.shift is not None:  # the shift ramped from the stage's start
            if stage is not shifted[0]:
                shifted = (stage, np.asarray(state.shift, dtype=float), 0)
            shifted = (*shifted[:2], shifted[2] + 1)
            fraction = shifted[2] / stage.steps
            shift = shifted[1] + fraction * (np.asarray(stage.shift) - shifted[1])
        else:
            shift = None
        step_of = _increment_step(contact_step, stage, moving, creep, shift)
        # a load position of Melan's check: Hamilton's field is a slide's load, or a
        # frictionless roll's (a rolling contact's shear is not mu p)
        hamilton = stage.motion == "slide" or case.friction_coefficient == 0.0
        if plastic and moving and target[0] > 0 and hamilton:
            loaded_positions.add(
                (*position_of(target), *np.sign(np.subtract(target, previous_target)[3:]))
            )
        if coupled and not moving and shift is None:  # no load sub-steps while it moves
            for sub in load_substeps(previous_target, target, case.solver.max_load_ratio, smallest):
                placed, state, window_plastic, _ = _placed(
                    follower, operators, state, plastic_state, previous_target, sub
                )
                if worn is not None:
                    worn.place(placed, follower)
                if plastic:  # sub-steps are increments of the plastic history too
                    step = plastic_step(placed, contact_step, state, window_plastic, sub, guess)
                    state = step.contact.state
                    plastic_state = _left(follower, plastic_state, step.plastic)
                    guess, previous = step.increment, None  # no extrapolation across sub-steps
                    work += step.contact.friction_work
                    worn_volume += worn.add(step.contact, follower, area, k) if worn else 0.0
                    count_iterations(sub_iterations, step.contact.iterations, step.iterations)
                    if not step.converged:
                        converged = False
                        failures.append(
                            (k + 1, f"(sub-step to W = {sub[0]:.4g} N): {step.message}")
                        )
                else:
                    sub_outcome = contact_step(placed, state, sub)
                    state = sub_outcome.state
                    work += sub_outcome.friction_work
                    worn_volume += worn.add(sub_outcome, follower, area, k) if worn else 0.0
                    count_iterations(sub_iterations, sub_outcome.iterations)
        messages = []
        placed, state, window_plastic, (di, dj) = _placed(
            follower, operators, state, plastic_state, previous_target, target
        )
        if worn is not None:
            worn.place(placed, follower, position_of(target))
        if plastic:
            load_step = np.subtract(target, previous_target)
            before_last = None
            same = previous is not None and np.allclose(load_step, previous[1], rtol=1e-9, atol=0.0)
            if guess is not None and same and moving:  # the last increment's pattern, moved on
                guess = _moved(guess, load_step[3] / grid.dx - di, load_step[4] / grid.dy - dj)
            elif guess is not None and (di or dj):  # in the window's new place
                guess = _moved(guess, -di, -dj)
            elif guess is not None and same:  # the same load increment again: extrapolate
                before_last = previous[0]  # the plastic increment linearly
            previous = None  # its increment is before_last now, or not needed
            step = _halving_plastic_step(
                placed, step_of, state, window_plastic, previous_target, target, guess,
                before_last, past_model=functools.partial(_past_model, placed),
            )  # fmt: skip
            previous = (guess, load_step) if guess is not None else None
            outcome, guess = step.contact, step.increment
            plastic_state = _left(follower, plastic_state, step.plastic)
            step_ok = step.converged
            residual = max(outcome.residual, step.residual)
            if step.message:
                messages.append(step.message)
            if "surface_shear_ratio" in history:  # on the increment's own (window) grids
                k_top = yield_cap(placed, top_layer(step.plastic), 1.0)
                shear = np.hypot(outcome.state.shear_x, outcome.state.shear_y)
                history["surface_shear_ratio"][k] = float((shear / k_top).max())
            past = _past_model(placed, outcome.state, step.plastic, target)
            if past:
                tops = (top_layer(window_plastic), top_layer(step.plastic))
                excess = shear_excess(case, outcome.state)
                ended = (k, past, _ending_note(k, past, excess, tops, step.message))
        else:
            initial = None
            if not coupled and step_of is slip_stick_step:
                initial = _extrapolated(state, before, np.subtract(target, previous_target))
                before = (state, np.subtract(target, previous_target))
            outcome = step_of(placed, state, target, None, initial)
            step_ok, residual = outcome.converged, outcome.residual
            if outcome.message:
                messages.append(outcome.message)
            if not step_ok and _past_model(placed, outcome.state, (), target):
                ended = (k, "gross_sliding", _ending_note(k, "gross_sliding", 0.0, None, ""))
        state = outcome.state
        halfway = np.add(position_of(previous_target), position_of(target)) / 2.0
        previous_target = target
        record(history, k, outcome, area, case.grid.periodic)
        if cycle_read is not None and cycles[k]:
            if cycles[k] != cycle_read[0]:
                cycle_read = (cycles[k], [])
            cycle_read[1].append(
                tuple(v.copy() for v in (state.pressure, state.shear_x, state.shear_y))
            )
        if worn is not None:
            added = worn.add(outcome, follower, area, k, halfway)
            history["wear_volume"][k] = worn_volume + added
            history["max_wear_depth"][k] = max(float(d.max()) for d in worn.depth.values())
            history["cycle_weight"][k] = worn.weights[k]
            if cycles[k] and (k + 1 == total or cycles[k + 1] != cycles[k]):  # a cycle's end
                pressure = _on_track(follower, state.pressure)
                middle = slice((pressure.shape[1] - 1) // 2, pressure.shape[1] // 2 + 1)
                for name, values in (("wear", worn.gap), ("pressure", pressure)):
                    profile = values[:, middle].mean(axis=1)
                    cycle_profiles.setdefault(f"cycle_{name}_profile", []).append(profile)
                if outcome.stick is not None:  # the stick zone: stick, slip or separated
                    row = middle.start  # the row at (or first beside) the axis
                    stick = _on_track(follower, outcome.stick)[:, row]
                    line = np.where(pressure[:, row] > 0, np.where(stick, STICK, SLIP), 0)
                    cycle_profiles.setdefault("cycle_stick_profile", []).append(line)
                if jumps is not None:
                    jumps.cycle_end(k, pressure)
        if outcome.creepage is not None:
            history["creepage_x"][k], history["creepage_y"][k], history["spin"][k] = (
                outcome.creepage
            )
        if case.grid.periodic:  # every step's spot sizes: the distribution along the path
            step_spots.append(spot_areas(state.pressure > 0, area, periodic=True))
        if case.grid.periodic and state.normal is None:  # unloaded
            gap = operators.gap if worn is None else operators.gap + worn.gap
            record_touching(history, k, gap, plastic_state)
        if "friction_work" in history:
            history["friction_work"][k] = work + outcome.friction_work
        if cycle_start is not None and cycles[k]:
            history["cycle_plastic_strain"][k] = max(
                float((p.equivalent - start).max())
                for p, (start, _) in zip(plastic_state, cycle_start, strict=True)
            )
            history["cycle_net_plastic_strain"][k] = max(
                float(equivalent_strain(p.strain - start).max())
                for p, (_, start) in zip(plastic_state, cycle_start, strict=True)
            )
            if k + 1 == total or cycles[k + 1] != cycles[k]:  # the cycle's last step
                largest, profiles = cycle_end(operators, plastic_state)
                history["cycle_residual_stress"][cycles == cycles[k]] = largest
                if "cycle_topography_rms" in history:  # body 2's surface, run in
                    own = case.pair.heights(2, *grid.mesh(), case.grid.size)
                    surface = own + plastic_state[0].displacement[2]
                    rms = float(np.sqrt(np.mean((surface - surface.mean()) ** 2)))
                    history["cycle_topography_rms"][cycles == cycles[k]] = rms
                    cycle_profiles.setdefault("cycle_topography_spectrum", []).append(
                        isotropic_spectrum(surface, case.grid.size)
                    )
                for name, values in profiles.items():
                    cycle_profiles.setdefault(name, []).append(values)
        history["residual"][k] = residual
        history["step_converged"][k] = float(step_ok)
        if (
            not edge_noted
            and not case.grid.periodic
            and touches_edge(state.pressure, case.grid.periodic_y)
        ):
            edge_noted = True
            notes.append(
                f"step {k + 1}: {TRUNCATED_NOTES[1]} (pressure on its outer "
                "cells), so the domain truncates it: enlarge the domain (grid.half_width or "
                "grid.size)"
            )
        if plastic:
            record_plastic(history, k, step.iterations, plastic_state, case)
            sides = "grid.plastic_half_width" if case.plastic_box else "grid.half_width"
            sides = None if case.grid.periodic else sides
            reached = sorted(
                {f for p in plastic_state for f in box_faces_reached(p.equivalent, sides)}
            )
            if follower is not None:
                cut = follower.sides_reached(window_plastic[0], step.plastic[0])
                window = "grid.half_width: the window follows the contact"
                reached += [f"window side {axis} ({window})" for axis in cut]
            if reached and not faces_noted:
                faces_noted = True
                notes.append(
                    f"step {k + 1}: plastic strain reaches the volume grid's "
                    f"{', '.join(reached)} {TRUNCATED_NOTES[0]}"
                )
        for name, count in sub_iterations.items():  # the sub-steps' iterations count too
            if name in history:
                history[name][k] += count
        if ended is not None:  # past the model: the path ends at this increment
            break
        if not step_ok:
            converged = False
            failures.extend((k + 1, m) for m in dict.fromkeys(messages))
    solved = np.ones(total, dtype=bool) if jumps is None else ~jumps.skipped
    if ended is not None:
        solved[ended[0] + 1 :] = False  # the histories of the increments solved
    if not solved.all():
        history = {name: values[solved] for name, values in history.items()}
        total = int(solved.sum())
    if jumps is not None and (note := jumps.note()):
        notes.append(note)
    if ended is not None:
        notes.append(ended[2])
        if ended[1] == "gross_sliding":
            converged = False
    notes.extend(failure_notes(failures))
    advice = failure_advice(case, history, failures, faces_noted or edge_noted)
    notes.extend([advice] if advice else [])
    notes.extend(path_dependence_notes(case) if coupled else [])
    if case.reference is None and not case.grid.periodic:  # heights only: the mesh check
        largest = history["contact_area"].max()
        if case.grid.periodic_y:  # a line contact: the strip's width along x
            across, measure = largest / (grid.ny * grid.dy) / grid.dx, "width along x"
        else:
            across = cells_across(largest, grid)
            measure = "equivalent diameter"
        if across < MIN_CELLS_ACROSS:
            notes.append(
                f"the contact spans {across:.3g} cells across at its largest ({measure}), "
                f"fewer than {MIN_CELLS_ACROSS}: refine the grid or shrink grid.size"
            )
    if case.grid.periodic and step_spots:  # the largest spot at the largest load
        spots = step_spots[int(np.argmax(history["normal_force"]))]
        across = cells_across(spots[0], grid) if spots.size else 0.0
        if 0.0 < across < MIN_CELLS_ACROSS:
            notes.append(
                f"the largest contact spot at the largest load spans {across:.3g} cells across "
                f"(equivalent diameter), fewer than {MIN_CELLS_ACROSS} (a single contact's "
                "rule): its peak pressure and plastic strain are under-resolved; refine grid.n "
                "(python -m study bench rough --periodic --error measures how far off)"
            )
    if not case.moving and any(stage.cycle and stage.steps == 1 for stage in case.stages):
        notes.append(
            "a cycle stage in one step: its loop has two points and no area (loop_energy, "
            "cycle_friction_work); give several steps per stage (10 per half cycle: 1.5 % "
            "from Mindlin-Deresiewicz at 64^2)"
        )

    if plastic and worn is not None and (note := worn.removed_layer_note(volume.dz)):
        notes.append(note)
    if plastic:
        largest = max(float(p.equivalent.max()) for p in plastic_state)
        if largest > SMALL_STRAIN_LIMIT:
            notes.append(
                f"the equivalent plastic strain reaches {largest:.3g}, beyond the small-strain "
                f"range ({SMALL_STRAIN_LIMIT:g}) the theory rests on"
            )
    if follower is not None:  # the last window's tractions on the whole track's grid
        state = dataclasses.replace(
            state, pressure=follower.on_track(state.pressure),
            shear_x=follower.on_track(state.shear_x), shear_y=follower.on_track(state.shear_y),
        )  # fmt: skip
        if outcome is not None and outcome.stick is not None:
            outcome = dataclasses.replace(outcome, stick=follower.on_track(outcome.stick))
        if follower.lost:
            converged = False
            notes.append(
                "an increment's tractions did not fit the window that follows the contact: "
                "enlarge grid.half_width or set grid.follow_contact = false"
            )
    contact = state.pressure > 0
    if moving and stage.motion == "slide":  # the last increment slid: every contact cell slips
        contact_state = np.where(contact, SLIP, SEPARATED)
    elif contact_step is slip_stick_step:
        contact_state = np.where(contact, np.where(outcome.stick, STICK, SLIP), SEPARATED)
    else:
        contact_state = np.where(contact, SLIP if case.friction_coefficient == 0 else STICK, 0)
    result = Result(
        case=case,
        grid=case.surface_grid,
        pressure=state.pressure,
        shear_x=state.shear_x,
        shear_y=state.shear_y,
        contact_state=contact_state.astype(np.int8),
        history=history,
        loops=loops,
        converged=converged,
        notes=notes,
        truncated=faces_noted or edge_noted,
    )
    if plastic or "stress" in case.fields or case.fatigue is not None:
        result.depth = volume.z
        if 1 in case.plastic_bodies:
            result.depth_body1 = case.volume_grid_of(1).z
    if "stress" in case.fields or case.fatigue is not None:
        sheared = state.shear_x.any() or state.shear_y.any()
        shears = (state.shear_x, state.shear_y) if sheared else (None, None)
        stress = operators.stress.stress(state.pressure, *shears)
        if "stress" in case.fields:
            result.fields["stress"] = stress
            result.fields["von_mises"] = von_mises(stress)
        if case.fatigue is not None and ended is not None:
            result.notes.append(
                "fatigue: not evaluated, the path ended before its last increment (no pass or "
                "cycle)"
            )
        elif cycle_read is not None:  # the criteria of body 2 under its last load cycle
            residual = residual_field(operators, plastic_state) if plastic else None
            last = cycles == cycle_read[0]
            gained = float(history["cycle_plastic_strain"][last].max()) if plastic else 0.0
            fields, result.fatigue, told = cycle_fatigue(
                case, operators.stress, cycle_read[1], residual, gained
            )
            result.fields.update(fields)
            result.notes.extend(told)
        elif case.fatigue is not None:  # the criteria of body 2 under a steady pass
            residual = track_residual(case, operators, plastic_state) if plastic else None
            fields, result.fatigue, told = pass_fatigue(
                case, stress, volume.z, position_of(previous_target)[0], residual
            )
            result.fields.update(fields)
            result.notes.extend(told)
    result.surface_flow = ended is not None and ended[1] == "surface_flow"
    if plastic:
        plastic_fields(result, operators, plastic_state)
        if loaded_positions:
            result.melan_factor = melan(case, operators, plastic_state, loaded_positions)
    result.fields.update({name: np.array(rows) for name, rows in cycle_profiles.items()})
    geometry = case.pair.geometry
    if geometry.profiles or geometry.surfaces:  # a quadric's gap is told by its radii
        result.fields["initial_gap"] = operators.gap
    if worn is not None:
        for body in worn.depth:  # body 1's where its apex ends
            result.fields["wear_depth" + ("_body1" if body == 1 else "")] = worn.on_body2(body)
    if case.grid.periodic:  # spots of each step, largest first, NaN past the step's count
        table = np.full((total, max([1, *map(len, step_spots)])), np.nan)
        for k, areas in enumerate(step_spots):
            table[k, : areas.size] = areas
        result.fields["spot_areas"] = table
    if plastic and case.grid.periodic:  # the plastically deformed topography
        result.fields["residual_gap"] = operators.gap + result.fields["residual_displacement_z"]
    result.wall_time = time.perf_counter() - start
    return result


def _ending_note(
    k: int, why: str, ratio: float, tops: tuple[list, list] | None, message: str
) -> str:
    """Why a path ended at increment ``k`` (0-based), and where: :func:`_past_model`.

    ``tops``: the top layers' equivalent plastic strain before and after the increment
    (None: no plastic body).
    """
    grown = 0.0
    if tops is not None:
        grown = max(float((after - before).max()) for before, after in zip(*tops, strict=True))
    solved = "its plasticity loop converged" if not message else f"({message})"
    if why == "surface_flow":
        return (
            f"step {k + 1}: {SURFACE_FLOW_NOTE} {ratio:.4g} x the largest shear stress the "
            "elastic-plastic body can carry (sigma_Y / sqrt 3 without hardening): no stress "
            "field in equilibrium with it stays within yield, so the top layer shears without "
            f"bound (its equivalent plastic strain grew by {grown:.3g} in this increment, set "
            "by grid.nz, not by the material); the path ends here, the increments before it "
            f"kept and this one recorded as the evidence ({solved}: its strains are the "
            "layers', not the material's).  Cap the friction at the shear yield stress "
            '(friction.shear_limit = "yield"), or lower the load or the friction'
        )
    return (
        f"step {k + 1}: the tangential force is at or above what the friction can carry under "
        "friction.shear_limit (the sum of min(mu p, m tau_c) over the contact): the contact "
        "slides grossly, so the path ends here, the increments before it kept"
        + (f" (the top layer's plastic strain grew by {grown:.3g} in it)" if tops else "")
        + ".  Lower the tangential force, or slide the contact (a slide stage)"
    )


def _extrapolated(
    state: ContactState, before: tuple[ContactState, np.ndarray] | None, load_step: np.ndarray
) -> ContactState | None:
    """Starting shear tractions of an uncoupled slip-stick increment that repeats the last one.

    ``2 q_k - q_{k-1}`` when the load increment equals the previous one (a tangential stage
    in equal steps), else None (start from ``state``).  Only a starting point: the tangential
    solve projects it onto the friction disks and iterates to its tolerance.
    """
    if before is None or not np.allclose(load_step, before[1], rtol=1e-9, atol=0.0):
        return None
    older = before[0]
    return dataclasses.replace(
        state,
        shear_x=2.0 * state.shear_x - older.shear_x,
        shear_y=2.0 * state.shear_y - older.shear_y,
    )
