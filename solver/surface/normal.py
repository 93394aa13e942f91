"""Normal contact under force control: conjugate gradient with an active set (Polonsky & Keer 1999).

The CG is preconditioned by the inverse Boussinesq symbol |k|/(2A) applied on the contact set
(:meth:`solver.surface.convolution.SurfaceOperator.inverse_normal`), which makes the iteration count
nearly independent of the mesh (about 10 for a Hertz start at 64^2 ... 512^2).

Find the pressure ``p >= 0`` (Pa) with ``sum(p) dA = W`` such that the gap
``g = h + u_z(p) - delta`` is zero where ``p > 0`` and non-negative elsewhere.  ``h`` is the
initial gap plus every extra gap term a caller feeds in (residual print, the normal displacement
of the shear tractions); ``delta`` is the rigid approach, the Lagrange multiplier of the force
constraint (the mean of ``h + u_z`` over the contact set).

Convergence is judged on the complementarity residual

    max( rms over contact of |g|, max over non-contact of max(-g, 0) ) / mean over contact of u_z

i.e. the gap error relative to the elastic displacement scale (on a periodic grid, whose
displacements have zero mean: their rms, or the mean pressure's displacement over a cell if
larger), and on the relative pressure change
``sum |dp| dA / W``; both must fall below ``tolerance``.  A residual below ``tolerance`` with no
descent direction left (the preconditioned gradient vanished to round-off, as when the starting
pressure already solves the problem) is converged too; with a larger residual it is a stall.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .convolution import SurfaceOperator


@dataclass(frozen=True)
class NormalSolution:
    """Result of one normal contact solve.

    Attributes
    ----------
    pressure : ndarray
        Contact pressure (Pa), shape (nx, ny).
    gap : ndarray
        Deformed gap (m), zero in contact up to the residual.
    displacement : ndarray
        u_z from the pressure alone (m).
    approach : float
        Rigid approach delta (m).
    iterations : int
        CG iterations.
    residual : float
        Final complementarity residual (dimensionless, see module docstring).
    converged : bool
        True when the residual fell below the tolerance.
    message : str
        Human-readable status.
    """

    pressure: np.ndarray
    gap: np.ndarray
    displacement: np.ndarray
    approach: float
    iterations: int
    residual: float
    converged: bool
    message: str


def _dot(a: np.ndarray, b: np.ndarray) -> float:
    """Sum of a*b over the grid, without BLAS (whose idle threads stall small calls)."""
    return float(np.einsum("ij,ij->", a, b))


#: Restarts of the normal solve from a contact set enlarged by its penetrating cells, when the
#: gradient vanishes on the set while cells outside it penetrate (:func:`solve_normal`).
MAX_RESTARTS = 50


def solve_normal(
    operator: SurfaceOperator,
    gap: np.ndarray,
    normal_force: float,
    *,
    initial_pressure: np.ndarray | None = None,
    tolerance: float = 1e-8,
    max_iterations: int = 1000,
    precondition: bool = True,
) -> NormalSolution:
    """Solve the frictionless normal contact problem under a prescribed normal force.

    Parameters
    ----------
    operator : SurfaceOperator
        Surface operator of the grid (its ``zz`` block is used).
    gap : ndarray
        Initial gap plus extra gap terms, ``h`` (m), shape (nx, ny).
    normal_force : float
        W (N), > 0.
    initial_pressure : ndarray, optional
        Starting pressure (Pa); a uniform pressure on the geometric overlap region if omitted.
    tolerance : float
        Relative tolerance on the complementarity residual and the pressure change.
    max_iterations : int
        Iteration cap; the result reports ``converged=False`` when it is reached.

    Returns
    -------
    NormalSolution
    """
    area = operator.grid.cell_area
    h = np.asarray(gap, dtype=float)
    if initial_pressure is None or not np.any(initial_pressure > 0):
        # Uniform pressure on the region the rigid approach of the mean gap would close.
        thresh = np.quantile(h, 0.05)
        p = np.where(h <= thresh, 1.0, 0.0)
    else:
        p = np.clip(np.asarray(initial_pressure, dtype=float), 0.0, None)
    p *= normal_force / (area * p.sum())

    t = np.zeros_like(p)
    g_norm_old = 1.0
    reset = True
    residual = np.inf
    change = np.inf
    converged = False
    iterations = 0
    message = ""
    restarts = 0
    tiny = np.finfo(float).tiny
    u, u_exact = operator.normal(p), True
    for iterations in range(1, max_iterations + 1):
        # Dense masked arithmetic (no boolean fancy indexing): mask is 1 in contact, 0 outside.
        mask = (p > 0.0).astype(float)
        n_contact = mask.sum()
        if n_contact == 0 or not np.isfinite(u).all():
            message = "breakdown: the pressure left every cell or became non-finite"
            break
        g = h + u
        g -= _dot(g, mask) / n_contact
        g_contact = g * mask
        g_norm = float(_dot(g_contact, g_contact))
        if operator.periodic:  # u has zero mean over the period: its rms sets the scale, or
            # (a flat period, uniform pressure, u = 0) the mean pressure's over one cell
            cell = normal_force / (area * u.size) * operator.pair.compliance * operator.grid.dx
            scale = max(np.sqrt(float(_dot(u, u)) / u.size), cell, tiny)
        else:
            scale = max(float(_dot(u, mask)) / n_contact, tiny)
        penetration = max(0.0, -float((g - g_contact).min()))
        residual = max(np.sqrt(g_norm / n_contact), penetration) / scale
        if residual < tolerance and (change < tolerance or g_norm == 0.0):
            if not u_exact:  # confirm with a fresh convolution before accepting
                u, u_exact = operator.normal(p), True
                continue
            converged = True
            iterations -= 1
            break
        if precondition:
            # z = M^-1 g: the inverse of the circulant kernel, applied on the contact set and
            # kept force-neutral; PCG with beta = <g, z>/<g_old, z_old>
            z = operator.inverse_normal(g_contact)
            z *= mask
            z -= mask * (_dot(z, mask) / n_contact)
            gz = _dot(g_contact, z)
        else:
            z, gz = g_contact, g_norm
        if not gz > 0.0:  # no descent direction left
            if residual < tolerance:
                # The gradient vanished to round-off: p already solves the problem (a re-solve
                # from the previous solution, before ``change`` could fall below the tolerance).
                if not u_exact:  # confirm with a fresh convolution before accepting
                    u, u_exact = operator.normal(p), True
                    continue
                converged = True
                iterations -= 1
                break
            outside = (g < 0.0) & (p == 0.0)  # penetrating cells out of the contact set
            if outside.any() and restarts < MAX_RESTARTS:
                # The gradient vanished on the contact set (a few cells of one gap) while
                # cells outside penetrate: give them the mean contact pressure and restart
                # (the overlap step needs a CG step to ride on)
                p = p + outside * (p.sum() / n_contact)
                p *= normal_force / (area * p.sum())
                u, u_exact = operator.normal(p), True
                reset, restarts = True, restarts + 1
                continue
            message = "stalled: no descent direction"  # and the residual is too large
            break
        t *= 0.0 if reset or g_norm_old <= 0.0 else gz / g_norm_old
        t += z
        t *= mask
        g_norm_old = gz
        raw = operator.normal(t)
        r = raw - _dot(raw, mask) / n_contact
        denominator = float(_dot(r, t))
        if denominator <= 0.0:
            reset = True
            continue
        tau = float(_dot(g, t)) / denominator
        if not np.isfinite(tau):
            message = "breakdown: non-finite step"
            break
        p_new = p - tau * t
        clipped = bool((p_new < 0.0).any())
        np.clip(p_new, 0.0, None, out=p_new)
        # Non-contact cells that penetrate re-enter the contact set (Polonsky-Keer overlap step).
        overlap = np.minimum(g, 0.0) * (p_new == 0.0)
        reset = bool(overlap.any())
        if reset:
            p_new -= tau * overlap
        rescale = normal_force / (area * p_new.sum())
        if not np.isfinite(rescale):
            message = "breakdown: no positive pressure left after the CG step"
            break
        p_new *= rescale
        change = float(np.abs(p_new - p).sum()) * area / normal_force
        p = p_new
        u_exact = clipped or reset or iterations % 16 == 0
        if u_exact:
            u = operator.normal(p)
        else:  # the update was exactly p - tau t, scaled: u follows by linearity, no FFT needed
            u -= tau * raw
            u *= rescale
    if not u_exact:
        u = operator.normal(p)
    contact = p > 0.0
    g = h + u
    delta = float(g[contact].mean())
    g -= delta
    message = (
        f"converged in {iterations} iterations"
        if converged
        else f"not converged after {iterations} iterations (residual {residual:.3g}) {message}"
    ).strip()
    return NormalSolution(p, g, u, delta, iterations, float(residual), converged, message)
