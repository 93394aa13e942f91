"""Bundles: many finished cases in one HDF5 file, written at once by the rank that computed them.

A campaign of 10^4-10^5 small cases cannot afford a netCDF file per case (milliseconds of
library overhead each, and as many files on a cluster file system).  A rank keeps its finished
cases in memory and writes them as one *bundle* every few seconds (:class:`study.run.storage
.CaseWriter`); the file is written to a temporary name, flushed to disk and renamed, as every
file of an output folder, so a bundle is either whole or absent.

Layout of ``cases/<host>-<pid>-<n>.bundle.h5`` (HDF5 through h5py), format :data:`FORMAT`:

- attributes ``slipstick_bundle`` (the format), ``shared`` (JSON: the global attributes the
  entries share, the run's provenance) and, written last, ``slipstick_complete`` = 1;
- ``case_id`` and ``status`` (entry): strings, one per entry; the status of a failure record is
  ``failed``;
- ``meta`` (bytes) with ``meta_offsets`` (entry + 1): each entry's JSON record: its own global
  attributes and, for each variable, its dims, attributes, dtype, shape and offset (a string
  variable holds its values there); or its failure record (``failure``);
- ``summary`` (bytes) with ``summary_offsets``: each result's row of the campaign dataset
  (:func:`study.run.assemble.case_summary`, computed by the rank that solved the case), JSON
  ``null`` for a failure;
- ``variables/<name>``: the flattened values of that variable of every entry, one after the
  other (gzip-compressed when large).

So a bundle holds one HDF5 object per variable name, not per case: the cost of writing and
of opening it does not grow with its number of cases, and its index (``case_id``, ``status``)
reads without touching the rest.  Values are stored as computed (a float keeps every bit;
JSON writes floats with their shortest exact representation).
"""

from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    import xarray as xr

#: Bundle format written here (a reader refuses a newer one).
FORMAT = 1
#: File name suffix of a bundle.
SUFFIX = ".bundle.h5"
#: Attribute of a complete bundle, written last (the same name as a case file's marker).
COMPLETE_ATTR = "slipstick_complete"
#: Variables with at least this many values are gzip-compressed (smaller ones cost more
#: to compress than they save).
COMPRESS_FROM = 4096
#: zlib level (4: most of the gain of 9 at a fraction of the time).
COMPRESSION_LEVEL = 4


class BundleError(RuntimeError):
    """A bundle that does not open, lacks its completion marker or is of a newer format."""


@dataclass
class CaseRecord:
    """One case in memory: coordinates, variables and global attributes, as xarray takes them.

    ``coords`` and ``data`` map a name to ``(dims, values, attrs)``.
    """

    coords: dict[str, tuple] = field(default_factory=dict)
    data: dict[str, tuple] = field(default_factory=dict)
    attrs: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:  # (dims, values) as xarray takes it: no attributes
        for parts in (self.coords, self.data):
            for name, part in parts.items():
                if len(part) == 2:
                    parts[name] = (*part, {})

    def __contains__(self, name: str) -> bool:
        return name in self.data or name in self.coords

    def values(self, name: str) -> np.ndarray:
        """The values of a variable or coordinate."""
        part = self.data.get(name) or self.coords[name]
        return np.asarray(part[1])

    def variable_attrs(self, name: str) -> dict:
        """The attributes of a variable or coordinate."""
        part = self.data.get(name) or self.coords[name]
        return dict(part[2])

    def to_xarray(self) -> xr.Dataset:
        """The case as an :class:`xarray.Dataset` (in memory)."""
        import xarray as xr

        return xr.Dataset(self.data, coords=self.coords, attrs=self.attrs)

    @classmethod
    def from_xarray(cls, dataset: xr.Dataset) -> CaseRecord:
        """The record of a dataset (a case file's contents, loaded)."""

        def parts(variables) -> dict:
            return {n: (v.dims, v.data, dict(v.attrs)) for n, v in variables.items()}

        return cls(parts(dataset.coords), parts(dataset.data_vars), dict(dataset.attrs))


