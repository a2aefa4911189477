"""Commands that read recordings and answer: ``stand analyze``, ``report``, ``influence``,
``balance``, ``daq``.
Each calls the API (:mod:`stand.api`, :mod:`stand.api.analysis`) and prints."""
from __future__ import annotations

import sys
from pathlib import Path

from stand.cli.common import (labelled, print_json, print_recognised, print_warnings,
                              say_not_applicable, shown)

__all__ = ["cmd_report", "cmd_analyze", "cmd_influence", "cmd_balance", "cmd_daq"]


#: endings of a batch report's ``-o`` that name its summary table, not its HTML directory
SUMMARY_ENDINGS = (".csv", ".json", ".parquet", ".pq")


def batch_report_outputs(output, summary) -> tuple:
    """``(summary table, HTML directory or None)`` of ``stand report FOLDER|GLOB``.

    ``-o`` ending in .csv, .json or .parquet is the summary table; any other ``-o`` is the
    directory of the HTML reports (one per recording and ``index.html``; created when
    missing), with the summary table ``--summary`` or else ``DIR/summary.csv``.

    Raises
    ------
    ValueError
        Neither ``-o`` nor ``--summary``; the summary given twice; ``-o`` ending in .html
        (a folder gets one report per recording) or naming an existing file.
    """
    if output is None:
        if not summary:
            raise ValueError("stand report FOLDER: give -o DIR (one HTML report per recording, "
                             "index.html and summary.csv in DIR) or -o/--summary SUMMARY.csv")
        return str(summary), None
    out = Path(output)
    if out.suffix.lower() in SUMMARY_ENDINGS:
        if summary:
            raise ValueError(f"-o {output} and --summary {summary}: both name the summary table; "
                             "give one (or -o DIR for the HTML reports)")
        return str(out), None
    if out.suffix.lower() in (".html", ".htm", ".pdf"):
        raise ValueError(f"-o {output}: a folder of recordings gets one report per recording: "
                         "give -o DIR (created if missing) or -o SUMMARY.csv")
    if out.exists() and not out.is_dir():
        raise ValueError(f"-o {output}: exists and is not a directory (for one HTML report per "
                         "recording); give a directory, or -o SUMMARY.csv")
    return str(summary or out / "summary.csv"), str(out)


def cmd_report(args) -> int:
    from stand.api import report
    from stand.api.analysis import is_batch, report_many
    from stand.cli.parser import _grade

    grade = _grade(args.grade)
    if is_batch(args.recording):
        summary, html_dir = batch_report_outputs(args.output, args.summary)
        if html_dir is not None:
            Path(html_dir).mkdir(exist_ok=True)      # each file in it is written atomically
        df, page = report_many(args.recording, summary, html_dir=html_dir, grade=grade,
                               service_speed_rpm=args.service_speed, recording_map=args.map,
                               columns=args.columns, workers=args.workers,
                               scheduler=args.scheduler, progress=sys.stderr.isatty())
        n_html = int(df["report"].fillna("").astype(bool).sum()) if "report" in df else 0
        where = (f"{n_html} HTML report{'s' if n_html != 1 else ''} and {Path(page).name} in "
                 f"{html_dir}/; " if html_dir is not None else "")
        print(f"{len(df)} recordings reported ({int((df['status'] != 'ok').sum())} failed): "
              f"{where}summary table {summary}")
        return 0
    if not args.output and not args.json_file and not args.json and not args.pdf:
        raise ValueError("stand report: give -o REPORT.html, --pdf REPORT.pdf, --json-file REPORT.json "
                         "or --json")
    doc = report(args.recording, grade=grade, service_speed_rpm=args.service_speed,
                 html_path=args.output, json_path=args.json_file, tracks=args.tracks,
                 recording_map=args.map, columns=args.columns, pdf_path=args.pdf)
    warnings = doc.get("warnings") or []
    print_warnings("report", warnings)
    if args.json:
        print_json(doc)
        return 0
    q = doc.get("balancing_quality") or {}
    iso = q.get("iso_21940_11") if isinstance(q.get("iso_21940_11"), dict) else {}
    parts = [f"{args.recording}: report -> "
             + ", ".join(str(o) for o in (args.output, args.pdf, args.json_file) if o)]
    residual = labelled(q, "residual_unbalance_gmm")
    if residual:
        parts.append(residual)
    if iso.get("passed") is not None:
        parts.append(f"ISO 21940-11 G{grade:g}: {'pass' if iso['passed'] else 'FAIL'}")
    n = len(warnings)
    parts.append(f"{n} warning{'s' if n != 1 else ''}" + (" (above)" if n else ""))
    print("; ".join(parts))
    return 0


