"""A campaign expanded in shares (worker processes, MPI ranks) is the campaign expanded in one.

The reference is the expansion in a single process: the spread one must give equal cases (ids,
tables, costs, memory, work, order) and the same error for the same bad case, whichever share
builds it, also when a worker dies.  And a case of a batch (its table the base copied on write,
its shared sub-tables parsed once) is the case built alone from a deep copy.
"""

from __future__ import annotations

import copy
import hashlib
import json
import subprocess
import sys

import pytest

import solver
from solver.case.batch import SharedTables, case_hash
from study.campaign import CampaignError, expand_campaign
from study.campaign import parallel as parallel_module
from study.campaign.expand import Expansion, serial
from study.campaign.model import BETA_KEY
from study.campaign.parallel import processes
from study.campaign.validate import _apply_beta, _value, assign

BASE = {
    "body1": {"behaviour": "elastic", "radius": 0.01, "E": 210e9, "nu": 0.3},
    "body2": {"behaviour": "elastic", "radius": "inf", "E": 210e9, "nu": 0.3},
    "load": {"normal_force": 100.0},
    "grid": {"n": [16, 16]},
}


def _table(count: int = 60, sweep: dict | None = None) -> dict:
    """A Latin hypercube over load and friction, swept over two grids (2 count cases)."""
    return {
        "campaign": {"name": "spread", "fields": []},
        "base": BASE,
        "sweep": sweep or {"grid.n": [16, 24]},
        "sample": {
            "method": "lhs",
            "count": count,
            "seed": 3,
            "load.normal_force": {"distribution": "log-uniform", "range": [10.0, 1000.0]},
            "friction.coefficient": {"distribution": "uniform", "range": [0.0, 0.5]},
        },
    }


@pytest.fixture
def small_shares(monkeypatch):
    """Workers for a small campaign: shares of 7 cases, a worker worth starting for any."""
    monkeypatch.setattr(parallel_module, "WORKER_SECONDS", 1e-9)
    monkeypatch.setattr(parallel_module, "SHARE", 7)


def test_parts_join_to_the_whole_expansion():
    campaign = expand_campaign(_table())
    expansion = Expansion(campaign.base, campaign.axes, {}, None)
    whole = expansion.cases(serial(expansion, None))
    for n in (2, 3, 17, len(whole), len(whole) + 5):  # more shares than cases: empty shares
        parts = [expansion.part(k, n) for k in range(n)]
        assert sum(len(found) for found, _ in parts) == len(whole)
        assert expansion.cases(parts) == whole == campaign.cases


def test_worker_processes_give_the_same_cases(small_shares):
    alone = expand_campaign(_table())
    spread = expand_campaign(_table(), spread=processes(2))
    assert spread == alone
    assert [c.work for c in spread.cases] == [c.work for c in alone.cases]
    assert [c.number for c in spread.cases] == list(range(len(alone.cases)))


def test_a_bad_case_in_a_workers_share_gives_the_same_error(small_shares):
    """A window of 1 a_H cannot hold the contact: the second half of the cases, all refused."""
    bad = {"grid.half_width": [1.5, 1.0]}
    with pytest.raises(CampaignError) as alone:
        expand_campaign(_table(sweep=bad))
    with pytest.raises(CampaignError) as spread:
        expand_campaign(_table(sweep=bad), spread=processes(2))
    assert str(spread.value) == str(alone.value)
    text = str(alone.value)
    assert text.startswith("case 61 of 120") and "(and 59 more of 120 cases)" in text, text


def test_a_worker_that_dies_costs_time_not_the_result(small_shares, monkeypatch):
    def dying():
        return subprocess.Popen(
            [sys.executable, "-c", "import sys; sys.stdin.buffer.read(1); sys.exit(3)"],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
        )

    monkeypatch.setattr(parallel_module, "_start", dying)
    assert expand_campaign(_table(), spread=processes(3)) == expand_campaign(_table())


def test_a_small_campaign_starts_no_worker(monkeypatch):
    def refuse():
        raise AssertionError("a worker was started for a small campaign")

    monkeypatch.setattr(parallel_module, "_start", refuse)
    assert expand_campaign(_table(count=8), spread=processes(4)) == expand_campaign(_table(count=8))


def test_no_worker_when_the_first_share_says_the_rest_is_quick(monkeypatch):
    def refuse():
        raise AssertionError("a worker was started for shares quicker than its start-up")

    monkeypatch.setattr(parallel_module, "_start", refuse)
    monkeypatch.setattr(parallel_module, "SHARE", 7)  # 17 shares of 120 cases
    monkeypatch.setattr(parallel_module, "WORKER_SECONDS", 1e9)
    assert expand_campaign(_table(), spread=processes(4)) == expand_campaign(_table())


