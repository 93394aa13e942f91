"""The Hertz yield searches sample the axis sparsely and return what every sample returns.

:func:`solver.theory.hertz.hertz_yield_region` and :func:`~solver.theory.hertz.first_yield_pressure`
evaluate the axis stress on coarse samples and in full only where it can reach the level
(a bound on its slope).  Here the same quantities come from every sample (the search they
replaced) and must be equal bit for bit: the case ids of elastic-plastic cases hold them.
"""

from __future__ import annotations

import numpy as np
import pytest

from solver.theory import hertz

NUS = (-0.5, 0.0, 0.1, 0.2, 0.25, 0.3, 0.33, 0.4, 0.45, 0.49, 0.4999)


def _region_from_every_sample(max_pressure, yield_stress, nu):
    zeta, parts, _ = hertz._axis_samples(20.0, 200001)
    excess = hertz._axis_stress(parts, nu)[2] - yield_stress / max_pressure
    above = np.flatnonzero(excess >= 0)
    if above.size == 0:
        return 0.0, 0.0

    def crossing(k):
        return float(zeta[k] + excess[k] / (excess[k] - excess[k + 1]) * (zeta[k + 1] - zeta[k]))

    first, last = above[0], min(above[-1], zeta.size - 2)
    return (0.0 if first == 0 else crossing(first - 1)), crossing(last)


def _first_yield_from_every_sample(yield_stress, nu):
    zeta, parts, _ = hertz._axis_samples(3.0, 300001)
    stress = hertz._axis_stress(parts, nu)[2]
    k = int(np.argmax(stress))
    return yield_stress / float(stress[k]), float(zeta[k])


@pytest.mark.parametrize("nu", NUS)
def test_first_yield_is_that_of_every_sample(nu):
    for yield_stress in (1.0, 300e6, 1.7e9):
        assert hertz.first_yield_pressure(yield_stress, nu) == _first_yield_from_every_sample(
            yield_stress, nu
        )


@pytest.mark.parametrize("nu", NUS)
def test_yield_region_is_that_of_every_sample(nu):
    rng = np.random.default_rng(int(1000 * (nu + 1)))
    first = hertz.first_yield_pressure(1.0, nu)[0]  # p_0 at first yield over sigma_Y0
    # from below first yield (nothing) through just past it (a thin region) to far past it
    # (from the surface down), and random loads in between
    factors = [0.5, 0.999999, 1.0, 1.000001, 1.0001, 1.01, 1.1, 1.5, 2.0, 3.0, 5.0, 10.0, 50.0]
    factors += list(np.exp(rng.uniform(0.0, np.log(20.0), 25)))
    for factor in factors:
        p0 = factor * first
        assert hertz.hertz_yield_region(p0, 1.0, nu) == _region_from_every_sample(p0, 1.0, nu)


def _half_width_from_every_sample(ratio, nu, traction, depth, reach):
    import math

    from solver.numerics.tensor import von_mises
    from solver.theory.half_space import stress_from_potential

    rows = len(np.arange(hertz._YIELD_STEP / 2, depth + hertz._YIELD_STEP / 2, hertz._YIELD_STEP))
    extent = 0.0
    for plane in range(2):
        across, down, w = hertz._unit_potential(reach, rows, plane)
        stress = stress_from_potential(w, down, nu, "pressure")
        if traction != 0.0:
            stress = stress + traction * stress_from_potential(w, down, nu, "shear_x")
        yielded = von_mises(math.pi * stress) >= ratio
        if yielded.any():
            extent = max(extent, float(np.abs(across[yielded]).max()))
    return min(extent, reach)


@pytest.mark.parametrize("nu", (0.0, 0.3, 0.45))
@pytest.mark.parametrize("traction", (0.0, 0.1, 0.3, 0.6))
def test_yield_half_width_is_that_of_every_sample(nu, traction):
    """Columns evaluated from the sides inwards give the whole planes' outermost yield."""
    rng = np.random.default_rng(int(100 * nu + 10 * traction))
    # sigma_Y0 / p_0 from nothing yielding to a zone past the sampled edge
    for ratio in (2.0, 0.7, 0.62, 0.5, 0.3, 0.2, 0.1, 0.02, *rng.uniform(0.05, 0.7, 4)):
        for depth, reach in ((1.5, 3.0), (3.0, 1.55), (0.7, 2.2)):
            args = (round(float(ratio), 12), nu, traction, depth, reach)
            assert hertz._yield_half_width.__wrapped__(*args) == _half_width_from_every_sample(
                *args
            ), args
