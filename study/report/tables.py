"""What the report's tables say of each case: reductions in the headers, flags, designs.

The helpers the sections share for their per-case tables:

- a column's header says how the per-case value was reduced from its history ("max over path",
  "last step", "at max load"), derived from the declaration in :mod:`solver.variables`
  (:func:`column_label`), never typed in a section;
- a case whose status is not converged, or that holds unconverged load increments
  (``step_converged_history``), is flagged (:func:`flag`, the ``flag`` column and the note
  :data:`FLAG_NOTE`): its headline values come from those increments;
- a sampled design (a ``sample`` axis) or a campaign of more cases than a table lists one by one
  is summarised: the distribution of each column (:func:`distribution`) and the few extreme
  cases (:func:`extremes`), not a row per case;
- a table whose values are all zero or undefined carries nothing (:func:`carries_nothing`).
"""

from __future__ import annotations

import numpy as np

from solver.variables import HISTORIES, reduced_scalars

from .. import analysis
from . import figures

#: Words of each declared reduction in a column header (:attr:`solver.variables.History.reduction`).
REDUCTION_WORDS = {"max": "max over path", "last": "last step", "sum": "sum over steps"}
#: Header words of a value read at the step of the largest normal force.
AT_PEAK = "at max load"
#: Per-case scalars computed from a reduced history: name -> (that history, how).
DERIVED = {
    "contact_radius": ("contact_area", "sqrt(. / pi)"),
    "stick_radius": ("stick_area", "sqrt(. / pi)"),
}
#: Name of the flag column of a per-case table (:func:`flag`).
FLAG = "flag"
#: What a flag means, said under a table that has one.
FLAG_NOTE = (
    "`flag`: the case is not converged (its status) or holds unconverged load increments "
    "(steps whose solves did not all converge); its values come from those increments: "
    "read them as indications only."
)
#: Quantiles of :func:`distribution` (besides min and max).
QUANTILES = (0.05, 0.5, 0.95)


def reduction(name: str) -> str | None:
    """How the per-case scalar ``name`` is reduced from its history (a key of REDUCTION_WORDS).

    From :func:`solver.variables.reduced_scalars`; a scalar computed from a reduced history
    (:data:`DERIVED`) has that history's reduction; None for a scalar that is not reduced.
    """
    name = DERIVED.get(name, (name, ""))[0]
    found = reduced_scalars().get(name)
    return found[1] if found else None


def reduction_words(name: str) -> str:
    """:func:`reduction` of ``name`` in words ("" when it is not a reduced history)."""
    return REDUCTION_WORDS.get(reduction(name) or "", "")


def column_label(short: str, name: str | None = None, words: str | None = None) -> str:
    """A column header that says its reduction, e.g. ``"p_max/p_H (max over path)"``.

    Parameters
    ----------
    short : str
        The column's short name.
    name : str, optional
        The per-case scalar or history the column holds: its declared reduction is said.
    words : str, optional
        The reduction in words instead (e.g. :data:`AT_PEAK` for a value read at a step).

    Returns
    -------
    str
        ``short`` with its reduction in brackets (``short`` alone when there is none).
    """
    words = words if words is not None else (reduction_words(name) if name else "")
    return f"{short} ({words})" if words else short


def long_name(name: str) -> str:
    """The declared long name of a history or of the history a scalar is computed from."""
    history = DERIVED.get(name, (name, ""))[0]
    for key, (source, _, _) in reduced_scalars().items():
        if key == history:
            history = source
    return HISTORIES[history].long_name if history in HISTORIES else name


def unconverged_steps(dataset, index: dict) -> tuple[int, int]:
    """(unconverged, all) load steps of the case at ``index`` (``step_converged_history``).

    (0, 0) when the dataset has no per-step convergence record.
    """
    if "step_converged_history" not in dataset:
        return 0, 0
    steps = np.asarray(dataset["step_converged_history"].isel(index).values, dtype=float)
    steps = steps[np.isfinite(steps)]
    return int(np.count_nonzero(steps == 0)), int(steps.size)


