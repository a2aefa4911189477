"""The gravity-insensitive non-classical autobalancer: the coupled pair (book 7.1).

Digest ``ch7_ch1.md`` sections 0, 1 and 5 (Filimonikhin 2004, section 7.1).

Physical model (digest 1.2)
---------------------------
A vertical rotor in plane-parallel motion on isotropic visco-elastic supports
(stiffness ``c`` [N/m], external viscous coefficient ``H3`` [N s/m] on the
absolute velocity of the shaft point K) spins at the constant rate ``omega``
[rad/s].  Two identical correction weights (CWs) are coupled so that they turn
about transverse axes by equal angles in *opposite* directions: the upper one
hangs, the lower one is inverted, both centres of mass move sideways by
``l sin(phi)`` and their vertical shifts cancel, so gravity does no work
(digest 1.1).  The pair is modelled as one weight of mass ``m`` (the pair's
total), arm ``l`` [m], moment of inertia ``A`` [kg m^2] about the transverse
axes and ``B`` [kg m^2] about the rotor axis (both taken constant, as in the
book).  Its orientation is given by the transverse angle ``phi`` and the angle
about the rotor axis (``psi`` relative to the rotor, ``alpha = psi + R_omega
tau`` absolute).  The CWs' centre of mass sits, relative to the pivot, at the
complex horizontal offset ``l * i sin(phi) e^{i alpha}``.  Viscous moments act
on the relative rates: ``-H1 phi'`` and ``-H2 psi'`` [N m s].

Dimensionless variables, (7.3)-(7.5) with erratum E2 (``xi = x l / rho1^2``,
not the printed ``x / rho1``; the printed scale would not make ``R_m`` appear in
the rotor equations -- see :func:`GravityPairParams.from_physical` and the test
``test_e2_length_scale``)::

    tau = omega0 t,  omega0 = sqrt(c / M_Sigma),  rho1 = sqrt(A/m), rho2 = sqrt(B/m)
    z = (x + i y) l / rho1^2           (fixed frame)
    R_m = m l^2/(M_Sigma rho1^2),  R_omega = omega/omega0,  R_rho = rho2/rho1,
    h1 = H1/(A omega0),  h2 = H2/(B omega0),  H = H3/(M_Sigma omega0),
    e0 = M e/(m l).

Equations of motion, fixed frame, (7.34) (verified by the digest and again here
by a Lagrangian derivation with sympy)::

    phi'' + h1 phi' + Im(z'' e^{-i alpha}) cos(phi) = 0
    [alpha'' + h2 (alpha' - R_omega)] R_rho^2 - Re(z'' e^{-i alpha}) sin(phi) = 0
    z'' + H z' + z - R_m < {(2 alpha' phi' - i phi'') cos(phi)
          + [alpha'' + i (phi'^2 + alpha'^2)] sin(phi)} e^{i alpha}
          + R_omega^2 e0 e^{i (R_omega tau + gamma)} > = 0

The rotating-frame form is (7.2) with erratum E1: the braces of the two rotor
equations contain ``phi''`` and ``psi''`` where the print (an OCR loss) has
``phi'`` and ``psi'``.  :func:`rhs_rotating` implements the corrected form and,
with ``printed_e1=True``, the printed one (for the erratum test only).

The second derivatives enter linearly; eliminating ``z''`` decouples the two
weight equations exactly (the 4x4 mass matrix has the determinant
``(1 - R_m cos^2 phi)(R_rho^2 - R_m sin^2 phi)`` times a constant, cf. the
coefficient a_8 of (7.13)), so each right-hand-side evaluation is closed form:

    phi''  (1 - R_m cos^2 phi)         = -h1 phi' - cos(phi) Im(F e^{-i alpha})
    alpha''(R_rho^2 - R_m sin^2 phi)  = -h2 R_rho^2 (alpha' - R_omega) + sin(phi) Re(F e^{-i alpha})

with ``F = -H z' - z + R_m[(2 alpha' phi' cos phi + i (phi'^2 + alpha'^2) sin phi) e^{i alpha}
+ R_omega^2 e0 e^{i(R_omega tau + gamma)}]`` and then
``z'' = F + R_m (alpha'' sin phi - i phi'' cos phi) e^{i alpha}``.

State vectors
-------------
Fixed frame (:func:`rhs`)::

    y = [phi, alpha, x, y, phi', alpha', x', y']     (rad, rad, -, -, per tau ...)

Rotating frame (:func:`rhs_rotating`)::

    y = [phi, psi, xi, eta, phi', psi', xi', eta']

with ``psi = alpha - R_omega tau`` and ``xi + i eta = z e^{-i R_omega tau}`` (7.35).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import minimize_scalar

__all__ = [
    "GravityPairParams", "SteadyMotion", "rhs", "rhs_rotating", "make_rhs",
    "to_rotating", "to_fixed", "energy", "simulate",
    "steady_motions", "side_band", "jacobian", "eigenvalues", "is_stable",
    "D", "qp_polynomial", "qp_roots", "qp_frequency", "qp_frequency_approx",
    "qp_frequency_approx_printed", "qp_family_limit", "qp_family_limit_exact",
    "qp_amplitudes", "qp_amplitudes_printed", "qp_radius_range", "qp_orbit",
    "qp_initial_state", "orbit_radius_range",
]


# ---------------------------------------------------------------------------
# input checks
# ---------------------------------------------------------------------------

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
class GravityPairParams:
    """Dimensionless parameters of the coupled pair, (7.4) with E2.

    Parameters
    ----------
    R_m : float
        ``m l^2 / (M_Sigma rho1^2)`` [-], 0 <= R_m < min(1, R_rho^2).
    R_omega : float
        Spin speed ``omega / omega0`` [-], >= 0.
    R_rho : float
        ``rho2 / rho1 = sqrt(B/A)`` [-], > 0.
    h1, h2 : float
        Relative viscous damping of the transverse (``phi``) and axial
        (``psi``) rotations, ``H1/(A omega0)``, ``H2/(B omega0)`` [-], >= 0.
    H : float
        External (support) viscous damping ``H3/(M_Sigma omega0)`` [-], >= 0.
    e0 : float
        Rotor unbalance in units of the pair's capacity, ``M e / (m l)`` [-], >= 0.
    gamma : float
        Unbalance angle in the rotor frame [rad].
    """

    R_m: float
    R_omega: float
    R_rho: float = 1.0
    h1: float = 0.05
    h2: float = 0.05
    H: float = 0.05
    e0: float = 0.0
    gamma: float = 0.0

    def __post_init__(self):
        for name in ("R_m", "R_omega", "h1", "h2", "H", "e0"):
            object.__setattr__(self, name, _nonneg(name, getattr(self, name), "dimensionless"))
        object.__setattr__(self, "R_rho", _pos("R_rho", self.R_rho, "dimensionless"))
        object.__setattr__(self, "gamma", _finite("gamma", self.gamma, "rad"))
        if self.R_m >= 1.0 or self.R_m >= self.R_rho ** 2:
            raise ValueError(
                f"R_m must be < min(1, R_rho^2) = {min(1.0, self.R_rho ** 2):g} [dimensionless] "
                f"(the mass matrix (1 - R_m cos^2 phi)(R_rho^2 - R_m sin^2 phi) must stay "
                f"positive), got {self.R_m!r}")

    # -- derived quantities -------------------------------------------------
    @property
    def R_mH(self) -> float:
        """``R_m H / (h2 R_rho^2)`` [-], the parameter of the QP frequency equation."""
        if self.h2 == 0.0:
            return math.inf
        return self.R_m * self.H / (self.h2 * self.R_rho ** 2)

    @property
    def phi0(self) -> float:
        """``arcsin(e0)`` [rad] (7.7); NaN when the capacity is insufficient (e0 > 1)."""
        return math.asin(self.e0) if self.e0 <= 1.0 else math.nan

    def with_speed(self, R_omega: float) -> "GravityPairParams":
        """The same parameters at another speed ``R_omega`` [-]."""
        return replace(self, R_omega=R_omega)

    @classmethod
    def from_physical(cls, M: float, c: float, omega: float, m: float, A: float, B: float,
                      l: float, H1: float, H2: float, H3: float, e: float,
                      gamma: float = 0.0, *, M_sigma: float | None = None) -> "GravityPairParams":
        """Build the dimensionless parameters from the twelve SI parameters (7.1).

        Parameters
        ----------
        M : float
            Rotor mass without the CWs [kg] (the mass carrying the eccentricity ``e``).
        c : float
            Isotropic support stiffness [N/m].
        omega : float
            Spin rate [rad/s].
        m : float
            Mass of the CW *pair* (both weights) [kg] (digest 1.1 inference).
        A, B : float
            Pair moments of inertia about the transverse and the rotor axis
            through the pivot [kg m^2].
        l : float
            Arm of each CW (pivot to centre of mass) [m].
        H1, H2 : float
            Viscous moment coefficients [N m s]: the moments are ``-H1 phi_t``
            and ``-H2 psi_t``.  The digest writes ``-2 H1 phi_t`` yet scales
            ``h1 = H1/(m rho1^2 omega0)`` with ``phi'' + h1 phi'`` in (7.2),
            which is a factor-2 inconsistency; here ``h1 = H1/(A omega0)``
            exactly matches the dimensionless equations.
        H3 : float
            External viscous coefficient of the supports [N s/m].
        e : float
            Rotor eccentricity [m].
        gamma : float
            Unbalance angle [rad].
        M_sigma : float, optional
            Total moving mass [kg]; default ``M + m`` (the book is ambiguous,
            digest 5 E0).

        Returns
        -------
        GravityPairParams
        """
        M = _pos("M", M, "kg"); c = _pos("c", c, "N/m"); omega = _nonneg("omega", omega, "rad/s")
        m = _pos("m", m, "kg"); A = _pos("A", A, "kg m^2"); B = _pos("B", B, "kg m^2")
        l = _pos("l", l, "m"); H1 = _nonneg("H1", H1, "N m s"); H2 = _nonneg("H2", H2, "N m s")
        H3 = _nonneg("H3", H3, "N s/m"); e = _nonneg("e", e, "m")
        Ms = M + m if M_sigma is None else _pos("M_sigma", M_sigma, "kg")
        w0 = math.sqrt(c / Ms)
        rho1_sq = A / m
        return cls(R_m=m * l * l / (Ms * rho1_sq), R_omega=omega / w0, R_rho=math.sqrt(B / A),
                   h1=H1 / (A * w0), h2=H2 / (B * w0), H=H3 / (Ms * w0), e0=M * e / (m * l),
                   gamma=gamma)

    @staticmethod
    def length_scale(m: float, A: float, l: float) -> float:
        """Factor turning a shaft displacement [m] into the dimensionless ``xi``:
        ``l / rho1^2 = m l / A`` [1/m] (E2; the print has ``1/rho1``)."""
        return _pos("m", m, "kg") * _pos("l", l, "m") / _pos("A", A, "kg m^2")


# ---------------------------------------------------------------------------
# equations of motion
# ---------------------------------------------------------------------------

def rhs(tau: float, y, p: GravityPairParams) -> np.ndarray:
    """Fixed-frame right-hand side of (7.34), usable with ``solve_ivp``.

    Parameters
    ----------
    tau : float
        Dimensionless time ``omega0 t`` [-].
    y : array_like, shape (8,)
        ``[phi, alpha, x, y, phi', alpha', x', y']`` (angles in rad, shaft
        position in units of ``rho1^2 / l``, derivatives per unit ``tau``).
    p : GravityPairParams

    Returns
    -------
    numpy.ndarray, shape (8,)
    """
    phi, al, x, yy, dphi, dal, dx, dy = y
    Rm, Rw = p.R_m, p.R_omega
    sp, cp = math.sin(phi), math.cos(phi)
    ea = complex(math.cos(al), math.sin(al))
    ub = Rw * Rw * p.e0 * complex(math.cos(Rw * tau + p.gamma), math.sin(Rw * tau + p.gamma))
    F = (-p.H * complex(dx, dy) - complex(x, yy)
         + Rm * ((2.0 * dal * dphi * cp + 1j * (dphi * dphi + dal * dal) * sp) * ea + ub))
    w = F * ea.conjugate()
    ddphi = (-p.h1 * dphi - cp * w.imag) / (1.0 - Rm * cp * cp)
    R2 = p.R_rho * p.R_rho
    ddal = (-p.h2 * R2 * (dal - Rw) + sp * w.real) / (R2 - Rm * sp * sp)
    zdd = F + Rm * (ddal * sp - 1j * ddphi * cp) * ea
    return np.array([dphi, dal, dx, dy, ddphi, ddal, zdd.real, zdd.imag])


def rhs_rotating(tau: float, y, p: GravityPairParams, *, printed_e1: bool = False) -> np.ndarray:
    """Rotating-frame right-hand side of (7.2) with erratum E1.

    Parameters
    ----------
    tau : float
        Dimensionless time [-] (unused: the rotating-frame system is autonomous).
    y : array_like, shape (8,)
        ``[phi, psi, xi, eta, phi', psi', xi', eta']`` [rad, rad, -, -, ...].
    p : GravityPairParams
    printed_e1 : bool
        ``False`` (default): the corrected braces ``[phi'' sin psi + ...]``,
        ``[psi'' cos psi ...]``, ``[psi'' sin psi ...]``, ``[phi'' cos psi ...]``.
        ``True``: the printed (OCR) form with ``phi'``, ``psi'`` in those four
        places -- physically wrong, kept only to demonstrate E1.

    Returns
    -------
    numpy.ndarray, shape (8,)
    """
    phi, psi, xi, eta, dphi, dpsi, dxi, deta = y
    Rm, Rw = p.R_m, p.R_omega
    sp, cp = math.sin(phi), math.cos(phi)
    ep = complex(math.cos(psi), math.sin(psi))
    zeta, dzeta = complex(xi, eta), complex(dxi, deta)
    dal = dpsi + Rw
    # absolute acceleration A = zeta'' + 2 i Rw zeta' - Rw^2 zeta; rotor equation:
    # A + H (zeta' + i Rw zeta) + zeta - R_m{[(2 al' phi' - i phi'') cos phi
    #   + (psi'' + i (phi'^2 + al'^2)) sin phi] e^{i psi} + Rw^2 e0 e^{i gamma}} = 0
    F = (-p.H * (dzeta + 1j * Rw * zeta) - zeta
         + Rm * ((2.0 * dal * dphi * cp + 1j * (dphi * dphi + dal * dal) * sp) * ep
                 + Rw * Rw * p.e0 * complex(math.cos(p.gamma), math.sin(p.gamma))))
    R2 = p.R_rho * p.R_rho
    if printed_e1:
        # the printed braces: phi' and psi' instead of phi'' and psi''
        Aacc = F + Rm * (dpsi * sp - 1j * dphi * cp) * ep
        w = Aacc * ep.conjugate()
        ddphi = -p.h1 * dphi - cp * w.imag
        ddpsi = -p.h2 * dpsi + sp * w.real / R2
    else:
        w = F * ep.conjugate()
        ddphi = (-p.h1 * dphi - cp * w.imag) / (1.0 - Rm * cp * cp)
        ddpsi = (-p.h2 * R2 * dpsi + sp * w.real) / (R2 - Rm * sp * sp)
        Aacc = F + Rm * (ddpsi * sp - 1j * ddphi * cp) * ep
    zdd = Aacc - 2j * Rw * dzeta + Rw * Rw * zeta
    return np.array([dphi, dpsi, dxi, deta, ddphi, ddpsi, zdd.real, zdd.imag])


def make_rhs(p: GravityPairParams, frame: str = "fixed"):
    """``f(tau, y)`` closure for ``solve_ivp`` (``frame`` = ``"fixed"`` or ``"rotating"``)."""
    if frame == "fixed":
        return lambda t, y: rhs(t, y, p)
    if frame == "rotating":
        return lambda t, y: rhs_rotating(t, y, p)
    raise ValueError(f"frame must be 'fixed' or 'rotating' [-], got {frame!r}")


def to_rotating(tau, y, R_omega: float) -> np.ndarray:
    """Fixed-frame state(s) -> rotating-frame state(s), (7.35).

    Parameters
    ----------
    tau : float or array_like, shape (n,)
        Time(s) [-].
    y : array_like, shape (8,) or (8, n)
        Fixed-frame state(s) (layout of :func:`rhs`).
    R_omega : float
        Spin speed [-].
    """
    y = np.asarray(y, dtype=float)
    tau = np.asarray(tau, dtype=float)
    e = np.exp(-1j * R_omega * tau)
    z = y[2] + 1j * y[3]
    dz = y[6] + 1j * y[7]
    zeta = z * e
    dzeta = (dz - 1j * R_omega * z) * e
    return np.array([y[0], y[1] - R_omega * tau, zeta.real, zeta.imag,
                     y[4], y[5] - R_omega, dzeta.real, dzeta.imag])


def to_fixed(tau, y, R_omega: float) -> np.ndarray:
    """Rotating-frame state(s) -> fixed-frame state(s) (inverse of :func:`to_rotating`)."""
    y = np.asarray(y, dtype=float)
    tau = np.asarray(tau, dtype=float)
    e = np.exp(1j * R_omega * tau)
    zeta = y[2] + 1j * y[3]
    dzeta = y[6] + 1j * y[7]
    z = zeta * e
    dz = (dzeta + 1j * R_omega * zeta) * e
    return np.array([y[0], y[1] + R_omega * tau, z.real, z.imag,
                     y[4], y[5] + R_omega, dz.real, dz.imag])


def energy(y, p: GravityPairParams) -> float:
    """Mechanical energy of the fixed-frame system [-] (units ``M_Sigma rho1^4 omega0^2 / l^2``).

    ``E = |z'|^2/2 + |z|^2/2 + R_m Re(conj(z') w') + R_m (phi'^2 + R_rho^2 alpha'^2)/2``,
    ``w = i sin(phi) e^{i alpha}``.  Conserved when ``h1 = h2 = H = e0 = 0``
    (the Lagrangian behind (7.34)); used by the E1 test.
    """
    phi, al, x, yy, dphi, dal, dx, dy = np.asarray(y, dtype=float)
    dz = complex(dx, dy)
    dw = (1j * math.cos(phi) * dphi - math.sin(phi) * dal) * complex(math.cos(al), math.sin(al))
    return (0.5 * abs(dz) ** 2 + 0.5 * (x * x + yy * yy) + p.R_m * (dz.conjugate() * dw).real
            + 0.5 * p.R_m * (dphi ** 2 + p.R_rho ** 2 * dal ** 2))


def simulate(p: GravityPairParams, y0, t_end: float, *, frame: str = "fixed",
             t_eval=None, rtol: float = 1e-8, atol: float = 1e-10, method: str = "DOP853"):
    """Integrate from ``tau = 0`` to ``t_end`` [-] with ``solve_ivp`` (DOP853 by default).

    Returns the ``solve_ivp`` result object; raises ``RuntimeError`` if it fails.
    """
    t_end = _pos("t_end", t_end, "dimensionless time")
    y0 = np.asarray(y0, dtype=float)
    if y0.shape != (8,):
        raise ValueError(f"y0 must have shape (8,) [state], got {y0.shape}")
    sol = solve_ivp(make_rhs(p, frame), (0.0, t_end), y0, method=method, rtol=rtol,
                    atol=atol, t_eval=t_eval)
    if not sol.success:
        raise RuntimeError(f"integration failed: {sol.message}")
    return sol


# ---------------------------------------------------------------------------
# steady (synchronous) motions (7.6)-(7.9)
# ---------------------------------------------------------------------------

@dataclass(frozen=True)
class SteadyMotion:
    """A steady synchronous motion: an equilibrium of the rotating-frame system.

    Attributes
    ----------
    label : int
        The book's index (Fig. 7.7 for e0 < 1, Fig. 7.8 for e0 > 1).
    kind : str
        ``"main"``, ``"side-1"`` (first group: CWs fully deflected) or
        ``"side-2"`` (second group: CW centre of mass on the axis).
    phi, psi : float
        Transverse angle and angle relative to the rotor [rad].
    xi, eta : float
        Rotating-frame shaft deflection [-].
    """

    label: int
    kind: str
    phi: float
    psi: float
    xi: float
    eta: float

    @property
    def state(self) -> np.ndarray:
        """Rotating-frame state vector (rates zero)."""
        return np.array([self.phi, self.psi, self.xi, self.eta, 0.0, 0.0, 0.0, 0.0])

    @property
    def deflection(self) -> float:
        """Shaft deflection ``|xi + i eta|`` [-]."""
        return math.hypot(self.xi, self.eta)


def _wrap(a):
    return (a + math.pi) % (2.0 * math.pi) - math.pi


def steady_motions(p: GravityPairParams) -> list[SteadyMotion]:
    """All steady motions at ``p.R_omega`` (solutions of (7.6)).

    For ``e0 < 1`` (7.7): main motions 1 (``phi = arcsin e0``) and 2
    (``pi - arcsin e0``) with ``xi = eta = 0``; first-group side motions 3
    (heavy side, ``phi = -pi/2``) and 4 (light side, ``phi = pi/2``) only
    outside the band (7.8); second-group side motions 5 (``phi = 0``) and 6
    (``phi = pi``).  For ``e0 > 1`` (7.9): 1 (light side, main), 2 (heavy
    side), 3 (``phi = 0``), 4 (``phi = pi``).  First-group motions are labelled by
    continuity of the two roots of their quadratic (see the code comment); the
    heavy-side branch is written with ``phi = -pi/2`` (the book's convention).

    Returns
    -------
    list of SteadyMotion, sorted by label.
    """
    Rw, Rm, e0, g = p.R_omega, p.R_m, p.e0, p.gamma
    if Rw == 0.0:
        raise ValueError("R_omega must be > 0 [dimensionless] for steady motions, got 0.0")
    K = complex(Rw * Rw - 1.0, -p.H * Rw)         # (R^2 - 1 - i H R) zeta = -R_m R^2 (...)
    cR = Rm * Rw * Rw
    eg = complex(math.cos(g), math.sin(g))
    out = []
    small = e0 < 1.0
    if small:
        ph0 = math.asin(e0)
        psi_m = _wrap(g + math.pi / 2)
        out.append(SteadyMotion(1, "main", ph0, psi_m, 0.0, 0.0))
        out.append(SteadyMotion(2, "main", math.pi - ph0, psi_m, 0.0, 0.0))
    # first group: sin(phi) = +1, zeta = i t e^{i psi}, |K t + cR| = cR e0
    if cR > 0.0:
        a2 = abs(K) ** 2
        a1 = 2.0 * K.real * cR
        a0 = cR * cR * (1.0 - e0 * e0)
        disc = a1 * a1 - 4.0 * a2 * a0
        if disc >= 0.0:
            sq = math.sqrt(disc)
            for k, t in enumerate(((-a1 + sq) / (2 * a2), (-a1 - sq) / (2 * a2))):
                q = K * t + cR
                eip = -cR * e0 * eg / (1j * q) if e0 > 0 else 1j
                psi = math.atan2(eip.imag, eip.real)
                zeta = 1j * t * complex(math.cos(psi), math.sin(psi))
                # The larger root t is the light-side branch above resonance and the
                # heavy-side branch below it (H -> 0: t = R_m R^2 (-1 +- e0)/(R^2 - 1));
                # the roots stay distinct inside each region, so this labelling is
                # continuous (a side test fails near the band edges, where the two
                # branches merge).
                heavy = (k == 0) == (Rw < 1.0)
                phi = -math.pi / 2 if heavy else math.pi / 2
                if heavy:                       # same configuration, book convention phi < 0
                    psi += math.pi
                if small:
                    lab, kind = (3, "side-1") if heavy else (4, "side-1")
                else:
                    lab, kind = (2, "side-1") if heavy else (1, "main")
                out.append(SteadyMotion(lab, kind, phi, _wrap(psi), zeta.real, zeta.imag))
    # second group: sin(phi) = 0
    zeta = -cR * e0 * eg / K
    psi = math.atan2(zeta.imag, zeta.real) if abs(zeta) > 0 else 0.0
    base = 5 if small else 3
    out.append(SteadyMotion(base, "side-2", 0.0, psi, zeta.real, zeta.imag))
    out.append(SteadyMotion(base + 1, "side-2", math.pi, psi, zeta.real, zeta.imag))
    return sorted(out, key=lambda s: s.label)


def side_band(p: GravityPairParams) -> tuple[float, float]:
    """Band ``(R^(1), R^(2))`` of (7.8) where the first-group side motions do not exist.

    Requires ``0 < e0 < 1``.  ``R^(1/2) = sqrt(1 + H^2/(4 tg^2 phi0)) -/+ H/(2 tg phi0)``.
    """
    if not (0.0 < p.e0 < 1.0):
        raise ValueError(f"e0 must be in (0, 1) [capacity units] for (7.8), got {p.e0!r}")
    k = p.H / (2.0 * math.tan(p.phi0))
    r = math.sqrt(1.0 + k * k)
    return r - k, r + k


# ---------------------------------------------------------------------------
# stability: numerical Jacobian of the rotating-frame system
# ---------------------------------------------------------------------------

def jacobian(p: GravityPairParams, y, *, step: float = 1e-6) -> np.ndarray:
    """Central-difference Jacobian (8x8) of :func:`rhs_rotating` at the state ``y``."""
    y = np.asarray(y, dtype=float)
    J = np.empty((8, 8))
    for k in range(8):
        d = np.zeros(8)
        d[k] = step
        J[:, k] = (rhs_rotating(0.0, y + d, p) - rhs_rotating(0.0, y - d, p)) / (2 * step)
    return J


def eigenvalues(p: GravityPairParams, motion: SteadyMotion) -> np.ndarray:
    """Characteristic roots of a steady motion (the numerical counterpart of
    (7.11), (7.21)-(7.22), (7.26)), sorted by decreasing real part."""
    lam = np.linalg.eigvals(jacobian(p, motion.state))
    return lam[np.argsort(-lam.real)]


def is_stable(p: GravityPairParams, motion: SteadyMotion, *, tol: float = 1e-7) -> bool:
    """Asymptotic stability: all roots with real part < ``-tol``."""
    return bool(np.all(eigenvalues(p, motion).real < -tol))


# ---------------------------------------------------------------------------
# quasi-periodic motions (1.6): (7.38)-(7.46), errata E3, E4, E5
# ---------------------------------------------------------------------------

def D(w, H: float):
    """``D(w) = (w^2 - 1)^2 + H^2 w^2`` [-] (squared modulus of ``1 + i H w - w^2``)."""
    w = np.asarray(w, dtype=float)
    return (w * w - 1.0) ** 2 + H * H * w * w


def qp_polynomial(Omega, p: GravityPairParams):
    """``P(Omega) = R_mH Omega^5 - (R_omega - Omega) D(Omega)`` [-], the precession-frequency
    equation (second of (7.39) at ``phi = pi/2``; the same as (6.132))."""
    Omega = np.asarray(Omega, dtype=float)
    return p.R_mH * Omega ** 5 - (p.R_omega - Omega) * D(Omega, p.H)


def qp_roots(p: GravityPairParams) -> np.ndarray:
    """All positive real roots of ``P(Omega)`` [-], ascending (polynomial of degree 5)."""
    if p.h2 == 0.0:
        raise ValueError("h2 must be > 0 [dimensionless] for the QP theory (R_mH = R_m H/(h2 R_rho^2)), got 0.0")
    H2, R = p.H * p.H, p.R_omega
    # (Omega - R)(Omega^4 + (H^2 - 2) Omega^2 + 1) + R_mH Omega^5
    d = np.array([1.0, 0.0, H2 - 2.0, 0.0, 1.0])
    poly = np.polymul([1.0, -R], d)
    poly[0] += p.R_mH
    r = np.roots(poly)
    r = r[(np.abs(r.imag) < 1e-9 * np.maximum(1.0, np.abs(r))) & (r.real > 0)].real
    return np.sort(r)


def qp_frequency(p: GravityPairParams) -> float:
    """Absolute CW speed ``Omega`` [-] of the stable QP family (7.40): the root of
    ``P`` in (0, 1); NaN if none (``R_omega`` outside the existence range)."""
    r = qp_roots(p)
    r = r[r < 1.0]
    return float(r.max()) if r.size else math.nan


def qp_frequency_approx(p: GravityPairParams) -> float:
    """Small-``H`` asymptotics of the QP frequency [-], corrected (E5):
    ``Omega ~ 1 - sqrt(R_mH/(R_omega - 1) - H^2) / 2`` (NaN outside the range)."""
    if p.R_omega <= 1.0:
        return math.nan
    a = p.R_mH / (p.R_omega - 1.0) - p.H ** 2
    return 1.0 - 0.5 * math.sqrt(a) if a >= 0 else math.nan


def qp_frequency_approx_printed(p: GravityPairParams) -> float:
    """The printed (7.42) ``1 - sqrt(R_m H / (h2 (R_omega - 1)))`` [-] (E5: wrong; for comparison)."""
    return 1.0 - math.sqrt(p.R_m * p.H / (p.h2 * (p.R_omega - 1.0)))


def qp_family_limit(p: GravityPairParams) -> float:
    """Upper speed of the stable QP family, (7.41) corrected (E4) [-]:
    ``R*_omega = 1 + R_m/(h2 H R_rho^2) = 1 + R_mH / H^2``.

    (The print has ``R_rho`` instead of ``R_rho^2``; Ch. 5/6 print a factor 2
    that the root scan of this system contradicts -- digest E4.)"""
    if p.H == 0.0 or p.h2 == 0.0:
        return math.inf
    return 1.0 + p.R_mH / p.H ** 2


def qp_family_limit_exact(p: GravityPairParams) -> tuple[float, float]:
    """Exact speed where the two roots of ``P`` near 1 merge, and the merged ``Omega`` [-].

    ``P`` is linear in ``R_omega``: ``R_omega(Omega) = Omega + R_mH Omega^5 / D(Omega)``; the
    family ends at the local maximum of this curve near ``Omega = 1``.
    """
    if p.H == 0.0:
        return math.inf, 1.0
    f = lambda w: -(w + p.R_mH * w ** 5 / D(w, p.H))
    lo = max(0.3, 1.0 - 4.0 * p.H)
    res = minimize_scalar(f, bounds=(lo, 1.0 + 2.0 * p.H), method="bounded",
                          options={"xatol": 1e-12})
    return float(-res.fun), float(res.x)


def qp_amplitudes(p: GravityPairParams, Omega: float | None = None,
                  phi: float = math.pi / 2) -> tuple[float, float]:
    """Precession and nutation amplitudes (7.43)-(7.46), corrected (E3) [-].

    ``A_P = R_m Omega^2 |sin phi| / sqrt(D(Omega))``,
    ``A_N = R_m R_omega^2 e0 / sqrt(D(R_omega))``.
    ``Omega`` defaults to :func:`qp_frequency`.
    """
    if Omega is None:
        Omega = qp_frequency(p)
    Ap = p.R_m * Omega ** 2 * abs(math.sin(phi)) / math.sqrt(float(D(Omega, p.H)))
    An = p.R_m * p.R_omega ** 2 * p.e0 / math.sqrt(float(D(p.R_omega, p.H)))
    return Ap, An


def qp_amplitudes_printed(p: GravityPairParams, Omega: float | None = None) -> tuple[float, float]:
    """The printed (7.38) amplitudes, without ``Omega^2`` and ``R_omega^2`` (E3; wrong)."""
    if Omega is None:
        Omega = qp_frequency(p)
    return (p.R_m / math.sqrt(float(D(Omega, p.H))),
            p.R_m * p.e0 / math.sqrt(float(D(p.R_omega, p.H))))


def qp_radius_range(p: GravityPairParams, Omega: float | None = None) -> tuple[float, float]:
    """Predicted range ``[A_P - A_N, A_P + A_N]`` of the orbit radius ``|z|`` [-] (E3)."""
    Ap, An = qp_amplitudes(p, Omega)
    return abs(Ap - An), Ap + An


def qp_orbit(p: GravityPairParams, tau, Omega: float | None = None, gamma: float = 0.0,
             phi: float = math.pi / 2) -> np.ndarray:
    """Shaft law of the QP motion, (7.38) corrected (E3), complex ``z(tau)`` [-]::

        z = i R_m Omega^2 sin(phi) e^{i(Omega tau + gamma)} / (1 + i H Omega - Omega^2)
          + R_m R_omega^2 e0 e^{i(R_omega tau + p.gamma)} / (1 + i H R_omega - R_omega^2)
    """
    if Omega is None:
        Omega = qp_frequency(p)
    tau = np.asarray(tau, dtype=float)
    R = p.R_omega
    zp = 1j * p.R_m * Omega ** 2 * math.sin(phi) / complex(1.0 - Omega ** 2, p.H * Omega)
    zn = p.R_m * R * R * p.e0 / complex(1.0 - R * R, p.H * R)
    return zp * np.exp(1j * (Omega * tau + gamma)) + zn * np.exp(1j * (R * tau + p.gamma))


def qp_initial_state(p: GravityPairParams, Omega: float | None = None,
                     phi: float = math.pi / 2 - 0.02) -> np.ndarray:
    """A fixed-frame starting state on the (approximate) QP family (digest 5, E3)."""
    if Omega is None:
        Omega = qp_frequency(p)
    if not math.isfinite(Omega):
        raise ValueError(f"no QP family at R_omega = {p.R_omega!r} [dimensionless]")
    z0 = complex(qp_orbit(p, 0.0, Omega, 0.0, phi))
    R = p.R_omega
    zp = 1j * p.R_m * Omega ** 2 * math.sin(phi) / complex(1.0 - Omega ** 2, p.H * Omega)
    zn = p.R_m * R * R * p.e0 / complex(1.0 - R * R, p.H * R) * complex(math.cos(p.gamma), math.sin(p.gamma))
    dz0 = 1j * Omega * zp + 1j * R * zn
    return np.array([phi, 0.0, z0.real, z0.imag, 0.0, Omega, dz0.real, dz0.imag])


def orbit_radius_range(sol, t_from: float) -> tuple[float, float]:
    """Min and max of ``|z|`` [-] over the samples of a fixed-frame solution with ``t >= t_from``."""
    k = sol.t >= t_from
    r = np.hypot(sol.y[2, k], sol.y[3, k])
    return float(r.min()), float(r.max())
