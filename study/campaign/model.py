"""The campaign's data: settings, axes, coordinates and cases (frozen, serialisable)."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import solver
from solver.keys import CASE_KEYS, Key

from .cost import WORK_FIELDS, Work, count
from .naming import CampaignError as CampaignError  # defined there, re-exported
from .naming import _is_inf, _is_number, format_value
from .sample import DISTRIBUTIONS, METHODS, SAMPLE_DIM, Design
from .surfaces import read_surface

#: Top-level tables of a campaign file.
TOP_LEVEL = ("campaign", "base", "sweep", "zip", "sample", "alias", "define")
#: First segments of a swept key: the case file's tables (declared in solver.keys) and the
#: pseudo-table of Dundurs' beta.
CASE_TABLES = (
    *(key.name for key in CASE_KEYS if key.table == "" and key.kind == "table"),
    "materials",
)
#: The pseudo-key that sweeps Dundurs' beta.
BETA_KEY = "materials.dundurs_beta"
#: 2-D surface fields a case file may keep (``[campaign] fields``).
SURFACE_FIELDS = ("pressure", "shear_x", "shear_y", "contact_state")
#: Largest case timeout (s, about 116 days): ``signal.setitimer`` overflows on huge values, and
#: ``inf`` is refused rather than read as "none" (leave the setting out for no timeout).
MAX_CASE_TIMEOUT = 1e7


#: Every key of a campaign file outside ``[base]`` (whose keys are :data:`solver.keys.CASE_KEYS`),
#: declared once: ``read`` takes the accepted ``[campaign]`` settings from here, the guide's
#: reference page is written from it.
CAMPAIGN_KEYS: tuple[Key, ...] = (
    Key("", "campaign", "table", "", "optional", "the settings below", "every campaign",
        "Name, output folder and run settings."),
    Key("", "base", "table", "", "required", "a case table (the case keys)", "every campaign",
        "The case every point of the sweep starts from."),
    Key("", "sweep", "table", "", "one of sweep / zip / sample", '"dotted.key" = [values]',
        "every campaign", "One axis per key; the cases are the product of the axes."),
    Key("", "zip", "table", "", "one of sweep / zip / sample", '[zip.NAME] "key" = [values], ...',
        "campaigns that vary keys together", "One axis per group, its keys stepping together."),
    Key("", "sample", "table", "", "one of sweep / zip / sample",
        '"dotted.key" = { distribution = ..., ... }, method, count, seed', "sampled designs",
        "A design's rows: one dimension, sample, with the sampled keys as its coordinates."),
    Key("", "alias", "table", "", "optional", '"dotted.key" = "name"', "every campaign",
        "Names of the dataset coordinates (default: the key with _ for .)."),
    Key("", "define", "table", "", "optional", "[define.NAME] tables", "sweeps of whole tables",
        'Named tables a sweep of "body1", "load", ... picks by name.'),
    Key("[sweep]", BETA_KEY, "number", "1", "", "what body 1's constants can reach",
        "two deforming bodies", "Dundurs' beta, set by body 1's E and nu at fixed E*."),
    Key("sample", "method", "string", "", "required", ", ".join(METHODS), "sampled designs",
        "lhs, sobol: space filling; saltelli: Sobol' indices; morris: elementary effects."),
    Key("sample", "count", "integer", "1", "required", "lhs, morris: >= 1; sobol, saltelli: a "
        "power of 2", "sampled designs", "Points (lhs, sobol), base samples N (saltelli: "
        "N (D + 2) cases, N (2 D + 2) with second_order), trajectories r (morris: r (D + 1))."),
    Key("sample", "seed", "integer", "1", "0", ">= 0", "sampled designs",
        "Seed of the design (the same seed, the same rows)."),
    Key("sample", "second_order", "boolean", "", "false", "true, false", "saltelli",
        "Add the rows of the second-order indices."),
    Key("sample", "levels", "integer", "1", "4", "even, >= 2", "morris",
        "Levels of Morris' grid in the unit interval."),
    Key("sample", '"dotted.key"', "table", "", "", ", ".join(
        f"{name}: {', '.join(fields)}" for name, fields in DISTRIBUTIONS.items()),
        "sampled designs", "A sampled key's distribution (normal: bounds truncate it; "
        "discrete: equally likely values)."),
    Key("campaign", "name", "string", "", "the file's name", "letters, digits, _ . -",
        "every campaign", "Campaign name: the dataset is OUT/<name>.nc."),
    Key("campaign", "output", "string", "", '"out/<name>"', "a folder path", "every campaign",
        "Output folder."),
    Key("campaign", "description", "string", "", '""', "any text", "every campaign",
        "Summary attribute of the dataset."),
    Key("campaign", "fft_threads", "integer", "1", "the cases' own", "[1, 256]",
        "every campaign", "FFTW threads of every case (not part of the case ids)."),
    Key("campaign", "fields", "array of strings", "", str(list(SURFACE_FIELDS)),
        ", ".join(SURFACE_FIELDS), "every campaign", "Surface fields each stored case keeps."),
    Key("campaign", "max_initial_failures", "integer", "1", "5", ">= 0 (0 never stops)",
        "every campaign", "Stop early when the first cases all fail."),
    Key("campaign", "profile_extent", "number", "a_H", "1.5", "(0, 100]", "every campaign",
        "Extent of the radial profiles (r / a_H)."),
    Key("campaign", "profile_points", "integer", "1", "151", "[2, 100000]", "every campaign",
        "Points of the radial profiles."),
    Key("campaign", "case_timeout", "number", "s", "none", f"(0, {MAX_CASE_TIMEOUT:g}]",
        "every campaign", "Seconds after which a case is abandoned (failed)."),
)  # fmt: skip


#: ``campaign.json``'s format.  /2 writes a case as a row of :data:`CASE_COLUMNS` (its
#: coordinates and work as lists in the order the record's head names them; coordinates of
#: other names as a table) and its spec as
#: the top-level tables that differ from the record's reference spec (the first case's,
#: :func:`spec_changes`); /1 (a table per case, every spec whole) is still read.
FORMAT = "slipstick-campaign/2"
READABLE_FORMATS = ("slipstick-campaign/1", FORMAT)
#: The columns of a case's row in ``campaign.json``.
CASE_COLUMNS = ("number", "index", "coords", "case_id", "cost", "memory", "warnings", "work",
                "changes")  # fmt: skip


def _same(a: object, b: object) -> bool:
    return a is b or a == b


def spec_changes(spec: Mapping, reference: Mapping) -> dict:
    """The top-level tables of ``spec`` that differ from ``reference``'s.

    A table of ``reference`` that ``spec`` lacks is None; :func:`with_changes` undoes it.
    """
    changes = {k: v for k, v in spec.items() if k not in reference or not _same(reference[k], v)}
    changes.update((k, None) for k in reference.keys() - spec.keys())
    return changes


def with_changes(reference: Mapping, changes: Mapping) -> dict:
    """The spec of :func:`spec_changes`: ``reference``'s tables (shared) with ``changes``."""
    spec = {**reference, **changes}
    if None in changes.values():
        spec = {k: v for k, v in spec.items() if v is not None}
    return spec


