"""Case specification: a frozen, validated description of one contact simulation.

A case is built from a TOML table or a dict (SI units) with :meth:`Case.from_dict` /
:meth:`Case.from_toml`; every rule is checked at this boundary and a violation raises
:class:`SpecError` naming the field and what to change.  :meth:`Case.to_dict` gives the
normalised table (floats where floats are meant, defaults filled in), whose hash is the case id,
so ``1`` and ``1.0`` give the same id.

Each table is parsed by the module of :mod:`solver.case` that holds it (:mod:`.bodies`,
:mod:`.path`, :mod:`.grid`, :mod:`.options`); here they are put together, the rules that join
tables are checked, the window and the plastic box are sized (:mod:`.volume`, :mod:`.sizing`),
the notes are gathered (:mod:`.notes`), and :class:`Case` derives the grids, the reference
contact and the increments from the validated values.
"""

from __future__ import annotations

import functools
import json
import math
import tomllib
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..bodies.materials import Body, Pair
from ..keys import (
    MAX_CREEPAGE,
    SOLVER_DEFAULTS,
    required_keys,
    table_keys,
)
from ..numerics.grid import IndexBox, SurfaceGrid, VolumeGrid, fft_size
from ..theory.hertz import HertzContact, hertz
from ..theory.line import hertz_line
from ..theory.sneddon import SneddonContact
from .batch import NO_TABLE, SharedTables, case_hash
from .bodies import body_spec, check_surfaces, parse_body
from .fatigue import FatigueLimits, check_fatigue_case, parse_fatigue
from .friction import Friction, limit_reached_note, parse_friction, sizing_ratio
from .grid import GridSpec, check_resolution, domain_half_widths, parse_grid
from .notes import (
    check_line_scene,
    check_periodic_load,
    check_periodic_scene,
    check_periodic_volume,
    check_plastic_scene,
    check_static_shakedown,
    check_steady_scene,
    layer_note,
    periodic_slide_note,
    rolling_step_note,
    scale_note,
    surface_shear_note,
    window_note,
    window_unbuilt,
)
from .options import (
    FIELD_OUTPUTS,
    ID_SILENT_DEFAULTS,
    METHOD_KEYS,
    SOLVER_RULES,
    SolverOptions,
    parse_solver,
)
from .path import (
    LoadStage,
    check_driven_stages,
    check_mean_pressure,
    creep_ramp,
    parse_path,
    parse_stage,
    slides,
    swap_rolling,
    symmetric_pair,
    tangential_load,
)
from .reading import SurfaceReader, check_keys, entries, fail, json_number, plain
from .sizing import (
    periodic_depth,
)
from .volume import size_open_volume
from .wear import Wear, check_wear_case, parse_wear

#: Version of the physical model: part of every case id, so that files computed by an older
#: model are never reused.  A case records the version of the last change that alters its
#: solution (:func:`case_model`), so a change reaches only the ids of the cases it alters.
#: Version 1: elastic-plastic bodies solved as elastic; 2: a plastic increment whose loop did
#: not converge was kept as it was, where 3 halves it, and a sliding increment's friction work
#: missed the step after a reversal (3 alters every case); then :data:`MODEL_CHANGES`.
MODEL_VERSION = 7
#: The oldest version a case may be solved by (the last change that altered every case).
OLDEST_MODEL = 3
#: The changes after :data:`OLDEST_MODEL`: version -> what it alters (:func:`case_model`).
MODEL_CHANGES = {
    4: "a transient roll's spin turns body 1 about the contact's position at the end of each "
    "increment, no longer about the travel's midpoint",
    5: "static_shakedown certifies Melan's lower bound between the program's points and "
    "positions (static_shakedown_lower_bound), which shakedown_load_factor now follows",
    6: "a case with friction on a body of bounded flow stress ends at the first increment whose "
    "surface shear passes the body's shear limit (status surface_flow) instead of solving on",
    7: "a plasticity loop, or a slip-stick loop coupling the pressure and the shear (beta != 0 "
    "with friction), that makes no progress over 25 iterations stops there, told (a plastic "
    "increment keeps its best iterate and is halved), instead of iterating on to its cap",
}


def case_model(stages: Sequence[LoadStage], method: str, iterated: bool = False) -> int:
    """The model version that solves a case as this code does (:data:`MODEL_CHANGES`).

    ``method`` is ``solver.method``; ``iterated``: a plasticity loop (an elastic-plastic
    body) or a slip-stick loop coupling pressure and shear solves its increments (version 7
    holds every change of version 6, to the cases whose friction may make the surface flow).
    """
    if method == "static_shakedown":
        return 5
    if iterated:
        return 7
    if any(stage.motion == "roll" and stage.spin for stage in stages):
        return 4
    return OLDEST_MODEL


