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
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from dsp.errors import SignalError

TWO_PI = 2 * math.pi


def _read(path, recording_map=None):
    """The arrays of a Run, a Recording, a stand recording file or a lab table."""
    from stand.lab.table import is_table
    from stand.recording.hdf5 import read_recording
    from stand.integrate.result import Run

    if isinstance(path, Run):
        return _from_run(path)
    p = Path(path)
    if is_table(p):
        return _from_table(p, recording_map)
    d = _from_run(read_recording(p))
    if recording_map is not None and recording_map.columns:   # e.g. a folder of mixed files
        d["notes"].append("the recording map applies to tables; this stand recording carries "
                          "its own channels (map ignored)")
    return d


def _from_table(p, recording_map):
    """A lab table (:func:`stand.lab.table.read_table`) and its rotor angle."""
    from stand.lab.speed_source import rotor_angle_of
    from stand.lab.table import read_table

    tab = read_table(p, recording_map)
    notes = [f"excluded rows {e['rows']}: {e['reason']}" for e in tab.excluded]
    angle, how = rotor_angle_of(tab, notes)
    t, x, y = tab.t, tab.signals["x"], tab.signals["y"]
    phi = None
    if angle is not None and angle.referenced:
        c = angle.covered
        if not c.all():
            notes.append(f"samples outside the first and last keyphasor pulse left out "
                         f"({int((~c).sum())})")
        t, x, y, phi = t[c], x[c], y[c], angle.angle_rad[c]
        angle = type(angle)(angle.angle_rad[c], angle.speed_rad_s[c], angle.acceleration_rad_s2[c],
                            np.ones(int(c.sum()), bool), angle.source, angle.referenced,
                            angle.estimated, angle.pulses_s)
    return dict(t=t, x=x, y=y, phi=phi, kp=None, weights=None, scene=None, notes=notes,
                angle=angle, speed_how=how, table=tab)


def _from_run(rec):
    """The arrays of a Run or Recording; the scene only where the model parts apply (the
    planar rotor of chapter 5)."""
    scene = rec.scene if getattr(rec.scene, "kind", None) == "planar" else None
    phi = rec.rotor_angle if np.all(np.isfinite(rec.rotor_angle)) else None
    w = rec.weight_angle if rec.weight_angle.size and np.all(np.isfinite(rec.weight_angle)) else None
    angle = None
    t = np.asarray(rec.t)
    if phi is not None and t.size > 1:
        from dsp.speed import RotorAngle

        ph = np.unwrap(np.asarray(phi, float))
        wr = np.gradient(ph, t)
        angle = RotorAngle(ph, wr, np.gradient(wr, t), np.ones(t.size, bool), "rotor angle",
                           referenced=True)
    return dict(t=t, x=np.asarray(rec.x), y=np.asarray(rec.y), phi=phi, kp=None,
                weights=w, scene=scene, notes=list(rec.notes), angle=angle,
                speed_how="the recording's rotor angle" if phi is not None else "no rotor angle",
                table=None, rec_scene=rec.scene)


