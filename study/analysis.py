"""Analysis of an assembled campaign dataset: convergence, sensitivity, speed versus error.

Every function takes the dataset written by :mod:`study.assemble` (``OUT/<name>.nc``, opened
with :func:`xarray.open_dataset`) and returns plain numbers or :class:`pandas.DataFrame` tables,
so they can be used from a notebook as well as by :mod:`study.report`.

Vocabulary
----------
mesh axis
    A refinement axis: a dimension carrying a coordinate whose campaign key is ``grid.n``
    (cells per side; the cell size is ``h = 2 half_width / n`` in units of the Hertz
    semi-axis ``a_x``) or ``load.steps`` (load steps; ``h = 1 / steps``, the load increment
    over the load).
slice
    One combination of the values of the other dimensions; convergence is studied along the
    mesh axis within each slice.
closed form
    Hertz (``p_0``, ``a``, ``delta``) wherever the normal problem is uncoupled (``mu = 0`` or
    ``beta = 0``) and the bodies are elastic; Cattaneo-Mindlin (stick ratio ``c / a``) where
    in addition ``mu > 0`` and ``0 <= Q < mu W``.
"""

from __future__ import annotations

import itertools
import json
import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from solver.result import SOLVE_STATUSES, STATUS_FLAGS

#: Quantities studied (when present in the dataset): name -> (units, label).
QUANTITIES = {
    "max_pressure": ("Pa", "max pressure p_0"),
    "contact_radius": ("m", "contact radius a"),
    "stick_radius": ("m", "stick radius c"),
    "stick_ratio": ("1", "stick ratio c / a_H"),
    "approach": ("m", "approach delta"),
    "max_plastic_strain": ("1", "max equivalent plastic strain"),
    "max_plastic_strain_depth": ("m", "depth of the max plastic strain"),
    "residual_depth": ("m", "residual central dent"),
}
#: Campaign keys of refinement ("mesh") axes -> (what the count is, what h is).
MESH_KEYS = {
    "grid.n": ("cells per side", "h / a = 2 half_width / n (cell size over the Hertz semi-axis)"),
    "load.steps": ("load steps", "h = 1 / steps (load increment over the load)"),
}
#: Range of orders searched by :func:`fit_convergence`.
ORDER_RANGE = (0.05, 8.0)


# -- axes ----------------------------------------------------------------------------------------
def _key(dataset, name: str) -> str:
    return str(dataset[name].attrs.get("campaign_key", name))


def axis_dims(dataset) -> list[str]:
    """The sweep dimensions of a campaign dataset (those of ``status``)."""
    return list(dataset["status"].dims)


def mesh_coordinate(dataset, dim: str):
    """The refinement coordinate on ``dim`` (a DataArray), or None.

    A numeric coordinate counts when its ``campaign_key`` is in :data:`MESH_KEYS` (the first
    key in that order when several are zipped on ``dim``) or, lacking the attribute, when it is
    called ``grid_n``.
    """
    found = {}
    for name, coord in dataset.coords.items():
        if coord.dims != (dim,) or np.asarray(coord.values).dtype.kind not in "iuf":
            continue
        key = coord.attrs.get("campaign_key")
        if key is None and name == "grid_n":
            key = "grid.n"
        if key in MESH_KEYS:
            found.setdefault(key, coord)
    return next((found[key] for key in MESH_KEYS if key in found), None)


def finest_index(dataset, index: dict | None = None, skip: Sequence[str] = ()) -> dict:
    """``index`` (isel) completed with the finest value of every mesh axis not in ``skip``."""
    out = dict(index or {})
    for dim in mesh_axes(dataset):
        if dim not in skip:
            out[dim] = int(np.argmax(mesh_coordinate(dataset, dim).values))
    return out


def mesh_axes(dataset) -> list[str]:
    """Dimensions along which the mesh size varies (see :func:`mesh_coordinate`)."""
    return [dim for dim in axis_dims(dataset) if mesh_coordinate(dataset, dim) is not None]


def numeric_coordinate(dataset, dim: str):
    """A numeric coordinate along ``dim``: the dimension coordinate, else the first numeric one."""
    if dim in dataset.coords and np.asarray(dataset[dim].values).dtype.kind in "iuf":
        return dataset[dim]
    for coord in dataset.coords.values():
        if coord.dims == (dim,) and np.asarray(coord.values).dtype.kind in "iuf":
            return coord
    return None


