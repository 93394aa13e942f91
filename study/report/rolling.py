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
mu W against the creepage xi of every steady step, a line per case, with the saturation
F_x = mu W at 1 and each case's Kalker linear law F_x = G a b C11 xi dashed up to mu W
(:func:`kalker_slope`, C11 from :func:`solver.theory.friction.kalker_coefficients`); and
``<name>_steady_tractions.png``, the shear traction of chosen points of a few curves with the
stick area hatched (:func:`traction_points`: the last step from the case file, the steps
nearest F_x / (mu W) = 0.3 and 0.7 re-solved from the case's table).
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
    if "hertz_normal_force" in case and np.isfinite(case["hertz_normal_force"]):
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


#: Force over mu W of the steady points whose traction the report draws, besides each drawn
#: case's last point (the step nearest each level is re-solved: the case files hold the
#: fields of the last step only).
TRACTION_LEVELS = (0.3, 0.7)
#: Most cases whose tractions are drawn (spread over the finished steady cases).
MAX_TRACTION_CASES = 3
#: A case whose stored wall time (s) is longer than this gets no point re-solved.
RESOLVE_BUDGET = 60.0
#: Largest difference, over mu W, between a re-solved point's force and the stored one.
RESOLVE_TOLERANCE = 1e-3


def _case_spec(out: str | Path | None, case, index=None) -> dict | None:
    """The case table (``case_spec``) stored with the case's result, or None.

    Parameters
    ----------
    out : str or Path or None
        Campaign output folder (None: no table).
    case : xarray.Dataset
        The case's dataset row.
    index : study.run.storage.CaseIndex, optional
        The folder's case index (:func:`study.run.storage.case_index`), built when omitted.
    """
    import json

    from ..run import storage

    if out is None:
        return None
    index = storage.case_index(out) if index is None else index
    case_id = str(case["case_id"].item())
    if case_id not in index.results:
        return None
    with storage.open_case(out, case_id, index=index) as stored:
        text = stored.attrs.get("case_spec", "")
    return json.loads(text) if text else None


def kalker_slope(spec: dict) -> dict:
    """Kalker's linear law F_x = G a b C11 xi of a case, from its own solver objects.

    Parameters
    ----------
    spec : dict
        The case table (``case_spec`` of its file).

    Returns
    -------
    dict
        ``G`` the pair's shear modulus (Pa, 2/G = 1/G1 + 1/G2), ``nu`` the pair's Poisson's
        ratio (1, nu/G = (nu1/G1 + nu2/G2)/2, Kalker's), ``a``, ``b`` the Hertz semi-axes
        along and across the rolling direction x (m), ``C11`` (1, NaN when not drawn),
        ``slope`` = G a b C11 (N per unit creepage, NaN when not drawn) and ``reason`` (empty,
        or why the slope is not drawn: bodies not quasi-identical, a ratio or nu outside
        Kalker's table).
    """
    import solver
    from solver.theory.friction import kalker_coefficients

    nan = float("nan")
    out = {"G": nan, "nu": nan, "a": nan, "b": nan, "C11": nan, "slope": nan}
    try:
        case = solver.Case.from_dict(spec)
        if case.grid.periodic_y:
            reason = "a line contact: Carter's closed form (solver.theory.line) is its reference"
            return {**out, "reason": reason}
        pair, hertz = case.pair, case.hertz
    except ValueError as error:  # a table this version refuses, a profile (no Hertz contact)
        return {**out, "reason": f"no Hertz contact of the case's table ({error})"}
    shear_modulus, nu = pair.rolling_shear_modulus, pair.rolling_poisson_ratio
    a, b = hertz.semi_axis_x, hertz.semi_axis_y
    out.update({"G": shear_modulus, "nu": nu, "a": a, "b": b, "reason": ""})
    if abs(pair.dundurs_beta) > 1e-9:
        out["reason"] = (
            f"Dundurs' beta = {pair.dundurs_beta:.3g}: Kalker's linear theory is for "
            "quasi-identical bodies"
        )
        return out
    try:
        out["C11"] = kalker_coefficients(nu, a / b)[0]
    except ValueError as error:
        out["reason"] = str(error)
        return out
    out["slope"] = shear_modulus * a * b * out["C11"]
    return out


def steady_curves(dataset, out: str | Path | None = None) -> list[dict]:
    """Per finished case with steady steps: labels, creepage xi, F_x / (mu W), status.

    With ``out`` each record also holds ``kalker`` (:func:`kalker_slope` of the case's stored
    table, or None without its stored result), ``spec`` (the table); every record holds
    ``steps`` (the indices of the steady steps along ``step``), ``scale`` (mu W, N) and
    ``case`` (the case's dataset row).

    Parameters
    ----------
    dataset : xarray.Dataset
        Campaign dataset.
    out : str or Path, optional
        Campaign output folder (the cases' tables are read from it).

    Returns
    -------
    list of dict
        One record per finished case with steady steps.
    """
    index = None
    if out is not None:
        from ..run import storage

        index = storage.case_index(out)
    found = []
    for labels, isel, case in analysis.finished_cases(dataset):
        xi = case["creepage_x_history"].values
        steady = np.flatnonzero(np.isfinite(xi) & (xi != 0.0))
        if steady.size == 0:
            continue
        scale = float(case["friction_coefficient"]) * _normal_force(case)
        record = {
            "labels": labels, "creepage": xi[steady],
            "ratio": case["tangential_force_x_history"].values[steady] / scale,
            "status": figures.status_of(dataset, isel),
            "steps": steady, "scale": scale, "case": case,
        }  # fmt: skip
        if out is not None:
            spec = _case_spec(out, case, index)
            record["spec"] = spec
            record["kalker"] = kalker_slope(spec) if spec is not None else None
        found.append(record)
    return found


def _kalker_reason(curve: dict) -> str:
    """Why a curve has no Kalker slope drawn (empty when it has one)."""
    kalker = curve.get("kalker")
    if kalker is None:
        return "no case file with the case's table"
    return kalker["reason"]


def plot_steady(dataset, path: str | Path, found: list[dict] | None = None) -> Path | None:
    """F_x / (mu W) against the creepage of every steady step, a line per case.

    Each case with a Kalker slope (:func:`steady_curves` with the cases' folder) also gets
    Kalker's linear law F_x = G a b C11 xi as a thin dashed line of its colour, from xi = 0 to
    where it reaches mu W; the saturation F_x = mu W is the black dotted line at 1.
    """
    found = steady_curves(dataset) if found is None else found
    if not found:
        return None
    from matplotlib.lines import Line2D

    plt = figures.pyplot()
    fig, ax = plt.subplots(figsize=(6.4, 4.8), layout="constrained", dpi=figures.DPI)
    statuses = [curve["status"] for curve in found]
    linear = False
    for j, curve in enumerate(found):
        style = figures.series_style(j, len(found), status=curve["status"])
        ax.plot(curve["creepage"], curve["ratio"], **style,
                label=figures.labels_text(curve["labels"]))  # fmt: skip
        kalker = curve.get("kalker")
        if kalker is not None and np.isfinite(kalker["slope"]):
            reach = curve["scale"] / kalker["slope"]  # xi where the linear law gives mu W
            ax.plot([0.0, reach], [0.0, 1.0], color=style["color"], lw=0.9, ls=(0, (4, 2)),
                    zorder=1.5, gid="kalker slope")  # fmt: skip
            linear = True
    ax.axhline(1.0, color="k", lw=1.0, ls=":", gid="saturation")
    ax.set_xlim(0.0, max(float(curve["creepage"].max()) for curve in found) * 1.02)
    ax.set_ylim(0.0, 1.12)
    ax.set_xlabel("creepage xi (1)")
    ax.set_ylabel("creep force F_x / (mu W) (1)")
    handles = ax.get_legend_handles_labels()[0]
    handles.append(Line2D([], [], color="k", lw=1.0, ls=":", label="saturation F_x = mu W"))
    if linear:
        handles.append(Line2D([], [], color="0.3", lw=0.9, ls=(0, (4, 2)),
                              label="Kalker linear: G a b C11 xi"))  # fmt: skip
    handles += figures.status_handle(statuses)
    ax.legend(handles=handles, fontsize=6, loc="lower right")
    ax.grid(alpha=0.3)
    figures.suptitle(
        fig,
        f"{dataset.attrs.get('campaign', '')}: steady creep curves",
        "each steady step solved directly"
        + ("; dashed: Kalker's linear law of each case, up to mu W" if linear else ""),
        figures.status_note(statuses, "hollow markers"),
    )
    figures.save(plt, fig, path)
    return Path(path)


def _traction_cases(found: list[dict]) -> list[dict]:
    """At most :data:`MAX_TRACTION_CASES` curves with a table, spread over ``found``."""
    usable = [curve for curve in found if curve.get("spec") is not None]
    if len(usable) <= MAX_TRACTION_CASES:
        return usable
    picks = np.linspace(0, len(usable) - 1, MAX_TRACTION_CASES).round().astype(int)
    return [usable[k] for k in sorted(set(picks))]


def _steady_table(spec: dict, case, step: int) -> dict | None:
    """The case's table solving one steady step directly (None if its path is not simple).

    The stages before the first steady stage, then that stage at the step's creepage and spin
    in one increment: a steady state depends on its creepage only, not on the ramp to it.
    """
    path = spec["load"]["path"]
    first = next((k for k, s in enumerate(path) if s.get("steady")), None)
    if first is None or any("cycles" in s for s in path[: first + 1]):
        return None
    stage = {k: v for k, v in path[first].items() if k not in ("steps", "tangential_force")}
    stage["creepage"] = [float(case[f"creepage_{c}_history"].values[step]) for c in "xy"]
    spin = float(case["spin_history"].values[step]) if "spin_history" in case else 0.0
    stage.pop("spin", None)
    if spin:
        stage["spin"] = spin
    stage["steps"] = 1
    return {**spec, "load": {"path": [*path[:first], stage]}}


def traction_points(found: list[dict], out: str | Path) -> tuple[list[dict], list[str]]:
    """The steady points whose traction is drawn, and notes on the points not drawn.

    Per chosen case (:func:`_traction_cases`): the steady steps nearest F_x / (mu W) =
    :data:`TRACTION_LEVELS` (re-solved from the case's table, :func:`_steady_table`, and kept
    only if their force matches the stored one within :data:`RESOLVE_TOLERANCE` of mu W) and
    the last step (the fields of the case file).

    Parameters
    ----------
    found : list of dict
        The curves of :func:`steady_curves` (with the output folder).
    out : str or Path
        Campaign output folder.

    Returns
    -------
    (list of dict, list of str)
        Per point: ``curve``, ``index`` (into the curve's steps), ``source`` ("stored" or
        "re-solved"), ``x``, ``y`` (cell centres, m), ``pressure``, ``shear_x``, ``shear_y``
        (Pa), ``state`` (:data:`solver.result.STICK` ...), ``force`` (F_x / (mu W) of the
        fields) and ``match`` (the fields' force minus the stored history's, over mu W; the
        case file's fields are kept only as the last steady step's, within
        :data:`RESOLVE_TOLERANCE`).
    """
    import solver

    from ..run import storage

    index = storage.case_index(out)
    points, notes = [], []
    for curve in _traction_cases(found):
        case, name = curve["case"], figures.labels_text(curve["labels"])
        chosen = []
        for level in TRACTION_LEVELS:
            k = int(np.argmin(np.abs(curve["ratio"] - level)))
            if k != curve["ratio"].size - 1 and k not in chosen:
                chosen.append(k)
        wall = float(case["wall_time"]) if "wall_time" in case else 0.0
        if chosen and wall > RESOLVE_BUDGET:
            notes.append(f"{name}: not re-solved (its wall time exceeds {RESOLVE_BUDGET:g} s)")
            chosen = []
        for k in sorted(chosen):
            table = _steady_table(curve["spec"], case, int(curve["steps"][k]))
            try:
                result = solver.solve(solver.Case.from_dict(table)) if table else None
            except ValueError:  # the one-step table refused
                result = None
            if result is None or result.status != "converged":
                notes.append(f"{name}: xi = {curve['creepage'][k]:.4g} not re-solved")
                continue
            force = result.history["tangential_force_x"][-1] / curve["scale"]
            match = force - curve["ratio"][k]
            if abs(match) > RESOLVE_TOLERANCE:
                notes.append(
                    f"{name}: xi = {curve['creepage'][k]:.4g} re-solved to F_x/(mu W) = "
                    f"{force:.4f}, stored {curve['ratio'][k]:.4f}: not drawn"
                )
                continue
            points.append({
                "curve": curve, "index": k, "source": "re-solved", "x": result.grid.x,
                "y": result.grid.y, "pressure": result.pressure, "shear_x": result.shear_x,
                "shear_y": result.shear_y, "state": result.contact_state, "force": force,
                "match": match,
            })  # fmt: skip
        names = ("x", "y", "pressure", "shear_x", "shear_y", "contact_state")
        with storage.open_case(out, str(case["case_id"].item()), index=index) as stored:
            fields = {k: stored[k].values for k in names if k in stored}
        if len(fields) < len(names):
            notes.append(f"{name}: the case file holds no traction fields of its last step")
            continue
        fields["state"] = fields.pop("contact_state")
        cell = (fields["x"][1] - fields["x"][0]) * (fields["y"][1] - fields["y"][0])
        force = float(fields["shear_x"].sum()) * cell / curve["scale"]
        last = curve["ratio"].size - 1
        match = force - curve["ratio"][last]
        if abs(match) > RESOLVE_TOLERANCE:  # a stage after the steady ones
            notes.append(f"{name}: the case file's fields are not its last steady step")
            continue
        points.append({"curve": curve, "index": last, "source": "stored", **fields,
                       "force": force, "match": match})  # fmt: skip
    return points, notes


def _line_panel(ax, point: dict, half_width: float) -> None:
    """A line contact's point: q_x / (mu p0) along x with Carter's traction, stick shaded.

    Carter's closed form (:func:`solver.theory.line.carter_traction`) from the case's Hertz
    strip (``line_half_width``, ``line_pressure``; the radius from ``b^2 = 4 w R / (pi E*)``)
    and the point's creepage.
    """
    from solver.result import STICK
    from solver.theory.line import carter_traction

    curve = point["curve"]
    case = curve["case"]
    mu = float(case["friction_coefficient"])
    p0 = float(case["line_pressure"])
    radius = (
        np.pi * float(case["composite_modulus"]) * half_width**2
        / (4.0 * float(case["line_force_per_length"]))
    )  # fmt: skip
    row = point["state"].shape[1] // 2
    x = point["x"]
    xi = float(curve["creepage"][point["index"]])
    ax.plot(x / half_width, point["shear_x"][:, row] / (mu * p0), "o", ms=2.5, label="q_x")
    fine = np.linspace(x.min(), x.max(), 400)
    carter = carter_traction(fine, xi, mu, half_width, radius, p0) / (mu * p0)
    ax.plot(fine / half_width, carter, "k-", lw=0.8, label="Carter")
    ax.plot(x / half_width, point["pressure"][:, row] / p0, color="0.6", lw=0.8, label="p / p0")
    stick = x[point["state"][:, row] == STICK] / half_width
    if stick.size:
        ax.axvspan(stick.min(), stick.max(), color="tab:green", alpha=0.15, label="stick")
    ax.set_title(
        f"{figures.title(curve['labels'], width=44)}\nxi = {xi:.3g}, F_x/(mu W) = "
        f"{point['force']:.3f}, {point['source']}",
        fontsize=7,
    )
    ax.set_xlim(-1.3, 1.3)
    ax.set_xlabel("x / b (1), rolling to +x", fontsize=8)
    ax.set_ylabel("q_x / (mu p0), p / p0 (1)", fontsize=8)
    ax.legend(fontsize=6, loc="upper left")
    figures.mark_panel(ax, [curve["status"]])


def _semi_axes(curve: dict) -> tuple[float, float]:
    """Hertz's semi-axes (m) along and across x of a curve's case; a line contact's (b, inf)."""
    kalker = curve.get("kalker") or {}
    a, b = kalker.get("a", np.nan), kalker.get("b", np.nan)
    if np.isfinite(a):
        return a, b
    case = curve["case"]
    for name, across in (("hertz_semi_axis_x", None), ("line_half_width", np.inf)):
        value = float(case[name]) if name in case else np.nan
        if np.isfinite(value):
            return value, value if across is None else across
    return 1.0, np.nan


def plot_tractions(points: list[dict], title: str, path: str | Path) -> Path | None:
    """The shear traction |q| / (mu p0) of chosen steady points, stick area hatched.

    A row per case, a panel per point: |q| over mu p0 (p0 the point's largest pressure) on
    x / a, y / a (a the Hertz semi-axis along the rolling direction x, rolling towards +x),
    the contact's edge (the cells in contact) in black, the stick area outlined in white and
    hatched, the Hertz ellipse dashed.
    """
    if not points:
        return None
    from matplotlib.patches import Patch

    from solver.result import SEPARATED, STICK

    plt = figures.pyplot()
    rows = []
    for point in points:
        if not rows or rows[-1][0]["curve"] is not point["curve"]:
            rows.append([])
        rows[-1].append(point)
    columns = max(len(row) for row in rows)
    size = (3.2 * columns + 1.0, 3.3 * len(rows) + figures.TITLE_HEIGHT + 0.3)
    fig, axes = plt.subplots(
        len(rows), columns, figsize=size, squeeze=False, layout="constrained", dpi=figures.DPI
    )
    t = np.linspace(0.0, 2.0 * np.pi, 200)
    image = None
    for r, row in enumerate(rows):
        for c in range(columns):
            ax = axes[r, c]
            if c >= len(row):
                ax.set_visible(False)
                continue
            point = row[c]
            curve = point["curve"]
            a, b = _semi_axes(curve)
            if not np.isfinite(b):  # a line contact: the traction along x, beside Carter's
                _line_panel(ax, point, a)
                continue
            x, y = point["x"] / a, point["y"] / a
            mu = float(curve["case"]["friction_coefficient"])
            p0 = float(np.max(point["pressure"]))
            q = np.hypot(point["shear_x"], point["shear_y"]) / (mu * p0)
            contact = point["state"] != SEPARATED
            stick = (point["state"] == STICK).astype(float)
            image = ax.pcolormesh(x, y, np.where(contact, q, np.nan).T, cmap="viridis",
                                  vmin=0.0, vmax=1.0, shading="nearest")  # fmt: skip
            ax.contour(x, y, contact.astype(float).T, levels=[0.5], colors="k", linewidths=0.8)
            if stick.any():
                ax.contourf(x, y, stick.T, levels=[0.5, 1.5], colors="none", hatches=["////"])
                ax.contour(x, y, stick.T, levels=[0.5], colors="w", linewidths=1.2)
            if np.isfinite(b):
                ax.plot(np.cos(t), b / a * np.sin(t), color="0.6", ls="--", lw=0.8)
            else:  # a line contact: Hertz's strip
                for edge in (-1.0, 1.0):
                    ax.axvline(edge, color="0.6", ls="--", lw=0.8)
            share = stick.sum() / max(contact.sum(), 1)
            head = figures.title(curve["labels"], width=44)
            ax.set_title(
                f"{head}\nxi = {curve['creepage'][point['index']]:.3g}, F_x/(mu W) = "
                f"{point['force']:.3f}\nstick {share:.0%} of the contact, {point['source']}",
                fontsize=7,
            )
            ax.set_aspect("equal")
            figures.mark_panel(ax, [curve["status"]])
            ax.set_xlabel("x / a (1), rolling to +x", fontsize=8)
            ax.set_ylabel("y / a (1)", fontsize=8)
    if image is None:  # line contacts only: profiles with their own legends
        figures.suptitle(fig, title, "along x; Carter's traction in black, stick shaded")
        figures.save(plt, fig, path)
        return Path(path)
    fig.colorbar(image, ax=axes, label="|q| / (mu p0) (1)", shrink=0.8)
    fig.legend(
        handles=[Patch(facecolor="none", edgecolor="k", hatch="////", label="stick"),
                 Patch(facecolor="none", edgecolor="0.6", ls="--", label="Hertz ellipse")],
        loc="outside lower center", ncols=2, fontsize=7,
    )  # fmt: skip
    figures.suptitle(fig, title, "contact's edge black; stick area hatched, outlined white")
    figures.save(plt, fig, path)
    return Path(path)


def steady_section(dataset, out: Path, name: str, plt, shown: list) -> list[str]:
    """Markdown lines of the steady creep curves (figures appended to ``shown``)."""
    found = steady_curves(dataset, out) if "creepage_x_history" in dataset else []
    if not found:
        return []
    import pandas as pd

    rows = []
    for c in found:
        kalker = c.get("kalker") or {}
        rows.append({
            **c["labels"], "steps": c["creepage"].size, "last xi": c["creepage"][-1],
            "last F_x/(mu W)": c["ratio"][-1], "a/b": kalker.get("a", np.nan) / kalker.get("b", 1),
            "nu": kalker.get("nu", np.nan), "C11": kalker.get("C11", np.nan),
            "G a b C11 / (mu W)": kalker.get("slope", np.nan) / c["scale"],
            "first step / Kalker": c["ratio"][0] * c["scale"]
            / (kalker.get("slope", np.nan) * c["creepage"][0]),
            "status": c["status"],
        })  # fmt: skip
    lines = ["## Steady creep curves", ""]
    lines += [
        "Each case's steady rolling steps (`steady = true`): the creep force on body 2 along x",
        "over mu W against the creepage xi (`creepage_x`); the table gives each curve's last",
        "point and Kalker's linear law F_x = G a b C11 xi of the case (G the pair's shear",
        "modulus, 2/G = 1/G1 + 1/G2; a, b the Hertz semi-axes along and across the rolling",
        "direction; C11 interpolated in Kalker's table E.3 at the pair's nu and a/b,",
        "`solver.theory.friction.kalker_coefficients`): its slope over mu W (1 per unit",
        "creepage) and the secant to the first steady step over it (below 1 by about the",
        "first step's xi over the saturation creepage: the curve bends from the start).",
        "",
        figures.markdown_table(pd.DataFrame(rows)),
        "",
    ]
    missing = [
        f"{figures.labels_text(c['labels'])}: {_kalker_reason(c)}"
        for c in found
        if _kalker_reason(c)
    ]
    if missing:
        lines += ["No Kalker slope drawn for:", ""] + [f"- {m}" for m in missing] + [""]
    if plt is None:
        return lines
    png = plot_steady(dataset, out / f"{name}_steady_creep_curves.png", found)
    if png:
        shown.append(("Steady creep curves", png, "every finished case, Kalker's slopes"))
        lines += [f"![steady creep curves]({png.name})", ""]
        if any(np.isfinite((curve.get("kalker") or {}).get("slope", np.nan)) for curve in found):
            lines += [
                "Dashed: each case's Kalker linear law in its colour, from xi = 0 to where it",
                "reaches mu W; dotted at 1: the saturation F_x = mu W (full slip).",
                "",
            ]
        else:
            lines += ["Dotted at 1: the saturation F_x = mu W (full slip).", ""]
    points, notes = traction_points(found, out)
    title = f"{dataset.attrs.get('campaign', '')}: shear traction of chosen steady points"
    png = plot_tractions(points, title, out / f"{name}_steady_tractions.png")
    if png:
        drawn = len({id(p["curve"]) for p in points})
        shown.append(("Steady tractions", png, f"{drawn} cases, stick areas hatched"))
        worst = max(abs(p["match"]) for p in points)
        lines += ["### Tractions of chosen steady points", ""]
        lines += [
            f"![steady tractions]({png.name})",
            "",
            "The shear traction |q| over mu p0 (p0 the largest pressure) of chosen points of",
            f"{drawn} of the curves, a row per case: the steps nearest F_x/(mu W) = "
            + ", ".join(f"{v:g}" for v in TRACTION_LEVELS)
            + " and the last step.  The case",
            "files hold the fields of the last step only: it is drawn from them (`stored`);",
            "the others are re-solved directly at their creepage from the case's table",
            "(`re-solved`: a steady state does not depend on the ramp to it), their force",
            f"matching the stored one to {worst:.1e} of mu W.  Hatched, outlined white: the",
            "stick area; black: the contact's edge; dashed: the Hertz ellipse.",
            "",
        ]
        if notes:
            lines += [f"- {note}" for note in notes] + [""]
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
