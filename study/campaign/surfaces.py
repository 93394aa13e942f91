"""Height-map files read into :class:`solver.bodies.heights.HeightMap` (the solver reads no files).

Two formats (docs: how-to "Contact shapes"):

* netCDF/HDF5 (``.nc``, ``.nc4``, ``.cdf``, ``.h5``, ``.hdf5``) that xarray opens, with a 2-D
  variable ``height(y, x)`` in metres over 1-D coordinates ``x``, ``y`` in metres (any uniform
  spacing, any extent); ``units`` attributes, when present, must say metres;
* ``.npy`` with ``spacing = dx`` or ``[dx, dy]`` (m) given in the surface table: rows are y,
  columns x, centred on the origin.

Every problem is a :class:`~solver.bodies.heights.SurfaceError` naming the file, the problem and
what to change; :meth:`solver.Case.from_dict` turns it into a :class:`~solver.SpecError` naming the
field (``bodyN.surface``), and the command line exits with status 2.  Maps are cached per file
(path, size, modification time), so a campaign's cases read a map once per process.
"""

from __future__ import annotations

import functools
import math
import numbers
from os import PathLike
from pathlib import Path

import numpy as np

from solver.bodies.heights import HeightMap, SurfaceError

#: File suffixes read as netCDF/HDF5.
NETCDF_SUFFIXES = (".nc", ".nc4", ".cdf", ".h5", ".hdf5")
#: ``units`` attributes accepted as metres.
METRES = ("m", "meter", "metre", "meters", "metres")


def read_surface(table: dict) -> HeightMap:
    """The height map a surface table names.

    ``{"file": ..., "spacing": ...}`` a map file, or ``{"case": ...}`` the residual print
    ``residual_displacement_z`` of a converged elastic-plastic case file; either shifted by
    ``"offset": [dx, dy]`` (m).  A relative path is taken from the working folder (a campaign
    makes it absolute first, from the campaign file's folder: :func:`absolute_surfaces`).

    Raises
    ------
    SurfaceError
        Naming the file and the problem (a table without one file name, a spacing or offset
        that is not numbers, included: :meth:`solver.Case.from_dict` checks them first).
    """
    if not isinstance(table, dict) or ("file" in table) == ("case" in table):
        raise SurfaceError(
            f"surface table {_brief(table)}: give one of file (a height map) and case (an "
            "earlier case's dent)"
        )
    kind = "case" if "case" in table else "file"
    if not isinstance(table[kind], str | PathLike) or not str(table[kind]):
        raise SurfaceError(f"surface {kind}: must be a file name, got {_brief(table[kind])}")
    path = Path(table[kind]).expanduser()
    spacing = _numbers(table.get("spacing", ()), f"{path}: spacing", "dx or [dx, dy] (m) > 0")
    offset = _numbers(table.get("offset", (0.0, 0.0)), f"{path}: offset", "[dx, dy] (m)")
    if len(spacing) > 2 or (spacing and min(spacing) <= 0):
        raise SurfaceError(f"{path}: spacing must be dx or [dx, dy] (m) > 0, got {spacing}")
    if len(offset) != 2:
        raise SurfaceError(f"{path}: offset must be [dx, dy] (m), got {offset}")
    try:
        stat = path.stat()
    except FileNotFoundError:
        if kind != "case" or not path.parent.is_dir() or path.parent.name != "cases":
            raise SurfaceError(
                f"{path}: no such file; check the path (relative paths are taken "
                "from the campaign file's folder)"
            ) from None
        stat = None  # OUT/cases/<id>: a case stored in the folder's bundles
    except OSError as error:
        raise SurfaceError(f"{path}: cannot read: {error.strerror or error}") from None
    if path.is_dir():
        raise SurfaceError(f"{path}: is a folder, expected a height-map file")
    if stat is None:
        folder = path.parent.resolve()
        case_id = path.name.removesuffix(".nc")
        surface = _read_stored_case(str(folder), case_id, folder.stat().st_mtime_ns)
    else:
        read = _read_case if kind == "case" else _read
        surface = read(str(path.resolve()), stat.st_size, stat.st_mtime_ns, spacing)
    if offset == (0.0, 0.0):
        return surface
    try:
        return HeightMap(
            surface.x + offset[0], surface.y + offset[1], surface.height, surface.source
        )
    except SurfaceError:  # the shift rounds the coordinates off their lattice
        raise SurfaceError(
            f"{path}: offset = {list(offset)} m is too large for the map's spacing "
            f"({surface.dx:.4g} m by {surface.dy:.4g} m): the shifted coordinates are no longer "
            "uniform; give a smaller offset"
        ) from None


