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
rotations) to a relative residual of :data:`GMRES_TOLERANCE`, right-preconditioned by the
inverse of ``A`` on the whole plane: the upwind difference undone from the leading edge
(:func:`undo_upwind`), then the inverse of Cerruti's symbol
(:func:`~solver.surface.convolution.cerruti_inverse`).  ``A`` is of order zero (``i k_x`` times
``1/|k|``), and so is its inverse: with it the iterations of a linear solve no longer grow with
the mesh (14, 18, 21 against 68, 198, 434 for a circle 16, 32, 64 cells across,
``tests/test_steady.py``).  Both ``A`` and the preconditioner act on the contact's box, one FFT
pair each (:class:`SteadyOperator`).

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

import weakref
from dataclasses import dataclass

import numpy as np

from ..numerics.grid import SurfaceGrid, fft_length
from .convolution import SurfaceOperator, cerruti_inverse, wavenumbers
from .tangential import friction_bound

#: Upwind schemes: first order (CONTACT's) and second order.
ORDERS = (1, 2)
#: Their coefficients: ``-d_x u_i = sum_s c_s u_(i+s) / dx``, s = 0, 1, ...
STENCILS = {1: (1.0, -1.0), 2: (1.5, -2.0, 0.5)}
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
    nx = u.shape[-2]
    for lower in range(1, order + 1):  # each order overwrites the rows its stencil fits
        rows = nx - lower
        out[..., :rows, :] = (
            sum(c * u[..., s : rows + s, :] for s, c in enumerate(STENCILS[lower])) / dx
        )
    return out


def undo_upwind(s: np.ndarray, dx: float, order: int = 1) -> np.ndarray:
    """The ``u`` whose :func:`upwind` difference is ``s`` (along x), zero ahead of the grid.

    First order: the sum from the leading edge, ``u_i = dx sum_{j >= i} s_j``; second order
    the recursion ``u_i = (4 u_{i+1} - u_{i+2} + 2 dx s_i) / 3`` from it, whose roots 1 and 1/3
    give the response ``dx (1 - 3^-(k + 1))`` to ``s`` k rows ahead: that sum less a geometric
    one, ``g_i = (g_(i+1) + s_i) / 3``.  Both along x (the last axis but one) towards the
    trailing edge.
    """
    backwards = s[..., ::-1, :]
    total = np.cumsum(backwards, axis=-2)
    if order == 2:
        carried = np.zeros_like(backwards[..., 0, :])
        for i in range(backwards.shape[-2]):
            carried = (carried + backwards[..., i, :]) / 3.0
            total[..., i, :] -= carried
    return dx * total[..., ::-1, :]


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
    from scipy.linalg import solve_triangular  # here: a case's memory estimate imports us

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


@dataclass(frozen=True)
class _Box:
    """What :class:`SteadyOperator` takes from a box of given spans: kernels, lengths."""

    lengths: tuple[int, int]
    kernels: tuple[np.ndarray, ...]  # D K_t's xx, xy, yy spectra on the padded box
    inverse: tuple[np.ndarray, ...]  # the preconditioner's xx, yy, xy spectra
    diagonal: float  # A's diagonal (1/Pa): the x-x block's value at zero offset


#: Boxes built per operator, by (spans, order); an operator's entries go with it.
_BOXES: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()
#: Boxes kept per operator, the latest (a steady stage's contact keeps its box from one
#: creepage to the next).
_BOXES_KEPT = 2


def _box(operator: SurfaceOperator, spans: tuple[int, int], order: int) -> _Box:
    """The box of ``spans`` cells (0: a periodic axis, whole), built once per operator."""
    kept = _BOXES.setdefault(operator, {})
    key = (spans, order)
    if key not in kept:
        if len(kept) >= _BOXES_KEPT:
            del kept[next(iter(kept))]
        kept[key] = _build_box(operator, spans, order)
    return kept[key]


