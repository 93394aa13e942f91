r"""The window that follows a moving contact over body 2's track.

A sliding or rolling case covers its whole track with the case's surface grid (and body 2's
volume grid under it: the plastic strain of every earlier position and pass lives there).  An
increment, though, only needs the contact and the plastic flow it drives, both within
``grid.half_width`` of the contact.  So each increment is solved on a window of
:attr:`~solver.case.case.Case.moving_window` cells of the same grid, placed at the contact
(whole cells: it covers the contacts at both ends of the increment), with the window's own
operators (:attr:`~solver.drive.operators.CaseOperators.local`, kernels built once):

* the contact state of the last increment is moved into the new window (tractions by whole
  cells; the displacements they cause recomputed there: the convolutions are exact for
  tractions inside a window);
* body 2's plastic strain under the window is the plasticity loop's; what it does not change
  enters as the residual stress and surface displacement of the whole track's plastic strain
  at the start of the increment (:attr:`~solver.drive.plastic_loop.PlasticState.frozen_stress`,
  the loop adding those of the increment alone: linear superposition);
* after the increment the window's plastic strain goes back into the track's, whose residual
  stress and surface displacement are evaluated once (the track's operators): the frozen
  fields of the next increment.

Exact for elastic cases (to round-off); with plasticity the increment's residual stress is the
window's, whose Boussinesq correction drops the surface normal stress outside the window
(:mod:`solver.volume.eigenstrain`), small at ``grid.half_width`` from the contact, and plastic flow
must stay inside the window (its sides are checked: :meth:`Follower.sides_reached`).
``grid.follow_contact = false`` solves every increment on the whole track instead.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ..numerics.grid import SurfaceGrid
from ..variables import PLASTIC_ZONE_THRESHOLD
from .operators import CaseOperators
from .plastic_loop import PlasticState
from .steps import ContactState, position_of


def shifted(values: np.ndarray, cells: tuple[int, ...], axes: tuple[int, ...]) -> np.ndarray:
    """``values`` moved by ``cells[k]`` cells along ``axes[k]``, zero where cells enter."""
    out = np.zeros_like(values)
    src = [slice(None)] * values.ndim
    dst = [slice(None)] * values.ndim
    for axis, count in zip(axes, cells, strict=True):
        n = values.shape[axis]
        if abs(count) >= n:
            return out
        src[axis] = slice(max(-count, 0), n - max(count, 0))
        dst[axis] = slice(max(count, 0), n - max(-count, 0))
    out[tuple(dst)] = values[tuple(src)]
    return out


class Follower:
    """Places the window of a moving case at every increment and keeps the track's fields.

    Parameters
    ----------
    operators : CaseOperators
        The case's bundle, with its :attr:`~CaseOperators.local` window bundle.

    Attributes
    ----------
    offset : (int, int)
        Index of the window's first cell in the track's grid.
    frozen : ndarray or None
        Deviatoric residual stress (Pa) of the track's plastic strain in its volume grid, or
        None (no plastic strain yet).
    lost : bool
        True once an increment's tractions did not fit the window they moved into.
    """

    def __init__(self, operators: CaseOperators):
        self.track = operators
        self.local = operators.local
        self.case = operators.case
        self.grid = self.case.surface_grid
        self.shape = self.local.surface.grid.shape
        self.offset = self._offset((0.0, 0.0), (0.0, 0.0))
        self.frozen: np.ndarray | None = None
        self.lost = False

    def _offset(self, start: tuple, end: tuple) -> tuple[int, int]:
        """First cell of the window centred on the middle of ``start`` and ``end`` (m)."""
        out = []
        for axis, (n, d, coordinates) in enumerate(
            ((self.grid.nx, self.grid.dx, self.grid.x), (self.grid.ny, self.grid.dy, self.grid.y))
        ):
            middle = 0.5 * (start[axis] + end[axis])
            # cells from the centred placement ((n - m) / 2, whole: same parity), rounded
            # half away from the track's middle so that a mirrored path mirrors the window
            room = (n - self.shape[axis]) // 2
            cells = (middle - 0.5 * (coordinates[0] + coordinates[-1])) / d
            first = room + int(math.copysign(math.floor(abs(cells) + 0.5), cells))
            out.append(min(max(first, 0), n - self.shape[axis]))
        return out[0], out[1]

    def _slices(self, offset: tuple[int, int]) -> tuple[slice, slice]:
        return (
            slice(offset[0], offset[0] + self.shape[0]),
            slice(offset[1], offset[1] + self.shape[1]),
        )

    def unloaded(self) -> ContactState:
        """The state before the first increment, on the window."""
        return ContactState.unloaded(self.shape)

    def operators(self, offset: tuple[int, int]) -> CaseOperators:
        """The window's bundle placed at ``offset``."""
        sx, sy = self._slices(offset)
        x, y = self.grid.x[sx], self.grid.y[sy]
        grid = SurfaceGrid(
            self.shape[0], self.shape[1], self.grid.dx, self.grid.dy,
            (0.5 * (x[0] + x[-1]), 0.5 * (y[0] + y[-1])),
        )  # fmt: skip
        return self.local.at(grid)

    def enter(
        self,
        state: ContactState,
        plastic: tuple[PlasticState, ...],
        start: tuple,
        target: tuple,
    ) -> tuple[CaseOperators, ContactState, tuple[PlasticState, ...], tuple[int, int]]:
        """The window of the increment from ``start`` to ``target`` and what it starts from.

        Returns the window's bundle, the last state moved into it, body 2's plastic state on
        it (with the frozen fields of the track's strain) and the whole cells it moved by.
        """
        begin, end = position_of(start), position_of(target)
        loaded = state.pressure.any()
        offset = self._offset(begin, end) if loaded else self._offset(end, end)
        di, dj = offset[0] - self.offset[0], offset[1] - self.offset[1]
        self.offset = offset
        operators = self.operators(offset)
        if di or dj:
            state = self._moved_state(state, di, dj, operators)
        if plastic:
            state = dataclasses.replace(
                state, residual_x=self.cut(plastic[0].displacement[0]),
                residual_y=self.cut(plastic[0].displacement[1]),
            )  # fmt: skip
        return operators, state, tuple(self._local(p) for p in plastic), (di, dj)

    def _moved_state(
        self, state: ContactState, di: int, dj: int, operators: CaseOperators
    ) -> ContactState:
        """``state`` in the window moved by (di, dj) cells.

        Tractions moved, the displacements they cause recomputed (no traction may leave:
        :attr:`lost` otherwise).
        """
        back, axes = (-di, -dj), (0, 1)  # the window moved on: its fields move back
        pressure = shifted(state.pressure, back, axes)
        shear_x = shifted(state.shear_x, back, axes)
        shear_y = shifted(state.shear_y, back, axes)
        kept = sum(float(np.abs(v).sum()) for v in (pressure, shear_x, shear_y))
        total = sum(float(np.abs(v).sum()) for v in (state.pressure, state.shear_x, state.shear_y))
        if kept < total * (1.0 - 1e-12):
            self.lost = True
        if self.case.pair.dundurs_beta and pressure.any():
            slip = operators.surface.tangential_from_pressure(pressure)
        else:
            slip = (np.zeros_like(pressure), np.zeros_like(pressure))
        return dataclasses.replace(
            state, pressure=pressure, shear_x=shear_x, shear_y=shear_y,
            pressure_slip_x=slip[0], pressure_slip_y=slip[1], shear_slip_x=None,
            shear_slip_y=None, normal=None,
        )  # fmt: skip

    def cut(self, values: np.ndarray) -> np.ndarray:
        """The window's part of a track field whose last two axes are x, y (a view)."""
        sx, sy = self._slices(self.offset)
        return values[..., sx, sy]

    def _cut_volume(self, values: np.ndarray | None) -> np.ndarray | None:
        """The window's part of a volume field ``(..., nx, ny, nz)`` (a view), or None."""
        if values is None:
            return None
        sx, sy = self._slices(self.offset)
        return values[..., sx, sy, :]

    def _local(self, plastic: PlasticState) -> PlasticState:
        frozen = self._cut_volume(self.frozen)
        if frozen is None:
            frozen = np.zeros_like(self._cut_volume(plastic.strain))
        return PlasticState(
            self._cut_volume(plastic.strain),
            self._cut_volume(plastic.equivalent),
            tuple(self.cut(u) for u in plastic.displacement),
            self._cut_volume(plastic.back_stress),
            frozen,
        )

    def leave(
        self, track: tuple[PlasticState, ...], window: tuple[PlasticState, ...]
    ) -> tuple[PlasticState, ...]:
        """The track's plastic state after an increment solved on the window.

        The window's plastic strain goes back into the track's; the residual displacement and
        the frozen residual stress of the whole are evaluated once (the track's operators).
        """
        out = []
        for old, new in zip(track, window, strict=True):
            if not (new.strain - self._cut_volume(old.strain)).any():
                out.append(old)  # no plastic flow in this increment
                continue
            fields = {}
            for name in ("strain", "equivalent", "back_stress"):
                values = getattr(old, name)
                if values is not None:
                    values = values.copy()
                    self._cut_volume(values)[...] = getattr(new, name)
                elif getattr(new, name) is not None:  # kinematic hardening begins
                    values = np.zeros_like(old.strain)
                    self._cut_volume(values)[...] = getattr(new, name)
                fields[name] = values
            eigenstrain = self.track.eigenstrain
            layers = eigenstrain.layer_spectra(fields["strain"])
            displacement = eigenstrain.displacement_from_layers(layers)
            self.frozen = eigenstrain.deviatoric_stress_with_tractions(
                fields["strain"], layers, {}, consume=True
            )
            out.append(
                PlasticState(
                    fields["strain"], fields["equivalent"], displacement, fields["back_stress"]
                )
            )
        return tuple(out)

    def sides_reached(self, before: PlasticState, after: PlasticState) -> list[str]:
        """Sides of the window where the increment's plastic strain passes the zone threshold.

        Only the sides inside the track (its own are the track box's faces): the flow the
        window cut off.
        """
        gained = after.equivalent - before.equivalent
        sides = []
        for axis, name in ((0, "x"), (1, "y")):
            first = self.offset[axis] > 0
            last = self.offset[axis] + self.shape[axis] < self.grid.shape[axis]
            ends = [index for index, inner in ((0, first), (-1, last)) if inner]
            if ends and np.take(gained, ends, axis=axis).max() > PLASTIC_ZONE_THRESHOLD:
                sides.append(name)
        return sides

    def on_track(self, values: np.ndarray) -> np.ndarray:
        """A window field ``(nx, ny)`` on the whole track's grid (zero outside the window)."""
        out = np.zeros(self.grid.shape, dtype=values.dtype)
        out[self._slices(self.offset)] = values
        return out