def _base(dataset) -> dict:
    try:
        return json.loads(dataset.attrs.get("campaign_base", "{}"))
    except ValueError:
        return {}


def _base_value(dataset, key: str, default=math.nan):
    table = _base(dataset)
    for part in key.split("."):
        if not isinstance(table, dict) or part not in table:
            return default
        table = table[part]
    return table


def _case_input(dataset, key: str, default: float):
    """A case input as a DataArray over the axes: a swept coordinate or the base value."""
    import xarray as xr

    for coord in dataset.coords.values():
        if coord.attrs.get("campaign_key") == key:
            return coord.astype(float)
    value = _base_value(dataset, key, default)
    try:
        value = float(value)
    except (TypeError, ValueError):
        value = default
    return xr.DataArray(value)


def half_width(dataset):
    """Domain half-width over the Hertz semi-axis, as a DataArray (swept or base; default 1.5)."""
    return _case_input(dataset, "grid.half_width", 1.5)


def friction_coefficient(dataset):
    """Friction coefficient as a DataArray over the axes (swept or base; default 0)."""
    return _case_input(dataset, "friction.coefficient", 0.0)


def dundurs_beta(dataset):
    """Dundurs' beta per case (the dataset variable or coordinate; 0 when absent)."""
    import xarray as xr

    if "dundurs_beta" in dataset.variables:
        return dataset["dundurs_beta"].astype(float)
    return xr.DataArray(0.0)


def is_plastic(dataset) -> bool:
    """True when a body of the campaign is elastic-plastic (no closed form applies)."""
    if "max_plastic_strain" in dataset.variables:
        return True
    text = dataset.attrs.get("campaign_base", "") + dataset.attrs.get("campaign_axes", "")
    return "plastic" in text or "yield_stress" in text


# -- closed forms --------------------------------------------------------------------------------
def with_derived(dataset):
    """A copy with derived quantities: ``stick_ratio = min(stick_radius / hertz_radius, 1)``.

    ``stick_radius`` is ``sqrt(stick_area / pi)`` with the stick area counted in whole cells,
    like the contact area.  Under full stick (friction, no tangential load, beta = 0) every
    contact cell sticks, so the plain ratio would be the counted contact radius over the Hertz
    radius, which overshoots 1 by up to about half a cell (1.0048 at 48^2); a stick zone never
    exceeds the contact zone (c <= a), so the ratio is clipped to 1.  Below 1 it is the counted
    stick radius over the Hertz radius, the c / a of Cattaneo-Mindlin (``(1 - Q / (mu W))^(1/3)``
    for beta = 0).  Added only when some case has friction and a non-zero stick radius; NaN
    where mu = 0.
    """
    dataset = dataset.copy()
    if "stick_radius" in dataset and "hertz_radius" in dataset:
        mu = friction_coefficient(dataset)
        stick = dataset["stick_radius"].where(mu > 0)
        if bool(np.any(np.nan_to_num(stick.values) > 0)):
            dataset["stick_ratio"] = (
                (stick / dataset["hertz_radius"])
                .clip(max=1.0)
                .assign_attrs(
                    units="1",
                    long_name="stick radius over the Hertz radius (cell counts, at most 1)",
                )
            )
    return dataset


def cell_counts(dataset):
    """Grid cells of every case (``nx ny``, or ``nx ny nz`` with a volume grid), over the axes.

    From the ``grid_cells`` variable of the dataset (each case's normalised spec, written by
    :mod:`study.assemble`); for datasets assembled before it existed, from the ``grid.n`` input
    (swept or base: ``n^2`` or the product of ``[nx, ny(, nz)]``) times a swept or base
    ``grid.nz``.  NaN where unknown.
    """
    import xarray as xr

    if "grid_cells" in dataset.variables:
        return dataset["grid_cells"].astype(float)
    n = _base_value(dataset, "grid.n")
    if isinstance(n, list) and n:
        base = float(np.prod([float(v) for v in n]))
    elif isinstance(n, int | float):
        base = float(n) ** 2
    else:
        base = math.nan
    cells = xr.DataArray(base)
    for coord in dataset.coords.values():
        if coord.attrs.get("campaign_key") == "grid.n" and coord.dtype.kind in "iuf":
            cells = coord.astype(float) ** 2
    nz = _case_input(dataset, "grid.nz", math.nan)
    if bool(np.all(np.isfinite(nz.values))) and not (isinstance(n, list) and len(n) == 3):
        cells = cells * nz
    return cells.broadcast_like(dataset["status"])


