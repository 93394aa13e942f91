"""Benchmark: a periodic rough interface with plasticity, ours and Tamaas' on the same heights.

``python -m study bench rough --periodic [--peers] [--error] [--sizes 32 64 128]``: one period (L =
100 um) of a self-affine surface (Hurst 0.8, rolloff at L/4, wavelengths down to L/16, rms
50 nm) on a steel half-space (E = 210 GPa, nu = 0.3, von Mises with linear hardening
sigma_Y = 1 GPa + 10 GPa e_p) pressed by a rigid flat to the mean pressures 0.25 and 0.5 GPa,
then unloaded; frictionless.  The heights are generated once, at :data:`REFERENCE` cells a
period (:func:`heights`), and every run reads them as a height map, so both codes and every
mesh see the same surface (Tamaas gets our gap on our cells, :mod:`.peers_rough`).  The
volume: L/8 deep, layers half a cell thick (n/4 layers; Tamaas n/4 + 1 node layers, the same
spacing).

Two tables.  Side by side: per code and mesh, the real contact area (fraction of the period)
at both loads, e_p,max, the rms of the residual topography after unloading (the gap of the
unloaded bodies about its mean), CPU, wall, resident-memory growth, iterations, and the
resolution of the mesh (cells across the largest contact spot at the largest load, by its
equivalent diameter; cells on the shortest wavelength).  Speed against error: each code's
results against ours on the finest mesh of the run, or with ``--error`` against the limit
fitted over our meshes (:func:`.plastic.error_table`; three sizes or more), the peer then
only up to :data:`PEER_ERROR_LARGEST`.
Each code in a child process (:func:`.timing.isolated`), one thread.
"""

from __future__ import annotations

import functools
import time

import numpy as np

from .timing import format_table, isolated, peak_memory

#: The period (m), the material and the loads of the scene.
SCENE = {
    "period": 1e-4,
    "E": 210e9,
    "nu": 0.3,
    "yield_stress": 1e9,
    "hardening_modulus": 10e9,
    "mean_pressures": (0.25e9, 0.5e9),
}
#: The roughness (m) on the period.
ROUGHNESS = {"hurst": 0.8, "long_cutoff": 2.5e-5, "short_cutoff": 6.25e-6, "rms": 5e-8, "seed": 7}
#: Cells a period of the mesh the heights are generated on.
REFERENCE = 256
#: Depth of the volume over the period.
DEPTH = 0.125
#: Largest mesh Tamaas runs on (cells a period): at 256 it would take about ten hours here
#: (267 s at 64, 8 to 16 times more for each doubling); ours runs on every size asked for.
PEER_LARGEST = 128
#: Largest mesh Tamaas runs on for ``--error`` (its trend, at a few minutes a run).
PEER_ERROR_LARGEST = 64
#: Longest a peer's run may take (s): Tamaas at 128 cells takes more than the default half hour.
PEER_TIMEOUT = 4 * 3600.0
#: Layers per cell width: layers half a cell thick (on cubic cells weak hardening lets the
#: plasticity loop stall, :func:`solver.case.notes.layer_note`).
LAYERS = 2


@functools.lru_cache(maxsize=1)
def heights():
    """The scene's heights: one period as a height map (generated on :data:`REFERENCE` cells)."""
    import solver
    from solver.bodies.heights import HeightMap
    from solver.drive.operators import initial_gap

    table = _table(REFERENCE, {"roughness": ROUGHNESS}, elastic=True)
    case = solver.Case.from_dict(table)
    grid = case.surface_grid
    return HeightMap(grid.x, grid.y, initial_gap(case).T, "rough period")


def steel(elastic: bool = False) -> dict:
    """The scene's flat steel half-space as a body table (linearly hardening unless elastic)."""
    s = SCENE
    body = {"behaviour": "elastic", "E": s["E"], "nu": s["nu"], "radius": "inf"}
    if not elastic:
        body["behaviour"] = "elastic-plastic"
        body["hardening"] = {
            "law": "linear",
            "yield_stress": s["yield_stress"],
            "modulus": s["hardening_modulus"],
        }
    return body


