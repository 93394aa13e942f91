"""Slip-stick loop benchmark: the cost of friction along a load path, against closed forms.

Three scenes (issue "four loops", item 4), each row in a fresh process (:mod:`study.bench`):

- **Spence**: rigid sphere on a nu = 0 half-space (Dundurs beta = -0.5, the normal-tangential
  coupling at its strongest), mu = 0.2986, normal load in 70 steps, the contact 70 cells across.
  Spence (1975): a self-similar stick disk of c/a = 0.50 and a peak pressure 1.31 p_H (read from
  his figure, no closed form).  CONTACT (Vollebregt's Fortran code, not installable here) was
  measured by the issue's author at about 8 s on this machine.
- **Cattaneo-Mindlin**: two identical steel spheres (beta = 0), Q = 0.5 mu W applied in 1 and
  in 10 steps; the ratio of their costs is the price of small increments.
- **Fretting path**: the same pair, one normal step, then Q to +Q*, -Q*, +Q* in 20 steps each;
  the loop area of the last cycle against Mindlin-Deresiewicz
  (:func:`solver.theory.friction.mindlin_deresiewicz_energy`).

``python -m study bench slipstick [--sizes N ...]`` (sizes: the Cattaneo and fretting grids).
Spence runs with both FFT planners (``solver.fft_planner``; the plans' timing is in the time).
"""

from __future__ import annotations

import math

import numpy as np

from .timing import format_table, isolated, timed_solve

STEEL = {"behaviour": "elastic", "E": 210e9, "nu": 0.3}
RADIUS, FORCE = 0.015, 1000.0
SPENCE_MU, SPENCE_STEPS, SPENCE_CELLS_ACROSS, SPENCE_HALF_WIDTH = 0.2986, 70, 70, 1.3
#: Spence (1975) for mu = 0.2986, nu = 0: stick radius over contact radius, and the peak
#: pressure over the Hertz peak of the same load (read from his figure).
SPENCE_STICK_RATIO, SPENCE_PEAK_RATIO = 0.50, 1.31
PAIR_MU, PAIR_FRACTION, PAIR_HALF_WIDTH, PAIR_STAGE_STEPS = 0.3, 0.5, 1.5, 20


def spence_table(planner: str = "estimate") -> dict:
    """Spence's scene with the contact ``SPENCE_CELLS_ACROSS`` cells across."""
    n = round(SPENCE_CELLS_ACROSS * SPENCE_HALF_WIDTH)
    return {
        "solver": {"fft_planner": planner},
        "body1": {"radius": RADIUS, "behaviour": "rigid"},
        "body2": {"radius": "inf", "behaviour": "elastic", "E": 210e9, "nu": 0.0},
        "load": {"normal_force": FORCE, "steps": SPENCE_STEPS},
        "friction": {"coefficient": SPENCE_MU},
        "grid": {"n": n, "half_width": SPENCE_HALF_WIDTH},
    }


def pair_table(n: int, tangential: list[tuple[float, int]]) -> dict:
    """Two identical steel spheres: a normal step, then tangential stages (Q_x (N), steps)."""
    stages = [{"normal_force": FORCE, "steps": 1}]
    stages += [{"tangential_force": [q, 0.0], "steps": steps} for q, steps in tangential]
    return {
        "body1": {"radius": RADIUS, **STEEL},
        "body2": {"radius": RADIUS, **STEEL},
        "load": {"path": stages},
        "friction": {"coefficient": PAIR_MU},
        "grid": {"n": n, "half_width": PAIR_HALF_WIDTH},
    }


def _solve(table: dict) -> dict:
    case, result, wall, cpu, memory = timed_solve(table)
    h = result.history
    area = np.asarray(h["contact_area"])
    return {
        "time": wall,
        "cpu": cpu,
        "memory": memory,
        "converged": result.converged,
        "tangential": int(np.sum(h["slip_iterations"])),
        "normal": int(np.sum(h["normal_iterations"])),
        "coupling": int(np.sum(h["coupling_iterations"])),
        "stick_ratio": math.sqrt(h["stick_area"][-1] / area[-1]) if area[-1] > 0 else math.nan,
        "peak_ratio": float(h["max_pressure"][-1]) / case.hertz.max_pressure,
        "force_x": np.asarray(h["tangential_force_x"]),
        "shift_x": np.asarray(h["tangential_shift_x"]),
        "hertz_radius": case.hertz.radius,
    }


