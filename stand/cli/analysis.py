"""Commands that read recordings and answer: ``stand analyze``, ``report``, ``influence``,
``balance``, ``daq``.
Each calls the library and prints."""
from __future__ import annotations

import sys
from pathlib import Path

from stand.cli.common import print_json, print_recognised, say_not_applicable

__all__ = ["report_row", "cmd_report", "cmd_analyze", "cmd_influence", "cmd_balance", "cmd_daq"]


def report_row(path, grade, service_speed_rpm, html_dir, recording_map=None):
    """One row of a batch report (never raises): writes <stem>.html next to the others."""
    from stand.reports.balancing import balancing_report

    row = {"file": path, "status": "ok", "error": "", "report": ""}
    try:
        out = str(Path(html_dir) / (Path(path).stem + ".html")) if html_dir else None
        doc = balancing_report(path, grade=grade, service_speed_rpm=service_speed_rpm, html_path=out,
                               recording_map=recording_map)
        row["report"] = out or ""
        q = doc.get("balancing_quality", {})
        for k, v in q.items():
            if isinstance(v, (int, float, str, bool)) or v is None:
                row[k] = v
        iso = q.get("iso_21940_11") or {}
        row["iso_passed"] = iso.get("passed")
        row["achieved_grade_mm_s"] = iso.get("achieved_grade_mm_s")
        row["warnings"] = len(doc.get("warnings", []))
    except Exception as exc:   # reported in the row: one bad file must not stop the batch
        row.update(status="error", error=f"{type(exc).__name__}: {exc}")
    return row


def cmd_report(args) -> int:
    from stand.analysis.batch import expand_sources, is_batch_source, run_batch, write_table

    from stand.cli.parser import _grade

    from stand.lab.recording_map import map_from_options

    grade = _grade(args.grade)
    rmap = map_from_options(args.columns, args.map)
    for o in (args.output, args.json_file, args.pdf):
        if o and not Path(o).resolve().parent.is_dir():
            raise FileNotFoundError(f"output directory of {o!r} does not exist")
    if is_batch_source(args.recording):
        files = expand_sources(args.recording)
        summary = args.summary or str(Path(args.output).with_suffix(".csv")) if args.output else args.summary
        if not summary:
            raise ValueError("a folder or glob needs --summary SUMMARY.csv (and optionally -o DIR/ for the HTML files)")
        html_dir = args.output if args.output and Path(args.output).is_dir() else None
        df = run_batch(files, report_row, workers=args.workers, scheduler=args.scheduler,
                       progress=sys.stderr.isatty(), grade=grade,
                       service_speed_rpm=args.service_speed, html_dir=html_dir, recording_map=rmap)
        from stand.reports.batch_summary import order_failures_first, write_summary_page

        df = order_failures_first(df)
        write_table(df, summary)
        page = write_summary_page(df, html_dir, grade) if html_dir else None
        print(f"{len(df)} recordings reported ({int((df['status'] != 'ok').sum())} failed) -> {summary}"
              + (f"; summary page {page}" if page else ""))
        return 0
    from stand.reports.balancing import balancing_report

    if not args.output and not args.json_file and not args.json and not args.pdf:
        raise ValueError("stand report: give -o REPORT.html, --pdf REPORT.pdf, --json-file REPORT.json "
                         "or --json")
    doc = balancing_report(args.recording, grade=grade, service_speed_rpm=args.service_speed,
                           html_path=args.output, json_path=args.json_file, tracks=args.tracks,
                           recording_map=rmap, pdf_path=args.pdf)
    if args.json:
        print_json(doc)
        return 0
    q = doc.get("balancing_quality", {})
    print(f"{args.recording}: report -> {', '.join(str(o) for o in (args.output, args.pdf, args.json_file) if o)}"
          + (f"; residual {q.get('residual_unbalance_gmm'):.4g} g mm" if isinstance(q.get('residual_unbalance_gmm'), (int, float)) else "")
          + (f", ISO 21940-11 G{grade:g}: {'pass' if q['iso_21940_11'].get('passed') else 'fail'}"
             if isinstance(q.get("iso_21940_11"), dict) and q["iso_21940_11"].get("passed") is not None else "")
          + f"; {len(doc.get('warnings', []))} warning(s)")
    return 0


