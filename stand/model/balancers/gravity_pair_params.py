"""GravityPairParams: the dimensionless parameters (7.4) of the coupled pair of book 7.1,
with erratum E2 (the length scale ``l / rho1^2``) and their physical form (7.3)-(7.5).

The model itself is described in :mod:`stand.model.balancers.gravity_pair`.  This is the
bottom module of the pair: its frames, steady motions and quasi-periodic motions import
the parameters from here, never the other way round.
"""
from __future__ import annotations

from dataclasses import dataclass, replace
import math

from stand.model.balancers._params import BOOK, group

__all__ = ["GravityPairParams"]


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
        BOOK.fields(self, *group(("R_m", "R_omega", "h1", "h2", "H", "e0"), "dimensionless", ">= 0"),
                    ("R_rho", "dimensionless", "> 0"), ("gamma", "rad", "finite"))
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
        M, c, omega, m, A, B, l, H1, H2, H3, e = BOOK.each(
            ("M", M, "kg", "> 0"), ("c", c, "N/m", "> 0"), ("omega", omega, "rad/s", ">= 0"),
            ("m", m, "kg", "> 0"), ("A", A, "kg m^2", "> 0"), ("B", B, "kg m^2", "> 0"),
            ("l", l, "m", "> 0"), ("H1", H1, "N m s", ">= 0"), ("H2", H2, "N m s", ">= 0"),
            ("H3", H3, "N s/m", ">= 0"), ("e", e, "m", ">= 0"))
        Ms = M + m if M_sigma is None else BOOK.positive("M_sigma", M_sigma, "kg")
        w0 = math.sqrt(c / Ms)
        rho1_sq = A / m
        return cls(R_m=m * l * l / (Ms * rho1_sq), R_omega=omega / w0, R_rho=math.sqrt(B / A),
                   h1=H1 / (A * w0), h2=H2 / (B * w0), H=H3 / (Ms * w0), e0=M * e / (m * l),
                   gamma=gamma)

    @staticmethod
    def length_scale(m: float, A: float, l: float) -> float:
        """Factor turning a shaft displacement [m] into the dimensionless ``xi``:
        ``l / rho1^2 = m l / A`` [1/m] (E2; the print has ``1/rho1``)."""
        m, l, A = BOOK.each(("m", m, "kg", "> 0"), ("l", l, "m", "> 0"), ("A", A, "kg m^2", "> 0"))
        return m * l / A
