"""Periodic mode (issue 37, first steps): exact periodic references, lattice sums, case files.

Westergaard's 1-D sinusoid (Johnson 1985, §13.2): the gap ``h = Delta (1 - cos 2 pi x / L)``
pressed by a mean pressure ``p`` is in full contact from ``p* = pi E* Delta / L``; below it the
contact half-width ``a`` obeys ``sin^2(pi a / L) = p / p*`` and the pressure is
``p(x) = (2 p cos(pi x / L) / sin^2(pi a / L)) sqrt(sin^2(pi a / L) - sin^2(pi x / L))``; above
it ``p(x) = p + p* cos(2 pi x / L)``.  A uniform strip in y (a few cells) is the plane problem.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

import solver
from solver.bodies.heights import HeightMap
from solver.bodies.materials import Body, Pair
from solver.drive.record import contact_spots
from solver.numerics.grid import SurfaceGrid
from solver.surface.convolution import SurfaceOperator
from solver.surface.normal import solve_normal
from solver.surface.periodic import PeriodicSurfaceOperator

STEEL = Body("elastic", E=210e9, nu=0.3)
PAIR = Pair(Body("rigid"), STEEL)
PERIOD, AMPLITUDE = 1e-3, 1e-6  # m


def westergaard(x: np.ndarray, mean: float, full: float) -> tuple[np.ndarray, float]:
    """Westergaard's pressure (Pa) at ``x`` (m from the crest) and contact half-width (m)."""
    if mean >= full:
        return mean + full * np.cos(2 * np.pi * x / PERIOD), PERIOD / 2
    s2 = mean / full
    half = PERIOD / np.pi * math.asin(math.sqrt(s2))
    inside = np.clip(s2 - np.sin(np.pi * x / PERIOD) ** 2, 0.0, None)
    return 2 * mean * np.cos(np.pi * x / PERIOD) / s2 * np.sqrt(inside), half


def sinusoid_contact(n: int, ratio: float):
    """Solve the periodic sinusoid on ``n`` cells per period at ``p = ratio p*``."""
    dx = PERIOD / n
    grid = SurfaceGrid.centred(n, 4, PERIOD / 2, 2 * dx)
    operator = PeriodicSurfaceOperator(grid, PAIR)
    x, _ = grid.mesh()
    gap = AMPLITUDE * (1 - np.cos(2 * np.pi * x / PERIOD))
    full = math.pi * PAIR.composite_modulus * AMPLITUDE / PERIOD
    mean = ratio * full
    solution = solve_normal(operator, gap, mean * PERIOD * 4 * dx, tolerance=1e-12)
    assert solution.converged
    expected, half = westergaard(x, mean, full)
    return solution, expected, half, full, grid


@pytest.mark.validation
@pytest.mark.parametrize("ratio", [0.1, 0.3, 0.6])
def test_westergaard_partial_contact_converges(ratio, validation):
    """Peak pressure within 1e-4 and converging; the contact edge within a cell at every mesh;
    the pressure within 1 % (L2) from 128 cells a period."""
    peaks = []
    for n in (64, 128, 256):
        solution, expected, half, full, grid = sinusoid_contact(n, ratio)
        peak = 2 * math.sqrt(ratio) * full  # p(0) = 2 sqrt(p p*)
        assert westergaard(np.zeros(1), ratio * full, full)[0][0] == pytest.approx(peak)
        assert np.allclose(solution.pressure, solution.pressure[:, :1])  # uniform in y
        pressure, exact = solution.pressure[:, 0], expected[:, 0]
        peaks.append(abs(pressure.max() - exact.max()) / exact.max())
        in_contact = np.count_nonzero(pressure > 0) * grid.dx / 2
        assert abs(in_contact - half) <= grid.dx
        error = np.linalg.norm(pressure - exact) / np.linalg.norm(exact)
        assert error < (0.02 if n == 64 else 0.01)
    assert peaks[-1] < peaks[0] and peaks[-1] < 1e-4
    validation(
        "periodic mode: Westergaard's sinusoid, p / p* = 0.1, 0.3, 0.6, 64 / 128 / 256 cells a "
        "period",
        "Westergaard (Johnson 1985 §13.2): peak 2 sqrt(p p*), half-width, pressure",
        f"p / p* = {ratio}: peak error {peaks[0]:.1e} / {peaks[1]:.1e} / {peaks[2]:.1e}, "
        f"pressure (L2) within {0.01:.0%} from 128 cells, contact edge within a cell",
    )


