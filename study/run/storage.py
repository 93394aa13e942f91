"""Campaign output folder: per-case netCDF files, failure records, the expanded campaign.

Layout of an output folder ``OUT``::

    OUT/campaign.json                 the expanded campaign (axes, resolved case specs)
    OUT/cases/<case_id>.nc            one finished case (a status of solver.result.SOLVE_STATUSES)
    OUT/cases/<case_id>.failed.json   one failed case (error, traceback, rank, host)
    OUT/<campaign name>.nc            the assembled dataset (:mod:`study.run.assemble`)

Every file has one writer and is written atomically: to a temporary name in the same folder
(``*.tmp<pid>``), flushed to disk, then renamed over the final name with :func:`os.replace`, so
a run killed at any moment leaves either the old file or the new one, never half a file.
Temporaries are never read; the ones whose process is gone are deleted by ``run``, ``status``
and ``assemble`` (:func:`remove_temporaries`).

A case file gets the global attribute ``slipstick_complete = 1`` last, after the dataset is
written and before the rename (:data:`COMPLETE_ATTR`).  A case counts as finished when its
``.nc`` file opens and carries that marker (:func:`check_case_file`); a re-run skips it and
retries failures.  A file that does not open or lacks the marker (truncated, overwritten, copied
half-way, or written by a version before the marker) is *corrupt*: ``status`` and ``assemble``
name it and count the case failed, ``run`` moves it aside to ``cases/<id>.nc.corrupt`` and
recomputes the case (:func:`quarantine_case`).

Write errors are reported as what they are: a full disk reads "no space left on device" even
when the netCDF library reports it as an HDF or permission error (:func:`describe_write_error`).
"""

from __future__ import annotations

import errno
import json
import os
import resource
import socket
import sys
import time
from collections.abc import Iterable
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

import solver
from solver.result import STICK, stored_status

from ..campaign import Campaign, CampaignCase, CampaignError

if TYPE_CHECKING:  # xarray loads lazily: validate and status do not need it
    import xarray as xr

CAMPAIGN_FILE = "campaign.json"
CASES_DIR = "cases"
#: zlib level of the netCDF4 files (4: most of the gain of 9 at a fraction of the time).
COMPRESSION_LEVEL = 4
#: The netCDF engine (``netCDF4`` is a declared dependency).
ENGINE = "netcdf4"
#: Global attribute of a case file, set to 1 after everything else is written.
COMPLETE_ATTR = "slipstick_complete"
#: Suffix of a case file moved aside as corrupt (``cases/<id>.nc.corrupt``).
CORRUPT_SUFFIX = ".corrupt"
#: Free bytes below which a failed write is put down to a full disk.
LOW_SPACE = 1 << 20


# -- paths ---------------------------------------------------------------------------------------
def cases_dir(out: str | Path) -> Path:
    """Folder of the per-case files."""
    return Path(out) / CASES_DIR


def case_path(out: str | Path, case_id: str) -> Path:
    """File of a finished case."""
    return cases_dir(out) / f"{case_id}.nc"


def failure_path(out: str | Path, case_id: str) -> Path:
    """Failure record of a case."""
    return cases_dir(out) / f"{case_id}.failed.json"


def dataset_path(out: str | Path, name: str) -> Path:
    """The assembled campaign dataset."""
    return Path(out) / f"{name}.nc"


# -- atomic writes -------------------------------------------------------------------------------
def _temporary(path: Path) -> Path:
    return path.with_name(f"{path.name}.tmp{os.getpid()}")


def _sync(path: Path) -> None:
    with open(path, "rb+") as handle:
        os.fsync(handle.fileno())


def atomic_write_text(path: str | Path, text: str) -> None:
    """Write ``text`` to ``path`` atomically (temporary file, fsync, :func:`os.replace`)."""
    path = Path(path)
    temporary = _temporary(path)
    try:
        with open(temporary, "w", encoding="utf-8") as handle:
            handle.write(text)
            handle.flush()
            os.fsync(handle.fileno())
        os.replace(temporary, path)
    finally:
        temporary.unlink(missing_ok=True)


