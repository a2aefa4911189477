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
  critical speeds found vs the theory (:func:`stand.theories.planar.speedmap.scene_theory`),
  the regime timeline, settling times after each perturbation;
* ``warnings`` -- capacity exceeded, stuck-ball risk band, friction-limited
  residual, model-validity flags;
* ``notes`` -- what could not be computed and why.

The HTML is rendered from the JSON by :func:`stand.reports.html.render_html`
(every number shown is in the JSON); the figures (matplotlib, Agg) show only
data read from the recording.

Modules: :mod:`.balancing_input` reads the recording, :mod:`.balancing_schema`
defines the document, :mod:`.balancing_quality` and :mod:`.balancing_dynamics`
compute its sections, :mod:`.balancing_figures` draws the figures and
:mod:`.signals` holds the signal helpers they share; this module assembles the
report, its header and its warnings.  The public names stay importable from here.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from stand.io.jsonable import to_jsonable
from stand.reports.balancing_dynamics import dynamics
from stand.reports.balancing_figures import figures
from stand.reports.balancing_input import load_record, source_name
from stand.reports.balancing_quality import balancing_quality
from stand.reports.balancing_schema import FORMAT_VERSION, REGIME_NAMES, SCHEMA, SECTIONS
from stand.reports.html import check_schema, write_report

__all__ = ["balancing_report", "SCHEMA", "REGIME_NAMES", "FORMAT_VERSION"]

TWO_PI = 2.0 * math.pi