@pytest.mark.validation
def test_westergaard_full_contact_is_exact(validation):
    solution, expected, _, full, _ = sinusoid_contact(64, 1.5)
    assert np.all(solution.pressure > 0)
    error = np.abs(solution.pressure - expected).max() / full
    assert error < 1e-8
    validation(
        "periodic mode: Westergaard's sinusoid in full contact, p = 1.5 p*, 64 cells a period",
        "p + p* cos(2 pi x / L)",
        f"largest error {error:.1e} p*",
    )


@pytest.mark.validation
def test_the_fourier_kernels_are_the_lattice_sum_of_the_cell_kernels(validation):
    """A zero-mean periodic load: the Fourier forms against the non-periodic DC-FFT operator on
    a tiled domain (the cell kernels summed over 5 x 5 periods), the central period compared;
    their difference shrinks with the cell size."""
    differences = []
    for n in (8, 16, 32):
        side = PERIOD / n
        grid = SurfaceGrid.centred(n, n, PERIOD / 2, PERIOD / 2)
        x, y = grid.mesh()
        load = {
            "p": np.cos(2 * np.pi * x / PERIOD) * np.cos(4 * np.pi * y / PERIOD),
            "qx": np.sin(2 * np.pi * (x + 2 * y) / PERIOD),
            "qy": 0.5 * np.cos(6 * np.pi * x / PERIOD),
        }
        periodic = PeriodicSurfaceOperator(grid, Pair(STEEL, STEEL))
        ux, uy, uz = periodic.displacement(load["qx"], load["qy"], load["p"])
        tiles = 5
        big = SurfaceGrid.centred(tiles * n, tiles * n, tiles * PERIOD / 2, tiles * PERIOD / 2)
        assert big.dx == pytest.approx(side)
        tiled = SurfaceOperator(big, Pair(STEEL, STEEL))
        spread = {k: np.tile(v, (tiles, tiles)) for k, v in load.items()}
        centre = slice(2 * n, 3 * n)
        wide = tiled.displacement(spread["qx"], spread["qy"], spread["p"])
        worst = 0.0
        for ours, theirs in zip((ux, uy, uz), wide, strict=True):
            theirs = theirs[centre, centre] - theirs[centre, centre].mean()
            worst = max(worst, np.abs(ours - theirs).max() / np.abs(theirs).max())
        differences.append(worst)
    assert differences[-1] < differences[0] / 2
    assert differences[-1] < 0.05
    validation(
        "periodic Boussinesq and Cerruti kernels (Fourier forms), a zero-mean load, 8 / 16 / 32 "
        "cells a period",
        "the non-periodic cell kernels summed over 5 x 5 tiled periods (DC-FFT)",
        " / ".join(f"{d:.1e}" for d in differences) + " (largest of u_x, u_y, u_z)",
    )


@pytest.mark.validation
def test_the_periodic_coupling_of_a_dissimilar_pair_is_the_lattice_sum(validation):
    """Aluminium on steel (beta != 0): the tangential displacements of a pressure and the normal
    displacement of shears, periodic against the non-periodic kernels on 5 x 5 tiled periods."""
    pair = Pair(Body("elastic", E=70e9, nu=0.33), STEEL)
    assert pair.dundurs_beta != 0.0
    differences = []
    for n in (16, 32, 64):
        grid = SurfaceGrid.centred(n, n, PERIOD / 2, PERIOD / 2)
        x, y = grid.mesh()
        pressure = np.cos(2 * np.pi * x / PERIOD) * np.cos(4 * np.pi * y / PERIOD)
        shear = np.sin(2 * np.pi * (2 * x - y) / PERIOD)
        periodic = PeriodicSurfaceOperator(grid, pair)
        ours = (
            *periodic.tangential_from_pressure(pressure),
            periodic.normal_from_shear(shear, 0 * shear),
        )
        tiles = 5
        big = SurfaceGrid.centred(tiles * n, tiles * n, tiles * PERIOD / 2, tiles * PERIOD / 2)
        tiled = SurfaceOperator(big, pair)
        wide_p, wide_q = np.tile(pressure, (tiles, tiles)), np.tile(shear, (tiles, tiles))
        theirs = (
            *tiled.tangential_from_pressure(wide_p),
            tiled.normal_from_shear(wide_q, 0 * wide_q),
        )
        centre = slice(2 * n, 3 * n)
        worst = 0.0
        for a, b in zip(ours, theirs, strict=True):
            b = b[centre, centre] - b[centre, centre].mean()
            worst = max(worst, np.abs(a - b).max() / np.abs(b).max())
        differences.append(worst)
    assert differences[-1] < differences[0] / 4 and differences[-1] < 0.01
    validation(
        "periodic normal-tangential coupling (beta != 0, aluminium on steel), 16 / 32 / 64 cells "
        "a period",
        "the non-periodic coupling kernels summed over 5 x 5 tiled periods (DC-FFT)",
        " / ".join(f"{d:.1e}" for d in differences) + " (largest of u_x(p), u_y(p), u_z(q))",
    )


