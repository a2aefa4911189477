"""Run-up and run-down recordings: Bode data, the sweep-corrected resonance and the model fit.

What ``stand analyze`` adds for a record whose speed sweeps (one of the
programme's stretches is a run-up, run-down or coast-down), on lab tables and
on recordings of rotors without weights:

* **Bode data**: the 1X vector revolution by revolution (order tracking,
  :func:`stand.analysis.signals.per_revolution`) against the speed; the phase only when
  the angle is referenced to a mark (keyphasor, encoder).
* **Model fit** over the whole record (:func:`dsp.response_fit.fit_unbalance_response`):
  natural frequency, damping ratio, specific unbalance and its angle, the
  probes' DC offset and 1X runout; no quasi-steady assumption.  A tachometer's
  integrated speed is the angle up to a constant (the unbalance angle is then not
  reported); with no speed channel at all the angle is estimated from
  the whirl (:func:`dsp.response_fit.fit_response_without_speed`) and the
  unbalance has a magnitude but no angle; the probes' runout is then not fitted
  but allowed for in the ± (:data:`RUNOUT_ALLOWANCE_M`).
* **Critical speed** from the resonance peak of the 1X amplitude with the
  sweep-rate lag removed (:func:`dsp.runup.resonance_from_runup`, papers
  001/003/004 sections 4.3, 5.4), using the fitted damping ratio; the runout
  is taken out of the 1X vectors first.  Its std (:func:`dsp.runup.resonance_std`):
  the peak's scatter and shape, the lag correction's neglected order and damping.
"""
from __future__ import annotations

import math
from typing import Optional

import numpy as np

__all__ = ["sweep_identification", "SWEEPS"]

TWO_PI = 2.0 * math.pi
SWEEPS = ("run-up", "run-down", "coast-down")

#: Without a speed channel the probes' 1X runout is not fitted (with the angle estimated
#: from the whirl it is not identifiable: a runout, a turn of the angle and a change of e,
#: zeta and the speed make a shallow curved valley); its effect on the estimates, for a
#: runout up to this magnitude [m] at an unknown angle, is put in their std.
RUNOUT_ALLOWANCE_M = 2.0e-6


def _keyphasor_angle_std(t, angle) -> float:
    """Std [rad] the keyphasor's pulse timing adds to every phase referenced to it.

    The pulses scatter about the angle's spline by sigma (edge timing: the DAQ's
    sampling of the edge, noise); the spline has a knot every 8 revolutions, so its
    level is known to sigma sqrt(8 / N) over any stretch of 8 revolutions (N pulses
    in all): a conservative bound on the shift of the mark that an unbalance angle
    fitted over the resonance sees.
    """
    p = getattr(angle, "pulses_s", None)
    if p is None or p.size < 16:
        return 0.0
    c = angle.covered
    ph = np.interp(p, t[c], angle.angle_rad[c])
    res = ph - ph[0] - TWO_PI * np.arange(p.size)
    res = res[1:-1] - np.mean(res[1:-1])
    return float(np.std(res) * math.sqrt(8.0 / p.size))


def _std_parts(fit, referenced: bool, mark_std_rad: float) -> dict:
    """What each std of the fit contains (``dsp.response_fit.ResponseFit.std_parts``), the
    angle's in degrees with the keyphasor pulses' scatter about their spline; no angle
    without a mark."""
    parts = {k: dict(v) for k, v in (getattr(fit, "std_parts", None) or {}).items()}
    ang = parts.pop("angle_rad", None)
    if referenced and ang is not None:
        parts["unbalance_angle_deg"] = {**{k: math.degrees(v) for k, v in ang.items()},
                                        "keyphasor_scatter": math.degrees(mark_std_rad)}
    return parts


