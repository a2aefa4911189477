"""Planar rotor with n weights: the corrected equations of motion, fixed frame.

Dimensionless form of the corrected (5.4), (5.7), (5.10) (digest ch5 sections
0.2 and 2.3; equivalently the corrected (5.16) for non-identical weights).
Time tau = omega_1 t, displacements xi = x/L, eta = y/L (L = r* with weights),
' = d/dtau, phi the angle of the rotor's reference mark, phi + beta the angle of
its heavy side, phi_j = phi + alpha_j the weights' absolute angles::

    xi''  + d11 xi' + d12 eta' + k11 xi + k12 eta
          = sum eps_j (phi_j'' sin phi_j + phi_j'^2 cos phi_j)
            + eps0 (phi'' sin(phi+beta) + phi'^2 cos(phi+beta))
    eta'' + d21 xi' + d22 eta' + k21 xi + k22 eta
          = sum eps_j (phi_j'^2 sin phi_j - phi_j'' cos phi_j)
            + eps0 (phi'^2 sin(phi+beta) - phi'' cos(phi+beta))
    phi_j'' + h_j (phi_j' - phi') - mu_j (xi'' sin phi_j - eta'' cos phi_j) = 0
    phi''   + h0 phi' + sum nu_j (phi' - phi_j')
            - mu0 (xi'' sin(phi+beta) - eta'' cos(phi+beta)) = m_rot   (free rotor)

Rolling balls add ``- rho_j phi''`` to their row and ``+ kappa_j (phi'' - phi_j'')`` to the
rotor's (their spin inertia on the angle relative to the rotor, :mod:`stand.model.weights`).

The signs are the corrected ones: '+phi_j'^2 cos' in the xi equation (printed
'-' in (5.16)-(5.36)), '+Me(...)' in the y equation (printed '-' in (5.7)), and
the drag reaction nu_j = H_j/(omega_1 J_0) (printed inverted in (5.16)).

The equations are linear in the accelerations and the weights couple only
through the shaft: eliminating phi_j'' leaves a 2x2 (3x3 with a free rotor)
Schur complement, so one right-hand-side evaluation costs O(n).  The state is
``[xi, eta, alpha_1..alpha_n, (phi), xi', eta', alpha_1'..alpha_n', (phi')]``
with weight angles relative to the rotor, so that a balanced weight has a
bounded state whatever the number of revolutions.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from stand._jit import njit
from stand.model.programme import (build_table, breakpoints, drive_torque_law, programme_kinematics,
                        programme_kinematics_many, rotor_kinematics, row_before)
from stand.model.structure import PlanarStructure
from stand.model.weights import EPS, H, KAPPA, MU, NU, RHO, weight_table

# layout of the scalar parameter vector ``sp``
D11, D12, D21, D22, K11, K12, K21, K22 = range(8)
EPS0, BETA, MU0, H0, FREE, MODEL, MROT, C1, C2, WTARGET = range(8, 18)
COAST_T0, COAST_T, COAST_R0, COAST_PHI0 = range(18, 22)
N_PROG, N_UB, N_FORCE = range(22, 25)  # row counts of the blocks of the table ``prog``
UX0, UY0 = range(25, 27)  # EPS0 (cos BETA, sin BETA), written with them (no trig per RHS call)
N_SP = 27
TABLE_COLUMNS = 6
DRIVE_MODELS = {"constant": 0, "speed_feedback": 1, "angle_feedback": 2}


@dataclass(frozen=True)
class PlanarModel:
    """Everything the compiled right-hand side needs, plus the SI scales.

    Attributes
    ----------
    n : int               number of weights
    free : bool           rotor speed is a state (torque drive)
    sp : ndarray          scalar parameters (layout constants above)
    wt : ndarray (n, 4)   weight table, :func:`stand.model.weights.weight_table`
    prog : ndarray (k, 6)
        One table, three blocks of rows (counts in ``sp[N_PROG]``, ``sp[N_UB]``,
        ``sp[N_FORCE]``): the speed programme ``[tau, R, phi]`` (prescribed
        speed); the unbalance programme ``[tau, u_x, u_y]`` (rotor frame, units
        of M_Sigma L, piecewise linear; empty = constant); side-force windows
        ``[tau_on, tau_off, f_x, f_y, k_x, k_y]`` (units of M_Sigma omega_1^2 L
        and M_Sigma omega_1^2).
    impulses : ndarray (m, 3)
        Blows to the housing: ``[tau, dxi', deta']`` shaft velocity jumps.
    omega_1 : float       time scale [rad/s]
    length : float        length scale L [m]
    structure : PlanarStructure
    """

    n: int
    free: bool
    sp: np.ndarray
    wt: np.ndarray
    prog: np.ndarray
    omega_1: float
    length: float
    structure: PlanarStructure
    impulses: np.ndarray = None

    # the model protocol of stand.integrate.driver
    kind = 0                 #: stand.model.kernels.PLANAR

    @property
    def numpy_rhs(self):
        """The pure-numpy right-hand side (full linear solve): the ``numpy-DOP853`` check path."""
        return rhs_planar_numpy

    @property
    def nq(self) -> int:
        return 2 + self.n + (1 if self.free else 0)

    @property
    def size(self) -> int:
        return 2 * self.nq

    def breakpoints(self) -> np.ndarray:
        """Dimensionless times where the prescribed acceleration jumps."""
        npg, nub, nf = (int(self.sp[k]) for k in (N_PROG, N_UB, N_FORCE))
        pts = [np.asarray(self.prog[npg:npg + nub, 0], float),
               np.asarray(self.prog[npg + nub:npg + nub + nf, :2], float).ravel()]
        if not self.free:
            pts.append(breakpoints(self.prog[:npg], self.sp[COAST_T0]))
        if self.impulses is not None:
            pts.append(np.asarray(self.impulses[:, 0], float))
        pts = np.concatenate(pts)
        return np.unique(pts[(pts > 0.0) & np.isfinite(pts)])

    def angle_mask(self) -> np.ndarray:
        """True for state components that are angles (error scale capped)."""
        mask = np.zeros(self.size, bool)
        mask[2:self.nq] = True
        return mask

    def rotor(self, tau: np.ndarray, y: np.ndarray):
        """Rotor angle [rad] and dimensionless speed at samples ``tau``."""
        if self.free:
            return y[:, self.nq - 1], y[:, 2 * self.nq - 1]
        return rotor_kinematics_many(np.asarray(tau, float), self.prog[:int(self.sp[N_PROG])], self.sp)


def build_planar_model(scene) -> PlanarModel:
    """Make the dimensionless model of a scene."""
    st = PlanarStructure.from_scene(scene)
    w1 = st.natural_frequency
    L = scene.length_scale
    Ms = st.total_mass
    free = scene.drive.kind == "torque"
    J0 = st.rotor_inertia if free else None
    sp = np.zeros(N_SP)
    Dn = st.damping / (w1 * Ms)
    Kn = st.stiffness / (Ms * w1 ** 2)
    sp[D11], sp[D12], sp[D21], sp[D22] = Dn.ravel()
    sp[K11], sp[K12], sp[K21], sp[K22] = Kn.ravel()
    sp[EPS0] = st.unbalance / (Ms * L)
    sp[BETA] = st.unbalance_angle
    sp[UX0] = sp[EPS0] * math.cos(sp[BETA])
    sp[UY0] = sp[EPS0] * math.sin(sp[BETA])
    sp[COAST_T0] = np.inf
    sp[COAST_T] = 1.0
    d = scene.drive
    if free:
        sp[FREE] = 1.0
        sp[MU0] = Ms * L * L / J0  # times the unbalance vector (units of M_Sigma L): M e L / J0
        sp[H0] = d.rotor_drag / (w1 * J0)
        sp[MODEL] = DRIVE_MODELS[d.model]
        sp[MROT] = d.torque / (J0 * w1 ** 2)
        sp[C1] = d.c1 / (J0 * w1)
        sp[C2] = d.c2 / (J0 * w1 ** 2)
        sp[WTARGET] = d.target_speed / w1
        prog = np.zeros((1, 3))
    else:
        pr = np.asarray(d.programme, float)
        prog = build_table(pr[:, 0] * w1, pr[:, 1] / w1)
        prog[:, 2] += d.initial_angle
        if d.coast_down_start is not None:
            tc = d.coast_down_start * w1
            phic, Rc, _ = programme_kinematics(tc, prog, prog.shape[0])
            sp[COAST_T0] = tc
            sp[COAST_T] = d.coast_down_time_constant * w1
            sp[COAST_R0] = Rc
            sp[COAST_PHI0] = phic
    wt = weight_table(scene.balancer, Ms, L, w1, J0)
    ub, forces, impulses = perturbation_tables(scene, Ms, L, w1)
    blocks = [prog, ub, forces]
    sp[N_PROG], sp[N_UB], sp[N_FORCE] = (b.shape[0] for b in blocks)
    table = np.zeros((sum(b.shape[0] for b in blocks), TABLE_COLUMNS))
    r = 0
    for b in blocks:
        table[r:r + b.shape[0], :b.shape[1]] = b
        r += b.shape[0]
    return PlanarModel(n=scene.balancer.count, free=free, sp=sp, wt=wt, prog=table,
                       omega_1=w1, length=L, structure=st, impulses=impulses)


def rotor_unbalance(scene, t: np.ndarray) -> np.ndarray:
    """The rotor's unbalance M e e^{i beta} [kg*m] at times ``t`` [s], rotor frame,
    following the scene's unbalance changes (piecewise linear; a discrete change
    takes effect at its time)."""
    t = np.asarray(t, float)
    u0 = scene.rotor.unbalance * np.exp(1j * scene.rotor.unbalance_angle)
    Ms, L, w1 = scene.total_mass, scene.length_scale, scene.natural_frequency
    ub, _, _ = perturbation_tables(scene, Ms, L, w1)
    if ub.shape[0] == 0:
        return np.full(t.shape, u0, complex)
    tau = t * w1
    out = np.empty(t.shape, complex)
    for k, tk in np.ndenumerate(tau):
        i = np.searchsorted(ub[:, 0], tk, side="right") - 1
        if i < 0:
            z = ub[0, 1] + 1j * ub[0, 2]
        elif i >= ub.shape[0] - 1:
            z = ub[-1, 1] + 1j * ub[-1, 2]
        else:
            f = (tk - ub[i, 0]) / (ub[i + 1, 0] - ub[i, 0])
            z = (ub[i, 1] + 1j * ub[i, 2]) * (1 - f) + (ub[i + 1, 1] + 1j * ub[i + 1, 2]) * f
        out[k] = z * Ms * L
    return out


def perturbation_tables(scene, Ms: float, L: float, w1: float):
    """Dimensionless tables of the scene's perturbations (tables 4.5-4.6 of the book).

    Returns the unbalance programme ``[tau, u_x, u_y]`` (empty when the
    unbalance never changes), side-force windows and impulses.
    """
    per = getattr(scene, "perturbations", ()) or ()
    u = scene.rotor.unbalance * np.exp(1j * scene.rotor.unbalance_angle) / (Ms * L)
    nodes = []
    forces = []
    impulses = []
    for p in sorted(per, key=lambda p: p.start):
        if p.kind == "unbalance":
            nodes.append((p.start * w1, u))
            new = p.mass * p.eccentricity * np.exp(1j * p.unbalance_angle) if p.mass is not None else (
                scene.rotor.mass * p.eccentricity * np.exp(1j * p.unbalance_angle))
            u = new / (Ms * L)
            nodes.append(((p.start + p.duration) * w1, u))
        elif p.kind == "side_force":
            f = 1.0 / (Ms * w1 ** 2 * L)
            k = 1.0 / (Ms * w1 ** 2)
            forces.append((p.start * w1, p.end * w1 if np.isfinite(p.end) else np.inf,
                           p.force_x * f, p.force_y * f, p.stiffness_x * k, p.stiffness_y * k))
        elif p.kind == "impulse":
            impulses.append((p.start * w1, p.velocity_x / (L * w1), p.velocity_y / (L * w1)))
    ub = np.array([(t, z.real, z.imag) for t, z in nodes]).reshape(-1, 3)
    return ub, np.array(forces).reshape(-1, 6), np.array(impulses).reshape(-1, 3)


def initial_state(scene, model: PlanarModel) -> np.ndarray:
    """Dimensionless initial state from the scene's initial conditions."""
    nq, n, L, w1 = model.nq, model.n, model.length, model.omega_1
    y = np.zeros(2 * nq)
    ini = scene.initial
    y[0], y[1] = ini.x / L, ini.y / L
    y[nq], y[nq + 1] = ini.vx / (L * w1), ini.vy / (L * w1)
    if n:
        y[2:2 + n] = scene.balancer.initial_angles
        y[nq + 2:nq + 2 + n] = np.asarray(scene.balancer.initial_speeds, float) / w1
    if model.free:
        y[2 * nq - 1] = scene.drive.initial_speed / w1
    return y


