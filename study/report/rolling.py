"""The rolling part of a campaign report: creep force against creepage, pass by pass.

For a campaign that sweeps a rolling stage's creepage (an axis whose campaign key ends in
``creepage``) and whose cases record the creep force of every pass (``creep_force_x``,
:data:`solver.variables.CYCLE_QUANTITIES`), this section writes

- a table: the creep force over mu W at the end of each pass, per case;
- ``<name>_creep_curves.png``: creep force over mu W against the creepage, one line per pass
  and per value of the other axes (the elastic-plastic track's passes beside the elastic
  pair's, say).

For a campaign whose cases have steady rolling stages (``steady = true``: histories
``creepage_x``, ``tangential_force_x`` per step) each case is a creep curve of its own: a
table of each case's last point and ``<name>_steady_creep_curves.png``, the creep force over
mu W against the creepage xi of every steady step, a line per case, with full slip at 1.
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
    """One record per value of the other axes: labels, creepages, creep force / (mu W) per pass.

    Each record also holds the ``status`` of each case (:func:`figures.status_of`).
    """
    usable = analysis.finished_mask(dataset)
    out = []
    for labels, isel in analysis.sweep_slices(dataset, [axis]):
        rows = dataset.isel(isel)
        creepage, ratio, status = [], [], []
        for i in range(rows.sizes[axis]):
            case = rows.isel({axis: i})
            if not bool(usable.isel(isel).isel({axis: i})):
                continue
            scale = float(case["friction_coefficient"]) * _normal_force(case)
            creepage.append(float(case[axis]))
            ratio.append(case["creep_force_x"].values / scale)
            status.append(figures.status_of(rows, {axis: i}))
        if creepage:
            out.append(
                {
                    "labels": labels,
                    "creepage": np.array(creepage),
                    "ratio": np.array(ratio),
                    "status": status,
                }
            )
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
    """Creep force over mu W against the creepage, a line per pass and per other-axes value.

    Every line (a pass of one value of the other axes) in its own colour, marker and line
    style (:func:`figures.series_style`), so passes that coincide stay visible; the points of
    cases not converged or truncated are hollow.
    """
    found = curves(dataset, axis)
    if not found:
        return None
    plt = figures.pyplot()
    fig, ax = plt.subplots(figsize=(6.4, 4.5), layout="constrained", dpi=figures.DPI)
    total = sum(curve["ratio"].shape[1] for curve in found)
    j, statuses = 0, []
    for curve in found:
        bad = np.array([s in figures.UNTRUSTED for s in curve["status"]])
        statuses += curve["status"]
        for c in range(curve["ratio"].shape[1]):  # passes that coincide: each its own style
            style = figures.series_style(j, total)
            ax.plot(curve["creepage"], curve["ratio"][:, c], **style,
                    label=f"{figures.labels_text(curve['labels'])}, pass {c + 1}")  # fmt: skip
            if bad.any():  # the untrusted cases hollow, over the line's markers
                hollow = figures.series_style(j, total, status="truncated")
                hollow.update(linestyle="none", gid="untrusted point")
                hollow["zorder"] += 0.01
                ax.plot(curve["creepage"][bad], curve["ratio"][bad, c], **hollow)
            j += 1
    ax.axhline(1.0, color="k", lw=0.8, ls=":")
    ax.set_xlabel(f"creepage {axis} (1)")
    ax.set_ylabel("creep force / (mu W) at the end of the pass (1)")
    handles = ax.get_legend_handles_labels()[0] + figures.status_handle(statuses)
    ax.legend(handles=handles, fontsize=6, loc="lower right")
    ax.grid(alpha=0.3)
    figures.suptitle(
        fig,
        f"{dataset.attrs.get('campaign', '')}: creep curves",
        "pass by pass",
        figures.status_note(statuses, "hollow markers"),
    )
    figures.save(plt, fig, path)
    return Path(path)


def steady_curves(dataset) -> list[dict]:
    """Per finished case with steady steps: labels, creepage xi, F_x / (mu W), status."""
    out = []
    for labels, isel, case in analysis.finished_cases(dataset):
        xi = case["creepage_x_history"].values
        steady = np.flatnonzero(np.isfinite(xi) & (xi != 0.0))
        if steady.size == 0:
            continue
        scale = float(case["friction_coefficient"]) * _normal_force(case)
        out.append({
            "labels": labels, "creepage": xi[steady],
            "ratio": case["tangential_force_x_history"].values[steady] / scale,
            "status": figures.status_of(dataset, isel),
        })  # fmt: skip
    return out


def plot_steady(dataset, path: str | Path) -> Path | None:
    """F_x / (mu W) against the creepage of every steady step, a line per case."""
    found = steady_curves(dataset)
    if not found:
        return None
    plt = figures.pyplot()
    fig, ax = plt.subplots(figsize=(6.4, 4.5), layout="constrained", dpi=figures.DPI)
    statuses = [curve["status"] for curve in found]
    for j, curve in enumerate(found):
        style = figures.series_style(j, len(found), status=curve["status"])
        ax.plot(curve["creepage"], curve["ratio"], **style,
                label=figures.labels_text(curve["labels"]))  # fmt: skip
    ax.axhline(1.0, color="k", lw=0.8, ls=":", label="full slip: mu W")
    ax.set_xlabel("creepage xi (1)")
    ax.set_ylabel("creep force F_x / (mu W) (1)")
    handles = ax.get_legend_handles_labels()[0] + figures.status_handle(statuses)
    ax.legend(handles=handles, fontsize=6, loc="lower right")
    ax.grid(alpha=0.3)
    figures.suptitle(
        fig,
        f"{dataset.attrs.get('campaign', '')}: steady creep curves",
        "each steady step solved directly",
        figures.status_note(statuses, "hollow markers"),
    )
    figures.save(plt, fig, path)
    return Path(path)


def steady_section(dataset, out: Path, name: str, plt, shown: list) -> list[str]:
    """Markdown lines of the steady creep curves (figure appended to ``shown``)."""
    found = steady_curves(dataset) if "creepage_x_history" in dataset else []
    if not found:
        return []
    import pandas as pd

    table = pd.DataFrame(
        [
            {**c["labels"], "steps": c["creepage"].size, "last xi": c["creepage"][-1],
             "last F_x/(mu W)": c["ratio"][-1], "status": c["status"]}
            for c in found
        ]
    )  # fmt: skip
    lines = ["## Steady creep curves", ""]
    lines += [
        "Each case's steady rolling steps (`steady = true`): the creep force on body 2 along x",
        "over mu W against the creepage xi (`creepage_x`); the table gives each curve's last",
        "point.",
        "",
        figures.markdown_table(table),
        "",
    ]
    if plt is None:
        return lines
    png = plot_steady(dataset, out / f"{name}_steady_creep_curves.png")
    if png:
        shown.append(("Steady creep curves", png, "every finished case"))
        lines += [f"![steady creep curves]({png.name})", ""]
    return lines


def section(dataset, out: Path, name: str, plt, shown: list) -> list[str]:
    """Markdown lines of the rolling part of the report (figures appended to ``shown``)."""
    lines = steady_section(dataset, out, name, plt, shown)
    axis = creepage_axis(dataset)
    if axis is None or "creep_force_x" not in dataset:
        return lines
    lines += ["## Creep curves", ""]
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
