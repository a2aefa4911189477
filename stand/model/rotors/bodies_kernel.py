"""Compiled equations of the body weights (two-axis pendulum, coupled pair, damper, liquid).

Every body weight sits at the point of a rotor plane (plane map T_p, force map
F_p, :mod:`stand.model.rotors.structure`).  Written once, in the fixed frame, in SI,
each body gives the generic right-hand side (:func:`stand.model.rotors.coupled_kernel.rhs_generic`)
two things:

1. its **reaction** on the plane point, affine in the point's absolute
   acceleration ``a = T_p q''``::

       F = R a + r          (R: 2x2 [kg], r: 2 [N])

   (its own accelerations are eliminated: bodies couple only through the
   shaft), so the rotor equation becomes
   ``(M - sum F_p^T R T_p) q'' = f + sum F_p^T r`` (one n x n solve, O(bodies));
2. its **state derivatives** once ``a`` is known.

Kinds (``B_KIND``)
------------------
``TILT`` -- a weight on a two-axis hinge at the plane point (ch. 6 two-axis
pendulum, ch. 7.1 coupled pair).  Azimuth ``alpha`` (absolute, about the shaft
axis) and tilt ``phi`` (about the transverse axis); centre of mass at the
horizontal offset ``d = l sin(phi) u``, ``u = (-sin alpha, cos alpha)``, and
``-l cos(phi)`` along the axis; kinetic energy
``m |v_p|^2/2 + m v_p . D theta' + (A phi'^2 + B alpha'^2)/2`` (inertia
diag(A, B, B) about the pivot, A about the tilt axis), ``D = dd/dtheta``.
Lagrange's equations (the fixed-frame (6.15) of ch. 6 and (7.34) of ch. 7.1 in SI)::

    A phi''   = -H1 phi'            - m g_a l sin(phi) - m D_phi   . (a - g)
    B alpha'' = -H2 (alpha' - Omega)                   - m D_alpha . (a - g)
    F = -m (a + D theta'' + c) + m g,   c = l[-(phi'^2 + alpha'^2) sin(phi) u
                                              - 2 phi' alpha' cos(phi) v]

with ``v = (cos alpha, sin alpha)``, ``g`` the transverse gravity of the rotor
and ``g_a`` the gravity along the axis acting on the tilt (ch. 6: ``g``; the
coupled pair of 7.1 is built so that gravity does no work: ``g_a = 0``).

``SPHERE`` -- the autobalancer-damper (ch. 7.2): a weight turning freely about
the plane point, spherical inertia A about it, centre of mass at ``l n``
(``|n| = 1``).  Euler's law about the moving point (digest ch7 section 2;
:mod:`stand.model.balancers.damper`)::

    A W' = m l n x (g3 - a3) - H1 (W - Omega e_z),    n' = W x n
    F    = -m (a + l n''_h) + m g

with ``g3 = (g_x, g_y, -g_a)``, ``a3 = (a_x, a_y, 0)``; eliminating ``W'``
gives ``R = -m I + (m^2 l^2/A)(I - n_h n_h^T)``.  The book's constraint
stabilisation ``k_c (1 - |n|^2) n / 2`` (per unit of the time scale) keeps
``|n| = 1`` attracting.

``LEVER`` -- liquid whose centre of mass stays at ``lambda`` times the plane's
displacement from the bearing axis (paper 001 model M1:
``lambda = r1^2/(r1^2 - r2^2)``; the liquid chamber of thesis 002 with its free
surface concentric with the axis: ``lambda = R^2/(R^2 - r^2)``)::

    F = -m lambda a + m g

``LAG`` -- the liquid chamber with a free surface that relaxes to the axis
with the time constant ``tau_l`` in the liquid's (rotating) frame.  State
``sigma``: the free-surface centre relative to the chamber centre (fixed-frame
components); the liquid centre of mass is at ``Z - kappa sigma``
(``kappa = r^2/(R^2 - r^2)``, thesis l.668)::

    sigma' = i Omega sigma - (sigma + Z)/tau_l
    F      = -m (a - kappa sigma'') + m g

(``sigma = -Z``, the ``LEVER`` with ``lambda = 1 + kappa``, when ``tau_l -> 0``).

Scaling: the state holds angles [rad], rates per unit of the scaled time
``tau = omega_ref t``, and the ``LAG`` offset in units of the body's length
scale ``B_LS``.
"""
from __future__ import annotations

import math

from stand._jit import njit

# body kinds
TILT, SPHERE, LEVER, LAG = 1, 2, 3, 4
#: states per kind (index = kind)
N_STATES = (0, 4, 6, 0, 2)
# columns of a body row: kind, plane index, offset of its states in y, mass [kg], arm [m],
# inertia A, B [kg m^2], drags H1, H2 [N m s], axial gravity [m/s^2], lever lambda / kappa [-],
# relaxation time [s], constraint gain k_c [-], length scale [m]
B_KIND, B_PLANE, B_OFF, B_M, B_L, B_A, B_B, B_H1, B_H2, B_GA, B_LAM, B_TAU, B_KC, B_LS = range(14)
N_BCOL = 14


