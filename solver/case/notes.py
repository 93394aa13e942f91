"""Every note a case carries, and the plastic regimes it refuses: one module for all of them.

A note (:attr:`solver.Case.warnings`) says what a case is built with but should be read with
care: Johnson's plastic index past contained plasticity, a window narrower than the plastic
zone, perfectly plastic layers too thick, a sliding shear past what the body can carry, a
moving case solved on the whole track.  :func:`check_plastic_scene` and the regime checks
refuse what the small-strain model cannot honour.
"""

from __future__ import annotations

import math
from typing import Any

from ..bodies.materials import Body, Pair
from ..keys import (
    LARGE_CONTACT_RADIUS,
    LARGE_RADIUS,
    MAX_AUTO_HALF_WIDTH,
    MAX_PERIODIC_DEPTH,
    MAX_ROLLING_STEP,
    MAX_THEOREM_FRICTION,
    MIN_CELLS_ACROSS,
    PLASTIC_WIDTH_MARGIN,
)
from .grid import GridSpec, require_yield_cells
from .reading import fail
from .sizing import slope_index

#: Equivalent plastic strain up to which the small-strain theory is trusted (the reference
#: paper stops at 2 %); also the strain of the reference flow stress of :func:`plastic_index`.
SMALL_STRAIN_LIMIT = 0.02


#: Johnson's index E* a / (R sigma_Y) of a fully plastic indentation (Johnson 1985, §6.4:
#: ~30 for a sphere; the mean pressure has reached ~3 sigma_Y): refused, small strain is void.
FULLY_PLASTIC_INDEX = 30.0


#: Johnson's index past which the case gets a note: measured here, a perfectly plastic body
#: (16^3, 10 steps) converged at every step at 9.4 (p_H = 6 sigma_Y, e_p 2 %) and no longer at
#: 12.6 (8 sigma_Y, e_p 6 %); the plastic zone outgrows the 1.5 a_H window there as well.
UNCONTAINED_PLASTIC_INDEX = 10.0


#: Thickest layer (dz / dx) under a perfectly plastic body without a note
#: (:func:`layer_note`).
MAX_PERFECT_LAYER = 0.62


def check_periodic_scene(
    body1: Body, body2: Body, stages, friction_coefficient: float, grid: GridSpec
) -> None:
    """Refuse what periodic mode (``grid.periodic``) does not solve in this release.

    Solved: flat bodies with periodic heights (a roughness, a height map used as one period),
    body 2 elastic or elastic-plastic (its volume grid the whole period, laterally periodic),
    body 1 rigid or elastic, under normal force, with friction and tangential forces (the
    normal-tangential coupling of dissimilar bodies included), and slid (body 1's heights
    shifted, wrapping around the period: :func:`periodic_slide_note`).  Refused, naming the
    key: a radius or profile (not periodic), an elastic-plastic body 1, a volume grid without
    a plastic body, a plastic box narrower than the period, and rolling stages.
    """
    if not grid.periodic:
        return
    for name, body in (("body1", body1), ("body2", body2)):
        if math.isfinite(body.radius_x) or math.isfinite(body.radius_y) or body.profile:
            fail(
                f"{name}.radius" if body.profile is None else f"{name}.profile",
                "a periodic domain is one period of a nominally flat surface: give the body "
                'radius = "inf" and no profile (a rough sphere: leave grid.periodic out)',
            )
    if body1.behaviour == "elastic-plastic":
        fail(
            "body1.behaviour",
            "under a periodic surface the elastic-plastic body is body 2 (body 1 rigid or "
            "elastic): make body 1 elastic and body 2 elastic-plastic",
        )
    plastic = body2.behaviour == "elastic-plastic"
    if grid.nz and not plastic:
        fail(
            "grid.n",
            "a periodic case has a volume grid only under an elastic-plastic body 2: give "
            "grid.n = [nx, ny]",
        )
    if plastic and not grid.nz:
        fail("grid.n", "an elastic-plastic body needs a volume grid: give grid.n = [nx, ny, nz]")
    if grid.plastic_half_width is not None:
        fail("grid.plastic_half_width", "a periodic case's plastic box is the whole period")
    motions = sorted({stage.motion for stage in stages if stage.motion and stage.motion != "slide"})
    if motions:
        line = ' (steady rolling of a line contact: grid.periodic = "y")' * ("steady" in motions)
        fail(
            "load.path",
            "a periodic case is pressed (with friction and tangential forces) or slid, not "
            f"rolled: remove {' and '.join(motions)}{line}",
        )


