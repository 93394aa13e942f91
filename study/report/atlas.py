"""The report of a stability atlas: corners of a hard scene, one at a time from an easy case.

A campaign whose zip is named ``corner`` (:data:`ATLAS_DIM`, e.g. ``campaigns/hard_cases.toml``)
lists the corners a tribologist will reach (friction, Dundurs beta, load, mesh, steps), each
with and without ``friction.shear_limit``; the first entry of each limit is the easy case,
every other entry its neighbour changed in one respect.  Per case the section tells its
status, why (its first note that names a failure, a cut or the surface flow), the increments
solved, its CPU time over the easy case's under the same friction law, and its iterations per
loop; the figure draws the same: a status chart with the CPU ratios, and the iterations.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from . import figures

#: The zip dimension a campaign names so to be read as an atlas.
ATLAS_DIM = "corner"
#: The coordinate of the friction law (the alias of ``friction.shear_limit``).
LAW = "shear_limit"
#: Coordinates that follow from the corner rather than define it (not in a corner's label).
DERIVED = ("Q", "nz", "grid_nz", LAW)
#: The loops whose iterations the atlas shows (scalars: the histories summed over the path).
LOOPS = ("normal_iterations", "slip_iterations", "coupling_iterations", "plastic_iterations")
#: Words of a note that says why a case did not end converged.
WHY = ("not converged", "surface shear traction reaches", "enlarge the box", "domain's edge",
       "tangential force is at or above", "stalled", "diverging")  # fmt: skip
#: Status colours of the chart.
COLOURS = {
    "converged": "#4daf4a", "surface_flow": "#ff7f00", "truncated": "#984ea3",
    "not_converged": "#e41a1c", "failed": "#000000", "pending": "#bbbbbb",
}  # fmt: skip


def is_atlas(dataset) -> bool:
    """True for a campaign whose zip is named :data:`ATLAS_DIM`."""
    return ATLAS_DIM in dataset.dims and dataset.sizes[ATLAS_DIM] > 1


def _coordinates(dataset) -> list[str]:
    return [name for name, c in dataset.coords.items() if c.dims == (ATLAS_DIM,)]


def corner_labels(dataset) -> list[str]:
    """Each entry's corner: what differs from the easy case of its law ("easy case" for it)."""
    names = [n for n in _coordinates(dataset) if n not in DERIVED]
    laws = _laws(dataset)
    labels = []
    for i in range(dataset.sizes[ATLAS_DIM]):
        easy = laws.index(laws[i])
        changed = [
            f"{n} {figures.fmt(dataset[n].values[i], 3)}"
            for n in names
            if dataset[n].values[i] != dataset[n].values[easy]
        ]
        labels.append(", ".join(changed) or "easy case")
    return labels


def _laws(dataset) -> list[str]:
    if LAW in dataset.coords:
        return [str(v) for v in dataset[LAW].values]
    return ["-"] * dataset.sizes[ATLAS_DIM]


def _why(notes: str) -> str:
    for note in notes.split("; "):
        if any(words in note for words in WHY):
            return note
    return ""


def atlas_table(dataset):
    """One row per case: corner, law, status, why, steps, CPU (s and over the easy case), loops."""
    import pandas as pd

    from solver.result import STATUS_FLAGS

    flags = {v: k for k, v in STATUS_FLAGS.items()}
    laws, labels = _laws(dataset), corner_labels(dataset)
    cpu = dataset["cpu_time"].values if "cpu_time" in dataset else None
    if cpu is None or np.isnan(cpu).all():  # files written before the CPU was recorded
        cpu = dataset["wall_time"].values if "wall_time" in dataset else None
    rows = []
    for i in range(dataset.sizes[ATLAS_DIM]):
        easy = laws.index(laws[i])
        row = {
            "corner": labels[i],
            "shear_limit": laws[i],
            "status": flags[int(dataset["status"].values[i])],
            "steps": dataset["steps"].values[i] if "steps" in dataset else np.nan,
        }
        if cpu is not None:
            row["cpu_s"] = cpu[i]
            row["cpu/easy"] = cpu[i] / cpu[easy] if cpu[easy] > 0 else np.nan
        for loop in LOOPS:
            if loop in dataset:
                row[loop.removesuffix("_iterations")] = dataset[loop].values[i]
        for name in ("max_plastic_strain", "surface_shear_ratio"):
            if name in dataset:
                row[name] = dataset[name].values[i]
        notes = str(dataset["notes"].values[i]) if "notes" in dataset else ""
        row["why"] = _why(notes) if row["status"] != "converged" else ""
        rows.append(row)
    return pd.DataFrame(rows)


