"""The light-slot stroboscope (issue 4, item 2; monograph 4.3.1, digest ch5 sections 5.3, 6.1).

Oracles:
* a balanced run: the weights are at the balancing angles pi -+ arccos(e0) and
  the stroboscope shows them at the same place at every flash -- the same
  relative angle within the slot error (4.1), the same pixels within the
  angular blur;
* a stuck-ball run: per flash the balls' relative angle changes by
  -2 pi (1 - Omega_k/omega), Omega_k the balls' mean speed over that
  revolution, integrated independently from a run sampled on a grid that
  contains the flash instants (no interpolation), to 1e-6 rad;
* multi-flash exposures: the number of ball images equals the clusters of the
  predicted positions (tripling at Omega/omega = 0.32 ~ 1/3).
"""
import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest
from scipy import ndimage

from stand.instruments.strobe_readings import (flash_times, image_multiplicity,
                                               multiplicity_for_ratio, strobe_angles)
from stand.instruments.strobe_render import LEVEL_BALL, LEVEL_INTERIOR, render_strobe_frames
from stand.scene.strobe_settings import Stroboscope, default_ball_radius, reading_error
from stand.instruments.timing import wrap
from stand.scene.model import SceneError, SpeedDrive
from stand.scene.parse import Table, load_scene
from stand.integrate.simulate import simulate
from stand.theories.planar.qp import qp_roots

SCENES = Path(__file__).resolve().parents[1] / "data_samples" / "scenes"
TWO_PI = 2 * math.pi
NOISELESS = dict(read_noise=0.0, full_well=0.0)


@pytest.fixture(scope="module")
def runup():
    return simulate(load_scene(SCENES / "ball_runup.toml"))


@pytest.fixture(scope="module")
def stuck_scene():
    return load_scene(SCENES / "ball_stuck.toml")


@pytest.fixture(scope="module")
def stuck(stuck_scene):
    """ball_stuck.toml sampled at 200 Hz: 22 samples per rotor revolution (the
    file's 100 Hz gives 11, and the Hermite interpolation error of the ball
    angles ~9e-7 rad, see test_stuck_strobe_at_the_files_sample_rate)."""
    return simulate(dataclasses.replace(
        stuck_scene, run=dataclasses.replace(stuck_scene.run, sample_rate=200.0)))


@pytest.fixture(scope="module")
def stuck_reference(stuck_scene):
    """The same run sampled at 360 Hz = 40 samples per revolution (9 rev/s)."""
    return simulate(dataclasses.replace(
        stuck_scene, run=dataclasses.replace(stuck_scene.run, sample_rate=360.0)))


def _last(traj, fraction):
    return traj.t[-1] - fraction * (traj.t[-1] - traj.t[0]), traj.t[-1]


# ---------------------------------------------------------------- (4.1)
def test_reading_error_is_slot_width_over_perimeter():
    assert reading_error(0.002, 0.12) == pytest.approx(0.002 / (TWO_PI * 0.12), rel=1e-15)
    s = Stroboscope(slot_width=0.003, slot_radius=0.15)
    assert s.reading_error == pytest.approx(0.003 / (TWO_PI * 0.15))
    assert s.blur == pytest.approx(TWO_PI * s.reading_error)  # rad


# ---------------------------------------------------------------- balanced run
def test_balanced_run_same_relative_angles_at_every_flash(runup):
    strobe = Stroboscope(flash_angle=math.radians(30.0))
    t0, t1 = 35.0, 40.0  # last 5 s at 15 rev/s: 75 flashes
    r = strobe_angles(runup, strobe, t0, t1)
    assert r.t.size == 75
    # one flash per revolution, at the flash angle
    assert np.allclose(np.diff(r.t), 1 / 15.0, atol=1e-12)
    assert np.max(np.abs(wrap(r.rotor_angle - strobe.flash_angle))) < 1e-10
    # the same relative angles at every flash, within the slot error (4.1)
    assert np.max(np.ptp(r.relative_angle, axis=0)) <= strobe.blur
    assert np.max(np.ptp(r.relative_angle, axis=0)) < 1e-9  # the truth: really constant
    # and they are the balancing angles pi -+ arccos(e0), e0 = 0.5
    sc = runup.scene
    e0 = sc.rotor.unbalance / sc.balancer.capacity
    expected = np.sort(wrap(math.pi + np.array([-1, 1]) * math.acos(e0)))
    assert np.allclose(np.sort(r.relative_angle[-1]), expected, atol=1e-5)


