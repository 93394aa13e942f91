"""slipstick study framework: campaigns of cases, MPI driver, storage, analysis, command line."""

from solver import __version__

__all__ = ["__version__"]
