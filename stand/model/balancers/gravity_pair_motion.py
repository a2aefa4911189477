"""Gravity-insensitive coupled pair (book 7.1): frames and energy.

Part of :mod:`stand.model.balancers.gravity_pair` (model, parameters and the
derivation are described there).  The pair runs on the one model (the generic
composition, :mod:`stand.model.balancers.composition`; its rotating frame,
:mod:`stand.theories.weights.one_model`); the book's own equations -- fixed frame
(7.34), rotating frame (7.2) with erratum E1 -- are the test oracle
``tests/oracles/gravity_pair.py``.

State vectors: fixed ``[phi, alpha, x, y, phi', alpha', x', y']``, rotating
``[phi, psi, xi, eta, phi', psi', xi', eta']`` with ``psi = alpha - R_omega tau``
and ``xi + i eta = z e^{-i R_omega tau}`` (7.35).
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from stand.model.balancers.gravity_pair_params import GravityPairParams

__all__ = ["to_rotating", "to_fixed", "energy"]


def to_rotating(tau, y, R_omega: float) -> np.ndarray:
    """Fixed-frame state(s) -> rotating-frame state(s), (7.35).

    Parameters
    ----------
    tau : float or array_like, shape (n,)
        Time(s) [-].
    y : array_like, shape (8,) or (8, n)
        Fixed-frame state(s) ``[phi, alpha, x, y, phi', alpha', x', y']``.
    R_omega : float
        Spin speed [-].
    """
    y = np.asarray(y, dtype=float)
    tau = np.asarray(tau, dtype=float)
    e = np.exp(-1j * R_omega * tau)
    z = y[2] + 1j * y[3]
    dz = y[6] + 1j * y[7]
    zeta = z * e
    dzeta = (dz - 1j * R_omega * z) * e
    return np.array([y[0], y[1] - R_omega * tau, zeta.real, zeta.imag,
                     y[4], y[5] - R_omega, dzeta.real, dzeta.imag])


def to_fixed(tau, y, R_omega: float) -> np.ndarray:
    """Rotating-frame state(s) -> fixed-frame state(s) (inverse of :func:`to_rotating`)."""
    y = np.asarray(y, dtype=float)
    tau = np.asarray(tau, dtype=float)
    e = np.exp(1j * R_omega * tau)
    zeta = y[2] + 1j * y[3]
    dzeta = y[6] + 1j * y[7]
    z = zeta * e
    dz = (dzeta + 1j * R_omega * zeta) * e
    return np.array([y[0], y[1] + R_omega * tau, z.real, z.imag,
                     y[4], y[5] + R_omega, dz.real, dz.imag])


def energy(y, p: GravityPairParams) -> float:
    """Mechanical energy of the fixed-frame system [-] (units ``M_Sigma rho1^4 omega0^2 / l^2``).

    ``E = |z'|^2/2 + |z|^2/2 + R_m Re(conj(z') w') + R_m (phi'^2 + R_rho^2 alpha'^2)/2``,
    ``w = i sin(phi) e^{i alpha}``.  Conserved when ``h1 = h2 = H = e0 = 0``
    (the Lagrangian behind (7.34)); used by the E1 test.
    """
    phi, al, x, yy, dphi, dal, dx, dy = np.asarray(y, dtype=float)
    dz = complex(dx, dy)
    dw = (1j * math.cos(phi) * dphi - math.sin(phi) * dal) * complex(math.cos(al), math.sin(al))
    return (0.5 * abs(dz) ** 2 + 0.5 * (x * x + yy * yy) + p.R_m * (dz.conjugate() * dw).real
            + 0.5 * p.R_m * (dphi ** 2 + p.R_rho ** 2 * dal ** 2))
