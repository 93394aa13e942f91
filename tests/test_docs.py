"""The guide: it builds with warnings as errors, and its reference pages match the declarations.

The reference pages are generated (``docs/generate.py``) from :data:`solver.keys.CASE_KEYS`,
:data:`study.campaign.CAMPAIGN_KEYS`, :mod:`solver.variables` and the argparse parser; these
tests check that every declared key and variable is on its page, that the parser accepts
exactly the declared keys, and that the whole guide builds offline without a warning.
"""

from __future__ import annotations

import importlib.util
import json
import re
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


def test_the_reference_pages_kept_in_the_repository_are_current(tmp_path):
    generate.write_all(tmp_path)
    stale = [
        page.name
        for page in sorted(tmp_path.iterdir())
        if not (kept := ROOT / "docs" / "reference" / page.name).exists()
        or kept.read_text() != page.read_text()
    ]
    assert not stale, f"{', '.join(stale)} differ from the code: run python docs/generate.py"


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
        "wear": ({}, "wear"),
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


@pytest.fixture(scope="module")
def built_guide(tmp_path_factory):
    """The guide built once for this module: (return code, stderr, html folder)."""
    pytest.importorskip("sphinx")
    pytest.importorskip("myst_parser")
    html = tmp_path_factory.mktemp("guide") / "html"
    done = subprocess.run(
        [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html", "docs",
         str(html)],
        capture_output=True, text=True, cwd=ROOT, timeout=600,
    )  # fmt: skip
    return done.returncode, done.stderr, html


def test_the_guide_builds_offline_with_warnings_as_errors(built_guide):
    returncode, stderr, html = built_guide
    assert returncode == 0, stderr[-3000:]
    assert (html / "reference" / "case-keys.html").exists()


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


# -- the gallery: every figure shown in the built guide, none older than its drawing code ------


def _script(name: str):
    """docs/NAME.py as a module (registered: its dataclasses need their module)."""
    spec = importlib.util.spec_from_file_location(f"docs_{name}", ROOT / "docs" / f"{name}.py")
    module = sys.modules[spec.name] = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


gallery = _script("gallery")
#: Figures the guide must show (issue 35): quickstart, load sweep, fretting, creep, own surface,
#: shakedown map.
REQUIRED_FIGURES = {
    "quickstart", "paper_load_sweep_load_curves", "paper_load_sweep_plastic_sections",
    "fretting_loop", "creep_curve", "your_surface", "shakedown_map_shakedown_map",
}  # fmt: skip


def test_the_gallery_has_every_example_and_the_required_report_figures():
    names = {figure.name for figure in gallery.FIGURES}
    examples = {p.stem for p in (ROOT / "examples").glob("*.py") if not p.stem.startswith("_")}
    assert examples <= names, sorted(examples - names)
    assert REQUIRED_FIGURES <= names, sorted(REQUIRED_FIGURES - names)


def test_every_gallery_figure_is_newer_than_the_code_that_draws_it():
    """By content: the manifest's sha256 of each figure's sources must match the files now."""
    stale = gallery.stale(gallery.read_manifest())
    message = [
        f"{name}: {'; '.join(reasons)}; regenerate with `python docs/gallery.py --only {name}`"
        for name, reasons in stale.items()
    ]
    assert not stale, "stale gallery figures (or `python docs/gallery.py --stale`):\n" + (
        "\n".join(message)
    )


def test_the_built_guide_shows_every_gallery_figure(built_guide):
    returncode, stderr, html = built_guide
    assert returncode == 0, stderr[-3000:]
    page = (html / "gallery.html").read_text()
    for figure in gallery.FIGURES:
        shown = html / "_images" / f"{figure.name}.png"
        assert f'src="_images/{figure.name}.png"' in page, figure.name
        assert shown.read_bytes() == (ROOT / "docs" / "gallery" / f"{figure.name}.png").read_bytes()


# -- stated times: only in the timings table (and the dated results pages) ---------------------
#: A time in seconds, minutes or hours ("3.4 s", "1 min 21 s", "about half a minute").
TIME = re.compile(
    r"(?<![\w.^/])\d[\d.,]*(?:\s?(?:-|to|and)\s?\d[\d.,]*)?\s?"
    r"(?:ms|s|secs?|seconds?|mins?|minutes?|h|hrs?|hours?)\b(?!\^)"
    r"|\b(?:half an?|an?|one)\s+(?:minute|hour)s?\b",
    re.I,
)
#: Pages of dated measurements, where times may stand: the generated tables (the timings table
#: among them), the benchmark, validation and run-times pages.  CHANGELOG.md is not checked.
TIMED_PAGES = {"docs/benchmarks.md", "docs/validation.md", "docs/run-times.md"}
#: Times that are settings, not measurements: (file, the words around the time).
NOT_MEASURED = {
    ("docs/howto/slurm.md", "default 60 s"),  # SLIPSTICK_TIME_RESERVE's default
    ("docs/howto/slurm.md", "for 4 hours"),  # a job's requested limit, in an example
}


