"""The unit costs of this machine for the cost model (:mod:`study.campaign.cost`), measured, kept.

:func:`measure` solves five small cases like the campaigns' (~10 s of CPU per core,
``time.process_time``, median of 2, in one process per core at once), splits each one's time
by the reference (:data:`~study.campaign.cost.REFERENCE`) into three families (Python
overheads, surface FFT work, volume FFT work) using its *measured* iteration counts, and fits
one speed factor per family.  The result is kept per machine in the cache folder of the FFT
wisdom (:func:`.wisdom.cache_folder`, ``$SLIPSTICK_CACHE``):
``cost/<machine key>-<fingerprint>.json``.  It is measured again when the file is missing or
unreadable, when its :data:`FORMAT`, the model (:data:`~study.campaign.cost.MODEL`), the
slipstick version or the :func:`fingerprint` (reference unit costs, calibration cases)
differs, or on request (``validate --recalibrate``).
"""

from __future__ import annotations

import hashlib
import json
import logging
import math
import os
import sys
import time
from dataclasses import asdict, replace
from pathlib import Path

import solver

from ..campaign.cost import (
    CACHE_CELLS,
    CACHE_EXPONENT,
    MODEL,
    REFERENCE,
    Calibration,
    Work,
    count,
    families,
)
from . import wisdom

#: Format of the calibration file.
FORMAT = 1


# -- calibration ---------------------------------------------------------------------------------
def calibration_file() -> Path:
    """The calibration file of this machine, in the cache folder of the FFT wisdom."""
    # one file per model version: processes of two versions never overwrite each other's
    return wisdom.cache_folder() / "cost" / f"{wisdom.machine_key()}-{fingerprint()}.json"


def fingerprint() -> str:
    """Hash of what a calibration depends on: the model's shape and the calibration cases."""
    text = json.dumps(
        [MODEL, asdict(REFERENCE), CACHE_EXPONENT, CACHE_CELLS, calibration_tables()],
        sort_keys=True,
    )
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def load() -> Calibration | None:
    """The saved calibration of this machine, or None (missing, unreadable, other format)."""
    try:
        data = json.loads(calibration_file().read_text())
        if (
            data.get("format") != FORMAT
            or data.get("model") != MODEL
            or data.get("machine") != wisdom.machine_key()
            or data.get("slipstick_version") != solver.__version__
            or data.get("fingerprint") != fingerprint()
        ):
            return None
        units = data["units"]
        found = Calibration(**units)
        if not all(math.isfinite(v) and v > 0 for v in (found.normal, found.volume)):
            return None
        return found
    except (OSError, ValueError, KeyError, TypeError):
        return None


def save(calibration: Calibration) -> Path:
    """Write the calibration file atomically (its folder made if missing); its path."""
    path = calibration_file()
    path.parent.mkdir(parents=True, exist_ok=True)
    data = {
        "format": FORMAT,
        "model": MODEL,
        "machine": calibration.machine,
        "slipstick_version": solver.__version__,
        "fingerprint": fingerprint(),
        "units": asdict(calibration),
    }
    temporary = path.with_name(f"{path.name}.{os.getpid()}.tmp")
    temporary.write_text(json.dumps(data, indent=1))
    os.replace(temporary, path)
    return path


_RIGID_SPHERE = {"radius": 0.015, "behaviour": "rigid"}
_STEEL = {"radius": "inf", "behaviour": "elastic", "E": 210e9, "nu": 0.3}
_SWIFT = {
    **_STEEL,
    "behaviour": "elastic-plastic",
    "hardening": {"law": "swift", "B": 945e6, "C": 20.0, "n": 0.121},
}


