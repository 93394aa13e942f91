"""Adapters that run open peer contact codes on the same problems as slipstick.

Three peers are wrapped, each imported lazily inside its adapter so that this module imports
without any of them:

``tamaas``
    Tamaas (EPFL, AGPL), ``pip install tamaas``.  Normal contact uses its built-in
    non-periodic Boussinesq operator (``ModelFactory.registerNonPeriodic``) with the
    Polonsky-Keer solver ``PolonskyKeerRey``.  Its frictional solver ``PolonskyKeerTan`` exists
    only for the *periodic* ``surface_2d`` model, so the partial-slip adapter embeds the window in
    a larger periodic cell (see ``periodic_padding``).
``contactmechanics``
    ContactMechanics (Pastewka group, MIT), ``pip install contactmechanics``.  Normal contact
    only: ``FreeFFTElasticHalfSpace`` (zero-padded, non-periodic) with
    ``constrained_conjugate_gradients`` at prescribed external force.
``aspher``
    ASPHER (Yastrebov, BSD-3), ``apt-get install libeigen3-dev && pip install aspher`` (built
    from source).  Normal contact through ``solve_nested`` with the exact zero-padded
    FFT-convolution operator (``backend="fft"``); partial slip through ``FrictionSolver``
    (uncoupled elasticity, load history: normal step, then tangential step).

All adapters use the slipstick grid convention: an ``n x n`` grid of square cells of side
``side / n`` covering ``[-side/2, side/2]^2`` centred on the contact, fields sampled at cell
centres, array index ``[i, j]`` with ``x`` along axis 0 and ``y`` along axis 1.  Units are SI.
Peer-specific conventions (ASPHER stores ``x`` along axis 1; Tamaas and ContactMechanics take
rigid-surface heights rather than gaps) are converted inside the adapters.

Timing: ``time`` and ``cpu`` cover the solve call(s) only; imports, grid construction and the
peer's setup (model/operator/Green's-function construction where the peer separates it) are
reported as ``setup``.  ASPHER's ``solve_nested`` builds its operators inside the solve, so for
ASPHER's normal solve the operator construction is part of ``time``.  Every solve runs with the
OpenMP thread count set to ``threads`` (``OMP_NUM_THREADS`` and friends for libraries loaded
afterwards, ``omp_set_num_threads`` on an already loaded ``libgomp``).  The installed Tamaas
wheel is its serial ``cpp`` backend and ContactMechanics runs serial FFTs, so only ASPHER is
actually multi-threaded.
"""

from __future__ import annotations

import contextlib
import ctypes
import importlib
import importlib.metadata
import math
import os
import re
import sys
import tempfile
import time
from collections.abc import Iterator
from typing import Any

import numpy as np

__all__ = ["PEERS", "available_peers", "cattaneo_peer", "hertz_peer", "stick_radius_ratio"]

#: Peer name -> (importable module, distribution name on the package index).
PEERS: dict[str, tuple[str, str]] = {
    "tamaas": ("tamaas", "tamaas"),
    "contactmechanics": ("ContactMechanics", "contactmechanics"),
    "aspher": ("aspher", "aspher"),
}

_THREAD_VARIABLES = (
    "OMP_NUM_THREADS",
    "OPENBLAS_NUM_THREADS",
    "MKL_NUM_THREADS",
    "NUMEXPR_NUM_THREADS",
)

# Accuracy targets, each in the peer's own measure, chosen so that every peer's solution error
# is dominated by the discretisation at n >= 64 (checked against the Hertz solution).
_TAMAAS_TOLERANCE = 1e-10  # Tamaas' normalised complementarity error
_CM_PENETRATION_TOLERANCE = 1e-8  # ContactMechanics' max penetration, relative to the approach
_ASPHER_TOLERANCE = 1e-8  # ASPHER's certified Frank-Wolfe error
_ASPHER_TANGENTIAL_TOLERANCE = 1e-6  # ASPHER's tangential projected-CG residual
_MAX_ITERATIONS = 5_000
_TAMAAS_FIRST_MAX_ITER = 128  # Tamaas PolonskyKeerTan: first iteration budget, then doubled
_TAMAAS_AGREEMENT = 1e-6  # ... until two runs agree to this, relative to the largest traction


