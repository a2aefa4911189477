"""The autobalancer-damper (ABD, book 7.2): one correction weight in spherical motion.

Digest ``ch7_ch1.md`` sections 0, 2, 5 and 6 (Filimonikhin 2004, section 7.2).

Physical model (digest 2.2)
---------------------------
The rotor of 7.1 (plane-parallel motion, isotropic supports ``c`` [N/m], external
viscous coefficient ``H2`` [N s/m], constant spin ``omega`` [rad/s]) carries one
correction weight (CW) of mass ``m`` [kg] that can turn in any way about a
suspension point on the rotor axis (cardan, sphere in a spherical cavity or a
ball joint).  The CW's centre of mass lies at distance ``l`` [m] from the point,
its inertia tensor about the point is spherical, ``A`` [kg m^2] (the book's
design rule), a viscous moment ``-H1 (w - omega e_z)`` [N m s] acts on its
angular velocity relative to the rotor, gravity ``g`` acts downwards along the
rotor axis.  5 DOF: shaft ``x, y`` and the three orientation angles.

Singularity-free formulation (replaces the Euler angles of (7.47))
------------------------------------------------------------------
The book writes the CW equations in Euler angles ``psi, phi, theta``, which are
singular at the neutral position ``phi = 0`` -- exactly where the weight rests.
Because the inertia tensor about the suspension point is spherical, the
angular momentum is ``A w`` in *any* frame, so the CW dynamics is Euler's law in
the inertial frame, and only the unit vector ``n`` from the suspension point to
the CW's centre of mass matters (the proper rotation ``theta`` is cyclic; its
rate is the component ``w . n``).  Dimensionless, with ``tau = omega0 t``::

    n'  = W x n  +  k_c (1 - |n|^2) n / 2          (constraint stabilisation)
    W'  = -R_g^2 n x e_z  -  n x a  -  h (W - R_omega e_z)  [+ friction]
    a   = z'' (the shaft acceleration as a horizontal 3-vector)
    z'' + H z' + z = -R_m (n_x + i n_y)'' + R_m R_omega^2 e0 e^{i(R_omega tau + gamma)}

``W`` is the absolute angular velocity in ``omega0`` units.  ``n' = W x n``
preserves ``|n| = 1`` exactly; the term ``k_c (1 - |n|^2) n / 2`` (default
``k_c = 1``) makes the unit sphere attracting for the integration error.  All
forces use ``n / |n|``.  Eliminating ``n''`` gives a 2x2 system for ``a`` solved
in closed form (Sherman-Morrison):
``[(1 - R_m) I + R_m n_h n_h^T] a_h = b``.

The relation to the book's angles: ``n = (-sin phi sin psi_a, sin phi cos psi_a,
-cos phi)`` with ``psi_a = psi + R_omega tau`` the absolute angle (``phi = 0``:
centre of mass straight below the point), and ``W = (psi' + R_omega) e_z +
phi' e_N + theta' e_3`` (``e_N = (cos psi_a, sin psi_a, 0)``, ``e_3 = -n``).
This reproduces the three CW equations of (7.47) (the digest checked them) and
the rotor equations of (7.47) with erratum E1 (``phi''``, ``psi''`` in the
braces).  The steady-motion equations (7.51)-(7.53) follow from it by hand
(torque balance ``n x (R_g^2 e_z - R_omega^2 Z) = 0`` gives (7.62), the rotor
equation then (7.53)); the test suite checks that every root of (7.53) is an
equilibrium of :func:`rhs_rotating` to 1e-12.

Dimensionless parameters (7.48)-(7.50)::

    omega0 = sqrt(c/M_Sigma),  rho = sqrt(A/m),  z = (x + i y) l / rho^2,
    R_m = m l^2/(M_Sigma rho^2),  R_omega = omega/omega0,  R_g^2 = g l/(rho^2 omega0^2),
    h = H1/(m rho^2 omega0),  H = H2/(M_Sigma omega0),  e0 = M e/(m l).

Dry friction (7.79)-(7.84), optional (:class:`DryFriction`)
-----------------------------------------------------------
A regularised Coulomb moment on the relative angular velocity
``W_r = W - R_omega e_z``::

    T_f = -R_f N W_r / sqrt(|W_r|^2 + eps^2),
    N   = |a + kappa n'' + R_g^2 e_z|     (the joint reaction / (m l omega0^2 ...))

where ``N`` is the dimensionless joint reaction force (``m`` times the
absolute acceleration of the CW's centre of mass minus gravity) and
``kappa = m l^2 / A`` (1 for a point-mass CW).  ``R_f = h_j f / (l sqrt(1 + f^2))``
(7.81) for a cardan or sphere, or the ball-joint law (7.84).  ``N`` depends on
the accelerations, which depend on ``T_f``: two fixed-point passes are made
(contraction factor about ``R_f``).  The regularisation ``eps`` turns perfect
sticking into a slow creep at relative rates ~ ``eps`` (use a small ``eps``
with ``method="LSODA"``: the regularised law is stiff); the quasi-static
residual unbalance of (7.80) is recovered when ``eps`` is small.  In (7.80) the
ratio ``R_m`` is ``m / M_Sigma`` -- equal to this module's ``R_m`` for
``kappa = 1``; :func:`residual_unbalance` takes it as an argument.

State vector (:func:`rhs`, fixed frame; :func:`rhs_rotating`, the same
quantities in rotating-frame components)::

    s = [x, y, x', y', n_x, n_y, n_z, W_x, W_y, W_z]
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

__all__ = [
    "DryFriction", "DamperParams", "DamperSteady", "rhs", "rhs_rotating", "make_rhs",
    "state_from_angles", "angles_from_state", "to_rotating", "to_fixed", "simulate",
    "steady_quartic_roots", "steady_motions", "efficiency", "efficiency_approx",
    "critical_speeds_undamped", "jacobian", "eigenvalues", "is_stable",
    "fast_rotor_roots", "stability_scan", "R_f_cardan", "R_f_ball_joint",
    "residual_parametric", "residual_unbalance", "residual_cubic", "residual_unbalance_now",
]


def _finite(name, value, unit):
    v = float(value)
    if not math.isfinite(v):
        raise ValueError(f"{name} must be a finite number [{unit}], got {value!r}")
    return v


def _nonneg(name, value, unit):
    v = _finite(name, value, unit)
    if v < 0.0:
        raise ValueError(f"{name} must be >= 0 [{unit}], got {value!r}")
    return v


def _pos(name, value, unit):
    v = _finite(name, value, unit)
    if v <= 0.0:
        raise ValueError(f"{name} must be > 0 [{unit}], got {value!r}")
    return v


# ---------------------------------------------------------------------------
# parameters
# ---------------------------------------------------------------------------

@dataclass(frozen=True)
class DryFriction:
    """Regularised Coulomb friction in the CW suspension (7.79)-(7.84).

    Parameters
    ----------
    R_f : float
        Friction ratio ``h_j f / (l sqrt(1+f^2))`` [-] (7.81), 0 <= R_f < 1.
    eps : float
        Regularisation rate [-] (relative angular speed in ``omega0`` units
        below which the moment grows linearly), > 0.
    kappa : float
        ``m l^2 / A`` [-] (1 for a point-mass CW), 0 < kappa <= 1.
    """

    R_f: float
    eps: float = 1e-3
    kappa: float = 1.0

    def __post_init__(self):
        object.__setattr__(self, "R_f", _nonneg("R_f", self.R_f, "dimensionless"))
        if self.R_f >= 1.0:
            raise ValueError(f"R_f must be < 1 [dimensionless] (7.81), got {self.R_f!r}")
        object.__setattr__(self, "eps", _pos("eps", self.eps, "dimensionless rate"))
        k = _pos("kappa", self.kappa, "dimensionless")
        if k > 1.0:
            raise ValueError(f"kappa = m l^2/A must be <= 1 [dimensionless], got {self.kappa!r}")
        object.__setattr__(self, "kappa", k)


@dataclass(frozen=True)
class DamperParams:
    """Dimensionless ABD parameters (7.48)-(7.49).

    Parameters
    ----------
    R_m : float
        ``m l^2/(M_Sigma rho^2)`` [-], 0 <= R_m < 1.
    R_omega : float
        Spin speed ``omega/omega0`` [-], >= 0.
    R_g : float
        Gravity parameter, ``R_g^2 = g l/(rho^2 omega0^2)`` [-], >= 0.
    h : float
        Relative viscous damping of the CW ``H1/(m rho^2 omega0)`` [-], >= 0.
    H : float
        External viscous damping ``H2/(M_Sigma omega0)`` [-], >= 0.
    e0 : float
        Unbalance in units of the capacity ``M e/(m l)`` [-], >= 0.
    gamma : float
        Unbalance angle in the rotor frame [rad].
    friction : DryFriction or None
        Optional dry friction in the suspension.
    k_c : float
        Constraint-stabilisation rate for ``|n| = 1`` [-], >= 0.
    """

    R_m: float
    R_omega: float
    R_g: float = 0.3
    h: float = 0.3
    H: float = 0.3
    e0: float = 0.0
    gamma: float = 0.0
    friction: DryFriction | None = None
    k_c: float = 1.0

    def __post_init__(self):
        for name in ("R_m", "R_omega", "R_g", "h", "H", "e0", "k_c"):
            object.__setattr__(self, name, _nonneg(name, getattr(self, name), "dimensionless"))
        object.__setattr__(self, "gamma", _finite("gamma", self.gamma, "rad"))
        if self.R_m >= 1.0:
            raise ValueError(f"R_m must be < 1 [dimensionless], got {self.R_m!r}")
        if self.friction is not None and not isinstance(self.friction, DryFriction):
            raise ValueError(f"friction must be a DryFriction or None, got {self.friction!r}")

    def with_speed(self, R_omega: float) -> "DamperParams":
        """The same parameters at another speed ``R_omega`` [-]."""
        return replace(self, R_omega=R_omega)

    @classmethod
    def from_physical(cls, M: float, c: float, omega: float, m: float, A: float, l: float,
                      H1: float, H2: float, e: float, gamma: float = 0.0, *,
                      g: float = 9.80665, M_sigma: float | None = None,
                      f: float | None = None, joint_radius: float | None = None,
                      eps: float = 1e-3) -> "DamperParams":
        """Dimensionless parameters from the eleven SI parameters (7.48)-(7.50).

        Parameters
        ----------
        M : float
            Rotor mass without the CW [kg].
        c : float
            Support stiffness [N/m].
        omega : float
            Spin rate [rad/s].
        m : float
            CW mass [kg].
        A : float
            CW moment of inertia about the suspension point (spherical tensor) [kg m^2].
        l : float
            Suspension point to CW centre of mass [m].
        H1 : float
            Viscous moment coefficient on the relative angular velocity [N m s].
        H2 : float
            External viscous coefficient of the supports [N s/m].
        e : float
            Rotor eccentricity [m].
        gamma : float
            Unbalance angle [rad].
        g : float
            Gravity [m/s^2].
        M_sigma : float, optional
            Total moving mass [kg]; default ``M + m``.
        f : float, optional
            Dry-friction coefficient [-]; with ``joint_radius`` enables
            :class:`DryFriction` with ``R_f = h_j f/(l sqrt(1+f^2))`` (7.81).
        joint_radius : float, optional
            Radius ``h_j`` of the inner sphere or joint axle [m].
        eps : float
            Friction regularisation rate [-].
        """
        M = _pos("M", M, "kg"); c = _pos("c", c, "N/m"); omega = _nonneg("omega", omega, "rad/s")
        m = _pos("m", m, "kg"); A = _pos("A", A, "kg m^2"); l = _pos("l", l, "m")
        H1 = _nonneg("H1", H1, "N m s"); H2 = _nonneg("H2", H2, "N s/m"); e = _nonneg("e", e, "m")
        g = _nonneg("g", g, "m/s^2")
        if m * l * l > A * (1 + 1e-12):
            raise ValueError(f"A must be >= m l^2 = {m * l * l:g} [kg m^2], got {A!r}")
        Ms = M + m if M_sigma is None else _pos("M_sigma", M_sigma, "kg")
        w0 = math.sqrt(c / Ms)
        rho2 = A / m
        fr = None
        if f is not None or joint_radius is not None:
            if f is None or joint_radius is None:
                raise ValueError("f [-] and joint_radius [m] must be given together for dry friction")
            f = _nonneg("f", f, "dimensionless")
            hj = _nonneg("joint_radius", joint_radius, "m")
            fr = DryFriction(R_f=R_f_cardan(hj / l, f), eps=eps, kappa=m * l * l / A)
        return cls(R_m=m * l * l / (Ms * rho2), R_omega=omega / w0,
                   R_g=math.sqrt(g * l / (rho2 * w0 * w0)), h=H1 / (m * rho2 * w0),
                   H=H2 / (Ms * w0), e0=M * e / (m * l), gamma=gamma, friction=fr)


# ---------------------------------------------------------------------------
# equations of motion
# ---------------------------------------------------------------------------

_EZ = np.array([0.0, 0.0, 1.0])


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
    s = np.asarray(s, dtype=float)
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
    s = np.asarray(s, dtype=float)
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
    if frame == "fixed":
        return lambda t, s: rhs(t, s, p)
    if frame == "rotating":
        return lambda t, s: rhs_rotating(t, s, p)
    raise ValueError(f"frame must be 'fixed' or 'rotating' [-], got {frame!r}")


def _rot(v, ang):
    c, s = math.cos(ang), math.sin(ang)
    return np.array([c * v[0] - s * v[1], s * v[0] + c * v[1], v[2]])


def to_rotating(tau: float, s, R_omega: float) -> np.ndarray:
    """Fixed-frame state -> rotating-frame components (same layout)."""
    s = np.asarray(s, dtype=float)
    e = complex(math.cos(R_omega * tau), -math.sin(R_omega * tau))
    z, dz = complex(s[0], s[1]), complex(s[2], s[3])
    zeta, dzeta = z * e, (dz - 1j * R_omega * z) * e
    return np.concatenate([[zeta.real, zeta.imag, dzeta.real, dzeta.imag],
                           _rot(s[4:7], -R_omega * tau), _rot(s[7:10], -R_omega * tau)])


def to_fixed(tau: float, s, R_omega: float) -> np.ndarray:
    """Rotating-frame components -> fixed-frame state (inverse of :func:`to_rotating`)."""
    s = np.asarray(s, dtype=float)
    e = complex(math.cos(R_omega * tau), math.sin(R_omega * tau))
    zeta, dzeta = complex(s[0], s[1]), complex(s[2], s[3])
    z, dz = zeta * e, (dzeta + 1j * R_omega * zeta) * e
    return np.concatenate([[z.real, z.imag, dz.real, dz.imag],
                           _rot(s[4:7], R_omega * tau), _rot(s[7:10], R_omega * tau)])


def state_from_angles(phi: float, psi: float, R_omega: float, *, xi: float = 0.0, eta: float = 0.0,
                      dphi: float = 0.0, dpsi: float = 0.0, dtheta: float = 0.0,
                      dxi: float = 0.0, deta: float = 0.0, frame: str = "rotating") -> np.ndarray:
    """State vector from the book's Euler angles at ``tau = 0`` (where both frames coincide).

    Parameters
    ----------
    phi : float
        Nutation: deflection of the CW from the downward vertical [rad].
    psi : float
        Angle of the CW's offset about the rotor axis, relative to the rotor [rad].
    R_omega : float
        Spin speed [-].
    xi, eta, dxi, deta : float
        Shaft position and rate in the rotating frame [-].
    dphi, dpsi, dtheta : float
        Euler-angle rates [-] (relative to the rotor for ``psi``).
    frame : str
        ``"rotating"`` or ``"fixed"`` layout of the result.
    """
    sp, cp, ss, cs = math.sin(phi), math.cos(phi), math.sin(psi), math.cos(psi)
    n = np.array([-sp * ss, sp * cs, -cp])
    eN = np.array([cs, ss, 0.0])
    W = (dpsi + R_omega) * _EZ + dphi * eN + dtheta * (-n)
    s = np.concatenate([[xi, eta, dxi, deta], n, W])
    if frame == "rotating":
        return s
    if frame == "fixed":
        return to_fixed(0.0, s, R_omega)
    raise ValueError(f"frame must be 'fixed' or 'rotating' [-], got {frame!r}")


def angles_from_state(s) -> tuple[float, float]:
    """``(phi, psi)`` [rad] of a state's direction vector (``phi`` in [0, pi]; ``psi``
    measured in the state's frame; undefined -- returned as 0 -- at ``phi = 0``)."""
    n = np.asarray(s, dtype=float)[4:7]
    n = n / np.linalg.norm(n)
    phi = math.acos(max(-1.0, min(1.0, -n[2])))
    psi = math.atan2(-n[0], n[1]) if math.hypot(n[0], n[1]) > 1e-15 else 0.0
    return phi, psi


