"""Surfaces given point by point: height-map files, random roughness, heights-only domains.

The sphere given as a height map is compared with the same sphere given as a radius (the
quadric, itself checked against Hertz in test_hertz.py); the roughness against its own
definition (rms, seed, spectrum); bad surfaces against their one-line refusals.
"""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest
import xarray as xr
from study_fixtures import write

import solver
from solver import Case, SpecError
from solver.bodies.heights import HeightMap, Roughness, SurfaceError
from study.campaign.surfaces import read_surface

RADIUS = 0.01
STEEL = {"behaviour": "elastic", "E": 210e9, "nu": 0.3}
SPHERE = {
    "body1": {"behaviour": "rigid", "radius": RADIUS},
    "body2": dict(STEEL),
    "load": {"normal_force": 100.0},
    "grid": {"n": 64, "half_width": 1.5},
}


def _sphere_map(points: int, side: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    x = np.linspace(-side / 2, side / 2, points)
    y = np.linspace(-side / 2, side / 2, points + 2)  # not square: x and y are told apart
    xx, yy = np.meshgrid(x, y)  # (y, x)
    return x, y, (xx**2 + yy**2) / (2 * RADIUS)


def _write_netcdf(path, x, y, height, **attrs) -> None:
    ds = xr.Dataset(
        {"height": (("y", "x"), height, {"units": "m"})},
        coords={"x": ("x", x, {"units": "m"}), "y": ("y", y, {"units": "m"})},
        attrs=attrs,
    )
    ds.to_netcdf(path)


@pytest.fixture(scope="module")
def quadric():
    case = Case.from_dict(SPHERE)
    return case, solver.solve(case)


# -- a sphere given as a height map ----------------------------------------------------------------
@pytest.mark.parametrize("factor", [2.0, 0.7])
def test_sphere_as_height_map_gives_the_quadric(tmp_path, quadric, factor):
    reference, expected = quadric
    a = reference.hertz.radius
    side = 2 * 1.5 * a  # the quadric's domain
    grid = reference.surface_grid
    points = math.ceil(factor * grid.nx) + 2  # map spacing ~ cell / factor, covering the domain
    x, y, height = _sphere_map(points, side + 4 * grid.dx)
    path = tmp_path / "sphere.nc"
    _write_netcdf(path, x, y, height)
    table = {**SPHERE, "body1": {"behaviour": "rigid", "surface": str(path)}}
    table["grid"] = {"n": 64, "size": side}
    case = Case.from_dict(table, read_surface)
    assert case.reference is None  # heights only: no closed form claimed
    got = solver.solve(case)
    assert got.status == "converged"
    gap_error = np.abs(case.pair.geometry.gap(*grid.mesh()) - reference.pair.geometry.gap(
        *grid.mesh())).max()  # fmt: skip
    for name in ("max_pressure", "approach", "contact_area"):
        assert got.history[name][-1] == pytest.approx(expected.history[name][-1], rel=1e-6)
    # the interpolation error of the gap shrinks with the map's resolution
    test_sphere_as_height_map_gives_the_quadric.errors[factor] = gap_error
    if len(test_sphere_as_height_map_gives_the_quadric.errors) == 2:
        errors = test_sphere_as_height_map_gives_the_quadric.errors
        assert errors[2.0] < errors[0.7]


test_sphere_as_height_map_gives_the_quadric.errors = {}


def test_npy_and_netcdf_give_the_same_map_and_the_case_id_is_the_content(tmp_path):
    x, y, height = _sphere_map(40, 1e-3)
    _write_netcdf(tmp_path / "a.nc", x, y, height)
    np.save(tmp_path / "a.npy", height)
    from_nc = read_surface({"file": str(tmp_path / "a.nc")})
    from_npy = read_surface(
        {"file": str(tmp_path / "a.npy"), "spacing": [x[1] - x[0], y[1] - y[0]]}
    )
    assert np.allclose(from_nc.x, from_npy.x, atol=1e-15) and np.array_equal(
        from_nc.height, from_npy.height
    )
    table = {**SPHERE, "body2": {**STEEL, "surface": str(tmp_path / "a.nc")}}
    first = Case.from_dict(table, read_surface)
    (tmp_path / "moved").mkdir()
    (tmp_path / "a.nc").rename(tmp_path / "moved" / "a.nc")
    table["body2"]["surface"] = str(tmp_path / "moved" / "a.nc")
    moved = Case.from_dict(table, read_surface)
    assert moved.case_id == first.case_id  # where the file lies is not the case
    # the normalised case remembers the content: a changed file is refused
    spec = moved.to_dict()
    assert Case.from_dict(spec, read_surface).case_id == moved.case_id
    _write_netcdf(tmp_path / "moved" / "a.nc", x, y, 1.01 * height)
    with pytest.raises(SpecError, match="changed since"):
        Case.from_dict(spec, read_surface)


def test_a_map_and_a_radius_add(tmp_path):
    """A flat map of constant height c shifts the approach by c and nothing else."""
    shift = 3e-7
    x = np.linspace(-2e-3, 2e-3, 200)
    path = tmp_path / "flat.npy"
    np.save(path, np.full((200, 200), shift))
    base = Case.from_dict(SPHERE)
    table = {**SPHERE, "body2": {**STEEL, "surface": {"file": str(path), "spacing": x[1] - x[0]}}}
    case = Case.from_dict(table, read_surface)
    a, b = solver.solve(base), solver.solve(case)
    assert case.hertz.radius == base.hertz.radius  # the smooth shape's Hertz estimate
    assert b.history["approach"][-1] == pytest.approx(a.history["approach"][-1] + shift, rel=1e-9)
    assert np.allclose(b.pressure, a.pressure, rtol=1e-7, atol=1e-7 * a.pressure.max())


def test_solver_reads_no_files_and_says_who_does(tmp_path):
    table = {**SPHERE, "body2": {**STEEL, "surface": "map.nc"}}
    with pytest.raises(SpecError, match="study.campaign.surfaces|study layer"):
        Case.from_dict(table)


# -- random roughness ------------------------------------------------------------------------------
ROUGH = {"rms": 2e-7, "hurst": 0.8, "long_cutoff": 2e-4, "short_cutoff": 2e-5, "seed": 7}


def test_roughness_is_reproducible_exact_in_rms_and_self_affine():
    rough = Roughness(0.8, 2e-4, 2e-5, rms=2e-7, seed=7)
    x = np.linspace(-4e-4, 4e-4, 301)
    xx, yy = np.meshgrid(x, x, indexing="ij")
    first, again = rough.sample(xx, yy), rough.sample(xx, yy)
    assert np.array_equal(first, again)
    other = Roughness(0.8, 2e-4, 2e-5, rms=2e-7, seed=8).sample(xx, yy)
    assert np.corrcoef(first.ravel(), other.ravel())[0, 1] < 0.2
    # the lattice realisation has the rms asked for, and the power spectrum's slope
    from solver.bodies.heights import _roughness_lattice

    points, spacing = rough.lattice(3.2e-3)  # 640 points: 16 long cutoffs
    lattice = _roughness_lattice(rough, points, spacing)
    assert math.sqrt(np.mean(lattice**2)) == pytest.approx(2e-7, rel=1e-12)
    power = np.abs(np.fft.fft2(lattice)) ** 2
    q = 2 * np.pi * np.fft.fftfreq(points, spacing)
    wavenumber = np.hypot(*np.meshgrid(q, q))
    edges = np.geomspace(2 * 2 * np.pi / 2e-4, 0.8 * 2 * np.pi / 2e-5, 12)  # self-affine range
    ring = np.digitize(wavenumber, edges)
    mean_power = [power[ring == i].mean() for i in range(1, len(edges))]
    centres = np.sqrt(edges[1:] * edges[:-1])
    slope = np.polyfit(np.log(centres), np.log(mean_power), 1)[0]
    assert slope == pytest.approx(-2 * (1 + 0.8), abs=0.1)
    # slopes: given as rms_slope, the realisation's spectral rms slope is exact
    by_slope = Roughness(0.8, 2e-4, 2e-5, rms_slope=0.05, seed=7)
    lattice = _roughness_lattice(by_slope, points, spacing)
    spectrum = np.fft.fft2(lattice)
    measured = math.sqrt(np.sum(wavenumber**2 * np.abs(spectrum) ** 2) / points**4)
    assert measured == pytest.approx(0.05, rel=1e-9)


def test_the_isotropic_spectrum_keeps_the_mean_square_and_the_self_affine_slope():
    """A cosine of ring m on a rectangular period: its ring alone holds power, the ring's
    wavevectors (counted here one by one) times C over the area its mean square a^2/2.  The
    roughness lattice: the slope -2(1 + H) between the cutoffs, and the mean square about
    (2 pi)^-1 sum q C dq."""
    from solver.bodies.heights import _roughness_lattice, isotropic_spectrum, ring_wavenumbers

    period, shape, a, m = (2e-4, 1e-4), (64, 32), 3e-8, 5
    x = (np.arange(shape[0]) + 0.5) * period[0] / shape[0]
    heights = a * np.cos(2 * np.pi * m * x / period[0])[:, None] * np.ones(shape[1])
    q = ring_wavenumbers(shape, period)
    assert q[0] == pytest.approx(2 * np.pi / period[0]) and q.size == 32  # up to pi / dx
    spectrum = isotropic_spectrum(heights, period)
    dq = 2 * np.pi / period[0]
    count = sum(
        round(math.hypot(2 * np.pi * i / period[0], 2 * np.pi * j / period[1]) / dq) == m
        for i in np.fft.fftfreq(shape[0], 1 / shape[0])
        for j in np.fft.fftfreq(shape[1], 1 / shape[1])
    )
    area = period[0] * period[1]
    assert count * spectrum[m - 1] / area == pytest.approx(a**2 / 2, rel=1e-12)
    assert np.delete(spectrum, m - 1).max() < 1e-12 * spectrum[m - 1]
    rough = Roughness(0.8, 2e-4, 2e-5, rms=2e-7, seed=7)
    points, spacing = rough.lattice(3.2e-3)  # 640 points: 16 long cutoffs
    lattice = _roughness_lattice(rough, points, spacing)
    side = (points * spacing, points * spacing)
    q, spectrum = ring_wavenumbers(lattice.shape, side), isotropic_spectrum(lattice, side)
    within = (q > 2 * 2 * np.pi / 2e-4) & (q < 0.8 * 2 * np.pi / 2e-5)
    slope = np.polyfit(np.log(q[within]), np.log(spectrum[within]), 1)[0]
    assert slope == pytest.approx(-2 * (1 + 0.8), abs=0.1)
    assert np.sum(q * spectrum) * q[0] / (2 * np.pi) == pytest.approx((2e-7) ** 2, rel=0.02)


def test_roughness_does_not_change_with_the_mesh():
    """The realisation lives on its own lattice: two grids sample the same surface."""
    coarse = Case.from_dict({**SPHERE, "body2": {**STEEL, "roughness": ROUGH}})
    fine = Case.from_dict(
        {**SPHERE, "body2": {**STEEL, "roughness": ROUGH}, "grid": {"n": 128, "half_width": 1.5}}
    )
    gap_coarse = coarse.pair.geometry.gap(*coarse.surface_grid.mesh())
    gap_fine = fine.pair.geometry.gap(*fine.surface_grid.mesh())
    # fine cells 2i, 2i+1 straddle coarse cell i: their mean is the coarse centre's value up to
    # the surface's curvature over a quarter cell
    mean = 0.25 * (gap_fine[::2, ::2] + gap_fine[1::2, ::2] + gap_fine[::2, 1::2]
                   + gap_fine[1::2, 1::2])  # fmt: skip
    assert np.abs(mean - gap_coarse).max() < 0.1 * ROUGH["rms"]


def test_rough_sphere_runs_through_the_four_loops():
    """Rigid sphere on the paper's Swift steel with roughness, mu = 0.5, a tangential load."""
    table = {
        "body1": {"behaviour": "rigid", "radius": RADIUS},
        "body2": {**STEEL, "behaviour": "elastic-plastic",
                  "hardening": {"law": "swift", "B": 945e6, "C": 20.0, "n": 0.121}},
        "friction": {"coefficient": 0.5},
        "load": {"path": [{"hertz_pressure": 3e9, "steps": 4}]},
        "grid": {"n": [32, 32, 16], "half_width": 1.5},
    }  # fmt: skip
    smooth = Case.from_dict(table)
    hertz = smooth.hertz
    table["body2"]["roughness"] = {
        **ROUGH, "rms": 0.05 * hertz.approach, "long_cutoff": hertz.radius,
        "short_cutoff": hertz.radius / 4,
    }  # fmt: skip
    table["load"]["path"].append({"tangential_force": 0.3 * hertz.normal_force, "steps": 2})
    case = Case.from_dict(table)
    assert case.hertz == hertz  # the smooth sphere's Hertz contact sizes the domain and box
    result = solver.solve(case)
    assert result.converged, result.notes
    assert np.isfinite(result.pressure).all() and np.isfinite(result.shear_x).all()
    assert result.history["max_plastic_strain"][-1] > 0
    assert result.history["tangential_force_x"][-1] == pytest.approx(0.3 * hertz.normal_force)


# -- heights only: the domain in metres ------------------------------------------------------------
def test_flat_on_rough_flat_needs_a_size_and_runs():
    flat = {"body1": {"behaviour": "rigid"}, "body2": {**STEEL, "roughness": ROUGH},
            "load": {"normal_force": 0.5}, "grid": {"n": 64}}  # fmt: skip
    with pytest.raises(SpecError, match="grid.size"):
        Case.from_dict(flat)
    flat["grid"] = {"n": 64, "size": 4e-4}
    case = Case.from_dict(flat)
    result = solver.solve(case)
    assert result.status in ("converged", "truncated")
    spots = result.pressure > 0
    assert 0 < spots.mean() < 1
    ds = result.to_xarray()
    assert ds.attrs["domain_half_width"] == pytest.approx(2e-4)
    with pytest.raises(SpecError, match="hertz_pressure|Hertz pressure"):
        Case.from_dict({**flat, "load": {"hertz_pressure": 1e9}})


def test_contact_reaching_the_domain_edge_is_told_and_truncated():
    """A rough flat pressed hard: contact everywhere, also on the outer cells."""
    flat = {"body1": {"behaviour": "rigid"}, "body2": {**STEEL, "roughness": ROUGH},
            "load": {"normal_force": 200.0}, "grid": {"n": 64, "size": 4e-4}}  # fmt: skip
    result = solver.solve(Case.from_dict(flat))
    assert result.status == "truncated"
    assert any("domain's edge" in note for note in result.notes)


# -- bad surfaces: one line naming the file, the problem and what to change ------------------------
def _bad(tmp_path, kind: str):
    """A surface table that must be refused, and words its message must hold."""
    x, y, height = _sphere_map(200, 1e-3)  # spacing 5 um: finer than the 6.9 um cells
    nc = tmp_path / "map.nc"
    if kind == "missing":
        return {"file": str(tmp_path / "nowhere.nc")}, "no such file"
    if kind == "folder":
        return {"file": str(tmp_path)}, "folder"
    if kind == "suffix":
        (tmp_path / "map.txt").write_text("1 2 3")
        return {"file": str(tmp_path / "map.txt")}, "unknown height-map format"
    if kind == "garbage_nc":
        nc.write_bytes(b"not a netcdf file at all")
        return {"file": str(nc)}, "cannot be opened"
    if kind == "no_height":
        xr.Dataset({"z": (("y", "x"), height)}, coords={"x": x, "y": y}).to_netcdf(nc)
        return {"file": str(nc)}, "no variable 'height'"
    if kind == "three_d":
        xr.Dataset({"height": (("t", "y", "x"), height[None])}, coords={"x": x, "y": y}).to_netcdf(
            nc
        )
        return {"file": str(nc)}, "2-D"
    if kind == "no_coordinate":
        xr.Dataset({"height": (("y", "x"), height)}, coords={"x": x}).to_netcdf(nc)
        return {"file": str(nc)}, "no coordinate y"
    if kind == "nan":
        height[5, 7] = np.nan
        _write_netcdf(nc, x, y, height)
        return {"file": str(nc)}, "NaN"
    if kind == "non_uniform":
        x = x.copy()
        x[10] += 0.3 * (x[1] - x[0])
        _write_netcdf(nc, x, y, height)
        return {"file": str(nc)}, "not uniformly spaced"
    if kind == "micrometres_units":
        ds = xr.Dataset({"height": (("y", "x"), height * 1e6, {"units": "um"})},
                        coords={"x": ("x", x, {"units": "m"}), "y": y})  # fmt: skip
        ds.to_netcdf(nc)
        return {"file": str(nc)}, "metres"
    if kind == "micrometres_as_metres":
        _write_netcdf(nc, x, y, height * 1e6)
        return {"file": str(nc)}, "in metres"
    if kind == "too_small":
        _write_netcdf(nc, x / 10, y / 10, height / 100)
        return {"file": str(nc)}, "smaller than the domain"
    if kind == "too_coarse":
        x, y, height = _sphere_map(6, 3e-3)
        _write_netcdf(nc, x, y, height)
        return {"file": str(nc)}, "too coarse"
    if kind == "tiny":
        _write_netcdf(nc, x[:3], y[:3], height[:3, :3])
        return {"file": str(nc)}, "4 x 4"
    if kind == "spacing_for_nc":
        _write_netcdf(nc, x, y, height)
        return {"file": str(nc), "spacing": 1e-5}, "spacing is for .npy"
    npy = tmp_path / "map.npy"
    if kind == "npy_no_spacing":
        np.save(npy, height)
        return {"file": str(npy)}, "spacing"
    if kind == "npy_one_d":
        np.save(npy, height[0])
        return {"file": str(npy), "spacing": 5e-5}, "2-D"
    if kind == "npy_strings":
        np.save(npy, np.array([["a"] * 5] * 5))
        return {"file": str(npy), "spacing": 5e-5}, "real numbers"
    if kind == "npy_bad_spacing":
        np.save(npy, height)
        return {"file": str(npy), "spacing": -1e-5}, "> 0"
    if kind == "npy_garbage":
        npy.write_bytes(b"\x93NUMPY garbage")
        return {"file": str(npy), "spacing": 5e-5}, "not a readable .npy"
    raise AssertionError(kind)


BAD_SURFACES = [
    "missing", "folder", "suffix", "garbage_nc", "no_height", "three_d", "no_coordinate", "nan",
    "non_uniform", "micrometres_units", "micrometres_as_metres", "too_small", "too_coarse",
    "tiny", "spacing_for_nc", "npy_no_spacing", "npy_one_d", "npy_strings", "npy_bad_spacing",
    "npy_garbage",
]  # fmt: skip


@pytest.mark.parametrize("kind", BAD_SURFACES)
def test_bad_surface_is_refused_in_one_line(tmp_path, kind):
    surface, words = _bad(tmp_path, kind)
    table = {**SPHERE, "body2": {**STEEL, "surface": surface}}
    with pytest.raises(SpecError) as error:
        Case.from_dict(table, read_surface)
    message = str(error.value)
    assert message.startswith("body2.surface") and words in message and "\n" not in message


BAD_ROUGHNESS = [
    ({"rms_slope": 0.1}, "one of rms"),
    ({"hurst": 1.5}, "hurst"),
    ({"long_cutoff": 1e-5}, "short_cutoff"),
    ({"short_cutoff": 1e-7}, "2 cells"),
    ({"rms": 1.0}, "metres"),
    ({"long_cutoff": 1.0}, "lattice"),
]


@pytest.mark.parametrize(("change", "words"), BAD_ROUGHNESS)
def test_bad_roughness_is_refused(change, words):
    table = {**SPHERE, "body2": {**STEEL, "roughness": {**ROUGH, **change}}}
    with pytest.raises(SpecError, match=words):
        Case.from_dict(table)


def test_command_line_refuses_a_bad_map_with_status_2(tmp_path):
    (tmp_path / "bad.nc").write_bytes(b"garbage")
    (tmp_path / "c.toml").write_text(
        '[base]\nbody1 = { behaviour = "rigid", radius = 0.01 }\n'
        'body2 = { behaviour = "elastic", E = 210e9, nu = 0.3, surface = "bad.nc" }\n'
        "load = { normal_force = 100.0 }\ngrid = { n = 32 }\n"
        '[sweep]\n"friction.coefficient" = [0.0]\n'
    )
    run = subprocess.run(
        [sys.executable, "-m", "study", "validate", str(tmp_path / "c.toml")],
        capture_output=True, text=True, cwd=tmp_path.parent,
    )  # fmt: skip
    assert run.returncode == 2
    assert "body2.surface" in run.stderr + run.stdout and "Traceback" not in run.stderr
    assert str(tmp_path / "bad.nc") in run.stderr + run.stdout  # relative to the campaign file


# -- several contact spots ------------------------------------------------------------------------
def test_two_bumps_make_two_spots_and_two_stick_zones():
    """Two spherical bumps 6 a apart on a flat (identical steels, beta = 0): each carries W/2 as
    a Hertz contact (the other's displacement there is of order a/d of its approach), and under a
    tangential load each has its own Cattaneo-Mindlin stick zone."""
    force, mu, ratio = 100.0, 0.4, 0.5
    half = force / 2
    from solver.theory.friction import cattaneo_stick_ratio
    from solver.theory.hertz import hertz

    e_star = 210e9 / (2 * (1 - 0.3**2))
    single = hertz(half, e_star, (1 / RADIUS, 1 / RADIUS))
    d = 3 * single.radius  # bump centres at x = -d, +d
    side = 4 * d
    x = np.linspace(-side / 2, side / 2, 801)
    xx, yy = np.meshgrid(x, x)
    bumps = np.minimum((xx + d) ** 2, (xx - d) ** 2) + yy**2
    table = {
        "body1": {**STEEL, "surface": HeightMap(x, x, bumps / (2 * RADIUS), "two bumps")},
        "body2": dict(STEEL),
        "friction": {"coefficient": mu},
        "load": {"path": [{"normal_force": force}, {"tangential_force": ratio * mu * force}]},
        "grid": {"n": [192, 96], "size": [3 * d, 1.5 * d]},
    }
    case = Case.from_dict(table)
    result = solver.solve(case)
    assert result.status == "converged"
    h = result.history
    assert h["contact_spots"][0] == 2 and h["contact_spots"][-1] == 2
    grid = case.surface_grid
    left = grid.x < 0
    area = grid.cell_area
    loads = [result.pressure[side_].sum() * area for side_ in (left, ~left)]
    assert loads == pytest.approx([half, half], rel=1e-9)  # the mirror symmetry
    assert result.pressure.max() == pytest.approx(single.max_pressure, rel=0.02)
    stick = result.contact_state == solver.result.STICK
    assert solver.drive.record.contact_spots(stick) == 2
    expected = single.radius * cattaneo_stick_ratio(ratio * mu * half, mu, half)
    for side_ in (left, ~left):
        measured = math.sqrt(np.count_nonzero(stick & side_[:, None]) * area / math.pi)
        assert abs(measured - expected) < 2 * grid.dx


# -- a second indentation on and beside a dent ----------------------------------------------------
def test_second_indentation_on_and_beside_a_dent(tmp_path):
    """The residual print of a first indentation is the surface of a second one (material virgin
    again): on the dent the sphere meets a conforming seat (larger contact, lower pressure, less
    new plastic strain); beside it (offset 0.5 a_H along +x) the new print forms off the dent,
    on the -x side."""
    base = {
        "body1": {"behaviour": "rigid", "radius": 0.015},
        "body2": {"behaviour": "elastic-plastic", "E": 210e9, "nu": 0.3,
                  "hardening": {"law": "linear", "yield_stress": 1.0e9, "modulus": 10e9}},
        "load": {"path": [{"hertz_pressure": 4.0e9, "steps": 4}, {"normal_force": 0.0}]},
        "grid": {"n": [24, 24, 24], "half_width": 2.0},
    }  # fmt: skip
    first = solver.solve(Case.from_dict(base))
    assert first.status == "converged"
    first.to_xarray().to_netcdf(tmp_path / "first.nc")
    a = first.case.hertz.radius
    peak = int(np.argmax(first.history["normal_force"]))
    second = {}
    for offset in (0.0, 0.5):
        table = {**base, "grid": {"n": [18, 18, 24], "half_width": 1.5,
                                  "depth": first.case.grid.depth}}  # fmt: skip
        surface = {"case": str(tmp_path / "first.nc"), "offset": [offset * a, 0.0]}
        table["body2"] = {**base["body2"], "surface": surface}
        case = Case.from_dict(table, read_surface)
        assert case.surface_grid.dx == pytest.approx(first.case.surface_grid.dx)
        second[offset] = solver.solve(case)
        assert second[offset].status == "converged", second[offset].notes

    def at_peak(result, name):
        return result.history[name][peak]

    on = second[0.0]
    assert at_peak(on, "contact_area") > 1.05 * at_peak(first, "contact_area")
    assert at_peak(on, "max_pressure") < 0.95 * at_peak(first, "max_pressure")
    assert on.history["max_plastic_strain"][-1] < 0.7 * first.history["max_plastic_strain"][-1]
    beside = second[0.5]
    print_z = beside.fields["residual_displacement_z"]
    deepest = np.unravel_index(np.argmax(print_z), print_z.shape)
    assert beside.grid.x[deepest[0]] < 0  # the new dent forms off the old one
    assert at_peak(beside, "max_pressure") > at_peak(on, "max_pressure")


def test_a_dent_is_read_from_a_campaign_output_folder(tmp_path):
    """``case = "OUT/cases/<id>"`` names a case stored in the folder's bundles."""
    from study.campaign import load_campaign
    from study.run import storage
    from study.run.driver import run_campaign

    text = """
[campaign]
name = "first"

[base]
body1 = { behaviour = "rigid", radius = 0.015 }
body2 = { behaviour = "elastic-plastic", E = 210e9, nu = 0.3, hardening = { law = "linear", yield_stress = 1.0e9, modulus = 10e9 } }
grid = { n = [20, 20, 16], half_width = 2.0 }

[[base.load.path]]
hertz_pressure = 4.0e9
steps = 2

[[base.load.path]]
normal_force = 0.0

[sweep]
"friction.coefficient" = [0.0]
"""  # noqa: E501
    campaign = load_campaign(write(tmp_path, text))
    out = tmp_path / "out"
    assert run_campaign(campaign, out).exit_status == 0
    case_id = campaign.cases[0].case_id
    stored = storage.open_case(out, case_id)
    for name in (case_id, f"{case_id}.nc"):
        dent = read_surface({"case": str(out / "cases" / name)})
        expected = stored["residual_displacement_z"].transpose("y", "x").values
        np.testing.assert_array_equal(dent.height, expected)
    with pytest.raises(SurfaceError, match="no finished case 0123456789abcdef"):
        read_surface({"case": str(out / "cases" / "0123456789abcdef")})


def test_a_dent_must_come_from_a_converged_plastic_case(tmp_path):
    elastic = solver.solve(Case.from_dict(SPHERE))
    elastic.to_xarray().to_netcdf(tmp_path / "elastic.nc")
    table = {**SPHERE, "body2": {**STEEL, "surface": {"case": str(tmp_path / "elastic.nc")}}}
    with pytest.raises(SpecError, match="not an elastic-plastic case"):
        Case.from_dict(table, read_surface)
    table["body2"]["surface"] = {"case": "a.nc", "file": "b.nc"}
    with pytest.raises(SpecError, match="one of file"):
        Case.from_dict(table, read_surface)


# -- campaigns over roughness: realisations -------------------------------------------------------
ROUGH_CAMPAIGN = """
[campaign]
name = "rough"

[base]
body1 = { behaviour = "rigid", radius = 0.01 }
load = { normal_force = 20.0 }
grid = { n = 32, half_width = 1.5 }

[base.body2]
behaviour = "elastic"
E = 210e9
nu = 0.3
roughness = { rms = 5e-8, hurst = 0.8, long_cutoff = 1.5e-4, short_cutoff = 3e-5, seed = 1 }

[sweep]
"body2.roughness.rms" = [5e-8, 4e-7]
"body2.roughness.seed" = [1, 2, 3]

[alias]
"body2.roughness.rms" = "rms"
"body2.roughness.seed" = "realisation"
"""


def test_seeds_are_realisations_the_analysis_and_report_reduce(tmp_path):
    from study import analysis
    from study.campaign import load_campaign
    from study.report import build_report
    from study.run.assemble import assemble_to_file
    from study.run.driver import run_campaign

    path = tmp_path / "rough.toml"
    path.write_text(ROUGH_CAMPAIGN)
    out = tmp_path / "out"
    campaign = load_campaign(path)
    assert run_campaign(campaign, out).exit_status == 0
    ds = xr.open_dataset(assemble_to_file(out, campaign))
    assert analysis.realisation_axes(ds) == ["realisation"]
    assert "realisation" not in analysis.sensitivity_axes(ds) and "rms" in (
        analysis.sensitivity_axes(ds)
    )
    stats = analysis.realisation_statistics(ds)
    area = ds.contact_area.values  # (rms, realisation)
    np.testing.assert_allclose(stats.contact_area.sel(statistic="mean"), area.mean(axis=1))
    np.testing.assert_allclose(stats.contact_area.sel(statistic="std"), area.std(axis=1, ddof=1))
    assert (stats.realisations == 3).all()
    assert np.all(np.diff(ds.contact_spots.values, axis=0) >= 0)  # rougher: more spots
    mean = stats.contact_area.sel(statistic="mean").values
    assert mean[1] < mean[0]  # rougher: less real contact area at the same load
    assert np.all(area.std(axis=1) > 0)  # the seeds draw different surfaces
    report = build_report(out, plots=False).read_text()
    assert "## Over the surface realisations" in report


def test_a_heights_only_contact_too_small_for_the_grid_is_told():
    """Without a radius the mesh check waits for the solve: a few-cell contact is a note."""
    flat = {"body1": {"behaviour": "rigid"}, "body2": {**STEEL, "roughness": ROUGH},
            "load": {"normal_force": 1e-3}, "grid": {"n": 64, "size": 4e-4}}  # fmt: skip
    result = solver.solve(Case.from_dict(flat))
    assert any("cells across" in note for note in result.notes), result.notes
