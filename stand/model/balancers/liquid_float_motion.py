"""Liquid float balancer, model M1 of paper 001: speed laws, stationary orbit, initial states.

Part of :mod:`stand.model.balancers.liquid_float` (model and parameters are
described there).

* Speed laws (defined beside the parameters, :mod:`.liquid_float_params`): the paper's
  linear run-up (6) ``beta' = omega_0 + 2 epsilon t`` (:class:`LinearSpeed`), a speed
  step (:class:`StepSpeed`, paper [2]) and any smooth law (:class:`GeneralSpeed`).
* Stationary orbit (5) and the initial conditions (7) (fixed frame) / (10)
  (rotating frame); the quasi-static amplitude laws (digest 1.5).
The model runs on the one model (the generic composition, planar rotor x liquid
float body, :mod:`stand.model.balancers.composition`).  The paper's own right-hand
sides -- the corrected fixed-frame (4)
``m Z'' + chi Z' + c Z = m1 e (beta'^2 - i beta'') e^{i beta}`` and the rotating-frame
(9) as printed -- and their integrators are the test oracle ``tests/oracles/liquid_float.py``.
"""
from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from stand.model.balancers._params import PAPER
from stand.model.balancers.liquid_float_params import GeneralSpeed, LinearSpeed, StepSpeed

if TYPE_CHECKING:
    from stand.model.balancers.liquid_float_params import LiquidFloatParams

__all__ = [
    "FRAMES", "LinearSpeed", "StepSpeed", "GeneralSpeed", "stationary_amplitude",
    "initial_state", "steady_amplitudes",
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


def _check_frame(frame: str) -> str:
    if frame not in FRAMES:
        raise ValueError(f"frame = {frame!r}: must be one of {FRAMES}")
    return frame
