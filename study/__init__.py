"""slipstick study framework: campaigns of cases, MPI driver, storage, analysis, command line.

The parts, each a sub-package, each importing only those listed before it:

- :mod:`study.campaign`: campaign files read, expanded into cases, validated and named;
- :mod:`study.run`: the MPI driver, per-case storage, the campaign dataset, progress logging;
- :mod:`study.analysis`: convergence, sensitivity, speed against error, lazy 3-D fields;
- :mod:`study.report`: figure helpers, the elastic, plastic and cyclic sections, the builder;
- :mod:`study.bench`: timing helpers, one module per scene, the peer adapters, the registry;
- :mod:`study.cli`: ``python -m study`` on top.

The modules' former flat names (``study.driver``, ``study.fields``, ``study.bench_plastic``, ...)
still import, as the moved modules themselves, with a :class:`DeprecationWarning`
(:data:`MOVED`); ``python -m study.bench_plastic`` runs ``study.bench.plastic``.

Importing the package imports nothing heavy, so that ``python -m study`` can limit the BLAS
threads before numpy loads.
"""

import importlib
import importlib.abc
import importlib.util
import sys
import warnings

__all__ = ["MOVED", "__version__"]

#: Former flat module names -> where the module lives now.
MOVED = {
    "study.driver": "study.run.driver",
    "study.storage": "study.run.storage",
    "study.assemble": "study.run.assemble",
    "study.progress": "study.run.progress",
    "study.fields": "study.analysis.fields",
    "study.report_plastic": "study.report.plastic",
    "study.report_cycles": "study.report.cycles",
    "study.bench_plastic": "study.bench.plastic",
    "study.bench_cattaneo": "study.bench.cattaneo",
    "study.bench_cycles": "study.bench.cycles",
    "study.bench_slipstick": "study.bench.slipstick",
    "study.bench_subsurface": "study.bench.subsurface",
    "study.peers": "study.bench.peers",
    "study.peers_plastic": "study.bench.peers_plastic",
}


class _MovedModules(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    """Imports a former name of :data:`MOVED` as the moved module itself (one object)."""

    def find_spec(self, name, path=None, target=None):
        """A spec for a former name, None for any other."""
        return importlib.util.spec_from_loader(name, self) if name in MOVED else None

    def create_module(self, spec):
        """The moved module (its own spec and name kept)."""
        warnings.warn(
            f"{spec.name} moved to {MOVED[spec.name]}; import that instead",
            DeprecationWarning,
            stacklevel=3,
        )
        return importlib.import_module(MOVED[spec.name])

    def exec_module(self, module):
        """Nothing: the moved module ran when it was imported."""

    def get_code(self, name):
        """For ``python -m <former name>``: code that runs the moved module as ``__main__``."""
        return compile(
            f"import runpy\nrunpy.run_module({MOVED[name]!r}, run_name='__main__', alter_sys=True)",
            f"<{name}: moved to {MOVED[name]}>",
            "exec",
        )


if not any(isinstance(finder, _MovedModules) for finder in sys.meta_path):
    sys.meta_path.append(_MovedModules())


def __getattr__(name: str):
    if name == "__version__":
        from solver import __version__

        return __version__
    raise AttributeError(f"module 'study' has no attribute {name!r}")
