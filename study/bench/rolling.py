"""Rolling benchmark: steady creep force against creepage, slipstick beside CONTACT.

Scene: two identical elastic bodies (E = 210 GPa, nu = 0.25: Dundurs beta = 0), a circular
Hertz contact of radius a = 1 mm (two 100 mm spheres: W = 2987 N, p_0 = 1.43 GPa), mu = 0.3,
longitudinal creepage ``xi = xi_n 3 mu W / (G a^2 C11)`` (C11 = 4.12, Kalker's table: xi_n = 1
is about full slip), rolling along +x, no spin.

- **slipstick**: body 1 a ball of the pair's radius (50 mm), body 2 flat (the contact moves over
  it); loaded, shifted (Cattaneo) to 0.9 of the Johnson-Vermeulen estimate of the creep force,
  then rolled 6 a at the creepage (Kalker's transient theory), in ``2 n`` steps a contact
  radius for ``n`` cells across the contact (a step of half a cell: the step is the error,
  O(step)); the steady force is the mean over the last 2 a.  (From rest the approach to the
  steady state has a tail: after 8 a the small-creepage force is still 0.5 % short.)
- **CONTACT** (E.A.H. Vollebregt's program, Apache-2.0, built from its public sources; not
  part of this project: give its executable in ``CONTACT_EXE``): the same scene in its steady
  rolling mode (``T = 3``, Hertzian semi-axes prescribed, ``n`` elements across the contact,
  rolling step one element), one input file per creepage, run in the same process tree.

The linear rows (``xi_n = 1e-3``, along x and along y) give C11 and C22 beside Kalker's table
(:data:`solver.theory.friction.KALKER_CIRCLE_COEFFICIENTS`).  Columns: code, cells across, steps a
radius, creepage, creep force over mu W (the linear rows: the coefficient), its difference from
CONTACT on 120 elements across (the reference) and from Kalker's table, CPU and wall time, peak
memory (ours: growth of the resident set; CONTACT's: its peak resident set),
tangential-operator applications (ours).

``--steady``: ours solved directly (``steady = true`` stages, :mod:`solver.surface.steady`,
second-order upwind: ``steady``; first order, CONTACT's scheme: ``steady o1``) instead of the
march, on a grid of 1.25 a either side; then a creep curve of :data:`CURVE_POINTS` creepages
(xi_n up to 1) both ways: one steady stage of that many increments, and one transient march a
point, with their CPU and the largest difference between the two curves (of mu W).

``python -m study bench rolling [--sizes N ...] [--peers] [--steady]`` (N: cells across,
default 32 64).
"""

from __future__ import annotations

import math
import os
import resource
import shutil
import subprocess
import tempfile
import time

from solver.theory.friction import KALKER_CIRCLE_COEFFICIENTS

from .timing import format_table, isolated, machine, timed_solve

E, NU, MU = 210e9, 0.25, 0.3
RADIUS = 1e-3  # m, the contact radius
PAIR_RADIUS = 0.05  # m: two 100 mm spheres
#: Kalker's C11, C22, C23 of the scene's nu (placing the creepages; the linear rows compare them)
C11, C22, C23 = KALKER_CIRCLE_COEFFICIENTS[NU]
#: Spins of ``--steady``'s spin rows over the spin of Kalker's linear saturation
#: ``mu W / (G a^3 C23)``.
PHI_N = (0.3, 1.0, 3.0)
#: CONTACT's spin CPHI (rad/mm) per our spin (1/m, x turned towards y) times 1e-3.
SPIN_SIGN = 1.0  # the same sense: checked on the spin rows (both forces +y)
XI_N = (0.1, 0.3, 0.5, 0.7, 1.0)
LINEAR = 1e-3
TRAVEL, AVERAGE = 6.0, 2.0  # contact radii rolled; the last ones averaged
#: CONTACT's elements across the contact of the reference rows
REFERENCE_ACROSS = 120
SHEAR = E / (2 * (1 + NU))
FORCE = 4.0 * E / (2 * (1 - NU * NU)) * RADIUS**3 / (3.0 * PAIR_RADIUS)


