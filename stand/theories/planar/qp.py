"""Quasi-periodic ("stuck-ball") motions of a ball autobalancer: roots, thresholds, stability.

Digest ch5 section 5 (book section 5.5).  With e0 = 0 all balls stick together
at one angle gamma of a frame turning at a constant speed Omega (5.175)-(5.180);
the shaft whirls on the circle (units of r*)

    s~ = Omega^2 e^{i gamma} / (1 - Omega^2 + i H Omega),

and the torque balance on the balls gives the corrected frequency equation
(5.181)

    P(Omega) = 2 R_mH Omega^5 - (R - Omega) D(Omega) = 0,
    D(w) = (1 - w^2)^2 + H^2 w^2,       R_mH = Rt H / h.

All quantities are dimensionless (digest ch5 section 2.2): ``R`` = omega/omega_1
(the book's R_omega), ``Omega`` in units of omega_1, ``Rt`` = R~_m = n m / (2 M_Sigma)
(0 <= Rt < 0.5), ``h`` the ball drag, ``H`` the support damping, ``e0`` the rotor
unbalance in units of the balancing capacity.

The frequency equation and its curve R(Omega) (the inverse of (5.181)) are in
:mod:`stand.theories.planar.qp_curve`; the laser-spot law (5.237) in
:mod:`stand.theories.planar.qp_spot`.  This module gathers all of them.

Root finding
------------
P is linear in R, so every Omega > 0 belongs to exactly one speed R(Omega)
(:func:`speed_of_precession`), and the QP roots at a speed R are the
intersections of this curve with the horizontal line R.  The root count
changes only at the local extrema of R(Omega) (Table 5.1-A), which lie in
(1, sqrt 5) and exist only for H below about 0.7136 (located in
:mod:`stand.theories.planar.qp_curve`).  Between consecutive extrema R(Omega) is
monotonic and ``brentq`` solves R(Omega) = R on each branch, so nearly double
roots are never lost.

Thresholds (5.182), (5.191), (5.201) and stability (5.210)-(5.216) complete
the module.
"""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from stand.theories.planar.qp_curve import (_D, _EPS, _RTOL, QPWarning, _check, _extrema, _params, _RmH,
                       dspeed_dOmega, frequency_polynomial, speed_of_precession)
from stand.theories.planar.qp_spot import SpotLaw, epitrochoid, spot_law

__all__ = [
    "QPWarning", "QPThresholds", "QPStability", "SpotLaw",
    "speed_of_precession", "dspeed_dOmega", "frequency_polynomial", "qp_roots",
    "qp_thresholds", "escape_speed", "qp_stability", "collective_coefficients",
    "spot_law", "epitrochoid",
]


# ---------------------------------------------------------------------------
# roots
# ---------------------------------------------------------------------------

def _degenerate_roots(R, Rt, h, H):
    """Roots for h = 0, H = 0 or Rt = 0 (None if the case is regular)."""
    if h == 0.0:
        if Rt > 0.0 and H > 0.0:
            warnings.warn(QPWarning(
                "qp_roots: h = 0, the balls feel no drive; the resistance 2 Rt H Omega^5/D "
                "stops them (Omega -> 0): no QP motion, returning an empty array"), stacklevel=3)
        else:
            warnings.warn(QPWarning(
                "qp_roots: h = 0 and Rt H = 0: neither drive nor resistance acts on the "
                "balls, every Omega is a neutral steady state; returning an empty array"),
                stacklevel=3)
        return np.empty(0)
    if Rt == 0.0:
        # R(Omega) = Omega: the balls are carried with the rotor (limit Rt -> 0+)
        return np.array([R]) if R > 0 else np.empty(0)
    if H == 0.0:
        warnings.warn(QPWarning(
            "qp_roots: H = 0, the whirl amplitude at Omega = 1 is infinite; returning the "
            "limits H -> 0+ of the roots: [R] for R <= 1, [1, 1, R] for R > 1 (two roots "
            "merge at the resonance, the third tends to R)"), stacklevel=3)
        if R <= 0:
            return np.empty(0)
        return np.array([R]) if R <= 1.0 else np.array([1.0, 1.0, R])
    return None


