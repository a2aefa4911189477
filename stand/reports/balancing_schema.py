"""The balancing report's JSON document: its required keys and types (:data:`SCHEMA`).

``analysis`` is ``stand analyze --json`` of the same input, unchanged (its keys are
documented in docs/results.md); the other sections present it.

Every key is documented with its unit in docs/reports.md; units are also in
the key names (``_gmm`` g mm, ``_hz`` Hz, ``_rpm`` rev/min, ``_um`` um,
``_s`` s, ``_m`` m, ``_deg`` degrees, ``_mm_s`` mm/s).  "number|null" keys
are None when they cannot be computed, with the reason in ``notes``.
"""
from __future__ import annotations

__all__ = ["SCHEMA", "SECTIONS", "REGIME_NAMES", "FORMAT_VERSION"]

from stand.io.labels import REGIME_NAMES      # dsp.regime names -> the words shown (one table)

FORMAT_VERSION = 1

N, S_, B, L, O = "number|null", "string|null", "bool|null", "list", "object|null"

#: required keys and types of the report (see docs/reports.md for units)
SCHEMA = {
    "report": {"kind": "string", "format_version": "number", "recording": "string",
               "input_format": "string", "generator": "string"},
    "header": {"scene_name": S_, "description": S_, "rotor_mass_kg": N, "total_mass_kg": N,
               "balancer_type": S_, "weights": N, "capacity_gmm": N,
               "rotor_unbalance_gmm": N, "e0": N, "duration_s": N, "samples": "number",
               "sample_rate_hz": N, "max_speed_hz": N, "final_speed_hz": N,
               "service_speed_rpm": N},
    "balancing_quality": {
        "initial_unbalance_gmm": N, "initial_unbalance_source": S_, "initial_zone": N,
        "residual_unbalance_gmm": N, "residual_unbalance_gmm_std": N,
        "residual_unbalance_angle_deg": N, "residual_unbalance_angle_deg_std": N,
        "unbalance_method": S_, "uncertainty_statement": S_, "residual_fraction_of_capacity": N,
        "residual_zone": N, "residual_zone_label": S_, "residual_window_s": L,
        "residual_speed_hz": N, "response_1x_m": N, "response_1x_m_std": N,
        "vibration_1x": O, "specific_unbalance_um": N, "specific_unbalance_um_std": N,
        "iso_21940_11": {"required_grade_mm_s": "number", "service_speed_rpm": N,
                         "permissible_residual_gmm": N, "permissible_specific_unbalance_um": N,
                         "achieved_grade_mm_s": N, "achieved_grade_mm_s_std": N,
                         "achieved_class": S_, "passed": B, "grade_mm_s": "number"},
        "reduction": {"applicable": "bool", "basis": S_, "factor": N, "factor_std": N,
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
    "analysis": "object",
    "warnings": L,
    "notes": L,
}

SECTIONS = ("report", "header", "balancing_quality", "dynamics", "analysis", "warnings",
            "notes")
