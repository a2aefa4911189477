"""The keyphasor's edges in the rotor angle, and what their timing leaves open.

:func:`retime_pulses` times each edge of a pulse channel by interpolating it linearly in
the rotor angle (the channel is a function of the angle, not of time);
:func:`pulse_timing_std` says how well each edge is timed, and
:func:`_pulse_angle_error` carries that through the angle's spline into a
:class:`dsp.held_display.AngleError` (``RotorAngle.angle_error``) for the fits.
"""
from __future__ import annotations

import math
from typing import Optional

import numpy as np

from .errors import check_times
from .pulses import _pulse_spline, _state_level, otsu_threshold
from .rotor_angle import TWO_PI

__all__ = ["retime_pulses", "pulse_timing_std"]


def _crossing_index(t, v, p, ref):
    """``(k, crossing)``: for each time ``p`` the sample ``k`` with ``p`` in ``[t[k-1], t[k]]``
    whose pair of samples crosses ``ref``; a time that rounds onto a sample may have its
    crossing in the pair after it (``crossing`` False: no pair around it crosses)."""
    k = np.clip(np.searchsorted(t, p), 1, t.size - 1)

    def crosses(k):
        a, b = v[k - 1] - ref, v[k] - ref
        return (a * b <= 0) & (a != b)

    c = crosses(k)
    k2 = np.clip(k + 1, 1, t.size - 1)
    use2 = ~c & crosses(k2) & (np.abs(p - t[k]) <= 1e-9 * (t[k2] - t[k - 1]))
    k = np.where(use2, k2, k)
    return k, c | use2


def retime_pulses(t, v, pulses, *, threshold: Optional[float] = None,
                  knot_revolutions: float = 8.0, passes: int = 2):
    """Pulse edges timed by interpolating the channel linearly in the rotor angle.

    A keyphasor's voltage is a function of the rotor's angle (the notch or the
    reflective mark passing the sensor), not of time.  :func:`pulse_times`
    interpolates the 50 % crossing linearly in time between the two samples
    around it; on a speed that changes the angle is not linear in time over the
    sample, and the edge is late or early by about ``(phi'' / phi') dt^2 / 8``
    (at 10 samples per revolution and 6 rev/s^2 on 40 rev/s: 1e-3 deg, an
    unbalance angle off by 1.6e-5 relative).  Here the same crossing is found
    in the angle of the spline through the pulses (:func:`angle_from_pulses`),
    linearly between the two samples' angles, and its time is that at which the
    spline reaches it; each pass rebuilds the spline from the re-timed pulses.
    A ramp linear in the angle is then timed exactly (to the spline's error over
    one sample, second order); a pulse that :func:`repair_pulses` inserted (no
    crossing between the samples around it) keeps its time.

    Parameters
    ----------
    t, v : array_like
        Sample times [s] and the pulse channel (as for :func:`pulse_times`).
    pulses : array_like
        Leading-edge times [s] from :func:`pulse_times` (possibly repaired).
    threshold : float, optional
        As given to :func:`pulse_times` (default: the 50 % level between the two states).
    knot_revolutions : float
        The spline's knot spacing (:func:`angle_from_pulses`).
    passes : int
        Spline rebuilds (two reach the rounding floor on a constant acceleration).

    Returns
    -------
    ndarray
        The re-timed pulses [s].
    """
    t = check_times(t, "t", 4)
    v = np.asarray(v, float)
    p = np.array(pulses, float)
    if p.size < 3:
        return p
    level = otsu_threshold(v) if threshold is None else float(threshold)
    high = v > level
    ref = (0.5 * (_state_level(v[~high]) + _state_level(v[high])) if threshold is None
           else level)
    kk, ok = _crossing_index(t, v, p, ref)           # the samples around each crossing
    a, b = v[kk - 1] - ref, v[kk] - ref
    if not ok.any():
        return p
    frac = np.where(ok, a / np.where(a - b == 0, 1.0, a - b), 0.0)
    for _ in range(max(int(passes), 0)):
        sp = _pulse_spline(p, knot_revolutions)
        pa, pb = sp(t[kk - 1]), sp(t[kk])
        target = pa + frac * (pb - pa)
        tc = p.copy()
        for _ in range(4):                           # Newton on sp(tc) = target
            w = sp(tc, 1)
            step = np.where(ok & (w > 0), (sp(tc) - target) / np.where(w > 0, w, 1.0), 0.0)
            tc = np.clip(tc - step, t[kk - 1], t[kk])
        new = np.where(ok, tc, p)
        if np.any(np.diff(new) <= 0):               # a crossing would reorder: keep the old
            break
        p = new
    return p


