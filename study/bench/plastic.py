"""Elastic-plastic benchmark: ``python -m study bench plastic [--peers] [--sizes 32 64]``.

Tamaas' own elastic-plastic scene: a rigid sphere R = 15 mm on a half-space E = 210 GPa,
nu = 0.3, von Mises with linear hardening sigma_Y0 = 1.3579 GPa, H = 152.3 GPa, frictionless,
loaded to W = 4716 N (p_H = 6 GPa) in 6 equal steps, then unloaded in one.  Every row runs in
a fresh child process (:func:`study.bench.isolated`); ``wall`` and ``cpu`` cover set-up and
solve (``setup_s`` apart: kernels and FFT plans, built once per grid and reused by every case of
a campaign on it), ``cpu_per_it_s`` is the solve's CPU time per plasticity iteration, and
``peak_MB`` the growth of the resident set during set-up and solve.  With
``--peers`` Tamaas runs the same scene in the same run (``study.bench.peers_plastic``; periodic, so
it gets a larger cell, see its notes).
"""

from __future__ import annotations

import math
import time

import numpy as np

from .timing import format_table, isolated, peak_memory

SCENE = {
    "radius": 0.015,
    "E": 210e9,
    "nu": 0.3,
    "yield_stress": 1.3579e9,
    "hardening_modulus": 152.3e9,
    "normal_force": 4716.0,
    "steps": 6,
}


def scene_table(n: int, precision: str = "double", planner: str = "estimate") -> dict:
    """The case table of the scene on an n^3 volume grid (depth sized from the yield region).

    ``precision``: ``solver.volume_precision`` of the 3-D eigenstrain convolution;
    ``planner``: ``solver.fft_planner``.
    """
    s = SCENE
    return {
        "solver": {"volume_precision": precision, "fft_planner": planner},
        "body1": {"behaviour": "rigid", "radius": s["radius"]},
        "body2": {
            "behaviour": "elastic-plastic",
            "radius": "inf",
            "E": s["E"],
            "nu": s["nu"],
            "hardening": {
                "law": "linear",
                "yield_stress": s["yield_stress"],
                "modulus": s["hardening_modulus"],
            },
        },
        "load": {
            "path": [
                {"normal_force": s["normal_force"], "steps": s["steps"]},
                {"normal_force": 0.0, "steps": 1},
            ]
        },
        # the window the benchmark pages measured (Tamaas' scene, the peers in the same run):
        # fixed, where a case without it now widens to 1.571 a_H to hold the plastic box
        "grid": {"n": [n, n, n], "half_width": 1.5},
    }


def _ours(n: int, precision: str = "double", planner: str = "estimate") -> dict:
    import solver
    from solver.drive.operators import PROCESS_BYTES, CaseOperators

    case = solver.Case.from_dict(scene_table(n, precision, planner))
    plans = 0.0
    if planner == "wisdom":  # the machine's saved plans; measured here once if missing
        from study.run import wisdom

        plans = time.process_time()
        wisdom.prepare([case])
        plans = time.process_time() - plans
    with peak_memory() as memory:
        setup, setup_cpu = time.perf_counter(), time.process_time()
        CaseOperators.build(case).eigenstrain.prepare()  # kernels and plans, cached per grid
        setup, setup_cpu = time.perf_counter() - setup, time.process_time() - setup_cpu
        wall, cpu = time.perf_counter(), time.process_time()
        result = solver.solve(case)
        wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    h = result.history
    loaded = SCENE["steps"] - 1
    return {
        "setup": setup,
        "time": wall + setup,
        "cpu": cpu + setup_cpu,
        "solve_cpu": cpu,
        "memory": memory["peak_MB"],
        "estimate_MB": (solver.memory_estimate(case) - PROCESS_BYTES) / 2**20,
        "max_pressure": h["max_pressure"][loaded],
        "contact_radius": math.sqrt(h["contact_area"][loaded] / math.pi),
        "max_plastic_strain": h["max_plastic_strain"][loaded],
        "max_plastic_strain_depth": h["max_plastic_strain_depth"][loaded],
        "plastic_zone_depth": h["plastic_zone_depth"][loaded],
        "residual_depth": h["residual_depth"][-1],
        "iterations": int(h["plastic_iterations"].sum()),
        "status": result.status,
        "plans": plans,
    }


