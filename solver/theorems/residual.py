r"""Residual stress fields that do not change along a track: every one, from three unknowns.

A load passing again and again along x over a long track leaves, once the body has shaken
down, a residual stress ``rho(y, z)`` that does not depend on x.  Such a field is
self-equilibrated with a traction-free surface ``z = 0`` exactly when (``d_x rho = 0``)::

    d_y rho_xy + d_z rho_xz = 0                      (x: anti-plane)
    d_y rho_yy + d_z rho_yz = 0,  d_y rho_yz + d_z rho_zz = 0        (y, z: in-plane)
    rho_xz = rho_yz = rho_zz = 0  on z = 0

and ``rho_xx`` is free.  Every solution is given by a Prandtl function ``phi`` and an Airy
function ``psi`` of (y, z)::

    rho_xy =  d_z phi      rho_xz = -d_y phi
    rho_yy =  d_zz psi     rho_zz =  d_yy psi     rho_yz = -d_yz psi

with ``phi = psi = d_z psi = 0`` on the surface.  On a cross-section box
``|y| <= Y, 0 <= z <= Z`` with ``phi = psi = d_n psi = 0`` on all of its edges the field
vanishes outside the box with no traction on the box's edges, so it is a residual field of
the whole half-space.  (An eigenstrain ``e* = -C^-1 : rho`` produces ``rho`` with no
displacement, so these are also all the fields the eigenstrain operator can make.)

Discretisation: ``ny x nz`` cells, ``phi`` and ``psi`` on the cell corners (zero on the box's
edges, ``psi`` mirrored across them for ``d_n psi = 0``), ``rho_xx`` per cell.  At a cell's
centre ``rho_yz`` and the derivatives of ``phi`` are central differences of its four corners,
``rho_yy`` and ``rho_zz`` the mean of the corners' three-point second differences: second
order in the cell size.  A *line* contact (the load uniform along y) has fields of z alone:
``rho_xx``, ``rho_yy`` and ``rho_xy`` free per layer, the others zero (Johnson & Jefferis 1963).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

#: Residual components that a line contact's fields can have, in
#: :data:`solver.numerics.tensor.COMPONENTS` order (xx, yy, xy).
LINE_COMPONENTS = (0, 1, 5)
#: Sign each component of :data:`solver.numerics.tensor.COMPONENTS` takes when a field even
#: about the track's centre line is mirrored to y < 0 (rho_yz and rho_xy are odd in y).
MIRROR_SIGNS = np.array([1.0, 1.0, 1.0, -1.0, 1.0, -1.0])


def line_basis(nz: int) -> sp.csr_matrix:
    """Residual fields of a line contact: ``(6 nz, 3 nz)``, rho_xx, rho_yy, rho_xy per layer.

    Row ``c nz + k`` is component c of :data:`~solver.numerics.tensor.COMPONENTS` in layer k.
    """
    rows = [c * nz + k for c in LINE_COMPONENTS for k in range(nz)]
    return sp.csr_matrix((np.ones(3 * nz), (rows, np.arange(3 * nz))), shape=(6 * nz, 3 * nz))


def section_basis(
    ny: int, nz: int, dy: float, dz: float, symmetric: bool = False, surface: bool = False
) -> sp.csr_matrix:
    """Residual fields on an ``ny x nz`` cross-section from ``phi``, ``psi`` and ``rho_xx``.

    Parameters
    ----------
    ny, nz : int
        Cells across (y) and in depth (z), at least 2 each.
    dy, dz : float
        Cell sizes (any length unit; the fields are per unit of the functions' second
        differences, so only the ratio of units matters).
    symmetric : bool
        The cells cover the half ``0 <= y <= Y`` of a field even in y (rho_yz and rho_xy odd,
        as under a load symmetric about the track's centre line): on ``y = 0`` ``phi = 0`` and
        ``d_y psi = 0`` (psi itself free there), instead of the edge conditions.
    surface : bool
        Also the points on the free surface above the cell centres, as a layer 0 before the
        cells': there ``rho_zz = rho_yz = rho_xz = 0``, ``rho_yy = d_zz psi`` (the corners'
        second difference with the mirrored ghost), ``rho_xy = d_z phi`` (one-sided, second
        order) and ``rho_xx`` free.

    Returns
    -------
    scipy.sparse.csr_matrix
        ``(6 ny nl, unknowns)`` (``nl = nz``, or ``nz + 1`` with the surface): the residual
        stress at the points, row ``(c ny + i) nl + k`` for component c, point (i, k), from
        the unknowns ``phi`` on the inner corners, ``psi`` on the inner corners (and those of
        ``y = 0`` if symmetric), each i then k, ``rho_xx`` per cell, then per surface point.
    """
    if ny < 2 or nz < 2:
        raise ValueError(f"a cross-section needs at least 2 x 2 cells, got {ny} x {nz}")
    cells = ny * nz

    def corner_map(mirror: bool, first: int) -> sp.csr_matrix:
        """Corner values (ny + 3) x (nz + 3), one ghost ring, from the unknown corners.

        The unknowns are the corners ``first <= i < ny``, ``0 < k < nz``; the others are zero,
        or (``mirror``, for d_n psi = 0) the ghosts mirror the corners across each edge.
        """
        shape = (ny + 3, nz + 3)  # corner i at index i + 1, ghosts at 0 and ny + 2
        rows, cols, vals = [], [], []
        for i in range(first, ny):
            for k in range(1, nz):
                unknown = (i - first) * (nz - 1) + k - 1
                targets = [(i, k)]
                if mirror:  # psi(-1) = psi(1) across each edge: d_n psi = 0
                    targets += [(-1, k)] if i == 1 else []
                    targets += [(ny + 1, k)] if i == ny - 1 else []
                    targets += [(i, -1)] if k == 1 else []
                    targets += [(i, nz + 1)] if k == nz - 1 else []
                for ti, tk in targets:
                    rows.append((ti + 1) * shape[1] + tk + 1)
                    cols.append(unknown)
                    vals.append(1.0)
        count = (ny - first) * (nz - 1)
        return sp.csr_matrix((vals, (rows, cols)), shape=(shape[0] * shape[1], count))

    def stencil(weights: dict[tuple[int, int], float], layers: int = nz) -> sp.csr_matrix:
        """Values of a stencil over the ghosted corner grid at ``ny x layers`` points.

        Offsets are from each point's lower corner (i, k): a cell's, or (i, 0) for the
        surface point above cell column i (``layers = 1``).
        """
        width = nz + 3
        rows, cols, vals = [], [], []
        for i in range(ny):
            for k in range(layers):
                for (di, dk), w in weights.items():
                    rows.append(i * layers + k)
                    cols.append((i + 1 + di) * width + k + 1 + dk)
                    vals.append(w)
        return sp.csr_matrix((vals, (rows, cols)), shape=(ny * layers, (ny + 3) * width))

    def second(axis: int, step: float) -> dict:
        """Mean over a cell's four corners of the three-point second difference along axis."""
        out: dict[tuple[int, int], float] = {}
        for ci in (0, 1):
            for ck in (0, 1):
                for shift, w in ((-1, 1.0), (0, -2.0), (1, 1.0)):
                    key = (ci + shift, ck) if axis == 0 else (ci, ck + shift)
                    out[key] = out.get(key, 0.0) + 0.25 * w / step**2
        return out

    cross = {(1, 1): 1.0, (1, 0): -1.0, (0, 1): -1.0, (0, 0): 1.0}
    along_z = {(0, 1): 0.5, (1, 1): 0.5, (0, 0): -0.5, (1, 0): -0.5}
    along_y = {(1, 0): 0.5, (1, 1): 0.5, (0, 0): -0.5, (0, 1): -0.5}
    phi = corner_map(mirror=False, first=1)
    psi = corner_map(mirror=True, first=0 if symmetric else 1)
    blocks = [[None] * 3 for _ in range(6)]
    blocks[0][2] = sp.identity(cells)  # rho_xx
    blocks[1][1] = stencil(second(1, dz)) @ psi  # rho_yy = d_zz psi
    blocks[2][1] = stencil(second(0, dy)) @ psi  # rho_zz = d_yy psi
    blocks[3][1] = -stencil({key: w / (dy * dz) for key, w in cross.items()}) @ psi
    blocks[4][0] = -stencil({key: w / dy for key, w in along_y.items()}) @ phi  # rho_xz
    blocks[5][0] = stencil({key: w / dz for key, w in along_z.items()}) @ phi  # rho_xy
    sizes = (phi.shape[1], psi.shape[1], cells)
    for row in blocks:
        for c, size in enumerate(sizes):
            if row[c] is None:
                row[c] = sp.csr_matrix((cells, size))
    interior = sp.bmat(blocks, format="csr")
    if not surface:
        return interior
    # the surface points: rho_yy = d_zz psi, rho_xy = d_z phi (one-sided), rho_xx free
    top = [[sp.csr_matrix((ny, size)) for size in (*sizes, ny)] for _ in range(6)]
    mean_zz = {
        (ci, dk): 0.5 * w / dz**2 for ci in (0, 1) for dk, w in ((-1, 1.0), (0, -2.0), (1, 1.0))
    }
    mean_z = {
        (ci, dk): 0.5 * w / (2.0 * dz)
        for ci in (0, 1)
        for dk, w in ((0, -3.0), (1, 4.0), (2, -1.0))
    }
    top[0][3] = sp.identity(ny)
    top[1][1] = stencil(mean_zz, layers=1) @ psi
    top[5][0] = stencil(mean_z, layers=1) @ phi
    rows = sp.bmat(top, format="csr")
    interior = sp.hstack([interior, sp.csr_matrix((6 * cells, ny))], format="csr")
    # interleave: per component and column i, the surface point then the column's cells
    stacked = sp.vstack([rows, interior], format="csr")
    order = [
        (c * ny + i) if k == 0 else 6 * ny + (c * ny + i) * nz + k - 1
        for c in range(6)
        for i in range(ny)
        for k in range(nz + 1)
    ]
    return stacked[order]


