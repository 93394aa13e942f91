r"""Stresses inside an elastic half-space under surface tractions: the closed forms.

Conventions (as :mod:`solver.surface.influence`): ``z`` points down, into body 2, the half-space
whose stresses are computed.  The tractions acting on its surface are ``(q_x, q_y, p)``: ``p > 0``
pushes into the body (+z), ``q_x > 0`` acts in +x.  Stresses are positive in tension and are
returned in the order :data:`solver.numerics.tensor.COMPONENTS` = (xx, yy, zz, yz, xz, xy).  At the
surface the stress balances the load: ``sigma_zz = -p``, ``sigma_xz = -q_x``, ``sigma_yz = -q_y``.

Derivation (checked with sympy: Navier's equations, the free surface and the total force).
With ``Omega = z ln(R + z) - R``, ``R = |x|``, the displacements of a unit point force at the
origin are, with ``G`` the shear modulus (Boussinesq, force along +z; Cerruti, force along +x)::

    4 pi G u  (normal)  = ( -z O_xzz - (1-2nu) O_xz,  -z O_yzz - (1-2nu) O_yz,
                            -z O_zzz + 2(1-nu) O_zz )
    4 pi G u  (shear x) = ( 2 O_zz - z O_xxz + 2nu O_xx,  -z O_xyz + 2nu O_xy,
                            -z O_xzz + (1-2nu) O_xz )

(``O_xz`` = d^2 Omega/dx dz, ...).  Omega is harmonic, so for any traction field the same
formulas hold with ``W = integral of t(xi, eta) Omega(x - xi, y - eta, z)`` in place of Omega.
Hooke's law and the harmonicity of W reduce the stresses to (times ``1/(2 pi)``)::

    pressure   xx: -W_xxz - 2nu W_yyz - z W_xxzz      yy: -W_yyz - 2nu W_xxz - z W_yyzz
               zz:  W_zzz - z W_zzzz                  yz: -z W_yzzz
               xz: -z W_xzzz                          xy: (2nu - 1) W_xyz - z W_xyzz
    shear x    xx: -2 W_xxx - 2(1+nu) W_xyy - z W_xxxz   yy: -2nu W_xxx - z W_xyyz
               zz: -z W_xzzz                          yz: -z W_xyzz
               xz:  W_zzz - z W_xxzz                  xy: W_yzz + 2nu W_xxy - z W_xxyz

and the y-shear table is the x-shear one with x and y exchanged.  The stresses do not depend on
G (nor on E), only on Poisson's ratio.

Rectangle (a uniformly loaded cell).  W is the alternating corner sum of ``Lambda`` with
``d^2 Lambda/dx dy = Omega``; every derivative ``W_b`` is the corner sum of ``F_b = d^b Lambda``.
Terms of ``F_b`` that depend on only one of x, y cancel in the sum and are dropped; Lambda is
harmonic up to such terms.  At a corner ``(x, y, z)``, ``z > 0``, with ``Rz = R + z``,
``rx^2 = x^2 + z^2`` and ``ry^2 = y^2 + z^2`` (the cases with x and y exchanged follow)::

    F_xxy = -x/Rz           F_xyz = ln Rz         F_xyzz = 1/R        F_xxyz = x/(R Rz)
    F_yzz = asinh(x/ry)     F_yyz = atan(x/y) - atan(x z/(y R))
    F_yyy = x/Rz - asinh(x/ry)                    F_yyzz = -x y/(ry^2 R)
    F_yzzz = -x z/(ry^2 R)  F_yyyz = x z/(ry^2 R) - x/(R Rz)
    F_zzz = -(F_xxz + F_yyz)                      F_zzzz = -(F_xxzz + F_yyzz)

Love (1929) gave the pressure case; the shear case is the integral of Cerruti's solution.  Both
are checked against quadrature of the point-force fields in ``tests/test_stress.py``.

Hertz and Hamilton (1983).  For ``p = p0 sqrt(1 - r^2/a^2)`` (and ``q_x = mu p``) the potential
W is axisymmetric and harmonic; its values on the axis continue off the axis with a source at
the complex depth ``-i a``: with ``u = z + i a``, ``Rc = sqrt(r^2 + u^2)`` (Hamilton's M + iN)
and ``l = ln((Rc + u)/2)``,
``W = (pi p0/a) Im h(u, Rc) - pi p0 (z^3 - 3 z r^2/2)/6`` with
``h = [C4 - ln2 P4]/12 - 7 P4/144 - 2 i a ([C3 - ln2 P3]/6 - 5 P3/36)``, where ``Pn`` and
``Cn`` are the harmonic continuations of ``z^n`` and ``z^n ln 2z``.  Only the derivatives
``E[m, c] = Dr^m Dz^c W``, ``Dr = (1/r) d/dr``, are needed (:func:`_hertz_radial_derivatives`);
they reproduce Hamilton's (1983) normal-load expressions to round-off and quadrature of the
Cerruti field for the tangential ones.
"""

