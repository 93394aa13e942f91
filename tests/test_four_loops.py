"""Four loops: tangential residual displacements in the slip-stick loop, fretting scenes."""

import copy

import numpy as np
import pytest

import solver
from solver.case.sizing import auto_depth
from solver.drive.operators import CaseOperators
from solver.drive.steps import ContactState, ResidualDisplacement, slip_stick_step

SWIFT = {"law": "swift", "B": 945e6, "C": 20, "n": 0.121}
STEEL = {"E": 210e9, "nu": 0.3}


def e_on_ep(mu, n=32, nz=10, **extra):
    table = {
        "body1": {"radius": 0.015, "behaviour": "elastic", **STEEL},
        "body2": {"radius": "inf", "behaviour": "elastic-plastic", **STEEL, "hardening": SWIFT},
        "load": {"normal_force": 1000.0},
        "friction": {"coefficient": mu},
        "grid": {"n": [n, n, nz]},
    }
    table.update(extra)
    return solver.Case.from_dict(table)


def test_shear_plastic_layer_shifts_the_surface_and_friction_resists_it():
    """A patch of pure-shear plastic strain e_xz under the contact centre moves body 2's surface
    by u_x = -2 h e_xz there (tests/test_eigenstrain.py); in full stick (beta = 0, mu = 2) the
    friction traction resists it: K_t q + u^r - Delta = 0 on the stick cells, q_x > 0 where
    the surface moved towards -x, no net force."""
    # the patch is set on the whole volume grid: the plastic box is the window
    case = e_on_ep(2.0, grid={"n": [32, 32, 10], "plastic_half_width": 1.5})
    assert case.pair.dundurs_beta == 0.0
    operators = CaseOperators.build(case)
    volume = case.volume_grid
    target = (1000.0, 0.0, 0.0)
    loaded = slip_stick_step(operators, ContactState.unloaded(operators.gap.shape), target)
    assert loaded.converged and not loaded.state.shear_x.any()  # beta = 0: no shear yet
    # the plastic patch: two layers deep, a third of the contact radius wide
    x, y = volume.surface.mesh()
    a = case.hertz.radius
    patch = (np.hypot(x, y) < a / 3)[:, :, None] & (volume.z < 2.01 * volume.dz)[None, None, :]
    e_xz = 1e-3
    strain = np.zeros((6,) + volume.shape)
    strain[4][patch] = e_xz
    ux, uy, uz = operators.eigenstrain.surface_displacement(strain)
    # a narrow patch moves its centre by a fraction of the wide-layer value -2 h e_xz
    shift = ux[np.hypot(x, y) < 0.5 * a / 3].mean()
    assert -2 * (2 * volume.dz) * e_xz < shift < 0
    residual = ResidualDisplacement(ux, uy, uz)
    step = slip_stick_step(operators, loaded.state, target, residual)
    assert step.converged, step.message
    qx = step.state.shear_x
    contact = step.state.pressure > 0
    assert step.stick[contact].all()  # mu = 2: everything sticks
    assert qx[np.hypot(x, y) < a / 4].mean() > 0  # resists the -x residual shift
    assert abs(qx.sum()) * volume.surface.cell_area < 1e-8 * np.abs(qx).max() * a * a
    # stick: the elastic displacement of q cancels the residual one up to the rigid shift
    kx, _ = operators.surface.tangential(qx, step.state.shear_y)
    slip = kx + ux - step.state.shift[0]
    assert np.abs(slip[contact]).max() < 1e-3 * np.abs(ux).max()
    # frictionless, the same residual displacement produces no shear at all
    free = CaseOperators.build(e_on_ep(0.0))
    assert not free.case.friction_coefficient