def check_line_scene(body1: Body, body2: Body, stages, paths, grid: GridSpec) -> None:
    """Refuse what a line contact (``grid.periodic = "y"``) does not solve in this release.

    Solved: elastic (or one rigid) bodies uniform along y, a cylinder along y (``radius_x``),
    under normal force, tangential forces and steady rolling at creepage.  Refused, naming the
    key: a radius along y or a profile (not uniform along y), height maps and roughness, an
    elastic-plastic body, sliding or transient rolling stages, and spin (its slip grows along
    y: not periodic).  A volume grid holds the plane-strain stresses
    (:mod:`solver.volume.plane_strain`; depth in units of the strip's half-width).
    """
    if not grid.periodic_y:
        return
    for name, body in (("body1", body1), ("body2", body2)):
        if math.isfinite(body.radius_y) or body.profile is not None:
            fail(
                f"{name}.radius_y" if body.profile is None else f"{name}.profile",
                'with grid.periodic = "y" the bodies are uniform along y: a cylinder along y '
                'has radius_x only (radius_y = "inf"), and no profile',
            )
        if body.surface is not None or body.roughness is not None:
            fail(
                f"{name}.surface" if body.surface is not None else f"{name}.roughness",
                'heights are not built for a line contact (grid.periodic = "y") in this '
                "release: leave them out",
            )
        if body.behaviour == "elastic-plastic":
            fail(
                f"{name}.behaviour",
                'a line contact (grid.periodic = "y") is built for elastic bodies in this '
                "release: make the body elastic",
            )
    if not math.isfinite(body1.radius_x) and not math.isfinite(body2.radius_x):
        fail("body1.radius_x", "a line contact needs a cylinder: give body 1 radius_x (m)")
    for stage, path in zip(stages, paths, strict=True):
        if stage.motion in ("slide", "roll"):
            fail(
                path,
                'a line contact (grid.periodic = "y") is pressed, sheared or rolled steadily '
                "(steady = true) in this release: remove slide and roll",
            )
        if stage.spin:
            fail(
                f"{path}.spin",
                "spin makes a slip that grows along y, which a line contact (periodic along y) "
                "cannot have: remove spin",
            )


def check_steady_scene(stages, plastic: Body | None, grid: GridSpec, order_given: bool) -> None:
    """Refuse what a steady rolling stage (``steady = true``) does not solve in this release.

    Refused, naming the key: a steady stage with an elastic-plastic body, on a doubly periodic
    grid (a line contact, periodic along y only, is solved), and ``solver.steady_order``
    (``order_given``) without a steady stage.
    """
    steady = any(stage.motion == "steady" for stage in stages)
    if steady and plastic is not None:
        fail(
            "load.path",
            "a steady rolling stage (steady = true) is built for elastic bodies (no plastic "
            "history has a steady state here): roll the elastic-plastic body with roll = "
            "[dx, dy] instead",
        )
    if not steady and order_given:
        fail("solver.steady_order", "only a steady stage (steady = true) takes it: leave it out")
    if steady and grid.periodic:
        fail(
            "grid.periodic",
            "a steady rolling stage needs a contact bounded along x: not periodic (a line "
            'contact: grid.periodic = "y")',
        )


