"""The two-plane section of the balancing report (``stand report --tracks FRONT.csv REAR.csv``).

Two laser screens at two axial positions (``[instruments.screen.<name>]``, tracked with
``stand track RUN.h5 --screen NAME``) give the shaft axis line (4.2), its points in the
two correction planes (4.3) and, through the scene's receptance (weights locked), the
residual unbalance in each plane (:func:`stand.analysis.two_plane.two_plane`).  Each plane's
residual is checked against its share of the ISO 21940-11 permissible residual
(:func:`dsp.two_plane.iso_two_plane_allocation`: the lever rule about the centre of mass
over the planes' distances, each share within 30-70 %).
"""
from __future__ import annotations

__all__ = ["two_plane_section", "TWO_PLANE_SCHEMA", "auto_two_plane_section"]

N, B, L = "number|null", "bool|null", "list"

#: required keys and types of the ``two_plane`` section
TWO_PLANE_SCHEMA = {
    "method": "string", "speed_hz": N, "screens": L, "planes": L,
    "iso_21940_11": {"required_grade_mm_s": "number", "service_speed_rpm": N, "rotor_mass_kg": N,
                     "permissible_gmm": N, "allocation": "string", "passed": B},
    "notes": L,
}

#: keys of each row of ``planes`` (units in the names; ``truth_*`` only when the scene
#: holds the unbalances)
PLANE_KEYS = ("plane", "axial_position_m", "unbalance_gmm", "unbalance_gmm_std", "angle_deg",
              "angle_deg_std", "correction_angle_deg", "correction_angle_deg_std",
              "permissible_gmm", "passed",
              "passed_with_uncertainty")


def two_plane_section(recording_path, tracks, grade, service_speed_rpm, warn) -> dict:
    """The ``two_plane`` section (plain types); ``warn(code, message)`` for a failed plane."""
    from stand.analysis.two_plane import two_plane

    doc = two_plane(recording_path, list(tracks), grade=grade,
                    service_speed_rpm=service_speed_rpm).to_dict()
    doc.pop("recording", None)
    for row in doc["planes"]:
        if not row["passed"]:
            warn("two_plane_iso_failed",
                 f"{row['plane']}: residual {row['unbalance_gmm']:.4g} g·mm exceeds its share "
                 f"{row['permissible_gmm']:.4g} g·mm of the ISO 21940-11 G{grade:g} permissible "
                 "residual")
    return doc


def auto_two_plane_section(recording_path, screens, grade, service_speed_rpm, warn) -> dict:
    """The ``two_plane`` section of a recording with two named screens, tracking each screen
    itself (``stand track RUN.h5 --screen NAME``, into a temporary folder)."""
    import tempfile
    from pathlib import Path

    from stand.analysis.tracking import track_frames, write_track_csv

    with tempfile.TemporaryDirectory(prefix="stand-report-tracks-") as tmp:
        tracks = []
        for name in screens:
            out = Path(tmp) / f"{name}.csv"
            write_track_csv(track_frames(str(recording_path), screen=name), out)
            tracks.append(str(out))
        doc = two_plane_section(recording_path, tracks, grade, service_speed_rpm, warn)
    for s, name in zip(doc.get("screens", []), screens):
        s["track"] = f"tracked by the report (screen {name})"
    return doc
