"""The frequency equation (5.181) of the quasi-periodic motions and its curve R(Omega).

Digest ch5 section 5 (book section 5.5); the quasi-periodic ("stuck-ball")
motions, their parameters and units are described in :mod:`stand.theories.planar.qp`
(all dimensionless: R, Omega in units of omega_1, Rt = R~_m, h the ball drag,
H the support damping).  The torque balance on the stuck balls gives the
corrected frequency equation (5.181)

    P(Omega) = 2 R_mH Omega^5 - (R - Omega) D(Omega) = 0,
    D(w) = (1 - w^2)^2 + H^2 w^2,       R_mH = Rt H / h.

P is linear in R, so every Omega > 0 belongs to exactly one speed,

    R(Omega) = Omega + 2 R_mH Omega^5 / D(Omega)                (speed_of_precession)

and the QP roots at a speed R (:func:`stand.theories.planar.qp.qp_roots`) are the
intersections of this curve with the horizontal line R.  The root count
changes only at the local extrema of R(Omega) (Table 5.1-A).  Writing x = Omega^2,

    dR/dOmega = 1 + 2 R_mH Omega^4 N(x) / D^2,   N(x) = x^2 - (6 - 3H^2) x + 5
              = (1 - x)(5 - x) + 3 H^2 x,

so dR/dOmega >= 1 wherever N >= 0: the extrema can lie only in
(Omega_-, Omega_+) = (sqrt(x_-), sqrt(x_+)), x_+- the roots of N, a sub-interval of
(1, sqrt 5) that exists only for H^2 < 2 - sqrt(20)/3 (about H < 0.7136).  There a
grid, geometrically refined towards both ends (where the extrema crowd for small
H or large R_mH) plus the real parts of the roots of the quartic
F(x) = D^2 + 2 R_mH x^2 N (whose sign is that of dR/dOmega), locates every sign
change of dR/dOmega; each is refined with ``brentq`` (:func:`_extrema`).
"""
from __future__ import annotations

import math
import warnings

import numpy as np
from scipy.optimize import brentq

__all__ = ["QPWarning", "speed_of_precession", "dspeed_dOmega", "frequency_polynomial"]

_EPS = np.finfo(float).eps
_RTOL = 4 * _EPS          # the smallest rtol brentq accepts


class QPWarning(UserWarning):
    """A QP computation met a degenerate or unresolvable case (the result says how)."""


# ---------------------------------------------------------------------------
# input checks and elementary functions
# ---------------------------------------------------------------------------

def _check(name, value, *, upper=None):
    v = float(value)
    if not math.isfinite(v) or v < 0.0:
        raise ValueError(f"{name} must be a finite number >= 0, got {value!r}")
    if upper is not None and v >= upper:
        raise ValueError(f"{name} must be < {upper} (R~_m = n m / (2 M_Sigma)), got {value!r}")
    return v


def _params(Rt, h, H):
    return _check("Rt", Rt, upper=0.5), _check("h", h), _check("H", H)


def _D(w, H):
    """D(w) = (1 - w^2)^2 + H^2 w^2, evaluated without cancellation near w = 1."""
    w = np.asarray(w, dtype=float)
    return ((1.0 - w) * (1.0 + w)) ** 2 + (H * w) ** 2


def _N_roots(H):
    """Roots x_- < x_+ of N(x) = x^2 - (6 - 3H^2) x + 5, or None (then N > 0)."""
    b = 6.0 - 3.0 * H * H
    disc = b * b - 20.0
    if b <= 0.0 or disc <= 0.0:
        return None
    xp = 0.5 * (b + math.sqrt(disc))
    return 5.0 / xp, xp          # x_- x_+ = 5, stable form


def _N(x, H, roots):
    x = np.asarray(x, dtype=float)
    if roots is None:
        return (1.0 - x) * (5.0 - x) + 3.0 * H * H * x
    return (x - roots[0]) * (x - roots[1])


def _RmH(Rt, h, H):
    return Rt * H / h


def speed_of_precession(Omega, Rt, h, H):
    """Rotor speed R at which a QP motion precesses at ``Omega`` (inverse of (5.181)).

    The frequency equation (5.181) is linear in R, so

        R(Omega) = Omega + 2 R_mH Omega^5 / D(Omega),   R_mH = Rt H / h,
        D(Omega) = (1 - Omega^2)^2 + H^2 Omega^2,

    i.e. the drive h (R - Omega) equals the resistance 2 Rt Omega^5 H / D (the
    torque balance after (5.180)).

    Parameters
    ----------
    Omega : float or array_like
        Precession speed(s) >= 0, units of omega_1.
    Rt, h, H : float
        R~_m, ball drag, support damping (all >= 0, Rt < 0.5).

    Returns
    -------
    float or ndarray
        R(Omega).  Degenerate cases: with ``h = 0`` (and Rt H > 0) R = inf for
        Omega > 0 (no finite drive balances the resistance); with ``H = 0`` the
        resistance vanishes except at Omega = 1, where its limit H -> 0+ is
        infinite: R = Omega for Omega != 1 and R(1) = inf (if Rt > 0).
    """
    Rt, h, H = _params(Rt, h, H)
    w = np.asarray(Omega, dtype=float)
    if np.any(~np.isfinite(w)) or np.any(w < 0):
        raise ValueError("Omega must be finite and >= 0")
    num = 2.0 * Rt * H * w ** 5
    den = h * _D(w, H)
    with np.errstate(divide="ignore", invalid="ignore"):
        extra = np.where(num == 0.0, 0.0, num / den)
        if H == 0.0 and Rt > 0.0 and h > 0.0:   # spike 2 Rt / (h H) -> inf at Omega = 1
            extra = np.where(w == 1.0, np.inf, 0.0)
    out = w + extra
    return float(out) if out.ndim == 0 else out


