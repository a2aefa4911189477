"""Classical fixed-step RK4 on the compiled right-hand sides (for error reports).

The paper-001 authors used "RK4 with an automatic step"; a fixed-step RK4 is
the reference class of method whose numerical damping of an undamped free
whirl the error reports show (papers digest 5.2 item 4).  Samples are taken
at the step nearest each requested time (the step divides the sample
interval exactly when ``step = interval / k``).
"""
from __future__ import annotations

from typing import Callable

import numpy as np

from stand._jit import literally, njit
from stand.model.kernels import derivatives

__all__ = ["rk4_loop", "rk4_fixed_step"]


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
    out[0, :] = y
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
            out[row, :] = y
            row += 1
    return 4 * n_steps


def rk4_fixed_step(fun: Callable, t0: float, y0, dt: float, n_steps: int,
                   record_every: int = 1):
    """Classical 4th-order Runge-Kutta with a fixed step on a Python right-hand side
    (paper 001's method class, l. 77, without its step control).

    Parameters
    ----------
    fun : callable
        ``fun(t, y) -> dy/dt`` on a 1-D numpy array.
    t0 : float
        Start time [s].
    y0 : array_like
        Initial state.
    dt : float
        Step [s], > 0.
    n_steps : int
        Number of steps.
    record_every : int
        Keep every ``record_every``-th state (the first and the last are
        always kept).

    Returns
    -------
    t : ndarray, y : ndarray (len(y0), k), nfev : int
    """
    dt = float(dt)
    if not (np.isfinite(dt) and dt > 0):
        raise ValueError(f"dt = {dt!r}: must be > 0 (s)")
    n_steps = int(n_steps)
    if n_steps < 0:
        raise ValueError(f"n_steps = {n_steps!r}: must be >= 0")
    if record_every < 1:
        raise ValueError(f"record_every = {record_every!r}: must be >= 1")
    y = np.array(y0, dtype=float)
    ts, ys = [t0], [y.copy()]
    half = 0.5 * dt
    for k in range(1, n_steps + 1):
        t = t0 + (k - 1) * dt
        k1 = fun(t, y)
        k2 = fun(t + half, y + half * k1)
        k3 = fun(t + half, y + half * k2)
        k4 = fun(t + dt, y + dt * k3)
        y = y + (dt / 6.0) * (k1 + 2.0 * (k2 + k3) + k4)
        if k % record_every == 0 or k == n_steps:
            ts.append(t0 + k * dt)
            ys.append(y.copy())
    return np.array(ts), np.array(ys).T, 4 * n_steps
