"""Sobol' and Morris' measures on functions that tell them apart, and the analysis' refusals.

Issue 57.  Hertz's ``ln a`` (``tests/test_sample.py``) is additive: its first-order and total
Sobol' indices coincide, and its Morris effects have no spread, so a swap of ``S1`` and ``ST``
(or of ``mu_star`` and ``sigma``) passes there.  Here the outputs have interactions with known
measures, computed from the formula on the inputs of a design built as a campaign builds it
(``[sample]`` table, expansion, assembly; every case marked finished, no solve).

Ishigami's function ``f = sin x1 + a sin^2 x2 + b x3^4 sin x1`` on ``[-pi, pi]^3`` (Ishigami and
Homma 1990; Saltelli et al. 2008, *Global Sensitivity Analysis: The Primer*, sec. 4.6), written
``f = sin x1 (1 + b x3^4) + a sin^2 x2``, with ``E sin^2 = 1/2``, ``E sin^4 = 3/8``,
``E x^4 = pi^4 / 5``, ``E x^8 = pi^8 / 9`` for ``x`` uniform on ``[-pi, pi]``:

- ``E[f | x1] = sin x1 (1 + b pi^4 / 5) + a / 2``: ``V1 = (1 + b pi^4 / 5)^2 / 2``;
- ``E[f | x2] = a sin^2 x2``: ``V2 = a^2 (3/8 - 1/4) = a^2 / 8``;
- ``E[f | x3] = a / 2``: ``V3 = 0``;
- ``E[f | x1, x3] = sin x1 (1 + b x3^4) + a / 2``: ``V13 = b^2 (pi^8 / 9 - pi^8 / 25) / 2``
  ``= b^2 pi^8 (1/18 - 1/50)`` beyond ``V1 + V3``;
- x2 enters alone: ``V = V1 + V2 + V13 = a^2 / 8 + b pi^4 / 5 + b^2 pi^8 / 18 + 1/2``.

So ``S1 = (V1, V2, 0) / V`` and ``ST = (V1 + V13, V2, V13) / V``; x3 acts only with x1.  A
quadrature checks these against the definitions (``test_ishigami_closed_forms_...``).

Morris: ``f = c1 x1 + c23 x2 x3`` on ``[-1, 1]^3`` with two grid levels.  A step moves an input
from one end to the other (``Delta = p / (2 (p - 1)) = 1`` in quantile level, ``2`` in x), so
x1's effects are all ``2 c1`` (``mu = 2 c1``, ``mu* = 2 |c1|``, ``sigma = 0``) and x2's are
``2 c23 x3 = +-2 c23`` (``mu* = 2 |c23|`` exactly; ``mu`` and ``sigma`` from the signs met, with
``mu^2 + sigma^2 (r - 1) / r = mu*^2`` since every effect has the same size).
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from study_fixtures import DESIGN_BASE as BASE
from study_fixtures import DESIGN_RANGES as RANGES

from solver.result import STATUS_FLAGS
from study.analysis import AnalysisError, morris_indices, sensitivity_table, sobol_indices
from study.campaign import expand_campaign
from study.run.assemble import assemble

#: Ishigami's constants (the common choice).
ISHIGAMI_A, ISHIGAMI_B = 7.0, 0.1
#: Morris check: the linear coefficient (negative: mu and mu* differ) and the interaction's.
C1, C23 = -1.5, 2.0


def _designed(tmp_path: Path, method: str, count: int, seed: int, **settings) -> xr.Dataset:
    """The campaign dataset of a ``[sample]`` design over :data:`RANGES`, every case finished.

    Expanded and assembled as ``run`` does (an output folder without case files: every result
    NaN), then every status set to converged, so the design, its coordinates and attributes,
    the text, flag and profile variables are the product's.
    """
    sample = {
        "method": method, "count": count, "seed": seed, **settings,
        **{k: {"distribution": "uniform", "range": list(r)} for k, r in RANGES.items()},
    }  # fmt: skip
    table = {"campaign": {"name": "designed", "fields": []}, "base": BASE, "sample": sample}
    campaign = expand_campaign(table, name="designed")
    out = tmp_path / "designed"
    out.mkdir(exist_ok=True)
    ds = assemble(out, campaign)
    finished = np.full(ds["status"].shape, STATUS_FLAGS["converged"], dtype=ds["status"].dtype)
    return ds.assign(status=ds["status"].copy(data=finished))


def _inputs(ds: xr.Dataset, low: float, high: float) -> list[np.ndarray]:
    """The sampled inputs of every case (coordinates of ``sample``), mapped onto [low, high]."""
    found = []
    for key, (start, stop) in RANGES.items():
        coord = next(c for c in ds.coords.values() if c.attrs.get("campaign_key") == key)
        found.append(low + (high - low) * (coord.values - start) / (stop - start))
    return found


def _ishigami(x1, x2, x3, a: float = ISHIGAMI_A, b: float = ISHIGAMI_B):
    return np.sin(x1) + a * np.sin(x2) ** 2 + b * x3**4 * np.sin(x1)


def _ishigami_variances(a: float = ISHIGAMI_A, b: float = ISHIGAMI_B) -> dict:
    """V, V1, V2, V3, V13 of Ishigami's function (module docstring)."""
    pi = math.pi
    return {
        "V": a**2 / 8 + b * pi**4 / 5 + b**2 * pi**8 / 18 + 0.5,
        "V1": 0.5 * (1 + b * pi**4 / 5) ** 2,
        "V2": a**2 / 8,
        "V3": 0.0,
        "V13": b**2 * pi**8 * (1 / 18 - 1 / 50),
    }