def qp_roots(R, Rt, h, H):
    """Real roots Omega in (0, R) of the frequency equation (5.181), sorted.

    Solves R(Omega) = R (see :func:`speed_of_precession`) on each monotonic
    branch of R(Omega) between its local extrema, so that a nearly double root
    is found as two close roots (an exactly double root is returned once).

    Parameters
    ----------
    R : float
        Rotor speed omega/omega_1 >= 0.
    Rt, h, H : float
        R~_m, ball drag, support damping (>= 0, Rt < 0.5).

    Returns
    -------
    ndarray
        Precession speeds of the QP motions.  Number of roots (digest Table in
        section 5.1): one below R*_omega1 (Omega_1 < 1), three between R*_omega1
        and R*_omega2, one (close to R) above R*_omega2.  Degenerate inputs:

        * ``h = 0``: no drive on the balls -> empty array and a :class:`QPWarning`;
        * ``Rt = 0``: R(Omega) = Omega, the only root is Omega = R (no warning);
        * ``H = 0``: the limits H -> 0+ of the roots, ``[R]`` for R <= 1 and
          ``[1, 1, R]`` for R > 1, with a :class:`QPWarning`.

    Raises
    ------
    ValueError
        A negative or non-finite parameter (the message names it), or Rt >= 0.5.

    Examples
    --------
    Table 5.1-B (Rt = 0.01, h = H = 0.05):

    >>> qp_roots(3.0, 0.01, 0.05, 0.05).round(5)
    array([0.96135, 1.04953, 2.92502])
    """
    R = _check("R", R)
    Rt, h, H = _params(Rt, h, H)
    deg = _degenerate_roots(R, Rt, h, H)
    if deg is not None:
        return deg
    if R == 0.0:
        return np.empty(0)
    ext = _extrema(Rt, h, H)
    ext = ext[ext < R]          # R(Omega) > Omega, so no root lies at or beyond R
    ends = np.concatenate([[0.0], ext, [R]])
    g = speed_of_precession(ends, Rt, h, H) - R
    g[0], g[-1] = -R, max(g[-1], R * _EPS)   # R(0) = 0; R(R) > R
    tiny = np.abs(g[1:-1]) <= 8 * _EPS * R
    if np.any(tiny):
        warnings.warn(QPWarning(
            f"qp_roots: R = {R!r} equals a threshold speed R(Omega) of a local extremum "
            f"(Omega = {ext[tiny]}) to within rounding; that double root is returned once "
            "and the root count there is ambiguous"), stacklevel=2)
        g[1:-1][tiny] = 0.0
    roots = []
    for a, b, ga, gb in zip(ends[:-1], ends[1:], g[:-1], g[1:]):
        if ga == 0.0:
            roots.append(a)
        elif ga * gb < 0.0:
            roots.append(brentq(lambda w: speed_of_precession(w, Rt, h, H) - R, a, b,
                                xtol=4 * _EPS * b, rtol=_RTOL, maxiter=500))
    return np.unique(np.asarray(roots, dtype=float))


# ---------------------------------------------------------------------------
# thresholds
# ---------------------------------------------------------------------------

def escape_speed(Rt, h, H):
    """Speed R*_omega = 1 + 2 R_mH / H^2 = 1 + 2 Rt / (h H), (5.182) = (5.226).

    Below it the stable QP motion Omega_1 < 1 exists; at R = R*_omega, Omega_1 = 1
    exactly; above it the balls escape from the QP motion.  ``inf`` when h H = 0
    and Rt > 0.
    """
    Rt, h, H = _params(Rt, h, H)
    if Rt == 0.0:
        return 1.0
    if h * H == 0.0:
        return math.inf
    return 1.0 + 2.0 * Rt / (h * H)


@dataclass(frozen=True)
class QPThresholds:
    """Speeds where the number of QP roots changes (digest Table 5.1-A).

    Attributes
    ----------
    one_to_three : float or None
        Exact R*_omega1, the local minimum of R(Omega): three roots appear above
        it.  None when R(Omega) is monotonic (always one root).
    three_to_one : float or None
        Exact R*_omega2, the local maximum of R(Omega): two roots merge and
        vanish above it.
    escape : float
        R*_omega of (5.182)/(5.226).
    approx_one_to_three : float
        (5.191) as in the digest: 1 + 1.5 R_mH^(1/3).
    approx_three_to_one : float
        (5.201): 1 + 2 R_mH / H^2 + 9/8 R_mH.
    Omega_one_to_three, Omega_three_to_one : float or None
        The (double) root at each threshold.
    Omega_extrema, R_extrema : ndarray
        All local extrema of R(Omega) (normally two).
    RmH : float
        R_mH = Rt H / h.
    """
    one_to_three: float | None
    three_to_one: float | None
    escape: float
    approx_one_to_three: float
    approx_three_to_one: float
    Omega_one_to_three: float | None
    Omega_three_to_one: float | None
    Omega_extrema: np.ndarray
    R_extrema: np.ndarray
    RmH: float


