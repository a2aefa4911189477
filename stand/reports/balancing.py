"""Balancing-quality report (``stand report``): a view of ``stand analyze``'s result.

:func:`balancing_report` identifies nothing itself: it runs the one identification
chain, :func:`stand.analysis.identify.analyze` (every input ``stand analyze`` takes: a
Run, a Recording, a recording file, a lab table with its map, a Bode / polar table), and
presents its :class:`~stand.analysis.results.Analysis` with the scene's data and its
theory (:func:`stand.theories.planar.speedmap.scene_theory`).  The JSON document
(schema :data:`SCHEMA`, key by key with units in ``docs/reports.md``):

* ``header`` -- scene, masses, balancer capacity S, speeds;
* ``balancing_quality`` -- the identified residual unbalance against the ring zones
  (i S/16), the ISO 21940-11 permissible residual and the seeds' criteria, the reduction
  balancer-off / balancer-on, the 1X vibration in the sensors' quantity;
* ``dynamics`` -- natural frequency and damping (identified, and the model's), critical
  speeds (theory, the recording's resonance, the weights' synchrony events), the regime
  timeline, the settling after each event;
* ``analysis`` -- the analysis' own document, unchanged (``stand analyze --json``): every
  number above is a copy of one of it, or of the scene's data;
* ``warnings``, ``notes``.

The HTML is rendered from the JSON (:func:`stand.reports.html.render_html`); the figures
(:mod:`.balancing_figures`) draw the analysis and the channels it analysed.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from stand.io.jsonable import to_jsonable
from stand.reports.balancing_schema import FORMAT_VERSION, REGIME_NAMES, SCHEMA, SECTIONS
from stand.reports.html import check_schema, write_report

__all__ = ["balancing_report", "SCHEMA", "REGIME_NAMES", "FORMAT_VERSION", "zone"]

TWO_PI = 2.0 * math.pi

#: what the ± of an unbalance contains, by the analysis' route (the report's one line on it)
SCATTER_UNCERTAINTY = ("± is one standard uncertainty: the revolution-to-revolution scatter of "
                       "the 1X vector; the scene's mass, natural frequency and damping are "
                       "taken as exact")
RING_UNCERTAINTY = ("± is one standard uncertainty: the spot circle's radius (its scatter, or "
                    "the long-exposure circles' scatter) and the ring scale's calibration, "
                    "interpolated between the rings; the rings themselves (zone i -> i S/16) "
                    "are taken as exact")
FIT_UNCERTAINTY = ("± is one standard uncertainty: the model fit's statistical part with "
                   "correlated residuals, with what the rotor angle's source leaves open "
                   "(docs/lab_recordings.md); the rigid-rotor model and the vibrating mass "
                   "are taken as exact")


def zone(U_kg_m, S):
    """Ring zone i of an unbalance ``U_kg_m`` [kg m]: i S/16 <= U < (i + 1) S/16 (S the
    capacity [kg m]); None without an unbalance or a capacity."""
    if U_kg_m is None or not S or not math.isfinite(U_kg_m):
        return None
    return int(math.floor(U_kg_m / (S / 16.0) + 1e-9))


def balancing_report(recording_path, *, grade=6.3, service_speed_rpm=None, html_path=None,
                     json_path=None, tracks=None, recording_map=None, pdf_path=None):
    """Balancing-quality report of one recording; returns the report's JSON document.

    Parameters
    ----------
    recording_path : str, Path, Recording or Run
        Whatever ``stand analyze`` reads: an HDF5 recording, a lab table (CSV, Parquet,
        pandas HDF5; ``recording_map`` says its columns), a Bode / polar table, a
        :class:`stand.Recording` or a :class:`stand.Run` in memory (nothing is written but
        the outputs asked for).
    grade : float
        ISO 21940-11 balance quality grade G to check [mm/s] (default 6.3).
    service_speed_rpm : float, optional
        Maximum service speed [rpm]; default: the map's, else the recording's final speed.
    html_path, json_path, pdf_path : path, optional
        Where to write the self-contained HTML, the JSON and a PDF (page 1 the verdict and
        the key figures, then the tables).
    tracks : two paths, optional
        ``stand track RUN.h5 --screen NAME`` CSVs of a recording's two screens: adds the
        ``two_plane`` section (:mod:`.balancing_two_plane`).
    recording_map : stand.lab.recording_map.RecordingMap, optional
        Columns, units and the machine's data of a lab table.

    Returns
    -------
    stand.reports.result.Report
        The report (plain JSON types), keys and types of :data:`SCHEMA`.

    Raises
    ------
    FileNotFoundError
        The recording does not exist.
    ValueError
        Unreadable input (the message names the file and the field); bad ``grade`` [mm/s]
        or ``service_speed_rpm`` [rpm].
    """
    grade = float(grade)
    if not (math.isfinite(grade) and grade > 0):
        raise ValueError(f"grade = {grade!r} mm/s: must be a finite number > 0")
    if service_speed_rpm is not None:
        service_speed_rpm = float(service_speed_rpm)
        if not (math.isfinite(service_speed_rpm) and service_speed_rpm > 0):
            raise ValueError(f"service_speed_rpm = {service_speed_rpm!r}: must be > 0 rpm")
    from stand.analysis.identify import analyze
    from stand.io import __version__

    a = analyze(recording_path, grade=grade, service_speed_rpm=service_speed_rpm,
                recording_map=recording_map)
    ch = a.channels or {}
    sc = ch.get("rec_scene")
    scene = sc if getattr(sc, "kind", None) == "planar" else None
    notes = list(a["notes"])
    if sc is None:
        notes.append("no scene in the recording: the masses, the balancer's capacity, the ring "
                     "zones and the reduction factor are not available")
    elif scene is None:
        notes.append(f"the recorded scene's structure is {sc.structure_type}: the model-based "
                     "parts (chapter-5 planar rotor) are skipped")
    warnings: list = []

    def warn(code, message, severity="warning"):
        warnings.append({"code": code, "severity": severity, "message": message})

    header = _header(a, scene, recording_path, recording_map)
    if not a.get("iso_grade"):
        notes.append("ISO 21940-11 grade and the seeds' criteria not evaluated: they need the "
                     "identified unbalance, the rotor mass and the service speed (given, the "
                     "map's [rotor] service_speed, or the record's final speed)")
    bq = _quality(a, scene, grade, header, warn)
    dyn = _dynamics(a, scene, notes)
    _scene_warnings(a, scene, bq, dyn, warn)
    import datetime

    doc = {
        "report": {"kind": "balancing-quality", "format_version": FORMAT_VERSION,
                   "recording": source_name(recording_path),
                   "input_format": _input_format(recording_path, a),
                   "generator": f"stand {__version__}",
                   "generated": datetime.datetime.now(datetime.timezone.utc)
                   .strftime("%Y-%m-%d %H:%M UTC")},
        "header": header, "balancing_quality": bq, "dynamics": dyn,
        "analysis": a.to_dict(), "warnings": warnings, "notes": notes,
    }
    sections, extra = SECTIONS, {}
    two = _two_plane(recording_path, tracks, grade, service_speed_rpm, warn, notes)
    if two is not None:
        from stand.reports.balancing_two_plane import TWO_PLANE_SCHEMA

        doc["two_plane"] = two
        sections = sections[:-2] + ("two_plane",) + sections[-2:]
        extra["two_plane"] = TWO_PLANE_SCHEMA
    plain = to_jsonable(doc)
    problems = check_schema(plain, dict(SCHEMA, **extra))
    if problems:  # pragma: no cover -- a bug here, not bad input
        raise RuntimeError("balancing report does not match its schema: " + "; ".join(problems))
    figs = None
    if html_path or pdf_path:
        from stand.reports.balancing_figures import figures, polar_figures

        figs = {**polar_figures(plain, scene), **figures(a, recording_path)}
    from stand.reports.balancing_page import page_body, pdf_tables, verdict

    title = f"Balancing-quality report: {header['scene_name']}"
    banner = verdict(plain)
    out = write_report(title, plain, html_path=html_path, json_path=json_path, figures=figs,
                       sections=sections, banner=banner,
                       body=(lambda p: page_body(p, figs)) if html_path else None)
    if pdf_path:
        from stand.reports.pdf import write_pdf

        write_pdf(pdf_path, title, banner, figures=figs, tables=pdf_tables(plain))
    from stand.reports.result import Report

    return Report(out)


def source_name(source) -> str:
    """The name a report gives its input: a file's name, a Recording's file name, or
    ``<run of SCENE>`` for a run in memory."""
    path = getattr(source, "path", None) if not isinstance(source, (str, Path)) else source
    if path:
        return Path(path).name
    return f"<run of {getattr(getattr(source, 'scene', None), 'name', '') or 'a scene'}>"


def _input_format(source, a) -> str:
    """``"run"`` (in memory), ``"bode-table"``, ``"csv"``, ``"parquet"``, ``"hdf5-table"``
    or ``"hdf5"`` (a stand recording)."""
    if not isinstance(source, (str, Path)):
        return "run" if not getattr(source, "path", "") else "hdf5"
    if a.get("bode") is not None:
        return "bode-table"
    if a.channels is not None and a.channels.get("table") is not None:
        suffix = Path(source).suffix.lower()
        return {".parquet": "parquet", ".pq": "parquet"}.get(
            suffix, "hdf5-table" if suffix in (".h5", ".hdf5", ".hdf") else "csv")
    return "hdf5"


def _header(a, scene, source, recording_map=None) -> dict:
    """The machine (scene or map) and the record: sizes, speeds [Hz, rpm]."""
    ch = a.channels or {}
    t = ch.get("t")
    prog = (a.get("programme") or {}).get("stretches") or []
    speeds = [abs(s[k]) for s in prog for k in ("speed_start_hz", "speed_end_hz")]
    bode = a.get("bode")
    if bode:
        speeds = [abs(f) for f in bode["speed_hz"]]
    iso = a.get("iso_grade") or {}
    rmap = getattr(ch.get("table"), "recording_map", None) or recording_map
    mass = getattr(rmap, "mass_kg", None)
    name = (ch.get("scene_name") or getattr(ch.get("rec_scene"), "name", None)
            or Path(source_name(source)).stem)
    S = scene.weights_capacity() if scene is not None else 0.0
    n = None if t is None else int(t.size)
    return {
        "scene_name": str(name),
        "description": (scene.description or None) if scene is not None else None,
        "rotor_mass_kg": scene.rotor.mass if scene is not None else mass,
        "total_mass_kg": scene.total_mass if scene is not None else mass,
        "balancer_type": (" + ".join([scene.balancer.type] * bool(scene.balancer.count)
                                     + [b.kind for b in scene.bodies]) or scene.balancer.type)
                         if scene is not None else None,
        "weights": scene.balancer.count + len(scene.bodies) if scene is not None else None,
        "capacity_gmm": S * 1e6 if scene is not None else None,
        "rotor_unbalance_gmm": scene.rotor.unbalance * 1e6 if scene is not None else None,
        "e0": scene.rotor.unbalance / S if scene is not None and S > 0 else None,
        "duration_s": float(t[-1] - t[0]) if n else None,
        "samples": n if n else len((bode or {}).get("speed_hz") or []),
        "sample_rate_hz": float((n - 1) / (t[-1] - t[0])) if n and n > 1 else None,
        "max_speed_hz": max(speeds) if speeds else a.get("speed_hz"),
        "final_speed_hz": a.get("speed_hz"),
        "service_speed_rpm": iso.get("service_speed_rpm"),
    }


def _quality(a, scene, grade, header, warn) -> dict:
    """The ``balancing_quality`` section: the analysis' unbalance, 1X and ISO grade, read
    against the ring zones, the permissible residual and the seeds' criteria."""
    S = scene.weights_capacity() if scene is not None else 0.0
    U, sU = a.get("unbalance_gmm"), a.get("unbalance_gmm_std")
    iso_a = a.get("iso_grade") or {}
    mass = iso_a.get("mass_kg") or header.get("rotor_mass_kg")
    st = a.get("stationary_stretch") or {}
    fit = (a.get("runup") or {}).get("model_fit") or a.get("modes")
    U0 = a.get("initial_unbalance_gmm")
    e = a.get("specific_unbalance_gmm_per_kg")
    if e is None and U is not None and mass:
        e = U / mass
    se = sU / mass if e is not None and sU is not None and mass else None
    bq = {
        "initial_unbalance_gmm": U0,
        "initial_unbalance_source": ("scene: rotor's own unbalance M e at the start (balancer "
                                     "off)") if U0 is not None else None,
        "initial_zone": zone(None if U0 is None else U0 * 1e-6, S),
        "residual_unbalance_gmm": U, "residual_unbalance_gmm_std": sU,
        "residual_unbalance_angle_deg": a.get("unbalance_angle_deg"),
        "residual_unbalance_angle_deg_std": a.get("unbalance_angle_deg_std"),
        "unbalance_method": a.get("unbalance_method") or (
            "steady 1X with the scene's mass, natural frequency and damping"
            if U is not None and scene is not None else None),
        "uncertainty_statement": None if U is None else (
            FIT_UNCERTAINTY if fit else ((a.get("ring_reading") or {}).get("uncertainty_statement")
                                         or RING_UNCERTAINTY)
            if "calibration rings" in (a.get("unbalance_method") or "") else SCATTER_UNCERTAINTY),
        "residual_fraction_of_capacity": U * 1e-6 / S if U is not None and S > 0 else None,
        "residual_zone": zone(None if U is None else U * 1e-6, S),
        "residual_window_s": [st["t_start_s"], st["t_end_s"]] if st else [],
        "residual_speed_hz": a.get("speed_hz"),
        "response_1x_m": a.get("response_1x_m"), "response_1x_m_std": a.get("response_1x_m_std"),
        "vibration_1x": a.get("vibration_1x"),
        "specific_unbalance_um": e, "specific_unbalance_um_std": se,
        "ring_reading": a.get("ring_reading"),
        "truth_residual_unbalance_gmm": a.get("truth_unbalance_gmm"),
        "seed_criteria": [],
    }
    z = bq["residual_zone"]
    bq["residual_zone_label"] = None if z is None else f"zone {z}: between {z} S/16 and {z + 1} S/16"
    Up = iso_a.get("permissible_gmm")
    bq["iso_21940_11"] = {
        "required_grade_mm_s": grade, "service_speed_rpm": iso_a.get("service_speed_rpm"),
        "permissible_residual_gmm": Up,
        "permissible_specific_unbalance_um": Up / mass if Up is not None and mass else None,
        "achieved_grade_mm_s": iso_a.get("achieved_grade_mm_s"),
        "achieved_grade_mm_s_std": iso_a.get("achieved_grade_mm_s_std"),
        "achieved_class": iso_a.get("class"), "passed": iso_a.get("passed"),
        "grade_mm_s": grade}    # the required grade's name before 2026-11-30 (docs/results.md)
    if iso_a.get("passed") is False:
        warn("iso_grade_failed", f"ISO 21940-11: the residual unbalance exceeds the permissible "
             f"residual of the grade (achieved G {iso_a['achieved_grade_mm_s']:.3g} mm/s, required "
             f"G {grade:g} mm/s)")
    bq["reduction"] = _reduction(a, scene)
    rpm = iso_a.get("service_speed_rpm")
    if e is not None and rpm:
        from stand.model.balancers.liquid_chamber import (permissible_eccentricity_general,
                                                          permissible_eccentricity_household)
        for crit, fn, rel in (
                ("household (machines a person contacts): [e] = 6000/n µm",
                 permissible_eccentricity_household,
                 "washing machines, centrifuges, fans: any rotor a person touches"),
                ("general machine building (Reutlinger): [e] = 2e8/n^2 µm",
                 permissible_eccentricity_general, "general machinery")):
            e_per = fn(rpm) * 1e6
            bq["seed_criteria"].append({"criterion": crit, "relevant_for": rel,
                                        "permissible_specific_unbalance_um": e_per,
                                        "specific_unbalance_um": e, "passed": e <= e_per})
    return bq


