"""Tamaas on a periodic nominally flat rough surface, elastic or elastic-plastic.

Tamaas (EPFL, AGPL, ``pip install tamaas``) is imported lazily inside :func:`tamaas_rough`, so
this module imports without it.  The scene: one period of a rigid rough surface pressed
(frictionless) onto a half-space, elastic or elastic-plastic (von Mises, linear isotropic
hardening ``sigma_Y = sigma_Y0 + H p``), loaded through increasing mean pressures, then
(plastic only) unloaded.

How the scene is put to Tamaas
------------------------------
- Grid: Tamaas is *periodic* and *nodal*: sample ``[i, j]`` of the ``n x n`` heights is at
  ``(x_i, y_j) = (i, j) side / n`` (i, j = 0 .. n-1; the period excludes ``side``), ``x`` along
  axis 0.  Every field returned on the surface uses the same grid.
- Heights: Tamaas' contact solvers take the *rigid surface's heights*, larger = protruding
  towards the half-space (its ``utils.hertz_surface`` is ``-r^2 / (2 R)``, apex highest), and
  its ``gap`` field is ``u_z - heights`` + a constant, ``u_z`` the surface displacement into
  the half-space.  That is this module's convention too, so the heights go to Tamaas as they
  are (a float64 copy: Tamaas' elastic-plastic solvers overwrite the array they are given).
  Under a vanishing load the first node in contact is the highest one.
- Elastic: ``model_type.basic_2d`` (``E``, ``nu``; the contact modulus is
  ``E / (1 - nu^2)``), one ``PolonskyKeerRey`` solve (tolerance 1e-12) per mean pressure.
- Elastic-plastic: ``model_type.volume_2d`` with system size ``[depth, side, side]`` and
  discretisation ``[nz, n, n]`` (z first): ``nz`` node layers at ``z_k = k depth / (nz - 1)``
  (k = 0 .. nz-1, the surface and the bottom of the volume included), each on the surface
  grid; the elastic half-space extends below, plastic strain lives only in the volume.
  ``materials.IsotropicHardening`` with ``tamaas.Residual``, plasticity sub-solver
  ``DFSANECXXSolver``, contact sub-solver ``PolonskyKeerRey`` (tolerance 1e-12), outer loop
  ``AndersonMixing`` (memory 5), as in :mod:`.peers_plastic`.  Each entry of
  ``mean_pressures`` is one ``solve``; the plastic state carries over.  Unloading goes to
  ``UNLOAD_FRACTION`` of the last mean pressure (Tamaas' contact solver fails at zero load).
- Residual topography: at every fixed-point iteration Tamaas' elastic-plastic solvers write
  the surface displacement due to the plastic strain (traction-free, periodic, zero mean) into
  the contact solver's surface: ``surface = heights - u_res``.  After unloading,
  ``u_res = heights - surface`` is the plastic print: the permanent normal displacement of the
  half-space's surface, positive *into* the half-space, zero mean (a periodic half-space has no
  absolute level).  It agrees with ``gap + heights`` at the unloaded state (mean removed) up to
  the elastic displacement of the tiny remaining load (1.5e-11 m against an rms of 1.7e-7 m on
  a 32 x 32 x 9 rough scene, 2026-11-26).
- Gap: Tamaas' ``gap`` field, which its contact solver computes against its (plastically
  shifted) surface, so it is the true gap, zero where the traction is positive.  Tamaas'
  ``displacement`` field is not used: in the elastic-plastic model its surface layer holds
  whatever the last sub-solver left (neither the elastic nor the total displacement; it is not
  consistent with the gap on that scene).
"""

from __future__ import annotations

import math
import re
import time
from collections.abc import Sequence
from typing import Any

import numpy as np

from .peers import _captured_output, _tamaas_iterations, _thread_limit
from .peers_plastic import (
    _ANDERSON_MEMORY,
    _CONTACT_TOLERANCE,
    PLASTIC_THRESHOLD,
    UNLOAD_FRACTION,
    _count,
)
from .timing import peak_memory

__all__ = ["DEFAULT_DEPTH_FRACTION", "tamaas_rough"]

#: Depth of the plastic volume, as a fraction of ``side``, when ``depth`` is not given.
DEFAULT_DEPTH_FRACTION = 0.25


