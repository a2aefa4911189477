"""Compiled Dormand-Prince 8(5,3) stepping loop with exact sampling by dense output.

The coefficients, error estimator and step-size control are those of
``scipy.integrate.solve_ivp(method="DOP853")`` (Hairer, Norsett & Wanner,
*Solving ODEs I*, section II.10); the loop itself runs in numba so that a step
costs a few right-hand-side evaluations and no Python.  Output is written only
at the requested sample times (7th-order dense output), never for every
internal step, so memory does not grow with the number of steps.

Angles get an error scale capped at ``cap`` (pi) instead of their magnitude:
an angle's accuracy requirement does not relax because it has turned many
times.
"""
from __future__ import annotations

import numpy as np
from stand.integrate.vendor import dop853_coefficients as _co

from stand._jit import literally, njit
from stand.model.kernels import derivatives

N_STAGES = _co.N_STAGES  # 12
A = np.ascontiguousarray(_co.A, dtype=float)  # (16, 16)
B = np.ascontiguousarray(_co.B, dtype=float)  # (12,)
C = np.ascontiguousarray(_co.C, dtype=float)  # (16,)
E3 = np.ascontiguousarray(_co.E3, dtype=float)  # (13,)
E5 = np.ascontiguousarray(_co.E5, dtype=float)  # (13,)
D = np.ascontiguousarray(_co.D, dtype=float)  # (4, 16)

SAFETY = 0.9
MIN_FACTOR = 0.2
MAX_FACTOR = 10.0
ERROR_EXPONENT = -1.0 / 8.0

# status codes returned by :func:`dop853_loop`
REACHED_END = 0
STEP_BUDGET = 1
STEP_TOO_SMALL = -1
NOT_FINITE = -2
DIVERGED = -4

# stats vector layout
N_ACCEPTED, N_REJECTED, N_FEV = 0, 1, 2


@njit(cache=True, inline="always", error_model="numpy")
def _stage_state(y, K, s, h, out):
    """State of stage ``s``: ``y + h sum_k A[s, k] K[k]``, the terms added in the order of k
    (as the loop over k inside did before).  The loop over k is outside, so the state's
    loop vectorises, and the zero coefficients (a quarter of them) are skipped: the same
    sums bit for bit while the stages are finite (a non-finite stage with a zero
    coefficient is left out here, but the new state's and the error estimate's sums take
    every stage, so the step is still rejected)."""
    n = y.shape[0]
    for i in range(n):
        out[i] = 0.0
    for k in range(s):
        a = A[s, k]
        if a != 0.0:
            for i in range(n):
                out[i] += a * K[k, i]
    for i in range(n):
        out[i] = y[i] + h * out[i]


@njit(cache=True, inline="always", error_model="numpy")
def _combine(w, K, m, out):
    """``out = sum_{k < m} w[k] K[k]``, the terms added in the order of k, all of them (zero
    weights too: a non-finite stage must still reach the step's sums).  The loop over k is
    outside, so the loop over the state runs along K's contiguous rows and vectorises;
    bit for bit the sums of the per-component loop over k it replaces (same order, no
    contraction), about 40 % of the stepper's own time at a state of 16 (issue 33 (b))."""
    n = out.shape[0]
    for i in range(n):
        out[i] = 0.0
    for k in range(m):
        a = w[k]
        for i in range(n):
            out[i] += a * K[k, i]


#: rows of the scratch array of :func:`dop853_loop`: the 16 stages, the stage state, the
#: new state and the 7 dense-output coefficients
WORK_ROWS = 25


def workspace(n: int) -> np.ndarray:
    """Scratch array of :func:`dop853_loop` for a state of size ``n``."""
    return np.empty((WORK_ROWS, n))