def interpolate_section(
    values: np.ndarray,
    y: np.ndarray,
    z: np.ndarray,
    at_y: np.ndarray,
    at_z: np.ndarray,
    signs: np.ndarray | None = MIRROR_SIGNS,
) -> np.ndarray:
    """A field known at the section's points, bilinear between them: ``(c, ...)`` at points.

    The field of the static program between its points: ``values`` at the points ``(y_j,
    z_k)`` (the half ``y >= 0`` of a field even about ``y = 0``, mirrored with ``signs``), linear
    in y and in z between neighbours and constant past the outermost ones.

    Parameters
    ----------
    values : ndarray
        ``(c, ny, nz)`` the field (any units) at the points, ``c`` components.
    y, z : ndarray
        ``(ny,)``, ``(nz,)`` the points' coordinates, increasing (any length unit); a single y
        (a line contact) gives a field of z alone.
    at_y, at_z : ndarray
        Where to evaluate (broadcast together; ``|at_y|`` is taken).
    signs : ndarray, optional
        ``(c,)`` each component's sign across ``y = 0`` (default :data:`MIRROR_SIGNS`); None:
        no mirror (the field constant below the first y).

    Returns
    -------
    ndarray
        ``(c, *shape)`` the field at the points.
    """
    at_y, at_z = np.broadcast_arrays(np.abs(np.asarray(at_y, float)), np.asarray(at_z, float))
    if y.size > 1 and signs is not None:  # the mirror image makes y = 0 a point between two
        values = np.concatenate([values[:, ::-1] * signs[:, None, None], values], axis=1)
        y = np.concatenate([-y[::-1], y])

    def weights(grid, at):
        if grid.size == 1:
            return np.zeros(at.shape, int), np.zeros(at.shape)
        j = np.clip(np.searchsorted(grid, at) - 1, 0, grid.size - 2)
        t = np.clip((at - grid[j]) / (grid[j + 1] - grid[j]), 0.0, 1.0)
        return j, t

    j, ty = weights(y, at_y)
    k, tz = weights(z, at_z)
    jn = np.minimum(j + 1, y.size - 1)
    kn = np.minimum(k + 1, z.size - 1)
    return (
        (1 - ty) * (1 - tz) * values[:, j, k]
        + ty * (1 - tz) * values[:, jn, k]
        + (1 - ty) * tz * values[:, j, kn]
        + ty * tz * values[:, jn, kn]
    )


__all__ = [
    "LINE_COMPONENTS",
    "MIRROR_SIGNS",
    "interpolate_section",
    "line_basis",
    "section_basis",
]
