"""The elliptic contacts of ``python -m study bench rolling --steady`` (study.bench.rolling).

Independent references: Hertz's semi-axes of the case the bench builds (the solver's own
reference, read back from the case) have the ratio asked for; CONTACT's input prescribes the
same semi-axes and elements of our cells' size, centred on our cells (Kalker's coefficients of
the same ellipses: tests/test_steady.py).
"""

from __future__ import annotations

import pytest

import solver
from study.bench import rolling

ACROSS = 32


@pytest.mark.parametrize("a_over_b", [0.5, 2.0])
def test_the_bench_ellipse_has_the_semi_axis_ratio_and_square_cells(a_over_b):
    table = rolling.steady_table(ACROSS, (1e-7, 0.0), a_over_b=a_over_b)
    case = solver.Case.from_dict(table)
    a, b = case.hertz.semi_axis_x, case.hertz.semi_axis_y
    assert a / b == pytest.approx(a_over_b, rel=1e-9)
    # the rolling direction x carries a: the longer axis along x for a/b = 2
    assert (a > b) == (a_over_b > 1.0)
    cell = 2.0 * min(a, b) / ACROSS
    grid = case.surface_grid
    assert grid.dx == pytest.approx(cell, rel=1e-9) and grid.dy == pytest.approx(cell, rel=1e-9)
    half_x, half_y = case.domain_half_widths
    assert half_x >= 1.2 * a and half_y >= 1.2 * b  # the ellipse with a margin
    # CONTACT: AA, BB the same semi-axes (mm), square elements of our cell, DQ one element
    lines = rolling._contact_input(ACROSS, (1e-4, 0.0), 0.0, a_over_b).splitlines()
    mx, my, aa, bb, scale = (float(v) for v in lines[11].split()[:5])
    assert (aa, bb) == pytest.approx((1e3 * a, 1e3 * b), rel=1e-7)
    assert 2 * aa * scale / mx == pytest.approx(1e3 * cell, rel=1e-7)
    assert 2 * bb * scale / my == pytest.approx(1e3 * cell, rel=1e-7)
    assert float(lines[8].split()[1]) == pytest.approx(1e3 * cell, rel=1e-6)
    assert scale > 1.0  # the potential contact covers the ellipse
    # the elements' centres are our cells' centres (both grids centred on the contact)
    assert (mx - case.grid.nx) % 2 == 0 and (my - case.grid.ny) % 2 == 0
