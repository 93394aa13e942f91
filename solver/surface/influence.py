r"""Surface influence coefficients of a pair of elastic half-spaces (piecewise-constant tractions).

Conventions (DESIGN §3.2).  ``z`` points down, into body 2.  The tractions acting on body 2 are
``(q_x, q_y, p)``: ``p > 0`` pushes body 2 down (compression), ``q_x > 0`` pulls body 2's surface
in +x.  Body 1 carries the opposite tractions.  Displacements ``u`` are *relative*: body 2 minus
body 1, so the gap is ``h = h_i + u_z - delta`` and a slip increment is an increment of
``(u_x, u_y)``.  Describing body 1 in its own frame (x, -y, -z), with z into the body there, and
summing the Boussinesq/Cerruti point-force solutions of both bodies gives, for a unit point force
at the origin and a field point at (x, y), r^2 = x^2 + y^2::

    u_z from p  :  A / (pi r)
    u_x from q_x:  [A / r + C x^2 / r^3] / pi      u_y from q_y:  [A / r + C y^2 / r^3] / pi
    u_y from q_x = u_x from q_y:  C x y / (pi r^3)
    u_x from p  :  +beta A x / (pi r^2)            u_y from p  :  +beta A y / (pi r^2)
    u_z from q_x:  -beta A x / (pi r^2)            u_z from q_y:  -beta A y / (pi r^2)

with ``A = sum (1 - nu_i^2)/E_i``, ``C = sum (1 + nu_i) nu_i / E_i`` and Dundurs' ``beta`` (see
:mod:`solver.bodies.materials`).  The operator mapping (q_x, q_y, p) to (u_x, u_y, u_z) is symmetric
(``K_xz(d) = K_zx(-d)``), as the work ``q.u_t + p u_z`` requires.  With beta > 0 a pressure pulls
the relative surface outwards (body 1 more compressible, it moves in further).

The discrete kernels integrate these over a cell ``[-dx/2, dx/2] x [-dy/2, dy/2]`` centred on the
source.  Each integrand f has a primitive F with d^2F/(dx dy) = f, and the cell integral is the
alternating corner sum ``F(x+a, y+b) - F(x+a, y-b) - F(x-a, y+b) + F(x-a, y-b)``.  Terms of F
that depend on one variable only cancel in the sum, which gives the round-off-safe forms::

    1/r      : x asinh(y/|x|) + y asinh(x/|y|)          (Love 1929)
    x^2/r^3  : y asinh(x/|y|)
    y^2/r^3  : x asinh(y/|x|)
    x y/r^3  : -r
    x / r^2  : y ln r + x atan(y/x)
    y / r^2  : x ln r + y atan(x/y)
"""

from __future__ import annotations

import numpy as np

from ..bodies.materials import Pair

#: Names of the six independent kernel blocks: displacement component, traction component.
COMPONENTS = ("zz", "xx", "yy", "xy", "xp", "yp")