@dataclass
class Entry:
    """What a bundle stores of one case: a result (``record``, ``summary``) or a failure."""

    case_id: str
    status: str
    record: CaseRecord | None = None
    summary: dict | None = None
    failure: dict | None = None


# -- JSON ----------------------------------------------------------------------------------------
def _encode(value: Any) -> Any:
    if isinstance(value, np.ndarray):
        return {"__array__": value.tolist(), "dtype": value.dtype.str}
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, Path):
        return str(value)
    raise TypeError(f"cannot store a {type(value).__name__} in a bundle")


def _decode(value: dict) -> Any:
    if "__array__" in value:
        return np.asarray(value["__array__"], dtype=value["dtype"])
    return value


def dumps(value: Any) -> str:
    """JSON with numpy arrays and scalars (arrays keep their dtype), NaN allowed."""
    return json.dumps(value, default=_encode, allow_nan=True)


def loads(text: str | bytes) -> Any:
    """Inverse of :func:`dumps`."""
    return json.loads(text, object_hook=_decode)


# -- writing -------------------------------------------------------------------------------------
def _layout(entries: list[Entry]) -> tuple[list[dict], dict[str, list[np.ndarray]]]:
    """Each entry's meta record and the pieces of each variable, in entry order."""
    metas: list[dict] = []
    pieces: dict[str, list[np.ndarray]] = {}
    sizes: dict[str, int] = {}
    for entry in entries:
        if entry.record is None:
            metas.append({"failure": entry.failure or {}})
            continue
        variables = {}
        for coord, parts in ((True, entry.record.coords), (False, entry.record.data)):
            for name, (dims, values, attrs) in parts.items():
                values = np.asarray(values)
                dims = [dims] if isinstance(dims, str) else [str(d) for d in dims]
                spec = {"coord": coord, "dims": dims, "attrs": attrs}
                if values.dtype.kind in "OSU":  # strings (a component coordinate): in the JSON
                    spec["strings"] = values.tolist()
                else:
                    offset = sizes.get(name, 0)
                    spec.update(dtype=values.dtype.str, shape=list(values.shape), offset=offset)
                    pieces.setdefault(name, []).append(values.ravel())
                    sizes[name] = offset + values.size
                variables[name] = spec
        record = entry.record
        metas.append({"attrs": record.attrs, "variables": variables})
    return metas, pieces


def write_bundle(path: str | Path, entries: list[Entry], shared: dict[str, Any]) -> Path:
    """Write ``entries`` to a new bundle atomically (temporary name, fsync, rename).

    Parameters
    ----------
    path : str or Path
        The bundle's final name (``*.bundle.h5``); must not exist.
    entries : list of Entry
        Results and failure records.
    shared : dict
        Global attributes every result of the bundle shares (the run's provenance).

    Returns
    -------
    Path
    """
    import h5py

    path = Path(path)
    metas, pieces = _layout(entries)
    temporary = path.with_name(f"{path.name}.tmp{os.getpid()}")
    try:
        with h5py.File(temporary, "w") as handle:
            handle.attrs["slipstick_bundle"] = FORMAT
            handle.attrs["shared"] = dumps(shared)
            text = h5py.string_dtype()
            handle.create_dataset("case_id", data=[e.case_id for e in entries], dtype=text)
            handle.create_dataset("status", data=[e.status for e in entries], dtype=text)
            _json_column(handle, "meta", metas)
            _json_column(handle, "summary", [entry.summary for entry in entries])
            group = handle.create_group("variables")
            for name, parts in pieces.items():
                dtype = np.result_type(*parts)
                _dataset(group, name, np.concatenate(parts).astype(dtype, copy=False))
            handle.attrs[COMPLETE_ATTR] = np.int8(1)
        with open(temporary, "rb+") as raw:
            os.fsync(raw.fileno())
        os.replace(temporary, path)
    finally:
        temporary.unlink(missing_ok=True)
    return path


def _json_column(handle, name: str, values: list) -> None:
    """One JSON text per entry: their bytes one after the other, and ``<name>_offsets``."""
    blobs = [dumps(value).encode() for value in values]
    _dataset(handle, name, np.frombuffer(b"".join(blobs), dtype=np.uint8))
    offsets = np.concatenate([[0], np.cumsum([len(blob) for blob in blobs])])
    handle.create_dataset(f"{name}_offsets", data=offsets.astype(np.int64))


