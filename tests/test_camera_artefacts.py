"""The screen camera's artefacts (issue 42, camera side): drawn by the stand
(``[instruments.screen]`` lens_k1/k2, jpeg_quality, flicker_depth, hot_pixels, saturation,
drop_rate) and allowed for by the analysis (vision.camera_artefacts, vision.compression,
the ring calibration with a declared lens), one fast test per artefact, and the committed
lab-like sample scored against its truth."""
import itertools
import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from stand.errors import SceneError
from stand.instruments.render import render_frames
from stand.instruments.rings import render_ring_image
from stand.instruments.screen import frame_truth, lens_of, spot_positions
from stand.scene.screen_camera import ScreenCamera
from vision.calibration import detect_rings, fit_homography, px_to_m
from vision.background import median_background
from vision.camera_artefacts import (Lens, declared_camera, declared_keys, distort_points,
                                     dropped_frames, flicker_gain, hot_pixel_map,
                                     repair_hot_pixels, undistort_points)
from vision.io import iter_frames
from vision.spot import track

ROOT = Path(__file__).resolve().parents[1]
VIDEO = ROOT / "data_samples" / "video"
PITCH = 1e-4          # m of screen per px
#: the issue-30 standard of a stated std, here on pooled u and v: RMS(error) <= 1.5 x RMS(std)
RATIO_MAX = 1.5


def _camera(**kw):
    base = dict(pixel_pitch=PITCH, width=128, height=128, frame_rate=47.0, exposure=0.002,
                subsamples=4, spot_diameter=0.8e-3, peak=150.0, background=8.0, seed=3)
    return ScreenCamera(**{**base, **kw})


def _frames(cam, n=40, radius_m=3e-3):
    """Frames of the spot on a circle of ``radius_m`` on the screen at 11.7 rev/s, with the
    flicker's gains; returns (frames, truth centre px (n, 2), truth centre m (n, 2), gains)."""
    t = np.arange(n) / cam.frame_rate
    T = t[:, None] + (np.arange(cam.subsamples) + 0.5) / cam.subsamples * cam.exposure
    w = 2 * math.pi * 11.7
    screen_m, px = spot_positions(radius_m * np.cos(w * T), radius_m * np.sin(w * T), w * T, cam)
    tr = frame_truth(screen_m, px, cam)
    g = flicker_gain(t + 0.5 * cam.exposure, cam.mains_frequency, cam.flicker_depth)
    return list(render_frames(px, cam, gains=g)), tr["centre_px"], tr["centre_m"], g


def _scores(df, truth_px):
    e = np.c_[df["u_px"] - truth_px[:, 0], df["v_px"] - truth_px[:, 1]]
    s = np.c_[df["u_std_px"], df["v_std_px"]]
    return math.sqrt(np.mean(e ** 2)), math.sqrt(np.mean(s ** 2))


# ---------------------------------------------------------------- lens distortion
def test_lens_distortion_is_opencvs_model_and_the_ring_calibration_undoes_it():
    cam = _camera(width=160, height=160, lens_k1=-0.3, lens_k2=0.05, offset_x=3e-4,
                  offset_y=-2e-4)
    lens = lens_of(cam)
    assert lens.focal_px == pytest.approx(1.4 * 160)          # camera distance / pitch
    u, v = np.meshgrid(np.linspace(0, 159, 7), np.linspace(0, 159, 7))
    ud, vd = distort_points(u, v, lens)
    # barrel: the corner moves in by k1 r^2 + k2 r^4 of its radius (r^2 = 0.2516 here)
    r2 = ((0 - 79.5) ** 2 * 2) / lens.focal_px ** 2
    assert ud[0, 0] - 79.5 == pytest.approx(-79.5 * (1 - 0.3 * r2 + 0.05 * r2 * r2))
    uu, vv = undistort_points(ud, vd, lens)                   # cv2.undistortPoints inverts it
    assert np.max(np.abs(uu - u)) < 1e-6 and np.max(np.abs(vv - v)) < 1e-6
    radii = np.arange(13) * 0.45e-3
    rings = detect_rings(render_ring_image(radii, cam))
    declared = fit_homography(rings, radii, lens=lens)
    assert abs(declared.scale - PITCH) < 2 * declared.scale_std      # within its +-
    assert declared.scale_std < 1e-3 * PITCH
    X, Y = px_to_m(*distort_points(79.5 + 40, 79.5, lens), declared)  # 4 mm right of centre
    # (the screen origin of the calibration is the rings' centre)
    assert X == pytest.approx(4e-3 - cam.offset_x, abs=3 * 40 * declared.scale_std + 2e-6)
    # undeclared, the barrel lens shrinks the outer rings: a scale off by many of its std
    blind = fit_homography(rings, radii)
    assert abs(blind.scale - PITCH) > 4 * blind.scale_std
    # ... unless k1, k2 are estimated with the rings (principal point: the image centre;
    # any normalising focal length): the scale within its (wider) +-
    start = Lens(0.0, 0.0, 160.0, (79.5, 79.5))
    est = fit_homography(rings, radii, lens=start, estimate_lens=True)
    assert abs(est.scale - PITCH) < 2 * est.scale_std < 5e-3 * PITCH


