"""The ``stand`` command line.

    stand run SCENE.toml -o RUN.h5 [--json] [--method M] [--no-progress]
    stand accuracy SCENE.toml [--json] [--rtols 1e-4,1e-6,...] [--methods DOP853,Radau]
    stand theory SCENE.toml [--json] [--plot MAP.png] [--max-speed REV_PER_S]
    stand snapshot RUN.h5 [--instrument screen|strobe|rings] [--frame N] -o FRAME.png
    stand experiment SCENE.toml PROGRAMME [options] -o RUN.h5
    stand analyze RUN.h5|RUN.csv [--json] [--grade G] [--service-speed RPM]
    stand track FRAMES -o track.csv [--calibration RINGS.png] [--ring-radii R1,R2,...|RINGS.txt]
                [--roi X,Y,W,H] [--background median|DARK.png] [--exposure S]
    stand video RUN.h5 -o screen.mp4 [--screen NAME] [--qp 10]
    stand strobe FRAMES -o angles.csv [--weights N]
    stand warmup [--all]

Exit codes: 0 success; 1 the simulation stopped early (what was computed is
still written); 2 invalid input (scene, arguments, files).

One BLAS thread per process: the command line's parallelism is processes (batch
and sweep workers), and the identification's matrices are small: on a busy
2-core machine OpenBLAS' threads made ``stand analyze`` 10x slower (1.1 s
instead of 0.08 s).  A value set in the environment is kept.
"""
from __future__ import annotations

import os

for _v in ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "BLIS_NUM_THREADS", "VECLIB_MAXIMUM_THREADS"):
    os.environ.setdefault(_v, "1")   # before numpy is imported (module docstring)

import argparse  # noqa: E402
import sys  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402


def _print_json(doc) -> None:
    """``--json``: the document on stdout (one JSON converter, strict JSON)."""
    from stand.io.jsonable import dumps

    print(dumps(doc, indent=2))


def _not_applicable(command: str, why: str) -> int:
    """A command that does not apply to a scene says so and why, and succeeds."""
    print(f"stand {command}: not applicable: {why}")
    return 0


def _cmd_run(args) -> int:
    from stand.api import load, run
    from stand.recording.hdf5 import check_output_path

    scene = load(args.scene)
    out = check_output_path(args.output)  # before the run, not after it
    res = run(scene, method=args.method, progress=not args.no_progress and sys.stderr.isatty(),
              checkpoint=args.checkpoint)
    res.write(out)
    summ = res.summary()
    final = summ.get("final") or {}
    doc = {"scene": scene.name, "structure": scene.structure_type, "output": str(out),
           "solver": summ["solver"], **final, "final": final, "notes": list(res.notes)}
    if args.json:
        _print_json(doc)
    else:
        st = res.stats
        print(f"{scene.name} ({scene.structure_type}): {st.message} [{st.method}, {st.n_steps} steps, "
              f"{st.nfev} RHS evaluations, {st.wall_time:.2f} s] -> {out}")
        if final:
            ru = final.get("residual_unbalance")
            print(f"  t = {final['time_s']:.6g} s, speed {final['rotor_speed_rev_per_s']:.4g} rev/s, "
                  f"plane {final['main_plane']} whirl radius {final['whirl_radius_m']:.4g} m"
                  + (f", residual unbalance {100 * ru:.3g} % of S" if ru is not None else ""))
        for n in res.notes:
            print(f"  note: {n}")
    if not res.stats.success:
        print(f"stand run: {res.stats.message}", file=sys.stderr)
        return 1
    return 0