def available_peers() -> dict[str, str]:
    """Return the installed, importable peer codes and their versions.

    Returns
    -------
    dict of str to str
        Peer name (a key of :data:`PEERS`) mapped to the installed distribution version, for
        every peer that imports without error.
    """
    found = {}
    for name, (module, distribution) in PEERS.items():
        try:
            importlib.import_module(module)
        except Exception:  # a peer that fails to import is simply not available
            continue
        try:
            found[name] = importlib.metadata.version(distribution)
        except importlib.metadata.PackageNotFoundError:
            found[name] = "unknown"
    return found


def _peer_key(name: str) -> str:
    key = name.strip().lower().replace("-", "").replace("_", "")
    if key not in PEERS:
        raise ValueError(f"unknown peer {name!r}; known peers: {', '.join(PEERS)}")
    return key


def _cell_centres(n: int, side: float) -> np.ndarray:
    return (np.arange(n) + 0.5) * (side / n) - 0.5 * side


def _paraboloid_gap(x: np.ndarray, radius: float) -> np.ndarray:
    """Initial gap ``(x^2 + y^2) / (2 R)`` on the grid, ``[i, j]`` at ``(x_i, y_j)``."""
    squared = x**2
    return (squared[:, None] + squared[None, :]) / (2.0 * radius)


def _hertz_approach(radius: float, contact_modulus: float, normal_force: float) -> float:
    """Hertz approach ``a^2 / R``, used only as a length scale for tolerances."""
    a = (3.0 * normal_force * radius / (4.0 * contact_modulus)) ** (1.0 / 3.0)
    return a * a / radius


def _check_common(n: int, radius: float, normal_force: float, side: float, threads: int) -> None:
    if n < 2:
        raise ValueError(f"n must be at least 2, got {n}")
    if radius <= 0 or side <= 0 or normal_force <= 0:
        raise ValueError("radius, side and normal_force must be positive")
    if threads < 1:
        raise ValueError(f"threads must be at least 1, got {threads}")


def _loaded_libgomp() -> Any:
    """Return the already loaded GNU OpenMP runtime, or None (never loads a new copy)."""
    if not sys.platform.startswith("linux"):
        return None
    try:
        return ctypes.CDLL("libgomp.so.1", mode=os.RTLD_NOLOAD)
    except OSError:
        return None


@contextlib.contextmanager
def _thread_limit(threads: int) -> Iterator[None]:
    """Run the body with OpenMP (and BLAS) thread counts set to ``threads``, then restore."""
    saved_environment = {key: os.environ.get(key) for key in _THREAD_VARIABLES}
    for key in _THREAD_VARIABLES:
        os.environ[key] = str(threads)
    gomp = _loaded_libgomp()
    saved_threads = None
    if gomp is not None:
        saved_threads = int(gomp.omp_get_max_threads())
        gomp.omp_set_num_threads(ctypes.c_int(threads))
    try:
        yield
    finally:
        if gomp is not None and saved_threads is not None:
            gomp.omp_set_num_threads(ctypes.c_int(saved_threads))
        for key, value in saved_environment.items():
            if value is None:
                os.environ.pop(key, None)
            else:
                os.environ[key] = value


@contextlib.contextmanager
def _captured_output(sink: list[str]) -> Iterator[None]:
    """Capture what native code writes to file descriptors 1 and 2; append it to ``sink``."""
    sys.stdout.flush()
    sys.stderr.flush()
    with tempfile.TemporaryFile(mode="w+b") as capture:
        saved = os.dup(1), os.dup(2)
        os.dup2(capture.fileno(), 1)
        os.dup2(capture.fileno(), 2)
        try:
            yield
        finally:
            os.dup2(saved[0], 1)
            os.dup2(saved[1], 2)
            os.close(saved[0])
            os.close(saved[1])
            capture.seek(0)
            sink.append(capture.read().decode(errors="replace"))


def _tamaas_iterations(log: str) -> int | None:
    """Last iteration number of a Tamaas solver log (``Iter Cost_f Error`` table), or None."""
    rows = re.findall(r"^\s*(\d+)\s+\S+\s+\S+\s*$", log, flags=re.MULTILINE)
    return int(rows[-1]) if rows else None


def _timed(function: Any, *args: Any, **kwargs: Any) -> tuple[Any, float, float]:
    cpu0, wall0 = time.process_time(), time.perf_counter()
    value = function(*args, **kwargs)
    return value, time.perf_counter() - wall0, time.process_time() - cpu0


# --------------------------------------------------------------------------------------------
# Normal (Hertz) contact
# --------------------------------------------------------------------------------------------