from __future__ import annotations

import math

import numpy as np

#: Surface traction components, in the order of
#: :meth:`solver.volume.stress.SubsurfaceStressOperator.kernel_spectra`.
TRACTIONS = ("pressure", "shear_x", "shear_y")


def _swap_xy(name: str) -> str:
    return name.translate(str.maketrans("xy", "yx"))


def _sort_key(name: str) -> str:
    return "".join(sorted(name))


def stress_from_potential(w: dict, z, nu: float, traction: str) -> np.ndarray:
    """Six stress components (per unit traction) from the derivatives ``w[name]`` of W.

    ``w`` maps sorted derivative names ("xxz", "xyzz", ...) to arrays; "zzz" and "zzzz" may be
    absent (they follow from harmonicity).
    """
    if traction == "shear_y":
        w_swapped = {_sort_key(_swap_xy(k)): v for k, v in w.items()}
        sx = stress_from_potential(w_swapped, z, nu, "shear_x")
        return sx[[1, 0, 2, 4, 3, 5]]
    zzz = w["zzz"] if "zzz" in w else -(w["xxz"] + w["yyz"])
    scale = 1.0 / (2.0 * math.pi)
    if traction == "pressure":
        zzzz = w["zzzz"] if "zzzz" in w else -(w["xxzz"] + w["yyzz"])
        out = (
            -w["xxz"] - 2.0 * nu * w["yyz"] - z * w["xxzz"],
            -w["yyz"] - 2.0 * nu * w["xxz"] - z * w["yyzz"],
            zzz - z * zzzz,
            -z * w["yzzz"],
            -z * w["xzzz"],
            (2.0 * nu - 1.0) * w["xyz"] - z * w["xyzz"],
        )
    elif traction == "shear_x":
        out = (
            -2.0 * w["xxx"] - 2.0 * (1.0 + nu) * w["xyy"] - z * w["xxxz"],
            -2.0 * nu * w["xxx"] - z * w["xyyz"],
            -z * w["xzzz"],
            -z * w["xyzz"],
            zzz - z * w["xxzz"],
            w["yzz"] + 2.0 * nu * w["xxy"] - z * w["xxyz"],
        )
    else:
        raise ValueError(f"unknown traction {traction!r}; use one of {TRACTIONS}")
    return scale * np.stack(np.broadcast_arrays(*out))


#: Derivatives of W each table needs (the y-shear set is the x-shear one with x, y exchanged).
POTENTIAL_DERIVATIVES = {
    "pressure": ("xxz", "yyz", "xxzz", "yyzz", "yzzz", "xzzz", "xyz", "xyzz"),
    "shear_x": ("xxx", "xyy", "xxxz", "xyyz", "xzzz", "xyzz", "xxz", "yyz", "xxzz", "yzz", "xxy",
                "xxyz"),
}  # fmt: skip
POTENTIAL_DERIVATIVES["shear_y"] = tuple(
    _sort_key(_swap_xy(k)) for k in POTENTIAL_DERIVATIVES["shear_x"]
)


