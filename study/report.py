"""Campaign report: convergence, sensitivity and speed-versus-error tables, figures, Markdown.

``python -m study report OUT [--no-plots]`` reads ``OUT/<name>.nc`` (assembling it first when
it is missing) and writes next to it:

- ``OUT/report.md``: provenance, the tables of :mod:`study.analysis` and links to the figures;
- ``OUT/<name>_convergence_<mesh axis>.png``: log-log error against cells per side, with the
  fitted orders;
- ``OUT/<name>_speed_error.png``: wall time and peak memory against the error, Pareto front;
- ``OUT/<name>_profiles.png``: pressure and shear along y = 0 against r / a;
- ``OUT/<name>_stick_slip.png``: contact-state maps from the per-case files.

Plots need matplotlib (the ``plot`` extra); it is imported lazily with the Agg backend, and the
report is written without figures when it is missing.
"""

from __future__ import annotations

import argparse
import datetime
import hashlib
import math
import os
import platform
import sys
from pathlib import Path

import numpy as np

from solver.result import STATUS_FLAGS

from . import analysis

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
_STATE_NAMES = ("separated", "stick", "slip")
#: Table columns printed with 9 significant digits (values close to each other).
VALUE_COLUMNS = ("value", "finest", "extrapolated", "error_bar", "reference")


# -- helpers -------------------------------------------------------------------------------------
def _pyplot():
    """Matplotlib's pyplot on the Agg backend, or None when matplotlib is missing."""
    try:
        import matplotlib
    except ImportError:
        return None
    matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt

    return plt


def _label(labels: dict) -> str:
    return ", ".join(f"{k}={_fmt(v)}" for k, v in labels.items()) or "all cases"


def _fmt(value, digits: int = 5) -> str:
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
        cells = (_fmt(row[c], 9 if c in VALUE_COLUMNS else 5) for c in columns)
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def _sha256(path: Path) -> str:
    try:
        return hashlib.sha256(path.read_bytes()).hexdigest()
    except OSError:
        return ""


def _locate(out: str | Path) -> tuple[Path, Path]:
    """(output folder, dataset path); assembles the dataset when it is missing."""
    from . import storage

    out = Path(out)
    if out.is_file() and out.suffix == ".nc":
        return out.parent, out
    campaign = storage.read_campaign(out)
    path = storage.dataset_path(out, campaign.name)
    if not path.exists():
        from .assemble import assemble_to_file

        path = assemble_to_file(out, campaign)
    return out, path


def _units(dataset, name: str) -> str:
    if name in dataset.variables:
        return str(dataset[name].attrs.get("units", analysis.QUANTITIES.get(name, ("",))[0]))
    return analysis.QUANTITIES.get(name, ("",))[0]


# -- figures -------------------------------------------------------------------------------------
def _title(labels: dict, width: int = 30) -> str:
    """A panel title from slice labels: one line when short, else one ``name=value`` per line."""
    parts = [f"{k}={_fmt(v)}" for k, v in labels.items()]
    text = ", ".join(parts)
    return text if len(text) <= width else "\n".join(parts)