def _parser(shared: SharedTables | None) -> Callable[[str, Any, Callable], Any]:
    """``parse(kind, table, parser)``: ``parser(table)``, once per shared table with ``shared``."""
    return shared.parse if shared is not None else lambda kind, table, parser: parser(table)


def _body(read_surface: SurfaceReader | None, path: str) -> Callable[[Any], tuple[Body, dict]]:
    """A ``[bodyN]`` table's parser: the body and its normalised table."""

    def parse(table: Any) -> tuple[Body, dict]:
        body = parse_body(table, path, read_surface)
        return body, body_spec(body)

    return parse


def _solver(table: Any) -> tuple[SolverOptions, dict]:
    """The options of a ``[solver]`` table and their normalised table.

    FFT threads and planner are kept (a campaign's cases are solved from this table) but
    change no result beyond round-off: not in the case id (EXECUTION_KEYS); the keys added
    later only when not their default (the older cases' ids stay).
    """
    solver = parse_solver(table)
    spec = {
        k: json_number(getattr(solver, k))
        for k in SOLVER_RULES
        if (
            METHOD_KEYS[k] == solver.method
            if k in METHOD_KEYS
            else getattr(solver, k) != SOLVER_DEFAULTS[k] or k not in ID_SILENT_DEFAULTS
        )
    }
    return solver, spec


def _output(table: Any) -> tuple[tuple[str, ...], dict]:
    """The field outputs of an ``[output]`` table (sorted) and its normalised table."""
    output = check_keys(table, "output", table_keys("output"))
    form = f"a list drawn from {list(FIELD_OUTPUTS)}"
    fields = [plain(f) for f in entries(output.get("fields", []), "output.fields", form)]
    if any(not isinstance(f, str) or f not in FIELD_OUTPUTS for f in fields):
        fail("output.fields", f"must be a list drawn from {list(FIELD_OUTPUTS)}")
    return tuple(sorted(fields)), {"fields": sorted(fields)}


