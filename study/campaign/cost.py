"""Case cost in seconds: a physics-free count of the work, times a machine's unit costs.

* :func:`count` (pure, no timing): how many surface-operator applications and plasticity
  iterations a case needs, from its grid, load path (steps, tangential and sliding
  increments, cycles), friction, coupling (Dundurs' beta) and plastic regime
  (p_max / sigma_Y0).  Its factors were fitted on the iteration histories
  (``normal_iterations``, ``slip_iterations``, ``coupling_iterations``,
  ``plastic_iterations``) of small versions of the shipped campaigns (``python -m
  study.bench.cost``, 2026-11-26); see :data:`COUNTS`.
* :class:`Calibration`: seconds per unit.  :data:`REFERENCE` holds unit costs fitted on the
  development machine; this machine's are measured and kept by :mod:`study.run.calibration`.

The model (CPU seconds of one core; :func:`seconds`)::

    seconds = case + build Ns' + c(Ns) Ns log2 Ns (normal NI + slip SI)
              + iteration (NI + SI) + passes CI
              + PI (plastic + c(Mv) volume Mv log2 Mv) + volume_build Mv'

``NI``, ``SI``, ``CI``, ``PI``: CG iterations, slip-solver applications, slip-stick passes and
plasticity iterations (:func:`count`); ``Ns = 4 nx ny`` and ``Mv = 4 bx by 2 nz`` the padded
surface and plastic-box cells an iteration works on (the surface of the window that follows a
moving contact, when there is one); ``Ns'``, ``Mv'`` the cells of every operator built; ``c``
the cache factor (:data:`CACHE_EXPONENT`).  The unit costs (``case``, ``build``,
``normal``, ``slip``, ``iteration``, ``passes``, ``plastic``, ``volume``, ``volume_build``)
are those of :class:`Calibration`.

:func:`campaign_seconds` turns case seconds into the time of a campaign on N ranks by list
scheduling, costliest first onto the least-loaded rank, as the driver hands cases out (rank 0
computes too, beside its dispatcher thread).  The campaign layer prices every case at
:data:`REFERENCE` (:attr:`CampaignCase.cost`: the same on every machine).
"""

from __future__ import annotations

import heapq
import math
from collections.abc import Iterable
from dataclasses import dataclass, fields, replace

import solver
from solver.case.substeps import substep_count, substep_floor

#: Version of the counting and of the calibration cases: a calibration of another is redone.
MODEL = 1

#: Iteration-count factors of :func:`count_features`, fitted (``/tmp``-free: the fit is the
#: least squares of ``python -m study.bench.cost --jsonl`` records, see the module doc) on 131
#: cases of the shipped campaigns and of smaller versions of them (16^3 to 48 x 24 x 24
#: plastic boxes, 32^2 to 768^2 surfaces; 2026-11-26).
#: Plastic strain (1) of the flow stress that scales the plastic regime of the count: hardening
#: laws that stiffen at once (Swift: 1.75 sigma_Y0 at 0.2 %) iterate like a lower load.
REFERENCE_PLASTIC_STRAIN = 0.002

