r"""Koiter's kinematic shakedown theorem for a load passing along a track: an upper bound.

A body does not shake down under a load factor lambda if some cycle of plastic strain rates,
whose increment accumulated over the cycle is compatible (the strain of a displacement that
satisfies the supports), dissipates less than the elastic stress does work on it (Koiter
1960; Johnson 1985, section 9.5; Ponter, Hearle & Johnson 1985 for a moving contact):

    lambda_K = min  sum_k int D(e_k) dA  /  sum_k int sigma_E(s_k) : e_k dA

over mechanisms is an upper bound of the shakedown limit, for any mechanism admitted.  Here
the load passes along x and a mechanism is, per unit length of track:

- an accumulated displacement ``u(y, z)`` (three components, the same at every x) on the
  cross-section, quadratic on six-node triangles (linear strains: Makrodimopoulos & Martin
  2007, whose plastic incompressibility at the vertices holds everywhere), zero on the box's
  far edges, free on the surface, symmetric about the track's centre line (``u_y = 0`` on
  ``y = 0``; the load is symmetric, so some optimal mechanism is);
- plastic strain rates ``e_k`` released when the load's centre is at ``s_k`` (a finite set
  of instants is a cycle), traceless, linear on each triangle, summing to the strain of u at
  every vertex.

The dissipation of von Mises' material is ``D(e) = sqrt 2 k |e|`` (Frobenius).  ``D`` is
convex, so the triangle's vertex rule ``A / 3 sum_v D(e_v)`` is at least its integral over the
linear field: the program's optimum bounds the mechanism's ratio from above, and the
mechanism's ratio bounds the limit from above.  The work integrals are a seven-point rule of
the closed-form elastic field against the rates' linear shape (exact up to the field's own
smoothness).  Kinematic hardening whose back stress stays within ``|alpha| <= b`` adds
``b |Delta e|`` of the accumulated strain (the dual of the static program's back stress); an
unbounded one (Prager) forces ``Delta e = 0``: only alternating plasticity is left.

The program is a second-order cone program solved by Clarabel, as the static one
(:mod:`.melan`), which it brackets from above on a mesh of its own.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from .melan import DEVIATOR_BASIS, MAX_SOLVER_ITERATIONS

#: Dunavant's seven-point rule on a triangle (degree 5): barycentric points and weights.
_A1, _B1 = 0.059715871789770, 0.470142064105115
_A2, _B2 = 0.797426985353087, 0.101286507323456
QUADRATURE = np.array(
    [
        [1 / 3, 1 / 3, 1 / 3],
        [_A1, _B1, _B1],
        [_B1, _A1, _B1],
        [_B1, _B1, _A1],
        [_A2, _B2, _B2],
        [_B2, _A2, _B2],
        [_B2, _B2, _A2],
    ]
)
QUADRATURE_WEIGHTS = np.array([0.225] + [0.132394152788506] * 3 + [0.125939180544827] * 3)

#: Local edges of a six-node triangle: its midside nodes 3, 4, 5 join these vertices.
EDGES = ((0, 1), (1, 2), (2, 0))

#: What a result's status means.
STATUSES = {
    "optimal": "the smallest ratio over the mechanisms of the mesh and the positions",
    "solver": "the conic solver stopped without a mechanism (its status in the reason)",
}


@dataclass
class KinematicLimit:
    """Koiter's upper bound of a track's shakedown factor and the mechanism that gives it.

    Attributes
    ----------
    factor : float
        lambda_K: the mechanism's dissipation over the elastic field's work on it, per unit of
        the elastic field's load (``p0 / k`` with k = 1); ``inf`` with status ``"solver"``.
    status : str
        A key of :data:`STATUSES`.
    reason : str
        One sentence with the numbers.
    displacement : ndarray
        ``(3, 2 ny + 1, 2 nz + 1)`` the accumulated displacement (x, y, z) on the nodes (corners
        and midsides of the ``ny x nz`` squares, spacing half a cell), scaled so the work is 1.
    dissipation : ndarray
        ``(ny, nz)`` the dissipation per square (sum over the positions; total = factor).
    cones, solver_iterations : int
        Cones of the program and interior-point iterations.
    seconds : float
        Wall time (s).
    """

    factor: float
    status: str
    reason: str
    displacement: np.ndarray
    dissipation: np.ndarray
    cones: int = 0
    solver_iterations: int = 0
    seconds: float = 0.0

    @property
    def converged(self) -> bool:
        """Whether the factor is the discretised program's optimum."""
        return self.status == "optimal"