def _cmd_accuracy(args) -> int:
    from stand.integrate.accuracy import DEFAULT_RTOLS, FAST_REFERENCE_RTOL, FAST_RTOLS, accuracy
    from stand.scene.parse import load_scene

    scene = load_scene(args.scene)
    rtols = FAST_RTOLS if args.fast else DEFAULT_RTOLS
    if args.rtols:
        try:
            rtols = tuple(float(v) for v in args.rtols.split(","))
        except ValueError:
            raise ValueError(f"--rtols = {args.rtols!r}: must be a comma-separated list of numbers")
        if not all(0 < r < 1 for r in rtols):
            raise ValueError(f"--rtols = {args.rtols!r}: each tolerance must be in (0, 1)")
    methods = args.methods.split(",") if args.methods else None
    steps = None
    if args.rk4_steps:
        try:
            steps = tuple(float(v) for v in args.rk4_steps.split(","))
        except ValueError:
            raise ValueError(f"--rk4-steps = {args.rk4_steps!r}: comma-separated steps in s") from None
        if not all(v > 0 for v in steps):
            raise ValueError(f"--rk4-steps = {args.rk4_steps!r}: steps must be > 0 (s)")
    if methods:
        from stand.scene.model import METHODS
        bad = [m for m in methods if m not in METHODS and m != "RK4"]
        if bad:
            raise ValueError(f"--methods: unknown {', '.join(bad)}; valid: {', '.join(METHODS)}, RK4")
    if args.output or args.json_file:
        from stand.reports.accuracy_report import accuracy_report

        for o in (args.output, args.json_file):
            if o and not Path(o).resolve().parent.is_dir():
                raise FileNotFoundError(f"output directory of {o!r} does not exist")

        doc = accuracy_report(scene, rtols=rtols if args.rtols else (1e-4, 1e-6, 1e-8, 1e-10),
                              methods=methods, rk4_steps=steps, html_path=args.output,
                              json_path=args.json_file)
        if args.json:
            _print_json(doc)
        else:
            rec = doc["recommended"]
            print(f"{scene.name}: {len(doc['runs'])} runs against {doc['reference']['name']}; "
                  f"recommended: {rec.get('method')} "
                  + (f"rtol {rec['rtol']:g}" if rec.get("rtol") else f"step {rec.get('step_s')}")
                  + (f" ({rec['relative_error']:.2g} relative error, {rec['wall_time_s']:.3g} s)"
                     if rec.get("relative_error") is not None else "")
                  + ("" if rec.get("reached") else " -- the target was not reached")
                  + (f" -> {args.output}" if args.output else ""))
        return 0
    rep = accuracy(scene, rtols=rtols, methods=methods, rk4_steps=steps,
                   reference_rtol=FAST_REFERENCE_RTOL if args.fast else None)
    if args.json:
        _print_json(rep.to_dict())
    else:
        print(rep.table())
    return 0


def _report_row(path, grade, service_speed_rpm, html_dir, recording_map=None):
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


