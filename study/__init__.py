"""slipstick study framework: campaigns of cases, MPI driver, storage, analysis, command line.

The parts, each importing only those listed before it:

- :mod:`study.bundle`: the file that holds many finished cases (layout, index, reader);
- :mod:`study.campaign`: campaign files read, expanded into cases, validated and named;
- :mod:`study.run`: the MPI driver, stored cases, the campaign dataset, progress logging;
- :mod:`study.analysis`: convergence, sensitivity, speed against error, lazy 3-D fields;
- :mod:`study.report`: figure helpers, the elastic, plastic and cyclic sections, the builder;
- :mod:`study.bench`: timing helpers, one module per scene, the peer adapters, the registry;
- :mod:`study.validation`: what ``validate`` prints (summary, estimates, warnings);
- :mod:`study.cli`: ``python -m study`` on top.

Importing the package imports nothing heavy, so that ``python -m study`` can limit the BLAS
threads before numpy loads.
"""

__all__ = ["PARTS", "__version__"]
#: The parts from the bottom up, as listed above: each imports only those before it (and
#: :mod:`solver`); ``tests/test_layout.py`` checks it.
PARTS = (
    "bundle",
    "campaign",
    "run",
    "analysis",
    "report",
    "bench",
    "validation",
    "cli",
    "__main__",
)


def __getattr__(name: str):
    if name == "__version__":
        from solver import __version__

        return __version__
    raise AttributeError(f"module 'study' has no attribute {name!r}")
