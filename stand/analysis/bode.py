"""``stand analyze`` of a Bode / polar table: the modal fit of the steady 1X response.

The table (:func:`stand.lab.bode_table.read_bode_table`) gives the 1X displacement
vector against the speed; :func:`dsp.bode.modal_fits` fits each resonance (rational /
circle fit on the polar plot, half-power as a cross-check): natural frequency, damping,
critical speed and, with the map's mass, the unbalance.  The keys are those of a
time record's analysis (the ones a table cannot give are None), plus ``modes`` (one per
resonance) and ``bode`` (the table in SI, for the report's Bode and polar plots).
"""
from __future__ import annotations

import math

import numpy as np

__all__ = ["analyze_bode"]

TWO_PI = 2 * math.pi
#: the keys of a time record's analysis a Bode table does not give
_NONE = ("natural_frequency_hz", "natural_frequency_hz_std", "damping_ratio", "damping_ratio_std",
         "speed_hz", "response_1x_m", "unbalance_gmm", "unbalance_gmm_std", "unbalance_angle_deg",
         "unbalance_angle_deg_std", "iso_grade", "programme", "critical_speed_hz", "critical_speed_hz_std",
         "critical_speed_method", "precession_hz", "nutation_hz", "petals", "shape", "regime",
         "runup", "stationary_stretch")


def analyze_bode(tab, notes: list) -> dict:
    """The analysis document of a :class:`stand.lab.bode_table.BodeTable`."""
    from dsp.bode import modal_fits
    from dsp.errors import SignalError

    out = {"recording": tab.path, "notes": notes, "input": tab.input_summary(),
           **{k: None for k in _NONE}, "critical_speeds_hz": [], "components": [], "modes": []}
    out["speed_source"] = f"the table's speed column {tab.columns['speed'].column!r}"
    out["bode"] = {"speed_hz": (tab.speed_rad_s / TWO_PI).tolist(),
                   "amplitude_m": np.abs(tab.vector_m).tolist(),
                   "phase_deg": np.degrees(np.angle(tab.vector_m)).tolist()}
    notes.append(f"Bode table: the phase column read as a {tab.phase_convention} (its direction "
                 "through the resonance)")
    if tab.quantity != "length":
        notes.append(f"Bode table in {tab.quantity}: the 1X vectors divided by (i w)^k to "
                     "displacement (exact for a steady harmonic)")
    try:
        fits = modal_fits(tab.speed_rad_s, tab.vector_m)
    except SignalError as exc:
        notes.append(f"modal fit: {exc}")
        return out
    mass = tab.recording_map.mass_kg
    for m in fits:
        out["modes"].append({
            "natural_frequency_hz": m.natural_frequency_hz,
            "natural_frequency_hz_std": m.natural_frequency_hz_std,
            "damping_ratio": m.damping_ratio, "damping_ratio_std": m.damping_ratio_std,
            "half_power_damping_ratio": m.half_power_damping_ratio,
            "critical_speed_hz": m.critical_speed_hz,
            "specific_unbalance_gmm_per_kg": m.specific_unbalance_m * 1e6,
            "unbalance_gmm": m.specific_unbalance_m * mass * 1e6 if mass else None,
            "unbalance_gmm_std": m.specific_unbalance_m_std * mass * 1e6 if mass else None,
            "unbalance_angle_deg": math.degrees(m.angle_rad) % 360.0,
            "unbalance_angle_deg_std": math.degrees(m.angle_rad_std),
            "critical_speed_hz_std": m.critical_speed_hz_std,
            "sweep_rate_hz_s": m.sweep_rate_rad_s2 / TWO_PI,
            "runout_m": abs(m.runout_m), "speed_range_hz": list(m.speed_range_hz),
            "residual_rms_m": m.residual_rms_m, "points": m.points})
    first = max(out["modes"], key=lambda d: d["specific_unbalance_gmm_per_kg"] /
                max(d["damping_ratio"], 1e-9))
    out.update(natural_frequency_hz=first["natural_frequency_hz"],
               natural_frequency_hz_std=first["natural_frequency_hz_std"],
               damping_ratio=first["damping_ratio"], damping_ratio_std=first["damping_ratio_std"],
               critical_speed_hz=first["critical_speed_hz"],
               critical_speed_hz_std=first["critical_speed_hz_std"],
               critical_speed_method="modal fit of the steady 1X table (rational fit on the "
                                     "polar plot, dsp.bode), half-power as a cross-check",
               unbalance_gmm=first["unbalance_gmm"], unbalance_gmm_std=first["unbalance_gmm_std"],
               unbalance_angle_deg=first["unbalance_angle_deg"],
               unbalance_angle_deg_std=first["unbalance_angle_deg_std"],
               specific_unbalance_gmm_per_kg=first["specific_unbalance_gmm_per_kg"])
    if len(out["modes"]) > 1:
        notes.append(f"{len(out['modes'])} resonances in the table, each fitted (modes); the "
                     "headline numbers are the strongest one's")
    if not mass:
        notes.append("unbalance in g·mm needs the vibrating mass: give [rotor] mass in the "
                      "recording map (the specific unbalance per kg is given)")
    return out
