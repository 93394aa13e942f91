"""The report builder: ``python -m study report OUT`` writes ``OUT/report.md`` and its figures.

The top of :mod:`study.report`: it assembles the dataset if needed, writes the summary, the
convergence and speed-error tables and figures (:mod:`.elastic`), and the plastic
(:mod:`.plastic`), cyclic (:mod:`.cycles`), shakedown (:mod:`.shakedown`), rolling
(:mod:`.rolling`) and stability-atlas (:mod:`.atlas`) sections when the campaign has them.
"""

from __future__ import annotations

import datetime
import hashlib
import os
import platform
import sys
from pathlib import Path

import numpy as np

from solver.result import STATUS_FLAGS

from .. import analysis
from . import (
    atlas,
    cycles,
    global_sensitivity,
    plastic,
    rolling,
    rough,
    shakedown,
    tables,
    theorem,
)
from .elastic import (
    _convergence_note,
    plot_convergence,
    plot_profiles,
    plot_speed_error,
    plot_stick_slip,
    profile_panels,
    speed_error_note,
    stick_slip_panels,
)
from .figures import fmt, markdown_table, pyplot, units_of

#: Most cases a per-case table lists one by one (beyond, and for a sampled design: their
#: statistics and extremes).
MAX_CASE_ROWS = 200
#: Quantities that mean nothing for a periodic (rough) period: its rigid-body approach and the
#: dent at its centre are not measured against anything.
NOT_PERIODIC = ("approach", "residual_depth")


def _sha256(path: Path) -> str:
    try:
        return hashlib.sha256(path.read_bytes()).hexdigest()
    except OSError:
        return ""


def _locate(out: str | Path) -> tuple[Path, Path]:
    """(output folder, dataset path); assembles the dataset when it is missing."""
    from ..run import storage

    out = Path(out)
    if out.is_file() and out.suffix == ".nc":
        return out.parent, out
    campaign = storage.read_campaign(out)
    path = storage.dataset_path(out, campaign.name)
    if not path.exists():
        from ..run.assemble import assemble_to_file

        path = assemble_to_file(out, campaign)
    return out, path


# -- report --------------------------------------------------------------------------------------
def provenance(dataset, out: Path) -> dict:
    """Provenance of the report: versions, campaign hashes, date, machine."""
    import solver

    source = Path(dataset.attrs.get("campaign_source", "") or "")
    return {
        "slipstick version": solver.__version__,
        "dataset version": dataset.attrs.get("slipstick_version", ""),
        "git commit": dataset.attrs.get("git_hash", "") or "(unknown)",
        "campaign file": str(source) if str(source) else "(table)",
        "campaign file sha256": (_sha256(source) if source.is_file() else "") or "(file not found)",
        "campaign.json sha256": _sha256(out / "campaign.json") or "(missing)",
        "dataset history": dataset.attrs.get("history", ""),
        "report date (UTC)": datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%dT%H:%M:%SZ"),
        "machine": f"{platform.node()} ({platform.platform()}, {os.cpu_count()} CPUs)",
        "python": f"{sys.version.split()[0]}, numpy {np.__version__}",
    }


