"""Write the guide's reference pages from the code's own declarations.

Run by ``docs/conf.py`` before every build; the pages are also kept in the repository, so that
the guide's links to them work where it is read unbuilt, and a test fails when they differ from
what the code declares (``python docs/generate.py`` rewrites them):

- ``case-keys.md``: :data:`solver.keys.CASE_KEYS` (the parser takes its accepted keys from it);
- ``campaign-keys.md``: :data:`study.campaign.CAMPAIGN_KEYS`;
- ``dataset.md``: :data:`solver.variables.HISTORIES`, ``FIELDS``, ``CYCLE_QUANTITIES`` and the
  campaign scalars of :data:`study.run.assemble.SCALARS`;
- ``cli.md``: the argparse parser of ``python -m study`` (:func:`study.cli.build_parser`);
- ``api.md``: autodoc directives for the public Python API;
- ``layout.md``: the packages' own docstrings, parts in their tested order
  (:data:`solver.PARTS`, :data:`study.PARTS`).
"""

from __future__ import annotations

import argparse
import importlib
import inspect
import json
from pathlib import Path

PAGES = ("case-keys", "campaign-keys", "dataset", "cli", "api", "layout")
#: JSON types of the declared kinds (a key whose kind starts so).
_JSON_TYPES = {
    'boolean or "y"': {"anyOf": [{"type": "boolean"}, {"const": "y"}]},
    'number or "inf"': {"anyOf": [{"type": "number"}, {"const": "inf"}]},
    "number or string": {"anyOf": [{"type": "number"}, {"enum": ["yield", "none"]}]},
    "number or [Qx, Qy]": {
        "anyOf": [{"type": "number"}, {"type": "array", "items": {"type": "number"}}]
    },
    "integer or [nx, ny] or [nx, ny, nz]": {
        "anyOf": [{"type": "integer"}, {"type": "array", "items": {"type": "integer"}}]
    },
    "number or [dx, dy]": {
        "anyOf": [{"type": "number"}, {"type": "array", "items": {"type": "number"}}]
    },
    "[dx, dy]": {"type": "array", "items": {"type": "number"}},
    "number or [xi, eta]": {
        "anyOf": [{"type": "number"}, {"type": "array", "items": {"type": "number"}}]
    },
    "number or [Lx, Ly]": {
        "anyOf": [{"type": "number"}, {"type": "array", "items": {"type": "number"}}]
    },
    "number": {"type": "number"},
    "integer": {"type": "integer"},
    'integer or "auto"': {"anyOf": [{"type": "integer"}, {"const": "auto"}]},
    "string": {"type": "string"},
    "boolean": {"type": "boolean"},
    "array of strings": {"type": "array", "items": {"type": "string"}},
}
#: The table a key of kind "table" (or a path's stages) opens.
_SUBTABLES = {
    "body1": "bodyN", "body2": "bodyN", "hardening": "bodyN.hardening",
    "profile": "bodyN.profile", "surface": "bodyN.surface", "roughness": "bodyN.roughness",
    "kinematic": "bodyN.hardening.kinematic", "load": "load", "friction": "friction",
    "grid": "grid", "solver": "solver", "output": "output", "wear": "wear", "fatigue": "fatigue",
}  # fmt: skip


def _cell(text: object) -> str:
    return str(text).replace("|", "\\|").replace("\n", " ") or " "


def _table(header: list[str], rows: list[list[object]]) -> list[str]:
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(_cell(c) for c in row) + " |" for row in rows]
    return lines + [""]


def _keys_section(keys, title_of) -> list[str]:
    lines = []
    tables = list(dict.fromkeys(key.table for key in keys))
    for table in tables:
        lines += [f"## {title_of(table)}", ""]
        rows = [
            [f"`{k.name}`", k.kind, k.unit, k.default, k.accepted, k.used_by, k.doc]
            for k in keys
            if k.table == table
        ]
        header = ["key", "type", "unit", "default", "accepted", "used by", "meaning"]
        lines += _table(header, rows)
    return lines


def case_keys_page() -> str:
    """The case keys: one table per case-file table."""
    from solver.keys import CASE_KEYS

    lines = [
        "# Case keys",
        "",
        "Every key of a case table (a case file, or `[base]` of a campaign file), generated from",
        "`solver.keys.CASE_KEYS`, from which the parser takes the keys each table accepts.",
        "Units are SI; `a_H` is the Hertz radius (the largest semi-axis) at the largest load.",
        "`bodyN` stands for `body1` (the indenter, upper) and `body2` (lower, z into it).",
        "A JSON Schema of a case file, generated from the same declarations, lets a TOML editor",
        "with schema support complete and check the keys: [case.schema.json](case.schema.json)",
        "(for a campaign's `[base]`, whose tables a sweep may fill, some required keys may be",
        "absent).",
        "",
    ]

    def title(table: str) -> str:
        return f"`[{table}]`" if table else "Top level"

    return "\n".join(lines + _keys_section(CASE_KEYS, title))