def check_periodic_load(body: Body, mean_pressure: float) -> None:
    """Refuse a mean pressure that yields a periodic elastic-plastic body at every depth.

    The mean pressure's own stress, uniaxial strain (periodic displacements), has the von
    Mises stress ``p (1 - 2 nu) / (1 - nu)`` at every depth: at the yield stress the whole
    half-space yields and no box holds the plastic zone.
    """
    sigma, nu = body.hardening.initial_yield_stress, body.nu
    uniform = mean_pressure * (1.0 - 2.0 * nu) / (1.0 - nu)
    if uniform >= sigma:
        fail(
            "load.path",
            f"the mean pressure {mean_pressure:.4g} Pa yields the whole half-space under a "
            f"periodic surface (its uniaxial strain has the von Mises stress p (1 - 2 nu) / "
            f"(1 - nu) = {uniform:.4g} Pa >= sigma_Y0 = {sigma:.4g} Pa, at every depth): lower "
            f"the load below a mean pressure of {sigma * (1 - nu) / (1 - 2 * nu):.4g} Pa",
        )


def check_periodic_volume(depth: float, nz: int, region, period: float, path: str) -> str | None:
    """Refuse a periodic elastic-plastic volume grid that cannot hold or resolve the zone.

    ``depth`` (m) of the volume grid, ``region`` the elastic yield region
    (:func:`~solver.case.sizing.periodic_yield_region`, m), ``period`` the shorter side (m).
    The region must end within :data:`MAX_PERIODIC_DEPTH` of the period, the box reach the
    depth where yield starts, and its layers resolve the region
    (:func:`~solver.case.grid.require_yield_cells`).  Returns a note when the box ends above
    the region's bottom (the plastic zone will likely reach it: truncated), else None.
    """
    top, bottom = region.top, region.bottom
    if bottom == 0.0:
        return None
    told = f"the elastic yield region spans {top:.3g}-{bottom:.3g} m"
    if depth < top:
        fail(
            path,
            f"the box ends at {depth:.4g} m, above the depth {top:.3g} m where plasticity "
            f"starts ({told}): give grid.depth >= {bottom:.3g} m, or leave it out",
        )
    if bottom >= MAX_PERIODIC_DEPTH * period:  # it reaches the trial's floor
        fail(
            "load.path",
            f"{told}, down to {MAX_PERIODIC_DEPTH:g} of the period ({period:.4g} m), which "
            "the periodic kernels cannot hold: lower the load or use a larger period",
        )
    cell = depth / nz
    thick = f"layers {cell:.3g} m thick (depth {depth:.4g} m over nz = {nz})"
    require_yield_cells(path, thick, told, top, bottom, depth, cell)
    if depth < bottom:
        return (
            f"the box ends at {depth:.4g} m, above the bottom of the elastic yield region "
            f"({told}): the plastic zone will likely reach it and the case end truncated; give "
            f"grid.depth >= {bottom:.3g} m, or leave it out"
        )
    return None