def residual_unbalance_now(s, p: DamperParams, tau: float = 0.0) -> float:
    """Instantaneous total unbalance ``|e0 e^{i gamma} + n_h|`` in capacity units [-] (rotating frame)."""
    r = to_rotating(tau, s, p.R_omega) if tau else np.asarray(s, dtype=float)
    nh = complex(r[4], r[5]) / np.linalg.norm(r[4:7])
    return abs(p.e0 * complex(math.cos(p.gamma), math.sin(p.gamma)) + nh)


def simulate(p: DamperParams, s0, t_end: float, *, frame: str = "fixed", t_eval=None,
             rtol: float = 1e-8, atol: float = 1e-10, method: str = "DOP853"):
    """Integrate from ``tau = 0`` to ``t_end`` [-] with ``solve_ivp``; raises on failure."""
    t_end = _pos("t_end", t_end, "dimensionless time")
    s0 = np.asarray(s0, dtype=float)
    if s0.shape != (10,):
        raise ValueError(f"s0 must have shape (10,) [state], got {s0.shape}")
    sol = solve_ivp(make_rhs(p, frame), (0.0, t_end), s0, method=method, rtol=rtol, atol=atol,
                    t_eval=t_eval)
    if not sol.success:
        raise RuntimeError(f"integration failed: {sol.message}")
    return sol


