"""The elastic-plastic part of a campaign report: a table and figures like the paper's.

:func:`section` adds to ``report.md`` (campaigns with an elastic-plastic body):

- a table of the plastic response per case (finest mesh and most load steps of each slice):
  p_max / p_H, contact radius, stick radius, maximum plastic strain and its depth, plastic
  zone depth and the residual dent, normalised by the Hertz solution like the paper;
- ``<name>_plastic_profiles.png`` (paper figs. 2 and 5): pressure and shear along y = 0
  over r / a (a: the Hertz semi-axis along x, a_H for a sphere), the cases along one axis
  overlaid (the bodies of a pair axis, else the friction coefficient) each in its own
  colour, marker and line style, with the stick and slip zones along y = 0 marked as bars
  under the curves;
- ``<name>_load_curves.png`` (paper figs. 3 and 4), with a load axis: maximum pressure, maximum
  plastic strain and its depth against the Hertz pressure;
- ``<name>_plastic_sections.png`` (paper fig. 6): the equivalent plastic strain in the x-z
  plane through the contact axis, one panel per case, one colour scale, the maximum marked.

Cases that finished but are not converged or truncated are drawn and marked in every figure
(hollow markers, a red dashed panel frame and label: :func:`.figures.mark_panel`).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from solver.result import SLIP, STATUS_FLAGS, STICK

from .. import analysis
from . import figures, tables

#: Keys of a swept load (the load curves' abscissa is the case's Hertz pressure).
LOAD_KEYS = ("hertz_pressure", "normal_force")
#: Columns of :func:`plastic_table`: name -> (per-case scalar, divided by, how it is shown).  The
#: report's headers add the scalar's reduction declared in :mod:`solver.variables`
#: (:func:`column_labels`), its description the declared long name.
COLUMNS = {
    "p_max/p_H": ("max_pressure", "hertz_pressure", "over the Hertz pressure p_H"),
    "a/a_H": ("contact_radius", "hertz_radius", "equivalent radius sqrt(A / pi) over a_H"),
    "c/a_H": ("stick_radius", "hertz_radius", "equivalent radius sqrt(A / pi) over a_H"),
    "ep_max_%": ("max_plastic_strain", None, "in %"),
    "z_ep/a_H": ("max_plastic_strain_depth", "hertz_radius", "over a_H"),
    "zone/a_H": ("plastic_zone_depth", "hertz_radius", "over a_H"),
    "dent_um": ("residual_depth", None, "in micrometres"),
}
#: Columns whose extremes a design's summary lists (:func:`.tables.extremes`).
EXTREMES = {"p_max/p_H": ("max", "min"), "ep_max_%": ("max",), "dent_um": ("max",)}
_SCALE = {"ep_max_%": 100.0, "dent_um": 1e6}


def shown_cases(dataset) -> list[tuple[dict, dict]]:
    """(labels, isel) of the finished cases on the finest refinement of every slice."""
    usable = analysis.finished_mask(dataset)
    cases = []
    for labels, isel in analysis.sweep_slices(dataset, analysis.mesh_axes(dataset)):
        index = analysis.finest_index(dataset, isel)
        if bool(usable.isel(index)):
            cases.append((labels, index))
    return cases


def plastic_table(dataset):
    """The plastic response per case (:data:`COLUMNS`), finest refinement of each slice.

    Returns
    -------
    pandas.DataFrame
        One row per slice of the non-refinement axes: its labels, ``status`` and the
        :data:`COLUMNS` (NaN where a case has no such value, e.g. an elastic pair) and
        ``flag`` (:func:`.tables.flag`: not converged, or unconverged increments; "" if not).
    """
    import pandas as pd

    flags = {v: k for k, v in STATUS_FLAGS.items()}
    rows = []
    for labels, index in shown_cases(dataset):
        case = dataset.isel(index)
        row = {**labels, "status": flags.get(int(case["status"]), "?")}
        row[tables.FLAG] = tables.flag(dataset, index)
        for column, (name, over, _) in COLUMNS.items():
            value = float(case[name]) if name in case else math.nan
            if over is not None:
                value /= float(case[over])
            row[column] = value * _SCALE.get(column, 1.0)
        rows.append(row)
    return pd.DataFrame(rows)


def overlay_dim(dataset) -> str | None:
    """The axis whose cases share a panel.

    A non-numeric (named) axis, else the friction axis, else the last axis that is neither a
    refinement nor a load axis.
    """
    dims = [d for d in analysis.axis_dims(dataset) if d not in analysis.mesh_axes(dataset)]
    if not dims:
        return None
    for dim in dims:
        if analysis.numeric_coordinate(dataset, dim) is None:
            return dim
    for dim in dims:
        if dataset[dim].attrs.get("campaign_key") == "friction.coefficient":
            return dim
    loads = [d for d in dims if _is_load(dataset, d)]
    rest = [d for d in dims if d not in loads]
    return (rest or dims)[-1]


def _is_load(dataset, dim: str) -> bool:
    for coord in dataset.coords.values():
        if coord.dims == (dim,):
            key = str(coord.attrs.get("campaign_key", ""))
            if key.split(".")[-1] in LOAD_KEYS:
                return True
    return False


def _line_at_axis(
    out: str | Path, case_id: str, name: str, index=None, whole: bool = False
) -> tuple[np.ndarray, np.ndarray] | None:
    """``(x / a_x, values)`` of a case's field along the cell row nearest y = 0.

    Parameters
    ----------
    out : str or Path
        Campaign output folder.
    case_id : str
        The case.
    name : str
        The field.
    index : study.run.storage.CaseIndex, optional
        The folder's case index (:func:`study.run.storage.case_index`), built when omitted.
    whole : bool, optional
        The whole row, x about body 1's last position (a moving case); else x >= 0.
    """
    from ..run import storage

    with storage.open_case(out, case_id, index=index) as case:
        if name not in case:
            return None
        a = float(case.attrs["hertz_semi_axis_x"])
        x, y = case["x"].values, case["y"].values
        row = case[name].isel(y=int(np.argmin(np.abs(y)))).values
        if whole and "position_x" in case:
            x = x - float(case["position_x"].values[-1])
    keep = np.ones(x.shape, bool) if whole else x >= 0
    return x[keep] / a, row[keep]


def _zones(x: np.ndarray, state: np.ndarray, code: int) -> list[tuple[float, float]]:
    """Intervals of x (cell edges) where ``state == code``."""
    dx = x[1] - x[0] if len(x) > 1 else 1.0
    out, start = [], None
    for xi, s in zip(x, state, strict=True):
        if s == code and start is None:
            start = xi - dx / 2
        elif s != code and start is not None:
            out.append((start, xi - dx / 2))
            start = None
    if start is not None:
        out.append((start, x[-1] + dx / 2))
    return out


def plot_profiles(dataset, out: str | Path, path: str | Path) -> Path | None:
    """Pressure and shear over r / a_H normalised by p_H, the overlay axis in one panel.

    One panel per slice of the other non-refinement axes (finest refinement); one style
    (colour, marker, line style: :func:`figures.series_style`) per value of
    :func:`overlay_dim`, the same in every panel, for its pressure and its shear ``q_x`` (the
    curves named "p" and "q_x" in the panel); under the curves one bar per case along y = 0:
    thick where the contact sticks, thin where it slips (from the case's ``contact_state``
    field).  A case that is not converged or truncated has hollow markers and its panel a red
    dashed frame and label (:func:`figures.mark_panel`).

    Parameters
    ----------
    dataset : xarray.Dataset
        Campaign dataset.
    out : str or Path
        Campaign output folder.
    path : str or Path
        PNG to write.

    Returns
    -------
    Path or None
        The PNG, or None without matplotlib, traction profiles or finished cases.
    """
    plt = figures.pyplot()
    if plt is None or "pressure_profile" not in dataset:
        return None
    overlay = overlay_dim(dataset)
    exclude = [*analysis.mesh_axes(dataset), *([overlay] if overlay else [])]
    usable = analysis.finished_mask(dataset)
    panels = []
    for labels, isel in analysis.sweep_slices(dataset, exclude):
        lines = []
        for line_labels, line_isel in analysis.sweep_slices(
            dataset.isel(isel), analysis.mesh_axes(dataset)
        ):
            index = analysis.finest_index(dataset, {**isel, **line_isel})
            if bool(usable.isel(index)):
                lines.append((line_labels, index))
        if lines:
            panels.append((labels, lines))
    panels = panels[: figures.MAX_PANELS]
    if not panels:
        return None
    from matplotlib.lines import Line2D

    from ..run import storage

    stored = storage.case_index(out)
    r = dataset["r_over_a"].values
    # one style per overlaid value, the same in every panel
    order: dict[str, int] = {}
    for labels, lines in panels:
        for line_labels, _ in lines[: figures.MAX_LINES]:
            own = {d: v for d, v in line_labels.items() if d not in labels}
            order.setdefault(figures.labels_text(own), len(order))
    count = len(order)
    moving = any(figures.is_moving(dataset, index) for _, lines in panels for _, index in lines)
    entries = 4 + count + any(
        figures.status_of(dataset, index) in figures.UNTRUSTED
        for _, lines in panels for _, index in lines[: figures.MAX_LINES]
    )  # fmt: skip
    width = 4.6 * min(figures.MAX_COLUMNS, len(panels))
    legend_columns = max(1, min(3, int(width // 2.3)))  # long entries: 2.3 inches each
    legend_rows = math.ceil(entries / legend_columns)
    fig, axes, columns = figures.panel_grid(
        plt, len(panels), 4.6, 3.6, below=figures.LEGEND_ROW * legend_rows + 0.2
    )
    names, statuses = {}, []
    for k, (ax, (labels, lines)) in enumerate(zip(axes, panels, strict=True)):
        top, shown, curves, abscissae = 0.0, [], [], []
        for line_labels, index in lines[: figures.MAX_LINES]:
            case = dataset.isel(index)
            p_h = float(case["hertz_pressure"])
            status = figures.status_of(dataset, index)
            label = figures.labels_text({d: v for d, v in line_labels.items() if d not in labels})
            j = order[label]
            case_id = str(case["case_id"].item())
            whole = figures.is_moving(dataset, index)
            line = figures.traction_line(out, case_id, stored) if whole else None
            x, pressure, shear = (
                (line[0], line[1] / p_h, line[2] / p_h)
                if line is not None
                else (
                    r,
                    case["pressure_profile"].values / p_h,
                    case["shear_x_profile"].values / p_h,
                )
            )
            style = figures.series_style(j, count, len(x), status)
            names.setdefault(j, label)
            shown.append((label, status))
            ax.plot(x, pressure, **style)
            ax.plot(x, shear, **style)
            curves.append((pressure, shear))
            abscissae.append(x)
            # the case's largest pressure (the dataset's, over the whole contact and path)
            peak = float(case["max_pressure"]) / p_h if "max_pressure" in case else math.nan
            if np.isfinite(peak):
                ax.axhline(peak, color=style["color"], ls=":", lw=1.0, zorder=1.5, gid="p_max")
            top = max(top, float(np.nanmax(pressure)), peak if np.isfinite(peak) else 0.0)
            state = _line_at_axis(out, case_id, "contact_state", stored, whole=line is not None)
            if state is None:
                continue
            level = -0.06 * (j + 1)
            for code, width in ((STICK, 4.0), (SLIP, 1.2)):
                for lo, hi in _zones(state[0], state[1], code):
                    ax.plot([lo, hi], [level, level], "-", color=style["color"], lw=width,
                            solid_capstyle="butt", gid="bar")  # fmt: skip
        figures.name_curves(ax, r, curves, abscissae)
        statuses += [status for _, status in shown]
        figures.mark_panel(ax, [s for _, s in shown], [n or "case" for n, _ in shown])
        ax.axhline(0.0, color="0.5", lw=0.6)
        ax.set_xlim(-float(r[-1]) if moving else 0.0, float(r[-1]))
        ax.set_ylim(-0.06 * (count + 1), max(1.05, 1.08 * top))
        ax.set_title(figures.title(labels, dataset=dataset) if labels else "", fontsize=8)
        ax.set_xlabel(("x" if moving else "r") + " / a (1)")
        if k % columns == 0:
            ax.set_ylabel("traction / p_H (1)")
        ax.grid(True, alpha=0.3)
    handles = [
        Line2D([], [], color="k", lw=4.0, label="stick (bar, y = 0)"),
        Line2D([], [], color="k", lw=1.2, label="slip (bar)"),
        Line2D([], [], color="k", lw=1.0, ls=":", label="p_max / p_H (max over path)"),
    ]
    handles += [figures.series_handle(j, count, n) for j, n in sorted(names.items()) if n]
    handles += figures.status_handle(statuses)
    fig.legend(handles=handles, loc="outside lower center", ncols=legend_columns, fontsize=8)
    figures.suptitle(
        fig,
        f"{dataset.attrs.get('campaign', '')}: tractions along y = 0 over the Hertz solution"
        + (f", {overlay} overlaid" if overlay else ""),
        "finest mesh and most load steps of each slice; curves p (pressure) and q_x (shear)"
        + ("; x about body 1's last position (a moving contact: both sides)" if moving else ""),
        figures.status_note(statuses),
    )
    figures.save(plt, fig, path)
    return Path(path)


def plot_load_curves(dataset, path: str | Path) -> Path | None:
    """Maximum pressure, maximum plastic strain and its depth against the Hertz pressure.

    Drawn when an axis sweeps the load; one line per slice of the other non-refinement axes
    (finest refinement), each in its own colour, marker and line style
    (:func:`figures.series_style`), the points of cases not converged or truncated hollow.  The
    elastic (Hertz) maximum p_max = p_H is the grey line.
    """
    plt = figures.pyplot()
    loads = [d for d in analysis.axis_dims(dataset) if _is_load(dataset, d)]
    if plt is None or not loads or "max_plastic_strain" not in dataset:
        return None
    load = loads[0]
    exclude = [*analysis.mesh_axes(dataset), load]
    usable = analysis.finished_mask(dataset)
    panels = (
        ("max_pressure", 1e-9, "max pressure p_max (GPa)"),
        ("max_plastic_strain", 100.0, "max plastic strain (%)"),
        ("max_plastic_strain_depth", None, "depth of the max plastic strain / a_H (1)"),
    )
    fig, axes, _ = figures.panel_grid(plt, len(panels), 4.2, 3.4)
    slices = list(analysis.sweep_slices(dataset, exclude))[: figures.MAX_LINES]
    statuses = []
    for j, (labels, isel) in enumerate(slices):
        xs, ys, marks = [], {name: [] for name, _, _ in panels}, []
        for i in range(dataset.sizes[load]):
            index = analysis.finest_index(dataset, {**isel, load: i})
            if not bool(usable.isel(index)):
                continue
            case = dataset.isel(index)
            xs.append(float(case["hertz_pressure"]) / 1e9)
            marks.append(figures.status_of(dataset, index))
            for name, scale, _ in panels:
                value = float(case[name]) if name in case else math.nan
                ys[name].append(
                    value / float(case["hertz_radius"]) if scale is None else value * scale
                )
        if not xs:
            continue
        statuses += marks
        style = figures.series_style(j, len(slices))
        bad = np.array([m in figures.UNTRUSTED for m in marks])
        for ax, (name, _, _) in zip(axes, panels, strict=True):
            ax.plot(xs, ys[name], **style, label=figures.labels_text(labels) if labels else None)
            if bad.any():  # the untrusted points hollow, over the line's markers
                hollow = {**figures.series_style(j, len(slices), status="truncated"),
                          "linestyle": "none", "gid": "untrusted point"}  # fmt: skip
                hollow["zorder"] += 0.01
                ax.plot(np.array(xs)[bad], np.array(ys[name])[bad], **hollow)
    if not statuses:
        plt.close(fig)
        return None
    p = dataset["hertz_pressure"].values / 1e9
    grid = np.linspace(0.0, float(np.nanmax(p)), 2)
    axes[0].plot(grid, grid, "-", color="0.65", lw=3, zorder=1, label="elastic (Hertz) p_H")
    for ax, (_, _, text) in zip(axes, panels, strict=True):
        ax.set_xlabel("Hertz pressure p_H (GPa)")
        ax.set_ylabel(text)
        ax.grid(True, alpha=0.3)
        ax.set_xlim(left=0.0)
        ax.set_ylim(bottom=0.0)
    handles, _ = axes[0].get_legend_handles_labels()
    axes[0].legend(handles=handles + figures.status_handle(statuses), fontsize=7)
    figures.suptitle(
        fig,
        f"{dataset.attrs.get('campaign', '')}: growth with the load (paper figs. 3-4)",
        "finest mesh and most load steps of each slice",
        figures.status_note(statuses),
    )
    figures.save(plt, fig, path)
    return Path(path)


def plot_sections(dataset, out: str | Path, path: str | Path) -> Path | None:
    """Equivalent plastic strain in the x-z plane through the contact axis, one scale.

    One panel per case of :func:`shown_cases` whose stored result holds ``plastic_strain`` (at
    most :data:`figures.MAX_PANELS`); the maximum of each section is marked and labelled, and a
    case not converged or truncated has a red dashed frame and label
    (:func:`figures.mark_panel`).

    Parameters
    ----------
    dataset : xarray.Dataset
        Campaign dataset.
    out : str or Path
        Campaign output folder.
    path : str or Path
        PNG to write.

    Returns
    -------
    Path or None
        The PNG, or None without matplotlib or plastic strain fields.
    """
    plt = figures.pyplot()
    if plt is None:
        return None
    from ..run import storage

    stored = storage.case_index(out)
    sections = []
    candidates, fieldless = shown_cases(dataset), 0
    for labels, index in candidates:
        case_id = str(dataset["case_id"].isel(index).item())
        if case_id not in stored.results:
            fieldless += 1
            continue
        with storage.open_case(out, case_id, index=stored) as case:
            if "plastic_strain" not in case:
                fieldless += 1
                continue
            a = float(case.attrs["hertz_semi_axis_x"])
            y = case["y"].values
            row = int(np.argmin(np.abs(y)))
            field = case["plastic_strain"].values
            plane = field[:, row, :]
            status = figures.status_of(dataset, index)
            # the label's number is the dataset's (largest over the body and the path); the
            # field's largest cell says where it is, perhaps off this plane
            at = np.unravel_index(int(np.argmax(field)), field.shape)
            if plane.max() >= field.max() * (1 - 1e-9):  # the plane holds it (a mirror image)
                i, k = np.unravel_index(int(np.argmax(plane)), plane.shape)
                at = (i, row, k)
            peak = {
                "value": float(dataset["max_plastic_strain"].isel(index)),
                "x": int(at[0]), "z": int(at[2]), "y": float(y[at[1]]) / a,
                "off": at[1] != row,
            }  # fmt: skip
            sections.append(
                (labels, case["x"].values / a, case["z"].values / a, plane, status, peak)
            )
        if len(sections) == figures.MAX_PANELS:
            break
    if not sections:
        return None
    top = max(float(np.max(s[3])) for s in sections) * 100.0
    if top <= 0:
        return None
    fig, axes, columns = figures.panel_grid(plt, len(sections), 3.8, 2.8, extra=1.0)
    for k, (ax, (labels, x, z, plane, status, peak)) in enumerate(zip(axes, sections, strict=True)):
        dx, dz = x[1] - x[0], z[1] - z[0]
        image = ax.imshow(
            plane.T * 100.0,
            origin="upper",
            extent=(x[0] - dx / 2, x[-1] + dx / 2, z[-1] + dz / 2, z[0] - dz / 2),
            cmap="magma_r",
            vmin=0.0,
            vmax=top,
            aspect="auto",
            interpolation="nearest",
        )
        i, j = peak["x"], peak["z"]
        ax.plot(x[i], z[j], "x", color="tab:cyan", ms=8, mew=2, gid="max")
        where = f"x = {x[i]:.2f}, z = {z[j]:.2f} a_H"
        if peak["off"]:  # the largest cell is not in this plane
            where += f",\nat y = {peak['y']:.2f} a_H (off this plane)"
        ax.text(
            0.98,
            0.04,
            f"max {peak['value'] * 100:.3g} % at {where}",
            transform=ax.transAxes,
            ha="right",
            fontsize=7,
            gid="max label",
            bbox={"facecolor": "white", "edgecolor": "0.7", "alpha": 0.9, "pad": 2},
        )
        figures.mark_panel(ax, [status])
        ax.set_xlim(x[0] - dx / 2, x[-1] + dx / 2)  # the whole box: nothing of the zone cut
        ax.set_title(figures.title(labels, dataset=dataset) if labels else "", fontsize=8)
        ax.set_xlabel("x / a_H (1)")
        if k % columns == 0:
            ax.set_ylabel("depth z / a_H (1)")
    rows = math.ceil(len(axes) / columns)
    bar = fig.colorbar(image, ax=axes, shrink=min(0.9, 1.8 / rows))
    bar.set_label("equivalent plastic strain (%)")
    figures.suptitle(
        fig,
        f"{dataset.attrs.get('campaign', '')}: plastic strain in the plane y = 0 "
        "(paper fig. 6), one colour scale, x: the largest plastic strain (max over path)",
        figures.panel_note(
            len(sections), len(candidates), fieldless, "finished cases", "without a stored field"
        )
        + ", finest mesh and most load steps of each slice",
        figures.status_note([section[4] for section in sections], "red dashed frame"),
    )
    figures.save(plt, fig, path)
    return Path(path)


def column_labels() -> dict[str, str]:
    """The report's header of each :data:`COLUMNS` entry: its name and declared reduction."""
    return {column: tables.column_label(column, name) for column, (name, _, _) in COLUMNS.items()}