def campaign_keys_page() -> str:
    """The campaign-file keys outside ``[base]``."""
    from study.campaign import CAMPAIGN_KEYS, CASE_TABLES

    lines = [
        "# Campaign keys",
        "",
        "The tables of a campaign file and the `[campaign]` settings, generated from",
        "`study.campaign.CAMPAIGN_KEYS`.  `[base]` holds a case table ([case keys](case-keys.md));",
        "a swept key is the dotted path of a case key whose first segment is one of "
        + ", ".join(f"`{t}`" for t in CASE_TABLES)
        + " (e.g. `friction.coefficient`, `load.path.1.steps`).",
        "",
    ]

    def title(table: str) -> str:
        return {"": "Tables", "[sweep]": "Pseudo-keys of `[sweep]` and `[zip]`"}.get(
            table, f"`[{table}]`"
        )

    return "\n".join(lines + _keys_section(CAMPAIGN_KEYS, title))


def _flags(flags: dict[str, int]) -> str:
    return "int8 flags: " + ", ".join(f"{value} {name}" for name, value in flags.items())


def dataset_page() -> str:
    """Every variable of a case's dataset and of a campaign's assembled dataset."""
    from solver.numerics.tensor import COMPONENTS
    from solver.result import CONTACT_STATES, STATUS_FLAGS
    from solver.theory.shakedown import SHAKEDOWN_FLAGS
    from solver.variables import CYCLE_QUANTITIES, FIELDS, HISTORIES
    from study.run.assemble import BOOKKEEPING, SCALARS

    lines = [
        "# Dataset variables",
        "",
        "Generated from `solver.variables` (histories, fields, per-cycle quantities: declared",
        "once, the result, its xarray view and the campaign assembly derive from them) and",
        "`study.run.assemble.SCALARS`.",
        "",
        "## Histories (one value per load step)",
        "",
        "In a case's dataset as `NAME(step)`; in a campaign's as `NAME_history(axes..., step)`,",
        "and reduced to a per-case scalar (the reduction column) under the scalar's name.",
        "",
    ]
    rows = [
        [f"`{name}`", h.units, h.long_name, h.reduction or "not reduced", h.scalar_name(name) or ""]
        for name, h in HISTORIES.items()
    ]
    lines += _table(["name", "units", "long_name", "campaign reduction", "scalar"], rows)
    lines += [
        "## Fields",
        "",
        "In a case's dataset (and the lazy loader `open_fields`).  Surface fields are indexed",
        '`(x, y)`: `ds.pressure.plot(x="x")` puts x along the abscissa (a height map is given',
        "the other way, `height(y, x)`, as an image).",
        "",
    ]
    rows = [[f"`{n}`", ", ".join(f.dims), f.units, f.long_name] for n, f in FIELDS.items()]
    lines += _table(["name", "dims", "units", "long_name"], rows)
    lines += ["## Flags and coordinates of a case's dataset", ""]
    rows = [
        ["`contact_state`", "x, y", _flags(CONTACT_STATES)],
        ["`shakedown`", "(scalar, cyclic paths)", _flags(SHAKEDOWN_FLAGS)],
        ["`component`", "coordinate", "tensor fields' order: " + ", ".join(COMPONENTS)],
    ]
    lines += _table(["name", "dims", "values"], rows)
    lines += ["## Per-cycle quantities (dimension `cycle`)", ""]
    rows = [[f"`{n}`", units, long] for n, (units, long) in CYCLE_QUANTITIES.items()]
    lines += _table(["name", "units", "long_name"], rows)
    lines += ["## Per-case scalars of a campaign dataset (dimensions: the sweep axes)", ""]
    rows = [[f"`{n}`", units, long] for n, (units, long) in SCALARS.items()]
    lines += _table(["name", "units", "long_name"], rows)
    lines += ["## Per-case bookkeeping of a campaign dataset", ""]
    notes = {"status": _flags(STATUS_FLAGS)}
    rows = [[f"`{n}`", long, notes.get(n, "")] for n, long in BOOKKEEPING.items()]
    lines += _table(["name", "long_name", "values"], rows)
    return "\n".join(lines)


def _actions(parser: argparse.ArgumentParser) -> list[list[object]]:
    rows = []
    for action in parser._actions:
        if isinstance(action, argparse._HelpAction | argparse._SubParsersAction):
            continue
        flags = ", ".join(action.option_strings) or action.dest
        default = "" if action.default in (None, argparse.SUPPRESS, False) else action.default
        rows.append([f"`{flags}`", (action.help or "").replace("%%", "%"), default])
    return rows


def cli_page() -> str:
    """Every command and option of ``python -m study``."""
    from study.cli import build_parser

    parser = build_parser()
    lines = ["# Command line", "", "Generated from the argparse parser of `python -m study`.", ""]
    lines += ["```text", parser.format_usage().strip(), "```", ""]
    if parser.description:
        lines += [parser.description, ""]
    commands = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    helps = {choice.dest: choice.help for choice in commands._choices_actions}
    for name, sub in commands.choices.items():
        lines += [f"## `python -m study {name}`", "", helps.get(name) or "", ""]
        lines += ["```text", sub.format_usage().strip(), "```", ""]
        if sub.description:
            lines += [sub.description, ""]
        rows = _actions(sub)
        if rows:
            lines += _table(["argument", "meaning", "default"], rows)
    return "\n".join(lines)


