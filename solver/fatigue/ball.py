"""The smallest ball enclosing each of many point sets: the deviatoric path's hypersphere.

Dang Van's and Crossland's criteria measure a stress path by the smallest ball that encloses
its deviatoric stresses (5-D): its radius is the shear amplitude, its centre the stabilised
(mesoscopic) residual stress.  The ball of a finite set is unique, and it is the ball of at
most d + 1 of its points (its support), which lie on its surface with the centre in their
convex hull.

The algorithm inserts the farthest point (as Bădoiu and Clarkson's core sets, solved
exactly): start from the ball on two far-apart points; while a point lies outside the current
ball, add the farthest one to the support and solve the support's ball exactly.  A point
outside the ball of a set lies on the surface of the ball of the set and the point, so only
the support's subsets joined by the new point are tried: for each, the ball centred in their
affine hull through all of them (a small Gram system), the smallest that holds the whole
support taken.  The radius grows at every insertion, so the loop ends, in a few insertions
for a stress path (its support is two or three points).  Every set is solved at once (numpy
over the sets); the radius returned is max_i ||x_i - c||.  Checked against brute force (every
subset of up to d + 1 points) on random sets (``tests/test_fatigue.py``).
"""

from __future__ import annotations

import itertools

import numpy as np

#: Relative slack of "inside the ball" (round-off of the distances).
BALL_SLACK = 1e-10
#: Most insertions (each adds a point to a set's support; a stress path needs a few).
BALL_MAX_INSERTIONS = 200


def _subsets(size: int) -> list[tuple[int, ...]]:
    """The subsets of range(size), the empty one included."""
    return [s for k in range(size + 1) for s in itertools.combinations(range(size), k)]


def _centres(points: np.ndarray) -> np.ndarray:
    """The centre, in their affine hull, of the ball through each row's points (n, k, d).

    A solve of their Gram system with a tiny ridge: nearly dependent points of a smooth path
    give a centre too, whose ball is then measured over every point (:func:`_insert`).
    """
    if points.shape[1] == 1:
        return points[:, 0].copy()
    edges = points[:, 1:] - points[:, :1]  # (n, k-1, d)
    gram = np.einsum("nid,njd->nij", edges, edges)
    right = 0.5 * np.einsum("nid,nid->ni", edges, edges)
    # a ridge of 1e-13 of the trace: the solve of a nearly singular Gram stays finite
    ridge = 1e-13 * np.trace(gram, axis1=1, axis2=2) + 1e-300
    gram = gram + ridge[:, None, None] * np.eye(gram.shape[1])
    weights = np.linalg.solve(gram, right[..., None])[..., 0]
    return points[:, 0] + np.einsum("ni,nid->nd", weights, edges)


def smallest_balls(
    points: np.ndarray, max_insertions: int = BALL_MAX_INSERTIONS
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The smallest enclosing ball of each point set (module docstring).

    Parameters
    ----------
    points : numpy.ndarray
        Shape (sets, count, dim): ``count`` points in ``dim`` dimensions per set.
    max_insertions : int
        Most insertions per set.

    Returns
    -------
    centres : numpy.ndarray
        Shape (sets, dim).
    radii : numpy.ndarray
        Shape (sets,): the largest distance from each centre to its points.
    excess : numpy.ndarray
        Shape (sets,): how far the farthest point lies outside the ball solved on the support,
        relative to its radius (<= the slack when the set is solved; else the loop was cut).
    """
    points = np.asarray(points, dtype=float)
    sets, count, dim = points.shape
    middle = points.mean(axis=1, keepdims=True)
    scale = np.abs(points - middle).max(axis=(1, 2), keepdims=True)
    scale = np.where(scale > 0, scale, 1.0)
    x = (points - middle) / scale
    rows = np.arange(sets)
    # the start: a far point from the first, and the far point from it
    a = np.einsum("mid,mid->mi", x - x[:, :1], x - x[:, :1]).argmax(axis=1)
    b = np.einsum("mid,mid->mi", x - x[rows, a][:, None], x - x[rows, a][:, None]).argmax(axis=1)
    support = np.full((sets, dim + 1), -1)  # indices of each set's support (-1: none)
    support[:, 0], support[:, 1] = a, b
    centre = 0.5 * (x[rows, a] + x[rows, b])
    radius2 = 0.25 * np.einsum("md,md->m", x[rows, a] - x[rows, b], x[rows, a] - x[rows, b])
    excess = np.zeros(sets)
    active = rows
    for _ in range(max_insertions):
        distance = np.einsum("mid,mid->mi", x[active] - centre[active][:, None],
                             x[active] - centre[active][:, None])  # fmt: skip
        far = distance.argmax(axis=1)
        worst = distance[np.arange(active.size), far]
        excess[active] = np.sqrt(worst / np.maximum(radius2[active], 1e-300)) - 1.0
        outside = worst > radius2[active] * (1.0 + BALL_SLACK) ** 2
        active, far = active[outside], far[outside]
        if active.size == 0:
            break
        centre[active], radius2[active], support[active] = _insert(
            x[active], support[active], far, dim
        )
    centres = middle[:, 0, :] + scale[:, 0, :] * centre
    radii = np.linalg.norm(points - centres[:, None, :], axis=2).max(axis=1)
    return centres, radii, np.maximum(excess, 0.0)


def _insert(x: np.ndarray, support: np.ndarray, new: np.ndarray, dim: int):
    """The ball of each set's support and its new point (module docstring)."""
    n = x.shape[0]
    rows = np.arange(n)
    held = support >= 0  # (n, dim + 1)
    members = np.where(held, support, 0)
    best_radius = np.full(n, np.inf)
    best_centre = np.zeros((n, dim))
    best_support = np.full_like(support, -1)
    candidates = np.concatenate([members, new[:, None]], axis=1)  # the support and the new point
    every = np.concatenate([held, np.ones((n, 1), dtype=bool)], axis=1)
    points = x[rows[:, None], candidates]  # (n, dim + 2, d): the support and the new point
    for subset in _subsets(dim + 1):
        if len(subset) > dim:  # with the new point: at most d + 1 points on the surface
            continue
        chosen = list(subset) + [dim + 1]  # the new point always on the surface
        valid = held[:, list(subset)].all(axis=1) if subset else np.ones(n, dtype=bool)
        centre = _centres(points[:, chosen])
        # the ball about that centre that holds the support and the new point
        gap = points - centre[:, None]
        radius2 = np.where(every, np.einsum("nkd,nkd->nk", gap, gap), 0.0).max(axis=1)
        better = valid & (radius2 < best_radius * (1.0 - 1e-12))
        best_radius = np.where(better, radius2, best_radius)
        best_centre[better] = centre[better]
        picked = np.full((n, dim + 1), -1)
        picked[:, : len(chosen)] = candidates[:, chosen]
        best_support[better] = picked[better]
    return best_centre, best_radius, best_support