def _ishigami_indices() -> tuple[np.ndarray, np.ndarray]:
    """(S1, ST) of Ishigami's function, inputs in order."""
    v = _ishigami_variances()
    first = np.array([v["V1"], v["V2"], v["V3"]]) / v["V"]
    total = np.array([v["V1"] + v["V13"], v["V2"], v["V3"] + v["V13"]]) / v["V"]
    return first, total


# -- Sobol': Ishigami ------------------------------------------------------------------------------
def test_ishigami_closed_forms_are_its_variance_decomposition():
    """The closed forms against the definitions, by Gauss-Legendre quadrature (48^3 points)."""
    t, w = np.polynomial.legendre.leggauss(48)
    x, w = math.pi * t, w / 2  # weights of the uniform distribution on [-pi, pi]
    grid = np.meshgrid(x, x, x, indexing="ij")
    weight = w[:, None, None] * w[None, :, None] * w[None, None, :]
    f = _ishigami(*grid)
    mean = np.sum(weight * f)

    def explained(keep: tuple) -> float:  # Var(E[f | x_keep])
        others = tuple(i for i in range(3) if i not in keep)
        share = np.sum(weight, axis=others, keepdims=True)
        conditional = np.sum(weight * f, axis=others, keepdims=True) / share
        return float(np.sum(share * (conditional - mean) ** 2))

    exact = _ishigami_variances()
    v1, v2, v3 = explained((0,)), explained((1,)), explained((2,))
    assert np.sum(weight * (f - mean) ** 2) == pytest.approx(exact["V"], rel=1e-12)
    assert (v1, v2) == pytest.approx((exact["V1"], exact["V2"]), rel=1e-12)
    assert abs(v3) < 1e-12 * exact["V"]
    assert explained((0, 2)) - v1 - v3 == pytest.approx(exact["V13"], rel=1e-12)
    assert explained((1, 2)) - v2 - v3 == pytest.approx(0.0, abs=1e-12 * exact["V"])


