"""The book's own equations of the autobalancer-damper (book 7.2): test oracle.

The model, its parameters and the direction-vector formulation are described in
:mod:`stand.model.balancers.damper`; the package runs the damper on the one model
(the generic composition with its spherical body weight).  Dimensionless, with
``tau = omega0 t``::

    n'  = W x n  +  k_c (1 - |n|^2) n / 2          (constraint stabilisation)
    W'  = -R_g^2 n x e_z  -  n x a  -  h (W - R_omega e_z)  [+ friction (7.79)-(7.84)]
    z'' + H z' + z = -R_m (n_x + i n_y)'' + R_m R_omega^2 e0 e^{i(R_omega tau + gamma)}

which reproduces the CW and rotor equations of (7.47) with erratum E1.  The
regularised dry friction (7.79)-(7.84) has no generic composition: it runs here only.
State vector (:func:`rhs`, fixed frame; :func:`rhs_rotating`, the same quantities in
rotating-frame components)::

    s = [x, y, x', y', n_x, n_y, n_z, W_x, W_y, W_z]
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from oracles.book_ode import frame_rhs, integrate

if TYPE_CHECKING:    # the parameters' container (a dataclass of numbers) names the type only:
    from stand.model.balancers.damper_params import DamperParams   # no package code runs here

__all__ = ["rhs", "rhs_rotating", "make_rhs", "simulate"]


def _cross(a0, a1, a2, b0, b1, b2):
    return a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0


def _accelerations(n, W, fx, fy, p: DamperParams, Rw, T=(0.0, 0.0, 0.0)):
    """Coupled CW / shaft accelerations (scalar arithmetic for speed).

    ``n`` unit direction, ``W`` absolute angular velocity, ``(fx, fy)`` the known
    shaft force, ``Rw`` the rotor rate about ``e_z``, ``T`` an extra moment.
    Returns ``(ax, ay, Wdot, ndd)`` with ``n'' = q - a + n (n . a)``,
    ``q = G x n + W x (W x n)``, ``W' = G - n x a``.
    """
    Rm, g2, h = p.R_m, p.R_g * p.R_g, p.h
    n0, n1, n2 = n
    W0, W1, W2 = W
    # G = -R_g^2 n x e_z - h (W - Rw e_z) + T ;  n x e_z = (n1, -n0, 0)
    G0 = -g2 * n1 - h * W0 + T[0]
    G1 = g2 * n0 - h * W1 + T[1]
    G2 = -h * (W2 - Rw) + T[2]
    c0, c1, c2 = _cross(W0, W1, W2, n0, n1, n2)
    cc0, cc1, cc2 = _cross(W0, W1, W2, c0, c1, c2)
    g0, g1, gz = _cross(G0, G1, G2, n0, n1, n2)
    q0, q1, q2 = g0 + cc0, g1 + cc1, gz + cc2
    b0, b1 = fx - Rm * q0, fy - Rm * q1
    den = (1.0 - Rm) + Rm * (n0 * n0 + n1 * n1)
    nb = n0 * b0 + n1 * b1
    ax = (b0 - Rm * n0 * nb / den) / (1.0 - Rm)
    ay = (b1 - Rm * n1 * nb / den) / (1.0 - Rm)
    # n x a with a = (ax, ay, 0)
    na0, na1, na2 = -n2 * ay, n2 * ax, n0 * ay - n1 * ax
    Wd = (G0 - na0, G1 - na1, G2 - na2)
    nda = n0 * ax + n1 * ay
    ndd = (q0 - ax + n0 * nda, q1 - ay + n1 * nda, q2 + n2 * nda)
    return ax, ay, Wd, ndd


def _cw_dynamics(n_raw, W, fx, fy, p: DamperParams, Rw):
    """Accelerations with the optional regularised friction, and ``n'``."""
    nn = math.sqrt(n_raw[0] ** 2 + n_raw[1] ** 2 + n_raw[2] ** 2)
    n = (n_raw[0] / nn, n_raw[1] / nn, n_raw[2] / nn)
    W = (float(W[0]), float(W[1]), float(W[2]))
    ax, ay, Wd, ndd = _accelerations(n, W, fx, fy, p, Rw)
    fr = p.friction
    if fr is not None and fr.R_f > 0.0:
        r0, r1, r2 = W[0], W[1], W[2] - Rw
        scale = fr.R_f / math.sqrt(r0 * r0 + r1 * r1 + r2 * r2 + fr.eps ** 2)
        g2 = p.R_g * p.R_g
        for _ in range(2):
            N = math.sqrt((ax + fr.kappa * ndd[0]) ** 2 + (ay + fr.kappa * ndd[1]) ** 2
                          + (fr.kappa * ndd[2] + g2) ** 2)
            k = -N * scale
            ax, ay, Wd, ndd = _accelerations(n, W, fx, fy, p, Rw, (k * r0, k * r1, k * r2))
    c = _cross(W[0], W[1], W[2], n[0], n[1], n[2])
    corr = 0.5 * p.k_c * (1.0 - nn * nn)
    nd = (c[0] + corr * n[0], c[1] + corr * n[1], c[2] + corr * n[2])
    return ax, ay, Wd, nd


