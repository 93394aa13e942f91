"""Bit-identity check for refactors: every output array and case id, before against after.

``python -m study.bench.identical save DIR`` runs a set of small scenes and writes every array
of their results (``DIR/<scene>.npz``) and the case id, normalised table, warnings and memory
estimate of every case of every campaign in ``campaigns/`` (``DIR/cases.json``).
``python -m study.bench.identical compare DIR`` runs the same and compares value by value:
arrays must be equal bit for bit (dtype, shape, NaN where NaN), attributes and case ids equal.
It prints one row per scene and exits 1 on any difference.  ``--only NAME ...`` runs the
scenes whose name contains one of the names; ``--campaigns STEM ...`` checks the cases of those
campaigns only (all of them take about a minute: the shipped Sobol' design has 3,072).

The scenes are the first and last case of every shipped campaign on a coarser grid (each count
halved, floored at 12, or cut by a quarter where
halving is refused), a height map read from a file, and the benchmark scenes' small sizes:
elastic, friction with coupling, profiles, plasticity of every law, the four loops, cycles,
sliding, rolling, rough surfaces and a measured map.  Only the public API and
:mod:`study.campaign` are used, so the script runs unchanged on either side of a refactor of
:mod:`solver`'s modules.
"""

from __future__ import annotations

import argparse
import copy
import json
import pathlib
import sys
import tempfile
import time

import numpy as np

import solver

#: Attributes that measure the run rather than compute it.
TIMING_ATTRS = ("wall_time", "cpu_time")
CAMPAIGNS = pathlib.Path(__file__).resolve().parents[2] / "campaigns"
MIN_CELLS = 12


def _coarser(spec: dict, reader) -> dict:
    """The table with its cells halved (at least :data:`MIN_CELLS`), cut by 1/4, or as it was.

    The first of the three the solver accepts.
    """
    for factor in (0.5, 0.75):
        table = copy.deepcopy(spec)
        n = table["grid"]["n"]
        counts = [max(MIN_CELLS, int(k * factor)) for k in (n if isinstance(n, list) else [n])]
        table["grid"]["n"] = counts if isinstance(n, list) else counts[0]
        try:
            solver.Case.from_dict(table, reader)
        except solver.SpecError:
            continue
        return table
    return spec


def _campaigns(keep=lambda stem: True):
    """(file stem, campaign) of the shipped campaigns whose stem ``keep`` accepts."""
    from study.campaign import load_campaign

    for path in sorted(CAMPAIGNS.glob("*.toml")):
        if keep(path.stem):
            yield path.stem, load_campaign(str(path))


def _height_map_table(folder: pathlib.Path) -> dict:
    """A rigid sphere on a measured-like map (a wavy, seeded random surface) from a file."""
    import xarray as xr

    x = np.linspace(-0.6e-3, 0.6e-3, 97)
    y = np.linspace(-0.5e-3, 0.5e-3, 81)
    rng = np.random.default_rng(7)
    height = 0.3e-6 * np.sin(2 * np.pi * x / 0.2e-3)[None, :] * np.cos(2 * np.pi * y / 0.25e-3)[
        :, None
    ] + 0.05e-6 * rng.standard_normal((y.size, x.size))
    path = folder / "map.nc"
    xr.Dataset(
        {"height": (("y", "x"), height, {"units": "m"})},
        coords={"x": ("x", x, {"units": "m"}), "y": ("y", y, {"units": "m"})},
    ).to_netcdf(path)
    return {
        "body1": {"behaviour": "rigid", "radius": 0.015},
        "body2": {"behaviour": "elastic", "E": 210e9, "nu": 0.3, "surface": str(path)},
        "friction": {"coefficient": 0.3},
        "load": {
            "path": [
                {"normal_force": 60.0, "steps": 2},
                {"tangential_force": [10.0, 0.0], "steps": 2},
            ]
        },
        "grid": {"n": [48, 48], "half_width": 1.5},
    }


def scenes(folder: pathlib.Path, only: list[str] | None = None) -> dict[str, tuple[dict, object]]:
    """Scene name -> (case table, surface reader); only those whose name holds one of ``only``."""
    from study.bench.plastic import scene_table
    from study.campaign.surfaces import read_surface

    def wanted(name: str) -> bool:
        return not only or any(o in name for o in only)

    out = {}

    def scene_of(stem: str) -> bool:  # only the campaigns with a wanted scene: some are large
        return wanted(f"{stem}.first") or wanted(f"{stem}.last")

    for name, campaign in _campaigns(scene_of):
        for which, case in (("first", campaign.cases[0]), ("last", campaign.cases[-1])):
            if wanted(f"{name}.{which}"):
                out[f"{name}.{which}"] = (_coarser(case.spec, read_surface), read_surface)
    if wanted("height_map"):
        out["height_map"] = (_height_map_table(folder), read_surface)
    if wanted("bench_plastic_16"):
        out["bench_plastic_16"] = (scene_table(16), None)
    return out


def _arrays(result) -> tuple[dict[str, np.ndarray], dict]:
    """Every array of the result's dataset, and its attributes (timing left out)."""
    data = result.to_xarray()
    arrays = {f"var:{k}": np.asarray(v.values) for k, v in data.variables.items()}
    attrs = {k: v for k, v in data.attrs.items() if k not in TIMING_ATTRS}
    for k, v in data.variables.items():
        attrs[f"{k}.attrs"] = dict(v.attrs)
    return arrays, json.loads(json.dumps(attrs, default=repr))


