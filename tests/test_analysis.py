"""Analysis and report of campaign datasets (study.analysis, study.report)."""

import json
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from study import analysis, report
from study.campaign import expand_campaign
from study.report import figures as report_figures
from study.run.assemble import _grid_cells, assemble_to_file
from study.run.driver import run_campaign

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
    # the error bar is the finest mesh's true error for an exact power law
    assert np.allclose(summary["error_bar"], 1e-4 * 0.3 * (3.0 / 128) ** 2, rtol=1e-6)
    table = analysis.convergence_table(dataset, "max_pressure", "grid_n")
    assert len(table) == 12
    finest = table[table["n"] == 128]
    assert np.allclose(finest["diff_finest"], 0.0)
    sens = analysis.sensitivity_table(dataset, "max_pressure", "friction_coefficient")
    # q = p_inf (1 + mu) on the finest mesh: dq/dmu = p(h_finest) / (1 + mu), exact (linear)
    expected = 2e9 * (1 - 0.5 * (3.0 / 128) ** 2)
    assert np.allclose(sens["derivative"], expected, rtol=1e-9)
    # contact_radius does not depend on mu here: its derivative is zero, not round-off
    flat = analysis.sensitivity_table(dataset, "contact_radius", "friction_coefficient")
    assert (flat["derivative"] == 0.0).all() and (flat["elasticity"] == 0.0).all()
    speed = analysis.speed_error_table(dataset)
    assert len(speed) == 12 and speed["error_basis"].str.contains("extrapolated").all()
    assert speed["pareto"].any()


def test_load_steps_axis_is_a_refinement_with_h_one_over_steps():
    steps = np.array([5, 10, 20, 40])
    h = 1.0 / steps
    e_star = 0.0123  # a plastic strain converging at first order in the load increment
    dataset = xr.Dataset(
        {
            "status": ("load_steps", np.ones(4, dtype=np.int8)),
            "case_id": ("load_steps", np.full(4, "x")),
            "max_plastic_strain": ("load_steps", e_star * (1 + 0.7 * h), {"units": "1"}),
        },
        coords={"load_steps": ("load_steps", steps, {"campaign_key": "load.steps"})},
        attrs={"campaign": "steps", "campaign_base": "{}"},
    )
    assert analysis.mesh_axes(dataset) == ["load_steps"]
    assert analysis.mesh_meaning(dataset, "load_steps")[0] == "load steps"
    np.testing.assert_allclose(analysis.mesh_sizes(dataset, "load_steps"), h)
    summary = analysis.convergence_summary(dataset, "max_plastic_strain")
    assert float(summary["order_fit"].iloc[0]) == pytest.approx(1.0, abs=0.02)
    assert float(summary["extrapolated"].iloc[0]) == pytest.approx(e_star, rel=1e-9)


def test_speed_error_reference_with_mesh_and_step_axes():
    """One reference per slice: Richardson along the mesh at the most steps, for every case."""
    n = np.array([16, 32, 64, 128])
    steps = np.array([5, 10, 20])
    h = 2 * 1.5 / n
    e_star = 0.007
    values = e_star * (1 + 0.4 * h[:, None] ** 2 + 0.3 / steps[None, :])
    dims = ("grid_n", "load_steps")
    dataset = xr.Dataset(
        {
            "status": (dims, np.ones(values.shape, dtype=np.int8)),
            "case_id": (dims, np.full(values.shape, "x")),
            "max_plastic_strain": (dims, values, {"units": "1"}),
            "wall_time": (dims, np.ones(values.shape)),
            "peak_rss": (dims, np.full(values.shape, 2.0**27)),
        },
        coords={
            "grid_n": ("grid_n", n, {"campaign_key": "grid.n"}),
            "load_steps": ("load_steps", steps, {"campaign_key": "load.steps"}),
        },
        attrs={"campaign": "two", "campaign_base": json.dumps({"grid": {"half_width": 1.5}})},
    )
    assert analysis.mesh_axes(dataset) == ["grid_n", "load_steps"]
    table = analysis.speed_error_table(dataset)
    reference = e_star * (1 + 0.3 / steps[-1])  # the mesh limit at 20 steps
    expected = (values.ravel() - reference) / reference
    np.testing.assert_allclose(table["err_max_plastic_strain"], expected, rtol=1e-6, atol=1e-12)
    best = table.loc[table["error"].idxmin()]
    assert (best["grid_n"], best["load_steps"]) == (128, 20)


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


