"""Campaign files: a base case, sweep axes and zipped axes, expanded into validated cases.

A campaign file is declarative TOML::

    [campaign]                        # optional settings
    name = "quickstart"               # default: the file name without .toml
    output = "out/quickstart"         # default: out/<name>, relative to the working directory
    fft_threads = 1                   # FFTW threads per rank (run-time only, not in the case id)
    fields = ["pressure", "shear_x", "shear_y", "contact_state"]   # 2-D fields kept per case
    max_initial_failures = 5          # stop when the first k cases all fail (0: never)
    case_timeout = 600                # a case running longer fails (seconds; default none)
    profile_extent = 1.5              # radial profiles on r / a in [0, extent] ...
    profile_points = 151              # ... with this many points

    [base]                            # one case table (see solver.Case.from_dict)
    body1 = { behaviour = "elastic", radius = 0.01, E = 210e9, nu = 0.3 }
    ...

    [sweep]                           # full product; one dimension per key
    "friction.coefficient" = [0.0, 0.1, 0.2]
    "materials.dundurs_beta" = [-0.1, 0.0, 0.1]

    [zip.mesh]                        # keys that vary together: ONE dimension "mesh"
    "grid.n" = [32, 64, 128]
    "solver.normal_tolerance" = [1e-6, 1e-7, 1e-8]

    [alias]                           # dimension / coordinate names (default: dots -> "_")
    "friction.coefficient" = "mu"

    [define.steel_swift]              # named tables, swept by name as a whole case table
    behaviour = "elastic-plastic"     # ("body1" = ["steel", "steel_swift"] in [sweep]/[zip])
    ...

Keys are dotted paths into the base table; an integer segment indexes an array of tables
(``"load.path.1.tangential_force"``, also written ``"load.path[1].tangential_force"``, 0-based).
Missing tables on the path are created.  A flat ``[zip]`` table (dotted keys directly under
``[zip]``) forms one dimension named by its coordinate names joined with ``"__"``; a sub-table
``[zip.NAME]`` forms one dimension called NAME.  When a zipped dimension has the name of one of
its coordinates, that coordinate indexes it.

A key that names a whole case table (``"body1"``, ``"body2"``, ``"load"``, ...) is swept by
name: each value is the name of a ``[define.NAME]`` table that replaces the base's table in that
case (e.g. an elastic and an elastic-plastic body, which take different keys).  The names are
the coordinate values.

The pseudo-key ``materials.dundurs_beta`` sets Dundurs' beta by changing body 1's elastic
constants, see :func:`body1_for_beta`.

Swept values are numbers, strings or booleans, never lists.  A volume grid is swept through
its two keys: ``"grid.n"`` (one number: nx = ny) and ``"grid.nz"`` (cells in depth).  The rule
for a ``"grid.n"`` axis over a base with ``grid.n = [nx, ny, nz]``: the base's nz is kept, so
every case has the volume grid ``[n, n, nz]`` (nz is not scaled with n); to vary nz as well,
zip ``"grid.n"`` with ``"grid.nz"`` or sweep ``"grid.nz"`` on its own axis (which replaces the
base's nz, also when the base gives it in ``grid.n``).

:func:`load_campaign` reads, expands and validates a campaign; every problem raises
:class:`CampaignError` whose message names the key or the case (by its sweep coordinates) and
the field.  This module imports no MPI and writes no files.
"""

from __future__ import annotations

import copy
import itertools
import math
import re
import tomllib
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import solver
from solver.case import MODULUS_RANGE
from solver.materials import Body
from solver.variables import CYCLE_QUANTITIES, reduced_scalars

#: Top-level tables of a campaign file.
TOP_LEVEL = ("campaign", "base", "sweep", "zip", "alias", "define")
#: First segments of a swept key.
CASE_TABLES = ("body1", "body2", "load", "friction", "grid", "solver", "output", "materials")
#: The pseudo-key that sweeps Dundurs' beta.
BETA_KEY = "materials.dundurs_beta"
#: 2-D surface fields a case file may keep (``[campaign] fields``).
SURFACE_FIELDS = ("pressure", "shear_x", "shear_y", "contact_state")
#: Names used by the assembled dataset for its structure and its per-case results; no axis may
#: take them (nor names ending in ``_history`` or ``_profile``).  Axes may take the names of the
#: per-case inputs the dataset also records (``dundurs_beta``, ``hertz_pressure``, ...): the
#: coordinate then replaces that variable.
RESERVED_NAMES = frozenset(
    {
        "status",
        "case_id",
        "error",
        "mpi_rank",
        "grid_cells",
        "step",
        "r_over_a",
        "z_over_a",
        "x",
        "y",
        "contact_radius",
        "stick_radius",
        "steps",
        "wall_time",
        "case_time",
        "peak_rss",
        "cycle",
    }
    | set(reduced_scalars())
    | set(CYCLE_QUANTITIES)
)
#: Largest case timeout (s, about 116 days): ``signal.setitimer`` overflows on huge values, and
#: ``inf`` is refused rather than read as "none" (leave the setting out for no timeout).
MAX_CASE_TIMEOUT = 1e7
_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")
_CAMPAIGN_NAME = re.compile(r"^[A-Za-z0-9_][A-Za-z0-9_.-]*$")

