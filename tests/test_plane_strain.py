"""A line contact's volume: plane-strain stresses of strips (``grid.periodic = "y"``)."""

import numpy as np
import pytest

from solver.numerics.grid import SurfaceGrid, VolumeGrid
from solver.theory.half_space import TRACTIONS, mcewen_stress, rectangle_stress, strip_stress
from solver.volume.plane_strain import PlaneStrainStressOperator

NU = 0.3


@pytest.mark.parametrize("traction", TRACTIONS)
def test_a_strip_is_loves_rectangle_made_long(traction):
    """The strip's closed form against Love's rectangle (and Cerruti's), 1 wide and L long
    along y, at y = 0: the difference falls as the rectangle grows (as 1/L or faster: the
    ends' field at distance L/2) and is below 1e-5 of the unit load at L = 1e5."""
    x = np.array([-2.3, -0.7, 0.13, 0.55, 1.9])  # off the lines through its edges
    z = 0.4
    strip = strip_stress(x, z, 0.5, NU, traction)
    misfits = [np.abs(strip - rectangle_stress(x, 0.0, z, 1.0, length, NU, traction)).max()
               for length in (1e2, 1e3, 1e4, 1e5)]  # fmt: skip
    assert all(b < 0.2 * a for a, b in zip(misfits, misfits[1:], strict=False)), misfits
    assert misfits[-1] < 1e-5
    assert np.abs(strip).max() > 0.05  # a field, not zeros


def test_strips_make_mcewens_line_contact_converging():
    """The plane-strain operator on cell-constant Hertz line tractions (pressure and a
    sliding shear mu p) against McEwen's closed form at the cells: the largest error (of p0)
    below a few cells' depth halves with each halving of the cells."""
    a, p0, mu = 1e-3, 1e9, 0.3
    errors = []
    for cells in (16, 32, 64):
        dx = 2 * a / cells
        surface = SurfaceGrid.centred(3 * cells, 4, 1.5 * cells * dx, 2 * dx)
        volume = VolumeGrid(surface, cells, a / cells)
        operator = PlaneStrainStressOperator(volume, NU)
        x = surface.x
        profile = p0 * np.sqrt(np.clip(1 - (x / a) ** 2, 0, None))
        pressure = np.repeat(profile[:, None], 4, axis=1)
        got = operator.stress(pressure, mu * pressure)
        assert np.array_equal(got[:, :, 0], got[:, :, 3])  # the same on every row
        deep = volume.z > 0.25 * a
        want = mcewen_stress(x[:, None], volume.z[None, deep], a, p0, NU, mu)
        errors.append(float(np.abs(got[:, :, 1, deep] - want).max() / p0))
    assert errors[0] < 0.05 and errors[1] < 0.6 * errors[0] and errors[2] < 0.6 * errors[1], errors


def test_the_operator_balances_the_load_and_keeps_a_box():
    """Near the surface the stress balances cell-constant tractions (sigma_zz = -p, sigma_xz =
    -q_x, sigma_yz = -q_y at a cell's centre, to the depth's O(z/dx)); a box is a slice of the
    whole grid's field."""
    surface = SurfaceGrid(8, 4, 1e-4, 1e-4)
    volume = VolumeGrid(surface, 4, 1e-7)
    rng = np.random.default_rng(3)
    p, qx, qy = (np.repeat(rng.uniform(0, 1e8, (8, 1)), 4, axis=1) for _ in range(3))
    operator = PlaneStrainStressOperator(volume, NU)
    whole = operator.stress(p, qx, qy)
    top = whole[:, :, :, 0]
    for component, load in ((2, p), (4, qx), (3, qy)):
        np.testing.assert_allclose(top[component], -load, atol=1e-2 * 1e8)
    from solver.numerics.grid import IndexBox

    box = IndexBox((2, 6), (1, 3), (1, 4))
    np.testing.assert_array_equal(operator.stress(p, qx, qy, box), whole[:, 2:6, 1:3, 1:4])
    with pytest.raises(ValueError, match="at least one"):
        operator.stress()


def test_the_memory_estimate_covers_the_operator():
    surface = SurfaceGrid(64, 4, 1e-5, 1e-5)
    volume = VolumeGrid(surface, 32, 1e-5)
    operator = PlaneStrainStressOperator(volume, NU)
    out = operator.stress(np.ones((64, 4)), np.ones((64, 4)), np.ones((64, 4)))
    held = sum(s.nbytes for s in operator._spectra.values()) + out.nbytes
    estimate = PlaneStrainStressOperator.memory_bytes(volume)
    assert held <= estimate < 3 * held
