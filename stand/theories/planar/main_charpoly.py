"""Main (balancing) motions of a planar rotor with n correction weights: the
characteristic polynomial (5.90), its conservative form (5.98) and the stability verdict.

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

Stability
---------
* Damped case (h, H > 0): asymptotic stability iff the spectral abscissa (the
  largest real part of the roots of (5.90)) is negative.
* Conservative case (h = H = 0), form (5.98) with the corrected k Rt^2 factor.
  Stability is neutral: it holds iff the four roots x = l^2 are real and negative.
  A continuous signed margin measures it: for an unstable point the largest
  Re sqrt(x) (> 0), for a stable one minus the smaller of half the smallest gap
  between the frequencies omega_i = sqrt(-x_i) and the smallest omega_i.  It
  vanishes exactly where two real roots x collide (a discriminant event) or a
  root x passes through 0, and its sign is that of the indicator "some x is
  non-real or >= 0" (:mod:`stand.theories.planar.main_critical` locates its zeros).
* Exactly one of h, H zero.  *Not* a neutral case, contrary to what one might
  expect: with h = 0 the coefficient a1 of (5.90) vanishes identically, so by
  Vieta (a1/a0 = -sum 1/l_i) the roots cannot all lie in the open left
  half-plane and the main motion is never asymptotically stable; with H = 0 the
  ball drag acts as rotating damping and the forward whirl is unstable at every
  speed (Kelvin-Tait-Chetaev), with a growth rate falling roughly as R^-3
  (+8e-9 at R = 100 for Rt = 0.05, h = 0.3, d = 0.3) that sinks below round-off
  near R ~ 10^3.  Both verified numerically over Rt in [0.001, 0.45], the other
  damping in [0.001, 20], d in [0, 1].  :func:`is_stable` returns False and
  :func:`stand.theories.planar.main_critical.critical_speeds` returns [], each with a
  :class:`StabilityWarning`.
* Round-off.  The computed abscissa is trusted down to ``_abscissa_tol(R)``
  (~4e-15 (1 + R)^2); a point whose abscissa lies within it counts as stable and
  a :class:`StabilityWarning` is issued (very small damping at high speed, e.g.
  H = 1e-9).

The structural zero root.  At d = 1 exactly (k = 0) a0 vanishes and l = 0 is a root
for every speed (motion along a degenerate family); it is removed (the polynomial
deflated) before the abscissa is taken, as in the digest's ``crit_speeds``.  The
remaining polynomial then has a real root passing through 0 at R = 1 (a1 = 0), the
critical speed R1 = 1 of (5.102) and (5.127).
"""
from __future__ import annotations

import math
import warnings

import numpy as np

__all__ = [
    "StabilityWarning",
    "charpoly_coefficients", "conservative_coefficients", "main_eigenvalues",
    "spectral_abscissa", "is_stable",
    "d_two_balls", "d_from_angles",
    "jacobian_eigenvalues",
]

_EPS = np.finfo(float).eps


class StabilityWarning(UserWarning):
    """A stability verdict rests on an abscissa within round-off of zero, or on a
    degenerate parameter set (exactly one of h, H zero); the message says which."""


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


def _is_stable_batch(R, Rt, h, H, d):
    """:func:`is_stable` at each speed of the 1-D array ``R`` (checked parameters), without the
    warning of the degenerate case: the same verdicts, the polynomials' roots in one stacked
    eigenvalue call."""
    R = np.asarray(R, dtype=float)
    if h == 0.0 and H == 0.0:
        return _conservative_margin_batch(R, Rt, d) <= _conservative_tol(R)
    if h == 0.0 or H == 0.0:
        return np.zeros(R.shape, dtype=bool)
    return _abscissa_batch(R, Rt, h, H, d) <= _abscissa_tol(R)


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


def _degenerate_message(h, H, who):
    if h == 0.0:
        return (f"{who}: h = 0 with H > 0: a1 of (5.90) vanishes identically, so by "
                f"Vieta the main motion is never asymptotically stable")
    return (f"{who}: H = 0 with h > 0: the ball drag acts as rotating damping and the "
            f"main motion is unstable at every speed (growth rate ~ R^-3, below "
            f"round-off from R ~ 10^3 on)")


# ---------------------------------------------------------------------------
# independent check: the simulator's own rotating-frame Jacobian
# ---------------------------------------------------------------------------

def jacobian_eigenvalues(model, R, alphas, *, zero_tol=1e-7):
    """Eigenvalues of the simulator's rotating-frame Jacobian at a main motion.

    Thin wrapper over :func:`stand.theories.rotating.rotating_jacobian` at
    :func:`stand.theories.rotating.main_motion_state` (central differences, error ~1e-7).
    For n = 2 the 8 eigenvalues are the roots of (5.90).  For n >= 3 the main
    motions form an (n-2)-parameter family (5.50), which contributes n - 2 zero
    eigenvalues (motion along the family) and n - 2 eigenvalues -h (relative
    weight modes, digest 4.1); the n - 2 eigenvalues of smallest modulus are
    dropped when below ``zero_tol * max(1, max|l|)``, the -h ones are kept.

    Parameters
    ----------
    model : stand.model.planar.PlanarModel
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
    from stand.theories.rotating import main_motion_state, rotating_jacobian, rotating_rhs

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
