"""The static-shakedown part of a campaign report: Melan's limits solved directly, and the map.

For campaigns whose cases ask ``solver.method = "static_shakedown"`` (:mod:`solver.theorems`)
the dataset holds per case the static limit (a residual field proves it), the pointwise and
Koiter's kinematic upper bounds beside it and first yield, all as p_0/k.  This section writes

- a table per case: its labels, mu, the static limit, the upper bounds, first yield, the
  surface-flow line 1/mu, the factor of the case's own load that shakes down, status,
  interior-point iterations, wall time;
- ``<name>_static_shakedown_map.png``: p_0/k against mu: the static limit (lower bound) and the
  upper bounds of every converged case, first yield, the line mu p_0 = k.

The incremental shakedown map (:mod:`.shakedown`) draws the static limit over its cases too.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from solver.result import STATUS_FLAGS

from .. import analysis
from . import figures

#: The dataset variables of the section, as table columns.
COLUMNS = {
    "static_shakedown_limit": "static p0/k",
    "shakedown_upper_bound": "upper p0/k",
    "kinematic_upper_bound": "kinematic p0/k",
    "first_yield_limit": "first yield p0/k",
    "shakedown_load_factor": "load factor",
    "program_iterations": "iterations",
}


def is_theorem(dataset) -> bool:
    """Whether the campaign's cases were solved by the static theorem."""
    return "static_shakedown_limit" in dataset


def _cases(dataset) -> list[dict]:
    statuses = {v: k for k, v in STATUS_FLAGS.items()}
    out = []
    for labels, _, case in analysis.finished_cases(dataset):
        if not np.isfinite(float(case["static_shakedown_limit"])):
            continue  # an incremental case of a mixed campaign
        mu = float(case["friction_coefficient"])
        row = {"labels": labels, "mu": mu}
        row.update({title: float(case[name]) for name, title in COLUMNS.items() if name in case})
        row["1/mu"] = 1.0 / mu if mu > 0.0 else np.inf
        row["status"] = statuses.get(int(case["status"]), "?")
        row["wall_s"] = float(case["wall_time"]) if "wall_time" in case else np.nan
        out.append(row)
    return out


def theorem_table(dataset):
    """One row per finished static-shakedown case (pandas.DataFrame)."""
    import pandas as pd

    rows = [
        {**c["labels"], **{k: v for k, v in c.items() if k != "labels"}} for c in _cases(dataset)
    ]
    return pd.DataFrame(rows)


def plot_map(dataset, path: str | Path) -> Path | None:
    """p_0/k against mu: static limits, upper bounds, first yield, mu p_0 = k."""
    cases = sorted(_cases(dataset), key=lambda c: c["mu"])
    if not cases:
        return None
    plt = figures.pyplot()
    fig, ax = plt.subplots(figsize=(6.0, 5.0), layout="constrained")
    draw_limits(ax, cases)
    mu_max = max(0.1, 1.05 * max(c["mu"] for c in cases))
    draw_surface_flow(ax, mu_max)
    ax.set_xlim(-0.02, mu_max)
    ax.set_xlabel("traction coefficient mu (sliding) (1)")
    ax.set_ylabel("p_0 / k (1)")
    ax.grid(alpha=0.3)
    fig.legend(fontsize=7, loc="outside lower center", ncol=2)
    untrusted = [c for c in cases if c["status"] != "converged"]
    shown = f"{len(cases)} cases" + (
        f"; {len(untrusted)} not converged or truncated (hollow)" if untrusted else ""
    )
    figures.suptitle(fig, f"{dataset.attrs.get('campaign', '')}: static shakedown map", shown)
    figures.save(plt, fig, path)
    return Path(path)


def draw_limits(ax, cases: list[dict], label: str = "") -> None:
    """The static limits, upper bounds and first yield of theorem cases (sorted by mu)."""
    mu = np.array([c["mu"] for c in cases])
    trusted = np.array([c["status"] == "converged" for c in cases])
    for key, style, name in (
        ("static p0/k", "o-", "Melan's static limit on the section's cells"),
        ("upper p0/k", "v--", "pointwise upper bound"),
        ("kinematic p0/k", "^-.", "Koiter's kinematic upper bound"),
        ("first yield p0/k", "k-", "first yield"),
    ):
        values = np.array([c.get(key, np.inf) for c in cases])
        if not np.isfinite(values).any():
            continue  # not solved (elliptical contacts, kinematic_cells = 0, older files)
        line = ax.plot(mu, values, style, lw=1.2, ms=5, label=name + label)[0]
        if not trusted.all() and key != "first yield p0/k":
            ax.scatter(mu[~trusted], values[~trusted], s=60, facecolors="none",
                       edgecolors=line.get_color(), zorder=4)  # fmt: skip


def draw_surface_flow(ax, mu_max: float) -> None:
    """The line mu p_0 = k: past it the sliding shear at Hertz's peak exceeds k."""
    top = ax.get_ylim()[1]
    if mu_max > 1.0 / top:
        mu = np.linspace(1.0 / top, mu_max, 41)
        ax.plot(mu, 1.0 / mu, "k:", lw=1, label="mu p_0 = k: the sliding shear reaches k")


def section(dataset, out: Path, name: str, plt, shown: list) -> list[str]:
    """Markdown lines of the static-shakedown part (figures appended to ``shown``)."""
    lines = ["## Static shakedown (Melan's theorem solved directly)", ""]
    lines += [
        "`static p0/k`: the largest peak pressure over k for which a residual stress field on",
        "the track's cross-section keeps every load position of the sliding Hertz field within",
        "yield at the section's points (solver.theorems.melan, a second-order cone program,",
        "certified for the field found): Melan's limit on the mesh, which converges to the",
        "limit as the cells shrink (from above where one point binds: the points sample it);",
        "`upper p0/k`: no constant residual shift at one point does better (an upper bound",
        "whatever the mesh); `kinematic p0/k`: Koiter's upper bound, the best mechanism on the",
        "cross-section's six-node triangles (solver.theorems.koiter; inf where not solved);",
        "`first yield p0/k`: the elastic limit;",
        "`1/mu`: the line mu p_0 = k; `load factor`: the static limit over the case's own",
        "p_0/k (below 1: the case's load does not shake down).",
        "",
        figures.markdown_table(theorem_table(dataset)),
        "",
    ]
    if plt is None:
        return lines
    png = plot_map(dataset, out / f"{name}_static_shakedown_map.png")
    if png:
        shown.append(("Static shakedown map", png, "every finished case"))
        lines += ["### Map", "", f"![static shakedown map]({png.name})", ""]
    return lines
