"""Inputs that used to pass silently, and numbers a user can trust at the edges (issue 20).

Each test states the input as it was reported and what it did before: a volume box that gave
an elastic answer, yield stresses that divided by zero, a load path of 2e9 increments that ran
out of memory, messages with an empty field name, and hard plastic cases past the contained
regime that ran without a word.
"""

from __future__ import annotations

import copy
import dataclasses
import math
from collections.abc import Iterator

import numpy as np
import pytest
from study_fixtures import write

import solver
from solver.case.grid import MAX_CELL_DEPTH, MIN_YIELD_CELLS
from solver.case.notes import (
    FULLY_PLASTIC_INDEX,
    SMALL_STRAIN_LIMIT,
    UNCONTAINED_PLASTIC_INDEX,
    plastic_index,
)
from solver.case.reading import SpecError
from solver.keys import MAX_INCREMENTS
from solver.theory.hertz import first_yield_pressure, hertz_yield_region
from study.campaign import load_campaign
from study.cli import LONG_PATH, main, path_warnings

STEEL = {"E": 210e9, "nu": 0.3}
SWIFT = {"law": "swift", "B": 945e6, "C": 20.0, "n": 0.121}
SIGMA_Y0 = SWIFT["B"] * SWIFT["C"] ** SWIFT["n"]


def swift_case(p_h=4e9, n=16, nz=16, steps=4, **grid):
    """The paper's Swift steel under a rigid sphere (R = 15 mm), as the issue reported it."""
    return {
        "body1": {"behaviour": "rigid", "radius": 0.015},
        "body2": {"behaviour": "elastic-plastic", "radius": "inf", **STEEL, "hardening": SWIFT},
        "load": {"hertz_pressure": p_h, "steps": steps},
        "grid": {"n": [n, n, nz], **grid},
    }


def perfect_case(ratio, law=None, load=None, n=16):
    """A rigid sphere on a 1 GPa steel, loaded to p_H = ratio x 1 GPa.

    2n layers (thinner than 0.62 of a cell at these loads): a perfectly plastic body on
    thicker ones has a note of its own (:func:`solver.case.notes.layer_note`).
    """
    law = law or {"law": "perfect", "yield_stress": 1e9}
    return {
        "body1": {"behaviour": "rigid", "radius": 0.015},
        "body2": {"behaviour": "elastic-plastic", "radius": "inf", **STEEL, "hardening": law},
        "load": load or {"hertz_pressure": ratio * 1e9, "steps": 10},
        "grid": {"n": [n, n, 2 * n]},
    }


# -- 1. the volume depth ---------------------------------------------------------------------------
@pytest.mark.parametrize("depth", [1e6, 1e-9, 10, 30, 100, 0.3])
def test_a_box_that_gave_an_elastic_or_wrong_answer_is_refused_by_name(depth):
    """Before: depth 1e6, 1e-9, 100 gave e_p = 0 and 10, 30 gave 8.8e-4, 3.1e-4 (true 1.4e-3),
    all "converged" with no note; 0.3 ends above 0.48 a_H, where plasticity starts."""
    with pytest.raises(SpecError, match=r"^grid\.depth: ") as info:
        solver.Case.from_dict(swift_case(depth=depth))
    assert "\n" not in str(info.value)


def test_depth_body1_is_bounded_too():
    table = swift_case()
    table["body1"] = {
        "behaviour": "elastic-plastic",
        "radius": 0.015,
        **STEEL,
        "hardening": {"law": "linear", "yield_stress": 0.6e9, "modulus": 20e9},
    }
    table["grid"]["n"] = [24, 24, 16]
    assert solver.Case.from_dict(table).plastic_bodies == (2, 1)
    for depth in (1e6, 30.0):  # 1e6 dropped body 1's plasticity
        table["grid"]["depth_body1"] = depth
        with pytest.raises(SpecError, match=r"^grid\.depth_body1: "):
            solver.Case.from_dict(table)


def test_the_refused_cells_do_give_an_elastic_answer(monkeypatch):
    """Why the cell rule: at p_H = 1.77 sigma_Y0 (yield region 0.28-0.75 a_H), half-a_H cells
    put no cell centre where the stress yields, and the solve says "converged" with e_p = 0."""
    p_h = 1.77 * SIGMA_Y0
    top, bottom = hertz_yield_region(p_h, SIGMA_Y0, 0.3)
    assert 0.5 > bottom - top > 0.25
    coarse = swift_case(p_h, nz=4, depth=2.0)  # cells 0.5 a_H thick
    with pytest.raises(SpecError, match=r"grid\.depth: cells 0\.5 a_H thick .* use nz >= 8"):
        solver.Case.from_dict(coarse)
    monkeypatch.setattr("solver.case.grid.MAX_CELL_DEPTH", 10.0)
    monkeypatch.setattr("solver.case.grid.MIN_YIELD_CELLS", 0)
    silent = solver.solve(solver.Case.from_dict(coarse))
    assert silent.converged and silent.history["max_plastic_strain"][-1] == 0.0
    monkeypatch.undo()
    resolved = solver.solve(solver.Case.from_dict(swift_case(p_h, nz=16, depth=2.0)))
    assert resolved.converged and resolved.history["max_plastic_strain"][-1] > 0.0


