r"""Uniform eigenstrain in a cuboid of an infinite isotropic body: closed forms (Chiu 1977).

For an eigenstrain ``e*`` (symmetric tensor) uniform in the cuboid ``Omega`` of half-sides
``(a1, a2, a3)``, with shear modulus ``G``, Poisson's ratio ``nu``, Lame's ``lam`` and the
eigenstress ``s = lam tr(e*) I + 2 G e*``, the Kelvin tensor written as
``G_ij = delta_ij/(4 pi G r) - d_i d_j r/(16 pi G (1 - nu))`` gives (Mura 1987)::

    u_i   = -s_il Phi_,l/(4 pi G) + s_jl Psi_,ijl/(16 pi G (1 - nu))
    eps_ij = -(s_il Phi_,lj + s_jl Phi_,li)/(8 pi G) + s_kl Psi_,ijkl/(16 pi G (1 - nu))
    sigma = lam tr(eps) I + 2 G eps - [x in Omega] s

with the Newtonian potential ``Phi = int_Omega dV'/|x - x'|`` and the biharmonic potential
``Psi = int_Omega |x - x'| dV'`` (``Phi_,kk = -4 pi`` inside, ``Psi_,kk = 2 Phi``).

Each derivative is the alternating sum over the eight corners ``c = x - x'_corner`` (sign
``s1 s2 s3``, + for the corner at ``x' = +a``) of a derivative of the triple primitive ``F`` of
``1/r`` (for Phi) or ``P`` of ``r`` (for Psi).  Terms independent of one of the three variables
cancel in the sum and are dropped.  With ``r = |c|``, ``r_ij^2 = c_i^2 + c_j^2``,
``A_k = asinh(c_k / r_ij)`` and ``T_k = atan(c_i c_j/(c_k r))`` for ``{i, j, k} = {x, y, z}``
(checked with sympy and against quadrature in ``tests/test_eigenstrain.py``)::

    F_kk = -T_k          F_ij = A_k                       (Phi_,kl: "gravity of a prism")
    F_x  = c_z A_y + c_y A_z - c_x T_x                    (Phi_,l)
    P_xyz = r            P_iij = c_i A_k                  P_iii = 2 F_i - P_ijj - P_ikk
    P_iijk = c_i / r     P_iijj = -c_x c_y c_z/(r_ij^2 r)
    P_iiij = A_k - c_i^2 c_k/(r_ij^2 r)                   P_iiii = 2 F_ii - P_iijj - P_iikk

``T_k`` is singular only on the planes ``c_k = 0``; there the limit ``c_k -> 0+`` is taken
(:func:`_atan_ratio`), i.e. the field point is on the side of the face where ``c_k > 0``.

Eigenstrain and stress components are stored in the order (xx, yy, zz, yz, xz, xy)
(:data:`solver.volume.stress.STRESS_COMPONENTS`); eigenstrains are tensor components (``e_xz``, not
the engineering ``gamma_xz = 2 e_xz``).
"""

from __future__ import annotations

import itertools
import math

import numpy as np

from .stress import STRESS_COMPONENTS

_AXIS = {"x": 0, "y": 1, "z": 2}
_PAIRS = [(0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1)]  # STRESS_COMPONENTS as index pairs


def _key(*indices: int) -> str:
    """Sorted derivative name, e.g. (2, 0, 0) -> "xxz"."""
    return "".join(sorted("xyz"[i] for i in indices))


#: Names of the base functions Phi_,kl (6) and Psi_,ijkl (15) that make up the strain.
SECOND = tuple(sorted({_key(i, j) for i in range(3) for j in range(3)}))
FOURTH = tuple(sorted({_key(*c) for c in itertools.product(range(3), repeat=4)}))
#: Names of Phi_,l (3) and Psi_,ijl (10), the displacement's base functions.
FIRST = ("x", "y", "z")
THIRD = tuple(sorted({_key(*c) for c in itertools.product(range(3), repeat=3)}))


