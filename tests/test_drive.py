"""Drives: prescribed speed programme and coast-down; torque models 1-3 (section 5.1.1)."""
import math

import numpy as np
import pytest
from scipy.integrate import quad

from stand.model.planar import build_planar_model
from stand.model.programme import build_table, rotor_kinematics
from stand.scene.model import (Balancer, InitialState, Rotor, RunSettings, Scene, SpeedDrive,
                         Supports, TorqueDrive)
from stand.scene.parse import load_scene
from stand.integrate.simulate import simulate

from _helpers import toml_text


def test_programme_angle_is_the_integral_of_the_speed():
    prog = build_table(np.array([0.5, 2.0, 3.0, 7.0]), np.array([1.0, 4.0, 4.0, 0.5]))
    tc, T = 5.0, 1.7
    phic, Rc, _ = rotor_kinematics(tc, prog, len(prog), np.inf, 1.0, 0.0, 0.0)
    kin = lambda t: rotor_kinematics(t, prog, len(prog), tc, T, Rc, phic)
    for t in (0.2, 0.5, 1.3, 2.0, 2.5, 4.0, 5.0, 6.0, 12.0):
        phi, R, acc = kin(t)
        # phi(t) = integral of R from 0 (quadrature to 1e-12)
        integral, _ = quad(lambda s: kin(s)[1], 0.0, t, points=[0.5, 2.0, 3.0, 5.0], limit=200,
                           epsabs=1e-13, epsrel=1e-13)
        assert phi == pytest.approx(integral, abs=1e-10)
        # R' = acceleration away from the nodes (central difference, error ~ d^2 R''' = 0 here)
        if all(abs(t - b) > 1e-3 for b in (0.5, 2.0, 3.0, 5.0)):
            d = 1e-6
            assert acc == pytest.approx((kin(t + d)[1] - kin(t - d)[1]) / (2 * d), abs=1e-6)
    # exponential coast-down: R = R_c exp(-(t - t_c)/T)
    assert kin(tc + 2 * T)[1] == pytest.approx(Rc * math.exp(-2), rel=1e-14)


def _free_rotor(model, torque=0.0, c1=0.0, c2=0.0, target=0.0, drag=0.0, e=0.0, duration=60.0):
    return Scene(rotor=Rotor(mass=2.0, eccentricity=e, inertia=0.05),
                 supports=Supports(2000.0, 2000.0, 20.0, 20.0), balancer=Balancer(),
                 drive=TorqueDrive(model=model, torque=torque, c1=c1, c2=c2, target_speed=target,
                                   rotor_drag=drag, initial_speed=0.0),
                 run=RunSettings(duration, 50.0, 1e-10, 1e-12))


def test_constant_torque_spins_up_against_drag():
    # J0 w' = M - H0 w  ->  w(t) = M/H0 (1 - exp(-H0 t / J0)), balanced rotor
    M, H0, J0 = 0.2, 0.01, 0.05
    tr = simulate(_free_rotor("constant", torque=M, drag=H0, duration=10.0))
    assert tr.success
    w = M / H0 * (1 - np.exp(-H0 * tr.t / J0))
    np.testing.assert_allclose(tr.rotor_speed, w, rtol=1e-8, atol=1e-9)


def test_speed_feedback_settles_at_its_equilibrium():
    # c1 (W - w) - H0 w = 0  ->  w = c1 W / (c1 + H0)
    c1, W, H0 = 0.5, 100.0, 0.01
    tr = simulate(_free_rotor("speed_feedback", c1=c1, target=W, drag=H0, duration=5.0))
    assert tr.rotor_speed[-1] == pytest.approx(c1 * W / (c1 + H0), rel=1e-8)


def test_angle_feedback_tracks_the_target_angle():
    # with the c2 (W t - phi) term the steady speed error vanishes: w -> W and
    # phi - W t -> -H0 W / c2
    c1, c2, W, H0 = 0.5, 20.0, 100.0, 0.01
    tr = simulate(_free_rotor("angle_feedback", c1=c1, c2=c2, target=W, drag=H0, duration=10.0))
    assert tr.rotor_speed[-1] == pytest.approx(W, rel=1e-8)
    assert tr.rotor_angle[-1] - W * tr.t[-1] == pytest.approx(-H0 * W / c2, rel=1e-6)


def test_unbalanced_free_rotor_slows_at_resonance_sommerfeld():
    """An unbalanced rotor driven by a weak motor through resonance draws energy
    into the whirl: its speed stays below that of the balanced rotor (the
    Sommerfeld effect), i.e. the rotor equation sees -M e (x'' sin - y'' cos)."""
    kw = dict(c1=0.002, target=60.0, drag=0.0, duration=20.0)
    balanced = simulate(_free_rotor("speed_feedback", **kw))
    unbalanced = simulate(_free_rotor("speed_feedback", e=2e-3, **kw))
    w1 = math.sqrt(2000.0 / 2.0)
    i = np.searchsorted(balanced.rotor_speed, w1)  # the balanced rotor crosses resonance
    assert unbalanced.rotor_speed[i] < balanced.rotor_speed[i]


def test_coast_down_scene_file():
    sc = load_scene(toml_text(
        rotor=dict(mass=4.45, eccentricity=1e-4), supports=dict(stiffness=1600.0, damping=8.0),
        drive=dict(type="speed", programme=[[0.0, 0.0], [5.0, 10.0]],
                   coast_down=dict(start=8.0, time_constant=2.0)),
        run=dict(duration=12.0, sample_rate=100.0)))
    tr = simulate(sc)
    assert tr.success
    i = np.searchsorted(tr.t, 10.0)
    assert tr.rotor_speed[i] == pytest.approx(2 * math.pi * 10 * math.exp(-1.0), rel=1e-12)
    assert build_planar_model(sc).breakpoints().tolist() == pytest.approx([5.0 * sc.natural_frequency,
                                                                          8.0 * sc.natural_frequency])