# -- grid.periodic: a case file's periodic mode ---------------------------------------------------
def periodic_case(body2: dict, n=(64, 64), size=(PERIOD, PERIOD), force=5.0, **extra) -> dict:
    """A rigid flat on an elastic body with periodic heights (a case table)."""
    table = {
        "body1": {"behaviour": "rigid", "radius": "inf"},
        "body2": {"behaviour": "elastic", "E": 210e9, "nu": 0.3, **body2},
        "load": {"normal_force": force},
        "grid": {"n": list(n), "size": list(size), "periodic": True},
    }
    for key, value in extra.items():  # other tables, or keys of these
        table.setdefault(key, {}).update(value)
    return table


def sinusoid_map(n: int, rows: int = 4) -> HeightMap:
    """Westergaard's gap as a height map of one period: n x rows points at the cell centres."""
    dx = PERIOD / n
    x = (np.arange(n) + 0.5) * dx - PERIOD / 2
    y = (np.arange(rows) + 0.5) * dx - rows * dx / 2
    height = AMPLITUDE * (1 - np.cos(2 * np.pi * x / PERIOD))[None, :] * np.ones((rows, 1))
    return HeightMap(x, y, height, "sinusoid")


ROUGH = {"hurst": 0.8, "long_cutoff": 2.5e-4, "short_cutoff": 1.25e-4, "rms": 0.5e-6, "seed": 3}
PLASTIC = {"behaviour": "elastic-plastic", "hardening": {"law": "perfect", "yield_stress": 1e9}}


def test_a_periodic_case_file_solves_westergaard():
    """The sinusoid as a periodic height map in a case: the peak 2 sqrt(p p*) to 1e-3."""
    full = math.pi * PAIR.composite_modulus * AMPLITUDE / PERIOD
    errors = []
    for n in (64, 128):
        dx = PERIOD / n
        mean = 0.3 * full
        table = periodic_case(
            {"surface": sinusoid_map(n)},
            n=(n, 4),
            size=(PERIOD, 4 * dx),
            force=mean * PERIOD * 4 * dx,
        )
        result = solver.solve(solver.Case.from_dict(table))
        assert result.status == "converged", result.notes
        peak = 2 * math.sqrt(mean * full)
        errors.append(abs(result.pressure.max() - peak) / peak)
        assert result.history["contact_spots"][-1] == 1  # one strip across the period
        assert not result.notes  # no edge or mesh note: the period has no edge
    assert errors[-1] < errors[0] and errors[-1] < 1e-3


def test_a_periodic_roughness_is_one_period_and_its_spots_join_across_the_seams():
    case = solver.Case.from_dict(periodic_case({"roughness": ROUGH}))
    assert case.spec["grid"]["periodic"] is True
    roughness = case.body2.roughness
    x, y = case.surface_grid.mesh()
    heights = roughness.sample(x, y, case.grid.size)
    shifted = roughness.sample(x + PERIOD, y - PERIOD, case.grid.size)
    assert np.allclose(heights, shifted, atol=1e-12 * np.abs(heights).max())
    result = solver.solve(case)
    assert result.status == "converged"
    force = result.pressure.sum() * case.surface_grid.cell_area
    assert force == pytest.approx(5.0, rel=1e-9)
    spots = result.history["contact_spots"][-1]
    assert 1 <= spots <= contact_spots(result.pressure > 0)


def test_contact_spots_join_across_the_period():
    mask = np.zeros((6, 6), dtype=bool)
    mask[0, 2] = mask[-1, 2] = True  # one spot split by the x seam
    mask[3, 0] = mask[3, -1] = True  # and one by the y seam
    assert contact_spots(mask) == 4
    assert contact_spots(mask, periodic=True) == 2
    mask[0, 0] = mask[-1, -1] = True  # corners only: separate (4-connectivity)
    assert contact_spots(mask, periodic=True) == 4


def test_a_periodic_case_has_its_own_id():
    table = periodic_case({"roughness": ROUGH})
    periodic = solver.Case.from_dict(table)
    del table["grid"]["periodic"]
    assert solver.Case.from_dict(table).case_id != periodic.case_id
    assert "periodic" not in solver.Case.from_dict(table).spec["grid"]


