"""The lazy field loader: a campaign's per-case fields over the sweep axes, one case at a time."""

import tracemalloc

import dask
import numpy as np
import pytest
from study_fixtures import copy_cases, pair_campaign, write

from study.analysis.fields import LATTICE_TOL, MISSING_FLAG, open_fields
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
grid = { n = [16, 16, 16], depth = 2.5, half_width = 1.5 }
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
        with storage.open_case(out, case.case_id) as data:
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
    middle = campaign.cases[3].case_id
    copy_cases(out, copy, {case.case_id for case in campaign.cases} - {middle})
    fields = open_fields(copy)
    assert np.isnan(fields.plastic_strain.sel(p_h=5e9).values).all()
    assert (fields.contact_state.sel(p_h=5e9).values == MISSING_FLAG).all()
    assert fields.contact_state.attrs["missing_value"] == MISSING_FLAG
    assert np.isfinite(fields.plastic_strain.sel(p_h=6e9).values).all()
    one = open_fields(out, p_h=6e9)
    assert "p_h" not in one.plastic_strain.dims
    np.testing.assert_array_equal(one.plastic_strain, fields.plastic_strain.sel(p_h=6e9))


@pytest.fixture(scope="module")
def sized_by_load(tmp_path_factory):
    """Two loads, the box sized from each: the depth (in a_H and m) and the cells (m) differ."""
    folder = tmp_path_factory.mktemp("sized_by_load")
    text = LOADS.replace(", depth = 2.5, half_width = 1.5", "").replace(
        "[3.5e9, 4e9, 4.5e9, 5e9, 5.5e9, 6e9]", "[3e9, 6e9]"
    )
    campaign = load_campaign(write(folder, text))
    assert run_campaign(campaign, folder / "out", options=RunOptions()).exit_status == 0
    return campaign, folder / "out"


def test_cases_with_different_cells_name_the_axis(sized_by_load):
    _, out = sized_by_load
    with pytest.raises(
        ValueError, match="different cells along [xz]; select one value of the axis 'p_h'"
    ) as info:
        open_fields(out)  # the box depth (and, by default, the window) follows the load
    assert "align='nearest'" in str(info.value)
    with pytest.raises(ValueError, match="do not line up along x .* use align='nearest'"):
        open_fields(out, align="union")  # the cells scale with a_H: no lattice in metres
    with pytest.raises(ValueError, match="align='cells'; use one of"):
        open_fields(out, align="cells")
    one = open_fields(out, p_h=3e9)  # the message's first way out
    assert one.plastic_strain.dims == ("x_over_a", "y_over_a", "z_over_a")
    one.close()
    for bad, match in (
        ({"mu": 0.1}, "'mu' is not a sweep coordinate"),
        ({"p_h": 4e9}, "p_h=4000000000.0 is not a swept value"),
    ):
        with pytest.raises(ValueError, match=match):
            open_fields(out, **bad)
    with pytest.raises(ValueError, match="hold no 'stress'"):
        open_fields(out, names=["stress"])


#: One load, two box depths (1.5 and 2.5 a_H) of the same cells (0.125 a_H): the cells line up.
DEPTHS = (
    LOADS.replace('"load.hertz_pressure" = [3.5e9, 4e9, 4.5e9, 5e9, 5.5e9, 6e9]', "")
    .replace('"load.hertz_pressure" = "p_h"', '"grid.depth" = "depth"')
    .replace("[sweep]", '[zip.box]\n"grid.depth" = [1.5, 2.5]\n"grid.nz" = [12, 20]')
    .replace("grid = { n = [16, 16, 16], depth = 2.5, half_width = 1.5 }", "grid = { n = 16 }")
)


def _on_grid(grid: np.ndarray, own: np.ndarray) -> np.ndarray:
    """Positions of a case's own cell centres on a common grid (m), checked to be on it."""
    at = np.abs(grid[:, None] - own[None, :]).argmin(axis=0)
    np.testing.assert_allclose(grid[at], own, rtol=0, atol=1e-9 * np.diff(own).min())
    return at


