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
"""
from __future__ import annotations

import math

from stand._jit import njit

__all__ = ["N_WCOL", "contact_moments", "race_gravity"]

# weight table columns: plane, mass, radius, inertia, drag, friction (kinetic,
# static, slip speed, dwell, release), index of its adhesion state (-1: none), spin inertia
# J_s on the angle relative to the rotor (rolling balls, stand.model.weights; 0: none); contact:
# the ball's own radius, spring, dashpot and the index of its next neighbour in its race (-1: none)
W_PLANE, W_M, W_L, W_J, W_H, W_MUK, W_MUS, W_VS, W_TD, W_TR, W_Z, W_JS, W_R, W_KC, W_CC, W_NEXT, \
    W_ER, W_TH = range(18)     # race eccentricity [m] and its angle [rad] in the rotor frame
N_WCOL = 18


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
def race_gravity(wt, j, phi, Om, dOm, gx, gy):
    """The ball's own transverse gravity g_j = g_p - o'' [m/s^2] on an eccentric race
    (module docstring): phi [rad], Om [rad/s], dOm [rad/s^2] the rotor's."""
    er = wt[j, W_ER]
    co, so = math.cos(phi + wt[j, W_TH]), math.sin(phi + wt[j, W_TH])
    return gx + er * (Om * Om * co + dOm * so), gy + er * (Om * Om * so - dOm * co)
