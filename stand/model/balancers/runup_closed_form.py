"""Closed-form run-up of model M1 (paper 001) through its critical speed.

Lewis (1932) / Dimentberg (1959) solution of the Jeffcott rotor accelerated
uniformly, in the form of the digest ``papers_001_003_004.md`` section 4.2,
here for the liquid float-type balancer (``Omega = Omega_0 sqrt(psi)``,
``2h = n psi``, ``q = psi e``).  It is both the gold oracle of the ODE
integrators (digest 5.2 item 1, oracle O3) and a fast path: the deflection at
any set of times costs a few Fresnel / Faddeeva evaluations, independent of
how many revolutions lie before them.

Derivation (re-checked here, it agrees with the digest).  With
``W = Z + q e^{i beta}``, ``beta = omega_0 t + epsilon t^2``:
``W'' + 2h W' + Omega^2 W = f(t) = q (Omega^2 + 2 i h omega(t)) e^{i beta}``.
Modes ``lambda_(+/-) = -h +/- sqrt(h^2 - Omega^2)`` and ``W = u_+ + u_-`` with
``u_(+/-)' = lambda u_(+/-) +/- f/(lambda_+ - lambda_-)``, so ``W' = lambda_+ u_+ + lambda_- u_-``
and::

    u(t) = e^{lambda t} u(0) +/- q/(lambda_+ - lambda_-) [(Omega^2 + 2 i h omega_0) E0 + 4 i h epsilon E1]
    E0 = e^{lambda t} int_0^t e^{i eps s^2 + b s} ds,  E1 = e^{lambda t} int_0^t s e^{i eps s^2 + b s} ds,
    b = i omega_0 - lambda.

* ``n = 0``: ``E0 = e^{i nu t} J(t; omega_0 - nu)`` (``lambda = i nu``) with the Fresnel
  integral ``J`` of digest 4.2 (``scipy.special.fresnel``); the E1 term has the factor
  ``h = 0``.
* ``n > 0``: ``E0 = sqrt(pi)/(2p) [-e^{i beta} w~(z1) + e^{lambda t} w~(z0) + 2 1{Im z0 < 0 <= Im z1} e^{lambda t - z0^2}]``
  with ``p = sqrt(eps) e^{-i pi/4}``, ``s0 = b/(2 i eps)``, ``z1 = i p (t + s0)``,
  ``z0 = i p s0``, ``w~(z) = w(z)`` for ``Im z >= 0`` and ``-w(-z)`` otherwise
  (``w`` = ``scipy.special.wofz``).  Every term is bounded: ``|e^{lambda t - z0^2}|
  = e^{-h (t - t_res)}`` and the indicator needs ``t >= t_res + h/(2 eps)``.  The
  naive form with ``w(z1)`` in the lower half plane overflows (digest: errors of
  1e43 at n = 5, NaN at n = 100) and is not used.
  ``E1 = (e^{i beta} - e^{lambda t} - b E0)/(2 i eps)``.
* ``epsilon < 0`` (run-down): ``Z(t; omega_0, eps) = conj Z(t; -omega_0, -eps)``
  (the conjugate equation is the one with ``beta -> -beta``; the stationary
  initial state conjugates the same way).
* ``epsilon = 0``: ``E0 = (e^{i omega_0 t} - e^{lambda t})/b`` (stationary orbit).

Initial data (7): ``Z0 = psi e omega_0^2/(Omega^2 - omega_0^2 + 2 i h omega_0)``,
``W0 = Z0 + q``, ``W0' = i omega_0 W0``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import minimize_scalar
from scipy.special import fresnel, wofz

from stand.model.balancers.liquid_float import LiquidFloatParams

__all__ = [
    "runup_closed_form", "runup_closed_form_state", "runup_extrema", "RunupExtrema",
    "free_whirl_amplitudes", "undamped_asymptotics", "fresnel_overshoot",
]

_SQRT_PI = math.sqrt(math.pi)


# ---------------------------------------------------------------------------
# special-function kernels
# ---------------------------------------------------------------------------

def _wtilde(z):
    """``w(z)`` for Im z >= 0 and ``-w(-z)`` below (bounded by 1 everywhere)."""
    up = z.imag >= 0
    return np.where(up, wofz(np.where(up, z, 1j)), -wofz(np.where(up, -1j, -z)))


def _E0_E1_faddeeva(lam: complex, omega_0: float, eps: float, t: np.ndarray, eib):
    """``E0``, ``E1`` of the module docstring for eps > 0, any complex lambda."""
    b = 1j * omega_0 - lam
    p = math.sqrt(eps) * complex(math.sqrt(0.5), -math.sqrt(0.5))   # sqrt(eps) e^{-i pi/4}
    ip = 1j * p
    s0 = b / (2j * eps)
    z0 = ip * s0
    z1 = ip * (t + s0)
    elt = np.exp(lam * t)
    expo = lam * t - z0 * z0                      # Re = -h (t - t_res): bounded where used
    ind = (z0.imag < 0) & (z1.imag >= 0)
    corr = np.where(ind, 2.0 * np.exp(np.where(ind, expo, 0.0)), 0.0)
    E0 = (_SQRT_PI / (2.0 * p)) * (-eib * _wtilde(z1) + elt * _wtilde(z0) + corr)
    E1 = (eib - elt - b * E0) / (2j * eps)
    return E0, E1


def _E0_fresnel(nu: float, omega_0: float, eps: float, t: np.ndarray):
    """``E0 = e^{i nu t} J(t; omega_0 - nu)`` for lambda = i nu (n = 0), eps > 0 (digest 4.2)."""
    kappa = omega_0 - nu
    s0 = kappa / (2.0 * eps)
    k = math.sqrt(2.0 * eps / math.pi)
    S1, C1 = fresnel(k * (t + s0))
    S0, C0 = fresnel(k * s0)
    dF = (C1 - C0) + 1j * (S1 - S0)
    # e^{i nu t} e^{-i eps s0^2}; the phase is reduced before the exponential
    ph = np.mod(nu * t - eps * s0 * s0, 2.0 * math.pi)
    return np.exp(1j * ph) * math.sqrt(math.pi / (2.0 * eps)) * dF


def _modes(h: float, Omega: float):
    disc = np.sqrt(complex(h * h - Omega * Omega))
    if abs(disc) < 1e-9 * Omega:
        raise ValueError(f"n gives critical damping (h = n psi/2 = {h!r} 1/s = Omega): "
                         "the closed form needs distinct modes; perturb n [1/s]")
    return -h + disc, -h - disc


def _raw_W(Omega, h, q, omega_0, eps, t, kernel):
    """W(t), W'(t) [m, m/s] for eps >= 0 (any sign of omega_0)."""
    lam_p, lam_m = _modes(h, Omega)
    den = Omega * Omega - omega_0 * omega_0 + 2j * h * omega_0
    if den == 0:
        raise ValueError(f"omega_0 = {omega_0!r} [rad/s] equals the critical speed with n = 0: "
                         "the initial stationary orbit (7) is unbounded")
    Z0 = q * omega_0 * omega_0 / den
    W0 = Z0 + q
    Wd0 = 1j * omega_0 * W0
    up0 = (Wd0 - lam_m * W0) / (lam_p - lam_m)
    um0 = W0 - up0
    beta = omega_0 * t + eps * t * t
    eib = np.exp(1j * np.mod(beta, 2.0 * math.pi))
    W = np.zeros(t.shape, complex)
    Wd = np.zeros(t.shape, complex)
    for lam, u0, sgn in ((lam_p, up0, 1.0), (lam_m, um0, -1.0)):
        if eps == 0.0:
            b = 1j * omega_0 - lam
            E0 = (eib - np.exp(lam * t)) / b
            E1 = 0.0
        elif kernel == "fresnel":
            E0 = _E0_fresnel(lam.imag, omega_0, eps, t)
            E1 = 0.0
        else:
            E0, E1 = _E0_E1_faddeeva(lam, omega_0, eps, t, eib)
        u = np.exp(lam * t) * u0 + sgn * q / (lam_p - lam_m) * (
            (Omega * Omega + 2j * h * omega_0) * E0 + 4j * h * eps * E1)
        W += u
        Wd += lam * u
    return W, Wd, beta, eib


