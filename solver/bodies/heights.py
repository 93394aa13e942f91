"""Surfaces given point by point: height maps and self-affine random roughness.

Heights are in metres, measured away from the other body (as a sphere's sag ``r^2/(2R)``), over
the common x, y frame whose origin is the first contact point of the smooth shape; they add to
the body's quadric and profile (:class:`solver.bodies.geometry.Geometry`).

* :class:`HeightMap`: a measured or computed topography on a uniform lattice, checked on
  construction (2-D, finite, uniform spacing, at least 4 x 4 points) and resampled onto the
  solver's cell centres by cubic B-spline interpolation (``scipy.ndimage.map_coordinates``,
  order :data:`MAP_ORDER`).  Reading files is the study layer's job (``study.campaign.surfaces``).
* :class:`Roughness`: a self-affine Gaussian surface made by FFT filtering of white noise
  (numpy's PCG64 seeded by ``seed``) on a lattice of its own, so a mesh refinement samples the
  same surface: spacing ``short_cutoff / 4``, side the smallest ``long_cutoff 2^k`` (k >= 0) that
  covers the domain.  Its power spectrum is ``C(q) ~ q^(-2(1+H))`` between the wavenumbers of
  ``long_cutoff`` and ``short_cutoff``, flat below (a roll-off), zero above; the realisation is
  scaled to the given rms height (or rms slope, taken spectrally on the lattice) exactly.
* :func:`isotropic_spectrum`: the ring-averaged power spectral density of one period of
  heights (a run-in topography's, pass by pass).
"""

from __future__ import annotations

import functools
import hashlib
import math
import numbers
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
#: Relative tolerance of a map's own period (N dx) against the period it is used as.
PERIOD_RTOL = 1e-6
#: Largest rms height step across a periodic map's seam, over the rms step between its
#: neighbouring points inside (a smooth periodic map: about 1; an unwindowed measurement: more).
MAX_SEAM_STEP = 3.0
#: Fewest cells on the shortest wavelength of a roughness in periodic mode.
MIN_PERIODIC_CUTOFF_CELLS = 8
#: Points resampled at a time by :func:`grid_rms_slope` (bounds its memory, ~100 MB).
SLOPE_CHUNK_POINTS = 2**22


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
        self.origin: dict = {}  # the surface table it was read from (solver.case.case)
        x, y = (_real_array(v, f"coordinate {n}", source) for n, v in (("x", x), ("y", y)))
        height = _real_array(height, "height", source)
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

    @property
    def period(self) -> tuple[float, float]:
        """(N dx, M dy) (m): the period the map is one of when used periodically."""
        return self.x.size * self.dx, self.y.size * self.dy

    def sample(
        self, x: np.ndarray, y: np.ndarray, period: tuple[float, float] | None = None
    ) -> np.ndarray:
        """Heights (m) at points ``x``, ``y`` (m) by cubic B-spline interpolation.

        Beyond its points the map holds its edge values; with ``period`` (m), which must be its
        own (:attr:`period`), it is one period and wraps around.
        """
        from scipy import ndimage

        if period is not None and not np.allclose(period, self.period, rtol=PERIOD_RTOL):
            raise ValueError(f"{self.source} spans {self.period} m, not the period {period} m")
        coords = np.stack([(np.asarray(y) - self.y[0]) / self.dy, (x - self.x[0]) / self.dx])
        return ndimage.map_coordinates(
            self.height,
            coords.reshape(2, -1),
            order=MAP_ORDER,
            mode="nearest" if period is None else "grid-wrap",
        ).reshape(np.shape(x))


