"""Anderson mixing: a linear fixed point converges to the exact solution, faster than plain."""

import numpy as np

from solver.anderson import Anderson


def iterations_to_converge(memory, matrix, rhs, tolerance=1e-10):
    x, mixer = np.zeros(rhs.size), Anderson(memory)
    for k in range(5000):
        f = matrix @ x + rhs - x
        if np.linalg.norm(f) < tolerance:
            return k, x
        x = mixer(x, f)
    return None, x


def test_anderson_accelerates_a_slow_contraction():
    rng = np.random.default_rng(0)
    n = 200
    q, _ = np.linalg.qr(rng.normal(size=(n, n)))
    matrix = q @ np.diag(np.linspace(-0.5, 0.97, n)) @ q.T
    rhs = rng.normal(size=n)
    exact = np.linalg.solve(np.eye(n) - matrix, rhs)
    plain, x_plain = iterations_to_converge(0, matrix, rhs)
    mixed, x_mixed = iterations_to_converge(5, matrix, rhs)
    assert plain is not None and mixed is not None
    assert mixed < plain / 2
    np.testing.assert_allclose(x_mixed, exact, atol=1e-8)
    np.testing.assert_allclose(x_plain, exact, atol=1e-8)


def test_an_overflowed_history_restarts_instead_of_raising():
    """An iteration that overflowed (inf in the residuals) must not stop the solve with a
    linear-algebra error: the history restarts and the step is a plain fixed-point step."""
    mixer = Anderson(memory=3)
    x = np.ones(8)
    mixer(x, np.full(8, 0.5))
    huge = np.full(8, np.inf)
    out = mixer(x + 0.5, huge)  # the history's difference overflows
    assert mixer.restarts == 1
    np.testing.assert_array_equal(out, x + 0.5 + huge)  # the plain step, reported by the caller
    finite = mixer(x, np.full(8, 0.25))
    assert np.isfinite(finite).all()