def check_plastic_scene(body1: Body, body2: Body, stages, grid: GridSpec) -> None:
    """Refuse the elastic-plastic scenes this release cannot solve (no silent elastic answer).

    Solved: one elastic-plastic body against a rigid or elastic one (frictionless: the
    plasticity loop around the normal step; with friction or a tangential load: the four
    loops; an elastic-plastic body 1 is solved with the bodies relabelled, :meth:`Case.swapped`),
    two elastic-plastic bodies (a plastic strain field in each: different bodies, or
    identical ones loaded tangentially), and the symmetric pair (eq. 2) under normal load with
    any friction.
    """
    plastic1 = body1.behaviour == "elastic-plastic"
    plastic2 = body2.behaviour == "elastic-plastic"
    if not (plastic1 or plastic2):
        return
    profiled = body1.profile is not None or body2.profile is not None
    if profiled and (plastic1 or not plastic2):
        fail(
            "body1.behaviour",
            "with a profile, only body 2 may be elastic-plastic in this release (its box is "
            "sized from the computed elastic yield region in body 2); make body 1 rigid or "
            "elastic",
        )
    if profiled and any(b.surface or b.roughness for b in (body1, body2)):
        fail(
            "body2.behaviour",
            "an elastic-plastic case with a profile takes no height map or roughness yet: its "
            "box is sized from the profile's elastic stress; drop one of them",
        )
    if (
        plastic1
        and not plastic2
        and (body1.surface or body1.roughness or body2.surface or body2.roughness)
    ):
        fail(
            "body1.behaviour",
            "an elastic-plastic body 1 against an elastic or rigid body 2 is solved with the "
            "bodies relabelled, which mirrors point heights: not built yet; make the "
            "elastic-plastic body body 2",
        )
    if Pair(body1, body2).geometry.reference_kind is None and not grid.periodic:
        fail(
            "body1.radius",
            "an elastic-plastic case needs a radius (a quadric shape under the heights): the "
            "volume depth and the plastic box are sized from the Hertz stress of the smooth "
            "shape",
        )
    if not grid.nz:
        fail(
            "grid.n",
            "an elastic-plastic body needs a volume grid: give grid.n = [nx, ny, nz] "
            "(e.g. [64, 64, 64])",
        )


def plastic_index(body: Body, max_pressure: float) -> float:
    """Johnson's index E* a / (R sigma_Y) of an elastic-plastic body at a Hertz pressure.

    Hertz's a / R = pi p_0 / (2 E*) makes it ``pi p_0 / (2 sigma_Y)``; sigma_Y is the flow
    stress at :data:`SMALL_STRAIN_LIMIT` (the hardening the small-strain range can use).
    Johnson (1985, §6.4): first yield at ~2.5 (p_0 = 1.6 sigma_Y), a fully plastic
    indentation at ~30.
    """
    sigma = float(body.hardening.flow_stress(SMALL_STRAIN_LIMIT))
    return math.pi * max_pressure / (2.0 * sigma)


def profile_regime(body: Body, pair: Pair, radius: float, path: str, name: str) -> str | None:
    """:func:`plastic_regime` for a profile: Johnson's index from the slope at the contact edge."""
    sigma = float(body.hardening.flow_stress(SMALL_STRAIN_LIMIT))
    index = slope_index(pair, radius, sigma)
    told = (
        f"Johnson's index E* f'(a)/sigma_Y = {index:.3g} for {name} (the gap's slope f'(a) at "
        f"Sneddon's contact radius a = {radius:.4g} m, sigma_Y = {sigma:.4g} Pa at e_p = "
        f"{SMALL_STRAIN_LIMIT:g})"
    )
    return _regime_note(index, told, path, "lower the load or blunt the profile")


def plastic_regime(body: Body, max_pressure: float, path: str, name: str) -> str | None:
    """Refuse a fully plastic indentation; a note (returned) past the contained regime."""
    index = plastic_index(body, max_pressure)
    sigma = float(body.hardening.flow_stress(SMALL_STRAIN_LIMIT))
    told = (
        f"Johnson's index E* a/(R sigma_Y) = pi p_H/(2 sigma_Y) = {index:.3g} for {name} "
        f"(p_H = {max_pressure:.4g} Pa, sigma_Y = {sigma:.4g} Pa at e_p = "
        f"{SMALL_STRAIN_LIMIT:g})"
    )
    lower = f"lower the load to p_H < {FULLY_PLASTIC_INDEX * 2 * sigma / math.pi:.4g} Pa"
    return _regime_note(index, told, path, lower)


