"""Figure and table helpers of the report: panel grids, titles, notes, log ticks, markdown.

The bottom of :mod:`study.report`: the elastic, plastic and cyclic sections draw with these.
Every line plot of the report (and of the examples) styles its series with
:func:`series_style` (own colour, marker and line style; coinciding series stay visible) and
marks the cases that are not converged or truncated with :func:`mark_panel` (a panel of one
case, or of several) and hollow markers (:func:`status_handle` names them in the legend).
Axis labels give units in brackets, a ratio's as "(1)".
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from .. import analysis

#: Most panels in one figure (further slices are named as not shown in its title and in
#: report.md), most lines (cases or slices) in one panel, most panel columns.
MAX_PANELS = 24
MAX_LINES = 16
MAX_COLUMNS = 4
#: Resolution of the PNG figures (dots per inch) and height (inches) added for the title.
DPI = 110
TITLE_HEIGHT = 0.7
#: Height (inches) added per row of a legend below the panels.
LEGEND_ROW = 0.25
#: More slices than this in a convergence figure share one legend below the panels.
SHARED_LEGEND_SLICES = 4
STATE_NAMES = ("separated", "stick", "slip")
#: Table columns printed with 9 significant digits (values close to each other).
VALUE_COLUMNS = ("value", "finest", "extrapolated", "error_bar", "reference")
#: Marker shapes and line styles of the series of a line plot (:func:`series_style`): the
#: markers differ for :data:`MAX_LINES` series, so no two series share a (marker, style) pair.
MARKERS = ("o", "s", "^", "D", "v", "P", "X", "*", "<", ">", "p", "h", "d", "H", "8", "x")
LINESTYLES = ("-", "--", "-.", ":", (0, (4, 1, 1, 1, 1, 1)))
#: Largest and smallest marker size (points) and line width of the series: the first series is
#: drawn largest and lowest, each later one smaller and above it, so coinciding ones stay visible.
MARKER_SIZES = (8.0, 3.5)
LINE_WIDTHS = (2.2, 1.0)
#: A line with more points than this gets markers on every few points only, shifted per series.
DENSE_POINTS = 24
#: Statuses of a finished case that is not trusted, as said in the figures.
UNTRUSTED = {
    "not_converged": "not converged", "truncated": "truncated", "surface_flow": "surface flow",
}  # fmt: skip
#: Colour of the status marks (:func:`mark_panel`, :func:`status_handle`).
STATUS_COLOUR = "tab:red"


# -- helpers -------------------------------------------------------------------------------------
def pyplot():
    """Matplotlib's pyplot on the Agg backend, or None when matplotlib is missing."""
    try:
        import matplotlib
    except ImportError:
        return None
    matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt

    return plt


def labels_text(labels: dict) -> str:
    """Sweep coordinates as ``name=value, ...`` ("all cases" when there are none)."""
    return ", ".join(f"{k}={fmt(v)}" for k, v in labels.items()) or "all cases"


def fmt(value, digits: int = 5) -> str:
    """A table cell as text: ``digits`` significant digits, booleans as "yes" or blank."""
    if isinstance(value, bool | np.bool_):
        return "yes" if value else ""
    if isinstance(value, int | np.integer):
        return str(int(value))
    if isinstance(value, float | np.floating):
        if not np.isfinite(value):
            return "" if np.isnan(value) else str(value)
        return f"{value:.{digits}g}"
    return str(value)


def markdown_table(table) -> str:
    """A :class:`pandas.DataFrame` as a Markdown table.

    Numbers get 5 significant digits, the value columns (:data:`VALUE_COLUMNS`) 9.
    """
    if table is None or len(table) == 0:
        return "_(no data)_\n"
    columns = list(table.columns)
    lines = ["| " + " | ".join(columns) + " |", "|" + "|".join("---" for _ in columns) + "|"]
    for _, row in table.iterrows():
        cells = (fmt(row[c], 9 if c in VALUE_COLUMNS else 5) for c in columns)
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def units_of(dataset, name: str) -> str:
    """Units of a dataset variable (or of a declared quantity that is not in it)."""
    if name in dataset.variables:
        return str(dataset[name].attrs.get("units", analysis.QUANTITIES.get(name, ("",))[0]))
    return analysis.QUANTITIES.get(name, ("",))[0]