def cmd_analyze(args) -> int:
    from dsp.errors import SignalError

    from stand.analysis.identify import analyze
    from stand.analysis.batch import analyze_row, expand_sources, is_batch_source, run_batch, write_table
    from stand.recording.hdf5 import RecordingError

    from stand.lab.recording_map import map_from_options

    rmap = map_from_options(args.columns, args.map)
    if is_batch_source(args.recording):
        files = expand_sources(args.recording)
        if not args.output:
            raise ValueError("a folder or glob needs -o SUMMARY.csv|.parquet (one row per recording)")
        if not Path(args.output).resolve().parent.is_dir():
            raise FileNotFoundError(f"output directory of {args.output!r} does not exist")
        df = run_batch(files, analyze_row, workers=args.workers, scheduler=args.scheduler,
                       progress=sys.stderr.isatty(), grade=args.grade,
                       service_speed_rpm=args.service_speed, recording_map=rmap)
        write_table(df, args.output)
        bad = int((df["status"] != "ok").sum())
        print(f"{len(df)} recordings analysed ({bad} failed) -> {args.output}")
        return 0
    if not Path(args.recording).exists():
        raise FileNotFoundError(f"recording not found: {args.recording}")
    if args.tracks:
        from stand.analysis.identify import two_plane
        doc = two_plane(args.recording, args.tracks, grade=args.grade, service_speed_rpm=args.service_speed)
        if args.json:
            return print_json(doc) or 0
        from stand.io.numbers import with_uncertainty as wu
        for r in doc["planes"]:     # values rounded to their uncertainty (GUM 7.2.6)
            print(f"  {r['plane']} ({r['axial_position_m']:g} m): "
                  f"{wu(r['unbalance_gmm'], r['unbalance_gmm_std'], 'g*mm')} at "
                  f"{wu(r['angle_deg'], r['angle_deg_std'], 'deg', resolution=False)} (correction at "
                  f"{wu(r['correction_angle_deg'], r['correction_angle_deg_std'], 'deg', resolution=False)}); "
                  f"permissible {r['permissible_gmm']:.4g}: {'pass' if r['passed'] else 'FAIL'}")
        return 0
    try:
        doc = analyze(args.recording, grade=args.grade, service_speed_rpm=args.service_speed,
                      recording_map=rmap)
    except (RecordingError, SignalError) as exc:
        raise ValueError(str(exc)) from None
    print_recognised(doc)
    if args.json:
        print_json({k: v for k, v in doc.items() if k != "regime_timeline"})
        return 0
    from stand.io.numbers import with_uncertainty

    def fmt(v, sd=None, unit="", angle=False):
        """``v ± sd`` rounded to the uncertainty (the report's rounding)."""
        return "n/a" if v is None else with_uncertainty(v, sd, unit, resolution=not angle)
    print(f"{args.recording}:")
    print(f"  natural frequency {fmt(doc['natural_frequency_hz'], doc['natural_frequency_hz_std'], 'Hz')}, "
          f"damping ratio {fmt(doc['damping_ratio'], doc['damping_ratio_std'])}")
    print(f"  speed {fmt(doc['speed_hz'], None, 'rev/s')}, 1X {fmt(doc['response_1x_m'], doc.get('response_1x_m_std'), 'm')}, "
          f"unbalance {fmt(doc['unbalance_gmm'], doc['unbalance_gmm_std'], 'g*mm')} at "
          f"{fmt(doc['unbalance_angle_deg'], doc.get('unbalance_angle_deg_std'), 'deg', angle=True)}")
    if doc["iso_grade"]:
        g = doc["iso_grade"]
        print(f"  ISO 21940-11: G {fmt(g['grade_mm_s'], g.get('grade_mm_s_std'), 'mm/s')} "
              f"({g['class']}), target G {g['target_mm_s']}: "
              + ("pass" if g["passed"] else "FAIL"))
    if doc.get("programme"):
        print(f"  programme {doc['programme']['kind']}; speed from {doc.get('speed_source')}")
    if doc.get("critical_speed_hz") is not None:
        print(f"  critical speed {fmt(doc['critical_speed_hz'], doc.get('critical_speed_hz_std'), 'rev/s')} "
              f"({doc['critical_speed_method']})")
    print(f"  precession {fmt(doc['precession_hz'], doc.get('precession_hz_std'), 'Hz')}, "
          f"nutation {fmt(doc['nutation_hz'], doc.get('nutation_hz_std'), 'Hz')}, "
          f"petals {doc['petals']}, shape {doc['shape']}; regime {doc['regime']}")
    for c in doc["critical_speeds_hz"]:
        print(f"  regime change {c['before']} -> {c['after']} at {c['speed_hz']:.4g} +- {c['speed_hz_std']:.2g} rev/s")
    for n in doc["notes"]:
        print(f"  note: {n}")
    return 0