@pytest.mark.parametrize(
    ("change", "field"),
    [
        ({"grid": {"size": None}}, "grid.periodic"),
        ({"body1": {"radius": 0.01}}, "body1.radius"),
        ({"body1": {"behaviour": "elastic-plastic", "E": 210e9, "nu": 0.3, "hardening": {
          "law": "perfect", "yield_stress": 400e6}}}, "body1.behaviour"),
        ({"body2": PLASTIC}, "grid.n"),  # no volume grid
        ({"body2": PLASTIC, "grid": {"n": [64, 64, 8], "plastic_half_width": 0.5}},
         "grid.plastic_half_width"),
        ({"body2": PLASTIC, "grid": {"n": [64, 64, 8], "depth": 0.6 * PERIOD}}, "grid.depth"),
        ({"body2": PLASTIC, "grid": {"n": [64, 64, 8], "depth": 5e-324}}, "grid.depth"),
        ({"body2": PLASTIC, "grid": {"n": [64, 64, 8]}, "load": {"normal_force": 1.8e9 * PERIOD
          * PERIOD}}, "load.path"),  # the mean pressure alone yields every depth
        ({"body2": PLASTIC, "grid": {"n": [64, 64, 4], "depth": 0.3 * PERIOD}}, "grid.depth"),
        ({"grid": {"n": [64, 64, 16]}}, "grid.n"),
        ({"body2": {"roughness": {**ROUGH, "long_cutoff": 2e-3}}}, "body2.roughness.long_cutoff"),
        ({"body2": {"roughness": {**ROUGH, "short_cutoff": 1e-4}}}, "body2.roughness.short_cutoff"),
        ({"grid": {"n": [64, 32], "size": [PERIOD, PERIOD / 2]}}, "grid.size"),
    ],
)  # fmt: skip
def test_what_periodic_mode_does_not_solve_is_refused(change, field):
    table = periodic_case({"roughness": ROUGH})
    for key, values in change.items():
        for name, value in values.items():
            if value is None:
                del table[key][name]
            else:
                table.setdefault(key, {})[name] = value
    with pytest.raises(solver.SpecError, match=f"^{re.escape(field)}"):
        solver.Case.from_dict(table)


def test_a_periodic_box_above_the_yield_region_is_noted_and_its_depth_sized():
    """Left out, the depth is 1.2 times the elastic yield region's (in metres); a box that ends
    above the region's bottom is solved with a note (the zone will likely reach it)."""
    table = periodic_case({**PLASTIC, "roughness": ROUGH})
    table["grid"]["n"] = [64, 64, 8]
    sized = solver.Case.from_dict(table)
    assert 0.0 < sized.grid.depth <= 0.5 * PERIOD and not sized.warnings
    table["grid"]["depth"] = sized.grid.depth / 2
    shallow = solver.Case.from_dict(table)
    assert any("above the bottom of the elastic yield region" in w for w in shallow.warnings)


def test_a_height_map_that_is_not_one_period_is_refused():
    n = 64
    dx = PERIOD / n
    size = (PERIOD, 4 * dx)
    whole = sinusoid_map(n)
    solver.Case.from_dict(periodic_case({"surface": whole}, n=(n, 4), size=size))
    short = HeightMap(whole.x[:-4], whole.y, whole.height[:, :-4], "short")  # a part of it
    with pytest.raises(solver.SpecError, match="not the period"):
        solver.Case.from_dict(periodic_case({"surface": short}, n=(n, 4), size=size))
    jumped = HeightMap(whole.x, whole.y, whole.height + 1e-7 * np.arange(n)[None, :], "ramp")
    with pytest.raises(solver.SpecError, match="not periodic along x"):
        solver.Case.from_dict(periodic_case({"surface": jumped}, n=(n, 4), size=size))


