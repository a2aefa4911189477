"""Liquid chamber balancer (thesis 002): design rules.

Part of :mod:`stand.model.balancers.liquid_chamber`.  The optimal liquid volume of
section 3.3 (energy capacity = liquid unbalance; capacity bounds by the
circular segment and by the intact annulus), the permissible residual
unbalance of section 2.1.7 (household and general machine building, with the
ISO 1940 grade mapping of the digest) and the unbalance coefficient (2.3).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Tuple

from scipy.optimize import brentq

from stand.model.balancers._params import THESIS
from stand.model.balancers.liquid_chamber_geometry import G_STANDARD

__all__ = [
    "OptimalVolume", "segment_capacity", "annulus_capacity", "optimal_volume",
    "permissible_eccentricity_household", "permissible_eccentricity_general",
    "iso_grade_from_eccentricity", "eccentricity_from_iso_grade", "unbalance_coefficient",
]


# --------------------------------------------------------------------------- optimal volume
#: relative rounding allowance at a full chamber: ``V = pi R^2 h`` computed by the
#: caller may exceed the chamber's own ``pi R^2 h`` by a few ulps
_FULL_RTOL = 1e-12


def _fill_args(V, R, h, rho):
    """Checked ``V`` [m^3] (>= 0), ``R`` [m], ``h`` [m], ``rho`` [kg/m^3] (> 0) of a capacity model."""
    return THESIS.each(("V", V, "m^3", ">= 0"), ("R", R, "m", "> 0"), ("h", h, "m", "> 0"),
                       ("rho", rho, "kg/m^3", "> 0"))


def _overfill(V, R, h):
    return ValueError(f"V = {V!r} m^3 is invalid: exceeds the chamber volume "
                      f"{math.pi * R * R * h:.6g} m^3 (R = {R!r} m, h = {h!r} m)")


def _segment_area(t: float, R: float) -> float:
    """Area [m^2] of the circular segment of half-angle ``t`` [rad] in a disk of radius ``R`` [m]."""
    return R * R * (t - math.sin(t) * math.cos(t))


def segment_capacity(V: float, R: float, h: float, rho: float = 1000.0) -> float:
    """Largest liquid unbalance a volume can produce in the chamber [kg m].

    All the liquid in a circular segment at the wall (bathtub principle: the
    region of given area with the largest first moment in a disk is cut by a
    straight line).  With half-angle ``t``: area ``R^2 (t - sin t cos t)``,
    first moment ``(2/3) R^3 sin^3 t``.  An upper bound for any free-surface
    shape, ``< rho V R``.  The capacity rises to ``(2/3) rho h R^3`` at half
    fill (``t = pi/2``) and falls back to 0 at a full chamber (``t = pi``:
    the limit is returned there, within a relative rounding of 1e-12 of
    ``pi R^2 h``, instead of searching ``t`` beyond ``pi``).

    Parameters
    ----------
    V : float
        Liquid volume [m^3], ``0 <= V <= pi R^2 h``.
    R, h : float
        Chamber radius and height [m].
    rho : float
        Liquid density [kg/m^3].

    Returns
    -------
    float
        Capacity [kg m].

    Raises
    ------
    ValueError
        ``V`` beyond the chamber volume (naming ``V``, its value and m^3).
    """
    V, R, h, rho = _fill_args(V, R, h, rho)
    A = V / h
    A_full = _segment_area(math.pi, R)       # the same expression the root search uses at t = pi
    if A > A_full * (1.0 + _FULL_RTOL):
        raise _overfill(V, R, h)
    if A == 0.0 or A >= A_full:              # empty, or full (the limit t = pi: no unbalance)
        return 0.0
    # _segment_area(0) - A = -A < 0 < A_full - A = _segment_area(pi) - A: a valid bracket
    t = brentq(lambda t: _segment_area(t, R) - A, 0.0, math.pi, xtol=1e-15)
    return rho * h * (2.0 / 3.0) * R ** 3 * math.sin(t) ** 3


def annulus_capacity(V: float, R: float, h: float, rho: float = 1000.0) -> float:
    """Largest liquid unbalance [kg m] with the annular layer intact (sufficiency at its limit).

    ``f = R - r`` in ``D = rho pi h r^2 f`` gives ``D = rho V r^2/(R + r)``
    (~ ``rho V R/2`` for a thin layer); 0 at a full chamber (``r = 0``, the
    limit is returned within a relative rounding of 1e-12 of ``pi R^2 h``).

    Parameters
    ----------
    V : float
        Liquid volume [m^3], ``0 <= V <= pi R^2 h``.
    R, h : float
        Chamber radius and height [m].
    rho : float
        Liquid density [kg/m^3].

    Returns
    -------
    float
        Capacity [kg m].
    """
    V, R, h, rho = _fill_args(V, R, h, rho)
    r2 = R * R - V / (math.pi * h)
    if r2 < 0:
        if r2 < -_FULL_RTOL * R * R:
            raise _overfill(V, R, h)
        r2 = 0.0
    return rho * V * r2 / (R + math.sqrt(r2))


def _segment_peak(R, h, rho):
    """(volume [m^3], capacity [kg m]) at the segment model's maximum (half fill, ``t = pi/2``)."""
    return 0.5 * math.pi * R * R * h, rho * h * (2.0 / 3.0) * R ** 3


