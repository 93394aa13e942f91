"""Analysis and report of campaign datasets (study.analysis, study.report)."""

import json

import numpy as np
import pytest
import xarray as xr

from study import analysis, report
from study.assemble import assemble_to_file
from study.campaign import expand_campaign
from study.driver import run_campaign

H = np.array([0.2, 0.1, 0.05, 0.025, 0.0125])


# -- synthetic data ------------------------------------------------------------------------------
def test_observed_order_of_a_power_law():
    order, constant = analysis.observed_order(H, 3.0 * H**2)
    assert order == pytest.approx(2.0, abs=0.05)
    assert constant == pytest.approx(3.0, rel=1e-6)
    assert np.isnan(analysis.observed_order([0.1], [1.0])[0])


@pytest.mark.parametrize("order", [1.0, 2.0, 3.5])
def test_fit_and_richardson_recover_order_and_limit(order):
    limit = 6e9
    values = limit - 4e9 * H**order
    fit = analysis.fit_convergence(H, values)
    assert fit.order == pytest.approx(order, abs=0.05)
    assert fit.limit == pytest.approx(limit, rel=1e-8)
    assert not fit.at_bound
    assert analysis.richardson(H, values, fit.order) == pytest.approx(limit, rel=1e-8)
    # uneven refinement ratios and unsorted input
    uneven = np.array([0.3, 0.01, 0.17, 0.04])
    assert analysis.richardson(uneven, limit - 2e9 * uneven**order, order) == pytest.approx(limit)


def test_fit_needs_three_meshes():
    assert np.isnan(analysis.fit_convergence([0.1, 0.05], [1.0, 1.1]).order)


def test_pareto_front():
    cost = [1.0, 2.0, 3.0, 4.0, np.nan]
    error = [0.5, 0.6, 0.1, 0.05, 0.0]
    assert analysis.pareto_front(cost, error).tolist() == [True, False, True, True, False]


def synthetic_dataset(order=2.0):
    """A campaign-like dataset over (grid_n, friction_coefficient) with known behaviour."""
    n = np.array([16, 32, 64, 128])
    mu = np.array([0.1, 0.2, 0.4])
    h = 2 * 1.5 / n
    p0, a, delta = 2e9, 1e-4, 3e-6
    shape = (len(n), len(mu))
    hh = np.broadcast_to(h[:, None], shape)
    mm = np.broadcast_to(mu[None, :], shape)

    def var(values, units):
        return (("grid_n", "friction_coefficient"), np.array(values, dtype=float), {"units": units})

    base = {"friction": {"coefficient": 0.2}, "grid": {"n": 16, "half_width": 1.5}}
    return xr.Dataset(
        {
            "status": (("grid_n", "friction_coefficient"), np.ones(shape, dtype=np.int8)),
            "case_id": (("grid_n", "friction_coefficient"), np.full(shape, "x")),
            "max_pressure": var(p0 * (1 - 0.5 * hh**order) * (1 + mm), "Pa"),
            "contact_radius": var(a * (1 + 0.3 * hh**order), "m"),
            "approach": var(delta * (1 + 0.1 * hh**order), "m"),
            "stick_radius": var(np.zeros(shape), "m"),
            "hertz_pressure": var(np.full(shape, p0), "Pa"),
            "hertz_radius": var(np.full(shape, a), "m"),
            "hertz_approach": var(np.full(shape, delta), "m"),
            "normal_force": var(np.full(shape, 10.0), "N"),
            "dundurs_beta": var(np.full(shape, 0.1), "1"),
            "wall_time": var(hh**-2 * 1e-3, "s"),
            "peak_rss": var(np.full(shape, 2**27), "byte"),
        },
        coords={
            "grid_n": ("grid_n", n, {"campaign_key": "grid.n"}),
            "friction_coefficient": (
                "friction_coefficient",
                mu,
                {"campaign_key": "friction.coefficient"},
            ),
        },
        attrs={"campaign": "synthetic", "campaign_base": json.dumps(base)},
    )


def test_tables_on_synthetic_dataset():
    dataset = synthetic_dataset()
    assert analysis.mesh_axes(dataset) == ["grid_n"]
    assert analysis.sensitivity_axes(dataset) == ["friction_coefficient"]
    assert analysis.quantities(dataset) == ["max_pressure", "contact_radius", "approach"]
    # beta != 0 with friction: Hertz does not apply
    assert analysis.closed_forms(dataset) == {}
    summary = analysis.convergence_summary(dataset, "contact_radius")
    assert len(summary) == 3
    assert np.allclose(summary["order_fit"], 2.0, atol=0.05)
    assert np.allclose(summary["extrapolated"], 1e-4, rtol=1e-9)
    table = analysis.convergence_table(dataset, "max_pressure", "grid_n")
    assert len(table) == 12
    finest = table[table["n"] == 128]
    assert np.allclose(finest["diff_finest"], 0.0)
    sens = analysis.sensitivity_table(dataset, "max_pressure", "friction_coefficient")
    # q = p_inf (1 + mu) on the finest mesh: dq/dmu = p(h_finest) / (1 + mu), exact (linear)
    expected = 2e9 * (1 - 0.5 * (3.0 / 128) ** 2)
    assert np.allclose(sens["derivative"], expected, rtol=1e-9)
    speed = analysis.speed_error_table(dataset)
    assert len(speed) == 12 and speed["error_basis"].str.contains("extrapolated").all()
    assert speed["pareto"].any()


