"""Speed against error: cost and error of each mesh, and the Pareto front."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from .convergence import convergence_summary
from .dataset import (
    cell_counts,
    closed_forms,
    finest_index,
    finished_mask,
    mesh_axes,
    mesh_coordinate,
    quantities,
    sweep_slices,
    with_derived,
)


def _pareto(cost: np.ndarray, error: np.ndarray) -> np.ndarray:
    """Mask of the points not dominated in (cost, error), both minimised."""
    mask = np.zeros(len(cost), dtype=bool)
    ok = np.isfinite(cost) & np.isfinite(error)
    best = math.inf
    for i in sorted(np.flatnonzero(ok), key=lambda j: (cost[j], error[j])):
        if error[i] < best:
            mask[i] = True
            best = error[i]
    return mask


def speed_error_table(dataset):
    """Wall time and peak memory of every case against its error.

    The error of a quantity is relative to its closed form where one applies (Hertz: p_0, a,
    delta; Cattaneo: c/a), else to the Richardson-extrapolated value of its slice (of the
    non-refinement axes) along the mesh axis (:func:`_primary_mesh_axis`) at the finest value
    of the other refinement axes (e.g. the most load steps): every case of the slice, coarse in
    mesh or in steps, is measured against that one value.  ``error`` is the largest of the
    quantities' absolute relative errors; ``pareto`` marks the cases on the front of
    (wall time, error).

    Parameters
    ----------
    dataset : xarray.Dataset
        Campaign dataset.

    Returns
    -------
    pandas.DataFrame
        One row per finished case: axis values, ``cells`` (:func:`cell_counts`; -1 unknown),
        ``wall_time`` (s), ``peak_rss_mib``,
        ``err_<quantity>`` (signed relative error), ``error_basis`` (of the quantities with
        an error in this case: "closed form", "extrapolated", each quantity's when they
        differ, or "none"), ``error`` and ``pareto``.
    """
    import pandas as pd

    dataset = with_derived(dataset)
    refs = closed_forms(dataset)
    mesh = mesh_axes(dataset)
    names = [q for q in quantities(dataset) if q != "stick_radius" or "stick_ratio" not in refs]
    targets, basis = {}, {}
    for q in names:
        if q in refs:
            targets[q] = refs[q].broadcast_like(dataset[q])
            basis[q] = "closed form"
        elif mesh:
            # one reference per slice of the other axes, for every refinement of it: the
            # extrapolation along the primary axis at the finest value of the other refinements
            primary = _primary_mesh_axis(dataset, mesh)
            sub = dataset.isel(finest_index(dataset, skip=[primary]))
            summary = convergence_summary(sub, q, primary)
            target = dataset[q].copy(data=np.full(dataset[q].shape, np.nan))
            for (_, isel), extrapolated in zip(
                sweep_slices(sub, [primary]), summary["extrapolated"], strict=True
            ):
                target[isel] = extrapolated
            targets[q] = target.transpose(*dataset[q].dims)
            basis[q] = "extrapolated"
    usable = finished_mask(dataset)
    rows = []
    cells = cell_counts(dataset)
    for labels, isel in sweep_slices(dataset, []):
        if not bool(usable.isel(isel)):
            continue
        n_cells = float(cells.isel(isel))
        row = {
            **labels,
            "cells": int(n_cells) if np.isfinite(n_cells) else -1,
            "wall_time": float(dataset["wall_time"].isel(isel)),
            "peak_rss_mib": float(dataset["peak_rss"].isel(isel)) / 2**20,
        }
        errors = []
        for q, target in targets.items():
            t = float(target.isel(isel))
            v = float(dataset[q].isel(isel))
            e = (v - t) / abs(t) if np.isfinite(t) and t != 0 else math.nan
            row[f"err_{q}"] = e
            if np.isfinite(e):
                errors.append(abs(e))
        used = {q: basis[q] for q in targets if np.isfinite(row[f"err_{q}"])}
        kinds = set(used.values())
        row["error_basis"] = (
            "none"  # no closed form and no extrapolation for this case
            if not kinds
            else kinds.pop()
            if len(kinds) == 1
            else ", ".join(f"{q}: {b}" for q, b in used.items())
        )
        row["error"] = max(errors) if errors else math.nan
        rows.append(row)
    table = pd.DataFrame(rows)
    if len(table):
        table["pareto"] = _pareto(table["wall_time"].to_numpy(), table["error"].to_numpy())
    return table


def _primary_mesh_axis(dataset, mesh: list[str]) -> str:
    """The refinement axis the speed-versus-error reference extrapolates along.

    Cells per side when swept, else the first refinement axis.
    """
    for dim in mesh:
        if mesh_coordinate(dataset, dim).attrs.get("campaign_key", "grid.n") == "grid.n":
            return dim
    return mesh[0]


def pareto_front(cost: Sequence[float], error: Sequence[float]) -> np.ndarray:
    """Boolean mask of the points on the Pareto front of (cost, error), both minimised.

    Parameters
    ----------
    cost, error : sequence of float
        Cost (e.g. wall time) and error per point; non-finite points are never on the front.

    Returns
    -------
    ndarray of bool
    """
    return _pareto(np.asarray(cost, dtype=float), np.asarray(error, dtype=float))
