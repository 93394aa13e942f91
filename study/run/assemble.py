"""Assembly: one CF netCDF dataset for a campaign, built from its per-case files.

Dimensions are the campaign axes (in file order), ``step`` (load increments; shorter histories
are padded with NaN) and ``r_over_a`` (radial profiles).  For an axis from ``[sweep]`` the
dimension coordinate holds the swept values; a ``[zip]`` dimension carries one coordinate per
zipped key (the one with the dimension's name, if any, indexes it).

Variables (all with ``units`` and ``long_name``):

- ``status`` (axes): int8 flags 0 pending, 1 converged, 2 not_converged, 3 failed, 4 truncated
  (the plastic zone reaches a face of the volume box, or the contact the domain's edge), 5
  surface_flow (the surface shear exceeded what the plastic body can carry: the path ended at
  that increment, its histories padded with NaN after it);
  ``case_id`` and ``error`` (axes): strings;
- per-case scalars (axes): :data:`SCALARS`, the histories' reductions declared in
  :mod:`solver.variables` (last step, largest or summed over the steps) and provenance;
- histories ``<name>_history`` (axes, step) for every history the solver returned;
- per-cycle quantities (axes, cycle) of cyclic load paths, :data:`CYCLE_QUANTITIES` (NaN
  beyond a case's cycles);
- ``plastic_strain_profile`` (axes, z_over_a), elastic-plastic cases: the equivalent plastic
  strain on the contact axis against depth over the Hertz radius (:data:`Z_OVER_A`, NaN
  below a case's volume grid);
- ``pressure_profile``, ``shear_x_profile`` (axes, r_over_a): tractions along y = 0, x >= 0,
  at ``x = r_over_a * a_x`` (``a_x`` the Hertz semi-axis along x, the Hertz radius for a
  circular contact), interpolated linearly between cell centres (cell values up to the domain
  edge, NaN beyond it), so that cases on different meshes share one coordinate.

The full 2-D fields stay in the per-case files.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

import solver
from solver.case.wear import solved_cycles
from solver.drive.record import axis_value
from solver.result import (
    HISTORY_META,
    STATUS_FLAGS,
    SURFACE_FLOW_REASON,
    cycle_variables,
    length_scale,
    stored_status,
)
from solver.theory.shakedown import SHAKEDOWN_FLAGS, shakedown_variable
from solver.variables import CYCLE_QUANTITIES, FATIGUE_SCALARS, HISTORIES, reduced_scalars

from .. import bundle
from ..bundle import CaseRecord
from ..campaign import Axis, Campaign
from ..campaign.sample import SAMPLE_DIM
from . import storage

if TYPE_CHECKING:
    import xarray as xr

_REDUCTION_TEXT = {
    "last": "{} at the last load step",
    "max": "{}, largest over the load steps",
    "sum": "{}, summed over the load steps",
}

#: Normalised depths z / a_H of the on-axis plastic-strain profile (``plastic_strain_profile``).
Z_OVER_A = np.linspace(0.0, 4.0, 161)

#: Status flags of the assembled dataset.

#: Per-case scalars reduced from the solver's histories (:mod:`solver.variables`):
#: name -> (history, reduction, units).
REDUCED = reduced_scalars()

#: Per-case scalars: name -> (units, long_name).  The reduced histories first, then the
#: scalars derived here and the case's provenance.
SCALARS = {
    name: (units, _REDUCTION_TEXT[reduction].format(HISTORIES[history].long_name))
    for name, (history, reduction, units) in REDUCED.items()
} | {
    "contact_radius": ("m", "equivalent contact radius sqrt(max contact_area / pi)"),
    "stick_radius": ("m", "equivalent stick-zone radius sqrt(stick_area / pi)"),
    "steps": ("1", "number of load steps"),
    "wall_time": ("s", "solve wall time"),
    "cpu_time": ("s", "solve CPU time of the case's process, all its threads (NaN: not recorded)"),
    "case_time": ("s", "wall time of the case on its rank before writing (set-up, solve, checks)"),
    "peak_rss": (
        "byte",
        "peak resident memory of the computing process during the case (where the kernel "
        "restarts the count, Linux; elsewhere its peak so far, an upper bound)",
    ),
    "mpi_rank": ("1", "MPI rank that computed the case (-1: none)"),
    "grid_cells": ("1", "grid cells of the case: nx ny, or nx ny nz with a volume grid"),
    "hertz_radius": ("m", "Hertz contact radius sqrt(a b) at the largest normal force"),
    "hertz_semi_axis_x": ("m", "Hertz semi-axis along x at the largest normal force"),
    "hertz_pressure": ("Pa", "Hertz peak pressure at the largest normal force"),
    "hertz_normal_force": ("N", "largest normal force of the load path"),
    "hertz_approach": ("m", "Hertz approach at the largest normal force"),
    "sneddon_radius": ("m", "Sneddon contact radius (a profile) at the largest normal force"),
    "sneddon_mean_pressure": ("Pa", "Sneddon mean pressure W/(pi a^2) at the largest normal force"),
    "sneddon_normal_force": ("N", "largest normal force of the load path"),
    "sneddon_approach": ("m", "Sneddon approach at the largest normal force"),
    "line_half_width": ("m", "Hertz half-width b of a line contact at the largest normal force"),
    "line_pressure": ("Pa", "Hertz peak pressure of a line contact at the largest normal force"),
    "line_force_per_length": ("N/m", "largest normal force per unit length of a line contact"),
    "composite_modulus": ("Pa", "composite modulus E*"),
    "dundurs_beta": ("1", "Dundurs' second constant beta"),
    "friction_coefficient": ("1", "friction coefficient mu"),
    "melan_factor": (
        "1",
        "Melan's static shakedown factor of the final residual stress under the sliding Hertz "
        "load (solver.theory.shakedown.melan_factor): the load times it is proven to shake down",
    ),
    "shear_yield_stress": (
        "Pa",
        "initial shear yield stress k = sigma_Y0 / sqrt(3) of the elastic-plastic body (von Mises)",
    ),
    **FATIGUE_SCALARS,
}
#: Per-case bookkeeping variables of a campaign dataset (name: long_name).
BOOKKEEPING = {
    "status": "case status",
    "case_id": "case id (study.run.storage.open_case(OUT, case_id) opens the stored case)",
    "error": "error of a failed case",
    "notes": "the solver's notes on the case ('; '-separated: warnings, path dependence, "
    "non-convergence, truncation)",
    "loops": "loops that ran (space-separated)",
    "shakedown_reason": "why the case has its shakedown regime (solver.theory.shakedown.classify)",
}
#: Scalars only some cases have (left out of a campaign's dataset when none has them).
_OPTIONAL_SCALARS = ("shear_yield_stress", "melan_factor", *FATIGUE_SCALARS)
_ATTRS = (
    "hertz_radius",
    "hertz_semi_axis_x",
    "hertz_pressure",
    "hertz_normal_force",
    "hertz_approach",
    "sneddon_radius",
    "sneddon_mean_pressure",
    "sneddon_normal_force",
    "sneddon_approach",
    "line_half_width",
    "line_pressure",
    "line_force_per_length",
    "composite_modulus",
    "dundurs_beta",
    "friction_coefficient",
    "shear_yield_stress",
    "melan_factor",
    *FATIGUE_SCALARS,
    "wall_time",
    "cpu_time",
    "peak_rss",
)


def _case_steps(spec: dict) -> int:
    return solver.case.path.path_steps(spec["load"]["path"], solved_cycles(spec))


def _grid_cells(spec: dict) -> int:
    """Cells of a case's grid from its normalised spec (``grid.n`` = [nx, ny] or [nx, ny, nz])."""
    return int(np.prod([int(n) for n in spec["grid"]["n"]]))


