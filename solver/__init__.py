"""slipstick solver: pure numerics for elastic(-plastic) frictional contact.

Public entry point::

    case = solver.Case.from_dict(table)   # or Case.from_toml(path)
    result = solver.solve(case)
    dataset = result.to_xarray()

No MPI, no file output: the study layer (``study``) does both.

The parts, from the bottom up; each imports only those listed before it (tested):

- :mod:`solver.variables`, :mod:`solver.keys`: the declarations, of every history and field a
  result holds and of every key of a case table;
- :mod:`solver.numerics`: grids, FFTW plans, threads, tensor convention, Anderson acceleration;
- :mod:`solver.theory`: closed forms (Hertz, Mindlin, Sneddon, Hamilton, Kalker), shakedown rules;
- :mod:`solver.plasticity`: hardening laws and the return mapping;
- :mod:`solver.bodies`: shapes, height maps and roughness, elastic constants, Dundurs' beta;
- :mod:`solver.surface`: influence coefficients, DC-FFT, normal and tangential solvers;
- :mod:`solver.volume`: subsurface stress, eigenstrain operator, cuboid kernels;
- :mod:`solver.spec`: the case tables parsed, the grid sized, the notes, :class:`Case`;
- :mod:`solver.result`: :class:`Result` (fields, histories, per-cycle quantities, xarray);
- :mod:`solver.drive`: operators, contact steps, the plasticity loop, the moving window,
  :func:`solve`.
"""

from .drive.loops import solve
from .drive.operators import memory_estimate
from .result import Result
from .spec.case import Case
from .spec.reading import SpecError

__all__ = ["Case", "Result", "SpecError", "memory_estimate", "solve"]
__version__ = "0.1.0"
