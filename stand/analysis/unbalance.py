"""The unbalance steps of ``stand analyze``: the 1X line without a phase reference, the
unbalance from a model, the calibration rings' reading, and the ISO 21940-11 grade.

Each step writes its keys into the analysis document ``out`` (the keys of
``stand analyze --json``) and its reasons into ``notes``; units in the key names.
"""
from __future__ import annotations

import math

import numpy as np

from dsp.errors import SignalError

__all__ = ["line_1x", "unbalance", "iso_grade", "ring_reading", "reduction"]

TWO_PI = 2 * math.pi


def line_1x(t, z, out, notes, speed_how=None) -> None:
    """No phase reference: the 1X line's frequency and amplitude from the spectrum
    (:func:`dsp.frequency.refine_frequencies`, the strongest forward line)."""
    from dsp.lines import refine_frequencies

    try:
        comp = refine_frequencies(t, z - np.mean(z), 1)
        f = float(comp.frequency_hz[0])
        out["speed_hz"] = abs(f)
        out["response_1x_m"] = float(abs(comp.amplitude[0]))
        out["response_1x_m_std"] = float(comp.amplitude_std[0])
        if speed_how:          # a tachometer: the speed is measured, the 1X phase has no mark
            notes.append(f"1X over the steady stretch: the strongest line of the orbit at "
                         f"{abs(f):.6g} rev/s (speed from the {speed_how}; no mark for the angle)")
            return
        out["speed_estimated"] = True
        notes.append(f"no keyphasor or encoder: the speed {abs(f):.6g} rev/s is the strongest line "
                     "of the orbit (estimated from the vibration)")
    except SignalError as exc:
        notes.append(f"1X line: {exc}")


def _turn_std(est, sc1) -> float:
    """The unbalance angle's std [rad]: the 1X vector's scatter across it (``est``) and what
    the phase reference adds (``sc1.reference_std_rad``: a keyphasor's timing,
    :func:`stand.analysis.identify._mark_timing`)."""
    return math.hypot(est.angle_std_rad, sc1.reference_std_rad)


