r"""Melan's static shakedown theorem for a load passing along a track, solved directly.

The body shakes down under repeated passes of a load if one time-independent residual stress
field ``rho`` keeps ``lambda sigma_E(x - s) + rho`` inside the yield surface at every point and
every load position s (Melan 1938; Johnson 1985, section 9.5).  For a long track ``rho`` does
not depend on x (:mod:`.residual`), so the condition is, at every point (y, z) of the
cross-section and every position s of the load along the track,

    | dev(lambda sigma_E(s, y, z) + rho(y, z)) - alpha(y, z) | <= sqrt(2) k(y, z)

(von Mises, ``k = sigma_Y / sqrt 3``, ``|.|`` the Frobenius norm), with ``alpha = 0`` for
perfect plasticity, and for kinematic hardening whose back stress saturates a time-independent
back stress of at most ``|alpha| <= b`` (Weichert & Gross-Weege 1988; Pycko & Maier 1995).  The
largest lambda over all residual fields (and back stresses) is the *static shakedown limit*: a
lower bound of the true limit in general, the limit itself in the theory.  With the elastic
field per unit peak pressure, lambda is ``p0 / k``.

The program is a second-order cone program: maximise lambda over lambda, the residual field's
unknowns (and the back stress), one five-dimensional cone per (cell, position).  It is solved
by Clarabel (an interior-point conic solver: exact cones, no polyhedral approximation, sparse;
Apache-2.0, maintained by the Oxford control group).  Positions are added as they are needed:
each cell's extreme positions first (the strongest, and where a deviator coordinate is largest
or smallest along the track) and the unloaded body, then, round after round, each cell's worst
position where the last solution yields, until none does.  The factor reported is certified
afterwards: the largest lambda for which the program's residual field keeps every cell within
yield at every position (the positive root of a quadratic per cell and position).

:func:`pointwise_limit` gives an upper bound of the same limit: at one point, no residual field
can do better than the best constant shift of the point's own stress path.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

#: Orthonormal basis of deviators in :data:`solver.numerics.tensor.COMPONENTS` order: the
#: five rows give coordinates whose Euclidean norm is the deviator's Frobenius norm.
DEVIATOR_BASIS = np.array(
    [
        [1.0 / math.sqrt(2.0), -1.0 / math.sqrt(2.0), 0.0, 0.0, 0.0, 0.0],
        [1.0 / math.sqrt(6.0), 1.0 / math.sqrt(6.0), -2.0 / math.sqrt(6.0), 0.0, 0.0, 0.0],
        [0.0, 0.0, 0.0, math.sqrt(2.0), 0.0, 0.0],
        [0.0, 0.0, 0.0, 0.0, math.sqrt(2.0), 0.0],
        [0.0, 0.0, 0.0, 0.0, 0.0, math.sqrt(2.0)],
    ]
)
#: A (cell, position) pair is added when its certified factor is below the program's by more
#: than this fraction (the conic solver's own tolerances are 1e-8).
YIELD_TOLERANCE = 1e-6
#: Rounds of adding positions before the program gives up (status ``"rounds"``).
MAX_ROUNDS = 12
#: Interior-point iterations of one conic solve (Clarabel's own default).
MAX_SOLVER_ITERATIONS = 200
#: A cell binds when some position brings it within this fraction of the yield radius.
BINDING = 1e-4

#: What a result's status means.
STATUSES = {
    "optimal": "the largest factor; every position and the unloaded body checked",
    "box_too_small": "the elastic field at the factor yields outside the box: enlarge the box",
    "rounds": f"positions still yield after {MAX_ROUNDS} rounds of adding them",
    "solver": "the conic solver stopped without a solution (its status in the reason)",
}


@dataclass
class StaticLimit:
    """Melan's factor for a moving load, the residual field that proves it, and how found.

    Attributes
    ----------
    factor : float
        lambda at the limit (per unit of the elastic field's load; ``p0 / k`` for a field per
        unit peak pressure and k = 1), certified for the residual field returned: with any
        status a lower bound on the cells (status ``"solver"``: first yield, no residual).
    status : str
        A key of :data:`STATUSES`; only ``"optimal"`` is a converged limit.
    reason : str
        One sentence with the numbers.
    residual : ndarray
        ``(6, ny, nz)`` residual stress (units of k) of the program's solution.
    back_stress : ndarray or None
        ``(5, ny, nz)`` deviator coordinates of the back stress (units of k), kinematic only.
    binding : ndarray
        ``(ny, nz)`` bool: cells at the yield radius (within :data:`BINDING`) at some position.
    rounds, cones, solver_iterations : int
        Rounds of adding positions, cones of the last program, interior-point iterations
        summed over the rounds.
    seconds : float
        Wall time of the program (s).
    edge_ratio : float
        Largest ``factor |dev sigma_E| / (sqrt 2 k)`` outside the box (must be <= 1).
    history : list of (int, int, float)
        (round, cones, program's factor) per round.
    """

    factor: float
    status: str
    reason: str
    residual: np.ndarray
    back_stress: np.ndarray | None
    binding: np.ndarray
    rounds: int = 0
    cones: int = 0
    solver_iterations: int = 0
    seconds: float = 0.0
    edge_ratio: float = 0.0
    history: list = field(default_factory=list)

    @property
    def converged(self) -> bool:
        """Whether the factor is the discretised program's limit."""
        return self.status == "optimal"


def deviatoric_coordinates(stress: np.ndarray) -> np.ndarray:
    """The five orthonormal deviator coordinates of ``(6, ...)`` stresses: ``(5, ...)``."""
    return np.tensordot(DEVIATOR_BASIS, stress, axes=(1, 0))


def certified_factors(load: np.ndarray, shift: np.ndarray, radius: np.ndarray) -> np.ndarray:
    """Largest lambda with ``|lambda d + r| <= R`` per position and cell.

    Parameters
    ----------
    load : ndarray
        ``(5, positions, cells)`` deviator coordinates d of the elastic field.
    shift : ndarray
        ``(5, cells)`` the time-independent part r (residual minus back stress).
    radius : ndarray
        ``(cells,)`` yield radius R.

    Returns
    -------
    ndarray
        ``(positions, cells)``: the positive root of ``a l^2 + 2 b l + c = 0``; ``inf`` where
        the load vanishes, 0 where the shift alone yields.
    """
    a = np.einsum("dpc,dpc->pc", load, load)
    b = np.einsum("dpc,dc->pc", load, shift)
    c = np.einsum("dc,dc->c", shift, shift) - radius**2
    with np.errstate(divide="ignore", invalid="ignore"):
        roots = (-b + np.sqrt(np.maximum(b * b - a * c, 0.0))) / a
    roots = np.where(a > 0.0, roots, np.inf)
    return np.where(c > 0.0, 0.0, roots)


def static_limit(
    elastic: np.ndarray,
    basis: sp.spmatrix,
    shear_yield: np.ndarray | float = 1.0,
    back_stress_bound: float | None = None,
    edge: np.ndarray | None = None,
    max_rounds: int = MAX_ROUNDS,
) -> StaticLimit:
    """The largest lambda with ``|dev(lambda sigma_E + rho) - alpha| <= sqrt 2 k`` (Melan).

    Parameters
    ----------
    elastic : ndarray
        ``(6, positions, ny, nz)`` elastic stress of the load at each position, per unit of
        the load (lambda multiplies it), on the cross-section's cells.
    basis : scipy.sparse matrix
        ``(6 ny nz, unknowns)`` residual fields (:mod:`.residual`), rows component-major.
    shear_yield : float or ndarray
        k per cell (``(ny, nz)``) or for all, in the units of ``elastic`` times lambda.
    back_stress_bound : float, optional
        b: the largest Frobenius norm ``|alpha|`` of the deviatoric back stress, in the units
        of k (the yield radius is sqrt 2 k); ``inf``: unbounded (linear kinematic hardening);
        None for perfect plasticity.
    edge : ndarray, optional
        ``(6, ...)`` elastic stress outside the box (where the residual field is zero) over
        the positions: checked at the factor (status ``"box_too_small"`` if it yields).
    max_rounds : int
        Rounds of adding positions.

    Returns
    -------
    StaticLimit
    """
    import clarabel

    start = time.perf_counter()
    _, positions, ny, nz = elastic.shape
    cells = ny * nz
    # unit columns: the stress functions' second differences scale as 1 / cell^2
    scale = abs(basis).max(axis=0).toarray().ravel()
    basis = sp.csr_matrix(basis @ sp.diags(1.0 / np.where(scale > 0.0, scale, 1.0)))
    unknowns = basis.shape[1]
    radius = math.sqrt(2.0) * np.broadcast_to(np.asarray(shear_yield, float), (ny, nz)).ravel()
    load = deviatoric_coordinates(elastic).reshape(5, positions, cells)
    residual = [  # (cells, unknowns) per deviator coordinate
        sp.csr_matrix(
            sum(DEVIATOR_BASIS[d, c] * basis[c * cells : (c + 1) * cells] for c in range(6))
        )
        for d in range(5)
    ]
    kinematic = back_stress_bound is not None
    # the first round: per cell, the strongest position, those where a deviator coordinate is
    # largest or smallest along the track, and the unloaded body (the last "position")
    active = np.zeros((positions + 1, cells), bool)
    every = np.arange(cells)
    active[np.argmax(np.einsum("dpc,dpc->pc", load, load), axis=0), every] = True
    for coordinate in load:
        active[np.argmax(coordinate, axis=0), every] = True
        active[np.argmin(coordinate, axis=0), every] = True
    active[positions] = True
    load = np.concatenate([load, np.zeros((5, 1, cells))], axis=1)
    history, iterations = [], 0
    for round_ in range(1, max_rounds + 1):
        pairs = np.argwhere(active)
        x, status, its = _solve(
            clarabel, load, residual, radius, pairs, back_stress_bound if kinematic else None
        )
        iterations += its
        if x is None:  # the certified factor of no residual field: first yield on the cells
            elastic_limit = float(certified_factors(load, np.zeros((5, cells)), radius).min())
            return StaticLimit(
                elastic_limit, "solver",
                f"Clarabel: {status} in round {round_}; the factor is first yield's "
                f"{elastic_limit:.5g} (no residual field)",
                np.zeros((6, ny, nz)), None, np.zeros((ny, nz), bool), round_, len(pairs),
                iterations, time.perf_counter() - start, history=history,
            )  # fmt: skip
        program = float(x[0])
        unknown = x[1 : 1 + unknowns]
        shift = np.stack([r @ unknown for r in residual])
        alpha = x[1 + unknowns :].reshape(5, cells) if kinematic else None
        if kinematic:
            shift = shift - alpha
        history.append((round_, len(pairs), program))
        roots = certified_factors(load, shift, radius)
        factor = float(roots.min())
        short = (roots < program * (1.0 - YIELD_TOLERANCE)) & ~active
        if not short.any():
            break
        worst = np.where(short, -roots, -np.inf)
        found = np.flatnonzero(short.any(axis=0))
        active[np.argmax(worst[:, found], axis=0), found] = True
    residual_field = (basis @ unknown).reshape(6, ny, nz)
    back = alpha.reshape(5, ny, nz) if kinematic else None
    if short.any():
        return StaticLimit(
            factor, "rounds",
            f"{int(short.sum())} (cell, position) pairs still short of the program's factor "
            f"{program:.5g} after {max_rounds} rounds (certified {factor:.5g})",
            residual_field, back, np.zeros((ny, nz), bool), max_rounds, len(pairs),
            iterations, time.perf_counter() - start, history=history,
        )  # fmt: skip
    total = factor * load + shift[:, None, :]
    norm = np.sqrt(np.einsum("dpc,dpc->pc", total, total)) / radius
    binding = (norm >= 1.0 - BINDING).any(axis=0).reshape(ny, nz)
    edge_ratio = 0.0
    if edge is not None:
        coords = deviatoric_coordinates(edge)
        edge_ratio = factor * float(np.sqrt(np.sum(coords * coords, axis=0)).max())
        edge_ratio /= float(radius.min())
    status = "optimal"
    reason = (
        f"lambda = {factor:.5g} after {round_} round(s), {len(pairs)} cones, "
        f"{int(binding.sum())} binding cell(s)"
    )
    if edge_ratio > 1.0:
        status = "box_too_small"
        reason += f"; the elastic field alone yields outside the box ({edge_ratio:.3g} of k)"
    return StaticLimit(
        factor, status, reason, residual_field, back, binding, round_, len(pairs),
        iterations, time.perf_counter() - start, edge_ratio, history,
    )  # fmt: skip


def _solve(clarabel, load, residual, radius, pairs, bound):
    """One conic program over the active (position, cell) pairs: (x, status, iterations).

    ``x = (lambda, unknowns[, alpha])``; each pair's cone is ``s = b - A x`` with
    ``s = (R, lambda d + r - alpha)``; a back stress adds a cone ``(b, alpha)`` per cell.
    """
    count = len(pairs)
    cells = radius.size
    position, cell = pairs[:, 0], pairs[:, 1]
    extra = 5 * cells if bound is not None else 0
    n = 1 + residual[0].shape[1] + extra
    blocks = []
    for d in range(5):
        parts = [sp.csr_matrix(-load[d, position, cell][:, None]), -residual[d][cell]]
        if extra:
            parts.append(
                sp.csr_matrix(
                    (np.ones(count), (np.arange(count), d * cells + cell)), shape=(count, extra)
                )
            )
        blocks.append(sp.hstack(parts, format="csr"))
    stacked = sp.vstack([sp.csr_matrix((count, n)), *blocks], format="csr")
    order = (np.arange(6)[None, :] * count + np.arange(count)[:, None]).ravel()
    a = stacked[order]
    b = np.zeros(6 * count)
    b[0::6] = radius[cell]
    cones = [clarabel.SecondOrderConeT(6)] * count
    if extra and math.isfinite(bound):  # |alpha| <= bound per cell (else free)
        rows = (np.arange(cells)[:, None] * 6 + 1 + np.arange(5)[None, :]).ravel()
        cols = (
            1
            + residual[0].shape[1]
            + (np.arange(5)[None, :] * cells + np.arange(cells)[:, None]).ravel()
        )
        back = sp.csr_matrix((-np.ones(5 * cells), (rows, cols)), shape=(6 * cells, n))
        a = sp.vstack([a, back], format="csr")
        extra_b = np.zeros(6 * cells)
        extra_b[0::6] = bound
        b = np.concatenate([b, extra_b])
        cones = cones + [clarabel.SecondOrderConeT(6)] * cells
    q = np.zeros(n)
    q[0] = -1.0
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    settings.max_iter = MAX_SOLVER_ITERATIONS
    solver = clarabel.DefaultSolver(sp.csc_matrix((n, n)), q, a.tocsc(), b, cones, settings)
    out = solver.solve()
    status = str(out.status)
    if status not in ("Solved", "AlmostSolved"):
        return None, status, int(out.iterations)
    return np.asarray(out.x), status, int(out.iterations)


def pointwise_limit(
    path: np.ndarray,
    directions: np.ndarray | None = None,
    shear_yield: float = 1.0,
    back_stress_bound: float | None = None,
) -> float:
    """Upper bound at one point: the largest factor some constant shift keeps within yield.

    Whatever the residual field, at one point it is one constant tensor: the factor can be no
    larger than the largest lambda for which some constant shift ``c`` keeps the point's path
    of deviators within yield, ``|lambda d(s) + c - alpha| <= sqrt 2 k`` at every position,
    the shift restricted to ``directions`` where the point constrains the residual field (on
    the free surface ``rho_zz = rho_xz = rho_yz = 0``) and ``|alpha| <= b``.  A small SOCP.

    Parameters
    ----------
    path : ndarray
        ``(6, positions)`` elastic stress at the point along the track, per unit load.
    directions : ndarray, optional
        ``(6, m)`` stress tensors spanning the shifts allowed (default: any).
    shear_yield : float
        k.
    back_stress_bound : float, optional
        b, as in :func:`static_limit`; None for perfect plasticity.

    Returns
    -------
    float
        The factor's upper bound at this point; ``inf`` if the conic solver fails (no bound).
    """
    import clarabel

    d = deviatoric_coordinates(path)  # (5, P)
    shifts = np.eye(5) if directions is None else deviatoric_coordinates(directions)
    m, count = shifts.shape[1], d.shape[1]
    back = 5 if back_stress_bound is not None else 0
    n = 1 + m + back
    # x = (lambda, w, alpha): cones s = b - A x = (R, lambda d_s + S w - alpha)
    a = np.zeros((6 * count, n))
    b = np.zeros(6 * count)
    b[0::6] = math.sqrt(2.0) * shear_yield
    for k in range(5):
        a[1 + k :: 6, 0] = -d[k]
        a[1 + k :: 6, 1 : 1 + m] = -shifts[k]
        if back:
            a[1 + k :: 6, 1 + m + k] = 1.0
    cones = [clarabel.SecondOrderConeT(6)] * count
    if back and math.isfinite(back_stress_bound):  # (b, alpha); else free
        extra = np.zeros((6, n))
        extra[1:, 1 + m :] = -np.eye(5)
        a = np.vstack([a, extra])
        b = np.concatenate([b, [back_stress_bound, 0, 0, 0, 0, 0]])
        cones = cones + [clarabel.SecondOrderConeT(6)]
    q = np.zeros(n)
    q[0] = -1.0
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    solver = clarabel.DefaultSolver(sp.csc_matrix((n, n)), q, sp.csc_matrix(a), b, cones, settings)
    out = solver.solve()
    if str(out.status) not in ("Solved", "AlmostSolved"):
        return math.inf
    return float(out.x[0])


def likeliest_cells(elastic: np.ndarray, binding: np.ndarray, count: int) -> list[tuple[int, int]]:
    """Cells (j, k) below the surface whose stress paths are widest, of all and of the binding.

    A path of diameter D needs a ball of radius D/2 at least: the widest paths are the
    likeliest to bind the pointwise bound.  Layer 0 is the surface (not among them).
    """
    coords = deviatoric_coordinates(elastic).reshape(5, elastic.shape[1], -1)
    width = np.zeros(coords.shape[2])
    for p in range(coords.shape[1]):
        gap = coords - coords[:, p : p + 1, :]
        width = np.maximum(width, np.sqrt(np.einsum("dpc,dpc->pc", gap, gap)).max(axis=0))
    layers = elastic.shape[3]
    inside = np.arange(width.size) % layers > 0
    bound = binding.ravel() & inside
    ranked = [
        *np.argsort(np.where(inside, -width, np.inf))[:count],
        *np.argsort(np.where(bound, -width, np.inf))[: min(count, int(bound.sum()))],
    ]
    return [(int(c // layers), int(c % layers)) for c in dict.fromkeys(ranked)]


#: Shifts a point on the free surface allows: rho_xx, rho_yy, rho_xy (traction-free).
SURFACE_SHIFTS = np.array(
    [
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 0.0],
        [0.0, 0.0, 0.0],
        [0.0, 0.0, 0.0],
        [0.0, 0.0, 1.0],
    ]
)


__all__ = [
    "DEVIATOR_BASIS",
    "STATUSES",
    "SURFACE_SHIFTS",
    "StaticLimit",
    "certified_factors",
    "deviatoric_coordinates",
    "likeliest_cells",
    "pointwise_limit",
    "static_limit",
]
