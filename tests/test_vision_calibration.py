"""vision.calibration: ring detection, homography, px <-> m, zones, fiducials."""
import math
from pathlib import Path

import cv2
import numpy as np
import pytest

from vision import artificial as art
from vision.calibration import (VisionError, apply_homography, detect_rings, fit_homography,
                                m_to_px, px_to_m, scale_from_fiducials, zone_map)

DATA = Path(__file__).resolve().parents[1] / "data_samples"
RADII = np.arange(21) * 0.0006       # m, zones 0..20 (zone 0 draws nothing)
PITCH = 1e-4


def _cal(tilt):
    """Rings seen by a 320 x 320 camera at PITCH m/px tilted by ``tilt`` rad: the true
    homography screen -> image, the rings found and the calibration fitted to them."""
    H = art.camera_homography(320, 320, PITCH, tilt)
    img = art.ring_image(RADII, H, (320, 320))
    rings = detect_rings(img)
    return H, rings, fit_homography(rings, RADII)


@pytest.mark.parametrize("tilt_deg", [0.0, 10.0, -10.0])
def test_scale_tilt_and_unbiased_radius(tilt_deg):
    H, rings, cal = _cal(math.radians(tilt_deg))
    assert len(rings) == 20
    assert [e.size for e in rings] == sorted(e.size for e in rings)
    assert cal.scale == pytest.approx(PITCH, rel=2e-3)
    assert math.degrees(cal.tilt) == pytest.approx(abs(tilt_deg), abs=0.3)
    if tilt_deg:
        # the +Y side recedes for tilt > 0
        want = 90.0 if tilt_deg > 0 else -90.0
        assert math.degrees(cal.tilt_direction) == pytest.approx(want, abs=2.0)
    rng = np.random.default_rng(1)
    r = rng.uniform(0.001, 0.0125, 200)
    a = rng.uniform(0, 2 * np.pi, 200)
    u, v = apply_homography(H, r * np.cos(a), r * np.sin(a))
    X, Y = px_to_m(u, v, cal)
    rel = np.hypot(X, Y) / r - 1
    assert abs(np.mean(rel)) < 5e-4          # no systematic radius offset
    assert np.max(np.abs(rel)) < 2e-3
    # positions too (the rotation gauge: +X along +u, +Y up)
    assert np.max(np.hypot(X - r * np.cos(a), Y - r * np.sin(a))) < 0.15 * PITCH    # 0.15 px (gauge fixed at the centre)
    uu, vv = m_to_px(X, Y, cal)
    assert np.max(np.hypot(uu - u, vv - v)) < 1e-6


def test_sample_calibration_image():
    import h5py
    img = cv2.imread(str(DATA / "images" / "calibration_rings.png"), cv2.IMREAD_GRAYSCALE)
    with h5py.File(DATA / "recordings" / "stand_cameras.h5") as f:
        radii = f["instruments/screen/ring_radius"][:]
        H = np.array(__import__("json").loads(f["instruments/screen"].attrs["settings"])["homography"])
    cal = fit_homography(detect_rings(img), radii)
    assert cal.scale == pytest.approx(1.0 / H[0, 0], rel=2e-3)
    assert cal.centre_px == pytest.approx((H[0, 2], H[1, 2]), abs=0.05)
    assert cal.tilt < math.radians(1.0)


def test_missing_inner_ring_is_matched_by_size():
    _, rings, _ = _cal(0.0)
    cal = fit_homography(rings[1:], RADII)      # ring of zone 1 not detected
    assert cal.scale == pytest.approx(PITCH, rel=2e-3)


def test_zone_map():
    z = zone_map([0.0, 0.0003, 0.0006, 0.00125, 0.012, 0.0126], RADII)
    assert z.zone.tolist() == [0, 0, 1, 2, 20, 20]
    assert z.unbalance == pytest.approx([0, 0.5 / 16, 1 / 16, 0.00125 / 0.0006 / 16, 20 / 16,
                                         21 / 16])
    with pytest.raises(VisionError):
        zone_map(0.001, [0.002, 0.001])


def test_scale_from_fiducials():
    px = np.array([[10.0, 20.0], [210.0, 20.0], [10.0, 120.0], [150.0, 300.0]])
    s = 2.5e-4
    m = np.c_[(px[:, 0] - 100) * s, -(px[:, 1] - 50) * s]
    cal = scale_from_fiducials(px, m)
    assert cal.scale == pytest.approx(s, rel=1e-9)
    X, Y = px_to_m(px[:, 0], px[:, 1], cal)
    assert np.allclose(np.c_[X, Y], m, atol=1e-12)
    cal2 = scale_from_fiducials(px[:2], m[:2])          # a ruler: two marks
    assert cal2.scale == pytest.approx(s, rel=1e-9)
    with pytest.raises(VisionError):
        scale_from_fiducials(px[:1], m[:1])
    with pytest.raises(VisionError):
        scale_from_fiducials(np.zeros((3, 2)), m[:3])


def test_bad_input():
    with pytest.raises(VisionError, match="blank"):
        detect_rings(np.full((100, 100), 255, np.uint8))
    with pytest.raises(VisionError):
        detect_rings(np.zeros((5,), np.uint8))
    # junk: random blobs and lines, no rings
    junk = np.full((200, 200), 255, np.uint8)
    cv2.line(junk, (10, 10), (190, 150), 0, 1)
    cv2.rectangle(junk, (30, 120), (80, 180), 0, -1)
    with pytest.raises(VisionError, match="no rings"):
        detect_rings(junk)
    # non-concentric circles: a family of at most one per centre
    junk = np.full((200, 200), 255, np.uint8)
    for (cx, cy, r) in ((50, 50, 30), (140, 60, 25), (100, 150, 35)):
        cv2.circle(junk, (cx, cy), r, 0, 1)
    with pytest.raises(VisionError, match="concentric"):
        detect_rings(junk)
    _, rings, _ = _cal(0.0)
    with pytest.raises(VisionError):
        fit_homography(rings[:1], RADII)
    with pytest.raises(VisionError):
        fit_homography(rings, RADII[:5])        # more rings than radii
    with pytest.raises(VisionError, match="proportional"):
        fit_homography(rings[::2], RADII)       # every other ring: sizes do not match