def unbalance(out, scene, sc1, d, rmap, mass, grade, service_speed_rpm, notes) -> None:
    """The unbalance from the model (the scene's, the run-up fit's, or the map's f0 and
    damping), the ring zones of a track, and the ISO 21940-11 grade."""
    from dsp import unbalance as ub

    e = se = ang = sang = None       # specific unbalance [m] and its angle [deg], stds
    how = None
    fit = (out.get("runup") or {}).get("model_fit")
    if scene is not None and sc1 is not None:
        s = scene.supports
        Ms = scene.total_mass
        zeta = s.damping_x / (2 * math.sqrt(s.stiffness_x * Ms))
        est = ub.unbalance_from_response(sc1, sc1.speed_rad_s, Ms, scene.natural_frequency / TWO_PI,
                                         zeta)
        out.update(unbalance_gmm=est.unbalance_gmm, unbalance_gmm_std=est.unbalance_std_gmm,
                   unbalance_angle_deg=est.angle_deg,
                   unbalance_angle_deg_std=math.degrees(_turn_std(est, sc1)))
        iso_grade(out, est.unbalance_gmm, est.unbalance_std_gmm, scene.rotor.mass,
                  sc1.speed_rad_s, grade, service_speed_rpm)
        ring_reading(out, d)
        return
    if fit is not None:
        e, se, ang = fit["specific_unbalance_m"], fit["specific_unbalance_m_std"], \
            fit["unbalance_angle_deg"]
        sang = fit.get("unbalance_angle_deg_std")
        how = "rigid-rotor model fitted to the run-up"
    elif sc1 is not None and rmap is not None and rmap.natural_frequency_hz \
            and rmap.damping_ratio is not None:
        est = ub.unbalance_from_response(sc1, sc1.speed_rad_s, 1.0, rmap.natural_frequency_hz,
                                         rmap.damping_ratio)
        e, se, ang = est.unbalance_kg_m, est.unbalance_std_kg_m, est.angle_deg
        sang = math.degrees(_turn_std(est, sc1))
        how = f"steady 1X with the map's natural frequency and damping ({rmap.source})"
    elif out.get("response_1x_m") and rmap is not None and rmap.natural_frequency_hz \
            and rmap.damping_ratio is not None:
        R = out["speed_hz"] / rmap.natural_frequency_hz
        e = out["response_1x_m"] * abs(1 - R * R + 2j * rmap.damping_ratio * R) / (R * R)
        how = f"1X line with the map's natural frequency and damping ({rmap.source})"
    rings = ring_reading(out, d)
    if e is None and rings is None:
        if d.get("table") is not None:
            notes.append("unbalance: a table has no scene (mass, f0, damping); it needs a run-up "
                         "through the resonance (model fit), or the "
                         "natural frequency and damping ratio in the map's [rotor], or a track "
                         "with ring radii and the capacity")
        else:
            notes.append(_why_no_unbalance(out, scene, sc1, d))
        return
    if e is not None:
        out["specific_unbalance_gmm_per_kg"] = e * 1e6       # [m] = [kg m / kg] -> g mm / kg
        out["specific_unbalance_gmm_per_kg_std"] = None if se is None else se * 1e6
        out["unbalance_method"] = how
        out["unbalance_angle_deg"] = ang
        out["unbalance_angle_deg_std"] = sang if ang is not None else None
        if mass:
            out.update(unbalance_gmm=e * mass * 1e6,
                       unbalance_gmm_std=None if se is None else se * mass * 1e6)
        else:
            notes.append("unbalance in g·mm needs the vibrating mass: give [rotor] mass in the "
                         "recording map (the specific unbalance per kg is given)")
    w_meas = (out.get("speed_hz") or 0.0) * TWO_PI
    if rmap is not None and rmap.service_speed_rad_s and not service_speed_rpm:
        service_speed_rpm = rmap.service_speed_rad_s * 60 / TWO_PI
    if e is None and mass and service_speed_rpm:   # the rings' unbalance (a camera's frame
        iso_grade(out, out["unbalance_gmm"], out["unbalance_gmm_std"], mass, 0.0, grade,
                  service_speed_rpm)                 # rate may alias the spot's speed: given)
    if e is not None and (w_meas > 0 or service_speed_rpm):
        iso_grade(out, e * (mass or 1.0) * 1e6, None if se is None else se * (mass or 1.0) * 1e6,
                  mass or 1.0, w_meas, grade, service_speed_rpm, per_kg=not mass)


def _why_no_unbalance(out, scene, sc1, d) -> str:
    """Why a recording's 1X gave no unbalance, in the user's words: no 1X (its note says
    why), no scene, a rotor the planar model does not describe, or no model fit."""
    rs = d.get("rec_scene")
    if sc1 is None and out.get("response_1x_m") is None:
        return "unbalance: no steady 1X in the record (see the 1X note): nothing to convert"
    if rs is None:
        return ("no scene in the recording: the 1X response is not converted to an unbalance "
                "(needs mass, f0, damping)")
    if getattr(rs, "kind", None) != "planar":
        kind = getattr(rs, "structure_type", None) or getattr(rs, "kind", "")
        return (f"unbalance: the 1X is turned into an unbalance with the planar rotor's model "
                f"(mass, f0, damping); this recording's rotor is the {kind!r} structure: not "
                "converted (stand theory / the recorded truth/residual describe it)")
    if scene is None:
        return ("unbalance: the run-up model fit gave no unbalance (see its note); the 1X is "
                "not converted")
    return "unbalance: the steady 1X has no phase reference (rotor angle): not converted"


