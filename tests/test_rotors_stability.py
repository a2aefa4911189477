"""Main-motion stability of any rotor with weights by Floquet multipliers
(stand.theories.rotor_stability), checked against the planar theory of the theory issue
and against simulation for a rotor the theory does not cover."""
import math

import numpy as np
import pytest

from stand.model.rotors import LinearRotor, Unbalance
from stand.integrate.coupled import PlaneWeights, simulate_coupled
from stand.scene.parse import load_scene
from stand.theories.rotor_stability import _state_guess, main_motion_critical_speeds, main_motion_stability
from stand.scene.model import Balancer
from stand.theories.planar.main_motion import critical_speeds, d_two_balls, spectral_abscissa


def _planar(m=0.025, l=0.1, e0=0.5, h=0.3, H=0.1):
    """M_Sigma = 1 kg, c = 1 N/m (omega_1 = 1 rad/s): rates are dimensionless."""
    rot = LinearRotor("planar", ("x", "y"), (1.0 - 2 * m) * np.eye(2), np.zeros((2, 2)),
                      H * np.eye(2), np.eye(2), {"balancer": np.eye(2)},
                      (Unbalance("balancer", e0 * 2 * m * l, 0.0),))
    b = Balancer(type="balls", mass=np.full(2, m), radius=np.full(2, l), drag=np.full(2, h * m),
                 inertia=np.full(2, m * l * l), initial_angles=np.radians([150.0, 210.0]),
                 initial_speeds=np.zeros(2))
    return rot, [PlaneWeights("balancer", b)], dict(Rt=m, h=h, H=H, d=d_two_balls(e0))


@pytest.mark.parametrize("R", [1.5, 3.0, 6.0])
def test_floquet_rate_is_the_planar_spectral_abscissa(R):
    """For the isotropic planar rotor the main motion is an equilibrium in rotating
    axes: log|mu| / T must equal the abscissa of (5.87)-(5.90)."""
    rot, w, p = _planar()
    r = main_motion_stability(rot, w, R)
    assert r.residual_unbalance < 1e-10 and r.stable
    assert r.growth_rate == pytest.approx(spectral_abscissa(R, **p), rel=1e-6)
    # two balls at 180 deg +- arccos(e0) = 120 / 240 deg
    np.testing.assert_allclose(np.sort(np.degrees(r.weight_angles) % 360), [120.0, 240.0], atol=1e-6)


def test_continuation_finds_the_planar_critical_speed():
    rot, w, p = _planar()
    exact = critical_speeds(**p)[0].R          # 1.47915 (gains stability)
    start = main_motion_stability(rot, w, 1.7)
    _, crit = main_motion_critical_speeds(rot, w, [1.7, 1.55, 1.4],
                                          y_guess=_state_guess(rot, w, start, 1.7))
    assert crit.size == 1 and crit[0] == pytest.approx(exact, rel=1e-5)


def test_two_mass_main_motion_edges_match_simulation():
    """Model 2.5.2 with finite ball masses: the Floquet onset of the first range
    lies where simulations start to balance (docs/rotors.md: between 9.2 and
    9.4 Hz, criterion 8.99 Hz) -- the finite-mass shift the criterion misses."""
    sc = load_scene("data_samples/scenes/family_two_mass.toml")
    rotor = sc.linear_rotor()
    w15 = 2 * math.pi * 15.0
    r15 = main_motion_stability(rotor, sc.weights, w15)
    assert r15.stable and r15.residual_unbalance < 1e-12
    g = _state_guess(rotor, sc.weights, r15, w15)
    _, crit = main_motion_critical_speeds(rotor, sc.weights,
                                          2 * math.pi * np.array([15.0, 10.0, 9.0]), y_guess=g)
    f = crit[0] / (2 * math.pi)
    assert 9.2 < f < 9.4
    for fz, expect in ((f - 0.1, False), (f + 0.1, True)):
        wz = 2 * math.pi * fz
        run = simulate_coupled(rotor, sc.weights, [[0.0, wz]], 120.0, 4 * fz)
        assert (float(np.hypot(*run.static_residual[-1])) < 1e-4 * 2e-3 * 50) == expect, fz


def test_fixed_point_stand_main_motion_ends_in_a_fold_that_simulation_confirms(monkeypatch):
    """Section 4.4 stand (horizontal axis: gravity on the balls).  Continued down from
    15 rev/s, the main motion ends near 4.86 rev/s: its growth rate goes to 0 there (a fold),
    and below it Newton shooting finds no periodic orbit.  Checked without Newton: a
    simulation at constant speed, sampled once per revolution (a stroboscope), settles to
    one point above the end (the orbit, the Floquet residual unbalance) and keeps moving
    below it (no motion periodic with the revolution).  Before the fix the scan bisected
    between points that were no orbits (Newton residuals 0.2-20) and ran 88 s into its
    budget (exit 1); now the theory spends < 1e6 state-steps."""
    import stand.theories.rotors as th

    sc = load_scene("data_samples/scenes/family_fixed_point_stand.toml")
    monkeypatch.setattr(th, "FLOQUET_BUDGET", 1_000_000)
    mm = th.family_theory(sc)["main_motion"]
    assert mm["critical_speeds_hz"] == [] and len(mm["ends_hz"]) == 1
    fe = mm["ends_hz"][0]
    assert 4.80 < fe < 4.90, fe
    rotor = sc.linear_rotor()
    w15 = 2 * math.pi * 15.0
    r15 = main_motion_stability(rotor, sc.weights, w15)
    out, crit = main_motion_critical_speeds(rotor, sc.weights, 2 * math.pi * np.array(
        [15.0, 8.0, 5.4, 4.5]), y_guess=_state_guess(rotor, sc.weights, r15, w15), xtol=1e-4)
    assert crit.size == 0 and all(r.converged for r in out[:-1]) and not out[-1].converged
    assert out[-1].omega - out[-2].omega == pytest.approx(0.0, abs=1e-3 * out[-1].omega)
    rates = {round(r.omega / (2 * math.pi), 1): r.growth_rate for r in out[:-1]}
    assert rates[5.4] < 0 and -0.1 * abs(rates[5.4]) < out[-2].growth_rate < 0     # -> 0
    above = next(r for r in out if r.omega / (2 * math.pi) == pytest.approx(5.4))
    for f, settles in ((5.4, True), (fe - 0.15, False)):
        run = simulate_coupled(rotor, sc.weights, [[0.0, 2 * math.pi * f]], 200.0, 4 * f)
        strobe = np.hypot(*run.static_residual.T)[::4][-int(20 * f):]    # last 20 s
        spread = float(strobe.max() - strobe.min())
        assert (spread < 2e-5) == settles and (spread > 5e-5) == (not settles), (f, spread)
        if settles:
            assert strobe.mean() == pytest.approx(above.residual_unbalance, rel=0.01)
