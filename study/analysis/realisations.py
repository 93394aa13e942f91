"""Statistics over realisations of a random surface: the seeds of a roughness.

A sweep over ``bodyN.roughness.seed`` draws several surfaces of one statistics (rms, Hurst
exponent, cut-offs); the dimension it spans is a *realisation axis*.  Its values are not a
physical parameter: the analysis reduces over it (mean, sample standard deviation, extremes and
the number of finished realisations) instead of differentiating along it
(:func:`study.analysis.sensitivity_axes` leaves it out).
"""

from __future__ import annotations

from .dataset import axis_dims, finished_mask, quantities

#: Campaign keys whose axis holds realisations (the seed of either body's roughness).
REALISATION_KEYS = ("body1.roughness.seed", "body2.roughness.seed")
#: Per-case results of a rough contact reduced over the realisations, besides
#: :func:`~study.analysis.dataset.quantities`.
ROUGH_QUANTITIES = ("contact_area", "contact_spots", "contact_fraction", "mean_separation")
#: The statistics of :func:`realisation_statistics`, in order.
STATISTICS = ("mean", "std", "min", "max")


def realisation_axes(dataset) -> list[str]:
    """Sweep dimensions whose coordinate is a roughness seed."""
    return [
        dim
        for dim in axis_dims(dataset)
        if any(
            coord.dims == (dim,) and coord.attrs.get("campaign_key") in REALISATION_KEYS
            for coord in dataset.coords.values()
        )
    ]


def realisation_statistics(dataset, names: list[str] | None = None):
    """Mean, sample standard deviation, min and max over the realisation axes.

    Parameters
    ----------
    dataset : xarray.Dataset
        An assembled campaign dataset with a realisation axis.
    names : list of str, optional
        Per-case variables to reduce; default the dataset's quantities and the
        :data:`ROUGH_QUANTITIES` it holds values of (the periodic ones in periodic cases).

    Returns
    -------
    xarray.Dataset
        Each variable with a leading ``statistic`` dimension (:data:`STATISTICS`) over the
        remaining sweep axes, and ``realisations``: the finished cases each statistic rests on
        (unfinished ones are left out, not counted as zero).

    Raises
    ------
    ValueError
        If the dataset has no realisation axis.
    """
    import xarray as xr

    dims = realisation_axes(dataset)
    if not dims:
        raise ValueError(
            "no realisation axis: sweep a roughness seed (body2.roughness.seed) to draw "
            "several surfaces of one statistics"
        )
    if names is None:
        rough = [n for n in ROUGH_QUANTITIES if n in dataset and dataset[n].notnull().any()]
        names = quantities(dataset) + rough
    finished = finished_mask(dataset)
    out = {}
    for name in names:
        values = dataset[name].where(finished)
        reduced = [
            values.mean(dims),
            values.std(dims, ddof=1),
            values.min(dims),
            values.max(dims),
        ]
        out[name] = xr.concat(reduced, dim="statistic").assign_attrs(dataset[name].attrs)
    data = xr.Dataset(out).assign_coords(statistic=list(STATISTICS))
    data["realisations"] = finished.sum(dims).assign_attrs(
        long_name="finished realisations per slice", units="1"
    )
    return data