def profile(x: np.ndarray, line: np.ndarray, radius: float, r_over_a: np.ndarray) -> np.ndarray:
    """A line of cell values along x sampled at ``x = r_over_a * radius``.

    Linear between cell centres, the edge cells' values out to the domain edge (half a cell
    beyond the last centre), NaN beyond.
    """
    dx = x[1] - x[0] if len(x) > 1 else 1.0
    xp = np.concatenate([[x[0] - 0.5 * dx], x, [x[-1] + 0.5 * dx]])
    fp = np.concatenate([[line[0]], line, [line[-1]]])
    target = r_over_a * radius
    target = np.where((target > xp[-1]) & (target <= xp[-1] * (1 + 1e-9)), xp[-1], target)
    return np.interp(target, xp, fp, left=np.nan, right=np.nan)


def case_summary(record: CaseRecord, r_over_a: np.ndarray) -> dict:
    """What the dataset holds of one case: status, scalars, histories, profiles.

    Computed by the rank that solved the case and stored with it (a bundle entry's
    ``summary``), so that the assembly only places rows; recomputed here for a case file of an
    older version or a campaign whose profile coordinate changed.

    Parameters
    ----------
    record : CaseRecord
        The stored case.
    r_over_a : ndarray
        The radial profiles' coordinate (the campaign's ``profile_extent``, ``profile_points``).
    """
    attrs = record.attrs
    histories = {name: record.values(name).astype(float) for name in HISTORY_META if name in record}
    cycles = {
        name: record.values(name).astype(float) for name in CYCLE_QUANTITIES if name in record
    }
    regime = None
    if "shakedown" in record:
        reason = str(record.variable_attrs("shakedown").get("reason", ""))
        regime = (int(record.values("shakedown")), reason)
    x = record.values("x")
    if "position_x" in histories:  # a sliding path: about the contact's last position
        x = x - histories["position_x"][-1]
    radius = length_scale(attrs)
    depth_profile = None
    heights_only = "domain_half_width" in attrs  # no contact radius to scale by
    if "plastic_strain" in record and "hertz_radius" in attrs:
        depth = record.values("z") / float(attrs["hertz_radius"])
        on_axis = axis_value(record.values("plastic_strain"))
        depth_profile = np.interp(Z_OVER_A, depth, on_axis, left=on_axis[0], right=np.nan)
    scalars = {name: float(attrs[name]) for name in _ATTRS if name in attrs}
    for name, (history, reduction, _) in REDUCED.items():
        if history in histories:
            values = histories[history]
            scalars[name] = {"last": values[-1], "max": np.max(values), "sum": np.sum(values)}[
                reduction
            ]
    if "contact_area" in histories and not heights_only:  # many spots: no one radius
        scalars["contact_radius"] = math.sqrt(scalars["contact_area"] / math.pi)
    if "stick_area" in histories:
        scalars["stick_radius"] = math.sqrt(histories["stick_area"][-1] / math.pi)
    elif "final_stick_area" in attrs:  # normal-only scenes: stick = contact when mu > 0
        scalars["stick_radius"] = math.sqrt(float(attrs["final_stick_area"]) / math.pi)
    scalars["steps"] = float(len(histories.get("normal_force", [])))
    scalars["case_time"] = float(attrs.get("time_before_write", math.nan))
    scalars["mpi_rank"] = float(attrs.get("rank", -1))
    status = stored_status(attrs.get("status", "converged"), str(attrs.get("notes", "")))
    if status == "surface_flow" and regime is not None:  # a file written before the status
        regime = (SHAKEDOWN_FLAGS["undetermined"], SURFACE_FLOW_REASON)
    lines = {name: record.values(f"{name}_y0") for name in ("pressure", "shear_x")}
    return {
        "status": status,
        "text": {name: str(attrs.get(name, "")) for name in ("notes", "loops")},
        "scalars": {name: float(value) for name, value in scalars.items()},
        "histories": histories,
        "cycles": cycles,
        "shakedown": regime,
        "profiles": {name: profile(x, line, radius, r_over_a) for name, line in lines.items()},
        "depth_profile": depth_profile,
        "r_over_a": _profile_key(r_over_a),
    }


