"""The rough-interface part of a campaign report: one period of a periodic rough surface.

:func:`section` adds to ``report.md`` (campaigns of periodic heights-only cases,
``grid.periodic``), from the case files:

- a row per finished case (its headers say each value's reduction, :data:`COLUMNS`; a case
  not converged or with unconverged increments flagged): at the largest load the real
  contact fraction, the mean
  separation, the contact spots and the largest spot's share of the contact area; for an
  elastic-plastic body the largest equivalent plastic strain, the yielded layer's mean
  thickness (the plastic volume over the period's area) and the rms of the gap before and
  after the path (the residual gap: the plastically deformed topography);
- ``<name>_load_curves.png``: the real contact fraction and the mean separation against the
  mean pressure, every case (the load-area and load-separation curves);
- ``<name>_spot_sizes.png``: the share of spots larger than an area at the largest load,
  against the area (log-log), every case (each step's spots are in the case files,
  ``spot_areas``);
- ``<name>_residual_topography.png`` (elastic-plastic): the first case's initial gap, its gap
  after the path (on one colour scale) and the difference (the plastic print);
- ``<name>_topography_spectra.png`` (passes over an elastic-plastic body 2): per case, the
  power spectral density of body 2's surface at the end of each pass (its run-in print,
  ``cycle_topography_spectrum``) beside that of the initial gap.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from solver.drive.record import spot_areas

from .. import analysis
from . import figures, tables

#: Columns of :func:`rough_table`: name -> (the declared history it reads or None, the
#: reduction in words or None for the declared one, what it is when nothing is declared).  The
#: report's headers say the reduction (:func:`column_labels`).
COLUMNS = {
    "p_mean_MPa": (None, tables.AT_PEAK, "normal force over the period's area"),
    "contact_%": ("contact_fraction", tables.AT_PEAK, ""),
    "separation_nm": ("mean_separation", tables.AT_PEAK, ""),
    "spots": ("contact_spots", tables.AT_PEAK, ""),
    "largest_spot_%": (None, tables.AT_PEAK, "the largest spot's share of the contact area"),
    "ep_max_%": ("max_plastic_strain", None, ""),
    "yielded_nm": ("plastic_volume", None, ""),
    "gap_rms_nm": (None, "before the path", "rms of the initial gap"),
    "residual_rms_nm": (None, "after the path", "rms of the residual gap (the deformed "
                        "topography)"),
}  # fmt: skip


def column_labels() -> dict[str, str]:
    """The report's header of each :data:`COLUMNS` entry: its name and its reduction."""
    return {
        column: tables.column_label(column, name, words)
        for column, (name, words, _) in COLUMNS.items()
    }


def _describe(column: str) -> str:
    """What a column holds: the declared long name of its history, and the column's note."""
    name, _, note = COLUMNS[column]
    if name is None:
        return note
    return tables.long_name(name) + (f"; {note}" if note else "")


def _cases(dataset, index) -> list[tuple[dict, str]]:
    """(labels, case id) of every finished case whose result is stored.

    Parameters
    ----------
    dataset : xarray.Dataset
        Campaign dataset.
    index : study.run.storage.CaseIndex
        The output folder's case index (:func:`study.run.storage.case_index`).
    """
    usable = analysis.finished_mask(dataset)
    found = []
    for labels, isel in analysis.sweep_slices(dataset, []):
        if bool(usable.isel(isel)):
            case_id = str(dataset["case_id"].isel(isel).item())
            if case_id in index.results:
                found.append((labels, case_id))
    return found


