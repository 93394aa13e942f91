"""Tangential contact for a given pressure: incremental Coulomb friction with slip and stick.

In load step k the slip increment of body 2 relative to body 1 at a surface cell is

    s = K_t q + c - Delta                                                    (m)

where ``K_t`` is the tangential 2x2 block of :class:`solver.surface.convolution.SurfaceOperator`,
``q`` the shear traction on body 2 (Pa), ``c`` everything the caller knows (minus the previous
step's ``K_t q_{k-1}``, plus the pressure-induced tangential displacement increment, the residual
displacement increment, plus the previous shift), and ``Delta`` the rigid tangential shift of
body 1 relative to body 2 (m), an unknown when the tangential force is prescribed (a rolling
increment at a given creepage prescribes it instead: the force is then free, ``force=None``,
and the caller folds ``Delta`` into ``c``).  Coulomb's law with memory:  stick ``s = 0,
|q| <= mu p``;  slip ``|q| = mu p, q = -mu p s/|s|``.  A shear limit (Orowan's law,
``friction.shear_limit``) replaces every ``mu p`` by ``g = min(mu p, m tau_c)``
(:func:`friction_bound`): the disks shrink where the cap binds, nothing else changes, so every
statement below holds with ``g`` for ``mu p``.

For a given pressure these are the optimality conditions of the convex problem (Kalker's
minimum complementary energy)

    minimise  1/2 q.K_t q + q.c   subject to  |q_i| <= mu p_i  and  sum q dA = Q,

with ``Delta`` the multiplier of the force constraint.  Two methods, the second a safety net:

1. **Active-set Newton** (:func:`_active_set`): split the contact into stick and slip by the
   trial traction ``q - rho s`` (a primal-dual active set), then take one Newton step on the
   stick tractions *and the slip directions* (slip magnitudes stay mu p; the circle's curvature
   ``nu/(mu p)`` enters the Hessian), solved by CG preconditioned with the inverse Cerruti symbol
   (:meth:`SurfaceOperator.inverse_tangential`), so the iteration count hardly depends on the
   mesh.  The force is restored by a multiplier on every cell, not on the stick cells alone
   (which overloaded them when the stick zone is small, as in Spence's problem).  On
   Cattaneo-Mindlin at 64^2 a tangential load in 10 steps costs 245 operator applications
   instead of 2,715 with the projected gradient alone.
2. **Accelerated projected gradient** (FISTA, Beck & Teboulle 2009, with O'Donoghue & Candes'
   gradient restart) from the best active-set iterate, when that stagnates: a gradient step of
   length 1/L (L the largest eigenvalue of the circulant ``K_t``), then the exact Euclidean
   projection onto {disks} and {sum q = Q} (:func:`project_onto_feasible`, a 2-D Newton
   iteration for the force multiplier).  It converges for this convex problem whatever the
   stick set does.

With the normal-tangential coupling (Dundurs beta != 0), :func:`solve_tangential_coupled` runs
the active-set iteration with the pressure renewed by a normal solve after every Newton step
(the caller's ``renew``), instead of a whole tangential solve per normal solve.

Convergence: the residual ``max(rms of |s| on stick cells, rms over the contact of the slip-cell
error |s + |s| q/|q|| and of the excess over the disks (times the cell self-compliance)) /
scale`` measures every optimality condition (the force is enforced exactly); ``scale`` is the
largest of the caller's scale, the rms of ``K_t q`` over the contact and the shift.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
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
    displacement_x, displacement_y : ndarray
        ``K_t q`` (m), the tangential displacement of the returned shear tractions.
    shift : tuple of float
        Rigid tangential shift Delta (m) of body 1 relative to body 2.
    stick : ndarray of bool
        Stick cells (in contact, |q| < mu p).
    iterations : int
        Applications of the tangential operator (both methods).
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
    displacement_x: np.ndarray
    displacement_y: np.ndarray
    shift: tuple[float, float]
    stick: np.ndarray
    iterations: int
    residual: float
    converged: bool
    message: str


def friction_bound(
    friction_coefficient: float, pressure: np.ndarray, cap: np.ndarray | float | None = None
) -> np.ndarray:
    """The radius of each cell's friction disk (Pa): ``mu p``, or ``min(mu p, cap)``.

    ``cap``: Orowan's shear limit ``m tau_c`` (Pa), one value or one per cell; None: Coulomb's
    law alone.  Zero outside the contact (``p = 0``).
    """
    bound = friction_coefficient * np.maximum(pressure, 0.0)
    return bound if cap is None else np.minimum(bound, cap)


def over_capacity(bound: np.ndarray, target: np.ndarray | None) -> bool:
    """True when a prescribed force per cell area ``target`` (Pa) reaches the disks' capacity.

    The largest force the contact can transmit is ``sum bound dA`` (every cell slipping along
    the force); a shear limit lowers it below ``mu W``.
    """
    return target is not None and bool(np.hypot(*target) >= (1.0 - 1e-12) * _sum(bound))


def _sum(a: np.ndarray) -> float:
    return float(np.einsum("ij->", a))


def _dot(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.einsum("ij,ij->", a, b))


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
    target : ndarray or None
        Required sums (sum q_x, sum q_y) (Pa, i.e. force / cell area); None: no force
        constraint (the projection onto the disks alone, ``multiplier`` returned unchanged).
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
    if target is None:  # no force constraint: each traction onto its disk
        norm = np.hypot(zx, zy)
        ratio = np.where(norm > bound, bound / np.where(norm > bound, norm, 1.0), 1.0)
        return zx * ratio, zy * ratio, lam

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
        if not jxx + jyy > 0.0:  # no cell can take more force (every bound 0): the target
            break  # cannot be met; the caller's residual says so (an infinite step would NaN)
        jacobian = np.array([[jxx, jxy], [jxy, jyy]]) + 1e-12 * np.eye(2) * (jxx + jyy)
        step = np.linalg.solve(jacobian, residual)
        if not np.isfinite(step).all():
            break
        length = 1.0
        for _ in range(40):  # backtracking on |residual|
            trial = lam + length * step
            tqx, tqy, tres, tparts = evaluate(trial)
            if np.hypot(*tres) < np.hypot(*residual) or length < 1e-9:
                break
            length *= 0.5
        lam, qx, qy, residual, parts = trial, tqx, tqy, tres, tparts
    return qx, qy, lam


def _optimality(ux, uy, qx, qy, cx, cy, shift, bound, contact, scale, compliance=0.0):
    """Relative KKT residual of the Coulomb problem at ``q`` (``u = K_t q``), and the stick mask.

    ``compliance`` (m/Pa) converts a traction above the bound into a displacement error; the
    projected gradient's iterates never exceed it, the active-set iterates may.
    """
    n_contact = max(int(contact.sum()), 1)
    sx, sy = ux + cx - shift[0], uy + cy - shift[1]
    magnitude = np.hypot(qx, qy)
    excess = np.maximum(magnitude - bound, 0.0) * compliance
    stick = contact & (magnitude < bound * (1.0 - 1e-9))
    slip = contact & ~stick
    s_mag = np.hypot(sx, sy)
    safe = np.where(slip, magnitude, 1.0)
    ex = np.where(slip, sx + s_mag * qx / safe, 0.0)
    ey = np.where(slip, sy + s_mag * qy / safe, 0.0)
    stick_error = _sum(np.where(stick, sx * sx + sy * sy, 0.0)) / max(int(stick.sum()), 1)
    slip_error = _sum(ex * ex + ey * ey + excess * excess) / n_contact
    displacement = max(
        scale, np.sqrt(_sum((ux * ux + uy * uy) * contact) / n_contact), float(np.hypot(*shift))
    )
    return float(np.sqrt(max(stick_error, slip_error)) / displacement), stick


#: Split parameter: a contact cell sticks when |q - rho s| <= mu p, rho = SPLIT / (the cell's
#: self-compliance).  Small values keep the split close to |q| < mu p (cells enter slip when
#: their traction reaches the bound and return when they slip backwards); 0.3 was the fastest
#: of 0.01-3 on Cattaneo-Mindlin and Spence.
SPLIT = 0.3
#: Passes without a 10 % fall of the residual after which the active-set iteration hands over
#: to the projected gradient.
STAGNATION = 5
#: CG iterations of one Newton step at most.
NEWTON_MAX_ITERATIONS = 100
#: Forcing of the Newton step's CG (its tolerance over the current residual): loose while the
#: stick/slip split still changes between passes (the step is then only as good as the split),
#: tighter once the split repeats (the linear system is then the right one).  0.03 took
#: Cattaneo-Mindlin in 10 steps at 64^2 from 218 to 201 operator applications and left
#: Spence's scene within 2 %.
FORCING, SETTLED_FORCING = 0.1, 0.03


def _newton_solve(
    operator, qx, qy, ux, uy, cx, cy, stick, slip, bound, tolerance, max_iterations, free=False
):
    """One Newton step for a fixed stick/slip split, solved by preconditioned CG.

    Unknowns: the traction of every stick cell and the direction of every slip cell (whose
    magnitude stays mu p); the force is held fixed.  The Hessian on these directions is
    ``P K_t P + nu/(mu p)`` (``P`` the restriction to the admissible directions, ``nu = -s.e``
    the slip multiplier: the curvature of the circle); the preconditioner is the inverse
    Cerruti symbol (:meth:`SurfaceOperator.inverse_tangential`) restricted alike.  Updates
    ``q`` (slip tractions retracted to their circles, the force restored on the stick cells)
    and ``u = K_t q`` in place; returns (shift, operator applications).  ``free``: no force
    constraint (the shift is then zero: the caller folded it into ``c``).
    """
    magnitude = np.hypot(qx, qy)
    slip = slip & (magnitude > 0.0)
    safe = np.where(slip, magnitude, 1.0)
    ex, ey = np.where(slip, qx / safe, 0.0), np.where(slip, qy / safe, 0.0)
    tx, ty = -ey, ex
    on_stick = stick.astype(float)
    # restriction to the admissible directions: identity on stick cells, onto t = e_perp on
    # slip cells, zero elsewhere: the symmetric 2x2 field [[rxx, rxy], [rxy, ryy]]
    rxx, rxy, ryy = on_stick + tx * tx, tx * ty, on_stick + ty * ty

    def restrict(fx, fy):
        return rxx * fx + rxy * fy, rxy * fx + ryy * fy

    # force constraint: the admissible images of the unit x and y tractions, (rxx, rxy), (rxy, ryy)
    cross = _dot(rxx, rxy) + _dot(rxy, ryy)
    gram = np.array(
        [[_dot(rxx, rxx) + _dot(rxy, rxy), cross], [cross, _dot(rxy, rxy) + _dot(ryy, ryy)]]
    )
    gram_inverse = np.zeros((2, 2)) if free else np.linalg.pinv(gram)

    def coefficients(fx, fy):
        # least-squares components of f along the admissible unit forces; f is always
        # admissible here (restricted) and the restriction is a projector, so the products
        # with (rxx, rxy) and (rxy, ryy) reduce to the sums of f
        return gram_inverse @ np.array([_sum(fx), _sum(fy)])

    def project(fx, fy):
        c0, c1 = coefficients(fx, fy)
        return fx - c0 * rxx - c1 * rxy, fy - c0 * rxy - c1 * ryy

    gx, gy = restrict(ux + cx, uy + cy)
    shift = coefficients(gx, gy)
    sx, sy = ux + cx - shift[0], uy + cy - shift[1]
    nu = np.maximum(-(sx * ex + sy * ey), 0.0)
    curvature = np.where(slip, nu / np.where(slip, bound, 1.0), 0.0)
    rx, ry = project(-gx, -gy)  # CG residual b - H d at d = 0, b the negative gradient
    dx, dy = np.zeros_like(qx), np.zeros_like(qy)
    kdx, kdy = np.zeros_like(qx), np.zeros_like(qy)
    px, py = np.zeros_like(qx), np.zeros_like(qy)
    count = max(float(np.count_nonzero(stick | slip)), 1.0)
    rz_old, applications = 0.0, 0
    for _ in range(max_iterations):
        if np.sqrt((_dot(rx, rx) + _dot(ry, ry)) / count) <= tolerance:
            break
        zx, zy = project(*restrict(*operator.inverse_tangential(rx, ry)))
        rz = _dot(rx, zx) + _dot(ry, zy)
        if not rz > 0.0:
            break
        beta = rz / rz_old if rz_old > 0.0 else 0.0
        px, py = zx + beta * px, zy + beta * py
        rz_old = rz
        wx, wy = operator.tangential(px, py)
        applications += 1
        hx, hy = project(*restrict(wx + curvature * px, wy + curvature * py))
        denominator = _dot(px, hx) + _dot(py, hy)
        if not denominator > 0.0:
            break
        alpha = rz / denominator
        dx += alpha * px
        dy += alpha * py
        kdx += alpha * wx
        kdy += alpha * wy
        rx -= alpha * hx
        ry -= alpha * hy
    # update: stick cells linearly, slip cells retracted onto their circles
    new_x, new_y = qx + dx, qy + dy
    norm = np.hypot(new_x, new_y)
    ratio = np.where(slip, bound / np.where(norm > 0.0, norm, 1.0), 1.0)
    new_x *= ratio
    new_y *= ratio
    if not free:  # the force restored on the stick cells
        n_stick = max(float(stick.sum()), 1.0)
        new_x += on_stick * ((_sum(qx) - _sum(new_x)) / n_stick)
        new_y += on_stick * ((_sum(qy) - _sum(new_y)) / n_stick)
    # u follows linearly; the retraction's (second-order) correction needs one more product
    cor_x, cor_y = new_x - qx - dx, new_y - qy - dy
    if np.any(cor_x) or np.any(cor_y):
        ucx, ucy = operator.tangential(cor_x, cor_y)
        applications += 1
        kdx += ucx
        kdy += ucy
    qx[...], qy[...] = new_x, new_y
    ux += kdx
    uy += kdy
    return coefficients(*restrict(ux + cx, uy + cy)), applications


def _active_set(
    operator, bound, contact, cx, cy, target, qx, qy, scale, tolerance, budget, renew=None
):
    """Active-set Newton iteration (module docstring).

    Each pass splits the contact by the trial traction ``z = q - rho s`` (``rho`` =
    :data:`SPLIT` over the cell self-compliance): stick where ``|z| <= mu p``; the slip cells
    move to ``z`` and the whole field is projected onto the disks and the force
    (:func:`project_onto_feasible`); then one Newton step (:func:`_newton_solve`) for that split,
    its CG run to :data:`FORCING` times the current residual (:data:`SETTLED_FORCING` once the
    split repeats the previous pass's).
    It stops when the KKT residual is below ``tolerance`` and gives up, returning the best
    iterate, when the stick set empties, the residual has not fallen by 10 % in
    :data:`STAGNATION` passes, or ``budget`` operator applications are spent.

    ``renew(qx, qy, residual)``, when given, makes the pressure follow the shear tractions
    (:func:`solve_tangential_coupled`): it is called before the first pass and after every
    Newton step and returns ``(bound, contact, cx, cy, settled)``, the disks and offset for the
    current shear and whether the pressure has settled.  The iteration stops when a Newton
    step's residual is below ``tolerance`` and the renewal after it has settled; the iterate
    then belongs to the data before that renewal.

    Returns (qx, qy, ux, uy, shift, residual, stick, applications, converged).
    """
    compliance = operator.tangential_diagonal()
    rho = SPLIT / compliance
    free = target is None  # no force constraint: the shift is in c
    area_target = None if free else np.asarray(target, dtype=float)
    settled = True
    if renew is not None:
        bound, contact, cx, cy, settled = renew(qx, qy, np.inf)
    if scale is None:  # the rms of the offset over the contact
        scale = max(np.sqrt(_sum((cx * cx + cy * cy) * contact) / max(contact.sum(), 1)), 1e-300)
    qx, qy, multiplier = project_onto_feasible(qx, qy, bound, area_target, np.zeros(2))
    ux, uy = operator.tangential(qx, qy)
    applications = 1
    # the starting shift: the mean rigid motion of the cells inside their disks
    inside = contact & (np.hypot(qx, qy) < bound)
    weight = (inside if inside.any() else contact).astype(float)
    shift = np.zeros(2)
    if not free and weight.any():
        shift = np.array([_sum((ux + cx) * weight), _sum((uy + cy) * weight)]) / _sum(weight)
    residual, stick = _optimality(ux, uy, qx, qy, cx, cy, shift, bound, contact, scale, compliance)
    best = (residual, qx.copy(), qy.copy(), ux.copy(), uy.copy(), shift.copy(), stick)
    stagnant = 0
    previous_split = None
    while (
        (residual >= tolerance or not settled) and applications < budget and stagnant < STAGNATION
    ):
        # split by the trial traction z = q - rho s; slip cells move to z
        zx = qx - rho * (ux + cx - shift[0])
        zy = qy - rho * (uy + cy - shift[1])
        stick_set = contact & (np.hypot(zx, zy) <= bound)
        if not stick_set.any() and not free:  # full slip under a force below mu W: no split
            break
        # the force is restored by the projection's multiplier on every cell, not by the few
        # stick cells alone (which would overload them when the stick zone is small)
        new_x, new_y, multiplier = project_onto_feasible(
            np.where(stick_set, qx, zx), np.where(stick_set, qy, zy), bound, area_target, multiplier
        )
        dux, duy = operator.tangential(new_x - qx, new_y - qy)
        applications += 1
        qx, qy, ux, uy = new_x, new_y, ux + dux, uy + duy
        displacement = max(
            scale,
            np.sqrt(_sum((ux * ux + uy * uy) * contact) / max(int(contact.sum()), 1)),
            float(np.hypot(*shift)),
        )
        settled_split = previous_split is not None and np.array_equal(previous_split, stick_set)
        previous_split = stick_set
        forcing = SETTLED_FORCING if settled_split else FORCING
        inner = displacement * max(0.3 * tolerance, min(1e-3, forcing * residual))
        shift, used = _newton_solve(
            operator, qx, qy, ux, uy, cx, cy, stick_set, contact & ~stick_set, bound, inner,
            min(budget - applications, NEWTON_MAX_ITERATIONS), free,
        )  # fmt: skip
        applications += used
        residual, stick = _optimality(
            ux, uy, qx, qy, cx, cy, shift, bound, contact, scale, compliance
        )
        if not np.isfinite(residual):
            break
        if renew is not None:  # the pressure for these shear tractions
            renewed = renew(qx, qy, residual)
            settled = renewed[4]
            if residual < tolerance and settled:
                break  # converged on the data it was computed with
            bound, contact, cx, cy = renewed[:4]
        if residual < 0.9 * best[0]:
            stagnant = 0
        else:
            stagnant += 1
        if residual < best[0]:
            best = (residual, qx.copy(), qy.copy(), ux.copy(), uy.copy(), shift.copy(), stick)
    if renew is not None:  # the current iterate: the one the last data belong to
        converged = residual < tolerance and settled
        return qx, qy, ux, uy, shift, residual, stick, applications, converged
    residual, qx, qy, ux, uy, shift, stick = best
    return qx, qy, ux, uy, shift, residual, stick, applications, residual < tolerance


def _projected_gradient(
    operator, bound, contact, cx, cy, target, qx, qy, shift, scale, tolerance, budget, check_every
):
    """Accelerated projected gradient (FISTA with gradient restart) from ``q``.

    Returns (qx, qy, ux, uy, shift, residual, stick, applications, converged).
    """
    step = 1.0 / operator.tangential_norm()  # 1/L, L the largest eigenvalue of K_t (m/Pa)
    multiplier = -np.asarray(shift, dtype=float) * step
    qx, qy, multiplier = project_onto_feasible(qx, qy, bound, target, multiplier)
    # One operator application per iteration: K_t y follows from K_t q and K_t q_old by
    # linearity, and the optimality check at q reuses K_t q.
    ux, uy = operator.tangential(qx, qy)
    old_ux, old_uy = ux, uy
    yx, yy, factor = qx, qy, 0.0
    momentum = 1.0
    residual, converged, iterations = np.inf, False, 1
    shift = -multiplier / step
    stick = contact
    for iterations in range(2, max(budget, 2) + 1):
        gx = ux + factor * (ux - old_ux) + cx
        gy = uy + factor * (uy - old_uy) + cy
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
        old_ux, old_uy = ux, uy
        ux, uy = operator.tangential(qx, qy)
        if iterations % check_every and iterations < budget:
            continue
        # optimality check at q: stick cells s = 0, slip cells s anti-parallel to q
        shift = -multiplier / step
        residual, stick = _optimality(ux, uy, qx, qy, cx, cy, shift, bound, contact, scale)
        if residual < tolerance:
            converged = True
            break
        if not np.isfinite(residual):
            break
    return qx, qy, ux, uy, shift, residual, stick, iterations, converged


def solve_tangential(
    operator: SurfaceOperator,
    pressure: np.ndarray,
    friction_coefficient: float,
    offset: tuple[np.ndarray, np.ndarray],
    force: tuple[float, float] | None,
    *,
    initial: tuple[np.ndarray, np.ndarray] | None = None,
    scale: float | None = None,
    tolerance: float = 1e-8,
    max_iterations: int = 5000,
    check_every: int = 5,
    shear_cap: np.ndarray | float | None = None,
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
    force : (float, float) or None
        Prescribed tangential force (Q_x, Q_y) on body 2 (N); must satisfy |Q| < mu W.  None:
        the force is free and the rigid shift prescribed (rolling at a given creepage): the
        caller subtracts it from ``offset`` and the returned shift is zero.
    initial : (ndarray, ndarray), optional
        Starting shear tractions (Pa), e.g. the previous step's.
    scale : float, optional
        Smallest displacement scale (m) of the residual; the rms of ``c``, of ``K_t q`` and
        the shift over the contact are used when larger.
    tolerance : float
        Relative tolerance.
    max_iterations : int
        Cap on applications of the tangential operator (half of it for the active-set
        iteration); reaching it gives ``converged=False``.
    check_every : int
        Projected-gradient iterations between optimality checks.
    shear_cap : ndarray or float, optional
        Orowan's shear limit ``m tau_c`` (Pa) capping the disks, ``|q| <= min(mu p, cap)``
        (:func:`friction_bound`); None: Coulomb's law alone.  A force the capped disks cannot
        carry (:func:`over_capacity`) is not solved: every contact cell slips along it at its
        bound, not converged, and the message says so.

    Returns
    -------
    TangentialSolution
    """
    area = operator.grid.cell_area
    contact = pressure > 0.0
    n_contact = max(int(contact.sum()), 1)
    bound = friction_bound(friction_coefficient, pressure, shear_cap)
    cx, cy = offset
    target = None if force is None else np.array(force, dtype=float) / area
    if over_capacity(bound, target):
        return _overloaded(operator, bound, contact, cx, cy, target)
    if not (cx.any() or cy.any()) and (target is None or not target.any()):
        # nothing drives the shear (no offset, no force): q = 0 is the energy's unique
        # minimiser (K_t is positive definite), every contact cell sticks
        zero = np.zeros_like(pressure)
        return _solution(zero, zero, zero, zero, cx, cy, (0.0, 0.0), contact, contact, 0, 0.0, True)
    if scale is None:
        scale = np.sqrt(_sum((cx * cx + cy * cy) * contact) / n_contact)
    scale = max(scale, 1e-300)
    if initial is None:
        qx, qy = np.zeros_like(pressure), np.zeros_like(pressure)
    else:
        qx, qy = initial[0] * contact, initial[1] * contact
    qx, qy, ux, uy, shift, residual, stick, iterations, converged = _active_set(
        operator, bound, contact, cx, cy, target, qx, qy, scale, tolerance,
        budget=max_iterations // 2,
    )  # fmt: skip
    if not converged:  # the projected gradient, from the best active-set iterate
        qx, qy, ux, uy, shift, residual, stick, used, converged = _projected_gradient(
            operator, bound, contact, cx, cy, target, qx, qy, shift, scale, tolerance,
            max_iterations - iterations, check_every,
        )  # fmt: skip
        iterations += used
    return _solution(qx, qy, ux, uy, cx, cy, shift, contact, stick, iterations, residual, converged)


def _overloaded(operator, bound, contact, cx, cy, target) -> TangentialSolution:
    """The answer to a force above the disks' capacity: full slip along it, not converged."""
    direction = target / np.hypot(*target)
    qx, qy = bound * direction[0], bound * direction[1]
    ux, uy = operator.tangential(qx, qy)
    capacity = _sum(bound) * operator.grid.cell_area
    solution = _solution(qx, qy, ux, uy, cx, cy, (0.0, 0.0), contact, np.zeros_like(contact), 0,
                         np.inf, False)  # fmt: skip
    message = (
        f"the tangential force {np.hypot(*target) * operator.grid.cell_area:.4g} N is at or "
        f"above what the friction can carry, {capacity:.4g} N (the sum of min(mu p, m tau_c) "
        "over the contact, lowered by friction.shear_limit): gross sliding; lower the "
        "tangential force or raise the shear limit"
    )
    return dataclasses.replace(solution, message=message)


def _solution(qx, qy, ux, uy, cx, cy, shift, contact, stick, iterations, residual, converged):
    sx, sy = ux + cx - shift[0], uy + cy - shift[1]
    message = (
        f"converged in {iterations} iterations"
        if converged
        else f"not converged after {iterations} iterations (residual {residual:.3g})"
    )
    return TangentialSolution(
        qx, qy, sx * contact, sy * contact, ux, uy, (float(shift[0]), float(shift[1])), stick,
        iterations, float(residual), converged, message,
    )  # fmt: skip


def solve_tangential_coupled(
    operator: SurfaceOperator,
    friction_coefficient: float,
    renew: Callable[[np.ndarray, np.ndarray, float], tuple],
    force: tuple[float, float] | None,
    initial: tuple[np.ndarray, np.ndarray],
    *,
    tolerance: float = 1e-8,
    max_iterations: int = 5000,
    shear_cap: np.ndarray | float | None = None,
) -> TangentialSolution:
    """Tangential solve whose pressure follows the shear tractions (normal-tangential coupling).

    The active-set Newton iteration of :func:`solve_tangential` with the pressure renewed
    after every Newton step instead of held fixed: ``renew(qx, qy, residual)`` solves the
    normal problem for the current shear tractions (``residual``, the current relative
    residual, lets it solve only as tightly as needed) and returns ``(pressure, (cx, cy),
    settled)``: the pressure (Pa), the offset ``c`` (m) that goes with it and whether the
    pressure has settled (changed less than the coupling tolerance in a tight normal solve).
    One Newton step per normal solve instead of a whole tangential solve: the coupling
    converges alongside the friction problem.  Converged when a Newton step leaves a KKT
    residual below ``tolerance`` and the pressure renewed after it has settled; the solution
    belongs to the renewal before that one (the caller keeps both).  Otherwise the caller
    falls back on alternating whole solves (no projected-gradient fallback here).

    Parameters
    ----------
    operator : SurfaceOperator
        Surface operator.
    friction_coefficient : float
        mu (dimensionless), > 0.
    renew : callable
        See above.
    force : (float, float) or None
        Prescribed tangential force (N); None: free, the shift in the offset
        (:func:`solve_tangential`).
    initial : (ndarray, ndarray)
        Starting shear tractions (Pa).
    tolerance : float
        Relative tolerance of the KKT residual.
    max_iterations : int
        Cap on applications of the tangential operator.
    shear_cap : ndarray or float, optional
        Orowan's shear limit capping the disks (:func:`solve_tangential`).

    Returns
    -------
    TangentialSolution
    """
    area = operator.grid.cell_area
    data = []  # (contact, cx, cy) of every renewal

    def disks(qx, qy, residual):
        pressure, (cx, cy), settled = renew(qx, qy, residual)
        contact = pressure > 0.0
        data.append((contact, cx, cy))
        bound = friction_bound(friction_coefficient, pressure, shear_cap)
        return bound, contact, cx, cy, settled

    target = None if force is None else np.array(force, dtype=float) / area
    zero = np.zeros_like(initial[0])  # placeholders: the first renewal sets the disks
    qx, qy, ux, uy, shift, residual, stick, iterations, converged = _active_set(
        operator, zero, zero > 0, zero, zero, target, initial[0], initial[1], None, tolerance,
        budget=max_iterations, renew=disks,
    )  # fmt: skip
    contact, cx, cy = data[-2] if converged else data[-1]  # the data q was solved with
    return _solution(
        qx, qy, ux, uy, cx, cy, shift, contact, stick, iterations, residual, converged
    )  # fmt: skip