def runup_closed_form_state(params: LiquidFloatParams, t, *, kernel: str = "auto"):
    """Exact ``Z(t)`` [m] and ``Z'(t)`` [m/s] of model M1 under the speed law (6).

    Parameters
    ----------
    params : LiquidFloatParams
    t : array_like
        Times >= 0 [s], any shape.
    kernel : {"auto", "fresnel", "faddeeva"}
        ``"auto"``: Fresnel integrals for ``n = 0``, Faddeeva otherwise.
        ``"faddeeva"`` also works for ``n = 0`` (used as a cross-check);
        ``"fresnel"`` requires ``n = 0``.

    Returns
    -------
    Z, Zdot : ndarray (complex)
        Fixed-frame deflection ``xi + i eta`` [m] and its velocity [m/s].
    """
    if kernel not in ("auto", "fresnel", "faddeeva"):
        raise ValueError(f"kernel = {kernel!r}: must be 'auto', 'fresnel' or 'faddeeva'")
    if kernel == "fresnel" and params.n != 0.0:
        raise ValueError(f"kernel = 'fresnel' needs n = 0 [1/s], got n = {params.n!r} 1/s")
    if kernel == "auto":
        kernel = "fresnel" if params.n == 0.0 else "faddeeva"
    t = np.asarray(t, dtype=float)
    if not np.all(np.isfinite(t)) or np.any(t < 0):
        raise ValueError("t [s]: the closed form needs finite times >= 0")
    Omega, h, q = params.Omega, params.h, params.q
    if params.epsilon >= 0.0:
        W, Wd, beta, eib = _raw_W(Omega, h, q, params.omega_0, params.epsilon, t, kernel)
        omega = params.omega_0 + 2.0 * params.epsilon * t
    else:   # run-down: conjugate problem with beta -> -beta
        W, Wd, beta, eib = _raw_W(Omega, h, q, -params.omega_0, -params.epsilon, t, kernel)
        W, Wd, eib = np.conj(W), np.conj(Wd), np.conj(eib)
        omega = params.omega_0 + 2.0 * params.epsilon * t
    Z = W - q * eib
    Zd = Wd - 1j * q * omega * eib
    return Z, Zd


