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
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Mapping, Optional, Sequence, Tuple

import numpy as np
from scipy.optimize import brentq

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

#: standard gravity [m/s^2]
G_STANDARD = 9.80665


# --------------------------------------------------------------------------- validation
def _num(name: str, value, unit: str) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} = {value!r} {unit} is invalid: not a number") from None
    if not math.isfinite(v):
        raise ValueError(f"{name} = {value!r} {unit} is invalid: must be finite")
    return v


def _pos(name: str, value, unit: str) -> float:
    v = _num(name, value, unit)
    if v <= 0.0:
        raise ValueError(f"{name} = {value!r} {unit} is invalid: must be > 0")
    return v


def _nonneg(name: str, value, unit: str) -> float:
    v = _num(name, value, unit)
    if v < 0.0:
        raise ValueError(f"{name} = {value!r} {unit} is invalid: must be >= 0")
    return v


def _result_flags(flags) -> Tuple[bool, Tuple[str, ...]]:
    flags = tuple(flags)
    return (len(flags) == 0, flags)


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
        _nonneg("rotor_mass", self.rotor_mass, "kg")
        _nonneg("chamber_mass", self.chamber_mass, "kg")
        _nonneg("unbalance_mass", self.unbalance_mass, "kg")
        _nonneg("unbalance_radius", self.unbalance_radius, "m")
        _pos("critical_speed", self.critical_speed, "rad/s")
        _pos("chamber_radius", self.chamber_radius, "m")
        _pos("chamber_height", self.chamber_height, "m")
        _nonneg("liquid_volume", self.liquid_volume, "m^3")
        _pos("liquid_density", self.liquid_density, "kg/m^3")
        _nonneg("kinematic_viscosity", self.kinematic_viscosity, "m^2/s")
        if self.log_decrement is None and self.damping_rate is None:
            raise ValueError("log_decrement = None - and damping_rate = None 1/s: one is required")
        if self.log_decrement is not None:
            _nonneg("log_decrement", self.log_decrement, "-")
        if self.damping_rate is not None:
            _nonneg("damping_rate", self.damping_rate, "1/s")
        om = _num("inclination", self.inclination, "rad")
        if not (-math.pi / 2 <= om <= math.pi / 2):
            raise ValueError(f"inclination = {self.inclination!r} rad is invalid: must be in [-pi/2, pi/2]")
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
    a_i = _pos("a_i", a_i, "m")
    a_iq = _pos("a_iq", a_iq, "m")
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
    theta = _nonneg("theta", theta, "-")
    omega_cr = _pos("omega_cr", omega_cr, "rad/s")
    if convention == "used":
        return theta * omega_cr / (2 * math.pi)
    if convention == "printed":
        return theta * omega_cr / 2
    if convention == "exact":
        return theta / math.sqrt(4 * math.pi ** 2 + theta ** 2) * omega_cr
    raise ValueError(f"convention = {convention!r} is invalid: use 'used', 'printed' or 'exact'")


# --------------------------------------------------------------------------- fill geometry
@dataclass(frozen=True)
class FillGeometry:
    """Chamber fill (cylindrical approximation, l.1787, plus paraboloid check).

    Attributes
    ----------
    r : float
        Free-surface radius [m] of the cylindrical approximation (= the rms
        radius of the paraboloid); NaN if the fill exceeds the chamber.
    layer : float
        ``R - r`` [m], layer thickness at the wall.
    chamber_volume : float
        ``pi R^2 h`` [m^3].
    fill_fraction : float
        ``V / (pi R^2 h)`` [-].
    r_bottom, r_top : float
        Paraboloid radii at the bottom and lid [m] (= ``r`` without gravity
        along the axis or if ``omega`` is not given); ``r_bottom`` NaN when
        the vertex is above the bottom.
    axial_gravity_term : float
        ``g h sin(Omega)/omega^2`` [m^2] (0 if omega not given).
    valid, flags
        Validity of the annular-layer model and the reasons when not.
    """

    r: float
    layer: float
    chamber_volume: float
    fill_fraction: float
    r_bottom: float
    r_top: float
    axial_gravity_term: float
    valid: bool
    flags: Tuple[str, ...]


def fill_geometry(R: float, h: float, V: float, omega: Optional[float] = None,
                  inclination: float = math.pi / 2, *, g: float = G_STANDARD,
                  gravity_tol: float = 0.1) -> FillGeometry:
    """Free-surface radius and layer of a liquid volume ``V`` in the chamber.

    ``r = sqrt(R^2 - V/(pi h))`` (App. B step 2.3).  With ``omega`` given the
    free surface is the paraboloid of l.662: ``r(z)^2 = r_b^2 + 2 g
    sin(Omega) z/omega^2``, with ``V = pi h (R^2 - r_b^2 - g h sin(Omega)/omega^2)``
    (digest section 2.3 addition); the cylindrical ``r`` is its rms radius.

    Parameters
    ----------
    R, h : float
        Chamber radius and height [m].
    V : float
        Liquid volume [m^3].
    omega : float, optional
        Spin speed [rad/s], for the paraboloid / gravity checks.
    inclination : float
        Shaft inclination to the horizontal [rad] (``pi/2``: vertical).
    g : float
        Gravity [m/s^2].
    gravity_tol : float
        Flag the unmodelled in-plane gravity when ``g cos(Omega)/(omega^2 R)``
        exceeds this.

    Returns
    -------
    FillGeometry
        Flags: fill exceeds the chamber; chamber full (no free surface, the
        liquid cannot move); no liquid; paraboloid vertex above the bottom
        (no annulus at the bottom); free surface meets the wall below the lid;
        in-plane gravity not negligible.
    """
    R = _pos("R", R, "m")
    h = _pos("h", h, "m")
    V = _nonneg("V", V, "m^3")
    Vk = math.pi * R * R * h
    flags = []
    r2 = R * R - V / (math.pi * h)
    if r2 < 0:
        flags.append(f"fill exceeds the chamber: V = {V:.6g} m^3 > pi R^2 h = {Vk:.6g} m^3")
        r = float("nan")
    else:
        r = math.sqrt(r2)
        if r2 == 0.0:
            flags.append("chamber completely full: no free surface, the liquid cannot redistribute")
    if V == 0.0:
        flags.append("no liquid: V = 0 m^3")
    q = 0.0
    r_b = r_t = r
    if omega is not None and r2 >= 0:
        omega = _pos("omega", omega, "rad/s")
        q = g * h * math.sin(inclination) / omega ** 2
        rb2, rt2 = r2 - abs(q), r2 + abs(q)
        r_b = math.sqrt(rb2) if rb2 >= 0 else float("nan")
        r_t = math.sqrt(rt2)
        if rb2 < 0 and V > 0:
            flags.append(f"paraboloid vertex above the chamber bottom (g h sin(Omega)/omega^2 = {q:.3g} m^2 "
                         f"> r^2 = {r2:.3g} m^2): the liquid covers the bottom centre, not an annulus")
        if rt2 > R * R and V > 0:
            flags.append(f"free surface meets the wall below the lid (g h sin(Omega)/omega^2 = {q:.3g} m^2 "
                         f"> R^2 - r^2 = {R * R - r2:.3g} m^2): the liquid does not form a full-height annulus")
        inplane = g * abs(math.cos(inclination)) / (omega ** 2 * R)
        if inplane > gravity_tol:
            flags.append(f"in-plane gravity g cos(Omega)/(omega^2 R) = {inplane:.3g} > {gravity_tol}: "
                         "not modelled by the thesis")
    valid, flags = _result_flags(flags)
    return FillGeometry(r=r, layer=R - r, chamber_volume=Vk, fill_fraction=V / Vk, r_bottom=r_b,
                        r_top=r_t, axial_gravity_term=q, valid=valid, flags=flags)