def section(dataset, out: Path, name: str, plt, shown: list, limit: int = 200) -> list[str]:
    """Markdown lines of the plastic part of the report (figures appended to ``shown``).

    Parameters
    ----------
    dataset : xarray.Dataset
        Campaign dataset.
    out : Path
        Campaign output folder.
    name : str
        Campaign name (the figures' file names).
    plt : module or None
        Matplotlib's pyplot (None: no figures).
    shown : list
        ``(title, png, note)`` of the report's figures, appended to.
    limit : int, optional
        Most cases listed one by one; a sampled design or more cases are summarised
        (:func:`.tables.is_design`).

    Returns
    -------
    list of str
    """
    lines = ["## Plastic response", ""]
    lines += [
        "Finest mesh and most load steps of each slice; lengths over the Hertz radius a_H,",
        "pressures over the Hertz pressure p_H of the case (elastic solution, same load).",
        "Each header says how the case's value is reduced from its load steps.",
        "",
    ]
    headers = column_labels()
    lines += [
        f"- `{headers[column]}`: {tables.long_name(variable)}, {how}"
        for column, (variable, _, how) in COLUMNS.items()
    ]
    table = plastic_table(dataset)
    flagged = tables.flagged_count(table)
    if not flagged:
        table = table.drop(columns=[tables.FLAG], errors="ignore")
    lines.append("")
    if tables.is_design(dataset, len(table), limit):
        columns = [c for c in COLUMNS if not tables.carries_nothing(table.get(c, []))]
        lines += tables.summary_lines(
            table.rename(columns=headers),
            [headers[c] for c in columns],
            {headers[c]: ends for c, ends in EXTREMES.items() if c in columns},
            "finished cases" + (" of the design" if "sample" in dataset.dims else ""),
        )
    else:
        lines.append(figures.markdown_table(table.rename(columns=headers)))
    if flagged:
        lines += [tables.FLAG_NOTE, ""]
    if plt is None:
        return lines
    for title, png in (
        (
            "Tractions and stick/slip zones",
            plot_profiles(dataset, out, out / f"{name}_plastic_profiles.png"),
        ),
        ("Growth with the load", plot_load_curves(dataset, out / f"{name}_load_curves.png")),
        (
            "Plastic strain sections",
            plot_sections(dataset, out, out / f"{name}_plastic_sections.png"),
        ),
    ):
        if png:
            shown.append((title, png, "finest mesh and most steps of each slice"))
            lines += [f"### {title}", "", f"![{title}]({png.name})", ""]
    return lines
