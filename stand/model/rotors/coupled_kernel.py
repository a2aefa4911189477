"""Correction weights (balls, pendulums) coupled to any :class:`LinearRotor`.

Weight j (mass m_j, radius l_j, moment of inertia J_j about the shaft axis,
viscous moment coefficient H_j on its speed relative to the rotor) sits in
plane p with absolute angle psi_j = phi + alpha_j; its centre is at
``r_j = T_p q + l_j e_j``, ``e_j = (cos psi_j, sin psi_j)``,
``n_j = (sin psi_j, -cos psi_j)``.  Lagrange's equations (the corrected
(5.4)/(5.7) of the planar model, digest ch5 section 0.2, generalised through
the plane map T_p, and (3.1)-(3.11) of ch. 3)::

    J_j psi_j'' = m_j l_j n_j . (T_p q'' - g_p) - H_j alpha_j'
    M q'' + (D + Omega G) q' + K q = f_unb + f_grav
          + sum_j T_p^T [ m_j g_p - m_j (T_p q'' - l_j psi_j'' n_j - l_j psi_j'^2 e_j) ]

(g_p: the transverse gravity acceleration, zero for a vertical axis).
Eliminating psi_j'' (the weights couple only through the shaft) leaves one
n x n system for q'' (n = rotor coordinates)::

    [M + sum_j m_j T_p^T T_p - sum_j (m_j^2 l_j^2 / J_j) T_p^T n_j n_j^T T_p] q''
        = f + sum_j T_p^T [ m_j g_p + m_j l_j psi_j'^2 e_j
                            - (m_j^2 l_j^2 / J_j)(n_j . g_p) n_j - (m_j l_j H_j alpha_j' / J_j) n_j ]

(forces through the plane's force map F_p^T when it has one, see
:mod:`stand.model.rotors.structure`).  For point balls (J = m l^2) the bracket is
M + sum m T^T e e^T T.  The weights enter only through their planes: the kernel gathers
the plane forces and each plane's 2 x 2 inertia (m_j I - (m_j^2 l_j^2 / J_j) n_j n_j^T,
summed) and :mod:`stand.model.rotors.coupled_solve` solves M + F^T C T either assembled
(O(n^3)) or, when the planes' space is the smaller (2 x planes < n: the flexible shaft), by
the Woodbury identity on the constant M (O(planes x n) with a diagonal M); K, D and G are
applied by their kind (zero, diagonal, dense).  The cost is linear in the number of weights.
The weights are point masses in their plane (their own transverse moments of
inertia are neglected, as in the book's linear models).  A rolling ball's spin inertia
J_s = J_j - m_j l_j^2 acts on its angle relative to the rotor (:mod:`stand.model.weights`):
its row gains ``+ J_s phi''`` (a known moment under a speed programme) and, on a free
rotor, the spin row ``+ J_s (phi'' - psi_j'')`` -- with psi_j'' eliminated, the column
``b`` and row ``gamma`` below gain ``-(m_j l_j J_s / J_j) n_j``, J_p gains
``J_s (1 - J_s / J_j)`` and the right side ``-(J_s / J_j)(m_j l_j n_j . g_p + M_r,j)``.

**Ball-ball contact**, **race eccentricity** and **out-of-roundness**: :mod:`stand.model.rotors.weight_table`
(internal moments between neighbouring balls of a race, beside their drag; the race's
kinematics: an out-of-round race's ball has its own row and push, ``oval_push``, ``oval_accel``).

**Torque drive** (the rotor angle phi and speed Omega = phi' are states, the last two
of ``y``; header flag ``H_FREE`` = index of phi, 0 for a speed programme, whose path is
unchanged).  The book's free rotor of section 5.1.1 ((5.1)-(5.10); digest ch5 sections
1-2: the corrected (5.7), with the drag reaction nu_j = H_j/(omega_1 J_0) of correction 4)
generalised to any LinearRotor.  An unbalance s_u = m e at angle phi + theta_u in plane p
sits at ``T_p q + e e_u`` (``e_u = (cos, sin)(phi + theta_u)``, ``n_u = (sin, -cos)(...)``);
its Lagrange terms give, besides the weights' equations above (unchanged: psi_j is
absolute, so the weights' elimination does not involve phi'')::

    M q'' + ... = ... + F_p^T s_u (phi'^2 e_u + phi'' n_u)           (translations)
    J_p phi'' = M_drive(phi', phi, t) - H0 phi' + sum_j (H_j alpha_j' + M_fric,j)
                + sum_b M_b + sum_u s_u n_u . (T_p q'' - g_p)          (spin)

(J_p: the rotor's polar moment of inertia about the shaft, m e^2 included, the weights
not; the weights' drag and friction moments act back on the rotor; body weights' turn
drags M_b = H2 (alpha' - Omega) (tilting weights) and the damper's drag z-moment
H1 (W_z - Omega) likewise; a liquid exerts no moment about the shaft in its models.)
The gyroscopic matrix takes the state Omega.  phi'' enters the translations linearly
(through the unbalances and, for the ``LAG`` liquid, through the body reaction, whose
phi''-part is found by evaluating it at phi'' = 1 and 0), so the accelerations solve one
augmented (n+1) system::

    [ A_schur            -sum_u s_u F_p^T n_u ] [ q''  ]   [ f (phi'' = 0)                      ]
    [ -sum_u s_u n_u^T T_p       J_p           ] [ phi'' ] = [ M_drive - H0 Omega + moments - sum_u s_u n_u . g_p ]

with A_schur and f the speed-programme system above (the body reactions' phi'' column
added to the first block column); for the planar rotor this is the book's 3x3 Schur
complement of (5.4)-(5.10) (:func:`stand.model.planar.rhs_planar`), which the generic path
reproduces to 1e-8 (tests/test_family_torque.py).  Drive models (``DRIVE_MODELS``, book
models 1-3): constant M; c1 (omega - phi'); c1 (omega - phi') + c2 (omega t - phi).

The integration is the one integrator path (:mod:`stand.integrate.driver`,
compiled DOP853 or scipy's methods) with model kind ``GENERIC`` in
:mod:`stand.model.kernels`; this module holds the compiled right-hand side and the
packing only (the runner is :mod:`stand.integrate.coupled`), so that the kernels
import nothing that imports them.  Time is scaled by a
reference frequency omega_ref (tau = omega_ref t) and each coordinate by its
own length scale, so that the tolerances mean the same for every rotor.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Optional, Sequence

import numpy as np

from stand._jit import njit
from stand.model.programme import build_table, drive_torque_law, programme_kinematics
from stand.model.rotors.bodies import PlaneBody, body_rows
from stand.model.rotors.bodies_kernel import (B_H1, B_H2, B_KIND, B_OFF, B_PLANE, N_BCOL, SPHERE, TILT,
                            body_derivatives, body_reaction)
from stand.model.rotors.coupled_solve import (matrix_kind, plane_parts, rotor_forces, row_ranges,
                                             solve_general, solve_planes, t_dot)
from stand.model.rotors.structure import LinearRotor
from stand.model.rotors.weight_table import (N_WCOL, W_EPS, W_ER, W_H, W_J, W_JS, W_L, W_M, W_MUK,
                                           W_NEXT, W_PLANE, W_TD, W_TR, W_VS, W_Z, contact_moments,
                                           friction_moment, oval_accel, oval_push, race_columns,
                                           race_gravity)

__all__ = ["CoupledModel", "build_model", "rhs_generic", "scratch_size",
           "with_locked_weights"]

# header of the scalar parameter vector sp
H_N, H_NW, H_NPL, H_NUB, H_WREF, H_OM, H_OG, H_OD, H_OK, H_OT, H_OUB, H_OL, H_OGR, H_OGP, \
    H_OF, H_NB, H_OB = range(17)
# torque drive (rotor angle and speed are states): index of phi in y (0: speed programme,
# phi and Omega from ``prog``), polar inertia J_p [kg m^2], drive model (0 constant,
# 1 speed feedback, 2 angle feedback), torque [N m], c1 [N m s], c2 [N m], target speed
# [rad/s], rotor drag H0 [N m s], initial speed [rad/s]
H_FREE, H_JP, H_DMODEL, H_TQ, H_C1, H_C2, H_WT, H_H0, H_W0 = range(17, 26)
# offset of the RHS's scratch block (sp's last, :func:`scratch_size`); the plane-space solve
# (stand.model.rotors.coupled_solve): offsets of M^-1, W = M^-1 F^T, S = T M^-1 F^T, the kinds
# (zero, diagonal, dense) of K, D, G and M^-1, and whether to solve in the planes' space
H_OS, H_OMI, H_OW, H_OSS, H_KK, H_KD, H_KG, H_KMI, H_FAST = range(26, 35)
# offset of the plane maps' rows' nonzero column ranges (coupled_solve.row_ranges); ball-ball
# contact anywhere (1.0) or not (0.0: no contact work)
H_OTR, H_CONTACT = 35, 36
N_HEAD = 37
DRIVE_MODELS = {"constant": 0, "speed_feedback": 1, "angle_feedback": 2}


def with_locked_weights(rotor: LinearRotor, weights: Sequence,
                        bodies: Sequence[PlaneBody] = ()) -> LinearRotor:
    """The rotor with its weights locked (their masses moving with the planes:
    ``M + sum m_j T_p^T T_p``, body weights included): the structure the engineering
    criterion and the calibration rings refer to."""
    import dataclasses

    M = rotor.M.copy()
    for w in weights:
        T = rotor.planes[w.plane]
        M += float(np.sum(w.balancer.mass)) * (rotor.force_map(w.plane).T @ T)
    for b in bodies:
        M += b.mass * (rotor.force_map(b.plane).T @ rotor.planes[b.plane])
    return dataclasses.replace(rotor, M=M)


@njit(cache=True, error_model="numpy", _nrt=False)
def drive_moment(t, phi, Om, sp):
    """Drive torque M_drive [N m] of the book's models 1-3 (section 5.1.1) at time t [s]."""
    return drive_torque_law(sp[H_DMODEL], sp[H_TQ], sp[H_C1], sp[H_C2], sp[H_WT], t, phi, Om)