# ---------------------------------------------------------------------------
# steady motions (7.51)-(7.60)
# ---------------------------------------------------------------------------

@dataclass(frozen=True)
class DamperSteady:
    """A steady motion of the ABD (equilibrium of :func:`rhs_rotating`).

    Attributes
    ----------
    label : int
        Book index (Fig. 7.25): e0 < 1: 1, 2 main, 3 (heavy side), 4 (light side);
        e0 >= 1: 1 main, 2 side.
    kind : str
        ``"main"`` or ``"side"``.
    phi : float
        Nutation angle [rad] (negative: heavy side, the book's convention).
    psi : float
        Angle relative to the rotor [rad].
    u : float
        ``cos(phi)`` [-].
    xi, eta : float
        Shaft deflection [-] (7.52), (7.62).
    """

    label: int
    kind: str
    phi: float
    psi: float
    u: float
    xi: float
    eta: float

    def state(self, R_omega: float) -> np.ndarray:
        """Rotating-frame state (CW locked to the rotor, ``theta' = 0``)."""
        return state_from_angles(self.phi, self.psi, R_omega, xi=self.xi, eta=self.eta)

    @property
    def deflection(self) -> float:
        """``|xi + i eta|`` [-]."""
        return math.hypot(self.xi, self.eta)


def _need_rg(p):
    if p.R_g <= 0.0:
        raise ValueError("R_g must be > 0 [dimensionless] for the steady-motion solver (7.53), got 0.0")
    if p.R_omega <= 0.0:
        raise ValueError(f"R_omega must be > 0 [dimensionless], got {p.R_omega!r}")