def creepage(xi_n: float, coefficient: float = C11) -> float:
    """The creepage of a normalised creepage ``xi_n`` (1: about full slip)."""
    return xi_n * 3.0 * MU * FORCE / (SHEAR * RADIUS**2 * coefficient)


#: The scene's bodies and friction (a case table's first keys).
BODIES = {
    "body1": {"behaviour": "elastic", "E": E, "nu": NU, "radius": PAIR_RADIUS},
    "body2": {"behaviour": "elastic", "E": E, "nu": NU},
    "friction": {"coefficient": MU},
}


def start_force(xi: tuple[float, float]) -> list[float]:
    """The tangential force (N) of the Cattaneo start before rolling at ``xi``.

    0.9 of the Johnson-Vermeulen estimate ``mu W (1 - (1 - xi_n)^3)`` of the creep force (below
    mu W): deliberately off, the rolling finds the steady force.
    """
    coefficients = (C11, C22)
    out = []
    for value, coefficient in zip(xi, coefficients, strict=True):
        xi_n = min(abs(value) * SHEAR * RADIUS**2 * coefficient / (3.0 * MU * FORCE), 1.0)
        out.append(math.copysign(0.9 * (1.0 - (1.0 - xi_n) ** 3) * MU * FORCE, value))
    return out


def rolling_table(across: int, xi: tuple[float, float]) -> dict:
    """The case table: load, shift to :func:`start_force`, roll TRAVEL radii at ``xi``."""
    per_radius = 2 * across
    n = (round((TRAVEL + 2.4) * across / 2), round(2.4 * across / 2))
    return {
        **BODIES,
        "load": {"path": [
            {"normal_force": FORCE},
            {"tangential_force": start_force(xi), "steps": 4},
            {"roll": [TRAVEL * RADIUS, 0.0], "creepage": list(xi),
             "steps": round(TRAVEL * per_radius)},
        ]},
        "grid": {"n": list(n), "half_width": 1.2},
    }  # fmt: skip


def _ours(across: int, xi: tuple[float, float]) -> dict:
    import numpy as np

    case, result, wall, cpu, memory = timed_solve(rolling_table(across, xi))
    axis = "x" if xi[0] else "y"
    last = round(AVERAGE * 2 * across)
    force = float(np.mean(result.history[f"tangential_force_{axis}"][-last:]))
    return {
        "force": force, "cpu": cpu, "wall": wall, "memory": memory,
        "iterations": int(result.history["slip_iterations"].sum()), "status": result.status,
    }  # fmt: skip


#: Creepages of the creep curve of ``--steady`` (xi_n from 1/CURVE_POINTS to 1).
CURVE_POINTS = 50


def steady_table(
    across: int, xi: tuple[float, float], order: int = 2, steps: int = 1, spin: float = 0.0
) -> dict:
    """The case table: load, then the steady state at ``xi`` and ``spin`` (1/m).

    The stage ramps from zero in ``steps`` increments (a creep curve).
    """
    n = round(1.25 * across)  # +-1.25 a in cells of 2 a / across
    rigid = {"creepage": list(xi)} if any(xi) else {}
    rigid.update({"spin": spin} if spin else {})
    return {
        **BODIES,
        "load": {"path": [
            {"normal_force": FORCE},
            {"steady": True, **rigid, "steps": steps},
        ]},
        "grid": {"n": [n, n], "half_width": 1.25},
        "solver": {"steady_order": order},
    }  # fmt: skip


def _ours_steady(across: int, xi: tuple[float, float], order: int = 2, spin: float = 0.0) -> dict:
    _, result, wall, cpu, memory = timed_solve(steady_table(across, xi, order, spin=spin))
    axis = "x" if xi[0] else "y"
    return {
        "force": float(result.history[f"tangential_force_{axis}"][-1]), "cpu": cpu,
        "wall": wall, "memory": memory,
        "iterations": int(result.history["slip_iterations"].sum()), "status": result.status,
    }  # fmt: skip


