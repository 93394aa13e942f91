"""Repeated passes and shakedown (issue 24): per-cycle plastic gains and their classification.

The classifier's rules are checked on gain sequences built for each boundary; the whole chain
on a frictionless load moved back and forth over an elastic-perfectly plastic half-space:
below first yield (from the Hertz closed form) nothing yields, a little above it the gain per
pass dies out (elastic shakedown), and well above it every pass yields as much as the last.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import solver
from solver import Case
from solver.drive.record import axis_value
from solver.theory.hertz import first_yield_pressure
from solver.theory.shakedown import (
    CLOSED_CYCLE_FRACTION,
    SHAKEDOWN_FLAGS,
    SHAKEDOWN_TOLERANCE,
    STEADY_DECAY,
    STEADY_NET,
    classify,
    net_trend,
    shakedown_variable,
)
from solver.variables import PLASTIC_ZONE_THRESHOLD

YIELD = 0.5e9
SHEAR_YIELD = YIELD / math.sqrt(3)  # k, von Mises
PERFECT = {
    "behaviour": "elastic-plastic", "E": 210e9, "nu": 0.3,
    "hardening": {"law": "perfect", "yield_stress": YIELD},
}  # fmt: skip


# -- the rules -----------------------------------------------------------------------------------
def test_no_yield_is_elastic():
    zero = np.zeros(3)
    assert classify(zero, zero, 0.0).regime == "elastic"
    assert classify(zero, zero, 0.5 * PLASTIC_ZONE_THRESHOLD).regime == "elastic"


def test_a_gain_that_dies_out_is_elastic_shakedown():
    gain = 1e-3 * (0.5 * SHAKEDOWN_TOLERANCE) ** np.linspace(0.0, 1.0, 4)  # last: tol/2 of first
    result = classify(gain, gain, 2e-3)
    assert result.regime == "elastic_shakedown" and result.flag == SHAKEDOWN_FLAGS[result.regime]
    # a path whose first increment was its only plastic one: no gain at all in the cycles
    assert classify(np.zeros(3), np.zeros(3), 2e-3).regime == "elastic_shakedown"


def test_a_steady_gain_is_ratchetting_or_closed_cycles():
    gain = np.full(4, 1e-3)
    assert classify(gain, gain, 5e-3).regime == "ratchetting"
    closed = gain * 0.5 * CLOSED_CYCLE_FRACTION
    assert classify(gain, closed, 5e-3).regime == "plastic_shakedown"
    # a steady gain falls by less than STEADY_DECAY per cycle, a steady net change less than
    # STEADY_NET
    slow = 1e-3 * (0.5 * (1 + STEADY_DECAY)) ** np.arange(4)
    assert classify(slow, np.full(4, 0.5 * slow[-1]), 5e-3).regime == "ratchetting"
    # a steady gain whose net part still falls: not yet told apart
    falling = gain * (0.96 * STEADY_NET) ** np.arange(4)
    assert falling[-1] > CLOSED_CYCLE_FRACTION * gain[-1]
    assert "net change still falls" in classify(gain, falling, 5e-3).reason


def test_the_regime_carries_its_evidence_and_says_how_many_more_cycles():
    """The net change's trend fitted over the last cycles, and the cycles it needs."""
    gain = np.full(5, 1e-3)
    rate = 0.8  # the net change falls 20 % a cycle, from 0.95 of the gain
    net = 0.95e-3 * rate ** np.arange(5)
    assert net_trend(net) == pytest.approx(rate, rel=1e-12)
    result = classify(gain, net, 5e-3)
    assert result.regime == "undetermined" and result.net_trend == pytest.approx(rate)
    fraction = net[-1] / gain[-1]
    assert result.net_fraction == pytest.approx(fraction)
    expected = math.ceil(math.log(CLOSED_CYCLE_FRACTION / fraction) / math.log(rate))
    assert result.more_cycles == expected and f"about {expected} more" in result.reason
    # after them, the net change is closed: plastic shakedown, with its evidence
    longer = 0.95e-3 * rate ** np.arange(5 + expected)
    done = classify(np.full(longer.size, 1e-3), longer, 5e-3)
    assert done.regime == "plastic_shakedown" and done.more_cycles == 0
    assert "near it" in done.reason or done.net_fraction < 0.5 * CLOSED_CYCLE_FRACTION
    # a steady net change just above the threshold is ratchetting, said to be near it
    near = classify(gain, np.full(5, 0.12 * 1e-3), 5e-3)
    assert near.regime == "ratchetting" and "near it" in near.reason
    assert near.net_trend == pytest.approx(1.0)
    _, _, attrs = shakedown_variable(near)
    assert attrs["net_fraction"] == pytest.approx(0.12) and attrs["more_cycles"] == 0


