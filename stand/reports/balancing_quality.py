"""Balancing quality of one recording: residual unbalance, ISO 21940-11 grade, reduction.

The residual unbalance is the 1X response over the end of the final
constant-speed stretch, turned into an unbalance with the scene's mass,
natural frequency and damping (:mod:`dsp.unbalance`); it is compared with the
ISO 21940-11 permissible residual of the chosen grade, the seeds' household
and general-machine criteria, the rotor's own unbalance (reduction factor)
and, when the recording carries them, the calibration rings (zones i S/16).
"""
from __future__ import annotations

import math

import numpy as np

from stand.reports.balancing_schema import SCHEMA

__all__ = ["balancing_quality", "zone", "zone_label"]

TWO_PI = 2.0 * math.pi

#: What the ± of the unbalance from the steady 1X contains (the report's one line on it).
SCATTER_UNCERTAINTY = ("± is one standard uncertainty: the revolution-to-revolution scatter of "
                       "the 1X vector; the scene's mass, natural frequency and damping are "
                       "taken as exact")


def zone(U_kg_m, S):
    """Ring zone i of an unbalance: i S/16 <= U < (i + 1) S/16.

    Parameters
    ----------
    U_kg_m : float or None
        Unbalance [kg m].
    S : float
        Balancer capacity [kg m]; 0: no zone.

    Returns
    -------
    int or None
    """
    if U_kg_m is None or not S or not math.isfinite(U_kg_m):
        return None
    return int(math.floor(U_kg_m / (S / 16.0) + 1e-9))


def zone_label(i):
    """``"zone i: between i S/16 and i+1 S/16"`` (None for no zone)."""
    if i is None:
        return None
    return f"zone {i}: between {i} S/16 and {i + 1} S/16"


def balancing_quality(rec, w_service, grade, notes, warn):
    """The ``balancing_quality`` section of the report.

    Parameters
    ----------
    rec : Record
        The recording (:func:`stand.reports.balancing_input.load_record`).
    w_service : float or None
        Service speed [rad/s] for the ISO grade and the seeds' criteria.
    grade : float
        ISO 21940-11 grade to check [mm/s].
    notes : list of str
        Receives what could not be computed and why.
    warn : callable
        ``warn(code, message, severity="warning")`` adds a warning.

    Returns
    -------
    dict
        The keys of ``SCHEMA["balancing_quality"]``: unbalances in g mm,
        specific unbalance in um, speeds in Hz, windows in s, 1X response in m.
    """
    from dsp import unbalance as ub
    from dsp.errors import SignalError

    d, scene, t, x, y, phi, speed = rec.data, rec.scene, rec.t, rec.x, rec.y, rec.phi, rec.speed
    S = (scene.balancer.capacity + sum(b.body.capacity for b in scene.bodies)
         if scene is not None else 0.0)
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
    red = {"applicable": False, "basis": "not evaluated: no residual unbalance identified", "factor": None,
           "factor_std": None, "factor_lower_bound": None,
           "percent": None, "decibel": None}
    bq["reduction"] = red

    # initial unbalance: the rotor's own (balancer off), from the scene
    if scene is not None:
        from stand.model.planar import rotor_unbalance

        U0 = float(abs(rotor_unbalance(scene, np.array([t[0]]))[0]))
        bq["initial_unbalance_gmm"] = U0 * 1e6
        bq["initial_unbalance_source"] = ("scene: rotor's own unbalance M e at the start "
                                          "(balancer off)")
        bq["initial_zone"] = zone(U0, S)

    # residual unbalance: 1X over the end of the final constant-speed stretch
    sc = None
    if not rec.rotating:
        notes.append("the rotor does not turn: no 1X response, no residual unbalance")
        return bq
    if d["weights"] is not None and d["weights"].shape[1] and phi is not None:
        rel_end = np.diff(d["rel"][-2:], axis=0) if d.get("rel") is not None else None
        if rel_end is not None and np.any(np.abs(rel_end) > 1e-3 * abs(speed[-1]) * (t[-1] - t[-2])):
            notes.append("the weights still move relative to the rotor at the end of the record: "
                         "the residual unbalance varies in time and the 1X value is its mean "
                         "over the window (its standard uncertainty includes the variation)")
    n0 = rec.steady
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
        return bq
    bq["residual_window_s"] = [sc.t_start, sc.t_end]
    bq["residual_speed_hz"] = sc.speed_rad_s / TWO_PI
    bq["response_1x_m"] = sc.amplitude_m
    bq["response_1x_m_std"] = sc.vector_std_m
    if scene is None:
        return bq
    s = scene.supports
    Ms = scene.total_mass
    f0 = scene.natural_frequency / TWO_PI
    zeta = s.damping_x / (2 * math.sqrt(s.stiffness_x * Ms))
    try:
        est = ub.unbalance_from_response(sc, sc.speed_rad_s, Ms, f0, zeta)
    except (SignalError, ValueError) as exc:
        notes.append(f"unbalance from the 1X response: {exc}")
        return bq
    U, sU = est.unbalance_kg_m, est.unbalance_std_kg_m
    bq.update(residual_unbalance_gmm=U * 1e6, residual_unbalance_gmm_std=sU * 1e6,
              residual_unbalance_angle_deg=est.angle_deg,
              residual_unbalance_angle_deg_std=math.degrees(est.angle_std_rad),
              uncertainty_statement=SCATTER_UNCERTAINTY,
              residual_fraction_of_capacity=(U / S if S > 0 else None),
              specific_unbalance_um=U * 1e6 / m_iso, specific_unbalance_um_std=sU * 1e6 / m_iso)
    if S > 0:
        bq["residual_zone"] = zone(U, S)
        bq["residual_zone_label"] = zone_label(bq["residual_zone"])
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
        from stand.model.balancers.liquid_chamber import (permissible_eccentricity_general,
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
        red.update(factor=r.factor if math.isfinite(r.factor) else None,
                   # first order holds while the residual is well above its std; below
                   # 3 sigma the factor is unbounded above: its lower bound says it
                   factor_std=(r.factor_std if math.isfinite(r.factor_std) and 3 * sU <= U
                               else None),
                   percent=r.percent,
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
            s_r = gain * sc.amplitude_std_m if math.isfinite(sc.amplitude_std_m) else None
            rr = ub.unbalance_from_rings(gain * sc.amplitude_m, inst["ring_radius"], S,
                                         radius_std_m=s_r or 0.0)
            bq["ring_reading"] = {
                "spot_radius_m": gain * sc.amplitude_m, "spot_radius_m_std": s_r,
                "zone": rr.zone,
                "unbalance_gmm": rr.unbalance_gmm, "interpolated_gmm": rr.interpolated_kg_m * 1e6,
                "interpolated_gmm_std": None if s_r is None else rr.interpolated_std_kg_m * 1e6,
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
    return bq
