"""A campaign dataset's axes, mesh coordinates, case inputs and closed forms.

The helpers every analysis shares: which dimensions are sweep axes and which refine the mesh,
the inputs of a case read back from the dataset, derived quantities, the closed forms of the
scene, and the slices of the non-refinement axes.
"""

from __future__ import annotations

import itertools
import json
import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from solver.result import SOLVE_STATUSES, STATUS_FLAGS

if TYPE_CHECKING:
    import xarray as xr

#: Quantities studied (when present in the dataset): name -> (units, label).
QUANTITIES = {
    "max_pressure": ("Pa", "max pressure p_0"),
    "contact_radius": ("m", "contact radius a"),
    "stick_radius": ("m", "stick radius c"),
    "stick_ratio": ("1", "stick ratio c / a (a_H when elastic)"),
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


class AnalysisError(ValueError):
    """A dataset, quantity or axis an analysis cannot use: the message names it and what to do."""


#: Per-case numbers that record the run rather than the contact (listed last).
RUN_RECORDS = (
    "mpi_rank", "grid_cells", "steps", "wall_time", "cpu_time", "case_time", "peak_rss",
)  # fmt: skip
#: Most names a message lists before it says how many more there are.
LISTED = 10


# -- checks of a caller's arguments --------------------------------------------------------------
def check_dataset(dataset: object) -> None:
    """Raise unless ``dataset`` is a campaign's :class:`xarray.Dataset` (with ``status``).

    Raises
    ------
    TypeError
        A path (to open first) or another object than a Dataset.
    AnalysisError
        A Dataset that is not a campaign's (no ``status``).
    """
    import os
    from pathlib import Path

    import xarray as xr

    if isinstance(dataset, str | os.PathLike):
        path = Path(dataset)
        found = sorted(path.glob("*.nc")) if path.is_dir() else []
        target = repr(str(found[0])) if found else "'OUT/<name>.nc'" if path.is_dir() else "path"
        raise TypeError(
            f"dataset: got a path {str(dataset)!r}; open it first with "
            f"xarray.open_dataset({target})"
        )
    if not isinstance(dataset, xr.Dataset):
        kind = type(dataset).__name__
        raise TypeError(
            f"dataset: got {'an' if kind[0] in 'AEIOUaeiou' else 'a'} {kind}; give the "
            "campaign's xarray.Dataset, xarray.open_dataset('OUT/<name>.nc')"
        )
    if "status" not in dataset.variables:
        raise AnalysisError(
            "dataset: not a campaign dataset (it has no status variable); give the one "
            "`python -m study run` assembled, xarray.open_dataset('OUT/<name>.nc')"
        )


def case_quantities(dataset: xr.Dataset) -> list[str]:
    """The variables with one number per case: numeric, on the dims of ``status``, no flag.

    :data:`QUANTITIES` first, then the others in the dataset's order, the run's own records
    (rank, cells, times, memory) last.
    """
    dims = set(axis_dims(dataset))
    found = [
        str(name)
        for name, var in dataset.data_vars.items()
        if set(var.dims) == dims and var.dtype.kind in "iuf" and "flag_values" not in var.attrs
    ]
    order = {name: i for i, name in enumerate(QUANTITIES)}
    return sorted(found, key=lambda q: (order.get(q, len(order)), q in RUN_RECORDS))


def _listed(names: list[str]) -> str:
    more = len(names) - LISTED
    return ", ".join(names[:LISTED]) + (f" (and {more} more)" if more > 0 else "") or "none"


def check_quantity(dataset: xr.Dataset, quantity: str) -> None:
    """Raise unless ``quantity`` names a variable with one number per case of ``dataset``.

    Raises
    ------
    TypeError
        ``quantity`` is not a string.
    AnalysisError
        No such variable, a text or flag variable, or one with other dimensions than the cases'
        (a profile, a history, a per-cycle quantity); the message lists the usable ones.
    """
    names = case_quantities(dataset)
    usable = f"give one of {_listed(names)}"
    if not isinstance(quantity, str):
        raise TypeError(
            f"quantity: got {quantity!r} ({type(quantity).__name__}), not a name; {usable}"
        )
    if quantity not in dataset.data_vars:
        import difflib

        if quantity in dataset.coords:
            raise AnalysisError(f"quantity {quantity!r} is an input (a coordinate); {usable}")
        close = difflib.get_close_matches(quantity, names, n=1)
        hint = f"did you mean {close[0]!r}? " if close else ""
        raise AnalysisError(
            f"quantity {quantity!r}: no such variable in the dataset; {hint}{usable}"
        )
    var = dataset[quantity]
    if var.dtype.kind not in "iuf":
        kind = "text" if var.dtype.kind in "USO" else str(var.dtype)
        raise AnalysisError(f"quantity {quantity!r} is not numeric (it holds {kind}); {usable}")
    if "flag_values" in var.attrs:
        meaning = var.attrs.get("long_name", "flags")
        raise AnalysisError(f"quantity {quantity!r} is a flag ({meaning}), not a measure; {usable}")
    dims = axis_dims(dataset)
    extra = [d for d in var.dims if d not in dims]
    if extra or set(var.dims) != set(dims):
        pick = f"; or pick one value along {extra[0]} first, e.g. dataset.isel({extra[0]}=0)"
        raise AnalysisError(
            f"quantity {quantity!r} has dims ({', '.join(map(str, var.dims))}), not one number "
            f"per case (dims {', '.join(dims)}): {usable}" + (pick if extra else "")
        )


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
    """A copy with derived quantities: ``stick_ratio``, the stick radius over the contact's.

    ``stick_radius`` is ``sqrt(stick_area / pi)`` with the stick area counted in whole cells,
    like the contact area.  An elastic case's ratio is over the Hertz radius (the c / a of
    Cattaneo-Mindlin, ``(1 - Q / (mu W))^(1/3)`` for beta = 0); an elastic-plastic case's
    contact outgrows a_H, so its ratio is over its own (counted) contact radius.  Under full
    stick every contact cell sticks, and the counted radius overshoots a_H by up to about half a
    cell (1.0048 at 48^2); a stick zone never exceeds the contact zone (c <= a), so the ratio is
    clipped to 1.  Added only when some case has friction and a non-zero stick radius; NaN
    where mu = 0.
    """
    dataset = dataset.copy()
    if "stick_radius" in dataset and "hertz_radius" in dataset:
        mu = friction_coefficient(dataset)
        stick = dataset["stick_radius"].where(mu > 0)
        if bool(np.any(np.nan_to_num(stick.values) > 0)):
            radius = dataset["hertz_radius"]
            if "max_plastic_strain" in dataset and "contact_radius" in dataset:
                plastic = dataset["max_plastic_strain"].fillna(0.0) > 0
                radius = radius.where(~plastic, dataset["contact_radius"])
            dataset["stick_ratio"] = (
                (stick / radius)
                .clip(max=1.0)
                .assign_attrs(
                    units="1",
                    long_name="stick radius over the contact radius (a_H when elastic; cell "
                    "counts, at most 1)",
                )
            )
    return dataset


def cell_counts(dataset):
    """Grid cells of every case (``nx ny``, or ``nx ny nz`` with a volume grid), over the axes.

    From the ``grid_cells`` variable of the dataset (each case's normalised spec, written by
    :mod:`study.run.assemble`); for datasets assembled before it existed, from the ``grid.n`` input
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
        Campaign dataset (see :mod:`study.run.assemble`).

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
        from solver.theory.friction import cattaneo_stick_ratio

        q = abs(dataset["tangential_force_x"]).fillna(0.0) if "tangential_force_x" in dataset else 0
        w = dataset["normal_force"]
        mu_b, q_b, w_b, ok_b = xr.broadcast(
            mu, xr.DataArray(q) if np.isscalar(q) else q, w, hertz_ok
        )
        ok = ok_b & (mu_b > 0) & (q_b < mu_b * w_b) & (abs(beta) < 1e-12)
        ratio = xr.apply_ufunc(
            np.vectorize(
                lambda qq, mm, ww: cattaneo_stick_ratio(qq, mm, ww) if qq < mm * ww else np.nan
            ),
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


# -- tables --------------------------------------------------------------------------------------
def sweep_slices(dataset, exclude: Sequence[str]):
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


def finished_mask(dataset):
    """Quantities masked to finished cases (a status of :data:`solver.result.SOLVE_STATUSES`)."""
    status = dataset["status"]
    return status.isin([STATUS_FLAGS[name] for name in SOLVE_STATUSES])


def finished_cases(dataset):
    """Yield (label dict, isel dict, case) for every finished case (:func:`finished_mask`)."""
    usable = finished_mask(dataset)
    for labels, isel in sweep_slices(dataset, []):
        if bool(usable.isel(isel)):
            yield labels, isel, dataset.isel(isel)


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