def analyze(path, grade_mm_s: float = 6.3, service_speed_rpm: float | None = None,
            recording_map=None) -> dict:
    """Identify what a lab would from one recording; returns a JSON-able dict.

    Every identification that does not apply (e.g. no rotation, no weights
    channel) is ``None`` with the reason in ``notes``.

    Parameters
    ----------
    path : str, Path, Run or Recording
    grade_mm_s : float
        Required ISO 21940-11 grade G [mm/s].
    service_speed_rpm : float, optional
        Service speed [rpm] of the grade (default: the map's, else the measured speed).
    recording_map : stand.lab.recording_map.RecordingMap, optional
        Columns, units and the machine's data of a lab table.
    """
    from dsp import quasiperiodic as qpd
    from dsp import regime as rg
    from dsp import unbalance as ub

    from stand.analysis.runup import sweep_identification
    from stand.analysis.signals import plane_free_decay, stationary_stretch, steady_start

    d = _read(path, recording_map)
    t, x, y, phi, scene = d["t"], d["x"], d["y"], d["phi"], d["scene"]
    if t.size < 2:  # np.gradient of the rotor angle needs two samples
        raise ValueError(f"{path}: {t.size} sample(s) in time (s); stand analyze needs at least 2")
    label = getattr(path, "path", None) or (f"<run of {path.scene.name}>"
                                            if hasattr(path, "scene") else str(path))
    out = {"recording": str(label), "notes": list(d.get("notes") or [])}
    notes = out["notes"]
    tab = d.get("table")
    rmap = tab.recording_map if tab is not None else recording_map
    mass = getattr(rmap, "mass_kg", None)
    if tab is not None:
        out["input"] = tab.input_summary()
    angle = d.get("angle")
    out["speed_source"] = d.get("speed_how")
    speed = None
    if phi is not None:
        speed = np.gradient(np.unwrap(phi), t)
    elif angle is not None:                    # a tachometer: speed without a mark
        speed = angle.speed_rad_s
    rotating = speed is not None and np.max(np.abs(speed)) > 1e-6 or d["kp"] is not None
    if speed is None and tab is not None:      # no speed channel: does the shaft whirl?
        rotating = _whirls(t, x, y)

    # the speed programme
    out["programme"] = None
    if speed is not None and rotating:
        from dsp.speed import speed_programme

        from stand.analysis.runup import _programme_dict

        out["programme"] = _programme_dict(speed_programme(t, speed))

    # natural frequency and damping: free decay of a non-spinning rotor
    out.update(natural_frequency_hz=None, natural_frequency_hz_std=None, damping_ratio=None,
               damping_ratio_std=None)
    if not rotating:
        fd = plane_free_decay(t, x, y, notes)
        if fd is not None:
            out.update(natural_frequency_hz=fd.natural_frequency_hz,
                       natural_frequency_hz_std=fd.natural_frequency_hz_std,
                       damping_ratio=fd.damping_ratio, damping_ratio_std=fd.damping_ratio_std)
        if tab is not None and "photogate" in tab.signals:
            out["photogate"] = _photogate(tab, notes)
    elif scene is not None:
        notes.append("rotating record: f0 and damping taken from the scene, not identified")

    # run-up / run-down: Bode data, sweep-corrected critical speed, model fit
    out.update(runup=None, critical_speed_hz=None, critical_speed_method=None)
    model_ok = scene is None and (d.get("rec_scene") is None or _no_weights(d.get("rec_scene")))
    if rotating and (tab is not None or model_ok or scene is not None):
        sw = sweep_identification(t, x, y, angle, notes, fit_model=model_ok or tab is not None)
        if sw is not None:
            out["runup"] = sw
            if sw["speed_estimated"]:
                out["speed_source"] = sw["speed_source"]
                if out["programme"] is None:
                    out["programme"] = sw["programme"]
            fit, res = sw["model_fit"], sw["resonance"]
            if res is not None:
                out.update(critical_speed_hz=res["critical_speed_hz"],
                           critical_speed_method=f"1X peak of the {res['stretch']}, sweep-rate lag "
                           "removed (papers 001/003/004 4.3, 5.4)")
            elif fit is not None:
                out.update(critical_speed_hz=fit["critical_speed_hz"],
                           critical_speed_hz_std=fit["critical_speed_hz_std"],
                           critical_speed_method="rigid-rotor model fitted to the whole record")
            if fit is not None:
                out.update(natural_frequency_hz=fit["natural_frequency_hz"],
                           natural_frequency_hz_std=fit["natural_frequency_hz_std"],
                           damping_ratio=fit["damping_ratio"],
                           damping_ratio_std=fit["damping_ratio_std"],
                           natural_frequency_method="rigid-rotor model fitted to the whole "
                           "record (dsp.response_fit)")

    # 1X and unbalance over the final constant-speed stretch
    out.update(unbalance_gmm=None, unbalance_gmm_std=None, unbalance_angle_deg=None,
               iso_grade=None, response_1x_m=None, speed_hz=None)
    i0 = steady_start(t, speed) if speed is not None else 0
    if tab is not None and out["programme"] and out["programme"]["stretches"] \
            and getattr(angle, "source", None) != "angle":
        last = out["programme"]["stretches"][-1]      # a lab speed wobbles: the programme's stretch
        if last["kind"] == "constant":
            i0 = int(np.searchsorted(t, last["t_start_s"]))
    sl, out["stationary_stretch"] = stationary_stretch(t, x + 1j * y, speed, i0)
    sc1 = None
    if rotating and (phi is not None or d["kp"] is not None):
        try:
            sc1 = ub.synchronous_component(t[sl], x[sl], y[sl],
                                           rotor_angle=None if phi is None else phi[sl],
                                           keyphasor_times=d["kp"])
            out["response_1x_m"] = sc1.amplitude_m
            out["speed_hz"] = sc1.speed_rad_s / TWO_PI
        except SignalError as exc:
            notes.append(f"1X / unbalance: {exc}")
    elif rotating:
        _line_1x(t[sl], x[sl] + 1j * y[sl], out, notes)
    if rotating:
        _unbalance(out, scene, sc1, d, rmap, mass, grade_mm_s, service_speed_rpm, notes)

    # quasi-periodic decomposition of the orbit
    out.update(components=[], precession_hz=None, nutation_hz=None, petals=None, shape=None)
    if rotating and out["speed_hz"] is not None:
        try:
            f_rot = out["speed_hz"]
            dec = qpd.decompose(t[sl], (x + 1j * y)[sl], rotor_speed_hz=f_rot, polish="rect")
            out["components"] = [{"frequency_hz": c.frequency_hz, "frequency_hz_std": c.frequency_std_hz,
                                  "amplitude_m": c.amplitude_m, "phase_deg": math.degrees(c.phase_rad),
                                  "direction": c.direction} for c in dec.components]
            qp = dec.precession is not None
            out.update(precession_hz=dec.precession_hz if qp else None,
                       precession_hz_std=dec.precession_std_hz if qp else None,
                       nutation_hz=dec.nutation_hz if dec.nutation is not None else None,
                       nutation_hz_std=dec.nutation_std_hz if dec.nutation is not None else None,
                       precession_amplitude_m=dec.precession_amplitude_m if qp else None,
                       nutation_amplitude_m=(dec.nutation_amplitude_m if dec.nutation is not None
                                             else None),
                       petals=dec.petals if dec.precession is not None else None,
                       shape=dec.shape if dec.precession is not None else None)
            if dec.precession is not None:
                notes.append("the precession line (stuck weights) lies slightly below the natural "
                             "frequency (Omega_1 < omega_1, (5.181)): a lower bound for f0, not f0")
        except SignalError as exc:
            notes.append(f"quasi-periodic decomposition: {exc}")

    # regime over windows and critical speeds (needs the weights' angles)
    out.update(regime=None, critical_speeds_hz=[])
    if d["weights"] is not None and phi is not None and scene is not None:
        try:
            w_s = max(4 * TWO_PI / max(float(np.median(np.abs(speed))), 1e-9), (t[-1] - t[0]) / 200)
            w_s = min(w_s, (t[-1] - t[0]) / 3)
            thr = scene.balancer.capacity / scene.total_mass / 16 if scene.balancer.count else 0.0
            wins = rg.classify_windows(t, np.unwrap(phi), d["weights"], x, y, w_s, thr)
            out["regime"] = wins[-1].regime
            out["regime_timeline"] = [{"t_start_s": w.t_start, "t_end_s": w.t_end, "regime": w.regime,
                                       "speed_hz": w.rotor_speed_rad_s / TWO_PI} for w in wins]
            out["critical_speeds_hz"] = [{"speed_hz": c.speed_hz, "speed_hz_std": c.speed_hz_uncertainty,
                                          "before": c.before, "after": c.after}
                                         for c in rg.critical_speeds(wins)]
        except SignalError as exc:
            notes.append(f"regime: {exc}")
    else:
        notes.append("regime: needs the weights' angles (stroboscope or simulator channel)")
    for key, value in list(out.items()):  # e.g. samples near 1e308 overflow inside dsp
        if isinstance(value, float) and not math.isfinite(value):
            out[key] = None
            notes.append(f"{key}: not finite ({value}); the input values are out of "
                         "floating-point range for this identification")
    return out


