"""Body 2's fatigue under a steady pass or a load cycle: the criteria of the solved field.

The final increment's tractions, passing unchanged along x, give every material point on a
line along x the same stress path (:func:`solver.fatigue.criteria.steady_pass_criteria`): the
field along that line, sampled at the grid's cells.  An elastic-plastic body 2 adds its
residual stress, constant in time at a point (:func:`track_residual`): only its hydrostatic
part changes the criteria (the ball's centre takes up a constant deviator), by a p_h^r
(Dang Van) and alpha p_h^r (Crossland).  Fields ``dang_van_stress`` and
``crossland_stress`` over (y, z); the result's attributes the smallest factor of safety of
each criterion and its depth.  Notes when the pass is sampled coarsely (fewer than
:data:`PASS_CELLS` cells per contact radius, a line contact's half-width, along x) or cut
short ahead of the contact.

A contact that does not move but cycles (fretting: a cycle block of tangential or normal
forces) gives each material point its own path: the stresses of the last solved cycle's
increments (:func:`cycle_fatigue`), read from their tractions layer block by layer block, so
only the tractions of one cycle are kept.  Fields ``dang_van_cycle_stress`` and
``crossland_cycle_stress`` over (x, y, z); the attributes as for a pass, with ``*_x`` (m)
where the smallest factor is.  A cycle's extremes are increment ends (reversals); notes
when a cycle has fewer than :data:`CYCLE_SAMPLES` increments or still gained plastic strain.
"""

from __future__ import annotations

import numpy as np

from ..fatigue.criteria import CRITERIA, fatigue_criteria, steady_pass_criteria
from ..numerics.grid import IndexBox

#: Cells per contact radius along x under which the pass's sampling is told (Crossland's
#: maximum of a Hertz pass: 2.6 % low at 6, 0.63 % at 12, 2026-12-06).
PASS_CELLS = 10
#: Contact radii of the field ahead of the contact under which the pass is told cut short.
PASS_AHEAD = 3.0
#: Increments of a load cycle under which its sampling is told (the reversals are sampled;
#: between them a partial slip's path bends).
CYCLE_SAMPLES = 8
#: Bytes of the stress paths held at once while the criteria of a cycle are read.
CYCLE_BLOCK_BYTES = 2**26
#: Arrays of a block's size the criteria hold at once (the paths, their deviatoric
#: coordinates and its moved copy, the deviator, the mesoscopic deviator, Tresca's
#: temporaries): the cycle's share of :meth:`CaseOperators.memory_bytes`.
CYCLE_BLOCK_COPIES = 7
#: Equivalent plastic strain gained over the last cycle above which it is told not shaken down.
CYCLE_SHAKEN_DOWN = 1e-6
#: A path's farthest point outside its ball, relative to the radius, above which the ball is
#: told not found (:func:`solver.fatigue.ball.smallest_balls`; round-off is about 1e-15).
BALL_EXCESS = 1e-8


def reads_cycle(case) -> bool:
    """True when the criteria read the last load cycle (a ``[fatigue]`` case not moving)."""
    return case.fatigue is not None and not any(stage.motion for stage in case.stages)


def residual_field(operators, plastic_state, x: int | None = None) -> tuple[np.ndarray, bool]:
    """Body 2's residual stress (6, nx, ny, nz) on the volume grid, or its x-slice ``x`` (Pa).

    Outside the plastic box it is not computed and taken as zero (the second value is True
    where that happened to a cell).
    """
    eigenstrain = operators.volume(2)[1]
    strain = plastic_state[0].strain
    residual = eigenstrain.evaluate(strain)[0] if strain.any() else np.zeros_like(strain)
    residual = eigenstrain.on_window(residual, np.nan)
    residual = residual if x is None else residual[:, x]
    return np.nan_to_num(residual, nan=0.0), bool(np.isnan(residual).any())


def track_residual(case, operators, plastic_state) -> tuple[np.ndarray, bool]:
    """Body 2's residual stress (6, ny, nz) on the x-slice at the middle of the track (Pa).

    The residual stress of a steady track does not change along it; away from its ends the
    middle's stands for it.  Outside the plastic box it is not computed and taken as zero
    (the second value is True where that happened to a line).
    """
    (x0, x1), _ = case.track
    i = int(np.argmin(np.abs(case.surface_grid.x - 0.5 * (x0 + x1))))
    return residual_field(operators, plastic_state, i)


def pass_fatigue(
    case, stress: np.ndarray, depth: np.ndarray, position: float, residual=None
) -> tuple:
    """The criteria of body 2 under the pass (module docstring).

    Parameters
    ----------
    case : Case
        A case with a ``[fatigue]`` table.
    stress : numpy.ndarray
        Shape (6, nx, ny, nz): the final tractions' field in body 2 (Pa).
    depth : numpy.ndarray
        The layers' depths (m).
    position : float
        x (m) of body 1's apex at the end of the path.
    residual : (numpy.ndarray, bool), optional
        :func:`track_residual` of an elastic-plastic body 2.

    Returns
    -------
    fields : dict
        ``dang_van_stress`` and ``crossland_stress`` (ny, nz), Pa.
    attrs : dict
        ``dang_van_factor``, ``crossland_factor`` (the smallest factors of safety) and
        ``dang_van_depth``, ``crossland_depth`` (m, where they are).
    notes : list of str
    """
    lines = residual[0] if residual is not None else None
    result, shape = steady_pass_criteria(stress, case.fatigue, lines)
    values = {
        name: getattr(result, name).reshape(shape)
        for name in (*CRITERIA, *(f"{c}_factor" for c in CRITERIA), "excess")
    }
    fields, attrs, notes = _summary(values, (depth,), "", residual is not None and residual[1])
    grid = case.surface_grid
    radius = case.reference.radius if case.reference is not None else None
    if case.grid.periodic_y:  # a line contact: Hertz's half-width
        radius = case.line_contact[0]
    if radius is not None and radius / grid.dx < PASS_CELLS:
        notes.append(
            f"fatigue: the pass is sampled at {radius / grid.dx:.3g} cells per contact radius "
            f"along x (fewer than {PASS_CELLS}): the criteria's maxima are a few per cent low; "
            "refine grid.n along x"
        )
    ahead = grid.x[-1] + 0.5 * grid.dx - position
    if radius is not None and ahead < PASS_AHEAD * radius:
        notes.append(
            f"fatigue: the field reaches {ahead / radius:.3g} contact radii ahead "
            f"of the contact (fewer than {PASS_AHEAD:g}): the pass's path is cut short; raise "
            "grid.half_width"
        )
    return fields, attrs, notes


