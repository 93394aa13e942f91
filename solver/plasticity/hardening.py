"""Hardening laws of an elastic-plastic body: Swift, linear, perfect, and a back stress.

The flow stress and its slope as functions of the equivalent plastic strain, and the largest
shear stress a law can carry; the return mapping (:mod:`.return_mapping`) integrates them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np

#: Swift's law counts plastic strain in micro-strain: sigma_Y = B (C + 1e6 e_p)^n, so C is the
#: pre-strain in micro-strain (the paper's C = 20 is 2e-5) and B (Pa), C, n are kept as written.
SWIFT_STRAIN_UNIT = 1e6


@dataclass(frozen=True)
class Hardening:
    """Hardening law of an elastic-plastic body: isotropic, optionally with a back stress.

    Parameters
    ----------
    law : {"swift", "linear", "perfect"}
        ``swift``: sigma_Y(e_p) = B (C + 1e6 e_p)^n (e_p in micro-strain inside the bracket,
        :data:`SWIFT_STRAIN_UNIT`);  ``linear``: sigma_Y0 + H e_p;
        ``perfect``: sigma_Y0.
    B : float
        Swift coefficient (Pa).
    C : float
        Swift offset (micro-strain, dimensionless).
    n : float
        Swift exponent (dimensionless).
    yield_stress : float
        Initial yield stress sigma_Y0 (Pa) for ``linear`` and ``perfect``.
    modulus : float
        Linear hardening modulus H (Pa) for ``linear``.
    kinematic_modulus : float
        Kinematic hardening modulus C_k (Pa) of the back stress (0: isotropic hardening only).
    kinematic_recall : float
        Armstrong-Frederick recall gamma (dimensionless, 0: linear Prager-Ziegler).  The back
        stress obeys ``d alpha = (2/3) C_k d eps_p - gamma alpha dp`` and saturates at
        ``C_k / gamma`` (uniaxial); the yield surface is ``sigma_eq(s - alpha) = sigma_Y(e_p)``.
    """

    law: Literal["swift", "linear", "perfect"]
    B: float = 0.0
    C: float = 0.0
    n: float = 0.0
    yield_stress: float = 0.0
    modulus: float = 0.0
    kinematic_modulus: float = 0.0
    kinematic_recall: float = 0.0

    @property
    def kinematic(self) -> bool:
        """True with a back stress (kinematic hardening)."""
        return self.kinematic_modulus > 0.0

    def flow_stress(self, plastic_strain):
        """Yield stress sigma_Y (Pa) at an equivalent plastic strain (float or array, >= 0)."""
        e = np.asarray(plastic_strain, dtype=float)
        if self.law == "swift":
            return self.B * (self.C + SWIFT_STRAIN_UNIT * e) ** self.n
        if self.law == "linear":
            return self.yield_stress + self.modulus * e
        return self.yield_stress + 0.0 * e

    def slope(self, plastic_strain):
        """Hardening modulus d sigma_Y / d e_p (Pa) at an equivalent plastic strain.

        Swift's slope at e_p = 0 is ``B n 1e6 C^(n-1)``: about 8000 GPa for the paper's steel,
        40 times the elastic shear stiffness, which is why the return mapping brackets its root.
        """
        e = np.asarray(plastic_strain, dtype=float)
        if self.law == "swift":
            unit = SWIFT_STRAIN_UNIT
            return self.B * self.n * unit * (self.C + unit * e) ** (self.n - 1.0)
        if self.law == "linear":
            return self.modulus + 0.0 * e
        return 0.0 * e

    @property
    def shear_limit(self) -> float:
        """The largest shear stress (Pa) the material can carry at any plastic strain.

        Von Mises bounds a shear stress tau by sqrt(3) |tau| <= sigma_eq, so a perfectly
        plastic body carries at most k = sigma_Y0 / sqrt 3, and one with a saturating
        (Armstrong-Frederick) back stress (sigma_Y0 + C_k / gamma) / sqrt 3; inf where the
        flow stress or the back stress grows without bound (linear, Swift, Prager).  A surface
        shear traction above it has no stress field in equilibrium with it inside the yield
        surface: at the surface sigma_xz = q_x and sigma_yz = q_y.
        """
        if self.law != "perfect" or (self.kinematic and self.kinematic_recall == 0.0):
            return math.inf
        saturated = self.kinematic_modulus / self.kinematic_recall if self.kinematic else 0.0
        return (self.yield_stress + saturated) / math.sqrt(3.0)

    @property
    def initial_yield_stress(self) -> float:
        """sigma_Y at zero plastic strain (Pa)."""
        return float(self.flow_stress(0.0))
