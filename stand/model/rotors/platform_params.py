"""Paper 004 (Drach): the parameters of the suspended platform-rotor system
(papers digest sections 3.1, 3.3-3.4, 3.8).

* :class:`Hanger` -- one elastic rod/spring with a viscous damper along it (3.4),
  (20), (37);
* :func:`quadrifilar_hangers` -- four rods consistent with the pendulum
  geometry of Fig. 2 (digest 3.3);
* :class:`PlatformParams` -- masses, inertias, linkage geometry (13), (19),
  diaphragm (25), spin-axis point D (31), eccentricity; validated on
  construction (every error names the parameter, value and unit), including
  the linkage singularity ``b h + z_k (S - b) = 0`` (digest 3.8, 5.4 (vii));
* :func:`default_params` -- an ASSUMED plausible set (the paper gives no numbers).

The equations of motion built from them are in :mod:`stand.model.rotors.platform`,
which re-exports these names.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional

import numpy as np

from stand.model.rotors._build import check

__all__ = ["Hanger", "quadrifilar_hangers", "PlatformParams", "default_params", "default_hangers",
           "scene_params", "SCENE_KEYS"]


def _store_checked(obj, prefix: str, rule: str, *specs) -> None:
    """Check the attributes ``(name, unit)`` of a frozen dataclass against ``rule``
    (:func:`stand.model.rotors._build.check`) and store them as floats; messages name
    ``prefix + name``."""
    for name, unit in specs:
        object.__setattr__(obj, name, check(prefix + name, getattr(obj, name), unit, rule))


@dataclass(frozen=True)
class Hanger:
    """One elastic suspension rod/spring with a viscous damper along it (3.4).

    Attributes
    ----------
    x, y, z : float
        Attachment point on the platform at rest, in the frame XYZ with origin at
        the platform's centre of inertia O [m] (paper: x_i, y_i, z_i).
    length : float
        Rod length at rest l_i [m].
    phi1 : float
        Inclination of the rod from the vertical phi_1 [rad] (20).
    phi2 : float
        Azimuth phi_2i [rad]: angle from +X to the horizontal projection of the
        direction from the attachment point up to the housing pivot, measured
        clockwise seen from above (20).  The rod vector (pivot -> attachment) is
        ``(l_ix, l_iy, l_iz) = l (-sin phi1 cos phi2, sin phi1 sin phi2, -cos phi1)``.
    c : float
        Axial stiffness c_1i [N/m] (0 for a pure damper).
    damping : float
        Viscous coefficient h_i of the damper along the rod [N s/m] (37), (41).
    """

    x: float
    y: float
    z: float
    length: float
    phi1: float = 0.0
    phi2: float = 0.0
    c: float = 0.0
    damping: float = 0.0

    def __post_init__(self):
        _store_checked(self, "Hanger.", "finite",
                       ("x", "m"), ("y", "m"), ("z", "m"), ("phi1", "rad"), ("phi2", "rad"))
        _store_checked(self, "Hanger.", "positive", ("length", "m"))
        _store_checked(self, "Hanger.", "nonnegative", ("c", "N/m"), ("damping", "N s/m"))

    def rod_vector(self) -> np.ndarray:
        """``(l_ix, l_iy, l_iz)`` [m], eq. (20)."""
        s1, c1 = math.sin(self.phi1), math.cos(self.phi1)
        return self.length * np.array([-s1 * math.cos(self.phi2), s1 * math.sin(self.phi2), -c1])


def quadrifilar_hangers(S1: float, S2: float, b1: float, b2: float, h: float, z_k: float,
                        c: float, damping: float = 0.0) -> tuple:
    """Four rods consistent with the pendulum geometry (Fig. 2, digest 3.3).

    Housing pivots at ``(+-S1/2, +-S2/2, -z_k + h)``, platform attachment points
    at ``(+-b1/2, +-b2/2, -z_k)`` (the platform link AB lies z_k below O, (13)).

    Parameters
    ----------
    S1, S2 : float
        Pivot spacings in the XOZ / YOZ projections [m].
    b1, b2 : float
        Attachment spacings on the platform [m].
    h : float
        Suspension height [m].
    z_k : float
        Height of O above the platform link AB [m].
    c : float
        Axial stiffness of each rod [N/m].
    damping : float
        Viscous coefficient of each rod's damper [N s/m].
    """
    for k, v in (("S1", S1), ("S2", S2), ("b1", b1), ("b2", b2), ("h", h)):
        check(k, v, "m", "positive")
    out = []
    for sx in (1.0, -1.0):
        for sy in (1.0, -1.0):
            lx, ly = sx * (b1 - S1) / 2.0, sy * (b2 - S2) / 2.0      # pivot -> attachment
            L = math.sqrt(lx * lx + ly * ly + h * h)
            ph = math.hypot(lx, ly)
            phi1 = math.atan2(ph, h)
            phi2 = math.atan2(ly, -lx) if ph > 0 else 0.0    # l_ix = -ph cos, l_iy = ph sin
            out.append(Hanger(sx * b1 / 2.0, sy * b2 / 2.0, -z_k, L, phi1, phi2, c, damping))
    return tuple(out)


@dataclass(frozen=True)
class PlatformParams:
    """Physical parameters of the platform-rotor system (digest 3.1, SI units).

    Attributes
    ----------
    m : float
        Total mass of the oscillating system (platform + rotor) [kg].
    m2 : float
        Rotor mass m_2 [kg].
    I_a1, I_b1, I_c1 : float
        Moments of inertia of the oscillating system about the axes a_1, b_1, c_1
        through O (parallel to X, Y, Z at rest) [kg m^2].
    I_p : float
        Polar moment of the rotor about its spin axis I^(2)_c1 [kg m^2].
    g : float
        Gravity [m/s^2].
    S1, S2 : float
        Housing pivot spacing in the XOZ / YOZ projections [m] (Fig. 2).
    b1, b2 : float
        Platform attachment spacing in those projections [m].
    h : float
        Suspension height h [m] (h_i = l_i cos phi_0).
    z_k : float
        z_k = |OK|, height of O above the platform link AB [m] (13).
    hangers : tuple of Hanger
        Rods/springs/dampers (any number; see :func:`quadrifilar_hangers`).
    c2x, c2y, c2z : float
        Sealing-diaphragm stiffnesses along X, Y, Z [N/m].
    x_M, y_M, z_M : float
        Diaphragm attachment point M [m].
    x_D, y_D, z_D : float
        Point D of the spin axis (foot of the perpendicular from the rotor's
        centre of mass) [m]; the spin axis is the vertical through (x_D, y_D).
    e : float
        Rotor eccentricity [m]; the unbalance is ``s = m2 e`` [kg m].
    z_B : float or None
        Height of the balancer plane on the spin axis [m] (None: z_D).
    """

    m: float
    m2: float
    I_a1: float
    I_b1: float
    I_c1: float
    I_p: float
    S1: float
    S2: float
    b1: float
    b2: float
    h: float
    z_k: float
    hangers: tuple = ()
    c2x: float = 0.0
    c2y: float = 0.0
    c2z: float = 0.0
    x_M: float = 0.0
    y_M: float = 0.0
    z_M: float = 0.0
    x_D: float = 0.0
    y_D: float = 0.0
    z_D: float = 0.0
    e: float = 0.0
    g: float = 9.81
    z_B: Optional[float] = None

    def __post_init__(self):
        _store_checked(self, "", "positive", ("m", "kg"), ("I_a1", "kg m^2"), ("I_b1", "kg m^2"),
                       ("I_c1", "kg m^2"), ("S1", "m"), ("S2", "m"), ("b1", "m"), ("b2", "m"),
                       ("h", "m"))
        _store_checked(self, "", "nonnegative", ("m2", "kg"), ("I_p", "kg m^2"), ("g", "m/s^2"),
                       ("e", "m"), ("c2x", "N/m"), ("c2y", "N/m"), ("c2z", "N/m"))
        _store_checked(self, "", "finite", ("z_k", "m"), ("x_M", "m"), ("y_M", "m"), ("z_M", "m"),
                       ("x_D", "m"), ("y_D", "m"), ("z_D", "m"))
        if self.z_B is not None:
            _store_checked(self, "", "finite", ("z_B", "m"))
        if self.m2 > self.m:
            raise ValueError(f"m2 = {self.m2!r} [kg] must not exceed the total mass m = {self.m!r} [kg]")
        hs = tuple(self.hangers)
        for i, hg in enumerate(hs):
            if not isinstance(hg, Hanger):
                raise ValueError(f"hangers[{i}] = {hg!r} must be a Hanger")
        object.__setattr__(self, "hangers", hs)
        # geometric singularity of the linkage (digest 3.8, 5.4 (vii))
        for j, (S, b) in enumerate(((self.S1, self.b1), (self.S2, self.b2)), start=1):
            den = b * self.h + self.z_k * (S - b)
            if abs(den) <= 1e-9 * b * self.h:
                raise ValueError(f"b{j}*h + z_k*(S{j} - b{j}) = {den!r} [m^2] is (nearly) zero: "
                                 f"the pendulum linkage is singular (d_{j + 2} infinite)")

    @property
    def s(self) -> float:
        """Unbalance ``m2 e`` [kg m]."""
        return self.m2 * self.e

    @property
    def balancer_z(self) -> float:
        """Height of the balancer plane [m] (z_B, default z_D)."""
        return self.z_D if self.z_B is None else self.z_B


def default_hangers(S1: float = 1.0, S2: float = 1.0, b1: float = 0.8, b2: float = 0.8,
                    h: float = 2.0, z_k: float = 0.3, rod_stiffness: float = 3.75e6,
                    rod_damping: float = 750.0, rim_damping: float = 10.0,
                    rim_radius: float = 0.4, rim_length: float = 0.5) -> tuple:
    """The hangers of :func:`default_params` for any linkage geometry: the four rods of
    :func:`quadrifilar_hangers` (each ``rod_stiffness`` [N/m], ``rod_damping`` [N s/m])
    and four horizontal pure dampers (``rim_damping`` [N s/m] each, rods of
    ``rim_length`` [m]) at the platform rim, ``rim_radius`` [m] from the axis at z = -z_k,
    for the pendulum and torsion modes (``rim_damping = 0`` leaves them out)."""
    rods = quadrifilar_hangers(S1, S2, b1, b2, h, z_k, c=rod_stiffness, damping=rod_damping)
    check("rim_damping", rim_damping, "N s/m", "nonnegative")
    if rim_damping == 0:
        return rods
    r = check("rim_radius", rim_radius, "m", "positive")
    q = 0.5 * math.pi
    return rods + (
        Hanger(0.0, r, -z_k, rim_length, q, 0.0, 0.0, rim_damping),
        Hanger(0.0, -r, -z_k, rim_length, q, 0.0, 0.0, rim_damping),
        Hanger(r, 0.0, -z_k, rim_length, q, q, 0.0, rim_damping),
        Hanger(-r, 0.0, -z_k, rim_length, q, q, 0.0, rim_damping),
    )


#: the scene-file keys of the platform (:func:`scene_params`): the PlatformParams fields
#: other than ``hangers``, then the arguments of :func:`default_hangers`
SCENE_KEYS = ("m", "m2", "I_a1", "I_b1", "I_c1", "I_p", "S1", "S2", "b1", "b2", "h", "z_k",
              "c2x", "c2y", "c2z", "x_M", "y_M", "z_M", "x_D", "y_D", "z_D", "e", "g", "z_B",
              "rod_stiffness", "rod_damping", "rim_damping", "rim_radius", "rim_length")


def scene_params(**overrides) -> PlatformParams:
    """:func:`default_params` with any of :data:`SCENE_KEYS` replaced (SI units; a value
    of None keeps the default).  The hangers are rebuilt by :func:`default_hangers`
    from the (possibly changed) linkage geometry and rod/damper keys, so the defaults
    give exactly :func:`default_params`."""
    bad = sorted(set(overrides) - set(SCENE_KEYS))
    if bad:
        raise ValueError(f"unknown platform parameter(s) {', '.join(bad)}; valid: "
                         f"{', '.join(SCENE_KEYS)}")
    base = default_params()
    kw = {k: getattr(base, k) for k in SCENE_KEYS[:24]}
    hk = dict(rod_stiffness=3.75e6, rod_damping=750.0, rim_damping=10.0, rim_radius=0.4,
              rim_length=0.5)
    for k, v in overrides.items():
        if v is None:
            continue
        (hk if k in hk else kw)[k] = v
    hangers = default_hangers(kw["S1"], kw["S2"], kw["b1"], kw["b2"], kw["h"], kw["z_k"], **hk)
    return PlatformParams(hangers=hangers, **kw)


def default_params() -> PlatformParams:
    """An ASSUMED plausible parameter set (paper 004 gives no numbers, digest 3.8).

    A small suspended centrifuge: m = 60 kg (rotor m2 = 15 kg, I_p = 0.5 kg m^2),
    four slightly inclined rods (S = 1.0 m, b = 0.8 m, h = 2.0 m, z_k = 0.3 m;
    each 3.75e6 N/m, 750 N s/m), four horizontal 10 N s/m dampers at the
    platform rim (0.4 m from the axis, z = -z_k) for the pendulum and torsion
    modes (damping ratio ~0.05-0.1), a soft diaphragm (200/200/1000 N/m) at
    M = (0, 0, 0.4) m, the spin axis offset x_D = 0.02 m, y_D = -0.01 m from O,
    z_D = 0.35 m, eccentricity e = 0.5 mm.  Pendulum modes ~2-3 rad/s, axial
    (bounce) mode ~500 rad/s (digest 5.2 item 5: the stiff case).
    """
    S, b, h, zk = 1.0, 0.8, 2.0, 0.3
    return PlatformParams(
        m=60.0, m2=15.0, I_a1=2.5, I_b1=2.5, I_c1=3.0, I_p=0.5,
        S1=S, S2=S, b1=b, b2=b, h=h, z_k=zk,
        # four rods, and horizontal pure dampers (c = 0) for the pendulum and torsion modes
        hangers=default_hangers(S, S, b, b, h, zk, rod_stiffness=3.75e6, rod_damping=750.0,
                                rim_damping=10.0, rim_radius=0.4, rim_length=0.5),
        c2x=200.0, c2y=200.0, c2z=1000.0, x_M=0.0, y_M=0.0, z_M=0.4,
        x_D=0.02, y_D=-0.01, z_D=0.35, e=5e-4, g=9.81,
    )
