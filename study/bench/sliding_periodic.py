"""Benchmark: sliding in periodic mode, a rough pass and a sparse asperity against the window.

``python -m study bench moving --periodic [--sizes 64 128 256] [--travel 0.0625]``.  Two
tables, each row in a fresh process (:func:`.timing.isolated`), one thread.

A rough pass: the rough period of :mod:`.rough_periodic` (L = 100 um, rms 50 nm, the heights
generated once) as a rigid body 1 slid along x over linearly hardening steel at the mean
pressure :data:`MEAN_PRESSURE`, mu = :data:`MU` capped at the body's shear yield stress; ``n x n``
cells a period, the depth sized from the elastic yield region and layers at most
:data:`LAYER_CELLS` of a cell thick (the rule of :func:`solver.case.notes.layer_note`), in
increments of a cell over ``--travel`` of the period (:data:`TRAVEL` unless told; 1 is a
whole pass of n increments).  The press alone is solved and timed too, in a process of its own:
the slide's CPU is the whole run's less the press's, so that a pass (the press and n slide
increments) is extrapolated from the slide's own cost.  Per size: cells, increments, wall,
CPU, the press's CPU, CPU a slide increment and a pass, peak memory, plasticity iterations,
e_p,max, the deepest residual dent, status.

A sparse asperity, both ways: one rigid sphere (R = 10 mm, W = 100 N, p_0 about 1.3 times
first yield) slid 4 a over hardening steel at 6 cells a contact radius and 15 layers 1.5 a
deep, mu = 0.3: on the window that follows it over an open half-space, and as a spherical
cap (radius 2.5 a) on a flat period of 24 a (the period at which the two agree within 2 %,
tests/test_periodic_sliding.py).  Wall, CPU, memory, e_p,max and the deepest residual dent.
"""

from __future__ import annotations

import math

import numpy as np

from .timing import format_table, isolated, machine, timed_solve

#: Mean pressure of the rough pass (Pa): at 0.25 GPa and mu = 0.3 the pass on 128 cells a
#: period strays past the small-strain range (e_p 0.097) and does not converge.
MEAN_PRESSURE = 0.1e9
#: Friction coefficient of the rough pass (the sparse asperity's is 0.3, its test's).
MU = 0.2
#: Thickest layer of the rough pass, in cells.
LAYER_CELLS = 0.6
#: Travel of the rough pass over the period unless ``--travel`` is given (a sixteenth: a
#: whole pass at 256 cells a period takes over an hour of CPU here; the table extrapolates the
#: CPU a slide increment takes to the pass).
TRAVEL = 1 / 16


def rough_pass_table(n: int, travel: float = TRAVEL) -> dict:
    """The case table of the rough pass on ``n x n`` cells a period, ``travel`` of it slid."""
    import solver

    from .rough_periodic import SCENE, heights, steel

    period = SCENE["period"]
    press = {"normal_force": MEAN_PRESSURE * period**2, "steps": 2}
    table = {
        "body1": {"behaviour": "rigid", "radius": "inf", "surface": heights()},
        "body2": steel(),
        "friction": {"coefficient": MU, "shear_limit": "yield"},
        "load": {"path": [press, {"slide": [travel * period, 0.0], "steps": round(travel * n)}]},
        "grid": {"n": [n, n, 4], "size": period, "periodic": True},
    }  # fmt: skip
    depth = solver.Case.from_dict(table).grid.depth  # sized from the elastic yield region
    table["grid"]["n"][2] = max(4, math.ceil(depth / (LAYER_CELLS * period / n)))
    return table


def sparse_pair_tables(cells: int, period_radii: float, layers: int, mu: float = 0.3) -> tuple:
    """The sparse asperity's two case tables: open (the window follows) and periodic.

    A rigid sphere (R = 10 mm, W = 100 N) slid 4 a over linearly hardening steel (sigma_Y =
    0.9 GPa, H = E/20): ``cells`` a contact radius, ``layers`` 1.5 a deep, the same cells in
    both; the periodic one a spherical cap (radius 2.5 a) on a flat period of ``period_radii``
    a (a whole number of cells).
    """
    import solver
    from solver.bodies.heights import HeightMap

    hardening = {"law": "linear", "yield_stress": 0.9e9, "modulus": 210e9 / 20}
    steel = {"behaviour": "elastic-plastic", "E": 210e9, "nu": 0.3, "hardening": hardening}
    rigid = {"behaviour": "rigid", "radius": 0.01}
    a = solver.Case.from_dict(
        {"body1": rigid, "body2": {"behaviour": "elastic", "E": 210e9, "nu": 0.3},
         "load": {"normal_force": 100.0}, "grid": {"n": 16}}
    ).reference.radius  # fmt: skip
    dx, travel = a / cells, 4 * a
    path = [{"normal_force": 100.0, "steps": 4}, {"slide": [travel, 0.0], "steps": 2 * cells}]
    along, across = round((3 * a + travel) / dx), round(3 * a / dx)
    grid = {"n": [along, across, layers], "depth": 1.5}
    open_case = {"body1": rigid, "body2": steel, "friction": {"coefficient": mu},
                 "load": {"path": path}, "grid": grid}  # fmt: skip
    n = round(period_radii * a / dx)
    x = (np.arange(n) + 0.5 - n / 2) * dx
    xx, yy = np.meshgrid(x, x)
    cap = np.minimum(xx**2 + yy**2, (2.5 * a) ** 2) / (2 * 0.01)
    periodic = {
        "body1": {"behaviour": "rigid", "radius": "inf", "surface": HeightMap(x, x, cap, "cap")},
        "body2": steel,
        "friction": {"coefficient": mu},
        "load": {"path": path},
        "grid": {"n": [n, n, layers], "size": [n * dx, n * dx], "periodic": True,
                 "depth": 1.5 * a},
    }  # fmt: skip
    return open_case, periodic