def closed_forms(dataset) -> dict:
    """Closed-form values of the studied quantities, where they apply.

    Parameters
    ----------
    dataset : xarray.Dataset
        Campaign dataset (see :mod:`study.assemble`).

    Returns
    -------
    dict
        Quantity name -> DataArray over the axes (NaN where the closed form does not apply):
        ``max_pressure``, ``contact_radius``, ``approach`` from Hertz; ``stick_ratio`` and
        ``stick_radius`` from Cattaneo-Mindlin.  Empty for elastic-plastic campaigns.
    """
    import xarray as xr

    if is_plastic(dataset) or "hertz_pressure" not in dataset:
        return {}
    mu = friction_coefficient(dataset)
    beta = dundurs_beta(dataset)
    hertz_ok = (mu == 0) | (abs(beta) < 1e-12)
    refs = {
        "max_pressure": dataset["hertz_pressure"].where(hertz_ok),
        "contact_radius": dataset["hertz_radius"].where(hertz_ok),
        "approach": dataset["hertz_approach"].where(hertz_ok),
    }
    if "stick_radius" in dataset:
        from solver.reference import cattaneo_stick_ratio

        q = abs(dataset["tangential_force_x"]).fillna(0.0) if "tangential_force_x" in dataset else 0
        w = dataset["normal_force"]
        mu_b, q_b, w_b, ok_b = xr.broadcast(
            mu, xr.DataArray(q) if np.isscalar(q) else q, w, hertz_ok
        )
        ok = ok_b & (mu_b > 0) & (q_b < mu_b * w_b) & (abs(beta) < 1e-12)
        ratio = xr.apply_ufunc(
            np.vectorize(lambda qq, mm, ww: cattaneo_stick_ratio(qq, mm, ww) if mm > 0 else np.nan),
            q_b,
            mu_b,
            w_b,
        ).where(ok)
        if bool(np.any(np.isfinite(ratio.values))):
            refs["stick_ratio"] = ratio
            refs["stick_radius"] = ratio * dataset["hertz_radius"]
    return {k: v for k, v in refs.items() if bool(np.any(np.isfinite(v.values)))}


def scene(dataset) -> str:
    """A short label of the closed forms that apply: "Hertz", "Hertz, Cattaneo" or "none"."""
    refs = closed_forms(dataset)
    names = []
    if "max_pressure" in refs:
        names.append("Hertz")
    if "stick_ratio" in refs and bool(np.any(refs["stick_ratio"].fillna(1.0).values < 1.0)):
        names.append("Cattaneo")
    return ", ".join(names) or "none"


def quantities(dataset) -> list[str]:
    """The quantities of :data:`QUANTITIES` the dataset holds with some finite non-zero value."""
    found = []
    for name in QUANTITIES:
        if name in dataset.variables:
            values = np.asarray(dataset[name].values, dtype=float)
            if np.any(np.isfinite(values) & (values != 0)):
                found.append(name)
    return found


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


# -- tables --------------------------------------------------------------------------------------
def _slices(dataset, exclude: Sequence[str]):
    """Yield (label dict, isel dict) for every combination of the dims not in ``exclude``."""
    dims = [d for d in axis_dims(dataset) if d not in exclude]
    named = {d: _label_coordinates(dataset, d) for d in dims}
    for index in itertools.product(*(range(dataset.sizes[d]) for d in dims)):
        labels = {}
        for d, i in zip(dims, index, strict=True):
            for name in named[d] or [d]:
                value = dataset[name].values[i] if named[d] else i
                labels[name] = value.item() if hasattr(value, "item") else value
        yield labels, dict(zip(dims, index, strict=True))


def _label_coordinates(dataset, dim: str) -> list[str]:
    """Coordinates that label ``dim``: its own, else every coordinate along it (a zip)."""
    if dim in dataset.coords:
        return [dim]
    return [name for name, c in dataset.coords.items() if c.dims == (dim,)]


def _usable(dataset):
    """Quantities masked to finished cases (status converged, not_converged or truncated)."""
    status = dataset["status"]
    return status.isin([STATUS_FLAGS[name] for name in SOLVE_STATUSES])


