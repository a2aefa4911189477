"""Laser-spot screen camera: geometry, rendering, calibration rings, settings.

Acceptance (issue 4): the intensity centroid of noiseless frames equals the true
exposure-averaged spot centre within 0.02 px; ring radii match the calibration
run; a long exposure of a steady whirl shows a ring of the true radius (1 %);
the QP example's long exposure shows (k - 1) petals; bad settings give errors
naming the key.
"""
import dataclasses
import math
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest
from scipy.signal import find_peaks

from stand.instruments.render import (background_table, frame_seed, render_frames,
                                      render_long_exposure)
from stand.instruments.rings import (check_spot_size, render_ring_image, ring_radii,
                                     ring_radii_by_simulation, zone_of)
from stand.instruments.screen import (ScreenCamera, exposure_times, frame_times, frame_truth,
                                      pixels_to_screen, screen_to_pixels, spot_on_screen,
                                      spot_positions)
from stand.scene.model import RunSettings, SceneError
from stand.scene.parse import Table, load_scene
from stand.integrate.simulate import simulate
from stand.theories.planar.qp import epitrochoid, spot_law

ROOT = Path(__file__).resolve().parents[1]
SCENES = ROOT / "data_samples" / "scenes"
TWO_PI = 2.0 * math.pi


def centroid(img, background):
    """Intensity centroid (u, v) [px] of a frame, background subtracted (numpy only)."""
    a = img.astype(float) - background
    v, u = np.mgrid[0:img.shape[0], 0:img.shape[1]]
    return np.array([(a * u).sum() / a.sum(), (a * v).sum() / a.sum()])


# ---------------------------------------------------------------- (a) centroid
@pytest.mark.parametrize("tilt", [0.0, 0.2, -0.3])
def test_noiseless_centroid_is_the_true_exposure_averaged_centre(tilt):
    cam = ScreenCamera(pixel_pitch=1e-4, spot_diameter=2e-3, tilt=tilt, bit_depth=12,
                       subsamples=16, misalignment=3e-4, misalignment_phase=0.4,
                       offset_x=1.3e-3, offset_y=-0.7e-3)          # spot 20 px
    assert cam.sigma_px[0] == pytest.approx(5.0)
    t = exposure_times([0.0], cam)                                   # (1, 16)
    w = TWO_PI * 15.0
    for k, (x0, y0, r) in enumerate([(0.0, 0.0, 0.0), (2.03e-3, -1.377e-3, 0.0),
                                     (-4.1e-3, 5.55e-3, 1e-3), (7.7e-3, 3.3e-3, 2.5e-3)]):
        # a still spot at sub-pixel positions and a blurred one on a whirl arc
        x = x0 + r * np.cos(w * t)
        y = y0 + r * np.sin(w * t)
        screen_m, px = spot_positions(x, y, w * t, cam)
        truth = frame_truth(screen_m, px, cam)
        assert truth["in_frame"].all()
        img = next(render_frames(px, cam, noise=False))
        err = centroid(img, round(cam.background)) - truth["centre_px"][0]
        assert np.all(np.abs(err) < 0.02), (k, err)


def test_still_spot_reads_peak_and_stays_symmetric():
    cam = ScreenCamera(pixel_pitch=1e-4, spot_diameter=3e-3, bit_depth=12, peak=3000.0,
                       background=100.0)
    img = render_long_exposure(np.array([[100.0, 80.0]]), cam, noise=False).astype(int)
    # pixel-integrated Gaussian of sigma 7.5 px: centre pixel within 0.2 % of the peak
    assert img[80, 100] == pytest.approx(3100, abs=8)
    assert np.array_equal(img[60:101, 100], img[60:101, 100][::-1])
    assert np.array_equal(img[80, 80:121], img[80, 80:121][::-1])
    assert img[0, 0] == 100


