"""Structural part of the rotor: mass, damping, stiffness, unbalance forcing.

The planar rotor of the book's chapter 5 (section 5.1.1) and section 2.5.1:
the shaft point K moves in the plane of the balancer (the balancer-plane map
is the identity), supports are linear viscoelastic, possibly anisotropic
(5.1).  Weights (:mod:`stand.model.weights`) couple to the structure only through
the acceleration of K; the rotor-family issue adds other structures with the
same interface (mass M_Sigma, 2x2 damping D and stiffness K at the balancer
plane, unbalance M e at angle beta from the reference mark).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class PlanarStructure:
    """Planar rigid rotor on viscoelastic supports.

    Attributes
    ----------
    total_mass : float
        M_Sigma = M + sum m_j [kg] (the weights move with the shaft).
    damping : ndarray (2, 2)
        D [N*s/m] acting on (x', y').
    stiffness : ndarray (2, 2)
        K [N/m] acting on (x, y).
    unbalance : float
        M e [kg*m].
    unbalance_angle : float
        beta [rad] from the rotor's reference mark.
    rotor_inertia : float or None
        J_0 about the shaft axis [kg*m^2] (free rotor only).
    """

    total_mass: float
    damping: np.ndarray
    stiffness: np.ndarray
    unbalance: float
    unbalance_angle: float
    rotor_inertia: float | None

    @classmethod
    def from_scene(cls, scene) -> "PlanarStructure":
        """The structure of a planar scene (any object with the attributes of
        :class:`stand.scene.model.Scene`: ``supports``, ``rotor``, ``total_mass``)."""
        s = scene.supports
        return cls(
            total_mass=scene.total_mass,
            damping=np.diag([s.damping_x, s.damping_y]).astype(float),
            stiffness=np.diag([s.stiffness_x, s.stiffness_y]).astype(float),
            unbalance=scene.rotor.unbalance,
            unbalance_angle=scene.rotor.unbalance_angle,
            rotor_inertia=scene.rotor.inertia_about_shaft,
        )

    @property
    def natural_frequency(self) -> float:
        """omega_1 = sqrt(K_xx / M_Sigma) [rad/s] (5.12)."""
        return float(np.sqrt(self.stiffness[0, 0] / self.total_mass))
