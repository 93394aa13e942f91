"""Load sub-steps of coupled scenes: how a load increment is split while the contact grows.

With Dundurs' beta != 0 the normal and tangential problems are coupled and the solution depends
on the path; an increment that doubles the load labels the new contact ring as a one-shot solve
would.  So an increment of a coupled scene that raises W by more than ``solver.max_load_ratio``
is solved in geometric sub-steps (:func:`load_substeps`), starting no lower than the load whose
contact the grid still resolves (:func:`substep_floor`).  The solve (:mod:`solver.drive.loops`)
and the cost model (``study.campaign.cost``) both count them from here.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from .case import Case

#: First sub-step of a coupled scene loaded from zero, as a fraction of the first target.
FIRST_SUBSTEP_FRACTION = 1.0 / 64.0
#: Smallest Hertz contact radius (cells) of a sub-step: a contact one cell wide is not a
#: contact problem the grid can solve (the normal solve stalls on it).
MIN_SUBSTEP_RADIUS_CELLS = 2.0


def _plan(w0: float, w1: float, max_ratio: float, smallest: float) -> tuple[float, int]:
    """First load of the geometric sequence and its number of terms (0: no sub-steps)."""
    if not math.isfinite(max_ratio) or w1 <= w0 * max_ratio:
        return 0.0, 0
    start = w0 if w0 > 0 else min(max(w1 * FIRST_SUBSTEP_FRACTION, smallest), w1 / max_ratio)
    return start, math.ceil(math.log(w1 / start) / math.log(max_ratio))


def load_substeps(
    previous: tuple, target: tuple, max_ratio: float, smallest: float = 0.0
) -> list[tuple]:
    """Intermediate (W, Q_x, Q_y, ...) targets so that W grows by at most ``max_ratio`` per step.

    The sub-steps are geometric in W (from :data:`FIRST_SUBSTEP_FRACTION` of the target when
    loading from zero, but not below ``smallest`` (N), a load whose contact the grid still
    resolves) with the other components interpolated linearly in W; ``target`` itself is not
    included, nor ``previous``.
    """
    w0, w1 = previous[0], target[0]
    start, count = _plan(w0, w1, max_ratio, smallest)
    if not count:
        return []
    loads = start * (w1 / start) ** (np.arange(count) / count)
    if w0 > 0:
        loads = loads[1:]
    out = []
    for w in loads:
        f = (w - w0) / (w1 - w0)
        out.append(
            (float(w), *(p + f * (t - p) for p, t in zip(previous[1:], target[1:], strict=True)))
        )
    return out


def substep_floor(case: Case) -> float:
    """The load (N) whose reference contact radius spans :data:`MIN_SUBSTEP_RADIUS_CELLS`.

    Hertz's radius grows as W^(1/3); a profile's load at that radius comes from its geometry.
    """
    grid, pair = case.surface_grid, case.pair
    resolved = MIN_SUBSTEP_RADIUS_CELLS * max(grid.dx, grid.dy)  # (m)
    if pair.geometry.hertzian:
        return case.max_normal_force * min(1.0, resolved / case.reference.radius) ** 3
    force = pair.geometry.force_at_radius(resolved, pair.composite_modulus)
    return min(case.max_normal_force, force)


def substep_count(case: Case, smallest: float) -> int:
    """Load sub-steps the solve of a coupled ``case`` adds (none while the contact moves)."""
    ratio = case.solver.max_load_ratio
    previous = (0.0, 0.0, 0.0, 0.0, 0.0)
    found = 0
    for target in case.step_targets():
        if target[3:] == previous[3:]:
            start, count = _plan(previous[0], target[0], ratio, smallest)
            found += count - 1 if count and previous[0] > 0 else count
        previous = target
    return found