# ---------------------------------------------------------------- geometry
def test_homography_round_trip_and_conventions():
    cam = ScreenCamera(pixel_pitch=2e-4, tilt=0.3, width=640, height=480)
    X = np.array([0.0, 0.01, -0.02, 0.005])
    Y = np.array([0.0, 0.02, -0.01, -0.03])
    u, v = screen_to_pixels(X, Y, cam)
    assert (u[0], v[0]) == pytest.approx((319.5, 239.5))             # image centre
    Xb, Yb = pixels_to_screen(u, v, cam)
    np.testing.assert_allclose(Xb, X, atol=1e-15)
    np.testing.assert_allclose(Yb, Y, atol=1e-15)
    # pitch along u at the centre; +Y is up in the image; +Y side farther (smaller)
    du, _ = screen_to_pixels(1e-6, 0.0, cam)
    assert (du - 319.5) * 2e-4 == pytest.approx(1e-6, rel=1e-5)
    _, vu = screen_to_pixels(0.0, 1e-3, cam)
    _, vd = screen_to_pixels(0.0, -1e-3, cam)
    assert vu < 239.5 < vd and (239.5 - vu) < (vd - 239.5)
    flat = dataclasses.replace(cam, tilt=0.0)
    assert screen_to_pixels(0.01, 0.02, flat) == pytest.approx((319.5 + 50, 239.5 - 100))


def test_spot_on_screen_gain_misalignment_offset_and_tilting_axis():
    cam = ScreenCamera(pixel_pitch=1e-4, gain=20.0, misalignment=1e-3,
                       misalignment_phase=0.5, offset_x=2e-3, offset_y=-1e-3)
    phi = np.linspace(0, 2 * TWO_PI, 9)
    X, Y = spot_on_screen(1e-4, -2e-4, phi, cam)
    np.testing.assert_allclose(X, 20 * 1e-4 + 1e-3 * np.cos(phi + 0.5) + 2e-3)
    np.testing.assert_allclose(Y, -20 * 2e-4 + 1e-3 * np.sin(phi + 0.5) - 1e-3)
    X2, Y2 = spot_on_screen(1e-4, -2e-4, phi, cam, tilt_x=0.01, tilt_y=-0.02,
                            screen_distance=0.5)
    np.testing.assert_allclose(X2 - X, 0.5 * math.tan(0.01))
    np.testing.assert_allclose(Y2 - Y, 0.5 * math.tan(-0.02))
    with pytest.raises(ValueError, match="together"):
        spot_on_screen(0, 0, 0, cam, tilt_x=0.1)


def test_frame_and_exposure_times():
    cam = ScreenCamera(pixel_pitch=1e-4, frame_rate=25.0, exposure=0.01, start_time=0.5,
                       subsamples=4)
    starts = frame_times(1.0, cam)
    np.testing.assert_allclose(starts, 0.5 + np.arange(13) / 25.0)   # last ends at 0.99
    t = exposure_times(starts, cam)
    assert t.shape == (13, 4)
    np.testing.assert_allclose(t[0], 0.5 + np.array([0.125, 0.375, 0.625, 0.875]) * 0.01)
    assert np.all(np.diff(t.ravel()) > 0) and t.max() < 1.0
    auto = dataclasses.replace(cam, subsamples=None)
    assert exposure_times(starts, auto).shape[1] == 16
    # automatic: at most one sigma between positions on an image-sized curve
    k = auto.subsamples_for(TWO_PI * 15)
    step = 0.01 * TWO_PI * 15 * 0.5 * math.hypot(640, 480) / k
    assert step <= min(auto.sigma_px) and k > 16
    assert frame_times(0.505, cam).size == 0


# ---------------------------------------------------------------- (b) rings
def test_ring_radii_match_the_calibration_run():
    scene = load_scene(SCENES / "ball_runup.toml")
    cam = ScreenCamera(pixel_pitch=1e-4, gain=30.0)
    speed = TWO_PI * 15.0                                            # the test speed
    closed = ring_radii(scene, speed, cam=cam)
    assert closed.shape == (21,) and closed[0] == 0.0
    run = ring_radii_by_simulation(scene, speed, cam=cam)           # run length from damping
    assert run[0] == 0.0
    np.testing.assert_allclose(run[1:], closed[1:], rtol=1e-6)
    # zone 20 = 1.25 S; formula of the steady whirl of the rotor with the weights locked
    S, Ms, w1 = scene.balancer.capacity, scene.total_mass, scene.natural_frequency
    R = speed / w1
    H = scene.supports.damping_x / (w1 * Ms)
    r20 = 30.0 * (1.25 * S / Ms) * R ** 2 / math.sqrt((1 - R ** 2) ** 2 + (H * R) ** 2)
    assert closed[20] == pytest.approx(r20, rel=1e-12)
    np.testing.assert_allclose(np.diff(closed), closed[1])          # linear in the unbalance
    # default speed: the programme's last speed
    np.testing.assert_allclose(ring_radii(scene, cam=cam), closed, rtol=1e-12)


