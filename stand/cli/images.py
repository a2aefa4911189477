"""Commands on the instruments' images: ``stand snapshot``, ``video``, ``track``, ``strobe``.
Each calls the library and prints."""
from __future__ import annotations

import sys
from pathlib import Path

from stand.cli.common import say_not_applicable, write_csv

__all__ = ["cmd_snapshot", "cmd_track", "cmd_video", "cmd_strobe"]


def cmd_snapshot(args) -> int:
    import cv2

    from stand.api import read
    from stand.io.atomic import atomic_path

    name = {"screen": "instruments/screen/frames", "strobe": "instruments/stroboscope/frames",
            "rings": "instruments/screen/calibration_image"}[args.instrument]
    rec = read(args.recording)
    shape = rec.shape(name)
    if shape is None:
        return say_not_applicable("snapshot", f"{args.recording} holds no {args.instrument} images "
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


def cmd_track(args) -> int:
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


def cmd_video(args) -> int:
    from stand.io.guard import check_outputs
    from stand.reports.video import sidecar_paths, write_screen_video

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
        return say_not_applicable("video", str(exc))
    extra = ", ".join(Path(doc[k]).name for k in ("truth", "rings_png", "rings_txt") if k in doc)
    print(f"{args.recording}: {doc['frames']} frames at {doc['frame_rate_hz']:g} Hz -> "
          f"{args.output} ({doc['codec']}, {doc['bytes'] / 1e6:.2f} MB); beside it: {extra}")
    return 0


def cmd_strobe(args) -> int:
    from vision.io import VisionError

    from stand.analysis.tracking import strobe_angles

    if not Path(args.output).resolve().parent.is_dir():
        raise FileNotFoundError(f"output directory of {args.output!r} does not exist")
    try:
        df = strobe_angles(args.source, n_weights=args.weights)
    except VisionError as exc:
        raise ValueError(str(exc)) from None
    write_csv(df, args.output)
    print(f"{args.source}: {len(df)} strobe frames -> {args.output}")
    return 0