@njit(cache=True, error_model="numpy", _nrt=False)
def body_spin_moment(sp, rb, y, wref, Om):
    """Moment [N m] about the shaft that body weight ``rb`` exerts on the rotor: the
    reaction of its turn drag (TILT: H2 (alpha' - Omega); SPHERE: the z-component
    H1 (W_z - Omega) of the damper's drag); none for the liquids."""
    kind = int(sp[rb + B_KIND])
    o = int(sp[rb + B_OFF])
    if kind == TILT:
        return sp[rb + B_H2] * (wref * y[o + 3] - Om)
    if kind == SPHERE:
        return sp[rb + B_H1] * (wref * y[o + 5] - Om)
    return 0.0


@njit(cache=True, error_model="numpy", _nrt=False)
def rhs_generic(tau, y, dy, sp, wt, prog):
    """Right-hand side of a LinearRotor with weights (module docstring), scaled time."""
    n = int(sp[H_N])
    nw = int(sp[H_NW])
    npl = int(sp[H_NPL])
    nub = int(sp[H_NUB])
    wref = sp[H_WREF]
    oT, oUB, oL, oGR, oGP = int(sp[H_OT]), int(sp[H_OUB]), int(sp[H_OL]), int(sp[H_OGR]), int(sp[H_OGP])
    ifree = int(sp[H_FREE])
    free = ifree != 0
    if not free:        # speed programme
        phi, R, dR = programme_kinematics(tau, prog, prog.shape[0])
        Om = R * wref
        dOm = dR * wref * wref
    else:               # torque drive: phi, Omega states, phi'' one more unknown
        phi = y[ifree]
        Om = wref * y[ifree + 1]
        dOm = 0.0
    ld = n + 1 if free else n
    gx = sp[oGP]
    gy = sp[oGP + 1]
    ns = n + nw
    nb = int(sp[H_NB])
    oB = int(sp[H_OB])
    m2 = 2 * npl
    # one flat scratch block, the tail of sp (scratch_size; views and allocations dominate at
    # small n), indexed by offsets: q, q', f, x, A, per point weight cos, sin, moment, a body
    # reaction, and the planes' space (stand.model.rotors.coupled_solve): T q, T q', f_p,
    # C (4 per plane), b, gamma, T x, the small system, u
    buf, oq = sp, int(sp[H_OS])
    oqd, of = oq + n, oq + 2 * n
    ox = of + ld
    oA = ox + ld
    oc = oA + ld * ld
    os_ = oc + nw
    om = os_ + nw
    oR = om + nw
    otq = oR + 6
    otqd = otq + m2
    ofp = otqd + m2
    oC = ofp + m2
    ob = oC + 2 * m2
    og = ob + m2
    otx = og + m2
    oE = otx + m2
    ou = oE + m2 * (m2 + 2)
    # views indexed from 0 in the loops over the coordinates (coupled_solve.dot)
    Ls, yq, yqd = sp[oL:oL + n], y[:n], y[ns:ns + n]
    q, qd = buf[oq:oq + n], buf[oqd:oqd + n]
    for i in range(n):
        q[i] = Ls[i] * yq[i]
        qd[i] = wref * Ls[i] * yqd[i]
    # the rotor's own forces f_s = g - K q - (D + Omega G) q' (each matrix by its kind)
    rotor_forces(sp, buf, n, oGR, int(sp[H_OK]), int(sp[H_KK]), int(sp[H_OD]), int(sp[H_KD]),
                 int(sp[H_OG]), int(sp[H_KG]), Om, oq, oqd, of)
    oTr = int(sp[H_OTR])
    for r in range(m2):
        if nb > 0:      # the plane points' motion: the bodies' reactions need it
            buf[otq + r] = t_dot(sp, oT, oTr, r, n, buf, oq)
            buf[otqd + r] = t_dot(sp, oT, oTr, r, n, buf, oqd)
        buf[ofp + r], buf[ob + r], buf[og + r] = 0.0, 0.0, 0.0
        buf[oC + 2 * r], buf[oC + 2 * r + 1] = 0.0, 0.0
    fn = 0.0
    # unbalances: plane forces; under a torque drive s phi'' (sin, -cos) = s phi'' n_u moves to
    # the left (b) and into the spin row (gamma)
    for u in range(nub):
        p = int(sp[oUB + 3 * u])
        s = sp[oUB + 3 * u + 1]
        th = phi + sp[oUB + 3 * u + 2]
        c, si = math.cos(th), math.sin(th)
        buf[ofp + 2 * p] += s * (Om * Om * c + dOm * si)
        buf[ofp + 2 * p + 1] += s * (Om * Om * si - dOm * c)
        if free:
            buf[ob + 2 * p] -= s * si
            buf[ob + 2 * p + 1] += s * c
            buf[og + 2 * p] -= s * si
            buf[og + 2 * p + 1] += s * c
            fn -= s * (si * gx - c * gy)
    # weights: plane inertia C_p += m I - k2 n n^T and plane forces (the angle's cosine, sine
    # and the resisting moment are kept for the weights' own accelerations below)
    jp = sp[H_JP]
    contact = sp[H_CONTACT] != 0.0
    if contact:
        contact_moments(wt, y, n, ns, wref, buf, om)
    for j in range(nw):
        p = int(wt[j, W_PLANE])
        m = wt[j, W_M]
        l = wt[j, W_L]
        J = wt[j, W_J]
        H = wt[j, W_H]
        a = y[n + j]
        ad = wref * y[ns + n + j]
        psi = phi + a
        psid = Om + ad
        c, si = math.cos(psi), math.sin(psi)
        k2 = m * m * l * l / J
        gjx, gjy = gx, gy
        if wt[j, W_ER] != 0.0:      # eccentric race (speed programme): g_j = g_p - o''
            gjx, gjy = race_gravity(wt, j, phi, Om, dOm, gx, gy)
        if wt[j, W_EPS] != 0.0:     # out-of-round race (speed programme): weight_table.oval_push
            oval_push(wt, j, p, a, ad, Om, dOm, c, si, gjx, gjy, buf, ofp, oC, om, contact)
            continue
        ng = si * gjx - c * gjy
        Mr = H * ad + friction_moment(wt, j, y, m, l, psid, ad, c, si, gjx, gjy)
        if contact:
            Mr += buf[om + j]
        buf[oc + j], buf[os_ + j], buf[om + j] = c, si, Mr
        buf[ofp + 2 * p] += m * gjx + m * l * psid * psid * c - k2 * ng * si - m * l * Mr / J * si
        buf[ofp + 2 * p + 1] += m * gjy + m * l * psid * psid * si + k2 * ng * c + m * l * Mr / J * c
        oc4 = oC + 4 * p
        buf[oc4] += m - k2 * si * si
        buf[oc4 + 1] += k2 * si * c
        buf[oc4 + 2] += k2 * si * c
        buf[oc4 + 3] += m - k2 * c * c
        Js = wt[j, W_JS]
        if Js != 0.0:   # rolling ball: + J_s phi'' in its row, the reaction on the rotor
            r = m * l * Js / J
            buf[ofp + 2 * p] += r * dOm * si
            buf[ofp + 2 * p + 1] -= r * dOm * c
            if free:
                buf[ob + 2 * p] -= r * si
                buf[ob + 2 * p + 1] += r * c
                buf[og + 2 * p] -= r * si
                buf[og + 2 * p + 1] += r * c
                jp += Js * (1.0 - Js / J)
                fn -= Js / J * (m * l * ng + Mr)
    # body weights (stand.model.rotors.bodies_kernel): reaction F = R a + r on their plane point
    for bi in range(nb):
        rb = oB + bi * N_BCOL
        pl = int(sp[rb + B_PLANE])
        zx, zy = buf[otq + 2 * pl], buf[otq + 2 * pl + 1]
        zdx, zdy = buf[otqd + 2 * pl], buf[otqd + 2 * pl + 1]
        if free:
            # the reaction's part proportional to phi'' (LAG), and the drag moments about
            # the shaft that act back on the rotor
            body_reaction(sp, rb, y, wref, Om, 1.0, gx, gy, zx, zy, zdx, zdy, buf, oR)
            d4, d5 = buf[oR + 4], buf[oR + 5]
            body_reaction(sp, rb, y, wref, Om, 0.0, gx, gy, zx, zy, zdx, zdy, buf, oR)
            buf[ob + 2 * pl] -= d4 - buf[oR + 4]
            buf[ob + 2 * pl + 1] -= d5 - buf[oR + 5]
            fn += body_spin_moment(sp, rb, y, wref, Om)
        else:
            body_reaction(sp, rb, y, wref, Om, dOm, gx, gy, zx, zy, zdx, zdy, buf, oR)
        for k in range(4):
            buf[oC + 4 * pl + k] -= buf[oR + k]
        buf[ofp + 2 * pl] += buf[oR + 4]
        buf[ofp + 2 * pl + 1] += buf[oR + 5]
    if free:
        for j in range(nw):
            fn += buf[om + j]       # the weights' drag and friction act back on the rotor
        fn += drive_moment(tau / wref, phi, Om, sp) - sp[H_H0] * Om
    if sp[H_FAST] != 0.0:
        dOm_free = solve_planes(sp, buf, n, npl, int(sp[H_OMI]), int(sp[H_KMI]), oT, oTr,
                                int(sp[H_OW]), int(sp[H_OSS]), of, ofp, oC, oA, ou, ox, otx, free,
                                ob, og, fn, jp)
    else:
        dOm_free = solve_general(sp, buf, n, npl, int(sp[H_OM]), oT, oTr, int(sp[H_OF]), of, ofp, oC,
                                 oA, ox, otx, free, ob, og, fn, jp)
    if free:
        dOm = dOm_free
        dy[ifree] = y[ifree + 1]
        dy[ifree + 1] = dOm / (wref * wref)
    x, dq, dqd = buf[ox:ox + n], dy[:n], dy[ns:ns + n]
    w2 = wref * wref
    for i in range(n):
        dq[i] = yqd[i]
        dqd[i] = x[i] / (w2 * Ls[i])
    for bi in range(nb):
        rb = oB + bi * N_BCOL
        pl = int(sp[rb + B_PLANE])
        body_derivatives(sp, rb, y, dy, wref, Om, dOm, gx, gy, buf[otq + 2 * pl],
                         buf[otq + 2 * pl + 1], buf[otqd + 2 * pl], buf[otqd + 2 * pl + 1],
                         buf[otx + 2 * pl], buf[otx + 2 * pl + 1])
    for j in range(nw):
        p = int(wt[j, W_PLANE])
        apx, apy = buf[otx + 2 * p], buf[otx + 2 * p + 1]
        ml = wt[j, W_M] * wt[j, W_L]
        gjx, gjy = gx, gy
        if wt[j, W_ER] != 0.0:
            gjx, gjy = race_gravity(wt, j, phi, Om, dOm, gx, gy)
        if wt[j, W_EPS] != 0.0:
            psidd = oval_accel(wt, j, y[n + j], wref * y[ns + n + j], phi, Om, dOm, apx, apy, gjx, gjy,
                               buf[om + j])
        else:
            psidd = (ml * (buf[os_ + j] * (apx - gjx) - buf[oc + j] * (apy - gjy)) - buf[om + j]
                     + wt[j, W_JS] * dOm) / wt[j, W_J]
        dy[n + j] = y[ns + n + j]
        dy[ns + n + j] = (psidd - dOm) / (wref * wref)
        iz = int(wt[j, W_Z])
        if iz >= 0:   # adhesion (sticking after a dwell), stand.model.balancers.friction
            z = y[iz]
            sl = math.exp(-(wref * y[ns + n + j] / wt[j, W_VS]) ** 2)
            dy[iz] = (sl * (1.0 - z) / wt[j, W_TD] - (1.0 - sl) * z / wt[j, W_TR]) / wref


