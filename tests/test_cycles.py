"""Cyclic load paths: cycle blocks, the fretting loop per cycle, repeated normal loading."""

import numpy as np
import pytest

import solver
from solver.case.path import path_steps
from solver.case.reading import SpecError
from solver.numerics.tensor import von_mises
from solver.theory import friction

STEEL = {"behaviour": "elastic", "E": 210e9, "nu": 0.3}
SWIFTLESS = {
    "behaviour": "elastic-plastic",
    "E": 210e9,
    "nu": 0.3,
    "hardening": {"law": "linear", "yield_stress": 1.3579e9, "modulus": 152.3e9},
}


def fretting_table(n, cycles=3, steps=20, mu=0.3, force=1000.0, fraction=0.5):
    """Two identical steel spheres (beta = 0): W, then Q to +Q*, then cycles of -Q*, +Q*."""
    amplitude = fraction * mu * force
    return {
        "body1": {"radius": 0.015, **STEEL},
        "body2": {"radius": 0.015, **STEEL},
        "load": {
            "path": [
                {"normal_force": force, "steps": 1},
                {"tangential_force": [amplitude, 0.0], "steps": steps},
                {
                    "cycles": cycles,
                    "stages": [
                        {"tangential_force": [-amplitude, 0.0], "steps": steps},
                        {"tangential_force": [amplitude, 0.0], "steps": steps},
                    ],
                },
            ]
        },
        "friction": {"coefficient": mu},
        "grid": {"n": n, "half_width": 1.5},
    }


def test_cycle_block_repeats_its_stages():
    case = solver.Case.from_dict(fretting_table(16, cycles=4, steps=3))
    assert case.cycles == 4 and len(case.stages) == 2 + 4 * 2
    assert [s.cycle for s in case.stages] == [0, 0, 1, 1, 2, 2, 3, 3, 4, 4]
    assert case.total_steps == 1 + 3 + 4 * 2 * 3 == path_steps(case.to_dict()["load"]["path"])
    cycles = case.step_cycles()
    assert cycles.tolist() == [0] * 4 + [c for c in (1, 2, 3, 4) for _ in range(6)]
    # the normalised spec keeps the block; its id changes with the number of cycles
    block = case.to_dict()["load"]["path"][2]
    assert block["cycles"] == 4 and len(block["stages"]) == 2
    assert solver.Case.from_dict(case.to_dict()) == case
    other = solver.Case.from_dict(fretting_table(16, cycles=5, steps=3))
    assert other.case_id != case.case_id
    # targets alternate between -Q* and +Q* at the end of every stage of the block
    targets = np.array(list(case.step_targets()))
    q = 0.5 * 0.3 * 1000.0
    assert targets[3 + 3 :: 3, 1].tolist() == [-q, q] * 4
    # relabelling flips Q_x inside the block too
    swapped = case.swapped().to_dict()["load"]["path"][2]["stages"]
    assert [s["tangential_force"][0] for s in swapped] == [q, -q]


@pytest.mark.parametrize(
    "block, message",
    [
        ({"cycles": 0, "stages": [{"steps": 1}]}, "load.path[1].cycles: must be between 1"),
        ({"cycles": 2}, "load.path[1].stages: missing required field"),
        ({"cycles": 2, "stages": []}, "load.path[1].stages: must be a non-empty array"),
        ({"cycles": 2, "stages": [{"cycles": 2, "stages": []}]}, "cycle blocks do not nest"),
        ({"cycles": 2, "stages": [{"steps": 1}], "steps": 3}, "load.path[1].steps: unknown key"),
        (
            {"cycles": 2, "stages": [{"tangential_force": 400.0}]},
            "load.path[1].stages[0].tangential_force: |Q| = 400 N reaches mu W",
        ),
    ],
)
def test_bad_cycle_blocks_are_refused_by_name(block, message):
    table = fretting_table(16)
    table["load"]["path"][1:] = [block]
    with pytest.raises(SpecError, match=message.replace("[", r"\[").replace("|", r"\|")):
        solver.Case.from_dict(table)


@pytest.mark.validation
def test_fretting_cycles_match_mindlin_deresiewicz_and_the_friction_work(validation):
    """Per cycle: loop area vs Johnson's eq. 7.64 (beta = 0), and vs the summed friction work."""
    mu, force, fraction = 0.3, 1000.0, 0.5
    amplitude = fraction * mu * force
    errors = []
    for n in (32, 64):
        case = solver.Case.from_dict(fretting_table(n, mu=mu, force=force, fraction=fraction))
        result = solver.solve(case)
        assert result.converged, result.notes
        ds = result.to_xarray()
        assert ds.cycle.values.tolist() == [1, 2, 3]
        assert ds.step_cycle.dims == ("step",)
        # two identical bodies: twice one body's full-slip shift (Johnson 1985, eq. 7.42)
        shear_modulus = 210e9 / 2.6
        full_slip = 2 * 3 * mu * force * (2 - 0.3) / (16 * shear_modulus * case.hertz.radius)
        expected = friction.mindlin_deresiewicz_energy(amplitude, mu, force, full_slip)
        energy = ds.loop_energy.values
        errors.append(abs(energy[-1] / expected - 1))
        # the steady loop: every cycle the same
        assert np.ptp(energy) < 1e-4 * energy[-1]
        # energy balance: the loop area is the friction work over the surface
        np.testing.assert_allclose(ds.cycle_friction_work.values, energy, rtol=1e-4)
        # amplitudes: the force's as prescribed; the shift below the full-slip one
        np.testing.assert_allclose(ds.force_amplitude.values, amplitude, rtol=1e-9)
        assert np.all(ds.slip_amplitude.values < full_slip)
        # smallest stick zone at the reversals: Cattaneo's c / a = (1 - Q*/(mu W))^(1/3)
        stick = ds.min_stick_radius.values / case.hertz.radius
        cell = 3.0 / n
        np.testing.assert_allclose(stick, (1 - fraction) ** (1 / 3), atol=cell)
    assert errors[1] < errors[0] and errors[1] < 0.01, errors
    validation(
        "fretting cycles: a cycle block of 3 cycles (-Q*, +Q*), Q* = 0.5 mu W, 20 steps per "
        "half cycle, two steel spheres (beta = 0), 32^2 / 64^2",
        "Mindlin & Deresiewicz energy per cycle (Johnson eq. 7.64); friction work summed over "
        "the surface; Cattaneo's smallest stick radius at the reversals",
        f"{100 * errors[0]:.2f} % / {100 * errors[1]:.2f} % (magnitude); cycles equal to 1e-4, "
        "loop area = friction work to 1e-4, stick radius within a cell (asserted)",
    )