def flag(dataset, index: dict) -> str:
    """Why the headline values of the case at ``index`` are not to be trusted ("" if they are).

    Parameters
    ----------
    dataset : xarray.Dataset
        Campaign dataset.
    index : dict
        ``isel`` of the case.

    Returns
    -------
    str
        Its status when it is not "converged" (e.g. "not converged", "truncated") and the
        count of unconverged increments (e.g. "2/6 steps unconverged"), "; "-joined.
    """
    status = figures.status_of(dataset, index)
    parts = [] if status == "converged" else [status.replace("_", " ")]
    bad, total = unconverged_steps(dataset, index)
    if bad:
        parts.append(f"{bad}/{total} steps unconverged")
    return "; ".join(parts)


def is_design(dataset, rows: int, limit: int) -> bool:
    """Whether a per-case table of ``rows`` rows is summarised instead of listed.

    A sampled design (a ``sample`` axis) always is; any campaign of more than ``limit`` rows.
    """
    return "sample" in analysis.axis_dims(dataset) or rows > limit


def carries_nothing(values) -> bool:
    """True when every value is zero or undefined (NaN, inf, missing)."""
    values = np.asarray(values, dtype=float)
    return not np.any(np.isfinite(values) & (values != 0))


def distribution(table, columns: list[str]):
    """Count, min, 5 %, median, 95 % and max of each numeric column over the table's rows.

    Parameters
    ----------
    table : pandas.DataFrame
        A per-case table.
    columns : list of str
        The columns to summarise (those missing or without a finite value are left out).

    Returns
    -------
    pandas.DataFrame
        One row per column: ``quantity``, ``cases`` (finite values), ``min``, ``p5``,
        ``median``, ``p95``, ``max``.
    """
    import pandas as pd

    rows = []
    for column in columns:
        if column not in table:
            continue
        values = table[column].to_numpy(dtype=float)
        values = values[np.isfinite(values)]
        if not values.size:
            continue
        low, mid, high = np.quantile(values, QUANTILES)
        rows.append({"quantity": column, "cases": values.size, "min": values.min(), "p5": low,
                     "median": mid, "p95": high, "max": values.max()})  # fmt: skip
    return pd.DataFrame(rows)


def extremes(table, columns: dict[str, tuple[str, ...]]):
    """The cases at the extremes of the headline columns, each once.

    Parameters
    ----------
    table : pandas.DataFrame
        A per-case table.
    columns : dict
        Column -> the extremes wanted of it (``"max"``, ``"min"``).

    Returns
    -------
    pandas.DataFrame
        The rows at those extremes, with an ``extreme`` column first (e.g. "max ep_max_%";
        a row at several extremes names them all).
    """
    import pandas as pd

    picked: dict[int, list[str]] = {}
    for column, which in columns.items():
        if column not in table:
            continue
        values = table[column].to_numpy(dtype=float)
        if not np.any(np.isfinite(values)):
            continue
        for end in which:
            at = int(np.nanargmax(values) if end == "max" else np.nanargmin(values))
            picked.setdefault(at, []).append(f"{end} {column}")
    if not picked:
        return pd.DataFrame()
    rows = table.iloc[list(picked)].copy()
    rows.insert(0, "extreme", [", ".join(names) for names in picked.values()])
    return rows


def flagged_count(table) -> int:
    """Rows of a per-case table with a :data:`FLAG`."""
    return 0 if FLAG not in table else int(sum(bool(f) for f in table[FLAG]))


def summary_lines(table, columns: list[str], extreme: dict[str, tuple[str, ...]], noun: str):
    """Markdown lines summarising a per-case table: its distribution and extreme cases.

    Parameters
    ----------
    table : pandas.DataFrame
        A per-case table (one row per finished case, with its labels and :data:`FLAG`).
    columns : list of str
        The columns to summarise.
    extreme : dict
        Column -> the extremes listed (:func:`extremes`).
    noun : str
        What the rows are, e.g. "finished cases of the design".

    Returns
    -------
    list of str
    """
    flagged = flagged_count(table)
    lines = [
        f"Over the {len(table)} {noun} (a table of every case would hide them): the",
        "distribution of each column (`p5`, `p95`: the 5 % and 95 % quantiles)"
        + (
            f"; {flagged} of the cases are flagged (not converged, or unconverged increments) "
            "and counted in it."
            if flagged
            else "."
        ),
        "",
        figures.markdown_table(distribution(table, columns)),
        "The extreme cases:",
        "",
        figures.markdown_table(extremes(table, extreme)),
    ]
    return lines