def free_surface_height(x, f: float, omega: float, inclination: float = math.pi / 2, *,
                        g: float = G_STANDARD):
    """Height of the free surface above its vertex, ``z = omega^2 (x + f)^2/(2 g sin Omega)``.

    Integral of l.662 (``tan psi = omega^2 (x + f)/(g sin Omega)``): a
    parabola with its axis on the rotation axis ``O_1`` (x = -f).

    Parameters
    ----------
    x : float or array
        Coordinate from the chamber centre O along the deflection line [m].
    f : float
        Shaft deflection ``O_1 O`` [m].
    omega : float
        Spin [rad/s].
    inclination : float
        Shaft inclination to the horizontal [rad]; ``sin(Omega) = 0`` (horizontal
        shaft) has no axial gravity and the surface is a cylinder (``inf``
        returned away from the axis).

    Returns
    -------
    float or ndarray
        ``z`` [m].
    """
    omega = _pos("omega", omega, "rad/s")
    s = math.sin(inclination)
    x = np.asarray(x, dtype=float)
    with np.errstate(divide="ignore"):
        z = omega ** 2 * (x + f) ** 2 / (2 * g * s) if s != 0 else np.where(x + f == 0, 0.0, np.inf)
    return z if z.ndim else float(z)


# --------------------------------------------------------------------------- centroid
@dataclass(frozen=True)
class LiquidCentroid:
    """Liquid centre of mass in the chamber cross-section (l.668).

    Attributes
    ----------
    x_p : float
        Centroid offset from the chamber centre O [m], along ``O_1 -> O``
        (away from the rotation axis): ``r^2 f/(R^2 - r^2)``.
    area : float
        Liquid cross-section ``pi (R^2 - r^2)`` [m^2].
    first_moment : float
        ``area * x_p = pi r^2 f`` [m^3]; times ``rho h`` gives ``D`` [kg m].
    valid, flags
        Flag when the free-surface circle leaves the chamber (``f > R - r``,
        sufficiency condition (3.4) violated): the liquid is then a crescent
        and the formula no longer holds.
    """

    x_p: float
    area: float
    first_moment: float
    valid: bool
    flags: Tuple[str, ...]


def liquid_centroid(R: float, r: float, f: float, *, r_top: Optional[float] = None) -> LiquidCentroid:
    """Centroid of disk(R, centre O) minus disk(r, centre O_1 at distance ``f``), l.668.

    Parameters
    ----------
    R : float
        Chamber radius [m].
    r : float
        Free-surface radius [m] (cylindrical approximation, ``0 <= r < R``).
    f : float
        Offset ``|O_1 O|`` [m] (shaft deflection), ``>= 0``.
    r_top : float, optional
        Largest paraboloid radius [m]; the sufficiency check then uses
        ``R - r_top`` (every slice must be an annulus; the first moment is the
        cylindrical one exactly, see the module notes).

    Returns
    -------
    LiquidCentroid
    """
    R = _pos("R", R, "m")
    r = _nonneg("r", r, "m")
    f = _nonneg("f", f, "m")
    if r >= R:
        raise ValueError(f"r = {r!r} m is invalid: must be < R = {R!r} m (no liquid otherwise)")
    flags = []
    r_chk = r if r_top is None else max(r, float(r_top))
    if f > R - r_chk:
        flags.append(f"free surface leaves the chamber: f = {f:.4g} m > R - r = {R - r_chk:.4g} m "
                     "(sufficiency (3.4) violated, liquid is a crescent, not an annulus)")
    area = math.pi * (R * R - r * r)
    x_p = r * r * f / (R * R - r * r)
    valid, flags = _result_flags(flags)
    return LiquidCentroid(x_p=x_p, area=area, first_moment=math.pi * r * r * f, valid=valid, flags=flags)


def total_unbalance(e: float, k: float, alpha: float) -> Tuple[float, float]:
    """System CoM eccentricity and its angle, (2.4), l.724, l.728.

    Parameters
    ----------
    e : float
        Liquid CoM eccentricity ``D/(M + m)`` [m].
    k : float
        ``D0/D`` [-].
    alpha : float
        Angle of the liquid CoM from the rotor unbalance [rad].

    Returns
    -------
    (e_c, phi_c) : tuple of float
        ``e_c = e sqrt(1 + 2k cos(alpha) + k^2)`` [m] and ``phi_c`` [rad]
        with ``tan(phi_c) = sin(alpha)/(cos(alpha) + k)`` (quadrant by atan2).
    """
    e = _nonneg("e", e, "m")
    k = _nonneg("k", k, "-")
    e_c = e * math.sqrt(max(1 + 2 * k * math.cos(alpha) + k * k, 0.0))
    return e_c, math.atan2(math.sin(alpha), math.cos(alpha) + k)


# --------------------------------------------------------------------------- damped model
def phase_lag(omega: float, omega_cr: float, n: float) -> float:
    """Phase lag ``delta`` [rad] of the deflection behind ``D_c``, (2.5).

    ``tan(delta) = 2 n omega/(omega_cr^2 - omega^2)``, in ``[0, pi]`` by atan2
    (90 deg exactly at ``omega = omega_cr``).
    """
    omega = _nonneg("omega", omega, "rad/s")
    omega_cr = _pos("omega_cr", omega_cr, "rad/s")
    n = _nonneg("n", n, "1/s")
    return math.atan2(2 * n * omega, omega_cr ** 2 - omega ** 2)


