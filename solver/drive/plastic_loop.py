r"""The plasticity loop: one load increment of elastic-plastic contact, wrapping any contact step.

Unknown: the plastic strain increment ``d`` of the increment (a ``(6, nx, ny, nz)`` tensor field
in each plastic body, stacked: body 2; or both bodies of the symmetric pair, whose fields
coincide; or body 2 and body 1, each in its own frame, when both are elastic-plastic and
different).  One evaluation of the fixed-point map ``d -> G(d)``:

1. plastic strain ``eps_p = eps_p,k-1 + d``; its residual stress ``sigma^r(eps_p)`` and surface
   displacements ``u^r(eps_p)`` (:class:`~solver.volume.eigenstrain.EigenstrainOperator`, one call
   per body);
2. contact step with the residual displacements in the gap (:func:`relative_residual`:
   ``u_z^r`` doubled for the symmetric pair, the paper's eq. 2; body 1's mapped from its frame
   (x, -y, -z)), warm-started from the previous evaluation;
3. stress ``sigma = sigma^e(p, q) + sigma^r(eps_p)`` (body 1: its tractions in its frame,
   :func:`body_tractions`), and the trial stress of the increment
   ``sigma + 2 G d`` (the stress had ``d`` been elastic: ``d`` is deviatoric); only deviators
   are computed (all a von Mises return needs, five components instead of six);
4. radial return (:func:`solver.plasticity.return_mapping.return_mapping`) from the equivalent
   plastic strain at the start of the increment: ``G(d)`` is its plastic strain increment.

The loop stops when ``max |G(d) - d| <= plastic_tolerance * sigma_Y0 / E`` in every body (the
change of the increment relative to its yield strain) and the contact step converged.  The
iterates are mixed by Anderson acceleration (:mod:`solver.numerics.anderson`, memory
``solver.anderson_memory``); the contact step starts from the previous iterate's tractions.
Hitting ``plastic_max_iterations``, or :data:`~solver.drive.steps.STALL_WINDOW` iterations
without progress, or iterates that run away (:data:`DIVERGED`) returns the best iterate with
``converged = False``, its residual and a message with the residual's history (first, best,
last).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..numerics.anderson import Anderson
from ..numerics.tensor import complete_deviator, deviator
from ..numerics.threads import by_rows
from ..plasticity.return_mapping import return_mapping_by_blocks
from ..volume.eigenstrain_kernels import DEVIATORIC
from .steps import STALL_WINDOW, ContactState, ResidualDisplacement, StepResult

if TYPE_CHECKING:
    from collections.abc import Callable

    from .operators import CaseOperators


#: A plasticity loop whose increment change grows to this multiple of its best is running
#: away (a load past what the body can carry): it stops and keeps its best iterate, instead of
#: iterating to the cap with iterates that grow without bound (numpy overflows were seen).
DIVERGED = 1e3


@dataclass(frozen=True)
class PlasticState:
    """Plastic state of the plastic body at the end of an increment.

    Attributes
    ----------
    strain : ndarray
        ``(6, nx, ny, nz)`` plastic strain tensor (dimensionless), :mod:`~solver.numerics.tensor`
        order.
    equivalent : ndarray
        ``(nx, ny, nz)`` accumulated equivalent plastic strain (dimensionless).
    displacement : tuple of ndarray
        Residual surface displacements ``(u_x, u_y, u_z)`` (m) of ``strain`` in the plastic body's
        own frame (z into the body).
    back_stress : ndarray or None
        ``(6, nx, ny, nz)`` back stress (Pa) of kinematic hardening; None: zero.
    frozen_stress : ndarray or None
        On a window of the body's volume (:mod:`.window`): the deviatoric residual stress
        ``(6, nx, ny, nz)`` (Pa) there of the body's whole plastic strain, inside the window
        and out, with ``displacement`` its residual displacements; the plasticity loop then
        adds those of the increment alone (linear superposition).  None: ``strain`` is all
        the body's plastic strain.
    """

    strain: np.ndarray
    equivalent: np.ndarray
    displacement: tuple[np.ndarray, np.ndarray, np.ndarray]
    back_stress: np.ndarray | None = None
    frozen_stress: np.ndarray | None = None

    @classmethod
    def virgin(cls, shape: tuple[int, int, int], surface: tuple[int, int]) -> PlasticState:
        """No plastic strain in the plastic box's cells ``shape``, none on the ``surface``."""
        zero = np.zeros(surface)
        return cls(np.zeros((6,) + shape), np.zeros(shape), (zero, zero, zero))


