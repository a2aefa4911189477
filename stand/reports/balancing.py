"""Balancing-quality report (``stand report``): one recording -> JSON + self-contained HTML.

:func:`balancing_report` reads a recording (HDF5 written by ``stand run`` or a
compatible file, or a CSV with columns ``t_s, x_m, y_m`` and optionally
``rotor_angle_rad`` or ``keyphasor``, as ``stand analyze`` accepts) and
returns a JSON document (schema :data:`SCHEMA`, documented key by key with
units in ``docs/reports.md``):

* ``header`` -- scene, masses, balancer capacity S, speeds;
* ``balancing_quality`` -- initial and residual unbalance (g mm and ring zone
  i S/16), specific unbalance e (um), ISO 21940-11 permissible residual and
  achieved grade, pass/fail, reduction factor balancer-off / balancer-on, the
  seeds' household and general-machine criteria;
* ``dynamics`` -- natural frequency and damping (identified with their
  standard uncertainties when the record allows it, and the model's values),
  critical speeds found vs the theory (:func:`stand.planar_theory.speedmap.scene_theory`),
  the regime timeline, settling times after each perturbation;
* ``warnings`` -- capacity exceeded, stuck-ball risk band, friction-limited
  residual, model-validity flags;
* ``notes`` -- what could not be computed and why.

The HTML is rendered from the JSON by :func:`stand.reports.html.render_html`
(every number shown is in the JSON); the figures (matplotlib, Agg) show only
data read from the recording.
"""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from .html import check_schema, figure_png, jsonable, write_report

__all__ = ["balancing_report", "SCHEMA", "REGIME_NAMES", "FORMAT_VERSION"]

TWO_PI = 2.0 * math.pi
FORMAT_VERSION = 1
#: dsp.regime names -> the names used in the report
REGIME_NAMES = {"main": "balanced", "side": "side", "quasi-periodic": "stuck",
                "transient": "transient"}

N, S_, B, L, O = "number|null", "string|null", "bool|null", "list", "object|null"

#: required keys and types of the report (see docs/reports.md for units)
SCHEMA = {
    "report": {"kind": "string", "format_version": "number", "recording": "string",
               "input_format": "string", "generator": "string"},
    "header": {"scene_name": S_, "description": S_, "rotor_mass_kg": N, "total_mass_kg": N,
               "balancer_type": S_, "weights": N, "capacity_gmm": N,
               "rotor_unbalance_gmm": N, "e0": N, "duration_s": N, "samples": "number",
               "sample_rate_hz": N, "max_speed_hz": N, "final_speed_hz": N,
               "final_speed_rpm": N, "service_speed_rpm": N, "service_speed_source": S_},
    "balancing_quality": {
        "initial_unbalance_gmm": N, "initial_unbalance_source": S_, "initial_zone": N,
        "residual_unbalance_gmm": N, "residual_unbalance_gmm_std": N,
        "residual_unbalance_angle_deg": N, "residual_fraction_of_capacity": N,
        "residual_zone": N, "residual_zone_label": S_, "residual_window_s": L,
        "residual_speed_hz": N, "response_1x_m": N, "response_1x_m_std": N,
        "specific_unbalance_um": N, "specific_unbalance_um_std": N,
        "iso_21940_11": {"grade_mm_s": "number", "service_speed_rpm": N,
                         "permissible_residual_gmm": N, "permissible_specific_unbalance_um": N,
                         "achieved_grade_mm_s": N, "achieved_grade_mm_s_std": N,
                         "achieved_class": S_, "passed": B},
        "reduction": {"applicable": "bool", "basis": "string", "factor": N,
                      "factor_lower_bound": N, "percent": N, "decibel": N},
        "seed_criteria": L,
        "ring_reading": O,
        "truth_residual_unbalance_gmm": N,
    },
    "dynamics": {
        "natural_frequency": {"identified_hz": N, "identified_hz_std": N, "damping_ratio": N,
                              "damping_ratio_std": N, "method": S_, "model_hz": N,
                              "model_damping_ratio": N},
        "theory_available": "bool",
        "critical_speeds": L,
        "final_regime": S_,
        "regime_timeline": L,
        "settling": L,
    },
    "warnings": L,
    "notes": L,
}

SECTIONS = ("report", "header", "balancing_quality", "dynamics", "warnings", "notes")


