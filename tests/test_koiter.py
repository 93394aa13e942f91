"""Koiter's kinematic shakedown theorem on the cross-section: an upper bound that converges.

Independent references: the line contact's limit from the orthogonal shear of McEwen's
closed-form field (Johnson & Jefferis 1963: 4.0 k), which the kinematic bound must not go
below and must approach; Ponter, Hearle & Johnson's 4.7 k (their mechanisms' upper bound) for
the point contact, which a richer mechanism must not exceed by more than its mesh error; the
static program's limit, which the two bracket ever more tightly.  Exact properties of the
program: nested meshes and instants can only lower the bound; a larger back-stress bound can
only raise it; the mechanism is compatible, incompressible and held on the box's edges.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from solver.theorems import koiter
from solver.theorems.koiter import Mesh, kinematic_limit, strain_operator
from solver.theorems.track import KINEMATIC_BOX, Track, track_limits
from solver.theory.half_space import mcewen_stress

#: Ponter, Hearle & Johnson (1985): frictionless point contact, kinematic theorem (upper bound).
PONTER_POINT = 4.7


def _line(s, y, z):
    """McEwen's frictionless line-contact field, the same at every y (per unit p0, a = 1)."""
    field = mcewen_stress(-s, z, 1.0, 1.0, 0.3, 0.0)
    return np.broadcast_to(field, (6, *np.broadcast_shapes(np.shape(s), np.shape(y), np.shape(z))))


def _instants(cells: int, span: float = 2.0) -> np.ndarray:
    return np.linspace(-span, span, round(2 * span * cells) + 1)


@pytest.mark.validation
def test_line_contact_bound_lies_above_johnson_and_jefferis_and_converges(validation):
    z = np.linspace(1e-3, 2.0, 4001)
    x = np.linspace(-2.0, 2.0, 801)
    expected = 1.0 / np.abs(mcewen_stress(x[:, None], z[None, :], 1.0, 1.0, 0.3)[4]).max()
    bounds = [kinematic_limit(_line, _instants(c), 1.0, 1.0, c).factor for c in (4, 8)]
    errors = [b / expected - 1.0 for b in bounds]
    assert all(e > -1e-4 for e in errors)  # an upper bound (up to the work's quadrature)
    assert errors[1] < 0.005 and errors[1] < errors[0] / 4
    validation(
        "Koiter's kinematic shakedown bound, frictionless line contact (solver.theorems.koiter)",
        f"Johnson & Jefferis 1963: 1 / max |tau_xz| = {expected:.4f} k (from above)",
        "error " + ", ".join(f"{e:+.1e}" for e in errors) + " at a/4, a/8",
    )


@pytest.mark.validation
def test_point_contact_bound_falls_with_the_mesh_below_ponters_onto_the_static(validation):
    limits = [track_limits(Track("point", 0.0, 0.3, cells=c), kinematic_cells=c) for c in (4, 8)]
    kin = [lim.kinematic.factor for lim in limits]
    static = [lim.static.factor for lim in limits]
    assert all(lim.kinematic.converged for lim in limits)
    assert kin[1] < kin[0]  # the coarse mesh's mechanisms are among the fine one's
    assert kin[1] < PONTER_POINT * 1.001  # no worse than Ponter's mechanisms
    assert abs(kin[1] - static[1]) < 0.5 * abs(kin[0] - static[0])  # the bracket closes
    assert abs(kin[1] / static[1] - 1.0) < 0.01
    assert kin[1] > limits[1].first_yield
    validation(
        "Koiter's kinematic shakedown bound, frictionless point contact (solver.theorems.koiter)",
        "Ponter, Hearle & Johnson 1985: 4.7 k (upper bound); Melan's static limit beside it",
        f"kinematic {kin[0]:.4f} k, {kin[1]:.4f} k; static {static[0]:.4f} k, "
        f"{static[1]:.4f} k at a/4, a/8",
    )


def test_friction_closes_the_gap_the_pointwise_bound_leaves():
    """mu = 0.2: the limit is below the surface and the pointwise bound well above it."""
    limits = track_limits(Track("point", 0.2, 0.3, cells=8), kinematic_cells=8)
    assert limits.kinematic.factor < limits.upper
    gap = limits.kinematic.factor / limits.static.factor - 1.0
    assert 0.0 < gap < 0.5 * (limits.upper / limits.static.factor - 1.0)


def test_the_mechanism_is_compatible_incompressible_and_held():
    cells, width, depth = 4, KINEMATIC_BOX, KINEMATIC_BOX
    track = Track("point", 0.2, 0.3, cells=cells)
    result = kinematic_limit(track.stress, _instants(cells), width, depth, cells)
    assert result.converged and math.isfinite(result.factor)
    mesh = Mesh.build(round(width * cells), round(depth * cells), 1.0 / cells)
    u = result.displacement  # (3, 2 ny + 1, 2 nz + 1)
    strain = (strain_operator(mesh) @ u.reshape(-1)).reshape(-1, 6)
    scale = np.abs(strain).max()
    assert scale > 0.0  # a mechanism that moves
    assert np.abs(strain[:, 1] + strain[:, 2]).max() < 1e-6 * scale  # traceless
    assert np.abs(strain[:, 0]).max() == 0.0  # nothing changes along x
    assert np.abs(u[:, -1, :]).max() == 0.0 and np.abs(u[:, :, -1]).max() == 0.0
    assert np.abs(u[1, 0, :]).max() == 0.0  # u_y = 0 on the centre line
    assert result.dissipation.sum() == pytest.approx(result.factor, rel=1e-6)
    assert (result.dissipation >= -1e-9).all()


def test_a_larger_back_stress_bound_can_only_raise_the_bound():
    """b = 0 is perfect plasticity; b = inf leaves alternating plasticity only."""
    track = Track("point", 0.5, 0.3, cells=4)
    bounds = [
        kinematic_limit(track.stress, _instants(4), 1.5, 1.5, 4, back_stress_bound=b).factor
        for b in (None, 0.0, 0.3, math.inf)
    ]
    assert bounds[1] == pytest.approx(bounds[0], rel=1e-5)
    assert bounds[0] * (1 - 1e-6) <= bounds[2] <= bounds[3] * (1 + 1e-6)
    assert bounds[3] > bounds[0] * 1.05  # the surface ratchets; alternating needs more


def test_a_solver_that_stops_gives_a_status_and_no_bound(monkeypatch):
    monkeypatch.setattr(koiter, "MAX_SOLVER_ITERATIONS", 2)
    track = Track("point", 0.0, 0.3, cells=4)
    result = kinematic_limit(track.stress, _instants(4), 1.0, 1.0, 4)
    assert result.status == "solver" and "MaxIterations" in result.reason
    assert result.factor == math.inf and not result.converged
    assert not np.isnan(result.displacement).any()


def test_only_point_contacts_take_a_mechanism():
    with pytest.raises(ValueError, match="kinematic_cells"):
        track_limits(Track("line", 0.0, 0.3, cells=10), kinematic_cells=4)


def test_a_load_that_does_no_work_is_infeasible_and_said_so():
    """No elastic stress: no mechanism can be normalised; Clarabel says infeasible."""

    def nothing(s, y, z):
        return np.zeros((6, *np.broadcast_shapes(np.shape(s), np.shape(y), np.shape(z))))

    result = kinematic_limit(nothing, _instants(2), 1.0, 1.0, 2)
    assert result.status == "solver" and "Infeasible" in result.reason
    assert result.factor == math.inf
