"""Every history and field a result can hold, declared once.

:class:`~solver.result.Result`, its xarray view, the campaign assembly (``study.run.assemble``) and
the reserved names of campaign axes are all derived from these two tables.

A history has one value per load step; its ``reduction`` says how a campaign turns it into a
per-case scalar (``"last"`` step, ``"max"`` over the steps, ``"sum"``; None: not reduced) and
``scalar`` names that scalar.  A field has named dimensions: ``x``, ``y`` (surface cells),
``z`` (volume layers, depth into body 2; ``z_body1`` into body 1 on its own grid),
``component`` (:data:`solver.numerics.tensor.COMPONENTS`); ``y_section``, ``z_section``: the
cross-section of a sliding track (``solver.method = "static_shakedown"``).

``swap_sign`` is the factor a value takes when the bodies are relabelled (an elastic-plastic
body 1 is solved as body 2, :meth:`solver.case.case.Case.swapped`): body 1's frame is body 2's
rotated by 180 degrees about x (x, -y, -z), so tractions and forces on the other body change
sign, and y components change sign again.  Tensor fields mirror by component
(:data:`solver.numerics.tensor.Y_REFLECTION`).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np


@dataclass(frozen=True)
class History:
    """Declaration of a per-step history.

    ``infinite`` and ``missing`` say why a value may be ``+inf`` (a documented infinity) or
    NaN (not computed); None: it may not, and a campaign fails a case that holds one
    (:meth:`admits`).
    """

    units: str
    long_name: str
    reduction: str | None = "last"
    scalar: str | None = None
    swap_sign: float = 1.0
    infinite: str | None = None
    missing: str | None = None

    def admits(self, values) -> np.ndarray:
        """Which values are data: finite, or ``+inf`` / NaN where declared (bool array)."""
        values = np.asarray(values, float)
        ok = np.isfinite(values)
        if self.infinite is not None:
            ok |= np.isposinf(values)
        if self.missing is not None:
            ok |= np.isnan(values)
        return ok

    def scalar_name(self, name: str) -> str | None:
        """Name of the per-case scalar of history ``name`` (None when not reduced)."""
        if self.reduction is None:
            return None
        return self.scalar or name


@dataclass(frozen=True)
class Field:
    """Declaration of a field (surface or volume)."""

    dims: tuple[str, ...]
    units: str
    long_name: str
    swap_sign: float = 1.0


HISTORIES: dict[str, History] = {
    "normal_force": History("N", "normal force"),
    "approach": History("m", "rigid-body approach"),
    "max_pressure": History("Pa", "maximum contact pressure", "max"),
    "contact_area": History("m2", "contact area", "max"),
    "contact_spots": History(
        "1", "contact spots: groups of contact cells joined through their edges", "max"
    ),
    "tangential_force_x": History("N", "tangential force on body 2 along x", swap_sign=-1.0),
    "tangential_force_y": History("N", "tangential force on body 2 along y", None),
    "tangential_shift_x": History(
        "m", "rigid tangential shift of body 1 relative to body 2 along x", swap_sign=-1.0
    ),
    "tangential_shift_y": History(
        "m", "rigid tangential shift of body 1 relative to body 2 along y", None
    ),
    "stick_area": History("m2", "stick area"),
    "creepage_x": History(
        "1",
        "creepage xi of a steady rolling step: given, or found for a prescribed force (0 "
        "outside steady stages)",
        swap_sign=-1.0,
    ),
    "creepage_y": History("1", "creepage eta of a steady rolling step (0 outside them)"),
    "spin": History("1/m", "spin of a steady rolling step (0 outside them)"),
    "contact_fraction": History(
        "1", "real contact area over the period's nominal area (grid.periodic)", "max"
    ),
    "mean_separation": History(
        "m",
        "mean gap between the deformed surfaces over the period (grid.periodic; unloaded: "
        "with the bodies just touching)",
    ),
    "position_x": History(
        "m", "position of body 1's apex over body 2 along x (sliding, rolling)", None
    ),
    "position_y": History(
        "m",
        "position of body 1's apex over body 2 along y (sliding, rolling)",
        None,
        swap_sign=-1.0,
    ),
    "normal_iterations": History(
        "1", "normal-solver CG iterations (summed over the step's loops)", "sum"
    ),
    "slip_iterations": History(
        "1", "tangential-operator applications of the slip solver (summed over the step)", "sum"
    ),
    "coupling_iterations": History(
        "1", "slip-stick (normal-tangential) loop passes: normal solves of the step", "sum"
    ),
    "plastic_iterations": History("1", "plasticity-loop iterations (contact solves)", "sum"),
    "max_plastic_strain": History("1", "maximum equivalent plastic strain", "max"),
    "max_plastic_strain_depth": History("m", "depth of the maximum equivalent plastic strain"),
    "surface_shear_ratio": History(
        "1",
        "largest surface shear traction over the current shear yield stress k = sigma_Y(e_p) / "
        "sqrt 3 of the plastic body's top layer under it (above 1 the surface flows unless it "
        'hardens; 1 in the slip zone under friction.shear_limit = "yield", m = 1)',
        "max",
    ),
    "plastic_volume": History(
        "m3",
        "volume of the cells whose equivalent plastic strain exceeds 1e-6 (grid.periodic: over "
        "the period; over its area, the yielded layer's mean thickness)",
        "max",
    ),
    "plastic_zone_depth": History(
        "m", "depth of the plastic zone on the contact axis (equivalent plastic strain > 1e-6)"
    ),
    "residual_depth": History(
        "m", "permanent central dent: residual surface displacement u_z^r at the centre"
    ),
    "residual": History(
        "1", "largest final relative residual of the step's solves", "max", "max_residual"
    ),
    "step_converged": History("1", "1 when every solve of the step converged", None),
    "friction_work": History(
        "J",
        "energy dissipated by friction in the step: -sum (q_k + q_(k-1))/2 . s_k dA (trapezoid "
        "in time; q on body 2, s the slip increment of body 2 relative to body 1)",
        "sum",
    ),
    "wear_volume": History(
        "m3",
        "volume worn off in the step, both bodies ([wear]: the depths worn times the cell area)",
        "sum",
    ),
    "max_wear_depth": History("m", "largest depth worn off a body so far ([wear])", "max"),
    "cycle_weight": History(
        "1",
        "load cycles the step's cycle stands for ([wear]; wear.cycle_jump: its wear is scaled "
        "by them; 1 without a jump)",
        None,
    ),
    "step_cycle": History("1", "load cycle of the step (0: outside a cycle block)", None),
    "static_shakedown_limit": History(
        "1",
        "Melan's static program's factor p_0/k of the case's sliding track (solver.method = "
        "static_shakedown) on the cross-section's points and the program's load positions: an "
        "estimate of the limit, not a bound (the points sample the field; on a Hertz track it "
        "lies above the limit and can lie above the upper bounds)",
    ),
    "static_shakedown_lower_bound": History(
        "1",
        "Melan's certified lower bound p_0/k of the track's shakedown limit: the static "
        "program's residual field, bilinear between the section's points, within yield at the "
        "points halfway between them, between the load positions and where the pointwise bound "
        "was found (an elliptical contact: the program's own points, all the upper bound sees)",
    ),
    "shakedown_upper_bound": History(
        "1",
        "smallest pointwise upper bound p_0/k found for the track's shakedown limit (the best "
        "constant residual shift of one point's stress path)",
        infinite="no bound: the pointwise program's conic solver failed at every point tried",
    ),
    "kinematic_upper_bound": History(
        "1",
        "Koiter's kinematic upper bound p_0/k of the track's shakedown limit: the best "
        "mechanism on the cross-section's six-node triangles (solver.kinematic_cells a contact "
        "radius; inf where not solved)",
        infinite="not solved: solver.kinematic_cells = 0, an elliptical contact (the mechanism "
        "is built for circular ones) or a conic solver that stopped (no bound)",
    ),
    "first_yield_limit": History("1", "p_0/k at first yield under the sliding Hertz contact"),
    "shakedown_load_factor": History(
        "1",
        "certified static lower bound over the case's own p_0/k: the factor of the case's load "
        "up to which repeated passes shake down",
    ),
    "program_iterations": History(
        "1", "interior-point iterations of the shakedown program, summed over its rounds", "sum"
    ),
    "cycle_residual_stress": History(
        "Pa",
        "largest von Mises residual stress of the plastic strain at the end of the step's load "
        "cycle (the same for every step of a cycle)",
        None,
    ),
    "cycle_plastic_strain": History(
        "1",
        "equivalent plastic strain gained since the start of the step's load cycle, largest "
        "over the volume",
        None,
    ),
    "cycle_topography_rms": History(
        "m",
        "rms about its mean of body 2's surface at the end of the step's load cycle: its own "
        "heights plus its residual displacement (a periodic elastic-plastic case's running-in)",
        None,
    ),
    "cycle_net_plastic_strain": History(
        "1",
        "equivalent strain of the plastic strain tensor's change since the start of the step's "
        "load cycle, largest over the volume (a closed plastic cycle returns it to zero)",
        None,
    ),
}

#: Histories an elastic-plastic case with a cycle block records.
CYCLE_PLASTIC_HISTORIES = (
    "cycle_plastic_strain",
    "cycle_net_plastic_strain",
    "cycle_residual_stress",
)

#: Per-cycle quantities of a cyclic load path (:func:`solver.result.cycle_summary`), dim
#: ``cycle``: name -> (units, long_name).
CYCLE_QUANTITIES: dict[str, tuple[str, str]] = {
    "loop_energy": (
        "J",
        "area of the cycle's Q_x-Delta_x loop, sum (Q_k + Q_(k-1))/2 (Delta_k - Delta_(k-1))",
    ),
    "cycle_friction_work": ("J", "energy dissipated by friction over the cycle's surface"),
    "creep_force_x": (
        "N",
        "tangential force on body 2 along x at the cycle's last loaded moving step (a rolling "
        "pass's creep force; mu W along the motion in sliding)",
    ),
    "creep_force_y": (
        "N",
        "tangential force on body 2 along y at the cycle's last loaded moving step",
    ),
    "slip_amplitude": ("m", "half the range of the tangential shift Delta_x over the cycle"),
    "min_stick_radius": (
        "m",
        "smallest equivalent stick radius sqrt(stick_area / pi) of the cycle",
    ),
    "force_amplitude": ("N", "half the range of the tangential force Q_x over the cycle"),
    "max_residual_stress": (
        "Pa",
        "largest von Mises residual stress of the plastic strain at the end of the cycle",
    ),
    "load_cycles": (
        "1",
        "load cycles done at the end of the solved cycle, the cycles jumps stand for counted "
        "([wear]; wear.cycle_jump)",
    ),
    "wear_rate": (
        "m3",
        "volume worn per load cycle over the solved cycle (its worn volume over the cycles it "
        "stands for; [wear])",
    ),
    "plastic_strain_increment": (
        "1",
        "equivalent plastic strain gained over the cycle, largest over the volume",
    ),
    "mean_contact_area": ("m2", "real contact area averaged over the cycle's increments"),
    "mean_contact_spots": ("1", "contact spots averaged over the cycle's increments"),
    "residual_topography_rms": (
        "m",
        "rms about its mean of body 2's surface at the end of the cycle, its own heights plus "
        "its residual displacement (periodic elastic-plastic cases: the running-in topography)",
    ),
    "net_plastic_strain_increment": (
        "1",
        "equivalent strain of the plastic strain tensor's change over the cycle, largest over "
        "the volume (ratchetting strain; zero for a closed plastic cycle)",
    ),
}

#: The result attributes of a case with a ``[fatigue]`` table (:mod:`solver.drive.fatigue`):
#: each criterion's smallest factor of safety under the pass (or the last load cycle) and
#: where it is, name -> (units, long_name).
FATIGUE_SCALARS: dict[str, tuple[str, str]] = {
    f"{name}_{what}": (unit, f"{label}'s {text} of body 2 under the pass or cycle ([fatigue])")
    for name, label in (("dang_van", "Dang Van"), ("crossland", "Crossland"))
    for what, unit, text in (
        ("factor", "1", "smallest factor of safety"),
        ("depth", "m", "depth of the smallest factor of safety"),
        (
            "x",
            "m",
            "x of the smallest factor of safety (a load cycle's; a pass has none: "
            "every x on a line sees the same path)",
        ),
    )  # fmt: skip
}

FIELDS: dict[str, Field] = {
    "pressure": Field(("x", "y"), "Pa", "contact pressure"),
    "initial_gap": Field(
        ("x", "y"), "m", "initial gap of the bodies' shapes (with a profile or point heights)"
    ),
    "wear_depth": Field(
        ("x", "y"), "m", "depth worn off body 2 along the path ([wear]; its surface receded)"
    ),
    "wear_depth_body1": Field(
        ("x", "y"), "m", "depth worn off body 1 along the path ([wear]; in place: it does not move)"
    ),
    "shear_x": Field(("x", "y"), "Pa", "shear traction x", -1.0),
    "shear_y": Field(("x", "y"), "Pa", "shear traction y"),
    "stress": Field(
        ("component", "x", "y", "z"), "Pa", "stress in body 2 from the surface tractions"
    ),
    "von_mises": Field(("x", "y", "z"), "Pa", "von Mises equivalent stress in body 2"),
    "plastic_strain": Field(
        ("x", "y", "z"), "1", "equivalent plastic strain in the elastic-plastic body"
    ),
    "plastic_strain_tensor": Field(
        ("component", "x", "y", "z"), "1", "plastic strain tensor in the elastic-plastic body"
    ),
    "residual_stress": Field(
        ("component", "x", "y", "z"), "Pa", "residual stress of the plastic strain"
    ),
    "residual_gap": Field(
        ("x", "y"),
        "m",
        "gap between the unloaded bodies after the path: the initial gap plus the residual "
        "surface displacements (the plastically deformed topography; grid.periodic)",
    ),
    "spot_areas": Field(
        ("step", "spot"),
        "m2",
        "areas of the contact spots at each step, largest first, NaN past the step's count "
        "(grid.periodic: spots joined across the period's sides)",
    ),
    "residual_displacement_x": Field(
        ("x", "y"), "m", "residual surface displacement of the elastic-plastic body along x"
    ),
    "residual_displacement_y": Field(
        ("x", "y"), "m", "residual surface displacement of the elastic-plastic body along y", -1.0
    ),
    "residual_displacement_z": Field(
        ("x", "y"), "m", "residual surface displacement of the elastic-plastic body into it"
    ),
    **{
        f"cycle_residual_stress_{c}": Field(
            ("cycle", "z"),
            "Pa",
            f"residual stress sigma_{c} of the plastic strain on the contact axis (the middle "
            "of a moving contact's track) at the end of each load cycle",
        )
        for c in ("xx", "yy", "zz")
    },
    "static_residual_stress": Field(
        ("component", "y_section", "z_section"),
        "Pa",
        "residual stress proving Melan's static limit on the track's cross-section (half y >= "
        "0; z_section 0 is the surface)",
    ),
    "static_binding": Field(
        ("y_section", "z_section"),
        "1",
        "1 where the static limit's yield condition binds at some load position",
    ),
    "dang_van_stress": Field(
        ("y", "z"),
        "Pa",
        "Dang Van's equivalent stress max_t [tau(t) + a p_h(t)] of body 2's points under the "
        "pass, on each line along x ([fatigue]; the factor of safety is torsion_limit over it)",
    ),
    "crossland_stress": Field(
        ("y", "z"),
        "Pa",
        "Crossland's equivalent stress sqrt(J2,a) + alpha max p_h of body 2's points under the "
        "pass, on each line along x ([fatigue])",
    ),
    "dang_van_cycle_stress": Field(
        ("x", "y", "z"),
        "Pa",
        "Dang Van's equivalent stress max_t [tau(t) + a p_h(t)] of body 2's points over the "
        "last load cycle's increments ([fatigue] with a cycle block, the contact not moving)",
    ),
    "crossland_cycle_stress": Field(
        ("x", "y", "z"),
        "Pa",
        "Crossland's equivalent stress sqrt(J2,a) + alpha max p_h of body 2's points over the "
        "last load cycle's increments ([fatigue] with a cycle block, the contact not moving)",
    ),
    "cycle_wear_profile": Field(
        ("cycle", "x"),
        "m",
        "depth worn off both bodies together (the gap's growth) along x through the contact axis "
        "at the end of each solved load cycle ([wear]; in body 2's frame)",
    ),
    "cycle_pressure_profile": Field(
        ("cycle", "x"),
        "Pa",
        "contact pressure along x through the contact axis at the end of each solved load "
        "cycle ([wear]: the pressure as the surfaces wear; in body 2's frame)",
    ),
    "cycle_stick_profile": Field(
        ("cycle", "x"),
        "1",
        "contact state along x through the contact axis at the end of each solved load cycle "
        "(0 separated, 1 stick, 2 slip; [wear]: the stick zone as the surfaces wear)",
    ),
    "cycle_topography_spectrum": Field(
        ("cycle", "wavenumber"),
        "m4",
        "isotropic power spectral density C(q) of body 2's surface at the end of each load "
        "cycle, its own heights plus its residual displacement, averaged over rings of "
        "wavevectors (a periodic elastic-plastic case's running-in topography)",
    ),
    "cycle_rut_profile": Field(
        ("cycle", "y"),
        "m",
        "residual surface displacement u_z^r into the elastic-plastic body along y through the "
        "contact axis (across the middle of a moving contact's track) at the end of each load "
        "cycle",
    ),
}
#: Per-cycle profiles of an elastic-plastic body 2 on a cyclic path: residual stress against
#: depth, the rut across the track.
CYCLE_PROFILES = (
    "cycle_residual_stress_xx", "cycle_residual_stress_yy", "cycle_residual_stress_zz",
    "cycle_rut_profile",
)  # fmt: skip

#: Histories and fields of an elastic-plastic body, declared for body 2 above; a second plastic
#: body 1 (two different elastic-plastic bodies) has each under the name + :data:`BODY1_SUFFIX`.
PLASTIC_BODY_HISTORIES = (
    "max_plastic_strain", "max_plastic_strain_depth", "plastic_zone_depth", "residual_depth",
)  # fmt: skip
PLASTIC_BODY_FIELDS = (
    "plastic_strain", "plastic_strain_tensor", "residual_stress",
    "residual_displacement_x", "residual_displacement_y", "residual_displacement_z",
)  # fmt: skip
BODY1_SUFFIX = "_body1"
HISTORIES.update(
    {
        name + BODY1_SUFFIX: replace(
            HISTORIES[name], long_name=HISTORIES[name].long_name + ", body 1"
        )
        for name in PLASTIC_BODY_HISTORIES
    }
)
FIELDS.update(
    {
        name + BODY1_SUFFIX: replace(
            FIELDS[name],
            long_name=FIELDS[name].long_name + ", body 1",
            dims=tuple("z" + BODY1_SUFFIX if d == "z" else d for d in FIELDS[name].dims),
        )
        for name in PLASTIC_BODY_FIELDS
    }
)

#: Field outputs a case may request in ``[output] fields`` (the others come with the scene).
OPTIONAL_FIELDS = ("stress", "plastic_strain_tensor", "residual_stress")

#: Equivalent plastic strain below which a cell does not count as plastic (zone depth).
PLASTIC_ZONE_THRESHOLD = 1e-6


def reduced_scalars() -> dict[str, tuple[str, str, str]]:
    """Per-case scalar name -> (history name, reduction, units) for every reduced history."""
    out = {}
    for name, history in HISTORIES.items():
        scalar = history.scalar_name(name)
        if scalar is not None:
            out[scalar] = (name, history.reduction, history.units)
    return out
