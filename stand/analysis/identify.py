"""``stand analyze``: the numbers a lab writes in its journal, from one recording.

Orchestrates the leaf package :mod:`dsp` on a recording (HDF5 written by
``stand run`` or by another tool, or a CSV of time and signals) and, when the
recording carries its scene, uses the scene for the model parameters (mass,
natural frequency, damping) that turn a 1X response into an unbalance.

Lab tables (CSV with any delimiter, decimal commas and header lines, Parquet,
pandas HDF5) are read by :func:`stand.lab.table.read_table`: columns mapped by
a recording map (``--columns`` or ``--map``, units converted at the edge) or
recognised by their well-known names (``t_s``, ``time_ms``, ``x_m``,
``disp_x_um``, ``rotor_angle_rad``, ``keyphasor``, ``tacho_rpm``, ...).  The
speed comes from an encoder angle, a keyphasor pulse channel, a tachometer,
or -- with none -- from the 1X line (flagged as estimated).  Swept records
(run-up, run-down, coast-down) add the Bode data, the sweep-corrected
critical speed and the model fit (:mod:`stand.analysis.runup`).

:func:`analyze` runs the steps in order, each writing its keys of the document:

1. the channels (:func:`stand.analysis.sources.read_source`);
2. the speed and its programme (:func:`_speed`);
3. natural frequency and damping of a free decay (:func:`_free_decay`);
4. run-up / run-down: Bode data, critical speed, model fit (:func:`_sweep`);
5. the 1X response and the unbalance over the final constant-speed stretch
   (:func:`_steady_1x`, :mod:`stand.analysis.unbalance`);
   with the reduction balancer off / on and the simulator's truth over the same stretch
   (:func:`stand.analysis.unbalance.reduction`, :func:`_truth`);
6. the quasi-periodic decomposition of the orbit (:func:`_components`);
7. the regime over windows and its critical speeds (:func:`_regime`);
8. the settling after each event of a planar scene (:func:`stand.analysis.signals.settling`).

The balancing report (:mod:`stand.reports.balancing`) presents this result; it identifies
nothing of its own.

Two-plane balancing from two screens is :func:`stand.analysis.two_plane.two_plane`.
"""
from __future__ import annotations

import math

import numpy as np

from dsp.errors import SignalError
from stand.analysis.sources import (no_weights as _no_weights, read_source, undersampled,
                                    undersampled_words, weightless_scene, whirls)
from stand.analysis.two_plane import two_plane
from stand.analysis.signals import settling
from stand.analysis.unbalance import line_1x, reduction, ring_reading, unbalance
from stand.analysis.vibration import VIBRATION, vibration_in_users_quantity

__all__ = ["analyze", "two_plane"]

TWO_PI = 2 * math.pi