def _reduction(a, scene) -> dict:
    """The analysis' reduction factor balancer off / on with what it rests on."""
    red = {"applicable": False, "basis": None, "factor": None, "factor_std": None,
           "factor_lower_bound": None, "percent": None, "decibel": None}
    if scene is None:
        red["basis"] = "no scene: no balancer-off unbalance to compare with"
    elif not scene.balancer.count:
        red["basis"] = ("the scene has no balancer: no balancer-on phase, no reduction factor "
                        "(the residual is the rotor's own unbalance)")
    elif a.get("reduction"):
        red.update(a["reduction"], applicable=True,
                   basis="the recording has only the balancer-on phase: balancer off = the "
                         "rotor's own unbalance M e (scene), balancer on = the identified residual")
    elif a.get("unbalance_gmm") is None:
        red["basis"] = "no residual unbalance identified (see the notes)"
    else:
        red["basis"] = "the rotor has no unbalance of its own (M e = 0): no reduction factor"
    return red


def _dynamics(a, scene, notes) -> dict:
    """The ``dynamics`` section: the analysis' natural frequency, critical speeds, regimes
    and settling beside the scene's model and theory."""
    nf = {"identified_hz": a.get("natural_frequency_hz"),
          "identified_hz_std": a.get("natural_frequency_hz_std"),
          "damping_ratio": a.get("damping_ratio"), "damping_ratio_std": a.get("damping_ratio_std"),
          "method": a.get("natural_frequency_method"), "model_hz": None,
          "model_damping_ratio": None}
    if nf["identified_hz"] is not None and nf["method"] is None:
        nf["method"] = ("modal fit of the 1X table" if a.get("modes") else
                        "free decay (matrix pencil + least squares)")
    if scene is not None:
        s = scene.supports
        nf["model_hz"] = scene.natural_frequency / TWO_PI
        nf["model_damping_ratio"] = s.damping_x / (2 * math.sqrt(s.stiffness_x * scene.total_mass))
    theory = []
    if scene is not None and scene.balancer.count > 0:
        try:
            import warnings as _w

            from stand.theories.planar.speedmap import scene_theory

            with _w.catch_warnings():
                _w.simplefilter("ignore")
                th = scene_theory(scene, closed_forms=False)   # its critical speeds only
            theory = [{"source": "theory", "speed_hz": c.hz, "speed_hz_std": None,
                       "event": f"{c.motion} {c.kind} stability ({c.source})"}
                      for c in th.critical_speeds]
        except Exception as exc:  # noqa: BLE001 -- TheoryError and numerical failures
            notes.append(f"theory (scene_theory) not available: {exc}")
    found = []
    if a.get("critical_speed_hz") is not None:
        found.append({"source": "recording (1X resonance of the run)",
                      "speed_hz": a["critical_speed_hz"],
                      "speed_hz_std": a.get("critical_speed_hz_std"),
                      "event": a.get("critical_speed_method")})
    for c in a.get("critical_speeds_hz") or []:
        found.append({"source": "recording (weights gain/lose synchrony)",
                      "speed_hz": c["speed_hz"], "speed_hz_std": c.get("speed_hz_std"),
                      "event": f"{REGIME_NAMES.get(c['before'], c['before'])} -> "
                               f"{REGIME_NAMES.get(c['after'], c['after'])} at t = "
                               f"{c['time_s']:.4g} s"})
    ths = np.array([r["speed_hz"] for r in theory])
    for r in found:
        k = int(np.argmin(np.abs(ths - r["speed_hz"]))) if ths.size else None
        r["nearest_theory_hz"] = None if k is None else float(ths[k])
        r["difference_hz"] = None if k is None else r["speed_hz"] - float(ths[k])
    segs = []
    for w in a.get("regime_timeline") or []:
        nm = REGIME_NAMES.get(w["regime"], w["regime"])
        if segs and segs[-1]["regime"] == nm:
            segs[-1].update(t_end_s=w["t_end_s"], speed_end_hz=w["speed_hz"])
            segs[-1]["windows"] += 1
        else:
            segs.append({"t_start_s": w["t_start_s"], "t_end_s": w["t_end_s"], "regime": nm,
                         "speed_start_hz": w["speed_hz"], "speed_end_hz": w["speed_hz"],
                         "windows": 1})
    return {"natural_frequency": nf, "theory_available": bool(theory),
            "critical_speeds": found + theory,
            "final_regime": REGIME_NAMES.get(a.get("regime"), a.get("regime")),
            "regime_timeline": segs, "settling": a.get("settling") or []}