def runup_closed_form(params: LiquidFloatParams, t, *, kernel: str = "auto") -> np.ndarray:
    """Exact complex deflection ``Z(t) = xi + i eta`` [m] of M1 during the run-up (6).

    Vectorised over ``t`` [s] (>= 0, any shape); see
    :func:`runup_closed_form_state` for the velocity and the kernels.  The
    rotating-frame deflection is ``Z e^{-i beta}``, ``delta = |Z|`` and
    ``d = |Z e^{-i beta}/(psi e) + 1|`` (11).
    """
    return runup_closed_form_state(params, t, kernel=kernel)[0]


# ---------------------------------------------------------------------------
# peaks, asymptotics, free whirl
# ---------------------------------------------------------------------------

_FSTAR_CACHE: tuple | None = None


def fresnel_overshoot() -> tuple[float, float]:
    """Cornu-spiral overshoot ``(F*, u*)``: ``F* = max_u |int_{-inf}^u e^{i pi s^2/2} ds|``
    = 1.655562 at ``u* = 1.2172`` (digest 4.3), computed here."""
    global _FSTAR_CACHE
    if _FSTAR_CACHE is None:
        def neg(u):
            S, C = fresnel(u)
            return -abs(complex(C + 0.5, S + 0.5))
        r = minimize_scalar(neg, bounds=(0.8, 1.6), method="bounded",
                            options={"xatol": 1e-12})
        _FSTAR_CACHE = (-float(r.fun), float(r.x))
    return _FSTAR_CACHE


