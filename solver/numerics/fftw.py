"""FFTW plans from one place: the planner modes, and wisdom handed in and out (no file I/O).

Every FFT plan of the solver is made by :func:`plan`, with one of the planner flags of
:data:`PLANNER_FLAGS` (``solver.fft_planner``):

- ``"estimate"``: FFTW's heuristics.  The same plans in every process: reproducible to the bit.
- ``"measure"``: FFTW times candidate algorithms and keeps the fastest.  Faster transforms,
  but the choice depends on timing noise, so two processes may round differently.
- ``"wisdom"``: a plan FFTW already knows (its wisdom: measured plans, imported with
  :func:`import_wisdom`) where it has one, else the estimate plan.  Processes that imported
  the same wisdom make the same plans: measured speed, reproducible to the bit.  Wisdom is
  made by planning with ``"measure"`` and read out with :func:`export_wisdom`; ``study``
  keeps it per machine in a cache folder and hands it to every rank.
"""

from __future__ import annotations

import importlib
import sys
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    import pyfftw

#: FFTW planner flag of each ``solver.fft_planner`` value.
PLANNER_FLAGS = {
    "estimate": "FFTW_ESTIMATE",
    "measure": "FFTW_MEASURE",
    "wisdom": "FFTW_WISDOM_ONLY",
}


#: What pyFFTW's ``interfaces`` import when it is installed, for an interface the solver never
#: uses: dask's FFT wrapper, and with it dask.array, xarray and pandas (about 0.7 s and 55 MiB
#: of every solving process, measured 2026-11-28).
_UNUSED_INTERFACE = "dask.array.fft"


def _pyfftw():
    """The pyfftw module, imported on first use, without its dask interface.

    Reading and checking case tables never needs it.  Unless this process has imported dask's
    FFT already, the import sees :data:`_UNUSED_INTERFACE` as absent (pyFFTW skips an absent
    interface), so that a solve does not load dask, xarray and pandas; the module can still
    be imported afterwards.
    """
    if "pyfftw" in sys.modules:
        return sys.modules["pyfftw"]
    hidden = _UNUSED_INTERFACE not in sys.modules
    if hidden:
        sys.modules[_UNUSED_INTERFACE] = None  # an import of it raises ImportError
    try:
        return importlib.import_module("pyfftw")
    finally:
        if hidden and sys.modules.get(_UNUSED_INTERFACE, 0) is None:
            del sys.modules[_UNUSED_INTERFACE]


def empty_aligned(shape: tuple[int, ...], dtype) -> np.ndarray:
    """An uninitialised array aligned for FFTW's SIMD transforms (``pyfftw.empty_aligned``)."""
    return _pyfftw().empty_aligned(shape, dtype=dtype)


def plan(
    input_array,
    output_array,
    *,
    axes: tuple[int, ...],
    planner: str = "FFTW_ESTIMATE",
    direction: str = "FFTW_FORWARD",
    threads: int = 1,
    extra: tuple[str, ...] = (),
) -> pyfftw.FFTW:
    """An FFTW plan between two arrays, planned by ``planner`` (a value of :data:`PLANNER_FLAGS`).

    ``"FFTW_WISDOM_ONLY"`` takes the measured plan from the imported wisdom when there is one
    and the estimate plan otherwise (never a new measurement).  ``extra`` are further flags
    (``"FFTW_DESTROY_INPUT"``, ``"FFTW_UNALIGNED"``); ``direction`` also takes FFTW's real-to-real
    kinds (``"FFTW_REDFT10"``...).
    """
    options = {"axes": axes, "direction": direction, "threads": threads}
    if planner == "FFTW_WISDOM_ONLY":
        try:
            flags = ("FFTW_MEASURE", "FFTW_WISDOM_ONLY", *extra)
            return _pyfftw().FFTW(input_array, output_array, flags=flags, **options)
        except RuntimeError:  # no wisdom for this transform
            planner = "FFTW_ESTIMATE"
    return _pyfftw().FFTW(input_array, output_array, flags=(planner, *extra), **options)


def export_wisdom() -> tuple[bytes, bytes, bytes]:
    """FFTW's accumulated wisdom (double, single, long double), to save or send."""
    return _pyfftw().export_wisdom()


def import_wisdom(wisdom: tuple[bytes, bytes, bytes]) -> None:
    """Add saved wisdom to this process's (what :func:`export_wisdom` gave)."""
    _pyfftw().import_wisdom(tuple(wisdom))


def forget_wisdom() -> None:
    """Drop this process's wisdom (tests)."""
    _pyfftw().forget_wisdom()