COUNTS = {
    # elastic, no slip-stick loop: CG iterations per increment
    "cg": 10.0,
    # elastic, coupled slip-stick (friction with beta != 0): passes per increment (load
    # sub-steps included), CG and slip-solver applications per pass
    "ec_passes": 4.3,
    "ec_cg": 3.9,
    "ec_slip": 4.15,
    # elastic, uncoupled tangential increments: slip applications of the whole tangential
    # path = exp(t0) n^a steps^b (|Q| / mu W)^c, n = sqrt(nx ny); CG iterations per increment
    "t_slip0": 0.439,
    "t_slip_lnn": 1.12,
    "t_slip_lnsteps": 0.405,
    "t_slip_lnq": 0.746,
    "t_cg": 1.0,
    # elastic, sliding or rolling increments with friction: CG per increment, slip per
    # increment / n^0.7
    "m_cg": 14.8,
    "m_slip": 1.8,
    # elastic, steady rolling states solved directly: tangential applications per steady
    # state = s_slip n^s_slip_lnn (the preconditioned Newton-GMRES of solver.surface.steady;
    # measured on creep curves of 1-25 states, 16-64 cells across, 2026-11-27: 32, 49, 71 per
    # state at n = 20, 40, 80); CG iterations as a static increment
    "s_slip": 5.8,
    "s_slip_lnn": 0.57,
    # plasticity iterations per increment (load sub-steps included): exp(p0 + p_lnr
    # ln(p_max / sigma_ref) + p_mu mu + p_lnsteps ln(increments) + p_slide, p_roll, p_tang x
    # the share of such increments (p_slide with friction, p_slide_dry without) + p_repeat x
    # the share of repeated cycles, in place, of a body without a back stress), at
    # least 1; sigma_ref the flow stress at REFERENCE_PLASTIC_STRAIN.  Fitted on 86 cases:
    # the shipped campaigns' (Swift, perfect, linear; normal, tangential, cyclic, sliding,
    # rolling) and a frictionless sweep of the four shipped laws at p_H = 2-6 sigma_Y0, 5 and
    # 20 steps, 24^3 (2026-11-26): measured / predicted 0.48-1.84
    "p0": 1.541,
    "p_lnr": 1.287,
    "p_mu": -0.254,
    "p_lnsteps": -0.369,
    "p_slide": 1.538,
    "p_slide_dry": 0.734,  # frictionless sliding (one case of shakedown_frictionless)
    "p_roll": 0.583,
    "p_tang": 1.866,
    "p_repeat": -1.952,
    # x the rolling creep ratio (Kalker's linear creep force / mu W; tractive_rolling)
    "p_creep": 0.759,
    # sliding with mu >= overload_mu and mu sqrt(3) p_max / sigma_Y0 >= overload (shakedown_map
    # at mu = 0.5; a lower bound: such cases can take 30 x longer still)
    "overload_mu": 0.5,
    "overload": 1.5,
    "creep_full": 1.5,  # the creep ratio's effect stops growing here ...
    "creep_saturated": 2.85,  # ... and past this (xi > 2 pi mu p0 / (G C11)) the loop saturates
    # per plasticity iteration: CG (frictionless); coupled slip-stick passes, CG and slip per
    # pass; uncoupled slip-stick CG and slip applications
    "p_cg": 6.7,
    "pc_passes": 4.2,
    "pc_cg": 4.3,
    "pc_slip": 3.5,
    "pu_cg": 4.6,
    "pu_slip": 11.2,
}


@dataclass(frozen=True)
class Work:
    """The predicted work of a case (:func:`count`).

    Attributes
    ----------
    surface_cells : int
        Padded surface cells ``Ns = 4 nx ny`` an iteration works on (of the window that
        follows a moving contact, when there is one).
    volume_cells : int
        Padded cells ``Mv = 4 bx by 2 nz`` of the plastic box a plasticity iteration works on
        (0 without plasticity).
    steps : int
        Load increments.
    normal, slip, coupling : float
        CG iterations, slip-solver applications and slip-stick passes (whole case).
    plastic : float
        Plasticity iterations, summed over the plastic bodies.
    stress : bool
        Subsurface stress asked for an elastic case (one volume evaluation per increment).
    built_surface_cells, built_volume_cells : int
        Padded cells of every surface and volume operator built (whole window and moving
        window): their influence coefficients and spectra.
    theorem : float
        Seconds of the shakedown theorems' programs (``solver.method = "static_shakedown"``,
        :func:`solver.drive.theorem.theorem_cost`: measured, not counted; no other work).
    """

    surface_cells: int
    volume_cells: int
    steps: int
    normal: float
    slip: float
    coupling: float
    plastic: float
    stress: bool = False
    built_surface_cells: int = 0
    built_volume_cells: int = 0
    theorem: float = 0.0

    def values(self) -> list:
        """The fields' values in :data:`WORK_FIELDS` order (``Work(*values)`` is this work)."""
        return [getattr(self, name) for name in WORK_FIELDS]

    @property
    def surface_units(self) -> float:
        """``Ns log2 Ns``: the work of one surface-operator application."""
        return _nlogn(self.surface_cells)

    @property
    def volume_units(self) -> float:
        """``Mv log2 Mv``: the volume work of one plasticity iteration (0 without)."""
        return _nlogn(self.volume_cells)