def undamped_asymptotics(params: LiquidFloatParams) -> dict:
    """Stationary-phase run-up asymptotics for ``n = 0`` (digest 4.3, oracle O5).

    Returns
    -------
    dict
        ``d_star`` = ``(Omega/2) sqrt(pi/(2 eps)) F*`` [-];
        ``delta_star_over_e`` = ``psi d_star + psi`` [-];
        ``residual_W_over_qe`` = ``|W_inf|/(psi e) = Omega sqrt(pi/(4 eps))`` [-];
        ``residual_delta_over_e`` = ``psi * residual_W_over_qe`` [-];
        ``dz`` = peak lag ``u* sqrt(2 pi eps)/Omega_0`` [-] after ``z = sqrt(psi)``.
    """
    if params.epsilon <= 0:
        raise ValueError(f"epsilon = {params.epsilon!r} [rad/s^2]: the run-up asymptotics need epsilon > 0")
    F, u = fresnel_overshoot()
    Om, eps = params.Omega, params.epsilon
    d_star = 0.5 * Om * math.sqrt(math.pi / (2 * eps)) * F
    res = Om * math.sqrt(math.pi / (4 * eps))
    return dict(d_star=d_star, delta_star_over_e=params.psi * d_star + params.psi,
                residual_W_over_qe=res, residual_delta_over_e=params.psi * res,
                dz=u * math.sqrt(2 * math.pi * eps) / params.Omega_0)


@dataclass
class RunupExtrema:
    """Maxima of a run-up (digest 1.7): ``delta_star_over_e`` = delta*/e [-] at
    ``z_delta`` (= omega/Omega_0 [-], time ``t_delta`` [s]); ``d_star`` [-] at
    ``z_d`` (``t_d``); ``delta_end_over_e`` and ``d_end`` at the end of the range."""

    delta_star_over_e: float
    z_delta: float
    t_delta: float
    d_star: float
    z_d: float
    t_d: float
    delta_end_over_e: float
    d_end: float


def runup_extrema(params: LiquidFloatParams, z_end: float = 2.0, *,
                  points_per_period: float = 3.0, n_refine: int = 8) -> RunupExtrema:
    """delta*/e and d* over ``z`` in ``[omega_0/Omega_0, z_end]`` from the closed form.

    A grid with ``points_per_period`` samples per period of the fastest
    envelope component ``2 pi/(Omega + omega_max)`` is searched, then the
    ``n_refine`` best grid maxima are polished with a bounded scalar search.
    The paper run (z to 2) takes about 0.15 s.

    Parameters
    ----------
    params : LiquidFloatParams (epsilon > 0)
    z_end : float
        Final speed ratio [-].
    """
    if params.epsilon <= 0:
        raise ValueError(f"epsilon = {params.epsilon!r} [rad/s^2]: runup_extrema needs a run-up (> 0)")
    t_end = params.time_at_z(z_end)
    wmax = params.Omega_0 * z_end
    dt = 2 * math.pi / (params.Omega + wmax) / points_per_period
    n = int(math.ceil(t_end / dt)) + 1
    q, e = params.q, params.e

    def outs(t):
        t = np.asarray(t, float)
        Z = runup_closed_form(params, t)
        beta = params.omega_0 * t + params.epsilon * t * t
        return np.abs(Z) / e, np.abs(Z * np.exp(-1j * beta) / q + 1.0)

    best = {"delta": (-1.0, 0.0), "d": (-1.0, 0.0)}
    chunk = 400_000
    grids = []
    for i0 in range(0, n, chunk):
        t = np.linspace(0.0, t_end, n)[i0:i0 + chunk]
        de, d = outs(t)
        grids.append((t, de, d))
    t_all = np.concatenate([g[0] for g in grids])
    for key, col in (("delta", 1), ("d", 2)):
        v = np.concatenate([g[col] for g in grids])
        kk = min(max(1, n_refine), v.size)
        cand = np.argpartition(v, v.size - kk)[v.size - kk:]
        for k in cand:
            a, b = t_all[max(k - 1, 0)], t_all[min(k + 1, n - 1)]
            f = (lambda s, c=col: -outs(s)[c - 1].item())
            r = minimize_scalar(f, bounds=(a, b), method="bounded", options={"xatol": 1e-9})
            val, ts = (-r.fun, r.x) if -r.fun >= v[k] else (v[k], t_all[k])
            if val > best[key][0]:
                best[key] = (float(val), float(ts))
    de_end, d_end = outs(np.array([t_end]))
    w = lambda s: (params.omega_0 + 2 * params.epsilon * s) / params.Omega_0
    return RunupExtrema(best["delta"][0], w(best["delta"][1]), best["delta"][1],
                        best["d"][0], w(best["d"][1]), best["d"][1],
                        float(de_end[0]), float(d_end[0]))


