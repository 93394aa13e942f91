"""Rough surfaces in motion (issue 61): slides in periodic mode, body 1's heights shifted.

In periodic mode a rigid rough body 1 that slides is an exact periodic shift of its heights:
its gap at position X is its heights at x - X, wrapping around the period.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from test_periodic import PERIOD, ROUGH, sinusoid_map, westergaard

import solver
from solver.bodies.heights import HeightMap, isotropic_spectrum
from solver.bodies.materials import Body, Pair
from solver.result import cycle_summary

MU = 0.3


def _sliding_sinusoid(n: int, travel: float, steps: int = 4, ratio: float = 0.3) -> tuple:
    """Westergaard's sinusoid (rigid body 1) slid by ``travel`` over incompressible steel
    (beta = 0) at p = ratio p*, mu = 0.3: the result and the closed form at its end."""
    pair = Pair(Body("rigid"), Body("elastic", E=210e9, nu=0.5))
    full = math.pi * pair.composite_modulus * 1e-6 / PERIOD
    mean = ratio * full
    dx = PERIOD / n
    table = {
        "body1": {"behaviour": "rigid", "radius": "inf", "surface": sinusoid_map(n)},
        "body2": {"behaviour": "elastic", "E": 210e9, "nu": 0.5},
        "friction": {"coefficient": MU},
        "load": {"path": [{"normal_force": mean * PERIOD * 4 * dx},
                          {"slide": [travel, 0.0], "steps": steps}]},
        "grid": {"n": [n, 4], "size": [PERIOD, 4 * dx], "periodic": True},
    }  # fmt: skip
    result = solver.solve(solver.Case.from_dict(table))
    assert result.status == "converged", result.notes
    x, _ = result.case.surface_grid.mesh()
    end = result.history["position_x"][-1]
    relative = (x - end + PERIOD / 2) % PERIOD - PERIOD / 2  # from the moved crest
    return result, westergaard(relative, mean, full)[0]


def test_a_sliding_sinusoid_is_westergaards_with_the_shear_of_gross_slip():
    """beta = 0: the slid sinusoid's pressure is Westergaard's about the moved crest (its mean
    error of p_max falling with the cells: 64, 128, 256 a period, a third of a period slid, a
    position between cells), the shear mu p along the motion everywhere, Q = mu W."""
    errors = []
    for n in (64, 128, 256):
        result, expected = _sliding_sinusoid(n, PERIOD / 3)
        errors.append(np.abs(result.pressure - expected).mean() / expected.max())
        touching = result.pressure > 0
        np.testing.assert_allclose(result.shear_x[touching], MU * result.pressure[touching])
        assert not result.shear_y.any()
        force = result.history["tangential_force_x"][-1]
        assert force == pytest.approx(MU * result.history["normal_force"][-1], rel=1e-9)
        assert not result.notes
    assert errors[0] < 2e-3 and errors[2] < 0.5 * errors[1] < 0.5 * errors[0], errors


def test_a_slide_wraps_around_the_period():
    """A slide of one period and a third ends where a third does (the heights come round
    again), and the case says it wraps; a slide shorter than a cell is told."""
    third, _ = _sliding_sinusoid(64, PERIOD / 3, steps=2)
    further, _ = _sliding_sinusoid(64, 4 * PERIOD / 3, steps=8)
    np.testing.assert_allclose(further.pressure, third.pressure, atol=1e-9 * third.pressure.max())
    assert any("wraps around the period" in note for note in further.case.warnings)
    small, expected = _sliding_sinusoid(64, 0.2 * PERIOD / 64, steps=1)
    assert any("shorter than a cell" in note for note in small.case.warnings)
    assert np.abs(small.pressure - expected).mean() < 2e-3 * expected.max()


def test_a_rough_surface_slid_twice_over_elastic_plastic_steel_runs_in():
    """A rigid rough surface slid twice over its period across perfectly plastic steel (shear
    capped at k, the hard case): both passes converge, each pass gains less plastic strain
    than the one before, the friction force is mu W or the capped force below it; per pass
    the mean real area and spots, the rms of body 2's run-in surface (its dent) and its
    spectrum."""
    table = {
        "body1": {"behaviour": "rigid", "radius": "inf", "roughness": ROUGH},
        "body2": {"behaviour": "elastic-plastic", "E": 210e9, "nu": 0.3,
                  "hardening": {"law": "perfect", "yield_stress": 1e9}},
        "friction": {"coefficient": MU, "shear_limit": "yield"},
        "load": {"path": [{"normal_force": 40.0, "steps": 2},
                          {"cycles": 2, "stages": [{"slide": [PERIOD, 0.0], "steps": 8}]}]},
        "grid": {"n": [64, 64, 12], "size": [PERIOD, PERIOD], "periodic": True},
    }  # fmt: skip
    result = solver.solve(solver.Case.from_dict(table))
    assert result.status == "converged", result.notes
    assert any("an increment slides 8 cells" in note for note in result.notes)  # told
    history = result.history
    cycles = result.case.step_cycles()
    gained = [history["cycle_plastic_strain"][cycles == c][-1] for c in (1, 2)]
    assert gained[0] > 1e-3 and gained[1] < 0.5 * gained[0], gained
    force = history["tangential_force_x"][cycles > 0]
    assert np.all(force <= MU * 40.0 * (1 + 1e-9)) and np.all(force > 0.8 * MU * 40.0)
    # per pass: the real area and the spots averaged over it, body 2's run-in topography
    per_pass = cycle_summary(history)
    for name in ("contact_area", "contact_spots"):
        expected = [history[name][cycles == c].mean() for c in (1, 2)]
        np.testing.assert_allclose(per_pass[f"mean_{name}"], expected)
    dent = result.fields["residual_displacement_z"]
    rms = np.sqrt(np.mean((dent - dent.mean()) ** 2))  # body 2 is flat: its dent alone
    assert per_pass["residual_topography_rms"][-1] == pytest.approx(rms, rel=1e-12)
    assert 0 < per_pass["residual_topography_rms"][0] <= per_pass["residual_topography_rms"][1]
    # and its spectrum, pass by pass: the last pass's is the run-in surface's
    spectra = result.fields["cycle_topography_spectrum"]
    assert spectra.shape == (2, 32)
    np.testing.assert_allclose(spectra[-1], isotropic_spectrum(dent, (PERIOD, PERIOD)), rtol=1e-5)
    q = result.to_xarray()["wavenumber"].values
    for pass_rms, spectrum in zip(per_pass["residual_topography_rms"], spectra, strict=True):
        # the mean square, less the wavevectors past the Nyquist ring (the corners)
        assert np.sum(q * spectrum) * q[0] / (2 * np.pi) == pytest.approx(pass_rms**2, rel=0.06)


def _sparse_pair(cells: int, period_radii: float, layers: int, mu: float = 0.3) -> tuple:
    """The sparse asperity slid open and in periodic mode (the bench's two cases,
    :func:`study.bench.sliding_periodic.sparse_pair_tables`): their e_p,max and deepest dents."""
    from study.bench.sliding_periodic import sparse_pair_tables

    out = []
    for table in sparse_pair_tables(cells, period_radii, layers, mu):
        result = solver.solve(solver.Case.from_dict(table))
        assert result.status == "converged", result.notes
        fields = result.fields
        out.append((fields["plastic_strain"].max(), fields["residual_displacement_z"].max()))
    return out


def test_a_sparse_asperity_slid_periodically_is_the_isolated_sphere():
    """One spherical asperity on a period of 24 contact radii, slid 4 a over hardening steel
    (p0 about 1.3 first yield, mu = 0.3, 6 cells a radius): e_p,max and the deepest residual
    dent within 2 % of the open (non-periodic) sliding of the same sphere on the same cells."""
    (strain, dent), (strain_p, dent_p) = _sparse_pair(6, 24.0, 15)
    assert strain > 1e-3 and dent > 0
    assert strain_p == pytest.approx(strain, rel=0.02)
    assert dent_p == pytest.approx(dent, rel=0.02)


@pytest.mark.slow
def test_the_periodic_asperity_tends_to_the_isolated_one_as_the_period_grows():
    """Periods of 12, 16 and 24 contact radii (frictionless): the periodic images and the
    mean pressure W / L^2 part the two solutions; the gap falls with the period (measured
    2026-12-06: e_p,max +2.0, +1.1, +0.4 %, dent +4.5, +2.5, +1.0 %)."""
    gaps = []
    for period in (12.0, 16.0, 24.0):
        (strain, dent), (strain_p, dent_p) = _sparse_pair(6, period, 12, mu=0.0)
        gaps.append((abs(strain_p / strain - 1), abs(dent_p / dent - 1)))
    for which in (0, 1):
        values = [g[which] for g in gaps]
        assert values == sorted(values, reverse=True) and values[-1] < 0.02, gaps


def test_coupled_sliding_in_periodic_mode_is_the_open_sliding_of_a_sparse_asperity():
    """beta != 0 (a rigid sphere on steel, beta = 0.29), mu = 0.3: sliding couples the
    shear into the pressure, which leans against the motion (its centroid 0.04 a behind the
    apex).  The sphere as a cap on a period of 16 contact radii, slid 2 a: the pressure on
    the open sliding's cells within 1.5 % of its peak, the centroid's lean within 2 % of the
    open one's (an independent discretisation: DC-FFT on a window against the periodic
    Fourier kernels); without friction no lean."""
    from solver.bodies.heights import HeightMap

    elastic = {"behaviour": "elastic", "E": 210e9, "nu": 0.3}
    rigid = {"behaviour": "rigid", "radius": 0.01}
    pressed = {"body1": rigid, "body2": elastic, "load": {"normal_force": 100.0}, "grid": {"n": 16}}
    a = solver.Case.from_dict(pressed).reference.radius
    dx, leans = a / 6, {}
    for mu in (0.0, MU):
        open_table = {
            "body1": rigid, "body2": elastic, "friction": {"coefficient": mu},
            "load": {"path": [{"normal_force": 100.0, "steps": 4},
                              {"slide": [2 * a, 0.0], "steps": 8}]},
            "grid": {"n": [30, 18]},
        }  # fmt: skip
        open_result = solver.solve(solver.Case.from_dict(open_table))
        n = 96
        x = (np.arange(n) + 0.5 - n / 2) * dx
        xx, yy = np.meshgrid(x, x)
        cap = np.minimum(xx**2 + yy**2, (2.5 * a) ** 2) / (2 * 0.01)
        periodic = {
            **open_table,
            "body1": {"behaviour": "rigid", "radius": "inf", "surface": HeightMap(x, x, cap, "c")},
            "grid": {"n": [n, n], "size": [n * dx, n * dx], "periodic": True},
        }
        result = solver.solve(solver.Case.from_dict(periodic))
        assert open_result.status == result.status == "converged"
        grid, cells = open_result.case.surface_grid, result.case.surface_grid
        assert grid.dx == pytest.approx(dx, rel=1e-12)
        rows = np.rint((grid.x - cells.x[0]) / dx).astype(int)
        columns = np.rint((grid.y - cells.y[0]) / dx).astype(int)
        moved = result.pressure[np.ix_(rows, columns)]  # on the open case's cells
        peak = open_result.pressure.max()
        assert np.abs(moved - open_result.pressure).max() < 0.015 * peak
        end = open_result.history["position_x"][-1]
        leans[mu] = [
            float((p.sum(axis=1) * grid.x).sum() / p.sum() - end) / a
            for p in (open_result.pressure, moved)
        ]
    assert abs(leans[0.0][0]) < 1e-9 and abs(leans[0.0][1]) < 1e-9
    assert leans[MU][0] < -0.03 and leans[MU][1] == pytest.approx(leans[MU][0], rel=0.02)


def test_the_running_in_campaign_reports_per_pass(tmp_path):
    """campaigns/running_in.toml cut to one case of two passes (8 increments each): it runs,
    assembles the per-pass running-in quantities, and its report draws them per cycle with
    the regime table and the run-in surface's spectrum per pass, but no Hertz shakedown map
    (a rough interface has no p0/k)."""
    from pathlib import Path

    import xarray as xr

    from study.campaign import load_campaign
    from study.report import build_report
    from study.run import storage
    from study.run.assemble import assemble_to_file
    from study.run.driver import RunOptions, run_campaign

    text = (Path(__file__).parent.parent / "campaigns" / "running_in.toml").read_text()
    for old, new in (('"body1.roughness.rms" = [2.5e-7, 5e-7]', '"body1.roughness.rms" = [5e-7]'),
                     ('"friction.coefficient" = [0.2, 0.5]', '"friction.coefficient" = [0.2]'),
                     ("cycles = 16", "cycles = 2"), ("steps = 64 }", "steps = 8 }")):  # fmt: skip
        assert old in text
        text = text.replace(old, new)
    (tmp_path / "running_in.toml").write_text(text)
    campaign = load_campaign(tmp_path / "running_in.toml")
    assert len(campaign.cases) == 1
    out = tmp_path / "out"
    assert run_campaign(campaign, out, options=RunOptions()).exit_status == 0
    assemble_to_file(out)
    with xr.open_dataset(storage.dataset_path(out, "running_in")) as data:
        rms = data["residual_topography_rms"].values.ravel()
        area = data["mean_contact_area"].values.ravel()
        gained = data["plastic_strain_increment"].values.ravel()
    assert rms.size == area.size == gained.size == 2 and np.all(rms > 0) and np.all(area > 0)
    assert gained[1] < gained[0]
    report = build_report(out).read_text()
    assert "running_in_cycles.png" in report and "## Shakedown" in report
    assert "running_in_topography_spectra.png" in report  # the print's spectrum per pass
    assert not (out / "running_in_shakedown_map.png").exists()


def test_a_fretting_stroke_in_periodic_mode_reverses_the_shear_with_the_motion():
    """Strokes of a third of a period back and forth (two cycles of +S, -S, then +S) of the
    sinusoid over incompressible steel (beta = 0) in gross slip: every step's friction force
    is mu W along the motion of its stroke; at the end of the back stroke and of the out
    stroke the pressure is Westergaard's about the crest where it stopped, the shear mu p along
    that stroke's motion."""
    n = 128
    pair = Pair(Body("rigid"), Body("elastic", E=210e9, nu=0.5))
    full = math.pi * pair.composite_modulus * 1e-6 / PERIOD
    mean, dx, stroke = 0.3 * full, PERIOD / n, PERIOD / 3
    for extra, sign in (([], -1), ([{"slide": [stroke, 0.0], "steps": 4}], 1)):
        strokes = [{"slide": [stroke, 0.0], "steps": 4}, {"slide": [-stroke, 0.0], "steps": 4}]
        table = {
            "body1": {"behaviour": "rigid", "radius": "inf", "surface": sinusoid_map(n)},
            "body2": {"behaviour": "elastic", "E": 210e9, "nu": 0.5},
            "friction": {"coefficient": MU},
            "load": {"path": [{"normal_force": mean * PERIOD * 4 * dx},
                              {"cycles": 2, "stages": strokes}, *extra]},
            "grid": {"n": [n, 4], "size": [PERIOD, 4 * dx], "periodic": True},
        }  # fmt: skip
        result = solver.solve(solver.Case.from_dict(table))
        assert result.status == "converged", result.notes
        h = result.history
        motion = np.sign(np.diff(h["position_x"]))
        assert list(motion) == [1] * 4 + [-1] * 4 + [1] * 4 + [-1] * 4 + [1] * len(extra) * 4
        force = h["tangential_force_x"][1:]
        np.testing.assert_allclose(force, motion * MU * h["normal_force"][1:], rtol=1e-9)
        x, _ = result.case.surface_grid.mesh()
        relative = (x - h["position_x"][-1] + PERIOD / 2) % PERIOD - PERIOD / 2
        expected = westergaard(relative, mean, full)[0]
        assert np.abs(result.pressure - expected).mean() < 2e-3 * expected.max()
        touching = result.pressure > 0
        np.testing.assert_allclose(
            result.shear_x[touching], sign * MU * result.pressure[touching], rtol=1e-9
        )
    assert h["position_x"][-1] == pytest.approx(h["position_x"][0] + stroke)


