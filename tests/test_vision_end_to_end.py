"""End to end: scene with a screen camera -> rendered frames -> vision track -> dsp.

The identification sees only the frames (and the per-frame rotor angle the
keyphasor gives); the truth is the scene.  Acceptance of the vision issue:
unbalance within 2 %, stuck-ball precession and nutation within 0.1 %.
"""
import dataclasses
import math
from pathlib import Path

import h5py
import numpy as np
import pytest

from dsp.quasiperiodic import decompose
from dsp.unbalance import synchronous_component, unbalance_from_response
from stand.instruments.pipeline import run_with_instruments
from stand.instruments.screen import ScreenCamera, pixels_to_screen
from stand.recording.hdf5 import write_recording
from stand.scene.model import SpeedDrive
from stand.scene.parse import load_scene
from stand.theories.planar.qp import qp_roots
from vision.io import iter_frames
from vision.spot import track

from _helpers import toml_text

SCENES = Path(__file__).resolve().parents[1] / "data_samples" / "scenes"


def _film(scene, cam, path):
    scene = dataclasses.replace(scene, instruments={"screen": cam})
    write_recording(run_with_instruments(scene), path)
    df = track(iter_frames(str(path)))
    with h5py.File(path) as f:
        t = f["instruments/screen/frame_time"][:] + 0.5 * cam.exposure
        phi = f["instruments/screen/frame_rotor_angle"][:]
    ok = df["ok"].to_numpy(bool)
    X, Y = pixels_to_screen(df["u_px"].to_numpy(), df["v_px"].to_numpy(), cam)
    return t[ok], np.asarray(X)[ok] / cam.gain, np.asarray(Y)[ok] / cam.gain, phi[ok], ok


def test_unbalance_from_filmed_spot_within_2_percent(tmp_path):
    base = load_scene(SCENES / "no_balancer.toml")
    w = 2 * math.pi * 15.0
    # filmed from 8 s (transient gone) to 11 s: 360 frames; the estimate is off by 8e-5 over
    # these 3 s as over 6 s (a systematic, not a noise-limited error): 2 % is >100 x it
    run = dataclasses.replace(base.run, duration=11.0, sample_rate=2000.0)
    sc = dataclasses.replace(base, drive=SpeedDrive(np.array([[0.0, w]])), run=run)
    cam = ScreenCamera(pixel_pitch=2e-4, width=320, height=320, gain=1.5, frame_rate=120.0,
                       exposure=2e-4, subsamples=1, spot_diameter=1.6e-3, start_time=8.0, seed=5)
    t, x, y, phi, ok = _film(sc, cam, tmp_path / "nb.h5")
    assert ok.mean() > 0.99
    phi = phi + w * cam.exposure / 2  # angle at mid-exposure
    s1 = synchronous_component(t, x, y, rotor_angle=phi)
    Ms = sc.total_mass
    zeta = sc.supports.damping_x / (2 * math.sqrt(sc.supports.stiffness_x * Ms))
    est = unbalance_from_response(s1, s1.speed_rad_s, Ms, sc.natural_frequency / (2 * math.pi), zeta)
    assert est.unbalance_gmm == pytest.approx(sc.rotor.unbalance * 1e6, rel=0.02)


def test_stuck_balls_frequencies_from_filmed_spot_within_0_1_percent(tmp_path):
    base = load_scene(SCENES / "ball_stuck.toml")
    # filmed from 30 s (stuck-ball motion established) to 40 s: 600 frames.  The frequency
    # estimates' spread scales as T^-1.5 N^-0.5; over these 10 s the nutation is found to
    # 4.9e-7 (5.0e-7 over 15 s, 1.4e-7 over 35 s) and the precession to 7.9e-6 (8e-6 either
    # way: the same offset from the linear root): the 0.1 % acceptance is still >100 x their error
    run = dataclasses.replace(base.run, duration=40.0, sample_rate=200.0)
    sc = dataclasses.replace(base, run=run)
    cam = ScreenCamera(pixel_pitch=1.5e-4, width=320, height=320, gain=1.0, frame_rate=60.0,
                       exposure=2e-4, subsamples=1, spot_diameter=1.2e-3, start_time=30.0, seed=6)
    t, x, y, phi, ok = _film(sc, cam, tmp_path / "st.h5")
    assert ok.mean() > 0.99
    f1 = sc.natural_frequency / (2 * math.pi)
    R = 3.0
    dec = decompose(t, x + 1j * y, rotor_speed_hz=R * f1)
    Omega = qp_roots(R, 0.01, 0.05, 0.05)[0]  # 0.96135, Table 5.1-B
    assert dec.nutation_hz == pytest.approx(R * f1, rel=1e-3)
    assert dec.precession_hz == pytest.approx(Omega * f1, rel=1e-3)


