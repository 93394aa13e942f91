"""Line contacts (``grid.periodic = "y"``): a cylinder, plane strain, Carter's steady rolling.

Independent references: Hertz's plane-strain pressure (its displacements inside the strip are
parabolas, :mod:`solver.theory.line`), the plane-strain coupling of a dissimilar pair
(``u_x = beta A int sgn(x - t) p(t) dt``, the 3-D kernel integrated along y), and Carter's
closed form of steady rolling (creep force and traction), all computed here from their
formulas; the error shrinks with the mesh.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import solver
from solver import SpecError
from solver.bodies.materials import Body, Pair
from solver.numerics.grid import SurfaceGrid
from solver.surface.periodic import YPeriodicSurfaceOperator
from solver.theory.line import carter_force_ratio, carter_traction, hertz_line

E, NU, MU, R = 210e9, 0.3, 0.3, 0.05  # body 1 a 50 mm cylinder on flat steel
STEEL = Body("elastic", E=E, nu=NU)
ALUMINIUM = Body("elastic", E=70e9, nu=0.33)
HALF_WIDTH = 1e-3  # m, Hertz's b of the scene
E_STAR = E / (2 * (1 - NU * NU))
PER_LENGTH = math.pi * E_STAR * HALF_WIDTH**2 / (4 * R)  # N/m giving b = HALF_WIDTH
SATURATION = MU * HALF_WIDTH / R  # Carter's full-slip creepage


def _displacement_errors(pair: Pair, cells: int) -> dict[str, float]:
    """Hertz's plane-strain pressure (and the same shears) on ``cells`` across the strip."""
    dx = 2 * HALF_WIDTH / cells
    grid = SurfaceGrid(round(1.5 * cells), 4, dx, dx)
    operator = YPeriodicSurfaceOperator(grid, pair)
    x = grid.mesh()[0]
    p = np.sqrt(np.clip(1 - (x / HALF_WIDTH) ** 2, 0, None))  # p_0 = 1 Pa
    row, inside = x[:, 0], np.abs(x[:, 0]) < 0.9 * HALF_WIDTH
    compliance, coupling = pair.compliance, pair.shear_coupling
    parabola = -row * row / HALF_WIDTH  # times the compliance: Hertz's u inside, p_0 = 1 Pa

    def error(values, expected):
        misfit = values[:, 0] - expected
        misfit -= misfit[inside].mean()  # defined up to a constant
        return float(np.abs(misfit[inside]).max() / np.abs(expected[inside]).max())

    ux, uy = operator.tangential(p, 0 * p)
    vx, vy = operator.tangential(0 * p, p)
    cx, _ = operator.tangential_from_pressure(p)
    pressure_row = p[:, 0]
    left = np.cumsum(pressure_row) * dx - 0.5 * pressure_row * dx  # int_-inf^x p dt
    beta_a = pair.body1.dilatational_compliance - pair.body2.dilatational_compliance
    coupled = 2 * beta_a * left  # beta A (left - right), up to a constant
    return {
        "zz": error(operator.normal(p), compliance * parabola),
        "xx": error(ux, compliance * parabola),
        "yy": error(vy, (compliance + coupling) * parabola),
        "uncoupled": float(np.abs(uy).max() + np.abs(vx).max()),
        "xp": error(cx, coupled) if pair.dundurs_beta else 0.0,
    }


@pytest.mark.validation
@pytest.mark.parametrize("pair", [Pair(STEEL, STEEL), Pair(ALUMINIUM, STEEL)], ids=["same", "al"])
def test_the_y_periodic_kernels_are_plane_strain_under_a_uniform_load(pair, validation):
    errors = [_displacement_errors(pair, cells) for cells in (32, 64, 128)]
    for name in ("zz", "xx", "yy", "xp"):
        values = [e[name] for e in errors]
        assert values[-1] < 2e-3, (name, values)
        assert values[-1] < 0.5 * values[0] or values[0] == 0.0, (name, values)
    assert all(e["uncoupled"] < 1e-25 for e in errors)  # x and y decouple under a uniform load
    validation(
        'Line contact kernels (grid.periodic = "y", solver.surface.periodic)',
        "Hertz's plane-strain strip: u_z, u_x, u_y parabolas inside it; the coupling "
        "beta A int sgn(x - t) p dt",
        "32 / 64 / 128 cells across: "
        + "; ".join(f"{n} " + "/".join(f"{e[n]:.1e}" for e in errors) for n in ("zz", "yy", "xp")),
    )