def _cmd_report(args) -> int:
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
        df = run_batch(files, _report_row, workers=args.workers, scheduler=args.scheduler,
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
        _print_json(doc)
        return 0
    q = doc.get("balancing_quality", {})
    print(f"{args.recording}: report -> {', '.join(str(o) for o in (args.output, args.pdf, args.json_file) if o)}"
          + (f"; residual {q.get('residual_unbalance_gmm'):.4g} g mm" if isinstance(q.get('residual_unbalance_gmm'), (int, float)) else "")
          + (f", ISO 21940-11 G{grade:g}: {'pass' if q['iso_21940_11'].get('passed') else 'fail'}"
             if isinstance(q.get("iso_21940_11"), dict) and q["iso_21940_11"].get("passed") is not None else "")
          + f"; {len(doc.get('warnings', []))} warning(s)")
    return 0


def _cmd_sweep(args) -> int:
    from stand.sweep import sweep_main

    return sweep_main(args)


def _cmd_stress(args) -> int:
    from stand.reports.stress import DEFAULT_CATALOGUE, run_stress

    for o in (args.output, args.json_file):
        if o and not Path(o).resolve().parent.is_dir():
            raise FileNotFoundError(f"output directory of {o!r} does not exist")
    cases = None
    if args.cases:
        cases = "fast" if args.cases == "fast" else [c.strip() for c in args.cases.split(",")]
    doc = run_stress(args.catalogue or DEFAULT_CATALOGUE, cases=cases, html_path=args.output,
                     json_path=args.json_file, progress=sys.stderr.isatty())
    if args.json:
        _print_json(doc)
    else:
        for c in doc["cases"]:
            print(f"  {'PASS' if c.get('pass') else 'FAIL'}  {c.get('name')}: {c.get('reason', '')}")
        s = doc["summary"]
        print(f"stand stress: {s.get('n_passed')} of {s.get('n_cases')} cases passed "
              f"in {s.get('total_time_s', 0):.0f} s"
              + (f" -> {args.output}" if args.output else ""))
    return 0 if doc["summary"].get("all_passed") else 1


def _cmd_theory(args) -> int:
    from stand.api import load
    from stand.theories.scene import theory, theory_lines

    scene = load(args.scene)
    if args.plot and not Path(args.plot).resolve().parent.exists():
        raise FileNotFoundError(f"plot directory {str(Path(args.plot).parent)!r} does not exist")
    doc = theory(scene, max_speed=args.max_speed, floquet=not args.no_floquet)
    if args.plot:
        if doc["kind"] == "chapter5":
            from stand.theories.planar.speedmap import plot_speed_map, scene_theory

            plot_speed_map(scene_theory(scene, R_max=args.max_speed * 2 * np.pi / scene.natural_frequency
                                        if args.max_speed else None), args.plot)
        else:
            doc["not_applicable"].append("--plot: the speed map is drawn for the chapter-5 planar "
                                         "rotor with weights only")
    if args.json:
        _print_json(doc)
        return 0
    for line in theory_lines(doc):
        print(line)
    if args.plot and doc["kind"] == "chapter5":
        print(f"speed map written to {args.plot}")
    return 0


def _cmd_snapshot(args) -> int:
    import cv2

    from stand.api import read
    from stand.io.atomic import atomic_path

    name = {"screen": "instruments/screen/frames", "strobe": "instruments/stroboscope/frames",
            "rings": "instruments/screen/calibration_image"}[args.instrument]
    rec = read(args.recording)
    shape = rec.shape(name)
    if shape is None:
        return _not_applicable("snapshot", f"{args.recording} holds no {args.instrument} images "
                               f"(dataset {name!r}): its scene had no "
                               f"[instruments.{'stroboscope' if args.instrument == 'strobe' else 'screen'}]")
    if len(shape) == 3:
        if not -shape[0] <= args.frame < shape[0]:
            raise ValueError(f"--frame = {args.frame}: the recording has {shape[0]} "
                             f"{args.instrument} frames")
        img = rec.dataset(name, args.frame)
    else:
        img = rec.dataset(name)
    with atomic_path(args.output, suffix=".png") as tmp:
        if not cv2.imwrite(tmp, img):
            raise ValueError(f"could not encode {args.output}")
    print(f"{args.instrument} frame {args.frame} -> {args.output}")
    return 0


def _cmd_experiment(args) -> int:
    from stand.scene.experiments import PROGRAMMES, not_applicable, programme
    from stand.instruments.pipeline import run_with_instruments
    from stand.recording.hdf5 import check_output_path, write_recording
    from stand.scene.parse import load_scene

    base = load_scene(args.scene)
    out = check_output_path(args.output)
    why = not_applicable(base, args.programme)
    if why:
        return _not_applicable("experiment", why)
    p = args.programme
    # the builders' arguments (stand.scene.experiments.PROGRAMMES) from the command's flags
    opts = dict(speed=args.speed, rate=args.rate, hold=args.hold, band=args.band,
                duration=args.change_time if p == "unbalance" else args.duration, time=args.time,
                exponential=args.exponential, at=args.at, start=args.at,
                eccentricity=args.eccentricity, angle_deg=args.angle, velocity=args.velocity,
                end=args.end, force=args.side_force, stiffness=args.stiffness,
                deflection=args.deflection)
    flag = {"start": "at", "force": "side-force", "angle_deg": "angle"}
    for k in PROGRAMMES[p][1]:
        if opts[k] is None:
            raise ValueError(f"stand experiment {p}: --{flag.get(k, k)} is required")
    sc = programme(base, p, **opts)
    res, writer = run_with_instruments(sc, progress=sys.stderr.isatty())
    write_recording(res, out, writer=writer, extra_attrs={"experiment": {
        "programme": p, **{k: v for k, v in vars(args).items() if k != "func" and v is not None}}})
    st = res.stats
    print(f"{sc.name} / {p}: {st.message} [{st.method}, {st.wall_time:.2f} s] -> {out}")
    return 0 if st.success else 1


def _cmd_daq(args) -> int:
    from stand.lab.daq_export import daq_export

    try:
        off = tuple(float(v) for v in args.offset.split(","))
    except ValueError:
        off = ()
    if len(off) != 2:
        raise ValueError(f"--offset = {args.offset!r}: two numbers X_UM,Y_UM (um)")
    from stand.errors import NotApplicable

    try:
        truth = daq_export(args.recording, args.output, truth_path=args.truth, offset_um=off)
    except NotApplicable as exc:
        return _not_applicable("daq", str(exc))
    print(f"{args.recording} -> {args.output} (DAQ export); truth: unbalance "
          f"{truth.get('unbalance_gmm', float('nan')):.6g} g*mm, f0 "
          f"{truth.get('natural_frequency_hz', float('nan')):.6g} Hz, critical speed "
          f"{truth.get('critical_speed_hz', float('nan')):.6g} rev/s")
    return 0


def _print_recognised(doc) -> None:
    """A table read without a map: which column was taken for what (stderr)."""
    inp = doc.get("input") or {}
    if inp.get("recognised"):
        print("columns recognised (give --columns or --map to choose): "
              + "; ".join(inp["recognised"]), file=sys.stderr)
    for e in inp.get("excluded") or []:
        print(f"excluded rows {e['rows']}: {e['reason']}", file=sys.stderr)


def _cmd_analyze(args) -> int:
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
                       progress=sys.stderr.isatty(), grade_mm_s=args.grade,
                       service_speed_rpm=args.service_speed, recording_map=rmap)
        write_table(df, args.output)
        bad = int((df["status"] != "ok").sum())
        print(f"{len(df)} recordings analysed ({bad} failed) -> {args.output}")
        return 0
    if not Path(args.recording).exists():
        raise FileNotFoundError(f"recording not found: {args.recording}")
    if args.tracks:
        from stand.analysis.identify import two_plane
        doc = two_plane(args.recording, args.tracks, grade_mm_s=args.grade, service_speed_rpm=args.service_speed)
        if args.json:
            return _print_json(doc) or 0
        for r in doc["planes"]:
            print(f"  {r['plane']} ({r['axial_position_m']:g} m): {r['unbalance_gmm']:.6g} +- {r['unbalance_gmm_std']:.2g} g*mm "
                  f"at {r['angle_deg']:.4g} +- {r['angle_deg_std']:.2g} deg; permissible {r['permissible_gmm']:.4g}: {'pass' if r['passed'] else 'FAIL'}")
        return 0
    try:
        doc = analyze(args.recording, grade_mm_s=args.grade, service_speed_rpm=args.service_speed,
                      recording_map=rmap)
    except (RecordingError, SignalError) as exc:
        raise ValueError(str(exc)) from None
    _print_recognised(doc)
    if args.json:
        _print_json({k: v for k, v in doc.items() if k != "regime_timeline"})
        return 0
    def fmt(v, sd=None, unit=""):
        if v is None:
            return "n/a"
        return f"{v:.6g}{' +- %.2g' % sd if sd else ''} {unit}".strip()
    print(f"{args.recording}:")
    print(f"  natural frequency {fmt(doc['natural_frequency_hz'], doc['natural_frequency_hz_std'], 'Hz')}, "
          f"damping ratio {fmt(doc['damping_ratio'], doc['damping_ratio_std'])}")
    print(f"  speed {fmt(doc['speed_hz'], None, 'rev/s')}, 1X {fmt(doc['response_1x_m'], None, 'm')}, "
          f"unbalance {fmt(doc['unbalance_gmm'], doc['unbalance_gmm_std'], 'g*mm')} at "
          f"{fmt(doc['unbalance_angle_deg'], None, 'deg')}")
    if doc["iso_grade"]:
        g = doc["iso_grade"]
        print(f"  ISO 21940-11: G {g['grade_mm_s']:.3g} mm/s ({g['class']}), target G {g['target_mm_s']}: "
              + ("pass" if g["passed"] else "FAIL"))
    if doc.get("programme"):
        print(f"  programme {doc['programme']['kind']}; speed from {doc.get('speed_source')}")
    if doc.get("critical_speed_hz") is not None:
        print(f"  critical speed {fmt(doc['critical_speed_hz'], doc.get('critical_speed_hz_std'), 'rev/s')} "
              f"({doc['critical_speed_method']})")
    print(f"  precession {fmt(doc['precession_hz'], None, 'Hz')}, nutation {fmt(doc['nutation_hz'], None, 'Hz')}, "
          f"petals {doc['petals']}, shape {doc['shape']}; regime {doc['regime']}")
    for c in doc["critical_speeds_hz"]:
        print(f"  regime change {c['before']} -> {c['after']} at {c['speed_hz']:.4g} +- {c['speed_hz_std']:.2g} rev/s")
    for n in doc["notes"]:
        print(f"  note: {n}")
    return 0


