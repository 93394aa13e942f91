"""The lazy field loader: a campaign's per-case fields over the sweep axes, one case at a time."""

import tracemalloc

import dask
import numpy as np
import pytest
import xarray as xr
from study_fixtures import pair_campaign, write

from study.analysis.fields import MISSING_FLAG, open_fields
from study.campaign import load_campaign
from study.run import storage
from study.run.driver import RunOptions, run_campaign

LOADS = """
[campaign]
name = "loads"

[sweep]
"load.hertz_pressure" = [3.5e9, 4e9, 4.5e9, 5e9, 5.5e9, 6e9]

[alias]
"load.hertz_pressure" = "p_h"

[base]
body1 = { behaviour = "rigid", radius = 0.015 }
grid = { n = [16, 16, 16], depth = 2.5 }
load = { hertz_pressure = 5e9, steps = 2 }
output = { fields = ["plastic_strain_tensor", "residual_stress"] }

[base.body2]
behaviour = "elastic-plastic"
radius = "inf"
E = 210e9
nu = 0.3
hardening = { law = "linear", yield_stress = 1.3579e9, modulus = 152.3e9 }
"""
VOLUME = ("plastic_strain", "plastic_strain_tensor", "residual_stress")


@pytest.fixture(scope="module")
def loads(tmp_path_factory):
    folder = tmp_path_factory.mktemp("fields")
    campaign = load_campaign(write(folder, LOADS))
    assert run_campaign(campaign, folder / "out", options=RunOptions()).exit_status == 0
    return campaign, folder / "out"


def test_fields_equal_the_case_files_and_stay_lazy(loads):
    campaign, out = loads
    fields = open_fields(out)
    for name in VOLUME:
        assert isinstance(fields[name].data, dask.array.Array)
        assert fields[name].chunks[0] == (1,) * 6  # one chunk per case
    assert fields.plastic_strain.dims == ("p_h", "x_over_a", "y_over_a", "z_over_a")
    assert fields.residual_stress.dims[:2] == ("p_h", "component")
    for case in campaign.cases:
        with xr.open_dataset(storage.case_path(out, case.case_id)) as data:
            a = float(data.attrs["hertz_semi_axis_x"])
            one = fields.sel(p_h=case.coords["p_h"])
            for name in (*VOLUME, "pressure", "contact_state"):
                np.testing.assert_array_equal(one[name].values, data[name].values)
            np.testing.assert_allclose(fields.z_over_a.values, data.z.values / a, rtol=1e-12)
            assert str(one.case_id.values) == case.case_id
    # a larger load: a larger plastic strain (the loader keeps the sweep order)
    peaks = fields.plastic_strain.max(("x_over_a", "y_over_a", "z_over_a")).values
    assert np.all(np.diff(peaks) > 0)


def test_reduction_needs_less_memory_than_the_fields(loads):
    """The volume fields together exceed a memory limit; a reduction over them stays below it."""
    _, out = loads
    fields = open_fields(out, names=list(VOLUME))
    total = sum(fields[name].nbytes for name in VOLUME)
    limit = total // 2
    assert total > limit > max(fields[name][0].nbytes for name in VOLUME)
    opened = open_fields(out, names=list(VOLUME))
    tracemalloc.start()  # numpy's buffers are traced
    try:
        with dask.config.set(scheduler="synchronous"):
            peaks = {
                name: opened[name].max([d for d in opened[name].dims if d != "p_h"]).values
                for name in VOLUME
            }
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak < limit, (peak, limit, total)
    expected = fields.plastic_strain.load().max(("x_over_a", "y_over_a", "z_over_a")).values
    np.testing.assert_array_equal(peaks["plastic_strain"], expected)


def test_missing_cases_hold_nan_and_selection_drops_the_axis(loads, tmp_path):
    campaign, out = loads
    # a copy of the output without the middle case (pending)
    copy = tmp_path / "out"
    (copy / "cases").mkdir(parents=True)
    (copy / "campaign.json").write_bytes((out / "campaign.json").read_bytes())
    middle = campaign.cases[3].case_id
    for case in campaign.cases:
        if case.case_id != middle:
            path = storage.case_path(out, case.case_id)
            (copy / "cases" / path.name).write_bytes(path.read_bytes())
    fields = open_fields(copy)
    assert np.isnan(fields.plastic_strain.sel(p_h=5e9).values).all()
    assert (fields.contact_state.sel(p_h=5e9).values == MISSING_FLAG).all()
    assert fields.contact_state.attrs["missing_value"] == MISSING_FLAG
    assert np.isfinite(fields.plastic_strain.sel(p_h=6e9).values).all()
    one = open_fields(out, p_h=6e9)
    assert "p_h" not in one.plastic_strain.dims
    np.testing.assert_array_equal(one.plastic_strain, fields.plastic_strain.sel(p_h=6e9))


def test_cases_with_different_cells_name_the_axis(tmp_path):
    # without a fixed depth the volume depth follows the load (the yield depth): z differs
    text = LOADS.replace(", depth = 2.5", "").replace(
        "[3.5e9, 4e9, 4.5e9, 5e9, 5.5e9, 6e9]", "[3e9, 6e9]"
    )
    campaign = load_campaign(write(tmp_path, text))
    assert run_campaign(campaign, tmp_path / "out", options=RunOptions()).exit_status == 0
    with pytest.raises(
        ValueError, match="different cells along z; select one value of the axis 'p_h'"
    ):
        open_fields(tmp_path / "out")
    assert open_fields(tmp_path / "out", names=["pressure"]).pressure.shape == (2, 16, 16)
    for bad, match in (
        ({"mu": 0.1}, "'mu' is not a sweep coordinate"),
        ({"p_h": 4e9}, "p_h=4000000000.0 is not a swept value"),
    ):
        with pytest.raises(ValueError, match=match):
            open_fields(tmp_path / "out", **bad)
    with pytest.raises(ValueError, match="hold no 'stress'"):
        open_fields(tmp_path / "out", names=["stress"])


PAIRS = pair_campaign(
    "grid = { n = [16, 16, 16], depth = 2.5 }\nload = { hertz_pressure = 5e9, steps = 2 }",
    '{ law = "linear", yield_stress = 1.3579e9, modulus = 152.3e9 }',
)


def test_a_selection_must_name_one_value_of_a_zipped_axis(tmp_path):
    campaign = load_campaign(write(tmp_path, PAIRS))
    assert campaign.shape == (3,)
    assert run_campaign(campaign, tmp_path / "out", options=RunOptions()).exit_status == 0
    with pytest.raises(ValueError, match="leaves 2 values of the axis 'pair'"):
        open_fields(tmp_path / "out", body1="steel")
    one = open_fields(tmp_path / "out", body1="swift", names=["plastic_strain"])
    assert one.plastic_strain.dims == ("x_over_a", "y_over_a", "z_over_a")
    both = open_fields(tmp_path / "out", names=["plastic_strain"])
    assert np.isnan(both.plastic_strain.isel(pair=0).values).all()  # the elastic pair has none
    np.testing.assert_array_equal(one.plastic_strain, both.plastic_strain.isel(pair=2))