# -- a batch of cases from one base (copy on write, SharedTables) ----------------------------------
def _mixed_table() -> dict:
    """Sweeps that change a body key, a whole body (by name), the grid, Dundurs' beta, a solver
    key and the output, and a path stage by index, on a sampled load and friction."""
    return {
        "campaign": {"name": "mixed", "fields": []},
        "base": {
            **BASE,
            "grid": {"n": [16, 16, 8]},
            "load": {"path": [{"normal_force": 100.0, "steps": 2}]},
            "solver": {"fft_threads": 1},
            "output": {"fields": []},
        },
        "define": {
            "flat": {"behaviour": "elastic", "radius": "inf", "E": 210e9, "nu": 0.3},
            "soft": {"behaviour": "elastic", "radius": "inf", "E": 70e9, "nu": 0.33},
            "few": {"fields": []},
            "more": {"fields": ["stress"]},
        },
        "sweep": {
            "body2": ["flat", "soft"],
            "grid.nz": [8, 10],
            "materials.dundurs_beta": [-0.1, 0.0],
            "solver.slip_tolerance": [1e-6, 1e-7],
            "output": ["few", "more"],
        },
        "sample": {
            "method": "lhs",
            "count": 3,
            "seed": 5,
            "load.path.0.normal_force": {"distribution": "log-uniform", "range": [10.0, 1e3]},
            "friction.coefficient": {"distribution": "uniform", "range": [0.1, 0.5]},
        },
    }


def _alone(expansion: Expansion, case) -> solver.Case:
    """A campaign case built on its own: the base deep-copied, its coordinates set, no sharing."""

    table, beta = copy.deepcopy(expansion.base), None
    for axis, i in zip(expansion.axes, case.index, strict=True):
        for c in axis.coordinates:
            if c.key == BETA_KEY:
                beta = float(c.values[i])
            else:
                assign(table, c.key, copy.deepcopy(_value(c.key, c.values[i], expansion.defined)))
    if beta is not None:
        _apply_beta(table, beta)
    return solver.Case.from_dict(table)


def test_a_batch_builds_every_case_as_it_is_built_alone():
    table = _mixed_table()
    campaign = expand_campaign(table)
    expansion = Expansion.of(campaign.base, campaign.axes, table["define"])
    base = copy.deepcopy(expansion.base)
    assert len(campaign.cases) == 2**5 * 3
    for case in expansion.cases(serial(expansion, None)):
        alone = _alone(expansion, case)
        assert (case.case_id, case.spec) == (alone.case_id, alone.spec)
        assert case.warnings == alone.warnings
        assert case.case().fields == alone.fields and case.case().solver == alone.solver
    assert expansion.base == base  # copied on write: the base is left as it was


def test_the_case_id_is_the_hash_of_the_sorted_json_of_its_table():
    shared = SharedTables()
    campaign = expand_campaign(_mixed_table())
    for c in campaign.cases[:12]:
        spec = json.loads(json.dumps(c.spec))  # fresh tables: nothing shared
        spec["solver"] = {k: v for k, v in spec["solver"].items() if not k.startswith("fft_")}
        text = json.dumps(spec, sort_keys=True, separators=(",", ":"))
        expected = hashlib.sha256(text.encode()).hexdigest()[:16]
        case = solver.Case.from_dict(c.spec, None, shared)
        assert c.case_id == case.case_id == solver.Case.from_dict(c.spec).case_id == expected
        assert case_hash(case.spec) == case_hash(case.spec, shared.text) == expected


def test_shared_tables_keep_no_failed_parse():
    shared = SharedTables()
    bad = {**BASE, "body1": {**BASE["body1"], "E": -1.0}}
    for _ in range(2):  # refused each time, not taken from a cache
        with pytest.raises(solver.SpecError, match="body1.E"):
            solver.Case.from_dict(bad, None, shared)
    good = {**bad, "body1": BASE["body1"]}
    assert solver.Case.from_dict(good, None, shared) == solver.Case.from_dict(good)


def test_the_collector_is_paused_while_a_campaign_is_built_and_sent():
    import gc

    from study.run.driver import broadcast_campaign

    seen = []
    assert gc.isenabled()
    broadcast_campaign(lambda spread: seen.append(gc.isenabled()))
    assert seen == [False] and gc.isenabled()