def steady_quartic_roots(p: DamperParams) -> np.ndarray:
    """Real roots ``u = cos(phi)`` in [-1, 1] of ``(1 - u^2) Delta(u) = R_m^2 R_omega^8 e0^2 u^2 / R_g^4`` (7.53)."""
    _need_rg(p)
    R = p.R_omega
    a, b, c2 = R * R - 1.0, p.R_m * R ** 4 / p.R_g ** 2, (p.H * R) ** 2
    Q = (p.R_m * R ** 4 / p.R_g ** 2) ** 2 * p.e0 ** 2
    Delta = np.array([b * b, 2 * a * b, a * a + c2])         # highest power first
    poly = np.polymul([-1.0, 0.0, 1.0], Delta)
    poly = np.polyadd(poly, [-Q, 0.0, 0.0])
    r = np.roots(poly)
    tol = 1e-7
    r = r[np.abs(r.imag) <= tol * np.maximum(1.0, np.abs(r))].real
    r = r[(r >= -1.0 - 1e-12) & (r <= 1.0 + 1e-12)]
    # polish
    out = []
    for u in r:
        u = float(np.clip(u, -1.0, 1.0))
        out.append(u)
    return np.array(sorted(set(np.round(out, 13)), reverse=True))


def _Delta(u, p):
    R = p.R_omega
    return (R * R - 1.0 + p.R_m * R ** 4 / p.R_g ** 2 * u) ** 2 + (p.H * R) ** 2