def corner_functions(x: np.ndarray, y: np.ndarray, z: float, names) -> dict:
    """The corner functions ``F_b`` (see the module docstring) at corners ``(x, y, z)``, z > 0.

    ``x`` and ``y`` must be nonzero (cell corners never lie on a cell-centre line).
    """
    x, y = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(y, dtype=float))
    names = set(names)
    z2 = z * z
    r = np.sqrt(x * x + y * y + z2)
    rz = r + z
    rx2, ry2 = x * x + z2, y * y + z2
    out = {}

    def want(*keys):
        return any(k in names for k in keys)

    if want("xzz", "xxx"):
        ay = np.arcsinh(y / np.sqrt(rx2))
    if want("yzz", "yyy"):
        ax = np.arcsinh(x / np.sqrt(ry2))
    for name in names:
        if name == "xxy":
            out[name] = -x / rz
        elif name == "xyy":
            out[name] = -y / rz
        elif name == "xyz":
            out[name] = np.log(rz)
        elif name == "xyzz":
            out[name] = 1.0 / r
        elif name == "xxyz":
            out[name] = x / (r * rz)
        elif name == "xyyz":
            out[name] = y / (r * rz)
        elif name == "xzz":
            out[name] = ay
        elif name == "yzz":
            out[name] = ax
        elif name == "xxz":
            out[name] = np.arctan(y / x) - np.arctan(y * z / (x * r))
        elif name == "yyz":
            out[name] = np.arctan(x / y) - np.arctan(x * z / (y * r))
        elif name == "xxx":
            out[name] = y / rz - ay
        elif name == "yyy":
            out[name] = x / rz - ax
        elif name == "xxzz":
            out[name] = -x * y / (rx2 * r)
        elif name == "yyzz":
            out[name] = -x * y / (ry2 * r)
        elif name == "xzzz":
            out[name] = -y * z / (rx2 * r)
        elif name == "yzzz":
            out[name] = -x * z / (ry2 * r)
        elif name == "xxxz":
            out[name] = y * z / (rx2 * r) - y / (r * rz)
        elif name == "yyyz":
            out[name] = x * z / (ry2 * r) - x / (r * rz)
        else:
            raise KeyError(name)
    return out


def rectangle_stress(
    x, y, z: float, dx: float, dy: float, nu: float, traction: str = "pressure"
) -> np.ndarray:
    """Stresses of a unit traction on the rectangle ``[-dx/2, dx/2] x [-dy/2, dy/2]``.

    Parameters
    ----------
    x, y : array_like
        Field-point coordinates relative to the rectangle's centre (m); no field point may lie
        on the lines through the rectangle's edges.
    z : float
        Depth (m), > 0.
    dx, dy : float
        Rectangle sides (m).
    nu : float
        Poisson's ratio of the half-space.
    traction : {"pressure", "shear_x", "shear_y"}
        The unit traction (1 Pa) applied on the rectangle.

    Returns
    -------
    ndarray
        Shape ``(6,) + broadcast(x, y).shape``, components :data:`STRESS_COMPONENTS`, in Pa per
        Pa of traction.
    """
    if not z > 0.0:
        raise ValueError("rectangle_stress needs a depth z > 0")
    names = POTENTIAL_DERIVATIVES[traction]
    a, b = 0.5 * dx, 0.5 * dy
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    corners = [(x + a, y + b, 1.0), (x + a, y - b, -1.0), (x - a, y + b, -1.0), (x - a, y - b, 1.0)]
    w: dict = {}
    for cx, cy, sign in corners:
        for k, v in corner_functions(cx, cy, z, names).items():
            w[k] = w.get(k, 0.0) + sign * v
    return stress_from_potential(w, z, nu, traction)


def _w_from_radial(e: dict, x, y) -> dict:
    """Cartesian derivatives of an axisymmetric W from ``e[m, c] = Dr^m Dz^c W``."""
    x2, y2 = x * x, y * y
    w = {
        "zzz": e[0, 3],
        "zzzz": e[0, 4],
        "xxz": e[1, 1] + x2 * e[2, 1],
        "yyz": e[1, 1] + y2 * e[2, 1],
        "xyz": x * y * e[2, 1],
        "xzz": x * e[1, 2],
        "yzz": y * e[1, 2],
        "xxzz": e[1, 2] + x2 * e[2, 2],
        "yyzz": e[1, 2] + y2 * e[2, 2],
        "xyzz": x * y * e[2, 2],
        "xzzz": x * e[1, 3],
        "yzzz": y * e[1, 3],
        "xxx": 3.0 * x * e[2, 0] + x * x2 * e[3, 0],
        "yyy": 3.0 * y * e[2, 0] + y * y2 * e[3, 0],
        "xyy": x * e[2, 0] + x * y2 * e[3, 0],
        "xxy": y * e[2, 0] + x2 * y * e[3, 0],
        "xxxz": 3.0 * x * e[2, 1] + x * x2 * e[3, 1],
        "yyyz": 3.0 * y * e[2, 1] + y * y2 * e[3, 1],
        "xyyz": x * e[2, 1] + x * y2 * e[3, 1],
        "xxyz": y * e[2, 1] + x2 * y * e[3, 1],
    }
    return w


