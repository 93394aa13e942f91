"""Residual fields of eigenstrains: cuboid closed forms, the FFT operator against direct sums,
and the half-space checks of DESIGN §6 (uniform layer, centre of dilatation, equilibrium, free
surface, the two routes to the surface displacement)."""

import itertools
import math

import numpy as np
import pytest

from solver.numerics.grid import SurfaceGrid, VolumeGrid
from solver.numerics.tensor import deviator
from solver.surface.influence import cell_integral
from solver.theory.half_space import rectangle_stress
from solver.volume.cuboid import (
    FIRST,
    FOURTH,
    SECOND,
    THIRD,
    cuboid_displacement,
    cuboid_stress,
    potentials,
)
from solver.volume.eigenstrain import EigenstrainOperator

E, NU = 210e9, 0.3
G = E / (2 * (1 + NU))
LAME = 2 * G * NU / (1 - 2 * NU)
PAIRS = [(0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1)]
WEIGHTS = np.array([1.0, 1.0, 1.0, 2.0, 2.0, 2.0])

# ---------------------------------------------------------------------------------------------
# cuboid closed forms
# ---------------------------------------------------------------------------------------------


def kernel_derivative(name, x):
    """Derivative of 1/r ("d...") or r ("p...") at offsets x (3, ...), written out."""
    idx = ["xyz".index(ch) for ch in name[1:]]
    r2 = x[0] ** 2 + x[1] ** 2 + x[2] ** 2
    r = np.sqrt(r2)

    def delta(i, j):
        return 1.0 if i == j else 0.0

    if name[0] == "d" and len(idx) == 1:
        return -x[idx[0]] / r**3
    if name[0] == "d":
        i, j = idx
        return (3 * x[i] * x[j] - delta(i, j) * r2) / r**5
    if len(idx) == 3:
        i, j, k = idx
        return (
            -(delta(i, j) * x[k] + delta(i, k) * x[j] + delta(j, k) * x[i]) / r**3
            + 3 * x[i] * x[j] * x[k] / r**5
        )
    i, j, k, m = idx
    pairs = [((i, j), (k, m)), ((i, k), (j, m)), ((i, m), (j, k))]
    out = -sum(delta(*a) * delta(*b) for a, b in pairs) / r**3
    out = out + 3 * sum(delta(*a) * x[b[0]] * x[b[1]] + delta(*b) * x[a[0]] * x[a[1]]
                        for a, b in pairs) / r**5  # fmt: skip
    return out - 15 * x[i] * x[j] * x[k] * x[m] / r**7


def test_potential_derivatives_match_quadrature():
    half = (0.5, 0.7, 0.4)
    point = np.array([1.3, -0.4, 0.9])
    t, w = np.polynomial.legendre.leggauss(40)
    nodes = [a * t for a in half]
    weights = [a * w for a in half]
    grid = np.meshgrid(*nodes, indexing="ij")
    weight = weights[0][:, None, None] * weights[1][None, :, None] * weights[2][None, None, :]
    offsets = np.array([point[i] - grid[i] for i in range(3)])
    names = ["d" + k for k in SECOND + FIRST] + ["p" + k for k in FOURTH + THIRD]
    closed = potentials(*point, half, names)
    for name in names:
        value = (kernel_derivative(name, offsets) * weight).sum()
        assert closed[name] == pytest.approx(value, abs=1e-11), name


def test_potential_identities():
    """Inside: Phi_,kk = -4 pi; everywhere: Psi_,ijkk = 2 Phi_,ij and Psi_,ikk = 2 Phi_,i."""
    half = (0.5, 0.6, 0.4)
    names = ["d" + k for k in SECOND + FIRST] + ["p" + k for k in FOURTH + THIRD]
    for point, inside in (((0.1, -0.2, 0.3), True), ((1.1, 0.4, -0.7), False)):
        v = potentials(*point, half, names)
        laplace = v["dxx"] + v["dyy"] + v["dzz"]
        assert laplace == pytest.approx(-4 * math.pi if inside else 0.0, abs=1e-12)
        for i, j in itertools.combinations_with_replacement("xyz", 2):
            psi = sum(v["p" + "".join(sorted(i + j + k + k))] for k in "xyz")
            assert psi == pytest.approx(2 * v["d" + "".join(sorted(i + j))], abs=1e-12)
        for i in "xyz":
            psi = sum(v["p" + "".join(sorted(i + k + k))] for k in "xyz")
            assert psi == pytest.approx(2 * v["d" + i], abs=1e-12)


