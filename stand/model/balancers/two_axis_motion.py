"""Two-axis pendulum CW (ch. 6): frame changes.

Part of :mod:`stand.model.balancers.two_axis` (model, parameters and the derivation
are described there).  The pendulum runs on the one model (the generic composition,
:mod:`stand.model.balancers.composition`; its rotating frame,
:mod:`stand.theories.weights.one_model`); the book's own equations (6.12), (6.15) and
the run-up extension are the test oracle ``tests/oracles/two_axis.py``.

Frame change (6.13) between the rotating-frame state
``[phi, psi, xi, eta, phi', psi', xi', eta']`` and the fixed-frame state
``[phi, alpha, x, y, phi', alpha', x', y']`` (alpha = psi + R_omega tau the CW
azimuth): :func:`rotating_to_fixed`, :func:`fixed_to_rotating`.
"""
from __future__ import annotations

import numpy as np

__all__ = ["rotating_to_fixed", "fixed_to_rotating"]


def rotating_to_fixed(tau, y_rot, R_omega):
    """Map a rotating-frame state (6.12) to the fixed-frame state (6.15) by (6.13).

    psi = alpha - R_omega tau; xi + i eta = (x + i y) e^{-i R_omega tau}.
    Works on arrays ``y_rot`` of shape (8,) or (8, k) with ``tau`` of shape () or (k,).
    """
    ph, ps, xi, et, dph, dps, dxi, det = np.asarray(y_rot, float)
    th = R_omega * np.asarray(tau, float)
    c, s = np.cos(th), np.sin(th)
    x = xi * c - et * s
    y = xi * s + et * c
    vxi = dxi - R_omega * et          # rotating components of the absolute velocity
    vet = det + R_omega * xi
    dx = vxi * c - vet * s
    dy = vxi * s + vet * c
    return np.array([ph, ps + th, x, y, dph, dps + R_omega, dx, dy])


def fixed_to_rotating(tau, y_fix, R_omega):
    """Inverse of :func:`rotating_to_fixed`."""
    ph, al, x, y, dph, dal, dx, dy = np.asarray(y_fix, float)
    th = R_omega * np.asarray(tau, float)
    c, s = np.cos(th), np.sin(th)
    xi = x * c + y * s
    et = -x * s + y * c
    vxi = dx * c + dy * s
    vet = -dx * s + dy * c
    return np.array([ph, al - th, xi, et, dph, dal - R_omega, vxi + R_omega * et,
                     vet - R_omega * xi])