def _steady_curve(across: int) -> dict:
    """One steady stage of CURVE_POINTS increments up to xi_n = 1: forces, CPU."""
    table = steady_table(across, (creepage(1.0), 0.0), 2, CURVE_POINTS)
    _, result, wall, cpu, _ = timed_solve(table)
    forces = [float(f) for f in result.history["tangential_force_x"][1:]]
    return {"forces": forces, "cpu": cpu, "wall": wall, "status": result.status}


def _curve_comparison(across: int) -> list[str]:
    """The creep curve both ways: CPU of each, the largest difference (of mu W)."""
    status, steady = isolated(_steady_curve, across, timeout=7200.0)
    if status != "ok":
        return [f"creep curve, steady: {steady}"]
    march_cpu, worst = 0.0, 0.0
    for k, force in enumerate(steady["forces"], start=1):
        status, out = isolated(_ours, across, (creepage(k / CURVE_POINTS), 0.0), timeout=7200.0)
        if status != "ok":
            return [f"creep curve, transient point {k}: {out}"]
        march_cpu += out["cpu"]
        worst = max(worst, abs(out["force"] - force) / (MU * FORCE))
    return [
        f"creep curve of {CURVE_POINTS} creepages (xi_n to 1), {across} cells across: steady "
        f"{steady['cpu']:.2f} s CPU ({steady['status']}), transient marches {march_cpu:.1f} s "
        f"CPU ({march_cpu / max(steady['cpu'], 1e-9):.0f} x); largest difference "
        f"{100 * worst:.2f} % of mu W",
    ]


def _contact_input(across: int, xi: tuple[float, float], spin: float = 0.0) -> str:
    """CONTACT's input (module 3, units mm, N, N/mm^2) for steady rolling at ``xi``."""
    elements = round(1.1 * across)  # the potential contact: 1.1 a on each side
    scale, step = elements / across, 2.0 * RADIUS * 1e3 / across
    shear = SHEAR * 1e-6
    lines = [
        "% slipstick bench rolling: steady rolling, Hertzian circle a = 1 mm",
        " 3  MODULE",
        "  203100     P-B-T-N-F-S",  # steady rolling (T = 3), Hertzian normal problem
        "  022020     L-D-C-M-Z-E",
        " 0000331   H-G-I-A-O-W-R",
        "   999   200    30     1   1e-6    MAXGS, MAXIN, MAXNR, MAXOUT, EPS",
        f"  {FORCE:.6f}  {xi[0]:.10e}  {xi[1]:.10e}  {SPIN_SIGN * spin * 1e-3:.10e}"
        "    FN, CKSI, CETA, CPHI",
        f"  {MU:.3f}  {MU:.3f}    FSTAT, FKIN",
        f"  0.000  {step:.8f}  1000.0    CHI, DQ, VELOC",
        f"  {NU:.4f}  {NU:.4f}  {shear:.4f}  {shear:.4f}    POISS 1,2, GG 1,2",
        "   -3    IPOTCN",
        f"  {elements}  {elements}  {RADIUS * 1e3:.4f}  {RADIUS * 1e3:.4f}  {scale:.8f}"
        "    MX, MY, AA, BB, SCALE",
        "",
        " 0  MODULE",
        "",
    ]
    return "\n".join(lines)


def _contact(executable: str, across: int, xi: tuple[float, float], spin: float = 0.0) -> dict:
    """Run CONTACT on the scene; its force on body 2 (the opposite of its force on body 1)."""
    folder = tempfile.mkdtemp(prefix="contact_")
    try:
        with open(os.path.join(folder, "bench.inp"), "w") as handle:
            handle.write(_contact_input(across, xi, spin))
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        start = time.perf_counter()
        done = subprocess.run(
            [executable, "2", "bench"], cwd=folder, capture_output=True, text=True, timeout=3600
        )
        wall = time.perf_counter() - start
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        if done.returncode != 0:
            raise RuntimeError(f"CONTACT exited with {done.returncode}: {done.stdout[-300:]}")
        with open(os.path.join(folder, "bench.out")) as handle:
            lines = handle.read().splitlines()
        totals = next(k for k, line in enumerate(lines) if line.split()[:3] == ["FN", "FX", "FY"])
        fn, fx, fy = (float(v) for v in lines[totals + 1].split()[:3])
        cpu = (after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime)
        return {
            "force": -(fx if xi[0] else fy), "normal": fn, "cpu": cpu, "wall": wall,
            "memory": after.ru_maxrss / 1024.0, "iterations": None, "status": "converged",
        }  # fmt: skip
    finally:
        shutil.rmtree(folder, ignore_errors=True)


