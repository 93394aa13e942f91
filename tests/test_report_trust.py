"""Reports a reader can trust: designs summarised, empty tables left out, headers that say their
reduction, moving contacts drawn whole, one number from one source, untrusted values flagged.

Synthetic datasets and per-case files (milliseconds): a sliding case whose largest pressure lies
behind the contact centre (x < 0) and whose largest plastic strain lies off the plane y = 0.
"""

import json
import math
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from study_fixtures import capture_figures as _capture

from solver.variables import reduced_scalars
from study import report
from study.report import builder, figures, tables
from study.report import plastic as report_plastic
from study.report import rough as report_rough
from study.run import storage

A = 4e-4  # the Hertz semi-axis (m)
P_H = 1e9  # the Hertz pressure (Pa)


def sliding_dataset(folder: Path, steps_converged=(1, 1, 1), status: int = 1) -> xr.Dataset:
    """One plastic sliding case along a friction axis of two values (the same case twice).

    Its pressure along y = 0 peaks at 1.65 p_H at x = -0.5 a (behind the centre, which the
    r >= 0 profiles miss); its largest plastic strain lies at y = 2 cells, off the plane y = 0.
    """
    x = (np.arange(32) - 15.5) / 8 * A * 1.5 + 1e-4  # body 1 moved 0.1 mm along x
    y = (np.arange(16) - 7.5) / 8 * A * 1.5
    z = (np.arange(8) + 0.5) / 8 * A * 1.5
    shift = 1e-4
    centred = (x - shift) / A
    line = P_H * np.where(np.abs(centred) < 1, 1.0 + 0.65 * np.exp(-((centred + 0.5) ** 2) * 40), 0)
    line *= np.sqrt(np.clip(1 - centred**2, 0, None)) / np.sqrt(1 - 0.25)  # 1.65 at x = -0.5
    strain = np.zeros((x.size, y.size, z.size))
    strain[20, 7, 2] = 0.141  # in the plane nearest y = 0 (row 7)
    strain[20, 10, 2] = 0.166  # the largest, off it
    ids = np.array(["s0", "s1"])
    storage.cases_dir(folder).mkdir(parents=True, exist_ok=True)
    for case_id in ids:
        xr.Dataset(
            {
                "pressure_y0": (("x",), line),
                "shear_x_y0": (("x",), 0.3 * line),
                "position_x": (("step",), np.linspace(0.0, shift, 3)),
                "contact_state": (
                    ("x", "y"),
                    np.broadcast_to(
                        np.where(line > 0, 2, 0).astype(np.int8)[:, None], (x.size, y.size)
                    ),
                ),
                "plastic_strain": (("x", "y", "z"), strain),
            },
            coords={"x": x, "y": y, "z": z},
            attrs={"hertz_semi_axis_x": A, storage.COMPLETE_ATTR: 1},
        ).to_netcdf(storage.cases_dir(folder) / f"{case_id}.nc")
    r = np.linspace(0.0, 1.5, 31)
    half = np.interp(r, centred, line)  # the dataset's profile: x >= 0 only
    mu = [0.3, 0.5]
    return xr.Dataset(
        {
            "status": (("mu",), np.full(2, status, dtype=np.int8)),
            "case_id": (("mu",), ids),
            "hertz_pressure": (("mu",), np.full(2, P_H), {"units": "Pa"}),
            "hertz_radius": (("mu",), np.full(2, A), {"units": "m"}),
            "max_pressure": (("mu",), np.full(2, line.max()), {"units": "Pa"}),
            "max_plastic_strain": (("mu",), np.full(2, strain.max()), {"units": "1"}),
            "max_plastic_strain_depth": (("mu",), np.full(2, z[2]), {"units": "m"}),
            "position_x_history": (("mu", "step"), np.tile(np.linspace(0, shift, 3), (2, 1))),
            "step_converged_history": (("mu", "step"), np.tile(steps_converged, (2, 1))),
            "pressure_profile": (("mu", "r_over_a"), np.tile(half, (2, 1)), {"units": "Pa"}),
            "shear_x_profile": (("mu", "r_over_a"), np.tile(0.3 * half, (2, 1)), {"units": "Pa"}),
        },
        coords={
            "mu": ("mu", mu, {"campaign_key": "friction.coefficient"}),
            "r_over_a": ("r_over_a", r, {"units": "1"}),
        },
        attrs={"campaign": "sliding", "campaign_base": json.dumps({})},
    )


