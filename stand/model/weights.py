"""Correction weights (balls, pendulums) coupled to the shaft point K.

Each weight j obeys the corrected (5.4):
    J_j phi_j'' + H_j (phi_j' - phi') - m_j l_j (x'' sin phi_j - y'' cos phi_j) = 0,
and pushes the shaft with m_j l_j (phi_j'' sin phi_j + phi_j'^2 cos phi_j, ...)
(corrected (5.7), digest ch5 section 0.2 items 1-2).  The dimensionless
per-weight table used by the compiled right-hand side is built here.
"""
from __future__ import annotations

import numpy as np

#: columns of the weight table
EPS, MU, H, NU = 0, 1, 2, 3


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
      (the corrected coefficient of item 4, digest ch5 section 0.2).
    """
    n = balancer.count
    tab = np.zeros((n, 4))
    if n == 0:
        return tab
    m = np.asarray(balancer.mass, float)
    l = np.asarray(balancer.radius, float)
    J = np.asarray(balancer.inertia, float)
    Hm = balancer.moment_drag
    tab[:, EPS] = m * l / (total_mass * length)
    tab[:, MU] = m * l * length / J
    tab[:, H] = Hm / (omega_1 * J)
    if rotor_inertia:
        tab[:, NU] = Hm / (omega_1 * rotor_inertia)
    return tab
