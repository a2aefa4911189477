"""The autobalancer-damper (ABD, book 7.2): one correction weight in spherical motion.

Digest ``ch7_ch1.md`` sections 0, 2, 5 and 6 (Filimonikhin 2004, section 7.2).

Physical model (digest 2.2)
---------------------------
The rotor of 7.1 (plane-parallel motion, isotropic supports ``c`` [N/m], external
viscous coefficient ``H2`` [N s/m], constant spin ``omega`` [rad/s]) carries one
correction weight (CW) of mass ``m`` [kg] that can turn in any way about a
suspension point on the rotor axis (cardan, sphere in a spherical cavity or a
ball joint).  The CW's centre of mass lies at distance ``l`` [m] from the point,
its inertia tensor about the point is spherical, ``A`` [kg m^2] (the book's
design rule), a viscous moment ``-H1 (w - omega e_z)`` [N m s] acts on its
angular velocity relative to the rotor, gravity ``g`` acts downwards along the
rotor axis.  5 DOF: shaft ``x, y`` and the three orientation angles.

Singularity-free formulation (replaces the Euler angles of (7.47))
------------------------------------------------------------------
The book writes the CW equations in Euler angles ``psi, phi, theta``, which are
singular at the neutral position ``phi = 0`` -- exactly where the weight rests.
Because the inertia tensor about the suspension point is spherical, the
angular momentum is ``A w`` in *any* frame, so the CW dynamics is Euler's law in
the inertial frame, and only the unit vector ``n`` from the suspension point to
the CW's centre of mass matters (the proper rotation ``theta`` is cyclic; its
rate is the component ``w . n``).  Dimensionless, with ``tau = omega0 t``::

    n'  = W x n  +  k_c (1 - |n|^2) n / 2          (constraint stabilisation)
    W'  = -R_g^2 n x e_z  -  n x a  -  h (W - R_omega e_z)  [+ friction]
    a   = z'' (the shaft acceleration as a horizontal 3-vector)
    z'' + H z' + z = -R_m (n_x + i n_y)'' + R_m R_omega^2 e0 e^{i(R_omega tau + gamma)}

``W`` is the absolute angular velocity in ``omega0`` units.  ``n' = W x n``
preserves ``|n| = 1`` exactly; the term ``k_c (1 - |n|^2) n / 2`` (default
``k_c = 1``) makes the unit sphere attracting for the integration error.  All
forces use ``n / |n|``.  Eliminating ``n''`` gives a 2x2 system for ``a`` solved
in closed form (Sherman-Morrison):
``[(1 - R_m) I + R_m n_h n_h^T] a_h = b``.

The relation to the book's angles: ``n = (-sin phi sin psi_a, sin phi cos psi_a,
-cos phi)`` with ``psi_a = psi + R_omega tau`` the absolute angle (``phi = 0``:
centre of mass straight below the point), and ``W = (psi' + R_omega) e_z +
phi' e_N + theta' e_3`` (``e_N = (cos psi_a, sin psi_a, 0)``, ``e_3 = -n``).
This reproduces the three CW equations of (7.47) (the digest checked them) and
the rotor equations of (7.47) with erratum E1 (``phi''``, ``psi''`` in the
braces).  The steady-motion equations (7.51)-(7.53) follow from it by hand
(torque balance ``n x (R_g^2 e_z - R_omega^2 Z) = 0`` gives (7.62), the rotor
equation then (7.53)); the test suite checks that every root of (7.53) is an
equilibrium of the rotating frame to 1e-12 (the one model's,
:func:`stand.theories.weights.one_model.rotating_form`, and the book's own, the test
oracle ``tests/oracles/damper.py``).

Dimensionless parameters (7.48)-(7.50)::

    omega0 = sqrt(c/M_Sigma),  rho = sqrt(A/m),  z = (x + i y) l / rho^2,
    R_m = m l^2/(M_Sigma rho^2),  R_omega = omega/omega0,  R_g^2 = g l/(rho^2 omega0^2),
    h = H1/(m rho^2 omega0),  H = H2/(M_Sigma omega0),  e0 = M e/(m l).

Dry friction (7.79)-(7.84), optional (:class:`DryFriction`)
-----------------------------------------------------------
A regularised Coulomb moment on the relative angular velocity
``W_r = W - R_omega e_z``::

    T_f = -R_f N W_r / sqrt(|W_r|^2 + eps^2),
    N   = |a + kappa n'' + R_g^2 e_z|     (the joint reaction / (m l omega0^2 ...))

where ``N`` is the dimensionless joint reaction force (``m`` times the
absolute acceleration of the CW's centre of mass minus gravity) and
``kappa = m l^2 / A`` (1 for a point-mass CW).  ``R_f = h_j f / (l sqrt(1 + f^2))``
(7.81) for a cardan or sphere, or the ball-joint law (7.84).  ``N`` depends on
the accelerations, which depend on ``T_f``: two fixed-point passes are made
(contraction factor about ``R_f``).  The regularisation ``eps`` turns perfect
sticking into a slow creep at relative rates ~ ``eps`` (use a small ``eps``
with ``method="LSODA"``: the regularised law is stiff); the quasi-static
residual unbalance of (7.80) is recovered when ``eps`` is small.  In (7.80) the
ratio ``R_m`` is ``m / M_Sigma`` -- equal to this module's ``R_m`` for
``kappa = 1``; :func:`residual_unbalance` takes it as an argument.

State vector (fixed frame; the rotating frame has the same quantities in
rotating-frame components)::

    s = [x, y, x', y', n_x, n_y, n_z, W_x, W_y, W_z]

Modules
-------
This module re-exports the parameters (:mod:`.damper_params`) and the model's functions from
:mod:`.damper_motion` (frames, initial states) and :mod:`.damper_residual` (dry-friction
residual unbalance (7.80)-(7.84)).  The steady motions (7.51)-(7.62), efficiency (7.54) and
stability (7.63)-(7.74) are theory: :mod:`stand.theories.weights.damper_steady`.
"""
from __future__ import annotations

from stand.model.balancers.damper_params import DryFriction, DamperParams
from stand.model.balancers.damper_motion import (angles_from_state, residual_unbalance_now, state_from_angles,
                                                 to_fixed, to_rotating)
from stand.model.balancers.damper_residual import (R_f_ball_joint, R_f_cardan, residual_cubic, residual_parametric,
                              residual_unbalance)

__all__ = [
    "DryFriction", "DamperParams", "state_from_angles", "angles_from_state", "to_rotating",
    "to_fixed", "R_f_cardan", "R_f_ball_joint", "residual_parametric", "residual_unbalance",
    "residual_cubic", "residual_unbalance_now",
]
