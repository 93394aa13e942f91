"""Cattaneo-Mindlin benchmark: partial slip of a rigid sphere on an incompressible half-space.

With nu = 0.5 Dundurs' beta vanishes for every code (Tamaas couples normal and tangential
elasticity, ASPHER does not), so all of them solve the same classical problem: normal load W,
then a tangential force Q = 0.5 mu W.  Errors are against the closed forms: stick radius
c/a = (1 - Q/(mu W))^(1/3) (stick cells: |q| < mu p (1 - 1e-3), the same rule for every code)
and the tangential compliance delta = 3 mu W (2 - nu)/(16 G a) [1 - (1 - Q/(mu W))^(2/3)].
Each row runs in a fresh process (see :mod:`study.bench`); ``time`` covers the whole load path.
"""

from __future__ import annotations

import math
import time

import numpy as np

from .timing import format_table, isolated, peak_memory

E_STAR = 210e9 / (1 - 0.3**2)  # steel's contact modulus
NU = 0.5
YOUNG = E_STAR * (1 - NU**2)
RADIUS, FORCE, MU, FRACTION, HALF_WIDTH = 0.015, 1000.0, 0.3, 0.5, 1.6
#: Tamaas solves periodic cells twice the window; beyond this size it takes many minutes.
TAMAAS_MAX_N = 128


def _table(n: int) -> dict:
    return {
        "body1": {"radius": RADIUS, "behaviour": "rigid"},
        "body2": {"radius": "inf", "behaviour": "elastic", "E": YOUNG, "nu": NU},
        "load": {
            "path": [
                {"normal_force": FORCE, "steps": 1},
                {"tangential_force": [FRACTION * MU * FORCE, 0.0], "steps": 1},
            ]
        },
        "friction": {"coefficient": MU},
        "grid": {"n": n, "half_width": HALF_WIDTH},
    }


def _ours(n: int, repeat: int) -> dict:
    import solver
    from solver.surface.convolution import surface_operator

    table = _table(n)
    table["solver"] = {"fft_planner": "measure"}
    case = solver.Case.from_dict(table)
    with peak_memory() as memory:
        t0 = time.perf_counter()
        operator = surface_operator(case.surface_grid, case.pair, 1, "FFTW_MEASURE")
        operator.kernel_spectrum("zz"), operator.kernel_spectrum("xx")
        setup = time.perf_counter() - t0
        best, cpu = math.inf, math.inf
        for _ in range(repeat):
            c0, t0 = time.process_time(), time.perf_counter()
            result = solver.solve(case)
            best = min(best, time.perf_counter() - t0)
            cpu = min(cpu, time.process_time() - c0)
    h = result.history
    return {
        "pressure": result.pressure,
        "shear_x": result.shear_x,
        "shear_y": result.shear_y,
        "x": result.grid.x,
        "tangential_shift": h["tangential_shift_x"][-1],
        "time": best,
        "cpu": cpu,
        "setup": setup,
        "iterations": int(h["slip_iterations"].sum() + h["normal_iterations"].sum()),
        "converged": result.converged,
        "memory": memory["peak_MB"],
    }


def _peer(name: str, n: int, repeat: int) -> dict:
    from solver import Case

    from .peers import cattaneo_peer

    case = Case.from_dict(_table(n))
    grid = case.surface_grid
    best = None
    with peak_memory() as memory:
        for _ in range(repeat):
            out = cattaneo_peer(
                name,
                n=n,
                radius=RADIUS,
                young_modulus=YOUNG,
                poisson_ratio=NU,
                normal_force=FORCE,
                tangential_force=FRACTION * MU * FORCE,
                friction_coefficient=MU,
                side=grid.nx * grid.dx,
            )
            if best is None or out["cpu"] < best["cpu"]:
                best = out
    best["memory"] = memory["peak_MB"]
    return best


def _row(code: str, n: int, out: dict) -> dict:
    from solver import Case

    from .peers import stick_radius_ratio

    case = Case.from_dict(_table(n))
    a = case.hertz.radius
    ratio = stick_radius_ratio(out, MU, a)
    shear_modulus = YOUNG / (2 * (1 + NU))
    compliance = 3 * MU * FORCE * (2 - NU) / (16 * shear_modulus * a)
    shift_ref = compliance * (1 - (1 - FRACTION) ** (2 / 3))
    shift = out.get("tangential_shift")
    return {
        "code": code,
        "n": n,
        "setup_s": out.get("setup", float("nan")),
        "time_s": out["time"],
        "cpu_s": out["cpu"],
        "c/a": ratio,
        "c/a_err": abs(ratio - (1 - FRACTION) ** (1 / 3)),
        "shift_err_%": 100 * abs(shift / shift_ref - 1) if shift is not None else float("nan"),
        "pmax_err_%": 100 * abs(np.max(out["pressure"]) / case.hertz.max_pressure - 1),
        "iterations": out.get("iterations"),
        "converged": out.get("converged"),
        "peak_MB": out["memory"],
    }


def run_cattaneo(sizes: list[int], peers: bool = False, repeat: int = 3) -> int:
    """Run the Cattaneo-Mindlin benchmark and print its table; returns an exit status."""
    names = []
    if peers:
        from .peers import available_peers

        found = available_peers()
        names = [name for name in found if name != "contactmechanics"]  # no friction solver
        print("peers:", ", ".join(f"{k} {found[k]}" for k in names) or "none installed")
    rows, failures = [], 0
    for n in sizes:
        status, out = isolated(_ours, n, repeat)
        if status == "ok":
            rows.append(_row("slipstick", n, out))
        else:
            failures += 1
            print(f"slipstick n={n}: {out}")
        for name in names:
            if name == "tamaas" and n > TAMAAS_MAX_N:
                print(f"tamaas n={n}: skipped (periodic cell of {2 * n}^2, many minutes)")
                continue
            status, out = isolated(_peer, name, n, 1 if name == "tamaas" else repeat)
            if status == "ok":
                rows.append(_row(name, n, out))
            else:
                print(f"{name} n={n}: {out}")
    print(
        f"Cattaneo-Mindlin: rigid sphere R = {RADIUS * 1e3:g} mm, W = {FORCE:g} N, nu = 0.5 "
        f"(beta = 0), mu = {MU}, Q = {FRACTION} mu W, domain {2 * HALF_WIDTH} a_H, one thread"
    )
    print(format_table(rows))
    return 1 if failures else 0
