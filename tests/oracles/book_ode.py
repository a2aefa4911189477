"""The books' own integration convention for the test oracles: a right-hand side of the
fixed or the rotating frame, ``f(tau, y, p)``, integrated with ``solve_ivp`` from
``tau = 0`` (used by :mod:`oracles.gravity_pair` and :mod:`oracles.damper`).

All times are the dimensionless ``tau = omega0 t`` [-].  Written apart from the package (no
import of ``stand``): an oracle shares none of the code it checks.
"""
from __future__ import annotations

from typing import Callable

import numpy as np
from scipy.integrate import solve_ivp

__all__ = ["frame_rhs", "integrate"]


def frame_rhs(p, frame: str, fixed: Callable, rotating: Callable) -> Callable:
    """``f(tau, y)`` closure for ``solve_ivp``.

    Parameters
    ----------
    p : parameters dataclass
        Passed as the third argument of the right-hand side.
    frame : {"fixed", "rotating"}
    fixed, rotating : callable
        ``rhs(tau, y, p)`` of the fixed and the rotating frame.
    """
    if frame not in ("fixed", "rotating"):
        raise ValueError(f"frame must be 'fixed' or 'rotating' [-], got {frame!r}")
    rhs = fixed if frame == "fixed" else rotating
    return lambda t, y: rhs(t, y, p)


def integrate(fun: Callable, y0, t_end: float, size: int, *, name: str = "y0", t_eval=None,
              rtol: float = 1e-8, atol: float = 1e-10, method: str = "DOP853"):
    """Integrate ``fun`` from ``tau = 0`` to ``t_end`` [-] with ``solve_ivp``.

    Parameters
    ----------
    fun : callable
        ``f(tau, y)``.
    y0 : array_like, shape (size,)
        Initial state (named ``name`` in the error message).
    t_end : float
        Final dimensionless time [-], > 0.
    size : int
        Length of the state vector.
    t_eval, rtol, atol, method
        Passed to :func:`scipy.integrate.solve_ivp`.

    Returns
    -------
    scipy.integrate.OdeResult

    Raises
    ------
    RuntimeError
        If the integration fails.
    """
    t_end = float(t_end)
    if not (np.isfinite(t_end) and t_end > 0.0):
        raise ValueError(f"t_end must be a finite number > 0 [dimensionless time], got {t_end!r}")
    y0 = np.asarray(y0, dtype=float)
    if y0.shape != (size,):
        raise ValueError(f"{name} must have shape ({size},) [state], got {y0.shape}")
    sol = solve_ivp(fun, (0.0, t_end), y0, method=method, rtol=rtol, atol=atol, t_eval=t_eval)
    if not sol.success:
        raise RuntimeError(f"integration failed: {sol.message}")
    return sol
