r"""The FFT convolution of the eigenstrain operator: per-layer 2-D transforms, then depth.

:class:`~solver.volume.eigenstrain.EigenstrainOperator` evaluates Chiu's source and image
cuboids as one 3-D convolution, symmetric in z.  Source plus image is a column of ``2 nz``
cells even in z (xx, yy, zz, xy) or odd (yz, xz) about the surface, and every cuboid kernel is
even or odd in its z offset, so the z direction is a symmetric convolution (Martucci 1994) of
period ``2M`` with ``M >= 2 nz`` (no wrap-around reaches an offset the layers have; M even,
:func:`depth_length`): the column goes through a DCT-II (even) or DST-II (odd) of length M,
the kernel's offsets ``0 .. M`` through a DCT-I or DST-I, their product through a DCT-III or
DST-III back, all real.  The data's DCTs and DSTs are real FFTs of length M of the reordered
column (Makhoul 1980), both planes (real and imaginary parts) in one call: FFTW's own
real-to-real transforms of these lengths were 1.7 to 3.8 times slower.
The data first go through per-layer 2-D transforms of the box zero-padded to ``(2nx, 2ny)``
(the layer spectra the surface terms use as well), then the z transforms; each kernel is even
or odd in x and y too, so its spectrum is real up to a power of i: stored real, for ``kx <=
nx``, ``ky <= ny`` (the mirrored kx by parity), ``(nx + 1, ny + 1, M + 1)``
(:mod:`solver.volume.eigenstrain_kernels`), and multiplied with the real and imaginary planes
of the inputs apart.  Per output component: 5 (trace-free) or 6 real multiply-adds per
frequency and plane; the spectrum has ``2nx (ny + 1) (M + 1)`` frequencies.
The convolution runs by blocks of kx rows: each block's inputs are transformed in z,
multiplied and transformed back while they are in cache, and its outputs replace its inputs.
"""

from __future__ import annotations

import functools
import itertools
from dataclasses import dataclass

import numpy as np

from ..numerics.fftw import empty_aligned, plan
from ..numerics.grid import fft_size
from ..numerics.threads import each
from .eigenstrain_kernels import component_name, parity3, rotation


def depth_length(nz: int) -> int:
    """M, the half period of the symmetric depth convolution of ``nz`` layers.

    The smallest even fast FFT length (:func:`~solver.numerics.grid.fft_size`) of at least ``2 nz``:
    even for the real FFTs of length M that carry the z transforms (Makhoul 1980).
    """
    return 2 * fft_size(nz)


#: Slot of each output component in the per-layer spectra it replaces (the mean stress takes
#: zz's, which a trace-free route does not transform).
SLOT = {0: 0, 1: 1, 2: 2, 3: 3, 4: 4, 5: 5, "mean": 2}

#: Pieces of layers each component's per-layer 2-D transforms are cut into
#: (:meth:`EigenstrainConvolution._each_component`): the five deviatoric components in ten pieces
#: share evenly between two threads.
LAYER_PIECES = 2

#: Bytes per plane of a row block of the depth convolution
#: (:meth:`EigenstrainConvolution._workers`).
CHUNK_BYTES = 2**18


@dataclass
class _Worker:
    """One worker of the depth convolution: its row blocks, z plans (by rows) and buffers.

    ``plans[rows]``: the real FFTs of length M along z, ``"rfft"`` from the reordered input
    columns (zero after the box's layers) into a half spectrum, ``"irfft"`` from it into the
    reordered output columns (columns ``(2, rows, ny + 1, M)`` real, planes real and
    imaginary; the spectrum ``(2, rows, ny + 1, M/2 + 1)`` complex, shared);
    ``twiddle_forward``, ``twiddle_backward`` the turns of the spectra ``2 exp(-i pi k /
    2M)``, ``exp(i pi k / 2M)`` (:meth:`EigenstrainConvolution._forward_z`); ``inputs`` ``(6,
    2, rows, ny + 1, M + 1)``: the turned z transforms of each component, planes real and
    imaginary; ``acc`` and ``work`` ``(2, rows, ny + 1, M + 1)``; ``surface`` ``(rows, ny +
    1, nz)`` complex: the traction terms.
    """

    blocks: list
    plans: dict
    twiddle_forward: np.ndarray
    twiddle_backward: np.ndarray
    inputs: np.ndarray
    acc: np.ndarray
    work: np.ndarray
    surface: np.ndarray