def test_box_depths_that_line_up_share_the_union_of_their_cells(tmp_path):
    campaign = load_campaign(write(tmp_path, DEPTHS))
    assert campaign.shape == (2,)
    out = tmp_path / "out"
    assert run_campaign(campaign, out, options=RunOptions()).exit_status == 0
    with pytest.raises(ValueError, match="different cells along z; select one value of the axis"):
        open_fields(out)  # 12 and 20 cells in depth
    fields = open_fields(out, align="union")
    assert fields.attrs["align"] == "union"
    assert fields.z.attrs["units"] == "m" and "none" in fields.z.attrs["resampling"]
    assert fields.plastic_strain.dims == ("box", "x", "y", "z")
    assert isinstance(fields.plastic_strain.data, dask.array.Array)
    assert fields.plastic_strain.chunks[0] == (1, 1)  # one chunk per case
    fields.load().close()  # the case files closed before they are opened below
    depths = []
    for k, case in enumerate(campaign.cases):
        with storage.open_case(out, case.case_id) as data:
            depths.append(data.z.size)
            at = {d: _on_grid(fields[d].values, data[d].values) for d in ("x", "y", "z")}
            one = fields.isel(box=k)
            for name in ("plastic_strain", "residual_stress", "pressure", "contact_state"):
                common = one[name].values
                own = np.ix_(
                    *[at[d] if d in at else np.arange(n) for d, n in one[name].sizes.items()]
                )
                np.testing.assert_array_equal(common[own], data[name].values)
                elsewhere = np.ones(common.shape, dtype=bool)
                elsewhere[own] = False
                missing = MISSING_FLAG if name == "contact_state" else np.nan
                np.testing.assert_array_equal(common[elsewhere], missing)
    assert depths == [12, 20] and fields.z.size == 20  # the deeper box's cells
    assert np.isnan(fields.plastic_strain.isel(box=0, z=slice(12, None)).values).all()
    # the cells line up: the nearest cell is the cell itself
    nearest = open_fields(out, align="nearest").load()
    nearest.close()
    for name in ("plastic_strain", "residual_stress", "contact_state"):
        np.testing.assert_array_equal(nearest[name].values, fields[name].values)


def test_a_load_sweep_lays_each_case_on_the_finest_cells_in_metres(sized_by_load):
    """Each case holds, at a common point, its own cell's value there; NaN beyond its box."""
    campaign, out = sized_by_load
    fields = open_fields(out, align="nearest")
    assert fields.plastic_strain.dims == ("p_h", "x", "y", "z")
    assert fields.residual_stress.dims == ("p_h", "component", "x", "y", "z")
    assert fields.plastic_strain.chunks == (
        (1, 1),
        *((n,) for n in fields.plastic_strain.shape[1:]),
    )
    assert "nearest cell" in fields.z.attrs["resampling"]
    fields.load().close()  # the case files closed before they are opened below
    grid = {d: fields[d].values for d in ("x", "y", "z")}
    spacing, reach = [], []
    for case in campaign.cases:
        with storage.open_case(out, case.case_id) as data:
            data.load()  # in memory: point selections on the file are slow
            step = {d: float(np.diff(data[d].values).mean()) for d in grid}
            spacing.append(step)
            # the case's cell holding each point: the nearest centre, a point on a face between
            # two cells (within LATTICE_TOL of a cell) taking the upper one; none off its box
            held, inside = {}, {}
            for d in grid:
                centres = data[d].values
                offset = (grid[d] - centres[0]) / step[d]
                nearest = np.floor(offset + 0.5 + LATTICE_TOL).astype(int)
                inside[d] = (nearest >= 0) & (nearest < centres.size)
                held[d] = centres[np.clip(nearest, 0, centres.size - 1)]
            one = fields.sel(p_h=case.coords["p_h"])
            for name in ("plastic_strain", "residual_stress", "pressure", "contact_state"):
                variable = data[name]
                cell_dims = [d for d in variable.dims if d in grid]
                expected = variable.sel({d: held[d] for d in cell_dims}).values
                mask = np.ones(expected.shape, dtype=bool)
                for axis, d in enumerate(variable.dims):
                    if d in grid:
                        mask &= inside[d].reshape(
                            [-1 if a == axis else 1 for a in range(mask.ndim)]
                        )
                missing = MISSING_FLAG if name == "contact_state" else np.nan
                np.testing.assert_array_equal(one[name].values, np.where(mask, expected, missing))
                # no cell is lost: every value of the case file is on the common grid
                np.testing.assert_array_equal(
                    np.unique(one[name].values[mask]), np.unique(variable.values)
                )
            reach.append(inside["z"])
    assert not reach[0].all() and reach[1].all()  # the smaller load's box is shallower
    small, large = spacing  # p_h = 3 then 6 GPa: the cells grow with a_H
    for d in grid:
        assert small[d] < large[d]
        np.testing.assert_allclose(np.diff(grid[d]), small[d], rtol=1e-9)
    # the tribologist's question: the plastic strain at one depth, over the loads
    at = fields.plastic_strain.sel(x=0, y=0, z=0.2e-3, method="nearest").values
    assert at.shape == (2,) and np.isfinite(at).all()


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