def test_declared_camera_keys():
    lens, q = declared_camera({"lens_k1": "-0.25", "lens_k2": 0.05, "lens_focal_px": 358.4,
                               "jpeg_quality": 30.0}, (256, 256))
    assert (lens.k1, lens.k2, lens.focal_px, lens.centre_px, q) == (-0.25, 0.05, 358.4,
                                                                     (127.5, 127.5), 30)
    assert declared_camera({}, (1, 1)) == (None, None)
    # what stand video writes in the ring file and stand track reads from a recording
    cam = _camera(lens_k1=-0.25, lens_k2=0.05, jpeg_quality=30)
    keys = declared_keys(cam.to_attrs())
    assert keys == {"lens_k1": -0.25, "lens_k2": 0.05, "jpeg_quality": 30,
                    "lens_focal_px": pytest.approx(1.4 * 128)}
    assert declared_camera(keys, (128, 128))[0] == lens_of(cam)
    assert declared_keys(_camera().to_attrs()) == {}
    with pytest.raises(ValueError, match="lens_focal_px"):
        declared_camera({"lens_k1": -0.2}, (64, 64))
    with pytest.raises(ValueError, match="jpeg_quality"):
        declared_camera({"jpeg_quality": 300}, (64, 64))


# ---------------------------------------------------------------- JPEG
def test_jpeg_spot_std_widened_for_the_block_noise():
    cam = _camera(jpeg_quality=30)
    frames, truth, _, _ = _frames(cam, n=30)
    assert len(np.unique(frames[0][:8, :8])) <= 2            # q 30 flattens the noise
    def z(df):
        return np.r_[(df["u_px"] - truth[:, 0]) / df["u_std_px"],
                     (df["v_px"] - truth[:, 1]) / df["v_std_px"]]

    df = track(frames, gain=cam.electrons_per_dn, jpeg_quality=30)
    rms, std = _scores(df, truth)
    assert 0.03 < rms < 0.3                                  # the block noise, ~0.1 px
    assert rms <= RATIO_MAX * std
    assert math.sqrt(np.mean(z(df) ** 2)) <= 1.5 and np.mean(np.abs(z(df)) < 2) >= 0.85
    blind = z(track(frames, gain=cam.electrons_per_dn))     # undeclared: the std too small
    assert math.sqrt(np.mean(blind ** 2)) > 2 and np.mean(np.abs(blind) < 2) < 0.85


def test_jpeg_needs_8_bits():
    with pytest.raises(SceneError, match="jpeg_quality"):
        _camera(jpeg_quality=30, bit_depth=12)


# ---------------------------------------------------------------- flicker
def test_flicker_modulates_each_frame_and_the_track_stays_right():
    cam = _camera(flicker_depth=0.4, mains_frequency=50.0)
    frames, truth, _, g = _frames(cam)
    assert g.min() < 0.7 and g.max() > 1.3                   # 100 Hz aliased at 47 frames/s
    df = track(frames, gain=cam.electrons_per_dn)
    # the spot's peak follows the lamps (the background's 8 DN too): within the noise
    ratio = df["peak"].to_numpy() / g
    assert np.std(ratio) / np.mean(ratio) < 0.05
    rms, std = _scores(df, truth)
    assert rms <= RATIO_MAX * std


def test_flicker_depth_out_of_range():
    with pytest.raises(SceneError, match="flicker_depth"):
        _camera(flicker_depth=1.2)


