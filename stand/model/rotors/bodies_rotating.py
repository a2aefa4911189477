"""Rotating-frame form of the generic composition (planar rotor x weights x bodies), derived.

As :mod:`stand.model.rotating` does for the planar kernel, the rotating-frame
right-hand side is not typed a second time: it is obtained from the fixed-frame
one (:func:`stand.model.rotors.coupled_kernel.rhs_generic`) at the instant tau = 0
where the frames coincide (rotor angle 0), for a constant speed R (per unit of
the model's time scale) on the planar rotor with isotropic supports, where the
rotating-frame system is autonomous.  With ``Z = z e^{i R tau}`` for every
planar vector (shaft, free-surface offset) and the body angles::

    Z = z,   Z' = z' + i R z,   z'' = Z'' - 2 i R z' + R^2 z
    alpha = psi,  alpha' = psi' + R                (azimuths: relative psi)
    n, W (damper): same components at tau = 0;  n_r' = n' - R e_z x n,
                   W_r' = W' - R e_z x W

so the equilibria of :func:`rotating_rhs` are the steady motions of the books
((5.49), (6.12) steady states, (7.6), (7.51)) -- the tests check the book's
steady motions against it, which ties the books' rotating-frame equations to
the one fixed-frame composition.

State ``z`` (scaled as the model's state, rotating components): the model's
layout with the shaft and the LAG offset in rotating components, the point
weights' and tilting bodies' azimuths relative to the rotor.
"""
from __future__ import annotations

import numpy as np

from stand.model.rotors import bodies_kernel as bk
from stand.model.rotors.coupled_kernel import CoupledModel
from stand.integrate.kernel_set import kernels
from stand.model.kernels import GENERIC

__all__ = ["rotating_rhs", "rotating_to_fixed"]


def _check(model: CoupledModel):
    if model.n != 2 or model.rotor.name != "planar":
        raise ValueError("rotating frame: defined for the planar rotor (two coordinates) here")
    if model.n_adhesion:
        raise ValueError("rotating frame: weights with adhesion states are not autonomous")


def rotating_to_fixed(model: CoupledModel, R: float, z: np.ndarray) -> np.ndarray:
    """The fixed-frame state at tau = 0 of the rotating-frame state ``z`` (speed ``R``)."""
    _check(model)
    n, nw = model.n, model.nw
    y = np.array(z, dtype=float)
    ns = n + nw
    u, v, du, dv = z[0], z[1], z[ns], z[ns + 1]
    y[ns], y[ns + 1] = du - R * v, dv + R * u
    y[ns + n:ns + n + nw] = z[ns + n:ns + n + nw] + R
    for row in model.bt:
        o, kind = int(row[bk.B_OFF]), int(row[bk.B_KIND])
        if kind == bk.TILT:
            y[o + 3] = z[o + 3] + R
    return y


def rotating_rhs(model: CoupledModel, R: float, z: np.ndarray) -> np.ndarray:
    """d/dtau of the rotating-frame state ``z`` at the constant speed ``R`` (module docstring).

    ``model`` must be built with the constant programme ``R * omega_ref`` rad/s.
    """
    _check(model)
    n, nw = model.n, model.nw
    ns = n + nw
    y = rotating_to_fixed(model, R, z)
    dy = np.zeros_like(y)
    kernels(GENERIC).evaluate(0.0, y, dy, model.sp, model.wt, model.prog)
    dz = np.array(dy)
    u, v, du, dv = z[0], z[1], z[ns], z[ns + 1]
    dz[0], dz[1] = du, dv
    # z'' = Z'' - 2 i R z' + R^2 z
    dz[ns] = dy[ns] + 2 * R * dv + R * R * u
    dz[ns + 1] = dy[ns + 1] - 2 * R * du + R * R * v
    dz[n:ns] = z[ns + n:ns + n + nw]                 # psi' (relative)
    for row in model.bt:
        o, kind = int(row[bk.B_OFF]), int(row[bk.B_KIND])
        if kind == bk.TILT:
            dz[o + 1] = z[o + 3]                         # psi' = alpha' - R
        elif kind == bk.SPHERE:
            for a in (o, o + 3):                         # - R e_z x (a0, a1, a2)
                dz[a] += R * y[a + 1]
                dz[a + 1] -= R * y[a]
        elif kind == bk.LAG:
            dz[o] += R * y[o + 1]
            dz[o + 1] -= R * y[o]
    return dz
