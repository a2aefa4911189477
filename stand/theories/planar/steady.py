"""Steady motions with the weights fixed relative to the rotor: which exist.

Main motions (5.50), side motions (5.51)-(5.75) and the e0 > 1 "maximally
balanced" main motion; their stability is in :mod:`stand.theories.planar.steady_stability`.

Digest ch5 sections 3 and 4.5 (book section 5.2 and 5.4).  All quantities are
dimensionless (digest ch5 section 2.2): ``R`` = omega/omega_1 (the book's
R_omega), ``H`` the support damping, ``e0`` the rotor unbalance and ``e_j`` the
weights' unbalances in units of the balancing capacity (sum e_j = 1; identical
weights have e_j = 1/n), shaft deflections in units of r*.

Conventions
-----------
A frame turns with the rotor; the rotor's heavy side lies on its +real axis
(``unbalance_angle = 0``).  ``alpha_j`` are the weights' angles from the heavy
side and ``s = u + i v`` the shaft deflection in this frame.  Setting all
derivatives to zero in the corrected equations of motion (5.44) gives the
steady equations (5.49)

    s = R^2 psi / (1 - R^2 + i H R),     psi = e0 + sum_j e_j exp(i alpha_j),
    Im(s exp(-i alpha_j)) = 0            (each weight lies on the line of s).

Main motions (5.50) have psi = 0 (s = 0).  In a side motion all weights lie
on one line through the shaft, ``alpha_j = gamma + k_j pi`` (5.52) with the bits
k_j of k (5.53), and the net weight unbalance is e(k) = sum (-1)^{k_j} e_j
(5.54).  The book's real variables (after (5.56)) are

    u~ = Im(s e^{-i gamma}),   v~ = Re(s e^{-i gamma}),

so the torque conditions say u~ = 0 and the shaft deflection is

    s = v~ exp(i gamma)                                            (*)

i.e. ``gamma`` is the angle, from the heavy side, of the direction of the
weights with k_j = 0 along their common line, and v~ is the signed
deflection along that direction.  Dividing the first steady equation by
exp(i gamma) and taking real and imaginary parts gives the corrected (5.57)

    (1 - R^2) v~ - R^2 [e(k) + e0 cos gamma] = 0,
    H R v~ + R^2 e0 sin gamma = 0          (printed with '-': digest 0.2 item 5),

whose elimination gives the corrected (5.64)

    (1 - R^2) e0 sin gamma + H R [e(k) + e0 cos gamma] = 0,
    v~ = R^2 [e(k) + e0 cos gamma] / (1 - R^2)  (= -R e0 sin gamma / H).

The printed first equation of (5.64) has '- H R [...]'; its roots are the
roots of the corrected one with H -> -H and are not equilibria (the steady
residual is O(0.1) for the T6 data, see the tests).  (5.65)-(5.74) are printed
correctly.  Replacing gamma by gamma + pi and k by its complement 2^n - 1 - k
describes the same motion (5.55), so each e(k) yields at most two physically
different side motions, the two roots (5.66).
"""
from __future__ import annotations

import cmath
import math
from dataclasses import dataclass
from itertools import combinations
from typing import Optional, Sequence

import numpy as np

__all__ = [
    "MainMotion", "SideMotion", "SideClass",
    "steady_deflection", "steady_residual", "net_unbalance", "bits_of",
    "main_motion_angles", "maximally_balanced_motion",
    "side_motions", "side_window", "identical_side_classes",
]

_TWO_PI = 2.0 * math.pi
_EPS = np.finfo(float).eps


# ---------------------------------------------------------------------------
# elementary relations
# ---------------------------------------------------------------------------

def _wrap(a: float) -> float:
    """Angle in (-pi, pi]."""
    a = math.remainder(float(a), _TWO_PI)
    return math.pi if a == -math.pi else a


def _check_nonneg(name, value):
    v = float(value)
    if not math.isfinite(v) or v < 0.0:
        raise ValueError(f"{name} must be a finite number >= 0, got {value!r}")
    return v