def _dataset(group, name: str, values: np.ndarray) -> None:
    if values.size >= COMPRESS_FROM:
        group.create_dataset(
            name, data=values, compression="gzip", compression_opts=COMPRESSION_LEVEL, shuffle=True
        )
    else:
        group.create_dataset(name, data=values)


# -- reading -------------------------------------------------------------------------------------
def _open(path: Path):
    import h5py

    try:
        handle = h5py.File(path, "r")
    except Exception as error:  # HDF5 raises OSError (or worse) on a damaged file
        raise BundleError(f"does not open ({_first_line(error)})") from None
    try:
        version = int(handle.attrs.get("slipstick_bundle", 0))
        complete = int(handle.attrs.get(COMPLETE_ATTR, 0)) == 1
    except Exception as error:
        handle.close()
        raise BundleError(f"does not open ({_first_line(error)})") from None
    if version > FORMAT:
        handle.close()
        raise BundleError(f"is of bundle format {version}, newer than this version's {FORMAT}")
    if not complete:
        handle.close()
        raise BundleError(f"has no completion marker (attribute {COMPLETE_ATTR} = 1)")
    return handle


def _first_line(error: BaseException) -> str:
    text = str(error).splitlines()[0] if str(error) else ""
    return text or type(error).__name__


def read_index(path: str | Path) -> tuple[list[str], list[str]]:
    """The case ids and statuses of a bundle's entries (its header and two small datasets).

    Raises
    ------
    BundleError
        When the bundle does not open, lacks its marker or is of a newer format.
    """
    handle = _open(Path(path))
    try:
        ids = [s.decode() for s in handle["case_id"][()]]
        statuses = [s.decode() for s in handle["status"][()]]
    except Exception as error:
        raise BundleError(f"does not open ({_first_line(error)})") from None
    finally:
        handle.close()
    return ids, statuses


@dataclass(frozen=True)
class Location:
    """Where a case's result or failure record is: a bundle entry, or a file of its own.

    ``position`` is the entry in the bundle ``path``; None for a per-case file (``<id>.nc`` or
    ``<id>.failed.json``, written by versions before bundles).
    """

    path: Path
    position: int | None = None


@dataclass
class CaseIndex:
    """Every case a folder of bundles (and per-case files) holds.

    Attributes
    ----------
    results : dict
        Case id -> (Location, status) of a complete result (the first one found when a case
        is stored twice: results are identical).
    failures : dict
        Case id -> Location of its latest failure record, for cases without a result.
    corrupt : dict
        Bundle file name (or the case id of a per-case file) -> what is wrong with it.
    """

    results: dict[str, tuple[Location, str]] = field(default_factory=dict)
    failures: dict[str, Location] = field(default_factory=dict)
    corrupt: dict[str, str] = field(default_factory=dict)


#: str(path) -> ((inode, size, mtime_ns), ids, statuses, problem): bundle indexes, read again
#: when the file changes.
_INDEXED: dict[str, tuple[tuple[int, int, int], list[str], list[str], str]] = {}


def _indexed(path: Path) -> tuple[list[str], list[str], str, float]:
    """(ids, statuses, problem, mtime) of a bundle, cached until it changes."""
    try:
        stat = path.stat()
    except OSError as error:
        return [], [], f"cannot be read ({error.strerror or error})", 0.0
    key = (stat.st_ino, stat.st_size, stat.st_mtime_ns)
    cached = _INDEXED.get(str(path))
    if cached is None or cached[0] != key:
        try:
            cached = (key, *read_index(path), "")
        except BundleError as error:
            cached = (key, [], [], str(error))
        _INDEXED[str(path)] = cached
    return cached[1], cached[2], cached[3], stat.st_mtime


