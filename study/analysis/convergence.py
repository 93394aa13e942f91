"""Convergence in the mesh: observed orders, Richardson estimates, convergence tables."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from .dataset import (
    closed_forms,
    finished_mask,
    mesh_axes,
    mesh_coordinate,
    mesh_sizes,
    sweep_slices,
    with_derived,
)

#: Range of orders searched by :func:`fit_convergence`.
ORDER_RANGE = (0.05, 8.0)


# -- convergence numerics ------------------------------------------------------------------------
def observed_order(h: Sequence[float], error: Sequence[float]) -> tuple[float, float]:
    """Order ``p`` and constant ``C`` of ``|error| = C h^p`` by a least-squares fit in log-log.

    Parameters
    ----------
    h : sequence of float
        Mesh sizes (any consistent unit).
    error : sequence of float
        Errors; zero, negative-size or non-finite entries are ignored (the absolute value is
        used).

    Returns
    -------
    (float, float)
        ``(p, C)``; NaN when fewer than two usable points remain.
    """
    h = np.asarray(h, dtype=float)
    e = np.abs(np.asarray(error, dtype=float))
    ok = np.isfinite(h) & np.isfinite(e) & (h > 0) & (e > 0)
    if np.count_nonzero(ok) < 2 or np.ptp(h[ok]) == 0:
        return math.nan, math.nan
    slope, intercept = np.polyfit(np.log(h[ok]), np.log(e[ok]), 1)
    return float(slope), float(math.exp(intercept))


def richardson(h: Sequence[float], values: Sequence[float], order: float) -> float:
    """Richardson extrapolation to ``h -> 0`` from the two finest meshes.

    ``v* = (r^p v_f - v_c) / (r^p - 1)`` with ``r = h_c / h_f`` (any ratio).

    Parameters
    ----------
    h : sequence of float
        Mesh sizes.
    values : sequence of float
        Values on those meshes (non-finite ones are ignored).
    order : float
        Order of convergence ``p`` (> 0).

    Returns
    -------
    float
        Extrapolated value; NaN with fewer than two finite values or a bad order.
    """
    h = np.asarray(h, dtype=float)
    v = np.asarray(values, dtype=float)
    ok = np.isfinite(h) & np.isfinite(v) & (h > 0)
    if np.count_nonzero(ok) < 2 or not (np.isfinite(order) and order > 0):
        return math.nan
    order_idx = np.argsort(h[ok])
    (h_f, h_c), (v_f, v_c) = h[ok][order_idx[:2]], v[ok][order_idx[:2]]
    if h_c == h_f:
        return math.nan
    factor = (h_c / h_f) ** order
    return float((factor * v_f - v_c) / (factor - 1.0))


@dataclass(frozen=True)
class ConvergenceFit:
    """Fit ``v(h) = limit + coefficient * h^order`` of values on a sequence of meshes.

    Attributes
    ----------
    limit : float
        Extrapolated value at ``h = 0``.
    coefficient : float
        ``C`` (units of the value over ``h^order``).
    order : float
        Observed order ``p``.
    rms : float
        Root-mean-square residual of the fit (units of the value).
    points : int
        Number of meshes used.
    at_bound : bool
        True when the best order is at the edge of :data:`ORDER_RANGE` (not in the asymptotic
        range, or non-monotone data).
    """

    limit: float
    coefficient: float
    order: float
    rms: float
    points: int
    at_bound: bool = False


def _linear_fit(h: np.ndarray, v: np.ndarray, p: float) -> tuple[float, float, float]:
    matrix = np.column_stack([np.ones_like(h), h**p])
    coef, *_ = np.linalg.lstsq(matrix, v, rcond=None)
    residual = v - matrix @ coef
    return float(coef[0]), float(coef[1]), float(np.sqrt(np.mean(residual**2)))


def fit_convergence(h: Sequence[float], values: Sequence[float]) -> ConvergenceFit:
    """Least-squares fit of ``v = v* + C h^p`` (variable projection over ``p``).

    For each ``p`` the limit ``v*`` and ``C`` are linear; ``p`` minimises the residual over
    :data:`ORDER_RANGE` (log-spaced scan, then golden-section refinement).  Exact for data
    that follow the model; needs three meshes.

    Parameters
    ----------
    h : sequence of float
        Mesh sizes.
    values : sequence of float
        Values (non-finite entries are ignored).

    Returns
    -------
    ConvergenceFit
        All NaN with fewer than three usable meshes.
    """
    h = np.asarray(h, dtype=float)
    v = np.asarray(values, dtype=float)
    ok = np.isfinite(h) & np.isfinite(v) & (h > 0)
    h, v = h[ok], v[ok]
    if len(np.unique(h)) < 3:
        return ConvergenceFit(math.nan, math.nan, math.nan, math.nan, int(len(h)))
    scale = float(np.max(h))
    hs = h / scale  # conditioning
    low, high = math.log(ORDER_RANGE[0]), math.log(ORDER_RANGE[1])
    grid = np.exp(np.linspace(low, high, 161))
    rms = np.array([_linear_fit(hs, v, p)[2] for p in grid])
    if np.ptp(v) == 0:
        return ConvergenceFit(float(v[0]), 0.0, math.nan, 0.0, int(len(h)))
    best = int(np.argmin(rms))
    a = math.log(grid[max(best - 1, 0)])
    b = math.log(grid[min(best + 1, len(grid) - 1)])
    golden = (math.sqrt(5.0) - 1.0) / 2.0
    for _ in range(80):
        c, d = b - golden * (b - a), a + golden * (b - a)
        if _linear_fit(hs, v, math.exp(c))[2] <= _linear_fit(hs, v, math.exp(d))[2]:
            b = d
        else:
            a = c
    p = math.exp(0.5 * (a + b))
    limit, coefficient, residual = _linear_fit(hs, v, p)
    at_bound = best in (0, len(grid) - 1)
    return ConvergenceFit(limit, coefficient / scale**p, p, residual, int(len(h)), at_bound)


def convergence_table(dataset, quantity: str, mesh_dim: str | None = None):
    """Per-mesh convergence table of one quantity along a mesh axis.

    Parameters
    ----------
    dataset : xarray.Dataset
        Campaign dataset.
    quantity : str
        A variable of the dataset (e.g. ``"max_pressure"``, or ``"stick_ratio"`` after
        :func:`with_derived`).
    mesh_dim : str, optional
        Mesh axis; default the first of :func:`mesh_axes`.

    Returns
    -------
    pandas.DataFrame
        One row per case: the other axes' values, ``n``, ``h_over_a``, ``value``,
        ``diff_finest`` (value minus the finest mesh's), ``rel_diff_finest``, ``reference``
        (closed form, NaN if none), ``rel_error`` (versus the closed form), ``extrapolated``
        (Richardson, see :func:`convergence_summary`) and ``rel_error_extrapolated``.
    """
    import pandas as pd

    dataset = with_derived(dataset)
    mesh_dim = mesh_dim or mesh_axes(dataset)[0]
    summary = convergence_summary(dataset, quantity, mesh_dim)
    refs = closed_forms(dataset)
    values = dataset[quantity].where(finished_mask(dataset))
    h_all = mesh_sizes(dataset, mesh_dim).broadcast_like(values)
    ref_all = refs[quantity].broadcast_like(values) if quantity in refs else None
    n_coord = mesh_coordinate(dataset, mesh_dim).values
    rows = []
    for (labels, isel), (_, srow) in zip(
        sweep_slices(dataset, [mesh_dim]), summary.iterrows(), strict=True
    ):
        v = values.isel(isel).values.astype(float)
        h = h_all.isel(isel).values.astype(float)
        finest = _finest(h, v)
        ref = (
            ref_all.isel(isel).values.astype(float)
            if ref_all is not None
            else np.full_like(v, np.nan)
        )
        extrapolated = srow["extrapolated"]
        for i in range(len(v)):
            rows.append(
                {
                    **labels,
                    "n": int(n_coord[i]),
                    "h_over_a": h[i],
                    "value": v[i],
                    "diff_finest": v[i] - finest,
                    "rel_diff_finest": (v[i] - finest) / abs(finest) if finest else np.nan,
                    "reference": ref[i],
                    "rel_error": (v[i] - ref[i]) / abs(ref[i]) if ref[i] else np.nan,
                    "extrapolated": extrapolated,
                    "rel_error_extrapolated": (
                        (v[i] - extrapolated) / abs(extrapolated) if extrapolated else np.nan
                    ),
                }
            )
    return pd.DataFrame(rows)


def _finest(h: np.ndarray, v: np.ndarray) -> float:
    ok = np.isfinite(v) & np.isfinite(h)
    if not np.any(ok):
        return math.nan
    return float(v[ok][np.argmin(h[ok])])


def convergence_summary(dataset, quantity: str, mesh_dim: str | None = None):
    """Per-slice convergence summary of one quantity along a mesh axis.

    Parameters
    ----------
    dataset : xarray.Dataset
        Campaign dataset.
    quantity : str
        Variable name.
    mesh_dim : str, optional
        Mesh axis; default the first of :func:`mesh_axes`.

    Returns
    -------
    pandas.DataFrame
        One row per combination of the other axes: ``meshes`` (finished cases), ``n_finest``,
        ``finest`` (value on the finest mesh), ``extrapolated`` (Richardson from the two finest
        meshes with ``order_fit``, or with order 2 when the fit failed), ``error_bar``
        (``|extrapolated - finest|``: the Richardson estimate of the finest mesh's error, so
        the converged value is ``extrapolated +- error_bar``), ``order_fit`` (fit of
        ``v* + C h^p``, :func:`fit_convergence`), ``fit_at_bound``, ``order_finest`` (log-log
        fit of ``|v - v_finest|`` vs ``h``, finest excluded), ``reference`` (closed form on the
        finest mesh), ``rel_error_finest`` and ``rel_error_extrapolated`` (versus the closed
        form) and ``order_reference`` (log-log fit of ``|v - reference|`` vs ``h``).
    """
    import pandas as pd

    dataset = with_derived(dataset)
    mesh_dim = mesh_dim or mesh_axes(dataset)[0]
    refs = closed_forms(dataset)
    values = dataset[quantity].where(finished_mask(dataset))
    h_all = mesh_sizes(dataset, mesh_dim).broadcast_like(values)
    ref_all = refs[quantity].broadcast_like(values) if quantity in refs else None
    n_coord = mesh_coordinate(dataset, mesh_dim).values
    rows = []
    for labels, isel in sweep_slices(dataset, [mesh_dim]):
        v = values.isel(isel).values.astype(float)
        h = h_all.isel(isel).values.astype(float)
        ok = np.isfinite(v) & np.isfinite(h)
        finest = _finest(h, v)
        fit = fit_convergence(h, v)
        order = fit.order if (np.isfinite(fit.order) and not fit.at_bound) else 2.0
        extrapolated = richardson(h, v, order)
        coarse = ok & (h > np.min(h[ok])) if np.any(ok) else ok
        order_finest, _ = observed_order(h[coarse], v[coarse] - finest)
        row = {
            **labels,
            "meshes": int(np.count_nonzero(ok)),
            "n_finest": int(n_coord[np.argmin(np.where(ok, h, np.inf))]) if np.any(ok) else -1,
            "finest": finest,
            "extrapolated": extrapolated,
            "error_bar": abs(extrapolated - finest),
            "order_fit": fit.order,
            "fit_at_bound": fit.at_bound,
            "order_finest": order_finest,
            "reference": math.nan,
            "rel_error_finest": math.nan,
            "rel_error_extrapolated": math.nan,
            "order_reference": math.nan,
        }
        if ref_all is not None:
            ref = ref_all.isel(isel).values.astype(float)
            r = _finest(h, ref)
            if np.isfinite(r) and r != 0:
                row["reference"] = r
                row["rel_error_finest"] = (finest - r) / abs(r)
                row["rel_error_extrapolated"] = (extrapolated - r) / abs(r)
                row["order_reference"] = observed_order(h[ok], v[ok] - ref[ok])[0]
        rows.append(row)
    return pd.DataFrame(rows)