#: 5 fast normal-contact cases on one 24^2 grid (no mesh axis), mu = 0 ... 0.4, beta = 0:
#: full stick wherever mu > 0.  The quickstart's axis names.
FIVE = {
    "campaign": {"name": "five"},
    "base": {
        "body1": {"behaviour": "elastic", "radius": 0.01, "E": 210e9, "nu": 0.3},
        "body2": {"behaviour": "elastic", "radius": "inf", "E": 210e9, "nu": 0.3},
        "load": {"hertz_pressure": 1e9, "steps": 1},
        "grid": {"n": 24, "half_width": 1.5},
    },
    "sweep": {
        "friction.coefficient": [0.0, 0.1, 0.2, 0.3, 0.4],
        "materials.dundurs_beta": [0.0],  # long panel titles, as in the quickstart
    },
    "alias": {
        "friction.coefficient": "friction_coefficient",
        "materials.dundurs_beta": "dundurs_beta",
    },
}


def _run_assembled(tmp_path_factory, table: dict, name: str):
    out = tmp_path_factory.mktemp(name) / "out"
    campaign = expand_campaign(table, name=name)
    assert run_campaign(campaign, out).exit_status == 0
    assemble_to_file(out, campaign)
    return out


@pytest.fixture(scope="module")
def five_out(tmp_path_factory):
    return _run_assembled(tmp_path_factory, FIVE, "five")


@pytest.fixture(scope="module")
def campaign_out(tmp_path_factory):
    return _run_assembled(tmp_path_factory, CATTANEO, "tiny_cattaneo")


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
    assert "Convergence along `grid_n` (cells per side)" in text
    assert "Speed versus error" in text and "campaign.json sha256" in text


def _png_size(path):
    """(width, height) in pixels from the PNG's IHDR chunk."""
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and data[12:16] == b"IHDR"
    return int.from_bytes(data[16:20], "big"), int.from_bytes(data[20:24], "big")


def _figures(monkeypatch):
    """Capture every matplotlib figure the report saves (still written to its file)."""
    from matplotlib.figure import Figure

    figures = {}
    original = Figure.savefig

    def savefig(self, path, *args, **kwargs):
        done = original(self, path, *args, **kwargs)
        self.problems = _layout_problems(self)  # with the renderer that drew the PNG
        figures[Path(path).name] = self
        return done

    monkeypatch.setattr(Figure, "savefig", savefig)
    return figures


def _panels(figure):
    """The visible data panels of a figure (no colour bar), as (columns, rows) used."""
    axes = [ax for ax in figure.axes if ax.get_visible() and ax.get_label() != "<colorbar>"]
    columns = {round(ax.get_position().x0, 3) for ax in axes}
    rows = {round(ax.get_position().y0, 3) for ax in axes}
    return axes, len(columns), len(rows)


def _layout_problems(figure):
    """What makes a drawn figure hard to read: overlapping or clipped texts, unlabelled axes.

    Texts are the titles, axis labels and drawn tick labels; every data panel needs at least
    two labelled ticks on each axis.
    """
    from matplotlib.legend import Legend

    renderer = figure.canvas.get_renderer()
    boxes = [(t.get_text(), t.get_window_extent(renderer)) for t in _labels(figure)]
    boxes = [(text, box) for text, box in boxes if text]
    legends = list(figure.legends) + [
        child for ax in figure.axes for child in ax.get_children() if isinstance(child, Legend)
    ]
    boxes += [("legend", legend.get_window_extent(renderer)) for legend in legends]
    page = figure.bbox
    problems = [
        ("overlap", a, b)
        for i, (a, box_a) in enumerate(boxes)
        for b, box_b in boxes[i + 1 :]
        if box_a.overlaps(box_b)
    ]
    problems += [
        ("clipped", text)
        for text, box in boxes
        if box.x0 < page.x0 - 1
        or box.x1 > page.x1 + 1
        or box.y0 < page.y0 - 1
        or box.y1 > page.y1 + 1
    ]
    for ax in _panels(figure)[0]:
        for axis in (ax.xaxis, ax.yaxis):
            labelled = [
                t for t in axis._update_ticks() if t.label1.get_visible() and t.label1.get_text()
            ]
            if len(labelled) < 2:
                problems.append(("ticks", ax.get_title(), axis.axis_name, len(labelled)))
    return problems


