"""Normal contact against Hertz: circular, elliptic, two elastic bodies; errors fall with n."""

import copy
import math
import sys

import numpy as np
import pytest

import solver
from solver.theory.hertz import hertz


def contact_radius(result):
    return math.sqrt(np.count_nonzero(result.pressure) * result.grid.cell_area / math.pi)


def errors(table, n):
    table["grid"]["n"] = n
    result = solver.solve(solver.Case.from_dict(table))
    ref = result.case.hertz
    assert result.converged
    return result, {
        "pmax": abs(result.pressure.max() / ref.max_pressure - 1),
        "radius": abs(contact_radius(result) - ref.radius),
        "approach": abs(result.history["approach"][-1] / ref.approach - 1),
        "force": abs(result.history["normal_force"][-1] / ref.normal_force - 1),
    }


@pytest.mark.validation
def test_rigid_sphere_on_steel_converges_to_hertz(hertz_table, validation):
    coarse, e64 = errors(hertz_table, 64)
    fine, e128 = errors(hertz_table, 128)
    assert e128["pmax"] <= 1e-3
    assert e128["radius"] <= fine.grid.dx
    assert e128["approach"] <= 5e-3
    assert e128["force"] < 1e-12
    # refinement: peak-pressure and approach errors shrink by at least 3x (second order)
    assert e128["pmax"] < e64["pmax"] / 3
    assert e128["approach"] < e64["approach"] / 3
    assert e128["radius"] < e64["radius"]
    validation(
        "Hertz, rigid sphere on steel, p_H = 6 GPa, 64^2 / 128^2",
        "Hertz: p_H, a_H, approach (`solver.theory.hertz.hertz`)",
        f"p_max error {e64['pmax']:.1e} / {e128['pmax']:.1e}, contact radius "
        f"{e64['radius'] / coarse.grid.dx:.2f} / {e128['radius'] / fine.grid.dx:.2f} cells, "
        f"approach {e64['approach']:.1e} / {e128['approach']:.1e}",
    )


def test_hertz_pressure_profile_and_self_similar_steps(hertz_table):
    hertz_table["load"]["steps"] = 3
    result, _ = errors(hertz_table, 96)
    pair = result.case.pair
    x, y = result.grid.mesh()
    for k, force in enumerate(result.history["normal_force"]):
        ref = hertz(force, pair.composite_modulus, pair.curvature)
        assert result.history["max_pressure"][k] == pytest.approx(ref.max_pressure, rel=2e-3)
        assert result.history["approach"][k] == pytest.approx(ref.approach, rel=5e-3)
    profile_error = np.abs(result.pressure - result.case.hertz.pressure(x, y)).max()
    assert profile_error < 0.06 * result.case.hertz.max_pressure  # edge cells carry the largest


def semi_axis(coordinate, pressure_row):
    """Semi-axis from a least-squares fit of the Hertz law p^2 = p0^2 (1 - x^2/a^2) on a row."""
    inside = pressure_row > 0
    slope, intercept = np.polyfit(coordinate[inside] ** 2, pressure_row[inside] ** 2, 1)
    return np.sqrt(-intercept / slope)


@pytest.mark.validation
def test_elliptic_contact(hertz_table, validation):
    hertz_table["body1"] = {"radius_x": 0.015, "radius_y": 0.045, "behaviour": "rigid"}
    hertz_table["grid"]["half_width"] = 1.3
    errors = []
    for n in (80, 160):
        result, err = errors_at(hertz_table, n)
        ref = result.case.hertz
        assert ref.semi_axis_y > 1.5 * ref.semi_axis_x  # really elliptic
        i, j = np.unravel_index(np.argmax(result.pressure), result.pressure.shape)
        a = semi_axis(result.grid.x, result.pressure[:, j])
        b = semi_axis(result.grid.y, result.pressure[i, :])
        errors.append(max(abs(a / ref.semi_axis_x - 1), abs(b / ref.semi_axis_y - 1)))
        assert errors[-1] < 0.01
        assert err["pmax"] < 0.01
        assert err["approach"] < 0.01
    assert errors[1] < errors[0]
    validation(
        "elliptic Hertz (R_y = 3 R_x), 80^2 / 160^2",
        "Johnson §4.2: semi-axes from a fit of p^2 on the axes",
        f"largest semi-axis error {errors[0]:.1e} / {errors[1]:.1e}",
    )


def errors_at(table, n):
    return errors(copy.deepcopy(table), n)