def hertz_peer(
    name: str,
    n: int,
    radius: float,
    contact_modulus: float,
    normal_force: float,
    side: float,
    threads: int = 1,
) -> dict[str, Any]:
    """Solve the non-periodic Hertz contact of a rigid paraboloid with a peer code.

    A rigid paraboloid ``z = (x^2 + y^2) / (2 R)`` is pressed onto an elastic half-space of
    contact modulus ``E*`` by the total normal force ``W``.  The half-space is non-periodic
    (free surface outside the window, zero pressure imposed outside it); the window is the
    ``n x n`` cell grid of side ``side`` centred on the apex.

    Parameters
    ----------
    name : str
        Peer code: ``"tamaas"``, ``"contactmechanics"`` or ``"aspher"`` (case-insensitive).
    n : int
        Cells per side.
    radius : float
        Sphere radius ``R`` (m).
    contact_modulus : float
        Contact modulus ``E* = E / (1 - nu^2)`` of the half-space (Pa); for two elastic bodies
        the composite ``1 / E* = (1 - nu1^2) / E1 + (1 - nu2^2) / E2``.
    normal_force : float
        Total normal force ``W`` (N).
    side : float
        Side of the square window (m).
    threads : int, optional
        OpenMP threads the peer may use (default 1).

    Returns
    -------
    dict
        ``pressure``: ``(n, n)`` array of cell pressures (Pa), ``[i, j]`` at ``(x[i], x[j])``;
        ``x``: ``(n,)`` cell-centre coordinates (m), the same along both axes;
        ``time``: wall seconds of the solve; ``cpu``: process CPU seconds of the solve;
        ``setup``: wall seconds of the peer's model and operator construction before the solve;
        ``iterations``: the peer's iteration count (int) or None;
        ``approach``: rigid-body approach (m) or None; ``converged``: the peer's own verdict
        (bool) or None; ``peer``: the peer name; ``method``: a one-line description.

    Raises
    ------
    ValueError
        For an unknown peer name or a non-physical input.
    ImportError
        If the peer is not installed.

    Notes
    -----
    - ``tamaas``: ``basic_2d`` model with the non-periodic Boussinesq operator registered by
      ``ModelFactory.registerNonPeriodic`` and ``PolonskyKeerRey`` at mean pressure
      ``W / side^2``, tolerance 1e-12 on Tamaas' own error; ``approach`` is recovered as the mean
      of ``u - h`` over the contact (one extra operator application, outside the timing);
      ``iterations`` is parsed from Tamaas' solver log.
    - ``contactmechanics``: ``FreeFFTElasticHalfSpace`` (computational grid ``2n x 2n``,
      Hockney zero padding) and ``constrained_conjugate_gradients(external_force=W)`` with a
      penetration tolerance of 1e-8 of the Hertz approach; the Green's function is built in
      ``setup``.  The grid is ContactMechanics' own (pixel ``k`` at ``k h``); since the kernel
      is translation invariant, passing heights sampled at our cell centres gives our problem.
    - ``aspher``: ``solve_nested(backend="fft")`` (exact zero-padded convolution of the Love
      element integrals), nested from the coarsest grid ``n / 2^k >= 64`` (a single level when
      ``n <= 64`` or ``n`` has no such factor), certified tolerance 1e-8; the operators are
      built inside the timed call; ``iterations`` is the finest-level count.
    """
    key = _peer_key(name)
    _check_common(n, radius, normal_force, side, threads)
    if contact_modulus <= 0:
        raise ValueError("contact_modulus must be positive")
    solve = {"tamaas": _tamaas_hertz, "contactmechanics": _cm_hertz, "aspher": _aspher_hertz}[key]
    out = solve(n, radius, contact_modulus, normal_force, side, threads)
    out["peer"] = key
    out["x"] = _cell_centres(n, side)
    return out