#: :class:`Work`'s fields, in order.
WORK_FIELDS = tuple(item.name for item in fields(Work))


def _nlogn(n: float) -> float:
    return n * math.log2(n) if n > 1 else 0.0


# -- counting (pure) -----------------------------------------------------------------------------
def features(case: solver.Case) -> dict:
    """What :func:`count` depends on, as plain numbers (also the benchmark's records).

    Parameters
    ----------
    case : solver.Case
        A validated case.

    Returns
    -------
    dict
        Grid (``nx``, ``ny``, ``nz``, plastic ``box``, the ``window`` (nx, ny) that follows a
        moving contact or None), ``steps`` and their kinds
        (``tangential_steps``, ``sliding_steps``, ``rolling_steps``, ``steady_steps``: steady
        rolling states solved directly, ``cycles``,
        ``load_ratio``: the largest ``|Q| / (mu W)`` of the path, ``creep_ratio``: the
        largest Kalker linear creep force over ``mu W`` of a rolling stage), friction
        (``mu``, ``beta``,
        ``slip_stick``, ``coupled``, ``substeps``: the load sub-steps of a coupled case),
        plasticity (``plastic_bodies``, ``pmax_over_yield``: the reference peak pressure over
        the initial yield stress, ``pmax_over_flow``: over the flow stress at
        :data:`REFERENCE_PLASTIC_STRAIN`, ``repeated_share``: the share of repeated cycles of
        bodies without a back stress) and ``stress``.
    """
    grid = case.grid
    plastic = case.plastic_body is not None
    ratio = flow_ratio = 0.0
    shakes_down = False  # repeated cycles of bodies without a back stress
    if plastic:
        laws = [(case.body1 if b == 1 else case.body2).hardening for b in case.plastic_bodies]
        shakes_down = not any(law.kinematic for law in laws)
        try:
            pressure = case.reference.max_pressure
            ratio = pressure / min(law.initial_yield_stress for law in laws)
            flow = min(float(law.flow_stress(REFERENCE_PLASTIC_STRAIN)) for law in laws)
            flow_ratio = pressure / flow
        except Exception:  # noqa: BLE001 - a profile or a law without one: a middle regime
            ratio = flow_ratio = 4.0
    still = not any(stage.motion for stage in case.stages)  # passes are not repeated cycles
    repeated = (case.cycles - 1) / case.cycles if shakes_down and still and case.cycles > 1 else 0.0
    box = case.plastic_box
    if plastic:
        bx, by, bz = box.shape if box is not None else (grid.nx, grid.ny, grid.nz)
    else:
        bx = by = bz = 0
    tangential = sliding = rolling = steady = 0
    load_ratio = 0.0  # largest |Q| / (mu W) of a tangential stage
    creep_ratio = 0.0  # largest Kalker creep force G a^2 C11 |xi| / (mu W) of a rolling stage
    for stage in case.stages:
        if stage.creepage is not None and stage.normal_force > 0 and case.friction_coefficient:
            try:
                shear = case.pair.rolling_shear_modulus
                force = shear * case.reference.radius**2 * 4.1 * math.hypot(*stage.creepage)
                creep = force / (case.friction_coefficient * stage.normal_force)
                creep_ratio = max(creep_ratio, creep)
            except Exception:  # noqa: BLE001 - no reference radius: no creep measure
                pass
        q = math.hypot(*stage.tangential_force)
        if q and stage.normal_force > 0 and case.friction_coefficient > 0:
            load_ratio = max(load_ratio, q / (case.friction_coefficient * stage.normal_force))
        if stage.motion == "slide":
            sliding += stage.steps
        elif stage.motion == "steady":
            steady += stage.steps
        elif stage.motion:
            rolling += stage.steps
        elif any(stage.tangential_force) or stage.creepage is not None:
            tangential += stage.steps
    slip_stick = case.needs_slip_stick
    beta = float(case.pair.dundurs_beta)
    coupled = slip_stick and beta != 0.0 and not case.solver.goodman
    window = case.moving_window if case.moving else None
    return {
        "window": list(window) if window is not None else None,
        "nx": int(grid.nx),
        "ny": int(grid.ny),
        "nz": int(grid.nz),
        "box": [int(bx), int(by), int(bz)],
        "steps": int(case.total_steps),
        "tangential_steps": tangential,
        "sliding_steps": sliding,
        "rolling_steps": rolling,
        "steady_steps": steady,
        "load_ratio": min(load_ratio, 1.0),
        "creep_ratio": creep_ratio,
        "plastic_max_iterations": int(case.solver.plastic_max_iterations),
        "cycles": int(case.cycles),
        "mu": float(case.friction_coefficient),
        "beta": beta,
        "slip_stick": slip_stick,
        "coupled": coupled,
        "substeps": _substeps(case) if coupled else 0,
        "plastic_bodies": len(case.plastic_bodies),
        "pmax_over_yield": float(ratio),
        "pmax_over_flow": float(flow_ratio),
        "repeated_share": repeated,
        "stress": "stress" in case.fields,
    }


