"""The book's own equations of the gravity-insensitive coupled pair (book 7.1): test oracle.

The model, its parameters and the derivation are described in
:mod:`stand.model.balancers.gravity_pair`; the package runs the pair on the one model.  Fixed frame, (7.34); rotating frame, (7.2)
with erratum E1 (``phi''``, ``psi''`` in the braces of the rotor equations).
Eliminating ``z''`` decouples the two weight equations exactly, so each
right-hand-side evaluation is closed form::

    phi''  (1 - R_m cos^2 phi)         = -h1 phi' - cos(phi) Im(F e^{-i alpha})
    alpha''(R_rho^2 - R_m sin^2 phi)  = -h2 R_rho^2 (alpha' - R_omega) + sin(phi) Re(F e^{-i alpha})
    z'' = F + R_m (alpha'' sin phi - i phi'' cos phi) e^{i alpha}

State vectors: fixed ``[phi, alpha, x, y, phi', alpha', x', y']``, rotating
``[phi, psi, xi, eta, phi', psi', xi', eta']`` with ``psi = alpha - R_omega tau``
and ``xi + i eta = z e^{-i R_omega tau}`` (7.35).
"""
from __future__ import annotations

import math

import numpy as np

from oracles.book_ode import frame_rhs, integrate
from stand.model.balancers.gravity_pair_params import GravityPairParams

__all__ = ["rhs", "rhs_rotating", "make_rhs", "simulate"]


# ---------------------------------------------------------------------------
# equations of motion
# ---------------------------------------------------------------------------

def rhs(tau: float, y, p: GravityPairParams) -> np.ndarray:
    """Fixed-frame right-hand side of (7.34), usable with ``solve_ivp``.

    Parameters
    ----------
    tau : float
        Dimensionless time ``omega0 t`` [-].
    y : array_like, shape (8,)
        ``[phi, alpha, x, y, phi', alpha', x', y']`` (angles in rad, shaft
        position in units of ``rho1^2 / l``, derivatives per unit ``tau``).
    p : GravityPairParams

    Returns
    -------
    numpy.ndarray, shape (8,)
    """
    phi, al, x, yy, dphi, dal, dx, dy = np.asarray(y, dtype=float).tolist()   # floats: ~3x faster
    Rm, Rw = p.R_m, p.R_omega
    sp, cp = math.sin(phi), math.cos(phi)
    ea = complex(math.cos(al), math.sin(al))
    ub = Rw * Rw * p.e0 * complex(math.cos(Rw * tau + p.gamma), math.sin(Rw * tau + p.gamma))
    F = (-p.H * complex(dx, dy) - complex(x, yy)
         + Rm * ((2.0 * dal * dphi * cp + 1j * (dphi * dphi + dal * dal) * sp) * ea + ub))
    w = F * ea.conjugate()
    ddphi = (-p.h1 * dphi - cp * w.imag) / (1.0 - Rm * cp * cp)
    R2 = p.R_rho * p.R_rho
    ddal = (-p.h2 * R2 * (dal - Rw) + sp * w.real) / (R2 - Rm * sp * sp)
    zdd = F + Rm * (ddal * sp - 1j * ddphi * cp) * ea
    return np.array([dphi, dal, dx, dy, ddphi, ddal, zdd.real, zdd.imag])


def rhs_rotating(tau: float, y, p: GravityPairParams, *, printed_e1: bool = False) -> np.ndarray:
    """Rotating-frame right-hand side of (7.2) with erratum E1.

    Parameters
    ----------
    tau : float
        Dimensionless time [-] (unused: the rotating-frame system is autonomous).
    y : array_like, shape (8,)
        ``[phi, psi, xi, eta, phi', psi', xi', eta']`` [rad, rad, -, -, ...].
    p : GravityPairParams
    printed_e1 : bool
        ``False`` (default): the corrected braces ``[phi'' sin psi + ...]``,
        ``[psi'' cos psi ...]``, ``[psi'' sin psi ...]``, ``[phi'' cos psi ...]``.
        ``True``: the printed (OCR) form with ``phi'``, ``psi'`` in those four
        places -- physically wrong, kept only to demonstrate E1.

    Returns
    -------
    numpy.ndarray, shape (8,)
    """
    phi, psi, xi, eta, dphi, dpsi, dxi, deta = np.asarray(y, dtype=float).tolist()
    Rm, Rw = p.R_m, p.R_omega
    sp, cp = math.sin(phi), math.cos(phi)
    ep = complex(math.cos(psi), math.sin(psi))
    zeta, dzeta = complex(xi, eta), complex(dxi, deta)
    dal = dpsi + Rw
    # absolute acceleration A = zeta'' + 2 i Rw zeta' - Rw^2 zeta; rotor equation:
    # A + H (zeta' + i Rw zeta) + zeta - R_m{[(2 al' phi' - i phi'') cos phi
    #   + (psi'' + i (phi'^2 + al'^2)) sin phi] e^{i psi} + Rw^2 e0 e^{i gamma}} = 0
    F = (-p.H * (dzeta + 1j * Rw * zeta) - zeta
         + Rm * ((2.0 * dal * dphi * cp + 1j * (dphi * dphi + dal * dal) * sp) * ep
                 + Rw * Rw * p.e0 * complex(math.cos(p.gamma), math.sin(p.gamma))))
    R2 = p.R_rho * p.R_rho
    if printed_e1:
        # the printed braces: phi' and psi' instead of phi'' and psi''
        Aacc = F + Rm * (dpsi * sp - 1j * dphi * cp) * ep
        w = Aacc * ep.conjugate()
        ddphi = -p.h1 * dphi - cp * w.imag
        ddpsi = -p.h2 * dpsi + sp * w.real / R2
    else:
        w = F * ep.conjugate()
        ddphi = (-p.h1 * dphi - cp * w.imag) / (1.0 - Rm * cp * cp)
        ddpsi = (-p.h2 * R2 * dpsi + sp * w.real) / (R2 - Rm * sp * sp)
        Aacc = F + Rm * (ddpsi * sp - 1j * ddphi * cp) * ep
    zdd = Aacc - 2j * Rw * dzeta + Rw * Rw * zeta
    return np.array([dphi, dpsi, dxi, deta, ddphi, ddpsi, zdd.real, zdd.imag])


def make_rhs(p: GravityPairParams, frame: str = "fixed"):
    """``f(tau, y)`` closure for ``solve_ivp`` (``frame`` = ``"fixed"`` or ``"rotating"``)."""
    return frame_rhs(p, frame, rhs, rhs_rotating)


def simulate(p: GravityPairParams, y0, t_end: float, *, frame: str = "fixed",
             t_eval=None, rtol: float = 1e-8, atol: float = 1e-10, method: str = "DOP853"):
    """Integrate from ``tau = 0`` to ``t_end`` [-] with ``solve_ivp`` (DOP853 by default).

    Returns the ``solve_ivp`` result object; raises ``RuntimeError`` if it fails.
    """
    return integrate(make_rhs(p, frame), y0, t_end, 8, name="y0", t_eval=t_eval, rtol=rtol,
                     atol=atol, method=method)