def test_zones_and_calibration_image():
    scene = load_scene(SCENES / "ball_runup.toml")
    cam = ScreenCamera(pixel_pitch=2e-4, gain=100.0, spot_diameter=2e-3)
    radii = ring_radii(scene, TWO_PI * 15.0, cam=cam)              # r1 ~ 10 mm = 52 px
    assert list(zone_of([0.0, 0.5 * radii[1], radii[3] * 1.01, radii[20] * 2], radii)) == \
        [0, 0, 3, 20]
    check_spot_size(cam, radii)
    with pytest.raises(SceneError, match="spot_diameter"):
        check_spot_size(dataclasses.replace(cam, spot_diameter=2.5 * radii[1]), radii)
    img = render_ring_image(radii[:6], cam, labels=True)
    assert img.dtype == np.uint8 and img.shape == (480, 640)
    cu, cv = 319.5, 239.5
    for r in radii[1:6]:
        rp = r / cam.pixel_pitch
        # the ring crosses the row through the centre at cu - rp (left: no labels there)
        j = int(round(cu - rp))
        row = img[240, j - 3:j + 4]
        assert row.min() < 128 and row[0] == 255 and row[-1] == 255
    assert img[240, 319] == 255 and img[240, 320] == 255            # nothing at zone 0
    tilted = render_ring_image(radii[:6], dataclasses.replace(cam, tilt=0.3))
    assert not np.array_equal(tilted, render_ring_image(radii[:6], cam))


# ---------------------------------------------------------------- (c) steady whirl
def test_long_exposure_of_a_steady_whirl_shows_a_ring_of_the_true_radius():
    scene = load_scene(SCENES / "no_balancer.toml")                # holds 15 rev/s after 10 s
    w = TWO_PI * 15.0
    cam = ScreenCamera(pixel_pitch=4e-4, gain=50.0, spot_diameter=4e-3, frame_rate=10.0,
                       exposure=1.02 * TWO_PI / w, start_time=39.9, peak=20000.0)
    starts = frame_times(scene.run.duration, cam)
    assert starts.size == 1
    t = exposure_times(starts, cam, max_rotor_speed=w)
    traj = simulate(scene, extra_times=t.ravel()).extra
    X = traj.x.reshape(t.shape)
    Y = traj.y.reshape(t.shape)
    screen_m, px = spot_positions(X, Y, traj.rotor_angle.reshape(t.shape), cam)
    truth_r = np.mean(np.hypot(px[0, :, 0] - 319.5, px[0, :, 1] - 239.5))
    M = scene.rotor.mass
    R = w / scene.natural_frequency
    H = scene.supports.damping_x / (scene.natural_frequency * M)
    closed = scene.rotor.eccentricity * R ** 2 / math.sqrt((1 - R ** 2) ** 2 + (H * R) ** 2)
    assert truth_r == pytest.approx(closed * 50.0 / 4e-4, rel=1e-6)   # steady: ~105 px
    img = next(render_frames(px, cam))                               # with noise
    a = img.astype(float) - cam.background
    a[a < 10 * cam.read_noise] = 0.0                                   # the bright ridge only
    v, u = np.nonzero(a)
    wgt = a[v, u]
    # weighted algebraic (Kasa) circle fit
    A = np.stack([u, v, np.ones_like(u)], axis=1).astype(float) * np.sqrt(wgt)[:, None]
    b = -(u.astype(float) ** 2 + v.astype(float) ** 2) * np.sqrt(wgt)
    D, E, F = np.linalg.lstsq(A, b, rcond=None)[0]
    fitted = math.sqrt((D * D + E * E) / 4 - F)
    assert fitted == pytest.approx(truth_r, rel=0.01)
    assert (-D / 2, -E / 2) == pytest.approx((319.5, 239.5), abs=1.0)


