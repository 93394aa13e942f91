"""Campaign files: expansion, zip, aliases, Dundurs beta, and one clear message per bad file."""

import json
import os
import subprocess
import sys

import pytest
from study_fixtures import CATTANEO_BASE, NORMAL_BASE, small_campaign, write

import solver
from solver.materials import Body
from study.campaign import (
    Campaign,
    CampaignError,
    beta_range,
    body1_for_beta,
    load_campaign,
)
from study.cli import main

RIGID_BASE = NORMAL_BASE.replace(
    'body1 = { behaviour = "elastic", radius = 0.01, E = 210e9, nu = 0.3 }',
    'body1 = { behaviour = "rigid", radius = 0.01 }',
)


def test_product_zip_alias_and_order(tmp_path):
    campaign = load_campaign(small_campaign(tmp_path))
    assert campaign.name == "small"
    assert campaign.dims == ("mu", "mesh") and campaign.shape == (2, 2)
    mesh = campaign.axes[1]
    assert mesh.zipped and [c.name for c in mesh.coordinates] == ["grid_n", "load_steps"]
    assert len(campaign.cases) == 4
    # C order over the axes, coordinates and specs follow the swept values
    assert [c.index for c in campaign.cases] == [(0, 0), (0, 1), (1, 0), (1, 1)]
    last = campaign.cases[-1]
    assert last.coords == {"mu": 0.2, "grid_n": 32, "load_steps": 3}
    assert last.spec["grid"]["n"] == [32, 32]
    assert last.spec["load"]["path"][0]["steps"] == 3
    assert last.spec["friction"]["coefficient"] == 0.2
    assert last.case_id == solver.Case.from_dict(last.spec).case_id
    assert len({c.case_id for c in campaign.cases}) == 4
    # JSON round trip (what OUT/campaign.json holds)
    again = Campaign.from_dict(json.loads(json.dumps(campaign.to_dict())))
    assert again == campaign


def test_index_syntax_reaches_a_path_stage(tmp_path):
    text = (
        '[sweep]\n"load.path[1].tangential_force" = [5.0, 20.0]\n'
        '"load.path.0.normal_force" = [100.0, 120.0]\n' + CATTANEO_BASE
    )
    campaign = load_campaign(write(tmp_path, text))
    stages = campaign.cases[-1].spec["load"]["path"]
    assert stages[1]["tangential_force"] == [20.0, 0.0]
    assert stages[0]["normal_force"] == 120.0
    assert campaign.dims == ("load_path_1_tangential_force", "load_path_0_normal_force")
    assert campaign.axes[0].coordinates[0].units == "N"


def test_flat_zip_is_one_dimension_named_by_joining(tmp_path):
    text = '[zip]\n"grid.n" = [24, 32, 48]\ngrid.half_width = [1.5, 1.6, 1.7]\n' + NORMAL_BASE
    campaign = load_campaign(write(tmp_path, text))
    assert campaign.dims == ("grid_n__grid_half_width",)
    assert [c.spec["grid"]["half_width"] for c in campaign.cases] == [1.5, 1.6, 1.7]


@pytest.mark.parametrize("beta", [-0.14, -0.1, 0.0, 0.05, 0.2])
def test_beta_rule_hits_beta_and_keeps_composite_modulus(tmp_path, beta):
    text = f'[sweep]\n"materials.dundurs_beta" = [{beta}]\n' + NORMAL_BASE
    case = load_campaign(write(tmp_path, text)).cases[0].case()
    assert case.pair.dundurs_beta == pytest.approx(beta, abs=1e-12)
    assert case.pair.composite_modulus == pytest.approx(210e9 / (2 * 0.91), rel=1e-12)
    assert case.body2 == Body("elastic", case.body2.radius_x, case.body2.radius_y, 210e9, 0.3)


def test_beta_range_and_inversion():
    steel = Body("elastic", E=210e9, nu=0.3)
    low, high = beta_range(steel, steel)
    assert low == pytest.approx(-0.26 / 1.82) and high == pytest.approx((0.75 * 0.91 - 0.26) / 1.82)
    young, nu = body1_for_beta(low, steel, steel)
    assert nu == pytest.approx(0.5) and young == pytest.approx(0.75 / (0.91 / 210e9))
    assert body1_for_beta(0.0, steel, steel) == pytest.approx((210e9, 0.3))
    # rigid body 2: beta = (1 - 2 nu1) / (2 (1 - nu1)) in [0, 3/4)
    assert beta_range(steel, Body("rigid")) == pytest.approx((0.0, 0.75))
    with pytest.raises(ValueError, match=r"not reachable.*\[-0\.1429, 0\.2321\)"):
        body1_for_beta(-0.3, steel, steel)


