"""Sensitivity of the results to the sweep axes that do not refine the mesh."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from .dataset import (
    AnalysisError,
    axis_dims,
    check_dataset,
    check_quantity,
    finest_index,
    finished_mask,
    mesh_axes,
    numeric_coordinate,
    sweep_slices,
    with_derived,
)
from .realisations import realisation_axes

if TYPE_CHECKING:
    import pandas as pd
    import xarray as xr


def sensitivity_table(dataset: xr.Dataset, quantity: str, axis: str) -> pd.DataFrame:
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
        ``elasticity`` (``x / q dq/dx``, dimensionless; NaN where q or x is 0); empty when
        ``axis`` has fewer than two values or no numeric coordinate.

    Raises
    ------
    TypeError
        ``dataset`` is a path (open it first) or not a Dataset, ``quantity`` not a name.
    AnalysisError
        ``quantity`` is not a numeric variable with one value per case, or ``axis`` not one of
        the cases' dimensions; the message lists what fits.
    """
    import pandas as pd

    check_dataset(dataset)
    dataset = with_derived(dataset)
    check_quantity(dataset, quantity)
    if axis not in axis_dims(dataset):
        raise AnalysisError(
            f"axis {axis!r}: not a dimension of the cases; give one of "
            f"{', '.join(sensitivity_axes(dataset)) or ', '.join(axis_dims(dataset))}"
        )
    sub = dataset.isel(finest_index(dataset, skip=[axis]))
    x_coord = numeric_coordinate(sub, axis)
    if x_coord is None or sub.sizes[axis] < 2:
        return pd.DataFrame()
    x = x_coord.values.astype(float)
    values = sub[quantity].where(finished_mask(sub))
    rows = []
    for labels, isel in sweep_slices(sub, [axis]):
        v = values.isel(isel).values.astype(float)
        with np.errstate(invalid="ignore", divide="ignore"):
            derivative = np.gradient(v, x) if len(x) > 1 else np.full_like(v, np.nan)
            # a change below round-off of the values over the axis' span is none (a quantity
            # the axis does not move showed -1e-19 in the report)
            span = float(np.ptp(x)) if len(x) > 1 else 0.0
            derivative[np.abs(derivative) * span <= 1e-12 * np.nanmax(np.abs(v), initial=0.0)] = 0.0
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


def sensitivity_axes(dataset: xr.Dataset) -> list[str]:
    """Numeric sweep dimensions that are not mesh, realisation or sampled axes, with 2+ values.

    A design's ``sample`` rows have their global sensitivity (:mod:`.global_sensitivity`).
    """
    check_dataset(dataset)
    skip = set(mesh_axes(dataset)) | set(realisation_axes(dataset)) | {"sample"}
    return [
        d
        for d in axis_dims(dataset)
        if d not in skip and dataset.sizes[d] > 1 and numeric_coordinate(dataset, d) is not None
    ]
