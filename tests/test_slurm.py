"""Integration test of the Slurm scripts (``slurm/``) against a real one-node Slurm cluster.

Debian's ``slurm-wlm`` and ``munge`` are installed with apt-get when missing (root only; the test
is skipped otherwise) and started on 127.0.0.1 with 2 CPUs (:mod:`slurm_cluster`).  Then:

- a small campaign through ``slurm/campaign.sbatch`` on 2 ranks (srun --mpi=pmi2);
- a campaign whose first job reaches its (1 minute) time limit with cases pending, resubmitted:
  the second job finishes it without recomputing a finished case, and the dataset equals an
  uninterrupted run.  The first job's cases take a known 8 s (the ``SLIPSTICK_TEST_CASE_SECONDS``
  hook of ``study.cli``) and its reserve leaves a 16 s window, so exactly the first wave (one
  case per rank) runs, on any machine; the other cases take ~0.4 s;
- the same small campaign as a 3-task job array with a dependent merge/assemble job
  (``slurm/submit.sh --slices 3``).

47 s on 2 cores (README, section Slurm).  Run with ``python -m pytest -m slurm
tests/test_slurm.py`` (without ``-m slurm`` or SLIPSTICK_SLURM_TESTS=1 the cluster tests are
skipped: they may install packages).
"""

from __future__ import annotations

import importlib.util
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parent))

import study_fixtures  # noqa: E402
from slurm_cluster import SlurmCluster, SlurmUnavailable, ensure_installed  # noqa: E402

pytestmark = pytest.mark.slurm

REPO = Path(__file__).resolve().parents[1]
SBATCH = REPO / "slurm" / "campaign.sbatch"
SUBMIT = REPO / "slurm" / "submit.sh"

#: 12 coupled slip-stick cases (friction with beta != 0) of equal estimated cost, ~0.4 s each
#: on one core (16^2 cells, 20 steps).
SLOW_CAMPAIGN = """
[campaign]
name = "slow"
max_initial_failures = 0

[base.body1]
behaviour = "elastic"
radius = 0.01
E = 210e9
nu = 0.3

[base.body2]
behaviour = "elastic"
radius = "inf"
E = 210e9
nu = 0.3

[base.load]
hertz_pressure = 1.5e9
steps = 20

[base.grid]
n = 16
half_width = 1.5

[sweep]
"friction.coefficient" = [0.2, 0.3, 0.4]
"materials.dundurs_beta" = [-0.12, -0.06, 0.06, 0.12]

[alias]
"friction.coefficient" = "friction_coefficient"
"materials.dundurs_beta" = "dundurs_beta"
"""

#: Compared exactly (rtol 1e-9) with an uninterrupted run: discrete or closed-form results.
EXACT = (
    "status",
    "case_id",
    "steps",
    "normal_force",
    "contact_area",
    "contact_radius",
    "stick_radius",
    "stick_area_history",
    "coupling_iterations",
    "hertz_radius",
    "hertz_pressure",
    "hertz_approach",
    "composite_modulus",
    "step_converged_history",
)
#: Compared to 1e-3 of their largest value: pyfftw plans with FFTW_MEASURE (timing-dependent),
#: so two runs of one case differ by rounding, which the slip-stick loop amplifies to ~3e-4 in
#: the peak pressure (iteration counts, residuals and the ~0 tangential force differ more).
CLOSE = ("max_pressure", "pressure_profile", "approach", "max_pressure_history")


@pytest.fixture(scope="module")
def cluster(request, tmp_path_factory):
    """A running one-node Slurm cluster (daemons stopped by pid at the end).

    Only when asked for (``-m slurm`` or SLIPSTICK_SLURM_TESTS=1): it may apt-get install Slurm.
    """
    if "slurm" not in (request.config.getoption("markexpr") or "") and not os.environ.get(
        "SLIPSTICK_SLURM_TESTS"
    ):
        pytest.skip("Slurm integration test: select it with -m slurm (or SLIPSTICK_SLURM_TESTS=1)")
    try:
        ensure_installed()
    except SlurmUnavailable as error:
        pytest.skip(f"no Slurm: {error}")
    if importlib.util.find_spec("mpi4py") is None:
        pytest.skip("mpi4py is not installed")
    cluster = SlurmCluster(tmp_path_factory.mktemp("slurm"), cpus=2)
    try:
        cluster.start()
    except SlurmUnavailable as error:
        cluster.stop()
        pytest.skip(f"cannot start a local Slurm cluster: {error}")
    yield cluster
    cluster.stop()


@pytest.fixture(scope="module")
def job_env():
    """Environment of the submissions: this interpreter runs the study."""
    return {"SLIPSTICK_PYTHON": sys.executable}


