"""Subsurface stresses from surface tractions: closed forms against quadrature and published
values, the DC-FFT operator against direct sums, Hertz (Johnson 3.45) and Hamilton (1983)."""

import math

import numpy as np
import pytest

from solver.numerics.grid import IndexBox, SurfaceGrid, VolumeGrid
from solver.numerics.tensor import von_mises
from solver.theory.half_space import (
    TRACTIONS,
    hamilton_stress,
    point_force_stress,
    rectangle_stress,
)
from solver.volume.stress import SubsurfaceStressOperator

# ---------------------------------------------------------------------------------------------
# closed forms
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "z, sxx, szz, sxz",
    [(0.1, -0.556117, -0.994294, -0.737147), (0.5, -0.076224, -0.700886, -0.149557),
     (1.0, 0.003973, -0.336108, -0.024229)],
)  # fmt: skip
def test_unit_square_published_values(z, sxx, szz, sxz):
    """Uniform load on [-0.5, 0.5]^2, nu = 0.28, on the axis (issue 4's table).

    sigma_xz is negative under a positive q_x: at the surface sigma_xz = -q_x, since the
    traction on the body is sigma . (-e_z) (z into the body)."""
    p = rectangle_stress(0.0, 0.0, z, 1.0, 1.0, 0.28, "pressure")
    q = rectangle_stress(0.0, 0.0, z, 1.0, 1.0, 0.28, "shear_x")
    assert p[0] == pytest.approx(sxx, abs=1e-6)
    assert p[2] == pytest.approx(szz, abs=1e-6)
    assert q[4] == pytest.approx(sxz, abs=1e-6)


def gauss(a, b, n):
    t, w = np.polynomial.legendre.leggauss(n)
    return 0.5 * (b - a) * t + 0.5 * (b + a), 0.5 * (b - a) * w


@pytest.mark.parametrize("traction", TRACTIONS)
@pytest.mark.parametrize("point", [(0.3, 0.2, 0.4), (1.7, -0.9, 0.3), (-0.45, 0.1, 0.15)])
def test_rectangle_equals_quadrature_of_point_force(traction, point):
    x, y, z = point
    nu, dx, dy = 0.3, 1.0, 0.6
    closed = rectangle_stress(x, y, z, dx, dy, nu, traction)
    xs, wx = gauss(-dx / 2, dx / 2, 300)
    ys, wy = gauss(-dy / 2, dy / 2, 200)
    kernel = point_force_stress(x - xs[:, None], y - ys[None, :], z, nu, traction)
    value = (kernel * (wx[:, None] * wy[None, :])).sum(axis=(1, 2))
    assert np.allclose(closed, value, atol=1e-11)


def test_point_force_balances_the_load():
    """Over a plane z = const the stresses carry the unit force: int sigma_iz dA = -F_i."""
    nu, z = 0.3, 1.0
    phi, w_phi = gauss(0.0, 0.5 * math.pi, 400)  # r = z tan(phi) covers the whole plane
    theta = np.linspace(0.0, 2 * math.pi, 64, endpoint=False)
    r = z * np.tan(phi)[:, None]
    weight = (w_phi * z / np.cos(phi) ** 2)[:, None] * r * (2 * math.pi / 64)
    x, y = r * np.cos(theta), r * np.sin(theta)
    for traction, component in (("pressure", 2), ("shear_x", 4), ("shear_y", 3)):
        total = np.sum(point_force_stress(x, y, z, nu, traction)[component] * weight)
        assert total == pytest.approx(-1.0, abs=1e-9)


def test_rectangle_surface_limit_and_far_field():
    """Just below a loaded cell sigma_iz = -t_i; far away the cell acts as a point force."""
    nu = 0.25
    for traction, component in (("pressure", 2), ("shear_x", 4), ("shear_y", 3)):
        near = rectangle_stress(0.1, -0.2, 1e-6, 1.0, 1.0, nu, traction)
        assert near[component] == pytest.approx(-1.0, abs=1e-5)
        far = rectangle_stress(20.0, -13.0, 9.0, 1.0, 1.0, nu, traction)
        point = point_force_stress(20.0, -13.0, 9.0, nu, traction)
        assert np.allclose(far, point, rtol=2e-3, atol=1e-3 * np.abs(point).max())


