"""Load-cycle benchmark: fretting loops per cycle against Mindlin-Deresiewicz, and their cost.

Two scenes, each row in a fresh process (:mod:`study.bench`):

- **Elastic fretting**: two identical steel spheres (beta = 0), R = 15 mm, W = 1000 N,
  mu = 0.3, Q ramped to Q* = 0.5 mu W, then cycles between -Q* and +Q* (a cycle block); the
  loop area of the last cycle against Johnson's eq. 7.64
  (:func:`solver.theory.friction.mindlin_deresiewicz_energy`), the friction work summed over the
  surface against the loop area, the smallest stick radius against Cattaneo's
  ``(1 - Q*/(mu W))^(1/3)``; over the mesh and the steps per half cycle.
- **Elastic-plastic fretting**: the same pair with body 2 of the paper's Swift steel at
  W = 1400 N (p_H = 4.0 GPa, past first yield), Q* = 0.5 mu W, mu = 0.5, ``cycles`` cycles on an
  n^3 grid; the cost per cycle, the energy and the plastic strain gained per cycle.

``python -m study bench cycles [--sizes N ...]`` (sizes: the elastic grids; the plastic scene
runs at 64^3, 10 cycles: ``python -m study.bench.cycles --plastic N --cycles C``).
"""

from __future__ import annotations

import argparse

import numpy as np

from .timing import format_table, isolated, timed_solve

STEEL = {"behaviour": "elastic", "E": 210e9, "nu": 0.3}
SWIFT = {"law": "swift", "B": 945e6, "C": 20.0, "n": 0.121}
RADIUS, MU, FRACTION = 0.015, 0.3, 0.5
ELASTIC_FORCE, PLASTIC_FORCE, PLASTIC_MU = 1000.0, 1400.0, 0.5


