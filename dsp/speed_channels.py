"""Continuous speed and angle channels: an analog or rounded tachometer output, an encoder.

Each sample is the speed (or the angle) itself, with the channel's noise or its rounding
to a resolution.  Differentiated or integrated sample by sample those errors become the
speed and acceleration noise (q / dt, q / dt^2) or an angle random walk that the fits'
± would not contain.  Here the channel is a least-squares cubic spline (a knot every 8
revolutions, as the keyphasor's angle), the speed's integral or the angle's derivatives
come from it, and the spline's covariance goes into ``RotorAngle.angle_error``.  A channel without noise or
quantum (a simulator's angle, a computed speed) is used as it is.
"""
from __future__ import annotations

import math

import numpy as np

from .errors import SignalError, check_times
from .rotor_angle import TWO_PI, RotorAngle

__all__ = ["angle_from_encoder"]


def _channel_noise(y) -> float:
    """The white noise of a smooth channel [its unit]: the second differences' robust
    spread over sqrt 6 (a smooth signal's curvature is far below it at a DAQ's rate), and
    a quantum ``q`` (the steps' common divisor, when they are whole multiples of one that
    is not a rounding artefact) counted as its rounding, q / sqrt 12."""
    d2 = np.diff(y, 2)
    sig = 1.4826 * float(np.median(np.abs(d2 - np.median(d2)))) / math.sqrt(6.0)
    return math.hypot(sig, _count_quantum(y) / math.sqrt(12.0))


def _count_quantum(y) -> float:
    """The quantum of a channel written as a count (an encoder's lines, a speed to 1 rpm):
    the steps' common divisor when it is at least 1e-3 of the typical step; else 0."""
    from .held_display import _quantum

    diffs = np.abs(np.diff(y))
    steps = diffs[diffs > 0]
    if steps.size < 8:
        return 0.0
    q = _quantum(steps)
    if not (q >= 1e-3 * float(np.median(steps))
            and np.all(np.abs(steps / q - np.round(steps / q)) < 1e-3)):
        return 0.0
    # a count's steps alternate between whole numbers of the quantum (k and k + 1 lines,
    # or 0 and one rpm) all along; a steady ramp sampled uniformly has one step, a ramp and
    # a hold one change of step: neither is a quantum
    k = np.round(diffs / q)
    return q if np.count_nonzero(np.diff(k)) >= 8 else 0.0


def _lsq_spline(t, y, phase, knot_revolutions: float = 8.0):
    """``(spline, coefficient covariance)``: the least-squares cubic spline of ``y(t)`` with
    a knot every ``knot_revolutions`` revolutions of ``phase`` [rad], the covariance with
    the residuals' variance, scaled by how much they keep over a quarter of a knot
    interval (filtered noise, a rounding that repeats: never below white).  A ramp that
    ends in a hold is rounded over about one knot interval (the fits then see a smooth
    acceleration step; a finer spacing would follow it at the price of noise)."""
    from scipy.interpolate import BSpline

    revs = abs(phase[-1] - phase[0]) / TWO_PI
    n_int = int(min(max(revs / knot_revolutions, 1), t.size / 16))
    inner = (np.interp(np.linspace(phase[0], phase[-1], n_int + 1)[1:-1], phase, t)
             if phase[-1] > phase[0] else np.linspace(t[0], t[-1], n_int + 1)[1:-1])
    tk = np.r_[[t[0]] * 4, inner, [t[-1]] * 4]
    D = BSpline.design_matrix(t, tk, 3)
    DtD = (D.T @ D).toarray()
    c = np.linalg.solve(DtD, D.T @ y)
    sp = BSpline(tk, c, 3)
    r = y - sp(t)
    s2 = float(r @ r) / max(t.size - c.size, 1)
    m = max(int(t.size / (4 * n_int)), 1)
    local = np.convolve(r, np.ones(m) / m, mode="valid")
    factor = float(np.clip(m * np.mean(local ** 2) / max(np.mean(r ** 2), 1e-300), 1.0, m))
    return sp, factor * s2 * np.linalg.pinv(DtD, hermitian=True)


