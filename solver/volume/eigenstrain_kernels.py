r"""Kernel spectra of the eigenstrain operator: Chiu's source and image cuboids.

What :class:`~solver.volume.eigenstrain.EigenstrainOperator` convolves the eigenstrain with
(:mod:`solver.volume.eigenstrain_convolution` multiplies them), built from the closed forms of
a uniform eigenstrain in a cuboid (:mod:`solver.volume.cuboid`) and normalised (the factor
``1/size`` of the inverse FFTs folded in):

* the 3-D stress kernels of source plus image (:class:`EigenstrainKernels`): every cuboid
  kernel is even or odd in x, y and z (:func:`parity3`), so its z offsets ``0 .. M`` go
  through a DCT-I (even) or DST-I (odd) and its x and y offsets through DCT-Is or DST-Is, whose
  spectrum is real up to a power of i: stored real, for ``kx <= nx``, ``ky <= ny`` (the
  mirrored kx by parity), ``(nx + 1, ny + 1, M + 1)``.  The 21 general kernels (``w_ij
  D_ij,mn`` is symmetric) or the 20 of a trace-free eigenstrain (15 of a symmetric 5 x 5
  deviatoric operator and 5 of the mean stress) are kept;
* the per-layer 2-D kernels of the surface fields of source plus image: the normal stress
  ``S_zz`` the Boussinesq correction cancels and, for the direct displacement route, the
  source's surface displacements and the Boussinesq displacement of a pressure on one cell.

The corner functions are summed over a lattice of corner coordinates
(:func:`_lattice_corner_sums`), the base functions that share a transcendental together
(:func:`_base_groups`).
"""

from __future__ import annotations

import functools
import itertools
import math
import threading

import numpy as np

from ..numerics.fftw import empty_aligned, plan
from ..numerics.grid import VolumeGrid
from ..numerics.images import far_images, fold_nonnegative, image_reach, signed
from ..numerics.tensor import WEIGHTS
from ..numerics.threads import each
from ..surface.influence import cell_integral
from ..theory.half_space import uniform_layer_stress
from .cuboid import (
    DISPLACEMENT_BASE,
    STRESS_BASE,
    corner_functions,
    displacement_coefficients,
    stress_coefficients,
)
from .stress import STRESS_COMPONENTS, SubsurfaceStressOperator, wrap_layout

#: Tensor weights of the six components in ``sigma : e`` (off-diagonal terms count twice).
COMPONENT_WEIGHTS = WEIGHTS
#: The five independent components of a deviatoric tensor (zz = -(xx + yy)).
DEVIATORIC = (0, 1, 3, 4, 5)


def _parity(indices: str) -> tuple[int, int]:
    return indices.count("x") % 2, indices.count("y") % 2


def _is_imaginary(indices: str) -> bool:
    px, py = _parity(indices)
    return bool((px + py) % 2)


def parity3(indices: str) -> tuple[int, int, int]:
    """Parity (0 even, 1 odd) in x, y and z of a kernel or field with these tensor indices."""
    return indices.count("x") % 2, indices.count("y") % 2, indices.count("z") % 2


def component_name(component) -> str:
    """Index letters of a stress component (an index, or ``"mean"``: a normal one)."""
    return "xx" if component == "mean" else STRESS_COMPONENTS[component]


def rotation(component) -> int:
    """1 when a component's x-y transform carries a factor i (odd in exactly one of x, y)."""
    px, py, _ = parity3(component_name(component))
    return (px + py) % 2


def _rotation_sign(a, b, parity_xy: tuple[int, int]) -> float:
    """``(-i)^(px + py) / i^(r_a + r_b)``: +-1, the sign of a stored real kernel spectrum.

    A kernel of x-y parity ``(px, py)`` has the 2-D transform ``(-i)^(px + py) R``;
    stored is ``K / i^(r_a + r_b)``, so that inputs turned by ``i^r_b`` and outputs by
    ``i^r_a`` (:meth:`~solver.volume.eigenstrain.EigenstrainOperator._stress`) see real
    kernels only.
    """
    value = (-1j) ** sum(parity_xy) / 1j ** (rotation(a) + rotation(b))
    if abs(value.imag) > 1e-12:
        raise AssertionError("kernel parity and component rotations disagree")  # pragma: no cover
    return value.real


