"""Numerics shared by the book's rotor models (:mod:`.two_axis`, :mod:`.gravity_pair`,
:mod:`.damper`): frame selection and the central-difference Jacobian used for the
stability of steady motions.  (The books' own ``solve_ivp`` convention is the test
oracles', ``tests/oracles/book_ode.py``.)

All times are the dimensionless ``tau = omega0 t`` [-].
"""
from __future__ import annotations

from typing import Callable

import numpy as np

__all__ = ["FRAMES", "check_frame", "central_jacobian"]

#: the two state layouts of the book models
FRAMES = ("fixed", "rotating")


def check_frame(frame: str) -> str:
    """``frame`` if it is ``"fixed"`` or ``"rotating"``, else :class:`ValueError`."""
    if frame not in FRAMES:
        raise ValueError(f"frame must be 'fixed' or 'rotating' [-], got {frame!r}")
    return frame


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