def _build_box(operator: SurfaceOperator, spans: tuple[int, int], order: int) -> _Box:
    grid = operator.grid
    offsets, lengths = [], []
    for span, length in zip(spans, operator.lengths, strict=True):
        if span == 0:  # a periodic axis: its period, whole
            offsets.append(np.arange(length))
            lengths.append(length)
        else:  # the box's offsets -(n - 1) .. n - 1, zero-padded
            offsets.append(np.arange(1 - span, span))
            lengths.append(fft_length(2 * span - 1))
    (mx, my), (lx, ly), (lx_grid, ly_grid) = offsets, lengths, operator.lengths
    source, target = np.ix_(mx % lx_grid, my % ly_grid), np.ix_(mx % lx, my % ly)
    kernels, diagonal = [], 0.0
    for name in ("xx", "xy", "yy"):  # K_t's kernels on the grid's layout, then D K_t's
        kernel = np.fft.irfft2(operator.kernel_spectrum(name), (lx_grid, ly_grid))
        kernel *= lx_grid * ly_grid  # FFTW's backward transform is unnormalised
        upwinded = (
            sum(c * np.roll(kernel, -shift, axis=0) for shift, c in enumerate(STENCILS[order]))
            / grid.dx
        )
        boxed = np.zeros((lx, ly))
        boxed[target] = upwinded[source]
        kernels.append(np.fft.rfft2(boxed) / (lx * ly))
        if name == "xx":
            diagonal = float(upwinded[0, 0])
    # undo_upwind's response along x (an open axis: steady rolling runs along it):
    # u_i = sum_m h_m s_(i+m), m = 0 .. span - 1
    span = (len(mx) + 1) // 2
    impulse = np.zeros((span, 1))
    impulse[-1] = 1.0
    response = np.zeros(lx)
    response[-np.arange(span) % lx] = undo_upwind(impulse, grid.dx, order)[::-1, 0]
    undo = np.fft.fft(response)[:, None]
    kx, ky = wavenumbers(grid, (lx, ly))
    inverse = tuple(c * undo for c in cerruti_inverse(operator.pair, kx, ky, lx * ly))
    return _Box((lx, ly), tuple(kernels), inverse, diagonal)