def write_netcdf(dataset: xr.Dataset, path: str | Path, *, mark_complete: bool = False) -> None:
    """Write an :class:`xarray.Dataset` to netCDF4 atomically, zlib-compressing numeric data.

    Parameters
    ----------
    dataset : xarray.Dataset
        The dataset.
    path : str or Path
        Final file name.
    mark_complete : bool
        Add the global attribute :data:`COMPLETE_ATTR` = 1 after the dataset is written (case
        files), so that a reader can tell a complete file from a damaged one.
    """
    path = Path(path)
    encoding = {}
    for name, variable in dataset.variables.items():
        if variable.dtype.kind in "biuf" and variable.ndim > 0:
            encoding[name] = {"zlib": True, "complevel": COMPRESSION_LEVEL, "shuffle": True}
    temporary = _temporary(path)
    try:
        dataset.to_netcdf(temporary, engine=ENGINE, encoding=encoding)
        if mark_complete:
            import netCDF4

            with netCDF4.Dataset(temporary, "a") as handle:
                handle.setncattr(COMPLETE_ATTR, np.int8(1))
        _sync(temporary)
        os.replace(temporary, path)
    finally:
        temporary.unlink(missing_ok=True)


def _temporary_pid(path: Path) -> int | None:
    """The pid in a ``*.tmp<pid>`` name (None when there is none)."""
    digits = path.name.rpartition(".tmp")[2]
    return int(digits) if digits.isdigit() else None


def _alive(pid: int) -> bool:
    """Whether a process with this pid exists on this host."""
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (PermissionError, OverflowError, OSError):
        return True  # exists (another user's), or cannot tell: keep the file
    return True


def remove_temporaries(out: str | Path) -> int:
    """Delete the temporary files (``*.tmp<pid>``) of processes that are gone; returns how many.

    A temporary of a live process (another ``assemble``, say) is left alone, and so are names
    without a pid.  Files that cannot be deleted (a read-only folder) are skipped: temporaries
    are never read, only cleaned up.
    """
    count = 0
    for folder in (Path(out), cases_dir(out)):
        if not folder.is_dir():
            continue
        for path in folder.glob("*.tmp*"):
            pid = _temporary_pid(path)
            if pid is None or _alive(pid):
                continue
            try:
                path.unlink(missing_ok=True)
            except OSError:
                continue
            count += 1
    return count


def free_bytes(folder: str | Path) -> int | None:
    """Bytes available to this user in the file system of ``folder`` (None when unknown)."""
    try:
        stats = os.statvfs(folder)
    except (OSError, AttributeError):
        return None
    return int(stats.f_bavail) * int(stats.f_frsize)


def describe_write_error(error: BaseException, folder: str | Path) -> str:
    """One line saying why a write into ``folder`` failed.

    ENOSPC and EDQUOT read "no space left on device" and "disk quota exceeded"; so does any
    other error (netCDF's "HDF error", "Permission denied") when the file system of ``folder``
    has less than :data:`LOW_SPACE` bytes free, since a full disk is then the likely cause.
    """
    text = f"{type(error).__name__}: {error}".splitlines()[0]
    code = getattr(error, "errno", None)
    if code == errno.ENOSPC:
        return f"no space left on device (in {folder})"
    if code == errno.EDQUOT:
        return f"disk quota exceeded (in {folder})"
    free = free_bytes(folder)
    if free is not None and free < LOW_SPACE:
        return (
            f"no space left on device ({free} bytes free in {folder}; the netCDF library "
            f"reported it as {text!r})"
        )
    return text


# -- campaign.json -------------------------------------------------------------------------------
def prepare_output(out: str | Path, campaign: Campaign, *, replace: bool = False) -> None:
    """Create the output folders, clear stale temporaries and (re)write ``campaign.json``.

    Parameters
    ----------
    out : str or Path
        Output folder.
    campaign : Campaign
        The campaign to record.
    replace : bool
        Replace the ``campaign.json`` of a *different* campaign (another name).  Without it
        that is refused: the folder belongs to the other campaign.  Its case files stay (case
        ids are content hashes: cases the new campaign shares are reused, others are ignored).

    Raises
    ------
    CampaignError
        When the folder cannot be created or written, or holds another campaign.
    """
    out = Path(out)
    try:
        cases_dir(out).mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise CampaignError(f"{out}: cannot create the output folder: {error}") from None
    if not os.access(cases_dir(out), os.W_OK):
        raise CampaignError(f"{out}: the output folder is not writable")
    remove_temporaries(out)
    if not replace:
        _check_same_campaign(out, campaign)
    record = campaign.to_dict()
    record["written"] = _now()
    try:
        atomic_write_text(out / CAMPAIGN_FILE, json.dumps(record, indent=1, allow_nan=True))
    except OSError as error:
        raise CampaignError(
            f"{out}: cannot write {CAMPAIGN_FILE}: {describe_write_error(error, out)}"
        ) from None


