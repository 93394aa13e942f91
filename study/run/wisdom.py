"""FFTW wisdom kept per machine, for cases with ``solver.fft_planner = "wisdom"``.

Measured FFT plans (:mod:`solver.numerics.fftw`) are faster than FFTW's estimates, but measuring
them takes time and depends on timing noise, so two processes measuring alike may round
differently.  Here they are measured once per machine and grid, on rank 0, and saved in a cache
folder (:func:`wisdom_file`; ``$SLIPSTICK_CACHE``, else ``$XDG_CACHE_HOME/slipstick``, else
``~/.cache/slipstick``, created on first use); every rank of a run imports the same wisdom
before its first case, so every rank and every later run makes the same plans and gives the
same bits.  A plan the wisdom lacks is an estimate plan, the same everywhere too.
"""

from __future__ import annotations

import base64
import hashlib
import importlib.metadata
import json
import logging
import os
import platform
from collections.abc import Iterable
from pathlib import Path

import solver
from solver.numerics import fftw

from ..campaign.surfaces import read_surface

#: Environment variable naming the cache folder.
CACHE_ENV = "SLIPSTICK_CACHE"
#: Format of the wisdom file.
FORMAT = 1


def _cpu_model() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor()


def machine_key() -> str:
    """What plans depend on: processor, architecture, cores, pyFFTW and FFTW's versions (hash)."""
    parts = [
        platform.machine(),
        _cpu_model(),
        str(os.cpu_count()),
        _pyfftw_version(),
    ]
    return hashlib.sha256("|".join(parts).encode()).hexdigest()[:16]


def _pyfftw_version() -> str:
    """The version of pyFFTW: its package metadata (no import), else the module's own."""
    try:
        return importlib.metadata.version("pyfftw")
    except importlib.metadata.PackageNotFoundError:  # installed without metadata
        import pyfftw

        return pyfftw.__version__


def cache_folder() -> Path:
    """The cache folder (not created here)."""
    if os.environ.get(CACHE_ENV):
        return Path(os.environ[CACHE_ENV])
    base = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
    return Path(base) / "slipstick"


def wisdom_file() -> Path:
    """The wisdom file of this machine, in the cache folder."""
    return cache_folder() / "fftw" / f"{machine_key()}.json"


def _plan_key(case: solver.Case) -> str:
    """What fixes a case's FFT plans: its grids, box, precision, threads, friction."""
    options = case.solver
    return repr(
        (
            case.surface_grid,
            case.volume_grid,
            case.volume_grid_of(1),
            case.plastic_box,
            options.volume_precision,
            options.fft_threads,
            case.friction_coefficient > 0,
        )
    )


def load() -> dict:
    """The saved wisdom: ``{"planned": [plan keys], "wisdom": (bytes, bytes, bytes)}`` or empty.

    A file that cannot be read (another machine's format, truncated) counts as none.
    """
    try:
        data = json.loads(wisdom_file().read_text())
        if data.get("format") != FORMAT or data.get("machine") != machine_key():
            return {}
        return {
            "planned": list(data["planned"]),
            "wisdom": tuple(base64.b64decode(w) for w in data["wisdom"]),
        }
    except (OSError, ValueError, KeyError, TypeError):
        return {}


def save(planned: list[str], wisdom: tuple[bytes, bytes, bytes]) -> Path:
    """Write the wisdom file atomically (the folder made if missing); returns its path."""
    path = wisdom_file()
    path.parent.mkdir(parents=True, exist_ok=True)
    data = {
        "format": FORMAT,
        "machine": machine_key(),
        "planned": sorted(set(planned)),
        "wisdom": [base64.b64encode(w).decode() for w in wisdom],
    }
    temporary = path.with_name(f"{path.name}.{os.getpid()}.tmp")
    temporary.write_text(json.dumps(data))
    os.replace(temporary, path)
    return path


def measure_plans(case: solver.Case) -> None:
    """Measure every FFT plan of ``case``'s solve into this process's wisdom (no kernels)."""
    from solver.drive.operators import CaseOperators

    table = case.to_dict()
    table["solver"]["fft_planner"] = "measure"
    operators = CaseOperators.build(solver.Case.from_dict(table, read_surface))
    for body in case.plastic_bodies:
        operators.volume(body)[1].make_plans()
    if operators.stress is not None:
        operators.stress.make_plans()


def prepare(cases: Iterable[solver.Case], logger: logging.Logger | None = None):
    """Import the saved wisdom, measure the plans of the grids it lacks, save; the wisdom.

    Only ``cases`` with ``fft_planner = "wisdom"`` count.  Returns the wisdom to hand to the
    other ranks (:func:`solver.numerics.fftw.import_wisdom`), or None when no case asks for it.  A
    cache folder that cannot be written costs the speed, not the run: a warning.
    """
    logger = logger or logging.getLogger("study")
    wanted = {}
    for case in cases:
        if case.solver.fft_planner == "wisdom":
            wanted.setdefault(_plan_key(case), case)
    if not wanted:
        return None
    saved = load()
    if saved:
        fftw.import_wisdom(saved["wisdom"])
    planned = saved.get("planned", [])
    missing = [key for key in wanted if key not in planned]
    for key in missing:
        logger.info("measuring the FFT plans of a new grid (saved for this machine)")
        measure_plans(wanted[key])
    wisdom = fftw.export_wisdom()
    if missing:
        try:
            path = save(planned + missing, wisdom)
            logger.info("FFTW wisdom saved in %s", path)
        except OSError as error:
            logger.warning("FFTW wisdom not saved (%s): the next run measures again", error)
    return wisdom
