"""vision.strobe: reference mark, weight angles and image multiplicity."""
import dataclasses
import json
import math
from pathlib import Path

import h5py
import numpy as np
import pytest

from stand.instruments.stroboscope import Stroboscope, image_multiplicity, render_strobe_frames
from stand.scene_file import load_scene
from stand.simulate import simulate
from vision.strobe import VisionError, weight_angles

DATA = Path(__file__).resolve().parents[1] / "data_samples"


def _wrap(a):
    return (np.asarray(a) + np.pi) % (2 * np.pi) - np.pi


def test_sample_recording_weight_angles_within_slot_error():
    with h5py.File(DATA / "recordings" / "stand_cameras.h5") as f:
        g = f["instruments/stroboscope"]
        frames = g["frames"][:]
        truth = f["truth/stroboscope/relative_angle"][:]
        st = json.loads(g.attrs["settings"])
    slot_error = st["slot_width"] / st["slot_radius"]      # (4.1) in rad
    for img, tr in zip(frames, truth):
        res = weight_angles(img, n_weights=2)
        assert res.n_images == 2
        assert _wrap(res.mark_angle - st["flash_angle"]) == pytest.approx(0, abs=slot_error)
        want = np.sort(_wrap(tr.ravel()))
        assert np.max(np.abs(_wrap(res.angles - want))) < slot_error
        assert np.all(res.sigma > 0) and np.all(res.sigma < slot_error)
    # the balanced end of the run: +-120 deg
    assert np.degrees(res.angles) == pytest.approx([-120.0, 120.0], abs=math.degrees(slot_error))


@pytest.fixture(scope="module")
def stuck():
    """ball_stuck.toml simulated at 200 Hz (22 samples per revolution)."""
    s = load_scene(DATA / "scenes" / "ball_stuck.toml")
    return simulate(dataclasses.replace(s, run=dataclasses.replace(s.run, sample_rate=200.0)))


@pytest.mark.parametrize("K", [1, 3, 6])
def test_stuck_multiflash_multiplicity(stuck, K):
    t1 = stuck.t[-1]
    t0 = t1 - 0.2 * (t1 - stuck.t[0])
    ball = 0.015
    track = stuck.scene.balancer.radius[0]
    strobe = Stroboscope(exposure_flashes=K, shaft_motion=False, slot_radius=0.15,
                         flash_angle=1.0, ball_radius=ball)
    blur = 2 * ball / track + strobe.blur
    for f in render_strobe_frames(stuck, strobe, t0, t1, max_frames=3):
        res = weight_angles(f.image, n_weights=2)
        assert res.n_images == image_multiplicity(f.relative_angle, blur)
        assert res.images_per_weight == res.n_images / 2
        if K == 3:   # three distinct positions: each within the slot error of the truth
            want = np.sort(_wrap(f.relative_angle[:, 0]))
            assert np.max(np.abs(_wrap(res.angles - want))) < strobe.blur


def test_bad_frames():
    with pytest.raises(VisionError, match="blank"):
        weight_angles(np.zeros((64, 64), np.uint8), n_weights=2)
    with pytest.raises(VisionError):
        weight_angles(np.zeros((4,), np.uint8), n_weights=2)
    rng = np.random.default_rng(0)
    with pytest.raises(VisionError):
        weight_angles(rng.integers(0, 255, (64, 64)).astype(np.uint8), n_weights=2)
    # a lit disk without a mark or weights
    yy, xx = np.mgrid[0:120, 0:120]
    disk = np.where(np.hypot(xx - 59.5, yy - 59.5) < 50, 50, 10).astype(np.uint8)
    with pytest.raises(VisionError):
        weight_angles(disk, n_weights=2)