def _regime_note(index: float, told: str, path: str, lower: str) -> str | None:
    """Refuse a fully plastic index; a note past the contained regime; None below."""
    if index >= FULLY_PLASTIC_INDEX:
        fail(
            path,
            f"{told} reaches {FULLY_PLASTIC_INDEX:g}, a fully plastic indentation (Johnson 1985, "
            f"§6.4): plastic strains of tens of %, beyond the small-strain theory; {lower}",
        )
    if index > UNCONTAINED_PLASTIC_INDEX:
        return (
            f"{told} is past {UNCONTAINED_PLASTIC_INDEX:g}: the plastic zone is no longer "
            "contained (mean pressure near 3 sigma_Y), plastic strains reach several %, the "
            "edge of the small-strain theory; the plasticity loop may not converge at every "
            "step (told per step) and the zone may outgrow the box (told)"
        )
    return None


def layer_note(case) -> str | None:
    """A note for a perfectly plastic body on layers thicker than :data:`MAX_PERFECT_LAYER`.

    The cell-centre residual stress of a cell-wise eigenstrain is not negative definite:
    checkerboard patterns have a negative Rayleigh quotient (-0.20 for xx - zz alternating
    in x and z on cubic cells, +0.24 with layers half a cell thick; -0.20 for xx - yy
    alternating in x and y at any thickness), which nothing but hardening holds back.  On
    cubic cells a perfectly plastic pass stalled and strayed (ep_max 0.0088 against 0.0045
    at 16 cells across, 2026-11-26); layers of 0.62 cell and thinner gave 0.0045 every time.
    Under a periodic rough surface any hardening law gets the note: its asperity contacts
    load the top layers to their hardness, where weak hardening holds the patterns back too
    little (linear, H = E / 21, 128^2 on cubic cells: no convergence in 100 iterations at 0.5
    GPa and e_p,max 0.032; layers half a cell thick: 22 iterations a step and 0.017).
    """
    body = case.plastic_body
    if body is None or case.volume_grid is None:
        return None
    hardening = body.hardening
    periodic = case.grid.periodic
    if not periodic and (hardening.law != "perfect" or hardening.kinematic):
        return None
    ratio = case.volume_grid.dz / min(case.surface_grid.dx, case.surface_grid.dy)
    if ratio <= MAX_PERFECT_LAYER:
        return None
    nz = math.ceil(case.grid.nz * ratio / MAX_PERFECT_LAYER)
    body = (
        "the elastic-plastic body of a periodic rough surface"
        if periodic
        else ("a perfectly plastic body")
    )
    return (
        f"layers {ratio:.2g} of a cell thick (dz / dx) under {body}: on "
        f"such cells its plasticity loop can stall and its plastic strain stray (a cell-wise "
        f"eigenstrain's checkerboard patterns can release elastic energy there); give "
        f"grid.n = [nx, ny, nz] with nz >= {nz} (layers <= {MAX_PERFECT_LAYER:g} cell)"
    )


def surface_shear_note(case) -> str | None:
    """A note when a slide's shear mu p_0 exceeds what the plastic body can carry.

    A body whose flow stress is bounded (:attr:`Hardening.shear_limit`) cannot carry a
    surface shear traction above that limit: no stress field in equilibrium with it stays
    inside the yield surface, so the top layer's plastic strain is set by the layers (it
    grows as they thin) and the plasticity loop may not converge.  Said at Hertz's peak
    pressure of the largest load (plastic flow flattens the pressure, which may bring the
    shear back under the limit).
    """
    body, reference = case.plastic_body, case.reference
    mu = case.friction_coefficient
    if body is None or reference is None or not mu or case.friction.follows_yield:
        return None  # "yield" caps the shear at the top layer's yield stress
    if not any(stage.motion == "slide" for stage in case.stages):
        return None
    limit = body.hardening.shear_limit
    cap = case.friction.stress_cap
    ratio = min(mu * reference.max_pressure, math.inf if cap is None else cap) / limit
    if ratio <= 1.0 + 1e-9:  # at the limit to rounding (mu = 0.5, p_0 = 2 k) is not past it
        return None
    return (
        f"the sliding shear mu p_0 = {ratio:.3g} x {limit / 1e6:.4g} MPa, the largest "
        f"shear stress the elastic-plastic body can carry (sigma_Y / sqrt 3 without "
        f"hardening): where the pressure stays that high no stress field in equilibrium "
        f"with the surface shear stays within yield, the top layer's plastic strain is set "
        f"by grid.nz and the case ends as surface_flow where it first does; lower the load or "
        f"friction.coefficient below p_0 = {limit / mu / 1e6:.4g} MPa, or cap the friction "
        f'(friction.shear_limit = "yield")'
    )