def point_force_stress(x, y, z, nu: float, traction: str = "pressure") -> np.ndarray:
    """Stresses of a unit point force at the origin (Boussinesq, Cerruti).

    Parameters
    ----------
    x, y, z : array_like
        Field points (m), ``z > 0``.
    nu : float
        Poisson's ratio.
    traction : {"pressure", "shear_x", "shear_y"}
        Direction of the 1 N force: +z (into the body), +x or +y.

    Returns
    -------
    ndarray
        Shape ``(6,) + broadcast shape`` (Pa/N).
    """
    x, y, z = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (x, y, z)))
    r = np.sqrt(x * x + y * y + z * z)
    rz = r + z
    r3, r5 = r**3, r**5
    e = {
        (0, 3): -z / r3,
        (0, 4): (3.0 * z * z - r * r) / r5,
        (1, 1): 1.0 / (r * rz),
        (1, 2): -1.0 / r3,
        (1, 3): 3.0 * z / r5,
        (2, 0): 1.0 / (r * rz**2),
        (2, 1): -(2.0 * r + z) / (r3 * rz**2),
        (2, 2): 3.0 / r5,
        (3, 0): -(3.0 * r + z) / (r3 * rz**3),
        (3, 1): (8.0 * r * r + 9.0 * r * z + 3.0 * z * z) / (r5 * rz**3),
    }
    return stress_from_potential(_w_from_radial(e, x, y), z, nu, traction)


def _hertz_radial_derivatives(r2, z, radius: float) -> dict:
    """``Dr^m Dz^c`` of the Hertz potential ``W / (pi p0)`` (see the module docstring)."""
    a = radius
    ia = 1j * a
    u = z + ia
    rc = np.sqrt(r2 + u * u)  # principal root: Re > 0 for z > 0
    t = rc + u
    log_half = np.log(t / 2.0)
    e = {
        (0, 3): 2.0 * (u - ia) * log_half - 2.0 * rc + 3.0 * u - 2.0 * ia,
        (1, 2): -log_half + (2.0 * ia - rc - 2.0 * u) / t,
        (1, 1): (ia - u) * log_half
        + (4.0 * rc * rc + 3.0 * ia * rc - 2.0 * rc * u + 9.0 * ia * u - 8.0 * u * u) / (6.0 * t),
        (2, 1): (2.0 * rc + u + 3.0 * ia) / (3.0 * t * t),
        (2, 0): 0.25 * log_half
        + (9.0 * rc * rc - 32.0 * ia * rc + 38.0 * rc * u - 16.0 * ia * u + 25.0 * u * u)
        / (48.0 * t * t),
        (3, 0): (3.0 * rc + u + 8.0 * ia) / (12.0 * t**3),
        (0, 4): 2.0 * log_half + 3.0 - 2.0 * ia / rc,
        (1, 3): -2.0 * (rc + ia) / (rc * t),
        (2, 2): -(rc + 2.0 * ia) / (rc * t * t),
        (3, 1): -2.0 * (rc + 3.0 * ia) / (3.0 * rc * t**3),
    }
    real_part = {(0, 3): -1.0, (1, 1): 0.5}  # from -(z^3 - 3 z r^2/2)/6
    return {k: np.imag(v) / a + real_part.get(k, 0.0) for k, v in e.items()}


def hamilton_stress(
    x,
    y,
    z,
    radius: float,
    max_pressure: float,
    nu: float,
    friction_coefficient: float = 0.0,
) -> np.ndarray:
    """Stress field of a Hertz pressure with a sliding traction ``q_x = mu p`` (Hamilton 1983).

    Parameters
    ----------
    x, y, z : array_like
        Field points (m), ``z > 0``, relative to the contact centre.
    radius : float
        Contact radius a (m).
    max_pressure : float
        Peak Hertz pressure p0 (Pa); ``p = p0 sqrt(1 - r^2/a^2)``.
    nu : float
        Poisson's ratio.
    friction_coefficient : float
        mu; the shear traction on the body is ``q_x = mu p`` (+x).

    Returns
    -------
    ndarray
        Shape ``(6,) + broadcast shape``, Pa, components :data:`STRESS_COMPONENTS`.

    Notes
    -----
    Closed form in elementary functions of the complex distance ``Rc = M + i N`` (see the
    module docstring); the normal part equals Hamilton's (1983) expressions and, on the axis,
    Johnson's (1985) eqs 3.45.
    """
    x, y, z = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (x, y, z)))
    e = _hertz_radial_derivatives(x * x + y * y, z, radius)
    w = _w_from_radial(e, x, y)
    out = stress_from_potential(w, z, nu, "pressure")
    if friction_coefficient != 0.0:
        out = out + friction_coefficient * stress_from_potential(w, z, nu, "shear_x")
    return math.pi * max_pressure * out


