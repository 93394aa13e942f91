"""Figure and table helpers of the report: panel grids, titles, notes, log ticks, markdown.

The bottom of :mod:`study.report`: the elastic, plastic and cyclic sections draw with these.
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
def title(labels: dict, width: int = 30) -> str:
    """A panel title from slice labels: one line when short, else one ``name=value`` per line."""
    parts = [f"{k}={fmt(v)}" for k, v in labels.items()]
    text = ", ".join(parts)
    return text if len(text) <= width else "\n".join(parts)


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
    its ends rounded inwards to two significant digits.
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
    return sorted(set(inside) | set(ends))
