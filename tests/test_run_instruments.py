"""A run's instrument frames and readings in memory (issue 29, item 5): ``run.instruments``.

Frames are rendered on demand and equal the recording's; nothing is written until
``stand.save``; the readings count what the run's duration says they must.
"""
import math
from pathlib import Path

import h5py
import numpy as np
import pytest

import stand

SCENES = Path(__file__).resolve().parents[1] / "data_samples" / "scenes"


@pytest.fixture(scope="module")
def nf_run():
    """natural_frequency.toml: screen (240 x 240 px, 20 frames/s) and photo-gate, 1.5 s."""
    return stand.run(stand.load(SCENES / "natural_frequency.toml"))


@pytest.fixture(scope="module")
def cameras_run():
    """stand_cameras.toml: screen, stroboscope, keyphasor, tachometer; 25 s, 0 -> 12 rev/s."""
    return stand.run(stand.load(SCENES / "stand_cameras.toml"))


def _centroid(img) -> np.ndarray:
    """Spot centre (column, row) [px]: intensity above the background, weighted."""
    a = img.astype(float)
    w = np.clip(a - np.median(a), 0, None)
    w[w < 0.2 * w.max()] = 0.0
    rows, cols = np.indices(a.shape)
    return np.array([(w * cols).sum(), (w * rows).sum()]) / w.sum()


def test_nothing_is_written_until_write(tmp_path, monkeypatch):
    """Running, rendering frames and tabulating readings open no file."""
    monkeypatch.chdir(tmp_path)

    def no_file(*a, **k):
        raise AssertionError("an HDF5 file was opened before stand.save")

    monkeypatch.setattr(h5py, "File", no_file)
    run = stand.run(stand.load(SCENES / "natural_frequency.toml"))
    assert list(run.instruments) == ["screen", "photogate"]
    assert run.instruments["screen"].frame(3).shape == (240, 240)
    assert len(run.instruments["photogate"].to_frame()) > 0
    assert list(tmp_path.iterdir()) == []


def test_screen_frames_in_memory_are_the_recorded_frames(nf_run, tmp_path):
    screen = nf_run.instruments["screen"]
    cam = screen.settings
    # 1.5 s at 20 frames/s, the first exposure at t = 0
    assert screen.n_frames == math.floor(nf_run.scene.run.duration * cam.frame_rate) == 30
    np.testing.assert_allclose(screen.times, np.arange(30) / 20.0, atol=1e-12)
    out = stand.save(nf_run, tmp_path / "nf.h5")
    with h5py.File(out) as f:
        frames = f["instruments/screen/frames"]
        assert frames.shape == (screen.n_frames, cam.height, cam.width) == (30, 240, 240)
        np.testing.assert_array_equal(f["instruments/screen/frame_time"][:], screen.times)
        recorded_centre = f["truth/screen/centre_px"][:]
        for i in (0, 7, 29, -1):
            img = screen.frame(i)
            assert img.shape == (240, 240) and img.dtype == frames.dtype == np.uint8
            np.testing.assert_array_equal(img, frames[i])
    np.testing.assert_array_equal(screen.truth["centre_px"], recorded_centre)
    # the spot seen in each in-memory frame sits where the recording says, within a pixel
    # (measured: at most 0.08 px; the spot sweeps 36 .. 219 px along the gate's axis)
    found = np.array([_centroid(screen.frame(i)) for i in range(screen.n_frames)])
    assert np.ptp(recorded_centre[:, 0]) > 150
    assert np.max(np.abs(found - recorded_centre)) < 1.0
    with pytest.raises(IndexError, match="frame 30 of 30"):
        screen.frame(30)


def test_screen_table(nf_run):
    df = nf_run.instruments["screen"].to_frame()
    assert list(df.columns) == ["time_s", "rotor_angle_rad", "centre_u_px", "centre_v_px",
                                "centre_x_m", "centre_y_m", "in_frame"]
    assert len(df) == 30 and df["in_frame"].all()