def _table(n: int, surface: dict | None = None, elastic: bool = False) -> dict:
    s = SCENE
    period = s["period"]
    body2 = steel(elastic) | (surface if surface is not None else {"surface": heights()})
    grid = {"n": [n, n], "size": period, "periodic": True}
    if not elastic:
        grid.update(n=[n, n, max(4, round(LAYERS * DEPTH * n))], depth=DEPTH * period)
    area = period * period
    path = [{"normal_force": p * area, "steps": 1} for p in s["mean_pressures"]]
    return {
        "body1": {"behaviour": "rigid", "radius": "inf"},
        "body2": body2,
        "load": {"path": [*path, {"normal_force": 0.0, "steps": 1}]},
        "grid": grid,
    }


def scene_table(n: int) -> dict:
    """The case table of the scene on ``n x n`` cells a period (n/4 layers)."""
    return _table(n)


def _ours(n: int) -> dict:
    import solver
    from solver.drive.record import cells_across

    case = solver.Case.from_dict(scene_table(n))
    with peak_memory() as memory:
        c0, t0 = time.process_time(), time.perf_counter()
        result = solver.solve(case)
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    h = result.history
    loads = len(SCENE["mean_pressures"])
    residual = result.fields["residual_gap"]
    largest = result.fields["spot_areas"][loads - 1]  # the spots at the largest load
    largest = largest[np.isfinite(largest)]
    return {
        "spot_cells": cells_across(largest[0], case.surface_grid) if largest.size else 0.0,
        "area": [float(v) for v in h["contact_fraction"][:loads]],
        "ep_max": [float(v) for v in h["max_plastic_strain"][:loads]],
        "residual_rms": float(np.std(residual)),
        "initial_rms": float(np.std(result.fields["initial_gap"])),
        "time": wall,
        "cpu": cpu,
        "memory": memory["peak_MB"],
        "iterations": int(np.sum(h["plastic_iterations"])),
        "converged": result.converged,
    }


def _inputs(n: int) -> dict:
    """Plain numbers and arrays for the peer's child (it must not load our FFTW build)."""
    import solver
    from solver.drive.operators import initial_gap

    case = solver.Case.from_dict(scene_table(n))
    return {
        "gap": initial_gap(case),
        "side": SCENE["period"],
        "depth": case.volume_grid.dz * case.volume_grid.nz,
        "layers": case.volume_grid.nz,
    }


def _tamaas(inputs: dict) -> dict:
    from .peers_rough import tamaas_rough

    s = SCENE
    gap = inputs["gap"]
    out = tamaas_rough(
        -gap,  # heights of the rigid surface towards the half-space
        inputs["side"],
        E=s["E"],
        nu=s["nu"],
        mean_pressures=list(s["mean_pressures"]),
        plastic={"yield_stress": s["yield_stress"], "hardening_modulus": s["hardening_modulus"]},
        depth=inputs["depth"],
        nz=inputs["layers"] + 1,  # node layers, the surface included: the same spacing
        unload=True,
    )
    # the unloaded gap: the initial gap plus the print (Tamaas' has zero mean)
    residual = gap + out["residual_topography"]
    return {
        "area": out["area_fraction"],
        "ep_max": out["ep_max"],
        "residual_rms": float(np.std(residual)),
        "initial_rms": float(np.std(gap)),
        "time": out["time"],
        "cpu": out["cpu"],
        "memory": out["memory"],
        "iterations": out.get("iterations"),
        "converged": out["converged"],
    }