def _stated_times():
    files = [ROOT / "README.md", *sorted((ROOT / "campaigns").glob("*.toml"))]
    files += sorted((ROOT / "examples").glob("*.py"))  # their docstrings say how to run them
    files += [
        path
        for path in sorted((ROOT / "docs").rglob("*.md"))
        if not {"_build", "reference", "tables"} & set(path.relative_to(ROOT / "docs").parts)
    ]
    for path in files:
        name = path.relative_to(ROOT).as_posix()
        if name in TIMED_PAGES:
            continue
        for number, line in enumerate(path.read_text().splitlines(), 1):
            if path.suffix == ".toml" and not line.lstrip().startswith("#"):
                continue  # only a campaign file's comments
            if any(name == where and words in line for where, words in NOT_MEASURED):
                continue
            for match in TIME.finditer(line):
                yield f"{name}:{number}: {match.group(0)!r} in: {line.strip()}"


def test_the_guard_finds_a_stated_time():
    for text in ("20 cases: 3.4 s", "in 1 min 21 s", "about half a minute", "42 min", "200 ms"):
        assert TIME.search(text), text
    for text in ("at 48^3", "steps of a/8", "1.5 a_H", "2 GPa", "10 steps", "n = 32 s_"):
        assert not TIME.search(text), text


def test_times_are_stated_only_in_the_timings_table():
    """README, campaign comments, examples and the guide link to docs/tables/timings.md."""
    found = list(_stated_times())
    assert not found, (
        "a time stated outside docs/tables/timings.md (measure it with `python docs/timings.py`"
        " and link to the table):\n" + "\n".join(found)
    )


def test_the_timings_table_is_written_from_its_record():
    timings = _script("timings")
    data = json.loads((ROOT / "docs" / "tables" / "timings.json").read_text())
    assert "quickstart" in data and data["quickstart"]["how"] == "docs/timings.py"
    assert (ROOT / "docs" / "tables" / "timings.md").read_text() == timings.render(data)
    for row in data.values():
        assert re.fullmatch(r"\d{4}-\d\d-\d\d", row["date"]), row


# -- the plastic-load-sweep how-to's open_fields snippet, run on its campaign -------------------


def test_the_plastic_load_sweep_how_to_opens_its_fields_as_written(tmp_path, monkeypatch):
    """The how-to's open_fields block runs as written on the how-to's campaign, coarsened.

    The campaign (the page's TOML block) keeps its axes with the first and last value of each
    (the smallest and largest load: boxes of different depths and cells) and 2 load steps.
    """
    import tomllib

    import numpy as np
    import xarray as xr

    pytest.importorskip("dask")
    pytest.importorskip("matplotlib")
    monkeypatch.setenv("MPLBACKEND", "Agg")
    from study.run.assemble import assemble_to_file
    from study.run.driver import RunOptions, run_campaign

    page = (ROOT / "docs" / "howto" / "plastic-load-sweep.md").read_text()
    (campaign_file,) = re.findall(r"```toml\n(.*?)```", page, re.S)
    snippets = [b for b in re.findall(r"```python\n(.*?)```", page, re.S) if "open_fields(" in b]
    assert len(snippets) == 1, "one python block of the how-to opens the fields"
    table = tomllib.loads(campaign_file)
    table["sweep"] = {key: [values[0], values[-1]] for key, values in table["sweep"].items()}
    table["base"]["load"]["steps"] = 2
    campaign = expand_campaign(table)
    out = Path("out") / campaign.name  # the folder `python -m study run` writes, as in the page
    assert f'"{out.as_posix()}"' in snippets[0]
    monkeypatch.chdir(tmp_path)
    assert run_campaign(campaign, out, options=RunOptions()).exit_status == 0
    namespace: dict = {}
    exec(compile(snippets[0], "docs/howto/plastic-load-sweep.md", "exec"), namespace)
    fields = namespace["fields"]
    try:
        strain = fields.plastic_strain.load()
        assert strain.sizes["p_h"] == 2 and strain.z.attrs["units"] == "m"
        assert strain.isel(p_h=0).isnull().any()  # the smaller load's box is the shallower
        with xr.open_dataset(assemble_to_file(out, campaign)) as assembled:  # no cell lost
            np.testing.assert_allclose(
                strain.max(("x", "y", "z")).transpose(*assembled.max_plastic_strain.dims),
                assembled.max_plastic_strain,
                rtol=1e-12,
            )
    finally:
        fields.close()
        import matplotlib.pyplot as plt

        plt.close("all")


@pytest.mark.parametrize("page", ["README.md", "docs/getting-started.md"])
def test_the_one_case_snippet_runs_as_written(page):
    """The "one case from Python" block solves its own case (no file to fetch first)."""
    text = (ROOT / page).read_text()
    (snippet,) = [b for b in re.findall(r"```python\n(.*?)```", text, re.S) if "Case.from" in b]
    namespace: dict = {}
    exec(compile(snippet, page, "exec"), namespace)
    assert namespace["result"].converged and "pressure" in namespace["ds"]
