"""``stand analyze``: the numbers a lab writes in its journal, from one recording.

Orchestrates the leaf package :mod:`dsp` on a recording (HDF5 written by
``stand run`` or by another tool, or a CSV of time and signals) and, when the
recording carries its scene, uses the scene for the model parameters (mass,
natural frequency, damping) that turn a 1X response into an unbalance.

CSV columns (header line required; SI units): ``t_s``, ``x_m``, ``y_m`` and
optionally ``rotor_angle_rad`` (unwrapped or wrapped) or ``keyphasor``
(1 on the samples where a once-per-revolution pulse occurs).
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from dsp.errors import SignalError

TWO_PI = 2 * math.pi


def _read(path):
    from .recording import read_recording
    from .result import Run

    if isinstance(path, Run):
        return _from_run(path)
    p = Path(path)
    if p.suffix.lower() == ".csv":
        import pandas as pd

        try:
            df = pd.read_csv(p)
        except Exception as exc:  # parse errors of any kind -> one clear line
            reason = " ".join(str(exc).split())  # pandas messages hold newlines
            raise ValueError(f"{p}: not a readable CSV ({reason})") from None
        for col in ("t_s", "x_m", "y_m"):
            if col not in df:
                raise ValueError(f"{p}: missing column {col!r} (need t_s, x_m, y_m; optional "
                                 "rotor_angle_rad or keyphasor)")

        def column(col, unit):
            """A numeric column; text in a number cell is an error naming file, column, row."""
            raw = df[col]
            num = pd.to_numeric(raw, errors="coerce")
            bad = np.flatnonzero((num.isna() & raw.notna()).to_numpy())
            if bad.size:
                i = int(bad[0])
                raise ValueError(f"{p}: column {col!r} ({unit}), data row {i + 1}: "
                                 f"{str(raw.iloc[i])[:40]!r} is not a number")
            return num.to_numpy(float)

        t = column("t_s", "s")
        phi = column("rotor_angle_rad", "rad") if "rotor_angle_rad" in df else None
        kp = None
        if phi is None and "keyphasor" in df:
            kp = t[column("keyphasor", "1 on a once-per-revolution pulse, else 0") > 0.5]
        return dict(t=t, x=column("x_m", "m"), y=column("y_m", "m"), phi=phi,
                    kp=kp, weights=None, scene=None)
    return _from_run(read_recording(p))


def _from_run(rec):
    """The arrays of a Run or Recording; the scene only where the model parts apply (the
    planar rotor of chapter 5)."""
    scene = rec.scene if getattr(rec.scene, "kind", None) == "planar" else None
    phi = rec.rotor_angle if np.all(np.isfinite(rec.rotor_angle)) else None
    w = rec.weight_angle if rec.weight_angle.size and np.all(np.isfinite(rec.weight_angle)) else None
    return dict(t=np.asarray(rec.t), x=np.asarray(rec.x), y=np.asarray(rec.y), phi=phi, kp=None,
                weights=w, scene=scene, notes=list(rec.notes))


def _steady_window(t, speed, frac=0.3):
    """Indices of the final stretch where the speed is constant (within 0.1 %), at most the
    last ``frac`` of the record."""
    from .signals import steady_start

    n = t.size
    return slice(max(int(n * (1 - frac)), steady_start(t, speed)), n)


def analyze(path, grade_mm_s: float = 6.3, service_speed_rpm: float | None = None) -> dict:
    """Identify what a lab would from one recording; returns a JSON-able dict.

    Every identification that does not apply (e.g. no rotation, no weights
    channel) is ``None`` with the reason in ``notes``.
    """
    from dsp import quasiperiodic as qpd
    from dsp import regime as rg
    from dsp import unbalance as ub

    from .signals import plane_free_decay

    d = _read(path)
    t, x, y, phi, scene = d["t"], d["x"], d["y"], d["phi"], d["scene"]
    if t.size < 2:  # np.gradient of the rotor angle needs two samples
        raise ValueError(f"{path}: {t.size} sample(s) in time (s); stand analyze needs at least 2")
    label = getattr(path, "path", None) or (f"<run of {path.scene.name}>"
                                            if hasattr(path, "scene") else str(path))
    out = {"recording": str(label), "notes": list(d.get("notes") or [])}
    notes = out["notes"]
    speed = None
    if phi is not None:
        speed = np.gradient(np.unwrap(phi), t)
    rotating = speed is not None and np.max(np.abs(speed)) > 1e-6 or d["kp"] is not None

    # natural frequency and damping: free decay of a non-spinning rotor
    out.update(natural_frequency_hz=None, natural_frequency_hz_std=None, damping_ratio=None,
               damping_ratio_std=None)
    if not rotating:
        fd = plane_free_decay(t, x, y, notes)
        if fd is not None:
            out.update(natural_frequency_hz=fd.natural_frequency_hz,
                       natural_frequency_hz_std=fd.natural_frequency_hz_std,
                       damping_ratio=fd.damping_ratio, damping_ratio_std=fd.damping_ratio_std)
    elif scene is not None:
        notes.append("rotating record: f0 and damping taken from the scene, not identified")

    # 1X and unbalance over the final constant-speed stretch
    out.update(unbalance_gmm=None, unbalance_gmm_std=None, unbalance_angle_deg=None,
               iso_grade=None, response_1x_m=None, speed_hz=None)
    sl = _steady_window(t, speed)
    if rotating:
        try:
            sc1 = ub.synchronous_component(t[sl], x[sl], y[sl],
                                           rotor_angle=None if phi is None else phi[sl],
                                           keyphasor_times=d["kp"])
            out["response_1x_m"] = sc1.amplitude_m
            out["speed_hz"] = sc1.speed_rad_s / TWO_PI
            if scene is not None:
                s = scene.supports
                Ms = scene.total_mass
                f0 = scene.natural_frequency / TWO_PI
                zeta = s.damping_x / (2 * math.sqrt(s.stiffness_x * Ms))
                est = ub.unbalance_from_response(sc1, sc1.speed_rad_s, Ms, f0, zeta)
                out.update(unbalance_gmm=est.unbalance_gmm, unbalance_gmm_std=est.unbalance_std_gmm,
                           unbalance_angle_deg=est.angle_deg)
                w_service = (service_speed_rpm * TWO_PI / 60.0 if service_speed_rpm
                             else sc1.speed_rad_s)
                g = ub.iso_21940_grade(est.unbalance_gmm, scene.rotor.mass, w_service,
                                       target_grade_mm_s=grade_mm_s,
                                       unbalance_std_gmm=est.unbalance_std_gmm)
                out["iso_grade"] = {"grade_mm_s": g.grade_mm_s, "grade_mm_s_std": g.grade_std_mm_s,
                                    "class": g.label, "target_mm_s": grade_mm_s,
                                    "passed": g.passed, "permissible_gmm": getattr(g, "permissible_gmm", None),
                                    "service_speed_rpm": w_service * 60 / TWO_PI}
            else:
                notes.append("no scene in the recording: the 1X response is not converted to an "
                             "unbalance (needs mass, f0, damping)")
        except SignalError as exc:
            notes.append(f"1X / unbalance: {exc}")

    # quasi-periodic decomposition of the orbit
    out.update(components=[], precession_hz=None, nutation_hz=None, petals=None, shape=None)
    if rotating:
        try:
            f_rot = out["speed_hz"]
            dec = qpd.decompose(t[sl], (x + 1j * y)[sl], rotor_speed_hz=f_rot)
            out["components"] = [{"frequency_hz": c.frequency_hz, "frequency_hz_std": c.frequency_std_hz,
                                  "amplitude_m": c.amplitude_m, "phase_deg": math.degrees(c.phase_rad),
                                  "direction": c.direction} for c in dec.components]
            out.update(precession_hz=dec.precession_hz, precession_hz_std=dec.precession_std_hz,
                       nutation_hz=dec.nutation_hz, nutation_hz_std=dec.nutation_std_hz,
                       precession_amplitude_m=dec.precession_amplitude_m,
                       nutation_amplitude_m=dec.nutation_amplitude_m,
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


# ------------------------------------------------------------ two-plane balancing
def _track_of(path, rec):
    """``(name, axial position [m], t [s], x [m], y [m], frame rotor angle [rad] or None)``
    of one ``stand track --screen`` CSV; the position from the recording's screen attrs."""
    import pandas as pd

    df = pd.read_csv(path)
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

    from .recording import read_recording
    from .rotors.coupled import with_locked_weights

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