def _analysis_lines(doc) -> list:
    """What ``stand analyze`` prints: each value the analysis gave, by its label
    (:mod:`stand.io.labels`), with its ± in the label's unit; nothing for what it did not give."""
    from stand.io.labels import label, regime_name
    from stand.io.numbers import plain, resolved, with_uncertainty

    lines = [labelled(doc, k) for k in ("natural_frequency_hz", "damping_ratio", "speed_hz")]
    one_x = labelled(doc, "response_1x_m")
    stretch = doc.get("stationary_stretch") or {}
    if one_x and stretch.get("t_start_s") is not None:
        one_x += f" (over {plain(stretch['t_start_s'])}–{plain(stretch['t_end_s'], 's')})"
    lines.append(one_x)
    vib = doc.get("vibration_1x") or {}
    if vib.get("quantity") not in (None, "displacement") and vib.get("peak") is not None:
        peak = with_uncertainty(vib["peak"], vib.get("value_std") if vib.get("convention") == "pk"
                                else None, vib.get("unit", ""))
        lines.append(f"{label('vibration_1x')}: {vib['quantity']} {peak} (peak)")
    if vib.get("velocity_rms_mm_s") is not None and resolved(doc.get("response_1x_m"),
                                                            doc.get("response_1x_m_std")):
        lines.append(labelled(vib, "velocity_rms_mm_s"))
    # without the vibrating mass the unbalance is per kg (the specific unbalance e)
    size = "unbalance_gmm" if doc.get("unbalance_gmm") is not None \
        else "specific_unbalance_gmm_per_kg"
    lines.append(labelled(doc, size))
    # an angle of an unbalance below resolution means nothing: not shown
    if resolved(doc.get(size), doc.get(f"{size}_std")):
        lines.append(labelled(doc, "unbalance_angle_deg", angle=True))
    g = doc.get("iso_grade")
    if g:
        achieved = shown(g, "achieved_grade_mm_s")
        lines.append(f"ISO 21940-11: {label('achieved_grade_mm_s').lower()} {achieved} "
                     f"({g['class']}), required G {plain(g['required_grade_mm_s'])} mm/s: "
                     + ("pass" if g["passed"] else "FAIL"))
    if doc.get("programme"):
        lines.append(f"{label('programme')}: {doc['programme']['kind']}"
                     + (f"; {label('speed_source').lower()} {doc['speed_source']}"
                        if doc.get("speed_source") else ""))
    crit = labelled(doc, "critical_speed_hz")
    if crit:
        lines.append(crit + (f" ({doc['critical_speed_method']})" if doc.get("critical_speed_method") else ""))
    lines += [labelled(doc, k) for k in ("precession_hz", "nutation_hz", "petals", "shape",
                                         "strongest_other_line_hz")]
    if doc.get("regime") is not None:       # the words of the report (one table)
        lines.append(f"{label('regime')}: {regime_name(doc['regime'])}")
    for c in doc.get("critical_speeds_hz") or []:
        lines.append(f"{label('regime_change')}: {regime_name(c['before'])} -> "
                     f"{regime_name(c['after'])} at {shown(c, 'speed_hz')}")
    lines += [f"note: {n}" for n in doc.get("notes") or []]
    return [f"  {line}" for line in lines if line]


