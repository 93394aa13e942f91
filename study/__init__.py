"""slipstick study framework: campaigns of cases, MPI driver, storage, analysis, command line.

Modules: :mod:`study.campaign` (campaign files), :mod:`study.driver` (MPI distribution),
:mod:`study.storage` (per-case files), :mod:`study.assemble` (the campaign dataset),
:mod:`study.progress` (logging), :mod:`study.cli` (``python -m study``).

Importing the package imports nothing heavy, so that ``python -m study`` can limit the BLAS
threads before numpy loads.
"""

__all__ = ["__version__"]


def __getattr__(name: str):
    if name == "__version__":
        from solver import __version__

        return __version__
    raise AttributeError(f"module 'study' has no attribute {name!r}")