@njit(cache=True, error_model="numpy", _nrt=False)
def dop853_loop(kind, sp, wt, prog, t, y, f, h_abs, t_end, rtol, atol, cap, max_step,
                ts, k_next, out, stats, max_steps, limit, work):
    """Advance from ``t`` to ``t_end`` writing the samples at times ``ts`` into ``out``.

    Parameters
    ----------
    kind : int
        Model kind for :func:`stand.model.kernels.derivatives`.
    sp, wt, prog : ndarray
        Model parameters passed through to ``rhs``.
    t : float
        Current time; ``y`` (state) and ``f`` (= rhs at (t, y)) are updated in place.
    h_abs : float
        Step size to try first.
    cap : ndarray
        Per-component cap of the magnitude used in the error scale
        (inf = ordinary relative error, pi for angles).
    ts : ndarray
        Sample times, increasing; the last one may equal the end of the run.
    k_next : int
        Index of the next sample to write (its time is > the previous t).
    out : ndarray (n_samples, n)
        Sample buffer.
    stats : ndarray of int64
        Accepted steps, rejected steps, rhs evaluations (incremented).
    max_steps : int
        Maximum accepted + rejected steps in this call.
    limit : float
        Stop with ``DIVERGED`` when an accepted state has a component beyond it.
    work : ndarray (WORK_ROWS, n)
        Scratch space (:func:`workspace`): the loop allocates nothing, so it is compiled
        without numba's reference counting (``_nrt=False``), whose atomic counts of the
        arrays handed to the inlined right-hand side cost 7 % of a run.

    Returns
    -------
    status, t, h_abs, k_next
    """
    literally(kind)  # one compiled loop per model kind, with that kind's right-hand side
    n = y.shape[0]
    n_samples = out.shape[0]
    if work.shape[0] < WORK_ROWS or work.shape[1] < n or f.shape[0] < n or out.shape[1] < n:
        raise ValueError("dop853_loop: work must be workspace(n), f and out rows of size n")
    K = work[0:16]
    yy = work[16]
    y_new = work[17]
    F = work[18:25]
    steps = 0
    nonfinite = False
    while t < t_end:
        if steps >= max_steps:
            return STEP_BUDGET, t, h_abs, k_next
        min_step = 10.0 * abs(np.nextafter(t, np.inf) - t)
        if h_abs > max_step:
            h_abs = max_step
        accepted = False
        rejected = False
        h = h_abs
        t_new = t
        while not accepted:
            if not (h_abs >= min_step):  # also catches a NaN step size
                if nonfinite:
                    return NOT_FINITE, t, h_abs, k_next
                return STEP_TOO_SMALL, t, h_abs, k_next
            h = h_abs
            t_new = t + h
            if t_new > t_end:
                t_new = t_end
            h = t_new - t
            h_abs = h  # as scipy: control continues from the clipped step
            # A step ending on t_end (a segment end, where the prescribed
            # acceleration may jump) evaluates its stages at t + h as the LEFT
            # limit: the right-hand side just before the kink.  Otherwise the
            # error estimate sees the jump at any step size and the step
            # collapses (a near-vertical speed ramp).  The caller restarts the
            # derivative from the right limit after the kink.
            t_left = np.nextafter(t_end, -np.inf) if t_new == t_end else t_new
            # the 12 stages
            for i in range(n):
                K[0, i] = f[i]
            for s in range(1, N_STAGES):
                _stage_state(y, K, s, h, yy)
                derivatives(kind, min(t + C[s] * h, t_left), yy, K[s], sp, wt, prog)
            _combine(B, K, N_STAGES, y_new)
            for i in range(n):
                y_new[i] = y[i] + h * y_new[i]
            derivatives(kind, t_left, y_new, K[N_STAGES], sp, wt, prog)
            stats[N_FEV] += N_STAGES
            steps += 1
            # error estimate (scipy's DOP853._estimate_error_norm); F's first two rows are
            # free until the dense output
            _combine(E5, K, N_STAGES + 1, F[0])
            _combine(E3, K, N_STAGES + 1, F[1])
            e5 = 0.0
            e3 = 0.0
            finite = True
            for i in range(n):
                mag = max(abs(y[i]), abs(y_new[i]))
                if mag > cap[i]:
                    mag = cap[i]
                sc = atol + rtol * mag
                a5 = F[0, i] / sc
                a3 = F[1, i] / sc
                e5 += a5 * a5
                e3 += a3 * a3
                if not np.isfinite(y_new[i]):
                    finite = False
            if not finite or not np.isfinite(e5) or not np.isfinite(e3):
                err = np.inf
                nonfinite = True
            elif e5 == 0.0 and e3 == 0.0:
                err = 0.0
            else:
                err = h * e5 / np.sqrt((e5 + 0.01 * e3) * n)
            if err < 1.0:
                if err == 0.0:
                    factor = MAX_FACTOR
                else:
                    factor = min(MAX_FACTOR, SAFETY * err ** ERROR_EXPONENT)
                if rejected:
                    factor = min(1.0, factor)
                h_abs *= factor
                accepted = True
                nonfinite = False
                stats[N_ACCEPTED] += 1
            else:
                if np.isfinite(err):
                    h_abs *= max(MIN_FACTOR, SAFETY * err ** ERROR_EXPONENT)
                else:
                    h_abs *= MIN_FACTOR
                rejected = True
                stats[N_REJECTED] += 1
                if steps >= max_steps:
                    return STEP_BUDGET, t, h_abs, k_next
        # dense output for the samples inside (t, t_new]
        if k_next < n_samples and ts[k_next] <= t_new:
            for s in range(N_STAGES + 1, 16):
                _stage_state(y, K, s, h, yy)
                derivatives(kind, min(t + C[s] * h, t_left), yy, K[s], sp, wt, prog)
            stats[N_FEV] += 3
            for r in range(4):
                _combine(D[r], K, 16, F[3 + r])
            for i in range(n):
                dyi = y_new[i] - y[i]
                F[0, i] = dyi
                F[1, i] = h * K[0, i] - dyi
                F[2, i] = 2.0 * dyi - h * (K[N_STAGES, i] + K[0, i])
                for r in range(3, 7):
                    F[r, i] = h * F[r, i]
            while k_next < n_samples and ts[k_next] <= t_new:
                tk = ts[k_next]
                if tk == t_new:
                    for i in range(n):
                        out[k_next, i] = y_new[i]
                else:
                    x = (tk - t) / h
                    for i in range(n):
                        v = 0.0
                        for r in range(6, -1, -1):
                            v += F[r, i]
                            if (6 - r) % 2 == 0:
                                v *= x
                            else:
                                v *= 1.0 - x
                        out[k_next, i] = v + y[i]
                k_next += 1
        t = t_new
        big = False
        for i in range(n):
            y[i] = y_new[i]
            f[i] = K[N_STAGES, i]
            if abs(y_new[i]) > limit:
                big = True
        if big:
            return DIVERGED, t, h_abs, k_next
    return REACHED_END, t, h_abs, k_next