#: Units and readable names of a swept key, by its last segment.
_KEY_META = {
    "coefficient": ("1", "Coulomb friction coefficient"),
    "hertz_pressure": ("Pa", "Hertz peak pressure of the load"),
    "normal_force": ("N", "normal force"),
    "tangential_force": ("N", "tangential force along x"),
    "steps": ("1", "number of load increments"),
    "n": ("1", "grid cells per side"),
    "nz": ("1", "volume-grid cells in depth"),
    "half_width": ("1", "domain half-width over the Hertz semi-axis"),
    "depth": ("1", "volume-grid depth over the Hertz semi-axis"),
    "E": ("Pa", "Young's modulus"),
    "nu": ("1", "Poisson's ratio"),
    "radius": ("m", "radius of curvature"),
    "radius_x": ("m", "radius of curvature in the x-z plane"),
    "radius_y": ("m", "radius of curvature in the y-z plane"),
    "dundurs_beta": ("1", "Dundurs' second constant beta"),
    "yield_stress": ("Pa", "initial yield stress"),
    "modulus": ("Pa", "linear hardening modulus"),
    "B": ("Pa", "Swift hardening coefficient"),
    "max_load_ratio": ("1", "largest normal-load ratio per coupled step"),
    "fft_threads": ("1", "FFTW threads"),
}


#: A progress callback: ``progress(done, total)`` (cases expanded so far, all cases).
Progress = Callable[[int, int], None]
#: Cases between two calls of a progress callback.
PROGRESS_EVERY = 2000


class CampaignError(ValueError):
    """A bad campaign file: the message names the key or case, the field, and what to change."""


# -- data ----------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Coordinate:
    """One swept key and its values.

    Attributes
    ----------
    key : str
        Normalised dotted key (``"load.path.1.tangential_force"``).
    name : str
        Coordinate name in the dataset (alias, or the key with dots replaced by ``_``).
    values : tuple
        Swept values as written in the file (numbers, strings or booleans).
    units : str or None
        CF units when known.
    long_name : str
        Readable description.
    """

    key: str
    name: str
    values: tuple
    units: str | None
    long_name: str

    def array_values(self) -> list:
        """Values as stored in the dataset: numbers (``"inf"`` -> inf) or strings."""
        if all(_is_number(v) or _is_inf(v) for v in self.values):
            if all(isinstance(v, int) and not isinstance(v, bool) for v in self.values):
                return list(self.values)
            return [float(v) for v in self.values]
        return list(self.values)


@dataclass(frozen=True)
class Axis:
    """One dimension of the campaign: a swept key, or several keys zipped together.

    Attributes
    ----------
    name : str
        Dimension name.
    coordinates : tuple of Coordinate
        One coordinate for a ``[sweep]`` axis, one per key for a ``[zip]`` group.
    zipped : bool
        True for a ``[zip]`` group.
    """

    name: str
    coordinates: tuple[Coordinate, ...]
    zipped: bool = False

    @property
    def size(self) -> int:
        """Number of values along the axis."""
        return len(self.coordinates[0].values)

    @property
    def index_coordinate(self) -> Coordinate | None:
        """The coordinate that indexes the dimension (same name), if any."""
        for coordinate in self.coordinates:
            if coordinate.name == self.name:
                return coordinate
        return None


@dataclass(frozen=True)
class CampaignCase:
    """One point of the sweep: its position, coordinates and validated case table.

    Attributes
    ----------
    number : int
        Position in the expansion order (C order over the axes), from 0.
    index : tuple of int
        Index along every axis.
    coords : dict
        Coordinate name -> swept value.
    spec : dict
        Normalised case table (:meth:`solver.Case.to_dict`).
    case_id : str
        :attr:`solver.Case.case_id`.
    cost : float
        :meth:`solver.Case.cost_estimate` (relative units).
    memory : int
        :meth:`solver.Case.memory_estimate` (bytes).
    warnings : tuple of str
        :attr:`solver.Case.warnings`: what the case is built with but should be read with care.
    """

    number: int
    index: tuple[int, ...]
    coords: dict
    spec: dict
    case_id: str
    cost: float
    memory: int
    warnings: tuple[str, ...] = ()

    @property
    def label(self) -> str:
        """``name=value, ...`` of the sweep coordinates (for messages)."""
        return ", ".join(f"{k}={_format_value(v)}" for k, v in self.coords.items()) or "(base)"

    def case(self) -> solver.Case:
        """The validated :class:`solver.Case`."""
        return solver.Case.from_dict(self.spec)


@dataclass(frozen=True)
class Settings:
    """``[campaign]`` settings (see the module docstring)."""

    name: str
    output: str
    fft_threads: int | None = None
    fields: tuple[str, ...] = SURFACE_FIELDS
    max_initial_failures: int = 5
    profile_extent: float = 1.5
    profile_points: int = 151
    description: str = ""
    case_timeout: float | None = None