def _write_csv(df, path) -> None:
    from stand.io.atomic import atomic_path

    with atomic_path(path, suffix=".csv.tmp") as tmp:
        df.to_csv(tmp, index=False)


def _cmd_track(args) -> int:
    from vision.io import VisionError

    from stand.analysis.tracking import track_frames, write_track_csv

    if not Path(args.output).resolve().parent.is_dir():
        raise FileNotFoundError(f"output directory of {args.output!r} does not exist")
    if sys.stderr.isatty() and not args.trace:
        from vision.blur import compile_needed

        if compile_needed():
            print("stand track: compiling the blurred-spot fit (one time, about 10 s; "
                  "`stand warmup` does it ahead)...", file=sys.stderr)
    try:
        df = track_frames(args.source, calibration=args.calibration, ring_radii=args.ring_radii,
                          gain=args.gain, threshold=args.threshold, trace=args.trace,
                          spot_sigma=args.spot_sigma, capacity_gmm=args.capacity,
                          optical_gain=args.optical_gain, progress=sys.stderr.isatty(),
                          screen=args.screen, roi=args.roi, background=args.background,
                          exposure=args.exposure)
    except VisionError as exc:
        raise ValueError(str(exc)) from None
    write_track_csv(df, args.output)
    ok = int(df["ok"].sum()) if "ok" in df else len(df)
    what = "trace" if args.trace else "spot"
    methods = ""
    if "method" in df and len(df):
        counts = df["method"].replace("", "none").value_counts()
        methods = " (" + ", ".join(f"{k} {v}" for k, v in counts.items()) + ")"
    if "flags" in df and len(df):
        fl = df["flags"].fillna("").astype(str)
        flagged = {f: int(fl.str.contains(f, regex=False).sum()) for f in ("not_refined", "fit_failed")}
        methods += "".join(f"; {f} {n}" for f, n in flagged.items() if n)
    print(f"{args.source}: {len(df)} frames, {what} found in {ok}{methods} -> {args.output}")
    return 0