# ---------------------------------------------------------------- hot pixels, saturation
def test_hot_pixels_fixed_and_ignored():
    cam = _camera(hot_pixels=12)
    frames, truth, _, _ = _frames(cam, n=20)
    hot = [np.argwhere(f == 255) for f in frames]
    assert all(len(h) == 12 and np.array_equal(h, hot[0]) for h in hot)   # the same pixels
    # a hot pixel in the ROI where the spot is not is taken for a dim spot ...
    assert _scores(track(frames, gain=cam.electrons_per_dn), truth)[0] > 5
    # ... unless the map of the median of the frames repairs them first
    found = hot_pixel_map(median_background(frames))
    assert sorted(zip(*found)) == sorted(map(tuple, hot[0]))
    df = track([repair_hot_pixels(f, found) for f in frames], gain=cam.electrons_per_dn)
    assert df["ok"].all()
    rms, std = _scores(df, truth)
    assert rms <= RATIO_MAX * std


def test_saturation_clips_below_full_scale():
    cam = _camera(peak=220.0, saturation=180.0)
    frames, truth, _, _ = _frames(cam, n=20)
    assert max(int(f.max()) for f in frames) == 180
    df = track(frames, gain=cam.electrons_per_dn, saturation=180.0)
    assert df["flags"].astype(str).str.contains("saturated").all()
    rms, std = _scores(df, truth)
    assert rms < 0.1 and rms <= RATIO_MAX * max(std, 0.02)   # a clipped symmetric spot


# ---------------------------------------------------------------- frame drops
def test_dropped_frames_found_from_timestamps():
    t = np.arange(50) / 30.0
    keep = np.ones(50, bool)
    keep[[7, 20, 21, 40]] = False
    d = dropped_frames(t[keep])
    assert d["count"] == 4
    assert t[keep][d["after"]].tolist() == pytest.approx([t[6], t[19], t[39]])
    assert d["missing"] == pytest.approx(t[~keep])
    assert dropped_frames(t)["count"] == 0


# ---------------------------------------------------------------- the committed sample
def test_lab_sample_track_and_rings_within_their_std():
    """data_samples/video/screen_lab.avi (lens k1 -0.25, k2 0.05; JPEG 30; 100 Hz flicker):
    the first 40 frames' spot within 1.5 x its stated std, the ring scale within its +-."""
    from stand.analysis.tracking import read_ring_file

    keys = read_ring_file(VIDEO / "screen_lab_rings.txt")
    from vision.io import read_image

    img = read_image(VIDEO / "screen_lab_rings.png")
    lens, q = declared_camera(keys, img.shape)
    assert q == 30 and lens.k1 == -0.25
    cal = fit_homography(detect_rings(img), keys["ring_radii_m"], lens=lens)
    assert abs(cal.scale - keys["pixel_pitch_m"]) < 2 * cal.scale_std
    truth = pd.read_csv(VIDEO / "screen_lab_truth.csv", comment="#").iloc[:40]
    frames = (r.image for r in itertools.islice(iter_frames(str(VIDEO / "screen_lab.avi")), 40))
    df = track(frames, jpeg_quality=q)
    rms, std = _scores(df, truth[["u_px", "v_px"]].to_numpy())
    assert rms <= RATIO_MAX * std
    assert (VIDEO / "screen_lab.avi").stat().st_size < 2e6


def test_stand_track_repairs_stuck_pixels_and_says_how_many():
    """`stand track` (stand.analysis.tracking.track_frames) finds the 12 hot pixels as constant
    over the first frames and replaces them before locating: the track within 1.5x its std
    (unrepaired it is > 5 px off, test above), one preamble line with the count."""
    from stand.analysis.tracking import track_frames
    from vision.camera_artefacts import stuck_pixels_repaired

    cam = _camera(hot_pixels=12)
    frames, truth, _, _ = _frames(cam, n=20)
    df = track_frames(np.stack(frames), gain=cam.electrons_per_dn)
    assert df.attrs["preamble"]["stuck_pixels"].startswith("12 ")
    assert df["ok"].all()
    rms, std = _scores(df, truth)
    assert rms <= RATIO_MAX * std
    clean, n = stuck_pixels_repaired(_frames(_camera(), n=20)[0])     # none: frames unchanged
    assert n == 0 and all(np.array_equal(a, b) for a, b in zip(clean, _frames(_camera(), n=20)[0]))