def _no_weights(scene) -> bool:
    """The rigid-rotor model of the run-up fit applies: a planar rotor without weights (a
    rotor of the family is left to its own model)."""
    bal = getattr(scene, "balancer", None)
    return getattr(scene, "kind", None) == "planar" and not getattr(bal, "count", 0)


def _whirls(t, x, y) -> bool:
    """Without a speed channel: the shaft whirls when the phase of x + i y (mean removed)
    advances steadily by ten turns or more."""
    z = (x - np.mean(x)) + 1j * (y - np.mean(y))
    if t.size < 16 or not np.any(np.abs(z) > 0):
        return False
    th = np.unwrap(np.angle(z))
    turns = abs(th[-1] - th[0]) / TWO_PI
    steps = np.diff(th)
    return bool(turns >= 10 and np.mean(np.sign(steps) == np.sign(th[-1] - th[0])) > 0.9)


def _line_1x(t, z, out, notes) -> None:
    """No phase reference: the 1X line's frequency and amplitude from the spectrum
    (:func:`dsp.frequency.refine_frequencies`, the strongest forward line)."""
    from dsp.lines import refine_frequencies

    try:
        comp = refine_frequencies(t, z - np.mean(z), 1)
        f = float(comp.frequency_hz[0])
        out["speed_hz"] = abs(f)
        out["response_1x_m"] = float(abs(comp.amplitude[0]))
        out["speed_estimated"] = True
        notes.append(f"no keyphasor or encoder: the speed {abs(f):.6g} rev/s is the strongest line "
                     "of the orbit (estimated from the vibration)")
    except SignalError as exc:
        notes.append(f"1X line: {exc}")