@njit(cache=True, error_model="numpy", inline="always")
def unbalance_vector(tau, phi, sp, table, start):
    """Rotor unbalance in the fixed frame, w = e^{i phi} u, and w' = e^{i phi} du/dtau.

    u is the unbalance vector in the rotor frame (units of M_Sigma L): constant
    ``eps0 e^{i beta}`` or the piecewise-linear unbalance programme.
    """
    nub = int(sp[N_UB])
    if nub == 0:
        ux = sp[UX0]
        uy = sp[UY0]
        dux = 0.0
        duy = 0.0
    else:
        ub = table[start:start + nub]
        if tau < ub[0, 0]:
            ux, uy, dux, duy = ub[0, 1], ub[0, 2], 0.0, 0.0
        elif tau >= ub[nub - 1, 0]:
            ux, uy, dux, duy = ub[nub - 1, 1], ub[nub - 1, 2], 0.0, 0.0
        else:
            i = row_before(ub, tau, nub)
            dt = ub[i + 1, 0] - ub[i, 0]
            dux = (ub[i + 1, 1] - ub[i, 1]) / dt
            duy = (ub[i + 1, 2] - ub[i, 2]) / dt
            ux = ub[i, 1] + dux * (tau - ub[i, 0])
            uy = ub[i, 2] + duy * (tau - ub[i, 0])
    c = math.cos(phi)
    s = math.sin(phi)
    return c * ux - s * uy, s * ux + c * uy, c * dux - s * duy, s * dux + c * duy


