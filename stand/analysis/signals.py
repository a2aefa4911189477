"""Signal helpers on one recorded run, shared by the reports (and meant for ``stand analyze``).

Arrays of one record: time ``t`` [s], shaft displacement ``x``, ``y`` [m],
unwrapped rotor angle ``phi`` [rad] and rotor speed ``speed`` [rad/s].  These
helpers orchestrate :mod:`dsp` the way every report needs it: where the final
constant-speed stretch starts, the per-revolution 1X vectors of a run-up, and
the free decay of a non-spinning rotor with the failure as a note instead of
an exception.
"""
from __future__ import annotations

import math

import numpy as np

__all__ = ["settling", "steady_start", "forward_start", "per_revolution", "plane_free_decay",
           "stationary_stretch"]

TWO_PI = 2.0 * math.pi


def steady_start(t, speed, rtol: float = 1e-3) -> int:
    """Index where the final stretch of constant speed starts.

    Parameters
    ----------
    t : ndarray
        Sample times [s].
    speed : ndarray or None
        Rotor speed [rad/s] at the samples; None: no speed, returns 0.
    rtol : float
        Constant means within ``rtol`` of the last speed (default 0.1 %) [-].

    Returns
    -------
    int
        The first sample of the stretch (``t.size - 1`` when only the last
        sample qualifies).
    """
    if speed is None:
        return 0
    ref = speed[-1]
    ok = np.abs(speed - ref) <= rtol * max(abs(ref), 1e-12)
    i = t.size - 1
    while i > 0 and ok[i - 1]:
        i -= 1
    return i


def forward_start(phi) -> int:
    """First index from which the rotor angle ``phi`` [rad] increases strictly to the end."""
    bad = np.nonzero(np.diff(phi) <= 0)[0]
    return 0 if bad.size == 0 else int(bad[-1] + 1)


def per_revolution(t, x, y, phi):
    """The 1X response revolution by revolution (dsp order tracking).

    Parameters
    ----------
    t, x, y : ndarray
        Times [s] and shaft displacements [m].
    phi : ndarray
        Unwrapped rotor angle [rad]; only its final strictly increasing part is used.

    Returns
    -------
    tuple of ndarray or None
        Revolution mid-times [s], speeds [rad/s] and complex 1X vectors
        x + i y [m]; None when fewer than 8 samples turn forward.

    Raises
    ------
    dsp.errors.SignalError
        Fewer than two whole revolutions.
    """
    from dsp import unbalance as ub

    i0 = forward_start(phi)
    if t.size - i0 < 8:
        return None
    sc = ub.synchronous_component(t[i0:], x[i0:], y[i0:], rotor_angle=phi[i0:], min_revolutions=2)
    ph = phi[i0:]
    j0 = math.ceil(ph[0] / TWO_PI - 1e-12)
    j1 = math.floor(ph[-1] / TWO_PI + 1e-12)
    tb = np.interp(TWO_PI * np.arange(j0, j1 + 1), ph, t[i0:])
    return 0.5 * (tb[1:] + tb[:-1]), TWO_PI / np.diff(tb), np.asarray(sc.per_revolution_m)


def plane_free_decay(t, x, y, notes: list):
    """Natural frequency and damping from the free decay of a rotor that does not turn.

    A plane decay is real: the channel that moves most (``x`` or ``y``) is
    fitted by :func:`dsp.frequency.free_decay` (matrix pencil + least
    squares); a complex fit of a real signal would see two counter-rotating
    lines.

    Parameters
    ----------
    t : ndarray
        Sample times [s].
    x, y : ndarray
        Shaft displacements [m].
    notes : list of str
        Receives ``"free decay: <reason>"`` when the fit fails.

    Returns
    -------
    object or None
        The fit (``natural_frequency_hz`` [Hz], ``natural_frequency_hz_std``
        [Hz], ``damping_ratio`` [-], ``damping_ratio_std`` [-]), or None when
        the record does not allow it (the reason is in ``notes``).
    """
    from dsp import frequency as fq
    from dsp.errors import SignalError

    try:
        return fq.free_decay(t, x if np.std(x) >= np.std(y) else y)
    except SignalError as exc:
        notes.append(f"free decay: {exc}")
        return None


def _line_amplitude(t, z):
    """Amplitude and its uncertainty of the strongest line of ``z`` (mean removed)."""
    from dsp.lines import refine_frequencies

    c = refine_frequencies(t, z - np.mean(z), 1, polish=True)
    return abs(complex(c.amplitude[0])), float(c.amplitude_std[0])


