"""Shakedown of a Hertz contact passing along a track: the static limit, bracketed.

A Hertz point contact (a sphere, circular) or line contact (a cylinder, plane strain) with the
sliding traction ``q_x = mu p`` (Hamilton 1983; McEwen 1949) passes along x over a half-space.
:func:`track_limits` sets up the cross-section (cells of ``a / cells``, a box ``width`` a to
the side of the track's centre line and ``depth`` a deep, positions from ``-span`` a to
``span`` a along the track) and returns, in units of k (the shear yield stress):

- the static program's factor (:func:`.melan.static_limit`): Melan's limit *on the section's
  points* (the cell centres and the surface above them, two positions a cell).  It samples
  the field and is an estimate, not a bound: the worst point of the limit lies between the
  points (on the centre plane y = 0, which no cell centre reaches; at the surface between the
  positions, where the sliding contact's edge passes), and it approaches the limit from above;
- the certified lower bound (:func:`certified_limit`): the program's residual field, bilinear
  between the section's points, checked at the points halfway between them and on y = 0, at
  :data:`BOUND_POSITIONS` positions a contact radius, and at the point where the pointwise
  upper bound was found (its own path): the largest factor with all of them within yield.
  It can lie below the limit, never above the pointwise bound;
- an upper bound: the smallest pointwise bound (:func:`.melan.pointwise_limit`) over the cells
  where the program binds, below them on the free surface, and a local search from the best;
- for a point contact, if asked, Koiter's kinematic upper bound (:func:`.koiter.kinematic_limit`)
  on a mesh of its own: a box of :data:`KINEMATIC_BOX` a (the mechanism may be confined: any
  admissible mechanism bounds the limit), the cycle's instants one a cell over
  :data:`KINEMATIC_SPAN` a either side.  A line contact needs none: its residual fields are
  those of a single layer, so the pointwise bound at the worst depth is the limit itself;
- first yield (:func:`solver.theory.shakedown.sliding_first_yield`) and the surface-flow line
  ``mu p0 = k``.

Classical values (frictionless, nu = 0.3): a line contact shakes down to 4.0 k (Johnson &
Jefferis 1963: the orthogonal shear 0.25 p0 cannot be relieved); a point contact to 4.7 k
(Ponter, Hearle & Johnson 1985, kinematic, an upper bound).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import minimize, minimize_scalar

from ..keys import MAX_THEOREM_FRICTION
from ..theory.half_space import hamilton_stress, mcewen_stress
from ..theory.shakedown import sliding_first_yield
from .koiter import KinematicLimit, kinematic_limit
from .melan import (
    SURFACE_SHIFTS,
    StaticLimit,
    certified_factors,
    deviatoric_coordinates,
    likeliest_cells,
    pointwise_limit,
    static_limit,
)
from .residual import interpolate_section, line_basis, section_basis

#: Contacts a track can carry.
CONTACTS = ("point", "line")
#: Depth (in a) at which the surface points' stress is evaluated (the closed forms need z > 0).
SURFACE = 1e-9
#: Positions per contact radius of the upper bound's stress paths (finer than the program's:
#: a coarse path would overstate the bound).
BOUND_POSITIONS = 100
#: Cells the upper bound tries: the widest stress paths, of all cells and of the binding ones.
CANDIDATES = 6
#: Evaluations of the upper bound's local search.
SEARCH_EVALUATIONS = 40
#: Half-width and depth of the kinematic mechanism's box, in a (the plastic zone of a sliding
#: sphere, mu <= 0.5, lies within 1 a of the centre line and the surface).
KINEMATIC_BOX = 1.5
#: Reach of the kinematic cycle's instants either side of the section, in a.
KINEMATIC_SPAN = 2.0
#: Sign of each deviator coordinate (:data:`.melan.DEVIATOR_BASIS`) across y = 0.
DEVIATOR_MIRROR_SIGNS = np.array([1.0, 1.0, -1.0, 1.0, -1.0])


@dataclass(frozen=True)
class Track:
    """A Hertz contact passing along x: the load and the cross-section's discretisation.

    Attributes
    ----------
    contact : str
        ``"point"`` or ``"line"``.
    friction : float
        mu: the shear traction ``mu p`` along +x (Hamilton's sliding), 0 to
        :data:`solver.keys.MAX_THEOREM_FRICTION`.
    nu : float
        Poisson's ratio.
    cells : int
        Cells per contact radius a (both y and z).
    width, depth, span : float
        Half-width and depth of the box, reach of the positions either side, in a.
    back_stress_bound : float or None
        Kinematic hardening: the largest norm ``|alpha| / k`` of the deviatoric back stress
        (Frobenius; the yield radius is sqrt 2 in these units, and an Armstrong-Frederick back
        stress saturating at ``C / gamma`` uniaxially has ``sqrt 2 (C / gamma) / sigma_Y``);
        ``inf`` for linear (Prager) hardening, None for perfect plasticity.
    """

    contact: str = "point"
    friction: float = 0.0
    nu: float = 0.3
    cells: int = 16
    width: float = 2.0
    depth: float = 4.0
    span: float = 4.0
    back_stress_bound: float | None = None

    def __post_init__(self):
        if self.contact not in CONTACTS:
            raise ValueError(f"contact must be one of {CONTACTS}, got {self.contact!r}")
        if not 0.0 <= self.friction <= MAX_THEOREM_FRICTION:
            raise ValueError(
                f"friction must be in [0, {MAX_THEOREM_FRICTION:g}], got {self.friction}"
            )
        if not -1.0 < self.nu < 0.5:
            raise ValueError(f"nu must be in (-1, 0.5), got {self.nu}")
        if self.cells < 2:
            raise ValueError(f"cells (per contact radius) must be at least 2, got {self.cells}")
        for name in ("width", "depth", "span"):
            if not getattr(self, name) >= 1.0:
                raise ValueError(
                    f"{name} must be at least 1 contact radius, got {getattr(self, name)}"
                )
        if self.back_stress_bound is not None and not self.back_stress_bound >= 0.0:
            raise ValueError(
                f"back_stress_bound must be >= 0 or None, got {self.back_stress_bound}"
            )

    def stress(self, s, y, z) -> np.ndarray:
        """Elastic stress per unit p0 at (y, z) with the load's centre at x = s: ``(6, ...)``."""
        if self.contact == "point":
            return hamilton_stress(-s, y, z, 1.0, 1.0, self.nu, self.friction)
        return mcewen_stress(-s, z, 1.0, 1.0, self.nu, self.friction)

    def positions(self, per_radius: float) -> np.ndarray:
        """Positions from ``-span`` to ``span`` (in a), ``per_radius`` a contact radius."""
        return np.linspace(-self.span, self.span, round(2 * self.span * per_radius) + 1)


@dataclass
class TrackLimits:
    """The shakedown limits of a track, in ``p0 / k``.

    Attributes
    ----------
    static : StaticLimit
        Melan's program on the section's points (``static.factor``: an estimate of the limit,
        not a bound; the residual field on the points).
    upper : float
        The smallest pointwise upper bound found.
    upper_at : (float, float)
        Where (y / a, z / a).
    first_yield : float
        First yield ``p0 / k``.
    surface_flow : float
        ``1 / mu``: the surface shear reaches k (inf for mu = 0).
    y, z : ndarray
        The cross-section's points (in a): y of the cell columns (the half y >= 0 of a point
        contact, 0 for a line), z of the surface (0) and the cell centres.
    kinematic : KinematicLimit or None
        Koiter's upper bound, where computed.
    lower : float
        The certified lower bound (:func:`certified_limit`; traction routes: ``static.factor``,
        certified on every point and position its pointwise bound sees).
    lower_at : (float, float, float)
        Where it binds: (y / a, z / a, the load's position s / a).
    """

    static: StaticLimit
    upper: float
    upper_at: tuple[float, float]
    first_yield: float
    surface_flow: float
    y: np.ndarray
    z: np.ndarray
    kinematic: KinematicLimit | None = None
    lower: float = math.nan
    lower_at: tuple[float, float, float] = (math.nan, math.nan, math.nan)


def track_limits(track: Track, kinematic_cells: int | None = None) -> TrackLimits:
    """Melan's static limit of a track, upper bounds beside it, first yield, surface flow.

    Parameters
    ----------
    track : Track
        The contact and the static program's cross-section.
    kinematic_cells : int, optional
        Cells a contact radius of Koiter's mechanism (point contacts only); None: not solved.
    """
    if kinematic_cells is not None and track.contact != "point":
        raise ValueError(
            "kinematic_cells: Koiter's mechanism is built for point contacts (a line "
            "contact's pointwise bound is its limit); leave it None"
        )
    h = 1.0 / track.cells
    layers = round(track.depth * track.cells)
    z = np.concatenate([[SURFACE], (np.arange(layers) + 0.5) * h])  # the surface, the cells
    s = track.positions(2.0 * track.cells)  # two positions a cell
    if track.contact == "point":
        y = (np.arange(round(track.width * track.cells)) + 0.5) * h  # the half y >= 0
        elastic = track.stress(s[:, None, None], y[None, :, None], z[None, None, :])
        basis = section_basis(y.size, layers, h, h, symmetric=True, surface=True)
        edge_y = np.linspace(0.0, track.width, 4 * y.size + 1)
        edge_z = np.linspace(h / 4, track.depth, 4 * z.size)
        edge = np.concatenate(
            [
                track.stress(s[:, None], edge_y[None, :], track.depth).reshape(6, -1),
                track.stress(s[:, None], track.width, edge_z[None, :]).reshape(6, -1),
            ],
            axis=1,
        )
    else:
        y = np.zeros(1)
        elastic = track.stress(s[:, None], 0.0, z[None, :])[:, :, None, :]
        basis = line_basis(z.size)
        edge = track.stress(s, 0.0, track.depth)
    static = static_limit(elastic, basis, 1.0, track.back_stress_bound, edge)
    upper, at = _upper_bound(track, static, elastic, y, z)
    lower, lower_at = certified_limit(track, static, y, z, s, at)
    first = sliding_first_yield(track.friction, track.nu, track.contact)[0]
    flow = math.inf if track.friction == 0.0 else 1.0 / track.friction
    z = np.concatenate([[0.0], z[1:]])
    kinematic = None
    if kinematic_cells is not None:
        instants = np.linspace(
            -KINEMATIC_SPAN, KINEMATIC_SPAN, round(2 * KINEMATIC_SPAN * kinematic_cells) + 1
        )
        kinematic = kinematic_limit(
            track.stress, instants, KINEMATIC_BOX, KINEMATIC_BOX, kinematic_cells,
            track.back_stress_bound,
        )  # fmt: skip
    return TrackLimits(static, upper, at, first, flow, y, z, kinematic, lower, lower_at)


def certified_limit(
    track: Track,
    static: StaticLimit,
    y: np.ndarray,
    z: np.ndarray,
    positions: np.ndarray,
    upper_at: tuple[float, float],
) -> tuple[float, tuple[float, float, float]]:
    """The static program's factor reduced until its field holds between its samples.

    The residual field (and back stress) of ``static``, known at the section's points
    ``(y, z)``, is taken bilinear between them (:func:`.residual.interpolate_section`, mirrored
    across y = 0).  It is checked at the points and those halfway between neighbours (y = 0
    among them), at the program's ``positions`` and :data:`BOUND_POSITIONS` a contact radius,
    and at ``upper_at`` on the pointwise bound's own path: the factor returned is the largest
    for which all of them are within yield (the smallest root of
    :func:`.melan.certified_factors`).  At ``upper_at`` no constant shift does better than the
    pointwise bound, so the factor cannot exceed it; between the checked points and positions
    nothing is proved (a finer section lowers the gap, see how-to "sliding").

    Parameters
    ----------
    track : Track
        The contact (its elastic field per unit p0, lengths in a).
    static : StaticLimit
        The program's solution on the section (residual in units of k).
    y, z : ndarray
        The section's points (a): cell columns, the surface (z at :data:`SURFACE`) and cells.
    positions : ndarray
        The program's load positions (a).
    upper_at : (float, float)
        Where the pointwise upper bound was found (y / a, z / a).

    Returns
    -------
    factor : float
        The certified lower bound (p0 / k).
    where : (float, float, float)
        (y, z, s) in a where it binds.
    """
    z0 = np.concatenate([[0.0], z[1:]])
    fine_z = np.sort(np.concatenate([z0, 0.5 * (z0[:-1] + z0[1:])]))
    if track.contact == "point":
        fine_y = np.sort(np.concatenate([[0.0], y, 0.5 * (y[:-1] + y[1:])]))
    else:
        fine_y = np.zeros(1)
    s = np.union1d(positions, track.positions(BOUND_POSITIONS))
    shifts = deviatoric_coordinates(static.residual)
    back = static.back_stress
    radius = np.array([math.sqrt(2.0)])
    best, where = math.inf, (math.nan, math.nan, math.nan)
    surface = upper_at[1] <= SURFACE  # the surface point itself: its field, not a cell's
    columns = [(py, fine_z) for py in fine_y]
    columns.append((upper_at[0], np.array([0.0 if surface else upper_at[1]])))
    for py, depths in columns:
        shift = interpolate_section(shifts, y, z0, py, depths, DEVIATOR_MIRROR_SIGNS)
        if back is not None:
            shift = shift - interpolate_section(back, y, z0, py, depths, DEVIATOR_MIRROR_SIGNS)
        path = track.stress(s[:, None], py, np.maximum(depths, SURFACE)[None, :])
        load = deviatoric_coordinates(path)
        roots = certified_factors(load, shift, np.broadcast_to(radius, depths.shape))
        if roots.min() < best:
            p, k = np.unravel_index(np.argmin(roots), roots.shape)
            best, where = float(roots[p, k]), (float(py), float(depths[k]), float(s[p]))
    return best, where


def _upper_bound(
    track: Track, static: StaticLimit, elastic: np.ndarray, y, z
) -> tuple[float, tuple[float, float]]:
    """The smallest pointwise bound over the likeliest cells, the surface, a local search."""
    s = track.positions(BOUND_POSITIONS)
    line = track.contact == "line"
    shifts = SURFACE_SHIFTS if line else None  # a line's fields: rho_xx, rho_yy, rho_xy only

    def bound(point) -> float:
        py, pz = abs(point[0]), max(point[1], SURFACE)
        surface = pz <= SURFACE
        path = track.stress(s, py, pz)
        allowed = SURFACE_SHIFTS if surface else shifts
        return pointwise_limit(path, allowed, 1.0, track.back_stress_bound)

    cells = likeliest_cells(elastic, static.binding, CANDIDATES)
    candidates = [(float(y[j]), float(z[k])) for j, k in cells]
    candidates += [(float(py), 0.0) for py in y]
    values = [bound(c) for c in candidates]
    best = int(np.nanargmin(values))
    start = candidates[best]
    if start[1] > SURFACE:  # a local search inside the body, or along the surface
        found = minimize(
            lambda p: bound((0.0 if line else p[0], max(p[1], 1e-6))),
            np.array(start),
            method="Nelder-Mead",
            options={"xatol": 1e-3, "fatol": 1e-5, "maxfev": SEARCH_EVALUATIONS},
        )
        point = (abs(float(found.x[0])), max(float(found.x[1]), 1e-6))
    elif not line:
        found = minimize_scalar(
            lambda py: bound((py, 0.0)),
            bounds=(0.0, track.width),
            method="bounded",
            options={"xatol": 1e-3, "maxiter": SEARCH_EVALUATIONS},
        )
        point = (float(found.x), SURFACE)
    else:
        return float(values[best]), start
    if found.fun < values[best]:
        return float(found.fun), point
    return float(values[best]), start


__all__ = [
    "BOUND_POSITIONS",
    "CONTACTS",
    "KINEMATIC_BOX",
    "KINEMATIC_SPAN",
    "Track",
    "TrackLimits",
    "certified_limit",
    "track_limits",
]