def _profile_key(r_over_a: np.ndarray) -> list:
    return [float(r_over_a[-1]), len(r_over_a)]


def profile_coordinate(settings) -> np.ndarray:
    """The radial profiles' coordinate r / a of a campaign (its settings)."""
    return np.linspace(0.0, settings.profile_extent, settings.profile_points)


def _summaries(out: Path, index: storage.CaseIndex, wanted: set[str], r_over_a: np.ndarray):
    """(case id, summary or the error that made it unreadable) of every wanted finished case.

    Bundle by bundle, one open file at a time (the memory is the dataset's, not the files').
    """
    by_file: dict[Path, list[tuple[str, int | None]]] = {}
    for case_id in sorted(wanted & set(index.results)):
        location = index.results[case_id][0]
        by_file.setdefault(location.path, []).append((case_id, location.position))
    key = _profile_key(r_over_a)
    for path, entries in by_file.items():
        if entries[0][1] is None:  # per-case files of an older version
            for case_id, _ in entries:
                try:
                    record = storage.read_record(out, case_id, index)
                except (OSError, RuntimeError, ValueError) as error:
                    yield case_id, error
                    continue
                yield case_id, case_summary(record, r_over_a)
            continue
        try:
            reader = bundle.Reader(path)
        except bundle.BundleError as error:
            for case_id, _ in entries:
                yield case_id, error
            continue
        with reader:
            for case_id, position in entries:
                try:
                    summary = reader.summary(position)
                    if summary is None or summary.get("r_over_a") != key:
                        summary = case_summary(reader.record(position), r_over_a)
                except (OSError, RuntimeError, ValueError, KeyError) as error:
                    yield case_id, error
                    continue
                yield case_id, summary


