"""Two-axis pendulum correction weight (monograph ch. 6): model, equations of motion,
steady motions.

The rotor is vertical, rigid, in plane-parallel motion on isotropic visco-elastic
supports (2 DOF).  One correction weight (CW) hangs at the shaft point K and turns
relative to the rotor by **psi** about the shaft axis and then by **phi** about the
transverse axis xi (the image of the rotor axis u after the turn psi).  Its inertia
at K is diag(A, B, B) (mass-inertia conditions (2.7), (2.8)); its centre of mass
lies at distance l below K when phi = 0.  Gravity acts on phi.  Digest:
``/work/shared/physics/ch6_two_axis.md`` (sections 1-3; numbers [Lnnnn] there).

Dimensionless variables and parameters (book (6.9)-(6.11), digest section 1.3)
---------------------------------------------------------------------------
tau = omega0 t with omega0 = sqrt(c / M_Sigma), M_Sigma = M + m;
shaft deflection (xi, eta) = (x, y) l / rho1^2  (rotating axes);
rho1^2 = A/m, rho2^2 = B/m.

==========  ===============================  ==========================================
name        definition                        meaning
==========  ===============================  ==========================================
R_m         m l^2 / (M_Sigma rho1^2)          CW-to-rotor mass (inertia) ratio
R_omega     omega / omega0                    speed ratio (resonance at 1)
R_g         sqrt(g l / (rho1^2 omega0^2))     gravity parameter (pendulum vs. resonance)
R_rho       rho2 / rho1 = sqrt(B / A)         CW inertia ratio (1/sqrt 2 for a planar CW)
h1          H1 / (A omega0)                   internal (CW) damping of phi
h2          H2 / (B omega0)                   internal (CW) damping of psi
H           H3 / (M_Sigma omega0)             external (support) damping
e0          M e / (m l)                       unbalance in units of the balancing
                                              capacity S = m l (e0 < 1 balanceable)
R_gm        R_g^2 / R_m = g M_Sigma/(S w0^2)  gravity-to-mass ratio (6.122)
kappa       R_m H / (h2 R_rho^2)              = R_mH of (6.122), QP parameter
==========  ===============================  ==========================================

Equations (book numbers; corrections per the digest)
----------------------------------------------------
* (6.12) rotating frame, state ``y = [phi, psi, xi, eta, phi', psi', xi', eta']``
  (' = d/dtau): :func:`rhs_rotating`, residual :func:`residual_rotating`.
  OCR fix (digest 2.3): the brackets of l3, l4 contain the second derivatives
  phi'', psi'' (the print shows first derivatives).
* (6.15) fixed frame, state ``y = [phi, alpha, x, y, phi', alpha', x', y']`` with
  alpha = psi + R_omega tau the CW azimuth: :func:`rhs_fixed`,
  :func:`residual_fixed`.  OCR fix: phi'' cos(alpha) in L4.
* Run-up / run-down (digest 2.6, not in the book): :func:`rhs_fixed_variable_speed`.

All equations are linear in the accelerations; the mass matrix has the block form
[[diag(1, R_rho^2), C], [R_m C^T, I]] with C C^T = diag(cos^2 phi, sin^2 phi), so
the accelerations follow in closed form (Schur complement) with the pivots
1 - R_m cos^2 phi > 0 and R_rho^2 - R_m sin^2 phi > 0, guaranteed by
R_m < min(1, R_rho^2) (physically B >= m l^2, A >= m l^2 and m < M_Sigma).

I re-derived (6.15) from the Lagrangian (rotor + CW kinetic energy,
V = c r^2/2 - m g l cos phi, Rayleigh function (H1 phi'^2 + H2 psi'^2 + H3 |v_K|^2)/2)
with sympy: the residual against the digest's corrected (6.15) is identically 0;
the rotating form (6.12) follows by (6.13) and is checked numerically in the tests.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Callable, List, Optional, Tuple

import numpy as np

__all__ = [
    "TwoAxisParams", "SteadyMotion",
    "residual_rotating", "residual_fixed", "rhs_rotating", "rhs_fixed",
    "rhs_fixed_variable_speed", "linear_ramp",
    "rotating_to_fixed", "fixed_to_rotating",
    "jacobian", "eigenvalues", "max_real_part",
    "steady_polynomial", "first_group", "second_group", "steady_motions",
    "no_gravity_no_damping", "efficiency", "r0",
]


# ---------------------------------------------------------------------------
# parameters
# ---------------------------------------------------------------------------

def _finite(name, value, unit="-", *, positive=False, nonneg=False):
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a real number [{unit}], got {value!r}") from None
    if not math.isfinite(v):
        raise ValueError(f"{name} must be finite [{unit}], got {value!r}")
    if positive and not v > 0.0:
        raise ValueError(f"{name} must be > 0 [{unit}], got {value!r}")
    if nonneg and v < 0.0:
        raise ValueError(f"{name} must be >= 0 [{unit}], got {value!r}")
    return v


@dataclass(frozen=True)
class TwoAxisParams:
    """Dimensionless parameters of the ch. 6 model (book (6.11), digest section 1.3).

    Parameters
    ----------
    R_m : float
        Mass ratio m l^2 / (M_Sigma rho1^2) [-], 0 < R_m < min(1, R_rho^2).
    R_omega : float
        Speed ratio omega / omega0 [-], >= 0.
    R_g : float
        Gravity parameter sqrt(g l / (rho1^2 omega0^2)) [-], >= 0 (0: no gravity).
    R_rho : float
        Inertia ratio rho2/rho1 = sqrt(B/A) [-]; 1/sqrt(2) for every planar CW.
    h1, h2 : float
        CW damping H1/(A omega0), H2/(B omega0) [-], >= 0.
    H : float
        Support damping H3/(M_Sigma omega0) [-], >= 0.
    e0 : float
        Unbalance M e / (m l) in units of the balancing capacity [-], >= 0.
    """

    R_m: float
    R_omega: float
    R_g: float
    R_rho: float = math.sqrt(0.5)
    h1: float = 0.1
    h2: float = 0.1
    H: float = 0.05
    e0: float = 0.0

    def __post_init__(self):
        for name in ("R_m", "R_rho"):
            object.__setattr__(self, name, _finite(name, getattr(self, name), positive=True))
        for name in ("R_omega", "R_g", "h1", "h2", "H", "e0"):
            object.__setattr__(self, name, _finite(name, getattr(self, name), nonneg=True))
        if not self.R_m < min(1.0, self.R_rho ** 2):
            raise ValueError(
                f"R_m must be < min(1, R_rho^2) = {min(1.0, self.R_rho ** 2):.6g} [-] "
                f"(B >= m l^2, A >= m l^2, m < M_Sigma), got {self.R_m!r}")

    # derived ------------------------------------------------------------
    @property
    def R_g2(self) -> float:
        """R_g^2 [-]."""
        return self.R_g ** 2

    @property
    def R_rho2(self) -> float:
        """R_rho^2 = B/A [-]."""
        return self.R_rho ** 2

    @property
    def R_gm(self) -> float:
        """R_gm = R_g^2 / R_m = g M_Sigma / (S omega0^2) [-] (6.122)."""
        return self.R_g ** 2 / self.R_m

    @property
    def kappa(self) -> float:
        """kappa = R_mH = R_m H / (h2 R_rho^2) [-] (6.122); inf when h2 = 0."""
        den = self.h2 * self.R_rho ** 2
        return self.R_m * self.H / den if den > 0 else math.inf

    R_mH = kappa

    def with_(self, **changes) -> "TwoAxisParams":
        """Copy with some fields changed (validated)."""
        return replace(self, **changes)

    @classmethod
    def from_R_gm(cls, R_m, R_gm, **kw) -> "TwoAxisParams":
        """Build from R_m and R_gm = R_g^2/R_m (the steady states depend on R_gm only)."""
        R_gm = _finite("R_gm", R_gm, nonneg=True)
        return cls(R_m=R_m, R_g=math.sqrt(R_gm * float(R_m)), **kw)

    @classmethod
    def from_physical(cls, *, M, m, l, A, B, c, omega, e=0.0, H1=0.0, H2=0.0, H3=0.0,
                      g=9.81) -> "TwoAxisParams":
        """Dimensionless parameters from SI quantities ((6.9)-(6.11)).

        Parameters
        ----------
        M : float
            Rotor mass without the CW [kg].
        m : float
            CW mass [kg].
        l : float
            Pivot-to-CW-centre-of-mass distance [m] (S = m l [kg m]).
        A : float
            CW moment of inertia about the transverse tilt axis xi, at K [kg m^2].
        B : float
            CW moment of inertia about eta and zeta (equal), at K [kg m^2].
        c : float
            Isotropic support stiffness [N/m].
        omega : float
            Rotor spin [rad/s].
        e : float
            Rotor eccentricity [m].
        H1, H2 : float
            Viscous coefficients of phi' and psi' [N m s/rad].
        H3 : float
            Support viscous coefficient [N s/m].
        g : float
            Gravity [m/s^2] (0 for a model without gravity).

        Returns
        -------
        TwoAxisParams
            with R_m = m l^2/(M_Sigma rho1^2), R_omega = omega/omega0,
            R_g^2 = g l/(rho1^2 omega0^2), R_rho = sqrt(B/A), h1 = H1/(A omega0),
            h2 = H2/(B omega0), H = H3/(M_Sigma omega0), e0 = M e/(m l),
            where M_Sigma = M + m, omega0 = sqrt(c/M_Sigma), rho1^2 = A/m.
            Lengths convert back by x_phys = xi rho1^2 / l (:meth:`length_scale`).
        """
        M = _finite("M", M, "kg", positive=True)
        m = _finite("m", m, "kg", positive=True)
        l = _finite("l", l, "m", positive=True)
        A = _finite("A", A, "kg m^2", positive=True)
        B = _finite("B", B, "kg m^2", positive=True)
        c = _finite("c", c, "N/m", positive=True)
        omega = _finite("omega", omega, "rad/s", nonneg=True)
        e = _finite("e", e, "m", nonneg=True)
        H1 = _finite("H1", H1, "N m s/rad", nonneg=True)
        H2 = _finite("H2", H2, "N m s/rad", nonneg=True)
        H3 = _finite("H3", H3, "N s/m", nonneg=True)
        g = _finite("g", g, "m/s^2", nonneg=True)
        if A < m * l * l:
            raise ValueError(f"A must be >= m l^2 = {m * l * l:.6g} [kg m^2], got {A!r}")
        if B < m * l * l:
            raise ValueError(f"B must be >= m l^2 = {m * l * l:.6g} [kg m^2], got {B!r}")
        Ms = M + m
        w0 = math.sqrt(c / Ms)
        rho1_2 = A / m
        return cls(R_m=m * l * l / (Ms * rho1_2), R_omega=omega / w0,
                   R_g=math.sqrt(g * l / (rho1_2 * w0 * w0)), R_rho=math.sqrt(B / A),
                   h1=H1 / (A * w0), h2=H2 / (B * w0), H=H3 / (Ms * w0), e0=M * e / (m * l))

    @staticmethod
    def length_scale(m, l, A) -> float:
        """rho1^2 / l = A / (m l) [m]: multiply xi, eta (or x, y) by it for metres."""
        return _finite("A", A, "kg m^2", positive=True) / (
            _finite("m", m, "kg", positive=True) * _finite("l", l, "m", positive=True))


# ---------------------------------------------------------------------------
# equations of motion
# ---------------------------------------------------------------------------

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


def _solve_acc(ph, ps, g1, g2, g3, g4, Rm, Rr2):
    """Solve [[diag(1,Rr2), C], [Rm C^T, I]] a = -g in closed form (C C^T diagonal)."""
    sf, cf, sp, cp = np.sin(ph), np.cos(ph), np.sin(ps), np.cos(ps)
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
    ph, ps, xi, et, dph, dps, dxi, det = y
    Rw, Rm = p.R_omega, p.R_m
    sf, cf, sp, cp = np.sin(ph), np.cos(ph), np.sin(ps), np.cos(ps)
    ax0 = -2 * Rw * det - Rw ** 2 * xi
    ay0 = 2 * Rw * dxi - Rw ** 2 * et
    W = dph ** 2 + dps ** 2 + 2 * Rw * dps
    g1 = p.h1 * dph + p.R_g2 * sf - (ax0 * sp - ay0 * cp) * cf
    g2 = p.h2 * dps * p.R_rho2 - (ax0 * cp + ay0 * sp) * sf
    g3 = ax0 + p.H * (dxi - Rw * et) + xi - Rm * (2 * (Rw + dps) * dph * cp * cf
                                                 - W * sp * sf + Rw ** 2 * (p.e0 - sf * sp))
    g4 = ay0 + p.H * (det + Rw * xi) + et - Rm * (W * cp * sf + 2 * (Rw + dps) * dph * sp * cf
                                                 + Rw ** 2 * sf * cp)
    a = _solve_acc(ph, ps, g1, g2, g3, g4, Rm, p.R_rho2)
    return np.array([dph, dps, dxi, det, *a])


def _rhs_fixed_core(y, p, h2_drive, fx, fy):
    ph, al, x, yy, dph, dal, dx, dy = y
    Rm = p.R_m
    sf, cf, sa, ca = np.sin(ph), np.cos(ph), np.sin(al), np.cos(al)
    W = dph ** 2 + dal ** 2
    g1 = p.h1 * dph + p.R_g2 * sf
    g2 = p.h2 * (dal - h2_drive) * p.R_rho2
    g3 = p.H * dx + x - Rm * (2 * dal * dph * ca * cf - W * sa * sf + fx)
    g4 = p.H * dy + yy - Rm * (W * ca * sf + 2 * dal * dph * sa * cf + fy)
    a = _solve_acc(ph, al, g1, g2, g3, g4, Rm, p.R_rho2)
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
    return _rhs_fixed_core(y, p, Rw, f * np.cos(Rw * tau), f * np.sin(Rw * tau))


def linear_ramp(R_start, R_end, duration, tau0=0.0) -> Callable[[float], Tuple[float, float, float]]:
    """Speed profile for :func:`rhs_fixed_variable_speed`: R_omega ramps linearly
    from ``R_start`` to ``R_end`` over ``duration`` (tau units) from ``tau0``, then
    stays constant.  Returns ``f(tau) -> (theta, theta', theta'')`` with the exact
    rotor angle theta = integral of R_omega dtau (theta(0) = 0) [rad, -, -]."""
    R0 = _finite("R_start", R_start, "-", nonneg=True)
    R1 = _finite("R_end", R_end, "-", nonneg=True)
    T = _finite("duration", duration, "tau", positive=True)
    t0 = _finite("tau0", tau0, "tau", nonneg=True)
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


def rotating_to_fixed(tau, y_rot, R_omega):
    """Map a rotating-frame state (6.12) to the fixed-frame state (6.15) by (6.13).

    psi = alpha - R_omega tau; xi + i eta = (x + i y) e^{-i R_omega tau}.
    Works on arrays ``y_rot`` of shape (8,) or (8, k) with ``tau`` of shape () or (k,).
    """
    ph, ps, xi, et, dph, dps, dxi, det = np.asarray(y_rot, float)
    th = R_omega * np.asarray(tau, float)
    c, s = np.cos(th), np.sin(th)
    x = xi * c - et * s
    y = xi * s + et * c
    vxi = dxi - R_omega * et          # rotating components of the absolute velocity
    vet = det + R_omega * xi
    dx = vxi * c - vet * s
    dy = vxi * s + vet * c
    return np.array([ph, ps + th, x, y, dph, dps + R_omega, dx, dy])


def fixed_to_rotating(tau, y_fix, R_omega):
    """Inverse of :func:`rotating_to_fixed`."""
    ph, al, x, y, dph, dal, dx, dy = np.asarray(y_fix, float)
    th = R_omega * np.asarray(tau, float)
    c, s = np.cos(th), np.sin(th)
    xi = x * c + y * s
    et = -x * s + y * c
    vxi = dx * c + dy * s
    vet = -dx * s + dy * c
    return np.array([ph, al - th, xi, et, dph, dal - R_omega, vxi + R_omega * et,
                     vet - R_omega * xi])


# ---------------------------------------------------------------------------
# linearisation
# ---------------------------------------------------------------------------

def jacobian(fun, y0, *args, eps=1e-6):
    """Central-difference Jacobian of ``fun(0, y, *args)`` at ``y0`` (8 x 8)."""
    y0 = np.asarray(y0, float)
    n = y0.size
    J = np.empty((n, n))
    for k in range(n):
        d = np.zeros(n)
        d[k] = eps * max(1.0, abs(y0[k]))
        J[:, k] = (fun(0.0, y0 + d, *args) - fun(0.0, y0 - d, *args)) / (2 * d[k])
    return J


def eigenvalues(p: TwoAxisParams, y0) -> np.ndarray:
    """Eigenvalues of the linearised (6.12) at the rotating-frame state ``y0``."""
    return np.linalg.eigvals(jacobian(rhs_rotating, y0, p))


def max_real_part(lam, drop_zero=False) -> float:
    """Largest real part; ``drop_zero`` removes the root nearest 0 (neutral phase)."""
    lam = np.asarray(lam)
    if drop_zero:
        lam = np.delete(lam, np.argmin(np.abs(lam)))
    return float(np.max(lam.real))


# ---------------------------------------------------------------------------
# steady (synchronous) motions, section 6.2
# ---------------------------------------------------------------------------

def _D(w, H):
    return (w * w - 1.0) ** 2 + H * H * w * w


def r0(p: TwoAxisParams) -> float:
    """No-ABP deflection r~0 = R_m R_omega^2 e0 / sqrt(D(R_omega)) (6.29)/(6.39)."""
    Rw = p.R_omega
    return p.R_m * Rw ** 2 * p.e0 / math.sqrt(_D(Rw, p.H))


def efficiency(p: TwoAxisParams, u) -> np.ndarray:
    """n = r~/r~0 for a first-group motion with cos(phi~) = u, (6.40).

    Depends on (R_omega, H, R_gm, u) only: R_m R_omega^4/R_g^2 = R_omega^4/R_gm.
    """
    Rw, H = p.R_omega, p.H
    if p.R_g == 0:
        raise ValueError("efficiency (6.40) needs R_g > 0 [-]; without gravity the main "
                         "motions are exactly balanced (n = 0)")
    Q = Rw ** 2 - 1 + Rw ** 4 * np.asarray(u, float) / p.R_gm
    return np.sqrt(_D(Rw, H)) / np.sqrt(Q ** 2 + H * H * Rw * Rw)


def steady_polynomial(p: TwoAxisParams) -> np.ndarray:
    """Coefficients (highest first) of the quartic P(u) of (6.36), u = cos(phi~)."""
    Rm, Rg2, Rw, H, e0 = p.R_m, p.R_g2, p.R_omega, p.H, p.e0
    A = Rw ** 2 - 1
    Dw = A * A + H * H * Rw * Rw
    return np.array([Rm ** 2 * Rw ** 8,
                     2 * Rm * Rg2 * Rw ** 4 * A,
                     Dw * Rg2 ** 2 - Rm ** 2 * Rw ** 8 * (1 - e0 * e0),
                     -2 * Rm * Rg2 * Rw ** 4 * A,
                     -Dw * Rg2 ** 2])


@dataclass
class SteadyMotion:
    """A synchronous (steady) motion of (6.12): all rotating-frame derivatives vanish.

    Attributes
    ----------
    phi, psi : float
        CW angles [rad].
    xi, eta : float
        Rotating-frame deflection [rho1^2/l].
    group : int
        1 (sin phi != 0) or 2 (phi = 0 or pi, CW neutral).
    kind : str
        ``main_below`` / ``main_above`` (balancing, CM below/above the pivot),
        ``side_light`` / ``side_heavy`` (side, CW toward the light/heavy side),
        ``neutral_below`` / ``neutral_above`` (second group).
    c : float
        Compensated fraction sin(phi) sin(psi) (= e0 for perfect balance).
    n : float
        Efficiency r~/r~0 (6.40) (nan if e0 = 0).
    eig : ndarray or None
        Eigenvalues of the linearisation (filled by :func:`steady_motions`).
    """
    phi: float
    psi: float
    xi: float
    eta: float
    group: int
    kind: str = ""
    n: float = math.nan
    eig: Optional[np.ndarray] = field(default=None, repr=False)

    @property
    def u(self) -> float:
        return math.cos(self.phi)

    @property
    def c(self) -> float:
        return math.sin(self.phi) * math.sin(self.psi)

    @property
    def r(self) -> float:
        return math.hypot(self.xi, self.eta)

    @property
    def below(self) -> bool:
        return math.cos(self.phi) > 0

    @property
    def state(self) -> np.ndarray:
        """Rotating-frame state vector for :func:`rhs_rotating`."""
        return np.array([self.phi, self.psi, self.xi, self.eta, 0, 0, 0, 0], float)

    @property
    def max_re(self) -> float:
        return math.nan if self.eig is None else max_real_part(self.eig)

    def distance(self, y) -> float:
        """Max-norm distance of the rotating-frame state ``y`` (positions only) from this
        motion, in invariants (cos phi, sin phi sin psi, sin phi cos psi, xi, eta), so that
        the equivalent representation (-phi, psi + pi) and 2 pi wraps count as equal."""
        def inv(ph, ps, xi, et):
            return np.array([math.cos(ph), math.sin(ph) * math.sin(ps),
                             math.sin(ph) * math.cos(ps), xi, et])
        return float(np.abs(inv(*np.asarray(y, float)[:4])
                            - inv(self.phi, self.psi, self.xi, self.eta)).max())

    @property
    def stable(self) -> Optional[bool]:
        return None if self.eig is None else bool(self.max_re < 0)


def _classify(motions: List[SteadyMotion], e0: float) -> None:
    """Physical labels (digest 3.6): heavy if c < 0; among c > 0 states with the same
    sign of cos(phi), the larger |cos(phi)| is the main motion, the other light-side."""
    for m in motions:
        if m.group == 2:
            m.kind = "neutral_below" if m.below else "neutral_above"
    first = [m for m in motions if m.group == 1]
    for m in first:
        if m.c < 0:
            m.kind = "side_heavy"
    for below in (True, False):
        grp = sorted([m for m in first if m.c >= 0 and m.below == below],
                     key=lambda m: -abs(m.u))
        for k, m in enumerate(grp):
            if e0 > 1:          # e0 > 1: the main motion is the light-side maximal one
                m.kind = "main_below" if below else "main_above"
            else:
                m.kind = ("main_below" if below else "main_above") if k == 0 else "side_light"


def first_group(p: TwoAxisParams, tol=1e-12) -> List[SteadyMotion]:
    """First-group steady motions (sin phi~ != 0) with gravity, H >= 0 (6.33)-(6.40).

    u = cos(phi~) runs over the real roots of P(u) (6.36) in (-1, 1) (2 or 4 of them);
    with s = sign(u): sin(psi~) = s Q / sqrt(Q^2 + H^2 R_omega^2),
    cos(psi~) = -s H R_omega / sqrt(...), Q = R_omega^2 - 1 + R_omega^4 u / R_gm (6.37),
    and (xi~, eta~) from (6.38).  phi~ in (0, pi) (the flip phi -> -phi, psi -> psi + pi
    is the same motion).  Needs R_g > 0 and e0 > 0 (see :func:`no_gravity_no_damping`).
    """
    if p.R_g == 0:
        raise ValueError("first_group needs R_g > 0 [-]; use no_gravity_no_damping for R_g = 0")
    if p.e0 == 0:
        return []
    Rw, H = p.R_omega, p.H
    roots = np.roots(steady_polynomial(p))
    us = sorted({float(r.real) for r in roots
                 if abs(r.imag) <= 1e-7 * max(1.0, abs(r)) and -1 < r.real < 1})
    # polish on the quartic
    poly = np.poly1d(steady_polynomial(p))
    dpoly = poly.deriv()
    out = []
    for u in us:
        for _ in range(3):
            d = dpoly(u)
            if d != 0:
                u = u - poly(u) / d
        if not -1 < u < 1:
            continue
        Q = Rw ** 2 - 1 + Rw ** 4 * u / p.R_gm
        N = math.sqrt(Q * Q + H * H * Rw * Rw)
        s = 1.0 if u >= 0 else -1.0
        psi = math.atan2(s * Q / N, -s * H * Rw / N) if N > 0 else math.pi / 2
        K = p.R_m * Rw ** 2 * p.e0 / (N * N) if N > 0 else math.nan
        out.append(SteadyMotion(phi=math.acos(u), psi=psi, xi=-K * Q, eta=-K * H * Rw,
                                group=1, n=float(efficiency(p, u))))
    _classify(out, p.e0)
    return out


def second_group(p: TwoAxisParams) -> List[SteadyMotion]:
    """Second-group motions (6.29), (6.30): phi~ = 0 (CW hanging) and pi (upright).

    They exist at every speed and are always unstable (6.112).  psi~ is along the
    deflection (xi~ sin psi~ - eta~ cos psi~ = 0).
    """
    Rw, H = p.R_omega, p.H
    Dw = _D(Rw, H)
    K = p.R_m * Rw ** 2 * p.e0 / Dw
    xi, eta = -K * (Rw ** 2 - 1), -K * H * Rw
    psi = math.atan2(eta, xi) if (xi or eta) else 0.0
    return [SteadyMotion(phi=0.0, psi=psi, xi=xi, eta=eta, group=2, n=1.0),
            SteadyMotion(phi=math.pi, psi=psi, xi=xi, eta=eta, group=2, n=1.0)]


def no_gravity_no_damping(p: TwoAxisParams) -> List[SteadyMotion]:
    """First-group motions for R_g = 0 and H = 0, section 6.2.2, (6.46)-(6.51).

    psi~ = pi/2.  e0 < 1: main phi~1 = phi0 = arcsin e0 (below), phi~2 = pi - phi0
    (above), both with xi~ = eta~ = 0 (exact balance); side phi~3 = -pi/2 (heavy
    side), phi~4 = pi/2 (light side) with xi~ = -R_m R_omega^2 (e0 - sin phi~) / (R_omega^2 - 1),
    eta~ = 0 (from s3, s4 of (6.25)).
    e0 > 1: phi~1 = pi/2 (main, light side) and phi~2 = -pi/2 (side, heavy).
    Requires R_omega != 1.  Labels are set directly (the CM is on the pivot level for
    phi = +-pi/2).
    """
    if p.R_g != 0 or p.H != 0:
        raise ValueError(f"no_gravity_no_damping needs R_g = 0 and H = 0 [-], got "
                         f"R_g={p.R_g!r}, H={p.H!r}")
    Rw, e0 = p.R_omega, p.e0
    if Rw == 1:
        raise ValueError("no_gravity_no_damping: R_omega = 1 [-] (resonance) is singular")
    K = p.R_m * Rw ** 2

    def side(sf, kind):
        return SteadyMotion(phi=math.asin(sf), psi=math.pi / 2,
                            xi=-K * (e0 - sf) / (Rw ** 2 - 1), eta=0.0, group=1, kind=kind,
                            n=abs(e0 - sf) / e0 if e0 else math.nan)
    if e0 <= 1:
        ph0 = math.asin(e0)
        return [SteadyMotion(ph0, math.pi / 2, 0.0, 0.0, 1, "main_below", 0.0),
                SteadyMotion(math.pi - ph0, math.pi / 2, 0.0, 0.0, 1, "main_above", 0.0),
                side(-1.0, "side_heavy"), side(1.0, "side_light")]
    return [side(1.0, "main_light"), side(-1.0, "side_heavy")]


def steady_motions(p: TwoAxisParams, *, stability=True) -> List[SteadyMotion]:
    """All steady motions (first group then second), labelled, with eigenvalues.

    Uses :func:`first_group` (R_g > 0) or :func:`no_gravity_no_damping`
    (R_g = H = 0); the R_g = 0, H > 0 case is not covered by the book and raises.
    """
    if p.R_g > 0:
        motions = first_group(p) + second_group(p)
        _classify(motions, p.e0)
    elif p.H == 0:
        motions = no_gravity_no_damping(p) + second_group(p)
        _classify([m for m in motions if m.group == 2], p.e0)
    else:
        raise ValueError(f"steady_motions: R_g = 0 with H = {p.H!r} > 0 [-] is not treated "
                         "in ch. 6 (section 6.2.2 assumes H = 0)")
    if stability:
        for m in motions:
            m.eig = eigenvalues(p, m.state)
    return motions