@pytest.mark.validation
def test_partial_slip_on_the_periodic_sinusoid_is_ciavarella_jaeger(validation):
    """Two identical steels (beta = 0), Westergaard's strip at p = 0.3 p*, then Q = mu W / 2.

    Ciavarella's and Jaeger's superposition for plane contacts: q = mu (p - p_c), p_c the
    normal pressure at the smaller load whose contact half-width is the stick zone's, at the mean
    pressure p (1 - Q / (mu W)).  The shear within 2.5 % (L2), 1 % from 128 cells a period; the
    stick zone within a cell; the shear's sum the prescribed force.
    """
    steel = {"behaviour": "elastic", "E": 210e9, "nu": 0.3}
    full = math.pi * Pair(STEEL, STEEL).composite_modulus * AMPLITUDE / PERIOD
    mu = 0.3
    errors = []
    for n, bound in ((64, 0.025), (128, 0.01)):
        dx = PERIOD / n
        mean = 0.3 * full
        force = mean * PERIOD * 4 * dx
        shear = 0.5 * mu * force
        table = periodic_case(
            {**steel, "surface": sinusoid_map(n)},
            (n, 4),
            (PERIOD, 4 * dx),
            body1={**steel, "radius": "inf"},
            friction={"coefficient": mu},
        )
        table["load"] = {
            "path": [
                {"normal_force": force, "steps": 1},
                {"tangential_force": [shear, 0.0], "steps": 10},
            ]
        }
        case = solver.Case.from_dict(table)
        result = solver.solve(case)
        assert result.status == "converged", result.notes
        x = case.surface_grid.mesh()[0]
        pressure, _ = westergaard(x, mean, full)
        smaller, stick_half = westergaard(x, mean * (1 - shear / (mu * force)), full)
        expected = mu * (pressure - smaller)
        q = result.shear_x
        errors.append(np.linalg.norm(q - expected) / np.linalg.norm(expected))
        assert errors[-1] < bound
        stick = np.count_nonzero(result.contact_state[:, 0] == 1) * dx / 2
        assert abs(stick - stick_half) <= dx
        assert q.sum() * case.surface_grid.cell_area == pytest.approx(shear, rel=1e-9)
    validation(
        "periodic mode: partial slip on Westergaard's strip, two steels (beta = 0), "
        "p = 0.3 p*, Q = mu W / 2, 64 / 128 cells a period",
        "Ciavarella and Jaeger: q = mu (p - p_c), p_c at the stick zone's half-width",
        f"shear (L2) {errors[0]:.1e} / {errors[1]:.1e}; stick zone within a cell (asserted)",
    )


def test_a_periodic_case_records_its_contact_fraction_and_mean_separation():
    """Westergaard's strip loaded to 0.1, 0.3, 0.6 and 1.2 p*: the fraction 2a/L within a cell,
    1 in full contact, where the deformed surfaces meet everywhere (mean separation 0); the
    separation falls as the load grows (the load-separation curve)."""
    n = 128
    dx = PERIOD / n
    full = math.pi * PAIR.composite_modulus * AMPLITUDE / PERIOD
    ratios = (0.1, 0.3, 0.6, 1.2)
    nominal = PERIOD * 4 * dx
    path = [{"normal_force": r * full * nominal, "steps": 1} for r in ratios]
    table = periodic_case({"surface": sinusoid_map(n)}, (n, 4), (PERIOD, 4 * dx))
    table["load"] = {"path": path}
    result = solver.solve(solver.Case.from_dict(table))
    assert result.status == "converged", result.notes
    fraction = result.history["contact_fraction"]
    separation = result.history["mean_separation"]
    for ratio, measured in zip(ratios[:-1], fraction, strict=False):
        half = PERIOD / np.pi * math.asin(math.sqrt(ratio))
        assert abs(measured - 2 * half / PERIOD) <= dx / PERIOD
    assert fraction[-1] == 1.0 and abs(separation[-1]) < 1e-9 * AMPLITUDE
    assert np.all(np.diff(separation) < 0) and separation[0] > 0
    data = result.to_xarray()
    assert data["contact_fraction"].attrs["units"] == "1"


def test_a_non_periodic_case_has_no_periodic_histories():
    table = periodic_case({"roughness": ROUGH})
    del table["grid"]["periodic"]
    history = solver.solve(solver.Case.from_dict(table)).history
    assert "contact_fraction" not in history and "mean_separation" not in history


@pytest.mark.validation
def test_the_2d_sinusoid_at_small_load_is_hertz_at_each_crest(validation):
    """``h = Delta (1 - cos(2 pi x / L) cos(2 pi y / L))`` has two crests a period, (0, 0) and
    (L/2, L/2), each a sphere of radius ``L^2 / (4 pi^2 Delta)``: at a small load (contact radius
    0.03 L) each carries W / 2 as Hertz says (the small-load end of Johnson, Greenwood and
    Higginson's wavy surface).  The peak pressure within 1 % from 256 cells a period."""
    wave = 2 * math.pi / PERIOD
    radius = 1 / (AMPLITUDE * wave * wave)
    modulus = PAIR.composite_modulus
    contact = 0.03 * PERIOD
    force = 2 * 4 * modulus * contact**3 / (3 * radius)  # two Hertz contacts
    peak = 2 * modulus * contact / (math.pi * radius)
    errors = []
    for n in (128, 256):
        grid = SurfaceGrid.centred(n, n, PERIOD / 2, PERIOD / 2)
        x, y = grid.mesh()
        gap = AMPLITUDE * (1 - np.cos(wave * x) * np.cos(wave * y))
        solution = solve_normal(PeriodicSurfaceOperator(grid, PAIR), gap, force, tolerance=1e-10)
        assert solution.converged
        errors.append(abs(solution.pressure.max() - peak) / peak)
        assert contact_spots(solution.pressure > 0, periodic=True) == 2
    assert errors[1] < errors[0] / 2 and errors[1] < 0.01
    validation(
        "periodic mode: 2-D sinusoid, two crests a period, contact radius 0.03 L, 128 / 256 "
        "cells a period",
        "Hertz at each crest (R = L^2 / (4 pi^2 Delta), W / 2 each)",
        f"peak pressure {errors[0]:.1e} / {errors[1]:.1e}",
    )


