"""The generic kernel's weight table (:mod:`stand.model.rotors.coupled_kernel`): its columns,
one row per point weight, and the moments between the balls of a race.

Ball-ball contact (``ball_radius`` r of a ball table; :func:`contact_moments`).  Balls
i, k of one race at chord distance d = |l_i e_i - l_k e_k|, d^2 = l_i^2 + l_k^2 -
2 l_i l_k cos(psi_i - psi_k), overlapping by delta = r_i + r_k - d > 0, push each other
along their line of centres with the linear spring-dashpot F = max(0, k delta - c d')
(k, c of ball i's table).  Its generalised force on psi_i is F dd/dpsi_i =
F l_i l_k sin(psi_i - psi_k) / d and the opposite on psi_k (the potential k delta^2 / 2 and
the dashpot on d'): internal, it pushes neither the shaft nor the rotor net, and it enters
the weights' rows as a moment beside their drag.  The balls keep their angular order on
a race, so only neighbours touch (each ball's next, from the initial angles): O(n).

Race eccentricity (``race_eccentricity`` e_r, ``race_eccentricity_angle`` theta of a ball
table; :func:`race_gravity`).  The race's centre sits at o = e_r (cos, sin)(phi + theta)
from the shaft (rotor frame), ball j at T_p q + o + l_j e_j.  Its acceleration gains
o'' = e_r (phi'' t_o - phi'^2 e_o) (t_o, e_o: the unit vectors along and across o), which
enters the ball's row and its push on the shaft exactly as a transverse gravity -o'' does
(the kernel's g_p): the ball's own g_j = g_p - o''.  With a speed programme only (phi''
known).  At steady state each ball's row reads n_j . (q_K + o) = 0 (the race turning about
the axis, K at q_K): two balls not in line hold the race's centre on the axis, so the shaft
whirls with the radius e_r itself, opposite the race's offset, whatever the masses.

Out-of-roundness (``race_out_of_roundness`` eps, ``race_lobes`` k, ``race_out_of_roundness_angle``
theta_o of a ball table; :func:`oval_push`, :func:`oval_accel`).  The race's radius in the
rotor frame is rho(a) = l [1 + eps cos k (a - theta_o)] (k = 2: ovality), a = psi - phi the
ball's angle on the rotor; rho' = -l eps k sin k(a - theta_o), rho'' = -l eps k^2 cos k(a - theta_o).
Ball j (a point mass m) sits at r = T_p q + rho(a) e, e = (cos, sin) psi, t = (-sin, cos) psi
= -n.  With phi prescribed (a speed programme) the ball has the one coordinate psi and

    T = m |T_p q' + rho' a' e + rho psi' t|^2 / 2,
    u = dr/dpsi = rho' e + rho t          (the coupling vector, [m]),
    G = m |u|^2 = m (rho^2 + rho'^2)       (the generalised mass, [kg m^2]),
    r'' = T_p q'' + u psi'' + c,   c = (rho'' a'^2 - rho' phi'' - rho psi'^2) e + 2 rho' a' psi' t

(c: the velocity-product and programme terms of r''; an eccentric race adds o to r and
enters through g_j as above).  Lagrange's equation for psi, d/dt dT/dpsi' - dT/dpsi =
m r'' . u (as dr'/dpsi' = u and d/dt u = dr'/dpsi), is Newton's projected on u,
m (r'' - g_j) . u = -M_r, that is

    G psi'' = m u . (gamma - T_p q'') - M_r,     gamma = g_j - c,

u . c = rho' rho'' a'^2 - rho'^2 phi'' + rho rho' (a'^2 - phi'^2): the (dG/da) a'^2 / 2 term of
the varying mass, the Euler term and the centrifugal pull m phi'^2 rho rho' along the race.
The ball's drag c_b acts on its speed along the race |u| a', so M_r = c_b |u|^2 a' =
H (rho^2 + rho'^2) / l^2 a' (H = c_b l^2, stand.scene.model.Balancer.moment_drag).  Its push on
the plane point, m g_j - m r'', with psi'' eliminated:

    m gamma - (m / G)(m u . gamma - M_r) u - [m I - (m^2 / G) u u^T] T_p q''

-- the plane force and the plane inertia C_p += m I - (m^2 / G) u u^T.  At eps = 0: u = -l n,
G = m l^2 = J, c = -l psi'^2 e, the kernel's own rows (which run then: no work without it).
In the rotor frame with the shaft held at constant phi' = Omega the ball moves in the
potential V = -m Omega^2 rho^2 / 2 with the mass G(a); it rests at the maxima of rho,
a = theta_o + 2 pi j / k, where V'' = m Omega^2 l^2 eps k^2 (1 + eps) and G = m l^2 (1 + eps)^2:
small oscillations at omega^2 = Omega^2 eps k^2 / (1 + eps) (tests/test_race_out_of_roundness.py).
Point balls with viscous drag on a speed programme: a rolling ball (its spin follows the
arc length), dry friction (its normal force), and a free rotor (phi'' coupled) are refused
(:func:`race_columns`).  Ball-ball contact runs on the chord of the out-of-round race
(:func:`oval_contact`): d^2 = rho_j^2 + rho_k^2 - 2 rho_j rho_k cos D, D = a_j - a_k,
dd/da_j = (rho_j rho_j' - rho_j' rho_k cos D + rho_j rho_k sin D) / d,
dd/da_k = (rho_k rho_k' - rho_j rho_k' cos D - rho_j rho_k sin D) / d,
d' = dd/da_j a_j' + dd/da_k a_k', the moments F dd/da_j, F dd/da_k
(no longer opposite: the push along the line of centres has a part across the race, which
the race takes; the pair's push on the shaft stays internal).  The plane's residual
unbalance counts each ball at its centre o + rho(a) e^{ia} (:func:`ball_offsets`).
"""
from __future__ import annotations

