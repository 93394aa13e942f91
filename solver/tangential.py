"""Tangential contact for a given pressure: incremental Coulomb friction with slip and stick.

In load step k the slip increment of body 2 relative to body 1 at a surface cell is

    s = K_t q + c - Delta                                                    (m)

where ``K_t`` is the tangential 2x2 block of :class:`solver.convolution.SurfaceOperator`, ``q`` the
shear traction on body 2 (Pa), ``c`` everything the caller knows (minus the previous step's
``K_t q_{k-1}``, plus the pressure-induced tangential displacement increment, the residual
displacement increment, plus the previous shift), and ``Delta`` the rigid tangential shift of
body 1 relative to body 2 (m), an unknown when the tangential force is prescribed.  Coulomb's law
with memory:  stick ``s = 0, |q| <= mu p``;  slip ``|q| = mu p, q = -mu p s/|s|``.

For a given pressure these are the optimality conditions of the convex problem (Kalker's
minimum complementary energy)

    minimise  1/2 q.K_t q + q.c   subject to  |q_i| <= mu p_i  and  sum q dA = Q,

with ``Delta`` the multiplier of the force constraint.  It is solved by an accelerated
projected gradient (FISTA, Beck & Teboulle 2009, with O'Donoghue & Candes' gradient restart):
a gradient step of length 1/L (L the largest eigenvalue of the circulant ``K_t``), then the
exact Euclidean projection onto {disks} and {sum q = Q} (:func:`project_onto_feasible`, a 2-D
Newton iteration for the force multiplier).  Convergence is guaranteed for this convex problem
whatever the stick set does.  (An active-set CG in the style of Polonsky & Keer converged faster
on Cattaneo-Mindlin but stalled or oscillated when the stick zone was small, as in Spence's
problem, where the force constraint has to be carried by a few stick cells.)

Convergence: the residual ``max(rms of |s| on stick cells, rms over the contact of the slip-cell
error |s + |s| q/|q||) / scale`` measures every optimality condition that the iteration does not
enforce by construction (the disks and the force are enforced exactly); ``scale`` is the largest
of the caller's scale, the rms of ``K_t q`` over the contact and the shift.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .convolution import SurfaceOperator


@dataclass(frozen=True)
class TangentialSolution:
    """Result of one tangential solve.

    Attributes
    ----------
    shear_x, shear_y : ndarray
        Shear tractions on body 2 (Pa).
    slip_x, slip_y : ndarray
        Slip increments s (m); zero in stick up to the residual.
    shift : tuple of float
        Rigid tangential shift Delta (m) of body 1 relative to body 2.
    stick : ndarray of bool
        Stick cells (in contact, |q| < mu p).
    iterations : int
        CG iterations.
    residual : float
        Final relative residual.
    converged : bool
        True when the residual fell below the tolerance.
    message : str
        Status text.
    """

    shear_x: np.ndarray
    shear_y: np.ndarray
    slip_x: np.ndarray
    slip_y: np.ndarray
    shift: tuple[float, float]
    stick: np.ndarray
    iterations: int
    residual: float
    converged: bool
    message: str


def _sum(a: np.ndarray) -> float:
    return float(np.einsum("ij->", a))


def project_onto_feasible(
    zx: np.ndarray,
    zy: np.ndarray,
    bound: np.ndarray,
    target: np.ndarray,
    multiplier: np.ndarray,
    max_iterations: int = 100,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Euclidean projection onto {|q_i| <= bound_i, sum q = target}.

    The projection is ``q_i = P_i(z_i - lambda)`` (``P_i`` the projection onto disk i) with the
    2-vector ``lambda`` solving ``sum P_i(z_i - lambda) = target``: the gradient of a convex
    function of ``lambda``, found by a damped Newton iteration from ``multiplier``.

    Parameters
    ----------
    zx, zy : ndarray
        Point to project (Pa).
    bound : ndarray
        Disk radii mu p (Pa).
    target : ndarray
        Required sums (sum q_x, sum q_y) (Pa, i.e. force / cell area).
    multiplier : ndarray
        Starting lambda (Pa).
    max_iterations : int
        Newton cap.

    Returns
    -------
    qx, qy, multiplier : ndarray
    """
    lam = np.array(multiplier, dtype=float)
    scale = max(_sum(bound), 1e-300)

    def evaluate(lam):
        wx, wy = zx - lam[0], zy - lam[1]
        norm = np.hypot(wx, wy)
        outside = norm > bound
        ratio = np.where(outside, bound / np.where(outside, norm, 1.0), 1.0)
        qx, qy = wx * ratio, wy * ratio
        return qx, qy, np.array([_sum(qx), _sum(qy)]) - target, (wx, wy, norm, outside, ratio)

    qx, qy, residual, parts = evaluate(lam)
    for _ in range(max_iterations):
        if np.hypot(*residual) <= 1e-13 * scale:
            break
        wx, wy, norm, outside, ratio = parts
        inside = ~outside
        ux = np.where(outside, wx / np.where(outside, norm, 1.0), 0.0)
        uy = np.where(outside, wy / np.where(outside, norm, 1.0), 0.0)
        weight = ratio * outside
        n_in = float(np.count_nonzero(inside & (bound > 0)))
        jxx = n_in + _sum(weight * (1.0 - ux * ux))
        jyy = n_in + _sum(weight * (1.0 - uy * uy))
        jxy = -_sum(weight * ux * uy)
        jacobian = np.array([[jxx, jxy], [jxy, jyy]]) + 1e-12 * np.eye(2) * (jxx + jyy + 1e-300)
        step = np.linalg.solve(jacobian, residual)
        length = 1.0
        for _ in range(40):  # backtracking on |residual|
            trial = lam + length * step
            tqx, tqy, tres, tparts = evaluate(trial)
            if np.hypot(*tres) < np.hypot(*residual) or length < 1e-9:
                break
            length *= 0.5
        lam, qx, qy, residual, parts = trial, tqx, tqy, tres, tparts
    return qx, qy, lam


