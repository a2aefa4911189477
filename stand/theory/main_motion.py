"""Main (balancing) motions of a planar rotor with n correction weights: stability.

Digest ch5 sections 3.1 and 4.1-4.4 (book sections 5.2-5.3).  In a main motion
(5.50) the weights rotate with the rotor, the shaft sits on the rotation axis
(s~ = 0) and the weights cancel the unbalance, sum e_j e^{i alpha_j} + e0 = 0.
Linearised about it (5.84)-(5.85) the motion has the characteristic determinant
(5.87)-(5.89)

    a11 = (l + iR)^2 + H (l + iR) + 1,   a13 = (l + iR)^2,   a33 = l^2 + h l,
    D = (a11 a33 - Rt a13^2)(a11' a33 - Rt a13'^2) - Rt^2 a13^2 a13'^2 d^2,

(the prime conjugates the coefficients only, not l) whose expansion is the
degree-8 polynomial (5.90) with real coefficients a0..a8.

Units and parameters (digest ch5 section 2.2), all dimensionless:

* ``R``  -- speed ratio omega / omega_1 (the book's R_omega);
* ``Rt`` -- R~_m = (1/(2 M_Sigma)) sum m_j^2 l_j^2 / J_j (= n m / (2 M_Sigma) for
  point balls), 0 < Rt < 0.5;
* ``h``  -- weight drag H_j / (omega_1 J_j); ``H`` -- support damping H_x/(omega_1 M_Sigma);
* ``d``  -- the configuration parameter (5.88), 0 <= d <= 1, and k = 1 - d^2.

Only (Rt, h, H, d, R) matter (5.91): the number of weights and the unbalance enter
through d alone.

Critical speeds
---------------
A critical speed is a speed at which the main motion gains or loses stability.

* Damped case (h, H > 0).  a0 = Rt^2 R^8 (1 - d^2) > 0, so roots cross the
  imaginary axis only as imaginary pairs l = +-i mu, x = mu^2 a common root of
  the two halves of (5.123) (the tests check this at every crossing found).  The
  spectral abscissa is sampled on a logarithmic grid, which is then zoomed: every
  cell holding a sign change, or whose end values are within a few local
  variations of zero, is re-sampled (four rounds, 16-fold each), and every local
  extremum of the wrong sign close to zero (a peak just below 0, a dip just
  above) is refined with a bounded scalar optimiser.  So nearly coincident
  crossings -- thin unstable bands or stable windows inside one grid cell -- are
  found (checked against brute-force grids of 10^5-10^6 points); each sign change
  is then solved with ``brentq``.
* Conservative case (h = H = 0), form (5.98) with the corrected k Rt^2 factor.
  Stability is neutral: it holds iff the four roots x = l^2 are real and negative.
  The same scan is run on a continuous signed margin: for an unstable point the
  largest Re sqrt(x) (> 0), for a stable one minus the smaller of half the
  smallest gap between the frequencies omega_i = sqrt(-x_i) and the smallest
  omega_i.  It vanishes exactly where two real roots x collide (a discriminant
  event) or a root x passes through 0, and its sign is that of the indicator
  "some x is non-real or >= 0"; ``brentq`` on it locates the boundaries to
  ~1e-12 near R ~ 1-3 (a collision is a double root x, so double precision
  limits this to about 1e-10 R^2 at higher speeds).  The touching double root of (5.107) at k = 1 is not
  reported (the margin only touches zero there), but the thin band it opens
  into for k < 1 is (Rt = 0.05, d = 0.02: (1.67091, 1.68351)).
* Exactly one of h, H zero.  *Not* a neutral case, contrary to what one might
  expect: with h = 0 the coefficient a1 of (5.90) vanishes identically, so by
  Vieta (a1/a0 = -sum 1/l_i) the roots cannot all lie in the open left
  half-plane and the main motion is never asymptotically stable; with H = 0 the
  ball drag acts as rotating damping and the forward whirl is unstable at every
  speed (Kelvin-Tait-Chetaev), with a growth rate falling roughly as R^-3
  (+8e-9 at R = 100 for Rt = 0.05, h = 0.3, d = 0.3) that sinks below round-off
  near R ~ 10^3.  Both verified numerically over Rt in [0.001, 0.45], the other
  damping in [0.001, 20], d in [0, 1].  :func:`critical_speeds` returns [] and
  :func:`is_stable` False, each with a :class:`StabilityWarning`.
* Round-off.  The computed abscissa is trusted down to ``_abscissa_tol(R)``
  (~4e-15 (1 + R)^2); a point whose abscissa lies within it counts as stable and
  a :class:`StabilityWarning` is issued (very small damping at high speed, e.g.
  H = 1e-9).  Crossings are found with hysteresis so that such a flat abscissa
  cannot produce a chatter of crossings.

The structural zero root.  At d = 1 exactly (k = 0) a0 vanishes and l = 0 is a root
for every speed (motion along a degenerate family); it is removed (the polynomial
deflated) before the abscissa is taken, as in the digest's ``crit_speeds``.  The
remaining polynomial then has a real root passing through 0 at R = 1 (a1 = 0), the
critical speed R1 = 1 of (5.102) and (5.127).

Vanishing damping.  The damped critical speeds do not tend to the conservative
ones as h, H -> 0 (the destabilisation paradox): at Rt = 0.05, d = 0.02 the thin
conservative band disappears and h = H = 1e-4 gives a single critical speed
1.7206 against the conservative 1.6835; the limit depends on h/H.
"""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq, minimize_scalar

