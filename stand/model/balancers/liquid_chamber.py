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
* Damped quasi-static model below the critical speed (section 2.2.2.1), in
  :mod:`stand.theories.weights.liquid_chamber_quasi_static`: ``phase_lag`` (2.5),
  ``deflection_factor`` (2.7), ``equilibrium_angle`` (2.13, **corrected**), ``efficiency``
  (2.14), ``quasi_static_efficiency`` (the self-consistent closure of digest
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
This module re-exports the parameters and the damping conventions
(:mod:`.liquid_chamber_params`) and the model's functions from :mod:`.liquid_chamber_geometry` (fill, free
surface, centroid), :mod:`.liquid_chamber_viscous` ((2.15)),
:mod:`.liquid_chamber_simplified` ((3.1)-(3.14)) and
:mod:`.liquid_chamber_design` (optimal volume, permissible unbalance).  The damped
quasi-static model (2.5)-(2.14) and the self-consistent efficiency are theory:
:mod:`stand.theories.weights.liquid_chamber_quasi_static`.
"""
from __future__ import annotations

from stand.model.balancers.liquid_chamber_params import (LiquidChamberParams,
                                                         damping_rate_from_log_decrement,
                                                         log_decrement)
from stand.model.balancers.liquid_chamber_design import (OptimalVolume, annulus_capacity, eccentricity_from_iso_grade,
                                    iso_grade_from_eccentricity, optimal_volume,
                                    permissible_eccentricity_general,
                                    permissible_eccentricity_household, segment_capacity,
                                    unbalance_coefficient)
from stand.model.balancers.liquid_chamber_geometry import (G_STANDARD, FillGeometry, LiquidCentroid, fill_geometry,
                                      free_surface_height, liquid_centroid, total_unbalance)
from stand.model.balancers.liquid_chamber_simplified import (MultiChamberResult, SimplifiedResult, multi_chamber,
                                        simplified_single_chamber)
from stand.model.balancers.liquid_chamber_viscous import (ViscousZone, in_equilibrium_zone, select_liquid, viscous_zone,
                                     wetted_arc)

__all__ = [
    "G_STANDARD", "LiquidChamberParams", "FillGeometry", "LiquidCentroid", "ViscousZone",
    "SimplifiedResult", "MultiChamberResult", "OptimalVolume", "log_decrement",
    "damping_rate_from_log_decrement", "fill_geometry", "free_surface_height", "liquid_centroid",
    "total_unbalance", "viscous_zone", "in_equilibrium_zone", "wetted_arc", "select_liquid",
    "simplified_single_chamber", "multi_chamber", "segment_capacity", "annulus_capacity",
    "optimal_volume", "permissible_eccentricity_household", "permissible_eccentricity_general",
    "iso_grade_from_eccentricity", "eccentricity_from_iso_grade", "unbalance_coefficient",
]