def deflection_factor(omega: float, omega_cr: float, n: float, form: str = "thesis") -> float:
    """Shaft deflection per system eccentricity, ``f/e_c`` [-], (2.7).

    ``form="thesis"``: (2.7) ``cos(d)[cos(phi) omega_cr^2/(omega_cr^2 - omega^2) - 1]``,
    evaluated as ``(cos(phi) - 1 + gamma^2)/sqrt(A)`` with ``A = (1 -
    gamma^2)^2 + (2 n omega/omega_cr^2)^2`` and ``sin(phi) = 2 n
    omega/omega_cr^2`` (2.8) (identical, and regular at gamma = 1).
    ``form="jeffcott"``: the classical ``gamma^2/sqrt(A)``.  Both coincide at n = 0.

    Raises
    ------
    ValueError
        If ``2 n omega > omega_cr^2`` for the thesis form (no real phi in (2.8));
        :func:`quasi_static_efficiency` flags this instead.
    """
    omega = _nonneg("omega", omega, "rad/s")
    omega_cr = _pos("omega_cr", omega_cr, "rad/s")
    n = _nonneg("n", n, "1/s")
    g2 = (omega / omega_cr) ** 2
    a = 2 * n * omega / omega_cr ** 2
    A = (1 - g2) ** 2 + a * a
    if A == 0.0:
        return float("inf")
    if form == "jeffcott":
        return g2 / math.sqrt(A)
    if form != "thesis":
        raise ValueError(f"form = {form!r} is invalid: use 'thesis' or 'jeffcott'")
    if a > 1.0:
        raise ValueError(f"2 n omega/omega_cr^2 = {a!r} - is invalid for (2.8): must be <= 1")
    return (math.sqrt(1 - a * a) - 1 + g2) / math.sqrt(A)


@dataclass(frozen=True)
class EquilibriumAngle:
    """Liquid equilibrium angle of (2.12)/(2.13).

    Attributes
    ----------
    alpha0 : float
        Angle [rad] of the liquid CoM from the rotor unbalance, thesis branch
        (``cos(alpha0) = (-sin^2 d - sqrt(.))/k``, corrected (2.13); or the
        printed formula when ``literal``).  NaN if undefined.
    alpha0_other : float
        The discarded ``+`` root of l.814 [rad] (tends to 0 as delta -> 0;
        the thesis gives no stability argument for discarding it).  NaN in
        literal mode or when undefined.
    arccos_argument : float
        The argument of arccos in (2.13) (printed or corrected) [-].
    literal : bool
    valid, flags
    """

    alpha0: float
    alpha0_other: float
    arccos_argument: float
    literal: bool
    valid: bool
    flags: Tuple[str, ...]


def equilibrium_angle(k: float, delta: float, *, literal: bool = False) -> EquilibriumAngle:
    """Liquid equilibrium angle ``alpha0`` [rad], (2.13).

    Corrected (default; the digest's correction, re-derived: it satisfies
    (2.12) ``sin(alpha0) = sin(d) sqrt(1 + 2k cos(alpha0) + k^2)/k``)::

        alpha0 = pi - arccos((sin^2 d + sqrt((1 - sin^2 d)(k^2 - sin^2 d)))/k)

    ``literal=True``: the printed (2.13) without ``1/k`` (also App. B step 3
    and OPTIMUM_KAMERA); satisfies (2.12) only for k = 1.

    Parameters
    ----------
    k : float
        ``D0/D`` [-], > 0.
    delta : float
        Phase lag (2.5) [rad], in [0, pi].

    Returns
    -------
    EquilibriumAngle
        Flagged (NaN angle) when ``k < sin(delta)`` (no equilibrium: too much
        liquid, ``D > D0/sin(d)``), or, in literal mode, when the printed
        arccos argument leaves [-1, 1] or its square root is of a negative
        number (Pascal would stop).
    """
    k = _pos("k", k, "-")
    delta = _num("delta", delta, "rad")
    if not (0.0 <= delta <= math.pi):
        raise ValueError(f"delta = {delta!r} rad is invalid: must be in [0, pi]")
    s2 = math.sin(delta) ** 2
    flags = []
    nan = float("nan")
    if literal:
        flags.append("thesis-literal: printed (2.13) lacks 1/k, not a physical prediction")
        rad = (s2 - 1.0) * (s2 - k * k)
        if rad < 0:
            flags.append(f"printed (2.13): sqrt of negative {(rad):.3g} (k = {k:.4g} < sin(delta) = "
                         f"{math.sqrt(s2):.4g}); undefined")
            return EquilibriumAngle(nan, nan, nan, True, *_result_flags(flags))
        y = s2 + math.sqrt(rad)
        if abs(y) > 1.0:
            flags.append(f"printed (2.13): arccos argument {y:.6g} outside [-1, 1]; undefined")
            return EquilibriumAngle(nan, nan, y, True, *_result_flags(flags))
        return EquilibriumAngle(math.pi - math.acos(y), nan, y, True, *_result_flags(flags))
    if k < math.sqrt(s2) * (1 - 1e-15):
        flags.append(f"no equilibrium: k = {k:.6g} < sin(delta) = {math.sqrt(s2):.6g} "
                     "(liquid unbalance D > D0/sin(delta))")
        return EquilibriumAngle(nan, nan, nan, False, *_result_flags(flags))
    root = math.sqrt(max((1.0 - s2) * (k * k - s2), 0.0))
    y = min((s2 + root) / k, 1.0)          # <= 1 by Cauchy-Schwarz; clip rounding
    y_other = max(min((s2 - root) / k, 1.0), -1.0)   # = -cos of the '+' branch
    return EquilibriumAngle(math.pi - math.acos(y), math.pi - math.acos(y_other), y, False,
                            *_result_flags(flags))


def efficiency(k: float, alpha0: float) -> float:
    """Balancing efficiency (2.14), ``lambda0 = k/sqrt(1 + 2k cos(alpha0) + k^2)`` [-].

    ``= zeta0/zeta = e0/e_c`` (same delta with and without liquid).  Returns
    ``inf`` at complete balance (``k = 1``, ``alpha0 = pi``).
    """
    k = _nonneg("k", k, "-")
    Q = 1 + 2 * k * math.cos(alpha0) + k * k
    if Q <= 1e-300:
        return float("inf")
    return k / math.sqrt(Q)


def efficiency_derivative(k: float, alpha0: float) -> float:
    """``d lambda0/dk`` at fixed ``alpha0``, l.1082: ``(1 + k c)/Q^(3/2)``, ``c = cos(alpha0)``."""
    c = math.cos(alpha0)
    Q = 1 + 2 * k * c + k * k
    return (1 + k * c) / Q ** 1.5


def efficiency_second_derivative(k: float, alpha0: float, *, literal: bool = False) -> float:
    """``d^2 lambda0/dk^2`` at fixed ``alpha0``.

    Default: the general form ``(-2c - 3k - k c^2 - 2 k^2 c)/Q^(5/2)`` (derived
    with sympy).  ``literal=True``: the printed l.1092 ``-k sin^2(alpha0)/Q^(5/2)``,
    which equals it only at the stationary point ``k = -1/c`` (digest 2.8 flag).
    """
    c = math.cos(alpha0)
    Q = 1 + 2 * k * c + k * k
    if literal:
        return -k * math.sin(alpha0) ** 2 / Q ** 2.5
    return (-2 * c - 3 * k - k * c * c - 2 * k * k * c) / Q ** 2.5