def _check_same_campaign(out: Path, campaign: Campaign) -> None:
    """Refuse to overwrite the ``campaign.json`` of another campaign (compared by name)."""
    path = out / CAMPAIGN_FILE
    if not path.exists():
        return
    try:
        with open(path, encoding="utf-8") as handle:
            record = json.load(handle)
        name, source = str(record["name"]), str(record.get("source") or "a table")
    except (OSError, ValueError, KeyError, TypeError) as error:
        raise CampaignError(
            f"{path}: unreadable campaign record ({error}); refusing to replace it with campaign "
            f"{campaign.name!r}: use another --out, or run with --replace"
        ) from None
    if name != campaign.name:
        raise CampaignError(
            f"{out} holds campaign {name!r} (from {source}); refusing to run campaign "
            f"{campaign.name!r} (from {campaign.source or 'a table'}) into it: use another "
            f"--out, or --replace to make {campaign.name!r} the campaign of this folder"
        )


def read_campaign(out: str | Path) -> Campaign:
    """The campaign recorded in ``OUT/campaign.json``.

    Raises
    ------
    CampaignError
        If the folder holds no readable ``campaign.json``.
    """
    path = Path(out) / CAMPAIGN_FILE
    try:
        with open(path, encoding="utf-8") as handle:
            return Campaign.from_dict(json.load(handle))
    except FileNotFoundError:
        raise CampaignError(
            f"{out}: no {CAMPAIGN_FILE}; not a campaign output folder (run the campaign first)"
        ) from None
    except (OSError, ValueError, KeyError, TypeError) as error:
        raise CampaignError(f"{path}: unreadable campaign record: {error}") from None


# -- case states ---------------------------------------------------------------------------------
#: str(path) -> ((inode, size, mtime_ns), problem, status): checks of case files, redone when
#: the file changes.
_CHECKED: dict[str, tuple[tuple[int, int, int], str, str]] = {}


def _inspect(path: Path) -> tuple[str, str]:
    """(problem, status) of a case file; problem is "" for a complete file."""
    try:
        stat = path.stat()
    except OSError as error:
        return f"cannot be read ({error.strerror or error})", ""
    key = (stat.st_ino, stat.st_size, stat.st_mtime_ns)
    cached = _CHECKED.get(str(path))
    if cached is not None and cached[0] == key:
        return cached[1], cached[2]
    import netCDF4

    problem, status = "", ""
    try:
        with netCDF4.Dataset(path, "r") as handle:
            attrs = {name: handle.getncattr(name) for name in handle.ncattrs()}
    except Exception as error:  # netCDF/HDF5 raise OSError or RuntimeError on a damaged file
        text = str(error).splitlines()[0] if str(error) else type(error).__name__
        problem = f"does not open ({text})"
    else:
        try:
            complete = int(np.asarray(attrs.get(COMPLETE_ATTR)).item()) == 1
        except (TypeError, ValueError):
            complete = False
        if not complete:
            problem = f"has no completion marker (global attribute {COMPLETE_ATTR} = 1)"
        status = stored_status(str(attrs.get("status", "converged")), str(attrs.get("notes", "")))
    _CHECKED[str(path)] = (key, problem, status)
    return problem, status


def check_case_file(path: str | Path) -> str:
    """What is wrong with a case file: "" when it opens and carries its completion marker.

    The check opens the file's header only (milliseconds) and is cached until the file changes.
    """
    return _inspect(Path(path))[0]


def _case_files(out: str | Path) -> dict[str, str]:
    """Map case id -> problem ("" for a complete file) for every ``cases/*.nc``."""
    folder = cases_dir(out)
    if not folder.is_dir():
        return {}
    return {p.name[: -len(".nc")]: check_case_file(p) for p in sorted(folder.glob("*.nc"))}


def finished_ids(out: str | Path) -> set[str]:
    """Ids of cases with a complete result file (:func:`check_case_file`)."""
    return {case_id for case_id, problem in _case_files(out).items() if not problem}