def analyze(path, grade: float = 6.3, service_speed_rpm: float | None = None,
            recording_map=None, *, grade_mm_s: float | None = None):
    """Identify what a lab would from one recording.

    Every identification that does not apply (e.g. no rotation, no weights
    channel) is ``None`` with the reason in ``notes``.

    Parameters
    ----------
    path : str, Path, Run or Recording
    grade : float
        Required ISO 21940-11 grade G [mm/s].
    service_speed_rpm : float, optional
        Service speed [rpm] of the grade (default: the map's, else the measured speed).
    recording_map : stand.lab.recording_map.RecordingMap, optional
        Columns, units and the machine's data of a lab table.
    grade_mm_s : float, optional
        The old name of ``grade`` (deprecated).

    Returns
    -------
    stand.analysis.results.Analysis
        The document of ``stand analyze --json`` (with ``regime_timeline``, which the
        JSON leaves out), with attribute access, ``to_frame()`` and ``plot()``.
    """
    from stand.analysis.results import Analysis
    from stand.io.result import renamed

    grade = renamed(grade, grade_mm_s, "grade_mm_s", "grade", "analyze")
    d = read_source(path, recording_map)
    if "bode" in d:                          # a Bode / polar table: the modal fit
        from stand.analysis.bode import analyze_bode

        return Analysis(analyze_bode(d["bode"], d["notes"]))
    t = d["t"]
    if t.size < 2:  # np.gradient of the rotor angle needs two samples
        raise ValueError(f"{path}: {t.size} sample(s) in time (s); stand analyze needs at least 2")
    label = getattr(path, "path", None) or (f"<run of {path.scene.name}>"
                                            if hasattr(path, "scene") else str(path))
    out = {"recording": str(label), "notes": list(d.get("notes") or [])}
    notes = out["notes"]
    tab = d.get("table")
    rmap = tab.recording_map if tab is not None else recording_map
    if tab is not None:
        out["input"] = tab.input_summary()
    speed, rotating = _speed(d, out)
    _free_decay(d, out, rotating)
    _sweep(d, out, rotating)
    sl, sc1 = _steady_1x(d, out, speed, rotating)
    vibration_in_users_quantity(d, out)
    if d.get("quantity", "length") != "length":
        sc1 = None          # its vector is a velocity / acceleration: the fit or the line's |1X|
    if rotating:
        unbalance(out, d["scene"], sc1, d, rmap, getattr(rmap, "mass_kg", None) or d.get("mass_kg"),
                  grade, service_speed_rpm, notes)
    elif tab is not None:       # long-exposure circles (stand track --trace) need no speed
        ring_reading(out, d)
    if rotating:
        reduction(out, d)
    _truth(d, out)
    _components(d, out, sl, rotating)
    _regime(d, out, speed)
    out["settling"] = settling(d.get("rec_scene"), d["t"], d["x"], d["y"], notes)
    for key, value in list(out.items()):  # e.g. samples near 1e308 overflow inside dsp
        if isinstance(value, float) and not math.isfinite(value):
            out[key] = None
            notes.append(f"{key}: not finite ({value}); the input values are out of "
                         "floating-point range for this identification")
    return Analysis(out, channels=d)


def _truth(d, out) -> None:
    """``truth_unbalance_gmm``: a simulated run's true static residual unbalance (the vector
    sum over all planes of the rotor's unbalances and the weights' static moments,
    :func:`stand.analysis.sources._truth`), the complex mean over the stationary stretch the
    1X was taken over."""
    tr, st = d.get("truth"), out.get("stationary_stretch")
    if tr is None or not st:
        return
    t, psi = tr
    w = (t >= st["t_start_s"] - 1e-9) & (t <= st["t_end_s"] + 1e-9)
    if w.any():
        out["truth_unbalance_gmm"] = float(abs(np.mean(psi[w]))) * 1e6


def _speed(d, out):
    """Step 2: ``(speed [rad/s] or None, rotating)``; ``speed_source`` and ``programme``."""
    t, x, y, phi, angle = d["t"], d["x"], d["y"], d["phi"], d.get("angle")
    out["speed_source"] = d.get("speed_how")
    speed = None
    if phi is not None:
        speed = np.gradient(np.unwrap(phi), t)
    elif angle is not None:                    # a tachometer: speed without a mark
        speed = angle.speed_rad_s
    rotating = speed is not None and np.max(np.abs(speed)) > 1e-6 or d["kp"] is not None
    # the rotor's own speed: the recording's rotor/speed, else the angle channel's (a lab's
    # encoder column or keyphasor pulses: not the wrapped differences of sampled angles)
    true, how = d.get("rotor_speed"), "the recorded rotor speed (rotor/speed)"
    if true is None and angle is not None and d.get("table") is not None:
        true, how = angle.speed_rad_s, (f"that of the {d.get('speed_how') or 'angle channel'} "
                                        "as it stands, not of its samples' wrapped steps")
    u = d["undersampled"] = undersampled(t, true if true is not None else speed)
    if u is not None and true is not None and phi is not None:
        speed = true                # the sampled angle aliases: its differences are no speed
        out["notes"].append(undersampled_words(u, "rotor angle") + f": its samples alias there; "
                            f"the speed is {how}")
    if speed is None and d.get("table") is not None:      # no speed channel: does the shaft whirl?
        rotating = whirls(t, x, y)
    out["programme"] = None
    if speed is not None and rotating:
        from dsp.speed import speed_programme

        from stand.analysis.runup import _programme_dict

        out["programme"] = _programme_dict(speed_programme(t, speed))
    return speed, rotating