def _fit_dict(fit, referenced: bool, mark_std_rad: float = 0.0) -> dict:
    angle_std = math.hypot(fit.angle_rad_std, mark_std_rad)
    return {"natural_frequency_hz": fit.natural_frequency_hz,
            "natural_frequency_hz_std": fit.natural_frequency_hz_std,
            "damping_ratio": fit.damping_ratio, "damping_ratio_std": fit.damping_ratio_std,
            "critical_speed_hz": fit.critical_speed_hz,
            "critical_speed_hz_std": fit.critical_speed_hz_std,
            "specific_unbalance_m": fit.specific_unbalance_m,
            "specific_unbalance_m_std": fit.specific_unbalance_m_std,
            "unbalance_angle_deg": (math.degrees(fit.angle_rad) % 360.0 if referenced else None),
            "unbalance_angle_deg_std": (math.degrees(angle_std) if referenced else None),
            "unbalance_angle_deg_std_parts": ({"fit": math.degrees(fit.angle_rad_std),
                                               "keyphasor_timing": math.degrees(mark_std_rad)}
                                              if referenced else None),
            "std_parts": _std_parts(fit, referenced, mark_std_rad),
            "offset_x_m": fit.offset_m.real, "offset_y_m": fit.offset_m.imag,
            "runout_m": abs(fit.runout_m), "residual_rms_m": fit.residual_rms_m,
            "samples": fit.samples, "delay_s": fit.delay_s or None,
            "delay_s_std": fit.delay_s_std if fit.delay_s else None}