__all__ = [
    "StabilityWarning", "CriticalSpeed",
    "charpoly_coefficients", "conservative_coefficients", "main_eigenvalues",
    "spectral_abscissa", "is_stable",
    "d_two_balls", "d_from_angles",
    "critical_speeds", "unbalance_independent_threshold",
    "R1_first_order", "R1_refined", "R1_max_closed_form", "R1_max_validity",
    "high_speed_h_crit", "high_speed_h_crit_exact",
    "conservative_series_k0", "conservative_R1_parametric", "conservative_R1_k1",
    "conservative_R1_series", "conservative_R23_k1", "R_window_large_H",
    "balancing_rate", "jacobian_eigenvalues",
]

_EPS = np.finfo(float).eps
_RTOL = 4 * _EPS                 # the smallest rtol brentq accepts
R_MIN_DEFAULT = 0.5
R_MAX_DEFAULT = 1000.0
_GRID_PER_DECADE = 300           # base scan density (cell width ~0.8 % of R)


class StabilityWarning(UserWarning):
    """A stability verdict rests on an abscissa within round-off of zero, or on a
    degenerate parameter set (exactly one of h, H zero); the message says which."""


@dataclass(frozen=True)
class CriticalSpeed:
    """A speed at which the main motion changes stability.

    Attributes
    ----------
    R : float
        Speed ratio omega / omega_1.
    kind : str
        ``"gains"`` if the main motion is stable just above ``R`` and unstable just
        below it (stability is gained on increasing R), ``"loses"`` otherwise.
    mu : float
        Frequency (units of omega_1, rotating frame) of the roots that cross:
        l = +-i mu with x = mu^2 a common root of the two halves of (5.123)
        (damped case), or the frequency at which two roots x = -mu^2 of (5.98)
        collide (conservative case).  0 for a real root passing through l = 0
        (d = 1, R = 1).
    """

    R: float
    kind: str
    mu: float = math.nan


# ---------------------------------------------------------------------------
# input checks
# ---------------------------------------------------------------------------

def _check_params(Rt, h, H, d):
    Rt, h, H, d = float(Rt), float(h), float(H), float(d)
    if not (0.0 < Rt < 0.5):
        raise ValueError(f"Rt = R~_m must lie in (0, 0.5), got {Rt!r}")
    for name, v in (("h", h), ("H", H)):
        if not (math.isfinite(v) and v >= 0.0):
            raise ValueError(f"{name} must be a finite number >= 0, got {v!r}")
    if not (0.0 <= d <= 1.0):
        raise ValueError(f"d must lie in [0, 1] (5.88), got {d!r}")
    return Rt, h, H, d


def _check_range(R_min, R_max):
    R_min, R_max = float(R_min), float(R_max)
    if not (0.0 < R_min < R_max and math.isfinite(R_max)):
        raise ValueError(f"need 0 < R_min < R_max < inf, got ({R_min!r}, {R_max!r})")
    return R_min, R_max


# ---------------------------------------------------------------------------
# the characteristic polynomial (5.90) and its conservative form (5.98)
# ---------------------------------------------------------------------------

