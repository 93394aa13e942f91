"""Campaign report: convergence, sensitivity and speed-versus-error tables, figures, Markdown.

``python -m study report OUT [--no-plots]`` reads ``OUT/<name>.nc`` (assembling it first when
it is missing) and writes next to it:

- ``OUT/report.md``: provenance, the tables of :mod:`study.analysis` and links to the figures;
- ``OUT/<name>_convergence_<mesh axis>.png``: log-log error against cells per side, with the
  fitted orders;
- ``OUT/<name>_speed_error.png``: wall time and peak memory against the error, Pareto front;
- ``OUT/<name>_profiles.png``: pressure and shear along y = 0 against r / a;
- ``OUT/<name>_stick_slip.png``: contact-state maps from the per-case files.

Plots need matplotlib (the ``plot`` extra); it is imported lazily with the Agg backend, and the
report is written without figures when it is missing.
"""

from __future__ import annotations

import argparse
import datetime
import hashlib
import math
import os
import platform
import sys
from pathlib import Path

import numpy as np

from . import analysis

#: Most panels / lines drawn in one figure.
MAX_PANELS = 12
MAX_LINES = 16
_STATE_NAMES = ("separated", "stick", "slip")
#: Table columns printed with 9 significant digits (values close to each other).
VALUE_COLUMNS = ("value", "finest", "extrapolated", "reference")


# -- helpers -------------------------------------------------------------------------------------
def _pyplot():
    """Matplotlib's pyplot on the Agg backend, or None when matplotlib is missing."""
    try:
        import matplotlib
    except ImportError:
        return None
    matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt

    return plt


def _label(labels: dict) -> str:
    return ", ".join(f"{k}={_fmt(v)}" for k, v in labels.items()) or "all cases"


def _fmt(value, digits: int = 5) -> str:
    if isinstance(value, bool | np.bool_):
        return "yes" if value else ""
    if isinstance(value, int | np.integer):
        return str(int(value))
    if isinstance(value, float | np.floating):
        if not np.isfinite(value):
            return "" if np.isnan(value) else str(value)
        return f"{value:.{digits}g}"
    return str(value)


def markdown_table(table) -> str:
    """A :class:`pandas.DataFrame` as a Markdown table.

    Numbers get 5 significant digits, the value columns (:data:`VALUE_COLUMNS`) 9.
    """
    if table is None or len(table) == 0:
        return "_(no data)_\n"
    columns = list(table.columns)
    lines = ["| " + " | ".join(columns) + " |", "|" + "|".join("---" for _ in columns) + "|"]
    for _, row in table.iterrows():
        cells = (_fmt(row[c], 9 if c in VALUE_COLUMNS else 5) for c in columns)
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def _sha256(path: Path) -> str:
    try:
        return hashlib.sha256(path.read_bytes()).hexdigest()
    except OSError:
        return ""


def _locate(out: str | Path) -> tuple[Path, Path]:
    """(output folder, dataset path); assembles the dataset when it is missing."""
    from . import storage

    out = Path(out)
    if out.is_file() and out.suffix == ".nc":
        return out.parent, out
    campaign = storage.read_campaign(out)
    path = storage.dataset_path(out, campaign.name)
    if not path.exists():
        from .assemble import assemble_to_file

        path = assemble_to_file(out, campaign)
    return out, path


def _units(dataset, name: str) -> str:
    if name in dataset.variables:
        return str(dataset[name].attrs.get("units", analysis.QUANTITIES.get(name, ("",))[0]))
    return analysis.QUANTITIES.get(name, ("",))[0]