def _read(out: str | Path, case_id: str, index) -> dict:
    """What the section uses of one case: histories, the period's area, final fields.

    Parameters
    ----------
    out : str or Path
        Campaign output folder.
    case_id : str
        The case.
    index : study.run.storage.CaseIndex
        The folder's case index (:func:`study.run.storage.case_index`).
    """
    from ..run import storage

    with storage.open_case(out, case_id, index=index) as case:
        x, y = case["x"].values, case["y"].values
        period = (float((x[1] - x[0]) * x.size), float((y[1] - y[0]) * y.size))
        data = {
            "cell_area": period[0] * period[1] / (x.size * y.size),
            "period_area": period[0] * period[1],
            "period": period,
        }
        for name in ("normal_force", "contact_fraction", "mean_separation", "contact_spots",
                     "max_plastic_strain", "plastic_volume"):  # fmt: skip
            if name in case:
                data[name] = case[name].values.astype(float)
        for name in ("pressure", "initial_gap", "residual_gap", "spot_areas",
                     "cycle_topography_spectrum", "wavenumber"):  # fmt: skip
            if name in case:
                data[name] = case[name].values.astype(float)
        data["extent"] = (x[0], x[-1], y[0], y[-1])
    return data


def _peak_spots(data: dict) -> np.ndarray | None:
    """Spot areas (m^2, largest first) at the largest load, or None when not on record.

    Every step's spots are in the case file (``spot_areas``); a file without them has only the
    final pressure, which serves when the path ends at its largest load.
    """
    peak = int(np.argmax(data["normal_force"]))
    if "spot_areas" in data:
        areas = data["spot_areas"][peak]
        return areas[np.isfinite(areas)]
    if data["normal_force"][-1] == data["normal_force"][peak] > 0:
        return spot_areas(data["pressure"] > 0, data["cell_area"], periodic=True)
    return None


def rough_table(dataset, out: str | Path):
    """Per finished case: contact and (elastic-plastic) plastic measures at the largest load.

    Parameters
    ----------
    dataset : xarray.Dataset
        Campaign dataset.
    out : str or Path
        Campaign output folder.

    Returns
    -------
    pandas.DataFrame
        One row per finished case: its labels and the columns of the module docstring.
    """
    import pandas as pd

    from ..run import storage

    index = storage.case_index(out)
    flags = {
        str(dataset["case_id"].isel(isel).item()): tables.flag(dataset, isel)
        for _, isel in analysis.sweep_slices(dataset, [])
    }
    rows = []
    for labels, case_id in _cases(dataset, index):
        data = _read(out, case_id, index)
        peak = int(np.argmax(data["normal_force"]))
        row = {
            **labels,
            tables.FLAG: flags.get(case_id, ""),
            "p_mean_MPa": data["normal_force"][peak] / data["period_area"] / 1e6,
            "contact_%": 100 * data["contact_fraction"][peak],
            "separation_nm": 1e9 * data["mean_separation"][peak],
            "spots": int(data["contact_spots"][peak]),
        }
        areas = _peak_spots(data)
        if areas is not None:
            row["largest_spot_%"] = 100 * areas[0] / areas.sum() if areas.size else math.nan
        if "max_plastic_strain" in data:
            row["ep_max_%"] = 100 * data["max_plastic_strain"].max()
            row["yielded_nm"] = 1e9 * data["plastic_volume"].max() / data["period_area"]
            row["gap_rms_nm"] = 1e9 * np.std(data["initial_gap"])
            row["residual_rms_nm"] = 1e9 * np.std(data["residual_gap"])
        rows.append(row)
    return pd.DataFrame(rows)


def plot_load_curves(dataset, out: str | Path, path: Path) -> Path | None:
    """Real contact fraction and mean separation against the mean pressure, every case.

    Parameters
    ----------
    dataset : xarray.Dataset
        Campaign dataset.
    out : str or Path
        Campaign output folder.
    path : Path
        PNG to write.

    Returns
    -------
    Path or None
        The PNG, or None without a stored finished case.
    """
    from ..run import storage

    index = storage.case_index(out)
    cases = _cases(dataset, index)
    if not cases:
        return None
    plt = figures.pyplot()
    fig, axes, _ = figures.panel_grid(plt, 2, 3.6, 3.0)
    for j, (labels, case_id) in enumerate(cases):
        data = _read(out, case_id, index)
        loaded = data["normal_force"] > 0
        pressure = data["normal_force"][loaded] / data["period_area"] / 1e6
        style = figures.series_style(j, len(cases))
        label = figures.labels_text(labels)
        axes[0].plot(pressure, 100 * data["contact_fraction"][loaded], label=label, **style)
        axes[1].plot(pressure, 1e9 * data["mean_separation"][loaded], label=label, **style)
    axes[0].set(xlabel="mean pressure (MPa)", ylabel="real contact area (% of the period)")
    axes[1].set(xlabel="mean pressure (MPa)", ylabel="mean separation (nm)")
    axes[0].set_title("load-area", fontsize=9)
    axes[1].set_title("load-separation", fontsize=9)
    axes[1].legend(fontsize=7)
    figures.suptitle(fig, "Periodic rough interface: loaded steps of every case")
    figures.save(plt, fig, path)
    return Path(path)