def _unbalance(out, scene, sc1, d, rmap, mass, grade_mm_s, service_speed_rpm, notes) -> None:
    """The unbalance from the model (the scene's, the run-up fit's, or the map's f0 and
    damping), the ring zones of a track, and the ISO 21940-11 grade."""
    from dsp import unbalance as ub

    e = se = ang = None       # specific unbalance [m] and its angle [deg]
    how = None
    fit = (out.get("runup") or {}).get("model_fit")
    if scene is not None and sc1 is not None:
        s = scene.supports
        Ms = scene.total_mass
        zeta = s.damping_x / (2 * math.sqrt(s.stiffness_x * Ms))
        est = ub.unbalance_from_response(sc1, sc1.speed_rad_s, Ms, scene.natural_frequency / TWO_PI,
                                         zeta)
        out.update(unbalance_gmm=est.unbalance_gmm, unbalance_gmm_std=est.unbalance_std_gmm,
                   unbalance_angle_deg=est.angle_deg)
        _grade(out, est.unbalance_gmm, est.unbalance_std_gmm, scene.rotor.mass,
               sc1.speed_rad_s, grade_mm_s, service_speed_rpm)
        return
    if fit is not None:
        e, se, ang = fit["specific_unbalance_m"], fit["specific_unbalance_m_std"], \
            fit["unbalance_angle_deg"]
        how = "rigid-rotor model fitted to the run-up"
    elif sc1 is not None and rmap is not None and rmap.natural_frequency_hz \
            and rmap.damping_ratio is not None:
        est = ub.unbalance_from_response(sc1, sc1.speed_rad_s, 1.0, rmap.natural_frequency_hz,
                                         rmap.damping_ratio)
        e, se, ang = est.unbalance_kg_m, est.unbalance_std_kg_m, est.angle_deg
        how = f"steady 1X with the map's natural frequency and damping ({rmap.source})"
    elif out.get("response_1x_m") and rmap is not None and rmap.natural_frequency_hz \
            and rmap.damping_ratio is not None:
        R = out["speed_hz"] / rmap.natural_frequency_hz
        e = out["response_1x_m"] * abs(1 - R * R + 2j * rmap.damping_ratio * R) / (R * R)
        how = f"1X line with the map's natural frequency and damping ({rmap.source})"
    rings = _ring_reading(out, d)
    if e is None and rings is None:
        if d.get("table") is not None:
            notes.append("unbalance: a table has no scene (mass, f0, damping); it needs a run-up "
                         "through the resonance (model fit), or the "
                         "natural frequency and damping ratio in the map's [rotor], or a track "
                         "with ring radii and the capacity")
        else:
            notes.append("no scene in the recording: the 1X response is not converted to an "
                         "unbalance (needs mass, f0, damping)")
        return
    if e is not None:
        out["specific_unbalance_gmm_per_kg"] = e * 1e6       # [m] = [kg m / kg] -> g mm / kg
        out["specific_unbalance_gmm_per_kg_std"] = None if se is None else se * 1e6
        out["unbalance_method"] = how
        out["unbalance_angle_deg"] = ang
        if mass:
            out.update(unbalance_gmm=e * mass * 1e6,
                       unbalance_gmm_std=None if se is None else se * mass * 1e6)
        else:
            notes.append("unbalance in g mm needs the vibrating mass: give [rotor] mass in the "
                         "recording map (the specific unbalance per kg is given)")
    w_meas = (out.get("speed_hz") or 0.0) * TWO_PI
    if rmap is not None and rmap.service_speed_rad_s and not service_speed_rpm:
        service_speed_rpm = rmap.service_speed_rad_s * 60 / TWO_PI
    if e is not None and (w_meas > 0 or service_speed_rpm):
        _grade(out, e * (mass or 1.0) * 1e6, None if se is None else se * (mass or 1.0) * 1e6,
               mass or 1.0, w_meas, grade_mm_s, service_speed_rpm, per_kg=not mass)


