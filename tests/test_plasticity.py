"""Hardening laws, tensor conventions and the radial-return mapping at single material points."""

import numpy as np
import pytest
from scipy.optimize import brentq

from solver.numerics.tensor import (
    deviator,
    equivalent_strain,
    from_matrix,
    norm,
    to_matrix,
    von_mises,
)
from solver.plasticity.hardening import SWIFT_STRAIN_UNIT, Hardening
from solver.plasticity.return_mapping import RETURN_MAX_ITERATIONS, return_mapping

E, NU = 210e9, 0.3
G = E / (2 * (1 + NU))
K = E / (3 * (1 - 2 * NU))
SWIFT = Hardening("swift", B=945e6, C=20.0, n=0.121)
LINEAR = Hardening("linear", yield_stress=1.3579e9, modulus=152.3e9)
PERFECT = Hardening("perfect", yield_stress=1.3579e9)
LAWS = {"swift": SWIFT, "linear": LINEAR, "perfect": PERFECT}


# -- tensor conventions ---------------------------------------------------------------------------
def test_tensor_conventions_match_matrix_algebra():
    rng = np.random.default_rng(0)
    a = rng.normal(size=(6, 5))
    b = rng.normal(size=(6, 5))
    ma, mb = to_matrix(a), to_matrix(b)
    np.testing.assert_allclose(from_matrix(ma), a)
    contraction = np.einsum("kij,kij->k", ma, mb)
    np.testing.assert_allclose(norm(a) ** 2, np.einsum("kij,kij->k", ma, ma))
    dev = ma - np.trace(ma, axis1=1, axis2=2)[:, None, None] / 3 * np.eye(3)
    np.testing.assert_allclose(to_matrix(deviator(a)), dev, atol=1e-14)
    j2 = 0.5 * np.einsum("kij,kij->k", dev, dev)
    np.testing.assert_allclose(von_mises(a), np.sqrt(3 * j2))
    assert contraction.shape == (5,)
    # uniaxial stress -> |sigma|; uniaxial isochoric plastic strain -> |e|
    uniaxial = np.array([-3.0, 0, 0, 0, 0, 0])
    assert von_mises(uniaxial) == pytest.approx(3.0)
    assert equivalent_strain(np.array([0.02, -0.01, -0.01, 0, 0, 0])) == pytest.approx(0.02)


# -- hardening laws -----------------------------------------------------------------------------
def test_swift_keeps_the_papers_parameters_and_micro_strain_unit():
    assert SWIFT.initial_yield_stress == pytest.approx(945e6 * 20**0.121, rel=1e-14)
    e = 0.01
    assert SWIFT.flow_stress(e) == pytest.approx(945e6 * (20 + 1e4) ** 0.121)
    slope0 = 945e6 * 0.121 * SWIFT_STRAIN_UNIT * 20 ** (0.121 - 1)
    assert SWIFT.slope(0.0) == pytest.approx(slope0)
    assert 7000e9 < slope0 < 9000e9  # the "about 8000 GPa" of the design notes


@pytest.mark.parametrize("law", LAWS)
def test_hardening_slope_is_the_derivative(law):
    h = LAWS[law]
    e = np.array([1e-10, 1e-7, 1e-5, 1e-3, 0.05])
    step = 1e-4 * np.maximum(e, 1e-7)
    numeric = (h.flow_stress(e + step) - h.flow_stress(e - step)) / (2 * step)
    np.testing.assert_allclose(h.slope(e), numeric, rtol=1e-6, atol=1.0)


# -- strain-driven single-point paths -------------------------------------------------------------
class MaterialPoint:
    """A strain-driven material point: elastic predictor, radial return."""

    def __init__(self, hardening):
        self.hardening = hardening
        self.stress = np.zeros(6)
        self.plastic = np.zeros(6)
        self.equivalent = 0.0

    def step(self, strain_increment):
        trial = self.stress + 2 * G * deviator(strain_increment)
        trial[:3] += K * (strain_increment[0] + strain_increment[1] + strain_increment[2])
        result = return_mapping(trial, self.equivalent, self.hardening, G)
        assert result.converged
        self.stress = result.stress
        self.plastic = self.plastic + result.plastic_strain_increment
        self.equivalent = self.equivalent + float(result.equivalent_increment)
        return result


def closed_form_plastic_strain(hardening, equivalent_total_strain):
    """e_p with sigma_Y(e_p) = 3 G (eps_eq - e_p) along an isochoric proportional path."""
    if 3 * G * equivalent_total_strain <= hardening.initial_yield_stress:
        return 0.0
    return brentq(
        lambda e: hardening.flow_stress(e) - 3 * G * (equivalent_total_strain - e),
        0.0,
        equivalent_total_strain,
        xtol=1e-16,
        rtol=1e-14,
    )


