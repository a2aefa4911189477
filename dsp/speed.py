"""Rotor angle and speed from what a lab records; the speed programme of a record.

A lab has one of: a once-per-revolution pulse train (keyphasor, photo-gate on
a mark: a TTL or proximity-probe voltage channel), a tachometer reading in
rpm, an angle encoder, or nothing but the vibration itself.  Each becomes the
same :class:`RotorAngle` (angle and speed at every sample, which samples are
covered, how it was obtained):

* :func:`pulse_times` -- the leading edges of a pulse channel (threshold by
  Otsu's two-level split of the values, so any duty cycle and either polarity
  work; Schmitt hysteresis; crossing time interpolated linearly between the
  two samples around it, i.e. sub-sample).
* :func:`angle_from_pulses` -- 2 pi per pulse, a cubic spline through the
  pulses (smooth speed and acceleration, which the unbalance forcing
  ``phi'^2 - i phi''`` needs); samples outside the first / last pulse are not
  covered.
* :func:`angle_from_speed` -- a tachometer's speed integrated (trapezoids);
  the angle has no reference mark (``referenced`` False: no unbalance angle).
* :func:`angle_from_1x` -- no speed channel: the phase of the shaft's own
  forward whirl (the 1X line dominates an unbalance response), flagged
  ``estimated``.  The phase of the response lags the rotor by the receptance's
  angle, which changes by about pi through a resonance; a speed spline fitted
  over many revolutions absorbs it (the error is about pi over the record's
  length in angle).

:func:`speed_programme` splits a speed record into stretches (constant,
run-up, run-down, coast-down, stopped) and names the whole record after them.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from .errors import SignalError, check_times

__all__ = ["RotorAngle", "angle_from_encoder", "pulse_times", "retime_pulses", "pulse_timing_std", "angle_from_pulses", "angle_from_speed",
           "angle_from_1x", "smoothed_phase", "repair_pulses", "Stretch", "Programme", "speed_programme", "otsu_threshold"]

TWO_PI = 2.0 * math.pi


@dataclass(frozen=True)
class RotorAngle:
    """The rotor's angle at every sample of a record.

    Attributes
    ----------
    angle_rad : ndarray
        Unwrapped rotor angle [rad] (NaN where not covered).
    speed_rad_s : ndarray
        d angle / dt [rad/s] (NaN where not covered).
    acceleration_rad_s2 : ndarray
        d speed / dt [rad/s^2] (NaN where not covered).
    covered : ndarray of bool
        Samples where the angle is known (between the first and last pulse).
    source : str
        ``"keyphasor"``, ``"angle"``, ``"tachometer"`` or ``"1X line"``.
    referenced : bool
        The angle is measured from a mark on the rotor (keyphasor, encoder):
        phases (the unbalance angle) are meaningful.
    estimated : bool
        The speed is estimated from the vibration (no speed channel).
    pulses_s : ndarray or None
        The pulse times [s] it was made from.
    angle_error : dsp.held_display.AngleError or None
        What the source leaves open of the angle (a held tachometer display's quantum
        and timing), for the fits that use it.
    """

    angle_rad: np.ndarray
    speed_rad_s: np.ndarray
    acceleration_rad_s2: np.ndarray
    covered: np.ndarray
    source: str
    referenced: bool
    estimated: bool = False
    pulses_s: Optional[np.ndarray] = None
    angle_error: Optional[object] = None


def otsu_threshold(v) -> float:
    """The level separating a two-level signal's values (Otsu 1979, on a 512-bin histogram).

    Maximises the between-class variance, so it works for any duty cycle
    (a 1 % pulse train) where a mid-range or percentile rule fails.
    """
    v = np.asarray(v, float)
    v = v[np.isfinite(v)]
    if v.size < 2 or np.ptp(v) == 0:
        raise SignalError("pulse channel: constant; no pulses")
    hist, edges = np.histogram(v, bins=512)
    centres = 0.5 * (edges[1:] + edges[:-1])
    w0 = np.cumsum(hist)
    w1 = v.size - w0
    m = np.cumsum(hist * centres)
    mu0 = m / np.maximum(w0, 1)
    mu1 = (m[-1] - m) / np.maximum(w1, 1)
    between = (w0 * w1 * (mu0 - mu1) ** 2)[:-1]
    # every split inside an empty gap between the levels scores the same: take the gap's middle
    top = np.flatnonzero(between >= between.max() * (1 - 1e-9))
    k = int(top[top.size // 2])
    return float(edges[k + 1])


def _state_level(v) -> float:
    """The level a pulse channel rests at in one state: the median of the samples in the
    densest part of its histogram (a ramp's samples, spread over the range, do not pull it
    as they pull the state's plain median)."""
    if np.ptp(v) == 0:
        return float(v[0])
    n, edges = np.histogram(v, bins=64)
    k = int(np.argmax(n))
    w = edges[1] - edges[0]
    near = v[(v >= edges[k] - w) & (v <= edges[k + 1] + w)]
    return float(np.median(near))


def pulse_times(t, v, *, threshold: Optional[float] = None, name: str = "pulse channel",
                mark: str = "leading"):
    """Times [s] of the leading edges of a once-per-revolution pulse channel.

    Parameters
    ----------
    t : array_like
        Sample times [s] (increasing).
    v : array_like
        The channel (e.g. a TTL voltage, or a proximity probe over a notch).
    threshold : float, optional
        Level between the two states; default :func:`otsu_threshold`.
    name : str
        The channel's name for error messages.
    mark : {"leading", "centre"}
        Time each pulse by its leading edge (a keyphasor: the notch's edge is
        the mark), or by the middle between its two edges (a photo-gate: the
        beam is centred on the gate then, whatever its speed).

    Returns
    -------
    ndarray
        Pulse times [s]: the edge into the state the channel spends less time in
        (the pulse), linearly interpolated at the 50 % level between the two
        states' medians (at ``threshold`` when given), or the mean of that and the
        next edge out; a Schmitt trigger of +-20 % of the two levels'
        distance rejects noise chatter.

    Raises
    ------
    SignalError
        Fewer than two pulses, or a constant channel.
    """
    t = check_times(t, "t", 4)
    v = np.asarray(v, float)
    if v.shape != t.shape:
        raise SignalError(f"{name}: {v.size} samples for {t.size} times")
    if not np.all(np.isfinite(v)):
        i = int(np.argmax(~np.isfinite(v)))
        raise SignalError(f"{name}: NaN or inf at sample {i}")
    level = otsu_threshold(v) if threshold is None else float(threshold)
    high = v > level
    if high.all() or not high.any():
        raise SignalError(f"{name}: never crosses the threshold {level:.6g}; no pulses")
    lo, hi = _state_level(v[~high]), _state_level(v[high])
    pulse_high = high.mean() < 0.5
    # the edge is timed at its 50 % reference level between the two states (IEEE 181),
    # not at the split of the histogram: a ramp's crossing then does not move with
    # the histogram's bins
    ref = 0.5 * (lo + hi) if threshold is None else level
    h = 0.2 * (hi - lo)
    # Schmitt states: +1 above level + h, -1 below level - h, else hold
    s = np.where(v > level + h, 1, np.where(v < level - h, -1, 0))
    idx = np.flatnonzero(s)
    if idx.size < 2:
        raise SignalError(f"{name}: no clean transitions (noise larger than the pulses?)")
    held = s[idx]
    change = np.flatnonzero(np.diff(held) != 0)
    into = held[change + 1]
    want = 1 if pulse_high else -1

    def crossings(into_state):
        res = []
        for j in idx[change[into == into_state] + 1]:     # first sample past the far band
            k = j
            while k > 0 and (v[k - 1] > ref) == (v[j] > ref):   # back to the crossing
                k -= 1
            if k == 0:
                continue
            a, b = v[k - 1] - ref, v[k] - ref
            res.append(t[k - 1] + (t[k] - t[k - 1]) * a / (a - b))
        return np.asarray(res)

    out = crossings(want)
    if mark == "centre":
        back = crossings(-want)
        j = np.searchsorted(back, out)
        keep = j < back.size
        out = 0.5 * (out[keep] + back[j[keep]])
    elif mark != "leading":
        raise SignalError(f"mark: 'leading' or 'centre', got {mark!r}")
    p = np.asarray(out)
    if p.size < 2:
        raise SignalError(f"{name}: {p.size} pulse(s); need at least 2 once-per-revolution "
                          "pulses")
    return p


def repair_pulses(pulses, window: int = 7):
    """Fill in missed pulses and drop double ones, judging each interval against its neighbours.

    A pulse shorter than the DAQ's sample interval is sometimes not sampled
    (an interval of ~2, 3, ... periods); a noisy edge can trigger twice (an
    interval well below one period).  Each interval is compared with the
    median of the ``window`` intervals around it.

    Returns
    -------
    (ndarray, int, int)
        The repaired pulse times [s], the number inserted and the number dropped.
    """
    p = np.asarray(pulses, float)
    if p.size < 4:
        return p, 0, 0
    dropped = 0
    while True:
        d = np.diff(p)
        ref = np.array([np.median(np.delete(d[max(0, i - window // 2):i + window // 2 + 1],
                                            min(i, window // 2))) if d.size > 1 else d[i]
                        for i in range(d.size)])
        short = np.flatnonzero(d < 0.5 * ref)
        if short.size == 0 or p.size < 4:
            break
        p = np.delete(p, short[0] + 1)
        dropped += 1
    d = np.diff(p)
    out, inserted = [p[0]], 0
    for i in range(d.size):
        m = int(round(d[i] / ref[i])) if ref[i] > 0 else 1
        if m >= 2 and abs(d[i] / ref[i] - m) < 0.25:
            out.extend(p[i] + d[i] * np.arange(1, m) / m)
            inserted += m - 1
        out.append(p[i + 1])
    return np.asarray(out), inserted, dropped


def _on_samples(spline, t, inside):
    """(angle, speed, acceleration) of a spline at the samples ``inside``; NaN elsewhere."""
    out = np.full((3,) + t.shape, np.nan)
    for d in range(3):
        out[d, inside] = spline(t[inside], d)
    return out[0], out[1], out[2]


def _lsq_cubic(x, y, n_int, knots_at=None, w=None):
    """Least-squares cubic spline of y(x) with ``n_int`` intervals (inner knots evenly spaced
    in x, or at ``knots_at``), residuals weighted by ``w``."""
    from scipy.interpolate import make_lsq_spline

    inner = np.linspace(x[0], x[-1], n_int + 1)[1:-1] if knots_at is None else knots_at
    return make_lsq_spline(x, y, np.concatenate(([x[0]] * 4, inner, [x[-1]] * 4)), k=3, w=w)


def _pulse_spline(p, knot_revolutions: float, source: str = "keyphasor"):
    """The angle through the points (pulse k, 2 pi k): interpolating for
    ``knot_revolutions = 0`` or fewer than two intervals, else a least-squares cubic with
    a knot every ``knot_revolutions`` pulses (:func:`angle_from_pulses`)."""
    from scipy.interpolate import CubicSpline

    if p.size < 3:
        raise SignalError(f"{source}: {p.size} pulse(s); need at least 3 (two revolutions)")
    if np.any(np.diff(p) <= 0):
        raise SignalError(f"{source}: pulse times must increase")
    k = TWO_PI * np.arange(p.size)
    n_int = int(p.size / max(knot_revolutions, 4.0)) if knot_revolutions else 0
    if n_int < 2:
        return CubicSpline(p, k)
    return _lsq_cubic(p, k, n_int, np.interp(np.linspace(0, p.size - 1, n_int + 1)[1:-1],
                                             np.arange(p.size), p))


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
    k = np.searchsorted(t, p)                        # t[k - 1] < p <= t[k]
    ok = (k > 0) & (k < t.size)
    kk = np.clip(k, 1, t.size - 1)
    a, b = v[kk - 1] - ref, v[kk] - ref
    ok &= (a * b < 0) | (b == 0)                     # a crossing between these samples
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


def angle_from_pulses(t, pulses, *, source: str = "keyphasor",
                      knot_revolutions: float = 8.0, timing_std_s=None) -> RotorAngle:
    """Rotor angle from once-per-revolution pulse times (2 pi per pulse).

    The angle through the points (pulse k, 2 pi k) is a least-squares cubic
    spline with a knot every ``knot_revolutions`` revolutions: a pulse timed to
    a fraction of a sample (a DAQ sampling a fast edge) jitters by up to half a
    sample, and an interpolating spline would turn that jitter into speed noise
    (its second derivative, the forcing's phi'', worse).  The spline follows
    any speed programme whose acceleration changes slowly over that many
    revolutions.  ``knot_revolutions = 0`` interpolates (exact pulses).

    Parameters
    ----------
    t : array_like
        Sample times [s].
    pulses : array_like
        Pulse times [s] (e.g. :func:`pulse_times`); the rotor is at its mark
        (angle 0 mod 2 pi) at each.
    source : str
        Stored in the result.
    knot_revolutions : float
        Revolutions per spline interval (>= 4 pulses each).
    timing_std_s : float or array_like, optional
        Std [s] of each pulse's time (:func:`pulse_timing_std`).  Given, the
        result's ``angle_error`` carries what it leaves open of the angle, for
        the fits that use it (:func:`_pulse_angle_error`).

    Returns
    -------
    RotorAngle
        Covered between the first and the last pulse.
    """
    t = check_times(t, "t", 2)
    p = np.asarray(pulses, float)
    sp = _pulse_spline(p, knot_revolutions, source)
    inside = (t >= p[0]) & (t <= p[-1])
    ang, spd, acc = _on_samples(sp, t, inside)
    err = (None if timing_std_s is None else
           _pulse_angle_error(p, sp, np.broadcast_to(np.asarray(timing_std_s, float), p.shape),
                              float(np.median(np.diff(t)))))
    return RotorAngle(ang, spd, acc, inside, source, referenced=True, pulses_s=p,
                      angle_error=err)


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
    ``m`` pulses around it), between 1 (white) and ``m`` (no averaging at all).
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
    return AngleError(tk, (S * (factor * sig_phi ** 2)) @ S.T, 0.0)


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
    k = np.clip(np.searchsorted(t, p), 1, t.size - 1)
    a, b = v[k - 1] - ref, v[k] - ref
    dt = t[k] - t[k - 1]
    crossing = (a * b < 0) | (b == 0)
    on_edge = ((np.minimum(v[k - 1], v[k]) > min(lo, hi) + margin)
               & (np.maximum(v[k - 1], v[k]) < max(lo, hi) - margin))
    f = np.clip((p - t[k - 1]) / dt, 0.0, 1.0)
    step = dt * np.sqrt(f * f - f + 1.0 / 3.0)
    slope = np.abs(v[k] - v[k - 1])
    noise = math.sqrt(2.0) * sigma_v * dt / np.where(slope > 0, slope, np.inf)
    return np.where(crossing, np.where(on_edge, noise, step), dt / math.sqrt(3.0))


def angle_from_speed(t, speed_rad_s, *, source: str = "tachometer") -> RotorAngle:
    """Rotor angle by integrating a speed channel [rad/s] (trapezoids); no reference mark.

    A tachometer display holds its reading between updates: each reading is the
    mean speed over the gate that preceded it (the typical hold taken as the gate),
    so the angle turned between the gates' starts is known exactly; the angle is
    the C2 spline through those (:func:`dsp.held_display.held_angle`, which also says
    what the readings leave open: ``angle_error``).  A reading held over several gates
    is a steady speed.
    """
    t = check_times(t, "t", 2)
    w = np.asarray(speed_rad_s, float)
    if w.shape != t.shape or not np.all(np.isfinite(w)):
        raise SignalError(f"{source}: needs a finite speed at every sample")
    change = np.flatnonzero(np.diff(w) != 0) + 1
    if 2 <= change.size < t.size // 4 and not _rounded_continuous(w, change):
        from .held_display import held_angle          # a held display: steps

        ang, spd, acc, err, covered = held_angle(t, w, change)
        return RotorAngle(ang, spd, acc, covered, source, referenced=False, angle_error=err)
    if t.size >= 64 and change.size >= 8:
        return _speed_spline_angle(t, w, source)
    ang = np.concatenate(([0.0], np.cumsum(0.5 * (w[1:] + w[:-1]) * np.diff(t))))
    acc = np.gradient(w, t)
    return RotorAngle(ang, w, acc, np.ones(t.size, bool), source, referenced=False)


def angle_from_encoder(t, angle_rad, *, source: str = "angle",
                       knot_revolutions: float = 8.0) -> RotorAngle:
    """Rotor angle, speed and acceleration from an encoder's angle channel [rad].

    An encoder's angle is a count: quantised to its line spacing ``q`` (the readings'
    common step), and read as the count of edges passed (``floor``) or as the nearest
    position -- which, a record does not say.  Differentiated sample by sample, the
    quantisation's sawtooth becomes speed and acceleration noise of ``q / dt`` and
    ``q / dt^2``; here the angle is a least-squares cubic spline (a knot every
    ``knot_revolutions`` revolutions), its derivatives the speed and acceleration,
    and ``angle_error`` carries the coefficients' covariance (the residuals' variance,
    never below white where they repeat, as for a tachometer) plus a common offset of
    RMS ``q / sqrt 3`` (the count's convention), which moves the unbalance angle.  An
    angle without steps (a simulator's, or an interpolated one) keeps a residual at
    the rounding floor: exact to the spline's approximation (~1e-7 rad on a smoothly
    changing acceleration, exact on a constant one).  Records shorter than 64 samples or
    two revolutions are differentiated by :func:`numpy.gradient`.
    """
    t = check_times(t, "t", 2)
    phi = np.unwrap(np.asarray(angle_rad, float))
    if phi.shape != t.shape or not np.all(np.isfinite(phi)):
        raise SignalError(f"{source}: needs a finite angle at every sample")
    revs = abs(phi[-1] - phi[0]) / TWO_PI
    if t.size < 64 or revs < 2:
        w = np.gradient(phi, t) if t.size > 1 else np.zeros_like(phi)
        a = np.gradient(w, t) if t.size > 1 else np.zeros_like(phi)
        return RotorAngle(phi, w, a, np.ones(t.size, bool), source, referenced=True)
    from scipy.interpolate import BSpline

    from .held_display import AngleError, _quantum

    n_int = int(min(max(revs / knot_revolutions, 1), t.size / 16))
    inner = (np.interp(np.linspace(phi[0], phi[-1], n_int + 1)[1:-1], phi, t)
             if phi[-1] > phi[0] else np.linspace(t[0], t[-1], n_int + 1)[1:-1])
    tk = np.r_[[t[0]] * 4, inner, [t[-1]] * 4]
    D = BSpline.design_matrix(t, tk, 3).toarray()
    c, *_ = np.linalg.lstsq(D, phi, rcond=None)
    r = phi - D @ c
    s2 = float(r @ r) / max(t.size - c.size, 1)
    m = max(int(t.size / (4 * n_int)), 1)
    local = np.convolve(r, np.ones(m) / m, mode="valid")
    factor = float(np.clip(m * np.mean(local ** 2) / max(np.mean(r ** 2), 1e-300), 1.0, m))
    q = _quantum(np.abs(np.diff(phi)))
    cov = factor * s2 * np.linalg.pinv(D.T @ D, hermitian=True) + q * q / 3.0
    sp = BSpline(tk, c, 3)
    return RotorAngle(sp(t), sp(t, 1), sp(t, 2), np.ones(t.size, bool), source,
                      referenced=True, angle_error=AngleError(tk, cov, 0.0))


def _rounded_continuous(w, change) -> bool:
    """A speed channel that follows the speed, rounded to its resolution (an analog
    tachometer's output, or a speed column written to 1 rpm), not a held display: every
    step is one quantum (a display's reading on a sweep jumps by the sweep over a gate)."""
    from .held_display import _quantum

    steps = np.abs(np.diff(w[np.r_[change - 1, change[-1]]]))
    q = _quantum(steps)
    return bool(change.size >= 20 and q > 0
                and np.mean(np.abs(steps - q) <= 1e-6 * q) >= 0.9)


def _speed_spline_angle(t, w, source, knot_revolutions: float = 8.0):
    """A continuous speed channel (each sample the speed, with noise or rounding): a
    least-squares cubic spline of the speed (a knot every ``knot_revolutions``
    revolutions), its integral the angle (a quartic spline) and its derivative the
    acceleration; ``angle_error`` carries the coefficients' covariance through the
    integral.  The channel's errors are white with the residuals' variance, scaled by
    how much they keep over a quarter of a knot interval (as for the keyphasor's timing,
    :func:`_pulse_angle_error`: filtered noise or a rounding that repeats does not
    average out; never below white)."""
    from scipy.interpolate import BSpline

    from .held_display import AngleError

    trap = np.concatenate(([0.0], np.cumsum(0.5 * (w[1:] + w[:-1]) * np.diff(t))))
    revs = abs(trap[-1] - trap[0]) / TWO_PI
    n_int = int(min(max(revs / knot_revolutions, 1), t.size / 16))
    inner = np.interp(np.linspace(trap[0], trap[-1], n_int + 1)[1:-1], trap, t) \
        if trap[-1] > trap[0] else np.linspace(t[0], t[-1], n_int + 1)[1:-1]
    tk = np.r_[[t[0]] * 4, inner, [t[-1]] * 4]
    D = BSpline.design_matrix(t, tk, 3).toarray()
    a, *_ = np.linalg.lstsq(D, w, rcond=None)
    r = w - D @ a
    K = a.size
    s2 = float(r @ r) / max(t.size - K, 1)
    m = max(int(t.size / (4 * n_int)), 1)
    local = np.convolve(r, np.ones(m) / m, mode="valid")
    factor = float(np.clip(m * np.mean(local ** 2) / max(np.mean(r ** 2), 1e-300), 1.0, m))
    cov_a = factor * s2 * np.linalg.pinv(D.T @ D, hermitian=True)
    speed = BSpline(tk, a, 3)
    angle = speed.antiderivative()
    anti = BSpline(tk, np.eye(K), 3).antiderivative()
    L = anti.c[: anti.t.size - 5]                              # angle coefficients per a_j
    err = AngleError(anti.t, L @ cov_a @ L.T, 0.0, degree=4)
    ang = angle(t)
    return RotorAngle(ang - ang[0], speed(t), speed(t, 1), np.ones(t.size, bool), source,
                      referenced=False, angle_error=err)


def angle_from_1x(t, z, *, min_amplitude_fraction: float = 0.05,
                  knot_revolutions: float = 20.0) -> RotorAngle:
    """Rotor angle estimated from the phase of the forward whirl (no speed channel).

    Parameters
    ----------
    t : array_like
        Sample times [s], uniform.
    z : array_like (complex)
        Shaft displacement x + i y with its mean removed [m].
    min_amplitude_fraction : float
        Samples whose smoothed whirl radius is below this fraction of its
        maximum (a slow rotor whose 1X drowns in noise) are not covered.
    knot_revolutions : float
        Revolutions between the knots of the smoothing spline of the phase.

    Returns
    -------
    RotorAngle
        ``estimated`` True, ``referenced`` False.  The angle follows the
        whirl's phase; its speed is the smoothed phase rate.
    """
    t = check_times(t, "t", 16)
    z = np.asarray(z, complex)
    if z.shape != t.shape:
        raise SignalError(f"z: {z.size} samples for {t.size} times")
    # the whirl radius, smoothed over ~1 % of the record
    k = max(3, t.size // 100)
    r = np.convolve(np.abs(z), np.ones(k) / k, mode="same")
    ok = r >= min_amplitude_fraction * r.max()
    # the longest covered stretch
    edges = np.flatnonzero(np.diff(np.concatenate(([0], ok.view(np.int8), [0]))))
    starts, stops = edges[::2], edges[1::2]
    j = int(np.argmax(stops - starts))
    i0, i1 = int(starts[j]), int(stops[j])
    if i1 - i0 < 16:
        raise SignalError("1X line: the whirl is too weak to follow its phase")
    th = np.unwrap(np.angle(z[i0:i1]))
    if th[-1] < th[0]:
        th = -th          # backward whirl: follow its magnitude
    cov = np.zeros(t.size, bool)
    cov[i0:i1] = True
    return smoothed_phase(t, th, cov, knot_revolutions=knot_revolutions)


def smoothed_phase(t, phase_rad, covered, *, knot_revolutions: float = 20.0,
                   weights=None) -> RotorAngle:
    """A rotor angle from a noisy phase track: a least-squares cubic spline with a knot
    every ``knot_revolutions`` revolutions (``estimated`` True, ``referenced`` False).

    Parameters
    ----------
    t : ndarray
        Sample times [s].
    phase_rad : ndarray
        The unwrapped phase [rad] on the ``covered`` samples (one contiguous stretch).
    covered : ndarray of bool
        Which samples of ``t`` it covers.
    weights : ndarray, optional
        Weight of each covered sample's phase residual (e.g. the whirl's radius: a
        phase read off a vector of radius A with noise sigma scatters by sigma / A).
    """
    idx = np.flatnonzero(covered)
    i0, i1 = int(idx[0]), int(idx[-1]) + 1
    tt, th = t[i0:i1], np.asarray(phase_rad, float)
    turns = (th[-1] - th[0]) / TWO_PI
    n_int = int(max(1, min(turns / knot_revolutions, (i1 - i0) / 50)))
    ang, spd, acc = _on_samples(_lsq_cubic(tt, th, n_int, w=weights), t, covered)
    if not np.all(spd[i0:i1] > 0):
        raise SignalError("1X line: the whirl's phase does not advance steadily; the speed "
                          "cannot be estimated from the vibration")
    return RotorAngle(ang, spd, acc, covered.copy(), "1X line", referenced=False, estimated=True)


# ------------------------------------------------------------------ programme
@dataclass(frozen=True)
class Stretch:
    """A part of a record with one kind of speed change.

    Attributes
    ----------
    kind : str
        ``"stopped"``, ``"constant"``, ``"run-up"``, ``"run-down"`` or ``"coast-down"``
        (decelerating with a rate proportional to the speed: the drive is off).
    i_start, i_stop : int
        Sample range ``[i_start, i_stop)``.
    t_start_s, t_end_s : float
        Its times [s].
    speed_start_hz, speed_end_hz : float
        Rotor speed at its ends [rev/s].
    rate_hz_s : float
        Mean speed change rate [rev/s^2].
    """

    kind: str
    i_start: int
    i_stop: int
    t_start_s: float
    t_end_s: float
    speed_start_hz: float
    speed_end_hz: float
    rate_hz_s: float

    @property
    def duration_s(self) -> float:
        """Length of the stretch [s]."""
        return self.t_end_s - self.t_start_s


@dataclass(frozen=True)
class Programme:
    """The speed programme of a record: its stretches and one name for the whole.

    ``kind`` is the stretches' kind when they are all alike (ignoring short
    constant dwells at the ends), ``"run-up + constant"`` style joins for two or
    three, else ``"mixed"``.
    """

    kind: str
    stretches: list = field(default_factory=list)

    def longest(self, kind: str) -> Optional[Stretch]:
        """The longest stretch of ``kind`` (None when there is none)."""
        s = [x for x in self.stretches if x.kind == kind]
        return max(s, key=lambda x: x.duration_s) if s else None


def speed_programme(t, speed_rad_s, *, constant_rtol: float = 2e-3,
                    stopped_rad_s: float = 0.1 * TWO_PI, min_duration_s: Optional[float] = None
                    ) -> Programme:
    """Split a speed record into constant / run-up / run-down / coast-down / stopped stretches.

    Parameters
    ----------
    t : array_like
        Times [s].
    speed_rad_s : array_like
        Rotor speed [rad/s] (NaN where unknown: those samples are skipped).
    constant_rtol : float
        A stretch is constant when its speed changes by less than this fraction
        of its mean speed over a window (about 2 % of the record, >= 0.5 s)
        [-]; the tolerance is also an absolute floor of 0.02 rev/s.
    stopped_rad_s : float
        Below this speed the rotor is stopped [rad/s] (default 0.1 rev/s).
    min_duration_s : float, optional
        Shorter stretches merge into their neighbours (default 3 % of the
        record).

    Returns
    -------
    Programme
    """
    t = check_times(t, "t", 2)
    w = np.asarray(speed_rad_s, float)
    if w.shape != t.shape:
        raise SignalError(f"speed: {w.size} samples for {t.size} times")
    ok = np.isfinite(w)
    if ok.sum() < 2:
        raise SignalError("speed: fewer than 2 known samples")
    idx = np.flatnonzero(ok)
    tk, wk = t[ok], np.abs(w[ok])
    T = tk[-1] - tk[0]
    if min_duration_s is None:
        min_duration_s = 0.03 * T
    # speed change over a window of ~2 % of the record (>= 0.5 s), centred
    half = max(0.01 * T, 0.25)
    lo = np.searchsorted(tk, tk - half)
    hi = np.clip(np.searchsorted(tk, tk + half, side="right") - 1, 0, tk.size - 1)
    span = np.maximum(tk[hi] - tk[lo], 1e-12)
    rate = (wk[hi] - wk[lo]) / span                              # rad/s^2
    tol = np.maximum(constant_rtol * wk, 0.02 * TWO_PI) / (2 * half)
    lab = np.where(wk < stopped_rad_s, 0, np.where(rate > tol, 1, np.where(rate < -tol, 2, 3)))
    # runs of equal labels, short ones merged into the previous
    runs = []
    start = 0
    for i in range(1, lab.size + 1):
        if i == lab.size or lab[i] != lab[start]:
            runs.append([lab[start], start, i])
            start = i
    merged = []
    for r in runs:
        if merged and (tk[r[2] - 1] - tk[r[1]] < min_duration_s or merged[-1][0] == r[0]):
            merged[-1][2] = r[2]
        else:
            merged.append(r)
    if len(merged) > 1 and tk[merged[0][2] - 1] - tk[merged[0][1]] < min_duration_s:
        merged[1][1] = merged[0][1]
        merged.pop(0)
    names = {0: "stopped", 1: "run-up", 2: "run-down", 3: "constant"}
    stretches = []
    for code, a, b in merged:
        kind = names[int(code)]
        ta, tb = tk[a], tk[b - 1]
        rate_m = (wk[b - 1] - wk[a]) / max(tb - ta, 1e-12)
        if kind == "run-down" and b - a >= 8:
            # coast-down: deceleration proportional to speed (viscous losses, drive off)
            seg_w, seg_r = wk[a:b], rate[a:b]
            if np.ptp(seg_w) > 0.2 * seg_w.max():
                c = np.polyfit(seg_w, seg_r, 1)
                fit_lin = np.std(seg_r - c[0] * seg_w - c[1])
                if c[0] < 0 and abs(c[0]) * np.ptp(seg_w) > 3 * max(fit_lin, 1e-12) \
                        and abs(c[1]) < 0.5 * abs(c[0]) * seg_w.mean():
                    kind = "coast-down"
        stretches.append(Stretch(kind, int(idx[a]), int(idx[b - 1]) + 1, float(ta), float(tb),
                                 float(wk[a] / TWO_PI), float(wk[b - 1] / TWO_PI),
                                 float(rate_m / TWO_PI)))
    kinds = [s.kind for s in stretches]
    core = [k for k in kinds if k != "stopped"]
    if not core:
        whole = "stopped"
    elif len(set(core)) == 1:
        whole = core[0]
    elif len(core) <= 3:
        whole = " + ".join(core)
    else:
        whole = "mixed"
    return Programme(whole, stretches)
