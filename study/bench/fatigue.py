"""Benchmark: the fatigue criteria of a pass against the pass they read.

``python -m study bench fatigue [--sizes N ...]``: a rigid sphere (R = 10 mm) slid 0.4 mm over
incompressible steel (beta = 0: Hertz's pressure, p0 = 1.4 GPa), frictionless and at mu = 0.3,
on N x 3N/4 x N/4 cells (``grid.half_width`` 4, depth 1.5 a), each case in a child process,
one thread.  Per case: the pass's CPU (the solve with the field output), the criteria's CPU
(Dang Van and Crossland on every line along x of the field:
:func:`solver.fatigue.criteria.steady_pass_criteria`) and their ratio, peak memory, and on the
line nearest the contact's path the criteria's maxima against the same criteria on
Hamilton's closed-form field at the same points (:mod:`solver.fatigue.hertz_pass`), below two
cells' depth (nearer the surface the field of tractions constant on cells is their average).

A second table: a fretting cycle (steel spheres, nu = 0, W = 100 N, mu = 0.3, the tangential
force cycled twice between +-0.6 mu W, 16 increments a half cycle) on N x N x N/3 cells: the
solve's CPU without and with the ``[fatigue]`` table (the last cycle's 32 samples read as each
cell's path, :func:`solver.drive.fatigue.cycle_fatigue`), their ratio, and the criteria's
maxima below three cells' depth against Mindlin and Deresiewicz's closed-form cycle
(:func:`solver.fatigue.hertz_pass.fretting_cycle_criteria`).

No peer contact solver gives fatigue criteria (Tamaas, ContactMechanics, CONTACT): the tables
are ours alone.
"""

from __future__ import annotations

import sys
import time

from .timing import format_table, isolated, timed_solve

#: Friction coefficients measured.
FRICTION = (0.0, 0.3)


def _table(n: int, mu: float) -> dict:
    return {
        "body1": {"behaviour": "rigid", "radius": 0.01},
        "body2": {"behaviour": "elastic", "E": 210e9, "nu": 0.5},
        "load": {"path": [{"normal_force": 100.0}, {"slide": [4e-4, 0.0], "steps": 8}]},
        "friction": {"coefficient": mu},
        "grid": {"n": [n, 3 * n // 4, n // 4], "half_width": 4.0, "depth": 1.5},
        "output": {"fields": ["stress"]},
    }


def _measure(n: int, mu: float) -> dict:
    import numpy as np

    from solver.fatigue.criteria import FatigueLimits, steady_pass_criteria
    from solver.fatigue.hertz_pass import hertz_pass_criteria

    limits = FatigueLimits(400e6, 250e6)
    case, result, _, cpu, memory = timed_solve(_table(n, mu))
    start = time.process_time()
    found, shape = steady_pass_criteria(result.fields["stress"], limits)
    criteria = time.process_time() - start
    a, p0 = case.reference.radius, case.reference.max_pressure
    _, y = case.surface_grid.mesh()
    j = int(np.argmin(np.abs(y[0])))
    depth = result.depth
    x, end = case.surface_grid.x, result.history["position_x"][-1]
    span = ((x[0] - end) / a, (x[-1] - end) / a)  # the track's extent about the contact
    reference = hertz_pass_criteria(a, p0, 0.4999, limits, depth, mu, span=span, lateral=y[0, j])
    deep = depth > 2 * case.surface_grid.dx
    row = {"status": result.status, "pass_cpu_s": cpu, "criteria_cpu_s": criteria,
           "ratio": criteria / cpu, "MB": memory, "lines": int(np.prod(shape))}  # fmt: skip
    for name in ("dang_van", "crossland"):
        got = getattr(found, name).reshape(shape)[j][deep].max()
        want = getattr(reference, name)[deep].max()
        row[f"{name}_err"] = float(got / want - 1.0)
    return row


def _cycle_table(n: int, fatigue: bool) -> dict:
    steel = {"behaviour": "elastic", "E": 210e9, "nu": 0.0}
    amplitude = 0.6 * 0.3 * 100.0
    cycle = [{"tangential_force": [sign * amplitude, 0.0], "steps": 16} for sign in (-1, 1)]
    table = {
        "body1": {**steel, "radius": 0.01},
        "body2": steel,
        "friction": {"coefficient": 0.3},
        "load": {"path": [{"normal_force": 100.0},
                          {"tangential_force": [amplitude, 0.0], "steps": 8},
                          {"cycles": 2, "stages": cycle}]},
        "grid": {"n": [n, n, n // 3], "half_width": 1.5, "depth": 1.0},
    }  # fmt: skip
    if fatigue:
        table["fatigue"] = {"bending_limit": 400e6, "torsion_limit": 250e6}
    return table


def _measure_cycle(n: int) -> dict:
    from solver.fatigue.hertz_pass import fretting_cycle_criteria

    _, _, _, plain, _ = timed_solve(_cycle_table(n, False))
    case, result, _, cpu, memory = timed_solve(_cycle_table(n, True))
    a, p0 = case.reference.radius, case.reference.max_pressure
    x, y = case.surface_grid.mesh()
    points = (x[:, :, None], y[:, :, None], result.depth[None, None, :])
    reference = fretting_cycle_criteria(
        points, a, p0, 0.0, case.fatigue, 0.3, 100.0, 0.6 * 0.3 * 100.0, 16
    )
    deep = result.depth > 3 * case.surface_grid.dx
    row = {"status": result.status, "solve_cpu_s": plain, "with_criteria_cpu_s": cpu,
           "ratio": cpu / plain, "MB": memory}  # fmt: skip
    for name in ("dang_van", "crossland"):
        got = result.fields[f"{name}_cycle_stress"]
        want = getattr(reference, name).reshape(got.shape)
        row[f"{name}_err"] = float(got[..., deep].max() / want[..., deep].max() - 1.0)
    return row


def run_fatigue(sizes: list[int]) -> int:
    """Measure the criteria against the pass; print the table."""
    rows, failures = [], 0
    for n in sizes:
        for mu in FRICTION:
            status, out = isolated(_measure, n, mu, timeout=3600.0)
            row = {"n": f"{n} x {3 * n // 4} x {n // 4}", "mu": mu}
            if status != "ok":
                failures += 1
                rows.append({**row, "status": f"error: {out}"})
                continue
            rows.append({**row, **out})
            print(f"  n {n} mu {mu}: {out['status']}", file=sys.stderr)
    print("Fatigue criteria of a sliding pass: a rigid sphere over incompressible steel, one "
          "thread, each case in a child process; errors of the maxima against Hamilton's "
          "closed-form pass below two cells' depth")  # fmt: skip
    print(format_table(rows))
    cycles = []
    for n in sizes:
        status, out = isolated(_measure_cycle, n, timeout=3600.0)
        row = {"n": f"{n} x {n} x {n // 3}"}
        failures += status != "ok"
        cycles.append({**row, **out} if status == "ok" else {**row, "status": f"error: {out}"})
        print(f"  cycle n {n}: {status}", file=sys.stderr)
    print("\nFatigue criteria of a fretting cycle: steel spheres fretted at +-0.6 mu W, 32 "
          "samples a cycle, one thread, each case in a child process; the solve's CPU without "
          "and with [fatigue]; errors of the maxima against Mindlin and Deresiewicz's "
          "closed-form cycle below three cells' depth")  # fmt: skip
    print(format_table(cycles))
    return 1 if failures else 0