def _panel_grid(
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


def _save(plt, fig, path: str | Path) -> None:
    """Write a figure as PNG and close it.

    The constrained layout is settled by a first draw without rendering: the first layout pass
    of a figure with many panels can let a row's axis labels run into the next row's titles.
    """
    fig.draw_without_rendering()
    fig.savefig(path, dpi=DPI)
    plt.close(fig)


def _suptitle(fig, *lines: str, fontsize: float = 10) -> None:
    """A figure title of several lines, each wrapped to the figure's width."""
    import textwrap

    width = max(40, int(fig.get_figwidth() * 72 / (0.55 * fontsize)))  # ~0.55 em per character
    text = "\n".join(textwrap.fill(line, width) for line in lines if line)
    fig.suptitle(text, fontsize=fontsize)


def _panel_note(
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


def _slice_noun(dataset, mesh: list[str], finest: bool) -> str:
    others = [d for d in analysis.axis_dims(dataset) if d not in mesh]
    if not mesh:
        return "cases"
    what = "finest mesh" if finest else "every mesh"
    return f"slices over {', '.join(others)} ({what} of each)" if others else f"meshes ({what})"


def _log_subs(values) -> tuple[float, ...]:
    """Mantissas of the labelled ticks of a log axis: fewer the more decades the data span."""
    values = np.asarray(values, dtype=float)
    values = values[np.isfinite(values) & (values > 0)]
    decades = np.log10(values.max() / values.min()) if len(values) else 0.0
    if decades < 1.2:
        return (1.0, 2.0, 3.0, 5.0, 7.0)
    return (1.0, 2.0, 5.0) if decades < 2.5 else (1.0,)


def _log_ticks(axis, values) -> None:
    """Readable tick labels on a log axis: :func:`_log_tick_values` as plain numbers."""
    from matplotlib.ticker import FixedLocator, FuncFormatter, NullFormatter

    axis.set_major_locator(FixedLocator(_log_tick_values(values)))
    axis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:.3g}"))
    axis.set_minor_formatter(NullFormatter())


def _log_tick_values(values) -> list[float]:
    """Tick values within the range of positive ``values`` on a log scale.

    Round mantissas (:func:`_log_subs`) inside the range; when fewer than two fall inside it,
    its ends rounded inwards to two significant digits.
    """
    values = np.asarray(values, dtype=float)
    values = values[np.isfinite(values) & (values > 0)]
    if not len(values):
        return []
    lo, hi = float(np.min(values)), float(np.max(values))
    decades = range(math.floor(math.log10(lo)), math.floor(math.log10(hi)) + 1)
    ticks = [float(f"{m * 10.0**d:.3g}") for d in decades for m in _log_subs(values)]
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


def plot_convergence(dataset, mesh_dim: str, path: str | Path) -> Path | None:
    """Log-log relative error against cells per side, one panel per quantity.

    The error is relative to the closed form where one applies, else to the Richardson
    extrapolation of the slice; dashed lines are the fits ``C h^p`` with the observed order.
    Panels wrap into at most :data:`MAX_COLUMNS` columns; at most :data:`MAX_LINES` slices are
    drawn per panel (the title says so when there are more).

    Parameters
    ----------
    dataset : xarray.Dataset
        Campaign dataset.
    mesh_dim : str
        Mesh axis.
    path : str or Path
        PNG to write.

    Returns
    -------
    Path or None
        The PNG, or None without matplotlib or data.
    """
    plt = _pyplot()
    dataset = analysis.with_derived(dataset)
    names = analysis.quantities(dataset)
    if plt is None or not names:
        return None
    from matplotlib.ticker import FixedLocator, FuncFormatter, NullLocator

    refs = analysis.closed_forms(dataset)
    slices = list(analysis._slices(dataset, [mesh_dim]))
    # a few slices: a legend per panel with the fitted orders; many: one legend of the slices
    # below the panels (the orders are in the report's tables)
    shared = len(slices) > SHARED_LEGEND_SLICES
    below = LEGEND_ROW * math.ceil(min(len(slices), MAX_LINES) / 3) + 0.2 if shared else 0.0
    fig, axes, _ = _panel_grid(plt, len(names), 4.2, 3.6, below=below)
    colours = {}
    for ax, name in zip(axes, names, strict=True):
        table = analysis.convergence_table(dataset, name, mesh_dim)
        basis = "closed form" if name in refs else "extrapolated"
        column = "rel_error" if name in refs else "rel_error_extrapolated"
        for labels, _ in slices[:MAX_LINES]:
            rows = table
            for key, value in labels.items():
                rows = rows[rows[key] == value]
            err = np.abs(rows[column].to_numpy(dtype=float))
            n = rows["n"].to_numpy(dtype=float)
            ok = np.isfinite(err) & (err > 0)
            if not np.any(ok):
                continue
            label = _label(labels) or "cases"
            many = min(len(slices), MAX_LINES) > 10
            index = len(colours)
            colour = colours.setdefault(
                label, plt.get_cmap("tab20")(index % 20) if many else f"C{index}"
            )
            ax.loglog(n[ok], err[ok], "o-", color=colour, label=None if shared else label)
            order, constant = analysis.observed_order(
                rows["h_over_a"].to_numpy(dtype=float)[ok], err[ok]
            )
            if np.isfinite(order):
                h = rows["h_over_a"].to_numpy(dtype=float)[ok]
                ax.loglog(
                    n[ok],
                    constant * h**order,
                    "--",
                    color=colour,
                    label=None if shared else f"fit, order {order:.2f}",
                )
        ns = np.unique(analysis.mesh_coordinate(dataset, mesh_dim).values.astype(float))
        ns = ns[:: max(1, math.ceil(len(ns) / 8))]  # at most 8 labels
        ax.xaxis.set_major_locator(FixedLocator(ns))
        ax.xaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
        ax.xaxis.set_minor_locator(NullLocator())
        ax.set_xlabel(f"{analysis.mesh_meaning(dataset, mesh_dim)[0]} {mesh_dim} (1)")
        ax.set_ylabel(f"|rel. error| vs {basis} (1)")
        ax.set_title(analysis.QUANTITIES.get(name, (None, name))[1], fontsize=10)
        ax.grid(True, which="both", alpha=0.3)
        if not ax.lines:  # every case equal to its extrapolation (e.g. counted in whole cells)
            ax.text(0.5, 0.5, f"no change along {mesh_dim}", transform=ax.transAxes,
                    ha="center", va="center", fontsize=9, color="0.4")  # fmt: skip
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=7)
    if shared:
        from matplotlib.lines import Line2D

        handles = [Line2D([], [], color=c, marker="o", label=k) for k, c in colours.items()]
        handles.append(Line2D([], [], color="k", ls="--", label="fits C h^p (orders: report.md)"))
        fig.legend(handles=handles, loc="outside lower center", ncols=3, fontsize=7)
    title = f"{dataset.attrs.get('campaign', '')}: convergence along {mesh_dim}"
    _suptitle(fig, title, _convergence_note(dataset, mesh_dim) if len(slices) > MAX_LINES else "")
    _save(plt, fig, path)
    return Path(path)