def _lattice_corner_sums(
    cx, cy, cz, names, chunk: int = 16, threads: int = 1, period: tuple | None = None
) -> dict:
    """Corner sums of the cuboid corner functions over a lattice of corner coordinates.

    ``cx``, ``cy``, ``cz`` are increasing 1-D corner coordinates ``x - x'_corner``.  Entry
    ``(i, j, k)`` of each result, shape ``(len(cx) - 1, len(cy) - 1, len(cz) - 1)``, is the
    alternating sum over the corners ``(cx[i:i+2], cy[j:j+2], cz[k:k+2])``: the field of a
    cuboid of one lattice cell at the offset of that cell's centre.  Computed in slabs of
    ``chunk`` x-rows to bound the temporaries, shared by ``threads`` threads.

    ``period = (nx, ny)``: the lattice covers the offsets ``0 .. image_reach(n)`` in x and y
    (the negative ones follow by each function's parity), and each slab is folded over the
    periodic images as it comes (:func:`~solver.numerics.images.fold_nonnegative`): the results
    are the periodised kernels at the offsets ``0 .. n - 1``, shape ``(nx, ny, len(cz) - 1)``,
    with what the images beyond the reach add but their mean
    (:func:`~solver.numerics.images.far_images`, from the lattice's outermost rows and columns).
    """
    rows, columns, depths = len(cx) - 1, len(cy) - 1, len(cz) - 1
    shape = (rows, columns, depths) if period is None else (period[0], period[1], depths)
    out = {name: np.zeros(shape) for name in names}
    # a periodic kernel's three outermost rows and columns (for the far images' terms)
    edge_x = {name: np.empty((3, columns, depths)) for name in names}
    edge_y = {name: np.empty((rows, 3, depths)) for name in names}
    lock = threading.Lock()

    def slab(i0: int) -> None:
        i1 = min(rows, i0 + chunk)
        f = corner_functions(
            cx[i0 : i1 + 1, None, None], cy[None, :, None], cz[None, None, :], names
        )
        for name in names:
            v = np.diff(np.diff(np.diff(f[name], axis=0), axis=1), axis=2)
            if period is None:
                out[name][i0:i1] = v
                continue
            edge_y[name][i0:i1] = v[:, -3:]
            last = np.arange(i0, i1) - (rows - 3)
            edge_x[name][last[last >= 0]] = v[last >= 0]
            odd_x, odd_y, _ = parity3(name[1:])
            v = fold_nonnegative(v, period[1], bool(odd_y), axis=1)
            with lock:
                fold_nonnegative(v, period[0], bool(odd_x), 0, start=i0, out=out[name])

    each(slab, range(0, rows, chunk), threads)
    if period is not None:  # the images beyond the reach, but their mean
        for name in names:
            odd_x, odd_y, _ = parity3(name[1:])
            edges = {
                "x": signed(edge_x[name], bool(odd_y), axis=1),
                "y": signed(np.swapaxes(edge_y[name], 0, 1), bool(odd_x), axis=1),
            }
            out[name] += far_images(edges, (odd_x, odd_y), *period)
    return out


def _base_groups(names) -> list[list[str]]:
    """Group base functions that share a transcendental (one asinh or atan) to evaluate once."""
    groups: dict[str, list[str]] = {}
    for name in names:
        letters = name[1:]
        counts = {a: letters.count(a) for a in "xyz"}
        if name[0] == "d" and len(letters) == 2:
            key = (
                ("t" + letters[0])
                if letters[0] == letters[1]
                else "a" + (set("xyz") - set(letters)).pop()
            )
        elif sorted(counts.values()) == [0, 1, 3]:
            key = "a" + next(a for a in "xyz" if counts[a] == 0)
        elif max(counts.values()) == 4:
            key = "t" + next(a for a in "xyz" if counts[a] == 4)
        else:
            key = "rational"
        groups.setdefault(key, []).append(name)
    return list(groups.values())


