"""Influence coefficients: closed forms vs quadrature of the single-body point-force solutions,
symmetry, and reciprocity of the assembled operator."""

import math

import numpy as np
import pytest
from scipy import integrate

from solver.bodies.materials import Body, Pair
from solver.numerics.grid import SurfaceGrid
from solver.surface.convolution import SurfaceOperator
from solver.surface.influence import COMPONENTS, surface_kernels

STEEL = Body("elastic", 0.01, 0.01, 210e9, 0.3)
ALUMINIUM = Body("elastic", math.inf, math.inf, 70e9, 0.33)
PAIRS = {
    "steel-aluminium": Pair(STEEL, ALUMINIUM),
    "rigid-steel": Pair(Body("rigid", 0.01, 0.01), STEEL),
    "soft-rubberlike": Pair(Body("elastic", 0.01, 0.01, 5e6, 0.49), Body("elastic", E=1e9, nu=0.0)),
}


def single_body(E, nu, x, y, force):
    """Displacement (ux, uy, uz) of one half-space, z into it, from a unit force at the origin
    acting along ``force`` ("x" tangential or "z" normal). DESIGN §3.2 formulas."""
    r = math.hypot(x, y)
    if force == "z":
        return (
            -(1 + nu) * (1 - 2 * nu) * x / (2 * math.pi * E * r * r),
            -(1 + nu) * (1 - 2 * nu) * y / (2 * math.pi * E * r * r),
            (1 - nu * nu) / (math.pi * E * r),
        )
    return (
        (1 + nu) / (math.pi * E) * ((1 - nu) / r + nu * x * x / r**3),
        (1 + nu) * nu * x * y / (math.pi * E * r**3),
        (1 + nu) * (1 - 2 * nu) * x / (2 * math.pi * E * r * r),
    )


def relative_point(pair, x, y, traction):
    """Body 2 minus body 1 displacement for a unit traction on body 2 ("x", "y" or "z").

    Body 1 is described in its own frame (x, -y, -z) and carries the opposite force."""
    total = np.zeros(3)
    for body, sign in ((pair.body2, 1.0), (pair.body1, -1.0)):
        if body.rigid:
            continue
        if sign > 0:
            xl, yl = x, y
        else:
            xl, yl = x, -y
        if traction == "z":
            # normal force on body 2 along +z; on body 1 it is along -z = +z' (into body 1)
            u = np.array(single_body(body.E, body.nu, xl, yl, "z"))
        elif traction == "x":
            # +x on body 2; body 1 gets -x, which is -x' in its frame
            u = sign * np.array(single_body(body.E, body.nu, xl, yl, "x"))
        else:
            # +y on body 2: rotate the x-solution by 90 degrees in the body's own frame.
            # body 1 gets -y = +y' in its frame.
            ux, uy, uz = single_body(body.E, body.nu, yl, -xl, "x")
            u = np.array([-uy, ux, uz])
        if sign < 0:
            u = np.array([u[0], -u[1], -u[2]])  # back to the global frame
        total += sign * u
    return total


KEYMAP = {
    "zz": (2, "z"),
    "xx": (0, "x"),
    "yy": (1, "y"),
    "xy": (0, "y"),
    "xp": (0, "z"),
    "yp": (1, "z"),
}


def cell_quadrature(pair, name, x0, y0, dx, dy):
    comp, traction = KEYMAP[name]

    def f(eta, xi):
        return relative_point(pair, x0 - xi, y0 - eta, traction)[comp]

    # split at the singular point when it lies in the cell
    xs = sorted({-dx / 2, dx / 2} | ({x0} if abs(x0) < dx / 2 else set()))
    ys = sorted({-dy / 2, dy / 2} | ({y0} if abs(y0) < dy / 2 else set()))
    total = 0.0
    for a, b in zip(xs[:-1], xs[1:], strict=False):
        for c, d in zip(ys[:-1], ys[1:], strict=False):
            total += integrate.dblquad(f, a, b, c, d, epsabs=0, epsrel=1e-11)[0]
    return total