def dspeed_dOmega(Omega, Rt, h, H):
    """Derivative of :func:`speed_of_precession`,

        dR/dOmega = 1 + 2 R_mH Omega^4 N(Omega^2) / D(Omega)^2,
        N(x) = (1 - x)(5 - x) + 3 H^2 x.

    Positive (>= 1) wherever N >= 0, in particular on (0, 1] and [sqrt 5, inf).
    Requires h > 0 and H > 0.
    """
    Rt, h, H = _params(Rt, h, H)
    if h == 0.0 or H == 0.0:
        raise ValueError("dspeed_dOmega needs h > 0 and H > 0")
    w = np.asarray(Omega, dtype=float)
    roots = _N_roots(H)
    out = 1.0 + 2.0 * _RmH(Rt, h, H) * w ** 4 * _N(w * w, H, roots) / _D(w, H) ** 2
    return float(out) if out.ndim == 0 else out


def frequency_polynomial(R, Rt, h, H):
    """Coefficients (highest power first) of P(Omega) of (5.181), for ``np.roots``.

    P(Omega) = 2 R_mH Omega^5 - (R - Omega)[Omega^4 - (2 - H^2) Omega^2 + 1].
    Ill conditioned when R_mH is tiny or huge; :func:`qp_roots` does not use it.
    """
    Rt, h, H = _params(Rt, h, H)
    RmH = _RmH(Rt, h, H)
    Dp = np.poly1d([1.0, 0.0, H * H - 2.0, 0.0, 1.0])
    P = np.poly1d([2.0 * RmH, 0, 0, 0, 0, 0]) - np.poly1d([-1.0, float(R)]) * Dp
    return P.coeffs


# ---------------------------------------------------------------------------
# extrema of R(Omega) and roots
# ---------------------------------------------------------------------------

def _extrema(Rt, h, H, n_grid=1500):
    """Omega at the local extrema of R(Omega), increasing (h > 0, H > 0, Rt > 0)."""
    roots = _N_roots(H)
    if roots is None:
        return np.empty(0)
    RmH = _RmH(Rt, h, H)
    wm, wp = math.sqrt(roots[0]), math.sqrt(roots[1])
    width = wp - wm

    def F(w):   # sign of dR/dOmega; D^2 + 2 R_mH Omega^4 N
        w = np.asarray(w, dtype=float)
        return _D(w, H) ** 2 + 2.0 * RmH * w ** 4 * _N(w * w, H, roots)

    t = np.geomspace(8 * _EPS * wp, width, n_grid)
    pts = [wm + t, wp - t, np.linspace(wm, wp, n_grid)]
    # the real parts of the quartic's roots mark where F dips (also near-double roots)
    x = np.polynomial.Polynomial
    Dx = x([1.0, -(2.0 - H * H), 1.0])
    Fx = Dx ** 2 + 2.0 * RmH * x([0, 0, 1.0]) * x([5.0, -(6.0 - 3.0 * H * H), 1.0])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        xr = Fx.roots()
    # a close pair of real roots bounds a narrow dip F < 0: sample between them
    xr = np.sort(xr.real)
    xr = np.concatenate([xr, 0.5 * (xr[:-1] + xr[1:])])
    xr = xr[(xr > roots[0]) & (xr < roots[1])]
    pts.append(np.sqrt(xr))
    # the near-resonance minimum sits near Omega ~ 1 + R_mH^(1/3) (5.188)-(5.196)
    c = 1.0 + np.cbrt(RmH) * np.array([0.5, 1.0, 2.0])
    pts.append(c[(c > wm) & (c < wp)])
    g = np.unique(np.concatenate(pts))
    g = g[(g > wm) & (g < wp)]
    g = np.concatenate([[wm], g, [wp]])
    s = np.sign(F(g))
    s[0] = s[-1] = 1.0   # dR/dOmega = 1 exactly at Omega_+- (N = 0)
    # zeros of F on the grid: treat as sign changes resolved by neighbours
    nz = s != 0
    g, s = g[nz], s[nz]
    idx = np.nonzero(s[:-1] != s[1:])[0]
    out = []
    for i in idx:
        a, b = g[i], g[i + 1]
        try:
            out.append(brentq(F, a, b, xtol=2 * _EPS * b, rtol=_RTOL, maxiter=500))
        except ValueError:     # F noisy at the ulp level: keep the midpoint
            out.append(0.5 * (a + b))
    if len(out) % 2:
        warnings.warn(QPWarning(
            f"qp: found an odd number ({len(out)}) of extrema of R(Omega) for Rt={Rt}, "
            f"h={h}, H={H}; the curve is not resolved in double precision near "
            f"Omega = {out}"), stacklevel=3)
    return np.asarray(out)