def _accumulate(
    acc: np.ndarray,
    work: np.ndarray,
    products: list,
    inputs: np.ndarray,
    rows: int,
    kxs: slice,
    mirrored: bool,
) -> None:
    """``acc = sum (+-) kernel * input`` over one block's rows, both planes.

    ``products`` are ``(kernel, component, negative, px)``: a real kernel (broadcast over
    the real and imaginary planes), the input component (its turned transform in
    ``inputs``, one slot per component), the sign of the z rule and the kernel's parity
    in x, which gives its sign in the mirrored rows.
    """
    for n, (kernel, b, negative, px) in enumerate(products):
        values = inputs[b, :, :rows]
        minus = bool(negative) != bool(px and mirrored)
        if n == 0:
            np.multiply(kernel[kxs], values, out=acc)
            if minus:
                np.negative(acc, out=acc)
        else:
            np.multiply(kernel[kxs], values, out=work)
            (np.subtract if minus else np.add)(acc, work, out=acc)


class EigenstrainConvolution:
    """The per-layer 2-D transforms and the depth convolution by row blocks on worker threads.

    A base class of :class:`~solver.volume.eigenstrain.EigenstrainOperator`: its methods read
    the operator's plastic box (``shape``), depth length M (``length_z``), threads, FFT planner
    and real and complex types (the attributes below), and keep the plans and buffers, made on
    first use, in its caches (``None`` until made).
    """

    shape: tuple[int, int, int]
    lengths: tuple[int, int]
    halves: tuple[int, int]
    length_z: int
    threads: int
    planner: str
    _real: str
    _complex: str
    _volume: list | None
    _work: list | None

    def _layer_pieces(self) -> list[slice]:
        """The box's layers cut into :data:`LAYER_PIECES` runs (the 2-D transforms' pieces)."""
        bounds = np.linspace(0, self.shape[2], LAYER_PIECES + 1).round().astype(int)
        return [slice(a, b) for a, b in itertools.pairwise(bounds) if b > a]

    def _volume_plans(self) -> list[dict]:
        """FFT plans and buffers of the per-layer 2-D transforms of the box, one set per thread.

        Each set maps a piece's layer count ``h`` (:meth:`_layer_pieces`) to its plans:
        ``"data"`` ``(Lx, Ly/2 + 1, h)`` complex holds per-layer 2-D spectra of the box: the
        forward transform of the data rows (``"y"`` on the box's ``nx`` rows of ``"rows"``,
        then ``"x"``) writes there; on the way back ``"-x"``, ``"-y"`` bring a stress
        component's spectra back to the box's cells in ``"rows"`` ``(nx, Ly, h)`` (``Lx, Ly``
        the lateral FFT lengths: twice the box's cells, or the period's own).  The
        depth convolution between them runs by row blocks (:meth:`_workers`).  With several
        threads each set (single-threaded plans: the same plans as one thread's) transforms
        its share of the pieces (:meth:`_each_component`).
        """
        if self._volume is None:
            nx = self.shape[0]
            lx, ly = self.lengths
            make = functools.partial(plan, planner=self.planner, threads=1)
            depths = sorted({zs.stop - zs.start for zs in self._layer_pieces()})
            self._volume = []
            for _ in range(max(1, self.threads)):
                sets = {}
                for h in depths:
                    data = empty_aligned((lx, ly // 2 + 1, h), dtype=self._complex)
                    rows = empty_aligned((nx, ly, h), dtype=self._real)
                    sets[h] = {
                        "data": data,
                        "rows": rows,
                        "y": make(rows, data[:nx], axes=(1,)),
                        "x": make(data, data, axes=(0,)),
                        "-x": make(data, data, axes=(0,), direction="FFTW_BACKWARD"),
                        "-y": make(
                            data[:nx],
                            rows,
                            axes=(1,),
                            direction="FFTW_BACKWARD",
                            extra=("FFTW_DESTROY_INPUT",),
                        ),
                    }
                    data[...] = 0.0
                    rows[...] = 0.0
                self._volume.append(sets)
        return self._volume

    def _each_component(self, components, job) -> None:
        """``job(component, layers, plans)`` for every component and piece of layers.

        The pieces (each component's :meth:`_layer_pieces`, ``layers`` a slice of them) are
        dealt to the plan sets of :meth:`_volume_plans` (one thread each; ``plans`` those of
        the piece's layer count): five components in ten pieces share evenly between two
        threads.  One thread transforms the same pieces with the same plans, so which set
        transforms a piece changes no bit.
        """
        sets = self._volume_plans()
        pieces = [(c, zs) for c in components for zs in self._layer_pieces()]

        def share(w: int) -> None:
            for component, zs in pieces[w :: len(sets)]:
                job(component, zs, sets[w][zs.stop - zs.start])

        each(share, range(min(len(sets), len(pieces))), len(sets))

    def _forward_layers(self, eigenstrain: np.ndarray, components, out: np.ndarray) -> None:
        """``out[c]``: the per-layer 2-D spectra of the box's ``eigenstrain[c]`` (zero-padded)."""
        nx, ny, _ = self.shape

        def job(c, zs: slice, plans: dict) -> None:
            rows, data = plans["rows"], plans["data"]
            rows[:, ny:] = 0.0  # the last inverse transform left its output
            rows[:, :ny] = eigenstrain[c, ..., zs]
            plans["y"].execute()
            data[nx:] = 0.0
            plans["x"].execute()
            out[c, ..., zs] = data

        self._each_component(components, job)

    def _convolve(
        self, spectral: np.ndarray, components, terms: dict, surface: dict, worker: _Worker
    ) -> None:
        """The depth convolution of a worker's row blocks, in place in ``spectral``.

        Per block: the DCT-II/DST-II of every input component's real and imaginary parts
        (turned by ``i^r``, :meth:`_forward_z`), then per output component the products with
        the real kernels (:func:`_accumulate`), the DCT-III/DST-III back (:meth:`_backward_z`),
        the traction stresses' terms (``surface``), into the output's slot of ``spectral``
        (:data:`SLOT`).  The same operations in the same order per element whatever the
        blocks and threads: results do not depend on the number of threads.
        """
        for xs, kxs, mirrored in worker.blocks:
            r = xs.stop - xs.start
            transforms = worker.plans[r]
            for b in components:
                self._forward_z(b, spectral[b, xs], worker, transforms, worker.inputs[b, :, :r])
            for a, products in terms.items():
                acc = worker.acc[:, :r]
                _accumulate(acc, worker.work[:, :r], products, worker.inputs, r, kxs, mirrored)
                target = spectral[SLOT[a], xs]
                self._backward_z(a, acc, worker, transforms, target)
                for kernel, factor in surface.get(a, ()):
                    work = worker.surface[:r]
                    np.multiply(kernel[xs], factor[xs], out=work)
                    target += work

    def _forward_z(
        self, component, layers: np.ndarray, worker: _Worker, transforms: dict, target: np.ndarray
    ) -> None:
        """The z transform of a block's per-layer spectra ``layers``, turned by ``i^r``: an input.

        A DCT-II (component even in z: source and image add up to an even column) or DST-II
        (odd) of length M of the real and of the imaginary part, into ``target`` ``(2, rows,
        ny + 1, M + 1)``, planes real and imaginary; a component with rotation 1
        (:func:`rotation`) is multiplied by i, ``(re, im) -> (-im, re)``.  The z slot the
        transform does not write (M for even components, 0 for odd) stays zero.

        Both planes at once through one real FFT of length M (Makhoul 1980): the column
        reordered (even layers, then the odd ones backwards; a DST-II is the DCT-II of the
        column with its odd layers negated, read backwards), transformed, and turned by
        ``2 exp(-i pi k / 2M)``: ``Y_k = Re T_k``, ``Y_(M-k) = -Im T_k``.  Only the box's
        layers are written into the reordered column (the zero padding stays zero).
        """
        m = self.length_z
        half = m // 2
        odd = parity3(component_name(component))[2]
        turned = rotation(component)
        transform = transforms["rfft"]
        column, spectrum = transform.input_array, transform.output_array
        for plane, part in ((turned, layers.real), (1 - turned, layers.imag)):
            sign = -1.0 if (turned and plane == 0) else 1.0
            evens, odds = self._reordered(column[plane])
            np.multiply(part[..., 0::2], sign, out=evens)
            np.multiply(part[..., 1::2], -sign if odd else sign, out=odds)
        transform.execute()
        np.multiply(spectrum, worker.twiddle_forward, out=spectrum)
        if odd:  # slots 1 .. M hold Y_(M-1), ..., Y_0
            np.negative(spectrum.imag[..., 1:half], out=target[..., 1:half])
            target[..., half:] = spectrum.real[..., half::-1]
        else:  # slots 0 .. M-1 hold Y_0, ..., Y_(M-1)
            target[..., : half + 1] = spectrum.real
            np.negative(spectrum.imag[..., half - 1 : 0 : -1], out=target[..., half + 1 : m])

    def _backward_z(
        self, component, acc: np.ndarray, worker: _Worker, transforms: dict, target: np.ndarray
    ) -> None:
        """Inverse z transform of a block's accumulator into its layers ``target``, turned by i^r.

        DCT-III (output even in z) or DST-III (odd) of length M of each plane, the first
        ``nz`` values (the box's layers); a component with rotation 1 is multiplied by i on
        the way: ``(A0, A1) -> (-A1, A0)``.  Through one inverse real FFT of length M
        (Makhoul 1980): the half spectrum ``exp(i pi k / 2M) (X_k - i X_(M-k))`` (``X_M =
        0``; a DST-III is the DCT-III of the reversed input, its odd outputs negated), whose
        inverse is the output reordered (even layers, then the odd ones backwards).
        """
        m = self.length_z
        half = m // 2
        odd = parity3(component_name(component))[2]
        turned = rotation(component)
        transform = transforms["irfft"]
        spectrum, column = transform.input_array, transform.output_array
        if odd:  # X_k = acc[M - k]
            spectrum.real[...] = acc[..., m : half - 1 : -1]
            np.negative(acc[..., 1 : half + 1], out=spectrum.imag[..., 1:])
        else:
            spectrum.real[...] = acc[..., : half + 1]
            np.negative(acc[..., m - 1 : half - 1 : -1], out=spectrum.imag[..., 1:])
        spectrum.imag[..., 0] = 0.0
        np.multiply(spectrum, worker.twiddle_backward, out=spectrum)
        transform.execute()
        planes = (target.imag, target.real) if turned else (target.real, target.imag)
        for plane, part in enumerate(planes):
            sign = -1.0 if (turned and plane == 1) else 1.0
            evens, odds = self._reordered(column[plane])
            np.multiply(evens, sign, out=part[..., 0::2])
            np.multiply(odds, -sign if odd else sign, out=part[..., 1::2])

    def _reordered(self, column: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Where a reordered column (last axis, length M) holds the box's layers (views).

        Makhoul's order: the even layers 0, 2, 4, ... first, the odd ones 1, 3, 5, ... from the
        end backwards (slots M - 1, M - 2, ...); the slots between stay the zero padding.
        """
        m, nz = self.length_z, self.shape[2]
        return column[..., : (nz + 1) // 2], column[..., m - 1 : m - 1 - nz // 2 : -1]

    def _workers(self) -> list[_Worker]:
        """Row blocks of the spectrum dealt to :attr:`threads` workers, with their buffers.

        Each block is ``(rows, kernel_rows, mirrored)``: spectrum rows ``kx`` and the rows of the
        stored kernel that hold them (``Lx - kx`` for the mirrored half above ``Lx/2``).  Blocks
        of about
        :data:`CHUNK_BYTES` of spectrum per plane keep a block's z transforms, products and
        accumulator in cache; every worker has its own buffers and z plans (one thread each:
        the workers are the parallelism), made here, before any thread runs.
        """
        if self._work is None:
            (lx, _), (hx, hy) = self.lengths, self.halves
            m = self.length_z
            row = (hy + 1) * (m + 1) * np.dtype(self._real).itemsize
            size = max(1, min(hx, CHUNK_BYTES // row))
            blocks = []
            for start in range(0, hx + 1, size):
                stop = min(hx + 1, start + size)
                blocks.append((slice(start, stop), slice(start, stop), False))
            for start in range(hx + 1, lx, size):
                stop = min(lx, start + size)
                # rows kx in [start, stop) hold kernel rows Lx - kx, from Lx - start down
                blocks.append((slice(start, stop), slice(lx - start, lx - stop, -1), True))
            count = max(1, min(self.threads, len(blocks)))
            self._work = [self._worker(blocks[w::count], size) for w in range(count)]
        return self._work

    def _worker(self, blocks: list, size: int) -> _Worker:
        """A worker's buffers and z plans for blocks of at most ``size`` rows."""
        nz, ky = self.shape[2], self.halves[1] + 1  # the y frequencies
        m = self.length_z
        half = m // 2
        empty = functools.partial(empty_aligned, dtype=self._real)
        padded = empty((2, size, ky, m))  # reordered input columns, zero past the layers
        column = empty((2, size, ky, m))  # reordered output columns
        spectrum = empty_aligned((2, size, ky, half + 1), dtype=self._complex)
        inputs = empty((6, 2, size, ky, m + 1))
        acc = empty((2, size, ky, m + 1))
        make = functools.partial(plan, planner=self.planner, threads=1, axes=(3,))
        plans = {}
        for r in sorted({xs.stop - xs.start for xs, _, _ in blocks}):
            plans[r] = {
                "rfft": make(padded[:, :r], spectrum[:, :r]),
                "irfft": make(
                    spectrum[:, :r],
                    column[:, :r],
                    direction="FFTW_BACKWARD",
                    extra=("FFTW_DESTROY_INPUT",),
                ),
            }
        padded[...] = 0.0
        inputs[...] = 0.0
        k = np.arange(half + 1)
        twiddles = (
            (2.0 * np.exp(-0.5j * np.pi * k / m)).astype(self._complex),
            np.exp(0.5j * np.pi * k / m).astype(self._complex),
        )
        surface = np.empty((size, ky, nz), dtype=complex)
        return _Worker(blocks, plans, *twiddles, inputs, acc, empty(acc.shape), surface)