def contact_executable() -> str | None:
    """CONTACT's executable from ``CONTACT_EXE``, if it is there."""
    path = os.environ.get("CONTACT_EXE")
    return path if path and os.access(path, os.X_OK) else None


def run_rolling(sizes: list[int], peers: bool = False, steady: bool = False) -> int:
    """Print the creep-curve and linear-coefficient table; 0 when every row ran."""
    executable = contact_executable() if peers else None
    if peers:
        print("peers:", f"CONTACT {executable}" if executable else "CONTACT_EXE not set")
    points = [(f"{x:g}", (creepage(x), 0.0), MU * FORCE, None, 0.0) for x in XI_N]
    for name, axis, kalker in (("C11", 0, C11), ("C22", 1, C22)):
        xi = [0.0, 0.0]
        xi[axis] = creepage(LINEAR, kalker)
        points.append((name, tuple(xi), SHEAR * RADIUS**2 * xi[axis], kalker, 0.0))
    if steady:  # spin alone: F_y over mu W, and C23 at a spin of LINEAR of saturation's
        saturation = MU * FORCE / (SHEAR * RADIUS**3 * C23)
        points += [(f"phi_n {p:g}", (0.0, 0.0), MU * FORCE, None, p * saturation) for p in PHI_N]
        spin = LINEAR * saturation
        points.append(("C23", (0.0, 0.0), SHEAR * RADIUS**3 * spin, C23, spin))
    rows, failures = [], 0

    def add(code, across, label, status, out, unit, kalker, reference):
        nonlocal failures
        if status != "ok":
            failures += 1
            rows.append({"code": code, "across": across, "xi_n": label, "status": out})
            return None
        value = out["force"] / unit
        rows.append({
            "code": code, "across": across,
            "steps_per_a": {"slipstick": 2 * across, "CONTACT": across // 2}.get(code, "-"),
            "xi_n": label, "F_over_muW_or_C": value,
            "vs_CONTACT_ref_%": None if reference is None else 100 * (value / reference - 1),
            "vs_Kalker_%": None if kalker is None else 100 * (value / kalker - 1),
            "cpu_s": round(out["cpu"], 2), "wall_s": round(out["wall"], 2),
            "peak_MB": round(out["memory"]), "iterations": out["iterations"],
            "status": out["status"],
        })  # fmt: skip
        return value

    for label, xi, unit, kalker, spin in points:
        reference = None
        if executable:  # CONTACT on its finest grid: the reference of the row's sizes
            status, out = isolated(_contact, executable, REFERENCE_ACROSS, xi, spin, timeout=7200.0)
            reference = add("CONTACT", REFERENCE_ACROSS, label, status, out, unit, kalker, None)
        for across in sizes:
            if steady:
                for code, order in (("steady", 2), ("steady o1", 1)):
                    status, out = isolated(_ours_steady, across, xi, order, spin, timeout=7200.0)
                    add(code, across, label, status, out, unit, kalker, reference)
            else:
                status, out = isolated(_ours, across, xi, timeout=7200.0)
                add("slipstick", across, label, status, out, unit, kalker, reference)
            if executable:
                status, out = isolated(_contact, executable, across, xi, spin, timeout=7200.0)
                add("CONTACT", across, label, status, out, unit, kalker, reference)
    print(
        f"# steady rolling, identical steel bodies (nu = {NU:g}), a = 1 mm, mu = {MU:g}, "
        f"W = {FORCE:.1f} N; xi_n = G a^2 C11 xi / (3 mu W); C11/C22 rows: the coefficient at "
        f"xi_n = {LINEAR:g}; reference: CONTACT at {REFERENCE_ACROSS} across; {machine()}"
    )
    print(format_table(rows))
    if steady:
        for line in _curve_comparison(min(sizes)):
            print(line)
    return 1 if failures else 0