import math

import numpy as np

from stand._jit import njit

__all__ = ["N_WCOL", "ball_offsets", "contact_moments", "friction_moment", "oval_accel",
           "oval_push", "race_columns", "race_gravity", "race_shape"]

# weight table columns: plane, mass, radius, inertia, drag, friction (kinetic,
# static, slip speed, dwell, release), index of its adhesion state (-1: none), spin inertia
# J_s on the angle relative to the rotor (rolling balls, stand.model.weights; 0: none); contact:
# the ball's own radius, spring, dashpot and the index of its next neighbour in its race (-1: none)
W_PLANE, W_M, W_L, W_J, W_H, W_MUK, W_MUS, W_VS, W_TD, W_TR, W_Z, W_JS, W_R, W_KC, W_CC, W_NEXT, \
    W_ER, W_TH, W_EPS, W_K, W_PH = range(21)
# race eccentricity [m] and its angle [rad] in the rotor frame; out-of-roundness eps, lobes k,
# angle theta_o [rad]
N_WCOL = 21


@njit(cache=True, error_model="numpy", _nrt=False)
def contact_moments(wt, y, n, ns, wref, buf, om):
    """Minus the contact moments [N m] on the weights (module docstring) into ``buf[om:]``
    (the weights' resisting moments, added to their drag and friction there)."""
    nw = wt.shape[0]
    for j in range(nw):
        buf[om + j] = 0.0
    for j in range(nw):
        k = int(wt[j, W_NEXT])
        if k < 0:
            continue
        if wt[j, W_EPS] != 0.0 or wt[k, W_EPS] != 0.0:     # out-of-round race: rho in the chord
            oval_contact(wt, y, n, ns, wref, buf, om, j, k)
            continue
        lj, lk = wt[j, W_L], wt[k, W_L]
        da = y[n + j] - y[n + k]
        d = math.sqrt(lj * lj + lk * lk - 2.0 * lj * lk * math.cos(da))
        delta = wt[j, W_R] + wt[k, W_R] - d
        if delta <= 0.0 or d <= 0.0:
            continue
        dd = lj * lk * math.sin(da) / d              # dd/dpsi_j = -dd/dpsi_k
        F = wt[j, W_KC] * delta - wt[j, W_CC] * dd * wref * (y[ns + n + j] - y[ns + n + k])
        if F > 0.0:
            buf[om + j] -= F * dd
            buf[om + k] += F * dd