@dataclass(frozen=True)
class EfficiencyExtremum:
    """Extremum of ``lambda0(k)`` at fixed ``alpha0`` (section 2.3.3).

    Attributes
    ----------
    k_star : float
        ``-1/cos(alpha0)`` [-] (l.1084).
    lambda_max : float
        ``1/|sin(alpha0)|`` [-] (l.1100); inf at ``alpha0 = pi``.
    valid, flags
        Flagged when ``cos(alpha0) >= 0`` (no maximum with ``k > 0``).
    """

    k_star: float
    lambda_max: float
    valid: bool
    flags: Tuple[str, ...]


def efficiency_extremum(alpha0: float) -> EfficiencyExtremum:
    """Maximum of (2.14) over k at fixed ``alpha0`` [rad] (section 2.3.3, l.1084-1100)."""
    alpha0 = _num("alpha0", alpha0, "rad")
    c, s = math.cos(alpha0), math.sin(alpha0)
    flags = []
    if c >= 0:
        flags.append(f"cos(alpha0) = {c:.4g} >= 0: no maximum for k > 0 (alpha0 must be in (pi/2, 3pi/2))")
        return EfficiencyExtremum(float("nan"), float("nan"), *_result_flags(flags))
    lam = float("inf") if abs(s) < 1e-15 else 1.0 / abs(s)
    return EfficiencyExtremum(-1.0 / c, lam, *_result_flags(flags))


# --------------------------------------------------------------------------- quasi-static model
@dataclass(frozen=True)
class QuasiStaticResult:
    """Steady state of the damped quasi-static model at one speed.

    Attributes
    ----------
    omega, gamma : float
        Speed [rad/s] and ``omega/omega_cr`` [-].
    delta : float
        Phase lag (2.5) [rad].
    deflection_factor : float
        ``H = f/e_c`` (2.7) [-].
    k : float
        ``D0/D`` [-].
    alpha0 : float
        Liquid equilibrium angle [rad] (corrected (2.13), or printed if literal).
    lambda0 : float
        Efficiency (2.14) [-].
    e0, e, e_c : float
        Rotor, liquid and system CoM eccentricities [m] (about the system mass).
    f : float
        Shaft deflection at the chamber [m].
    D0, D : float
        Rotor and liquid unbalance [kg m] (x 1e5 for g cm).
    r, layer : float
        Free-surface radius and ``R - r`` [m].
    k_alt, lambda0_alt : float
        The second self-consistent state when it exists (smaller k), else NaN.
    literal : bool
        True for the App. B algorithm as printed.
    valid, flags
    """

    omega: float
    gamma: float
    delta: float
    deflection_factor: float
    k: float
    alpha0: float
    lambda0: float
    e0: float
    e: float
    e_c: float
    f: float
    D0: float
    D: float
    r: float
    layer: float
    k_alt: float
    lambda0_alt: float
    literal: bool
    valid: bool
    flags: Tuple[str, ...]

    @property
    def D_gcm(self) -> float:
        """Liquid unbalance in g cm."""
        return self.D * 1e5

    @property
    def D0_gcm(self) -> float:
        """Rotor unbalance in g cm."""
        return self.D0 * 1e5