def charpoly_coefficients(R, Rt, h, H, d):
    """Coefficients a0..a8 of the main-motion characteristic polynomial (5.90).

    D(l) = sum_i a_i l^i is the expansion of the determinant (5.89); all a_i are
    real and polynomials in R^2.

    Parameters
    ----------
    R : float or array_like
        Speed ratio omega / omega_1.
    Rt : float
        R~_m (5.88), 0 < Rt < 0.5.
    h, H : float
        Weight drag and support damping (>= 0).
    d : float
        Configuration parameter (5.88), 0 <= d <= 1.

    Returns
    -------
    ndarray
        Shape ``(9,)`` for a scalar ``R``, else ``R.shape + (9,)``; entry i is a_i
        (increasing powers; reverse for :func:`numpy.roots`).
    """
    W = np.asarray(R, dtype=float)
    k = 1.0 - d * d
    W2 = W * W
    W4 = W2 * W2
    s = W2 - 1.0
    P = s * s + H * H * W2                      # (R^2-1)^2 + H^2 R^2
    one = np.ones_like(W)
    a = [Rt * Rt * W4 * W4 * k,
         2.0 * h * Rt * W4 * s,
         P * h * h + 2.0 * Rt * W4 * (s + 3.0 * h * H) + 4.0 * Rt * Rt * W4 * W2 * k,
         2.0 * ((P + Rt * W2 * (6.0 + W2)) * h + 3.0 * Rt * W4 * H + (W2 + 1.0) * h * h * H),
         (s * s + (H * H + 2.0 * h * h + 4.0 * h * H) * W2 + h * h * H * H + 2.0 * h * h
          + 4.0 * h * H + 2.0 * Rt * W2 * (W2 + 6.0 + 2.0 * h * H) + 6.0 * Rt * Rt * W4 * k),
         2.0 * (h * (2.0 - Rt) * (W2 + 1.0) + H * ((1.0 + 2.0 * Rt) * W2 + 1.0) + h * H * (h + H)),
         2.0 * (1.0 - Rt) * (W2 + 1.0 + H * h) + (h + H) ** 2 + 4.0 * Rt * Rt * W2 * k,
         2.0 * (h + H) * (1.0 - Rt) * one,
         (1.0 - 2.0 * Rt + Rt * Rt * k) * one]
    return np.stack(a, axis=-1)


def conservative_coefficients(R, Rt, d):
    """Coefficients c0..c4 of the conservative polynomial (5.98) in x = l^2.

    P(x) = (A6 x^3 + A4 x^2 + A2 x + A0) x + k Rt^2 (x + R^2)^4  with
    A0 = 2 Rt R^4 (R^2 - 1), A2 = (R^2 - 1)^2 + 2 Rt R^2 (R^2 + 6),
    A4 = 2 (1 - Rt)(R^2 + 1), A6 = 1 - 2 Rt and k = 1 - d^2.  The factor Rt^2 of
    the last term is the digest's correction of the printed (5.98); with it c_j
    equals a_{2j} of (5.90) at h = H = 0.

    Returns
    -------
    ndarray
        Shape ``(5,)`` (or ``R.shape + (5,)``), increasing powers of x.
    """
    W = np.asarray(R, dtype=float)
    W2 = W * W
    k = 1.0 - d * d
    A0 = 2.0 * Rt * W2 * W2 * (W2 - 1.0)
    A2 = (W2 - 1.0) ** 2 + 2.0 * Rt * W2 * (W2 + 6.0)
    A4 = 2.0 * (1.0 - Rt) * (W2 + 1.0)
    A6 = (1.0 - 2.0 * Rt) * np.ones_like(W)
    q = k * Rt * Rt
    # (x + R^2)^4 = x^4 + 4 R^2 x^3 + 6 R^4 x^2 + 4 R^6 x + R^8
    c = [q * W2 ** 4, A0 + 4.0 * q * W2 ** 3, A2 + 6.0 * q * W2 ** 2, A4 + 4.0 * q * W2, A6 + q]
    return np.stack(c, axis=-1)


def _companion_roots(A):
    """Roots of the polynomials with coefficient rows ``A`` (increasing powers,
    leading coefficient non-zero), shape (N, m+1) -> (N, m), by batched eigvals."""
    A = np.atleast_2d(A)
    N, m1 = A.shape
    m = m1 - 1
    C = np.zeros((N, m, m))
    C[:, 0, :] = -A[:, m - 1::-1] / A[:, m:m + 1]
    if m > 1:
        C[:, np.arange(1, m), np.arange(m - 1)] = 1.0
    return np.linalg.eigvals(C)


def main_eigenvalues(R, Rt, h, H, d):
    """The 8 roots of (5.90), sorted by decreasing real part.

    At d = 1 the list contains the structural root l = 0 (see the module notes);
    :func:`spectral_abscissa` ignores it.

    Parameters
    ----------
    R, Rt, h, H, d : float
        As in :func:`charpoly_coefficients`.

    Returns
    -------
    ndarray of complex, shape (8,)
    """
    Rt, h, H, d = _check_params(Rt, h, H, d)
    a = charpoly_coefficients(float(R), Rt, h, H, d)
    lam = _companion_roots(a)[0]
    return lam[np.argsort(-lam.real, kind="stable")]


def _abscissa_batch(R, Rt, h, H, d):
    """max Re l over the roots of (5.90) at each speed of ``R`` (array), with the
    structural zero root removed when d = 1."""
    A = charpoly_coefficients(np.asarray(R, float), Rt, h, H, d)
    if d == 1.0:
        A = A[:, 1:]                      # a0 == 0: deflate l = 0
    return _companion_roots(A).real.max(axis=1)


