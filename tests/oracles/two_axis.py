"""The book's own equations of the two-axis pendulum CW (monograph ch. 6): test oracle.

The model, its parameters and the derivation are described in
:mod:`stand.model.balancers.two_axis`; the package runs the pendulum on the one model
(the generic composition with its tilting body; its rotating frame -- at the rotor's
speed or at a QP motion's speed Omega -- :mod:`stand.theories.weights.one_model`).

* (6.12) rotating frame, state ``y = [phi, psi, xi, eta, phi', psi', xi', eta']``
  (' = d/dtau): :func:`rhs_rotating`, residual :func:`residual_rotating`.
  OCR fix (digest 2.3): the brackets of l3, l4 contain the second derivatives
  phi'', psi'' (the print shows first derivatives).
* (6.15) fixed frame, state ``y = [phi, alpha, x, y, phi', alpha', x', y']`` with
  alpha = psi + R_omega tau the CW azimuth: :func:`rhs_fixed`,
  :func:`residual_fixed`.  OCR fix: phi'' cos(alpha) in L4.
* Run-up / run-down (digest 2.6, not in the book): :func:`rhs_fixed_variable_speed`
  with a speed profile such as :func:`linear_ramp`.
* (6.15) in axes turning at a QP motion's speed Omega (6.19)-(6.22):
  :func:`rhs_omega_frame`.

The accelerations follow in closed form (Schur complement of the mass matrix
[[diag(1, R_rho^2), C], [R_m C^T, I]], pivots 1 - R_m cos^2 phi and
R_rho^2 - R_m sin^2 phi).
"""
from __future__ import annotations

import math
from typing import Callable, Tuple

import numpy as np

from stand.model.balancers._params import BOOK
from stand.model.balancers.two_axis_params import TwoAxisParams

__all__ = [
    "residual_rotating", "residual_fixed", "rhs_rotating", "rhs_fixed",
    "rhs_fixed_variable_speed", "linear_ramp", "rhs_omega_frame",
]


def residual_rotating(q, dq, ddq, p: TwoAxisParams):
    """Left-hand sides l1..l4 of (6.12) (rotating frame), OCR-corrected (digest 2.3).

    Parameters
    ----------
    q, dq, ddq : array_like, shape (4, ...)
        (phi, psi, xi, eta) and their first/second tau-derivatives [rad, -].
    p : TwoAxisParams

    Returns
    -------
    ndarray, shape (4, ...)
        l1, l2 (divided by A omega0^2), l3, l4 (times l/(M_Sigma rho1^2 omega0^2));
        zero on a solution.
    """
    ph, ps, xi, et = q
    dph, dps, dxi, det = dq
    aph, aps, axi, aet = ddq
    Rw, Rm = p.R_omega, p.R_m
    sf, cf, sp, cp = np.sin(ph), np.cos(ph), np.sin(ps), np.cos(ps)
    ax = axi - 2 * Rw * det - Rw ** 2 * xi
    ay = aet + 2 * Rw * dxi - Rw ** 2 * et
    W = dph ** 2 + dps ** 2 + 2 * Rw * dps
    l1 = aph + p.h1 * dph + p.R_g2 * sf - (ax * sp - ay * cp) * cf
    l2 = (aps + p.h2 * dps) * p.R_rho2 - (ax * cp + ay * sp) * sf
    l3 = (ax + p.H * (dxi - Rw * et) + xi
          - Rm * ((aph * sp + 2 * (Rw + dps) * dph * cp) * cf
                  + (aps * cp - W * sp) * sf + Rw ** 2 * (p.e0 - sf * sp)))
    l4 = (ay + p.H * (det + Rw * xi) + et
          - Rm * ((aps * sp + W * cp) * sf - (aph * cp - 2 * (Rw + dps) * dph * sp) * cf
                  + Rw ** 2 * sf * cp))
    return np.array([l1, l2, l3, l4])