def quasi_static_efficiency(p: LiquidChamberParams, omega: float, *, literal: bool = False,
                            g: float = G_STANDARD, gravity_tol: float = 0.1) -> QuasiStaticResult:
    """Balancing efficiency of the damped quasi-static model (section 2.2.2.1).

    Default (corrected, the digest's self-consistent closure, section 4.6):
    (2.4) ``e = m/(M+m) r^2/(R^2-r^2) f = G' f`` with ``G' = rho pi h
    r^2/(M+m)``; (2.7) ``f = e_c H``; ``e_c = e sqrt(Q)`` with the corrected
    (2.13), for which ``sqrt(Q) = |sqrt(k^2 - sin^2 d) - |cos d||``.  Hence
    ``sqrt(Q) = 1/(G' H)``, solved in closed form::

        sqrt(k^2 - sin^2 d) = |cos d| +- 1/(G' H),   lambda0 = k G' H

    (independent of D0; D0 fixes the scale ``e = e0/k``, ``f = e/G'``).  The
    ``+`` root (larger k, the one the digest reports) is returned; the other,
    when it exists, is ``k_alt`` and flagged as an ambiguity.

    ``literal=True``: App. B / OPTIMUM_KAMERA as printed: ``e0 = D0/m_d``
    (= e_d), ``f = e0 H`` (empty-rotor deflection), ``e = r^2 f/(R^2 - r^2)``
    (no ``m/(M+m)``), ``D = e m``, ``k = D0/D``, printed (2.13).

    Parameters
    ----------
    p : LiquidChamberParams
    omega : float
        Spin [rad/s], > 0.
    literal : bool
    g, gravity_tol : float
        See :func:`fill_geometry`.

    Returns
    -------
    QuasiStaticResult
        Flags (each makes ``valid`` False): fill outside the annular-layer
        model (see :func:`fill_geometry`); ``omega > omega_cr`` (the model is
        derived below the critical speed; the thesis extends it only
        qualitatively, section 2.2.2.3); ``2 n omega > omega_cr^2``; no
        self-consistent state (``G'H <= 0`` or ``k < sin d``); sufficiency
        ``f <= R - r_top`` violated; two self-consistent states; literal mode.
    """
    omega = _pos("omega", omega, "rad/s")
    wc = p.critical_speed
    n = p.n
    R, h, rho, V = p.chamber_radius, p.chamber_height, p.liquid_density, p.liquid_volume
    nan = float("nan")
    gamma = omega / wc
    flags = []
    geo = fill_geometry(R, h, V, omega, p.inclination, g=g, gravity_tol=gravity_tol)
    flags.extend(geo.flags)
    if literal:
        flags.append("thesis-literal: App. B algorithm with printed (2.13) (no 1/k), e0 = D0/m_d, "
                     "no m/(M+m); not a physical prediction")
    if omega > wc:
        flags.append(f"supercritical: omega = {omega:.4g} rad/s > omega_cr = {wc:.4g} rad/s; the damped "
                     "quasi-static model (2.4)-(2.14) is derived for omega < omega_cr (section 2.2.2.1)")
    delta = phase_lag(omega, wc, n)
    s2 = math.sin(delta) ** 2
    a = 2 * n * omega / wc ** 2
    D0 = p.rotor_unbalance
    r = geo.r

    def out(H=nan, k=nan, alpha0=nan, lam=nan, e0=nan, e=nan, e_c=nan, f=nan, D=nan, k_alt=nan,
            lam_alt=nan):
        valid, fl = _result_flags(flags)
        return QuasiStaticResult(omega, gamma, delta, H, k, alpha0, lam, e0, e, e_c, f, D0, D, r,
                                 R - r, k_alt, lam_alt, literal, valid, fl)

    if a > 1.0:
        flags.append(f"2 n omega/omega_cr^2 = {a:.4g} > 1: no real phi in (2.8)")
        return out()
    if not (r == r) or V == 0.0 or r == 0.0:
        return out()
    H = deflection_factor(omega, wc, n)
    r_top = geo.r_top if geo.r_top == geo.r_top else r

    if literal:
        if p.unbalance_mass <= 0:
            flags.append("literal App. B needs m_d > 0 (e0 = D0/m_d)")
            return out(H=H)
        e0 = D0 / p.unbalance_mass
        f = e0 * H
        e = r * r / (R * R - r * r) * f
        D = e * p.liquid_mass
        if D <= 0:
            flags.append(f"liquid unbalance D = {D:.3g} kg m <= 0: k undefined")
            return out(H=H, e0=e0, f=f, e=e, D=D)
        k = D0 / D
        eq = equilibrium_angle(k, delta, literal=True)
        flags.extend(fl for fl in eq.flags if not fl.startswith("thesis-literal"))
        lam = efficiency(k, eq.alpha0) if eq.alpha0 == eq.alpha0 else nan
        if abs(f) > R - r_top:
            flags.append(f"sufficiency violated: f = {abs(f):.4g} m > R - r = {R - r_top:.4g} m")
        return out(H=H, k=k, alpha0=eq.alpha0, lam=lam, e0=e0, e=e, f=f, D=D)

    M_tot = p.total_mass
    Gp = rho * math.pi * h * r * r / M_tot
    GH = Gp * H
    e0 = D0 / M_tot
    if GH <= 0:
        flags.append(f"no self-consistent state: G'H = {GH:.4g} <= 0 (deflection factor H = {H:.4g})")
        return out(H=H, e0=e0)
    c = math.sqrt(max(1.0 - s2, 0.0))
    roots = [q for q in (c + 1.0 / GH, c - 1.0 / GH) if q > 0]
    if not roots:
        flags.append("no self-consistent state (k < sin(delta))")
        return out(H=H, e0=e0)
    ks = [math.sqrt(s2 + q * q) for q in roots]
    k = ks[0]
    eq = equilibrium_angle(k, delta)
    lam = k * GH
    k_alt = lam_alt = nan
    if len(ks) > 1:
        k_alt, lam_alt = ks[1], ks[1] * GH
        flags.append(f"two self-consistent states (k = {k:.4g}, {k_alt:.4g}); the larger k is reported, "
                     "selection not established by a stability analysis")
    if D0 <= 0:
        flags.append("no rotor unbalance (D0 = 0): nothing to balance")
        return out(H=H, k=k, alpha0=eq.alpha0, lam=lam, e0=e0, k_alt=k_alt, lam_alt=lam_alt)
    e = e0 / k
    f = e / Gp
    e_c = e / GH
    D = e * M_tot
    if f > R - r_top:
        flags.append(f"sufficiency violated: f = {f:.4g} m > R - r = {R - r_top:.4g} m "
                     "(free surface leaves the chamber; x_p of l.668 invalid)")
    return out(H=H, k=k, alpha0=eq.alpha0, lam=lam, e0=e0, e=e, e_c=e_c, f=f, D=D, k_alt=k_alt,
               lam_alt=lam_alt)


# --------------------------------------------------------------------------- viscous zones
@dataclass(frozen=True)
class ViscousZone:
    """Equilibrium zone of a viscous liquid, (2.15).

    Attributes
    ----------
    sin_beta_star : float
        ``8 pi nu R xi/(V omega)`` [-] (``xi`` in rad; = ``8 pi^2 mu R
        xi_deg/(180 m omega)`` of l.951).
    beta_star : float
        Half-width of the zone [rad] (NaN if ``sin_beta_star > 1``).
    tan_beta_max : float
        Bound of (2.15), ``sin b*/sqrt(1 - sin^2 b*)`` [-].
    residual_unbalance : float
        ``D sin(beta*)`` [kg m] if ``D`` was given (incomplete balancing,
        digest suggestion), else NaN.
    valid, flags
    """

    sin_beta_star: float
    beta_star: float
    tan_beta_max: float
    residual_unbalance: float
    valid: bool
    flags: Tuple[str, ...]


def viscous_zone(nu: float, R: float, V: float, omega: float, xi: float = 2 * math.pi,
                 D: Optional[float] = None) -> ViscousZone:
    """Equilibrium-zone half-width of a viscous liquid, l.951 / (2.15).

    Darcy-Weisbach with the laminar factor ``64/Re`` over an arc ``l = R xi``
    (digest section 2.7; the dimensionally consistent rewriting of l.951).

    Parameters
    ----------
    nu : float
        Kinematic viscosity [m^2/s].
    R : float
        Chamber radius [m].
    V : float
        Liquid volume [m^3].
    omega : float
        Spin [rad/s].
    xi : float
        Central angle of the arc of liquid motion [rad] (the thesis uses degrees).
    D : float, optional
        Liquid unbalance [kg m] for the residual ``D sin(beta*)``.

    Returns
    -------
    ViscousZone
        Flagged when ``sin beta* >= 1`` (friction exceeds the driving
        component everywhere: no equilibrium zone bound, the liquid does not
        settle -- outside the model).
    """
    nu = _nonneg("nu", nu, "m^2/s")
    R = _pos("R", R, "m")
    V = _pos("V", V, "m^3")
    omega = _pos("omega", omega, "rad/s")
    xi = _nonneg("xi", xi, "rad")
    sb = 8 * math.pi * nu * R * xi / (V * omega)
    flags = []
    if sb >= 1.0:
        flags.append(f"sin(beta*) = {sb:.4g} >= 1: friction exceeds the centrifugal drive, no bounded zone")
        beta = tb = float("nan")
    else:
        beta = math.asin(sb)
        tb = sb / math.sqrt(1 - sb * sb)
    res = float("nan") if D is None else _nonneg("D", D, "kg m") * sb
    return ViscousZone(sb, beta, tb, res, *_result_flags(flags))


def in_equilibrium_zone(beta: float, sin_beta_star: float) -> bool:
    """Whether an angle ``beta`` [rad] lies in the zone (2.15): ``|tan b| <= sin b*/sqrt(1 - sin^2 b*)``."""
    if not (0 <= sin_beta_star < 1):
        raise ValueError(f"sin_beta_star = {sin_beta_star!r} - is invalid: must be in [0, 1)")
    return abs(math.tan(beta)) <= sin_beta_star / math.sqrt(1 - sin_beta_star ** 2)