@pytest.mark.validation
def test_sobol_indices_tell_first_order_from_total_on_ishigami(tmp_path, validation):
    """Saltelli N = 1024 (5120 rows): S1 and ST within their 95 % intervals of the closed forms,
    and x3 (no effect alone, a quarter of the variance with x1) separates them."""
    ds = _designed(tmp_path, "saltelli", 1024, 3)
    x = _inputs(ds, -math.pi, math.pi)
    ds["ishigami"] = (("sample",), _ishigami(*x), {"units": "1", "long_name": "Ishigami's f"})
    table = sobol_indices(ds, "ishigami")
    first, total = _ishigami_indices()
    s1, st = table["S1"].to_numpy(), table["ST"].to_numpy()
    s1_conf, st_conf = table["S1_conf"].to_numpy(), table["ST_conf"].to_numpy()
    assert sobol_indices(ds, "ishigami").equals(table)  # the bootstrap's seed holds (0 too)
    assert list(table["input"]) == ["load_normal_force", "body1_E", "body1_radius"]
    assert set(table["samples"]) == {1024} and set(table["left_out"]) == {0}
    assert np.all(np.abs(s1 - first) <= s1_conf), (s1, first, s1_conf)
    assert np.all(np.abs(st - total) <= st_conf), (st, total, st_conf)
    # what a swap of the columns would break: x3 alone explains nothing, with x1 a quarter
    assert abs(s1[2]) <= s1_conf[2] < total[2] / 2
    assert st[2] - s1[2] > st_conf[2] + s1_conf[2]
    assert st[0] - s1[0] > st_conf[0] + s1_conf[0]  # x1's share through x3
    validation(
        "Sobol' first-order and total indices apart (study.analysis.global_sensitivity)",
        "Ishigami a = 7, b = 0.1: S1 " + ", ".join(f"{v:.4f}" for v in first)
        + "; ST " + ", ".join(f"{v:.4f}" for v in total),
        "Saltelli N = 1024: S1 " + ", ".join(f"{v:.3f}" for v in s1)
        + " (+- " + ", ".join(f"{v:.3f}" for v in s1_conf) + "); ST "
        + ", ".join(f"{v:.3f}" for v in st) + " (+- " + ", ".join(f"{v:.3f}" for v in st_conf)
        + ")",
    )  # fmt: skip


# -- Morris: a linear input and an interaction -----------------------------------------------------
@pytest.mark.validation
def test_morris_measures_tell_mean_size_and_spread_apart(tmp_path, validation):
    """20 trajectories at 2 levels of f = c1 x1 + c23 x2 x3: x1's effects all 2 c1, x2's and
    x3's +-2 c23 (module docstring)."""
    levels, count = 2, 20
    ds = _designed(tmp_path, "morris", count, 4, levels=levels)
    x1, x2, x3 = _inputs(ds, -1.0, 1.0)
    ds["interacting"] = (("sample",), C1 * x1 + C23 * x2 * x3, {"units": "1"})
    table = morris_indices(ds, "interacting").set_index("input")
    delta = levels / (2 * (levels - 1))  # Morris' step in quantile level
    dx = 2.0 * delta  # the step in x: the whole interval [-1, 1]
    linear, interaction = C1 * dx / delta, abs(C23) * 1.0 * dx / delta  # |x3| = 1 at both levels
    row = table.loc["load_normal_force"]
    assert row["mu"] == pytest.approx(linear, rel=1e-9)
    assert row["mu_star"] == pytest.approx(abs(linear), rel=1e-9)
    assert row["sigma"] <= 1e-9 * abs(linear)
    for name in ("body1_E", "body1_radius"):
        row = table.loc[name]
        assert row["mu_star"] == pytest.approx(interaction, rel=1e-9)
        assert abs(row["mu"]) < row["mu_star"]  # effects of both signs
        spread = row["sigma"] ** 2 * (count - 1) / count  # the effects' own variance
        assert row["mu"] ** 2 + spread == pytest.approx(interaction**2, rel=1e-9)
        assert row["sigma"] > 0.25 * interaction
    assert set(table["trajectories"]) == {count}
    validation(
        "Morris' mu, mu* and sigma apart (study.analysis.global_sensitivity)",
        f"f = {C1} x1 + {C23} x2 x3 on [-1, 1]^3, 2 levels: mu1 = {linear:g}, mu*1 = "
        f"{abs(linear):g}, sigma1 = 0; mu*2 = mu*3 = {interaction:g}",
        f"{count} trajectories: mu " + ", ".join(f"{v:.3g}" for v in table["mu"])
        + "; mu* " + ", ".join(f"{v:.3g}" for v in table["mu_star"])
        + "; sigma " + ", ".join(f"{v:.3g}" for v in table["sigma"]),
    )  # fmt: skip


