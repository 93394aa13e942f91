"""Single precision for the 3-D eigenstrain convolution: what it changes and what it refuses."""

import numpy as np
import pytest

import solver
from solver.numerics.grid import SurfaceGrid, VolumeGrid
from solver.volume.eigenstrain import EigenstrainOperator

SWIFT = {"law": "swift", "B": 945e6, "C": 20.0, "n": 0.121}


def indentation(precision=None, tolerance=None, mu=0.3):
    solver_table = {}
    if precision:
        solver_table["volume_precision"] = precision
    if tolerance:
        solver_table["plastic_tolerance"] = tolerance
    return {
        "body1": {"behaviour": "rigid", "radius": 0.015},
        "body2": {
            "behaviour": "elastic-plastic",
            "radius": "inf",
            "E": 210e9,
            "nu": 0.3,
            "hardening": SWIFT,
        },  # fmt: skip
        "load": {"path": [{"hertz_pressure": 6e9, "steps": 4}, {"normal_force": 0.0}]},
        "friction": {"coefficient": mu},
        "grid": {"n": [24, 24, 16]},
        "solver": solver_table,
    }


def test_single_precision_operator_agrees_with_double_to_its_rounding():
    grid = VolumeGrid(SurfaceGrid(20, 18, 1e-5, 1e-5), 12, 1e-5)
    rng = np.random.default_rng(5)
    e = rng.normal(size=(6,) + grid.shape) * 1e-3
    e[2] = -(e[0] + e[1])
    stresses = []
    for precision in ("double", "single"):
        op = EigenstrainOperator(grid, 210e9, 0.3, precision=precision)
        stresses.append(op.deviatoric_stress_with_tractions(e, op.layer_spectra(e), {}))
    double, single = stresses
    error = np.abs(single - double).max() / np.abs(double).max()
    assert 1e-12 < error < 1e-6  # float32 rounding: not double's, far below any tolerance


def test_single_precision_case_gives_the_double_answer_within_the_plasticity_tolerance():
    double_case = solver.Case.from_dict(indentation())
    single_case = solver.Case.from_dict(indentation("single"))
    assert "volume_precision" not in double_case.spec["solver"]  # double ids as before
    assert single_case.case_id != double_case.case_id
    double, single = solver.solve(double_case), solver.solve(single_case)
    assert double.converged and single.converged, single.notes
    yield_strain = SWIFT["B"] * SWIFT["C"] ** SWIFT["n"] / 210e9
    tolerance = 10 * double_case.solver.plastic_tolerance * yield_strain
    np.testing.assert_allclose(
        single.fields["plastic_strain"], double.fields["plastic_strain"], rtol=0, atol=tolerance
    )
    np.testing.assert_allclose(
        single.history["residual_depth"], double.history["residual_depth"], rtol=1e-5
    )
    np.testing.assert_allclose(single.pressure, double.pressure, rtol=0, atol=1e-6 * 6e9)


@pytest.mark.parametrize(
    "precision, tolerance, message",
    [
        ("single", 1e-7, "solver.volume_precision: single precision rounds the stress"),
        ("half", None, 'solver.volume_precision: must be "double" or "single"'),
    ],
)
def test_unusable_precisions_are_refused_by_name(precision, tolerance, message):
    with pytest.raises(solver.SpecError, match=message):
        solver.Case.from_dict(indentation(precision, tolerance))