def _normal(field: Any) -> np.ndarray:
    """The normal (z) component of a Tamaas surface field, as a float array ``(n, n)``."""
    array = np.array(field, dtype=float)
    return array[..., 2] if array.ndim == 3 else array


def _check(
    heights: np.ndarray,
    side: float,
    E: float,
    nu: float,
    pressures: list[float],
    plastic: dict[str, float] | None,
    tolerance: float,
    threads: int,
) -> None:
    if heights.ndim != 2 or heights.shape[0] != heights.shape[1] or heights.shape[0] < 2:
        raise ValueError(f"heights must be a square (n, n) array with n >= 2, got {heights.shape}")
    if not np.all(np.isfinite(heights)):
        raise ValueError("heights must be finite")
    if not side > 0 or not E > 0 or not tolerance > 0:
        raise ValueError("side, E and tolerance must be positive")
    if not 0.0 <= nu < 0.5:
        raise ValueError(f"need 0 <= nu < 0.5, got {nu}")
    if not pressures or not all(p > 0 for p in pressures):
        raise ValueError("mean_pressures must be a non-empty list of positive pressures")
    if any(b <= a for a, b in zip(pressures, pressures[1:], strict=False)):
        raise ValueError("mean_pressures must increase strictly")
    if threads < 1:
        raise ValueError(f"threads must be at least 1, got {threads}")
    if plastic is not None:
        unknown = set(plastic) - {"yield_stress", "hardening_modulus"}
        if unknown or "yield_stress" not in plastic:
            raise ValueError(
                "plastic must be dict(yield_stress=..., hardening_modulus=...), "
                f"got keys {sorted(plastic)}"
            )
        if not plastic["yield_stress"] > 0 or plastic.get("hardening_modulus", 0.0) < 0:
            raise ValueError("need yield_stress > 0 and hardening_modulus >= 0")


