"""Wear along the load path: each increment's worn depth added to the bodies' surfaces.

:mod:`solver.case.wear` states the laws.  The steps give, per cell, what the laws take: the
pressure times the local slip distance of the increment (``p |s|``, Archard) and the friction
energy dissipated per area (``-q . s``, the energy law), the trapezoid in time of the
increment's two ends.  The depths live on the case's surface grid (the whole track of a moving
contact, body 2's frame); their sum adds to the gap of the next increment's solves.  Under a
cycle jump (``wear.cycle_jump``) each solved cycle's wear is scaled by the cycles it stands for.
"""

from __future__ import annotations

import numpy as np

from ..case.case import Case
from .steps import StepResult


class WornSurfaces:
    """The worn depths of the bodies (m) on the case's surface grid (module docstring).

    Parameters
    ----------
    case : Case
        A case with a ``[wear]`` table.
    shape : (int, int)
        The case's surface grid.
    """

    def __init__(self, case: Case, shape: tuple[int, int]) -> None:
        self.wear = case.wear
        self.depth = {body: np.zeros(shape) for body in self.wear.bodies}
        self.gap = np.zeros(shape)  # the sum over the bodies: the gap's addition
        self.volume = 0.0  # worn so far (m^3), both bodies
        # the cycles each increment's cycle stands for (wear.cycle_jump): its wear scaled
        self.weights = np.repeat([s.weight for s in case.stages], [s.steps for s in case.stages])

    def place(self, operators, follower) -> None:
        """Give the increment's operators (a window's, when it follows) the worn gap."""
        operators.wear = self.gap if follower is None else follower.cut(self.gap)

    def add(self, outcome: StepResult, follower, cell_area: float, step: int) -> float:
        """Wear increment ``step``'s ``outcome`` into the surfaces; its worn volume (m^3).

        Scaled by the cycles the increment's cycle stands for (``wear.cycle_jump``).
        """
        driver = outcome.slid_pressure if self.wear.law == "archard" else outcome.dissipation
        if driver is None:  # nothing slipped (an unloaded or normal step)
            return 0.0
        driver = np.maximum(driver, 0.0)  # round-off of a dissipation in stick
        volume = 0.0
        for body, depth in self.depth.items():
            worn = (self.weights[step] * self.wear.coefficient(body)) * driver
            (depth if follower is None else follower.cut(depth))[...] += worn
            (self.gap if follower is None else follower.cut(self.gap))[...] += worn
            volume += float(worn.sum()) * cell_area
        self.volume += volume
        return volume

    def removed_layer_note(self, layer: float) -> str | None:
        """A note when the deepest wear passes half the plastic body's top layer ``layer`` (m).

        The volume grid of an elastic-plastic body stays where it is while its surface recedes:
        the plastic strain and residual stress of the worn-off material are still counted.
        That is the small-wear approximation (the removed part of the top layer carries a part
        of the print it made); past half a layer it is told.
        """
        deepest = max(float(d.max()) for d in self.depth.values())
        if deepest <= 0.5 * layer:
            return None
        return (
            f"wear: the deepest wear ({deepest:.3g} m) passes half the plastic body's top layer "
            f"({layer:.3g} m thick), whose plastic strain and residual stress are still counted "
            "(the volume grid does not recede with the worn surface): the plastic fields near "
            "the surface are an approximation there"
        )