def test_photogate_period_and_passes(nf_run, tmp_path):
    """The counter's period equals the damped period (0.1 %); three events per pass."""
    sc = nf_run.scene
    c, d, m = sc.supports.stiffness_x, sc.supports.damping_x, sc.total_mass
    zeta = d / (2 * math.sqrt(c * m))
    T = 2 * math.pi / (math.sqrt(c / m) * math.sqrt(1 - zeta ** 2))
    gate = nf_run.instruments["photogate"]
    assert gate.attrs["period_s"] == pytest.approx(T, rel=1e-3)
    assert gate.n_frames == 0
    with pytest.raises(IndexError, match="readings, not frames"):
        gate.frame(0)
    # the spot passes the gate twice per period (out and back): 2 * 1.5 s / T passes, +-1
    assert abs(len(gate.times) - 2 * sc.run.duration / T) <= 1
    df = gate.to_frame()
    assert set(df["event"]) == {"enter", "centre", "leave"} and df["time_s"].is_monotonic_increasing
    with h5py.File(stand.save(nf_run, tmp_path / "g.h5")) as f:
        assert f["instruments/photogate"].attrs["period_s"] == gate.attrs["period_s"]
        np.testing.assert_array_equal(f["instruments/photogate/enter_time"][:],
                                      gate.readings["enter_time"])


def test_stroboscope_frames_and_flashes(cameras_run, tmp_path):
    strobe = cameras_run.instruments["stroboscope"]
    assert strobe.readings["flash_time"].shape[1] == strobe.settings.exposure_flashes
    n = strobe.n_frames
    assert strobe.readings["flash_time"].shape[0] == n
    assert 0 < n <= 200
    out = stand.save(cameras_run, tmp_path / "cams.h5")
    with h5py.File(out) as f:
        frames = f["instruments/stroboscope/frames"]
        assert frames.shape[0] == n
        assert strobe.frame(0).shape == frames.shape[1:] == (strobe.settings.height,
                                                            strobe.settings.width)
        for i in (0, n // 2, -1):
            np.testing.assert_array_equal(strobe.frame(i), frames[i])
        np.testing.assert_array_equal(f["instruments/stroboscope/flash_time"][:],
                                      strobe.readings["flash_time"])
        rel = f["truth/stroboscope/relative_angle"][:]
    df = strobe.to_frame()
    assert len(df) == n and list(df.columns) == ["time_s", "rotor_angle_rad",
                                                 "relative_angle1_rad", "relative_angle2_rad"]
    np.testing.assert_array_equal(df["relative_angle1_rad"], rel[:, 0, 0])
    # balanced at the end: the balls at +-120 deg from the mark (e0 = 0.5), as the recording says
    np.testing.assert_allclose(np.sort(np.abs(np.degrees(rel[-1, 0]))), [120.0, 120.0], atol=0.05)


def test_readings_count_what_the_duration_says(cameras_run):
    T = cameras_run.scene.run.duration
    kp = cameras_run.instruments["keyphasor"]
    revolutions = (cameras_run.rotor_angle[-1] - cameras_run.rotor_angle[0]) / (2 * math.pi)
    assert abs(len(kp.times) - revolutions) <= 1 and len(kp.times) == 300
    assert np.all(np.diff(kp.times) > 0) and 0 < kp.times[0] and kp.times[-1] <= T
    tach = cameras_run.instruments["tachometer"]
    gate = tach.settings.gate_time
    # one reading per gate time after the first full gate: floor((T - gate) / gate) + 1
    assert len(tach.times) == math.floor((T - gate) / gate + 1e-9) + 1 == 25
    df = tach.to_frame()
    assert list(df.columns) == ["time_s", "speed_rad_s", "counts_1", "true_speed_rad_s",
                                "true_speed_at_time_rad_s"]
    # each displayed speed is the gate's mean speed to one count's resolution
    assert np.max(np.abs(df["speed_rad_s"] - df["true_speed_rad_s"])) <= tach.settings.resolution


def test_probe_readings():
    run = stand.run(stand.load(SCENES / "daq_runup.toml"))
    probes = run.instruments["probes"]
    T, rate = run.scene.run.duration, probes.settings.sample_rate
    assert len(probes.times) == math.floor(T * rate + 1e-9) + 1 == 30001
    df = probes.to_frame()
    p = len(probes.settings.angles)
    assert p == 2 and len(df) == len(probes.times)
    assert [c for c in df.columns if c.startswith("signal")] == ["signal1_m", "signal2_m"]
    # the probe along x reads the shaft's x (plus runout, noise, quantisation: < 10 um here)
    x = np.interp(probes.times, run.t, run.x)
    assert np.max(np.abs(df["displacement1_m"] - x)) < 1e-6 * np.max(np.abs(x)) + 1e-9


def test_a_run_without_instruments_has_none():
    run = stand.run(stand.load(SCENES / "ball_runup.toml"))
    assert len(run.instruments) == 0 and dict(run.instruments) == {}