def _coordinates(axis: Axis) -> dict:
    coords = {}
    for coordinate in axis.coordinates:
        attrs = {"long_name": coordinate.long_name, "campaign_key": coordinate.key}
        if coordinate.units:
            attrs["units"] = coordinate.units
        coords[coordinate.name] = (axis.name, np.asarray(coordinate.array_values()), attrs)
    return coords


def assemble(out: str | Path, campaign: Campaign | None = None) -> xr.Dataset:
    """Build the campaign dataset from the files in ``out``.

    Parameters
    ----------
    out : str or Path
        Campaign output folder (with ``campaign.json`` and ``cases/``).
    campaign : Campaign, optional
        Default: read from ``out/campaign.json``.

    Returns
    -------
    xarray.Dataset
        See the module docstring for the layout.
    """
    import logging

    import xarray as xr

    from .progress import LOGGER_NAME

    out = Path(out)
    campaign = campaign or storage.read_campaign(out)
    settings = campaign.settings
    dims, shape = campaign.dims, campaign.shape
    r_over_a = profile_coordinate(settings)
    steps = max(_case_steps(case.spec) for case in campaign.cases)
    index = storage.case_index(out)
    logger = logging.getLogger(LOGGER_NAME)  # names each corrupt file once
    for name, problem in sorted(index.corrupt.items()):
        if name.endswith(bundle.SUFFIX):
            logger.warning(
                "corrupt bundle cases/%s, %s; its cases count as pending "
                "(python -m study run moves it aside and computes them again)",
                name,
                problem,
            )

    status = np.zeros(shape, dtype=np.int8)
    case_ids = np.empty(shape, dtype=object)
    errors = np.full(shape, "", dtype=object)
    texts = {name: np.full(shape, "", dtype=object) for name in ("notes", "loops")}
    scalars = {name: np.full(shape, np.nan) for name in SCALARS}
    histories: dict[str, np.ndarray] = {}
    cycle_count = max(
        solver.case.path.path_cycles(case.spec["load"]["path"], solved_cycles(case.spec))
        for case in campaign.cases
    )
    per_cycle: dict[str, np.ndarray] = {}
    regimes = None  # shakedown flags, when a case has them
    profiles = {name: np.full((*shape, len(r_over_a)), np.nan) for name in ("pressure", "shear_x")}
    depth_profiles = None
    rows: dict[str, list] = {}
    for case in campaign.cases:
        index_ = tuple(case.index)
        rows.setdefault(case.case_id, []).append((index_, case))
        case_ids[index_] = case.case_id
        scalars["grid_cells"][index_] = _grid_cells(case.spec)
        problem = index.corrupt.get(case.case_id)
        if problem is not None:  # a damaged per-case file: failed here; `run` recomputes it
            status[index_] = STATUS_FLAGS["failed"]
            errors[index_] = f"corrupt case file cases/{case.case_id}.nc: {problem}"
        elif case.case_id in index.failures:
            status[index_] = STATUS_FLAGS["failed"]
    for case_id, record in storage.read_failures(out, rows, index).items():
        for index_, _ in rows[case_id]:
            errors[index_] = record.get("error", "")
    for case_id, problem in index.corrupt.items():
        if case_id in rows:
            logger.warning(
                "case %s [%s]: corrupt case file cases/%s.nc, %s; counted failed "
                "(python -m study run recomputes it)",
                case_id,
                rows[case_id][0][1].label,
                case_id,
                problem,
            )
    finished = 0
    for case_id, data in _summaries(out, index, set(rows), r_over_a):
        for index_, case in rows[case_id]:
            if isinstance(data, Exception):  # damaged beyond its index
                status[index_] = STATUS_FLAGS["failed"]
                errors[index_] = f"case {case_id} cannot be read ({str(data).splitlines()[0]})"
                logger.warning("case %s [%s]: %s", case_id, case.label, errors[index_])
                continue
            finished += 1
            status[index_] = STATUS_FLAGS.get(data["status"], STATUS_FLAGS["converged"])
            for name, text in data["text"].items():
                texts[name][index_] = text
            for name, value in data["scalars"].items():
                scalars[name][index_] = value
            for name, values in data["histories"].items():
                if name not in histories:
                    histories[name] = np.full((*shape, steps), np.nan)
                histories[name][index_][: len(values)] = values
            for name, values in data["cycles"].items():
                if name not in per_cycle:
                    per_cycle[name] = np.full((*shape, cycle_count), np.nan)
                per_cycle[name][index_][: len(values)] = values
            if data["shakedown"] is not None:
                if regimes is None:
                    regimes = np.zeros(shape, dtype=np.int8)  # undetermined
                    texts["shakedown_reason"] = np.full(shape, "", dtype=object)
                regimes[index_], texts["shakedown_reason"][index_] = data["shakedown"]
            for name, values in data["profiles"].items():
                profiles[name][index_] = values
            if data["depth_profile"] is not None:
                if depth_profiles is None:
                    depth_profiles = np.full((*shape, len(Z_OVER_A)), np.nan)
                depth_profiles[index_] = data["depth_profile"]
    ranks = scalars.pop("mpi_rank")
    rank = np.where(np.isnan(ranks), -1, ranks).astype(np.int32)
    cells = scalars.pop("grid_cells").astype(np.int64)

    coords: dict = {
        "step": ("step", np.arange(1, steps + 1), {"units": "1", "long_name": "load step"}),
        "r_over_a": (
            "r_over_a",
            r_over_a,
            {
                "units": "1",
                "long_name": "distance from the centre along +x (y = 0) over the Hertz "
                "semi-axis a_x",
            },
        ),
    }
    for axis in campaign.axes:
        coords.update(_coordinates(axis))
    data_vars: dict = {
        "status": (
            dims,
            status,
            {
                "long_name": BOOKKEEPING["status"],
                "flag_values": np.array(list(STATUS_FLAGS.values()), dtype=np.int8),
                "flag_meanings": " ".join(STATUS_FLAGS),
            },
        ),
        "case_id": (dims, case_ids.astype(str), {"long_name": BOOKKEEPING["case_id"]}),
        "error": (dims, errors.astype(str), {"long_name": BOOKKEEPING["error"]}),
        **{
            name: (dims, values.astype(str), {"long_name": BOOKKEEPING[name]})
            for name, values in texts.items()
        },
        "mpi_rank": (dims, rank, {"units": "1", "long_name": SCALARS["mpi_rank"][1]}),
        "grid_cells": (dims, cells, {"units": "1", "long_name": SCALARS["grid_cells"][1]}),
    }
    specs = [case.spec for case in campaign.cases]
    profiled = [any("profile" in spec[b] for b in ("body1", "body2")) for spec in specs]
    references = {"hertz_": not all(profiled), "sneddon_": any(profiled)}  # by the case specs
    for name, values in scalars.items():
        if name in coords:  # an axis holds this input (e.g. dundurs_beta): keep the coordinate
            continue
        if any(name.startswith(prefix) and not used for prefix, used in references.items()):
            continue  # a closed-form reference no case of this campaign has
        if name in REDUCED and REDUCED[name][0] not in histories:
            continue  # a history no case of this campaign has (e.g. plastic ones)
        if name in _OPTIONAL_SCALARS and np.isnan(values).all():
            continue  # no case has it (no elastic-plastic case, no sliding one, no fatigue)
        units, long_name = SCALARS[name]
        data_vars[name] = (dims, values, {"units": units, "long_name": long_name})
    for name in HISTORY_META:
        if name in histories:
            units, long_name = HISTORY_META[name]
            data_vars[f"{name}_history"] = (
                (*dims, "step"),
                histories[name],
                {"units": units, "long_name": f"{long_name} per load step"},
            )
    if per_cycle:
        cycle_coords, cycle_data = cycle_variables(per_cycle, dims)
        coords.update(cycle_coords)
        data_vars.update(cycle_data)
    if regimes is not None:
        data_vars["shakedown"] = shakedown_variable(regimes, dims)
    if depth_profiles is not None:
        coords["z_over_a"] = (
            "z_over_a",
            Z_OVER_A,
            {"units": "1", "long_name": "depth below the contact centre over the Hertz radius"},
        )
        data_vars["plastic_strain_profile"] = (
            (*dims, "z_over_a"),
            depth_profiles,
            {"units": "1", "long_name": "equivalent plastic strain on the contact axis"},
        )
    for name, long_name in (("pressure", "contact pressure"), ("shear_x", "shear traction x")):
        data_vars[f"{name}_profile"] = (
            (*dims, "r_over_a"),
            profiles[name],
            {"units": "Pa", "long_name": f"{long_name} along y = 0, x >= 0"},
        )
    counts = {flag: int(np.sum(status == value)) for flag, value in STATUS_FLAGS.items()}
    attrs = {
        "Conventions": "CF-1.8",
        "title": f"slipstick campaign {campaign.name}",
        "summary": settings.description or f"parametric study over {', '.join(dims)}",
        "source": f"slipstick {solver.__version__}",
        "slipstick_version": solver.__version__,
        "git_hash": storage.git_hash(),
        "history": (
            f"{storage.now()}: assembled from {finished} finished cases "
            f"({storage.command_line() or 'study.run.assemble'})"
        ),
        "campaign": campaign.name,
        "campaign_source": campaign.source,
        "campaign_axes": json.dumps(campaign.axes_dicts(values=False)),
        "campaign_base": json.dumps(campaign.base),
        "cases_total": len(campaign.cases),
        **{f"cases_{flag}": count for flag, count in counts.items()},
    }
    if campaign.design is not None:
        design_coords, design_vars, design_attrs = design_variables(campaign)
        coords.update(design_coords)
        data_vars.update(design_vars)
        attrs.update(design_attrs)
    return xr.Dataset(data_vars, coords=coords, attrs=attrs)


