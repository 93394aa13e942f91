"""The README is the front door: at most 250 lines, and its quickstart runs as written.

The quickstart section's shell block (``mpiexec -n 2 python -m study run
campaigns/quickstart.toml``, then ``status``) and every Python block of the section run
verbatim in a scratch folder holding the campaign file, the way a new user pastes them; the
Python blocks read what the shell block wrote.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text()
#: The fenced blocks of the README's "## Quickstart" section (up to the next "## " heading).
QUICKSTART = README.split("\n## Quickstart", 1)[-1].split("\n## ", 1)[0]
BLOCKS = re.findall(r"```(\w+)\n(.*?)```", QUICKSTART, flags=re.S)
#: A case file for the "one case from Python" snippet (it reads case.toml).
CASE_TOML = """
[body1]
radius = 0.015
behaviour = "rigid"
[body2]
radius = "inf"
behaviour = "elastic"
E = 210e9
nu = 0.3
[load]
hertz_pressure = 1e9
[grid]
n = 32
"""


def test_readme_is_at_most_250_lines():
    assert len(README.splitlines()) <= 250


def test_the_quickstart_and_python_snippets_run_verbatim(tmp_path):
    pytest.importorskip("matplotlib")
    if shutil.which("mpiexec") is None:
        pytest.skip("no mpiexec on PATH")
    shell = [code for lang, code in BLOCKS if lang == "bash" and "quickstart.toml" in code]
    python = [code for lang, code in BLOCKS if lang == "python"]
    assert len(shell) == 1 and python, "the README lost its quickstart"
    (tmp_path / "campaigns").mkdir()
    shutil.copy(ROOT / "campaigns" / "quickstart.toml", tmp_path / "campaigns")
    (tmp_path / "case.toml").write_text(CASE_TOML)
    done = subprocess.run(
        ["bash", "-euo", "pipefail", "-c", shell[0]],
        capture_output=True, text=True, cwd=tmp_path, timeout=900,
    )  # fmt: skip
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-2000:]
    assert "finished" in done.stdout
    for code in python:
        done = subprocess.run(
            [sys.executable, "-c", code], capture_output=True, text=True, cwd=tmp_path,
            timeout=900, env=os.environ | {"MPLBACKEND": "Agg"},
        )  # fmt: skip
        assert done.returncode == 0, code + done.stderr[-2000:]
    assert (tmp_path / "out" / "quickstart" / "quickstart.nc").exists()


def test_the_readme_picture_is_a_gallery_figure():
    """The front door's picture is one of the gallery's (docs/gallery.py keeps it current)."""
    images = re.findall(r"!\[[^\]]*\]\(([^)\s]+)\)", README)
    assert images, "the README lost its picture"
    for image in images:
        assert image.startswith("docs/gallery/") and (ROOT / image).is_file(), image


def test_every_row_of_the_feature_table_links_its_measurement():
    table = README.split("\n## What it does", 1)[1].split("\n## ", 1)[0]
    rows = [line for line in table.splitlines() if line.startswith("| ") and "---" not in line]
    assert len(rows) >= 6, "the feature table lost rows"
    for row in rows[1:]:
        links = re.findall(r"\]\((docs/(?:validation|benchmarks)\.md[^)]*)\)", row)
        assert len(links) == 1, row
        assert (ROOT / links[0].split("#")[0]).is_file(), row
