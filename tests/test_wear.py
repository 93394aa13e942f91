"""Wear (issue 59, first step): the worn depth of every increment fed back into the gap."""

import math

import numpy as np
import pytest

import solver
from solver.theory.wear import fretting_wear_limit
from study.bench.wear import RADIUS as PUNCH_RADIUS
from study.bench.wear import punch_table

E, NU, RADIUS, W, MU = 210e9, 0.3, 0.01, 100.0, 0.5
STEEL = {"behaviour": "elastic", "E": E, "nu": NU}


def _sliding(n: int, law: str = "archard", k: float = 1e-15, travel: float = 3e-4) -> dict:
    """A rigid sphere sliding over elastic steel (beta != 0: the shears' coupling iterated)."""
    return {
        "body1": {"behaviour": "rigid", "radius": RADIUS},
        "body2": STEEL,
        "load": {"path": [{"normal_force": W, "steps": 2}, {"slide": [travel, 0.0], "steps": 12}]},
        "friction": {"coefficient": MU},
        "grid": {"n": n},
        "wear": {"law": law, "body2": k},
    }


def _fretting(n: int, share: float, k: float = 1e-15, cycles: int = 1) -> dict:
    """Two steel spheres' contact (a sphere on a flat: beta = 0) fretted at +-share mu W."""
    q = share * MU * W
    swing = [{"tangential_force": [f, 0.0], "steps": 8} for f in (-q, q)]
    return {
        "body1": {**STEEL, "radius": RADIUS},
        "body2": STEEL,
        "load": {
            "path": [
                {"normal_force": W, "steps": 1},
                {"tangential_force": [q, 0.0], "steps": 8},
                {"cycles": cycles, "stages": swing},
            ]
        },
        "friction": {"coefficient": MU},
        "grid": {"n": n},
        "wear": {"law": "archard", "body1": k, "body2": k},
    }


@pytest.mark.parametrize("n", [32, 64])
def test_gross_slip_wears_k_W_s_and_the_energy_law_alpha_times_the_work(n):
    """Archard in gross slip: every contact cell slips the travel s, so the volume is k W s
    (the normal load held); the energy law's volume is alpha times the friction work."""
    k, travel = 1e-15, 3e-4
    result = solver.solve(solver.Case.from_dict(_sliding(n, k=k, travel=travel)))
    assert result.status == "converged"
    history, area = result.history, result.case.surface_grid.cell_area
    volume = history["wear_volume"].sum()
    assert volume == pytest.approx(k * W * travel, rel=1e-2)
    assert result.fields["wear_depth"].sum() * area == pytest.approx(volume, rel=1e-12)
    # pressed in place, the dissimilar pair slips only radially at the edge (Spence): a trace
    assert 0.0 < history["wear_volume"][:2].sum() < 1e-5 * volume
    assert np.all(np.diff(history["max_wear_depth"]) >= 0.0)  # the deepest point only grows
    energy = solver.solve(solver.Case.from_dict(_sliding(n, "energy", k, travel)))
    work = energy.history["friction_work"].sum()
    assert work == pytest.approx(MU * W * travel, rel=1e-2)
    assert energy.history["wear_volume"].sum() == pytest.approx(k * work, rel=1e-6)


def test_the_stick_zone_of_a_fretted_sphere_does_not_wear():
    """Partial slip at +-0.6 mu W (Mindlin and Deresiewicz): the stick disk of radius
    c = a (1 - Q / (mu W))^(1/3) never slips, so it does not wear; the annulus does.  Both
    bodies wear alike (identical elastic bodies, the same slip)."""
    share = 0.6
    for n in (32, 64):
        case = solver.Case.from_dict(_fretting(n, share))
        result = solver.solve(case)
        assert result.status == "converged"
        a = case.reference.radius
        c = a * (1.0 - share) ** (1.0 / 3.0)
        x, y = case.surface_grid.mesh()
        r, h = np.hypot(x, y), case.surface_grid.dx
        depth = result.fields["wear_depth"]
        annulus = depth[(r > c + h) & (r < a - h)]
        assert annulus.min() > 0.0
        assert depth[r < c - h].max() < 1e-4 * annulus.min()
        assert depth[r > a + h].max() == 0.0
        np.testing.assert_array_equal(result.fields["wear_depth_body1"], depth)


