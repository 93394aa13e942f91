"""Global sensitivity of a sampled campaign: Sobol' indices and Morris' elementary effects.

A campaign with a ``[sample]`` design (:mod:`study.campaign.sample`) has the dimension
``sample``, the sampled inputs as its coordinates, and the design's rows in the unit hypercube
(``sample_design``).  The estimators are SALib's: Sobol' first-order and total indices (Saltelli
2010, Jansen) with bootstrap confidence intervals from Saltelli's design, Morris' ``mu``,
``mu*`` and ``sigma`` (Campolongo 2007) from Morris' trajectories, the latter in units of the
quantity per unit of the input's quantile level (the unit hypercube).

Cases that did not finish break the blocks they belong to (a Saltelli block of ``D + 2``
rows, a Morris trajectory of ``D + 1``): such blocks are left out whole, which keeps the
estimators unbiased on fewer samples, and the tables say how many were used and left out.
A design cut inside a block (fewer rows than whole blocks), a dataset without the design, or a
quantity that is not one number per case is refused with an :class:`~.dataset.AnalysisError`
that says what to give instead.
Other dimensions of the campaign (a swept key beside the design) give one set of indices per
combination of their values.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from .dataset import (
    AnalysisError,
    check_dataset,
    check_quantity,
    finished_mask,
    quantities,
    sweep_slices,
)

if TYPE_CHECKING:
    import pandas as pd
    import xarray as xr

SAMPLE_DIM = "sample"
#: Bootstrap resamples of the confidence intervals, and their level.
RESAMPLES, CONFIDENCE = 1000, 0.95


def design_method(dataset) -> str | None:
    """The sampling method of a campaign dataset (``"saltelli"``, ``"morris"``...), or None."""
    return dataset.attrs.get("sample_method") if "sample_design" in dataset else None


def sampled_inputs(dataset) -> list[str]:
    """Names of the sampled inputs (coordinates of ``sample``), in the design's column order."""
    return [str(name) for name in dataset["sample_input"].values]


def result_quantities(dataset: xr.Dataset) -> list[str]:
    """The report's quantities (:func:`~.dataset.quantities`) that vary over the finished cases."""
    check_dataset(dataset)
    found = []
    for name in quantities(dataset):
        values = np.asarray(dataset[name].where(finished_mask(dataset)).values, dtype=float)
        finite = values[np.isfinite(values)]
        if finite.size > 1 and np.ptp(finite) > 1e-12 * np.max(np.abs(finite)):
            found.append(name)
    return found


def _outputs(dataset, quantity: str, log: bool):
    """The quantity masked to finished cases (``ln`` of it with ``log``)."""
    values = dataset[quantity].where(finished_mask(dataset)).astype(float)
    if log:
        if bool((values <= 0).any()):
            raise AnalysisError(
                f"quantity {quantity!r}: log needs positive values and it has some <= 0; "
                "give log=False"
            )
        values = np.log(values)
    return values


def _complete_blocks(y: np.ndarray, block: int) -> tuple[np.ndarray, int, int]:
    """The rows of the blocks with every value finite; (rows, blocks kept, blocks left out)."""
    blocks = y.reshape(-1, block)
    keep = np.all(np.isfinite(blocks), axis=1)
    return np.flatnonzero(np.repeat(keep, block)), int(keep.sum()), int((~keep).sum())


#: What each method's analysis is, and what its block of rows is called.
_ANALYSES = {
    "saltelli": ("Sobol' indices", "sobol_indices", "Saltelli block"),
    "morris": ("Morris' elementary effects", "morris_indices", "Morris trajectory"),
}


def _check_design(dataset, method: str) -> None:
    """Raise unless the dataset holds a ``[sample]`` design of ``method``, naming what fits."""
    found = design_method(dataset)
    if found == method:
        return
    wanted = _ANALYSES[method][0]
    if found in _ANALYSES:
        instead = f"it is {found!r}: use {_ANALYSES[found][1]}(dataset, quantity)"
    elif found:
        instead = f"it is {found!r}, a space-filling design that gives no indices"
    else:
        instead = "it has none (a swept grid: sensitivity_table(dataset, quantity, axis))"
    raise AnalysisError(
        f"dataset: {wanted} need a [sample] design with method = {method!r}; {instead}"
    )


def _check_whole_blocks(dataset, method: str, block: int) -> None:
    """Raise when the design was cut inside a block (a row count not a multiple of ``block``)."""
    rows = dataset.sizes[SAMPLE_DIM]
    if rows % block == 0:
        return
    unit = _ANALYSES[method][2]
    whole = rows // block * block
    full = int(dataset.attrs.get("sample_count", 0)) * block
    keep = (
        f"keep whole ones, e.g. dataset.isel({SAMPLE_DIM}=slice(0, {whole}))"
        if whole
        else f"give at least one whole {unit} (the full design has {full} rows)"
    )
    raise AnalysisError(
        f"dataset: the design is cut inside a {unit} of {block} rows ({rows} {SAMPLE_DIM} rows, "
        f"not a multiple of {block}); {keep}"
    )