def test_the_accepted_boxes_agree_with_the_yield_sized_one():
    """Accepted boxes below the yield region give the default box's e_p,max: within 5 % with
    cells of 0.19 a_H, within 20 % at the thickest accepted cells (the largest strain is
    sampled at cell centres); the refused ones were 40-100 % off."""
    default = solver.solve(solver.Case.from_dict(swift_case()))
    reference = default.history["max_plastic_strain"][-1]
    _, bottom = hertz_yield_region(4e9, SIGMA_Y0, 0.3)
    assert bottom < 2.0
    for depth, within in ((2.0, 0.05), (3.0, 0.05), (16 * MAX_CELL_DEPTH, 0.2)):
        result = solver.solve(solver.Case.from_dict(swift_case(depth=depth)))
        assert result.status == "converged", result.notes
        assert result.history["max_plastic_strain"][-1] == pytest.approx(reference, rel=within)


def test_a_box_that_cuts_the_plastic_zone_is_solved_but_not_trusted():
    """Between the depth where plasticity starts and the yield region's bottom: solved, with
    the note and the status "truncated" (before: "converged")."""
    start = first_yield_pressure(SIGMA_Y0, 0.3)[1]
    result = solver.solve(solver.Case.from_dict(swift_case(depth=max(start, 0.5))))
    assert result.converged and result.truncated
    assert result.status == "truncated"
    assert any("reaches the volume grid's bottom" in note for note in result.notes)
    assert result.to_xarray().attrs["status"] == "truncated"


def test_too_few_cells_across_the_yield_region_names_the_nz_that_resolves_it():
    p_h = 1.62 * SIGMA_Y0  # just past first yield (1.613 sigma_Y0): a thin region
    top, bottom = hertz_yield_region(p_h, SIGMA_Y0, 0.3)
    with pytest.raises(SpecError, match=r"^grid\.n: .*at least 2 needed\): use nz >= (\d+)") as e:
        solver.Case.from_dict(swift_case(p_h, nz=16))
    need = int(str(e.value).rsplit(">= ", 1)[1])
    depth = solver.Case.from_dict(swift_case(p_h, nz=need)).grid.depth
    assert (bottom - top) / (depth / need) >= MIN_YIELD_CELLS
    assert (bottom - top) / (depth / (need - 1)) < MIN_YIELD_CELLS


# -- 2. yield stresses that underflow --------------------------------------------------------------
@pytest.mark.parametrize(
    ("hardening", "field"),
    [
        ({"law": "perfect", "yield_stress": 5e-324}, "yield_stress"),
        ({"law": "perfect", "yield_stress": 1e-300}, "yield_stress"),
        ({"law": "linear", "yield_stress": 1e-300, "modulus": 1e9}, "yield_stress"),
        ({"law": "swift", "B": 5e-324, "C": 20.0, "n": 0.121}, "B"),
        ({"law": "swift", "B": 945e6, "C": 1e-300, "n": 0.121}, "C"),
        ({"law": "perfect", "yield_stress": 0.2 * STEEL["E"]}, "yield_stress"),
        ({"law": "linear", "yield_stress": 1e9, "modulus": 1e300}, "modulus"),
        ({"law": "swift", "B": 945e6, "C": 20.0, "n": 3.0}, "n"),
    ],
)
def test_yield_stresses_and_hardening_parameters_are_bounded(hardening, field):
    """Before: 5e-324 raised ZeroDivisionError, 1e-300 ran to increments of 1e307."""
    table = perfect_case(4, law=hardening)
    with pytest.raises(SpecError, match=rf"^body2\.hardening\.{field}: "):
        solver.Case.from_dict(table)


def test_a_hand_built_vanishing_yield_stress_is_told_not_raised():
    """The residual scale is floored: a Case built past validation reports, never divides by 0."""
    case = solver.Case.from_dict(
        perfect_case(4, load={"hertz_pressure": 4e9, "steps": 1})
        | {"solver": {"plastic_max_iterations": 3}}
    )
    hardening = dataclasses.replace(case.body2.hardening, yield_stress=5e-324)
    case = dataclasses.replace(case, body2=dataclasses.replace(case.body2, hardening=hardening))
    result = solver.solve(case)
    assert not result.converged  # and its zone reaches the box: truncated is the status
    assert result.status == ("truncated" if result.truncated else "not_converged")
    assert any(note.startswith("diagnosis: the plasticity") for note in result.notes)
    assert np.isfinite(result.history["residual"]).all()
    assert np.isfinite(result.fields["plastic_strain"]).all()


