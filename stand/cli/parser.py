"""The ``stand`` command line's argument parser (the commands, their arguments and help).

The handlers live in :mod:`stand.cli.simulation`, :mod:`.analysis` and :mod:`.images`;
:mod:`stand.cli.main` passes them in.
"""
from __future__ import annotations

import argparse
import math


def _grade(text) -> float:
    """An ISO 21940-11 grade [mm/s] from ``G6.3`` or ``6.3``."""
    t = str(text).strip().upper()
    try:
        g = float(t[1:] if t.startswith("G") else t)
    except ValueError:
        raise ValueError(f"--grade = {text!r}: an ISO 21940-11 grade such as G6.3 or 6.3 (mm/s)") from None
    if not (math.isfinite(g) and g > 0):
        raise ValueError(f"--grade = {text!r}: must be > 0 (mm/s)")
    return g


def _table_options(sp) -> None:
    """``--columns`` and ``--map``: which column of a lab table is what (stand.lab.recording_map)."""
    sp.add_argument("--columns", default=None, metavar="SPEC",
                    help="lab table columns: ROLE=COLUMN[unit],... e.g. time=time_s,x=disp_x_um[um],"
                         "y=disp_y_um[um],speed=tacho_rpm[rpm] (roles: time, x, y, speed, angle, "
                         "keyphasor, photogate; a probe in volts: x=px[V, 7.87 V/mm])")
    sp.add_argument("--map", default=None, metavar="MAP.toml",
                    help="recording map file: [columns], [table] layout, [rotor] mass and service "
                         "speed (docs/lab_recordings.md)")


def _screen_option(sp, what: str) -> None:
    """``--screen NAME``, the same in ``stand snapshot``, ``track`` and ``video``
    (:func:`stand.recording.read.screen_group_of` resolves it)."""
    sp.add_argument("--screen", default=None, metavar="NAME",
                    help="a recording's named screen ([instruments.screen.NAME]; needed when the "
                         f"recording has only named screens): {what}")


