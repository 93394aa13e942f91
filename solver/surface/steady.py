r"""Steady-state rolling for a given pressure: Kalker's steady slip, solved directly.

In a contact that rolls along +x at constant creepage the tractions are steady in a frame that
moves with the contact.  A point of body 2 crosses the contact from its leading edge (+x) to its
trailing edge; per unit distance rolled its slip relative to body 1 is (Kalker 1967, 1990)

    s = -d_x u + c,    c = (-xi + phi y, -eta - phi x)                       (1)

with ``u = K_t q`` the tangential displacement difference of the shear tractions q on body 2
(:class:`~solver.surface.convolution.SurfaceOperator`), (xi, eta) the creepages, phi the spin
(1/m) and (x, y) measured from the contact's centre: the signs of the transient rolling step
(:func:`solver.drive.steps.slip_stick_step`), of which (1) is the limit of a small step.
Coulomb's law: stick ``s = 0, |q| <= mu p``; slip ``q = -mu p s / |s|``.

**Discretisation.**  ``-d_x u`` is the upwind difference ``(u_i - u_{i+1}) / dx`` along the
material's path (the point came from the cell ahead): first order in the cell size, the scheme
of Kalker's CONTACT, and exactly the transient step of one cell with the tractions shifted by
one cell (so a march of one-cell steps ends at this solution).  With
``theta = 2`` the second-order upwind difference ``(3 u_i - 4 u_{i+1} + u_{i+2}) / (2 dx)``.

**Solver.**  The steady operator ``A q = -d_x K_t q`` is not symmetric: the problem is no longer
a minimisation and the tangential solver's conjugate gradients do not apply.  It is solved as
the nonsmooth equation ``F(q) = q - P(q - r s(q)) = 0`` (P the projection onto the disks
``|q| <= mu p``, r a positive scaling) by a semi-smooth Newton method: the Jacobian of P is the
identity on stick cells and ``(mu p / |z|)(I - z z^T / |z|^2)`` on slip cells; each Newton
system is solved by GMRES (one tangential convolution a product), the step damped by a
backtracking line search on ``|F|``.  Stick and slip are the active sets of the last iterate.
A prescribed tangential force adds the creepage (xi, eta) as two unknowns and the force's two
equations (as mean tractions over the contact) to the same Newton system.

Convergence: ``rms(F) / rms(mu p)`` over the contact (a relative traction error that vanishes
exactly at the solution) below the tolerance; the Newton iterations and the operator
applications are capped, and a solve that reaches a cap says so (``converged = False``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.sparse.linalg import LinearOperator, gmres

from .convolution import SurfaceOperator

#: Upwind schemes: first order (CONTACT's) and second order.
ORDERS = (1, 2)
#: Backtracking halvings of a Newton step before the step is taken as it is.
LINE_SEARCH_HALVINGS = 12
#: GMRES restart length and its relative tolerance (relative to the Newton residual).
GMRES_RESTART, GMRES_TOLERANCE = 60, 1e-3


@dataclass(frozen=True)
class SteadySolution:
    """Result of one steady rolling solve for a given pressure.

    Attributes
    ----------
    shear_x, shear_y : ndarray
        Shear tractions on body 2 (Pa).
    slip_x, slip_y : ndarray
        Slip per unit distance rolled (1), zero in stick up to the residual.
    displacement_x, displacement_y : ndarray
        ``K_t q`` (m).
    stick : ndarray of bool
        Stick cells.
    creepage : (float, float)
        The creepage (xi, eta) found for a prescribed force (0, 0 when none is prescribed).
    newton_iterations, iterations : int
        Newton steps, and applications of the tangential operator in all.
    residual : float
        ``rms(F) / rms(mu p)`` over the contact.
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
    stick: np.ndarray
    creepage: tuple[float, float]
    newton_iterations: int
    iterations: int
    residual: float
    converged: bool
    message: str