def balancing_report(recording_path, *, grade=6.3, service_speed_rpm=None, html_path=None,
                     json_path=None, tracks=None, recording_map=None, pdf_path=None):
    """Balancing-quality report of one recording; returns the report's JSON document.

    Parameters
    ----------
    recording_path : str, Path, Recording or Run
        HDF5 recording (``stand run``) or CSV (``t_s, x_m, y_m`` [+ ``rotor_angle_rad`` or
        ``keyphasor``]); or a :class:`stand.Recording` already read, or a :class:`stand.Run`
        in memory (read where it is: nothing is written but the outputs asked for).
    grade : float
        ISO 21940-11 balance quality grade G to check [mm/s] (default 6.3).
    service_speed_rpm : float, optional
        Maximum service speed [rpm]; default: the recording's final constant speed.
    html_path, json_path : path, optional
        Where to write the self-contained HTML and the JSON (atomically, through
        :mod:`stand.io.atomic`).
    tracks : two paths, optional
        ``stand track RUN.h5 --screen NAME`` CSVs of a recording's two screens: adds the
        ``two_plane`` section (per-plane residual unbalance, its ISO 21940-11 share,
        pass/fail; :mod:`.balancing_two_plane`).
    recording_map : stand.lab.recording_map.RecordingMap, optional
        Columns, units and the machine's data of a lab table: adds the
        ``lab_identification`` section (``stand analyze``'s identification: programme,
        critical speed, natural frequency and damping from the run-up, unbalance, the
        rows excluded) and fills the quality and dynamics sections from it.
    pdf_path : path, optional
        A PDF of the report (matplotlib's PDF backend, no browser): page 1 holds
        the verdict and the key figures, then the tables (:mod:`.pdf`).

    Returns
    -------
    stand.reports.result.Report
        The report (plain JSON types), keys and types of :data:`SCHEMA`, units
        in the key names (docs/reports.md), as a result object (mapping and attribute
        access, ``to_dict()``, ``to_frame()``, ``plot()``).

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
    from stand.io import __version__

    rec = load_record(recording_path, recording_map)
    d = rec.data
    notes: list = list(d["notes"])
    warnings: list = []

    def warn(code, message, severity="warning"):
        warnings.append({"code": code, "severity": severity, "message": message})

    t, speed, rotating, i_st, scene = rec.t, rec.speed, rec.rotating, rec.steady, rec.scene
    if d["scene_error"]:
        notes.append(f"scene not usable: {d['scene_error']}")

    # ---------------- header
    S = (scene.balancer.capacity + sum(b.body.capacity for b in scene.bodies)
         if scene is not None else 0.0)
    Ms = scene.total_mass if scene is not None else None
    name = d["attrs"].get("scene_name") or (scene.name if scene is not None else None)
    if not name:
        name = Path(source_name(recording_path)).stem
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
    lab = None
    if d.get("table") is not None:
        from stand.reports.balancing_lab import lab_identification

        lab = lab_identification(recording_path, d["table"].recording_map, grade,
                                 service_speed_rpm, notes)
        rmap = d["table"].recording_map
        if service_speed_rpm is None and rmap.service_speed_rad_s:
            w_service, sv_src = rmap.service_speed_rad_s, "the recording map's [rotor] service_speed"
    header = {
        "scene_name": str(name),
        "description": (scene.description or None) if scene is not None else None,
        "rotor_mass_kg": scene.rotor.mass if scene is not None else None,
        "total_mass_kg": Ms,
        "balancer_type": (" + ".join([scene.balancer.type] * bool(scene.balancer.count)
                                     + [b.kind for b in scene.bodies]) or scene.balancer.type)
                         if scene is not None else None,
        "weights": scene.balancer.count + len(scene.bodies) if scene is not None else None,
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
    if scene is None and (lab is None or lab.get("unbalance_gmm") is None):
        notes.append("no scene in the recording: masses, capacity and the unbalance (which needs "
                     "mass, natural frequency and damping) are not available; the 1X response "
                     "is reported in metres")

    # ---------------- balancing quality
    bq = balancing_quality(rec, w_service, grade, notes, warn)

    # ---------------- dynamics
    dyn = dynamics(rec, notes, warn)
    if lab is not None:
        from stand.reports.balancing_lab import fill_from_lab

        fill_from_lab(lab, header, bq, dyn, grade, w_service, warn)

    # ---------------- warnings from the scene's theory
    _scene_warnings(rec, bq, dyn, w_service, final_speed, steady_len, warn, notes)

    import datetime

    doc = {
        "report": {"kind": "balancing-quality", "format_version": FORMAT_VERSION,
                   "recording": source_name(recording_path), "input_format": d["fmt"],
                   "generator": f"stand {__version__}",
                   "generated": datetime.datetime.now(datetime.timezone.utc)
                   .strftime("%Y-%m-%d %H:%M UTC")},
        "header": header,
        "balancing_quality": bq,
        "dynamics": dyn,
        "warnings": warnings,
        "notes": notes,
    }
    sections = SECTIONS
    extra = {}
    if lab is not None:
        from stand.reports.balancing_lab import LAB_SCHEMA

        doc["lab_identification"] = lab
        sections = SECTIONS[:-2] + ("lab_identification",) + SECTIONS[-2:]
        extra["lab_identification"] = LAB_SCHEMA
    auto_screens = []
    if not tracks:
        from stand.recording.read import named_screens

        path = getattr(recording_path, "path", recording_path)
        if isinstance(path, (str, Path)) and path and Path(path).is_file():
            auto_screens = named_screens(path)
        if len(auto_screens) > 2:
            notes.append(f"the recording has {len(auto_screens)} screens "
                         f"({', '.join(auto_screens)}); two-plane balancing takes two: give "
                         f"--tracks")
            auto_screens = []
        elif len(auto_screens) == 2:
            from stand.reports.balancing_two_plane import TWO_PLANE_SCHEMA, auto_two_plane_section

            doc["two_plane"] = auto_two_plane_section(path, auto_screens, grade,
                                                      service_speed_rpm, warn)
            notes.append(f"screens {' and '.join(auto_screens)} tracked by the report "
                         f"(as `stand track --screen`) for the two-plane section")
            sections = sections[:-2] + ("two_plane",) + sections[-2:]
            extra["two_plane"] = TWO_PLANE_SCHEMA
    if tracks:
        from stand.reports.balancing_two_plane import TWO_PLANE_SCHEMA, two_plane_section

        path = getattr(recording_path, "path", recording_path)
        if not isinstance(path, (str, Path)) or not path:
            raise ValueError("tracks: two-plane balancing reads the screens' positions from a "
                             "recording file; write the run first (stand.save(run, path))")
        doc["two_plane"] = two_plane_section(path, tracks, grade, service_speed_rpm, warn)
        sections = sections[:-2] + ("two_plane",) + sections[-2:]
        extra["two_plane"] = TWO_PLANE_SCHEMA
    plain = to_jsonable(doc)
    problems = check_schema(plain, dict(SCHEMA, **extra))
    if problems:  # pragma: no cover -- a bug here, not bad input
        raise RuntimeError("balancing report does not match its schema: " + "; ".join(problems))
    figs = None
    if html_path or pdf_path:
        from stand.reports.balancing_figures import polar_figures

        figs = {**polar_figures(plain, scene), **figures(rec)}
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


def _scene_warnings(rec, bq, dyn, w_service, final_speed, steady_len, warn, notes):
    """The ``warnings`` from the run's solver status, the scene and its theory.

    Capacity exceeded (e0 > 1), stuck-ball risk band 1 < R < R* (5.182),
    stuck balls or a friction-limited residual observed, failed ISO grade
    (added by the quality section), and model-validity flags (anisotropic
    supports, unequal weights, torque drive, near resonance, fewer than 8
    samples per revolution, short final stretch, not settled).  Speeds in
    rad/s, ``steady_len`` in s.
    """
    scene, d, t = rec.scene, rec.data, rec.t
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
        from stand.scene.dimensionless import dimensionless
        from stand.theories.planar import qp

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
