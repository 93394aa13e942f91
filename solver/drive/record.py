"""What the load-path driver records: per-step histories, final fields, the Melan bound, notes.

The histories are declared in :mod:`solver.variables`; here an increment's contact, friction and
plastic quantities are written into them (:func:`record`, :func:`record_plastic`), the plastic
fields of each body are put on the common axes (:func:`plastic_fields`), and the notes on
failed increments and on path dependence are worded (:func:`failure_notes`,
:func:`path_dependence_notes`).
"""

from __future__ import annotations

import math

import numpy as np

from ..case.case import Case
from ..case.notes import MAX_PERFECT_LAYER
from ..numerics.tensor import Y_REFLECTION, von_mises
from ..result import Result
from ..theory.half_space import hamilton_stress
from ..theory.shakedown import melan_factor
from ..variables import BODY1_SUFFIX, CYCLE_PROFILES, FIELDS, PLASTIC_ZONE_THRESHOLD
from .operators import CaseOperators
from .plastic_loop import PlasticState, mirror
from .steps import STALL_WINDOW, StepResult

#: Fewest increments per normal-loading stage for which the stick zone of a coupled
#: (beta != 0) scene is trusted; fewer give a path-dependence note.
MIN_COUPLED_STEPS = 20


CONTACT_HISTORY = (
    "normal_force", "approach", "max_pressure", "contact_area", "contact_spots",
    "normal_iterations",
)  # fmt: skip


#: Histories of a case with steady rolling stages: the creepage of every step.
STEADY_HISTORY = ("creepage_x", "creepage_y", "spin")
FRICTION_HISTORY = (
    "tangential_force_x", "tangential_force_y", "tangential_shift_x", "tangential_shift_y",
    "stick_area", "slip_iterations", "coupling_iterations", "friction_work",
)  # fmt: skip


#: Histories of a case that wears (``[wear]``).
WEAR_HISTORY = ("wear_volume", "max_wear_depth", "cycle_weight")
#: What a periodic case records beside the contact histories (the period is the nominal area).
PERIODIC_HISTORY = ("contact_fraction", "mean_separation")
#: ... and beside the plastic histories.
PERIODIC_PLASTIC_HISTORY = ("plastic_volume",)
PLASTIC_HISTORY = (
    "plastic_iterations", "max_plastic_strain", "max_plastic_strain_depth",
    "plastic_zone_depth", "residual_depth",
)  # fmt: skip
#: ... and beside those of friction.
PLASTIC_FRICTION_HISTORY = ("surface_shear_ratio",)


# -- plastic-zone measures -----------------------------------------------------------------------
def spot_labels(in_contact: np.ndarray, periodic: bool = False) -> tuple[np.ndarray, int]:
    """Contact spots: groups of contact cells joined through their edges, labelled 1 .. count.

    Cells that touch at a corner only are separate spots (4-connectivity,
    ``scipy.ndimage.label``).  ``periodic``: the grid is one period, and a spot that leaves it
    on one side and comes back on the other is one spot.  Returns ``(labels, count)``, 0 off
    contact.
    """
    from scipy import ndimage

    labels, count = ndimage.label(in_contact)
    if not periodic or not count:
        return labels, int(count)
    parent = np.arange(count + 1)

    def root(label: int) -> int:
        while parent[label] != label:
            parent[label] = parent[parent[label]]
            label = parent[label]
        return int(label)

    seams = ((labels[0, :], labels[-1, :]), (labels[:, 0], labels[:, -1]))
    for first, last in seams:  # the cells that face each other across the period's sides
        for a, b in zip(first.tolist(), last.tolist(), strict=True):
            if a and b and root(a) != root(b):
                parent[root(a)] = root(b)
    roots = np.array([root(label) for label in range(count + 1)])
    _, merged = np.unique(roots, return_inverse=True)  # root 0 (no contact) stays 0
    return merged[labels], int(merged.max())


def contact_spots(in_contact: np.ndarray, periodic: bool = False) -> int:
    """Number of contact spots (:func:`spot_labels`)."""
    return spot_labels(in_contact, periodic)[1]


def cells_across(area: float, grid) -> float:
    """Cells across a spot of ``area`` (m^2): its equivalent diameter over the coarser cell.

    ``2 sqrt(area / pi) / max(dx, dy)`` on ``grid`` (anything with ``dx`` and ``dy``, m).
    """
    return 2.0 * math.sqrt(area / math.pi) / max(grid.dx, grid.dy)