@pytest.mark.validation
def test_two_elastic_bodies_use_the_composite_modulus(hertz_table, validation):
    hertz_table["body1"] = {"radius": 0.01, "behaviour": "elastic", "E": 210e9, "nu": 0.3}
    hertz_table["body2"] = {"radius": 0.02, "behaviour": "elastic", "E": 70e9, "nu": 0.33}
    hertz_table["load"] = {"normal_force": 500.0}
    result, err = errors(hertz_table, 128)
    expected_modulus = 1 / ((1 - 0.09) / 210e9 + (1 - 0.33**2) / 70e9)
    assert result.case.pair.composite_modulus == pytest.approx(expected_modulus, rel=1e-14)
    assert err["pmax"] < 1e-3 and err["approach"] < 5e-3
    assert err["radius"] <= result.grid.dx
    validation(
        "steel sphere on aluminium sphere, 128^2",
        "Hertz with the composite modulus E*",
        f"p_max {err['pmax']:.1e}, approach {err['approach']:.1e}, contact radius "
        f"{err['radius'] / result.grid.dx:.2f} cells",
    )


def test_elliptic_reference_limits():
    circ = hertz(1000.0, 1e11, (100.0, 100.0))
    near = hertz(1000.0, 1e11, (100.0, 100.0 * (1 + 1e-7)))
    assert near.semi_axis_x == pytest.approx(circ.radius, rel=1e-6)
    assert near.max_pressure == pytest.approx(circ.max_pressure, rel=1e-6)
    assert near.approach == pytest.approx(circ.approach, rel=1e-6)
    assert circ.max_pressure == pytest.approx(3 * 1000 / (2 * math.pi * circ.radius**2))


def test_iteration_cap_is_reported_not_raised(hertz_table):
    hertz_table["solver"] = {"normal_max_iterations": 2}
    result = solver.solve(solver.Case.from_dict(hertz_table))
    assert not result.converged and result.status == "not_converged"
    assert "not converged" in result.notes[0]
    assert np.isfinite(result.pressure).all()
    assert result.to_xarray().attrs["converged"] == 0


def test_solver_is_pure_numerics():
    import subprocess

    code = (
        "import sys, solver; solver.solve(solver.Case.from_dict(" + repr(_small()) + "))"
        ".to_xarray(); bad = [m for m in ('mpi4py', 'netCDF4', 'h5py', 'h5netcdf') "
        "if m in sys.modules]; assert not bad, bad"
    )
    subprocess.run([sys.executable, "-c", code], check=True)


def _small():
    from conftest import RIGID_SPHERE_ON_STEEL

    return RIGID_SPHERE_ON_STEEL


def test_dataset_layout(hertz_table):
    ds = solver.solve(solver.Case.from_dict(hertz_table)).to_xarray()
    for name in ("pressure", "normal_force", "approach", "max_pressure", "contact_area"):
        assert "units" in ds[name].attrs and "long_name" in ds[name].attrs
    assert ds.pressure.dims == ("x", "y") and ds.normal_force.dims == ("step",)
    for attr in (
        "hertz_radius",
        "hertz_pressure",
        "hertz_approach",
        "composite_modulus",
        "dundurs_beta",
        "friction_coefficient",
        "loops",
        "converged",
        "wall_time",
    ):
        assert attr in ds.attrs
    assert ds.attrs["loops"] == "load_steps normal"
    assert ds.x.attrs["units"] == "m"
    assert float(ds.x.mean()) == pytest.approx(0.0, abs=1e-18)


@pytest.mark.validation
def test_stress_output_matches_hertz_axis(hertz_table, validation):
    hertz_table["grid"] = {"n": [64, 64, 24], "half_width": 1.6, "depth": 1.5}
    hertz_table["output"] = {"fields": ["stress"]}
    ds = solver.solve(solver.Case.from_dict(hertz_table)).to_xarray()
    assert ds.stress.dims == ("component", "x", "y", "z") and ds.z.attrs["units"] == "m"
    a, p0 = ds.attrs["hertz_radius"], ds.attrs["hertz_pressure"]
    axis = ds.stress.sel(x=0, y=0, method="nearest")
    z = ds.z.values
    expected = -p0 / (1 + (z / a) ** 2)  # Johnson eq. 3.45, sigma_z on the axis
    np.testing.assert_allclose(axis.sel(component="zz"), expected, atol=0.01 * p0)
    peak = ds.von_mises.sel(x=0, y=0, method="nearest")
    assert float(peak.max()) / p0 == pytest.approx(0.620, rel=0.01)
    assert float(z[int(np.argmax(peak.values))]) / a == pytest.approx(0.481, abs=1.5 * 1.5 / 24)
    validation(
        "stress output on the Hertz axis, 64^2 x 24",
        "Johnson eq. 3.45 sigma_z; largest von Mises 0.620 p_H at z = 0.481 a",
        f"sigma_z within {float(abs(axis.sel(component='zz') - expected).max()) / p0:.1e} p_H; "
        f"von Mises {float(peak.max()) / p0:.4f} p_H at z = "
        f"{float(z[int(np.argmax(peak.values))]) / a:.3f} a",
    )


def test_stress_output_needs_a_volume_grid(hertz_table):
    hertz_table["output"] = {"fields": ["stress"]}
    with pytest.raises(solver.SpecError, match="output.fields"):
        solver.Case.from_dict(hertz_table)
