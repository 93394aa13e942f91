r"""Von Mises plasticity with isotropic hardening: the radial-return mapping (the innermost loop).

Strain-driven, small strains, vectorised over cells (DESIGN §3.6).  Given the *trial* stress
of a cell (the stress if the increment were elastic) and its equivalent plastic strain
``e_p`` before the increment, the return mapping finds the plastic strain increment.  With the
trial deviator ``s`` and ``q = sqrt(3/2) |s|`` (von Mises of the trial stress),
``f = q - sigma_Y(e_p)``; where ``f <= 1e-12 sigma_Y`` (:data:`RETURN_TOLERANCE`: a stress
returned onto the surface earlier stays elastic despite round-off) the increment is elastic.
Elsewhere the equivalent plastic strain increment ``dp`` solves the scalar consistency equation

    r(dp) = q - 3 G dp - sigma_Y(e_p + dp) = 0,

and the plastic strain increment and the returned stress are

    d eps_p = dp * (3/2) s / q,        sigma = sigma_trial - 2 G d eps_p

(radial return: exact for any step along a proportional path with isotropic hardening).

``r`` decreases strictly on ``[0, q/(3G)]`` with ``r(0) = f > 0`` and ``r(q/(3G)) < 0``: the root is
bracketed.  Newton's method is kept inside the bracket (a Newton step that leaves it is replaced
by bisection), so it converges for any hardening law, including Swift's with its initial slope
of ~8000 GPa (:meth:`solver.plasticity.hardening.Hardening.slope`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..numerics.tensor import contract, deviator, norm
from ..numerics.threads import ROW_BLOCK, by_rows
from .hardening import Hardening

#: Relative tolerance of the consistency equation (on |r| / sigma_Y).
RETURN_TOLERANCE = 1e-12
#: Newton iteration cap; bisection alone would need ~60 steps to reach round-off.
RETURN_MAX_ITERATIONS = 200


@dataclass(frozen=True)
class ReturnMapping:
    """Outcome of :func:`return_mapping` on a set of cells.

    Attributes
    ----------
    plastic_strain_increment : ndarray
        ``(6, ...)`` tensor plastic strain increment (dimensionless), deviatoric.
    equivalent_increment : ndarray
        Equivalent plastic strain increment ``dp`` (dimensionless), shape ``(...)``.
    stress : ndarray
        ``(6, ...)`` returned stress (Pa).
    plastic : ndarray of bool
        Cells that yielded.
    iterations : int
        Largest number of Newton iterations over the cells.
    residual : float
        Largest final ``|r| / sigma_Y`` over the yielding cells.
    converged : bool
        True when every yielding cell met :data:`RETURN_TOLERANCE`.
    back_stress : ndarray or None
        ``(6, ...)`` back stress after the increment (Pa), kinematic hardening only.
    """

    plastic_strain_increment: np.ndarray
    equivalent_increment: np.ndarray
    stress: np.ndarray
    plastic: np.ndarray
    iterations: int
    residual: float
    converged: bool
    back_stress: np.ndarray | None = None


def equivalent_increment(
    trial_equivalent: np.ndarray,
    plastic_strain: np.ndarray,
    hardening: Hardening,
    shear_modulus: float,
    *,
    tolerance: float = RETURN_TOLERANCE,
    max_iterations: int = RETURN_MAX_ITERATIONS,
) -> tuple[np.ndarray, int, float, bool]:
    """Root ``dp >= 0`` of ``q - 3 G dp - sigma_Y(e_p + dp)`` for cells with ``q > sigma_Y(e_p)``.

    Parameters
    ----------
    trial_equivalent : ndarray
        Von Mises value ``q`` of the trial stress (Pa), 1-D.
    plastic_strain : ndarray
        Equivalent plastic strain before the increment, same shape.
    hardening : Hardening
        The hardening law.
    shear_modulus : float
        G (Pa).
    tolerance, max_iterations
        Stopping rule: ``|r| <= tolerance * sigma_Y(e_p + dp)`` or a bracket below round-off.

    Returns
    -------
    dp : ndarray
        Equivalent plastic strain increments.
    iterations : int
        Newton iterations used (largest over the cells).
    residual : float
        Largest ``|r| / sigma_Y``.
    converged : bool
        True when every cell met the tolerance.
    """
    q = np.asarray(trial_equivalent, dtype=float)
    e0 = np.asarray(plastic_strain, dtype=float)
    three_g = 3.0 * shear_modulus

    def evaluate(x, active):  # r, its scale and -dr/dx on the active cells
        flow = hardening.flow_stress(e0[active] + x)
        slope = three_g + hardening.slope(e0[active] + x)
        return q[active] - three_g * x - flow, flow, slope

    # first Newton step from dp = 0 (exact for linear hardening and perfect plasticity)
    f0 = q - hardening.flow_stress(e0)
    x0 = f0 / (three_g + hardening.slope(e0))
    return bracketed_newton(evaluate, x0, q / three_g, tolerance, max_iterations)


def bracketed_newton(
    evaluate, x0: np.ndarray, high: np.ndarray, tolerance: float, max_iterations: int
) -> tuple[np.ndarray, int, float, bool]:
    """Roots of decreasing scalar functions, one per cell, bracketed in ``[0, high]``.

    ``evaluate(x, active)`` returns the residual ``r``, its scale and the slope ``-dr/dx`` at
    ``x`` on the cells ``active``; ``r(0) > 0 > r(high)``.  Newton steps that leave the bracket
    are replaced by bisection.  Stops when ``|r| <= tolerance * scale`` or the bracket is below
    round-off.  Returns the roots, the iterations, the largest final ``|r| / scale`` and whether
    every cell met the tolerance.
    """
    low = np.zeros_like(high)
    high = high.copy()
    x = np.clip(x0, 0.0, high)
    active = np.arange(x.size)
    residual = 0.0
    iterations = 0
    while iterations < max_iterations:
        iterations += 1
        xa = x[active]
        r, scale, slope = evaluate(xa, active)
        scale = np.maximum(scale, np.finfo(float).tiny)
        positive = r > 0.0
        low[active] = np.where(positive, xa, low[active])
        high[active] = np.where(positive, high[active], xa)
        width = high[active] - low[active]
        done = (np.abs(r) <= tolerance * scale) | (width <= 4.0 * np.finfo(float).eps * xa)
        residual = max(residual, float(np.max(np.abs(r[done]) / scale[done], initial=0.0)))
        keep = ~done
        if not keep.any():
            active = active[:0]
            break
        active, r, xa = active[keep], r[keep], xa[keep]
        lo, hi = low[active], high[active]
        step = xa + r / slope[keep]
        inside = (step > lo) & (step < hi)
        x[active] = np.where(inside, step, 0.5 * (lo + hi))
    if active.size:  # the cap was reached: report the residual of the unconverged cells
        r, scale, _ = evaluate(x[active], active)
        residual = max(residual, float(np.max(np.abs(r) / scale)))
    return x, iterations, residual, active.size == 0


def return_mapping(
    trial_stress: np.ndarray,
    plastic_strain: np.ndarray,
    hardening: Hardening,
    shear_modulus: float,
    *,
    back_stress: np.ndarray | None = None,
    tolerance: float = RETURN_TOLERANCE,
    max_iterations: int = RETURN_MAX_ITERATIONS,
    reuse_trial: bool = False,
    out: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None,
) -> ReturnMapping:
    """Radial return of trial stresses onto the von Mises yield surface.

    Parameters
    ----------
    trial_stress : ndarray
        ``(6, ...)`` trial stress (Pa), components :data:`solver.numerics.tensor.COMPONENTS`.
    plastic_strain : ndarray
        Equivalent plastic strain before the increment (dimensionless), shape ``(...)``.
    hardening : Hardening
        Isotropic hardening law.
    shear_modulus : float
        Elastic shear modulus G (Pa).
    back_stress : ndarray, optional
        ``(6, ...)`` back stress before the increment (Pa; kinematic hardening, default zero).
    tolerance, max_iterations
        Stopping rule of the scalar Newton solve (:func:`equivalent_increment`).
    reuse_trial : bool
        The trial stress is deviatoric and the caller gives it up: it serves as its own
        deviator and becomes the returned stress (two fields fewer; isotropic hardening).
        A float32 trial stress (a single-precision volume) gives float32 stress and plastic
        strain increments; the equivalent increment is solved in float64.
    out : tuple of ndarray, optional
        Zero-filled arrays to return the plastic strain increment, the equivalent increment
        and the yielded cells in (isotropic hardening; a block of larger arrays).

    Returns
    -------
    ReturnMapping
    """
    if hardening.kinematic:
        return _kinematic_return(
            trial_stress, plastic_strain, back_stress, hardening, shear_modulus,
            tolerance, max_iterations,
        )  # fmt: skip
    trial_stress = np.asarray(trial_stress)
    if trial_stress.dtype not in (np.float32, np.float64):
        trial_stress = trial_stress.astype(float)
    shape = trial_stress.shape[1:]
    s = trial_stress if reuse_trial else deviator(trial_stress)
    q = np.sqrt(1.5) * norm(s)
    e0 = np.broadcast_to(np.asarray(plastic_strain, dtype=float), shape)
    # a yield tolerance of round-off size: a stress returned onto the surface stays elastic
    plastic = q > hardening.flow_stress(e0) * (1.0 + tolerance)
    increment, dp, yielded = (
        out if out is not None else (np.zeros_like(trial_stress), np.zeros(shape), None)
    )
    if yielded is not None:
        yielded[...] = plastic
        plastic = yielded
    stress = trial_stress if reuse_trial else trial_stress.copy()
    iterations, residual, converged = 0, 0.0, True
    if plastic.any():
        qp = q[plastic].astype(float)
        dpp, iterations, residual, converged = equivalent_increment(
            qp,
            e0[plastic],
            hardening,
            shear_modulus,
            tolerance=tolerance,
            max_iterations=max_iterations,
        )
        dp[plastic] = dpp
        flow = s[:, plastic] * (1.5 * dpp / qp)
        increment[:, plastic] = flow
        stress[:, plastic] -= 2.0 * shear_modulus * flow
    return ReturnMapping(increment, dp, stress, plastic, iterations, residual, converged)


def return_mapping_by_blocks(
    trial_stress: np.ndarray,
    plastic_strain: np.ndarray,
    hardening: Hardening,
    shear_modulus: float,
    *,
    back_stress: np.ndarray | None = None,
    reuse_trial: bool = False,
    threads: int = 1,
) -> ReturnMapping:
    """:func:`return_mapping` by blocks of rows shared by ``threads`` threads.

    Blocks of :data:`~solver.numerics.threads.ROW_BLOCK` rows (the first cell axis).  Every cell
    returns on its own (the scalar Newton solve of a cell depends on that cell only), so the
    blocks give the bits of one call whatever the number of threads; one thread makes that
    one call.
    """
    rows = trial_stress.shape[1]
    if threads <= 1 or rows <= ROW_BLOCK:
        return return_mapping(
            trial_stress, plastic_strain, hardening, shear_modulus,
            back_stress=back_stress, reuse_trial=reuse_trial,
        )  # fmt: skip
    plastic_strain = np.broadcast_to(plastic_strain, trial_stress.shape[1:])
    # isotropic hardening: the blocks fill whole arrays in place (no joining copies)
    whole = None
    if not hardening.kinematic:
        whole = (
            np.zeros_like(trial_stress),
            np.zeros(trial_stress.shape[1:]),
            np.empty(trial_stress.shape[1:], dtype=bool),
        )

    def block(xs: slice) -> ReturnMapping:
        return return_mapping(
            trial_stress[:, xs],
            plastic_strain[xs],
            hardening,
            shear_modulus,
            back_stress=None if back_stress is None else back_stress[:, xs],
            reuse_trial=reuse_trial,
            out=None if whole is None else (whole[0][:, xs], whole[1][xs], whole[2][xs]),
        )

    parts = by_rows(block, rows, threads)
    first = parts[0]

    def joined(name: str):
        if getattr(first, name) is None:
            return None
        return np.concatenate([getattr(p, name) for p in parts], axis=getattr(first, name).ndim - 3)

    # with reuse_trial the stress of each block is the trial stress's own block (in place)
    stress = trial_stress if reuse_trial and not hardening.kinematic else joined("stress")
    increment, equivalent, plastic = whole or map(
        joined, ("plastic_strain_increment", "equivalent_increment", "plastic")
    )
    return ReturnMapping(
        increment,
        equivalent,
        stress,
        plastic,
        max(p.iterations for p in parts),
        max(p.residual for p in parts),
        all(p.converged for p in parts),
        joined("back_stress"),
    )


def _kinematic_return(
    trial_stress, plastic_strain, back_stress, hardening, shear_modulus, tolerance, max_iterations
) -> ReturnMapping:
    """Return mapping with a back stress (Prager-Ziegler or Armstrong-Frederick), backward Euler.

    With ``a = 1 / (1 + gamma dp)``, ``eta = s_trial - a alpha_n`` and ``N = eta / sigma_eq(eta)``
    the relative stress ``s - alpha`` after the increment is parallel to ``eta``, and ``dp``
    solves ``r(dp) = sigma_eq(eta) - (3 G + a C_k) dp - sigma_Y(e_p + dp) = 0``; then
    ``d eps_p = (3/2) dp N`` and ``alpha = a (alpha_n + C_k dp N)``.  ``r`` falls from
    ``r(0) = sigma_eq(s_trial - alpha_n) - sigma_Y > 0`` below zero before
    ``(sigma_eq(s_trial) + sigma_eq(alpha_n)) / (3 G)``: the root is bracketed.  Prager-Ziegler
    (gamma = 0) is radial: ``N`` is the trial direction.
    """
    trial_stress = np.asarray(trial_stress, dtype=float)
    shape = trial_stress.shape[1:]
    s = deviator(trial_stress)
    alpha = np.zeros_like(s) if back_stress is None else np.asarray(back_stress, dtype=float)
    q = np.sqrt(1.5) * norm(s - alpha)
    e0 = np.broadcast_to(np.asarray(plastic_strain, dtype=float), shape)
    plastic = q > hardening.flow_stress(e0) * (1.0 + tolerance)
    dp = np.zeros(shape)
    increment = np.zeros_like(trial_stress)
    stress = trial_stress.copy()
    new_alpha = alpha.copy()
    iterations, residual, converged = 0, 0.0, True
    if plastic.any():
        three_g, c_k, gamma = (
            3.0 * shear_modulus,
            hardening.kinematic_modulus,
            hardening.kinematic_recall,
        )
        sp, ap, ep = s[:, plastic], alpha[:, plastic], e0[plastic]
        cross, alpha2, s2 = contract(sp, ap), contract(ap, ap), contract(sp, sp)

        def evaluate(x, active):
            a = 1.0 / (1.0 + gamma * x)
            # sigma_eq(s - a alpha) from the invariants: no (6, n) temporaries per iteration
            eta2 = s2[active] - 2.0 * a * cross[active] + a * a * alpha2[active]
            eq = np.sqrt(1.5 * np.maximum(eta2, 0.0))
            flow = hardening.flow_stress(ep[active] + x)
            r = eq - (three_g + a * c_k) * x - flow
            d_eq = 1.5 * gamma * a * a * (cross[active] - a * alpha2[active]) / np.maximum(eq, 1.0)
            slope = three_g + c_k * a * a + hardening.slope(ep[active] + x) - d_eq
            return r, flow, slope

        high = (np.sqrt(1.5 * s2) + np.sqrt(1.5 * alpha2)) / three_g
        x0 = (q[plastic] - hardening.flow_stress(ep)) / (three_g + c_k + hardening.slope(ep))
        dpp, iterations, residual, converged = bracketed_newton(
            evaluate, x0, high, tolerance, max_iterations
        )
        a = 1.0 / (1.0 + gamma * dpp)
        eta = sp - a * ap
        direction = eta / (np.sqrt(1.5) * norm(eta))
        dp[plastic] = dpp
        increment[:, plastic] = 1.5 * dpp * direction
        stress[:, plastic] -= 2.0 * shear_modulus * increment[:, plastic]
        new_alpha[:, plastic] = a * (ap + c_k * dpp * direction)
    return ReturnMapping(increment, dp, stress, plastic, iterations, residual, converged, new_alpha)