def plot_spot_sizes(dataset, out: str | Path, path: Path) -> Path | None:
    """Share of the spots larger than an area (log-log) at the largest load, every case.

    Parameters
    ----------
    dataset : xarray.Dataset
        Campaign dataset.
    out : str or Path
        Campaign output folder.
    path : Path
        PNG to write.

    Returns
    -------
    Path or None
        The PNG, or None without a stored finished case with spots.
    """
    from ..run import storage

    index = storage.case_index(out)
    cases = [
        (labels, _peak_spots(_read(out, case_id, index)))
        for labels, case_id in _cases(dataset, index)
    ]
    cases = [(labels, areas) for labels, areas in cases if areas is not None and areas.size]
    if not cases:
        return None
    plt = figures.pyplot()
    fig, (ax,), _ = figures.panel_grid(plt, 1, 4.2, 3.2)
    for j, (labels, areas) in enumerate(cases):
        share = np.arange(1, areas.size + 1) / areas.size  # larger-or-equal, largest first
        style = figures.series_style(j, len(cases))
        ax.loglog(areas * 1e12, share, label=figures.labels_text(labels), **style)
    ax.set(xlabel="spot area (um^2)", ylabel="share of spots at least this large (1)")
    ax.legend(fontsize=7)
    figures.suptitle(fig, "Contact spot sizes at the largest load (spots joined across the period)")
    figures.save(plt, fig, path)
    return Path(path)


def plot_residual_topography(dataset, out: str | Path, path: Path) -> Path | None:
    """The first elastic-plastic case's gap before and after the path, and their difference.

    Parameters
    ----------
    dataset : xarray.Dataset
        Campaign dataset.
    out : str or Path
        Campaign output folder.
    path : Path
        PNG to write.

    Returns
    -------
    Path or None
        The PNG, or None without a stored finished case with a residual gap.
    """
    from ..run import storage

    index = storage.case_index(out)
    found = next(
        ((labels, data) for labels, case_id in _cases(dataset, index)
         if "residual_gap" in (data := _read(out, case_id, index))),
        None,
    )  # fmt: skip
    if found is None:
        return None
    labels, data = found
    plt = figures.pyplot()
    fig, axes, _ = figures.panel_grid(plt, 3, 3.0, 3.0, below=0.5)
    extent = [1e6 * v for v in data["extent"]]
    before, after = data["initial_gap"], data["residual_gap"]
    panels = (
        (before - before.mean(), "initial gap"),
        (after - after.mean(), "gap after the path"),
        (after - before, "plastic print (after - before)"),
    )
    shared = 1e9 * max(np.abs(panels[0][0]).max(), np.abs(panels[1][0]).max())
    limits = ((-shared, shared), (-shared, shared), (None, None))  # before and after alike
    for ax, (values, name), (low, high) in zip(axes, panels, limits, strict=True):
        image = ax.imshow(
            1e9 * values.T, origin="lower", extent=extent, cmap="viridis", vmin=low, vmax=high
        )
        ax.set(xlabel="x (um)", ylabel="y (um)")
        ax.set_title(name, fontsize=9)
        fig.colorbar(image, ax=ax, location="bottom", label="nm", shrink=0.8)
    figures.suptitle(
        fig, "Plastically deformed topography (gap about its mean)", figures.labels_text(labels)
    )
    figures.save(plt, fig, path)
    return Path(path)


