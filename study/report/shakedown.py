"""The shakedown part of a campaign report: each case's regime and the shakedown map.

For campaigns whose cases repeat a load on an elastic-plastic body (cycle blocks: fretting
cycles, passes of a moving contact) the dataset holds the regime of every case
(``shakedown``, :mod:`solver.theory.shakedown`) and its evidence, the plastic strain gained per
cycle.  This section writes

- a table per case: peak pressure over the shear yield stress p_0/k, friction coefficient,
  regime, the pressure up to which the case's final residual stress proves shakedown under
  the sliding Hertz load (Melan's static theorem, :func:`solver.theory.shakedown.melan_factor`),
  cycles, the gain of the first and the last cycle and the net tensor change of the last one;
- ``<name>_shakedown_map.png``: p_0/k against mu, one marker per case coloured by its regime,
  with first yield under a sliding point contact (Hamilton's field,
  :func:`solver.theory.shakedown.sliding_first_yield`), Melan's certified lower bound (direct)
  and the upper bounds beside it, pointwise and Koiter's kinematic one (:func:`static_curve`:
  the classical limit, for an unchanging surface;
  the cases put the print into the gap), the line mu p_0 = k (above it the sliding
  shear at Hertz's peak exceeds what a perfectly plastic surface can carry:
  :attr:`solver.plasticity.hardening.Hardening.shear_limit`) and each converged case's Melan
  bound drawn over it.
"""

from __future__ import annotations

import functools
from pathlib import Path

import numpy as np

from solver.result import STATUS_FLAGS
from solver.theory.shakedown import SHAKEDOWN_FLAGS, net_trend, sliding_first_yield

from .. import analysis
from . import figures

#: Marker colour of each regime on the map.
COLOURS = {
    "undetermined": "0.6",
    "elastic": "tab:green",
    "elastic_shakedown": "tab:blue",
    "plastic_shakedown": "tab:orange",
    "ratchetting": "tab:red",
}


def _cases(dataset) -> list[dict]:
    """One record per finished case: labels, p_0/k, mu, regime, status, cycle gains."""
    regimes = {v: k for k, v in SHAKEDOWN_FLAGS.items()}
    statuses = {v: k for k, v in STATUS_FLAGS.items()}
    out = []
    for labels, _, case in analysis.finished_cases(dataset):
        gain = case["plastic_strain_increment"].values
        # a Hertz contact's peak pressure; none on a rough interface (periodic mode)
        p0 = float(case["hertz_pressure"]) if "hertz_pressure" in case else np.nan
        done = gain[np.isfinite(gain)]
        net = case["net_plastic_strain_increment"].values[: done.size]
        out.append(
            {
                "labels": labels,
                "p0/k": p0 / float(case["shear_yield_stress"]),
                "mu": float(case["friction_coefficient"]),
                "regime": regimes.get(int(case["shakedown"]), "?"),
                "melan p0/k": (
                    p0 * float(case["melan_factor"]) / float(case["shear_yield_stress"])
                    if "melan_factor" in case
                    else np.nan
                ),
                "status": statuses.get(int(case["status"]), "?"),
                "cycles": done.size,
                "gain_first": done[0] if done.size else np.nan,
                "gain_last": done[-1] if done.size else np.nan,
                "net_last": net[-1] if net.size else np.nan,
                "net/gain": net[-1] / done[-1] if net.size and done[-1] > 0 else np.nan,
                "net_trend": net_trend(net),
            }
        )
    return out


def shakedown_table(dataset):
    """Per case: p_0/k, mu, regime, status, cycles, first and last gain, last net change.

    Returns
    -------
    pandas.DataFrame
        One row per finished case.
    """
    import pandas as pd

    columns = (
        "p0/k", "mu", "regime", "melan p0/k", "status", "cycles", "gain_first", "gain_last",
        "net_last", "net/gain", "net_trend",
    )  # fmt: skip
    table = pd.DataFrame([{**c["labels"], **{k: c[k] for k in columns}} for c in _cases(dataset)])
    return table.dropna(axis=1, how="all")  # no Melan factor: not a sliding campaign