def _convergence_note(dataset, mesh_dim: str) -> str:
    slices = len(list(analysis._slices(dataset, [mesh_dim])))
    if slices <= MAX_LINES:
        return f"all {slices} slice(s), every quantity"
    return f"the first {MAX_LINES} of {slices} slices in axis order, every quantity"


def speed_error_note(table) -> str:
    """Which cases :func:`plot_speed_error` draws (those with a finite, non-zero error)."""
    if len(table) == 0:
        return "no finished case"
    error = table["error"].to_numpy(dtype=float)
    drawn = int(np.count_nonzero(np.isfinite(error) & (error > 0)))
    if drawn == len(table):
        return f"all {drawn} finished cases"
    return (
        f"{drawn} of {len(table)} finished cases; the others have no finite non-zero error "
        "(no closed form, no mesh axis to extrapolate along)"
    )


def plot_speed_error(table, title: str, path: str | Path) -> Path | None:
    """Wall time and peak memory against the error of every case, Pareto front marked.

    Points are coloured by the grid cells of the case when these differ (colour bar in cells);
    when every case has the same grid the title gives its size instead.

    Parameters
    ----------
    table : pandas.DataFrame
        :func:`study.analysis.speed_error_table`.
    title : str
        Campaign name for the title.
    path : str or Path
        PNG to write.

    Returns
    -------
    Path or None
        The PNG, or None without matplotlib or usable errors.
    """
    plt = _pyplot()
    if plt is None or len(table) == 0:
        return None
    ok = np.isfinite(table["error"].to_numpy(dtype=float)) & (table["error"] > 0)
    if not np.any(ok):
        return None
    from matplotlib.colors import LogNorm

    data = table[ok]
    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4.2), layout="constrained", dpi=DPI)
    cells = data["cells"].to_numpy(dtype=float)
    known = cells[cells > 0]
    varying = len(np.unique(known)) > 1
    colour = {"c": cells, "cmap": "viridis", "norm": LogNorm(known.min(), known.max())}
    for ax, column, xlabel, xscale in (
        (left, "wall_time", "solve wall time (s)", "log"),
        (right, "peak_rss_mib", "peak resident memory (MiB)", "linear"),
    ):
        x = data[column].to_numpy(dtype=float)
        y = data["error"].to_numpy(dtype=float)
        style = colour if varying else {"color": "C0"}
        scatter = ax.scatter(x, y, zorder=3, **style)
        front = analysis.pareto_front(x, y)
        order = np.argsort(x[front])
        ax.plot(x[front][order], y[front][order], "r-", lw=1.2, label="Pareto front", zorder=2)
        ax.scatter(x[front], y[front], s=90, facecolors="none", edgecolors="r", zorder=4)
        ax.set_xscale(xscale)
        ax.set_yscale("log")
        if xscale == "log":
            _log_ticks(ax.xaxis, x)
        ax.set_xlabel(xlabel)
        ax.set_ylabel("largest |relative error| (1)")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    if varying:
        bar = fig.colorbar(scatter, ax=right, label="grid cells (nx ny [nz])")
        ticks = _log_tick_values(known)
        bar.set_ticks(ticks, labels=[f"{t:g}" for t in ticks])
        bar.minorticks_off()
    grid = "" if varying or not len(known) else f", every case {int(known[0])} cells"
    basis = data["error_basis"].iloc[0]
    _suptitle(fig, f"{title}: speed versus error ({basis}{grid})", speed_error_note(table))
    _save(plt, fig, path)
    return Path(path)


