"""Weights coupled to the generic LinearRotor (stand.model.rotors.coupled)."""
import math

import numpy as np
import pytest

from stand.model.rotors import LinearRotor, Unbalance, working_ranges
from stand.model.rotors.coupled import PlaneWeights, simulate_coupled
from stand.scene.model import Balancer
from stand.scene.parse import load_scene
from stand.integrate.simulate import simulate


def _planar_rotor(sc):
    s = sc.supports
    return LinearRotor("planar", ("x [m]", "y [m]"), np.eye(2) * sc.rotor.mass, np.zeros((2, 2)),
                       np.diag([s.damping_x, s.damping_y]), np.diag([s.stiffness_x, s.stiffness_y]),
                       {"balancer": np.eye(2)},
                       (Unbalance("balancer", sc.rotor.unbalance, sc.rotor.unbalance_angle),))


def test_generic_form_reproduces_the_planar_model():
    """The planar model of the core simulator written as a LinearRotor (M, D, K,
    T = I) with the same two balls: same shaft motion to the tolerance."""
    import dataclasses

    sc = load_scene("data_samples/scenes/ball_runup.toml")
    sc = dataclasses.replace(sc, run=dataclasses.replace(sc.run, duration=15.0, rtol=1e-10,
                                                         atol=1e-12))
    tr = simulate(sc)
    cr = simulate_coupled(_planar_rotor(sc), [PlaneWeights("balancer", sc.balancer)],
                          sc.drive.programme, sc.run.duration, sc.run.sample_rate,
                          rtol=1e-10, atol=1e-12)
    assert cr.success and tr.success
    np.testing.assert_allclose(cr.t, tr.t, atol=1e-12)
    X = np.column_stack([tr.x, tr.y])
    # both integrate the same ODE at rtol 1e-10: agreement far below the 10 mm motion
    assert np.abs(cr.planes["balancer"] - X).max() < 1e-7 * np.abs(X).max()
    assert np.abs(np.angle(np.exp(1j * (cr.weight_angle - tr.relative_angle)))).max() < 1e-6


def _two_mass(M1=2.0, M2=1.0, c1=1.0e4, c2=3.0e4, zeta=0.01, s=2e-3):
    """Rotor M2 on springs c2 in a body M1 on springs c1 (model 2.5.2), light damping."""
    I2 = np.eye(2)
    Z = np.zeros((2, 2))
    M = np.block([[M1 * I2, Z], [Z, M2 * I2]])
    K = np.block([[(c1 + c2) * I2, -c2 * I2], [-c2 * I2, c2 * I2]])
    D = 2 * zeta * math.sqrt(c2 * M2) * K / c2
    T = np.hstack([Z, I2])
    return LinearRotor("two_mass", ("x1 [m]", "y1 [m]", "x2 [m]", "y2 [m]"), M, np.zeros((4, 4)), D,
                       K, {"balancer": T, "body": np.hstack([I2, Z])},
                       (Unbalance("balancer", s, 0.0),))


def _balls(m=0.01, R=0.2, drag=2.0):
    return Balancer(type="balls", mass=np.full(2, m), radius=np.full(2, R), drag=np.full(2, drag),
                    inertia=np.full(2, m * R * R), initial_angles=np.radians([60.0, 250.0]),
                    initial_speeds=np.zeros(2))


def test_two_mass_rotor_balances_inside_its_working_range_only():
    """Model 2.5.2 with two balls: criterion ranges (w1, w2) U (w3, inf); a run held
    inside the first range and one in the gap (w2, w3) end balanced / unbalanced."""
    rot = _two_mass()
    crit, ranges = working_ranges(rot, "balancer", 1.0, 2000.0)
    assert len(crit) == 3 and len(ranges) == 2
    w1, w2, w3 = crit
    # inside the first range (geometric middle) and in the gap between w2 and w3
    for w, expect in ((math.sqrt(w1 * w2), True), (math.sqrt(w2 * w3), False),
                      (2.0 * w3, True)):
        run = simulate_coupled(rot, [PlaneWeights("balancer", _balls())], [[0.0, w]],
                               duration=400 * 2 * math.pi / w1, sample_rate=20 * w / (2 * math.pi))
        assert run.success
        U = np.hypot(*run.residual["balancer"][-1])
        balanced = U < 0.05 * 2e-3
        assert balanced == expect, (w, U)
