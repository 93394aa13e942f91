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
``|q| <= mu p``, r a positive scaling: the inverse of A's diagonal) by a semi-smooth Newton
method: the Jacobian of P is the identity on stick cells and ``(mu p / |z|)(I - z z^T / |z|^2)``
on slip cells, the step damped by a backtracking line search on ``|F|``.  Stick and slip are the
active sets of the last iterate.  On a slip cell the Newton step's component along ``z`` is
known outright (P's Jacobian annihilates it), so each Newton system is reduced to the stick
cells' two components and the slip cells' one (across ``z``).  The reduced system is solved by
restarted GMRES (:func:`gmres`: classical Gram-Schmidt twice on a preallocated basis, Givens
rotations; one tangential convolution a product) to a relative residual of
:data:`GMRES_TOLERANCE`, right-preconditioned by the inverse of ``A`` on the whole plane: the
upwind difference undone from the leading edge (:func:`undo_upwind`), then the inverse of
Cerruti's symbol (:meth:`~solver.surface.convolution.SurfaceOperator.inverse_tangential`, a
quarter of a convolution).  ``A`` is of order zero (``i k_x`` times ``1/|k|``), and so is its
inverse: with it the iterations of a linear solve no longer grow with the mesh (13-19 against
48-434 for a circle from 16 to 64 cells across).

A prescribed tangential force adds the creepage (xi, eta) as two unknowns and the force's two
equations (as mean tractions over the contact) to the same Newton system.