def steady_motions(p: DamperParams) -> list[DamperSteady]:
    """All steady motions at ``p.R_omega`` (7.51)-(7.53), labelled as in Fig. 7.25.

    The book's continuation labels are assigned as follows: heavy-side roots
    (CW unbalance along the rotor's) are motion 3 (e0 < 1) or 2 (e0 >= 1);
    light-side roots sorted by decreasing ``u`` are (1, 4, 2) when there are
    three, and for a single one: 1 if ``u > 0`` else 2 (e0 < 1).
    """
    _need_rg(p)
    R, Rm, e0 = p.R_omega, p.R_m, p.e0
    K = complex(R * R - 1.0, -p.H * R)
    eg = complex(math.cos(p.gamma), math.sin(p.gamma))
    roots = steady_quartic_roots(p)
    light, heavy = [], []
    for u in roots:
        s = math.sqrt(max(0.0, 1.0 - u * u))
        if e0 == 0.0:
            # no unbalance: only the axial positions, e^{i psi} arbitrary
            if s > 1e-12:
                continue
            ent = (u, 0.0, 0.0j)
            light.append(ent)
            continue
        if s < 1e-14 or abs(u) < 1e-14:
            continue
        # i e^{i psi} [-(R_g^2/(R^2 u)) K s - R_m R^2 s] = R_m R^2 e0 e^{i gamma}
        q = -(p.R_g ** 2 / (R * R * u)) * K * s - Rm * R * R * s
        ie = Rm * R * R * e0 * eg / q
        eip = ie / 1j
        psi = math.atan2(eip.imag, eip.real)
        zeta = (p.R_g ** 2 / (R * R)) * (s / u) * 1j * complex(math.cos(psi), math.sin(psi))
        # side: CW offset i s e^{i psi} along e^{i gamma} is the heavy side
        along = (1j * s * complex(math.cos(psi), math.sin(psi)) * eg.conjugate()).real
        if along > 0:
            heavy.append((u, psi, zeta))
        else:
            light.append((u, psi, zeta))
    out = []
    small = e0 < 1.0
    light.sort(key=lambda t: -t[0])
    if small:
        if len(light) >= 3:
            labs = [1, 4, 2] + [0] * (len(light) - 3)
        elif len(light) == 2:
            labs = [1, 2] if light[1][0] < 0 else [1, 4]
        else:
            labs = [1 if (light and light[0][0] > 0 and R > 1.0) else 2]
    else:
        labs = [1] * len(light)
    for (u, psi, zeta), lab in zip(light, labs):
        kind = "main" if lab in (1, 2) else "side"
        out.append(DamperSteady(lab, kind, math.acos(u), psi, u, zeta.real, zeta.imag))
    for (u, psi, zeta) in heavy:
        # book convention: the heavy side has phi < 0 (psi shifted by pi)
        out.append(DamperSteady(3 if small else 2, "side", -math.acos(u),
                                math.atan2(-math.sin(psi), -math.cos(psi)), u,
                                zeta.real, zeta.imag))
    return sorted(out, key=lambda m: m.label)