def build_report(out: str | Path, plots: bool = True) -> Path:
    """Write ``OUT/report.md`` (and the figures) for a campaign output folder.

    Parameters
    ----------
    out : str or Path
        Campaign output folder (or the assembled ``.nc`` dataset inside it).
    plots : bool
        Draw the PNG figures (needs matplotlib; skipped with a note when it is missing).

    Returns
    -------
    Path
        The Markdown report.
    """
    import xarray as xr

    from ..run import storage

    out, path = _locate(out)
    with xr.open_dataset(path, engine=storage.ENGINE) as raw:
        dataset = analysis.with_derived(raw.load())
    if _periodic(dataset):  # no approach or central dent of a period: not shown
        dataset = dataset.drop_vars([v for v in NOT_PERIODIC if v in dataset])
    name = str(dataset.attrs.get("campaign", path.stem))
    heights_only = _heights_only(dataset, out)
    by_theorem = theorem.is_theorem(dataset)  # no load path was followed: no profiles, no maps
    mesh = analysis.mesh_axes(dataset)
    names = analysis.quantities(dataset)
    refs = analysis.closed_forms(dataset)
    lines = [f"# Campaign report: {name}", ""]
    if dataset.attrs.get("summary"):
        lines += [f"{dataset.attrs['summary']}", ""]
    lines += ["## Provenance", ""]
    lines += [f"- **{k}**: {v}" for k, v in provenance(dataset, out).items()]
    lines += ["", "## Campaign", ""]
    lines.append(f"- dataset: `{path.name}`")
    axes = ", ".join(
        f"`{d}` ({dataset.sizes[d]}: {_values(dataset, d)})" for d in analysis.axis_dims(dataset)
    )
    lines.append(f"- axes: {axes or 'none (a campaign of one case: its variables are scalars)'}")
    counts = ", ".join(f"{flag} {dataset.attrs.get(f'cases_{flag}', '?')}" for flag in STATUS_FLAGS)
    lines.append(f"- cases: {dataset.attrs.get('cases_total', '?')} ({counts})")
    lines.append(f"- closed forms: {analysis.scene(dataset)}")
    lines.append(f"- mesh axes: {', '.join(mesh) or 'none'}")
    lines.append(
        "- quantities: "
        + ", ".join(
            f"{q} ({', '.join(filter(None, [units_of(dataset, q), tables.reduction_words(q)]))})"
            for q in names
        )
    )
    lines.append("")

    figures: list[tuple[str, Path, str]] = []
    plt = pyplot() if plots else None
    if plots and plt is None:
        lines += ["_matplotlib is not installed: no figures (pip install slipstick[plot])._", ""]

    for dim in mesh:
        noun, meaning = analysis.mesh_meaning(dataset, dim)
        lines += [f"## Convergence along `{dim}` ({noun})", ""]
        lines += [
            f"{meaning}; `n` is the count.  `order_fit`: fit of",
            "v = v* + C h^p over all meshes; `extrapolated`: Richardson from the two finest meshes",
            "with that order (order 2 when the fit hits its bounds, `fit_at_bound`), converged",
            "value `extrapolated` +- `error_bar` (= |extrapolated - finest|);",
            "`order_finest`: log-log fit of |v - v_finest| vs h; `order_reference`: log-log fit",
            "of |v - closed form| vs h.  Relative errors are signed.",
            "",
        ]
        for q in names:
            units = units_of(dataset, q)
            lines += [f"### {analysis.QUANTITIES.get(q, ('', q))[1]} (`{q}`, {units})", ""]
            lines += ["Summary per slice:", ""]
            lines.append(markdown_table(analysis.convergence_summary(dataset, q, dim)))
            lines += ["Per mesh:", ""]
            table = analysis.convergence_table(dataset, q, dim)
            keep = [c for c in table.columns if c not in ("extrapolated",)]
            lines.append(markdown_table(table[keep]))
        if plt is not None:
            png = plot_convergence(dataset, dim, out / f"{name}_convergence_{dim}.png")
            if png:
                note = _convergence_note(dataset, dim)
                figures.append((f"Convergence along {dim}", png, note))
                lines += [f"![convergence along {dim}]({png.name})", ""]

    realisations = analysis.realisation_axes(dataset)
    if realisations:
        stats = analysis.realisation_statistics(dataset)
        axes = ", ".join(f"`{d}`" for d in realisations)
        lines += ["## Over the surface realisations", ""]
        lines += [
            f"The roughness seeds ({axes}) draw surfaces of one statistics: each quantity's",
            "mean, sample standard deviation, min and max over the finished realisations",
            "(`realisations` of them) per slice of the other axes.",
            "",
        ]
        stats = stats.to_dataframe().reset_index()  # each header says its reduction
        lines.append(markdown_table(stats.rename(columns=lambda c: tables.column_label(c, c))))
    lines += _sensitivity_lines(dataset, names)
    lines += ["## Speed versus error", ""]
    speed = analysis.speed_error_table(dataset)
    basis = "closed forms" if refs else "Richardson-extrapolated values"
    cost = (
        "Wall time is the solve time of the case (it includes FFTW planning for the first case "
        "of a size on a rank); peak memory is the process's peak resident set during the case "
        "(Linux)."
    )
    has_error = "error" in speed and bool(speed["error"].notna().any())
    if has_error:
        lines += [
            f"Errors relative to the {basis} (`err_*`, signed); `error` is the largest absolute "
            "one; `pareto` marks the cases no other case beats in both wall time and error.  "
            + cost,
            "",
        ]
    else:  # no closed form and no mesh axis: no error to show, only the cost
        speed = speed.drop(columns=["error_basis", "error", "pareto"], errors="ignore")
        speed = speed.dropna(axis=1, how="all")
        lines += [f"No closed form applies and no mesh axis refines: no error.  {cost}", ""]
    if len(speed) > MAX_CASE_ROWS:  # a sampled design: its statistics, not every case
        lines += [f"Over the {len(speed)} cases (count, mean, quantiles):", ""]
        numbers = speed.select_dtypes("number").drop(columns=["pareto"], errors="ignore")
        lines.append(markdown_table(numbers.describe().reset_index()))
    else:
        lines.append(markdown_table(speed))
    if plt is not None:
        png = plot_speed_error(speed, name, out / f"{name}_speed_error.png") if has_error else None
        if png:
            note = speed_error_note(speed)
            figures.append(("Speed versus error", png, note))
            lines += [f"![speed versus error]({png.name})", "", f"Shown: {note}.", ""]
        if by_theorem:
            pass  # the theorem's section says what the cases hold
        elif heights_only:
            lines += [
                "## Profiles and stick/slip maps",
                "",
                "Not drawn: the cases are heights only (no radius or profile, e.g. a periodic "
                "rough period), with no contact radius to scale a profile or a map by; the "
                "rough-interface section below has their curves and maps.",
                "",
            ]
        skip = heights_only or by_theorem
        png = None if skip else plot_profiles(dataset, out / f"{name}_profiles.png", out)
        if png:
            note = profile_panels(dataset)[1]
            figures.append(("Traction profiles", png, note))
            lines += ["## Profiles", "", f"![profiles]({png.name})", "", f"Shown: {note}.", ""]
        png = None if skip else plot_stick_slip(dataset, out, out / f"{name}_stick_slip.png")
        if png:
            note = stick_slip_panels(dataset, out)[1]
            figures.append(("Stick/slip maps", png, note))
            lines += ["## Stick and slip", "", f"![stick and slip]({png.name})", ""]
            lines += [f"Shown: {note}.", ""]
    if heights_only:
        lines += rough.section(dataset, out, name, plt, figures)
    if by_theorem:
        lines += theorem.section(dataset, out, name, plt, figures)
    elif analysis.is_plastic(dataset) and not heights_only:  # (the rough has its own)
        lines += plastic.section(dataset, out, name, plt, figures, limit=MAX_CASE_ROWS)
    if "cycle" in dataset.dims:
        lines += cycles.section(dataset, out, name, plt, figures)
    if "shakedown" in dataset:
        nu = _yielding_poisson_ratio(out)
        lines += shakedown.section(dataset, out, name, plt, figures, nu)
    if "sample_design" in dataset:
        lines += global_sensitivity.section(dataset, out, name, plt, figures)
    if "creep_force_x" in dataset or "creepage_x_history" in dataset:
        lines += rolling.section(dataset, out, name, plt, figures)
    if atlas.is_atlas(dataset):
        lines += atlas.section(dataset, out, name, plt, figures)
    if figures:
        lines += ["## Figures", ""]
        lines += [f"- {title}: `{png.name}` ({note})" for title, png, note in figures]
        lines.append("")
    report = out / "report.md"
    storage.atomic_write_text(report, "\n".join(lines))
    return report