# -- bad campaign files: one clear message each, exit status 2 -----------------------------------
SWEEP_MU = '[sweep]\n"friction.coefficient" = [0.1, 0.2]\n'
BAD = {
    "unknown table": ("[sweeps]\na = 1\n" + SWEEP_MU + NORMAL_BASE, "[sweeps]: unknown table"),
    "case table at top": (
        SWEEP_MU + NORMAL_BASE + "[grid]\nn = 3\n",
        "case tables go under [base]",
    ),
    "missing base": (SWEEP_MU, "[base]: missing"),
    "nothing to sweep": (NORMAL_BASE, "nothing to sweep"),
    "empty sweep table": ("[sweep]\n" + NORMAL_BASE, "[sweep]: empty"),
    "empty list": ('[sweep]\n"friction.coefficient" = []\n' + NORMAL_BASE, "empty list"),
    "not a list": ('[sweep]\n"friction.coefficient" = 0.1\n' + NORMAL_BASE, "must be a list"),
    "unknown first segment": (
        '[sweep]\n"frction.coefficient" = [0.1]\n' + NORMAL_BASE,
        'unknown case table "frction"',
    ),
    "unknown key": (
        '[sweep]\n"friction.coeficient" = [0.1]\n' + NORMAL_BASE,
        "friction.coeficient: unknown key",
    ),
    "unknown materials key": (
        '[sweep]\n"materials.dundurs_alpha" = [0.1]\n' + NORMAL_BASE,
        "unknown materials key",
    ),
    "wrong value type": (
        '[sweep]\n"friction.coefficient" = ["high", "low"]\n' + NORMAL_BASE,
        "friction.coefficient: must be a number",
    ),
    "mixed types": (
        '[sweep]\n"friction.coefficient" = [0.1, "a"]\n' + NORMAL_BASE,
        "mixed value types",
    ),
    "duplicate values": (
        '[sweep]\n"friction.coefficient" = [0.1, 0.10]\n' + NORMAL_BASE,
        "appears twice",
    ),
    "nan value": ('[sweep]\n"friction.coefficient" = [nan]\n' + NORMAL_BASE, "nan is not"),
    "list values": ('[sweep]\n"grid.n" = [[32, 32]]\n' + NORMAL_BASE, "must be numbers"),
    "impossible beta": (
        '[sweep]\n"materials.dundurs_beta" = [0.0, 0.5]\n' + NORMAL_BASE,
        "materials.dundurs_beta = 0.5 is not reachable",
    ),
    "beta with rigid body 1": (
        '[sweep]\n"materials.dundurs_beta" = [0.1]\n' + RIGID_BASE,
        "needs an elastic body1",
    ),
    "beta with body1.E swept": (
        '[sweep]\n"materials.dundurs_beta" = [0.1]\n"body1.E" = [1e11]\n' + NORMAL_BASE,
        "do not sweep them as well",
    ),
    "duplicate axis sweep and zip": (
        '[sweep]\n"grid.n" = [24, 32]\n[zip]\n"grid.n" = [24, 32]\n"load.steps" = [1, 2]\n'
        + NORMAL_BASE,
        "duplicate axis",
    ),
    "duplicate axis by index syntax": (
        '[sweep]\n"load.path[1].steps" = [1, 2]\n"load.path.1.steps" = [1, 2]\n' + CATTANEO_BASE,
        "duplicate axis",
    ),
    "overlapping axes": (
        '[sweep]\n"load.path.1" = [1, 2]\n"load.path.1.steps" = [1, 2]\n' + CATTANEO_BASE,
        "overlapping axes",
    ),
    "zip length mismatch": (
        '[zip]\n"grid.n" = [24, 32]\n"load.steps" = [1, 2, 3]\n' + NORMAL_BASE,
        "same length",
    ),
    "alias of an unswept key": (
        SWEEP_MU + '[alias]\n"grid.n" = "cells"\n' + NORMAL_BASE,
        "not a swept key",
    ),
    "alias not an identifier": (
        SWEEP_MU + '[alias]\n"friction.coefficient" = "friction coefficient"\n' + NORMAL_BASE,
        "must be an identifier",
    ),
    "alias reserved": (
        SWEEP_MU + '[alias]\n"friction.coefficient" = "status"\n' + NORMAL_BASE,
        "reserved",
    ),
    "alias collision": (
        '[sweep]\n"friction.coefficient" = [0.1]\n"grid.n" = [24]\n'
        '[alias]\n"friction.coefficient" = "a"\n"grid.n" = "a"\n' + NORMAL_BASE,
        'duplicate axis name "a"',
    ),
    "index out of range": (
        '[sweep]\n"load.path.5.steps" = [1, 2]\n' + CATTANEO_BASE,
        "index 5 is out of range",
    ),
    "index into a table": ('[sweep]\n"load.0.steps" = [1, 2]\n' + NORMAL_BASE, "not an array"),
    "single-stage key on a path": (
        '[sweep]\n"load.hertz_pressure" = [1e9]\n' + CATTANEO_BASE,
        "address a stage",
    ),
    "invalid case names it": (
        '[sweep]\n"grid.n" = [24, 8]\n' + NORMAL_BASE,
        "case 2 of 2 (grid_n=8): grid.n: mesh too coarse",
    ),
    "gross sliding names the stage": (
        '[sweep]\n"load.path.1.tangential_force" = [10.0, 40.0]\n' + CATTANEO_BASE,
        "load.path[1].tangential_force: |Q| = 40 N reaches mu W",
    ),
    "not TOML": ('[sweep\n"friction.coefficient" = [0.1]\n' + NORMAL_BASE, "not valid TOML"),
    "bad setting value": ("[campaign]\nfft_threads = 0\n" + SWEEP_MU + NORMAL_BASE, "fft_threads"),
    "unknown setting": ("[campaign]\ncolour = 1\n" + SWEEP_MU + NORMAL_BASE, "unknown setting"),
    "bad fields": (
        '[campaign]\nfields = ["stress"]\n' + SWEEP_MU + NORMAL_BASE,
        "campaign.fields",
    ),
    "bad zip group name": (
        '[zip.bad-name]\n"grid.n" = [24]\n"load.steps" = [1]\n' + NORMAL_BASE,
        "identifier",
    ),
}


