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

Every contender is checked before it is timed (``benchmarks/_peers.py``): its
first frames against the exact expectation -- background plus the spot
integrated over each pixel (``erf``), written here independently of both
renderers.  Noiseless: the largest deviation [DN] (rounding gives 0.5);
with noise: | RMS of (frame - expectation) / sigma - 1 |, sigma^2 = shot noise +
read noise^2 + 1/12 (rounding), on the pixels at least 5 sigma from 0 and from
saturation, the larger of the spot's pixels (> background + 1 DN) and the
others.  An invalid contender is printed as such, not timed.

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

from _peers import check_peer  # noqa: E402
from stand.instruments.render import render_frames  # noqa: E402
from stand.instruments.screen import (ScreenCamera, exposure_times, frame_times,  # noqa: E402
                                      spot_positions)

TWO_PI = 2.0 * math.pi
CHECK_FRAMES = 10         #: frames of each contender checked against the expectation
TOL_NOISELESS_DN = 0.6    #: max |frame - expectation| [DN]: rounding 0.5, the 4-sigma window
TOL_NOISE = 0.05          #: | RMS of the normalised residual - 1 |, spot or background pixels


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


def expected_frame(block, cam) -> np.ndarray:
    """(H, W) mean of a frame [DN], not rounded: background + the Gaussian spot of every
    sub-sample (weight 1/K, peak ``cam.peak``) integrated over each pixel's area."""
    from scipy.special import erf

    su, sv = cam.sigma_px

    def pixel_integrals(centres, n, s):   # (K, n): integral over [x - 1/2, x + 1/2]
        a = (np.arange(n)[None, :] - np.asarray(centres)[:, None]) / (s * math.sqrt(2.0))
        h = 0.5 / (s * math.sqrt(2.0))
        return s * math.sqrt(math.pi / 2.0) * (erf(a + h) - erf(a - h))

    gu = pixel_integrals(block[:, 0], cam.width, su)
    gv = pixel_integrals(block[:, 1], cam.height, sv)
    return cam.background + (cam.peak / block.shape[0]) * (gv.T @ gu)


def frame_error(frames, blocks, cam, noise: bool) -> float:
    """Error of rendered frames against :func:`expected_frame` (see the module's docstring)."""
    if not noise:
        return max(float(np.max(np.abs(f.astype(float) - np.clip(expected_frame(b, cam), 0,
                                                                   cam.max_dn))))
                   for f, b in zip(frames, blocks))
    sq, count = np.zeros(2), np.zeros(2)          # the spot's pixels, the background's
    for f, b in zip(frames, blocks):
        mean = expected_frame(b, cam)
        shot = mean / cam.electrons_per_dn if cam.shot_noise else 0.0
        sd = np.sqrt(shot + cam.read_noise ** 2 + 1.0 / 12.0) * np.ones_like(mean)
        use = (mean - 5 * sd > 0) & (mean + 5 * sd < cam.max_dn)
        spot = mean > cam.background + 1.0
        r2 = ((f.astype(float) - mean) / sd) ** 2
        for k, region in enumerate((use & spot, use & ~spot)):
            sq[k] += float(np.sum(r2[region]))
            count[k] += int(np.count_nonzero(region))
    if not count.all():
        return math.inf
    return float(np.max(np.abs(np.sqrt(sq / count) - 1.0)))


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

    # (name, bits, K, frames to time, frame count, camera, positions, noise)
    contenders = [
        ("**stand** (numba kernel), noise", "8", 16, lambda: stand_frames(pos, cam), args.frames,
         cam, pos, True),
        ("stand, noiseless", "8", 16, lambda: stand_frames(pos, cam, noise=False), args.frames,
         cam, pos, False),
        ("stand, noise, 12-bit", "12", 16, lambda: stand_frames(pos12, cam12), args.frames,
         cam12, pos12, True),
        ("stand, noise, long exposure (1 whirl period)", "8", K_long,
         lambda: stand_frames(pos_long, long_cam), len(pos_long), long_cam, pos_long, True),
        ("numpy peer (full-image Gaussians, Generator noise)", "8", 16,
         lambda: numpy_frames(pos_np, cam), len(pos_np), cam, pos_np, True),
    ]
    peers = {}
    for name, _, _, make, _, c, p, noisy in contenders:   # check (and warm up) first
        first = [f.copy() for f, _ in zip(make(), range(CHECK_FRAMES))]
        peers[name] = check_peer(name, frame_error(first, p[:CHECK_FRAMES], c, noisy),
                                 TOL_NOISE if noisy else TOL_NOISELESS_DN)
    best = {name: math.inf for name, *_ in contenders}
    for _ in range(args.repeats):
        for name, _, _, make, n, *_ in contenders:
            if peers[name].valid:                          # an invalid one is not timed
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
    print(f"# checked first: {CHECK_FRAMES} frames each against the exact expectation; valid when "
          f"|RMS(residual / sigma) - 1| <= {TOL_NOISE:g} (noise) or max |residual| <= "
          f"{TOL_NOISELESS_DN:g} DN (noiseless)\n")
    numpy_name = contenders[-1][0]
    ref = best[numpy_name] if peers[numpy_name].valid else math.nan
    print("| renderer | bits | sub-samples | check error | time / frame | frames/s | speed-up vs numpy |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for name, bits, K, *_ in contenders:
        dt, peer = best[name], peers[name]
        ratio = f"{ref / dt:.0f}x" if math.isfinite(ref) else "-"
        cells = peer.cells(f"{dt * 1e3:.3f} ms", f"{1.0 / dt:,.0f}", ratio)
        print(f"| {name} | {bits} | {K} | {peer.error:.2g} | " + " | ".join(cells) + " |")
    first = peers[contenders[0][0]]
    goal = 1.0 / best[contenders[0][0]]
    print("\nGoal >= 1000 frames/s (8 bit, noise, 16 sub-samples): "
          + (f"{'met' if goal >= 1000 else 'NOT met'} ({goal:,.0f} frames/s)" if first.valid
             else f"NOT met: {first.verdict}"))


if __name__ == "__main__":
    main()
