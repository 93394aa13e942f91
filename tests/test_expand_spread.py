"""A campaign expanded in shares (worker processes, MPI ranks) is the campaign expanded in one.

The reference is the expansion in a single process: the spread one must give equal cases (ids,
tables, costs, memory, work, order) and the same error for the same bad case, whichever share
builds it, also when a worker dies.
"""

from __future__ import annotations

import subprocess
import sys

import pytest

from study.campaign import CampaignError, expand_campaign
from study.campaign import parallel as parallel_module
from study.campaign.expand import Expansion, serial
from study.campaign.parallel import processes

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
    """Workers for a small campaign: 2 processes from 20 cases, shares of 7 cases."""
    monkeypatch.setattr(parallel_module, "MIN_CASES", 10)
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