def _tamaas(n: int) -> dict:
    from .peers_plastic import tamaas_plastic

    s = SCENE
    with peak_memory() as memory:
        out = tamaas_plastic(
            n,
            n,
            radius=s["radius"],
            E=s["E"],
            nu=s["nu"],
            yield_stress=s["yield_stress"],
            hardening_modulus=s["hardening_modulus"],
            normal_force=s["normal_force"],
            steps=s["steps"],
            unload=True,
        )
    out["memory"] = memory["peak_MB"]
    return out


def _row(code: str, n: int, out: dict, a_h: float, p_h: float) -> dict:
    def ratio(key, scale):
        value = out.get(key)
        return float("nan") if value is None else value / scale

    return {
        "code": code,
        "n": n,
        "wall_s": out["time"],
        "cpu_s": out["cpu"],
        "peak_MB": out["memory"],
        "pmax/pH": ratio("max_pressure", p_h),
        "a/aH": ratio("contact_radius", a_h),
        "ep_max_%": 100 * out["max_plastic_strain"],
        "z_ep/aH": ratio("max_plastic_strain_depth", a_h),
        "zone/aH": ratio("plastic_zone_depth", a_h),
        "dent_um": ratio("residual_depth", 1e-6),
        "iterations": out.get("iterations"),
        "setup_s": out.get("setup", float("nan")),
        "cpu_per_it_s": (
            out.get("solve_cpu", out["cpu"]) / out["iterations"]
            if out.get("iterations")
            else float("nan")
        ),
    }


def run_plastic(sizes: list[int], peers: bool = False, error: bool = False) -> int:
    """Run the scene at each size (ours, and Tamaas with ``peers``); print the table.

    ``error``: also the speed-error table (:func:`error_table`).
    """
    from solver import Case

    reference = Case.from_dict(scene_table(sizes[0])).hertz
    rows, failures = [], 0
    for n in sizes:
        codes = [
            ("slipstick", _ours, ()),
            ("slipstick (single)", _ours, ("single",)),
            ("slipstick (wisdom)", _ours, ("double", "wisdom")),
            ("slipstick (single, wisdom)", _ours, ("single", "wisdom")),
        ]
        codes += [("tamaas", _tamaas, ())] if peers else []
        for code, target, args in codes:
            status, out = isolated(target, n, *args, timeout=3600.0)
            if status != "ok":
                failures += code.startswith("slipstick")
                print(f"{code} n={n}: {out}")
                continue
            rows.append(_row(code, n, out, reference.radius, reference.max_pressure))
            if code.startswith("slipstick"):
                print(
                    f"{code} n={n}: {out['status']}, memory estimate beyond the process "
                    f"baseline {out['estimate_MB']:.0f} MB, measured growth {out['memory']:.0f} MB"
                    + (
                        f"; plans measured into the machine's wisdom first: {out['plans']:.1f} s "
                        "CPU (once per machine and grid, not in cpu_s)"
                        if out["plans"] > 0.05
                        else ""
                    )
                )
            elif out.get("notes"):
                print(f"tamaas n={n}: {out['notes']}")
    print(
        "Elastic-plastic: rigid sphere R = 15 mm, E = 210 GPa, nu = 0.3, linear hardening "
        "sigma_Y0 = 1.3579 GPa, H = 152.3 GPa, W = 4716 N in 6 steps then unloaded; "
        "one thread.  pmax, a, ep, depths at the maximum load; dent after unloading.  "
        '"single": solver.volume_precision = "single" (the 3-D eigenstrain convolution); '
        '"wisdom": solver.fft_planner = "wisdom" (FFT plans measured once per machine).'
    )
    print(format_table(rows))
    ours = [row for row in rows if row["code"] == "slipstick"]
    if len(ours) > 1:  # cost growth per plasticity iteration against N log N, N = n^3
        first, last = ours[0], ours[-1]
        cells = [row["n"] ** 3 for row in (first, last)]
        observed = math.log(last["cpu_per_it_s"] / first["cpu_per_it_s"]) / math.log(
            cells[1] / cells[0]
        )
        nlogn = math.log(cells[1] * math.log(cells[1]) / (cells[0] * math.log(cells[0])))
        print(
            f"cpu per plasticity iteration grows as N^{observed:.2f} from n = {first['n']} "
            f"to {last['n']} (N log N: N^{nlogn / math.log(cells[1] / cells[0]):.2f})"
        )
    if error:
        error_table(rows)
    return 1 if failures else 0