@pytest.mark.parametrize("point", [(1.3, -0.4, 0.9), (0.2, 0.1, -1.5), (0.1, -0.2, 0.15)])
def test_cuboid_stress_is_hooke_of_displacement(point):
    """sigma = C:(grad_s u - e*): the stress kernels agree with the displacement kernels."""
    half = (0.5, 0.6, 0.4)
    inside = all(abs(p) < a for p, a in zip(point, half, strict=True))
    for component in range(6):
        e = np.zeros(6)
        e[component] = 1.0
        grad = np.zeros((3, 3))
        h = 1e-5
        for j in range(3):
            step = np.zeros(3)
            step[j] = h
            up = cuboid_displacement(*(np.array(point) + step), half, 1.0, NU, e)
            down = cuboid_displacement(*(np.array(point) - step), half, 1.0, NU, e)
            grad[:, j] = (up - down) / (2 * h)
        strain = 0.5 * (grad + grad.T)
        if inside:
            i, j = PAIRS[component]
            strain[i, j] -= 1.0
            if i != j:
                strain[j, i] -= 1.0
        lam = 2 * NU / (1 - 2 * NU)
        sigma = lam * np.trace(strain) * np.eye(3) + 2 * strain
        expected = [sigma[i, j] for i, j in PAIRS]
        assert np.allclose(cuboid_stress(*point, half, 1.0, NU, e), expected, atol=1e-8)


def test_cuboid_kernel_reciprocity():
    """w_ij D_ij,mn = w_mn D_mn,ij (Betti, with tensor weights of the shear components)."""
    for point in [(1.3, -0.4, 0.9), (0.1, 0.2, -0.3)]:
        d = np.array(
            [cuboid_stress(*point, (0.5, 0.5, 0.5), 1.0, NU, np.eye(6)[m]) for m in range(6)]
        )
        weighted = WEIGHTS[:, None] * d.T
        assert np.allclose(weighted, weighted.T, atol=1e-14)


def test_cuboid_far_field_is_a_centre_of_dilatation():
    e, volume = 1e-3, 1.0
    point = np.array([7.0, -4.0, 5.0])
    r = np.linalg.norm(point)
    u = cuboid_displacement(*point, (0.5, 0.5, 0.5), G, NU, [e, e, e, 0, 0, 0])
    expected = (1 + NU) / (4 * math.pi * (1 - NU)) * e * volume * point / r**3
    assert np.allclose(u, expected, rtol=1e-4)


# ---------------------------------------------------------------------------------------------
# the operator
# ---------------------------------------------------------------------------------------------


def operator(grid, planner="FFTW_ESTIMATE"):
    return EigenstrainOperator(grid, E, NU, planner=planner)