def _two_plane(source, tracks, grade, service_speed_rpm, warn, notes):
    """The ``two_plane`` section: from the given tracks, or from a recording's two screens."""
    path = getattr(source, "path", source)
    if tracks:
        from stand.reports.balancing_two_plane import two_plane_section

        if not isinstance(path, (str, Path)) or not path:
            raise ValueError("tracks: two-plane balancing reads the screens' positions from a "
                             "recording file; write the run first (stand.save(run, path))")
        return two_plane_section(path, tracks, grade, service_speed_rpm, warn)
    if not (isinstance(path, (str, Path)) and path and Path(path).is_file()):
        return None
    from stand.recording.read import named_screens

    screens = named_screens(path)
    if len(screens) > 2:
        notes.append(f"the recording has {len(screens)} screens ({', '.join(screens)}); "
                     "two-plane balancing takes two: give --tracks")
    if len(screens) != 2:
        return None
    from stand.reports.balancing_two_plane import auto_two_plane_section

    notes.append(f"screens {' and '.join(screens)} tracked by the report (as `stand track "
                 "--screen`) for the two-plane section")
    return auto_two_plane_section(path, screens, grade, service_speed_rpm, warn)


def _scene_warnings(a, scene, bq, dyn, warn):
    """The ``warnings`` from the run's solver status, the scene and its theory: capacity
    exceeded (e0 > 1), stuck-ball risk band 1 < R < R* (5.182), stuck balls or a
    friction-limited residual observed, and model-validity flags (anisotropic supports,
    unequal weights, torque drive, near resonance, fewer than 8 samples per revolution,
    not settled)."""
    ch = a.channels or {}
    solver = ch.get("solver") or {}
    if solver and (solver.get("success") is False or (solver.get("status") or 0) < 0):
        warn("run_incomplete", f"the simulation stopped early: {solver.get('message', '')}")
    if scene is None:
        return
    S = scene.weights_capacity()        # balls and body weights, as the header's e0
    f_end = a.get("speed_hz")
    w_end = f_end * TWO_PI if f_end else None
    if S > 0:
        es = [scene.rotor.unbalance / S] + [p.eccentricity * (p.mass or scene.rotor.mass) / S
                                            for p in scene.perturbations if p.kind == "unbalance"]
        if max(es) > 1:
            warn("capacity_exceeded", f"e0 = {max(es):.4g} > 1: the unbalance exceeds the "
                 "balancer's capacity S; the weights cannot balance it (they gather on the light "
                 "side)")
    rpm = bq["iso_21940_11"]["service_speed_rpm"]
    w_service = rpm * TWO_PI / 60 if rpm else w_end
    if scene.balancer.count and w_service:
        from stand.scene.dimensionless import dimensionless
        from stand.theories.planar import qp

        p = dimensionless(scene)
        Rstar = qp.escape_speed(p.Rt, float(p.h[0]), 0.5 * (p.H_x + p.H_y))
        R = w_service / p.omega_1
        if 1 < R < Rstar:
            warn("stuck_ball_risk", f"speed ratio R = {R:.4g} lies in 1 < R < R* = {Rstar:.4g} "
                 "(escape speed (5.182)): the weights may stay stuck in the quasi-periodic motion")
    fr = dyn.get("final_regime")
    if fr == "stuck":
        warn("stuck_balls_observed", "the weights slip behind the rotor at the end of the record "
             "(quasi-periodic motion, stuck balls)")
    U = bq.get("residual_unbalance_gmm")
    if U is not None and S > 0 and fr in ("balanced", "side") and U * 1e-6 > S / 16 \
            and scene.rotor.unbalance <= S:
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
    if w_end and 0.9 < w_end / scene.natural_frequency < 1.1:
        warn("model_near_resonance", f"the residual is identified at R = "
             f"{w_end / scene.natural_frequency:.4g}, near resonance: the inversion is sensitive "
             "to the damping", "model-validity")
    t = ch.get("t")
    if w_end and t is not None and t.size > 1:
        spr = TWO_PI / w_end * (t.size - 1) / (t[-1] - t[0])
        if spr < 8:
            warn("model_undersampled", f"{spr:.3g} samples per revolution (< 8): the 1X order "
                 "tracking is coarse", "model-validity")
    set_rows = dyn.get("settling") or []
    if set_rows and not set_rows[-1]["settled"]:
        warn("not_settled", "the whirl had not settled at the end of the record: the residual "
             "is an upper bound of the final one", "model-validity")