def _xasinh(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """X asinh(y/|x|), continuous with value 0 at x = 0."""
    ax = np.abs(x)
    with np.errstate(divide="ignore", invalid="ignore"):
        out = x * np.arcsinh(y / ax)
    return np.where(ax > 0.0, out, 0.0)


def _xatan(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """X atan(y/x), continuous with value 0 at x = 0."""
    with np.errstate(divide="ignore", invalid="ignore"):
        out = x * np.arctan(y / x)
    return np.where(x != 0.0, out, 0.0)


def _ylnr(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Y ln r, with value 0 at r = 0."""
    r2 = x * x + y * y
    with np.errstate(divide="ignore", invalid="ignore"):
        out = 0.5 * y * np.log(r2)
    return np.where(r2 > 0.0, out, 0.0)


#: The parts of the primitives, each a function of a corner's (x, y) (m).
_PARTS = {
    "x_asinh": lambda x, y: _xasinh(x, y),
    "y_asinh": lambda x, y: _xasinh(y, x),
    "minus_r": lambda x, y: -np.sqrt(x * x + y * y),
    "y_ln_r": lambda x, y: _ylnr(x, y),
    "x_atan": lambda x, y: _xatan(x, y),
    "x_ln_r": lambda x, y: _ylnr(y, x),
    "y_atan": lambda x, y: _xatan(y, x),
}
#: Each integrand's primitive: the sum of its parts (module docstring).
_PRIMITIVES = {
    "inv_r": ("x_asinh", "y_asinh"),
    "xx_r3": ("y_asinh",),
    "yy_r3": ("x_asinh",),
    "xy_r3": ("minus_r",),
    "x_r2": ("y_ln_r", "x_atan"),
    "y_r2": ("x_ln_r", "y_atan"),
}


def _corner_integrals(
    names: tuple[str, ...], x: np.ndarray, y: np.ndarray, dx: float, dy: float
) -> dict[str, np.ndarray]:
    """The alternating corner sums of the primitives ``names`` (of :data:`_PRIMITIVES`).

    One corner at a time: the parts the primitives share (1/r, x^2/r^3 and y^2/r^3 their
    asinh terms) are evaluated once per corner and dropped before the next, so the memory is
    the sums and one corner's parts; the sums are formed in the order of one integral alone.
    """
    a, b = 0.5 * dx, 0.5 * dy
    sums: dict[str, np.ndarray] = {}
    for corner, (cx, cy) in enumerate(((a, b), (a, -b), (-a, b), (-a, -b))):
        px, py = x + cx, y + cy
        parts: dict[str, np.ndarray] = {}
        for name in names:
            for part in _PRIMITIVES[name]:
                if part not in parts:
                    parts[part] = _PARTS[part](px, py)
            first, *rest = (parts[part] for part in _PRIMITIVES[name])
            value = first
            for other in rest:
                value = value + other
            if corner == 0:
                sums[name] = value
            elif corner < 3:
                sums[name] = sums[name] - value
            else:
                sums[name] = sums[name] + value
    return sums


def cell_integral(name: str, x: np.ndarray, y: np.ndarray, dx: float, dy: float) -> np.ndarray:
    """Integral of a point-force shape function over a cell centred at the origin.

    Parameters
    ----------
    name : {"inv_r", "xx_r3", "yy_r3", "xy_r3", "x_r2", "y_r2"}
        The integrand: 1/r, x^2/r^3, y^2/r^3, x y/r^3, x/r^2, y/r^2 (with x, y the offset of the
        field point from the source point).
    x, y : ndarray
        Field-point offsets from the cell centre (m).
    dx, dy : float
        Cell sizes (m).

    Returns
    -------
    ndarray
        The integral over the cell (units of the integrand times m^2).
    """
    return _corner_integrals((name,), x, y, dx, dy)[name]


def surface_kernels(
    pair: Pair,
    x: np.ndarray,
    y: np.ndarray,
    dx: float,
    dy: float,
    names: tuple[str, ...] = COMPONENTS,
) -> dict:
    """Relative-displacement influence coefficients of a uniformly loaded cell.

    Parameters
    ----------
    pair : Pair
        The two bodies.
    x, y : ndarray
        Offsets of the field-cell centre from the loaded-cell centre (m).
    dx, dy : float
        Cell sizes (m).
    names : tuple of str
        The blocks wanted (of :data:`COMPONENTS`; default all): only their integrals are
        computed, each corner term once; ``"xp"`` and ``"yp"`` are zero when Dundurs' beta is.

    Returns
    -------
    dict of ndarray
        Keys ``names``; ``"zz"`` is u_z per unit p, ``"xx"``/``"yy"``/``"xy"`` the
        tangential block (u_x per q_x, u_y per q_y, u_x per q_y = u_y per q_x), ``"xp"``/``"yp"``
        u_x/u_y per unit p.  u_z per unit q_x (q_y) at the same offset is ``-xp`` (``-yp``).
        Units: m/Pa.
    """
    a_c, c_c, beta = pair.compliance, pair.shear_coupling, pair.dundurs_beta
    wanted = {
        "zz": ("inv_r",), "xx": ("inv_r", "xx_r3"), "yy": ("inv_r", "yy_r3"), "xy": ("xy_r3",),
        "xp": ("x_r2",) if beta else (), "yp": ("y_r2",) if beta else (),
    }  # fmt: skip
    integrals = tuple(dict.fromkeys(i for name in names for i in wanted[name]))
    cell = _corner_integrals(integrals, x, y, dx, dy)
    inv_r = cell.get("inv_r")
    blocks = {
        "zz": lambda: a_c / np.pi * inv_r,
        "xx": lambda: (a_c * inv_r + c_c * cell["xx_r3"]) / np.pi,
        "yy": lambda: (a_c * inv_r + c_c * cell["yy_r3"]) / np.pi,
        "xy": lambda: c_c / np.pi * cell["xy_r3"],
        "xp": lambda: beta * a_c / np.pi * cell["x_r2"] if beta else np.zeros(np.shape(x)),
        "yp": lambda: beta * a_c / np.pi * cell["y_r2"] if beta else np.zeros(np.shape(x)),
    }
    return {name: blocks[name]() for name in names}


def point_kernels(pair: Pair, x: np.ndarray, y: np.ndarray) -> dict:
    """Point-force relative displacements (m/N), the integrands of :func:`surface_kernels`."""
    a_c, c_c, beta = pair.compliance, pair.shear_coupling, pair.dundurs_beta
    r = np.hypot(x, y)
    return {
        "zz": a_c / (np.pi * r),
        "xx": (a_c / r + c_c * x * x / r**3) / np.pi,
        "yy": (a_c / r + c_c * y * y / r**3) / np.pi,
        "xy": c_c * x * y / (np.pi * r**3),
        "xp": beta * a_c * x / (np.pi * r * r),
        "yp": beta * a_c * y / (np.pi * r * r),
    }