def residual_fixed(tau, q, dq, ddq, p: TwoAxisParams):
    """Left-hand sides L1..L4 of (6.15) (fixed frame), OCR-corrected (digest 2.4).

    Parameters
    ----------
    tau : float
        Dimensionless time omega0 t [-].
    q, dq, ddq : array_like, shape (4, ...)
        (phi, alpha, x, y) and derivatives; alpha = psi + R_omega tau is the CW
        azimuth in fixed axes, (x, y) the fixed-axis deflection (units rho1^2/l).
    p : TwoAxisParams
    """
    ph, al, x, y = q
    dph, dal, dx, dy = dq
    aph, aal, axx, ayy = ddq
    Rw, Rm = p.R_omega, p.R_m
    sf, cf, sa, ca = np.sin(ph), np.cos(ph), np.sin(al), np.cos(al)
    W = dph ** 2 + dal ** 2
    L1 = aph + p.h1 * dph + p.R_g2 * sf + (ayy * ca - axx * sa) * cf
    L2 = (aal + p.h2 * (dal - Rw)) * p.R_rho2 - (axx * ca + ayy * sa) * sf
    L3 = axx + p.H * dx + x - Rm * ((aph * sa + 2 * dal * dph * ca) * cf
                                    + (aal * ca - W * sa) * sf
                                    + Rw ** 2 * p.e0 * np.cos(Rw * tau))
    L4 = ayy + p.H * dy + y - Rm * ((aal * sa + W * ca) * sf
                                    - (aph * ca - 2 * dal * dph * sa) * cf
                                    + Rw ** 2 * p.e0 * np.sin(Rw * tau))
    return np.array([L1, L2, L3, L4])


def _trig(y):
    """``(y, sin, cos)``: a 1-D state as Python floats with :mod:`math` (``solve_ivp`` calls
    the right-hand side once per stage; scalar numpy arithmetic costs ~3x the time), an
    (8, k) state as it is with numpy.  Same formulas, same values to round-off."""
    y = np.asarray(y, dtype=float)
    if y.ndim == 1:
        return y.tolist(), math.sin, math.cos
    return y, np.sin, np.cos


def _solve_acc(ph, ps, g1, g2, g3, g4, Rm, Rr2, sin=np.sin, cos=np.cos):
    """Solve [[diag(1,Rr2), C], [Rm C^T, I]] a = -g in closed form (C C^T diagonal)."""
    sf, cf, sp, cp = sin(ph), cos(ph), sin(ps), cos(ps)
    a_ph = (-g1 - cf * sp * g3 + cf * cp * g4) / (1.0 - Rm * cf * cf)
    a_ps = (-g2 - sf * cp * g3 - sf * sp * g4) / (Rr2 - Rm * sf * sf)
    a_x = -g3 + Rm * (cf * sp * a_ph + sf * cp * a_ps)
    a_y = -g4 - Rm * (cf * cp * a_ph - sf * sp * a_ps)
    return a_ph, a_ps, a_x, a_y


def rhs_rotating(tau, y, p: TwoAxisParams):
    """Right-hand side of (6.12) for ``scipy.integrate.solve_ivp``.

    Parameters
    ----------
    tau : float
        Dimensionless time [-] (unused: (6.12) is autonomous).
    y : array_like, shape (8,) or (8, k)
        ``[phi, psi, xi, eta, phi', psi', xi', eta']``: CW tilt about the transverse
        axis [rad] (0 = hanging), CW turn about the shaft relative to the rotor
        [rad], rotating-frame deflection (unbalance along +xi) [rho1^2/l] and
        tau-derivatives.
    p : TwoAxisParams

    Returns
    -------
    ndarray
        dy/dtau, same shape as ``y`` (works with ``vectorized=True``).
    """
    y, sin, cos = _trig(y)
    ph, ps, xi, et, dph, dps, dxi, det = y
    Rw, Rm = p.R_omega, p.R_m
    sf, cf, sp, cp = sin(ph), cos(ph), sin(ps), cos(ps)
    ax0 = -2 * Rw * det - Rw ** 2 * xi
    ay0 = 2 * Rw * dxi - Rw ** 2 * et
    W = dph ** 2 + dps ** 2 + 2 * Rw * dps
    g1 = p.h1 * dph + p.R_g2 * sf - (ax0 * sp - ay0 * cp) * cf
    g2 = p.h2 * dps * p.R_rho2 - (ax0 * cp + ay0 * sp) * sf
    g3 = ax0 + p.H * (dxi - Rw * et) + xi - Rm * (2 * (Rw + dps) * dph * cp * cf
                                                 - W * sp * sf + Rw ** 2 * (p.e0 - sf * sp))
    g4 = ay0 + p.H * (det + Rw * xi) + et - Rm * (W * cp * sf + 2 * (Rw + dps) * dph * sp * cf
                                                 + Rw ** 2 * sf * cp)
    a = _solve_acc(ph, ps, g1, g2, g3, g4, Rm, p.R_rho2, sin, cos)
    return np.array([dph, dps, dxi, det, *a])


def _rhs_fixed_core(y, p, h2_drive, fx, fy):
    y, sin, cos = _trig(y)
    ph, al, x, yy, dph, dal, dx, dy = y
    Rm = p.R_m
    sf, cf, sa, ca = sin(ph), cos(ph), sin(al), cos(al)
    W = dph ** 2 + dal ** 2
    g1 = p.h1 * dph + p.R_g2 * sf
    g2 = p.h2 * (dal - h2_drive) * p.R_rho2
    g3 = p.H * dx + x - Rm * (2 * dal * dph * ca * cf - W * sa * sf + fx)
    g4 = p.H * dy + yy - Rm * (W * ca * sf + 2 * dal * dph * sa * cf + fy)
    a = _solve_acc(ph, al, g1, g2, g3, g4, Rm, p.R_rho2, sin, cos)
    return np.array([dph, dal, dx, dy, *a])