def iso_grade(out, U_gmm, sU_gmm, mass, w_meas, grade, service_speed_rpm, per_kg=False) -> None:
    """``out["iso_grade"]``: the achieved ISO 21940-11 grade (``achieved_grade_mm_s``) of the
    unbalance ``U_gmm`` [g mm] (std ``sU_gmm``) of a rotor of ``mass`` [kg] at the service
    speed (``service_speed_rpm`` [rpm], else the measured ``w_meas`` [rad/s]) against the
    required ``grade`` G [mm/s] (``required_grade_mm_s``; the same names as the report's
    ``iso_21940_11``)."""
    from dsp import unbalance as ub

    w_service = service_speed_rpm * TWO_PI / 60.0 if service_speed_rpm else w_meas
    g = ub.iso_21940_grade(U_gmm, mass, w_service, target_grade_mm_s=grade,
                           unbalance_std_gmm=sU_gmm)
    out["iso_grade"] = {"achieved_grade_mm_s": g.grade_mm_s,
                        "achieved_grade_mm_s_std": g.grade_std_mm_s,
                        "class": g.label, "required_grade_mm_s": grade, "passed": g.passed,
                        "permissible_gmm": None if per_kg else getattr(g, "permissible_gmm", None),
                        "service_speed_rpm": w_service * 60 / TWO_PI,
                        "mass_kg": None if per_kg else float(mass),
                        # the names before 2026-11-30, kept for scripts that read them
                        # (docs/results.md): grade_mm_s = achieved, target_mm_s = required
                        "grade_mm_s": g.grade_mm_s, "grade_mm_s_std": g.grade_std_mm_s,
                        "target_mm_s": grade}


def ring_reading(out, d):
    """A ``stand track`` CSV with ring radii and the capacity in its header: the spot
    circle's radius on the screen read against the rings (the lab's laser method, 4.3)."""
    from dsp.unbalance import unbalance_from_rings

    from stand.analysis.trace_reading import settled_circles

    tab = d.get("table")
    meta = tab.metadata if tab is not None else {}
    try:            # the ring scale's relative std (systematic: it does not average out)
        rel_scale = float(meta["scale_std_mm_per_px"]) / float(meta["scale_mm_per_px"])
    except (KeyError, ValueError, ZeroDivisionError):
        rel_scale = None
    circles = settled_circles(tab.path, rel_scale, out["notes"]) if tab is not None else None
    if out.get("response_1x_m") is None and circles is None:
        return None
    if tab is None:
        return _recorded_rings(out, d)
    try:
        radii = [float(v) for v in str(meta["ring_radii_m"]).split(",")]
        S = float(meta["capacity_gmm"]) * 1e-6
        gain = float(meta.get("optical_gain", 1.0))
    except (KeyError, ValueError):
        return None
    if circles is not None:       # long exposures: the circles drawn on the screen itself
        r_screen, s_resp, n_circles = circles
        gain = 1.0
    else:
        r_screen, s_resp = out["response_1x_m"] * gain, out.get("response_1x_m_std")
    if rel_scale is None:
        out["notes"].append("ring reading: the track does not state the ring scale's "
                            "uncertainty (scale_std_mm_per_px); the circle radius's std is the "
                            "spot's scatter only")
    # the circle radius's std: the spot's scatter (the 1X line's, or the circles') and the ring
    # scale's calibration, once
    sr = (math.hypot(gain * s_resp, r_screen * (rel_scale or 0.0))
          if s_resp is not None and math.isfinite(s_resp) else None)
    parts = [("the settled circles' scatter or pixel noise" if circles is not None
              else "the 1X line's scatter")] + (["the ring scale's calibration"] if rel_scale else [])
    rd = unbalance_from_rings(r_screen, radii, S, radius_std_m=sr or 0.0)
    s_int = rd.interpolated_std_kg_m * 1e6 if sr is not None else None
    out["ring_reading"] = {"circle_radius_mm": r_screen * 1e3,
                           "circle_radius_mm_std": None if sr is None else sr * 1e3,
                           "zone": rd.zone,
                           "unbalance_gmm": rd.unbalance_gmm, "unbalance_gmm_std": rd.unbalance_std_gmm,
                           "interpolated_gmm": rd.interpolated_kg_m * 1e6,
                           "interpolated_gmm_std": s_int, "off_scale": rd.off_scale,
                           "uncertainty_statement": None if sr is None else (
                               "± is one standard uncertainty: " + " and ".join(parts) +
                               ", interpolated between the rings; the rings themselves (zone i "
                               "-> i S/16) are taken as exact")}
    if circles is not None:
        out["ring_reading"]["circles"] = n_circles
    if out.get("unbalance_gmm") is None:
        what = (f"the mean of the last {n_circles} (settled) long-exposure circles"
                if circles is not None else "spot circle")
        out.update(unbalance_gmm=rd.interpolated_kg_m * 1e6,
                   unbalance_gmm_std=rd.unbalance_std_gmm if s_int is None else s_int,
                   unbalance_method=f"{what} against the calibration rings (zone i -> i S/16, "
                                    "interpolated between the rings)")
    return rd