def wetted_arc(R: float, r: float, f: float) -> float:
    """Wetted arc of the chamber wall [rad] (digest section 4.7 geometry).

    ``2 pi`` while the free-surface circle (radius ``r``, centre at distance
    ``f``) stays inside the chamber (``f <= R - r``); otherwise ``2 pi -
    2 theta*`` with ``cos(theta*) = (R^2 + f^2 - r^2)/(2 R f)`` (dry arc
    ``2 theta*`` centred on the rotation-axis side); 0 if the surface circle
    contains the whole wall.  (App. D's ``xi = 2 pi - arccos z`` with its
    garbled ``z`` is not reproduced.)
    """
    R = _pos("R", R, "m")
    r = _nonneg("r", r, "m")
    f = _nonneg("f", f, "m")
    if f <= R - r:
        return 2 * math.pi
    if f + R <= r:
        return 0.0
    z = (R * R + f * f - r * r) / (2 * R * f)
    return 2 * math.pi - 2 * math.acos(max(-1.0, min(1.0, z)))


def select_liquid(liquids: Mapping[str, float], R: float, V: float, omega: float,
                  xi: float = 2 * math.pi) -> Tuple[str, dict]:
    """Choose the liquid with the narrowest equilibrium zone (App. D, corrected SINUS).

    Parameters
    ----------
    liquids : mapping name -> kinematic viscosity [m^2/s]
    R, V, omega, xi : see :func:`viscous_zone`.

    Returns
    -------
    (name, zones) : the best name and ``{name: ViscousZone}``.
    """
    if not liquids:
        raise ValueError("liquids = {} - is invalid: need at least one liquid")
    zones = {name: viscous_zone(nu, R, V, omega, xi) for name, nu in liquids.items()}
    best = min(zones, key=lambda nm: zones[nm].sin_beta_star)
    return best, zones


# --------------------------------------------------------------------------- chapter 3
@dataclass(frozen=True)
class SimplifiedResult:
    """Simplified ("virtual disk") model of section 3.1 / 3.2.

    Attributes
    ----------
    s : float
        Shaft deflection at the reservoir [m] ((3.2)/(3.12); negative =
        opposite to the unbalance, supercritical).
    omega_k : float
        Critical speed with the liquid virtual mass [rad/s] ((3.3)/(3.13)).
    omega_k_empty : float
        ``sqrt(c/m)`` [rad/s].
    virtual_mass : float
        ``k rho pi h sum R_i^2`` [kg].
    liquid_mass : float
        ``m_p`` total [kg].
    e : float
        System eccentricity (3.7) at this speed [m].
    e_limit : float
        (3.8) ``e0 m/(m + virtual_mass)`` [m], the ``omega >> omega_k`` limit.
    E : float
        (3.9)/(3.14) ``E_e = E_s = (m + virtual_mass)/m`` [-].
    m0 : float
        Limiting liquid mass of the sufficiency condition, exact ``rho pi h
        (2 R s - s^2)`` [kg] (outer chamber) (printed first-order ``2 s rho pi h R``
        is ``m0_approx``).
    m0_approx : float
    sufficient : bool
        (3.4)/(3.11) holds.
    valid, flags
    """

    s: float
    omega_k: float
    omega_k_empty: float
    virtual_mass: float
    liquid_mass: float
    e: float
    e_limit: float
    E: float
    m0: float
    m0_approx: float
    sufficient: bool
    valid: bool
    flags: Tuple[str, ...]

    @property
    def omega_k_ratio(self) -> float:
        """``omega_k/omega_k_empty`` [-]."""
        return self.omega_k / self.omega_k_empty


def simplified_single_chamber(m: float, c: float, e0: float, omega: float, R: float, h: float,
                              V: float, rho: float = 1000.0, *, conversion_k: Optional[float] = None,
                              literal: bool = False) -> SimplifiedResult:
    """Single-chamber simplified model, (3.1)-(3.9).

    Force balance (kinetostatics, delta = 0) ``c s = m omega^2 (s + e0) +
    m_p omega^2 s_p`` with ``m_p s_p = rho pi h R^2 s`` (virtual full disk)::

        s = e0 m omega^2/(c - (m + k rho pi h R^2) omega^2)      (3.2)/(3.5)
        omega_k = sqrt(c/(m + k rho pi h R^2))                    (3.3)/(3.6)
        e = (e0 m + m_p (s_p - s))/(m + m_p)                      (3.7)
        E = (m + k rho pi h R^2)/m                                (3.9)

    with ``k = 1`` while (3.4) ``R - r >= |s|`` holds.  The print of (3.2)
    lacks ``h`` (``literal=True`` evaluates it so, in SI).

    Parameters
    ----------
    m : float
        Rotor + reservoir mass (chapter 3's ``m``) [kg].
    c : float
        Radial shaft stiffness [N/m].
    e0 : float
        Rotor eccentricity [m].
    omega : float
        Spin [rad/s].
    R, h, V, rho : float
        Chamber radius [m], height [m], liquid volume [m^3], density [kg/m^3].
    conversion_k : float, optional
        Fig. 3.3's conversion coefficient for insufficient liquid (not
        reproduced in the thesis); without it an insufficient fill is flagged
        and ``k = 1`` is used.
    literal : bool

    Returns
    -------
    SimplifiedResult
        Flags: fill exceeds the chamber; near resonance (denominator ~ 0);
        subcritical (``omega < omega_k``: section 3.1 is stated for steady
        supercritical rotation, (3.9) is the ``omega >> omega_k`` limit);
        insufficient liquid without ``conversion_k``.
    """
    return multi_chamber(m, c, e0, omega, [R], [V], h, rho, 0.0, conversion_k=conversion_k,
                         literal=literal, _single=True)


@dataclass(frozen=True)
class MultiChamberResult(SimplifiedResult):
    """:class:`SimplifiedResult` plus per-chamber free-surface radii ``r`` [m] and margins [m]."""

    r: Tuple[float, ...] = ()
    margins: Tuple[float, ...] = ()