def _cattaneo_shear(r: np.ndarray, mu: float, p0: float, ratio: float) -> np.ndarray:
    """Cattaneo-Mindlin shear traction along a radius (r over a)."""
    outer = mu * p0 * np.sqrt(np.clip(1.0 - r**2, 0.0, None))
    inner = mu * p0 * ratio * np.sqrt(np.clip(1.0 - (r / ratio) ** 2, 0.0, None))
    return outer - np.where(r < ratio, inner, 0.0)


def profile_panels(dataset) -> tuple[list, str]:
    """The panels of :func:`plot_profiles` and a note saying which slices they show.

    Returns
    -------
    (list, str)
        ``(labels, isel, cases)`` per panel (slices of the non-mesh axes with a finished case,
        at most :data:`MAX_PANELS`; ``cases`` the finished ones along the mesh axes), and the
        note (e.g. "all 20 cases").
    """
    mesh = analysis.mesh_axes(dataset)
    usable = analysis._usable(dataset)
    slices = list(analysis._slices(dataset, mesh))
    missing = len(slices) - int(usable.any(dim=mesh).sum()) if mesh else int((~usable).sum())
    shown = []
    for labels, isel in slices:
        if len(shown) >= MAX_PANELS:
            break
        ok = usable.isel(isel)
        cases = [c for c in analysis._slices(dataset.isel(isel), []) if bool(ok.isel(c[1]))]
        if cases:
            shown.append((labels, isel, cases))
    noun = _slice_noun(dataset, mesh, False)
    note = _panel_note(len(shown), len(slices), missing, noun)
    if any(len(cases) > MAX_LINES for _, _, cases in shown):
        note += f"; the first {MAX_LINES} meshes per panel"
    return shown, note