@njit(cache=True, error_model="numpy", _nrt=False)
def oval_contact(wt, y, n, ns, wref, buf, om, j, k):
    """Contact of neighbours j, k on an out-of-round race (module docstring) into ``buf[om:]``."""
    aj, ak = y[n + j], y[n + k]
    rj, r1j, _ = race_shape(wt[j, W_L], wt[j, W_EPS], wt[j, W_K], wt[j, W_PH], aj)
    rk, r1k, _ = race_shape(wt[k, W_L], wt[k, W_EPS], wt[k, W_K], wt[k, W_PH], ak)
    cd, sd = math.cos(aj - ak), math.sin(aj - ak)
    d = math.sqrt(rj * rj + rk * rk - 2.0 * rj * rk * cd)
    delta = wt[j, W_R] + wt[k, W_R] - d
    if delta <= 0.0 or d <= 0.0:
        return
    gj = (rj * r1j - r1j * rk * cd + rj * rk * sd) / d      # dd/da_j, dd/da_k
    gk = (rk * r1k - rj * r1k * cd - rj * rk * sd) / d
    F = wt[j, W_KC] * delta - wt[j, W_CC] * wref * (gj * y[ns + n + j] + gk * y[ns + n + k])
    if F > 0.0:
        buf[om + j] -= F * gj
        buf[om + k] -= F * gk


@njit(cache=True, error_model="numpy", _nrt=False)
def race_gravity(wt, j, phi, Om, dOm, gx, gy):
    """The ball's own transverse gravity g_j = g_p - o'' [m/s^2] on an eccentric race
    (module docstring): phi [rad], Om [rad/s], dOm [rad/s^2] the rotor's."""
    er = wt[j, W_ER]
    co, so = math.cos(phi + wt[j, W_TH]), math.sin(phi + wt[j, W_TH])
    return gx + er * (Om * Om * co + dOm * so), gy + er * (Om * Om * so - dOm * co)


@njit(cache=True, error_model="numpy", _nrt=False)
def friction_moment(wt, j, y, m, l, psid, ad, c, si, gx, gy):
    """Regularised Coulomb moment [N m] on weight j (stand.model.balancers.friction)."""
    muk = wt[j, W_MUK]
    if muk <= 0.0 and wt[j, W_MUS] <= 0.0:
        return 0.0
    mu = muk
    iz = int(wt[j, W_Z])
    if iz >= 0:
        mu = muk + (wt[j, W_MUS] - muk) * y[iz]
    N = m * (l * psid * psid + c * gx + si * gy)
    if N < 0.0:
        N = 0.0
    x = ad / wt[j, W_VS]
    return mu * N * l * x / math.sqrt(1.0 + x * x)


def race_columns(balancer, plane: str, free: bool, friction) -> list:
    """The race's columns of a ball's row (W_ER, W_TH, W_EPS, W_K, W_PH): eccentricity [m] and
    its angle [rad], out-of-roundness eps [-], lobes k, its angle [rad]; ValueError naming the
    key for what the race's kinematics do not cover (module docstring)."""
    er = float(getattr(balancer, "race_eccentricity", 0.0))
    if er and free:
        raise ValueError(f"weights[{plane}].race_eccentricity = {er!r} m: with a speed "
                         f"programme only (a free rotor's phi'' is not coupled to the race)")
    eps = float(getattr(balancer, "race_out_of_roundness", 0.0))
    k = int(getattr(balancer, "race_lobes", 2))
    if eps:
        key = f"weights[{plane}].race_out_of_roundness = {eps!r} (dimensionless)"
        if not (0.0 < eps < 0.2) or k < 2:
            raise ValueError(f"{key}, race_lobes = {k}: need 0 <= eps < 0.2 and an integer k >= 2")
        why = ("a torque drive (a free rotor's phi'' is not coupled to the race)" if free else
               "rolling = true or an inertia other than m l^2 (a rolling ball's spin follows the "
               "race's arc length)"
               if np.any(balancer.spin_inertia != 0.0)
               or np.any(np.asarray(balancer.inertia) != balancer.mass * balancer.radius ** 2) else
               "friction / static_friction (the normal force on the out-of-round race)"
               if friction is not None and (friction.kinetic > 0 or friction.static > 0) else "")
        if why:
            raise ValueError(f"{key}: not modelled together with {why}; point balls with "
                             f"viscous drag on a speed programme only")
    return [er, float(getattr(balancer, "race_eccentricity_angle", 0.0)), eps, float(k),
            float(getattr(balancer, "race_out_of_roundness_angle", 0.0))]


