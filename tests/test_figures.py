"""Figures a reader can read: distinct series, marked untrusted cases, ratio units, layout.

The report's line plots and the examples draw every series with
:func:`study.report.figures.series_style`; cases that are not converged or truncated are marked
in the figures; a ratio's axis label says "(1)"; titles stay clear of colour bars.
"""

import importlib.util
import itertools
import json
import sys
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from study_fixtures import capture_figures as _capture
from study_fixtures import small_campaign

from study import report
from study.campaign import load_campaign
from study.report import figures
from study.report import plastic as report_plastic
from study.run import storage
from study.run.driver import RunOptions, run_campaign

pytest.importorskip("matplotlib")

EXAMPLES = Path(__file__).parent.parent / "examples"
TRUNCATED, NOT_CONVERGED = 4, 2


# -- helpers -------------------------------------------------------------------------------------
def _series(ax):
    """The data series of a panel: its lines drawn by :func:`figures.series_style`."""
    return [line for line in ax.get_lines() if str(line.get_gid()).startswith("series ")]


def _style(line):
    """(marker, line style): the style's name and its dash pattern (a tuple style is "--")."""
    offset, dashes = line._unscaled_dash_pattern
    return line.get_marker(), line.get_linestyle(), offset, tuple(dashes or ())


def _distinct_series(figure) -> int:
    """Assert that the series of each panel differ in (marker, line style); count the panels."""
    checked = 0
    for ax in figure.axes:
        by_series = {}
        for line in _series(ax):
            by_series.setdefault(line.get_gid(), set()).add(_style(line))
        if len(by_series) < 2:
            continue
        styles = [style for group in by_series.values() for style in group]
        assert all(len(group) == 1 for group in by_series.values()), by_series
        assert len(set(styles)) == len(styles), f"shared (marker, line style): {by_series}"
        checked += 1
    return checked


def _marks(ax) -> list[str]:
    return [t.get_text() for t in ax.texts if t.get_gid() == "status mark"]


def _axis_labels(figure) -> list[str]:
    labels = []
    for ax in figure.axes:
        labels += [ax.get_xlabel(), ax.get_ylabel()]
    return [label for label in labels if label]


def _ratio_labels_say_one(figure) -> None:
    """No axis label carries "[Pa]" or xarray's "[...]" units; a ratio's label ends in (1)."""
    for label in _axis_labels(figure):
        assert "[Pa]" not in label and "[m]" not in label, label
        if " / " in label:
            assert label.rstrip().endswith("(1)"), label