def kernel_plans(halves: tuple, length_z: int, planner: str, threads: int) -> tuple:
    """Buffers and plans of the kernel transforms (:meth:`EigenstrainKernels._build_spectra`).

    ``(lattice, along_z, spectrum, {parity in z: DCT-I or DST-I plan}, {(parity in x,
    parity in y): DCT-I / DST-I plan along x and y})``, every buffer ``(hx + 1, hy + 1, M +
    1)`` real: offsets (then frequencies) ``0 .. h`` of the kernels' even or odd halves,
    ``halves = (hx, hy)`` half the lateral FFT lengths (the box's cells, or half the period's).
    """
    nx, ny = halves
    m = length_z
    lattice, along_z, spectrum = (
        empty_aligned((nx + 1, ny + 1, m + 1), dtype="float64") for _ in range(3)
    )
    make = functools.partial(plan, planner=planner, threads=threads)
    z_plans = {
        0: make(lattice, along_z, axes=(2,), direction="FFTW_REDFT00"),
        1: make(lattice[..., 1:m], along_z[..., 1:m], axes=(2,), direction="FFTW_RODFT00"),
    }
    kinds = {0: (slice(None), "FFTW_REDFT00"), 1: (slice(1, None), "FFTW_RODFT00")}
    xy_plans = {}
    for px, py in itertools.product((0, 1), repeat=2):
        (sx, kx), (sy, ky) = kinds[px], kinds[py]
        sx = slice(sx.start, nx if px else None)
        sy = slice(sy.start, ny if py else None)
        xy_plans[px, py] = make(along_z[sx, sy], spectrum[sx, sy], axes=(0, 1), direction=[kx, ky])
    return lattice, along_z, spectrum, z_plans, xy_plans


def unit_stress_coefficients(shear_modulus: float, nu: float) -> np.ndarray:
    """``D[ij, mn]``: stress ij of a unit eigenstrain mn, over the base functions and more.

    Shape ``(6, 6, len(STRESS_BASE) + 2)``: the coefficients of the base functions, then the
    eigenstress inside the source cell, then the stress inside a laterally uniform layer of a
    periodic half-space (:func:`~solver.theory.half_space.uniform_layer_stress`: the mean mode
    of a periodic kernel, :meth:`EigenstrainKernels._build_spectra`).  Taken from the
    symmetric weighted form ``w_ij D_ij,mn`` (ij <= mn).
    """
    coef, inside = stress_coefficients(shear_modulus, nu)
    unit = np.empty((6, 6, len(STRESS_BASE) + 2))
    for ij, mn in itertools.product(range(6), repeat=2):
        lo, hi = min(ij, mn), max(ij, mn)
        ratio = COMPONENT_WEIGHTS[lo] / COMPONENT_WEIGHTS[ij]
        unit[ij, mn, :-2] = ratio * coef[lo, hi]
        unit[ij, mn, -2] = -ratio * inside[lo, hi]
    unit[..., -1] = uniform_layer_stress(2.0 * shear_modulus * (1.0 + nu), nu)
    return unit


