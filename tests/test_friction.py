"""Dry friction, sticking and rolling inertia of the weights (stand.model.balancers.friction
in the generic coupled kernel), on the universal stand's planar rotor."""
import dataclasses
import math

import numpy as np
import pytest

from stand.model.balancers.friction import Friction
from stand.integrate.coupled import PlaneWeights, simulate_coupled
from stand.model.rotors.planar_supports import planar_rotor
from stand.scene.structure_tables import parse_family_scene
from stand.scene.model import Balancer, SceneError

M, m, l = 4.45, 0.045, 0.08                    # universal stand (ch. 4.3), two balls
MS = M + 2 * m
C = MS * (2 * math.pi * 3.0) ** 2              # f0 = 3 Hz
U = 0.5 * 2 * m * l                            # e0 = 0.5
ROT = planar_rotor(M, C, damping_x=2 * 0.05 * math.sqrt(C * MS), unbalance=U)
BALLS = Balancer(type="balls", mass=np.full(2, m), radius=np.full(2, l), drag=np.full(2, 0.17),
                 inertia=np.full(2, m * l * l), initial_angles=np.radians([150.0, 210.0]),
                 initial_speeds=np.zeros(2))
W15 = 2 * math.pi * 15.0


def test_friction_parameters_are_checked():
    with pytest.raises(ValueError, match="friction.kinetic"):
        Friction(kinetic=-1.0)
    with pytest.raises(ValueError, match="friction.static"):
        Friction(kinetic=0.01, static=0.001)
    assert not Friction(kinetic=0.01).sticks and Friction(kinetic=0.01, static=0.02).sticks


def test_zero_friction_is_the_frictionless_model():
    prog = [[0.0, 0.0], [5.0, W15]]
    a = simulate_coupled(ROT, [PlaneWeights("balancer", BALLS)], prog, 8.0, 50.0)
    b = simulate_coupled(ROT, [PlaneWeights("balancer", BALLS, Friction(kinetic=0.0))], prog, 8.0, 50.0)
    np.testing.assert_array_equal(a.planes["balancer"], b.planes["balancer"])


@pytest.mark.parametrize("start", [(150.0, 210.0), (20.0, 300.0), (90.0, 100.0)])
def test_friction_leaves_a_residual_circle_5_to_6_times_smaller(start):
    """Rolling resistance mu = 2.5e-3: the balls stop where the shaft's push
    m l omega^2 r falls below the friction ~ mu m l^2 omega^2, so the residual
    whirl radius is of order mu l and the circle shrinks e / r times -- 3.5 to 8
    depending on where the balls stop (median 5.9 over 8 random starts), the
    measured 5-6x (digest ch5 T12, ch7)."""
    balls = dataclasses.replace(BALLS, initial_angles=np.radians(start))
    run = simulate_coupled(ROT, [PlaneWeights("balancer", balls, Friction(kinetic=2.5e-3))],
                           [[0.0, 0.0], [5.0, W15]], 30.0, 100.0)
    r = np.hypot(*run.planes["balancer"][-100:].T).max()     # last second
    e = U / MS                                               # circle without the balancer
    assert 0 < r <= 1.5 * 2.5e-3 * l
    assert 3.0 < e / r < 10.0
    # without friction the same start balances completely
    free = simulate_coupled(ROT, [PlaneWeights("balancer", balls)], [[0.0, 0.0], [5.0, W15]],
                            30.0, 100.0)
    assert np.hypot(*free.planes["balancer"][-1]) < 1e-3 * r


def test_sticking_keeps_the_balls_near_balance_below_the_critical_speed():
    """Slow run-down 15 -> 1 rev/s from the balanced configuration: without
    friction the balls go to the heavy side below f0 = 3 Hz (residual -> U + S,
    3x the unbalance); with sticking (mu_s = 0.03 after a 0.5 s dwell) they
    stay near the balancing place well below the ideal critical speed."""
    balls = dataclasses.replace(BALLS, initial_angles=np.radians([120.0, 240.0]))
    prog = [[0.0, W15], [10.0, W15], [130.0, 2 * math.pi * 1.0]]
    out = {}
    for key, fr in (("free", None), ("stick", Friction(kinetic=3e-3, static=0.03, dwell_time=0.5))):
        run = simulate_coupled(ROT, [PlaneWeights("balancer", balls, fr)], prog, 130.0, 20.0)
        R = np.hypot(*run.static_residual.T) / U
        f = run.speed / (2 * math.pi)
        out[key] = R[np.searchsorted(-f, -2.2)]                # at 2.2 rev/s (0.73 f0)
    assert out["free"] > 2.0
    assert out["stick"] < 0.5 * out["free"]


def test_scene_keys_friction_and_rolling():
    doc = {"structure": {"type": "planar", "mass": M, "stiffness_x": C},
           "weights": [{"type": "balls", "count": 2, "mass": m, "radius": l, "friction": 2.5e-3,
                        "static_friction": 0.01, "rolling": True}],
           "drive": {"type": "speed", "programme": [[0.0, 1.0]]},
           "run": {"duration": 1.0, "sample_rate": 10.0}}
    sc = parse_family_scene(doc)
    w = sc.weights[0]
    assert w.friction.kinetic == 2.5e-3 and w.friction.static == 0.01
    np.testing.assert_allclose(w.balancer.inertia, 7 / 5 * m * l * l)     # j = 5/7
    doc["weights"][0]["static_friction"] = 1e-4
    with pytest.raises(SceneError, match="static"):
        parse_family_scene(doc)