def test_operator_equals_direct_sums():
    """Source + image (3-D FFT), Boussinesq correction, and both displacement routes equal their
    definitions summed cell by cell."""
    grid = VolumeGrid(SurfaceGrid(6, 5, 0.8, 1.1), 3, 0.6)
    s = grid.surface
    nx, ny, nz = grid.shape
    half = (s.dx / 2, s.dy / 2, grid.dz / 2)
    rng = np.random.default_rng(3)
    eps = rng.normal(size=(6, nx, ny, nz)) * 1e-3
    op = operator(grid)
    stress, (ux, uy, uz) = op.evaluate(eps)
    direct = op.surface_displacement(eps, method="direct")

    x, y = s.mesh()
    image = eps * np.array([1, 1, 1, -1, -1, 1.0])[:, None, None, None]
    ref = np.zeros_like(stress)
    pressure = np.zeros((nx, ny))
    u_sum = np.zeros((3, nx, ny))
    for i, j, k in itertools.product(range(nx), range(ny), range(nz)):
        dx, dy = x - s.x[i], y - s.y[j]
        for zz, e, sign in ((grid.z[k], eps, 1.0), (-grid.z[k], image, -1.0)):
            del sign
            field = cuboid_stress(dx[..., None], dy[..., None], grid.z - zz, half, G, NU,
                                  e[:, i, j, k])  # fmt: skip
            ref += field
            pressure += cuboid_stress(dx, dy, 0.0 - zz, half, G, NU, e[:, i, j, k])[2]
        u_sum += 2 * cuboid_displacement(dx, dy, -grid.z[k], half, G, NU, eps[:, i, j, k])
    for i, j, k in itertools.product(range(nx), range(ny), range(nz)):
        kern = rectangle_stress(s.x[i] - x, s.y[j] - y, grid.z[k], s.dx, s.dy, NU, "pressure")
        ref[:, i, j, k] += (kern * pressure).sum(axis=(1, 2))
    assert np.allclose(stress, ref, rtol=0, atol=1e-12 * np.abs(ref).max())

    # direct route: 2 u^source(z = 0) + Boussinesq displacement of the correction pressure
    ox = x[:, :, None, None] - x[None, None]
    oy = y[:, :, None, None] - y[None, None]
    kz = (1 - NU**2) / (math.pi * E) * cell_integral("inv_r", ox, oy, s.dx, s.dy)
    kt = -(1 + NU) * (1 - 2 * NU) / (2 * math.pi * E)
    kx = kt * cell_integral("x_r2", ox, oy, s.dx, s.dy)
    ky = kt * cell_integral("y_r2", ox, oy, s.dx, s.dy)
    expected = [
        u_sum[0] + (kx * pressure).sum(axis=(2, 3)),
        u_sum[1] + (ky * pressure).sum(axis=(2, 3)),
        (kz * pressure).sum(axis=(2, 3)),
    ]
    for got, want in zip(direct, expected, strict=True):
        assert np.allclose(got, want, rtol=0, atol=1e-12 * np.abs(want).max())

    # reciprocal route: u_k = sum sigma^(k)_ij e_ij dz (stress of unit traction k on the cell)
    for got, traction in zip((ux, uy, uz), ("shear_x", "shear_y", "pressure"), strict=True):
        want = np.zeros((nx, ny))
        for i, j, k in itertools.product(range(nx), range(ny), range(nz)):
            kern = rectangle_stress(s.x[i] - x, s.y[j] - y, grid.z[k], s.dx, s.dy, NU, traction)
            want += (kern * (WEIGHTS * eps[:, i, j, k])[:, None, None]).sum(axis=0) * grid.dz
        assert np.allclose(got, want, rtol=0, atol=1e-12 * np.abs(want).max())


def test_shape_is_checked():
    op = operator(VolumeGrid(SurfaceGrid(4, 4, 1.0, 1.0), 2, 1.0))
    with pytest.raises(ValueError, match="eigenstrain must have the plastic box.s shape"):
        op.stress(np.zeros((6, 4, 4, 3)))
    with pytest.raises(ValueError, match="unknown method"):
        op.surface_displacement(np.zeros((6, 4, 4, 2)), method="magic")


@pytest.fixture(scope="module")
def thin_layer():
    """A 36 x 36 patch (W = 18 cells) of uniform eigenstrain, h = 2 layers of dz = 0.05: h/W
    = 1/180, so edge effects (of relative size ~ h/W) stay below 1 % at the patch centre."""
    grid = VolumeGrid(SurfaceGrid(48, 48, 1.0, 1.0), 4, 0.05)
    op = operator(grid)
    mask = np.zeros(grid.shape)
    mask[6:42, 6:42, :2] = 1.0
    return grid, op, mask, 2 * grid.dz


