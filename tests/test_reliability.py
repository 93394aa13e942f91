"""Reliability of the study framework and the normal solver on inputs that used to break them.

Corrupt case files, a CG restarted at its own solution, an infinite case timeout, non-regular
campaign files, another campaign in the output folder, stale temporaries, a full disk.
"""

import errno
import json
import logging
import os
import subprocess
import sys

import h5py
import netCDF4
import numpy as np
import pytest
import xarray as xr
from study_fixtures import small_campaign, write

import solver
from study import bundle
from study.campaign import CampaignError, load_campaign
from study.cli import main
from study.run import storage
from study.run.assemble import STATUS_FLAGS, assemble
from study.run.driver import RunOptions, run_campaign
from study.run.progress import LOGGER_NAME


@pytest.fixture(autouse=True)
def _restore_study_logger():
    """The CLI binds the ``study`` logger to this test's captured stdout: undo that after."""
    logger = logging.getLogger(LOGGER_NAME)
    saved = (list(logger.handlers), logger.level, logger.propagate)
    yield
    logger.handlers[:], logger.level, logger.propagate = saved


@pytest.fixture
def small_run(tmp_path):
    """The 4-case campaign, run once, each case written as its own bundle (about 0.5 s)."""
    path = small_campaign(tmp_path)
    campaign = load_campaign(path)
    out = tmp_path / "out"
    assert run_campaign(campaign, out, options=RunOptions(bundle_seconds=0)).exit_status == 0
    return path, campaign, out


def _dead_pid() -> int:
    child = subprocess.Popen([sys.executable, "-c", "pass"])
    child.wait()
    return child.pid


# -- 1. corrupt bundles and case files -----------------------------------------------------------
def _bundles(out, campaign) -> list:
    """The bundle of each case, in campaign order (one case per bundle here)."""
    index = storage.case_index(out)
    files = [index.results[case.case_id][0].path for case in campaign.cases]
    assert len(set(files)) == len(files)
    return files