def qp_thresholds(Rt, h, H):
    """Exact and approximate speeds at which QP roots appear and disappear.

    The thresholds are the local extrema of R(Omega) (:func:`speed_of_precession`);
    between them three QP motions coexist.  The exact values are returned beside
    the book's approximations (5.191) and (5.201) and the escape speed (5.182).

    Parameters
    ----------
    Rt, h, H : float
        R~_m, ball drag, support damping.

    Returns
    -------
    QPThresholds

    Notes
    -----
    Three roots exist only if R(Omega) has extrema, which requires (5.202)
    roughly, R_mH / H^3 > 3 sqrt(3) / 8, and always H < 0.7136.  Degenerate inputs:
    ``h = 0`` -> no thresholds, escape = inf (QPWarning); ``H = 0`` -> the limits
    H -> 0+: one_to_three = 1, three_to_one = inf (QPWarning); ``Rt = 0`` -> no
    thresholds, escape = 1.

    Examples
    --------
    >>> t = qp_thresholds(0.01, 0.05, 0.05)       # R_mH = 0.01, H = 0.05
    >>> round(t.one_to_three, 5), round(t.three_to_one, 5), round(t.escape, 12)
    (1.44019, 9.01222, 9.0)
    >>> round(t.approx_one_to_three, 4), round(t.approx_three_to_one, 5)
    (1.3232, 9.01125)
    """
    Rt, h, H = _params(Rt, h, H)
    esc = escape_speed(Rt, h, H)
    empty = np.empty(0)
    if h == 0.0:
        warnings.warn(QPWarning("qp_thresholds: h = 0, no QP motion exists"), stacklevel=2)
        return QPThresholds(None, None, esc, math.inf, math.inf, None, None, empty, empty,
                            math.inf if Rt * H > 0 else math.nan)
    RmH = _RmH(Rt, h, H)
    a1 = 1.0 + 1.5 * RmH ** (1.0 / 3.0)
    if Rt == 0.0:
        return QPThresholds(None, None, esc, a1, 1.0, None, None, empty, empty, RmH)
    if H == 0.0:
        warnings.warn(QPWarning(
            "qp_thresholds: H = 0, returning the limits H -> 0+ (one_to_three = 1, "
            "three_to_one = inf)"), stacklevel=2)
        return QPThresholds(1.0, math.inf, esc, a1, math.inf, 1.0, 1.0,
                            np.array([1.0, 1.0]), np.array([1.0, math.inf]), RmH)
    a2 = 1.0 + 2.0 * RmH / H ** 2 + 9.0 / 8.0 * RmH
    ext = _extrema(Rt, h, H)
    Rext = speed_of_precession(ext, Rt, h, H) if ext.size else empty
    up, lo = None, None
    w_up = w_lo = None
    if ext.size >= 2:
        # extrema alternate max, min, max, ... (dR/dOmega > 0 at both ends)
        imax = np.arange(0, ext.size, 2)
        imin = np.arange(1, ext.size, 2)
        i_up = imax[np.argmax(Rext[imax])]
        i_lo = imin[np.argmin(Rext[imin])]
        up, lo = float(Rext[i_up]), float(Rext[i_lo])
        w_up, w_lo = float(ext[i_up]), float(ext[i_lo])
        if ext.size > 2:
            warnings.warn(QPWarning(
                f"qp_thresholds: R(Omega) has {ext.size} extrema (speeds {Rext}); the "
                "root count changes at each of them"), stacklevel=2)
    return QPThresholds(lo, up, esc, a1, a2, w_lo, w_up, ext, np.asarray(Rext), RmH)


# ---------------------------------------------------------------------------
# stability
# ---------------------------------------------------------------------------

def collective_coefficients(Omega, Rt, h, H):
    """b0..b5 of the collective-mode polynomial, (5.213)-(5.216) as in the digest.

    With v = 2 Omega^4 (1 - Omega^2) / D(Omega) (corrected (5.214): no R~_m in v)::

        b0 = h[(Omega^2-1)^2 + H^2 Omega^2] + 2 H Rt [(1+Omega^2) v + 3 Omega^4]
        b1 = (1-Omega^2)^2 + H^2 Omega^2 + 2 h H (1+Omega^2)
             + Rt {[2(1+Omega^2) + H^2] v + 2 Omega^2 (6+Omega^2)}
        b2 = 2(h+H)(1+Omega^2) + 2 Rt (2 Omega^2 + v) H + h H^2
        b3 = 2(1+Omega^2)(1-Rt) + v Rt + H(H+2h)
        b4 = 2H(1-Rt) + h,      b5 = 1 - 2 Rt

    Returns
    -------
    ndarray
        ``[b0, b1, b2, b3, b4, b5]`` (lowest power first).
    """
    W2 = Omega * Omega
    D = float(_D(Omega, H))
    v = 2.0 * W2 * W2 * (1.0 - W2) / D
    b0 = h * D + 2.0 * H * Rt * ((1.0 + W2) * v + 3.0 * W2 * W2)
    b1 = D + 2.0 * h * H * (1.0 + W2) + Rt * ((2.0 * (1.0 + W2) + H * H) * v
                                              + 2.0 * W2 * (6.0 + W2))
    b2 = 2.0 * (h + H) * (1.0 + W2) + 2.0 * Rt * (2.0 * W2 + v) * H + h * H * H
    b3 = 2.0 * (1.0 + W2) * (1.0 - Rt) + v * Rt + H * (H + 2.0 * h)
    b4 = 2.0 * H * (1.0 - Rt) + h
    b5 = 1.0 - 2.0 * Rt
    return np.array([b0, b1, b2, b3, b4, b5])