def tamaas_rough(
    heights: np.ndarray,
    side: float,
    *,
    E: float,
    nu: float,
    mean_pressures: Sequence[float],
    plastic: dict[str, float] | None = None,
    depth: float | None = None,
    nz: int | None = None,
    unload: bool = True,
    tolerance: float = 1e-7,
    threads: int = 1,
) -> dict[str, Any]:
    """Press a rigid periodic rough surface on a half-space with Tamaas, load by load.

    Parameters
    ----------
    heights : numpy.ndarray
        One period of the rigid surface's heights (m), shape ``(n, n)``; ``[i, j]`` at
        ``(x, y) = (i, j) side / n``; larger = protruding towards the half-space (Tamaas' own
        convention, passed unchanged; the array itself is not modified).
    side : float
        Period in x and y (m).
    E : float
        Young's modulus of the half-space (Pa).
    nu : float
        Poisson's ratio of the half-space.
    mean_pressures : sequence of float
        Strictly increasing mean pressures (Pa): total normal force over ``side^2``; one solve
        each, the plastic state carrying over.
    plastic : dict, optional
        ``dict(yield_stress=sigma_Y0, hardening_modulus=H)`` (Pa, Pa) for a von Mises
        half-space with linear isotropic hardening ``sigma_Y = sigma_Y0 + H p``, ``p`` the
        accumulated equivalent plastic strain (``H`` defaults to 0); None for an elastic one.
    depth : float, optional
        Depth of the plastic volume (m); default ``DEFAULT_DEPTH_FRACTION * side``.  Unused
        without ``plastic``.
    nz : int, optional
        Node layers of the plastic volume (>= 2), the surface and ``depth`` included, spacing
        ``depth / (nz - 1)``; default: the spacing nearest ``side / n``.  Unused without
        ``plastic``.
    unload : bool, optional
        Plastic only: after the last load, unload to ``UNLOAD_FRACTION`` of it and record the
        residual topography.
    tolerance : float, optional
        Tolerance on Tamaas' outer (Anderson) error, plastic only; the elastic solve and the
        contact sub-solver use 1e-12 on Tamaas' complementarity error.
    threads : int, optional
        OpenMP threads (the PyPI wheel is Tamaas' serial ``cpp`` backend anyway).

    Returns
    -------
    dict
        Per load (lists, one entry per mean pressure): ``area_fraction``: fraction of the
        surface nodes with traction > 0; ``mean_gap``: mean over the period of Tamaas' ``gap``
        field (m); ``max_pressure`` (Pa); plastic only (else None): ``ep_max``: largest
        accumulated equivalent plastic strain ``p`` (Tamaas' ``cumulated_plastic_strain``);
        ``plastic_fraction``: fraction of the ``nz n^2`` volume nodes with
        ``p > PLASTIC_THRESHOLD``.
        After unloading (plastic with ``unload``, else None): ``residual_topography``:
        ``(n, n)`` permanent normal surface displacement (m), positive into the half-space,
        zero mean, on the heights' grid; ``residual_rms``: its rms (m); ``unload_pressure``
        (Pa); ``unloaded_area_fraction``; ``ep_max_unloaded``.
        ``time``, ``cpu``: wall and process-CPU seconds of the ``solve`` calls (s); ``setup``:
        wall seconds of the model and solver construction (s); ``memory``: peak resident-set
        growth over setup and solves (MB); ``iterations``: Polonsky-Keer iterations (elastic)
        or outer Anderson iterations (plastic), summed over the solves; ``inner_iterations``:
        DF-SANE iterations (plastic; None if not logged); ``step_errors``: Tamaas' final error
        of each solve; ``converged``: every error at most its tolerance; ``pressures``,
        ``side``, ``depth``, ``nz`` (Pa, m, m, -); ``method``, ``notes``: descriptions.

    Raises
    ------
    ValueError
        For an input Tamaas cannot take.
    ImportError
        If Tamaas is not installed.
    tamaas.FloatingPointError
        Tamaas' own, when its complementarity error is NaN (contact on a single node while it
        iterates); not caught.

    Notes
    -----
    ``mean_gap`` is Tamaas' gap, ``u_z - heights + c`` with ``c`` such that the gap vanishes
    where the traction is positive; elastic-plastic, ``u_z`` includes the plastic
    displacement.  The residual topography is ``heights - surface`` with ``surface`` the
    contact solver's surface, which Tamaas' elastic-plastic loop sets to ``heights - u_res``.
    """
    surface = np.array(heights, dtype=np.float64, order="C", copy=True)
    pressures = [float(p) for p in mean_pressures]
    side = float(side)
    _check(surface, side, E, nu, pressures, plastic, tolerance, threads)
    n = surface.shape[0]
    if plastic is not None:
        depth = DEFAULT_DEPTH_FRACTION * side if depth is None else float(depth)
        nz = max(2, round(depth / (side / n)) + 1) if nz is None else int(nz)
        if not depth > 0 or nz < 2:
            raise ValueError(f"need depth > 0 and nz >= 2, got {depth}, {nz}")
    else:
        depth, nz, unload = None, None, False
    loads = list(pressures)
    if unload:
        loads.append(UNLOAD_FRACTION * pressures[-1])

    import tamaas as tm
    from tamaas.nonlinear_solvers import DFSANECXXSolver
    from tamaas.utils import log_context

    logs: list[str] = []
    errors: list[float] = []
    records: list[dict[str, Any]] = []
    wall = cpu = 0.0
    with peak_memory() as memory, _thread_limit(threads), log_context(tm.LogLevel.info):
        wall0 = time.perf_counter()
        if plastic is None:
            model = tm.ModelFactory.createModel(tm.model_type.basic_2d, [side, side], [n, n])
            model.E, model.nu = E, nu
            solver = tm.PolonskyKeerRey(model, surface, _CONTACT_TOLERANCE)
            contact_solver, limit = solver, _CONTACT_TOLERANCE
        else:
            model = tm.ModelFactory.createModel(
                tm.model_type.volume_2d, [depth, side, side], [nz, n, n]
            )
            model.E, model.nu = E, nu
            material = tm.materials.IsotropicHardening(
                model, plastic["yield_stress"], plastic.get("hardening_modulus", 0.0)
            )
            residual = tm.Residual(model, material)
            contact_solver = tm.PolonskyKeerRey(model, surface, _CONTACT_TOLERANCE)
            solver = tm.AndersonMixing(
                contact_solver, DFSANECXXSolver(residual), tolerance, memory=_ANDERSON_MEMORY
            )
            limit = tolerance
        setup = time.perf_counter() - wall0
        for load in loads:
            log: list[str] = []
            with _captured_output(log):
                cpu0, wall0 = time.process_time(), time.perf_counter()
                errors.append(float(solver.solve(load)))
                wall += time.perf_counter() - wall0
                cpu += time.process_time() - cpu0
            logs.append("".join(log))
            pressure = _normal(model.traction)
            record = {
                "area_fraction": float(np.count_nonzero(pressure > 0)) / pressure.size,
                "mean_gap": float(np.mean(_normal(model["gap"]))),
                "max_pressure": float(pressure.max()),
            }
            if plastic is not None:
                p = np.array(model["cumulated_plastic_strain"], dtype=float)
                record["ep_max"] = float(p.max())
                record["plastic_fraction"] = float(np.count_nonzero(p > PLASTIC_THRESHOLD)) / p.size
            records.append(record)
        if unload:
            solver_surface = np.array(contact_solver.surface, dtype=float).reshape(n, n)
            plastic_print = np.asarray(heights, dtype=float) - solver_surface
    loaded = records[: len(pressures)]

    def column(key: str) -> list[float] | None:
        return [r[key] for r in loaded] if key in loaded[0] else None

    if plastic is None:
        iterations = sum(_tamaas_iterations(text) or 0 for text in logs)
        inner = None
        method = "tamaas PolonskyKeerRey (basic_2d, periodic), elastic"
    else:
        iterations = sum(len(re.findall(r"\[(?:Anderson|EPIC)\] error", text)) for text in logs)
        found = _count(r"DF-SANE: \w+ convergence \((\d+) iterations", "".join(logs))
        inner = sum(found) if found else None
        method = (
            "tamaas AndersonMixing (volume_2d, periodic), DF-SANE plasticity, "
            "PolonskyKeerRey contact"
        )
    residual_topography = residual_rms = None
    if unload:
        residual_topography = plastic_print - plastic_print.mean()
        residual_rms = float(math.sqrt(np.mean(residual_topography**2)))
    cell = side / n
    notes = (
        f"Tamaas {tm.__version__} periodic cell {side * 1e6:.4g} um, {n}x{n} nodes every "
        f"{cell * 1e6:.4g} um, E {E:g} Pa, nu {nu:g}; "
        + (
            f"elastic basic_2d, PolonskyKeerRey tol {_CONTACT_TOLERANCE:g}"
            if plastic is None
            else f"volume_2d {depth * 1e6:.4g} um deep, {nz} node layers every "
            f"{depth / (nz - 1) * 1e6:.4g} um (surface and bottom included), sigma_Y0 "
            f"{plastic['yield_stress']:g} Pa, H {plastic.get('hardening_modulus', 0.0):g} Pa; "
            f"AndersonMixing(memory {_ANDERSON_MEMORY}) tol {tolerance:g} + DFSANECXXSolver + "
            f"PolonskyKeerRey tol {_CONTACT_TOLERANCE:g}; "
            + (
                f"unloaded to {loads[-1]:g} Pa mean pressure (Tamaas fails at 0)"
                if unload
                else "no unloading"
            )
        )
    )
    return {
        "area_fraction": column("area_fraction"),
        "mean_gap": column("mean_gap"),
        "max_pressure": column("max_pressure"),
        "ep_max": column("ep_max"),
        "plastic_fraction": column("plastic_fraction"),
        "residual_topography": residual_topography,
        "residual_rms": residual_rms,
        "unload_pressure": loads[-1] if unload else None,
        "unloaded_area_fraction": records[-1]["area_fraction"] if unload else None,
        "ep_max_unloaded": records[-1]["ep_max"] if unload else None,
        "time": wall,
        "cpu": cpu,
        "setup": setup,
        "memory": memory["peak_MB"],
        "iterations": iterations if iterations else None,
        "inner_iterations": inner,
        "step_errors": errors,
        "converged": all(error <= limit for error in errors),
        "pressures": pressures,
        "side": side,
        "depth": depth,
        "nz": nz,
        "method": method,
        "notes": notes,
    }
