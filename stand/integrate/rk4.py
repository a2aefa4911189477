"""Classical fixed-step RK4 on the compiled right-hand sides (for error reports).

The paper-001 authors used "RK4 with an automatic step"; a fixed-step RK4 is
the reference class of method whose numerical damping of an undamped free
whirl the error reports show (papers digest 5.2 item 4).  Samples are taken
at the step nearest each requested time (the step divides the sample
interval exactly when ``step = interval / k``).
"""
from __future__ import annotations

import numpy as np

from stand._jit import literally, njit
from stand.model.kernels import derivatives

__all__ = ["rk4_loop"]


@njit(cache=True, error_model="numpy")
def rk4_loop(kind, sp, wt, prog, y, h, n_steps, every, out):
    """Advance ``n_steps`` steps of size ``h`` from t = 0, writing ``y`` into
    ``out[k]`` after every ``every`` steps (``out[0]`` = initial state).
    Returns the number of RHS evaluations."""
    literally(kind)  # one compiled loop per model kind
    n = y.size
    k1 = np.empty(n)
    k2 = np.empty(n)
    k3 = np.empty(n)
    k4 = np.empty(n)
    tmp = np.empty(n)
    for i in range(n):      # (loops, not out[0, :] = y: a slice assignment compiles numba's
        out[0, i] = y[i]    # shape-mismatch message, seconds of string code on a cold start)
    row = 1
    t = 0.0
    for s in range(n_steps):
        derivatives(kind, t, y, k1, sp, wt, prog)
        for i in range(n):
            tmp[i] = y[i] + 0.5 * h * k1[i]
        derivatives(kind, t + 0.5 * h, tmp, k2, sp, wt, prog)
        for i in range(n):
            tmp[i] = y[i] + 0.5 * h * k2[i]
        derivatives(kind, t + 0.5 * h, tmp, k3, sp, wt, prog)
        for i in range(n):
            tmp[i] = y[i] + h * k3[i]
        derivatives(kind, t + h, tmp, k4, sp, wt, prog)
        for i in range(n):
            y[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])
        t = (s + 1) * h
        if (s + 1) % every == 0 and row < out.shape[0]:
            for i in range(n):
                out[row, i] = y[i]
            row += 1
    return 4 * n_steps