def _free_decay(d, out, rotating) -> None:
    """Step 3: natural frequency and damping from the free decay of a non-spinning rotor
    (and the photo-gate test of a lab table)."""
    from stand.analysis.signals import plane_free_decay

    notes, tab = out["notes"], d.get("table")
    out.update(natural_frequency_hz=None, natural_frequency_hz_std=None, damping_ratio=None,
               damping_ratio_std=None)
    if not rotating:
        fd = plane_free_decay(d["t"], d["x"], d["y"], notes)
        if fd is not None:
            out.update(natural_frequency_hz=fd.natural_frequency_hz,
                       natural_frequency_hz_std=fd.natural_frequency_hz_std,
                       damping_ratio=fd.damping_ratio, damping_ratio_std=fd.damping_ratio_std)
        if tab is not None and "photogate" in tab.signals:
            out["photogate"] = _photogate(tab, notes)
    elif d["scene"] is not None:
        notes.append("rotating record: f0 and damping taken from the scene, not identified")


def _sweep(d, out, rotating) -> None:
    """Step 4: run-up / run-down: Bode data, sweep-corrected critical speed, model fit."""
    from stand.analysis.runup import sweep_identification

    scene, tab = d["scene"], d.get("table")
    out.update(runup=None, critical_speed_hz=None, critical_speed_hz_std=None,
               critical_speed_method=None)
    model_ok = scene is None and (d.get("rec_scene") is None or _no_weights(d.get("rec_scene")))
    if not (rotating and (tab is not None or model_ok or scene is not None)):
        return
    sw = sweep_identification(d["t"], d["x"], d["y"], d.get("angle"), out["notes"],
                              fit_model=model_ok or tab is not None,
                              derivative=VIBRATION[d.get("quantity", "length")],
                              damping_ratio=_scene_damping(scene),
                              runout_allowance_m=getattr(getattr(tab, "recording_map", None),
                                                         "probe_runout_m", None),
                              channel_filter=d.get("channel_filter"), censored=d.get("censored"))
    if sw is None:
        return
    out["runup"] = sw
    if sw["speed_estimated"]:
        out["speed_source"] = sw["speed_source"]
        if out["programme"] is None:
            out["programme"] = sw["programme"]
    fit, res = sw["model_fit"], sw["resonance"]
    if fit is not None:     # exact for the model; the sweep-corrected 1X peak is a cross-check
        cross = (f"; the 1X peak of the {res['stretch']} with the sweep-rate lag removed gives "
                 f"{res['critical_speed_hz']:.5g} ± {res['critical_speed_hz_std']:.2g} rev/s "
                 f"(papers 001/003/004 4.3, 5.4)"
                 if res is not None else "")
        out.update(critical_speed_hz=fit["critical_speed_hz"],
                   critical_speed_hz_std=fit["critical_speed_hz_std"],
                   critical_speed_method="rigid-rotor model fitted to the whole record "
                   "(sweep-rate lag and transients in the model), f0 / sqrt(1 - 2 zeta^2)" + cross)
    elif res is not None:
        zeta = (f", zeta = {res['damping_ratio_used']:.4g} from the recording's scene"
                if res["damping_ratio_used"] else "")
        p = res["critical_speed_hz_std_parts"]
        out.update(critical_speed_hz=res["critical_speed_hz"],
                   critical_speed_hz_std=res["critical_speed_hz_std"],
                   critical_speed_method=f"1X peak of the {res['stretch']}, sweep-rate lag "
                   f"removed (papers 001/003/004 4.3, 5.4{zeta}); its std: the peak's scatter "
                   f"{p['peak']:.2g} and shape {p['peak_shape']:.2g}, the lag correction's "
                   f"neglected order {p['lag_model']:.2g} and damping {p['damping']:.2g} rev/s")
    if fit is not None:
        out.update(natural_frequency_hz=fit["natural_frequency_hz"],
                   natural_frequency_hz_std=fit["natural_frequency_hz_std"],
                   damping_ratio=fit["damping_ratio"],
                   damping_ratio_std=fit["damping_ratio_std"],
                   natural_frequency_method="rigid-rotor model fitted to the whole "
                   "record (dsp.response_fit)")