# ------------------------------------------------------------------ reading
def _read_csv(p: Path) -> dict:
    import pandas as pd

    try:
        df = pd.read_csv(p)
    except Exception as exc:  # any parse error -> one clear line
        raise ValueError(f"{p}: not a readable CSV ({type(exc).__name__}: {exc})") from None
    for col in ("t_s", "x_m", "y_m"):
        if col not in df:
            raise ValueError(f"{p}: missing column {col!r} (need t_s, x_m, y_m; optional "
                             "rotor_angle_rad or keyphasor)")
    try:
        t = df["t_s"].to_numpy(float)
        x = df["x_m"].to_numpy(float)
        y = df["y_m"].to_numpy(float)
        phi = df["rotor_angle_rad"].to_numpy(float) if "rotor_angle_rad" in df else None
        kp = t[df["keyphasor"].to_numpy(float) > 0.5] if ("keyphasor" in df and phi is None) \
            else None
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{p}: non-numeric values in a column ({exc})") from None
    for name, a in (("t_s", t), ("x_m", x), ("y_m", y)):
        if a.size < 3 or not np.all(np.isfinite(a)):
            raise ValueError(f"{p}: column {name!r} needs at least 3 finite values")
    if np.any(np.diff(t) <= 0):
        raise ValueError(f"{p}: column 't_s' must be strictly increasing")
    if phi is not None and not np.all(np.isfinite(phi)):
        raise ValueError(f"{p}: column 'rotor_angle_rad' has NaN or inf values")
    if phi is None and kp is not None and kp.size >= 2:
        # rotor angle from the once-per-revolution pulses (linear between pulses)
        k = np.arange(kp.size) * TWO_PI
        inside = (t >= kp[0]) & (t <= kp[-1])
        phi_k = np.interp(t, kp, k)
        t, x, y, phi = t[inside], x[inside], y[inside], phi_k[inside]
    return dict(t=t, x=x, y=y, phi=phi, weights=None, scene=None, scene_error=None,
                attrs={}, notes=[], solver={}, inst={}, truth={}, fmt="csv")


def _read_h5(p: Path) -> dict:
    from ..recording import read_recording

    rec = read_recording(p)  # RecordingError (a ValueError) names file and dataset
    scene, scene_error = rec.scene, None
    if scene is None and rec.scene_text.strip():
        scene_error = next((n for n in rec.notes if "stored scene" in n), "scene not readable")
    elif scene is not None and scene.kind != "planar":
        scene_error = (f"the recorded scene's structure is {scene.structure_type}: the model-based "
                       "parts (chapter-5 planar rotor) are skipped")
        scene = None
    phi = np.asarray(rec.rotor_angle) if np.all(np.isfinite(rec.rotor_angle)) else None
    wa = np.asarray(rec.weight_angle)
    weights = wa if wa.size and np.all(np.isfinite(wa)) else None
    rel = np.asarray(rec.relative_angle) if weights is not None else None
    inst, truth = {}, {}
    if rec.shape("instruments/screen/ring_radius") is not None:
        inst["ring_radius"] = np.asarray(rec.dataset("instruments/screen/ring_radius"), float)
        attrs = rec.dataset_attrs("instruments/screen")
        try:
            inst["screen_settings"] = json.loads(attrs.get("settings", "{}"))
        except (TypeError, ValueError):
            inst["screen_settings"] = {}
        ts = attrs.get("ring_test_speed_rad_s", None)
        inst["ring_test_speed_rad_s"] = None if ts is None else float(ts)
    for key, name in (("instruments/screen/frames", "screen"),
                      ("instruments/stroboscope/frames", "strobe")):
        shape = rec.shape(key)
        if shape is not None and len(shape) == 3 and shape[0] > 0:
            inst[name + "_frame"] = np.asarray(rec.dataset(key, shape[0] - 1))
    shape = rec.shape("truth/residual_unbalance")
    if shape is not None and len(shape) == 2 and shape[0] == rec.t.size:
        truth["residual_unbalance"] = np.asarray(rec.dataset("truth/residual_unbalance"), float)
    return dict(t=np.asarray(rec.t), x=np.asarray(rec.x), y=np.asarray(rec.y), phi=phi,
                weights=weights, rel=rel, scene=scene, scene_error=scene_error,
                attrs=rec.attrs, notes=list(rec.notes), solver=rec.solver, inst=inst,
                truth=truth, fmt="hdf5")


def _read(path) -> dict:
    p = Path(path)
    if not p.exists():
        raise FileNotFoundError(2, "recording not found", str(p))
    if p.is_dir():
        raise ValueError(f"{p}: is a directory, not a recording")
    d = _read_csv(p) if p.suffix.lower() == ".csv" else _read_h5(p)
    t, x, y = d["t"], d["x"], d["y"]
    if t.size < 3:
        raise ValueError(f"{p}: 'time' has {t.size} samples; at least 3 are needed")
    for name, a in (("time", t), ("shaft/x", x), ("shaft/y", y)):
        if not np.all(np.isfinite(a)):
            raise ValueError(f"{p}: dataset {name!r} contains NaN or inf")
    if np.any(np.diff(t) <= 0):
        raise ValueError(f"{p}: dataset 'time' must be strictly increasing")
    return d


