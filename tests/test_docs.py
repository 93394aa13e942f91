"""The guide: it builds with warnings as errors, and its reference pages match the declarations.

The reference pages are generated (``docs/generate.py``) from :data:`solver.keys.CASE_KEYS`,
:data:`study.campaign.CAMPAIGN_KEYS`, :mod:`solver.variables` and the argparse parser; these
tests check that every declared key and variable is on its page, that the parser accepts
exactly the declared keys, and that the whole guide builds offline without a warning.
"""

from __future__ import annotations

import importlib.util
import subprocess
import sys
from pathlib import Path

import pytest

import solver
from solver.keys import CASE_KEYS, table_keys
from solver.variables import CYCLE_QUANTITIES, FIELDS, HISTORIES
from study.campaign import CAMPAIGN_KEYS, CampaignError, expand_campaign
from study.cli import build_parser
from study.run.assemble import BOOKKEEPING, SCALARS

ROOT = Path(__file__).resolve().parents[1]
spec = importlib.util.spec_from_file_location("docs_generate", ROOT / "docs" / "generate.py")
generate = importlib.util.module_from_spec(spec)
spec.loader.exec_module(generate)

ELASTIC = {"behaviour": "elastic", "radius": 0.01, "E": 210e9, "nu": 0.3}
BASE = {
    "body1": ELASTIC,
    "body2": ELASTIC | {"radius": "inf"},
    "load": {"hertz_pressure": 1e9},
    "grid": {"n": 16},
}


def test_every_case_key_is_on_the_case_keys_page():
    page = generate.case_keys_page()
    for key in CASE_KEYS:
        assert f"| `{key.name}` |" in page, key.path
        assert f"`[{key.table}]`" in page or not key.table


def test_the_parser_accepts_exactly_the_declared_keys():
    """An undeclared key is refused with the declared set as the allowed keys."""
    tables = {
        "": (BASE, ""),
        "bodyN": (BASE["body1"], "body1"),
        "grid": (BASE["grid"], "grid"),
        "friction": ({}, "friction"),
        "solver": ({}, "solver"),
        "output": ({}, "output"),
        "load.path[i]": (BASE["load"], "load"),
    }
    for table, (content, where) in tables.items():
        bad = dict(BASE)
        inner = dict(content) | {"colour": 1}
        if where:
            bad[where] = inner
        else:
            bad = inner
        with pytest.raises(solver.SpecError) as info:
            solver.Case.from_dict(bad)
        allowed = str(info.value).split("allowed keys are ", 1)[1].split(", ")
        assert set(allowed) == table_keys(table), table
    assert table_keys("load") - {"path"} == table_keys("load.path[i]")


def test_every_campaign_setting_is_declared_and_on_its_page():
    page = generate.campaign_keys_page()
    settings = {key.name for key in CAMPAIGN_KEYS if key.table == "campaign"}
    for key in CAMPAIGN_KEYS:
        assert f"| `{key.name}` |" in page
    with pytest.raises(CampaignError) as info:
        expand_campaign({"campaign": {"colour": 1}, "base": BASE, "sweep": {"grid.n": [16]}})
    assert set(str(info.value).split("allowed are ", 1)[1].split(", ")) == settings


def test_every_dataset_variable_is_on_the_dataset_page():
    page = generate.dataset_page()
    for name in [*HISTORIES, *FIELDS, *CYCLE_QUANTITIES, *SCALARS, *BOOKKEEPING]:
        assert f"| `{name}` |" in page, name


def test_every_command_and_option_is_on_the_cli_page():
    page = generate.cli_page()
    parser = build_parser()
    commands = next(a for a in parser._actions if a.__class__.__name__ == "_SubParsersAction")
    for name, sub in commands.choices.items():
        assert f"## `python -m study {name}`" in page
        for action in sub._actions:
            for flag in action.option_strings:
                if flag not in ("-h", "--help"):
                    assert flag in page, (name, flag)


def test_the_guide_builds_offline_with_warnings_as_errors(tmp_path):
    pytest.importorskip("sphinx")
    pytest.importorskip("myst_parser")
    done = subprocess.run(
        [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html", "docs",
         str(tmp_path / "html")],
        capture_output=True, text=True, cwd=ROOT, timeout=600,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr[-3000:]
    assert (tmp_path / "html" / "reference" / "case-keys.html").exists()


def test_the_case_schema_accepts_the_shipped_cases_and_refuses_an_unknown_key():
    jsonschema = pytest.importorskip("jsonschema")
    import tomllib

    schema = generate.case_schema()
    jsonschema.Draft202012Validator.check_schema(schema)
    validator = jsonschema.Draft202012Validator(schema)
    checked = 0
    for path in sorted((ROOT / "campaigns").glob("*.toml")):
        base = tomllib.loads(path.read_text())["base"]
        if {"body1", "body2"} <= set(base):  # complete cases (others take bodies from [define])
            assert not list(validator.iter_errors(base)), path.name
            solver.Case.from_dict(base)  # and the solver agrees
            checked += 1
    assert checked >= 5
    bad = BASE | {"grid": {"n": 16, "nzz": 8}}
    assert any("nzz" in error.message for error in validator.iter_errors(bad))
