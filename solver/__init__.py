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
- :mod:`solver.fatigue`: multiaxial fatigue criteria (Dang Van, Crossland) on stress paths;
- :mod:`solver.bodies`: shapes, height maps and roughness, elastic constants, Dundurs' beta;
- :mod:`solver.surface`: influence coefficients, DC-FFT, normal and tangential solvers;
- :mod:`solver.volume`: subsurface stress, eigenstrain operator, cuboid kernels;
- :mod:`solver.theorems`: shakedown theorems solved directly (Melan's static limit of a track
  as a conic program, its pointwise upper bound);
- :mod:`solver.case`: the case tables parsed, the grid sized, the notes, :class:`Case`;
- :mod:`solver.result`: :class:`Result` (fields, histories, per-cycle quantities, xarray);
- :mod:`solver.drive`: operators, contact steps, the plasticity loop, the moving window,
  :func:`solve`.

Where a new kind of physics goes:

- a body shape: :mod:`solver.bodies.geometry` (a profile) or :mod:`solver.bodies.heights` (given
  point by point); its keys in :mod:`solver.keys`, their parsing in :mod:`solver.case.bodies`;
- a load stage (a motion, a target): :class:`~solver.case.path.LoadStage` and its parser in
  :mod:`solver.case.path`, what an increment of it does in :mod:`solver.drive.loops`;
- a step or a loop: :mod:`solver.drive.steps`, or a loop around a step beside
  :mod:`solver.drive.plastic_loop`; its histories declared in :mod:`solver.variables` and
  written in :mod:`solver.drive.record`;
- a surface solver (a periodic operator, steady rolling): :mod:`solver.surface`;
- a hardening law: :mod:`solver.plasticity.hardening` (and the return mapping if it needs one);
- a closed form: :mod:`solver.theory`; a theorem solved as a program (a shakedown bound):
  :mod:`solver.theorems`; a criterion on stress paths (fatigue): :mod:`solver.fatigue`;
- a note or a refusal of a case: :mod:`solver.case.notes`.
"""

from .numerics.lazy import lazy_exports

#: Where each public name is defined; imported when first used (:mod:`solver.numerics.lazy`).
_PUBLIC = {
    "Case": ".case.case",
    "Result": ".result",
    "SpecError": ".case.reading",
    "memory_estimate": ".drive.operators",
    "solve": ".drive.loops",
}
__all__ = ["PARTS", *_PUBLIC]
__getattr__, __dir__ = lazy_exports(__name__, _PUBLIC)

#: The parts from the bottom up, as listed above: each imports only those before it (a
#: sub-package's modules import each other without a cycle); ``tests/test_layout.py`` checks it.
PARTS = (
    "variables", "keys", "numerics", "theory", "plasticity", "fatigue", "bodies", "surface",
    "volume",
    "theorems", "case", "result", "drive",
)  # fmt: skip
__version__ = "0.1.0"