def design_variables(campaign: Campaign) -> tuple[dict, dict, dict]:
    """Coordinates, variables and attributes of a sampled design (:mod:`study.campaign.sample`).

    ``sample_design`` (sample, sample_input): the rows in the unit hypercube (each input's
    quantile level); ``sample_distribution`` (sample_input): each input's distribution; the
    attributes ``sample_method``, ``sample_count``, ``sample_seed``, ``sample_second_order``,
    ``sample_levels`` and ``sample_block`` (rows that belong together: a Saltelli block, a Morris
    trajectory).
    """
    design = campaign.design
    axis = next(axis for axis in campaign.axes if axis.name == SAMPLE_DIM)
    names = {c.key: c.name for c in axis.coordinates}
    inputs = [names[key] for key in design.keys]
    meaning = {"long_name": "sampled input (a coordinate of sample)"}
    coords = {"sample_input": ("sample_input", np.array(inputs), meaning)}
    data_vars = {
        "sample_design": (
            (SAMPLE_DIM, "sample_input"),
            np.asarray(design.unit, dtype=float),
            {"units": "1", "long_name": "the design's rows in the unit cube (quantile levels)"},
        ),
        "sample_distribution": (
            "sample_input",
            np.array([d.describe() for d in design.distributions]),
            {"long_name": "distribution of the sampled input"},
        ),
    }
    attrs = {
        "sample_method": design.method,
        "sample_count": design.count,
        "sample_seed": design.seed,
        "sample_second_order": int(design.second_order),
        "sample_levels": design.levels,
        "sample_block": design.block,
    }
    return coords, data_vars, attrs


def assemble_to_file(out: str | Path, campaign: Campaign | None = None) -> Path:
    """Assemble and write ``OUT/<campaign name>.nc`` atomically; returns its path."""
    campaign = campaign or storage.read_campaign(out)
    dataset = assemble(out, campaign)
    path = storage.dataset_path(out, campaign.name)
    storage.write_netcdf(dataset, path)
    return path