def _cmd_video(args) -> int:
    from stand.io.guard import check_outputs
    from stand.instruments.video import sidecar_paths, write_screen_video

    side = sidecar_paths(args.output)
    check_outputs([args.recording], [(side["video"], side["video"].suffix.lstrip(".").lower()),
                                     (side["truth"], "csv"), (side["rings_png"], "png"),
                                     (side["rings_txt"], "csv")], force=args.force)
    if side["video"].exists() and not args.force:   # it may be a lab's own recording
        raise ValueError(f"output {args.output!r} exists: a video may be a recording nothing "
                         "can replace; give --force to overwrite it, or choose another output")
    from stand.errors import NotApplicable

    try:
        doc = write_screen_video(args.recording, args.output, screen=args.screen, qp=args.qp)
    except NotApplicable as exc:
        return _not_applicable("video", str(exc))
    extra = ", ".join(Path(doc[k]).name for k in ("truth", "rings_png", "rings_txt") if k in doc)
    print(f"{args.recording}: {doc['frames']} frames at {doc['frame_rate_hz']:g} Hz -> "
          f"{args.output} ({doc['codec']}, {doc['bytes'] / 1e6:.2f} MB); beside it: {extra}")
    return 0


def _cmd_strobe(args) -> int:
    from vision.io import VisionError

    from stand.analysis.tracking import strobe_angles

    if not Path(args.output).resolve().parent.is_dir():
        raise FileNotFoundError(f"output directory of {args.output!r} does not exist")
    try:
        df = strobe_angles(args.source, n_weights=args.weights)
    except VisionError as exc:
        raise ValueError(str(exc)) from None
    _write_csv(df, args.output)
    print(f"{args.source}: {len(df)} strobe frames -> {args.output}")
    return 0


def _cmd_influence(args) -> int:
    from stand.analysis.influence import cli_influence
    return cli_influence(args.recordings, args.trial, args.sensors, as_json=args.json)


def _cmd_warmup(args) -> int:
    from stand.integrate.warmup import warmup

    warmup(every_kind=args.all)
    return 0