# ------------------------------------------------------------------ helpers
def _steady_stretch(t, speed):
    """Index of the start of the final stretch where the speed is constant (0.1 %)."""
    if speed is None:
        return 0
    ref = speed[-1]
    ok = np.abs(speed - ref) <= 1e-3 * max(abs(ref), 1e-12)
    i = t.size - 1
    while i > 0 and ok[i - 1]:
        i -= 1
    return i


def _forward_start(phi):
    """First index from which the rotor angle increases strictly to the end."""
    bad = np.nonzero(np.diff(phi) <= 0)[0]
    return 0 if bad.size == 0 else int(bad[-1] + 1)


def _zone(U_kg_m, S):
    if U_kg_m is None or not S or not math.isfinite(U_kg_m):
        return None
    return int(math.floor(U_kg_m / (S / 16.0) + 1e-9))


def _zone_label(i):
    if i is None:
        return None
    return f"zone {i}: between {i} S/16 and {i + 1} S/16"


def _per_revolution(t, x, y, phi):
    """Revolution mid-times, speeds [rad/s] and 1X vectors [m] (dsp order tracking)."""
    from dsp import unbalance as ub

    i0 = _forward_start(phi)
    if t.size - i0 < 8:
        return None
    sc = ub.synchronous_component(t[i0:], x[i0:], y[i0:], rotor_angle=phi[i0:], min_revolutions=2)
    ph = phi[i0:]
    j0 = math.ceil(ph[0] / TWO_PI - 1e-12)
    j1 = math.floor(ph[-1] / TWO_PI + 1e-12)
    tb = np.interp(TWO_PI * np.arange(j0, j1 + 1), ph, t[i0:])
    return 0.5 * (tb[1:] + tb[:-1]), TWO_PI / np.diff(tb), np.asarray(sc.per_revolution_m)


