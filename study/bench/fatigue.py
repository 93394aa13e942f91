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

No peer contact solver gives fatigue criteria (Tamaas, ContactMechanics, CONTACT): the table
is ours alone.
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
    return 1 if failures else 0
