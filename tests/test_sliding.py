"""Sliding stages (issue 24, first step): body 1 slides over body 2 in gross slip.

Checks: a stage that moves by zero is the static answer; sliding along +x is the mirror of
sliding along -x; the answer translates with the contact; the steady sliding stress field is
Hamilton's (1983) closed form; plasticity accumulates along a track; bad inputs are refused.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import solver
from solver import Case, SpecError
from solver.theory.half_space import hamilton_stress

STEEL = {"behaviour": "elastic", "E": 210e9, "nu": 0.3}
SPHERE = {"behaviour": "rigid", "radius": 0.01}
FORCE = 100.0


def _case(path: list[dict], n=(64, 64), mu=0.3, **extra) -> Case:
    table = {
        "body1": dict(SPHERE), "body2": dict(STEEL), "friction": {"coefficient": mu},
        "load": {"path": path}, "grid": {"n": list(n)},
    }  # fmt: skip
    table.update(extra)
    return Case.from_dict(table)


@pytest.fixture(scope="module")
def radius():
    return _case([{"normal_force": FORCE}]).hertz.radius


def test_a_stage_that_moves_by_zero_is_the_static_answer():
    static = _case([{"normal_force": FORCE}, {"steps": 2}])
    still = _case([{"normal_force": FORCE}, {"slide": [0.0, 0.0], "steps": 2}])
    assert still.case_id == static.case_id and not still.moving
    a, b = solver.solve(static), solver.solve(still)
    assert np.array_equal(a.pressure, b.pressure) and np.array_equal(a.shear_x, b.shear_x)


def test_sliding_along_x_is_the_mirror_of_sliding_back(radius):
    """Rigid sphere on steel (beta != 0: the shear pushes the pressure, the coupling runs)."""
    out = {}
    for sign in (1.0, -1.0):
        path = [{"normal_force": FORCE}, {"slide": [sign * radius, 0.0], "steps": 3}]
        out[sign] = solver.solve(_case(path, n=(96, 48)))
        assert out[sign].status == "converged"
        assert out[sign].history["tangential_force_x"][-1] == pytest.approx(sign * 0.3 * FORCE)
    forward, back = out[1.0], out[-1.0]
    assert np.allclose(forward.pressure, back.pressure[::-1], rtol=1e-8, atol=1e-8 * FORCE)
    assert np.allclose(forward.shear_x, -back.shear_x[::-1], rtol=1e-8, atol=1e-8 * FORCE)
    # the coupling moved the pressure off the apex: not the frictionless answer
    x = forward.grid.mesh()[0] - forward.history["position_x"][-1]
    assert abs((forward.pressure * x).sum() / forward.pressure.sum()) > 1e-3 * radius


def test_the_answer_translates_with_the_contact(radius):
    """Slides of 4 and 8 cells in windows of one size centred on their tracks (2 and 4 cells
    from the origin): the second pressure is the first moved by 4 cells, 2 in window cells."""
    size = [8 * radius, 4 * radius]
    cell = size[0] / 96
    results = {}
    for cells in (4, 8):
        path = [{"normal_force": FORCE}, {"slide": [cells * cell, 0.0], "steps": 2}]
        results[cells] = solver.solve(_case(path, grid={"n": [96, 48], "size": size}))
    assert results[8].grid.x[0] - results[4].grid.x[0] == pytest.approx(2 * cell)
    shifted = np.roll(results[4].pressure, 2, axis=0)
    difference = np.abs(results[8].pressure - shifted).max() / results[8].pressure.max()
    assert difference < 1e-6  # the coupling tolerance (pressure change between passes)


@pytest.mark.validation
def test_steady_sliding_stress_is_hamiltons(radius, validation):
    """Goodman (pressure exactly Hertz's), mu = 0.3: every stress component of the final state
    against Hamilton's closed form centred on the contact's new position."""
    mu = 0.3
    path = [{"normal_force": FORCE}, {"slide": [radius, 0.0], "steps": 2}]
    case = _case(
        path, n=(128, 64), mu=mu, solver={"goodman": True},
        grid={"n": [128, 64, 24], "half_width": 1.5, "depth": 2.0},
        output={"fields": ["stress"]},
    )  # fmt: skip
    result = solver.solve(case)
    assert result.status == "converged"
    stress = result.fields["stress"]  # (component, x, y, z)
    grid = result.grid
    x, y = grid.mesh()
    z = result.depth
    p_h = case.hertz.max_pressure
    ref = hamilton_stress(
        (x - radius)[..., None], y[..., None], z[None, None, :], radius, p_h, 0.3, mu
    )
    error = np.abs(stress - ref).max(axis=(1, 2, 3)) / p_h
    deep = np.abs(stress - ref)[..., z > 0.29 * radius].max() / p_h
    assert error.max() < 0.03, error
    assert deep < 0.01
    validation(
        "a sphere slid one contact radius, Goodman, mu = 0.3, 128 x 64 x 24",
        "Hamilton's (1983) closed-form sliding stresses at the new position",
        f"largest component error {error.max():.1e} p_H, {deep:.1e} p_H below 0.29 a",
    )


def test_plastic_strain_accumulates_along_a_sliding_track(radius):
    """A rigid sphere (p_H = 2 sigma_Y) slides two radii over linear-hardening steel at mu =
    0.3: the plastic strain spreads along the track and grows past the static indentation's."""
    plastic = {**STEEL, "behaviour": "elastic-plastic",
               "hardening": {"law": "linear", "yield_stress": 0.5e9, "modulus": 10e9}}  # fmt: skip
    table = dict(body1=dict(SPHERE), body2=plastic, friction={"coefficient": 0.3})
    static = Case.from_dict({**table, "load": {"path": [{"hertz_pressure": 1.0e9, "steps": 2}]},
                             "grid": {"n": [24, 24, 12]}})  # fmt: skip
    a = static.hertz.radius
    path = [{"hertz_pressure": 1.0e9, "steps": 2}, {"slide": [2 * a, 0.0], "steps": 12}]
    moving = Case.from_dict({**table, "load": {"path": path}, "grid": {"n": [48, 24, 12]}})
    first, slid = solver.solve(static), solver.solve(moving)
    assert slid.status == "converged", slid.notes
    assert np.isfinite(slid.fields["plastic_strain"]).all()
    strain = slid.fields["plastic_strain"].max(axis=(1, 2))  # along x
    x = slid.grid.x
    plastic_x = x[strain > 1e-6]
    assert plastic_x.min() < 0.2 * a and plastic_x.max() > 1.8 * a  # the whole track
    assert slid.history["max_plastic_strain"][-1] > first.history["max_plastic_strain"][-1]
    assert slid.history["friction_work"][2:].sum() > 0


@pytest.mark.parametrize(
    ("edit", "field"),
    [
        (lambda t: t["body1"].update(STEEL), "body1.behaviour"),
        (lambda t: t["load"]["path"][1].update(tangential_force=1.0), "load.path[1].slide"),
        (lambda t: t["load"]["path"][1].update(slide=[1e-4]), "load.path[1].slide"),
        (lambda t: t["grid"].update(size=4e-4), "grid.size"),
    ],
    ids=["elastic_body1", "with_tangential_force", "one_component", "window_off_track"],
)
def test_bad_sliding_stages_are_refused(edit, field):
    table = {
        "body1": dict(SPHERE), "body2": dict(STEEL), "friction": {"coefficient": 0.3},
        "load": {"path": [{"normal_force": FORCE}, {"slide": [1e-4, 0.0]}]}, "grid": {"n": 64},
    }  # fmt: skip
    edit(table)
    with pytest.raises(SpecError, match=field.replace("[", r"\[").replace("]", r"\]")):
        Case.from_dict(table)


def test_window_covers_the_track(radius):
    travel = 3 * radius
    case = _case([{"normal_force": FORCE}, {"slide": [travel, 0.0], "steps": 3}], n=(128, 48))
    hx, hy = case.domain_half_widths
    grid = case.surface_grid
    assert grid.centre == (0.5 * travel, 0.0)  # the window is centred on the track
    assert hx >= 0.5 * travel + 1.5 * radius * (1 - 1e-12) and hy >= 1.5 * radius * (1 - 1e-12)
    assert grid.x[0] < -1.5 * radius + grid.dx and grid.x[-1] > travel + 1.5 * radius - grid.dx
    assert math.isclose(grid.dx, grid.dy)


def test_the_moving_cost_scene_has_its_cells_across_the_contact():
    """`python -m study bench moving`: n cells across the contact diameter, layers half a cell
    thick (no note on them), the window over the whole pass."""
    from study.bench.moving import TRAVEL, pass_table

    case = Case.from_dict(pass_table(16))
    a = case.hertz.radius
    grid = case.surface_grid
    assert 2 * a / grid.dx == pytest.approx(16, rel=0.05)
    volume = case.volume_grid
    assert volume.z[1] - volume.z[0] == pytest.approx(0.5 * grid.dx, rel=0.05)
    assert not case.warnings
    assert grid.x[0] < -1.5 * a + grid.dx and grid.x[-1] > (TRAVEL + 1.5) * a - grid.dx


def test_sliding_cycles_dissipate_friction_work_without_a_fretting_loop(radius):
    """Back and forth at mu = 0.3, elastic: each cycle dissipates mu W times the distance slid
    (the friction work), and there is no Q - Delta loop (the shift stays, the travel is the
    position), so no loop energy."""
    travel = radius
    stroke = [{"slide": [travel, 0.0], "steps": 4}, {"slide": [-travel, 0.0], "steps": 4}]
    path = [{"normal_force": FORCE}, {"cycles": 2, "stages": stroke}]
    result = solver.solve(_case(path, n=(64, 32), solver={"goodman": True}))
    assert result.status == "converged"
    dataset = result.to_xarray()
    assert "loop_energy" not in dataset
    work = dataset["cycle_friction_work"].values
    np.testing.assert_allclose(work, 0.3 * FORCE * 2 * travel, rtol=1e-3)


@pytest.mark.parametrize("travel", [-1.0, 1e300, 1e-2])
def test_a_track_too_long_for_the_grid_is_refused_by_the_slide(travel):
    """The window covers the track: a slide the grid's cells cannot resolve names the slide."""
    path = [{"normal_force": FORCE}, {"slide": [travel, 0.0], "steps": 2}]
    with pytest.raises(SpecError, match=r"^load\.path \(slide\): mesh too coarse for the sliding"):
        _case(path, n=(64, 32))


def test_the_cells_a_too_coarse_plastic_slide_is_told_to_take_are_accepted():
    """The message's n keeps the volume's cells: taken as written, the case is accepted."""
    import re

    table = {
        "body1": {"behaviour": "rigid", "radius": 0.015},
        "body2": {
            "behaviour": "elastic-plastic", "radius": "inf", "E": 210e9, "nu": 0.3,
            "hardening": {"law": "perfect", "yield_stress": 1e9},
        },
        "friction": {"coefficient": 0.3},
        "load": {"path": [{"hertz_pressure": 2e9}, {"slide": [5e-4, 0.0], "steps": 4}]},
        "grid": {"n": [16, 16, 16]},
    }  # fmt: skip
    with pytest.raises(SpecError, match="mesh too coarse for the sliding") as info:
        solver.Case.from_dict(table)
    told = re.search(r"n = \[([\d, ]+)\]", str(info.value)).group(1)
    table["grid"]["n"] = [int(v) for v in told.split(",")]
    assert len(table["grid"]["n"]) == 3 and solver.Case.from_dict(table).grid.nz == 16