#: Quantities of the speed-error table: table column -> (short name, what it is).
ERROR_QUANTITIES = {"ep_max_%": ("ep", "e_p,max"), "dent_um": ("dent", "residual dent")}


def error_table(
    rows: list[dict],
    target: float = 0.01,
    quantities: dict[str, tuple[str, str]] | None = None,
    carry: tuple[str, ...] = (),
) -> None:
    """Print each row's error against the converged value and the CPU each code needs for it.

    The converged value of each quantity is the limit of ``v = v* + C h^p`` fitted over our
    double-precision meshes (:func:`study.analysis.convergence.fit_convergence`, h = 1/n;
    three or more).  Every code's error is taken against that one limit (Tamaas solves the same
    scene in a periodic cell, so its own limit may differ: its finest value is printed beside
    ours).  The CPU for ``target`` relative error is interpolated in log-log between the two
    meshes that bracket it, or said not reached.  ``quantities``: table column -> (short
    name, what it is); :data:`ERROR_QUANTITIES` by default.  ``carry``: row columns copied
    into the table (a mesh's resolution, say).
    """
    from ..analysis.convergence import fit_convergence
    from .timing import format_table

    quantities = quantities or ERROR_QUANTITIES
    ours = [row for row in rows if row["code"] == "slipstick"]
    if len(ours) < 3:
        print("speed-error table: needs our results on 3 or more sizes")
        return
    limits = {}
    for column, (_, label) in quantities.items():
        fit = fit_convergence([1 / row["n"] for row in ours], [row[column] for row in ours])
        limits[column] = fit.limit
        print(
            f"{label}: converged value {fit.limit:.5g} ({column}), observed order "
            f"{fit.order:.2f}{' (at the bound of the fit: not asymptotic)' if fit.at_bound else ''}"
        )
    table, needs = [], []
    for code in dict.fromkeys(row["code"] for row in rows):
        mine = sorted((row for row in rows if row["code"] == code), key=lambda row: row["n"])
        for row in mine:
            table.append(
                {"code": code, "n": row["n"]}
                | {column: row.get(column) for column in carry}
                | {"cpu_s": row["cpu_s"]}
                | {
                    f"{short}_err_%": 100 * abs(row[column] / limits[column] - 1)
                    for column, (short, _) in quantities.items()
                }
            )
        for column, (_, label) in quantities.items():
            errors = [abs(row[column] / limits[column] - 1) for row in mine]
            needs.append(f"{code}, {label}: {_cpu_for(target, mine, errors)}")
    print(format_table(table))
    print(f"CPU for {100 * target:g} % error:")
    for line in needs:
        print(f"  {line}")


def _cpu_for(target: float, rows: list[dict], errors: list[float]) -> str:
    """CPU (s) at ``target`` error, log-log between the bracketing meshes, as text."""
    for (a, ea), (b, eb) in zip(
        zip(rows, errors, strict=True), zip(rows[1:], errors[1:], strict=True), strict=False
    ):
        if ea >= target >= eb > 0:
            f = math.log(ea / target) / math.log(ea / eb)
            cpu = math.exp(math.log(a["cpu_s"]) + f * math.log(b["cpu_s"] / a["cpu_s"]))
            return f"{cpu:.3g} s (between n = {a['n']} and {b['n']})"
    if errors and errors[0] <= target:
        return f"reached at the coarsest mesh n = {rows[0]['n']}: {rows[0]['cpu_s']:.3g} s or less"
    smallest = min(errors) if errors else math.nan
    return f"not reached (smallest error {100 * smallest:.2g} %)"


