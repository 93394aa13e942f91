"""Campaign output folder: bundles of finished cases, the expanded campaign, the dataset.

Layout of an output folder ``OUT``::

    OUT/campaign.json                      the expanded campaign (axes, resolved case specs)
    OUT/cases/<host>-<pid>-<t>-<n>.bundle.h5  finished cases and failure records of one rank,
                                           written together (:mod:`study.bundle`)
    OUT/<campaign name>.nc                 the assembled dataset (:mod:`study.run.assemble`)

A rank keeps its finished cases in memory and writes them as one bundle every
:data:`BUNDLE_SECONDS` (:class:`CaseWriter`): a campaign of 10^4 small cases makes tens of
files, not 10^4, and a crash loses at most that interval's finished cases per rank (the
re-run computes them again).  Folders of versions before bundles hold a file per case,
``cases/<id>.nc`` and ``cases/<id>.failed.json``: they are still read.

Every file has one writer and is written atomically: to a temporary name in the same folder
(``*.tmp<pid>``), flushed to disk, then renamed over the final name with :func:`os.replace`, so
a run killed at any moment leaves either the old file or the new one, never half a file.
Temporaries are never read; the ones whose process is gone are deleted by ``run``, ``status``
and ``assemble`` (:func:`remove_temporaries`).

A bundle (and a per-case file) gets the attribute ``slipstick_complete = 1`` last, before the
rename (:data:`COMPLETE_ATTR`).  A case counts as finished when a bundle that opens and carries
the marker holds its result (:func:`case_index`); a re-run skips it and retries failures.  A
file that does not open or lacks the marker (truncated, overwritten, copied half-way) is
*corrupt*: ``status`` and ``assemble`` name it, ``run`` moves it aside to ``<file>.corrupt``
(:func:`quarantine`) and computes its cases again.  A damaged bundle cannot say which cases it
held: they count as pending; a damaged per-case file counts its case failed.

Write errors are reported as what they are: a full disk reads "no space left on device" even
when the HDF5 library reports it as an HDF or permission error (:func:`describe_write_error`).
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
from solver.result import stored_status

from .. import bundle
from ..bundle import CaseIndex, CaseRecord, Location
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


def write_netcdf(dataset: xr.Dataset, path: str | Path) -> None:
    """Write an :class:`xarray.Dataset` to netCDF4 atomically, zlib-compressing numeric data.

    Parameters
    ----------
    dataset : xarray.Dataset
        The dataset.
    path : str or Path
        Final file name.
    """
    path = Path(path)
    encoding = {}
    for name, variable in dataset.variables.items():
        if variable.dtype.kind in "biuf" and variable.ndim > 0:
            encoding[name] = {"zlib": True, "complevel": COMPRESSION_LEVEL, "shuffle": True}
    temporary = _temporary(path)
    try:
        dataset.to_netcdf(temporary, engine=ENGINE, encoding=encoding)
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
            f"no space left on device ({free} bytes free in {folder}; the HDF5 library "
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
    record["written"] = now()
    try:
        atomic_write_text(out / CAMPAIGN_FILE, campaign_text(record))
    except OSError as error:
        raise CampaignError(
            f"{out}: cannot write {CAMPAIGN_FILE}: {describe_write_error(error, out)}"
        ) from None


def campaign_text(record: dict) -> str:
    """``campaign.json``'s text: the settings and axes indented, then one line per case.

    An indented dump goes through Python's own JSON encoder (about 0.4 ms a case: 40 s for
    10^5 cases on rank 0 while the other ranks wait); a case per line goes through the C
    encoder, and the file still reads one case per line.
    """
    rest = {key: value for key, value in record.items() if key != "cases"}
    head = json.dumps({**rest, "cases": None}, indent=1, allow_nan=True)  # ends "null\n}"
    cases = [json.dumps(case, allow_nan=True) for case in record.get("cases", [])]
    listed = "[\n  " + ",\n  ".join(cases) + "\n ]" if cases else "[]"
    return head[: -len("null\n}")] + listed + "\n}\n"


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
#: str(path) -> ((inode, size, mtime_ns), status, problem): checks of per-case files, redone
#: when the file changes.
_CHECKED: dict[str, tuple[tuple[int, int, int], str, str]] = {}


def _inspect_case_file(path: Path) -> tuple[str, str]:
    """(status, problem) of a per-case netCDF file (the layout before bundles).

    The problem is "" when the file opens and carries its completion marker.  Cached until the
    file changes.
    """
    try:
        stat = path.stat()
    except OSError as error:
        return "", f"cannot be read ({error.strerror or error})"
    key = (stat.st_ino, stat.st_size, stat.st_mtime_ns)
    cached = _CHECKED.get(str(path))
    if cached is not None and cached[0] == key:
        return cached[1], cached[2]
    import netCDF4

    status, problem = "", ""
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
        status = stored_status(str(attrs.get("status", "converged")), str(attrs.get("notes", "")))
        if not complete:
            problem = f"has no completion marker (global attribute {COMPLETE_ATTR} = 1)"
    _CHECKED[str(path)] = (key, status, problem)
    return status, problem


def case_index(out: str | Path) -> CaseIndex:
    """The cases stored in ``OUT/cases``.

    Its bundles (:func:`.bundle.scan`), and the per-case files of older versions (``<id>.nc``,
    ``<id>.failed.json``).
    """
    folder = cases_dir(out)
    index = bundle.scan(folder)
    if not folder.is_dir():
        return index
    for path in sorted(folder.glob("*.nc")):
        case_id = path.name[: -len(".nc")]
        status, problem = _inspect_case_file(path)
        if problem:
            index.corrupt[case_id] = problem
        else:
            index.results.setdefault(case_id, (Location(path), status))
    for path in folder.glob("*.failed.json"):
        index.failures.setdefault(path.name[: -len(".failed.json")], Location(path))
    for case_id in set(index.failures) & set(index.results):
        del index.failures[case_id]
    return index


def finished_ids(out: str | Path) -> set[str]:
    """Ids of cases with a complete result (in a bundle or a per-case file)."""
    return set(case_index(out).results)


def corrupt_ids(out: str | Path) -> dict[str, str]:
    """Damaged per-case files (case id) and bundles (file name) -> what is wrong with them.

    A bundle that does not open cannot say which cases it held: they count as pending.
    """
    return case_index(out).corrupt


def quarantine(out: str | Path, name: str) -> Path:
    """Move a corrupt bundle or case file aside, to ``<file>.corrupt`` (replacing an older one).

    ``name`` is a key of :func:`corrupt_ids`: a bundle's file name or a case id.
    """
    path = cases_dir(out) / name if name.endswith(bundle.SUFFIX) else case_path(out, name)
    target = path.with_name(path.name + CORRUPT_SUFFIX)
    os.replace(path, target)
    _CHECKED.pop(str(path), None)
    return target


def failed_ids(out: str | Path) -> set[str]:
    """Ids of cases with a failure record and no result."""
    return set(case_index(out).failures)


def read_failures(out: str | Path, ids: Iterable[str], index: CaseIndex | None = None) -> dict:
    """The failure records of the cases ``ids`` that have one: case id -> record.

    A record that cannot be read is ``{}``.  Each bundle is opened once.
    """
    index = index or case_index(out)
    by_file: dict[Path, list[tuple[str, int | None]]] = {}
    for case_id in ids:
        if case_id in index.failures:
            location = index.failures[case_id]
            by_file.setdefault(location.path, []).append((case_id, location.position))
    records: dict[str, dict] = {}
    for path, entries in by_file.items():
        try:
            if entries[0][1] is None:  # a per-case record of an older version
                with open(path, encoding="utf-8") as handle:
                    records[entries[0][0]] = json.load(handle)
                continue
            with bundle.Reader(path) as reader:
                for case_id, position in entries:
                    records[case_id] = reader.meta(position).get("failure", {})
        except (OSError, ValueError, bundle.BundleError):
            records.update({case_id: {} for case_id, _ in entries if case_id not in records})
    return records


def read_failure(out: str | Path, case_id: str, index: CaseIndex | None = None) -> dict:
    """The failure record of a case ({} when there is none or it is unreadable)."""
    return read_failures(out, [case_id], index).get(case_id, {})


def case_states(
    out: str | Path, campaign: Campaign, index: CaseIndex | None = None
) -> dict[str, str]:
    """State of every case: pending, converged, not_converged, truncated, failed or corrupt.

    The statuses come from the bundles' indexes (per-case files: their attributes);
    ``corrupt`` is a per-case file that does not open or lacks its completion marker
    (:func:`corrupt_ids` says why; a damaged bundle's cases are pending).
    """
    index = index or case_index(out)
    states = {}
    for case in campaign.cases:
        if case.case_id in index.results:
            states[case.case_id] = index.results[case.case_id][1]
        elif case.case_id in index.corrupt:
            states[case.case_id] = "corrupt"
        elif case.case_id in index.failures:
            states[case.case_id] = "failed"
        else:
            states[case.case_id] = "pending"
    return states


def read_record(
    out: str | Path, case_id: str, index: CaseIndex | None = None, lazy: bool = False
) -> CaseRecord:
    """A finished case's variables and attributes (from its bundle, or its own file).

    With ``lazy`` the data variables are dask arrays, read when computed.

    Raises
    ------
    KeyError
        When the case has no complete result.
    """
    location = (index or case_index(out)).results[case_id][0]
    if location.position is None:
        import xarray as xr

        if lazy:  # dask arrays over the open file
            return CaseRecord.from_xarray(xr.open_dataset(location.path, engine=ENGINE, chunks={}))
        with xr.open_dataset(location.path, engine=ENGINE) as dataset:
            return CaseRecord.from_xarray(dataset.load())
    with bundle.Reader(location.path) as reader:
        return reader.record(location.position, lazy=lazy)


def open_case(
    out: str | Path, case_id: str, index: CaseIndex | None = None, lazy: bool = False
) -> xr.Dataset:
    """A finished case as an :class:`xarray.Dataset` (what a case file held).

    In memory, or with ``lazy`` its data variables read when computed (dask).
    """
    return read_record(out, case_id, index, lazy).to_xarray()


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


def now() -> str:
    """The time now, UTC, ISO 8601 to the second."""
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


def run_provenance(campaign: Campaign, *, rank: int, size: int) -> dict[str, Any]:
    """Global attributes every case of a rank's run shares: what, where and how it ran."""
    return {
        "campaign": campaign.name,
        "campaign_source": campaign.source,
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
    }


def case_provenance(case: CampaignCase, **extra: Any) -> dict[str, Any]:
    """Global attributes of one case: its specification, place in the campaign, estimates."""
    return {
        "case_spec": json.dumps(case.spec, sort_keys=True),
        "campaign_coordinates": json.dumps(case.coords),
        "campaign_index": json.dumps(list(case.index)),
        "cost_estimate": case.cost,
        "memory_estimate": case.memory,
        **extra,
    }
