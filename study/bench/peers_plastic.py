"""Tamaas on its own elastic-plastic scene, for side-by-side benchmarks with slipstick.

Tamaas (EPFL, AGPL, ``pip install tamaas``) is imported lazily inside :func:`tamaas_plastic`,
so this module imports without it.  The scene: a rigid sphere of radius ``R`` pressed on an
elastic-plastic half-space (von Mises, linear isotropic hardening
``sigma_Y = sigma_Y0 + H p``), frictionless, loaded to ``W`` in equal steps, then unloaded.

How the scene is put to Tamaas
------------------------------
- Model ``model_type.volume_2d`` with system size ``[depth, side, side]`` and discretisation
  ``[nz, n, n]`` (z first).  Tamaas is *periodic* in x and y and *nodal*: the surface grid and
  every depth layer of the plastic volume are the same ``n x n`` points ``x_i = i side / n``
  (i = 0 .. n-1, the period excludes ``side``), and the ``nz`` layers are at
  ``z_k = k depth / (nz - 1)`` (k = 0 .. nz-1), the surface and the bottom of the volume
  included.  The elastic half-space extends below the volume; plastic strain lives only in it.
  The sphere apex sits on node ``(n/2, n/2)``, so the axis is the column ``[:, n/2, n/2]``.
- Material ``materials.IsotropicHardening(model, sigma_Y0, H)`` with ``tamaas.Residual``;
  plasticity sub-solver ``nonlinear_solvers.DFSANECXXSolver`` (Tamaas' default tolerance);
  contact sub-solver ``PolonskyKeerRey`` (tolerance 1e-12); outer loop ``AndersonMixing``
  (memory 5), which reaches the same state as Tamaas' relaxed fixed point ``EPICSolver`` in
  about a third of the time.  Each load step calls ``solve(W_k / side^2)`` (mean pressure over
  the periodic cell); the plastic state carries over from step to step.
- Plastic strain: Tamaas stores ``plastic_strain`` (``[nz, n, n, 6]``, Mandel notation: shear
  components times sqrt(2), so the Euclidean norm of the 6 components is the tensor norm) and
  ``cumulated_plastic_strain`` (``[nz, n, n]``), the accumulated equivalent plastic strain
  ``p = int sqrt(2/3 d eps_p : d eps_p)`` that drives the hardening.  We report ``p``; it equals
  ``sqrt(2/3) |eps_p|`` wherever the loading was radial (checked on a material point; over this
  scene at n = 24 the two differ by at most 2 % of the maximum, ``p`` being the larger).
- Default cell (scaled with the Hertz radius ``a_H`` at ``W``): side 6 ``a_H``, depth 2.5
  ``a_H``.  Elastic periodic Hertz at side 6 ``a_H``: ``p_max`` 0.6 % above Hertz (2 % at
  4 ``a_H``); on the scene, going from side 6 to 8 ``a_H`` at the same spacing changes
  ``p_max`` by 0.5 %, the maximum plastic strain by 1.4 % and the dent by 1.3 %.  The plastic
  zone ends near 1.8 ``a_H``; a 3.5 ``a_H`` volume gives the same results.
"""

from __future__ import annotations

import math
import re
import time
from typing import Any

import numpy as np

from .peers import _captured_output, _thread_limit

__all__ = ["DEFAULT_DEPTH", "DEFAULT_SIDE", "DEFAULT_TOLERANCE", "tamaas_plastic"]

#: Periodic cell side, in Hertz radii at the maximum load, when ``side`` is not given.  The
#: periodic images matter: at the same node spacing (0.19 a_H) a 6 a_H cell gave a maximum
#: plastic strain 2.4 % higher and a dent 2.2 % deeper than a 12 a_H cell (2026-11-23).
DEFAULT_SIDE = 12.0
#: Depth of the plastic volume, in Hertz radii at the maximum load, when ``depth`` is not given.
DEFAULT_DEPTH = 2.5
#: Tolerance of Tamaas' outer (Anderson) error when ``tolerance`` is not given.
DEFAULT_TOLERANCE = 1e-7
#: Fraction of the maximum load kept at the "unloaded" state (Tamaas' contact solver fails on an
#: exactly zero load: its error is NaN without contact).
UNLOAD_FRACTION = 1e-6
#: Equivalent plastic strain above which a node counts as plastic.
PLASTIC_THRESHOLD = 1e-6

_CONTACT_TOLERANCE = 1e-12
_ANDERSON_MEMORY = 5


def _hertz(radius: float, contact_modulus: float, normal_force: float) -> tuple[float, float]:
    """Hertz contact radius (m) and peak pressure (Pa) of a sphere on a half-space."""
    a = (3.0 * normal_force * radius / (4.0 * contact_modulus)) ** (1.0 / 3.0)
    return a, 3.0 * normal_force / (2.0 * math.pi * a * a)


