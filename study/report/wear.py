"""The wear part of a campaign report: worn volume, friction energy, worn profiles, pressure.

For a campaign whose cases wear (``[wear]``: the per-cycle ``wear_rate`` and ``load_cycles``
of :data:`solver.variables.CYCLE_QUANTITIES`) :func:`section` writes

- a table per case: load cycles and cycles solved, worn volume, friction energy dissipated,
  their ratio, the wear rate of the first and the last solved cycle, the deepest wear;
- ``<name>_wear_energy.png``: the worn volume against the friction energy dissipated, both
  summed over the load cycles (a solved cycle counts the cycles it stands for), one line per
  case on log-log axes: the energy law's ratio is alpha, Archard's k / mu where the cells wear
  only in slip (q = mu p there);
- ``<name>_fretting_map.png``, for a campaign of two axes (amplitude and load, say): the
  worn volume per load cycle of the last solved cycle over the two axes, each case marked by
  its regime in that cycle (partial slip: a stick zone left; gross slip: none), the
  Vingsbo and Soderberg map with wear;
- ``<name>_wear_profiles.png`` and ``<name>_wear_pressure.png``: the worn depth and the
  pressure along x through the contact axis at checkpoints (solved cycles spread over the
  path, from the case files' ``cycle_wear_profile`` and ``cycle_pressure_profile``), a panel
  per case.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .. import analysis
from . import figures

#: Most cases drawn with their profiles (a panel each), and checkpoints per panel.
MAX_PANELS, CHECKPOINTS = 9, 5
#: The checkpoint figures: case-file field -> (file suffix, scale, axis label, title).
PROFILES = {
    "cycle_wear_profile": ("wear_profiles", 1e6, "worn depth (um), both bodies", "Worn profile"),
    "cycle_pressure_profile": ("wear_pressure", 1e-6, "pressure (MPa)", "Pressure"),
}
#: Where each checkpoint figure's legends go: the middle of a worn profile is the unworn
#: stick zone, the pressure's sides are empty.
LEGENDS = {
    "cycle_wear_profile": "center",
    "cycle_pressure_profile": "best",
}


def is_wear(dataset) -> bool:
    """Whether the campaign's cases wear (their per-cycle wear rate is stored)."""
    return "wear_rate" in dataset


def _cases(dataset) -> list[tuple[dict, dict, object]]:
    return [
        (labels, isel, case)
        for labels, isel, case in analysis.finished_cases(dataset)
        if np.isfinite(case["wear_rate"].values).any()
    ]


def totals(case) -> dict[str, np.ndarray]:
    """Per solved cycle of one case: load cycles done, worn volume and friction energy so far.

    Each solved cycle counts the load cycles it stands for (``load_cycles``' steps).
    """
    done = case["load_cycles"].values
    kept = np.isfinite(done)
    done = done[kept]
    stood = np.diff(done, prepend=0.0)
    volume = np.cumsum(case["wear_rate"].values[kept] * stood)
    out = {"load_cycles": done, "volume": volume}
    if "cycle_friction_work" in case:
        out["energy"] = np.cumsum(case["cycle_friction_work"].values[kept] * stood)
    return out


def wear_table(dataset):
    """One row per finished case that wears (module docstring).

    Returns
    -------
    pandas.DataFrame
    """
    import pandas as pd

    rows = []
    for labels, _, case in _cases(dataset):
        summed = totals(case)
        rate = case["wear_rate"].values
        rate = rate[np.isfinite(rate)]
        energy = summed.get("energy", [np.nan])[-1]
        row = {**labels, "cycles": int(summed["load_cycles"][-1]), "solved": rate.size}
        row |= {"volume_m3": summed["volume"][-1], "energy_J": energy}
        row |= {"volume_per_J": summed["volume"][-1] / energy if energy > 0 else np.nan}
        row |= {"rate_first_m3": rate[0], "rate_last_m3": rate[-1]}
        if "max_wear_depth_history" in case:
            depth = case["max_wear_depth_history"].values
            row["depth_m"] = float(np.nanmax(depth)) if np.isfinite(depth).any() else np.nan
        rows.append(row)
    return pd.DataFrame(rows)


