"""Benchmark: cycle jumps of a wearing contact against every cycle solved.

``python -m study bench wear [--sizes N ...]``: a rigid flat punch (face radius 1 mm, its edge
rounded to 1 mm) slid to and fro by 5 % of its radius over a wearing steel flat in gross slip
(W = 100 N, mu = 0.5, Archard's k = 2e-13 1/Pa on the flat, 4 increments a cycle) for 1,000
and 10,000 cycles: solved every cycle, then with fixed jumps (``wear.cycle_jump`` J) and the
automatic jump at several pressure changes (:data:`JUMPS`), each case in a child process, one
thread.  Per case: solved cycles, increments, CPU and wall time, peak
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
#: The flat's Archard coefficient (1/Pa), and per number of cycles the jumps measured: every
#: cycle solved (1, the reference), fixed jumps, and the automatic jump at pressure changes.
K = 2e-13
JUMPS = {
    1000: (1, 10, 20, 50, 100, ("auto", 0.1), ("auto", 0.05), ("auto", 0.02)),
    10_000: (1, 100, ("auto", 0.1), ("auto", 0.05)),
}


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
    cycles = result.history["step_cycle"]
    return {
        "status": result.status, "solved_cycles": len(set(cycles[cycles > 0].tolist())),
        "steps": cycles.size, "cpu_s": cpu, "wall_s": wall, "MB": memory,
        "depth": result.fields["wear_depth"], "pressure": result.pressure,
        "volume": float(result.history["wear_volume"].sum()),
    }  # fmt: skip


def run_wear(sizes: list[int]) -> int:
    """Measure the cycle jumps against every cycle solved; print the table."""
    import numpy as np

    rows, failures = [], 0
    for n in sizes:
        for cycles, jumps in JUMPS.items():
            reference = None
            for jump in jumps:
                rule = {"pressure_change": jump[1]} if isinstance(jump, tuple) else {}
                jump = jump[0] if rule else jump
                table = punch_table(K, cycles, jump, n, **rule)
                status, out = isolated(_measure, table, timeout=3600.0)
                label = f"auto, {rule['pressure_change']:g}" if rule else str(jump)
                row = {"n": n, "cycles": cycles, "jump": label}
                if status != "ok" or (reference is None and out["status"] != "converged"):
                    failures += 1
                    error = out if status != "ok" else out["status"]
                    rows.append({**row, "status": f"error: {error}"})
                    break
                reference = reference or out
                depth, peak = reference["depth"], reference["pressure"]
                kept = {k: v for k, v in out.items() if k not in ("depth", "pressure", "volume")}
                rows.append({
                    **row, **kept,
                    "profile_err": float(np.abs(out["depth"] - depth).max() / depth.max()),
                    "pressure_err": float(np.abs(out["pressure"] - peak).max() / peak.max()),
                    "volume_ratio": out["volume"] / reference["volume"],
                })  # fmt: skip
                print(f"  n {n} cycles {cycles} jump {label}: {out['status']}", file=sys.stderr)
    print("Cycle jumps: a fretted flat punch over 1,000 and 10,000 cycles, one thread, each case "
          "in a child process; errors against every cycle solved (jump 1); auto: the automatic "
          "jump at its pressure change (wear.solved_cycles 100)")  # fmt: skip
    print(format_table(rows))
    return 1 if failures else 0