def _indices(dataset, quantity: str, method: str, log: bool, keys: tuple, counted: str, analyse):
    """One row per input and slice of the other dimensions: ``keys`` from ``analyse``.

    ``analyse(problem, rows, y)``: SALib's analysis of the complete blocks' ``rows`` (indices
    into the design) and their outputs ``y``.
    """
    import pandas as pd

    from ..campaign.sample import salib_problem

    check_dataset(dataset)
    _check_design(dataset, method)
    check_quantity(dataset, quantity)
    block = int(dataset.attrs["sample_block"])
    _check_whole_blocks(dataset, method, block)
    names = sampled_inputs(dataset)
    values = _outputs(dataset, quantity, log)
    rows = []
    for labels, isel in sweep_slices(dataset, [SAMPLE_DIM]):
        y = np.asarray(values.isel(isel).values, dtype=float)
        kept, used, dropped = _complete_blocks(y, block)
        result = {key: [np.nan] * len(names) for key in keys}
        if used > 1 and np.ptp(y[kept]) > 0:  # a constant quantity has no indices
            result = analyse(salib_problem(names), kept, y[kept])
        for j, name in enumerate(names):
            rows.append({
                **labels, "input": name, **{key: float(result[key][j]) for key in keys},
                counted: used, "left_out": dropped,
            })  # fmt: skip
    return pd.DataFrame(rows)


def sobol_indices(
    dataset: xr.Dataset,
    quantity: str,
    *,
    log: bool = False,
    resamples: int = RESAMPLES,
    confidence: float = CONFIDENCE,
    seed: int = 0,
) -> pd.DataFrame:
    """Sobol' first-order and total indices of ``quantity`` over the sampled inputs.

    Parameters
    ----------
    dataset : xarray.Dataset
        A campaign dataset with a Saltelli design.
    quantity : str
        A numeric variable with one value per case (:func:`~.dataset.case_quantities`).
    log : bool
        Indices of ``ln(quantity)`` (positive quantities).
    resamples : int
        Bootstrap resamples of the confidence intervals.
    confidence : float
        Level of the intervals (their half-widths are ``S1_conf``, ``ST_conf``).
    seed : int
        Of the bootstrap.

    Returns
    -------
    pandas.DataFrame
        One row per input (and per combination of the other dimensions' values): ``input``,
        ``S1``, ``S1_conf``, ``ST``, ``ST_conf`` (dimensionless), ``samples`` (complete
        base samples used), ``left_out`` (base samples with a case not finished); NaN for a
        quantity that does not vary.

    Raises
    ------
    TypeError
        ``dataset`` is a path (open it first with :func:`xarray.open_dataset`) or not a Dataset.
    AnalysisError
        The dataset has no Saltelli design or is cut inside a block of ``D + 2`` rows;
        ``quantity`` is unknown, text, a flag, or not one number per case; ``log`` with values
        <= 0.  One line that names the argument and what to give instead.
    """
    from SALib.analyze import sobol

    def analyse(problem, rows, y):
        second = bool(dataset.attrs.get("sample_second_order", 0))
        # a Generator: SALib's sobol.analyze seeds its bootstrap only for a truthy seed (`if
        # seed:`), so seed 0 gave intervals that changed from call to call
        return sobol.analyze(
            problem, y, calc_second_order=second, num_resamples=resamples,
            conf_level=confidence, seed=np.random.default_rng(seed),
        )  # fmt: skip

    keys = ("S1", "S1_conf", "ST", "ST_conf")
    return _indices(dataset, quantity, "saltelli", log, keys, "samples", analyse)


def morris_indices(
    dataset: xr.Dataset,
    quantity: str,
    *,
    log: bool = False,
    resamples: int = RESAMPLES,
    confidence: float = CONFIDENCE,
    seed: int = 0,
) -> pd.DataFrame:
    """Morris' screening measures of ``quantity`` over the sampled inputs.

    Parameters
    ----------
    dataset : xarray.Dataset
        A campaign dataset with a Morris design.
    quantity : str
        A numeric variable with one value per case (:func:`~.dataset.case_quantities`).
    log : bool
        Of ``ln(quantity)`` (positive quantities).
    resamples : int
        Bootstrap resamples of the interval of ``mu_star``.
    confidence : float
        Level of that interval (its half-width is ``mu_star_conf``).
    seed : int
        Of the bootstrap.

    Returns
    -------
    pandas.DataFrame
        One row per input (and combination of the other dimensions' values): ``input``, ``mu``,
        ``mu_star``, ``sigma``, ``mu_star_conf`` (units of the quantity, or 1 with ``log``,
        per unit quantile level), ``trajectories`` used, ``left_out``; NaN for a quantity that
        does not vary.

    Raises
    ------
    TypeError
        ``dataset`` is a path (open it first with :func:`xarray.open_dataset`) or not a Dataset.
    AnalysisError
        The dataset has no Morris design or is cut inside a trajectory of ``D + 1`` rows;
        ``quantity`` is unknown, text, a flag, or not one number per case; ``log`` with values
        <= 0.  One line that names the argument and what to give instead.
    """
    from SALib.analyze import morris

    def analyse(problem, rows, y):
        design = np.asarray(dataset["sample_design"].values, dtype=float)
        levels = int(dataset.attrs.get("sample_levels", 4))
        return morris.analyze(
            problem, design[rows], y, num_resamples=resamples, conf_level=confidence,
            num_levels=levels, seed=seed,
        )  # fmt: skip

    keys = ("mu", "mu_star", "sigma", "mu_star_conf")
    return _indices(dataset, quantity, "morris", log, keys, "trajectories", analyse)