def test_closed_forms_when_beta_is_zero():
    dataset = synthetic_dataset()
    dataset["dundurs_beta"][:] = 0.0
    refs = analysis.closed_forms(dataset)
    assert {"max_pressure", "contact_radius", "approach"} <= set(refs)
    # no tangential load with friction: full stick, c / a = 1
    assert np.allclose(refs["stick_ratio"], 1.0)
    summary = analysis.convergence_summary(dataset, "approach")
    assert np.allclose(summary["order_reference"], 2.0, atol=0.05)
    assert np.allclose(summary["rel_error_extrapolated"], 0.0, atol=1e-9)


# -- a small real campaign -----------------------------------------------------------------------
CATTANEO = {
    "campaign": {"name": "tiny_cattaneo"},
    "base": {
        "body1": {"behaviour": "elastic", "radius": 0.01, "E": 210e9, "nu": 0.3},
        "body2": {"behaviour": "elastic", "radius": 0.01, "E": 210e9, "nu": 0.3},
        "friction": {"coefficient": 0.3},
        "grid": {"n": 16, "half_width": 1.5},
        "load": {"path": [{"normal_force": 100.0}, {"tangential_force": 10.0}]},
    },
    "sweep": {"grid.n": [16, 20, 28], "load.path.1.tangential_force": [10.0, 20.0]},
    "alias": {"load.path.1.tangential_force": "tangential_force"},
}


@pytest.fixture(scope="module")
def campaign_out(tmp_path_factory):
    out = tmp_path_factory.mktemp("analysis") / "out"
    campaign = expand_campaign(CATTANEO, name="tiny_cattaneo")
    assert run_campaign(campaign, out).exit_status == 0
    assemble_to_file(out, campaign)
    return out


def test_real_campaign_tables(campaign_out):
    dataset = xr.open_dataset(campaign_out / "tiny_cattaneo.nc")
    assert analysis.scene(dataset) == "Hertz, Cattaneo"
    refs = analysis.closed_forms(dataset)
    assert {"max_pressure", "contact_radius", "approach", "stick_ratio"} <= set(refs)
    ratio = refs["stick_ratio"].isel(grid_n=0).values
    assert ratio == pytest.approx([(1 - 10 / 30) ** (1 / 3), (1 - 20 / 30) ** (1 / 3)])
    summary = analysis.convergence_summary(dataset, "max_pressure")
    assert len(summary) == 2
    assert (abs(summary["rel_error_finest"]) < 0.02).all()
    stick = analysis.convergence_summary(analysis.with_derived(dataset), "stick_ratio")
    assert (abs(stick["rel_error_finest"]) < 0.1).all()
    speed = analysis.speed_error_table(dataset)
    assert len(speed) == 6 and (speed["error"] < 0.2).all()


def test_report_without_plots(campaign_out):
    assert report.main([str(campaign_out), "--no-plots"]) == 0
    text = (campaign_out / "report.md").read_text()
    assert "# Campaign report: tiny_cattaneo" in text
    assert "Mesh convergence along `grid_n`" in text
    assert "Speed versus error" in text and "campaign.json sha256" in text


def _png_size(path):
    """(width, height) in pixels from the PNG's IHDR chunk."""
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and data[12:16] == b"IHDR"
    return int.from_bytes(data[16:20], "big"), int.from_bytes(data[20:24], "big")


def test_report_plots(campaign_out):
    pytest.importorskip("matplotlib")
    import matplotlib.image

    assert report.main([str(campaign_out)]) == 0
    dataset = xr.open_dataset(campaign_out / "tiny_cattaneo.nc")
    # panels: one per quantity (convergence), one per tangential force (profiles and the
    # stick/slip maps of the finest mesh, 4 columns at most); pixels = figsize (in) x 110 dpi
    quantities = len(analysis.quantities(analysis.with_derived(dataset)))
    forces = dataset.sizes["tangential_force"]
    expected = {
        "convergence_grid_n": (4.2 * quantities, 4.0),
        "speed_error": (10, 4.2),
        "profiles": (4.0 * forces, 6.5),
        "stick_slip": (3.6 * min(4, forces), 3.4 * -(-forces // 4)),
    }
    assert quantities >= 3 and forces == 2
    for suffix, (width, height) in expected.items():
        png = campaign_out / f"tiny_cattaneo_{suffix}.png"
        assert _png_size(png) == (round(width * 110), round(height * 110)), suffix
        pixels = matplotlib.image.imread(png)[..., :3]
        assert pixels.std() > 0.05, suffix  # something is drawn, not a blank canvas
        assert f"({png.name})" in (campaign_out / "report.md").read_text()


def test_report_subcommand_parser():
    import argparse

    parser = argparse.ArgumentParser()
    report.add_parser(parser.add_subparsers(dest="command"))
    args = parser.parse_args(["report", "OUT", "--no-plots"])
    assert args.command == "report" and args.out == "OUT" and args.no_plots
