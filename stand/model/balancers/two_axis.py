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
The package runs the pendulum on the one model (the generic composition,
:mod:`.composition`; its rotating frame, :mod:`.one_model`).  The book's own forms
are the test oracle ``tests/oracles/two_axis.py``:

* (6.12) rotating frame, state ``y = [phi, psi, xi, eta, phi', psi', xi', eta']``
  (' = d/dtau): ``rhs_rotating``, residual ``residual_rotating``.
  OCR fix (digest 2.3): the brackets of l3, l4 contain the second derivatives
  phi'', psi'' (the print shows first derivatives).
* (6.15) fixed frame, state ``y = [phi, alpha, x, y, phi', alpha', x', y']`` with
  alpha = psi + R_omega tau the CW azimuth: ``rhs_fixed``,
  ``residual_fixed``.  OCR fix: phi'' cos(alpha) in L4.
* Run-up / run-down (digest 2.6, not in the book): ``rhs_fixed_variable_speed``.

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
This module re-exports the parameters (:mod:`.two_axis_params`) and the model's frame
changes (6.13) (:mod:`.two_axis_motion`).  The theory is in :mod:`stand.theories.weights`:
linearisation and steady motions of section 6.2 in ``two_axis_steady``, sections 6.3-6.5 in
``two_axis_theory``.
"""
from __future__ import annotations

from stand.model.balancers.two_axis_params import TwoAxisParams
from stand.model.balancers.two_axis_motion import fixed_to_rotating, rotating_to_fixed

__all__ = [
    "TwoAxisParams", "rotating_to_fixed", "fixed_to_rotating",
]
