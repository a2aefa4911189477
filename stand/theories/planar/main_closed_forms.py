"""Closed forms of the main-motion theory beside the numerics (book (5.96)-(5.128)).

Digest ch5 sections 4.2-4.4: the damped critical speeds to first and second
order (5.125)-(5.127) with their smallness parameter (5.128), the high-speed
ball-drag threshold (5.96), the conservative series and parametric forms
(5.102)-(5.107), the stability window for large support damping (5.97) and
the slow balancing roots.  Dimensionless parameters as in
:mod:`stand.theories.planar.main_charpoly` (R, Rt, h, H, d); the exact values come from
:mod:`stand.theories.planar.main_critical`.
"""
from __future__ import annotations

import math

import numpy as np
from scipy.optimize import brentq

__all__ = [
    "R1_first_order", "R1_refined", "R1_max_closed_form", "R1_max_validity",
    "high_speed_h_crit",
    "conservative_series_k0", "conservative_R1_parametric", "conservative_R1_k1",
    "conservative_R1_series", "conservative_R23_k1", "R_window_large_H",
    "balancing_rate",
]

_RTOL = 4 * np.finfo(float).eps   # the smallest rtol brentq accepts


def R1_first_order(Rt, h, H, d):
    """First-order damped critical speed (5.125).

    R1 = 1 + Rt (2h + H) / (2 h^2 H) (1 - d^2); stability is gained above it.
    Valid for Rt / (2 h^2 H) small (5.128).
    """
    return 1.0 + Rt * (2.0 * h + H) / (2.0 * h * h * H) * (1.0 - d * d)


def R1_refined(Rt, h, H, d):
    """Second-order damped critical speed (5.126).

    R1 = (5.125) + Rt^2 (1-d^2) / (8 h^4 H^2) [H (7H + 12h)(1-d^2) - 4 d^2 h (3H + 5h)].
    """
    k = 1.0 - d * d
    return (R1_first_order(Rt, h, H, d)
            + Rt * Rt * k / (8.0 * h ** 4 * H * H) * (H * (7.0 * H + 12.0 * h) * k
                                                       - 4.0 * d * d * h * (3.0 * H + 5.0 * h)))


def R1_max_closed_form(Rt, h, H):
    """Largest damped critical speed over d, reached at d = 0 (5.127).

    R1max = 1 + Rt (2h + H)/(2 h^2 H) + Rt^2 (7H + 12h)/(8 h^4 H); the smallest
    is 1 (d = 1).  The book's validity claim (10 %) needs Rt/(2 h^2 H) < 1 (5.128)
    and, per the digest, d = 0 being the worst case, which fails at low damping
    (use :func:`unbalance_independent_threshold`).
    """
    return (1.0 + Rt * (2.0 * h + H) / (2.0 * h * h * H)
            + Rt * Rt * (7.0 * H + 12.0 * h) / (8.0 * h ** 4 * H))


def R1_max_validity(Rt, h, H):
    """The smallness parameter Rt / (2 h^2 H) of (5.128) (closed forms good when < 1)."""
    return Rt / (2.0 * h * h * H)


def high_speed_h_crit(Rt, H):
    """High-speed stability threshold h > H sqrt(Rt) (5.96), the worst case d = 0.

    If h < H sqrt(Rt) balancing is lost at high speed.
    """
    return H * math.sqrt(Rt)


def conservative_series_k0(Rt):
    """Series (5.103) for the 2nd and 3rd conservative critical speeds at k = 0 (d = 1).

    R2 = 1 + 49/16 Rt + 12397/1024 Rt^2,
    R3 = 1 + 2 (Rt/2)^(1/3) + 7/3 (Rt/2)^(2/3) + 29/8 (Rt/2).
    The first is R1 = 1 (5.102).  Stated range 0 < Rt < 0.05 (error <= 0.7 % at
    Rt = 0.01, <= 7 % at 0.05); the printed form for 0.05 <= Rt < 0.25 is garbled
    (digest 4.2) and not provided.

    Returns
    -------
    (float, float)
        (R2, R3).
    """
    q = Rt / 2.0
    return (1.0 + 49.0 / 16.0 * Rt + 12397.0 / 1024.0 * Rt * Rt,
            1.0 + 2.0 * q ** (1.0 / 3.0) + 7.0 / 3.0 * q ** (2.0 / 3.0) + 29.0 / 8.0 * q)