def test_fretting_ii_runs_all_four_loops_and_friction_raises_plastic_strain():
    """Rigid sphere on Swift steel to p_H = 6 GPa (beta = -0.29): the four loops run, every step
    converges, the shear tractions stay within the Coulomb disk, a stick zone exists, and the
    traction on body 2 points outwards (the pressure pulls its surface inwards, Boussinesq's
    u_r = -(1 + nu)(1 - 2 nu) P / (2 pi E r), and friction resists that)."""
    base = {
        "body1": {"radius": 0.015, "behaviour": "rigid"},
        "body2": {"radius": "inf", "behaviour": "elastic-plastic", **STEEL, "hardening": SWIFT},
        "load": {"hertz_pressure": 6e9, "steps": 6},
        "grid": {"n": [20, 20, 20]},
    }
    results = {}
    for mu in (0.0, 0.3):
        table = copy.deepcopy(base)
        table["friction"] = {"coefficient": mu}
        results[mu] = solver.solve(solver.Case.from_dict(table))
    frictional = results[0.3]
    assert frictional.loops == (
        "load_steps", "plasticity", "slip_stick", "normal", "tangential", "return_mapping"
    )  # fmt: skip
    assert frictional.history["step_converged"].all(), frictional.notes
    q = np.hypot(frictional.shear_x, frictional.shear_y)
    assert np.all(q <= 0.3 * frictional.pressure * (1 + 1e-9) + 1e-6 * q.max())
    assert q.max() > 0.05 * frictional.pressure.max()
    h = frictional.history
    assert 0 < h["stick_area"][-1] < h["contact_area"][-1]
    x, y = frictional.grid.mesh()
    assert (frictional.shear_x * x + frictional.shear_y * y).sum() > 0  # outwards
    assert np.isfinite(frictional.fields["plastic_strain"]).all()
    assert results[0.0].history["max_plastic_strain"][-1] > 0
    assert h["max_plastic_strain"][-1] > 0


@pytest.mark.parametrize(
    "mu, pressure, steps", [(1.0, 10e9, 5), (1.0, 10e9, 80), (0.5, 10e9, 40), (1.0, 3e9, 2)]
)
def test_four_loop_hard_cases_finish_with_status(mu, pressure, steps):
    """High friction, far past yield, few and many steps, a coarse mesh: finite, status
    reported, the Coulomb disk respected."""
    table = {
        "body1": {"radius": 0.015, "behaviour": "rigid"},
        "body2": {"radius": "inf", "behaviour": "elastic-plastic", **STEEL, "hardening": SWIFT},
        "load": {"hertz_pressure": pressure, "steps": steps},
        "friction": {"coefficient": mu},
        "grid": {"n": [16, 16, 16]},
    }
    result = solver.solve(solver.Case.from_dict(table))
    assert result.converged, result.notes
    assert result.history["step_converged"].all()
    for values in (result.pressure, result.shear_x, result.fields["plastic_strain"]):
        assert np.isfinite(values).all()
    q = np.hypot(result.shear_x, result.shear_y)
    assert np.all(q <= mu * result.pressure * (1 + 1e-9) + 1e-6 * q.max())
    assert result.history["max_plastic_strain"][-1] > 0


def mirror_pair(plastic_first: bool, body_other: dict, q=(0.15, 0.1), mu=0.3, n=24):
    """Body 1 elastic-plastic (``plastic_first``) or body 2, the other ``body_other``; a normal
    load, then a tangential force (Q_x, Q_y) = q mu W on body 2 of the case with the plastic body
    2, and the same physical force in the relabelled case: (-Q_x, Q_y) on its body 2."""
    plastic = {"radius": "inf", "behaviour": "elastic-plastic", **STEEL, "hardening": SWIFT}
    force = 1000.0
    qx, qy = q[0] * mu * force, q[1] * mu * force
    tangential = [-qx, qy] if plastic_first else [qx, qy]
    bodies = (plastic, body_other) if plastic_first else (body_other, plastic)
    return solver.Case.from_dict(
        {
            "body1": bodies[0],
            "body2": bodies[1],
            "load": {
                "path": [
                    {"hertz_pressure": 4e9, "steps": 2},
                    {"tangential_force": tangential, "steps": 2},
                ]
            },
            "friction": {"coefficient": mu},
            "grid": {"n": [n, n, 12]},
            "output": {"fields": ["plastic_strain_tensor"]},
        }
    )