def mcewen_stress(
    x, z, half_width: float, max_pressure: float, nu: float, friction_coefficient=0.0
):
    """Plane-strain stress of a Hertz line contact with a sliding traction (McEwen 1949).

    The pressure ``p = p0 sqrt(1 - x^2/a^2)`` and the shear ``q_x = mu p`` (+x) on the surface
    of a half-space in plane strain along y.  With ``A = a^2 - x^2 + z^2``,
    ``m^2 = (sqrt(A^2 + 4 x^2 z^2) + A)/2``, ``n^2 = (sqrt(A^2 + 4 x^2 z^2) - A)/2`` (n has the
    sign of x) and ``S = m^2 + n^2``, per unit ``p0 / a`` (Johnson 1985, section 7.1, the
    sign of the normal load's shear fixed by quadrature of Flamant's solution,
    ``tests/test_theorems.py``)::

        pressure  xx: -m (1 + (z^2 + n^2)/S) + 2 z   zz: -m (1 - (z^2 + n^2)/S)
                  xz: -n (m^2 - z^2)/S
        shear x   xx:  mu (n (2 - (z^2 - m^2)/S) - 2 x)   zz: -mu n (m^2 - z^2)/S
                  xz: -mu (m (1 + (z^2 + n^2)/S) - 2 z)

    and ``sigma_yy = nu (sigma_xx + sigma_zz)``, ``sigma_yz = sigma_xy = 0``.

    Parameters
    ----------
    x, z : array_like
        Field points (m), ``z > 0``, relative to the contact's centre line.
    half_width : float
        Contact half-width a (m).
    max_pressure : float
        Peak pressure p0 (Pa).
    nu : float
        Poisson's ratio.
    friction_coefficient : float
        mu; the shear traction on the body is ``q_x = mu p`` (+x).

    Returns
    -------
    ndarray
        Shape ``(6,) + broadcast shape`` (Pa), components :data:`STRESS_COMPONENTS`.
    """
    x, z = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (x, z)))
    a, mu = half_width, friction_coefficient
    big = a * a - x * x + z * z
    root = np.sqrt(big * big + 4.0 * x * x * z * z)
    m = np.sqrt(0.5 * (root + big))
    n = np.sign(x) * np.sqrt(np.maximum(0.5 * (root - big), 0.0))
    s = m * m + n * n
    out = np.zeros((6,) + x.shape)
    out[0] = (
        -m * (1.0 + (z * z + n * n) / s)
        + 2.0 * z
        + mu * (n * (2.0 - (z * z - m * m) / s) - 2.0 * x)
    )
    out[2] = -m * (1.0 - (z * z + n * n) / s) - mu * n * (m * m - z * z) / s
    out[4] = -n * (m * m - z * z) / s - mu * (m * (1.0 + (z * z + n * n) / s) - 2.0 * z)
    out[1] = nu * (out[0] + out[2])
    return out * (max_pressure / a)