def _substeps(case: solver.Case) -> int:
    """Load sub-steps a coupled case adds (:mod:`solver.case.substeps`), as its solve does."""
    try:
        smallest = substep_floor(case)
    except Exception:  # noqa: BLE001 - no reference: the first sub-step's default
        smallest = 0.0
    return substep_count(case, smallest)


def count_features(f: dict, counts: dict | None = None) -> Work:
    """:func:`count` from :func:`features` (pure; ``counts`` overrides :data:`COUNTS`)."""
    k = {**COUNTS, **(counts or {})}
    steps = max(f["steps"] + f["substeps"], 1)  # increments solved
    n = math.sqrt(f["nx"] * f["ny"])
    friction = f["slip_stick"]
    moving = f["sliding_steps"] + f["rolling_steps"]
    steady = f.get("steady_steps", 0)
    normal = slip = coupling = plastic = 0.0
    if f["plastic_bodies"]:
        exponent = (
            k["p0"]
            + k["p_lnr"] * math.log(max(f["pmax_over_flow"], 1.0))
            + k["p_mu"] * (f["mu"] if friction else 0.0)
            + k["p_lnsteps"] * math.log(steps)
            + k["p_slide" if friction else "p_slide_dry"] * f["sliding_steps"] / steps
            + k["p_roll"] * f["rolling_steps"] / steps
            + k["p_tang"] * f["tangential_steps"] / steps
            + k["p_repeat"] * f["repeated_share"]
            + k["p_creep"] * min(f.get("creep_ratio", 0.0), k["creep_full"])
        )
        plastic = steps * max(math.exp(exponent), 1.0)
        overload = f["mu"] * math.sqrt(3.0) * f["pmax_over_yield"] if friction else 0.0
        if f["sliding_steps"] and f["mu"] >= k["overload_mu"] and overload >= k["overload"]:
            # sliding shear mu p0 past the shear yield stress (validate warns: the loop may
            # not converge): the loop runs to about half its limit on every sliding increment
            plastic += 0.5 * f["sliding_steps"] * f.get("plastic_max_iterations", 100)
        if f.get("creep_ratio", 0.0) >= k["creep_saturated"]:  # rolling in full slip: every
            # rolling increment runs the plasticity loop to its limit (tractive_rolling, 6e-3)
            plastic += f["rolling_steps"] * f.get("plastic_max_iterations", 100)
        if friction and f["coupled"]:
            coupling = k["pc_passes"] * plastic
            normal, slip = k["pc_cg"] * coupling, k["pc_slip"] * coupling
        elif friction:
            coupling = plastic
            normal, slip = k["pu_cg"] * plastic, k["pu_slip"] * plastic
        else:
            normal = k["p_cg"] * plastic
        plastic *= f["plastic_bodies"]
    elif friction and f["coupled"]:
        coupling = k["ec_passes"] * steps
        normal, slip = k["ec_cg"] * coupling, k["ec_slip"] * coupling
    elif friction:
        tangential = f["tangential_steps"]
        still = max(steps - tangential - moving - steady, 0)
        normal = k["cg"] * still + k["t_cg"] * tangential + k["m_cg"] * moving
        if tangential:
            slip = math.exp(
                k["t_slip0"]
                + k["t_slip_lnn"] * math.log(n)
                + k["t_slip_lnsteps"] * math.log(tangential)
                + k["t_slip_lnq"] * math.log(max(f["load_ratio"], 0.05))
            )
        slip += k["m_slip"] * moving * n**0.7
        coupling = tangential + moving
    else:
        normal = k["cg"] * steps
    if steady and not f["plastic_bodies"]:  # steady states solved directly (GMRES-Newton)
        slip += k["s_slip"] * steady * n ** k["s_slip_lnn"]
        if not f["coupled"]:
            normal += k["cg"] * steady
    bx, by, bz = f["box"]
    surface_cells = 4 * f["nx"] * f["ny"]
    volume_cells = 8 * bx * by * bz if f["plastic_bodies"] else 0
    built_surface, built_volume = surface_cells, volume_cells * max(f["plastic_bodies"], 1)
    if f.get("window"):  # iterations on the window that follows the contact
        wx, wy = f["window"]
        surface_cells = 4 * wx * wy
        built_surface += surface_cells
        if f["plastic_bodies"]:  # its volume operator is built too; the plasticity loop
            built_volume += 8 * wx * wy * f["nz"]  # works on the box (measured: 1.8 x less)
    return Work(
        built_surface_cells=built_surface,
        built_volume_cells=built_volume,
        surface_cells=surface_cells,
        volume_cells=volume_cells,
        steps=f["steps"],
        normal=normal,
        slip=slip,
        coupling=coupling,
        plastic=plastic,
        stress=bool(f["stress"]) and not f["plastic_bodies"],
    )


