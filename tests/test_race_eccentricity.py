"""The balls' race off the shaft (``race_eccentricity``, ``race_eccentricity_angle``;
stand.model.rotors.weight_table): the balls balance about their race's centre, so the
shaft keeps a whirl of the eccentricity itself."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import stand
from stand.scene.model import SceneError

RUNUP = (Path(__file__).resolve().parents[1] / "data_samples" / "scenes" / "ball_runup.toml").read_text()
E_R, THETA = 1e-4, 30.0          # m, deg


def _scene(race=True):
    text = (RUNUP.replace("duration = 40.0", "duration = 30.0")
            .replace("[[0.0, 0.0], [10.0, 15.0]]", "[[0.0, 0.0], [4.0, 15.0]]")
            .replace("rtol = 1e-8", "rtol = 1e-10").replace("atol = 1e-10", "atol = 1e-12"))
    if race:
        text = text.replace("initial_angles = [150.0, 210.0]   # deg from the reference mark",
                            f"initial_angles = [150.0, 210.0]\nrace_eccentricity = {E_R}\n"
                            f"race_eccentricity_angle = {THETA}")
    return stand.load(text)


def test_residual_whirl_is_the_race_eccentricity():
    """Steady state above the resonance (15 rev/s, f0 = 3 Hz): at rest on the rotor, ball j's
    row reads n_j . (q_K + o) = 0 (the centrifugal field about the axis has no component
    along the race), so two balls not in line put the race's centre o on the axis: the
    shaft K whirls at q_K = -o, radius e_r, opposite the race's offset (angle theta + 180
    deg from the mark), whatever the masses (not n m e_r / M_S = 0.9 um: the balls balance
    about the race's centre, not the shaft's).  Bound: the integrator (rtol 1e-10) and the
    settling left after 26 s (measured 4e-10 of e_r in radius, 5e-11 rad)."""
    sc = _scene()
    assert sc.generic_kernel == "race eccentricity"
    run = stand.run(sc)
    z = run.x + 1j * run.y
    assert np.abs(z[-1]) == pytest.approx(E_R, rel=1e-7)
    rel = (np.angle(z[-1]) - run.rotor_angle[-1] - math.radians(THETA + 180.0) + math.pi) \
        % (2 * math.pi) - math.pi
    assert abs(rel) < 1e-7
    # the same stand on a centred race balances completely
    free = stand.run(_scene(race=False))
    assert np.hypot(free.x[-1], free.y[-1]) < 1e-3 * E_R


def test_race_keys_are_checked():
    sc = _scene()
    assert sc.balancer.race_eccentricity == E_R
    assert sc.balancer.race_eccentricity_angle == pytest.approx(math.radians(THETA), abs=1e-15)
    with pytest.raises(SceneError, match=r"race_eccentricity = -0\.001.*m"):
        stand.load(RUNUP.replace("[balancer]", "[balancer]\nrace_eccentricity = -0.001"))
    torque = RUNUP.replace("[balancer]", "[balancer]\nrace_eccentricity = 0.001").replace(
        'type = "speed"\nprogramme = [[0.0, 0.0], [10.0, 15.0]]   # [s, rev/s]; held at 15 rev/s afterwards',
        'type = "torque"\nmodel = "constant"\ntorque = 0.1').replace(
        "unbalance_angle = 0.0       # deg from the reference mark",
        "unbalance_angle = 0.0\ninertia = 0.05")
    with pytest.raises(SceneError, match="race_eccentricity run on the generic kernel: a speed"):
        stand.load(torque)


def test_theory_says_the_race_is_outside_it():
    from stand.theories.scene import theory

    na = theory(_scene()).not_applicable
    assert any("race eccentricity of balancer (0.0001 m)" in x for x in na), na
