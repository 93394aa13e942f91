"""Laterally periodic volume operators: the stress of tractions and of eigenstrains in one period.

The periodised cell kernels (:mod:`solver.numerics.images`) are checked against independent
computations: the closed forms of laterally uniform loads and layers, the Fourier series of a
periodic traction (:func:`solver.theory.half_space.periodic_traction_stress`), and the
non-periodic operator applied to many copies of the period.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import solver
from solver.bodies.heights import HeightMap
from solver.numerics.grid import SurfaceGrid, VolumeGrid
from solver.numerics.tensor import von_mises
from solver.theory.half_space import (
    periodic_traction_stress,
    uniform_layer_stress,
    uniform_traction_stress,
)
from solver.volume.eigenstrain import EigenstrainOperator
from solver.volume.stress import SubsurfaceStressOperator

E, NU = 210e9, 0.3


def periodic_grid(n: int, nz: int, period: float = 1.0) -> VolumeGrid:
    dx = period / n
    return VolumeGrid(SurfaceGrid(n, n, dx, dx), nz, dx, periodic=True)


def blob(n: int, nz: int, centre=(0.4, 0.6, 0.15), width=(0.14, 0.1)) -> np.ndarray:
    """A smooth bump over one unit period, ``(n, n, nz)`` (cubic cells)."""
    x = (np.arange(n) + 0.5) / n
    z = (np.arange(nz) + 0.5) / n
    lateral = (x[:, None] - centre[0]) ** 2 + (x[None, :] - centre[1]) ** 2
    return np.exp(-lateral / width[0] ** 2)[:, :, None] * np.exp(
        -(((z - centre[2]) / width[1]) ** 2)
    )


def deviatoric_field(n: int, nz: int, seed: int = 1) -> np.ndarray:
    """A trace-free eigenstrain: six random amplitudes of one bump."""
    amplitudes = np.random.default_rng(seed).normal(size=6)
    field = amplitudes[:, None, None, None] * blob(n, nz)[None]
    field[:3] -= field[:3].sum(axis=0) / 3.0
    return field


@pytest.mark.parametrize("traction", ["pressure", "shear_x", "shear_y"])
def test_a_uniform_traction_gives_the_uniform_stress_of_a_periodic_body(traction):
    """Uniaxial strain under a mean pressure, simple shear under a mean shear: to round-off."""
    grid = periodic_grid(16, 6)
    stress = SubsurfaceStressOperator(grid, NU).stress(**{traction: np.full((16, 16), 2.0)})
    expected = 2.0 * uniform_traction_stress(traction, NU)
    assert np.abs(stress - expected[:, None, None, None]).max() < 1e-12


@pytest.mark.validation
def test_periodic_traction_stress_agrees_with_the_fourier_series_and_converges(validation):
    """Cell kernels against the Fourier series of smooth tractions: error ~ dx^2."""
    errors = []
    for n in (32, 64, 128):
        x = (np.arange(n) + 0.5) / n
        X, Y = np.meshgrid(x, x, indexing="ij")
        p = 1.0 + 0.5 * np.cos(2 * np.pi * X) * np.sin(4 * np.pi * Y)
        p += 0.3 * np.exp(-((X - 0.5) ** 2 + (Y - 0.4) ** 2) / 0.01)
        qx = 0.3 + 0.2 * np.sin(2 * np.pi * (X + 2 * Y))
        qy = -0.1 + 0.2 * np.exp(-((X - 0.3) ** 2 + (Y - 0.6) ** 2) / 0.02)
        grid = periodic_grid(n, n // 4)
        ours = SubsurfaceStressOperator(grid, NU).stress(pressure=p, shear_x=qx, shear_y=qy)
        series = periodic_traction_stress((1.0, 1.0), grid.z, NU, p, qx, qy)
        # below the first two layers (there the cells' steps differ from the smooth field)
        errors.append(np.abs(ours - series)[..., 2:].max() / np.abs(series).max())
    assert errors[-1] < 5e-4
    assert errors[0] > 2.0 * errors[1] > 4.0 * errors[2]
    validation(
        "periodic subsurface stress of pressure and shears (cell kernels summed over the "
        "periods), 32 / 64 / 128 cells a period",
        "Fourier series of the tractions (plane-strain modes; uniaxial strain and simple shear "
        "for the means)",
        " / ".join(f"{e:.1e}" for e in errors) + " of the peak",
    )


def test_a_uniform_eigenstrain_layer_gives_its_closed_form():
    """Any eigenstrain in a layer: the closed-form stress inside, none outside, to round-off."""
    n, nz, layer = 16, 8, 3
    operator = EigenstrainOperator(periodic_grid(n, nz), E, NU)
    values = np.random.default_rng(0).normal(size=6)
    for trace_free in (False, True):
        if trace_free:
            values[:3] -= values[:3].mean()
        field = np.zeros((6, n, n, nz))
        field[..., layer] = values[:, None, None]
        stress = operator.stress(field)
        inside = uniform_layer_stress(E, NU) @ values
        scale = np.abs(inside).max()
        assert np.abs(stress[..., layer] - inside[:, None, None]).max() < 1e-12 * scale
        assert np.abs(np.delete(stress, layer, axis=-1)).max() < 1e-12 * scale
    # the surface sinks by the layer's thickness change: e_zz (1 - 2 nu) / (1 - nu) h
    u_z = operator.surface_displacement(field)[2]
    expected = -operator.grid.dz * values[2] * (1 - 2 * NU) / (1 - NU)
    assert np.abs(u_z - expected).max() < 1e-12 * abs(expected)


@pytest.mark.validation
def test_periodic_eigenstrain_stress_is_the_stress_of_many_copies(validation):
    """One period against the non-periodic operator on 9 x 9 copies (a zero-mean field).

    A field with no mean in any layer acts at a distance like a multipole, so the copies
    beyond the 9 x 9 block add little: the two computations agree to about 1e-4 of the peak.
    """
    n, nz, copies = 16, 8, 9
    field = deviatoric_field(n, nz)
    field -= field.mean(axis=(1, 2), keepdims=True)
    periodic = EigenstrainOperator(periodic_grid(n, nz), E, NU).stress(field)
    side = copies * n
    wide = VolumeGrid(SurfaceGrid(side, side, 1.0 / n, 1.0 / n), nz, 1.0 / n)
    tiled = EigenstrainOperator(wide, E, NU).stress(np.tile(field, (1, copies, copies, 1)))
    middle = slice(copies // 2 * n, (copies // 2 + 1) * n)
    centre = tiled[:, middle, middle]
    error = np.abs(periodic - centre).max() / np.abs(periodic).max()
    assert error < 5e-4
    validation(
        "periodic residual stress of a zero-mean eigenstrain, 16^2 x 8 cells",
        "the non-periodic operator on 9 x 9 copies of the period",
        f"{error:.1e} of the peak",
    )


def test_the_direct_displacement_route_is_refused_on_a_periodic_grid():
    operator = EigenstrainOperator(periodic_grid(8, 4), E, NU)
    with pytest.raises(ValueError, match="reciprocal"):
        operator.surface_displacement(np.zeros((6, 8, 8, 4)), method="direct")


# -- a periodic elastic-plastic case: first yield of Westergaard's sinusoid in full contact --

PERIOD, AMPLITUDE = 1e-4, 5e-8  # m


def sinusoid_case(n: int, yield_stress: float, mean_over_full: float) -> dict:
    """A rigid flat on an elastic-plastic body whose surface is a periodic sinusoid along x.

    A square period of ``n x n`` cells (the periodic kernels sum the nearest periods, so the
    volume must be shallow against both sides), cubic cells down to 3/8 of the period.
    """
    dx = PERIOD / n
    x = (np.arange(n) + 0.5) * dx - PERIOD / 2
    heights = AMPLITUDE * (1 - np.cos(2 * np.pi * x / PERIOD))[None, :] * np.ones((n, 1))
    full = math.pi * E / (1 - NU**2) * AMPLITUDE / PERIOD
    return {
        "body1": {"behaviour": "rigid", "radius": "inf"},
        "body2": {
            "behaviour": "elastic-plastic", "E": E, "nu": NU, "radius": "inf",
            "surface": HeightMap(x, x, heights, "sinusoid"),
            "hardening": {"law": "linear", "yield_stress": yield_stress, "modulus": 20e9},
        },
        "load": {"normal_force": mean_over_full * full * PERIOD**2, "steps": 2},
        "grid": {"n": [n, n, 3 * n // 8], "size": PERIOD, "periodic": True,
                 "depth": 0.375 * PERIOD},
    }  # fmt: skip


def sinusoid_von_mises(mean_over_full: float) -> float:
    """Largest von Mises stress of the sinusoid in full contact (Fourier series, fine grid)."""
    n = 256
    full = math.pi * E / (1 - NU**2) * AMPLITUDE / PERIOD
    x = (np.arange(n) + 0.5) / n
    pressure = full * (mean_over_full + np.cos(2 * np.pi * x))[:, None] * np.ones((1, 2))
    z = np.linspace(0.0, 0.5, 257)[1:] * PERIOD
    stress = periodic_traction_stress((PERIOD, 2 * PERIOD / n), z, NU, pressure)
    return float(von_mises(stress).max())


@pytest.mark.validation
def test_the_periodic_sinusoid_yields_where_its_elastic_stress_says(validation):
    """Full contact (mean pressure 1.5 p*): no plastic strain at 1.03 of the largest von Mises
    stress of the Fourier series (with the mean pressure's uniaxial strain), some at 0.97."""
    peak = sinusoid_von_mises(1.5)
    strains = {}
    for factor in (1.03, 0.97):
        result = solver.solve(solver.Case.from_dict(sinusoid_case(32, factor * peak, 1.5)))
        assert result.converged
        strains[factor] = result.history["max_plastic_strain"][-1]
    assert strains[1.03] == 0.0
    assert strains[0.97] > 0.0
    validation(
        "periodic elastic-plastic sinusoid in full contact (p = 1.5 p*), 32^2 x 12 cells",
        "first yield at the largest von Mises stress of the Fourier series",
        "no plastic strain at 1.03 of it, some at 0.97",
    )


def test_the_periodic_sinusoids_plastic_strain_converges_with_the_mesh():
    """Past first yield (sigma_Y0 at 0.9 of the elastic peak): e_p,max on 16, 32 and 64 cells
    per period converges at second order (successive changes shrink about fourfold)."""
    yield_stress = 0.9 * sinusoid_von_mises(1.5)
    strains = []
    for n in (16, 32, 64):
        result = solver.solve(solver.Case.from_dict(sinusoid_case(n, yield_stress, 1.5)))
        assert result.converged
        strains.append(result.history["max_plastic_strain"][-1])
    first, second = abs(strains[1] - strains[0]), abs(strains[2] - strains[1])
    assert strains[0] > 0.0
    assert second < first / 3.0
    assert second < 0.05 * strains[2]


def test_a_yield_region_deeper_than_half_the_period_is_refused():
    """The sinusoid with sigma_Y0 at 0.7 of its elastic peak: the mean pressure's uniaxial
    strain is close to yield at every depth and the modes push it over down past half the
    period, which the periodic kernels cannot hold."""
    table = sinusoid_case(16, 0.7 * sinusoid_von_mises(1.5), 1.5)
    del table["grid"]["depth"]
    with pytest.raises(solver.SpecError, match="^load.path: the elastic yield region spans"):
        solver.Case.from_dict(table)
