"""Instruments wired into stand run: only what the scene asks for, truth beside the output."""
import math
from pathlib import Path

import h5py
import numpy as np
import pytest

from stand.cli.main import main
from stand.instruments.pipeline import run_with_instruments
from stand.scene.parse import load_scene
from stand.scene.model import SceneError

SCENES = Path(__file__).resolve().parents[1] / "data_samples" / "scenes"


def test_no_instruments_nothing_rendered(tmp_path):
    traj = run_with_instruments(load_scene(SCENES / "ball_runup.toml"))
    assert not traj.instruments and traj.extra is None
    out = tmp_path / "r.h5"
    assert main(["run", str(SCENES / "no_balancer.toml"), "-o", str(out)]) == 0
    with h5py.File(out) as f:
        assert "instruments" not in f and "truth" not in f


def test_natural_frequency_scene_photogate_period(tmp_path):
    """The photo-gate's 1st-to-3rd-pass period equals the damped period (0.1 %)."""
    out = tmp_path / "nf.h5"
    assert main(["run", str(SCENES / "natural_frequency.toml"), "-o", str(out)]) == 0
    sc = load_scene(SCENES / "natural_frequency.toml")
    c, d, m = sc.supports.stiffness_x, sc.supports.damping_x, sc.total_mass
    w1 = math.sqrt(c / m)
    zeta = d / (2 * math.sqrt(c * m))
    T = 2 * math.pi / (w1 * math.sqrt(1 - zeta**2))
    with h5py.File(out) as f:
        assert f["instruments/photogate"].attrs["period_s"] == pytest.approx(T, rel=1e-3)
        assert f["instruments/screen/frames"].shape[1:] == (240, 240)


def test_sample_recording_has_frames_truth_and_rings():
    path = Path(__file__).resolve().parents[1] / "data_samples" / "recordings" / "stand_cameras.h5"
    assert path.stat().st_size < 8e6  # "a few MB at most"
    with h5py.File(path) as f:
        frames = f["instruments/screen/frames"]
        assert frames.dtype == np.uint8 and frames.ndim == 3
        assert f["truth/screen/centre_px"].shape == (frames.shape[0], 2)
        assert f["instruments/screen/frame_time"].shape == (frames.shape[0],)
        radii = f["instruments/screen/ring_radius"][:]
        assert len(radii) == 21 and radii[0] == 0 and np.all(np.diff(radii) > 0)
        # equal zones: radius linear in the unbalance i S/16
        np.testing.assert_allclose(radii, radii[1] * np.arange(21), rtol=1e-12)
        assert f["instruments/stroboscope/frames"].shape[0] == f["truth/stroboscope/relative_angle"].shape[0]
        # balanced at the end: the strobe truth shows the balls at +-120 deg (e0 = 0.5)
        rel = np.degrees(f["truth/stroboscope/relative_angle"][-1, 0])
        np.testing.assert_allclose(np.sort(np.abs(rel)), [120.0, 120.0], atol=0.05)


def test_bad_instrument_settings_name_the_key():
    text = (SCENES / "stand_cameras.toml").read_text()
    with pytest.raises(SceneError, match=r"instruments\.screen\.exposure"):
        load_scene(text.replace("exposure = 0.2 ", "exposure = 0.0 "))
    with pytest.raises(SceneError, match=r"instruments\.screen\.frame_rate"):
        load_scene(text.replace("frame_rate = 2.0 ", "frame_rate = 5000.0 "))
    with pytest.raises(SceneError, match=r"instruments\.screen"):
        load_scene(text.replace("spot_diameter = 0.8e-3", "spot_diameter = 0.5"))
    with pytest.raises(SceneError, match=r"instruments\.scren"):
        load_scene(text.replace("[instruments.screen]", "[instruments.scren]"))