def efficiency(p: DamperParams, u: float | None = None) -> float:
    """Efficiency ``n = sqrt(Delta(0)/Delta(u))`` [-] (7.54): shaft deflection with the ABD
    over that without it.  ``u`` defaults to the largest positive root of (7.53)
    (the branch stable by (7.68))."""
    _need_rg(p)
    if u is None:
        r = steady_quartic_roots(p)
        r = r[r > 0]
        if r.size == 0:
            return math.nan
        u = float(r.max())
    return math.sqrt(_Delta(0.0, p) / _Delta(u, p))


def efficiency_approx(p: DamperParams) -> float:
    """Approximation of (6.114) with ``u = sqrt(1 - e0^2)`` [-] (e0 <= 0.6); the print lacks the
    square root on the numerator (digest 2.3)."""
    _need_rg(p)
    if p.e0 >= 1.0:
        raise ValueError(f"e0 must be < 1 [capacity units] for (6.114), got {p.e0!r}")
    return efficiency(p, math.sqrt(1.0 - p.e0 ** 2))


def critical_speeds_undamped(R_m: float, R_g: float, e0: float) -> dict:
    """Existence boundaries (7.55)-(7.56) for ``H = 0`` (duplicated print line removed, E6).

    Returns
    -------
    dict
        ``e0_star`` [-], ``R1`` [-], and ``R2``, ``R3`` [-] (NaN when the
        radicand ``R_g^4 - 4 R_m R_g^2 cos^3 phi_k`` is negative);
        ``phi_k = arcsin(e0^(1/3))``.
    """
    R_m = _pos("R_m", R_m, "dimensionless"); R_g = _pos("R_g", R_g, "dimensionless")
    e0 = _nonneg("e0", e0, "capacity units")
    if e0 >= 1.0:
        raise ValueError(f"e0 must be < 1 [capacity units] for (7.56), got {e0!r}")
    g2 = R_g * R_g
    x = (g2 / (4.0 * R_m)) ** (2.0 / 3.0)
    e_star = (1.0 - x) ** 1.5 if x < 1.0 else 0.0
    pk = math.asin(e0 ** (1.0 / 3.0))
    c3 = math.cos(pk) ** 3
    R1 = math.sqrt((math.sqrt(g2 * g2 + 4 * R_m * g2 * c3) - g2) / (2 * R_m * c3))
    disc = g2 * g2 - 4 * R_m * g2 * c3
    if disc >= 0.0:
        R2 = math.sqrt((g2 - math.sqrt(disc)) / (2 * R_m * c3))
        R3 = math.sqrt((g2 + math.sqrt(disc)) / (2 * R_m * c3))
    else:
        R2 = R3 = math.nan
    return {"e0_star": e_star, "phi_k": pk, "R1": R1, "R2": R2, "R3": R3}


