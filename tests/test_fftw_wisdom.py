"""Measured FFT plans saved per machine (``solver.fft_planner = "wisdom"``): reproducible bits.

Issue 22, item 2: the plans are measured once (rank 0, first run on a machine), saved in the
cache folder and imported by every rank; results are bit-identical between runs and between
one and two ranks, and equal to the estimate plans' results to round-off.
"""

import os
import shutil
import subprocess
import sys

import numpy as np
import pytest
import xarray as xr
from study_fixtures import write

import solver
from solver.drive.operators import CaseOperators
from solver.numerics import fftw
from study.run import storage, wisdom

PLASTIC = """
[campaign]
name = "planned"

[base]
body1 = { behaviour = "rigid", radius = 0.015 }
load = { hertz_pressure = 5e9, steps = 3 }
grid = { n = [16, 16, 12] }
solver = { fft_planner = "wisdom" }

[base.body2]
behaviour = "elastic-plastic"
radius = "inf"
E = 210e9
nu = 0.3
hardening = { law = "linear", yield_stress = 1.3579e9, modulus = 152.3e9 }

[sweep]
"friction.coefficient" = [0.0, 0.3]
"""


def _table(planner: str) -> dict:
    return {
        "body1": {"behaviour": "rigid", "radius": 0.015},
        "body2": {
            "behaviour": "elastic-plastic",
            "radius": "inf",
            "E": 210e9,
            "nu": 0.3,
            "hardening": {"law": "linear", "yield_stress": 1.3579e9, "modulus": 152.3e9},
        },
        "load": {"hertz_pressure": 5e9, "steps": 2},
        "grid": {"n": [16, 16, 12]},
        "solver": {"fft_planner": planner},
    }


def test_wisdom_without_wisdom_is_the_estimate_plan_to_the_bit():
    fftw.forget_wisdom()
    estimate = solver.solve(solver.Case.from_dict(_table("estimate")))
    planned = solver.solve(solver.Case.from_dict(_table("wisdom")))
    assert planned.status == estimate.status == "converged"
    np.testing.assert_array_equal(planned.pressure, estimate.pressure)
    np.testing.assert_array_equal(
        planned.fields["plastic_strain"], estimate.fields["plastic_strain"]
    )


def test_measured_plans_are_found_in_the_wisdom(tmp_path, monkeypatch):
    """The plan pass covers the volume operator's transforms: with its wisdom imported, a
    ``"wisdom"`` operator takes measured plans (no estimate fallback) and the file round-trips."""
    monkeypatch.setenv(wisdom.CACHE_ENV, str(tmp_path))
    fftw.forget_wisdom()
    case = solver.Case.from_dict(_table("wisdom"))
    saved = wisdom.prepare([case])
    assert wisdom.wisdom_file().exists() and wisdom.load()["wisdom"] == saved
    assert wisdom.load()["planned"] == [wisdom._plan_key(case)]
    fftw.forget_wisdom()
    fftw.import_wisdom(wisdom.load()["wisdom"])
    operator = CaseOperators.build(case).volume(2)[1]
    for depth, plans in operator._volume_plans()[0].items():  # each piece of layers' plans
        for name in ("x", "y", "-x", "-y"):
            assert "FFTW_WISDOM_ONLY" in plans[name].flags, (depth, name)  # a hit, no estimate
    for rows, depth in operator._workers()[0].plans.items():  # the row blocks' z transforms
        for name, z_plan in depth.items():
            assert "FFTW_WISDOM_ONLY" in z_plan.flags, (rows, name)
    fftw.forget_wisdom()


MPIEXEC = shutil.which("mpiexec")


def _run(path, out, env, ranks=1):
    command = [sys.executable, "-m", "study", "run", str(path), "--out", str(out)]
    if ranks > 1:
        command = [MPIEXEC, "-n", str(ranks), *command]
    done = subprocess.run(command, capture_output=True, text=True, env=env, timeout=300)
    assert done.returncode == 0, done.stdout + done.stderr
    return done.stdout + done.stderr


@pytest.mark.skipif(MPIEXEC is None, reason="needs mpiexec")
def test_saved_plans_give_the_same_bits_between_runs_and_ranks(tmp_path):
    path = write(tmp_path, PLASTIC)
    env = {k: v for k, v in os.environ.items() if not k.startswith(("PMI_", "PMIX_", "OMPI_"))}
    env[wisdom.CACHE_ENV] = str(tmp_path / "cache")
    first = _run(path, tmp_path / "first", env)
    assert "measuring the FFT plans" in first  # first run on this machine: measured, saved
    files = list((tmp_path / "cache" / "fftw").glob("*.json"))
    assert len(files) == 1
    saved = files[0].read_bytes()
    again = _run(path, tmp_path / "again", env)
    two = _run(path, tmp_path / "two", env, ranks=2)
    assert "measuring" not in again + two  # the saved plans serve every later run and rank
    assert files[0].read_bytes() == saved
    datasets = [
        xr.open_dataset(storage.dataset_path(tmp_path / name, "planned"))
        for name in ("first", "again", "two")
    ]
    try:
        for ds in datasets:
            assert (ds.status == 1).all()  # converged
        assert set(np.unique(datasets[2].mpi_rank.values)) == {0, 1}
        for ds in datasets[1:]:
            for name in ("max_plastic_strain", "residual_depth", "max_pressure"):
                np.testing.assert_array_equal(ds[name].values, datasets[0][name].values)
    finally:
        for ds in datasets:
            ds.close()


def test_machine_key_without_pyfftw_metadata(monkeypatch):
    """pyFFTW installed without package metadata: the same key, from the module's version."""
    import importlib.metadata

    key = wisdom.machine_key()

    def missing(name):
        raise importlib.metadata.PackageNotFoundError(name)

    monkeypatch.setattr(importlib.metadata, "version", missing)
    assert wisdom.machine_key() == key