def _tamaas_hertz(
    n: int, radius: float, contact_modulus: float, normal_force: float, side: float, threads: int
) -> dict[str, Any]:
    import tamaas as tm

    heights = -_paraboloid_gap(_cell_centres(n, side), radius)  # rigid surface, apex at 0
    log: list[str] = []
    with _thread_limit(threads):
        wall0 = time.perf_counter()
        model = tm.ModelFactory.createModel(tm.model_type.basic_2d, [side, side], [n, n])
        model.E = contact_modulus  # with nu = 0, Tamaas' E* equals E
        model.nu = 0.0
        tm.ModelFactory.registerNonPeriodic(model, "hertz")
        solver = tm.PolonskyKeerRey(model, heights, _TAMAAS_TOLERANCE)
        solver.setIntegralOperator("hertz")
        solver.max_iter = _MAX_ITERATIONS
        setup = time.perf_counter() - wall0
        with _captured_output(log):
            error, wall, cpu = _timed(solver.solve, normal_force / side**2)
    pressure = np.array(model.traction, dtype=float, copy=True).reshape(n, n)
    displacement = np.zeros_like(pressure)
    model.operators["hertz"](pressure.copy(), displacement)
    contact = pressure > 0
    approach = float(np.mean(displacement[contact] - heights[contact])) if contact.any() else None
    return {
        "pressure": pressure,
        "time": wall,
        "cpu": cpu,
        "setup": setup,
        "iterations": _tamaas_iterations(log[0]) if log else None,
        "approach": approach,
        "converged": bool(error < _TAMAAS_TOLERANCE),
        "method": "tamaas PolonskyKeerRey, non-periodic Boussinesq operator",
    }


def _cm_hertz(
    n: int, radius: float, contact_modulus: float, normal_force: float, side: float, threads: int
) -> dict[str, Any]:
    from ContactMechanics import FreeFFTElasticHalfSpace
    from ContactMechanics.Optimization import constrained_conjugate_gradients
    from SurfaceTopography import Topography

    heights = -_paraboloid_gap(_cell_centres(n, side), radius)
    pentol = _CM_PENETRATION_TOLERANCE * _hertz_approach(radius, contact_modulus, normal_force)
    with _thread_limit(threads):
        wall0 = time.perf_counter()
        substrate = FreeFFTElasticHalfSpace((n, n), contact_modulus, (side, side))
        topography = Topography(heights, physical_sizes=(side, side))
        setup = time.perf_counter() - wall0
        result, wall, cpu = _timed(
            constrained_conjugate_gradients,
            substrate,
            topography,
            external_force=normal_force,
            pentol=pentol,
            maxiter=_MAX_ITERATIONS,
        )
    forces = np.asarray(result.jac, dtype=float)[:n, :n]  # compressive nodal forces (N)
    return {
        "pressure": forces / (side / n) ** 2,
        "time": wall,
        "cpu": cpu,
        "setup": setup,
        "iterations": int(result.nit),
        "approach": float(result.offset),
        "converged": bool(result.success),
        "method": "ContactMechanics FreeFFTElasticHalfSpace + constrained_conjugate_gradients",
    }


def _nested_coarsest(n: int, floor: int = 64) -> int:
    coarsest = n
    while coarsest % 2 == 0 and coarsest // 2 >= floor:
        coarsest //= 2
    return coarsest


def _aspher_hertz(
    n: int, radius: float, contact_modulus: float, normal_force: float, side: float, threads: int
) -> dict[str, Any]:
    import aspher

    # ASPHER stores x along axis 1: hand it the transpose and transpose its fields back.
    gap = np.ascontiguousarray(_paraboloid_gap(_cell_centres(n, side), radius).T)
    with _thread_limit(threads):
        result, wall, cpu = _timed(
            aspher.solve_nested,
            grid_size=n,
            gap=gap,
            p_nominal=normal_force / side**2,
            domain_size=side,
            E_star=contact_modulus,
            coarsest=_nested_coarsest(n),
            backend="fft",
            tol=_ASPHER_TOLERANCE,
            max_iter=_MAX_ITERATIONS,
        )
    pressure = np.array(result.pressure, dtype=float).reshape(n, n).T.copy()
    return {
        "pressure": pressure,
        "time": wall,
        "cpu": cpu,
        "setup": 0.0,
        "iterations": int(result.iterations),
        "approach": float(result.approach),
        "converged": bool(result.converged),
        "method": "aspher solve_nested, backend='fft' (operator build inside the solve)",
    }


# --------------------------------------------------------------------------------------------
# Partial slip (Cattaneo-Mindlin)
# --------------------------------------------------------------------------------------------


