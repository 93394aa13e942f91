"""The plastic box: plastic strain and the volume convolutions on the cells near the axis only.

A box that holds the plastic zone gives the whole window's answer; one that does not is a note
and the status ``truncated``; the key is refused where it cannot be honoured.
"""

import math
import re

import numpy as np
import pytest

import solver
import solver.numerics.grid

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


@pytest.mark.parametrize("mu, box", [(0.0, 1.4), (0.3, 1.4), (0.3, None)])
def test_a_box_that_holds_the_plastic_zone_gives_the_windows_answer(mu, box):
    """A box given (1.4 a_H) or sized from the yield region (None)."""
    window = solver.solve(indentation(box=2.0, mu=mu, fields=["residual_stress"]))
    case = indentation(box=box, mu=mu, fields=["residual_stress"])
    box = case.plastic_box
    if case.grid.plastic_half_width == 1.4:
        assert box.shape == (24, 24, 16)  # 1.4 a_H of a 2 a_H window: 24 of 32 cells
    else:  # automatic: narrower than the window, padded to a fast FFT size
        assert (
            box.shape[0] < 32
            and solver.numerics.grid.fft_size(2 * box.shape[0]) == 2 * box.shape[0]
        )
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


def test_the_whole_window_given_is_kept_apart_from_the_automatic_box():
    whole, auto = indentation(box=2.0), indentation()
    assert whole.plastic_box is None and auto.plastic_box is not None
    assert whole.case_id != auto.case_id != indentation(box=1.4).case_id
    for case in (whole, auto):  # a campaign solves its cases from their spec: the same box
        again = solver.Case.from_dict(case.to_dict())
        assert again.case_id == case.case_id and again.plastic_box == case.plastic_box


def test_a_box_as_wide_as_the_window_is_the_same_case_when_the_zone_fills_it():
    """Where the automatic box is the window, giving the window is the same case (same id)."""
    assert indentation(half_width=1.2).plastic_box is None
    assert indentation(box=1.2, half_width=1.2).case_id == indentation(half_width=1.2).case_id


