"""Liquid chamber balancer (thesis 002): simplified "virtual disk" models of chapter 3.

Part of :mod:`stand.model.balancers.liquid_chamber`.  Kinetostatics of a single
chamber, (3.1)-(3.9), and of concentric chambers, (3.10)-(3.14): the liquid
acts as a virtual full disk of mass ``rho pi h sum R_i^2`` while the
sufficiency condition (3.4)/(3.11) holds.  Corrections: (3.2) has ``h``
restored, (3.10) ``l`` is ``pi``, (3.12) is used with the sign of (3.2),
``m0 = rho pi h (2 R s - s^2)``; ``literal=True`` evaluates the print.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional, Sequence, Tuple

from stand.model.balancers._params import THESIS
from stand.model.balancers.liquid_chamber_geometry import _result_flags

__all__ = [
    "SimplifiedResult", "MultiChamberResult", "simplified_single_chamber", "multi_chamber",
]


# --------------------------------------------------------------------------- chapter 3
@dataclass(frozen=True)
class SimplifiedResult:
    """Simplified ("virtual disk") model of section 3.1 / 3.2.

    Attributes
    ----------
    s : float
        Shaft deflection at the reservoir [m] ((3.2)/(3.12); negative =
        opposite to the unbalance, supercritical).
    omega_k : float
        Critical speed with the liquid virtual mass [rad/s] ((3.3)/(3.13)).
    omega_k_empty : float
        ``sqrt(c/m)`` [rad/s].
    virtual_mass : float
        ``k rho pi h sum R_i^2`` [kg].
    liquid_mass : float
        ``m_p`` total [kg].
    e : float
        System eccentricity (3.7) at this speed [m].
    e_limit : float
        (3.8) ``e0 m/(m + virtual_mass)`` [m], the ``omega >> omega_k`` limit.
    E : float
        (3.9)/(3.14) ``E_e = E_s = (m + virtual_mass)/m`` [-].
    m0 : float
        Limiting liquid mass of the sufficiency condition, exact ``rho pi h
        (2 R s - s^2)`` [kg] (outer chamber) (printed first-order ``2 s rho pi h R``
        is ``m0_approx``).
    m0_approx : float
    sufficient : bool
        (3.4)/(3.11) holds.
    valid, flags
    """

    s: float
    omega_k: float
    omega_k_empty: float
    virtual_mass: float
    liquid_mass: float
    e: float
    e_limit: float
    E: float
    m0: float
    m0_approx: float
    sufficient: bool
    valid: bool
    flags: Tuple[str, ...]

    @property
    def omega_k_ratio(self) -> float:
        """``omega_k/omega_k_empty`` [-]."""
        return self.omega_k / self.omega_k_empty


def simplified_single_chamber(m: float, c: float, e0: float, omega: float, R: float, h: float,
                              V: float, rho: float = 1000.0, *, conversion_k: Optional[float] = None,
                              literal: bool = False) -> SimplifiedResult:
    """Single-chamber simplified model, (3.1)-(3.9).

    Force balance (kinetostatics, delta = 0) ``c s = m omega^2 (s + e0) +
    m_p omega^2 s_p`` with ``m_p s_p = rho pi h R^2 s`` (virtual full disk)::

        s = e0 m omega^2/(c - (m + k rho pi h R^2) omega^2)      (3.2)/(3.5)
        omega_k = sqrt(c/(m + k rho pi h R^2))                    (3.3)/(3.6)
        e = (e0 m + m_p (s_p - s))/(m + m_p)                      (3.7)
        E = (m + k rho pi h R^2)/m                                (3.9)

    with ``k = 1`` while (3.4) ``R - r >= |s|`` holds.  The print of (3.2)
    lacks ``h`` (``literal=True`` evaluates it so, in SI).

    Parameters
    ----------
    m : float
        Rotor + reservoir mass (chapter 3's ``m``) [kg].
    c : float
        Radial shaft stiffness [N/m].
    e0 : float
        Rotor eccentricity [m].
    omega : float
        Spin [rad/s].
    R, h, V, rho : float
        Chamber radius [m], height [m], liquid volume [m^3], density [kg/m^3].
    conversion_k : float, optional
        Fig. 3.3's conversion coefficient for insufficient liquid (not
        reproduced in the thesis); without it an insufficient fill is flagged
        and ``k = 1`` is used.
    literal : bool

    Returns
    -------
    SimplifiedResult
        Flags: fill exceeds the chamber; near resonance (denominator ~ 0);
        subcritical (``omega < omega_k``: section 3.1 is stated for steady
        supercritical rotation, (3.9) is the ``omega >> omega_k`` limit);
        insufficient liquid without ``conversion_k``.
    """
    return multi_chamber(m, c, e0, omega, [R], [V], h, rho, 0.0, conversion_k=conversion_k,
                         literal=literal, _single=True)


@dataclass(frozen=True)
class MultiChamberResult(SimplifiedResult):
    """:class:`SimplifiedResult` plus per-chamber free-surface radii ``r`` [m] and margins [m]."""

    r: Tuple[float, ...] = ()
    margins: Tuple[float, ...] = ()


def multi_chamber(m: float, c: float, e0: float, omega: float, radii: Sequence[float],
                  volumes: Sequence[float], h: float, rho: float = 1000.0,
                  wall_thickness: float = 0.0, *, conversion_k: Optional[float] = None,
                  literal: bool = False, _single: bool = False) -> MultiChamberResult:
    """Concentric multi-chamber device, (3.10)-(3.14).

    Chambers numbered from the outside in: chamber i occupies ``R_{i+1} +
    delta < rho_ < R_i``.  ``m_i = rho pi h (R_i^2 - r_i^2)`` ((3.10), printed
    ``l`` is OCR for ``pi``), ``s_i = s R_i^2/(R_i^2 - r_i^2)``; the sum gives
    the virtual mass ``rho pi h sum R_i^2``.  ``s`` uses the sign of (3.2);
    ``literal=True`` uses the printed (3.12) denominator ``(m + ...) omega^2 - c``.

    Parameters
    ----------
    m, c, e0, omega : see :func:`simplified_single_chamber`.
    radii : sequence of float
        Outer radii ``R_i`` [m], strictly decreasing.
    volumes : sequence of float
        Liquid volumes ``V_i`` [m^3].
    h : float
        Common height [m].
    rho : float
        Density [kg/m^3].
    wall_thickness : float
        Partition wall thickness ``delta`` [m].

    Returns
    -------
    MultiChamberResult
        Sufficiency (3.11): ``R_i - r_i >= |s|`` and ``r_i - (R_{i+1} + delta) >= |s|``.
    """
    m, c, e0, omega, h, rho, dw = THESIS.each(
        ("m", m, "kg", "> 0"), ("c", c, "N/m", "> 0"), ("e0", e0, "m", ">= 0"),
        ("omega", omega, "rad/s", ">= 0"), ("h", h, "m", "> 0"), ("rho", rho, "kg/m^3", "> 0"),
        ("wall_thickness", wall_thickness, "m", ">= 0"))
    Rs = [THESIS.positive(f"radii[{i}]", x, "m") for i, x in enumerate(radii)]
    Vs = [THESIS.nonneg(f"volumes[{i}]", x, "m^3") for i, x in enumerate(volumes)]
    if not Rs or len(Rs) != len(Vs):
        raise ValueError(f"radii/volumes = {len(Rs)}/{len(Vs)} chambers is invalid: need equal, >= 1")
    for i in range(len(Rs) - 1):
        if Rs[i + 1] + dw >= Rs[i]:
            raise ValueError(f"radii[{i + 1}] = {Rs[i + 1]!r} m is invalid: R_{i + 2} + delta must be "
                             f"< R_{i + 1} = {Rs[i]!r} m (chambers overlap)")
    if conversion_k is not None:
        conversion_k = THESIS.nonneg("conversion_k", conversion_k, "-")
    flags = []
    rs = []
    for i, (Ri, Vi) in enumerate(zip(Rs, Vs)):
        r2 = Ri * Ri - Vi / (math.pi * h)
        inner = Rs[i + 1] + dw if i + 1 < len(Rs) else 0.0
        if r2 < inner * inner:
            flags.append(f"chamber {i + 1}: fill V = {Vi:.4g} m^3 exceeds the chamber "
                         f"({math.pi * h * (Ri * Ri - inner * inner):.4g} m^3)")
        rs.append(math.sqrt(max(r2, 0.0)))
    m_p = rho * sum(Vs)
    sumR2 = sum(Ri * Ri for Ri in Rs)
    kk = 1.0 if conversion_k is None else conversion_k
    vm = kk * rho * math.pi * h * sumR2
    vm_s = kk * rho * math.pi * sumR2 if (literal and _single) else vm   # printed (3.2): no h
    if literal:
        flags.append("thesis-literal: printed " + ("(3.2) without h" if _single else
                                                   "(3.12) denominator sign") + "; not physical")
    denom = c - (m + vm_s) * omega ** 2
    if literal and not _single:
        denom = -denom
    if abs(denom) <= 1e-9 * c:
        flags.append("at the critical speed: (3.2) singular")
        s = float("inf")
    else:
        s = e0 * m * omega ** 2 / denom
    wk = math.sqrt(c / (m + vm))
    wk0 = math.sqrt(c / m)
    if omega < wk:
        flags.append(f"subcritical: omega = {omega:.4g} rad/s < omega_k = {wk:.4g} rad/s; section 3.1 "
                     "models steady supercritical rotation")
    margins = []
    for i, (Ri, ri) in enumerate(zip(Rs, rs)):
        margins.append(Ri - ri)
        if i + 1 < len(Rs):
            margins.append(ri - (Rs[i + 1] + dw))
    sufficient = all(abs(s) <= mg for mg in margins) if math.isfinite(s) else False
    if not sufficient and math.isfinite(s) and conversion_k is None:
        flags.append(f"insufficient liquid: |s| = {abs(s):.4g} m > min margin {min(margins):.4g} m "
                     "((3.4)/(3.11)); (3.5) needs Fig. 3.3's conversion coefficient (not reproduced)")
    # (3.7): m_p (s_p - s) summed = rho pi h sum r_i^2 s
    if math.isfinite(s):
        e = (e0 * m + rho * math.pi * h * sum(ri * ri for ri in rs) * s) / (m + m_p)
    else:
        e = float("nan")
    e_lim = e0 * m / (m + vm)
    s_abs = abs(s) if math.isfinite(s) else float("nan")
    R1 = Rs[0]
    m0 = rho * math.pi * h * (2 * R1 * s_abs - s_abs ** 2)
    m0a = 2 * s_abs * rho * math.pi * h * R1
    valid, fl = _result_flags(flags)
    return MultiChamberResult(s=s, omega_k=wk, omega_k_empty=wk0, virtual_mass=vm, liquid_mass=m_p,
                              e=e, e_limit=e_lim, E=(m + vm) / m, m0=m0, m0_approx=m0a,
                              sufficient=sufficient, valid=valid, flags=fl, r=tuple(rs),
                              margins=tuple(margins))