def _weights(n: int, e) -> np.ndarray:
    if e is None:
        n = int(n)
        if n < 1:
            raise ValueError(f"n must be >= 1, got {n!r}")
        return np.full(n, 1.0 / n)
    e = np.asarray(e, dtype=float).ravel()
    if e.size < 1 or not np.all(np.isfinite(e)) or np.any(e <= 0):
        raise ValueError(f"weights' unbalances e_j must be finite and > 0, got {e!r}")
    return e


def steady_deflection(R: float, psi: complex, H: float) -> complex:
    """Shaft deflection of a synchronous steady motion, (5.49).

    s~ = R^2 psi / (1 - R^2 + i H R) [r*], rotating frame, heavy side on +real.
    """
    return R * R * complex(psi) / complex(1.0 - R * R, H * R)


def steady_residual(R: float, e0: float, H: float, s: complex, alphas, e=None) -> float:
    """Largest residual of the steady equations (5.49) at (s, alphas).

    Returns max(|(1 - R^2 + iHR) s - R^2 psi|, max_j R^2 e_j |Im(s e^{-i alpha_j})|):
    the force balance on the shaft and the torque balance on each weight
    (scaled as the weights' accelerations of (5.44)).
    """
    alphas = np.asarray(alphas, dtype=float)
    e = _weights(alphas.size, e)
    psi = e0 + np.sum(e * np.exp(1j * alphas))
    force = abs(complex(1.0 - R * R, H * R) * s - R * R * psi)
    torque = np.max(R * R * np.abs(np.imag(s * np.exp(-1j * alphas)))) if alphas.size else 0.0
    return float(max(force, torque))


def bits_of(k: int, n: int) -> tuple:
    """Bits (k_1, ..., k_n) of the side-motion number k = k_n ... k_1 (5.53)."""
    k = int(k)
    if not 0 <= k < 2 ** n:
        raise ValueError(f"k must be in [0, 2^n - 1] = [0, {2 ** n - 1}], got {k}")
    return tuple((k >> j) & 1 for j in range(n))


def net_unbalance(bits: Sequence[int], e=None) -> float:
    """Net weight unbalance e(k) = sum_j (-1)^{k_j} e_j (5.54)."""
    bits = np.asarray(bits, dtype=int)
    e = _weights(bits.size, e)
    return float(np.sum(np.where(bits % 2 == 0, e, -e)))


# ---------------------------------------------------------------------------
# main motions (5.50) and the e0 > 1 main motion
# ---------------------------------------------------------------------------

@dataclass(frozen=True)
class MainMotion:
    """A main motion: the weights as close to balancing the rotor as they can.

    Attributes
    ----------
    alphas : ndarray
        Weights' angles from the heavy side [rad].
    s : complex or None
        Shaft deflection [r*] (rotating frame); 0 when balanced; None when the
        rotor cannot be balanced and no speed was given.
    psi : complex
        Residual (total) unbalance e0 + sum e_j e^{i alpha_j} [capacity].
    balanced : bool
        psi = 0 (5.50) -- the existence conditions hold.
    family : bool
        One representative of a continuous family (n >= 3, or e0 = 0): the
        balancing configurations form a manifold of dimension n - 2 (n - 1 for
        e0 = 0), (5.50) and book line 3076.
    gamma, v : float or None
        For an unbalanceable rotor: the side-motion description (5.52), (5.64)
        of this motion, in which the weights with k_j = 1 lie at gamma + pi
        (for identical weights all k_j = 1, the book's k = 2^n - 1) and
        s = v e^{i gamma}.
    bits : tuple or None
        The k_j of that description.
    """

    alphas: np.ndarray
    s: Optional[complex]
    psi: complex
    balanced: bool
    family: bool = False
    gamma: Optional[float] = None
    v: Optional[float] = None
    bits: Optional[tuple] = None


