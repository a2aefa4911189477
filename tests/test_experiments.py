"""Experiment programmes of tables 4.2-4.6 built from a base scene."""
import math
from pathlib import Path

import h5py
import numpy as np
import pytest

from stand.scene import experiments as ex
from stand.cli.main import main
from stand.analysis.regime import classify
from stand.scene.model import SceneError
from stand.scene.parse import load_scene
from stand.integrate.simulate import simulate

SCENES = Path(__file__).resolve().parents[1] / "data_samples" / "scenes"


@pytest.fixture(scope="module")
def stand():
    return load_scene(SCENES / "ball_runup.toml")


@pytest.mark.parametrize("band, ratio", [("sub", 0.7), ("near", 1.0), ("super", 1.5)])
def test_constant_speed_bands_of_table_4_2(stand, band, ratio):
    sc = ex.constant(stand, band=band, duration=20.0)
    f0 = stand.natural_frequency / (2 * math.pi)
    assert sc.drive.programme[-1, 1] == pytest.approx(2 * math.pi * ratio * f0)
    assert (ratio < 0.9) == (band == "sub") and (ratio > 1.1) == (band == "super")


def test_run_down_of_the_fixed_point_stand(stand):
    """1800 rpm to rest in 175 s, linearly: -0.171 rev/s^2 (digest ch5 8.1)."""
    sc = ex.run_down(stand, 30.0, time=175.0, settle=5.0)
    tr = simulate(sc)
    assert tr.success
    i = np.searchsorted(tr.t, 5.0 + 87.5)
    assert tr.rotor_speed[i] / (2 * math.pi) == pytest.approx(15.0, rel=1e-12)
    assert tr.rotor_speed[-1] == pytest.approx(0.0, abs=1e-12)
    # the deceleration the digest infers for that stand: -0.171 rev/s^2
    acc = np.gradient(tr.rotor_speed, tr.t)[np.searchsorted(tr.t, 50.0)] / (2 * math.pi)
    assert acc == pytest.approx(-0.171, abs=1e-3)


def test_run_up_then_balanced(stand):
    tr = simulate(ex.run_up(stand, 15.0, 1.5, hold=30.0))
    assert classify(tr).name == "main"


def test_impact_disturbs_then_balancing_recovers(stand):
    """A blow at 30 s knocks the balanced rotor; the balls rebalance it (robust main motion)."""
    sc = ex.impact(stand, 15.0, at=30.0, velocity=0.05, after=40.0)
    tr = simulate(sc)
    r = tr.whirl_radius()
    i = np.searchsorted(tr.t, 30.0)
    assert r[i - 1] < 1e-6 and np.max(r[i:i + 50]) > 1e-4
    assert classify(tr).name == "main"


def test_unbalance_step_is_rebalanced(stand):
    sc = ex.unbalance(stand, 15.0, at=30.0, eccentricity=1.2e-3, angle_deg=40.0, after=60.0)
    tr = simulate(sc)
    r = classify(tr)
    assert r.name == "main" and r.residual < 1e-3
    # the balls moved to the new balancing angles: e^{i a1} + e^{i a2} = -2 e0 e^{i 40 deg}
    e0 = 4.45 * 1.2e-3 / stand.balancer.capacity
    a = tr.relative_angle[-1]
    np.testing.assert_allclose(np.exp(1j * a).sum(), -2 * e0 * np.exp(1j * math.radians(40.0)),
                               atol=2e-3)
    before = tr.relative_angle[np.searchsorted(tr.t, 29.0)]
    assert np.max(np.abs(np.exp(1j * a) - np.exp(1j * before))) > 0.1


def test_experiment_command_and_errors(tmp_path, capsys):
    out = tmp_path / "p.h5"
    rc = main(["experiment", str(SCENES / "ball_runup.toml"), "pressure", "--speed", "15", "--at", "20",
               "--end", "25", "--side-force", "5", "-o", str(out)])
    assert rc == 0
    with h5py.File(out) as f:
        assert "pressure" in f.attrs["experiment"]
    rc = main(["experiment", str(SCENES / "ball_runup.toml"), "run-up", "--speed", "15", "-o",
               str(tmp_path / "x.h5")])
    assert rc == 2 and "--rate" in capsys.readouterr().err
    with pytest.raises(SceneError, match="rate"):
        ex.run_up(load_scene(SCENES / "ball_runup.toml"), 15.0, -1.0)


def test_experiments_on_a_scene_with_instruments(tmp_path):
    """Run-down and the natural-frequency test on the stand with cameras: the rings use the
    programme's largest speed; a non-spinning rotor gives no strobe frames but a note."""
    base = SCENES / "stand_cameras.toml"
    assert main(["experiment", str(base), "run-down", "--speed", "15", "--time", "10",
                 "-o", str(tmp_path / "rd.h5")]) == 0
    assert main(["experiment", str(base), "natural-frequency", "--deflection", "0.003",
                 "-o", str(tmp_path / "nf.h5")]) == 0
    with h5py.File(tmp_path / "rd.h5") as f:
        assert f["instruments/screen"].attrs["ring_test_speed_rad_s"] == pytest.approx(2 * math.pi * 15)
    with h5py.File(tmp_path / "nf.h5") as f:
        assert "no flashes" in f["instruments/stroboscope"].attrs["note"]
        assert "ring_radius" not in f["instruments/screen"]
