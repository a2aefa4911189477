"""TwoAxisParams: the dimensionless parameters (6.9)-(6.11) of the two-axis pendulum CW of
monograph ch. 6, with the derived ratios R_gm and kappa of (6.122).

See :mod:`stand.model.balancers.two_axis` for the model and its units; the pendulum's
frames, steady motions and theory take the parameters from this module, which
depends on none of them.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

from stand.model.balancers._params import BOOK, group

__all__ = ["TwoAxisParams"]


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
