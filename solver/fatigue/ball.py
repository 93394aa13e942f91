"""The smallest ball enclosing each of many point sets: the deviatoric path's hypersphere.

Dang Van's and Crossland's criteria measure a stress path by the smallest ball that encloses
its deviatoric stresses (5-D): its radius is the shear amplitude, its centre the stabilised
(mesoscopic) residual stress.  The ball of a set {x_i} is unique; its centre is
c = sum_i lambda_i x_i for the weights lambda (lambda >= 0, sum 1) that maximise the dual

    f(lambda) = sum_i lambda_i ||x_i||^2 - ||sum_i lambda_i x_i||^2 = sum_i lambda_i ||x_i - c||^2,

and f is the squared radius at the optimum.  Any weights bound the radius r*: f(lambda) <= r*^2
<= max_i ||x_i - c||^2 (the ball about c that holds every point), so the relative gap of
the two is a certificate.  The weights are found by Frank and Wolfe's method with away steps
(Yildirim 2008, *SIAM J. Optim.* 19, "Two algorithms for the minimum enclosing ball
problem", algorithm 2), which converges linearly: each iteration either moves weight toward
the farthest point j (step (d_j - f) / (2 d_j), d_i = ||x_i - c||^2) or away from the nearest
point k that has weight (step (f - d_k) / (2 d_k), at most lambda_k / (1 - lambda_k)), each an
exact line search of f, whichever the larger of d_j - f and f - d_k asks.  All sets iterate
together (numpy over the sets), each until its gap is below the tolerance; the radius returned
is max_i ||x_i - c||, every point inside by construction.  Checked against brute force (every
subset of up to d + 1 points, its circumscribed ball) on random paths (``tests/test_fatigue.py``).
"""

from __future__ import annotations

import numpy as np

#: Relative gap (r_upper^2 - r_lower^2) / r_upper^2 at which a set's ball is accepted.
BALL_TOLERANCE = 1e-12
#: Most iterations (a set not within the tolerance by then is reported).
BALL_MAX_ITERATIONS = 20_000


def smallest_balls(
    points: np.ndarray, tolerance: float = BALL_TOLERANCE, max_iterations: int = BALL_MAX_ITERATIONS
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The smallest enclosing ball of each point set (module docstring).

    Parameters
    ----------
    points : numpy.ndarray
        Shape (sets, count, dim): ``count`` points in ``dim`` dimensions per set.
    tolerance : float
        Relative gap of the squared radius's bounds at which a set stops.
    max_iterations : int
        Iteration cap.

    Returns
    -------
    centres : numpy.ndarray
        Shape (sets, dim).
    radii : numpy.ndarray
        Shape (sets,): the largest distance from each centre to its points.
    gaps : numpy.ndarray
        Shape (sets,): each set's relative gap at the end (<= ``tolerance`` when converged).
    """
    points = np.asarray(points, dtype=float)
    sets, count, _ = points.shape
    # a common shift and scale per set keep the arithmetic well conditioned
    middle = points.mean(axis=1, keepdims=True)
    scale = np.abs(points - middle).max(axis=(1, 2), keepdims=True)
    scale = np.where(scale > 0, scale, 1.0)
    x = (points - middle) / scale
    squares = np.einsum("mid,mid->mi", x, x)
    # start: all weight on the point farthest from the first (a diameter's end)
    first = np.einsum("mid,mid->mi", x - x[:, :1], x - x[:, :1]).argmax(axis=1)
    weights = np.zeros((sets, count))
    weights[np.arange(sets), first] = 1.0
    centre = x[np.arange(sets), first].copy()
    gaps = np.ones(sets)
    active = np.arange(sets)
    for _ in range(max_iterations):
        if active.size == 0:
            break
        w, c, pts = weights[active], centre[active], x[active]
        distance = squares[active] - 2.0 * np.einsum("mid,md->mi", pts, c) + (c * c).sum(1)[:, None]
        distance = np.maximum(distance, 0.0)
        lower = (w * distance).sum(axis=1)  # f(lambda), the squared radius's lower bound
        far = distance.argmax(axis=1)
        upper = distance[np.arange(active.size), far]
        gap = (upper - lower) / np.maximum(upper, 1e-300)
        gaps[active] = gap
        going = gap > tolerance
        active, w, c, pts = active[going], w[going], c[going], pts[going]
        distance, lower, far, upper = distance[going], lower[going], far[going], upper[going]
        if active.size == 0:
            break
        rows = np.arange(active.size)
        near = np.where(w > 0, distance, np.inf).argmin(axis=1)
        d_near = distance[rows, near]
        toward = (upper - lower) >= (lower - d_near)
        # toward the farthest point
        alpha = np.where(toward, (upper - lower) / (2.0 * np.maximum(upper, 1e-300)), 0.0)
        # away from the nearest weighted point, at most to its weight's end
        share = w[rows, near]
        cap = np.where(share < 1.0, share / np.maximum(1.0 - share, 1e-300), 0.0)
        beta = np.where(
            toward, 0.0, np.minimum((lower - d_near) / (2.0 * np.maximum(d_near, 1e-300)), cap)
        )
        w *= (1.0 - alpha + beta)[:, None]
        w[rows, far] += alpha
        w[rows, near] -= beta
        w[rows, near] = np.where(~toward & (beta >= cap), 0.0, w[rows, near])
        c = (1.0 - alpha + beta)[:, None] * c + alpha[:, None] * pts[rows, far]
        c -= beta[:, None] * pts[rows, near]
        weights[active], centre[active] = w, c
    centres = middle[:, 0, :] + scale[:, 0, :] * centre
    radii = np.linalg.norm(points - centres[:, None, :], axis=2).max(axis=1)
    return centres, radii, gaps