# ------------------------------------------------------------------ main
def balancing_report(recording_path, *, grade=6.3, service_speed_rpm=None, html_path=None,
                     json_path=None) -> dict:
    """Balancing-quality report of one recording; returns the JSON document (plain types).

    Parameters
    ----------
    recording_path : str or Path
        HDF5 recording (``stand run``) or CSV (``t_s, x_m, y_m`` [+ ``rotor_angle_rad`` or
        ``keyphasor``]).
    grade : float
        ISO 21940-11 balance quality grade G to check [mm/s] (default 6.3).
    service_speed_rpm : float, optional
        Maximum service speed [rpm]; default: the recording's final constant speed.
    html_path, json_path : path, optional
        Where to write the self-contained HTML and the JSON (atomically).

    Raises
    ------
    FileNotFoundError
        The recording does not exist.
    ValueError
        Unreadable input (not HDF5/CSV, missing dataset or column, NaN samples, ...): the
        message names the file and the field; bad ``grade`` / ``service_speed_rpm``.
    """
    grade = float(grade)
    if not (math.isfinite(grade) and grade > 0):
        raise ValueError(f"grade = {grade!r} mm/s: must be a finite number > 0")
    if service_speed_rpm is not None:
        service_speed_rpm = float(service_speed_rpm)
        if not (math.isfinite(service_speed_rpm) and service_speed_rpm > 0):
            raise ValueError(f"service_speed_rpm = {service_speed_rpm!r}: must be > 0 rpm")
    from .. import __version__

    d = _read(recording_path)
    notes: list = list(d["notes"])
    warnings: list = []

    def warn(code, message, severity="warning"):
        warnings.append({"code": code, "severity": severity, "message": message})

    t, x, y, phi, scene = d["t"], d["x"], d["y"], d["phi"], d["scene"]
    if d["scene_error"]:
        notes.append(f"scene not usable: {d['scene_error']}")
    speed = None
    if phi is not None:
        phi = np.unwrap(phi)
        speed = np.gradient(phi, t)
    rotating = speed is not None and float(np.max(np.abs(speed))) > 1e-6

    # ---------------- header
    S = scene.balancer.capacity if scene is not None else 0.0
    Ms = scene.total_mass if scene is not None else None
    name = d["attrs"].get("scene_name") or (scene.name if scene is not None else None)
    if not name:
        name = Path(recording_path).stem
    i_st = _steady_stretch(t, speed) if rotating else 0
    final_speed = float(np.mean(speed[i_st:])) if rotating else None
    steady_len = float(t[-1] - t[i_st]) if rotating else 0.0
    if service_speed_rpm is not None:
        w_service, sv_src = service_speed_rpm * TWO_PI / 60.0, "given"
    elif rotating and final_speed > 0:
        w_service, sv_src = final_speed, "final constant speed of the recording"
    else:
        w_service, sv_src = None, None
        notes.append("no rotation in the recording and no service speed given: the ISO grade "
                     "and the seeds' criteria are not evaluated")
    e0 = None
    if scene is not None and S > 0:
        e0 = scene.rotor.unbalance / S
    header = {
        "scene_name": str(name),
        "description": (_scene_description(scene) if scene is not None else None),
        "rotor_mass_kg": scene.rotor.mass if scene is not None else None,
        "total_mass_kg": Ms,
        "balancer_type": scene.balancer.type if scene is not None else None,
        "weights": scene.balancer.count if scene is not None else None,
        "capacity_gmm": S * 1e6 if scene is not None else None,
        "rotor_unbalance_gmm": scene.rotor.unbalance * 1e6 if scene is not None else None,
        "e0": e0,
        "duration_s": float(t[-1] - t[0]),
        "samples": int(t.size),
        "sample_rate_hz": float((t.size - 1) / (t[-1] - t[0])),
        "max_speed_hz": float(np.max(np.abs(speed))) / TWO_PI if rotating else None,
        "final_speed_hz": final_speed / TWO_PI if rotating else None,
        "final_speed_rpm": final_speed * 60 / TWO_PI if rotating else None,
        "service_speed_rpm": w_service * 60 / TWO_PI if w_service else None,
        "service_speed_source": sv_src,
    }
    if scene is None:
        notes.append("no scene in the recording: masses, capacity and the unbalance (which needs "
                     "mass, natural frequency and damping) are not available; the 1X response "
                     "is reported in metres")

    # ---------------- balancing quality
    bq, sc_res = _balancing_quality(d, scene, t, x, y, phi, speed, rotating, i_st, w_service,
                                    grade, notes, warn)

    # ---------------- dynamics
    dyn = _dynamics(d, scene, t, x, y, phi, speed, rotating, notes, warn)

    # ---------------- warnings from the scene's theory
    _scene_warnings(scene, d, bq, dyn, w_service, final_speed, steady_len, t, speed, warn, notes)

    doc = {
        "report": {"kind": "balancing-quality", "format_version": FORMAT_VERSION,
                   "recording": str(recording_path), "input_format": d["fmt"],
                   "generator": f"stand {__version__}"},
        "header": header,
        "balancing_quality": bq,
        "dynamics": dyn,
        "warnings": warnings,
        "notes": notes,
    }
    plain = jsonable(doc)
    problems = check_schema(plain, SCHEMA)
    if problems:  # pragma: no cover -- a bug here, not bad input
        raise RuntimeError("balancing report does not match its schema: " + "; ".join(problems))
    figures = None
    if html_path:
        figures = _figures(d, t, x, y, phi, speed, rotating, i_st, sc_res)
    return write_report(f"Balancing-quality report: {header['scene_name']}", plain,
                        html_path=html_path, json_path=json_path, figures=figures,
                        sections=SECTIONS)


def _scene_description(scene):
    try:
        import tomllib
    except ModuleNotFoundError:  # pragma: no cover -- Python < 3.11
        import tomli as tomllib
    try:
        return str(tomllib.loads(scene.text).get("scene", {}).get("description", "")) or None
    except Exception:  # noqa: BLE001
        return None


