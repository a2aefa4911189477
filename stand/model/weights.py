"""Correction weights (balls, pendulums) coupled to the shaft point K.

Each weight j obeys the corrected (5.4):
    J_j phi_j'' + H_j (phi_j' - phi') - m_j l_j (x'' sin phi_j - y'' cos phi_j) = 0,
and pushes the shaft with m_j l_j (phi_j'' sin phi_j + phi_j'^2 cos phi_j, ...)
(corrected (5.7), digest ch5 section 0.2 items 1-2).  The dimensionless
per-weight table used by the compiled right-hand side is built here.

Rolling balls (``rolling = true``).  A ball of radius r rolling without slip on the rotor's
track spins at (l_j / r)(phi_j' - phi') relative to the rotor: its kinetic energy is
m_j l_j^2 phi_j'^2 / 2 + J_s (phi_j' - phi')^2 / 2 with J_s = (2/5) m_j r^2 (l_j / r)^2 =
(2/5) m_j l_j^2 (small ball, r << l_j: the ball's centre on the radius l_j, terms of order
r / l_j and the rotor-driven spin in phi' alone neglected).  Lagrange's equations give,
with J_j = m_j l_j^2 + J_s = (7/5) m_j l_j^2 (the digest's j = 5/7)::

    J_j phi_j'' - J_s phi'' + H_j (phi_j' - phi') - m_j l_j (x'' sin phi_j - y'' cos phi_j) = 0
    (rotor row, free rotor)  ... + sum_j J_s (phi'' - phi_j'') = M_rot

so the spin inertia drives the ball on a speed ramp and reacts on a free rotor; at constant
speed nothing changes.  The mass matrix couples phi'' and the phi_j'' only through these
terms: the elimination stays O(n) (columns ``rho_j``, ``kappa_j``).  A pendulum's J_j is
about the shaft (absolute): J_s = 0.
"""
from __future__ import annotations

import numpy as np

#: columns of the weight table
EPS, MU, H, NU, RHO, KAPPA = range(6)


def weight_table(balancer, total_mass: float, length: float,
                 omega_1: float, rotor_inertia: float | None) -> np.ndarray:
    """Dimensionless coefficients, one row per weight of ``balancer`` (the attributes of
    :class:`stand.scene.model.Balancer`: ``count``, ``mass`` [kg], ``radius`` [m], ``inertia``
    [kg m^2], ``moment_drag`` [N m s]).

    Columns (see :mod:`stand.model.planar` for the equations):

    * ``eps_j = m_j l_j / (M_Sigma L)``  -- weight's push on the shaft (e_j when L = r*);
    * ``mu_j  = m_j l_j L / J_j``         -- shaft's push on the weight (R_m j_j when L = r*);
    * ``h_j   = H_j / (omega_1 J_j)``     -- relative drag (5.14);
    * ``nu_j  = H_j / (omega_1 J_0)``     -- reaction of the drag on a free rotor
      (the corrected coefficient of item 4, digest ch5 section 0.2);
    * ``rho_j = J_s / J_j``               -- the rotor's angular acceleration driving a
      rolling ball (module docstring; 2/7, else 0);
    * ``kappa_j = J_s / J_0``             -- its reaction on a free rotor.
    """
    n = balancer.count
    tab = np.zeros((n, 6))
    if n == 0:
        return tab
    m = np.asarray(balancer.mass, float)
    l = np.asarray(balancer.radius, float)
    J = np.asarray(balancer.inertia, float)
    Hm = balancer.moment_drag
    tab[:, EPS] = m * l / (total_mass * length)
    tab[:, MU] = m * l * length / J
    tab[:, H] = Hm / (omega_1 * J)
    Js = getattr(balancer, "spin_inertia", 0.0)
    tab[:, RHO] = Js / J
    if rotor_inertia:
        tab[:, NU] = Hm / (omega_1 * rotor_inertia)
        tab[:, KAPPA] = Js / rotor_inertia
    return tab
