"""Reading a campaign file: its TOML, ``[campaign]`` settings and ``[define]`` tables.

:func:`load_campaign` reads a file, :func:`expand_campaign` a parsed table; both validate
everything before returning (:class:`CampaignError` names the key or the case).
"""

from __future__ import annotations

import copy
import tomllib
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from .expand import (
    Expansion,
    Spread,
    _all_keys,
    _build_axes,
    _Entry,
    _parse_aliases,
    _parse_axes,
    serial,
)
from .model import (
    CAMPAIGN_KEYS,
    CASE_TABLES,
    MAX_CASE_TIMEOUT,
    SURFACE_FIELDS,
    TOP_LEVEL,
    Campaign,
    CampaignError,
    Progress,
    Settings,
)
from .naming import _CAMPAIGN_NAME, _NAME, _is_int, _is_number
from .sample import parse_sample
from .validate import _check_paths, normalise_key


# -- reading -------------------------------------------------------------------------------------
def load_campaign(
    path: str | Path, progress: Progress | None = None, spread: Spread = serial
) -> Campaign:
    """Read, expand and validate a campaign file.

    Parameters
    ----------
    path : str or Path
        The TOML campaign file.
    progress : callable, optional
        ``progress(done, total)``, called every :data:`PROGRESS_EVERY` cases of the expansion
        and at its end (for a progress line on long campaigns).
    spread : Spread
        Where the shares of the expansion are built: :func:`~study.campaign.expand.serial`
        (this process), :func:`study.campaign.parallel.processes` (worker processes) or the
        ranks of an MPI run (:func:`study.run.driver.broadcast_campaign`).

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
    return expand_campaign(table, path.stem, str(path), progress, spread)


def expand_campaign(
    table: Mapping,
    name: str = "campaign",
    source: str = "",
    progress: Progress | None = None,
    spread: Spread = serial,
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
    spread : Spread
        Where the shares of the expansion are built (see :func:`load_campaign`).

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
        if unknown[0] in CASE_TABLES[:-1]:  # (not the pseudo-table "materials")
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
    design = None if "sample" not in table else parse_sample(table["sample"], normalise_key)
    entries = _parse_axes(table.get("sweep"), table.get("zip"), design)
    defined = _parse_defined(table.get("define", {}), entries)
    aliases = _parse_aliases(table.get("alias", {}), [key for key, _ in _all_keys(entries)])
    axes = _build_axes(entries, aliases)
    _check_paths(base, axes, defined)
    folder = Path(source).resolve().parent if source else Path.cwd()  # of relative map files
    expansion = Expansion.of(dict(base), axes, defined, folder)
    cases = expansion.cases(spread(expansion, progress))
    if progress is not None:
        progress(expansion.total, expansion.total)
    return Campaign(settings, axes, cases, source, base=copy.deepcopy(dict(base)), design=design)


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
    allowed = {key.name for key in CAMPAIGN_KEYS if key.table == "campaign"}
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