# -- 3. load paths too long to hold ---------------------------------------------------------------
def _cycled(cycles, steps):
    return {
        "path": [
            {"hertz_pressure": 1e9, "steps": 1},
            {"cycles": cycles, "stages": [
                {"tangential_force": 10.0, "steps": steps},
                {"tangential_force": -10.0, "steps": steps},
            ]},
        ]
    }  # fmt: skip


def _elastic(load):
    return {
        "body1": {"behaviour": "elastic", "radius": 0.01, **STEEL},
        "body2": {"behaviour": "elastic", "radius": "inf", **STEEL},
        "load": load,
        "friction": {"coefficient": 0.3},
        "grid": {"n": 16},
    }


def test_a_path_of_two_billion_increments_is_refused_before_it_is_built():
    """Before: validate passed (a memory warning), run died with a bare MemoryError."""
    with pytest.raises(SpecError, match=r"^load\.path\[1\]\.cycles: .* more than 1,000,000"):
        solver.Case.from_dict(_elastic(_cycled(10_000, 100_000)))
    # the same cap for stages side by side, none of them over its own limit
    stages = [{"hertz_pressure": 1e9, "steps": 100_000}] * 11
    with pytest.raises(SpecError, match=r"^load\.path\[10\]\.steps: the load path reaches"):
        solver.Case.from_dict(_elastic({"path": stages}))