def cmd_analyze(args) -> int:
    from stand.api import analyze
    from stand.api.analysis import analyze_many, is_batch, two_plane

    if is_batch(args.recording):
        if not args.output:
            raise ValueError("a folder or glob needs -o SUMMARY.csv|.parquet (one row per recording)")
        df = analyze_many(args.recording, args.output, grade=args.grade,
                          service_speed_rpm=args.service_speed, recording_map=args.map,
                          columns=args.columns, workers=args.workers, scheduler=args.scheduler,
                          progress=sys.stderr.isatty())
        bad = int((df["status"] != "ok").sum())
        print(f"{len(df)} recordings analysed ({bad} failed) -> {args.output}")
        return 0
    if not Path(args.recording).exists():
        raise FileNotFoundError(f"recording not found: {args.recording}")
    if args.tracks:
        doc = two_plane(args.recording, args.tracks, grade=args.grade,
                        service_speed_rpm=args.service_speed)
        if args.json:
            return print_json(doc) or 0
        for r in doc["planes"]:     # values rounded to their uncertainty (GUM 7.2.6)
            at = (f" at {shown(r, 'angle_deg', angle=True)} (correction at "
                  f"{shown(r, 'correction_angle_deg', angle=True)})"
                  if _resolved(r) else "")
            print(f"  {r['plane']} ({shown(r, 'axial_position_m')}): {shown(r, 'unbalance_gmm')}{at}; "
                  f"permissible {shown(r, 'permissible_gmm')}: {'pass' if r['passed'] else 'FAIL'}")
        return 0
    doc = analyze(args.recording, grade=args.grade, service_speed_rpm=args.service_speed,
                  recording_map=args.map, columns=args.columns)
    print_recognised(doc)
    if args.json:
        print_json({k: v for k, v in doc.items() if k != "regime_timeline"})
        return 0
    print(f"{args.recording}:")
    for line in _analysis_lines(doc):
        print(line)
    return 0


def _resolved(row) -> bool:
    """Whether a row's unbalance stands above its ± (else its angle is not shown)."""
    from stand.io.numbers import resolved

    return resolved(row.get("unbalance_gmm"), row.get("unbalance_gmm_std"))


def _after(after, before, unit: str, sig: int = 4) -> str:
    """A predicted residual: 0 when it is round-off (below 1e-9 of the value before: the
    corrections cancel the readings exactly, as many planes as readings)."""
    from stand.io.numbers import plain

    return plain(0 if abs(after) < 1e-9 * abs(before) else after, unit, sig)


def _influence_lines(res) -> list:
    """Influence-coefficient balancing as text: one line per correction plane, then the sensors."""
    import math

    from stand.io.numbers import plain, with_uncertainty as wu

    lines = [f"influence-coefficient balancing at {plain(res.speed_rad_s / (2 * math.pi), 'rev/s', 6)} "
             f"(condition number of A {plain(res.condition, sig=3)})"]
    for j, p in enumerate(res.planes):
        lines.append(f"  {p}: correction {wu(res.mass_g[j], res.mass_std_g[j], 'g')} at "
                     f"{wu(res.angle_deg[j], res.angle_std_deg[j], '°', resolution=False)}, radius "
                     f"{plain(res.radius_m[j] * 1e3, 'mm')} ({plain(res.correction_gmm[j], 'g·mm', 5)})")
    for i, s in enumerate(res.sensors):
        v = res.reference_m[i]
        lines.append(f"  sensor {s}: 1X {plain(abs(v) * 1e6, 'µm')} at "
                     f"{plain(math.degrees(math.atan2(v.imag, v.real)) % 360, '°')}, after correction "
                     f"(predicted) {_after(abs(res.residual_m[i]) * 1e6, abs(v) * 1e6, 'µm', 2)}")
    return lines


def cmd_influence(args) -> int:
    from stand.api.analysis import influence

    if len(args.recordings) < 2:
        raise ValueError("give the reference recording and one trial recording per --trial")
    res = influence(args.recordings[0], args.recordings[1:], args.trial, args.sensors)
    if args.json:
        print_json(res.to_dict())
    else:
        print("\n".join(_influence_lines(res)))
    return 0


