"""Benchmark: a rough sphere, ours and Tamaas' on the same heights, in the same run.

``python -m study bench rough [--peers]``: a rigid sphere (R = 15 mm) with a self-affine
roughness (rms 0.25 of the smooth Hertz approach at the largest load, H = 0.8, wavelengths from
a_H/8 to a_H) on a steel half-space, loaded in three steps to the force of p_H = 1.5 GPa; domain
3.2 a_H, non-periodic.  Tamaas gets our gap on our cells (heights = -gap) and its non-periodic
Boussinesq operator (``ModelFactory.registerNonPeriodic``, the same problem), one
``PolonskyKeerRey`` solve per load.  Per code and mesh: real contact area and peak pressure at
every load, their difference from the other code at the same mesh, the number of contact spots
(:func:`solver.drive.record.contact_spots`), CPU, wall and resident-memory growth; each code in a
child process (:func:`.timing.isolated`), one thread.
"""

from __future__ import annotations

import time

import numpy as np

from solver.drive.record import contact_spots

from .timing import format_table, isolated, peak_memory

#: Loads of the scene, as fractions of the largest.
LOAD_FRACTIONS = (0.25, 0.5, 1.0)


def scene_table(n: int) -> dict:
    """The case table of the rough sphere at ``n`` x ``n`` cells."""
    import solver

    smooth = {
        "body1": {"behaviour": "rigid", "radius": 0.015},
        "body2": {"behaviour": "elastic", "E": 210e9, "nu": 0.3},
        "load": {"path": [{"hertz_pressure": 1.5e9 * f ** (1 / 3), "steps": 1}
                          for f in LOAD_FRACTIONS]},
        "grid": {"n": n, "half_width": 1.6},
    }  # fmt: skip
    hertz = solver.Case.from_dict(smooth).hertz
    smooth["body1"]["roughness"] = {
        "rms": 0.25 * hertz.approach,
        "hurst": 0.8,
        "long_cutoff": hertz.radius,
        "short_cutoff": hertz.radius / 8,
        "seed": 1,
    }
    return smooth


def _ours(n: int) -> dict:
    import solver

    case = solver.Case.from_dict(scene_table(n))
    with peak_memory() as memory:
        c0, t0 = time.process_time(), time.perf_counter()
        result = solver.solve(case)
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    h = result.history
    return {
        "area": list(h["contact_area"]),
        "pmax": list(h["max_pressure"]),
        "spots": int(h["contact_spots"][-1]),
        "time": wall,
        "cpu": cpu,
        "memory": memory["peak_MB"],
        "iterations": int(np.sum(h["normal_iterations"])),
        "converged": result.converged,
    }


def _inputs(n: int) -> dict:
    """Plain numbers and arrays for the peer's child (it must not load our FFTW build)."""
    import solver

    case = solver.Case.from_dict(scene_table(n))
    grid = case.surface_grid
    return {
        "gap": case.pair.geometry.gap(*grid.mesh()),
        "side": grid.nx * grid.dx,
        "contact_modulus": case.pair.composite_modulus,
        "forces": [stage.normal_force for stage in case.stages],
        "cell_area": grid.cell_area,
    }


def _tamaas(inputs: dict) -> dict:
    import tamaas as tm

    from .peers import _captured_output, _tamaas_iterations, _thread_limit

    gap, side = inputs["gap"], inputs["side"]
    n = gap.shape[0]
    areas, peaks, iterations, converged = [], [], 0, True
    with peak_memory() as memory, _thread_limit(1):
        c0, t0 = time.process_time(), time.perf_counter()
        model = tm.ModelFactory.createModel(tm.model_type.basic_2d, [side, side], [n, n])
        model.E = inputs["contact_modulus"]  # nu = 0: Tamaas' E* is E
        model.nu = 0.0
        tm.ModelFactory.registerNonPeriodic(model, "hertz")
        solver = tm.PolonskyKeerRey(model, -gap, 1e-10)
        solver.setIntegralOperator("hertz")
        solver.max_iter = 5000
        for force in inputs["forces"]:
            log: list[str] = []
            with _captured_output(log):
                error = solver.solve(force / side**2)
            converged &= bool(error < 1e-10)
            iterations += (_tamaas_iterations(log[0]) or 0) if log else 0
            pressure = np.array(model.traction, dtype=float).reshape(n, n)
            areas.append(float(np.count_nonzero(pressure > 0)) * inputs["cell_area"])
            peaks.append(float(pressure.max()))
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    return {
        "area": areas,
        "pmax": peaks,
        "spots": contact_spots(pressure > 0),  # the same count on Tamaas' pressure
        "time": wall,
        "cpu": cpu,
        "memory": memory["peak_MB"],
        "iterations": iterations,
        "converged": converged,
    }


def run_rough(
    sizes: list[int], peers: bool = False, periodic: bool = False, error: bool = False
) -> int:
    """Run the rough-sphere scene over ``sizes``, print its table, return an exit status.

    ``periodic``: the periodic rough interface with plasticity instead
    (:func:`.rough_periodic.run_rough_periodic`), ``error`` its speed-error table.
    """
    if periodic:
        from .rough_periodic import run_rough_periodic

        return run_rough_periodic(sizes, peers, error)
    if error:
        from .registry import BenchOptionError

        raise BenchOptionError("--error: the rough sphere has no error table (add --periodic)")
    have_tamaas = False
    if peers:
        from .peers import available_peers

        found = available_peers()
        have_tamaas = "tamaas" in found
        print("peers:", f"tamaas {found['tamaas']}" if have_tamaas else "tamaas not installed")
    rows, failures = [], 0
    for n in sizes:
        runs = {"slipstick": isolated(_ours, n)}
        if have_tamaas:
            runs["tamaas"] = isolated(_tamaas, _inputs(n))
        outs = {code: out for code, (status, out) in runs.items() if status == "ok"}
        for code, (status, out) in runs.items():
            if status != "ok":
                failures += 1
                print(f"{code} n={n}: {out}")
        for code, out in outs.items():
            other = next((o for c, o in outs.items() if c != code), None)
            row = {"code": code, "n": n}
            for i, fraction in enumerate(LOAD_FRACTIONS):
                row[f"area_{fraction:g}W_mm2"] = out["area"][i] * 1e6
            row["pmax_W_GPa"] = out["pmax"][-1] / 1e9
            if other is not None:
                row["area_diff_%"] = 100 * max(
                    abs(a / b - 1) for a, b in zip(out["area"], other["area"], strict=True)
                )
                row["pmax_diff_%"] = 100 * max(
                    abs(a / b - 1) for a, b in zip(out["pmax"], other["pmax"], strict=True)
                )
            row.update(
                spots=out["spots"], cpu_s=out["cpu"], wall_s=out["time"],
                iterations=out["iterations"], peak_MB=out["memory"], converged=out["converged"],
            )  # fmt: skip
            rows.append(row)
    print(
        "Rough sphere: rigid R = 15 mm with roughness (rms 0.25 Hertz approach, H 0.8, "
        "a_H/8 to a_H) on steel, 3 loads to p_H = 1.5 GPa, domain 3.2 a_H, one thread; "
        "diff: largest over the loads against the other code at the same n"
    )
    print(format_table(rows))
    return 1 if failures else 0