def spectral_abscissa(R, Rt, h, H, d):
    """Largest real part of the roots of (5.90) (structural zero root removed at d = 1).

    Negative: asymptotically stable main motion; positive: unstable.  In the
    conservative case (h = H = 0) it is >= 0 (neutral stability at best); use
    :func:`is_stable` for a verdict.

    Parameters
    ----------
    R : float or array_like
    Rt, h, H, d : float

    Returns
    -------
    float or ndarray
    """
    Rt, h, H, d = _check_params(Rt, h, H, d)
    Ra = np.asarray(R, dtype=float)
    out = _abscissa_batch(Ra.reshape(-1), Rt, h, H, d)
    return float(out[0]) if Ra.ndim == 0 else out.reshape(Ra.shape)


def _abscissa_tol(R):
    """Round-off floor of the computed abscissa (companion eigenvalues; measured
    against 40-digit roots the error stays below ~1e-15 R^2 for R <= 5000)."""
    return 16.0 * _EPS * (1.0 + np.asarray(R, float)) ** 2


def _conservative_margin_batch(R, Rt, d):
    """Signed stability margin of the conservative case (module notes): > 0 iff some
    root x of (5.98) is non-real or >= 0 (unstable), < 0 iff all are real and < 0."""
    C = conservative_coefficients(np.asarray(R, float), Rt, d)
    if d == 1.0:
        C = C[:, 1:]                      # c0 == 0: deflate x = 0 (l = 0 twice)
    x = _companion_roots(C)
    u = np.sqrt(x.astype(complex)).real.max(axis=1)   # principal sqrt: Re >= 0
    w = np.sort(np.sqrt(np.maximum(-x.real, 0.0)), axis=1)
    stable_margin = np.minimum(w[:, 0], 0.5 * np.diff(w, axis=1).min(axis=1))
    return np.where(u > 0.0, u, -stable_margin)


def _conservative_tol(R):
    """Noise floor of the conservative margin: a double root x is computed to
    ~sqrt(eps) |x|, i.e. the margin to ~1e-8 (1 + R)."""
    return 1e-7 * (1.0 + np.asarray(R, float))


def is_stable(R, Rt, h, H, d):
    """Whether the main motion is stable at speed ``R``.

    Asymptotic stability (abscissa below the round-off floor ``_abscissa_tol``)
    when h, H > 0; neutral stability in the first approximation (all x = l^2 real
    and negative, (5.98)) when h = H = 0; ``False`` with a
    :class:`StabilityWarning` when exactly one of h, H is zero (module notes).
    """
    Rt, h, H, d = _check_params(Rt, h, H, d)
    R = float(R)
    if h == 0.0 and H == 0.0:
        return bool(_conservative_margin_batch(np.array([R]), Rt, d)[0] <= _conservative_tol(R))
    if h == 0.0 or H == 0.0:
        warnings.warn(StabilityWarning(_degenerate_message(h, H, "is_stable")), stacklevel=2)
        return False
    return bool(_abscissa_batch(np.array([R]), Rt, h, H, d)[0] <= _abscissa_tol(R))


# ---------------------------------------------------------------------------
# the configuration parameter d (5.88)
# ---------------------------------------------------------------------------

def d_two_balls(e0):
    """d = |cos(alpha_1 - alpha_2)| = |2 e0^2 - 1| for two identical balls (5.88).

    The balls of a main motion sit at pi +- theta with cos theta = e0 (5.50), so
    k = 1 - d^2 = 4 e0^2 (1 - e0^2).  ``e0`` in [0, 1] (the unbalance S in units
    of the capacity).
    """
    e0 = np.asarray(e0, dtype=float)
    if np.any((e0 < 0) | (e0 > 1)):
        raise ValueError("d_two_balls: a main motion of two balls needs 0 <= e0 <= 1")
    out = np.abs(2.0 * e0 * e0 - 1.0)
    return float(out) if out.ndim == 0 else out


def d_from_angles(alphas, weights=None):
    """Configuration parameter d of (5.88) from the weights' relative angles.

    d = |sum_j w_j e^{2 i alpha_j}| / sum_j w_j with w_j = m_j^2 l_j^2 / J_j; for
    identical weights (the default, ``weights=None``) d = |mean e^{2 i alpha_j}|.

    Parameters
    ----------
    alphas : array_like
        Angles alpha_j of the weights relative to the rotor [rad].
    weights : array_like or None
        m_j^2 l_j^2 / J_j (any common unit), one per weight.

    Returns
    -------
    float in [0, 1]
    """
    a = np.asarray(alphas, dtype=float)
    w = np.ones_like(a) if weights is None else np.asarray(weights, dtype=float)
    if w.shape != a.shape or np.any(w < 0) or not np.sum(w) > 0:
        raise ValueError("d_from_angles: need one non-negative weight per angle, not all zero")
    return float(min(1.0, abs(np.sum(w * np.exp(2j * a))) / np.sum(w)))