def _count(pattern: str, log: str) -> list[int]:
    return [int(value) for value in re.findall(pattern, log)]


def tamaas_plastic(
    n: int,
    nz: int,
    *,
    radius: float = 0.015,
    E: float = 210e9,
    nu: float = 0.3,
    yield_stress: float = 1.3579e9,
    hardening_modulus: float = 152.3e9,
    normal_force: float = 4716.0,
    steps: int = 6,
    unload: bool = True,
    side: float | None = None,
    depth: float | None = None,
    tolerance: float | None = None,
    threads: int = 1,
) -> dict[str, Any]:
    """Solve the elastic-plastic indentation of a half-space by a rigid sphere with Tamaas.

    Parameters
    ----------
    n : int
        Points per side of Tamaas' periodic surface grid, which is also the horizontal grid of
        every layer of the plastic volume (even, >= 4); spacing ``side / n`` (m).
    nz : int
        Layers of the plastic volume (>= 2), from the surface to ``depth`` inclusive; spacing
        ``depth / (nz - 1)`` (m).
    radius : float, optional
        Sphere radius ``R`` (m); the sphere is rigid.
    E : float, optional
        Young's modulus of the half-space (Pa).
    nu : float, optional
        Poisson's ratio of the half-space.
    yield_stress : float, optional
        Initial von Mises yield stress ``sigma_Y0`` (Pa).
    hardening_modulus : float, optional
        Linear isotropic hardening modulus ``H`` (Pa): ``sigma_Y = sigma_Y0 + H p`` with ``p``
        the accumulated equivalent plastic strain.
    normal_force : float, optional
        Maximum normal force ``W`` (N).
    steps : int, optional
        Equal loading steps up to ``W``.
    unload : bool, optional
        Add one unloading step to ``UNLOAD_FRACTION * W`` (Tamaas cannot solve zero load).
    side : float, optional
        Side of the periodic cell (m); default ``DEFAULT_SIDE`` Hertz radii at ``W``.
    depth : float, optional
        Depth of the plastic volume (m); default ``DEFAULT_DEPTH`` Hertz radii at ``W``.
    tolerance : float, optional
        Tolerance on Tamaas' outer (Anderson) error; default ``DEFAULT_TOLERANCE``.
    threads : int, optional
        OpenMP threads (the PyPI wheel is Tamaas' serial ``cpp`` backend anyway).

    Returns
    -------
    dict
        ``time``, ``cpu``: wall and process-CPU seconds of the ``solve`` calls only (s);
        ``setup``: wall seconds of the model, material and solver construction (s);
        ``max_pressure``: peak contact pressure at ``W`` (Pa);
        ``contact_radius``: ``sqrt(A / pi)`` at ``W``, ``A`` = nodes with ``p > 0`` times
        ``(side / n)^2`` (m);
        ``max_plastic_strain``, ``max_plastic_strain_unloaded``: largest accumulated equivalent
        plastic strain at ``W`` and after unloading (None without ``unload``);
        ``max_plastic_strain_depth``: depth of the node holding the maximum at ``W`` (m);
        ``plastic_zone_depth``: deepest on-axis node with ``p > PLASTIC_THRESHOLD`` at ``W`` (m;
        0 if none; equal to ``depth`` means the volume truncates the zone);
        ``residual_depth``: permanent central dent after unloading, positive into the body (m),
        relative to the corner of the periodic cell (the point farthest from the contact), or
        None without ``unload``;
        ``iterations``: outer (Anderson) iterations over all steps;
        ``inner_iterations``: DF-SANE iterations over all steps (None if not logged);
        ``depth_profile``: ``(z, p)`` arrays: node depths (m) and on-axis ``p`` at ``W``;
        ``converged``: every step reached ``tolerance``; ``step_errors``: Tamaas' final error
        of each step; ``side``, ``depth``, ``unload_force`` (m, m, N); ``hertz_radius``,
        ``hertz_pressure`` at ``W`` (m, Pa); ``method`` and ``notes``: descriptions.

    Raises
    ------
    ValueError
        For a grid or input Tamaas cannot take.
    ImportError
        If Tamaas is not installed.

    Notes
    -----
    The residual dent is read from Tamaas' ``gap`` field at the unloaded state, where the
    sphere touches the dented surface at its apex: the surface profile is the sphere profile
    minus the gap, so the dent below the cell corner is
    ``(r_c^2 / (2 R) - gap_c) - (0 - gap_0)`` with ``r_c = side / sqrt(2)``.  (Tamaas'
    ``displacement`` field holds only the elastic part of the last contact solve.)  The
    periodic images are dented too, so the corner is not quite the far field.
    """
    if n < 4 or n % 2:
        raise ValueError(f"n must be even and at least 4 (apex on a node), got {n}")
    if nz < 2:
        raise ValueError(f"nz must be at least 2 (surface and bottom layers), got {nz}")
    if steps < 1 or threads < 1:
        raise ValueError("steps and threads must be at least 1")
    if min(radius, E, yield_stress, normal_force) <= 0 or hardening_modulus < 0:
        raise ValueError("radius, E, yield_stress, normal_force must be positive, H >= 0")
    if not 0.0 <= nu < 0.5:
        raise ValueError(f"need 0 <= nu < 0.5, got {nu}")

    a_hertz, p_hertz = _hertz(radius, E / (1.0 - nu * nu), normal_force)
    side = DEFAULT_SIDE * a_hertz if side is None else float(side)
    depth = DEFAULT_DEPTH * a_hertz if depth is None else float(depth)
    tolerance = DEFAULT_TOLERANCE if tolerance is None else float(tolerance)
    if side <= 0 or depth <= 0 or tolerance <= 0:
        raise ValueError("side, depth and tolerance must be positive")
    unload_force = UNLOAD_FRACTION * normal_force
    loads = [normal_force * (k + 1) / steps for k in range(steps)]
    if unload:
        loads.append(unload_force)

    import tamaas as tm
    from tamaas.nonlinear_solvers import DFSANECXXSolver
    from tamaas.utils import log_context

    x = np.arange(n) * (side / n) - 0.5 * side  # node n/2 at the apex
    heights = -(x[:, None] ** 2 + x[None, :] ** 2) / (2.0 * radius)
    centre = n // 2
    z = np.linspace(0.0, depth, nz)
    logs: list[str] = []
    errors: list[float] = []
    wall = cpu = 0.0
    with _thread_limit(threads), log_context(tm.LogLevel.info):
        wall0 = time.perf_counter()
        model = tm.ModelFactory.createModel(
            tm.model_type.volume_2d, [depth, side, side], [nz, n, n]
        )
        model.E = E
        model.nu = nu
        material = tm.materials.IsotropicHardening(model, yield_stress, hardening_modulus)
        residual = tm.Residual(model, material)
        plastic_solver = DFSANECXXSolver(residual)
        contact_solver = tm.PolonskyKeerRey(model, heights, _CONTACT_TOLERANCE)
        solver = tm.AndersonMixing(
            contact_solver, plastic_solver, tolerance, memory=_ANDERSON_MEMORY
        )
        setup = time.perf_counter() - wall0
        loaded: dict[str, np.ndarray] = {}
        for step, load in enumerate(loads):
            with _captured_output(logs):
                cpu0, wall0 = time.process_time(), time.perf_counter()
                errors.append(float(solver.solve(load / side**2)))
                wall += time.perf_counter() - wall0
                cpu += time.process_time() - cpu0
            if step == steps - 1:
                loaded = {
                    "pressure": np.array(model.traction, dtype=float)[..., 2],
                    "plastic": np.array(model["cumulated_plastic_strain"], dtype=float),
                }
        unloaded_plastic = np.array(model["cumulated_plastic_strain"], dtype=float)
        gap = np.array(model["gap"], dtype=float)[..., 2]

    log = "".join(logs)
    outer = len(re.findall(r"\[(?:Anderson|EPIC)\] error", log))
    inner = _count(r"DF-SANE: \w+ convergence \((\d+) iterations", log)
    pressure, plastic = loaded["pressure"], loaded["plastic"]
    axis = plastic[:, centre, centre]
    k_max = np.unravel_index(int(np.argmax(plastic)), plastic.shape)[0]
    plastic_axis = np.flatnonzero(axis > PLASTIC_THRESHOLD)
    residual_depth = None
    if unload:
        corner_sphere = (x[0] ** 2 + x[0] ** 2) / (2.0 * radius)
        residual_depth = float((corner_sphere - gap[0, 0]) + gap[centre, centre])
    cell = side / n
    notes = (
        f"Tamaas {tm.__version__} volume_2d [nz, n, n] = [{nz}, {n}, {n}]: periodic cell "
        f"{side * 1e3:.4g} mm = {side / a_hertz:.3g} a_H square (period, images at that "
        f"spacing), {n}x{n} surface nodes every {cell * 1e6:.4g} um "
        f"({a_hertz / cell:.3g} per a_H); plastic volume {depth * 1e3:.4g} mm = "
        f"{depth / a_hertz:.3g} a_H deep, {nz} node layers every "
        f"{depth / (nz - 1) * 1e6:.4g} um (surface and bottom included), same horizontal grid; "
        f"AndersonMixing(memory {_ANDERSON_MEMORY}) tol {tolerance:g} + DFSANECXXSolver + "
        f"PolonskyKeerRey tol {_CONTACT_TOLERANCE:g}; "
        + (
            f"unloaded to {unload_force:g} N (Tamaas fails at 0 N); dent relative to the cell "
            "corner (periodic images dented too)"
            if unload
            else "no unloading"
        )
    )
    return {
        "time": wall,
        "cpu": cpu,
        "setup": setup,
        "max_pressure": float(pressure.max()),
        "contact_radius": math.sqrt(np.count_nonzero(pressure > 0) * cell * cell / math.pi),
        "max_plastic_strain": float(plastic.max()),
        "max_plastic_strain_unloaded": float(unloaded_plastic.max()) if unload else None,
        "max_plastic_strain_depth": float(z[k_max]),
        "plastic_zone_depth": float(z[plastic_axis[-1]]) if plastic_axis.size else 0.0,
        "residual_depth": residual_depth,
        "iterations": outer if outer else None,
        "inner_iterations": sum(inner) if inner else None,
        "depth_profile": (z, axis.copy()),
        "converged": all(error <= tolerance for error in errors),
        "step_errors": errors,
        "side": side,
        "depth": depth,
        "unload_force": unload_force if unload else None,
        "hertz_radius": a_hertz,
        "hertz_pressure": p_hertz,
        "method": "tamaas AndersonMixing (volume_2d, periodic), DF-SANE plasticity",
        "notes": notes,
    }


