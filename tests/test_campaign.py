"""Campaign files: expansion, zip, aliases, Dundurs beta, and one clear message per bad file."""

import dataclasses
import itertools
import json
import os
import subprocess
import sys

import pytest
from study_fixtures import CATTANEO_BASE, NORMAL_BASE, small_campaign, write

import solver
from solver.bodies.materials import Body
from study.campaign import (
    Campaign,
    CampaignError,
    beta_range,
    body1_for_beta,
    load_campaign,
)
from study.campaign.model import CASE_COLUMNS, spec_changes, with_changes
from study.cli import main
from study.run.storage import campaign_text

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
    # JSON round trip (what OUT/campaign.json holds: one line per case)
    text = campaign_text(campaign.to_dict())
    assert Campaign.from_dict(json.loads(text)) == campaign
    lines = [line for line in text.splitlines() if line.startswith("  [")]
    assert len(lines) == len(campaign.cases)
    # a case records the tables its spec changes from the first case's
    rows = json.loads(text)["cases"]
    changed = [set(row[CASE_COLUMNS.index("changes")]) for row in rows]
    assert changed == [set(), {"load", "grid"}, {"friction"}, {"friction", "load", "grid"}]


def test_campaign_records_of_the_first_format_are_still_read(tmp_path):
    """A folder written before the rows (format /1: a table per case, whole specs) reads alike."""
    campaign = load_campaign(small_campaign(tmp_path))
    record = campaign.to_dict()
    record["format"] = "slipstick-campaign/1"
    record["cases"] = [
        {
            "number": c.number,
            "index": list(c.index),
            "coords": c.coords,
            "case_id": c.case_id,
            "cost": c.cost,
            "memory": c.memory,
            "warnings": list(c.warnings),
            "work": dataclasses.asdict(c.work),
            "spec": json.loads(json.dumps(c.spec)),
        }
        for c in campaign.cases
    ]
    read = Campaign.from_dict(json.loads(json.dumps(record)))
    assert read == campaign
    assert [c.work for c in read.cases] == [c.work for c in campaign.cases]
    record["format"] = "slipstick-campaign/9"
    with pytest.raises(CampaignError, match="format 'slipstick-campaign/9'"):
        Campaign.from_dict(record)


def test_spec_changes_undo_to_the_spec():
    """Changed, added and missing tables all come back; unchanged tables are the reference's."""
    reference = {"a": {"x": 1}, "b": {"y": [1, 2]}, "c": {"z": 3}}
    spec = {"a": {"x": 1}, "b": {"y": [1, 3]}, "d": {"w": 0}}
    changes = spec_changes(spec, reference)
    assert changes == {"b": {"y": [1, 3]}, "d": {"w": 0}, "c": None}
    back = with_changes(reference, json.loads(json.dumps(changes)))
    assert back == spec and back["a"] is reference["a"]


def test_whole_body_tables_swept_by_name(tmp_path):
    """E-E, E-EP and EP-EP pairs in one zipped axis: bodies with different keys, by name."""
    steel = "radius = 0.01\nE = 210e9\nnu = 0.3\n"
    text = (
        '[zip.pair]\nbody1 = ["steel", "steel", "swift"]\nbody2 = ["steel", "swift", "swift"]\n'
        f'[define.steel]\nbehaviour = "elastic"\n{steel}'
        f'[define.swift]\nbehaviour = "elastic-plastic"\n{steel}'
        'hardening = { law = "swift", B = 945e6, C = 20.0, n = 0.121 }\n'
        + NORMAL_BASE.replace("n = 24,", "n = [24, 24, 12],").replace("1e9", "8e9")
    )
    campaign = load_campaign(write(tmp_path, text))
    assert campaign.dims == ("pair",) and campaign.shape == (3,)
    behaviours = [
        (c.spec["body1"]["behaviour"], c.spec["body2"]["behaviour"]) for c in campaign.cases
    ]
    assert behaviours == [
        ("elastic", "elastic"),
        ("elastic", "elastic-plastic"),
        ("elastic-plastic", "elastic-plastic"),
    ]
    assert [c.coords for c in campaign.cases][1] == {"body1": "steel", "body2": "swift"}
    cases = [c.case() for c in campaign.cases]
    assert [case.plastic_body for case in cases][0] is None
    assert cases[2].pair.body1.hardening == cases[2].pair.body2.hardening


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
    with pytest.raises(ValueError, match=r"not reachable.*\[-0\.142857, 0\.232142\]"):
        body1_for_beta(-0.3, steel, steel)