# ---------------------------------------------------------------------------
# critical speeds
# ---------------------------------------------------------------------------

def _merge(R, F, Rn, Fn):
    R2 = np.concatenate([R, Rn])
    F2 = np.concatenate([F, Fn])
    o = np.argsort(R2, kind="stable")
    return R2[o], F2[o]


def _scan_sign_changes(f, R_min, R_max, n_grid, floor, *, depth=4, split=16):
    """Sample a continuous function ``f`` (vectorised over an array of speeds) on
    [R_min, R_max] densely enough to bracket every sign change, including nearly
    coincident pairs.

    1. Log grid of ``n_grid`` points.
    2. ``depth`` rounds of zooming: every cell that holds a sign change, or whose
       smaller end value is within 3 local cell-variations of zero (a thin band or
       window may hide inside, or more crossings share the cell), is re-sampled
       with ``split - 1`` interior points.
    3. Every interior local extremum of the wrong sign that is close to zero on
       the same scale (a peak below zero, a dip above zero) is refined by a
       bounded scalar optimiser; a point of the other sign is added if found.

    ``floor(R)`` is the magnitude below which f is round-off; cells whose values
    all lie below it are not zoomed.  Returns the sorted speeds and values, and
    the base grid with its values.
    """
    R = np.geomspace(R_min, R_max, n_grid)
    F = f(R)
    R0, F0 = R, F
    for _ in range(depth):
        if R.size < 3:
            break
        dF = np.abs(np.diff(F))
        var = dF.copy()
        var[1:] = np.maximum(var[1:], dF[:-1])
        var[:-1] = np.maximum(var[:-1], dF[1:])
        a, b = F[:-1], F[1:]
        change = (a > 0) != (b > 0)
        near = np.minimum(np.abs(a), np.abs(b)) <= 3.0 * var
        noisy = np.maximum(np.abs(a), np.abs(b)) <= floor(R[1:])
        wide = (R[1:] - R[:-1]) > 1e-9 * R[1:]
        cells = np.nonzero((change | (near & ~noisy)) & wide)[0]
        if cells.size == 0:
            break
        t = np.linspace(0.0, 1.0, split + 1)[1:-1]
        Rn = (R[cells, None] + (R[cells + 1] - R[cells])[:, None] * t).ravel()
        R, F = _merge(R, F, Rn, f(Rn))
    extra = []
    i = np.arange(1, R.size - 1)
    lo, mid, hi = F[i - 1], F[i], F[i + 1]
    var = np.maximum(np.abs(mid - lo), np.abs(hi - mid))
    noisy = np.maximum(np.maximum(np.abs(lo), np.abs(hi)), np.abs(mid)) <= floor(R[i])
    peak = (mid < 0) & (mid >= lo) & (mid >= hi)
    dip = (mid > 0) & (mid <= lo) & (mid <= hi)
    near = np.abs(mid) <= 4.0 * var
    for j in i[(peak | dip) & near & ~noisy]:
        sgn = 1.0 if F[j] < 0 else -1.0          # maximise f at a peak, minimise at a dip
        res = minimize_scalar(lambda r: -sgn * f(np.array([r]))[0],
                              bounds=(R[j - 1], R[j + 1]), method="bounded",
                              options={"xatol": 1e-12 * R[j]})
        if res.fun < 0:                          # f changes sign inside the cell
            extra.append(res.x)
    if extra:
        Rn = np.asarray(extra)
        R, F = _merge(R, F, Rn, f(Rn))
    return R, F, R0, F0


def _crossing_frequency(R, Rt, h, H, d):
    """mu of :class:`CriticalSpeed` at a crossing speed R."""
    if h == 0.0 and H == 0.0:
        C = conservative_coefficients(np.array([R]), Rt, d)
        if d == 1.0:
            C = C[:, 1:]
        x = _companion_roots(C)[0]
        w = np.sort(np.sqrt(np.abs(x)))
        if w.size < 2:
            return float(w[0])
        g = np.diff(w)
        j = int(np.argmin(g))
        return float(w[0]) if w[0] < 0.5 * g[j] else float(0.5 * (w[j] + w[j + 1]))
    A = charpoly_coefficients(np.array([R]), Rt, h, H, d)
    if d == 1.0:
        A = A[:, 1:]
    lam = _companion_roots(A)[0]
    mu = float(abs(lam[np.argmax(lam.real)].imag))
    if d == 1.0 or mu == 0.0:
        return mu
    # polish x = mu^2 on the odd half of (5.123), a1 - a3 x + a5 x^2 - a7 x^3 = 0
    a = A[0]
    x = mu * mu
    for _ in range(3):
        q = a[1] - a[3] * x + a[5] * x * x - a[7] * x ** 3
        dq = -a[3] + 2.0 * a[5] * x - 3.0 * a[7] * x * x
        if dq == 0.0 or not math.isfinite(q / dq) or x - q / dq <= 0.0:
            break
        x -= q / dq
    return math.sqrt(x)