@pytest.mark.validation
def test_the_2d_sinusoid_near_full_contact_has_jgh_holes(validation):
    """Near full contact (``p* = sqrt(2) pi E* Delta / L``) the gaps left around the two troughs
    are circles whose radius makes the full-contact tension vanish at their edge, like a penny
    crack with no stress intensity: ``b^2 = 3 (1 - p/p*) / k^2``, so the area out of contact is
    ``(3 / 2 pi) (1 - p/p*)`` of the period (Johnson, Greenwood & Higginson 1985's
    near-complete-contact asymptote).  Within 1 % at 1 - p/p* = 0.05 and 0.025 on 256 and 512
    cells a period; at 1 - p/p* = 0.1 the next order shows (the asymptote's own error)."""
    wave = 2 * math.pi / PERIOD
    full = math.sqrt(2) * math.pi * PAIR.composite_modulus * AMPLITUDE / PERIOD
    ratios = {}
    for n in (256, 512):
        grid = SurfaceGrid.centred(n, n, PERIOD / 2, PERIOD / 2)
        x, y = grid.mesh()
        gap = AMPLITUDE * (1 - np.cos(wave * x) * np.cos(wave * y))
        operator = PeriodicSurfaceOperator(grid, PAIR)
        for eps in (0.1, 0.05, 0.025) if n == 512 else (0.05, 0.025):
            solution = solve_normal(operator, gap, (1 - eps) * full * PERIOD**2, tolerance=1e-10)
            assert solution.converged
            assert contact_spots(solution.pressure <= 0, periodic=True) == 2  # two holes
            out_of_contact = np.count_nonzero(solution.pressure <= 0) / n**2
            ratios[n, eps] = out_of_contact / (3 / (2 * math.pi) * eps)
    close = [abs(ratios[n, eps] - 1) for n in (256, 512) for eps in (0.05, 0.025)]
    assert max(close) < 0.01
    assert ratios[512, 0.1] - 1 > abs(ratios[512, 0.05] - 1)
    validation(
        "periodic mode: 2-D sinusoid near full contact, 1 - p/p* = 0.05 and 0.025, 256 / 512 "
        "cells a period",
        "Johnson, Greenwood & Higginson (1985): area out of contact (3 / 2 pi)(1 - p/p*)",
        f"area out of contact within {max(close):.1%} of the asymptote "
        f"(at 1 - p/p* = 0.1: {ratios[512, 0.1] - 1:+.1%}, the next order)",
    )


def test_friction_on_a_rough_periodic_interface_converges_towards_gross_slip():
    """Two rough-contacting steels (beta = 0), mu = 0.3, Q raised to 0.99 mu W: every increment
    converges, the stick area falls from the whole contact to a few cells, the shear's sum is Q
    and never exceeds mu p anywhere."""
    steel = {"behaviour": "elastic", "E": 210e9, "nu": 0.3}
    table = periodic_case(
        {**steel, "roughness": ROUGH},
        body1={**steel, "radius": "inf"},
        friction={"coefficient": 0.3},
    )
    table["load"] = {
        "path": [
            {"normal_force": 5.0, "steps": 2},
            {"tangential_force": [0.99 * 0.3 * 5.0, 0.0], "steps": 6},
        ]
    }
    case = solver.Case.from_dict(table)
    result = solver.solve(case)
    assert result.status == "converged", result.notes
    stick = result.history["stick_area"] / result.history["contact_area"]
    assert stick[1] == 1.0 and np.all(np.diff(stick[1:]) <= 0) and stick[-1] < 0.1
    area = case.surface_grid.cell_area
    assert result.shear_x.sum() * area == pytest.approx(0.99 * 0.3 * 5.0, rel=1e-9)
    traction = np.hypot(result.shear_x, result.shear_y)
    assert np.all(traction <= 0.3 * result.pressure * (1 + 1e-9) + 1e-12 * result.pressure.max())


def dissimilar_rough_case(swap: bool = False, n: int = 64) -> dict:
    """Aluminium on rough steel (Dundurs' beta = 0.117; ``swap``: the materials exchanged, beta
    = -0.117, the same heights), mu = 0.3: pressed in 2 steps, then Q to 0.9 mu W in 4."""
    steel = {"behaviour": "elastic", "E": 210e9, "nu": 0.3}
    aluminium = {"behaviour": "elastic", "E": 70e9, "nu": 0.33}
    first, second = (steel, aluminium) if swap else (aluminium, steel)
    table = periodic_case(
        {**second, "roughness": ROUGH},
        n=(n, n),
        body1={**first, "radius": "inf"},
        friction={"coefficient": 0.3},
    )
    table["load"] = {
        "path": [
            {"normal_force": 5.0, "steps": 2},
            {"tangential_force": [0.9 * 0.3 * 5.0, 0.0], "steps": 4},
        ]
    }
    return table