def build_parser() -> argparse.ArgumentParser:
    """The argument parser (stand.cli.parser) with this module's command handlers."""
    from stand.cli.parser import build_parser as build

    return build({"accuracy": _cmd_accuracy, "analyze": _cmd_analyze, "daq": _cmd_daq, "experiment": _cmd_experiment, "influence": _cmd_influence, "report": _cmd_report, "run": _cmd_run, "snapshot": _cmd_snapshot, "stress": _cmd_stress, "strobe": _cmd_strobe, "sweep": _cmd_sweep, "theory": _cmd_theory, "track": _cmd_track, "video": _cmd_video, "warmup": _cmd_warmup})


def _table_kind(path) -> str:
    return "parquet" if str(path).lower().endswith((".parquet", ".pq")) else "csv"


def _guard(args) -> None:
    """Refuse outputs that are inputs or files of another kind (stand.io.guard), before any work."""
    from stand.io.guard import check_outputs

    g = lambda name: getattr(args, name, None)  # noqa: E731
    cmd = args.command
    inputs = [g("scene"), g("recording"), g("source"), g("calibration"), g("catalogue"), g("spec")]
    out = g("output")
    outputs = [(g("json_file"), "json"), (g("plot"), "png"), (g("summary"), _table_kind(g("summary"))),
               (g("regime_map"), "png"), (g("critical_map"), "png"), (g("pdf"), "pdf")]
    kind = {"run": "hdf5", "experiment": "hdf5", "accuracy": "html", "report": "html",
            "stress": "html", "snapshot": "png", "track": "csv", "strobe": "csv", "daq": "csv",
            "sweep": "parquet", "analyze": _table_kind(out)}.get(cmd)
    if out is not None and kind and not Path(out).is_dir():
        outputs.append((out, kind))
    if cmd == "run":
        outputs.append((g("checkpoint"), "npz"))
    check_outputs(inputs, outputs, force=bool(g("force")))


def _naming_the_input(args, exc) -> str:
    """The error as one line that names the input (or, for a failed write, the output) it is about."""
    import errno

    out = getattr(args, "output", None)
    if isinstance(exc, OSError) and out and (exc.errno in (errno.EFBIG, errno.ENOSPC, errno.EROFS,
                                                            errno.EACCES, errno.EPERM, errno.EDQUOT)
                                             or "write" in str(exc).lower()):
        why = exc.strerror or " ".join(str(exc).split())
        return (f"cannot write {out}: {why}; nothing was written under that name (an existing "
                f"file is unchanged)")
    msg = " ".join(str(exc).split())
    src = next((getattr(args, k) for k in ("scene", "recording", "source", "spec", "catalogue")
                if getattr(args, k, None)), None)
    if src is not None and Path(str(src)).name not in msg:
        msg = f"{src}: {msg}"
    return msg


def _background_precompile() -> None:
    """A command that ran a kernel on numba's JIT starts the build of its precompiled module
    (stand.integrate.kernel_set), so that the next command starts without numba."""
    ks = sys.modules.get("stand.integrate.kernel_set")
    if ks is not None:
        try:
            ks.precompile_in_background()
        except Exception:  # noqa: BLE001 - never let a background build spoil the command
            pass


def main(argv=None) -> int:
    from stand.scene.model import SceneError

    args = build_parser().parse_args(argv)
    try:
        _guard(args)
        return args.func(args)
    except (SceneError, ValueError, OSError) as exc:
        # OSError: missing files, permissions, a full disk or a file-size limit (EFBIG): the
        # outputs are written atomically, so what existed before is intact
        # TheoryError is a ValueError: out-of-scope scenes end here with their reason
        print(f"stand {args.command}: error: {_naming_the_input(args, exc)}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"stand {args.command}: interrupted", file=sys.stderr)
        return 130
    except MemoryError:
        print(f"stand {args.command}: error: not enough memory for this run (reduce run.duration * "
              "run.sample_rate or the number of weights)", file=sys.stderr)
        return 2
    except Exception as exc:  # last resort: a clear line, not a traceback
        print(f"stand {args.command}: internal error: {type(exc).__name__}: {exc} "
              "(please report this with the scene file)", file=sys.stderr)
        return 3
    finally:
        _background_precompile()


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
