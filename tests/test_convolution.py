"""DC-FFT against the direct O(N^2) sum."""

import math

import numpy as np
import pytest

from solver.bodies.materials import Body, Pair
from solver.numerics.grid import SurfaceGrid
from solver.surface.convolution import SurfaceOperator
from solver.surface.influence import surface_kernels

PAIR = Pair(Body("elastic", 0.01, 0.02, 210e9, 0.3), Body("elastic", math.inf, math.inf, 70e9, 0.2))


def direct(grid, pair, qx, qy, p):
    x, y = grid.mesh()
    dx_ = x.ravel()[:, None] - x.ravel()[None, :]
    dy_ = y.ravel()[:, None] - y.ravel()[None, :]
    k = surface_kernels(pair, dx_, dy_, grid.dx, grid.dy)
    qx, qy, p = qx.ravel(), qy.ravel(), p.ravel()
    ux = k["xx"] @ qx + k["xy"] @ qy + k["xp"] @ p
    uy = k["xy"] @ qx + k["yy"] @ qy + k["yp"] @ p
    uz = -k["xp"] @ qx - k["yp"] @ qy + k["zz"] @ p
    return [u.reshape(grid.shape) for u in (ux, uy, uz)]


@pytest.mark.validation
@pytest.mark.parametrize("shape", [(7, 5), (8, 8), (1, 6), (16, 9)])
@pytest.mark.parametrize("planner", ["FFTW_ESTIMATE", "FFTW_MEASURE"])
def test_dcfft_equals_direct_sum(shape, planner, validation):
    rng = np.random.default_rng(1)
    grid = SurfaceGrid(*shape, 1e-5, 1.3e-5)
    op = SurfaceOperator(grid, PAIR, planner=planner)
    fields = [rng.normal(size=shape) * 1e8 for _ in range(3)]
    reference = direct(grid, PAIR, *fields)
    for _ in range(2):  # operator reuse gives identical answers
        got = op.displacement(*fields)
        for g, r in zip(got, reference, strict=True):
            np.testing.assert_allclose(g, r, rtol=0, atol=1e-12 * np.abs(r).max())
    validation(
        "DC-FFT surface convolution, odd, even and one-row grids, two FFTW planners",
        "direct O(N^2) sum of the influence coefficients",
        max(
            float(np.abs(g - r).max() / np.abs(r).max())
            for g, r in zip(got, reference, strict=True)
        ),
    )
    np.testing.assert_allclose(
        op.normal(fields[2]),
        op.displacement(0 * fields[0], 0 * fields[1], fields[2])[2]
        + op.normal_from_shear(0 * fields[0], 0 * fields[1]),
        atol=1e-30,
    )
    ux, uy = op.tangential(fields[0], fields[1])
    px, py = op.tangential_from_pressure(fields[2])
    full = op.displacement(*fields)
    np.testing.assert_allclose(ux + px, full[0], atol=1e-12 * np.abs(full[0]).max())
    np.testing.assert_allclose(uy + py, full[1], atol=1e-12 * np.abs(full[1]).max())
    uz = op.normal(fields[2]) + op.normal_from_shear(fields[0], fields[1])
    np.testing.assert_allclose(uz, full[2], atol=1e-12 * np.abs(full[2]).max())