def calibration_tables() -> dict[str, dict]:
    """The small cases :func:`measure` solves: name -> case table.

    Scenes like the shipped campaigns' (where :data:`REFERENCE` was fitted, so that its
    machine measures factors near 1): ``normal``: CG iterations, 20 increments on a 48^2
    surface; ``coupled``:
    slip-stick passes of a rigid sphere with friction on steel (beta = -0.29) on 48^2;
    ``slip``: a Cattaneo tangential load on 96^2 (slip-solver applications); ``plastic24`` and
    ``plastic32``: frictionless plasticity at 6 GPa on 24^3 and 32^3 boxes (volume
    convolution and return mapping).
    """
    elastic = {"body1": _RIGID_SPHERE, "body2": _STEEL, "friction": {"coefficient": 0.0}}
    return {
        "normal": {**elastic, "load": {"hertz_pressure": 2e9, "steps": 20}, "grid": {"n": 48}},
        "coupled": {
            **elastic,
            "friction": {"coefficient": 0.3},
            "load": {"hertz_pressure": 2e9, "steps": 4},
            "grid": {"n": 48},
        },
        "slip": {
            "body1": {**_STEEL, "radius": 0.01},
            "body2": _STEEL,
            "friction": {"coefficient": 0.3},
            "load": {
                "path": [
                    {"normal_force": 100.0, "steps": 1},
                    {"normal_force": 100.0, "tangential_force": 20.0, "steps": 2},
                ]
            },
            "grid": {"n": 96, "half_width": 1.5},
        },
        "plastic32": {
            "body1": _RIGID_SPHERE,
            "body2": _SWIFT,
            "friction": {"coefficient": 0.0},
            "load": {"hertz_pressure": 6e9, "steps": 2},
            "grid": {"n": [32, 32, 32]},
        },
        "plastic24": {
            "body1": _RIGID_SPHERE,
            "body2": _SWIFT,
            "friction": {"coefficient": 0.0},
            "load": {"hertz_pressure": 6e9, "steps": 5},
            "grid": {"n": [24, 24, 24]},
        },
    }


def _timed(table: dict) -> tuple[float, Work]:
    """(CPU s, the case's work with its measured iteration counts) of one solve here."""
    import warnings

    import numpy as np

    case = solver.Case.from_dict(table)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        start = time.process_time()
        result = solver.solve(case)
        cpu = time.process_time() - start

    def total(name: str) -> float:
        return float(np.sum(result.history[name])) if name in result.history else 0.0

    predicted = count(case)
    measured = replace(
        predicted,
        normal=total("normal_iterations"),
        slip=total("slip_iterations"),
        coupling=total("coupling_iterations"),
        plastic=total("plastic_iterations"),
    )
    return cpu, measured