class SteadyOperator:
    """``A = -d_x K_t`` on a contact's cells and its whole-plane inverse, one FFT pair each.

    Both act on the contact's box (the smallest block of cells that holds it), zero-padded to
    :func:`~solver.numerics.grid.fft_length` ``(2 n - 1)`` for its n cells along each open
    axis (a periodic axis keeps its period): smaller, and for contacts a power of two across,
    much faster transforms than the grid's.

    ``A``: the upwind stencil (:data:`STENCILS`) is a convolution along x, so ``d_x K_t`` is
    the convolution with the stencil applied to each kernel of ``K_t`` (the kernels at the
    box's offsets, from the operator's): one batched transform pair gives ``A v`` at the
    contact cells.  It equals the upwind difference of ``K_t v`` (:func:`upwind`) there, as
    the stencil stays on the grid on contact cells (the contact keeps off the grid's last
    ``order`` rows).  The preconditioner (:meth:`inverse`) undoes the upwind difference from
    the box's leading edge (the response of :func:`undo_upwind`, a linear convolution along x)
    and applies the inverse of Cerruti's symbol (:func:`~.convolution.cerruti_inverse`) on the
    box's padded lengths, in one transform pair: an approximation of ``A^-1`` of the whole
    plane (order zero, like ``A``).

    Parameters
    ----------
    operator : SurfaceOperator
        The surface operator (its tangential kernels).
    contact : ndarray of bool
        The contact cells on the (nx, ny) grid, at least one.
    order : int
        The upwind difference's order, 1 or 2.
    """

    def __init__(self, operator: SurfaceOperator, contact: np.ndarray, order: int):
        ix, iy = np.nonzero(contact)
        spans, corner = [], []
        for index, cells, length in zip(
            (ix, iy), operator.grid.shape, operator.lengths, strict=True
        ):
            periodic = length < 2 * cells - 1  # a periodic axis: its period, whole
            spans.append(0 if periodic else int(index.max() - index.min()) + 1)
            corner.append(0 if periodic else int(index.min()))
        box = _box(operator, (spans[0], spans[1]), order)  # built once per operator and box
        (lx, ly), self._kernels, self._inverse = box.lengths, box.kernels, box.inverse
        #: ``A``'s diagonal (1/Pa): the x-x block's value at zero offset.
        self.diagonal = box.diagonal
        #: Flat positions of the contact cells in a field of the box's padded lengths.
        self.cells = (ix - corner[0]) * ly + (iy - corner[1])
        padded, spectrum, work, output, self._forward, self._backward = operator.batch_transforms(
            (lx, ly)
        )
        padded[...] = 0.0  # only the contact's cells are written from here
        self._input, self._output = padded.reshape(-1), output.reshape(-1)
        self._spectra, self._work = tuple(spectrum), tuple(work)
        self._positions = self.positions()
        #: Applications of ``A``.
        self.applications = 0

    @staticmethod
    def memory_bytes(grid: SurfaceGrid) -> int:
        """Bytes steady solves on ``grid`` hold at most beside the surface operator.

        The batched buffers of :meth:`SurfaceOperator.batch_transforms` on a box and the kept
        boxes' six spectra each, bounded by the grid's padded lengths (a box's are at most
        those).
        """
        lx, ly = SurfaceOperator.padded_lengths(grid)
        real, spectrum = 8 * lx * ly, 16 * lx * (ly // 2 + 1)
        return 4 * real + 4 * spectrum + _BOXES_KEPT * 6 * spectrum

    def positions(self, order: np.ndarray | None = None) -> np.ndarray:
        """The contact's cells (taken in ``order``) as flat positions in the padded fields.

        The x field's, then the y field's: the ``positions`` of :meth:`apply` and
        :meth:`inverse`.
        """
        cells = self.cells if order is None else self.cells[order]
        return np.concatenate([cells, cells + self._input.size // 2])

    def _transform(self, values: np.ndarray, positions: np.ndarray, blocks: tuple) -> np.ndarray:
        """``blocks`` (xx, xy, yy spectra) applied to (2, m) ``values`` at ``positions``."""
        self._input[positions] = values.ravel()  # the other cells stay zero
        self._forward.execute()
        xx, xy, yy = blocks
        (sx, sy), (wx, wy) = self._spectra, self._work
        np.multiply(xy, sy, out=wx)
        np.multiply(xy, sx, out=wy)
        sx *= xx
        sx += wx
        sy *= yy
        sy += wy
        self._backward.execute()
        return self._output[positions].reshape(2, -1)

    def apply(self, values: np.ndarray, positions: np.ndarray | None = None) -> np.ndarray:
        """``A v`` (1) of shears ``v`` (Pa) on the contact's cells (at :meth:`positions`)."""
        self.applications += 1
        where = self._positions if positions is None else positions
        return self._transform(values, where, self._kernels)

    def inverse(self, values: np.ndarray, positions: np.ndarray | None = None) -> np.ndarray:
        """The preconditioner: shears (Pa) from slips ``values`` (1) on the contact's cells."""
        cxx, cyy, cxy = self._inverse
        where = self._positions if positions is None else positions
        return self._transform(values, where, (cxx, cxy, cyy))


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
    shear_cap: np.ndarray | float | None = None,
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
    shear_cap : ndarray or float, optional
        Orowan's shear limit ``m tau_c`` (Pa) capping the disks
        (:func:`solver.surface.tangential.friction_bound`); None: Coulomb's law alone.

    Returns
    -------
    SteadySolution
    """
    if order not in ORDERS:
        raise ValueError(f"order must be one of {ORDERS}, got {order}")
    contact = pressure > 0.0
    if contact[-order:].any():
        raise ValueError(
            "the contact reaches the grid's leading edge (largest x): the upwind difference "
            "needs free cells ahead of it; widen the grid along x"
        )
    steady = SteadyOperator(operator, contact, order)
    bound = friction_bound(friction_coefficient, pressure, shear_cap)[contact]
    c = np.array([rigid[0][contact], rigid[1][contact]])
    count = bound.size
    r = 1.0 / max(steady.diagonal, 1e-300)  # the scaling: the inverse of A's diagonal
    # the residual's scale: the tractions' size, mu p in slip, ~ r |c| near full stick
    area = count * operator.grid.cell_area
    driven = r * float(np.sqrt(np.mean(c[0] * c[0] + c[1] * c[1])))
    if force is not None:
        driven += float(np.hypot(*force)) / area
    norm = max(min(float(np.sqrt(np.mean(bound * bound))), driven), 1e-300)
    budget = max_iterations

    free = force is not None  # the creepage is two more unknowns
    creep = np.array(initial_creepage if free else (0.0, 0.0), dtype=float)
    if initial is None or not (initial[0].any() or initial[1].any()):
        # no start: the stick solution (A q = creepage - c), cut to the disks
        def stick(y):
            return steady.apply(steady.inverse(y.reshape(2, count))).ravel()

        start = (creep[:, None] - c).ravel()
        y, _ = gmres(stick, start, GMRES_TOLERANCE, GMRES_RESTART, max(budget // 4, 1))
        q = steady.inverse(y.reshape(2, count))
        size = np.hypot(q[0], q[1])
        q *= np.divide(bound, size, out=np.ones_like(size), where=size > bound)
    else:
        q = np.array([initial[0][contact], initial[1][contact]])
    mean_target = np.zeros(2) if force is None else np.asarray(force, dtype=float) / area

    def state(q, creep):
        s = steady.apply(q) + c - creep[:, None]
        z = q - r * s
        size = np.hypot(z[0], z[1])
        scale = np.divide(bound, size, out=np.ones_like(size), where=size > bound)
        res = q - scale * z
        res_f = q.mean(axis=1) - mean_target if free else np.zeros(0)
        total = float(np.sum(res * res) + count * np.sum(res_f * res_f))
        error = float(np.sqrt(total / count)) / norm
        return (s, z, size, res, res_f), error

    current, error = state(q, creep)
    newton, converged, message = 0, error <= tolerance, ""
    while not converged and newton < max_newton and steady.applications < budget:
        newton += 1
        _, z, size, res, res_f = current
        step = _newton_step(
            steady, z, size, res, res_f, bound, r, free, max(budget - steady.applications, 1)
        )
        t = 1.0
        for _ in range(LINE_SEARCH_HALVINGS):
            trial, trial_error = state(q + t * step[0], creep + t * step[1] if free else creep)
            if trial_error < (1.0 - 1e-4 * t) * error:
                break
            t *= 0.5
        q = q + t * step[0]
        if free:
            creep = creep + t * step[1]
        current, error = trial, trial_error
        converged = error <= tolerance
    if not converged:
        cap = "Newton steps" if newton >= max_newton else "operator applications"
        message = f"not converged: {cap} capped (residual {error:.3g})"
    else:
        message = f"converged in {newton} Newton steps, {steady.applications} applications"
    s, _, size, _, _ = current
    stick = np.zeros_like(contact)
    stick[contact] = size <= bound
    out = []
    for values in (q[0], q[1], s[0], s[1]):
        full = np.zeros_like(pressure)
        full[contact] = values
        out.append(full)
    ux, uy = operator.tangential(out[0], out[1])  # K_t q on the grid, for the state
    creepage = (float(creep[0]), float(creep[1]))
    return SteadySolution(
        *out, ux, uy, stick, creepage, newton, steady.applications + 1, error, converged, message
    )  # fmt: skip


def _newton_step(steady, z, size, res, res_f, bound, r, free, budget):
    """One semi-smooth Newton step ``(dq, d creepage)``, dq (2, m) on the contact cells.

    The Newton system ``J dq = -F`` (module docstring), reduced: on a slip cell the step's
    component along ``h = z / |z|`` is ``-h.F`` outright (P's Jacobian annihilates h), which
    leaves the stick cells' two components and the slip cells' one component ``dq_t`` along
    ``t = (-h_y, h_x)``, with J's rows ``r ds = -F`` on stick cells and
    ``(1 - k) dq_t + k r t.ds = -t.F`` on slip cells (``k = mu p / |z|``,
    ``ds = A dq - d creepage``); a prescribed force adds ``mean(dq) = -F_force``.  Solved by
    GMRES with ``A`` (:meth:`SteadyOperator.apply`), right-preconditioned by its whole-plane
    inverse (:meth:`SteadyOperator.inverse`): a reduced residual is read as the slip
    ``ds = residual / r`` (along ``t`` on slip cells) and mapped to the step that makes it.
    The cells are taken stick first, then slip, so that the reduced unknowns are slices.
    """
    count = size.size
    slip = size > bound
    order = np.concatenate([np.flatnonzero(~slip), np.flatnonzero(slip)])
    positions = steady.positions(order)
    ns = count - int(slip.sum())
    end = count + ns  # the reduced unknowns: stick (x, y), slip (t), then the creepage's
    h = z[:, slip] / size[slip]
    tx, ty = -h[1], h[0]
    ratio = bound[slip] / size[slip]
    keep, rx, ry = 1.0 - ratio, ratio * tx, ratio * ty
    res = res[:, order]
    along = -(h[0] * res[0, ns:] + h[1] * res[1, ns:])  # the known component along h
    known = np.zeros((2, count))
    known[:, ns:] = h * along
    target = np.concatenate([-res[:, :ns].ravel(), -(tx * res[0, ns:] + ty * res[1, ns:]), -res_f])

    def expand(w):
        """The step (2, m) on the ordered cells of the reduced unknowns (no known part)."""
        v = np.empty((2, count))
        v[:, :ns] = w[: 2 * ns].reshape(2, ns)
        v[0, ns:] = tx * w[2 * ns : end]
        v[1, ns:] = ty * w[2 * ns : end]
        return v

    def rows(a, v, w):
        """J's reduced rows of ``A dq = a`` for the step ``dq = v`` and ``w``."""
        if free:
            a = a - w[end:, None]
        out = np.empty(w.size)
        out[: 2 * ns] = (r * a[:, :ns]).ravel()
        out[2 * ns : end] = keep * w[2 * ns : end] + r * (rx * a[0, ns:] + ry * a[1, ns:])
        if free:
            out[end:] = v.mean(axis=1)
        return out

    def precondition(y):
        """Reduced unknowns from a reduced residual ``y`` (the creepage's kept as they are)."""
        s = np.empty((2, count))
        s[:, :ns] = y[: 2 * ns].reshape(2, ns) / r
        slipping = y[2 * ns : end] / r
        s[0, ns:] = rx * slipping
        s[1, ns:] = ry * slipping
        v = steady.inverse(s, positions)
        out = y.copy()  # the creepage's unknowns as they are
        out[: 2 * ns] = v[:, :ns].ravel()
        out[2 * ns : end] = keep * y[2 * ns : end] + rx * v[0, ns:] + ry * v[1, ns:]
        return out

    def reduced(y):
        w = precondition(y)
        v = expand(w)
        return rows(steady.apply(v, positions), v, w)

    rhs = target
    if ns < count:
        rhs = target - rows(steady.apply(known, positions), known, np.zeros(target.size))
    y, _ = gmres(reduced, rhs, GMRES_TOLERANCE, GMRES_RESTART, budget)
    w = precondition(y)
    step = np.empty((2, count))
    step[:, order] = expand(w) + known
    return step, w[end:]


__all__ = [
    "ORDERS",
    "STENCILS",
    "SteadyOperator",
    "SteadySolution",
    "gmres",
    "solve_steady_tangential",
    "undo_upwind",
    "upwind",
]