def plot_energy(dataset, path: str | Path) -> Path | None:
    """The worn volume against the friction energy dissipated, one line per case."""
    plt = figures.pyplot()
    cases = [c for c in _cases(dataset) if "cycle_friction_work" in c[2]][: figures.MAX_LINES]
    if plt is None or not cases:
        return None
    rows = -(-(len(cases) + 1) // 2)  # the legend's rows below the axes
    fig, ax = plt.subplots(figsize=(6.4, 4.2 + 0.18 * rows), layout="constrained")
    statuses = []
    for k, (labels, isel, case) in enumerate(cases):
        summed = totals(case)
        statuses.append(figures.status_of(dataset, isel))
        style = figures.series_style(k, len(cases), summed["volume"].size, statuses[-1])
        ax.loglog(summed["energy"], summed["volume"] * 1e18, **style,
                  label=figures.labels_text(labels))  # fmt: skip
    ax.set_xlabel("friction energy dissipated (J), summed over the load cycles")
    ax.set_ylabel("worn volume (um^3)")
    ax.grid(True, which="both", alpha=0.3)
    handles = ax.get_legend_handles_labels()[0] + figures.status_handle(statuses)
    fig.legend(handles=handles, loc="outside lower center", ncols=2, fontsize=7)  # clear of lines
    figures.suptitle(
        fig, f"{dataset.attrs.get('campaign', '')}: worn volume against friction energy",
        figures.status_note(statuses),
    )  # fmt: skip
    figures.save(plt, fig, path)
    return Path(path)


def _axis_values(dataset, dim: str) -> tuple[str, np.ndarray]:
    """The name and the values that label an axis (its own coordinate, else its first)."""
    if dim in dataset.coords:
        return dim, dataset[dim].values
    name = next(c for c in dataset.coords if dataset[c].dims == (dim,))
    return name, dataset[name].values


def _axis_key(dataset, dim: str) -> str:
    """The campaign key an axis sweeps ("" when not told)."""
    return str(dataset[_axis_values(dataset, dim)[0]].attrs.get("campaign_key", ""))


def plot_map(dataset, path: str | Path) -> Path | None:
    """The fretting map with wear over a campaign's two axes (module docstring)."""
    plt = figures.pyplot()
    dims = analysis.axis_dims(dataset)
    cases = _cases(dataset)
    if plt is None or len(dims) != 2 or not cases or "min_stick_radius" not in dataset:
        return None
    from matplotlib.colors import LogNorm

    shifted = [d for d in dims if "tangential" in _axis_key(dataset, d)]
    dims = shifted + [d for d in dims if d not in shifted]  # the amplitude along x
    (xname, xs), (yname, ys) = (_axis_values(dataset, d) for d in dims)
    points = []  # (x, y, rate, gross slip, status)
    for _, isel, case in cases:
        rate = case["wear_rate"].values
        last = np.flatnonzero(np.isfinite(rate))[-1]
        stick = float(case["min_stick_radius"].values[last])
        x, y = xs[isel[dims[0]]], ys[isel[dims[1]]]
        points.append((x, y, rate[last] * 1e18, stick == 0.0, figures.status_of(dataset, isel)))
    fig, ax = plt.subplots(figsize=(6.0, 4.4), layout="constrained")
    rates = [p[2] for p in points]
    norm = LogNorm(min(rates), max(rates)) if min(rates) > 0 else None
    for gross, marker, label in ((False, "^", "partial slip"), (True, "o", "gross slip")):
        chosen = [p for p in points if p[3] == gross]
        if chosen:
            drawn = ax.scatter([p[0] for p in chosen], [p[1] for p in chosen],
                               c=[p[2] for p in chosen], norm=norm, cmap="viridis", s=90,
                               marker=marker, edgecolors="k", label=label)  # fmt: skip
    untrusted = [p for p in points if p[4] in figures.UNTRUSTED]
    if untrusted:
        ax.scatter([p[0] for p in untrusted], [p[1] for p in untrusted], s=260,
                   facecolors="none", edgecolors="red", linestyles="--")  # fmt: skip
    fig.colorbar(drawn, ax=ax, label="worn volume per load cycle (um^3), last solved cycle")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(f"{xname} ({figures.units_of(dataset, xname) or '-'})")
    ax.set_ylabel(f"{yname} ({figures.units_of(dataset, yname) or '-'})")
    ax.grid(True, which="both", alpha=0.3)
    from matplotlib.lines import Line2D

    ax.minorticks_off()  # ticks at the cases' values (log axes' minor labels overlap)
    for values, axis in (([p[0] for p in points], ax.xaxis), ([p[1] for p in points], ax.yaxis)):
        ticks = sorted(set(values))
        axis.set_ticks(ticks, labels=[f"{v:.3g}" for v in ticks])
    regimes = [(False, "^", "partial slip"), (True, "o", "gross slip")]
    handles = [Line2D([], [], ls="", marker=m, color="0.5", markeredgecolor="k", label=t)
               for gross, m, t in regimes if any(p[3] == gross for p in points)]  # fmt: skip
    ax.legend(handles=handles, fontsize=8, loc="best")
    statuses = [p[4] for p in points]
    figures.suptitle(fig, f"{dataset.attrs.get('campaign', '')}: fretting map with wear",
                     figures.status_note(statuses, "ringed in red"))  # fmt: skip
    figures.save(plt, fig, path)
    return Path(path)


def plot_checkpoints(dataset, out: str | Path, field: str, path: str | Path) -> Path | None:
    """A case-file profile (:data:`PROFILES`) at checkpoints, a panel per case."""
    from ..run import storage

    plt = figures.pyplot()
    if plt is None:
        return None
    stored = storage.case_index(out)
    panels = []
    for labels, isel, case in _cases(dataset):
        case_id = str(case["case_id"].item())
        if case_id not in stored.results:
            continue
        with storage.open_case(out, case_id, index=stored) as data:
            if field not in data:
                continue
            rows = data[field].values
            x = data["x"].values.astype(float)
        done = case["load_cycles"].values
        done = done[np.isfinite(done)][: rows.shape[0]]
        picks = np.unique(np.linspace(0, rows.shape[0] - 1, CHECKPOINTS).round().astype(int))
        panels.append((labels, isel, x, rows[picks], done[picks]))
        if len(panels) == MAX_PANELS:
            break
    if not panels:
        return None
    _, scale, ylabel, title = PROFILES[field]
    fig, axes, _ = figures.panel_grid(plt, len(panels), 4.2, 3.2)
    statuses = []
    for ax, (labels, isel, x, rows, done) in zip(axes, panels, strict=True):
        statuses.append(figures.status_of(dataset, isel))
        for j, (row, cycles) in enumerate(zip(rows, done, strict=True)):
            style = figures.series_style(j, len(rows), x.size, statuses[-1])
            done = f"after {int(cycles):,} cycle" + ("s" if cycles != 1 else "")
            ax.plot(x * 1e3, row * scale, **style, label=done)
        ax.set_xlabel("x (mm), through the contact axis")
        ax.set_ylabel(ylabel)
        ax.set_title(figures.title(labels, dataset=dataset), fontsize=8)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=6, loc=LEGENDS[field])
        figures.mark_panel(ax, [statuses[-1]])
    figures.suptitle(
        fig, f"{dataset.attrs.get('campaign', '')}: {title.lower()} at checkpoints",
        figures.status_note(statuses, "red dashed frame"),
    )  # fmt: skip
    figures.save(plt, fig, path)
    return Path(path)


def section(dataset, out: Path, name: str, plt, shown: list) -> list[str]:
    """Markdown lines of the wear part of the report (figures appended to ``shown``)."""
    lines = ["## Wear", ""]
    lines += [
        "`cycles`: load cycles (jumps counted), `solved`: cycles solved; `volume_m3` and",
        "`energy_J`: worn volume (both bodies) and friction energy dissipated over the load",
        "cycles; `rate_*`: volume worn per load cycle in the first and the last solved cycle;",
        "`depth_m`: the deepest wear.",
        "",
        figures.markdown_table(wear_table(dataset)),
        "",
    ]
    if plt is None:
        return lines
    made = [
        ("Fretting map", plot_map(dataset, out / f"{name}_fretting_map.png")),
        ("Worn volume against energy", plot_energy(dataset, out / f"{name}_wear_energy.png")),
    ]
    for field, (suffix, _, _, title) in PROFILES.items():
        png = plot_checkpoints(dataset, out, field, out / f"{name}_{suffix}.png")
        made.append((f"{title} at checkpoints", png))
    for title, png in made:
        if png:
            shown.append((title, png, "every finished case that wears"))
            lines += [f"### {title}", "", f"![{title}]({png.name})", ""]
    return lines
