"""Main (balancing) motions of a planar rotor with n correction weights: stability.

Digest ch5 sections 3.1 and 4.1-4.4 (book sections 5.2-5.3).  In a main motion
(5.50) the weights rotate with the rotor, the shaft sits on the rotation axis
(s~ = 0) and the weights cancel the unbalance, sum e_j e^{i alpha_j} + e0 = 0.
Linearised about it the motion has the characteristic polynomial (5.90) of
degree 8; only (Rt, h, H, d, R) matter (5.91), all dimensionless (digest ch5
section 2.2): R = omega/omega_1, Rt = R~_m, h the weight drag, H the support
damping, d the configuration parameter (5.88).

This module gathers the theory; the code lives in

* :mod:`stand.theories.planar.main_charpoly` -- the polynomial (5.90), its conservative
  form (5.98), eigenvalues, spectral abscissa, the stability verdict
  :func:`is_stable`, the parameter d (5.88), and the independent check on the
  simulator's rotating-frame Jacobian;
* :mod:`stand.theories.planar.main_critical` -- the critical speeds (where stability is
  gained or lost), the unbalance-independent threshold, the exact high-speed
  ball-drag threshold;
* :mod:`stand.theories.planar.main_closed_forms` -- the book's closed forms
  (5.96)-(5.128) and the slow balancing roots.
"""
from __future__ import annotations

from stand.theories.planar.main_charpoly import (  # noqa: F401  (the private ones: batch forms used by stand.sweep)
    StabilityWarning, _abscissa_batch, _abscissa_tol, _conservative_margin_batch,
    _conservative_tol, charpoly_coefficients, conservative_coefficients, d_from_angles,
    d_two_balls, is_stable, jacobian_eigenvalues, main_eigenvalues, spectral_abscissa,
)
from stand.theories.planar.main_closed_forms import (
    R1_first_order, R1_max_closed_form, R1_max_validity, R1_refined, R_window_large_H,
    balancing_rate, conservative_R1_k1, conservative_R1_parametric, conservative_R1_series,
    conservative_R23_k1, conservative_series_k0, high_speed_h_crit,
)
from stand.theories.planar.main_critical import (  # noqa: F401  (R_MIN/MAX_DEFAULT: not in __all__)
    R_MAX_DEFAULT, R_MIN_DEFAULT, CriticalSpeed, critical_speeds, high_speed_h_crit_exact,
    unbalance_independent_threshold,
)

__all__ = [
    "StabilityWarning", "CriticalSpeed",
    "charpoly_coefficients", "conservative_coefficients", "main_eigenvalues",
    "spectral_abscissa", "is_stable",
    "d_two_balls", "d_from_angles",
    "critical_speeds", "unbalance_independent_threshold",
    "R1_first_order", "R1_refined", "R1_max_closed_form", "R1_max_validity",
    "high_speed_h_crit", "high_speed_h_crit_exact",
    "conservative_series_k0", "conservative_R1_parametric", "conservative_R1_k1",
    "conservative_R1_series", "conservative_R23_k1", "R_window_large_H",
    "balancing_rate", "jacobian_eigenvalues",
]