@njit(cache=True, error_model="numpy", _nrt=False)
def _tilt_terms(sp, rb, y, o, wref, Om, gx, gy):
    """Offsets' derivatives D_phi, D_alpha, velocity acceleration c and generalised forces Q."""
    m, l, ga = sp[rb + B_M], sp[rb + B_L], sp[rb + B_GA]
    ph, al = y[o], y[o + 1]
    dph, dal = wref * y[o + 2], wref * y[o + 3]
    sf, cf, sa, ca = math.sin(ph), math.cos(ph), math.sin(al), math.cos(al)
    # u = (-sa, ca), v = (ca, sa)
    dpx, dpy = -l * cf * sa, l * cf * ca          # D_phi = l cos(phi) u
    dax, day = -l * sf * ca, -l * sf * sa         # D_alpha = -l sin(phi) v
    w2 = dph * dph + dal * dal
    cx = l * (w2 * sf * sa - 2.0 * dph * dal * cf * ca)
    cy = l * (-w2 * sf * ca - 2.0 * dph * dal * cf * sa)
    qph = -sp[rb + B_H1] * dph - m * ga * l * sf + m * (dpx * gx + dpy * gy)
    qal = -sp[rb + B_H2] * (dal - Om) + m * (dax * gx + day * gy)
    return dpx, dpy, dax, day, cx, cy, qph, qal


@njit(cache=True, error_model="numpy", _nrt=False)
def _sphere_terms(sp, rb, y, o, wref, Om, gx, gy):
    """Unit direction n, absolute angular velocity W [rad/s] and the known part G of W'."""
    m, l, A = sp[rb + B_M], sp[rb + B_L], sp[rb + B_A]
    n0, n1, n2 = y[o], y[o + 1], y[o + 2]
    nn = math.sqrt(n0 * n0 + n1 * n1 + n2 * n2)
    n0, n1, n2 = n0 / nn, n1 / nn, n2 / nn
    W0, W1, W2 = wref * y[o + 3], wref * y[o + 4], wref * y[o + 5]
    k = m * l / A
    h = sp[rb + B_H1] / A
    g2 = -sp[rb + B_GA]
    # G = (m l / A) n x g3 - (H1 / A)(W - Omega e_z)
    G0 = k * (n1 * g2 - n2 * gy) - h * W0
    G1 = k * (n2 * gx - n0 * g2) - h * W1
    G2 = k * (n0 * gy - n1 * gx) - h * (W2 - Om)
    return n0, n1, n2, W0, W1, W2, G0, G1, G2


@njit(cache=True, error_model="numpy", _nrt=False)
def _lag_sigma(sp, rb, y, o, zx, zy, zdx, zdy, Om, dOm):
    """Offset sigma [m], its rate and its acceleration without the plane's acceleration."""
    Ls, tl = sp[rb + B_LS], sp[rb + B_TAU]
    sx, sy = Ls * y[o], Ls * y[o + 1]
    sdx = -Om * sy - (sx + zx) / tl
    sdy = Om * sx - (sy + zy) / tl
    sddx = -dOm * sy - Om * sdy - (sdx + zdx) / tl
    sddy = dOm * sx + Om * sdx - (sdy + zdy) / tl
    return sx, sy, sdx, sdy, sddx, sddy