def count(case: solver.Case) -> Work:
    """The predicted work of a case: solves, iterations, grid sizes (pure, no timing).

    Parameters
    ----------
    case : solver.Case
        A validated case.

    Returns
    -------
    Work
        Predicted iteration counts and the padded grid sizes they act on.
    """
    if case.solver.method == "static_shakedown":
        from solver.drive.theorem import theorem_cost

        return Work(0, 0, 1, 0.0, 0.0, 0.0, 0.0, theorem=theorem_cost(case)[0])
    return count_features(features(case))


# -- unit costs ----------------------------------------------------------------------------------
@dataclass(frozen=True)
class Calibration:
    """Seconds per unit of work on one machine (CPU time of one core).

    Attributes
    ----------
    case : float
        Seconds per case (set-up, bookkeeping).
    build : float
        Seconds per padded surface cell ``Ns`` (influence coefficients and their spectra).
    normal, slip : float
        Seconds per CG iteration and per slip-solver application, per ``Ns log2 Ns``.
    passes : float
        Seconds per slip-stick pass beyond its iterations.
    iteration : float
        Seconds per CG iteration or slip-solver application beyond its FFT work (Python and
        array bookkeeping: what small grids, such as a moving window, spend).
    plastic : float
        Seconds per plasticity iteration beyond its volume work (return mapping, bookkeeping).
    volume : float
        Seconds per plasticity iteration per ``Mv log2 Mv`` (volume convolutions).
    volume_build : float
        Seconds per padded box cell ``Mv`` (the eigenstrain kernels' spectra).
    machine : str
        :func:`.wisdom.machine_key` of the machine measured ("reference": built in).
    seconds : float
        CPU seconds the calibration took (all its processes, about).
    created : str
        When it was measured (UTC).
    """

    case: float
    build: float
    normal: float
    slip: float
    passes: float
    iteration: float
    plastic: float
    volume: float
    volume_build: float
    machine: str = "reference"
    seconds: float = 0.0
    created: str = ""

    def scaled(self, overhead: float, surface: float, volume: float, **extra) -> Calibration:
        """These unit costs with the three families scaled (Python overheads, surface, volume)."""
        return replace(
            self,
            case=self.case * overhead,
            passes=self.passes * overhead,
            iteration=self.iteration * overhead,
            plastic=self.plastic * overhead,
            build=self.build * surface,
            normal=self.normal * surface,
            slip=self.slip * surface,
            volume=self.volume * volume,
            volume_build=self.volume_build * volume,
            **extra,
        )


