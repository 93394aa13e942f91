"""Kinematic hardening: closed forms of uniaxial cycles (Prager-Ziegler, Armstrong-Frederick).

A material-point driver: deviatoric strain increments along the uniaxial deviator ``d``
(``sigma_eq(sigma d) = |sigma|``), so the trial stress rises by ``3 G`` per unit of "equivalent
strain" and the stress stays ``sigma d``; the return mapping is the solver's.
"""

import numpy as np
import pytest

import solver
from solver.case.reading import SpecError
from solver.plasticity.hardening import Hardening
from solver.plasticity.return_mapping import return_mapping

G = 80e9
SIGMA_Y = 1.0e9
D = np.array([2 / 3, -1 / 3, -1 / 3, 0.0, 0.0, 0.0])


def drive(hardening, strains):
    """Stress (scalar along d), back stress and accumulated p along an equivalent-strain path."""
    stress, alpha, p = np.zeros((6, 1)), np.zeros((6, 1)), np.zeros(1)
    out = []
    previous = 0.0
    for strain in strains:
        trial = stress + 3.0 * G * (strain - previous) * D[:, None]
        mapped = return_mapping(trial, p, hardening, G, back_stress=alpha)
        assert mapped.converged
        stress, alpha = mapped.stress, mapped.back_stress
        p = p + mapped.equivalent_increment
        previous = strain
        out.append((stress[0, 0] / D[0], alpha[0, 0] / D[0], p[0], bool(mapped.plastic[0])))
    return np.array(out)


def prager(c):
    return Hardening("perfect", yield_stress=SIGMA_Y, kinematic_modulus=c)


def armstrong_frederick(c, gamma):
    return Hardening("perfect", yield_stress=SIGMA_Y, kinematic_modulus=c, kinematic_recall=gamma)


def test_prager_slope_is_exact_for_any_step():
    c = 50e9
    tangent = 3 * G * c / (3 * G + c)
    yield_strain = SIGMA_Y / (3 * G)
    for steps in (1, 7):
        strains = np.linspace(0, 4 * yield_strain, steps + 1)[1:]
        sigma = drive(prager(c), strains)[:, 0]
        expected = np.where(
            strains <= yield_strain, 3 * G * strains, SIGMA_Y + tangent * (strains - yield_strain)
        )
        np.testing.assert_allclose(sigma, expected, rtol=1e-10)


def test_prager_bauschinger_reverse_yield_at_sigma_max_minus_two_sigma_y():
    c = 50e9
    loaded = drive(prager(c), [0.03])[-1]
    sigma_max, alpha = loaded[0], loaded[1]
    assert alpha == pytest.approx(sigma_max - SIGMA_Y, rel=1e-10)  # on the surface
    reverse = sigma_max - 2 * SIGMA_Y  # not -sigma_max: the Bauschinger effect
    for margin, plastic in ((1e-6, False), (-1e-6, True)):
        target = reverse + margin * SIGMA_Y
        strain = 0.03 - (sigma_max - target) / (3 * G)
        row = drive(prager(c), [0.03, strain])[-1]
        assert row[3] == plastic
    # isotropic hardening of the same modulus would need the stress to reach -sigma_max
    assert reverse > -sigma_max + SIGMA_Y


@pytest.mark.validation
def test_armstrong_frederick_monotonic_back_stress_converges_to_its_closed_form(validation):
    c, gamma = 200e9, 400.0
    strain = 0.02
    errors = []
    for steps in (10, 40, 160):
        row = drive(armstrong_frederick(c, gamma), np.linspace(0, strain, steps + 1)[1:])[-1]
        sigma, alpha, p = row[0], row[1], row[2]
        expected = c / gamma * (1 - np.exp(-gamma * p))  # d alpha = (C - gamma alpha) dp
        assert sigma == pytest.approx(SIGMA_Y + alpha, rel=1e-10)
        errors.append(abs(alpha / expected - 1))
    assert errors[0] > errors[1] > errors[2] and errors[2] < 2e-3
    order = np.log(errors[0] / errors[2]) / np.log(16)
    assert order == pytest.approx(1.0, abs=0.15)  # backward Euler
    validation(
        "Armstrong-Frederick back stress, uniaxial to 2 %, 10 / 40 / 160 steps",
        "alpha = (C / gamma) (1 - exp(-gamma p))",
        " / ".join(f"{e:.1e}" for e in errors) + f" (order {order:.2f}, backward Euler)",
    )


@pytest.mark.validation
def test_armstrong_frederick_saturated_loop(validation):
    """Symmetric strain cycles: sigma_max = sigma_Y + (C/gamma) tanh(gamma dEp / 2)."""
    c, gamma = 200e9, 400.0
    amplitude = 0.01
    half = np.linspace(amplitude, -amplitude, 401)[1:]
    path = np.concatenate(
        [np.linspace(0, amplitude, 201)[1:]] + [np.concatenate([half, -half])] * 6
    )
    rows = drive(armstrong_frederick(c, gamma), path)
    last = rows[-800:]
    sigma_max = last[:, 0].max()
    # plastic strain range of the stable cycle from the stress and the elastic strain
    plastic_strain = path[-800:] - last[:, 0] / (3 * G)
    strain_range = np.ptp(plastic_strain)
    expected = SIGMA_Y + c / gamma * np.tanh(gamma * strain_range / 2)
    assert sigma_max == pytest.approx(expected, rel=2e-3)
    assert -last[:, 0].min() == pytest.approx(sigma_max, rel=1e-3)  # symmetric loop
    validation(
        "Armstrong-Frederick saturated loop, strain amplitude 1 %",
        "sigma_max = sigma_Y + (C / gamma) tanh(gamma dEp / 2)",
        f"{100 * abs(sigma_max / expected - 1):.2f} %",
    )