def multi_chamber(m: float, c: float, e0: float, omega: float, radii: Sequence[float],
                  volumes: Sequence[float], h: float, rho: float = 1000.0,
                  wall_thickness: float = 0.0, *, conversion_k: Optional[float] = None,
                  literal: bool = False, _single: bool = False) -> MultiChamberResult:
    """Concentric multi-chamber device, (3.10)-(3.14).

    Chambers numbered from the outside in: chamber i occupies ``R_{i+1} +
    delta < rho_ < R_i``.  ``m_i = rho pi h (R_i^2 - r_i^2)`` ((3.10), printed
    ``l`` is OCR for ``pi``), ``s_i = s R_i^2/(R_i^2 - r_i^2)``; the sum gives
    the virtual mass ``rho pi h sum R_i^2``.  ``s`` uses the sign of (3.2);
    ``literal=True`` uses the printed (3.12) denominator ``(m + ...) omega^2 - c``.

    Parameters
    ----------
    m, c, e0, omega : see :func:`simplified_single_chamber`.
    radii : sequence of float
        Outer radii ``R_i`` [m], strictly decreasing.
    volumes : sequence of float
        Liquid volumes ``V_i`` [m^3].
    h : float
        Common height [m].
    rho : float
        Density [kg/m^3].
    wall_thickness : float
        Partition wall thickness ``delta`` [m].

    Returns
    -------
    MultiChamberResult
        Sufficiency (3.11): ``R_i - r_i >= |s|`` and ``r_i - (R_{i+1} + delta) >= |s|``.
    """
    m = _pos("m", m, "kg")
    c = _pos("c", c, "N/m")
    e0 = _nonneg("e0", e0, "m")
    omega = _nonneg("omega", omega, "rad/s")
    h = _pos("h", h, "m")
    rho = _pos("rho", rho, "kg/m^3")
    dw = _nonneg("wall_thickness", wall_thickness, "m")
    Rs = [_pos(f"radii[{i}]", x, "m") for i, x in enumerate(radii)]
    Vs = [_nonneg(f"volumes[{i}]", x, "m^3") for i, x in enumerate(volumes)]
    if not Rs or len(Rs) != len(Vs):
        raise ValueError(f"radii/volumes = {len(Rs)}/{len(Vs)} chambers is invalid: need equal, >= 1")
    for i in range(len(Rs) - 1):
        if Rs[i + 1] + dw >= Rs[i]:
            raise ValueError(f"radii[{i + 1}] = {Rs[i + 1]!r} m is invalid: R_{i + 2} + delta must be "
                             f"< R_{i + 1} = {Rs[i]!r} m (chambers overlap)")
    if conversion_k is not None:
        conversion_k = _nonneg("conversion_k", conversion_k, "-")
    flags = []
    rs = []
    for i, (Ri, Vi) in enumerate(zip(Rs, Vs)):
        r2 = Ri * Ri - Vi / (math.pi * h)
        inner = Rs[i + 1] + dw if i + 1 < len(Rs) else 0.0
        if r2 < inner * inner:
            flags.append(f"chamber {i + 1}: fill V = {Vi:.4g} m^3 exceeds the chamber "
                         f"({math.pi * h * (Ri * Ri - inner * inner):.4g} m^3)")
        rs.append(math.sqrt(max(r2, 0.0)))
    m_p = rho * sum(Vs)
    sumR2 = sum(Ri * Ri for Ri in Rs)
    kk = 1.0 if conversion_k is None else conversion_k
    vm = kk * rho * math.pi * h * sumR2
    vm_s = kk * rho * math.pi * sumR2 if (literal and _single) else vm   # printed (3.2): no h
    if literal:
        flags.append("thesis-literal: printed " + ("(3.2) without h" if _single else
                                                   "(3.12) denominator sign") + "; not physical")
    denom = c - (m + vm_s) * omega ** 2
    if literal and not _single:
        denom = -denom
    if abs(denom) <= 1e-9 * c:
        flags.append("at the critical speed: (3.2) singular")
        s = float("inf")
    else:
        s = e0 * m * omega ** 2 / denom
    wk = math.sqrt(c / (m + vm))
    wk0 = math.sqrt(c / m)
    if omega < wk:
        flags.append(f"subcritical: omega = {omega:.4g} rad/s < omega_k = {wk:.4g} rad/s; section 3.1 "
                     "models steady supercritical rotation")
    margins = []
    for i, (Ri, ri) in enumerate(zip(Rs, rs)):
        margins.append(Ri - ri)
        if i + 1 < len(Rs):
            margins.append(ri - (Rs[i + 1] + dw))
    sufficient = all(abs(s) <= mg for mg in margins) if math.isfinite(s) else False
    if not sufficient and math.isfinite(s) and conversion_k is None:
        flags.append(f"insufficient liquid: |s| = {abs(s):.4g} m > min margin {min(margins):.4g} m "
                     "((3.4)/(3.11)); (3.5) needs Fig. 3.3's conversion coefficient (not reproduced)")
    # (3.7): m_p (s_p - s) summed = rho pi h sum r_i^2 s
    if math.isfinite(s):
        e = (e0 * m + rho * math.pi * h * sum(ri * ri for ri in rs) * s) / (m + m_p)
    else:
        e = float("nan")
    e_lim = e0 * m / (m + vm)
    s_abs = abs(s) if math.isfinite(s) else float("nan")
    R1 = Rs[0]
    m0 = rho * math.pi * h * (2 * R1 * s_abs - s_abs ** 2)
    m0a = 2 * s_abs * rho * math.pi * h * R1
    valid, fl = _result_flags(flags)
    return MultiChamberResult(s=s, omega_k=wk, omega_k_empty=wk0, virtual_mass=vm, liquid_mass=m_p,
                              e=e, e_limit=e_lim, E=(m + vm) / m, m0=m0, m0_approx=m0a,
                              sufficient=sufficient, valid=valid, flags=fl, r=tuple(rs),
                              margins=tuple(margins))


# --------------------------------------------------------------------------- optimal volume
def segment_capacity(V: float, R: float, h: float, rho: float = 1000.0) -> float:
    """Largest liquid unbalance a volume can produce in the chamber [kg m].

    All the liquid in a circular segment at the wall (bathtub principle: the
    region of given area with the largest first moment in a disk is cut by a
    straight line).  With half-angle ``t``: area ``R^2 (t - sin t cos t)``,
    first moment ``(2/3) R^3 sin^3 t``.  An upper bound for any free-surface
    shape, ``< rho V R``.
    """
    V = _nonneg("V", V, "m^3")
    R = _pos("R", R, "m")
    h = _pos("h", h, "m")
    rho = _pos("rho", rho, "kg/m^3")
    A = V / h
    if A > math.pi * R * R:
        raise ValueError(f"V = {V!r} m^3 is invalid: exceeds the chamber volume {math.pi * R * R * h:.6g} m^3")
    if A == 0:
        return 0.0
    t = brentq(lambda t: R * R * (t - math.sin(t) * math.cos(t)) - A, 0.0, math.pi, xtol=1e-15)
    return rho * h * (2.0 / 3.0) * R ** 3 * math.sin(t) ** 3


def annulus_capacity(V: float, R: float, h: float, rho: float = 1000.0) -> float:
    """Largest liquid unbalance [kg m] with the annular layer intact (sufficiency at its limit).

    ``f = R - r`` in ``D = rho pi h r^2 f`` gives ``D = rho V r^2/(R + r)``
    (~ ``rho V R/2`` for a thin layer).
    """
    V = _nonneg("V", V, "m^3")
    R = _pos("R", R, "m")
    h = _pos("h", h, "m")
    rho = _pos("rho", rho, "kg/m^3")
    r2 = R * R - V / (math.pi * h)
    if r2 < 0:
        raise ValueError(f"V = {V!r} m^3 is invalid: exceeds the chamber volume {math.pi * R * R * h:.6g} m^3")
    return rho * V * r2 / (R + math.sqrt(r2))


