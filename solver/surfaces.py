"""Surfaces given point by point: height maps and self-affine random roughness.

Heights are in metres, measured away from the other body (as a sphere's sag ``r^2/(2R)``), over
the common x, y frame whose origin is the first contact point of the smooth shape; they add to
the body's quadric and profile (:class:`solver.geometry.Geometry`).

* :class:`HeightMap`: a measured or computed topography on a uniform lattice, checked on
  construction (2-D, finite, uniform spacing, at least 4 x 4 points) and resampled onto the
  solver's cell centres by cubic B-spline interpolation (``scipy.ndimage.map_coordinates``,
  order :data:`MAP_ORDER`).  Reading files is the study layer's job (``study.surfaces``).
* :class:`Roughness`: a self-affine Gaussian surface made by FFT filtering of white noise
  (numpy's PCG64 seeded by ``seed``) on a lattice of its own, so a mesh refinement samples the
  same surface: spacing ``short_cutoff / 4``, side the smallest ``long_cutoff 2^k`` (k >= 0) that
  covers the domain.  Its power spectrum is ``C(q) ~ q^(-2(1+H))`` between the wavenumbers of
  ``long_cutoff`` and ``short_cutoff``, flat below (a roll-off), zero above; the realisation is
  scaled to the given rms height (or rms slope, taken spectrally on the lattice) exactly.
"""

from __future__ import annotations

import functools
import hashlib
import math
from dataclasses import dataclass

import numpy as np

#: Order of the B-spline that resamples a height map onto the solver grid (3: cubic).
MAP_ORDER = 3
#: Lattice points per shortest wavelength of a random roughness.
ROUGHNESS_POINTS_PER_CUTOFF = 4
#: Largest lattice side (points) of a random roughness.
MAX_ROUGHNESS_LATTICE = 8192
#: Relative tolerance on the uniformity of a height map's spacing.
SPACING_RTOL = 1e-6


class SurfaceError(ValueError):
    """A height map or roughness that cannot be used; the message says why and what to do."""