def corrupt_ids(out: str | Path) -> dict[str, str]:
    """Case files that do not open or lack the completion marker: case id -> problem."""
    return {case_id: problem for case_id, problem in _case_files(out).items() if problem}


def quarantine_case(out: str | Path, case_id: str) -> Path:
    """Move a corrupt case file aside to ``cases/<id>.nc.corrupt`` (replacing an older one)."""
    path = case_path(out, case_id)
    target = path.with_name(path.name + CORRUPT_SUFFIX)
    os.replace(path, target)
    _CHECKED.pop(str(path), None)
    return target


def failed_ids(out: str | Path) -> set[str]:
    """Ids of cases with a failure record and no result file."""
    folder = cases_dir(out)
    if not folder.is_dir():
        return set()
    failed = {p.name[: -len(".failed.json")] for p in folder.glob("*.failed.json")}
    return failed - finished_ids(out)


def read_failure(out: str | Path, case_id: str) -> dict:
    """The failure record of a case ({} when unreadable)."""
    try:
        with open(failure_path(out, case_id), encoding="utf-8") as handle:
            return json.load(handle)
    except (OSError, ValueError):
        return {}


def case_states(out: str | Path, campaign: Campaign) -> dict[str, str]:
    """State of every case: pending, converged, not_converged, truncated, failed or corrupt.

    Finished cases are opened to read their ``status`` attribute; ``corrupt`` is a case file
    that does not open or lacks its completion marker (:func:`corrupt_ids` says why).
    """
    files = _case_files(out)
    failed = failed_ids(out)
    states = {}
    for case in campaign.cases:
        if case.case_id in files:
            problem, status = _inspect(case_path(out, case.case_id))
            states[case.case_id] = "corrupt" if problem else status
        elif case.case_id in failed:
            states[case.case_id] = "failed"
        else:
            states[case.case_id] = "pending"
    return states


def read_case_attrs(out: str | Path, case_id: str) -> dict:
    """Global attributes of a case file."""
    import xarray as xr

    with xr.open_dataset(case_path(out, case_id), engine=ENGINE) as dataset:
        return dict(dataset.attrs)


# -- provenance ----------------------------------------------------------------------------------
def git_hash(start: str | Path | None = None) -> str:
    """Commit of the source tree (read from ``.git`` without running git), or "".

    Parameters
    ----------
    start : str or Path, optional
        Where to look up from; default the folder of the installed ``solver`` package.
    """
    folder = Path(start or Path(solver.__file__).resolve().parent)
    for candidate in (folder, *folder.parents):
        git = candidate / ".git"
        if git.is_file():  # a worktree: "gitdir: <path>"
            text = git.read_text().strip()
            if text.startswith("gitdir:"):
                git = (candidate / text.split(":", 1)[1].strip()).resolve()
        if git.is_dir():
            return _resolve_head(git)
    return ""


def _resolve_head(git: Path) -> str:
    try:
        head = (git / "HEAD").read_text().strip()
        if not head.startswith("ref:"):
            return head
        ref = head.split(":", 1)[1].strip()
        for root in (git, _common_dir(git)):
            path = root / ref
            if path.is_file():
                return path.read_text().strip()
            packed = root / "packed-refs"
            if packed.is_file():
                for line in packed.read_text().splitlines():
                    parts = line.split()
                    if len(parts) == 2 and parts[1] == ref:
                        return parts[0]
    except OSError:
        pass
    return ""


def _common_dir(git: Path) -> Path:
    common = git / "commondir"
    if common.is_file():
        return (git / common.read_text().strip()).resolve()
    return git


def _now() -> str:
    return time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())


def command_line() -> str:
    """The command that runs this process (``python -m study ...`` for the study CLI)."""
    argv = list(sys.argv)
    if argv and argv[0].endswith(os.path.join("study", "__main__.py")):
        argv[0] = "python -m study"
    return " ".join(argv)


def reset_peak_rss() -> bool:
    """Restart the peak-resident-set count of this process (Linux: ``/proc/self/clear_refs``).

    Returns True when the count was reset, so that :func:`peak_rss_bytes` measures from here
    (one case): checked, since some kernels accept the write and keep the old peak (the peak
    must then be within :data:`RESET_SLACK` of the resident set).  Elsewhere, without
    permission or without effect it stays the process's peak so far.
    """
    try:
        with open("/proc/self/clear_refs", "w") as handle:
            handle.write("5")
    except OSError:
        return False
    peak, resident = status_bytes("VmHWM"), status_bytes("VmRSS")
    return peak is not None and resident is not None and peak <= resident + RESET_SLACK