def _labels(figure):
    """Every title, axis label and visible tick label of a figure's panels."""
    texts = [figure._suptitle] if figure._suptitle else []
    for ax in figure.axes:
        if not ax.get_visible():
            continue
        texts += [ax.title, ax.xaxis.label, ax.yaxis.label]
        for axis in (ax.xaxis, ax.yaxis):  # the ticks drawn (major and minor, in view)
            texts += [tick.label1 for tick in axis._update_ticks() if tick.label1.get_visible()]
    return texts


def test_report_plots(campaign_out, monkeypatch):
    pytest.importorskip("matplotlib")
    import matplotlib.image

    figures = _figures(monkeypatch)
    assert report.main([str(campaign_out)]) == 0
    dataset = xr.open_dataset(campaign_out / "tiny_cattaneo.nc")
    text = (campaign_out / "report.md").read_text()
    # panels: one per quantity (convergence), one per tangential force (profiles and the
    # stick/slip maps of the finest mesh); at most 4 columns; pixels = figsize (in) x 110 dpi
    quantities = len(analysis.quantities(analysis.with_derived(dataset)))
    forces = dataset.sizes["tangential_force"]
    assert quantities >= 3 and forces == 2
    title = report_figures.TITLE_HEIGHT
    columns = min(4, quantities)
    expected = {
        "convergence_grid_n": (4.2 * columns, 3.6 * -(-quantities // 4) + title, quantities),
        "speed_error": (10, 4.2, 2),
        # 5 legend entries (Hertz, Cattaneo-Mindlin, 3 meshes): one row of at most 6
        "profiles": (4.0 * forces, 3.0 + title + report_figures.LEGEND_ROW, forces),
        "stick_slip": (3.0 * forces + 1.0, 3.0 + title, forces),
    }
    for suffix, (width, height, panels) in expected.items():
        png = campaign_out / f"tiny_cattaneo_{suffix}.png"
        assert _png_size(png) == (round(width * 110), round(height * 110)), suffix
        pixels = matplotlib.image.imread(png)[..., :3]
        assert pixels.std() > 0.05, suffix  # something is drawn, not a blank canvas
        assert f"({png.name})" in text
        figure = figures[png.name]
        assert len(_panels(figure)[0]) == panels, suffix
        assert _panels(figure)[1] <= 4, suffix
        assert not figure.problems, suffix
    # which panels are shown is said in the figure and in report.md
    for suffix in ("profiles", "stick_slip"):
        assert (
            "all 2 slices over tangential_force"
            in figures[f"tiny_cattaneo_{suffix}.png"]._suptitle.get_text()
        )
    assert text.count("Shown: all 2 slices over tangential_force") == 2
    assert "Shown: all 6 finished cases." in text
    # every series (a slice, or a mesh) in its own (marker, line style) in each panel; the
    # panels of a converged campaign carry no status mark
    for name in ("tiny_cattaneo_convergence_grid_n.png", "tiny_cattaneo_profiles.png"):
        most = 0
        for ax in figures[name].axes:
            styles = {
                line.get_gid(): (line.get_marker(), line.get_linestyle(), line.get_color())
                for line in ax.get_lines()
                if str(line.get_gid()).startswith("series ")
            }
            assert len(set(styles.values())) == len(styles), (name, styles)
            assert not [t for t in ax.texts if t.get_gid() == "status mark"], name
            most = max(most, len(styles))
        assert most >= 2, name
    # the colour bar of the speed-error figure spans the cells of the cases (16^2 ... 28^2)
    speed = figures["tiny_cattaneo_speed_error.png"]
    (bar,) = [ax for ax in speed.axes if ax.get_label() == "<colorbar>"]
    assert sorted(bar.get_ylim()) == pytest.approx([16**2, 28**2])


def test_figures_wrap_into_four_columns_and_say_what_they_show(five_out, monkeypatch):
    """20-ish panels wrap into at most 4 columns; a panel limit is stated, not silent."""
    pytest.importorskip("matplotlib")
    figures = _figures(monkeypatch)
    assert report.main([str(five_out)]) == 0
    text = (five_out / "report.md").read_text()
    for suffix in ("profiles", "stick_slip"):
        figure = figures[f"five_{suffix}.png"]
        panels, columns, rows = _panels(figure)
        assert (len(panels), columns, rows) == (5, 4, 2), suffix
        assert "all 5 cases" in figure._suptitle.get_text()
        assert not figure.problems, suffix
    assert text.count("Shown: all 5 cases.") == 2
    # one grid for every case: no colour bar of a constant, the grid size in the title
    speed = figures["five_speed_error.png"]
    assert [ax.get_label() for ax in speed.axes].count("<colorbar>") == 0
    assert "every case 576 cells" in speed._suptitle.get_text()
    # the closed forms apply to mu = 0 and to the full stick of beta = 0: all 5 cases drawn
    assert "all 5 finished cases" in speed._suptitle.get_text()

    monkeypatch.setattr(report_figures, "MAX_PANELS", 3)
    figures.clear()
    assert report.main([str(five_out)]) == 0
    text = (five_out / "report.md").read_text()
    for suffix in ("profiles", "stick_slip"):
        figure = figures[f"five_{suffix}.png"]
        assert len(_panels(figure)[0]) == 3
        note = "3 of 5 cases (only the first 3 in axis order: 3 panels at most)"
        assert note in figure._suptitle.get_text(), suffix
        assert f"Shown: {note}." in text


def test_speed_error_cells_from_the_case_spec(campaign_out, five_out):
    dataset = xr.open_dataset(campaign_out / "tiny_cattaneo.nc")
    assert dataset["grid_cells"].sel(grid_n=20).values.tolist() == [400, 400]
    speed = analysis.speed_error_table(dataset)
    assert (speed["cells"] == speed["grid_n"] ** 2).all()
    # no mesh axis: the cells still come from the spec (was -1 in every row)
    five = analysis.speed_error_table(xr.open_dataset(five_out / "five.nc"))
    assert (five["cells"] == 24 * 24).all()
    # datasets assembled before grid_cells existed: from grid.n (swept, or base n / [nx, ny, nz])
    assert analysis.cell_counts(dataset.drop_vars("grid_cells")).sel(grid_n=28).values.tolist() == [
        784,
        784,
    ]
    old = xr.open_dataset(five_out / "five.nc").drop_vars("grid_cells")
    assert (analysis.cell_counts(old) == 576).all()
    old.attrs["campaign_base"] = json.dumps({"grid": {"n": [16, 12, 8]}})
    assert (analysis.cell_counts(old) == 16 * 12 * 8).all()
    old.attrs["campaign_base"] = json.dumps({"grid": {"n": 16, "nz": 8}})
    assert (analysis.cell_counts(old) == 16 * 16 * 8).all()
    # volume grids count their layers
    assert _grid_cells({"grid": {"n": [16, 12, 8], "half_width": 1.5}}) == 16 * 12 * 8
    assert _grid_cells({"grid": {"n": [16, 16], "half_width": 1.5}}) == 256


def test_stick_ratio_never_exceeds_one(five_out):
    """Full stick: the stick zone (counted in cells) is the contact zone, which overshoots a_H."""
    dataset = xr.open_dataset(five_out / "five.nc")
    raw = (dataset.stick_radius / dataset.hertz_radius).sel(friction_coefficient=slice(0.1, None))
    assert (raw > 1.001).all()  # the counted contact radius at 24^2: 1.017 a_H
    ratio = analysis.with_derived(dataset)["stick_ratio"]
    assert np.isnan(ratio.sel(friction_coefficient=0.0))
    np.testing.assert_array_equal(ratio.sel(friction_coefficient=slice(0.1, None)), 1.0)
    speed = analysis.speed_error_table(dataset)
    assert (speed["err_stick_ratio"].dropna() == 0).all()
    # partial slip below 1 is left alone
    synthetic = synthetic_dataset()
    synthetic["stick_radius"][:] = 1e-4 * np.array([0.5, 0.999, 1.0048])
    derived = analysis.with_derived(synthetic)["stick_ratio"]
    np.testing.assert_allclose(derived.isel(grid_n=0), [0.5, 0.999, 1.0])
    assert float(derived.max()) == 1.0
    # an elastic-plastic contact outgrows a_H: its ratio is over its own contact radius
    plastic = synthetic.assign(
        max_plastic_strain=synthetic["stick_radius"] * 0 + 0.01,
        contact_radius=synthetic["hertz_radius"] * 1.08,
    )
    plastic["stick_radius"][:] = 1.03e-4
    derived = analysis.with_derived(plastic)["stick_ratio"]
    np.testing.assert_allclose(derived.where(derived.notnull(), 1.03 / 1.08), 1.03 / 1.08)


def test_report_subcommand_parser():
    import argparse

    parser = argparse.ArgumentParser()
    report.add_parser(parser.add_subparsers(dest="command"))
    args = parser.parse_args(["report", "OUT", "--no-plots"])
    assert args.command == "report" and args.out == "OUT" and args.no_plots


def test_speed_error_table_finds_the_limit_and_the_cpu_for_one_percent(capsys):
    """Synthetic meshes v = v* + C n^-p: the fit recovers v*, and the CPU at 1 % error is the
    log-log interpolation between the meshes that bracket it (computed here from the model)."""
    import math

    from study.bench.plastic import error_table

    rows = []
    for code, cpu0 in (("slipstick", 1.0), ("tamaas", 10.0)):
        for n in (16, 24, 32, 48):
            rows.append(
                {
                    "code": code,
                    "n": n,
                    "cpu_s": cpu0 * (n / 16) ** 3,
                    "ep_max_%": 0.78 + 0.5 * n**-1.5,
                    "dent_um": 4.3 + 1.0 / n,
                }  # fmt: skip
            )
    error_table(rows)
    out = capsys.readouterr().out
    assert "e_p,max: converged value 0.78 " in out and "order 1.50" in out
    # the dent's error 1/(4.3 n) crosses 1 % between n = 16 and 24: log-log interpolation
    e16, e24 = 1 / (4.3 * 16), 1 / (4.3 * 24)
    f = math.log(e16 / 0.01) / math.log(e16 / e24)
    cpu = math.exp(f * math.log(1.5**3))
    assert f"slipstick, residual dent: {cpu:.3g} s (between n = 16 and 24)" in out
    assert f"tamaas, residual dent: {10 * cpu:.3g} s (between n = 16 and 24)" in out


def test_speed_error_table_takes_the_quantities_and_the_columns_it_is_given(capsys):
    """The periodic rough scene's table: its own quantities (an area with order-1 error), and
    the resolution columns carried over from the rows (None where a code has none)."""
    from study.bench.plastic import error_table
    from study.bench.rough_periodic import ERROR_QUANTITIES

    rows = [
        {"code": code, "n": n, "cpu_s": 1.0, "spot_cells": n / 4 if code == "slipstick" else None}
        | {column: 30.0 + 40.0 / n for column in ERROR_QUANTITIES}
        for code in ("slipstick", "tamaas")
        for n in (32, 64, 128)
    ]
    error_table(rows, quantities=ERROR_QUANTITIES, carry=("spot_cells",))
    out = capsys.readouterr().out
    assert "real area at 0.5 GPa: converged value 30 (area_0.5GPa_%), observed order 1.00" in out
    header = next(line for line in out.splitlines() if line.startswith("| code"))
    assert header.split("|")[3].strip() == "spot_cells" and "area2_err_%" in header
    # slipstick at n = 32: 8 cells across, error (40/32)/30 in percent
    assert f"| slipstick | 32 | 8 | 1 | {100 * 40 / 32 / 30:.4g} |" in out
    assert "| tamaas | 32 | - | 1 |" in out