@pytest.mark.parametrize("back", [0.0, -1.0])
def test_a_tangential_force_cycle_in_periodic_mode_is_mindlin_deresiewicz(back):
    """Two steels (beta = 0), Westergaard's strip at p = 0.3 p*, Q to Q* = mu W / 2, then back
    to ``back`` Q*: on the way back the shear is the loading's Ciavarella-Jaeger field less
    twice the one of the change, q = mu (p - p_c(Q*)) - 2 mu (p - p_c((Q* - Q) / 2)), p_c(Q)
    Westergaard's pressure at the mean pressure p (1 - Q / (mu W)); at Q = -Q* the loading's
    shear reversed.  Within 1 % (L2) at 128 cells a period."""
    from test_periodic import periodic_case

    n = 128
    steel = {"behaviour": "elastic", "E": 210e9, "nu": 0.3}
    full = math.pi * Pair(Body(**steel), Body(**steel)).composite_modulus * 1e-6 / PERIOD
    dx, mean = PERIOD / n, 0.3 * full
    force = mean * PERIOD * 4 * dx
    peak = 0.5 * MU * force
    table = periodic_case(
        {**steel, "surface": sinusoid_map(n)}, (n, 4), (PERIOD, 4 * dx),
        body1={**steel, "radius": "inf"}, friction={"coefficient": MU},
    )  # fmt: skip
    table["load"] = {
        "path": [
            {"normal_force": force, "steps": 1},
            {"tangential_force": [peak, 0.0], "steps": 10},
            {"tangential_force": [back * peak, 0.0], "steps": 20},
        ]
    }
    result = solver.solve(solver.Case.from_dict(table))
    assert result.status == "converged", result.notes
    x = result.case.surface_grid.mesh()[0]

    def p_c(q: float) -> np.ndarray:
        return westergaard(x, mean * (1 - q / (MU * force)), full)[0]

    pressure = westergaard(x, mean, full)[0]
    change = peak * (1 - back)
    expected = MU * (pressure - p_c(peak)) - 2 * MU * (pressure - p_c(change / 2))
    if back == -1.0:
        np.testing.assert_allclose(expected, -MU * (pressure - p_c(peak)), atol=1e-9 * full)
    error = np.linalg.norm(result.shear_x - expected) / np.linalg.norm(MU * pressure)
    assert error < 0.01, error