def cycle_fatigue(
    case, stress_operator, tractions: list, residual=None, gained: float = 0.0
) -> tuple:
    """The criteria of body 2 under the last solved load cycle (module docstring).

    Parameters
    ----------
    case : Case
        A case with a ``[fatigue]`` table and a cycle block, its contact not moving.
    stress_operator : SubsurfaceStressOperator or PlaneStrainStressOperator
        Body 2's stress of surface tractions.
    tractions : list of (numpy.ndarray, numpy.ndarray, numpy.ndarray)
        (p, q_x, q_y) (Pa) at the end of each increment of the cycle, in order.
    residual : (numpy.ndarray, bool), optional
        :func:`residual_field` of an elastic-plastic body 2 at the end of the cycle.
    gained : float
        Equivalent plastic strain gained over the cycle (0 for elastic bodies).

    Returns
    -------
    fields : dict
        ``dang_van_cycle_stress`` and ``crossland_cycle_stress`` (nx, ny, nz), Pa.
    attrs : dict
        ``*_factor``, ``*_depth`` (m) and ``*_x`` (m) of each criterion.
    notes : list of str
    """
    grid = stress_operator.grid
    shape, samples = grid.shape, len(tractions)
    names = (*CRITERIA, *(f"{c}_factor" for c in CRITERIA), "excess")
    values = {name: np.empty(shape) for name in names}
    block = max(1, min(shape[2], CYCLE_BLOCK_BYTES // (48 * samples * shape[0] * shape[1])))
    for k0 in range(0, shape[2], block):  # the paths of a block of layers at once
        layers = slice(k0, min(shape[2], k0 + block))
        box = IndexBox((0, shape[0]), (0, shape[1]), (layers.start, layers.stop))
        paths = np.empty((6, samples, *box.shape))  # each sample's field contiguous
        for t, (p, *shears) in enumerate(tractions):
            shears = (q if q.any() else None for q in shears)
            paths[:, t] = stress_operator.stress(p, *shears, box=box)
        if residual is not None:
            paths += residual[0][:, None, :, :, layers]
        paths = np.moveaxis(paths.reshape(6, samples, -1), 1, 2)  # (6, points, samples)
        result = fatigue_criteria(paths, case.fatigue)
        for name in names:
            values[name][:, :, layers] = getattr(result, name).reshape(box.shape)
    missing = residual is not None and residual[1]
    fields, attrs, notes = _summary(values, (grid.surface.x, None, grid.z), "_cycle", missing)
    if samples < CYCLE_SAMPLES:
        notes.append(
            f"fatigue: the cycle is sampled at {samples} increments (fewer than "
            f"{CYCLE_SAMPLES}): between its reversals a partial slip's path bends; give more "
            "steps to the cycle's stages"
        )
    if gained > CYCLE_SHAKEN_DOWN:
        notes.append(
            f"fatigue: the last cycle gained {gained:.2g} equivalent plastic strain: it has not "
            "shaken down elastically, which the criteria assume (read the factors as a "
            "warning, not a life)"
        )
    return fields, attrs, notes


def _summary(values: dict, axes: tuple, suffix: str, missing: bool) -> tuple:
    """Fields, attributes and notes of the criteria's ``values`` (arrays over the points).

    ``axes``: the points' coordinates along each axis (m; None for y, not told), depth last;
    ``suffix`` of the fields' names; ``missing``: a residual stress was taken as zero somewhere.
    """
    fields, attrs, notes = {}, {}, []
    for name in CRITERIA:  # the attributes of solver.variables.FATIGUE_SCALARS
        fields[f"{name}{suffix}_stress"] = values[name]
        factors = values[f"{name}_factor"]
        worst = np.unravel_index(int(np.argmin(factors)), factors.shape)
        attrs[f"{name}_factor"] = float(factors[worst])
        attrs[f"{name}_depth"] = float(axes[-1][worst[-1]])
        if len(axes) == 3:  # a cycle: where along x
            attrs[f"{name}_x"] = float(axes[0][worst[0]])
    unsolved = int((values["excess"] > BALL_EXCESS).sum())
    if unsolved:  # the insertion loop cut at its cap: a ball that may not be the smallest
        notes.append(
            f"fatigue: the smallest ball of {unsolved} paths was not found within its "
            f"insertions (a point {values['excess'].max():.2g} of the radius outside): their "
            "criteria are approximate"
        )
    if missing:
        notes.append(
            "fatigue: outside the plastic box the residual stress is not computed and is taken "
            "as zero there (grid.plastic_half_width widens the box)"
        )
    return fields, attrs, notes