@pytest.mark.validation
@pytest.mark.parametrize("pair_name", list(PAIRS))
@pytest.mark.parametrize(
    "offset", [(0.0, 0.0), (1.0, 0.0), (0.0, -1.0), (1.0, 2.0), (-3.0, 1.0), (0.3, -0.2)]
)
def test_closed_forms_match_quadrature(pair_name, offset, validation):
    pair = PAIRS[pair_name]
    dx, dy = 1e-4, 0.7e-4
    x0, y0 = offset[0] * dx, offset[1] * dy
    kernels = surface_kernels(pair, np.array(x0), np.array(y0), dx, dy)
    scale = abs(float(kernels["zz"]))
    worst = 0.0
    for name in COMPONENTS:
        if pair.dundurs_beta == 0 and name in ("xp", "yp"):
            assert float(kernels[name]) == 0.0
            continue
        reference = cell_quadrature(pair, name, x0, y0, dx, dy)
        assert float(kernels[name]) == pytest.approx(reference, rel=1e-7, abs=1e-9 * scale), name
        worst = max(worst, abs(float(kernels[name]) - reference) / max(abs(reference), scale))
    validation(
        "surface influence coefficients, 6 blocks, 3 material pairs, 6 cell offsets",
        "quadrature of each body's point-force solution over a cell",
        worst,
    )


def test_symmetries_of_the_kernels():
    pair = PAIRS["steel-aluminium"]
    d = 1e-4
    x, y = np.meshgrid(np.arange(-4, 5) * d, np.arange(-4, 5) * d, indexing="ij")
    k = surface_kernels(pair, x, y, d, d)
    flip_x = (slice(None, None, -1), slice(None))
    for name in ("zz", "xx", "yy"):
        np.testing.assert_allclose(k[name], k[name][flip_x], rtol=1e-13)
        np.testing.assert_allclose(k[name], k[name][:, ::-1], rtol=1e-13)
    for name in ("xy", "xp"):
        atol = 1e-12 * np.abs(k[name]).max()
        np.testing.assert_allclose(k[name], -k[name][flip_x], rtol=1e-12, atol=atol)
    atol = 1e-12 * np.abs(k["xp"]).max()
    np.testing.assert_allclose(k["xp"], k["xp"][:, ::-1], rtol=1e-12, atol=atol)
    np.testing.assert_allclose(k["xx"], k["yy"].T, rtol=1e-12)  # x <-> y swap
    np.testing.assert_allclose(k["xp"], k["yp"].T, rtol=1e-12, atol=atol)
    # physics: the body with the larger (1+nu)(1-2nu)/E is pulled further towards the load;
    # here body 2 (aluminium) is, so beta < 0 and the relative u_x on the +x side is negative.
    assert pair.dundurs_beta < 0 and k["xp"][5, 4] < 0


@pytest.mark.validation
@pytest.mark.parametrize("pair_name", list(PAIRS))
def test_assembled_operator_is_symmetric(pair_name, validation):
    """Betti reciprocity: the 3N x 3N map (q_x, q_y, p) -> (u_x, u_y, u_z) is symmetric."""
    grid = SurfaceGrid(5, 4, 1e-4, 0.8e-4)
    op = SurfaceOperator(grid, PAIRS[pair_name], planner="FFTW_ESTIMATE")
    n = grid.nx * grid.ny
    matrix = np.zeros((3 * n, 3 * n))
    for j in range(3 * n):
        e = np.zeros(3 * n)
        e[j] = 1.0
        fields = [e[i * n : (i + 1) * n].reshape(grid.shape) for i in range(3)]
        matrix[:, j] = np.concatenate([u.ravel() for u in op.displacement(*fields)])
    np.testing.assert_allclose(matrix, matrix.T, rtol=1e-10, atol=1e-12 * np.abs(matrix).max())
    eigenvalues = np.linalg.eigvalsh(0.5 * (matrix + matrix.T))
    assert eigenvalues.min() > 0  # positive definite: elastic energy
    validation(
        "assembled surface operator (q_x, q_y, p) -> (u_x, u_y, u_z), 5 x 4 cells, 3 pairs",
        "Betti reciprocity: symmetric, positive definite",
        f"{pair_name}: asymmetry {np.abs(matrix - matrix.T).max() / np.abs(matrix).max():.0e}, "
        f"smallest eigenvalue {eigenvalues.min() / eigenvalues.max():.1e} of the largest",
    )