def test_the_path_is_walked_not_held():
    case = solver.Case.from_dict(_elastic(_cycled(3, 2)))
    targets = case.step_targets()
    assert isinstance(targets, Iterator)
    walked = list(targets)
    assert len(walked) == case.total_steps == 1 + 3 * 2 * 2
    assert walked[0] == (case.stages[0].normal_force, 0.0, 0.0, 0.0, 0.0)  # W, Q, position
    assert walked[-1][1] == pytest.approx(-10.0)
    longest = solver.Case.from_dict(_elastic(_cycled((MAX_INCREMENTS - 1) // 200_000, 100_000)))
    assert longest.total_steps <= MAX_INCREMENTS


def test_validate_warns_on_path_length_before_anything_runs(tmp_path, capsys):
    campaign = {
        "campaign": {"name": "long"},
        "base": _elastic(_cycled(60, 100)),
        "sweep": {"friction.coefficient": [0.3]},
    }
    text = _toml(campaign)
    status = main(["validate", str(write(tmp_path, text))])
    err = capsys.readouterr().err
    assert status == 0
    assert f"load paths of more than {LONG_PATH:,} increments" in err and "12,001" in err
    short = load_campaign(write(tmp_path, _toml({**campaign, "base": _elastic(_cycled(2, 10))})))
    assert path_warnings(short) == []


# -- 4. messages ---------------------------------------------------------------------------------
def test_a_case_that_is_not_a_table_is_named():
    """Before: Case.from_dict(None) said ": must be a table" (no field)."""
    with pytest.raises(SpecError, match=r"^case: must be a table, got NoneType"):
        solver.Case.from_dict(None)
    with pytest.raises(SpecError, match=r"^body1: must be a table, got NoneType"):
        solver.Case.from_dict({**_elastic({"hertz_pressure": 1e9}), "body1": None})


# -- 5. hard plastic cases past the contained regime -----------------------------------------------
HARD = {
    "perfect at p_H = 10 sigma_Y": perfect_case(10),
    "linear hardening of 1 MPa at 8 GPa": perfect_case(
        8, law={"law": "linear", "yield_stress": 1e9, "modulus": 1e6}
    ),
    "Swift n = 1e-4 at 8 GPa": perfect_case(
        8, law={"law": "swift", "B": 1e9 / 20.0**1e-4, "C": 20.0, "n": 1e-4}
    ),
    "unloading and reloading a perfect body at 10 sigma_Y": perfect_case(
        10,
        load={
            "path": [
                {"hertz_pressure": 10e9, "steps": 10},
                {"normal_force": 0.0, "steps": 5},
                {"hertz_pressure": 10e9, "steps": 5},
            ]
        },
    ),
}


@pytest.mark.parametrize("name", list(HARD))
def test_hard_plastic_cases_are_told_when_built(name):
    """Before: built without a word, then not converged at most steps."""
    case = solver.Case.from_dict(HARD[name])
    index = plastic_index(case.body2, case.hertz.max_pressure)
    assert UNCONTAINED_PLASTIC_INDEX < index < FULLY_PLASTIC_INDEX
    # 16 cells resolve a narrower window than the zone asks: a note of its own says the cells
    (warning,) = [w for w in case.warnings if not w.startswith("grid.n: raised")]
    assert "Johnson's index" in warning and f"{index:.3g}" in warning
    assert "may not converge" in warning


def test_the_note_reaches_the_result_and_the_contained_regime_has_none():
    table = copy.deepcopy(HARD["perfect at p_H = 10 sigma_Y"])
    table["load"]["steps"] = 2
    result = solver.solve(solver.Case.from_dict(table))
    assert any("Johnson's index" in note for note in result.notes)
    if result.history["max_plastic_strain"][-1] > SMALL_STRAIN_LIMIT:
        assert any("beyond the small-strain range" in note for note in result.notes)
    contained = solver.Case.from_dict(perfect_case(6, n=20))  # index 9.4: converged every step
    assert plastic_index(contained.body2, contained.hertz.max_pressure) < UNCONTAINED_PLASTIC_INDEX
    assert contained.warnings == ()
    paper = solver.Case.from_dict(swift_case(8e9, n=20, nz=24))  # the paper's 8 GPa: hardening
    assert paper.warnings == ()


def test_a_fully_plastic_indentation_is_refused_citing_the_limit():
    ratio = 1.01 * FULLY_PLASTIC_INDEX * 2 / math.pi  # p_H / sigma_Y at Johnson's index 30.3
    with pytest.raises(SpecError, match=r"^load: Johnson's index .* fully plastic indentation"):
        solver.Case.from_dict(perfect_case(ratio, n=32))


def _toml(table: dict) -> str:
    from test_fuzz_inputs import to_toml

    return to_toml(table)


# -- 6. layers under a perfectly plastic body ------------------------------------------------------
def _rayleigh_quotient(thickness: float, pattern: str) -> float:
    """-<sigma, e> / (2 G <e, e>) of an xx - zz eigenstrain alternating in x and z.

    The block of 12 x 12 x (nz / 2) cells in a 16^2 grid of cells 1 m wide and ``thickness``
    thick; 1 for an eigenstrain its own stress fully resists, negative for one its stress
    drives on.
    """
    from solver.numerics.grid import SurfaceGrid, VolumeGrid
    from solver.numerics.tensor import WEIGHTS, deviator
    from solver.volume.eigenstrain import EigenstrainOperator

    n, nz = 16, round(16 / thickness)
    grid = VolumeGrid(SurfaceGrid(n, n, 1.0, 1.0), nz, thickness)
    operator = EigenstrainOperator(grid, STEEL["E"], STEEL["nu"])
    i, j, k = np.meshgrid(np.arange(n), np.arange(n), np.arange(nz), indexing="ij")
    block = (abs(i - n / 2) < 6) & (abs(j - n / 2) < 6) & (k >= nz / 4) & (k < 3 * nz / 4)
    sign = {"x": (-1.0) ** i, "xz": (-1.0) ** (i + k)}[pattern]
    strain = np.zeros((6, n, n, nz))
    strain[0], strain[2] = sign * block, -sign * block
    stress = deviator(operator.stress(strain))
    weights = np.asarray(WEIGHTS)[:, None, None, None]
    shear_modulus = STEEL["E"] / (2 * (1 + STEEL["nu"]))
    energy = (weights * stress * strain).sum()
    return float(-energy / (2 * shear_modulus * (weights * strain**2).sum()))


def test_cubic_cells_have_a_checkerboard_their_stress_drives_and_thin_layers_do_not():
    """Why the layer note: the cell-centre stress of a cell-wise eigenstrain drives xx - zz
    alternating in x and z on cubic cells (nothing but hardening holds it back), and resists
    it on layers half a cell thick; a smooth pattern is resisted on both."""
    assert _rayleigh_quotient(1.0, "xz") < -0.1
    assert _rayleigh_quotient(0.5, "xz") > 0.1
    assert _rayleigh_quotient(1.0, "x") > 0.1 and _rayleigh_quotient(0.5, "x") > 0.1


def test_a_perfectly_plastic_body_on_thick_layers_is_told_the_layers_to_use():
    table = perfect_case(6)
    table["grid"]["n"] = [20, 20, 16]  # 20 cells: the window holds the plastic zone
    thick = solver.Case.from_dict(table)
    (note,) = thick.warnings
    ratio = thick.volume_grid.dz / thick.surface_grid.dx
    assert note.startswith(f"layers {ratio:.2g} of a cell thick") and "grid.n" in note
    nz = int(note.rsplit("nz >= ", 1)[1].split()[0])
    table["grid"]["n"] = [20, 20, nz]
    case = solver.Case.from_dict(table)
    assert case.warnings == () and case.volume_grid.dz <= 0.62 * case.surface_grid.dx
    hardening = perfect_case(6, law={"law": "linear", "yield_stress": 1e9, "modulus": 10e9})
    hardening["grid"]["n"] = [20, 20, 16]
    assert solver.Case.from_dict(hardening).warnings == ()  # hardening holds the pattern back