def _atan_ratio(num: np.ndarray, den: np.ndarray) -> np.ndarray:
    """atan(num/den), with the limit den -> 0+ (that is, (pi/2) sign(num)) where den == 0."""
    with np.errstate(divide="ignore", invalid="ignore"):
        out = np.arctan(num / den)
    return np.where(den == 0.0, 0.5 * math.pi * np.sign(num), out)


def corner_functions(c1, c2, c3, names) -> dict:
    """Derivatives of the triple primitives at corner offsets ``c`` (not yet corner-summed).

    Parameters
    ----------
    c1, c2, c3 : array_like
        Corner offsets ``x - x'_corner`` (m); broadcast together.  ``c1`` and ``c2`` must be
        nonzero; ``c3 = 0`` is allowed (limit ``c3 -> 0+``).
    names : iterable of str
        Wanted functions: ``"d" + k`` for derivatives of F (Phi), e.g. ``"dxz"``, ``"dx"``;
        ``"p" + k`` for derivatives of P (Psi), e.g. ``"pxxyz"``, ``"pxyz"``.

    Returns
    -------
    dict of ndarray
    """
    c = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (c1, c2, c3)))
    sq = [v * v for v in c]
    r = np.sqrt(sq[0] + sq[1] + sq[2])
    rho2 = {}  # rho2[k] = sum of the squares of the two other offsets
    asinh, atan = {}, {}

    def get_rho2(k):
        if k not in rho2:
            i, j = (m for m in range(3) if m != k)
            rho2[k] = sq[i] + sq[j]
        return rho2[k]

    def get_asinh(k):
        if k not in asinh:
            asinh[k] = np.arcsinh(c[k] / np.sqrt(get_rho2(k)))
        return asinh[k]

    def get_atan(k):
        if k not in atan:
            i, j = (m for m in range(3) if m != k)
            atan[k] = _atan_ratio(c[i] * c[j], c[k] * r)
        return atan[k]

    def f_first(i):
        j, k = (m for m in range(3) if m != i)
        return c[k] * get_asinh(j) + c[j] * get_asinh(k) - c[i] * get_atan(i)

    def f_second(i, j):
        if i == j:
            return -get_atan(i)
        return get_asinh(3 - i - j)

    def p_third(idx):
        counts = [idx.count(m) for m in range(3)]
        if counts == [1, 1, 1]:
            return r
        i = counts.index(max(counts))
        if counts[i] == 2:
            j = idx[0] if idx[0] != i else (idx[1] if idx[1] != i else idx[2])
            return c[i] * get_asinh(3 - i - j)
        j, k = (m for m in range(3) if m != i)
        return 2.0 * f_first(i) - c[j] * get_asinh(k) - c[k] * get_asinh(j)

    def p_fourth(idx):
        counts = [idx.count(m) for m in range(3)]
        xyz = c[0] * c[1] * c[2]
        if sorted(counts) == [1, 1, 2]:
            return c[counts.index(2)] / r
        if sorted(counts) == [0, 2, 2]:
            k = counts.index(0)
            return -xyz / (get_rho2(k) * r)
        if sorted(counts) == [0, 1, 3]:
            i, j = counts.index(3), counts.index(1)
            k = 3 - i - j
            return get_asinh(k) - sq[i] * c[k] / (get_rho2(k) * r)
        i = counts.index(4)
        j, k = (m for m in range(3) if m != i)
        return -2.0 * get_atan(i) + xyz / (get_rho2(k) * r) + xyz / (get_rho2(j) * r)

    out = {}
    for name in names:
        idx = tuple(_AXIS[ch] for ch in name[1:])
        if name[0] == "d" and len(idx) == 1:
            out[name] = f_first(idx[0])
        elif name[0] == "d" and len(idx) == 2:
            out[name] = f_second(*idx)
        elif name[0] == "p" and len(idx) == 3:
            out[name] = p_third(idx)
        elif name[0] == "p" and len(idx) == 4:
            out[name] = p_fourth(idx)
        else:
            raise KeyError(name)
    return out


