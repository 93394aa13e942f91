"""The static-shakedown part of a campaign report: Melan's limits solved directly, and the map.

For campaigns whose cases ask ``solver.method = "static_shakedown"`` (:mod:`solver.theorems`)
the dataset holds per case the static program's factor on the section's points (an estimate),
its certified lower bound, the pointwise and Koiter's kinematic upper bounds and first yield,
all as p_0/k.  This section writes

- a table per case: its labels, mu, the static estimate, the lower bound, the upper bounds,
  first yield, the surface-flow line 1/mu, the factor of the case's own load that shakes down,
  status, interior-point iterations, wall time.  A lower bound above an upper bound of its
  case is never printed as one (:func:`_cases` blanks it and says so in ``bracket``);
- ``<name>_static_shakedown_map.png``: p_0/k against mu: the lower bound and the upper bounds
  of every case, the estimate, first yield, the line mu p_0 = k, the regimes between them
  (elastic, elastic shakedown, plastic shakedown, ratchetting) and the literature's points
  (Ponter, Hearle & Johnson's 4.7 k at mu = 0; the surface limit mu p_0 = k).

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
    "static_shakedown_lower_bound": "lower bound p0/k",
    "static_shakedown_limit": "static estimate p0/k",
    "shakedown_upper_bound": "upper p0/k",
    "kinematic_upper_bound": "kinematic p0/k",
    "first_yield_limit": "first yield p0/k",
    "shakedown_load_factor": "load factor",
    "program_iterations": "iterations",
}


#: The table's lower bound and the upper bounds it must not exceed.
LOWER = "lower bound p0/k"
UPPER = ("upper p0/k", "kinematic p0/k")
#: Ponter, Hearle & Johnson (1985): a frictionless point contact's limit (kinematic), p_0/k.
PONTER_POINT = 4.7
#: The surface binds (ratchetting at the surface above the limit) where the pointwise bound
#: reaches this fraction of the surface limit mu p_0 = k.
SURFACE_BINDS = 0.95


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
        uppers = [row.get(key, np.inf) for key in UPPER]
        lower = row.get(LOWER, np.nan)
        row["bracket"] = "ok"
        if not lower <= min(uppers):  # above an upper bound (or not computed): not a bound
            row[LOWER] = np.nan
            row["bracket"] = "no lower bound" if np.isnan(lower) else "withheld: above an upper"
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
    """p_0/k against mu: the bounds, first yield, mu p_0 = k, the regimes, the literature."""
    cases = sorted(_cases(dataset), key=lambda c: c["mu"])
    if not cases:
        return None
    plt = figures.pyplot()
    fig, ax = plt.subplots(figsize=(6.4, 5.6), layout="constrained")
    draw_limits(ax, cases)
    mu_max = max(0.1, 1.05 * max(c["mu"] for c in cases))
    draw_surface_flow(ax, mu_max)
    draw_literature(ax, cases)
    draw_regimes(ax, cases)
    ax.set_xlim(-0.02, mu_max)
    ax.set_xlabel("traction coefficient mu (sliding) (1)")
    ax.set_ylabel("p_0 / k (1)")
    ax.grid(alpha=0.3)
    fig.legend(fontsize=7, loc="outside lower center", ncol=2)
    untrusted = [c for c in cases if c["status"] != "converged"]
    shown = f"{len(cases)} cases" + (
        f"; {len(untrusted)} not converged or truncated (hollow)" if untrusted else ""
    )
    withheld = [c for c in cases if c["bracket"] != "ok"]
    if withheld:
        shown += f"; {len(withheld)} lower bound(s) above an upper bound withheld"
    figures.suptitle(fig, f"{dataset.attrs.get('campaign', '')}: static shakedown map", shown)
    figures.save(plt, fig, path)
    return Path(path)


def draw_limits(ax, cases: list[dict], label: str = "") -> None:
    """The lower and upper bounds, the estimate and first yield of theorem cases (by mu)."""
    mu = np.array([c["mu"] for c in cases])
    trusted = np.array([c["status"] == "converged" for c in cases])
    for key, style, name in (
        (LOWER, "o-", "Melan: certified lower bound"),
        ("static estimate p0/k", "x:", "Melan: program's points (estimate)"),
        ("upper p0/k", "v--", "pointwise upper bound"),
        ("kinematic p0/k", "^-.", "Koiter: kinematic upper bound"),
        ("first yield p0/k", "k-", "first yield"),
    ):
        values = np.array([c.get(key, np.inf) for c in cases])
        if not np.isfinite(values).any():
            continue  # not solved (elliptical contacts, kinematic_cells = 0, older files)
        line = ax.plot(mu, values, style, lw=1.2, ms=5, label=name + label)[0]
        if not trusted.all() and key != "first yield p0/k":
            ax.scatter(mu[~trusted], values[~trusted], s=60, facecolors="none",
                       edgecolors=line.get_color(), zorder=4)  # fmt: skip


def draw_literature(ax, cases: list[dict]) -> None:
    """Ponter, Hearle & Johnson's 4.7 k at mu = 0 (a point contact, kinematic)."""
    if min(c["mu"] for c in cases) > 0.05:
        return
    ax.plot([0.0], [PONTER_POINT], "*", color="tab:red", ms=11, zorder=5,
            label="Ponter et al. 1985: 4.7 k at mu = 0")  # fmt: skip