def _steel_beta_campaign(tmp_path, beta):
    return write(tmp_path, f'[sweep]\n"materials.dundurs_beta" = [{beta!r}]\n' + NORMAL_BASE)


def test_beta_range_both_ends_are_reachable(tmp_path):
    """Both ends of beta_range give valid cases; the limit nu1 -> -1 (E1 -> 0) is refused."""
    steel = Body("elastic", E=210e9, nu=0.3)
    c1, d2 = 0.91 / 210e9, 1.3 * 0.4 / (2 * 210e9)
    low, high = beta_range(steel, steel)
    # upper end: nu1 = -sqrt(1 - E_min c1), where E1 = (1 - nu1^2)/c1 reaches E_min = 1e3 Pa
    nu_min = -((1 - 1e3 * c1) ** 0.5)
    g = (1 - 2 * nu_min) / (2 * (1 - nu_min))
    assert high == pytest.approx((g * c1 - d2) / (2 * c1), rel=1e-14)
    limit = (0.75 * c1 - d2) / (2 * c1)  # the old, unreachable bound
    assert high < limit and limit - high < 1e-8
    for beta, nu1 in ((low, 0.5), (high, nu_min)):
        case = load_campaign(_steel_beta_campaign(tmp_path, beta)).cases[0].case()
        assert case.pair.dundurs_beta == pytest.approx(beta, abs=1e-9)
        assert case.body1.nu == pytest.approx(nu1, abs=1e-9)
        assert case.pair.composite_modulus == pytest.approx(210e9 / (2 * 0.91), rel=1e-7)
        assert 1e3 <= case.body1.E <= 1e15
    # just beyond either end, and the reported value just below the limit: a clear message
    for beta in (limit, 0.23214285714285712, low - 1e-9):
        with pytest.raises(CampaignError) as info:
            load_campaign(_steel_beta_campaign(tmp_path, beta))
        message = str(info.value)
        assert f"materials.dundurs_beta = {beta!r} is not reachable" in message, message
        assert "[-0.142857, 0.232142]" in message and "body1.E:" not in message


