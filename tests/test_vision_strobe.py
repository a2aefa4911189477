"""vision.strobe: reference mark, weight angles and image multiplicity."""
import json
import math
from pathlib import Path

import h5py
import numpy as np
import pytest

from vision import artificial as art
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


#: ball_stuck.toml at the end of its run: both balls stuck together at the stable root
#: Omega = 0.96135 omega_1 of (5.181) while the rotor turns at omega = 3 omega_1, so their
#: angle from the mark moves by -2 pi (1 - Omega / omega) from one flash to the next
RATIO = 0.96135 / 3.0
TRACK, BALL = 0.08, 0.015      #: m: the balancer's track radius, the drawn ball radius
START = 0.222                  #: rad: the pair's angle from the mark at the first flash


@pytest.mark.parametrize("K", [1, 3, 6])
def test_stuck_multiflash_multiplicity(K):
    setup = art.StrobeSetup(slot_radius=0.15, track_radius=TRACK, ball_radius=BALL)
    blur = 2 * BALL / TRACK + setup.blur
    flashes = START - 2 * np.pi * (1 - RATIO) * np.arange(3 * K)     # three frames of K flashes
    rng = np.random.default_rng(K)
    for i in range(3):
        rel = np.repeat(_wrap(flashes[i * K:(i + 1) * K])[:, None], 2, axis=1)   # (K, 2)
        image = art.strobe_frame(rel, setup, rng, flash_angle=1.0, weight_speed_ratio=RATIO)
        res = weight_angles(image, n_weights=2)
        assert res.n_images == art.image_multiplicity(rel, blur)
        assert res.images_per_weight == res.n_images / 2
        if K == 3:   # three distinct positions: each within the slot error of the truth
            want = np.sort(_wrap(rel[:, 0]))
            assert np.max(np.abs(_wrap(res.angles - want))) < setup.blur


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
