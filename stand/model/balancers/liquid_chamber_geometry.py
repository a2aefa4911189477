"""Liquid chamber balancer (thesis 002): fill geometry, free surface, liquid centroid.

Part of :mod:`stand.model.balancers.liquid_chamber` (model, corrections and
validity conventions are described there).  The cylindrical approximation
``r = sqrt(R^2 - V/(pi h))`` (App. B step 2.3, l.1787) with the paraboloid
free surface of l.662-666 as a check, the liquid centre of mass of l.668
(valid under the sufficiency condition (3.4) ``f <= R - r``) and the system
unbalance (2.4).  Also the two conventions every part of the chamber model
shares: standard gravity :data:`G_STANDARD` and the ``(valid, flags)`` pair of
the result objects.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional, Tuple

import numpy as np

from stand.model.balancers._params import THESIS

__all__ = [
    "G_STANDARD", "FillGeometry", "LiquidCentroid", "fill_geometry", "free_surface_height",
    "liquid_centroid", "total_unbalance",
]


#: standard gravity [m/s^2]
G_STANDARD = 9.80665


def _result_flags(flags) -> Tuple[bool, Tuple[str, ...]]:
    """``(valid, flags)`` of a result: valid when no flag was raised."""
    flags = tuple(flags)
    return (len(flags) == 0, flags)


# --------------------------------------------------------------------------- fill geometry
@dataclass(frozen=True)
class FillGeometry:
    """Chamber fill (cylindrical approximation, l.1787, plus paraboloid check).

    Attributes
    ----------
    r : float
        Free-surface radius [m] of the cylindrical approximation (= the rms
        radius of the paraboloid); NaN if the fill exceeds the chamber.
    layer : float
        ``R - r`` [m], layer thickness at the wall.
    chamber_volume : float
        ``pi R^2 h`` [m^3].
    fill_fraction : float
        ``V / (pi R^2 h)`` [-].
    r_bottom, r_top : float
        Paraboloid radii at the bottom and lid [m] (= ``r`` without gravity
        along the axis or if ``omega`` is not given); ``r_bottom`` NaN when
        the vertex is above the bottom.
    axial_gravity_term : float
        ``g h sin(Omega)/omega^2`` [m^2] (0 if omega not given).
    valid, flags
        Validity of the annular-layer model and the reasons when not.
    """

    r: float
    layer: float
    chamber_volume: float
    fill_fraction: float
    r_bottom: float
    r_top: float
    axial_gravity_term: float
    valid: bool
    flags: Tuple[str, ...]


def fill_geometry(R: float, h: float, V: float, omega: Optional[float] = None,
                  inclination: float = math.pi / 2, *, g: float = G_STANDARD,
                  gravity_tol: float = 0.1) -> FillGeometry:
    """Free-surface radius and layer of a liquid volume ``V`` in the chamber.

    ``r = sqrt(R^2 - V/(pi h))`` (App. B step 2.3).  With ``omega`` given the
    free surface is the paraboloid of l.662: ``r(z)^2 = r_b^2 + 2 g
    sin(Omega) z/omega^2``, with ``V = pi h (R^2 - r_b^2 - g h sin(Omega)/omega^2)``
    (digest section 2.3 addition); the cylindrical ``r`` is its rms radius.

    Parameters
    ----------
    R, h : float
        Chamber radius and height [m].
    V : float
        Liquid volume [m^3].
    omega : float, optional
        Spin speed [rad/s], for the paraboloid / gravity checks.
    inclination : float
        Shaft inclination to the horizontal [rad] (``pi/2``: vertical).
    g : float
        Gravity [m/s^2].
    gravity_tol : float
        Flag the unmodelled in-plane gravity when ``g cos(Omega)/(omega^2 R)``
        exceeds this.

    Returns
    -------
    FillGeometry
        Flags: fill exceeds the chamber; chamber full (no free surface, the
        liquid cannot move); no liquid; paraboloid vertex above the bottom
        (no annulus at the bottom); free surface meets the wall below the lid;
        in-plane gravity not negligible.
    """
    R, h, V = THESIS.each(("R", R, "m", "> 0"), ("h", h, "m", "> 0"), ("V", V, "m^3", ">= 0"))
    Vk = math.pi * R * R * h
    flags = []
    r2 = R * R - V / (math.pi * h)
    if r2 < 0:
        flags.append(f"fill exceeds the chamber: V = {V:.6g} m^3 > pi R^2 h = {Vk:.6g} m^3")
        r = float("nan")
    else:
        r = math.sqrt(r2)
        if r2 == 0.0:
            flags.append("chamber completely full: no free surface, the liquid cannot redistribute")
    if V == 0.0:
        flags.append("no liquid: V = 0 m^3")
    q = 0.0
    r_b = r_t = r
    if omega is not None and r2 >= 0:
        omega = THESIS.positive("omega", omega, "rad/s")
        q = g * h * math.sin(inclination) / omega ** 2
        rb2, rt2 = r2 - abs(q), r2 + abs(q)
        r_b = math.sqrt(rb2) if rb2 >= 0 else float("nan")
        r_t = math.sqrt(rt2)
        if rb2 < 0 and V > 0:
            flags.append(f"paraboloid vertex above the chamber bottom (g h sin(Omega)/omega^2 = {q:.3g} m^2 "
                         f"> r^2 = {r2:.3g} m^2): the liquid covers the bottom centre, not an annulus")
        if rt2 > R * R and V > 0:
            flags.append(f"free surface meets the wall below the lid (g h sin(Omega)/omega^2 = {q:.3g} m^2 "
                         f"> R^2 - r^2 = {R * R - r2:.3g} m^2): the liquid does not form a full-height annulus")
        inplane = g * abs(math.cos(inclination)) / (omega ** 2 * R)
        if inplane > gravity_tol:
            flags.append(f"in-plane gravity g cos(Omega)/(omega^2 R) = {inplane:.3g} > {gravity_tol}: "
                         "not modelled by the thesis")
    valid, flags = _result_flags(flags)
    return FillGeometry(r=r, layer=R - r, chamber_volume=Vk, fill_fraction=V / Vk, r_bottom=r_b,
                        r_top=r_t, axial_gravity_term=q, valid=valid, flags=flags)


def free_surface_height(x, f: float, omega: float, inclination: float = math.pi / 2, *,
                        g: float = G_STANDARD):
    """Height of the free surface above its vertex, ``z = omega^2 (x + f)^2/(2 g sin Omega)``.

    Integral of l.662 (``tan psi = omega^2 (x + f)/(g sin Omega)``): a
    parabola with its axis on the rotation axis ``O_1`` (x = -f).

    Parameters
    ----------
    x : float or array
        Coordinate from the chamber centre O along the deflection line [m].
    f : float
        Shaft deflection ``O_1 O`` [m].
    omega : float
        Spin [rad/s].
    inclination : float
        Shaft inclination to the horizontal [rad]; ``sin(Omega) = 0`` (horizontal
        shaft) has no axial gravity and the surface is a cylinder (``inf``
        returned away from the axis).

    Returns
    -------
    float or ndarray
        ``z`` [m].
    """
    omega = THESIS.positive("omega", omega, "rad/s")
    s = math.sin(inclination)
    x = np.asarray(x, dtype=float)
    with np.errstate(divide="ignore"):
        z = omega ** 2 * (x + f) ** 2 / (2 * g * s) if s != 0 else np.where(x + f == 0, 0.0, np.inf)
    return z if z.ndim else float(z)


# --------------------------------------------------------------------------- centroid
@dataclass(frozen=True)
class LiquidCentroid:
    """Liquid centre of mass in the chamber cross-section (l.668).

    Attributes
    ----------
    x_p : float
        Centroid offset from the chamber centre O [m], along ``O_1 -> O``
        (away from the rotation axis): ``r^2 f/(R^2 - r^2)``.
    area : float
        Liquid cross-section ``pi (R^2 - r^2)`` [m^2].
    first_moment : float
        ``area * x_p = pi r^2 f`` [m^3]; times ``rho h`` gives ``D`` [kg m].
    valid, flags
        Flag when the free-surface circle leaves the chamber (``f > R - r``,
        sufficiency condition (3.4) violated): the liquid is then a crescent
        and the formula no longer holds.
    """

    x_p: float
    area: float
    first_moment: float
    valid: bool
    flags: Tuple[str, ...]


def liquid_centroid(R: float, r: float, f: float, *, r_top: Optional[float] = None) -> LiquidCentroid:
    """Centroid of disk(R, centre O) minus disk(r, centre O_1 at distance ``f``), l.668.

    Parameters
    ----------
    R : float
        Chamber radius [m].
    r : float
        Free-surface radius [m] (cylindrical approximation, ``0 <= r < R``).
    f : float
        Offset ``|O_1 O|`` [m] (shaft deflection), ``>= 0``.
    r_top : float, optional
        Largest paraboloid radius [m]; the sufficiency check then uses
        ``R - r_top`` (every slice must be an annulus; the first moment is the
        cylindrical one exactly, see the module notes).

    Returns
    -------
    LiquidCentroid
    """
    R, r, f = THESIS.each(("R", R, "m", "> 0"), ("r", r, "m", ">= 0"), ("f", f, "m", ">= 0"))
    if r >= R:
        raise ValueError(f"r = {r!r} m is invalid: must be < R = {R!r} m (no liquid otherwise)")
    flags = []
    r_chk = r if r_top is None else max(r, float(r_top))
    if f > R - r_chk:
        flags.append(f"free surface leaves the chamber: f = {f:.4g} m > R - r = {R - r_chk:.4g} m "
                     "(sufficiency (3.4) violated, liquid is a crescent, not an annulus)")
    area = math.pi * (R * R - r * r)
    x_p = r * r * f / (R * R - r * r)
    valid, flags = _result_flags(flags)
    return LiquidCentroid(x_p=x_p, area=area, first_moment=math.pi * r * r * f, valid=valid, flags=flags)


def total_unbalance(e: float, k: float, alpha: float) -> Tuple[float, float]:
    """System CoM eccentricity and its angle, (2.4), l.724, l.728.

    Parameters
    ----------
    e : float
        Liquid CoM eccentricity ``D/(M + m)`` [m].
    k : float
        ``D0/D`` [-].
    alpha : float
        Angle of the liquid CoM from the rotor unbalance [rad].

    Returns
    -------
    (e_c, phi_c) : tuple of float
        ``e_c = e sqrt(1 + 2k cos(alpha) + k^2)`` [m] and ``phi_c`` [rad]
        with ``tan(phi_c) = sin(alpha)/(cos(alpha) + k)`` (quadrant by atan2).
    """
    e = THESIS.nonneg("e", e, "m")
    k = THESIS.nonneg("k", k, "-")
    e_c = e * math.sqrt(max(1 + 2 * k * math.cos(alpha) + k * k, 0.0))
    return e_c, math.atan2(math.sin(alpha), math.cos(alpha) + k)