class HeightMap:
    """A height map h(x, y) (m) on a uniform lattice.

    Parameters
    ----------
    x, y : array_like
        Lattice coordinates (m), 1-D, uniform, strictly increasing (decreasing ones are flipped).
    height : array_like
        Heights (m), shape (len(y), len(x)): ``height[j, i]`` at ``(x[i], y[j])``.
    source : str
        Where the map comes from (a file name), for messages.

    Raises
    ------
    SurfaceError
        If the map is not a 2-D grid of finite heights on uniform coordinates.
    """

    def __init__(self, x, y, height, source: str = "the height map") -> None:
        self.source = source
        self.origin: dict = {}  # the surface table it was read from (solver.case)
        x, y = (np.asarray(v, dtype=float) for v in (x, y))
        height = np.asarray(height, dtype=float)
        if height.ndim != 2:
            raise SurfaceError(
                f"{source}: height must be a 2-D grid height(y, x), got {height.ndim}-D"
            )
        if x.ndim != 1 or y.ndim != 1 or height.shape != (y.size, x.size):
            raise SurfaceError(
                f"{source}: height has shape {height.shape} but the coordinates give "
                f"(y, x) = ({y.size}, {x.size}); height must be height(y, x)"
            )
        if min(height.shape) < 4:
            raise SurfaceError(f"{source}: at least 4 x 4 points are needed, got {height.shape}")
        if not np.isfinite(height).all():
            bad = int(np.count_nonzero(~np.isfinite(height)))
            raise SurfaceError(
                f"{source}: {bad} heights are NaN or infinite (missing points); fill them "
                "(e.g. by interpolation) before using the map"
            )
        for name, axis in (("x", x), ("y", y)):
            if not np.isfinite(axis).all():
                raise SurfaceError(f"{source}: coordinate {name} has NaN or infinite values")
        if x[1] < x[0]:
            x, height = x[::-1], height[:, ::-1]
        if y[1] < y[0]:
            y, height = y[::-1], height[::-1, :]
        self.dx, self.dy = (_spacing(axis, name, source) for name, axis in (("x", x), ("y", y)))
        self.x, self.y = x, y
        self.height = np.ascontiguousarray(height)
        self.height.setflags(write=False)
        digest = hashlib.sha256()
        digest.update(np.array([x[0], self.dx, y[0], self.dy], dtype="<f8").tobytes())
        digest.update(np.array(height.shape, dtype="<i8").tobytes())
        digest.update(self.height.astype("<f8").tobytes())
        self.digest = digest.hexdigest()

    def __eq__(self, other: object) -> bool:
        return isinstance(other, HeightMap) and other.digest == self.digest

    def __hash__(self) -> int:
        return hash(self.digest)

    def __repr__(self) -> str:
        return f"HeightMap({self.source!r}, {self.height.shape[1]} x {self.height.shape[0]})"

    @property
    def extent(self) -> tuple[float, float, float, float]:
        """(x_min, x_max, y_min, y_max) (m) of the lattice."""
        return (self.x[0], self.x[-1], self.y[0], self.y[-1])

    def sample(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        """Heights (m) at points ``x``, ``y`` (m) by cubic B-spline interpolation."""
        from scipy import ndimage

        coords = np.stack([(np.asarray(y) - self.y[0]) / self.dy, (x - self.x[0]) / self.dx])
        return ndimage.map_coordinates(
            self.height, coords.reshape(2, -1), order=MAP_ORDER, mode="nearest"
        ).reshape(np.shape(x))


def _spacing(axis: np.ndarray, name: str, source: str) -> float:
    steps = np.diff(axis)
    step = (axis[-1] - axis[0]) / (axis.size - 1)
    if not step > 0 or np.any(np.abs(steps - step) > SPACING_RTOL * abs(step)):
        raise SurfaceError(
            f"{source}: coordinate {name} is not uniformly spaced (steps from {steps.min():.6g} "
            f"to {steps.max():.6g} m); resample the map onto a uniform lattice"
        )
    return float(step)


@dataclass(frozen=True)
class Roughness:
    """A self-affine Gaussian random surface (module docstring).

    Parameters
    ----------
    hurst : float
        Hurst exponent H, in (0, 1].
    long_cutoff, short_cutoff : float
        Longest and shortest wavelengths of the self-affine range (m), long > short.
    rms : float
        Rms height (m), or None with ``rms_slope``.
    rms_slope : float
        Rms slope (dimensionless), or None with ``rms``.
    seed : int
        Seed of the white noise.
    """

    hurst: float
    long_cutoff: float
    short_cutoff: float
    rms: float | None = None
    rms_slope: float | None = None
    seed: int = 0

    def lattice(self, side: float) -> tuple[int, float]:
        """(points per side, spacing (m)) of the lattice that covers a domain of ``side`` (m)."""
        spacing = self.short_cutoff / ROUGHNESS_POINTS_PER_CUTOFF
        length = self.long_cutoff
        while length < side * (1 - 1e-12):
            length *= 2.0
        return math.ceil(length / spacing - 1e-9), spacing

    def sample(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        """Heights (m) at points ``x``, ``y`` (m): the lattice realisation, cubic-interpolated."""
        side = 2.0 * float(max(np.abs(x).max(), np.abs(y).max())) + 1e-300
        points, spacing = self.lattice(side)
        heights = _roughness_lattice(self, points, spacing)
        coordinate = (np.arange(points) - 0.5 * (points - 1)) * spacing
        return HeightMap(coordinate, coordinate, heights, "roughness").sample(x, y)


@functools.lru_cache(maxsize=4)
def _roughness_lattice(roughness: Roughness, points: int, spacing: float) -> np.ndarray:
    """The realisation on its lattice (m), shape (points, points) = (y, x)."""
    if points > MAX_ROUGHNESS_LATTICE:
        raise SurfaceError(
            f"the roughness lattice would need {points} points per side (long_cutoff "
            f"{roughness.long_cutoff:g} m x 2^k over short_cutoff/"
            f"{ROUGHNESS_POINTS_PER_CUTOFF}), more than {MAX_ROUGHNESS_LATTICE}; raise "
            "short_cutoff or lower long_cutoff"
        )
    q = 2.0 * math.pi * np.fft.fftfreq(points, spacing)
    qx, qy = np.meshgrid(q, q, indexing="xy")
    wavenumber = np.hypot(qx, qy)
    q_long = 2.0 * math.pi / roughness.long_cutoff
    q_short = 2.0 * math.pi / roughness.short_cutoff
    exponent = -(1.0 + roughness.hurst)  # amplitude ~ sqrt(C) ~ q^(-(1+H))
    amplitude = np.where(
        wavenumber <= q_short, np.maximum(wavenumber, q_long) ** exponent / q_long**exponent, 0.0
    )
    amplitude[0, 0] = 0.0  # zero mean
    noise = np.random.Generator(np.random.PCG64(roughness.seed)).standard_normal((points, points))
    spectrum = np.fft.fft2(noise) * amplitude
    heights = np.fft.ifft2(spectrum).real
    if roughness.rms is not None:
        scale = roughness.rms / math.sqrt(np.mean(heights**2))
    else:
        slope2 = np.sum(wavenumber**2 * np.abs(spectrum) ** 2) / points**4
        scale = roughness.rms_slope / math.sqrt(slope2)
    out = heights * scale
    out.setflags(write=False)
    return out