# ---------------------------------------------------------------------------
# stability (2.4): numerical Jacobian on the tangent space of |n| = 1
# ---------------------------------------------------------------------------

def _tangent(n):
    t1 = np.cross(n, _EZ)
    if np.linalg.norm(t1) < 1e-8:
        t1 = np.cross(n, np.array([1.0, 0.0, 0.0]))
    t1 /= np.linalg.norm(t1)
    t2 = np.cross(n, t1)
    return t1, t2


def jacobian(p: DamperParams, s, *, step: float = 1e-6) -> np.ndarray:
    """9x9 Jacobian of :func:`rhs_rotating` at ``s`` in the chart
    ``(xi, eta, xi', eta', eps1, eps2, W1, W2, W3)``, ``n = normalise(n0 + eps1 t1 + eps2 t2)``
    -- the book's 9 first-order variables (``x, y, phi, psi, p`` and rates), without the
    constraint direction."""
    s = np.asarray(s, dtype=float)
    n0 = s[4:7] / np.linalg.norm(s[4:7])
    t1, t2 = _tangent(n0)

    def full(v):
        n = n0 + v[4] * t1 + v[5] * t2
        n = n / np.linalg.norm(n)
        return np.concatenate([v[:4], n, v[6:9]])

    def red(ds):
        return np.concatenate([ds[:4], [ds[4:7] @ t1, ds[4:7] @ t2], ds[7:10]])

    v0 = np.concatenate([s[:4], [0.0, 0.0], s[7:10]])
    J = np.empty((9, 9))
    for k in range(9):
        d = np.zeros(9)
        d[k] = step
        J[:, k] = (red(rhs_rotating(0.0, full(v0 + d), p))
                   - red(rhs_rotating(0.0, full(v0 - d), p))) / (2 * step)
    return J


def eigenvalues(p: DamperParams, motion: DamperSteady) -> np.ndarray:
    """The 9 characteristic roots of a steady motion (numerical counterpart of (7.63)),
    sorted by decreasing real part."""
    lam = np.linalg.eigvals(jacobian(p, motion.state(p.R_omega)))
    return lam[np.argsort(-lam.real)]


def is_stable(p: DamperParams, motion: DamperSteady, *, tol: float = 1e-7) -> bool:
    """Asymptotic stability: all 9 roots with real part < ``-tol``."""
    return bool(np.all(eigenvalues(p, motion).real < -tol))


def fast_rotor_roots(p: DamperParams, phi: float) -> np.ndarray:
    """Fast-rotor asymptotics (7.72) of a main motion, converted to ``lambda`` [-].

    Uses ``lambda = R_omega mu`` (erratum E7: the print's ``mu = lambda / nu``
    contradicts ``b_11 = a_11 / R_omega^2``), ``nu = 1 / R_omega``.  Returns the
    five roots ``lambda^(5), lambda^(6), lambda^(7), lambda^(8), lambda^(9)``.
    """
    R = _pos("R_omega", p.R_omega, "dimensionless")
    nu, Rm, h, H = 1.0 / R, p.R_m, p.h, p.H
    s2, c2 = math.sin(phi) ** 2, math.cos(phi) ** 2
    den = s2 + Rm * c2
    re56 = -nu / (2 * (1 - Rm) * (1 - Rm * c2)) * (
        h * (s2 + 2 * Rm ** 2 * (1 - Rm) * c2 ** 2) / den + H * Rm * (1 + (1 - 2 * Rm) * c2))
    im56 = math.sqrt(Rm * den / ((1 - Rm) * (1 - Rm * c2)))
    mu = np.array([complex(re56, im56), complex(re56, -im56), complex(-h * nu, 1.0),
                   complex(-h * nu, -1.0), complex(-nu * h * Rm * c2 / den, 0.0)])
    return R * mu


def stability_scan(p: DamperParams, speeds, label: int) -> np.ndarray:
    """Largest real part of the roots of motion ``label`` over ``speeds`` [-]
    (NaN where the motion does not exist).  Use it for the critical speeds of
    (7.73)-(7.74), which the digest flags (E8) -- compute, do not trust the print."""
    out = []
    for R in np.asarray(speeds, dtype=float):
        q = p.with_speed(float(R))
        ms = [m for m in steady_motions(q) if m.label == label]
        out.append(max(eigenvalues(q, m)[0].real for m in ms) if ms else math.nan)
    return np.array(out)


# ---------------------------------------------------------------------------
# dry friction: residual unbalance (7.80)-(7.84)
# ---------------------------------------------------------------------------