def scan(folder: str | Path) -> CaseIndex:
    """The cases the bundles of ``folder`` hold (each bundle's index read once, then cached).

    A case stored twice keeps its first result; of several failure records the newest file's
    counts; a case with a result has no failure.
    """
    index = CaseIndex()
    newest: dict[str, float] = {}
    for path in sorted(Path(folder).glob("*" + SUFFIX)):
        ids, statuses, problem, mtime = _indexed(path)
        if problem:
            index.corrupt[path.name] = problem
        for position, (case_id, status) in enumerate(zip(ids, statuses, strict=True)):
            if status != "failed":
                index.results.setdefault(case_id, (Location(path, position), status))
            elif mtime >= newest.get(case_id, -math.inf):
                newest[case_id] = mtime
                index.failures[case_id] = Location(path, position)
    for case_id in set(index.failures) & set(index.results):
        del index.failures[case_id]
    return index


def find_result(folder: str | Path, case_id: str) -> CaseRecord:
    """The stored result of case ``case_id`` among the bundles of ``folder``.

    Raises
    ------
    KeyError
        When no complete bundle of the folder holds a result of that case.
    """
    location = scan(folder).results[case_id][0]
    with Reader(location.path) as reader:
        return reader.record(location.position)


class Reader:
    """An open bundle: its shared attributes and its entries' records, read on demand.

    Use as a context manager; :meth:`meta` decodes an entry's JSON, :meth:`record` reads a
    result's variables.
    """

    def __init__(self, path: str | Path):
        self.path = Path(path)
        self.handle = _open(self.path)
        try:
            self.shared = loads(self.handle.attrs["shared"])
            self._columns: dict[str, tuple[np.ndarray, np.ndarray]] = {}
        except Exception as error:
            self.handle.close()
            raise BundleError(f"does not open ({_first_line(error)})") from None

    def __enter__(self) -> Reader:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def close(self) -> None:
        """Close the file."""
        self.handle.close()

    def _json(self, name: str, position: int):
        if name not in self._columns:  # read whole, once: entries are read together
            self._columns[name] = (self.handle[name][()], self.handle[f"{name}_offsets"][()])
        blob, offsets = self._columns[name]
        return loads(blob[offsets[position] : offsets[position + 1]].tobytes())

    def meta(self, position: int) -> dict:
        """The JSON record of entry ``position``: attributes and variables, or ``failure``."""
        return self._json("meta", position)

    def summary(self, position: int) -> dict | None:
        """The row of entry ``position`` for the campaign dataset (None: a failure)."""
        return self._json("summary", position)

    def record(self, position: int, meta: dict | None = None, lazy: bool = False) -> CaseRecord:
        """The case stored at entry ``position`` (its attributes include the shared ones).

        With ``lazy`` the data variables are dask arrays, read from the file when computed
        (coordinates are read now).
        """
        meta = meta if meta is not None else self.meta(position)
        if "variables" not in meta:
            raise BundleError(f"entry {position} is a failure record, not a result")
        record = CaseRecord(attrs={**self.shared, **meta["attrs"]})
        for name, spec in meta["variables"].items():
            if "strings" in spec:
                values = np.asarray(spec["strings"])
            elif lazy and not spec["coord"]:
                values = _lazy(self.path, name, spec)
            else:
                values = _piece(self.handle, name, spec)
            part = (tuple(spec["dims"]), values, spec["attrs"])
            (record.coords if spec["coord"] else record.data)[name] = part
        return record


def _piece(handle, name: str, spec: dict) -> np.ndarray:
    """One entry's values of a variable (``spec``: its dtype, shape and offset)."""
    size = int(np.prod(spec["shape"], dtype=np.int64))
    start = int(spec["offset"])
    stored = handle["variables"][name][start : start + size]
    return stored.astype(spec["dtype"], copy=False).reshape(spec["shape"])


def _read_piece(path: Path, name: str, spec: dict) -> np.ndarray:
    handle = _open(path)
    try:
        return _piece(handle, name, spec)
    finally:
        handle.close()


def _lazy(path: Path, name: str, spec: dict):
    import dask
    import dask.array as da

    shape, dtype = tuple(spec["shape"]), np.dtype(spec["dtype"])
    return da.from_delayed(dask.delayed(_read_piece)(path, name, spec), shape, dtype=dtype)