def paper_spheres(n: int, steps: int = 10) -> int:
    """The reference paper's §3 scenes: two steel spheres R = 15 mm to p_H = 8 GPa (Swift).

    E-E, E-EP and EP-EP (mu = 0 and 0.5) on an n^3 volume grid; prints p_max/p_H, the
    central pressure, the contact radius and the maximum plastic strain at the maximum load.
    """
    import solver

    swift = {"law": "swift", "B": 945e6, "C": 20.0, "n": 0.121}
    rows = []
    for label, behaviours, mu in (
        ("E-E", ("elastic", "elastic"), 0.0),
        ("E-EP", ("elastic", "elastic-plastic"), 0.0),
        ("EP-EP", ("elastic-plastic", "elastic-plastic"), 0.0),
        ("EP-EP", ("elastic-plastic", "elastic-plastic"), 0.5),
    ):
        bodies = []
        for behaviour in behaviours:
            body = {"behaviour": behaviour, "radius": 0.015, "E": 210e9, "nu": 0.3}
            if behaviour == "elastic-plastic":
                body["hardening"] = dict(swift)
            bodies.append(body)
        plastic = "elastic-plastic" in behaviours
        case = solver.Case.from_dict(
            {
                "body1": bodies[0],
                "body2": bodies[1],
                "load": {"normal_force": 11179.0, "steps": steps},
                "friction": {"coefficient": mu},
                "grid": {"n": [n, n, n] if plastic else n},
            }
        )
        wall = time.perf_counter()
        result = solver.solve(case)
        h, hertz = result.history, case.hertz
        x, y = case.surface_grid.mesh()
        centre = result.pressure[np.unravel_index(np.argmin(x * x + y * y), x.shape)]
        rows.append(
            {
                "scene": label,
                "mu": mu,
                "loops": " ".join(result.loops),
                "status": result.status,
                "pmax/pH": h["max_pressure"][-1] / hertz.max_pressure,
                "p_centre/pH": centre / hertz.max_pressure,
                "a/aH": math.sqrt(h["contact_area"][-1] / math.pi) / hertz.radius,
                "ep_max_%": 100 * h["max_plastic_strain"][-1] if plastic else 0.0,
                "wall_s": time.perf_counter() - wall,
            }
        )
    print(f"Paper §3: steel spheres R = 15 mm, W = 11179 N (p_H = 8 GPa), {steps} steps, n = {n}")
    print(format_table(rows))
    return 0


