"""The laser-spot law of a quasi-periodic motion: precession plus nutation, (5.229)-(5.243).

Digest ch5 section 5.3 (book section 5.5).  A QP motion (a root Omega of the
frequency equation (5.181), :func:`stand.theories.planar.qp.qp_roots`) of a rotor with
a small unbalance e0 moves the shaft -- and the laser spot on the screen -- on
the epitrochoid (5.237), the sum of the precession at Omega and the nutation
at the rotor speed R.  Dimensionless units (digest ch5 section 2.2): speeds in
omega_1, amplitudes in r* (or in the track radius l), e0 in units of the
capacity, H the support damping.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction

import numpy as np

from stand.theories.planar.qp_curve import _D, _check

__all__ = ["SpotLaw", "spot_law", "epitrochoid"]


@dataclass(frozen=True)
class SpotLaw:
    """The shaft (laser-spot) trajectory of a QP motion, (5.229)-(5.243).

    z(tau) = A_P e^{i(Omega tau + phase_P)} + A_N e^{i(R tau + phase_N)}; after the
    time and angle shift (5.230)-(5.236) it is the epitrochoid (5.237)
    Z = A_P e^{i Omega T} + A_N e^{i R T}.

    Attributes
    ----------
    A_P, A_N : float
        Precession and nutation amplitudes in units of r* (5.229):
        A_P = Omega^2 / sqrt(D(Omega)), A_N = e0 R^2 / sqrt(D(R)).
    A_P_l, A_N_l : float or None
        The same in units of the track radius l, (5.237): multiplied by
        R_m = n m / M_Sigma (r* = R_m l); None if R_m was not given.
    gamma1, gamma2 : float
        Phase angles of (5.231): cos g1 = (1-Omega^2)/sqrt(D(Omega)),
        sin g1 = H Omega / sqrt(D(Omega)), cos g2 = (R^2-1)/sqrt(D(R)),
        sin g2 = H R / sqrt(D(R)).
    phase_P, phase_N : float
        Phases of the two terms of z(tau): gamma - gamma1 and gamma2 - pi.
    k : float
        R / Omega.
    p, q : int or None
        k = p/q in lowest terms (q = 1: integer k) if k is rational with a small
        denominator, else None (irrational: the pattern never closes).
    petals : int or None
        p - q (= k - 1 for integer k), (5.239)-(5.240).
    period : float
        Closing time 2 pi q / Omega (inf if the curve never closes).
    ratio : float
        A_P Omega / (A_N R) (inf for e0 = 0).
    shape : str
        "curtate" (ratio > 1, no loops), "normal" (ratio = 1, cusps) or
        "prolate" (ratio < 1, loops), (5.241)-(5.243) as reconstructed in the
        digest (section 0.2 item 11).
    """
    Omega: float
    R: float
    e0: float
    H: float
    A_P: float
    A_N: float
    A_P_l: float | None
    A_N_l: float | None
    gamma1: float
    gamma2: float
    phase_P: float
    phase_N: float
    k: float
    p: int | None
    q: int | None
    petals: int | None
    period: float
    ratio: float
    shape: str


def _rational(k, max_denominator, rtol):
    f = Fraction(k).limit_denominator(max_denominator)
    if abs(k - f.numerator / f.denominator) <= rtol * abs(k):
        return f.numerator, f.denominator
    return None, None


def spot_law(Omega, R, e0, H, R_m=None, *, gamma=0.0, max_denominator=12, rtol=1e-6,
             shape_rtol=1e-6):
    """Precession/nutation amplitudes, phases, petals and shape of the spot, (5.237).

    Parameters
    ----------
    Omega : float
        Precession speed (a QP root), > 0.
    R : float
        Rotor speed, > 0.
    e0 : float
        Rotor unbalance (units of the capacity, first order in e0).
    H : float
        Support damping.
    R_m : float, optional
        n m / M_Sigma (= 2 Rt for point balls); if given, the amplitudes are also
        returned in units of the track radius l, as (5.237) prints them.
    gamma : float
        Angle of the ball group in the Omega-frame (a free family parameter).
    max_denominator : int
        Largest q accepted when recognising k = R/Omega as p/q.
    rtol : float
        Relative tolerance of that recognition.
    shape_rtol : float
        |ratio - 1| <= shape_rtol counts as "normal".

    Returns
    -------
    SpotLaw

    Examples
    --------
    The digest's time-domain check (section 5.3, n = 2, Rt = 0.01, h = H = 0.05,
    R = 3, e0 = 0.3): precession 10.297 r* (the digest prints 10.293; its own
    formula gives 10.297, the simulation 10.298) and nutation 0.337 r*
    (first order in e0; the simulation gives 0.3605).

    >>> from stand.theories.planar.qp import qp_roots
    >>> W = qp_roots(3.0, 0.01, 0.05, 0.05)[0]
    >>> s = spot_law(W, 3.0, 0.3, 0.05, R_m=0.02)
    >>> round(s.A_P, 3), round(s.A_N, 3), round(s.k, 3), s.shape
    (10.297, 0.337, 3.121, 'curtate')
    """
    Omega = _check("Omega", Omega)
    R = _check("R", R)
    e0 = _check("e0", e0)
    H = _check("H", H)
    if Omega == 0.0 or R == 0.0:
        raise ValueError("Omega and R must be > 0")
    DW = float(_D(Omega, H))
    DR = float(_D(R, H))
    A_P = Omega * Omega / math.sqrt(DW) if DW > 0 else math.inf
    A_N = e0 * R * R / math.sqrt(DR) if DR > 0 else (math.inf if e0 > 0 else 0.0)
    g1 = math.atan2(H * Omega, 1.0 - Omega * Omega)
    g2 = math.atan2(H * R, R * R - 1.0)
    k = R / Omega
    p, q = _rational(k, max_denominator, rtol)
    petals = None if p is None else p - q
    period = math.inf if q is None else 2.0 * math.pi * q / Omega
    ratio = math.inf if A_N == 0.0 else A_P * Omega / (A_N * R)
    if abs(ratio - 1.0) <= shape_rtol:
        shape = "normal"
    elif ratio > 1.0:
        shape = "curtate"
    else:
        shape = "prolate"
    if R_m is not None:
        R_m = _check("R_m", R_m)
    return SpotLaw(Omega=Omega, R=R, e0=e0, H=H, A_P=A_P, A_N=A_N,
                   A_P_l=None if R_m is None else R_m * A_P,
                   A_N_l=None if R_m is None else R_m * A_N,
                   gamma1=g1, gamma2=g2, phase_P=gamma - g1, phase_N=g2 - math.pi,
                   k=k, p=p, q=q, petals=petals, period=period, ratio=ratio, shape=shape)


def epitrochoid(A_P, A_N, Omega, R, t, phase_P=0.0, phase_N=0.0):
    """Z(t) = A_P e^{i(Omega t + phase_P)} + A_N e^{i(R t + phase_N)}, (5.237).

    Both terms turn forward, so the curve is an epitrochoid (digest section 0.2
    item 12), with k - 1 petals for integer k = R/Omega.

    Returns
    -------
    complex ndarray
        Same shape as ``t``.
    """
    t = np.asarray(t, dtype=float)
    return A_P * np.exp(1j * (Omega * t + phase_P)) + A_N * np.exp(1j * (R * t + phase_N))