@pytest.mark.parametrize("ratio, traction", [(1.8, 0.0), (2.5, 0.0), (2.5, 0.3)])
def test_the_yield_region_half_width_matches_the_numerical_stress_field(ratio, traction):
    """The closed-form (Hamilton) estimate against the DC-FFT stress of the same tractions.

    The numerical field's yield region, on the cell centres of two meshes, is within a cell
    of the sampled closed form, and closer on the finer mesh.
    """
    from solver.numerics.grid import SurfaceGrid, VolumeGrid
    from solver.numerics.tensor import von_mises
    from solver.theory.hertz import hertz_yield_half_width
    from solver.volume.stress import SubsurfaceStressOperator

    expected = hertz_yield_half_width(1.0, 1.0 / ratio, 0.3, traction, depth=1.5)
    errors = []
    for n in (32, 64):
        surface = SurfaceGrid.centred(n, n, 2.0, 2.0)  # a = 1, window 2 a
        grid = VolumeGrid(surface, n // 2, 1.5 / (n // 2))
        x, y = np.meshgrid(surface.x, surface.y, indexing="ij")
        pressure = np.sqrt(np.clip(1.0 - x * x - y * y, 0.0, None))  # p_0 = 1
        stress = SubsurfaceStressOperator(grid, 0.3).stress(pressure, traction * pressure)
        yielded = von_mises(stress) >= 1.0 / ratio
        lateral = np.broadcast_to(np.maximum(np.abs(x), np.abs(y))[..., None], yielded.shape)
        errors.append(abs(lateral[yielded].max() - expected))
        assert errors[-1] <= surface.dx, (n, lateral[yielded].max(), expected)
    assert errors[1] <= errors[0] + 0.02  # the closed form is sampled every 0.02 a


@pytest.mark.parametrize("law", ["linear", "perfect"])
@pytest.mark.parametrize("ratio, mu", [(1.8, 0.5), (3.5, 0.5), (2.5, 0.0)])
def test_the_automatic_box_holds_the_plastic_zone(law, ratio, mu):
    """Plastic flow spreads the zone beyond the elastic yield region: the margin covers it.

    Hard scenes: perfect plasticity, far past first yield, partial slip with mu = 0.5.
    """
    y0 = 1.3579e9
    hardening = {"law": law, "yield_stress": y0} | ({"modulus": 152.3e9} if law == "linear" else {})
    case = solver.Case.from_dict(
        {
            "body1": {"behaviour": "rigid", "radius": 0.015},
            "body2": {
                "behaviour": "elastic-plastic",
                "radius": "inf",
                "E": 210e9,
                "nu": 0.3,
                "hardening": hardening,
            },  # fmt: skip
            "load": {"hertz_pressure": ratio * y0, "steps": 6},
            "friction": {"coefficient": mu},
            "grid": {"n": [32, 32, 32], "half_width": 2.0},
        }
    )
    assert case.plastic_box is not None  # narrower than the window
    result = solver.solve(case)
    assert result.status == "converged", result.notes
    assert result.fields["plastic_strain"].max() > 0.0


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


def test_two_threads_give_one_threads_bits():
    """Every parallel piece of a solve (transforms, depth convolution, Anderson chunks, return
    mapping rows, kernel set-up) is fixed whatever the threads: the same bits on 1 and 2."""
    results = []
    for threads in (1, 2):
        table = indentation(box=2.0, mu=0.3).to_dict()  # the whole window: 16384 cells
        table["solver"]["fft_threads"] = threads
        results.append(solver.solve(solver.Case.from_dict(table)))
    one, two = results
    assert one.status == two.status == "converged"
    # Anderson mixes 5 components of every cell: several chunks
    assert 5 * one.fields["plastic_strain"].size > 2**16
    np.testing.assert_array_equal(one.fields["plastic_strain"], two.fields["plastic_strain"])
    np.testing.assert_array_equal(one.pressure, two.pressure)
    np.testing.assert_array_equal(one.shear_x, two.shear_x)


def _linear_steel(ratio, mu=0.0, n=24, **grid):
    """Rigid sphere on linear-hardening steel at p_H = ratio x sigma_Y0, nothing else set."""
    hardening = {"law": "linear", "yield_stress": 0.8e9, "modulus": 15e9}
    return solver.Case.from_dict(
        {
            "body1": {"behaviour": "rigid", "radius": 0.015},
            "body2": {
                "behaviour": "elastic-plastic",
                "E": 210e9,
                "nu": 0.3,
                "hardening": hardening,
            },  # fmt: skip
            "load": {"hertz_pressure": ratio * 0.8e9, "steps": 5},
            "friction": {"coefficient": mu},
            "grid": {"n": [n, n, n], **grid},
        }
    )


@pytest.mark.parametrize("ratio", [2.0, 4.0, 6.0])
def test_the_window_holds_the_plastic_box_when_half_width_is_not_given(ratio):
    """Window = max(1.5, the plastic box the elastic yield region asks for); box = window."""
    from solver.case.sizing import auto_plastic_half_width
    from solver.keys import DEFAULT_HALF_WIDTH, MAX_AUTO_HALF_WIDTH

    case = _linear_steel(ratio)
    box = auto_plastic_half_width(  # within the default window
        ratio * 0.8e9, 0.8e9, 0.3, 0.0, case.grid.depth, DEFAULT_HALF_WIDTH
    )
    zone = auto_plastic_half_width(  # as wide as it asks
        ratio * 0.8e9, 0.8e9, 0.3, 0.0, case.grid.depth, MAX_AUTO_HALF_WIDTH
    )
    if box < DEFAULT_HALF_WIDTH:
        assert (case.grid.half_width, case.grid.plastic_half_width) == (DEFAULT_HALF_WIDTH, box)
    else:
        assert (case.grid.half_width, case.grid.plastic_half_width) == (zone, None)
    assert not case.warnings
    given = _linear_steel(ratio, half_width=DEFAULT_HALF_WIDTH)
    # within the default window nothing changes (same case id); beyond it the window grows
    assert (given.case_id == case.case_id) == (zone <= DEFAULT_HALF_WIDTH)
    if zone > DEFAULT_HALF_WIDTH:
        (note,) = given.warnings
        assert note.startswith("grid.half_width: the window (1.5 a_H) is narrower")
        assert f">= {zone:.4g}" in note


def test_the_grown_window_is_not_truncated_where_the_default_one_was():
    """p_H = 6 sigma_Y0: the 1.5 a_H window truncates the zone, the grown one holds it."""
    grown = solver.solve(_linear_steel(6.0))
    fixed = solver.solve(_linear_steel(6.0, half_width=1.5))
    assert fixed.status == "truncated", fixed.notes
    assert grown.status == "converged", grown.notes


def test_validate_warns_of_a_window_narrower_than_the_plastic_zone(tmp_path):
    import subprocess
    import sys

    campaign = tmp_path / "narrow.toml"
    campaign.write_text(
        '[campaign]\nname = "narrow"\n[base]\n'
        'body1 = { behaviour = "rigid", radius = 0.015 }\n'
        'body2 = { behaviour = "elastic-plastic", E = 210e9, nu = 0.3, hardening = '
        '{ law = "linear", yield_stress = 0.8e9, modulus = 15e9 } }\n'
        "load = { hertz_pressure = 4.8e9, steps = 5 }\n"
        "grid = { n = [24, 24, 24], half_width = 1.5 }\n"
        '[sweep]\n"friction.coefficient" = [0.0]\n'
    )
    done = subprocess.run(
        [sys.executable, "-m", "study", "validate", str(campaign)], capture_output=True, text=True
    )
    assert done.returncode == 0, done.stderr
    assert "grid.half_width: the window (1.5 a_H) is narrower than the plastic box" in (
        done.stdout + done.stderr
    )


SHIPPED_HARDENING = {
    "swift": SWIFT,
    "perfect": {"law": "perfect", "yield_stress": 433.0127e6},
    "linear": {"law": "linear", "yield_stress": 0.8e9, "modulus": 15e9},
    "linear_soft": {"law": "linear", "yield_stress": 0.5e9, "modulus": 10e9},
}


@pytest.mark.slow
@pytest.mark.parametrize("mu", [0.0, 0.5])
@pytest.mark.parametrize("law", sorted(SHIPPED_HARDENING))
def test_nothing_set_no_truncated_case_up_to_six_times_yield(law, mu):
    """The shipped materials at p_H = 6 sigma_Y0, only the cells given: never truncated."""
    table = _linear_steel(2.0).to_dict()
    del table["model"]  # another material and friction: the model that solves it decides
    table["body2"]["hardening"] = SHIPPED_HARDENING[law]
    table["friction"]["coefficient"] = mu
    table["grid"] = {"n": [24, 24, 24]}
    y0 = solver.Case.from_dict(table).plastic_body.hardening.initial_yield_stress
    table["load"] = {"hertz_pressure": 6.0 * y0, "steps": 5}
    case = solver.Case.from_dict(table)
    # a perfectly plastic body on layers too thick is told the layers to give: follow the note
    (advice,) = [int(n) for w in case.warnings for n in re.findall(r"nz >= (\d+)", w)] or [None]
    assert (advice is not None) == (law == "perfect")
    if advice is not None:
        table["grid"] = {"n": [24, 24, advice]}
        case = solver.Case.from_dict(table)
    result = solver.solve(case)
    assert result.status == "converged", result.notes


def test_cells_too_few_for_the_window_the_zone_asks_are_raised_and_said():
    """n = 16 at p_H = 6.875 sigma_Y0: 16 cells resolve a window of 1.6 a_H (10 cells across the
    contact), narrower than the zone asks: the cells grow so that the window holds the zone at
    the same cell size, and a note says so; rebuilt from its spec (as the run does) the case is
    the same.  With the window given, the cells are kept and the narrow window told."""
    from solver.keys import MIN_CELLS_ACROSS

    case = _linear_steel(6.875, n=16)
    wide = _linear_steel(6.875, n=32)  # the window the zone asks for
    need = math.ceil(16 * wide.grid.half_width / (16 / MIN_CELLS_ACROSS))
    assert case.grid.half_width == wide.grid.half_width > 16 / MIN_CELLS_ACROSS
    assert (case.grid.nx, case.grid.ny, case.grid.nz) == (need, need, 16)
    (note,) = case.warnings
    assert note.startswith(f"grid.n: raised to {need} x {need} cells (from 16 x 16)")
    rebuilt = solver.Case.from_dict(case.to_dict())
    assert rebuilt.case_id == case.case_id and rebuilt.grid == case.grid
    given = _linear_steel(6.875, n=16, half_width=1.599)
    (note,) = given.warnings
    assert (given.grid.nx, given.grid.half_width) == (16, 1.599)
    # the cells given kept their size (a whole cell more at most: rounded up)
    assert 1.0 - 1.0 / need < case.surface_grid.dx / given.surface_grid.dx <= 1.0
    assert note.startswith("grid.half_width: the window (1.599 a_H) is narrower")
    assert f"give n >= {need} and leave half_width out" in note


def test_a_sliding_window_narrower_than_the_zone_is_told():
    """A sliding case's window covers the track and is not sized for the zone: beside the track
    a zone wider than it (sized for the sliding shear mu p) is told, with the half width to
    give; at 2 sigma_Y0 the zone fits and nothing is said."""
    from solver.keys import PLASTIC_WIDTH_MARGIN
    from solver.theory.hertz import hertz_yield_half_width

    def sliding(ratio: float) -> solver.Case:
        table = _linear_steel(ratio, mu=0.3).to_dict()
        del table["model"]
        radius = solver.Case.from_dict(table).reference.max_semi_axis
        table["grid"] = {"n": [40, 32, 24]}
        path = [{"hertz_pressure": ratio * 0.8e9, "steps": 4}]
        table["load"] = {"path": [*path, {"slide": [3 * radius, 0.0], "steps": 24}]}
        return solver.Case.from_dict(table)

    case = sliding(5.0)
    (note,) = case.warnings
    assert case.grid.half_width == 1.5 and note.startswith(
        "grid.half_width: beside the track the window reaches 1.5 a_H, narrower than the "
        "plastic box"
    )
    given = float(re.search(r"give half_width >= ([0-9.]+)", note).group(1))
    extent = [hertz_yield_half_width(4e9, 0.8e9, 0.3, mu, case.grid.depth, 4.0) for mu in (0.3, 0)]
    assert given == pytest.approx(PLASTIC_WIDTH_MARGIN * extent[0], rel=0.01)  # mu p sliding
    assert extent[0] > extent[1]  # wider than frictionless: sized for the sliding friction
    assert not sliding(2.0).warnings