def cattaneo_peer(
    name: str,
    n: int,
    radius: float,
    young_modulus: float,
    poisson_ratio: float,
    normal_force: float,
    tangential_force: float,
    friction_coefficient: float,
    side: float,
    threads: int = 1,
    periodic_padding: int = 2,
) -> dict[str, Any]:
    """Solve the Cattaneo-Mindlin partial-slip contact of a rigid sphere with a peer code.

    A rigid paraboloid ``z = (x^2 + y^2) / (2 R)`` on an elastic half-space of Young's modulus
    ``E`` and Poisson's ratio ``nu`` is first pressed by the normal force ``W``, then loaded by
    the tangential force ``Q`` along ``+x`` at constant ``W``, with Coulomb friction ``mu``
    (``|Q| < mu W``: partial slip).  The bodies are dissimilar (rigid on elastic), so the
    Dundurs constant is ``beta = (1 - 2 nu) / (2 (1 - nu))``, non-zero unless ``nu = 0.5``.

    Parameters
    ----------
    name : str
        Peer code: ``"tamaas"`` or ``"aspher"`` (``"contactmechanics"`` has no frictional
        solver and raises :class:`NotImplementedError`).
    n : int
        Cells per side of the window.
    radius : float
        Sphere radius ``R`` (m).
    young_modulus : float
        Young's modulus ``E`` of the half-space (Pa); the sphere is rigid.
    poisson_ratio : float
        Poisson's ratio ``nu`` of the half-space, ``0 <= nu <= 0.5``.  The contact modulus is
        ``E* = E / (1 - nu^2)`` and the shear modulus ``G = E / (2 (1 + nu))``; the Cattaneo
        tangential compliance involves ``(2 - nu) / G``.
    normal_force : float
        Total normal force ``W`` (N).
    tangential_force : float
        Total tangential force ``Q`` (N) along ``+x``, ``0 <= Q < mu W``.
    friction_coefficient : float
        Coulomb friction coefficient ``mu``.
    side : float
        Side of the square window (m), centred on the apex.
    threads : int, optional
        OpenMP threads the peer may use (default 1).
    periodic_padding : int, optional
        Tamaas only: the periodic cell is ``periodic_padding`` times the window (same cell
        size, window at its centre); ``(periodic_padding - 1) * n`` must be even.  Default 2.

    Returns
    -------
    dict
        The keys of :func:`hertz_peer` (``pressure``, ``x``, ``time``, ``cpu``, ``setup``,
        ``iterations``, ``approach``, ``converged``, ``peer``, ``method``) with ``time`` and
        ``cpu`` covering the whole load history, plus ``shear_x`` and ``shear_y``: ``(n, n)``
        tangential tractions (Pa) the sphere applies to the half-space (like ``pressure``), so
        that ``shear_x.sum() * (side / n)**2 == Q``; ``tangential_shift``: rigid tangential
        displacement of the sphere along ``x`` (m) or None.

    Raises
    ------
    NotImplementedError
        For ``contactmechanics``, which solves frictionless normal contact only.
    ValueError
        For an unknown peer, ``Q >= mu W``, or a padding that cannot centre the window.

    Notes
    -----
    The two peers solve *different* idealisations of the problem; neither is the exact
    coupled sequential-loading problem for ``nu < 0.5``:

    - ``aspher`` (``FrictionSolver``): non-periodic (zero-padded FFT), **uncoupled**
      elasticity (``beta = 0`` assumed whatever ``nu``: the tangential tractions do not change
      the pressure; ``nu`` enters only the Cerruti tangential compliance), true load history
      (normal step at ``p_bar = W / side^2``, then tangential step at ``q_bar = Q / side^2``).
      This is the classical Cattaneo-Mindlin problem, for which
      ``c / a = (1 - Q / (mu W))^(1/3)``.  It is run without its spectral preconditioner
      (which stalls on this problem) and with tangential tolerance 1e-6; ``converged`` is
      ASPHER's verdict, and a non-converged step still returns its last tractions (its
      ``tangential_shift`` is then None); with ``nu = 0.5`` ASPHER 0.1.3 reported
      non-convergence at n = 64 and 128 although ``Q`` and ``c / a`` came out right.
    - ``tamaas`` (``PolonskyKeerTan``): **fully coupled** three-dimensional Boussinesq-Cerruti
      elasticity (``beta != 0`` for ``nu < 0.5``), **periodic only** (the ``surface_2d`` model
      has no non-periodic operator in Tamaas 2.9), and a **single step**: ``W`` and ``Q`` are
      imposed together as mean tractions, not one after the other.  For ``nu = 0.5``
      (``beta = 0``) the single step reproduces Cattaneo-Mindlin; for ``nu < 0.5`` it does not
      (e.g. steel ``nu = 0.3`` gives a markedly smaller stick zone and a higher peak
      pressure).  To compare with the ``beta = 0`` theory pass ``poisson_ratio = 0.5`` and
      ``young_modulus = 0.75 E*``.  The periodic images perturb the window unless
      ``periodic_padding * side`` is several contact diameters; ``approach`` is None (undefined
      in a periodic cell).  Tamaas' error measure for this solver levels off near 1e-7 instead
      of tending to zero and each solve restarts from scratch, so the adapter solves with
      ``max_iter`` = 128, 256, ... and returns the first run whose tractions agree with the
      next (twice as long) run to 1e-6 of the largest traction; ``time``, ``cpu`` and
      ``iterations`` are those of the returned run alone, while the whole call costs about
      three times as much (n = 256 with padding 2: 2048 iterations on a 512^2 cell, ~160 s
      CPU for the returned run).
    """
    key = _peer_key(name)
    _check_common(n, radius, normal_force, side, threads)
    if young_modulus <= 0 or not 0.0 <= poisson_ratio <= 0.5:
        raise ValueError("need young_modulus > 0 and 0 <= poisson_ratio <= 0.5")
    if friction_coefficient <= 0 or not 0 <= tangential_force < friction_coefficient * normal_force:
        raise ValueError("partial slip needs mu > 0 and 0 <= Q < mu W")
    if key == "contactmechanics":
        raise NotImplementedError(
            "ContactMechanics solves frictionless normal contact only; it has no tangential "
            "or partial-slip solver"
        )
    args = (
        n,
        radius,
        young_modulus,
        poisson_ratio,
        normal_force,
        tangential_force,
        friction_coefficient,
        side,
        threads,
    )
    if key == "tamaas":
        out = _tamaas_cattaneo(*args, periodic_padding=periodic_padding)
    else:
        out = _aspher_cattaneo(*args)
    out["peer"] = key
    out["x"] = _cell_centres(n, side)
    return out