def strip_stress(x, z, half: float, nu: float, traction: str = "pressure") -> np.ndarray:
    r"""Plane-strain stress (per unit traction) of a uniform traction on a strip ``|x| < half``.

    The line-load fields (Flamant; Johnson 1985, section 2.2), with ``r^2 = X^2 + z^2`` at
    ``X`` from the load: a normal load P (+z, into the body) gives ``sigma_xx, sigma_zz,
    sigma_xz = -(2P/pi) (X^2 z, z^3, X z^2) / r^4``, a tangential one Q (+x) ``-(2Q/pi)
    (X^3, X z^2, X^2 z) / r^4``, and an antiplane one S (+y) ``sigma_xy, sigma_yz = -(S/pi)
    (X, z) / r^2`` (``w = -(S/(pi G)) ln r``).  Each integrates over the strip in closed form,
    ``G(x + half) - G(x - half)`` with ``theta = atan(X/z)`` and the antiderivatives
    (derived here; checked in ``tests/test_plane_strain.py`` against Love's rectangle made
    long along y)::

        int z^3/r^4 = (theta + z X/r^2)/2      int X^2 z/r^4 = (theta - z X/r^2)/2
        int X z^2/r^4 = -z^2/(2 r^2)          int X^3/r^4 = ln(r^2)/2 + z^2/(2 r^2)
        int X/r^2 = ln(r^2)/2                 int z/r^2 = theta

    and ``sigma_yy = nu (sigma_xx + sigma_zz)`` (plane strain) for the in-plane loads.  At the
    surface the stress balances the load, as in the module's conventions.

    Parameters
    ----------
    x, z : array_like
        Field points (m) relative to the strip's centre line, ``z > 0``.
    half : float
        The strip's half-width (m).
    nu : float
        Poisson's ratio.
    traction : str
        One of :data:`TRACTIONS`.

    Returns
    -------
    ndarray
        Shape ``(6,) + broadcast shape``, per unit traction (Pa/Pa), components
        :data:`solver.numerics.tensor.COMPONENTS`.
    """
    if traction not in TRACTIONS:
        raise ValueError(f"unknown traction {traction!r}; use one of {TRACTIONS}")
    x, z = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (x, z)))

    def parts(big_x):
        r2 = big_x * big_x + z * z
        theta = np.arctan2(big_x, z)
        ratio = z * big_x / r2
        log = 0.5 * np.log(r2 / (half * half))
        return {
            "zzz": 0.5 * (theta + ratio),
            "xxz": 0.5 * (theta - ratio),
            "xzz": -0.5 * z * z / r2,
            "xxx": log + 0.5 * z * z / r2,
            "x": log,
            "z": theta,
        }

    ahead, behind = parts(x + half), parts(x - half)
    g = {key: ahead[key] - behind[key] for key in ahead}
    out = np.zeros((6,) + x.shape)
    scale = -2.0 / math.pi
    if traction == "pressure":
        out[0], out[2], out[4] = scale * g["xxz"], scale * g["zzz"], scale * g["xzz"]
    elif traction == "shear_x":
        out[0], out[2], out[4] = scale * g["xxx"], scale * g["xzz"], scale * g["xxz"]
    else:
        out[5], out[3] = -g["x"] / math.pi, -g["z"] / math.pi
    if traction != "shear_y":
        out[1] = nu * (out[0] + out[2])
    return out


def uniform_traction_stress(traction: str, nu: float) -> np.ndarray:
    """Stress (per unit traction) of a uniform traction on a laterally periodic half-space.

    A periodic body has periodic displacements, so the mean lateral strains vanish:
    ``e_xx = e_yy = e_xy = 0``, and the stress is uniform with depth.  A unit pressure gives
    ``sigma_zz = -1`` and ``sigma_xx = sigma_yy = -nu / (1 - nu)`` (uniaxial strain); a unit
    shear ``q_x`` gives ``sigma_xz = -1`` only (simple shear), ``q_y`` likewise.  Components in
    :data:`solver.numerics.tensor.COMPONENTS` order; this is the mean mode of the periodic
    traction-to-stress kernels.
    """
    out = np.zeros(6)
    if traction == "pressure":
        out[:3] = (-nu / (1.0 - nu), -nu / (1.0 - nu), -1.0)
    elif traction in ("shear_x", "shear_y"):
        out[4 if traction == "shear_x" else 3] = -1.0
    else:
        raise ValueError(f"unknown traction {traction!r}; use one of {TRACTIONS}")
    return out


def uniform_layer_stress(E: float, nu: float) -> np.ndarray:
    """Stress inside a laterally uniform eigenstrain layer of a periodic half-space (Pa).

    ``D[ij, mn]``: stress component ij per unit eigenstrain tensor component mn (shear
    components are tensor values, ``e_xy = e_yx``), in
    :data:`solver.numerics.tensor.COMPONENTS` order.  The total strain has no lateral part
    (periodic displacements), the tractions on horizontal planes vanish (a free surface and
    equilibrium), so ``sigma_xz = sigma_yz = sigma_zz = 0`` and
    ``sigma_xx = -E/(1 - nu^2) (e_xx + nu e_yy)``, ``sigma_yy`` likewise,
    ``sigma_xy = -2 G e_xy``; ``e_zz``, ``e_xz``, ``e_yz`` stress nothing.  Outside the layer
    the stress is zero: the mean mode of the periodic eigenstrain kernels is local in depth.
    """
    plane = E / (1.0 - nu * nu)
    out = np.zeros((6, 6))
    out[0, 0] = out[1, 1] = -plane
    out[0, 1] = out[1, 0] = -plane * nu
    out[5, 5] = -E / (1.0 + nu)
    return out


