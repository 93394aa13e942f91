"""The plastic box: plastic strain and the volume convolutions on the cells near the axis only.

A box that holds the plastic zone gives the whole window's answer; one that does not is a note
and the status ``truncated``; the key is refused where it cannot be honoured.
"""

import numpy as np
import pytest

import solver

SWIFT = {"law": "swift", "B": 945e6, "C": 20.0, "n": 0.121}


def indentation(box=None, n=32, half_width=2.0, mu=0.0, plastic_body=2, fields=()):
    """Rigid sphere on Swift steel to 5 GPa in 4 steps and lifted off (body 1 if asked)."""
    grid = {"n": [n, n, 16], "half_width": half_width}
    if box is not None:
        grid["plastic_half_width"] = box
    plastic = {"behaviour": "elastic-plastic", "radius": "inf", "E": 210e9, "nu": 0.3,
               "hardening": SWIFT}  # fmt: skip
    rigid = {"behaviour": "rigid", "radius": 0.015}
    bodies = (rigid, plastic) if plastic_body == 2 else (plastic, rigid)
    return solver.Case.from_dict(
        {
            "body1": bodies[0],
            "body2": bodies[1],
            "load": {"path": [{"hertz_pressure": 5e9, "steps": 4}, {"normal_force": 0.0}]},
            "friction": {"coefficient": mu},
            "grid": grid,
            "output": {"fields": list(fields)},
        }
    )


@pytest.mark.parametrize("mu", [0.0, 0.3])
def test_a_box_that_holds_the_plastic_zone_gives_the_windows_answer(mu):
    window = solver.solve(indentation(mu=mu, fields=["residual_stress"]))
    case = indentation(box=1.4, mu=mu, fields=["residual_stress"])
    box = case.plastic_box
    assert box.shape == (24, 24, 16)  # 1.4 a_H of a 2 a_H window: 24 of 32 cells
    boxed = solver.solve(case)
    assert window.status == boxed.status == "converged", boxed.notes
    # the same fixed point: within the plasticity loop's tolerance (of the yield strain)
    yield_strain = 945e6 * 20.0**0.121 / 210e9
    tolerance = 10 * case.solver.plastic_tolerance * yield_strain
    np.testing.assert_allclose(
        boxed.history["max_plastic_strain"], window.history["max_plastic_strain"], atol=tolerance
    )
    np.testing.assert_allclose(
        boxed.history["residual_depth"], window.history["residual_depth"], rtol=1e-5
    )
    np.testing.assert_allclose(boxed.pressure, window.pressure, rtol=0, atol=1e-6 * 5e9)
    np.testing.assert_allclose(
        boxed.fields["plastic_strain"], window.fields["plastic_strain"], atol=tolerance
    )
    outside = np.ones(case.volume_grid.shape, dtype=bool)
    outside[box.slices] = False
    assert np.all(boxed.fields["plastic_strain"][outside] == 0.0)
    assert np.all(window.fields["plastic_strain"][outside] < tolerance)  # the zone is inside
    # residual stress: the window's inside the box, not computed (NaN) outside
    inside = boxed.fields["residual_stress"][(slice(None),) + box.slices]
    reference = window.fields["residual_stress"][(slice(None),) + box.slices]
    np.testing.assert_allclose(inside, reference, atol=1e-5 * np.abs(reference).max())
    assert np.isnan(boxed.fields["residual_stress"][:, outside]).all()


def test_a_box_too_small_for_the_zone_is_truncated_and_names_its_key():
    result = solver.solve(indentation(box=0.6))
    assert result.status == "truncated" and result.truncated
    assert any("side x (grid.plastic_half_width)" in note for note in result.notes)


def test_a_box_as_wide_as_the_window_is_the_same_case():
    assert indentation(box=2.0).case_id == indentation().case_id
    assert indentation(box=2.0).plastic_box is None
    assert indentation(box=1.4).case_id != indentation().case_id


def test_plastic_body_one_in_a_box_mirrors_body_two():
    """The box is centred, so body 1's mirrored frame (x, -y) has the same cells."""
    lower = solver.solve(indentation(box=1.4, mu=0.3))
    upper = solver.solve(indentation(box=1.4, mu=0.3, plastic_body=1))
    assert lower.converged and upper.converged
    np.testing.assert_array_equal(upper.pressure, np.flip(lower.pressure, axis=1))
    np.testing.assert_array_equal(
        upper.fields["plastic_strain"], np.flip(lower.fields["plastic_strain"], axis=1)
    )


@pytest.mark.parametrize(
    "change, message",
    [
        ({"plastic_half_width": 2.5}, "grid.plastic_half_width: must be in [0.25, half_width = 2"),
        ({"plastic_half_width": 0.2}, "grid.plastic_half_width: must be in [0.25"),
    ],
)
def test_bad_boxes_are_refused_by_name(change, message):
    table = indentation().to_dict()
    table["grid"].update(change)
    with pytest.raises(solver.SpecError, match=message.replace("[", r"\[")):
        solver.Case.from_dict(table)


def test_an_elastic_case_has_no_plastic_box():
    table = indentation().to_dict()
    table["body2"] = {"behaviour": "elastic", "radius": "inf", "E": 210e9, "nu": 0.3}
    table["grid"]["plastic_half_width"] = 1.0
    with pytest.raises(solver.SpecError, match="only an elastic-plastic body has a plastic box"):
        solver.Case.from_dict(table)