def rhs_fixed(tau, y, p: TwoAxisParams):
    """Right-hand side of (6.15) (fixed frame) for ``solve_ivp``.

    Parameters
    ----------
    tau : float
        Dimensionless time omega0 t [-]; the unbalance points along +x at tau = 0.
    y : array_like, shape (8,) or (8, k)
        ``[phi, alpha, x, y, phi', alpha', x', y']``; alpha = psi + R_omega tau is the
        CW azimuth [rad], (x, y) fixed-screen deflection [rho1^2/l].
    p : TwoAxisParams
    """
    Rw = p.R_omega
    f = Rw ** 2 * p.e0
    if np.ndim(tau) == 0:
        c, s = math.cos(Rw * tau), math.sin(Rw * tau)
    else:
        c, s = np.cos(Rw * tau), np.sin(Rw * tau)
    return _rhs_fixed_core(y, p, Rw, f * c, f * s)


def linear_ramp(R_start, R_end, duration, tau0=0.0) -> Callable[[float], Tuple[float, float, float]]:
    """Speed profile for :func:`rhs_fixed_variable_speed`: R_omega ramps linearly
    from ``R_start`` to ``R_end`` over ``duration`` (tau units) from ``tau0``, then
    stays constant.  Returns ``f(tau) -> (theta, theta', theta'')`` with the exact
    rotor angle theta = integral of R_omega dtau (theta(0) = 0) [rad, -, -]."""
    R0, R1, T, t0 = BOOK.each(("R_start", R_start, "-", ">= 0"), ("R_end", R_end, "-", ">= 0"),
                              ("duration", duration, "tau", "> 0"), ("tau0", tau0, "tau", ">= 0"))
    k = (R1 - R0) / T

    def prof(tau):
        if tau <= t0:
            return R0 * tau, R0, 0.0
        s = min(tau - t0, T)
        th = R0 * t0 + R0 * s + 0.5 * k * s * s
        if tau - t0 <= T:
            return th, R0 + k * s, k
        return th + R1 * (tau - t0 - T), R1, 0.0
    return prof


def rhs_fixed_variable_speed(tau, y, p: TwoAxisParams,
                             profile: Callable[[float], Tuple[float, float, float]]):
    """(6.15) with a prescribed rotor speed (run-up / run-down; digest 2.6, not in the book).

    Changes with respect to (6.15): the CW drag is h2 (alpha' - theta'(tau)) and the
    unbalance forcing R_omega^2 e0 e^{i R_omega tau} becomes
    e0 (theta'^2 - i theta'') e^{i theta} (from -d^2/dtau^2 e^{i theta}).
    ``p.R_omega`` is ignored.

    Parameters
    ----------
    tau : float
    y : array_like, shape (8,)
        As in :func:`rhs_fixed`.
    p : TwoAxisParams
    profile : callable
        ``profile(tau) -> (theta, theta', theta'')`` rotor angle [rad] and its
        tau-derivatives, e.g. :func:`linear_ramp`.
    """
    th, dth, ddth = profile(tau)
    c, s = math.cos(th), math.sin(th)
    e0 = p.e0
    return _rhs_fixed_core(y, p, dth, e0 * (dth * dth * c + ddth * s),
                           e0 * (dth * dth * s - ddth * c))


def rhs_omega_frame(tau, y, p: TwoAxisParams, Omega):
    """(6.15) in axes turning at Omega (6.19)-(6.22): alpha = Omega tau + beta,
    z = q e^{i Omega tau}.  State ``[phi, beta, Re q, Im q, phi', beta', Re q', Im q']``.
    Autonomous when e0 = 0 (QP motions are then equilibria)."""
    ph, be, qr, qi, dph, dbe, dqr, dqi = y
    E = np.exp(1j * Omega * tau)
    q, dq = qr + 1j * qi, dqr + 1j * dqi
    z, dz = q * E, (dq + 1j * Omega * q) * E
    f = rhs_fixed(tau, np.array([ph, Omega * tau + be, z.real, z.imag, dph, Omega + dbe,
                                 dz.real, dz.imag]), p)
    ddq = (f[6] + 1j * f[7]) / E - 2j * Omega * dq + Omega ** 2 * q
    return np.array([dph, dbe, dqr, dqi, f[4], f[5], ddq.real, ddq.imag])
