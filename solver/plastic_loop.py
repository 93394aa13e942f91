r"""The plasticity loop: one load increment of elastic-plastic contact, wrapping any contact step.

Unknown: the plastic strain increment ``d`` of the increment (a ``(6, nx, ny, nz)`` tensor field
in the plastic body; body 2, or both bodies of the symmetric pair, whose fields coincide).  One
evaluation of the fixed-point map ``d -> G(d)``:

1. plastic strain ``eps_p = eps_p,k-1 + d``; its residual stress ``sigma^r(eps_p)`` and surface
   displacements ``u^r(eps_p)`` (:class:`~solver.eigenstrain.EigenstrainOperator`, one call);
2. contact step with the residual displacements in the gap (``u_z^r``, doubled for the
   symmetric pair: the paper's eq. 2), warm-started from the previous evaluation;
3. stress ``sigma = sigma^e(p, q) + sigma^r(eps_p)``, and the trial stress of the increment
   ``sigma + 2 G d`` (the stress had ``d`` been elastic: ``d`` is deviatoric); only deviators
   are computed (all a von Mises return needs, five components instead of six);
4. radial return (:func:`solver.plasticity.return_mapping`) from the equivalent plastic strain
   at the start of the increment: ``G(d)`` is its plastic strain increment.

The loop stops when ``max |G(d) - d| <= plastic_tolerance * sigma_Y0 / E`` (the change of the
increment relative to the yield strain) and the contact step converged.  The iterates are mixed
by Anderson acceleration (:mod:`solver.anderson`, memory ``solver.anderson_memory``); the
contact step starts from the previous iterate's tractions.  Hitting ``plastic_max_iterations``
returns the last iterate with ``converged = False`` and its residual.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from .anderson import Anderson
from .plasticity import return_mapping
from .steps import ContactState, ResidualDisplacement, StepResult

if TYPE_CHECKING:
    from collections.abc import Callable

    from .operators import CaseOperators


@dataclass(frozen=True)
class PlasticState:
    """Plastic state of the plastic body at the end of an increment.

    Attributes
    ----------
    strain : ndarray
        ``(6, nx, ny, nz)`` plastic strain tensor (dimensionless), :mod:`solver.tensor` order.
    equivalent : ndarray
        ``(nx, ny, nz)`` accumulated equivalent plastic strain (dimensionless).
    displacement : tuple of ndarray
        Residual surface displacements ``(u_x, u_y, u_z)`` (m) of ``strain`` in the plastic body's
        own frame (z into the body).
    """

    strain: np.ndarray
    equivalent: np.ndarray
    displacement: tuple[np.ndarray, np.ndarray, np.ndarray]

    @classmethod
    def virgin(cls, shape: tuple[int, int, int]) -> PlasticState:
        """No plastic strain."""
        surface = np.zeros(shape[:2])
        return cls(np.zeros((6,) + shape), np.zeros(shape), (surface, surface, surface))


@dataclass(frozen=True)
class PlasticStepResult:
    """Outcome of :func:`plastic_step`.

    Attributes
    ----------
    contact : StepResult
        The contact step of the accepted iterate (its iteration counts summed over the loop).
    plastic : PlasticState
        The plastic state at the end of the increment.
    increment : ndarray
        The accepted plastic strain increment ``(6, nx, ny, nz)``.
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


def relative_residual(
    operators: CaseOperators, displacement: tuple[np.ndarray, np.ndarray, np.ndarray]
) -> ResidualDisplacement:
    """Residual displacements of the pair (what enters the gap) from the plastic body's own.

    Body 2 alone: as they are.  The symmetric pair (paper's eq. 2): the normal displacements of
    the two bodies add up and their tangential ones coincide, so no relative tangential part.
    """
    ux, uy, uz = displacement
    if operators.case.symmetric_plastic:
        zero = np.zeros_like(uz)
        return ResidualDisplacement(zero, zero, 2.0 * uz)
    return ResidualDisplacement(ux, uy, uz)