def rhs(tau: float, s, p: DamperParams) -> np.ndarray:
    """Fixed-frame right-hand side of the ABD (direction-vector form of (7.47), E1).

    Parameters
    ----------
    tau : float
        Dimensionless time [-].
    s : array_like, shape (10,)
        ``[x, y, x', y', n_x, n_y, n_z, W_x, W_y, W_z]``: shaft position in units
        ``rho^2/l``, its rate, the CW direction (unit) vector, the absolute
        angular velocity of the CW in ``omega0`` units.
    p : DamperParams

    Returns
    -------
    numpy.ndarray, shape (10,)
    """
    s = np.asarray(s, dtype=float).tolist()     # Python floats: the same values, ~2x faster
    x, y, dx, dy = s[:4]
    Rw = p.R_omega
    ph = Rw * tau + p.gamma
    u = p.R_m * Rw * Rw * p.e0
    fx = -p.H * dx - x + u * math.cos(ph)
    fy = -p.H * dy - y + u * math.sin(ph)
    ax, ay, Wd, nd = _cw_dynamics(s[4:7], s[7:10], fx, fy, p, Rw)
    return np.array([dx, dy, ax, ay, nd[0], nd[1], nd[2], Wd[0], Wd[1], Wd[2]])


def rhs_rotating(tau: float, s, p: DamperParams) -> np.ndarray:
    """Rotating-frame right-hand side (autonomous; steady motions are equilibria).

    ``s = [xi, eta, xi', eta', n_1, n_2, n_3, W_1, W_2, W_3]``: the same
    quantities as in :func:`rhs` in rotating-frame components (``W`` still the
    *absolute* angular velocity; ``n' = (W - R_omega e_z) x n``).
    """
    s = np.asarray(s, dtype=float).tolist()
    xi, eta, dxi, deta = s[:4]
    Rw = p.R_omega
    zeta, dzeta = complex(xi, eta), complex(dxi, deta)
    # absolute velocity and the shaft force in rotating components
    v = dzeta + 1j * Rw * zeta
    f_h = -p.H * v - zeta + p.R_m * Rw * Rw * p.e0 * complex(math.cos(p.gamma), math.sin(p.gamma))
    ax, ay, Wd, nd = _cw_dynamics(s[4:7], s[7:10], f_h.real, f_h.imag, p, Rw)
    zdd = complex(ax, ay) - 2j * Rw * dzeta + Rw * Rw * zeta
    # d/dt of rotating components: v_rot' = (v')_rot - Rw e_z x v_rot, e_z x v = (-v1, v0, 0)
    n0, n1 = s[4], s[5]
    W0, W1 = s[7], s[8]
    return np.array([dxi, deta, zdd.real, zdd.imag,
                     nd[0] + Rw * n1, nd[1] - Rw * n0, nd[2],
                     Wd[0] + Rw * W1, Wd[1] - Rw * W0, Wd[2]])


def make_rhs(p: DamperParams, frame: str = "fixed"):
    """``f(tau, s)`` closure for ``solve_ivp`` (``frame`` = ``"fixed"`` or ``"rotating"``)."""
    return frame_rhs(p, frame, rhs, rhs_rotating)


def simulate(p: DamperParams, s0, t_end: float, *, frame: str = "fixed", t_eval=None,
             rtol: float = 1e-8, atol: float = 1e-10, method: str = "DOP853"):
    """Integrate from ``tau = 0`` to ``t_end`` [-] with ``solve_ivp``; raises on failure.

    ``s0`` is the state (shape (10,)) in ``frame``; returns the ``solve_ivp`` result.
    """
    return integrate(make_rhs(p, frame), s0, t_end, 10, name="s0", t_eval=t_eval, rtol=rtol,
                     atol=atol, method=method)