def _brief(value) -> str:
    """``repr(value)`` for a one-line message, cut to 80 characters."""
    text = " ".join(repr(value).split())
    return text if len(text) <= 80 else text[:77] + "..."


def _numbers(value, name: str, form: str) -> tuple[float, ...]:
    """Finite real numbers given as one number, a list, a tuple or a 1-D array, as a tuple.

    Anything else (text, a table, a 2-D array, NaN, an infinity) is a :class:`SurfaceError`
    naming ``name`` (the file and the key) and saying ``form``.
    """
    array = value if isinstance(value, np.ndarray) else np.asarray(value, dtype=object)
    items = array.ravel().tolist() if array.ndim <= 1 else [None]
    try:
        if not all(isinstance(v, numbers.Real) and not isinstance(v, bool) for v in items):
            raise TypeError
        out = tuple(float(v) for v in items)
    except (TypeError, OverflowError):
        out = (math.nan,)
    if not all(math.isfinite(v) for v in out):
        raise SurfaceError(f"{name} must be {form}, got {_brief(value)}")
    return out


@functools.lru_cache(maxsize=8)
def _read_case(path: str, size: int, mtime: int, spacing: tuple[float, ...]) -> HeightMap:
    """The residual print of a finished elastic-plastic case's own file, as a height map."""
    import xarray as xr

    try:
        dataset = xr.open_dataset(path)
    except Exception as error:
        first = str(error).strip().splitlines()[0] if str(error).strip() else type(error).__name__
        raise SurfaceError(f"{path}: cannot be opened as a case file ({first})") from None
    with dataset:
        return _dent(dataset, path)


@functools.lru_cache(maxsize=8)
def _read_stored_case(folder: str, case_id: str, mtime: int) -> HeightMap:
    """The residual print of case ``case_id`` stored in the bundles of ``folder`` (OUT/cases)."""
    from .. import bundle

    source = f"{folder}/{case_id}"
    try:
        record = bundle.find_result(folder, case_id)
    except KeyError:
        raise SurfaceError(
            f"{source}: no finished case {case_id} in {folder} (no such case file either); name "
            "a case of `python -m study status`, as OUT/cases/<case id>"
        ) from None
    return _dent(record.to_xarray(), source)


def _dent(dataset, source: str) -> HeightMap:
    """The residual print ``residual_displacement_z`` of a case's dataset, checked."""
    name = "residual_displacement_z"
    if name not in dataset.variables:
        raise SurfaceError(
            f"{source}: no {name}: not an elastic-plastic case (only those leave a dent)"
        )
    status = dataset.attrs.get("status", "")
    if status != "converged":
        raise SurfaceError(
            f"{source}: its status is {status or 'unknown'!r}, not converged: its residual "
            "print is not to be trusted; use a converged case"
        )
    field = dataset[name].transpose("y", "x")
    return HeightMap(dataset["x"].values, dataset["y"].values, field.values, source)