def _tamaas_cattaneo(
    n: int,
    radius: float,
    young_modulus: float,
    poisson_ratio: float,
    normal_force: float,
    tangential_force: float,
    friction_coefficient: float,
    side: float,
    threads: int,
    periodic_padding: int = 2,
) -> dict[str, Any]:
    import tamaas as tm

    if periodic_padding < 1 or ((periodic_padding - 1) * n) % 2:
        raise ValueError(
            f"periodic_padding={periodic_padding} cannot centre an n={n} window; "
            "(periodic_padding - 1) * n must be even"
        )
    cells = periodic_padding * n
    period = periodic_padding * side
    heights = -_paraboloid_gap(_cell_centres(cells, period), radius)
    start = (cells - n) // 2
    window = slice(start, start + n)
    mean_tractions = [tangential_force / period**2, 0.0, normal_force / period**2]
    runs: list[dict[str, Any]] = []
    with _thread_limit(threads):
        wall0 = time.perf_counter()
        model = tm.ModelFactory.createModel(
            tm.model_type.surface_2d, [period, period], [cells, cells]
        )
        model.E = young_modulus
        model.nu = poisson_ratio
        # Tamaas' error measure for this solver levels off at a problem-dependent value
        # (~1e-7), so it cannot serve as the stopping rule and every solve restarts from zero.
        # Run with an unreachable tolerance and max_iter = 128, 256, ...; accept the first run
        # whose tractions agree with those of the run twice as long.
        solver = tm.PolonskyKeerTan(model, heights, _TAMAAS_TOLERANCE, friction_coefficient)
        setup = time.perf_counter() - wall0
        max_iter = _TAMAAS_FIRST_MAX_ITER
        while max_iter <= _MAX_ITERATIONS:
            solver.max_iter = max_iter
            log: list[str] = []
            with _captured_output(log):
                error, wall, cpu = _timed(solver.solve, mean_tractions)
            traction = np.array(model.traction, dtype=float, copy=True).reshape(cells, cells, 3)
            # The log shows every dump_freq-th iteration only; a run that did not reach the
            # tolerance ran exactly max_iter iterations.
            done = max_iter if error >= _TAMAAS_TOLERANCE else _tamaas_iterations(log[0])
            runs.append({"traction": traction, "time": wall, "cpu": cpu, "iterations": done})
            if len(runs) > 1:
                change = np.abs(traction - runs[-2]["traction"]).max()
                if change <= _TAMAAS_AGREEMENT * np.abs(traction).max():
                    break
            max_iter *= 2
    converged = len(runs) > 1 and max_iter <= _MAX_ITERATIONS
    accepted = runs[-2] if converged else runs[-1]
    traction = accepted["traction"][window, window]
    return {
        "pressure": traction[..., 2].copy(),
        "shear_x": traction[..., 0].copy(),
        "shear_y": traction[..., 1].copy(),
        "time": accepted["time"],
        "cpu": accepted["cpu"],
        "setup": setup,
        "iterations": accepted["iterations"],
        "approach": None,
        "tangential_shift": None,
        "converged": converged,
        "method": (
            f"tamaas PolonskyKeerTan, periodic surface_2d cell {periodic_padding}x the window, "
            "coupled elasticity, W and Q in one step"
        ),
    }