@dataclass(frozen=True)
class PlasticStepResult:
    """Outcome of :func:`plastic_step`.

    Attributes
    ----------
    contact : StepResult
        The contact step of the accepted iterate (its iteration counts summed over the loop).
    plastic : tuple of PlasticState
        The plastic state of each of ``case.plastic_bodies`` at the end of the increment.
    increment : ndarray
        The accepted plastic strain increments ``(bodies, 6, nx, ny, nz)``.
    iterations : int
        Plasticity-loop iterations (contact solves).
    residual : float
        Final ``max |G(d) - d|`` over the yield strain.
    converged : bool
        True when the loop and every contact step converged.
    message : str
        Empty when converged, else what failed.
    """

    contact: StepResult
    plastic: PlasticState
    increment: np.ndarray
    iterations: int
    residual: float
    converged: bool
    message: str


def mirror(values: np.ndarray, axis: int = 1) -> np.ndarray:
    """A field in body 1's frame on the common axes, or back: y -> -y (the grids are centred)."""
    return np.flip(values, axis=axis)


def top_layer(states: tuple[PlasticState, ...]) -> list[np.ndarray]:
    """Each plastic body's equivalent plastic strain in its top layer (the box's cells)."""
    return [p.equivalent[:, :, 0] for p in states]


def yield_cap(
    operators: CaseOperators, top_strains: list[np.ndarray], factor: float | None = None
) -> np.ndarray:
    """Orowan's cap ``m k`` (Pa) on every surface cell (``friction.shear_limit = "yield"``).

    k is the current shear yield stress of the plastic body's top layer under the cell,
    ``sigma_Y(e_p) / sqrt 3`` (von Mises: a pure shear tau yields at sqrt 3 |tau| =
    sigma_Y), its hardening followed through ``top_strains``, each plastic body's equivalent
    plastic strain in its top layer (the plastic box's cells; the virgin yield stress
    elsewhere); the softer body's where two bodies are plastic (body 1's mirrored onto the
    common axes).  A back stress moves the yield surface but not its radius: k stays the
    isotropic part's.  ``factor``: m, ``friction.shear_factor`` if None (1: k itself).
    """
    case = operators.case
    shape = operators.gap.shape
    cap = np.full(shape, np.inf)
    for body, top in zip(case.plastic_bodies, top_strains, strict=True):
        hardening = (case.body2 if body == 2 else case.body1).hardening
        k = np.full(shape, hardening.initial_yield_stress)
        xs, ys, _ = operators.volume(body)[1].box.slices
        k[xs, ys] = hardening.flow_stress(top)
        cap = np.minimum(cap, k if body == 2 else mirror(k))
    m = case.friction.shear_factor if factor is None else factor
    return m / math.sqrt(3.0) * cap


