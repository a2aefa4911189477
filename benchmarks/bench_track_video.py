"""Benchmark of ``stand track`` on a video: mp4 decode alone against decode + spot
tracking (the blurred-spot fit on every saturated or elongated blob), one core.

    python benchmarks/bench_track_video.py [VIDEO.mp4] [--repeats 3] [--truth TRUTH.csv]

Default: the video sample ``data_samples/video/screen.mp4`` (500 frames of
256 x 256 px, H.264; 300 of them saturated arcs up to 95 px long).  The process
is pinned to one CPU (``os.sched_setaffinity``) and OpenCV to one thread, so the
decoder's own threads share that core too.  Each measurement is the best of
``--repeats`` passes over the whole file, decode and decode + track alternating
(wall time; the CPU time of the process is printed too, the fairer number on a
shared machine);
the numba kernel is compiled (or loaded from its cache) before timing, and that
first-call cost is printed apart.  Prints frames/s, the ratio of the two, the
share of frames fitted, and the RMS error against the truth CSV beside the video.
"""
import argparse
import math
import os
import time
from pathlib import Path

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import cv2  # noqa: E402
import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
SAMPLE = ROOT / "data_samples" / "video" / "screen.mp4"


def decode_only(path) -> int:
    """Read every frame with cv2.VideoCapture and convert it to gray (what
    vision.io.iter_frames does); returns the number of frames."""
    cap = cv2.VideoCapture(str(path))
    n = 0
    while True:
        ok, img = cap.read()
        if not ok:
            break
        cv2.cvtColor(img, cv2.COLOR_BGR2GRAY)
        n += 1
    cap.release()
    return n


def decode_and_track(path):
    from vision.io import iter_frames
    from vision.spot import track

    return track(iter_frames(str(path)))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("video", nargs="?", default=str(SAMPLE))
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--truth", default=None, help="truth CSV (default: NAME_truth.csv beside the video)")
    args = ap.parse_args()
    if hasattr(os, "sched_setaffinity"):
        os.sched_setaffinity(0, {sorted(os.sched_getaffinity(0))[0]})
    cv2.setNumThreads(1)
    path = Path(args.video)

    t0 = time.perf_counter()
    from vision import _blur_kernel
    from vision.spot import locate
    first = cv2.VideoCapture(str(path)).read()[1]
    locate(cv2.cvtColor(first, cv2.COLOR_BGR2GRAY), refine="blur")   # compile / load the kernel
    warm = time.perf_counter() - t0

    t_dec = t_trk = c_dec = c_trk = math.inf
    df = None
    for _ in range(args.repeats):
        t0, c0 = time.perf_counter(), time.process_time()
        n = decode_only(path)
        t_dec, c_dec = min(t_dec, time.perf_counter() - t0), min(c_dec, time.process_time() - c0)
        t0, c0 = time.perf_counter(), time.process_time()
        df = decode_and_track(path)
        t_trk, c_trk = min(t_trk, time.perf_counter() - t0), min(c_trk, time.process_time() - c0)
    fps_dec, fps_trk = n / t_dec, n / t_trk
    engine = "numba" if _blur_kernel.compiled_available() else "numpy"
    print(f"{path.name}: {n} frames, one core, best of {args.repeats}")
    print(f"first call (numba import + kernel compile or cache load): {warm:.2f} s")
    print("| step | frames/s | ms/frame |")
    print("|---|---:|---:|")
    print(f"| decode alone (cv2.VideoCapture + gray) | {fps_dec:.0f} | {1e3 / fps_dec:.3f} |")
    print(f"| decode + track (blurred-spot fit: {engine}) | {fps_trk:.0f} | {1e3 / fps_trk:.3f} |")
    dt = t_trk - t_dec
    print(f"| tracking alone (difference) | {n / dt:.0f} | {1e3 * dt / n:.3f} |")
    print(f"CPU time (process_time, best of {args.repeats}): decode {1e3 * c_dec / n:.3f} ms/frame, "
          f"decode + track {1e3 * c_trk / n:.3f} ms/frame = {n / c_trk:.0f} frames/s")
    print(f"ratio decode+track / decode = {fps_trk / fps_dec:.2f}; target decode+track >= 500 "
          f"frames/s: {'met' if fps_trk >= 500 else 'NOT met'}")
    counts = df["method"].value_counts().to_dict()
    print("methods: " + ", ".join(f"{k} {v}" for k, v in counts.items()))
    truth = Path(args.truth) if args.truth else path.with_name(path.stem + "_truth.csv")
    if truth.is_file():
        import pandas as pd

        tr = pd.read_csv(truth, comment="#")
        e = np.hypot(df["u_px"].to_numpy() - tr["u_px"].to_numpy(),
                     df["v_px"].to_numpy() - tr["v_px"].to_numpy())
        print(f"RMS error vs {truth.name}: {math.sqrt(np.mean(e ** 2)):.4f} px (max {e.max():.4f})")


if __name__ == "__main__":
    main()