def free_whirl_amplitudes(params: LiquidFloatParams, t, Z, Zdot):
    """Free-whirl (modal) amplitudes ``|c_+|, |c_-|`` [m] of a state for ``n = 0``.

    The exact solution is ``W = c_+ e^{i Omega t} + c_- e^{-i Omega t} + W_p(t)``
    where the forced part ``W_p`` is written with the Fresnel *tails*
    ``int_t^inf`` (it is the steady chirp response, vanishing relative to the
    free whirl after the passage).  Hence ``c_(+/-)`` are **constants** of the
    exact motion for any t: computed from a numerical state ``(Z, Z')`` they
    expose numerical damping directly (oracle O9, digest 1.6).  After the
    passage ``|c_+| -> psi e Omega sqrt(pi/(4 eps))`` (digest 4.3).

    Parameters
    ----------
    params : LiquidFloatParams with n = 0, epsilon > 0
    t : array_like
        Times [s].
    Z, Zdot : array_like (complex)
        Fixed-frame deflection [m] and velocity [m/s] at ``t``.

    Returns
    -------
    c_plus, c_minus : ndarray (float) [m]
    """
    if params.n != 0.0:
        raise ValueError(f"n = {params.n!r} [1/s]: free_whirl_amplitudes is defined for n = 0")
    if params.epsilon <= 0:
        raise ValueError(f"epsilon = {params.epsilon!r} [rad/s^2]: needs epsilon > 0")
    t = np.asarray(t, float)
    Om, q, eps, w0 = params.Omega, params.q, params.epsilon, params.omega_0
    beta = w0 * t + eps * t * t
    omega = w0 + 2 * eps * t
    eib = np.exp(1j * np.mod(beta, 2 * math.pi))
    W = np.asarray(Z) + q * eib
    Wd = np.asarray(Zdot) + 1j * q * omega * eib
    up = (Wd + 1j * Om * W) / (2j * Om)
    um = W - up
    k = math.sqrt(2 * eps / math.pi)
    out = []
    for nu, u, sgn in ((Om, up, 1.0), (-Om, um, -1.0)):
        s0 = (w0 - nu) / (2 * eps)
        S1, C1 = fresnel(k * (t + s0))
        tail = (0.5 - C1) + 1j * (0.5 - S1)        # F(inf) - F(x1)
        ph = np.mod(-eps * s0 * s0, 2 * math.pi)
        tailJ = np.exp(1j * ph) * math.sqrt(math.pi / (2 * eps)) * tail
        # u = e^{i nu t} [c - sgn q Om/(2i) tail]   (u = e^{i nu t}[u0 + sgn (q Om/2i) J])
        c = u * np.exp(-1j * np.mod(nu * t, 2 * math.pi)) + sgn * q * Om / 2j * tailJ
        out.append(np.abs(c))
    return out[0], out[1]