@pytest.mark.parametrize(
    "other",
    [
        {"radius": 0.015, "behaviour": "rigid"},
        {"radius_x": 0.015, "radius_y": 0.03, "behaviour": "elastic", "E": 70e9, "nu": 0.33},
    ],
    ids=["rigid", "aluminium"],
)
@pytest.mark.validation
def test_relabelling_the_bodies_gives_the_mirrored_answer(other, validation):
    """An elastic-plastic body 1 is the same contact as the plastic body 2 seen from the other
    body: its frame is (x, -y, -z), so tractions on the other body change sign, y components
    change sign again, and fields mirror in y (y-odd tensor components flip)."""
    lower = mirror_pair(False, other)  # plastic body 2: solved directly
    upper = mirror_pair(True, other)  # plastic body 1: relabelled
    assert upper.plastic_body1 and not lower.plastic_body1
    assert upper.swapped().case_id == lower.case_id  # the relabelling maps the whole case
    assert upper.swapped().swapped() == upper
    a, b = solver.solve(lower), solver.solve(upper)
    assert a.converged and b.converged, (a.notes, b.notes)
    assert a.history["max_plastic_strain"][-1] > 0 and a.loops == b.loops

    def mirror(values, axis=1):
        return np.flip(values, axis=axis)

    # tractions on body 2 are those on body 1 reversed: p(x, y) = p'(x, -y),
    # q_x(x, y) = -q'_x(x, -y), q_y(x, y) = +q'_y(x, -y)
    np.testing.assert_array_equal(b.pressure, mirror(a.pressure))
    np.testing.assert_array_equal(b.shear_x, -mirror(a.shear_x))
    np.testing.assert_array_equal(b.shear_y, mirror(a.shear_y))
    np.testing.assert_array_equal(b.contact_state, mirror(a.contact_state))
    for name in ("tangential_force_x", "tangential_shift_x"):
        np.testing.assert_array_equal(b.history[name], -a.history[name])
    for name in ("tangential_force_y", "tangential_shift_y", "max_plastic_strain", "approach"):
        np.testing.assert_array_equal(b.history[name], a.history[name])
    assert b.history["tangential_force_x"][-1] == pytest.approx(-0.15 * 0.3 * 1000.0)
    np.testing.assert_array_equal(b.fields["plastic_strain"], mirror(a.fields["plastic_strain"]))
    tensor = mirror(a.fields["plastic_strain_tensor"], axis=2)
    signs = np.array([1, 1, 1, -1, 1, -1]).reshape(6, 1, 1, 1)  # yz and xy are odd in y
    np.testing.assert_array_equal(b.fields["plastic_strain_tensor"], signs * tensor)
    np.testing.assert_array_equal(
        b.fields["residual_displacement_y"], -mirror(a.fields["residual_displacement_y"])
    )
    dataset = b.to_xarray()
    assert dataset["z"].attrs["long_name"] == "depth into body 1"
    assert "relabelled" in dataset.attrs["notes"]
    validation(
        "an elastic-plastic body 1 against the same contact with the plastic body 2 "
        "(rigid sphere; elliptic aluminium body, beta != 0), friction 0.3, oblique tangential "
        "load, 24^2 x 12",
        "the mirrored answer: p(x, -y), -q_x, q_y, -Q_x, y-odd tensor components flipped",
        "bitwise equal (asserted)",
    )


def test_body_two_stress_with_a_plastic_body_one_is_refused():
    table = {
        "body1": {"radius": "inf", "behaviour": "elastic-plastic", **STEEL, "hardening": SWIFT},
        "body2": {"radius": 0.015, "behaviour": "rigid"},
        "load": {"normal_force": 1000.0},
        "grid": {"n": [16, 16, 16]},
        "output": {"fields": ["stress"]},
    }
    with pytest.raises(solver.SpecError, match="volume is body 1's"):
        solver.Case.from_dict(table)


def ep_ep(hardening1, n=24, nz=14, mu=0.0, **body1):
    """A Swift steel sphere (body 2) pressed by an elastic-plastic sphere (body 1)."""
    sphere = {"radius": 0.015, "behaviour": "elastic-plastic", **STEEL}
    return solver.Case.from_dict(
        {
            "body1": {**sphere, **body1, "hardening": hardening1},
            "body2": {**sphere, "hardening": SWIFT},
            "load": {"hertz_pressure": 5e9, "steps": 3},
            "friction": {"coefficient": mu},
            "grid": {"n": [n, n, nz]},
            "output": {"fields": ["plastic_strain_tensor"]},
        }
    )


