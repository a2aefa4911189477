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
* :func:`angle_from_speed` -- a tachometer's speed integrated (a held display by
  :mod:`dsp.held_display`, a continuous channel by :mod:`dsp.speed_channels`);
  the angle has no reference mark (``referenced`` False: no unbalance angle).
  An encoder's angle column: :func:`dsp.speed_channels.angle_from_encoder`; the
  keyphasor edges' timing and its uncertainty: :mod:`dsp.pulse_timing`.
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

from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from .errors import SignalError, check_times
from .pulses import _lsq_cubic, _pulse_spline, otsu_threshold, pulse_times, repair_pulses  # noqa: F401
from .rotor_angle import TWO_PI, RotorAngle  # noqa: F401  (their public home is here too)

__all__ = ["RotorAngle", "pulse_times", "angle_from_pulses", "angle_from_speed",
           "angle_from_1x", "smoothed_phase", "repair_pulses", "Stretch", "Programme", "speed_programme", "otsu_threshold"]



def _on_samples(spline, t, inside):
    """(angle, speed, acceleration) of a spline at the samples ``inside``; NaN elsewhere."""
    out = np.full((3,) + t.shape, np.nan)
    for d in range(3):
        out[d, inside] = spline(t[inside], d)
    return out[0], out[1], out[2]


def angle_from_pulses(t, pulses, *, source: str = "keyphasor",
                      knot_revolutions: float = 8.0, timing_std_s=None,
                      corners=False) -> RotorAngle:
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
    corners : bool or sequence of float
        True: a double knot (a jump of the acceleration: a run-up turning into a hold) where
        it lowers the pulses' chi^2 by more than the information criterion's price
        (:func:`dsp.pulses._corner_knots`); a sequence: double knots at those times [s].

    Returns
    -------
    RotorAngle
        Covered between the first and the last pulse.
    """
    t = check_times(t, "t", 2)
    p = np.asarray(pulses, float)
    sig_phi = None
    if corners is True and timing_std_s is not None:
        w = np.abs(np.gradient(TWO_PI * np.arange(p.size), p)) if p.size > 2 else 1.0
        sig_phi = w * np.broadcast_to(np.asarray(timing_std_s, float), p.shape)
    sp = _pulse_spline(p, knot_revolutions, source, corners=corners, sigma_phi=sig_phi)
    inside = (t >= p[0]) & (t <= p[-1])
    ang, spd, acc = _on_samples(sp, t, inside)
    from .pulse_timing import _pulse_angle_error

    err = (None if timing_std_s is None else
           _pulse_angle_error(p, sp, np.broadcast_to(np.asarray(timing_std_s, float), p.shape),
                              float(np.median(np.diff(t)))))
    return RotorAngle(ang, spd, acc, inside, source, referenced=True, pulses_s=p,
                      angle_error=err, pulse_timing_std_s=(
                          None if timing_std_s is None else
                          np.broadcast_to(np.asarray(timing_std_s, float), p.shape).copy()))


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
    from .speed_channels import _rounded_continuous, _speed_spline_angle

    if 2 <= change.size < t.size // 4 and not _rounded_continuous(w, change):
        from .held_display import held_angle          # a held display: steps

        ang, spd, acc, err, covered = held_angle(t, w, change)
        return RotorAngle(ang, spd, acc, covered, source, referenced=False, angle_error=err)
    if t.size >= 64 and change.size >= 8:
        ra = _speed_spline_angle(t, w, source)
        if ra is not None:
            return ra
    ang = np.concatenate(([0.0], np.cumsum(0.5 * (w[1:] + w[:-1]) * np.diff(t))))
    acc = np.gradient(w, t)
    return RotorAngle(ang, w, acc, np.ones(t.size, bool), source, referenced=False)


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
