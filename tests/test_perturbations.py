"""Perturbations of tables 4.5-4.6: unbalance change, blow to the housing, side force.

Oracles: the linear rotor without weights (closed forms), so the tolerances are
the integrator's (rtol 1e-10) plus the decay of the transients.
"""
import math

import numpy as np
import pytest

from stand.integrate.accuracy import closed_form_no_balancer
from stand.scene.model import (Balancer, Impulse, Rotor, RunSettings, Scene, SideForce, SpeedDrive,
                         Supports, UnbalanceChange)
from stand.scene.parse import load_scene, SceneError
from stand.integrate.simulate import simulate

from _helpers import toml_text

M, C, H = 4.0, 1600.0, 0.1
W1 = math.sqrt(C / M)
D = H * W1 * M


def rotor_scene(R, duration, perturbations=(), e=1e-3):
    return Scene(Rotor(M, e, 0.0), Supports(C, C, D, D), Balancer(),
                 SpeedDrive(np.array([[0.0, R * W1]])), RunSettings(duration, 50.0, 1e-10, 1e-12),
                 perturbations=tuple(perturbations))


def steady(R, e, beta=0.0):
    return e * R**2 * np.exp(1j * beta) / (1 - R**2 + 1j * H * R)  # rotor frame, m


@pytest.mark.parametrize("duration", [0.0, 2.0])
def test_unbalance_change_new_steady_whirl(duration):
    """A discrete step (duration 0) or a continuous change to e = 2 mm at 90 deg: the whirl
    settles to the closed form of the new unbalance (transient e^{-H tau/2} < 1e-8 after 80 s)."""
    R = 3.0
    sc = rotor_scene(R, 120.0, [UnbalanceChange(10.0, duration, 2e-3, math.pi / 2)])
    tr = simulate(sc)
    assert tr.success
    z = (tr.x + 1j * tr.y) * np.exp(-1j * tr.rotor_angle)
    before = np.searchsorted(tr.t, 9.9)
    transient = 2 * math.exp(-H * W1 * 9.9 / 2)  # start from rest: e^{-H tau / 2} left at 9.9 s
    assert abs(z[before] - steady(R, 1e-3)) < transient * abs(steady(R, 1e-3))
    assert abs(z[-1] - steady(R, 2e-3, math.pi / 2)) < 1e-7 * abs(steady(R, 2e-3))


def test_continuous_change_includes_the_moving_mass_terms():
    """During a linear change u(tau) = u0 + u1 tau the forcing is e^{i R tau}(R^2 u - 2 i R u1)
    (the centre of mass moves: -d'' = e^{i phi}(phi'^2 u - 2 i phi' u')).  Its exact
    particular solution is z = e^{i R tau}(A + B tau), B = R^2 u1 / D,
    A = (R^2 u0 - 2 i R u1 - (2 i R + H) B) / D, D = 1 - R^2 + i H R; compare at the end of
    a long change (transients e^{-H tau/2} < 1e-9).  Without the 2 i R u1 term the error
    would be 2 R u1 / |D|, far above the tolerance."""
    R = 3.0
    T0, T = 5.0, 200.0
    sc = rotor_scene(R, T0 + T, [UnbalanceChange(T0, T, 3e-3, 0.0)])
    tr = simulate(sc)
    z = (tr.x + 1j * tr.y) * np.exp(-1j * tr.rotor_angle)
    i = np.searchsorted(tr.t, T0 + 0.9 * T)
    tau = (tr.t[i] - T0) * W1
    u0, u1 = 1e-3, (3e-3 - 1e-3) / (T * W1)
    Dn = 1 - R**2 + 1j * H * R
    B = R**2 * u1 / Dn
    A = (R**2 * u0 - 2j * R * u1 - (2j * R + H) * B) / Dn
    expected = A + B * tau
    assert abs(z[i] - expected) < 1e-7 * abs(expected)
    assert 2 * R * u1 / abs(Dn) > 100 * 1e-7 * abs(expected)


def test_impulse_is_a_velocity_jump_then_free_decay():
    """A blow at t = 1 s to a rotor at rest without unbalance: x(t) = v0/w_d e^{-zeta w1 t'} sin(w_d t')."""
    v0 = 0.01
    sc = rotor_scene(0.0, 3.0, [Impulse(1.0, v0, 0.0)], e=0.0)
    tr = simulate(sc)
    assert tr.success
    tp = tr.t - 1.0
    zeta = H / 2
    wd = W1 * math.sqrt(1 - zeta**2)
    x = np.where(tp > 0, v0 / wd * np.exp(-zeta * W1 * tp) * np.sin(wd * np.maximum(tp, 0)), 0.0)
    assert np.max(np.abs(tr.x - x)) < 1e-8 * v0 / wd
    assert np.max(np.abs(tr.y)) == 0.0


def test_side_force_static_deflection():
    """A constant side force F_x with extra stiffness k_x from t = 0.5 s: the shaft settles at
    F_x / (c + k_x) (rotor at rest, no unbalance)."""
    F, k = 5.0, 400.0
    sc = rotor_scene(0.0, 20.0, [SideForce(0.5, math.inf, force_x=F, stiffness_x=k)], e=0.0)
    tr = simulate(sc)
    assert tr.x[-1] == pytest.approx(F / (C + k), rel=1e-8)
    assert tr.x[np.searchsorted(tr.t, 0.49)] == 0.0


def test_perturbations_from_a_scene_file():
    text = toml_text(
        rotor=dict(mass=4.0, eccentricity=1e-3), supports=dict(stiffness=1600.0, damping=4.0),
        drive=dict(type="speed", programme=[[0.0, 10.0]]), run=dict(duration=5.0, sample_rate=100.0),
        perturbation=[dict(type="unbalance", time=1.0, eccentricity=2e-3, unbalance_angle=90.0),
                      dict(type="impulse", time=2.0, velocity_x=0.01),
                      dict(type="side_force", start=3.0, end=4.0, force_y=2.0)])
    sc = load_scene(text)
    kinds = [p.kind for p in sc.perturbations]
    assert kinds == ["unbalance", "impulse", "side_force"]
    assert sc.perturbations[0].unbalance_angle == pytest.approx(math.pi / 2)
    assert simulate(sc).success
    with pytest.raises(SceneError, match=r"perturbation\[0\]\.force_x"):
        load_scene(text.replace('time = 1.0\neccentricity', 'time = 1.0\nforce_x = 1.0\neccentricity'))
    with pytest.raises(SceneError, match=r"perturbation\[1\]\.time"):
        load_scene(text.replace("time = 2.0", "time = 20.0"))
