"""Expanding ``[sweep]``, ``[zip]`` and ``[alias]`` into axes, and the axes into cases.

Every case table is built from the base with its coordinates set (:func:`assign`) and
validated by :meth:`solver.Case.from_dict`; a failure names the case by its coordinates.
"""

from __future__ import annotations

import contextlib
import difflib
import gc
import itertools
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import solver
from solver.case.batch import SharedTables

from .cost import REFERENCE, count, seconds
from .model import (
    BETA_KEY,
    CASE_TABLES,
    PROGRESS_EVERY,
    Axis,
    CampaignCase,
    CampaignError,
    Coordinate,
    Progress,
    shared_spec,
)
from .naming import _NAME, RESERVED_NAMES, _is_inf, _meta, default_name, format_value
from .sample import SAMPLE_DIM, Design
from .surfaces import absolute_surfaces, read_surface
from .validate import (
    _apply_beta,
    _check_values,
    _copy_table,
    _explain,
    _value,
    assign,
    normalise_key,
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


def _parse_axes(sweep: Any, zipped: Any, design: Design | None = None) -> list[_Entry]:
    entries: list[_Entry] = []
    if sweep is not None:
        if not isinstance(sweep, Mapping):
            raise CampaignError("[sweep]: must be a table of dotted keys = [values]")
        if not sweep and zipped is None and design is None:
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
            if group == SAMPLE_DIM:
                raise CampaignError(
                    f"[zip.{group}]: {SAMPLE_DIM} is the dimension of a [sample] design; "
                    "name the group otherwise"
                )
            entries.append(_zip_entry(members, group, f"[zip.{group}]"))
    if design is not None:  # the design's rows: one zipped axis, rows may repeat
        members = list(zip(design.keys, design.keys, design.values(), strict=True))
        entries.append(_Entry(members, SAMPLE_DIM, True))
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


def _parse_aliases(raw: Any, keys: list[str]) -> dict[str, str]:
    if not isinstance(raw, Mapping):
        raise CampaignError("[alias]: must be a table of dotted key = name")
    out = {}
    for written, name in _flatten_keys(raw, "[alias]"):
        key = normalise_key(written, "[alias]")
        if key not in keys:
            close = difflib.get_close_matches(key, keys, n=1)  # the swept key misspelt?
            hint = f' (is "{close[0]}" misspelt in the sweep?)' if close else ""
            raise CampaignError(
                f'[alias] "{written}": not a key of [sweep], [zip] or [sample]; those are '
                f"{', '.join(keys)}{hint}"
            )
        if not isinstance(name, str) or not _NAME.match(name):
            raise CampaignError(
                f'[alias] "{written}": the name must be an identifier (letters, digits, _), '
                f"got {name!r}"
            )
        out[key] = name
    return out


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
            design = label == SAMPLE_DIM and axis.name == SAMPLE_DIM  # [zip.sample] is refused
            if (label in RESERVED_NAMES and not design) or label.endswith(("_history", "_profile")):
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


def _repeated_row(index: tuple, other: tuple, axes: tuple[Axis, ...]) -> bool:
    """True when two cases differ in their ``sample`` row only (a design's repeated point)."""
    return all(
        i == j or axis.name == SAMPLE_DIM for i, j, axis in zip(index, other, axes, strict=True)
    )


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


@contextlib.contextmanager
def collector_paused():
    """Pause Python's cyclic garbage collector.

    A case builds many small containers and no cycles; the collector's passes over every case
    built so far cost 17 % at 3 10^4 cases, and more the more cases.
    """
    paused = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if paused:
            gc.enable()


#: A share of an expansion: its cases, and its failures as (number, where, message).
Part = tuple[list[CampaignCase], list[tuple[int, str, str]]]


@dataclass(frozen=True)
class Expansion:
    """What a campaign's cases are built from; :meth:`part` builds a share of them.

    Every case table is the base with its coordinates set; it is validated by
    :meth:`solver.Case.from_dict`.  Parts are independent (each may be built in another
    process or on another rank) and :meth:`cases` joins them, so a spread expansion gives the
    same cases, the same order and the same errors as one in a single process.
    """

    base: dict
    axes: tuple[Axis, ...]
    defined: dict[str, dict]
    folder: Path | None

    @classmethod
    def of(
        cls,
        base: dict,
        axes: tuple[Axis, ...],
        defined: dict[str, dict] | None = None,
        folder: Path | None = None,
    ) -> Expansion:
        """Check the axes against each other and keep the base's volume depth.

        Raises
        ------
        CampaignError
            If Dundurs' beta is swept together with body 1's elastic constants.
        """
        keys = {c.key for axis in axes for c in axis.coordinates}
        if BETA_KEY in keys and keys & {"body1.E", "body1.nu"}:
            raise CampaignError(f"{BETA_KEY} sets body1.E and body1.nu; do not sweep them as well")
        return cls(_keep_volume_depth(base, keys), axes, defined or {}, folder)

    @property
    def total(self) -> int:
        """Number of cases."""
        return math.prod(axis.size for axis in self.axes)

    def _where(self, number: int, coords: dict) -> str:
        label = ", ".join(f"{k}={format_value(v)}" for k, v in coords.items())
        return f"case {number + 1} of {self.total} ({label})"

    def part(self, k: int, n: int, progress: Progress | None = None) -> Part:
        """The cases numbered ``total k // n`` up to ``total (k + 1) // n``, built and checked.

        A case that fails its checks is a failure of the part, not an exception; ``progress``
        gets ``(done, total)`` with this part's count scaled by ``n`` (an estimate of all
        parts' progress when they run side by side).
        """
        with collector_paused():
            return self._part(k, n, progress)

    def _part(self, k: int, n: int, progress: Progress | None) -> Part:
        total = self.total
        start, stop = total * k // n, total * (k + 1) // n
        product = itertools.product(*(range(axis.size) for axis in self.axes))
        cases: list[CampaignCase] = []
        failures: list[tuple[int, str, str]] = []
        # every case table is the base with its coordinates set, copied on write: the tables
        # no swept key changes are the base's own, parsed once (SharedTables)
        base = _copy_table(self.base)
        if self.folder is not None:
            absolute_surfaces(base, self.folder)
        shared = SharedTables()
        for number, index in enumerate(itertools.islice(product, start, stop), start):
            done = number - start
            if progress is not None and done and done % PROGRESS_EVERY == 0:
                progress(min(n * done, total), total)
            table = dict(base)
            owned = {id(table)}
            coords: dict[str, Any] = {}
            beta = None
            for axis, i in zip(self.axes, index, strict=True):
                for coordinate in axis.coordinates:
                    value = coordinate.values[i]
                    coords[coordinate.name] = value
                    if coordinate.key == BETA_KEY:
                        beta = float(value)
                    else:
                        value = _value(coordinate.key, value, self.defined)  # shared
                        assign(table, coordinate.key, value, owned)
            try:
                if beta is not None:
                    _apply_beta(table, beta)
                if self.folder is not None:
                    absolute_surfaces(table, self.folder)
                case = solver.Case.from_dict(table, read_surface, shared)
            except (solver.SpecError, CampaignError) as error:
                failures.append((number, self._where(number, coords), str(error)))
                continue
            except Exception as error:  # a validation bug must still name the case
                message = f"{type(error).__name__}: {error}"
                failures.append((number, self._where(number, coords), message))
                continue
            work = count(case)
            reference = cases[0].spec if cases else case.spec
            cases.append(
                CampaignCase(
                    number=number,
                    index=tuple(index),
                    coords=coords,
                    spec=shared_spec(case.spec, reference),
                    case_id=case.case_id,
                    cost=float(seconds(work, REFERENCE)),
                    memory=int(solver.memory_estimate(case)),
                    warnings=case.warnings,
                    work=work,
                )
            )
        return cases, failures

    def cases(self, parts: Sequence[Part]) -> tuple[CampaignCase, ...]:
        """Join the parts (in order) into the campaign's cases.

        Raises
        ------
        CampaignError
            At the first case (in expansion order) that repeats an earlier one (an axis with
            no effect), else at the first that failed, counting the others.
        """
        cases = [case for found, _ in parts for case in found]
        failures = [failure for _, lost in parts for failure in lost]
        seen: dict[str, CampaignCase] = {}
        for case in cases:
            first = seen.setdefault(case.case_id, case)
            if first is not case and not _repeated_row(case.index, first.index, self.axes):
                raise CampaignError(
                    f"{self._where(case.number, case.coords)} is the same case as "
                    f"{self._where(first.number, first.coords)} (case id {case.case_id}); an "
                    "axis has no effect there, remove the duplicate values"
                )
        if failures:
            _, where, message = failures[0]
            message = _explain(message, self.axes)
            field_path = message.split(":", 1)[0]
            kinds = {
                c.key: "sampled" if axis.name == SAMPLE_DIM else "swept"
                for axis in self.axes
                for c in axis.coordinates
            }
            if "unknown key" in message and field_path in kinds:
                raise CampaignError(
                    f'{kinds[field_path]} key "{field_path}": {message.split(" [set by")[0]}'
                )
            more = (
                f" (and {len(failures) - 1} more of {self.total} cases)"
                if len(failures) > 1
                else ""
            )
            raise CampaignError(f"{where}{more}: {message}")
        return tuple(cases)


#: Builds every part of an expansion somewhere and returns them in order:
#: ``spread(expansion, progress)``.  ``expansion.part(0, n, progress)`` runs in the calling
#: process (``progress`` reports it); the other parts may run in other processes or on other
#: ranks (:mod:`study.campaign.parallel`, :func:`study.run.driver.broadcast_campaign`).
Spread = Callable[[Expansion, Progress | None], list[Part]]


def serial(expansion: Expansion, progress: Progress | None) -> list[Part]:
    """The :data:`Spread` of one process: the whole expansion as one part."""
    return [expansion.part(0, 1, progress)]