def test_dissimilar_periodic_bodies_slip_under_normal_load_and_the_sign_follows_beta():
    """The coupled slip-stick loop on a rough period (beta != 0; it stalled before the normal
    solve restarted from its penetrating cells): every increment converges, normal loading
    alone slips part of the contact (the coupling's shear), Q is carried exactly within the
    friction disks, and exchanging the materials (beta -> -beta, the same heights) gives the
    same pressure and the opposite coupling shear after the normal steps."""
    results = {}
    for swap in (False, True):
        case = solver.Case.from_dict(dissimilar_rough_case(swap))
        assert case.pair.dundurs_beta == pytest.approx(-0.11674 if swap else 0.11674, abs=1e-5)
        result = solver.solve(case)
        assert result.status == "converged", result.notes
        stick = result.history["stick_area"] / result.history["contact_area"]
        assert stick[1] < 1.0  # the coupling slips part of the contact under normal load
        assert stick[-1] < stick[2]
        area = case.surface_grid.cell_area
        assert result.shear_x.sum() * area == pytest.approx(0.9 * 0.3 * 5.0, rel=1e-9)
        traction = np.hypot(result.shear_x, result.shear_y)
        assert np.all(
            traction <= 0.3 * result.pressure * (1 + 1e-9) + 1e-12 * result.pressure.max()
        )
        table = dissimilar_rough_case(swap)
        table["load"]["path"] = table["load"]["path"][:1]
        results[swap] = solver.solve(solver.Case.from_dict(table))
    plain, swapped = results[False], results[True]
    scale = np.abs(plain.shear_x).max()
    assert scale > 0.01 * 0.3 * plain.pressure.max()  # a coupling shear to speak of
    assert np.allclose(swapped.pressure, plain.pressure, rtol=0, atol=1e-6 * plain.pressure.max())
    assert np.abs(swapped.shear_x + plain.shear_x).max() < 1e-3 * scale
    assert np.abs(swapped.shear_y + plain.shear_y).max() < 1e-3 * scale


def test_a_flat_period_gives_the_uniform_pressure_and_converges():
    """No heights to speak of (a flat map, a roughness of rms 5e-324 m): u = 0, the pressure is
    the mean pressure everywhere, and the solve says converged (its residual is scaled by the
    mean pressure's displacement over a cell when the displacements vanish)."""
    n = 16
    x = (np.arange(n) + 0.5) / n * PERIOD - PERIOD / 2
    tiny = {**ROUGH, "rms": 5e-324}
    for body2 in ({"surface": HeightMap(x, x, np.zeros((n, n)), "flat")}, {"roughness": tiny}):
        result = solver.solve(solver.Case.from_dict(periodic_case(body2)))
        assert result.status == "converged", result.notes
        mean = 5.0 / PERIOD**2
        assert np.allclose(result.pressure, mean, rtol=1e-12)
        assert result.history["contact_fraction"][-1] == 1.0


def test_absurd_periodic_domains_are_refused():
    for size in (5e-324, 1e300, -1.0, 0.0):
        with pytest.raises(solver.SpecError, match="^grid.size"):
            solver.Case.from_dict(periodic_case({"roughness": ROUGH}, size=(size, size)))
    for value in (1, 0, "yes", None):
        table = periodic_case({"roughness": ROUGH})
        table["grid"]["periodic"] = value
        with pytest.raises(solver.SpecError, match='^grid.periodic: must be true, false or "y"'):
            solver.Case.from_dict(table)


def _plastic_friction(rms: float, yield_stress: float = 1e9) -> solver.Result:
    """Rough steel pressed on elastic-plastic steel (beta = 0), then sheared to 0.99 mu W.

    One period of 1e-4 m on 32 x 32 cells (the shortest wavelength 8 cells), 16 layers half a
    cell thick; linear hardening sigma_Y = ``yield_stress`` + 10 GPa e_p; mu = 0.3, a mean
    pressure of 400 MPa.  ``rms`` 5e-324 m: flat bodies.
    """
    steel = {"E": 210e9, "nu": 0.3}
    rough = {"hurst": 0.8, "long_cutoff": 5e-5, "short_cutoff": 2.5e-5, "rms": rms, "seed": 5}
    hardening = {"law": "linear", "yield_stress": yield_stress, "modulus": 10e9}
    table = {
        "body1": {"behaviour": "elastic", "radius": "inf", **steel},
        "body2": {"behaviour": "elastic-plastic", "radius": "inf", **steel, "hardening": hardening},
        "friction": {"coefficient": 0.3},
        "grid": {"n": [32, 32, 16], "size": 1e-4, "depth": 2.5e-5, "periodic": True},
        "load": {
            "path": [
                {"normal_force": 4.0, "steps": 2},
                {"tangential_force": [0.99 * 0.3 * 4.0, 0.0], "steps": 5},
            ]
        },
    }
    table["body2"]["roughness"] = rough
    return solver.solve(solver.Case.from_dict(table))