def _polygon(e: np.ndarray, target: complex) -> np.ndarray:
    """Angles with sum e_j e^{i a_j} = target; the target must be reachable.

    A chain of links e_j reaches exactly the lengths
    [max(0, 2 max e - sum e), sum e].  The last link is turned so that the
    rest must reach the middle of the admissible interval, then recursion.
    """
    n = e.size
    T = complex(target)
    if n == 1:
        return np.array([cmath.phase(T)])
    if n == 2:
        r = abs(T)
        e1, e2 = e
        c = (r * r + e1 * e1 - e2 * e2) / (2 * r * e1) if r > 0 else 0.0
        a1 = cmath.phase(T) + math.acos(min(1.0, max(-1.0, c)))
        rest = T - e1 * complex(math.cos(a1), math.sin(a1))
        return np.array([a1, cmath.phase(rest)])
    en = e[-1]
    rest = e[:-1]
    lo = max(0.0, 2 * rest.max() - rest.sum())
    hi = rest.sum()
    r = abs(T)
    lo2, hi2 = abs(r - en), r + en
    a, b = max(lo, lo2), min(hi, hi2)
    if a > b + 1e-12:
        raise ValueError("target not reachable")  # pragma: no cover - guarded by the caller
    rr = 0.5 * (a + b)
    if r > 0:
        c = (r * r + en * en - rr * rr) / (2 * r * en)
        an = cmath.phase(T) + math.acos(min(1.0, max(-1.0, c)))
    else:
        an = 0.0
    Tn = T - en * complex(math.cos(an), math.sin(an))
    return np.append(_polygon(rest, Tn), an)


def main_motion_angles(e0: float, n: int = 2, e=None, *, R: Optional[float] = None,
                       H: float = 0.0) -> list:
    """Main motions (5.50), or the maximally balanced motion beyond capacity.

    Parameters
    ----------
    e0 : float
        Rotor unbalance [capacity], >= 0.
    n : int
        Number of identical weights (e_j = 1/n); ignored when ``e`` is given.
    e : array_like or None
        Weights' unbalances e_j > 0 (any sum; the capacity unit of the digest
        has sum e_j = 1).
    R, H : float
        Speed and support damping; used only when the rotor cannot be balanced.

    Returns
    -------
    list of MainMotion
        * Balanceable (e0 <= sum e_j and the polygon inequality
          e0 >= 2 max e_j - sum e_j, i.e. 2 max e_j - 1 for sum 1 -- digest 3.1):
          for n = 2 both mirror images; identical weights give the closed form
          alpha = pi -+ arccos(e0) (cos theta = e0, (5.50)); for n >= 3 one
          representative of the (n-2)-dimensional family (``family=True``).
        * Not balanceable (e0 > 1 for identical weights): one motion, the
          "maximally balanced" one -- all weights together on the light side
          for identical weights (alpha_j = pi when H = 0).  It is a side motion
          (the book's k = 2^n - 1, section 5.4.2): with ``R`` given, gamma and
          v~ solve the corrected (5.64) (:func:`maximally_balanced_motion`);
          without ``R`` the H = 0 configuration is returned with ``s=None``.
          Empty if that motion does not exist at R (see
          :func:`maximally_balanced_motion`).
    """
    e0 = _check_nonneg("e0", e0)
    e = _weights(n, e)
    n = e.size
    S, emax = float(e.sum()), float(e.max())
    tol = 1e-12 * max(1.0, S)
    if e0 <= S + tol and e0 >= 2 * emax - S - tol:
        fam = n >= 3 or e0 == 0.0
        if n == 1:
            a = np.array([math.pi])
            return [MainMotion(a, 0j, complex(e0 + e[0] * np.exp(1j * a[0])), True, False)]
        if n == 2 and e[0] == e[1]:
            th = math.acos(min(1.0, e0 / S))
            out = [np.array([math.pi - th, math.pi + th]), np.array([math.pi + th, math.pi - th])]
        else:
            a = _polygon(e, complex(-e0, 0.0))
            out = [a] if n >= 3 else [a, -a]
        res = []
        for a in out:
            a = np.array([_wrap(x) for x in a])
            psi = complex(e0 + np.sum(e * np.exp(1j * a)))
            res.append(MainMotion(a, 0j, psi, True, fam))
        if n == 2 and all(abs(_wrap(d)) < 1e-12 for d in res[0].alphas - res[1].alphas):
            res = res[:1]  # e0 = 1 (or e0 = |e1 - e2|): the two mirror images coincide
        return res
    mb = maximally_balanced_motion(R, e0, H, e=e)
    return [] if mb is None else [mb]


def _best_bits(e: np.ndarray, e0: float) -> tuple:
    """Bit pattern with the smallest |e0 + e(k)| (H = 0, gamma = 0)."""
    n = e.size
    best, bk = None, None
    for k in range(2 ** n):
        b = bits_of(k, n)
        val = abs(e0 + net_unbalance(b, e))
        if best is None or val < best - 1e-14:
            best, bk = val, b
    return bk