#: a channel whose noise is below this fraction of its range is taken as exact
EXACT = 1e-12


def angle_from_encoder(t, angle_rad, *, source: str = "angle") -> RotorAngle:
    """Rotor angle, speed and acceleration from an encoder's angle channel [rad].

    An encoder's angle is a count: quantised to its line spacing ``q`` (the readings'
    common step), and read as the count of edges passed (``floor``) or as the nearest
    position -- which, a record does not say.  Differentiated sample by sample, the
    quantisation's sawtooth becomes speed and acceleration noise of ``q / dt`` and
    ``q / dt^2``.  A counted or noisy angle is a least-squares spline (module docstring),
    its derivatives the speed and acceleration, and ``angle_error`` carries its
    covariance plus a common offset of RMS ``q / sqrt 3`` (the count's convention),
    which moves the unbalance angle.  An angle without noise or quantum (a simulator's,
    an interpolated one) is differentiated by :func:`numpy.gradient` as it is (exact to
    its second order; a spline would round a ramp's corner).
    """
    t = check_times(t, "t", 2)
    phi = np.asarray(angle_rad, float)
    steps = np.diff(phi)
    # a column already continuous (monotone) is kept: unwrapping it would fold steps of half a
    # revolution or more per sample (a camera's frames on a fast rotor) back into aliases
    if not (np.all(steps >= 0) or np.all(steps <= 0)):
        phi = np.unwrap(phi)
    if phi.shape != t.shape or not np.all(np.isfinite(phi)):
        raise SignalError(f"{source}: needs a finite angle at every sample")
    sigma = _channel_noise(phi) if t.size >= 64 else 0.0
    if sigma <= EXACT * max(float(np.ptp(phi)), 1.0):
        w = np.gradient(phi, t) if t.size > 1 else np.zeros_like(phi)
        a = np.gradient(w, t) if t.size > 1 else np.zeros_like(phi)
        return RotorAngle(phi, w, a, np.ones(t.size, bool), source, referenced=True)
    from .held_display import AngleError

    sp, cov = _lsq_spline(t, phi, phi)
    q = _count_quantum(phi)
    return RotorAngle(sp(t), sp(t, 1), sp(t, 2), np.ones(t.size, bool), source,
                      referenced=True, angle_error=AngleError(sp.t, cov + q * q / 3.0, 0.0))


def _rounded_continuous(w, change) -> bool:
    """A speed channel that follows the speed, rounded to its resolution (an analog
    tachometer's output, or a speed column written to 1 rpm), not a held display: every
    step is one quantum (a display's reading on a sweep jumps by the sweep over a gate)."""
    from .held_display import _quantum

    steps = np.abs(np.diff(w[np.r_[change - 1, change[-1]]]))
    q = _quantum(steps)
    return bool(change.size >= 20 and q > 0
                and np.mean(np.abs(steps - q) <= 1e-6 * q) >= 0.9)


def _speed_spline_angle(t, w, source):
    """A continuous speed channel (each sample the speed, with noise or rounding): a
    least-squares spline of the speed (module docstring), its integral the angle (a quartic
    spline) and its derivative the acceleration; ``angle_error`` carries the spline's
    covariance through the integral.  A speed without noise or quantum is integrated by
    trapezoids as it is (None: the caller's plain path)."""
    from scipy.interpolate import BSpline

    from .held_display import AngleError

    sigma = _channel_noise(w)
    if sigma <= EXACT * max(float(np.max(np.abs(w))), 1.0):
        return None
    trap = np.concatenate(([0.0], np.cumsum(0.5 * (w[1:] + w[:-1]) * np.diff(t))))
    speed, cov_a = _lsq_spline(t, w, trap)
    K = cov_a.shape[0]
    anti = BSpline(speed.t, np.eye(K), 3).antiderivative()
    L = anti.c[: anti.t.size - 5]                              # angle coefficients per a_j
    err = AngleError(anti.t, L @ cov_a @ L.T, 0.0, degree=4)
    ang = speed.antiderivative()(t)
    return RotorAngle(ang - ang[0], speed(t), speed(t, 1), np.ones(t.size, bool), source,
                      referenced=False, angle_error=err)