def _full_slip_shift(hertz_radius: float) -> float:
    """C of :func:`solver.theory.friction.cattaneo_shift` for the two identical steel spheres, m."""
    shear_modulus = STEEL["E"] / (2 * (1 + STEEL["nu"]))
    return 2 * 3 * PAIR_MU * FORCE * (2 - STEEL["nu"]) / (16 * shear_modulus * hertz_radius)


def _row(scene: str, n: int, steps: int, out: dict, errors: dict) -> dict:
    return {
        "scene": scene,
        "n": n,
        "steps": steps,
        "time_s": out["time"],
        "cpu_s": out["cpu"],
        "tangential_it": out["tangential"],
        "normal_it": out["normal"],
        "coupling_it": out["coupling"],
        **errors,
        "converged": out["converged"],
        "peak_MB": out["memory"],
    }


def run_slipstick(sizes: list[int]) -> int:
    """Run the three scenes and print their table; returns an exit status."""
    from solver.theory.friction import (
        cattaneo_shift,
        cattaneo_stick_ratio,
        mindlin_deresiewicz_energy,
    )

    rows, failures = [], 0

    def record(scene, n, steps, table, errors):
        nonlocal failures
        status, out = isolated(_solve, table)
        if status != "ok":
            failures += 1
            print(f"{scene} n={n}: {out}")
            return None
        rows.append(_row(scene, n, steps, out, errors(out)))
        return out

    n_spence = spence_table()["grid"]["n"]
    for planner in ("estimate", "measure"):
        record(
            f"Spence ({planner})",
            n_spence,
            SPENCE_STEPS,
            spence_table(planner),
            lambda out: {
                "c/a": out["stick_ratio"],
                "c/a_ref": SPENCE_STICK_RATIO,
                "p_max/p_H": out["peak_ratio"],
                "ref": SPENCE_PEAK_RATIO,
            },
        )
    q_star = PAIR_FRACTION * PAIR_MU * FORCE
    for n in sizes:
        costs = {}
        for steps in (1, 10):
            out = record(
                "Cattaneo Q",
                n,
                steps,
                pair_table(n, [(q_star, steps)]),
                lambda out: {
                    "c/a": out["stick_ratio"],
                    "c/a_ref": cattaneo_stick_ratio(q_star, PAIR_MU, FORCE),
                    "p_max/p_H": math.nan,
                    "ref": math.nan,
                },
            )
            if out is not None:
                costs[steps] = out["cpu"]
                shift = cattaneo_shift(
                    q_star, PAIR_MU, FORCE, _full_slip_shift(out["hertz_radius"])
                )
                rows[-1]["shift_err_%"] = 100 * abs(out["shift_x"][-1] / shift - 1)
        if len(costs) == 2:
            print(f"n={n}: Q in 10 steps costs {costs[10] / costs[1]:.2f}x one step (CPU)")
        stages = [
            (q_star, PAIR_STAGE_STEPS),
            (-q_star, PAIR_STAGE_STEPS),
            (q_star, PAIR_STAGE_STEPS),
        ]
        out = record(
            "fretting path",
            n,
            1 + 3 * PAIR_STAGE_STEPS,
            pair_table(n, stages),
            lambda out: {
                "c/a": math.nan,
                "c/a_ref": math.nan,
                "p_max/p_H": math.nan,
                "ref": math.nan,
            },
        )
        if out is not None:
            # the last cycle: +Q* -> -Q* -> +Q*, loop area = closed integral of Q d(delta)
            cycle = slice(1 + PAIR_STAGE_STEPS - 1, None)
            area = abs(np.trapezoid(out["force_x"][cycle], out["shift_x"][cycle]))
            reference = mindlin_deresiewicz_energy(
                q_star, PAIR_MU, FORCE, _full_slip_shift(out["hertz_radius"])
            )
            rows[-1]["energy_err_%"] = 100 * abs(area / reference - 1)
    columns = list(dict.fromkeys(key for row in rows for key in row))
    rows = [{key: row.get(key, math.nan) for key in columns} for row in rows]
    print(
        f"Slip-stick loop: Spence (rigid sphere on nu = 0, mu = {SPENCE_MU}, "
        f"{SPENCE_STEPS} normal steps, contact {SPENCE_CELLS_ACROSS} cells across); "
        f"two steel spheres R = {RADIUS * 1e3:g} mm, W = {FORCE:g} N, mu = {PAIR_MU}, "
        f"Q* = {PAIR_FRACTION} mu W; one thread, each row a fresh process"
    )
    print(format_table(rows))
    return 1 if failures else 0