def _grade(out, U_gmm, sU_gmm, mass, w_meas, grade_mm_s, service_speed_rpm, per_kg=False) -> None:
    from dsp import unbalance as ub

    w_service = service_speed_rpm * TWO_PI / 60.0 if service_speed_rpm else w_meas
    g = ub.iso_21940_grade(U_gmm, mass, w_service, target_grade_mm_s=grade_mm_s,
                           unbalance_std_gmm=sU_gmm)
    out["iso_grade"] = {"grade_mm_s": g.grade_mm_s, "grade_mm_s_std": g.grade_std_mm_s,
                        "class": g.label, "target_mm_s": grade_mm_s, "passed": g.passed,
                        "permissible_gmm": None if per_kg else getattr(g, "permissible_gmm", None),
                        "service_speed_rpm": w_service * 60 / TWO_PI}


def _ring_reading(out, d):
    """A ``stand track`` CSV with ring radii and the capacity in its header: the spot
    circle's radius on the screen read against the rings (the lab's laser method, 4.3)."""
    from dsp.unbalance import unbalance_from_rings

    tab = d.get("table")
    if tab is None or out.get("response_1x_m") is None:
        return None
    meta = tab.metadata
    try:
        radii = [float(v) for v in str(meta["ring_radii_m"]).split(",")]
        S = float(meta["capacity_gmm"]) * 1e-6
        gain = float(meta.get("optical_gain", 1.0))
    except (KeyError, ValueError):
        return None
    r_screen = out["response_1x_m"] * gain
    rd = unbalance_from_rings(r_screen, radii, S)
    out["ring_reading"] = {"circle_radius_mm": r_screen * 1e3, "zone": rd.zone,
                           "unbalance_gmm": rd.unbalance_gmm, "unbalance_gmm_std": rd.unbalance_std_gmm,
                           "interpolated_gmm": rd.interpolated_kg_m * 1e6, "off_scale": rd.off_scale}
    if out.get("unbalance_gmm") is None:
        out.update(unbalance_gmm=rd.interpolated_kg_m * 1e6, unbalance_gmm_std=rd.unbalance_std_gmm,
                   unbalance_method="spot circle against the calibration rings (zone i -> i S/16)")
    return rd


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


