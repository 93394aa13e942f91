"""Per-cycle quantities of a cyclic load path, from the per-step histories.

A load path with a cycle block (``cycles = N``, :class:`solver.spec.case.LoadStage`) records the
cycle of every step (history ``step_cycle``).  Cycle ``c`` runs over its steps; its loop closes
on the state before its first step (the last step of the previous cycle, or of the stage before
the block).  With ``Q`` the tangential force on body 2 and ``Delta`` the rigid shift of body 1
relative to body 2, the work done on the contact over a cycle is ``oint Q dDelta``: body 1,
pushed by the external force, passes ``Q`` on to body 2.  Over a closed cycle of an elastic
contact the stored energy returns, so this loop area is the energy dissipated by friction,
which is also the friction work summed over the surface and the steps (history
``friction_work``); both use the trapezoidal rule in time, under which the two agree to the
solver's tolerance for an uncoupled (beta = 0) elastic contact.  Plastic strain stores and
dissipates energy too: then they differ by the plastic work.
"""

from __future__ import annotations

import math

import numpy as np

from .variables import CYCLE_QUANTITIES


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