def spot_areas(in_contact: np.ndarray, cell_area: float, periodic: bool = False) -> np.ndarray:
    """Areas (m^2) of the contact spots (:func:`spot_labels`), largest first."""
    labels, count = spot_labels(in_contact, periodic)
    return np.sort(np.bincount(labels.ravel(), minlength=count + 1)[1:] * cell_area)[::-1]


def touches_edge(pressure: np.ndarray, periodic_y: bool = False) -> bool:
    """True when any cell of the surface grid's outer ring carries pressure.

    ``periodic_y``: the grid is one period along y, its edges along x only.
    """
    along_x = pressure[0].any() or pressure[-1].any()
    return bool(along_x or (not periodic_y and (pressure[:, 0].any() or pressure[:, -1].any())))


def axis_value(values: np.ndarray) -> np.ndarray:
    """Values on the contact axis x = y = 0 of an ``(nx, ny, ...)`` cell field.

    The mean of the 1, 2 or 4 cells whose centres are nearest the axis (bilinear interpolation
    at the grid's centre: the origin, or the middle of a sliding track).
    """
    nx, ny = values.shape[:2]
    ix = slice((nx - 1) // 2, nx // 2 + 1)
    iy = slice((ny - 1) // 2, ny // 2 + 1)
    return values[ix, iy].mean(axis=(0, 1))


def zone_depth(profile: np.ndarray, depth: np.ndarray, threshold: float) -> float:
    """Deepest depth (m) where ``profile`` crosses ``threshold``, interpolated between layers.

    0 when no layer exceeds it; the last layer's centre when the deepest layer does.
    """
    above = np.flatnonzero(profile > threshold)
    if above.size == 0:
        return 0.0
    k = above[-1]
    if k == len(profile) - 1:
        return float(depth[k])
    f = (profile[k] - threshold) / (profile[k] - profile[k + 1])
    return float(depth[k] + f * (depth[k + 1] - depth[k]))


def peak_depth(values: np.ndarray, depth: np.ndarray) -> float:
    """Depth (m) of the maximum of a cell field, refined by a parabola through its column."""
    i, j, k = np.unravel_index(int(np.argmax(values)), values.shape)
    if 0 < k < values.shape[2] - 1:
        lo, mid, hi = values[i, j, k - 1 : k + 2]
        curvature = lo - 2 * mid + hi
        if curvature < 0:
            shift = 0.5 * (lo - hi) / curvature
            return float(depth[k] + shift * (depth[1] - depth[0]))
    return float(depth[k])


def box_faces_reached(equivalent: np.ndarray, sides: str | None) -> list[str]:
    """Faces of the plastic box where the equivalent plastic strain exceeds the zone threshold.

    ``sides`` names the key that sets the box's sides; None for a box without sides (one
    period of a periodic body: its bottom only).
    """
    faces = {"bottom (grid.depth)": equivalent[:, :, -1]}
    if sides is not None:
        faces[f"side x ({sides})"] = equivalent[[0, -1], :, :]
        faces[f"side y ({sides})"] = equivalent[:, [0, -1], :]
    return [name for name, cells in faces.items() if cells.max() > PLASTIC_ZONE_THRESHOLD]


def on_common_axes(name: str, values: np.ndarray) -> np.ndarray:
    """Field ``name`` of body 1's frame (x, -y, -z) on the common x, y axes, or back.

    Mirrored in y, times the declared ``swap_sign``; tensor fields also flip their y-odd
    components.  Depths stay into the body.
    """
    declared = FIELDS[name]
    out = values * declared.swap_sign
    if "y" in declared.dims:
        out = mirror(out, axis=declared.dims.index("y"))
    if "component" in declared.dims:
        out = out * Y_REFLECTION.reshape((6,) + (1,) * (out.ndim - 1))
    return out


#: Iteration counts of a contact step (:attr:`StepResult.iterations`) and their histories.
ITERATION_HISTORY = {
    "normal": "normal_iterations", "slip": "slip_iterations", "coupling": "coupling_iterations",
}  # fmt: skip


def count_iterations(totals: dict, contact: dict, plastic: int = 0) -> None:
    """Add a sub-step's contact and plasticity iteration counts to ``totals`` (by history)."""
    for key, name in ITERATION_HISTORY.items():
        totals[name] += contact.get(key, 0)
    totals["plastic_iterations"] += plastic


def record(history: dict, k: int, outcome: StepResult, area: float, periodic: bool = False) -> None:
    """Write increment ``k``'s contact (and friction) histories from its step's outcome.

    ``periodic``: the grid is one period (spots joined across its sides).
    """
    state = outcome.state
    history["normal_force"][k] = state.pressure.sum() * area
    history["approach"][k] = outcome.approach
    history["max_pressure"][k] = state.pressure.max()
    history["contact_area"][k] = np.count_nonzero(state.pressure) * area
    history["contact_spots"][k] = contact_spots(state.pressure > 0, periodic)
    if "contact_fraction" in history:
        history["contact_fraction"][k] = np.count_nonzero(state.pressure) / state.pressure.size
        gap = state.normal.gap if state.normal is not None else np.nan
        history["mean_separation"][k] = float(np.mean(gap))
    if "position_x" in history:
        history["position_x"][k], history["position_y"][k] = state.position
    for key, name in ITERATION_HISTORY.items():
        if name in history:
            history[name][k] = outcome.iterations.get(key, 0)
    if "stick_area" in history:
        history["tangential_force_x"][k] = state.shear_x.sum() * area
        history["tangential_force_y"][k] = state.shear_y.sum() * area
        history["tangential_shift_x"][k], history["tangential_shift_y"][k] = state.shift
        history["stick_area"][k] = np.count_nonzero(outcome.stick) * area


def record_touching(history: dict, k: int, gap: np.ndarray, states: tuple) -> None:
    """The mean separation of an unloaded periodic step: the bodies just touching.

    Without a load the bodies part; the separation recorded is the one at vanishing load, the
    unloaded gap (the initial gap plus the residual displacements of body 2's plastic strain,
    ``states``) less its smallest value.
    """
    unloaded = gap + sum(plastic.displacement[2] for plastic in states)
    history["mean_separation"][k] = float(np.mean(unloaded - unloaded.min()))


def record_plastic(
    history: dict, k: int, iterations: int, states: tuple[PlasticState, ...], case: Case
) -> None:
    """Write increment ``k``'s plastic histories from the plastic states of its bodies."""
    history["plastic_iterations"][k] = iterations
    for body, plastic in zip(case.plastic_bodies, states, strict=True):
        suffix = BODY1_SUFFIX if body == 1 else ""
        volume = case.volume_grid_of(body)
        equivalent = plastic.equivalent
        history["max_plastic_strain" + suffix][k] = equivalent.max()
        history["max_plastic_strain_depth" + suffix][k] = (
            peak_depth(equivalent, volume.z) if equivalent.max() > 0 else 0.0
        )
        history["plastic_zone_depth" + suffix][k] = zone_depth(
            axis_value(equivalent), volume.z, PLASTIC_ZONE_THRESHOLD
        )
        history["residual_depth" + suffix][k] = float(axis_value(plastic.displacement[2]))
        if "plastic_volume" in history:
            cells = np.count_nonzero(equivalent > PLASTIC_ZONE_THRESHOLD)
            history["plastic_volume"][k] = cells * volume.surface.cell_area * volume.dz


def shear_excess(case: Case, state) -> float:
    """The largest surface shear traction over the plastic bodies' shear limit (0: none).

    :attr:`solver.plasticity.hardening.Hardening.shear_limit`: above 1 no stress field in
    equilibrium with the tractions stays within yield.
    """
    limit = min((case.body2 if b == 2 else case.body1).hardening.shear_limit
                for b in case.plastic_bodies)  # fmt: skip
    if not math.isfinite(limit):
        return 0.0
    return float(np.hypot(state.shear_x, state.shear_y).max()) / limit


def melan(
    case: Case, operators: CaseOperators, states: tuple[PlasticState, ...], positions: set
) -> float | None:
    """Melan's factor of the final residual stress under the sliding Hertz load, or None.

    The elastic loads are Hamilton's (1983) field of the largest Hertz pressure with the shear
    ``mu p`` along the motion, at every loaded position of the path (sliding along x only);
    the yield stress is each cell's current flow stress.  None where that field is not the
    load's: a non-circular or non-Hertzian contact, sliding along y, kinematic hardening,
    two plastic bodies, a rolling contact with friction (its positions are not collected).
    """
    reference, body = case.reference, case.body2
    circular = case.pair.geometry.hertzian and math.isclose(
        reference.semi_axis_x, reference.semi_axis_y, rel_tol=1e-9
    )
    along_x = all(sy == 0.0 for _, _, _, sy in positions)
    if not circular or not along_x or case.plastic_bodies != (2,) or body.hardening.kinematic:
        return None
    (plastic,) = states
    residual = (
        operators.volume(2)[1].stress(plastic.strain)
        if plastic.strain.any()
        else np.zeros_like(plastic.strain)
    )
    grid = case.surface_grid
    x = grid.x[:, None, None]
    y = grid.y[None, :, None]
    z = case.volume_grid.z[None, None, :]
    mu = case.friction_coefficient
    loads = (
        hamilton_stress(
            x - px, y - py, z, reference.radius, reference.max_pressure, body.nu, sx * mu
        )
        for px, py, sx, _ in sorted(positions)
    )
    return melan_factor(residual, loads, body.hardening.flow_stress(plastic.equivalent))


def cycle_end(
    operators: CaseOperators, states: tuple[PlasticState, ...]
) -> tuple[float, dict[str, np.ndarray]]:
    """The largest residual stress and the first plastic body's profiles at a cycle's end.

    The largest von Mises stress of the plastic strain alone (Pa, over the plastic bodies); the
    profiles (:data:`CYCLE_PROFILES`): the residual normal stresses on the contact axis against
    depth, the residual dent along y through it.
    """
    largest, profiles = 0.0, {}
    for body, plastic in zip(operators.case.plastic_bodies, states, strict=True):
        stress = (
            operators.volume(body)[1].stress(plastic.strain)
            if plastic.strain.any()
            else np.zeros_like(plastic.strain)
        )
        largest = max(largest, float(von_mises(stress).max()))
        if not profiles:
            for i, name in enumerate(CYCLE_PROFILES[:3]):
                profiles[name] = axis_value(stress[i])
            dent = plastic.displacement[2]
            nx = dent.shape[0]
            profiles["cycle_rut_profile"] = dent[(nx - 1) // 2 : nx // 2 + 1].mean(axis=0)
    return largest, profiles


def plastic_fields(
    result: Result, operators: CaseOperators, states: tuple[PlasticState, ...]
) -> None:
    """Final plastic fields of each plastic body (body 1's on the common x, y axes).

    Displacements and residual stress are those of the final plastic strain.  Volume fields
    span the surface window: a plastic box narrower than it (``grid.plastic_half_width``) has
    no plastic strain outside by construction (zeros there), and its residual stress is not
    computed outside (NaN there).
    """
    for body, plastic in zip(result.case.plastic_bodies, states, strict=True):
        eigenstrain = operators.volume(body)[1]
        if plastic.strain.any():
            residual_stress, displacement = eigenstrain.evaluate(plastic.strain)
        else:
            residual_stress, displacement = np.zeros_like(plastic.strain), plastic.displacement
        window = eigenstrain.on_window
        fields = {"plastic_strain": window(plastic.equivalent)}
        fields.update(
            {
                f"residual_displacement_{axis}": u
                for axis, u in zip("xyz", displacement, strict=True)
            }
        )
        if "plastic_strain_tensor" in result.case.fields:
            fields["plastic_strain_tensor"] = window(plastic.strain)
        if "residual_stress" in result.case.fields:
            fields["residual_stress"] = window(residual_stress, np.nan)
        for name, values in fields.items():
            if body == 1:
                result.fields[name + BODY1_SUFFIX] = on_common_axes(name, values)
            else:
                result.fields[name] = values


#: Failed increments told one by one; more are told in one note (first, last, the steps).
MAX_FAILURE_NOTES = 3


def failure_notes(failures: list[tuple[int, str]]) -> list[str]:
    """Notes of the increments that did not converge: each, or one for many.

    A case whose every pass fails (a load past what the body can carry) would otherwise
    carry a note per increment and sub-step; beyond :data:`MAX_FAILURE_NOTES` one note names
    the steps and tells the first and the last failure in full.
    """
    told = [f"step {k}{'' if m.startswith('(') else ':'} {m}" for k, m in failures]
    if len(told) <= MAX_FAILURE_NOTES:
        return told
    steps = sorted({k for k, _ in failures})
    runs, start = [], steps[0]
    for a, b in zip(steps, [*steps[1:], None], strict=True):
        if b != a + 1:
            runs.append(f"{start}" if start == a else f"{start}-{a}")
            start = b
    return [
        f"{len(failures)} increments did not converge, in steps {', '.join(runs)}; the first: "
        f"{told[0]}; the last: {told[-1]}"
    ]


def failure_advice(
    case: Case, history: dict, failures: list[tuple[int, str]], truncated: bool
) -> str | None:
    """One note after the failures: which loops failed, and what to change (None: none failed).

    The remedies follow the case: layers thicker than :data:`MAX_PERFECT_LAYER` of a cell
    under a body whose checkerboard patterns they let stall (:func:`solver.case.notes.layer_note`),
    a surface shear past the top layer's yield stress (``friction.shear_limit = "yield"``), a
    box the plastic zone reached, and smaller increments.
    """
    if not failures:
        return None
    kinds = {"plasticity loop": "plasticity", "tangential solve": "slip-stick (tangential)",
             "slip-stick loop": "slip-stick (coupling)", "normal solve": "normal",
             "return mapping": "return mapping"}  # fmt: skip
    failed = [name for words, name in kinds.items() if any(words in m for _, m in failures)]
    advice = []
    volume, body = case.volume_grid, case.plastic_body
    if "plasticity" in failed and volume is not None and body is not None:
        ratio = volume.dz / min(case.surface_grid.dx, case.surface_grid.dy)
        bounded = body.hardening.law == "perfect" and not body.hardening.kinematic
        if ratio > MAX_PERFECT_LAYER and (bounded or case.grid.periodic):
            nz = math.ceil(case.grid.nz * ratio / MAX_PERFECT_LAYER)
            advice.append(
                f"thinner layers (they are {ratio:.2g} of a cell: grid.n with nz >= {nz})"
            )
        shear = history.get("surface_shear_ratio")
        if shear is not None and shear.size and shear.max() > 1.0:
            advice.append(
                f'friction.shear_limit = "yield" (the surface shear reached {shear.max():.3g} x '
                "the top layer's shear yield stress)"
            )
    if truncated:
        advice.append("a larger box (grid.half_width, grid.plastic_half_width or grid.depth)")
    advice.append("more steps in the stages of the failed increments (smaller increments)")
    steps = sorted({k for k, _ in failures})
    stalled = sorted({k for k, m in failures if "stalled" in m})
    return (
        f"diagnosis: the {', '.join(failed) or 'solve'} loop{'s' if len(failed) > 1 else ''} "
        f"did not reach the tolerance at step{'s' if len(steps) > 1 else ''} "
        f"{', '.join(map(str, steps[:5]))}{', ...' if len(steps) > 5 else ''}"
        + (
            f" (stalled, stopped after {STALL_WINDOW} iterations without progress, at "
            f"{len(stalled)} of them)"
            if stalled
            else ""
        )
        + "; try "
        + "; or ".join(advice)
    )


def path_dependence_notes(case: Case) -> list[str]:
    """One note naming every stage that raises the normal force in too few steps.

    Not a stage a steady rolling stage follows: a steady state does not depend on the path
    that led to it.
    """
    few, previous_force = [], 0.0
    for i, stage in enumerate(case.stages):
        forgotten = any(later.motion == "steady" for later in case.stages[i + 1 :])
        if (
            stage.normal_force > previous_force
            and stage.steps < MIN_COUPLED_STEPS
            and not forgotten
        ):
            few.append(f"{i + 1} ({stage.steps} step{'s' if stage.steps > 1 else ''})")
        previous_force = stage.normal_force
    if not few:
        return []
    stages = (
        f"load stage {few[0]} raises" if len(few) == 1 else (f"load stages {', '.join(few)} raise")
    )
    return [
        f"path dependence: {stages} the normal force in fewer than {MIN_COUPLED_STEPS} steps; "
        f"the stick zone of a dissimilar pair (beta != 0) depends on the loading path"
    ]
