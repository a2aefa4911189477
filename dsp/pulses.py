"""Once-per-revolution pulses: their times in a sampled channel, repaired, and the angle
spline through them.

:func:`pulse_times` finds the leading edges of a keyphasor or photo-gate channel (Otsu's
two-level threshold, Schmitt hysteresis, the 50 % crossing interpolated between samples);
:func:`repair_pulses` fills in missed and drops double pulses; :func:`debounced` merges a
contact's bounce into the edge before it (:func:`bounced` draws it); :func:`_pulse_spline` is
the angle through (pulse k, 2 pi k) that :func:`dsp.speed.angle_from_pulses` and
:func:`dsp.pulse_timing.retime_pulses` use.  Also importable from :mod:`dsp.speed`.
"""
from __future__ import annotations

from typing import Optional

import numpy as np

from .errors import SignalError, check_times
from .rotor_angle import TWO_PI

__all__ = ["otsu_threshold", "pulse_times", "repair_pulses", "debounced", "bounced"]


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


def debounced(pulses, *, hold_off: float = 0.4, window: int = 8):
    """A contact's bounce merged into the true edge before it.

    A pulse less than ``hold_off`` times the once-per-revolution period after the last kept
    pulse is a bounce of it and is dropped.  The period is the median of the last three kept
    intervals (each divided by the number of periods it spans: a missed pulse does not double
    it), at the start the longest of the first ``window`` intervals (the bounces' short intervals cannot pull it down as they pull a
    median when there are several per revolution).

    Returns
    -------
    (ndarray, int)
        The kept pulse times [s] and the number merged.
    """
    p = np.asarray(pulses, float)
    if p.size < 3:
        return p, 0
    kept, per, periods = [p[0]], float(np.max(np.diff(p[:window + 1]))), []
    for x in p[1:]:
        d = x - kept[-1]
        if d >= hold_off * per:
            kept.append(x)
            periods.append(d / max(1, round(d / per)))     # a missed pulse's interval halved
            per = float(np.median(periods[-3:]))
    return np.asarray(kept), int(p.size - len(kept))


def bounced(t, v, edges, count: int, bounce_time: float, low: float):
    """A pulse channel ``v`` at times ``t`` [s] with contact bounce after each true edge
    (``edges`` [s]): ``count`` extra rising edges at ``edges + k bounce_time`` (k = 1..count),
    each after the contact opened (``low``) for the quarter ``bounce_time`` before it, closed
    again at the level the edge reached in the samples before the first opening."""
    t = np.asarray(t, float)
    out = np.array(v, float)
    if count <= 0:
        return out
    edges = np.asarray(edges, float)
    i0, lo, hi = (np.searchsorted(t, edges + c * bounce_time) for c in (0.0, 0.75, count))
    for te, e, a, b in zip(edges, i0, lo, hi):
        high = out[e:a].max() if a > e else out[min(e, t.size - 1)]
        out[a:b] = np.where((t[a:b] - te) / bounce_time % 1.0 < 0.75, high, low)
    return out


def _lsq_cubic(x, y, n_int, knots_at=None, w=None):
    """Least-squares cubic spline of y(x) with ``n_int`` intervals (inner knots evenly spaced
    in x, or at ``knots_at``), residuals weighted by ``w``."""
    from scipy.interpolate import make_lsq_spline

    inner = np.linspace(x[0], x[-1], n_int + 1)[1:-1] if knots_at is None else knots_at
    return make_lsq_spline(x, y, np.concatenate(([x[0]] * 4, inner, [x[-1]] * 4)), k=3, w=w)


def _pulse_spline(p, knot_revolutions: float, source: str = "keyphasor", corners: bool = False,
                  sigma_phi=None):
    """The angle through the points (pulse k, 2 pi k): interpolating for
    ``knot_revolutions = 0`` or fewer than two intervals, else a least-squares cubic with
    a knot every ``knot_revolutions`` pulses (:func:`angle_from_pulses`); with ``corners``
    True, double knots where the speed's slope jumps (:func:`_corner_knots`); a sequence of
    times: double knots there."""
    from scipy.interpolate import CubicSpline

    if p.size < 3:
        raise SignalError(f"{source}: {p.size} pulse(s); need at least 3 (two revolutions)")
    if np.any(np.diff(p) <= 0):
        raise SignalError(f"{source}: pulse times must increase")
    k = TWO_PI * np.arange(p.size)
    n_int = int(p.size / max(knot_revolutions, 4.0)) if knot_revolutions else 0
    if n_int < 2:
        return CubicSpline(p, k)
    inner = np.interp(np.linspace(0, p.size - 1, n_int + 1)[1:-1], np.arange(p.size), p)
    if corners is True:
        inner = _corner_knots(p, k, inner, sigma_phi)
    elif corners is not False and corners is not None:     # corner times given
        c = np.asarray(corners, float).ravel()
        c = c[(c > p[1]) & (c < p[-2])]
        inner = np.sort(np.concatenate([inner, c, c]))
    return _lsq_cubic(p, k, n_int, inner)




def _corner_knots(p, k, inner, sigma_phi=None, max_corners: int = 4):
    """Inner knots with double knots added where the speed's slope jumps (a run-up that
    turns into a hold, a drive switched over): the cubic through a knot every few
    revolutions rounds such a corner over its interval and misses the angle there by many
    times the pulses' scatter.  One corner at a time, at the place that lowers the pulses'
    chi^2 most (a scan over the pulses, then Brent between the neighbours), while it lowers it
    by more than :data:`CORNER_CHI2`; ``sigma_phi`` the pulses' angle std [rad] (default:
    their scatter about the spline, robust)."""
    from scipy.optimize import minimize_scalar

    def chi2(knots):
        try:
            sp = _lsq_cubic(p, k, 0, np.sort(knots))
        except (ValueError, np.linalg.LinAlgError):
            return np.inf, None
        return float(np.sum(((k - sp(p)) / sig) ** 2)), sp

    base = _lsq_cubic(p, k, 0, inner)
    r = k - base(p)
    if sigma_phi is None:
        sig = 1.4826 * float(np.median(np.abs(r - np.median(r)))) or 1e-12
    else:
        sig = np.maximum(np.broadcast_to(np.asarray(sigma_phi, float), p.shape), 1e-12)
    knots = np.asarray(inner, float)
    best, _ = chi2(knots)
    for _ in range(max_corners):
        cand = p[2:-2]
        trials = [chi2(np.concatenate([knots, [c, c]]))[0] for c in cand]
        if not trials:
            break
        i = int(np.argmin(trials))
        lo, hi = p[i + 1], p[i + 3]
        res = minimize_scalar(lambda c: chi2(np.concatenate([knots, [c, c]]))[0],
                              bounds=(lo, hi), method="bounded",
                              options={"xatol": 1e-6 * (hi - lo)})
        c = float(res.x) if res.fun <= trials[i] else float(cand[i])
        new, _ = chi2(np.concatenate([knots, [c, c]]))
        if not best - new > 2.0 * np.log(p.size):
            break
        knots, best = np.concatenate([knots, [c, c]]), new
    return np.sort(knots)
