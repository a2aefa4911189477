"""Two-plane balancing from two laser screens (``stand analyze RUN.h5 --tracks A.csv B.csv``).

Monograph 4.3, (4.2)-(4.3); paper 003: each screen's synchronous phasor in the rotor
frame, the shaft axis through the two screens' points, its points in the two
correction planes, and the unbalances there through the model's receptance
(:func:`two_plane`).
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

__all__ = ["two_plane"]

TWO_PI = 2 * math.pi


def _track_of(path, rec):
    """``(name, axial position [m], t [s], x [m], y [m], frame rotor angle [rad] or None)``
    of one ``stand track --screen`` CSV; the position from the recording's screen attrs."""
    from stand.lab.table import read_frame
    from stand.recording.layout import instrument_key

    df, _ = read_frame(path)
    for col in ("t_s", "x_m", "y_m"):
        if col not in df:
            raise ValueError(f"{path}: missing column {col!r}: track each screen of the recording "
                             "with `stand track RUN.h5 --screen NAME -o NAME.csv`")
    name = str(df["screen"].iloc[0]) if "screen" in df and len(df) else ""
    d = None
    if name and getattr(rec, "path", None):
        a = rec.dataset_attrs(instrument_key(name))
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


def two_plane(path, tracks, grade: float = 6.3, service_speed_rpm: float | None = None, *,
              grade_mm_s: float | None = None):
    """Two-plane unbalances from two laser screens (monograph 4.3, (4.2)-(4.3); paper 003).

    ``tracks``: two CSVs of ``stand track RUN.h5 --screen NAME`` (spots turned into the
    axis point each screen shows).  Chain: each screen's synchronous phasor in the rotor
    frame (:func:`dsp.two_plane.rotor_frame_phasor`, the recording's rotor angle at each
    frame's mid-exposure) -> the axis line through the two points (4.2) -> its points in
    the two correction planes (the scene's balancer planes) -> the unbalances there from
    the model's receptance (the scene's LinearRotor with its weights locked, at the
    measured speed; :func:`dsp.two_plane.two_plane_unbalances`).  Uncertainties: the
    frames' scatter, propagated linearly (the model is taken as exact).  With the
    ISO 21940-11 permissible residual of ``grade`` G [mm/s] split between the planes
    (:func:`dsp.two_plane.iso_two_plane_allocation`) and, when the scene has unbalances,
    the truth (the rotor's unbalances moved onto the correction planes by statics).
    ``grade_mm_s``: the old name of ``grade`` (deprecated).

    Returns
    -------
    stand.analysis.results.TwoPlane
        The document of ``stand analyze --tracks --json`` (``planes``, ``screens``,
        ``iso_21940_11``, ...); ``to_frame()`` one row per correction plane.
    """
    from stand.io.result import renamed

    grade = renamed(grade, grade_mm_s, "grade_mm_s", "grade", "two_plane")
    from dsp import two_plane as tp
    from dsp.unbalance import iso_21940_permissible

    from stand.recording.hdf5 import read_recording
    from stand.recording.layout import instrument_key
    from stand.integrate.coupled import with_locked_weights

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
            exposure = float(json.loads(rec.dataset_attrs(instrument_key(name))
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
    U_per = iso_21940_permissible(grade, mass, w_service)
    per = tp.iso_two_plane_allocation(U_per, a1, a2)
    out_planes = []
    for k, ((name, a), u, su, up) in enumerate(zip(planes, U, sU, per)):
        row = {"plane": name, "axial_position_m": a,
               "unbalance_gmm": abs(u) * 1e6, "unbalance_gmm_std": float(su) * 1e6,
               "angle_deg": math.degrees(math.atan2(u.imag, u.real)) % 360.0,
               "angle_deg_std": math.degrees(float(su) / abs(u)) if abs(u) > 0 else None,
               "correction_angle_deg": (math.degrees(math.atan2(u.imag, u.real)) + 180.0) % 360.0,
               "correction_angle_deg_std": math.degrees(float(su) / abs(u)) if abs(u) > 0 else None,
               "permissible_gmm": up, "passed": bool(abs(u) * 1e6 <= up),
               "passed_with_uncertainty": bool((abs(u) + 2 * su) * 1e6 <= up)}
        if truth is not None:
            tr = truth[k]
            row.update(truth_gmm=abs(tr) * 1e6,
                       truth_angle_deg=math.degrees(math.atan2(tr.imag, tr.real)) % 360.0,
                       error_percent=100.0 * abs(abs(u) - abs(tr)) / abs(tr) if abs(tr) else None,
                       vector_error_percent=100.0 * abs(u - tr) / abs(tr) if abs(tr) else None)
        out_planes.append(row)
    from stand.analysis.results import TwoPlane

    doc = {"recording": str(path),
           "method": "two laser screens -> axis line (4.2) -> correction planes (4.3) -> "
                     "unbalances through the model's receptance (weights locked)",
           "speed_hz": omega / TWO_PI, "screens": screens, "planes": out_planes,
           "iso_21940_11": {"required_grade_mm_s": grade, "service_speed_rpm": w_service * 60 / TWO_PI,
                            "rotor_mass_kg": mass, "permissible_gmm": U_per,
                            "allocation": "lever rule about the centre of mass over the correction "
                                          "planes' distances, each plane within 30-70 % (ISO 21940-11 7.3)",
                            "passed": all(r["passed"] for r in out_planes)},
           "notes": ["uncertainties: the frames' scatter only (the receptance is the scene's model)"]}
    return TwoPlane(doc)