def _aspher_cattaneo(
    n: int,
    radius: float,
    young_modulus: float,
    poisson_ratio: float,
    normal_force: float,
    tangential_force: float,
    friction_coefficient: float,
    side: float,
    threads: int,
) -> dict[str, Any]:
    import aspher

    contact_modulus = young_modulus / (1.0 - poisson_ratio**2)
    # ASPHER stores x along axis 1 (its q_bar[0] is along axis 1): transpose in and out.
    gap = np.ascontiguousarray(_paraboloid_gap(_cell_centres(n, side), radius).T)
    area = side * side
    with _thread_limit(threads):
        wall0 = time.perf_counter()
        solver = aspher.FrictionSolver(
            grid_size=n,
            domain_size=side,
            E_star=contact_modulus,
            nu=poisson_ratio,
            model=aspher.CoulombFriction(friction_coefficient),
            precond=False,
        )
        solver.set_gap(gap)
        setup = time.perf_counter() - wall0
        cpu0, wall0 = time.process_time(), time.perf_counter()
        normal = solver.step(p_bar=normal_force / area, tol_normal=_ASPHER_TOLERANCE)
        tangential = solver.step(
            q_bar=(tangential_force / area, 0.0),
            tol_normal=_ASPHER_TOLERANCE,
            tol_tangential=_ASPHER_TANGENTIAL_TOLERANCE,
            max_iter=_MAX_ITERATIONS,
        )
        wall, cpu = time.perf_counter() - wall0, time.process_time() - cpu0
    pressure = np.array(solver.pressure, dtype=float).reshape(n, n).T.copy()
    shift = tangential.delta_t
    return {
        "pressure": pressure,
        "shear_x": np.array(tangential.qx, dtype=float).reshape(n, n).T.copy(),
        "shear_y": np.array(tangential.qy, dtype=float).reshape(n, n).T.copy(),
        "time": wall,
        "cpu": cpu,
        "setup": setup,
        "iterations": int(normal.normal_iters) + int(tangential.tangential_iters),
        "approach": float(normal.approach),
        "tangential_shift": float(shift[0]) if shift is not None else None,
        "converged": bool(normal.converged and tangential.converged),
        "method": "aspher FrictionSolver (uncoupled, beta = 0), normal step then tangential step",
    }


def stick_radius_ratio(out: dict[str, Any], friction_coefficient: float, radius: float) -> float:
    """Return the equivalent stick-zone radius of a partial-slip result over a contact radius.

    Stick cells are those in contact (``p > 0``) with ``|q| < mu p (1 - 1e-3)``; their total
    area is converted to the radius of a disc of the same area.

    Parameters
    ----------
    out : dict
        A result of :func:`cattaneo_peer` (needs ``pressure``, ``shear_x``, ``shear_y``, ``x``).
    friction_coefficient : float
        Coulomb coefficient ``mu``.
    radius : float
        Contact radius ``a`` (m) to divide by, e.g. the Hertz radius.

    Returns
    -------
    float
        ``c / a``, to compare with Cattaneo-Mindlin ``(1 - Q / (mu W))^(1/3)``.
    """
    pressure = np.asarray(out["pressure"])
    shear = np.hypot(out["shear_x"], out["shear_y"])
    stick = (pressure > 0) & (shear < friction_coefficient * pressure * (1.0 - 1e-3))
    dx = float(out["x"][1] - out["x"][0])
    return math.sqrt(np.count_nonzero(stick) * dx * dx / math.pi) / radius