def scale_note(case) -> str | None:
    """A note for lengths far above machine contacts' (a radius in mm given as metres?).

    Given when a body's radius of curvature exceeds :data:`LARGE_RADIUS` or the closed-form
    contact's largest semi-axis :data:`LARGE_CONTACT_RADIUS`; the case is solved as given.
    """
    radii = []
    for name, body in (("body1", case.body1), ("body2", case.body2)):
        if body.radius_x == body.radius_y:  # a sphere's one radius
            radii.append((f"{name}.radius", body.radius_x))
        else:
            radii += [(f"{name}.radius_x", body.radius_x), (f"{name}.radius_y", body.radius_y)]
    finite = [(key, radius) for key, radius in radii if math.isfinite(radius)]
    key, radius = max(finite, key=lambda item: item[1], default=("", 0.0))
    reference = case.reference if not case.grid.periodic else None
    contact = reference.max_semi_axis if reference is not None else 0.0
    if radius <= LARGE_RADIUS and contact <= LARGE_CONTACT_RADIUS:
        return None
    told = f"{key} = {radius:g} m: " if radius > LARGE_RADIUS else ""
    return (
        f"{told}the contact radius is {1e3 * contact:.3g} mm; lengths are in metres (a 10 mm "
        "sphere is radius = 0.01): solved as given"
    )


def window_unbuilt(case) -> list[str]:
    """What keeps a moving case off the window that follows the contact (none: it fits)."""
    bodies = (case.body1, case.body2)
    return [
        reason
        for reason, applies in (
            ("a given grid.size", case.grid.size is not None),
            (
                "a height map or roughness",
                any(b.surface is not None or b.roughness is not None for b in bodies),
            ),
            ("two elastic-plastic bodies", case.plastic_bodies not in ((), (2,))),
        )
        if applies
    ]


def periodic_slide_note(case) -> str | None:
    """A note on a periodic case's slides: past the period, too fast, or shorter than a cell.

    All are solved: a slide wraps around the period (the same heights come round again); an
    increment of more than a cell leaves a plastic body's strain (or the wear) at the
    increments' positions (measured: a groove of dots one increment apart); a sub-cell slide
    moves body 1's heights interpolated between the cells (cubic B-spline).
    """
    if not case.grid.periodic or not case.moving:
        return None
    grid, period, told = case.surface_grid, case.grid.size, []
    slides = [stage.travel for stage in case.stages if stage.motion == "slide"]
    wraps = max(abs(t[axis]) / period[axis] for t in slides for axis in (0, 1))
    if wraps > 1.0:
        told.append(
            f"a slide of {wraps:.3g} periods wraps around the period (solved: the same heights "
            "come round again)"
        )
    steps = [stage for stage in case.stages if stage.motion == "slide"]
    jump = max(math.hypot(*stage.travel) / stage.steps for stage in steps) / grid.dx
    if jump > 1.0 + 1e-9 and (case.plastic_body is not None or case.wear is not None):
        told.append(
            f"an increment slides {jump:.3g} cells: a contact spot a few cells across leaves "
            "its plastic strain (or wear) at each increment's position, a row of dents rather "
            "than a groove; give a slide at least as many steps as the cells it travels"
        )
    shortest = min(math.hypot(*t) for t in slides)
    if shortest < grid.dx:
        told.append(
            f"a slide of {shortest:.3g} m is shorter than a cell ({grid.dx:.3g} m): body 1's "
            "heights are moved between the cells by cubic B-spline interpolation, the stroke "
            "unresolved by the cells; refine grid.n to resolve it"
        )
    return "periodic sliding: " + "; ".join(told) if told else None