@njit(cache=True, error_model="numpy", _nrt=False)
def body_reaction(sp, rb, y, wref, Om, dOm, gx, gy, zx, zy, zdx, zdy, Rr, oR):
    """Fill ``Rr[oR:oR + 6] = [R00, R01, R10, R11, r0, r1]``: the reaction ``F = R a + r``
    [kg, N] of the body whose row starts at ``sp[rb]``.

    ``(zx, zy)``, ``(zdx, zdy)``: the plane point's displacement [m] and velocity [m/s]
    (used by ``LAG`` only).
    """
    kind = int(sp[rb + B_KIND])
    o = int(sp[rb + B_OFF])
    m = sp[rb + B_M]
    if kind == TILT:
        dpx, dpy, dax, day, cx, cy, qph, qal = _tilt_terms(sp, rb, y, o, wref, Om, gx, gy)
        iA, iB = 1.0 / sp[rb + B_A], 1.0 / sp[rb + B_B]
        m2 = m * m
        Rr[oR + 0] = -m + m2 * (dpx * dpx * iA + dax * dax * iB)
        Rr[oR + 1] = m2 * (dpx * dpy * iA + dax * day * iB)
        Rr[oR + 2] = Rr[oR + 1]
        Rr[oR + 3] = -m + m2 * (dpy * dpy * iA + day * day * iB)
        Rr[oR + 4] = -m * (dpx * qph * iA + dax * qal * iB) - m * cx + m * gx
        Rr[oR + 5] = -m * (dpy * qph * iA + day * qal * iB) - m * cy + m * gy
    elif kind == SPHERE:
        n0, n1, n2, W0, W1, W2, G0, G1, G2 = _sphere_terms(sp, rb, y, o, wref, Om, gx, gy)
        l = sp[rb + B_L]
        kap = m * l * l / sp[rb + B_A]
        # q = G x n + W x (W x n) (horizontal part)
        wn = W0 * n0 + W1 * n1 + W2 * n2
        ww = W0 * W0 + W1 * W1 + W2 * W2
        q0 = (G1 * n2 - G2 * n1) + W0 * wn - n0 * ww
        q1 = (G2 * n0 - G0 * n2) + W1 * wn - n1 * ww
        Rr[oR + 0] = -m + m * kap * (1.0 - n0 * n0)
        Rr[oR + 1] = -m * kap * n0 * n1
        Rr[oR + 2] = Rr[oR + 1]
        Rr[oR + 3] = -m + m * kap * (1.0 - n1 * n1)
        Rr[oR + 4] = -m * l * q0 + m * gx
        Rr[oR + 5] = -m * l * q1 + m * gy
    elif kind == LEVER:
        lam = sp[rb + B_LAM]
        Rr[oR + 0] = -m * lam
        Rr[oR + 1] = 0.0
        Rr[oR + 2] = 0.0
        Rr[oR + 3] = -m * lam
        Rr[oR + 4] = m * gx
        Rr[oR + 5] = m * gy
    else:   # LAG
        sx, sy, sdx, sdy, sddx, sddy = _lag_sigma(sp, rb, y, o, zx, zy, zdx, zdy, Om, dOm)
        kap = sp[rb + B_LAM]
        Rr[oR + 0] = -m
        Rr[oR + 1] = 0.0
        Rr[oR + 2] = 0.0
        Rr[oR + 3] = -m
        Rr[oR + 4] = m * kap * sddx + m * gx
        Rr[oR + 5] = m * kap * sddy + m * gy


@njit(cache=True, error_model="numpy", _nrt=False)
def body_derivatives(sp, rb, y, dy, wref, Om, dOm, gx, gy, zx, zy, zdx, zdy, ax, ay):
    """Write the body's scaled state derivatives into ``dy`` given the plane point's
    absolute acceleration ``(ax, ay)`` [m/s^2]."""
    kind = int(sp[rb + B_KIND])
    o = int(sp[rb + B_OFF])
    m = sp[rb + B_M]
    w2 = wref * wref
    if kind == TILT:
        dpx, dpy, dax, day, cx, cy, qph, qal = _tilt_terms(sp, rb, y, o, wref, Om, gx, gy)
        ddph = (qph - m * (dpx * ax + dpy * ay)) / sp[rb + B_A]
        ddal = (qal - m * (dax * ax + day * ay)) / sp[rb + B_B]
        dy[o] = y[o + 2]
        dy[o + 1] = y[o + 3]
        dy[o + 2] = ddph / w2
        dy[o + 3] = ddal / w2
    elif kind == SPHERE:
        n0, n1, n2, W0, W1, W2, G0, G1, G2 = _sphere_terms(sp, rb, y, o, wref, Om, gx, gy)
        k = m * sp[rb + B_L] / sp[rb + B_A]
        # W' = G - (m l / A) n x a3,  n x a3 = (-n2 ay, n2 ax, n0 ay - n1 ax)
        dW0 = G0 + k * n2 * ay
        dW1 = G1 - k * n2 * ax
        dW2 = G2 - k * (n0 * ay - n1 * ax)
        r0, r1, r2 = y[o], y[o + 1], y[o + 2]
        s0, s1, s2 = y[o + 3], y[o + 4], y[o + 5]
        st = 0.5 * sp[rb + B_KC] * (1.0 - (r0 * r0 + r1 * r1 + r2 * r2))
        dy[o] = s1 * r2 - s2 * r1 + st * r0
        dy[o + 1] = s2 * r0 - s0 * r2 + st * r1
        dy[o + 2] = s0 * r1 - s1 * r0 + st * r2
        dy[o + 3] = dW0 / w2
        dy[o + 4] = dW1 / w2
        dy[o + 5] = dW2 / w2
    elif kind == LAG:
        sx, sy, sdx, sdy, sddx, sddy = _lag_sigma(sp, rb, y, o, zx, zy, zdx, zdy, Om, dOm)
        Ls = sp[rb + B_LS]
        dy[o] = sdx / (wref * Ls)
        dy[o + 1] = sdy / (wref * Ls)