def maximally_balanced_motion(R: Optional[float], e0: float, H: float = 0.0, n: int = 2,
                              e=None) -> Optional[MainMotion]:
    """The main motion of a rotor the weights cannot balance (e0 > 1).

    The weights lie on one line (a side motion, (5.52)) with the bit pattern
    that minimises |e0 + e(k)| -- for identical weights all k_j = 1, e(k) = -1
    (the book's k = 2^n - 1, section 5.4.2), i.e. all weights together on the
    light side.  Of the two roots gamma of the corrected (5.64) the one with
    the smaller residual unbalance |psi| is taken; at R = 1 both have the same
    |psi| and the one continuing the branch above resonance (lagging: the
    weights' resultant at a negative angle) is taken.  Section 4.5: this motion
    is stable above resonance for R~_m << 1 or R >> 1 ((5.155)-(5.161)) --
    but at finite R~_m not just above resonance: the conservative cubic
    (5.155) has complex roots in a band (R~_m = 0.01, e0 = 1.5: about
    1.15 < R < 1.50; the band shrinks to R = 1 as R~_m -> 0), where with
    damping the motion is unstable (see the tests).

    With ``R=None`` (or H = 0) the H = 0 configuration gamma = 0 is returned
    (exact for H = 0 at any R != 1); ``s`` is None when R is None.  Returns
    None when the pattern has |e(k)| > e0 (a weight heavier than the rest
    plus the rotor, or one weight with e0 < 1) and R lies inside its window
    (5.70): then no synchronous steady motion of this kind exists.
    """
    e0 = _check_nonneg("e0", e0)
    H = _check_nonneg("H", H)
    e = _weights(n, e)
    if R is not None and H == 0.0 and float(R) == 1.0:
        raise ValueError("H = 0 at R = 1: undamped resonance, no finite steady deflection")
    bits = _best_bits(e, e0)
    ek = net_unbalance(bits, e)
    if R is None or H == 0.0:
        g = 0.0
        alphas = np.array([_wrap(g + b * math.pi) for b in bits])
        psi = complex(e0 + ek)
        if R is None:
            return MainMotion(alphas, None, psi, False, False, g, None, bits)
        v = R * R * (ek + e0) / (1.0 - R * R)
        return MainMotion(alphas, complex(v), psi, False, False, g, v, bits)
    sm = side_motions(R, e0, ek, H, bits=bits)
    if not sm:
        # |e(k)| > e0 (a weight too heavy for the polygon, or n = 1 with e0 < 1)
        # and R inside the window (5.70): no such steady motion
        return None
    best = min(sm, key=lambda m: (round(abs(e0 + ek * np.exp(1j * m.gamma)), 12),
                                  math.sin(m.gamma) * math.copysign(1.0, ek)))
    psi = complex(e0 + ek * np.exp(1j * best.gamma))
    return MainMotion(best.alphas, best.s, psi, False, False, best.gamma, best.v, bits)


# ---------------------------------------------------------------------------
# side motions (5.51)-(5.75)
# ---------------------------------------------------------------------------

@dataclass(frozen=True)
class SideMotion:
    """One steady side motion (5.52), (5.64)-(5.66).

    Attributes
    ----------
    gamma : float
        Angle of the weights' common line from the heavy side [rad] in
        (-pi, pi]: the weights with k_j = 0 sit at gamma, those with k_j = 1 at
        gamma + pi (5.52).
    v : float
        The book's v~ (5.64): signed deflection along e^{i gamma} [r*].
    s : complex
        Shaft deflection s~ = v e^{i gamma} [r*], rotating frame, heavy side on
        +real.
    ek : float
        Net weight unbalance e(k) (5.54) [capacity].
    root : int
        1 or 2: the sign + or - in (5.66) (H = 0: 1 is gamma = 0, 2 is gamma = pi).
    family : bool
        H = 0 and e0 = 0: gamma is arbitrary (5.63); gamma = 0 represents it.
    bits : tuple or None
        k_j if given to :func:`side_motions`.
    alphas : ndarray or None
        Weights' angles gamma + k_j pi, wrapped to (-pi, pi], if bits given.
    """

    gamma: float
    v: float
    s: complex
    ek: float
    root: int
    family: bool = False
    bits: Optional[tuple] = None
    alphas: Optional[np.ndarray] = None

    def angles(self, bits: Sequence[int]) -> np.ndarray:
        """Weights' angles alpha_j = gamma + k_j pi (5.52) for the bits k_j."""
        return np.array([_wrap(self.gamma + (b % 2) * math.pi) for b in bits])