@dataclass(frozen=True)
class Campaign:
    """An expanded, validated campaign.

    Attributes
    ----------
    settings : Settings
        ``[campaign]`` settings.
    axes : tuple of Axis
        Dimensions, ``[sweep]`` keys first (file order), then ``[zip]`` groups.
    cases : tuple of CampaignCase
        Every case, in C order over the axes.
    source : str
        The campaign file it was read from ("" for a table).
    """

    settings: Settings
    axes: tuple[Axis, ...]
    cases: tuple[CampaignCase, ...]
    source: str = ""
    base: dict = field(default_factory=dict, compare=False)

    @property
    def name(self) -> str:
        """Campaign name."""
        return self.settings.name

    @property
    def dims(self) -> tuple[str, ...]:
        """Dimension names."""
        return tuple(axis.name for axis in self.axes)

    @property
    def shape(self) -> tuple[int, ...]:
        """Dimension sizes."""
        return tuple(axis.size for axis in self.axes)

    def by_id(self) -> dict[str, CampaignCase]:
        """Cases by case id."""
        return {case.case_id: case for case in self.cases}

    def to_dict(self) -> dict:
        """JSON-able form (what ``OUT/campaign.json`` holds)."""
        return {
            "format": "slipstick-campaign/1",
            "slipstick_version": solver.__version__,
            "name": self.name,
            "source": self.source,
            "settings": {
                "name": self.settings.name,
                "output": self.settings.output,
                "fft_threads": self.settings.fft_threads,
                "fields": list(self.settings.fields),
                "max_initial_failures": self.settings.max_initial_failures,
                "profile_extent": self.settings.profile_extent,
                "profile_points": self.settings.profile_points,
                "description": self.settings.description,
                "case_timeout": self.settings.case_timeout,
            },
            "base": self.base,
            "axes": [
                {
                    "name": axis.name,
                    "zipped": axis.zipped,
                    "coordinates": [
                        {
                            "key": c.key,
                            "name": c.name,
                            "values": list(c.values),
                            "units": c.units,
                            "long_name": c.long_name,
                        }
                        for c in axis.coordinates
                    ],
                }
                for axis in self.axes
            ],
            "cases": [
                {
                    "number": case.number,
                    "index": list(case.index),
                    "coords": case.coords,
                    "case_id": case.case_id,
                    "cost": case.cost,
                    "memory": case.memory,
                    "warnings": list(case.warnings),
                    "spec": case.spec,
                }
                for case in self.cases
            ],
        }

    @classmethod
    def from_dict(cls, data: Mapping) -> Campaign:
        """Rebuild a campaign from :meth:`to_dict` output (no re-validation)."""
        settings = data["settings"]
        axes = tuple(
            Axis(
                name=axis["name"],
                zipped=axis["zipped"],
                coordinates=tuple(
                    Coordinate(c["key"], c["name"], tuple(c["values"]), c["units"], c["long_name"])
                    for c in axis["coordinates"]
                ),
            )
            for axis in data["axes"]
        )
        cases = tuple(
            CampaignCase(
                number=c["number"],
                index=tuple(c["index"]),
                coords=dict(c["coords"]),
                spec=c["spec"],
                case_id=c["case_id"],
                cost=c["cost"],
                memory=c["memory"],
                warnings=tuple(c.get("warnings", ())),
            )
            for c in data["cases"]
        )
        return cls(
            settings=Settings(
                name=settings["name"],
                output=settings["output"],
                fft_threads=settings["fft_threads"],
                fields=tuple(settings["fields"]),
                max_initial_failures=settings["max_initial_failures"],
                profile_extent=settings["profile_extent"],
                profile_points=settings["profile_points"],
                description=settings.get("description", ""),
                case_timeout=settings.get("case_timeout"),
            ),
            axes=axes,
            cases=cases,
            source=data.get("source", ""),
            base=data.get("base", {}),
        )


# -- reading -------------------------------------------------------------------------------------
def load_campaign(path: str | Path, progress: Progress | None = None) -> Campaign:
    """Read, expand and validate a campaign file.

    Parameters
    ----------
    path : str or Path
        The TOML campaign file.
    progress : callable, optional
        ``progress(done, total)``, called every :data:`PROGRESS_EVERY` cases of the expansion
        and at its end (for a progress line on long campaigns).

    Returns
    -------
    Campaign
        Every case validated by :meth:`solver.Case.from_dict`.

    Raises
    ------
    CampaignError
        If the file cannot be read, is not TOML, or any key, value or case is invalid.
    """
    path = Path(path)
    try:
        with open(path, "rb") as handle:
            table = tomllib.load(handle)
    except FileNotFoundError:
        raise CampaignError(f"{path}: no such campaign file") from None
    except IsADirectoryError:
        raise CampaignError(f"{path}: is a directory, expected a campaign file (.toml)") from None
    except OSError as error:
        raise CampaignError(f"{path}: cannot read: {error.strerror or error}") from None
    except ValueError as error:  # TOMLDecodeError, UnicodeDecodeError, an int of > 4300 digits
        raise CampaignError(f"{path}: not valid TOML: {error}") from None
    return expand_campaign(table, name=path.stem, source=str(path), progress=progress)


def expand_campaign(
    table: Mapping, name: str = "campaign", source: str = "", progress: Progress | None = None
) -> Campaign:
    """Expand and validate a campaign table (the parsed TOML).

    Parameters
    ----------
    table : mapping
        The campaign table with ``base`` and ``sweep``/``zip`` (and optional ``campaign``,
        ``alias``) entries.
    name : str
        Default campaign name when ``[campaign] name`` is not given.
    source : str
        Where the table came from (recorded, used in messages).
    progress : callable, optional
        ``progress(done, total)`` during the expansion (see :func:`load_campaign`).

    Returns
    -------
    Campaign
        The expanded campaign.

    Raises
    ------
    CampaignError
        Naming the key or case and field.
    """
    if not isinstance(table, Mapping):
        raise CampaignError("a campaign must be a table")
    unknown = sorted(set(table) - set(TOP_LEVEL))
    if unknown:
        hint = ""
        if unknown[0] in ("body1", "body2", "load", "friction", "grid", "solver", "output"):
            hint = f"; case tables go under [base] (write [base.{unknown[0]}])"
        elif unknown[0] == "axes":
            hint = "; coordinate names go in [alias]"
        raise CampaignError(
            f"[{unknown[0]}]: unknown table; a campaign has {', '.join(TOP_LEVEL)}{hint}"
        )
    if "base" not in table:
        raise CampaignError("[base]: missing; give the base case table (body1, body2, load, ...)")
    base = table["base"]
    if not isinstance(base, Mapping):
        raise CampaignError("[base]: must be a table")
    settings = _parse_settings(table.get("campaign", {}), name)
    entries = _parse_axes(table.get("sweep"), table.get("zip"))
    defined = _parse_defined(table.get("define", {}), entries)
    aliases = _parse_aliases(table.get("alias", {}), [key for key, _ in _all_keys(entries)])
    axes = _build_axes(entries, aliases)
    _check_paths(base, axes, defined)
    cases = _expand_cases(dict(base), axes, progress, defined)
    return Campaign(settings, axes, cases, source, base=copy.deepcopy(dict(base)))