# -- refusals: one line naming the argument and what to give -------------------------------------
@pytest.fixture(scope="module")
def designs(tmp_path_factory) -> dict[str, xr.Dataset]:
    """Small designs of each method, with a varying max_pressure and a contact_radius <= 0 in
    places."""
    found = {}
    for method, count in (("saltelli", 8), ("morris", 4), ("lhs", 6)):
        ds = _designed(tmp_path_factory.mktemp(method), method, count, 1)
        x1, x2, x3 = _inputs(ds, 1.0, 2.0)
        found[method] = ds.assign(
            max_pressure=(("sample",), x1 * x2 + x3, {"units": "Pa"}),
            contact_radius=(("sample",), x1 - 1.5, {"units": "m"}),  # some <= 0
        )
    return found


def _refused(error, match: str, call):
    """Run ``call``; it must raise ``error`` with ``match`` in one line, from study.analysis."""
    with pytest.raises(error, match=match) as caught:
        call()
    assert "\n" not in str(caught.value)
    assert caught.value.__cause__ is None and caught.value.__context__ is None  # nothing raw
    raised_in = Path(str(caught.traceback[-1].path))
    assert raised_in.parent.name == "analysis" and raised_in.parent.parent.name == "study"
    return str(caught.value)


FUNCTIONS = {
    "sobol_indices": ("saltelli", sobol_indices),
    "morris_indices": ("morris", morris_indices),
    "sensitivity_table": ("saltelli", lambda ds, q, **kw: sensitivity_table(ds, q, "sample")),
}


@pytest.mark.parametrize("function", FUNCTIONS)
@pytest.mark.parametrize(
    ("quantity", "match"),
    [
        ("case_id", r"^quantity 'case_id' is not numeric \(it holds text\); give one of "
         r"max_pressure, contact_radius, "),
        ("status", r"^quantity 'status' is a flag \(case status\), not a measure; give one of "
         r"max_pressure"),
        ("pressure_profile", r"^quantity 'pressure_profile' has dims \(sample, r_over_a\), not "
         r"one number per case \(dims sample\): give one of max_pressure.*; or pick one value "
         r"along r_over_a first, e\.g\. dataset\.isel\(r_over_a=0\)$"),
        ("max_presure", r"^quantity 'max_presure': no such variable in the dataset; did you mean "
         r"'max_pressure'\? give one of max_pressure"),
        ("load_normal_force", r"^quantity 'load_normal_force' is an input \(a coordinate\); give "
         r"one of max_pressure"),
    ],
)  # fmt: skip
def test_a_quantity_that_is_not_one_number_per_case_is_refused_by_name(
    designs, function, quantity, match
):
    method, call = FUNCTIONS[function]
    text = _refused(AnalysisError, match, lambda: call(designs[method], quantity))
    assert "(and " in text and "more)" in text  # the list is cut, not every variable


@pytest.mark.parametrize("function", FUNCTIONS)
def test_a_path_or_another_object_is_refused_with_how_to_open_it(designs, function, tmp_path):
    method, call = FUNCTIONS[function]
    for path in ("out/x/x.nc", Path("out/x/x.nc")):
        _refused(
            TypeError,
            r"^dataset: got a path 'out/x/x\.nc'; open it first with xarray\.open_dataset\(path\)$",
            lambda path=path: call(path, "max_pressure"),
        )
    (tmp_path / "x.nc").write_bytes(b"")  # a campaign folder: its dataset is named
    _refused(
        TypeError,
        rf"^dataset: got a path '{re.escape(str(tmp_path))}'; open it first with "
        rf"xarray\.open_dataset\('{re.escape(str(tmp_path / 'x.nc'))}'\)$",
        lambda: call(tmp_path, "max_pressure"),
    )
    _refused(
        TypeError,
        r"^dataset: got a DataArray; give the campaign's xarray\.Dataset",
        lambda: call(designs[method]["max_pressure"], "max_pressure"),
    )
    _refused(
        TypeError,
        r"^quantity: got 3 \(int\), not a name; give one of max_pressure, ",
        lambda: call(designs[method], 3),
    )
    _refused(
        AnalysisError,
        r"^dataset: not a campaign dataset \(it has no status variable\)",
        lambda: call(xr.Dataset({"max_pressure": ("sample", [1.0, 2.0])}), "max_pressure"),
    )


