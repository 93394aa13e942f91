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
Other dimensions of the campaign (a swept key beside the design) give one set of indices per
combination of their values.
"""

from __future__ import annotations

import numpy as np

from .dataset import finished_mask, quantities, sweep_slices

SAMPLE_DIM = "sample"
#: Bootstrap resamples of the confidence intervals, and their level.
RESAMPLES, CONFIDENCE = 1000, 0.95


def design_method(dataset) -> str | None:
    """The sampling method of a campaign dataset (``"saltelli"``, ``"morris"``...), or None."""
    return dataset.attrs.get("sample_method") if "sample_design" in dataset else None


def sampled_inputs(dataset) -> list[str]:
    """Names of the sampled inputs (coordinates of ``sample``), in the design's column order."""
    return [str(name) for name in dataset["sample_input"].values]


def result_quantities(dataset) -> list[str]:
    """The report's quantities (:func:`~.dataset.quantities`) that vary over the finished cases."""
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
            raise ValueError(f"{quantity}: log needs positive values; it has some <= 0")
        values = np.log(values)
    return values


def _complete_blocks(y: np.ndarray, block: int) -> tuple[np.ndarray, int, int]:
    """The rows of the blocks with every value finite; (rows, blocks kept, blocks left out)."""
    blocks = y.reshape(-1, block)
    keep = np.all(np.isfinite(blocks), axis=1)
    return np.flatnonzero(np.repeat(keep, block)), int(keep.sum()), int((~keep).sum())


def _indices(dataset, quantity: str, method: str, log: bool, keys: tuple, counted: str, analyse):
    """One row per input and slice of the other dimensions: ``keys`` from ``analyse``.

    ``analyse(problem, rows, y)``: SALib's analysis of the complete blocks' ``rows`` (indices
    into the design) and their outputs ``y``.
    """
    import pandas as pd

    from ..campaign.sample import salib_problem

    found = design_method(dataset)
    if found != method:
        wanted = {"saltelli": "Sobol' indices", "morris": "Morris' elementary effects"}[method]
        raise ValueError(
            f"{wanted} need a [sample] design with method = {method!r}; this campaign's is "
            f"{found!r}" + ("" if found else " (no [sample] design)")
        )
    names = sampled_inputs(dataset)
    block = int(dataset.attrs["sample_block"])
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
    dataset,
    quantity: str,
    *,
    log: bool = False,
    resamples: int = RESAMPLES,
    confidence: float = CONFIDENCE,
    seed: int = 0,
):
    """Sobol' first-order and total indices of ``quantity`` over the sampled inputs.

    Parameters
    ----------
    dataset : xarray.Dataset
        A campaign dataset with a Saltelli design.
    quantity : str
        A per-case variable.
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
    """
    from SALib.analyze import sobol

    second = bool(dataset.attrs.get("sample_second_order", 0))

    def analyse(problem, rows, y):
        return sobol.analyze(
            problem, y, calc_second_order=second, num_resamples=resamples,
            conf_level=confidence, seed=seed,
        )  # fmt: skip

    keys = ("S1", "S1_conf", "ST", "ST_conf")
    return _indices(dataset, quantity, "saltelli", log, keys, "samples", analyse)


def morris_indices(
    dataset,
    quantity: str,
    *,
    log: bool = False,
    resamples: int = RESAMPLES,
    confidence: float = CONFIDENCE,
    seed: int = 0,
):
    """Morris' screening measures of ``quantity`` over the sampled inputs.

    Parameters
    ----------
    dataset : xarray.Dataset
        A campaign dataset with a Morris design.
    quantity : str
        A per-case variable.
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
    """
    from SALib.analyze import morris

    design = np.asarray(dataset["sample_design"].values, dtype=float)
    levels = int(dataset.attrs.get("sample_levels", 4))

    def analyse(problem, rows, y):
        return morris.analyze(
            problem, design[rows], y, num_resamples=resamples, conf_level=confidence,
            num_levels=levels, seed=seed,
        )  # fmt: skip

    keys = ("mu", "mu_star", "sigma", "mu_star_conf")
    return _indices(dataset, quantity, "morris", log, keys, "trajectories", analyse)