def _parse_defined(raw: Any, entries: list[_Entry]) -> dict[str, dict]:
    """``[define.NAME]`` tables, and a check that every whole-table axis names one of them."""
    if not isinstance(raw, Mapping) or not all(isinstance(v, Mapping) for v in raw.values()):
        raise CampaignError(
            "[define]: must hold named tables, e.g. [define.steel] with behaviour, E, nu, ..."
        )
    for name in raw:
        if not _NAME.match(name):
            raise CampaignError(
                f"[define.{name}]: the name must be an identifier (letters, digits, _)"
            )
    used = set()
    for entry in entries:
        for key, written, values in entry.members:
            if "." in key:
                continue
            for value in values:
                if not isinstance(value, str) or value not in raw:
                    known = ", ".join(sorted(raw)) or "none defined"
                    raise CampaignError(
                        f'"{written}": a whole case table is swept by name; {value!r} is not '
                        f"a [define.NAME] table (defined: {known}); add [define.{value}] with "
                        f'the {key} table, or sweep a key inside it (e.g. "{key}.E")'
                    )
                used.add(value)
    unused = sorted(set(raw) - used)
    if unused:
        raise CampaignError(
            f"[define.{unused[0]}]: defined but no axis names it; sweep a whole table by name "
            f'(e.g. "body1" = ["{unused[0]}", ...]) or remove it'
        )
    return {name: dict(table) for name, table in raw.items()}


# -- settings ------------------------------------------------------------------------------------
def _parse_settings(raw: Any, default_name: str) -> Settings:
    if not isinstance(raw, Mapping):
        raise CampaignError("[campaign]: must be a table")
    allowed = {
        "name",
        "output",
        "fft_threads",
        "fields",
        "max_initial_failures",
        "profile_extent",
        "profile_points",
        "description",
        "case_timeout",
    }
    unknown = sorted(set(raw) - allowed)
    if unknown:
        raise CampaignError(
            f"campaign.{unknown[0]}: unknown setting; allowed are {', '.join(sorted(allowed))}"
        )
    name = raw.get("name", default_name)
    if not isinstance(name, str) or not _CAMPAIGN_NAME.match(name):
        raise CampaignError(
            f"campaign.name: must be a file-name-safe string (letters, digits, _ . -), got {name!r}"
        )
    output = raw.get("output", str(Path("out") / name))
    if not isinstance(output, str) or not output.strip():
        raise CampaignError(f"campaign.output: must be a folder path (string), got {output!r}")
    threads = raw.get("fft_threads")
    if threads is not None and (not _is_int(threads) or not 1 <= threads <= 256):
        raise CampaignError(f"campaign.fft_threads: must be an integer 1..256, got {threads!r}")
    fields = raw.get("fields", list(SURFACE_FIELDS))
    if (
        not isinstance(fields, list)
        or any(f not in SURFACE_FIELDS for f in fields)
        or len(set(fields)) != len(fields)
    ):
        raise CampaignError(
            f"campaign.fields: must be a list drawn from {list(SURFACE_FIELDS)}, got {fields!r}"
        )
    failures = raw.get("max_initial_failures", 5)
    if not _is_int(failures) or failures < 0:
        raise CampaignError(
            f"campaign.max_initial_failures: must be an integer >= 0 (0 never stops), "
            f"got {failures!r}"
        )
    extent = raw.get("profile_extent", 1.5)
    if not _is_number(extent) or not 0 < extent <= 100:
        raise CampaignError(
            f"campaign.profile_extent: must be a number in (0, 100], got {extent!r}"
        )
    points = raw.get("profile_points", 151)
    if not _is_int(points) or not 2 <= points <= 100000:
        raise CampaignError(f"campaign.profile_points: must be an integer >= 2, got {points!r}")
    description = raw.get("description", "")
    if not isinstance(description, str):
        raise CampaignError("campaign.description: must be a string")
    timeout = raw.get("case_timeout")
    if timeout is not None and (not _is_number(timeout) or not 0 < timeout <= MAX_CASE_TIMEOUT):
        raise CampaignError(
            f"campaign.case_timeout: must be a number of seconds in (0, {MAX_CASE_TIMEOUT:g}] "
            f"(leave it out for no timeout), got {timeout!r}"
        )
    return Settings(
        name=name,
        output=output,
        fft_threads=threads,
        fields=tuple(fields),
        max_initial_failures=int(failures),
        profile_extent=float(extent),
        profile_points=int(points),
        description=description,
        case_timeout=None if timeout is None else float(timeout),
    )


# -- axes ----------------------------------------------------------------------------------------
@dataclass
class _Entry:
    """A parsed axis before naming: its keys (with values) and an explicit group name."""

    members: list[tuple[str, str, list]]  # (normalised key, key as written, values)
    group: str | None  # "[sweep]", "[zip]" or the zip sub-table name
    zipped: bool


def _all_keys(entries: list[_Entry]):
    for entry in entries:
        for key, written, _ in entry.members:
            yield key, written