def annuli(contact_state: np.ndarray) -> int:
    """Stick/slip zones met along y = 0 from the centre outwards.

    1 = one zone, 2 = stick core and slip annulus, more = alternating annuli; counted on the
    cell row nearest y = 0.
    """
    from solver.result import SEPARATED

    nx, ny = contact_state.shape
    row = contact_state[nx // 2 :, ny // 2]
    row = row[row != SEPARATED]
    return int(1 + np.count_nonzero(np.diff(row))) if row.size else 0


def fretting_ii(
    n: int,
    steps: int,
    mus=(0.0, 0.1, 0.2, 0.3, 0.5),
    depth: float | None = None,
    planner: str = "estimate",
) -> list[dict]:
    """The paper's §4 scene: rigid sphere R = 15 mm on Swift steel to p_H = 6 GPa, friction mu.

    Prints per mu the maximum plastic strain, its depth, the stick fraction, the stick/slip
    zones along a radius (:func:`annuli`), p_max and the cost.  ``depth`` (units of a_H) is the
    volume depth; default: sized from the yield region.  ``planner`` is ``solver.fft_planner``.
    """
    import solver

    rows = []
    for mu in mus:
        grid = {"n": [n, n, n], **({"depth": depth} if depth else {})}
        case = solver.Case.from_dict(
            {
                "body1": {"behaviour": "rigid", "radius": 0.015},
                "body2": {
                    "behaviour": "elastic-plastic",
                    "radius": "inf",
                    "E": 210e9,
                    "nu": 0.3,
                    "hardening": {"law": "swift", "B": 945e6, "C": 20.0, "n": 0.121},
                },
                "load": {"hertz_pressure": 6e9, "steps": steps},
                "friction": {"coefficient": mu},
                "grid": grid,
                "solver": {"fft_planner": planner},
            }
        )
        wall, cpu = time.perf_counter(), time.process_time()
        result = solver.solve(case)
        wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
        h, a = result.history, case.hertz.radius
        stick = h["stick_area"][-1] / h["contact_area"][-1] if "stick_area" in h else 1.0
        rows.append(
            {
                "mu": mu,
                "n": n,
                "steps": steps,
                "depth/aH": case.grid.depth,
                "status": result.status,
                "ep_max_%": 100 * h["max_plastic_strain"][-1],
                "z_ep/aH": h["max_plastic_strain_depth"][-1] / a,
                "pmax/pH": h["max_pressure"][-1] / case.hertz.max_pressure,
                "stick/contact": stick,
                "zones": annuli(result.contact_state) if mu else 1,
                "plastic_it": int(h["plastic_iterations"].sum()),
                "wall_s": wall,
                "cpu_s": cpu,
            }
        )
        print(format_table(rows[-1:]), flush=True)
    print(f"Fretting II (paper §4): rigid sphere, Swift steel, p_H = 6 GPa, n = {n}, {steps} steps")
    print(format_table(rows))
    return rows


def _box_case(n: int, ratio: float, mu: float, whole: bool) -> dict:
    """The scene's material to p_H = ``ratio`` sigma_Y0 (6 steps, unloaded), friction ``mu``.

    Solved with the automatic plastic box, or with the whole window (``whole``).
    """
    import solver

    table = scene_table(n)
    load = {"hertz_pressure": ratio * SCENE["yield_stress"], "steps": SCENE["steps"]}
    table["load"]["path"][0] = load
    table["friction"] = {"coefficient": mu}
    if whole:
        table["grid"]["plastic_half_width"] = 1.5  # the default window's half width
    case = solver.Case.from_dict(table)
    wall, cpu = time.perf_counter(), time.process_time()
    result = solver.solve(case)
    wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    h, loaded = result.history, SCENE["steps"] - 1
    box = case.plastic_box
    return {
        "cells": box.shape[0] if box is not None else n,
        "status": result.status,
        "ep": h["max_plastic_strain"][loaded],
        "dent": h["residual_depth"][-1],
        "iterations": int(h["plastic_iterations"].sum()),
        "wall": wall,
        "cpu": cpu,
    }


def box_sweep(n: int, ratios=(1.8, 2.5, 3.5, 4.42), mus=(0.0, 0.5)) -> list[dict]:
    """The automatic plastic box against the whole window, over the load, in one run.

    Tamaas' scene material (linear hardening) to p_H / sigma_Y0 = ``ratios``, each case twice in
    fresh processes: with the default (automatic) box and with ``grid.plastic_half_width`` =
    the window.  Prints the box's cells across, both answers (e_p,max at the maximum load and
    the dent after unloading), their relative difference, and both CPU times (solve only).
    """
    rows = []
    for ratio in ratios:
        for mu in mus:
            out = {}
            for label, whole in (("box", False), ("window", True)):
                status, out[label] = isolated(_box_case, n, ratio, mu, whole, timeout=3600.0)
                if status != "ok":
                    raise RuntimeError(f"p_H/sigma_Y0 = {ratio}, mu = {mu}, {label}: {out[label]}")
            box, window = out["box"], out["window"]
            rows.append(
                {
                    "pH/sY0": ratio,
                    "mu": mu,
                    "n": n,
                    "box_cells": box["cells"],
                    "status": box["status"],
                    "ep_max_%": 100 * box["ep"],
                    "ep_rel_diff": abs(box["ep"] / window["ep"] - 1.0),
                    "dent_rel_diff": abs(box["dent"] / window["dent"] - 1.0),
                    "plastic_it": box["iterations"],
                    "cpu_window_s": window["cpu"],
                    "cpu_box_s": box["cpu"],
                    "speed_up": window["cpu"] / box["cpu"],
                }
            )
            print(format_table(rows[-1:]), flush=True)
    print(
        f"Automatic plastic box against the whole window (half_width 1.5 a_H), n = {n}: rigid "
        "sphere on Tamaas' linear-hardening steel, 6 steps and unloaded; one thread, solve CPU"
    )
    print(format_table(rows))
    return rows


def _threaded(n: int, threads: int) -> dict:
    """Tamaas' scene at n^3 on ``threads`` FFTW threads: wall and CPU of set-up plus solve."""
    import solver
    from solver.drive.operators import CaseOperators

    table = scene_table(n)
    table["solver"]["fft_threads"] = threads
    case = solver.Case.from_dict(table)
    wall, cpu = time.perf_counter(), time.process_time()
    CaseOperators.build(case).eigenstrain.prepare()
    setup = time.perf_counter() - wall
    result = solver.solve(case)
    h = result.history
    return {
        "wall": time.perf_counter() - wall,
        "cpu": time.process_time() - cpu,
        "setup": setup,
        "iterations": int(h["plastic_iterations"].sum()),
        "ep": float(h["max_plastic_strain"][SCENE["steps"] - 1]),
        "dent": float(h["residual_depth"][-1]),
        "status": result.status,
    }


def thread_speedup(n: int, pairs: int = 3, threads: int = 2) -> list[dict]:
    """One case on ``threads`` FFTW threads against one thread, ``pairs`` times, alternating.

    Tamaas' scene at n^3, every run in a fresh process; prints each run (wall, CPU, set-up
    wall, iterations, e_p,max, dent) and each pair's wall-time speed-up.  The answers must
    be the same bits (threads split the work in pieces that do not depend on their number).
    """
    import solver

    solver.Case.from_dict(scene_table(n))  # a grid the solver refuses: its one line, here
    rows = []
    for pair in range(1, pairs + 1):
        runs = {}
        for count in (1, threads):
            status, out = isolated(_threaded, n, count, timeout=7200.0)
            if status != "ok":
                raise RuntimeError(f"{count} threads: {out}")
            runs[count] = out
        one, many = runs[1], runs[threads]
        if (one["ep"], one["dent"]) != (many["ep"], many["dent"]):
            raise RuntimeError("the answers differ between thread counts")
        for count, out in runs.items():
            rows.append(
                {
                    "pair": pair,
                    "threads": count,
                    "status": out["status"],
                    "wall_s": out["wall"],
                    "cpu_s": out["cpu"],
                    "setup_wall_s": out["setup"],
                    "plastic_it": out["iterations"],
                    "ep_max_%": 100 * out["ep"],
                    "speed_up": one["wall"] / out["wall"],
                }
            )
        print(format_table(rows[-2:]), flush=True)
    print(
        f"Tamaas' scene at n = {n}, double precision, estimate plans: {threads} threads against "
        f"one, {pairs} pairs in fresh processes (speed_up: the pair's one-thread wall time over "
        "this row's); the same e_p,max and dent bits in every run"
    )
    print(format_table(rows))
    return rows


if __name__ == "__main__":  # pragma: no cover
    import argparse

    from solver import SpecError

    def count(text: str) -> int:
        """A positive integer option."""
        value = int(text)
        if value < 1:
            raise argparse.ArgumentTypeError(f"must be a positive integer, got {value}")
        return value

    parser = argparse.ArgumentParser(description="elastic-plastic benchmarks")
    parser.add_argument("--paper", type=int, metavar="N", help="the paper's §3 scenes at N^3")
    parser.add_argument("--sizes", type=int, nargs="+", default=[32])
    parser.add_argument("--peers", action="store_true")
    parser.add_argument("--fretting", type=int, metavar="N", help="the paper's §4 scene at N^3")
    parser.add_argument("--steps", type=int, default=20, help="load steps (--fretting)")
    parser.add_argument("--depth", type=float, help="volume depth over a_H (--fretting)")
    parser.add_argument("--mu", type=float, nargs="+", default=[0.0, 0.1, 0.2, 0.3, 0.5])
    parser.add_argument("--planner", choices=["estimate", "measure"], default="estimate")
    parser.add_argument("--box", type=int, metavar="N", help="automatic box vs window at N^3")
    parser.add_argument("--threads", type=count, metavar="N", help="2 threads vs 1 at N^3")
    parser.add_argument("--pairs", type=count, default=3, help="runs of each (--threads)")
    args = parser.parse_args()
    if args.threads is not None:
        try:
            thread_speedup(args.threads, args.pairs)
        except SpecError as error:
            parser.error(f"--threads {args.threads}: {error}")
        raise SystemExit(0)
    if args.box:
        box_sweep(args.box)
        raise SystemExit(0)
    if args.fretting:
        fretting_ii(args.fretting, args.steps, args.mu, args.depth, args.planner)
        raise SystemExit(0)
    if args.paper:
        raise SystemExit(paper_spheres(args.paper))
    raise SystemExit(run_plastic(args.sizes, peers=args.peers))
