"""Prescribed rotor kinematics: piecewise-linear speed programme and coast-down.

All quantities are dimensionless: time tau = omega_1 t, speed R = omega/omega_1,
angle phi in rad (book (5.15), (5.28)).  The programme table has rows
``[tau_k, R_k, phi_k]`` where ``phi_k`` is the rotor angle at ``tau_k``
(phi(0) = 0).  Before the first node the speed is ``R_0``; after the last one it
is held.  An optional exponential coast-down starting at ``tau_c`` overrides
the programme: R(tau) = R_c exp(-(tau - tau_c)/T).
"""
from __future__ import annotations

import math

import numpy as np

from stand._jit import njit


def build_table(times: np.ndarray, speeds: np.ndarray) -> np.ndarray:
    """Programme table ``[tau_k, R_k, phi_k]`` from node times and speeds.

    Parameters
    ----------
    times : ndarray
        Node times, dimensionless, strictly increasing, ``>= 0``.
    speeds : ndarray
        Node speeds, dimensionless.
    """
    times = np.asarray(times, dtype=float)
    speeds = np.asarray(speeds, dtype=float)
    # phi_k = phi_{k-1} + the trapezoid of step k (np.cumsum adds in order: the same sums
    # as the loop); a constant speed R_0 before the first node
    steps = np.empty_like(times)
    steps[:1] = speeds[:1] * times[:1]
    steps[1:] = 0.5 * (speeds[1:] + speeds[:-1]) * (times[1:] - times[:-1])
    return np.column_stack([times, speeds, np.cumsum(steps)])


@njit(cache=True, inline="always", error_model="numpy")
def row_before(table, tau, k):
    """The row ``i`` with ``table[i, 0] <= tau < table[i + 1, 0]`` among the first ``k`` rows
    of ``table`` (column 0 non-decreasing, ``table[0, 0] <= tau < table[k - 1, 0]``):
    ``np.searchsorted(table[:k, 0], tau, "right") - 1`` written out as a bisection (numba
    compiles numpy's generic searchsorted, about 1 s, in every cold start)."""
    i, hi = 0, k - 1
    while hi - i > 1:
        mid = (i + hi) // 2
        if table[mid, 0] <= tau:
            i = mid
        else:
            hi = mid
    return i


@njit(cache=True, inline="always", error_model="numpy")
def programme_kinematics(tau, prog, k):
    """(phi, R, dR/dtau) of the piecewise-linear programme made of the first ``k`` rows of
    ``prog`` at ``tau`` (a row count, not a slice: a view costs a reference count in
    compiled code)."""
    if tau <= prog[0, 0]:
        return prog[0, 2] + prog[0, 1] * (tau - prog[0, 0]), prog[0, 1], 0.0
    if tau >= prog[k - 1, 0]:
        return prog[k - 1, 2] + prog[k - 1, 1] * (tau - prog[k - 1, 0]), prog[k - 1, 1], 0.0
    i = row_before(prog, tau, k)
    dt = tau - prog[i, 0]
    a = (prog[i + 1, 1] - prog[i, 1]) / (prog[i + 1, 0] - prog[i, 0])
    return prog[i, 2] + prog[i, 1] * dt + 0.5 * a * dt * dt, prog[i, 1] + a * dt, a


def programme_kinematics_many(taus, prog):
    """(k, 3) array of :func:`programme_kinematics` at the times ``taus`` (k,), in numpy
    (post-processing: no compiled code, so reading a run's rotor angle needs no numba)."""
    taus = np.asarray(taus, dtype=float).reshape(-1)
    k = prog.shape[0]
    out = np.empty((taus.size, 3))
    if k == 1:                        # a constant speed: phi = phi_0 + R (tau - tau_0)
        out[:, 0] = prog[0, 2] + prog[0, 1] * (taus - prog[0, 0])
        out[:, 1] = prog[0, 1]
        out[:, 2] = 0.0
        return out
    t0, tl = prog[0, 0], prog[k - 1, 0]
    i = np.clip(np.searchsorted(prog[:, 0], taus, side="right") - 1, 0, k - 2)
    dt = taus - prog[i, 0]
    with np.errstate(all="ignore"):
        a = (prog[i + 1, 1] - prog[i, 1]) / (prog[i + 1, 0] - prog[i, 0])
    out[:, 0] = prog[i, 2] + prog[i, 1] * dt + 0.5 * a * dt * dt
    out[:, 1] = prog[i, 1] + a * dt
    out[:, 2] = a
    lo = taus <= t0
    hi = (taus >= tl) & ~lo
    for mask, r in ((lo, 0), (hi, k - 1)):
        out[mask, 0] = prog[r, 2] + prog[r, 1] * (taus[mask] - prog[r, 0])
        out[mask, 1] = prog[r, 1]
        out[mask, 2] = 0.0
    return out


@njit(cache=True, inline="always", error_model="numpy")
def rotor_kinematics(tau, prog, k, coast_t0, coast_T, coast_R0, coast_phi0):
    """Rotor angle, speed and acceleration (phi, phi', phi'') at ``tau`` of the programme in
    the first ``k`` rows of ``prog``.

    ``coast_t0 = inf`` disables the coast-down.
    """
    if tau >= coast_t0:
        x = (tau - coast_t0) / coast_T
        ex = math.exp(-x)
        R = coast_R0 * ex
        return coast_phi0 + coast_R0 * coast_T * (1.0 - ex), R, -R / coast_T
    return programme_kinematics(tau, prog, k)


@njit(cache=True, inline="always", error_model="numpy")
def drive_torque_law(model, m0, c1, c2, w_target, t, phi, speed):
    """Drive torque of the book's models 1-3 (section 5.1.1), in any consistent units:
    model 0 a constant ``m0``; 1 ``c1 (w_target - speed)``; 2 adds ``c2 (w_target t - phi)``."""
    if model == 0.0:
        return m0
    m = c1 * (w_target - speed)
    if model == 2.0:
        m += c2 * (w_target * t - phi)
    return m


def breakpoints(prog: np.ndarray, coast_t0: float) -> np.ndarray:
    """Times where phi'' jumps: integration restarts there for accuracy."""
    pts = np.asarray(prog[:, 0], float)
    if np.isfinite(coast_t0):
        pts = np.append(pts[pts < coast_t0], coast_t0)
    return np.unique(pts[pts > 0.0])