@pytest.mark.validation
def test_uniform_layer_stress(thin_layer, validation):
    grid, op, mask, h = thin_layer
    e = np.array([1.0, -0.4, 0.7, 0.3, 0.5, 0.2]) * 1e-3
    stress = op.stress(e[:, None, None, None] * mask)
    centre = stress[:, 20:28, 20:28, :2]
    sxx = -2 * G / (1 - NU) * (e[0] + NU * e[1])
    syy = -2 * G / (1 - NU) * (e[1] + NU * e[0])
    sxy = -2 * G * e[5]  # the in-plane shear eigenstrain is constrained too
    assert np.allclose(centre[0], sxx, rtol=0.01)
    assert np.allclose(centre[1], syy, rtol=0.01)
    assert np.allclose(centre[5], sxy, rtol=0.01)
    # sigma_zz = sigma_xz = sigma_yz = 0 in and below the layer, away from the edges
    assert np.abs(stress[2:5, 20:28, 20:28, :]).max() < 1e-3 * abs(sxx)
    worst = max(np.abs(centre[k] / value - 1).max() for k, value in ((0, sxx), (1, syy), (5, sxy)))
    validation(
        "eigenstrain in a thin surface layer (48^2 x 4)",
        "the constrained layer's sigma_xx, sigma_yy, sigma_xy; sigma_iz = 0",
        f"in-plane within {100 * worst:.2f} %, sigma_iz "
        f"{np.abs(stress[2:5, 20:28, 20:28, :]).max() / abs(sxx):.1e} sigma_xx",
    )


def test_uniform_layer_surface_displacement(thin_layer):
    """u_z = -h e_zz and u_x = -2 h e_xz, u_y = -2 h e_yz at the patch centre (reciprocal
    route).  In-plane eigenstrain of a finite patch lifts the centre by
    h (1 + 2 nu)/2 (e_xx + e_yy) (Betti: the plane integral of the Boussinesq sigma_xx is
    -(1 + 2 nu)/2); the laterally unbounded layer's nu/(1 - nu) is not the limit of finite
    patches, because the edge forces of any finite patch load the substrate."""
    grid, op, mask, h = thin_layer
    centre = (slice(22, 26), slice(22, 26))  # the in-plane part still varies 1 % at +-4 cells
    e_zz, e_xz, e_yz, e_xx, e_yy = 0.7e-3, 0.5e-3, 0.3e-3, 1.0e-3, -0.4e-3
    for e, check in (
        ([0, 0, e_zz, 0, 0, 0], lambda u: u[2] / (-h * e_zz)),
        ([0, 0, 0, e_yz, e_xz, 0], lambda u: u[0] / (-2 * h * e_xz)),
        ([0, 0, 0, e_yz, e_xz, 0], lambda u: u[1] / (-2 * h * e_yz)),
        ([e_xx, e_yy, 0, 0, 0, 0], lambda u: u[2] / (-h * (1 + 2 * NU) / 2 * (e_xx + e_yy))),
    ):
        u = op.surface_displacement(np.asarray(e)[:, None, None, None] * mask)
        ratio = check([component[centre] for component in u])
        assert np.allclose(ratio, 1.0, atol=0.01), ratio.mean()
    u = op.surface_displacement(np.array([e_xx, e_yy, 0, 0, 0, 0])[:, None, None, None] * mask)
    unbounded = -h * NU / (1 - NU) * (e_xx + e_yy)
    assert u[2][centre].mean() / unbounded > 1.8  # DESIGN §6's formula is the unbounded layer