def _segment_volume(target, R, h, rho):
    """Smallest volume [m^3] whose segment capacity is ``target`` [kg m] (<= the peak).

    Closed form: ``sin t = (target/((2/3) rho h R^3))^(1/3)``, ``V = h R^2 (t - sin t cos t)``.
    """
    _, peak = _segment_peak(R, h, rho)
    s = min((target / peak) ** (1.0 / 3.0), 1.0)
    return h * _segment_area(math.asin(s), R)


def _annulus_peak(R, h, rho):
    """(volume [m^3], capacity [kg m]) at the annulus model's maximum, ``r = 2R/3``.

    ``D = rho pi h (R - r) r^2`` peaks at ``r = 2R/3``: ``V = (5/9) pi R^2 h``,
    ``D = (4/27) pi rho h R^3``.
    """
    return 5.0 / 9.0 * math.pi * R * R * h, 4.0 / 27.0 * math.pi * rho * h * R ** 3


def _annulus_volume(target, R, h, rho):
    """Smallest volume [m^3] whose annulus capacity is ``target`` [kg m] (<= the peak).

    The root of ``rho pi h (R - r) r^2 = target`` in ``[2R/3, R]`` (capacity
    ``>= target`` at ``2R/3``, 0 at ``R``: a valid bracket).
    """
    _, peak = _annulus_peak(R, h, rho)
    if target >= peak:
        r = 2.0 * R / 3.0
    else:
        c = target / (rho * math.pi * h)
        r = brentq(lambda r: (R - r) * r * r - c, 2.0 * R / 3.0, R, xtol=1e-15 * R)
    return math.pi * h * (R * R - r * r)