def test_friction_on_a_rough_elastic_plastic_interface():
    """Shear to gross slip on a rough elastic-plastic period: it converges, the stick spots
    shrink to a few cells, the shear raises the plastic strain; plasticity off it is the elastic
    interface, roughness off the smooth one (full stick, nothing yields)."""
    rough = _plastic_friction(2e-7)
    assert rough.status == "converged", rough.notes
    h = rough.history
    stick = h["stick_area"] / h["contact_area"]
    # pressed, nearly all sticks (the plastic strain's tangential print slips a few cells)
    assert stick[1] > 0.9 and np.all(np.diff(stick[1:]) <= 1e-12) and stick[-1] < 0.1
    assert rough.contact_state.max() == 2 and (rough.contact_state == 1).any()  # slip and stick
    sheared = h["max_plastic_strain"]
    assert sheared[1] > 1e-4 and sheared[-1] > 1.05 * sheared[1]  # the shear's plastic strain
    traction = np.hypot(rough.shear_x, rough.shear_y)
    assert np.all(traction <= 0.3 * rough.pressure * (1 + 1e-9) + 1e-12 * rough.pressure.max())
    # plasticity off: a yield stress nothing reaches gives the elastic interface's answer
    stiff = _plastic_friction(2e-7, yield_stress=2.1e10)
    assert stiff.history["max_plastic_strain"].max() == 0.0
    elastic_table = stiff.case.to_dict()
    elastic_table["body2"] = {**elastic_table["body2"], "behaviour": "elastic"}
    elastic_table["body2"].pop("hardening")
    elastic_table["grid"]["n"] = elastic_table["grid"]["n"][:2]
    elastic_table["grid"].pop("depth")
    elastic = solver.solve(solver.Case.from_dict(elastic_table))
    for name in ("contact_area", "stick_area"):
        assert np.array_equal(stiff.history[name], elastic.history[name]), name
    # to the tangential solve's tolerance (the plastic route warm-starts differently)
    scale = np.abs(elastic.shear_x).max()
    np.testing.assert_allclose(stiff.shear_x, elastic.shear_x, rtol=0, atol=1e-5 * scale)
    # roughness off: smaller asperities stick more and yield less; flat, all sticks, none yields
    finer, flat = _plastic_friction(2e-8), _plastic_friction(5e-324)
    fractions = [
        r.history["stick_area"][-1] / r.history["contact_area"][-1] for r in (rough, finer, flat)
    ]
    strains = [r.history["max_plastic_strain"].max() for r in (rough, finer, flat)]
    assert fractions[0] < fractions[1] <= fractions[2] == 1.0
    assert strains[0] > strains[1] >= strains[2] == 0.0


def test_a_contact_spot_narrower_than_ten_cells_is_told():
    """One spherical cap a period (R = 10 mm) pressed to a Hertz radius of a tenth of the
    period: its spot spans 2a / dx = 6.4 cells on 32 cells a period (told, with the measured
    diameter), 25.6 on 128 (not told)."""
    radius, period = 0.01, PERIOD
    a = 0.1 * period
    force = 4 * PAIR.composite_modulus * a**3 / (3 * radius)  # Hertz: a^3 = 3 W R / (4 E*)
    told = {}
    for n in (32, 128):
        x = (np.arange(n) + 0.5 - n / 2) * period / n
        xx, yy = np.meshgrid(x, x)
        cap = np.minimum(xx**2 + yy**2, (0.3 * period) ** 2) / (2 * radius)
        table = periodic_case({"surface": HeightMap(x, x, cap, "cap")}, (n, n), force=force)
        result = solver.solve(solver.Case.from_dict(table))
        assert result.status == "converged"
        told[n] = [note for note in result.notes if "largest contact spot" in note]
    assert len(told[32]) == 1 and not told[128]
    across = float(re.search(r"spans ([\d.]+) cells", told[32][0]).group(1))
    assert across == pytest.approx(2 * a / (period / 32), rel=0.05)  # 6.38: cells, images
