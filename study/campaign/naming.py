"""Names of campaign axes and coordinates, their units and long names, and values as text.

A swept key gets a coordinate name (``friction.coefficient`` -> ``friction_coefficient``, or
the ``[alias]``), units and a long name from :data:`_KEY_META` or the solver's declarations;
reserved names are those of the assembled dataset's own variables.
"""

from __future__ import annotations

import re
from typing import Any

from solver.variables import CYCLE_QUANTITIES, FATIGUE_SCALARS, reduced_scalars

#: Names used by the assembled dataset for its structure and its per-case results; no axis may
#: take them (nor names ending in ``_history`` or ``_profile``).  Axes may take the names of the
#: per-case inputs the dataset also records (``dundurs_beta``, ``hertz_pressure``, ...): the
#: coordinate then replaces that variable.
RESERVED_NAMES = frozenset(
    {
        "status",
        "case_id",
        "error",
        "mpi_rank",
        "grid_cells",
        "step",
        "r_over_a",
        "z_over_a",
        "x",
        "y",
        "contact_radius",
        "stick_radius",
        "steps",
        "wall_time",
        "cpu_time",
        "case_time",
        "peak_rss",
        "cycle",
        "melan_factor",
        "shakedown",
        "shakedown_reason",
        "notes",
        "loops",
        "sample",
        "sample_input",
        "sample_design",
        "sample_distribution",
    }
    | set(reduced_scalars())
    | set(CYCLE_QUANTITIES)
    | set(FATIGUE_SCALARS)
)


class CampaignError(ValueError):
    """A bad campaign file: the message names the key or case, the field, and what to change."""


_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")
_CAMPAIGN_NAME = re.compile(r"^[A-Za-z0-9_][A-Za-z0-9_.-]*$")

#: Units and readable names of a swept key, by its last two segments or else its last.
_KEY_META = {
    "coefficient": ("1", "Coulomb friction coefficient"),
    "hertz_pressure": ("Pa", "Hertz peak pressure of the load"),
    "normal_force": ("N", "normal force"),
    "tangential_force": ("N", "tangential force along x"),
    "tangential_shift": ("m", "rigid tangential shift along x"),
    "wear.body1": ("1/Pa", "wear coefficient of body 1"),
    "wear.body2": ("1/Pa", "wear coefficient of body 2"),
    "steps": ("1", "number of load increments"),
    "n": ("1", "grid cells per side"),
    "nz": ("1", "volume-grid cells in depth"),
    "half_width": ("1", "domain half-width over the Hertz semi-axis"),
    "depth": ("1", "volume-grid depth over the Hertz semi-axis"),
    "E": ("Pa", "Young's modulus"),
    "nu": ("1", "Poisson's ratio"),
    "radius": ("m", "radius of curvature"),
    "radius_x": ("m", "radius of curvature in the x-z plane"),
    "radius_y": ("m", "radius of curvature in the y-z plane"),
    "dundurs_beta": ("1", "Dundurs' second constant beta"),
    "yield_stress": ("Pa", "initial yield stress"),
    "modulus": ("Pa", "linear hardening modulus"),
    "B": ("Pa", "Swift hardening coefficient"),
    "max_load_ratio": ("1", "largest normal-load ratio per coupled step"),
    "fft_threads": ("1", "FFTW threads"),
    # profile keys, by their last two segments (a profile's radius is not a curvature)
    "profile.angle": ("degree", "cone angle to the tangent plane"),
    "profile.radius": ("m", "flat-punch face radius"),
    "profile.edge_radius": ("m", "flat-punch edge radius"),
    "profile.coefficient": ("m^(1-k)", "power-law profile coefficient A"),
    "profile.exponent": ("1", "power-law profile exponent k"),
}


def default_name(key: str) -> str:
    """Default coordinate name of a key: dots replaced by underscores."""
    return key.replace(".", "_")


def _meta(key: str) -> tuple[str | None, str]:
    if "." not in key:
        return None, f"{key} table, by its [define] name ({key})"
    last = key.split(".")[-1]
    units, text = _KEY_META.get(
        ".".join(key.split(".")[-2:]), _KEY_META.get(last, (None, last.replace("_", " ")))
    )
    if last.endswith("_tolerance"):
        units = "1"
    if last.endswith("_iterations"):
        units = "1"
    owner = key.split(".")[0]
    if owner in ("body1", "body2"):
        text = f"{text} of body {owner[-1]}"
    match = re.search(r"path\.(\d+)\.", key)
    if match:
        text = f"{text} at load stage {match.group(1)}"
    return units, f"{text} ({key})"


# -- helpers -------------------------------------------------------------------------------------
def _is_number(value: Any) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool)


def _is_int(value: Any) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def _is_inf(value: Any) -> bool:
    return isinstance(value, str) and value.lower() in ("inf", "infinity")


def _kind(value: Any) -> str:
    if _is_number(value) or _is_inf(value):
        return "number"
    return type(value).__name__


def format_value(value: Any) -> str:
    """A swept value as text for labels and messages (an int too long to print by its size)."""
    if isinstance(value, float):
        return f"{value:g}"
    if _is_int(value) and abs(value) >= 10**30:
        return f"<integer of {value.bit_length()} bits>"
    return str(value)
