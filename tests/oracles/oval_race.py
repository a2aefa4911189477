"""An independent reference for balls on an out-of-round race (``race_out_of_roundness``).

Written from the Lagrangian, not from the stand's simulator: no import of ``stand``, its
own coordinates (the balls' absolute angles psi_j, not the stand's angles on the rotor),
its own mass matrix solved as it stands (Gaussian elimination with partial pivoting,
plain floats) at every call, scipy's ``solve_ivp`` (DOP853) segment by segment between
the programme's nodes.

Model (SI, fixed axes X, Y, vertical shaft: no gravity in the plane)
---------------------------------------------------------------------
Shaft point K = (x, y) on isotropic linear supports (stiffness c [N/m], damping d [N s/m]);
the rotor (mass M, every rotating part but the balls) has its centre of mass at
K + e E(phi + beta), E(v) = (cos v, sin v), T(v) = (-sin v, cos v); phi(t) the prescribed
rotor angle (a piecewise-linear speed programme, phi(0) = 0).  The race's radius in the
rotor frame is rho(a) = l [1 + eps cos k (a - theta)], a = psi - phi; ball j (a point,
mass m_j) sits at

    r_j(x, y, psi_j, t) = K + rho(psi_j - phi(t)) E(psi_j).

Its partial derivatives: dr/dx = (1, 0), dr/dy = (0, 1), u_j = dr/dpsi_j = rho' E + rho T,
dr/dt = -rho' phi' E.  Differentiating r_j' = K' + u_j psi_j' - rho' phi' E once more
(rho' changes at rho'' a', E at psi' T, T at -psi' E):

    r_j'' = K'' + u_j psi_j'' + h_j,
    h_j = (rho'' a'^2 - rho psi'^2 - rho' phi'') E + 2 rho' a' psi' T.

Lagrange's equations of T = M |r_C'|^2 / 2 + sum m_j |r_j'|^2 / 2 with the support forces
and the balls' drag c_b [N s/m] on their speed along the race (the velocity relative to
the race u_j a_j': generalised force -c_b |u_j|^2 a_j') give A(q) q'' = f, q = (x, y,
psi_1..psi_n)::

    M_S K'' + sum m_j u_j psi_j'' = -c K - d K' - M e (phi'' T_b - phi'^2 E_b) - sum m_j h_j
    m_j u_j . K'' + m_j |u_j|^2 psi_j'' = -m_j u_j . h_j - c_b |u_j|^2 a_j'

(M_S = M + sum m_j; E_b, T_b at phi + beta).  Contact (two balls of radius r): the centres
P_j = rho_j E_j (from K) at d = |P_0 - P_1| < 2 r push apart with F = k (2 r - d) - c d'
(when > 0), d' = (P_0 - P_1) . (P_0' - P_1') / d: the generalised forces F dd/dpsi_j,
dd/dpsi_0 = (P_0 - P_1) . u_0 / d, dd/dpsi_1 = -(P_0 - P_1) . u_1 / d (internal: no force
on K).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

from oracles._dense import solve

__all__ = ["OvalStand", "simulate"]

DEG = math.pi / 180.0


@dataclass(frozen=True)
class OvalStand:
    """The stand, SI (angles in degrees as in a scene file; speeds of the programme rev/s)."""

    mass: float = 4.45                 # kg, M
    eccentricity: float = 8.0899e-4    # m, e
    unbalance_angle: float = 0.0       # deg, beta
    stiffness: float = 1613.09         # N/m
    damping: float = 8.5577            # N s/m
    ball_mass: tuple = (0.045, 0.045)  # kg
    radius: float = 0.08               # m, l
    drag: float = 0.16965              # N s/m, c_b
    initial_angles: tuple = (150.0, 210.0)   # deg from the mark
    eps: float = 0.02                  # relative out-of-roundness
    lobes: int = 2                     # k
    theta: float = 20.0                # deg
    ball_radius: float = 0.0           # m, r (0: no contact; two balls)
    contact_stiffness: float = 0.0     # N/m
    contact_damping: float = 0.0       # N s/m


def _programme(nodes, t):
    """phi [rad], phi' [rad/s], phi'' [rad/s^2] of a piecewise-linear speed programme
    [[t s, rev/s], ...] (held after the last node) at time t."""
    ts = [p[0] for p in nodes]
    ws = [2.0 * math.pi * p[1] for p in nodes]
    phi = 0.0
    for i in range(len(ts) - 1):
        t0, t1, w0, w1 = ts[i], ts[i + 1], ws[i], ws[i + 1]
        slope = (w1 - w0) / (t1 - t0)
        if t <= t1:
            dt = t - t0
            return phi + w0 * dt + 0.5 * slope * dt * dt, w0 + slope * dt, slope
        phi += 0.5 * (w0 + w1) * (t1 - t0)
    return phi + ws[-1] * (t - ts[-1]), ws[-1], 0.0


def _rhs(t, s, p: OvalStand, nodes):
    n = len(p.ball_mass)
    m = [float(v) for v in p.ball_mass]
    s = s.tolist()
    x, y, psi = s[0], s[1], s[2:2 + n]
    vx, vy, dpsi = s[2 + n], s[3 + n], s[4 + n:]
    phi, W, dW = _programme(nodes, t)
    l, eps, k = p.radius, p.eps, p.lobes
    E, T, u, h, rho, rho1, da, uu = [], [], [], [], [], [], [], []
    for j in range(n):
        a, d = psi[j] - phi, dpsi[j] - W
        arg = k * (a - p.theta * DEG)
        ca, sa = math.cos(arg), math.sin(arg)
        r0, r1, r2 = l * (1.0 + eps * ca), -l * eps * k * sa, -l * eps * k * k * ca
        c, s_ = math.cos(psi[j]), math.sin(psi[j])
        e, tt = (c, s_), (-s_, c)
        uj = (r1 * e[0] + r0 * tt[0], r1 * e[1] + r0 * tt[1])
        g = r2 * d * d - r0 * dpsi[j] * dpsi[j] - r1 * dW
        q = 2.0 * r1 * d * dpsi[j]
        E.append(e), T.append(tt), u.append(uj), rho.append(r0), rho1.append(r1), da.append(d)
        h.append((g * e[0] + q * tt[0], g * e[1] + q * tt[1]))
        uu.append(uj[0] * uj[0] + uj[1] * uj[1])
    b = phi + p.unbalance_angle * DEG
    cb, sb = math.cos(b), math.sin(b)
    Ms = p.mass + sum(m)
    A = [[0.0] * (2 + n) for _ in range(2 + n)]
    A[0][0] = A[1][1] = Ms
    for j in range(n):
        A[0][2 + j] = A[2 + j][0] = m[j] * u[j][0]
        A[1][2 + j] = A[2 + j][1] = m[j] * u[j][1]
        A[2 + j][2 + j] = m[j] * uu[j]
    me = p.mass * p.eccentricity
    f = [-p.stiffness * x - p.damping * vx - me * (dW * -sb - W * W * cb)
         - sum(m[j] * h[j][0] for j in range(n)),
         -p.stiffness * y - p.damping * vy - me * (dW * cb - W * W * sb)
         - sum(m[j] * h[j][1] for j in range(n))]
    f += [-m[j] * (u[j][0] * h[j][0] + u[j][1] * h[j][1]) - p.drag * uu[j] * da[j]
          for j in range(n)]
    if p.ball_radius > 0.0:     # contact: the centres' distance from their positions
        P = [(rho[j] * E[j][0], rho[j] * E[j][1]) for j in range(2)]          # from K
        V = [(rho1[j] * da[j] * E[j][0] + rho[j] * dpsi[j] * T[j][0],
              rho1[j] * da[j] * E[j][1] + rho[j] * dpsi[j] * T[j][1]) for j in range(2)]
        dP = (P[0][0] - P[1][0], P[0][1] - P[1][1])
        d = math.hypot(*dP)
        if 0.0 < d < 2.0 * p.ball_radius:
            g0 = (dP[0] * u[0][0] + dP[1] * u[0][1]) / d        # dd/dpsi_0
            g1 = -(dP[0] * u[1][0] + dP[1] * u[1][1]) / d       # dd/dpsi_1
            F = p.contact_stiffness * (2.0 * p.ball_radius - d) \
                - p.contact_damping * (dP[0] * (V[0][0] - V[1][0])
                                       + dP[1] * (V[0][1] - V[1][1])) / d
            if F > 0.0:
                f[2] += F * g0
                f[3] += F * g1
    return np.array([vx, vy, *dpsi, *solve(A, f)])


def simulate(p: OvalStand, nodes, duration: float, fs: float, rtol: float = 1e-11,
             atol_scale: float = 1e-3):
    """Integrate from rest (K at the origin, balls at their initial angles, at rest on the
    rotor) over ``duration`` [s] at ``rtol`` (atol ``rtol * atol_scale`` in m, rad, m/s,
    rad/s); samples at ``fs`` [Hz] from t = 0.  Returns (t, x, y, alpha)
    with alpha (n, samples) the balls' angles on the rotor [rad]."""
    n = len(p.ball_mass)
    t_out = np.arange(int(round(duration * fs)) + 1) / fs
    _, W0, _ = _programme(nodes, 0.0)
    s = np.concatenate([[0.0, 0.0], np.asarray(p.initial_angles, float) * DEG,
                        [0.0, 0.0], np.full(n, W0)])
    edges = sorted({0.0, duration, *[float(q[0]) for q in nodes if 0.0 < q[0] < duration]})
    out = np.empty((t_out.size, s.size))
    for t0, t1 in zip(edges[:-1], edges[1:]):     # no step across a kink of phi'
        sol = solve_ivp(_rhs, (t0, t1), s, method="DOP853", rtol=rtol, atol=rtol * atol_scale,
                        dense_output=True, args=(p, nodes))
        if not sol.success:
            raise RuntimeError(sol.message)
        sel = (t_out >= t0) & (t_out <= t1)
        out[sel] = sol.sol(t_out[sel]).T
        s = sol.y[:, -1]
    phi = np.array([_programme(nodes, t)[0] for t in t_out])
    return t_out, out[:, 0], out[:, 1], out[:, 2:2 + n].T - phi