def fretting_table(
    n: int, steps: int, cycles: int, force: float, mu: float, plastic: bool = False
) -> dict:
    """The sphere pair: W in one step (5 if plastic), Q to +Q*, then ``cycles`` of -Q*, +Q*."""
    amplitude = FRACTION * mu * force
    body2 = {"radius": RADIUS, **STEEL}
    if plastic:
        body2 = {**body2, "behaviour": "elastic-plastic", "hardening": SWIFT}
    return {
        "body1": {"radius": RADIUS, **STEEL},
        "body2": body2,
        "load": {
            "path": [
                {"normal_force": force, "steps": 5 if plastic else 1},
                {"tangential_force": [amplitude, 0.0], "steps": steps // 2},
                {
                    "cycles": cycles,
                    "stages": [
                        {"tangential_force": [-amplitude, 0.0], "steps": steps},
                        {"tangential_force": [amplitude, 0.0], "steps": steps},
                    ],
                },
            ]
        },
        "friction": {"coefficient": mu},
        "grid": {"n": [n, n, n] if plastic else n, "half_width": 1.5},
    }


def _solve(table: dict) -> dict:
    case, result, wall, cpu, memory = timed_solve(table)
    ds = result.to_xarray()
    per_cycle = {
        name: ds[name].values.tolist()
        for name in ("loop_energy", "cycle_friction_work", "min_stick_radius")
    }
    if "plastic_strain_increment" in ds:
        per_cycle["plastic_strain_increment"] = ds.plastic_strain_increment.values.tolist()
    return {
        "status": result.status,
        "wall": wall,
        "cpu": cpu,
        "memory": memory,
        "hertz_radius": case.hertz.radius,
        "finite": bool(all(np.isfinite(v).all() for v in result.history.values())),
        **per_cycle,
    }


def _full_slip_shift(radius: float, force: float, mu: float) -> float:
    """Twice one body's full-slip shift 3 mu W (2 - nu)/(16 G a) (Johnson 1985, eq. 7.42)."""
    shear_modulus = STEEL["E"] / (2 * (1 + STEEL["nu"]))
    return 2 * 3 * mu * force * (2 - STEEL["nu"]) / (16 * shear_modulus * radius)


def run_cycles(sizes: list[int], steps_list=(10, 20, 40), cycles: int = 3) -> int:
    """Elastic fretting cycles over meshes and steps; prints the table, returns a status."""
    from solver.theory.friction import cattaneo_stick_ratio, mindlin_deresiewicz_energy

    rows, failures = [], 0
    amplitude = FRACTION * MU * ELASTIC_FORCE
    for n in sizes:
        for steps in steps_list:
            status, out = isolated(_solve, fretting_table(n, steps, cycles, ELASTIC_FORCE, MU))
            if status != "ok":
                failures += 1
                print(f"n={n} steps={steps}: {out}")
                continue
            full_slip = _full_slip_shift(out["hertz_radius"], ELASTIC_FORCE, MU)
            expected = mindlin_deresiewicz_energy(amplitude, MU, ELASTIC_FORCE, full_slip)
            energy = out["loop_energy"]
            stick = out["min_stick_radius"][-1] / out["hertz_radius"]
            rows.append(
                {
                    "n": n,
                    "steps/half": steps,
                    "cycles": cycles,
                    "status": out["status"],
                    "E_last/E_MD-1_%": 100 * (energy[-1] / expected - 1),
                    "work/E-1": out["cycle_friction_work"][-1] / energy[-1] - 1,
                    "cycle_spread": (max(energy) - min(energy)) / energy[-1],
                    "c_min/a": stick,
                    "c/a_Cattaneo": cattaneo_stick_ratio(amplitude, MU, ELASTIC_FORCE),
                    "wall_s": out["wall"],
                    "cpu_s": out["cpu"],
                    "cpu_per_cycle_s": out["cpu"] / cycles,
                    "peak_MB": out["memory"],
                }
            )
    print(
        f"Elastic fretting cycles: two steel spheres R = {RADIUS * 1e3:g} mm, "
        f"W = {ELASTIC_FORCE:g} N, mu = {MU}, Q* = {FRACTION} mu W, Mindlin-Deresiewicz "
        "(Johnson eq. 7.64); one thread, each row a fresh process"
    )
    print(format_table(rows))
    return 1 if failures else 0


def run_plastic_cycles(n: int, cycles: int, steps: int = 16) -> int:
    """The elastic-plastic fretting scene: cost and outputs per cycle."""
    status, out = isolated(
        _solve, fretting_table(n, steps, cycles, PLASTIC_FORCE, PLASTIC_MU, True), timeout=14400.0
    )
    if status != "ok":
        print(f"plastic n={n}: {out}")
        return 1
    rows = [
        {
            "cycle": c + 1,
            "E_J": out["loop_energy"][c],
            "work/E": out["cycle_friction_work"][c] / out["loop_energy"][c],
            "c_min/a_H": out["min_stick_radius"][c] / out["hertz_radius"],
            "dep": out["plastic_strain_increment"][c],
        }
        for c in range(cycles)
    ]
    print(
        f"Elastic-plastic fretting: steel sphere on Swift-steel sphere, W = {PLASTIC_FORCE:g} N "
        f"(p_H = 4.0 GPa), mu = {PLASTIC_MU}, Q* = {FRACTION} mu W, {n}^3, {cycles} cycles of "
        f"2 x {steps} steps: status {out['status']}, finite {out['finite']}, "
        f"wall {out['wall']:.1f} s, CPU {out['cpu']:.1f} s ({out['cpu'] / cycles:.1f} s per "
        f"cycle with the loading), peak +{out['memory']:.0f} MB"
    )
    print(format_table(rows))
    return 0 if out["status"] == "converged" else 1


def main(argv: list[str] | None = None) -> int:
    """Command line of the module (``python -m study.bench.cycles``)."""
    parser = argparse.ArgumentParser(description="load-cycle benchmarks")
    parser.add_argument("--sizes", type=int, nargs="+", default=[32, 64, 128])
    parser.add_argument("--steps", type=int, nargs="+", default=[10, 20, 40])
    parser.add_argument("--plastic", type=int, metavar="N", help="the plastic scene at N^3")
    parser.add_argument("--cycles", type=int, default=10)
    args = parser.parse_args(argv)
    if args.plastic:
        return run_plastic_cycles(args.plastic, args.cycles)
    return run_cycles(args.sizes, tuple(args.steps))


if __name__ == "__main__":
    raise SystemExit(main())
