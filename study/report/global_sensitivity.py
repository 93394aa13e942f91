"""The global-sensitivity part of a report: a sampled campaign's Sobol' or Morris indices.

For a campaign with a ``[sample]`` design (:mod:`study.campaign.sample`) this section writes

- the design: method, count, seed, cases, and each input's distribution;
- with Saltelli's design, per quantity that varies, Sobol' first-order and total indices with
  their bootstrap intervals (:func:`study.analysis.global_sensitivity.sobol_indices`), and
  ``<name>_sobol.png``: one panel per quantity, S1 and ST bars with the intervals;
- with Morris' trajectories, ``mu*``, ``sigma`` and the interval of ``mu*``
  (:func:`~study.analysis.global_sensitivity.morris_indices`), and ``<name>_morris.png``:
  sigma against mu* per quantity (screening: large mu* matters, large sigma interacts or is
  nonlinear);
- with a space-filling design (Latin hypercube, Sobol' sequence): the note that it gives no
  indices, and ``<name>_scatter.png``: each quantity against each input.

Other dimensions beside ``sample`` give one table per combination of their values; the
figures show the first combination.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .. import analysis
from ..analysis import global_sensitivity as gsa
from . import figures
from .tables import reduction_words

#: Most quantities drawn (panels of a figure).
MAX_QUANTITIES = 12


def section(dataset, out: Path, name: str, plt, shown: list) -> list[str]:
    """Markdown lines of the global-sensitivity part (figures appended to ``shown``)."""
    method = gsa.design_method(dataset)
    inputs = gsa.sampled_inputs(dataset)
    lines = ["## Global sensitivity", ""]
    lines += [
        f"Design: `{method}`, count {dataset.attrs['sample_count']}, seed "
        f"{dataset.attrs['sample_seed']}, {dataset.sizes[gsa.SAMPLE_DIM]} rows "
        f"({len(set(dataset['case_id'].values.ravel()))} distinct cases).",
        "",
        "| input | distribution |",
        "|---|---|",
        *(
            f"| `{i}` | {d} |"
            for i, d in zip(inputs, dataset["sample_distribution"].values, strict=True)
        ),
        "",
    ]
    names = gsa.result_quantities(dataset)[:MAX_QUANTITIES]
    if not names:
        return [*lines, "_No quantity varies over the finished cases._", ""]
    if method == "saltelli":
        lines += [
            "Sobol' indices (SALib): `S1` the share of the quantity's variance due to the input",
            "alone, `ST` with all its interactions; `*_conf` the half-widths of the "
            f"{gsa.CONFIDENCE:.0%} bootstrap intervals ({gsa.RESAMPLES} resamples); `samples`",
            "the complete base samples used, `left_out` those with a case not finished.",
            "",
        ]
        tables = {q: gsa.sobol_indices(dataset, q) for q in names}
        draw = _plot_sobol
    elif method == "morris":
        lines += [
            "Morris' screening (SALib): `mu_star` the mean absolute elementary effect, `sigma`",
            "their spread (interaction or nonlinearity), per unit quantile level of the input",
            "(the unit hypercube), in the quantity's units; `mu_star_conf` the "
            f"{gsa.CONFIDENCE:.0%} bootstrap half-width.",
            "",
        ]
        tables = {q: gsa.morris_indices(dataset, q) for q in names}
        draw = _plot_morris
    else:
        lines += [
            f"A `{method}` design fills the space but gives no indices (use `saltelli` for",
            "Sobol' indices, `morris` for screening); the figure plots the quantities against",
            "the inputs.",
            "",
        ]
        tables, draw = {}, _plot_scatter
    for q, table in tables.items():
        said = [figures.units_of(dataset, q), reduction_words(q)]  # units, reduction
        lines += [f"### `{q}` ({', '.join(filter(None, said))})", ""]
        lines.append(figures.markdown_table(table))
    if plt is not None:
        png = draw(plt, dataset, names, tables, out / f"{name}_{method}.png")
        shown.append((f"Global sensitivity ({method})", png, f"{len(names)} quantities"))
        lines += [f"![global sensitivity]({png.name})", ""]
    return lines


def _first_slice(table):
    """The rows of the first combination of the other dimensions' values."""
    count = len(set(table["input"]))
    return table.iloc[:count]


def _plot_sobol(plt, dataset, names, tables, path: Path) -> Path:
    fig, axes, _ = figures.panel_grid(plt, len(names), 3.4, 2.6)
    for ax, q in zip(axes, names, strict=True):
        table = _first_slice(tables[q])
        x = np.arange(len(table))
        for shift, key, label in ((-0.2, "S1", "first order"), (0.2, "ST", "total")):
            ax.bar(x + shift, table[key], 0.4, yerr=table[f"{key}_conf"], capsize=3, label=label)
        ax.set_xticks(x, table["input"], rotation=30, ha="right", fontsize=7)
        ends = [
            table[key] + sign * table[f"{key}_conf"] for key in ("S1", "ST") for sign in (-1, 1)
        ]
        low, high = float(np.nanmin(ends)), float(np.nanmax(ends))  # whole intervals shown
        ax.set_ylim(min(0.0, low) - 0.02, max(1.0, high) + 0.05)
        ax.set_title(q, fontsize=9)
        ax.axhline(0.0, color="0.5", lw=0.5)
    axes[0].legend(fontsize=7)
    figures.suptitle(fig, f"Sobol' indices with {gsa.CONFIDENCE:.0%} bootstrap intervals")
    figures.save(plt, fig, path)
    return path


def _plot_morris(plt, dataset, names, tables, path: Path) -> Path:
    fig, axes, _ = figures.panel_grid(plt, len(names), 3.4, 2.8)
    for ax, q in zip(axes, names, strict=True):
        table = _first_slice(tables[q])
        ax.errorbar(table["mu_star"], table["sigma"], xerr=table["mu_star_conf"], fmt="o")
        for _, row in table.iterrows():
            ax.annotate(row["input"], (row["mu_star"], row["sigma"]), fontsize=7)
        ax.set_xlabel(f"mu* ({figures.units_of(dataset, q)})", fontsize=8)
        ax.set_ylabel("sigma", fontsize=8)
        ax.set_title(q, fontsize=9)
    figures.suptitle(fig, "Morris screening: mu* (with its interval) and sigma per input")
    figures.save(plt, fig, path)
    return path


def _plot_scatter(plt, dataset, names, tables, path: Path) -> Path:
    del tables
    inputs = gsa.sampled_inputs(dataset)
    first = next(analysis.sweep_slices(dataset, [gsa.SAMPLE_DIM]))[1]
    sub = dataset.isel(first).where(analysis.finished_mask(dataset.isel(first)))
    fig, axes, _ = figures.panel_grid(plt, len(names) * len(inputs), 2.4, 2.0)
    for k, (q, i) in enumerate((q, i) for q in names for i in inputs):
        ax = axes[k]
        ax.plot(sub[i].values, sub[q].values, ".", ms=2)
        ax.set_xlabel(i, fontsize=7)
        ax.set_ylabel(q, fontsize=7)
    figures.suptitle(fig, "The quantities against the sampled inputs")
    figures.save(plt, fig, path)
    return path
