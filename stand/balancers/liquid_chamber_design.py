"""Liquid chamber balancer (thesis 002): design rules.

Part of :mod:`stand.balancers.liquid_chamber`.  The optimal liquid volume of
section 3.3 (energy capacity = liquid unbalance; capacity bounds by the
circular segment and by the intact annulus), the permissible residual
unbalance of section 2.1.7 (household and general machine building, with the
ISO 1940 grade mapping of the digest) and the unbalance coefficient (2.3).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Tuple

import numpy as np
from scipy.optimize import brentq

from ._params import THESIS
from .liquid_chamber_geometry import G_STANDARD

__all__ = [
    "OptimalVolume", "segment_capacity", "annulus_capacity", "optimal_volume",
    "permissible_eccentricity_household", "permissible_eccentricity_general",
    "iso_grade_from_eccentricity", "eccentricity_from_iso_grade", "unbalance_coefficient",
]


# --------------------------------------------------------------------------- optimal volume
def _fill_args(V, R, h, rho):
    """Checked ``V`` [m^3] (>= 0), ``R`` [m], ``h`` [m], ``rho`` [kg/m^3] (> 0) of a capacity model."""
    return THESIS.each(("V", V, "m^3", ">= 0"), ("R", R, "m", "> 0"), ("h", h, "m", "> 0"),
                       ("rho", rho, "kg/m^3", "> 0"))


def segment_capacity(V: float, R: float, h: float, rho: float = 1000.0) -> float:
    """Largest liquid unbalance a volume can produce in the chamber [kg m].

    All the liquid in a circular segment at the wall (bathtub principle: the
    region of given area with the largest first moment in a disk is cut by a
    straight line).  With half-angle ``t``: area ``R^2 (t - sin t cos t)``,
    first moment ``(2/3) R^3 sin^3 t``.  An upper bound for any free-surface
    shape, ``< rho V R``.
    """
    V, R, h, rho = _fill_args(V, R, h, rho)
    A = V / h
    if A > math.pi * R * R:
        raise ValueError(f"V = {V!r} m^3 is invalid: exceeds the chamber volume {math.pi * R * R * h:.6g} m^3")
    if A == 0:
        return 0.0
    t = brentq(lambda t: R * R * (t - math.sin(t) * math.cos(t)) - A, 0.0, math.pi, xtol=1e-15)
    return rho * h * (2.0 / 3.0) * R ** 3 * math.sin(t) ** 3


def annulus_capacity(V: float, R: float, h: float, rho: float = 1000.0) -> float:
    """Largest liquid unbalance [kg m] with the annular layer intact (sufficiency at its limit).

    ``f = R - r`` in ``D = rho pi h r^2 f`` gives ``D = rho V r^2/(R + r)``
    (~ ``rho V R/2`` for a thin layer).
    """
    V, R, h, rho = _fill_args(V, R, h, rho)
    r2 = R * R - V / (math.pi * h)
    if r2 < 0:
        raise ValueError(f"V = {V!r} m^3 is invalid: exceeds the chamber volume {math.pi * R * R * h:.6g} m^3")
    return rho * V * r2 / (R + math.sqrt(r2))


@dataclass(frozen=True)
class OptimalVolume:
    """Result of the optimal-volume method (section 3.3).

    Attributes
    ----------
    V_opt : float
        Volume whose capacity equals ``D0`` (k = 1, the maximum of the
        corrected lambda0) [m^3].
    V_design : float
        Volume whose capacity equals ``reserve * D0`` [m^3].
    capacity : float
        Capacity of ``V_design`` [kg m] (= ``reserve * D0``).
    lower_bound : float
        ``D0/(rho R)`` [m^3]; physically ``V_opt >= lower_bound``.
    chamber_volume, fill_fraction, layer : float
        ``pi R^2 h`` [m^3], ``V_design/chamber_volume`` [-], ``R - r`` [m]
        of the design fill.
    model : str
    valid, flags
    """

    V_opt: float
    V_design: float
    capacity: float
    lower_bound: float
    chamber_volume: float
    fill_fraction: float
    layer: float
    model: str
    valid: bool
    flags: Tuple[str, ...]


def optimal_volume(D0: float, R: float, h: float, rho: float = 1000.0, *, reserve: float = 1.0,
                   model: str = "segment") -> OptimalVolume:
    """Optimal liquid volume of section 3.3 (energy capacity = liquid unbalance).

    With the corrected (2.13) the efficiency (2.14) peaks (singularly) at
    ``k = 1`` (section 2.8 of the digest), so the optimum is the volume whose
    liquid unbalance equals ``D0``; the reserve factor ``k_zapasu`` (1.1-1.25,
    l.1315) then scales the capacity.

    Parameters
    ----------
    D0 : float
        Rotor unbalance to balance [kg m] (1000 g cm = 0.01 kg m).
    R, h : float
        Chamber radius and height [m].
    rho : float
        Liquid density [kg/m^3].
    reserve : float
        Energy-capacity reserve factor [-], >= 1 (thesis 1.1-1.25).
    model : {"segment", "annulus"}
        Capacity model: :func:`segment_capacity` (the physical maximum; its
        volume is the smallest that can balance ``D0``) or
        :func:`annulus_capacity` (annular layer kept, sufficiency (3.4) at its
        limit).

    Returns
    -------
    OptimalVolume
        Flagged when the chamber cannot hold enough liquid.
    """
    D0, R, h, rho, reserve = THESIS.each(("D0", D0, "kg m", "> 0"), ("R", R, "m", "> 0"),
                                         ("h", h, "m", "> 0"), ("rho", rho, "kg/m^3", "> 0"),
                                         ("reserve", reserve, "-", "finite"))
    if reserve < 1.0:
        raise ValueError(f"reserve = {reserve!r} - is invalid: must be >= 1")
    if model == "segment":
        cap = segment_capacity
    elif model == "annulus":
        cap = annulus_capacity
    else:
        raise ValueError(f"model = {model!r} is invalid: use 'segment' or 'annulus'")
    Vk = math.pi * R * R * h
    # capacity is increasing on (0, V_peak); find its maximum first
    vs = np.linspace(0.0, Vk, 2001)
    caps = np.array([cap(v, R, h, rho) for v in vs])
    i_pk = int(np.argmax(caps))
    flags = []
    nan = float("nan")

    def solve(target):
        if caps[i_pk] < target:
            return nan
        j = int(np.argmax(caps >= target))
        if j == 0:
            return 0.0
        return brentq(lambda v: cap(v, R, h, rho) - target, vs[j - 1], vs[j], xtol=1e-15)

    V_opt = solve(D0)
    V_des = solve(reserve * D0)
    if not (V_opt == V_opt):
        flags.append(f"chamber too small: maximum capacity {caps[i_pk]:.4g} kg m < D0 = {D0:.4g} kg m")
    elif not (V_des == V_des):
        flags.append(f"chamber too small for the reserve: maximum capacity {caps[i_pk]:.4g} kg m "
                     f"< {reserve} D0")
    layer = R - math.sqrt(R * R - V_des / (math.pi * h)) if V_des == V_des else nan
    return OptimalVolume(V_opt=V_opt, V_design=V_des, capacity=reserve * D0 if V_des == V_des else nan,
                         lower_bound=D0 / (rho * R), chamber_volume=Vk, fill_fraction=V_des / Vk,
                         layer=layer, model=model, valid=not flags, flags=tuple(flags))


# --------------------------------------------------------------------------- permissible unbalance
def _rpm(n_rpm):
    return THESIS.positive("n_rpm", n_rpm, "rpm")


def permissible_eccentricity_household(n_rpm: float) -> float:
    """Permissible specific unbalance for machines a person contacts (household), l.604-606.

    ``[e_st] = 6000/n`` um with ``n`` in rpm.  Returns metres (SI).
    """
    return 6000.0 / _rpm(n_rpm) * 1e-6


def permissible_eccentricity_general(n_rpm: float) -> float:
    """Permissible specific unbalance for general machine building (Reutlinger), l.600-602.

    ``[e_st] = 2e8 n^-2`` (unit missing in the print; um reconstructed by the
    digest: ``2 * 0.1 g/omega^2``).  Returns metres (SI).
    """
    return 2e8 / _rpm(n_rpm) ** 2 * 1e-6


def iso_grade_from_eccentricity(e: float, n_rpm: float) -> float:
    """ISO 1940 grade ``G = e omega`` [mm/s] of a permissible eccentricity ``e`` [m] at ``n`` rpm.

    (``e_per[um] = 9549 G/n``; not in the thesis -- digest mapping.)
    """
    e = THESIS.nonneg("e", e, "m")
    return e * 1e3 * _rpm(n_rpm) * 2 * math.pi / 60.0


def eccentricity_from_iso_grade(G: float, n_rpm: float) -> float:
    """Permissible eccentricity [m] of ISO 1940 grade ``G`` [mm/s] at ``n`` rpm."""
    G = THESIS.nonneg("G", G, "mm/s")
    return G * 1e-3 / (_rpm(n_rpm) * 2 * math.pi / 60.0)


def unbalance_coefficient(e: float, omega: float, g: float = G_STANDARD) -> float:
    """Unbalance coefficient (2.3) ``k = F_c/P_st = e omega^2/g`` [-] for a single mass.

    The most favourable bearing regime needs ``k < 1``; recommended limits are
    0.01-0.5 by rotor type (l.592-596).

    Parameters
    ----------
    e : float
        Specific unbalance (CoM eccentricity) [m].
    omega : float
        Spin [rad/s].
    """
    e = THESIS.nonneg("e", e, "m")
    omega = THESIS.nonneg("omega", omega, "rad/s")
    return e * omega ** 2 / g
