"""Benchmarks: speed against error, ours and the peers' in the same run.

``python -m study bench hertz [--peers]`` solves the rigid-sphere Hertz case (R = 15 mm, steel,
p_H = 6 GPa, domain side 3.2 a_H) at several grid sizes.  Every row runs in a fresh child
process.  Its memory figure is the growth of that process's resident set, sampled every 2 ms
during setup and solves (imports and inputs excluded), so that codes in C++ and in Python are
measured alike.  Times are wall-clock seconds, best of ``repeat`` solves; ``setup`` (kernel and
FFT-plan construction, reused across load steps and cases) is reported apart from ``solve``.
Our rows: ``slipstick`` plans its FFTs by timing (``solver.fft_planner = "measure"``),
``slipstick (estimate)`` uses the reproducible default.
"""

from __future__ import annotations

import math
import time

import numpy as np

from .timing import format_table, isolated, peak_memory

HERTZ_TABLE = {
    "body1": {"radius": 0.015, "behaviour": "rigid"},
    "body2": {"radius": "inf", "behaviour": "elastic", "E": 210e9, "nu": 0.3},
    "load": {"hertz_pressure": 6e9, "steps": 1},
    "friction": {"coefficient": 0.0},
    "grid": {"n": 128, "half_width": 1.6},
}


def _ours_hertz(n: int, repeat: int, planner: str = "measure") -> dict:
    import solver
    from solver.drive.operators import planner_flag
    from solver.surface.convolution import surface_operator

    table = {**HERTZ_TABLE, "grid": {"n": n, "half_width": 1.6}}
    table["solver"] = {"fft_planner": planner}
    case = solver.Case.from_dict(table)
    with peak_memory() as memory:
        t0 = time.perf_counter()
        operator = surface_operator(case.surface_grid, case.pair, 1, planner_flag(case.solver))
        operator.kernel_spectrum("zz")
        operator.inverse_normal(np.zeros(case.surface_grid.shape))
        setup = time.perf_counter() - t0
        best, cpu, result = math.inf, math.inf, None
        for _ in range(repeat):
            c0, t0 = time.process_time(), time.perf_counter()
            result = solver.solve(case)
            best = min(best, time.perf_counter() - t0)
            cpu = min(cpu, time.process_time() - c0)
    return {
        "pressure": result.pressure,
        "dx": case.surface_grid.dx,
        "time": best,
        "cpu": cpu,
        "setup": setup,
        "iterations": int(result.history["normal_iterations"][-1]),
        "approach": result.history["approach"][-1],
        "memory": memory["peak_MB"],
        "converged": result.converged,
    }


def _hertz_parameters(n: int) -> dict:
    """The Hertz scene as plain numbers (peers' children must not load our FFTW build)."""
    from solver import Case

    case = Case.from_dict({**HERTZ_TABLE, "grid": {"n": n, "half_width": 1.6}})
    grid = case.surface_grid
    return {
        "radius": 0.015,
        "contact_modulus": case.pair.composite_modulus,
        "normal_force": case.hertz.normal_force,
        "side": grid.nx * grid.dx,
    }


def _peer_hertz(name: str, n: int, repeat: int, parameters: dict) -> dict:
    # Runs in a child that never imports pyfftw: Tamaas links its own FFTW, and with both
    # loaded Tamaas stalled at 256^2 here.
    from .peers import hertz_peer

    best = None
    with peak_memory() as memory:
        for _ in range(repeat):
            out = hertz_peer(name, n=n, **parameters)
            if best is None or out["time"] < best["time"]:
                best = out
    best["memory"] = memory["peak_MB"]
    best["dx"] = parameters["side"] / n
    return best


def _hertz_row(code: str, n: int, out: dict) -> dict:
    from solver import Case

    case = Case.from_dict({**HERTZ_TABLE, "grid": {"n": n, "half_width": 1.6}})
    reference = case.hertz
    pressure = np.asarray(out["pressure"])
    in_contact = pressure > 1e-9 * pressure.max()
    radius = math.sqrt(np.count_nonzero(in_contact) * out["dx"] ** 2 / math.pi)
    approach = out.get("approach")
    return {
        "code": code,
        "n": n,
        "setup_s": out.get("setup", float("nan")),
        "solve_s": out["time"],
        "cpu_s": out["cpu"],
        "pmax_err_%": 100 * abs(pressure.max() / reference.max_pressure - 1),
        "radius_err_cells": abs(radius - reference.radius) / out["dx"],
        "approach_err_%": (
            100 * abs(approach / reference.approach - 1) if approach is not None else float("nan")
        ),
        "iterations": out.get("iterations"),
        "peak_MB": out["memory"],
    }


def run_hertz(sizes: list[int], peers: bool = False, repeat: int = 3) -> int:
    """Run the Hertz scene over ``sizes``, print its table, and return an exit status."""
    peer_names = []
    if peers:
        from .peers import available_peers

        found = available_peers()
        print("peers:", ", ".join(f"{k} {v}" for k, v in found.items()) or "none installed")
        peer_names = list(found)
    rows, failures = [], 0
    for n in sizes:
        for planner in ("measure", "estimate"):
            code = "slipstick" if planner == "measure" else "slipstick (estimate)"
            status, out = isolated(_ours_hertz, n, repeat, planner)
            if status == "ok":
                rows.append(_hertz_row(code, n, out))
            else:
                failures += 1
                print(f"{code} n={n}: {out}")
        for name in peer_names:
            status, out = isolated(_peer_hertz, name, n, repeat, _hertz_parameters(n))
            if status == "ok":
                rows.append(_hertz_row(name, n, out))
            else:
                print(f"{name} n={n}: {out}")
    print("Hertz: rigid sphere R = 15 mm on steel, p_H = 6 GPa, domain 3.2 a_H, one thread")
    print(format_table(rows))
    return 1 if failures else 0