def mesh_sizes(dataset, mesh_dim: str):
    """Refinement size over the axes (DataArray).

    ``h / a_x = 2 half_width / n`` for a grid axis, ``1 / steps`` for a load-step axis
    (:data:`MESH_KEYS`).
    """
    coord = mesh_coordinate(dataset, mesh_dim)
    n = coord.astype(float)
    if coord.attrs.get("campaign_key") == "load.steps":
        return 1.0 / n
    return 2.0 * half_width(dataset) / n


def mesh_meaning(dataset, mesh_dim: str) -> tuple[str, str]:
    """(what the count of a mesh axis is, what its h is): :data:`MESH_KEYS`."""
    key = mesh_coordinate(dataset, mesh_dim).attrs.get("campaign_key", "grid.n")
    return MESH_KEYS[key]


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
    values = dataset[quantity].where(_usable(dataset))
    h_all = mesh_sizes(dataset, mesh_dim).broadcast_like(values)
    ref_all = refs[quantity].broadcast_like(values) if quantity in refs else None
    n_coord = mesh_coordinate(dataset, mesh_dim).values
    rows = []
    for (labels, isel), (_, srow) in zip(
        _slices(dataset, [mesh_dim]), summary.iterrows(), strict=True
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
    values = dataset[quantity].where(_usable(dataset))
    h_all = mesh_sizes(dataset, mesh_dim).broadcast_like(values)
    ref_all = refs[quantity].broadcast_like(values) if quantity in refs else None
    n_coord = mesh_coordinate(dataset, mesh_dim).values
    rows = []
    for labels, isel in _slices(dataset, [mesh_dim]):
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


def sensitivity_table(dataset, quantity: str, axis: str):
    """Finite-difference sensitivity of a quantity to a (non-mesh) axis, on the finest meshes.

    Parameters
    ----------
    dataset : xarray.Dataset
        Campaign dataset.
    quantity : str
        Variable name.
    axis : str
        A numeric sweep dimension (e.g. friction coefficient, beta, load).

    Returns
    -------
    pandas.DataFrame
        One row per case (mesh axes at their finest value): the other axes' values, the axis
        value, ``value``, ``derivative`` (central differences, one-sided at the ends, on the
        possibly uneven axis values; units of the quantity per unit of the axis) and
        ``elasticity`` (``x / q dq/dx``, dimensionless; NaN where q or x is 0).
    """
    import pandas as pd

    dataset = with_derived(dataset)
    sub = dataset.isel(finest_index(dataset, skip=[axis]))
    x_coord = numeric_coordinate(sub, axis)
    if x_coord is None or sub.sizes[axis] < 2:
        return pd.DataFrame()
    x = x_coord.values.astype(float)
    values = sub[quantity].where(_usable(sub))
    rows = []
    for labels, isel in _slices(sub, [axis]):
        v = values.isel(isel).values.astype(float)
        with np.errstate(invalid="ignore", divide="ignore"):
            derivative = np.gradient(v, x) if len(x) > 1 else np.full_like(v, np.nan)
            elasticity = np.where((v != 0) & (x != 0), x / v * derivative, np.nan)
        for i in range(len(x)):
            rows.append(
                {
                    **labels,
                    x_coord.name: x[i],
                    "value": v[i],
                    "derivative": derivative[i],
                    "elasticity": elasticity[i],
                }
            )
    return pd.DataFrame(rows)


def sensitivity_axes(dataset) -> list[str]:
    """Numeric sweep dimensions that are not mesh axes and have at least two values."""
    mesh = set(mesh_axes(dataset))
    return [
        d
        for d in axis_dims(dataset)
        if d not in mesh and dataset.sizes[d] > 1 and numeric_coordinate(dataset, d) is not None
    ]


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
        ``err_<quantity>`` (signed relative error), ``error_basis`` ("closed form" or
        "extrapolated"), ``error`` and ``pareto``.
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
                _slices(sub, [primary]), summary["extrapolated"], strict=True
            ):
                target[isel] = extrapolated
            targets[q] = target.transpose(*dataset[q].dims)
            basis[q] = "extrapolated"
    usable = _usable(dataset)
    rows = []
    cells = cell_counts(dataset)
    for labels, isel in _slices(dataset, []):
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
        row["error_basis"] = (
            "closed form"
            if set(basis.values()) == {"closed form"}
            else (", ".join(f"{q}: {b}" for q, b in basis.items()))
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
