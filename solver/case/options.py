"""The ``[solver]`` and ``[output]`` tables: tolerances, iteration caps, FFT settings, fields.

Defaults and accepted ranges come from :data:`solver.keys.SOLVER_DEFAULTS` and
:data:`solver.keys.CASE_KEYS`; :data:`EXECUTION_KEYS` change how a case is computed, not what,
and stay out of its id.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from ..keys import (
    MAX_ANDERSON_MEMORY,
    MAX_FFT_THREADS,
    MAX_ITERATIONS,
    MAX_KINEMATIC_CELLS,
    MAX_TOLERANCE,
    MIN_SINGLE_PLASTIC_TOLERANCE,
    SOLVER_DEFAULTS,
    table_keys,
)
from ..numerics.fftw import PLANNER_FLAGS
from ..variables import OPTIONAL_FIELDS
from .reading import check_keys, fail, integer, number, plain


@dataclass(frozen=True)
class SolverOptions:
    """Tolerances and caps of the iterative loops (all dimensionless), and FFT settings.

    Defaults: :data:`solver.keys.SOLVER_DEFAULTS`.

    ``plastic_tolerance`` bounds the last change of a step's plastic strain increment relative
    to the yield strain sigma_Y0/E; ``anderson_memory`` is the number of past iterates the
    plasticity loop and the normal-tangential coupling loop mix (0: plain fixed-point iteration).

    ``fft_planner = "estimate"`` gives FFTW plans that do not depend on timing, so a case gives
    bit-identical results in any process; ``"measure"`` plans by timing (about 15 % faster
    solves, 0.5 s more set-up per grid) and results then agree only to round-off, which
    path-dependent coupled friction cases can amplify to ~1e-4.  ``"wisdom"`` takes measured
    plans from the wisdom imported into the process (:mod:`solver.numerics.fftw`), estimate plans
    where it has none: processes with the same wisdom give bit-identical results.
    """

    normal_tolerance: float = SOLVER_DEFAULTS["normal_tolerance"]
    normal_max_iterations: int = SOLVER_DEFAULTS["normal_max_iterations"]
    slip_tolerance: float = SOLVER_DEFAULTS["slip_tolerance"]
    slip_max_iterations: int = SOLVER_DEFAULTS["slip_max_iterations"]
    coupling_tolerance: float = SOLVER_DEFAULTS["coupling_tolerance"]
    coupling_max_iterations: int = SOLVER_DEFAULTS["coupling_max_iterations"]
    goodman: bool = SOLVER_DEFAULTS["goodman"]
    max_load_ratio: float = SOLVER_DEFAULTS["max_load_ratio"]
    plastic_tolerance: float = SOLVER_DEFAULTS["plastic_tolerance"]
    plastic_max_iterations: int = SOLVER_DEFAULTS["plastic_max_iterations"]
    anderson_memory: int = SOLVER_DEFAULTS["anderson_memory"]
    fft_threads: int = SOLVER_DEFAULTS["fft_threads"]
    fft_planner: str = SOLVER_DEFAULTS["fft_planner"]
    volume_precision: str = SOLVER_DEFAULTS["volume_precision"]
    method: str = SOLVER_DEFAULTS["method"]
    residual_print: str = SOLVER_DEFAULTS["residual_print"]
    kinematic_cells: int = SOLVER_DEFAULTS["kinematic_cells"]
    steady_order: int = SOLVER_DEFAULTS["steady_order"]


SOLVER_RULES = {
    "normal_tolerance": ("tol",),
    "normal_max_iterations": ("int",),
    "slip_tolerance": ("tol",),
    "slip_max_iterations": ("int",),
    "coupling_tolerance": ("tol",),
    "coupling_max_iterations": ("int",),
    "goodman": ("bool",),
    "max_load_ratio": ("ratio",),
    "plastic_tolerance": ("tol",),
    "plastic_max_iterations": ("int",),
    "anderson_memory": ("memory",),
    "fft_threads": ("threads",),
    "fft_planner": ("planner",),
    "volume_precision": ("precision",),
    "method": ("method",),
    "residual_print": ("print",),
    "kinematic_cells": ("kinematic",),
    "steady_order": ("order",),
}


def parse_solver(table: Any) -> SolverOptions:
    """The :class:`SolverOptions` of a ``[solver]`` table (defaults filled in)."""
    check_keys(table, "solver", table_keys("solver"))
    values = {}
    for key, value in table.items():
        rule = SOLVER_RULES[key][0]
        path = f"solver.{key}"
        if rule == "tol":
            values[key] = number(value, path, positive=True)
            if values[key] >= MAX_TOLERANCE:
                fail(path, f"tolerance must be < {MAX_TOLERANCE:g}, got {value}")
        elif rule == "int":
            values[key] = integer(value, path, 1, MAX_ITERATIONS)
        elif rule == "ratio":
            values[key] = number(value, path, positive=True, allow_inf=True)
            if values[key] <= 1.0:
                fail(path, f'must be > 1 (or "inf" to disable sub-stepping), got {value}')
        elif rule == "planner":
            if value not in PLANNER_FLAGS:
                fail(
                    path,
                    f'must be "estimate" (reproducible), "measure" or "wisdom" (measured plans '
                    f"saved per machine, reproducible), got {value!r}",
                )
            values[key] = value
        elif rule == "precision":
            if value not in ("double", "single"):
                fail(path, f'must be "double" or "single", got {value!r}')
            values[key] = value
        elif rule == "method":
            if value not in METHODS:
                fail(path, f"must be one of {list(METHODS)}, got {value!r}")
            values[key] = value
        elif rule == "print":
            if value not in RESIDUAL_PRINTS:
                fail(path, f"must be one of {list(RESIDUAL_PRINTS)}, got {value!r}")
            values[key] = value
        elif rule == "order":
            values[key] = integer(value, path, 1, 2)
        elif rule == "kinematic":
            values[key] = integer(value, path, 0, MAX_KINEMATIC_CELLS)
        elif rule == "threads":
            values[key] = integer(value, path, 1, MAX_FFT_THREADS)
        elif rule == "memory":
            values[key] = integer(value, path, 0, MAX_ANDERSON_MEMORY)
        elif not isinstance(value := plain(value), bool):
            fail(path, f"must be true or false, got {value!r}")
        else:
            values[key] = value
    options = SolverOptions(**values)
    if (
        options.volume_precision == "single"
        and options.plastic_tolerance < MIN_SINGLE_PLASTIC_TOLERANCE
    ):
        fail(
            "solver.volume_precision",
            f"single precision rounds the stress to ~1e-7, too coarse for plastic_tolerance = "
            f"{options.plastic_tolerance:g}: use plastic_tolerance >= "
            f'{MIN_SINGLE_PLASTIC_TOLERANCE:g} or volume_precision = "double"',
        )
    return options


#: What ``solver.method`` can be: the load path's loops, or Melan's theorem solved directly.
METHODS = ("incremental", "static_shakedown")
#: Solver keys added after cases were stored: in the normalised table (and the case id) only
#: when not their default, so the ids of the cases before them stay as they were.
ID_SILENT_DEFAULTS = ("volume_precision", "method", "residual_print", "steady_order")
#: Solver keys of one method only: in the normalised table (and the case id) of that method's
#: cases, always, and of no other's.
METHOD_KEYS = {"kinematic_cells": "static_shakedown"}
#: What ``solver.residual_print`` can be: the print in the gap, or left out of it.
RESIDUAL_PRINTS = ("in_gap", "ignored")
#: Solver keys of how a case is computed, not what: kept in the table, not in the case id.
EXECUTION_KEYS = ("fft_threads", "fft_planner")


#: Field outputs a case may request.
FIELD_OUTPUTS = OPTIONAL_FIELDS