def _recorded_rings(out, d):
    """A recording's screen rings (``d["rings"]``, :func:`stand.analysis.sources.from_run`)
    against the spot circle gain |1X| (the scene's capacity S: zone i -> i S/16)."""
    from dsp.unbalance import unbalance_from_rings

    rings, scene = d.get("rings"), d.get("rec_scene")
    S = scene.weights_capacity() if getattr(scene, "kind", None) == "planar" else 0.0
    if rings is None or not S > 0:
        return None
    gain, a, sa = rings["gain"], out["response_1x_m"], out.get("response_1x_m_std")
    s_r = gain * sa if sa is not None and math.isfinite(sa) else None
    try:
        rd = unbalance_from_rings(gain * a, rings["radius_m"], S, radius_std_m=s_r or 0.0)
    except (SignalError, ValueError) as exc:
        out["notes"].append(f"ring reading: {exc}")
        return None
    ts = rings["test_speed_rad_s"]
    out["ring_reading"] = {"circle_radius_mm": gain * a * 1e3,
                           "circle_radius_mm_std": None if s_r is None else s_r * 1e3,
                           "zone": rd.zone, "unbalance_gmm": rd.unbalance_gmm,
                           "unbalance_gmm_std": rd.unbalance_std_gmm,
                           "interpolated_gmm": rd.interpolated_kg_m * 1e6,
                           "interpolated_gmm_std": (None if s_r is None
                                                    else rd.interpolated_std_kg_m * 1e6),
                           "off_scale": rd.off_scale,
                           "ring_test_speed_hz": None if not ts else ts / TWO_PI}
    w = (out.get("speed_hz") or 0.0) * TWO_PI
    if ts and abs(ts - w) > 1e-3 * ts:
        out["notes"].append("the calibration rings were drawn for another speed than the final "
                            "one: the ring reading is not an unbalance reading")
    return rd


def reduction(out, d) -> None:
    """``initial_unbalance_gmm`` (the scene's own rotor unbalance M e at the start: balancer
    off) and ``reduction`` (balancer off / on: factor with its std and its lower bound at
    2 sigma, percent, dB) of a simulated planar run whose residual was identified."""
    from dsp import unbalance as ub

    scene, t = d.get("rec_scene"), d["t"]
    if getattr(scene, "kind", None) != "planar":
        return
    from stand.model.planar import rotor_unbalance

    U0 = float(abs(rotor_unbalance(scene, np.array([t[0]]))[0]))
    out["initial_unbalance_gmm"] = U0 * 1e6
    U, sU = out.get("unbalance_gmm"), out.get("unbalance_gmm_std") or 0.0
    if U is None or not scene.balancer.count or not U0:
        return
    U, sU = U * 1e-6, sU * 1e-6
    r = ub.reduction_factor(U0, U, 0.0, sU)
    out["reduction"] = {
        "factor": r.factor if math.isfinite(r.factor) else None,
        # first order holds while the residual is well above its std; below 3 sigma the
        # factor is unbounded above: its lower bound says it
        "factor_std": r.factor_std if math.isfinite(r.factor_std) and 3 * sU <= U else None,
        "factor_lower_bound": U0 / (U + 2 * sU) if (U + 2 * sU) > 0 else None,
        "percent": r.percent, "decibel": r.decibel if math.isfinite(r.decibel) else None}
