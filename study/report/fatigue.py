"""The fatigue part of a campaign report: the factors of safety under the pass, as a map.

For a campaign whose cases have a ``[fatigue]`` table (the scalars ``dang_van_factor``,
``crossland_factor`` and their depths) :func:`section` writes

- a table per case: each criterion's smallest factor of safety and its depth over the contact
  radius (under a load cycle where along x too), and the case's shakedown regime when the
  campaign has one;
- ``<name>_fatigue_map.png``, for p_0/k against mu (a shakedown campaign: the same axes as its
  shakedown map) or any two axes: each criterion's factor per case in a panel of its own,
  coloured, the regime as the marker, the cases not trusted ringed in red.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from solver.result import STATUS_FLAGS
from solver.theory.shakedown import SHAKEDOWN_FLAGS

from .. import analysis
from . import figures
from .shakedown import COLOURS

#: The criteria, their labels.
CRITERIA = {"dang_van": "Dang Van", "crossland": "Crossland"}


def is_fatigue(dataset) -> bool:
    """Whether the campaign's cases tell their fatigue under the pass."""
    return "dang_van_factor" in dataset


def _cases(dataset) -> list[dict]:
    regimes = {v: k for k, v in SHAKEDOWN_FLAGS.items()}
    statuses = {v: k for k, v in STATUS_FLAGS.items()}
    out = []
    for labels, isel, case in analysis.finished_cases(dataset):
        if not np.isfinite(float(case["dang_van_factor"])):
            continue
        radius = float(case["hertz_radius"]) if "hertz_radius" in case else np.nan
        row = {"labels": labels, "isel": isel, "status": statuses.get(int(case["status"]), "?")}
        if "shakedown" in case:
            row["regime"] = regimes.get(int(case["shakedown"]), "?")
        if "shear_yield_stress" in case and "hertz_pressure" in case:
            row["p0/k"] = float(case["hertz_pressure"]) / float(case["shear_yield_stress"])
            row["mu"] = float(case["friction_coefficient"])
        for name in CRITERIA:
            row[f"{name}_factor"] = float(case[f"{name}_factor"])
            row[f"{name}_depth/a"] = float(case[f"{name}_depth"]) / radius
            where = float(case[f"{name}_x"]) if f"{name}_x" in case else np.nan
            if np.isfinite(where):  # a load cycle's: where along x
                row[f"{name}_x/a"] = where / radius
        out.append(row)
    return out


def fatigue_table(dataset):
    """One row per finished case with a ``[fatigue]`` table (module docstring).

    Returns
    -------
    pandas.DataFrame
    """
    import pandas as pd

    rows = []
    for case in _cases(dataset):
        row = {**case["labels"]}
        row |= {k: v for k, v in case.items() if k.endswith(("_factor", "depth/a", "_x/a"))}
        row |= {"regime": case["regime"]} if "regime" in case else {}
        rows.append(row | {"status": case["status"]})
    return pd.DataFrame(rows)


def plot_fatigue_map(dataset, path: str | Path) -> Path | None:
    """Each criterion's smallest factor of safety over p_0/k and mu (module docstring)."""
    plt = figures.pyplot()
    cases = [c for c in _cases(dataset) if "p0/k" in c]
    if plt is None or not cases:
        return None
    from matplotlib.colors import Normalize

    fig, axes, _ = figures.panel_grid(plt, len(CRITERIA), 4.6, 4.0, extra=0.8)
    factors = [c[f"{name}_factor"] for c in cases for name in CRITERIA]
    norm = Normalize(min(factors), max(factors))
    for ax, (name, label) in zip(axes, CRITERIA.items(), strict=True):
        for j, regime in enumerate([*COLOURS, None]):
            mine = [c for c in cases if c.get("regime") == regime]
            if not mine:
                continue
            drawn = ax.scatter(
                [c["mu"] for c in mine], [c["p0/k"] for c in mine],
                c=[c[f"{name}_factor"] for c in mine], cmap="RdYlGn", norm=norm, s=110,
                marker=figures.MARKERS[j], edgecolors="k", linewidths=0.6, zorder=3,
            )  # fmt: skip
            for c in mine:
                ax.annotate(f"{c[f'{name}_factor']:.2f}", (c["mu"], c["p0/k"]), fontsize=6,
                            xytext=(6, 4), textcoords="offset points")  # fmt: skip
        untrusted = [c for c in cases if c["status"] in figures.UNTRUSTED]
        if untrusted:
            ax.scatter([c["mu"] for c in untrusted], [c["p0/k"] for c in untrusted], s=260,
                       facecolors="none", edgecolors=figures.STATUS_COLOUR, linewidths=1.5,
                       zorder=4)  # fmt: skip
        ax.set_xlabel("friction coefficient mu (1)")
        ax.set_ylabel("p_0 / k (1)")
        ax.set_title(f"{label}: smallest factor of safety", fontsize=9)
        ax.grid(alpha=0.3)
        ax.margins(0.12)
    from matplotlib.lines import Line2D

    shown = [r for r in [*COLOURS, None] if any(c.get("regime") == r for c in cases)]
    handles = [
        Line2D([], [], ls="", marker=figures.MARKERS[[*COLOURS, None].index(r)], color="0.5",
               markeredgecolor="k", label=(r or "no regime").replace("_", " "))
        for r in shown
    ]  # fmt: skip
    fig.legend(handles=handles, loc="outside lower center", ncols=len(handles), fontsize=7,
               title="marker: the case's shakedown regime", title_fontsize=7)  # fmt: skip
    fig.colorbar(drawn, ax=axes, label="factor of safety (torsion limit over the stress)")
    statuses = [c["status"] for c in cases]
    figures.suptitle(fig, f"{dataset.attrs.get('campaign', '')}: fatigue under the pass",
                     figures.status_note(statuses, "ringed in red"))  # fmt: skip
    figures.save(plt, fig, path)
    return Path(path)


def section(dataset, out: Path, name: str, plt, shown: list) -> list[str]:
    """Markdown lines of the fatigue part of the report (figures appended to ``shown``)."""
    lines = ["## Fatigue under the pass", ""]
    lines += [
        "`*_factor`: each criterion's smallest factor of safety over body 2 (the torsion limit",
        "over its equivalent stress; solver.drive.fatigue), `*_depth/a` where it is, over the",
        "contact radius; `regime`: the case's shakedown regime (the criteria assume an elastic",
        "shakedown: read them with it).",
        "",
        figures.markdown_table(fatigue_table(dataset)),
        "",
    ]
    if plt is None:
        return lines
    png = plot_fatigue_map(dataset, out / f"{name}_fatigue_map.png")
    if png:
        shown.append(("Fatigue map", png, "every finished case with a [fatigue] table"))
        lines += ["### Map", "", f"![fatigue map]({png.name})", ""]
    return lines
