"""Benchmark of ``stand track`` on a video: decode alone against decode + spot tracking,
on the video sample and on a synthetic 1280 x 1024 high-speed video with its truth.

    python benchmarks/bench_track_video.py [VIDEO.mp4] [--repeats 3] [--truth TRUTH.csv]
                                           [--no-synthetic] [--frames 300] [--cores 2]

Videos: ``data_samples/video/screen.mp4`` (500 frames of 256 x 256 px, H.264; 300 of
them saturated arcs up to 95 px long; truth ``screen_truth.csv``), or the one given, and
a synthetic high-speed recording (:func:`synthetic_video`: 1280 x 1024 px, 2000 frames/s,
the spot whirling at 50 rev/s on a 150 px circle, exposure 1/4 of the frame period: 5.9 px
arcs; lossless FFV1 in Matroska, written with OpenCV; its truth is the exposure-averaged
centre of the drawn positions).

The process runs on ``--cores`` CPUs (``os.sched_setaffinity``; OpenCV one thread).  Rows:

* decode alone: ``cv2.VideoCapture`` with one FFmpeg thread + gray conversion, in the
  caller's thread, and the same with FFmpeg's own threads -- the decoder's rate is the faster
  of the two (the goal's ratio is against it);
* decode + track: ``vision.spot.track(vision.io.iter_frames(path))`` as ``stand track``
  runs it: a read-ahead thread decodes (one FFmpeg thread, FFmpeg's own threads for frames of
  ``vision.io.LARGE_FRAME_PIXELS`` and more; OpenCV releases the GIL) while the caller tracks,
  the tracker's work inside the ROI around the predicted spot;
* the same sequentially (``iter_frames(path, ahead=0)``: FFmpeg's own threads).

Each is the best of ``--repeats`` passes over the whole file (wall time; decode alone and
decode + track alternate, so the machine's load spreads over both; the sequential row is
timed after them); the numba kernel is compiled (or loaded from
its cache) first, its cost printed apart.  Prints frames/s, the ratio decode + track /
decode (goal >= 0.9), the share of frames per refinement and the RMS error against the
truth.
"""
import argparse
import math
import os
import tempfile
import time
from pathlib import Path

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import cv2  # noqa: E402
import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
SAMPLE = ROOT / "data_samples" / "video" / "screen.mp4"


def decode_only(path, threads: int = 1) -> int:
    """Read every frame with cv2.VideoCapture (``threads`` FFmpeg threads, 0: FFmpeg's own
    choice) and convert it to gray; returns the number of frames."""
    cap = cv2.VideoCapture(str(path), cv2.CAP_FFMPEG, [cv2.CAP_PROP_N_THREADS, threads])
    n = 0
    while True:
        ok, img = cap.read()
        if not ok:
            break
        cv2.cvtColor(img, cv2.COLOR_BGR2GRAY)
        n += 1
    cap.release()
    return n


def decode_and_track(path, ahead=None):
    from vision.io import iter_frames
    from vision.spot import track

    kw = {} if ahead is None else {"ahead": ahead}
    return track(iter_frames(str(path), **kw))


def synthetic_video(folder, n_frames=300, width=1280, height=1024, fps=2000.0, rev_s=50.0,
                    radius=150.0, exposure=0.25, sigma=2.5, seed=3):
    """Write ``folder/whirl_1280x1024.mkv`` (FFV1, gray; Matroska: AVI cannot time 2000
    frames/s) and its truth; returns the video's path and the truth (n_frames, 2) [px]: a
    spot of sigma ``sigma`` [px] whirling at ``rev_s`` [rev/s] on a circle of ``radius``
    [px] about the frame's centre (plus a slow drift of the centre), filmed at ``fps``
    [frames/s] with an exposure of ``exposure`` frame periods (16 sub-positions per
    exposure; the camera noise of :class:`vision.artificial.Camera`, 8 bits)."""
    from vision import artificial as art

    cam = art.Camera(width=width, height=height, sigma_px=sigma)
    k = np.arange(16) / 16.0
    t = (np.arange(n_frames)[:, None] + exposure * k[None, :]) / fps     # s, (F, 16)
    th = 2.0 * math.pi * rev_s * t
    cu = 0.5 * width + 20.0 * np.sin(2.0 * math.pi * 0.7 * t)
    cv = 0.5 * height + 12.0 * np.cos(2.0 * math.pi * 0.4 * t)
    px = np.stack([cu + radius * np.cos(th), cv + radius * np.sin(th)], axis=-1)
    truth = art.exposure_centre(px)
    path = str(Path(folder) / f"whirl_{width}x{height}.mkv")
    w = cv2.VideoWriter(path, cv2.CAP_FFMPEG, cv2.VideoWriter_fourcc(*"FFV1"), fps,
                        (width, height), [cv2.VIDEOWRITER_PROP_IS_COLOR, 0])
    if not w.isOpened():
        raise SystemExit("OpenCV cannot write FFV1 here")
    for f in art.spot_frames(px, cam, seed=seed):
        w.write(f)
    w.release()
    return path, truth


