#!/usr/bin/env python
"""Rendering speed of laser-spot screen frames (a script, not a test).

640 x 480 frames, 8 bits, spot 20 px (1/e^2 diameter), 16 sub-samples per
exposure (motion blur along a steady whirl: radius 100 px, 15 rev/s, exposure
2 ms), background 8 DN with shot noise (40 e-/DN) and 1 DN read noise, one
core (NUMBA_NUM_THREADS=1).  Contenders, measured in the same run:

* ``stand`` -- :func:`stand.instruments.render.render_frames` (the numba
  kernel: spot drawn only in +-4 sigma windows, spot-free pixels drawn from the
  exact background law by table inversion);
* ``numpy`` -- a plain-numpy peer: the Gaussian of each sub-sample evaluated on
  the full image (separably, one BLAS matrix product for all K sub-samples),
  then ``Generator.poisson`` shot noise and ``Generator.normal`` read noise on
  every pixel, rounding and clipping.

Frames per second = frames / wall time of the whole loop, best of ``--repeats``
rounds in which the contenders run in turn (the machine's speed drifts).
Goal (issue 4): >= 1000 frames/s for the compiled kernel.

Run:  python benchmarks/bench_render.py            (about 10-20 s)
"""
from __future__ import annotations

import os

os.environ.setdefault("NUMBA_NUM_THREADS", "1")

import argparse  # noqa: E402
import math  # noqa: E402
import platform  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

try:  # run from a checkout without ``pip install -e .``
    import stand  # noqa: F401
except ImportError:  # pragma: no cover
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

from stand.instruments.render import render_frames  # noqa: E402
from stand.instruments.screen import (ScreenCamera, exposure_times, frame_times,  # noqa: E402
                                      spot_positions)

TWO_PI = 2.0 * math.pi


def camera(**kw):
    base = dict(pixel_pitch=1e-4, spot_diameter=2e-3, width=640, height=480, bit_depth=8,
                frame_rate=200.0, exposure=2e-3, subsamples=16, background=8.0,
                read_noise=1.0, electrons_per_dn=40.0, peak=200.0, gain=1.0)
    base.update(kw)
    return ScreenCamera(**base)


def whirl_positions(cam, frames, radius=0.01, speed=TWO_PI * 15.0):
    """(F, K, 2) px of a steady whirl of ``radius`` m on the screen."""
    starts = frame_times(frames / cam.frame_rate, cam)[:frames]
    t = exposure_times(starts, cam)
    x, y = radius * np.cos(speed * t), radius * np.sin(speed * t)
    return spot_positions(x, y, speed * t, cam)[1]


def numpy_frames(positions_px, cam, seed=0):
    """Plain-numpy peer: full-image Gaussians, per-pixel Poisson and normal noise."""
    rng = np.random.default_rng(seed)
    su, sv = cam.sigma_px
    cols = np.arange(cam.width, dtype=float)
    rows = np.arange(cam.height, dtype=float)
    top = cam.max_dn
    for block in positions_px:
        K = block.shape[0]
        gu = np.exp(-0.5 * ((cols[None, :] - block[:, :1]) / su) ** 2)     # (K, W)
        gv = np.exp(-0.5 * ((rows[None, :] - block[:, 1:]) / sv) ** 2)     # (K, H)
        signal = cam.background + (cam.peak / K) * (gv.T @ gu)              # (H, W)
        if cam.shot_noise:
            signal = rng.poisson(signal * cam.electrons_per_dn) / cam.electrons_per_dn
        signal = signal + rng.normal(0.0, cam.read_noise, signal.shape)
        yield np.clip(np.floor(signal + 0.5), 0, top).astype(cam.dtype)


def stand_frames(positions_px, cam, noise=True):
    return render_frames(positions_px, cam, noise=noise, reuse=True)


def time_loop(make, n):
    t0 = time.perf_counter()
    last = None
    for last in make():
        pass
    dt = time.perf_counter() - t0
    assert last is not None
    return dt / n


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--frames", type=int, default=2000, help="frames per round (stand)")
    ap.add_argument("--numpy-frames", type=int, default=40, help="frames per round (numpy peer)")
    ap.add_argument("--repeats", type=int, default=5)
    args = ap.parse_args(argv)

    cam = camera()
    cam12 = camera(bit_depth=12, background=128.0, peak=3200.0, read_noise=4.0,
                   electrons_per_dn=2.5)
    long_cam = camera(frame_rate=10.0, exposure=TWO_PI / (TWO_PI * 15.0), subsamples=None,
                      peak=20000.0)
    K_long = long_cam.subsamples_for(TWO_PI * 15.0)
    pos = whirl_positions(cam, args.frames)
    pos12 = whirl_positions(cam12, args.frames)
    pos_np = pos[:args.numpy_frames]
    pos_long = whirl_positions(long_cam, 20)

    contenders = [
        ("**stand** (numba kernel), noise", "8", 16, lambda: stand_frames(pos, cam), args.frames),
        ("stand, noiseless", "8", 16, lambda: stand_frames(pos, cam, noise=False), args.frames),
        ("stand, noise, 12-bit", "12", 16, lambda: stand_frames(pos12, cam12), args.frames),
        ("stand, noise, long exposure (1 whirl period)", "8", K_long,
         lambda: stand_frames(pos_long, long_cam), len(pos_long)),
        ("numpy peer (full-image Gaussians, Generator noise)", "8", 16,
         lambda: numpy_frames(pos_np, cam), len(pos_np)),
    ]
    for _, _, _, make, _ in contenders:          # warm-up: compile, tables, caches
        for i, _f in enumerate(make()):
            if i > 3:
                break
    best = {name: math.inf for name, *_ in contenders}
    for _ in range(args.repeats):
        for name, _, _, make, n in contenders:
            best[name] = min(best[name], time_loop(make, n))

    try:
        import numba
        nb = numba.__version__
    except ImportError:  # pragma: no cover
        nb = "not installed"
    print(f"# bench_render: {platform.python_version()}, numpy {np.__version__}, numba {nb}, "
          f"NUMBA_NUM_THREADS={os.environ.get('NUMBA_NUM_THREADS')}, {platform.machine()}, "
          f"{os.cpu_count()} cores")
    print(f"# 640x480, spot {cam.spot_diameter / cam.pixel_pitch:.0f} px, background "
          f"{cam.background:g} DN, shot noise {cam.electrons_per_dn:g} e-/DN, read noise "
          f"{cam.read_noise:g} DN; whirl 100 px at 15 rev/s; best of {args.repeats} rounds\n")
    ref = best[contenders[-1][0]]
    print("| renderer | bits | sub-samples | time / frame | frames/s | speed-up vs numpy |")
    print("|---|---:|---:|---:|---:|---:|")
    for name, bits, K, _, _ in contenders:
        dt = best[name]
        print(f"| {name} | {bits} | {K} | {dt * 1e3:.3f} ms | {1.0 / dt:,.0f} | {ref / dt:.0f}x |")
    goal = 1.0 / best[contenders[0][0]]
    print(f"\nGoal >= 1000 frames/s (8 bit, noise, 16 sub-samples): "
          f"{'met' if goal >= 1000 else 'NOT met'} ({goal:,.0f} frames/s)")


if __name__ == "__main__":
    main()