def draw_regimes(ax, cases: list[dict]) -> None:
    """Name the regions between first yield, the limit and above it (Johnson's map).

    Below first yield the passes stay elastic; up to the lower bound they shake down
    elastically; between the bounds nothing is decided (unshaded); above the smaller upper
    bound the plastic strain cycles (plastic shakedown) where the limit is set below the
    surface, and accumulates (ratchetting) where the surface binds (mu p_0 = k).
    """
    mu = np.array([c["mu"] for c in cases])
    first = np.array([c.get("first yield p0/k", np.nan) for c in cases])
    lower = np.array([c.get(LOWER, np.nan) for c in cases])
    limit = np.where(np.isfinite(lower), lower, first)
    if not np.isfinite(first).any():
        return
    bottom, top = 0.0, float(np.nanmax(limit)) * 1.3
    ax.set_ylim(bottom, top)
    ax.fill_between(mu, bottom, first, color="tab:green", alpha=0.08, lw=0)
    ax.fill_between(mu, first, limit, color="tab:blue", alpha=0.08, lw=0)
    bounds = [np.array([c.get(key, np.inf) for c in cases]) for key in UPPER]
    above = np.minimum(np.fmin(*bounds), top)  # between the bounds: undecided (unshaded)
    ax.fill_between(mu, np.where(np.isfinite(above), above, limit), top, color="tab:red",
                    alpha=0.06, lw=0)  # fmt: skip
    style = {"fontsize": 8, "ha": "center", "va": "center", "color": "0.2"}
    low, high = mu[0], mu[-1]
    ax.text(low + 0.3 * (high - low), 0.45 * np.nanmin(first), "elastic", **style)
    j = int(np.argmin(np.abs(mu - (low + 0.25 * (high - low)))))
    ax.text(mu[j], 0.5 * (first[j] + limit[j]), "elastic\nshakedown", **style)
    upper = np.array([c.get("upper p0/k", np.nan) for c in cases])
    surface = mu * upper >= SURFACE_BINDS  # the pointwise bound on mu p_0 = k: the surface
    below = ~surface
    ceiling = 0.5 * (float(np.nanmax(limit)) + top)
    if below.any():
        ax.text(float(np.mean(mu[below])), ceiling, "plastic shakedown\n(below the surface)",
                **style)  # fmt: skip
    if surface.any():
        ax.text(float(np.mean(mu[surface])), ceiling, "ratchetting\n(at the surface)", **style)


def draw_surface_flow(ax, mu_max: float) -> None:
    """The line mu p_0 = k: past it the sliding shear at Hertz's peak exceeds k."""
    top = ax.get_ylim()[1]
    if mu_max > 1.0 / top:
        mu = np.linspace(1.0 / top, mu_max, 41)
        ax.plot(mu, 1.0 / mu, "k:", lw=1, label="surface limit mu p_0 = k")


def section(dataset, out: Path, name: str, plt, shown: list) -> list[str]:
    """Markdown lines of the static-shakedown part (figures appended to ``shown``)."""
    lines = ["## Static shakedown (Melan's theorem solved directly)", ""]
    lines += [
        "`lower bound p0/k`: Melan's certified lower bound: the static program's residual",
        "field, bilinear between the section's points, keeps the sliding Hertz field within",
        "yield at the points halfway between them, between the load positions and where the",
        "pointwise bound was found (solver.theorems.track.certified_limit); blank, with",
        "`bracket` saying so, where it would lie above an upper bound of its case;",
        "`static estimate p0/k`: the program's optimum at the section's points only (a",
        "second-order cone program): an estimate of the limit, not a bound (the points sample",
        "the field, and on a Hertz track it approaches the limit from above);",
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