def _status(out: Path) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "study", "status", str(out)],
        cwd=REPO,
        capture_output=True,
        text=True,
        timeout=120,
    )


def _case_files(out: Path) -> dict[str, tuple[int, int]]:
    """case id -> (inode, mtime in ns) of the file (bundle) holding every finished case."""
    from study.run import storage

    stats = {
        case_id: location.path.stat()
        for case_id, (location, _) in storage.case_index(out).results.items()
    }
    return {case_id: (stat.st_ino, stat.st_mtime_ns) for case_id, stat in stats.items()}


def _job_log(cluster: SlurmCluster, path: Path) -> str:
    text = path.read_text(errors="replace") if path.exists() else f"(no {path})"
    return f"\n--- job output {path}\n{text}{cluster.logs()}"


def _dataset(path: Path):
    import xarray as xr

    with xr.open_dataset(path) as ds:
        return ds.load()


def _assert_same_results(a, b) -> None:
    """Two assembled datasets hold the same results (to the solver's reproducibility)."""
    assert set(a.data_vars) == set(b.data_vars)
    assert a.sizes == b.sizes
    for name in a.coords:
        np.testing.assert_array_equal(a[name].values, b[name].values, err_msg=name)
    for name in EXACT:
        x, y = a[name].values, b[name].values
        if x.dtype.kind in "fc":
            np.testing.assert_allclose(x, y, rtol=1e-9, atol=0, equal_nan=True, err_msg=name)
        else:
            np.testing.assert_array_equal(x, y, err_msg=name)
    for name in CLOSE:
        x, y = a[name].values, b[name].values
        scale = float(np.nanmax(np.abs(y)))
        np.testing.assert_allclose(x, y, rtol=0, atol=1e-3 * scale, equal_nan=True, err_msg=name)


def test_campaign_job(cluster, job_env, tmp_path):
    """A small campaign on 2 ranks: COMPLETED, every case converged, one log per job."""
    campaign = study_fixtures.small_campaign(tmp_path)
    out = tmp_path / "out"
    output = tmp_path / "job-%j.out"
    job = cluster.sbatch(
        "--ntasks=2", "--time=5", f"--output={output}", str(SBATCH), str(campaign), str(out),
        cwd=REPO, env=job_env,
    )  # fmt: skip
    log = Path(str(output).replace("%j", job))
    assert cluster.wait(job, 240) == "COMPLETED", _job_log(cluster, log)
    text = log.read_text()
    assert "2 task(s) x 1 FFT thread(s)" in text
    assert "done: every case finished" in text
    assert (out / "logs" / f"{job}.0.log").exists()
    ds = _dataset(out / "small.nc")
    assert (ds.status.values == 1).all()
    # the rank recorded for each case is the rank that computed it: the dataset's counts per
    # rank are the job summary's "(rank 0: i, rank 1: j)", i + j = 4 cases over 2 tasks
    match = re.search(r"\((rank \d+: \d+(?:, rank \d+: \d+)*)\); overhead", text)
    assert match, text
    logged = {int(r): int(n) for r, n in re.findall(r"rank (\d+): (\d+)", match.group(1))}
    ranks, counts = np.unique(ds.mpi_rank.values, return_counts=True)
    assert dict(zip(ranks.tolist(), counts.tolist(), strict=True)) == logged
    assert set(logged) <= {0, 1} and sum(logged.values()) == 4
    from study.run import storage

    for case_id, rank in zip(ds.case_id.values.ravel(), ds.mpi_rank.values.ravel(), strict=True):
        with storage.open_case(out, case_id) as case:
            assert case.attrs["rank"] == rank, case_id
    status = _status(out)
    assert status.returncode == 0 and "4/4 finished" in status.stdout, status.stdout