def _real_array(value, name: str, source: str) -> np.ndarray:
    """``value`` as a float array, or a :class:`SurfaceError` naming ``name`` (and ``source``).

    Real numbers only: integers and floats (numpy's or Python's); strings, booleans, complex
    numbers, dates, ragged nested lists (rows of unequal lengths) and numbers beyond the float
    range are refused, never converted.
    """
    try:
        array = np.asarray(value)
    except (ValueError, TypeError):  # ragged nested lists (numpy >= 1.24), odd objects
        raise SurfaceError(
            f"{source}: {name} must be a rectangular array of numbers, got rows of unequal "
            "length (a ragged nested list) or values numpy cannot read as an array"
        ) from None
    kind = array.dtype.kind
    if kind == "O":  # a list mixing kinds, or Python ints beyond int64
        items = array.ravel().tolist()
        if any(isinstance(v, list | tuple | np.ndarray) for v in items):
            raise SurfaceError(
                f"{source}: {name} must be a rectangular array of numbers, got rows of unequal "
                "length (a ragged nested list)"
            )
        bad = next((v for v in items if isinstance(v, bool) or not _is_real(v)), None)
        if bad is not None:
            raise SurfaceError(f"{source}: {name} must hold real numbers (m), got {bad!r}")
        try:
            return np.asarray(items, dtype=float).reshape(array.shape)
        except OverflowError:
            raise SurfaceError(
                f"{source}: {name} holds integers beyond the float range; give metres"
            ) from None
    if kind not in "iuf":
        told = {"U": "text", "S": "bytes", "b": "booleans", "c": "complex numbers"}
        raise SurfaceError(
            f"{source}: {name} must hold real numbers (m), got {told.get(kind, 'values')} of "
            f"dtype {array.dtype}"
        )
    return array.astype(float, copy=False)


def _is_real(value) -> bool:
    """True for a real number (Python's or numpy's int, float, a Fraction, ...)."""
    return isinstance(value, numbers.Real)


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

    def lattice(self, side: float, periodic: bool = False) -> tuple[int, float]:
        """(points per side, spacing (m)) of the lattice that covers a domain of ``side`` (m).

        ``periodic``: the lattice is the period ``side`` itself, its spacing the largest at most
        ``short_cutoff`` / :data:`ROUGHNESS_POINTS_PER_CUTOFF` that divides it.
        """
        spacing = self.short_cutoff / ROUGHNESS_POINTS_PER_CUTOFF
        if periodic:
            points = math.ceil(side / spacing - 1e-9)
            return points, side / points
        length = self.long_cutoff
        while length < side * (1 - 1e-12):
            length *= 2.0
        return math.ceil(length / spacing - 1e-9), spacing

    def sample(
        self, x: np.ndarray, y: np.ndarray, period: tuple[float, float] | None = None
    ) -> np.ndarray:
        """Heights (m) at points ``x``, ``y`` (m): the lattice realisation, cubic-interpolated.

        ``period`` (m, a square one): the realisation on the period's own lattice
        (:meth:`lattice`), periodic in x and y, wrapping around.
        """
        if period is None:
            side = 2.0 * float(max(np.abs(x).max(), np.abs(y).max())) + 1e-300
            points, spacing = self.lattice(side)
        else:
            if not math.isclose(period[0], period[1], rel_tol=PERIOD_RTOL):
                raise ValueError(f"a roughness has a square period, not {period} m")
            points, spacing = self.lattice(period[0], periodic=True)
        heights = _roughness_lattice(self, points, spacing)
        coordinate = (np.arange(points) - 0.5 * (points - 1)) * spacing
        surface = HeightMap(coordinate, coordinate, heights, "roughness")
        return surface.sample(x, y, None if period is None else surface.period)

    def slope_bound(self) -> float:
        """An upper bound of the realisation's rms slope (dimensionless), known without it.

        ``rms_slope`` when given; else ``rms x 2 pi / short_cutoff``: the spectrum holds no
        wavenumber above ``2 pi / short_cutoff``, and the rms slope over the rms height is a
        mean of the wavenumbers (weighted by the power), so it cannot exceed the largest.
        """
        if self.rms_slope is not None:
            return self.rms_slope
        return self.rms * 2.0 * math.pi / self.short_cutoff

    def realised_rms_slope(self, side: float, periodic: bool = False) -> float:
        """Rms slope (dimensionless) of the realisation that covers a domain of ``side`` (m).

        The slope measure ``rms_slope`` is given in: spectral on the realisation's lattice
        (:meth:`lattice`), sqrt(sum |q|^2 |H(q)|^2) / points^2 with H the heights' discrete
        Fourier transform; ``rms_slope`` itself when given (the realisation is scaled to it).
        """
        if self.rms_slope is not None:
            return self.rms_slope
        points, spacing = self.lattice(side, periodic)
        heights = _roughness_lattice(self, points, spacing)
        q = 2.0 * math.pi * np.fft.fftfreq(points, spacing)
        power = np.abs(np.fft.fft2(heights)) ** 2
        slope2 = np.sum(power * (q[:, None] ** 2 + q[None, :] ** 2)) / float(points) ** 4
        return math.sqrt(float(slope2))