def _balancing_quality(d, scene, t, x, y, phi, speed, rotating, i_st, w_service, grade, notes,
                       warn):
    from dsp import unbalance as ub
    from dsp.errors import SignalError

    S = scene.balancer.capacity if scene is not None else 0.0
    bq = {k: None for k in SCHEMA["balancing_quality"]}
    bq["residual_window_s"] = []
    bq["seed_criteria"] = []
    m_iso = scene.total_mass if scene is not None else None
    iso = {"grade_mm_s": grade, "service_speed_rpm": w_service * 60 / TWO_PI if w_service else None,
           "permissible_residual_gmm": None, "permissible_specific_unbalance_um": None,
           "achieved_grade_mm_s": None, "achieved_grade_mm_s_std": None, "achieved_class": None,
           "passed": None}
    if w_service and m_iso:
        iso["permissible_residual_gmm"] = ub.iso_21940_permissible(grade, m_iso, w_service)
        iso["permissible_specific_unbalance_um"] = iso["permissible_residual_gmm"] / m_iso
    bq["iso_21940_11"] = iso
    red = {"applicable": False, "basis": "not evaluated: no residual unbalance identified", "factor": None, "factor_lower_bound": None,
           "percent": None, "decibel": None}
    bq["reduction"] = red

    # initial unbalance: the rotor's own (balancer off), from the scene
    if scene is not None:
        from ..planar import rotor_unbalance

        U0 = float(abs(rotor_unbalance(scene, np.array([t[0]]))[0]))
        bq["initial_unbalance_gmm"] = U0 * 1e6
        bq["initial_unbalance_source"] = ("scene: rotor's own unbalance M e at the start "
                                          "(balancer off)")
        bq["initial_zone"] = _zone(U0, S)

    # residual unbalance: 1X over the end of the final constant-speed stretch
    sc = None
    if not rotating:
        notes.append("the rotor does not turn: no 1X response, no residual unbalance")
        return bq, None
    if d["weights"] is not None and d["weights"].shape[1] and phi is not None:
        rel_end = np.diff(d["rel"][-2:], axis=0) if d.get("rel") is not None else None
        if rel_end is not None and np.any(np.abs(rel_end) > 1e-3 * abs(speed[-1]) * (t[-1] - t[-2])):
            notes.append("the weights still move relative to the rotor at the end of the record: "
                         "the residual unbalance varies in time and the 1X value is its mean "
                         "over the window (its standard uncertainty includes the variation)")
    n0 = i_st
    rev_s = TWO_PI / max(abs(speed[-1]), 1e-12)
    stretch = t[-1] - t[n0]
    if stretch < 2 * rev_s:
        notes.append("no constant-speed stretch of 2 revolutions at the end of the record: the "
                     "residual is evaluated over the last 30 % of the record")
        n0 = int(0.7 * t.size)
        stretch = t[-1] - t[n0]
    win = min(stretch, max(0.25 * stretch, 10 * rev_s))
    sel = t >= t[-1] - win
    try:
        sc = ub.synchronous_component(t[sel], x[sel], y[sel], rotor_angle=phi[sel])
    except SignalError as exc:
        notes.append(f"1X response: {exc}")
        return bq, None
    bq["residual_window_s"] = [sc.t_start, sc.t_end]
    bq["residual_speed_hz"] = sc.speed_rad_s / TWO_PI
    bq["response_1x_m"] = sc.amplitude_m
    bq["response_1x_m_std"] = sc.vector_std_m
    if scene is None:
        return bq, sc
    s = scene.supports
    Ms = scene.total_mass
    f0 = scene.natural_frequency / TWO_PI
    zeta = s.damping_x / (2 * math.sqrt(s.stiffness_x * Ms))
    try:
        est = ub.unbalance_from_response(sc, sc.speed_rad_s, Ms, f0, zeta)
    except (SignalError, ValueError) as exc:
        notes.append(f"unbalance from the 1X response: {exc}")
        return bq, sc
    U, sU = est.unbalance_kg_m, est.unbalance_std_kg_m
    bq.update(residual_unbalance_gmm=U * 1e6, residual_unbalance_gmm_std=sU * 1e6,
              residual_unbalance_angle_deg=est.angle_deg,
              residual_fraction_of_capacity=(U / S if S > 0 else None),
              specific_unbalance_um=U * 1e6 / m_iso, specific_unbalance_um_std=sU * 1e6 / m_iso)
    if S > 0:
        bq["residual_zone"] = _zone(U, S)
        bq["residual_zone_label"] = _zone_label(bq["residual_zone"])
    if w_service:
        g = ub.iso_21940_grade(U * 1e6, m_iso, w_service, target_grade_mm_s=grade,
                               unbalance_std_gmm=sU * 1e6)
        iso.update(achieved_grade_mm_s=g.grade_mm_s, achieved_grade_mm_s_std=g.grade_std_mm_s,
                   achieved_class=g.label, passed=g.passed)
        if not g.passed:
            warn("iso_grade_failed", f"the residual unbalance exceeds the permissible residual of "
                 f"the grade (G = {g.grade_mm_s:.4g} mm/s > {grade:g} mm/s)")
        n_rpm = w_service * 60 / TWO_PI
        e_um = U * 1e6 / m_iso
        from ..balancers.liquid_chamber import (permissible_eccentricity_general,
                                                permissible_eccentricity_household)
        for crit, fn, rel in (
                ("household (machines a person contacts): [e] = 6000/n um", 
                 permissible_eccentricity_household,
                 "washing machines, centrifuges, fans: any rotor a person touches"),
                ("general machine building (Reutlinger): [e] = 2e8/n^2 um",
                 permissible_eccentricity_general, "general machinery")):
            e_per = fn(n_rpm) * 1e6
            bq["seed_criteria"].append({"criterion": crit, "relevant_for": rel,
                                        "permissible_specific_unbalance_um": e_per,
                                        "specific_unbalance_um": e_um, "passed": e_um <= e_per})

    # reduction factor balancer off / on
    if scene.balancer.count == 0:
        red["basis"] = ("the scene has no balancer: no balancer-on phase, no reduction factor "
                        "(the residual is the rotor's own unbalance)")
    elif bq["initial_unbalance_gmm"]:
        red["applicable"] = True
        red["basis"] = ("the recording has only the balancer-on phase: balancer off = the rotor's "
                        "own unbalance M e (scene), balancer on = the identified residual")
        U0 = bq["initial_unbalance_gmm"] * 1e-6
        r = ub.reduction_factor(U0, U, 0.0, sU)
        red.update(factor=r.factor if math.isfinite(r.factor) else None, percent=r.percent,
                   decibel=r.decibel if math.isfinite(r.decibel) else None,
                   factor_lower_bound=U0 / (U + 2 * sU) if (U + 2 * sU) > 0 else None)
        if not math.isfinite(r.factor):
            notes.append("residual unbalance exactly 0: reduction factor infinite; see its lower "
                         "bound")
    else:
        red["basis"] = "the rotor has no unbalance of its own (M e = 0): no reduction factor"

    # ring reading (the lab's laser method) when the recording carries the rings
    inst = d["inst"]
    if "ring_radius" in inst and S > 0:
        gain = float(inst.get("screen_settings", {}).get("gain", 1.0))
        try:
            rr = ub.unbalance_from_rings(gain * sc.amplitude_m, inst["ring_radius"], S)
            bq["ring_reading"] = {
                "spot_radius_m": gain * sc.amplitude_m, "zone": rr.zone,
                "unbalance_gmm": rr.unbalance_gmm, "interpolated_gmm": rr.interpolated_kg_m * 1e6,
                "off_scale": rr.off_scale,
                "ring_test_speed_hz": (inst["ring_test_speed_rad_s"] / TWO_PI
                                       if inst.get("ring_test_speed_rad_s") else None)}
            ts = inst.get("ring_test_speed_rad_s")
            if ts and abs(ts - sc.speed_rad_s) > 1e-3 * ts:
                notes.append("the calibration rings were drawn for another speed than the final "
                             "one: the ring reading is not an unbalance reading")
        except (SignalError, ValueError) as exc:
            notes.append(f"ring reading: {exc}")

    # the recording's truth over the same window (simulated recordings)
    tr = d["truth"].get("residual_unbalance")
    if tr is not None:
        w = (t >= sc.t_start) & (t <= sc.t_end)
        bq["truth_residual_unbalance_gmm"] = float(abs(np.mean(tr[w, 0] + 1j * tr[w, 1]))) * 1e6
    return bq, sc


