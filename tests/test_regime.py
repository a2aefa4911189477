"""Regime classifier on runs whose regime the theory fixes."""
from pathlib import Path

import numpy as np
import pytest

from stand.analysis.regime import classify
from stand.scene.model import RunSettings, SpeedDrive
from stand.scene.parse import load_scene, scene_from_dimensionless
from stand.integrate.simulate import simulate

SCENES = Path(__file__).resolve().parents[1] / "data_samples" / "scenes"


def test_stuck_balls_are_quasi_periodic():
    r = classify(simulate(load_scene(SCENES / "ball_stuck.toml")))
    assert r.name == "quasi-periodic"
    # the balls' common speed is the stable root of (5.181), 0.96135 (digest Table 5.1-B)
    assert np.allclose(r.weight_speed, 0.96135, rtol=2e-3)


def test_run_up_ends_in_the_main_motion():
    r = classify(simulate(load_scene(SCENES / "ball_runup.toml")))
    assert r.name == "main" and r.residual < 1e-6


def test_below_resonance_balls_go_to_the_heavy_side():
    """R = 0.7 < 1, e0 = 0.5, h = H = 0.1: the side motion k = 0 (both balls on
    the heavy side) is stable (digest ch5 section 4.5 table); the balls lag the
    heavy side by the angle gamma of the corrected (5.64)/(5.66)."""
    R, e0, H = 0.7, 0.5, 0.1
    sc = scene_from_dimensionless(2, 0.01, 0.1, H, e0, drive=SpeedDrive(np.array([[0.0, R]])),
                                  run=RunSettings(2000.0, 1.0), initial_angles=np.radians([120.0, 240.0]))
    tr = simulate(sc)
    r = classify(tr)
    assert r.name == "side"
    ek = 1.0  # both balls on one side
    root = np.sqrt(e0**2 * (R**2 - 1)**2 + H**2 * R**2 * (e0**2 - ek**2))
    gamma = 2 * np.arctan((-e0 * (R**2 - 1) - root) / (H * R * (e0 - ek)))  # (5.66), branch near 0
    np.testing.assert_allclose(tr.relative_angle[-1], [gamma, gamma], atol=1e-6)
    assert r.residual == pytest.approx(abs(e0 + ek * np.exp(1j * gamma)), rel=1e-6)


@pytest.mark.parametrize("R, residual", [(1.05, 0.6198), (3.0, 0.5002)])
def test_beyond_capacity_the_maximally_balanced_motion_is_main(R, residual):
    """e0 = 1.5 > 1: the weights go together to the light side; with damping the
    residual is |psi| of the corrected (5.64) (0.620 at R = 1.05, -> e0 - 1 = 0.5
    at high speed), not e0 - 1 (helper check of side.maximally_balanced_motion)."""
    sc = scene_from_dimensionless(2, 0.01, 0.1, 0.1, 1.5, drive=SpeedDrive(np.array([[0.0, R]])),
                                  run=RunSettings(3000.0, 1.0), initial_angles=np.radians([170.0, 190.0]))
    r = classify(simulate(sc))
    assert r.name == "main"
    assert r.residual == pytest.approx(residual, abs=2e-4)