def plot_atlas(dataset, path: Path, plt) -> Path | None:
    """The status chart (CPU over the easy case written in each cell) and iterations per loop."""
    table = atlas_table(dataset)
    corners = list(dict.fromkeys(table["corner"]))
    laws = list(dict.fromkeys(table["shear_limit"]))
    height = 1.6 + 0.36 * len(corners)
    fig, (chart, bars) = plt.subplots(
        1, 2, figsize=(12, height), width_ratios=(1, 1.4), layout="constrained"
    )
    for _, row in table.iterrows():
        x, y = laws.index(row["shear_limit"]), corners.index(row["corner"])
        chart.add_patch(plt.Rectangle((x - 0.45, y - 0.4), 0.9, 0.8,
                                      color=COLOURS.get(row["status"], "#bbbbbb")))  # fmt: skip
        ratio = row.get("cpu/easy", np.nan)
        text = row["status"].replace("_", " ")
        if np.isfinite(ratio):
            text += f"\nCPU x{ratio:.2g}"
        chart.text(x, y, text, ha="center", va="center", fontsize=7, color="white")
    chart.set_xlim(-0.5, len(laws) - 0.5)
    chart.set_ylim(len(corners) - 0.5, -0.5)
    chart.set_xticks(range(len(laws)), [f"shear_limit = {law}" for law in laws], fontsize=8)
    chart.set_yticks(range(len(corners)), corners, fontsize=8)
    chart.set_title("status, CPU over the easy case (same law)", fontsize=9)
    loops = [loop.removesuffix("_iterations") for loop in LOOPS if loop in dataset]
    offsets = np.linspace(-0.2, 0.2, max(1, len(laws)))
    for j, law in enumerate(laws):
        part = table[table["shear_limit"] == law]
        positions = np.array([corners.index(c) for c in part["corner"]]) + offsets[j]
        for k, loop in enumerate(loops):
            values = part[loop].to_numpy(float)
            bars.plot(values, positions, ls="none", marker=figures.MARKERS[k], color=f"C{k}",
                      markerfacecolor="white" if j else f"C{k}", markersize=6,
                      label=loop if j == 0 else None)  # fmt: skip
    bars.set_xscale("symlog", linthresh=10)
    bars.set_ylim(len(corners) - 0.5, -0.5)
    bars.set_yticks(range(len(corners)), [])
    bars.grid(axis="x", alpha=0.3)
    hollow = f"hollow: shear_limit = {laws[1]}" if len(laws) > 1 else ""
    bars.set_xlabel(f"iterations over the path, per loop (filled: shear_limit = {laws[0]}; "
                    f"{hollow})", fontsize=8)  # fmt: skip
    bars.legend(fontsize=8, ncol=len(loops), loc="lower center", bbox_to_anchor=(0.5, 1.0))
    figures.suptitle(fig, f"Stability atlas: {dataset.attrs.get('campaign', '')}")
    figures.save(plt, fig, path)
    return path


def section(dataset, out: Path, name: str, plt, shown: list) -> list[str]:
    """Markdown lines of the atlas (its figure added to ``shown``)."""
    table = atlas_table(dataset)
    lines = ["## Stability atlas", ""]
    lines += [
        "Each corner changes the easy case (the first entry of its friction law) in one "
        "respect.  `cpu/easy`: the case's CPU time over the easy case's under the same law; "
        "the loops' columns: iterations summed over the path; `why`: the note that says why "
        "a case did not end converged.",
        "",
        figures.markdown_table(table),
        "",
    ]
    if plt is None:
        return lines
    png = plot_atlas(dataset, out / f"{name}_atlas.png", plt)
    if png:
        shown.append(("Stability atlas", png, "every case"))
        lines += ["### Status, CPU and iterations", "", f"![stability atlas]({png.name})", ""]
    return lines