# ---------------------------------------------------------------- (d) QP petals
def count_petals(img, background, centre):
    """Local maxima of the radial extent of the bright pixels vs polar angle."""
    a = img.astype(float) - background
    v, u = np.nonzero(a > 0.25 * a.max())
    theta = np.arctan2(-(v - centre[1]), u - centre[0])
    rho = np.hypot(u - centre[0], v - centre[1])
    bins = ((theta + math.pi) / TWO_PI * 360).astype(int) % 360
    extent = np.zeros(360)
    np.maximum.at(extent, bins, rho)
    extent = np.convolve(np.r_[extent[-3:], extent, extent[:3]], np.ones(7) / 7, "valid")
    span = extent.max() - extent.min()
    peaks, _ = find_peaks(np.r_[extent, extent, extent], prominence=0.2 * span)
    return int(np.sum((peaks >= 360) & (peaks < 720)))


@pytest.mark.parametrize("k, ratio", [(3, 0.25), (4, 0.15), (5, 0.35)])
def test_qp_long_exposure_shows_k_minus_1_petals(k, ratio):
    # digest section 5.3 example (n = 2, Rt = 0.01, h = H = 0.05, e0 = 0.3):
    # precession speed Omega of the stuck balls; rotor speed R = k Omega, k integer
    Omega = 0.96135
    law = spot_law(Omega, k * Omega, 0.3, 0.05)
    assert law.petals == k - 1
    w1 = TWO_PI * 3.0                                    # natural frequency 3 Hz
    A_P, A_N = 1.0, ratio                                # curtate for k = 3, 4; looped for 5
    assert (A_P * Omega > A_N * k * Omega) == (k < 5)
    period = TWO_PI / (Omega * w1)                       # the curve closes after one turn
    cam = ScreenCamera(pixel_pitch=5e-4, gain=1.0, spot_diameter=3e-3, frame_rate=0.5,
                       exposure=period, peak=30000.0, subsamples=4000)
    t = exposure_times([0.0], cam)[0]
    z = 0.055 * epitrochoid(A_P, A_N, Omega * w1, k * Omega * w1, t)   # m on the screen
    _, px = spot_positions(z.real, z.imag, k * Omega * w1 * t, cam)
    img = render_long_exposure(px, cam)
    assert count_petals(img, cam.background, (319.5, 239.5)) == k - 1


# ---------------------------------------------------------------- (e) settings
def table(**kw):
    return Table(kw, "instruments.screen")


@pytest.mark.parametrize("settings, words", [
    (dict(exposure=0.0), ["instruments.screen.exposure = 0", "> 0", "(s)"]),
    (dict(exposure=0.05, frame_rate=25.0), ["instruments.screen.exposure = 0.05",
                                            "frame period", "frame_rate = 25"]),
    (dict(spot_diameter=0.2), ["instruments.screen.spot_diameter = 0.2", "larger than the frame"]),
    (dict(pixel_pitch=None), ["instruments.screen.pixel_pitch", "missing"]),
    (dict(tilt=30.0), ["instruments.screen.tilt = 30.0", "deg"]),
    (dict(bit_depth=9), ["instruments.screen.bit_depth = 9", "8, 10, 12"]),
    (dict(shot_noise="yes"), ["instruments.screen.shot_noise", "true or false"]),
    (dict(subsamples=0), ["instruments.screen.subsamples = 0", ">= 1"]),
    (dict(frame_rat=25.0), ["unknown key instruments.screen.frame_rat", "frame_rate"]),
])
def test_bad_settings_name_the_key(settings, words):
    kw = {"pixel_pitch": 1e-4}
    kw.update(settings)
    kw = {k: v for k, v in kw.items() if v is not None}
    with pytest.raises(SceneError) as exc:
        ScreenCamera.from_table(table(**kw))
    for word in words:
        assert word in str(exc.value)