@dataclass(frozen=True)
class OptimalVolume:
    """Result of the optimal-volume method (section 3.3).

    Attributes
    ----------
    V_opt : float
        Volume whose capacity equals ``D0`` (k = 1, the maximum of the
        corrected lambda0) [m^3].  When no volume reaches ``D0`` (the chamber
        is too small): the limit, the volume of the largest capacity (flagged,
        ``valid`` False).
    V_design : float
        Volume whose capacity equals ``reserve * D0`` [m^3] (the limit, flagged,
        when the chamber cannot hold that much).
    capacity : float
        Capacity of ``V_design`` [kg m] (= ``reserve * D0``, or
        ``max_capacity`` at the limit).
    lower_bound : float
        ``D0/(rho R)`` [m^3]; physically ``V_opt >= lower_bound``.
    chamber_volume, fill_fraction, layer : float
        ``pi R^2 h`` [m^3], ``V_design/chamber_volume`` [-], ``R - r`` [m]
        of the design fill.
    model : str
    valid : bool
    flags : tuple of str
        Why the result is limited (each flag makes ``valid`` False).
    max_capacity : float
        Largest capacity the chamber can hold with this model [kg m]:
        ``(2/3) rho h R^3`` (segment, at half fill) or ``(4/27) pi rho h R^3``
        (annulus, at 5/9 fill); a fuller chamber holds less.
    V_max_capacity : float
        Volume of ``max_capacity`` [m^3].
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
    max_capacity: float = float("nan")
    V_max_capacity: float = float("nan")


def optimal_volume(D0: float, R: float, h: float, rho: float = 1000.0, *, reserve: float = 1.0,
                   model: str = "segment") -> OptimalVolume:
    """Optimal liquid volume of section 3.3 (energy capacity = liquid unbalance).

    With the corrected (2.13) the efficiency (2.14) peaks (singularly) at
    ``k = 1`` (section 2.8 of the digest), so the optimum is the volume whose
    liquid unbalance equals ``D0``; the reserve factor ``k_zapasu`` (1.1-1.25,
    l.1315) then scales the capacity.

    The capacity of either model rises from 0 (empty) to a single maximum and
    falls back to 0 at a full chamber, so the smallest volume of a given
    capacity is found on the rising branch, in closed form (segment) or by a
    root search bracketed by the maximum and the full chamber (annulus);
    a demand beyond the maximum returns that limit, flagged, never a
    root-finder error.

    Parameters
    ----------
    D0 : float
        Rotor unbalance to balance [kg m] (1000 g cm = 0.01 kg m), > 0.
    R, h : float
        Chamber radius and height [m], > 0.
    rho : float
        Liquid density [kg/m^3], > 0.
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
        ``valid`` False with a flag naming the largest capacity when the
        chamber cannot hold ``D0`` (or ``reserve * D0``).

    Raises
    ------
    ValueError
        A non-positive or non-finite ``D0``, ``R``, ``h``, ``rho``, a
        ``reserve`` below 1 or an unknown ``model`` (naming the parameter,
        its value and unit).
    """
    D0, R, h, rho, reserve = THESIS.each(("D0", D0, "kg m", "> 0"), ("R", R, "m", "> 0"),
                                         ("h", h, "m", "> 0"), ("rho", rho, "kg/m^3", "> 0"),
                                         ("reserve", reserve, "-", "finite"))
    if reserve < 1.0:
        raise ValueError(f"reserve = {reserve!r} - is invalid: must be >= 1")
    if model == "segment":
        V_pk, cap_pk = _segment_peak(R, h, rho)
        volume = _segment_volume
    elif model == "annulus":
        V_pk, cap_pk = _annulus_peak(R, h, rho)
        volume = _annulus_volume
    else:
        raise ValueError(f"model = {model!r} is invalid: use 'segment' or 'annulus'")
    Vk = math.pi * R * R * h
    flags = []

    def solve(target):
        return V_pk if target >= cap_pk else volume(target, R, h, rho)

    V_opt = solve(D0)
    V_des = solve(reserve * D0)
    limit = (f"the largest liquid unbalance this chamber (R = {R:.4g} m, h = {h:.4g} m, "
             f"rho = {rho:.4g} kg/m^3, {model} model) can hold is {cap_pk:.4g} kg m "
             f"at V = {V_pk:.4g} m^3 ({V_pk / Vk:.0%} full; a fuller chamber holds less)")
    if D0 > cap_pk:
        flags.append(f"chamber too small: D0 = {D0:.4g} kg m exceeds the maximum capacity; {limit}; "
                     "the volumes returned are that limit")
    elif reserve * D0 > cap_pk:
        flags.append(f"chamber too small for the reserve: {reserve:g} D0 = {reserve * D0:.4g} kg m "
                     f"exceeds the maximum capacity; {limit}; V_design is that limit")
    capacity = min(reserve * D0, cap_pk)
    layer = R - math.sqrt(max(R * R - V_des / (math.pi * h), 0.0))
    return OptimalVolume(V_opt=V_opt, V_design=V_des, capacity=capacity,
                         lower_bound=D0 / (rho * R), chamber_volume=Vk, fill_fraction=V_des / Vk,
                         layer=layer, model=model, valid=not flags, flags=tuple(flags),
                         max_capacity=cap_pk, V_max_capacity=V_pk)


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