def design_dataset(rows: int = 300) -> xr.Dataset:
    """A sampled design of ``rows`` plastic cases (no files: the tables read the dataset)."""
    rng = np.random.default_rng(5)
    p_h = rng.uniform(3e9, 6e9, rows)
    strain = 1e-3 * (p_h / 1e9 - 2.5)
    steps = np.ones((rows, 3))
    steps[7, 1] = 0  # one case holds an unconverged increment

    def var(values, units):
        return (("sample",), np.asarray(values, dtype=float), {"units": units})

    return xr.Dataset(
        {
            "status": (("sample",), np.ones(rows, dtype=np.int8)),
            "case_id": (("sample",), np.array([f"d{i}" for i in range(rows)])),
            "hertz_pressure": var(p_h, "Pa"),
            "hertz_radius": var(np.full(rows, A), "m"),
            "max_pressure": var(p_h * (1 - 20 * strain), "Pa"),
            "contact_radius": var(np.full(rows, A), "m"),
            "max_plastic_strain": var(strain, "1"),
            "residual_depth": var(strain * 1e-4, "m"),
            "step_converged_history": (("sample", "step"), steps),
        },
        coords={"p_h": ("sample", p_h, {"campaign_key": "load.hertz_pressure"})},
        attrs={"campaign": "design"},
    )


# -- 1. designs summarised, empty tables left out ------------------------------------------------
def test_a_design_gets_a_summary_not_a_row_per_case():
    dataset = design_dataset()
    lines = report_plastic.section(dataset, Path("."), "design", None, [])
    text = "\n".join(lines)
    assert len(lines) < 60 < dataset.sizes["sample"]  # 300 cases
    assert "The extreme cases:" in text and "| quantity | cases | min |" in text
    headers = report_plastic.column_labels()
    ep, p = headers["ep_max_%"], headers["p_max/p_H"]
    # the extremes are the dataset's: the largest plastic strain and the smallest p_max / p_H
    ratio = dataset["max_pressure"].values / dataset["hertz_pressure"].values
    largest = 100 * float(dataset["max_plastic_strain"].max())
    assert f"max {ep}" in text and figures.fmt(largest) in text
    assert f"min {p}" in text and figures.fmt(float(ratio.min())) in text
    # the summary's median is the dataset's
    assert figures.fmt(float(np.median(ratio))) in text
    assert tables.FLAG_NOTE in text  # one case holds an unconverged increment


def test_a_table_of_zero_derivatives_is_not_written():
    mu = np.array([0.0, 0.3])
    flat = np.full((2, 3), 2e9)  # friction does not move the pressure
    moved = np.array([[1.0, 2.0, 3.0], [1.5, 2.5, 3.5]]) * 1e-4
    dataset = xr.Dataset(
        {
            "status": (("mu", "p_h"), np.ones((2, 3), dtype=np.int8)),
            "max_pressure": (("mu", "p_h"), flat, {"units": "Pa"}),
            "contact_radius": (("mu", "p_h"), moved, {"units": "m"}),
        },
        coords={
            "mu": ("mu", mu, {"campaign_key": "friction.coefficient"}),
            "p_h": ("p_h", [1e9, 2e9, 3e9], {"campaign_key": "load.hertz_pressure"}),
        },
    )
    text = "\n".join(builder._sensitivity_lines(dataset, ["max_pressure", "contact_radius"]))
    assert "### d `max_pressure`" not in text
    assert "not tabulated: d `max_pressure` / d `mu`" in text
    assert "### d `contact_radius` / d `mu`" in text
    assert builder._sensitivity_lines(dataset, ["max_pressure"])[-2].startswith("Zero")


# -- 2. headers say their reduction, from the declarations ---------------------------------------
def test_headers_say_the_declared_reduction():
    declared = reduced_scalars()
    for column, label in report_plastic.column_labels().items():
        name = report_plastic.COLUMNS[column][0]
        source = tables.DERIVED.get(name, (name,))[0]
        words = tables.REDUCTION_WORDS[declared[source][1]]
        assert label == f"{column} ({words})"
    rough = report_rough.column_labels()
    assert rough["spots"] == f"spots ({tables.AT_PEAK})"  # not the declared max over the path
    assert rough["ep_max_%"].endswith(
        f"({tables.REDUCTION_WORDS[declared['max_plastic_strain'][1]]})"
    )