def test_the_worn_surface_moves_the_pressure_into_the_stick_zone():
    """Fretted long enough to wear a fraction of the approach, the annulus carries less and
    the stick zone more (the worn gap is fed back: Ciavarella and Hills' trend); W held."""
    share = 0.6
    fresh = solver.solve(solver.Case.from_dict(_fretting(32, share, k=1e-15)))
    worn = solver.solve(solver.Case.from_dict(_fretting(32, share, k=2e-11, cycles=10)))
    assert worn.status == "converged"
    case = worn.case
    a = case.reference.radius
    c = a * (1.0 - share) ** (1.0 / 3.0)
    x, y = case.surface_grid.mesh()
    r, area = np.hypot(x, y), case.surface_grid.cell_area
    depth = worn.fields["wear_depth"] + worn.fields["wear_depth_body1"]
    assert depth.max() > 0.02 * case.reference.approach  # a wear that matters
    inner = r < c

    def carried(result, where):
        return result.pressure[where].sum() * area

    assert carried(worn, inner) > 1.05 * carried(fresh, inner)
    assert carried(worn, ~inner) < 0.95 * carried(fresh, ~inner)
    assert worn.pressure.sum() * area == pytest.approx(W, rel=1e-6)
    data = worn.to_xarray()
    assert data["wear_depth"].attrs["units"] == "m"
    assert data["wear_volume"].attrs["units"] == "m3"


BAD = [
    ({"law": "abrasion", "body2": 1e-15}, "wear.law", "must be one of 'archard', 'energy'"),
    ({"body2": 1e-15}, "wear.law", "is required"),
    ({"law": "archard", "body2": -1e-15}, "wear.body2", "must be 0 (it does not wear) or in"),
    ({"law": "archard", "body2": math.nan}, "wear.body2", "finite"),
    ({"law": "archard"}, "wear", "no body wears"),
    ({"law": "archard", "body1": 1e-15, "tribofilm": 1}, "wear.tribofilm", "unknown key"),
    ({"law": "archard", "body2": 1e-15, "cycle_jump": "x"}, "wear.cycle_jump", '"auto"'),
    ({"law": "archard", "body2": 1e-15, "pressure_change": 0.1}, "wear.pressure_change",
     'give it with cycle_jump = "auto"'),
    ({"law": "archard", "body2": 1e-15, "cycle_jump": "auto", "pressure_change": 1.0},
     "wear.pressure_change", "must be in [0.0001, 0.2]"),
    ({"law": "archard", "body2": 1e-15, "cycle_jump": "auto", "pressure_change": math.nan},
     "wear.pressure_change", "finite"),
    ({"law": "archard", "body2": 1e-15, "cycle_jump": "auto", "solved_cycles": 1},
     "wear.solved_cycles", "must be between 2 and"),
]  # fmt: skip


@pytest.mark.parametrize(("table", "where", "what"), BAD)
def test_bad_wear_tables_are_refused_in_one_line(table, where, what):
    case = _sliding(32)
    case["wear"] = table
    with pytest.raises(solver.SpecError) as info:
        solver.Case.from_dict(case)
    message = str(info.value)
    assert message.startswith(f"{where}:") and what in message and "\n" not in message


def test_wear_the_solver_cannot_honour_is_refused():
    """A rolling body 1's wear, a path that never slips, the energy law without friction: each
    refused with the key to change."""
    moving = {
        "body1": {**STEEL, "radius": RADIUS},
        "body2": STEEL,
        "load": {"path": [{"normal_force": W}, {"roll": [6e-4, 0.0], "creepage": 1e-3}]},
        "friction": {"coefficient": 0.3},
        "grid": {"n": [96, 32]},
        "wear": {"law": "archard", "body1": 1e-15},
    }
    pressed = _fretting(32, 0.5)
    pressed["load"] = {"normal_force": W, "steps": 2}
    frictionless = _sliding(32, "energy")
    frictionless["friction"] = {"coefficient": 0.0}
    for table, where, what in (
        (moving, "wear.body1", "a rolling body 1 brings new surface"),
        (pressed, "wear", "no stage of load.path slips"),
        (frictionless, "wear.law", "friction.coefficient is 0"),
    ):
        with pytest.raises(solver.SpecError) as info:
            solver.Case.from_dict(table)
        assert str(info.value).startswith(f"{where}:") and what in str(info.value)
    # frictionless sliding still wears by Archard's law (the pressure slides)
    archard = _sliding(32)
    archard["friction"] = {"coefficient": 0.0}
    result = solver.solve(solver.Case.from_dict(archard))
    assert result.history["wear_volume"].sum() == pytest.approx(1e-15 * W * 3e-4, rel=1e-2)