def _regime_windows(d, scene, t, x, y, phi, speed):
    from dsp import regime as rg

    w_s = max(4 * TWO_PI / max(float(np.median(np.abs(speed))), 1e-9), (t[-1] - t[0]) / 200)
    w_s = min(w_s, (t[-1] - t[0]) / 3)
    thr = scene.balancer.capacity / scene.total_mass / 16
    return rg.classify_windows(t, phi, d["weights"], x, y, w_s, thr), w_s


def _dynamics(d, scene, t, x, y, phi, speed, rotating, notes, warn):
    from dsp import frequency as fq
    from dsp import regime as rg
    from dsp.errors import SignalError

    nf = {"identified_hz": None, "identified_hz_std": None, "damping_ratio": None,
          "damping_ratio_std": None, "method": None, "model_hz": None, "model_damping_ratio": None}
    if scene is not None:
        s = scene.supports
        nf["model_hz"] = scene.natural_frequency / TWO_PI
        nf["model_damping_ratio"] = s.damping_x / (2 * math.sqrt(s.stiffness_x * scene.total_mass))
    dyn = {"natural_frequency": nf, "theory_available": False, "critical_speeds": [],
           "final_regime": None, "regime_timeline": [], "settling": []}
    if not rotating:
        try:
            sig = x if np.std(x) >= np.std(y) else y
            fd = fq.free_decay(t, sig)
            nf.update(identified_hz=fd.natural_frequency_hz,
                      identified_hz_std=fd.natural_frequency_hz_std,
                      damping_ratio=fd.damping_ratio, damping_ratio_std=fd.damping_ratio_std,
                      method="free decay (matrix pencil + least squares)")
        except SignalError as exc:
            notes.append(f"free decay: {exc}")
    else:
        # run-up / run-down: 1X resonance peak with the sweep lag removed
        try:
            pr = _per_revolution(t, x, y, phi) if d["weights"] is None else None
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

            from ..planar_theory.speedmap import scene_theory

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
            wins, w_s = _regime_windows(d, scene, t, x, y, phi, speed)
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
    """5 % settling time of the sliding RMS whirl after each event."""
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


