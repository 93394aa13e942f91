"""Multiaxial high-cycle fatigue criteria on stress paths: Dang Van's and Crossland's.

A material point that has shaken down elastically sees a periodic stress path sigma(t) as the
contact passes (or cycles).  With p_h = tr(sigma) / 3 the hydrostatic stress and s the deviator,
both criteria read the path's deviatoric part through its smallest enclosing ball
(:mod:`.ball`, in the norm |s| = sqrt(s : s)), centre s* and radius R:

* Crossland: sigma_C = sqrt(J2,a) + alpha_C max_t p_h(t), with sqrt(J2,a) = R / sqrt 2 (the
  amplitude of sqrt(J2) = |s| / sqrt 2); safe while sigma_C <= beta_C.
* Dang Van: the mesoscopic deviator s(t) - s* (the ball's centre is the stabilised residual
  stress of the grains) gives the mesoscopic Tresca shear tau(t) = (s1 - s3) / 2 of its
  principal values; sigma_DV = max_t [tau(t) + a_DV p_h(t)], safe while sigma_DV <= b_DV.

The parameters follow from two fatigue limits (amplitudes of fully reversed tests), bending
f_-1 and torsion t_-1: under reversed bending sqrt(J2,a) = f/sqrt 3, max p_h = f/3 and the
largest tau + a p_h is f/2 + a f/3 (both at the peak); under reversed torsion p_h = 0 and
sqrt(J2,a) = max tau = t.  Setting both at their limits,

    beta_C = b_DV = t_-1,   alpha_C = 3 t_-1 / f_-1 - sqrt 3,   a_DV = 3 t_-1 / f_-1 - 3/2,

valid for 1/sqrt 3 < t_-1 / f_-1 < 1 (metals: about 0.55 to 0.8; below, alpha_C <= 0).  The
factor of safety of a path is beta / sigma_eq (infinite where sigma_eq <= 0).

The 5-D coordinates of a deviator keep its norm: (s_xx - s_yy)/sqrt 2, sqrt(3/2) s_zz,
sqrt 2 s_yz, sqrt 2 s_xz, sqrt 2 s_xy (tensor components in :data:`COMPONENTS` order).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..numerics.tensor import deviator, trace
from .ball import smallest_balls

#: The criteria, in the order of every array of them.
CRITERIA = ("dang_van", "crossland")


@dataclass(frozen=True)
class FatigueLimits:
    """A material's fatigue parameters, from its fully reversed limits (module docstring).

    Attributes
    ----------
    bending : float
        f_-1 (Pa): the stress amplitude of the fully reversed bending (or tension) limit.
    torsion : float
        t_-1 (Pa): the shear amplitude of the fully reversed torsion limit.
    """

    bending: float
    torsion: float

    def __post_init__(self) -> None:
        for name in ("bending", "torsion"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise ValueError(f"the {name} fatigue limit must be a positive stress: {value!r}")
        ratio = self.torsion / self.bending
        if not 1.0 / math.sqrt(3.0) < ratio < 1.0:
            raise ValueError(
                f"the torsion limit over the bending limit must be in (1/sqrt 3, 1) = "
                f"(0.577, 1), got {ratio:.4g}: below, Crossland's pressure coefficient is <= 0; "
                "at or above 1, torsion is not the milder test"
            )

    def spec(self) -> dict:
        """The normalised ``[fatigue]`` table."""
        return {"bending_limit": self.bending, "torsion_limit": self.torsion}

    @property
    def crossland(self) -> tuple[float, float]:
        """(alpha_C, beta_C (Pa))."""
        return 3.0 * self.torsion / self.bending - math.sqrt(3.0), self.torsion

    @property
    def dang_van(self) -> tuple[float, float]:
        """(a_DV, b_DV (Pa))."""
        return 3.0 * self.torsion / self.bending - 1.5, self.torsion


@dataclass
class FatigueResult:
    """The criteria on a set of stress paths (one per point).

    Attributes
    ----------
    dang_van, crossland : numpy.ndarray
        The equivalent stresses sigma_DV and sigma_C (Pa), one per path.
    dang_van_factor, crossland_factor : numpy.ndarray
        The factors of safety b_DV / sigma_DV and beta_C / sigma_C (inf where sigma <= 0).
    shear_amplitude : numpy.ndarray
        sqrt(J2,a) (Pa): the ball's radius over sqrt 2.
    excess : numpy.ndarray
        How far a path's farthest point lies outside its ball, relative (:func:`smallest_balls`;
        round-off when solved).
    """

    dang_van: np.ndarray
    crossland: np.ndarray
    dang_van_factor: np.ndarray
    crossland_factor: np.ndarray
    shear_amplitude: np.ndarray
    excess: np.ndarray


def deviatoric_coordinates(stress: np.ndarray) -> np.ndarray:
    """The 5-D coordinates (Pa) of the deviators of ``stress`` (6, ...) (module docstring)."""
    s = deviator(stress)
    root2 = math.sqrt(2.0)
    return np.stack(
        [
            (s[0] - s[1]) / root2,
            math.sqrt(1.5) * s[2],
            root2 * s[3],
            root2 * s[4],
            root2 * s[5],
        ]
    )


def _tresca(s: np.ndarray) -> np.ndarray:
    """Half the largest difference of principal values of deviators s (6, ...).

    In closed form: with J2 = s : s / 2, J3 = det s and the Lode angle
    theta = arccos((3 sqrt 3 / 2) J3 / J2^(3/2)) / 3 in [0, pi/3], the principal values are
    2 sqrt(J2/3) cos(theta - 2 pi k / 3), so (s1 - s3) / 2 = sqrt(J2) sin(theta + pi/3).
    """
    xx, yy, zz, yz, xz, xy = s
    j2 = 0.5 * (xx * xx + yy * yy + zz * zz) + yz * yz + xz * xz + xy * xy
    j3 = xx * (yy * zz - yz * yz) - xy * (xy * zz - yz * xz) + xz * (xy * yz - yy * xz)
    root = np.sqrt(j2)
    with np.errstate(divide="ignore", invalid="ignore"):
        cosine = np.where(j2 > 0, 1.5 * math.sqrt(3.0) * j3 / (j2 * root), 1.0)
    theta = np.arccos(np.clip(cosine, -1.0, 1.0)) / 3.0
    return root * np.sin(theta + math.pi / 3.0)


def fatigue_criteria(paths: np.ndarray, limits: FatigueLimits) -> FatigueResult:
    """Dang Van's and Crossland's criteria of stress paths (module docstring).

    Parameters
    ----------
    paths : numpy.ndarray
        Shape (6, points, samples): the stress (Pa) of each point at each sample of its
        path (a pass or a cycle, sampled finely enough to hold its peaks).
    limits : FatigueLimits
        The material's fatigue limits.
    """
    paths = np.asarray(paths, dtype=float)
    pressure = trace(paths) / 3.0  # (points, samples)
    coordinates = np.moveaxis(deviatoric_coordinates(paths), 0, -1)  # (points, samples, 5)
    centres, radii, excess = smallest_balls(coordinates)
    amplitude = radii / math.sqrt(2.0)
    alpha, beta = limits.crossland
    crossland = amplitude + alpha * pressure.max(axis=1)
    # the mesoscopic deviator: the path less the ball's centre, back in tensor components
    root2 = math.sqrt(2.0)
    c = centres.T[:, :, None]  # (5, points, 1)
    zz = c[1] / math.sqrt(1.5)
    centre_tensor = np.stack([(c[0] * root2 - zz) / 2, (-c[0] * root2 - zz) / 2, zz,
                              c[2] / root2, c[3] / root2, c[4] / root2])  # fmt: skip
    meso = deviator(paths) - centre_tensor
    a, b = limits.dang_van
    dang_van = (_tresca(meso) + a * pressure).max(axis=1)

    def factor(limit: float, value: np.ndarray) -> np.ndarray:
        with np.errstate(divide="ignore", over="ignore"):
            return np.where(value > 0, limit / np.maximum(value, 1e-300), np.inf)

    return FatigueResult(
        dang_van, crossland, factor(b, dang_van), factor(beta, crossland), amplitude, excess
    )


def steady_pass_criteria(
    stress: np.ndarray, limits: FatigueLimits, residual: np.ndarray | None = None
) -> tuple[FatigueResult, tuple[int, ...]]:
    """The criteria of a steady pass along x, from one snapshot of the moving load's field.

    A load that passes unchanged along x (a frictionless or sliding contact over an elastic,
    or elastically shaken-down, half-space) gives every material point on a line along x the
    same stress path, shifted in time: the snapshot's field along that line, sampled at its
    cells (the pass's sampling is the grid's spacing along x).  The residual stress of a
    steady track does not change along x; constant in time at a material point, it adds to
    each sample of the line's path.

    Parameters
    ----------
    stress : numpy.ndarray
        Shape (6, nx, ...): the moving load's stress field (Pa) at one position, x second.
    limits : FatigueLimits
        The material's fatigue limits.
    residual : numpy.ndarray, optional
        Shape (6, ...): the track's residual stress (Pa) on each line along x.

    Returns
    -------
    FatigueResult
        One value per line along x (the remaining axes flattened in C order).
    tuple of int
        The lines' shape (the remaining axes).
    """
    lines = np.moveaxis(np.asarray(stress, dtype=float), 1, -1)  # (6, ..., nx)
    shape = lines.shape[1:-1]
    paths = lines.reshape(6, -1, lines.shape[-1])
    if residual is not None:
        paths = paths + np.asarray(residual, dtype=float).reshape(6, -1, 1)
    return fatigue_criteria(paths, limits), shape