def _ball_centroids(image, full, level_lo, level_hi, mask=None):
    """Centroids (column, row) of the blobs brighter than the mid level."""
    img = image.astype(float) / full
    thr = 0.5 * (level_lo + level_hi)
    sel = img > thr
    if mask is not None:
        sel &= mask
    lab, k = ndimage.label(sel)
    w = np.where(sel, img - level_lo, 0.0)
    cents = ndimage.center_of_mass(w, lab, range(1, k + 1))
    return np.array([(c[1], c[0]) for c in cents]).reshape(-1, 2)


@pytest.mark.parametrize("noise", [False, True], ids=["noiseless", "noisy"])
def test_balanced_run_balls_at_the_same_pixels_in_every_frame(runup, noise):
    kw = {} if noise else NOISELESS
    strobe = Stroboscope(flash_angle=math.radians(30.0), **kw)
    frames = list(render_strobe_frames(runup, strobe, 37.0, 40.0))
    assert len(frames) == 45
    f0 = frames[0]
    assert f0.image.dtype == np.uint8 and f0.image.shape == (strobe.height, strobe.width)
    track = runup.scene.balancer.radius[0]
    blur_px = strobe.blur * track / strobe.pixel_pitch  # angular blur at the track, px
    full = 255
    found = []
    for f in frames:
        c = _ball_centroids(f.image, full, LEVEL_INTERIOR, LEVEL_BALL)
        assert c.shape == (2, 2)
        # each blob at a true ball position, within the angular blur
        truth = f.weight_px[0]
        d = np.linalg.norm(c[:, None, :] - truth[None, :, :], axis=-1)
        assert np.max(np.min(d, axis=1)) <= blur_px
        found.append(c[np.argsort(c[:, 0])])
    found = np.array(found)
    # the same pixel positions in every frame
    assert np.max(np.ptp(found, axis=0)) <= blur_px
    # the truth of every frame: weights at the flash, identical relative angles
    rel = np.array([f.relative_angle[0] for f in frames])
    assert np.max(np.ptp(rel, axis=0)) < 1e-9


# ---------------------------------------------------------------- stuck balls
def test_stuck_balls_move_by_minus_2pi_1_minus_Omega_over_omega_per_flash(stuck_scene, stuck,
                                                                           stuck_reference):
    """Per-flash change -2 pi (1 - Omega_k/omega) to 1e-6 rad (last 20 % of the run).

    The reference: the same scene sampled at 360 Hz = 40 samples per rotor
    revolution (9 rev/s), with the flash angle chosen so that the flashes fall
    on samples: its angles need no interpolation and Omega_k (the balls'
    mean speed over revolution k) is the Simpson integral of the sampled ball
    speed over the revolution.  The stroboscope itself works on 200 Hz
    samples (22 per revolution, interpolated)."""
    w1 = stuck_scene.natural_frequency
    omega = 3.0 * w1                     # R_omega = 3: 9 rev/s
    assert omega / TWO_PI == pytest.approx(9.0, rel=1e-12)
    ref = stuck_reference
    k0 = int(round(42.5 * 360))           # a reference sample in the last 20 %
    strobe = Stroboscope(flash_angle=float(np.mod(ref.rotor_angle[k0], TWO_PI)))
    t0, t1 = _last(stuck, 0.2)
    assert t0 < 42.5 - 1e-6
    r = strobe_angles(stuck, strobe, 42.5 - 1e-6, t1)
    K = r.t.size
    assert K >= 90
    # flashes on the reference grid: every 40 samples from k0
    idx = k0 + 40 * np.arange(K)
    assert np.max(np.abs(r.t - ref.t[idx])) < 1e-9
    # the interpolated strobe angles equal the directly sampled ones
    assert np.max(np.abs(wrap(r.relative_angle - ref.relative_angle[idx]))) < 1e-6
    # the balls are stuck together (one image)
    assert np.max(np.abs(wrap(r.relative_angle[:, 0] - r.relative_angle[:, 1]))) < 1e-6
    # per flash change against -2 pi (1 - Omega_k / omega)
    h = 1.0 / 360.0
    sw = np.array([1.0] + [4.0, 2.0] * 19 + [4.0, 1.0]) * h / 3.0     # Simpson, 40 intervals
    Omega_k = np.array([[sw @ ref.weight_speed[i:i + 41, j] for j in range(2)]
                        for i in idx[:-1]]) / (1.0 / 9.0)
    delta = wrap(np.diff(r.relative_angle, axis=0))
    expected = wrap(-TWO_PI * (1.0 - Omega_k / omega))
    assert np.max(np.abs(wrap(delta - expected))) < 1e-6
    # on average: the simulated mean ball speed Omega
    Omega = float(np.mean(Omega_k))
    assert np.mean(delta) == pytest.approx(wrap(-TWO_PI * (1.0 - Omega / omega)), abs=1e-6)
    # which is the stable root Omega_1 of (5.181) (digest Table 5.1-B: 0.96135);
    # the simulated speed ripples at the nutation frequency, hence the tolerance
    Omega_theory = qp_roots(3.0, 0.01, 0.05, 0.05)[0]
    assert Omega / w1 == pytest.approx(Omega_theory, abs=5e-5)
    # the per-flash change itself varies (nutation-driven speed ripple): only its
    # mean equals the steady formula
    assert np.ptp(delta) > 1e-3


