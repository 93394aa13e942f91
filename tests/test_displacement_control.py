"""Displacement-controlled fretting: a stage's tangential_shift prescribed, its force a result."""

import math

import numpy as np
import pytest

import solver
from solver.result import cycle_summary
from solver.theory.friction import mindlin_deresiewicz_energy

E, NU, RADIUS, W, MU = 210e9, 0.3, 0.01, 100.0, 0.5
STEEL = {"behaviour": "elastic", "E": E, "nu": NU}
ALUMINIUM = {"behaviour": "elastic", "E": 70e9, "nu": 0.33}


def _table(path: list, n: int = 48, body2: dict = STEEL) -> dict:
    """A steel sphere on a flat (steel: beta = 0), pressed by W, then along ``path``."""
    return {
        "body1": {**STEEL, "radius": RADIUS},
        "body2": body2,
        "load": {"path": [{"normal_force": W, "steps": 1 if body2 is STEEL else 20}, *path]},
        "friction": {"coefficient": MU},
        "grid": {"n": n},
    }


def _full_slip_shift(case: solver.Case) -> float:
    """C = 3 mu W (2 - nu) / (8 G a): Cattaneo-Mindlin's shift at full slip, two steel bodies."""
    shear_modulus = E / (2.0 * (1.0 + NU))
    return 2.0 * 3.0 * MU * W * (2.0 - NU) / (16.0 * shear_modulus * case.reference.radius)


def _mindlin_force(shift: np.ndarray, full: float) -> np.ndarray:
    """Q(delta) = mu W [1 - (1 - delta / C)^(3/2)], the inverse of Cattaneo-Mindlin's shift."""
    return MU * W * (1.0 - (1.0 - np.minimum(shift / full, 1.0)) ** 1.5)


def test_a_prescribed_shift_gives_cattaneo_mindlins_force_converging_with_the_cells():
    """The shift ramped to 0.6 C in 8 increments: the tangential force of every increment is
    Cattaneo and Mindlin's inverse, the error falling with the cells."""
    errors = []
    for n in (24, 48):
        case = solver.Case.from_dict(_table([], n))
        full = _full_slip_shift(case)
        table = _table([{"tangential_shift": 0.6 * full, "steps": 8}], n)
        result = solver.solve(solver.Case.from_dict(table))
        assert result.status == "converged"
        history = result.history
        shift = history["tangential_shift_x"][1:]
        np.testing.assert_allclose(shift, 0.6 * full * np.arange(1, 9) / 8, rtol=1e-12)
        expected = _mindlin_force(shift, full)
        errors.append(np.abs(history["tangential_force_x"][1:] - expected).max() / expected[-1])
    assert errors[1] < 0.6 * errors[0] and errors[1] < 0.01


def test_a_shift_past_full_slip_slides_at_mu_W_and_a_cycle_dissipates_mindlin_deresiewicz():
    """Past C the whole contact slips and Q = mu W (gross slip, which a prescribed force
    cannot reach); a cycle between -+0.5 C dissipates Mindlin and Deresiewicz's energy for
    the force amplitude it reaches."""
    case = solver.Case.from_dict(_table([]))
    full = _full_slip_shift(case)
    gross = solver.solve(
        solver.Case.from_dict(_table([{"tangential_shift": 2 * full, "steps": 4}]))
    )
    assert gross.status == "converged"
    assert gross.history["tangential_force_x"][-1] == pytest.approx(MU * W, rel=1e-5)
    assert gross.history["stick_area"][-1] == 0.0
    swing = [{"tangential_shift": s * 0.5 * full, "steps": 10} for s in (-1, 1)]
    path = [{"tangential_shift": 0.5 * full, "steps": 10}, {"cycles": 2, "stages": swing}]
    result = solver.solve(solver.Case.from_dict(_table(path)))
    assert result.status == "converged"
    summary = cycle_summary(result.history)
    amplitude = summary["force_amplitude"][-1]
    assert amplitude == pytest.approx(_mindlin_force(np.array(0.5 * full), full), rel=0.01)
    expected = mindlin_deresiewicz_energy(amplitude, MU, W, full)
    assert summary["loop_energy"][-1] == pytest.approx(expected, rel=0.03)