def sweep_identification(t, x, y, angle, notes: list, *, referenced: Optional[bool] = None,
                         fit_model: bool = True, derivative: int = 0,
                         damping_ratio: Optional[float] = None,
                         runout_allowance_m: Optional[float] = None, channel_filter=None,
                         censored=None) -> Optional[dict]:
    """Identify what a swept record gives (module docstring).

    Parameters
    ----------
    t, x, y : ndarray
        Times [s] (uniform) and shaft displacements [m].
    angle : dsp.speed.RotorAngle or None
        The rotor angle; None or not ``referenced``: estimated from the whirl.
    notes : list of str
        Receives what could not be done and why.
    fit_model : bool
        Fit the rigid-rotor model (off for rotors whose weights make it wrong).
    derivative : int
        x, y measure displacement (0), velocity (1, [m/s]) or acceleration (2, [m/s²]):
        the model is fitted in that quantity; the Bode data are displacement (1X / (i w)^k).
    damping_ratio : float, optional
        zeta [-] for the resonance's sweep-lag correction when the model is not fitted
        (e.g. from a recording's scene); default 0 (the sweep-limited lag, the damped lag's
        upper bound: half of it then goes into the critical speed's std).
    runout_allowance_m : float, optional
        Without a speed channel: the probes' 1X runout [m] the ± allows for (a recording
        map's ``[probes] runout``); default :data:`RUNOUT_ALLOWANCE_M`.
    channel_filter : dsp.artefacts.ChannelFilter, optional
        The probes' declared filter: in the model fit, and divided out of the Bode vectors.
    censored : ndarray of bool, optional
        Samples (clipped) left out of the model fit and of the Bode data.

    Returns
    -------
    dict or None
        ``programme``, ``speed_source``, ``bode``, ``resonance``, ``model_fit``
        (each None when not obtained, with the reason in ``notes``); None when
        the record is not swept.
    """
    from dsp.artefacts import delay_checked, sensor_checked
    from dsp.errors import SignalError
    from dsp.response_fit import fit_response_without_speed, fit_unbalance_response
    from dsp.runup import resonance_from_runup, resonance_std
    from dsp.speed import speed_programme

    from stand.analysis.signals import per_revolution

    z = np.asarray(x) + 1j * np.asarray(y)
    ref = bool(angle is not None and angle.referenced) if referenced is None else referenced
    out = {"speed_source": None if angle is None else angle.source, "speed_estimated": False,
           "bode": None, "resonance": None, "model_fit": None, "programme": None}
    fit = None
    # a tachometer's integrated angle is the rotor angle up to a constant, which the fit's
    # unbalance angle absorbs: f0, zeta and |U| as with a mark (issue 31, item 2)
    if angle is not None and (ref or not angle.estimated):
        c = angle.covered
        prog = speed_programme(t[c], angle.speed_rad_s[c])
        if not any(s.kind in SWEEPS for s in prog.stretches):
            return None
        if fit_model:
            args = (t[c], z[c], angle.angle_rad[c], angle.speed_rad_s[c],
                    angle.acceleration_rad_s2[c])
            kw = dict(derivative=derivative, angle_error=angle.angle_error,
                      channel_filter=channel_filter,
                      censored=None if censored is None else censored[c])
            try:
                fit = fit_unbalance_response(*args, **kw)
                if ref:
                    fit = delay_checked(fit, lambda: fit_unbalance_response(*args, **kw,
                                                                            fit_delay=True),
                                        float(np.max(np.abs(angle.speed_rad_s[c]))),
                                        channel_filter, notes)
                    fit = sensor_checked(fit, lambda **k: fit_unbalance_response(*args, **{**kw, **k}),
                                         np.percentile(np.abs(angle.speed_rad_s[c]), [0, 100]) / TWO_PI,
                                         channel_filter, notes)
            except SignalError as exc:
                notes.append(f"run-up model fit: {exc}")
    else:
        if angle is not None:       # a tachometer: is the record swept at all?
            prog = speed_programme(t, angle.speed_rad_s)
            if not any(s.kind in SWEEPS for s in prog.stretches):
                return None
        if not fit_model:
            return None
        if derivative:
            notes.append("run-up model fit: a velocity or acceleration record needs a speed "
                         "channel (keyphasor, encoder or tachometer)")
            return None
        if angle is None and _steady_line(t, z):
            return None     # not swept: a constant-speed fit would take the speed for f0
        try:
            allow = RUNOUT_ALLOWANCE_M if runout_allowance_m is None else runout_allowance_m
            fit, angle = fit_response_without_speed(t, z, runout_allowance_m=allow)
        except SignalError as exc:
            notes.append(f"run-up model fit without a keyphasor: {exc}")
            return None
        out.update(speed_source="1X line (estimated from the vibration)", speed_estimated=True)
        said = ("the recording map's [probes] runout" if runout_allowance_m is not None else
                "the default; declare the probes' runout as [probes] runout = \"... um\" in the "
                "recording map")
        notes.append("run-up model fit without a speed channel: the probes' 1X runout is not "
                     f"fitted; the ± allows for one up to {allow * 1e6:g} µm at any angle "
                     f"({said}; a larger runout is not covered)")
        c = angle.covered
        prog = speed_programme(t[c], angle.speed_rad_s[c])
        if not any(s.kind in SWEEPS for s in prog.stretches):
            notes.append("run-up: the speed estimated from the 1X line does not sweep")
            return None
    out["programme"] = _programme_dict(prog)
    if fit is not None:
        out["model_fit"] = _fit_dict(fit, ref, _keyphasor_angle_std(t, angle) if ref else 0.0)
        if out["speed_estimated"]:
            out["model_fit"]["runout_allowance_m"] = (
                RUNOUT_ALLOWANCE_M if runout_allowance_m is None else runout_allowance_m)
    # Bode: the 1X vector revolution by revolution, runout removed
    c = angle.covered
    try:
        pr = per_revolution(t[c], z[c].real, z[c].imag, angle.angle_rad[c])
    except SignalError as exc:
        notes.append(f"1X vs speed: {exc}")
        pr = None
    if pr is None:
        return out
    tm, w, v = pr
    if fit is not None:
        v = v - fit.runout_m
    if channel_filter is not None:
        v = v / channel_filter.response(w / TWO_PI)
    if fit is not None and fit.delay_s:
        v = v * np.exp(1j * w * fit.delay_s)
    if censored is not None and censored[c].any():        # revolutions with clipped samples
        tc = t[c][censored[c]]
        hit = np.searchsorted(tc, tm + np.pi / w) > np.searchsorted(tc, tm - np.pi / w)
        tm, w, v = tm[~hit], w[~hit], v[~hit]
        if hit.any():
            notes.append(f"1X vs speed: {int(hit.sum())} revolutions with clipped samples left "
                         "out; no critical speed from the 1X peak (the fit gives it)")
    v = v / (1j * w) ** derivative            # the 1X of a velocity / acceleration -> displacement
    out["bode"] = {"t_s": tm.tolist(), "speed_hz": (w / TWO_PI).tolist(),
                   "amplitude_m": np.abs(v).tolist(),
                   "phase_deg": np.degrees(np.angle(v)).tolist() if ref else None}
    if censored is not None and censored[c].any() and hit.any():
        return out
    # the sweep-rate-corrected resonance, on the longest sweep stretch
    sweeps = [s for s in prog.stretches if s.kind in SWEEPS]
    s = max(sweeps, key=lambda s: s.duration_s)
    inside = (tm >= s.t_start_s) & (tm <= s.t_end_s)
    zeta = fit.damping_ratio if fit is not None else float(damping_ratio or 0.0)
    try:
        if inside.sum() < 16:
            raise SignalError(f"{int(inside.sum())} revolutions in the {s.kind}; need 16")
        r = resonance_from_runup(tm[inside], w[inside], np.abs(v[inside]), damping_ratio=zeta)
        shift = 1.0 / math.sqrt(1.0 - 2.0 * zeta * zeta)
        sd = resonance_std(w[inside], np.abs(v[inside]), r, zeta,
                           fit.damping_ratio_std if fit is not None else 0.0,
                           damping_known=fit is not None or damping_ratio is not None)
        out["resonance"] = {"stretch": s.kind, "peak_speed_hz": r.peak_frequency_hz,
                            "sweep_rate_hz_s": r.angular_acceleration_rad_s2 / TWO_PI,
                            "lag_hz": r.lag_rad_s / TWO_PI,
                            "critical_speed_hz": r.corrected_frequency_hz * shift,
                            "critical_speed_hz_std": sd["std_rad_s"] / TWO_PI * shift,
                            "critical_speed_hz_std_parts": {
                                k: sd[k] / TWO_PI * shift
                                for k in ("peak", "peak_shape", "lag_model", "damping")},
                            "natural_frequency_hz": r.corrected_frequency_hz,
                            "damping_ratio_used": zeta, "direction": r.direction}
    except SignalError as exc:
        notes.append(f"resonance from the {s.kind}: {exc}")
    return out