def _steady_1x(d, out, speed, rotating):
    """Step 5: the final constant-speed stretch and its 1X response; ``(slice, the
    dsp.unbalance.SynchronousComponent or None)``."""
    from dsp import unbalance as ub

    from stand.analysis.signals import stationary_stretch, steady_start

    t, x, y, phi, tab = d["t"], d["x"], d["y"], d["phi"], d.get("table")
    notes = out["notes"]
    out.update(unbalance_gmm=None, unbalance_gmm_std=None, unbalance_angle_deg=None,
               iso_grade=None, response_1x_m=None, response_1x_m_std=None, speed_hz=None)
    i0 = steady_start(t, speed) if speed is not None else 0
    if tab is not None and out["programme"] and out["programme"]["stretches"] \
            and getattr(d.get("angle"), "source", None) != "angle":
        # a lab speed wobbles: the programme's last constant stretch, also when a short tail
        # after it (at most a tenth of the record: a keyphasor spline's end) reads as a ramp
        const = [s for s in out["programme"]["stretches"] if s["kind"] == "constant"]
        if const and t[-1] - const[-1]["t_end_s"] <= 0.1 * (t[-1] - t[0]):
            i0 = int(np.searchsorted(t, const[-1]["t_start_s"]))
    sl, out["stationary_stretch"] = stationary_stretch(t, x + 1j * y, speed, i0)
    cens = d.get("censored")
    if cens is not None and cens[sl].any():          # its longest stretch without clipping
        ok = np.concatenate(([0], (~cens[sl]).astype(np.int8), [0]))
        e = np.flatnonzero(np.diff(ok)).reshape(-1, 2)
        a, b = e[int(np.argmax(e[:, 1] - e[:, 0]))] + sl.start
        notes.append(f"steady 1X: clipped samples in the stationary stretch; its longest part "
                     f"without them taken ({t[a]:.6g}-{t[b - 1]:.6g} s)")
        sl = slice(int(a), int(b))
        out["stationary_stretch"].update(t_start_s=float(t[a]), t_end_s=float(t[b - 1]),
                                         duration_s=float(t[b - 1] - t[a]), samples=int(b - a))
    sc1 = None
    why = _no_steady_1x(d, out, speed, sl) if rotating else None
    if why is not None:
        notes.append(why)
    elif rotating and (phi is not None or d["kp"] is not None):
        try:
            sc1 = ub.synchronous_component(t[sl], x[sl], y[sl],
                                           rotor_angle=None if phi is None else phi[sl],
                                           keyphasor_times=d["kp"])
            if d.get("probes") is not None and d["scene"] is not None:
                sc1 = _runout_removed(d, sc1, speed, sl, notes)
            sc1 = _mark_timing(d.get("angle"), sc1, t[sl], None if speed is None else speed[sl])
            if d.get("channel_filter") is not None:       # the declared filter divided out
                from dsp.artefacts import unfiltered

                sc1 = unfiltered(sc1, d["channel_filter"], notes)
            out["response_1x_m"] = sc1.amplitude_m
            out["response_1x_m_std"] = sc1.amplitude_std_m
            out["speed_hz"] = sc1.speed_rad_s / TWO_PI
        except SignalError as exc:
            notes.append(f"1X / unbalance: {exc}")
    elif rotating:
        ang = d.get("angle")
        line_1x(t[sl], x[sl] + 1j * y[sl], out, notes,
                speed_how=d.get("speed_how") if ang is not None and not ang.estimated else None)
    return sl, sc1


