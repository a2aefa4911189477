"""Steady motions with the weights fixed relative to the rotor: main motions
(5.50), side motions (5.51)-(5.75), the e0 > 1 "maximally balanced" main
motion, and their stability from the rotating-frame Jacobian (section 5.4).

Digest ch5 sections 3 and 4.5 (book sections 5.2 and 5.4), dimensionless
units (digest ch5 section 2.2): R = omega/omega_1, e0 and e_j in units of the
balancing capacity, shaft deflections in units of r*.  This module gathers the
theory; the code lives in

* :mod:`stand.theories.planar.steady` -- which steady motions exist: the steady
  equations (5.49) and their conventions (the corrected (5.57) and (5.64)),
  main motions (5.50), the maximally balanced motion, side motions and their
  existence windows (5.61)-(5.75);
* :mod:`stand.theories.planar.steady_stability` -- their stability: the rotating-frame
  state, the Jacobian's eigenvalues, the e0 > 1 conservative coefficients
  (5.155)-(5.158) and :func:`stable_steady_motions`, all motions at a speed
  with their verdicts.
"""
from __future__ import annotations

from stand.theories.planar.steady import (MainMotion, SideClass, SideMotion, bits_of, identical_side_classes,
                     main_motion_angles, maximally_balanced_motion, net_unbalance,
                     side_motions, side_window, steady_deflection, steady_residual)
from stand.theories.planar.steady_stability import (SteadyMotionReport, is_stable, large_unbalance_coefficients,
                               stable_steady_motions, steady_eigenvalues, steady_state)

__all__ = [
    "MainMotion", "SideMotion", "SideClass", "SteadyMotionReport",
    "steady_deflection", "steady_residual", "net_unbalance", "bits_of",
    "main_motion_angles", "maximally_balanced_motion",
    "side_motions", "side_window", "identical_side_classes",
    "steady_state", "steady_eigenvalues", "is_stable",
    "large_unbalance_coefficients", "stable_steady_motions",
]
