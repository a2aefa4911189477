"""Parameters of the damper model: DryFriction, DamperParams.

Part of :mod:`stand.model.balancers.damper` (the model, its equations and units are
described there).  The modules that name the parameters import them from here and this
module imports none of them, so there is no circle.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

from stand.model.balancers._params import BOOK, group
from stand.model.balancers.damper_residual import R_f_cardan

__all__ = ["DryFriction", "DamperParams"]


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
        BOOK.fields(self, ("R_f", "dimensionless", ">= 0"), ("eps", "dimensionless rate", "> 0"),
                    ("kappa", "dimensionless", "> 0"))
        if self.R_f >= 1.0:
            raise BOOK.error("R_f", self.R_f, "dimensionless", "< 1 (7.81)")
        if self.kappa > 1.0:
            raise BOOK.error("kappa = m l^2/A", self.kappa, "dimensionless", "<= 1")


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
        BOOK.fields(self, *group(("R_m", "R_omega", "R_g", "h", "H", "e0", "k_c"), "dimensionless",
                                 ">= 0"), ("gamma", "rad", "finite"))
        if self.R_m >= 1.0:
            raise BOOK.error("R_m", self.R_m, "dimensionless", "< 1")
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
        M, c, omega, m, A, l, H1, H2, e, g = BOOK.each(
            ("M", M, "kg", "> 0"), ("c", c, "N/m", "> 0"), ("omega", omega, "rad/s", ">= 0"),
            ("m", m, "kg", "> 0"), ("A", A, "kg m^2", "> 0"), ("l", l, "m", "> 0"),
            ("H1", H1, "N m s", ">= 0"), ("H2", H2, "N s/m", ">= 0"), ("e", e, "m", ">= 0"),
            ("g", g, "m/s^2", ">= 0"))
        if m * l * l > A * (1 + 1e-12):
            raise BOOK.error("A", A, "kg m^2", f">= m l^2 = {m * l * l:g}")
        Ms = M + m if M_sigma is None else BOOK.positive("M_sigma", M_sigma, "kg")
        w0 = math.sqrt(c / Ms)
        rho2 = A / m
        fr = None
        if f is not None or joint_radius is not None:
            if f is None or joint_radius is None:
                raise ValueError("f [-] and joint_radius [m] must be given together for dry friction")
            f, hj = BOOK.each(("f", f, "dimensionless", ">= 0"),
                              ("joint_radius", joint_radius, "m", ">= 0"))
            fr = DryFriction(R_f=R_f_cardan(hj / l, f), eps=eps, kappa=m * l * l / A)
        return cls(R_m=m * l * l / (Ms * rho2), R_omega=omega / w0,
                   R_g=math.sqrt(g * l / (rho2 * w0 * w0)), h=H1 / (m * rho2 * w0),
                   H=H2 / (Ms * w0), e0=M * e / (m * l), gamma=gamma, friction=fr)
