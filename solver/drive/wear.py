"""Wear along the load path: each increment's worn depth added to the bodies' surfaces.

:mod:`solver.case.wear` states the laws.  The steps give, per cell, what the laws take: the
pressure times the local slip distance of the increment (``p |s|``, Archard) and the friction
energy dissipated per area (``-q . s``, the energy law), the trapezoid in time of the
increment's two ends.  The depths live on the case's surface grid (the whole track of a moving
contact, body 2's frame); their sum adds to the gap of the next increment's solves.  Under a
cycle jump (``wear.cycle_jump``) each solved cycle's wear is scaled by the cycles it stands for.

The automatic jump (``cycle_jump = "auto"``, :class:`CycleJumps`) bounds the pressure change of
each jump.  Solving cycle after cycle, the wear of a jump of J cycles is J times its solved
cycle's: explicit Euler in the cycles, dh/dN = w(p) with w the wear per cycle (Archard:
w = k p s).  Over the jump the pressure moves by dp, so the cycles it stands for wear at rates
between w(p) and w(p + dp), and the jump's error is about J (w(p + dp) - w(p)) / 2 =
(J w / 2) (dp / p) where the wear rate is proportional to the pressure.  A jump that changes
the pressure by at most a fraction eps of its peak therefore errs by at most eps / 2 of the
wear it adds, and the jumps together by eps / 2 of the deepest wear.  The change a jump of J
makes is predicted from the last solved cycle's, dp_n / J_n per cycle (the pressures at the
ends of consecutive solved cycles, their largest difference over the peak):

    J_(n+1) = min(2 J_n, max(1, floor(eps J_n / (max |p_n - p_(n-1)| / max p_n))))

the doubling a guard against a rate that has not settled.  A block's first solved cycle stands
for one cycle (its change measured from the pressure before the block).  When the block's
solved cycles (``wear.solved_cycles``) would run out first, the jumps grow to cover its cycles
and the solve says so; once the block's cycles are covered its remaining solved cycles are
skipped.
"""

from __future__ import annotations

import math

import numpy as np

from ..case.case import Case
from .steps import StepResult
from .window import shifted