@pytest.mark.validation
def test_two_plastic_bodies_agree_with_the_symmetric_pair(validation):
    """Two elastic-plastic spheres that differ by 1e-9 in B run with two plastic fields, body 1's
    mapped from its own frame; they must give the symmetric pair's answer (eq. 2: one field,
    doubled print) to the plasticity tolerance, and body 1's field is body 2's."""
    symmetric = solver.solve(ep_ep(SWIFT))
    general_case = ep_ep(dict(SWIFT, B=SWIFT["B"] * (1 + 1e-9)))
    assert symmetric.case.plastic_bodies == (2,) and general_case.plastic_bodies == (2, 1)
    general = solver.solve(general_case)
    assert symmetric.converged and general.converged, general.notes
    h, g = symmetric.history, general.history
    peak = h["max_plastic_strain"][-1]
    assert peak > 0
    tolerance = 10 * general_case.solver.plastic_tolerance * 945e6 / 210e9  # yield-strain scale
    for name in ("max_plastic_strain", "max_plastic_strain_body1"):
        assert np.allclose(g[name], h["max_plastic_strain"], atol=tolerance)
    np.testing.assert_allclose(general.pressure, symmetric.pressure, rtol=1e-4, atol=1e-4 * 5e9)
    for field in ("plastic_strain", "plastic_strain_body1"):
        np.testing.assert_allclose(
            general.fields[field], symmetric.fields["plastic_strain"], atol=tolerance
        )
    tensor = symmetric.fields["plastic_strain_tensor"]
    np.testing.assert_allclose(
        general.fields["plastic_strain_tensor_body1"], tensor, atol=tolerance
    )
    validation(
        "two elastic-plastic spheres differing by 1e-9 in B (two plastic fields) against the "
        "symmetric pair (eq. 2, one field), p_H = 5 GPa, 24^2 x 14",
        "the same contact",
        f"p within {np.abs(general.pressure - symmetric.pressure).max() / 5e9:.1e} p_H; e_p in "
        "body 1 and body 2 within "
        + ", ".join(
            f"{np.abs(general.fields[f] - symmetric.fields['plastic_strain']).max():.1e}"
            for f in ("plastic_strain_body1", "plastic_strain")
        ),
    )


@pytest.mark.validation
def test_identical_plastic_bodies_sheared_mirror_each_other(validation):
    """Identical Swift spheres pressed to p_H = 5 GPa, then sheared to Q = 0.5 mu W (mu = 0.3):
    each body has its own field.  Exchanging the bodies and reflecting x maps the problem onto
    itself (body 1 sees the opposite shear in its frame (x, -y, -z)), so body 1's field is
    body 2's reflected in x, to the plasticity tolerance, while the shear makes each field
    lopsided; and the pair that differs by 1e-9 in B (two fields before) gives the same."""

    def sheared(hardening1):
        case = ep_ep(hardening1, mu=0.3)
        table = case.to_dict()
        force = case.stages[-1].normal_force
        table["load"]["path"].append({"tangential_force": [0.5 * 0.3 * force, 0.0], "steps": 3})
        return solver.Case.from_dict(table)

    case = sheared(SWIFT)
    assert case.plastic_bodies == (2, 1) and not case.symmetric_plastic
    result = solver.solve(case)
    assert result.status == "converged", result.notes
    assert "slip_stick" in result.loops
    tolerance = 10 * case.solver.plastic_tolerance * 945e6 / 210e9  # yield-strain scale
    body2, body1 = result.fields["plastic_strain"], result.fields["plastic_strain_body1"]
    assert body2.max() > 0
    mirrored = np.abs(body1 - body2[::-1]).max()
    lopsided = np.abs(body2 - body2[::-1]).max()
    assert mirrored < tolerance < 0.01 * lopsided
    near = solver.solve(sheared(dict(SWIFT, B=SWIFT["B"] * (1 + 1e-9))))
    for field in ("plastic_strain", "plastic_strain_body1"):
        np.testing.assert_allclose(near.fields[field], result.fields[field], atol=tolerance)
    validation(
        "identical elastic-plastic spheres (Swift), p_H = 5 GPa, then Q = 0.5 mu W, mu = 0.3, "
        "24^2 x 14: a plastic strain field each",
        "the symmetry of the pair: body 1's field is body 2's reflected in x",
        f"within {mirrored:.1e} (the field's asymmetry {lopsided:.1e}); the pair differing by "
        "1e-9 in B the same within the tolerance",
    )


def test_a_sheared_identical_plastic_pair_at_high_friction_reverses_and_ends_with_a_status():
    """A hard case: identical Swift spheres at p_H = 3 GPa, mu = 1, sheared to 0.9 mu W and
    reversed to -0.9 mu W (a fretting half cycle) on 16^3: a status, finite histories, and
    the two bodies' largest plastic strains equal (the pair's symmetry)."""
    sphere = {"radius": 0.015, "behaviour": "elastic-plastic", **STEEL, "hardening": SWIFT}
    probe = {"body1": sphere, "body2": sphere, "load": {"hertz_pressure": 3e9}}
    force = solver.Case.from_dict({**probe, "grid": {"n": [16, 16, 16]}}).stages[0].normal_force
    shear = 0.9 * force
    path = [
        {"normal_force": force, "steps": 3},
        {"tangential_force": [shear, 0.0], "steps": 4},
        {"tangential_force": [-shear, 0.0], "steps": 8},
    ]
    table = {**probe, "load": {"path": path}, "friction": {"coefficient": 1.0}}
    result = solver.solve(solver.Case.from_dict({**table, "grid": {"n": [16, 16, 16]}}))
    assert result.status in ("converged", "truncated", "not_converged")
    h = result.history
    assert all(np.isfinite(np.asarray(v, float)).all() for v in h.values())
    assert h["max_plastic_strain"][-1] > 0
    assert h["max_plastic_strain_body1"][-1] == pytest.approx(h["max_plastic_strain"][-1])