def potentials(x, y, z, half_sizes, names) -> dict:
    """Derivatives of Phi and Psi of the cuboid ``|x_i| <= a_i`` at field points (corner sums).

    Parameters
    ----------
    x, y, z : array_like
        Field points relative to the cuboid centre (m).  Points on the planes ``x = +-a1`` or
        ``y = +-a2`` are not allowed; on ``z = +-a3`` the limit from ``z - z'_corner > 0`` is
        taken (see :func:`_atan_ratio`).
    half_sizes : (float, float, float)
        Half-sides ``a_i`` (m).
    names : iterable of str
        As in :func:`corner_functions`, e.g. ``"dxx"`` for Phi_,xx, ``"pxxyz"`` for Psi_,xxyz.

    Returns
    -------
    dict of ndarray
        Phi derivatives in m^(2 - order), Psi derivatives in m^(4 - order).
    """
    names = list(names)
    a = half_sizes
    out = {name: 0.0 for name in names}
    for signs in itertools.product((1.0, -1.0), repeat=3):
        corner = corner_functions(
            x + signs[0] * a[0], y + signs[1] * a[1], z + signs[2] * a[2], names
        )
        weight = signs[0] * signs[1] * signs[2]
        for name in names:
            out[name] = out[name] + weight * corner[name]
    return out


# --------------------------------------------------------------------------------------------
# Linear maps from the base functions to strain, stress and displacement
# --------------------------------------------------------------------------------------------


def lame(shear_modulus: float, nu: float) -> float:
    """Lame's first parameter lambda (Pa)."""
    return 2.0 * shear_modulus * nu / (1.0 - 2.0 * nu)


def unit_eigenstrain(component: int) -> np.ndarray:
    """3x3 tensor with a unit eigenstrain component (both e_ij and e_ji set for i != j)."""
    i, j = _PAIRS[component]
    e = np.zeros((3, 3))
    e[i, j] = e[j, i] = 1.0
    return e


def eigenstress(shear_modulus: float, nu: float, eigenstrain: np.ndarray) -> np.ndarray:
    """``C : e*`` for a 3x3 tensor (Pa)."""
    return lame(shear_modulus, nu) * np.trace(eigenstrain) * np.eye(3) + 2.0 * shear_modulus * (
        eigenstrain
    )


def stress_coefficients(shear_modulus: float, nu: float) -> tuple[np.ndarray, np.ndarray]:
    """Coefficients of the full-space stress in the base functions.

    Returns
    -------
    coefficients : ndarray
        Shape ``(6, 6, 21)``: stress component ``ij`` per unit eigenstrain ``mn`` is
        ``sum_b coefficients[ij, mn, b] * base_b``, base = ``"d" + SECOND`` then
        ``"p" + FOURTH`` (Pa per unit of the base function).
    inside : ndarray
        Shape ``(6, 6)``: ``C_ijmn``, to subtract where the field point is inside the cuboid.
    """
    g = shear_modulus
    lam = lame(g, nu)
    base = ["d" + k for k in SECOND] + ["p" + k for k in FOURTH]
    index = {name: b for b, name in enumerate(base)}
    coef = np.zeros((6, 6, len(base)))
    inside = np.zeros((6, 6))
    cphi = -1.0 / (8.0 * math.pi * g)
    cpsi = 1.0 / (16.0 * math.pi * g * (1.0 - nu))
    for mn in range(6):
        s = eigenstress(g, nu, unit_eigenstrain(mn))
        strain = np.zeros((3, 3, len(base)))
        for i, j in itertools.product(range(3), repeat=2):
            for ell in range(3):
                strain[i, j, index["d" + _key(ell, j)]] += cphi * s[i, ell]
                strain[i, j, index["d" + _key(ell, i)]] += cphi * s[j, ell]
            for k, ell in itertools.product(range(3), repeat=2):
                strain[i, j, index["p" + _key(i, j, k, ell)]] += cpsi * s[k, ell]
        trace = strain[0, 0] + strain[1, 1] + strain[2, 2]
        for ij, (i, j) in enumerate(_PAIRS):
            coef[ij, mn] = 2.0 * g * strain[i, j] + (lam * trace if i == j else 0.0)
            inside[ij, mn] = s[i, j]
    return coef, inside


