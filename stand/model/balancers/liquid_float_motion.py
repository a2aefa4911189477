"""Liquid float balancer, model M1 of paper 001: speed laws, stationary orbit, equations.

Part of :mod:`stand.model.balancers.liquid_float` (model and parameters are
described there).

* Speed laws (defined beside the parameters, :mod:`.liquid_float_params`): the paper's
  linear run-up (6) ``beta' = omega_0 + 2 epsilon t`` (:class:`LinearSpeed`), a speed
  step (:class:`StepSpeed`, paper [2]) and any smooth law (:class:`GeneralSpeed`).
* Stationary orbit (5) and the initial conditions (7) (fixed frame) / (10)
  (rotating frame); the quasi-static amplitude laws (digest 1.5).
* Right-hand sides: the corrected fixed-frame (4)
  ``m Z'' + chi Z' + c Z = m1 e (beta'^2 - i beta'') e^{i beta}`` and the
  rotating-frame (9) as printed, with their Jacobians for the implicit solvers.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Callable

import numpy as np

from stand.model.balancers._params import PAPER
from stand.model.balancers.liquid_float_params import GeneralSpeed, LinearSpeed, StepSpeed

if TYPE_CHECKING:
    from stand.model.balancers.liquid_float_params import LiquidFloatParams

__all__ = [
    "FRAMES", "LinearSpeed", "StepSpeed", "GeneralSpeed", "stationary_amplitude",
    "initial_state", "steady_amplitudes", "rhs_fixed", "rhs_rotating", "jac_fixed", "jac_rotating",
]

FRAMES = ("rotating", "fixed")


def _speed_for(params: LiquidFloatParams, speed):
    return params.speed() if speed is None else speed


# ---------------------------------------------------------------------------
# stationary solution, initial conditions, steady laws
# ---------------------------------------------------------------------------

def stationary_amplitude(params: LiquidFloatParams, omega: float | None = None) -> complex:
    """Complex amplitude ``A`` [m] of the stationary orbit ``Z = A e^{i omega t}`` (5).

    ``A = m1 e omega^2 / (c - m omega^2 + i chi omega)
    = D [(c - m omega^2) - i chi omega]``, with ``D`` of (5).  In the rotating
    frame this is the constant point ``x + i y = A`` of (10).

    Parameters
    ----------
    params : LiquidFloatParams
    omega : float, optional
        Speed [rad/s]; default ``params.omega_0``.

    Raises
    ------
    ValueError
        At the undamped critical speed (``n = 0``, ``omega = Omega``).
    """
    w = params.omega_0 if omega is None else PAPER.finite("omega", omega, "rad/s")
    den = params.Omega ** 2 - w * w + 2j * params.h * w
    if den == 0:
        raise ValueError(f"omega = {w!r} [rad/s]: equals the critical speed Omega = "
                         f"Omega_0 sqrt(psi) with n = 0; the stationary orbit (5) is unbounded")
    return params.q * w * w / den


def initial_state(params: LiquidFloatParams, frame: str = "rotating",
                  omega: float | None = None) -> np.ndarray:
    """Initial state [m, m, m/s, m/s] from (7) (fixed frame) or (10) (rotating).

    Fixed: ``[xi, eta, xi', eta'] = [Re A, Im A, Re(i w A), Im(i w A)]``, which
    is (7): ``xi = D(c - m w^2)``, ``eta = -D chi w``, ``xi' = D chi w^2``,
    ``eta' = D (c - m w^2) w``.  Rotating: ``[x, y, x', y'] = [Re A, Im A, 0, 0]`` (10).
    At t = 0 the two frames coincide (``beta(0) = 0``).
    """
    frame = _check_frame(frame)
    w = params.omega_0 if omega is None else omega
    A = stationary_amplitude(params, w)
    if frame == "rotating":
        return np.array([A.real, A.imag, 0.0, 0.0])
    V = 1j * w * A
    return np.array([A.real, A.imag, V.real, V.imag])


def steady_amplitudes(params: LiquidFloatParams, omega):
    """Quasi-static (steady) amplitude laws at speed ``omega`` [rad/s] (digest 1.5).

    Returns
    -------
    delta_over_e : ndarray
        ``psi omega^2 / sqrt((Omega^2 - omega^2)^2 + 4 h^2 omega^2)`` [-].
    d : ndarray
        ``sqrt(Omega^4 + 4 h^2 omega^2) / sqrt((Omega^2 - omega^2)^2 + 4 h^2 omega^2)`` [-].
    """
    w = np.asarray(omega, dtype=float)
    O2, h = params.Omega ** 2, params.h
    den = np.sqrt((O2 - w * w) ** 2 + 4.0 * h * h * w * w)
    with np.errstate(divide="ignore"):
        return params.psi * w * w / den, np.sqrt(O2 * O2 + 4.0 * h * h * w * w) / den


# ---------------------------------------------------------------------------
# right-hand sides
# ---------------------------------------------------------------------------

def _check_frame(frame: str) -> str:
    if frame not in FRAMES:
        raise ValueError(f"frame = {frame!r}: must be one of {FRAMES}")
    return frame


def rhs_fixed(params: LiquidFloatParams, speed=None) -> Callable:
    """Right-hand side ``f(t, y)`` of the corrected fixed-frame equations (4).

    ``y = [xi, eta, xi', eta']`` [m, m, m/s, m/s]; ``y`` may also be ``(4, k)``
    (``vectorized=True`` in solve_ivp).  Digest correction of the printed (4):
    the forcing is ``m1 e (beta'^2 cos beta + beta'' sin beta)`` and
    ``m1 e (beta'^2 sin beta - beta'' cos beta)`` (re-derived from (2)-(3)).
    """
    sp = _speed_for(params, speed)
    O2, h2, q = params.Omega ** 2, 2.0 * params.h, params.q
    beta, omega, alpha = sp.beta, sp.omega, sp.alpha

    def f(t, y):
        xi, eta, vxi, veta = y[0], y[1], y[2], y[3]
        b, w, a = beta(t), omega(t), alpha(t)
        cb, sb = np.cos(b), np.sin(b)
        w2 = w * w
        return np.array([vxi, veta,
                         -h2 * vxi - O2 * xi + q * (w2 * cb + a * sb),
                         -h2 * veta - O2 * eta + q * (w2 * sb - a * cb)])
    return f


def rhs_rotating(params: LiquidFloatParams, speed=None) -> Callable:
    """Right-hand side ``f(t, y)`` of the rotating-frame equations (9) (as printed).

    ``y = [x, y, x', y']`` [m, m, m/s, m/s] in the frame ``O2xy`` turning with
    the rotor (x along O1P); ``y`` may be ``(4, k)``.  Divided by ``m``:
    ``x'' = 2 w y' + a y + w^2 x - Omega^2 x - 2h (x' - w y) + q w^2`` and
    ``y'' = -2 w x' - a x + w^2 y - Omega^2 y - 2h (y' + w x) - q a``.
    """
    sp = _speed_for(params, speed)
    O2, h2, q = params.Omega ** 2, 2.0 * params.h, params.q
    omega, alpha = sp.omega, sp.alpha

    def f(t, y):
        x, yy, vx, vy = y[0], y[1], y[2], y[3]
        w, a = omega(t), alpha(t)
        w2 = w * w
        return np.array([vx, vy,
                         2.0 * w * vy + a * yy + (w2 - O2) * x - h2 * (vx - w * yy) + q * w2,
                         -2.0 * w * vx - a * x + (w2 - O2) * yy - h2 * (vy + w * x) - q * a])
    return f


def jac_fixed(params: LiquidFloatParams, speed=None) -> Callable:
    """Jacobian ``J(t, y)`` of :func:`rhs_fixed` (constant) for Radau/BDF/LSODA."""
    O2, h2 = params.Omega ** 2, 2.0 * params.h
    J = np.array([[0, 0, 1, 0], [0, 0, 0, 1], [-O2, 0, -h2, 0], [0, -O2, 0, -h2]], float)
    return lambda t, y: J


def jac_rotating(params: LiquidFloatParams, speed=None) -> Callable:
    """Jacobian ``J(t, y)`` of :func:`rhs_rotating` for Radau/BDF/LSODA."""
    sp = _speed_for(params, speed)
    O2, h2 = params.Omega ** 2, 2.0 * params.h

    def J(t, y):
        w, a = float(sp.omega(t)), float(sp.alpha(t))
        k = w * w - O2
        return np.array([[0, 0, 1, 0], [0, 0, 0, 1],
                         [k, a + h2 * w, -h2, 2 * w],
                         [-a - h2 * w, k, -2 * w, -h2]], float)
    return J