def _damage(out, campaign):
    """Truncate one bundle, overwrite one, strip the marker of one; returns the four files."""
    files = _bundles(out, campaign)
    truncated, garbage, unmarked, good = files
    truncated.write_bytes(truncated.read_bytes()[: truncated.stat().st_size // 2])
    garbage.write_bytes(b"\x89HDF garbage" * 300)
    with h5py.File(unmarked, "a") as handle:  # complete, but no marker
        del handle.attrs[storage.COMPLETE_ATTR]
    corrupt = storage.corrupt_ids(out)
    assert set(corrupt) == {truncated.name, garbage.name, unmarked.name}
    assert "does not open" in corrupt[truncated.name]
    assert "completion marker" in corrupt[unmarked.name]
    assert storage.finished_ids(out) == {campaign.cases[3].case_id}
    return files


def test_corrupt_bundles_are_named_by_status_assemble_report(small_run, capsys):
    _, campaign, out = small_run
    assert main(["assemble", str(out)]) == 0  # a dataset assembled while the files were good
    *bad, good = _damage(out, campaign)
    capsys.readouterr()
    # report (on a dataset assembled from the good files), status, assemble: one line per
    # damaged bundle, no traceback, the rest goes on
    assert main(["report", str(out), "--no-plots"]) == 0
    assert main(["status", str(out)]) == 0
    assert main(["assemble", str(out)]) == 0
    captured = capsys.readouterr()
    text = captured.out + captured.err
    assert "Traceback" not in text
    for file in bad:
        assert captured.out.count(f"corrupt bundle cases/{file.name}:") == 1  # status
        assert text.count(f"corrupt bundle cases/{file.name}") == 3  # report, assemble too
    assert "1/4 finished (1 converged, 0 not converged), 0 failed, 3 pending" in captured.out
    with xr.open_dataset(storage.dataset_path(out, "small")) as ds:
        assert int((ds.status == STATUS_FLAGS["pending"]).sum()) == 3
        assert int((ds.status == STATUS_FLAGS["converged"]).sum()) == 1
    assert sorted(storage.corrupt_ids(out)) == sorted(f.name for f in bad)  # nothing moved


def test_run_moves_corrupt_bundles_aside_and_recomputes(small_run, capsys):
    path, campaign, out = small_run
    *bad, good = _damage(out, campaign)
    capsys.readouterr()
    assert main(["run", str(path), "--out", str(out), "--mpi", "off"]) == 0
    log = capsys.readouterr().out
    for file in bad:
        assert f"moved to cases/{file.name}.corrupt, computing its cases again" in log
        assert file.with_name(file.name + storage.CORRUPT_SUFFIX).exists()
    assert "1 finished earlier, 3 to run" in log and "this run 3 converged" in log
    assert "0 pending, 0 failed in all" in log and "Traceback" not in log
    assert storage.finished_ids(out) == {case.case_id for case in campaign.cases}
    assert not storage.corrupt_ids(out)
    assert (assemble(out).status == STATUS_FLAGS["converged"]).all()


def test_case_files_of_older_versions_are_read_and_quarantined(small_run, capsys):
    """A folder of per-case files (before bundles): read as before, a damaged one recomputed."""
    path, campaign, out = small_run
    reference = assemble(out)
    good, garbage = campaign.cases[0].case_id, campaign.cases[1].case_id
    for case_id in (good, garbage):  # the case as its own netCDF file, marked complete
        file = storage.case_path(out, case_id)
        storage.write_netcdf(storage.open_case(out, case_id), file)
        with netCDF4.Dataset(file, "a") as handle:
            handle.setncattr(storage.COMPLETE_ATTR, np.int8(1))
    for file in _bundles(out, campaign)[:2]:
        file.unlink()
    storage.case_path(out, garbage).write_bytes(b"\x89HDF garbage" * 300)
    assert set(storage.corrupt_ids(out)) == {garbage}
    assert storage.case_states(out, campaign)[good] == "converged"
    ds = assemble(out)
    assert int((ds.status == STATUS_FLAGS["failed"]).sum()) == 1
    assert ds.error.values.ravel()[1].startswith(f"corrupt case file cases/{garbage}.nc")
    xr.testing.assert_identical(
        ds.drop_attrs().isel(mu=0, mesh=0), reference.drop_attrs().isel(mu=0, mesh=0)
    )
    assert main(["run", str(path), "--out", str(out), "--mpi", "off"]) == 0
    assert (
        "moved to cases/" + garbage + ".nc.corrupt, computing it again" in capsys.readouterr().out
    )
    assert (assemble(out).status == STATUS_FLAGS["converged"]).all()


# -- 2. a CG started at its own solution ---------------------------------------------------------
G, NU = 200e6, 0.42
SOFT = {"behaviour": "elastic", "E": 2 * G * (1 + NU), "nu": NU}


def _regrip_table(body1, force, goodman=False):
    """Sphere R = 50 mm on a soft half-space, normal load, then Q = 7/8 mu W in 10 steps."""
    return {
        "body1": {"radius": 0.05, **body1},
        "body2": {"radius": "inf", **SOFT},
        "load": {
            "path": [
                {"normal_force": force, "steps": 1},
                {"tangential_force": [7 / 8 * 0.4 * force, 0.0], "steps": 10},
            ]
        },
        "friction": {"coefficient": 0.4},
        "grid": {"n": 32, "half_width": 1.5},
        "solver": {"goodman": goodman},
    }


@pytest.mark.parametrize(
    "table",
    [
        _regrip_table(SOFT, 1.0),  # identical bodies: beta = 0
        _regrip_table({"behaviour": "rigid"}, 1000.0, goodman=True),  # beta ignored
    ],
    ids=["identical-bodies", "rigid-goodman"],
)
def test_normal_resolve_at_the_solution_is_converged(table):
    case = solver.Case.from_dict(table)
    assert case.pair.dundurs_beta == 0.0 or case.solver.goodman
    result = solver.solve(case)
    assert result.status == "converged", result.notes
    assert np.all(result.history["step_converged"] == 1)


# -- 3. case_timeout = inf -----------------------------------------------------------------------
@pytest.mark.parametrize("value", ["inf", "1e300", "nan", "0"])
def test_unusable_case_timeout_is_refused(tmp_path, capsys, value):
    text = small_campaign(tmp_path).read_text()
    text = text.replace('name = "small"', f'name = "small"\ncase_timeout = {value}')
    path = write(tmp_path, text, "timeout.toml")
    with pytest.raises(CampaignError, match=r"campaign\.case_timeout: .*\(0, 1e\+07\]"):
        load_campaign(path)
    assert main(["validate", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.count("error: ") == 1 and "campaign.case_timeout" in err
    assert main(["run", str(small_campaign(tmp_path)), "--case-timeout", value]) == 2
    assert "--case-timeout: must be a number of seconds in (0, 1e+07]" in capsys.readouterr().err


def test_largest_case_timeout_is_accepted(tmp_path):
    text = small_campaign(tmp_path).read_text()
    text = text.replace('name = "small"', 'name = "small"\ncase_timeout = 1e7')
    campaign = load_campaign(write(tmp_path, text, "timeout.toml"))
    summary = run_campaign(campaign, tmp_path / "out")
    assert summary.converged == 4 and summary.failed == 0


# -- 4. non-regular campaign files ---------------------------------------------------------------
@pytest.mark.parametrize("command", ["validate", "run"])
def test_fifo_campaign_file_is_refused(tmp_path, command):
    fifo = tmp_path / "campaign.toml"
    os.mkfifo(fifo)
    argv = [sys.executable, "-m", "study", command, str(fifo)]
    done = subprocess.run(argv, capture_output=True, text=True, timeout=60, cwd=tmp_path)
    assert done.returncode == 2, done.stdout + done.stderr
    assert done.stderr.strip() == f"error: {fifo}: is a FIFO, expected a campaign file (.toml)"


def test_device_campaign_file_is_refused(capsys):
    assert main(["validate", os.devnull]) == 2
    assert main(["status", os.devnull]) == 2
    err = capsys.readouterr().err
    assert err.count(f"error: {os.devnull}: is a character device") == 2


# -- 5. another campaign in the output folder ----------------------------------------------------
def test_other_campaign_into_output_is_refused_unless_replace(small_run, tmp_path, capsys):
    _, campaign, out = small_run
    text = small_campaign(tmp_path).read_text().replace('name = "small"', 'name = "other"')
    other = write(tmp_path, text, "other.toml")
    before = (out / "campaign.json").read_text()
    argv = ["run", str(other), "--out", str(out), "--mpi", "off", "--no-assemble"]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("error: ") == 1
    assert "holds campaign 'small'" in err and "campaign 'other'" in err and "--replace" in err
    assert (out / "campaign.json").read_text() == before
    with pytest.raises(CampaignError, match="holds campaign 'small'"):
        run_campaign(load_campaign(other), out)
    # the same campaign again is fine; --replace takes the folder over (shared cases reused)
    assert run_campaign(campaign, out).skipped == 4
    assert main([*argv, "--replace"]) == 0
    assert "4 finished earlier, 0 to run" in capsys.readouterr().out
    assert json.loads((out / "campaign.json").read_text())["name"] == "other"
    assert (
        "--replace"
        in subprocess.run(
            [sys.executable, "-m", "study", "run", "--help"], capture_output=True, text=True
        ).stdout
    )


# -- 6. stale temporaries ------------------------------------------------------------------------
def test_stale_temporaries_are_ignored_and_cleaned(small_run, capsys):
    path, campaign, out = small_run
    dead, alive = _dead_pid(), os.getpid()
    case_id = campaign.cases[0].case_id
    stale = [out / f"small.nc.tmp{dead}", storage.cases_dir(out) / f"{case_id}.nc.tmp{dead}"]
    live = storage.cases_dir(out) / f"{case_id}.nc.tmp{alive}"
    for file in (*stale, live):
        file.write_bytes(b"half a netCDF file")
    assert main(["status", str(out)]) == 0
    assert "4/4 finished (4 converged" in capsys.readouterr().out
    assert not any(file.exists() for file in stale) and live.exists()
    stale[0].write_bytes(b"half a netCDF file")
    assert main(["assemble", str(out)]) == 0
    assert not stale[0].exists() and live.exists()
    with xr.open_dataset(storage.dataset_path(out, "small")) as ds:
        assert (ds.status == STATUS_FLAGS["converged"]).all()
    stale[1].write_bytes(b"half a netCDF file")
    assert run_campaign(campaign, out).skipped == 4  # run cleans too, but not a live process's
    assert not stale[1].exists() and live.exists()


# -- 7. disk full --------------------------------------------------------------------------------
def _disk_full(*args, **kwargs):
    raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))


def test_disk_full_is_reported_and_counted(tmp_path, monkeypatch, capsys):
    path = small_campaign(tmp_path)
    out = tmp_path / "out"
    # campaign.json fits; then no bundle (results or failure records) and no dataset does
    monkeypatch.setattr(bundle, "write_bundle", _disk_full)
    monkeypatch.setattr(storage, "write_netcdf", _disk_full)
    argv = ["run", str(path), "--out", str(out), "--mpi", "off", "--max-initial-failures", "0"]
    assert main(argv) == 1
    captured = capsys.readouterr()
    text = captured.out + captured.err
    assert "Traceback" not in text and "Permission denied" not in text
    assert "python -m study status" not in text  # no pointer to records that were never written
    assert text.count("no failure record was written") == 4
    assert "result not written to cases/" in text and "no space left on device" in text
    assert "this run 0 converged, 0 not converged, 4 failed" in text
    assert "0 pending, 4 failed in all" in text
    assert "assembly of" in text and "failed: no space left on device" in text
    assert not list(storage.cases_dir(out).iterdir())


def test_full_disk_behind_an_hdf_error_reads_no_space(small_run, monkeypatch):
    _, campaign, out = small_run
    write_bundle = bundle.write_bundle

    def hdf_error(path, entries, shared):  # what HDF5 raises on ENOSPC; failure records fit
        if all(entry.status == "failed" for entry in entries):
            return write_bundle(path, entries, shared)
        raise PermissionError(errno.EACCES, "Permission denied")

    monkeypatch.setattr(bundle, "write_bundle", hdf_error)
    monkeypatch.setattr(storage, "free_bytes", lambda folder: 0)
    for file in storage.cases_dir(out).iterdir():
        file.unlink()
    summary = run_campaign(campaign, out)
    assert summary.failed == 4 and summary.failed_total == 4 and summary.exit_status == 1
    errors = [storage.read_failure(out, i)["error"] for i in sorted(storage.failed_ids(out))]
    assert len(errors) == 4
    for error in errors:
        assert error.startswith("CaseWriteError: result not written to cases/")
        assert "no space left on device (0 bytes free" in error
        # the HDF5 library's own word is quoted as its report, not as the cause
        assert "the HDF5 library reported it as 'PermissionError" in error
    # a real permission problem, with space left, stays a permission problem
    monkeypatch.setattr(storage, "free_bytes", lambda folder: 1 << 40)
    summary = run_campaign(campaign, out, options=RunOptions(max_initial_failures=1))
    assert summary.failed == 4 and summary.failed_total == 4
    errors = [storage.read_failure(out, i)["error"] for i in storage.failed_ids(out)]
    assert all("Permission denied" in e and "no space" not in e for e in errors)