def _no_steady_1x(d, out, speed, sl):
    """Why the record gives no steady 1X, in the user's words, or None: its stationary stretch
    itself sampled below twice the rotor speed (:func:`stand.analysis.sources.undersampled`;
    a later, slower stretch keeps its 1X), or too short (it ends in a run-up or run-down)."""
    from stand.io.numbers import plain

    t, u = d["t"], d.get("undersampled")
    start, stop = sl.indices(t.size)[:2]
    f = np.abs(np.asarray(speed[start:stop])) / TWO_PI if u is not None else np.zeros(0)
    if len(bad := np.flatnonzero(f >= 0.5 * u["sample_rate_hz"]) if f.size else ()):  # aliases
        i = start + int(bad[0])
        u = dict(u, index=i, t_s=float(t[i]), speed_hz=float(np.max(f)))
        return undersampled_words(u, "1X") + ": no 1X"
    n = stop - start
    if n >= 3:
        return None
    st = (out.get("programme") or {}).get("stretches") or []
    last = next((s for s in reversed(st) if s["kind"] not in ("constant", "stopped")), None)
    ends = (f"the record ends in a {last['kind']} ({plain(last['t_start_s'])}–"
            f"{plain(last['t_end_s'], 's')}, {plain(last['speed_start_hz'])} -> "
            f"{plain(last['speed_end_hz'], 'rev/s')}): " if last and st[-1] is last else "")
    return (f"1X: {ends}the constant-speed stretch at its end holds {n} sample"
            f"{'s' if n != 1 else ''}; a steady 1X needs at least 3: no 1X")


def _runout_removed(d, sc1, speed, sl, notes):
    """The steady 1X of probes that see a runout (a profile fixed to the rotor: a 1X of its
    own, up to its amplitude on the 1X), on the scene-model route (rotors with weights).

    Where the record turns slowly (at most a quarter of the scene's natural frequency, four
    revolutions or more, before the steady stretch) its 1X there -- the slow-roll vector --
    is taken off; the ± then holds the slow-roll vector's scatter and the response still in
    it (the model's |H(w_s)| times the unbalance plus the weights' capacity, all of it, as a
    bound).  Else -- or when that gives the larger ± -- the probes' stated 1X runout r goes
    into the ± (r on each of Re, Im: a vector of that length at an unknown angle, bounded)."""
    import dataclasses

    from stand.analysis.signals import per_revolution

    scene, t, x, y, phi = d["scene"], d["t"], d["x"], d["y"], d["phi"]
    w1 = scene.natural_frequency
    zeta = scene.supports.damping_x / (2 * math.sqrt(scene.supports.stiffness_x * scene.total_mass))

    def H(w):
        R = w / w1
        return abs(R * R / complex(1 - R * R, 2 * zeta * R))

    v1, sv = sc1.vector_m, sc1.vector_std_m
    i_end = sl.start if isinstance(sl, slice) and sl.start else t.size
    slow = (np.abs(speed[:i_end]) > 0) & (np.abs(speed[:i_end]) <= 0.25 * w1) if w1 > 0 \
        else np.zeros(0, bool)
    j = np.flatnonzero(slow)
    pr = None
    if j.size >= 8:
        k = j[: int(np.argmax(np.diff(np.append(j, -1)) != 1)) + 1]   # the first slow block
        try:
            pr = per_revolution(t[k], x[k], y[k], phi[k])
        except SignalError:
            pr = None
    r = (d.get("probes") or {}).get("runout_1x_m")
    stated = None if r is None else (v1, math.hypot(sv, r),
                                     f"the probes' stated 1X runout {r * 1e6:.3g} µm is in the "
                                     "steady 1X's ±")
    slowroll = None
    if pr is not None and pr[2].size >= 4:
        vs = pr[2]
        V = complex(np.mean(vs))
        sV = float(np.std(vs, ddof=1) / math.sqrt(2 * vs.size))
        cap = scene.weights_capacity()
        dyn = H(float(np.max(pr[1]))) * (abs(v1) / max(H(sc1.speed_rad_s), 1e-300)
                                         + cap / scene.total_mass)
        slowroll = (v1 - V, math.sqrt(sv * sv + sV * sV + dyn * dyn),
                    f"the slow-roll 1X ({abs(V) * 1e6:.3g} µm over {vs.size} revolutions at "
                    f"<= {np.max(pr[1]) / TWO_PI:.3g} rev/s) taken off the steady 1X; its scatter "
                    f"and the response still in it ({dyn * 1e6:.2g} µm, bound) are in the ±")
    if slowroll is None and stated is None:
        notes.append("probe runout: no slow roll in the record (four revolutions below a "
                     "quarter of f0) and no stated runout: the steady 1X may be off by the "
                     "probes' runout, not in the ±")
        return sc1
    # both honest: the one with the smaller ± (a slow roll still full of response is no use)
    v, s, how = min((c for c in (slowroll, stated) if c is not None), key=lambda c: c[1])
    if slowroll is None:
        how += " (no slow roll in the record: four revolutions below a quarter of f0)"
    elif how is stated[2]:
        how += (f" (the slow roll's ± would be {slowroll[1] * 1e6:.2g} µm: the response in it "
                "is too large)")
    notes.append(f"probe runout: {how}")
    a = abs(v)
    return dataclasses.replace(sc1, vector_m=v, amplitude_m=a, amplitude_std_m=s,
                               phase_rad=math.atan2(v.imag, v.real),
                               phase_std_rad=s / a if a > 0 else math.pi, vector_std_m=s)