# -- figures -------------------------------------------------------------------------------------
def plot_convergence(dataset, mesh_dim: str, path: str | Path) -> Path | None:
    """Log-log relative error against cells per side, one panel per quantity.

    The error is relative to the closed form where one applies, else to the Richardson
    extrapolation of the slice; dashed lines are the fits ``C h^p`` with the observed order.

    Parameters
    ----------
    dataset : xarray.Dataset
        Campaign dataset.
    mesh_dim : str
        Mesh axis.
    path : str or Path
        PNG to write.

    Returns
    -------
    Path or None
        The PNG, or None without matplotlib or data.
    """
    plt = _pyplot()
    dataset = analysis.with_derived(dataset)
    names = analysis.quantities(dataset)
    if plt is None or not names:
        return None
    refs = analysis.closed_forms(dataset)
    fig, axes = plt.subplots(1, len(names), figsize=(4.2 * len(names), 4.0), squeeze=False)
    for ax, name in zip(axes[0], names, strict=True):
        table = analysis.convergence_table(dataset, name, mesh_dim)
        basis = "closed form" if name in refs else "extrapolated"
        column = "rel_error" if name in refs else "rel_error_extrapolated"
        for k, (labels, _) in enumerate(analysis._slices(dataset, [mesh_dim])):
            if k >= MAX_LINES:
                break
            rows = table
            for key, value in labels.items():
                rows = rows[rows[key] == value]
            err = np.abs(rows[column].to_numpy(dtype=float))
            n = rows["n"].to_numpy(dtype=float)
            ok = np.isfinite(err) & (err > 0)
            if not np.any(ok):
                continue
            (line,) = ax.loglog(n[ok], err[ok], "o-", label=_label(labels) or "cases")
            order, constant = analysis.observed_order(
                rows["h_over_a"].to_numpy(dtype=float)[ok], err[ok]
            )
            if np.isfinite(order):
                h = rows["h_over_a"].to_numpy(dtype=float)[ok]
                ax.loglog(
                    n[ok],
                    constant * h**order,
                    "--",
                    color=line.get_color(),
                    label=f"fit, order {order:.2f}",
                )
        from matplotlib.ticker import NullFormatter, ScalarFormatter

        ax.xaxis.set_major_formatter(ScalarFormatter())
        ax.xaxis.set_minor_formatter(NullFormatter())
        ax.set_xlabel(f"cells per side {mesh_dim} (1)")
        ax.set_ylabel(f"|relative error| vs {basis} (1)")
        ax.set_title(analysis.QUANTITIES.get(name, (None, name))[1])
        ax.grid(True, which="both", alpha=0.3)
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=7)
    fig.suptitle(f"{dataset.attrs.get('campaign', '')}: mesh convergence along {mesh_dim}")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return Path(path)


