"""Benchmark: the shakedown map by Melan's theorem solved directly, beside the incremental passes.

``python -m study bench shakedown [--incremental]``: the 12 cases of
``campaigns/shakedown_map.toml`` (a rigid sphere sliding over elastic-perfectly plastic steel,
p_0/k = 2 to 5, mu = 0.1, 0.3, 0.5) solved with ``solver.method = "static_shakedown"`` (one
conic program a case, :mod:`solver.theorems`), and with ``--incremental`` also as the campaign
has them (four passes a case, the four loops), each in a child process, one thread.  Per case:
Melan's certified lower bound, the static program's estimate and the two upper bounds
(pointwise, Koiter's kinematic; p_0/k), what they say of the case's own load (below first
yield: elastic; at most the certified lower bound: shakes down;
above an upper bound: does not; between: undecided on this mesh), the incremental regime, CPU,
wall, memory; then the totals and the ratio of the two methods' CPU.

The incremental cases put the plastic print into the gap (the contact conforms pass after pass),
the theorem takes Hamilton's field on an unchanging surface: their regimes need not agree
near the limit (the geometric shakedown of Kapoor and Johnson).
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

from .timing import format_table, isolated

#: The campaign whose cases the benchmark solves both ways.
CAMPAIGN = Path(__file__).resolve().parents[2] / "campaigns" / "shakedown_map.toml"
#: Longest an incremental case may take (s) before its row says so.
INCREMENTAL_TIMEOUT = 7200.0


def _theorem(table: dict) -> dict:
    from .timing import timed_solve

    table = {**table, "solver": {**table.get("solver", {}), "method": "static_shakedown"}}
    table["solver"].pop("plastic_tolerance", None)
    table.pop("model", None)  # the incremental case's version: the theorem's is today's
    _, result, wall, cpu, memory = timed_solve(table)
    h = result.history
    return {
        "lower": float(h["static_shakedown_lower_bound"][0]),
        "estimate": float(h["static_shakedown_limit"][0]),
        "upper": float(h["shakedown_upper_bound"][0]),
        "kinematic": float(h["kinematic_upper_bound"][0]),
        "first_yield": float(h["first_yield_limit"][0]),
        "status": result.status,
        "wall": wall, "cpu": cpu, "memory": memory,
    }  # fmt: skip


def _incremental(table: dict) -> dict:
    from .timing import timed_solve

    _, result, wall, cpu, memory = timed_solve(table)
    regime = result.shakedown.regime if result.shakedown is not None else "?"
    return {"regime": regime, "status": result.status, "wall": wall, "cpu": cpu, "memory": memory}


def _verdict(p0k: float, theorem: dict) -> str:
    if p0k < theorem["first_yield"]:
        return "elastic"
    upper = min(theorem["upper"], theorem["kinematic"])
    if p0k <= min(theorem["lower"], upper):
        return "shakes down"
    if p0k > upper:
        return "does not shake down"
    return "undecided on this mesh"


def run_shakedown(sizes: list[int], incremental: bool = False) -> int:
    """Solve the shakedown map's cases by the theorem (and incrementally); print the table."""
    del sizes  # the campaign fixes the cases
    from ..campaign import load_campaign

    campaign = load_campaign(CAMPAIGN)
    rows, totals, failures = [], {"theorem": [0.0, 0.0], "incremental": [0.0, 0.0]}, 0
    start = time.perf_counter()
    for item in campaign.cases:
        case = item.case()
        table = case.to_dict()
        p0k = case.reference.max_pressure / (case.body2.hardening.yield_stress / 3**0.5)
        row = {"case": item.label, "mu": case.friction_coefficient, "p0/k": p0k}
        status, theorem = isolated(_theorem, table)
        if status != "ok":
            failures += 1
            print(f"{row['case']}: theorem: {theorem}")
            continue
        totals["theorem"][0] += theorem["cpu"]
        totals["theorem"][1] += theorem["wall"]
        row.update(
            lower=theorem["lower"], estimate=theorem["estimate"], upper=theorem["upper"],
            kinematic=theorem["kinematic"],
            theorem=_verdict(p0k, theorem),
            theorem_status=theorem["status"], theorem_cpu_s=theorem["cpu"],
            theorem_wall_s=theorem["wall"], theorem_MB=theorem["memory"],
        )  # fmt: skip
        if incremental:
            status, passes = isolated(_incremental, table, timeout=INCREMENTAL_TIMEOUT)
            if status != "ok":
                failures += 1
                row.update(incremental=passes)
            else:
                totals["incremental"][0] += passes["cpu"]
                totals["incremental"][1] += passes["wall"]
                row.update(
                    incremental=passes["regime"], incremental_status=passes["status"],
                    incremental_cpu_s=passes["cpu"], incremental_wall_s=passes["wall"],
                    incremental_MB=passes["memory"],
                )  # fmt: skip
        rows.append(row)
        print(f"  {row['case']}: done ({time.perf_counter() - start:.0f} s)", file=sys.stderr)
    print(
        "Shakedown map of a sliding sphere (campaigns/shakedown_map.toml, 12 cases): Melan's "
        "theorem solved directly (solver.method = static_shakedown)"
        + (" beside the incremental passes" if incremental else "")
        + "; one thread, each case in a child process"
    )
    print(format_table(rows))
    theorem_cpu, theorem_wall = totals["theorem"]
    line = f"theorem: {theorem_cpu:.1f} s CPU, {theorem_wall:.1f} s wall for {len(rows)} cases"
    if incremental:
        passes_cpu, passes_wall = totals["incremental"]
        line += (
            f"; incremental: {passes_cpu:.1f} s CPU, {passes_wall:.1f} s wall; the theorem "
            f"takes {theorem_cpu / passes_cpu:.3g} of the incremental CPU"
            if passes_cpu > 0
            else "; no incremental case finished"
        )
    print(line)
    return 1 if failures else 0
