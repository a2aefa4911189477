"""Autobalancer-damper (book 7.2): frames and initial states.

Part of :mod:`stand.model.balancers.damper` (model, parameters and the
direction-vector formulation are described there).  The damper runs on the one
model (the generic composition, :mod:`stand.model.balancers.composition`; its
rotating frame, :mod:`stand.theories.weights.one_model`); the book's own equations
of motion (7.47) with erratum E1 are the test oracle ``tests/oracles/damper.py``.
State vector, fixed frame, and the same quantities in rotating-frame components::

    s = [x, y, x', y', n_x, n_y, n_z, W_x, W_y, W_z]
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from stand.model.balancers._ode import check_frame

if TYPE_CHECKING:
    from stand.model.balancers.damper_params import DamperParams

__all__ = ["state_from_angles", "angles_from_state", "to_rotating", "to_fixed",
           "residual_unbalance_now"]

#: the rotor axis (unit vector, upwards)
_EZ = np.array([0.0, 0.0, 1.0])


def _rot(v, ang):
    c, s = math.cos(ang), math.sin(ang)
    return np.array([c * v[0] - s * v[1], s * v[0] + c * v[1], v[2]])


def to_rotating(tau: float, s, R_omega: float) -> np.ndarray:
    """Fixed-frame state -> rotating-frame components (same layout)."""
    s = np.asarray(s, dtype=float)
    e = complex(math.cos(R_omega * tau), -math.sin(R_omega * tau))
    z, dz = complex(s[0], s[1]), complex(s[2], s[3])
    zeta, dzeta = z * e, (dz - 1j * R_omega * z) * e
    return np.concatenate([[zeta.real, zeta.imag, dzeta.real, dzeta.imag],
                           _rot(s[4:7], -R_omega * tau), _rot(s[7:10], -R_omega * tau)])


def to_fixed(tau: float, s, R_omega: float) -> np.ndarray:
    """Rotating-frame components -> fixed-frame state (inverse of :func:`to_rotating`)."""
    s = np.asarray(s, dtype=float)
    e = complex(math.cos(R_omega * tau), math.sin(R_omega * tau))
    zeta, dzeta = complex(s[0], s[1]), complex(s[2], s[3])
    z, dz = zeta * e, (dzeta + 1j * R_omega * zeta) * e
    return np.concatenate([[z.real, z.imag, dz.real, dz.imag],
                           _rot(s[4:7], R_omega * tau), _rot(s[7:10], R_omega * tau)])


def state_from_angles(phi: float, psi: float, R_omega: float, *, xi: float = 0.0, eta: float = 0.0,
                      dphi: float = 0.0, dpsi: float = 0.0, dtheta: float = 0.0,
                      dxi: float = 0.0, deta: float = 0.0, frame: str = "rotating") -> np.ndarray:
    """State vector from the book's Euler angles at ``tau = 0`` (where both frames coincide).

    Parameters
    ----------
    phi : float
        Nutation: deflection of the CW from the downward vertical [rad].
    psi : float
        Angle of the CW's offset about the rotor axis, relative to the rotor [rad].
    R_omega : float
        Spin speed [-].
    xi, eta, dxi, deta : float
        Shaft position and rate in the rotating frame [-].
    dphi, dpsi, dtheta : float
        Euler-angle rates [-] (relative to the rotor for ``psi``).
    frame : str
        ``"rotating"`` or ``"fixed"`` layout of the result.
    """
    sp, cp, ss, cs = math.sin(phi), math.cos(phi), math.sin(psi), math.cos(psi)
    n = np.array([-sp * ss, sp * cs, -cp])
    eN = np.array([cs, ss, 0.0])
    W = (dpsi + R_omega) * _EZ + dphi * eN + dtheta * (-n)
    s = np.concatenate([[xi, eta, dxi, deta], n, W])
    return s if check_frame(frame) == "rotating" else to_fixed(0.0, s, R_omega)


def angles_from_state(s) -> tuple[float, float]:
    """``(phi, psi)`` [rad] of a state's direction vector (``phi`` in [0, pi]; ``psi``
    measured in the state's frame; undefined -- returned as 0 -- at ``phi = 0``)."""
    n = np.asarray(s, dtype=float)[4:7]
    n = n / np.linalg.norm(n)
    phi = math.acos(max(-1.0, min(1.0, -n[2])))
    psi = math.atan2(-n[0], n[1]) if math.hypot(n[0], n[1]) > 1e-15 else 0.0
    return phi, psi


def residual_unbalance_now(s, p: DamperParams, tau: float = 0.0) -> float:
    """Instantaneous total unbalance ``|e0 e^{i gamma} + n_h|`` in capacity units [-] (rotating frame)."""
    r = to_rotating(tau, s, p.R_omega) if tau else np.asarray(s, dtype=float)
    nh = complex(r[4], r[5]) / np.linalg.norm(r[4:7])
    return abs(p.e0 * complex(math.cos(p.gamma), math.sin(p.gamma)) + nh)