def test_frame_rate_above_sample_rate_is_refused():
    cam = ScreenCamera.from_table(table(pixel_pitch=1e-4, frame_rate=250.0, exposure=1e-3))
    cam.check_against_run(RunSettings(duration=1.0, sample_rate=250.0))
    with pytest.raises(SceneError, match=r"instruments\.screen\.frame_rate = 250.*run\.sample_rate = 200"):
        cam.check_against_run(RunSettings(duration=1.0, sample_rate=200.0))
    with pytest.raises(SceneError, match=r"instruments\.screen\.start_time"):
        dataclasses.replace(cam, start_time=2.0).check_against_run(
            RunSettings(duration=1.0, sample_rate=250.0))


def test_scene_file_with_a_screen_camera():
    text = (SCENES / "no_balancer.toml").read_text()
    good = text + textwrap.dedent("""
        [instruments.screen]
        pixel_pitch = 4e-4
        gain = 50.0
        tilt = 5.0                # deg
        misalignment_phase = 90.0 # deg
        frame_rate = 100.0
        exposure = 0.004
        bit_depth = 12
        shot_noise = false
        """)
    cam = load_scene(good).instruments["screen"]
    assert cam.tilt == pytest.approx(math.radians(5.0))
    assert cam.misalignment_phase == pytest.approx(math.pi / 2)
    assert cam.dtype == np.uint16 and cam.shot_noise is False and cam.exposure == 0.004
    assert cam.to_attrs()["subsamples"] == -1
    with pytest.raises(SceneError, match=r"instruments\.screen\.frame_rate = 400.*run\.sample_rate"):
        load_scene(good.replace("frame_rate = 100.0", "frame_rate = 400.0")
                   .replace("exposure = 0.004", "exposure = 0.002"))


# ---------------------------------------------------------------- (f) bit depth, noise
def test_12_bit_frames_are_uint16_and_saturate_at_4095():
    cam = ScreenCamera(pixel_pitch=1e-4, spot_diameter=2e-3, bit_depth=12, peak=10000.0)
    img = render_long_exposure(np.array([[320.0, 240.0]]), cam)
    assert img.dtype == np.uint16 and img.max() == 4095 and (img == 4095).sum() > 20
    assert 1000 < np.median(img[img < 4095]) or img[0:100, 0:100].mean() == pytest.approx(
        cam.background, abs=1)
    cam8 = ScreenCamera(pixel_pitch=1e-4, spot_diameter=2e-3, peak=1000.0)
    img8 = render_long_exposure(np.array([[320.0, 240.0]]), cam8)
    assert img8.dtype == np.uint8 and img8.max() == 255


def test_noise_statistics_background_and_spot():
    cam = ScreenCamera(pixel_pitch=1e-4, width=128, height=96, spot_diameter=3e-3,
                       bit_depth=12, peak=800.0, background=50.0, read_noise=3.0,
                       electrons_per_dn=2.0)
    frames = np.array(list(render_frames(np.full((400, 1, 2), [64.0, 48.0]), cam)), float)
    clean = render_long_exposure(np.array([[64.0, 48.0]]), cam, noise=False).astype(float)
    # background: Poisson(100 e-)/2 + read noise 3 DN: variance 25 + 9 (+ 1/12 rounding)
    bg = frames[:, :4, :].ravel()
    assert bg.mean() == pytest.approx(50.0, abs=0.1)
    assert bg.var() == pytest.approx(34.0 + 1 / 12, rel=0.05)
    # spot centre: signal 850 DN = 1700 e-: variance 425 + 9
    c = frames[:, 48, 64]
    assert c.mean() == pytest.approx(clean[48, 64], abs=3 * math.sqrt(434 / 400) + 0.5)
    assert c.var() == pytest.approx(434.0, rel=0.25)
    # exact background law: the table's mean and variance
    thr, guide, kmin = background_table(50.0, 3.0, True, 2.0, 4095)
    p = np.diff(np.r_[0, thr]) / 2.0 ** 32
    vals = kmin + np.arange(p.size)
    assert (p * vals).sum() == pytest.approx(50.0, abs=1e-6)
    assert (p * vals ** 2).sum() - 2500 == pytest.approx(34.0 + 1 / 12, rel=1e-3)