# -- in the contact loops ----------------------------------------------------------------------

SIGMA_Y0 = 1.3579e9


def indentation(hardening, cycles=1, steps=1, pressure=5e9, n=16, half_width=1.5):
    """A rigid sphere pressed into a flat (and lifted off) ``cycles`` times."""
    stages = [{"hertz_pressure": pressure, "steps": steps}]
    if cycles > 1:
        stages.append({"normal_force": 0.0, "steps": 2})
    path = [{"cycles": cycles, "stages": stages}] if cycles > 1 else stages
    table = {
        "body1": {"behaviour": "rigid", "radius": 0.015},
        "body2": {"behaviour": "elastic-plastic", "radius": "inf", "E": 210e9, "nu": 0.3,
                  "hardening": hardening},
        "load": {"path": path},
        "grid": {"n": [n, n, n], "half_width": half_width},
    }  # fmt: skip
    result = solver.solve(solver.Case.from_dict(table))
    assert result.converged, result.notes
    return result


@pytest.mark.validation
def test_prager_equals_linear_isotropic_hardening_in_one_loading_step(validation):
    """From a virgin body in one increment both return mappings give dp = f / (3 G + H)."""
    modulus = 152.3e9
    isotropic = indentation({"law": "linear", "yield_stress": SIGMA_Y0, "modulus": modulus})
    kinematic = indentation(
        {"law": "perfect", "yield_stress": SIGMA_Y0, "kinematic": {"law": "prager", "C": modulus}}
    )
    a, b = isotropic.fields["plastic_strain"], kinematic.fields["plastic_strain"]
    assert a.max() > 1e-3
    np.testing.assert_allclose(b, a, rtol=0, atol=1e-9 * a.max())
    validation(
        "kinematic hardening in the contact loops: Prager (C = H) against linear isotropic "
        "hardening, one loading step, 16^3",
        "the same return from a virgin state",
        f"plastic strain fields equal to {np.abs(b - a).max() / a.max():.0e} of e_p,max",
    )


@pytest.mark.validation
def test_repeated_indentation_reverse_yields_with_kinematic_hardening_only(validation):
    """A soft steel (sigma_Y0 = 0.8 GPa, modulus 15 GPa) indented to 8 GPa and lifted off 3
    times, the plastic zone inside the box (half_width 2.5 a_H: no face note).  On unloading
    the stress range exceeds 2 sigma_Y: isotropic hardening has grown the surface and shakes
    down after the first cycle; Prager's surface moves with the back stress, so the body yields
    in reverse on every unloading (the Bauschinger effect): alternating plasticity, a gain of
    equivalent plastic strain every cycle (0.56-0.59 % here; 0.52-0.55 % with 12 loading
    steps instead of 6), while the dent settles (its change per cycle shrinks: no ratchet)."""
    soft = 0.8e9
    kinds = {
        "isotropic": {"law": "linear", "yield_stress": soft, "modulus": 15e9},
        "prager": {"law": "perfect", "yield_stress": soft,
                   "kinematic": {"law": "prager", "C": 15e9}},
    }  # fmt: skip
    gained, dent = {}, {}
    for name, hardening in kinds.items():
        result = indentation(hardening, cycles=3, steps=6, pressure=8e9, n=28, half_width=2.5)
        assert not any("face" in note for note in result.notes), result.notes
        ds = result.to_xarray()
        gained[name] = ds.plastic_strain_increment.values
        ends = np.searchsorted(ds.step_cycle.values, [1, 2, 3], side="right") - 1
        dent[name] = ds.residual_depth.values[ends]  # lifted off at the end of each cycle
    tolerance = result.case.solver.plastic_tolerance
    assert np.all(gained["isotropic"][1:] < tolerance * gained["isotropic"][0])
    assert np.all(gained["prager"][1:] > 0.1 * gained["prager"][0])
    change = np.abs(np.diff(dent["prager"]))
    assert change[1] < change[0] < 0.01 * dent["prager"][0]
    validation(
        "repeated indentation of a soft steel (sigma_Y0 = 0.8 GPa, modulus 15 GPa) to 8 GPa, "
        "3 cycles of 6 + 2 steps, 28^3 in a 2.5 a_H domain",
        "unloading stress range above 2 sigma_Y: isotropic hardening shakes down, Prager's "
        "surface yields in reverse every cycle (Melan; Bauschinger)",
        "gain per cycle: isotropic "
        + ", ".join(f"{g:.1e}" for g in gained["isotropic"])
        + "; Prager "
        + ", ".join(f"{g:.2e}" for g in gained["prager"])
        + "; dent change per cycle "
        + ", ".join(f"{100 * c / dent['prager'][0]:.2f} %" for c in change),
    )


@pytest.mark.parametrize(
    "kinematic, message",
    [
        ({"law": "chaboche", "C": 1e9}, "kinematic.law: must be one of prager, armstrong"),
        ({"law": "prager", "C": 1e9, "gamma": 10.0}, "kinematic.gamma: unknown key"),
        ({"law": "armstrong-frederick", "C": 1e9}, "kinematic.gamma: missing required field"),
        ({"law": "prager", "C": -1e9}, "kinematic.C: must be > 0"),
    ],
)
def test_bad_kinematic_tables_are_refused_by_name(kinematic, message):
    hardening = {"law": "perfect", "yield_stress": SIGMA_Y0, "kinematic": kinematic}
    with pytest.raises(SpecError, match=message):
        indentation(hardening)