def stationary_stretch(t, z, speed=None, start: int = 0, parts: int = 4):
    """The stationary stretch at the end of a record: constant speed and a settled orbit.

    From ``start`` (the first sample of the final constant-speed stretch, 0 without a
    speed) the record is cut into ``parts`` equal parts; leading parts whose strongest
    line's amplitude differs from the last part's by more than 5 combined standard
    uncertainties plus 2 % (a transient still settling) are dropped.  Everything else is
    used: no fixed fraction of the record.

    Parameters
    ----------
    t : ndarray
        Times [s] (uniform).
    z : ndarray
        Orbit x + i y [m].
    speed : ndarray, optional
        Rotor speed [rad/s] (only to name the rule).
    start : int
        First sample of the candidate stretch.
    parts : int
        Number of parts compared.

    Returns
    -------
    (slice, dict)
        The stretch and ``{"t_start_s", "t_end_s", "duration_s", "samples", "rule"}``.
    """
    from dsp.errors import SignalError

    n = t.size
    i0 = int(start)
    rule = "constant speed" if speed is not None else "whole record (no speed channel)"
    size = (n - i0) // parts
    if size >= 64:
        try:
            amps = [_line_amplitude(t[i0 + k * size:i0 + (k + 1) * size],
                                    z[i0 + k * size:i0 + (k + 1) * size]) for k in range(parts)]
            a_end, s_end = amps[-1]
            k = 0
            while k < parts - 1:
                a, s = amps[k]
                if abs(a - a_end) <= 5 * math.hypot(s, s_end) + 0.02 * a_end:
                    break
                k += 1
            if k:
                rule += f", settled after {k} of {parts} parts"
            i0 += k * size
        except SignalError:
            pass
    sl = slice(i0, n)
    return sl, {"t_start_s": float(t[i0]), "t_end_s": float(t[-1]),
                "duration_s": float(t[-1] - t[i0]), "samples": int(n - i0), "rule": rule}


def _events(scene, t_end):
    """``(time [s], what)`` of the scene's events before ``t_end`` [s], in time order."""
    ev = []
    dr = scene.drive
    if dr.kind == "speed" and dr.programme.shape[0] > 1 and dr.coast_down_start is None:
        te = float(dr.programme[-1, 0])
        if te < t_end:
            ev.append((te, "end of the speed programme (constant speed reached)"))
    for p in scene.perturbations:
        if p.kind == "unbalance":
            te = p.start + p.duration
            ev.append((te, f"unbalance change to e = {p.eccentricity:.4g} m"
                       + (" (end of the ramp)" if p.duration > 0 else "")))
        elif p.kind == "impulse":
            ev.append((p.start, "blow to the housing (impulse)"))
        elif p.kind == "side_force":
            ev.append((p.start, "side force applied"))
            if p.end is not None and math.isfinite(p.end) and p.end < t_end:
                ev.append((p.end, "side force removed"))
    return sorted((e for e in ev if e[0] < t_end), key=lambda e: e[0])


def settling(scene, t, x, y, notes) -> list:
    """Settling after each event of a planar scene (``settling`` of the analysis; [] without
    a planar scene).

    The whirl envelope (largest whirl radius [m] over one natural period)
    settles when it enters and stays within 5 % of its largest deviation from
    its final value; times in s (``settling_time_s`` from the event).
    """
    from scipy.ndimage import maximum_filter1d

    if getattr(scene, "kind", None) != "planar" or not scene.natural_frequency > 0:
        return []
    r = np.hypot(x, y)
    T0 = TWO_PI / scene.natural_frequency
    fs = (t.size - 1) / (t[-1] - t[0])
    rms = maximum_filter1d(r, size=max(1, int(round(T0 * fs))), mode="nearest")
    ev = _events(scene, float(t[-1]))
    rows = []
    for k, (te, what) in enumerate(ev):
        tn = ev[k + 1][0] if k + 1 < len(ev) else float(t[-1])
        sel = (t >= te) & (t <= tn)
        if np.count_nonzero(sel) < 8 or tn - te < 2 * T0:
            rows.append({"event": what, "time_s": te, "settled": False, "settling_time_s": None,
                         "final_whirl_m": None, "tolerance_m": None})
            continue
        ts, rs = t[sel], rms[sel]
        ref = ts >= tn - max(0.1 * (tn - te), T0)
        rf = float(np.mean(rs[ref]))
        tol = 0.05 * float(np.max(np.abs(rs - rf)))
        out = np.nonzero(np.abs(rs - rf) > tol)[0]
        t_set = float(ts[out[-1] + 1]) if out.size and out[-1] + 1 < ts.size else \
            (float(ts[0]) if not out.size else None)
        settled = t_set is not None and t_set < float(ts[ref][0])
        rows.append({"event": what, "time_s": te, "settled": bool(settled),
                     "settling_time_s": (t_set - te) if settled else None,
                     "final_whirl_m": rf, "tolerance_m": tol})
    if rows:
        notes.append("settling time: the whirl envelope (largest whirl radius over one natural period) enters and stays in a "
                     "band of 5 % of its largest deviation from its final value (mean over the "
                     "last 10 % before the next event)")
    return rows
