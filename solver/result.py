"""Result of a case: final fields, per-step and per-cycle histories, status, and the xarray view.

Per-cycle quantities (:func:`cycle_summary`).  A load path with a cycle block (``cycles = N``,
:class:`solver.case.path.LoadStage`) records the cycle of every step (history ``step_cycle``).
Cycle ``c`` runs over its steps; its loop closes on the state before its first step (the last step
of the previous cycle, or of the stage before the block).  With ``Q`` the tangential force on body 2
and ``Delta`` the rigid shift of body 1 relative to body 2, the work done on the contact over a
cycle is ``oint Q dDelta``: body 1, pushed by the external force, passes ``Q`` on to body 2.  Over a
closed cycle of an elastic contact the stored energy returns, so this loop area is the energy
dissipated by friction, which is also the friction work summed over the surface and the steps
(history ``friction_work``); both use the trapezoidal rule in time, under which the two agree to the
solver's tolerance for an uncoupled (beta = 0) elastic contact.  Plastic strain stores and
dissipates energy too: then they differ by the plastic work.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .bodies.heights import ring_wavenumbers
from .case.case import Case
from .numerics.grid import SurfaceGrid
from .numerics.tensor import COMPONENTS
from .theory.shakedown import Shakedown, classify, shakedown_variable
from .variables import BODY1_SUFFIX, CYCLE_QUANTITIES, FIELDS, HISTORIES

#: CF metadata of every history variable: name -> (units, long_name) (from :mod:`.variables`).
HISTORY_META = {name: (h.units, h.long_name) for name, h in HISTORIES.items()}

#: Values of ``contact_state``.
SEPARATED, STICK, SLIP = 0, 1, 2
#: Flags of ``contact_state`` (CF ``flag_values`` / ``flag_meanings``).
CONTACT_STATES = {"separated": SEPARATED, "stick": STICK, "slip": SLIP}
#: What a solve says of itself (:attr:`Result.status`).
SOLVE_STATUSES = ("converged", "not_converged", "truncated", "surface_flow")
#: Flags of a case's status in a campaign dataset: a solve's status, or ``pending`` (not run
#: yet) and ``failed`` (raised, timed out, or its file is corrupt).
STATUS_FLAGS = {
    "pending": 0, "converged": 1, "not_converged": 2, "failed": 3, "truncated": 4,
    "surface_flow": 5,
}  # fmt: skip


#: The words of the note that a surface shear passed the plastic body's limit (written by
#: :func:`solver.solve`; the evidence :func:`stored_status` reads older case files by).
SURFACE_FLOW_NOTE = "the surface shear traction reaches"
#: Why a case in surface flow has no shakedown regime.
SURFACE_FLOW_REASON = (
    "surface flow: the surface shear exceeded what the body can carry, so its plastic strain "
    "per cycle follows the layers (the regime is not the material's)"
)


#: The words of the notes that the plastic zone reached a face of the volume box, or the
#: contact the domain's edge (:attr:`Result.truncated`).
TRUNCATED_NOTES = ("face: enlarge the box", "the contact reaches the domain's edge")


def stored_status(status: str, notes: str) -> str:
    """A stored case's status as this model tells it (:data:`SOLVE_STATUSES`).

    A converged solve whose notes say the surface shear passed the body's limit
    (:data:`SURFACE_FLOW_NOTE`) is ``"surface_flow"``, and one not converged whose notes say
    the box or the domain cut it (:data:`TRUNCATED_NOTES`) ``"truncated"``: case files written
    before these rules carry the same evidence in their notes, found by the same criteria.
    """
    if status == "converged" and SURFACE_FLOW_NOTE in notes:
        return "surface_flow"
    if status == "not_converged" and any(words in notes for words in TRUNCATED_NOTES):
        return "truncated"
    return status


#: The histories of each plastic body's largest equivalent plastic strain.
_LARGEST_STRAIN = ("max_plastic_strain", "max_plastic_strain" + BODY1_SUFFIX)


@dataclass
class Result:
    """Outcome of :func:`solver.solve`.

    Attributes
    ----------
    case : Case
        The case that was solved.
    grid : SurfaceGrid
        Its surface grid.
    pressure, shear_x, shear_y : ndarray
        Final tractions on body 2 (Pa), shape (nx, ny).
    contact_state : ndarray of int8
        0 separated, 1 stick, 2 slip.
    history : dict of ndarray
        Per-step histories, keys of :data:`HISTORY_META`.
    loops : tuple of str
        The loops that ran (``load_steps``, ``normal``, ``slip_stick``).
    converged : bool
        True when every solve of every step converged.
    notes : list of str
        Warnings and status messages (non-convergence, path dependence...).
    truncated : bool
        True when the plastic strain reaches a face of the volume box, or the contact the
        surface domain's edge (a note says which and when): the answer is not to be trusted.
    wall_time : float
        Solve time (s).
    fields : dict of ndarray
        Further fields, each declared in :data:`solver.variables.FIELDS`: the stress of the
        tractions in body 2 (``[output] fields = ["stress"]``), and for elastic-plastic cases
        the equivalent plastic strain, residual surface displacements and, on request, the
        plastic strain tensor and the residual stress.
    depth : ndarray or None
        Layer-centre depths (m) of the volume fields.
    depth_body1 : ndarray or None
        Layer-centre depths (m) of body 1's own volume grid (two different elastic-plastic
        bodies), dimension ``z_body1``.
    melan_factor : float or None
        Melan's static shakedown factor of the final residual stress under the sliding Hertz
        load (:func:`solver.theory.shakedown.melan_factor`): sliding cases along x with a circular
        Hertz contact on isotropic hardening; None otherwise.
    fatigue : dict or None
        ``[fatigue]``: the smallest factor of safety of each criterion under the pass and its
        depth (``dang_van_factor``, ``dang_van_depth``, ``crossland_factor``,
        ``crossland_depth``; :mod:`solver.drive.fatigue`).
    section : (ndarray, ndarray) or None
        y and z (m) of a sliding track's cross-section (``solver.method = "static_shakedown"``,
        dimensions ``y_section``, ``z_section``).
    surface_flow : bool
        True when the path ended at the increment whose surface shear traction first exceeded
        the plastic body's bounded shear limit
        (:attr:`solver.plasticity.hardening.Hardening.shear_limit`; a note says where and by
        how much): no stress field in equilibrium with it stays within yield, so the plastic
        strain near the surface depends on the layers.
    cpu_time : float
        Solve CPU time of the process (s), all its threads.
    """

    case: Case
    grid: SurfaceGrid
    pressure: np.ndarray
    shear_x: np.ndarray
    shear_y: np.ndarray
    contact_state: np.ndarray
    history: dict[str, np.ndarray]
    loops: tuple[str, ...]
    converged: bool
    notes: list[str] = field(default_factory=list)
    wall_time: float = 0.0
    fields: dict[str, np.ndarray] = field(default_factory=dict)
    depth: np.ndarray | None = None
    depth_body1: np.ndarray | None = None
    truncated: bool = False
    melan_factor: float | None = None
    fatigue: dict[str, float] | None = None
    section: tuple[np.ndarray, np.ndarray] | None = None
    surface_flow: bool = False
    cpu_time: float = 0.0

    @property
    def status(self) -> str:
        """``"converged"``, ``"not_converged"``, ``"truncated"`` or ``"surface_flow"``.

        The cause before its symptoms.  ``"surface_flow"``: the surface shear traction
        exceeded what the plastic body can carry (:attr:`surface_flow`; the path ends at that
        increment, whose top-layer strain is set by the layers, not the material), every
        increment before it converged.  ``"truncated"``: the plastic zone reaches a face of the
        volume box, or the contact the domain's edge (:attr:`truncated`), so the answer is not
        to be trusted, whether or not its solves converged (a loop that failed is in the
        notes).  ``"not_converged"``: a solve failed, the notes say which and why.
        """
        if self.surface_flow and self.converged:
            return "surface_flow"
        if self.truncated:
            return "truncated"
        return "converged" if self.converged else "not_converged"

    @property
    def shakedown(self) -> Shakedown | None:
        """Shakedown regime of an elastic-plastic path with a cycle block (None otherwise).

        :func:`solver.theory.shakedown.classify` of the per-cycle plastic strain gains; a path that
        is not ``"converged"`` (status) is ``undetermined``.
        """
        per_cycle = cycle_summary(self.history)
        if "net_plastic_strain_increment" not in per_cycle:
            return None
        if self.status == "surface_flow":
            return Shakedown("undetermined", SURFACE_FLOW_REASON)
        return classify(
            per_cycle["plastic_strain_increment"],
            per_cycle["net_plastic_strain_increment"],
            max(float(np.max(self.history[n])) for n in _LARGEST_STRAIN if n in self.history),
            self.status == "converged",
        )

    def to_xarray(self):
        """The result as an :class:`xarray.Dataset` with CF attributes (SI units)."""
        import xarray as xr

        coords, data, attrs = self.variables()
        return xr.Dataset(data, coords=coords, attrs=attrs)

    def variables(self) -> tuple[dict, dict, dict]:
        """The dataset's parts without xarray: coordinates, variables, global attributes.

        Returns
        -------
        (dict, dict, dict)
            ``{name: (dims, values, attrs)}`` for the coordinates and the data variables, and
            the global attributes (what :meth:`to_xarray` wraps).
        """
        case = self.case
        pair = case.pair
        steps = np.arange(1, len(self.history["normal_force"]) + 1)
        coords = {
            "x": ("x", self.grid.x, {"units": "m", "long_name": "x coordinate of cell centre"}),
            "y": ("y", self.grid.y, {"units": "m", "long_name": "y coordinate of cell centre"}),
            "step": ("step", steps, {"units": "1", "long_name": "load step"}),
        }
        data = {
            name: (FIELDS[name].dims, getattr(self, name), _cf(FIELDS[name]))
            for name in ("pressure", "shear_x", "shear_y")
        }
        data.update(
            {
                "contact_state": (
                    ("x", "y"),
                    self.contact_state.astype(np.int8),
                    {
                        "long_name": "contact state",
                        "flag_values": np.array(list(CONTACT_STATES.values()), dtype=np.int8),
                        "flag_meanings": " ".join(CONTACT_STATES),
                    },
                ),
            }
        )
        if self.depth is not None:
            body = 1 if case.plastic_body1 else 2
            coords["z"] = ("z", self.depth, {"units": "m", "long_name": f"depth into body {body}"})
        if self.depth_body1 is not None:
            coords["z_body1"] = (
                "z_body1",
                self.depth_body1,
                {"units": "m", "long_name": "depth into body 1 (its own volume grid)"},
            )
        if self.section is not None:
            along = {"y": "across the track (its half y >= 0)", "z": "depth (0: the surface)"}
            for axis, values in zip("yz", self.section, strict=True):
                coords[f"{axis}_section"] = (
                    f"{axis}_section",
                    values,
                    {"units": "m", "long_name": f"track cross-section: {along[axis]}"},
                )
        if "cycle_topography_spectrum" in self.fields:
            coords["wavenumber"] = (
                "wavenumber",
                ring_wavenumbers(self.grid.shape, case.grid.size),
                {"units": "1/m", "long_name": "wavenumber of a ring of wavevectors"},
            )
        for name, values in self.fields.items():
            declared = FIELDS[name]
            if "component" in declared.dims:
                coords["component"] = (
                    "component",
                    list(COMPONENTS),
                    {"long_name": "tensor component (tensor values: e_xz is half gamma_xz)"},
                )
            data[name] = (declared.dims, values, _cf(declared))
        for name, values in self.history.items():
            units, long_name = HISTORY_META[name]
            data[name] = ("step", np.asarray(values), {"units": units, "long_name": long_name})
        per_cycle = cycle_summary(self.history)
        if per_cycle:
            cycle_coords, cycle_data = cycle_variables(per_cycle)
            coords.update(cycle_coords)
            data.update(cycle_data)
        if self.shakedown is not None:
            data["shakedown"] = shakedown_variable(self.shakedown)
        attrs = {
            "Conventions": "CF-1.8",
            "title": "slipstick contact solution",
            "case_id": case.case_id,
            **reference_attrs(case),
            "composite_modulus": pair.composite_modulus,
            "dundurs_beta": pair.dundurs_beta,
            "friction_coefficient": case.friction_coefficient,
            **(
                {"shear_yield_stress": case.plastic_body.hardening.initial_yield_stress / 3**0.5}
                if case.plastic_body is not None
                else {}
            ),
            "loops": " ".join(self.loops),
            "converged": int(self.converged),
            "status": self.status,
            **({"melan_factor": self.melan_factor} if self.melan_factor is not None else {}),
            **(self.fatigue or {}),
            "notes": "; ".join(self.notes),
            "wall_time": self.wall_time,
            "cpu_time": self.cpu_time,
        }
        return coords, data, attrs


def reference_attrs(case: Case) -> dict[str, float]:
    """The closed-form elastic reference at the case's largest load, as result attributes.

    ``hertz_*`` (radius sqrt(a b), semi-axes, peak pressure, approach, force) for quadric
    bodies; ``sneddon_*`` (radius, mean pressure W/(pi a^2), approach, force) with a profile;
    of the smooth shape under point heights; ``line_*`` (half-width, peak pressure, force per
    length: :attr:`Case.line_contact`) for a line contact; ``domain_half_width`` (m)
    for heights only.
    """
    reference = case.reference
    if case.grid.periodic_y:  # a line contact: Hertz's strip
        half_width, pressure, per_length = case.line_contact
        return {
            "line_half_width": half_width,
            "line_pressure": pressure,
            "line_force_per_length": per_length,
        }
    if reference is None:  # heights only
        return {"domain_half_width": case.domain_half_widths[0]}
    if case.pair.geometry.hertzian:
        return {
            "hertz_radius": reference.radius,
            "hertz_semi_axis_x": reference.semi_axis_x,
            "hertz_semi_axis_y": reference.semi_axis_y,
            "hertz_pressure": reference.max_pressure,
            "hertz_approach": reference.approach,
            "hertz_normal_force": reference.normal_force,
        }
    return {
        "sneddon_radius": reference.radius,
        "sneddon_mean_pressure": reference.mean_pressure,
        "sneddon_approach": reference.approach,
        "sneddon_normal_force": reference.normal_force,
    }


def length_scale(attrs: dict) -> float:
    """The reference semi-axis along x (m) of a result's attributes.

    Hertz's a_x, Sneddon's contact radius, a line contact's half-width, or the domain's half
    width (:func:`reference_attrs`).
    """
    for name in ("hertz_semi_axis_x", "sneddon_radius", "line_half_width", "domain_half_width"):
        if name in attrs:
            return float(attrs[name])
    raise KeyError("no reference length among the attributes")


def _cf(declared) -> dict:
    return {"units": declared.units, "long_name": declared.long_name}


def cycle_summary(history: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """Per-cycle quantities (:data:`solver.variables.CYCLE_QUANTITIES`) of a result's history.

    Parameters
    ----------
    history : dict of ndarray
        Per-step histories (:attr:`solver.Result.history`) with ``step_cycle``.

    Returns
    -------
    dict of ndarray
        One array of length (number of cycles) per quantity the histories allow (the
        tangential ones need a friction scene, the plastic increment an elastic-plastic body);
        empty without a ``step_cycle`` history or cycle.
    """
    cycle = np.asarray(history.get("step_cycle", []), dtype=int)
    count = int(cycle.max()) if cycle.size else 0
    if count == 0:
        return {}
    out: dict[str, np.ndarray] = {}
    blocks = [np.flatnonzero(cycle == c) for c in range(1, count + 1)]
    if "tangential_force_x" in history and "position_x" not in history:  # a sliding path
        # has no Q - Delta loop (its shift stays; the travel is the position)
        force = np.asarray(history["tangential_force_x"], dtype=float)
        shift = np.asarray(history["tangential_shift_x"], dtype=float)
        energy, forces, shifts = [], [], []
        for steps in blocks:
            # the loop from the state before the cycle's first step (zero before step 1)
            before = steps[0] - 1
            q = np.concatenate([[force[before] if before >= 0 else 0.0], force[steps]])
            d = np.concatenate([[shift[before] if before >= 0 else 0.0], shift[steps]])
            energy.append(float(np.sum(0.5 * (q[1:] + q[:-1]) * np.diff(d))))
            forces.append(0.5 * float(q.max() - q.min()))
            shifts.append(0.5 * float(d.max() - d.min()))
        out["loop_energy"] = np.array(energy)
        out["force_amplitude"] = np.array(forces)
        out["slip_amplitude"] = np.array(shifts)
        stick = np.asarray(history["stick_area"], dtype=float)
        out["min_stick_radius"] = np.array([math.sqrt(stick[s].min() / math.pi) for s in blocks])
    if "tangential_force_x" in history and "position_x" in history:  # a moving path
        position = np.stack([np.asarray(history[f"position_{a}"], dtype=float) for a in "xy"])
        moved = np.any(np.diff(position, axis=1, prepend=0.0) != 0.0, axis=0)
        loaded_moves = moved & (np.asarray(history["normal_force"], dtype=float) > 0)
        for axis in "xy":
            force = np.asarray(history[f"tangential_force_{axis}"], dtype=float)
            out[f"creep_force_{axis}"] = np.array(
                [force[s[loaded_moves[s]][-1]] if loaded_moves[s].any() else np.nan for s in blocks]
            )
    if "friction_work" in history:
        work = np.asarray(history["friction_work"], dtype=float)
        out["cycle_friction_work"] = np.array([float(work[s].sum()) for s in blocks])
    if "cycle_residual_stress" in history:
        stress = np.asarray(history["cycle_residual_stress"], dtype=float)
        out["max_residual_stress"] = np.array([float(stress[s[-1]]) for s in blocks])
    if "cycle_plastic_strain" in history:
        gained = np.asarray(history["cycle_plastic_strain"], dtype=float)
        out["plastic_strain_increment"] = np.array([float(gained[s[-1]]) for s in blocks])
    if "cycle_net_plastic_strain" in history:
        net = np.asarray(history["cycle_net_plastic_strain"], dtype=float)
        out["net_plastic_strain_increment"] = np.array([float(net[s[-1]]) for s in blocks])
    for name in ("contact_area", "contact_spots"):
        if name in history:
            values = np.asarray(history[name], dtype=float)
            out[f"mean_{name}"] = np.array([float(values[s].mean()) for s in blocks])
    if "cycle_topography_rms" in history:
        rms = np.asarray(history["cycle_topography_rms"], dtype=float)
        out["residual_topography_rms"] = np.array([float(rms[s[-1]]) for s in blocks])
    if "wear_volume" in history:
        volume = np.asarray(history["wear_volume"], dtype=float)
        weight = np.asarray(history["cycle_weight"], dtype=float)
        stood = np.array([float(weight[s[-1]]) for s in blocks])
        out["load_cycles"] = np.cumsum(stood)
        out["wear_rate"] = np.array([float(volume[s].sum()) for s in blocks]) / stood
    assert set(out) <= set(CYCLE_QUANTITIES)
    return out


def cycle_variables(per_cycle: dict[str, np.ndarray], dims: tuple[str, ...] = ()) -> tuple:
    """The ``cycle`` coordinate and CF variables of per-cycle arrays for an xarray dataset.

    Parameters
    ----------
    per_cycle : dict of ndarray
        :data:`solver.variables.CYCLE_QUANTITIES` names -> arrays whose last axis is the cycle.
    dims : tuple of str
        Dimensions before the cycle (a campaign's axes; none for one case).

    Returns
    -------
    (dict, dict)
        ``{"cycle": (dim, values, attrs)}`` and ``{name: (dims, values, attrs)}``.
    """
    count = max(np.shape(values)[-1] for values in per_cycle.values())
    coords = {
        "cycle": ("cycle", np.arange(1, count + 1), {"units": "1", "long_name": "load cycle"})
    }
    variables = {}
    for name, values in per_cycle.items():
        units, long_name = CYCLE_QUANTITIES[name]
        variables[name] = ((*dims, "cycle"), values, {"units": units, "long_name": long_name})
    return coords, variables
