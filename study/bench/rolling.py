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

``--steady`` adds elliptic contacts (:data:`SHAPES`: semi-axes a along the rolling direction x,
b along y, a/b = 0.5 and 2) under the same W: body 1 of radii ``R_x``, ``R_y`` (geometric mean
50 mm, body 2 flat) whose Hertz ellipse has that ratio (:func:`shape`: a root find on Hertz's
semi-axes; a/b = 0.5: a = 0.697 mm, b = 1.394 mm), ``xi = xi_n 3 mu W / (G a b C11)`` with
Kalker's C11 of the ellipse (:data:`solver.theory.friction.KALKER_ELLIPSE_COEFFICIENTS`);
CONTACT given the same semi-axes (``AA``, ``BB``).  For every shape ``n`` (cells, CONTACT's
elements) counts across the smaller axis, 2 min(a, b), in square cells.

The linear rows (``xi_n = 1e-3``, along x and along y) give C11 and C22 (on ``c^2 = a b``)
beside Kalker's tables (:data:`solver.theory.friction.KALKER_CIRCLE_COEFFICIENTS`, the
ellipses'). Columns: code, a/b (1: the circle), cells across, steps a radius, creepage, creep
force over mu W (the linear rows: the coefficient), its difference from CONTACT on
:data:`REFERENCE_ACROSS` elements across (the reference), from CONTACT's mesh limit
(:func:`extrapolate`, with the peers) and from Kalker's table, CPU and wall time, peak
memory (ours: growth of the resident set; CONTACT's: its peak resident set),
tangential-operator applications (ours).

``--steady``: ours solved directly (``steady = true`` stages, :mod:`solver.surface.steady`,
second-order upwind: ``steady``; first order, CONTACT's scheme: ``steady o1``) instead of the
march, on a grid of 1.25 semi-axes either side (:func:`steady_grid`), CONTACT's potential
contact 1.1 semi-axes either side; the circle's spin rows (``phi_n``, C23); then a creep curve
of :data:`CURVE_POINTS` creepages (xi_n up to 1, the circle) both ways: one steady stage of
that many increments, and one transient march a point, with their CPU and the largest
difference between the two curves (of mu W).

``python -m study bench rolling [--sizes N ...] [--peers] [--steady]`` (N: cells across,
default 32 64); :func:`run_rolling`'s ``shapes`` (a/b of :data:`SHAPES`) limits the rows to
those contacts.
"""

from __future__ import annotations

import functools
import math
import os
import resource
import shutil
import subprocess
import tempfile
import time
from dataclasses import dataclass

from solver.theory.friction import KALKER_CIRCLE_COEFFICIENTS, KALKER_ELLIPSE_COEFFICIENTS
from solver.theory.hertz import hertz

from .registry import BenchOptionError
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
#: ``--steady``'s point at a prescribed force with spin (the circle): the force on body 2 over
#: mu W and the spin over Kalker's linear saturation spin (:data:`PHI_N`'s unit).
FORCE_SPIN = ((0.1, 0.05), 0.3)
LINEAR = 1e-3
TRAVEL, AVERAGE = 6.0, 2.0  # contact radii rolled; the last ones averaged
#: CONTACT's elements across the contact (its smaller axis) of the reference rows, by a/b: an
#: ellipse's larger axis takes twice as many (its 120 cost 3-4 min CPU a row)
REFERENCE_ACROSS = {1.0: 120, 0.5: 80, 2.0: 80}
SHEAR = E / (2 * (1 + NU))
FORCE = 4.0 * E / (2 * (1 - NU * NU)) * RADIUS**3 / (3.0 * PAIR_RADIUS)


#: The composite modulus E* of the pair (1/E* = 2 (1 - nu^2) / E).
E_STAR = E / (2 * (1 - NU * NU))
#: Contact shapes of ``--steady``: the Hertz semi-axis ratio a/b (a along the rolling direction
#: x, b along y); 1 the circle, the others rows of
#: :data:`solver.theory.friction.KALKER_ELLIPSE_COEFFICIENTS`.
SHAPES = (1.0, 0.5, 2.0)


def creepage(xi_n: float, coefficient: float = C11, area: float = RADIUS**2) -> float:
    """The creepage of a normalised creepage ``xi_n`` (1: about full slip).

    Parameters
    ----------
    xi_n : float
        ``G c^2 C xi / (3 mu W)``.
    coefficient : float
        Kalker's linear coefficient C of the shape along the creepage.
    area : float
        ``c^2 = a b`` (m^2): the contact's semi-axes multiplied (a^2 for the circle).
    """
    return xi_n * 3.0 * MU * FORCE / (SHEAR * area * coefficient)


@dataclass(frozen=True)
class Shape:
    """One contact of the scene: body 1's radii and the Hertz ellipse under :data:`FORCE`.

    Attributes
    ----------
    a_over_b : float
        The semi-axis ratio asked for (a along x, the rolling direction).
    radius_x, radius_y : float
        Body 1's radii (m); body 2 is flat.
    semi_x, semi_y : float
        Hertz's semi-axes a, b (m) of the contact of those radii.
    c11, c22, c23 : float
        Kalker's linear coefficients of the shape (on ``c = sqrt(a b)``).
    """

    a_over_b: float
    radius_x: float
    radius_y: float
    semi_x: float
    semi_y: float
    c11: float
    c22: float
    c23: float

    @property
    def area(self) -> float:
        """``c^2 = a b`` (m^2), the area of Kalker's normalisation."""
        return self.semi_x * self.semi_y

    @property
    def semi_min(self) -> float:
        """The smaller semi-axis (m): the cells across it are the row's size."""
        return min(self.semi_x, self.semi_y)

    @property
    def body1(self) -> dict:
        """Body 1's table (its radii)."""
        radii = (
            {"radius": self.radius_x}
            if self.radius_x == self.radius_y
            else {"radius_x": self.radius_x, "radius_y": self.radius_y}
        )
        return {"behaviour": "elastic", "E": E, "nu": NU, **radii}


@functools.lru_cache(maxsize=8)
def shape(a_over_b: float = 1.0) -> Shape:
    """The scene's contact of semi-axis ratio ``a_over_b`` under :data:`FORCE`.

    The circle: two spheres of :data:`PAIR_RADIUS` (a = :data:`RADIUS`).  An ellipse: body 1's
    radii ``R_x = PAIR_RADIUS sqrt(t)``, ``R_y = PAIR_RADIUS / sqrt(t)`` (body 2 flat), ``t``
    found by bisection (in log t) on the Hertz semi-axis ratio
    (:func:`solver.theory.hertz.hertz`) at the same normal force.
    """
    if a_over_b == 1.0:
        contact = hertz(FORCE, E_STAR, (1.0 / PAIR_RADIUS, 1.0 / PAIR_RADIUS))
        return Shape(1.0, PAIR_RADIUS, PAIR_RADIUS, contact.semi_axis_x, contact.semi_axis_y, *(
            KALKER_CIRCLE_COEFFICIENTS[NU]))  # fmt: skip
    if a_over_b not in KALKER_ELLIPSE_COEFFICIENTS:  # (and within the bracket below)
        raise ValueError(
            f"a/b = {a_over_b:g}: Kalker's table here has a/b in "
            f"{sorted([1.0, *KALKER_ELLIPSE_COEFFICIENTS])}"
        )

    def ratio(log_t: float):
        radius_x, radius_y = (
            PAIR_RADIUS * math.exp(0.5 * log_t),
            PAIR_RADIUS * math.exp(-0.5 * log_t),
        )
        contact = hertz(FORCE, E_STAR, (1.0 / radius_x, 1.0 / radius_y))
        return contact.semi_axis_x / contact.semi_axis_y, radius_x, radius_y, contact

    low, high = -math.log(4.0), math.log(4.0)  # R_x / R_y: a / b from 0.4 to 2.5
    while high - low > 1e-13:
        middle = 0.5 * (low + high)
        if ratio(middle)[0] < a_over_b:
            low = middle
        else:
            high = middle
    _, radius_x, radius_y, contact = ratio(0.5 * (low + high))
    return Shape(
        a_over_b, radius_x, radius_y, contact.semi_axis_x, contact.semi_axis_y,
        *KALKER_ELLIPSE_COEFFICIENTS[a_over_b][NU],
    )  # fmt: skip


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


def steady_grid(across: int, a_over_b: float = 1.0) -> dict:
    """The ``[grid]`` of ``--steady``: square cells, ``across`` of them on the smaller axis.

    Cells of ``h = 2 min(a, b) / across``; ``round(1.25 across a / min(a, b))`` of them along
    x and likewise along y (1.25 semi-axes either side of the centre), given as
    ``grid.size`` (m): for the circle the grid of ``half_width = 1.25``.
    """
    contact = shape(a_over_b)
    cell = 2.0 * contact.semi_min / across
    n = [
        round(1.25 * across * semi / contact.semi_min) for semi in (contact.semi_x, contact.semi_y)
    ]
    return {"n": n, "size": [count * cell for count in n]}


def steady_table(
    across: int,
    xi: tuple[float, float],
    order: int = 2,
    steps: int = 1,
    spin: float = 0.0,
    a_over_b: float = 1.0,
    force: tuple[float, float] | None = None,
) -> dict:
    """The case table: load, then the steady state at ``xi`` and ``spin`` (1/m).

    The stage ramps from zero in ``steps`` increments (a creep curve); the contact is
    :func:`shape` ``(a_over_b)`` on :func:`steady_grid`.  ``force``: the tangential force on
    body 2 over mu W prescribed instead of ``xi``.
    """
    rigid = {"creepage": list(xi)} if any(xi) and force is None else {}
    if force is not None:
        rigid["tangential_force"] = [f * MU * FORCE for f in force]
    rigid.update({"spin": spin} if spin else {})
    return {
        **BODIES,
        "body1": shape(a_over_b).body1,
        "load": {"path": [
            {"normal_force": FORCE},
            {"steady": True, **rigid, "steps": steps},
        ]},
        "grid": steady_grid(across, a_over_b),
        "solver": {"steady_order": order},
    }  # fmt: skip


def _ours_steady(
    across: int,
    xi: tuple[float, float],
    order: int = 2,
    spin: float = 0.0,
    a_over_b: float = 1.0,
    repeat: int = 1,
    force: tuple[float, float] | None = None,
) -> dict:
    from solver.surface.convolution import surface_operator

    table = steady_table(across, xi, order, spin=spin, a_over_b=a_over_b, force=force)
    runs = []
    for _ in range(repeat):  # best of: a point takes milliseconds
        surface_operator.cache_clear()  # each run builds its operator, as each CONTACT run does
        runs.append(timed_solve(table))
    _, result, _, _, memory = runs[0]
    wall, cpu = min(run[2] for run in runs), min(run[3] for run in runs)
    axis = "x" if xi[0] else "y"
    return {
        "force": float(result.history[f"tangential_force_{axis}"][-1]), "cpu": cpu,
        "creepage": tuple(float(result.history[f"creepage_{c}"][-1]) for c in "xy"),
        "wall": wall, "memory": memory,
        "iterations": int(result.history["slip_iterations"].sum()), "status": result.status,
    }  # fmt: skip


def _steady_curve(across: int) -> dict:
    """One steady stage of CURVE_POINTS increments up to xi_n = 1: forces, CPU."""
    table = steady_table(across, (creepage(1.0), 0.0), 2, CURVE_POINTS)
    _, result, wall, cpu, _ = timed_solve(table)
    forces = [float(f) for f in result.history["tangential_force_x"][1:]]
    return {"forces": forces, "cpu": cpu, "wall": wall, "status": result.status}


def _force_spin_comparison(sizes: list[int], executable: str | None, repeat: int) -> list[str]:
    """The circle at a prescribed force with spin (:data:`FORCE_SPIN`): the creepage found.

    Ours (both orders) and CONTACT (``F = 2``) on each size, best of ``repeat`` runs each;
    the difference from CONTACT on the largest size (CONTACT prints four digits).
    """
    (fx, fy), phi_n = FORCE_SPIN
    spin = phi_n * MU * FORCE / (SHEAR * RADIUS**3 * C23)
    runs = []
    for across in sizes:
        for code, order in (("steady", 2), ("steady o1", 1)):
            status, out = isolated(
                _ours_steady, across, (0.0, 0.0), order, spin, 1.0, repeat, (fx, fy),
                timeout=7200.0,
            )  # fmt: skip
            runs.append((code, across, status, out))
        if executable:
            status, out = isolated(
                _contact, executable, across, (0.0, 0.0), spin, 1.0, repeat, (fx, fy),
                timeout=7200.0,
            )  # fmt: skip
            runs.append(("CONTACT", across, status, out))
    reference = next(
        (out["creepage"] for code, n, status, out in runs
         if code == "CONTACT" and n == max(sizes) and status == "ok"),
        None,
    )  # fmt: skip
    rows = []
    for code, across, status, out in runs:
        if status != "ok":
            rows.append({"code": code, "across": across, "status": out})
            continue
        row = {"code": code, "across": across}
        for c, value in zip("xy", out["creepage"], strict=True):
            row[f"creepage_{c}"] = f"{value:.5g}"
            off = None if reference is None else 100 * (value / reference["xy".index(c)] - 1)
            row[f"{c}_vs_CONTACT_%"] = None if off is None else round(off, 2)
        row.update(
            cpu_s=round(out["cpu"], 3), wall_s=round(out["wall"], 3),
            peak_MB=round(out["memory"]), status=out["status"],
        )  # fmt: skip
        rows.append(row)
    return [
        f"# prescribed force with spin (the circle): F / (mu W) = ({fx:g}, {fy:g}) on body 2, "
        f"spin phi_n = {phi_n:g} ({spin:.4g} 1/m); the creepage found; against CONTACT "
        f"(F = 2) at {max(sizes)} across",
        format_table(rows),
    ]


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


def contact_elements(across: int, a_over_b: float = 1.0) -> tuple[int, int, float]:
    """CONTACT's elements ``MX, MY`` and ``SCALE`` for ``across`` on the smaller axis.

    Its potential contact is ``[-AA s, AA s] x [-BB s, BB s]`` (``s = SCALE``) in ``MX`` by
    ``MY`` elements: ``round(1.1 across)`` across the smaller axis (1.1 of it), one more when
    that count's parity differs from :func:`steady_grid`'s (so that the elements' centres are
    our cells' centres: 35 elements against our 40 cells, at 32 across, put CONTACT's centres
    half a cell off ours, 1 % on C11), ``s`` from that, and the larger axis in as many as keep
    the elements square (the ratio 2: exactly twice), each of the size of :func:`steady_grid`'s
    cells.
    """
    contact = shape(a_over_b)
    elements = round(1.1 * across)  # the potential contact: 1.1 semi-axes on each side
    elements += (elements - round(1.25 * across)) % 2  # centred like our grid
    scale = elements / across
    mx, my = (
        round(scale * across * s / contact.semi_min) for s in (contact.semi_x, contact.semi_y)
    )
    return mx, my, scale


def _contact_input(
    across: int,
    xi: tuple[float, float],
    spin: float = 0.0,
    a_over_b: float = 1.0,
    force: tuple[float, float] | None = None,
) -> str:
    """CONTACT's input (module 3, units mm, N, N/mm^2) for steady rolling at ``xi``.

    Hertzian semi-axes ``AA`` (x, rolling) and ``BB`` (y) of :func:`shape` prescribed
    (``IPOTCN = -3``), :func:`contact_elements`; the rolling step ``DQ`` one element along x.
    ``force``: the tangential force on body 2 over mu W prescribed instead of ``xi``
    (``F = 2``: CONTACT's ``FXREL``, ``FYREL``, its force on body 1 over ``FSTAT FN``).
    """
    contact = shape(a_over_b)
    mx, my, scale = contact_elements(across, a_over_b)
    aa, bb = contact.semi_x * 1e3, contact.semi_y * 1e3  # mm
    step = 2.0 * aa * scale / mx
    given = xi if force is None else (-force[0], -force[1])
    shear = SHEAR * 1e-6
    lines = [
        f"% slipstick bench rolling: steady rolling, Hertzian ellipse a = {aa:.4f} mm, "
        f"b = {bb:.4f} mm",
        " 3  MODULE",
        f"  2031{0 if force is None else 2}0     P-B-T-N-F-S",  # steady (T = 3), Hertzian
        "  022020     L-D-C-M-Z-E",
        " 0000331   H-G-I-A-O-W-R",
        "   999   200    30     1   1e-6    MAXGS, MAXIN, MAXNR, MAXOUT, EPS",
        f"  {FORCE:.6f}  {given[0]:.10e}  {given[1]:.10e}  {SPIN_SIGN * spin * 1e-3:.10e}"
        f"    FN, {'CKSI, CETA' if force is None else 'FXREL, FYREL'}, CPHI",
        f"  {MU:.3f}  {MU:.3f}    FSTAT, FKIN",
        f"  0.000  {step:.8f}  1000.0    CHI, DQ, VELOC",
        f"  {NU:.4f}  {NU:.4f}  {shear:.4f}  {shear:.4f}    POISS 1,2, GG 1,2",
        "   -3    IPOTCN",
        f"  {mx}  {my}  {aa:.8f}  {bb:.8f}  {scale:.8f}    MX, MY, AA, BB, SCALE",
        "",
        " 0  MODULE",
        "",
    ]
    return "\n".join(lines)


def _contact(
    executable: str,
    across: int,
    xi: tuple[float, float],
    spin: float = 0.0,
    a_over_b: float = 1.0,
    repeat: int = 1,
    force: tuple[float, float] | None = None,
) -> dict:
    """Run CONTACT on the scene; its force on body 2 (the opposite of its force on body 1).

    Wall and CPU time of its whole process, best of ``repeat`` runs; ``force`` as in
    :func:`_contact_input` (the creepage it finds is in ``creepage``).
    """
    folder = tempfile.mkdtemp(prefix="contact_")
    try:
        with open(os.path.join(folder, "bench.inp"), "w") as handle:
            handle.write(_contact_input(across, xi, spin, a_over_b, force))
        wall = cpu = math.inf
        for _ in range(repeat):
            before = resource.getrusage(resource.RUSAGE_CHILDREN)
            start = time.perf_counter()
            done = subprocess.run(
                [executable, "2", "bench"], cwd=folder, capture_output=True, text=True,
                timeout=3600,
            )  # fmt: skip
            wall = min(wall, time.perf_counter() - start)
            after = resource.getrusage(resource.RUSAGE_CHILDREN)
            used = (after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime)
            cpu = min(cpu, used)
            if done.returncode != 0:
                raise RuntimeError(f"CONTACT exited with {done.returncode}: {done.stdout[-300:]}")
        with open(os.path.join(folder, "bench.out")) as handle:
            lines = handle.read().splitlines()
        totals = next(k for k, line in enumerate(lines) if line.split()[:3] == ["FN", "FX", "FY"])
        fn, fx, fy = (float(v) for v in lines[totals + 1].split()[:3])
        creep = next(k for k, line in enumerate(lines) if "CREEP X" in line)
        found = tuple(float(v) for v in lines[creep + 1].split()[1:3])
        return {
            "force": -(fx if xi[0] else fy), "creepage": found, "normal": fn, "cpu": cpu,
            "wall": wall,
            "memory": after.ru_maxrss / 1024.0, "iterations": None, "status": "converged",
        }  # fmt: skip
    finally:
        shutil.rmtree(folder, ignore_errors=True)


def contact_executable() -> str | None:
    """CONTACT's executable from ``CONTACT_EXE``, if it is there."""
    path = os.environ.get("CONTACT_EXE")
    return path if path and os.access(path, os.X_OK) else None


def _points(contact: Shape, steady: bool) -> list[tuple]:
    """The rows of one shape: ``(label, xi, unit, Kalker's value, spin)``.

    The creep curve's :data:`XI_N` (force over mu W), C11 and C22 at ``xi_n =``
    :data:`LINEAR` (force over ``G a b xi``); with ``steady`` and the circle, the spin rows
    (:data:`PHI_N`, F_y over mu W) and C23.
    """
    area = contact.area
    points = [
        (f"{x:g}", (creepage(x, contact.c11, area), 0.0), MU * FORCE, None, 0.0) for x in XI_N
    ]
    for name, axis, kalker in (("C11", 0, contact.c11), ("C22", 1, contact.c22)):
        xi = [0.0, 0.0]
        xi[axis] = creepage(LINEAR, kalker, area)
        points.append((name, tuple(xi), SHEAR * area * xi[axis], kalker, 0.0))
    if steady and contact.a_over_b == 1.0:  # spin alone: F_y over mu W, and C23 at a spin of
        saturation = MU * FORCE / (SHEAR * RADIUS**3 * C23)  # LINEAR of saturation's
        points += [(f"phi_n {p:g}", (0.0, 0.0), MU * FORCE, None, p * saturation) for p in PHI_N]
        spin = LINEAR * saturation
        points.append(("C23", (0.0, 0.0), SHEAR * RADIUS**3 * spin, C23, spin))
    return points


def extrapolate(rows: list[dict], largest: int) -> None:
    """Fill ``vs_CONTACT_extrapolated_%``: each row against CONTACT's mesh limit.

    CONTACT's scheme is first order in the element (its forces approach the limit as 1/n, the
    rows show): the limit from its reference ``N`` and its largest benchmarked size ``n`` is
    ``(N F_N - n F_n) / (N - n)`` (Richardson), per shape and creepage row.
    """
    found = {}
    for row in rows:
        if row["code"] == "CONTACT" and "F_over_muW_or_C" in row:
            found[(row["a_over_b"], row["xi_n"], row["across"])] = row["F_over_muW_or_C"]
    for row in rows:
        key = (row["a_over_b"], row["xi_n"])
        fine = REFERENCE_ACROSS[float(row["a_over_b"])]
        if "F_over_muW_or_C" not in row or fine == largest:
            continue
        pair = (found.get((*key, fine)), found.get((*key, largest)))
        if None in pair:
            continue
        limit = (fine * pair[0] - largest * pair[1]) / (fine - largest)
        row["vs_CONTACT_extrapolated_%"] = 100 * (row["F_over_muW_or_C"] / limit - 1)


def run_rolling(
    sizes: list[int],
    peers: bool = False,
    steady: bool = False,
    shapes: list[float] | None = None,
    repeat: int = 3,
) -> int:
    """Print the creep-curve and linear-coefficient table; 0 when every row ran.

    Parameters
    ----------
    sizes : list of int
        Cells across the contact (the smaller axis of an ellipse).
    peers : bool
        Also run CONTACT (``CONTACT_EXE``): on each size and on :data:`REFERENCE_ACROSS`
        of the shape.
    steady : bool
        Ours solved directly (both orders) instead of the transient march.
    shapes : list of float, optional
        The contacts' a/b of :data:`SHAPES` (default: all with ``steady``, the circle
        without: the march is the circle's only); the creep curve of ``--steady`` runs with
        the circle.
    repeat : int
        Steady points, ours and CONTACT's on the same sizes: times are the best of ``repeat``
        solves (a point at 16 cells across takes milliseconds), each from scratch: ours
        builds its operator again each time (the libraries loaded before,
        :func:`~study.bench.timing.load_solver`), CONTACT's is a process each time.
        CONTACT's reference and the transient march run once.
    """
    if shapes is None:
        shapes = list(SHAPES) if steady else [1.0]
    shapes = [float(q) for q in shapes]
    if any(q not in SHAPES for q in shapes):
        raise BenchOptionError(f"--shapes: a/b must be among {list(SHAPES)}, got {shapes}")
    if not steady and shapes != [1.0]:
        raise BenchOptionError("--shapes: the transient march rolls the circle only; add --steady")
    executable = contact_executable() if peers else None
    if peers:
        print("peers:", f"CONTACT {executable}" if executable else "CONTACT_EXE not set")
    rows, failures = [], 0

    def add(code, a_over_b, across, label, status, out, unit, kalker, reference):
        nonlocal failures
        if status != "ok":
            failures += 1
            rows.append({
                "code": code, "a_over_b": a_over_b, "across": across, "xi_n": label,
                "status": out,
            })  # fmt: skip
            return None
        value = out["force"] / unit
        rows.append({
            "code": code, "a_over_b": a_over_b, "across": across,
            "steps_per_a": {"slipstick": 2 * across, "CONTACT": across // 2}.get(code, "-"),
            "xi_n": label, "F_over_muW_or_C": value,
            "vs_CONTACT_ref_%": None if reference is None else 100 * (value / reference - 1),
            "vs_CONTACT_extrapolated_%": None,
            "vs_Kalker_%": None if kalker is None else 100 * (value / kalker - 1),
            "cpu_s": round(out["cpu"], 3), "wall_s": round(out["wall"], 3),
            "peak_MB": round(out["memory"]), "iterations": out["iterations"],
            "status": out["status"],
        })  # fmt: skip
        return value

    for a_over_b in shapes:
        contact, q = shape(a_over_b), f"{a_over_b:g}"
        for label, xi, unit, kalker, spin in _points(contact, steady):
            reference = None
            if executable:  # CONTACT on its finest grid: the reference of the row's sizes
                finest = REFERENCE_ACROSS[a_over_b]
                status, out = isolated(
                    _contact, executable, finest, xi, spin, a_over_b, timeout=7200.0
                )
                reference = add("CONTACT", q, finest, label, status, out, unit, kalker, None)
            for across in sizes:
                if steady:
                    for code, order in (("steady", 2), ("steady o1", 1)):
                        status, out = isolated(
                            _ours_steady, across, xi, order, spin, a_over_b, repeat,
                            timeout=7200.0,
                        )  # fmt: skip
                        add(code, q, across, label, status, out, unit, kalker, reference)
                else:
                    status, out = isolated(_ours, across, xi, timeout=7200.0)
                    add("slipstick", q, across, label, status, out, unit, kalker, reference)
                if executable:
                    status, out = isolated(
                        _contact, executable, across, xi, spin, a_over_b,
                        repeat if steady else 1, timeout=7200.0,
                    )  # fmt: skip
                    add("CONTACT", q, across, label, status, out, unit, kalker, reference)
    print(
        f"# steady rolling, identical steel bodies (nu = {NU:g}), mu = {MU:g}, "
        f"W = {FORCE:.1f} N; xi_n = G a b C11 xi / (3 mu W) (C11 Kalker's of the shape); C11/C22 "
        f"rows: the coefficient (on c^2 = a b) at xi_n = {LINEAR:g}; across: cells (CONTACT: "
        f"elements) across the smaller axis; reference: CONTACT at "
        f"{', '.join(f'{n} across (a/b = {q:g})' for q, n in REFERENCE_ACROSS.items())}; "
        f"{machine()}"
    )
    for a_over_b in shapes:
        c = shape(a_over_b)
        print(
            f"# a/b = {a_over_b:g}: body 1 R_x = {1e3 * c.radius_x:.4g} mm, R_y = "
            f"{1e3 * c.radius_y:.4g} mm (body 2 flat); Hertz a = {1e3 * c.semi_x:.4f} mm (x, "
            f"rolling), b = {1e3 * c.semi_y:.4f} mm; Kalker C11, C22 = {c.c11:g}, {c.c22:g}"
        )
    extrapolate(rows, max(sizes))
    print(format_table(rows))
    if steady and 1.0 in shapes:
        for line in _force_spin_comparison(sizes, executable, repeat):
            print(line)
        for line in _curve_comparison(min(sizes)):
            print(line)
    return 1 if failures else 0
