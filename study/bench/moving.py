"""Moving-load benchmark: the cost of one frictionless pass over elastic-perfectly plastic steel.

A rigid sphere (R = 10 mm) at p_0 = ``ratio`` k (k = sigma_Y / sqrt(3), sigma_Y = 433 MPa,
E = 210 GPa, nu = 0.3) is pressed at the origin in two steps and slid 8 a along +x in steps
of a/4, mu = 0 (issue 24's cost scene); the grid has ``n`` cells across the contact diameter
(cells of 2a/n, layers of a/n; the grid covers the track plus 1.5 a on every side, the volume
twice the static yield depth).  Two rows per size, in the same run: every increment on the
window that follows the contact (``follows``, the default, :mod:`solver.drive.window`) and on the
whole track (``track``, ``grid.follow_contact = false``): cells of the window and of the
track, wall and CPU time, peak memory, plasticity iterations, largest plastic strain and its
difference from the whole track's, status.  Each row runs in a fresh process.

``python -m study bench moving [--sizes N ...]`` (N: cells across the contact, default 16 32).
``--periodic``: sliding in periodic mode instead (:mod:`.sliding_periodic`).
"""

from __future__ import annotations

import math

from .timing import format_table, isolated, machine, timed_solve

YIELD = 433.0127e6  # Pa: k = 250 MPa
RATIO = 5.0  # p_0 / k
TRAVEL = 8.0  # contact radii
STEPS_PER_RADIUS = 4


def pass_table(across: int, ratio: float = RATIO, follow: bool = True) -> dict:
    """The case table of one pass with ``across`` cells across the contact diameter.

    ``follow``: ``grid.follow_contact`` (false: every increment on the whole track).
    """
    import solver

    body2 = {
        "behaviour": "elastic-plastic", "E": 210e9, "nu": 0.3,
        "hardening": {"law": "perfect", "yield_stress": YIELD},
    }  # fmt: skip
    table = {
        "body1": {"behaviour": "rigid", "radius": 0.01}, "body2": body2,
        "friction": {"coefficient": 0.0},
    }  # fmt: skip
    pressure = ratio * YIELD / math.sqrt(3.0)
    probe = {**table, "load": {"hertz_pressure": pressure}, "grid": {"n": [16, 16, 16]}}
    radius = solver.Case.from_dict(probe).hertz.radius
    cell = 2.0 * radius / across
    nx = math.ceil((TRAVEL + 3.0) * radius / cell)
    ny = math.ceil(3.0 * radius / cell)
    path = [
        {"hertz_pressure": pressure, "steps": 2},
        {"slide": [TRAVEL * radius, 0.0], "steps": int(TRAVEL * STEPS_PER_RADIUS)},
    ]
    depth = solver.Case.from_dict({**table, "load": {"path": path}, "grid": {"n": [nx, ny, 64]}})
    # layers half a cell thick: on cubic cells the perfectly plastic pass stalls and strays
    # (ep_max 0.0088 instead of 0.0045 at 16 across; docs: how-to "Moving contacts")
    nz = math.ceil(2.0 * depth.volume_grid.z[-1] / cell)
    grid = {"n": [nx, ny, nz], "follow_contact": follow}
    return {**table, "load": {"path": path}, "grid": grid}


def _row(across: int, follow: bool) -> dict:
    case, result, wall, cpu, memory = timed_solve(pass_table(across, follow=follow))
    nx, ny, nz = case.volume_grid.shape
    window = case.moving_window or (nx, ny)
    return {
        "across": across,
        "solved on": "follows" if follow else "track",
        "window": f"{window[0]}x{window[1]}x{nz}",
        "track": f"{nx}x{ny}x{nz}",
        "steps": case.total_steps,
        "wall_s": round(wall, 1),
        "cpu_s": round(cpu, 1),
        "peak_MB": round(memory),
        "plastic_its": int(result.history["plastic_iterations"].sum()),
        "ep_max": float(result.history["max_plastic_strain"].max()),
        "status": result.status,
    }


def run_moving(sizes: list[int], periodic: bool = False, travel: float | None = None) -> int:
    """Print the table of one pass per size and way; 0 when every row ran.

    ``periodic``: the periodic-mode tables (:func:`.sliding_periodic.run_sliding_periodic`,
    the rough pass sliding ``travel`` of its period).
    """
    if periodic:
        from .sliding_periodic import run_sliding_periodic

        return run_sliding_periodic(sizes, travel)
    rows, failed = [], False
    for across in sizes:
        pair = []
        for follow in (True, False):
            status, row = isolated(_row, across, follow, timeout=7200.0)
            if status != "ok":
                failed = True
                row = {"across": across, "status": f"error: {row}"}
            pair.append(row)
        reference = pair[1].get("ep_max")
        for row in pair:
            if "ep_max" in row:
                ep = row["ep_max"]
                row["ep_max"] = f"{ep:.4g}"
                row["vs_track"] = f"{ep / reference - 1:+.2%}" if reference else "-"
        rows.extend(pair)
    print(
        f"# one frictionless pass over {TRAVEL:g} a at p_0 = {RATIO:g} k in steps of "
        f"a/{STEPS_PER_RADIUS}; {machine()}"
    )
    print(format_table(rows))
    return 1 if failed else 0