@dataclass(frozen=True)
class Mesh:
    """Six-node triangles on ``ny x nz`` squares of side h covering ``[0, ny h] x [0, nz h]``.

    Nodes are the points of the half-cell grid, ``(2 ny + 1) x (2 nz + 1)``, numbered
    ``p (2 nz + 1) + q`` for the point ``(p h / 2, q h / 2)``.  Each square is cut along a
    diagonal, alternating between neighbours.

    Attributes
    ----------
    nodes : ndarray
        ``(elements, 6)`` node numbers: the vertices, then the midsides of :data:`EDGES`.
    area : ndarray
        ``(elements,)`` areas.
    gradients : ndarray
        ``(elements, 3, 2)`` gradients (d_y, d_z) of the barycentric coordinates.
    corners : ndarray
        ``(elements, 3, 2)`` the vertices' (y, z).
    square : ndarray
        ``(elements,)`` the square ``i nz + j`` each triangle belongs to.
    """

    ny: int
    nz: int
    h: float
    nodes: np.ndarray
    area: np.ndarray
    gradients: np.ndarray
    corners: np.ndarray
    square: np.ndarray

    @classmethod
    def build(cls, ny: int, nz: int, h: float) -> Mesh:
        """The mesh of ``ny x nz`` squares of side h."""
        columns = 2 * nz + 1
        nodes, corners, square = [], [], []
        for i in range(ny):
            for j in range(nz):
                a, b, c, d = (
                    (2 * i, 2 * j),
                    (2 * i + 2, 2 * j),
                    (2 * i + 2, 2 * j + 2),
                    (
                        2 * i,
                        2 * j + 2,
                    ),
                )
                pairs = [(a, b, c), (a, c, d)] if (i + j) % 2 == 0 else [(a, b, d), (b, c, d)]
                for tri in pairs:
                    mids = [tuple((tri[m][r] + tri[n][r]) // 2 for r in (0, 1)) for m, n in EDGES]
                    nodes.append([p * columns + q for p, q in (*tri, *mids)])
                    corners.append([(p * h / 2, q * h / 2) for p, q in tri])
                    square.append(i * nz + j)
        corners = np.array(corners)
        matrix = np.concatenate([np.ones((len(corners), 1, 3)), corners.transpose(0, 2, 1)], 1)
        inverse = np.linalg.inv(matrix)  # barycentric = inverse @ (1, y, z)
        area = 0.5 * np.abs(np.linalg.det(matrix))
        return cls(ny, nz, h, np.array(nodes), area, inverse[:, :, 1:], corners, np.array(square))

    @property
    def node_count(self) -> int:
        """Nodes of the half-cell grid."""
        return (2 * self.ny + 1) * (2 * self.nz + 1)

    def vertex_gradients(self) -> np.ndarray:
        """``(elements, 3, 6, 2)``: gradient of each node's shape function at each vertex."""
        g = self.gradients
        out = np.zeros((len(g), 3, 6, 2))
        for v in range(3):
            for i in range(3):  # vertex shapes lambda_i (2 lambda_i - 1)
                out[:, v, i] = 3.0 * g[:, v] if i == v else -g[:, i]
            for e, (i, j) in enumerate(EDGES):  # midside shapes 4 lambda_i lambda_j
                if v == i:
                    out[:, v, 3 + e] = 4.0 * g[:, j]
                elif v == j:
                    out[:, v, 3 + e] = 4.0 * g[:, i]
        return out

    def quadrature_points(self) -> np.ndarray:
        """``(elements, 7, 2)`` the seven-point rule's (y, z)."""
        return np.einsum("qv,evr->eqr", QUADRATURE, self.corners)


def strain_operator(mesh: Mesh) -> sp.csr_matrix:
    """The strain of u at each element's vertices: ``(6 * 3 * elements, 3 * nodes)``.

    Rows ``(e * 3 + v) * 6 + c`` for component c of :data:`~solver.numerics.tensor.COMPONENTS`
    (tensor shears; ``e_xx = 0``: nothing changes along x), columns ``r * nodes + n`` for the
    displacement component r (x, y, z) at node n.
    """
    grad = mesh.vertex_gradients()  # (E, 3, 6, 2): d_y, d_z
    count = mesh.node_count
    rows, cols, vals = [], [], []
    # (component, displacement r, derivative d, weight): e_c += weight d_d u_r
    terms = [(1, 1, 0, 1.0), (2, 2, 1, 1.0), (3, 1, 1, 0.5), (3, 2, 0, 0.5), (4, 0, 1, 0.5)]
    terms.append((5, 0, 0, 0.5))
    elements = len(mesh.nodes)
    base = (np.arange(elements)[:, None] * 3 + np.arange(3)[None, :]) * 6  # (E, 3)
    for c, r, d, w in terms:
        for n in range(6):
            rows.append(np.broadcast_to(base + c, (elements, 3)).ravel())
            cols.append(np.repeat(r * count + mesh.nodes[:, n], 3))
            vals.append(w * grad[:, :, n, d].ravel())
    shape = (18 * elements, 3 * count)
    return sp.csr_matrix(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=shape
    )


def kinematic_limit(
    stress,
    positions: np.ndarray,
    width: float,
    depth: float,
    cells: int,
    back_stress_bound: float | None = None,
) -> KinematicLimit:
    """Koiter's upper bound of a load passing along x, by a mechanism on the cross-section.

    Parameters
    ----------
    stress : callable
        ``stress(s, y, z)``: the elastic stress ``(6, ...)`` per unit load at (y, z) with the
        load's centre at x = s (broadcasting), symmetric about ``y = 0`` (``sigma_yz``,
        ``sigma_xy`` odd in y, the others even).
    positions : ndarray
        The instants of the cycle: the load's centre positions s_k at which rates may occur.
    width, depth : float
        The mechanism's box ``0 <= y <= width`` (its mirror image for y < 0), ``z <= depth``,
        in the units of ``stress``'s lengths.
    cells : int
        Squares per unit length (side ``1 / cells``).
    back_stress_bound : float, optional
        b: the largest Frobenius norm of the back stress in units of k (``inf``: Prager's
        unbounded hardening); None for perfect plasticity.

    Returns
    -------
    KinematicLimit
    """
    import clarabel

    start = time.perf_counter()
    h = 1.0 / cells
    mesh = Mesh.build(round(width * cells), round(depth * cells), h)
    elements, count, steps = len(mesh.nodes), mesh.node_count, len(positions)
    vertices = 3 * elements
    # the work of a unit rate at (element, vertex, position): coordinates of int sigma lambda_v
    points = mesh.quadrature_points()  # (E, 7, 2)
    field = stress(
        np.asarray(positions)[:, None, None], points[None, :, :, 0], points[None, :, :, 1]
    )  # (6, P, E, 7)
    coords = np.tensordot(DEVIATOR_BASIS, field, axes=(1, 0))  # (5, P, E, 7)
    weights = QUADRATURE_WEIGHTS[:, None] * QUADRATURE  # (7, 3)
    work = np.einsum("dpeq,qv,e->evpd", coords, weights, mesh.area)  # (E, 3, P, 5)
    work = work.reshape(vertices * steps * 5)
    # the displacement's free components: zero on the far edges, u_y = 0 on y = 0
    columns = 2 * mesh.nz + 1
    p, q = np.divmod(np.arange(count), columns)
    far = (p == 2 * mesh.ny) | (q == 2 * mesh.nz)
    fixed = np.concatenate([far, far | (p == 0), far])
    strain = strain_operator(mesh)[:, ~fixed]
    deviator = sp.kron(sp.identity(vertices), sp.csr_matrix(DEVIATOR_BASIS), format="csr")
    prager = back_stress_bound is not None and not math.isfinite(back_stress_bound)
    bounded = back_stress_bound is not None and not prager
    if prager:  # no accumulated strain: no displacement
        strain = strain[:, :0]
    unknowns = strain.shape[1]
    accumulated = deviator @ strain  # (5 V, U)
    trace = sp.kron(sp.identity(vertices), sp.csr_matrix([[1.0, 1.0, 1.0, 0, 0, 0]])) @ strain
    rates = vertices * steps
    # x = (u, r: 5 per (vertex, position), t: 1 per (vertex, position)[, t_acc per vertex])
    n = unknowns + 6 * rates + (vertices if bounded else 0)
    r0, t0 = unknowns, unknowns + 5 * rates
    # equalities: sum_k r_vk - dev e(u)_v = 0, trace e(u)_v = 0, work . r = 1
    summing = sp.kron(
        sp.identity(vertices), sp.kron(np.ones((1, steps)), sp.identity(5)), format="csr"
    )
    blocks = [
        sp.hstack([-accumulated, summing, sp.csr_matrix((5 * vertices, n - t0))]),
        sp.hstack([trace, sp.csr_matrix((vertices, n - unknowns))]),
        sp.hstack([sp.csr_matrix((1, unknowns)), sp.csr_matrix(work), sp.csr_matrix((1, n - t0))]),
    ]
    if prager:
        blocks = [blocks[0], blocks[2]]
    zero_rows = sum(b.shape[0] for b in blocks)
    # cones (t_vk, r_vk): s = -(t, r)
    cone_rows = np.arange(6 * rates).reshape(rates, 6)
    cone = sp.csr_matrix(
        (
            -np.ones(6 * rates),
            (
                cone_rows.ravel(),
                np.concatenate([t0 + np.arange(rates)[:, None], r0 + 5 * np.arange(rates)[:, None]
                                + np.arange(5)[None, :]], axis=1).ravel(),
            ),
        ),
        shape=(6 * rates, n),
    )  # fmt: skip
    blocks.append(cone)
    cones = [clarabel.ZeroConeT(zero_rows)] + [clarabel.SecondOrderConeT(6)] * rates
    b = np.zeros(zero_rows + 6 * rates)
    b[zero_rows - 1] = 1.0  # the work
    q_cost = np.zeros(n)
    third = np.repeat(mesh.area / 3.0, 3)  # per vertex
    q_cost[t0 : t0 + rates] = math.sqrt(2.0) * np.repeat(third, steps)
    if bounded:  # (t_acc, dev e(u)) per vertex
        acc = sp.hstack([sp.csr_matrix((vertices, n - vertices)), -sp.identity(vertices)])
        pieces = sp.vstack(
            [acc, sp.hstack([-accumulated, sp.csr_matrix((5 * vertices, n - unknowns))])]
        )
        order = np.concatenate(
            [
                np.arange(vertices)[:, None],
                vertices + 5 * np.arange(vertices)[:, None] + np.arange(5)[None, :],
            ],
            axis=1,
        ).ravel()
        blocks.append(pieces.tocsr()[order])
        cones += [clarabel.SecondOrderConeT(6)] * vertices
        b = np.concatenate([b, np.zeros(6 * vertices)])
        q_cost[n - vertices :] = back_stress_bound * third
    a = sp.vstack(blocks, format="csc")
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    settings.max_iter = MAX_SOLVER_ITERATIONS
    solver = clarabel.DefaultSolver(sp.csc_matrix((n, n)), q_cost, a, b, cones, settings)
    out = solver.solve()
    status = str(out.status)
    seconds = time.perf_counter() - start
    empty = np.zeros((3, 2 * mesh.ny + 1, 2 * mesh.nz + 1))
    if status not in ("Solved", "AlmostSolved"):
        return KinematicLimit(
            math.inf, "solver", f"Clarabel: {status} after {out.iterations} iterations",
            empty, np.zeros((mesh.ny, mesh.nz)), rates, int(out.iterations), seconds,
        )  # fmt: skip
    x = np.asarray(out.x)
    displacement = np.zeros(3 * count)
    displacement[~fixed] = x[:unknowns] if unknowns else 0.0
    t = x[t0 : t0 + rates].reshape(elements, 3, steps)
    density = math.sqrt(2.0) * np.einsum("evp,e->e", t, mesh.area / 3.0)
    if bounded:
        density += back_stress_bound * np.einsum(
            "ev,e->e", x[n - vertices :].reshape(elements, 3), mesh.area / 3.0
        )
    dissipation = np.bincount(mesh.square, density, mesh.ny * mesh.nz).reshape(mesh.ny, mesh.nz)
    factor = float(q_cost @ x)
    reason = (
        f"lambda_K = {factor:.5g}: {elements} six-node triangles of {h:.3g}, {steps} positions, "
        f"{rates} cones, {out.iterations} interior-point iterations"
    )
    return KinematicLimit(
        factor, "optimal", reason, displacement.reshape(3, 2 * mesh.ny + 1, 2 * mesh.nz + 1),
        dissipation, rates, int(out.iterations), seconds,
    )  # fmt: skip


__all__ = ["KinematicLimit", "Mesh", "STATUSES", "kinematic_limit", "strain_operator"]