@pytest.mark.parametrize("name", list(BAD))
def test_bad_campaign_one_message_exit_2(tmp_path, capsys, name):
    text, expected = BAD[name]
    path = write(tmp_path, text)
    assert main(["validate", str(path)]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    assert captured.err.startswith("error: ") and captured.err.count("\n") == 1, captured.err
    assert expected in captured.err, captured.err
    assert "Traceback" not in captured.err


def test_missing_file_and_bad_options(tmp_path, capsys):
    assert main(["validate", str(tmp_path / "nope.toml")]) == 2
    assert "no such campaign file" in capsys.readouterr().err
    assert main(["run", str(small_campaign(tmp_path)), "--time-limit", "-1"]) == 2
    assert "--time-limit" in capsys.readouterr().err


def test_validate_prints_summary(tmp_path, capsys):
    assert main(["validate", str(small_campaign(tmp_path))]) == 0
    out = capsys.readouterr().out
    assert "4 cases" in out and "mu = friction.coefficient" in out
    assert "estimated cost per case" in out and "MiB" in out and out.strip().endswith("valid")


def test_validate_command_needs_no_mpi(tmp_path):
    good, bad = small_campaign(tmp_path), write(tmp_path, SWEEP_MU, "bad.toml")
    code = (
        "import sys; from study.cli import main; rc = main(sys.argv[1:]); "
        "assert 'mpi4py' not in sys.modules, 'mpi4py imported'; sys.exit(rc)"
    )
    ok = subprocess.run([sys.executable, "-c", code, "validate", str(good)], capture_output=True)
    assert ok.returncode == 0, ok.stderr.decode()
    failed = subprocess.run(
        [sys.executable, "-m", "study", "validate", str(bad)], capture_output=True, text=True
    )
    assert failed.returncode == 2
    assert failed.stderr.strip() == "error: [base]: missing; give the base case table " + (
        "(body1, body2, load, ...)"
    )


def test_campaigns_shipped_are_valid():
    from pathlib import Path

    folder = Path(__file__).resolve().parent.parent / "campaigns"
    for name in ("quickstart", "convergence_hertz", "convergence_cattaneo"):
        campaign = load_campaign(folder / f"{name}.toml")
        assert campaign.name == name and len(campaign.cases) >= 10


def test_campaign_error_is_a_value_error():
    assert issubclass(CampaignError, ValueError)


def test_cli_limits_blas_threads_before_numpy_loads():
    code = (
        "import sys, os; import study, study.cli; assert 'numpy' not in sys.modules; "
        "study.cli._single_threaded_blas(); print(os.environ['OPENBLAS_NUM_THREADS'])"
    )
    env = {k: v for k, v in os.environ.items() if "NUM_THREADS" not in k}
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env)
    assert done.returncode == 0 and done.stdout.strip() == "1", done.stderr