# -- figures -------------------------------------------------------------------------------------
def title(labels: dict, width: int = 30, dataset=None) -> str:
    """A panel title from slice labels: one line when short, else one ``name=value`` per line.

    With the ``dataset``, each value carries its coordinate's units (pressures in GPa).
    """
    parts = [_labelled(k, v, dataset) for k, v in labels.items()]
    text = ", ".join(parts)
    return text if len(text) <= width else "\n".join(parts)


def _labelled(name: str, value, dataset) -> str:
    """``name=value unit`` of a slice label (no unit for a ratio or a label without one)."""
    coordinate = dataset.coords.get(name) if dataset is not None else None
    units = str(coordinate.attrs.get("units", "")) if coordinate is not None else ""
    if units == "Pa" and isinstance(value, int | float | np.number):
        return f"{name}={fmt(value / 1e9)} GPa"
    return f"{name}={fmt(value)}" + (f" {units}" if units not in ("", "1") else "")


def series_colour(j: int, count: int):
    """The colour of series ``j`` of ``count``: tab10, or tab20 for more than 10 series."""
    if count <= 10:
        return f"C{j % 10}"
    from matplotlib import colormaps

    return colormaps["tab20"](j % 20)


def series_style(
    j: int, count: int, points: int = 0, status: str = "converged", colour=None
) -> dict:
    """Keyword arguments of ``Axes.plot`` for series ``j`` of ``count`` in one panel.

    Every series gets its own marker (:data:`MARKERS`), line style (:data:`LINESTYLES`) and
    colour, so no two share a (marker, line style) pair.  Series that coincide stay visible:
    the first is drawn widest with the largest markers and lowest, each later one narrower,
    with smaller white-rimmed markers and above the earlier ones (a dashed line over a solid
    one); on a
    dense line (more than :data:`DENSE_POINTS` points) the markers are on every few points,
    shifted from one series to the next.  A case that is not trusted (:data:`UNTRUSTED`) is
    drawn with hollow markers.

    Parameters
    ----------
    j : int
        Index of the series in the panel (0 first).
    count : int
        Number of series in the panel.
    points : int, optional
        Points of the line (for the marker spacing of dense lines).
    status : str, optional
        The case's status (a key of :data:`solver.result.STATUS_FLAGS`).
    colour : optional
        A colour instead of :func:`series_colour`.

    Returns
    -------
    dict
        ``color``, ``marker``, ``linestyle``, ``markersize``, ``linewidth``, ``zorder``,
        ``gid`` (``"series <j>"``, for tests) and, where they apply, ``markevery`` and the
        hollow marker's face.
    """
    share = j / max(count - 1, 1)
    big, small = MARKER_SIZES
    wide, narrow = LINE_WIDTHS
    if count == 1:  # nothing to stand out from: a middle size
        big, wide = (big + small) / 2, (wide + narrow) / 2
    style = {
        "color": series_colour(j, count) if colour is None else colour,
        "marker": MARKERS[j % len(MARKERS)],
        "linestyle": LINESTYLES[j % len(LINESTYLES)],
        "markersize": big - (big - small) * share,
        "markeredgecolor": "white",  # a white rim parts a marker from a larger one below it
        "markeredgewidth": 0.8,
        "linewidth": wide - (wide - narrow) * share,
        "zorder": 2.0 + share,
        "gid": f"series {j}",
    }
    if points > DENSE_POINTS:
        step = max(2, points // 12)
        style["markevery"] = ((j * step) // max(count, 1) % step, step)
    if status in UNTRUSTED:
        style["markerfacecolor"] = "white"
        style["markeredgecolor"] = style["color"]
        style["markeredgewidth"] = 1.5
    return style


def series_handle(j: int, count: int, label: str, colour=None):
    """A legend entry (a :class:`matplotlib.lines.Line2D`) drawn as series ``j`` of ``count``."""
    from matplotlib.lines import Line2D

    style = series_style(j, count, colour=colour)
    style.pop("gid")
    return Line2D([], [], label=label, **style)


def status_handle(statuses) -> list:
    """The legend entry of hollow markers when ``statuses`` has an untrusted case, else none."""
    from matplotlib.lines import Line2D

    names = sorted({UNTRUSTED[s] for s in statuses if s in UNTRUSTED})
    if not names:
        return []
    return [
        Line2D([], [], color="0.3", ls="none", marker="o", markerfacecolor="white",
               markeredgewidth=1.5, label=f"hollow: {' or '.join(names)}")
    ]  # fmt: skip


def name_curves(
    ax,
    r: np.ndarray,
    curves: list[tuple[np.ndarray, np.ndarray]],
    abscissae: list[np.ndarray] | None = None,
) -> None:
    """Name the pressure "p" and the shear "q_x" curves of a panel.

    The pressure is named on the highest pressure curve at r = 0.5, the shear on the highest
    shear curve at its peak (not at all when every shear is zero): with each case drawn in its
    own style (:func:`series_style`), the names say which curves are the pressures.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The panel.
    r : numpy.ndarray
        Abscissa of the curves.
    curves : list of (numpy.ndarray, numpy.ndarray)
        ``(pressure, shear)`` of each case drawn, over ``r``.
    abscissae : list of numpy.ndarray, optional
        An abscissa per curve instead of ``r`` (a moving case's whole line,
        :func:`traction_line`).
    """
    xs = abscissae if abscissae is not None else [r] * len(curves)
    for which, name, where in ((0, "p", 0.5), (1, "q_x", None)):
        values = [
            (x, curve[which]) for x, curve in zip(xs, curves, strict=True)
            if np.any(np.isfinite(curve[which]))
        ]  # fmt: skip
        if not values:
            continue
        x, y = max(values, key=lambda v: float(np.nanmax(np.abs(v[1]))))
        if float(np.nanmax(np.abs(y))) == 0.0:
            continue  # no shear: nothing to name
        i = int(np.nanargmax(np.abs(y))) if where is None else int(np.argmin(np.abs(x - where)))
        ax.annotate(name, (x[i], y[i]), xytext=(5, 5), textcoords="offset points", fontsize=9,
                    fontweight="bold", gid="curve name")  # fmt: skip


def is_moving(dataset, index: dict) -> bool:
    """Whether the case at ``index`` moved (sliding, rolling): its contact is not symmetric.

    Its ``position_x_history`` (body 1's apex over body 2) is non-zero at some step; the
    dataset's radial profiles (r >= 0) then show only half of its contact.
    """
    if "position_x_history" not in dataset:
        return False
    values = np.asarray(dataset["position_x_history"].isel(index).values, dtype=float)
    return bool(np.any(np.isfinite(values) & (values != 0)))


def traction_line(out: str | Path, case_id: str, index=None):
    """A case's pressure and shear ``q_x`` along y = 0 over the whole line, from its file.

    Parameters
    ----------
    out : str or Path
        Campaign output folder.
    case_id : str
        The case.
    index : study.run.storage.CaseIndex, optional
        The folder's case index, built when omitted.

    Returns
    -------
    tuple of numpy.ndarray or None
        ``(x / a_x, pressure, shear)`` in Pa, x about body 1's last position (a moving case's
        contact centre, as the dataset's profiles are), or None when the file has no lines.
    """
    from ..run import storage

    with storage.open_case(out, case_id, index=index) as case:
        if "pressure_y0" not in case:
            return None
        x = case["x"].values.astype(float)
        if "position_x" in case:
            x = x - float(case["position_x"].values[-1])
        a = float(case.attrs["hertz_semi_axis_x"])
        return x / a, case["pressure_y0"].values, case["shear_x_y0"].values


def status_of(dataset, index: dict) -> str:
    """The status name (:data:`solver.result.STATUS_FLAGS`) of the case at ``index``."""
    from solver.result import STATUS_FLAGS

    names = {v: k for k, v in STATUS_FLAGS.items()}
    return names.get(int(dataset["status"].isel(index)), "?")


def mark_panel(ax, statuses, labels: list[str] | None = None) -> bool:
    """Mark a panel that shows untrusted cases: a red dashed frame and a hatched label.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The panel.
    statuses : list of str
        The status of each case the panel shows.
    labels : list of str, optional
        A name per case, said beside its status when the panel shows several cases.

    Returns
    -------
    bool
        Whether the panel was marked (a case is :data:`UNTRUSTED`).
    """
    bad = [(k, s) for k, s in enumerate(statuses) if s in UNTRUSTED]
    if not bad:
        return False
    if len(statuses) == 1 or labels is None:
        text = ", ".join(sorted({UNTRUSTED[s] for _, s in bad}))
    else:
        text = "\n".join(f"{labels[k]}: {UNTRUSTED[s]}" for k, s in bad)
    for spine in ax.spines.values():
        spine.set(edgecolor=STATUS_COLOUR, linewidth=2.0, linestyle="--")
    ax.text(
        0.98, 0.97, text, transform=ax.transAxes, ha="right", va="top", fontsize=7,
        color=STATUS_COLOUR, fontweight="bold", zorder=6, gid="status mark",
        bbox={"facecolor": "white", "edgecolor": STATUS_COLOUR, "hatch": "////",
              "hatchcolor": "#f5c6c6", "alpha": 0.95, "boxstyle": "square,pad=0.3",  # mpl 3.11
              "linewidth": 0.8},
    )  # fmt: skip
    return True


def status_note(statuses, marks: str = "red dashed frame, hollow markers") -> str:
    """A figure note on the untrusted cases shown, or "" when there are none.

    Parameters
    ----------
    statuses : iterable of str
        The status of every case the figure shows.
    marks : str, optional
        How the figure marks them, said in brackets.

    Returns
    -------
    str
        E.g. "1 case truncated (marked: red dashed frame)".
    """
    counts = {}
    for s in statuses:
        if s in UNTRUSTED:
            counts[UNTRUSTED[s]] = counts.get(UNTRUSTED[s], 0) + 1
    if not counts:
        return ""
    parts = [f"{n} case{'s' if n > 1 else ''} {name}" for name, n in sorted(counts.items())]
    return ", ".join(parts) + f" (marked: {marks})"


def panel_grid(
    plt, count: int, width: float, height: float, extra: float = 0.0, below: float = 0.0, **kwargs
):
    """A constrained-layout figure of ``count`` panels in at most :data:`MAX_COLUMNS` columns.

    Each panel is ``width`` x ``height`` inches; ``extra`` inches are added to the width (for a
    colour bar), ``below`` to the height (for a legend below the panels).  Returns the figure,
    the ``count`` panels in reading order and the columns.
    """
    columns = min(MAX_COLUMNS, count)
    rows = math.ceil(count / columns)
    fig, axes = plt.subplots(
        rows,
        columns,
        figsize=(width * columns + extra, height * rows + TITLE_HEIGHT + below),
        squeeze=False,
        layout="constrained",
        dpi=DPI,
        **kwargs,
    )
    fig.get_layout_engine().set(h_pad=0.08, hspace=0.04)  # a row's labels clear of the next titles
    flat = list(axes.ravel())
    for ax in flat[count:]:
        ax.set_visible(False)
    return fig, flat[:count], columns


def save(plt, fig, path: str | Path) -> None:
    """Write a figure as PNG and close it.

    The constrained layout is settled by a first draw without rendering: the first layout pass
    of a figure with many panels can let a row's axis labels run into the next row's titles.
    """
    fig.draw_without_rendering()
    fig.savefig(path, dpi=DPI)
    plt.close(fig)


def suptitle(fig, *lines: str, fontsize: float = 10) -> None:
    """A figure title of several lines, each wrapped to the figure's width."""
    import textwrap

    width = max(40, int(fig.get_figwidth() * 72 / (0.55 * fontsize)))  # ~0.55 em per character
    text = "\n".join(textwrap.fill(line, width) for line in lines if line)
    fig.suptitle(text, fontsize=fontsize)


def panel_note(
    shown: int, total: int, missing: int, noun: str, why: str = "without a finished case"
) -> str:
    """Which panels a figure shows, e.g. "all 20 cases" or "24 of 30 slices (...)"."""
    if shown == total:
        return f"all {total} {noun}"
    reasons = []
    if missing:
        reasons.append(f"{missing} {why}")
    if shown < total - missing:
        reasons.append(f"only the first {MAX_PANELS} in axis order: {MAX_PANELS} panels at most")
    return f"{shown} of {total} {noun} ({'; '.join(reasons)})"


def slice_noun(dataset, mesh: list[str], finest: bool) -> str:
    """What one panel shows, in words: a slice of the axes that are not ``mesh``."""
    others = [d for d in analysis.axis_dims(dataset) if d not in mesh]
    if not mesh:
        return "cases"
    what = "finest mesh" if finest else "every mesh"
    return f"slices over {', '.join(others)} ({what} of each)" if others else f"meshes ({what})"


def log_subs(values) -> tuple[float, ...]:
    """Mantissas of the labelled ticks of a log axis: fewer the more decades the data span."""
    values = np.asarray(values, dtype=float)
    values = values[np.isfinite(values) & (values > 0)]
    decades = np.log10(values.max() / values.min()) if len(values) else 0.0
    if decades < 1.2:
        return (1.0, 2.0, 3.0, 5.0, 7.0)
    return (1.0, 2.0, 5.0) if decades < 2.5 else (1.0,)


def log_ticks(axis, values) -> None:
    """Readable tick labels on a log axis: :func:`log_tick_values` as plain numbers."""
    from matplotlib.ticker import FixedLocator, FuncFormatter, NullFormatter

    axis.set_major_locator(FixedLocator(log_tick_values(values)))
    axis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:.3g}"))
    axis.set_minor_formatter(NullFormatter())


def log_tick_values(values) -> list[float]:
    """Tick values within the range of positive ``values`` on a log scale.

    Round mantissas (:func:`log_subs`) inside the range; when fewer than two fall inside it,
    its ends rounded inwards to two significant digits, and a round value between them when it
    is not too near either.
    """
    values = np.asarray(values, dtype=float)
    values = values[np.isfinite(values) & (values > 0)]
    if not len(values):
        return []
    lo, hi = float(np.min(values)), float(np.max(values))
    decades = range(math.floor(math.log10(lo)), math.floor(math.log10(hi)) + 1)
    ticks = [float(f"{m * 10.0**d:.3g}") for d in decades for m in log_subs(values)]
    inside = [t for t in ticks if lo * (1 - 1e-9) <= t <= hi * (1 + 1e-9)]
    if len(inside) >= 2 or hi == lo:
        return inside or [lo]
    scale = 10.0 ** (math.floor(math.log10(hi)) - 1)
    ends = [
        float(f"{math.ceil(lo / scale) * scale:.3g}"),
        float(f"{math.floor(hi / scale) * scale:.3g}"),
    ]
    ends = ends if ends[0] < ends[1] else [lo, hi]
    gap = 0.2 * math.log(ends[1] / ends[0])  # a round value too near an end would overlap it
    return sorted(ends + [t for t in inside if min(abs(math.log(t / e)) for e in ends) >= gap])