def test_time_limit_then_resubmit(cluster, job_env, tmp_path):
    """Job 1 stops at its time limit with cases pending; job 2 finishes without redoing any."""
    campaign = study_fixtures.write(tmp_path, SLOW_CAMPAIGN, "slow.toml")
    out = tmp_path / "out"
    first_log = tmp_path / "first-%j.out"
    # Job 1: Slurm's time limit --time=1 (60 s, the job's real end time) less a 44 s reserve
    # leaves a 16 s window, and every case takes 8 s (test hook).  The first wave (one case per
    # rank) starts when the run is up within the window; when it ends, >= 8 s of it are gone and
    # the next case is predicted to take 1.25 x 8 = 10 s > 16 - 8 s left: none starts, exit 3.
    first = cluster.sbatch(
        "--ntasks=2", "--time=1", f"--output={first_log}", str(SBATCH), str(campaign), str(out),
        cwd=REPO,
        env={**job_env, "SLIPSTICK_TIME_RESERVE": "44", "SLIPSTICK_TEST_CASE_SECONDS": "8"},
    )  # fmt: skip
    first_log = Path(str(first_log).replace("%j", first))
    state = cluster.wait(first, 240)
    info = cluster.job_info(first)
    text = first_log.read_text()
    # exit status 3: stopped by the time limit with cases pending (not killed by Slurm)
    assert state == "FAILED" and info.get("ExitCode") == "3:0", _job_log(cluster, first_log)
    assert "time limit: cases pending" in text
    run_log = (out / "logs" / f"{first}.0.log").read_text()
    assert "too little for the 10 remaining case(s)" in run_log, run_log[-3000:]
    assert not list(out.glob("**/*.tmp*")), "a temporary file was left behind"
    before = _case_files(out)
    assert len(before) == 2, f"{len(before)} cases finished by job 1 (one per rank expected)"
    status = _status(out)
    assert f"{len(before)}/12 finished" in status.stdout, status.stdout
    assert f"{12 - len(before)} pending" in status.stdout, status.stdout
    partial = _dataset(out / "slow.nc")
    assert int((partial.status.values == 0).sum()) == 12 - len(before)

    second_log = tmp_path / "second-%j.out"
    second = cluster.sbatch(
        "--ntasks=2", "--time=5", f"--output={second_log}", str(SBATCH), str(campaign), str(out),
        cwd=REPO, env={**job_env, "SLIPSTICK_TIME_RESERVE": "0"},
    )  # fmt: skip
    second_log = Path(str(second_log).replace("%j", second))
    assert cluster.wait(second, 300) == "COMPLETED", _job_log(cluster, second_log)
    after = _case_files(out)
    assert len(after) == 12
    for case_id, stamp in before.items():
        assert after[case_id] == stamp, f"case {case_id} was recomputed by the second job"
    log = (out / "logs" / f"{second}.0.log").read_text()
    assert f"{len(before)} finished earlier, {12 - len(before)} to run" in log

    reference = tmp_path / "reference"
    done = subprocess.run(
        [sys.executable, "-m", "study", "run", str(campaign), "--out", str(reference)]
        + ["--mpi", "off"],
        cwd=REPO,
        capture_output=True,
        text=True,
        timeout=600,
        env={**os.environ, "OMP_NUM_THREADS": "1"},
    )
    assert done.returncode == 0, done.stderr[-3000:]
    resumed, uninterrupted = _dataset(out / "slow.nc"), _dataset(reference / "slow.nc")
    assert (resumed.status.values == 1).all()
    _assert_same_results(resumed, uninterrupted)


def test_job_array_and_merge(cluster, job_env, tmp_path):
    """submit.sh --slices 3: three array tasks with disjoint slices, then merge + assemble."""
    campaign = study_fixtures.small_campaign(tmp_path)
    out = tmp_path / "out"
    done = cluster.run(
        [str(SUBMIT), "--slices", "3", str(campaign), str(out), "--ntasks=1", "--time=5"],
        cwd=tmp_path,  # the scripts must not depend on the submission folder
        env=job_env,
    )
    assert done.returncode == 0, done.stderr
    array, merge = done.stdout.split()
    assert cluster.wait(array, 240) == "COMPLETED", cluster.logs()
    assert cluster.wait(merge, 120) == "COMPLETED", _job_log(
        cluster, out / "logs" / f"slurm-slipstick-merge-{merge}.out"
    )
    slices = [set(_case_files(out / "slices" / str(k))) for k in range(3)]
    assert all(slices), "every slice has cases (4 cases over 3 slices)"
    assert sum(len(s) for s in slices) == 4 and set.union(*slices) == set(_case_files(out))
    ds = _dataset(out / "small.nc")
    assert (ds.status.values == 1).all()
    status = _status(out)
    assert status.returncode == 0 and "4/4 finished" in status.stdout, status.stdout

    # resubmitting the same command finds nothing to do and merges again
    done = cluster.run(
        [str(SUBMIT), "--slices", "3", str(campaign), str(out), "--ntasks=1", "--time=5"],
        cwd=tmp_path,
        env=job_env,
    )
    array, merge = done.stdout.split()
    assert cluster.wait(array, 240) == "COMPLETED", cluster.logs()
    assert cluster.wait(merge, 120) == "COMPLETED", cluster.logs()
    assert (out / "logs" / f"merge-{merge}.log").read_text().startswith("merged 0 new")


def test_scripts_are_valid_bash():
    """bash -n on every script (shellcheck, when installed, is the linters' job)."""
    for script in (SBATCH, SUBMIT, REPO / "slurm" / "merge.sbatch"):
        subprocess.run(["bash", "-n", str(script)], check=True)
