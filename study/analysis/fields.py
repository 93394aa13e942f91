"""The per-case fields of a campaign as one lazy (dask-backed) xarray dataset.

The assembled dataset (:mod:`study.run.assemble`) holds scalars, histories and profiles; the 2-D
surface fields and the 3-D volume fields (plastic strain, residual stress, ...) stay in the
per-case files.  :func:`open_fields` opens those files lazily and lays their fields out over the
campaign's sweep axes, so that a campaign whose fields do not fit in memory can be reduced, sliced
or plotted one case (one dask chunk) at a time::

    from study.analysis.fields import open_fields

    fields = open_fields("out/fretting_ii")                 # nothing is read yet
    peak = fields.plastic_strain.max(("x_over_a", "y_over_a", "z_over_a")).compute()
    section = fields.plastic_strain.sel(y_over_a=0, method="nearest").sel(mu=0.5).load()

Cell coordinates are normalised by the case's reference semi-axis a_x (Hertz's; Sneddon's
contact radius for a profile) (``x_over_a``, ``y_over_a``, ``z_over_a``: depth into the
elastic-plastic body), so that cases with the same mesh but different loads or materials share
them; ``semi_axis_x`` (per case, m) turns them back
into metres.  Cases whose cells differ (a mesh or a depth axis) cannot share one array: select
one value of such an axis (``open_fields(out, grid_n=64)``).  Cases not finished (pending,
failed) hold NaN (``contact_state``: :data:`MISSING_FLAG`).
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from solver.result import length_scale
from solver.variables import FIELDS

from ..run import storage
from ..run.assemble import _coordinates

if TYPE_CHECKING:
    import xarray as xr

#: The fields a case file may hold: the declared ones and the contact state map.
FIELD_NAMES = (*FIELDS, "contact_state")
#: Value of an integer field (``contact_state``) in a case not finished (float fields: NaN).
MISSING_FLAG = -1
#: Cell dimensions of the case files (``z_body1``: body 1's own volume grid).
CELL_DIMS = ("x", "y", "z", "z_body1")
#: Relative tolerance within which two cases' normalised cell centres count as the same.
COORDINATE_RTOL = 1e-9


def _normalised(case: xr.Dataset, dim: str) -> np.ndarray:
    """Cell centres along ``dim`` over the case's reference semi-axis a_x.

    Hertz's, or Sneddon's contact radius for a profile (:func:`solver.result.length_scale`).
    """
    return np.asarray(case[dim].values, dtype=float) / length_scale(case.attrs)


def open_fields(out: str | Path, names: list[str] | None = None, **selection) -> xr.Dataset:
    """Open the fields of a campaign's case files lazily, over the sweep axes.

    Parameters
    ----------
    out : str or Path
        Campaign output folder (with ``campaign.json`` and ``cases/``).
    names : list of str, optional
        Fields to open (:data:`FIELD_NAMES`); default every field that a finished case file
        holds.
    **selection
        ``coordinate=value`` pairs that keep only the cases with that swept value (e.g.
        ``grid_n=64``); the axis then drops out.

    Returns
    -------
    xarray.Dataset
        One dask-backed variable per field, dims ``(*sweep axes, [component,] x_over_a,
        y_over_a[, z_over_a])``, one chunk per case; the sweep coordinates, ``case_id`` and
        ``semi_axis_x`` (m) per case.

    Raises
    ------
    ValueError
        If a selection names no coordinate or value, no selected case is finished, a field is
        unknown or absent, or the selected cases' cells differ (the message names the axis to
        select).
    """
    import dask.array as da
    import xarray as xr

    campaign = storage.read_campaign(out)
    cases = list(campaign.cases)
    known = {c.name: c for axis in campaign.axes for c in axis.coordinates}
    for name, value in selection.items():
        if name not in known:
            raise ValueError(
                f"open_fields: {name!r} is not a sweep coordinate; use one of {sorted(known)}"
            )
        if value not in known[name].values:
            raise ValueError(
                f"open_fields: {name}={value!r} is not a swept value; the values are "
                f"{list(known[name].values)}"
            )
        cases = [c for c in cases if c.coords[name] == value]
    axes = [
        axis for axis in campaign.axes if not any(c.name in selection for c in axis.coordinates)
    ]
    for i, axis in enumerate(campaign.axes):
        left = sorted({c.index[i] for c in cases})
        if axis not in axes and len(left) > 1:
            raise ValueError(
                f"open_fields: the selection leaves {len(left)} values of the axis "
                f"{axis.name!r}; select it by a coordinate that names one value"
            )
    dims = tuple(axis.name for axis in axes)
    shape = tuple(axis.size for axis in axes)
    keep = [i for i, axis in enumerate(campaign.axes) if axis in axes]
    finished = storage.finished_ids(out)
    opened = {
        c.case_id: xr.open_dataset(
            storage.case_path(out, c.case_id), engine=storage.ENGINE, chunks={}
        )
        for c in cases
        if c.case_id in finished
    }
    if not opened:
        raise ValueError(f"open_fields: no finished case in {out} (with {selection or 'all'})")
    holding = {n: [i for i, d in opened.items() if n in d.data_vars] for n in FIELD_NAMES}
    available = [name for name, ids in holding.items() if ids]
    names = list(names) if names is not None else available
    for name in names:
        if name not in FIELD_NAMES:
            raise ValueError(f"open_fields: unknown field {name!r}; fields are {FIELD_NAMES}")
        if name not in available:
            raise ValueError(
                f"open_fields: the case files hold no {name!r}; they hold {available} "
                "(volume tensors are kept when listed in output.fields)"
            )
    reference: dict[str, np.ndarray] = {}
    source: dict[str, str] = {}
    for name in names:
        for case_id in holding[name]:
            data = opened[case_id]
            for d in (d for d in CELL_DIMS if d in data[name].dims):
                values = _normalised(data, d)
                if d not in reference:
                    reference[d], source[d] = values, case_id
                elif not (
                    values.shape == reference[d].shape
                    and np.allclose(values, reference[d], rtol=COORDINATE_RTOL, atol=0.0)
                ):
                    axis = _varying_axis(axes, cases, source[d], case_id)
                    raise ValueError(
                        f"open_fields: cases {source[d]} and {case_id} have different cells "
                        f"along {d}; select one value of the axis {axis!r} that changes them "
                        f"(e.g. open_fields(out, {axis}=...))"
                    )
    cell_dims = [d for d in CELL_DIMS if d in reference]
    index_of = {c.case_id: tuple(c.index[i] for i in keep) for c in cases}
    data_vars = {}
    for name in names:
        template = opened[holding[name][0]][name]
        attrs = dict(template.attrs)
        missing = np.nan if np.issubdtype(template.dtype, np.floating) else MISSING_FLAG
        if missing is MISSING_FLAG:
            attrs["missing_value"] = MISSING_FLAG
        blocks = np.empty(shape, dtype=object)
        for index in np.ndindex(*shape):
            blocks[index] = da.full(template.shape, missing, dtype=template.dtype)
        for case_id in holding[name]:
            if case_id in index_of:
                blocks[index_of[case_id]] = opened[case_id][name].data
        array = da.stack(list(blocks.ravel()), axis=0).reshape(shape + template.shape)
        inner = tuple(f"{d}_over_a" if d in cell_dims else d for d in template.dims)
        data_vars[name] = (dims + inner, array, attrs)
    coords: dict = {
        f"{d}_over_a": (
            f"{d}_over_a",
            reference[d],
            {"units": "1", "long_name": f"cell centre {d} over the Hertz semi-axis a_x"},
        )
        for d in cell_dims
    }
    for name in names:
        template = opened[holding[name][0]][name]
        if "component" in template.dims:
            coords["component"] = ("component", template["component"].values)
    for axis in axes:
        coords.update(_coordinates(axis))
    ids = np.full(shape, "", dtype=object)
    scale = np.full(shape, np.nan)
    for c in cases:
        ids[index_of[c.case_id]] = c.case_id
        if c.case_id in opened:
            scale[index_of[c.case_id]] = length_scale(opened[c.case_id].attrs)
    data_vars["case_id"] = (dims, ids.astype(str), {"long_name": "case id (cases/<id>.nc)"})
    data_vars["semi_axis_x"] = (
        dims,
        scale,
        {
            "units": "m",
            "long_name": "reference semi-axis a_x of the case: Hertz's, or Sneddon's contact "
            "radius for a profile (cell coordinates' unit)",
        },
    )
    attrs = {"campaign": campaign.name, "selection": repr(selection or {})}
    return xr.Dataset(data_vars, coords=coords, attrs=attrs)


def _varying_axis(axes, cases, first_id: str, other_id: str) -> str:
    """Name of the first axis whose coordinate differs between two cases."""
    by_id = {c.case_id: c for c in cases}
    a, b = by_id[first_id], by_id[other_id]
    for axis in axes:
        for c in axis.coordinates:
            if a.coords[c.name] != b.coords[c.name]:
                return c.name
    return "?"