def _parse_axes(sweep: Any, zipped: Any) -> list[_Entry]:
    if sweep is None and zipped is None:
        raise CampaignError(
            "nothing to sweep: add a [sweep] table (or [zip]); for a single case sweep one "
            'value, e.g. "friction.coefficient" = [0.1]'
        )
    entries: list[_Entry] = []
    if sweep is not None:
        if not isinstance(sweep, Mapping):
            raise CampaignError("[sweep]: must be a table of dotted keys = [values]")
        if not sweep and zipped is None:
            raise CampaignError('[sweep]: empty; give at least one key, e.g. "grid.n" = [32, 64]')
        for written, values in _flatten_keys(sweep, "[sweep]"):
            key = normalise_key(written, "[sweep]")
            values = _check_values(values, f'[sweep] "{written}"', key)
            entries.append(_Entry([(key, written, values)], None, False))
    if zipped is not None:
        if not isinstance(zipped, Mapping) or not zipped:
            raise CampaignError(
                "[zip]: must be a non-empty table of dotted keys = [values] "
                "(or sub-tables [zip.NAME])"
            )
        # [zip.NAME] sub-tables are groups; unquoted dotted keys (grid.n = [...]) arrive as
        # nested tables named after a case table and belong to the flat group.
        groups = {
            k: v
            for k, v in zipped.items()
            if isinstance(v, Mapping) and "." not in k and k not in CASE_TABLES
        }
        flat = {k: v for k, v in zipped.items() if k not in groups}
        if flat:
            entries.append(_zip_entry(flat, None, "[zip]"))
        for group, members in groups.items():
            if not _NAME.match(group):
                raise CampaignError(
                    f"[zip.{group}]: the group name is a dimension name and must be an "
                    "identifier (letters, digits, _)"
                )
            entries.append(_zip_entry(members, group, f"[zip.{group}]"))
    seen: dict[str, str] = {}
    for key, written in _all_keys(entries):
        if key in seen:
            raise CampaignError(
                f'duplicate axis: "{written}" and "{seen[key]}" both set {key}; sweep a key once'
            )
        seen[key] = written
    keys = sorted(seen)
    for a, b in itertools.pairwise(keys):
        if b.startswith(a + "."):
            raise CampaignError(
                f'overlapping axes: "{seen[a]}" contains "{seen[b]}"; sweep one or the other'
            )
    return entries


def _flatten_keys(table: Mapping, where: str):
    """Yield (dotted key, value); TOML splits unquoted dotted keys into nested tables."""
    for key, value in table.items():
        if isinstance(value, Mapping):
            for sub, inner in _flatten_keys(value, where):
                yield f"{key}.{sub}", inner
        else:
            yield key, value


def _zip_entry(members: Mapping, group: str | None, where: str) -> _Entry:
    flat = list(_flatten_keys(members, where))
    if not flat:
        raise CampaignError(f"{where}: empty; give two or more dotted keys = [values]")
    out = []
    for written, values in flat:
        key = normalise_key(written, where)
        out.append((key, written, _check_values(values, f'{where} "{written}"', key, False)))
    lengths = {written: len(values) for _, written, values in out}
    if len(set(lengths.values())) > 1:
        detail = ", ".join(f'"{k}" has {n}' for k, n in lengths.items())
        raise CampaignError(f"{where}: zipped lists must have the same length, but {detail} values")
    seen = []
    for point in zip(*(values for _, _, values in out), strict=True):
        normal = tuple(float(v) if _is_inf(v) else v for v in point)
        if normal in seen:
            raise CampaignError(
                f"{where}: the values {list(point)!r} appear twice; zipped points must differ"
            )
        seen.append(normal)
    return _Entry(out, group, True)


def normalise_key(written: str, where: str = "[sweep]") -> str:
    """Normalise a dotted key: ``"load.path[1].steps"`` -> ``"load.path.1.steps"``.

    Raises
    ------
    CampaignError
        If the key is empty, has empty segments or bad brackets.
    """
    key = re.sub(r"\[(\d+)\]", r".\1", written.strip())
    segments = key.split(".")
    if not key or any(not s or not re.match(r"^[A-Za-z0-9_]+$", s) for s in segments):
        raise CampaignError(
            f'{where} "{written}": not a dotted key path like "friction.coefficient" or '
            '"load.path.1.tangential_force"'
        )
    if segments[0] == "materials":
        if key != BETA_KEY:
            raise CampaignError(
                f'{where} "{written}": unknown materials key; the only one is "{BETA_KEY}"'
            )
    elif segments[0] not in CASE_TABLES:
        raise CampaignError(
            f'{where} "{written}": unknown case table "{segments[0]}"; keys start with body1, '
            f"body2, load, friction, grid, solver, output (or {BETA_KEY})"
        )
    return key


def _check_values(values: Any, where: str, key: str, unique: bool = True) -> list:
    if not isinstance(values, list):
        raise CampaignError(f"{where}: must be a list of values, got {values!r}")
    if not values:
        raise CampaignError(f"{where}: empty list; give at least one value")
    for value in values:
        if isinstance(value, list | dict):
            raise CampaignError(
                f"{where}: values must be numbers, strings or booleans, got {value!r}"
                + (
                    "; for a tangential force give the x component as a number"
                    if key.endswith("tangential_force")
                    else ""
                )
                + (
                    '; sweep "grid.n" as one number per value (nx = ny; the base\'s nz is '
                    'kept) and the depth as "grid.nz"'
                    if key == "grid.n"
                    else ""
                )
            )
        if isinstance(value, float) and math.isnan(value):
            raise CampaignError(f"{where}: nan is not a value")
    kinds = {_kind(v) for v in values}
    if len(kinds) > 1:
        raise CampaignError(f"{where}: mixed value types {values!r}; use one type per axis")
    if key == BETA_KEY and kinds != {"number"}:
        raise CampaignError(f"{where}: Dundurs' beta values must be numbers, got {values!r}")
    seen = []
    for value in values if unique else ():
        normal = float(value) if _is_inf(value) else value  # 1 == 1.0; no float(huge int)
        if normal in seen:
            raise CampaignError(f"{where}: value {value!r} appears twice; axis values must differ")
        seen.append(normal)
    return values