#: Passes named in a spectra panel's legend (the first and the last among them).
LABELLED_PASSES = 4


def plot_topography_spectra(dataset, out: str | Path, path: Path) -> Path | None:
    """Per case with passes, the spectrum of body 2's surface after each pass.

    One panel per case (at most :data:`figures.MAX_LINES`): ``C(q)`` of each pass's run-in
    surface, light to dark with the pass (the first, the last and at most
    :data:`LABELLED_PASSES` in all named in the legend), and dashed the initial gap's (the
    heights being printed), both by :func:`solver.bodies.heights.isotropic_spectrum`.

    Returns
    -------
    Path or None
        The PNG, or None without a stored finished case with per-pass spectra.
    """
    from solver.bodies.heights import isotropic_spectrum

    from ..run import storage

    index = storage.case_index(out)
    found = [
        (labels, data)
        for labels, case_id in _cases(dataset, index)
        if "cycle_topography_spectrum" in (data := _read(out, case_id, index))
    ][: figures.MAX_LINES]
    if not found:
        return None
    plt = figures.pyplot()
    fig, axes, _ = figures.panel_grid(plt, len(found), 3.8, 3.2, below=0.4)
    for ax, (labels, data) in zip(axes, found, strict=True):
        q, spectra = data["wavenumber"], data["cycle_topography_spectrum"]
        colours = plt.get_cmap("viridis")(np.linspace(0.85, 0.0, len(spectra)))
        named = set(np.linspace(0, len(spectra) - 1, LABELLED_PASSES).round().astype(int))
        for k, (spectrum, colour) in enumerate(zip(spectra, colours, strict=True)):
            label = f"after pass {k + 1}" if k in named else "_nolegend_"
            ax.loglog(q, spectrum, color=colour, label=label)
        initial = isotropic_spectrum(data["initial_gap"], data["period"])
        ax.loglog(q, initial, "k--", label="initial gap")
        top = max(float(initial.max()), float(spectra.max()))
        floor = max(1e-8 * top, float(spectra[spectra > 0].min(initial=top)))
        ax.set_ylim(0.5 * floor, 2 * top)  # not the round-off past the heights' cutoff
        ax.set(xlabel="wavenumber q (1/m)", ylabel="C(q) (m^4)")
        ax.set_title(figures.labels_text(labels), fontsize=8)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=6, loc="upper right")
    figures.suptitle(fig, "Run-in surface of body 2: power spectral density per pass", "")
    figures.save(plt, fig, path)
    return Path(path)


def section(dataset, out: Path, name: str, plt, shown: list) -> list[str]:
    """Markdown lines of the rough-interface part of the report (figures added to ``shown``)."""
    lines = ["## Rough interface", ""]
    lines += [
        "Per finished case; each header says when its value is read (at the step of the largest",
        "normal force, over the path, before or after it):",
        "",
    ]
    headers = column_labels()
    table = rough_table(dataset, out)
    lines += [f"- `{headers[c]}`: {_describe(c)}" for c in COLUMNS if c in table]
    if not tables.flagged_count(table):
        table = table.drop(columns=[tables.FLAG], errors="ignore")
    lines += ["", figures.markdown_table(table.rename(columns=headers)), ""]
    if tables.FLAG in table:
        lines += [tables.FLAG_NOTE, ""]
    if plt is None:
        return lines
    drawn = (
        ("Load-area and load-separation", plot_load_curves, "load_curves", "every case"),
        ("Contact spot sizes", plot_spot_sizes, "spot_sizes", "every case, at its largest load"),
        ("Residual topography", plot_residual_topography, "residual_topography",
         "the first elastic-plastic case"),
        ("Run-in spectra", plot_topography_spectra, "topography_spectra",
         "every case with passes"),
    )  # fmt: skip
    for title, plot, stem, which in drawn:
        png = plot(dataset, out, out / f"{name}_{stem}.png")
        if png:
            shown.append((title, png, f"{which}, finished"))
            lines += [f"### {title}", "", f"![{title}]({png.name})", ""]
    return lines
