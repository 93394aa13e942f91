"""Every key of a case table, declared once: type, unit, default, accepted range, who uses it.

:mod:`solver.case.case` takes the keys each table accepts (:func:`table_keys`), the required ones,
the limits it checks and the solver defaults from here, and the guide's reference page of case
keys is written from :data:`CASE_KEYS` (``docs/generate.py``): the parser, its messages and the
documentation cannot drift apart.

A table is named by its place in the case file: ``""`` (the top level), ``"bodyN"`` (both
``[body1]`` and ``[body2]``), ``"bodyN.hardening"``, ``"bodyN.hardening.kinematic"``,
``"load"`` (a single stage, or ``path``), ``"load.path[i]"`` (a stage of a path),
``"load.path[i] (cycle block)"``, ``"friction"``, ``"grid"``, ``"solver"``, ``"output"``.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

from .variables import OPTIONAL_FIELDS

# -- limits the validation checks (SI units unless said) ------------------------------------------
#: Smallest number of cells the contact diameter may span.
MIN_CELLS_ACROSS = 10
#: Coarsest height map accepted: its spacing at most this many grid cells (finer grids would
#: only see the interpolating spline between the map's points).
MAX_MAP_COARSENING = 4.0
#: Largest grid side (cells) accepted.
MAX_CELLS = 8192
#: Young's moduli accepted (Pa): from soft gels to beyond diamond.
MODULUS_RANGE = (1e3, 1e15)
#: Finite radii of curvature accepted (m); "inf" (flat) is accepted as well.
RADIUS_RANGE = (1e-9, 1e6)
#: Accepted sides of a domain given in metres (grid.size), m: a nanometre to a kilometre.
SIZE_RANGE = (1e-9, 1e3)
#: Hertz peak pressure over the composite modulus, p_H / E*, accepted for every non-zero load.
#: It is the contact's strain scale (a / R = pi/2 p_H / E* for a sphere): below 1e-9 the
#: contact is a rounding error, above 1 the small-strain theory the solver rests on is void.
PRESSURE_RATIO_RANGE = (1e-9, 1.0)
#: Largest cone angle (degrees) to the tangent plane: slopes up to 1 (small-slope theory,
#: :data:`solver.bodies.geometry.MAX_PROFILE_SLOPE`).
PROFILE_MAX_ANGLE = 45.0
#: Largest surface slope (dz/dr) of a profile inside the contact, and largest rms slope of a
#: roughness: the half-space theory the solver rests on assumes small slopes (a sphere at the
#: largest accepted p_H/E* = 1 reaches a/R = pi/2 at the contact edge; shapes are held to 45
#: degrees).
MAX_SURFACE_SLOPE = 1.0
#: Exponents k of a power-law profile h = A r^k accepted.
PROFILE_EXPONENT_RANGE = (1.0, 8.0)
#: Initial yield strain sigma_Y0 / E accepted for an elastic-plastic body: from the softest
#: annealed metals (indium, lead: ~1e-4) to metallic glasses (~0.02), with a decade of slack.
YIELD_STRAIN_RANGE = (1e-5, 0.1)
#: Swift's offset C (micro-strain) accepted: its initial slope B n 1e6 C^(n-1) is finite.
SWIFT_OFFSET_RANGE = (1e-3, 1e7)
#: Largest hardening modulus (linear H, kinematic C) over Young's modulus.
MAX_HARDENING_RATIO = 10.0
#: Largest Armstrong-Frederick recall gamma (dimensionless; measured values are 10-1000).
MAX_RECALL = 1e6
#: Largest number of increments of one load stage.
MAX_STAGE_STEPS = 100_000
#: Largest creepage of a rolling stage: a rigid slip of the whole distance rolled (steel
#: slides fully from about 0.005, rubber from about 0.1).
MAX_CREEPAGE = 1.0
#: Largest prescribed tangential shift (``tangential_shift``) over the contact's smaller Hertz
#: semi-axis: the shift is a rigid displacement of the bodies, whose shapes stay where they
#: are (small displacement); a stroke that moves the contact farther is a slide.
MAX_SHIFT = 0.1
#: Largest roll per increment of a transient rolling stage with friction, in units of the
#: contact's semi-axis along the roll, without a note: the tractions converge with the step
#: (first order).  A 4 a roll at xi = 1e-3 (steel, 48 x 16 cells) put the creep force 115,
#: 28 and 6 % off the 100-step value at steps of 4, 1 and 0.25 a (2026-11-28).
MAX_ROLLING_STEP = 0.1
#: Largest number of cycles of a cycle block.
MAX_CYCLES = 10_000
#: Largest number of load increments of a path (cycle blocks repeated): every increment is a
#: contact solve and a row of every history.
MAX_INCREMENTS = 1_000_000
#: Radius of curvature (m) above which a case gets a note asking whether its lengths are in
#: metres: railway wheels (about 0.46 m) and mill rolls stay below it, a "10" meant as 10 mm
#: does not.
LARGE_RADIUS = 2.0
#: Hertz contact radius (m) above which a case gets the same note (a 10 m sphere at 1 GPa on
#: steel touches over 68 mm; wheel-rail contacts are about 7 mm).
LARGE_CONTACT_RADIUS = 0.02
#: Largest friction coefficient accepted (dimensionless).
MAX_FRICTION = 100.0
#: Largest friction coefficient the shakedown theorems take (``solver.method =
#: "static_shakedown"``, :class:`solver.theorems.track.Track`): their boxes and the checks of
#: their limits reach mu = 1 (the surface binds from about 0.25 on, at mu p_0 = k).
MAX_THEOREM_FRICTION = 1.0
#: Shear limits accepted by ``friction.shear_limit`` (Pa): from soft polymers to above any
#: metal's shear strength.
SHEAR_LIMIT_RANGE = (1e3, 1e11)
#: Smallest Orowan factor ``friction.shear_factor`` accepted (a cap that small is a limit).
MIN_SHEAR_FACTOR = 1e-3
#: Wear laws of ``wear.law`` (:mod:`solver.case.wear`).
WEAR_LAWS = ("archard", "energy")
#: Wear coefficients accepted (1/Pa): Archard's k of metals is 1e-18 to 1e-13 1/Pa
#: (1e-9 to 1e-4 mm^3/(N m)); above the range a micrometre of slip at 1 GPa wears a micrometre.
WEAR_COEFFICIENT_RANGE = (1e-24, 1e-10)
#: Relative pressure changes a cycle jump may make under ``wear.cycle_jump = "auto"``
#: (:mod:`solver.drive.wear`): the default and the accepted range.  The worn profile's error
#: is about half the bound, relative to the deepest wear.
PRESSURE_CHANGE = 0.05
PRESSURE_CHANGE_RANGE = (1e-4, 0.2)
#: Fatigue limits accepted (Pa): from soft polymers' to above any steel's.
FATIGUE_LIMIT_RANGE = (1e5, 1e10)
#: Most cycles solved per cycle block under ``wear.cycle_jump = "auto"`` (the default).
SOLVED_CYCLES = 100
#: Smallest positive friction coefficient accepted: below it the tangential solve's scales
#: (mu p, the tractions it bounds) underflow its residual (1e-9 gave NaN residuals,
#: 2026-11-28); such a contact is frictionless to the solver's tolerances: give 0.
MIN_FRICTION = 1e-6
#: Volume depths accepted (``grid.depth``, ``grid.depth_body1``; units of the Hertz radius).
DEPTH_RANGE = (0.05, 20.0)
#: Smallest half side of the plastic box (``grid.plastic_half_width``, units of a_H).
MIN_PLASTIC_HALF_WIDTH = 0.25
#: Deepest volume grid of a periodic case, as a fraction of the period's shorter side: its
#: kernels sum the nearest periods (:mod:`solver.numerics.images`), whose truncation grows
#: with the depth over the period.
MAX_PERIODIC_DEPTH = 0.5
#: Volume depth of a periodic elastic-plastic case whose elastic stress nowhere yields, as a
#: fraction of the period's shorter side.
DEFAULT_PERIODIC_DEPTH = 0.125
#: Fewest volume cells across the elastic yield region in depth (``solver.case.case``).
MIN_YIELD_CELLS = 2
#: Thickest volume cell (units of a_H) of an elastic-plastic body (``solver.case.case``).
MAX_CELL_DEPTH = 0.25
#: Margin on the elastic yield region's half width that sizes the plastic box laterally.
PLASTIC_WIDTH_MARGIN = 1.25
#: Half side (units of a_H) of the surface window when none is given.  An elastic-plastic
#: case's window widens to hold its plastic box (:data:`PLASTIC_WIDTH_MARGIN` x the elastic
#: yield region's half width) when that is wider, up to :data:`MAX_AUTO_HALF_WIDTH`.
DEFAULT_HALF_WIDTH = 1.5
#: Widest window (units of a_H) sized from the plastic zone when ``grid.half_width`` is not given.
MAX_AUTO_HALF_WIDTH = 4.0
#: Volume depth (units of the largest Hertz semi-axis) when none is given for elastic cases.
DEFAULT_DEPTH = 1.2
#: Margin on the elastic yield depth that sizes an elastic-plastic case's volume grid.
YIELD_DEPTH_MARGIN = 1.2
#: The volume depth over the static yield depth under a sliding load: the plastic zone of
#: repeated passes reaches below the static one's (2.2 a_H at p_0 = 5.2 k, where 1.2 times
#: the static 1.25 a_H truncated it and the plasticity loop then failed).
MOVING_DEPTH_MARGIN = 2.0
#: Loop tolerances must be below this (dimensionless).
MAX_TOLERANCE = 0.1
#: Largest iteration cap of a loop.
MAX_ITERATIONS = 10_000_000
#: Largest number of FFTW threads.
MAX_FFT_THREADS = 256
#: Largest Anderson memory.
MAX_ANDERSON_MEMORY = 50

#: Hardening laws (``hardening.law``) and their keys.
HARDENING_KEYS = {
    "swift": {"B", "C", "n"},
    "linear": {"yield_stress", "modulus"},
    "perfect": {"yield_stress"},
}
#: Kinematic hardening laws (``hardening.kinematic.law``) and their keys.
KINEMATIC_KEYS = {"prager": {"C"}, "armstrong-frederick": {"C", "gamma"}}

#: Defaults of ``[solver]`` (:class:`solver.case.options.SolverOptions` takes them from here).
SOLVER_DEFAULTS = {
    "normal_tolerance": 1e-8,
    "normal_max_iterations": 2000,
    "slip_tolerance": 1e-6,
    "slip_max_iterations": 5000,
    "coupling_tolerance": 1e-6,
    "coupling_max_iterations": 100,
    "goodman": False,
    "max_load_ratio": 1.25,
    "plastic_tolerance": 1e-5,
    "plastic_max_iterations": 100,
    "anderson_memory": 5,
    "fft_threads": 1,
    "fft_planner": "estimate",
    "volume_precision": "double",
    "method": "incremental",
    "residual_print": "in_gap",
    "kinematic_cells": 8,
    "steady_order": 2,
}
#: Finest mesh of Koiter's mechanism, cells a contact radius (memory grows as the cube).
MAX_KINEMATIC_CELLS = 16
#: Smallest plasticity tolerance a single-precision volume convolution can settle to: its
#: rounding (~1e-7 of the stress) would otherwise keep the plasticity loop from converging.
MIN_SINGLE_PLASTIC_TOLERANCE = 1e-6


@dataclass(frozen=True)
class Key:
    """One key of a case table.

    Attributes
    ----------
    table : str
        The table it sits in (module docstring).
    name : str
        The key.
    kind : str
        TOML type(s): ``number``, ``integer``, ``string``, ``boolean``, ``table``, ``array``.
    unit : str
        SI unit, ``1`` for dimensionless, ``a_H`` for units of the Hertz radius, ``""`` for none.
    default : str
        Its default, or ``required`` / ``optional`` (no default: absent means not used).
    accepted : str
        What the validation accepts.
    used_by : str
        The scenes (bodies, loads, grids) that read it.
    doc : str
        What it sets.
    """

    table: str
    name: str
    kind: str
    unit: str
    default: str
    accepted: str
    used_by: str
    doc: str

    @property
    def path(self) -> str:
        """``table.name`` (``name`` at the top level)."""
        return f"{self.table}.{self.name}" if self.table else self.name

    @property
    def required(self) -> bool:
        """True when the table must give it."""
        return self.default == "required"


def _range(low: float, high: float, unit: str = "") -> str:
    return f"[{low:g}, {high:g}]" + (f" {unit}" if unit else "")


_EP = "elastic-plastic bodies"
_SWIFT = "Swift hardening"
_LOADS = "every case (a load stage)"
#: Every key of a case table, in the order of the case file.
CASE_KEYS: tuple[Key, ...] = (
    Key("", "body1", "table", "", "required", "a body table", "every case",
        "The upper body (the indenter)."),
    Key("", "body2", "table", "", "required", "a body table", "every case",
        "The lower body; z points into it."),
    Key("", "load", "table", "", "required", "a load table", "every case",
        "The load: one stage, or a path of stages."),
    Key("", "friction", "table", "", "optional", "a friction table", "every case",
        "Coulomb friction."),
    Key("", "grid", "table", "", "required", "a grid table", "every case", "The discretisation."),
    Key("", "solver", "table", "", "optional", "a solver table", "every case",
        "Tolerances, iteration caps and FFT settings of the loops."),
    Key("", "output", "table", "", "optional", "an output table", "every case",
        "Optional field outputs."),
    Key("", "wear", "table", "", "optional", "a wear table", "cases that slip",
        "Wear: the worn surface fed back into the contact after every increment."),
    Key("", "fatigue", "table", "", "optional", "a fatigue table", "passes over body 2",
        "Multiaxial fatigue of body 2 under the pass: Dang Van's and Crossland's criteria."),
    Key("", "model", "integer", "", "the current model",
        "a version that solves the case as the current model does",
        "every case", "The model version a normalised case was written by (part of the case "
        "id): the last version that changed how such a case is solved."),
    # bodies
    Key("bodyN", "behaviour", "string", "", "required", "rigid, elastic or elastic-plastic",
        "every body", "Constitutive behaviour (at least one body deforms)."),
    Key("bodyN", "radius", "number or \"inf\"", "m", "\"inf\" (flat)",
        _range(*RADIUS_RANGE, "m") + ' or "inf"', "every body",
        "Radius of curvature (a sphere); not with radius_x / radius_y."),
    Key("bodyN", "radius_x", "number or \"inf\"", "m", "\"inf\"",
        _range(*RADIUS_RANGE, "m") + ' or "inf"', "every body",
        "Radius of curvature in the x-z plane (an ellipsoid; R_x/R_y within 1:100)."),
    Key("bodyN", "radius_y", "number or \"inf\"", "m", "\"inf\"",
        _range(*RADIUS_RANGE, "m") + ' or "inf"', "every body",
        "Radius of curvature in the y-z plane."),
    Key("bodyN", "profile", "table", "", "optional (a quadric only)", "a profile table",
        "every body", "An axisymmetric shape added to the quadric (a sphere's radius at most: "
        "the pair stays axisymmetric); the load is then a normal_force and the domain is "
        "scaled by Sneddon's contact radius at the largest load (docs: shapes)."),
    Key("bodyN.profile", "shape", "string", "", "required", "cone, flat_punch or power",
        "profiles", "cone: h = r tan(angle); flat_punch: h = 0 for r <= radius, a circular arc "
        "of edge_radius beyond; power: h = coefficient r^exponent."),
    Key("bodyN.profile", "angle", "number", "degree", "required by its shape",
        f"(0, {PROFILE_MAX_ANGLE:g}]", "cones", "Angle between the cone's surface and the "
        "tangent plane."),
    Key("bodyN.profile", "radius", "number", "m", "required by its shape",
        _range(*RADIUS_RANGE, "m"), "flat punches", "Radius of the flat face."),
    Key("bodyN.profile", "edge_radius", "number", "m", "required by its shape",
        _range(*RADIUS_RANGE, "m"), "flat punches", "Radius of the rounded edge."),
    Key("bodyN.profile", "coefficient", "number", "m^(1-k)", "required by its shape", "> 0",
        "power laws", "A of h = A r^k."),
    Key("bodyN.profile", "exponent", "number", "1", "required by its shape",
        _range(*PROFILE_EXPONENT_RANGE), "power laws", "k of h = A r^k (1: a cone, 2: a "
        "paraboloid)."),
    Key("bodyN", "surface", "string or table", "", "optional", "a height-map file, or a "
        "surface table", "every body", "Heights given point by point (m, away from the other "
        "body), added to the quadric and profile: a netCDF/HDF5 file with height(y, x) over "
        "coordinates x, y (m), or {file = \"map.npy\", spacing = dx}; resampled onto the grid "
        "by cubic B-splines (docs: how-to \"Contact shapes\")."),
    Key("bodyN.surface", "file", "string", "", "one of file / case",
        "an existing .nc/.h5/.npy file", "height maps", "The height-map file (a relative path "
        "is taken from the campaign file's folder in a campaign, else from the working "
        "folder); not part of the case id."),
    Key("bodyN.surface", "case", "string", "", "one of file / case",
        "a converged elastic-plastic case: OUT/cases/<case id>, or a case's own .nc file",
        "dents",
        "An earlier case whose residual print (residual_displacement_z) is the surface: a "
        "second indentation on or beside a dent.  Its geometry only: the material starts "
        "virgin (no residual stress or hardening carried over)."),
    Key("bodyN.surface", "offset", "[dx, dy]", "m", "[0, 0]", "finite",
        "height maps, dents", "Where the map's origin lies in this case's frame (the first "
        "contact point of the smooth shape is the origin): a dent at offset [0.5 a, 0] lies "
        "half a contact radius along +x of the new contact."),
    Key("bodyN.surface", "spacing", "number or [dx, dy]", "m", "required for .npy",
        "> 0", "height maps in .npy", "Lattice spacing of a .npy map (rows y, columns x, "
        "centred on the origin)."),
    Key("bodyN.surface", "sha256", "string", "", "optional", "the map's content hash",
        "normalised cases", "Written by the solver into a normalised case: a map whose content "
        "changed since is refused (the case id holds it)."),
    Key("bodyN", "roughness", "table", "", "optional", "a roughness table", "every body",
        "A self-affine random surface added to the body's shape."),
    Key("bodyN.roughness", "rms", "number", "m", "one of rms / rms_slope", "> 0, below the "
        "domain side", "roughness", "Rms height of the realisation."),
    Key("bodyN.roughness", "rms_slope", "number", "1", "one of rms / rms_slope", f"(0, "
        f"{MAX_SURFACE_SLOPE:g}]", "roughness", "Rms slope of the realisation (spectral)."),
    Key("bodyN.roughness", "hurst", "number", "1", "required", "(0, 1]", "roughness",
        "Hurst exponent H: power spectrum ~ q^(-2(1+H))."),
    Key("bodyN.roughness", "long_cutoff", "number", "m", "required", "> short_cutoff",
        "roughness", "Longest wavelength of the self-affine range (roll-off below)."),
    Key("bodyN.roughness", "short_cutoff", "number", "m", "required",
        ">= 2 grid cells", "roughness", "Shortest wavelength (no content beyond)."),
    Key("bodyN.roughness", "seed", "integer", "1", "0", "[0, 2^63)", "roughness",
        "Seed of the white noise: one realisation per seed."),
    Key("bodyN", "E", "number", "Pa", "required (not for rigid)", _range(*MODULUS_RANGE, "Pa"),
        "elastic and elastic-plastic bodies", "Young's modulus."),
    Key("bodyN", "nu", "number", "1", "required (not for rigid)",
        "(-1, 0.5]; elastic-plastic: (-1, 0.5)", "elastic and elastic-plastic bodies",
        "Poisson's ratio."),
    Key("bodyN", "hardening", "table", "", "required for elastic-plastic", "a hardening table",
        _EP, "The hardening law."),
    Key("bodyN.hardening", "law", "string", "", "required", "swift, linear or perfect", _EP,
        "swift: sigma_Y = B (C + 1e6 e_p)^n; linear: sigma_Y0 + H e_p; perfect: sigma_Y0."),
    Key("bodyN.hardening", "B", "number", "Pa", "required by its law",
        "> 0; B C^n in the yield_stress range", _SWIFT,
        "Swift's coefficient (the paper's steel: 945e6)."),
    Key("bodyN.hardening", "C", "number", "1 (micro-strain)", "required by its law",
        _range(*SWIFT_OFFSET_RANGE), _SWIFT, "Swift's offset, a pre-strain in micro-strain "
        "(the paper's 20)."),
    Key("bodyN.hardening", "n", "number", "1", "required by its law", "(0, 1]", _SWIFT,
        "Swift's exponent (the paper's 0.121)."),
    Key("bodyN.hardening", "yield_stress", "number", "Pa", "required by its law",
        f"{YIELD_STRAIN_RANGE[0]:g} E to {YIELD_STRAIN_RANGE[1]:g} E",
        "linear and perfect hardening", "Initial yield stress sigma_Y0 (Swift's is B C^n, in the "
        "same range)."),
    Key("bodyN.hardening", "modulus", "number", "Pa", "required by its law",
        f"[0, {MAX_HARDENING_RATIO:g} E]", "linear hardening", "Hardening modulus H."),
    Key("bodyN.hardening", "kinematic", "table", "", "optional (isotropic only)",
        "a kinematic table", _EP, "A back stress (kinematic hardening) beside the isotropic law."),
    Key("bodyN.hardening.kinematic", "law", "string", "", "required",
        "prager or armstrong-frederick", "kinematic hardening",
        "d alpha = (2/3) C d eps_p - gamma alpha dp (gamma = 0: Prager-Ziegler)."),
    Key("bodyN.hardening.kinematic", "C", "number", "Pa", "required by its law",
        f"(0, {MAX_HARDENING_RATIO:g} E]", "kinematic hardening", "Kinematic modulus C_k."),
    Key("bodyN.hardening.kinematic", "gamma", "number", "1", "required by its law",
        f"(0, {MAX_RECALL:g}]", "Armstrong-Frederick", "Recall; the back stress saturates at "
        "C_k / gamma."),
    # load
    Key("load", "hertz_pressure", "number", "Pa", "one of hertz_pressure / normal_force",
        f"p_H / E* in {_range(*PRESSURE_RATIO_RANGE)}", _LOADS,
        "Target load as the Hertz peak pressure of the pair (>= 0 after the first stage; quadric "
        "bodies only: with a profile give normal_force)."),
    Key("load", "normal_force", "number", "N", "one of hertz_pressure / normal_force",
        "its Hertz pressure in the same range (with a profile: its mean pressure W/(pi a^2), "
        "Sneddon's radius within the slope limit); 0 unloads", _LOADS, "Target normal force W."),
    Key("load", "tangential_force", "number or [Qx, Qy]", "N", "[0, 0] (then the previous)",
        "|Q| < mu W (no gross sliding)", "friction", "Target tangential force on body 2."),
    Key("load", "tangential_shift", "number or [dx, dy]", "m", "none (the force is prescribed)",
        f"finite; |shift| <= {MAX_SHIFT:g} a (Hertz); not with tangential_force, slide, roll, "
        "creepage or steady; mu > 0; quadric elastic bodies, not periodic",
        "displacement control",
        "Target rigid tangential shift of body 1 relative to body 2 (the history "
        "tangential_shift_x/y) at the end of the stage, ramped from the shift before it: the "
        "tangential force is then a result (displacement-controlled fretting, partial to "
        "gross slip).  A later stage without tangential_shift or tangential_force holds "
        "the shift."),
    Key("load", "slide", "[dx, dy]", "m", "[0, 0] (no motion)",
        "finite; not with tangential_force; the window grows by the travel",
        "sliding contacts", "Travel of body 1's apex over body 2 during the stage, in gross "
        "sliding: the shear traction is mu p along the motion on body 2 (frictionless: a "
        "moving load).  The surface window covers every position of the path."),
    Key("load", "roll", "[dx, dy]", "m", "[0, 0] (no motion)",
        "finite; not with slide; the window grows by the travel", "rolling contacts",
        "Travel of the contact over body 2 during the stage, in rolling: each increment's slip "
        "is the rigid creepage times the distance rolled plus the change of the tangential "
        "displacement difference at the same point of body 2 (Kalker's transient theory).  "
        "With tangential_force the creepage is a result (tangential_shift over the travel), "
        "with creepage the force is."),
    Key("load", "creepage", "number or [xi, eta]", "1", "none (the tangential force is prescribed)",
        f"each within +-{MAX_CREEPAGE:g}; roll stages only; not with tangential_force; "
        "mu > 0", "rolling contacts",
        "Kalker's creepages: the rigid slip of body 1 relative to body 2 per unit distance "
        "rolled; the creep force on body 2 points along it.  A later stage without "
        "creepage or tangential_force keeps the rigid shift (rolls on at zero creepage)."),
    Key("load", "spin", "number", "1/m", "0",
        f"|spin| a within {MAX_CREEPAGE:g} (a the contact radius); roll stages only; mu > 0",
        "rolling contacts", "Rigid rotation of body 1 relative to body 2 about z per unit "
        "distance rolled, counter-clockwise from x to y, about the contact's centre; with "
        "creepage (the force a result) or tangential_force (the creepage a result)."),
    Key("load", "steady", "boolean", "", "false",
        "with creepage and/or spin, or tangential_force (|Q| < mu W) with or without spin; "
        "no roll or slide; elastic bodies; mu > 0", "steady rolling",
        "The steady state of rolling along +x at the stage's creepage and spin, or at its "
        "tangential force (the creepage then a result, histories creepage_x/y), solved "
        "directly (solver.surface.steady: Kalker's steady slip, an upwind difference along "
        "the rolling direction of order solver.steady_order): no travel; each increment of "
        "the ramp is one steady state (a creep curve)."),
    Key("load", "steps", "integer", "1", "1", f"[1, {MAX_STAGE_STEPS:,}]", _LOADS,
        "Increments of the linear ramp from the previous stage."),
    Key("load", "path", "array of tables", "", "optional (one stage)",
        f"stages and cycle blocks, at most {MAX_INCREMENTS:,} increments in all",
        "load paths", "The load path ([[load.path]]), instead of the keys above."),
    Key("load.path[i]", "hertz_pressure", "number", "Pa", "the previous stage's load",
        f"p_H / E* in {_range(*PRESSURE_RATIO_RANGE)}, or 0", "load paths",
        "As load.hertz_pressure (required in the first stage)."),
    Key("load.path[i]", "normal_force", "number", "N", "the previous stage's load",
        ">= 0, its Hertz pressure in range", "load paths", "As load.normal_force."),
    Key("load.path[i]", "tangential_force", "number or [Qx, Qy]", "N",
        "the previous stage's", "|Q| < mu W", "load paths with friction",
        "As load.tangential_force."),
    Key("load.path[i]", "tangential_shift", "number or [dx, dy]", "m",
        "none (the force is prescribed; after a shift stage the shift held)",
        f"|shift| <= {MAX_SHIFT:g} a; not with tangential_force", "displacement control",
        "As load.tangential_shift."),
    Key("load.path[i]", "slide", "[dx, dy]", "m", "[0, 0] (no motion)",
        "finite; not with tangential_force", "sliding contacts", "As load.slide."),
    Key("load.path[i]", "roll", "[dx, dy]", "m", "[0, 0] (no motion)",
        "finite; not with slide", "rolling contacts", "As load.roll."),
    Key("load.path[i]", "creepage", "number or [xi, eta]", "1",
        "none (the force is prescribed; after a creepage stage [0, 0])",
        f"each within +-{MAX_CREEPAGE:g}; roll stages; not with tangential_force",
        "rolling contacts", "As load.creepage."),
    Key("load.path[i]", "spin", "number", "1/m", "0",
        f"|spin| a within {MAX_CREEPAGE:g}; roll stages only",
        "rolling contacts", "As load.spin."),
    Key("load.path[i]", "steady", "boolean", "", "false",
        "with creepage and/or spin, or tangential_force with or without spin; not with roll "
        "or slide",
        "steady rolling", "As load.steady."),
    Key("load.path[i]", "steps", "integer", "1", "1", f"[1, {MAX_STAGE_STEPS:,}]", "load paths",
        "As load.steps."),
    Key("load.path[i] (cycle block)", "cycles", "integer", "1", "required",
        f"[1, {MAX_CYCLES:,}]", "cyclic paths", "Repeats the block's stages (blocks do not nest)."),
    Key("load.path[i] (cycle block)", "stages", "array of tables", "", "required",
        "non-empty, stages as in load.path[i]", "cyclic paths", "The stages of one cycle."),
    # friction, grid
    Key("friction", "coefficient", "number", "1", "0",
        f"0 or [{MIN_FRICTION:g}, {MAX_FRICTION:g}]; at most {MAX_THEOREM_FRICTION:g} with "
        "solver.method = static_shakedown", "every case",
        "Coulomb coefficient mu (0: frictionless)."),
    Key("friction", "shear_limit", "number or string", "Pa", "none (Coulomb's law alone)",
        f"a stress in {_range(*SHEAR_LIMIT_RANGE)}, \"yield\" with an elastic-plastic body, "
        "or \"none\" (no limit: a campaign sweeps the limit against its absence)",
        "cases with friction",
        "Caps the friction traction: |q| <= min(mu p, m tau_c) (Orowan's law).  A stress: "
        "tau_c everywhere, elastic pairs too.  \"yield\": tau_c is the current shear yield "
        "stress of the plastic body's top layer under each cell, k = sigma_Y(e_p) / sqrt 3, "
        "following its hardening (the softer body's where both are plastic)."),
    Key("friction", "shear_factor", "number", "1", "1", f"[{MIN_SHEAR_FACTOR:g}, 1]",
        "friction.shear_limit",
        "Orowan's factor m: the cap is m tau_c (an interface weaker than the metal)."),
    Key("fatigue", "bending_limit", "number", "Pa", "required",
        f"{_range(*FATIGUE_LIMIT_RANGE)}; torsion_limit / bending_limit in (1/sqrt 3, 1)",
        "fatigue",
        "Body 2's fully reversed bending (or tension) fatigue limit f_-1: a stress amplitude."),
    Key("fatigue", "torsion_limit", "number", "Pa", "required", _range(*FATIGUE_LIMIT_RANGE),
        "fatigue",
        "Body 2's fully reversed torsion fatigue limit t_-1: a shear amplitude.  With "
        "bending_limit it sets Crossland's alpha = 3 t/f - sqrt 3, beta = t and Dang Van's "
        "a = 3 t/f - 3/2, b = t."),
    Key("wear", "law", "string", "", "required", ", ".join(WEAR_LAWS), "wear",
        "archard: the depth worn dh = k p |s| (p the pressure, s the local slip increment); "
        "energy: dh = alpha q . s, the friction energy dissipated per area (Fouvry)."),
    Key("wear", "body1", "number", "1/Pa", "0 (no wear)",
        f"0 or {_range(*WEAR_COEFFICIENT_RANGE)}; 0 when body 1 slides or rolls", "wear",
        "Body 1's coefficient k (m^3 per N per m) or alpha (m^3 per J); a rigid body wears too."),
    Key("wear", "body2", "number", "1/Pa", "0 (no wear)",
        f"0 or {_range(*WEAR_COEFFICIENT_RANGE)}", "wear",
        "Body 2's coefficient k or alpha (one of the two bodies must wear)."),
    Key("wear", "cycle_jump", "integer or \"auto\"", "cycles", "1 (every cycle solved)",
        f"[1, {MAX_CYCLES:,}] or \"auto\"; with a cycle block", "wear",
        "Cycles one solved cycle stands for: each cycle block of N cycles is solved as "
        "ceil(N / J) cycles, each one's wear scaled by the J cycles it stands for (the last by "
        "the rest).  \"auto\": each solved cycle's J is set from the pressure change the "
        "cycles before made, so that a jump changes the pressure by at most "
        "wear.pressure_change of its peak."),
    Key("wear", "pressure_change", "number", "1", f"{PRESSURE_CHANGE:g}",
        _range(*PRESSURE_CHANGE_RANGE), 'wear.cycle_jump = "auto"',
        "Largest change of the pressure a jump may make, relative to the peak pressure (the "
        "worn profile's error against every cycle solved is about half of it)."),
    Key("wear", "solved_cycles", "integer", "cycles", f"{SOLVED_CYCLES}",
        f"[2, {MAX_CYCLES:,}]", 'wear.cycle_jump = "auto"',
        "Most cycles solved per cycle block: when the bound asks for more, the last jumps "
        "grow past it and a note says so."),
    Key("grid", "n", "integer or [nx, ny] or [nx, ny, nz]", "cells", "required",
        f"each in [4, {MAX_CELLS}]; the contact spans >= {MIN_CELLS_ACROSS} cells",
        "every case", "Cells per side of the surface grid, and nz cells in depth of the volume "
        "grid (required by elastic-plastic bodies and the stress output)."),
    Key("grid", "size", "number or [Lx, Ly]", "m", "optional (half_width)",
        f"each in {_range(*SIZE_RANGE)}; square cells (Lx/nx = Ly/ny); the map or roughness "
        "within it",
        "height maps, roughness", "Side(s) of the surface domain in metres, instead of "
        "half_width; required when no body has a smooth shape (radius or profile)."),
    Key("grid", "nz", "integer", "cells", "optional", f"[4, {MAX_CELLS}]; not with a 3-entry n",
        "volume grids", "Volume cells in depth, apart from grid.n."),
    Key("grid", "half_width", "number", "a_H",
        f"{DEFAULT_HALF_WIDTH:g}; an elastic-plastic case's window holds its plastic box "
        f"({PLASTIC_WIDTH_MARGIN:g} x the elastic yield region's half width, <= "
        f"{MAX_AUTO_HALF_WIDTH:g})", "the contact fits (>= 1.1; 1.5 usual)",
        "every case", "Half side of the surface domain in units of the largest Hertz semi-axis "
        "(with a profile: Sneddon's contact radius) at the largest load.  Not given, the "
        "window of an elastic-plastic case widens to hold the plastic zone predicted from the "
        "elastic yield region (the plastic box then fills it); given narrower than that, "
        "validate warns that the case will likely end truncated.  Sliding and rolling cases "
        "keep 1.5 around the contact."),
    Key("grid", "depth", "number", "a_H (m with grid.periodic; b in a line contact)",
        f"1.2 x the Hertz yield depth "
        f"(a profile, a periodic surface: of the computed elastic yield region; >= "
        f"{DEFAULT_DEPTH:g} a_H; 2 x under a sliding load; periodic with no elastic yield: "
        f"{DEFAULT_PERIODIC_DEPTH:g} of the period); {DEFAULT_DEPTH:g} for elastic bodies",
        f"{_range(*DEPTH_RANGE)}, periodic [a surface cell, {MAX_PERIODIC_DEPTH:g} of the "
        f"period]; plastic bodies: cells <= {MAX_CELL_DEPTH:g} a_H, the box reaches where "
        f"yield starts, >= {MIN_YIELD_CELLS} cells across the yield region", "volume grids",
        "Depth of the volume grid (the plastic box); in metres for a periodic surface, which "
        "has no Hertz radius; in units of Hertz's half-width b for a line contact "
        '(grid.periodic = "y", elastic: its plane-strain stresses).'),
    Key("grid", "plastic_half_width", "number", "a_H",
        f"{PLASTIC_WIDTH_MARGIN:g} x the half width of the elastic yield region at the maximum "
        f"load (>= {MIN_PLASTIC_HALF_WIDTH:g}, <= half_width)",
        f"[{MIN_PLASTIC_HALF_WIDTH:g}, half_width]", "elastic-plastic bodies",
        "Half side of the plastic box: plastic strain lives, and the volume convolutions run, on "
        "the cells within this distance of the axis along x and y (the surface window stays "
        "half_width; half_width itself: the whole window).  By default sized from the Hertz "
        "stress (a profile: the computed elastic stress, solver.case.sizing), with a sliding shear "
        "of the path's largest |Q|/W, where it exceeds the initial "
        "yield stress, its cell count rounded up to a fast FFT size; a plastic zone reaching "
        "its sides is a note and the status truncated."),
    Key("grid", "follow_contact", "boolean", "", "true", "true or false", "sliding and rolling",
        "Solve each increment of a moving contact on a window that follows it (grid.half_width "
        "around the contact, plus the step's travel) instead of the whole track: the plastic "
        "strain stays in body 2's volume under the whole track and enters every later increment "
        "once per increment; the plasticity iterations run on the window's volume alone.  false: "
        "every increment on the whole track's window (slower; the reference to check it).  "
        "Not with a height map, roughness or two elastic-plastic bodies (the whole track then)."),
    Key("grid", "periodic", 'boolean or "y"', "", "false",
        'true, false or "y"; both need grid.size; true: flat bodies (no radius or profile), '
        'periodic heights, body 1 rigid or elastic, no slide or roll; "y": elastic bodies '
        "uniform along y (a cylinder: radius_x only), no heights, no slide, roll or spin",
        "rough flat surfaces; line contacts (a cylinder, Carter's rolling)",
        "The domain grid.size = [Lx, Ly] is one period of a nominally flat surface in x and y: "
        "periodic influence coefficients (Fourier-space forms, solver.surface.periodic), a "
        "roughness generated on the period, a height map used as one period (its opposite "
        "edges must join), contact spots joined across the period's sides.  Body 2 may be "
        "elastic-plastic (grid.n = [nx, ny, nz]): its volume grid is the whole period, "
        "laterally periodic (solver.numerics.images), grid.depth in metres, sized from the "
        "period's elastic yield region when not given; a mean pressure whose uniaxial strain "
        "alone yields the body is refused.  Normal loading, and friction with tangential loads "
        "(the normal-tangential coupling of dissimilar bodies included).  \"y\": the domain is one "
        "period along y only and the whole surface along x (solver.surface.periodic, "
        "YPeriodicSurfaceOperator): a line contact of bodies uniform along y, the normal force "
        "that on the period's length Ly (the rigid approach is then defined up to a constant, "
        "the plane-strain displacement's), normal, tangential and steady rolling stages."),
    Key("grid", "depth_body1", "number", "a_H", "depth if given, else body 1's yield depth",
        "as grid.depth", "two elastic-plastic bodies, different or loaded tangentially",
        "Depth of body 1's own volume grid."),
    # output
    Key("output", "fields", "array of strings", "", "[]", ", ".join(OPTIONAL_FIELDS),
        "volume grids (plastic outputs: elastic-plastic bodies)", "Optional field outputs."),
    # solver
    Key("solver", "normal_tolerance", "number", "1", f"{SOLVER_DEFAULTS['normal_tolerance']:g}",
        f"(0, {MAX_TOLERANCE:g})", "every case", "Normal CG: complementarity relative to p_H."),
    Key("solver", "normal_max_iterations", "integer", "1",
        str(SOLVER_DEFAULTS["normal_max_iterations"]), f"[1, {MAX_ITERATIONS:,}]", "every case",
        "Iteration cap of the normal CG."),
    Key("solver", "slip_tolerance", "number", "1", f"{SOLVER_DEFAULTS['slip_tolerance']:g}",
        f"(0, {MAX_TOLERANCE:g})", "friction", "Tangential active-set solve: KKT residual."),
    Key("solver", "slip_max_iterations", "integer", "1",
        str(SOLVER_DEFAULTS["slip_max_iterations"]), f"[1, {MAX_ITERATIONS:,}]", "friction",
        "Iteration cap of the tangential solve."),
    Key("solver", "coupling_tolerance", "number", "1",
        f"{SOLVER_DEFAULTS['coupling_tolerance']:g}", f"(0, {MAX_TOLERANCE:g})",
        "friction with beta != 0", "Normal-tangential coupling: pressure change."),
    Key("solver", "coupling_max_iterations", "integer", "1",
        str(SOLVER_DEFAULTS["coupling_max_iterations"]), f"[1, {MAX_ITERATIONS:,}]",
        "friction with beta != 0", "Iteration cap of the coupling loop."),
    Key("solver", "goodman", "boolean", "", "false", "true or false", "friction with beta != 0",
        "Drop the shear-to-normal coupling (Goodman's approximation)."),
    Key("solver", "max_load_ratio", "number or \"inf\"", "1",
        f"{SOLVER_DEFAULTS['max_load_ratio']:g}", '> 1, or "inf" (no sub-steps)',
        "friction with beta != 0", "Largest growth of W per sub-step of a coupled increment."),
    Key("solver", "plastic_tolerance", "number", "1", f"{SOLVER_DEFAULTS['plastic_tolerance']:g}",
        f"(0, {MAX_TOLERANCE:g})", _EP, "Plasticity loop: change of the increment over the "
        "yield strain sigma_Y0 / E."),
    Key("solver", "plastic_max_iterations", "integer", "1",
        str(SOLVER_DEFAULTS["plastic_max_iterations"]), f"[1, {MAX_ITERATIONS:,}]", _EP,
        "Iteration cap of the plasticity loop."),
    Key("solver", "anderson_memory", "integer", "1", str(SOLVER_DEFAULTS["anderson_memory"]),
        f"[0, {MAX_ANDERSON_MEMORY}]", "elastic-plastic bodies, coupled friction",
        "Past iterates Anderson acceleration mixes (0: plain fixed point)."),
    Key("solver", "fft_threads", "integer", "1", str(SOLVER_DEFAULTS["fft_threads"]),
        f"[1, {MAX_FFT_THREADS}]", "every case", "FFTW threads (not part of the case id)."),
    Key("solver", "fft_planner", "string", "", f'"{SOLVER_DEFAULTS["fft_planner"]}"',
        '"estimate" (reproducible), "measure" or "wisdom"', "every case",
        "FFTW planning (not part of the case id): \"measure\" times the candidates in every "
        "process (faster, may round differently between processes); \"wisdom\" takes "
        "measured plans saved per machine (python -m study run measures the missing ones once, "
        "on rank 0, and hands them to every rank), the estimate plan where none is saved: "
        "reproducible."),
    Key("solver", "volume_precision", "string", "", f'"{SOLVER_DEFAULTS["volume_precision"]}"',
        f'"double" or "single" (with plastic_tolerance >= {MIN_SINGLE_PLASTIC_TOLERANCE:g})', _EP,
        "Floating-point precision of the 3-D eigenstrain convolution (kernels, FFTs, products; "
        "with the traction stresses it carries when the plastic box is the window); "
        '"single" uses about half its memory and saves about 1/6 of the CPU at 48^3 '
        "(docs/tables/plastic.md), results within ~1e-7 of double's (part of the case id when "
        "single)."),
    Key("solver", "residual_print", "string", "", f'"{SOLVER_DEFAULTS["residual_print"]}"',
        '"in_gap" or "ignored"', "elastic-plastic bodies",
        '"in_gap": the residual surface displacements of the plastic strain enter the gap (the '
        'contact conforms to its print); "ignored": they are recorded but left out of the '
        "gap, so the tractions are those of the unchanging surface (the assumption of the "
        "classical shakedown theorems: compare like with like); part of the case id when "
        "ignored."),
    Key("solver", "method", "string", "", f'"{SOLVER_DEFAULTS["method"]}"',
        '"incremental" or "static_shakedown"', "elastic-plastic body 2 on a sliding track",
        '"incremental": the four loops along the load path; "static_shakedown": Melan\'s '
        "static theorem solved directly for the case's sliding Hertz contact (a lower bound of "
        "the shakedown limit on the track's cross-section, an upper bound beside it, "
        "solver.theorems); part of the case id when not incremental."),
    Key("solver", "steady_order", "integer", "", str(SOLVER_DEFAULTS["steady_order"]),
        "1 or 2", "steady rolling stages",
        "Order of the upwind difference of a steady rolling stage's slip along the rolling "
        "direction: 1 is Kalker's CONTACT's scheme (the transient step of one cell), 2 the "
        "second-order upwind difference (C11 within 0.2 % of Kalker's at a/13); part of the "
        "case id when 1."),
    Key("solver", "kinematic_cells", "integer", "", str(SOLVER_DEFAULTS["kinematic_cells"]),
        f"0 to {MAX_KINEMATIC_CELLS}", 'method = "static_shakedown", circular contacts',
        "Cells a contact radius of the mechanism of Koiter's kinematic upper bound "
        "(solver.theorems.koiter); 0: not solved.  Its time and memory grow as the cube "
        "(measured in docs/validation.md).  Part of the case id of static_shakedown cases."),
)  # fmt: skip


@functools.cache
def table_keys(table: str) -> frozenset[str]:
    """The keys a table accepts (module docstring for the table names)."""
    keys = frozenset(key.name for key in CASE_KEYS if key.table == table)
    if not keys:
        raise KeyError(f"no table {table!r} is declared")
    return keys


@functools.cache
def required_keys(table: str) -> frozenset[str]:
    """The keys a table must give."""
    return frozenset(key.name for key in CASE_KEYS if key.table == table and key.required)