def _kind(value: Any) -> str:
    if _is_number(value) or _is_inf(value):
        return "number"
    return type(value).__name__


def _parse_aliases(raw: Any, keys: list[str]) -> dict[str, str]:
    if not isinstance(raw, Mapping):
        raise CampaignError("[alias]: must be a table of dotted key = name")
    out = {}
    for written, name in _flatten_keys(raw, "[alias]"):
        key = normalise_key(written, "[alias]")
        if key not in keys:
            raise CampaignError(
                f'[alias] "{written}": not a swept key; swept keys are {", ".join(keys)}'
            )
        if not isinstance(name, str) or not _NAME.match(name):
            raise CampaignError(
                f'[alias] "{written}": the name must be an identifier (letters, digits, _), '
                f"got {name!r}"
            )
        out[key] = name
    return out


def default_name(key: str) -> str:
    """Default coordinate name of a key: dots replaced by underscores."""
    return key.replace(".", "_")


def _meta(key: str) -> tuple[str | None, str]:
    if "." not in key:
        return None, f"{key} table, by its [define] name ({key})"
    last = key.split(".")[-1]
    units, text = _KEY_META.get(last, (None, last.replace("_", " ")))
    if last.endswith("_tolerance"):
        units = "1"
    if last.endswith("_iterations"):
        units = "1"
    owner = key.split(".")[0]
    if owner in ("body1", "body2"):
        text = f"{text} of body {owner[-1]}"
    match = re.search(r"path\.(\d+)\.", key)
    if match:
        text = f"{text} at load stage {match.group(1)}"
    return units, f"{text} ({key})"


def _build_axes(entries: list[_Entry], aliases: dict[str, str]) -> tuple[Axis, ...]:
    axes = []
    for entry in entries:
        coordinates = []
        for key, _, values in entry.members:
            units, long_name = _meta(key)
            name = aliases.get(key, default_name(key))
            coordinates.append(Coordinate(key, name, tuple(values), units, long_name))
        if entry.group is not None:
            name = entry.group
        else:
            name = "__".join(c.name for c in coordinates)
        axes.append(Axis(name, tuple(coordinates), entry.zipped))
    owner: dict[str, str] = {}
    for axis in axes:
        labels = {axis.name: axis.name if axis.zipped else axis.coordinates[0].key}
        for c in axis.coordinates:
            labels.setdefault(c.name, c.key)
        for label, source in labels.items():
            if label in RESERVED_NAMES or label.endswith(("_history", "_profile")):
                raise CampaignError(
                    f'axis name "{label}" ({source}) is reserved by the campaign dataset; '
                    "choose another in [alias]"
                )
            if label in owner:
                raise CampaignError(
                    f'duplicate axis name "{label}" ({owner[label]} and {source}); '
                    "give distinct names in [alias] or [zip.NAME]"
                )
            owner[label] = source
    return tuple(axes)


# -- paths into the base table -------------------------------------------------------------------
def _segments(key: str) -> list[str | int]:
    return [int(s) if s.isdigit() else s for s in key.split(".")]


def assign(table: dict, key: str, value: Any) -> None:
    """Set the dotted ``key`` of a case table to ``value`` (in place).

    Missing tables on the path are created; integer segments index arrays of tables.

    Raises
    ------
    CampaignError
        If the path runs through a value, indexes a table or runs past an array.
    """
    node: Any = table
    segments = _segments(key)
    done: list[str] = []
    for position, segment in enumerate(segments):
        last = position == len(segments) - 1
        where = ".".join(done) or "the base table"
        if isinstance(segment, int):
            if not isinstance(node, list):
                raise CampaignError(
                    f'key "{key}": {where} is not an array of tables, cannot index it with '
                    f"{segment}"
                )
            if segment >= len(node):
                raise CampaignError(
                    f'key "{key}": index {segment} is out of range, {where} has {len(node)} '
                    "entries (indices start at 0)"
                )
            if last:
                node[segment] = value
            else:
                node = node[segment]
        else:
            if isinstance(node, list):
                raise CampaignError(
                    f'key "{key}": {where} is an array; give an index, e.g. "{where}.0.{segment}"'
                )
            if not isinstance(node, dict):
                raise CampaignError(f'key "{key}": {where} is a value, not a table')
            if last:
                node[segment] = value
            else:
                if segment not in node:
                    node[segment] = {}
                node = node[segment]
        done.append(str(segment))


def _check_paths(base: Mapping, axes: tuple[Axis, ...], defined: dict[str, dict]) -> None:
    probe = copy.deepcopy(dict(base))
    for axis in axes:
        for coordinate in axis.coordinates:
            if coordinate.key == BETA_KEY:
                continue
            assign(probe, coordinate.key, _value(coordinate.key, coordinate.values[0], defined))
    load = base.get("load")
    for axis in axes:
        for c in axis.coordinates:
            if c.key.startswith("load.") and not c.key.startswith("load.path"):
                if isinstance(load, Mapping) and "path" in load:
                    raise CampaignError(
                        f'key "{c.key}": the base load is a path ([[base.load.path]]); address '
                        f'a stage, e.g. "load.path.0.{c.key.split(".", 1)[1]}"'
                    )


# -- Dundurs' beta -------------------------------------------------------------------------------
def _beta_factor(nu: float) -> float:
    """g(nu1) = (1 - 2 nu1) / (2 (1 - nu1)), through which beta depends on nu1."""
    return (1.0 - 2.0 * nu) / (2.0 * (1.0 - nu))


def _lowest_nu1(body1: Body) -> float:
    """Most negative nu1 with body 1's compliance held: where E1 reaches the smallest modulus."""
    return -math.sqrt(max(1.0 - MODULUS_RANGE[0] * body1.compliance, 0.0))