def plastic_step(
    operators: CaseOperators,
    contact_step: Callable[..., StepResult],
    previous: ContactState,
    previous_plastic: PlasticState,
    target: tuple[float, float, float],
    guess: np.ndarray | None = None,
) -> PlasticStepResult:
    """One load increment of elastic-plastic contact (module docstring).

    Parameters
    ----------
    operators : CaseOperators
        The case's operators (with the eigenstrain operator).
    contact_step : callable
        :func:`~solver.steps.normal_step` or :func:`~solver.steps.slip_stick_step`.
    previous : ContactState
        Converged contact state of the previous increment.
    previous_plastic : PlasticState
        Plastic state at the end of the previous increment.
    target : (float, float, float)
        (W, Q_x, Q_y) at the end of the increment (N).
    guess : ndarray, optional
        Starting plastic strain increment (e.g. the previous increment's); zero if omitted.

    Returns
    -------
    PlasticStepResult
    """
    case = operators.case
    options = case.solver
    body = case.plastic_body
    hardening = body.hardening
    shear_modulus = body.shear_modulus
    scale = hardening.initial_yield_stress / body.E  # yield strain
    eigenstrain, stress_operator = operators.eigenstrain, operators.stress

    increment = np.zeros_like(previous_plastic.strain) if guess is None else guess.copy()
    mixer = Anderson(options.anderson_memory)
    contact_guess: ContactState | None = None
    totals = {"normal": 0, "slip": 0, "coupling": 0}
    residual, converged, iterations = np.inf, False, 0
    best = None
    message = ""
    while iterations < options.plastic_max_iterations:
        iterations += 1
        strain = previous_plastic.strain + increment
        layers = eigenstrain.layer_spectra(strain) if strain.any() else None
        if layers is not None:
            displacement = eigenstrain.displacement_from_layers(layers)
        else:  # nothing has yielded yet: skip the volume transforms
            displacement = previous_plastic.displacement
        contact = contact_step(
            operators, previous, target, relative_residual(operators, displacement), contact_guess
        )
        for key in totals:
            totals[key] += contact.iterations.get(key, 0)
        contact_guess = contact.state
        state = contact.state
        tractions = {"pressure": state.pressure}
        if state.shear_x.any() or state.shear_y.any():
            tractions.update(shear_x=state.shear_x, shear_y=state.shear_y)
        if layers is not None:  # residual and traction stress in one pass, deviators only
            trial = eigenstrain.deviatoric_stress_with_tractions(strain, layers, tractions)
        elif state.pressure.any() or len(tractions) > 1:
            trial = stress_operator.stress(**tractions)
        else:
            trial = np.zeros_like(strain)
        trial += 2.0 * shear_modulus * increment
        mapped = return_mapping(trial, previous_plastic.equivalent, hardening, shear_modulus)
        change = mapped.plastic_strain_increment - increment
        residual = float(np.abs(change).max()) / scale
        if best is None or residual < best[0]:
            best = (residual, contact, mapped, displacement)
        if not mapped.converged:
            message = f"return mapping not converged (residual {mapped.residual:.3g})"
        if residual <= options.plastic_tolerance:
            converged = contact.converged and mapped.converged
            break  # settled; an unconverged inner solve is reported, not iterated on
        increment = mixer(increment, change)
    if not converged:  # keep the best iterate
        residual, contact, mapped, displacement = best
    if not converged and not message:
        message = (
            f"plasticity loop not converged after {options.plastic_max_iterations} iterations "
            f"(increment change {residual:.3g} of the yield strain)"
        )
    if not contact.converged:
        message = "; ".join(filter(None, (message, contact.message)))
    increment = mapped.plastic_strain_increment
    plastic = PlasticState(
        previous_plastic.strain + increment,
        previous_plastic.equivalent + mapped.equivalent_increment,
        displacement,
    )
    contact = StepResult(
        contact.state,
        contact.converged,
        totals,
        contact.residual,
        contact.message,
        contact.stick,
        contact.approach,
    )
    return PlasticStepResult(
        contact, plastic, increment, iterations, residual, converged, "" if converged else message
    )