def _wavy_passes(n: int, p0k: float, passes: int = 4) -> list[float]:
    """A rigid sinusoid (one crest a period, uniform along y) slid over elastic-perfectly
    plastic steel (sigma_Y = 1 GPa) at mu = 0.2, ``passes`` passes of one period in
    increments of a cell: Westergaard's peak pressure p_0 = 2 sqrt(p p*) = ``p0k`` k at the
    mean pressure p = 0.15 p* (a contact band 0.25 of the period wide); n x n cells a period,
    0.45 of it deep in layers half a cell thick.  The plastic strain gained in each pass."""
    sigma_y, mu, ratio, depth = 1e9, 0.2, 0.15, 0.45
    pair = Pair(Body("rigid"), Body("elastic", E=210e9, nu=0.3))
    full = p0k * sigma_y / math.sqrt(3) / (2 * math.sqrt(ratio))  # p*
    amplitude = full * PERIOD / (math.pi * pair.composite_modulus)
    x = (np.arange(n) + 0.5) * PERIOD / n - PERIOD / 2
    heights = amplitude * (1 - np.cos(2 * np.pi * x / PERIOD))[None, :] * np.ones((n, 1))
    table = {
        "body1": {"behaviour": "rigid", "radius": "inf",
                  "surface": HeightMap(x, x, heights, "sinusoid")},
        "body2": {"behaviour": "elastic-plastic", "E": 210e9, "nu": 0.3,
                  "hardening": {"law": "perfect", "yield_stress": sigma_y}},
        "friction": {"coefficient": mu},
        "load": {"path": [{"normal_force": ratio * full * PERIOD**2, "steps": 2},
                          {"cycles": passes, "stages": [{"slide": [PERIOD, 0.0], "steps": n}]}]},
        "grid": {"n": [n, n, round(2 * depth * n)], "size": [PERIOD, PERIOD], "periodic": True,
                 "depth": depth * PERIOD},
    }  # fmt: skip
    result = solver.solve(solver.Case.from_dict(table))
    assert result.status == "converged", result.notes
    return list(cycle_summary(result.history)["plastic_strain_increment"])


