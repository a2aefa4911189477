"""Rigid rotor in spatial motion: book sections 2.7.1-2.7.3 and paper 003 (model M2).

Coordinates ``q = (x, y, alpha, beta)``: the translation of the centre of mass
[m] and the Resal tilts [rad] (digest ch2_ch3 section 2.6).  The equations are
the book's (2.118) with the gyroscopic terms of (2.122)::

    M x''                     + k_1j q_j = s w^2 cos(w t)
    M y''                     + k_2j q_j = s w^2 sin(w t)
    A alpha'' + C w beta'     + k_3j q_j = -s a w^2 sin(w t)
    A beta''  - C w alpha'    + k_4j q_j =  s a w^2 cos(w t)

i.e. ``G = [[0,0,0,0],[0,0,0,0],[0,0,0,C],[0,0,-C,0]]`` per unit spin.  A point
of the axis at axial distance ``a`` from the centre of mass moves as (2.131)
``x_B = x + a beta``, ``y_B = y - a alpha``, so its plane map is
``T(a) = [[1, 0, 0, a], [0, 1, -a, 0]]``; the unbalance forcing of
:class:`stand.model.rotors.LinearRotor` (``T^T s w^2 (cos, sin)``) is then exactly the
right-hand side above (the factor ``a`` in the moment equations is the one
missing from the printed (2.119)-(2.120); digest section 2.6).

Axial coordinate convention: see :mod:`stand.model.rotors.spatial_supports` (Table
2.4 puts support 1 at ``zeta = +l1``, paper 003 at ``zeta = -l1``).

Contents (every name is importable from this module)
----------------------------------------------------
* :mod:`.spatial_supports`: :class:`SupportStiffness` with the forms (2.118),
  (2.119), (2.121)/(2.122), the Table 2.4 schemes (:func:`two_elastic_supports`,
  :func:`isotropic_supports`, :func:`cantilever_disk`, :func:`disk_on_hinged_shaft`,
  :func:`disk_on_clamped_shaft` with the corrected ``c33 = 4EJ(l1+l2)/(l1 l2)``)
  and :func:`plane_map` (2.131).
* This module: :func:`spatial_rotor`, the :class:`LinearRotor` of (2.118)/(2.122);
  :func:`static_unbalance`, :func:`couple_unbalance`; the scene-file builder
  :func:`spatial_scene_rotor`.
* :mod:`stand.theories.spatial_criterion` (theory), closed forms of 2.7.2/2.7.3: ``delta`` (2.126),
  :func:`r_ac` (2.133), :func:`high_speed_limit` (2.134)-(2.137),
  :func:`auxiliary_speed` (2.138), :func:`frequency_polynomial` /
  :func:`frequency_roots` (2.139)-(2.141), :func:`critical_speeds`
  (2.142)-(2.153), :func:`symmetric_critical_speeds` (2.155)-(2.159),
  :func:`two_balancer_ranges` (2.160).
* :mod:`.spatial_two_support`, paper 003 (M2): :func:`two_support_rotor` ->
  :class:`TwoSupportRotor` with (14), (31)-(34), (17)-(19), (26), (36)-(41), (43)
  and the compact criterion "K_xi(w) and K_eta(w) negative definite" (papers
  digest sections 2.3-2.6).
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np

from stand.model.rotors._build import gyroscopic_pair, nonnegative, positive
from stand.model.rotors.spatial_supports import (COORDS, SupportStiffness, cantilever_disk, disk_on_clamped_shaft,
                               disk_on_hinged_shaft, isotropic_supports, numbered_planes, plane_map,
                               two_elastic_supports)
from stand.model.rotors.spatial_two_support import TwoSupportRotor, two_support_rotor
from stand.model.rotors.structure import LinearRotor

__all__ = [
    "SupportStiffness", "two_elastic_supports", "isotropic_supports", "cantilever_disk",
    "disk_on_hinged_shaft", "disk_on_clamped_shaft", "plane_map", "spatial_rotor",
    "static_unbalance", "couple_unbalance", "TwoSupportRotor", "two_support_rotor",
]


def static_unbalance(s: float, angle: float = 0.0, a: float = 0.0):
    """A static unbalance ``s`` [kg m] at ``angle`` [rad] in the plane ``a`` [m]
    (default: the centre-of-mass plane), as a list of ``(a, s, angle)``."""
    return [(float(a), nonnegative("s", s, "kg m"), float(angle))]


def couple_unbalance(s: float, a1: float, a2: float, angle: float = 0.0):
    """A couple unbalance: ``s`` [kg m] at ``angle`` in plane ``a1`` and ``s`` at
    ``angle + pi`` in plane ``a2`` [m] (moment ``s (a1 - a2)`` [kg m^2], no static part)."""
    s = nonnegative("s", s, "kg m")
    if float(a1) == float(a2):
        raise ValueError(f"couple unbalance needs two different planes, got a1 = a2 = {a1!r} m")
    return [(float(a1), s, float(angle)), (float(a2), s, float(angle) + math.pi)]


def spatial_rotor(M: float, A: float, C: float, supports: SupportStiffness,
                  balancers=(0.0,), unbalances=(), damping=None,
                  name: str = "spatial_rigid") -> LinearRotor:
    """Rigid rotor in spatial motion, (2.118) with the gyroscopic terms of (2.122).

    Parameters
    ----------
    M : float  mass [kg];  A : float  transverse central moment [kg m^2];
    C : float  polar moment [kg m^2]
    supports : SupportStiffness  (isotropic (2.122), principal (2.119) or general (2.118))
    balancers : float or sequence of float
        Axial positions ``a`` [m] of the balancer planes from the centre of
        mass (one or two), named ``"balancer1"``, ``"balancer2"``, ...
    unbalances : sequence of (a [m], s [kg m], angle [rad])
        Unbalances, each in its own plane ``"unbalance1"``, ...; see
        :func:`static_unbalance`, :func:`couple_unbalance`.
    damping : SupportStiffness or (4, 4) array, optional
        Viscous damping matrix [N s/m, N s/rad, N m s/rad] (default none, as in the book).

    Returns
    -------
    LinearRotor
        Coordinates (x, y, alpha, beta); planes ``"com"`` (a = 0), the balancer
        and unbalance planes.
    """
    M = positive("M", M, "kg")
    A = positive("A", A, "kg m^2")
    C = nonnegative("C", C, "kg m^2")
    if not isinstance(supports, SupportStiffness):
        supports = SupportStiffness.general(supports)
    if damping is None:
        D = np.zeros((4, 4))
    else:
        D = (damping.matrix if isinstance(damping, SupportStiffness)
             else SupportStiffness.general(damping).matrix)
    planes = {"com": plane_map(0.0)}
    numbered, ubs = numbered_planes(balancers, unbalances)
    planes.update(numbered)
    return LinearRotor(name=name, coords=COORDS, M=np.diag([M, M, A, A]),
                       G=gyroscopic_pair(4, 2, 3, C), D=D,
                       K=supports.matrix, planes=planes, unbalances=ubs,
                       source=f"Filimonikhin 2004 sec. 2.7, (2.118)/(2.122); supports {supports.source}")


def spatial_scene_rotor(mass, A, C, l1, l2, c1, c2=None, balancer_positions=(0.0,),
                        unbalance=0.0, unbalance_position=0.0, unbalance_angle=0.0,
                        couple_unbalance=0.0, couple_positions=(0.0, 0.0),
                        stiffness_damping=0.0, screen_positions=(),
                        axial_convention: str = "book") -> LinearRotor:
    """Scene-file form of :func:`spatial_rotor` (plain numbers only): a rigid
    rotor on two isotropic supports (Table 2.4 row 1 with c1 = c2 left, c3 = c4
    right; supports at distances l1, l2 [m] from the centre of mass).

    Parameters
    ----------
    mass : float  M [kg];  A, C : float  transverse and polar moments [kg m^2]
    l1, l2 : float  support distances [m];  c1, c2 : float  support stiffnesses [N/m]
    balancer_positions : list of float  axial positions a [m] of the balancer
        planes ("balancer1", "balancer2", ...)
    unbalance, unbalance_position, unbalance_angle : static unbalance s [kg m]
        at a [m], angle [rad] (plane "unbalance1")
    couple_unbalance : float  s [kg m] of a couple (s at couple_positions[0],
        -s at couple_positions[1]) [m]
    stiffness_damping : float  beta [s]: damping matrix beta K (stiffness-proportional)
    axial_convention : "book" or "paper003"
        Where the supports sit on the axial coordinate zeta (from the centre of mass,
        the coordinate of every plane position above): ``"book"`` (default, Table 2.4)
        support 1 (c1) at ``zeta = +l1`` and support 2 (c2) at ``-l2``; ``"paper003"``
        (paper 003 (12), (14)) support 1 at ``-l1`` and support 2 at ``+l2``.  The
        same rotor is ``paper003`` with (l1, l2, c1, c2) = ``book`` with (l2, l1, c2, c1).
    screen_positions : list of float  axial positions [m] of laser screens: the
        beam along the shaft axis hits a screen at distance y where the axis
        line is, x + y beta, y - y alpha (2.131): planes "screen1", "screen2", ...
        (two screens give both correction planes, (4.2)-(4.3), :mod:`dsp.two_plane`)
    """
    c2 = c1 if c2 is None else c2
    if axial_convention == "book":
        sup = isotropic_supports(l1, l2, c1, c2)
    elif axial_convention == "paper003":       # support 1 at -l1, support 2 at +l2
        sup = isotropic_supports(l2, l1, c2, c1)
        sup = dataclasses.replace(sup, source="paper 003 (12), (14): support 1 at -l1, "
                                              "support 2 at +l2")
    else:
        raise ValueError(f'axial_convention = {axial_convention!r}: must be "book" (Table 2.4, '
                         'support 1 at zeta = +l1) or "paper003" (support 1 at zeta = -l1)')
    unb = []
    if unbalance:
        unb += static_unbalance(unbalance, unbalance_angle, unbalance_position)
    if couple_unbalance:
        unb += _couple(couple_unbalance, couple_positions[0], couple_positions[1], unbalance_angle)
    beta = nonnegative("stiffness_damping", stiffness_damping, "s")
    damping = beta * np.asarray(sup.matrix, float) if beta else None
    bp = balancer_positions if isinstance(balancer_positions, (list, tuple)) else (balancer_positions,)
    rot = spatial_rotor(mass, A, C, sup, balancers=tuple(float(a) for a in bp), unbalances=unb,
                        damping=damping)
    sp = screen_positions if isinstance(screen_positions, (list, tuple)) else (screen_positions,)
    if sp:
        planes = dict(rot.planes)
        for k, y in enumerate(sp, start=1):
            planes[f"screen{k}"] = plane_map(float(y))
        rot = dataclasses.replace(rot, planes=planes)
    return rot


_couple = couple_unbalance   # (the scene wrapper's parameter shadows the name)
