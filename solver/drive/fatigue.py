"""Body 2's fatigue under a steady pass: the criteria of the solved contact's field.

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
"""

from __future__ import annotations

import numpy as np

from ..fatigue.criteria import CRITERIA, steady_pass_criteria

#: Cells per contact radius along x under which the pass's sampling is told (Crossland's
#: maximum of a Hertz pass: 2.6 % low at 6, 0.63 % at 12, 2026-12-06).
PASS_CELLS = 10
#: Contact radii of the field ahead of the contact under which the pass is told cut short.
PASS_AHEAD = 3.0
#: A path's farthest point outside its ball, relative to the radius, above which the ball is
#: told not found (:func:`solver.fatigue.ball.smallest_balls`; round-off is about 1e-15).
BALL_EXCESS = 1e-8


def track_residual(case, operators, plastic_state) -> tuple[np.ndarray, bool]:
    """Body 2's residual stress (6, ny, nz) on the x-slice at the middle of the track (Pa).

    The residual stress of a steady track does not change along it; away from its ends the
    middle's stands for it.  Outside the plastic box it is not computed and taken as zero
    (the second value is True where that happened to a line).
    """
    eigenstrain = operators.volume(2)[1]
    strain = plastic_state[0].strain
    residual = eigenstrain.evaluate(strain)[0] if strain.any() else np.zeros_like(strain)
    residual = eigenstrain.on_window(residual, np.nan)
    (x0, x1), _ = case.track
    grid = case.surface_grid
    i = int(np.argmin(np.abs(grid.x - 0.5 * (x0 + x1))))
    line = residual[:, i]
    missing = bool(np.isnan(line).any())
    return np.nan_to_num(line, nan=0.0), missing


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
    fields, attrs = {}, {}
    for name in CRITERIA:  # the attributes of solver.variables.FATIGUE_SCALARS
        values = getattr(result, name).reshape(shape)
        factors = getattr(result, f"{name}_factor").reshape(shape)
        fields[f"{name}_stress"] = values
        worst = np.unravel_index(int(np.argmin(factors)), shape)
        attrs[f"{name}_factor"] = float(factors[worst])
        attrs[f"{name}_depth"] = float(depth[worst[1]])
    notes = []
    unsolved = int((result.excess > BALL_EXCESS).sum())
    if unsolved:  # the insertion loop cut at its cap: a ball that may not be the smallest
        notes.append(
            f"fatigue: the smallest ball of {unsolved} paths was not found within its "
            f"insertions (a point {result.excess.max():.2g} of the radius outside): their "
            "criteria are approximate"
        )
    if residual is not None and residual[1]:
        notes.append(
            "fatigue: outside the plastic box the residual stress is not computed and is taken "
            "as zero on those lines (grid.plastic_half_width widens the box)"
        )
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