@pytest.mark.validation
@pytest.mark.parametrize("law", LAWS)
@pytest.mark.parametrize("steps", [1, 7, 50])
@pytest.mark.parametrize("path", ["uniaxial", "shear"])
def test_proportional_paths_match_closed_forms(law, steps, path, validation):
    """Isochoric uniaxial strain diag(e, -e/2, -e/2) and simple shear e_xz: closed forms."""
    hardening = LAWS[law]
    point = MaterialPoint(hardening)
    final = 0.03
    if path == "uniaxial":
        direction = np.array([1.0, -0.5, -0.5, 0, 0, 0])  # equivalent strain = amplitude
    else:
        direction = np.array([0, 0, 0, 0, np.sqrt(3) / 2, 0])  # equivalent strain = amplitude
    for _ in range(steps):
        point.step(direction * final / steps)
    expected = closed_form_plastic_strain(hardening, final)
    assert point.equivalent == pytest.approx(expected, rel=1e-9)
    # the stress is on the yield surface, and the plastic strain has the direction of the path
    sigma_y = float(hardening.flow_stress(point.equivalent))
    assert norm(deviator(point.stress)) == pytest.approx(np.sqrt(2 / 3) * sigma_y, rel=1e-10)
    np.testing.assert_allclose(point.plastic, expected * direction, rtol=1e-9, atol=1e-18)
    assert von_mises(point.stress) == pytest.approx(3 * G * (final - expected), rel=1e-9)
    validation(
        "return mapping, uniaxial and shear paths to 3 %, Swift / linear / perfect, 1-50 steps",
        "sigma_Y(e_p) = 3 G (e_eq - e_p), solved in closed form or by bisection",
        abs(point.equivalent / expected - 1),
    )


def test_elastic_unloading_and_reloading_add_no_plastic_strain():
    point = MaterialPoint(SWIFT)
    direction = np.array([1.0, -0.5, -0.5, 0, 0, 0])
    for _ in range(10):
        point.step(direction * 0.002)
    stress, plastic = point.stress.copy(), point.equivalent
    # unload halfway and reload: purely elastic (isotropic hardening)
    result = point.step(-direction * 0.003)
    assert not result.plastic.any()
    np.testing.assert_allclose(point.stress, stress - 2 * G * direction * 0.003, rtol=1e-12)
    point.step(direction * 0.003)
    assert point.equivalent == plastic
    np.testing.assert_allclose(point.stress, stress, rtol=1e-12, atol=1e-3)


def test_below_yield_is_elastic():
    trial = np.zeros((6, 3))
    trial[0] = np.array([0.5, 0.99, 0.999999]) * SWIFT.initial_yield_stress
    result = return_mapping(trial, np.zeros(3), SWIFT, G)
    assert not result.plastic.any()
    assert np.all(result.plastic_strain_increment == 0)
    np.testing.assert_array_equal(result.stress, trial)


@pytest.mark.validation
@pytest.mark.parametrize("law", LAWS)
def test_non_proportional_path_converges_with_step_refinement(law, validation):
    """Uniaxial then shear (a 90 degree turn): consistency at every step, first-order in steps."""
    hardening = LAWS[law]
    uniaxial = np.array([1.0, -0.5, -0.5, 0, 0, 0]) * 0.012
    shear = np.array([0, 0, 0, 0, np.sqrt(3) / 2, 0]) * 0.012

    def run(steps):
        point = MaterialPoint(hardening)
        for segment in (uniaxial, shear):
            for _ in range(steps):
                result = point.step(segment / steps)
                if result.plastic.any():
                    sigma_y = float(hardening.flow_stress(point.equivalent))
                    assert von_mises(point.stress) == pytest.approx(sigma_y, rel=1e-10)
        return point

    reference = run(4096)
    errors = [
        np.abs(run(n).plastic - reference.plastic).max() / reference.equivalent
        for n in (8, 32, 128)
    ]
    assert errors[2] < errors[1] < errors[0]
    assert errors[0] / errors[2] > 8  # at least first order over a factor 16 in steps
    validation(
        "return mapping, a 90-degree non-proportional path (uniaxial, then shear)",
        "the same path in 4096 steps",
        f"{law}: error with 8 / 32 / 128 steps " + " / ".join(f"{e:.1e}" for e in errors),
    )
    assert run(1).equivalent > 0  # large steps stay finite and on the yield surface


@pytest.mark.validation
def test_swift_newton_never_fails(validation):
    """Trial stresses from just above yield to 1000 sigma_Y, prior strains 0 to 0.5."""
    rng = np.random.default_rng(1)
    n = 20000
    directions = rng.normal(size=(6, n))
    directions = deviator(directions) / von_mises(directions)
    e0 = np.concatenate([np.zeros(n // 4), 10 ** rng.uniform(-9, np.log10(0.5), n - n // 4)])
    sigma_y = SWIFT.flow_stress(e0)
    ratio = np.concatenate(
        [1 + 10 ** rng.uniform(-12, -3, n // 2), 10 ** rng.uniform(0, 3, n - n // 2)]
    )
    trial = directions * (ratio * sigma_y)
    trial[:3] += rng.normal(size=(3, n)).mean(axis=0) * 1e9  # hydrostatic part: irrelevant
    result = return_mapping(trial, e0, SWIFT, G)
    assert result.converged and result.iterations < RETURN_MAX_ITERATIONS
    assert result.plastic.all()
    assert np.all(np.isfinite(result.stress)) and np.all(result.equivalent_increment > 0)
    final = SWIFT.flow_stress(e0 + result.equivalent_increment)
    np.testing.assert_allclose(von_mises(result.stress), final, rtol=1e-10)
    # consistency |s| = sqrt(2/3) sigma_Y
    np.testing.assert_allclose(norm(deviator(result.stress)), np.sqrt(2 / 3) * final, rtol=1e-10)
    # the hydrostatic part is untouched
    np.testing.assert_allclose(
        result.stress[:3].sum(axis=0), trial[:3].sum(axis=0), rtol=1e-12, atol=1e-3
    )
    validation(
        "Swift Newton return, 20,000 random trial states up to 1000 sigma_Y",
        "consistency |s| = sqrt(2/3) sigma_Y(e_p)",
        f"all converged in at most {int(np.max(result.iterations))} iterations; consistency "
        f"{np.abs(von_mises(result.stress) / final - 1).max():.0e}",
    )
