"""Closed forms of the rigid rotor in spatial motion on isotropic supports,
book sections 2.7.2-2.7.3 (digest ch2_ch3 sections 2.7-2.8, table 6.1).

For a balancer at axial distance ``a`` [m] from the centre of mass of the
rotor (mass M [kg], transverse and polar central moments A, C [kg m^2]) on
isotropic supports ``(c11 [N/m], c14 [N/rad], c33 [N m/rad])`` (2.122):

* :func:`delta` (2.126) and the engineering criterion :func:`r_ac` (2.133);
* :func:`high_speed_limit`, :func:`balances_at_high_speed` (2.134)-(2.137);
* :func:`auxiliary_speed` (2.138), :func:`frequency_polynomial` /
  :func:`frequency_roots` (2.139)-(2.141);
* :func:`critical_speeds` (2.142)-(2.153), :func:`symmetric_critical_speeds`
  (2.154)-(2.159), as :class:`SpeedRegions`;
* :func:`intersect_ranges`, :func:`two_balancer_ranges` (2.160).

Each closed form equals the generic :meth:`LinearRotor.criterion` of
:func:`stand.model.rotors.spatial.spatial_rotor` (the model; this is its theory).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from stand.model.rotors._build import finite, nonnegative, positive
from stand.model.rotors.spatial_supports import _REL, _check_isotropic_coefficients

__all__ = ["rotor_shape", "delta", "r_ac", "high_speed_limit", "balances_at_high_speed",
           "auxiliary_speed", "frequency_polynomial", "frequency_roots", "SpeedRegions",
           "critical_speeds", "symmetric_critical_speeds", "intersect_ranges",
           "two_balancer_ranges"]


def rotor_shape(A: float, C: float) -> str:
    """``"long"`` (C < A), ``"spherical"`` (C = A, relative 1e-12) or ``"short"`` (C > A), (2.19)-(2.21)."""
    A = positive("A", A, "kg m^2")
    C = nonnegative("C", C, "kg m^2")
    if math.isclose(A, C, rel_tol=_REL):
        return "spherical"
    return "long" if C < A else "short"


def delta(omega, M, A, C, c11, c14, c33):
    """(2.126): ``Delta(w^2) = (c11 - M w^2)(c33 - (A - C) w^2) - c14^2`` [N^2/rad].
    ``omega`` [rad/s] may be an array."""
    w2 = np.square(np.asarray(omega, dtype=float))
    return (c11 - M * w2) * (c33 - (A - C) * w2) - c14 * c14


def r_ac(omega, M, A, C, c11, c14, c33, a, s=1.0):
    """Engineering criterion (2.133) for a balancer at axial distance ``a`` [m]::

        r_Ac = -[(A + M a^2 - C) w^2 - c33 - c11 a^2 + 2 a c14] s w^2 / Delta(w^2)

    [m] for an unbalance ``s`` [kg m]; autobalancing needs ``r_Ac < 0``.  It is
    the (time-constant) projection of the plane's deflection on the unbalance,
    equal to :meth:`LinearRotor.criterion` of :func:`spatial_rotor`.
    """
    w2 = np.square(np.asarray(omega, dtype=float))
    num = (A + M * a * a - C) * w2 - c33 - c11 * a * a + 2 * a * c14
    return -num * s * w2 / delta(omega, M, A, C, c11, c14, c33)


def high_speed_limit(M, A, C, a, s=1.0) -> float:
    """(2.134)-(2.137): ``r_Ac -> -(A + M a^2 - C) s / (M (A - C))`` [m] as w -> inf
    (``A != C``; for the spherical rotor the limit is ``+a^2 s / c33``-like, not given)."""
    if math.isclose(A, C, rel_tol=_REL):
        raise ValueError(f"high_speed_limit needs A != C (non-spherical rotor), got A = C = {A!r} kg m^2")
    return -(A + M * a * a - C) * s / (M * (A - C))


def balances_at_high_speed(M, A, C, a) -> bool:
    """(2.135)-(2.137): high-speed autobalancing iff ``C < A`` (long rotor, any ``a``)
    or ``C > A + M a^2``, i.e. a short rotor with ``|a| < sqrt((C - A)/M)``;
    never for a spherical rotor."""
    M = positive("M", M, "kg")
    shape = rotor_shape(A, C)
    if shape == "long":
        return True
    if shape == "spherical":
        return False
    return bool(A + M * a * a < C)


def auxiliary_speed(M, A, C, c11, c14, c33, a) -> float:
    """(2.138): ``w~ = sqrt((c33 + c11 a^2 - 2 a c14) / (A + M a^2 - C))`` [rad/s],
    the zero of the numerator of (2.133).  ``inf`` when ``A + M a^2 = C``
    (spherical rotor with ``a = 0``), ``nan`` when ``A + M a^2 < C`` (no real zero)."""
    num = c33 + c11 * a * a - 2 * a * c14
    den = A + M * a * a - C
    if abs(den) <= _REL * max(A, C):
        return math.inf
    return math.sqrt(num / den) if den > 0 else math.nan


def frequency_polynomial(M, A, C, c11, c14, c33):
    """(2.139)-(2.140): ``Delta(x) = a2 x^2 - a1 x + a0`` in ``x = w^2`` with
    ``a2 = M(A - C)``, ``a1 = c11 (A - C) + M c33``, ``a0 = c11 c33 - c14^2`` and the
    discriminant ``D = [c11 (A - C) - M c33]^2 + 4 c14^2 M (A - C)``.

    Returns ``(a2, a1, a0, D)``.  (The book says "up to sign"; the sign is +.)
    """
    a2 = M * (A - C)
    a1 = c11 * (A - C) + M * c33
    a0 = c11 * c33 - c14 * c14
    D = (c11 * (A - C) - M * c33) ** 2 + 4 * c14 * c14 * M * (A - C)
    return a2, a1, a0, D


def frequency_roots(M, A, C, c11, c14, c33) -> np.ndarray:
    """Real roots ``x = w^2`` [rad^2/s^2] of (2.139), sorted ((2.141) in a
    cancellation-free form).  Two roots if ``A != C`` (both positive for a long
    rotor; ``x_- < 0 < x_+`` for a short one), one (``a0 / (M c33)``, (2.145)) if ``A = C``."""
    a2, a1, a0, D = frequency_polynomial(M, A, C, c11, c14, c33)
    if math.isclose(A, C, rel_tol=_REL):
        return np.array([a0 / a1])
    q = 0.5 * (a1 + math.copysign(math.sqrt(D), a1))
    return np.sort(np.array([q / a2, a0 / q]))


@dataclass(frozen=True)
class SpeedRegions:
    """Critical speeds and autobalancing regions of one balancer plane.

    Attributes
    ----------
    case : str
        ``"long"``, ``"spherical"``, ``"short, A+Ma^2>C"`` or ``"short, A+Ma^2<=C"``.
    speeds : tuple of float
        Critical speeds [rad/s], ascending.
    ranges : tuple of (float, float)
        Autobalancing speed ranges [rad/s]; the last end may be ``inf``.
    equations : str
        Book equations used.
    """

    case: str
    speeds: tuple
    ranges: tuple
    equations: str = ""

    def contains(self, omega: float) -> bool:
        """True if ``omega`` [rad/s] lies in an autobalancing range."""
        return any(lo < omega < hi for lo, hi in self.ranges)


def _merge(ranges):
    """Join ranges that touch (a cancelled critical speed, e.g. a = 0)."""
    out = []
    for lo, hi in sorted(ranges):
        if out and math.isclose(out[-1][1], lo, rel_tol=1e-12):
            out[-1] = (out[-1][0], hi)
        elif lo < hi:
            out.append((lo, hi))
    return tuple(out)


def _case_regions(shape, P, wt, roots, equations):
    """Regions from the sign analysis of (2.133): ``r_Ac < 0`` iff ``N / Delta > 0``."""
    if shape == "long":                      # (2.142)-(2.144)
        w = sorted([wt, math.sqrt(roots[0]), math.sqrt(roots[1])])
        case, ranges = "long", [(w[0], w[1]), (w[2], math.inf)]
    elif shape == "spherical":               # (2.145)-(2.147)
        wk = math.sqrt(roots[0])
        case = "spherical"
        if math.isinf(wt):                   # a = 0: numerator constant
            w, ranges = [wk], [(wk, math.inf)]
        else:
            w = sorted([wk, wt])
            ranges = [(w[0], w[1])]
    else:
        wp = math.sqrt(roots[-1])            # the positive root x_+
        if P > 0:                            # (2.148)-(2.150)
            w = sorted([wp, wt])
            case, ranges = "short, A+Ma^2>C", [(w[0], w[1])]
        else:                                # (2.151)-(2.153)
            w = [wp]
            case, ranges = "short, A+Ma^2<=C", [(wp, math.inf)]
    ranges = _merge(ranges)
    speeds = tuple(sorted({float(x) for r in ranges for x in r if math.isfinite(x)}))
    return SpeedRegions(case, speeds, tuple((float(a), float(b)) for a, b in ranges), equations)


def critical_speeds(M, A, C, c11, c14, c33, a) -> SpeedRegions:
    """Critical speeds and regions of (2.133) for isotropic supports (2.142)-(2.153).

    * long (C < A): ``{w~, sqrt(x1), sqrt(x2)}`` sorted to w1 < w2 < w3,
      region ``(w1, w2) U (w3, inf)`` (any order of w~, (2.144));
    * spherical (A = C): ``w_k = sqrt((c11 c33 - c14^2)/(M c33))`` and
      ``w~ = sqrt((c33 + c11 a^2 - 2 a c14)/(M a^2))``, region between them
      (corrected (2.145)-(2.146)); ``a = 0``: ``(w_k, inf)``;
    * short (C > A) with ``A + M a^2 > C``: between ``sqrt(x_+)`` and w~ (2.148)-(2.150);
    * short with ``A + M a^2 <= C``: ``(sqrt(x_+), inf)`` (2.151)-(2.153).

    Touching ranges (a cancelled critical speed) are merged.

    Parameters
    ----------
    M [kg], A, C [kg m^2], c11 [N/m], c14 [N/rad], c33 [N m/rad], a [m]
    """
    M = positive("M", M, "kg")
    c11, c14, c33 = _check_isotropic_coefficients(c11, c14, c33)
    a = finite("a", a, "m")
    shape = rotor_shape(A, C)
    P = A + M * a * a - C
    return _case_regions(shape, P, auxiliary_speed(M, A, C, c11, c14, c33, a),
                         frequency_roots(M, A, C, c11, c14, c33),
                         "(2.133), (2.138)-(2.153)")


def symmetric_critical_speeds(M, A, C, c11, c33, a) -> SpeedRegions:
    """Symmetric mounting (c14 = 0, section 2.7.3): the explicit speeds (2.155)-(2.159)::

        w1 = sqrt(c11/M),  w2 = sqrt((c33 + c11 a^2)/(A + M a^2 - C)),  w3 = sqrt(c33/(A - C))

    * long (2.155)-(2.156): ``(w1, w2) U (w3, inf)``; the book assumes
      ``c11/M < c33/(A - C)`` (then w1 < w2 < w3); otherwise the three are
      sorted (w3 < w2 < w1) and the same pattern holds;
    * spherical (2.157): ``(w1, w2)`` (``(w1, inf)`` for a = 0);
    * short, ``A + M a^2 > C`` (2.158): between w1 and w2;
    * short, ``A + M a^2 <= C`` (2.159): ``(w1, inf)``.
    """
    M = positive("M", M, "kg")
    c11, _, c33 = _check_isotropic_coefficients(c11, 0.0, c33)
    a = finite("a", a, "m")
    shape = rotor_shape(A, C)
    P = A + M * a * a - C
    w1 = math.sqrt(c11 / M)
    w2 = math.inf if abs(P) <= _REL * max(A, C) else (
        math.sqrt((c33 + c11 * a * a) / P) if P > 0 else math.nan)
    if shape == "long":
        roots = [w1 ** 2, c33 / (A - C)]
    elif shape == "spherical":
        roots = [w1 ** 2]
    else:
        roots = [c33 / (A - C), w1 ** 2]     # x_- < 0 < x_+ = c11/M
    return _case_regions(shape, P, w2, roots, "(2.154)-(2.159)")


def intersect_ranges(r1, r2):
    """Intersection of two lists of (lo, hi) ranges [rad/s] (rule (2.160))."""
    out = []
    for a0, a1 in r1:
        for b0, b1 in r2:
            lo, hi = max(a0, b0), min(a1, b1)
            if lo < hi:
                out.append((lo, hi))
    return tuple(sorted(out))


def two_balancer_ranges(M, A, C, c11, c14, c33, a1, a2):
    """Two balancers at ``a1``, ``a2`` [m]: the book's rule (2.160)
    ``Omega = Omega_1 ∩ Omega_2`` of the single-plane regions (2.142)-(2.153).

    Note: this is the book's engineering rule.  Paper 003's generalised
    criterion (:meth:`TwoSupportRotor.is_stable`) is stricter for dynamic
    balancing (a long rotor only above its largest critical speed).
    """
    return intersect_ranges(critical_speeds(M, A, C, c11, c14, c33, a1).ranges,
                            critical_speeds(M, A, C, c11, c14, c33, a2).ranges)