def beta_range(body1: Body, body2: Body) -> tuple[float, float]:
    """Range [low, high] of Dundurs' beta that :func:`body1_for_beta` can reach.

    Parameters
    ----------
    body1 : Body
        Elastic body 1 (its compliance ``(1 - nu1^2)/E1`` is held fixed).
    body2 : Body
        Body 2 (fixed; may be rigid).

    Returns
    -------
    (float, float)
        ``low`` is reached with ``nu1 = 0.5``; ``high`` with the most negative nu1 whose
        ``E1 = (1 - nu1^2)/c1`` is still the smallest modulus a case accepts
        (:data:`solver.case.MODULUS_RANGE`, 1e3 Pa): ``nu1 -> -1`` would need ``E1 -> 0``.
        ``high`` lies just below the limit ``(3/4 c1 - d2)/A`` (by ~1e-9 relative for steel).
        Both ends are reachable.
    """
    c1, c2, d2 = body1.compliance, body2.compliance, body2.dilatational_compliance
    total = c1 + c2
    return -d2 / total, (_beta_factor(_lowest_nu1(body1)) * c1 - d2) / total


def body1_for_beta(beta: float, body1: Body, body2: Body) -> tuple[float, float]:
    """Body 1's (E1, nu1) that give Dundurs' beta with body 2 and E* unchanged.

    The rule: body 2 is fixed, and body 1 keeps its compliance ``c1 = (1 - nu1^2)/E1``, so the
    composite modulus E*, the Hertz solution and the grid stay the same across a beta sweep.
    With ``A = c1 + c2`` and ``d2 = (1 + nu2)(1 - 2 nu2)/(2 E2)``, beta depends on nu1 only
    through ``g(nu1) = (1 - 2 nu1)/(2 (1 - nu1)) = (beta A + d2)/c1 =: t``, which inverts to::

        nu1 = (1 - 2 t) / (2 (1 - t)),     E1 = (1 - nu1^2) / c1.

    ``g`` falls monotonically from 3/4 (nu1 -> -1) to 0 (nu1 = 1/2), so beta is reachable for
    ``-d2/A <= beta < (3/4 c1 - d2)/A``; but E1 falls to 0 as nu1 -> -1, so the upper end is
    where E1 reaches the smallest modulus a case accepts (1e3 Pa), a hair below that limit:
    :func:`beta_range` gives the closed range, both ends included.

    Parameters
    ----------
    beta : float
        Target Dundurs beta (dimensionless).
    body1 : Body
        Elastic body 1 of the base case (its E and nu set ``c1``).
    body2 : Body
        Body 2 (kept).

    Returns
    -------
    (float, float)
        Young's modulus E1 (Pa) and Poisson's ratio nu1 of body 1.

    Raises
    ------
    ValueError
        If beta is outside the reachable range (the message gives the range, rounded inwards
        to 6 decimals so that both printed ends are reachable), or E1 would exceed the
        largest modulus accepted.
    """
    low, high = beta_range(body1, body2)
    c1, c2, d2 = body1.compliance, body2.compliance, body2.dilatational_compliance
    slack = 1e-12 * max(abs(low), abs(high), 1.0)  # round-off of beta_range itself
    if not (math.isfinite(beta) and low - slack <= beta <= high + slack):
        side = (
            "for a more negative beta make body 1 stiffer (raise body1.E in [base])"
            if beta < low
            else "for a larger beta make body 1 more compliant (lower body1.E in [base])"
        )
        shown_low, shown_high = math.ceil(low * 1e6) / 1e6, math.floor(high * 1e6) / 1e6
        raise ValueError(
            f"{BETA_KEY} = {beta!r} is not reachable: with body 2 fixed and E* = "
            f"{1.0 / (c1 + c2):.4g} Pa held, beta must lie in [{shown_low:.6f}, "
            f"{shown_high:.6f}] (nu1 from 0.5 down to where E1 reaches "
            f"{MODULUS_RANGE[0]:g} Pa); {side}"
        )
    nu_min = _lowest_nu1(body1)
    t = min(max((beta * (c1 + c2) + d2) / c1, 0.0), _beta_factor(nu_min))
    nu1 = max((1.0 - 2.0 * t) / (2.0 * (1.0 - t)), nu_min)
    young = max((1.0 - nu1 * nu1) / c1, MODULUS_RANGE[0])  # round-off at the upper end
    if young > MODULUS_RANGE[1]:
        raise ValueError(
            f"{BETA_KEY} = {beta!r} needs body1.E = {young:.4g} Pa (nu1 = {nu1:.4g}), beyond "
            f"the largest modulus accepted, {MODULUS_RANGE[1]:g} Pa; lower body1.E in [base]"
        )
    return young, nu1


def _apply_beta(table: dict, beta: float) -> None:
    raw1, raw2 = table.get("body1"), table.get("body2")
    if not isinstance(raw1, dict) or raw1.get("behaviour") not in ("elastic", "elastic-plastic"):
        behaviour = raw1.get("behaviour") if isinstance(raw1, dict) else None
        raise CampaignError(
            f"{BETA_KEY}: needs an elastic body1 (its E and nu are adjusted), but body1 is "
            f"{behaviour or 'missing'}; make body1 elastic in [base]"
        )
    try:
        body1 = Body("elastic", E=float(raw1["E"]), nu=float(raw1["nu"]))
        if isinstance(raw2, dict) and raw2.get("behaviour") == "rigid":
            body2 = Body("rigid")
        else:
            body2 = Body("elastic", E=float(raw2["E"]), nu=float(raw2["nu"]))
        moduli = [body1.E] + ([] if body2.rigid else [body2.E])
        if not all(MODULUS_RANGE[0] <= e <= MODULUS_RANGE[1] for e in moduli):
            raise ValueError
        if not (-1 < body1.nu <= 0.5 and (body2.rigid or -1 < body2.nu <= 0.5)):
            raise ValueError
    except (KeyError, TypeError, ValueError):
        return  # let Case.from_dict name the bad elastic constant
    try:
        young, nu = body1_for_beta(beta, body1, body2)
    except ValueError as error:
        raise CampaignError(str(error)) from None
    raw1["E"], raw1["nu"] = young, nu