def relative_residual(
    operators: CaseOperators, displacements: dict[int, tuple[np.ndarray, np.ndarray, np.ndarray]]
) -> ResidualDisplacement:
    """Residual displacements of the pair (what enters the gap) from each plastic body's own.

    None of them with ``solver.residual_print = "ignored"`` (zeros: the surface unchanged).

    ``displacements`` maps a body (1 or 2) to its residual surface displacements in its own
    frame (z into it).  Body 1's frame is (x, -y, -z) in body 2's: its dent adds to the gap
    like body 2's, and its tangential displacement, ``(u_x, -u_y)`` on the common axes, is
    subtracted (the tangential part is body 2's relative to body 1).  The symmetric pair
    (paper's eq. 2): the normal displacements of the two bodies add up and their tangential
    ones coincide, so no relative tangential part.
    """
    if operators.case.solver.residual_print == "ignored":  # the surface stays as it was
        zero = np.zeros_like(next(iter(displacements.values()))[2])
        return ResidualDisplacement(zero, zero, zero)
    if operators.case.symmetric_plastic:
        uz = displacements[2][2]
        zero = np.zeros_like(uz)
        return ResidualDisplacement(zero, zero, 2.0 * uz)
    x = y = z = 0.0
    if 2 in displacements:
        ux, uy, uz = displacements[2]
        x, y, z = x + ux, y + uy, z + uz
    if 1 in displacements:
        ux, uy, uz = (mirror(u) for u in displacements[1])
        x, y, z = x - ux, y + uy, z + uz
    return ResidualDisplacement(x, y, z)


def body_tractions(state: ContactState, body: int) -> dict[str, np.ndarray]:
    """Surface tractions on ``body`` in its own frame (Pa), for its subsurface stress.

    Body 2 carries ``(p, q_x, q_y)``; body 1 the opposite shear, which in its frame (x, -y)
    reads ``(p, -q_x, q_y)`` at the mirrored cells.
    """
    pressure, shear_x, shear_y = state.pressure, state.shear_x, state.shear_y
    if body == 1:
        pressure, shear_x, shear_y = mirror(pressure), -mirror(shear_x), mirror(shear_y)
    tractions = {"pressure": pressure}
    if shear_x.any() or shear_y.any():
        tractions.update(shear_x=shear_x, shear_y=shear_y)
    return tractions


#: The independent components of a deviatoric tensor as runs of consecutive indices.
_FREE_RUNS = [
    slice(run[0], run[-1] + 1)
    for run in np.split(np.array(DEVIATORIC), np.flatnonzero(np.diff(DEVIATORIC) > 1) + 1)
]


def _mix(mixer: Anderson, increment: np.ndarray, change: np.ndarray, threads: int) -> np.ndarray:
    """Anderson's next increment, mixed on the five independent deviatoric components.

    Plastic strain increments are deviatoric (zz = -(xx + yy)): the mixer sees five of the six
    components (its history 5/6 the size), as views of each body's runs of them (no copy),
    and zz follows.
    """
    out = np.empty_like(increment)
    parts = [(i, run) for i in range(len(increment)) for run in _FREE_RUNS]
    mixer(
        [increment[i, run] for i, run in parts],
        [change[i, run] for i, run in parts],
        out=[out[i, run] for i, run in parts],
    )
    for body in out:
        complete_deviator(body, threads)
    return out


