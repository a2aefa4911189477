"""Calibration of the stated uncertainties on a lab camera's artefacts (issue 42, camera side).

Paths of :mod:`bench_uncertainty` (merged through :mod:`_uncertainty_images`), each
``path(seed, workdir) -> {quantity: z}``:

* ``camera``: the stand's screen camera (:class:`stand.scene.screen_camera.ScreenCamera`,
  160 x 160 px, sigma 2 px, peak 150 DN, 47 frames/s, 2 ms) with a barrel lens (k1 drawn
  in [-0.35, -0.1], k2 = 0.05), JPEG at quality 30 and the lamps' 100 Hz flicker (depth
  0.3); the spot on a closed-form circle of 3 mm on the screen (phase, ring offset and
  noise drawn per seed); :func:`vision.spot.track` with the declared JPEG quality on
  :data:`FRAMES` frames: ``u``, ``v`` of frame ``seed % FRAMES`` against the
  exposure-averaged centre (the truth: the circle through the homography and the Brown
  model, ``frame_truth``); the ring image (rings every 0.45 mm about the drawn offset)
  through :func:`vision.calibration.fit_homography` with the declared lens: ``scale``
  against the pixel pitch;
* ``camera-undeclared``: the same frames and rings, nothing declared (the lab did not say
  its camera compresses, nor its lens): shown to be *refused* -- the JPEG block noise is
  not in the std and the barrel lens biases the scale; ``stand track`` needs the ring
  file's ``jpeg_quality`` and ``lens_k1``, ``lens_k2``, ``lens_focal_px``.
"""
from __future__ import annotations

import math

import numpy as np

FRAMES = 20
PITCH = 1e-4          #: m of screen per px


def _draw(seed, frames=True):
    from stand.instruments.render import render_frames
    from stand.instruments.rings import render_ring_image
    from stand.instruments.screen import frame_truth, spot_positions
    from stand.scene.screen_camera import ScreenCamera
    from vision.camera_artefacts import flicker_gain

    rng = np.random.default_rng(42_000 + seed)
    off = rng.uniform(-1e-3, 1e-3, 2)
    cam = ScreenCamera(pixel_pitch=PITCH, width=160, height=160, frame_rate=47.0, exposure=0.002,
                       subsamples=4, spot_diameter=0.8e-3, peak=150.0, background=8.0,
                       seed=seed, lens_k1=float(rng.uniform(-0.35, -0.1)), lens_k2=0.05,
                       jpeg_quality=30, flicker_depth=0.3, offset_x=off[0], offset_y=off[1])
    t = np.arange(FRAMES) / cam.frame_rate + rng.uniform(0, 0.02)
    T = t[:, None] + (np.arange(cam.subsamples) + 0.5) / cam.subsamples * cam.exposure
    w = 2 * math.pi * 11.7
    ph = w * T + rng.uniform(0, 2 * math.pi)
    screen_m, px = spot_positions(3e-3 * np.cos(ph), 3e-3 * np.sin(ph), ph, cam)
    truth = frame_truth(screen_m, px, cam)["centre_px"]
    g = flicker_gain(t + 0.5 * cam.exposure, cam.mains_frequency, cam.flicker_depth)
    frames = list(render_frames(px, cam, gains=g)) if frames else None
    radii = np.arange(13) * 0.45e-3
    return cam, frames, truth, render_ring_image(radii, cam), radii


def _path(seed, declared):
    from stand.instruments.screen import lens_of
    from vision.calibration import detect_rings, fit_homography
    from vision.spot import track

    cam, frames, truth, rings, radii = _draw(seed)
    df = track(frames, gain=cam.electrons_per_dn, jpeg_quality=30 if declared else None)
    k = seed % FRAMES
    cal = fit_homography(detect_rings(rings), radii, lens=lens_of(cam) if declared else None)
    return {"u": (df["u_px"][k] - truth[k, 0]) / df["u_std_px"][k],
            "v": (df["v_px"][k] - truth[k, 1]) / df["v_std_px"][k],
            "scale": (cal.scale - PITCH) / cal.scale_std}


def camera(seed, workdir=None):
    """z of a frame's spot centre (u, v) and of the ring scale, artefacts declared."""
    return _path(seed, True)


def camera_undeclared(seed, workdir=None):
    """The same, nothing declared (the refused row)."""
    return _path(seed, False)


def camera_lens_estimated(seed, workdir=None):
    """z of the ring scale with k1, k2 estimated from the rings (nothing declared but the
    principal point, the image centre; the focal length normalising r: the image width)."""
    from vision.calibration import detect_rings, fit_homography
    from vision.camera_artefacts import Lens

    cam, _, _, rings, radii = _draw(seed, frames=False)
    start = Lens(0.0, 0.0, float(cam.width), ((cam.width - 1) / 2, (cam.height - 1) / 2))
    cal = fit_homography(detect_rings(rings), radii, lens=start, estimate_lens=True)
    return {"scale": (cal.scale - PITCH) / cal.scale_std}


PATHS = {"camera": camera, "camera-undeclared": camera_undeclared,
         "camera-lens-estimated": camera_lens_estimated}