def _line_table(cells: int, stages: list[dict], order: int = 2) -> dict:
    """The 50 mm cylinder on flat steel, ``cells`` across the strip, domain 2.6 b along x."""
    dx = 2 * HALF_WIDTH / cells
    nx, ny = round(2.6 * cells / 2), 4
    return {
        "body1": {"behaviour": "elastic", "E": E, "nu": NU, "radius_x": R},
        "body2": {"behaviour": "elastic", "E": E, "nu": NU},
        "friction": {"coefficient": MU},
        "load": {"path": [{"normal_force": PER_LENGTH * ny * dx}, *stages]},
        "grid": {"n": [nx, ny], "size": [nx * dx, ny * dx], "periodic": "y"},
        "solver": {"steady_order": order},
    }


def _line_case(cells: int, stages: list[dict], order: int = 2) -> solver.Case:
    return solver.Case.from_dict(_line_table(cells, stages, order))


def _carter_errors(cells: int) -> tuple[float, float]:
    """Largest creep-force error (of mu w) over a creep curve of 5 points, and the traction's
    mean error over the strip at xi = 0.5 of saturation (of mu p_0; its largest is at the
    stick-slip kink and the strip's edge cells, of a cell's size)."""
    curve = _line_case(cells, [{"steady": True, "creepage": [SATURATION, 0.0], "steps": 5}])
    result = solver.solve(curve)
    assert result.status == "converged"
    force = PER_LENGTH * curve.surface_grid.ny * curve.surface_grid.dy
    xi, fx = result.history["creepage_x"][1:], result.history["tangential_force_x"][1:]
    expected = [carter_force_ratio(v, MU, HALF_WIDTH, R) for v in xi]
    force_error = float(np.max(np.abs(fx / (MU * force) - expected)))
    middle = _line_case(cells, [{"steady": True, "creepage": [0.5 * SATURATION, 0.0]}])
    state = solver.solve(middle)
    assert state.status == "converged"
    x = middle.surface_grid.mesh()[0][:, 0]
    b, p0 = hertz_line(PER_LENGTH, E_STAR, R)
    carter = carter_traction(x, 0.5 * SATURATION, MU, b, R, p0)
    inside = np.abs(x) < b
    misfit = np.abs(state.shear_x[:, 0] - carter)[inside]
    traction_error = float(misfit.mean() / (MU * p0))
    return force_error, traction_error


@pytest.mark.validation
def test_steady_rolling_of_a_cylinder_is_carters(validation):
    sizes = (16, 32, 64, 128)
    errors = {cells: _carter_errors(cells) for cells in sizes}
    forces = [errors[c][0] for c in sizes]
    tractions = [errors[c][1] for c in sizes]
    assert max(forces[1:]) < 0.01 and forces[-1] < 0.25 * forces[0], forces
    assert tractions == sorted(tractions, reverse=True) and tractions[-1] < 0.002, tractions
    validation(
        'Steady rolling of a cylinder (line contact, grid.periodic = "y")',
        "Carter 1926: F / (mu w) = 1 - (1 - |xi| R / (mu b))^2 and his traction",
        "creep force (of mu w) at 16 / 32 / 64 / 128 cells across: "
        + " / ".join(f"{e:.2%}" for e in forces)
        + "; traction at xi = 0.5 saturation, mean error (of mu p_0): "
        + " / ".join(f"{e:.2%}" for e in tractions),
    )


