"""Gravity-insensitive coupled pair (book 7.1): quasi-periodic motions, (7.38)-(7.46).

Theory of the model :mod:`stand.model.balancers.gravity_pair` (digest section 1.6).  Above
resonance the CWs can whirl at their own speed ``Omega`` below the shaft's
(the QP family): ``Omega`` is the root in (0, 1) of the precession-frequency
equation ``P(Omega) = R_mH Omega^5 - (R_omega - Omega) D(Omega) = 0`` (second
of (7.39) at ``phi = pi/2``), the family ends at (7.41), the shaft orbit is
(7.38).  Corrected prints: amplitudes (E3), family limit (E4), small-``H``
frequency (E5); the printed forms are kept as ``*_printed`` for comparison.
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
from scipy.optimize import minimize_scalar

if TYPE_CHECKING:
    from stand.model.balancers.gravity_pair_params import GravityPairParams

__all__ = [
    "D", "qp_polynomial", "qp_roots", "qp_frequency", "qp_frequency_approx",
    "qp_frequency_approx_printed", "qp_family_limit", "qp_family_limit_exact",
    "qp_amplitudes", "qp_amplitudes_printed", "qp_radius_range", "qp_orbit",
    "qp_initial_state", "orbit_radius_range",
]


# ---------------------------------------------------------------------------
# quasi-periodic motions (1.6): (7.38)-(7.46), errata E3, E4, E5
# ---------------------------------------------------------------------------

def D(w, H: float):
    """``D(w) = (w^2 - 1)^2 + H^2 w^2`` [-] (squared modulus of ``1 + i H w - w^2``)."""
    w = np.asarray(w, dtype=float)
    return (w * w - 1.0) ** 2 + H * H * w * w


def qp_polynomial(Omega, p: GravityPairParams):
    """``P(Omega) = R_mH Omega^5 - (R_omega - Omega) D(Omega)`` [-], the precession-frequency
    equation (second of (7.39) at ``phi = pi/2``; the same as (6.132))."""
    Omega = np.asarray(Omega, dtype=float)
    return p.R_mH * Omega ** 5 - (p.R_omega - Omega) * D(Omega, p.H)


def qp_roots(p: GravityPairParams) -> np.ndarray:
    """All positive real roots of ``P(Omega)`` [-], ascending (polynomial of degree 5)."""
    if p.h2 == 0.0:
        raise ValueError("h2 must be > 0 [dimensionless] for the QP theory (R_mH = R_m H/(h2 R_rho^2)), got 0.0")
    H2, R = p.H * p.H, p.R_omega
    # (Omega - R)(Omega^4 + (H^2 - 2) Omega^2 + 1) + R_mH Omega^5
    d = np.array([1.0, 0.0, H2 - 2.0, 0.0, 1.0])
    poly = np.polymul([1.0, -R], d)
    poly[0] += p.R_mH
    r = np.roots(poly)
    r = r[(np.abs(r.imag) < 1e-9 * np.maximum(1.0, np.abs(r))) & (r.real > 0)].real
    return np.sort(r)


def qp_frequency(p: GravityPairParams) -> float:
    """Absolute CW speed ``Omega`` [-] of the stable QP family (7.40): the root of
    ``P`` in (0, 1); NaN if none (``R_omega`` outside the existence range)."""
    r = qp_roots(p)
    r = r[r < 1.0]
    return float(r.max()) if r.size else math.nan


def qp_frequency_approx(p: GravityPairParams) -> float:
    """Small-``H`` asymptotics of the QP frequency [-], corrected (E5):
    ``Omega ~ 1 - sqrt(R_mH/(R_omega - 1) - H^2) / 2`` (NaN outside the range)."""
    if p.R_omega <= 1.0:
        return math.nan
    a = p.R_mH / (p.R_omega - 1.0) - p.H ** 2
    return 1.0 - 0.5 * math.sqrt(a) if a >= 0 else math.nan


def qp_frequency_approx_printed(p: GravityPairParams) -> float:
    """The printed (7.42) ``1 - sqrt(R_m H / (h2 (R_omega - 1)))`` [-] (E5: wrong; for comparison)."""
    return 1.0 - math.sqrt(p.R_m * p.H / (p.h2 * (p.R_omega - 1.0)))


def qp_family_limit(p: GravityPairParams) -> float:
    """Upper speed of the stable QP family, (7.41) corrected (E4) [-]:
    ``R*_omega = 1 + R_m/(h2 H R_rho^2) = 1 + R_mH / H^2``.

    (The print has ``R_rho`` instead of ``R_rho^2``; Ch. 5/6 print a factor 2
    that the root scan of this system contradicts -- digest E4.)"""
    if p.H == 0.0 or p.h2 == 0.0:
        return math.inf
    return 1.0 + p.R_mH / p.H ** 2


def qp_family_limit_exact(p: GravityPairParams) -> tuple[float, float]:
    """Exact speed where the two roots of ``P`` near 1 merge, and the merged ``Omega`` [-].

    ``P`` is linear in ``R_omega``: ``R_omega(Omega) = Omega + R_mH Omega^5 / D(Omega)``; the
    family ends at the local maximum of this curve near ``Omega = 1``.
    """
    if p.H == 0.0:
        return math.inf, 1.0
    f = lambda w: -(w + p.R_mH * w ** 5 / D(w, p.H))
    lo = max(0.3, 1.0 - 4.0 * p.H)
    res = minimize_scalar(f, bounds=(lo, 1.0 + 2.0 * p.H), method="bounded",
                          options={"xatol": 1e-12})
    return float(-res.fun), float(res.x)


def qp_amplitudes(p: GravityPairParams, Omega: float | None = None,
                  phi: float = math.pi / 2) -> tuple[float, float]:
    """Precession and nutation amplitudes (7.43)-(7.46), corrected (E3) [-].

    ``A_P = R_m Omega^2 |sin phi| / sqrt(D(Omega))``,
    ``A_N = R_m R_omega^2 e0 / sqrt(D(R_omega))``.
    ``Omega`` defaults to :func:`qp_frequency`.
    """
    if Omega is None:
        Omega = qp_frequency(p)
    Ap = p.R_m * Omega ** 2 * abs(math.sin(phi)) / math.sqrt(float(D(Omega, p.H)))
    An = p.R_m * p.R_omega ** 2 * p.e0 / math.sqrt(float(D(p.R_omega, p.H)))
    return Ap, An


def qp_amplitudes_printed(p: GravityPairParams, Omega: float | None = None) -> tuple[float, float]:
    """The printed (7.38) amplitudes, without ``Omega^2`` and ``R_omega^2`` (E3; wrong)."""
    if Omega is None:
        Omega = qp_frequency(p)
    return (p.R_m / math.sqrt(float(D(Omega, p.H))),
            p.R_m * p.e0 / math.sqrt(float(D(p.R_omega, p.H))))


def qp_radius_range(p: GravityPairParams, Omega: float | None = None) -> tuple[float, float]:
    """Predicted range ``[A_P - A_N, A_P + A_N]`` of the orbit radius ``|z|`` [-] (E3)."""
    Ap, An = qp_amplitudes(p, Omega)
    return abs(Ap - An), Ap + An


def qp_orbit(p: GravityPairParams, tau, Omega: float | None = None, gamma: float = 0.0,
             phi: float = math.pi / 2) -> np.ndarray:
    """Shaft law of the QP motion, (7.38) corrected (E3), complex ``z(tau)`` [-]::

        z = i R_m Omega^2 sin(phi) e^{i(Omega tau + gamma)} / (1 + i H Omega - Omega^2)
          + R_m R_omega^2 e0 e^{i(R_omega tau + p.gamma)} / (1 + i H R_omega - R_omega^2)
    """
    if Omega is None:
        Omega = qp_frequency(p)
    tau = np.asarray(tau, dtype=float)
    R = p.R_omega
    zp = 1j * p.R_m * Omega ** 2 * math.sin(phi) / complex(1.0 - Omega ** 2, p.H * Omega)
    zn = p.R_m * R * R * p.e0 / complex(1.0 - R * R, p.H * R)
    return zp * np.exp(1j * (Omega * tau + gamma)) + zn * np.exp(1j * (R * tau + p.gamma))


def qp_initial_state(p: GravityPairParams, Omega: float | None = None,
                     phi: float = math.pi / 2 - 0.02) -> np.ndarray:
    """A fixed-frame starting state on the (approximate) QP family (digest 5, E3)."""
    if Omega is None:
        Omega = qp_frequency(p)
    if not math.isfinite(Omega):
        raise ValueError(f"no QP family at R_omega = {p.R_omega!r} [dimensionless]")
    z0 = complex(qp_orbit(p, 0.0, Omega, 0.0, phi))
    R = p.R_omega
    zp = 1j * p.R_m * Omega ** 2 * math.sin(phi) / complex(1.0 - Omega ** 2, p.H * Omega)
    zn = p.R_m * R * R * p.e0 / complex(1.0 - R * R, p.H * R) * complex(math.cos(p.gamma), math.sin(p.gamma))
    dz0 = 1j * Omega * zp + 1j * R * zn
    return np.array([phi, 0.0, z0.real, z0.imag, 0.0, Omega, dz0.real, dz0.imag])


def orbit_radius_range(sol, t_from: float) -> tuple[float, float]:
    """Min and max of ``|z|`` [-] over the samples of a fixed-frame solution with ``t >= t_from``."""
    k = sol.t >= t_from
    r = np.hypot(sol.y[2, k], sol.y[3, k])
    return float(r.min()), float(r.max())