def scratch_size(n: int, nw: int, npl: int, free: bool) -> int:
    """Length of :func:`rhs_generic`'s scratch block, the last of ``sp``: q, q', the right-hand
    side and solution (n + free each), the (n + free)^2 matrix, cos, sin, moment of each point
    weight, a body reaction (6); in the planes' space (2P = 2 x npl): T q, T q', f_p, C (2 x 2P),
    b, gamma, T x, the 2P x (2P + 2) system; u (n).  The RHS writes there instead of
    allocating: one thread at a time per ``sp`` (copy it to share a model)."""
    ld = n + int(free)
    m2 = 2 * npl
    return 3 * n + 2 * ld + ld * ld + 3 * nw + 6 + 8 * m2 + m2 * (m2 + 2)


@dataclass(frozen=True)
class CoupledModel:
    """Packed arrays for :func:`rhs_generic` plus the scales to undo them."""

    rotor: LinearRotor
    weights: tuple
    plane_names: tuple
    sp: np.ndarray
    wt: np.ndarray
    prog: np.ndarray
    omega_ref: float
    scale: np.ndarray      # per rotor coordinate [m or rad per unit state]
    bodies: tuple = ()     #: PlaneBody weights (stand.model.rotors.bodies)
    bt: np.ndarray = field(default_factory=lambda: np.zeros((0, N_BCOL)))   #: packed rows
    n_body_states: int = 0
    free: bool = False     #: torque drive: the rotor angle and speed are the last two states

    @property
    def n(self) -> int:
        return self.rotor.n

    @property
    def nw(self) -> int:
        return int(self.wt.shape[0])

    @property
    def n_adhesion(self) -> int:
        """Extra states: one adhesion variable per sticking weight (after the 2(n + nw))."""
        return int(np.count_nonzero(self.wt[:, W_Z] >= 0)) if self.wt.size else 0

    # the model protocol of stand.integrate.driver
    kind = 1                 #: stand.model.kernels.GENERIC
    #: blows to the housing: rows (tau, jump of the scaled state) (stand.integrate.driver)
    impulses = None

    @property
    def omega_1(self) -> float:
        """Time scale [rad/s] (tau = omega_ref t)."""
        return self.omega_ref

    @property
    def size(self) -> int:
        return 2 * (self.n + self.nw) + self.n_adhesion + self.n_body_states + 2 * self.free

    @property
    def i_phi(self) -> int:
        """Index of the rotor angle phi [rad] in the state (torque drive; Omega / omega_ref
        follows it); ``None`` under a speed programme."""
        return int(self.sp[H_FREE]) if self.free else None

    @property
    def first_body_state(self) -> int:
        return 2 * (self.n + self.nw) + self.n_adhesion

    def angle_mask(self) -> np.ndarray:
        """True for the weights' angles (error scale capped at pi)."""
        from stand.model.rotors.bodies_kernel import B_KIND, B_OFF, TILT

        mask = np.zeros(self.size, bool)
        mask[self.n:self.n + self.nw] = True
        for row in self.bt:
            if int(row[B_KIND]) == TILT:
                mask[int(row[B_OFF]):int(row[B_OFF]) + 2] = True
        if self.free:
            mask[self.i_phi] = True
        return mask

    def breakpoints(self) -> np.ndarray:
        """Dimensionless times where the programme's acceleration jumps."""
        pts = [np.zeros(0) if self.free else np.asarray(self.prog[1:, 0], float)]
        if self.impulses is not None:
            pts.append(np.asarray(self.impulses[:, 0], float))
        pts = np.concatenate(pts)
        return np.unique(pts[(pts > 0.0) & np.isfinite(pts)])


