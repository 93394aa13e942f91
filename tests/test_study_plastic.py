"""A small elastic-plastic campaign through the study layer: case files, assembly, profiles."""

import numpy as np
import pytest
from study_fixtures import write

import solver
from solver.theory.hertz import hertz_yield_depth
from study.analysis import speed_error_table
from study.campaign import load_campaign
from study.run.assemble import Z_OVER_A, assemble
from study.run.driver import RunOptions, run_campaign

PLASTIC = """
[campaign]
name = "plastic"

[sweep]
"load.path.0.hertz_pressure" = [2e9, 5e9]

[alias]
"load.path.0.hertz_pressure" = "p_h"

[base]
body1 = { behaviour = "rigid", radius = 0.015 }
grid = { n = [20, 20, 20] }

[base.body2]
behaviour = "elastic-plastic"
radius = "inf"
E = 210e9
nu = 0.3
hardening = { law = "linear", yield_stress = 1.3579e9, modulus = 152.3e9 }

[[base.load.path]]
hertz_pressure = 5e9
steps = 3

[[base.load.path]]
normal_force = 0.0
steps = 1
"""


def test_plastic_campaign_assembles_scalars_histories_and_axis_profile(tmp_path):
    campaign = load_campaign(write(tmp_path, PLASTIC))
    summary = run_campaign(campaign, tmp_path / "out", options=RunOptions())
    assert summary.exit_status == 0
    ds = assemble(tmp_path / "out", campaign)
    assert (ds.status == 1).all()
    low, high = ds.sel(p_h=2e9), ds.sel(p_h=5e9)
    assert float(low.max_plastic_strain) == 0.0  # 2 GPa < first yield (2.19 GPa)
    assert float(high.max_plastic_strain) > 0.0
    # unloaded at the last step: the pressure is zero, its largest value is the loaded one
    assert float(high.max_pressure_history.isel(step=-1)) == 0.0
    assert float(high.max_pressure) == float(high.max_pressure_history.max())
    assert float(high.residual_depth) > 0 and float(high.plastic_iterations) >= 4
    profile = high.plastic_strain_profile
    assert profile.dims == ("z_over_a",) and ds.z_over_a.size == Z_OVER_A.size
    peak = float(profile.idxmax())
    assert 0.3 < peak < 0.8  # below the surface, near the Hertz maximum of von Mises
    # the box is deeper than the yield region, and the profile is NaN below it
    case = solver.Case.from_dict(campaign.cases[1].spec)
    assert case.grid.depth >= 1.2 * hertz_yield_depth(5e9, 1.3579e9, 0.3) - 1e-12
    assert np.isnan(profile.sel(z_over_a=3.9, method="nearest"))
    assert ds.max_plastic_strain.attrs["units"] == "1"
    # the volume grid's layers count in the cells of the report's speed-versus-error table
    assert (ds.grid_cells == 20 * 20 * 20).all()
    assert (speed_error_table(ds)["cells"] == 8000).all()
    with pytest.raises(KeyError):
        ds["tangential_force_x"]  # no slip-stick history in this campaign


CONE = """
[campaign]
name = "cone"

[base.body1]
behaviour = "rigid"
radius = "inf"
profile = { shape = "cone", angle = 0.05 }

[base.body2]
behaviour = "elastic-plastic"
radius = "inf"
E = 210e9
nu = 0.3
hardening = { law = "linear", yield_stress = 1e9, modulus = 20e9 }

[base]
load = { normal_force = 5.0, steps = 1 }
grid = { n = [16, 16, 16] }

[sweep]
"body2.hardening.modulus" = [10e9, 20e9]
"""


def test_a_cone_on_a_plastic_body_assembles_without_a_hertz_radius(tmp_path):
    """A profile's cases carry Sneddon's radius, not Hertz's: the assembly read the Hertz radius
    for every plastic depth profile and failed (KeyError); there is no such profile now."""
    campaign = load_campaign(write(tmp_path, CONE))
    assert run_campaign(campaign, tmp_path / "out", options=RunOptions()).exit_status == 0
    ds = assemble(tmp_path / "out", campaign)
    assert (ds.status == 1).all() and np.isfinite(ds.max_plastic_strain).all()
    assert "plastic_strain_profile" not in ds  # no Hertz radius to scale the depth by
