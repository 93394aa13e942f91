"""Run under ``mpiexec -n 2 python -m pytest -m mpi``: the campaign driver on two ranks."""

import numpy as np
import pytest
from study_fixtures import CATTANEO_BASE, NORMAL_BASE, mixed_campaign, small_campaign, write

import solver
from study.campaign import CampaignError, load_campaign
from study.run import storage
from study.run.driver import RunOptions, broadcast_campaign, run_campaign

pytestmark = pytest.mark.mpi


@pytest.fixture
def comm():
    """A duplicate of COMM_WORLD (the driver never names COMM_WORLD itself)."""
    from mpi4py import MPI

    comm = MPI.COMM_WORLD.Dup()
    if comm.Get_size() < 2:
        pytest.skip("run with mpiexec -n 2")
    yield comm
    comm.Free()


@pytest.fixture
def shared(comm, tmp_path):
    """A folder every rank sees: rank 0's tmp_path."""
    return type(tmp_path)(comm.bcast(str(tmp_path) if comm.Get_rank() == 0 else None))


def load(comm, path_on_root):
    return broadcast_campaign(lambda spread: load_campaign(path_on_root, spread=spread), comm)


def test_dynamic_distribution_costliest_first(comm, shared):
    if comm.Get_rank() == 0:
        mixed_campaign(shared)
    comm.Barrier()
    campaign = load(comm, shared / "mixed.toml")
    order = []

    def solve(case):
        order.append(case.case_id)
        return solver.solve(case)

    summary = run_campaign(campaign, shared / "out", comm, RunOptions(solve=solve))
    everyone = comm.allgather(order)
    assert summary.exit_status == 0 and summary.converged == 8
    assert sum(len(o) for o in everyone) == 8 and all(everyone)  # every rank computed
    assert summary.per_rank == {r: len(o) for r, o in enumerate(everyone)}
    costliest = sorted(campaign.cases, key=lambda c: -c.cost)[: comm.Get_size()]
    assert {o[0] for o in everyone} == {c.case_id for c in costliest}
    assert comm.allgather(summary.describe()) == [summary.describe()] * comm.Get_size()


def test_failures_isolated_across_ranks(comm, shared):
    if comm.Get_rank() == 0:
        small_campaign(shared)
    comm.Barrier()
    campaign = load(comm, shared / "small.toml")

    def solve(case):
        if case.friction_coefficient == 0.2 and case.grid.nx == 32:
            raise RuntimeError(f"injected on rank {comm.Get_rank()}")
        return solver.solve(case)

    summary = run_campaign(campaign, shared / "out", comm, RunOptions(solve=solve))
    assert summary.failed == 1 and summary.converged == 3 and summary.exit_status == 1
    if comm.Get_rank() == 0:
        (case_id,) = storage.failed_ids(shared / "out")
        record = storage.read_failure(shared / "out", case_id)
        assert record["error"] == f"RuntimeError: injected on rank {record['rank']}"
        assert "Traceback" in record["traceback"]


def test_early_stop_reaches_every_rank(comm, shared):
    if comm.Get_rank() == 0:
        mixed_campaign(shared)
    comm.Barrier()
    campaign = load(comm, shared / "mixed.toml")

    def solve(case):
        raise RuntimeError("always")

    options = RunOptions(solve=solve, max_initial_failures=3)
    summary = run_campaign(campaign, shared / "out", comm, options)
    assert "all failed" in summary.stopped and summary.exit_status == 1
    assert 3 <= summary.failed <= 3 + comm.Get_size() - 1 and summary.pending > 0


def test_same_results_whatever_the_number_of_ranks(comm, shared):
    if comm.Get_rank() == 0:
        mixed_campaign(shared)
    comm.Barrier()
    campaign = load(comm, shared / "mixed.toml")
    run_campaign(campaign, shared / "parallel", comm)
    message = ""
    if comm.Get_rank() == 0:
        from mpi4py import MPI

        run_campaign(campaign, shared / "serial", MPI.COMM_SELF)
        for case in campaign.cases:
            with (
                storage.open_case(shared / "parallel", case.case_id) as a,
                storage.open_case(shared / "serial", case.case_id) as b,
            ):
                assert a.attrs["case_spec"] == b.attrs["case_spec"]
                assert a.attrs["status"] == b.attrs["status"]
                for name in ("pressure", "shear_x", "shear_y"):
                    scale = np.abs(b[name].values).max()
                    if not np.allclose(a[name], b[name], rtol=0, atol=1e-9 * scale):
                        message += f"{case.case_id} {name} differs; "
                assert (a.contact_state.values == b.contact_state.values).all()
    assert comm.bcast(message) == ""


