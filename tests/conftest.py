import copy

import pytest

STEEL = {"behaviour": "elastic", "E": 210e9, "nu": 0.3}

RIGID_SPHERE_ON_STEEL = {
    "body1": {"radius": 0.015, "behaviour": "rigid"},
    "body2": {"radius": "inf", **STEEL},
    "load": {"hertz_pressure": 6e9, "steps": 1},
    "friction": {"coefficient": 0.0},
    "grid": {"n": 64, "half_width": 1.6},
}


@pytest.fixture
def hertz_table():
    """A fresh copy of the rigid-sphere-on-steel case table (p_H = 6 GPa)."""
    return copy.deepcopy(RIGID_SPHERE_ON_STEEL)
