"""Rotating-frame form of the planar model at constant speed, for steady states and Jacobians.

At a constant dimensionless speed R on isotropic supports the equations in a
frame turning with the rotor are autonomous (book (5.44)-(5.48), digest ch5
section 2.4).  Rather than coding (5.47)-(5.48) a second time, the rotating-frame
right-hand side is obtained from the fixed-frame one (:func:`stand.model.planar.rhs_planar`)
at the instant tau = 0 where the two frames coincide (phi = 0):

    xi = u,  eta = v,  xi' = u' - R v,  eta' = v' + R u,
    u'' = xi'' + 2 R v' + R^2 u,   v'' = eta'' - 2 R u' + R^2 v,

and the weights' relative angles alpha_j are the same in both frames.  The
state is ``[u, v, alpha_1..alpha_n, u', v', alpha_1'..alpha_n']`` in units of
L (= r*).  Equilibria of this system are the book's steady motions (5.49); the
eigenvalues of its Jacobian decide their stability (5.87)-(5.90).
"""
from __future__ import annotations

import numpy as np

from stand.integrate.kernel_set import kernels
from stand.model.kernels import PLANAR
from stand.model.planar import COAST_T0, FREE, N_FORCE, N_PROG, N_UB, PlanarModel
from stand.model.programme import build_table


def constant_speed_programme(R: float) -> np.ndarray:
    """Programme table for constant speed R with phi(0) = 0."""
    return build_table(np.array([0.0]), np.array([float(R)]))


def rotating_rhs(model: PlanarModel, R: float, z: np.ndarray) -> np.ndarray:
    """d/dtau of the rotating-frame state ``z`` at constant speed ``R``.

    Requires a prescribed-speed model; the support stiffness and damping should
    be isotropic for the result to be autonomous (not checked here: an
    anisotropic model gives the instantaneous value at phi = 0).
    """
    if model.sp[FREE] != 0.0:
        raise ValueError("rotating frame: the rotor speed must be prescribed (speed drive)")
    n = model.n
    nq = 2 + n
    u, v, du, dv = z[0], z[1], z[nq], z[nq + 1]
    y = np.array(z, dtype=float, copy=True)
    y[nq] = du - R * v
    y[nq + 1] = dv + R * u
    dy = np.empty_like(y)
    prog = constant_speed_programme(R)
    sp = model.sp.copy()
    sp[COAST_T0] = np.inf  # no coast-down
    sp[N_PROG], sp[N_UB], sp[N_FORCE] = 1, 0, 0  # constant speed and unbalance, no side force
    kernels(PLANAR).evaluate(0.0, y, dy, sp, model.wt, prog)
    out = dy.copy()
    out[0], out[1] = du, dv
    out[nq] = dy[nq] + 2 * R * dv + R * R * u
    out[nq + 1] = dy[nq + 1] - 2 * R * du + R * R * v
    return out


def rotating_jacobian(model: PlanarModel, R: float, z: np.ndarray, step: float = 1e-7) -> np.ndarray:
    """Jacobian of :func:`rotating_rhs` by central differences."""
    z = np.asarray(z, dtype=float)
    J = np.empty((z.size, z.size))
    for i in range(z.size):
        dz = np.zeros_like(z)
        dz[i] = step * max(1.0, abs(z[i]))
        J[:, i] = (rotating_rhs(model, R, z + dz) - rotating_rhs(model, R, z - dz)) / (2 * dz[i])
    return J


def main_motion_state(model: PlanarModel, alphas) -> np.ndarray:
    """Rotating-frame state of a main (balancing) motion: shaft on the axis,
    weights at relative angles ``alphas`` [rad], everything at rest in the frame."""
    z = np.zeros(2 * (2 + model.n))
    z[2:2 + model.n] = alphas
    return z