@pytest.mark.validation
def test_centre_of_dilatation(validation):
    """A cube of side 1 (2 x 2 x 2 cells) of dilatation e at depth c = 4 against Mindlin and
    Cheng's nucleus: u_z = -(1+nu) e V c/(pi (r^2+c^2)^1.5), u_r = (1+nu) e V r/(...)."""
    d, c, e = 0.5, 4.0, 1e-3
    grid = VolumeGrid(SurfaceGrid(64, 64, d, d), 16, d)
    s = grid.surface
    inside_xy = np.abs(s.x) < 0.5
    inside_z = np.abs(grid.z - c) < 0.5
    eps = np.zeros((6,) + grid.shape)
    for k in range(3):
        eps[k][np.ix_(inside_xy, inside_xy, inside_z)] = e
    op = operator(grid)
    x, y = s.mesh()
    r = np.hypot(x, y)
    scale = (1 + NU) * e * 1.0 / (math.pi * (r**2 + c**2) ** 1.5)
    uz_ref, ur_ref = -scale * c, scale * r
    far = r >= 2.0
    ux, uy, uz = op.surface_displacement(eps)
    u_r = (ux * x + uy * y) / np.maximum(r, 1e-300)
    assert np.abs(uz[far] / uz_ref[far] - 1).max() < 0.02
    assert np.abs(u_r[far] / ur_ref[far] - 1).max() < 0.02
    validation(
        "eigenstrain: a cube of dilatation at depth 4 sides, surface displacement at r >= 2",
        "Mindlin & Cheng's centre of dilatation",
        f"u_z {100 * np.abs(uz[far] / uz_ref[far] - 1).max():.2f} %, u_r "
        f"{100 * np.abs(u_r[far] / ur_ref[far] - 1).max():.2f} %",
    )
    # the direct route misses the correction pressure outside the grid (side 32 = 8 depths):
    # a slowly decaying error, within a few % of the peak displacement
    ux, uy, uz = op.surface_displacement(eps, method="direct")
    u_r = (ux * x + uy * y) / np.maximum(r, 1e-300)
    assert np.abs(u_r[far] - ur_ref[far]).max() < 0.02 * np.abs(ur_ref).max()
    assert np.abs(uz[far] - uz_ref[far]).max() < 0.05 * np.abs(uz_ref).max()


def gaussian_blob(grid, width=2.0, depth=4.0):
    s = grid.surface
    x, y = s.mesh()
    z = grid.z
    g = np.exp(-(x[..., None] ** 2 + y[..., None] ** 2 + (z - depth) ** 2) / (2 * width**2))
    e = np.array([1.0, -0.5, 0.3, 0.4, -0.6, 0.2]) * 1e-3
    return e[:, None, None, None] * g[None]


def blob_case(d):
    """Grid of side 24 and depth 10 with spacing d, the Gaussian blob, and its fields."""
    n, nz = int(round(24 / d)), int(round(10 / d))
    grid = VolumeGrid(SurfaceGrid(n, n, d, d), nz, d)
    eps = gaussian_blob(grid)
    op = operator(grid)
    stress, u = op.evaluate(eps)
    return grid, stress, u, op.surface_displacement(eps, method="direct")


@pytest.fixture(scope="module")
def blob_cases():
    return {d: blob_case(d) for d in (1.0, 0.5)}


def test_equilibrium_and_free_surface(blob_cases):
    """Central-difference divergence of the residual stress and its normal traction at z = 0
    (extrapolated from the first two layers) vanish to discretisation accuracy (second order)."""
    width = 2.0
    residual = {}
    for d, (_, stress, _, _) in blob_cases.items():
        full = np.zeros((3, 3) + stress.shape[1:])
        for c, (i, j) in enumerate(PAIRS):
            full[i, j] = full[j, i] = stress[c]
        div = sum(np.gradient(full[:, j], d, axis=1 + j) for j in range(3))
        inner = (slice(None), slice(2, -2), slice(2, -2), slice(2, -2))
        scale = np.abs(stress).max()
        traction = 1.5 * stress[2:5, :, :, 0] - 0.5 * stress[2:5, :, :, 1]
        residual[d] = (np.abs(div[inner]).max() * width / scale, np.abs(traction).max() / scale)
    assert residual[0.5][0] < 0.02 and residual[0.5][1] < 0.015
    assert residual[0.5][0] < residual[1.0][0] / 3
    assert residual[0.5][1] < residual[1.0][1] / 2.5


