"""Dynamics of one recording: natural frequency, critical speeds, regimes, settling.

The natural frequency and damping are identified from a free decay (rotor at
rest) or from the 1X resonance of a run-up without loose weights
(:mod:`dsp.frequency`); the critical speeds of the recording are where the
weights gain or lose synchrony (:mod:`dsp.regime`), compared with those of
the chapter-5 theory (:func:`stand.theories.planar.speedmap.scene_theory`); the
settling time after each event of the scene is that of the whirl envelope.
"""
from __future__ import annotations

import math

import numpy as np

from stand.reports.balancing_schema import REGIME_NAMES
from stand.analysis.signals import per_revolution, plane_free_decay

__all__ = ["dynamics"]

TWO_PI = 2.0 * math.pi


def _regime_windows(rec):
    """Regime of each window (:func:`dsp.regime.classify_windows`) and the window length [s].

    Windows of 4 revolutions at the median speed (at least 1/200, at most 1/3
    of the record); the residual threshold is S / (M_Sigma 16) [m].
    """
    from dsp import regime as rg

    t, speed, scene = rec.t, rec.speed, rec.scene
    w_s = max(4 * TWO_PI / max(float(np.median(np.abs(speed))), 1e-9), (t[-1] - t[0]) / 200)
    w_s = min(w_s, (t[-1] - t[0]) / 3)
    thr = scene.balancer.capacity / scene.total_mass / 16
    return rg.classify_windows(t, rec.phi, rec.data["weights"], rec.x, rec.y, w_s, thr), w_s


