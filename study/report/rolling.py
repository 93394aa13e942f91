"""The rolling part of a campaign report: creep force against creepage, pass by pass.

For a campaign that sweeps a rolling stage's creepage (an axis whose campaign key ends in
``creepage``) and whose cases record the creep force of every pass (``creep_force_x``,
:data:`solver.variables.CYCLE_QUANTITIES`), this section writes

- a table: the creep force over mu W at the end of each pass, per case;
- ``<name>_creep_curves.png``: creep force over mu W against the creepage, one line per pass
  and per value of the other axes (the elastic-plastic track's passes beside the elastic
  pair's, say).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .. import analysis
from . import figures


def creepage_axis(dataset) -> str | None:
    """The dimension that sweeps a creepage, if any."""
    for dim in dataset["status"].dims:
        if str(dataset[dim].attrs.get("campaign_key", "")).endswith("creepage"):
            return dim
    return None


def _normal_force(case) -> float:
    """The case's largest normal force (N)."""
    if "hertz_normal_force" in case:
        return float(case["hertz_normal_force"])
    return float(np.nanmax(case["normal_force_history"].values))


def curves(dataset, axis: str) -> list[dict]:
    """One record per value of the other axes: labels, creepages, creep force / (mu W) per pass."""
    usable = analysis.finished_mask(dataset)
    out = []
    for labels, isel in analysis.sweep_slices(dataset, [axis]):
        rows = dataset.isel(isel)
        creepage, ratio = [], []
        for i in range(rows.sizes[axis]):
            case = rows.isel({axis: i})
            if not bool(usable.isel(isel).isel({axis: i})):
                continue
            scale = float(case["friction_coefficient"]) * _normal_force(case)
            creepage.append(float(case[axis]))
            ratio.append(case["creep_force_x"].values / scale)
        if creepage:
            out.append({"labels": labels, "creepage": np.array(creepage), "ratio": np.array(ratio)})
    return out


def creep_table(dataset, axis: str):
    """Per finished case: its labels, the creepage and F/(mu W) at the end of every pass."""
    import pandas as pd

    rows = []
    for curve in curves(dataset, axis):
        for creepage, ratios in zip(curve["creepage"], curve["ratio"], strict=True):
            passes = {f"pass {c + 1}": ratio for c, ratio in enumerate(ratios)}
            rows.append({**curve["labels"], axis: creepage, **passes})
    return pd.DataFrame(rows)


def plot_curves(dataset, axis: str, path: str | Path) -> Path | None:
    """Creep force over mu W against the creepage, a line per pass and per other-axes value."""
    found = curves(dataset, axis)
    if not found:
        return None
    plt = figures.pyplot()
    fig, ax = plt.subplots(figsize=(6.4, 4.5))
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for k, curve in enumerate(found):
        colour = colours[k % len(colours)]
        passes = curve["ratio"].shape[1]
        for c in range(passes):
            ax.plot(
                curve["creepage"], curve["ratio"][:, c], marker="o", ms=3, color=colour,
                alpha=0.4 + 0.6 * (c + 1) / passes,
                label=f"{figures.labels_text(curve['labels'])}, pass {c + 1}",
            )  # fmt: skip
    ax.axhline(1.0, color="k", lw=0.8, ls=":")
    ax.set_xlabel(f"creepage {axis} (1)")
    ax.set_ylabel("creep force / (mu W) at the end of the pass")
    ax.legend(fontsize=6, loc="lower right")
    ax.grid(alpha=0.3)
    figures.suptitle(fig, f"{dataset.attrs.get('campaign', '')}: creep curves", "pass by pass")
    figures.save(plt, fig, path)
    return Path(path)


def section(dataset, out: Path, name: str, plt, shown: list) -> list[str]:
    """Markdown lines of the rolling part of the report (figures appended to ``shown``)."""
    axis = creepage_axis(dataset)
    if axis is None or "creep_force_x" not in dataset:
        return []
    lines = ["## Creep curves", ""]
    lines += [
        "Creep force on body 2 along x over mu W at the end of every pass (`creep_force_x`),",
        f"against the creepage `{axis}`; 1 is full slip.",
        "",
        figures.markdown_table(creep_table(dataset, axis)),
        "",
    ]
    if plt is None:
        return lines
    png = plot_curves(dataset, axis, out / f"{name}_creep_curves.png")
    if png:
        shown.append(("Creep curves", png, "every finished case, every pass"))
        lines += [f"![creep curves]({png.name})", ""]
    return lines