@dataclass(frozen=True)
class Case:
    """One validated contact simulation.  Build it with :meth:`from_dict` or :meth:`from_toml`.

    Attributes
    ----------
    body1, body2 : Body
        Upper (indenter) and lower bodies.
    stages : tuple of LoadStage
        Load path.
    friction_coefficient : float
        Coulomb coefficient mu (dimensionless).
    grid : GridSpec
        Discretisation.
    solver : SolverOptions
        Tolerances and iteration caps.
    fields : tuple of str
        Optional field outputs.
    spec : dict
        The normalised table (SI units); its hash is :attr:`case_id`.
    warnings : tuple of str
        What the case is built with but should be read with care (a plastic zone past the
        contained regime, :func:`plastic_index`); the solve repeats them in its notes.
    friction : Friction
        The friction law: ``friction_coefficient`` and the shear limit that caps it.
    wear : Wear or None
        ``[wear]``: the wear laws of the bodies.
    fatigue : FatigueLimits or None
        ``[fatigue]``: body 2's fatigue limits, its criteria under the pass.
    """

    body1: Body
    body2: Body
    stages: tuple[LoadStage, ...]
    friction_coefficient: float
    grid: GridSpec
    solver: SolverOptions
    fields: tuple[str, ...] = ()
    spec: dict = field(default_factory=dict, compare=False, hash=False, repr=False)
    warnings: tuple[str, ...] = field(default=(), compare=False, hash=False, repr=False)
    friction: Friction = Friction()
    wear: Wear | None = None
    fatigue: FatigueLimits | None = None

    # -- construction -----------------------------------------------------------------------
    @classmethod
    def from_toml(cls, path: str | Path, read_surface: SurfaceReader | None = None) -> Case:
        """Read and validate a case file (TOML); ``read_surface`` as in :meth:`from_dict`."""
        with open(path, "rb") as handle:
            return cls.from_dict(tomllib.load(handle), read_surface)

    @classmethod
    def from_dict(
        cls,
        table: dict,
        read_surface: SurfaceReader | None = None,
        shared: SharedTables | None = None,
    ) -> Case:
        """Validate a case table (see the README for the format) and build the case.

        ``read_surface`` reads the height-map files the bodies name (``bodyN.surface``):
        ``study.campaign.surfaces.read_surface``; without it such a case is refused.
        ``shared`` (:class:`~solver.case.batch.SharedTables`) parses the sub-tables that a
        batch of tables built from one base shares once; the case is the same without it.

        Raises
        ------
        SpecError
            If any field is missing, unknown, of the wrong type or non-physical.

        Notes
        -----
        Numpy scalars (``np.int64``, ``np.float32``, ``np.bool_``, ...) are taken as the Python
        values they hold; a list (a pair of numbers, ``grid.n``, ``output.fields``) may be given
        as a list, a tuple or a 1-D numpy array alike (the same case id), a file name as a
        string or a path, a roughness as its table or a :class:`~solver.bodies.heights.Roughness`; a
        boolean is never a number.
        """
        if isinstance(table, dict) and "base" in table:  # a campaign table, not a case's
            fail(
                "base",
                "this is a campaign ([base] with [sweep], [zip] or [sample]), not one case: run "
                "it with python -m study validate / run FILE, or give a case's own tables "
                "(body1, body2, load, grid, ...)",
            )
        check_keys(table, "", table_keys(""), required_keys(""))
        model = table.get("model", MODEL_VERSION)
        if model not in range(OLDEST_MODEL, MODEL_VERSION + 1) or isinstance(model, bool):
            fail(
                "model",
                f"this case was written by model version {model!r}; this solver is "
                f"version {MODEL_VERSION}: remove the key to solve it with the current model",
            )
        parse = _parser(shared)
        body1, body1_spec = parse("body1", table["body1"], _body(read_surface, "body1"))
        body2, body2_spec = parse("body2", table["body2"], _body(read_surface, "body2"))
        if body1.rigid and body2.rigid:
            fail("body2.behaviour", "both bodies are rigid; make at least one elastic")
        pair = Pair(body1, body2)
        kx, ky = pair.curvature
        geometry = pair.geometry
        grid = parse("grid", table["grid"], parse_grid)
        if grid.periodic_y:
            pass  # a line contact: check_line_scene below, with the stages
        elif geometry.profiles:
            if kx != ky:
                which = "body1" if body1.profile is None else "body2"
                fail(
                    f"{which}.radius_x",
                    "with a profile the pair must stay axisymmetric: give the other body a "
                    "radius (or none), not radius_x / radius_y",
                )
        elif kx > 0 or ky > 0 or not geometry.surfaces:
            if grid.periodic and not geometry.surfaces:
                fail(
                    "grid.periodic",
                    "a periodic domain is one period of a rough flat surface: give body 1 or "
                    "body 2 a roughness table or a surface (a height map); radii are refused "
                    "there (a smooth sphere: leave grid.periodic out)",
                )
            if not (kx > 0 and ky > 0):
                fail(
                    "body1.radius",
                    "both bodies are flat in x or y; give a finite radius (a cylinder along y: "
                    'radius_x with grid.periodic = "y")',
                )
            if max(kx, ky) / min(kx, ky) > 100:
                fail("body1.radius_x", "contact ellipse too slender (R_x/R_y beyond 1:100)")

        wear = parse_wear(table["wear"]) if "wear" in table else None
        fatigue = parse_fatigue(table["fatigue"]) if "fatigue" in table else None
        load = table["load"]
        if not isinstance(load, dict):
            fail("load", "must be a table")
        if "path" in load:
            check_keys(load, "load", {"path"})
            raw_stages = load["path"]
            if isinstance(raw_stages, tuple):  # a tuple of tables as a list (one spelling)
                raw_stages = list(raw_stages)
            if not isinstance(raw_stages, list) or not raw_stages:
                fail("load.path", "must be a non-empty array of tables ([[load.path]])")
            stages, paths, given = parse_path(raw_stages, pair, wear)
        else:
            stage, spec = parse_stage(load, "load", (0.0, (0.0, 0.0), False), pair, True)
            stages, paths, given = [stage], ["load"], [spec]

        has_plastic = "elastic-plastic" in (body1.behaviour, body2.behaviour)
        friction, friction_notes = parse_friction(table.get("friction", {}), has_plastic)
        mu = friction.coefficient
        for stage, path in zip(stages, paths, strict=True):
            q = math.hypot(*stage.tangential_force)
            if q > 0 and q >= mu * stage.normal_force:
                fail(
                    f"{path}.tangential_force",
                    f"|Q| = {q:g} N reaches mu W = {mu * stage.normal_force:g} N: gross sliding; "
                    "lower the tangential force or raise friction.coefficient",
                )

        if geometry.reference_kind is None:
            if grid.size is None:
                fail(
                    "grid.size",
                    "no body has a smooth shape (radius or profile) whose contact radius could "
                    "scale the domain: give the domain's sides in metres, grid.size = [Lx, Ly]",
                )
            if grid.nz and not (grid.periodic or grid.periodic_y):
                fail(
                    "grid.n",
                    "a volume grid is scaled by the smooth shape's contact radius; with heights "
                    "only give grid.n = [nx, ny] (a periodic rough surface has one: "
                    "grid.periodic = true)",
                )
            for stage, path in zip(stages, paths, strict=True):
                check_mean_pressure(stage.normal_force, pair, grid.size, f"{path}.normal_force")
        moving = slides(stages)
        if any(stage.motion == "slide" for stage in stages) and not body1.rigid:
            fail(
                "body1.behaviour",
                "sliding takes a rigid body 1 in this release (an elastic body 1's surface "
                "moves with it: its displacements would have to follow the apex); make body 1 "
                "rigid, or roll",
            )
        rolls = any(stage.motion == "roll" for stage in stages)
        if rolls and (math.isfinite(body2.radius_x) or math.isfinite(body2.radius_y)):
            fail(
                "body2.radius",
                "a rolling contact moves over body 2, whose curvature would stay where it is: "
                "give body 2 flat and body 1 the pair's radius (1/R = 1/R1 + 1/R2 along each "
                "axis), which the half-space contact sees alike",
            )
        scene = "with an elastic-plastic body" if has_plastic else ""
        scene = "in periodic mode (grid.periodic)" if grid.periodic else scene
        check_driven_stages(stages, paths, mu, pair, scene)
        check_periodic_scene(body1, body2, stages, mu, grid)
        check_line_scene(body1, body2, stages, paths, grid)
        check_plastic_scene(body1, body2, stages, grid)
        plastics = [b for b in (body2, body1) if b.behaviour == "elastic-plastic"]
        plastic = plastics[0] if plastics else None
        force, e_star = max(stage.normal_force for stage in stages), pair.composite_modulus
        hertzian_plastic = plastics and geometry.hertzian  # else a profile (check_plastic_scene)
        p_max = hertz(force, e_star, (kx, ky)).max_pressure if hertzian_plastic else math.nan
        ratio = max(  # unloaded stages carry no tangential force (checked above)
            (
                math.hypot(*st.tangential_force) / st.normal_force
                for st in stages
                if st.normal_force
            ),
            default=0.0,
        )
        if any(st.motion == "slide" for st in stages):  # gross sliding: |Q| = mu W
            ratio = max(ratio, mu)
        if not symmetric_pair(body1, body2, stages):  # the friction the zone grows under
            limits = [b.hardening.shear_limit for b in plastics]
            ratio = sizing_ratio(friction, ratio, p_max, limits)
        box_key = None  # grid.plastic_half_width as the case's spec records it
        warnings = list(friction_notes)
        if grid.periodic and plastic is not None:
            check_periodic_load(plastic, force / (grid.size[0] * grid.size[1]))
            grid, region = periodic_depth(grid, pair, force, ratio, plastic)
            given_key = "grid.depth" if "depth" in table["grid"] else "grid.n"
            note = check_periodic_volume(grid.depth, grid.nz, region, min(grid.size), given_key)
            warnings += [note] if note else []
        elif not grid.periodic:
            grid, box_key, notes = size_open_volume(
                table["grid"], grid, pair, stages, paths, force, ratio, p_max, moving
            )
            warnings += notes
        solver, solver_spec = parse("solver", table.get("solver", NO_TABLE), _solver)
        coupled = mu > 0 and pair.dundurs_beta != 0 and not solver.goodman
        version = case_model(stages, solver.method, bool(plastics) or coupled)
        if model < version:
            fail(
                "model",
                f"this case was written by model version {model}, and version {version} "
                f"changed how it is solved ({MODEL_CHANGES[version]}): remove the key to solve "
                "it with the current model",
            )
        if solver.method == "static_shakedown" and friction.shear_limit is not None:
            fail(
                "friction.shear_limit",
                "static_shakedown loads the surface with Hamilton's sliding field, shear mu p "
                "everywhere: the theorems take no shear limit; leave it out",
            )
        if solver.method == "static_shakedown" and "residual_print" in table.get("solver", {}):
            fail(
                "solver.residual_print",
                "static_shakedown follows no load path: the theorem takes the unchanging "
                "surface of the classical theorems; leave the key out",
            )
        check_steady_scene(stages, plastic, grid, "steady_order" in table.get("solver", {}))
        for key, method in METHOD_KEYS.items():
            if solver.method != method and key in table.get("solver", {}):
                fail(f"solver.{key}", f'only solver.method = "{method}" takes it: leave it out')
        if solver.residual_print == "ignored" and plastic is None:
            fail(
                "solver.residual_print",
                "only an elastic-plastic body leaves a print to ignore: leave the key out",
            )
        if wear is not None:
            check_wear_case(wear, stages, mu)
        if fatigue is not None:
            plastic1 = body1.behaviour == "elastic-plastic"
            check_fatigue_case(stages, bool(grid.nz), grid.periodic, plastic1)
        fields, output_spec = parse("output", table.get("output", NO_TABLE), _output)
        if "stress" in fields and not grid.nz:
            fail("output.fields", "stress needs a volume grid: give grid.n = [nx, ny, nz]")
        if "stress" in fields and plastic is body1 and body1 != body2:
            fail(
                "output.fields",
                "stress is computed in body 2; with an elastic-plastic body 1 the volume is body "
                "1's: request residual_stress or plastic_strain_tensor instead",
            )
        if "stress" in fields and body2.rigid:
            fail("output.fields", "stress is computed in body 2, which is rigid here")
        for name in ("plastic_strain_tensor", "residual_stress"):
            if name in fields and plastic is None:
                fail("output.fields", f"{name} needs an elastic-plastic body")

        spec = {
            "model": version,
            "body1": body1_spec,
            "body2": body2_spec,
            "load": {"path": given},
            "friction": friction.spec(),
            "grid": {
                "n": [grid.nx, grid.ny] + ([grid.nz] if grid.nz else []),
                **({"size": list(grid.size)} if grid.size else {"half_width": grid.half_width}),
                **({"depth": grid.depth} if grid.nz else {}),
                **({"depth_body1": grid.depth_body1} if grid.depth_body1 else {}),
                **({"plastic_half_width": box_key} if box_key is not None else {}),
                **({"follow_contact": grid.follow_contact} if moving else {}),
                **({"periodic": True} if grid.periodic else {}),
                **({"periodic": "y"} if grid.periodic_y else {}),
            },
            "solver": solver_spec,
            "output": output_spec,
            **({"wear": wear.spec()} if wear is not None else {}),
            **({"fatigue": fatigue.spec()} if fatigue is not None else {}),
        }
        case = cls(body1, body2, tuple(stages), mu, grid, solver, fields, spec, tuple(warnings),
                   friction, wear, fatigue)  # fmt: skip
        case.__dict__["pair"] = pair  # the cached Case.pair: the same bodies, built once
        check_resolution(case)
        check_surfaces(case)
        if solver.method == "static_shakedown":  # no loops: the theorem's own notes
            notes = check_static_shakedown(case)
        else:
            hertzian = case.reference is not None and case.pair.geometry.hertzian
            peak = case.reference.max_pressure if hertzian else math.nan  # a profile: none
            notes = (
                layer_note(case), surface_shear_note(case), window_note(case),
                periodic_slide_note(case), rolling_step_note(case), scale_note(case),
                limit_reached_note(friction, mu * peak),
            )  # fmt: skip
            notes = tuple(filter(None, notes))
        if notes:  # the case is not yet given out: its cached quantities stay
            object.__setattr__(case, "warnings", (*case.warnings, *notes))
        for stage, path in zip(stages, paths, strict=True):
            reach = abs(stage.spin) * case.reference.max_semi_axis if stage.spin else 0.0
            if reach > MAX_CREEPAGE:  # the spin's rigid slip at the contact's edge
                fail(
                    f"{path}.spin",
                    f"the spin's rigid slip at the contact's edge, |spin| a = {reach:.6g}, "
                    f"must be within {MAX_CREEPAGE:g} like a creepage (a = "
                    f"{case.reference.max_semi_axis:.4g} m), got spin = {stage.spin:g} 1/m",
                )
        if shared is not None:  # the id from the texts of the tables the batch shares
            case.__dict__["case_id"] = case_hash(spec, shared.text)
        return case

    @property
    def symmetric_plastic(self) -> bool:
        """True for the symmetric elastic-plastic pair (seed eq. 2), :func:`symmetric_pair`."""
        return symmetric_pair(self.body1, self.body2, self.stages)

    @functools.cached_property
    def needs_slip_stick(self) -> bool:
        """True when friction acts: beta != 0, a shear load, or an elastic-plastic body 2.

        The tangential residual displacements of a plastic body have no match on the other
        body, so friction with an elastic-plastic body needs the tangential loop even when
        beta = 0 (the paper's E-EP remark); the symmetric elastic-plastic pair never needs it
        (seed eq. 2: both bodies deform alike).
        """
        if self.friction_coefficient == 0.0 or self.symmetric_plastic:
            return False
        plastic = self.plastic_body is not None
        return plastic or self.pair.dundurs_beta != 0.0 or self.has_tangential_load

    @property
    def plastic_body(self) -> Body | None:
        """The elastic-plastic body whose plastic strain is computed, or None."""
        for body in (self.body2, self.body1):
            if body.behaviour == "elastic-plastic":
                return body
        return None

    @property
    def plastic_body1(self) -> bool:
        """True when body 1 alone is elastic-plastic: solved as :meth:`swapped`."""
        return self.body1.behaviour == "elastic-plastic" and self.body2.behaviour != (
            "elastic-plastic"
        )

    @property
    def plastic_bodies(self) -> tuple[int, ...]:
        """Bodies with a plastic strain field of their own: (2,), (2, 1) or ().

        (2, 1) for two different elastic-plastic bodies; the symmetric pair has one field
        (body 2's), and an elastic-plastic body 1 alone is solved as body 2 of :meth:`swapped`.
        """
        if self.body2.behaviour != "elastic-plastic":
            return (2,) if self.plastic_body1 else ()
        if self.body1.behaviour == "elastic-plastic" and not self.symmetric_plastic:
            return (2, 1)
        return (2,)

    def swapped(self) -> Case:
        """The same contact with the bodies relabelled (body 1 <-> body 2).

        Body 1's frame is body 2's turned by 180 degrees about x: (x, -y, -z).  A tangential
        force (Q_x, Q_y) on body 2 is (-Q_x, -Q_y) on body 1 in the common frame, so
        (-Q_x, Q_y) in its own; the surface fields mirror in y (:mod:`solver.variables`,
        ``swap_sign``).  The swapped case of the swapped case is the case itself.
        """
        table = self.to_dict()
        table["body1"], table["body2"] = table["body2"], table["body1"]
        path = table["load"]["path"]
        stages = [s for e in path for s in (e["stages"] if "cycles" in e else [e])]
        for stage in stages:
            if "tangential_force" in stage:
                qx, qy = stage["tangential_force"]
                stage["tangential_force"] = [-qx if qx else 0.0, qy]
        if any("roll" in stage for stage in stages):
            swap_rolling(table, stages)
        if "wear" in table:  # each body keeps its coefficient
            wear = table["wear"]
            wear["body1"], wear["body2"] = wear["body2"], wear["body1"]
        return Case.from_dict(table)

    # -- derived quantities ------------------------------------------------------------------
    @functools.cached_property
    def pair(self) -> Pair:
        """The two bodies."""
        return Pair(self.body1, self.body2)

    @property
    def max_normal_force(self) -> float:
        """Largest normal force along the load path (N)."""
        return max(stage.normal_force for stage in self.stages)

    @functools.cached_property
    def reference(self) -> HertzContact | SneddonContact | None:
        """The closed-form elastic contact at the largest normal force (computed once).

        Hertz's for quadric bodies, Sneddon's for a profile (:meth:`Geometry.reference`), of
        the smooth shape only under point heights (a first estimate); None for heights only.
        Its semi-axes scale the domain (``grid.half_width``) and the volume depth.
        """
        pair = self.pair
        if pair.geometry.reference_kind is None:
            return None
        return pair.geometry.reference(self.max_normal_force, pair.composite_modulus)

    @property
    def line_contact(self) -> tuple[float, float, float]:
        """A line contact's Hertz strip: half-width b (m), peak pressure (Pa), force (N/m)."""
        grid = self.surface_grid
        per_length = self.max_normal_force / (grid.ny * grid.dy)
        radius = 1.0 / self.pair.curvature[0]
        return (*hertz_line(per_length, self.pair.composite_modulus, radius), per_length)

    @property
    def hertz(self) -> HertzContact:
        """Hertz reference at the largest normal force of the path (quadric bodies only)."""
        if not self.pair.geometry.hertzian:
            kind = "a line contact" if self.grid.periodic_y else "a profile or heights only"
            raise ValueError(f"a case with {kind} has no Hertz reference; use Case.reference")
        return self.reference

    @property
    def domain_half_widths(self) -> tuple[float, float]:
        """Half-widths (m) of the surface domain along x and y (square cells)."""
        scale = self.reference.max_semi_axis if self.grid.size is None else math.nan
        if self.grid.size is not None or not self.moving:
            return domain_half_widths(self.grid, scale)
        # the window covers the contact (half_width around it) at every position of the path
        half = self.grid.half_width * scale
        (x0, x1), (y0, y1) = self.track
        cell = max((2 * half + x1 - x0) / self.grid.nx, (2 * half + y1 - y0) / self.grid.ny)
        return 0.5 * cell * self.grid.nx, 0.5 * cell * self.grid.ny

    @functools.cached_property
    def surface_grid(self) -> SurfaceGrid:
        """The surface grid, centred on :attr:`window_centre` (computed once)."""
        hx, hy = self.domain_half_widths
        return SurfaceGrid.centred(self.grid.nx, self.grid.ny, hx, hy, self.window_centre)

    @property
    def volume_grid(self) -> VolumeGrid | None:
        """The volume grid below the surface (in body 2), or None when nz = 0."""
        return self.volume_grid_of(2)

    @property
    def plastic_box(self) -> IndexBox | None:
        """Cells of the plastic box in the volume grid, or None for the whole window.

        Centred on the axis (the same cells in body 1's mirrored frame): the fewest cells with
        the window's parity whose outer cells' centres lie at ``-w`` and ``w`` or beyond along
        x and y (a zone that reaches ``w`` then stays off the box's side cells), ``w`` =
        ``grid.plastic_half_width`` x the largest Hertz semi-axis, and whose padded length
        (twice as many) is a fast FFT size (:func:`~solver.numerics.grid.fft_size`); every
        layer.  None when that is the whole window.
        """
        if self.grid.plastic_half_width is None or not self.grid.nz:
            return None
        half = self.grid.plastic_half_width * self.reference.max_semi_axis
        surface = self.surface_grid
        ranges = []
        for n, d in ((surface.nx, surface.dx), (surface.ny, surface.dy)):
            # the outer cells' centres (where the stress is collocated) at w or beyond
            cells = min(n, math.ceil(2 * half / d + 1.0 - 1e-9))
            cells += (n - cells) % 2  # centred: as many cells left as right
            while cells < n and fft_size(2 * cells) != 2 * cells:
                cells += 2
            ranges.append(((n - cells) // 2, (n + cells) // 2))
        if ranges == [(0, surface.nx), (0, surface.ny)]:
            return None
        return IndexBox(ranges[0], ranges[1], (0, self.grid.nz))

    @property
    def moving_window(self) -> tuple[int, int] | None:
        """Cells (nx, ny) of the window that follows a moving contact, or None: the whole track.

        ``grid.half_width`` times the largest Hertz semi-axis on every side of the contact plus
        the travel of the longest step that starts or ends loaded (the window holds the
        contact at both ends of an increment), plus a cell for the snapping to whole cells,
        each side's cell count rounded up to a fast FFT size of the track's parity.  None
        (every increment on the whole track's window) without a moving load, with
        ``grid.follow_contact = false``, a given ``grid.size``, a height map or roughness, or
        two elastic-plastic bodies, and when the window would be the track's along both axes.
        """
        if not self.moving or not self.grid.follow_contact or window_unbuilt(self):
            return None
        travel = [0.0, 0.0]
        force = 0.0
        for stage in self.stages:
            if stage.steps and (force > 0.0 or stage.normal_force > 0.0):
                for axis in (0, 1):
                    travel[axis] = max(travel[axis], abs(stage.travel[axis]) / stage.steps)
            force = stage.normal_force
        surface = self.surface_grid
        half = self.grid.half_width * self.reference.max_semi_axis
        cells = []
        along = ((surface.nx, surface.dx, travel[0]), (surface.ny, surface.dy, travel[1]))
        for n, d, length in along:
            count = math.ceil((2.0 * half + length) / d - 1e-9) + 2
            # the track's parity: a window placed as far left as its mirror is right
            while count < n and (fft_size(2 * count) != 2 * count or (n - count) % 2):
                count += 1
            cells.append(min(n, count))
        if cells == [surface.nx, surface.ny]:
            return None
        return cells[0], cells[1]

    def volume_grid_of(self, body: int) -> VolumeGrid | None:
        """The volume grid of body ``body`` (1 or 2).

        Body 1 has its own only with two different elastic-plastic bodies
        (``grid.depth_body1``); else it is body 2's.
        """
        if not self.grid.nz:
            return None
        depth = self.grid.depth_body1 if body == 1 and self.grid.depth_body1 else self.grid.depth
        if self.grid.periodic:  # metres, laterally periodic
            return VolumeGrid(self.surface_grid, self.grid.nz, depth / self.grid.nz, True)
        depth *= self.line_contact[0] if self.grid.periodic_y else self.reference.max_semi_axis
        return VolumeGrid(self.surface_grid, self.grid.nz, depth / self.grid.nz)

    @property
    def total_steps(self) -> int:
        """Number of load increments over the whole path."""
        return sum(stage.steps for stage in self.stages)

    def step_targets(self) -> Iterator[tuple[float, float, float, float, float]]:
        """(W, Q_x, Q_y, p_x, p_y) at the end of every load increment, in order, one at a time.

        W, Q (N); p (m): body 1's apex over body 2 (``slide`` stages move it).  A generator
        (the path is never held whole): :attr:`total_steps` counts it.
        """
        w0, (qx0, qy0), (px0, py0) = 0.0, (0.0, 0.0), (0.0, 0.0)
        for stage in self.stages:
            w1, (qx1, qy1) = stage.normal_force, stage.tangential_force
            px1, py1 = px0 + stage.travel[0], py0 + stage.travel[1]
            for k in range(1, stage.steps + 1):
                f = k / stage.steps
                yield (
                    w0 + f * (w1 - w0), qx0 + f * (qx1 - qx0), qy0 + f * (qy1 - qy0),
                    px0 + f * (px1 - px0), py0 + f * (py1 - py0),
                )  # fmt: skip
            w0, qx0, qy0, px0, py0 = w1, qx1, qy1, px1, py1

    def creep_ramp(self) -> Iterator[tuple[tuple[float, float], float]]:
        """((xi, eta), spin) of every increment of a steady stage (:func:`creep_ramp`)."""
        return creep_ramp(self.stages)

    def increment_stages(self) -> Iterator[LoadStage]:
        """The stage of every load increment, in order (as :meth:`step_targets`)."""
        for stage in self.stages:
            for _ in range(stage.steps):
                yield stage

    @property
    def track(self) -> tuple[tuple[float, float], tuple[float, float]]:
        """((x_min, x_max), (y_min, y_max)) (m): the range of body 1's apex over the path.

        The origin (the apex at the start) is in it; without sliding it is that point alone.
        """
        px = py = 0.0
        xs, ys = [0.0], [0.0]
        for stage in self.stages:
            px, py = px + stage.travel[0], py + stage.travel[1]
            xs.append(px)
            ys.append(py)
        return (min(xs), max(xs)), (min(ys), max(ys))

    @property
    def window_centre(self) -> tuple[float, float]:
        """Centre (m) of the surface window: the origin, or the middle of a sliding track.

        A periodic case's is the origin: the period holds every position of the track.
        """
        if self.grid.periodic:
            return 0.0, 0.0
        (x0, x1), (y0, y1) = self.track
        return 0.5 * (x0 + x1), 0.5 * (y0 + y1)

    @property
    def moving(self) -> bool:
        """True when a stage slides body 1 over body 2."""
        return slides(self.stages)

    def step_cycles(self) -> np.ndarray:
        """Load cycle of every increment (:attr:`LoadStage.cycle`: 0 outside a cycle block)."""
        return np.repeat([stage.cycle for stage in self.stages], [s.steps for s in self.stages])

    @property
    def cycles(self) -> int:
        """Number of load cycles of the path (0 without a cycle block)."""
        return max(stage.cycle for stage in self.stages)

    @property
    def has_tangential_load(self) -> bool:
        """True when any stage prescribes a tangential force or rolls at given creepages or spin."""
        return tangential_load(self.stages)

    @functools.cached_property
    def case_id(self) -> str:
        """Content hash of the normalised specification (16 hex digits, :func:`case_hash`).

        Without :data:`~solver.case.options.EXECUTION_KEYS`, which change no result beyond
        round-off.
        """
        return case_hash(self.spec)

    def to_dict(self) -> dict:
        """The normalised case table (a deep copy); ``Case.from_dict(c.to_dict()) == c``."""
        return json.loads(json.dumps(self.spec))