def locked_stand(ecc: float) -> str:
    """stand_cameras.toml with the balancer locked (the calibration condition of the
    rings): no moving weights, their mass in the rotor, the same unbalance 0.5 S."""
    return toml_text(
        rotor=dict(mass=4.54, eccentricity=ecc), supports=dict(stiffness=1613.09, damping=8.5577),
        drive=dict(type="speed", programme=[[0.0, 15.0], [1.0, 15.0]]),
        run=dict(duration=11.0, sample_rate=200.0),
        instruments__screen=dict(gain=6.0, pixel_pitch=1.0e-4, width=320, height=320, frame_rate=2.0,
                                 exposure=0.2, start_time=8.0, spot_diameter=0.8e-3, peak=4000.0,
                                 background=8.0, read_noise=1.0, bit_depth=8, seed=3))


def test_stand_track_trace_reads_the_unbalance_through_the_rings(tmp_path):
    """stand run -> long-exposure frames (3 revolutions each) -> `stand track --trace`
    with the sample ring image -> unbalance within 2 % of the truth (0.5 S)."""
    from stand.cli.main import main

    root = SCENES.parents[1]
    S_gmm = 2 * 0.045 * 0.08 * 1e6          # stand_cameras.toml: two 45 g balls at 80 mm
    U_true_gmm = 4.45 * 8.0899e-4 * 1e6     # its rotor unbalance (0.5 S)
    scene = tmp_path / "locked.toml"
    scene.write_text(locked_stand(U_true_gmm * 1e-6 / 4.54))
    rec = tmp_path / "locked.h5"
    assert main(["run", str(scene), "-o", str(rec)]) == 0
    with h5py.File(root / "data_samples" / "recordings" / "stand_cameras.h5") as f:
        radii = f["instruments/screen/ring_radius"][:]
    out = tmp_path / "trace.csv"
    assert main(["track", str(rec), "--trace", "--calibration",
                 str(root / "data_samples" / "images" / "calibration_rings.png"),
                 "--ring-radii", ",".join(repr(float(r)) for r in radii),
                 "--capacity", repr(S_gmm), "-o", str(out)]) == 0
    import pandas as pd

    df = pd.read_csv(out, comment="#")
    assert len(df) == 6 and df["ok"].all()
    # 0.5 S is exactly ring 8 of 16: a person reads zone 7 or 8 (the circle sits on the ring)
    assert df["zone"].isin([7, 8]).all()
    np.testing.assert_allclose(df["unbalance_gmm"], U_true_gmm, rtol=0.02)
    # the circle's centre is the screen origin (beam centred), within 0.05 mm
    np.testing.assert_allclose(df[["x_mm", "y_mm"]].to_numpy(), 0.0, atol=0.05)
    # `stand analyze` of the trace CSV reads the same unbalance from the circles' mean radius
    # against the rings (it needs no speed): within 2 % of the truth, the interpolated reading
    # of the frames' mean within its ± of the frames' own readings' mean (the same rings)
    import stand

    a = stand.analyze(str(out)).to_dict()
    np.testing.assert_allclose(a["unbalance_gmm"], U_true_gmm, rtol=0.02)
    assert a["ring_reading"]["circles"] == 6 and a["ring_reading"]["zone"] in (7, 8)
    assert abs(a["unbalance_gmm"] - df["unbalance_gmm"].mean()) <= a["unbalance_gmm_std"]
    assert 0 < a["unbalance_gmm_std"] < 0.01 * U_true_gmm