def plot_profiles(dataset, path: str | Path) -> Path | None:
    """Pressure and shear along y = 0 against r / a, one panel per slice of the non-mesh axes.

    Each panel shows the finished cases along the mesh axes (or the single case): pressure
    solid, shear ``q_x`` dashed in the same colour, with the Hertz pressure and the
    Cattaneo-Mindlin shear as thick grey lines where they apply; one colour per mesh, the same
    in every panel (legend below the panels).  Panels wrap into at most
    :data:`MAX_COLUMNS` columns; the title says which slices are shown
    (:func:`profile_panels`).

    Parameters
    ----------
    dataset : xarray.Dataset
        Campaign dataset.
    path : str or Path
        PNG to write.

    Returns
    -------
    Path or None
        The PNG, or None without matplotlib or finished cases.
    """
    plt = _pyplot()
    if plt is None or "pressure_profile" not in dataset:
        return None
    panels, note = profile_panels(dataset)
    if not panels:
        return None
    from matplotlib.lines import Line2D
    from matplotlib.ticker import MultipleLocator

    refs = analysis.closed_forms(analysis.with_derived(dataset))
    status = dataset["status"]
    p_ref = refs["max_pressure"].broadcast_like(status) if "max_pressure" in refs else None
    c_ref = refs["stick_ratio"].broadcast_like(status) if "stick_ratio" in refs else None
    mu_all = analysis.friction_coefficient(dataset).broadcast_like(status)
    r = dataset["r_over_a"].values
    # one colour per mesh (the same in every panel), named in the legend below the panels
    meshes = [label for label, _ in analysis._slices(dataset.isel(panels[0][1]), [])]
    entries = 4 + (len(meshes) if len(meshes) > 1 else 0)  # legend rows of 6 entries
    fig, axes, columns = _panel_grid(
        plt, len(panels), 4.0, 3.0, below=LEGEND_ROW * -(-entries // 6)
    )
    grey = {"color": "0.65", "lw": 3.0, "zorder": 1}
    drawn = {"Hertz p": False, "Cattaneo-Mindlin q_x": False}
    names = [_label(label) if label else "" for label in meshes]
    colours = [
        f"C{j}" if len(meshes) <= 10 else plt.get_cmap("viridis")(j / (len(meshes) - 1))
        for j in range(len(meshes))
    ]
    used = set()
    for k, (ax, (labels, isel, cases)) in enumerate(zip(axes, panels, strict=True)):
        sub = dataset.isel(isel)
        for case_labels, case_isel in cases[:MAX_LINES]:
            case = sub.isel(case_isel)
            j = names.index(_label(case_labels)) if case_labels else 0
            used.add(j)
            colour = colours[j]
            ax.plot(r, case["pressure_profile"].values / 1e9, "-", color=colour)
            ax.plot(r, case["shear_x_profile"].values / 1e9, "--", color=colour)
        index = {**isel, **cases[0][1]}
        p0 = float(p_ref.isel(index)) if p_ref is not None else math.nan
        if np.isfinite(p0):
            ax.plot(r, p0 * np.sqrt(np.clip(1.0 - r**2, 0.0, None)) / 1e9, "-", **grey)
            drawn["Hertz p"] = True
            ratio = float(c_ref.isel(index)) if c_ref is not None else math.nan
            mu = float(mu_all.isel(index))
            if np.isfinite(ratio) and mu > 0 and ratio < 1:
                first = sub.isel(cases[0][1])
                sign = np.sign(np.nanmean(first["shear_x_profile"].values)) or 1.0
                shear = sign * _cattaneo_shear(r, mu, p0, ratio) / 1e9
                ax.plot(r, shear, "--", **grey)
                drawn["Cattaneo-Mindlin q_x"] = True
        ax.set_title(_title(labels), fontsize=8)
        ax.set_xlim(0.0, float(r[-1]))
        ax.xaxis.set_major_locator(MultipleLocator(0.5))
        ax.set_xlabel("r / a (1)")
        if k % columns == 0:
            ax.set_ylabel("traction (GPa)")
        ax.grid(True, alpha=0.3)
    styles = [
        Line2D([], [], color="k", ls="-", label="pressure p"),
        Line2D([], [], color="k", ls="--", label="shear q_x"),
    ]
    styles += [
        Line2D([], [], ls="-" if name.startswith("Hertz") else "--", label=name, **grey)
        for name, shown in drawn.items()
        if shown
    ]
    if len(meshes) > 1:
        styles += [Line2D([], [], color=colours[j], label=names[j]) for j in sorted(used)]
    columns = min(len(styles), 6)
    fig.legend(handles=styles, loc="outside lower center", ncols=columns, fontsize=8)
    _suptitle(
        fig,
        f"{dataset.attrs.get('campaign', '')}: traction along y = 0, x >= 0 (r / a: over the "
        "Hertz semi-axis)",
        note,
    )
    _save(plt, fig, path)
    return Path(path)


def stick_slip_panels(dataset, cases_dir: str | Path) -> tuple[list, str]:
    """The panels of :func:`plot_stick_slip` and a note saying which slices they show.

    Returns
    -------
    (list, str)
        ``(labels, index, file)`` per panel (the finest mesh of each slice of the non-mesh
        axes whose case finished and has a ``contact_state`` field, at most
        :data:`MAX_PANELS`) and the note (slices whose finest case did not finish, or has no
        file or field, count as missing).
    """
    import xarray as xr

    mesh = analysis.mesh_axes(dataset)
    usable = analysis._usable(dataset)
    slices = list(analysis._slices(dataset, mesh))
    found, missing = [], 0
    for labels, isel in slices:
        index = analysis.finest_index(dataset, isel)
        if not bool(usable.isel(index)):
            missing += 1
            continue
        if len(found) >= MAX_PANELS:
            continue  # finished, not shown (the note says so)
        file = Path(cases_dir) / f"{dataset['case_id'].isel(index).item()}.nc"
        has_state = False
        if file.exists():
            with xr.open_dataset(file) as case:
                has_state = "contact_state" in case
        if has_state:
            found.append((labels, index, file))
        else:
            missing += 1
    noun = _slice_noun(dataset, mesh, True)
    why = "without a finished case with a contact-state map"
    return found, _panel_note(len(found), len(slices), missing, noun, why)


def plot_stick_slip(dataset, cases_dir: str | Path, path: str | Path) -> Path | None:
    """Contact-state maps (separated / stick / slip) from the per-case files.

    One panel per slice of the non-mesh axes, on the finest mesh of the slice, in at most
    :data:`MAX_COLUMNS` columns and :data:`MAX_PANELS` panels (the title says which slices are
    shown, :func:`stick_slip_panels`); the Hertz radius (dashed) and the Cattaneo stick radius
    (dotted) are drawn as circles.

    Parameters
    ----------
    dataset : xarray.Dataset
        Campaign dataset.
    cases_dir : str or Path
        Folder of the per-case files (``OUT/cases``).
    path : str or Path
        PNG to write.

    Returns
    -------
    Path or None
        The PNG, or None without matplotlib or contact-state fields.
    """
    plt = _pyplot()
    if plt is None:
        return None
    panels, note = stick_slip_panels(dataset, cases_dir)
    if not panels:
        return None
    import xarray as xr
    from matplotlib.colors import ListedColormap
    from matplotlib.ticker import MultipleLocator

    refs = analysis.closed_forms(analysis.with_derived(dataset))
    c_ref = None
    if "stick_ratio" in refs:
        c_ref = refs["stick_ratio"].broadcast_like(dataset["status"])
    mesh = analysis.mesh_axes(dataset)
    fig, axes, columns = _panel_grid(plt, len(panels), 3.0, 3.0, extra=1.0)
    cmap = ListedColormap(["#eeeeee", "#2b83ba", "#fdae61"])
    t = np.linspace(0, 2 * np.pi, 200)
    dotted = False
    for k, (ax, (labels, index, file)) in enumerate(zip(axes, panels, strict=True)):
        with xr.open_dataset(file) as case:
            a = float(case.attrs.get("hertz_semi_axis_x", case.attrs.get("hertz_radius", 1.0)))
            x, y = case["x"].values / a, case["y"].values / a
            state = case["contact_state"].values
        dx = x[1] - x[0] if len(x) > 1 else 1.0
        dy = y[1] - y[0] if len(y) > 1 else 1.0
        image = ax.imshow(
            state.T,
            origin="lower",
            extent=(x[0] - dx / 2, x[-1] + dx / 2, y[0] - dy / 2, y[-1] + dy / 2),
            cmap=cmap,
            vmin=-0.5,
            vmax=2.5,
            interpolation="nearest",
        )
        ax.plot(np.cos(t), np.sin(t), "k--", lw=0.8)
        ratio = float(c_ref.isel(index)) if c_ref is not None else math.nan
        if np.isfinite(ratio) and ratio < 1:
            ax.plot(ratio * np.cos(t), ratio * np.sin(t), "k:", lw=1.2)
            dotted = True
        n_label = {d: dataset[d].values[index[d]] for d in mesh}
        ax.set_title(_title({**labels, **n_label}), fontsize=8)
        ax.xaxis.set_major_locator(MultipleLocator(1.0))
        ax.yaxis.set_major_locator(MultipleLocator(1.0))
        ax.set_xlabel("x / a (1)")
        if k % columns == 0:
            ax.set_ylabel("y / a (1)")
    rows = math.ceil(len(axes) / columns)
    bar = fig.colorbar(image, ax=axes, ticks=[0, 1, 2], shrink=min(0.9, 1.8 / rows))
    bar.ax.set_yticklabels(_STATE_NAMES)
    _suptitle(
        fig,
        f"{dataset.attrs.get('campaign', '')}: contact state{' (finest mesh)' if mesh else ''}",
        "dashed circle: Hertz radius a"
        + ("; dotted: Cattaneo-Mindlin stick radius c" if dotted else ""),
        note,
    )
    _save(plt, fig, path)
    return Path(path)


# -- report --------------------------------------------------------------------------------------
def provenance(dataset, out: Path) -> dict:
    """Provenance of the report: versions, campaign hashes, date, machine."""
    import solver

    source = Path(dataset.attrs.get("campaign_source", "") or "")
    return {
        "slipstick version": solver.__version__,
        "dataset version": dataset.attrs.get("slipstick_version", ""),
        "git commit": dataset.attrs.get("git_hash", "") or "(unknown)",
        "campaign file": str(source) if str(source) else "(table)",
        "campaign file sha256": (_sha256(source) if source.is_file() else "") or "(file not found)",
        "campaign.json sha256": _sha256(out / "campaign.json") or "(missing)",
        "dataset history": dataset.attrs.get("history", ""),
        "report date (UTC)": datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%dT%H:%M:%SZ"),
        "machine": f"{platform.node()} ({platform.platform()}, {os.cpu_count()} CPUs)",
        "python": f"{sys.version.split()[0]}, numpy {np.__version__}",
    }


def build_report(out: str | Path, plots: bool = True) -> Path:
    """Write ``OUT/report.md`` (and the figures) for a campaign output folder.

    Parameters
    ----------
    out : str or Path
        Campaign output folder (or the assembled ``.nc`` dataset inside it).
    plots : bool
        Draw the PNG figures (needs matplotlib; skipped with a note when it is missing).

    Returns
    -------
    Path
        The Markdown report.
    """
    import xarray as xr

    from . import storage

    out, path = _locate(out)
    with xr.open_dataset(path, engine=storage.ENGINE) as raw:
        dataset = analysis.with_derived(raw.load())
    name = str(dataset.attrs.get("campaign", path.stem))
    mesh = analysis.mesh_axes(dataset)
    names = analysis.quantities(dataset)
    refs = analysis.closed_forms(dataset)
    lines = [f"# Campaign report: {name}", ""]
    if dataset.attrs.get("summary"):
        lines += [f"{dataset.attrs['summary']}", ""]
    lines += ["## Provenance", ""]
    lines += [f"- **{k}**: {v}" for k, v in provenance(dataset, out).items()]
    lines += ["", "## Campaign", ""]
    lines.append(f"- dataset: `{path.name}`")
    lines.append(
        "- axes: "
        + ", ".join(
            f"`{d}` ({dataset.sizes[d]}: {_values(dataset, d)})"
            for d in analysis.axis_dims(dataset)
        )
    )
    counts = ", ".join(f"{flag} {dataset.attrs.get(f'cases_{flag}', '?')}" for flag in STATUS_FLAGS)
    lines.append(f"- cases: {dataset.attrs.get('cases_total', '?')} ({counts})")
    lines.append(f"- closed forms: {analysis.scene(dataset)}")
    lines.append(f"- mesh axes: {', '.join(mesh) or 'none'}")
    lines.append("- quantities: " + ", ".join(f"{q} ({_units(dataset, q)})" for q in names))
    lines.append("")

    figures: list[tuple[str, Path, str]] = []
    plt = _pyplot() if plots else None
    if plots and plt is None:
        lines += ["_matplotlib is not installed: no figures (pip install slipstick[plot])._", ""]

    for dim in mesh:
        noun, meaning = analysis.mesh_meaning(dataset, dim)
        lines += [f"## Convergence along `{dim}` ({noun})", ""]
        lines += [
            f"{meaning}; `n` is the count.  `order_fit`: fit of",
            "v = v* + C h^p over all meshes; `extrapolated`: Richardson from the two finest meshes",
            "with that order (order 2 when the fit hits its bounds, `fit_at_bound`), converged",
            "value `extrapolated` +- `error_bar` (= |extrapolated - finest|);",
            "`order_finest`: log-log fit of |v - v_finest| vs h; `order_reference`: log-log fit",
            "of |v - closed form| vs h.  Relative errors are signed.",
            "",
        ]
        for q in names:
            units = _units(dataset, q)
            lines += [f"### {analysis.QUANTITIES.get(q, ('', q))[1]} (`{q}`, {units})", ""]
            lines += ["Summary per slice:", ""]
            lines.append(markdown_table(analysis.convergence_summary(dataset, q, dim)))
            lines += ["Per mesh:", ""]
            table = analysis.convergence_table(dataset, q, dim)
            keep = [c for c in table.columns if c not in ("extrapolated",)]
            lines.append(markdown_table(table[keep]))
        if plt is not None:
            png = plot_convergence(dataset, dim, out / f"{name}_convergence_{dim}.png")
            if png:
                note = _convergence_note(dataset, dim)
                figures.append((f"Convergence along {dim}", png, note))
                lines += [f"![convergence along {dim}]({png.name})", ""]

    sensitivity = analysis.sensitivity_axes(dataset)
    if sensitivity:
        lines += ["## Sensitivities", ""]
        lines += [
            "Finite differences on the finest mesh (central inside, one-sided at the ends);",
            "`elasticity` = x / q dq/dx.",
            "",
        ]
        for axis in sensitivity:
            for q in names:
                table = analysis.sensitivity_table(dataset, q, axis)
                lines += [f"### d `{q}` / d `{axis}` ({_units(dataset, q)} per unit of {axis})", ""]
                lines.append(markdown_table(table))

    lines += ["## Speed versus error", ""]
    speed = analysis.speed_error_table(dataset)
    basis = "closed forms" if refs else "Richardson-extrapolated values"
    lines += [
        f"Errors relative to the {basis} (`err_*`, signed); `error` is the largest absolute one;",
        "`pareto` marks the cases no other case beats in both wall time and error.  Wall time is",
        "the solve time of the case (it includes FFTW planning for the first case of a size on a",
        "rank); peak memory is the process's peak resident set during the case (Linux).",
        "",
    ]
    lines.append(markdown_table(speed))
    if plt is not None:
        png = plot_speed_error(speed, name, out / f"{name}_speed_error.png")
        if png:
            note = speed_error_note(speed)
            figures.append(("Speed versus error", png, note))
            lines += [f"![speed versus error]({png.name})", "", f"Shown: {note}.", ""]
        png = plot_profiles(dataset, out / f"{name}_profiles.png")
        if png:
            note = profile_panels(dataset)[1]
            figures.append(("Traction profiles", png, note))
            lines += ["## Profiles", "", f"![profiles]({png.name})", "", f"Shown: {note}.", ""]
        cases = storage.cases_dir(out)
        png = plot_stick_slip(dataset, cases, out / f"{name}_stick_slip.png")
        if png:
            note = stick_slip_panels(dataset, cases)[1]
            figures.append(("Stick/slip maps", png, note))
            lines += ["## Stick and slip", "", f"![stick and slip]({png.name})", ""]
            lines += [f"Shown: {note}.", ""]
    if analysis.is_plastic(dataset):
        from . import report_plastic

        lines += report_plastic.section(dataset, out, name, plt, figures)
    if "cycle" in dataset.dims:
        from . import report_cycles

        lines += report_cycles.section(dataset, out, name, plt, figures)
    if figures:
        lines += ["## Figures", ""]
        lines += [f"- {title}: `{png.name}` ({note})" for title, png, note in figures]
        lines.append("")
    report = out / "report.md"
    storage.atomic_write_text(report, "\n".join(lines))
    return report


def _values(dataset, dim: str) -> str:
    values = dataset[dim].values if dim in dataset.coords else range(dataset.sizes[dim])
    return ", ".join(_fmt(v.item() if hasattr(v, "item") else v) for v in values)


# -- command line --------------------------------------------------------------------------------
def add_parser(subparsers) -> argparse.ArgumentParser:
    """Add the ``report`` subcommand to an :mod:`argparse` subparsers object."""
    parser = subparsers.add_parser(
        "report",
        help="convergence, sensitivity and speed-versus-error report of a campaign",
        description="Write OUT/report.md with convergence, sensitivity and speed-versus-error "
        "tables, and PNG figures next to the dataset (matplotlib, the 'plot' extra).",
    )
    parser.add_argument("out", metavar="OUT", help="campaign output folder (or its .nc dataset)")
    parser.add_argument("--no-plots", action="store_true", help="write the tables only")
    return parser


def main(args: argparse.Namespace | list[str] | None = None) -> int:
    """Run the ``report`` subcommand; returns the exit status.

    Parameters
    ----------
    args : argparse.Namespace or list of str, optional
        Parsed arguments (``out``, ``no_plots``), or a command line after ``report``.
    """
    if not isinstance(args, argparse.Namespace):
        parser = argparse.ArgumentParser(prog="python -m study")
        add_parser(parser.add_subparsers(dest="command", required=True))
        args = parser.parse_args(["report", *(args or [])])
    report = build_report(args.out, plots=not args.no_plots)
    print(f"report {report}")
    return 0
