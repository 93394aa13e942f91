"""Kalker's linear creep law in the steady creep-curve report, and its table.

Independent references: Kalker's table E.3 (1990) (its transcription checked for its own
symmetries); the steady solver's own small-creepage slope of an ellipse between the table's
nodes; G a b C11 computed here from the campaign's inputs (Hertz's semi-axes of
solver.theory.hertz, G = E / (2 (1 + nu))).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import solver
from solver.theory.friction import (
    KALKER_TABLE_A_ABOVE_B,
    KALKER_TABLE_A_BELOW_B,
    kalker_coefficients,
)
from solver.theory.hertz import hertz

E, W = 210e9, 1000.0


def test_the_transcribed_table_keeps_its_symmetries():
    """The circle's row is in both halves; C11 = C22 at nu = 0 (Kalker's symmetry); C23 rises
    with g where a < b (the 1.15 typo of an older copy would break it)."""
    for nu in (0.0, 0.25, 0.5):
        assert KALKER_TABLE_A_BELOW_B[1.0][nu] == KALKER_TABLE_A_ABOVE_B[1.0][nu]
    for table in (KALKER_TABLE_A_BELOW_B, KALKER_TABLE_A_ABOVE_B):
        assert all(row[0.0][0] == row[0.0][1] for row in table.values())
    for nu in (0.0, 0.25, 0.5):
        c23 = [KALKER_TABLE_A_BELOW_B[g][nu][2] for g in sorted(KALKER_TABLE_A_BELOW_B)]
        assert np.all(np.diff(c23) > 0.0)


@pytest.mark.parametrize("nu", [0.0, 0.25, 0.5])
def test_the_interpolation_gives_the_table_at_its_nodes(nu):
    for g in KALKER_TABLE_A_BELOW_B:
        assert kalker_coefficients(nu, g) == pytest.approx(KALKER_TABLE_A_BELOW_B[g][nu], 1e-12)
        assert kalker_coefficients(nu, 1.0 / g) == pytest.approx(
            KALKER_TABLE_A_ABOVE_B[g][nu], 1e-12
        )


def test_the_interpolation_lies_between_its_neighbours():
    """Between two rows (g) and between two columns (nu), each coefficient between its nodes."""
    for table, ratio in ((KALKER_TABLE_A_BELOW_B, lambda g: g),
                         (KALKER_TABLE_A_ABOVE_B, lambda g: 1.0 / g)):  # fmt: skip
        rows = sorted(table)
        for g0, g1 in zip(rows[:-1], rows[1:], strict=True):
            for nu in (0.0, 0.25, 0.5, 0.3, 0.1):
                mid = kalker_coefficients(nu, ratio(0.5 * (g0 + g1)))
                ends = kalker_coefficients(nu, ratio(g0)), kalker_coefficients(nu, ratio(g1))
                for i in range(3):
                    low, high = sorted((ends[0][i], ends[1][i]))
                    assert low - 1e-12 <= mid[i] <= high + 1e-12
                if nu in (0.0, 0.25, 0.5):  # a node column: the mean of the rows
                    assert mid == pytest.approx(np.mean(ends, axis=0), rel=1e-12)
    for nu, (n0, n1) in ((0.1, (0.0, 0.25)), (0.3, (0.25, 0.5)), (0.45, (0.25, 0.5))):
        for ratio in (0.15, 0.75, 1.0, 1.6, 7.0):
            value = kalker_coefficients(nu, ratio)
            ends = kalker_coefficients(n0, ratio), kalker_coefficients(n1, ratio)
            for i in range(3):
                assert min(ends[0][i], ends[1][i]) < value[i] < max(ends[0][i], ends[1][i])


@pytest.mark.parametrize(
    ("nu", "ratio"),
    [(-0.01, 1.0), (0.51, 1.0), (math.nan, 1.0), (0.3, 0.09), (0.3, 10.5), (0.3, math.nan),
     (0.3, 0.0), (0.3, -1.0), (0.3, math.inf)],
)  # fmt: skip
def test_the_interpolation_refuses_what_the_table_does_not_cover(nu, ratio):
    with pytest.raises(ValueError, match="Kalker's table covers"):
        kalker_coefficients(nu, ratio)


def _radius_x_for(ratio: float, nu: float, radius_y: float = 0.025) -> float:
    """Body 1's radius along x giving Hertz semi-axes a/b = ``ratio`` on a flat."""
    from scipy.optimize import brentq

    modulus = E / (2.0 * (1.0 - nu**2))

    def axes(radius_x):
        contact = hertz(W, modulus, (1.0 / radius_x, 1.0 / radius_y))
        return contact.semi_axis_x / contact.semi_axis_y - ratio

    return brentq(axes, radius_y / 50, radius_y * 50, rtol=1e-12)