# ------------------------------------------------------------ two-plane balancing
def _track_of(path, rec):
    """``(name, axial position [m], t [s], x [m], y [m], frame rotor angle [rad] or None)``
    of one ``stand track --screen`` CSV; the position from the recording's screen attrs."""
    from stand.lab.table import read_frame

    df, _ = read_frame(path)
    for col in ("t_s", "x_m", "y_m"):
        if col not in df:
            raise ValueError(f"{path}: missing column {col!r}: track each screen of the recording "
                             "with `stand track RUN.h5 --screen NAME -o NAME.csv`")
    name = str(df["screen"].iloc[0]) if "screen" in df and len(df) else ""
    d = None
    if name and getattr(rec, "path", None):
        a = rec.dataset_attrs(f"instruments/{name}")
        if "axial_position_m" in a:
            d = float(a["axial_position_m"])
    if d is None and "axial_position_m" in df:
        d = float(df["axial_position_m"].iloc[0])
    if d is None or not math.isfinite(d):
        raise ValueError(f"{path}: the screen's axial position is unknown (neither the "
                         f"recording's instruments/{name or '<screen>'} attrs nor the track say it)")
    ok = df["ok"].to_numpy(bool) if "ok" in df else np.ones(len(df), bool)
    phi = df["rotor_angle_rad"].to_numpy(float)[ok] if "rotor_angle_rad" in df else None
    return (name or Path(path).stem, d, df["t_s"].to_numpy(float)[ok],
            df["x_m"].to_numpy(float)[ok], df["y_m"].to_numpy(float)[ok], phi)


def _correction_planes(scene):
    """``[(plane name, axial position [m])]``: the balancer planes of a spatial rotor."""
    params = dict(getattr(scene.structure, "params", {}) or {})
    pos = params.get("balancer_positions", ())
    pos = list(pos) if isinstance(pos, (list, tuple)) else [pos]
    if len(pos) != 2:
        raise ValueError(f"two-plane balancing needs two correction planes: the scene's "
                         f"structure.balancer_positions = {pos!r} (m) gives {len(pos)}")
    return [(f"balancer{k}", float(a)) for k, a in enumerate(pos, start=1)]


def _forward(XY) -> complex:
    """The forward (x + i y) phasor of a plane's complex amplitudes (X, Y)."""
    return complex(0.5 * (XY[0] + 1j * XY[1]))


