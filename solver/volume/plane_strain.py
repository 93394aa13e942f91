"""Stresses inside a half-space in plane strain: a line contact's volume (``grid.periodic = "y"``).

A line contact's tractions do not change along y, so its stress field is the plane-strain one
of the tractions' profile along x: per layer a 1-D linear convolution of the profile with the
kernel of a uniformly loaded strip one cell wide (:func:`solver.theory.half_space.strip_stress`,
closed forms), by FFTs zero-padded to twice the cells.  Cost per evaluation
``O(nz nx log nx)``; the kernels' spectra are built once per grid and Poisson's ratio.  The
field is the same on every row along y and is returned on the grid's ``(nx, ny, nz)`` cells as
:class:`~solver.volume.stress.SubsurfaceStressOperator` returns its own.
"""

from __future__ import annotations

import numpy as np

from ..numerics.grid import IndexBox, VolumeGrid
from ..numerics.tensor import COMPONENTS
from ..theory.half_space import TRACTIONS, strip_stress


class PlaneStrainStressOperator:
    """Plane-strain stresses at the volume grid's cell centres (module docstring).

    Parameters
    ----------
    grid : VolumeGrid
        Surface cells (loads) and layers (field points); the tractions are uniform along y.
    nu : float
        Poisson's ratio of the half-space.
    """

    def __init__(self, grid: VolumeGrid, nu: float):
        self.grid = grid
        self.nu = float(nu)
        #: The FFT length along x: twice the cells (a linear convolution)
        self.length = 2 * grid.surface.nx
        self._spectra: dict[str, np.ndarray] = {}

    def kernel_spectra(self, traction: str) -> np.ndarray:
        """Spectra ``(6, length // 2 + 1, nz)`` of one traction's kernels (built on first use)."""
        if traction not in self._spectra:
            if traction not in TRACTIONS:
                raise ValueError(f"unknown traction {traction!r}; use one of {TRACTIONS}")
            surface, n = self.grid.surface, self.grid.surface.nx
            offsets = np.arange(-(n - 1), n) * surface.dx
            kernels = strip_stress(
                offsets[:, None], self.grid.z[None, :], 0.5 * surface.dx, self.nu, traction
            )
            wrapped = np.zeros((6, self.length, self.grid.nz))
            wrapped[:, :n] = kernels[:, n - 1 :]  # offsets 0 .. n-1
            wrapped[:, n + 1 :] = kernels[:, : n - 1]  # offsets -(n-1) .. -1
            self._spectra[traction] = np.fft.rfft(wrapped, axis=1)
        return self._spectra[traction]

    def stress(
        self,
        pressure: np.ndarray | None = None,
        shear_x: np.ndarray | None = None,
        shear_y: np.ndarray | None = None,
        box: IndexBox | None = None,
    ) -> np.ndarray:
        """Stresses at the cell centres from surface tractions uniform along y.

        Parameters
        ----------
        pressure, shear_x, shear_y : ndarray or None
            ``(nx, ny)`` tractions on the body (Pa): p (+z into the body), q_x, q_y; None for
            zero.  Their mean along y is the profile (a line contact's rows are equal).
        box : IndexBox or None
            Sub-box of cells where stresses are wanted (default: the whole grid).

        Returns
        -------
        ndarray
            ``(6,) + box.shape`` stresses (Pa), components
            :data:`~solver.numerics.tensor.COMPONENTS`.
        """
        fields = {"pressure": pressure, "shear_x": shear_x, "shear_y": shear_y}
        if all(v is None for v in fields.values()):
            raise ValueError("stress needs at least one of pressure, shear_x, shear_y")
        total = np.zeros((len(COMPONENTS), self.length // 2 + 1, self.grid.nz), complex)
        for traction, field in fields.items():
            if field is not None:
                profile = np.fft.rfft(np.asarray(field).mean(axis=1), n=self.length)
                total += self.kernel_spectra(traction) * profile[None, :, None]
        plane = np.fft.irfft(total, n=self.length, axis=1)[:, : self.grid.surface.nx]
        box = box or IndexBox.full(self.grid)
        sx, sy, sz = box.slices
        rows = sy.stop - sy.start
        return np.repeat(plane[:, sx, None, sz], rows, axis=2)

    @staticmethod
    def memory_bytes(grid: VolumeGrid, tractions: int = 3) -> int:
        """Bytes of the kernel spectra for ``tractions`` traction types and one evaluation."""
        half = (grid.surface.nx + 1) * grid.nz  # entries of one component's spectrum
        return tractions * 6 * 16 * half + 16 * 6 * half + 8 * 6 * int(np.prod(grid.shape))