@dataclass(frozen=True)
class QPStability:
    """Linear stability of a QP motion, (5.210)-(5.216).

    Attributes
    ----------
    v : float
        2 Omega^4 (1 - Omega^2) / D(Omega).
    relative_roots : ndarray
        Roots of lambda^2 + h lambda + Rt v = 0 (5.210), the n - 1 identical
        relative (ball-against-ball) modes; empty for n = 1.
    b : ndarray
        b0..b5 of (5.213)-(5.216).
    collective_roots : ndarray
        The 5 roots of b5 lambda^5 + ... + b0; the factor lambda (the zero root of
        the one-parameter family in gamma) is excluded.
    abscissa : float
        Largest real part over relative and collective roots.
    stable : bool
        ``abscissa < 0`` (asymptotic stability up to the neutral family direction).
    residual : float
        R(Omega) - R: how far ``Omega`` is from a QP root of speed ``R``.
    """
    v: float
    relative_roots: np.ndarray
    b: np.ndarray
    collective_roots: np.ndarray
    abscissa: float
    stable: bool
    residual: float


def qp_stability(Omega, R, Rt, h, H, *, n=2):
    """Stability of the QP motion with precession speed ``Omega`` at speed ``R``.

    Relative modes (5.210): lambda^2 + h lambda + Rt v = 0, v = 2 Omega^4 (1 - Omega^2)/D,
    hence the necessary condition Omega < 1 (5.211).  Collective mode
    (5.213)-(5.216): lambda (b5 lambda^5 + ... + b0) = 0 (see
    :func:`collective_coefficients`).  The conclusion (5.226): only Omega_1 < 1 is
    stable, throughout 0 < R < R*_omega.

    Parameters
    ----------
    Omega : float
        Precession speed, normally a root from :func:`qp_roots`.
    R : float
        Rotor speed; only used to check that ``Omega`` is a QP root (a
        :class:`QPWarning` is issued if R(Omega) differs from R by more than 1e-6
        relative).
    Rt, h, H : float
        R~_m, ball drag, support damping.
    n : int
        Number of balls (n - 1 relative modes; none for n = 1).

    Returns
    -------
    QPStability

    Examples
    --------
    The digest's example (Rt = 0.01, h = H = 0.05, R = 3, Omega_1 = 0.96135):

    >>> s = qp_stability(qp_roots(3, 0.01, 0.05, 0.05)[0], 3, 0.01, 0.05, 0.05)
    >>> s.stable, complex(s.relative_roots[-1].round(5)), float(s.collective_roots.real.min().round(5))
    (True, (-0.025+0.40014j), -0.04492)
    """
    Rt, h, H = _params(Rt, h, H)
    Omega = _check("Omega", Omega)
    R = _check("R", R)
    if int(n) != n or n < 1:
        raise ValueError(f"n must be a positive integer, got {n!r}")
    if Rt * H > 0 and h > 0:
        Rw = speed_of_precession(Omega, Rt, h, H)
        residual = Rw - R
        if abs(residual) > 1e-6 * max(1.0, R):
            warnings.warn(QPWarning(
                f"qp_stability: Omega = {Omega} is not a QP root at R = {R} "
                f"(it belongs to R = {Rw})"), stacklevel=2)
    else:
        residual = math.nan
    W2 = Omega * Omega
    v = 2.0 * W2 * W2 * (1.0 - W2) / float(_D(Omega, H))
    rel = np.roots([1.0, h, Rt * v]) if n >= 2 else np.empty(0, dtype=complex)
    b = collective_coefficients(Omega, Rt, h, H)
    col = np.roots(b[::-1])
    allr = np.concatenate([rel, col])
    absc = float(np.max(allr.real))
    return QPStability(v=v, relative_roots=np.sort_complex(rel.astype(complex)), b=b,
                       collective_roots=np.sort_complex(col.astype(complex)),
                       abscissa=absc, stable=absc < 0.0, residual=residual)