def test_dissimilar_plastic_pair_reports_both_bodies():
    """A softer linear-hardening body 1 on the Swift steel body 2, with friction (four loops):
    both bodies yield, the softer more, and the body-1 fields come with the result."""
    soft = {"law": "linear", "yield_stress": 0.6e9, "modulus": 20e9}
    case = ep_ep(soft, mu=0.3, E=200e9, nu=0.29)
    assert case.plastic_bodies == (2, 1) and case.pair.dundurs_beta != 0.0
    result = solver.solve(case)
    assert result.converged, result.notes
    assert "slip_stick" in result.loops
    h = result.history
    assert h["max_plastic_strain_body1"][-1] > h["max_plastic_strain"][-1] > 0
    assert h["plastic_zone_depth_body1"][-1] > h["plastic_zone_depth"][-1]
    for name in ("plastic_strain_body1", "residual_displacement_z_body1", "plastic_strain"):
        assert np.isfinite(result.fields[name]).all()
    dataset = result.to_xarray()
    assert "plastic_strain_body1" in dataset and "max_plastic_strain_body1" in dataset
    assert dataset["plastic_strain_body1"].attrs["long_name"].endswith("body 1")
    # each body has its own volume grid, sized from its own yield depth (the softer: deeper)
    p_max = case.hertz.max_pressure
    for body, material in ((1, case.body1), (2, case.body2)):
        expected = auto_depth(p_max, material.hardening.initial_yield_stress, material.nu)
        grid = case.volume_grid_of(body)
        assert grid.nz * grid.dz == pytest.approx(expected * case.hertz.max_semi_axis)
    assert case.volume_grid_of(1).dz > case.volume_grid_of(2).dz
    assert dataset["plastic_strain_body1"].dims == ("x", "y", "z_body1")
    np.testing.assert_allclose(dataset["z_body1"], case.volume_grid_of(1).z)
    assert h["plastic_zone_depth_body1"][-1] < case.volume_grid_of(1).z[-1]


def test_depth_body1_only_for_two_plastic_fields():
    table = ep_ep({"law": "linear", "yield_stress": 0.6e9, "modulus": 20e9}).to_dict()
    table["grid"]["depth_body1"] = 3.0
    assert solver.Case.from_dict(table).grid.depth_body1 == 3.0
    symmetric = ep_ep(SWIFT).to_dict()
    symmetric["grid"]["depth_body1"] = 3.0
    with pytest.raises(solver.SpecError, match="grid.depth_body1: only two elastic-plastic"):
        solver.Case.from_dict(symmetric)


def test_merged_coupling_in_the_four_loops_equals_alternating_solves(monkeypatch):
    """Fretting II (rigid sphere on Swift steel, beta != 0, mu = 0.5) at 16^3: the merged
    normal-tangential iteration inside the plasticity loop gives the solution of alternating
    whole solves, to the loops' tolerances."""
    import solver.drive.steps as steps

    table = {
        "body1": {"radius": 0.015, "behaviour": "rigid"},
        "body2": {"radius": "inf", "behaviour": "elastic-plastic", **STEEL, "hardening": SWIFT},
        "load": {"hertz_pressure": 6e9, "steps": 6},
        "friction": {"coefficient": 0.5},
        "grid": {"n": [16, 16, 16]},
    }
    case = solver.Case.from_dict(table)
    results = {}
    for merged in (False, True):
        monkeypatch.setattr(steps, "MERGED_COUPLING", merged)
        results[merged] = solver.solve(case)
    alternating, merged = results[False], results[True]
    assert alternating.converged and merged.converged
    for name in ("pressure", "shear_x", "shear_y"):
        a, b = getattr(alternating, name), getattr(merged, name)
        assert np.abs(a - b).max() <= 1e-4 * np.abs(a).max(), name
    strain_a = alternating.fields["plastic_strain"]
    strain_b = merged.fields["plastic_strain"]
    yield_strain = case.body2.hardening.initial_yield_stress / case.body2.E
    assert np.abs(strain_a - strain_b).max() <= 10 * case.solver.plastic_tolerance * yield_strain
    assert merged.history["slip_iterations"].sum() < alternating.history["slip_iterations"].sum()