def _crossings(f, R, F, noise, params):
    """brentq every change of sign of f on the sampled grid; kind from the signs.

    Hysteresis against round-off: a sample counts as positive if f > noise(R),
    negative if f < -noise(R), and keeps the previous verdict otherwise, so a
    function that creeps along zero cannot produce a chatter of crossings.
    """
    eta = noise(R)
    state = np.where(F > eta, 1, np.where(F < -eta, -1, 0))
    idx = np.nonzero(state)[0]
    out = []
    for p, q in zip(idx[:-1], idx[1:]):
        if state[p] == state[q]:
            continue
        r = brentq(lambda x: f(np.array([x]))[0], R[p], R[q], xtol=1e-13, rtol=_RTOL,
                   maxiter=200)
        out.append(CriticalSpeed(R=float(r), kind="gains" if state[p] > 0 else "loses",
                                 mu=_crossing_frequency(r, *params)))
    return out


def _polish_conservative(c, Rt, d):
    """Move a conservative boundary from margin = tol to margin = 0.

    Near a collision of roots x the margin grows like sqrt|R - R*|, so the root of
    margin - tol found by the scan sits (tol / slope)^2 inside the unstable side
    (up to ~1e-9 at R ~ 30).  The margin itself is bracketed by stepping towards the
    stable side and solved again; the noise of the margin (~1e-8 (1 + R)) then
    displaces the boundary by < 1e-12.
    """
    def m(x):
        return _conservative_margin_batch(np.array([x]), Rt, d)[0]

    toward = 1.0 if c.kind == "gains" else -1.0        # the stable side
    if not m(c.R) > 0.0:
        return c
    step = 1e-13 * c.R
    while step < 1e-6 * c.R:
        other = c.R + toward * step
        if m(other) < 0.0:
            lo, hi = sorted((c.R, other))
            r = brentq(m, lo, hi, xtol=1e-15, rtol=_RTOL, maxiter=200)
            return CriticalSpeed(R=float(r), kind=c.kind, mu=c.mu)
        step *= 4.0
    return c


def _n_grid(R_min, R_max, n_grid):
    if n_grid is not None:
        return max(int(n_grid), 8)
    return max(64, int(math.ceil(_GRID_PER_DECADE * math.log10(R_max / R_min))))