#: The public Python API, by module: (module, [names]) documented with autodoc.
API = (
    ("solver", ["Case", "solve", "Result", "SpecError", "memory_estimate"]),
    ("solver.theory.hertz", None),
    ("solver.theory.friction", None),
    ("solver.bodies.geometry", None),
    ("solver.theory.sneddon", None),
    ("solver.bodies.dundurs", None),
    ("study.campaign", ["load_campaign", "expand_campaign", "Campaign", "CampaignCase"]),
    ("study.run.driver", ["run_campaign", "RunOptions"]),
    ("study.run.assemble", ["assemble_to_file"]),
    ("study.analysis", None),
    ("study.analysis.fields", ["open_fields"]),
    ("study.report", ["build_report"]),
)


def api_page() -> str:
    """Autodoc directives for the public API."""
    lines = [
        "# Python API",
        "",
        "The docstrings of the public functions and classes (numpydoc, SI units).",
        "",
    ]
    for module, names in API:
        lines += [f"## `{module}`", ""]
        if names is None:
            lines += ["```{eval-rst}", f".. automodule:: {module}", "   :members:", "```", ""]
            continue
        imported = importlib.import_module(module)
        for name in names:
            kind = "autoclass" if inspect.isclass(getattr(imported, name)) else "autofunction"
            options = ["   :members:"] if kind == "autoclass" else []
            lines += ["```{eval-rst}", f".. {kind}:: {module}.{name}", *options, "```", ""]
    return "\n".join(lines)


def layout_page() -> str:
    """The code's layout: each package's docstring, then each part's, bottom up."""
    lines = [
        "# Code layout",
        "",
        "What each package and part holds and may import, from their own docstrings (the",
        "order, each part importing only those before it, is tested by `tests/test_layout.py`).",
        "",
    ]
    on_api_page = {module for module, names in API if names is None}
    for package in ("solver", "study"):
        parts = [p for p in importlib.import_module(package).PARTS if p != "__main__"]
        for name in (package, *(f"{package}.{part}" for part in parts)):
            lines += [f"{'##' if name == package else '###'} `{name}`", ""]
            if name in on_api_page:  # its docstring is there, with its labels
                lines += [f"Its docstring is on the [API page](api.md) (`{name}`).", ""]
                continue
            directive = [f".. automodule:: {name}", "   :no-index:"]  # the API page indexes
            lines += ["```{eval-rst}", *directive, "```", ""]
    return "\n".join(lines)


def case_schema() -> dict:
    """A JSON Schema of a case table (TOML editors with schema support complete and check keys)."""
    from solver.keys import CASE_KEYS

    def table(name: str) -> dict:
        keys = [key for key in CASE_KEYS if key.table == name]
        properties = {}
        for key in keys:
            if key.kind == "table":
                properties[key.name] = table(_SUBTABLES[key.name])
            elif key.kind == "string or table":  # a file name, or its table
                properties[key.name] = {"anyOf": [{"type": "string"}, table(_SUBTABLES[key.name])]}
            elif key.name == "stages":  # of a cycle block
                properties[key.name] = {"type": "array", "items": table("load.path[i]")}
            elif key.name == "path":
                items = [table("load.path[i]"), table("load.path[i] (cycle block)")]
                properties[key.name] = {"type": "array", "items": {"anyOf": items}}
            else:
                properties[key.name] = dict(_JSON_TYPES[key.kind])
            unit = f" ({key.unit})" if key.unit and key.unit != "1" else ""
            properties[key.name]["description"] = f"{key.doc}{unit} Accepted: {key.accepted}."
        out = {"type": "object", "properties": properties, "additionalProperties": False}
        required = sorted(key.name for key in keys if key.required)
        return out | ({"required": required} if required else {})

    return {
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "title": "slipstick case",
    } | table("")


def write_all(folder: Path) -> None:
    """Write every reference page into ``folder`` (only the ones whose text changed)."""
    folder = Path(folder)
    folder.mkdir(exist_ok=True)
    builders = {
        "case-keys": case_keys_page,
        "campaign-keys": campaign_keys_page,
        "dataset": dataset_page,
        "cli": cli_page,
        "api": api_page,
        "layout": layout_page,
    }
    texts = {f"{name}.md": builders[name]() + "\n" for name in PAGES}
    texts["case.schema.json"] = json.dumps(case_schema(), indent=1) + "\n"
    for name, text in texts.items():
        path = folder / name
        if not path.exists() or path.read_text() != text:
            path.write_text(text)


if __name__ == "__main__":
    write_all(Path(__file__).resolve().parent / "reference")