def shared_spec(spec: dict, reference: Mapping) -> dict:
    """``spec`` with the tables equal to ``reference``'s replaced by ``reference``'s own.

    Cases built from one base share their unchanged tables: less memory, and a pickle of many
    cases writes each shared table once.  A spec is read, never changed in place (copy it
    first, as :func:`study.run.driver.solver_case` does).
    """
    return {
        k: reference[k] if k in reference and _same(reference[k], v) else v for k, v in spec.items()
    }


#: A progress callback: ``progress(done, total)`` (cases expanded so far, all cases).
Progress = Callable[[int, int], None]
#: Cases between two calls of a progress callback.
PROGRESS_EVERY = 2000


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
        Normalised case table (:meth:`solver.Case.to_dict`); its unchanged tables may be
        shared with other cases' (:func:`shared_spec`): read it, copy it to change it.
    case_id : str
        :attr:`solver.Case.case_id`.
    cost : float
        Estimated work (:func:`study.campaign.cost.reference_seconds`: seconds at the reference
        machine's unit costs; machine-independent, for ordering and comparing cases).
    memory : int
        :meth:`solver.Case.memory_estimate` (bytes).
    warnings : tuple of str
        :attr:`solver.Case.warnings`: what the case is built with but should be read with care.
    work : study.campaign.cost.Work, optional
        The predicted work (:func:`study.campaign.cost.count`), counted at the expansion, so
        that estimates on a machine's unit costs need not build the case again.
    """

    number: int
    index: tuple[int, ...]
    coords: dict
    spec: dict
    case_id: str
    cost: float
    memory: int
    warnings: tuple[str, ...] = ()
    work: Work | None = field(default=None, compare=False, repr=False)

    @property
    def label(self) -> str:
        """``name=value, ...`` of the sweep coordinates (for messages)."""
        return ", ".join(f"{k}={format_value(v)}" for k, v in self.coords.items()) or "(base)"

    def case(self) -> solver.Case:
        """The validated :class:`solver.Case`."""
        return solver.Case.from_dict(self.spec, read_surface)

    def estimated_work(self) -> Work:
        """The predicted work of the case (:attr:`work`, else counted from :meth:`case`)."""
        return self.work if self.work is not None else count(self.case())


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
    base : dict
        The ``[base]`` table.
    design : Design, optional
        The ``[sample]`` design, whose rows are the ``sample`` axis.
    """

    settings: Settings
    axes: tuple[Axis, ...]
    cases: tuple[CampaignCase, ...]
    source: str = ""
    base: dict = field(default_factory=dict, compare=False)
    design: Design | None = None

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

    def distinct_cases(self) -> tuple[CampaignCase, ...]:
        """The cases with distinct case ids, the first of each, in case order.

        A design's repeated rows are one case, computed once.
        """
        return tuple(self.by_id().values())

    def by_id(self) -> dict[str, CampaignCase]:
        """Cases by case id (of a repeated id, its first case)."""
        found: dict[str, CampaignCase] = {}
        for case in self.cases:
            found.setdefault(case.case_id, case)
        return found

    def axes_dicts(self, values: bool = True) -> list[dict]:
        """The axes in JSON-able form.

        Without ``values``, a sampled axis's values are left out (the dataset's coordinates
        hold them).
        """
        return [
            {
                "name": axis.name,
                "zipped": axis.zipped,
                "coordinates": [
                    {
                        "key": c.key,
                        "name": c.name,
                        "values": list(c.values)
                        if values or self.design is None or axis.name != SAMPLE_DIM
                        else f"{axis.size} rows (the coordinate {c.name})",
                        "units": c.units,
                        "long_name": c.long_name,
                    }
                    for c in axis.coordinates
                ],
            }
            for axis in self.axes
        ]

    def to_dict(self) -> dict:
        """JSON-able form (what ``OUT/campaign.json`` holds: :data:`FORMAT`)."""
        reference = self.cases[0].spec if self.cases else {}
        names = [c.name for axis in self.axes for c in axis.coordinates]
        return {
            "format": FORMAT,
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
            "design": None if self.design is None else self.design.to_dict(),
            "axes": self.axes_dicts(),
            "reference_spec": reference,
            "case_columns": list(CASE_COLUMNS),
            "coordinate_names": names,
            "work_fields": list(WORK_FIELDS),
            "cases": [
                [
                    case.number,
                    list(case.index),
                    list(case.coords.values()) if list(case.coords) == names else case.coords,
                    case.case_id,
                    case.cost,
                    case.memory,
                    list(case.warnings),
                    None if case.work is None else case.work.values(),
                    spec_changes(case.spec, reference),
                ]
                for case in self.cases
            ],
        }

    @classmethod
    def from_dict(cls, data: Mapping) -> Campaign:
        """Rebuild a campaign from :meth:`to_dict` output (no re-validation).

        Raises
        ------
        CampaignError
            If the record is of a format this version does not read.
        """
        found = data.get("format")
        if found not in READABLE_FORMATS:
            raise CampaignError(
                f"campaign record of format {found!r}; this version reads "
                f"{', '.join(READABLE_FORMATS)}: run the campaign again with this version (its "
                "case files are reused), or read it with the version that wrote it"
            )
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
        if found == FORMAT:
            cases = _cases_from_rows(data)
        else:
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
                    work=Work(**c["work"]) if c.get("work") else None,
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
            design=Design.from_dict(data["design"]) if data.get("design") else None,
        )


def _cases_from_rows(data: Mapping) -> tuple[CampaignCase, ...]:
    """The cases of a :data:`FORMAT` record (rows of its ``case_columns``)."""
    if tuple(data["case_columns"]) != CASE_COLUMNS or tuple(data["work_fields"]) != WORK_FIELDS:
        raise CampaignError(
            f"campaign record with case columns {data['case_columns']} and work fields "
            f"{data['work_fields']}; this version writes {list(CASE_COLUMNS)} and "
            f"{list(WORK_FIELDS)}: run the campaign again with this version"
        )
    reference, names = data["reference_spec"], data["coordinate_names"]
    return tuple(
        CampaignCase(
            number=number,
            index=tuple(index),
            coords=dict(zip(names, coords, strict=True)) if isinstance(coords, list) else coords,
            spec=with_changes(reference, changes),
            case_id=case_id,
            cost=cost,
            memory=memory,
            warnings=tuple(warnings),
            work=None if work is None else Work(*work),
        )
        for number, index, coords, case_id, cost, memory, warnings, work, changes in data["cases"]
    )