def test_frames_are_reproducible_per_index_and_streamed():
    cam = ScreenCamera(pixel_pitch=1e-4, width=80, height=60, seed=7)
    pos = np.random.default_rng(1).uniform(10, 50, (6, 3, 2))
    gen = render_frames(pos, cam)
    assert iter(gen) is gen                                          # a generator
    frames = list(gen)
    assert all(f.shape == (60, 80) and f.dtype == np.uint8 for f in frames)
    again = list(render_frames(pos[3:], cam, first_index=3))
    for a, b in zip(frames[3:], again):
        assert np.array_equal(a, b)
    assert not np.array_equal(frames[0], frames[1])
    other = next(render_frames(pos[:1], cam, seed=8))
    assert not np.array_equal(frames[0], other)
    assert frame_seed(7, 0) != frame_seed(7, 1)


# ---------------------------------------------------------------- (g) plain Python
def test_plain_python_kernel_gives_the_same_frames():
    code = textwrap.dedent("""
        import numpy as np, sys
        from stand.instruments.screen import ScreenCamera
        from stand.instruments.render import render_frames
        from stand import _jit
        cam = ScreenCamera(pixel_pitch=1e-4, width=40, height=30, spot_diameter=1e-3,
                           read_noise=2.0, electrons_per_dn=0.5)
        pos = np.array([[[20.3, 14.6], [21.0, 15.1], [22.2, 15.9]]])
        a = next(render_frames(pos, cam))
        b = next(render_frames(pos, cam, noise=False))
        np.save(sys.argv[1], np.stack([a, b]))
        print(_jit.HAVE_NUMBA)
        """)
    out = {}
    import tempfile
    with tempfile.TemporaryDirectory() as tmp:
        for flag in ("0", "1"):
            path = os.path.join(tmp, f"f{flag}.npy")
            env = dict(os.environ, STAND_DISABLE_JIT=flag)
            res = subprocess.run([sys.executable, "-c", code, path], env=env, cwd=ROOT,
                                 capture_output=True, text=True, timeout=120)
            assert res.returncode == 0, res.stderr
            assert res.stdout.strip() == ("False" if flag == "1" else "True")
            out[flag] = np.load(path)
    assert np.array_equal(out["0"][1], out["1"][1])                  # noiseless: identical
    differ = np.count_nonzero(out["0"][0] != out["1"][0])
    assert differ <= 2 and np.abs(out["0"][0].astype(int) - out["1"][0]).max() <= 1


def test_simulated_stuck_balls_long_exposure_shows_k_minus_1_petals():
    """The digest's QP example (ball_stuck.toml physics) simulated at the rotor speed where
    k = omega / Omega_1 = 3 exactly (root of (5.181)): a long exposure of one closing period
    2 pi / Omega of the simulated spot shows k - 1 = 2 petals."""
    from scipy.optimize import brentq

    from stand.scene.parse import load_scene
    from stand.integrate.simulate import simulate
    from stand.theories.planar.qp import qp_roots
    from _verify import at_speed

    base = load_scene(Path(__file__).resolve().parents[1] / "data_samples" / "scenes" / "ball_stuck.toml")
    R = brentq(lambda r: r / qp_roots(r, 0.01, 0.05, 0.05)[0] - 3.0, 2.5, 3.2, xtol=1e-13)
    Omega = qp_roots(R, 0.01, 0.05, 0.05)[0]
    sc = at_speed(base, R, hold_tau=900.0)
    w1 = sc.natural_frequency
    period = TWO_PI / (Omega * w1)
    cam = ScreenCamera(pixel_pitch=1.2e-4, gain=1.0, spot_diameter=1.5e-3, frame_rate=0.2,
                       exposure=period, peak=30000.0, subsamples=3000, read_noise=0.0)
    t = sc.run.duration - period + exposure_times([0.0], cam)[0]
    tr = simulate(sc, extra_times=t).extra
    assert abs(np.mean(tr.weight_speed[:, 0]) / w1 / Omega - 1) < 1e-3  # stuck at Omega_1
    c = np.mean(tr.x + 1j * tr.y)
    _, px = spot_positions(tr.x - c.real, tr.y - c.imag, tr.rotor_angle, cam)
    img = render_long_exposure(px, cam)
    assert count_petals(img, cam.background, (319.5, 239.5)) == 2