def critical_speeds(Rt, h, H, d, R_min=R_MIN_DEFAULT, R_max=R_MAX_DEFAULT, *, n_grid=None):
    """Critical speeds of the main motion in (R_min, R_max) (digest ch5 4.2, 4.4).

    Parameters
    ----------
    Rt : float
        R~_m (5.88), 0 < Rt < 0.5.
    h, H : float
        Weight drag and support damping, >= 0.  h = H = 0 selects the conservative
        analysis (5.98)-(5.107); otherwise the spectral abscissa of (5.90) is used.
    d : float
        Configuration parameter (5.88).
    R_min, R_max : float
        Speed range scanned (log grid).  Below resonance the main motion is
        unstable (a1 < 0, digest 4.1), so the default R_min = 0.5 starts in an
        unstable zone.
    n_grid : int or None
        Base grid size; default 300 points per decade (then zoomed, see
        :func:`_scan_sign_changes`).

    Returns
    -------
    list of CriticalSpeed
        In increasing R.  ``"gains"``: stable just above; ``"loses"``: unstable
        just above.  Whether the motion is stable at R_min is given by
        :func:`is_stable`.  Crossings are located to ~1e-12 in R (damped; less
        where the abscissa itself is tiny, e.g. ~1e-6 for H = 1000 near R = 1)
        and to ~1e-12 at R ~ 1-3 in the conservative case, where a boundary is a
        double root x and double precision limits it to about 1e-10 R^2 (e.g.
        +-3e-10 at R = 22, Rt = 0.24).

    Notes
    -----
    Damped case: scan of f(R) = abscissa(R) - tol(R) with tol the round-off floor
    (~4e-15 (1 + R)^2; moves a crossing by tol / slope, far below any printed
    digit).  Conservative case: the signed margin of the module notes minus its
    noise floor 1e-7 (1 + R) (so a touching double root, (5.107) at k = 1, is not
    taken for a band); each boundary is then re-solved on the margin itself
    (:func:`_polish_conservative`).  Unstable bands narrower than the location
    accuracy cannot be resolved (the scan itself was checked down to a band
    6e-5 wide, Rt = 0.05, d = 1e-4).
    A :class:`StabilityWarning` is issued when exactly one of h, H is zero
    (see module notes) or when the verdict somewhere rests on an abscissa within
    the round-off floor.
    """
    Rt, h, H, d = _check_params(Rt, h, H, d)
    R_min, R_max = _check_range(R_min, R_max)
    n = _n_grid(R_min, R_max, n_grid)
    if h == 0.0 and H == 0.0:
        def f(R):
            return _conservative_margin_batch(R, Rt, d) - _conservative_tol(R)
        Rg, Fg, _, _ = _scan_sign_changes(f, R_min, R_max, n, _conservative_tol)
        cs = _crossings(f, Rg, Fg, lambda R: 0.5 * _conservative_tol(R), (Rt, h, H, d))
        return [_polish_conservative(c, Rt, d) for c in cs]

    if h == 0.0 or H == 0.0:
        warnings.warn(StabilityWarning(_degenerate_message(h, H, "critical_speeds")
                                       + "; no critical speed returned"), stacklevel=2)
        return []

    def f(R):
        return _abscissa_batch(R, Rt, h, H, d) - _abscissa_tol(R)

    Rg, Fg, R0, F0 = _scan_sign_changes(f, R_min, R_max, n, _abscissa_tol)
    flat = np.abs(F0 + _abscissa_tol(R0)) <= _abscissa_tol(R0)
    if np.any(flat):
        r = R0[flat]
        warnings.warn(StabilityWarning(
            f"critical_speeds: the spectral abscissa is within round-off of zero for R in "
            f"[{r.min():.6g}, {r.max():.6g}] (damping too small to resolve there); those "
            f"speeds count as stable"), stacklevel=2)
    return _crossings(f, Rg, Fg, lambda R: 0.5 * _abscissa_tol(R), (Rt, h, H, d))


def _degenerate_message(h, H, who):
    if h == 0.0:
        return (f"{who}: h = 0 with H > 0: a1 of (5.90) vanishes identically, so by "
                f"Vieta the main motion is never asymptotically stable")
    return (f"{who}: H = 0 with h > 0: the ball drag acts as rotating damping and the "
            f"main motion is unstable at every speed (growth rate ~ R^-3, below "
            f"round-off from R ~ 10^3 on)")


def _last_gain(cs, stable_at_end):
    """The last stabilising crossing, or inf if the motion is unstable at the end."""
    if not stable_at_end:
        return math.inf
    for c in reversed(cs):
        if c.kind == "gains":
            return c.R
    return -math.inf      # stable over the whole range (cannot happen from R_min < 1)


def unbalance_independent_threshold(Rt, h, H, *, R_min=R_MIN_DEFAULT, R_max=R_MAX_DEFAULT,
                                    n_d=41, n_grid=None):
    """Speed above which the main motion is stable for every unbalance (digest 4.2, 4.4).

    sup over d in [0, 1] of the last stabilising critical speed.  Since d ranges
    over all configurations of any number of weights (5.88), this is the speed
    above which autobalancing holds whatever the unbalance.  The book's
    R_omega1max (5.127) assumes the worst case is d = 0; for low damping it is not
    (digest 4.4 "Warning for low damping": d = 1 gives the sup).

    Parameters
    ----------
    Rt, h, H : float
    R_min, R_max : float
        Speed range of each scan.
    n_d : int
        Size of the d grid (uniform in d, plus points clustered at d = 1); the best
        grid point is refined by a bounded scalar search over its neighbours.
    n_grid : int or None
        Passed to :func:`critical_speeds`.

    Returns
    -------
    float
        ``inf`` if for some d the main motion is unstable at R_max (e.g.
        h < H sqrt(Rt), (5.96), or exactly one of h, H zero).
    """
    Rt, h, H, _ = _check_params(Rt, h, H, 0.0)
    R_min, R_max = _check_range(R_min, R_max)

    def last(d):
        d = min(max(float(d), 0.0), 1.0)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", StabilityWarning)
            cs = critical_speeds(Rt, h, H, d, R_min, R_max, n_grid=n_grid)
            ok = is_stable(R_max, Rt, h, H, d)
        return _last_gain(cs, ok)

    ds = np.unique(np.concatenate([np.linspace(0.0, 1.0, max(int(n_d), 3)),
                                   1.0 - np.geomspace(1e-4, 0.05, 8)]))
    vals = np.array([last(d) for d in ds])
    if np.any(np.isinf(vals) & (vals > 0)):
        return math.inf
    j = int(np.argmax(vals))
    best = vals[j]
    lo, hi = ds[max(j - 1, 0)], ds[min(j + 1, ds.size - 1)]
    if hi > lo:
        res = minimize_scalar(lambda x: -last(x), bounds=(lo, hi), method="bounded",
                              options={"xatol": 1e-7})
        best = max(best, -res.fun)
    return float(best)