class EigenstrainKernels:
    """The kernel spectra of the eigenstrain operator, built on first use.

    A base class of :class:`~solver.volume.eigenstrain.EigenstrainOperator`: its methods read
    the operator's grid, plastic box (``shape``), its lateral FFT lengths and their halves
    (``lengths``, ``halves``), elastic constants, threads, FFT planner,
    depth length M (``length_z``), real type and traction-to-stress operator (the attributes
    below), and keep the spectra in its caches (``None`` until built).
    """

    grid: VolumeGrid
    shape: tuple[int, int, int]
    lengths: tuple[int, int]
    halves: tuple[int, int]
    E: float
    nu: float
    shear_modulus: float
    threads: int
    planner: str
    length_z: int
    surface_stress: SubsurfaceStressOperator
    _real: str
    _stress_spectra: dict | None
    _deviatoric_spectra: dict | None
    _surface_kernels: dict | None

    def _build_spectra(self, combinations: dict) -> dict:
        """Real spectra of linear combinations of the cuboid kernels (normalised).

        ``combinations`` maps a key ``(a, b)`` (output and input component names; ``"mean"``
        counts as a normal component) to the coefficients of the
        :data:`~solver.volume.cuboid.STRESS_BASE` functions followed by the one of the eigenstress
        inside the source cell (a delta at offset 0: a flat spectrum).  Each kernel has a
        parity in x, y and z: its z offsets ``0 .. M`` go through a DCT-I (even) or DST-I
        (odd), then the x and y offsets through a 2-D FFT, whose value is ``i^(r_a + r_b)``
        times a real array (``r`` the x-y rotation of a component, :func:`rotation`): that
        array is stored, for ``kx <= hx``, ``ky <= hy`` (half the lateral FFT lengths) and the
        ``M + 1`` z frequencies, shape ``(hx + 1, hy + 1, M + 1)``.  Each base function is
        transformed once and added to every combination that uses it; nothing else is kept.
        On a periodic grid the kernels are periodised (:func:`_lattice_corner_sums`) and their
        offsets ``0 .. n/2`` carry the whole period (the DCT-I's even extension of period n).
        """
        g = self.grid.surface
        nx, ny, nz = self.shape
        hx, hy = self.halves
        m = self.length_z
        lattice, along_z, spectrum, z_plans, xy_plans = kernel_plans(
            self.halves, self.length_z, self.planner, self.threads
        )
        scale = 1.0 / (2 * m * self.lengths[0] * self.lengths[1])
        shape = (hx + 1, hy + 1, m + 1)
        spectra = {key: np.empty(shape, dtype=self._real) for key in combinations}

        def start(key: tuple) -> None:
            inside = combinations[key][-2]  # nonzero only where a and b have one parity
            sign = _rotation_sign(*key, (0, 0)) if inside else 0.0
            spectra[key][...] = sign * inside * scale

        each(start, list(combinations), self.threads)
        # offsets 0 .. n - 1 in x and y: the negative ones follow by the kernel's parity; a
        # periodic grid's kernels are summed over the periodic images (offsets up to the reach)
        periodic = self.grid.periodic
        reach = (image_reach(nx), image_reach(ny)) if periodic else (nx - 1, ny - 1)
        cx = (np.arange(-1, reach[0] + 1) + 0.5) * g.dx
        cy = (np.arange(-1, reach[1] + 1) + 0.5) * g.dy
        cz = (np.arange(-1, m + 1) + 0.5) * self.grid.dz  # z offsets 0 .. M
        works = [np.empty(shape) for _ in range(max(1, self.threads))]
        lattice[hx] = 0.0
        lattice[:, hy] = 0.0  # padded: offset n, no pair of cells has it (periodic: set below)
        # a periodic kernel's sum over one period at each z offset (its mean mode), per key
        period_sums = {key: np.zeros(m + 1) for key in combinations}
        for group in _base_groups(STRESS_BASE):
            sums = _lattice_corner_sums(
                cx, cy, cz, group, threads=self.threads, period=(nx, ny) if periodic else None
            )
            for name in group:
                base = STRESS_BASE.index(name)
                px, py, pz = parity3(name[1:])
                values = sums.pop(name)
                if periodic:  # offsets 0 .. n/2 of the period's (the rest by parity)
                    lattice[...] = values[: hx + 1, : hy + 1]
                    if not (px or py):
                        base_sum = values.sum(axis=(0, 1))
                        for key, coefficients in combinations.items():
                            period_sums[key] += coefficients[base] * base_sum
                else:
                    lattice[:nx, :ny] = values
                along_z[..., 0] = along_z[..., m] = 0.0  # the DST-I leaves the ends
                z_plans[pz].execute()
                # the 2-D DFT (period 2n) of a kernel of parity (px, py) is (-i)^(px + py)
                # times its DCT-I (even) / DST-I (odd) along x and y: that real array is kept
                spectrum[...] = 0.0  # a DST-I leaves the frequencies 0 and n
                xy_plans[px, py].execute()
                terms = []  # (key, factor) of the combinations this base function enters
                for (a, b), coefficients in combinations.items():
                    c = coefficients[base]
                    if abs(c) <= 1e-14 * np.abs(coefficients[:-2]).max():
                        continue  # zero, or zero up to the round-off of a combination
                    if parity3(component_name(a) + component_name(b)) != (px, py, pz):
                        raise AssertionError("cuboid kernel of mixed parity")  # pragma: no cover
                    terms.append(((a, b), c * scale * _rotation_sign(a, b, (px, py))))

                def add(w: int, terms=terms) -> None:  # each combination on one thread
                    for key, factor in terms[w :: len(works)]:
                        np.multiply(spectrum, factor, out=works[w])
                        spectra[key] += works[w]

                each(add, range(len(works)), len(works))
        if periodic:
            self._exact_mean_modes(combinations, period_sums, spectra, scale)
        return spectra

    def _exact_mean_modes(
        self, combinations: dict, period_sums: dict, spectra: dict, scale: float
    ) -> None:
        """Give each periodic kernel the exact sum over one period (its mean mode).

        The images beyond :data:`~solver.numerics.images.IMAGES` periods add a nearly uniform
        part that the truncated sum misses; the exact sum is the stress of a laterally uniform
        layer (the last coefficient of a combination, :func:`unit_stress_coefficients`) at the
        z offset 0 and zero at every other (source or image) offset.  The difference, spread
        evenly over the period's offsets, is transformed like the kernels and added to the
        spectra of the even-even combinations (the odd ones sum to zero by parity).
        """
        nx, ny, _ = self.shape
        lattice, along_z, spectrum, z_plans, xy_plans = kernel_plans(
            self.halves, self.length_z, self.planner, self.threads
        )
        for key, coefficients in combinations.items():
            px, py, _ = parity3(component_name(key[0]) + component_name(key[1]))
            if px or py:
                continue
            target = -period_sums[key]
            target[0] += coefficients[-1] - coefficients[-2]  # the delta's own share
            lattice[...] = target / (nx * ny)  # uniform over the period
            z_plans[0].execute()
            spectrum[...] = 0.0
            xy_plans[0, 0].execute()
            spectra[key] += spectrum * (scale * _rotation_sign(*key, (0, 0)))

    def _stress_kernels(self) -> dict:
        """Spectra ``S[(ij, mn)] = w_ij D_ij,mn`` (symmetric), ij <= mn: any eigenstrain.

        Built on first use by :meth:`stress` of an eigenstrain with a trace; the plasticity
        loop's trace-free eigenstrains use :meth:`_deviatoric_kernels` only.
        """
        if self._stress_spectra is None:
            unit = unit_stress_coefficients(self.shear_modulus, self.nu)
            self._stress_spectra = self._build_spectra(
                {
                    (ij, mn): COMPONENT_WEIGHTS[ij] * unit[ij, mn]
                    for ij in range(6)
                    for mn in range(ij, 6)
                }
            )
        return self._stress_spectra

    def _deviatoric_kernels(self) -> dict:
        """Spectra for a trace-free eigenstrain: deviatoric stress and mean stress.

        Inputs are the five independent components :data:`DEVIATORIC` of a deviatoric tensor
        (``zz = -(xx + yy)``).  Outputs ``u_a = w_a t_a`` with ``t_xx = sigma_xx - sigma_zz``,
        ``t_yy = sigma_yy - sigma_zz`` and the shear stresses for the others (``w_a`` the
        tensor weight, 2 for shear): ``u_a = sum_b K[a, b] e_b`` has a symmetric matrix
        (``sigma : e`` is a symmetric bilinear form, and ``t`` with ``w`` are its components
        conjugate to the five ``e_b``), so the 15 kernels ``a <= b`` serve all 25 products; the
        deviator follows as ``s_xx = t_xx - (t_xx + t_yy)/3``, ``s_yy = t_yy - (t_xx + t_yy)/3``,
        ``s_zz = -(t_xx + t_yy)/3``.  ``K[("mean", b)]`` gives the mean stress ``tr(sigma)/3``,
        for the full stress.  Each combination keeps the parity of ``a + b`` (xx, yy and zz
        share theirs), so real spectra suffice.  25 products and 10 volume transforms per
        deviatoric evaluation instead of 36 and 12; 20 kernels kept instead of 21 + 25.
        """
        if self._deviatoric_spectra is None:
            unit = unit_stress_coefficients(self.shear_modulus, self.nu)
            # e_zz = -(e_xx + e_yy): a unit e_xx or e_yy comes with e_zz = -1
            unit_in = unit.copy()
            unit_in[:, :2] -= unit[:, 2:3]
            mean = unit_in[:3].mean(axis=0)
            combinations = {}
            for i, a in enumerate(DEVIATORIC):
                combinations["mean", a] = mean[a]
                t = unit_in[a] - unit_in[2] if a in (0, 1) else unit_in[a]
                for b in DEVIATORIC[i:]:
                    combinations[a, b] = COMPONENT_WEIGHTS[a] * t[b]
            self._deviatoric_spectra = self._build_spectra(combinations)
        return self._deviatoric_spectra

    def _surface_layer_kernels(self, displacement: bool = False) -> dict:
        """Per-layer 2-D spectra of the surface fields of source + image (normalised).

        ``"zz"``: ``S_zz = 2 sigma_zz^source(z = 0)`` per unit e_mn, shape
        ``(6, Lx, Ly/2 + 1, nz)`` (float, parity-typed), always built.  With ``displacement``
        also ``"x"``, ``"y"``: ``2 u_x``, ``2 u_y`` of the source at z = 0, and ``"bx"``,
        ``"by"``, ``"bz"``: the Boussinesq surface displacement per unit pressure on a cell
        (complex ``(2nx, ny + 1)``) - the kernels of the direct route.
        """
        kernels = self._surface_kernels if self._surface_kernels is not None else {}
        if "zz" in kernels and (not displacement or "x" in kernels):
            return kernels
        g = self.grid.surface
        nx, ny, nz = self.grid.shape
        gmod, nu = self.shear_modulus, self.nu
        periodic = self.grid.periodic
        if periodic and displacement:
            raise ValueError(
                "the direct displacement route is not built for a periodic grid: use the "
                "reciprocal route (method='reciprocal')"
            )
        if periodic:  # offsets 0 .. reach, folded over the images by parity
            cx = (np.arange(-1, image_reach(nx) + 1) + 0.5) * g.dx
            cy = (np.arange(-1, image_reach(ny) + 1) + 0.5) * g.dy
        else:
            cx = (np.arange(-nx, nx) + 0.5) * g.dx
            cy = (np.arange(-ny, ny) + 0.5) * g.dy
        cz = -np.arange(nz, -1, -1) * self.grid.dz  # -nz dz .. 0, increasing
        coef, inside = stress_coefficients(gmod, nu)
        ucoef = displacement_coefficients(gmod, nu)
        zz = STRESS_COMPONENTS.index("zz")
        forward, _ = self.surface_stress.batched_transforms(nz)
        lx, ly = self.surface_stress.lengths
        scale = 1.0 / (lx * ly)

        def lattice_sums(names: list[str]) -> dict:
            """Kernels at the signed offsets ``-(n-1) .. n-1`` (periodic: ``0 .. n-1``)."""
            period = (nx, ny) if periodic else None
            sums = _lattice_corner_sums(cx, cy, cz, names, threads=self.threads, period=period)
            # z offsets ascending: -(nz - 1/2) dz .. -dz/2, layers nz-1 .. 0: to layer order
            return {k: v[:, :, ::-1] for k, v in sums.items()}

        def spectrum_of(field: np.ndarray, indices: str) -> np.ndarray:
            if periodic:  # one period's offsets 0 .. n-1: the circular layout already
                forward.input_array[...] = field
            else:
                wrap_layout(field, (0, 1), forward.input_array)
            forward.execute()
            out = forward.output_array
            part = out.imag if _is_imaginary(indices) else out.real
            return part * scale

        if "zz" not in kernels:
            # S_zz of every component, one base function at a time (each transformed once and
            # added where it enters: the lattices of all of them are never held at once)
            field = kernels["zz"] = np.zeros((6, lx, ly // 2 + 1, nz), dtype=self._real)
            used = [n for n in STRESS_BASE if np.any(coef[zz, :, STRESS_BASE.index(n)] != 0.0)]
            period_sums = np.zeros((6, nz))  # of a periodic kernel over one period, per layer
            for group in _base_groups(used):
                sums = lattice_sums(group)
                for name in group:
                    b = STRESS_BASE.index(name)
                    values = sums.pop(name)
                    if periodic and not any(parity3(name[1:])[:2]):
                        period_sums += np.outer(2.0 * coef[zz, :, b], values.sum((0, 1)))
                    # its parity is that of S_zz of each component it enters
                    spectrum = spectrum_of(values, name[1:])
                    for mn in range(6):
                        if coef[zz, mn, b] != 0.0:
                            field[mn] += 2.0 * coef[zz, mn, b] * spectrum
            for mn, comp in enumerate(STRESS_COMPONENTS):
                # the field point z = 0+ lies inside the first layer's source cell: a delta at
                # offset 0 of layer 0, a flat (real) spectrum
                if inside[zz, mn] != 0.0:
                    assert not _is_imaginary("zz" + comp)
                    field[mn, :, :, 0] -= 2.0 * inside[zz, mn] * scale
                    period_sums[mn, 0] -= 2.0 * inside[zz, mn]
            if periodic:  # a uniform layer has no S_zz: each period sums to zero exactly
                flat = spectrum_of(np.ones((nx, ny, nz)), "xx")[..., :1]
                for mn in range(3):  # the even-even ones (the others sum to zero by parity)
                    field[mn] -= flat * (period_sums[mn] / (nx * ny))
        if displacement:
            sums = lattice_sums(list(DISPLACEMENT_BASE))
            for i, axis in enumerate("xy"):
                kernels[axis] = np.empty((6, 2 * nx, ny + 1, nz))
                for mn, comp in enumerate(STRESS_COMPONENTS):
                    field = 2.0 * sum(
                        ucoef[i, mn, b] * sums[n]
                        for b, n in enumerate(DISPLACEMENT_BASE)
                        if ucoef[i, mn, b] != 0.0
                    )
                    kernels[axis][mn] = spectrum_of(field, axis + comp)
            # Boussinesq surface displacement of a unit pressure on one cell (single body)
            ox, oy = g.offsets()
            b_z = (1.0 - nu * nu) / (math.pi * self.E) * cell_integral("inv_r", ox, oy, g.dx, g.dy)
            b_t = -(1.0 + nu) * (1.0 - 2.0 * nu) / (2.0 * math.pi * self.E)
            b_x = b_t * cell_integral("x_r2", ox, oy, g.dx, g.dy)
            b_y = b_t * cell_integral("y_r2", ox, oy, g.dx, g.dy)
            for key, field in (("bz", b_z), ("bx", b_x), ("by", b_y)):
                field = field.copy()
                field[nx, :] = 0.0
                field[:, ny] = 0.0
                kernels[key] = self.surface_stress.surface_spectrum(field) * scale
        forward.input_array[...] = 0.0
        self._surface_kernels = kernels
        return kernels