def test_shear_y_is_shear_x_rotated():
    nu = 0.3
    a = rectangle_stress(0.4, -1.1, 0.7, 1.0, 0.5, nu, "shear_y")
    b = rectangle_stress(-1.1, 0.4, 0.7, 0.5, 1.0, nu, "shear_x")
    assert np.allclose(a, b[[1, 0, 2, 4, 3, 5]], atol=1e-15)


def test_von_mises():
    uniaxial = np.array([2.0, 0, 0, 0, 0, 0])
    shear = np.array([0, 0, 0, 0, 0, 1.0])
    hydrostatic = np.array([-3.0, -3.0, -3.0, 0, 0, 0])
    assert von_mises(uniaxial) == pytest.approx(2.0)
    assert von_mises(shear) == pytest.approx(math.sqrt(3.0))
    assert von_mises(hydrostatic) == pytest.approx(0.0)


# ---------------------------------------------------------------------------------------------
# Hertz / Hamilton closed form
# ---------------------------------------------------------------------------------------------


def johnson_axis(z, nu):
    """Johnson (1985) eqs 3.45 on the axis, per p0, z in units of a."""
    s_r = -(1 + nu) * (1 - z * np.arctan(1 / z)) + 0.5 / (1 + z * z)
    s_z = -1 / (1 + z * z)
    return s_r, s_z


def test_hamilton_normal_part_matches_johnson_axis():
    z = np.linspace(0.05, 3.0, 40)
    s = hamilton_stress(0 * z, 0 * z, z, 1.0, 1.0, 0.3)
    s_r, s_z = johnson_axis(z, 0.3)
    assert np.allclose(s[0], s_r, atol=1e-13)
    assert np.allclose(s[1], s_r, atol=1e-13)
    assert np.allclose(s[2], s_z, atol=1e-13)
    assert np.abs(s[3:]).max() < 1e-13


def test_hamilton_equals_quadrature_of_point_forces():
    """Closed form (normal and sliding parts) against quadrature over the Hertz disk."""
    nu, mu = 0.3, 0.4
    phi, w_phi = gauss(0.0, 0.5 * math.pi, 300)  # rho = sin(phi) smooths the edge
    theta = np.linspace(0.0, 2 * math.pi, 512, endpoint=False)
    rho = np.sin(phi)[:, None]
    # p(rho) rho drho dtheta = cos(phi)^2 sin(phi) dphi dtheta
    weight = (w_phi * np.cos(phi) ** 2 * np.sin(phi))[:, None] * (2 * math.pi / 512)
    xs, ys = rho * np.cos(theta), rho * np.sin(theta)
    for x, y, z in [(0.3, 0.2, 0.4), (1.2, -0.5, 0.3), (0.0, 0.9, 0.5)]:
        closed = hamilton_stress(x, y, z, 1.0, 1.0, nu, mu)
        normal = point_force_stress(x - xs, y - ys, z, nu, "pressure")
        shear = point_force_stress(x - xs, y - ys, z, nu, "shear_x")
        value = ((normal + mu * shear) * weight).sum(axis=(1, 2))
        assert np.allclose(closed, value, atol=1e-9)


def test_hamilton_surface_tractions():
    """Just below the surface inside the contact: sigma_zz = -p, sigma_xz = -mu p."""
    nu, mu = 0.3, 0.3
    x, y = np.array([0.1, -0.5, 0.3]), np.array([0.2, 0.3, -0.6])
    s = hamilton_stress(x, y, 1e-7, 1.0, 1.0, nu, mu)
    p = np.sqrt(1 - x * x - y * y)
    assert np.allclose(s[2], -p, atol=1e-5)
    assert np.allclose(s[4], -mu * p, atol=1e-5)
    assert np.allclose(s[3], 0.0, atol=1e-5)


# ---------------------------------------------------------------------------------------------
# the DC-FFT operator
# ---------------------------------------------------------------------------------------------


def brute_force(grid, nu, fields, box):
    s = grid.surface
    x, y = s.mesh()
    out = np.zeros((6,) + box.shape)
    for n, (traction, field) in enumerate(fields.items()):
        del n
        for k_out, k in enumerate(range(*box.z)):
            for i_out, i in enumerate(range(*box.x)):
                for j_out, j in enumerate(range(*box.y)):
                    kern = rectangle_stress(
                        s.x[i] - x, s.y[j] - y, grid.z[k], s.dx, s.dy, nu, traction
                    )
                    out[:, i_out, j_out, k_out] += np.einsum("cij,ij->c", kern, field)
    return out