Convergence: ``rms(F) / T`` over the contact (a relative traction error that vanishes exactly
at the solution) below the tolerance, ``T`` the tractions' scale: the smaller of ``rms(mu p)``
(their size in slip) and ``r rms(c)`` plus a prescribed force's mean traction (their size near
full stick; measured on ``mu p`` alone, a creepage of 1e-7 passed at 1e-6 with C11 0.5 % off).
The Newton iterations and the operator applications are capped, and a solve that reaches a cap
says so (``converged = False``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.linalg import solve_triangular
from scipy.signal import lfilter

from .convolution import SurfaceOperator

#: Upwind schemes: first order (CONTACT's) and second order.
ORDERS = (1, 2)
#: Backtracking halvings of a Newton step before the step is taken as it is.
LINE_SEARCH_HALVINGS = 12
#: GMRES restart length and its relative tolerance (relative to the Newton residual).  The
#: Newton steps are inexact: the convergence test is on the nonlinear residual, and 3e-2 takes
#: 20-30 % fewer applications than 1e-3 (16 to 64 cells across, circle, ellipses and spin) for
#: the same forces to 1e-6.
GMRES_RESTART, GMRES_TOLERANCE = 60, 3e-2


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
        ``rms(F) / T`` over the contact (module docstring).
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

    Along the last axis but one (x of an ``(..., nx, ny)`` field).  The last row (and the last
    two for ``order = 2``) keep the lower order there, or zero on the last row: the contact
    must not touch the grid's leading edge.
    """
    out = np.zeros_like(u)
    out[..., :-1, :] = (u[..., :-1, :] - u[..., 1:, :]) / dx
    if order == 2:
        out[..., :-2, :] = (3.0 * u[..., :-2, :] - 4.0 * u[..., 1:-1, :] + u[..., 2:, :]) / (
            2.0 * dx
        )
    return out


def undo_upwind(s: np.ndarray, dx: float, order: int = 1) -> np.ndarray:
    """The ``u`` whose :func:`upwind` difference is ``s`` (along x), zero ahead of the grid.

    First order: the sum from the leading edge, ``u_i = dx sum_{j >= i} s_j``; second order
    the recursion ``u_i = (4 u_{i+1} - u_{i+2} + 2 dx s_i) / 3`` from it (a stable filter: its
    roots are 1 and 1/3), both along x (the last axis but one) towards the trailing edge.
    """
    backwards = s[..., ::-1, :]
    if order == 1:
        return dx * np.cumsum(backwards, axis=-2)[..., ::-1, :]
    filtered = lfilter([2.0 * dx / 3.0], [1.0, -4.0 / 3.0, 1.0 / 3.0], backwards, axis=-2)
    return filtered[..., ::-1, :]


def gmres(matvec, rhs: np.ndarray, tolerance: float, restart: int, budget: int):
    """Restarted GMRES: ``x`` with ``|rhs - matvec(x)| <= tolerance |rhs|``, from ``x = 0``.

    Arnoldi by classical Gram-Schmidt applied twice (matrix products on a preallocated basis),
    Givens rotations for the small least-squares problem.  Stops at ``budget`` products.

    Returns
    -------
    x : ndarray
        The approximate solution.
    products : int
        Applications of ``matvec``.
    """
    n = rhs.size
    x = np.zeros(n)
    basis = np.empty((restart + 1, n))
    hessenberg = np.zeros((restart, restart))
    residual, beta = rhs, float(np.linalg.norm(rhs))
    target = tolerance * beta
    products = 0
    while beta > target and products < budget:
        basis[0] = residual / beta
        g = [beta] + [0.0] * restart
        cosines, sines = [], []
        for j in range(restart):
            w = matvec(basis[j])
            products += 1
            previous = basis[: j + 1]
            h = previous @ w
            w -= h @ previous
            again = previous @ w
            w -= again @ previous
            h += again
            norm = float(np.linalg.norm(w))
            column = h.tolist()
            column.append(norm)
            for i, (c, s) in enumerate(zip(cosines, sines, strict=True)):
                column[i], column[i + 1] = (
                    c * column[i] + s * column[i + 1],
                    (c * column[i + 1] - s * column[i]),
                )
            d = max(float(np.hypot(column[j], column[j + 1])), 1e-300)
            c, s = column[j] / d, column[j + 1] / d
            cosines.append(c)
            sines.append(s)
            column[j] = d
            g[j], g[j + 1] = c * g[j], -s * g[j]
            hessenberg[: j + 1, j] = column[: j + 1]
            if norm > 0.0:
                basis[j + 1] = w / norm
            if abs(g[j + 1]) <= target or norm == 0.0 or products >= budget:
                break
        k = j + 1
        y = solve_triangular(hessenberg[:k, :k], np.asarray(g[:k]))
        x += y @ basis[:k]
        if abs(g[k]) <= target or products >= budget:
            break
        residual = rhs - matvec(x)
        products += 1
        beta = float(np.linalg.norm(residual))
    return x, products


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
        Relative tolerance of ``rms(F) / T`` (module docstring).
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
    cx, cy = rigid
    cx, cy = cx[contact], cy[contact]
    count = int(contact.sum())
    applications = 0
    field = np.zeros((2, *pressure.shape))  # (x, y) components, zero off the contact
    fx, fy = field

    def apply(vx, vy):
        """``A v`` on the contact cells: ``-d_x K_t v`` (v zero outside)."""
        nonlocal applications
        applications += 1
        fx[contact], fy[contact] = vx, vy
        ux, uy = operator.tangential(fx, fy)
        sx, sy = upwind(np.array((ux, uy)), dx, order)
        return sx[contact], sy[contact], ux, uy

    # the scaling r: the inverse of the operator's diagonal, from one impulse at the centre
    probe = np.zeros_like(pressure)
    i, j = (n // 2 for n in pressure.shape)
    probe[i, j] = 1.0
    ux, _ = operator.tangential(probe, np.zeros_like(probe))
    applications += 1
    r = 1.0 / max(float(upwind(ux, dx, order)[i, j]), 1e-300)
    # the residual's scale: the tractions' size, mu p in slip, ~ r |c| near full stick
    area = count * operator.grid.cell_area
    driven = r * float(np.sqrt(np.mean(cx * cx + cy * cy)))
    if force is not None:
        driven += float(np.hypot(*force)) / area
    norm = max(min(float(np.sqrt(np.mean(bound * bound))), driven), 1e-300)

    def inverse(vx, vy):
        """The preconditioner: ``A^-1 v`` of the whole plane on the contact cells (v zero off).

        The upwind difference undone from the leading edge, then ``K_t^-1`` (periodic FFTs).
        """
        field[...] = 0.0
        fx[contact], fy[contact] = vx, vy
        qx, qy = operator.inverse_tangential(*undo_upwind(field, dx, order))
        return qx[contact], qy[contact]

    free = force is not None  # the creepage is two more unknowns
    creep = np.array(initial_creepage if free else (0.0, 0.0), dtype=float)
    if initial is None or not (initial[0].any() or initial[1].any()):
        # no start: the stick solution (A q = creepage - c), cut to the disks
        start = np.concatenate([creep[0] - cx, creep[1] - cy])

        def stick(y):
            vx, vy = inverse(y[:count], y[count:])
            return np.concatenate(apply(vx, vy)[:2])

        y, _ = gmres(stick, start, GMRES_TOLERANCE, GMRES_RESTART, max(max_iterations // 4, 1))
        qx, qy = inverse(y[:count], y[count:])
        size = np.hypot(qx, qy)
        cut = np.divide(bound, size, out=np.ones_like(size), where=size > bound)
        qx, qy = qx * cut, qy * cut
    else:
        qx, qy = initial[0][contact].copy(), initial[1][contact].copy()
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
        error = float(np.sqrt(total / count)) / norm
        return (sx, sy, zx, zy, size, res_x, res_y, res_f, ux, uy), error

    current, error = state(qx, qy, creep)
    newton, converged, message = 0, error <= tolerance, ""
    while not converged and newton < max_newton and applications < max_iterations:
        newton += 1
        _, _, zx, zy, size, res_x, res_y, res_f, _, _ = current
        step = _newton_step(
            zx, zy, size, res_x, res_y, res_f, bound, r, free, apply, inverse,
            max(max_iterations - applications, 1),
        )  # fmt: skip
        t = 1.0
        for _ in range(LINE_SEARCH_HALVINGS):
            trial, trial_error = state(
                qx + t * step[0], qy + t * step[1], creep + t * step[2] if free else creep
            )
            if trial_error < (1.0 - 1e-4 * t) * error:
                break
            t *= 0.5
        qx, qy = qx + t * step[0], qy + t * step[1]
        if free:
            creep = creep + t * step[2]
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


def _newton_step(zx, zy, size, res_x, res_y, res_f, bound, r, free, apply, inverse, budget):
    """One semi-smooth Newton step ``(dq_x, dq_y, d creepage)``.

    The Newton system ``J dq = -F`` (module docstring), reduced: on a slip cell the step's
    component along ``h = z / |z|`` is ``-h.F`` outright (P's Jacobian annihilates h), which
    leaves the stick cells' two components and the slip cells' one component ``dq_t`` along
    ``t = (-h_y, h_x)``, with J's rows ``r ds = -F`` on stick cells and
    ``(1 - k) dq_t + k r t.ds = -t.F`` on slip cells (``k = mu p / |z|``,
    ``ds = A dq - d creepage``); a prescribed force adds ``mean(dq) = -F_force``.  Solved by
    GMRES with ``apply`` (``A``), right-preconditioned by ``inverse`` (``A^-1`` of the whole
    plane): a reduced residual is read as the slip ``ds = residual / r`` (along ``t`` on slip
    cells) and mapped to the step that makes it.
    """
    count = size.size
    slip = size > bound
    st, sl = np.flatnonzero(~slip), np.flatnonzero(slip)
    ns, nl = st.size, sl.size
    tangent = slice(2 * ns, 2 * ns + nl)  # the slip cells' unknowns dq_t
    hx, hy = zx[sl] / size[sl], zy[sl] / size[sl]
    tx, ty = -hy, hx
    ratio = bound[sl] / size[sl]
    along = -(hx * res_x[sl] + hy * res_y[sl])  # the known component of the step along h
    known_x, known_y = np.zeros(count), np.zeros(count)
    known_x[sl], known_y[sl] = hx * along, hy * along
    target = [-res_x[st], -res_y[st], -(tx * res_x[sl] + ty * res_y[sl])]
    target = np.concatenate([*target, -res_f] if free else target)

    def expand(w):
        """The step on the contact cells of the reduced unknowns (without the known part)."""
        vx, vy = np.zeros(count), np.zeros(count)
        vx[st], vy[st] = w[:ns], w[ns : 2 * ns]
        vx[sl], vy[sl] = tx * w[tangent], ty * w[tangent]
        return vx, vy

    def rows(ax, ay, vx, vy, w):
        """J's reduced rows of ``A dq = (ax, ay)``, the step ``dq = (vx, vy)`` and ``w``."""
        if free:
            ax, ay = ax - w[-2], ay - w[-1]
        out = [r * ax[st], r * ay[st], (1.0 - ratio) * w[tangent]
               + ratio * r * (tx * ax[sl] + ty * ay[sl])]  # fmt: skip
        if free:
            out.append(np.array([vx.mean(), vy.mean()]))
        return np.concatenate(out)

    def precondition(y):
        """Reduced unknowns from a reduced residual ``y`` (the creepage's kept as they are)."""
        sx, sy = np.zeros(count), np.zeros(count)
        sx[st], sy[st] = y[:ns] / r, y[ns : 2 * ns] / r
        sx[sl], sy[sl] = ratio * tx * y[tangent] / r, ratio * ty * y[tangent] / r
        vx, vy = inverse(sx, sy)
        slipping = (1.0 - ratio) * y[tangent] + ratio * (tx * vx[sl] + ty * vy[sl])
        return np.concatenate([vx[st], vy[st], slipping, y[2 * ns + nl :]])

    def reduced(y):
        w = precondition(y)
        vx, vy = expand(w)
        ax, ay, _, _ = apply(vx, vy)
        return rows(ax, ay, vx, vy, w)

    rhs = target
    if nl:
        ax, ay, _, _ = apply(known_x, known_y)
        rhs = target - rows(ax, ay, known_x, known_y, np.zeros(target.size))
    y, _ = gmres(reduced, rhs, GMRES_TOLERANCE, GMRES_RESTART, budget)
    w = precondition(y)
    vx, vy = expand(w)
    return vx + known_x, vy + known_y, w[2 * ns + nl :]


__all__ = ["ORDERS", "SteadySolution", "gmres", "solve_steady_tangential", "undo_upwind", "upwind"]