def _cases(names: list[str] | None = None) -> dict:
    """Case id, normalised table, warnings and memory estimate of every campaign case.

    Of the campaigns ``names`` (file stems) only, when given.
    """
    out = {}
    for name, campaign in _campaigns(lambda stem: names is None or stem in names):
        out[name] = [
            {
                "case_id": c.case_id,
                "spec": c.spec,
                "warnings": list(c.warnings),
                "memory": c.memory,
            }
            for c in campaign.cases
        ]
    return json.loads(json.dumps(out, default=repr))


def _same(a: np.ndarray, b: np.ndarray) -> bool:
    if a.dtype != b.dtype or a.shape != b.shape:
        return False
    if a.dtype.kind in "fc":
        return bool(np.array_equal(a, b, equal_nan=True)) and bool(
            np.array_equal(np.signbit(a.real), np.signbit(b.real))
        )
    return bool(np.array_equal(a, b))


def run(
    folder: pathlib.Path,
    save: bool,
    only: list[str] | None = None,
    campaigns: list[str] | None = None,
) -> int:
    """Run every scene; save (``save``) or compare against what ``folder`` holds.

    ``only``: the scenes whose name contains one of these; ``campaigns``: the campaigns (file
    stems) whose cases are checked (default: all; a saved check then compares those only);
    2 (nothing run) when one is not a shipped campaign.
    """
    shipped = {path.stem for path in CAMPAIGNS.glob("*.toml")}
    unknown = sorted(set(campaigns or ()) - shipped)
    if unknown:
        print(f"error: --campaigns: no shipped campaign {unknown}; of {sorted(shipped)}")
        return 2
    folder.mkdir(parents=True, exist_ok=True)
    failures = 0
    cases = _cases(campaigns)
    cases_path = folder / "cases.json"
    if save:
        cases_path.write_text(json.dumps(cases, indent=1, sort_keys=True))
        print(f"cases: {sum(len(v) for v in cases.values())} case ids of {len(cases)} campaigns")
    else:
        before = json.loads(cases_path.read_text())
        if campaigns is not None:
            before = {name: found for name, found in before.items() if name in campaigns}
        differ = [
            f"{name}[{i}].{key}"
            for name in sorted(set(before) | set(cases))
            for i, (b, a) in enumerate(zip(before.get(name, []), cases.get(name, []), strict=False))
            for key in b
            if b[key] != a.get(key)
        ]
        differ += [n for n in set(before) ^ set(cases)]
        differ += [n for n in before if n in cases and len(before[n]) != len(cases[n])]
        total = sum(len(v) for v in cases.values())
        print(f"cases: {total} case ids of {len(cases)} campaigns; differing: {differ or 'none'}")
        failures += bool(differ)
    print(f"{'scene':42s} {'status':14s} {'arrays':>6s} {'differ':>6s} {'time (s)':>8s}")
    with tempfile.TemporaryDirectory() as tmp:
        for name, (table, reader) in scenes(pathlib.Path(tmp), only).items():
            start = time.perf_counter()
            result = solver.solve(solver.Case.from_dict(table, reader))
            arrays, attrs = _arrays(result)
            seconds = time.perf_counter() - start
            path = folder / f"{name}.npz"
            if save:
                np.savez(path, **arrays)
                (folder / f"{name}.json").write_text(json.dumps(attrs, indent=1, sort_keys=True))
                differ = []
            elif not path.exists():  # a scene the baseline's code did not have (a new campaign)
                differ = ["new: no baseline"]
            else:
                with np.load(path) as old:
                    keys = set(old.files) | set(arrays)
                    differ = [
                        k
                        for k in sorted(keys)
                        if k not in old.files or k not in arrays or not _same(old[k], arrays[k])
                    ]
                old_attrs = json.loads((folder / f"{name}.json").read_text())
                differ += [
                    f"attr:{k}"
                    for k in sorted(set(old_attrs) | set(attrs))
                    if old_attrs.get(k) != attrs.get(k)
                ]
                failures += bool(differ)
            print(
                f"{name:42s} {result.status:14s} {len(arrays):6d} {len(differ):6d} {seconds:8.1f}"
                + (f"  {', '.join(differ[:6])}" if differ else ""),
                flush=True,
            )
    return 1 if failures else 0


def main(argv: list[str] | None = None) -> int:
    """Command line: ``save DIR`` or ``compare DIR`` [``--only`` NAME ...] [``--campaigns`` ...]."""
    parser = argparse.ArgumentParser(prog="python -m study.bench.identical", description=__doc__)
    parser.add_argument("action", choices=("save", "compare"))
    parser.add_argument("folder", type=pathlib.Path)
    parser.add_argument(
        "--only", nargs="*", help="run only scenes whose name contains one of these"
    )
    parser.add_argument(
        "--campaigns", nargs="*", help="check only the cases of these campaigns (file stems)"
    )
    args = parser.parse_args(argv)
    return run(args.folder, args.action == "save", args.only, args.campaigns)


if __name__ == "__main__":
    sys.exit(main())