def test_stuck_strobe_at_the_files_sample_rate(stuck_scene, stuck_reference):
    """At the file's 100 Hz (11 samples per revolution) the interpolated strobe
    angles are still within the documented Hermite bound: the ball angle's
    ripple (~0.016 rad at 2.04 omega_1) gives ~1e-6 rad."""
    coarse = simulate(stuck_scene)
    ref = stuck_reference
    k0 = int(round(42.5 * 360))
    strobe = Stroboscope(flash_angle=float(np.mod(ref.rotor_angle[k0], TWO_PI)))
    r = strobe_angles(coarse, strobe, 42.5 - 1e-6, coarse.t[-1])
    idx = k0 + 40 * np.arange(r.t.size)
    err = np.max(np.abs(wrap(r.relative_angle - ref.relative_angle[idx])))
    assert 1e-8 < err < 2e-6


def test_multi_flash_exposure_shows_the_expected_number_of_images(stuck, runup):
    """Omega/omega = 0.3205 (stuck balls at R = 3): the images cycle through ~3
    positions (tripling); a 3-flash exposure shows 3 images, a 6-flash one 3
    merged pairs (the 13.8 deg drift per cycle is smaller than a ball), a
    1-flash one a single image (the two balls coincide); the balanced run shows
    the 2 balls in every exposure."""
    ball = 0.015  # m: drawn ball radius (larger than the steel ball, for a robust merge)
    t0, t1 = _last(stuck, 0.2)
    track = stuck.scene.balancer.radius[0]
    ratio = float(np.mean(stuck.weight_speed[stuck.t >= t0]) / np.mean(stuck.rotor_speed[stuck.t >= t0]))
    assert ratio == pytest.approx(0.3205, abs=1e-3)
    for K, expected in ((1, 1), (3, 3), (6, 3)):
        # slot_radius 0.15 m: the reference mark (0.80..0.97 of it) stays off the track
        strobe = Stroboscope(exposure_flashes=K, shaft_motion=False, ball_radius=ball,
                             slot_radius=0.15, flash_angle=1.0, **NOISELESS)
        blur = 2 * ball / track + strobe.blur     # angular size of one ball image
        assert multiplicity_for_ratio(ratio, K, blur) == expected
        cx, cy = (strobe.width - 1) / 2, (strobe.height - 1) / 2
        rr = np.hypot(*np.meshgrid(np.arange(strobe.width) - cx, np.arange(strobe.height) - cy))
        annulus = np.abs(rr * strobe.pixel_pitch - track) < 1.5 * ball
        lo = LEVEL_INTERIOR
        hi = LEVEL_INTERIOR + (LEVEL_BALL - LEVEL_INTERIOR) / K   # one image in one flash
        frames = list(render_strobe_frames(stuck, strobe, t0, t1, max_frames=6))
        assert len(frames) == 6
        for f in frames:
            assert f.t.size == K
            assert image_multiplicity(f.relative_angle, blur) == expected
            n_blobs = _ball_centroids(f.image, 255, lo, hi, annulus).shape[0]
            assert n_blobs == expected
    strobe = Stroboscope(exposure_flashes=3, **NOISELESS)
    for f in render_strobe_frames(runup, strobe, 38.0, 40.0, max_frames=3):
        assert image_multiplicity(f.relative_angle, strobe.blur) == 2
        hi = LEVEL_INTERIOR + (LEVEL_BALL - LEVEL_INTERIOR)  # the same place in every flash
        assert _ball_centroids(f.image, 255, LEVEL_INTERIOR, hi).shape[0] == 2