def _render(figure) -> np.ndarray:
    """The figure's pixels (RGB), drawn without its legends (their swatches hold every colour)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    legends = [ax.get_legend() for ax in figure.axes if ax.get_legend()] + list(figure.legends)
    for legend in legends:
        legend.set_visible(False)
    canvas = FigureCanvasAgg(figure)  # the report closed the figure: a canvas of its own
    canvas.draw()
    for legend in legends:
        legend.set_visible(True)
    return np.asarray(canvas.buffer_rgba())[..., :3].astype(int)


def _colour_pixels(image, ax, colour, tol=40, above=None) -> int:
    """Pixels of ``ax`` in ``image`` within ``tol`` of ``colour`` in every RGB channel.

    ``above``: only the part of the panel above this ordinate (data units).
    """
    from matplotlib.colors import to_rgb

    box = ax.get_window_extent()
    height = image.shape[0]
    bottom = box.y0 if above is None else ax.transData.transform((0.0, above))[1]
    rows = slice(int(height - box.y1) + 2, int(height - bottom) - 2)
    cols = slice(int(box.x0) + 2, int(box.x1) - 2)
    target = np.array(to_rgb(colour)) * 255
    close = np.all(np.abs(image[rows, cols] - target) <= tol, axis=-1)
    return int(close.sum())


# -- the style helper ----------------------------------------------------------------------------
@pytest.mark.parametrize("count", [1, 2, 3, 5, 10, 11, figures.MAX_LINES])
def test_series_styles_differ_and_let_later_ones_show(count):
    styles = [figures.series_style(j, count) for j in range(count)]
    pairs = [(s["marker"], str(s["linestyle"])) for s in styles]
    assert len(set(pairs)) == count
    assert len({str(s["color"]) for s in styles}) == count
    for earlier, later in itertools.pairwise(styles):
        # a later series is drawn above an earlier one, narrower and with smaller markers
        assert later["zorder"] > earlier["zorder"]
        assert later["markersize"] < earlier["markersize"]
        assert later["linewidth"] < earlier["linewidth"]
    # no two of the first five (a typical sweep) share a line style either
    assert len({str(s["linestyle"]) for s in styles[:5]}) == min(count, 5)


def test_dense_lines_get_shifted_markers_and_untrusted_cases_hollow():
    dense = [figures.series_style(j, 3, points=151)["markevery"] for j in range(3)]
    assert len({start for start, _ in dense}) == 3  # markers of coinciding lines do not stack
    assert "markevery" not in figures.series_style(0, 3, points=4)
    for status in ("truncated", "not_converged"):
        style = figures.series_style(1, 3, status=status)
        assert style["markerfacecolor"] == "white" and style["markeredgecolor"] == style["color"]
    assert "markerfacecolor" not in figures.series_style(1, 3, status="converged")
    (handle,) = figures.status_handle(["converged", "truncated"])
    assert "truncated" in handle.get_label()
    assert figures.status_handle(["converged"]) == []
    assert figures.status_note(["converged", "truncated", "truncated"]).startswith(
        "2 cases truncated"
    )


# -- the plastic figures on a synthetic dataset --------------------------------------------------
MU = [0.0, 0.3, 0.5]
P_H = [3e9, 4e9, 5e9]


def plastic_dataset(folder: Path, statuses=None) -> xr.Dataset:
    """A plastic load x friction sweep where mu = 0.3 and mu = 0.5 give the same answers.

    The cases' results (contact state along the surface, plastic strain in the volume) are
    written to the output folder ``folder`` as per-case files (``folder/cases/<id>.nc``, the
    layout before bundles, still read by :func:`study.run.storage.open_case`).
    """
    shape = (len(MU), len(P_H))
    p_h = np.broadcast_to(np.array(P_H)[None, :], shape)
    same = np.array([0.0, 1.0, 1.0])[:, None]  # mu = 0.3 and 0.5: the same numbers
    r = np.linspace(0.0, 1.5, 151)
    hertz = np.sqrt(np.clip(1 - r**2, 0, None))
    pressure = p_h[..., None] * (0.9 + 0.05 * same[..., None]) * hertz
    shear = 0.1 * same[..., None] * pressure * r

    def var(values, units):
        return (("mu", "p_h"), np.asarray(values, dtype=float), {"units": units})

    ids = np.array([[f"c{i}{j}" for j in range(shape[1])] for i in range(shape[0])])
    dataset = xr.Dataset(
        {
            "status": (
                ("mu", "p_h"),
                np.ones(shape, dtype=np.int8)
                if statuses is None
                else np.asarray(statuses, dtype=np.int8),
            ),  # fmt: skip
            "case_id": (("mu", "p_h"), ids),
            "hertz_pressure": var(p_h, "Pa"),
            "hertz_radius": var(np.full(shape, 4e-4), "m"),
            "max_pressure": var(p_h * (0.9 + 0.05 * same), "Pa"),
            "max_plastic_strain": var(1e-3 * (p_h / 1e9 - 2) * (1 + 0.1 * same), "1"),
            "max_plastic_strain_depth": var(np.full(shape, 2e-4) * (1 - 0.2 * same), "m"),
            "pressure_profile": (("mu", "p_h", "r_over_a"), pressure, {"units": "Pa"}),
            "shear_x_profile": (("mu", "p_h", "r_over_a"), shear, {"units": "Pa"}),
        },
        coords={
            "mu": ("mu", MU, {"campaign_key": "friction.coefficient"}),
            "p_h": ("p_h", P_H, {"campaign_key": "load.hertz_pressure"}),
            "r_over_a": ("r_over_a", r, {"units": "1"}),
        },
        attrs={"campaign": "synthetic_plastic", "campaign_base": json.dumps({})},
    )
    x = y = (np.arange(16) - 7.5) / 8 * 1.5
    z = (np.arange(8) + 0.5) / 8 * 1.5
    xx, yy, zz = np.meshgrid(x, y, z, indexing="ij")
    storage.cases_dir(folder).mkdir(parents=True, exist_ok=True)
    for (i, mu), (j, load) in itertools.product(enumerate(MU), enumerate(P_H)):
        rr = np.hypot(xx[..., 0], yy[..., 0])
        state = np.where(rr < 0.5 if mu else rr < 0, 1, np.where(rr < 1, 2, 0))
        strain = 1e-3 * load / 1e9 * np.exp(-(xx**2 + yy**2 + (zz - 0.5) ** 2) * 4)
        xr.Dataset(
            {
                "contact_state": (("x", "y"), state.astype(np.int8)),
                "plastic_strain": (("x", "y", "z"), strain),
            },
            coords={"x": x * 4e-4, "y": y * 4e-4, "z": z * 4e-4},
            attrs={"hertz_semi_axis_x": 4e-4, storage.COMPLETE_ATTR: 1},
        ).to_netcdf(storage.cases_dir(folder) / f"c{i}{j}.nc")
    return dataset


@pytest.fixture
def statuses():
    values = np.ones((len(MU), len(P_H)), dtype=np.int8)
    values[2, 2] = TRUNCATED  # mu = 0.5, p_H = 5 GPa
    values[1, 1] = NOT_CONVERGED  # mu = 0.3, p_H = 4 GPa
    return values


def test_load_curves_keep_coinciding_series_visible(tmp_path, monkeypatch, statuses):
    saved = _capture(monkeypatch)
    dataset = plastic_dataset(tmp_path)
    png = report_plastic.plot_load_curves(dataset, tmp_path / "curves.png")
    figure = saved[png.name]
    assert _distinct_series(figure) == 3  # every panel: 3 series, each its own style
    _ratio_labels_say_one(figure)
    # mu = 0.3 (C1) lies under mu = 0.5 (C2) in every panel: it still shows (drawn in one
    # style, "o-" for both, the orange line and markers were hidden under the green ones)
    image = _render(figure)
    for ax in figure.axes:
        assert _colour_pixels(image, ax, "C1") > 30, ax.get_ylabel()
        assert _colour_pixels(image, ax, "C2") > 10, ax.get_ylabel()
    assert not figure._suptitle.get_text().count("truncated")  # every case converged

    saved.clear()
    dataset = plastic_dataset(tmp_path, statuses)
    png = report_plastic.plot_load_curves(dataset, tmp_path / "curves.png")
    figure = saved[png.name]
    for ax in figure.axes:
        hollow = [line for line in ax.get_lines() if line.get_gid() == "untrusted point"]
        assert len(hollow) == 2 and all(line.get_markerfacecolor() == "white" for line in hollow)
    legend = [t.get_text() for t in figure.axes[0].get_legend().get_texts()]
    assert "hollow: not converged or truncated" in legend
    assert "1 case not converged, 1 case truncated" in figure._suptitle.get_text()


def test_plastic_profiles_and_sections_mark_untrusted_cases(tmp_path, monkeypatch, statuses):
    saved = _capture(monkeypatch)
    dataset = plastic_dataset(tmp_path, statuses)
    png = report_plastic.plot_profiles(dataset, tmp_path, tmp_path / "profiles.png")
    figure = saved[png.name]
    panels = [ax for ax in figure.axes if ax.get_visible()]
    assert len(panels) == 3  # one per load, mu overlaid
    assert _distinct_series(figure) == 3
    _ratio_labels_say_one(figure)
    # the curves are named in each panel (the style says the case, not the quantity)
    assert all({"p", "q_x"} <= {t.get_text() for t in ax.texts} for ax in panels[1:])
    # the mu = 0.3 and 0.5 tractions coincide: both colours show above the stick/slip bars
    image = _render(figure)
    for ax in panels:
        assert _colour_pixels(image, ax, "C1", above=0.02) > 100
        assert _colour_pixels(image, ax, "C2", above=0.02) > 100
    marks = [_marks(ax) for ax in panels]
    assert marks == [[], ["mu=0.3: not converged"], ["mu=0.5: truncated"]]
    for ax, mark in zip(panels, marks, strict=True):
        red = {spine.get_edgecolor() for spine in ax.spines.values()}
        assert (len(mark) > 0) == (red == {(0.8392156862745098, 0.15294117647058825,
                                            0.1568627450980392, 1.0)})  # fmt: skip
    truncated = [line for line in _series(panels[2]) if line.get_gid() == "series 2"]
    assert truncated and all(line.get_markerfacecolor() == "white" for line in truncated)
    assert "1 case not converged, 1 case truncated" in figure._suptitle.get_text()

    png = report_plastic.plot_sections(dataset, tmp_path, tmp_path / "sections.png")
    figure = saved[png.name]
    panels = [ax for ax in figure.axes if ax.get_visible() and ax.get_label() != "<colorbar>"]
    titles = {ax.get_title(): _marks(ax) for ax in panels}
    assert titles["mu=0.5, p_h=5e+09"] == ["truncated"]
    assert titles["mu=0.3, p_h=4e+09"] == ["not converged"]
    assert sum(bool(m) for m in titles.values()) == 2
    _ratio_labels_say_one(figure)


# -- the elastic report on a tiny campaign -------------------------------------------------------
@pytest.fixture(scope="module")
def small_out(tmp_path_factory):
    folder = tmp_path_factory.mktemp("figures_small")
    campaign = load_campaign(small_campaign(folder))
    assert run_campaign(campaign, folder / "out", options=RunOptions()).exit_status == 0
    return folder / "out"


def test_report_series_distinct_and_truncated_panels_marked(small_out, monkeypatch):
    saved = _capture(monkeypatch)
    monkeypatch.setattr("study.report.figures.DPI", 50)
    assert report.main([str(small_out)]) == 0
    convergence = saved["small_convergence_mesh.png"]
    assert _distinct_series(convergence) >= 2  # mu = 0 and 0.2 in each quantity's panel
    for figure in saved.values():
        _ratio_labels_say_one(figure)
        assert not any(_marks(ax) for ax in figure.axes)  # every case converged
    # one case truncated: its profile and contact-state panels carry the mark, the report's
    # convergence points of it are hollow
    path = small_out / "small.nc"
    with xr.open_dataset(path) as ds:
        ds = ds.load()
    ds["status"][1, 1] = TRUNCATED  # mu = 0.2 on the finest mesh
    ds.to_netcdf(path)
    saved.clear()
    assert report.main([str(small_out)]) == 0
    for name in ("small_profiles.png", "small_stick_slip.png"):
        figure = saved[name]
        marked = [ax.get_title() for ax in figure.axes if _marks(ax)]
        assert len(marked) == 1 and "mu=0.2" in marked[0], name
        assert "1 case truncated" in figure._suptitle.get_text(), name
    hollow = [
        line
        for ax in saved["small_convergence_mesh.png"].axes
        for line in ax.get_lines()
        if line.get_gid() == "untrusted point"
    ]
    assert hollow


# -- the examples --------------------------------------------------------------------------------
def _example(name: str):
    sys.path.insert(0, str(EXAMPLES))
    try:
        spec = importlib.util.spec_from_file_location(f"example_{name}", EXAMPLES / f"{name}.py")
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
    finally:
        sys.path.remove(str(EXAMPLES))
    return module


def test_your_surface_titles_clear_of_the_colour_bars():
    import matplotlib.pyplot as plt

    module = _example("your_surface")
    n = 32
    x = np.linspace(-1.5, 1.5, n)
    xx, yy = np.meshgrid(x, x, indexing="ij")
    pressure = 1.4e9 * np.sqrt(np.clip(1 - xx**2 - yy**2, 0, None))
    heights = 2e-7 * np.sin(5 * xx) * np.cos(3 * yy)
    # a long title, as with many contact spots
    figure = module.draw(heights, pressure, 4 * pressure, (-1.5, 1.5, -1.5, 1.5), 12345)
    figure.canvas.draw()
    renderer = figure.canvas.get_renderer()
    bars = [ax for ax in figure.axes if ax.get_label() == "<colorbar>"]
    panels = [ax for ax in figure.axes if ax.get_label() != "<colorbar>"]
    assert len(bars) == 3 and len(panels) == 3
    texts = [ax.title for ax in panels] + [figure._suptitle]
    for text in texts:
        box = text.get_window_extent(renderer)
        for bar in bars:
            assert not box.overlaps(bar.get_tightbbox(renderer)), text.get_text()
    for bar in bars:  # each colour bar says its quantity and unit
        assert bar.get_xlabel().endswith(("(um)", "(GPa)"))
    _ratio_labels_say_one(figure)
    plt.close(figure)


def test_examples_import_the_report_style():
    common = (EXAMPLES / "_common.py").read_text()
    assert "from study.report.figures import series_style" in common
    for name in ("hertz_pressure", "fretting_loop"):
        assert "series_style(" in (EXAMPLES / f"{name}.py").read_text(), name


# -- the rolling and shakedown figures on synthetic datasets -------------------------------------
def test_creep_curves_passes_distinct_and_labelled_as_ratios(tmp_path, monkeypatch):
    from study.report import rolling

    saved = _capture(monkeypatch)
    creepage = np.array([0.5e-3, 1e-3, 2e-3])
    ratio = np.tanh(creepage / 1e-3)[:, None] * np.ones((1, 2))  # two passes, the same force
    dataset = xr.Dataset(
        {
            "status": (("xi",), np.array([1, 1, TRUNCATED], dtype=np.int8)),
            "friction_coefficient": (("xi",), np.full(3, 0.3)),
            "hertz_normal_force": (("xi",), np.full(3, 100.0), {"units": "N"}),
            "creep_force_x": (("xi", "cycle"), 30.0 * ratio, {"units": "N"}),
        },
        coords={"xi": ("xi", creepage, {"campaign_key": "load.path.1.creepage"})},
        attrs={"campaign": "synthetic_rolling"},
    )
    assert rolling.creepage_axis(dataset) == "xi"
    png = rolling.plot_curves(dataset, "xi", tmp_path / "creep.png")
    figure = saved[png.name]
    assert _distinct_series(figure) == 1
    _ratio_labels_say_one(figure)
    assert figure.axes[0].get_ylabel().endswith("(1)")
    image = _render(figure)  # pass 1 under pass 2: both show
    assert _colour_pixels(image, figure.axes[0], "C0") > 30
    assert _colour_pixels(image, figure.axes[0], "C1") > 10
    hollow = [line for line in figure.axes[0].get_lines() if line.get_gid() == "untrusted point"]
    assert len(hollow) == 2  # the truncated case, in each pass
    assert "1 case truncated" in figure._suptitle.get_text()


def test_shakedown_map_rings_untrusted_cases(tmp_path, monkeypatch):
    from solver.theory.shakedown import SHAKEDOWN_FLAGS
    from study.report import shakedown

    saved = _capture(monkeypatch)
    dataset = xr.Dataset(
        {
            "status": (("mu",), np.array([1, NOT_CONVERGED], dtype=np.int8)),
            "hertz_pressure": (("mu",), np.full(2, 4e9)),
            "shear_yield_stress": (("mu",), np.full(2, 1e9)),
            "friction_coefficient": (("mu",), np.array([0.1, 0.2])),
            "shakedown": (("mu",), np.full(2, SHAKEDOWN_FLAGS["elastic_shakedown"])),
            "plastic_strain_increment": (("mu", "cycle"), np.full((2, 3), 1e-6)),
            "net_plastic_strain_increment": (("mu", "cycle"), np.full((2, 3), 1e-7)),
        },
        coords={"mu": ("mu", [0.1, 0.2], {"campaign_key": "friction.coefficient"})},
        attrs={"campaign": "synthetic_shakedown"},
    )
    png = shakedown.plot_map(dataset, tmp_path / "map.png", 0.3)
    figure = saved[png.name]
    assert "1 not converged (ringed" in figure._suptitle.get_text()  # the status it has
    legend = [t.get_text() for t in figure.legends[0].get_texts()]
    assert "not converged" in legend
    _ratio_labels_say_one(figure)


def test_panel_titles_carry_their_units():
    """The trial read ``p_h=2.5e+09``: pressures in GPa, other units as declared, ratios bare."""
    import xarray as xr

    from study.report.figures import title

    dataset = xr.Dataset(
        coords={
            "p_h": ("p_h", [2.5e9], {"units": "Pa"}),
            "radius": ("radius", [0.015], {"units": "m"}),
            "mu": ("mu", [0.3], {"units": "1"}),
        }
    )
    labels = {"mu": 0.3, "p_h": 2.5e9, "radius": 0.015}
    assert title(labels, width=80, dataset=dataset) == "mu=0.3, p_h=2.5 GPa, radius=0.015 m"
    assert title(labels, width=80) == "mu=0.3, p_h=2.5e+09, radius=0.015"