def _runs_in(gained: list[float]) -> bool:
    """Each pass gains less than the one before, the last under a fifth of the first."""
    return bool(np.all(np.diff(gained) < 0)) and gained[-1] < 0.2 * gained[0]


def _keeps_flowing(gained: list[float]) -> bool:
    """The last pass gains as much as the one before (within 10 %), over half the first."""
    return gained[-1] > 0.9 * gained[-2] and gained[-1] > 0.5 * gained[0]


def _running_in_contrast(n: int) -> tuple[list[float], list[float]]:
    below, above = _wavy_passes(n, 3.2), _wavy_passes(n, 3.8)
    assert below[0] > 0  # both loads yield the first pass
    assert _runs_in(below) and not _keeps_flowing(below), below
    assert _keeps_flowing(above) and not _runs_in(above), above
    assert above[-1] > 10 * below[-1]
    return below, above


def test_running_in_stops_below_the_shakedown_load_and_not_above():
    """The sliding sinusoid four times over its period: at p_0 = 3.2 k the strain gained per
    pass falls pass by pass (elastic shakedown), at 3.8 k it settles at a constant gain (no
    shakedown: the strain grows by as much every pass); 32 cells a period."""
    _running_in_contrast(32)


@pytest.mark.slow
def test_running_in_below_and_above_shakedown_holds_on_a_finer_mesh():
    """The same two loads on 48 cells a period: the same verdicts.  (On 64 the pass at 3.8 k
    stalls in its first increment: not converged, its strain at 0.05 past the small-strain
    range.)"""
    _running_in_contrast(48)


def test_a_slid_map_that_is_not_periodic_is_refused_naming_body1():
    """Body 1's map slid in periodic mode must be one period: a ramp across it (its opposite
    edges apart) is refused by name before anything is solved."""
    n, dx = 64, PERIOD / 64
    whole = sinusoid_map(n)
    ramp = HeightMap(whole.x, whole.y, whole.height + 1e-7 * np.arange(n)[None, :], "ramp")
    table = {
        "body1": {"behaviour": "rigid", "radius": "inf", "surface": ramp},
        "body2": {"behaviour": "elastic", "E": 210e9, "nu": 0.3},
        "friction": {"coefficient": MU},
        "load": {"path": [{"normal_force": 1.0}, {"slide": [PERIOD / 3, 0.0], "steps": 4}]},
        "grid": {"n": [n, 4], "size": [PERIOD, 4 * dx], "periodic": True},
    }  # fmt: skip
    with pytest.raises(solver.SpecError, match=r"^body1\.surface: .*not periodic along x"):
        solver.Case.from_dict(table)