def cmd_influence(args) -> int:
    from stand.analysis.influence import cli_influence
    return cli_influence(args.recordings, args.trial, args.sensors, as_json=args.json)


def cmd_balance(args) -> int:
    """``stand balance JOB.toml``: corrections from a field-balancing job file."""
    from stand.analysis.field_balance import influence_toml
    from stand.api import balance

    res = balance(args.job, influence=args.influence, method=args.method, html_path=args.output,
                  pdf_path=args.pdf)
    if args.save_influence:
        from stand.io.atomic import write_text

        write_text(args.save_influence, influence_toml(res))
    for w in res["warnings"]:
        print(f"stand balance: warning: {w}", file=sys.stderr)
    if args.json:
        print_json(res.to_dict())
        return 0
    mu, vu = res["mass_unit"], res["vibration_unit"]
    print(f"field balancing ({res['method']}, {res['solver']}): condition {res['condition']:.3g}")
    from stand.io.numbers import with_uncertainty

    for p, c in res["corrections"].items():
        line = (f"  {p}: {with_uncertainty(c['mass'], c['mass_std'] or None, mu)} @ "
                f"{with_uncertainty(c['angle_deg'], c['angle_std_deg'] or None, 'deg', resolution=False)}")
        if "split" in c:
            line += "  = " + " + ".join(f"{h['mass']:.4g} {mu} in hole {h['hole']} "
                                         f"({h['angle_deg']:.1f} deg)" for h in c["split"])
        print(line)
    for r in res["residuals"]:
        at = f" at {r['speed_rpm']:.6g} rpm" if r["speed_rpm"] is not None else ""
        print(f"  {r['sensor']}{at}: {r['before']:.4g} -> {r['after']:.4g} {vu} {res['amplitude']}"
              f" (predicted)")
    return 0


def cmd_daq(args) -> int:
    from stand.lab.daq_export import daq_export

    try:
        off = tuple(float(v) for v in args.offset.split(","))
    except ValueError:
        off = ()
    if len(off) != 2:
        raise ValueError(f"--offset = {args.offset!r}: two numbers X_UM,Y_UM (um)")
    from stand.errors import NotApplicable

    try:
        if getattr(args, "bode", False):
            from stand.lab.daq_export import daq_bode

            truth = daq_bode(args.recording, args.output, truth_path=args.truth)
        else:
            truth = daq_export(args.recording, args.output, truth_path=args.truth, offset_um=off,
                               quantity=getattr(args, "quantity", "displacement"))
    except NotApplicable as exc:
        return say_not_applicable("daq", str(exc))
    print(f"{args.recording} -> {args.output} (DAQ export); truth: unbalance "
          f"{truth.get('unbalance_gmm', float('nan')):.6g} g*mm, f0 "
          f"{truth.get('natural_frequency_hz', float('nan')):.6g} Hz, critical speed "
          f"{truth.get('critical_speed_hz', float('nan')):.6g} rev/s")
    return 0