def _sensitivity_lines(dataset, names: list[str]) -> list[str]:
    """The finite-difference sensitivities: a table per quantity and axis, or their summary.

    A table whose derivatives are all zero or undefined is not written (the note names it); a
    sampled design or a campaign of more than :data:`MAX_CASE_ROWS` rows gets one summary row
    per quantity and axis instead of a row per case.
    """
    found = [
        (axis, q, analysis.sensitivity_table(dataset, q, axis))
        for axis in analysis.sensitivity_axes(dataset)
        for q in names
    ]
    if not found:
        return []
    carries = [len(t) > 0 and not tables.carries_nothing(t["derivative"]) for _, _, t in found]
    kept = [entry for entry, keep in zip(found, carries, strict=True) if keep]
    empty = [
        f"d `{q}` / d `{a}`" for (a, q, _), keep in zip(found, carries, strict=True) if not keep
    ]
    lines = ["## Sensitivities", ""]
    lines += [
        "Finite differences on the finest mesh (central inside, one-sided at the ends);",
        "`elasticity` = x / q dq/dx.",
        "",
    ]
    if empty:
        lines += [f"Zero or undefined everywhere, not tabulated: {', '.join(empty)}.", ""]
    rows = max((len(t) for _, _, t in kept), default=0)
    if kept and tables.is_design(dataset, rows, MAX_CASE_ROWS):
        import pandas as pd

        summary = []
        for axis, q, table in kept:
            derivative = table["derivative"].to_numpy(dtype=float)
            elasticity = table["elasticity"].to_numpy(dtype=float)
            ok = np.isfinite(derivative)
            summary.append({
                "quantity": q, "axis": axis, "units": f"{units_of(dataset, q)} per unit of {axis}",
                "cases": int(ok.sum()), "min": np.nanmin(derivative), "median":
                np.nanmedian(derivative), "max": np.nanmax(derivative),
                "elasticity_median": np.nanmedian(elasticity) if np.isfinite(elasticity).any()
                else np.nan,
            })  # fmt: skip
        lines += [
            f"Over the {rows} cases of each table (a row per case would hide them): the",
            "derivative's range and median, and the median elasticity.",
            "",
            markdown_table(pd.DataFrame(summary)),
        ]
        return lines
    for axis, q, table in kept:
        lines += [f"### d `{q}` / d `{axis}` ({units_of(dataset, q)} per unit of {axis})", ""]
        lines.append(markdown_table(table))
    return lines