def _scene_warnings(scene, d, bq, dyn, w_service, final_speed, steady_len, t, speed, warn, notes):
    if d["solver"] and (d["solver"].get("success") is False or d["solver"].get("status", 0) < 0):
        warn("run_incomplete", f"the simulation stopped early: {d['solver'].get('message', '')}")
    if scene is None:
        return
    S = scene.balancer.capacity
    if S > 0:
        es = [scene.rotor.unbalance / S] + [p.eccentricity * (p.mass or scene.rotor.mass) / S
                                            for p in scene.perturbations if p.kind == "unbalance"]
        if max(es) > 1:
            warn("capacity_exceeded", f"e0 = {max(es):.4g} > 1: the unbalance exceeds the "
                 "balancer's capacity S; the weights cannot balance it (they gather on the light "
                 "side)")
    if scene.balancer.count and final_speed:
        from ..scene import dimensionless
        from ..planar_theory import qp

        try:
            p = dimensionless(scene)
            H = 0.5 * (p.H_x + p.H_y)
            Rstar = qp.escape_speed(p.Rt, float(p.h[0]), H)
            R = (w_service or final_speed) / p.omega_1
            if 1 < R < Rstar:
                warn("stuck_ball_risk", f"speed ratio R = {R:.4g} lies in 1 < R < R* = "
                     f"{Rstar:.4g} (escape speed (5.182)): the weights may stay stuck in the "
                     "quasi-periodic motion")
        except Exception as exc:  # noqa: BLE001
            notes.append(f"stuck-ball band not evaluated: {exc}")
    fr = dyn.get("final_regime")
    if fr == "stuck":
        warn("stuck_balls_observed", "the weights slip behind the rotor at the end of the record "
             "(quasi-periodic motion, stuck balls)")
    U = bq.get("residual_unbalance_gmm")
    if U is not None and S > 0 and fr in ("balanced", "side") and U * 1e-6 > S / 16 \
            and (scene.rotor.unbalance <= S):
        warn("friction_limited_residual", "the weights turn with the rotor but the residual "
             "exceeds S/16: friction-limited residual (or a side motion)")
    s = scene.supports
    if s.stiffness_x != s.stiffness_y or s.damping_x != s.damping_y:
        warn("model_anisotropic_supports", "anisotropic supports: the unbalance is inverted with "
             "the isotropic model (X-axis stiffness and damping)", "model-validity")
    if len(set(np.round(np.asarray(scene.balancer.mass), 12))) > 1:
        warn("model_non_identical_weights", "weights differ: the chapter-5 theory (critical "
             "speeds, escape speed) assumes identical weights", "model-validity")
    if scene.drive.kind != "speed":
        warn("model_torque_drive", "torque drive: the theory uses the target speed",
             "model-validity")
    R_eval = (bq.get("residual_speed_hz") or 0) * TWO_PI / scene.natural_frequency
    if bq.get("residual_speed_hz") and 0.9 < R_eval < 1.1:
        warn("model_near_resonance", f"the residual is identified at R = {R_eval:.4g}, near "
             "resonance: the inversion is sensitive to the damping", "model-validity")
    if final_speed:
        spr = TWO_PI / abs(final_speed) * (t.size - 1) / (t[-1] - t[0])
        if spr < 8:
            warn("model_undersampled", f"{spr:.3g} samples per revolution (< 8): the 1X order "
                 "tracking is coarse", "model-validity")
        if steady_len < 10 * TWO_PI / abs(final_speed):
            warn("model_short_steady_stretch", "the final constant-speed stretch is shorter than "
                 "10 revolutions: the residual may still be settling", "model-validity")
    set_rows = dyn.get("settling") or []
    if set_rows and not set_rows[-1]["settled"]:
        warn("not_settled", "the whirl had not settled at the end of the record: the residual "
             "is an upper bound of the final one", "model-validity")