@njit(cache=True, inline="always", error_model="numpy")
def side_forces(tau, xi, eta, sp, table, start):
    """Sum of the active side-force windows on the shaft: f - k (xi, eta)."""
    fx = 0.0
    fy = 0.0
    for r in range(start, start + int(sp[N_FORCE])):
        if table[r, 0] <= tau < table[r, 1]:
            fx += table[r, 2] - table[r, 4] * xi
            fy += table[r, 3] - table[r, 5] * eta
    return fx, fy


def rotor_kinematics_many(tau, prog, sp):
    """Rotor angle and speed (phi, phi') of the prescribed programme with its coast-down at
    many times, in numpy (the compiled kernels use :func:`rotor_kinematics`)."""
    tau = np.asarray(tau, dtype=float)
    kin = programme_kinematics_many(tau, prog)
    phi, R = kin[:, 0].copy(), kin[:, 1].copy()
    t0, T, R0, phi0 = sp[COAST_T0], sp[COAST_T], sp[COAST_R0], sp[COAST_PHI0]
    coast = tau >= t0
    if coast.any():
        ex = np.exp(-(tau[coast] - t0) / T)
        R[coast] = R0 * ex
        phi[coast] = phi0 + R0 * T * (1.0 - ex)
    return phi.reshape(tau.shape), R.reshape(tau.shape)