@pytest.mark.parametrize(
    ("change", "key"),
    [
        ({"body1": {"behaviour": "elastic", "E": E, "nu": NU, "radius": R}}, "body1.radius_y"),
        ({"body1": {"behaviour": "elastic", "E": E, "nu": NU}}, "body1.radius_x"),
        ({"body1": {"behaviour": "elastic-plastic", "E": E, "nu": NU, "radius_x": R,
                    "hardening": {"law": "perfect", "yield_stress": 1e9}}}, "body1.behaviour"),
        ({"stage": {"steady": True, "spin": 1.0}}, "spin"),
        ({"stage": {"roll": [1e-4, 0.0], "creepage": [1e-3, 0.0], "steps": 2}}, "load.path"),
    ],
)  # fmt: skip
def test_a_line_contact_refuses_what_is_not_built(change, key):
    stage = change.pop("stage", {"tangential_force": [1.0, 0.0]})
    table = {**_line_table(16, [stage]), **change}
    if "steady" not in stage:
        del table["solver"]
    with pytest.raises(SpecError, match=key.replace(".", r"\.")):
        solver.Case.from_dict(table)


def test_a_line_contact_is_its_own_case():
    table = _line_table(16, [{"steady": True, "creepage": [1e-3, 0.0]}])
    case = solver.Case.from_dict(table)
    assert case.spec["grid"]["periodic"] == "y"
    del table["grid"]["periodic"]
    with pytest.raises(SpecError, match="body1.radius"):  # a cylinder needs the line contact
        solver.Case.from_dict(table)


def test_the_shipped_line_contact_campaign_reports_carters_traction(tmp_path):
    """campaigns/carter_cylinder.toml (its friction axis cut to one value) runs, assembles,
    and its report draws the traction beside Carter's instead of a Kalker slope."""
    import xarray as xr

    from study.campaign import load_campaign
    from study.report import build_report
    from study.run.assemble import assemble_to_file
    from study.run.driver import RunOptions, run_campaign

    text = (Path(__file__).parent.parent / "campaigns" / "carter_cylinder.toml").read_text()
    sweep = '"friction.coefficient" = [0.2, 0.3, 0.4]'
    assert sweep in text
    (tmp_path / "carter.toml").write_text(text.replace(sweep, '"friction.coefficient" = [0.3]'))
    campaign = load_campaign(tmp_path / "carter.toml")
    assert run_campaign(campaign, tmp_path / "out", options=RunOptions()).exit_status == 0
    with xr.open_dataset(assemble_to_file(tmp_path / "out")) as data:
        half_width = float(data["line_half_width"].values.ravel()[0])
        xi = data["creepage_x_history"].values.ravel()
        force = data["tangential_force_x_history"].values.ravel()
        per_length = float(data["line_force_per_length"].values.ravel()[0])
        mu_w = 0.3 * np.nanmax(data["normal_force_history"].values)
    assert half_width == pytest.approx(HALF_WIDTH, rel=1e-4)  # the file's scene: b = 1 mm
    assert per_length == pytest.approx(PER_LENGTH, rel=1e-4)
    steady = np.isfinite(xi) & (xi > 0)
    expected = [carter_force_ratio(v, 0.3, half_width, R) for v in xi[steady]]
    assert np.abs(force[steady] / mu_w - expected).max() < 0.005  # 64 cells across
    text = build_report(tmp_path / "out").read_text()
    assert "a line contact: Carter's closed form" in text
    assert (tmp_path / "out" / f"{campaign.name}_steady_tractions.png").exists()


def test_a_coarse_line_contact_is_told_by_its_width_along_x():
    """The mesh note measures a strip by its width along x, not as a disc of its area."""
    fine = solver.solve(_line_case(16, [{"steady": True, "creepage": [1e-3, 0.0]}]))
    assert not any("cells across" in note for note in fine.notes)
    coarse = solver.solve(_line_case(8, [{"steady": True, "creepage": [1e-3, 0.0]}], order=1))
    assert any("8 cells across" in n and "width along x" in n for n in coarse.notes), coarse.notes