def conservative_R1_parametric(u):
    """Parametric first conservative critical speed at k = 1 (d = 0), (5.105) corrected.

    Rt = (u^3 / (1 - 2u^2))^2,  R1 = sqrt(1 - u^2) / (1 - 2u^2),  0 < u < 1/sqrt 2
    (the exponent 2 is the digest's correction of the printed 1/2).

    Returns
    -------
    (float, float)
        (Rt, R1).
    """
    u = float(u)
    if not 0.0 < u < math.sqrt(0.5):
        raise ValueError("conservative_R1_parametric: need 0 < u < 1/sqrt(2)")
    q = 1.0 - 2.0 * u * u
    return (u ** 3 / q) ** 2, math.sqrt(1.0 - u * u) / q


def conservative_R1_k1(Rt):
    """First conservative critical speed at k = 1 (d = 0) from (5.105), solved for u.

    Exact within the conservative theory (the roots x of P1 (5.104) turn purely
    imaginary there); Rt(u) increases monotonically on (0, 1/sqrt 2).
    """
    Rt = float(Rt)
    if not 0.0 < Rt < 0.5:
        raise ValueError("conservative_R1_k1: need 0 < Rt < 0.5")
    u = brentq(lambda u: conservative_R1_parametric(u)[0] - Rt, 1e-9, math.sqrt(0.5) - 1e-12,
               xtol=1e-15, rtol=_RTOL)
    return conservative_R1_parametric(u)[1]


def conservative_R1_series(Rt):
    """Series (5.106): R1(Rt, k=1) = 1 + 3/2 Rt^(1/3) + 7/8 Rt^(2/3) + Rt/48.

    The book claims a maximum error of 1.08 % (at Rt = 0.5).
    """
    c = Rt ** (1.0 / 3.0)
    return 1.0 + 1.5 * c + 0.875 * c * c + Rt / 48.0


def conservative_R23_k1(Rt):
    """Touching double root (5.107) of the conservative case at k = 1 (d = 0).

    R2 = R3 = sqrt(2 (1 - 2 Rt)) / (1 - 4 Rt) for 0.04173 < Rt < 0.25: stability is
    not lost at k = 1 itself, but for slightly smaller k the touch opens into a
    thin unstable band around this speed (Rt = 0.05, d = 0.02: (1.6709, 1.6835)).
    At Rt = 0.04173 it meets R1 (1.6252).

    Returns
    -------
    float
        nan outside 0 < Rt < 0.25.
    """
    Rt = float(Rt)
    if not 0.0 < Rt < 0.25:
        return math.nan
    return math.sqrt(2.0 * (1.0 - 2.0 * Rt)) / (1.0 - 4.0 * Rt)


def R_window_large_H(Rt, h):
    """Stability window for H >> 1, (5.97): R in (R1, R2) when 4 Rt < h and p < 1.

    R_{1,2} = [1 -+ (1 - p^2)^(1/2)]^(1/2) / p,  p = (2 Rt)^(1/2) / h.  The book's
    estimate; the digest found the upper end rough (Rt = 0.01, h = 0.5, H = 1000:
    exact 4.897 vs 4.949) and the lower end effectively 1.

    Returns
    -------
    (float, float) or None
        None when p >= 1 (no window).
    """
    p = math.sqrt(2.0 * Rt) / h
    if p >= 1.0:
        return None
    r = math.sqrt(1.0 - p * p)
    return math.sqrt(1.0 - r) / p, math.sqrt(1.0 + r) / p


def balancing_rate(R, Rt, h, H, d):
    """Slow balancing roots l7, l8 of digest section 4.3 (small Rt or large h).

    l_{7,8} = -Rt R^4 [R^2 - 1 +- sqrt((R^2-1)^2 d^2 - H^2 R^2 (1-d^2))]
              / (h [(R^2-1)^2 + H^2 R^2]).

    The residual unbalance |psi| decays like exp(-r tau) with r = -max Re l; for
    R >> 1 the roots tend to -Rt (1 +- d)/h, a time constant h / (Rt (1 - d)).

    Returns
    -------
    ndarray of complex, shape (2,)
        (l7, l8) with the + sign first (complex when the radicand is negative).
    """
    W2 = float(R) ** 2
    s = W2 - 1.0
    rad = np.sqrt(complex(s * s * d * d - H * H * W2 * (1.0 - d * d)))
    den = h * (s * s + H * H * W2)
    return np.array([-Rt * W2 * W2 * (s + rad) / den, -Rt * W2 * W2 * (s - rad) / den])
