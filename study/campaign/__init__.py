"""Campaign files: a base case, sweep axes and zipped axes, expanded into validated cases.

A campaign file is declarative TOML::

    [campaign]                        # optional settings
    name = "quickstart"               # default: the file name without .toml
    output = "out/quickstart"         # default: out/<name>, relative to the working directory
    fft_threads = 1                   # FFTW threads per rank (run-time only, not in the case id)
    fields = ["pressure", "shear_x", "shear_y", "contact_state"]   # 2-D fields kept per case
    max_initial_failures = 5          # stop when the first k cases all fail (0: never)
    case_timeout = 600                # a case running longer fails (seconds; default none)
    profile_extent = 1.5              # radial profiles on r / a in [0, extent] ...
    profile_points = 151              # ... with this many points

    [base]                            # one case table (see solver.Case.from_dict)
    body1 = { behaviour = "elastic", radius = 0.01, E = 210e9, nu = 0.3 }
    ...

    [sweep]                           # full product; one dimension per key
    "friction.coefficient" = [0.0, 0.1, 0.2]
    "materials.dundurs_beta" = [-0.1, 0.0, 0.1]

    [zip.mesh]                        # keys that vary together: ONE dimension "mesh"
    "grid.n" = [32, 64, 128]
    "solver.normal_tolerance" = [1e-6, 1e-7, 1e-8]

    [sample]                          # a sampled design: ONE dimension "sample" (.sample)
    method = "saltelli"               # lhs, sobol, saltelli (Sobol' indices), morris
    count = 256
    "load.normal_force" = { distribution = "log-uniform", range = [10.0, 1000.0] }

    [alias]                           # dimension / coordinate names (default: dots -> "_")
    "friction.coefficient" = "mu"

    [define.steel_swift]              # named tables, swept by name as a whole case table
    behaviour = "elastic-plastic"     # ("body1" = ["steel", "steel_swift"] in [sweep]/[zip])
    ...

Keys are dotted paths into the base table; an integer segment indexes an array of tables
(``"load.path.1.tangential_force"``, also written ``"load.path[1].tangential_force"``, 0-based).
Missing tables on the path are created.  A flat ``[zip]`` table (dotted keys directly under
``[zip]``) forms one dimension named by its coordinate names joined with ``"__"``; a sub-table
``[zip.NAME]`` forms one dimension called NAME.  When a zipped dimension has the name of one of
its coordinates, that coordinate indexes it.

A key that names a whole case table (``"body1"``, ``"body2"``, ``"load"``, ...) is swept by
name: each value is the name of a ``[define.NAME]`` table that replaces the base's table in that
case (e.g. an elastic and an elastic-plastic body, which take different keys).  The names are
the coordinate values.

The pseudo-key ``materials.dundurs_beta`` sets Dundurs' beta by changing body 1's elastic
constants, see :func:`body1_for_beta`.

Swept values are numbers, strings or booleans, never lists.  A volume grid is swept through
its two keys: ``"grid.n"`` (one number: nx = ny) and ``"grid.nz"`` (cells in depth).  The rule
for a ``"grid.n"`` axis over a base with ``grid.n = [nx, ny, nz]``: the base's nz is kept, so
every case has the volume grid ``[n, n, nz]`` (nz is not scaled with n); to vary nz as well,
zip ``"grid.n"`` with ``"grid.nz"`` or sweep ``"grid.nz"`` on its own axis (which replaces the
base's nz, also when the base gives it in ``grid.n``).

:func:`load_campaign` reads, expands and validates a campaign; every problem raises
:class:`CampaignError` whose message names the key or the case (by its sweep coordinates) and
the field.  The cases may be built in shares elsewhere (a ``spread``: worker processes,
:mod:`.parallel`, or the ranks of a run) with the same result.  This package imports no MPI
and writes no files.

The package by job: :mod:`.naming` (coordinate names, units, values as text) at the bottom,
:mod:`.sample` (``[sample]`` designs and their distributions), :mod:`.model` (the frozen
campaign, its axes and cases), :mod:`.validate` (keys, values and the paths they set),
:mod:`.expand` (axes from ``[sweep]``/``[zip]``/``[sample]``, cases from the axes, in
shares), :mod:`.parallel` (shares built in worker processes) and :mod:`.read` (files,
``[campaign]`` settings, ``[define]``) on top.
"""

from solver.bodies.dundurs import beta_range, body1_for_beta

from .model import (
    BETA_KEY,
    CAMPAIGN_KEYS,
    CASE_TABLES,
    MAX_CASE_TIMEOUT,
    PROGRESS_EVERY,
    SURFACE_FIELDS,
    TOP_LEVEL,
    Axis,
    Campaign,
    CampaignCase,
    CampaignError,
    Coordinate,
    Progress,
    Settings,
)
from .naming import RESERVED_NAMES, default_name, format_value
from .read import expand_campaign, load_campaign
from .validate import assign, normalise_key

__all__ = [
    "BETA_KEY",
    "CAMPAIGN_KEYS",
    "CASE_TABLES",
    "MAX_CASE_TIMEOUT",
    "PROGRESS_EVERY",
    "RESERVED_NAMES",
    "SURFACE_FIELDS",
    "TOP_LEVEL",
    "Axis",
    "Campaign",
    "CampaignCase",
    "CampaignError",
    "Coordinate",
    "Progress",
    "Settings",
    "assign",
    "beta_range",
    "body1_for_beta",
    "default_name",
    "expand_campaign",
    "format_value",
    "load_campaign",
    "normalise_key",
]