@pytest.mark.validation
def test_repeated_normal_loading_shakes_down_with_isotropic_hardening(validation):
    """Isotropic hardening: the first cycle hardens the body; later cycles add no plastic strain."""
    table = {
        "body1": {"behaviour": "rigid", "radius": 0.015},
        "body2": {"radius": "inf", **SWIFTLESS},
        "load": {
            "path": [
                {
                    "cycles": 3,
                    "stages": [
                        {"hertz_pressure": 5e9, "steps": 3},
                        {"normal_force": 0.0, "steps": 1},
                    ],
                }
            ]
        },
        "grid": {"n": [16, 16, 16]},
        "output": {"fields": ["residual_stress"]},
    }
    case = solver.Case.from_dict(table)
    result = solver.solve(case)
    assert result.converged, result.notes
    ds = result.to_xarray()
    gained = ds.plastic_strain_increment.values
    # the last cycle's residual stress is that of the final field (lifted off)
    final = von_mises(result.fields["residual_stress"]).max()
    assert ds.max_residual_stress.values[-1] == pytest.approx(final, rel=1e-12)
    assert np.ptp(ds.max_residual_stress.values) < 1e-4 * final  # shaken down
    first = float(result.history["max_plastic_strain"][3])
    assert gained[0] == pytest.approx(first, rel=1e-12)  # from a virgin body
    assert np.all(np.abs(gained[1:]) < case.solver.plastic_tolerance * first), gained
    validation(
        "repeated normal loading, rigid sphere on linear-hardening steel, p_H = 5 GPa, "
        "3 cycles, 16^3",
        "isotropic hardening: no plastic strain after the first cycle",
        "plastic strain gained per cycle "
        + ", ".join(f"{g:.1e}" for g in gained)
        + f"; residual stress constant to {np.ptp(ds.max_residual_stress.values) / final:.0e}",
    )


def test_hard_cycles_report_status_and_stay_finite():
    """Q* at 0.95 mu W in two steps per half cycle, 20 cycles, on a coarse mesh: converged,
    finite, the loop area still the friction work, every cycle the same.  With one step per
    half cycle the loop has two points and no area: a note says so."""
    table = fretting_table(16, cycles=3, steps=1, fraction=0.95)
    result = solver.solve(solver.Case.from_dict(table))
    assert result.converged and any("one step" in note for note in result.notes)
    np.testing.assert_allclose(result.to_xarray().loop_energy.values, 0.0, atol=1e-12)
    table = fretting_table(16, cycles=20, steps=2, fraction=0.95)
    result = solver.solve(solver.Case.from_dict(table))
    assert result.converged, result.notes
    ds = result.to_xarray()
    assert all(np.isfinite(ds[name].values).all() for name in ds.data_vars)
    energy = ds.loop_energy.values
    assert np.all(energy > 0) and np.ptp(energy[1:]) < 1e-6 * energy[-1]
    np.testing.assert_allclose(ds.cycle_friction_work.values, energy, rtol=1e-4)


def test_cycles_beyond_what_the_material_carries_are_reported_truncated_not_converged():
    """Armstrong-Frederick saturating at 300 MPa, indented to 10 GPa twice in a domain its
    plastic zone outgrows: the plasticity loop does not settle; the result says so, per step,
    without NaN."""
    hardening = {
        "law": "perfect",
        "yield_stress": 1.3579e9,
        "kinematic": {"law": "armstrong-frederick", "C": 15e9, "gamma": 50.0},
    }
    table = {
        "body1": {"behaviour": "rigid", "radius": 0.015},
        "body2": {"radius": "inf", **SWIFTLESS, "hardening": hardening},
        "load": {
            "path": [
                {
                    "cycles": 2,
                    "stages": [
                        {"hertz_pressure": 10e9, "steps": 3},
                        {"normal_force": 0.0, "steps": 1},
                    ],
                }
            ]
        },
        "grid": {"n": [16, 16, 16], "half_width": 1.5},  # narrower than its plastic zone
    }
    result = solver.solve(solver.Case.from_dict(table))
    assert not result.converged and result.status == "truncated"  # the box cuts the zone
    assert any("not converged" in note for note in result.notes)
    assert any("enlarge the box" in note for note in result.notes)
    assert result.history["step_converged"].min() == 0.0
    ds = result.to_xarray()
    assert all(np.isfinite(ds[name].values).all() for name in ds.data_vars)
