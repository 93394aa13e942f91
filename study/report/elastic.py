"""The report's sections for every campaign: convergence, speed against error, profiles.

Convergence in the mesh, speed against error, traction profiles against the closed forms,
stick and slip zones.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from .. import analysis
from . import figures
from .figures import (
    labels_text,
    log_tick_values,
    log_ticks,
    panel_grid,
    panel_note,
    pyplot,
    save,
    slice_noun,
    suptitle,
    title,
)


def plot_convergence(dataset, mesh_dim: str, path: str | Path) -> Path | None:
    """Log-log relative error against cells per side, one panel per quantity.

    The error is relative to the closed form where one applies, else to the Richardson
    extrapolation of the slice; dotted lines are the fits ``C h^p`` with the observed order.
    Each slice has its own colour, marker and line style (:func:`figures.series_style`); the
    points of cases not converged or truncated are hollow.
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
    plt = pyplot()
    dataset = analysis.with_derived(dataset)
    names = analysis.quantities(dataset)
    if plt is None or not names:
        return None
    from matplotlib.ticker import FixedLocator, FuncFormatter, NullLocator

    refs = analysis.closed_forms(dataset)
    slices = list(analysis.sweep_slices(dataset, [mesh_dim]))
    # a few slices: a legend per panel with the fitted orders; many: one legend of the slices
    # below the panels (the orders are in the report's tables)
    shared = len(slices) > figures.SHARED_LEGEND_SLICES
    below = (
        figures.LEGEND_ROW * math.ceil(min(len(slices), figures.MAX_LINES) / 3) + 0.2
        if shared
        else 0.0
    )
    fig, axes, _ = panel_grid(plt, len(names), 4.2, 3.6, below=below)
    drawn = slices[: figures.MAX_LINES]
    statuses = [
        [figures.status_of(dataset, {**isel, mesh_dim: i}) for i in range(dataset.sizes[mesh_dim])]
        for _, isel in drawn
    ]
    used = {}  # series index -> label, of the slices drawn in some panel
    for ax, name in zip(axes, names, strict=True):
        table = analysis.convergence_table(dataset, name, mesh_dim)
        basis = "closed form" if name in refs else "extrapolated"
        column = "rel_error" if name in refs else "rel_error_extrapolated"
        for j, (labels, _) in enumerate(drawn):
            rows = table
            for key, value in labels.items():
                rows = rows[rows[key] == value]
            err = np.abs(rows[column].to_numpy(dtype=float))
            n = rows["n"].to_numpy(dtype=float)
            ok = np.isfinite(err) & (err > 0)
            if not np.any(ok):
                continue
            label = labels_text(labels) or "cases"
            used[j] = label
            style = figures.series_style(j, len(drawn))
            ax.loglog(n[ok], err[ok], **style, label=None if shared else label)
            bad = ok & np.array([s in figures.UNTRUSTED for s in statuses[j]])
            if bad.any():  # points of untrusted cases hollow, over the line's markers
                hollow = figures.series_style(j, len(drawn), status="truncated")
                hollow.update(
                    linestyle="none", gid="untrusted point", zorder=style["zorder"] + 0.01
                )
                ax.loglog(n[bad], err[bad], **hollow)
            order, constant = analysis.observed_order(
                rows["h_over_a"].to_numpy(dtype=float)[ok], err[ok]
            )
            if np.isfinite(order):
                h = rows["h_over_a"].to_numpy(dtype=float)[ok]
                ax.loglog(
                    n[ok],
                    constant * h**order,
                    ":",
                    color=style["color"],
                    lw=1.0,
                    zorder=1.5,
                    gid="fit",
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
            handles = ax.get_legend_handles_labels()[0]
            ax.legend(handles=handles + figures.status_handle(sum(statuses, [])), fontsize=7)
    if shared:
        from matplotlib.lines import Line2D

        handles = [figures.series_handle(j, len(drawn), k) for j, k in sorted(used.items())]
        handles.append(Line2D([], [], color="k", ls=":", label="fits C h^p (orders: report.md)"))
        handles += figures.status_handle(sum(statuses, []))
        fig.legend(handles=handles, loc="outside lower center", ncols=3, fontsize=7)
    title = f"{dataset.attrs.get('campaign', '')}: convergence along {mesh_dim}"
    suptitle(
        fig,
        title,
        _convergence_note(dataset, mesh_dim) if len(slices) > figures.MAX_LINES else "",
        figures.status_note(sum(statuses, []), "hollow markers"),
    )
    save(plt, fig, path)
    return Path(path)


def _convergence_note(dataset, mesh_dim: str) -> str:
    slices = len(list(analysis.sweep_slices(dataset, [mesh_dim])))
    if slices <= figures.MAX_LINES:
        return f"all {slices} slice(s), every quantity"
    return f"the first {figures.MAX_LINES} of {slices} slices in axis order, every quantity"


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
    plt = pyplot()
    if plt is None or len(table) == 0:
        return None
    ok = np.isfinite(table["error"].to_numpy(dtype=float)) & (table["error"] > 0)
    if not np.any(ok):
        return None
    from matplotlib.colors import LogNorm
    from matplotlib.ticker import MaxNLocator

    data = table[ok]
    fig, (left, right) = plt.subplots(
        1, 2, figsize=(10, 4.2), layout="constrained", dpi=figures.DPI
    )
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
            log_ticks(ax.xaxis, x)
        else:  # a narrow memory range has long tick labels: few of them
            ax.xaxis.set_major_locator(MaxNLocator(nbins=4))
        ax.set_xlabel(xlabel)
        ax.set_ylabel("largest |relative error| (1)")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    if varying:
        bar = fig.colorbar(scatter, ax=right, label="grid cells (nx ny [nz])")
        ticks = log_tick_values(known)
        bar.set_ticks(ticks, labels=[f"{t:g}" for t in ticks])
        bar.minorticks_off()
    grid = "" if varying or not len(known) else f", every case {int(known[0])} cells"
    basis = "; ".join(dict.fromkeys(data["error_basis"]))
    suptitle(fig, f"{title}: speed versus error ({basis}{grid})", speed_error_note(table))
    save(plt, fig, path)
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
    usable = analysis.finished_mask(dataset)
    slices = list(analysis.sweep_slices(dataset, mesh))
    missing = len(slices) - int(usable.any(dim=mesh).sum()) if mesh else int((~usable).sum())
    shown = []
    for labels, isel in slices:
        if len(shown) >= figures.MAX_PANELS:
            break
        ok = usable.isel(isel)
        cases = [c for c in analysis.sweep_slices(dataset.isel(isel), []) if bool(ok.isel(c[1]))]
        if cases:
            shown.append((labels, isel, cases))
    noun = slice_noun(dataset, mesh, False)
    note = panel_note(len(shown), len(slices), missing, noun)
    if any(len(cases) > figures.MAX_LINES for _, _, cases in shown):
        note += f"; the first {figures.MAX_LINES} meshes per panel"
    return shown, note


def plot_profiles(dataset, path: str | Path, out: str | Path | None = None) -> Path | None:
    """Pressure and shear along y = 0 against r / a, one panel per slice of the non-mesh axes.

    Each panel shows the finished cases along the mesh axes (or the single case): pressure
    and shear ``q_x`` of a case in one style (colour, marker, line style:
    :func:`figures.series_style`), one per mesh, the same in every panel (legend below the
    panels), the curves named "p" and "q_x" in the panel; the Hertz pressure and the
    Cattaneo-Mindlin shear as thick grey lines where they apply.  A case not converged or
    truncated has hollow markers and its panel a red dashed frame and label
    (:func:`figures.mark_panel`).  Panels wrap into at most
    :data:`MAX_COLUMNS` columns; the title says which slices are shown
    (:func:`profile_panels`).

    Parameters
    ----------
    dataset : xarray.Dataset
        Campaign dataset.
    path : str or Path
        PNG to write.
    out : str or Path, optional
        Campaign output folder: a moving case's (sliding, rolling) tractions are drawn over
        its whole line from its file (:func:`figures.traction_line`), x about body 1's last
        position; without it, the dataset's half line r >= 0.

    Returns
    -------
    Path or None
        The PNG, or None without matplotlib or finished cases.
    """
    plt = pyplot()
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
    # one style per mesh (the same in every panel), named in the legend below the panels
    meshes = [label for label, _ in analysis.sweep_slices(dataset.isel(panels[0][1]), [])]
    untrusted = any(
        figures.status_of(dataset.isel(isel), c) in figures.UNTRUSTED
        for _, isel, cases in panels
        for _, c in cases[: figures.MAX_LINES]
    )
    entries = 2 + max(len(meshes), 1) + untrusted  # legend rows of 6 entries
    fig, axes, columns = panel_grid(
        plt, len(panels), 4.0, 3.0, below=figures.LEGEND_ROW * -(-entries // 6)
    )
    grey = {"color": "0.65", "lw": 3.0, "zorder": 1}
    drawn = {"Hertz p": False, "Cattaneo-Mindlin q_x": False}
    names = [labels_text(label) if label else "" for label in meshes]
    moving = any(
        figures.is_moving(dataset.isel(isel), c) for _, isel, cases in panels for _, c in cases
    )
    moving = moving and out is not None  # the whole lines are in the case files
    stored = None
    if moving:
        from ..run import storage

        stored = storage.case_index(out)
    used, statuses = set(), []
    for k, (ax, (labels, isel, cases)) in enumerate(zip(axes, panels, strict=True)):
        sub = dataset.isel(isel)
        shown, curves, abscissae, top = [], [], [], 0.0
        for case_labels, case_isel in cases[: figures.MAX_LINES]:
            case = sub.isel(case_isel)
            j = names.index(labels_text(case_labels)) if case_labels else 0
            used.add(j)
            status = figures.status_of(sub, case_isel)
            shown.append((names[j] or "case", status))
            line = None
            if moving and figures.is_moving(sub, case_isel):  # both sides, from its file
                line = figures.traction_line(out, str(case["case_id"].item()), stored)
            x, pressure, shear = (
                (line[0], line[1] / 1e9, line[2] / 1e9)
                if line is not None
                else (
                    r,
                    case["pressure_profile"].values / 1e9,
                    case["shear_x_profile"].values / 1e9,
                )
            )
            style = figures.series_style(j, len(meshes), len(x), status)
            curves.append((pressure, shear))
            abscissae.append(x)
            ax.plot(x, pressure, **style)
            ax.plot(x, shear, **style)
            peak = float(case["max_pressure"]) / 1e9 if "max_pressure" in case else math.nan
            top = max(top, float(np.nanmax(pressure)), peak if np.isfinite(peak) else 0.0)
        figures.name_curves(ax, r, curves, abscissae)
        statuses += [status for _, status in shown]
        figures.mark_panel(ax, [s for _, s in shown], [n for n, _ in shown])
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
        top = max(top, p0 / 1e9 if np.isfinite(p0) else 0.0)
        if top > 0:  # the case's p_max (the dataset's, over the contact and the path) shows
            ax.set_ylim(top=1.08 * top)
        ax.set_title(title(labels, dataset=dataset), fontsize=8)
        ax.set_xlim(-float(r[-1]) if moving else 0.0, float(r[-1]))
        ax.xaxis.set_major_locator(MultipleLocator(0.5))
        ax.set_xlabel(("x" if moving else "r") + " / a (1)")
        if k % columns == 0:
            ax.set_ylabel("traction (GPa)")
        ax.grid(True, alpha=0.3)
    styles = [
        Line2D([], [], ls="-" if name.startswith("Hertz") else "--", label=name, **grey)
        for name, done in drawn.items()
        if done
    ]
    if len(meshes) > 1:
        styles += [figures.series_handle(j, len(meshes), names[j]) for j in sorted(used)]
    else:
        styles.append(figures.series_handle(0, 1, "computed p and q_x"))
    styles += figures.status_handle(statuses)
    columns = min(len(styles), 6)
    fig.legend(handles=styles, loc="outside lower center", ncols=columns, fontsize=8)
    suptitle(
        fig,
        f"{dataset.attrs.get('campaign', '')}: traction along y = 0, "
        + ("about body 1's last position (a moving contact)" if moving else "x >= 0")
        + " (over the Hertz semi-axis a); curves p (pressure) and q_x (shear)",
        note,
        figures.status_note(statuses),
    )
    save(plt, fig, path)
    return Path(path)


def stick_slip_panels(dataset, out: str | Path, *, index=None) -> tuple[list, str]:
    """The panels of :func:`plot_stick_slip` and a note saying which slices they show.

    Parameters
    ----------
    dataset : xarray.Dataset
        Campaign dataset.
    out : str or Path
        Campaign output folder.
    index : study.run.storage.CaseIndex, optional
        The folder's case index (:func:`study.run.storage.case_index`), built when omitted.

    Returns
    -------
    (list, str)
        ``(labels, index, case_id)`` per panel (the finest mesh of each slice of the non-mesh
        axes whose case finished and has a ``contact_state`` field, at most
        :data:`MAX_PANELS`) and the note (slices whose finest case did not finish, or has no
        stored result or field, count as missing).
    """
    from ..run import storage

    stored = storage.case_index(out) if index is None else index
    mesh = analysis.mesh_axes(dataset)
    usable = analysis.finished_mask(dataset)
    slices = list(analysis.sweep_slices(dataset, mesh))
    found, missing = [], 0
    for labels, isel in slices:
        index = analysis.finest_index(dataset, isel)
        if not bool(usable.isel(index)):
            missing += 1
            continue
        if len(found) >= figures.MAX_PANELS:
            continue  # finished, not shown (the note says so)
        case_id = str(dataset["case_id"].isel(index).item())
        has_state = False
        if case_id in stored.results:
            with storage.open_case(out, case_id, index=stored) as case:
                has_state = "contact_state" in case
        if has_state:
            found.append((labels, index, case_id))
        else:
            missing += 1
    noun = slice_noun(dataset, mesh, True)
    why = "without a finished case with a contact-state map"
    return found, panel_note(len(found), len(slices), missing, noun, why)


def plot_stick_slip(dataset, out: str | Path, path: str | Path) -> Path | None:
    """Contact-state maps (separated / stick / slip) from the cases' stored results.

    One panel per slice of the non-mesh axes, on the finest mesh of the slice, in at most
    :data:`MAX_COLUMNS` columns and :data:`MAX_PANELS` panels (the title says which slices are
    shown, :func:`stick_slip_panels`); the Hertz radius (dashed) and the Cattaneo stick radius
    (dotted) are drawn as circles; a case not converged or truncated has a red dashed frame and
    label (:func:`figures.mark_panel`).

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
        The PNG, or None without matplotlib or contact-state fields.
    """
    plt = pyplot()
    if plt is None:
        return None
    from ..run import storage

    stored = storage.case_index(out)
    panels, note = stick_slip_panels(dataset, out, index=stored)
    if not panels:
        return None
    from matplotlib.colors import ListedColormap
    from matplotlib.ticker import MultipleLocator

    refs = analysis.closed_forms(analysis.with_derived(dataset))
    c_ref = None
    if "stick_ratio" in refs:
        c_ref = refs["stick_ratio"].broadcast_like(dataset["status"])
    mesh = analysis.mesh_axes(dataset)
    fig, axes, columns = panel_grid(plt, len(panels), 3.0, 3.0, extra=1.0)
    cmap = ListedColormap(["#eeeeee", "#2b83ba", "#fdae61"])
    t = np.linspace(0, 2 * np.pi, 200)
    dotted, statuses = False, []
    for k, (ax, (labels, index, case_id)) in enumerate(zip(axes, panels, strict=True)):
        with storage.open_case(out, case_id, index=stored) as case:
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
        ax.set_title(title({**labels, **n_label}), fontsize=8)
        statuses.append(figures.status_of(dataset, index))
        figures.mark_panel(ax, statuses[-1:])
        ax.xaxis.set_major_locator(MultipleLocator(1.0))
        ax.yaxis.set_major_locator(MultipleLocator(1.0))
        ax.set_xlabel("x / a (1)")
        if k % columns == 0:
            ax.set_ylabel("y / a (1)")
    rows = math.ceil(len(axes) / columns)
    bar = fig.colorbar(image, ax=axes, ticks=[0, 1, 2], shrink=min(0.9, 1.8 / rows))
    bar.ax.set_yticklabels(figures.STATE_NAMES)
    suptitle(
        fig,
        f"{dataset.attrs.get('campaign', '')}: contact state{' (finest mesh)' if mesh else ''}",
        "dashed circle: Hertz radius a"
        + ("; dotted: Cattaneo-Mindlin stick radius c" if dotted else ""),
        note,
        figures.status_note(statuses, "red dashed frame"),
    )
    save(plt, fig, path)
    return Path(path)