def periodic_traction_stress(
    size: tuple[float, float],
    z: np.ndarray,
    nu: float,
    pressure: np.ndarray,
    shear_x: np.ndarray | None = None,
    shear_y: np.ndarray | None = None,
) -> np.ndarray:
    """Stress under periodic surface tractions, from their Fourier series (Pa).

    A Fourier mode ``exp(i k.x)`` of the tractions is a two-dimensional problem along
    ``n = k/|k|`` (``t`` = n turned a quarter, ``K = |k|``, ``E = exp(-K z)``), solved with Airy's
    function (Johnson 1985, §2.8) and, for the shear along the crests, anti-plane shear:

    * pressure ``p``: ``s_nn = -p (1 - K z) E``, ``s_zz = -p (1 + K z) E``,
      ``s_nz = i p K z E``;
    * shear along n, ``q_n``: ``s_nn = i q_n (2 - K z) E``, ``s_zz = i q_n K z E``,
      ``s_nz = -q_n (1 - K z) E``;
    * in both, plane strain: ``s_tt = nu (s_nn + s_zz)``;
    * shear along t, ``q_t``: ``s_tz = -q_t E``, ``s_nt = i q_t E``;

    turned to x and y.  The mean tractions give the uniform stresses of
    :func:`uniform_traction_stress`.  The tractions are taken as samples of band-limited
    fields (no cell averaging): a trial stress, and an independent check of the periodised cell
    kernels of :mod:`solver.volume.stress`.

    Parameters
    ----------
    size : (float, float)
        The period ``(Lx, Ly)`` (m).
    z : ndarray
        Depths (m), positive into the body.
    nu : float
        Poisson's ratio.
    pressure : ndarray
        ``(nx, ny)`` pressure over one period (Pa, positive into the body).
    shear_x, shear_y : ndarray, optional
        ``(nx, ny)`` shear tractions on the body (Pa).

    Returns
    -------
    ndarray
        ``(6, nx, ny, len(z))`` stress (Pa), components
        :data:`solver.numerics.tensor.COMPONENTS`.
    """
    nx, ny = pressure.shape
    zero = np.zeros_like(pressure)
    fields = [pressure, zero if shear_x is None else shear_x, zero if shear_y is None else shear_y]
    p, qx, qy = (np.fft.rfft2(f) for f in fields)
    kx = 2.0 * np.pi * np.fft.fftfreq(nx, size[0] / nx)[:, None]
    ky = 2.0 * np.pi * np.fft.rfftfreq(ny, size[1] / ny)[None, :]
    k = np.hypot(kx, ky)
    safe = np.where(k > 0.0, k, 1.0)
    n1, n2 = kx / safe, ky / safe
    qn, qt = n1 * qx + n2 * qy, -n2 * qx + n1 * qy
    mean = sum(
        uniform_traction_stress(name, nu) * f.mean()
        for name, f in zip(TRACTIONS, fields, strict=True)
    )
    out = np.empty((6, nx, ny, len(z)))
    for j, depth in enumerate(np.asarray(z, dtype=float)):
        e, kz = np.exp(-k * depth), k * depth
        nn = (-p * (1.0 - kz) + 1j * qn * (2.0 - kz)) * e
        zz = (-p * (1.0 + kz) + 1j * qn * kz) * e
        nz = (1j * p * kz - qn * (1.0 - kz)) * e
        tt, tz, nt = nu * (nn + zz), -qt * e, 1j * qt * e
        parts = (
            n1 * n1 * nn - 2.0 * n1 * n2 * nt + n2 * n2 * tt,
            n2 * n2 * nn + 2.0 * n1 * n2 * nt + n1 * n1 * tt,
            zz,
            n2 * nz + n1 * tz,
            n1 * nz - n2 * tz,
            n1 * n2 * (nn - tt) + (n1 * n1 - n2 * n2) * nt,
        )
        for c, part in enumerate(parts):
            part[0, 0] = 0.0
            out[c, :, :, j] = np.fft.irfft2(part, s=(nx, ny)) + mean[c]
    return out