def _run_child(n: int, nz: int, kwargs: dict[str, Any]) -> dict[str, Any]:
    import resource

    out = tamaas_plastic(n, nz, **kwargs)
    out["peak_rss_MB"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    return out


def _main(argv: list[str] | None = None) -> int:
    import argparse
    import multiprocessing
    import os

    parser = argparse.ArgumentParser(description="Tamaas on the elastic-plastic sphere scene")
    parser.add_argument("--n", type=int, nargs="+", default=[32], help="grid sizes n (n^3)")
    parser.add_argument("--nz", type=int, help="volume layers (default: n)")
    parser.add_argument("--side", type=float, help="periodic cell side in Hertz radii")
    parser.add_argument("--depth", type=float, help="volume depth in Hertz radii")
    parser.add_argument("--tolerance", type=float)
    parser.add_argument("--yield-stress", type=float, default=1.3579e9, help="(Pa)")
    parser.add_argument("--force", type=float, default=4716.0, help="maximum load W (N)")
    args = parser.parse_args(argv)
    os.environ["OMP_NUM_THREADS"] = "1"
    E, nu, radius = 210e9, 0.3, 0.015
    a_h, p_h = _hertz(radius, E / (1 - nu * nu), args.force)
    kwargs: dict[str, Any] = {
        "radius": radius,
        "E": E,
        "nu": nu,
        "yield_stress": args.yield_stress,
        "normal_force": args.force,
        "tolerance": args.tolerance,
    }
    if args.side:
        kwargs["side"] = args.side * a_h
    if args.depth:
        kwargs["depth"] = args.depth * a_h
    header = (
        f"{'n':>4} {'wall_s':>8} {'cpu_s':>8} {'rss_MB':>7} {'pmax/pH':>8} {'a/aH':>6} "
        f"{'ep_max':>9} {'z_ep/aH':>7} {'zone/aH':>7} {'dent_um':>8} {'iters':>5}"
    )
    rows = []
    context = multiprocessing.get_context("fork")
    for n in args.n:  # one child per size, so that each peak RSS is its own
        with context.Pool(1) as pool:
            out = pool.apply(_run_child, (n, args.nz or n, kwargs))
        dent = out["residual_depth"]
        rows.append(
            f"{n:>4} {out['time']:8.1f} {out['cpu']:8.1f} {out['peak_rss_MB']:7.0f} "
            f"{out['max_pressure'] / p_h:8.4f} {out['contact_radius'] / a_h:6.3f} "
            f"{out['max_plastic_strain']:9.5f} {out['max_plastic_strain_depth'] / a_h:7.3f} "
            f"{out['plastic_zone_depth'] / a_h:7.3f} "
            f"{'-' if dent is None else f'{dent * 1e6:8.3f}':>8} {out['iterations']!s:>5}"
        )
        print(f"n={n}: {out['notes']}; converged={out['converged']}", flush=True)
    print(f"Hertz at W = {args.force:g} N: a_H = {a_h * 1e3:.4f} mm, p_H = {p_h / 1e9:.3f} GPa")
    print(header)
    print("\n".join(rows))
    return 0


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(_main())