# -- 3. a moving contact drawn whole; one number, one source -------------------------------------
def test_a_sliding_case_is_drawn_on_both_sides_up_to_its_largest_pressure(tmp_path, monkeypatch):
    pytest.importorskip("matplotlib")
    monkeypatch.setattr("study.report.figures.DPI", 40)
    saved = _capture(monkeypatch)
    dataset = sliding_dataset(tmp_path)
    ratio = float(dataset["max_pressure"].max() / dataset["hertz_pressure"].max())
    assert ratio > 1.6  # the case: 1.65 p_H, behind the centre
    assert float(dataset["pressure_profile"].max()) / P_H < ratio - 0.1  # the half line misses it
    png = report_plastic.plot_profiles(dataset, tmp_path, tmp_path / "profiles.png")
    (ax,) = [a for a in saved[png.name].axes if a.get_visible()]
    low, high = ax.get_xlim()
    assert low < 0 < high and ax.get_ylim()[1] >= ratio
    drawn = max(float(np.nanmax(line.get_ydata())) for line in ax.get_lines()
                if str(line.get_gid()).startswith("series "))  # fmt: skip
    assert drawn == pytest.approx(ratio)
    assert any(line.get_gid() == "p_max" for line in ax.get_lines())
    # the legend inside the figure
    figure = saved[png.name]
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    box = figure.legends[0].get_window_extent(FigureCanvasAgg(figure).get_renderer())
    assert box.x0 >= 0 and box.x1 <= figure.bbox.width and box.y0 >= 0

    png = report.plot_profiles(dataset, tmp_path / "gpa.png", tmp_path)  # one panel per case
    for ax, peak in zip(saved[png.name].axes, dataset["max_pressure"].values, strict=True):
        assert ax.get_xlim()[0] < 0 and ax.get_ylim()[1] >= peak / 1e9


def test_the_sections_label_says_the_datasets_largest_strain(tmp_path, monkeypatch):
    pytest.importorskip("matplotlib")
    monkeypatch.setattr("study.report.figures.DPI", 40)
    saved = _capture(monkeypatch)
    dataset = sliding_dataset(tmp_path)
    png = report_plastic.plot_sections(dataset, tmp_path, tmp_path / "sections.png")
    panels = [ax for ax in saved[png.name].axes if ax.get_label() != "<colorbar>"]
    expected = f"max {100 * float(dataset['max_plastic_strain'][0]):.3g} %"
    for ax in panels:
        (label,) = [t.get_text() for t in ax.texts if t.get_gid() == "max label"]
        assert label.startswith(expected + " at") and "off this plane" in label


def test_the_sections_title_says_which_cases_it_leaves_out(tmp_path, monkeypatch):
    pytest.importorskip("matplotlib")
    monkeypatch.setattr("study.report.figures.DPI", 40)
    saved = _capture(monkeypatch)
    dataset = sliding_dataset(tmp_path)
    total = dataset.sizes["mu"]

    def title() -> str:
        png = report_plastic.plot_sections(dataset, tmp_path, tmp_path / "sections.png")
        return " ".join(saved[png.name].get_suptitle().split())

    assert f"all {total} finished cases, finest mesh" in title()
    panels = report_plastic.figures.MAX_PANELS
    monkeypatch.setattr("study.report.figures.MAX_PANELS", total - 1)
    assert (
        f"{total - 1} of {total} finished cases (only the first {total - 1} in axis order"
    ) in title()
    monkeypatch.setattr("study.report.figures.MAX_PANELS", panels)
    (storage.cases_dir(tmp_path) / "s1.nc").unlink()
    assert f"{total - 1} of {total} finished cases (1 without a stored field)" in title()


# -- 4. untrusted values flagged -----------------------------------------------------------------
@pytest.mark.parametrize(("steps", "status", "flag"), [
    ((1, 0, 1), 1, "1/3 steps unconverged"),
    ((1, 1, 1), 2, "not converged"),
    ((1, 1, 1), 1, ""),
])  # fmt: skip
def test_unconverged_cases_are_flagged(tmp_path, steps, status, flag):
    dataset = sliding_dataset(tmp_path, steps, status)
    table = report_plastic.plastic_table(dataset)
    assert list(table[tables.FLAG]) == [flag, flag]
    text = "\n".join(report_plastic.section(dataset, tmp_path, "sliding", None, []))
    assert (tables.FLAG_NOTE in text) == bool(flag)
    header = next(line for line in text.splitlines() if line.startswith("| mu |"))
    assert (f"| {tables.FLAG} |" in header) == bool(flag)  # the column only when it says something
    if flag:
        assert f"| {flag} |" in text


def test_flag_counts_the_unconverged_steps():
    dataset = design_dataset(12)
    assert tables.unconverged_steps(dataset, {"sample": 7}) == (1, 3)
    assert tables.flag(dataset, {"sample": 7}) == "1/3 steps unconverged"
    assert tables.flag(dataset, {"sample": 0}) == ""
    assert not math.isnan(tables.carries_nothing([0.0, np.nan]))
    assert tables.carries_nothing([0.0, np.nan]) and not tables.carries_nothing([0.0, 1e-30])