@njit(cache=True, inline="always", error_model="numpy")
def drive_torque(tau, phi, dphi, sp):
    """Dimensionless drive torque m_rot = M_rot / (J_0 omega_1^2), models 1-3."""
    return drive_torque_law(sp[MODEL], sp[MROT], sp[C1], sp[C2], sp[WTARGET], tau, phi, dphi)


# compiled once, on its own (cached), and inlined by LLVM into each calling loop: numba's IR
# inlining (inline="always") typed and lowered it again for every caller's set of flags
@njit(cache=True, forceinline=True, error_model="numpy", _nrt=False)
def rhs_planar(tau, y, dy, sp, wt, prog):
    """Right-hand side, O(n): writes dy/dtau into ``dy``."""
    n = wt.shape[0]
    free = sp[FREE] != 0.0
    nq = 2 + n + (1 if free else 0)
    xi = y[0]
    eta = y[1]
    dxi = y[nq]
    deta = y[nq + 1]
    npg = int(sp[N_PROG])
    if free:
        phi = y[nq - 1]
        dphi = y[2 * nq - 1]
        ddphi = 0.0
    else:
        phi, dphi, ddphi = rotor_kinematics(tau, prog, npg, sp[COAST_T0], sp[COAST_T],
                                            sp[COAST_R0], sp[COAST_PHI0])
    # rotor unbalance in the fixed frame (w) and its rate of change (v)
    wx, wy, vx, vy = unbalance_vector(tau, phi, sp, prog, npg)
    fx, fy = side_forces(tau, xi, eta, sp, prog, npg + int(sp[N_UB]))
    w2 = dphi * dphi
    # forces on the shaft that do not depend on the unknown accelerations
    b1 = (-(sp[D11] * dxi + sp[D12] * deta + sp[K11] * xi + sp[K12] * eta)
          + w2 * wx + 2.0 * dphi * vy + fx)
    b2 = (-(sp[D21] * dxi + sp[D22] * deta + sp[K21] * xi + sp[K22] * eta)
          + w2 * wy - 2.0 * dphi * vx + fy)
    a11 = 1.0
    a12 = 0.0
    a22 = 1.0
    b3 = 0.0
    # rolling balls (rho_j, kappa_j != 0): sum eps rho (sin, cos) phi_j, the rotor row's
    # sum kappa mu (sin, cos) phi_j and its phi'' coefficient
    sr = 0.0
    cr = 0.0
    k1 = 0.0
    k2 = 0.0
    a33 = 1.0
    for j in range(n):
        aj = phi + y[2 + j]
        da = y[nq + 2 + j]
        wj = dphi + da
        sj = math.sin(aj)
        cj = math.cos(aj)
        e = wt[j, EPS]
        em = e * wt[j, MU]
        g = -wt[j, H] * da
        # keep sin/cos for the second pass in the output slots not yet written
        dy[2 + j] = sj
        dy[nq + 2 + j] = cj
        a11 -= em * sj * sj
        a12 += em * sj * cj
        a22 -= em * cj * cj
        b1 += e * (wj * wj * cj + sj * g)
        b2 += e * (wj * wj * sj - cj * g)
        b3 += wt[j, NU] * da
        rho = wt[j, RHO]
        if rho != 0.0:
            sr += e * rho * sj
            cr += e * rho * cj
            kap = wt[j, KAPPA]
            k1 += kap * wt[j, MU] * sj
            k2 += kap * wt[j, MU] * cj
            a33 += kap * (1.0 - rho)
            b3 += kap * g
    if free:
        # 3x3 Schur complement: unknowns (xi'', eta'', phi'')
        a13 = -wy - sr
        a23 = wx + cr
        mu0 = sp[MU0]
        a31 = (-mu0 * wy - k1) / a33
        a32 = (mu0 * wx + k2) / a33
        b3 = (b3 + drive_torque(tau, phi, dphi, sp) - sp[H0] * dphi) / a33
        det = (a11 * (a22 - a23 * a32) - a12 * (a12 - a23 * a31)
               + a13 * (a12 * a32 - a22 * a31))
        x1 = (b1 * (a22 - a23 * a32) - a12 * (b2 - a23 * b3) + a13 * (b2 * a32 - a22 * b3)) / det
        x2 = (a11 * (b2 - a23 * b3) - b1 * (a12 - a23 * a31) + a13 * (a12 * b3 - b2 * a31)) / det
        ddphi = b3 - a31 * x1 - a32 * x2
    else:
        b1 += wy * ddphi
        b2 -= wx * ddphi
        b1 += sr * ddphi
        b2 -= cr * ddphi
        det = a11 * a22 - a12 * a12
        x1 = (b1 * a22 - a12 * b2) / det
        x2 = (a11 * b2 - a12 * b1) / det
    for j in range(n):
        sj = dy[2 + j]
        cj = dy[nq + 2 + j]
        ddj = -wt[j, H] * y[nq + 2 + j] + wt[j, MU] * (x1 * sj - x2 * cj) + wt[j, RHO] * ddphi
        dy[nq + 2 + j] = ddj - ddphi
    for i in range(nq):
        dy[i] = y[nq + i]
    dy[nq] = x1
    dy[nq + 1] = x2
    if free:
        dy[2 * nq - 1] = ddphi