def _pulse_angle_error(p, sp, sigma_t, dt):
    """The angle's uncertainty from the pulses' timing (a :class:`dsp.held_display.AngleError`
    in the B-spline basis of the angle's least-squares spline, or None when it is nil).

    A pulse late by ``delta t`` puts the angle ``phi' delta t`` off at it; the spline's
    coefficients are linear in those angles (``c = S phi``, ``S`` the least-squares
    solution operator): white errors give ``S diag(sigma_phi^2) S'``.  A sampled edge's
    error is a function of where in its sample interval the edge falls (for a step,
    ``(1/2 - u) dt`` with ``u`` that fraction), and ``u`` follows the rotation against
    the sampling: alternating from pulse to pulse the errors cancel within a spline
    interval, near a speed commensurate with the sample rate they repeat for many
    revolutions and do not.  ``u`` is predicted from the spline (the times at which it
    reaches 2 pi k, to well under a sample), and the white covariance is scaled by how
    much the sawtooth ``1/2 - u`` keeps over a spline interval: ``m`` pulses per
    coefficient, ``m (local mean)^2 / mean(sawtooth^2)`` at each pulse (the mean over the
    ``m`` pulses around it), between 1 (white) and ``m`` (no averaging at all); and what
    the whole record cannot average, a common delay of RMS ``R sigma_t`` (``R`` the
    circular concentration of ``u``: 1 at a speed commensurate with the sample rate).
    """
    from scipy.interpolate import BSpline

    from .held_display import AngleError

    w = np.abs(sp(p, 1))
    sig_phi = w * sigma_t
    if not np.any(sig_phi > 0):
        return None
    tk = getattr(sp, "t", None)
    if tk is None:          # the interpolating spline of a short record: one cubic for the error
        tk = np.r_[[p[0]] * 4, [p[-1]] * 4]
    D = BSpline.design_matrix(p, tk, 3).toarray()
    S = np.linalg.pinv(D)
    m = max(int(round(p.size / (tk.size - 4))), 1)
    # when the smooth angle reaches each mark, and where that falls in its sample interval
    tau = p - (sp(p) - TWO_PI * np.arange(p.size)) / np.where(w > 0, w, 1.0)
    u = np.mod((tau - p[0]) / dt, 1.0) if dt > 0 else np.zeros(p.size)
    g = 0.5 - u
    local = np.convolve(g, np.ones(m) / m, mode="same")      # centred on each pulse
    factor = np.clip(m * local ** 2 / max(np.mean(g ** 2), 1e-300), 1.0, m)
    # a common delay: when the marks fall at the same place in their sample intervals all
    # along (a speed commensurate with the sample rate), the errors are one offset that no
    # spline averages; the phases' circular concentration R (1: all alike, ~0: spread)
    # scales the edges' RMS timing std into that delay
    R = float(abs(np.mean(np.exp(2j * np.pi * u))))
    delay = R * float(np.sqrt(np.mean(sigma_t ** 2)))
    # ... and when the marks fall on a few places only (a speed at p/q samples per
    # revolution: q phases), the sawtooth's mean over them is not zero although its first
    # harmonic is (three phases 0, 1/3, 2/3: R = 0, mean 1/6): an offset of mean(g) dt where
    # the edges are faster than a sample (their timing std there ~ dt / sqrt(12))
    fast = sigma_t >= 0.25 * dt if dt > 0 else np.zeros(p.size, bool)
    if fast.any():
        delay = max(delay, abs(float(np.mean(np.where(fast, g, 0.0)))) * dt)
    C = (S * (factor * sig_phi ** 2)) @ S.T
    # the sawtooth's local mean where the edges are fast: a bias of the spline over every
    # stretch the speed keeps the same few phases (a hold at p/q samples per revolution: the
    # whole hold), the same sign all along it -- one error mode of its own shape (unit
    # std), not an independent error per coefficient that the stretch would average away
    bias = S @ (w * np.where(fast, local, 0.0) * dt)
    return AngleError(tk, C + np.outer(bias, bias), delay)


def pulse_timing_std(t, v, pulses, *, threshold: Optional[float] = None):
    """Std [s] of each pulse time of :func:`pulse_times` / :func:`retime_pulses`.

    An edge with both samples around its crossing on the edge itself (off both
    states by more than four times the channel's noise) is interpolated between
    them: its time is as good as the samples' noise over the edge's slope,
    ``sqrt 2 sigma_v dt / |v_k - v_(k-1)|`` (the edge taken as linear in the angle
    between them, :func:`retime_pulses`).  An edge faster than that (a TTL
    step, a proximity probe over a sharp notch) lies anywhere in the sample
    interval: the crossing put at the fraction ``f`` of it is off by
    ``dt sqrt(f^2 - f + 1/3)`` RMS (``dt / sqrt 12`` at the middle).  A pulse
    without a crossing between its samples (one :func:`repair_pulses` filled in)
    gets ``dt / sqrt 3``.

    Parameters
    ----------
    t, v : array_like
        Sample times [s] and the pulse channel.
    pulses : array_like
        Pulse times [s].
    threshold : float, optional
        As given to :func:`pulse_times`.

    Returns
    -------
    ndarray
        One std [s] per pulse.
    """
    t = check_times(t, "t", 4)
    v = np.asarray(v, float)
    p = np.asarray(pulses, float)
    level = otsu_threshold(v) if threshold is None else float(threshold)
    high = v > level
    lo, hi = _state_level(v[~high]), _state_level(v[high])
    ref = 0.5 * (lo + hi) if threshold is None else level
    band = 0.1 * abs(hi - lo)
    near = np.r_[v[np.abs(v - lo) < band] - lo, v[np.abs(v - hi) < band] - hi]
    sigma_v = 1.4826 * float(np.median(np.abs(near - np.median(near)))) if near.size else 0.0
    margin = max(4.0 * sigma_v, 0.02 * abs(hi - lo))
    k, crossing = _crossing_index(t, v, p, ref)
    dt = t[k] - t[k - 1]
    on_edge = ((np.minimum(v[k - 1], v[k]) > min(lo, hi) + margin)
               & (np.maximum(v[k - 1], v[k]) < max(lo, hi) - margin))
    f = np.clip((p - t[k - 1]) / dt, 0.0, 1.0)
    step = dt * np.sqrt(f * f - f + 1.0 / 3.0)
    slope = np.abs(v[k] - v[k - 1])
    noise = math.sqrt(2.0) * sigma_v * dt / np.where(slope > 0, slope, np.inf)
    return np.where(crossing, np.where(on_edge, noise, step), dt / math.sqrt(3.0))
