"""Benchmark: hard cases where Coulomb friction asks for more shear than the metal can carry.

``python -m study bench hard [--sizes N ...]``: the scenes of issue 58 (a rigid sphere on
elastic-perfectly plastic steel, k = 250 MPa, pressed to p_0 = 4 k and sheared to 0.9 and 0.99
of the force friction can carry; the same sphere sliding 3 contact radii at p_0 = 3 k; linear
hardening H = 2 GPa at p_0 = 6 k), each at mu = 0.3 (the easy neighbour) and at mu = 0.5 to 2,
with Coulomb's law alone and with ``friction.shear_limit = "yield"``, each case in a child
process, one thread.  Under the limit the tangential force is the same fraction of what the
capped contact can carry (:func:`solver.theory.friction.capped_sliding_force` on Hertz's
pressure with k), since a force above it is gross sliding.  Per case: status, increments
solved, CPU and wall time, peak memory, the largest plastic strain and surface shear ratio,
plasticity-loop iterations, and the CPU over the scene's mu = 0.3 case under the same law.
Then the pressed scene at mu = 1 under the limit (m = 1 and 0.9) on refined meshes
(``--sizes``, cells a side): its largest plastic strain, in the top layer where the capped slip
traction shears it, and below it, with the dent, as the layers thin.

No peer contact solver has a shear limit or elastic-plastic friction (Tamaas, ContactMechanics
and CONTACT solve elastic friction or frictionless plasticity): the table is ours alone.
"""

from __future__ import annotations

import math
import sys

from .timing import format_table, isolated, timed_solve

#: Shear yield stress of the steel (Pa) and its modulus, Poisson ratio, sphere radius (m).
K, E, NU, RADIUS = 250e6, 210e9, 0.3, 0.01


def _contact(p0: float) -> tuple[float, float]:
    """Hertz's radius (m) and force (N) of the rigid sphere on the steel at peak ``p0``."""
    a = math.pi * p0 * RADIUS / (2 * E / (1 - NU * NU))
    return a, 2 / 3 * math.pi * a * a * p0


def _body(hardening: dict) -> dict:
    return {"behaviour": "elastic-plastic", "radius": "inf", "E": E, "nu": NU,
            "hardening": hardening}  # fmt: skip


def _case(body2: dict, friction: dict, n: list[int], path: list[dict]) -> dict:
    return {"body1": {"behaviour": "rigid", "radius": RADIUS}, "body2": body2,
            "friction": friction, "grid": {"n": n}, "load": {"path": path}}  # fmt: skip


PERFECT = {"law": "perfect", "yield_stress": K * math.sqrt(3.0)}
LINEAR = {"law": "linear", "yield_stress": K * math.sqrt(3.0), "modulus": 2e9}


def scene_table(
    scene: str, mu: float, capped: bool, n: int | None = None, factor: float = 1.0
) -> dict:
    """The case table of ``scene`` at friction ``mu``, limited by ``"yield"`` if ``capped``.

    ``factor`` is ``friction.shear_factor`` m (the cap m k).
    """
    limit = {"shear_limit": "yield"} | ({"shear_factor": factor} if factor != 1.0 else {})
    friction = {"coefficient": mu, **(limit if capped else {})}
    if scene == "sliding":
        p0 = 3 * K
        a, _ = _contact(p0)
        path = [{"hertz_pressure": p0, "steps": 2}, {"slide": [3 * a, 0.0], "steps": 12}]
        return _case(_body(PERFECT), friction, [40, 32, 24], path)
    from solver.theory.friction import capped_sliding_force

    share, hardening, p0, cells = {
        "pressed 0.9": (0.9, PERFECT, 4 * K, 16),
        "pressed 0.99": (0.99, PERFECT, 4 * K, 16),
        "linear hardening": (0.9, LINEAR, 6 * K, 24),
    }[scene]
    a, force = _contact(p0)
    carried = capped_sliding_force(mu, p0, a, factor * K) if capped else mu * force
    n = n or cells
    path = [{"hertz_pressure": p0, "steps": 4},
            {"tangential_force": [share * carried, 0.0], "steps": 8}]  # fmt: skip
    return _case(_body(hardening), friction, [n, n, n], path)


#: Scene -> the friction coefficients measured (the first is the easy neighbour).
SCENES = {
    "pressed 0.9": (0.3, 1.0, 2.0),
    "pressed 0.99": (0.3, 1.0, 2.0),
    "sliding": (0.3, 0.5, 1.0),
    "linear hardening": (0.3, 0.5, 1.0),
}


def _measure(table: dict) -> dict:
    case, result, wall, cpu, memory = timed_solve(table)
    h = result.history
    return {
        "status": result.status,
        "steps": f"{len(h['normal_force'])}/{case.total_steps}",
        "cpu_s": cpu, "wall_s": wall, "MB": memory,
        "ep_max": float(h["max_plastic_strain"].max()),
        "shear_ratio": float(h["surface_shear_ratio"].max()),
        "plastic_its": int(h["plastic_iterations"].sum()),
    }  # fmt: skip


def _refined(table: dict) -> dict:
    """:func:`_measure` with what a refinement of the plastic zone compares."""
    import numpy as np

    case, result, wall, cpu, memory = timed_solve(table)
    a = case.reference.radius
    strain, depth = result.fields["plastic_strain"], result.depth
    middle = strain[strain.shape[0] // 2, strain.shape[1] // 2]
    return {
        "layer/a": case.volume_grid.dz / a,
        "status": result.status, "cpu_s": cpu, "wall_s": wall, "MB": memory,
        "ep_max": float(strain.max()),
        "ep_max_below_0.1a": float(strain[..., depth > 0.1 * a].max()),
        "axis_int_ep_dz/a": float(np.sum(middle) * case.volume_grid.dz / a),
        "dent/a": float(result.history["residual_depth"][-1] / a),
        "plastic_its": int(result.history["plastic_iterations"].sum()),
    }  # fmt: skip


def run_hard(sizes: list[int]) -> int:
    """Measure the hard cases and the limit's refinement; print the tables."""
    rows, failures = [], 0
    for scene, mus in SCENES.items():
        for capped in (False, True):
            easy = None
            for mu in mus:
                status, out = isolated(_measure, scene_table(scene, mu, capped), timeout=3600.0)
                row = {"scene": scene, "mu": mu, "law": "min(mu p, k)" if capped else "mu p"}
                if status != "ok":
                    failures += 1
                    rows.append({**row, "status": f"error: {out}"})
                    continue
                easy = out["cpu_s"] if easy is None else easy
                rows.append({**row, **out, "cpu/mu0.3": out["cpu_s"] / easy})
                print(f"  {scene} mu {mu} {row['law']}: {out['status']}", file=sys.stderr)
    print("Hard cases (issue 58), one thread, each case in a child process")
    print(format_table(rows))
    refined = []
    for factor in (1.0, 0.9):
        for n in sizes:
            table = scene_table("pressed 0.9", 1.0, True, n, factor)
            status, out = isolated(_refined, table, timeout=7200.0)
            row = {"m": factor, "n": n}
            if status != "ok":
                failures += 1
                refined.append({**row, "status": f"error: {out}"})
                continue
            refined.append({**row, **out})
    print()
    print(
        'The pressed scene at mu = 1 under shear_limit = "yield" (shear_factor m), refined (n^3 '
        "cells): the largest plastic strain, the largest below 0.1 a, the plastic strain "
        "integrated over depth on the axis and the dent, over the contact radius a"
    )
    print(format_table(refined))
    return 1 if failures else 0