@dataclass(frozen=True)
class OptimalVolume:
    """Result of the optimal-volume method (section 3.3).

    Attributes
    ----------
    V_opt : float
        Volume whose capacity equals ``D0`` (k = 1, the maximum of the
        corrected lambda0) [m^3].
    V_design : float
        Volume whose capacity equals ``reserve * D0`` [m^3].
    capacity : float
        Capacity of ``V_design`` [kg m] (= ``reserve * D0``).
    lower_bound : float
        ``D0/(rho R)`` [m^3]; physically ``V_opt >= lower_bound``.
    chamber_volume, fill_fraction, layer : float
        ``pi R^2 h`` [m^3], ``V_design/chamber_volume`` [-], ``R - r`` [m]
        of the design fill.
    model : str
    valid, flags
    """

    V_opt: float
    V_design: float
    capacity: float
    lower_bound: float
    chamber_volume: float
    fill_fraction: float
    layer: float
    model: str
    valid: bool
    flags: Tuple[str, ...]


def optimal_volume(D0: float, R: float, h: float, rho: float = 1000.0, *, reserve: float = 1.0,
                   model: str = "segment") -> OptimalVolume:
    """Optimal liquid volume of section 3.3 (energy capacity = liquid unbalance).

    With the corrected (2.13) the efficiency (2.14) peaks (singularly) at
    ``k = 1`` (section 2.8 of the digest), so the optimum is the volume whose
    liquid unbalance equals ``D0``; the reserve factor ``k_zapasu`` (1.1-1.25,
    l.1315) then scales the capacity.

    Parameters
    ----------
    D0 : float
        Rotor unbalance to balance [kg m] (1000 g cm = 0.01 kg m).
    R, h : float
        Chamber radius and height [m].
    rho : float
        Liquid density [kg/m^3].
    reserve : float
        Energy-capacity reserve factor [-], >= 1 (thesis 1.1-1.25).
    model : {"segment", "annulus"}
        Capacity model: :func:`segment_capacity` (the physical maximum; its
        volume is the smallest that can balance ``D0``) or
        :func:`annulus_capacity` (annular layer kept, sufficiency (3.4) at its
        limit).

    Returns
    -------
    OptimalVolume
        Flagged when the chamber cannot hold enough liquid.
    """
    D0 = _pos("D0", D0, "kg m")
    R = _pos("R", R, "m")
    h = _pos("h", h, "m")
    rho = _pos("rho", rho, "kg/m^3")
    reserve = _num("reserve", reserve, "-")
    if reserve < 1.0:
        raise ValueError(f"reserve = {reserve!r} - is invalid: must be >= 1")
    if model == "segment":
        cap = segment_capacity
    elif model == "annulus":
        cap = annulus_capacity
    else:
        raise ValueError(f"model = {model!r} is invalid: use 'segment' or 'annulus'")
    Vk = math.pi * R * R * h
    # capacity is increasing on (0, V_peak); find its maximum first
    vs = np.linspace(0.0, Vk, 2001)
    caps = np.array([cap(v, R, h, rho) for v in vs])
    i_pk = int(np.argmax(caps))
    flags = []
    nan = float("nan")

    def solve(target):
        if caps[i_pk] < target:
            return nan
        j = int(np.argmax(caps >= target))
        if j == 0:
            return 0.0
        return brentq(lambda v: cap(v, R, h, rho) - target, vs[j - 1], vs[j], xtol=1e-15)

    V_opt = solve(D0)
    V_des = solve(reserve * D0)
    if not (V_opt == V_opt):
        flags.append(f"chamber too small: maximum capacity {caps[i_pk]:.4g} kg m < D0 = {D0:.4g} kg m")
    elif not (V_des == V_des):
        flags.append(f"chamber too small for the reserve: maximum capacity {caps[i_pk]:.4g} kg m "
                     f"< {reserve} D0")
    layer = R - math.sqrt(R * R - V_des / (math.pi * h)) if V_des == V_des else nan
    return OptimalVolume(V_opt=V_opt, V_design=V_des, capacity=reserve * D0 if V_des == V_des else nan,
                         lower_bound=D0 / (rho * R), chamber_volume=Vk, fill_fraction=V_des / Vk,
                         layer=layer, model=model, valid=not flags, flags=tuple(flags))


# --------------------------------------------------------------------------- permissible unbalance
def _rpm(n_rpm):
    return _pos("n_rpm", n_rpm, "rpm")


def permissible_eccentricity_household(n_rpm: float) -> float:
    """Permissible specific unbalance for machines a person contacts (household), l.604-606.

    ``[e_st] = 6000/n`` um with ``n`` in rpm.  Returns metres (SI).
    """
    return 6000.0 / _rpm(n_rpm) * 1e-6


def permissible_eccentricity_general(n_rpm: float) -> float:
    """Permissible specific unbalance for general machine building (Reutlinger), l.600-602.

    ``[e_st] = 2e8 n^-2`` (unit missing in the print; um reconstructed by the
    digest: ``2 * 0.1 g/omega^2``).  Returns metres (SI).
    """
    return 2e8 / _rpm(n_rpm) ** 2 * 1e-6


def iso_grade_from_eccentricity(e: float, n_rpm: float) -> float:
    """ISO 1940 grade ``G = e omega`` [mm/s] of a permissible eccentricity ``e`` [m] at ``n`` rpm.

    (``e_per[um] = 9549 G/n``; not in the thesis -- digest mapping.)
    """
    e = _nonneg("e", e, "m")
    return e * 1e3 * _rpm(n_rpm) * 2 * math.pi / 60.0


def eccentricity_from_iso_grade(G: float, n_rpm: float) -> float:
    """Permissible eccentricity [m] of ISO 1940 grade ``G`` [mm/s] at ``n`` rpm."""
    G = _nonneg("G", G, "mm/s")
    return G * 1e-3 / (_rpm(n_rpm) * 2 * math.pi / 60.0)


def unbalance_coefficient(e: float, omega: float, g: float = G_STANDARD) -> float:
    """Unbalance coefficient (2.3) ``k = F_c/P_st = e omega^2/g`` [-] for a single mass.

    The most favourable bearing regime needs ``k < 1``; recommended limits are
    0.01-0.5 by rotor type (l.592-596).

    Parameters
    ----------
    e : float
        Specific unbalance (CoM eccentricity) [m].
    omega : float
        Spin [rad/s].
    """
    e = _nonneg("e", e, "m")
    omega = _nonneg("omega", omega, "rad/s")
    return e * omega ** 2 / g
