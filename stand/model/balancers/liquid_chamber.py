"""Liquid chamber autobalancer of thesis 002 (Khomiak & Drach 2020).

Quasi-static (Jeffcott, planar) models of a rotor carrying a cylindrical
chamber partly filled with liquid, following the verified digest
``/work/shared/physics/thesis_002_liquid.md`` (equation numbers are the
thesis's).  Everything is SI: m, kg, s, rad (degrees only where a function
name or argument says so).

Contents
--------
* :class:`LiquidChamberParams` -- the stand of Table 3.1 and friends.
* Fill geometry and free surface: :func:`fill_geometry` (r = sqrt(R^2 -
  V/(pi h)), l.1787; the paraboloid of l.662-666), :func:`free_surface_height`.
* Liquid centre of mass: :func:`liquid_centroid` (l.668), valid under the
  sufficiency condition (3.4) ``f <= R - r``.
* Damped quasi-static model below the critical speed (section 2.2.2.1):
  :func:`phase_lag` (2.5), :func:`deflection_factor` (2.7),
  :func:`equilibrium_angle` (2.13, **corrected**), :func:`efficiency` (2.14),
  :func:`quasi_static_efficiency` (the self-consistent closure of digest
  section 4.6, or the literal Appendix-B algorithm with ``literal=True``).
* Viscous equilibrium zones (2.15): :func:`viscous_zone`, :func:`wetted_arc`,
  :func:`select_liquid`.
* Extremum of the efficiency function (section 2.3.3):
  :func:`efficiency_derivative`, :func:`efficiency_second_derivative`,
  :func:`efficiency_extremum`.
* Simplified models of chapter 3: :func:`simplified_single_chamber` (3.1)-(3.9),
  :func:`multi_chamber` (3.10)-(3.14).
* Optimal volume (section 3.3): :func:`segment_capacity`,
  :func:`annulus_capacity`, :func:`optimal_volume`.
* Permissible residual unbalance (section 2.1.7): :func:`permissible_eccentricity_household`,
  :func:`permissible_eccentricity_general`, :func:`iso_grade_from_eccentricity`,
  :func:`eccentricity_from_iso_grade`, :func:`unbalance_coefficient`.
* Damping helpers: :func:`log_decrement`, :func:`damping_rate_from_log_decrement`.

Corrections of the print (each checked by derivation, sympy)
-------------------------------------------------------------
* (2.13): the printed ``alpha0 = pi - arccos(sin^2 d + sqrt((sin^2 d - 1)(sin^2 d - k^2)))``
  drops the ``1/k`` of l.814; the corrected form
  ``alpha0 = pi - arccos((sin^2 d + sqrt((1 - sin^2 d)(k^2 - sin^2 d)))/k)``
  satisfies (2.12) identically and gives ``1 + 2k cos alpha0 + k^2 =
  (sqrt(k^2 - sin^2 d) - |cos d|)^2``.  ``literal=True`` evaluates the print.
* l.704 vs l.648: ``e0 = D0/(M + m)`` is used consistently with (2.4).
* l.674: ``D = m x_p`` and ``e = D/(M + m)`` (the print mixes the two).
* (2.7)/App. B step 2.5: evaluated in the regular form
  ``f = e_c (cos phi - 1 + gamma^2)/sqrt(A)`` (identical for gamma != 1;
  App. B's ``omega^2 - omega^2`` denominator is OCR for ``omega_p^2 - omega^2``).
* (2.5)/l.734: the thesis's numbers use ``n = theta omega_cr/(2 pi)``
  (Table 3.1: 7.85), not the printed ``2n = theta omega_cr``.
* Second derivative l.1092: correct only at the stationary point; the general
  form is ``(-2c - 3k - k c^2 - 2k^2 c)/Q^(5/2)``.
* (3.1): the liquid inertia force uses the liquid mass ``m_p``; (3.2) has
  ``h`` restored; (3.10) ``l`` is ``pi``; (3.12) is used with the sign of
  (3.2) (the print flips the denominator); ``m0 = rho pi h (2 R s - s^2)``
  (printed ``2 s_p rho pi h R``).
* (2.15): ``sin beta* = 8 pi^2 mu R xi_deg/(180 m omega) = 8 pi nu R xi/(V omega)``
  (xi in rad); App. D's SINUS (``nu^2``, ``V^2``) is dimensionally wrong.

Addition beyond the thesis (derived here): for the paraboloid free surface
``r(z)^2 = r_b^2 + 2 g sin(Omega) z/omega^2`` every horizontal slice is a disk
minus an offset disk, so the liquid unbalance is ``D = rho pi f int r(z)^2 dz
= rho pi h r_cyl^2 f`` -- exactly the cylindrical value -- *provided every
slice is an annulus*: ``r_b^2 >= 0`` and ``f <= R - r_top``.  Hence the
cylinder approximation is exact for D, and gravity enters only through the
stricter sufficiency margin ``R - r_top`` (flagged by the models).

Validity
--------
Result objects carry ``valid`` and ``flags``; a flagged result is outside the
model (the numbers are still returned, for documentation, never silently).
Physically impossible inputs (negative masses, ...) raise :class:`ValueError`
naming the parameter, the value and the unit.

Modules
-------
This module holds the parameters and the damping conventions, and re-exports
the model's functions from :mod:`.liquid_chamber_geometry` (fill, free
surface, centroid), :mod:`.liquid_chamber_quasi_static` ((2.5)-(2.14) and the
self-consistent efficiency), :mod:`.liquid_chamber_viscous` ((2.15)),
:mod:`.liquid_chamber_simplified` ((3.1)-(3.14)) and
:mod:`.liquid_chamber_design` (optimal volume, permissible unbalance), so
``stand.model.balancers.liquid_chamber.<name>`` keeps working for all of them.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional

from stand.model.balancers._params import THESIS, group
from stand.model.balancers.liquid_chamber_design import (OptimalVolume, annulus_capacity, eccentricity_from_iso_grade,
                                    iso_grade_from_eccentricity, optimal_volume,
                                    permissible_eccentricity_general,
                                    permissible_eccentricity_household, segment_capacity,
                                    unbalance_coefficient)
from stand.model.balancers.liquid_chamber_geometry import (G_STANDARD, FillGeometry, LiquidCentroid, fill_geometry,
                                      free_surface_height, liquid_centroid, total_unbalance)
from stand.model.balancers.liquid_chamber_quasi_static import (EfficiencyExtremum, EquilibriumAngle, QuasiStaticResult,
                                          deflection_factor, efficiency, efficiency_derivative,
                                          efficiency_extremum, efficiency_second_derivative,
                                          equilibrium_angle, phase_lag, quasi_static_efficiency)
from stand.model.balancers.liquid_chamber_simplified import (MultiChamberResult, SimplifiedResult, multi_chamber,
                                        simplified_single_chamber)
from stand.model.balancers.liquid_chamber_viscous import (ViscousZone, in_equilibrium_zone, select_liquid, viscous_zone,
                                     wetted_arc)

__all__ = [
    "G_STANDARD", "LiquidChamberParams", "FillGeometry", "LiquidCentroid", "EquilibriumAngle",
    "EfficiencyExtremum", "QuasiStaticResult", "ViscousZone", "SimplifiedResult",
    "MultiChamberResult", "OptimalVolume",
    "log_decrement", "damping_rate_from_log_decrement", "fill_geometry", "free_surface_height",
    "liquid_centroid", "total_unbalance", "phase_lag", "deflection_factor", "equilibrium_angle",
    "efficiency", "efficiency_derivative", "efficiency_second_derivative", "efficiency_extremum",
    "quasi_static_efficiency", "viscous_zone", "in_equilibrium_zone", "wetted_arc",
    "select_liquid", "simplified_single_chamber", "multi_chamber", "segment_capacity",
    "annulus_capacity", "optimal_volume", "permissible_eccentricity_household",
    "permissible_eccentricity_general", "iso_grade_from_eccentricity",
    "eccentricity_from_iso_grade", "unbalance_coefficient",
]


# --------------------------------------------------------------------------- parameters
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


# --------------------------------------------------------------------------- damping
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
