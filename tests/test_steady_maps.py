"""Steady rolling over shapes given point by point (height maps): a worn, conformal profile.

Independent references: the same sphere given as a quadric (Hertz) and as a height map; and,
for a non-Hertzian gap (a wheel's curvature along the rolling direction with a worn, quartic
transverse profile: the wheel-rail use case), the transient march of one-cell steps, which
ends at the first-order steady state (its discretisation is the same).
"""

from __future__ import annotations

import numpy as np
import pytest

import solver
from study.campaign.surfaces import read_surface

E, NU, MU, W, R = 210e9, 0.25, 0.3, 1000.0, 0.025
ELASTIC = {"behaviour": "elastic", "E": E, "nu": NU}
#: A quartic transverse profile c y^4 whose height at y = 0.55 mm is the sphere's there.
QUARTIC = (0.55e-3) ** 2 / (2 * R) / (0.55e-3) ** 4
SPACING = 10e-6  # m: the map's lattice


def _map(tmp_path, name: str, quartic: bool, extent: float = 1.5e-3) -> dict:
    """A height map of body 1 (.npy): x^2 / 2R plus y^2 / 2R or the quartic profile, over
    ``|x| <= extent`` (m) and ``|y| <= 1.5 mm``."""
    along = np.arange(-extent, extent + SPACING / 2, SPACING)
    across = np.arange(-1.5e-3, 1.5e-3 + SPACING / 2, SPACING)
    x, y = np.meshgrid(along, across)  # height[j, i] at (x[i], y[j])
    across = QUARTIC * y**4 if quartic else y * y / (2 * R)
    path = tmp_path / f"{name}.npy"
    np.save(path, x * x / (2 * R) + across)
    return {"file": str(path), "spacing": SPACING}  # centred on the apex


def _solve(body1: dict, stages: list[dict], n: tuple[int, int], size: float, order: int = 1):
    cell = size / n[1]
    table = {
        "body1": body1,
        "body2": ELASTIC,
        "friction": {"coefficient": MU},
        "load": {"path": [{"normal_force": W}, *stages]},
        "grid": {"n": list(n), "size": [n[0] * cell, n[1] * cell]},
    }
    if any(stage.get("steady") for stage in stages):
        table["solver"] = {"steady_order": order}
    result = solver.solve(solver.Case.from_dict(table, read_surface))
    assert result.status == "converged", result.notes
    return result


def test_a_sphere_given_as_a_height_map_rolls_as_the_quadric(tmp_path):
    stage = [{"steady": True, "creepage": [0.002, 0.0]}]
    size, n = 2.6e-3, (26, 26)
    quadric = _solve({**ELASTIC, "radius": R}, stage, n, size, order=2)
    mapped = _solve({**ELASTIC, "surface": _map(tmp_path, "sphere", False)}, stage, n, size, 2)
    force = quadric.history["tangential_force_x"][-1]
    assert force > 0.2 * MU * W  # a partial slip state, not saturated
    assert mapped.history["tangential_force_x"][-1] == pytest.approx(force, rel=2e-3)


def test_a_worn_profile_steady_state_is_where_the_march_ends(tmp_path):
    """The march of one-cell steps over a non-Hertzian gap, rolled 4 domains, ends at the
    first-order steady state (the same discretisation: within 1e-4 mu W)."""
    worn = {**ELASTIC, "surface": _map(tmp_path, "worn", True)}
    size, ny = 2.6e-3, 20
    cell = size / ny
    xi = 0.002
    steady = _solve(worn, [{"steady": True, "creepage": [xi, 0.0]}], (ny, ny), size)
    force = steady.history["tangential_force_x"][-1]
    assert 0.1 * MU * W < force < 0.9 * MU * W
    travel = 4.0 * size
    steps = round(travel / cell)
    track = {**ELASTIC, "surface": _map(tmp_path, "track", True, travel + size)}
    march = _solve(
        track,
        [{"roll": [steps * cell, 0.0], "creepage": [xi, 0.0], "steps": steps}],
        (ny + steps, ny),
        size,
    )
    rolled = march.history["tangential_force_x"]
    assert abs(rolled[-1] - force) < 1e-4 * MU * W, (rolled[-1], force)
    assert abs(rolled[steps // 4] - force) > 10 * abs(rolled[-1] - force)  # it got there