class WornSurfaces:
    """The worn depths of the bodies (m) on the case's surface grid (module docstring).

    A sliding body 1's depth lives in its own frame, which travels with its apex: the case's
    grid with x - p for x (p the apex's position), moved onto body 2's frame by linear
    interpolation (:func:`moved`) where its gap is needed and where its wear is added.

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
        # the cycles each increment's cycle stands for (wear.cycle_jump): its wear scaled
        self.weights = np.repeat([s.weight for s in case.stages], [s.steps for s in case.stages])
        self.jumps = CycleJumps(case, self.weights) if self.wear.auto else None
        self.spacing = (case.surface_grid.dx, case.surface_grid.dy)
        self.travels = case.moving and 1 in self.depth  # body 1's frame moves with its apex
        self.position = (0.0, 0.0)  # the apex's position the gap was last built at (m)

    def _cells(self, position, sign: float = 1.0) -> tuple[float, float]:
        return tuple(sign * p / d for p, d in zip(position, self.spacing, strict=True))

    def _rebuild(self, position) -> None:
        """The gap's addition with body 1 at ``position`` (m): body 1's depth moved there."""
        self.position = tuple(position)
        self.gap = moved(self.depth[1], *self._cells(position))
        self.gap += self.depth.get(2, 0.0)

    def on_body2(self, body: int) -> np.ndarray:
        """Body ``body``'s depth (m) in body 2's frame (body 1 where its apex was last)."""
        if body == 1 and self.travels:
            return moved(self.depth[1], *self._cells(self.position))
        return self.depth[body]

    def place(self, operators, follower, position=(0.0, 0.0)) -> None:
        """Give the increment's operators (a window's, when it follows) the worn gap.

        ``position``: body 1's apex at the end of the increment (m), where its gap is solved.
        """
        if self.travels and tuple(position) != self.position:
            self._rebuild(position)
        operators.wear = self.gap if follower is None else follower.cut(self.gap)

    def add(
        self, outcome: StepResult, follower, cell_area: float, step: int, position=(0.0, 0.0)
    ) -> float:
        """Wear increment ``step``'s ``outcome`` into the surfaces; its worn volume (m^3).

        Scaled by the cycles the increment's cycle stands for (``wear.cycle_jump``).
        ``position``: body 1's apex halfway through the increment (m): a travelling body 1's
        wear goes into its frame from there.
        """
        driver = outcome.slid_pressure if self.wear.law == "archard" else outcome.dissipation
        if driver is None:  # nothing slipped (an unloaded or normal step)
            return 0.0
        driver = np.maximum(driver, 0.0)  # round-off of a dissipation in stick
        volume = 0.0
        for body, depth in self.depth.items():
            worn = (self.weights[step] * self.wear.coefficient(body)) * driver
            volume += float(worn.sum()) * cell_area
            if body == 1 and self.travels:
                whole = worn if follower is None else follower.on_track(worn)
                depth += moved(whole, *self._cells(position, -1.0))
                continue
            (depth if follower is None else follower.cut(depth))[...] += worn
            if not self.travels:
                (self.gap if follower is None else follower.cut(self.gap))[...] += worn
        if self.travels:
            self._rebuild(self.position)
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


class CycleJumps:
    """The automatic cycle jump of ``wear.cycle_jump = "auto"`` (module docstring).

    Parameters
    ----------
    case : Case
        A case whose ``[wear]`` jumps automatically.
    weights : numpy.ndarray
        The cycles each increment's cycle stands for (set here, cycle by cycle).
    """

    def __init__(self, case: Case, weights: np.ndarray) -> None:
        self.change = case.wear.pressure_change
        self.weights = weights
        counts = [s.steps for s in case.stages]
        self.cycles = case.step_cycles()
        self.sizes = np.repeat([s.block for s in case.stages], counts)  # N of each step's block
        self.blocks = np.repeat(_block_ids(case), counts)
        self.skipped = np.zeros(self.cycles.size, dtype=bool)
        self.forced: list[int] = []  # cycles whose jump the budget pushed past the bound
        self.reference = None  # the pressure at the last solved cycle's end (on the track)
        self.jump = 1  # the next solved cycle's jump
        self.allowed = math.inf  # the jump the bound allows at the last rate (not doubled)
        self.done = 0  # cycles of the current block stood for so far

    def _first(self, k: int) -> bool:
        return bool(self.cycles[k]) and (k == 0 or self.cycles[k - 1] != self.cycles[k])

    def skip(self, k: int, pressure) -> bool:
        """Whether increment ``k`` is skipped (its block's cycles all stood for already).

        At a solved cycle's first increment its jump is set; ``pressure()`` gives the pressure
        on the track before it (asked for at a block's start only).
        """
        if self.skipped[k] or not self._first(k):
            return bool(self.skipped[k])
        cycle = self.cycles[k]
        steps = self.cycles == cycle
        block = self.blocks[k]
        if k == 0 or self.blocks[k - 1] != block:  # a new block: its first cycle stands for
            self.reference, self.done = pressure(), 0  # one, its change measured from here
            self.jump, self.allowed = 1, math.inf
        left = self.sizes[k] - self.done
        if left == 0:  # the block is covered: its remaining solved cycles are skipped
            self.skipped |= (self.blocks == block) & (self.cycles >= cycle)
            return True
        later = int(self.cycles[self.blocks == block].max()) - cycle + 1  # solved cycles left
        jump = self.jump
        if self.allowed * later < left:  # the rate held, the budget would run out:
            jump = max(jump, int(-(-left // later)))  # spread what is left over the cycles left
            self.forced.append(int(cycle))
        jump = int(min(jump, left))
        self.weights[steps] = jump
        self.done += jump
        return False

    def cycle_end(self, k: int, pressure: np.ndarray) -> None:
        """After increment ``k``, a solved cycle's last: the next jump from its change."""
        jump = int(self.weights[k])
        peak = max(float(pressure.max()), float(self.reference.max()), 1e-300)
        change = float(np.abs(pressure - self.reference).max()) / peak
        rate = change / jump  # per cycle
        self.allowed = max(1, math.floor(self.change / rate)) if rate > 0 else math.inf
        self.jump = int(min(2 * jump, self.allowed))
        self.reference = pressure

    def note(self) -> str | None:
        """A note when the solved-cycle budget pushed jumps past the bound."""
        if not self.forced:
            return None
        return (
            f"wear.cycle_jump = auto: in {len(self.forced)} solved cycles (from cycle "
            f"{self.forced[0]}) the jumps grew past the pressure bound to cover their block "
            "within wear.solved_cycles: raise wear.solved_cycles or wear.pressure_change"
        )


def _block_ids(case: Case) -> list[int]:
    """The cycle block of every stage: 0, 1, ... in order (-1 outside blocks).

    A block's solved cycles are numbered on from the previous block's, so a block ends when
    the stages leave the blocks or its solved cycles (:meth:`Wear.solved`) are all seen.
    """
    ids, block, seen, previous = [], -1, set(), 0
    for stage in case.stages:
        if stage.cycle:
            full = len(seen) == case.wear.solved(stage.block) and stage.cycle not in seen
            if previous == 0 or full:
                block, seen = block + 1, set()
            seen.add(stage.cycle)
        ids.append(block if stage.cycle else -1)
        previous = stage.cycle
    return ids


def moved(values: np.ndarray, cells_x: float, cells_y: float) -> np.ndarray:
    """``values`` moved by fractions of cells along x and y (linear interpolation).

    The value at cell (i, j) is the input's at (i - cells_x, j - cells_y); zero where cells
    enter.
    """
    ix, iy = math.floor(cells_x), math.floor(cells_y)
    fx, fy = cells_x - ix, cells_y - iy
    out = np.zeros_like(values)
    for (dx, dy), share in (
        ((ix, iy), (1 - fx) * (1 - fy)),
        ((ix + 1, iy), fx * (1 - fy)),
        ((ix, iy + 1), (1 - fx) * fy),
        ((ix + 1, iy + 1), fx * fy),
    ):
        if share:
            out += share * shifted(values, (dx, dy), (0, 1))
    return out