def _positive(name, v, unit):
    v = float(v)
    if not (math.isfinite(v) and v > 0):
        raise ValueError(f"{name} = {v!r}: must be > 0 ({unit})")
    return v


def build_model(rotor: LinearRotor, weights: Sequence, programme,
                omega_ref: Optional[float] = None, bodies: Sequence[PlaneBody] = (),
                inertia: Optional[float] = None) -> CoupledModel:
    """Pack a rotor, its weights and a speed programme for the compiled RHS.

    Parameters
    ----------
    rotor : LinearRotor
    weights : sequence of plane weights
        Weights per plane (any number of planes, any number of weights): objects with
        ``plane``, ``balancer`` and ``friction``, as :class:`stand.scene.model.PlaneWeights`.
    programme : array (k, 2) or TorqueDrive
        Speed programme ``[[t_s, omega_rad_s], ...]``, piecewise linear, held
        after the last node; or a torque drive (:class:`stand.scene.model.TorqueDrive`):
        the rotor angle and speed become states (module docstring).
    omega_ref : float, optional
        Time scale [rad/s]; default the lowest natural frequency at rest.
    bodies : sequence of PlaneBody, optional
        Body weights (two-axis pendulums, coupled pairs, dampers, liquids;
        :mod:`stand.model.rotors.bodies`); their states follow the point weights'.
    inertia : float, optional
        Torque drive: the rotor's polar moment of inertia J_p about the shaft [kg m^2]
        (default ``programme.inertia``); required then.
    """
    names = tuple(rotor.planes)
    for w in tuple(weights) + tuple(bodies):
        if w.plane not in rotor.planes:
            raise ValueError(f"weights: plane {w.plane!r} is not a plane of rotor {rotor.name!r} "
                             f"(planes: {', '.join(names)})")
    drive = None
    if getattr(programme, "kind", None) == "torque":
        drive = programme
        if inertia is None:
            inertia = getattr(drive, "inertia", None)
        if inertia is None:
            raise ValueError("torque drive: the rotor's polar moment of inertia (inertia, "
                             "kg m^2) is required")
        inertia = _positive("drive.inertia", inertia, "kg m^2")
        if drive.model not in DRIVE_MODELS:
            raise ValueError(f"drive.model = {drive.model!r}: one of {', '.join(DRIVE_MODELS)}")
        programme = [[0.0, max(abs(float(drive.initial_speed)), abs(float(drive.target_speed)))]]
    prog_si = np.atleast_2d(np.asarray(programme, dtype=float))
    if prog_si.ndim != 2 or prog_si.shape[1] != 2 or not np.all(np.isfinite(prog_si)) \
            or np.any(np.diff(prog_si[:, 0]) <= 0) or prog_si[0, 0] < 0:
        raise ValueError("programme: expected rows [t_s, omega_rad_s] with increasing times >= 0 (s)")
    if omega_ref is None:
        wn = rotor.natural_frequencies(0.0)
        wn = wn[wn > 0]
        omega_ref = float(wn[0]) if wn.size else 1.0
    omega_ref = _positive("omega_ref", omega_ref, "rad/s")
    n = rotor.n
    rows = []
    cap = 0.0
    nw_total = sum(w.balancer.count for w in weights)
    n_adh = 0
    nxt = {}
    for w in weights:
        b = w.balancer
        p = names.index(w.plane)
        H = b.moment_drag
        Js = getattr(b, "spin_inertia", np.zeros(b.count))
        r_ball = float(getattr(b, "ball_radius", 0.0))
        race = race_columns(b, w.plane, drive is not None, w.friction)
        if r_ball > 0.0:        # neighbours in the race, in the order of the initial angles
            order = len(rows) + np.argsort(np.mod(b.initial_angles, 2.0 * math.pi), kind="stable")
            nxt.update(zip(order[:-1], order[1:]))
            if b.count > 2:
                nxt[order[-1]] = order[0]
        fr = w.friction
        for k in range(b.count):
            m = _positive(f"weights[{w.plane}].mass[{k}]", b.mass[k], "kg")
            l = _positive(f"weights[{w.plane}].radius[{k}]", b.radius[k], "m")
            J = _positive(f"weights[{w.plane}].inertia[{k}]", b.inertia[k], "kg m^2")
            row = [p, m, l, J, float(H[k]), 0.0, 0.0, 1.0, 1.0, 1.0, -1.0, float(Js[k]),
                   r_ball, getattr(b, "contact_stiffness", 0.0), getattr(b, "contact_damping", 0.0),
                   -1.0] + race
            if fr is not None:
                row[W_MUK:W_TR + 1] = [fr.kinetic, fr.static, fr.slip_speed, fr.dwell_time,
                                       fr.release_time]
                if fr.sticks:
                    row[W_Z] = 2 * (n + nw_total) + n_adh
                    n_adh += 1
            rows.append(row)
            cap += m * l
    wt = np.array(rows, dtype=float).reshape(-1, N_WCOL)
    for j, k in nxt.items():
        wt[j, W_NEXT] = k
    # coordinate scales: the high-speed response to the larger of the capacity
    # and the unbalance, per coordinate (floor 1e-3 of the largest)
    cap += sum(b.body.capacity for b in bodies)
    s_ref = max(cap, sum(abs(u.s) for u in rotor.unbalances), 1e-12)
    Minv = np.linalg.inv(rotor.M)
    resp = np.zeros(n)
    for T in rotor.planes.values():
        resp = np.maximum(resp, np.abs(Minv @ T.T).max(axis=1) * s_ref)
    scale = np.maximum(resp, 1e-3 * resp.max()) if resp.max() > 0 else np.ones(n)
    ub = np.array([[names.index(u.plane), u.s, u.angle] for u in rotor.unbalances],
                  dtype=float).reshape(-1, 3)
    parts = [rotor.M.ravel(), rotor.G.ravel(), rotor.D.ravel(), rotor.K.ravel(),
             np.concatenate([rotor.planes[p].ravel() for p in names]), ub.ravel(), scale,
             rotor.gravity, rotor.gravity_plane,
             np.concatenate([rotor.force_map(p).ravel() for p in names])]
    length = float(np.max(np.abs(np.concatenate([rotor.planes[p] for p in names], axis=0))
                          @ scale)) or 1.0
    bt, nbs = body_rows(bodies, names, 2 * (n + wt.shape[0]) + n_adh, length)
    parts.append(bt.ravel())
    head = np.zeros(N_HEAD)
    head[H_N], head[H_NW], head[H_NPL], head[H_NUB], head[H_WREF] = n, wt.shape[0], len(names), \
        ub.shape[0], omega_ref
    off = N_HEAD
    head[H_NB] = bt.shape[0]
    head[H_CONTACT] = float(bool(nxt))
    if drive is not None:
        head[H_FREE] = 2 * (n + wt.shape[0]) + n_adh + nbs
        head[H_JP], head[H_DMODEL] = inertia, DRIVE_MODELS[drive.model]
        head[H_TQ], head[H_C1], head[H_C2] = drive.torque, drive.c1, drive.c2
        head[H_WT], head[H_H0] = drive.target_speed, drive.rotor_drag
        head[H_W0] = drive.initial_speed
    T_all = np.concatenate([rotor.planes[p] for p in names], axis=0)
    F_all = np.concatenate([rotor.force_map(p) for p in names], axis=0)
    Minv_p, head[H_KMI], W, S = plane_parts(np.asarray(rotor.M, float), T_all, F_all)
    parts += [Minv_p.ravel(), W.ravel(), S.ravel(), row_ranges(T_all)]
    head[H_KK], head[H_KD], head[H_KG] = (matrix_kind(np.asarray(a, float))
                                          for a in (rotor.K, rotor.D, rotor.G))
    # the planes' space pays when it is smaller than the rotor's (coupled_solve)
    head[H_FAST] = float(2 * len(names) < n)
    for slot, a in zip((H_OM, H_OG, H_OD, H_OK, H_OT, H_OUB, H_OL, H_OGR, H_OGP, H_OF, H_OB,
                        H_OMI, H_OW, H_OSS, H_OTR), parts):
        head[slot] = off
        off += a.size
    head[H_OS] = off
    parts.append(np.zeros(scratch_size(n, wt.shape[0], len(names), drive is not None)))
    sp = np.concatenate([head] + parts)
    prog = build_table(prog_si[:, 0] * omega_ref, prog_si[:, 1] / omega_ref)
    return CoupledModel(rotor, tuple(weights), names, sp, wt, prog, omega_ref, scale,
                        tuple(bodies), bt, nbs, drive is not None)


