"""Liquid chamber balancer (thesis 002): damped quasi-static model below the critical speed.

Theory of the model :mod:`stand.model.balancers.liquid_chamber` (section 2.2.2.1 of the
thesis): phase lag (2.5), deflection factor (2.7)-(2.8), liquid equilibrium
angle (2.12)-(2.13) (**corrected**: the print drops the ``1/k`` of l.814;
``literal=True`` evaluates the print), efficiency (2.14) and its extremum over
``k`` (section 2.3.3), and the self-consistent closure of digest section 4.6
(:func:`quasi_static_efficiency`; ``literal=True``: the Appendix-B algorithm
as printed).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Tuple

from stand.model.balancers._params import THESIS
from stand.model.balancers.liquid_chamber_geometry import G_STANDARD, _result_flags, fill_geometry

if TYPE_CHECKING:
    from stand.model.balancers.liquid_chamber_params import LiquidChamberParams

__all__ = [
    "EquilibriumAngle", "EfficiencyExtremum", "QuasiStaticResult", "phase_lag",
    "deflection_factor", "equilibrium_angle", "efficiency", "efficiency_derivative",
    "efficiency_second_derivative", "efficiency_extremum", "quasi_static_efficiency",
]


# --------------------------------------------------------------------------- damped model
def _speed_args(omega, omega_cr, n):
    """Checked ``omega`` [rad/s] (>= 0), ``omega_cr`` [rad/s] (> 0) and ``n`` [1/s] (>= 0)."""
    return THESIS.each(("omega", omega, "rad/s", ">= 0"), ("omega_cr", omega_cr, "rad/s", "> 0"),
                       ("n", n, "1/s", ">= 0"))


def phase_lag(omega: float, omega_cr: float, n: float) -> float:
    """Phase lag ``delta`` [rad] of the deflection behind ``D_c``, (2.5).

    ``tan(delta) = 2 n omega/(omega_cr^2 - omega^2)``, in ``[0, pi]`` by atan2
    (90 deg exactly at ``omega = omega_cr``).
    """
    omega, omega_cr, n = _speed_args(omega, omega_cr, n)
    return math.atan2(2 * n * omega, omega_cr ** 2 - omega ** 2)


def deflection_factor(omega: float, omega_cr: float, n: float, form: str = "thesis") -> float:
    """Shaft deflection per system eccentricity, ``f/e_c`` [-], (2.7).

    ``form="thesis"``: (2.7) ``cos(d)[cos(phi) omega_cr^2/(omega_cr^2 - omega^2) - 1]``,
    evaluated as ``(cos(phi) - 1 + gamma^2)/sqrt(A)`` with ``A = (1 -
    gamma^2)^2 + (2 n omega/omega_cr^2)^2`` and ``sin(phi) = 2 n
    omega/omega_cr^2`` (2.8) (identical, and regular at gamma = 1).
    ``form="jeffcott"``: the classical ``gamma^2/sqrt(A)``.  Both coincide at n = 0.

    Raises
    ------
    ValueError
        If ``2 n omega > omega_cr^2`` for the thesis form (no real phi in (2.8));
        :func:`quasi_static_efficiency` flags this instead.
    """
    omega, omega_cr, n = _speed_args(omega, omega_cr, n)
    g2 = (omega / omega_cr) ** 2
    a = 2 * n * omega / omega_cr ** 2
    A = (1 - g2) ** 2 + a * a
    if A == 0.0:
        return float("inf")
    if form == "jeffcott":
        return g2 / math.sqrt(A)
    if form != "thesis":
        raise ValueError(f"form = {form!r} is invalid: use 'thesis' or 'jeffcott'")
    if a > 1.0:
        raise ValueError(f"2 n omega/omega_cr^2 = {a!r} - is invalid for (2.8): must be <= 1")
    return (math.sqrt(1 - a * a) - 1 + g2) / math.sqrt(A)


@dataclass(frozen=True)
class EquilibriumAngle:
    """Liquid equilibrium angle of (2.12)/(2.13).

    Attributes
    ----------
    alpha0 : float
        Angle [rad] of the liquid CoM from the rotor unbalance, thesis branch
        (``cos(alpha0) = (-sin^2 d - sqrt(.))/k``, corrected (2.13); or the
        printed formula when ``literal``).  NaN if undefined.
    alpha0_other : float
        The discarded ``+`` root of l.814 [rad] (tends to 0 as delta -> 0;
        the thesis gives no stability argument for discarding it).  NaN in
        literal mode or when undefined.
    arccos_argument : float
        The argument of arccos in (2.13) (printed or corrected) [-].
    literal : bool
    valid, flags
    """

    alpha0: float
    alpha0_other: float
    arccos_argument: float
    literal: bool
    valid: bool
    flags: Tuple[str, ...]


def equilibrium_angle(k: float, delta: float, *, literal: bool = False) -> EquilibriumAngle:
    """Liquid equilibrium angle ``alpha0`` [rad], (2.13).

    Corrected (default; the digest's correction, re-derived: it satisfies
    (2.12) ``sin(alpha0) = sin(d) sqrt(1 + 2k cos(alpha0) + k^2)/k``)::

        alpha0 = pi - arccos((sin^2 d + sqrt((1 - sin^2 d)(k^2 - sin^2 d)))/k)

    ``literal=True``: the printed (2.13) without ``1/k`` (also App. B step 3
    and OPTIMUM_KAMERA); satisfies (2.12) only for k = 1.

    Parameters
    ----------
    k : float
        ``D0/D`` [-], > 0.
    delta : float
        Phase lag (2.5) [rad], in [0, pi].

    Returns
    -------
    EquilibriumAngle
        Flagged (NaN angle) when ``k < sin(delta)`` (no equilibrium: too much
        liquid, ``D > D0/sin(d)``), or, in literal mode, when the printed
        arccos argument leaves [-1, 1] or its square root is of a negative
        number (Pascal would stop).
    """
    k = THESIS.positive("k", k, "-")
    delta = THESIS.finite("delta", delta, "rad")
    if not (0.0 <= delta <= math.pi):
        raise ValueError(f"delta = {delta!r} rad is invalid: must be in [0, pi]")
    s2 = math.sin(delta) ** 2
    flags = []
    nan = float("nan")
    if literal:
        flags.append("thesis-literal: printed (2.13) lacks 1/k, not a physical prediction")
        rad = (s2 - 1.0) * (s2 - k * k)
        if rad < 0:
            flags.append(f"printed (2.13): sqrt of negative {(rad):.3g} (k = {k:.4g} < sin(delta) = "
                         f"{math.sqrt(s2):.4g}); undefined")
            return EquilibriumAngle(nan, nan, nan, True, *_result_flags(flags))
        y = s2 + math.sqrt(rad)
        if abs(y) > 1.0:
            flags.append(f"printed (2.13): arccos argument {y:.6g} outside [-1, 1]; undefined")
            return EquilibriumAngle(nan, nan, y, True, *_result_flags(flags))
        return EquilibriumAngle(math.pi - math.acos(y), nan, y, True, *_result_flags(flags))
    if k < math.sqrt(s2) * (1 - 1e-15):
        flags.append(f"no equilibrium: k = {k:.6g} < sin(delta) = {math.sqrt(s2):.6g} "
                     "(liquid unbalance D > D0/sin(delta))")
        return EquilibriumAngle(nan, nan, nan, False, *_result_flags(flags))
    root = math.sqrt(max((1.0 - s2) * (k * k - s2), 0.0))
    y = min((s2 + root) / k, 1.0)          # <= 1 by Cauchy-Schwarz; clip rounding
    y_other = max(min((s2 - root) / k, 1.0), -1.0)   # = -cos of the '+' branch
    return EquilibriumAngle(math.pi - math.acos(y), math.pi - math.acos(y_other), y, False,
                            *_result_flags(flags))


def efficiency(k: float, alpha0: float) -> float:
    """Balancing efficiency (2.14), ``lambda0 = k/sqrt(1 + 2k cos(alpha0) + k^2)`` [-].

    ``= zeta0/zeta = e0/e_c`` (same delta with and without liquid).  Returns
    ``inf`` at complete balance (``k = 1``, ``alpha0 = pi``).
    """
    k = THESIS.nonneg("k", k, "-")
    Q = 1 + 2 * k * math.cos(alpha0) + k * k
    if Q <= 1e-300:
        return float("inf")
    return k / math.sqrt(Q)


def efficiency_derivative(k: float, alpha0: float) -> float:
    """``d lambda0/dk`` at fixed ``alpha0``, l.1082: ``(1 + k c)/Q^(3/2)``, ``c = cos(alpha0)``."""
    c = math.cos(alpha0)
    Q = 1 + 2 * k * c + k * k
    return (1 + k * c) / Q ** 1.5


def efficiency_second_derivative(k: float, alpha0: float, *, literal: bool = False) -> float:
    """``d^2 lambda0/dk^2`` at fixed ``alpha0``.

    Default: the general form ``(-2c - 3k - k c^2 - 2 k^2 c)/Q^(5/2)`` (derived
    with sympy).  ``literal=True``: the printed l.1092 ``-k sin^2(alpha0)/Q^(5/2)``,
    which equals it only at the stationary point ``k = -1/c`` (digest 2.8 flag).
    """
    c = math.cos(alpha0)
    Q = 1 + 2 * k * c + k * k
    if literal:
        return -k * math.sin(alpha0) ** 2 / Q ** 2.5
    return (-2 * c - 3 * k - k * c * c - 2 * k * k * c) / Q ** 2.5


@dataclass(frozen=True)
class EfficiencyExtremum:
    """Extremum of ``lambda0(k)`` at fixed ``alpha0`` (section 2.3.3).

    Attributes
    ----------
    k_star : float
        ``-1/cos(alpha0)`` [-] (l.1084).
    lambda_max : float
        ``1/|sin(alpha0)|`` [-] (l.1100); inf at ``alpha0 = pi``.
    valid, flags
        Flagged when ``cos(alpha0) >= 0`` (no maximum with ``k > 0``).
    """

    k_star: float
    lambda_max: float
    valid: bool
    flags: Tuple[str, ...]


def efficiency_extremum(alpha0: float) -> EfficiencyExtremum:
    """Maximum of (2.14) over k at fixed ``alpha0`` [rad] (section 2.3.3, l.1084-1100)."""
    alpha0 = THESIS.finite("alpha0", alpha0, "rad")
    c, s = math.cos(alpha0), math.sin(alpha0)
    flags = []
    if c >= 0:
        flags.append(f"cos(alpha0) = {c:.4g} >= 0: no maximum for k > 0 (alpha0 must be in (pi/2, 3pi/2))")
        return EfficiencyExtremum(float("nan"), float("nan"), *_result_flags(flags))
    lam = float("inf") if abs(s) < 1e-15 else 1.0 / abs(s)
    return EfficiencyExtremum(-1.0 / c, lam, *_result_flags(flags))


# --------------------------------------------------------------------------- quasi-static model
@dataclass(frozen=True)
class QuasiStaticResult:
    """Steady state of the damped quasi-static model at one speed.

    Attributes
    ----------
    omega, gamma : float
        Speed [rad/s] and ``omega/omega_cr`` [-].
    delta : float
        Phase lag (2.5) [rad].
    deflection_factor : float
        ``H = f/e_c`` (2.7) [-].
    k : float
        ``D0/D`` [-].
    alpha0 : float
        Liquid equilibrium angle [rad] (corrected (2.13), or printed if literal).
    lambda0 : float
        Efficiency (2.14) [-].
    e0, e, e_c : float
        Rotor, liquid and system CoM eccentricities [m] (about the system mass).
    f : float
        Shaft deflection at the chamber [m].
    D0, D : float
        Rotor and liquid unbalance [kg m] (x 1e5 for g cm).
    r, layer : float
        Free-surface radius and ``R - r`` [m].
    k_alt, lambda0_alt : float
        The second self-consistent state when it exists (smaller k), else NaN.
    literal : bool
        True for the App. B algorithm as printed.
    valid, flags
    """

    omega: float
    gamma: float
    delta: float
    deflection_factor: float
    k: float
    alpha0: float
    lambda0: float
    e0: float
    e: float
    e_c: float
    f: float
    D0: float
    D: float
    r: float
    layer: float
    k_alt: float
    lambda0_alt: float
    literal: bool
    valid: bool
    flags: Tuple[str, ...]


def quasi_static_efficiency(p: LiquidChamberParams, omega: float, *, literal: bool = False,
                            g: float = G_STANDARD, gravity_tol: float = 0.1) -> QuasiStaticResult:
    """Balancing efficiency of the damped quasi-static model (section 2.2.2.1).

    Default (corrected, the digest's self-consistent closure, section 4.6):
    (2.4) ``e = m/(M+m) r^2/(R^2-r^2) f = G' f`` with ``G' = rho pi h
    r^2/(M+m)``; (2.7) ``f = e_c H``; ``e_c = e sqrt(Q)`` with the corrected
    (2.13), for which ``sqrt(Q) = |sqrt(k^2 - sin^2 d) - |cos d||``.  Hence
    ``sqrt(Q) = 1/(G' H)``, solved in closed form::

        sqrt(k^2 - sin^2 d) = |cos d| +- 1/(G' H),   lambda0 = k G' H

    (independent of D0; D0 fixes the scale ``e = e0/k``, ``f = e/G'``).  The
    ``+`` root (larger k, the one the digest reports) is returned; the other,
    when it exists, is ``k_alt`` and flagged as an ambiguity.

    ``literal=True``: App. B / OPTIMUM_KAMERA as printed: ``e0 = D0/m_d``
    (= e_d), ``f = e0 H`` (empty-rotor deflection), ``e = r^2 f/(R^2 - r^2)``
    (no ``m/(M+m)``), ``D = e m``, ``k = D0/D``, printed (2.13).

    Parameters
    ----------
    p : LiquidChamberParams
    omega : float
        Spin [rad/s], > 0.
    literal : bool
    g, gravity_tol : float
        See :func:`fill_geometry`.

    Returns
    -------
    QuasiStaticResult
        Flags (each makes ``valid`` False): fill outside the annular-layer
        model (see :func:`fill_geometry`); ``omega > omega_cr`` (the model is
        derived below the critical speed; the thesis extends it only
        qualitatively, section 2.2.2.3); ``2 n omega > omega_cr^2``; no
        self-consistent state (``G'H <= 0`` or ``k < sin d``); sufficiency
        ``f <= R - r_top`` violated; two self-consistent states; literal mode.
    """
    omega = THESIS.positive("omega", omega, "rad/s")
    wc = p.critical_speed
    n = p.n
    R, h, rho, V = p.chamber_radius, p.chamber_height, p.liquid_density, p.liquid_volume
    nan = float("nan")
    gamma = omega / wc
    flags = []
    geo = fill_geometry(R, h, V, omega, p.inclination, g=g, gravity_tol=gravity_tol)
    flags.extend(geo.flags)
    if literal:
        flags.append("thesis-literal: App. B algorithm with printed (2.13) (no 1/k), e0 = D0/m_d, "
                     "no m/(M+m); not a physical prediction")
    if omega > wc:
        flags.append(f"supercritical: omega = {omega:.4g} rad/s > omega_cr = {wc:.4g} rad/s; the damped "
                     "quasi-static model (2.4)-(2.14) is derived for omega < omega_cr (section 2.2.2.1)")
    delta = phase_lag(omega, wc, n)
    s2 = math.sin(delta) ** 2
    a = 2 * n * omega / wc ** 2
    D0 = p.rotor_unbalance
    r = geo.r

    def out(H=nan, k=nan, alpha0=nan, lam=nan, e0=nan, e=nan, e_c=nan, f=nan, D=nan, k_alt=nan,
            lam_alt=nan):
        valid, fl = _result_flags(flags)
        return QuasiStaticResult(omega, gamma, delta, H, k, alpha0, lam, e0, e, e_c, f, D0, D, r,
                                 R - r, k_alt, lam_alt, literal, valid, fl)

    if a > 1.0:
        flags.append(f"2 n omega/omega_cr^2 = {a:.4g} > 1: no real phi in (2.8)")
        return out()
    if not (r == r) or V == 0.0 or r == 0.0:
        return out()
    H = deflection_factor(omega, wc, n)
    r_top = geo.r_top if geo.r_top == geo.r_top else r

    if literal:
        if p.unbalance_mass <= 0:
            flags.append("literal App. B needs m_d > 0 (e0 = D0/m_d)")
            return out(H=H)
        e0 = D0 / p.unbalance_mass
        f = e0 * H
        e = r * r / (R * R - r * r) * f
        D = e * p.liquid_mass
        if D <= 0:
            flags.append(f"liquid unbalance D = {D:.3g} kg m <= 0: k undefined")
            return out(H=H, e0=e0, f=f, e=e, D=D)
        k = D0 / D
        eq = equilibrium_angle(k, delta, literal=True)
        flags.extend(fl for fl in eq.flags if not fl.startswith("thesis-literal"))
        lam = efficiency(k, eq.alpha0) if eq.alpha0 == eq.alpha0 else nan
        if abs(f) > R - r_top:
            flags.append(f"sufficiency violated: f = {abs(f):.4g} m > R - r = {R - r_top:.4g} m")
        return out(H=H, k=k, alpha0=eq.alpha0, lam=lam, e0=e0, e=e, f=f, D=D)

    M_tot = p.total_mass
    Gp = rho * math.pi * h * r * r / M_tot
    GH = Gp * H
    e0 = D0 / M_tot
    if GH <= 0:
        flags.append(f"no self-consistent state: G'H = {GH:.4g} <= 0 (deflection factor H = {H:.4g})")
        return out(H=H, e0=e0)
    c = math.sqrt(max(1.0 - s2, 0.0))
    roots = [q for q in (c + 1.0 / GH, c - 1.0 / GH) if q > 0]
    if not roots:
        flags.append("no self-consistent state (k < sin(delta))")
        return out(H=H, e0=e0)
    ks = [math.sqrt(s2 + q * q) for q in roots]
    k = ks[0]
    eq = equilibrium_angle(k, delta)
    lam = k * GH
    k_alt = lam_alt = nan
    if len(ks) > 1:
        k_alt, lam_alt = ks[1], ks[1] * GH
        flags.append(f"two self-consistent states (k = {k:.4g}, {k_alt:.4g}); the larger k is reported, "
                     "selection not established by a stability analysis")
    if D0 <= 0:
        flags.append("no rotor unbalance (D0 = 0): nothing to balance")
        return out(H=H, k=k, alpha0=eq.alpha0, lam=lam, e0=e0, k_alt=k_alt, lam_alt=lam_alt)
    e = e0 / k
    f = e / Gp
    e_c = e / GH
    D = e * M_tot
    if f > R - r_top:
        flags.append(f"sufficiency violated: f = {f:.4g} m > R - r = {R - r_top:.4g} m "
                     "(free surface leaves the chamber; x_p of l.668 invalid)")
    return out(H=H, k=k, alpha0=eq.alpha0, lam=lam, e0=e0, e=e, e_c=e_c, f=f, D=D, k_alt=k_alt,
               lam_alt=lam_alt)
