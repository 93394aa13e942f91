"""Analysis of an assembled campaign dataset: convergence, sensitivity, speed versus error.

Every function takes the dataset written by :mod:`study.run.assemble` (``OUT/<name>.nc``, opened
with :func:`xarray.open_dataset`) and returns plain numbers or :class:`pandas.DataFrame` tables,
so they can be used from a notebook as well as by :mod:`study.report`.  The sensitivity
functions (Sobol', Morris, finite differences), given a path, an unknown quantity or one that is
not a number per case, raise a :class:`TypeError` or an :class:`AnalysisError` (a
:class:`ValueError`) whose one line says what to give instead.

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

The package: :mod:`.dataset` (axes, mesh coordinates, case inputs, closed forms) at the
bottom; :mod:`.convergence`, :mod:`.sensitivity` (local, along a swept axis),
:mod:`.global_sensitivity` (Sobol' and Morris over a sampled design), :mod:`.realisations`
and :mod:`.speed_error` on it;
:mod:`.fields` (the lazy 3-D field loader) beside them.  The names below are re-exported here:
``from study import analysis; analysis.convergence_table(ds, ...)``.
"""

from .convergence import (
    ORDER_RANGE,
    ConvergenceFit,
    convergence_summary,
    convergence_table,
    fit_convergence,
    observed_order,
    richardson,
)
from .dataset import (
    MESH_KEYS,
    QUANTITIES,
    AnalysisError,
    axis_dims,
    case_quantities,
    cell_counts,
    closed_forms,
    dundurs_beta,
    finest_index,
    finished_cases,
    finished_mask,
    friction_coefficient,
    half_width,
    is_plastic,
    mesh_axes,
    mesh_coordinate,
    mesh_meaning,
    mesh_sizes,
    numeric_coordinate,
    quantities,
    scene,
    sweep_slices,
    with_derived,
)
from .global_sensitivity import (
    design_method,
    morris_indices,
    result_quantities,
    sampled_inputs,
    sobol_indices,
)
from .realisations import (
    realisation_axes,
    realisation_statistics,
)
from .sensitivity import (
    sensitivity_axes,
    sensitivity_table,
)
from .speed_error import (
    pareto_front,
    speed_error_table,
)

__all__ = [
    "AnalysisError",
    "case_quantities",
    "design_method",
    "morris_indices",
    "result_quantities",
    "sampled_inputs",
    "sobol_indices",
    "ConvergenceFit",
    "MESH_KEYS",
    "ORDER_RANGE",
    "QUANTITIES",
    "axis_dims",
    "cell_counts",
    "closed_forms",
    "realisation_axes",
    "realisation_statistics",
    "convergence_summary",
    "convergence_table",
    "dundurs_beta",
    "finest_index",
    "fit_convergence",
    "friction_coefficient",
    "half_width",
    "is_plastic",
    "mesh_axes",
    "mesh_coordinate",
    "mesh_meaning",
    "mesh_sizes",
    "numeric_coordinate",
    "observed_order",
    "pareto_front",
    "quantities",
    "richardson",
    "scene",
    "sensitivity_axes",
    "sensitivity_table",
    "sweep_slices",
    "speed_error_table",
    "finished_cases",
    "finished_mask",
    "with_derived",
]
