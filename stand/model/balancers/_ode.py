"""Numerics shared by the book's rotor models (:mod:`.two_axis`, :mod:`.gravity_pair`,
:mod:`.damper`): frame selection, the ``solve_ivp`` wrapper and the
central-difference Jacobian used for the stability of steady motions.

All times are the dimensionless ``tau = omega0 t`` [-].
"""
from __future__ import annotations

from typing import Callable

import numpy as np
from scipy.integrate import solve_ivp

from stand.model.balancers._params import BOOK

__all__ = ["FRAMES", "check_frame", "frame_rhs", "integrate", "central_jacobian"]

#: the two state layouts of the book models
FRAMES = ("fixed", "rotating")


def check_frame(frame: str) -> str:
    """``frame`` if it is ``"fixed"`` or ``"rotating"``, else :class:`ValueError`."""
    if frame not in FRAMES:
        raise ValueError(f"frame must be 'fixed' or 'rotating' [-], got {frame!r}")
    return frame


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
    rhs = fixed if check_frame(frame) == "fixed" else rotating
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
    t_end = BOOK.positive("t_end", t_end, "dimensionless time")
    y0 = np.asarray(y0, dtype=float)
    if y0.shape != (size,):
        raise ValueError(f"{name} must have shape ({size},) [state], got {y0.shape}")
    sol = solve_ivp(fun, (0.0, t_end), y0, method=method, rtol=rtol, atol=atol, t_eval=t_eval)
    if not sol.success:
        raise RuntimeError(f"integration failed: {sol.message}")
    return sol


def central_jacobian(f: Callable, x0, steps) -> np.ndarray:
    """Central-difference Jacobian of the vector function ``f`` at ``x0``.

    Parameters
    ----------
    f : callable
        ``f(x) -> ndarray`` of the same length as ``x``.
    x0 : array_like, shape (n,)
    steps : array_like, shape (n,)
        Step of each component (same units as ``x0``).

    Returns
    -------
    numpy.ndarray, shape (n, n)
        ``J[:, k] = (f(x0 + h_k e_k) - f(x0 - h_k e_k)) / (2 h_k)``.
    """
    x0 = np.asarray(x0, dtype=float)
    n = x0.size
    J = np.empty((n, n))
    for k in range(n):
        d = np.zeros(n)
        d[k] = steps[k]
        J[:, k] = (f(x0 + d) - f(x0 - d)) / (2 * d[k])
    return J