def _mark_timing(angle, sc1, t, speed):
    """The 1X phase's std with what the rotor angle leaves open over the stretch (a
    keyphasor's edge timing, an encoder's count: ``RotorAngle.angle_error``): the mean
    angle error over the stretch turns the vector by ``sigma``, its amplitude not
    (``phase_std_rad``; :func:`stand.analysis.unbalance.unbalance` carries it into the
    unbalance angle's std)."""
    import dataclasses

    err = getattr(angle, "angle_error", None)
    if err is None or speed is None or not getattr(angle, "referenced", False):
        return sc1
    A, C = err.modes(t, speed)
    a = np.asarray(A.mean(axis=0)).ravel()
    sig = math.sqrt(max(float(a @ C @ a), 0.0))
    if not sig > 0:
        return sc1
    return dataclasses.replace(sc1, phase_std_rad=math.hypot(sc1.phase_std_rad, sig),
                               reference_std_rad=sig)


def _components(d, out, sl, rotating) -> None:
    """Step 6: the quasi-periodic decomposition of the orbit (:func:`dsp.quasiperiodic.decompose`)."""
    from dsp import quasiperiodic as qpd

    t, x, y, notes = d["t"], d["x"], d["y"], out["notes"]
    out.update(components=[], petals=None, shape=None, **dict.fromkeys(
        f"{w}{q}" for w in ("precession", "nutation", "strongest_other_line")
        for q in ("_hz", "_hz_std", "_amplitude_m", "_amplitude_m_std")))
    if not (rotating and out["speed_hz"] is not None):
        return
    if d.get("quantity", "length") != "length":
        notes.append("quasi-periodic decomposition: on displacement records only (this one is "
                     f"{d['quantity']})")
        return
    try:
        f_rot = out["speed_hz"]
        dec = qpd.decompose(t[sl], (x + 1j * y)[sl], rotor_speed_hz=f_rot, polish="rect")
        out["components"] = [{"frequency_hz": c.frequency_hz, "frequency_hz_std": c.frequency_std_hz,
                              "amplitude_m": c.amplitude_m, "amplitude_m_std": c.amplitude_std_m,
                              "phase_deg": math.degrees(c.phase_rad),
                              "phase_deg_std": math.degrees(c.phase_std_rad),
                              "direction": c.direction} for c in dec.components]
        line = dec.precession                   # the strongest forward line below the 1X
        stuck = line is not None and _stuck_weights_line(d, sl, line, f_rot, notes)
        if line is not None and not stuck:      # what it is not: the stuck weights' precession
            out.update(strongest_other_line_hz=line.frequency_hz,
                       strongest_other_line_hz_std=line.frequency_std_hz,
                       strongest_other_line_amplitude_m=line.amplitude_m,
                       strongest_other_line_amplitude_m_std=line.amplitude_std_m)
        if not stuck:       # without a precession the rotor-speed line is the 1X, no nutation
            return
        out.update(precession_hz=dec.precession_hz, precession_hz_std=dec.precession_std_hz,
                   nutation_hz=dec.nutation_hz if dec.nutation is not None else None,
                   nutation_hz_std=dec.nutation_std_hz if dec.nutation is not None else None,
                   precession_amplitude_m=dec.precession_amplitude_m,
                   precession_amplitude_m_std=dec.precession_amplitude_std_m,
                   nutation_amplitude_m=(dec.nutation_amplitude_m if dec.nutation is not None
                                         else None),
                   nutation_amplitude_m_std=(dec.nutation_amplitude_std_m
                                             if dec.nutation is not None else None),
                   petals=dec.petals, shape=dec.shape)
        _precession_against_f0(d, out, notes)
    except SignalError as exc:
        notes.append(f"quasi-periodic decomposition: {exc}")