def R_f_cardan(R_l: float, f: float) -> float:
    """``R_f = R_l f / sqrt(1 + f^2)`` [-] (7.81), ``R_l = h_j / l`` (joint radius over arm)."""
    R_l = _nonneg("R_l", R_l, "dimensionless"); f = _nonneg("f", f, "dimensionless")
    return R_l * f / math.sqrt(1.0 + f * f)


def R_f_ball_joint(phi: float, R_l: float, theta: float, f: float) -> float:
    """Ball-joint friction ratio (7.84) [-]: ``R_l sin(gamma_f)`` for ``phi <= theta + gamma_f``,
    else ``R_l [sin(phi - theta) + sin(phi - theta - gamma_f)]`` (``gamma_f = arctan f``,
    ``theta`` the socket wrap angle [rad]), valid for ``phi < pi/2 - theta``."""
    R_l = _nonneg("R_l", R_l, "dimensionless"); f = _nonneg("f", f, "dimensionless")
    theta = _nonneg("theta", theta, "rad"); phi = _nonneg("phi", phi, "rad")
    if phi >= math.pi / 2 - theta:
        raise ValueError(f"phi must be < pi/2 - theta = {math.pi / 2 - theta:g} [rad], got {phi!r}")
    gf = math.atan(f)
    if phi <= theta + gf:
        return R_l * math.sin(gf)
    return R_l * (math.sin(phi - theta) + math.sin(phi - theta - gf))


def residual_parametric(phi, R_m: float, R_f) -> tuple[np.ndarray, np.ndarray]:
    """(7.80): ``s(phi)`` and ``s_res(phi)`` [capacity units] for ``0 <= phi < arccos R_f``.

    ``s_res = R_f sin phi / (R_m (cos phi - R_f))``, ``s = sin phi + s_res``.
    ``R_m`` here is ``m / M_Sigma`` (equal to :attr:`DamperParams.R_m` when
    ``A = m l^2``); ``R_f`` may be an array (ball joint, (7.84))."""
    phi = np.asarray(phi, dtype=float)
    R_f = np.asarray(R_f, dtype=float)
    sres = R_f * np.sin(phi) / (R_m * (np.cos(phi) - R_f))
    return np.sin(phi) + sres, sres


def residual_unbalance(s, R_m: float, R_f: float) -> np.ndarray:
    """Exact worst-case residual unbalance ``s_res(s)`` [capacity units] from (7.80) (root of the
    parametric form; cardan/sphere, constant ``R_f``).  Valid while ``phi <= pi/2`` (s <= 1 region
    and beyond up to the parametric limit)."""
    R_m = _pos("R_m", R_m, "dimensionless"); R_f = _nonneg("R_f", R_f, "dimensionless")
    if R_f >= 1.0:
        raise ValueError(f"R_f must be < 1 [dimensionless], got {R_f!r}")
    s_arr = np.atleast_1d(np.asarray(s, dtype=float))
    out = np.empty_like(s_arr)
    top = min(math.pi / 2, math.acos(R_f)) - 1e-12
    s_top = float(residual_parametric(top, R_m, R_f)[0])
    for k, sv in enumerate(s_arr):
        if sv < 0 or not math.isfinite(sv):
            raise ValueError(f"s must be a finite number >= 0 [capacity units], got {sv!r}")
        if sv == 0.0:
            out[k] = 0.0
            continue
        if sv > s_top:
            raise ValueError(f"s must be <= {s_top:g} [capacity units] for R_m = {R_m}, R_f = {R_f}, got {sv!r}")
        phi = brentq(lambda a: float(residual_parametric(a, R_m, R_f)[0]) - sv, 0.0, top, xtol=1e-14)
        out[k] = float(residual_parametric(phi, R_m, R_f)[1])
    return out if np.ndim(s) else float(out[0])


def residual_cubic(s, R_m: float, R_f: float, *, printed: bool = True):
    """Explicit approximation (7.82) ``a1 s + a3 s^3`` [capacity units].

    ``a1 = R_f/(R_m + R_f(1 - R_m))`` is correct; the printed
    ``a3 = R_m^3 R_f (1 - R_f)^2 / [R_m + R_f (1 - R_m)]^4`` does not give the
    claimed 3 % (E9); ``printed=False`` uses the Taylor value ``a3/2`` (still ~7 %).
    Prefer :func:`residual_unbalance`.
    """
    s = np.asarray(s, dtype=float)
    d = R_m + R_f * (1.0 - R_m)
    a1 = R_f / d
    a3 = R_m ** 3 * R_f * (1.0 - R_f) ** 2 / d ** 4
    if not printed:
        a3 = 0.5 * a3
    return a1 * s + a3 * s ** 3