@pytest.mark.parametrize("shape", [(7, 6, 3), (8, 5, 4)])
def test_operator_equals_direct_sum(shape):
    nx, ny, nz = shape
    grid = VolumeGrid(SurfaceGrid(nx, ny, 0.7, 1.1), nz, 0.45)
    rng = np.random.default_rng(1)
    fields = {t: rng.normal(size=(nx, ny)) for t in TRACTIONS}
    op = SubsurfaceStressOperator(grid, 0.27, planner="FFTW_ESTIMATE")
    full = op.stress(fields["pressure"], fields["shear_x"], fields["shear_y"])
    box = IndexBox.full(grid)
    assert np.allclose(full, brute_force(grid, 0.27, fields, box), atol=1e-12)
    sub = IndexBox((1, 4), (2, 5), (1, 3))
    part = op.stress(fields["pressure"], fields["shear_x"], fields["shear_y"], box=sub)
    assert np.allclose(part, full[(slice(None),) + sub.slices], atol=1e-13)
    only_p = op.stress(pressure=fields["pressure"], box=sub)
    assert np.allclose(only_p, brute_force(grid, 0.27, {"pressure": fields["pressure"]}, sub))


def test_box_validation():
    grid = VolumeGrid(SurfaceGrid(4, 4, 1.0, 1.0), 3, 1.0)
    op = SubsurfaceStressOperator(grid, 0.3, planner="FFTW_ESTIMATE")
    with pytest.raises(ValueError, match="box range z"):
        op.stress(np.ones((4, 4)), box=IndexBox((0, 4), (0, 4), (2, 5)))
    with pytest.raises(ValueError, match="at least one"):
        op.stress()


def hertz_grid(n, nz, depth):
    """Grid of side 3 a (a = 1) whose cell (n/2, n/2) is centred on the load axis."""
    return VolumeGrid(SurfaceGrid.centred(n, n, 1.5, 1.5), nz, depth / nz)