def _stuck_weights_line(d, sl, line, f_rot, notes) -> bool:
    """Whether the orbit's strongest line below the 1X (``line``, a dsp.quasiperiodic
    Component) is the stuck weights' precession.  With the weights' angles recorded: they
    slip behind the rotor (their mean speed over the stretch below the rotor's by more than
    the regime's synchrony tolerance, 1e-3 of it) and the line runs at their mean speed
    (within 3 of its std or the stretch's resolution 1 / T) -- the orbit precesses with the
    stuck weights at their speed Omega (:mod:`dsp.quasiperiodic`).  Without them (a lab
    record: the orbit is all there is) the line is taken as the precession, as the
    decomposition identifies it, unless the recording's scene has no weights at all."""
    w = d.get("weights")
    t = d["t"][sl]
    if t.size < 2 or not t[-1] > t[0]:
        return False
    if w is None:    # a line within 1/T of the 1X is not resolved from it (a changing 1X)
        bare, near = weightless_scene(d.get("rec_scene")), abs(line.frequency_hz - f_rot) < 1 / (t[-1] - t[0])
        if bare or near:
            notes.append(f"the orbit's strongest line besides the 1X, {line.frequency_hz:.6g} Hz, is " + (
                "the rotor's own: the recording's scene has no weights" if bare else "within the "
                "stretch's resolution 1/T of the 1X: not resolved from it, not identified as a precession"))
        return not (bare or near)
    wa = np.unwrap(np.asarray(w, float)[sl].reshape(t.size, -1), axis=0)
    f_w = (wa[-1] - wa[0]) / (t[-1] - t[0]) / TWO_PI           # [rev/s] per weight
    tol = max(3 * line.frequency_std_hz, 1.0 / (t[-1] - t[0]))
    slipping = bool(np.all(f_w < f_rot * (1 - 1e-3)))
    at_their_speed = bool(abs(line.frequency_hz - float(np.mean(f_w))) <= tol)
    if not (slipping and at_their_speed):
        notes.append(f"the orbit's strongest line besides the 1X, {line.frequency_hz:.6g} Hz, is "
                     f"no stuck weights' precession: the weights turn at "
                     f"{float(np.mean(f_w)):.6g} rev/s " + ("with the rotor (synchronous)"
                                                            if not slipping else
                                                            "and the line is not at their speed"))
    return slipping and at_their_speed


def _precession_against_f0(d, out, notes) -> None:
    """The note of (5.181), Omega_1 < omega_1: where the stuck weights' precession lies below
    the natural frequency it is compared with (the one identified, else the planar scene's),
    by 20 % of it at most, it is a lower bound for f0, not f0."""
    f0, src = out.get("natural_frequency_hz"), "identified"
    sc = d.get("scene")
    if f0 is None and getattr(sc, "kind", None) == "planar":
        f0, src = sc.natural_frequency / TWO_PI, "the scene's"
    fP, sP = out["precession_hz"], out.get("precession_hz_std") or 0.0
    if f0 is None or not (0.8 * f0 <= fP and fP + 2 * sP < f0):
        return
    notes.append(f"the stuck weights' precession {fP:.6g} Hz lies {100 * (1 - fP / f0):.2g} % "
                 f"below the natural frequency {f0:.6g} Hz ({src}): Omega_1 < omega_1 (5.181), a lower "
                 "bound for f0, not f0")