def _half_angle(num: float, den: float) -> float:
    """gamma = 2 arctan(num / den) in (-pi, pi], den = 0 meaning tan(gamma/2) = inf."""
    if den < 0 or (den == 0 and num < 0):
        num, den = -num, -den
    return _wrap(2.0 * math.atan2(num, den))


def side_motions(R: float, e0: float, ek: float, H: float, *, bits=None) -> list:
    """Steady side motions with net weight unbalance e(k), (5.61)-(5.66).

    Parameters
    ----------
    R : float
        Speed ratio omega/omega_1, > 0.
    e0 : float
        Rotor unbalance [capacity], >= 0.
    ek : float
        Net weight unbalance e(k) (5.54).
    H : float
        Support damping, >= 0.
    bits : sequence of int, optional
        k_j; fills ``alphas`` of each result (the bits must give e(k) = ek for
        the weights the caller has in mind; not checked).

    Returns
    -------
    list of SideMotion
        * H > 0, e0 > 0: the roots (5.66) of (5.65) -- two, or none inside the
          window (R*_1, R*_2) of (5.70) when |e(k)| > e0 (at its ends a double
          root).  Computed with the cancellation-free form of the quadratic's
          roots; a root tan(gamma/2) = inf (e0 = e(k)) is gamma = pi, the main
          motion psi = 0.  v~ from the corrected (5.64): R^2[e(k) + e0 cos
          gamma]/(1 - R^2) or -R e0 sin gamma / H, whichever has the larger
          denominator (they are equal at a root).
        * H = 0, e0 > 0 (5.61): gamma = 0 and gamma = pi (the latter is the
          book's motion 2^n - 1 - k at gamma = 0), R != 1.
        * H = 0, e0 = 0 (5.63): one family, gamma arbitrary (represented by
          gamma = 0), v~ = R^2 e(k)/(1 - R^2); none if e(k) = 0 (a main motion).
        * H > 0, e0 = 0: none -- the analogues of (5.63) do not exist (5.57)
          (for e(k) = 0 the weights balance each other: a main motion).

    Raises
    ------
    ValueError
        R <= 0, e0 < 0, H < 0, or H = 0 at R = 1 (undamped resonance: no
        finite deflection).
    """
    R = float(R)
    if not math.isfinite(R) or R <= 0:
        raise ValueError(f"R must be > 0, got {R!r}")
    e0 = _check_nonneg("e0", e0)
    H = _check_nonneg("H", H)
    ek = float(ek)
    x = R * R

    def make(g, root, family=False, v=None):
        if v is None:
            if H == 0.0 or abs(1.0 - x) >= H * R:
                v = x * (ek + e0 * math.cos(g)) / (1.0 - x)
            else:
                v = -R * e0 * math.sin(g) / H
        al = None
        if bits is not None:
            al = np.array([_wrap(g + (b % 2) * math.pi) for b in bits])
        return SideMotion(g, float(v), complex(v * math.cos(g), v * math.sin(g)), ek, root,
                          family, None if bits is None else tuple(int(b) for b in bits), al)

    if H == 0.0:
        if x == 1.0:
            raise ValueError("H = 0 at R = 1: undamped resonance, no finite steady deflection")
        if e0 == 0.0:
            if ek == 0.0:
                return []
            return [make(0.0, 1, family=True)]
        return [make(0.0, 1), make(math.pi, 2)]
    if e0 == 0.0:
        return []
    # (5.65): a t^2 + 2 b t + c = 0, t = tan(gamma/2)
    a = H * R * (e0 - ek)
    b = e0 * (x - 1.0)
    c = -H * R * (e0 + ek)
    D = b * b - a * c                      # = e0^2 (R^2-1)^2 + H^2 R^2 (e0^2 - e(k)^2)
    if D < 0:
        if D < -8 * _EPS * (b * b + abs(a * c)):
            return []
        D = 0.0  # rounding at the ends of the window (5.70): the double root
    sq = math.sqrt(D)
    # (5.66) t_{1/2} = (-b +- sq)/a; the root that suffers cancellation is c/q
    if b >= 0:
        q = -(b + sq)                      # = a t_2
        t1, t2 = (c, q), (q, a)
    else:
        q = -b + sq                        # = a t_1
        t1, t2 = (q, a), (c, q)
    if q == 0.0:
        # b = 0 (R = 1) and D = 0, so a c = 0: a = 0 (e0 = e(k)) gives the double
        # root t = inf (gamma = pi, the main motion), c = 0 (e0 = -e(k)) t = 0
        t1 = t2 = (1.0, 0.0) if a == 0.0 else (0.0, 1.0)
    return [make(_half_angle(*t1), 1), make(_half_angle(*t2), 2)]