# ---------------------------------------------------------------------------
# closed forms beside the numerics
# ---------------------------------------------------------------------------

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


def high_speed_h_crit_exact(Rt, H, d, R=1000.0, *, h_max=None):
    """Exact ball-drag threshold for stability at a fixed high speed (cf. (5.96)).

    The largest h at which the spectral abscissa of (5.90) at speed ``R`` changes
    sign from positive (h below) to negative (h above).  For d = 0 and R >= 100
    it equals H sqrt(Rt) to 0.3 % (digest 4.2: 0.16771 at Rt = 0.05, H = 0.75);
    for d > 0 it is lower (0.0773 at d = 0.5, 0.0119 at d = 0.9).

    Parameters
    ----------
    Rt, H : float
        H > 0.
    d : float
    R : float
        Speed ratio (>> 1).
    h_max : float or None
        Upper end of the h search (default 10 (1 + H)).

    Returns
    -------
    float
        0.0 if the main motion is stable at ``R`` for every h scanned.
    """
    Rt, _, H, d = _check_params(Rt, 0.0, H, d)
    if H <= 0.0:
        raise ValueError("high_speed_h_crit_exact: needs H > 0")
    R = float(R)
    hi = 10.0 * (1.0 + H) if h_max is None else float(h_max)
    hs = np.geomspace(1e-6 * max(H * math.sqrt(Rt), 1e-6), hi, 400)
    tol = _abscissa_tol(R)

    def g(hh):
        return _abscissa_batch(np.array([R]), Rt, hh, H, d)[0] - tol

    vals = np.array([g(x) for x in hs])
    idx = np.nonzero((vals[:-1] > 0) & (vals[1:] <= 0))[0]
    if idx.size == 0:
        return 0.0 if vals[-1] <= 0 else math.inf
    c = idx[-1]
    return float(brentq(g, hs[c], hs[c + 1], xtol=1e-14, rtol=_RTOL))


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


# ---------------------------------------------------------------------------
# independent check: the simulator's own rotating-frame Jacobian
# ---------------------------------------------------------------------------

def jacobian_eigenvalues(model, R, alphas, *, zero_tol=1e-7):
    """Eigenvalues of the simulator's rotating-frame Jacobian at a main motion.

    Thin wrapper over :func:`stand.rotating.rotating_jacobian` at
    :func:`stand.rotating.main_motion_state` (central differences, error ~1e-7).
    For n = 2 the 8 eigenvalues are the roots of (5.90).  For n >= 3 the main
    motions form an (n-2)-parameter family (5.50), which contributes n - 2 zero
    eigenvalues (motion along the family) and n - 2 eigenvalues -h (relative
    weight modes, digest 4.1); the n - 2 eigenvalues of smallest modulus are
    dropped when below ``zero_tol * max(1, max|l|)``, the -h ones are kept.

    Parameters
    ----------
    model : stand.planar.PlanarModel
        A prescribed-speed model with isotropic supports.
    R : float
        Speed ratio of the frame (the model's programme speed should equal it).
    alphas : array_like
        Relative angles of a balanced configuration [rad].

    Returns
    -------
    ndarray of complex
        Sorted by decreasing real part; 2n + 4 - (n - 2) values for n >= 3.

    Raises
    ------
    ValueError
        ``alphas`` is not a main motion of ``model`` at speed R.
    """
    from stand.rotating import main_motion_state, rotating_jacobian, rotating_rhs

    z = main_motion_state(model, np.asarray(alphas, dtype=float))
    res = np.max(np.abs(rotating_rhs(model, R, z)))
    if res > 1e-8 * (1.0 + R * R):
        raise ValueError(f"jacobian_eigenvalues: not a main motion (residual {res:.3g})")
    lam = np.linalg.eigvals(rotating_jacobian(model, R, z))
    n = model.n
    if n >= 3:
        scale = max(1.0, float(np.max(np.abs(lam))))
        order = np.argsort(np.abs(lam))
        drop = [i for i in order[:n - 2] if abs(lam[i]) < zero_tol * scale]
        lam = np.delete(lam, drop)
    return lam[np.argsort(-lam.real, kind="stable")]