@functools.lru_cache(maxsize=512)
def _first_yield(mu: float, nu: float) -> float:
    """p_0/k of first yield at one friction coefficient (a search: kept for the next report)."""
    return sliding_first_yield(mu, nu)[0]


def first_yield_curve(mu_max: float, nu: float, points: int = 41) -> tuple[np.ndarray, np.ndarray]:
    """(mu, p_0/k) of first yield under a sliding point contact, mu from 0 to ``mu_max``."""
    mu = np.linspace(0.0, mu_max, points)
    return mu, np.array([_first_yield(round(float(m), 12), nu) for m in mu])


#: Cross-section cells a contact radius of the static limit drawn over an incremental map (a
#: second or two a point; 1 % above the fine-mesh limit at mu = 0).
STATIC_CELLS = 4
#: Cells a contact radius of the map's Koiter mechanisms (coarser ones lie well above the limit:
#: 2 % frictionless at a/4, 0.4 % at a/8).
KINEMATIC_CELLS = 8


def static_curve(mu_max: float, nu: float, step: float = 0.1) -> tuple[np.ndarray, ...]:
    """(mu, certified lower bound, pointwise and kinematic upper bounds) p_0/k of a sliding sphere.

    Perfect plasticity; Melan's and Koiter's theorems solved directly
    (:func:`solver.theorems.track.track_limits`) on cells of a/:data:`STATIC_CELLS` and
    mechanisms of a/:data:`KINEMATIC_CELLS`, mu from 0 to ``mu_max`` every ``step``.
    """
    mu = np.arange(0.0, mu_max + 1e-9, step)
    bounds = np.array([_theorem_bounds(round(float(m), 12), nu) for m in mu])
    return (mu, *bounds.T)


@functools.lru_cache(maxsize=64)
def _theorem_bounds(mu: float, nu: float) -> tuple[float, float, float]:
    """The lower, pointwise and kinematic p_0/k at one mu.

    Seconds of conic programs: solved once per process (every report drawn in a session draws
    the same curve).
    """
    from solver.theorems.track import Track, track_limits

    limits = track_limits(Track("point", mu, nu, STATIC_CELLS), KINEMATIC_CELLS)
    return limits.lower, limits.upper, limits.kinematic.factor


