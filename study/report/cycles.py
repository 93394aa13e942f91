"""The cyclic part of a campaign report: fretting loops, energy and plastic strain per cycle.

:func:`section` adds to ``report.md`` (campaigns whose cases have a cyclic load path):

- a table per case: cycles, dissipated energy (loop area and summed friction work) of the first
  and the last cycle, slip and force amplitudes, smallest stick radius, plastic strain gained
  in the first and the last cycle;
- ``<name>_fretting_loops.png``: the Q_x - Delta_x loop of every cycle, one panel per case;
- ``<name>_cycles.png``: the energy dissipated (or the friction work of a sliding pass), the
  plastic strain gained, the residual stress, the mean real contact area and a periodic
  case's run-in surface rms per cycle against the cycle number (those the scene has);
- the wear of cases that wear (:mod:`.wear`), the fatigue of passes (:mod:`.fatigue`).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from solver.result import STATUS_FLAGS
from solver.variables import CYCLE_QUANTITIES

from .. import analysis
from . import fatigue, figures, wear

#: Per-cycle quantities drawn against the cycle, in this order, when the campaign has them:
#: name -> (scale, axis label, panel title, log axis).
PANELS = {
    "loop_energy": (1e3, "energy per cycle (mJ)", "dissipated", False),
    "cycle_friction_work": (1e3, "friction work (mJ)", "per cycle", False),
    "plastic_strain_increment": (1.0, "plastic strain gained (1)", "largest over the volume", True),
    "max_residual_stress": (1e-6, "residual stress (MPa)", "largest von Mises, cycle end", False),
    "mean_contact_area": (1e12, "real contact area (um^2)", "mean over the cycle", False),
    "residual_topography_rms": (1e9, "body 2's rms (nm)", "run-in surface, cycle end", False),
}


def _per_cycle(dataset) -> list[str]:
    """The per-cycle quantities of :data:`solver.variables.CYCLE_QUANTITIES` in the dataset."""
    return [name for name in CYCLE_QUANTITIES if name in dataset]


def _cases(dataset) -> list[tuple[dict, dict]]:
    usable = analysis.finished_mask(dataset)
    first = _per_cycle(dataset)[0]
    return [
        (labels, isel)
        for labels, isel in analysis.sweep_slices(dataset, [])
        if bool(usable.isel(isel)) and np.isfinite(dataset[first].isel(isel)).any()
    ]


def cycle_table(dataset):
    """Per case: the first and the last cycle's energy, amplitudes, stick radius, plastic gain.

    Returns
    -------
    pandas.DataFrame
        One row per finished case with cycles.
    """
    import pandas as pd

    rows = []
    for labels, isel in _cases(dataset):
        case = dataset.isel(isel)
        count = int(np.count_nonzero(np.isfinite(case[_per_cycle(dataset)[0]].values)))
        status = {v: k for k, v in STATUS_FLAGS.items()}.get(int(case["status"]), "?")
        row = {**labels, "status": status, "cycles": count}

        def pick(name, i, case=case):
            return float(case[name].values[i]) if name in case else math.nan

        for tag, i in (("first", 0), ("last", count - 1)):
            row[f"E_{tag}_J"] = pick("loop_energy", i)
        energy = row["E_last_J"]
        row["work/E_last"] = pick("cycle_friction_work", count - 1) / energy if energy else math.nan
        row["slip_amp_um"] = pick("slip_amplitude", count - 1) * 1e6
        row["Q_amp_N"] = pick("force_amplitude", count - 1)
        row["c_min/a_H"] = pick("min_stick_radius", count - 1) / float(case["hertz_radius"])
        row["dep_first"] = pick("plastic_strain_increment", 0)
        row["dep_last"] = pick("plastic_strain_increment", count - 1)
        row["res_MPa"] = pick("max_residual_stress", count - 1) / 1e6
        rows.append(row)
    return pd.DataFrame(rows).dropna(axis=1, how="all")  # a scene's absent quantities


def plot_loops(dataset, path: str | Path) -> Path | None:
    """Q_x against Delta_x, one panel per case.

    Every cycle in its own colour (a colour bar), marker and line style
    (:func:`figures.series_style`), so loops that coincide stay visible; a case not converged
    or truncated has a red dashed frame and label (:func:`figures.mark_panel`).
    """
    plt = figures.pyplot()
    needed = ("tangential_force_x_history", "tangential_shift_x_history", "step_cycle_history")
    if plt is None or not all(name in dataset for name in needed):
        return None
    if "position_x_history" in dataset:  # a moving path: no Q - Delta loop (solver.result)
        return None
    cases = _cases(dataset)[: figures.MAX_PANELS]
    if not cases:
        return None
    fig, axes, columns = figures.panel_grid(plt, len(cases), 3.8, 3.2, extra=1.0)
    count = dataset.sizes["cycle"]
    cmap = plt.get_cmap("viridis")
    statuses = []
    for k, (ax, (labels, isel)) in enumerate(zip(axes, cases, strict=True)):
        case = dataset.isel(isel)
        q = case["tangential_force_x_history"].values
        d = case["tangential_shift_x_history"].values * 1e6
        cycle = case["step_cycle_history"].values
        for c in range(1, count + 1):
            steps = np.flatnonzero(cycle == c)
            if not steps.size:
                continue
            steps = np.concatenate([[steps[0] - 1], steps]) if steps[0] > 0 else steps
            # the loops of the cycles often coincide: each its own marker and line style too
            style = figures.series_style(
                c - 1, count, len(steps), colour=cmap((c - 1) / max(count - 1, 1))
            )
            ax.plot(d[steps], q[steps], **style)
        statuses.append(figures.status_of(dataset, isel))
        figures.mark_panel(ax, statuses[-1:])
        ax.set_title(figures.title(labels, dataset=dataset), fontsize=8)
        ax.set_xlabel("tangential shift Delta_x (um)")
        if k % columns == 0:
            ax.set_ylabel("tangential force Q_x (N)")
        ax.grid(True, alpha=0.3)
    mappable = plt.cm.ScalarMappable(cmap=cmap, norm=plt.Normalize(1, max(count, 2)))
    rows = math.ceil(len(axes) / columns)
    fig.colorbar(mappable, ax=axes, shrink=min(0.9, 1.8 / rows), label="cycle")
    figures.suptitle(
        fig,
        f"{dataset.attrs.get('campaign', '')}: fretting loops Q_x - Delta_x",
        "each cycle its own colour, marker and line style (cycle 1 widest, drawn lowest)",
        figures.status_note(statuses, "red dashed frame"),
    )
    figures.save(plt, fig, path)
    return Path(path)


def plot_cycles(dataset, path: str | Path) -> Path | None:
    """The per-cycle quantities (:data:`PANELS`) against the cycle, one line per case.

    Each case in its own colour, marker and line style (:func:`figures.series_style`), hollow
    markers for a case not converged or truncated.
    """
    plt = figures.pyplot()
    cases = _cases(dataset)[: figures.MAX_LINES]
    names = [name for name in PANELS if name in dataset]
    if "loop_energy" in names and "cycle_friction_work" in names:  # drawn over the loop's
        names.remove("cycle_friction_work")
    if plt is None or not cases or not names:
        return None
    from matplotlib.ticker import MaxNLocator

    entries = len(cases) + 1  # and the hollow markers' entry, in 2 columns below the panels
    fig, axes, _ = figures.panel_grid(
        plt, len(names), 4.4, 3.4, below=figures.LEGEND_ROW * (math.ceil(entries / 2) + 1)
    )
    cycle = dataset["cycle"].values
    statuses = []
    for k, (labels, isel) in enumerate(cases):
        case = dataset.isel(isel)
        statuses.append(figures.status_of(dataset, isel))
        style = figures.series_style(k, len(cases), len(cycle), statuses[-1])
        for ax, name in zip(axes, names, strict=True):
            scale, _, _, log = PANELS[name]
            values = case[name].values * scale
            plot = ax.semilogy if log else ax.plot
            label = figures.labels_text(labels) if ax is axes[0] else None
            plot(cycle, np.clip(values, 1e-12, None) if log else values, **style, label=label)
            if name == "loop_energy" and "cycle_friction_work" in case:
                ax.plot(cycle, case["cycle_friction_work"].values * scale, "+", ms=9,
                        color=style["color"], zorder=4, gid="friction work")  # fmt: skip
    for ax, name in zip(axes, names, strict=True):
        _, ylabel, title, _ = PANELS[name]
        ax.set_ylabel(ylabel)
        ax.set_title(title, fontsize=9)
        ax.xaxis.set_major_locator(MaxNLocator(integer=True))
        ax.set_xlabel("cycle")
        ax.grid(True, which="both", alpha=0.3)
    note = "lines: loop area, +: friction work" if "loop_energy" in names else None
    handles = axes[0].get_legend_handles_labels()[0] + figures.status_handle(statuses)
    fig.legend(handles=handles, loc="outside lower center", ncols=2, fontsize=7, title=note,
               title_fontsize=7)  # fmt: skip
    figures.suptitle(
        fig, f"{dataset.attrs.get('campaign', '')}: per cycle", figures.status_note(statuses)
    )
    figures.save(plt, fig, path)
    return Path(path)


def section(dataset, out: Path, name: str, plt, shown: list) -> list[str]:
    """Markdown lines of the cyclic part of the report (figures appended to ``shown``)."""
    lines = ["## Load cycles", ""]
    lines += [
        "`E_*`: area of the Q_x - Delta_x loop of the first and the last cycle;",
        "`work/E_last`: the friction work summed over the surface and the last cycle's steps",
        "over that area (1 for an elastic contact: the energy balance); amplitudes and the",
        "smallest stick radius of the last cycle; `dep_*`: equivalent plastic strain gained in",
        "the first and the last cycle (largest over the volume); `res_MPa`: largest von Mises",
        "residual stress at the end of the last cycle.",
        "",
        figures.markdown_table(cycle_table(dataset)),
    ]
    if plt is None:
        return lines
    for title, png in (
        ("Fretting loops", plot_loops(dataset, out / f"{name}_fretting_loops.png")),
        ("Per cycle", plot_cycles(dataset, out / f"{name}_cycles.png")),
    ):
        if png:
            shown.append((title, png, "every finished case with cycles"))
            lines += [f"### {title}", "", f"![{title}]({png.name})", ""]
    if wear.is_wear(dataset):  # the cycles' wear (its per-cycle quantities)
        lines += wear.section(dataset, out, name, plt, shown)
    if fatigue.is_fatigue(dataset):  # the passes' fatigue, beside their shakedown regime
        lines += fatigue.section(dataset, out, name, plt, shown)
    return lines