def _plastic(yield_stress: float) -> dict:
    return {**STEEL, "behaviour": "elastic-plastic",
            "hardening": {"law": "perfect", "yield_stress": yield_stress}}  # fmt: skip


def test_a_worn_elastic_plastic_body_keeps_its_strain_and_its_elastic_limit_is_elastic():
    """The sliding sphere over a perfectly plastic body 2: with a yield stress nothing reaches
    (2e10 Pa at p_0 = 2.18 GPa) it wears as the elastic body does; at 1.2 GPa (p_0 = 1.8
    sigma_Y, mu = 0.3) it yields under the track and still wears k W s in gross slip."""
    table = _sliding(32)
    table["friction"] = {"coefficient": 0.3}
    elastic = solver.solve(solver.Case.from_dict(table))
    for yield_stress in (2e10, 1.2e9):
        table = _sliding(32)
        table["body2"] = _plastic(yield_stress)
        table["friction"] = {"coefficient": 0.3}  # mu p_0 below k: the surface does not flow
        table["grid"] = {"n": [32, 32, 24]}  # layers 0.6 of a cell (the layer note's bound)
        result = solver.solve(solver.Case.from_dict(table))
        assert result.status == "converged", result.notes
        volume = result.history["wear_volume"].sum()
        assert volume == pytest.approx(1e-15 * W * 3e-4, rel=1e-2)
        strain = result.history["max_plastic_strain"].max()
        if yield_stress > 1e10:
            assert strain == 0.0
            np.testing.assert_allclose(
                result.fields["wear_depth"], elastic.fields["wear_depth"], rtol=1e-9, atol=1e-22
            )
        else:
            assert strain > 1e-3
            assert not any(n.startswith("wear:") for n in result.notes)  # 0.5 nm of 15 um layers


def test_wear_past_half_the_top_layer_is_told():
    """Worn deeper than half the plastic body's top layer: the fields of the removed material
    are still counted, and the notes say so."""
    table = _sliding(32, k=1e-10, travel=3e-4)
    table["body2"] = _plastic(2e10)
    table["grid"] = {"n": [32, 32, 16], "depth": 0.05}
    case = solver.Case.from_dict(table)
    result = solver.solve(case)
    layer = case.volume_grid.dz
    assert result.history["max_wear_depth"][-1] > 0.5 * layer
    (note,) = [n for n in result.notes if n.startswith("wear:")]
    assert f"({layer:.3g} m thick)" in note


def test_a_case_without_wear_keeps_its_id():
    table = _sliding(32)
    del table["wear"]
    case = solver.Case.from_dict(table)
    assert "wear" not in case.spec and case.wear is None
    assert solver.Case.from_dict(case.to_dict()).case_id == case.case_id


def test_a_transient_roll_wears_alpha_times_its_friction_work():
    """Rolling with creepage (Kalker's transient march): the micro-slip at the trailing edge
    dissipates, and the energy law wears alpha times that work, in the track's frame."""
    table = {
        "body1": {**STEEL, "radius": RADIUS},
        "body2": STEEL,
        "load": {
            "path": [
                {"normal_force": W, "steps": 1},
                {"roll": [6e-4, 0.0], "creepage": [1e-3, 0.0], "steps": 24},
            ]
        },
        "friction": {"coefficient": 0.3},
        "grid": {"n": [96, 32]},
        "wear": {"law": "energy", "body2": 1e-15},
    }
    result = solver.solve(solver.Case.from_dict(table))
    assert result.status == "converged"
    work = result.history["friction_work"].sum()
    assert work > 0.0
    assert result.history["wear_volume"].sum() == pytest.approx(1e-15 * work, rel=1e-6)
    assert result.fields["wear_depth"].shape == result.case.surface_grid.shape


def _punch(k: float, cycles: int, jump: int | str = 1, **rule) -> tuple:
    """The benchmark's fretted flat punch: its result, r about its last position, its radius."""
    result = solver.solve(solver.Case.from_dict(punch_table(k, cycles, jump, **rule)))
    assert result.status == "converged"
    x, y = result.case.surface_grid.mesh()
    r = np.hypot(x - result.history["position_x"][-1], y)
    return result, r, PUNCH_RADIUS


