"""Parameters of the liquid chamber model: LiquidChamberParams and the damping conventions.

Part of :mod:`stand.model.balancers.liquid_chamber` (the model, its equations and units are
described there).  The modules that name the parameters import them from here and this
module imports none of them, so there is no circle.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional

from stand.model.balancers._params import THESIS, group

__all__ = ["LiquidChamberParams", "log_decrement", "damping_rate_from_log_decrement"]


@dataclass(frozen=True)
class LiquidChamberParams:
    """Rotor + liquid chamber of chapter 2 / Table 3.1 (SI units).

    Parameters
    ----------
    rotor_mass : float
        ``M_p`` [kg], rotor (disk) mass without chamber, unbalance mass or liquid.
    chamber_mass : float
        ``M_k`` [kg], mass of the empty chamber.
    unbalance_mass : float
        ``m_d`` [kg], the unbalance mass.
    unbalance_radius : float
        ``e_d`` [m], radius of the unbalance mass (Table 3.1 "e0" = 0.2 m);
        the rotor unbalance is ``D0 = m_d e_d`` [kg m].
    critical_speed : float
        ``omega_cr`` (= ``omega_p``) [rad/s], critical (resonant) speed of
        the rotor with the chamber.
    chamber_radius : float
        ``R`` [m], inner radius of the cylindrical chamber.
    chamber_height : float
        ``h`` [m], inner height of the chamber.
    liquid_volume : float
        ``V`` [m^3], liquid volume (must not exceed ``pi R^2 h``).
    liquid_density : float
        ``rho`` [kg/m^3].
    kinematic_viscosity : float
        ``nu`` [m^2/s] (water ~1e-6).
    log_decrement : float, optional
        ``theta`` [-], logarithmic decrement of free vibration (l.738).
    damping_rate : float, optional
        ``n`` [1/s], decay rate of (2.5) (``tan d = 2 n omega/(omega_cr^2 -
        omega^2)``).  If omitted it is computed from ``log_decrement`` with the
        convention the thesis's numbers follow, ``n = theta omega_cr/(2 pi)``
        (digest section 2.5 flag).  One of the two is required.
    inclination : float
        ``Omega`` [rad], shaft inclination to the horizontal (l.620);
        ``pi/2`` is a vertical shaft (no in-plane gravity).

    Notes
    -----
    Masses follow chapter 2 with clash-free names: ``dry_mass`` ``M = M_p +
    M_k + m_d`` (the thesis's ``M``), ``liquid_mass`` ``m = rho V``,
    ``total_mass`` ``M + m`` (App. B step 2.2).
    """

    rotor_mass: float
    chamber_mass: float
    unbalance_mass: float
    unbalance_radius: float
    critical_speed: float
    chamber_radius: float
    chamber_height: float
    liquid_volume: float
    liquid_density: float = 1000.0
    kinematic_viscosity: float = 1.0e-6
    log_decrement: Optional[float] = None
    damping_rate: Optional[float] = None
    inclination: float = math.pi / 2

    def __post_init__(self):
        THESIS.fields(self, *group(("rotor_mass", "chamber_mass", "unbalance_mass"), "kg", ">= 0"),
                      ("unbalance_radius", "m", ">= 0"), ("critical_speed", "rad/s", "> 0"),
                      *group(("chamber_radius", "chamber_height"), "m", "> 0"),
                      ("liquid_volume", "m^3", ">= 0"), ("liquid_density", "kg/m^3", "> 0"),
                      ("kinematic_viscosity", "m^2/s", ">= 0"))
        if self.log_decrement is None and self.damping_rate is None:
            raise ValueError("log_decrement = None - and damping_rate = None 1/s: one is required")
        damping = (("log_decrement", "-", ">= 0"), ("damping_rate", "1/s", ">= 0"))
        THESIS.fields(self, *(spec for spec in damping if getattr(self, spec[0]) is not None),
                      ("inclination", "rad", "finite"))
        if not (-math.pi / 2 <= self.inclination <= math.pi / 2):
            raise THESIS.error("inclination", self.inclination, "rad", "in [-pi/2, pi/2]")
        if self.dry_mass + self.liquid_mass <= 0.0:
            raise ValueError("rotor_mass + chamber_mass + unbalance_mass + liquid mass = 0 kg is invalid: must be > 0")

    @classmethod
    def table_3_1(cls, **overrides) -> "LiquidChamberParams":
        """The test stand of Table 3.1 (l.1473-1488), ``n = 7.85`` 1/s, vertical shaft."""
        kw = dict(rotor_mass=6.5, chamber_mass=0.5, unbalance_mass=0.15, unbalance_radius=0.2,
                  critical_speed=59.7, chamber_radius=0.2, chamber_height=0.05,
                  liquid_volume=1.5e-4, liquid_density=1000.0, kinematic_viscosity=1.0e-6,
                  log_decrement=0.826, damping_rate=7.85)
        kw.update(overrides)
        return cls(**kw)

    @property
    def n(self) -> float:
        """Damping decay rate ``n`` [1/s] used in (2.5)."""
        if self.damping_rate is not None:
            return float(self.damping_rate)
        return damping_rate_from_log_decrement(self.log_decrement, self.critical_speed, "used")

    @property
    def liquid_mass(self) -> float:
        """``m = rho V`` [kg]."""
        return self.liquid_density * self.liquid_volume

    @property
    def dry_mass(self) -> float:
        """``M = M_p + M_k + m_d`` [kg] (chapter 2's rotor mass without liquid)."""
        return self.rotor_mass + self.chamber_mass + self.unbalance_mass

    @property
    def total_mass(self) -> float:
        """``M + m`` [kg] (App. B step 2.2)."""
        return self.dry_mass + self.liquid_mass

    @property
    def rotor_unbalance(self) -> float:
        """``D0 = m_d e_d`` [kg m] (App. B step 2.7 with the radius corrected)."""
        return self.unbalance_mass * self.unbalance_radius

    @property
    def chamber_volume(self) -> float:
        """``V_k = pi R^2 h`` [m^3]."""
        return math.pi * self.chamber_radius ** 2 * self.chamber_height


def log_decrement(a_i: float, a_iq: float, q: int = 1) -> float:
    """Logarithmic decrement ``theta = ln(A_i/A_{i+q})/q`` (l.738).

    Parameters
    ----------
    a_i, a_iq : float
        Double amplitudes [any length unit] ``q`` full periods apart (l.740).
    q : int
        Number of periods between them.

    Returns
    -------
    float
        ``theta`` [-].
    """
    a_i = THESIS.positive("a_i", a_i, "m")
    a_iq = THESIS.positive("a_iq", a_iq, "m")
    if int(q) != q or q < 1:
        raise ValueError(f"q = {q!r} periods is invalid: must be a positive integer")
    return math.log(a_i / a_iq) / q


def damping_rate_from_log_decrement(theta: float, omega_cr: float, convention: str = "used") -> float:
    """Decay rate ``n`` [1/s] from the logarithmic decrement.

    Parameters
    ----------
    theta : float
        Logarithmic decrement [-].
    omega_cr : float
        Critical speed [rad/s].
    convention : {"used", "printed", "exact"}
        ``"used"``: ``n = theta omega_cr/(2 pi)`` -- what Table 3.1's numbers
        follow (7.85 for theta = 0.826, 59.7 rad/s); ``"printed"``: ``2n =
        theta omega_cr`` (l.734, literal); ``"exact"``: ``n = zeta omega_cr``
        with ``zeta = theta/sqrt(4 pi^2 + theta^2)``.
    """
    theta = THESIS.nonneg("theta", theta, "-")
    omega_cr = THESIS.positive("omega_cr", omega_cr, "rad/s")
    if convention == "used":
        return theta * omega_cr / (2 * math.pi)
    if convention == "printed":
        return theta * omega_cr / 2
    if convention == "exact":
        return theta / math.sqrt(4 * math.pi ** 2 + theta ** 2) * omega_cr
    raise ValueError(f"convention = {convention!r} is invalid: use 'used', 'printed' or 'exact'")