def hertz_pressure(grid):
    s = grid.surface
    x, y = s.mesh()
    xc, yc = s.x[s.nx // 2], s.y[s.ny // 2]
    return np.sqrt(np.clip(1 - (x - xc) ** 2 - (y - yc) ** 2, 0, None)), (xc, yc)


@pytest.mark.validation
def test_hertz_axis_and_max_von_mises(validation):
    """Rigid sphere on steel (nu = 0.3), Hertz pressure sampled on 64^2: axis stresses
    (Johnson 3.45) and the maximum von Mises stress 0.620 p_H at z = 0.481 a_H, within 1 %."""
    nu = 0.3
    grid = hertz_grid(64, 96, 2.0)
    p, _ = hertz_pressure(grid)
    op = SubsurfaceStressOperator(grid, nu, planner="FFTW_ESTIMATE")
    c = grid.surface.nx // 2
    axis = op.stress(p, box=IndexBox((c, c + 1), (c, c + 1), (0, grid.nz)))[:, 0, 0, :]
    z = grid.z
    s_r, s_z = johnson_axis(z, nu)
    assert np.abs(axis[2] - s_z).max() < 0.01
    assert np.abs(axis[0] - s_r).max() < 0.01
    assert np.abs(axis[1] - s_r).max() < 0.01
    assert np.abs(axis[2] / s_z - 1).max() < 0.01
    vm = von_mises(axis)
    k = int(vm.argmax())
    # parabola through the discrete maximum and its neighbours
    f0, f1, f2 = vm[k - 1 : k + 2]
    shift = 0.5 * (f0 - f2) / (f0 - 2 * f1 + f2)
    z_max = z[k] + shift * grid.dz
    vm_max = f1 - 0.25 * (f0 - f2) * shift
    assert vm_max == pytest.approx(0.620, rel=0.01)
    assert z_max == pytest.approx(0.481, rel=0.01)
    # the maximum over the whole volume is on the axis (coarser layers)
    coarse = hertz_grid(64, 24, 2.0)
    full = SubsurfaceStressOperator(coarse, nu, planner="FFTW_ESTIMATE").stress(p)
    i, j, _ = np.unravel_index(von_mises(full).argmax(), full.shape[1:])
    assert (i, j) == (c, c)
    validation(
        "subsurface stress of Hertz's pressure sampled on 64^2, 96 layers, nu = 0.3",
        "Johnson eq. 3.45 on the axis; largest von Mises 0.620 p_H at z = 0.481 a",
        f"axis within {max(np.abs(axis[2] - s_z).max(), np.abs(axis[0] - s_r).max()):.1e} p_H; "
        f"von Mises {vm_max:.4f} p_H at z = {z_max:.4f} a, on the axis",
    )


def cell_averaged_hertz(grid, sub=16):
    """Hertz pressure averaged over each cell (sub x sub midpoints), axis at cell (n/2, n/2)."""
    s = grid.surface
    xc, yc = s.x[s.nx // 2], s.y[s.ny // 2]
    t = (np.arange(sub) + 0.5) / sub - 0.5
    x = (s.x[:, None] + t * s.dx - xc).reshape(-1)
    y = (s.y[:, None] + t * s.dy - yc).reshape(-1)
    p = np.sqrt(np.clip(1 - x[:, None] ** 2 - y[None, :] ** 2, 0, None))
    return p.reshape(s.nx, sub, s.ny, sub).mean(axis=(1, 3)), (xc, yc)


@pytest.mark.validation
@pytest.mark.parametrize("plane_offset", [0.0, 0.5])
def test_hamilton_sliding_sphere(plane_offset, validation):
    """Hertz pressure plus q_x = 0.3 p on 64^2 (tractions averaged over the cells): all six
    components on a vertical plane within 2 % of p_H of the closed form (Hamilton 1983).

    The largest error is in the first layer (z = a/24) at the contact edge, where the stress
    resolves the piecewise-constant load; point-sampled tractions give 2.2 % at z = a/32."""
    nu, mu = 0.3, 0.3
    grid = hertz_grid(64, 24, 2.0)
    p, (xc, yc) = cell_averaged_hertz(grid)
    op = SubsurfaceStressOperator(grid, nu, planner="FFTW_ESTIMATE")
    s = grid.surface
    j = s.ny // 2 + int(round(plane_offset / s.dy))
    plane = op.stress(p, mu * p, box=IndexBox((0, s.nx), (j, j + 1), (0, grid.nz)))[:, :, 0, :]
    x = (s.x - xc)[:, None]
    z = grid.z[None, :]
    ref = hamilton_stress(x, s.y[j] - yc, z, 1.0, 1.0, nu, mu)
    error = np.abs(plane - ref).max(axis=(1, 2))
    assert error.max() < 0.02, error
    deep = np.abs(plane - ref)[:, :, 3:].max()  # below z = 0.29 a
    assert deep < 0.005
    validation(
        "sliding sphere: Hertz pressure and q_x = 0.3 p on 64^2 x 24, planes y = 0 and 0.5 a",
        "Hamilton (1983), all six stress components",
        f"y = {plane_offset} a: largest error {error.max():.1e} p_H, {deep:.1e} p_H below 0.29 a",
    )


@pytest.mark.slow
def test_hamilton_error_converges():
    """Doubling the in-plane and depth resolution cuts the largest error below z = a/4 at least
    threefold (the first layer, at depth dz/2, always resolves the pixelated load)."""
    nu, mu = 0.3, 0.3
    errors = []
    for n, nz in ((64, 24), (128, 48)):
        grid = hertz_grid(n, nz, 2.0)
        p, (xc, yc) = cell_averaged_hertz(grid)
        op = SubsurfaceStressOperator(grid, nu, planner="FFTW_ESTIMATE")
        s = grid.surface
        j = s.ny // 2 + int(round(0.5 / s.dy))
        plane = op.stress(p, mu * p, box=IndexBox((0, s.nx), (j, j + 1), (0, nz)))[:, :, 0, :]
        ref = hamilton_stress((s.x - xc)[:, None], s.y[j] - yc, grid.z[None, :], 1, 1, nu, mu)
        errors.append(np.abs(plane - ref)[:, :, grid.z >= 0.25].max())
    assert errors[1] < errors[0] / 3
