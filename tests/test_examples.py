"""The example scripts run and draw their figure; each checks itself against a closed form."""

import pathlib
import subprocess
import sys

import pytest

EXAMPLES = pathlib.Path(__file__).parent.parent / "examples"
SCRIPTS = sorted(p.stem for p in EXAMPLES.glob("*.py") if not p.stem.startswith("_"))


def test_every_example_is_listed_in_the_guide():
    listed = (EXAMPLES.parent / "docs" / "examples.md").read_text()
    assert len(SCRIPTS) >= 4
    assert all(f"examples/{name}.py" in listed for name in SCRIPTS)


@pytest.mark.parametrize("name", SCRIPTS)
def test_example_runs_and_draws_its_figure(name, tmp_path):
    """Exit status 0 means the script's own check against its closed form passed."""
    run = subprocess.run(
        [sys.executable, str(EXAMPLES / f"{name}.py"), "--out", str(tmp_path)],
        capture_output=True,
        text=True,
        cwd=tmp_path,
    )
    assert run.returncode == 0, run.stdout + run.stderr
    assert "Traceback" not in run.stderr
    figure = tmp_path / f"{name}.png"
    assert figure.stat().st_size > 10_000  # a drawn figure, not an empty canvas