@pytest.mark.parametrize(
    ("gain", "converged", "why"),
    [
        (1e-3 * (0.25 * STEADY_DECAY) ** np.arange(3), True, "still falls"),  # not yet settled
        (np.full(1, 1e-3), True, "at least"),  # one cycle shows no trend
        (np.full(4, 1e-3), False, "did not converge"),
    ],
    ids=["still_falling", "one_cycle", "not_converged"],
)
def test_what_cannot_be_told_is_undetermined(gain, converged, why):
    result = classify(gain, gain, 1e-2, converged)
    assert result.regime == "undetermined" and why in result.reason


# -- the chain: a frictionless moving load, back and forth ---------------------------------------
def _passes(ratio: float, passes: int, travel: float = 2.0, nx: int = 40, **extra) -> solver.Result:
    """Rigid sphere at p_0 = ratio k, moved ``travel`` a forward and back ``passes`` times, mu =
    0, 8 steps a stroke, cells of a/8 (the volume twice the yield depth: 16 layers)."""
    table = dict(body1={"behaviour": "rigid", "radius": 0.01}, body2=PERFECT,
                 friction={"coefficient": 0.0})  # fmt: skip
    pressure = ratio * SHEAR_YIELD
    a = Case.from_dict({**table, "load": {"hertz_pressure": pressure}, "grid": {"n": [16, 16, 16]}})
    travel *= a.hertz.radius
    stroke = [{"slide": [travel, 0.0], "steps": 8}, {"slide": [-travel, 0.0], "steps": 8}]
    path = [{"hertz_pressure": pressure, "steps": 2}, {"cycles": passes, "stages": stroke}]
    grid = {"n": [nx, nx // 2, 16]}
    return solver.solve(Case.from_dict({**table, "load": {"path": path}, "grid": grid, **extra}))


def test_below_first_yield_nothing_yields():
    p_yield, _ = first_yield_pressure(YIELD, PERFECT["nu"])
    result = _passes(0.9 * p_yield / SHEAR_YIELD, 2)
    assert result.status == "converged"
    assert result.shakedown.regime == "elastic"
    assert result.history["max_plastic_strain"].max() == 0.0
    # no residual stress: Melan's factor is first yield over the load (cell centres: 1 %)
    assert result.melan_factor == pytest.approx(1 / 0.9, rel=0.01)


def test_gain_per_pass_dies_out_above_first_yield():
    """p_0 = 4 k (first yield at 2.79 k for nu = 0.3): elastic shakedown within four passes;
    the pass gains and their flag reach the dataset."""
    result = _passes(4.0, 4, output={"fields": ["residual_stress"]})
    assert result.status == "converged", result.notes
    gain = result.to_xarray()["plastic_strain_increment"].values
    assert gain[0] > 1e-4 and gain[-1] < SHAKEDOWN_TOLERANCE * gain[0]
    assert np.all(np.diff(gain) < 0)
    assert result.shakedown.regime == "elastic_shakedown"
    assert int(result.to_xarray()["shakedown"]) == SHAKEDOWN_FLAGS["elastic_shakedown"]
    # the residual stress raises the load Melan can prove above first yield (2.79 k)
    p_yield, _ = first_yield_pressure(YIELD, PERFECT["nu"])
    assert 4.0 * SHEAR_YIELD * result.melan_factor > 1.05 * p_yield
    # per-pass profiles: the last pass's are the final fields' on the track's middle
    data = result.to_xarray()
    assert data["cycle_residual_stress_xx"].dims == ("cycle", "z")
    assert data["cycle_rut_profile"].dims == ("cycle", "y")
    final = result.fields["residual_stress"]
    for i, component in enumerate(("xx", "yy", "zz")):
        column = axis_value(final[i])
        assert np.allclose(data[f"cycle_residual_stress_{component}"][-1], column, rtol=1e-12)
    nx = result.grid.nx
    centre = result.fields["residual_displacement_z"][(nx - 1) // 2 : nx // 2 + 1].mean(axis=0)
    # the loop's print and the final fields' re-evaluation: the same to 4e-7 (seen)
    assert np.allclose(data["cycle_rut_profile"][-1], centre, rtol=1e-5, atol=0)
    rut = data["cycle_rut_profile"].values.max(axis=1)
    assert rut[0] > 0 and np.all(np.diff(rut) >= 0)  # the rut deepens, ever more slowly
    # rolling leaves the track in longitudinal compression below the surface
    assert data["cycle_residual_stress_xx"][-1].min() < -0.2 * SHEAR_YIELD


def test_far_above_the_limit_every_pass_yields():
    """p_0 = 6 k: the gain per pass settles at a steady value far above the tolerance; whether
    its cycles close is not yet told after four passes (net change still falling)."""
    result = _passes(6.0, 4, travel=3.0, nx=48)
    assert result.status == "converged", result.notes
    gain = result.to_xarray()["plastic_strain_increment"].values
    assert gain[-1] > 30 * SHAKEDOWN_TOLERANCE * gain[0] and gain[-1] > STEADY_DECAY * gain[-2]
    assert result.shakedown.regime not in ("elastic", "elastic_shakedown")
    assert np.isfinite(result.fields["plastic_strain"]).all()


# -- first yield under a sliding point contact (the map's lower line) ----------------------------
def test_sliding_first_yield_meets_the_frictionless_closed_form_and_moves_to_the_surface():
    from solver.theory.shakedown import sliding_first_yield

    p_axis, z_axis = first_yield_pressure(math.sqrt(3.0), PERFECT["nu"])  # k = 1: p_0 / k
    ratio, x, z = sliding_first_yield(0.0, PERFECT["nu"])
    assert ratio == pytest.approx(p_axis, rel=1e-6)
    assert x == pytest.approx(0.0, abs=1e-4) and z == pytest.approx(z_axis, abs=1e-3)
    ratios = [sliding_first_yield(mu, PERFECT["nu"]) for mu in (0.1, 0.2, 0.3, 0.4, 0.5)]
    assert np.all(np.diff([r[0] for r in [(ratio, x, z), *ratios]]) < 0)  # friction lowers it
    assert all(r[2] > 0.3 for r in ratios[:3])  # below the surface up to mu = 0.3
    assert all(r[2] < 1e-3 and r[1] < -0.99 for r in ratios[3:])  # then at the trailing edge


# -- halving an increment the plasticity loop cannot follow --------------------------------------
@dataclasses.dataclass(frozen=True)
class _Contact:
    state: float  # the load reached
    iterations: dict
    friction_work: float


@dataclasses.dataclass(frozen=True)
class _Step:
    contact: _Contact
    plastic: float
    increment: np.ndarray
    iterations: int
    residual: float
    converged: bool


def _fake_plastic_step(reach):
    """A plasticity loop that converges on increments of at most ``reach`` of load, in 7
    iterations, and fails otherwise after 100; its increment is the load increment."""

    def step(operators, step_of, state, plastic, target, guess=None, before=None):
        size = target[0] - state
        ok = abs(size) <= reach + 1e-12
        contact = _Contact(target[0], {"normal": 1}, 2.0 * size)
        return _Step(contact, plastic + size, np.array([size]), 7 if ok else 100, 0.0, ok)

    return step


@pytest.mark.parametrize(("reach", "pieces"), [(1.0, 1), (0.5, 2), (0.25, 4), (0.125, 8)])
def test_a_failed_increment_is_halved_until_it_converges(monkeypatch, reach, pieces):
    from solver.drive import loops

    monkeypatch.setattr(loops, "plastic_step", _fake_plastic_step(reach))
    out = loops._halving_plastic_step(None, None, 0.0, 0.0, (0.0,), (1.0,), None)
    assert out.converged and out.contact.state == 1.0 and out.plastic == 1.0
    assert out.increment[0] == pytest.approx(1.0)  # the halves' increments add up
    assert out.contact.friction_work == pytest.approx(2.0)
    failed = sum(2**level for level in range(int(math.log2(pieces))))  # attempts that failed
    assert out.iterations == 100 * failed + 7 * pieces


def test_an_increment_that_fails_at_every_halving_keeps_the_whole_increments_state(monkeypatch):
    from solver.drive import loops

    monkeypatch.setattr(loops, "plastic_step", _fake_plastic_step(0.5 / 2**loops.MAX_SPLITS))
    out = loops._halving_plastic_step(None, None, 0.0, 0.0, (0.0,), (1.0,), None)
    assert not out.converged
    assert out.contact.state == 1.0  # the target's state, not a half's
    assert out.iterations == 100 * (loops.MAX_SPLITS + 1)  # every attempt counted


# -- the surface shear a perfectly plastic body can carry ----------------------------------------
def test_the_shear_limit_is_k_for_bounded_flow_and_inf_for_hardening():
    """sqrt(3) |tau| <= sigma_eq: k = sigma_Y / sqrt 3, raised by a saturated back stress."""
    from solver.plasticity.hardening import Hardening

    perfect = Hardening("perfect", yield_stress=YIELD)
    assert perfect.shear_limit == pytest.approx(SHEAR_YIELD, rel=1e-15)
    saturating = Hardening(
        "perfect", yield_stress=YIELD, kinematic_modulus=20e9, kinematic_recall=200.0
    )
    assert saturating.shear_limit == pytest.approx((YIELD + 20e9 / 200.0) / math.sqrt(3))
    assert Hardening("perfect", yield_stress=YIELD, kinematic_modulus=20e9).shear_limit == math.inf
    assert Hardening("linear", yield_stress=YIELD, modulus=1e9).shear_limit == math.inf


def _slide(mu: float, ratio: float, nz: int) -> Case:
    probe = {"body1": {"behaviour": "rigid", "radius": 0.01}, "body2": PERFECT}
    pressure = ratio * SHEAR_YIELD
    a = Case.from_dict(
        {**probe, "load": {"hertz_pressure": pressure}, "grid": {"n": [16, 16, 16]}}
    ).hertz.radius
    return Case.from_dict(
        {
            **probe, "friction": {"coefficient": mu},
            "load": {"path": [{"hertz_pressure": pressure, "steps": 2},
                              {"slide": [3 * a, 0.0], "steps": 12}]},
            "grid": {"n": [40, 16, nz]}, "solver": {"plastic_tolerance": 1e-4},
        }
    )  # fmt: skip


@pytest.mark.validation
def test_a_sliding_shear_past_k_is_told_and_its_surface_strain_follows_the_layers(validation):
    """mu = 0.5 at p_0 = 3 k: mu p past k where the pressure stays above 2 k.  No stress field
    in equilibrium with such a shear stays within yield, so the top layer's plastic strain is
    set by the layer thickness: it grows as the layers thin (0.043 on 24 layers, 0.116 on 48
    seen).  At mu = 0.3 nothing is said."""
    assert not any("sliding shear" in note for note in _slide(0.3, 3.0, 24).warnings)
    coarse, fine = _slide(0.5, 3.0, 24), _slide(0.5, 3.0, 48)
    assert any("sliding shear mu p_0 = 1.5 x" in note for note in coarse.warnings)
    results = [solver.solve(case) for case in (coarse, fine)]
    for result in results:
        peak = np.hypot(result.shear_x, result.shear_y).max() / SHEAR_YIELD
        assert peak > 1.0  # the flattened pressure still carries mu p above k
        assert any("surface shear traction reaches" in note for note in result.notes)
        # not labelled converged: its numbers follow the layers
        assert result.status == "surface_flow" and result.surface_flow
        assert result.to_xarray().attrs["status"] == "surface_flow"
        assert result.shakedown is None or result.shakedown.regime == "undetermined"
    strains = [r.history["max_plastic_strain"][-1] for r in results]
    assert strains[1] > 1.5 * strains[0]
    validation(
        "a rigid sphere sliding at mu = 0.5 over perfectly plastic steel at p_0 = 3 k, 24 / 48 "
        "layers",
        "no stress field within yield carries a surface shear above k (sigma_xz = q at the "
        "surface): the top layer's strain must follow the layers",
        f"e_p,max {strains[0]:.3f} / {strains[1]:.3f}; the note given",
    )


def test_a_case_file_from_before_the_surface_flow_status_reads_as_surface_flow(tmp_path):
    """Its notes carry the evidence: the same criterion tells its status and regime."""
    import netCDF4

    from solver.result import SURFACE_FLOW_NOTE, stored_status
    from study.run import storage
    from study.run.assemble import case_summary
    from study.run.writer import case_record

    note = f"step 7: {SURFACE_FLOW_NOTE} 1.3 x the largest shear stress ..."
    assert stored_status("converged", note) == "surface_flow"
    assert stored_status("converged", "nothing said") == "converged"
    assert stored_status("not_converged", note) == "not_converged"  # the worse status stays
    result = _passes(6.0, 2)  # frictionless: a converged cyclic case with a regime
    assert result.status == "converged"
    record = case_record(result, ("pressure", "shear_x"), {})
    record.attrs.update(notes=note, status="converged")  # as written before the status existed
    read = case_summary(record, np.linspace(0.0, 1.5, 4))
    assert read["status"] == "surface_flow"
    assert read["shakedown"][0] == SHAKEDOWN_FLAGS["undetermined"]
    assert "surface flow" in read["shakedown"][1]
    path = tmp_path / "old.nc"  # a per-case file of that time, with its completion marker
    storage.write_netcdf(record.to_xarray(), path)
    with netCDF4.Dataset(path, "a") as handle:
        handle.setncattr(storage.COMPLETE_ATTR, np.int8(1))
    assert storage._inspect_case_file(path) == ("surface_flow", "")


def test_many_failed_increments_are_told_in_one_note():
    """A case past what its body can carry fails every increment: one note names them all."""
    from solver.drive.record import MAX_FAILURE_NOTES, failure_notes

    few = [(3, "plasticity loop not converged"), (4, "(sub-step to W = 1 N): normal")]
    assert failure_notes(few) == [
        "step 3: plasticity loop not converged", "step 4 (sub-step to W = 1 N): normal",
    ]  # fmt: skip
    many = [(k, f"failure {k}") for k in (3, 4, 5, 5, 9, 10, 12)]
    assert len(many) > MAX_FAILURE_NOTES
    (note,) = failure_notes(many)
    assert note == (
        "7 increments did not converge, in steps 3-5, 9-10, 12; the first: step 3: failure 3; "
        "the last: step 12: failure 12"
    )


def test_a_plasticity_loop_whose_iterates_run_away_stops_with_its_best(monkeypatch):
    """Iterates pushed away (each mixed increment 50 times the last step's): the loop stops
    once the change is DIVERGED times its best, keeps the best iterate, says so, finite."""
    from solver.drive import plastic_loop

    case = Case.from_dict(
        {
            "body1": {"behaviour": "rigid", "radius": 0.01}, "body2": PERFECT,
            "load": {"hertz_pressure": 5 * SHEAR_YIELD}, "grid": {"n": [16, 16, 16]},
        }
    )  # fmt: skip
    monkeypatch.setattr(
        plastic_loop, "_mix", lambda mixer, increment, change, threads: 50 * (increment + change)
    )
    result = solver.solve(case)
    assert not result.converged
    assert any("plasticity loop diverging" in note for note in result.notes)
    assert result.history["plastic_iterations"].max() < case.solver.plastic_max_iterations
    assert all(np.isfinite(values).all() for values in result.history.values())
    assert all(np.isfinite(values).all() for values in result.fields.values())