def _timings(repeat: int) -> list[tuple[float, Work]]:
    """(median CPU s, work with the measured iterations) of every calibration case, here."""
    solver.solve(solver.Case.from_dict(calibration_tables()["normal"]))  # imports, plans
    found = []
    for table in calibration_tables().values():
        runs = sorted((_timed(table) for _ in range(max(repeat, 1))), key=lambda run: run[0])
        found.append(runs[len(runs) // 2])
    return found


def measure(repeat: int = 2, processes: int | None = None) -> Calibration:
    """Measure this machine's unit costs with small solves (CPU time, median of ``repeat``).

    Each calibration case (:func:`calibration_tables`) is solved; its time is split by
    :data:`REFERENCE` into three families (Python overheads, surface FFT work, volume FFT
    work) with its *measured* iteration counts, and one factor per family is fitted (least
    squares on relative errors, drawn towards the median case's common factor) so that the
    reference shape times the factors gives the measured times.  The cases run in
    ``processes`` processes at once, as a campaign keeps every core busy (one rank each):
    the cores then share caches and memory bandwidth as they do in a run.

    Parameters
    ----------
    repeat : int
        Solves of each calibration case; the median CPU time counts.
    processes : int, optional
        Processes measuring at once (default: the cores, at most 4; 1 in a process that
        imported MPI); the median over them counts.  1 measures in this process.

    Returns
    -------
    Calibration
        Unit costs of this machine.
    """
    import numpy as np

    start = time.process_time()
    if processes is None:  # one per core; in an MPI process (rank 0 of a run), no children
        processes = 1 if "mpi4py.MPI" in sys.modules else min(os.cpu_count() or 1, 4)
    runs = None
    if processes > 1:
        import multiprocessing

        try:  # spawned: no fork of an MPI process, FFTW threads or locks
            with multiprocessing.get_context("spawn").Pool(processes) as pool:
                runs = pool.map(_timings, [repeat] * processes)
        except Exception as error:  # noqa: BLE001 - measure here instead
            logging.getLogger("study").info("calibration in one process (%s)", error)
    if runs is None:
        runs = [_timings(repeat)]
    rows, times = [], []
    for case in range(len(runs[0])):
        ordered = sorted((run[case] for run in runs), key=lambda one: one[0])
        cpu, work = ordered[len(ordered) // 2]
        rows.append(families(work, REFERENCE))
        times.append(cpu)
    matrix = np.array(rows) / np.array(times)[:, None]  # relative: each case counts alike
    # one speed for all (the median case), then per family, drawn towards it (ridge): the
    # families share the cases, so their factors alone are ill-conditioned
    common = float(np.median(1.0 / matrix.sum(axis=1)))
    ridge = 2.0
    factors = np.linalg.solve(
        matrix.T @ matrix + ridge * np.eye(3),
        matrix.T @ np.ones(len(times)) + ridge * common,
    )
    factors = [float(f) if np.isfinite(f) and f > 0.05 else 1.0 for f in factors]
    factors = [min(f, 20.0) for f in factors]
    return REFERENCE.scaled(
        *factors,
        machine=wisdom.machine_key(),
        seconds=repeat * sum(cpu for run in runs for cpu, _ in run) + time.process_time() - start,
        created=time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
    )


def calibration(recalibrate: bool = False, logger: logging.Logger | None = None) -> Calibration:
    """The unit costs of this machine: the saved ones, else measured now (and saved).

    Parameters
    ----------
    recalibrate : bool
        Measure again even when a calibration is saved.
    logger : logging.Logger, optional
        Where to say that it measures (default: the ``study`` logger).

    Returns
    -------
    Calibration
        Saved or newly measured; :data:`REFERENCE` when measuring fails.
    """
    logger = logger or logging.getLogger("study")
    if not recalibrate:
        saved = load()
        if saved is not None:
            return saved
    logger.info(
        "measuring this machine's solver speed for the cost estimates: once per machine, "
        "up to half a minute"
    )
    try:
        found = measure()
    except Exception as error:  # noqa: BLE001 - an estimate must not stop a run
        logger.warning("cost calibration failed (%s): reference unit costs instead", error)
        return REFERENCE
    try:
        path = save(found)
        logger.info("cost calibration saved in %s", path)
    except OSError as error:
        logger.warning("cost calibration not saved (%s): the next run measures again", error)
    return found


def describe_calibration(calibration: Calibration) -> str:
    """One line: the unit costs (against :data:`REFERENCE`) and where they come from."""
    where = (
        "built-in reference unit costs"
        if calibration.machine == "reference"
        else f"calibrated {calibration.created or '?'} in {calibration.seconds:.1f} s CPU, "
        f"{calibration_file()}"
    )
    return (
        f"{calibration.normal * 1e9:.2f} ns per CG iteration per Ns log2 Ns, "
        f"{calibration.volume * 1e9:.2f} ns per plasticity iteration per Mv log2 Mv, "
        f"{calibration.case * 1e3:.1f} ms per case; speed "
        f"{REFERENCE.normal / calibration.normal:.2f} (surface), "
        f"{REFERENCE.volume / calibration.volume:.2f} (volume), "
        f"{REFERENCE.case / calibration.case:.2f} (overheads) x the reference ({where})"
    )
