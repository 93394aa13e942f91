"""Writing cases: what is stored of a solved case, and a rank's bundle writer.

:func:`case_record` turns a :class:`solver.Result` into the variables and attributes stored
for the case (no xarray: it runs once per case, in milliseconds); :class:`CaseWriter` keeps a
rank's finished cases and writes them as bundles (:mod:`study.bundle`) into the output
folder (:mod:`study.run.storage`).
"""

from __future__ import annotations

import json
import os
import socket
import time
from collections.abc import Iterable
from pathlib import Path
from typing import Any

import numpy as np

import solver
from solver.result import STICK

from .. import bundle
from ..bundle import CaseRecord, Entry
from .storage import CASES_DIR, cases_dir, command_line, describe_write_error, now


# -- case files ----------------------------------------------------------------------------------
def warm_up() -> None:
    """Import the storage stack now, so that the first case does not pay for it."""
    import h5py  # noqa: F401


def line_at_y0(values: np.ndarray, y: np.ndarray) -> np.ndarray:
    """A field (nx, ny) interpolated linearly in y onto the line y = 0."""
    j = int(np.searchsorted(y, 0.0))
    if j == 0:
        return values[:, 0].copy()
    if j >= len(y):
        return values[:, -1].copy()
    w = (0.0 - y[j - 1]) / (y[j] - y[j - 1])
    return (1.0 - w) * values[:, j - 1] + w * values[:, j]


def case_record(result: solver.Result, fields: Iterable[str], attrs: dict[str, Any]) -> CaseRecord:
    """What is stored of a case: the solver's variables, the y = 0 lines, provenance attributes.

    Parameters
    ----------
    result : solver.Result
        The solved case.
    fields : iterable of str
        2-D surface fields to keep (others are dropped; the y = 0 lines are always kept).
    attrs : dict
        Extra global attributes (provenance).

    Returns
    -------
    CaseRecord
        :meth:`CaseRecord.to_xarray` gives the case's dataset.
    """
    coords, data, global_attrs = result.variables()
    stick = np.count_nonzero(np.asarray(result.contact_state) == STICK)
    global_attrs["final_stick_area"] = float(stick * result.grid.cell_area)
    y = np.asarray(coords["y"][1])
    for name in ("pressure", "shear_x"):
        declared = data[name][2]
        data[f"{name}_y0"] = (
            "x",
            line_at_y0(np.asarray(data[name][1]), y),
            {
                "units": declared.get("units", "Pa"),
                "long_name": f"{declared.get('long_name', name)} along y = 0",
            },
        )
    for name in set(("pressure", "shear_x", "shear_y", "contact_state")) - set(fields):
        data.pop(name)
    global_attrs.update(_netcdf_attrs(attrs))
    global_attrs["history"] = f"{now()}: {command_line()}"
    return CaseRecord(coords, data, global_attrs)


def _netcdf_attrs(attrs: dict[str, Any]) -> dict[str, Any]:
    out = {}
    for key, value in attrs.items():
        if value is None:
            continue
        if isinstance(value, bool):
            value = int(value)
        elif isinstance(value, dict | list | tuple):
            value = json.dumps(value)
        out[key] = value
    return out


#: Seconds a rank keeps finished cases in memory before writing them as one bundle: a crash
#: loses at most this much finished work per rank (and the cases running).
BUNDLE_SECONDS = 10.0
#: Longest bundle interval accepted (s).
MAX_BUNDLE_SECONDS = 3600.0
#: Bytes of results a rank keeps in memory at most (a bundle is written when they are reached).
BUNDLE_BYTES = 256 * 2**20


class CaseWriter:
    """A rank's finished cases, kept in memory and written as bundles (:mod:`study.bundle`).

    :meth:`add` writes a bundle when the oldest case kept has waited ``seconds`` or the kept
    arrays reach ``max_bytes``; :meth:`flush` writes what is kept (call it at the end).  A
    bundle that cannot be written (a full disk) turns its results into failures
    (``CaseWriteError: result not written ...``); their failure records are written when that
    still works.  Both methods return the cases so lost.

    Parameters
    ----------
    out : str or Path
        Output folder.
    shared : dict
        Global attributes the cases of this run share (:func:`run_provenance`), stored once per
        bundle.
    seconds : float
        Longest time a finished case is kept in memory (s); 0 writes every case at once.
    max_bytes : int
        Largest size of the kept arrays (bytes).
    """

    def __init__(
        self,
        out: str | Path,
        shared: dict[str, Any],
        *,
        seconds: float = BUNDLE_SECONDS,
        max_bytes: int = BUNDLE_BYTES,
    ):
        self.out = Path(out)
        self.shared = _netcdf_attrs(shared)
        self.seconds = seconds
        self.max_bytes = max_bytes
        self.entries: list[Entry] = []
        self.kept_bytes = 0
        self.since: float | None = None
        self.stem = f"{socket.gethostname()}-{os.getpid()}-{time.time_ns() // 1000:x}"
        self.written = 0

    def add(self, entry: Entry) -> list[dict]:
        """Keep a finished case (result or failure); write a bundle when one is due."""
        if entry.record is not None:
            entry.record.attrs = {
                k: v for k, v in entry.record.attrs.items() if self.shared.get(k, ...) != v
            }
            parts = (*entry.record.coords.values(), *entry.record.data.values())
            self.kept_bytes += sum(np.asarray(values).nbytes for _, values, _ in parts)
        self.entries.append(entry)
        if self.since is None:
            self.since = time.monotonic()
        if time.monotonic() - self.since >= self.seconds or self.kept_bytes >= self.max_bytes:
            return self.flush()
        return []

    def flush(self) -> list[dict]:
        """Write the kept cases as one bundle; returns the cases lost (see the class)."""
        entries, self.entries, self.kept_bytes, self.since = self.entries, [], 0, None
        if not entries:
            return []
        try:
            self._write(entries)
            return []
        except Exception as error:  # noqa: BLE001 - reported as lost cases, never raised
            reason = describe_write_error(error, cases_dir(self.out))
        records = [
            Entry(
                entry.case_id,
                "failed",
                failure={
                    "case_id": entry.case_id,
                    "error": f"CaseWriteError: result not written to {CASES_DIR}/: {reason}",
                    **_where(),
                },
            )
            for entry in entries
            if entry.status != "failed"
        ]
        written = False
        if records:
            try:
                self._write(records)
                written = True
            except Exception:  # noqa: BLE001 - the disk is full: said in the log
                pass
        lost = [  # failure records kept here are lost with the bundle
            {"case_id": e.case_id, "error": e.failure["error"], "failure_record": False}
            for e in entries
            if e.status == "failed"
        ]
        lost += [
            {"case_id": e.case_id, "error": e.failure["error"], "failure_record": written}
            for e in records
        ]
        return lost

    def _write(self, entries: list[Entry]) -> Path:
        self.written += 1
        path = cases_dir(self.out) / f"{self.stem}-{self.written:05d}{bundle.SUFFIX}"
        return bundle.write_bundle(path, entries, self.shared)


def _where() -> dict[str, Any]:
    return {"host": socket.gethostname(), "pid": os.getpid(), "when": now()}