def test_a_prescribed_shift_matches_the_prescribed_force_that_reaches_it_for_a_dissimilar_pair():
    """Aluminium on steel (beta != 0, the shears coupled to the pressure): the force found
    under a prescribed shift, prescribed in turn, gives back the shift and the tractions."""
    shifted = solver.solve(
        solver.Case.from_dict(_table([{"tangential_shift": 5e-7, "steps": 8}], body2=ALUMINIUM))
    )
    force = shifted.history["tangential_force_x"][-1]
    forced = solver.solve(
        solver.Case.from_dict(_table([{"tangential_force": force, "steps": 8}], body2=ALUMINIUM))
    )
    assert shifted.status == forced.status == "converged"
    assert forced.history["tangential_shift_x"][-1] == pytest.approx(5e-7, rel=1e-4)
    assert np.abs(shifted.shear_x - forced.shear_x).max() < 1e-3 * np.abs(forced.shear_x).max()


def test_a_stage_after_a_shift_holds_it():
    """A stage without tangential_shift or tangential_force after a shift stage holds the
    shift (its force a result); a tangential_force there is refused (no force to ramp from)."""
    path = [{"tangential_shift": 5e-7, "steps": 4}, {"normal_force": 0.9 * W, "steps": 2}]
    result = solver.solve(solver.Case.from_dict(_table(path)))
    assert result.status == "converged"
    np.testing.assert_allclose(result.history["tangential_shift_x"][-2:], 5e-7, rtol=1e-9)
    path[1] = {"tangential_force": 10.0}
    with pytest.raises(solver.SpecError, match=r"^load.path\[2\].tangential_force: the previous"):
        solver.Case.from_dict(_table(path))


@pytest.mark.parametrize(
    ("stage", "extra", "what"),
    [
        ({"tangential_shift": 1e-7, "tangential_force": 1.0}, {}, "does not go with"),
        ({"tangential_shift": 1e-7, "slide": [1e-5, 0.0]}, {}, "does not go with slide"),
        ({"tangential_shift": math.nan}, {}, "finite"),
        ({"tangential_shift": [1e-7]}, {}, "dx or [dx, dy]"),
        ({"tangential_shift": True}, {}, "must be a number"),
        ({"tangential_shift": 1e300}, {}, "slide the stroke instead"),
        ({"tangential_shift": 1e-7},
         {"profile": {"shape": "flat_punch", "radius": 1e-3, "edge_radius": 1e-3}},
         "built for quadric bodies"),
        ({"tangential_shift": 1e-3}, {}, "slide the stroke instead"),
        ({"tangential_shift": 1e-7}, {"friction": {"coefficient": 0.0}}, "frictionless"),
        (
            {"tangential_shift": 1e-7},
            {"body2": {"behaviour": "elastic-plastic", "E": E, "nu": NU,
                       "hardening": {"law": "perfect", "yield_stress": 1e9}}},
            "not built yet with an elastic-plastic body",
        ),
    ],
)  # fmt: skip
def test_shifts_the_solver_cannot_honour_are_refused_in_one_line(stage, extra, what):
    extra = dict(extra)
    table = _table([stage])
    if "profile" in extra:  # body 1 a flat punch: no Hertz contact to bound the shift
        table["body1"] = {**STEEL, "profile": extra.pop("profile")}
    table |= extra
    if "body2" in extra:
        table["grid"] = {"n": [32, 32, 16]}
    with pytest.raises(solver.SpecError) as info:
        solver.Case.from_dict(table)
    message = str(info.value)
    assert message.startswith("load.path[1].tangential_shift:") or "tangential_shift" in message
    assert what in message and "\n" not in message
