"""The per-case fields of a campaign as one lazy (dask-backed) xarray dataset.

The assembled dataset (:mod:`study.run.assemble`) holds scalars, histories and profiles; the 2-D
surface fields and the 3-D volume fields (plastic strain, residual stress, ...) stay with the
cases (the bundles of :mod:`study.bundle`).  :func:`open_fields` opens them lazily and lays
their fields out over the campaign's sweep axes, so that a campaign whose fields do not fit in
memory can be reduced, sliced or plotted one case (one dask chunk) at a time::

    from study.analysis.fields import open_fields

    fields = open_fields("out/fretting_ii")                 # nothing is read yet
    peak = fields.plastic_strain.max(("x_over_a", "y_over_a", "z_over_a")).compute()
    section = fields.plastic_strain.sel(y_over_a=0, method="nearest").sel(mu=0.5).load()

Cell coordinates are normalised by the case's reference semi-axis a_x (Hertz's; Sneddon's
contact radius for a profile) (``x_over_a``, ``y_over_a``, ``z_over_a``: depth into the
elastic-plastic body), so that cases with the same mesh but different loads or materials share
them; ``semi_axis_x`` (per case, m) turns them back
into metres.  Cases whose cells differ (a mesh axis, or a load or material axis of an
elastic-plastic campaign: the box depth is sized from each case's yield region) do not share
them: select one value of such an axis (``open_fields(out, grid_n=64)``), or lay the cases on
one grid in metres (``x``, ``y``, ``z``), NaN where a case's box does not reach::

    fields = open_fields("out/ep_friction_load", align="nearest")
    axis = fields.plastic_strain.sel(x=0, y=0, method="nearest")    # (mu, p_h, z)
    at = fields.plastic_strain.sel(z=0.3e-3, method="nearest")      # 0.3 mm deep, every load

``align="union"`` takes the union of the cases' cell centres and refuses cells that do not line
up (no value resampled); ``align="nearest"`` takes the finest case's cells, each case holding the
value of its own cell that contains a point (resampled by nearest cell, never interpolated).
Cases not finished (pending, failed) hold NaN (``contact_state``: :data:`MISSING_FLAG`).
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
    import dask.array as da
    import xarray as xr

#: The fields a case file may hold: the declared ones and the contact state map.
FIELD_NAMES = (*FIELDS, "contact_state")
#: Value of an integer field (``contact_state``) in a case not finished (float fields: NaN).
MISSING_FLAG = -1
#: Cell dimensions of the case files (``z_body1``: body 1's own volume grid).
CELL_DIMS = ("x", "y", "z", "z_body1")
#: Relative tolerance within which two cases' normalised cell centres count as the same.
COORDINATE_RTOL = 1e-9
#: How :func:`open_fields` lays the cases' cells on one grid: the same cells in units of a_x,
#: the union of cells that line up (m), the finest case's cells with each case's nearest (m).
ALIGNMENTS = ("exact", "union", "nearest")
#: Tolerance, in cells, within which cells line up (``align="union"``) and a point on a cell's
#: face counts as on it.
LATTICE_TOL = 1e-6
#: The ``resampling`` attribute of the cell coordinates (m) of each alignment.
RESAMPLING = {
    "union": "none: the union of the cases' cell centres (their cells line up); a case holds "
    "NaN where it has no cell",
    "nearest": "nearest cell: a case holds the value of its cell containing the point (the "
    "finest case's cells), NaN where none does",
}


def _normalised(case: xr.Dataset, dim: str) -> np.ndarray:
    """Cell centres along ``dim`` over the case's reference semi-axis a_x.

    Hertz's, or Sneddon's contact radius for a profile (:func:`solver.result.length_scale`).
    """
    return np.asarray(case[dim].values, dtype=float) / length_scale(case.attrs)


def open_fields(
    out: str | Path, names: list[str] | None = None, *, align: str = "exact", **selection
) -> xr.Dataset:
    """Open the fields of a campaign's case files lazily, over the sweep axes.

    Parameters
    ----------
    out : str or Path
        Campaign output folder (with ``campaign.json`` and ``cases/``).
    names : list of str, optional
        Fields to open (:data:`FIELD_NAMES`); default every field that a finished case file
        holds.
    align : {"exact", "union", "nearest"}, default "exact"
        How the cases' cells are laid on one grid (:data:`ALIGNMENTS`).

        ``"exact"``
            Every case has the same cells in units of its semi-axis a_x: cell coordinates
            ``x_over_a``, ``y_over_a``, ``z_over_a`` (1).  Cases whose cells differ are refused.
        ``"union"``
            Cell coordinates ``x``, ``y``, ``z`` in metres: along each, the union of the cases'
            cell centres.  The cells must line up (the same size, centres on one lattice, within
            :data:`LATTICE_TOL` of a cell), else refused: no value is resampled, each case
            holds its own cell values and NaN where its box does not reach.
        ``"nearest"``
            Cell coordinates ``x``, ``y``, ``z`` in metres on a common grid: the cells of the
            case with the finest spacing (along each coordinate apart), continued over the
            union of the cases' boxes.  Each case holds, at a grid point, the value of its own
            cell that contains the point (the nearest of its cell centres; a point on a face
            between two cells takes the one on its positive side, the deeper one along z), and
            NaN where no cell of it does (below or beside its box).  A case coarser than the
            grid repeats each cell's value over the grid points within it: values are
            resampled (nearest cell, never interpolated), which the coordinates'
            ``resampling`` attribute says.  Where the cells line up this is ``"union"``.  The
            grid has (extent of the boxes' union / finest cell) points per coordinate: it grows
            with the spread of the cases' semi-axes (a load sweep: of the loads).
    **selection
        ``coordinate=value`` pairs that keep only the cases with that swept value (e.g.
        ``grid_n=64``); the axis then drops out.

    Returns
    -------
    xarray.Dataset
        One dask-backed variable per field, dims ``(*sweep axes, [component,] x_over_a,
        y_over_a[, z_over_a])`` (``align="exact"``, 1) or ``(*sweep axes, [component,] x, y[,
        z])`` (m), one chunk per case; the sweep coordinates, ``case_id`` and ``semi_axis_x``
        (m) per case; the attribute ``align``.  Each case's field is read from its bundle when
        its chunk is computed (a per-case file of an older version stays open until
        ``close()`` or garbage collection).

    Raises
    ------
    ValueError
        If a selection names no coordinate or value, no selected case is finished, a field is
        unknown or absent, ``align`` is unknown, or the selected cases' cells differ under
        ``align="exact"`` (the message names the axis to select and the other alignments) or
        do not line up under ``align="union"`` (the message names ``align="nearest"``).

    Notes
    -----
    With the per-case files of an older version, close a result before opening the same files
    again where you can: the netCDF-4/HDF5 libraries may crash when a file holding a string
    variable (``component``, with tensor fields) is opened while it is open (netcdf4-python
    issue 1444, HDF5 issue 5359).

    Examples
    --------
    Plastic strain against depth on the contact axis over the loads of a load sweep, whose
    box depth and cell size follow the load:

    >>> fields = open_fields("out/ep_friction_load", align="nearest")  # doctest: +SKIP
    >>> fields.plastic_strain.sel(x=0, y=0, z=0.3e-3, method="nearest")  # doctest: +SKIP
    """
    if align not in ALIGNMENTS:
        raise ValueError(f"open_fields: align={align!r}; use one of {ALIGNMENTS}")
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
    index = storage.case_index(out)
    opened: dict[str, xr.Dataset] = {}

    def close() -> None:
        for data in opened.values():
            data.close()

    try:  # no file left open on an error (to the garbage collector)
        for c in cases:
            if c.case_id in index.results:
                opened[c.case_id] = storage.open_case(out, c.case_id, index, lazy=True)
        if not opened:
            raise ValueError(f"open_fields: no finished case in {out} (with {selection or 'all'})")
        fields = _layout(campaign, cases, axes, opened, names, align, selection)
    except BaseException:
        close()
        raise
    fields.set_close(close)
    return fields


def _layout(campaign, cases, axes, opened: dict, names, align: str, selection: dict):
    """The dataset of :func:`open_fields` from the opened cases (its arguments, checked)."""
    import dask.array as da
    import xarray as xr

    dims = tuple(axis.name for axis in axes)
    shape = tuple(axis.size for axis in axes)
    keep = [i for i, axis in enumerate(campaign.axes) if axis in axes]
    holding = {n: [i for i, d in opened.items() if n in d.data_vars] for n in FIELD_NAMES}
    available = [name for name, ids in holding.items() if ids]
    names = list(names) if names is not None else available
    for name in names:
        if name not in FIELD_NAMES:
            raise ValueError(f"open_fields: unknown field {name!r}; fields are {FIELD_NAMES}")
        if name not in available:
            raise ValueError(
                f"open_fields: the cases hold no {name!r}; they hold {available} "
                "(volume tensors are kept when listed in output.fields)"
            )
    # the cases holding a field along each cell dimension, in campaign order
    along: dict[str, list[str]] = {}
    for name in names:
        for case_id in holding[name]:
            for d in (d for d in CELL_DIMS if d in opened[case_id][name].dims):
                if case_id not in along.setdefault(d, []):
                    along[d].append(case_id)
    cell_dims = [d for d in CELL_DIMS if d in along]
    grids: dict[str, np.ndarray] = {}
    cells: dict[str, dict[str, tuple[np.ndarray, np.ndarray]]] = {}
    for d in cell_dims:
        if align == "exact":
            normalised = {i: _normalised(opened[i], d) for i in along[d]}
            grids[d] = _exact_cells(d, normalised, axes, cases)
        else:
            centres = {i: np.asarray(opened[i][d].values, dtype=float) for i in along[d]}
            grids[d], cells[d] = _common_cells(d, centres, align)
    index_of = {c.case_id: tuple(c.index[i] for i in keep) for c in cases}
    named = {d: f"{d}_over_a" if align == "exact" else d for d in cell_dims}
    data_vars = {}
    for name in names:
        template = opened[holding[name][0]][name]
        attrs = dict(template.attrs)
        missing = np.nan if np.issubdtype(template.dtype, np.floating) else MISSING_FLAG
        if missing is MISSING_FLAG:
            attrs["missing_value"] = MISSING_FLAG
        sizes = zip(template.dims, template.shape, strict=True)
        inner_shape = tuple(grids[d].size if d in grids else n for d, n in sizes)
        blocks = np.empty(shape, dtype=object)
        for index in np.ndindex(*shape):
            blocks[index] = da.full(inner_shape, missing, dtype=template.dtype)
        for case_id in holding[name]:
            if case_id in index_of:
                variable = opened[case_id][name]
                blocks[index_of[case_id]] = (
                    variable.data
                    if align == "exact"
                    else _placed(variable, {d: cells[d][case_id] for d in cells}, missing)
                )
        array = da.stack(list(blocks.ravel()), axis=0).reshape(shape + inner_shape)
        inner = tuple(named.get(d, d) for d in template.dims)
        data_vars[name] = (dims + inner, array, attrs)
    coords: dict = {}
    for d in cell_dims:
        if align == "exact":
            attrs = {"units": "1", "long_name": f"cell centre {d} over the Hertz semi-axis a_x"}
        else:
            attrs = {
                "units": "m",
                "long_name": opened[along[d][0]][d].attrs.get("long_name", f"cell centre {d}"),
                "resampling": RESAMPLING[align],
            }
        coords[named[d]] = (named[d], grids[d], attrs)
    for name in names:
        template = opened[holding[name][0]][name]
        if "component" in template.dims:
            component = template["component"]
            coords["component"] = ("component", component.values, component.attrs)
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
            "radius for a profile (unit of the x_over_a coordinates)",
        },
    )
    attrs = {"campaign": campaign.name, "selection": repr(selection or {}), "align": align}
    return xr.Dataset(data_vars, coords=coords, attrs=attrs)


def _exact_cells(dim: str, normalised: dict[str, np.ndarray], axes, cases) -> np.ndarray:
    """The normalised cell centres along ``dim`` shared by every case (``align="exact"``).

    Raises
    ------
    ValueError
        If two cases' centres differ; the message names the sweep coordinate that changes them
        and the alignments in metres.
    """
    first, reference = next(iter(normalised.items()))
    for case_id, values in normalised.items():
        if not (
            values.shape == reference.shape
            and np.allclose(values, reference, rtol=COORDINATE_RTOL, atol=0.0)
        ):
            axis = _varying_axis(axes, cases, first, case_id)
            raise ValueError(
                f"open_fields: cases {first} and {case_id} have different cells along {dim}; "
                f"select one value of the axis {axis!r} that changes them (e.g. "
                f"open_fields(out, {axis}=...)), or lay the cases on one grid in metres: "
                "open_fields(out, align='nearest') (each case's own cell values on the finest "
                "case's cells, NaN where its box does not reach), or align='union' (cells "
                "that line up, no value resampled)"
            )
    return reference


def _spacing(dim: str, centres: np.ndarray) -> float:
    """The (uniform) cell size along ``dim`` (m) of cell centres ``centres``."""
    if centres.size < 2:
        raise ValueError(f"open_fields: one cell along {dim}: no cell size to align it by")
    return float(centres[-1] - centres[0]) / (centres.size - 1)


def _common_cells(
    dim: str, centres: dict[str, np.ndarray], align: str
) -> tuple[np.ndarray, dict[str, tuple[np.ndarray, np.ndarray]]]:
    """A common grid along ``dim`` (m) and where each case's cells fall on it.

    The grid is the cells of the finest case continued over the union of the cases' boxes
    (points that no box holds dropped); each case's cell ``i`` spans ``centre_i -+ h / 2``.

    Parameters
    ----------
    dim : str
        Cell dimension (``x``, ``y``, ``z``, ``z_body1``).
    centres : dict of str to numpy.ndarray
        Each case's cell centres along ``dim`` (m), uniform, by case id.
    align : {"union", "nearest"}
        ``"union"`` refuses cases whose cells do not line up with the finest case's.

    Returns
    -------
    grid : numpy.ndarray
        The common cell centres (m), increasing.
    cells : dict of str to (numpy.ndarray, numpy.ndarray)
        Per case id: the index of its cell holding each grid point (clipped to its cells), and
        whether one does.

    Raises
    ------
    ValueError
        Under ``align="union"``, if a case's cells differ in size from the finest case's or
        are offset from them by a fraction of a cell (the message names ``align="nearest"``).
    """
    spacing = {case_id: _spacing(dim, values) for case_id, values in centres.items()}
    finest = min(spacing, key=spacing.__getitem__)
    step, anchor = spacing[finest], float(centres[finest][0])
    if align == "union":
        for case_id, values in centres.items():
            shift = (values[0] - anchor) / step
            if (
                abs(spacing[case_id] - step) > LATTICE_TOL * step
                or abs(shift - round(shift)) > LATTICE_TOL
            ):
                why = (
                    f"cells {spacing[case_id]:.6g} m and {step:.6g} m thick"
                    if abs(spacing[case_id] - step) > LATTICE_TOL * step
                    else f"cells offset by {shift - round(shift):+.3g} of a cell"
                )
                raise ValueError(
                    f"open_fields: the cells of cases {finest} and {case_id} do not line up "
                    f"along {dim} ({why}), so align='union' has no common grid; use "
                    "align='nearest' (each case's own cell values on the finest case's cells, "
                    "a coarser case's cell repeated over the grid points it holds)"
                )
    low = min(values[0] - spacing[i] / 2 for i, values in centres.items())
    high = max(values[-1] + spacing[i] / 2 for i, values in centres.items())
    steps = np.arange(np.floor((low - anchor) / step), np.ceil((high - anchor) / step) + 1)
    grid = anchor + steps * step
    cells = {i: _cells_holding(grid, values, spacing[i]) for i, values in centres.items()}
    held = np.any([inside for _, inside in cells.values()], axis=0)
    return grid[held], {i: (index[held], inside[held]) for i, (index, inside) in cells.items()}


def _cells_holding(points: np.ndarray, centres: np.ndarray, step: float):
    """Index of the cell (``centres``, size ``step``) holding each point, and whether one does.

    A point on a face between two cells (within :data:`LATTICE_TOL` of a cell) goes to the
    upper one; the upper face of the last cell is outside.
    """
    index = np.floor((points - (centres[0] - step / 2)) / step + LATTICE_TOL).astype(np.int64)
    inside = (index >= 0) & (index < centres.size)
    return np.clip(index, 0, centres.size - 1), inside


def _placed(variable: xr.DataArray, cells: dict, missing) -> da.Array:
    """A case's field (lazy, one chunk) on the common grid, ``missing`` outside its box.

    Parameters
    ----------
    variable : xarray.DataArray
        The case's field, dask-backed.
    cells : dict of str to (numpy.ndarray, numpy.ndarray)
        Per cell dimension: the index of the case's cell holding each grid point and whether
        one does (:func:`_common_cells`).
    missing : float or int
        Value where no cell of the case holds the point (NaN, or :data:`MISSING_FLAG`).

    Returns
    -------
    dask.array.Array
        One chunk, the dims of ``variable``, the grid's size along each cell dimension.
    """
    index = [
        cells[d][0] if d in cells else np.arange(n)
        for d, n in zip(variable.dims, variable.shape, strict=True)
    ]
    inside = np.ones([i.size for i in index], dtype=bool)
    for axis, d in enumerate(variable.dims):
        if d in cells:
            inside &= cells[d][1].reshape([-1 if a == axis else 1 for a in range(variable.ndim)])
    dtype = variable.dtype

    def place(block: np.ndarray) -> np.ndarray:
        return np.where(inside, block[np.ix_(*index)], missing).astype(dtype, copy=False)

    return variable.data.rechunk(-1).map_blocks(
        place,
        chunks=tuple((i.size,) for i in index),
        dtype=dtype,
        meta=np.empty((0,) * variable.ndim, dtype=dtype),
    )


def _varying_axis(axes, cases, first_id: str, other_id: str) -> str:
    """Name of the first axis whose coordinate differs between two cases."""
    by_id = {c.case_id: c for c in cases}
    a, b = by_id[first_id], by_id[other_id]
    for axis in axes:
        for c in axis.coordinates:
            if a.coords[c.name] != b.coords[c.name]:
                return c.name
    return "?"
