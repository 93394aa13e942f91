"""Bundles (study.bundle): many cases in one file, read back bit for bit."""

import h5py
import numpy as np
import pytest

from study import bundle


def _record(k: int) -> bundle.CaseRecord:
    """A case with every kind of variable a result holds, values depending on ``k``."""
    rng = np.random.default_rng(k)
    return bundle.CaseRecord(
        coords={
            "x": ("x", np.linspace(-1.0, 1.0, 5 + k), {"units": "m"}),
            "component": ("component", ["xx", "yy", "zz"]),  # strings: no attributes
        },
        data={
            "pressure": (("x", "y"), rng.standard_normal((5 + k, 3)), {"units": "Pa"}),
            "state": (("x", "y"), rng.integers(0, 3, (5 + k, 3)).astype(np.int8), {}),
            "stress": (("component", "x"), rng.standard_normal((3, 5 + k)).astype(np.float32), {}),
            "step_converged": ("step", np.array([True, k % 2 == 0, False]), {}),
            "shakedown": ((), np.int8(k), {"reason": f"case {k}", "flags": np.arange(3)}),
            "force": ("step", np.array([np.nan, -0.0, 1e-308 * k]), {}),
        },
        attrs={"status": "converged", "k": k, "tiny": 5e-324, "big": np.float64(1.7e308)},
    )


def test_results_and_failures_are_read_back_bit_for_bit(tmp_path):
    entries = [
        bundle.Entry(f"case{k}", "converged", record=_record(k), summary={"k": k}) for k in range(3)
    ]
    entries.insert(1, bundle.Entry("bad", "failed", failure={"error": "ValueError: no"}))
    path = bundle.write_bundle(tmp_path / f"a{bundle.SUFFIX}", entries, {"host": "h", "rank": 1})
    assert bundle.read_index(path) == (
        ["case0", "bad", "case1", "case2"],
        ["converged", "failed", "converged", "converged"],
    )
    with bundle.Reader(path) as reader:
        assert reader.meta(1) == {"failure": {"error": "ValueError: no"}}
        assert reader.summary(1) is None and reader.summary(3) == {"k": 2}
        with pytest.raises(bundle.BundleError, match="failure record"):
            reader.record(1)
        for position, k in ((0, 0), (2, 1), (3, 2)):
            read, given = reader.record(position), _record(k)
            assert read.attrs == {"host": "h", "rank": 1, **given.attrs}
            for parts in ("coords", "data"):
                for name, (dims, values, attrs) in getattr(given, parts).items():
                    got = getattr(read, parts)[name]
                    assert got[0] == ((dims,) if isinstance(dims, str) else tuple(dims))
                    values = np.asarray(values)
                    assert got[1].dtype == values.dtype and got[1].shape == values.shape
                    assert got[1].tobytes() == values.tobytes(), name  # NaN, -0, denormals
                    assert got[2].keys() == attrs.keys()
            np.testing.assert_array_equal(read.variable_attrs("shakedown")["flags"], np.arange(3))
            lazy = reader.record(position, lazy=True).to_xarray()
            np.testing.assert_array_equal(lazy["pressure"].values, read.values("pressure"))
    index = bundle.scan(tmp_path)
    assert set(index.results) == {"case0", "case1", "case2"} and set(index.failures) == {"bad"}
    assert bundle.find_result(tmp_path, "case1").values("x").size == 6


def test_a_later_result_clears_a_failure_and_damage_is_named(tmp_path):
    failed = bundle.Entry("c", "failed", failure={"error": "first try"})
    bundle.write_bundle(tmp_path / f"1{bundle.SUFFIX}", [failed], {})
    assert set(bundle.scan(tmp_path).failures) == {"c"}
    good = bundle.Entry("c", "converged", record=_record(0))
    bundle.write_bundle(tmp_path / f"2{bundle.SUFFIX}", [good], {})
    index = bundle.scan(tmp_path)
    assert set(index.results) == {"c"} and not index.failures and not index.corrupt
    newer = tmp_path / f"3{bundle.SUFFIX}"
    bundle.write_bundle(newer, [good], {})
    with h5py.File(newer, "a") as handle:
        handle.attrs["slipstick_bundle"] = bundle.FORMAT + 1
    assert "newer than this version's" in bundle.scan(tmp_path).corrupt[newer.name]