def window_note(case) -> str | None:
    """A note when a moving case asks for the window but is solved on the whole track."""
    if not case.moving or not case.grid.follow_contact or case.grid.periodic:
        return None  # a period holds every position: no window to follow with
    reasons = window_unbuilt(case)
    if not reasons:
        return None
    return (
        "every increment is solved on the whole track, not on a window that follows the "
        f"contact ({', '.join(reasons)}: the window is not built for them): the same "
        "answer, slower"
    )


def rolling_step_note(case) -> str | None:
    """A note when a rolling stage with friction rolls too far per increment.

    More than :data:`MAX_ROLLING_STEP` contact semi-axes (along the roll) per increment; the
    stage that rolls most per step is named: a transient roll's tractions converge with the
    step.
    """
    reference = case.reference
    if reference is None or not case.needs_slip_stick:
        return None
    worst = (0.0, 0, None)
    for i, stage in enumerate(case.stages):
        if stage.motion != "roll" or stage.normal_force == 0.0:  # unloaded: no tractions
            continue
        dx, dy = stage.travel
        semi = reference.semi_axis_x if abs(dx) >= abs(dy) else reference.semi_axis_y
        worst = max(worst, (math.hypot(dx, dy) / stage.steps / semi, i, stage), key=lambda w: w[0])
    per_step, i, stage = worst
    if per_step <= MAX_ROLLING_STEP:
        return None
    need = math.ceil(stage.steps * per_step / MAX_ROLLING_STEP)
    return (
        f"load stage {i + 1} rolls {per_step:.2g} contact semi-axes per increment: a transient "
        "roll's tractions converge with the step (first order; a quarter semi-axis per step put "
        f"a creep force 6 % off), so give steps >= {need} ({MAX_ROLLING_STEP:g} a per step), or "
        "steady = true for the steady state"
    )


def more_cells_note(given: tuple[int, int], grid: Any, zone: float) -> str:
    """The note of cells added so that the window sized for the plastic zone stays resolved.

    ``given``: (nx, ny) as given; ``grid`` the sized grid; ``zone`` (units of a_H):
    :data:`PLASTIC_WIDTH_MARGIN` x the elastic yield region's half width at the largest load.
    """
    return (
        f"grid.n: raised to {grid.nx} x {grid.ny} cells (from {given[0]} x {given[1]}) so that "
        f"the window holds the plastic zone predicted ({zone:.4g} a_H: {PLASTIC_WIDTH_MARGIN:g} "
        "x the elastic yield region's half width at the largest load) with the contact "
        f"resolved as the cells given resolve it ({MIN_CELLS_ACROSS} cells across); give "
        "grid.half_width to keep the cells given (the zone may then be cut: the case ends "
        "truncated)"
    )


