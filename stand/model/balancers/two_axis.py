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

Modules
-------
This module holds the parameters and re-exports the model's functions from
:mod:`.two_axis_motion` (equations (6.12), (6.15), run-up, frame changes) and
:mod:`.two_axis_steady` (linearisation, steady motions of section 6.2), so
``stand.model.balancers.two_axis.<name>`` keeps working for all of them; the theory
of sections 6.3-6.5 is in :mod:`.two_axis_theory`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

from stand.model.balancers._params import BOOK, group
from stand.model.balancers.two_axis_motion import (fixed_to_rotating, linear_ramp, residual_fixed, residual_rotating,
                              rhs_fixed, rhs_fixed_variable_speed, rhs_rotating, rotating_to_fixed)
from stand.model.balancers.two_axis_steady import (SteadyMotion, efficiency, eigenvalues, first_group, jacobian,
                              max_real_part, no_gravity_no_damping, r0, second_group,
                              steady_motions, steady_polynomial)

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
        BOOK.fields(self, *group(("R_m", "R_rho"), "-", "> 0"),
                    *group(("R_omega", "R_g", "h1", "h2", "H", "e0"), "-", ">= 0"))
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
        R_gm = BOOK.nonneg("R_gm", R_gm, "-")
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
        M, m, l, A, B, c, omega, e, H1, H2, H3, g = BOOK.each(
            ("M", M, "kg", "> 0"), ("m", m, "kg", "> 0"), ("l", l, "m", "> 0"),
            ("A", A, "kg m^2", "> 0"), ("B", B, "kg m^2", "> 0"), ("c", c, "N/m", "> 0"),
            ("omega", omega, "rad/s", ">= 0"), ("e", e, "m", ">= 0"), ("H1", H1, "N m s/rad", ">= 0"),
            ("H2", H2, "N m s/rad", ">= 0"), ("H3", H3, "N s/m", ">= 0"), ("g", g, "m/s^2", ">= 0"))
        for name, value in (("A", A), ("B", B)):
            if value < m * l * l:
                raise BOOK.error(name, value, "kg m^2", f">= m l^2 = {m * l * l:.6g}")
        Ms = M + m
        w0 = math.sqrt(c / Ms)
        rho1_2 = A / m
        return cls(R_m=m * l * l / (Ms * rho1_2), R_omega=omega / w0,
                   R_g=math.sqrt(g * l / (rho1_2 * w0 * w0)), R_rho=math.sqrt(B / A),
                   h1=H1 / (A * w0), h2=H2 / (B * w0), H=H3 / (Ms * w0), e0=M * e / (m * l))

    @staticmethod
    def length_scale(m, l, A) -> float:
        """rho1^2 / l = A / (m l) [m]: multiply xi, eta (or x, y) by it for metres."""
        A, m, l = BOOK.each(("A", A, "kg m^2", "> 0"), ("m", m, "kg", "> 0"), ("l", l, "m", "> 0"))
        return A / (m * l)