@functools.lru_cache(maxsize=8)
def _read(path: str, size: int, mtime: int, spacing: tuple[float, ...]) -> HeightMap:
    suffix = Path(path).suffix.lower()
    if suffix == ".npy":
        return _read_npy(path, spacing)
    if suffix in NETCDF_SUFFIXES:
        if spacing:
            raise SurfaceError(
                f"{path}: spacing is for .npy maps only; a netCDF/HDF5 map's coordinates x, y "
                "give it (remove spacing)"
            )
        return _read_netcdf(path)
    raise SurfaceError(
        f"{path}: unknown height-map format {suffix or '(no suffix)'}; give a netCDF/HDF5 file "
        f"({', '.join(NETCDF_SUFFIXES)}) with height(y, x), or a .npy array with spacing"
    )


def _read_npy(path: str, spacing: tuple[float, ...]) -> HeightMap:
    if not spacing:
        raise SurfaceError(
            f"{path}: a .npy map has no coordinates; give its spacing (m): "
            'surface = {file = "...", spacing = dx} or [dx, dy]'
        )
    try:
        heights = np.load(path, allow_pickle=False)
    except (ValueError, OSError, EOFError) as error:
        raise SurfaceError(f"{path}: not a readable .npy array ({error})") from None
    if heights.ndim != 2:
        raise SurfaceError(
            f"{path}: height must be a 2-D array (rows y, columns x), got shape {heights.shape}"
        )
    if not np.issubdtype(heights.dtype, np.number) or np.iscomplexobj(heights):
        raise SurfaceError(f"{path}: heights must be real numbers, got dtype {heights.dtype}")
    dx, dy = (spacing[0], spacing[0]) if len(spacing) == 1 else spacing
    ny, nx = heights.shape
    x = (np.arange(nx) - 0.5 * (nx - 1)) * dx
    y = (np.arange(ny) - 0.5 * (ny - 1)) * dy
    return HeightMap(x, y, heights, path)


def _read_netcdf(path: str) -> HeightMap:
    import xarray as xr

    try:
        dataset = xr.open_dataset(path)
    except Exception as error:  # the engines raise many kinds for a file that is not theirs
        first = str(error).strip().splitlines()[0] if str(error).strip() else type(error).__name__
        raise SurfaceError(f"{path}: cannot be opened as netCDF/HDF5 ({first})") from None
    with dataset:
        if "height" not in dataset.variables:
            found = ", ".join(map(str, dataset.data_vars)) or "none"
            raise SurfaceError(
                f"{path}: no variable 'height' (variables: {found}); name the heights height(y, x)"
            )
        height = dataset["height"]
        if height.ndim != 2 or set(height.dims) != {"x", "y"}:
            raise SurfaceError(
                f"{path}: height must be 2-D over dims (y, x), got dims {height.dims}"
            )
        for name, variable in (("height", height), ("x", None), ("y", None)):
            if variable is None:
                if name not in dataset.coords and name not in dataset.variables:
                    raise SurfaceError(f"{path}: no coordinate {name} (m) for height(y, x)")
                variable = dataset[name]
            units = str(variable.attrs.get("units", "m")).strip()
            if units not in METRES:
                raise SurfaceError(
                    f'{path}: {name} is in {units!r}; convert it to metres (units = "m")'
                )
        return HeightMap(
            dataset["x"].values, dataset["y"].values, height.transpose("y", "x").values, path
        )


def absolute_surfaces(table: dict, folder: Path) -> dict:
    """The case table with the bodies' relative height-map paths made absolute from ``folder``.

    Changes ``table`` in place, but not the body tables it holds: a body whose paths change is
    a new table (a campaign's case tables share their base's).
    """
    for name in ("body1", "body2"):
        body = table.get(name)
        if not isinstance(body, dict) or "surface" not in body:
            continue
        surface = body["surface"]
        given = surface if isinstance(surface, dict) else {"file": surface}
        for key in ("file", "case"):
            file = given.get(key)
            if isinstance(file, str) and file and not Path(file).expanduser().is_absolute():
                resolved = str((folder / file).resolve())
                given = {**given, key: resolved}
        given = given if isinstance(surface, dict) else given["file"]
        if given != surface:
            table[name] = {**body, "surface": given}
    return table