def _optimality(operator, qx, qy, cx, cy, shift, bound, contact, scale):
    """Relative KKT residual of the Coulomb problem at ``q``, and the stick mask."""
    n_contact = max(int(contact.sum()), 1)
    ux, uy = operator.tangential(qx, qy)
    sx, sy = ux + cx - shift[0], uy + cy - shift[1]
    magnitude = np.hypot(qx, qy)
    stick = contact & (magnitude < bound * (1.0 - 1e-9))
    slip = contact & ~stick
    s_mag = np.hypot(sx, sy)
    safe = np.where(slip, magnitude, 1.0)
    ex = np.where(slip, sx + s_mag * qx / safe, 0.0)
    ey = np.where(slip, sy + s_mag * qy / safe, 0.0)
    stick_error = _sum(np.where(stick, sx * sx + sy * sy, 0.0)) / max(int(stick.sum()), 1)
    slip_error = _sum(ex * ex + ey * ey) / n_contact
    displacement = max(
        scale, np.sqrt(_sum((ux * ux + uy * uy) * contact) / n_contact), float(np.hypot(*shift))
    )
    return float(np.sqrt(max(stick_error, slip_error)) / displacement), stick


def solve_tangential(
    operator: SurfaceOperator,
    pressure: np.ndarray,
    friction_coefficient: float,
    offset: tuple[np.ndarray, np.ndarray],
    force: tuple[float, float],
    *,
    initial: tuple[np.ndarray, np.ndarray] | None = None,
    initial_shift: tuple[float, float] = (0.0, 0.0),
    scale: float | None = None,
    tolerance: float = 1e-8,
    max_iterations: int = 5000,
    check_every: int = 5,
) -> TangentialSolution:
    """Solve the incremental Coulomb problem for a given pressure and tangential force.

    Parameters
    ----------
    operator : SurfaceOperator
        Surface operator (its tangential block is used).
    pressure : ndarray
        Contact pressure (Pa).
    friction_coefficient : float
        mu (dimensionless), > 0.
    offset : (ndarray, ndarray)
        The known part ``c`` of the slip increment (m), see the module docstring.
    force : (float, float)
        Prescribed tangential force (Q_x, Q_y) on body 2 (N); must satisfy |Q| < mu W.
    initial : (ndarray, ndarray), optional
        Starting shear tractions (Pa), e.g. the previous step's.
    initial_shift : (float, float)
        Starting shift (m), used while no cell sticks.
    scale : float, optional
        Smallest displacement scale (m) of the residual; the rms of ``c``, of ``K_t q`` and
        the shift over the contact are used when larger.
    tolerance : float
        Relative tolerance.
    max_iterations : int
        Iteration cap; reaching it gives ``converged=False``.
    check_every : int
        Iterations between optimality checks (each costs one operator application).

    Returns
    -------
    TangentialSolution
    """
    area = operator.grid.cell_area
    contact = pressure > 0.0
    n_contact = max(int(contact.sum()), 1)
    bound = friction_coefficient * np.where(contact, pressure, 0.0)
    cx, cy = offset
    target = np.array(force, dtype=float) / area
    if scale is None:
        scale = np.sqrt(_sum((cx * cx + cy * cy) * contact) / n_contact)
    scale = max(scale, 1e-300)
    step = 1.0 / operator.tangential_norm()  # 1/L, L the largest eigenvalue of K_t (m/Pa)
    multiplier = -np.asarray(initial_shift, dtype=float) * step
    if initial is None:
        qx, qy = np.zeros_like(pressure), np.zeros_like(pressure)
    else:
        qx, qy = initial[0] * contact, initial[1] * contact
    qx, qy, multiplier = project_onto_feasible(qx, qy, bound, target, multiplier)
    yx, yy = qx, qy
    momentum = 1.0
    residual, converged, iterations = np.inf, False, 0
    shift = -multiplier / step
    stick = contact
    for iterations in range(1, max_iterations + 1):
        # accelerated projected gradient (FISTA with gradient restart)
        gx, gy = operator.tangential(yx, yy)
        gx += cx
        gy += cy
        new_x, new_y, multiplier = project_onto_feasible(
            yx - step * gx, yy - step * gy, bound, target, multiplier
        )
        dx, dy = new_x - qx, new_y - qy
        if _sum((yx - new_x) * dx + (yy - new_y) * dy) > 0.0:
            momentum = 1.0  # restart: the momentum points uphill
        next_momentum = 0.5 * (1.0 + np.sqrt(1.0 + 4.0 * momentum * momentum))
        factor = (momentum - 1.0) / next_momentum
        momentum = next_momentum
        qx, qy = new_x, new_y
        yx, yy = qx + factor * dx, qy + factor * dy
        if iterations % check_every and iterations < max_iterations:
            continue
        # optimality check at q: stick cells s = 0, slip cells s anti-parallel to q
        shift = -multiplier / step
        residual, stick = _optimality(operator, qx, qy, cx, cy, shift, bound, contact, scale)
        if residual < tolerance:
            converged = True
            break
        if not np.isfinite(residual):
            break
    ux, uy = operator.tangential(qx, qy)
    sx, sy = ux + cx - shift[0], uy + cy - shift[1]
    message = (
        f"converged in {iterations} iterations"
        if converged
        else f"not converged after {iterations} iterations (residual {residual:.3g})"
    )
    return TangentialSolution(
        qx,
        qy,
        sx * contact,
        sy * contact,
        (float(shift[0]), float(shift[1])),
        stick,
        iterations,
        float(residual),
        converged,
        message,
    )