@njit(cache=True, error_model="numpy", _nrt=False)
def race_shape(l, eps, k, theta, a):
    """rho, rho', rho'' [m] of the race l [1 + eps cos k (a - theta)] at the ball's angle a [rad]
    on the rotor (module docstring); on arrays of a through its ``py_func`` (:func:`ball_offsets`)."""
    x = k * (a - theta)
    c, s = np.cos(x), np.sin(x)
    return l * (1.0 + eps * c), -l * eps * k * s, -l * eps * k * k * c


def ball_offsets(wt, j, alpha):
    """Ball j's centre from the shaft in the rotor frame [m], complex, at its angles ``alpha``
    [rad] (array) on the rotor: the race's offset e_r e^{i theta} plus rho(alpha) e^{i alpha}."""
    shape = getattr(race_shape, "py_func", race_shape)      # plain numpy, no compilation
    rho = shape(wt[j, W_L], wt[j, W_EPS], wt[j, W_K], wt[j, W_PH], np.asarray(alpha, float))[0]
    return wt[j, W_ER] * np.exp(1j * wt[j, W_TH]) + rho * np.exp(1j * alpha)


@njit(cache=True, error_model="numpy", _nrt=False)
def oval_row(wt, j, a, ad, Om, dOm, c, si, gjx, gjy):
    """Ball j on an out-of-round race (module docstring): the coupling vector u [m], the
    generalised mass G [kg m^2], gamma = g_j - c [m/s^2] and the drag moment M_r [N m] at its
    angle a [rad] and speed a' [rad/s] on the rotor (phi' = Om [rad/s], phi'' = dOm [rad/s^2];
    c, si: cos, sin psi)."""
    l = wt[j, W_L]
    rho, r1, r2 = race_shape(l, wt[j, W_EPS], wt[j, W_K], wt[j, W_PH], a)
    psid = Om + ad
    u2 = rho * rho + r1 * r1
    ce = r2 * ad * ad - r1 * dOm - rho * psid * psid      # c along e and along t
    ct = 2.0 * r1 * ad * psid
    return (r1 * c - rho * si, r1 * si + rho * c, wt[j, W_M] * u2, gjx - (ce * c - ct * si),
            gjy - (ce * si + ct * c), wt[j, W_H] * u2 / (l * l) * ad)


@njit(cache=True, error_model="numpy", _nrt=False)
def oval_push(wt, j, p, a, ad, Om, dOm, c, si, gjx, gjy, buf, ofp, oC, om, contact):
    """Ball j's push on plane p (module docstring): its force into ``buf[ofp + 2 p:]``, its
    inertia m I - (m^2 / G) u u^T into ``buf[oC + 4 p:]``, its resisting moment (drag, and the
    contact's already in ``buf[om + j]`` when ``contact``) into ``buf[om + j]``."""
    ux, uy, G, gx, gy, Mr = oval_row(wt, j, a, ad, Om, dOm, c, si, gjx, gjy)
    if contact:
        Mr += buf[om + j]
    m = wt[j, W_M]
    h = m / G * (m * (ux * gx + uy * gy) - Mr)
    buf[ofp + 2 * p] += m * gx - h * ux
    buf[ofp + 2 * p + 1] += m * gy - h * uy
    k2 = m * m / G
    o = oC + 4 * p
    buf[o] += m - k2 * ux * ux
    buf[o + 1] -= k2 * ux * uy
    buf[o + 2] -= k2 * ux * uy
    buf[o + 3] += m - k2 * uy * uy
    buf[om + j] = Mr


@njit(cache=True, error_model="numpy", _nrt=False)
def oval_accel(wt, j, a, ad, phi, Om, dOm, apx, apy, gjx, gjy, Mr):
    """psi'' [rad/s^2] of ball j on an out-of-round race: (m u . (gamma - T_p q'') - M_r) / G
    (module docstring), the plane point's acceleration T_p q'' = (apx, apy) [m/s^2], M_r [N m]
    its resisting moment (:func:`oval_push`'s)."""
    c, si = math.cos(phi + a), math.sin(phi + a)
    ux, uy, G, gx, gy, _ = oval_row(wt, j, a, ad, Om, dOm, c, si, gjx, gjy)
    return (wt[j, W_M] * (ux * (gx - apx) + uy * (gy - apy)) - Mr) / G