def plot_map(dataset, path: str | Path, nu: float | None) -> Path | None:
    """p_0/k against mu, a marker per case (shape and colour: its regime); first yield over it.

    Cases not converged, truncated or in surface flow are ringed in red.
    """
    cases = [case for case in _cases(dataset) if np.isfinite(case["p0/k"])]
    if not cases:  # no Hertz contact (a rough interface): the map's axes are not theirs
        return None
    plt = figures.pyplot()
    fig, ax = plt.subplots(figsize=(6.0, 5.4), layout="constrained")
    for j, (regime, colour) in enumerate(COLOURS.items()):
        mine = [c for c in cases if c["regime"] == regime]
        if mine:
            ax.scatter(
                [c["mu"] for c in mine], [c["p0/k"] for c in mine], c=colour, s=45,
                marker=figures.MARKERS[j], label=regime.replace("_", " "), edgecolors="k",
                linewidths=0.5, zorder=3,
            )  # fmt: skip
    unconverged = [c for c in cases if c["status"] in figures.UNTRUSTED]
    if unconverged:  # a red ring round each case not trusted (figures.UNTRUSTED)
        ax.scatter(
            [c["mu"] for c in unconverged], [c["p0/k"] for c in unconverged], s=150,
            facecolors="none", edgecolors=figures.STATUS_COLOUR, linewidths=1.5, zorder=4,
            label=" or ".join(sorted({figures.UNTRUSTED[c["status"]] for c in unconverged})),
        )  # fmt: skip
    # a case that did not converge has no trusted residual field: no bound drawn from it
    melan = [c for c in cases if np.isfinite(c["melan p0/k"]) and c["status"] == "converged"]
    if melan:
        ax.scatter(
            [c["mu"] for c in melan], [c["melan p0/k"] for c in melan], marker="_", s=120,
            c="k", label="Melan's bound from each case's residual stress", zorder=2,
        )  # fmt: skip
    mu_max = max(0.1, 1.1 * max(c["mu"] for c in cases))
    if nu is not None:
        mu, ratio = first_yield_curve(mu_max, nu)
        ax.plot(mu, ratio, "k-", lw=1, label=f"first yield (Hamilton 1983, nu = {nu:g})")
        mu, static, upper, kinematic = static_curve(mu_max, nu)
        ax.plot(mu, static, "-", color="tab:purple", lw=1.2,
                label=f"Melan's certified lower bound (cells a/{STATIC_CELLS})")  # fmt: skip
        ax.plot(mu, upper, "--", color="tab:purple", lw=1, label="its pointwise upper bound")
        koiter = f"Koiter's kinematic upper bound (triangles a/{KINEMATIC_CELLS})"
        ax.plot(mu, kinematic, "-.", color="tab:purple", lw=1, label=koiter)
    # mu p_0 = k: past it the sliding shear at Hertz's peak exceeds the shear a perfectly
    # plastic surface can carry (solver.plasticity.hardening.Hardening.shear_limit)
    top = ax.get_ylim()[1]
    if mu_max > 1.0 / top:
        mu = np.linspace(1.0 / top, mu_max, 41)
        ax.plot(mu, 1.0 / mu, "k--", lw=1, label="mu p_0 = k: the sliding shear reaches k")
    ax.set_xlim(-0.02, mu_max)
    ax.set_xlabel("traction coefficient mu (sliding) (1)")
    ax.set_ylabel("p_0 / k (1)")
    # below the axes: every marker of the map stays visible
    fig.legend(fontsize=7, loc="outside lower center", ncol=2)
    ax.grid(alpha=0.3)
    total = int(np.prod([dataset.sizes[d] for d in dataset["status"].dims]))
    shown = f"{len(cases)} of {total} cases" + (
        " (the others failed or are pending: not drawn)" if len(cases) < total else ""
    )
    if unconverged:
        told = " or ".join(sorted({figures.UNTRUSTED[c["status"]] for c in unconverged}))
        shown += f"; {len(unconverged)} {told} (ringed, no Melan bound drawn)"
    figures.suptitle(fig, f"{dataset.attrs.get('campaign', '')}: shakedown map", shown)
    figures.save(plt, fig, path)
    return Path(path)


def section(dataset, out: Path, name: str, plt, shown: list, nu: float | None) -> list[str]:
    """Markdown lines of the shakedown part of the report (figures appended to ``shown``)."""
    lines = ["## Shakedown", ""]
    lines += [
        "`regime`: solver.theory.shakedown.classify of the plastic strain gained per cycle (the",
        "largest over the volume): elastic (never yields), elastic shakedown (the last cycle",
        "gains less than 1e-3 of the largest), plastic shakedown (a steady gain whose net tensor",
        "change is below 0.1 of it), ratchetting (a steady net gain), undetermined (not",
        "converged, or still settling: more cycles). `gain_*`: equivalent plastic strain gained",
        "in the first and the last cycle; `net_last`: equivalent strain of the plastic strain",
        "tensor's change over the last cycle, `net/gain` its share of the last gain (closed",
        "below 0.1), `net_trend` its rate per cycle over the last three (below 0.9: still",
        "falling; the case's reason says how many more cycles it needs). `surface_flow`",
        "status: the surface shear passed what the body can carry (regime undetermined).",
        "`melan p0/k`: the peak pressure up to which the",
        "case's final residual stress keeps the sliding Hertz load (Hamilton's field, every",
        "loaded position) inside the yield surface: Melan's static lower bound from that field.",
        "",
        figures.markdown_table(shakedown_table(dataset)),
        "",
    ]
    if plt is None:
        return lines
    png = plot_map(dataset, out / f"{name}_shakedown_map.png", nu)
    if png:
        shown.append(("Shakedown map", png, "every finished case with a regime"))
        lines += ["### Map", "", f"![shakedown map]({png.name})", ""]
    return lines