def upwind(u: np.ndarray, dx: float, order: int = 1) -> np.ndarray:
    """``-d_x u`` by the upwind difference along +x rolling (the leading edge at large x).

    The last row (and the last two for ``order = 2``) keep the lower order there, or zero on
    the last row: the contact must not touch the grid's leading edge.
    """
    out = np.zeros_like(u)
    out[:-1] = (u[:-1] - u[1:]) / dx
    if order == 2:
        out[:-2] = (3.0 * u[:-2] - 4.0 * u[1:-1] + u[2:]) / (2.0 * dx)
    return out


def solve_steady_tangential(
    operator: SurfaceOperator,
    pressure: np.ndarray,
    friction_coefficient: float,
    rigid: tuple[np.ndarray, np.ndarray],
    *,
    force: tuple[float, float] | None = None,
    order: int = 1,
    initial: tuple[np.ndarray, np.ndarray] | None = None,
    initial_creepage: tuple[float, float] = (0.0, 0.0),
    tolerance: float = 1e-8,
    max_iterations: int = 5000,
    max_newton: int = 100,
) -> SteadySolution:
    """Steady rolling tractions for a given pressure and rigid slip (module docstring).

    Parameters
    ----------
    operator : SurfaceOperator
        Surface operator (its tangential block).
    pressure : ndarray
        Contact pressure (Pa); the contact must stay off the grid's leading (last x) rows.
    friction_coefficient : float
        mu, > 0.
    rigid : (ndarray, ndarray)
        ``c`` of (1): the rigid slip per unit distance rolled (1), e.g. ``(-xi + phi y,
        -eta - phi x)``, plus any known displacement's upwind difference.
    force : (float, float), optional
        A prescribed tangential force (N) on body 2: the creepage (xi, eta) is then two more
        unknowns, subtracted from ``rigid`` (the force's two equations, as mean tractions over
        the contact, join the Newton system); ``|force| < mu W``.
    order : int
        1 or 2: the upwind difference's order.
    initial : (ndarray, ndarray), optional
        Starting tractions (Pa), e.g. the previous creepage's.
    initial_creepage : (float, float)
        Starting creepage of a prescribed force.
    tolerance : float
        Relative tolerance of ``rms(F) / rms(mu p)``.
    max_iterations : int
        Cap on tangential operator applications.
    max_newton : int
        Cap on Newton steps.

    Returns
    -------
    SteadySolution
    """
    if order not in ORDERS:
        raise ValueError(f"order must be one of {ORDERS}, got {order}")
    dx = operator.grid.dx
    contact = pressure > 0.0
    if contact[-order:].any():
        raise ValueError(
            "the contact reaches the grid's leading edge (largest x): the upwind difference "
            "needs free cells ahead of it; widen the grid along x"
        )
    bound = friction_coefficient * np.where(contact, pressure, 0.0)[contact]
    norm_bound = max(float(np.sqrt(np.mean(bound * bound))), 1e-300)
    cx, cy = rigid
    cx, cy = cx[contact], cy[contact]
    count = int(contact.sum())
    applications = 0
    fx, fy = np.zeros_like(pressure), np.zeros_like(pressure)

    def apply(vx, vy):
        """``A v`` on the contact cells: ``-d_x K_t v`` (v zero outside)."""
        nonlocal applications
        applications += 1
        fx[contact], fy[contact] = vx, vy
        ux, uy = operator.tangential(fx, fy)
        return upwind(ux, dx, order)[contact], upwind(uy, dx, order)[contact], ux, uy

    # the scaling r: the inverse of the operator's diagonal, from one impulse at the centre
    probe = np.zeros_like(pressure)
    i, j = (n // 2 for n in pressure.shape)
    probe[i, j] = 1.0
    ux, _ = operator.tangential(probe, np.zeros_like(probe))
    applications += 1
    r = 1.0 / max(float(upwind(ux, dx, order)[i, j]), 1e-300)

    if initial is None:
        qx, qy = np.zeros(count), np.zeros(count)
    else:
        qx, qy = initial[0][contact].copy(), initial[1][contact].copy()
    free = force is not None  # the creepage is two more unknowns
    creep = np.array(initial_creepage if free else (0.0, 0.0), dtype=float)
    area = count * operator.grid.cell_area
    mean_target = np.zeros(2) if force is None else np.asarray(force, dtype=float) / area

    def state(qx, qy, creep):
        ax, ay, ux, uy = apply(qx, qy)
        sx, sy = ax + cx - creep[0], ay + cy - creep[1]
        zx, zy = qx - r * sx, qy - r * sy
        size = np.hypot(zx, zy)
        scale = np.divide(bound, size, out=np.ones_like(size), where=size > bound)
        res_x, res_y = qx - scale * zx, qy - scale * zy
        res_f = np.array([qx.mean(), qy.mean()]) - mean_target if free else np.zeros(0)
        total = float(np.sum(res_x * res_x + res_y * res_y) + count * np.sum(res_f * res_f))
        error = float(np.sqrt(total / count)) / norm_bound
        return (sx, sy, zx, zy, size, res_x, res_y, res_f, ux, uy), error

    extra = 2 if free else 0
    current, error = state(qx, qy, creep)
    newton, converged, message = 0, error <= tolerance, ""
    while not converged and newton < max_newton and applications < max_iterations:
        newton += 1
        sx, sy, zx, zy, size, res_x, res_y, res_f, _, _ = current
        slip = size > bound
        ratio = np.divide(bound, size, out=np.zeros_like(size), where=slip)
        hx = np.divide(zx, size, out=np.zeros_like(size), where=slip)
        hy = np.divide(zy, size, out=np.zeros_like(size), where=slip)

        def jacobian(v, slip=slip, ratio=ratio, hx=hx, hy=hy):
            vx, vy, dc = v[:count], v[count : 2 * count], v[2 * count :]
            ax, ay, _, _ = apply(vx, vy)
            dzx, dzy = vx - r * ax, vy - r * ay
            if free:  # s = A q + c - creepage: dz = dq - r A dq + r d(creepage)
                dzx, dzy = dzx + r * dc[0], dzy + r * dc[1]
            along = hx * dzx + hy * dzy
            px = np.where(slip, ratio * (dzx - hx * along), dzx)
            py = np.where(slip, ratio * (dzy - hy * along), dzy)
            forces = [vx.mean(), vy.mean()] if free else []
            return np.concatenate([vx - px, vy - py, forces])

        size_n = 2 * count + extra
        system = LinearOperator((size_n, size_n), matvec=jacobian, dtype=float)
        rhs = -np.concatenate([res_x, res_y, res_f])
        budget = max((max_iterations - applications) // GMRES_RESTART, 1)
        step, _ = gmres(
            system, rhs, rtol=GMRES_TOLERANCE, restart=GMRES_RESTART, maxiter=budget, atol=0.0
        )
        t = 1.0
        for _ in range(LINE_SEARCH_HALVINGS):
            trial, trial_error = state(
                qx + t * step[:count],
                qy + t * step[count : 2 * count],
                creep + t * step[2 * count :] if free else creep,
            )
            if trial_error < (1.0 - 1e-4 * t) * error:
                break
            t *= 0.5
        qx, qy = qx + t * step[:count], qy + t * step[count : 2 * count]
        if free:
            creep = creep + t * step[2 * count :]
        current, error = trial, trial_error
        converged = error <= tolerance
    if not converged:
        cap = "Newton steps" if newton >= max_newton else "operator applications"
        message = f"not converged: {cap} capped (residual {error:.3g})"
    else:
        message = f"converged in {newton} Newton steps, {applications} applications"
    sx, sy, zx, zy, size, _, _, _, ux, uy = current
    stick = np.zeros_like(contact)
    stick[contact] = size <= bound
    out = []
    for values in (qx, qy, sx, sy):
        full = np.zeros_like(pressure)
        full[contact] = values
        out.append(full)
    creepage = (float(creep[0]), float(creep[1]))
    return SteadySolution(
        *out, ux, uy, stick, creepage, newton, applications, error, converged, message
    )  # fmt: skip


__all__ = ["ORDERS", "SteadySolution", "solve_steady_tangential", "upwind"]
