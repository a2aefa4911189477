"""Theory of the two-axis pendulum CW (ch. 6): stability, critical speeds,
efficiency, quasi-periodic motions.

Companion of :mod:`stand.model.balancers.two_axis` (model, equations; steady motions in :mod:`.two_axis_steady`).
Digest ``/work/shared/physics/ch6_two_axis.md`` sections 4-6; book numbers cited
per function.  Book errors are NOT reproduced; where a formula follows the
digest's correction instead of the print, the docstring says so:

* (6.71)   cos phi~_{1,2} = +-cos phi0 + delta tg^2 phi0 (print: delta / cos^2 phi0);
* (6.101)  R*_omega1 ~ R_g / (R_m^{1/2} (1 - e0^2)^{3/4}) (print: R_m^2);
* (6.102)  side-heavy roots carry a factor R_omega (missing in the print);
* (6.114)  square root in the numerator;
* (6.133)-(6.154) and (6.145): the Ch. 5 formulas are valid with R_mH -> kappa/2;
  here everything is written with kappa = R_m H / (h2 R_rho^2) itself, i.e. the exact
  frequency equation kappa Omega^5 sin^2 phi = D(Omega) (R_omega - Omega) (6.123);
  b10 of (6.145) = -(4 - H^2) - 2 kappa (print: +);
* (6.146)  Omega_{2/3} linear in R_gm (print: R_gm^2);
* (6.185), (6.186)  A33 includes b / R_rho^2.

The first-group characteristic equation (6.91), the second-group one (6.111) and the
QP one (6.178) with (6.176)/(6.190) are checked against the numerical Jacobian in
``tests/test_two_axis.py``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import List, Optional, Sequence

import numpy as np
from numpy.polynomial import polynomial as P
from scipy.optimize import brentq, minimize_scalar

from stand.model.balancers._params import BOOK
from stand.model.balancers.two_axis_params import TwoAxisParams
from stand.theories.weights.one_model import rotating_form
from stand.theories.weights.two_axis_steady import _D, efficiency, eigenvalues, first_group, jacobian, max_real_part

__all__ = [
    "char_poly_first_group", "char_poly_second_group", "small_mass_roots",
    "fast_rotation_main_roots", "fast_rotation_side_roots", "R_star_omega1",
    "fold_speeds", "above_pivot_onset", "fast_rotation_u", "near_resonance_u",
    "slow_rotation_phi", "efficiency_approx", "n_max_estimate", "track_branch",
    "efficiency_curve", "efficiency_extremum",
    "QPMotion", "qp_frequency_function", "qp_motions", "qp_state",
    "qp_char_poly", "qp_polynomial", "qp_existence_limit", "qp_gravity_allows",
    "qp_amplitudes", "qp_omega1_fast", "qp_omega12_away",
]


# ---------------------------------------------------------------------------
# polynomial helpers (numpy.polynomial convention: lowest degree first)
# ---------------------------------------------------------------------------

def _mul(*ps):
    out = np.array([1.0 + 0j])
    for q in ps:
        out = P.polymul(out, q)
    return out


def _conj_coef(q):
    return np.conj(np.asarray(q, complex))


def _shifted_quadratics(w, H):
    """a11 = (l + i w)^2 + H (l + i w) + 1 and a13 = (l + i w)^2 in l (low -> high)."""
    iw = 1j * w
    a13 = np.array([iw * iw, 2 * iw, 1.0])
    a11 = a13 + np.array([H * iw + 1.0, H, 0.0])
    return a11, a13


def _real(q):
    q = np.asarray(q)
    return np.real_if_close(q, tol=1e6).real if np.iscomplexobj(q) else q


# ---------------------------------------------------------------------------
# stability of steady motions, section 6.3
# ---------------------------------------------------------------------------

def char_poly_first_group(p: TwoAxisParams, phi) -> np.ndarray:
    """Characteristic polynomial (6.91) of a first-group motion, highest degree first.

    D = 4 a11 a11^ a33 a44 - 2 R_m (a33 + a44)(a11 a13^^2 + a11^ a13^2) + 4 R_m^2 a13^2 a13^^2
    with (6.90): a11 = (l + i R_omega)^2 + H (l + i R_omega) + 1, a13 = (l + i R_omega)^2,
    a33 = [(l^2 + h2 l) R_rho^2 + R_g^2 sin^2 phi / cos phi] / sin^2 phi,
    a44 = (l^2 + h1 l + R_g^2 / cos phi) / cos^2 phi; ^ conjugates coefficients only.
    Its 8 roots equal the eigenvalues of the linearised (6.12).  Needs sin, cos phi != 0.
    """
    s, c = math.sin(phi), math.cos(phi)
    if abs(s) < 1e-14 or abs(c) < 1e-14:
        raise ValueError(f"char_poly_first_group needs sin(phi) != 0 and cos(phi) != 0, "
                         f"got phi={phi!r} rad")
    Rm, Rg2 = p.R_m, p.R_g2
    a11, a13 = _shifted_quadratics(p.R_omega, p.H)
    b11, b13 = _conj_coef(a11), _conj_coef(a13)
    a33 = np.array([Rg2 * s * s / c, p.h2 * p.R_rho2, p.R_rho2]) / (s * s)
    a44 = np.array([Rg2 / c, p.h1, 1.0]) / (c * c)
    t1 = 4 * _mul(a11, b11, a33, a44)
    mix = P.polyadd(_mul(a11, b13, b13), _mul(b11, a13, a13))
    t2 = 2 * Rm * _mul(P.polyadd(a33, a44), mix)
    t3 = 4 * Rm * Rm * _mul(a13, a13, b13, b13)
    d = P.polyadd(P.polysub(t1, t2), t3)
    return _real(d)[::-1]


def char_poly_second_group(p: TwoAxisParams, below=True) -> np.ndarray:
    """Characteristic polynomial (6.111) of the second group, highest degree first.

    D = a11 a11^ a33 a44 - (R_m/2)(a11 a13^^2 + a11^ a13^2) a44 - R_m^2 a11 a11^ a34^2,
    a33 = l^2 + h1 l +- R_g^2 (+ for phi~ = 0, ``below``), a44 = (l^2 + h2 l) R_rho^2,
    a34 = R_omega^4 e0 / sqrt(D(R_omega)).  b0 = -R_m^2 e0^2 R_omega^8 < 0 and
    b8 = (1 - R_m) R_rho^2 > 0 (6.112): a positive real root always exists, so the
    second group is always unstable (for e0 > 0).
    """
    Rm, Rw = p.R_m, p.R_omega
    a11, a13 = _shifted_quadratics(Rw, p.H)
    b11, b13 = _conj_coef(a11), _conj_coef(a13)
    a33 = np.array([p.R_g2 if below else -p.R_g2, p.h1, 1.0])
    a44 = np.array([0.0, p.h2 * p.R_rho2, p.R_rho2])
    a34 = Rw ** 4 * p.e0 / math.sqrt(_D(Rw, p.H))
    t1 = _mul(a11, b11, a33, a44)
    t2 = 0.5 * Rm * _mul(P.polyadd(_mul(a11, b13, b13), _mul(b11, a13, a13)), a44)
    t3 = Rm * Rm * a34 * a34 * _mul(a11, b11)
    return _real(P.polysub(P.polysub(t1, t2), t3))[::-1]


def small_mass_roots(p: TwoAxisParams, phi) -> np.ndarray:
    """Zeroth-order roots for R_m << 1, (6.94): rotor roots
    -H/2 +- i sqrt(1 - H^2/4) -+ i R_omega and CW roots
    -h1/2 +- sqrt(h1^2/4 - R_g^2/cos phi), -h2/2 +- sqrt(h2^2/4 - R_g^2 sin^2 phi/(R_rho^2 cos phi)).
    Stability needs cos phi > 0 (6.95): only CM-below-pivot motions can be stable."""
    H, Rw = p.H, p.R_omega
    c, s = math.cos(phi), math.sin(phi)
    w = np.sqrt(complex(1 - H * H / 4))
    rot = [-H / 2 + 1j * w - 1j * Rw, -H / 2 - 1j * w - 1j * Rw,
           -H / 2 - 1j * w + 1j * Rw, -H / 2 + 1j * w + 1j * Rw]
    k5 = np.sqrt(complex(p.h1 ** 2 / 4 - p.R_g2 / c))
    k7 = np.sqrt(complex(p.h2 ** 2 / 4 - p.R_g2 * s * s / (p.R_rho2 * c)))
    return np.array(rot + [-p.h1 / 2 + k5, -p.h1 / 2 - k5, -p.h2 / 2 + k7, -p.h2 / 2 - k7])


def fast_rotation_main_roots(p: TwoAxisParams, u) -> np.ndarray:
    """CW roots of a main motion for R_omega >> 1, R_m ~ 1/R_omega^2 (6.100), u = cos phi~:
    -h1/2 +- [h1^2/4 - u^2 (R_m R_omega^2 + R_g^2/u^3)]^{1/2},
    -h2/2 +- [h2^2/4 - (1-u^2)/R_rho^2 (R_m R_omega^2 + R_g^2/u)]^{1/2}."""
    k = p.R_m * p.R_omega ** 2
    s5 = np.sqrt(complex(p.h1 ** 2 / 4 - u * u * (k + p.R_g2 / u ** 3)))
    s7 = np.sqrt(complex(p.h2 ** 2 / 4 - (1 - u * u) / p.R_rho2 * (k + p.R_g2 / u)))
    return np.array([-p.h1 / 2 + s5, -p.h1 / 2 - s5, -p.h2 / 2 + s7, -p.h2 / 2 - s7])


def fast_rotation_side_roots(p: TwoAxisParams, kind: str) -> np.ndarray:
    """CW roots of side motions / the e0 > 1 main motion for R_omega >> 1.

    ``kind='side_heavy'`` (6.102), **corrected** (digest 4.3; the print lacks the factor
    R_omega): +-R_omega sqrt(R_m (1 + e0)), +-R_omega sqrt(R_m e0 / (R_rho^2 - R_m)).
    ``kind='side_light'`` (6.103): +-R_omega sqrt(R_m (1 - e0)),
    -(h2 R_rho^2 + H R_m)/(2 (R_rho^2 - R_m)) +- i R_omega sqrt(R_m e0/(R_rho^2 - R_m)).
    ``kind='main_light'`` (e0 > 1, (6.104)): -h1/2 +- i R_omega sqrt(R_m (e0 - 1)) and
    the (6.103) pair.
    """
    Rw, Rm, e0, r2 = p.R_omega, p.R_m, p.e0, p.R_rho2
    sq = lambda v: np.sqrt(complex(v))
    pair = (-(p.h2 * r2 + p.H * Rm) / (2 * (r2 - Rm)), Rw * sq(Rm * e0 / (r2 - Rm)))
    if kind == "side_heavy":
        a, b = Rw * sq(Rm * (1 + e0)), Rw * sq(Rm * e0 / (r2 - Rm))
        return np.array([a, -a, b, -b])
    if kind == "side_light":
        a = Rw * sq(Rm * (1 - e0))
        return np.array([a, -a, pair[0] + 1j * pair[1], pair[0] - 1j * pair[1]])
    if kind == "main_light":
        a = Rw * sq(Rm * (e0 - 1))
        return np.array([-p.h1 / 2 + 1j * a, -p.h1 / 2 - 1j * a,
                         pair[0] + 1j * pair[1], pair[0] - 1j * pair[1]])
    raise ValueError(f"kind must be 'side_heavy', 'side_light' or 'main_light', got {kind!r}")


def R_star_omega1(p: TwoAxisParams) -> float:
    """Asymptotic onset of stability of the above-pivot main motion (6.101), **corrected**:
    R*_omega1 ~ R_g / (R_m^{1/2} (1 - e0^2)^{3/4}) = sqrt(R_gm)/(1 - e0^2)^{3/4}
    (the print has R_m^2).  Invalid where it matters (digest 4.4): the practical
    threshold is the fold R_omega3 of (6.62), see :func:`fold_speeds`."""
    if p.e0 >= 1:
        raise ValueError(f"R_star_omega1 needs e0 < 1 [-], got {p.e0!r}")
    return p.R_g / (math.sqrt(p.R_m) * (1 - p.e0 ** 2) ** 0.75)


def fold_speeds(R_gm, e0):
    """Saddle-node speeds (6.62) of the H = 0 first group (gravity on).

    c3 = cos^3 phi_k1 = (1 - e0^{2/3})^{3/2} ((6.59)-(6.60)),
    R_omega1 = sqrt[(sqrt(R_gm^2 + 4 R_gm c3) - R_gm)/(2 c3)],
    R_omega2,3 = sqrt[(R_gm -+ sqrt(R_gm^2 - 4 R_gm c3))/(2 c3)].
    Four first-group motions exist for R_omega in (R_omega1, R_omega2) U (R_omega3, inf)
    (6.65).  R_omega2,3 exist iff R_gm > 4 c3 (6.66); otherwise they are nan.
    R_omega3 is where the above-pivot main motion phi~2 is born (digest 4.4).

    Returns
    -------
    (R_omega1, R_omega2, R_omega3) : tuple of float
    """
    R_gm, e0 = BOOK.each(("R_gm", R_gm, "-", ">= 0"), ("e0", e0, "-", ">= 0"))
    if not 0 < e0 < 1 or R_gm <= 0:
        raise ValueError(f"fold_speeds needs 0 < e0 < 1 [-] and R_gm > 0 [-], got e0={e0!r}, "
                         f"R_gm={R_gm!r}")
    c3 = (1 - e0 ** (2 / 3)) ** 1.5
    r1 = math.sqrt((math.sqrt(R_gm ** 2 + 4 * R_gm * c3) - R_gm) / (2 * c3))
    disc = R_gm ** 2 - 4 * R_gm * c3
    if disc <= 0:
        return r1, math.nan, math.nan
    return (r1, math.sqrt((R_gm - math.sqrt(disc)) / (2 * c3)),
            math.sqrt((R_gm + math.sqrt(disc)) / (2 * c3)))


def _has_stable_above(p):
    for m in first_group(p):
        if m.u < 0 and m.c > 0 and max_real_part(eigenvalues(p, m.state)) < 0:
            return True
    return False


def above_pivot_onset(p: TwoAxisParams, R_lo=1.05, R_hi=60.0, step=0.5, tol=1e-3) -> float:
    """Numerical onset speed of a stable above-pivot main motion (digest 4.4).

    Scans R_omega from ``R_lo`` in steps ``step`` for the first speed with a stable
    first-group motion having cos phi~ < 0 and c = sin phi~ sin psi~ > 0, then bisects to
    ``tol``.  (The key numerical finding: it coincides with the fold R_omega3 of (6.62),
    not with (6.101).)  Returns nan if none is found below ``R_hi``.
    """
    prev = R_lo
    if _has_stable_above(p.with_(R_omega=R_lo)):
        return R_lo
    R = R_lo + step
    while R <= R_hi:
        if _has_stable_above(p.with_(R_omega=R)):
            a, b = prev, R
            while b - a > tol:
                mid = 0.5 * (a + b)
                if _has_stable_above(p.with_(R_omega=mid)):
                    b = mid
                else:
                    a = mid
            return b
        prev = R
        R += step
    return math.nan


# ---------------------------------------------------------------------------
# asymptotics of the steady states, section 6.2.4
# ---------------------------------------------------------------------------

def fast_rotation_u(R_gm, R_omega, e0) -> np.ndarray:
    """Fast-rotation expansions (6.71)/(6.72) of u = cos phi~, delta = R_gm / R_omega^2.

    e0 < 1: [cos phi0 + delta tg^2 phi0, -cos phi0 + delta tg^2 phi0 (**corrected**; print:
    delta/cos^2 phi0), -delta/(1 + e0), -delta/(1 - e0)] (main below, main above,
    side phi~3, side phi~4).  e0 > 1: [delta/(e0 - 1), -delta/(e0 + 1)].
    """
    d = R_gm / R_omega ** 2
    if e0 < 1:
        c0 = math.sqrt(1 - e0 * e0)
        t2 = e0 * e0 / (c0 * c0)
        return np.array([c0 + d * t2, -c0 + d * t2, -d / (1 + e0), -d / (1 - e0)])
    return np.array([d / (e0 - 1), -d / (e0 + 1)])


def near_resonance_u(p: TwoAxisParams) -> float:
    """|u| at R_omega = 1 (6.73)/(6.74): x = u^2 = (1-e0^2-b^2)/2 + sqrt((1-e0^2-b^2)^2/4 + b^2),
    b^2 = H^2 R_g^4 / R_m^2 (exact at R_omega = 1)."""
    b2 = (p.H * p.R_g2 / p.R_m) ** 2
    a = 1 - p.e0 ** 2 - b2
    return math.sqrt(a / 2 + math.sqrt(a * a / 4 + b2))


def slow_rotation_phi(p: TwoAxisParams) -> float:
    """phi~1 for R_omega -> 0 (6.82) with the OCR fix v(6) = (1 - H^2/2) v(4):
    R_m e0 R_omega^4 / R_g^2 [1 + (1 - H^2/2) R_omega^2]; phi~2 = pi - phi~1."""
    Rw = p.R_omega
    return p.R_m * p.e0 * Rw ** 4 / p.R_g2 * (1 + (1 - p.H ** 2 / 2) * Rw ** 2)


# ---------------------------------------------------------------------------
# efficiency, section 6.4
# ---------------------------------------------------------------------------

def efficiency_approx(p: TwoAxisParams) -> float:
    """(6.114) with the OCR fix (square root in the numerator): u -> sqrt(1 - e0^2) in (6.40)."""
    Rw, H = p.R_omega, p.H
    Q = Rw ** 2 - 1 + Rw ** 4 * math.sqrt(max(0.0, 1 - p.e0 ** 2)) / p.R_gm
    return math.sqrt(_D(Rw, H)) / math.sqrt(Q * Q + H * H * Rw * Rw)


def n_max_estimate(R_gm) -> float:
    """Closed form of the local maximum of n near R_omega = sqrt 2 for H -> 0, u ~ 1
    (digest 5): n_max ~ R_gm / (R_gm + 4)."""
    return R_gm / (R_gm + 4.0)


def track_branch(p: TwoAxisParams, R_omegas: Sequence[float], u_start: float) -> np.ndarray:
    """Follow a first-group branch by continuity: at each R_omega take the root u of
    (6.36) nearest to the previous one (labels swap at folds, so never re-classify).
    Returns u per speed (nan where the branch has died: no root within 0.2)."""
    out, u_prev = [], u_start
    for R in R_omegas:
        us = [m.u for m in first_group(p.with_(R_omega=float(R)))]
        if not us or math.isnan(u_prev):
            out.append(math.nan)
            continue
        u = min(us, key=lambda v: abs(v - u_prev))
        if abs(u - u_prev) > 0.2:
            u = math.nan
        out.append(u)
        u_prev = u
    return np.array(out)


def efficiency_curve(p: TwoAxisParams, R_omegas: Sequence[float], u_start=1.0):
    """n(R_omega) along the below-pivot branch phi~1 tracked by continuity from
    u_start at the first speed (default: CW hanging, u = 1 at low speed).

    Returns
    -------
    (u, n) : ndarrays
    """
    us = track_branch(p, R_omegas, u_start)
    ns = np.array([float(efficiency(p.with_(R_omega=float(R)), u)) if not math.isnan(u)
                   else math.nan for R, u in zip(R_omegas, us)])
    return us, ns


def _main_below_n(p, R):
    q = p.with_(R_omega=R)
    ms = [m for m in first_group(q) if m.u > 0]
    if not ms:
        return math.nan
    return float(efficiency(q, max(ms, key=lambda m: m.u).u))


def efficiency_extremum(p: TwoAxisParams, R_lo, R_hi, kind="max"):
    """Local extremum of n on the below-pivot main motion (largest root u > 0) in
    [R_lo, R_hi] (bounded Brent).  Returns (R_omega, n)."""
    sgn = -1.0 if kind == "max" else 1.0
    res = minimize_scalar(lambda R: sgn * _main_below_n(p, R), bounds=(R_lo, R_hi),
                          method="bounded", options={"xatol": 1e-6})
    return float(res.x), sgn * float(res.fun)


# ---------------------------------------------------------------------------
# quasi-periodic motions, section 6.5
# ---------------------------------------------------------------------------

@dataclass
class QPMotion:
    """A quasi-periodic motion (6.115)-(6.124) for e0 = 0: the CW turns in fixed axes at
    Omega (alpha = Omega tau + beta) with constant tilt phi, the rotor whirls
    z0 = i R_m a(Omega) sin phi e^{i(Omega tau + beta)}.

    Attributes
    ----------
    Omega : float
        CW absolute angular speed [omega0 units].
    phi : float
        CW tilt [rad].
    family : str
        ``'gravity'``, ``'cos0'`` (no gravity, phi = pi/2) or ``'omega1'`` (no gravity,
        Omega = 1).
    eig : ndarray
        Omega-frame Jacobian eigenvalues (one ~0: neutral phase).
    """
    Omega: float
    phi: float
    family: str
    eig: Optional[np.ndarray] = field(default=None, repr=False)

    @property
    def max_re(self) -> float:
        return max_real_part(self.eig, drop_zero=True)

    @property
    def stable(self) -> bool:
        return self.max_re < 0


def qp_frequency_function(p: TwoAxisParams, Omega):
    """F(Omega) = kappa Omega^5 sin^2 phi - D(Omega)(R_omega - Omega) with cos phi from
    (6.144) (gravity): zero on a QP motion (6.123).  Returns (F, cos phi)."""
    W = np.asarray(Omega, float)
    D = _D(W, p.H)
    cphi = -p.R_gm * D / (W ** 4 * (W * W - 1))
    return p.kappa * W ** 5 * (1 - cphi ** 2) - D * (p.R_omega - W), cphi


def qp_state(p: TwoAxisParams, Omega, phi, beta=0.0) -> np.ndarray:
    """Omega-frame state [phi, beta, Re q, Im q, 0, 0, 0, 0] of a QP motion (e0 = 0) -- in axes
    turning at Omega (6.19)-(6.22): alpha = Omega tau + beta, z = q e^{i Omega tau};
    q = i R_m Omega^2 sin(phi) e^{i beta} / (1 - Omega^2 + i H Omega) (6.124)/(6.169)."""
    q = 1j * p.R_m * Omega ** 2 * math.sin(phi) * np.exp(1j * beta) / (
        1 - Omega ** 2 + 1j * p.H * Omega)
    return np.array([phi, beta, q.real, q.imag, 0, 0, 0, 0])


def _qp_eig(p, Omega, phi):
    """Eigenvalues of (6.15) linearised in axes turning at ``Omega`` (6.19)-(6.22), about the
    QP motion's state (:func:`qp_state`): the one model's rotating frame at the frame speed
    ``Omega`` (:func:`stand.theories.weights.one_model.rotating_form`), e0 = 0."""
    q = p.with_(e0=0.0)
    form = rotating_form("two_axis", q, frame_speed=Omega)
    return np.linalg.eigvals(jacobian(lambda tau, y: form(y), qp_state(q, Omega, phi)))


def qp_motions(p: TwoAxisParams, *, stability=True, n_grid=20000) -> List[QPMotion]:
    """All QP motions (6.123) at ``p.R_omega`` (computed with e0 = 0).

    Gravity (R_g > 0): cos phi from (6.144), Omega from F(Omega) = 0 on a grid dense near
    Omega = 1 (bracketing + brentq, |cos phi| <= 1 required).  No gravity: the family
    cos phi = 0 with Omega from P~(Omega) = kappa Omega^5 - (R_omega - Omega) D(Omega) (6.132)
    and the family Omega = 1, sin^2 phi = H^2 (R_omega - 1)/kappa (6.130).  kappa is used
    exactly as defined in (6.122) -- not the factor-2 formulas (6.133)-(6.154).
    """
    Rw = p.R_omega
    out: List[QPMotion] = []
    if Rw <= 0:
        return out
    kap = p.kappa
    if p.R_g == 0:
        coef = P.polysub(np.r_[np.zeros(5), kap],
                         P.polymul([Rw, -1.0], [1.0, 0.0, p.H ** 2 - 2, 0.0, 1.0]))
        for r in P.polyroots(coef):
            if abs(r.imag) < 1e-9 and 0 < r.real < Rw:
                out.append(QPMotion(float(r.real), math.pi / 2, "cos0"))
        if Rw > 1 and p.H > 0:
            s2 = p.H ** 2 * (Rw - 1) / kap
            if 0 < s2 <= 1:
                f1 = math.asin(math.sqrt(s2))
                out += [QPMotion(1.0, f1, "omega1"), QPMotion(1.0, math.pi - f1, "omega1")]
    else:
        g = np.unique(np.concatenate([
            np.linspace(1e-3, Rw, n_grid, endpoint=False),
            1 - np.logspace(-8, 0, 4000, endpoint=False),
            1 + np.logspace(-8, math.log10(max(Rw - 1, 1e-8)), 4000, endpoint=False)]))
        g = g[(g > 0) & (g < Rw) & (g != 1)]
        F, cphi = qp_frequency_function(p, g)
        ok = np.abs(cphi) <= 1
        for i in range(len(g) - 1):
            if ok[i] and ok[i + 1] and (g[i] - 1) * (g[i + 1] - 1) > 0 and F[i] * F[i + 1] <= 0:
                W = brentq(lambda w: qp_frequency_function(p, w)[0], g[i], g[i + 1],
                           xtol=1e-15, rtol=4 * np.finfo(float).eps)
                cp = float(qp_frequency_function(p, W)[1])
                out.append(QPMotion(float(W), math.acos(max(-1.0, min(1.0, cp))), "gravity"))
    if stability:
        for m in out:
            m.eig = _qp_eig(p, m.Omega, m.phi)
    return sorted(out, key=lambda m: (m.Omega, m.phi))


def qp_char_poly(p: TwoAxisParams, Omega, phi) -> np.ndarray:
    """QP characteristic polynomial (6.178) with (6.188)-(6.190), highest degree first.

    Delta = a11 a11^ (a33 a44 - a34^2) - (R_m/2)(a11 a13^^2 + a11^ a13^2)(a33 sin^2 phi
    + a44 cos^2 phi) + R_m^2 a13^2 a13^^2 sin^2 phi cos^2 phi, with a11, a13 at Omega,
    b = Omega^4 (1 - Omega^2) R_m / D(Omega), a33 = l^2 + h1 l + b,
    a44 = (l^2 + h2 l) R_rho^2 + b sin^2 phi, a34 = Omega^5 H R_m sin phi cos phi / D(Omega).
    (Reduces to (6.176) without gravity; the corrected A33 of (6.185) contains b/R_rho^2.)
    Delta(0) = 0: the phase is neutral.
    """
    Rm, H = p.R_m, p.H
    s, c = math.sin(phi), math.cos(phi)
    D = _D(Omega, H)
    b = Omega ** 4 * (1 - Omega ** 2) * Rm / D
    a34 = Omega ** 5 * H * Rm * s * c / D
    a11, a13 = _shifted_quadratics(Omega, H)
    b11, b13 = _conj_coef(a11), _conj_coef(a13)
    a33 = np.array([b, p.h1, 1.0])
    a44 = np.array([b * s * s, p.h2 * p.R_rho2, p.R_rho2])
    t1 = _mul(a11, b11, P.polysub(_mul(a33, a44), [a34 * a34]))
    mix = P.polyadd(_mul(a11, b13, b13), _mul(b11, a13, a13))
    t2 = 0.5 * Rm * _mul(mix, P.polyadd(a33 * s * s, a44 * c * c))
    t3 = Rm * Rm * s * s * c * c * _mul(a13, a13, b13, b13)
    return _real(P.polyadd(P.polysub(t1, t2), t3))[::-1]


def qp_polynomial(p: TwoAxisParams) -> np.ndarray:
    """Coefficients b0..b12 (lowest first) of (6.145), **corrected** (digest 6.3):
    kappa [Omega^8 (Omega^2-1)^2 - R_gm^2 D^2] - D (R_omega - Omega) Omega^3 (Omega^2-1)^2,
    b10 = -(4 - H^2) - 2 kappa (the print has +).  Its real roots in (0, R_omega) with
    |cos phi| <= 1 in (6.144) are the QP frequencies (it may contain spurious roots)."""
    k, G, H, Rw = p.kappa, p.R_gm, p.H, p.R_omega
    H2 = H * H
    return np.array([-k * G * G, 0.0, 2 * k * G * G * (2 - H2), -Rw,
                     1 - k * G * G * (6 - 4 * H2 + H2 * H2), (4 - H2) * Rw,
                     -4 + H2 + 2 * k * G * G * (2 - H2), -2 * (3 - H2) * Rw,
                     6 - 2 * H2 + k * (1 - G * G), (4 - H2) * Rw,
                     -(4 - H2) - 2 * k, -Rw, 1 + k])


def qp_existence_limit(p: TwoAxisParams) -> float:
    """R*_omega = 1 + kappa/H^2 ((6.133) corrected = (6.130) = (6.187)): without gravity
    the stable family Omega1 < 1, phi = pi/2 exists for R_omega < R*_omega (the print of
    (6.133) gives 1 + 2 R_mH / H^2)."""
    if p.H <= 0:
        return math.inf
    return 1 + p.kappa / p.H ** 2


def qp_gravity_allows(p: TwoAxisParams) -> bool:
    """Gravity-suppression criterion (digest 6.3): QP motions with Omega < 1 need
    roughly 2 H R_gm < 1 (dimensionally H3 < S omega0^3 / (2 g))."""
    return 2 * p.H * p.R_gm < 1


def qp_amplitudes(p: TwoAxisParams, Omega, phi):
    """Precession and nutation amplitudes of (6.162):
    A_p = R_m Omega^2 sin phi / sqrt(D(Omega)), A_n = R_m R_omega^2 e0 / sqrt(D(R_omega)).
    The trace Z = A_p e^{i Omega T} + A_n e^{i R_omega T} is an epitrochoid."""
    Ap = p.R_m * Omega ** 2 * math.sin(phi) / math.sqrt(_D(Omega, p.H))
    An = p.R_m * p.R_omega ** 2 * p.e0 / math.sqrt(_D(p.R_omega, p.H))
    return Ap, An


def qp_omega1_fast(p: TwoAxisParams) -> float:
    """(6.136)/(6.149): Omega1 ~ R_omega/(1 + kappa) for R_omega >> 1 (kappa, not 2 R_mH)."""
    return p.R_omega / (1 + p.kappa)


def qp_omega12_away(p: TwoAxisParams):
    """(6.137) with the (6.146) shift, R_omega > 1, no gravity (kappa form):
    Omega_{1/2} ~ 1 -+ sqrt(kappa/(R_omega-1) - H^2)/2 + (kappa/8)(4 R_omega-3)/(R_omega-1)^2."""
    Rw, k = p.R_omega, p.kappa
    if Rw <= 1:
        raise ValueError(f"qp_omega12_away needs R_omega > 1 [-], got {Rw!r}")
    r = 0.5 * math.sqrt(max(0.0, k / (Rw - 1) - p.H ** 2))
    sh = k / 8 * (4 * Rw - 3) / (Rw - 1) ** 2
    return 1 - r + sh, 1 + r + sh
