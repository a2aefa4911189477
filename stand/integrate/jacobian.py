"""The finite-difference Jacobian of a compiled right-hand side (scipy's implicit methods).

Used by :mod:`stand.integrate.kernel_set` (the implicit solvers' ``jac``) and compiled
ahead by :mod:`stand.api.warmup`; a module of its own so that the integrator
driver and the kernel set both import it and not each other.
"""
from __future__ import annotations

import numpy as np

from stand._jit import literally, njit
from stand.model.kernels import derivatives

__all__ = ["jac_fd"]


# the RK4 loop's flags (stand.integrate.rk4): the inlined planar right-hand side is compiled
# once for both (numba compiles an overload once per set of the caller's flags)
@njit(cache=True, error_model="numpy")
def jac_fd(kind, t, y, f0, sp, wt, prog, J):
    """Forward-difference Jacobian of model ``kind``'s right-hand side into ``J``."""
    literally(kind)
    n = y.shape[0]
    yy = y.copy()
    df = np.empty(n)
    for i in range(n):
        dh = 1.5e-8 * max(1.0, abs(y[i]))
        yy[i] = y[i] + dh
        derivatives(kind, t, yy, df, sp, wt, prog)
        for k in range(n):
            J[k, i] = (df[k] - f0[k]) / dh
        yy[i] = y[i]