def two_plane(path, tracks, grade_mm_s: float = 6.3, service_speed_rpm: float | None = None) -> dict:
    """Two-plane unbalances from two laser screens (monograph 4.3, (4.2)-(4.3); paper 003).

    ``tracks``: two CSVs of ``stand track RUN.h5 --screen NAME`` (spots turned into the
    axis point each screen shows).  Chain: each screen's synchronous phasor in the rotor
    frame (:func:`dsp.two_plane.rotor_frame_phasor`, the recording's rotor angle at each
    frame's mid-exposure) -> the axis line through the two points (4.2) -> its points in
    the two correction planes (the scene's balancer planes) -> the unbalances there from
    the model's receptance (the scene's LinearRotor with its weights locked, at the
    measured speed; :func:`dsp.two_plane.two_plane_unbalances`).  Uncertainties: the
    frames' scatter, propagated linearly (the model is taken as exact).  With the
    ISO 21940-11 permissible residual of ``grade_mm_s`` split between the planes
    (:func:`dsp.two_plane.iso_two_plane_allocation`) and, when the scene has unbalances,
    the truth (the rotor's unbalances moved onto the correction planes by statics).
    """
    from dsp import two_plane as tp
    from dsp.unbalance import iso_21940_permissible

    from stand.recording.hdf5 import read_recording
    from stand.model.rotors.coupled import with_locked_weights

    if len(tracks) != 2:
        raise ValueError(f"--tracks: two screens' tracks, got {len(tracks)}")
    rec = read_recording(path)
    scene = rec.scene
    if scene is None or getattr(scene, "kind", None) != "rotor":
        raise ValueError(f"{path}: two-plane balancing needs the recording's rotor-family scene "
                         "([structure] with two balancer planes)")
    planes = _correction_planes(scene)
    phi_rec = np.unwrap(np.asarray(rec.rotor_angle, float))
    t_rec = np.asarray(rec.t, float)
    screens, Z, sZ, speeds = [], [], [], []
    for p in tracks:
        name, d, t, x, y, phi0 = _track_of(p, rec)
        phi = np.interp(t, t_rec, phi_rec) if np.all(np.isfinite(phi_rec)) else phi0
        if phi is None:
            raise ValueError(f"{p}: no rotor angle (the recording has none and the track has no "
                             "rotor_angle_rad column)")
        w = float(np.median(np.interp(t, t_rec, np.gradient(phi_rec, t_rec))))
        import json

        try:
            exposure = float(json.loads(rec.dataset_attrs(f"instruments/{name}")
                                        .get("settings", "{}")).get("exposure", 0.0))
        except (TypeError, ValueError):
            exposure = 0.0
        z, se = tp.rotor_frame_phasor(x, y, phi, blur_angle=w * exposure)
        screens.append({"screen": name, "track": str(p), "axial_position_m": d, "frames": int(t.size),
                        "amplitude_m": abs(z), "amplitude_m_std": se,
                        "angle_deg": math.degrees(math.atan2(z.imag, z.real))})
        Z.append(z)
        sZ.append(se)
        speeds.append(w)
    (d1, d2) = (s["axial_position_m"] for s in screens)
    omega = float(np.mean(speeds))
    (a1, a2) = (a for _, a in planes)
    L = np.array([[(d2 - a) / (d2 - d1), (a - d1) / (d2 - d1)] for a in (a1, a2)])  # (4.2)
    P = tp.shaft_axis_points(Z[0], d1, Z[1], d2, [a1, a2])
    rotor = with_locked_weights(scene.linear_rotor(), scene.weights, scene.bodies)
    H = np.array([[_forward(rotor.unbalance_response(omega, pj, at=pi)) for pj, _ in planes]
                  for pi, _ in planes])
    U = tp.two_plane_unbalances(P, H)
    sU = tp.propagate(np.linalg.solve(H, L), sZ)
    # truth: the rotor's unbalances, statically equivalent in the correction planes
    truth = None
    if rotor.unbalances:
        F = np.column_stack([rotor.force_map(pj).T @ np.array([1.0, -1j]) for pj, _ in planes])
        f = sum(u.s * np.exp(1j * u.angle) * (rotor.force_map(u.plane).T @ np.array([1.0, -1j]))
                for u in rotor.unbalances)
        truth = np.linalg.lstsq(F, f, rcond=None)[0]
    w_service = service_speed_rpm * TWO_PI / 60.0 if service_speed_rpm else omega
    mass = float(rotor.M[0, 0])     # x first (rigid rotors): the mass, locked weights included
    U_per = iso_21940_permissible(grade_mm_s, mass, w_service)
    per = tp.iso_two_plane_allocation(U_per, a1, a2)
    out_planes = []
    for k, ((name, a), u, su, up) in enumerate(zip(planes, U, sU, per)):
        row = {"plane": name, "axial_position_m": a,
               "unbalance_gmm": abs(u) * 1e6, "unbalance_gmm_std": float(su) * 1e6,
               "angle_deg": math.degrees(math.atan2(u.imag, u.real)) % 360.0,
               "angle_deg_std": math.degrees(float(su) / abs(u)) if abs(u) > 0 else None,
               "correction_angle_deg": (math.degrees(math.atan2(u.imag, u.real)) + 180.0) % 360.0,
               "permissible_gmm": up, "passed": bool(abs(u) * 1e6 <= up),
               "passed_with_uncertainty": bool((abs(u) + 2 * su) * 1e6 <= up)}
        if truth is not None:
            tr = truth[k]
            row.update(truth_gmm=abs(tr) * 1e6,
                       truth_angle_deg=math.degrees(math.atan2(tr.imag, tr.real)) % 360.0,
                       error_percent=100.0 * abs(abs(u) - abs(tr)) / abs(tr) if abs(tr) else None,
                       vector_error_percent=100.0 * abs(u - tr) / abs(tr) if abs(tr) else None)
        out_planes.append(row)
    return {"recording": str(path), "method": "two laser screens -> axis line (4.2) -> correction "
            "planes (4.3) -> unbalances through the model's receptance (weights locked)",
            "speed_hz": omega / TWO_PI, "screens": screens, "planes": out_planes,
            "iso_21940_11": {"grade_mm_s": grade_mm_s, "service_speed_rpm": w_service * 60 / TWO_PI,
                             "rotor_mass_kg": mass, "permissible_gmm": U_per,
                             "allocation": "lever rule about the centre of mass over the correction "
                                           "planes' distances, each plane within 30-70 % (ISO 21940-11 7.3)",
                             "passed": all(r["passed"] for r in out_planes)},
            "notes": ["uncertainties: the frames' scatter only (the receptance is the scene's model)"]}
