"""Anderson mixing: a linear fixed point converges to the exact solution, faster than plain."""

import numpy as np

from solver.numerics.anderson import Anderson


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


def test_segments_mix_in_place_as_one_vector():
    """A vector given as views of an array's pieces (the deviatoric components of a strain)
    is mixed where it lies, as the gathered vector would be: same iterates up to the
    summation order of the dot products, across chunks and with threads."""
    from solver.numerics import anderson

    rng = np.random.default_rng(1)
    n = 3 * anderson.CHUNK + 17  # several chunks per piece
    matrix_diagonal = rng.uniform(-0.5, 0.9, size=5 * n)
    rhs = rng.normal(size=5 * n)
    gathered = Anderson(4)
    pieces = Anderson(4, threads=2)
    x_one = np.zeros(5 * n)
    x_six = np.zeros((6, n))  # the pieces are rows 0-1 and 3-5; row 2 is left alone
    free = [slice(0, 2), slice(3, 6)]
    for _ in range(6):
        f_one = matrix_diagonal * x_one + rhs - x_one
        np.testing.assert_allclose(np.concatenate([x_six[s].ravel() for s in free]), x_one,
                                   rtol=1e-12, atol=1e-12)  # fmt: skip
        x_one = gathered(x_one, f_one)
        f_six = np.zeros((6, n))
        f_six[0:2] = f_one[: 2 * n].reshape(2, n)
        f_six[3:6] = f_one[2 * n :].reshape(3, n)
        new = np.full((6, n), np.nan)
        returned = pieces([x_six[s] for s in free], [f_six[s] for s in free],
                          out=[new[s] for s in free])  # fmt: skip
        assert returned[0].base is new or np.shares_memory(returned[0], new)
        assert np.isnan(new[2]).all()  # only the pieces were written
        new[2] = 0.0
        x_six = new
    exact = rhs / (1.0 - matrix_diagonal)
    assert np.abs(x_one - exact).max() < np.abs(exact).max()  # it is iterating, not idle