def _timed(table: dict) -> dict:
    case, result, wall, cpu, memory = timed_solve(table)
    history, fields = result.history, result.fields
    return {
        "cells": "x".join(map(str, case.volume_grid.shape)),
        "increments": case.total_steps,
        "wall_s": wall,
        "cpu_s": cpu,
        "cpu_per_increment_s": cpu / case.total_steps,
        "peak_MB": memory,
        "plastic_its": int(history["plastic_iterations"].sum()),
        "ep_max": float(fields["plastic_strain"].max()),
        "dent_nm": 1e9 * float(fields["residual_displacement_z"].max()),
        "status": result.status,
    }


def _press_table(table: dict) -> dict:
    """The rough pass's press alone (its first stage)."""
    return table | {"load": {"path": table["load"]["path"][:1]}}


def run_sliding_periodic(sizes: list[int], travel: float | None = None) -> int:
    """Print both tables; 0 when every row ran.

    The rough pass over ``sizes``, ``travel`` of the period slid (1 a whole pass;
    :data:`TRAVEL` when None).
    """
    from solver.keys import MAX_CELLS

    from .registry import BenchOptionError

    travel = TRAVEL if travel is None else travel
    if not 1.0 / MAX_CELLS <= travel <= 1.0:  # a cell an increment on at most MAX_CELLS cells
        raise BenchOptionError(
            f"--travel: the fraction of the period the rough pass slides, in [1/{MAX_CELLS}, 1] "
            f"(1 a whole pass), got {travel:g}"
        )
    smallest = math.ceil(1 / travel)
    if min(sizes) < smallest:
        raise BenchOptionError(
            f"--sizes: the rough pass slides {travel:g} of the period a cell an increment: give "
            f"{smallest} cells a period or more, got {min(sizes)}"
        )
    failed = False

    def row(label: dict, function, *args) -> dict:
        nonlocal failed
        status, out = isolated(function, *args, timeout=8 * 3600.0)
        if status != "ok":
            failed = True
            return label | {"status": f"error: {out}"}
        return label | out

    rough = []
    for n in sizes:  # the press alone in a process of its own: the slide's CPU is the rest
        table = rough_pass_table(n, travel)
        press = row({}, _timed, _press_table(table))
        out = row({"n": n}, _timed, table)
        if "cpu_s" in press and "cpu_s" in out:
            per_slide = (out["cpu_s"] - press["cpu_s"]) / (out["increments"] - press["increments"])
            out |= {"press_cpu_s": press["cpu_s"], "cpu_per_slide_s": per_slide,
                    "cpu_per_pass_s": press["cpu_s"] + n * per_slide}  # fmt: skip
        rough.append(out)
    print(
        f"# a rough pass in periodic mode: L = 100 um, rms 50 nm, mean pressure "
        f"{MEAN_PRESSURE / 1e9:g} GPa, mu = {MU:g} capped at k, linear hardening; layers at "
        f"most {LAYER_CELLS:g} cell thick, {travel:g} of the period in increments of a cell "
        f"after 2 to press (press_cpu: the press alone, solved apart; cpu_per_slide: the rest "
        f"an increment; cpu_per_pass: the press and n slide increments, a whole pass); "
        f"{machine()}"
    )
    print(format_table(rough))
    open_case, periodic = sparse_pair_tables(6, 24.0, 15)
    pair = [row({"solved on": "window (open)"}, _timed, open_case),
            row({"solved on": "period 24 a"}, _timed, periodic)]  # fmt: skip
    if all("cpu_s" in r for r in pair):
        pair[1]["cpu_vs_window"] = pair[1]["cpu_s"] / pair[0]["cpu_s"]
    print("# one sphere slid 4 a, 6 cells a radius: the open window and a sparse period")
    print(format_table(pair))
    return 1 if failed else 0