def narrow_window_note(grid: Any, zone: float, sized: bool, moving: bool = False) -> str:
    """The note of a surface window narrower than the plastic box the yield region asks for.

    ``zone`` (units of a_H): :data:`PLASTIC_WIDTH_MARGIN` x the elastic yield region's half
    width at the largest load, at most :data:`MAX_AUTO_HALF_WIDTH`; ``sized``: the window was
    sized from it (no ``grid.half_width`` given).  The same words whether the window was given
    or held back by the cells (a case rebuilt from its spec gives it), with the cells that keep
    today's cell size over the wider window; ``moving``: a sliding case's window, which covers
    the track and is not sized for the zone.
    """
    need = f"{PLASTIC_WIDTH_MARGIN:g} x the elastic yield region's half width at the largest load"
    if sized and zone >= MAX_AUTO_HALF_WIDTH:
        return (
            f"grid.half_width: the plastic zone predicted ({need}) reaches the widest window "
            f"sized for it ({MAX_AUTO_HALF_WIDTH:g} a_H): the case may end truncated; give "
            "half_width larger (and n in proportion)"
        )
    if grid.size is not None:
        return (
            f"grid.size: the domain is narrower than the plastic box the yield region asks for "
            f"({zone:.4g} a_H: {need}), so the case may end truncated; enlarge grid.size"
        )
    if moving:  # the window covers the track: it is not sized for the zone
        return (
            f"grid.half_width: beside the track the window reaches {grid.half_width:g} a_H, "
            f"narrower than the plastic box the yield region asks for ({zone:.4g} a_H: {need}), "
            f"so the case may end truncated; give half_width >= {zone:.4g}, with grid.n raised "
            "in proportion to the window's sides to keep the cells' size"
        )
    cells = math.ceil(max(grid.nx, grid.ny) * zone / grid.half_width - 1e-9)
    return (
        f"grid.half_width: the window ({grid.half_width:g} a_H) is narrower than the plastic box "
        f"the yield region asks for ({zone:.4g} a_H: {need}), so the case may end truncated; "
        f"give n >= {cells} and leave half_width out (the window then holds the zone), or "
        f"half_width >= {zone:.4g} with n >= {cells}"
    )


def check_static_shakedown(case) -> tuple[str, ...]:
    """Refuse a ``solver.method = "static_shakedown"`` case the theorem cannot take; its notes.

    The theorem (:mod:`solver.theorems`) passes the field of a Hertz contact (circular or
    elliptical), with the shear ``mu p`` of gross sliding along x, over an elastic-perfectly
    plastic body 2 (or one with kinematic hardening): everything else is refused, naming the
    key.
    """
    path = "solver.method"
    body, pair = case.body2, case.pair
    if case.grid.periodic:
        fail(path, "static_shakedown passes one contact along a track: not with grid.periodic")
    if case.plastic_body1 or body.behaviour != "elastic-plastic":
        fail(path, "static_shakedown needs an elastic-plastic body 2 (body 1 rigid or elastic)")
    hardening = body.hardening
    if hardening.law != "perfect":
        fail(
            "body2.hardening.law",
            f"static_shakedown takes perfect plasticity, with or without kinematic hardening; "
            f'isotropic hardening ({hardening.law!r}) is not built: use law = "perfect"',
        )
    mu = case.friction_coefficient
    if mu > MAX_THEOREM_FRICTION:
        fail(
            "friction.coefficient",
            f"static_shakedown's theorems take 0 <= mu <= {MAX_THEOREM_FRICTION:g}, got {mu:g}: "
            f"give a coefficient of at most {MAX_THEOREM_FRICTION:g} or use the incremental method",
        )
    if case.reference is None or not pair.geometry.hertzian:
        fail(path, "static_shakedown takes a Hertz contact: quadric bodies, no profile or heights")
    slides = [s for s in case.stages if s.motion == "slide"]
    if any(s.motion == "roll" for s in case.stages):
        fail(path, "static_shakedown takes sliding stages; rolling (creepages) is not built")
    loaded = [s for s in slides if s.normal_force > 0.0]
    if not loaded or any(s.travel[1] != 0.0 for s in loaded):
        fail(
            path,
            "static_shakedown needs the load path to slide the loaded contact along x "
            "(slide = [dx, 0])",
        )
    notes = []
    if pair.dundurs_beta != 0.0 and case.friction_coefficient > 0.0:
        notes.append(
            f"static_shakedown takes Hertz's pressure and the shear mu p (Hamilton's field): the "
            f"coupling of dissimilar bodies (beta = {pair.dundurs_beta:.3g}) is left out"
        )
    return tuple(notes)