def rhs_planar_numpy(tau, y, sp, wt, prog):
    """Reference right-hand side: the full (n+2)- or (n+3)-system by ``numpy.linalg.solve``.

    Same equations as :func:`rhs_planar` written literally (no elimination);
    used to check the compiled path and as the benchmark peer.
    """
    n = wt.shape[0]
    free = sp[FREE] != 0.0
    nq = 2 + n + (1 if free else 0)
    xi, eta, dxi, deta = y[0], y[1], y[nq], y[nq + 1]
    alpha, dalpha = y[2:2 + n], y[nq + 2:nq + 2 + n]
    npg = int(sp[N_PROG])
    if free:
        phi, dphi = y[nq - 1], y[2 * nq - 1]
        ddphi_known = None
    else:
        phi, dphi, ddphi_known = rotor_kinematics(tau, prog, npg, sp[COAST_T0], sp[COAST_T],
                                                  sp[COAST_R0], sp[COAST_PHI0])
    # unbalance d = e^{i phi} u(tau) (rotor frame u): -d'' = e^{i phi}(phi'^2 u - i phi'' u - 2 i phi' u')
    wx, wy, vx, vy = unbalance_vector(tau, phi, sp, prog, npg)
    fx, fy = side_forces(tau, y[0], y[1], sp, prog, npg + int(sp[N_UB]))
    pj = phi + alpha
    wj = dphi + dalpha
    s, c = np.sin(pj), np.cos(pj)
    eps, mu, hh, nu, rho, kap = wt[:, EPS], wt[:, MU], wt[:, H], wt[:, NU], wt[:, RHO], wt[:, KAPPA]
    m = n + 2 + (1 if free else 0)
    A = np.zeros((m, m))
    b = np.zeros(m)
    # unknowns: phi_1''..phi_n'', xi'', eta'', (phi'')
    A[np.arange(n), np.arange(n)] = 1.0
    A[np.arange(n), n] = -mu * s
    A[np.arange(n), n + 1] = mu * c
    b[:n] = -hh * dalpha
    A[n, :n] = -eps * s
    A[n, n] = 1.0
    b[n] = (-(sp[D11] * dxi + sp[D12] * deta + sp[K11] * xi + sp[K12] * eta)
            + np.sum(eps * wj ** 2 * c) + dphi ** 2 * wx + 2 * dphi * vy + fx)
    A[n + 1, :n] = eps * c
    A[n + 1, n + 1] = 1.0
    b[n + 1] = (-(sp[D21] * dxi + sp[D22] * deta + sp[K21] * xi + sp[K22] * eta)
                + np.sum(eps * wj ** 2 * s) + dphi ** 2 * wy - 2 * dphi * vx + fy)
    if free:
        A[n, n + 2] = -wy
        A[n + 1, n + 2] = wx
        A[n + 2, n] = -sp[MU0] * wy
        A[n + 2, n + 1] = sp[MU0] * wx
        A[n + 2, n + 2] = 1.0 + np.sum(kap)
        A[n + 2, :n] = -kap
        A[np.arange(n), n + 2] = -rho
        b[n + 2] = drive_torque(tau, phi, dphi, sp) - sp[H0] * dphi + np.sum(nu * dalpha)
    else:
        b[n] += wy * ddphi_known
        b[n + 1] -= wx * ddphi_known
        b[:n] += rho * ddphi_known
    acc = np.linalg.solve(A, b)
    ddphi = acc[n + 2] if free else ddphi_known
    dy = np.empty_like(y)
    dy[:nq] = y[nq:]
    dy[nq] = acc[n]
    dy[nq + 1] = acc[n + 1]
    dy[nq + 2:nq + 2 + n] = acc[:n] - ddphi
    if free:
        dy[2 * nq - 1] = ddphi
    return dy