# -- expansion -----------------------------------------------------------------------------------
def _copy_table(value: Any) -> Any:
    """Deep copy of a parsed TOML table (dicts, lists, immutable values): 5x copy.deepcopy."""
    if isinstance(value, dict):
        return {key: _copy_table(item) for key, item in value.items()}
    if isinstance(value, list):
        return [_copy_table(item) for item in value]
    return value


def _keep_volume_depth(base: dict, keys: set[str]) -> dict:
    """A base whose ``grid.n = [nx, ny, nz]`` is written ``n = [nx, ny], nz = nz``.

    Applied when ``grid.n`` or ``grid.nz`` is swept (a swept ``grid.n`` is one number,
    nx = ny), so that a ``grid.n`` sweep keeps the base's nz instead of dropping it and a
    ``grid.nz`` sweep replaces it (module docstring).
    """
    grid = base.get("grid")
    if not {"grid.n", "grid.nz"} & keys or not isinstance(grid, dict) or "nz" in grid:
        return base
    n = grid.get("n")
    if not (isinstance(n, list) and len(n) == 3):
        return base
    return {**base, "grid": {**grid, "n": n[:2], "nz": n[2]}}


def _value(key: str, value: Any, defined: dict[str, dict]) -> Any:
    """What a swept value sets: the ``[define]`` table it names for a whole-table key."""
    return _copy_table(defined[value]) if "." not in key else value


def _expand_cases(
    base: dict,
    axes: tuple[Axis, ...],
    progress: Progress | None = None,
    defined: dict[str, dict] | None = None,
) -> tuple[CampaignCase, ...]:
    cases: list[CampaignCase] = []
    failures: list[tuple[str, str]] = []
    total = math.prod(axis.size for axis in axes)
    seen: dict[str, int] = {}
    keys = {c.key for axis in axes for c in axis.coordinates}
    if BETA_KEY in keys and keys & {"body1.E", "body1.nu"}:
        raise CampaignError(f"{BETA_KEY} sets body1.E and body1.nu; do not sweep them as well")
    base = _keep_volume_depth(base, keys)

    def where(number: int, coords: dict) -> str:
        label = ", ".join(f"{k}={_format_value(v)}" for k, v in coords.items())
        return f"case {number + 1} of {total} ({label})"

    coords_of: dict[int, dict] = {}
    for number, index in enumerate(itertools.product(*(range(axis.size) for axis in axes))):
        if progress is not None and number and number % PROGRESS_EVERY == 0:
            progress(number, total)
        table = _copy_table(base)
        coords: dict[str, Any] = {}
        beta = None
        for axis, i in zip(axes, index, strict=True):
            for coordinate in axis.coordinates:
                value = coordinate.values[i]
                coords[coordinate.name] = value
                if coordinate.key == BETA_KEY:
                    beta = float(value)
                else:
                    assign(table, coordinate.key, _value(coordinate.key, value, defined or {}))
        try:
            if beta is not None:
                _apply_beta(table, beta)
            case = solver.Case.from_dict(table)
        except (solver.SpecError, CampaignError) as error:
            failures.append((where(number, coords), _explain(str(error), axes)))
            continue
        except Exception as error:  # a validation bug must still name the case
            failures.append((where(number, coords), f"{type(error).__name__}: {error}"))
            continue
        case_id = case.case_id
        if case_id in seen:
            first = seen[case_id]
            raise CampaignError(
                f"{where(number, coords)} is the same case as {where(first, coords_of[first])} "
                f"(case id {case_id}); an axis has no effect there, remove the duplicate values"
            )
        seen[case_id] = number
        coords_of[number] = coords
        cases.append(
            CampaignCase(
                number=number,
                index=tuple(index),
                coords=coords,
                spec=case.spec,  # built for this case alone by from_dict: no copy needed
                case_id=case_id,
                cost=float(case.cost_estimate()),
                memory=int(case.memory_estimate()),
                warnings=case.warnings,
            )
        )
    if progress is not None:
        progress(total, total)
    if failures:
        where, message = failures[0]
        field_path = message.split(":", 1)[0]
        if "unknown key" in message and field_path in keys:
            raise CampaignError(f'swept key "{field_path}": {message.split(" [set by")[0]}')
        more = f" (and {len(failures) - 1} more of {total} cases)" if len(failures) > 1 else ""
        raise CampaignError(f"{where}{more}: {message}")
    return tuple(cases)


def _explain(message: str, axes: tuple[Axis, ...]) -> str:
    """Append which axis sets the field a SpecError names, when one does."""
    field_path = message.split(":", 1)[0].strip()
    dotted = re.sub(r"\[(\d+)\]", r".\1", field_path)
    for axis in axes:
        for c in axis.coordinates:
            if c.key == dotted or c.key.startswith(dotted + "."):
                return f'{message} [set by axis "{c.key}"]'
    return message


# -- helpers -------------------------------------------------------------------------------------
def _is_number(value: Any) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool)


def _is_int(value: Any) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def _is_inf(value: Any) -> bool:
    return isinstance(value, str) and value.lower() in ("inf", "infinity")


def _format_value(value: Any) -> str:
    if isinstance(value, float):
        return f"{value:g}"
    if _is_int(value) and abs(value) >= 10**30:
        return f"<integer of {value.bit_length()} bits>"
    return str(value)