def side_window(e0: float, ek: float, H: float):
    """Speed window without side motions of net unbalance e(k), (5.70)-(5.71).

    Returns
    -------
    (R1, R2) or None
        For |e(k)| > e0:
        R*_{1/2} = [sqrt(4 e0^2 + H^2 (e(k)^2 - e0^2)) -+ H sqrt(e(k)^2 - e0^2)] / (2 e0),
        0 < R*_1 <= 1 <= R*_2, R*_1 R*_2 = 1; side motions exist for
        R in (0, R*_1] U [R*_2, inf) and merge pairwise (saddle-node) at the
        ends, at gamma* = -+[pi - arccos(e0/|e(k)|)] (5.69).  For e0 = 0 and
        H > 0 there are no side motions at all: (0, inf).  For H = 0 the
        window shrinks to the resonance, (1, 1).  None when |e(k)| <= e0
        (two branches at every speed, Fig. 5.2 b, c).
    """
    e0 = _check_nonneg("e0", e0)
    H = _check_nonneg("H", H)
    ek = abs(float(ek))
    if ek <= e0:
        return None
    if H == 0.0:
        return (1.0, 1.0)
    if e0 == 0.0:
        return (0.0, math.inf)
    w = math.sqrt(ek * ek - e0 * e0)
    r = math.sqrt(4 * e0 * e0 + H * H * w * w)
    R1 = (r - H * w) / (2 * e0)
    # R2 = 1/R1 exactly (product 1); this form has no cancellation
    R2 = (r + H * w) / (2 * e0)
    return (R1, R2)


@dataclass(frozen=True)
class SideClass:
    """A class of side motions of identical weights, (5.75).

    Attributes
    ----------
    n : int
        Number of weights.
    k : int
        Number of weights on the far end of the common line (k_j = 1), 2k <= n.
    ek : float
        e_k = 1 - 2k/n.
    multiplicity : int
        Number of bit patterns with e(k) = e_k: C(n, k).  Each has a complement
        (e = -e_k) describing the same motions with gamma + pi (5.55); for
        2k = n the complements are in the class itself.
    patterns : tuple of int
        The book's numbers k = k_n ... k_1 (5.53) of these patterns.
    """

    n: int
    k: int
    ek: float
    multiplicity: int
    patterns: tuple

    def bits(self, i: int = 0) -> tuple:
        """k_j of the i-th pattern."""
        return bits_of(self.patterns[i], self.n)


def identical_side_classes(n: int) -> list:
    """Classes of side motions of n identical weights, (5.75).

    e_k = 1 - 2k/n for 2k <= n; with their complements (e = -e_k) they give
    n + 1 essentially different side motions (even n: two groups of n/2 plus
    one with e_k = 0; odd n: two groups of (n+1)/2).  Each pattern's first
    member in ``patterns`` has its k_j = 1 on the highest-numbered weights.
    """
    n = int(n)
    if n < 1:
        raise ValueError(f"n must be >= 1, got {n}")
    out = []
    for k in range(n // 2 + 1):
        pats = []
        for ones in combinations(range(n - 1, -1, -1), k):
            pats.append(sum(1 << j for j in ones))
        out.append(SideClass(n, k, 1.0 - 2.0 * k / n, len(pats), tuple(pats)))
    return out