def test_multiplicity_doubling_tripling():
    blur = math.radians(20)
    assert multiplicity_for_ratio(0.5, 8, blur) == 2
    assert multiplicity_for_ratio(0.501, 8, blur) == 2
    assert multiplicity_for_ratio(1 / 3, 9, blur) == 3
    assert multiplicity_for_ratio(0.25, 12, blur) == 4
    assert multiplicity_for_ratio(1.0, 5, blur) == 1      # synchronous: one image
    assert image_multiplicity([], blur) == 0
    assert image_multiplicity([0.0, 2 * math.pi - 0.01], 0.05) == 1   # across 0
    assert image_multiplicity([0.0, 1.0, 2.0], 0.5) == 3


def test_pendulums_and_frame_truth(runup):
    """Pendulums are drawn as rod + bob; 12-bit frames are uint16."""
    b = runup.scene.balancer
    pend = dataclasses.replace(runup.scene, balancer=dataclasses.replace(b, type="pendulums"))
    traj = dataclasses.replace(runup, scene=pend)
    strobe = Stroboscope(bit_depth=12, **NOISELESS)
    f = next(render_strobe_frames(traj, strobe, 39.0, 40.0))
    assert f.image.dtype == np.uint16 and f.image.max() <= 4095
    # the rod: a bright pixel half-way between the centre and each bob
    for (c, r) in f.weight_px[0]:
        cx, cy = f.centre_px[0]
        mid = f.image[int(round((cy + r) / 2)), int(round((cx + c) / 2))] / 4095
        assert mid > 0.5
    assert default_ball_radius(0.045) == pytest.approx(0.01111, abs=1e-4)


# ---------------------------------------------------------------- bad settings
def _table(data):
    return Table(data, "instruments.stroboscope")


@pytest.mark.parametrize("data, key", [
    ({"slot_width": 0.0}, "slot_width"),
    ({"slot_width": -1e-3}, "slot_width"),
    ({"slot_radius": 0}, "slot_radius"),
    ({"slot_width": 1.0, "slot_radius": 0.1}, "slot_width"),      # wider than the perimeter
    ({"exposure_flashes": 0}, "exposure_flashes"),
    ({"exposure_flashes": 2.5}, "exposure_flashes"),
    ({"pixel_pitch": 0.0}, "pixel_pitch"),
    ({"width": 0}, "width"),
    ({"ball_radius": -0.01}, "ball_radius"),
    ({"bit_depth": 17}, "bit_depth"),
    ({"read_noise": 1.5}, "read_noise"),
    ({"shaft_motion": "yes"}, "shaft_motion"),
    ({"flash_angel": 3.0}, "flash_angel"),
])
def test_bad_settings_name_the_key(data, key):
    with pytest.raises(SceneError, match=rf"instruments\.stroboscope\.{key}"):
        Stroboscope.from_table(_table(data))


def test_slot_wider_than_perimeter_message():
    with pytest.raises(SceneError, match="perimeter"):
        Stroboscope(slot_width=0.7, slot_radius=0.1)


def test_from_table_units():
    s = Stroboscope.from_table(_table({"flash_angle": 90.0, "slot_width": 0.001,
                                       "exposure_flashes": 3, "shaft_motion": False}))
    assert s.flash_angle == pytest.approx(math.pi / 2)
    assert (s.slot_width, s.exposure_flashes, s.shaft_motion) == (0.001, 3, False)


def test_scene_file_with_stroboscope_table():
    text = (SCENES / "ball_runup.toml").read_text()
    good = load_scene(text + "\n[instruments.stroboscope]\nflash_angle = 45.0\n")
    assert good.instruments["stroboscope"].flash_angle == pytest.approx(math.pi / 4)
    with pytest.raises(SceneError, match=r"instruments\.stroboscope\.slot_width = -0\.002"):
        load_scene(text + "\n[instruments.stroboscope]\nslot_width = -0.002\n")


def test_exposure_over_flashes_with_no_rotation(runup):
    sc = runup.scene
    still = dataclasses.replace(sc, drive=SpeedDrive(programme=np.array([[0.0, 0.0]])),
                                run=dataclasses.replace(sc.run, duration=1.0))
    traj = simulate(still)
    with pytest.raises(SceneError, match="exposure over flashes with no rotation"):
        render_strobe_frames(traj, Stroboscope(exposure_flashes=3), None, None)
    # one flash per frame: no flash, no frame (the slot never passes the lamp)
    assert list(render_strobe_frames(traj, Stroboscope())) == []
    assert flash_times(traj, Stroboscope()).size == 0


def test_weights_outside_the_image(runup):
    with pytest.raises(SceneError, match=r"instruments\.stroboscope\.pixel_pitch"):
        render_strobe_frames(runup, Stroboscope(pixel_pitch=1e-4), 39.0, 40.0)