def test_two_routes_to_the_surface_displacement_agree(blob_cases):
    """Reciprocal (cell averages, exact lateral sums) and direct (source + image + Boussinesq at
    z = 0) routes: u_x, u_y agree to discretisation accuracy (second order); the direct u_z
    also misses the correction pressure outside the grid (a few % here, window 6 depths)."""
    diff = {}
    for d, (_, _, recip, direct) in blob_cases.items():
        peak = max(np.abs(u).max() for u in recip)
        diff[d] = [np.abs(a - b).max() / peak for a, b in zip(direct, recip, strict=True)]
    assert max(diff[0.5][:2]) < 0.01
    assert max(diff[0.5][:2]) < max(diff[1.0][:2]) / 3
    assert diff[0.5][2] < 0.05


@pytest.mark.slow
def test_direct_route_converges_with_the_window():
    """The direct route's u_z misses the correction pressure outside the grid: for a surface
    layer of e_zz (36 x 36 cells) it converges to -h e_zz as the grid widens (48: +23 %,
    96: +4 %, 192: +1 %), while the reciprocal route is exact on every grid."""
    errors = []
    for n in (48, 96, 192):
        grid = VolumeGrid(SurfaceGrid(n, n, 1.0, 1.0), 4, 0.05)
        mask = np.zeros(grid.shape)
        m = (n - 36) // 2
        mask[m : m + 36, m : m + 36, :2] = 1.0
        eps = np.array([0, 0, 0.7e-3, 0, 0, 0])[:, None, None, None] * mask
        op = operator(grid)
        expected = -2 * grid.dz * 0.7e-3
        direct = op.surface_displacement(eps, method="direct")[2][n // 2, n // 2]
        recip = op.surface_displacement(eps)[2][n // 2, n // 2]
        assert recip == pytest.approx(expected, rel=1e-6)
        errors.append(abs(direct / expected - 1))
    assert errors[2] < 0.015 and errors[1] < errors[0] / 4 and errors[2] < errors[1] / 3


def test_deviatoric_path_equals_the_deviator_of_the_full_stress():
    """Five components in and out (the plasticity loop's path) against the full evaluation."""
    from solver.numerics.tensor import deviator

    grid = VolumeGrid(SurfaceGrid.centred(12, 10, 1.0, 0.9), 8, 0.1)
    op = EigenstrainOperator(grid, 210e9, 0.3)
    rng = np.random.default_rng(0)
    strain = deviator(rng.normal(size=(6,) + grid.shape)) * 1e-3
    layers = op.layer_spectra(strain)
    pressure = rng.random(grid.shape[:2]) * 1e9
    tractions = {"pressure": pressure, "shear_x": 0.3 * pressure}
    full = op.stress_with_tractions(strain, layers, dict(tractions))
    fast = op.deviatoric_stress_with_tractions(strain, layers, dict(tractions))
    assert np.abs(deviator(full) - fast).max() <= 1e-13 * np.abs(full).max()
    residual_only = op.stress_with_tractions(strain, layers, {})
    np.testing.assert_allclose(residual_only, op.stress(strain), rtol=0, atol=1e-9)


@pytest.mark.parametrize("nz", [5, 8])
def test_depth_transforms_are_the_dct_and_dst_of_the_columns(nz):
    """The depth convolution's z transforms (real FFTs of reordered columns) equal the DCT-II /
    DST-II of each zero-padded column and the DCT-III / DST-III back (scipy's, unnormalised as
    FFTW's), turned by i for the components odd in exactly one of x, y; odd and even layer
    counts."""
    import scipy.fft

    from solver.volume.eigenstrain_kernels import parity3, rotation

    op = operator(VolumeGrid(SurfaceGrid(4, 3, 1.0, 1.0), nz, 1.0))
    worker = op._workers()[0]
    (xs, _, _), m = worker.blocks[0], op.length_z
    rows = xs.stop - xs.start
    transforms = worker.plans[rows]
    rng = np.random.default_rng(nz)
    shape = (rows, op.shape[1] + 1)
    for component in range(6):  # xx, yy, zz even in z; yz, xz odd; xy, yz, xz turned
        odd, turned = (
            parity3(["xx", "yy", "zz", "yz", "xz", "xy"][component])[2],
            rotation(component),
        )
        window = slice(1, m + 1) if odd else slice(0, m)
        layers = rng.normal(size=shape + (nz,)) + 1j * rng.normal(size=shape + (nz,))
        target = np.zeros((2,) + shape + (m + 1,))
        op._forward_z(component, layers, worker, transforms, target)
        column = np.zeros(shape + (m,), dtype=complex)
        column[..., :nz] = layers
        transform = scipy.fft.dst if odd else scipy.fft.dct
        want = transform(column.real, type=2) + 1j * transform(column.imag, type=2)
        want = 1j * want if turned else want
        got = target[0, ..., window] + 1j * target[1, ..., window]
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-12 * np.abs(want).max())
        assert not target[..., m if not odd else 0].any()  # the slot it does not write

        acc = rng.normal(size=(2,) + shape + (m + 1,))
        out = np.zeros(shape + (nz,), dtype=complex)
        op._backward_z(component, acc, worker, transforms, out)
        back = transform(acc[0, ..., window], type=3) + 1j * transform(acc[1, ..., window], type=3)
        back = (1j * back if turned else back)[..., :nz]
        np.testing.assert_allclose(out, back, rtol=0, atol=1e-12 * np.abs(back).max())


def test_threads_split_the_spectral_products_without_changing_a_bit():
    """Two threads share the row blocks of the spectral products, of the per-layer sums (and
    FFTW's transforms): the same operations per element, so the residual stress and the
    surface displacement are bit-identical to one thread's."""
    grid = VolumeGrid(SurfaceGrid(40, 36, 1e-5, 1e-5), 30, 1e-5)
    rng = np.random.default_rng(3)
    e = rng.normal(size=(6,) + grid.shape) * 1e-3
    e[2] = -(e[0] + e[1])
    p = np.zeros(grid.surface.shape)
    p[15:25, 12:24] = 1e9
    results = []
    for threads in (1, 2):
        op = EigenstrainOperator(grid, 210e9, NU, threads=threads)
        assert len(op._workers()) == threads  # one share of the row blocks per thread
        layers = op.layer_spectra(e)
        results.append(
            (
                op.stress(e),
                op.deviatoric_stress_with_tractions(e, layers, {"pressure": p}),
                np.array(op.displacement_from_layers(layers)),
            )
        )
    for one, two in zip(*results, strict=True):
        np.testing.assert_array_equal(one, two)


def test_trace_free_eigenstrain_takes_the_deviatoric_kernels_and_agrees_with_the_general():
    """A plastic (trace-free) eigenstrain's stress comes from the 15 kernels of the symmetric
    deviatoric operator and 5 mean-stress kernels; with a dilatation added it goes through the
    21 general kernels.  By linearity the two routes must give the same stress for the
    trace-free part."""
    grid = VolumeGrid(SurfaceGrid(20, 18, 1e-5, 1e-5), 12, 1e-5)
    rng = np.random.default_rng(7)
    e = rng.normal(size=(6,) + grid.shape) * 1e-3
    e[2] = -(e[0] + e[1])
    dilatation = np.zeros_like(e)
    dilatation[:3] = rng.normal(size=grid.shape) * 1e-3
    op = EigenstrainOperator(grid, 210e9, NU)
    trace_free = op.stress(e)
    assert op._stress_spectra is None  # the general kernels were not needed
    assert len(op._deviatoric_spectra) == 20
    general = op.stress(e + dilatation) - op.stress(dilatation)
    scale = np.abs(general).max()
    np.testing.assert_allclose(trace_free, general, rtol=0, atol=1e-11 * scale)
    layers = op.layer_spectra(e)
    np.testing.assert_allclose(
        op.deviatoric_stress_with_tractions(e, layers, {}),
        deviator(general),
        rtol=0,
        atol=1e-11 * scale,
    )
