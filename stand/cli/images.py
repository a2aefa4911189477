"""Commands on the instruments' images: ``stand snapshot``, ``video``, ``track``, ``strobe``.
Each calls the API (:func:`stand.api.track`, :mod:`stand.api.images`) and prints."""
from __future__ import annotations

import sys
from pathlib import Path

from stand.cli.common import print_warnings, say_not_applicable

__all__ = ["cmd_snapshot", "cmd_track", "cmd_video", "cmd_strobe"]


def cmd_snapshot(args) -> int:
    from stand.api.images import snapshot
    from stand.errors import NotApplicable
    from stand.io.numbers import plain

    try:
        doc = snapshot(args.recording, args.output, instrument=args.instrument, frame=args.frame,
                       screen=args.screen)
    except NotApplicable as exc:
        return say_not_applicable("snapshot", str(exc))
    print_warnings("snapshot", doc["warnings"])
    at = f" (t = {plain(doc['time_s'], 's')})" if doc["time_s"] is not None else ""
    where = f" of screen {args.screen}" if args.screen else ""
    what = (f"{args.instrument} frame {args.frame}{where}{at}" if doc["frames"] > 1 or args.instrument != "rings"
            else f"calibration-ring image{where}")
    print(f"{what} -> {args.output}")
    return 0


def cmd_track(args) -> int:
    from stand.api import track
    from stand.api.images import spot_fit_compiles, write_track

    if sys.stderr.isatty() and not args.trace and spot_fit_compiles():
        print("stand track: compiling the blurred-spot fit (one time, about 10 s; "
              "`stand warmup` does it ahead)...", file=sys.stderr)
    tr = track(args.source, calibration=args.calibration, ring_radii=args.ring_radii,
               gain=args.gain, threshold=args.threshold, trace=args.trace,
               spot_sigma=args.spot_sigma, capacity_gmm=args.capacity,
               optical_gain=args.optical_gain, progress=sys.stderr.isatty(),
               screen=args.screen, roi=args.roi, background=args.background,
               exposure=args.exposure)
    write_track(tr, args.output)
    df = tr.frame
    what = "trace" if args.trace else "spot"
    methods = ""
    if "method" in df and len(df):
        counts = df["method"].replace("", "none").value_counts()
        methods = " (" + ", ".join(f"{k} {v}" for k, v in counts.items()) + ")"
    if "flags" in df and len(df):
        fl = df["flags"].fillna("").astype(str)
        flagged = {f: int(fl.str.contains(f, regex=False).sum()) for f in ("not_refined", "fit_failed")}
        methods += "".join(f"; {f} {n}" for f, n in flagged.items() if n)
    if tr.get("bounds"):
        cols = ", ".join(c for c in ("radius_max_mm", "unbalance_max_gmm") if c in df)
        methods += (f"; {tr['bounds']} unresolved: no radius, only an upper bound"
                    f"{' (' + cols + ')' if cols else ''} -- the circle is not separable from "
                    "the spot")
    print(f"{args.source}: {tr['frames']} frames, {what} found in {tr['found']}{methods} -> {args.output}")
    return 0


def cmd_video(args) -> int:
    from stand.api.images import video
    from stand.errors import NotApplicable

    try:
        doc = video(args.recording, args.output, screen=args.screen, qp=args.qp, force=args.force)
    except NotApplicable as exc:
        return say_not_applicable("video", str(exc))
    extra = ", ".join(Path(doc[k]).name for k in ("truth", "rings_png", "rings_txt") if k in doc)
    print(f"{args.recording}: {doc['frames']} frames at {doc['frame_rate_hz']:g} Hz -> "
          f"{args.output} ({doc['codec']}, {doc['bytes'] / 1e6:.2f} MB); beside it: {extra}")
    return 0


def cmd_strobe(args) -> int:
    from stand.api import track
    from stand.api.images import write_track

    tr = track(args.source, strobe=True, n_weights=args.weights)
    write_track(tr, args.output)
    print(f"{args.source}: {tr['frames']} strobe frames -> {args.output}")
    return 0