#: Unit costs fitted on the development machine (2 shared cores, 2026-11-26) to the CPU time
#: of the benchmark's cases given their measured iterations: the unit of
#: :func:`reference_seconds` (machine-independent work units, e.g. ``CampaignCase.cost``) and
#: the shape :func:`measure` scales per family.
REFERENCE = Calibration(
    case=2.0e-3,
    build=132e-9,
    normal=2.15e-9,
    slip=2.39e-9,
    passes=1.15e-3,
    iteration=50e-6,
    plastic=8.7e-3,
    volume=2.73e-9,
    volume_build=2.0e-6,
)


#: Per-unit FFT work grows past the caches: x (cells / CACHE_CELLS)^CACHE_EXPONENT beyond
#: (2026-11-26: 768^2 Hertz surfaces 1.5 x, 96^3 plastic boxes 2 x the 128^2 and 24^3 rates).
CACHE_EXPONENT = 0.15
CACHE_CELLS = {"surface": 4 * 128 * 128, "volume": 8 * 24 * 24 * 24}


def _cache(cells: float, kind: str) -> float:
    """The cache factor of an operator on ``cells`` padded cells (1 below :data:`CACHE_CELLS`)."""
    return max(1.0, cells / CACHE_CELLS[kind]) ** CACHE_EXPONENT


def families(work: Work, units: Calibration) -> tuple[float, float, float]:
    """Seconds of ``work`` by family (Python overheads, surface FFT work, volume FFT work)."""
    overhead = units.case + units.passes * work.coupling + units.plastic * work.plastic
    overhead += work.theorem
    overhead += units.iteration * (work.normal + work.slip)
    surface = units.build * work.built_surface_cells + work.surface_units * _cache(
        work.surface_cells, "surface"
    ) * (units.normal * work.normal + units.slip * work.slip)
    volume = units.volume_build * work.built_volume_cells
    volume += units.volume * work.plastic * work.volume_units * _cache(work.volume_cells, "volume")
    if work.stress:  # the elastic stress of every increment: a volume convolution of 2 nz layers
        volume += units.volume * work.steps * _nlogn(2 * work.surface_cells)
    return overhead, surface, volume


def seconds(work: Work, calibration: Calibration = REFERENCE) -> float:
    """Estimated CPU seconds of a case from its work and the unit costs.

    Parameters
    ----------
    work : Work
        :func:`count` of the case.
    calibration : Calibration
        Unit costs (default :data:`REFERENCE`).

    Returns
    -------
    float
        Seconds (one core).
    """
    return sum(families(work, calibration))


def case_seconds(case: solver.Case, calibration: Calibration = REFERENCE) -> float:
    """Estimated seconds of one case on this machine (:func:`count`, :func:`seconds`)."""
    return seconds(count(case), calibration)


def reference_seconds(case: solver.Case) -> float:
    """Machine-independent work units of a case: its seconds at :data:`REFERENCE` unit costs."""
    return seconds(count(case), REFERENCE)


def campaign_seconds(
    case_seconds: Iterable[float], ranks: int, root_computes: bool = True
) -> float:
    """Seconds of a campaign on ``ranks`` ranks: list scheduling, costliest first.

    Each case goes, costliest first, to the rank that is free first (the least loaded), as
    :func:`study.run.driver.run_campaign` hands them out; rank 0 computes too unless
    ``root_computes`` is False (then it only dispatches, when there are other ranks).

    Parameters
    ----------
    case_seconds : iterable of float
        Estimated seconds of every case.
    ranks : int
        MPI ranks (>= 1).
    root_computes : bool
        Rank 0 computes cases beside its dispatcher.

    Returns
    -------
    float
        The largest rank load (s): the campaign's estimated wall time.
    """
    workers = max(int(ranks), 1)
    if not root_computes and workers > 1:
        workers -= 1
    loads = [0.0] * workers
    heapq.heapify(loads)
    for value in sorted(case_seconds, reverse=True):
        heapq.heappush(loads, heapq.heappop(loads) + value)
    return max(loads)