def test_a_fretted_flat_punch_wears_towards_a_uniform_pressure():
    """Under a rigid flat punch in gross slip the fresh pressure is Boussinesq's,
    W / (2 pi a sqrt(a^2 - r^2)), highest at the edge; the edge wears fastest, and the only
    pressure under which a rigid approach wears the face uniformly is uniform: ten cycles
    later the pressure over the face is flat."""

    def edge_over_centre(pressure, r, a):
        edge, centre = (r > 0.6 * a) & (r < 0.8 * a), r < 0.2 * a
        return pressure[edge].mean() / pressure[centre].mean()

    fresh, r, a = _punch(1e-18, 1)
    boussinesq = 1.0 / np.sqrt(a * a - np.minimum(r, 0.999 * a) ** 2)
    expected = edge_over_centre(boussinesq, r, a)
    assert expected > 1.3
    assert edge_over_centre(fresh.pressure, r, a) == pytest.approx(expected, rel=0.05)
    worn, r, a = _punch(2e-11, 10)
    assert edge_over_centre(worn.pressure, r, a) == pytest.approx(1.0, abs=0.05)
    area = worn.case.surface_grid.cell_area
    assert worn.pressure.sum() * area == pytest.approx(W, rel=1e-6)


def test_cycle_jumps_approach_every_cycle_solved():
    """The fretted punch over 200 cycles: solved every cycle, and with jumps of 5 and 10 cycles
    (40 and 20 solved, each one's wear scaled): the same worn volume, the worn profile within
    2 % of the deepest wear at 10, closer at 5 (an explicit step in cycles: first order)."""
    every, _, _ = _punch(1e-12, 200)
    assert len(every.history["normal_force"]) == 2 + 200 * 4
    errors = []
    for jump in (10, 5):
        jumped, _, _ = _punch(1e-12, 200, jump)
        history = jumped.history
        assert len(history["normal_force"]) == 2 + (200 // jump) * 4
        assert set(history["cycle_weight"][2:]) == {jump}
        assert history["wear_volume"].sum() == pytest.approx(
            every.history["wear_volume"].sum(), rel=1e-9
        )
        depth, reference = jumped.fields["wear_depth"], every.fields["wear_depth"]
        errors.append(np.abs(depth - reference).max() / reference.max())
        # the worn profile through the axis at each solved cycle's end, the last one the field's
        profiles = jumped.fields["cycle_wear_profile"]
        assert profiles.shape == (200 // jump, depth.shape[0])
        assert np.all(np.diff(profiles.max(axis=1)) > 0.0)
        middle = depth.shape[1] // 2
        np.testing.assert_allclose(profiles[-1], depth[:, middle - 1 : middle + 1].mean(axis=1))
    assert errors[0] < 0.02
    assert errors[1] < 0.6 * errors[0]


def _solved_weights(result) -> list[int]:
    """The cycles each solved cycle stood for (its last increment's cycle_weight)."""
    history = result.history
    cycle = history["step_cycle"]
    ends = np.flatnonzero((cycle > 0) & (np.append(cycle[1:], 0) != cycle))
    return history["cycle_weight"][ends].astype(int).tolist()


def test_automatic_jumps_bound_the_profile_error_by_half_the_pressure_change():
    """wear.cycle_jump = "auto" over the punch's 200 cycles: each jump set so that it changes
    the pressure by at most eps of its peak, which bounds the worn profile's error against
    every cycle solved by about eps / 2 of the deepest wear (solver.drive.wear); a tighter
    eps solves more cycles and errs less."""
    every, _, _ = _punch(1e-12, 200)
    reference = every.fields["wear_depth"]
    errors, solved = [], []
    for eps in (0.1, 0.05):
        auto, _, _ = _punch(1e-12, 200, "auto", pressure_change=eps)
        weights = _solved_weights(auto)
        assert sum(weights) == 200 and weights[0] == 1 and max(weights) > 2
        assert len(auto.history["normal_force"]) == 2 + 4 * len(weights)
        assert auto.history["wear_volume"].sum() == pytest.approx(
            every.history["wear_volume"].sum(), rel=1e-9
        )
        errors.append(np.abs(auto.fields["wear_depth"] - reference).max() / reference.max())
        solved.append(len(weights))
        assert errors[-1] < eps / 2
    assert solved[1] > solved[0] and errors[1] < errors[0]


def test_automatic_jumps_within_a_budget_cover_every_block_and_say_so():
    """Two blocks of 60 cycles, at most 4 solved each: the jumps grow past the bound to stand
    for the 60 cycles of each block, and the note says so; a block covered early skips its
    remaining solved cycles (the histories hold the increments solved)."""
    table = _fretting(24, 0.5, k=1e-12, cycles=60)
    table["load"]["path"].append(dict(table["load"]["path"][-1]))
    table["wear"] |= {"cycle_jump": "auto", "solved_cycles": 4}
    result = solver.solve(solver.Case.from_dict(table))
    assert result.status == "converged"
    weights = _solved_weights(result)
    assert len(weights) <= 8 and 60 in np.cumsum(weights) and sum(weights) == 120
    assert any("grew past the pressure bound" in note for note in result.notes)
    table["wear"] |= {"solved_cycles": 1000, "pressure_change": 0.2}
    loose = solver.solve(solver.Case.from_dict(table))
    weights = _solved_weights(loose)
    assert len(weights) < 2 * 60 and sum(weights) == 120
    assert not any("grew past" in note for note in loose.notes)
    steps = len(loose.history["normal_force"])
    assert steps == 1 + 8 + 16 * len(weights) == len(loose.history["cycle_weight"])


def test_a_jump_past_a_block_stands_for_its_rest():
    """7 cycles with jumps of 3: three solved cycles standing for 3, 3 and 1; a jump of 10^9
    or 0 is refused, and so is a jump without a cycle block."""
    table = _fretting(32, 0.5, cycles=7)
    table["wear"]["cycle_jump"] = 3
    case = solver.Case.from_dict(table)
    assert [s.weight for s in case.stages if s.cycle] == [3, 3, 3, 3, 1, 1]
    assert case.cycles == 3 and case.spec["load"]["path"][2]["cycles"] == 7
    for jump, what in ((0, "must be"), (10**9, "must be")):
        table["wear"]["cycle_jump"] = jump
        with pytest.raises(solver.SpecError, match=f"^wear.cycle_jump: {what}"):
            solver.Case.from_dict(table)
    table = _sliding(32)
    table["wear"]["cycle_jump"] = 2
    with pytest.raises(solver.SpecError, match="^wear.cycle_jump: the path has no cycle block"):
        solver.Case.from_dict(table)


def test_one_pass_of_a_sphere_wears_the_track_of_its_line_load():
    """A rigid sphere sliding once over an incompressible flat (beta = 0: Hertz's pressure,
    unchanged by a wear far below the approach): a point of the track at y wears
    k int p dx = k p_0 (pi a / 2)(1 - y^2 / a^2); across the middle of the track the worn
    depth converges to it with the cells (the window follows the contact)."""
    k, travel = 1e-15, 6.0
    errors = []
    for per_diameter in (12, 24, 48):  # cells across the contact
        table = {
            "body1": {"behaviour": "rigid", "radius": RADIUS},
            "body2": {**STEEL, "nu": 0.5},
            "load": {"path": [{"normal_force": W, "steps": 1}]},
            "friction": {"coefficient": 0.3},
            "grid": {"n": 32},
        }
        reference = solver.Case.from_dict(table).reference
        a, p0 = reference.radius, reference.max_pressure
        table["load"]["path"].append(
            {"slide": [travel * a, 0.0], "steps": round(travel * per_diameter / 2)}
        )
        table["grid"] = {"n": [round(per_diameter * (travel + 3) / 2), round(1.5 * per_diameter)]}
        table["wear"] = {"law": "archard", "body2": k}
        case = solver.Case.from_dict(table)
        assert case.moving_window is not None  # the window that follows the contact
        result = solver.solve(case)
        assert result.status == "converged"
        x, y = case.surface_grid.mesh()
        middle = np.argmin(np.abs(x[:, 0] - travel * a / 2))
        across = y[middle]
        expected = k * p0 * (math.pi * a / 2) * np.clip(1.0 - (across / a) ** 2, 0.0, None)
        worn = result.fields["wear_depth"][middle]
        errors.append(np.abs(worn - expected).max() / expected.max())
    assert errors[-1] < 0.01
    assert errors[0] > errors[1] > errors[2]


def test_partial_slip_wears_to_ciavarella_and_hills_limit():
    """A sphere fretted in partial slip (Q = 0.6 mu W, nu = 0: Cattaneo's stick circle exact)
    wears its annulus until it carries no pressure: the stick zone, unworn, carries the load
    as Hertz's pressure of radius c plus a flat punch's, the approach is c^2/R + P/(2cE*), and
    the annulus is worn to just touching (solver.theory.wear).  The pressure inside 0.7 c and
    the approach converge to the limit with the cells; the worn annulus (beyond 1.15 c, away
    from the punch's edge singularity) is within 3 % of the limit's depth at 64 cells."""
    share, errors = 0.6, []
    for n in (48, 64):
        table = _fretting(n, share, k=1e-10, cycles=200)
        for body in ("body1", "body2"):
            table[body] = {**table[body], "nu": 0.0}
        table["wear"]["cycle_jump"] = "auto"
        result = solver.solve(solver.Case.from_dict(table))
        assert result.status == "converged"
        case = result.case
        limit = fretting_wear_limit(W, RADIUS, case.pair.composite_modulus, share)
        c, h = limit.stick_radius, case.surface_grid.dx
        x, y = case.surface_grid.mesh()
        r = np.hypot(x, y)
        annulus_load = result.pressure[r > c + h].sum() * case.surface_grid.cell_area
        assert annulus_load < 1e-4 * W
        # the stick zone at every checkpoint: the same cells, within c (it does not wear)
        states = result.fields["cycle_stick_profile"]
        sticking = np.abs(x[:, 0])[states[-1] == 1]
        counts = (states == 1).sum(axis=1)
        assert counts.min() == counts.max()
        assert sticking.size > 0 and sticking.max() < c + h
        inner = r < 0.7 * c
        expected = limit.pressure(r[inner])
        worn = result.fields["wear_depth"] + result.fields["wear_depth_body1"]
        ring = (r > max(c + 1.5 * h, 1.15 * c)) & (r < case.reference.radius - h)
        depth = limit.worn_depth(r[ring])
        errors.append(
            (
                np.abs(result.pressure[inner] - expected).max() / expected.max(),
                abs(result.history["approach"][-1] / limit.approach - 1.0),
                np.abs(worn[ring] - depth).max() / depth.max(),
            )
        )
    (p48, d48, h48), (p64, d64, h64) = errors
    assert p64 < 0.5 * p48 and p64 < 0.005
    assert d64 < 0.5 * d48 and d64 < 0.002
    assert h64 < min(h48, 0.03)


def test_a_periodic_rough_interface_wears_its_slipping_spots():
    """grid.periodic: a rough steel flat fretted at +-0.9 mu W (partial slip of its spots)
    for three cycles, the energy law on both bodies: the worn volume is alpha times the
    friction work, the wear sits on the spots that touch, and the worn heights move the pressure
    (the same path without wear ends elsewhere)."""
    from test_periodic import ROUGH, periodic_case

    q = 0.9 * MU * 5.0
    swing = [{"tangential_force": [f, 0.0], "steps": 4} for f in (-q, q)]
    table = periodic_case({**STEEL, "roughness": ROUGH}, body1={**STEEL})
    table["body1"]["radius"] = "inf"
    table["friction"] = {"coefficient": MU}
    table["load"] = {
        "path": [
            {"normal_force": 5.0, "steps": 2},
            {"tangential_force": [q, 0.0], "steps": 4},
            {"cycles": 3, "stages": swing},
        ]
    }
    alpha = 1e-10
    table["wear"] = {"law": "energy", "body1": alpha, "body2": alpha}
    worn = solver.solve(solver.Case.from_dict(table))
    assert worn.status == "converged", worn.notes
    history = worn.history
    volume = history["wear_volume"].sum()
    assert volume == pytest.approx(2 * alpha * history["friction_work"].sum(), rel=1e-6)
    depth = worn.fields["wear_depth"] + worn.fields["wear_depth_body1"]
    assert depth.sum() * worn.case.surface_grid.cell_area == pytest.approx(volume, rel=1e-9)
    del table["wear"]
    fresh = solver.solve(solver.Case.from_dict(table))
    touched = (fresh.pressure > 0) | (worn.pressure > 0)  # the spots grow as they wear
    assert depth[touched].sum() > 0.99 * depth.sum() and touched.mean() < 0.5
    assert np.abs(worn.pressure - fresh.pressure).max() > 0.01 * fresh.pressure.max()


FRETTING_CAMPAIGN = """
[campaign]
name = "worn"

[base]
body1 = { behaviour = "elastic", radius = 0.01, E = 210e9, nu = 0.3 }
body2 = { behaviour = "elastic", E = 210e9, nu = 0.3 }
friction = { coefficient = 0.5 }
grid = { n = 24 }
wear = { law = "archard", body2 = 5e-12, cycle_jump = "auto" }

[[base.load.path]]
normal_force = 100.0

[[base.load.path]]
tangential_force = 30.0
steps = 4

[[base.load.path]]
cycles = 40

[[base.load.path.stages]]
tangential_force = -30.0
steps = 4

[[base.load.path.stages]]
tangential_force = 30.0
steps = 4

[sweep]
"friction.coefficient" = [0.5, 0.75]
"""


def test_the_report_tells_the_wear_and_draws_it(tmp_path):
    """A campaign of two fretted spheres: the report's wear table sums the load cycles the
    jumps stand for, its volume over energy is Archard's k / mu (the cells wear only in slip,
    where q = mu p), and the three figures exist."""
    from study_fixtures import write

    from study.campaign import load_campaign
    from study.report import build_report
    from study.run.assemble import assemble_to_file
    from study.run.driver import RunOptions, run_campaign

    out = tmp_path / "out"
    campaign = load_campaign(write(tmp_path, FRETTING_CAMPAIGN))
    assert run_campaign(campaign, out, options=RunOptions()).exit_status == 0
    assemble_to_file(out)
    text = build_report(out).read_text()
    section = text[text.index("## Wear") :].splitlines()
    header = next(line for line in section if line.startswith("| "))
    names = [cell.strip() for cell in header.strip("|").split("|")]
    rows = [line for line in section if line.startswith("| 0.")]
    assert len(rows) == 2
    for row in rows:
        value = dict(zip(names, (cell.strip() for cell in row.strip("|").split("|")), strict=True))
        mu = float(value[names[0]])
        assert int(value["cycles"]) == 40 and int(value["solved"]) < 40
        assert float(value["volume_per_J"]) == pytest.approx(5e-12 / mu, rel=1e-3)
        assert 0.0 < float(value["rate_last_m3"]) and 0.0 < float(value["rate_first_m3"])
    for suffix in ("wear_energy", "wear_profiles", "wear_pressure"):
        assert (out / f"worn_{suffix}.png").stat().st_size > 10_000


def test_gross_slip_wear_of_a_sphere_matches_the_method_of_dimensionality_reduction():
    """A rigid sphere slid to and fro by 0.02 a over an incompressible flat (beta = 0: the
    pressure axisymmetric) for 400 cycles, wearing its centre until the pressure there falls to
    0.64 p_H and the contact widens by a quarter: the worn profile and the pressure across the
    stroke against MDR's (Popov and Hess; solver.theory.mdr, an independent 1-D computation
    whose own discretisation error is about 0.2 % and 0.4 %)."""
    from solver.theory.mdr import mdr_gross_slip_wear

    nu, cycles, wear_per_pressure = 0.5, 400, 1e-18  # k s: depth per cycle per pressure (m/Pa)
    modulus = E / (1.0 - nu**2)
    a = (3.0 * W * RADIUS / (4.0 * modulus)) ** (1.0 / 3.0)
    stroke = 0.02 * a
    reference = mdr_gross_slip_wear(RADIUS, W, modulus, wear_per_pressure, cycles, 400, 800)
    assert reference.pressure[0] < 0.7 * 3.0 * W / (2.0 * math.pi * a * a)  # a worn contact
    errors = []
    for n in (32, 64):
        table = _sliding(n, k=wear_per_pressure / (2.0 * stroke))
        table["body2"] = {**STEEL, "nu": nu}
        swing = [{"slide": [d, 0.0], "steps": 2} for d in (-stroke, stroke)]
        table["load"]["path"] = [
            {"normal_force": W},
            {"slide": [stroke / 2, 0.0]},
            {"cycles": cycles, "stages": swing},
        ]
        table["wear"]["cycle_jump"] = "auto"
        result = solver.solve(solver.Case.from_dict(table))
        assert result.status == "converged"
        x, y = result.case.surface_grid.mesh()
        row = np.argmin(np.abs(x[:, 0]))  # the stroke's middle: across it the wear of y
        end = np.argmin(np.abs(x[:, 0] - result.history["position_x"][-1]))
        measured = []
        for found, i, centre, of in (
            (result.fields["wear_depth"], row, 0.0, reference.worn_depth),
            (result.pressure, end, result.history["position_x"][-1], reference.pressure),
        ):
            r = np.hypot(x[i, 0] - centre, y[i])
            expected = np.interp(r, reference.radius, of)
            inside = r < 0.9 * reference.contact_radius
            measured.append(np.abs(found[i] - expected)[inside].max() / expected.max())
        errors.append(measured)
    (depth32, p32), (depth64, p64) = errors
    assert max(depth32, depth64) < 0.01 and max(p32, p64) < 0.015 and p64 < p32


def test_an_elastic_plastic_body_1_wears_as_body_2_relabelled():
    """An elastic-plastic body 1 is solved as body 2 (the bodies swapped), its wear with it:
    fretted at +-0.6 mu W with different coefficients on the two bodies and a yield stress
    nothing reaches, each body wears as in the elastic pair, each under its own label."""
    table = _fretting(24, 0.6, cycles=2)
    table["wear"] |= {"body1": 3e-15, "body2": 1e-15}
    table["grid"] = {"n": [24, 24, 16]}
    elastic = solver.solve(solver.Case.from_dict(table))
    table["body1"] = {**_plastic(2e10), "radius": RADIUS}
    plastic = solver.solve(solver.Case.from_dict(table))
    assert elastic.status == plastic.status == "converged"
    assert plastic.history["max_plastic_strain"].max() == 0.0
    for name in ("wear_depth", "wear_depth_body1"):
        reference = elastic.fields[name]
        assert np.abs(plastic.fields[name] - reference).max() < 1e-4 * reference.max()
    assert plastic.fields["wear_depth_body1"].sum() == pytest.approx(
        3.0 * plastic.fields["wear_depth"].sum(), rel=1e-9
    )


@pytest.mark.parametrize("n", [24, 48])
def test_a_sliding_pin_wears_its_own_pressure_times_the_distance(n):
    """A rigid pin (sphere) slid 9 a over an incompressible flat (beta = 0: Hertz's pressure,
    unchanged by a small wear), both wearing: every point of the pin's face stays under the
    same pressure, so the pin wears k1 s p(r) (its frame travels with it, moved onto body 2's
    by interpolation at sub-cell positions), while a point of the flat's track wears its line
    load; both volumes are k W s."""
    table = _sliding(n, k=1e-15)
    table["body2"] = {**STEEL, "nu": 0.5}
    a = (3.0 * W * RADIUS / (4.0 * E / (1.0 - 0.5**2))) ** (1.0 / 3.0)  # Hertz, rigid sphere
    travel = 9.0 * a * (1.0 + 1.0 / (7.0 * n))  # the end not on a cell's centre
    table["load"]["path"][1] = {"slide": [travel, 0.0], "steps": 4 * n}
    table["grid"] = {"n": [4 * n, n]}  # n cells across the window (3 a), 9 a of track
    table["wear"] = {"law": "archard", "body1": 2e-15, "body2": 1e-15}
    result = solver.solve(solver.Case.from_dict(table))
    assert result.status == "converged"
    area = result.case.surface_grid.cell_area
    pin, flat = result.fields["wear_depth_body1"], result.fields["wear_depth"]
    assert pin.sum() * area == pytest.approx(2e-15 * W * travel, rel=1e-2)
    assert flat.sum() * area == pytest.approx(1e-15 * W * travel, rel=1e-2)
    x, y = result.case.surface_grid.mesh()
    r = np.hypot(x - result.history["position_x"][-1], y)
    p0 = 3.0 * W / (2.0 * math.pi * a * a)
    expected = 2e-15 * travel * p0 * np.sqrt(np.clip(1.0 - (r / a) ** 2, 0.0, None))
    inner = r < 0.8 * a
    error = np.abs(pin - expected)[inner].max() / expected.max()
    assert error < (0.02 if n == 24 else 0.008)  # measured 1.1 % and 0.41 %
    assert np.abs(pin[r > 1.5 * a]).max() < 1e-3 * expected.max()  # (cells and a step of smear)


def test_a_field_moved_by_fractions_of_cells_is_linearly_interpolated():
    """solver.drive.wear.moved: a linear field moved by (2.3, -1.6) cells is the same field at
    x - 2.3, y + 1.6 where both are defined (linear interpolation is exact for it), and a
    move and its inverse return the field away from the entering edges."""
    from solver.drive.wear import moved

    i, j = np.meshgrid(np.arange(20.0), np.arange(16.0), indexing="ij")
    field = 3.0 * i - 2.0 * j + 5.0
    out = moved(field, 2.3, -1.6)
    inside = (slice(3, None), slice(None, -2))
    expected = 3.0 * (i - 2.3) - 2.0 * (j + 1.6) + 5.0
    np.testing.assert_allclose(out[inside], expected[inside], rtol=1e-12)
    back = moved(moved(field, 1.0, 2.0), -1.0, -2.0)
    np.testing.assert_allclose(back[:-1, :-2], field[:-1, :-2], rtol=1e-12)