# ------------------------------------------------------------------ figures
def _figures(d, t, x, y, phi, speed, rotating, i_st, sc_res) -> dict:
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    figs = {}
    inst = d["inst"]
    # orbit / laser trace
    fig, axs = plt.subplots(1, 2, figsize=(9, 4.2))
    if "ring_radius" in inst:
        st = inst.get("screen_settings", {})
        g = float(st.get("gain", 1.0))
        ox, oy = float(st.get("offset_x", 0.0)), float(st.get("offset_y", 0.0))
        X, Y, unit, sc = g * x + ox, g * y + oy, "screen, mm", 1e3
    else:
        X, Y, unit, sc = x, y, "shaft, mm", 1e3
    sel = slice(i_st, None) if rotating and t.size - i_st > 8 else slice(int(0.7 * t.size), None)
    for ax, s_, title in ((axs[0], slice(None), "whole record"),
                          (axs[1], sel, "final stretch")):
        ax.plot(X[s_] * sc, Y[s_] * sc, lw=0.6)
        if "ring_radius" in inst:
            th = np.linspace(0, TWO_PI, 200)
            for rr in inst["ring_radius"]:
                if rr > 0:
                    ax.plot(rr * sc * np.cos(th), rr * sc * np.sin(th), color="0.75", lw=0.5)
            if title == "final stretch":
                lim = max(float(np.max(np.hypot(X[s_], Y[s_]))) * sc * 1.2,
                          float(inst["ring_radius"][min(2, inst["ring_radius"].size - 1)]) * sc)
                ax.set_xlim(-lim, lim)
                ax.set_ylim(-lim, lim)
        ax.set_aspect("equal", adjustable="box")
        ax.set_xlabel(f"X ({unit})")
        ax.set_ylabel(f"Y ({unit})")
        ax.set_title(title)
    figs["orbit / laser trace (rings: zones i S/16 when recorded)"] = figure_png(fig)

    # 1X amplitude / phase vs speed for varying speed
    if rotating:
        try:
            pr = _per_revolution(t, x, y, phi)
        except Exception:  # noqa: BLE001
            pr = None
        if pr is not None and np.ptp(pr[1]) > 0.05 * np.max(pr[1]):
            tm, wr, vec = pr
            fig, (a1, a2) = plt.subplots(2, 1, figsize=(8, 5), sharex=True)
            a1.semilogy(wr / TWO_PI, np.maximum(np.abs(vec), 1e-30) * 1e3, ".", ms=2)
            a1.set_ylabel("1X amplitude (mm)")
            a2.plot(wr / TWO_PI, np.degrees(np.angle(vec)), ".", ms=2)
            a2.set_ylabel("1X phase (deg)")
            a2.set_xlabel("rotor speed (rev/s)")
            figs["1X amplitude and phase vs speed (one point per revolution)"] = figure_png(fig)

    # spectrogram of the complex orbit
    from scipy import signal as sg

    fs = (t.size - 1) / (t[-1] - t[0])
    nper = int(min(max(16, 2 ** round(math.log2(max(fs, 1.0)))), max(16, t.size // 4)))
    nper = min(nper, t.size)
    if t.size >= 16:
        f, tt, Sxx = sg.spectrogram(x + 1j * y, fs=fs, nperseg=nper, noverlap=nper // 2,
                                    return_onesided=False, detrend=False)
        f = np.fft.fftshift(f)
        Sxx = np.fft.fftshift(Sxx, axes=0)
        fig, ax = plt.subplots(figsize=(8, 4))
        ax.pcolormesh(tt + t[0], f, 10 * np.log10(Sxx + 1e-30 + Sxx.max() * 1e-12),
                      shading="auto", cmap="viridis")
        if rotating:
            ax.plot(t, speed / TWO_PI, "w--", lw=0.7)
        ax.set_xlabel("time (s)")
        ax.set_ylabel("frequency (Hz, + forward whirl)")
        figs["spectrogram of the orbit x + i y (dashed: rotor speed)"] = figure_png(fig)

    # weights' relative angles
    rel = d.get("rel")
    if rel is not None and rel.size:
        fig, ax = plt.subplots(figsize=(8, 3.5))
        ax.plot(t, np.degrees(np.angle(np.exp(1j * rel))), ".", ms=1)
        ax.set_xlabel("time (s)")
        ax.set_ylabel("angle from the mark (deg)")
        ax.set_ylim(-180, 180)
        figs["weights' angles relative to the reference mark"] = figure_png(fig)

    for key, cap in (("strobe_frame", "stroboscope frame (last recorded)"),
                     ("screen_frame", "screen camera frame (last recorded)")):
        if key in inst:
            fig, ax = plt.subplots(figsize=(4, 4))
            ax.imshow(inst[key], cmap="gray", origin="upper")
            ax.set_axis_off()
            figs[cap] = figure_png(fig)
    return figs