def test_bad_campaign_stops_every_rank_with_one_message(comm, shared):
    if comm.Get_rank() == 0:
        write(shared, '[sweep]\n"grid.n" = [24, 8]\n' + NORMAL_BASE, "bad.toml")
    comm.Barrier()
    with pytest.raises(CampaignError) as info:
        load(comm, shared / "bad.toml")
    messages = comm.allgather(str(info.value))
    assert messages == [messages[0]] * comm.Get_size()
    assert messages[0].startswith("case 2 of 2 (grid_n=8): grid.n: mesh too coarse")


def _spread_table(half_widths: list[float]) -> dict:
    """20 Latin-hypercube cases over the load on each window (half of them refused at 1.0)."""
    sample = {"method": "lhs", "count": 20, "seed": 5}
    sample["load.normal_force"] = {"distribution": "log-uniform", "range": [10.0, 1000.0]}
    return {
        "campaign": {"name": "spread", "fields": []},
        "base": {
            "body1": {"behaviour": "elastic", "radius": 0.01, "E": 210e9, "nu": 0.3},
            "body2": {"behaviour": "rigid"},
            "load": {"normal_force": 100.0},
            "grid": {"n": 24},
        },
        "sweep": {"grid.half_width": half_widths},
        "sample": sample,
    }


def test_every_rank_builds_a_share_of_the_cases(comm, monkeypatch):
    """The campaign built a share per rank equals the one built alone, errors included."""
    from study.campaign import expand_campaign
    from study.campaign.expand import Expansion
    from study.run import driver

    monkeypatch.setattr(driver, "MIN_RANK_CASES", 5)
    built = []
    part = Expansion.part

    def counted(self, k, n, progress=None):
        built.append((k, n))
        return part(self, k, n, progress)

    monkeypatch.setattr(Expansion, "part", counted)
    table = _spread_table([1.5, 1.2])
    campaign = broadcast_campaign(lambda spread: expand_campaign(table, spread=spread), comm)
    assert built == [(comm.Get_rank(), comm.Get_size())]
    assert campaign == expand_campaign(table)  # built alone on every rank
    bad = _spread_table([1.5, 1.0])  # the last share's cases are refused
    with pytest.raises(CampaignError) as alone:
        expand_campaign(bad)
    with pytest.raises(CampaignError) as spread:
        broadcast_campaign(lambda spread: expand_campaign(bad, spread=spread), comm)
    assert str(spread.value) == str(alone.value) and "case 21 of 40" in str(alone.value)


def test_one_case_campaign_runs_restarts_and_reports(comm, shared):
    """A campaign file without [sweep], [zip] or [sample] is its base case: no axes."""
    if comm.Get_rank() == 0:
        write(shared, '[campaign]\nname = "one"\n' + CATTANEO_BASE, "one.toml")
    comm.Barrier()
    campaign = load(comm, shared / "one.toml")
    assert campaign.axes == () and len(campaign.cases) == 1 and campaign.shape == ()
    first = run_campaign(campaign, shared / "out", comm)
    again = run_campaign(campaign, shared / "out", comm)  # a restart: nothing left to do
    assert (first.converged, first.skipped) == (1, 0) and first.exit_status == 0
    assert (again.converged, again.skipped, again.pending) == (0, 1, 0)
    if comm.Get_rank() == 0:
        import xarray as xr

        from study.report import build_report
        from study.run.assemble import assemble_to_file

        with xr.open_dataset(assemble_to_file(shared / "out")) as dataset:
            assert dataset.max_pressure.dims == () and dataset.stick_radius.dims == ()
            direct = solver.solve(campaign.cases[0].case())  # the same case, outside the study
            assert float(dataset.max_pressure) == pytest.approx(direct.pressure.max(), rel=1e-12)
        text = build_report(shared / "out").read_text()
        assert "- axes: none (a campaign of one case" in text and "- cases: 1 (" in text