def displacement_coefficients(shear_modulus: float, nu: float) -> np.ndarray:
    """Coefficients of the full-space displacement: shape ``(3, 6, 13)``.

    ``u_i`` per unit eigenstrain ``mn`` is ``sum_b coefficients[i, mn, b] * base_b``, base =
    ``"d" + FIRST`` then ``"p" + THIRD`` (m per unit base function).
    """
    g = shear_modulus
    base = ["d" + k for k in FIRST] + ["p" + k for k in THIRD]
    index = {name: b for b, name in enumerate(base)}
    coef = np.zeros((3, 6, len(base)))
    for mn in range(6):
        s = eigenstress(g, nu, unit_eigenstrain(mn))
        for i in range(3):
            for ell in range(3):
                coef[i, mn, index["d" + "xyz"[ell]]] -= s[i, ell] / (4.0 * math.pi * g)
                for j in range(3):
                    coef[i, mn, index["p" + _key(i, j, ell)]] += s[j, ell] / (
                        16.0 * math.pi * g * (1.0 - nu)
                    )
    return coef


STRESS_BASE = tuple(["d" + k for k in SECOND] + ["p" + k for k in FOURTH])
DISPLACEMENT_BASE = tuple(["d" + k for k in FIRST] + ["p" + k for k in THIRD])


def cuboid_stress(x, y, z, half_sizes, shear_modulus: float, nu: float, eigenstrain) -> np.ndarray:
    """Full-space stress of a uniform eigenstrain in a cuboid (pointwise closed form).

    Parameters
    ----------
    x, y, z : array_like
        Field points relative to the cuboid centre (m).  On a face plane the limit from the
        side of larger coordinate is returned (the lower faces count as inside).
    half_sizes : (float, float, float)
        Half-sides (m).
    shear_modulus, nu : float
        G (Pa) and Poisson's ratio.
    eigenstrain : array_like
        Six tensor components (xx, yy, zz, yz, xz, xy).

    Returns
    -------
    ndarray
        ``(6,) + broadcast shape`` stresses (Pa).
    """
    coef, inside = stress_coefficients(shear_modulus, nu)
    base = potentials(x, y, z, half_sizes, STRESS_BASE)
    e = np.asarray(eigenstrain, dtype=float)
    x, y, z = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (x, y, z)))
    # half-open cell [-a, a): consistent with the limit c -> 0+ taken on the face planes
    is_inside = np.ones(x.shape, dtype=bool)
    for v, a in zip((x, y, z), half_sizes, strict=True):
        is_inside &= (v >= -a) & (v < a)
    out = np.zeros((6,) + x.shape)
    for ij in range(6):
        for b, name in enumerate(STRESS_BASE):
            weight = float(np.einsum("m,m", coef[ij, :, b], e))
            if weight != 0.0:
                out[ij] += weight * base[name]
        out[ij] -= np.where(is_inside, np.einsum("m,m", inside[ij], e), 0.0)
    return out


def cuboid_displacement(
    x, y, z, half_sizes, shear_modulus: float, nu: float, eigenstrain
) -> np.ndarray:
    """Full-space displacement of a uniform eigenstrain in a cuboid: ``(3,) + shape`` (m)."""
    coef = displacement_coefficients(shear_modulus, nu)
    base = potentials(x, y, z, half_sizes, DISPLACEMENT_BASE)
    e = np.asarray(eigenstrain, dtype=float)
    x = np.asarray(x, dtype=float)
    shape = np.broadcast_shapes(x.shape, np.shape(y), np.shape(z))
    out = np.zeros((3,) + shape)
    for i in range(3):
        for b, name in enumerate(DISPLACEMENT_BASE):
            weight = float(np.einsum("m,m", coef[i, :, b], e))
            if weight != 0.0:
                out[i] += weight * base[name]
    return out


__all__ = [
    "STRESS_COMPONENTS",
    "corner_functions",
    "cuboid_displacement",
    "cuboid_stress",
    "displacement_coefficients",
    "potentials",
    "stress_coefficients",
]