def plot_speed_error(table, title: str, path: str | Path) -> Path | None:
    """Wall time and peak memory against the error of every case, Pareto front marked.

    Parameters
    ----------
    table : pandas.DataFrame
        :func:`study.analysis.speed_error_table`.
    title : str
        Campaign name for the title.
    path : str or Path
        PNG to write.

    Returns
    -------
    Path or None
        The PNG, or None without matplotlib or usable errors.
    """
    plt = _pyplot()
    if plt is None or len(table) == 0:
        return None
    ok = np.isfinite(table["error"].to_numpy(dtype=float)) & (table["error"] > 0)
    if not np.any(ok):
        return None
    data = table[ok]
    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4.2))
    cells = data["cells"].to_numpy(dtype=float)
    for ax, column, xlabel, xscale in (
        (left, "wall_time", "solve wall time (s)", "log"),
        (right, "peak_rss_mib", "peak resident memory (MiB)", "linear"),
    ):
        x = data[column].to_numpy(dtype=float)
        y = data["error"].to_numpy(dtype=float)
        scatter = ax.scatter(x, y, c=np.log2(np.maximum(cells, 1)), cmap="viridis", zorder=3)
        front = analysis.pareto_front(x, y)
        order = np.argsort(x[front])
        ax.plot(x[front][order], y[front][order], "r-", lw=1.2, label="Pareto front", zorder=2)
        ax.scatter(x[front], y[front], s=90, facecolors="none", edgecolors="r", zorder=4)
        ax.set_xscale(xscale)
        ax.set_yscale("log")
        ax.set_xlabel(xlabel)
        ax.set_ylabel("largest |relative error| (1)")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.colorbar(scatter, ax=right, label="log2(cells)")
    fig.suptitle(f"{title}: speed versus error ({data['error_basis'].iloc[0]})", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return Path(path)


def _cattaneo_shear(r: np.ndarray, mu: float, p0: float, ratio: float) -> np.ndarray:
    """Cattaneo-Mindlin shear traction along a radius (r over a)."""
    outer = mu * p0 * np.sqrt(np.clip(1.0 - r**2, 0.0, None))
    inner = mu * p0 * ratio * np.sqrt(np.clip(1.0 - (r / ratio) ** 2, 0.0, None))
    return outer - np.where(r < ratio, inner, 0.0)


def plot_profiles(dataset, path: str | Path) -> Path | None:
    """Pressure and shear along y = 0 against r / a, one column per slice of the non-mesh axes.

    Each column shows the cases along the mesh axes (or the single case), with the Hertz
    pressure and the Cattaneo-Mindlin shear dashed where they apply.

    Parameters
    ----------
    dataset : xarray.Dataset
        Campaign dataset.
    path : str or Path
        PNG to write.

    Returns
    -------
    Path or None
        The PNG, or None without matplotlib.
    """
    plt = _pyplot()
    if plt is None or "pressure_profile" not in dataset:
        return None
    refs = analysis.closed_forms(analysis.with_derived(dataset))
    mesh = analysis.mesh_axes(dataset)
    slices = list(analysis._slices(dataset, mesh))[:MAX_PANELS]
    fig, axes = plt.subplots(
        2, len(slices), figsize=(4.0 * len(slices), 6.5), squeeze=False, sharex=True
    )
    r = dataset["r_over_a"].values
    usable = analysis._usable(dataset)
    mu_all = analysis.friction_coefficient(dataset).broadcast_like(dataset["status"])
    for column, (labels, isel) in enumerate(slices):
        sub = dataset.isel(isel)
        sub_ok = usable.isel(isel)
        cases = list(analysis._slices(sub, []))[:MAX_LINES]
        for case_labels, case_isel in cases:
            if not bool(sub_ok.isel(case_isel)):
                continue
            case = sub.isel(case_isel)
            name = _label(case_labels) if case_labels else "case"
            axes[0, column].plot(r, case["pressure_profile"].values / 1e9, label=name)
            axes[1, column].plot(r, case["shear_x_profile"].values / 1e9, label=name)
        first = sub.isel(cases[0][1]) if cases else sub
        index = {**isel, **(cases[0][1] if cases else {})}
        if "max_pressure" in refs:
            p0 = float(refs["max_pressure"].broadcast_like(dataset["status"]).isel(index))
            if np.isfinite(p0):
                hertz = p0 * np.sqrt(np.clip(1.0 - r**2, 0.0, None))
                axes[0, column].plot(r, hertz / 1e9, "k--", label="Hertz")
                ratio = math.nan
                if "stick_ratio" in refs:
                    ratio = float(refs["stick_ratio"].broadcast_like(dataset["status"]).isel(index))
                mu = float(mu_all.isel(index))
                if np.isfinite(ratio) and mu > 0 and ratio < 1:
                    shear = _cattaneo_shear(r, mu, p0, ratio)
                    sign = np.sign(np.nanmean(first["shear_x_profile"].values)) or 1.0
                    axes[1, column].plot(r, sign * shear / 1e9, "k--", label="Cattaneo-Mindlin")
        axes[0, column].set_title(_label(labels), fontsize=9)
        axes[0, column].set_ylabel("pressure p (GPa)")
        axes[1, column].set_ylabel("shear traction q_x (GPa)")
        axes[1, column].set_xlabel("r / a (1), along +x at y = 0")
        for ax in axes[:, column]:
            ax.grid(True, alpha=0.3)
            ax.legend(fontsize=6)
    fig.suptitle(f"{dataset.attrs.get('campaign', '')}: traction profiles")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return Path(path)


def plot_stick_slip(dataset, cases_dir: str | Path, path: str | Path) -> Path | None:
    """Contact-state maps (separated / stick / slip) from the per-case files.

    One panel per slice of the non-mesh axes, on the finest mesh of the slice, at most
    :data:`MAX_PANELS`; the Hertz radius and the Cattaneo stick radius are drawn as circles.

    Parameters
    ----------
    dataset : xarray.Dataset
        Campaign dataset.
    cases_dir : str or Path
        Folder of the per-case files (``OUT/cases``).
    path : str or Path
        PNG to write.

    Returns
    -------
    Path or None
        The PNG, or None without matplotlib or contact-state fields.
    """
    plt = _pyplot()
    if plt is None:
        return None
    import xarray as xr
    from matplotlib.colors import ListedColormap

    refs = analysis.closed_forms(analysis.with_derived(dataset))
    mesh = analysis.mesh_axes(dataset)
    usable = analysis._usable(dataset)
    panels = []
    for labels, isel in analysis._slices(dataset, mesh):
        index = dict(isel)
        for dim in mesh:
            index[dim] = int(np.argmax(analysis.mesh_coordinate(dataset, dim).values))
        if not bool(usable.isel(index)):
            continue
        file = Path(cases_dir) / f"{dataset['case_id'].isel(index).item()}.nc"
        if file.exists():
            panels.append((labels, index, file))
        if len(panels) >= MAX_PANELS:
            break
    if not panels:
        return None
    columns = min(4, len(panels))
    rows = math.ceil(len(panels) / columns)
    fig, axes = plt.subplots(rows, columns, figsize=(3.6 * columns, 3.4 * rows), squeeze=False)
    cmap = ListedColormap(["#eeeeee", "#2b83ba", "#fdae61"])
    drawn = 0
    for ax, (labels, index, file) in zip(axes.ravel(), panels, strict=False):
        with xr.open_dataset(file) as case:
            if "contact_state" not in case:
                ax.set_visible(False)
                continue
            a = float(case.attrs.get("hertz_semi_axis_x", case.attrs.get("hertz_radius", 1.0)))
            x, y = case["x"].values / a, case["y"].values / a
            state = case["contact_state"].values
        dx = x[1] - x[0] if len(x) > 1 else 1.0
        dy = y[1] - y[0] if len(y) > 1 else 1.0
        image = ax.imshow(
            state.T,
            origin="lower",
            extent=(x[0] - dx / 2, x[-1] + dx / 2, y[0] - dy / 2, y[-1] + dy / 2),
            cmap=cmap,
            vmin=-0.5,
            vmax=2.5,
            interpolation="nearest",
        )
        drawn += 1
        t = np.linspace(0, 2 * np.pi, 200)
        ax.plot(np.cos(t), np.sin(t), "k--", lw=0.8, label="Hertz a")
        if "stick_ratio" in refs:
            ratio = float(refs["stick_ratio"].broadcast_like(dataset["status"]).isel(index))
            if np.isfinite(ratio) and ratio < 1:
                ax.plot(ratio * np.cos(t), ratio * np.sin(t), "k:", lw=1.0, label="Cattaneo c")
        n_label = ", ".join(f"{d}={_fmt(dataset[d].values[index[d]])}" for d in mesh)
        ax.set_title(", ".join(filter(None, [_label(labels), n_label])), fontsize=8)
        ax.set_xlabel("x / a (1)")
        ax.set_ylabel("y / a (1)")
        ax.legend(fontsize=6, loc="upper right")
    for ax in axes.ravel()[len(panels) :]:
        ax.set_visible(False)
    if not drawn:
        plt.close(fig)
        return None
    bar = fig.colorbar(image, ax=list(axes.ravel()), ticks=[0, 1, 2], shrink=0.8)
    bar.ax.set_yticklabels(_STATE_NAMES)
    fig.suptitle(f"{dataset.attrs.get('campaign', '')}: contact state (finest mesh)")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return Path(path)


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

    from . import storage

    out, path = _locate(out)
    with xr.open_dataset(path, engine=storage.ENGINE) as raw:
        dataset = analysis.with_derived(raw.load())
    name = str(dataset.attrs.get("campaign", path.stem))
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
    lines.append(
        "- axes: "
        + ", ".join(
            f"`{d}` ({dataset.sizes[d]}: {_values(dataset, d)})"
            for d in analysis.axis_dims(dataset)
        )
    )
    counts = ", ".join(
        f"{flag} {dataset.attrs.get(f'cases_{flag}', '?')}"
        for flag in ("converged", "not_converged", "failed", "pending")
    )
    lines.append(f"- cases: {dataset.attrs.get('cases_total', '?')} ({counts})")
    lines.append(f"- closed forms: {analysis.scene(dataset)}")
    lines.append(f"- mesh axes: {', '.join(mesh) or 'none'}")
    lines.append("- quantities: " + ", ".join(f"{q} ({_units(dataset, q)})" for q in names))
    lines.append("")

    figures: list[tuple[str, Path]] = []
    plt = _pyplot() if plots else None
    if plots and plt is None:
        lines += ["_matplotlib is not installed: no figures (pip install slipstick[plot])._", ""]

    for dim in mesh:
        lines += [f"## Mesh convergence along `{dim}`", ""]
        lines += [
            "h / a = 2 half_width / n (cell size over the Hertz semi-axis).  `order_fit`: fit of",
            "v = v* + C h^p over all meshes; `extrapolated`: Richardson from the two finest meshes",
            "with that order (order 2 when the fit hits its bounds, `fit_at_bound`);",
            "`order_finest`: log-log fit of |v - v_finest| vs h; `order_reference`: log-log fit",
            "of |v - closed form| vs h.  Relative errors are signed.",
            "",
        ]
        for q in names:
            units = _units(dataset, q)
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
                figures.append((f"Mesh convergence along {dim}", png))
                lines += [f"![convergence along {dim}]({png.name})", ""]

    sensitivity = analysis.sensitivity_axes(dataset)
    if sensitivity:
        lines += ["## Sensitivities", ""]
        lines += [
            "Finite differences on the finest mesh (central inside, one-sided at the ends);",
            "`elasticity` = x / q dq/dx.",
            "",
        ]
        for axis in sensitivity:
            for q in names:
                table = analysis.sensitivity_table(dataset, q, axis)
                lines += [f"### d `{q}` / d `{axis}` ({_units(dataset, q)} per unit of {axis})", ""]
                lines.append(markdown_table(table))

    lines += ["## Speed versus error", ""]
    speed = analysis.speed_error_table(dataset)
    basis = "closed forms" if refs else "Richardson-extrapolated values"
    lines += [
        f"Errors relative to the {basis} (`err_*`, signed); `error` is the largest absolute one;",
        "`pareto` marks the cases no other case beats in both wall time and error.  Wall time is",
        "the solve time of the case (it includes FFTW planning for the first case of a size on a",
        "rank); peak memory is the process's peak resident set after the case.",
        "",
    ]
    lines.append(markdown_table(speed))
    if plt is not None:
        png = plot_speed_error(speed, name, out / f"{name}_speed_error.png")
        if png:
            figures.append(("Speed versus error", png))
            lines += [f"![speed versus error]({png.name})", ""]
        png = plot_profiles(dataset, out / f"{name}_profiles.png")
        if png:
            figures.append(("Traction profiles", png))
            lines += ["## Profiles", "", f"![profiles]({png.name})", ""]
        png = plot_stick_slip(dataset, storage.cases_dir(out), out / f"{name}_stick_slip.png")
        if png:
            figures.append(("Stick/slip maps", png))
            lines += ["## Stick and slip", "", f"![stick and slip]({png.name})", ""]
    if figures:
        lines += ["## Figures", ""]
        lines += [f"- {title}: `{png.name}`" for title, png in figures]
        lines.append("")
    report = out / "report.md"
    storage.atomic_write_text(report, "\n".join(lines))
    return report


def _values(dataset, dim: str) -> str:
    values = dataset[dim].values if dim in dataset.coords else range(dataset.sizes[dim])
    return ", ".join(_fmt(v.item() if hasattr(v, "item") else v) for v in values)


# -- command line --------------------------------------------------------------------------------
def add_parser(subparsers) -> argparse.ArgumentParser:
    """Add the ``report`` subcommand to an :mod:`argparse` subparsers object."""
    parser = subparsers.add_parser(
        "report",
        help="convergence, sensitivity and speed-versus-error report of a campaign",
        description="Write OUT/report.md with convergence, sensitivity and speed-versus-error "
        "tables, and PNG figures next to the dataset (matplotlib, the 'plot' extra).",
    )
    parser.add_argument("out", metavar="OUT", help="campaign output folder (or its .nc dataset)")
    parser.add_argument("--no-plots", action="store_true", help="write the tables only")
    return parser


def main(args: argparse.Namespace | list[str] | None = None) -> int:
    """Run the ``report`` subcommand; returns the exit status.

    Parameters
    ----------
    args : argparse.Namespace or list of str, optional
        Parsed arguments (``out``, ``no_plots``), or a command line after ``report``.
    """
    if not isinstance(args, argparse.Namespace):
        parser = argparse.ArgumentParser(prog="python -m study")
        add_parser(parser.add_subparsers(dest="command", required=True))
        args = parser.parse_args(["report", *(args or [])])
    report = build_report(args.out, plots=not args.no_plots)
    print(f"report {report}")
    return 0
