"""Model 2.5.1 as a LinearRotor: planar rigid rotor on (an)isotropic supports.

Equation (2.22) with viscous damping: ``M x'' + d_x x' + c_x x = s w^2 cos wt``,
``M y'' + d_y y' + c_y y = s w^2 sin wt`` (X the softest axis).  The core
simulator (:mod:`stand.model.planar`) integrates the same model in its own compiled,
dimensionless form; ``tests/test_rotors_coupled.py`` checks that both agree.
Critical speeds (2.29): sqrt(c_min/M), sqrt((c_min + c_max)/(2M)), sqrt(c_max/M)
(the digest's correction of (2.28): no factor 2 in the denominator; signs unchanged).
"""
from __future__ import annotations

import math

import numpy as np

from stand.model.rotors._build import nonnegative, positive, transverse_gravity, weight_force
from stand.model.rotors.structure import LinearRotor, Unbalance

__all__ = ["planar_rotor", "planar_critical_speeds"]


def planar_rotor(mass, stiffness_x, stiffness_y=None, damping_x=0.0, damping_y=None,
                 unbalance=0.0, unbalance_angle=0.0, g=(0.0, 0.0)) -> LinearRotor:
    """Planar rotor (2.22) with damping.

    Parameters
    ----------
    mass : float  M [kg] (rotating parts without the correction weights)
    stiffness_x, stiffness_y : float  c_x, c_y [N/m] (default isotropic)
    damping_x, damping_y : float  [N s/m]
    unbalance : float  s = M e [kg m];  unbalance_angle : float [rad]
    g : (float, float)  transverse gravity [m/s^2] (zero for a vertical axis)
    """
    M = positive("mass", mass, "kg")
    cx = positive("stiffness_x", stiffness_x, "N/m")
    cy = cx if stiffness_y is None else positive("stiffness_y", stiffness_y, "N/m")
    dx = nonnegative("damping_x", damping_x, "N s/m")
    dy = dx if damping_y is None else nonnegative("damping_y", damping_y, "N s/m")
    g = transverse_gravity(g)
    centre = np.eye(2)                  # the rotor's centre (x, y): plane "balancer"
    return LinearRotor("planar", ("x [m]", "y [m]"), M * np.eye(2), np.zeros((2, 2)),
                       np.diag([dx, dy]), np.diag([cx, cy]), {"balancer": centre},
                       (Unbalance("balancer", float(unbalance), float(unbalance_angle)),),
                       gravity=weight_force(g, (M, centre)), gravity_plane=g, source="section 2.5.1, (2.22)")


def planar_critical_speeds(mass, stiffness_x, stiffness_y) -> tuple:
    """(2.29): the criterion's critical speeds [rad/s] (one for isotropic supports)."""
    cmin, cmax = sorted((float(stiffness_x), float(stiffness_y)))
    if cmin == cmax:
        return (math.sqrt(cmin / mass),)
    return (math.sqrt(cmin / mass), math.sqrt(0.5 * (cmin + cmax) / mass), math.sqrt(cmax / mass))