@pytest.mark.parametrize(("ratio", "nu"), [(0.75, 0.25), (1.35, 0.3)])
def test_the_steady_solvers_small_creepage_slope_is_kalkers_interpolated_c11(ratio, nu):
    """An ellipse between the table's rows (and, at nu = 0.3, its columns): F_x / (G a b xi).

    12 cells on the smaller semi-axis, second-order steady scheme.
    """
    radius_x = _radius_x_for(ratio, nu)
    body1 = {"behaviour": "elastic", "E": E, "nu": nu, "radius_x": radius_x, "radius_y": 0.025}
    table = {
        "body1": body1,
        "body2": {"behaviour": "elastic", "E": E, "nu": nu},
        "friction": {"coefficient": 0.3},
        "load": {"path": [{"normal_force": W}, {"steady": True, "creepage": [1e-7, 0.0]}]},
    }
    contact = solver.Case.from_dict({**table, "grid": {"n": [40, 40]}}).hertz
    a, b = contact.semi_axis_x, contact.semi_axis_y
    assert a / b == pytest.approx(ratio, rel=1e-9)
    h = min(a, b) / 12
    n = [round(2.5 * a / h), round(2.5 * b / h)]
    result = solver.solve(
        solver.Case.from_dict({**table, "grid": {"n": n, "size": [n[0] * h, n[1] * h]}})
    )
    assert result.status == "converged"
    c11 = result.history["tangential_force_x"][-1] / (E / (2 * (1 + nu)) * a * b * 1e-7)
    expected = kalker_coefficients(nu, ratio)[0]
    assert c11 == pytest.approx(expected, rel=0.015)


# -- the report ----------------------------------------------------------------------------------
NU, RADIUS_Y = 0.25, 0.04
STEADY_ELLIPSE = f"""
[campaign]
name = "kalker"
output = "out"

[base]
grid = {{ n = [24, 24], half_width = 1.25 }}
body1 = {{ behaviour = "elastic", radius_x = 0.025, radius_y = {RADIUS_Y}, E = 210e9, nu = {NU} }}
body2 = {{ behaviour = "elastic", E = 210e9, nu = {NU} }}
friction = {{ coefficient = 0.3 }}

[[base.load.path]]
normal_force = {W}

[[base.load.path]]
steady = true
creepage = [0.004, 0.0]
steps = 8

[sweep]
"friction.coefficient" = [0.2, 0.4]
"""


def test_the_steady_report_draws_kalkers_slope_and_the_tractions(tmp_path, monkeypatch):
    import xarray as xr
    from study_fixtures import write

    from study.campaign import load_campaign
    from study.report import build_report, rolling
    from study.run import storage
    from study.run.assemble import assemble_to_file
    from study.run.driver import RunOptions, run_campaign

    out = tmp_path / "out"
    campaign = load_campaign(write(tmp_path, STEADY_ELLIPSE))
    assert run_campaign(campaign, out, options=RunOptions()).exit_status == 0
    assemble_to_file(out)
    drawn = {}
    save = rolling.figures.save

    def keep(plt, fig, path):  # the creep-curve figure's dashed lines, before it is closed
        drawn[Path(path).name] = [
            (line.get_xdata(), line.get_ydata(), line.get_color())
            for ax in fig.axes
            for line in ax.get_lines()
            if line.get_gid() == "kalker slope"
        ]
        save(plt, fig, path)

    monkeypatch.setattr(rolling.figures, "save", keep)
    text = build_report(out).read_text()

    # Kalker's slope from the inputs: G a b C11 with Hertz's a, b of a ball on a flat
    contact = hertz(W, E / (2.0 * (1.0 - NU**2)), (1.0 / 0.025, 1.0 / RADIUS_Y))
    a, b = contact.semi_axis_x, contact.semi_axis_y
    assert 0.6 < a / b < 0.9  # between the table's rows
    slope = E / (2.0 * (1.0 + NU)) * a * b * kalker_coefficients(NU, a / b)[0]
    lines = drawn["kalker_steady_creep_curves.png"]
    assert len(lines) == 2
    for mu, (xi, ratio, _) in zip((0.2, 0.4), lines, strict=True):
        assert ratio == pytest.approx([0.0, 1.0])
        assert xi[0] == 0.0 and xi[1] == pytest.approx(mu * W / slope, rel=1e-9)
    with xr.open_dataset(storage.dataset_path(out, "kalker")) as data:
        found = rolling.steady_curves(data.load(), out)
    assert [c["kalker"]["slope"] for c in found] == pytest.approx([slope, slope], rel=1e-9)
    assert "G a b C11 / (mu W)" in text and "saturation F_x = mu W" in text
    section = text[text.index("## Steady creep curves") :].splitlines()
    row = next(line for line in section if line.startswith("| 0.2 |"))
    assert float(row.split("|")[-4]) == pytest.approx(slope / (0.2 * W), rel=1e-4)
    # the first step's secant: below Kalker's slope, by about its creepage over saturation's
    first = float(row.split("|")[-3])
    assert 0.85 < first < 1.0

    # the tractions: the last point stored, two re-solved points with a stick area
    assert (out / "kalker_steady_tractions.png").exists()
    points, notes = rolling.traction_points(found, out)
    assert not notes
    assert [p["source"] for p in points].count("re-solved") == 4
    for point in points:
        assert abs(point["match"]) < 1e-6
        assert point["force"] == pytest.approx(point["curve"]["ratio"][point["index"]], abs=1e-6)
        if point["source"] == "re-solved":
            assert np.any(point["state"] == solver.result.STICK)
    assert "### Tractions of chosen steady points" in text