def grid_rms_slope(
    surface, x: np.ndarray, y: np.ndarray, period: tuple[float, float] | None = None
) -> float:
    """Rms slope (dimensionless) of a surface's heights resampled at cell centres.

    Parameters
    ----------
    surface : HeightMap or Roughness
        Anything with ``sample(x, y)`` (heights in m).
    x, y : numpy.ndarray
        Cell-centre coordinates (m), 1-D, uniform: the solver's grid (each at least 2 points).
    period : tuple of float or None
        The period (m) of a periodic grid: the surface sampled as one period.

    Returns
    -------
    float
        sqrt(<(dh/dx)^2> + <(dh/dy)^2>), each derivative a forward difference between
        neighbouring cells, each mean over its own differences: the slope the solver sees.
        Resampled :data:`SLOPE_CHUNK_POINTS` points at a time.
    """
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    dx, dy = x[1] - x[0], y[1] - y[0]
    columns = max(2, SLOPE_CHUNK_POINTS // y.size)
    sum_x = sum_y = 0.0
    last = None  # the previous chunk's last column: the difference across chunks
    for start in range(0, x.size, columns):
        xx, yy = np.meshgrid(x[start : start + columns], y, indexing="ij")
        heights = surface.sample(xx, yy, period)  # (x, y)
        sum_y += float(np.sum(np.diff(heights, axis=1) ** 2))
        if last is not None:
            heights = np.concatenate([last, heights], axis=0)
        sum_x += float(np.sum(np.diff(heights, axis=0) ** 2))
        last = heights[-1:]
    mean_x = sum_x / ((x.size - 1) * y.size) / dx**2
    mean_y = sum_y / (x.size * (y.size - 1)) / dy**2
    return math.sqrt(mean_x + mean_y)


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


def ring_wavenumbers(shape: tuple[int, int], period: tuple[float, float]) -> np.ndarray:
    """The wavenumbers (1/m) of :func:`isotropic_spectrum`'s rings on a period of ``shape`` cells.

    ``k dq`` for k = 1, 2, ... up to the Nyquist wavenumber ``pi / dx`` of the coarser axis,
    ``dq = 2 pi / max(period)``.
    """
    step = 2.0 * math.pi / max(period)
    spacing = max(length / cells for length, cells in zip(period, shape, strict=True))
    return step * np.arange(1, int(math.floor(math.pi / spacing / step + 1e-9)) + 1)


def isotropic_spectrum(heights: np.ndarray, period: tuple[float, float]) -> np.ndarray:
    """The isotropic power spectral density of one period of heights, averaged over rings.

    ``C(q)`` is the mean of ``|H(q)|^2 A / N^2`` over the wavevectors of a ring, ``H`` the
    heights' discrete Fourier transform, ``A`` the period's area, ``N`` its cells: the
    convention under which the mean square height about the mean is ``(2 pi)^-2 sum_q C(q)
    dq_x dq_y`` over the wavevectors (Parseval), about ``(2 pi)^-1 integral q C(q) dq``
    (Jacobs, Junge and Pastewka, Surf. Topogr. Metrol. Prop. 5 (2017) 013001).  Ring ``k``
    holds the wavevectors of length within half a step of ``k dq`` (:func:`ring_wavenumbers`).

    Parameters
    ----------
    heights : numpy.ndarray
        Heights (m) at the cell centres of one period, shape (nx, ny).
    period : tuple of float
        The period (m) along x and y.

    Returns
    -------
    numpy.ndarray
        ``C(q)`` (m^4) on the rings of :func:`ring_wavenumbers`.
    """
    heights = np.asarray(heights, dtype=float)
    (nx, ny), (lx, ly) = heights.shape, period
    rings = ring_wavenumbers(heights.shape, period)
    qx = 2.0 * math.pi * np.fft.fftfreq(nx, lx / nx)
    qy = 2.0 * math.pi * np.fft.fftfreq(ny, ly / ny)
    ring = np.rint(np.hypot(qx[:, None], qy[None, :]) / rings[0]).astype(int)
    power = np.abs(np.fft.fft2(heights)) ** 2 * (lx * ly) / heights.size**2
    inside = (ring >= 1) & (ring <= rings.size)
    total = np.bincount(ring[inside], power[inside], rings.size + 1)[1:]
    count = np.bincount(ring[inside], minlength=rings.size + 1)[1:]
    return total / np.maximum(count, 1)