#: How far above the resident set the peak may be right after a reset that worked (bytes).
RESET_SLACK = 16 * 2**20


def status_bytes(field: str) -> int | None:
    """A ``kB`` field of ``/proc/self/status`` in bytes, or None."""
    try:
        with open("/proc/self/status") as handle:
            for line in handle:
                if line.startswith(field + ":"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    return None


def peak_rss_bytes() -> int:
    """Peak resident set size of this process (bytes) since :func:`reset_peak_rss`, or so far.

    Linux: ``VmHWM`` of ``/proc/self/status`` (which the reset restarts); elsewhere the
    ``ru_maxrss`` of :func:`resource.getrusage`, the process's peak since it started.
    """
    peak = status_bytes("VmHWM")
    if peak is not None:
        return peak
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return int(peak if sys.platform == "darwin" else peak * 1024)


def provenance(
    campaign: Campaign, case: CampaignCase, *, rank: int, size: int, **extra: Any
) -> dict[str, Any]:
    """Global attributes recording where, how and from what a case was computed."""
    attrs = {
        "campaign": campaign.name,
        "campaign_source": campaign.source,
        "case_spec": json.dumps(case.spec, sort_keys=True),
        "campaign_coordinates": json.dumps(case.coords),
        "campaign_index": json.dumps(list(case.index)),
        "source": f"slipstick {solver.__version__}",
        "slipstick_version": solver.__version__,
        "git_hash": git_hash(),
        "host": socket.gethostname(),
        "rank": rank,
        "mpi_size": size,
        "pid": os.getpid(),
        "python_version": sys.version.split()[0],
        "numpy_version": np.__version__,
        "command": command_line(),
        "cost_estimate": case.cost,
        "memory_estimate": case.memory,
    }
    attrs.update(extra)
    return attrs


# -- case files ----------------------------------------------------------------------------------
def warm_up() -> None:
    """Import the netCDF stack now, so that the first case does not pay for it."""
    import netCDF4  # noqa: F401
    import xarray  # noqa: F401


def line_at_y0(values: np.ndarray, y: np.ndarray) -> np.ndarray:
    """A field (nx, ny) interpolated linearly in y onto the line y = 0."""
    j = int(np.searchsorted(y, 0.0))
    if j == 0:
        return values[:, 0].copy()
    if j >= len(y):
        return values[:, -1].copy()
    w = (0.0 - y[j - 1]) / (y[j] - y[j - 1])
    return (1.0 - w) * values[:, j - 1] + w * values[:, j]


def case_dataset(result: solver.Result, fields: Iterable[str], attrs: dict[str, Any]) -> xr.Dataset:
    """The per-case dataset: the solver's dataset, the y = 0 lines, provenance attributes.

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
    xarray.Dataset
    """
    dataset = result.to_xarray()
    state = np.asarray(result.contact_state)
    stick = np.count_nonzero(state == STICK) * result.grid.cell_area
    dataset.attrs["final_stick_area"] = float(stick)
    y = dataset["y"].values
    for name in ("pressure", "shear_x"):
        dataset[f"{name}_y0"] = (
            "x",
            line_at_y0(dataset[name].values, y),
            {
                "units": dataset[name].attrs.get("units", "Pa"),
                "long_name": f"{dataset[name].attrs.get('long_name', name)} along y = 0",
            },
        )
    drop = [name for name in ("pressure", "shear_x", "shear_y", "contact_state")]
    dataset = dataset.drop_vars([name for name in drop if name not in set(fields)])
    dataset.attrs.update(_netcdf_attrs(attrs))
    dataset.attrs["history"] = f"{_now()}: {command_line()}"
    return dataset


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


def write_case(out: str | Path, case_id: str, dataset: xr.Dataset) -> Path:
    """Write a finished case atomically, marked complete, and drop any stale failure record."""
    path = case_path(out, case_id)
    write_netcdf(dataset, path, mark_complete=True)
    failure_path(out, case_id).unlink(missing_ok=True)
    return path


def write_failure(out: str | Path, case_id: str, record: dict[str, Any]) -> Path:
    """Write a failure record atomically (JSON)."""
    path = failure_path(out, case_id)
    atomic_write_text(path, json.dumps(record, indent=1, default=str))
    return path