def bench(path, repeats, truth=None):
    """Time the rows (module docstring) on ``path`` and print them; ``truth`` (F, 2) [px]."""
    t_dec = t_dec0 = t_trk = t_seq = c_trk = c_dec = math.inf
    df = None
    for _ in range(repeats):     # the compared rows alternate back to back
        t0, c0 = time.perf_counter(), time.process_time()
        n = decode_only(path)
        t_dec, c_dec = min(t_dec, time.perf_counter() - t0), min(c_dec, time.process_time() - c0)
        t0 = time.perf_counter()
        decode_only(path, threads=0)
        t_dec0 = min(t_dec0, time.perf_counter() - t0)
        t0, c0 = time.perf_counter(), time.process_time()
        df = decode_and_track(path)
        t_trk, c_trk = min(t_trk, time.perf_counter() - t0), min(c_trk, time.process_time() - c0)
    for _ in range(repeats):     # the sequential row, for information, after them
        t0 = time.perf_counter()
        seq = decode_and_track(path, ahead=0)
        t_seq = min(t_seq, time.perf_counter() - t0)
    assert seq.equals(df), "the read-ahead track differs from the sequential one"
    fps_dec, fps_trk, fps_seq, fps_dec0 = n / t_dec, n / t_trk, n / t_seq, n / t_dec0
    print(f"\n{Path(path).name}: {n} frames, best of {repeats}, load {os.getloadavg()[0]:.1f}")
    print("| step | frames/s | ms/frame |")
    print("|---|---:|---:|")
    print(f"| decode alone (cv2.VideoCapture, 1 thread, + gray) | {fps_dec:.0f} | "
          f"{1e3 / fps_dec:.3f} |")
    print(f"| decode alone (cv2.VideoCapture, FFmpeg's threads, + gray) | {fps_dec0:.0f} | "
          f"{1e3 / fps_dec0:.3f} |")
    print(f"| decode + track (read-ahead thread) | {fps_trk:.0f} | {1e3 / fps_trk:.3f} |")
    print(f"| decode + track (sequential) | {fps_seq:.0f} | {1e3 / fps_seq:.3f} |")
    print(f"CPU time (process_time): decode {1e3 * c_dec / n:.3f}, decode + track "
          f"{1e3 * c_trk / n:.3f} ms/frame; CPU ratio {c_dec / c_trk:.2f}")
    best = max(fps_dec, fps_dec0)    # the decoder's rate: the faster of its two ways
    print(f"ratio decode+track / decode = {fps_trk / best:.2f} (the faster decode, "
          f"{'FFmpeg threads' if fps_dec0 > fps_dec else '1 thread'}; goal >= 0.9: "
          f"{'met' if fps_trk >= 0.9 * best else 'NOT met'}); against 1 thread "
          f"{fps_trk / fps_dec:.2f}, FFmpeg's threads {fps_trk / fps_dec0:.2f}; sequential "
          f"{fps_seq / best:.2f}")
    counts = df["method"].value_counts().to_dict()
    print("methods: " + ", ".join(f"{k} {v}" for k, v in counts.items())
          + f"; frames not ok: {int((~df['ok']).sum())}")
    if truth is not None:
        e = np.hypot(df["u_px"].to_numpy() - truth[:, 0], df["v_px"].to_numpy() - truth[:, 1])
        print(f"RMS error vs truth: {math.sqrt(np.nanmean(e ** 2)):.4f} px "
              f"(max {np.nanmax(e):.4f})")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("video", nargs="?", default=str(SAMPLE))
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--truth", default=None,
                    help="truth CSV (default: NAME_truth.csv beside the video)")
    ap.add_argument("--no-synthetic", action="store_true", help="skip the 1280 x 1024 video")
    ap.add_argument("--frames", type=int, default=300, help="frames of the synthetic video")
    ap.add_argument("--cores", type=int, default=2, help="CPUs the process may use")
    args = ap.parse_args()
    if hasattr(os, "sched_setaffinity"):
        os.sched_setaffinity(0, set(sorted(os.sched_getaffinity(0))[:args.cores]))
    cv2.setNumThreads(1)
    path = Path(args.video)

    t0 = time.perf_counter()
    from vision import _blur_kernel
    from vision.spot import locate
    first = cv2.VideoCapture(str(path)).read()[1]
    locate(cv2.cvtColor(first, cv2.COLOR_BGR2GRAY), refine="blur")   # compile / load the kernel
    print(f"first call (numba import + kernel compile or cache load): "
          f"{time.perf_counter() - t0:.2f} s; "
          f"blurred-spot fit: {'numba' if _blur_kernel.compiled_available() else 'numpy'}; "
          f"{len(os.sched_getaffinity(0))} CPU(s)")
    truth = Path(args.truth) if args.truth else path.with_name(path.stem + "_truth.csv")
    tr = None
    if truth.is_file():
        import pandas as pd

        tr = pd.read_csv(truth, comment="#")[["u_px", "v_px"]].to_numpy()
    bench(path, args.repeats, tr)
    if not args.no_synthetic:
        with tempfile.TemporaryDirectory() as d:
            t0 = time.perf_counter()
            vid, tr = synthetic_video(d, args.frames)
            print(f"\n(synthetic video written in {time.perf_counter() - t0:.1f} s, "
                  f"{os.path.getsize(vid) / 1e6:.0f} MB)")
            bench(vid, args.repeats, tr)


if __name__ == "__main__":
    main()