def _regime(d, out, speed) -> None:
    """Step 7: the regime over windows and its critical speeds, from the recorded weights'
    angles (``weights/<weight>/angle``) against the rotor angle, over the part of the record
    sampled at more than twice the rotor speed."""
    from dsp import regime as rg

    t, x, y, phi, notes = d["t"], d["x"], d["y"], d["phi"], out["notes"]
    w, scene = d["weights"], d.get("rec_scene")
    out.update(regime=None, critical_speeds_hz=[])
    why = None
    if w is None:
        why = ("the recording's scene has no weights: there is no regime of weights"
               if weightless_scene(scene) else
               "needs the weights' angles (a stroboscope or the simulator's "
               "weights/<weight>/angle); " + ("a lab table has none" if d.get("table") is not None
                                              else "the recording has none (a liquid has no "
                                              "angle)" if scene is not None else
                                              "the recording has none"))
    elif phi is None:
        why = "needs the rotor angle (rotor/angle) to see the weights slip against the rotor"
    elif scene is None:
        why = ("needs the recording's scene (the balancer's capacity sets when the rotor is "
               "balanced)")
    elif scene.kind != "planar" and d.get("residual_ratio") is None:
        why = ("a rotor of the family is balanced when each plane's residual unbalance is "
               "inside its ring of zone 1; the recording has no truth/residual/<plane>")
    if why is not None:
        notes.append(f"regime: {why}")
        return
    u = d.get("undersampled")
    n = t.size if u is None else u["index"]
    if u is not None:
        notes.append(undersampled_words(u, "regime") + ": the weights' angles alias there; "
                     + (f"classified before {u['t_s']:.6g} s only (the timeline and its changes; "
                        "the regime at the end of the record is not known)" if n >= 3
                        else "no regime"))
        if n < 3:
            return
    try:
        t, x, y, phi, w, speed = t[:n], x[:n], y[:n], phi[:n], w[:n], speed[:n]
        w_s = max(4 * TWO_PI / max(float(np.median(np.abs(speed))), 1e-9), (t[-1] - t[0]) / 200)
        w_s = min(w_s, (t[-1] - t[0]) / 3)
        if scene.kind == "planar":     # balanced: the whirl inside the ring of zone 1, S / (16 M)
            thr = scene.weights_capacity() / scene.total_mass / 16    # balls and body weights
        else:     # a rotor of the family: every plane's recorded residual below S_p / 16
            x, y, thr = d["residual_ratio"][:n], np.zeros(n), 1.0
        wins = rg.classify_windows(t, np.unwrap(phi), w, x, y, w_s, thr)
        out["regime"] = wins[-1].regime if u is None else None
        out["regime_timeline"] = [{"t_start_s": w.t_start, "t_end_s": w.t_end, "regime": w.regime,
                                   "speed_hz": w.rotor_speed_rad_s / TWO_PI} for w in wins]
        out["critical_speeds_hz"] = [{"speed_hz": c.speed_hz, "speed_hz_std": c.speed_hz_uncertainty,
                                      "before": c.before, "after": c.after, "time_s": c.time_s}
                                     for c in rg.critical_speeds(wins)]
    except SignalError as exc:
        notes.append(f"regime: {exc}")


def _scene_damping(scene):
    """The rigid rotor's damping ratio c / (2 sqrt(k M)) of a planar scene without weights
    (None otherwise): the resonance's sweep-lag correction then needs no fit (with zeta = 0
    it removed the sweep-limited lag, 3.6 % too much on a 2 rev/s^2 run-up at zeta 0.04)."""
    if scene is None or not _no_weights(scene):
        return None
    s = scene.supports
    k, c = 0.5 * (s.stiffness_x + s.stiffness_y), 0.5 * (s.damping_x + s.damping_y)
    return float(c / (2.0 * math.sqrt(k * scene.total_mass))) if k > 0 else None


def _photogate(tab, notes):
    """The book's natural-frequency test: the period from the 1st to the 3rd pass of the beam
    over the photo-gate (:func:`dsp.crossings.photogate_period`)."""
    from dsp.crossings import photogate_period
    from dsp.speed import pulse_times

    try:
        p = pulse_times(tab.t, tab.signals["photogate"],
                        threshold=tab.columns["photogate"].threshold,
                        name=f"column {tab.columns['photogate'].column!r}", mark="centre")
        period = photogate_period(p, 1, 3)
        return {"passes": int(p.size), "period_s": period, "frequency_hz": 1.0 / period,
                "method": "1st to 3rd pass of the beam over the photo-gate (FPM-09, 4.3); each "
                "pass timed at the middle of its pulse"}
    except (SignalError, ValueError) as exc:
        notes.append(f"photo-gate: {exc}")
        return None

