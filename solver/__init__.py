"""slipstick solver: pure numerics for elastic(-plastic) frictional contact.

Public entry point::

    case = solver.Case.from_dict(table)   # or Case.from_toml(path)
    result = solver.solve(case)
    dataset = result.to_xarray()

No MPI, no file output: the study layer (``study``) does both.
"""

from .drive.loops import solve
from .drive.operators import memory_estimate
from .result import Result
from .spec.case import Case
from .spec.reading import SpecError

__all__ = ["Case", "Result", "SpecError", "memory_estimate", "solve"]
__version__ = "0.1.0"