def dynamics(rec, notes, warn):
    """The ``dynamics`` section of the report (``rec``, ``notes``, ``warn`` as for
    :func:`stand.reports.balancing_quality.balancing_quality`).

    Returns
    -------
    dict
        Natural frequency [Hz] and damping ratio [-] (identified with standard
        uncertainties, and the model's), critical speeds [Hz] found in the
        recording and from the theory, the regime timeline (times [s], speeds
        [Hz]), the final regime and the settling after each event (times [s],
        whirl [m]).
    """
    from dsp import frequency as fq
    from dsp import regime as rg
    from dsp.errors import SignalError

    d, scene, t, x, y, phi, rotating = rec.data, rec.scene, rec.t, rec.x, rec.y, rec.phi, rec.rotating
    nf = {"identified_hz": None, "identified_hz_std": None, "damping_ratio": None,
          "damping_ratio_std": None, "method": None, "model_hz": None, "model_damping_ratio": None}
    if scene is not None:
        s = scene.supports
        nf["model_hz"] = scene.natural_frequency / TWO_PI
        nf["model_damping_ratio"] = s.damping_x / (2 * math.sqrt(s.stiffness_x * scene.total_mass))
    dyn = {"natural_frequency": nf, "theory_available": False, "critical_speeds": [],
           "final_regime": None, "regime_timeline": [], "settling": []}
    if not rotating:
        fd = plane_free_decay(t, x, y, notes)
        if fd is not None:
            nf.update(identified_hz=fd.natural_frequency_hz,
                      identified_hz_std=fd.natural_frequency_hz_std,
                      damping_ratio=fd.damping_ratio, damping_ratio_std=fd.damping_ratio_std,
                      method="free decay (matrix pencil + least squares)")
    else:
        # run-up / run-down: 1X resonance peak with the sweep lag removed
        try:
            pr = per_revolution(t, x, y, phi) if d["weights"] is None else None
            if d["weights"] is not None:
                notes.append("natural frequency: not identified from the run-up (the loose weights "
                             "shift the resonance peak); the model value is shown")
            elif pr is not None and np.ptp(pr[1]) > 0.05 * np.max(pr[1]):
                tm, wr, vec = pr
                zeta = nf["model_damping_ratio"] or 0.0
                res = fq.resonance_from_runup(tm, wr, np.abs(vec), damping_ratio=zeta)
                k = int(np.argmin(np.abs(wr - res.peak_speed_rad_s)))
                dw = abs(wr[min(k + 1, wr.size - 1)] - wr[max(k - 1, 0)]) / 2
                nf.update(identified_hz=res.corrected_frequency_hz,
                          identified_hz_std=dw / TWO_PI / math.sqrt(12.0),
                          method=(f"{res.direction} 1X resonance peak, sweep lag removed "
                                  "(damping ratio from the model when known, else 0; assumes no "
                                  "loose weights; uncertainty: speed step of one revolution / "
                                  "sqrt 12)"))
            else:
                notes.append("natural frequency: the rotor turns at a constant speed; no free "
                             "decay or resonance passage to identify it from (model value shown)")
        except SignalError as exc:
            notes.append(f"natural frequency from the run-up: {exc}")

    # theory (scene_theory) critical speeds
    theory = None
    if scene is not None and scene.balancer.count > 0:
        try:
            import warnings as _w

            from stand.theories.planar.speedmap import scene_theory

            with _w.catch_warnings():
                _w.simplefilter("ignore")
                theory = scene_theory(scene)
            dyn["theory_available"] = True
        except Exception as exc:  # noqa: BLE001 -- TheoryError and numerical failures
            notes.append(f"theory (scene_theory) not available: {exc}")
    th_rows = []
    if theory is not None:
        for c in theory.critical_speeds:
            th_rows.append({"source": "theory", "speed_hz": c.hz, "speed_hz_std": None,
                            "event": f"{c.motion} {c.kind} stability ({c.source})",
                            "nearest_theory_hz": None, "difference_hz": None})

    # regimes and critical speeds found in the recording
    found = []
    if rotating and d["weights"] is not None and scene is not None and scene.balancer.count:
        try:
            wins, w_s = _regime_windows(rec)
            segs = []
            for w in wins:
                nm = REGIME_NAMES.get(w.regime, w.regime)
                if segs and segs[-1]["regime"] == nm:
                    segs[-1]["t_end_s"] = w.t_end
                    segs[-1]["speed_end_hz"] = w.rotor_speed_rad_s / TWO_PI
                    segs[-1]["windows"] += 1
                else:
                    segs.append({"t_start_s": w.t_start, "t_end_s": w.t_end, "regime": nm,
                                 "speed_start_hz": w.rotor_speed_rad_s / TWO_PI,
                                 "speed_end_hz": w.rotor_speed_rad_s / TWO_PI, "windows": 1})
            dyn["regime_timeline"] = segs
            dyn["regime_window_s"] = w_s
            dyn["final_regime"] = segs[-1]["regime"] if segs else None
            for c in rg.critical_speeds(wins):
                found.append({"source": "recording (weights gain/lose synchrony)",
                              "speed_hz": c.speed_hz, "speed_hz_std": c.speed_hz_uncertainty,
                              "event": f"{REGIME_NAMES.get(c.before, c.before)} -> "
                                       f"{REGIME_NAMES.get(c.after, c.after)} at t = "
                                       f"{c.time_s:.4g} s",
                              "nearest_theory_hz": None, "difference_hz": None})
        except SignalError as exc:
            notes.append(f"regime timeline: {exc}")
    elif rotating:
        notes.append("regime timeline: needs the weights' angles and the scene (balancer)")
    if th_rows:
        ths = np.array([r["speed_hz"] for r in th_rows])
        for r in found:
            k = int(np.argmin(np.abs(ths - r["speed_hz"])))
            r["nearest_theory_hz"] = float(ths[k])
            r["difference_hz"] = r["speed_hz"] - float(ths[k])
        if found:
            notes.append("critical speeds: the theory's are those of slow (quasi-static) speed "
                         "changes; during a run-up the weights lag, so synchrony is gained at a "
                         "higher speed than the theory's")
    dyn["critical_speeds"] = found + th_rows

    # settling after each perturbation (and after the end of the speed programme)
    if scene is not None:
        dyn["settling"] = _settling(scene, t, x, y, notes)
    return dyn


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


def _settling(scene, t, x, y, notes):
    """Settling after each event: the rows of ``dynamics.settling``.

    The whirl envelope (largest whirl radius [m] over one natural period)
    settles when it enters and stays within 5 % of its largest deviation from
    its final value; times in s (``settling_time_s`` from the event).
    """
    from scipy.ndimage import maximum_filter1d

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