def _row(code: str, n: int, out: dict, reference: dict | None) -> dict:
    loads = SCENE["mean_pressures"]
    row = {"code": code, "n": n}
    for i, p in enumerate(loads):
        row[f"area_{p / 1e9:g}GPa_%"] = 100 * out["area"][i]
    row["ep_max"] = out["ep_max"][-1]
    row["residual_rms_nm"] = out["residual_rms"] * 1e9
    row["spot_cells"] = out.get("spot_cells")  # ours only: the peer's spots are not read
    row["wave_cells"] = n * ROUGHNESS["short_cutoff"] / SCENE["period"]
    if reference is not None:
        row["area_err_%"] = 100 * max(
            abs(a / b - 1) for a, b in zip(out["area"], reference["area"], strict=True)
        )
        row["ep_err_%"] = 100 * abs(out["ep_max"][-1] / reference["ep_max"][-1] - 1)
        row["rms_err_%"] = 100 * abs(out["residual_rms"] / reference["residual_rms"] - 1)
    row.update(
        cpu_s=out["cpu"], wall_s=out["time"], peak_MB=out["memory"],
        iterations=out["iterations"], converged=out["converged"],
    )  # fmt: skip
    return row


def run_rough_periodic(sizes: list[int], peers: bool = False, error: bool = False) -> int:
    """Run the periodic rough scene over ``sizes``, print both tables, return an exit status.

    ``error``: the speed-error table against the limit fitted over our meshes.
    """
    have_tamaas = False
    if peers:
        from .peers import available_peers

        found = available_peers()
        have_tamaas = "tamaas" in found
        print("peers:", f"tamaas {found['tamaas']}" if have_tamaas else "tamaas not installed")
    peer_largest = PEER_ERROR_LARGEST if error else PEER_LARGEST
    if have_tamaas and max(sizes) > peer_largest:
        print(f"tamaas runs up to n = {peer_largest} (it would take hours above)")
    results, failures = {}, 0
    for n in sorted(sizes):
        runs = {("slipstick", n): isolated(_ours, n)}
        if have_tamaas and n <= peer_largest:
            runs["tamaas", n] = isolated(_tamaas, _inputs(n), timeout=PEER_TIMEOUT)
        for key, (status, out) in runs.items():
            if status == "ok":
                results[key] = out
            else:
                failures += 1
                print(f"{key[0]} n={key[1]}: {out}")
    finest = max((n for code, n in results if code == "slipstick"), default=None)
    reference = results.get(("slipstick", finest))
    side, against = [], []
    for (code, n), out in sorted(results.items(), key=lambda item: (item[0][1], item[0][0])):
        other = results.get(("tamaas" if code == "slipstick" else "slipstick", n))
        row = _row(code, n, out, other)
        side.append(row)
        if reference is not None and (code, n) != ("slipstick", finest):
            against.append(_row(code, n, out, reference))
    s = SCENE
    print(
        f"Periodic rough interface: L = {s['period'] * 1e6:g} um, self-affine H 0.8 (L/4 to "
        f"L/16, rms {ROUGHNESS['rms'] * 1e9:g} nm), rigid flat on steel (sigma_Y = 1 GPa + 10 "
        "GPa e_p), mean pressures 0.25 and 0.5 GPa then unloaded; volume L/8 deep, layers half "
        "a cell thick; one thread.  err: largest over the loads against the other code at the "
        "same n"
    )
    print(format_table(side))
    if error:
        from .plastic import error_table

        print("Speed against error: each code against the limit fitted over our meshes")
        error_table(side, quantities=ERROR_QUANTITIES, carry=("spot_cells", "wave_cells"))
    elif against:
        print(f"Speed against error: each code against slipstick at n = {finest}")
        print(format_table(against))
    return 1 if failures else 0


#: Quantities of the ``--error`` table: table column -> (short name, what it is).
ERROR_QUANTITIES = {
    **{
        f"area_{p / 1e9:g}GPa_%": (f"area{i + 1}", f"real area at {p / 1e9:g} GPa")
        for i, p in enumerate(SCENE["mean_pressures"])
    },
    "ep_max": ("ep", "e_p,max"),
    "residual_rms_nm": ("rms", "residual topography rms"),
}