def _steady_line(t, z, parts: int = 4, k: float = 5.0, rtol: float = 2e-3) -> bool:
    """Without a speed channel: is the whirl one steady line?  The strongest line's
    frequency in each of ``parts`` equal pieces of the record (:func:`dsp.lines.
    refine_frequencies`) agrees with the others within ``k`` of their combined std or
    within ``rtol`` (the speed programme's constant tolerance): then the record is not
    swept (a lab's constant-speed record, a track of the spot's circle)."""
    from dsp.errors import SignalError
    from dsp.lines import refine_frequencies

    n = t.size // parts
    if n < 64:
        return False
    f, s = [], []
    try:
        for i in range(parts):
            sl = slice(i * n, (i + 1) * n)
            c = refine_frequencies(t[sl], z[sl] - np.mean(z[sl]), 1)
            f.append(float(c.frequency_hz[0]))
            s.append(float(c.frequency_hz_std[0]))
    except SignalError:
        return False
    f, s = np.array(f), np.array(s)
    spread = np.abs(f[:, None] - f[None, :])
    return bool(np.all((spread <= k * np.hypot(s[:, None], s[None, :]))
                       | (spread <= rtol * np.abs(f).max())))


def _programme_dict(prog) -> dict:
    return {"kind": prog.kind,
            "stretches": [{"kind": s.kind, "t_start_s": s.t_start_s, "t_end_s": s.t_end_s,
                           "speed_start_hz": s.speed_start_hz, "speed_end_hz": s.speed_end_hz,
                           "rate_hz_s": s.rate_hz_s} for s in prog.stretches]}
