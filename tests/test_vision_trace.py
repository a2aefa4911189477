"""vision.trace: the circle a whirling spot draws in a long exposure, against
frames drawn with a known circle (vision.artificial draws them)."""
import math

import numpy as np
import pytest

from vision import artificial as art
from vision.trace import fit_trace, track_traces


def _circle_frames(R, n=12, peak=4000.0, turns=3, epi=0.0, seed=0):
    """n frames of a spot (sigma 2 px) drawing `turns` turns of a circle of R px
    (plus an epicycle of `epi` px at -2x the whirl, for a non-circular trace)."""
    cam = art.Camera(width=320, height=320, sigma_px=2.0, peak=peak)   # 0.8 mm spot, 0.1 mm/px
    rng = np.random.default_rng(seed)
    out = []
    for k in range(n):
        c = np.array([160.0, 160.0]) + rng.uniform(-2, 2, 2)
        out.append((art.orbit_positions(c, R, 4000, turns=turns, phase=rng.uniform(0, 2 * np.pi),
                                        epicycle_px=epi), c))
    frames = list(art.spot_frames([p for p, _ in out], cam, seed=seed))
    return frames, np.array([c for _, c in out]), cam.sigma_uv[0]


@pytest.mark.parametrize("R", [20.0, 60.0])
def test_radius_and_centre_of_resolved_circles(R):
    frames, centres, sigma = _circle_frames(R)
    fits = [fit_trace(f) for f in frames]
    assert all(f.ok and not f.flags for f in fits)
    err = np.array([f.radius_px - R for f in fits])
    std = np.array([f.radius_std_px for f in fits])
    # noise-limited: ~0.005 px; the uncorrected rms radius would be off by ~2 s^2 / (2R)
    assert np.sqrt(np.mean(err ** 2)) < 0.02
    assert np.mean(np.abs(err) <= 2 * std) >= 0.75
    assert abs(fits[0].rms_radius_px - R) > 5 * abs(err[0])       # the correction matters
    assert all(abs(f.spot_sigma_px - sigma) < 0.1 for f in fits)
    cerr = np.array([[f.u_px, f.v_px] for f in fits]) - centres
    assert np.abs(cerr).max() < 0.05


def test_small_circle_needs_the_spot_sigma():
    """R = 3 px < 3 sigma: flagged unresolved without the spot's sigma; with it,
    R^2 = <|x - c|^2> - 2 sigma^2 still holds exactly."""
    frames, _, sigma = _circle_frames(3.0, n=8, peak=300.0)
    free = [fit_trace(f) for f in frames]
    given = [fit_trace(f, spot_sigma_px=sigma) for f in frames]
    assert all("unresolved" in f.flags for f in free)
    err = np.array([f.radius_px - 3.0 for f in given])
    assert np.sqrt(np.mean(err ** 2)) < 0.1
    assert not any(f.flags for f in given)


def test_epitrochoid_flagged_not_circle():
    frames, _, sigma = _circle_frames(40.0, n=3, epi=4.0)
    fits = [fit_trace(f, spot_sigma_px=sigma) for f in frames]
    assert all("not_circle" in f.flags for f in fits)
    # the rms radius of z = R e^{ip} + a e^{-2ip} is sqrt(R^2 + a^2)
    for f in fits:
        assert f.radius_px == pytest.approx(math.hypot(40.0, 4.0), abs=0.05)


def test_saturated_small_circle_flagged():
    frames, _, _ = _circle_frames(6.0, n=2, peak=4000.0)
    assert all("saturated" in fit_trace(f).flags for f in frames)


def test_missing_blank_and_bad_input():
    blank = np.zeros((100, 100), np.uint8)
    r = fit_trace(blank)
    assert not r.ok and {"missing", "blank"} <= r.flags and math.isnan(r.radius_px)
    rng = np.random.default_rng(1)
    noise = rng.normal(10, 1, (100, 100)).round().astype(np.uint8)
    assert "missing" in fit_trace(noise).flags
    with pytest.raises(ValueError, match="frame"):
        fit_trace(np.zeros(10))
    with pytest.raises(ValueError, match="spot_sigma_px"):
        fit_trace(noise, spot_sigma_px=-1.0)
    df = track_traces([blank, noise])
    assert list(df["ok"]) == [False, False] and df["radius_px"].isna().all()