def test_a_dataset_without_the_right_design_is_refused_naming_what_fits(designs):
    grid = designs["saltelli"].drop_vars(["sample_design", "sample_distribution"])
    for call, method in ((sobol_indices, "saltelli"), (morris_indices, "morris")):
        _refused(
            AnalysisError,
            rf"^dataset: .* need a \[sample\] design with method = '{method}'; it has none \(a "
            r"swept grid: sensitivity_table\(dataset, quantity, axis\)\)$",
            lambda call=call: call(grid, "max_pressure"),
        )
    _refused(
        AnalysisError,
        r"^dataset: Morris' elementary effects need a \[sample\] design with method = 'morris'; "
        r"it is 'saltelli': use sobol_indices\(dataset, quantity\)$",
        lambda: morris_indices(designs["saltelli"], "max_pressure"),
    )
    _refused(
        AnalysisError,
        r"^dataset: Sobol' indices need .* it is 'morris': use morris_indices\(",
        lambda: sobol_indices(designs["morris"], "max_pressure"),
    )
    _refused(
        AnalysisError,
        r"^dataset: Sobol' indices need .* it is 'lhs', a space-filling design that gives no "
        r"indices$",
        lambda: sobol_indices(designs["lhs"], "max_pressure"),
    )


@pytest.mark.parametrize(
    ("method", "call", "unit", "block", "counted", "index"),
    [
        ("saltelli", sobol_indices, "Saltelli block", 5, "samples", "S1"),
        ("morris", morris_indices, "Morris trajectory", 4, "trajectories", "mu_star"),
    ],
)
def test_a_design_cut_inside_a_block_is_refused_with_where_to_cut(
    designs, method, call, unit, block, counted, index
):
    ds = designs[method]
    rows = ds.sizes["sample"]
    assert (
        rows
        == int(ds.attrs["sample_count"]) * block
        == int(ds.attrs["sample_block"]) * (rows // block)
    )
    cut = 2 * block + 1
    _refused(
        AnalysisError,
        rf"^dataset: the design is cut inside a {unit} of {block} rows \({cut} sample rows, not a "
        rf"multiple of {block}\); keep whole ones, e\.g\. dataset\.isel\(sample=slice\(0, "
        rf"{2 * block}\)\)$",
        lambda: call(ds.isel(sample=slice(0, cut)), "max_pressure"),
    )
    _refused(
        AnalysisError,
        rf"^dataset: the design is cut inside a {unit} of {block} rows \(3 sample rows, .*; give "
        rf"at least one whole {unit} \(the full design has {rows} rows\)$",
        lambda: call(ds.isel(sample=slice(0, 3)), "max_pressure"),
    )
    # cut at a block's end, as suggested: indices of the blocks kept (the behaviour before)
    table = call(ds.isel(sample=slice(0, 2 * block)), "max_pressure")
    assert set(table[counted]) == {2} and set(table["left_out"]) == {0}
    assert np.all(np.isfinite(table[index]))


def test_log_of_a_quantity_with_values_below_zero_says_to_drop_log(designs):
    for method, call in (("saltelli", sobol_indices), ("morris", morris_indices)):
        _refused(
            AnalysisError,
            r"^quantity 'contact_radius': log needs positive values and it has some <= 0; "
            r"give log=False$",
            lambda call=call, method=method: call(designs[method], "contact_radius", log=True),
        )


def test_an_unknown_axis_of_the_finite_differences_is_refused(designs):
    _refused(
        AnalysisError,
        r"^axis 'friction_coefficient': not a dimension of the cases; give one of sample$",
        lambda: sensitivity_table(designs["saltelli"], "max_pressure", "friction_coefficient"),
    )
