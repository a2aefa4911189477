"""The balancing report of a lab table: ``stand analyze``'s identification as a report section.

A DAQ export has no scene: the unbalance, natural frequency, damping and
critical speed come from the record itself (the run-up model fit and the
sweep-corrected resonance, :mod:`stand.analysis.runup`) and the machine's data
from the recording map.  :func:`lab_identification` runs
:func:`stand.analysis.identify.analyze` on the table and keeps what the report shows;
:func:`fill_from_lab` puts its numbers where the report's common sections
expect them (residual unbalance, ISO 21940-11 grade, natural frequency,
critical speeds), so a lab table and a simulated run read alike.
"""
from __future__ import annotations

import math

__all__ = ["lab_identification", "fill_from_lab", "LAB_SCHEMA"]

TWO_PI = 2.0 * math.pi

#: What a ± of the run-up model fit contains (the report's one line on it).
FIT_UNCERTAINTY = ("± is one standard uncertainty: the model fit's statistical part with "
                   "correlated residuals (block-score sandwich covariance, never below the "
                   "white-noise one); the keyphasor's pulse timing (an edge faster than a "
                   "sample anywhere in its sample interval) through the rotor angle; a rotor angle "
                   "estimated from the whirl, fitted with the model (its spline's coefficients "
                   "as nuisance parameters); a rotor angle from a held tachometer display, "
                   "that display's count quantum and its update timing (to one DAQ sample); "
                   "the rigid-rotor model itself and the vibrating mass are taken as exact")
N, S_, L, O = "number|null", "string|null", "list", "object|null"

#: keys and types of the ``lab_identification`` section (docs/reports.md)
LAB_SCHEMA = {"input": O, "speed_source": S_, "programme": O, "critical_speed_hz": N,
              "critical_speed_hz_std": N, "unbalance_angle_deg_std": N,
              "uncertainty_statement": S_, "critical_speed_method": S_, "natural_frequency_hz": N,
              "natural_frequency_hz_std": N, "damping_ratio": N, "damping_ratio_std": N,
              "unbalance_gmm": N, "unbalance_gmm_std": N, "unbalance_angle_deg": N,
              "specific_unbalance_gmm_per_kg": N, "unbalance_method": S_, "mass_kg": N,
              "resonance": O, "model_fit": O, "excluded_rows": L}


def lab_identification(path, recording_map, grade, service_speed_rpm, notes) -> dict:
    """The ``lab_identification`` section (keys of :data:`LAB_SCHEMA`); the analysis' notes
    are added to ``notes``."""
    from stand.analysis.identify import analyze

    a = analyze(path, grade=grade, service_speed_rpm=service_speed_rpm,
                recording_map=recording_map)
    runup = a.get("runup") or {}
    for n in a.get("notes", []):
        if n not in notes and not n.startswith("regime:"):
            notes.append(n)
    inp = a.get("input") or {}
    return {"input": {k: v for k, v in inp.items() if k != "excluded"},
            "speed_source": a.get("speed_source"), "programme": a.get("programme"),
            "critical_speed_hz": a.get("critical_speed_hz"),
            "critical_speed_hz_std": a.get("critical_speed_hz_std"),
            "unbalance_angle_deg_std": a.get("unbalance_angle_deg_std"),
            "uncertainty_statement": (FIT_UNCERTAINTY if runup.get("model_fit") else None),
            "critical_speed_method": a.get("critical_speed_method"),
            "natural_frequency_hz": a.get("natural_frequency_hz"),
            "natural_frequency_hz_std": a.get("natural_frequency_hz_std"),
            "damping_ratio": a.get("damping_ratio"), "damping_ratio_std": a.get("damping_ratio_std"),
            "unbalance_gmm": a.get("unbalance_gmm"), "unbalance_gmm_std": a.get("unbalance_gmm_std"),
            "unbalance_angle_deg": a.get("unbalance_angle_deg"),
            "specific_unbalance_gmm_per_kg": a.get("specific_unbalance_gmm_per_kg"),
            "unbalance_method": a.get("unbalance_method"),
            "mass_kg": getattr(recording_map, "mass_kg", None) if recording_map else None,
            "resonance": runup.get("resonance"), "model_fit": runup.get("model_fit"),
            "excluded_rows": inp.get("excluded") or [],
            "_iso": a.get("iso_grade")}


def fill_from_lab(lab, header, bq, dyn, grade, w_service, warn) -> None:
    """Copy the lab identification into the report's header, quality and dynamics sections
    where those are empty (no scene)."""
    from dsp import unbalance as ub

    iso = lab.pop("_iso", None)
    mass = lab.get("mass_kg")
    if mass and header.get("rotor_mass_kg") is None:
        header["rotor_mass_kg"] = header["total_mass_kg"] = mass
    if w_service and header.get("service_speed_rpm") is None:
        header["service_speed_rpm"] = w_service * 60 / TWO_PI
    if lab.get("unbalance_gmm") is not None and bq.get("residual_unbalance_gmm") is None:
        bq["residual_unbalance_gmm"] = lab["unbalance_gmm"]
        bq["residual_unbalance_gmm_std"] = lab["unbalance_gmm_std"]
        bq["residual_unbalance_angle_deg"] = lab["unbalance_angle_deg"]
        bq["residual_unbalance_angle_deg_std"] = lab.get("unbalance_angle_deg_std")
        bq["uncertainty_statement"] = lab.get("uncertainty_statement")
    if lab.get("specific_unbalance_gmm_per_kg") is not None and bq.get("specific_unbalance_um") is None:
        bq["specific_unbalance_um"] = lab["specific_unbalance_gmm_per_kg"]   # g mm / kg = um
    q = bq["iso_21940_11"]
    if iso and q.get("achieved_grade_mm_s") is None:
        q.update(service_speed_rpm=iso["service_speed_rpm"], achieved_grade_mm_s=iso["grade_mm_s"],
                 achieved_grade_mm_s_std=iso["grade_mm_s_std"], achieved_class=iso["class"],
                 passed=iso["passed"])
        if mass:
            w = iso["service_speed_rpm"] * TWO_PI / 60.0
            q["permissible_residual_gmm"] = ub.iso_21940_permissible(grade, mass, w)
            q["permissible_specific_unbalance_um"] = q["permissible_residual_gmm"] / mass
        if iso["passed"] is False:
            warn("iso_grade_failed", f"ISO 21940-11: achieved G {iso['grade_mm_s']:.3g} mm/s, "
                 f"required G {grade:g}")
    nf = dyn["natural_frequency"]
    if lab.get("natural_frequency_hz") is not None and lab.get("model_fit") is not None:
        nf.update(identified_hz=lab["natural_frequency_hz"],
                  identified_hz_std=lab["natural_frequency_hz_std"],
                  damping_ratio=lab["damping_ratio"], damping_ratio_std=lab["damping_ratio_std"],
                  method="rigid-rotor model fitted to the run-up (dsp.response_fit)")
    if lab.get("critical_speed_hz") is not None:
        dyn["critical_speeds"].append({"source": "recording (1X resonance of the run)",
                                       "speed_hz": lab["critical_speed_hz"],
                                       "speed_hz_std": lab.get("critical_speed_hz_std"),
                                       "event": lab.get("critical_speed_method"),
                                       "nearest_theory_hz": None, "difference_hz": None})
