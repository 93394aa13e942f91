"""Benchmark: cycle jumps of a wearing contact against every cycle solved.

``python -m study bench wear [--sizes N ...]``: a rigid flat punch (face radius 1 mm, its edge
rounded to 1 mm) slid to and fro by 5 % of its radius over a wearing steel flat in gross slip
(W = 100 N, mu = 0.5, Archard's k = 2e-13 1/Pa on the flat, 4 increments a cycle) for 1,000
cycles: solved every cycle, then with ``wear.cycle_jump`` J = 10, 20, 50 and 100, each case in
a child process, one thread.  Per case: solved cycles, increments, CPU and wall time, peak
memory, and against every cycle solved the worn profile's largest difference over the deepest
wear, the final pressure's largest difference over its peak and the worn volume's ratio.

No peer contact solver wears its surfaces (Tamaas, ContactMechanics and CONTACT): the table
is ours alone.
"""

from __future__ import annotations

import sys

from .timing import format_table, isolated, timed_solve

#: The punch's face radius (m), the normal force (N), the stroke over the radius.
RADIUS, FORCE, STROKE = 1e-3, 100.0, 0.05
#: The flat's Archard coefficient (1/Pa), the cycles, and the jumps measured.
K, CYCLES, JUMPS = 2e-13, 1000, (10, 20, 50, 100)


def punch_table(k: float, cycles: int, jump: int | str = 1, n: int = 32, **rule) -> dict:
    """The fretted flat punch over a wearing steel flat (module docstring), as a case table.

    ``jump``: ``wear.cycle_jump``; ``rule``: the automatic jump's keys (``pressure_change``,
    ``solved_cycles``).
    """
    stroke = STROKE * RADIUS
    swing = [{"slide": [s, 0.0], "steps": 2} for s in (-stroke / 2, stroke / 2)]
    punch = {"shape": "flat_punch", "radius": RADIUS, "edge_radius": RADIUS}
    return {
        "body1": {"behaviour": "rigid", "profile": punch},
        "body2": {"behaviour": "elastic", "E": 210e9, "nu": 0.3},
        "load": {
            "path": [
                {"normal_force": FORCE, "steps": 1},
                {"slide": [stroke / 2, 0.0], "steps": 1},
                {"cycles": cycles, "stages": swing},
            ]
        },
        "friction": {"coefficient": 0.5},
        "grid": {"n": n},
        "wear": {"law": "archard", "body2": k, "cycle_jump": jump, **rule},
    }


def _measure(table: dict) -> dict:
    case, result, wall, cpu, memory = timed_solve(table)
    return {
        "status": result.status, "solved_cycles": case.cycles,
        "steps": len(result.history["normal_force"]), "cpu_s": cpu, "wall_s": wall, "MB": memory,
        "depth": result.fields["wear_depth"], "pressure": result.pressure,
        "volume": float(result.history["wear_volume"].sum()),
    }  # fmt: skip


def run_wear(sizes: list[int]) -> int:
    """Measure the cycle jumps against every cycle solved; print the table."""
    import numpy as np

    rows, failures = [], 0
    for n in sizes:
        reference = None
        for jump in (1, *JUMPS):
            status, out = isolated(_measure, punch_table(K, CYCLES, jump, n), timeout=3600.0)
            row = {"n": n, "jump": jump}
            if status != "ok" or (reference is None and out["status"] != "converged"):
                failures += 1
                rows.append({**row, "status": f"error: {out if status != 'ok' else out['status']}"})
                break
            reference = reference or out
            depth, pressure = reference["depth"], reference["pressure"]
            rows.append({
                **row, **{k: v for k, v in out.items() if k not in ("depth", "pressure", "volume")},
                "profile_err": float(np.abs(out["depth"] - depth).max() / depth.max()),
                "pressure_err": float(np.abs(out["pressure"] - pressure).max() / pressure.max()),
                "volume_ratio": out["volume"] / reference["volume"],
            })  # fmt: skip
            print(f"  n {n} jump {jump}: {out['status']}", file=sys.stderr)
    print(f"Cycle jumps: a fretted flat punch over {CYCLES:,} cycles, one thread, each case in a "
          "child process; errors against every cycle solved (jump 1)")  # fmt: skip
    print(format_table(rows))
    return 1 if failures else 0
