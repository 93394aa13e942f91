"""The bit-identity check of refactors (``python -m study.bench.identical``) finds differences."""

from __future__ import annotations

import json

import numpy as np

from study.bench import identical


def test_compare_passes_on_the_same_code_and_fails_on_one_changed_bit(tmp_path, capsys):
    only, campaigns = ["quickstart.last"], ["quickstart"]  # all campaigns: ~1 min a run
    assert identical.run(tmp_path, save=True, only=only, campaigns=campaigns) == 0
    assert identical.run(tmp_path, save=False, only=only, campaigns=campaigns) == 0
    assert "differing: none" in capsys.readouterr().out

    path = tmp_path / "quickstart.last.npz"
    with np.load(path) as saved:
        arrays = dict(saved)
    key = "var:pressure"
    flat = arrays[key].reshape(-1).copy()
    flat[np.argmax(flat)] = np.nextafter(flat.max(), np.inf)  # one ulp on one cell
    arrays[key] = flat.reshape(arrays[key].shape)
    np.savez(path, **arrays)
    assert identical.run(tmp_path, save=False, only=only, campaigns=campaigns) == 1
    assert key in capsys.readouterr().out


def test_compare_fails_on_a_changed_case_id(tmp_path, capsys):
    only, campaigns = ["no scene has this name"], ["quickstart", "fretting_ii"]
    assert identical.run(tmp_path, save=True, only=only, campaigns=campaigns) == 0
    cases = json.loads((tmp_path / "cases.json").read_text())
    assert set(cases) == set(campaigns)
    cases["quickstart"][0]["case_id"] = "0" * 16
    (tmp_path / "cases.json").write_text(json.dumps(cases))
    assert identical.run(tmp_path, save=False, only=only, campaigns=campaigns) == 1
    assert "quickstart[0].case_id" in capsys.readouterr().out
    # the saved check of every campaign, compared on some of them, compares those only
    assert identical.run(tmp_path, save=False, only=only, campaigns=["fretting_ii"]) == 0


def test_an_unknown_campaign_is_refused(tmp_path, capsys):
    assert (
        identical.run(tmp_path, save=True, only=["none"], campaigns=["quickstart", "nosuch"]) == 2
    )
    assert "no shipped campaign ['nosuch']" in capsys.readouterr().out
    assert not (tmp_path / "cases.json").exists()