def cmd_balance(args) -> int:
    """``stand balance JOB.toml``: corrections from a field-balancing job file."""
    from stand.api import balance
    from stand.api.analysis import save_influence
    from stand.io.numbers import plain, with_uncertainty

    res = balance(args.job, influence=args.influence, method=args.method, html_path=args.output,
                  pdf_path=args.pdf)
    if args.save_influence:
        save_influence(res, args.save_influence)
        print(f"influence matrix (each coefficient with its ±, measured by "
              f"{res['influence_measured_by']}) saved to {args.save_influence}",
              file=sys.stderr if args.json else sys.stdout)
    print_warnings("balance", res["warnings"])
    if args.json:
        print_json(res.to_dict())
        return 0
    mu, vu = res["mass_unit"], res["vibration_unit"]
    if res.get("verdict"):                         # the verdict first
        print("\n  ".join([res["verdict"]["headline"]] + res["verdict"]["lines"]))
    print(f"field balancing ({res['method']}, {res['solver']}): condition {plain(res['condition'], sig=3)}")
    for p, c in res["corrections"].items():
        line = (f"  {p}: {with_uncertainty(c['mass'], c['mass_std'] or None, mu)} @ "
                f"{with_uncertainty(c['angle_deg'], c['angle_std_deg'] or None, '°', resolution=False)}")
        if "split" in c:
            line += "  = " + " + ".join(f"{plain(h['mass'], mu)} in hole {h['hole']} "
                                         f"({plain(h['angle_deg'], '°')})" for h in c["split"])
        print(line)
    for r in res["residuals"]:
        at = f" at {plain(r['speed_rpm'], 'rpm', 6)}" if r["speed_rpm"] is not None else ""
        print(f"  {r['sensor']}{at}: {plain(r['before'])} -> {_after(r['after'], r['before'], vu)} "
              f"{res['amplitude']}"
              f" (predicted)")
    if res.get("trial_mass"):
        print("  suggested trial mass (force 10 % of the rotor weight per plane): " + ", ".join(
            f"{p} {plain(m, mu, 2)}" for p, m in res["trial_mass"].items()))
    ck = res.get("check")
    if ck:
        print(f"check run[{ck['run']}] (installed: " + ", ".join(
            f"{p} {plain(c['mass'], mu)} @ {plain(c['angle_deg'], '°')}"
            for p, c in ck["installed"].items()) + "):")
        for r in ck["sensors"]:
            at = f" at {plain(r['speed_rpm'], 'rpm', 6)}" if r["speed_rpm"] is not None else ""
            print(f"  {r['sensor']}{at}: measured {plain(r['measured'])} @ "
                  f"{plain(r['measured_deg'], '°')}, predicted {plain(r['predicted'])} @ "
                  f"{plain(r['predicted_deg'], '°')} {vu} {res['amplitude']}; after trim "
                  f"{_after(r['after_trim'], r['measured'], vu)} (predicted)")
        print("  trim: " + ", ".join(f"{p} {with_uncertainty(c['mass'], c['mass_std'] or None, mu)}"
                                     f" @ {plain(c['angle_deg'], '°')}" for p, c in ck["trim"].items()))
    return 0


def cmd_daq(args) -> int:
    from stand.api.analysis import daq
    from stand.errors import NotApplicable
    from stand.io.numbers import plain

    try:
        off = tuple(float(v) for v in args.offset.split(","))
    except ValueError:
        off = ()
    if len(off) != 2:
        raise ValueError(f"--offset = {args.offset!r}: two numbers X_UM,Y_UM (um)")
    try:
        truth = daq(args.recording, args.output, truth=args.truth, offset_um=off,
                    quantity=args.quantity, bode=args.bode)
    except NotApplicable as exc:
        return say_not_applicable("daq", str(exc))
    known = [f"{name} {plain(truth[k], u, 6)}" for k, name, u in (
        ("unbalance_gmm", "unbalance", "g·mm"), ("natural_frequency_hz", "f0", "Hz"),
        ("critical_speed_hz", "critical speed", "rev/s")) if truth.get(k) is not None]
    print(f"{args.recording} -> {args.output} (DAQ export)"
          + (f"; truth: {', '.join(known)}" if known else ""))
    return 0
