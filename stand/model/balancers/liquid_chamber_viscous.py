"""Liquid chamber balancer (thesis 002): equilibrium zones of a viscous liquid, (2.15).

Part of :mod:`stand.model.balancers.liquid_chamber`.  Darcy-Weisbach with the
laminar factor ``64/Re`` over an arc ``l = R xi`` bounds the angle at which a
viscous liquid can stop short of the balancing position:
``sin beta* = 8 pi nu R xi/(V omega)`` (l.951 rewritten consistently; App. D's
SINUS is dimensionally wrong), the wetted arc (digest section 4.7) and the
choice of the liquid with the narrowest zone (App. D).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Mapping, Optional, Tuple

from stand.model.balancers._params import THESIS
from stand.model.balancers.liquid_chamber_geometry import _result_flags

__all__ = [
    "ViscousZone", "viscous_zone", "in_equilibrium_zone", "wetted_arc", "select_liquid",
]


# --------------------------------------------------------------------------- viscous zones
@dataclass(frozen=True)
class ViscousZone:
    """Equilibrium zone of a viscous liquid, (2.15).

    Attributes
    ----------
    sin_beta_star : float
        ``8 pi nu R xi/(V omega)`` [-] (``xi`` in rad; = ``8 pi^2 mu R
        xi_deg/(180 m omega)`` of l.951).
    beta_star : float
        Half-width of the zone [rad] (NaN if ``sin_beta_star > 1``).
    tan_beta_max : float
        Bound of (2.15), ``sin b*/sqrt(1 - sin^2 b*)`` [-].
    residual_unbalance : float
        ``D sin(beta*)`` [kg m] if ``D`` was given (incomplete balancing,
        digest suggestion), else NaN.
    valid, flags
    """

    sin_beta_star: float
    beta_star: float
    tan_beta_max: float
    residual_unbalance: float
    valid: bool
    flags: Tuple[str, ...]


def viscous_zone(nu: float, R: float, V: float, omega: float, xi: float = 2 * math.pi,
                 D: Optional[float] = None) -> ViscousZone:
    """Equilibrium-zone half-width of a viscous liquid, l.951 / (2.15).

    Darcy-Weisbach with the laminar factor ``64/Re`` over an arc ``l = R xi``
    (digest section 2.7; the dimensionally consistent rewriting of l.951).

    Parameters
    ----------
    nu : float
        Kinematic viscosity [m^2/s].
    R : float
        Chamber radius [m].
    V : float
        Liquid volume [m^3].
    omega : float
        Spin [rad/s].
    xi : float
        Central angle of the arc of liquid motion [rad] (the thesis uses degrees).
    D : float, optional
        Liquid unbalance [kg m] for the residual ``D sin(beta*)``.

    Returns
    -------
    ViscousZone
        Flagged when ``sin beta* >= 1`` (friction exceeds the driving
        component everywhere: no equilibrium zone bound, the liquid does not
        settle -- outside the model).
    """
    nu, R, V, omega, xi = THESIS.each(("nu", nu, "m^2/s", ">= 0"), ("R", R, "m", "> 0"),
                                      ("V", V, "m^3", "> 0"), ("omega", omega, "rad/s", "> 0"),
                                      ("xi", xi, "rad", ">= 0"))
    sb = 8 * math.pi * nu * R * xi / (V * omega)
    flags = []
    if sb >= 1.0:
        flags.append(f"sin(beta*) = {sb:.4g} >= 1: friction exceeds the centrifugal drive, no bounded zone")
        beta = tb = float("nan")
    else:
        beta = math.asin(sb)
        tb = sb / math.sqrt(1 - sb * sb)
    res = float("nan") if D is None else THESIS.nonneg("D", D, "kg m") * sb
    return ViscousZone(sb, beta, tb, res, *_result_flags(flags))


def in_equilibrium_zone(beta: float, sin_beta_star: float) -> bool:
    """Whether an angle ``beta`` [rad] lies in the zone (2.15): ``|tan b| <= sin b*/sqrt(1 - sin^2 b*)``."""
    if not (0 <= sin_beta_star < 1):
        raise ValueError(f"sin_beta_star = {sin_beta_star!r} - is invalid: must be in [0, 1)")
    return abs(math.tan(beta)) <= sin_beta_star / math.sqrt(1 - sin_beta_star ** 2)


def wetted_arc(R: float, r: float, f: float) -> float:
    """Wetted arc of the chamber wall [rad] (digest section 4.7 geometry).

    ``2 pi`` while the free-surface circle (radius ``r``, centre at distance
    ``f``) stays inside the chamber (``f <= R - r``); otherwise ``2 pi -
    2 theta*`` with ``cos(theta*) = (R^2 + f^2 - r^2)/(2 R f)`` (dry arc
    ``2 theta*`` centred on the rotation-axis side); 0 if the surface circle
    contains the whole wall.  (App. D's ``xi = 2 pi - arccos z`` with its
    garbled ``z`` is not reproduced.)
    """
    R, r, f = THESIS.each(("R", R, "m", "> 0"), ("r", r, "m", ">= 0"), ("f", f, "m", ">= 0"))
    if f <= R - r:
        return 2 * math.pi
    if f + R <= r:
        return 0.0
    z = (R * R + f * f - r * r) / (2 * R * f)
    return 2 * math.pi - 2 * math.acos(max(-1.0, min(1.0, z)))


def select_liquid(liquids: Mapping[str, float], R: float, V: float, omega: float,
                  xi: float = 2 * math.pi) -> Tuple[str, dict]:
    """Choose the liquid with the narrowest equilibrium zone (App. D, corrected SINUS).

    Parameters
    ----------
    liquids : mapping name -> kinematic viscosity [m^2/s]
    R, V, omega, xi : see :func:`viscous_zone`.

    Returns
    -------
    (name, zones) : the best name and ``{name: ViscousZone}``.
    """
    if not liquids:
        raise ValueError("liquids = {} - is invalid: need at least one liquid")
    zones = {name: viscous_zone(nu, R, V, omega, xi) for name, nu in liquids.items()}
    best = min(zones, key=lambda nm: zones[nm].sin_beta_star)
    return best, zones