def plastic_step(
    operators: CaseOperators,
    contact_step: Callable[..., StepResult],
    previous: ContactState,
    previous_plastic: tuple[PlasticState, ...],
    target: tuple[float, float, float],
    guess: np.ndarray | None = None,
    before_guess: np.ndarray | None = None,
) -> PlasticStepResult:
    """One load increment of elastic-plastic contact (module docstring).

    Parameters
    ----------
    operators : CaseOperators
        The case's operators (with the eigenstrain operators).
    contact_step : callable
        :func:`~solver.drive.steps.normal_step` or :func:`~solver.drive.steps.slip_stick_step`.
    previous : ContactState
        Converged contact state of the previous increment.
    previous_plastic : tuple of PlasticState
        Plastic state of each of ``case.plastic_bodies`` at the end of the previous increment.
    target : (float, float, float)
        (W, Q_x, Q_y) at the end of the increment (N).
    guess : ndarray, optional
        Starting plastic strain increments, stacked over the plastic bodies (e.g. the previous
        increment's); zero if omitted.
    before_guess : ndarray, optional
        The increments of the increment before ``guess``'s, for the same load increment: the
        start is then extrapolated linearly, ``2 guess - before_guess``.

    Returns
    -------
    PlasticStepResult
    """
    case = operators.case
    options = case.solver
    bodies = case.plastic_bodies
    materials = [case.body2 if b == 2 else case.body1 for b in bodies]
    # yield strain of each body, the scale of its increment's change (a validated case has
    # sigma_Y0 / E >= 1e-5; the floor keeps a hand-built one from dividing by zero)
    tiny = np.finfo(float).tiny
    scales = [max(m.hardening.initial_yield_stress / m.E, tiny) for m in materials]

    if len(previous_plastic) == 1:  # a view: no copy of the plastic strain
        previous_strain = previous_plastic[0].strain[np.newaxis]
    else:
        previous_strain = np.stack([p.strain for p in previous_plastic])
    if guess is None:
        increment = np.zeros_like(previous_strain)
    elif before_guess is None:
        increment = guess.copy()
    else:  # 2 guess - before_guess, no further temporary
        increment = np.multiply(guess, 2.0)
        increment -= before_guess
    # on a window of the volume: the residual fields of the increment alone, added to the
    # frozen ones of all the plastic strain at the start (PlasticState.frozen_stress)
    frozen = [p.frozen_stress for p in previous_plastic]
    incremental = frozen[0] is not None
    strain = np.empty_like(previous_strain)  # eps_p of the iterate, rewritten in place
    change = np.empty_like(previous_strain)  # G(d) - d, rewritten in place
    mixer = Anderson(options.anderson_memory, history_dtype=np.float32, threads=options.fft_threads)
    contact_guess: ContactState | None = None
    totals = {"normal": 0, "slip": 0, "coupling": 0}
    residual, converged, iterations = np.inf, False, 0
    first = np.inf  # the first iterate's change (the residual history's start)
    best, best_at = None, 0
    message = ""
    threads, rows = options.fft_threads, previous_strain.shape[2]
    follows_yield = case.friction.follows_yield
    top_strains = top_layer(previous_plastic)
    while iterations < options.plastic_max_iterations:
        iterations += 1
        source = increment if incremental else strain  # whose residual fields are computed

        def start(xs: slice, increment=increment, source=source) -> list[bool]:
            """The iterate's strain, by rows; whether each body's source is not zero there."""
            np.add(previous_strain[:, :, xs], increment[:, :, xs], out=strain[:, :, xs])
            return [bool(part.any()) for part in source[:, :, xs]]

        nonzero = np.any(by_rows(start, rows, threads), axis=0)
        layers, displacements = [], {}
        for i, body in enumerate(bodies):
            eigenstrain = operators.volume(body)[1]
            layers.append(eigenstrain.layer_spectra(source[i]) if nonzero[i] else None)
            own = previous_plastic[i].displacement
            if layers[i] is None:  # nothing has yielded yet: skip the volume transforms
                displacements[body] = own
            elif incremental:
                moved = eigenstrain.displacement_from_layers(layers[i])
                displacements[body] = tuple(u + du for u, du in zip(own, moved, strict=True))
            else:
                displacements[body] = eigenstrain.displacement_from_layers(layers[i])
        residual_displacement = relative_residual(operators, displacements)
        if follows_yield:  # the cap of the iterate's hardening (the last return mapping's)
            residual_displacement = dataclasses.replace(
                residual_displacement, shear_cap=yield_cap(operators, top_strains)
            )
        contact = contact_step(operators, previous, target, residual_displacement, contact_guess)
        for key in totals:
            totals[key] += contact.iterations.get(key, 0)
        contact_guess = contact.state
        mapped = []
        for i, (body, material) in enumerate(zip(bodies, materials, strict=True)):
            stress_operator, eigenstrain = operators.volume(body)
            tractions = body_tractions(contact.state, body)
            if layers[i] is not None:  # residual and traction stress in one pass, deviators
                trial = eigenstrain.deviatoric_stress_with_tractions(
                    source[i],
                    layers[i],
                    tractions,
                    consume=True,  # their last use
                )
                layers[i] = None  # consumed: freed before the return mapping
            elif tractions["pressure"].any() or len(tractions) > 1:
                trial = deviator(stress_operator.stress(**tractions, box=eigenstrain.box))
            else:
                trial = np.zeros_like(strain[i])

            def predict(
                xs: slice, i=i, trial=trial, increment=increment, two_g=2.0 * material.shear_modulus
            ) -> None:
                part = trial[:, xs]  # the elastic predictor, by rows: no full temporary
                if incremental:
                    part += frozen[i][:, xs]
                for component, values in zip(part, increment[i, :, xs], strict=True):
                    component += two_g * values

            by_rows(predict, rows, threads)
            mapped.append(
                return_mapping_by_blocks(
                    trial,
                    previous_plastic[i].equivalent,
                    material.hardening,
                    material.shear_modulus,
                    back_stress=previous_plastic[i].back_stress,
                    reuse_trial=True,  # deviatoric, and not used after
                    threads=options.fft_threads,
                )
            )

        def compare(xs: slice, mapped=mapped, increment=increment) -> list[float]:
            sizes = []  # G(d) - d and its largest size, by rows
            for i, m in enumerate(mapped):
                part = change[i, :, xs]
                np.subtract(m.plastic_strain_increment[:, xs], increment[i, :, xs], out=part)
                sizes.append(max(float(part.max()), -float(part.min())) / scales[i])
            return sizes

        if follows_yield:
            top_strains = [
                p.equivalent[:, :, 0] + m.equivalent_increment[:, :, 0]
                for p, m in zip(previous_plastic, mapped, strict=True)
            ]
        residual = float(np.max(by_rows(compare, rows, threads)))
        first = residual if iterations == 1 else first
        if best is None or residual < best[0]:
            best = (residual, contact, mapped, displacements)
            best_at = iterations
        failed = [m for m in mapped if not m.converged]
        if failed:
            message = f"return mapping not converged (residual {failed[0].residual:.3g})"
        if residual <= options.plastic_tolerance:
            converged = contact.converged and not failed
            break  # settled; an unconverged inner solve is reported, not iterated on
        if residual / DIVERGED > best[0]:  # the iterates run away: stop, keep the best
            message = (
                f"plasticity loop diverging after {iterations} iterations (increment change "
                f"{residual:.3g} of the yield strain, {residual / best[0]:.3g} x its best)"
            )
            break
        if iterations - best_at >= STALL_WINDOW:  # no progress: stop, keep the best (halved)
            message = (
                f"plasticity loop stalled after {iterations} iterations, no progress over its "
                f"last {STALL_WINDOW} (increment change of the yield strain {first:.3g} at the "
                f"first, {best[0]:.3g} at its best, iteration {best_at}, {residual:.3g} at the "
                "last)"
            )
            break
        increment = _mix(mixer, increment, change, options.fft_threads)
    last = residual  # the last iterate's change, before the best is taken back
    if not converged:  # keep the best iterate
        residual, contact, mapped, displacements = best
    if not converged and not message:
        message = (
            f"plasticity loop not converged after {options.plastic_max_iterations} iterations "
            f"(increment change of the yield strain {first:.3g} at the first, {best[0]:.3g} at "
            f"its best, iteration {best_at}, {last:.3g} at the last)"
        )
    if not contact.converged:
        message = "; ".join(filter(None, (message, contact.message)))
    increment = np.stack([m.plastic_strain_increment for m in mapped])
    if incremental:  # the frozen stress of the strain at the end (a halved increment's second
        for i, body in enumerate(bodies):  # half starts from it)
            if increment[i].any():
                eigenstrain = operators.volume(body)[1]
                layers_i = eigenstrain.layer_spectra(increment[i])
                frozen[i] = frozen[i] + eigenstrain.deviatoric_stress_with_tractions(
                    increment[i], layers_i, {}, consume=True
                )
    plastic = tuple(
        PlasticState(
            previous_plastic[i].strain + increment[i],
            previous_plastic[i].equivalent + mapped[i].equivalent_increment,
            displacements[body],
            mapped[i].back_stress,
            frozen[i],
        )
        for i, body in enumerate(bodies)
    )
    contact = dataclasses.replace(contact, iterations=totals)
    return PlasticStepResult(
        contact, plastic, increment, iterations, residual, converged, "" if converged else message
    )