def build_parser(handlers: dict) -> argparse.ArgumentParser:
    """The argument parser; ``handlers`` maps each command to its function (stand.cli.main passes them)."""
    from stand.api.simulation import METHODS
    from stand.cli.sweep import add_sweep_arguments

    p = argparse.ArgumentParser(prog="stand", description="Virtual autobalancer test stand")
    sub = p.add_subparsers(dest="command", required=True)
    rp = sub.add_parser("report", help="balancing-quality report (HTML + JSON) of a recording, or a folder/glob")
    rp.add_argument("recording", help="HDF5 recording or lab table (CSV, Parquet), or a folder / glob of them")
    _table_options(rp)
    rp.add_argument("-o", "--output", default=None,
                    help="HTML report; batch (a folder or glob): SUMMARY.csv|.json|.parquet names the "
                         "summary table, anything else the directory (created if missing) for one "
                         "HTML per file, index.html and, without --summary, summary.csv")
    rp.add_argument("--json", action="store_true", help="print the JSON report on stdout")
    rp.add_argument("--json-file", default=None, help="write the JSON report (the source of the HTML)")
    rp.add_argument("--pdf", default=None, metavar="REPORT.pdf",
                    help="write a PDF (page 1: the verdict and the key figures)")
    rp.add_argument("--grade", default="G6.3", help="ISO 21940-11 grade (G6.3 or 6.3, mm/s)")
    rp.add_argument("--service-speed", type=float, default=None, help="service speed [rpm]")
    rp.add_argument("--tracks", nargs=2, default=None, metavar="CSV", help="two screens' tracks: two-plane section")
    rp.add_argument("--summary", default=None, help="batch: summary table (.csv, .json or .parquet)")
    rp.add_argument("--workers", type=int, default=None, help="batch: local worker processes")
    rp.add_argument("--scheduler", default=None, help="batch: dask.distributed scheduler address")
    rp.set_defaults(func=handlers["report"])
    sw = sub.add_parser("sweep", help="parameter sweep (theory and/or simulation) on a process pool or a Dask cluster")
    add_sweep_arguments(sw)
    sw.set_defaults(func=handlers["sweep"])
    st = sub.add_parser("stress", help="numerical stability on the stiff and extreme catalogue (HTML + JSON)")
    st.add_argument("-o", "--output", default=None, help="HTML report")
    st.add_argument("--json-file", default=None, help="write the JSON report to this file")
    st.add_argument("--json", action="store_true", help="print the JSON report on stdout")
    st.add_argument("--catalogue", default=None, help="catalogue TOML (default: the built-in one)")
    st.add_argument("--cases", default=None, help="comma-separated case names, or 'fast'")
    st.set_defaults(func=handlers["stress"])
    ft = sub.add_parser("fit", help="calibrate a scene to a recording: the free values by least "
                                    "squares, with their ± and identifiability (issue 39)")
    ft.add_argument("scene", help="template scene file (TOML)")
    ft.add_argument("data", help="recording: lab table with --map/--columns, HDF5 recording with "
                                 "probes (anything stand analyze reads)")
    _table_options(ft)
    ft.add_argument("--free", required=True, metavar="PATH[=LO..HI],...",
                    help="scene values to fit by their dotted TOML path, with optional bounds in "
                         "the file's units, e.g. supports.stiffness,rotor.unbalance_angle,"
                         "balancer.drag=0.01..1")
    ft.add_argument("-o", "--output", default=None, metavar="FITTED.toml",
                    help="write the fitted scene (a new file; never an input)")
    ft.add_argument("--json", action="store_true", help="print the JSON result on stdout")
    ft.add_argument("--json-file", default=None, help="write the JSON result to this file")
    ft.add_argument("--report", default=None, metavar="FIT.html",
                    help="write the HTML report: values, theory against experiment, overlays")
    ft.add_argument("--workers", type=int, default=None, help="local worker processes for the "
                                                              "Jacobian's simulations")
    ft.add_argument("--scheduler", default=None, help="dask.distributed scheduler address")
    ft.add_argument("--no-progress", action="store_true", help="no progress lines on stderr")
    ft.add_argument("--force", action="store_true", help="replace an output of another kind")
    ft.set_defaults(func=handlers["fit"])
    wu = sub.add_parser("warmup", help="compile the kernels ahead (one time after an install)")
    wu.add_argument("--all", action="store_true",
                    help="every model kind and every compiled function, not only the planar rotor")
    wu.set_defaults(func=handlers["warmup"])
    r = sub.add_parser("run", help="simulate a scene and write an HDF5 recording")
    r.add_argument("scene", help="scene file (TOML)")
    r.add_argument("-o", "--output", required=True, help="recording to write (HDF5)")
    r.add_argument("--json", action="store_true", help="print a JSON summary")
    r.add_argument("--method", choices=METHODS, default=None, help="override run.method")
    r.add_argument("--no-progress", action="store_true", help="no progress bar")
    r.add_argument("--checkpoint", default=None,
                   help="long runs: save the integrator state to this .npz file as it goes and "
                        "resume from it when it exists (deleted at the end)")
    r.set_defaults(func=handlers["run"])
    a = sub.add_parser("accuracy", help="error against run time over tolerances and methods")
    a.add_argument("scene", help="scene file (TOML)")
    a.add_argument("--json", action="store_true", help="print JSON instead of a table")
    a.add_argument("--rtols", default=None, help="comma-separated relative tolerances")
    a.add_argument("--methods", default=None,
                   help="comma-separated methods (default: automatic); RK4 = fixed-step RK4")
    a.add_argument("--rk4-steps", default=None, help="RK4 steps [s], comma-separated")
    a.add_argument("--fast", action="store_true",
                   help="fast ladder: rtol 1e-4, 1e-6 against a reference at rtol 1e-10")
    a.add_argument("--duration", type=float, default=None,
                   help="run only the scene's first DURATION seconds (a quick check)")
    a.add_argument("-o", "--output", default=None,
                   help="write the report as self-contained HTML (work-precision plot, recommendation)")
    a.add_argument("--json-file", default=None, help="write the report's JSON to this file")
    a.set_defaults(func=handlers["accuracy"])
    t = sub.add_parser("theory", help="steady motions, stability bands, critical speeds, stuck-ball law")
    t.add_argument("scene", help="scene file (TOML)")
    t.add_argument("--json", action="store_true", help="print JSON")
    t.add_argument("--plot", default=None, help="write the speed map chart (PNG)")
    t.add_argument("--max-speed", type=float, default=None, help="upper end of the map [rev/s]")
    t.add_argument("--no-floquet", action="store_true",
                   help="rotor-family scenes: skip the Floquet scan of the main motion (faster)")
    t.set_defaults(func=handlers["theory"])
    s = sub.add_parser("snapshot", help="save one recorded instrument frame as PNG")
    s.add_argument("recording", help="recording (HDF5) written by stand run")
    s.add_argument("--instrument", choices=("screen", "strobe", "rings"), default="screen")
    s.add_argument("--frame", type=int, default=0, help="frame index (negative: from the end)")
    _screen_option(s, "its frames, or with --instrument rings its ring image")
    s.add_argument("-o", "--output", required=True, help="PNG to write")
    s.set_defaults(func=handlers["snapshot"])
    e = sub.add_parser("experiment", help="run an experiment programme of tables 4.2-4.6 on a scene")
    e.add_argument("scene", help="base scene (the stand) in TOML")
    e.add_argument("programme", choices=("constant", "run-up", "run-down", "unbalance", "impact",
                                         "pressure", "natural-frequency"))
    e.add_argument("-o", "--output", required=True, help="recording to write (HDF5)")
    e.add_argument("--band", choices=("sub", "near", "super"), default="super",
                   help="table 4.2 speed band for 'constant' (0.7, 1.0, 1.5 f0)")
    e.add_argument("--speed", type=float, help="rotor speed [rev/s]")
    e.add_argument("--rate", type=float, help="run-up rate [rev/s^2]")
    e.add_argument("--hold", type=float, default=20.0, help="hold after the run-up [s]")
    e.add_argument("--time", type=float, default=175.0, help="run-down time [s]")
    e.add_argument("--exponential", action="store_true", help="exponential coast-down")
    e.add_argument("--duration", type=float, help="duration of a constant-speed run [s]")
    e.add_argument("--at", type=float, help="time of the change / blow / pressure start [s]")
    e.add_argument("--end", type=float, help="end of the pressure [s]")
    e.add_argument("--eccentricity", type=float, help="new eccentricity [m]")
    e.add_argument("--angle", type=float, default=0.0, help="angle [deg]")
    e.add_argument("--change-time", type=float, default=0.0, help="0 = discrete change [s]")
    e.add_argument("--velocity", type=float, help="velocity jump of the blow [m/s]")
    e.add_argument("--side-force", dest="side_force", type=float, help="pressure programme: side force [N]")
    e.add_argument("--stiffness", type=float, default=0.0, help="extra side stiffness [N/m]")
    e.add_argument("--deflection", type=float, help="initial shaft deflection [m]")
    e.set_defaults(func=handlers["experiment"])
    a2 = sub.add_parser("analyze", help="identify f0, damping, unbalance, components, regime from a recording")
    a2.add_argument("recording", help="HDF5 recording, or a lab table (CSV with any delimiter, "
                    "Parquet, pandas HDF5) of time, x, y and optionally keyphasor / tachometer / "
                    "angle; or a folder / glob of them (with -o)")
    _table_options(a2)
    a2.add_argument("--json", action="store_true", help="print JSON")
    a2.add_argument("--grade", type=_grade, default=6.3, help="ISO 21940-11 target grade (G6.3 or 6.3, mm/s)")
    a2.add_argument("--service-speed", type=float, default=None, help="service speed [rpm] (default: the recorded speed)")
    a2.add_argument("--tracks", nargs=2, default=None, metavar="CSV", help="two-plane balancing: the "
                    "`stand track --screen NAME` CSVs of the recording's two screens")
    a2.add_argument("-o", "--output", default=None,
                    help="folder/glob input: write one summary table (CSV, .json or .parquet)")
    a2.add_argument("--workers", type=int, default=None, help="local worker processes (default: all cores)")
    a2.add_argument("--scheduler", default=None, help="dask.distributed scheduler address (tcp://...)")
    a2.set_defaults(func=handlers["analyze"])
    dq = sub.add_parser("daq", help="a recording's probes, keyphasor and tachometer written as a "
                        "lab DAQ export (CSV: ms, um with DC offsets, keyphasor volts, rpm) with its truth")
    dq.add_argument("recording", help="HDF5 recording with [instruments.probes] at 0 and 90 deg")
    dq.add_argument("-o", "--output", required=True, help="CSV to write")
    dq.add_argument("--truth", default=None, help="truth JSON (default: <output stem>.truth.json)")
    dq.add_argument("--offset", default="35,-20", help="DC offsets of the x and y probes [um]")
    dq.add_argument("--quantity", default="displacement",
                    choices=("displacement", "velocity", "acceleration"),
                    help="what the x, y channels measure: probes [um], velocity pickups [mm/s] "
                    "or accelerometers [g] (no offsets)")
    dq.add_argument("--bode", action="store_true",
                    help="write the order-tracked steady 1X Bode table (rpm, um, deg) of a slow run-up")
    dq.set_defaults(func=handlers["daq"])
    tk = sub.add_parser("track", help="sub-pixel laser-spot track from frames (HDF5, video, images)")
    tk.add_argument("source", help="recording.h5[:dataset], video file (mp4, avi, mov, ...), image "
                    "folder or glob")
    tk.add_argument("-o", "--output", required=True, help="CSV to write (# key = value lines, then "
                    "the table)")
    tk.add_argument("--calibration", default=None,
                    help="calibration-ring image, or a recording holding one (px -> mm)")
    tk.add_argument("--ring-radii", default=None, help="ring radii [m], comma-separated, or a ring "
                    "file with 'ring_radii_m = ...' (and optical_gain, exposure_s, capacity_gmm "
                    "lines, as `stand video` writes); default: from the recording")
    tk.add_argument("--gain", type=float, default=None, help="camera gain [electrons/DN] for the uncertainty")
    tk.add_argument("--optical-gain", type=float, default=None,
                    help="spot displacement / shaft displacement (default: from the ring file or "
                         "the recording): adds t_s, x_m, y_m[, rotor_angle_rad] for `stand analyze`")
    tk.add_argument("--exposure", type=float, default=None,
                    help="camera exposure [s] (default: from the ring file or the recording): "
                         "t_s at mid-exposure")
    _screen_option(tk, "its frames; x_m, y_m of the point it shows (for `stand analyze --tracks`)")
    tk.add_argument("--threshold", type=float, default=None,
                    help="smallest spot amplitude [DN above background] (default 10 x background noise)")
    tk.add_argument("--roi", default=None, metavar="X,Y,W,H",
                    help="search only this rectangle of every frame [px: left column, top row, "
                         "width, height]")
    tk.add_argument("--background", default=None, metavar="median|FILE",
                    help="subtract a static background: 'median' (per-pixel median of 25 frames "
                         "spread over the source; 'median:N'), or a dark-frame image")
    tk.add_argument("--trace", action="store_true",
                    help="long exposures: fit the circle the spot draws (centre, radius) instead of the spot")
    tk.add_argument("--spot-sigma", type=float, default=None,
                    help="with --trace: the still spot's sigma [px] (default: estimated from the trace)")
    tk.add_argument("--capacity", type=float, default=None,
                    help="with --calibration: balancer capacity S [g mm] (ring zones i S/16, in the "
                         "CSV's preamble); with --trace also zone and unbalance columns")
    tk.set_defaults(func=handlers["track"])
    vd = sub.add_parser("video", help="a recording's screen frames as a lab video (mp4) with "
                        "its rings and truth beside it")
    vd.add_argument("recording", help="HDF5 recording with a screen camera")
    vd.add_argument("-o", "--output", required=True, help="video to write: NAME.mp4 (H.264, needs "
                    "PyAV) or NAME.mkv / NAME.avi (FFV1, lossless); beside it NAME_truth.csv, "
                    "NAME_rings.png, NAME_rings.txt")
    _screen_option(vd, "its frames")
    vd.add_argument("--qp", type=int, default=10, help="H.264 quantiser 0..51 (0 lossless; default 10)")
    vd.set_defaults(func=handlers["video"])
    sb = sub.add_parser("strobe", help="weights' angles from stroboscope frames")
    sb.add_argument("source", help="recording.h5[:dataset] (default dataset instruments/stroboscope/frames), video or images")
    sb.add_argument("-o", "--output", required=True, help="CSV to write")
    sb.add_argument("--weights", type=int, default=None, help="number of weights (default: detect)")
    sb.set_defaults(func=handlers["strobe"])
    fi = sub.add_parser("influence", help="influence-coefficient balancing: a reference and one trial-weight run per plane")
    fi.add_argument("recordings", nargs="+", metavar="RUN", help="reference recording, then one trial recording per --trial")
    fi.add_argument("--trial", action="append", required=True, help="trial weight PLANE:MASS_G:ANGLE_DEG:RADIUS_MM (repeat)")
    fi.add_argument("--sensors", required=True, help="measurement planes, comma-separated (e.g. probe1,probe2)")
    fi.add_argument("--json", action="store_true", help="print the result as JSON")
    fi.set_defaults(func=handlers["influence"])
    ba = sub.add_parser("balance", help="field balancing from a job file of readings (trial runs, "
                                        "several speeds, least squares / weighted / min-max)")
    ba.add_argument("job", help="job file (TOML: [job], [planes.*], [sensors.*], [[run]], [[influence]])")
    ba.add_argument("--method", default=None, choices=("least_squares", "weighted", "min_max"),
                    help="override the job's method")
    ba.add_argument("--influence", default=None, metavar="FILE",
                    help="a saved influence file (--save-influence) instead of the job's trial runs")
    ba.add_argument("--save-influence", default=None, metavar="FILE",
                    help="write the influence matrix for the next machine of the type (TOML)")
    ba.add_argument("-o", "--output", default=None, metavar="REPORT.html", help="field-balancing report (HTML)")
    ba.add_argument("--pdf", default=None, metavar="REPORT.pdf", help="field-balancing report (PDF)")
    ba.add_argument("--json", action="store_true", help="print the result as JSON")
    ba.set_defaults(func=handlers["balance"])
    for sp in sub.choices.values():
        if not any("--force" in a.option_strings for a in sp._actions):
            sp.add_argument("--force", action="store_true",
                            help="replace an existing output file of another kind (never an input)")
    return p
