"""The 1X vibration in the quantity the user's sensors measure, and as displacement.

A lab table's probes may measure displacement, velocity (velocity pickups) or
acceleration (accelerometers) (:attr:`stand.lab.table.LabTable.quantity`).  The
identification fits the model in that quantity; the steady 1X amplitude is measured in
it too.  Here it is reported three ways: in the user's unit and amplitude convention,
as shaft displacement (a harmonic's amplitude divided by w^k, k = 1 for velocity, 2 for
acceleration: exact for the steady 1X line), and as the ISO 20816 vibration velocity
(RMS, mm/s).
"""
from __future__ import annotations

import math

from stand.lab.units import AMPLITUDE, VIBRATION, split_convention

__all__ = ["VIBRATION", "vibration_in_users_quantity"]

TWO_PI = 2 * math.pi


def vibration_in_users_quantity(d, out) -> None:
    """``out["vibration_1x"]`` and ``out["response_1x_m"]`` as displacement [m].

    ``out["response_1x_m"]`` arrives as the 1X peak amplitude in the channel's SI unit
    (m, m/s or m/s²); ``d["quantity"]`` says which.
    """
    q = d.get("quantity", "length")
    a, f = out.get("response_1x_m"), out.get("speed_hz")
    if a is None or not f:
        return
    k = VIBRATION[q]
    w = TWO_PI * f
    disp = a / w ** k
    out["response_1x_m"] = disp
    if out.get("response_1x_m_std") is not None:
        out["response_1x_m_std"] = out["response_1x_m_std"] / w ** k
    tab = d.get("table")
    sa = out.get("response_1x_m_std")
    rel = sa / disp if sa is not None and disp else None      # the 1X's relative std
    v_rms = w * disp / math.sqrt(2.0) * 1e3
    doc = {"quantity": {"length": "displacement"}.get(q, q), "displacement_peak_m": disp,
           "displacement_peak_m_std": sa, "velocity_rms_mm_s": v_rms,
           "velocity_rms_mm_s_std": None if rel is None else v_rms * rel,
           "velocity_rms_note": "ISO 20816: RMS of the 1X vibration velocity w |z1x| / sqrt 2"}
    if tab is not None and "x" in tab.columns:
        spec = tab.columns["x"]
        unit, conv = split_convention(spec.unit or "")
        try:
            scale = spec.si_factor("x")
        except ValueError:
            scale = None
        if scale:
            peak = a / scale
            value = peak / AMPLITUDE[conv] if conv else peak
            doc.update(unit=spec.unit, peak=peak, pk_pk=2 * peak, rms=peak / math.sqrt(2.0),
                       value=value, value_std=None if rel is None else value * rel,
                       convention=conv or "pk")
    out["vibration_1x"] = doc