def _periodic(dataset) -> bool:
    """Whether the campaign's cases are periodic periods (``contact_fraction`` is declared so)."""
    return "contact_fraction" in dataset and not tables.carries_nothing(
        dataset["contact_fraction"].values
    )


def _yielding_poisson_ratio(out: Path) -> float | None:
    """Poisson's ratio of the campaign's elastic-plastic bodies, if they share one."""
    from ..run import storage

    try:
        campaign = storage.read_campaign(out)
    except (OSError, ValueError):  # a dataset without its campaign folder
        return None
    ratios = {
        float(case.spec[body]["nu"])
        for case in campaign.cases
        for body in ("body1", "body2")
        if case.spec[body].get("behaviour") == "elastic-plastic"
    }
    return ratios.pop() if len(ratios) == 1 else None


def _values(dataset, dim: str) -> str:
    if dim == "sample" and "sample_design" in dataset:
        return f"rows of a {dataset.attrs['sample_method']} design"
    values = dataset[dim].values if dim in dataset.coords else range(dataset.sizes[dim])
    return ", ".join(fmt(v.item() if hasattr(v, "item") else v) for v in values)


# -- command line --------------------------------------------------------------------------------
def _heights_only(dataset, out: str | Path) -> bool:
    """True when the campaign's finished cases have no smooth shape to scale profiles by.

    Their results carry ``domain_half_width`` instead of a Hertz or Sneddon radius
    (:func:`solver.result.reference_attrs`); the first finished case stored is read.

    Parameters
    ----------
    dataset : xarray.Dataset
        Campaign dataset.
    out : str or Path
        Campaign output folder.
    """
    from ..run import storage

    index = storage.case_index(out)
    finished = analysis.finished_mask(dataset).values.ravel()
    ids = dataset["case_id"].values.ravel()
    for case_id in ids[finished]:
        if str(case_id) in index.results:
            with storage.open_case(out, str(case_id), index=index) as case:
                return "domain_half_width" in case.attrs
    return False