# -- bad campaign files: one clear message each, exit status 2 -----------------------------------
SWEEP_MU = '[sweep]\n"friction.coefficient" = [0.1, 0.2]\n'
BAD = {
    "unknown table": ("[sweeps]\na = 1\n" + SWEEP_MU + NORMAL_BASE, "[sweeps]: unknown table"),
    "case table at top": (
        SWEEP_MU + NORMAL_BASE + "[grid]\nn = 3\n",
        "case tables go under [base]",
    ),
    "missing base": (SWEEP_MU, "[base]: missing"),
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
    "list values": (
        '[sweep]\n"grid.n" = [[32, 32]]\n' + NORMAL_BASE,
        'must be numbers, strings or booleans, got [32, 32]; sweep "grid.n" as one number',
    ),
    "huge force": (
        '[sweep]\n"load.path.0.normal_force" = [100.0, 1e300]\n' + CATTANEO_BASE,
        "case 2 of 2 (load_path_0_normal_force=1e+300): load.path[0].normal_force: W = 1e+300 N",
    ),
    "beta at the old limit": (
        '[sweep]\n"materials.dundurs_beta" = [0.0, 0.23214285714285712]\n' + NORMAL_BASE,
        "materials.dundurs_beta = 0.23214285714285712 is not reachable",
    ),
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
        "not a key of [sweep], [zip] or [sample]; those are friction.coefficient",
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
    "define: unknown name": (
        '[sweep]\nbody2 = ["steel", "glass"]\n[define.steel]\nbehaviour = "rigid"\n' + NORMAL_BASE,
        "'glass' is not a [define.NAME] table (defined: steel)",
    ),
    "define: a number swept as a table": (
        "[sweep]\nbody2 = [1, 2]\n" + NORMAL_BASE,
        "a whole case table is swept by name; 1 is not",
    ),
    "define: unused": (
        SWEEP_MU + '[define.steel]\nbehaviour = "rigid"\n' + NORMAL_BASE,
        "[define.steel]: defined but no axis names it",
    ),
    "define: not a table": (SWEEP_MU + "[define]\nsteel = 1\n" + NORMAL_BASE, "named tables"),
    "zip: a point twice": (
        '[zip]\n"grid.n" = [24, 24]\n"load.steps" = [1, 1]\n' + NORMAL_BASE,
        "the values [24, 1] appear twice",
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


def test_status_assemble_and_report_before_and_after_a_run(tmp_path, capsys):
    """A campaign file or its output folder alike; before the run, a missing folder or
    nothing to assemble is said in one line (status still counts the pending cases)."""
    path = small_campaign(tmp_path)
    out = tmp_path / "out"
    assert main(["status", str(path), "--out", str(out)]) == 0
    assert "0/4 finished (0 converged" in capsys.readouterr().out
    for command in ("assemble", "report"):
        argv = [command, str(path)] + (["--out", str(out)] if command == "assemble" else [])
        assert main(argv) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "run the campaign first" in err, err
    for command in ("status", "assemble"):
        assert main([command, str(tmp_path / "never")]) == 2
        assert "no such output folder or campaign file" in capsys.readouterr().err
    assert main(["run", str(path), "--out", str(out), "--mpi", "off", "--no-assemble"]) == 0
    assert main(["assemble", str(out)]) == 0
    capsys.readouterr()
    path.write_text(path.read_text().replace("[campaign]", f'[campaign]\noutput = "{out}"'))
    assert main(["report", str(path), "--no-plots"]) == 0, capsys.readouterr().err
    assert (out / "report.md").is_file()


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
    import math
    import tomllib
    from pathlib import Path

    folder = Path(__file__).resolve().parent.parent / "campaigns"
    for name in ("quickstart", "convergence_hertz", "convergence_cattaneo"):
        path = folder / f"{name}.toml"
        campaign = load_campaign(path)
        # the full product of the [sweep] lists, read from the file itself, one case each
        sweep = tomllib.loads(path.read_text())["sweep"]
        sizes = tuple(len(values) for values in sweep.values())
        assert campaign.name == name and campaign.shape == sizes
        assert len(campaign.cases) == math.prod(sizes) >= 10
        assert len({case.case_id for case in campaign.cases}) == len(campaign.cases)
        assert [case.index for case in campaign.cases] == list(
            itertools.product(*(range(size) for size in sizes))
        )


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


# -- volume grids in sweeps ----------------------------------------------------------------------
VOLUME_BASE = NORMAL_BASE.replace("n = 24,", "n = [24, 24, 16],").replace(
    "grid = {", 'output = { fields = ["stress"] }\ngrid = {'
)


def test_grid_n_sweep_keeps_the_base_nz(tmp_path):
    """A scalar "grid.n" sweep over grid.n = [nx, ny, nz] keeps nz (module docstring rule)."""
    campaign = load_campaign(write(tmp_path, '[sweep]\n"grid.n" = [24, 32]\n' + VOLUME_BASE))
    assert [c.spec["grid"]["n"] for c in campaign.cases] == [[24, 24, 16], [32, 32, 16]]
    assert [c.case().volume_grid.nz for c in campaign.cases] == [16, 16]
    assert campaign.base["grid"]["n"] == [24, 24, 16]  # the recorded base is as written
    # the same cases as writing each volume grid out in full
    for case in campaign.cases:
        n = case.coords["grid_n"]
        table = solver.Case.from_dict({**case.spec, "grid": {"n": [n, n, 16], "half_width": 1.5}})
        assert table.case_id == case.case_id


def test_grid_nz_sweeps_and_zips_with_grid_n(tmp_path):
    base = VOLUME_BASE.replace("n = [24, 24, 16],", "n = 24, nz = 8,")
    swept = load_campaign(write(tmp_path, '[sweep]\n"grid.nz" = [8, 12]\n' + base))
    assert [c.spec["grid"]["n"] for c in swept.cases] == [[24, 24, 8], [24, 24, 12]]
    assert swept.axes[0].coordinates[0].units == "1"
    text = '[zip.mesh]\n"grid.n" = [24, 32]\n"grid.nz" = [8, 12]\n' + VOLUME_BASE
    zipped = load_campaign(write(tmp_path, text))
    assert [c.spec["grid"]["n"] for c in zipped.cases] == [[24, 24, 8], [32, 32, 12]]


def test_grid_nz_sweep_replaces_the_nz_of_a_three_entry_base_n(tmp_path):
    """Was refused ("grid.n = [24, 24, 16] already gives nz") though the README offered it."""
    swept = load_campaign(write(tmp_path, '[sweep]\n"grid.nz" = [8, 12]\n' + VOLUME_BASE))
    assert [c.spec["grid"]["n"] for c in swept.cases] == [[24, 24, 8], [24, 24, 12]]
    assert [c.case().volume_grid.nz for c in swept.cases] == [8, 12]


# -- validate: memory warnings and progress ------------------------------------------------------
def test_memory_warning_names_the_largest_case_and_the_machine(tmp_path, capsys, monkeypatch):
    import study.cli as cli

    campaign = load_campaign(small_campaign(tmp_path))
    largest = max(campaign.cases, key=lambda c: c.memory)
    gib = 2**30
    # more than the machine has: one line, naming the case, its memory and the machine's
    lines = cli.memory_warnings(campaign, largest.memory - 1, cores=2)
    assert len(lines) == 1 and lines[0].startswith("warning: 1 of 4 cases need more memory")
    assert largest.case_id in lines[0] and f"~{largest.memory / gib:.1f} GiB" in lines[0]
    assert f"{(largest.memory - 1) / gib:.1f} GiB in total" in lines[0]
    assert "each MPI rank" in lines[0]
    # fits once but not once per core: how many ranks fit
    lines = cli.memory_warnings(campaign, 3 * largest.memory, cores=8)
    assert len(lines) == 1 and "holds 3 such rank(s), fewer than its 8 cores" in lines[0]
    assert cli.memory_warnings(campaign, 8 * largest.memory, cores=8) == []
    assert cli.memory_warnings(campaign, None, cores=8) == []
    # through the command: stdout unchanged ("valid" last), the warning on stderr, status 0
    monkeypatch.setattr(cli, "machine_memory", lambda: largest.memory // 2)
    assert main(["validate", str(small_campaign(tmp_path))]) == 0
    captured = capsys.readouterr()
    assert captured.out.strip().endswith("valid")
    assert captured.err.count("\n") == 1 and captured.err.startswith("warning: ")


def test_machine_memory_reads_meminfo():
    from study.cli import machine_memory

    total = machine_memory()
    with open("/proc/meminfo") as handle:
        kib = next(int(line.split()[1]) for line in handle if line.startswith("MemTotal:"))
    assert total == kib * 1024


def test_n8192_warns_on_this_machine(tmp_path, capsys):
    """n = 8192 needs ~28 GiB (surface operator and work arrays): warned when above MemTotal."""
    from study.cli import machine_memory

    text = '[sweep]\n"friction.coefficient" = [0.0]\n' + NORMAL_BASE.replace("n = 24", "n = 8192")
    path = write(tmp_path, text)
    assert main(["validate", str(path)]) == 0
    captured = capsys.readouterr()
    memory = load_campaign(path).cases[0].memory
    assert memory > 25 * 2**30
    if memory > machine_memory():
        assert captured.err.startswith("warning: 1 of 1 cases need more memory")
        assert f"~{memory / 2**30:.1f} GiB" in captured.err
    else:
        assert "than this machine has" not in captured.err


def test_progress_lines_on_a_long_expansion(tmp_path, monkeypatch):
    import io

    import study.cli as cli

    stream = io.StringIO()
    ticks = iter(range(0, 1000, 2))  # a clock that advances 2 s per reading
    monkeypatch.setattr(cli.ProgressLine, "every", 4.0)
    progress = cli.ProgressLine(stream)
    progress._clock = lambda: next(ticks)
    progress._start = progress._next = 0
    total, step = 10000, 2000
    for done in range(0, total + 1, step):
        progress(done, total)
    progress.finish()
    lines = stream.getvalue().splitlines()
    # calls at t = 0, 2, ..., 10 s (done 0, 2000, ..., 10000): the first with cases done says
    # the rate and the time left at once (the whole takes 10 s > delay), then every 4 s; none
    # for the last call (done = total), finish() at t = 12 s
    rate = step / 2  # cases per second of the fake clock

    def line(t):
        done = rate * t
        left = (total - done) / rate
        return (
            f"validating: {done:.0f}/{total} cases ({100 * done / total:.0f} %) in {t:.1f}s, "
            f"{rate:.0f} cases/s: about {left:.1f}s left"
        )

    assert lines == [line(2), line(6), "validating: done in 12.0s"]
    quiet = io.StringIO()
    cli.ProgressLine(quiet).finish()
    assert quiet.getvalue() == ""
    short = io.StringIO()  # an expansion that takes less than the delay says nothing
    fast = cli.ProgressLine(short)
    fast._clock = iter([0.0, 0.1, 0.2, 0.3]).__next__
    fast._start = fast._next = 0.0
    for done in (2000, 4000):
        fast(done, 6000)
    fast.finish()
    assert short.getvalue() == ""


def test_expansion_reports_progress(tmp_path):
    from study.campaign import PROGRESS_EVERY

    calls = []
    values = ", ".join(str(0.001 * i) for i in range(PROGRESS_EVERY + 1))
    text = f'[sweep]\n"friction.coefficient" = [{values}]\n' + NORMAL_BASE
    campaign = load_campaign(write(tmp_path, text), progress=lambda *a: calls.append(a))
    total = PROGRESS_EVERY + 1
    assert len(campaign.cases) == total
    assert calls == [(PROGRESS_EVERY, total), (total, total)]
