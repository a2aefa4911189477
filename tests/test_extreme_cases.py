"""Extreme and pathological scenes: each run completes or stops with a clear message.

Contract checked for every run (``check_outcome``): a successful run returns every
requested sample and only finite numbers; a failed run has ``success`` False, a
negative ``status``, a non-empty message, and the samples it keeps are finite.  No
run may hang: durations are short, and the pathological runs carry a step budget.

omega_1 = 1 rad/s throughout (``scene_from_dimensionless`` default or M_Sigma = c_x = 1),
so t [s] = tau and speeds [rad/s] = R_omega.
"""
import math
import time

import numpy as np
import pytest

from stand.model.planar import build_planar_model, initial_state, rhs_planar, rhs_planar_numpy
from stand.scene.dimensionless import dimensionless
from stand.scene.model import Balancer, Rotor, RunSettings, Scene, SpeedDrive, Supports
from stand.scene.parse import scene_from_dimensionless
from stand.integrate.simulate import simulate

ARRAYS = ("t", "x", "y", "rotor_angle", "rotor_speed", "weight_angle", "weight_speed", "state")


def constant_speed(R):
    return SpeedDrive(programme=np.array([[0.0, float(R)]]))


def check_outcome(tr):
    """Never NaN silently: complete and finite, or stopped with a message and finite samples."""
    st = tr.stats
    run = tr.scene.run
    for name in ARRAYS:
        assert np.all(np.isfinite(getattr(tr, name))), f"non-finite {name} (success={st.success})"
    assert np.all(np.isfinite(tr.residual_unbalance()))
    if st.success:
        assert st.status == 0
        n_expected = int(math.floor(run.duration * run.sample_rate + 1e-9)) + 1
        assert len(tr.t) == n_expected
        # samples at k / sample_rate, the last one at or before the end of the run
        assert tr.t[-1] == pytest.approx((n_expected - 1) / run.sample_rate, rel=1e-12)
        assert run.duration - 1.0 / run.sample_rate < tr.t[-1] <= run.duration * (1 + 1e-12)
    else:
        assert st.status < 0
        assert st.message.strip()


def two_balls(R, *, h=0.5, e0=0.3, duration, sample_rate, angles=(2.0, 4.0), **run):
    """n = 2, Rt = 0.01, H = 0.1; balls not on one line with the unbalance (not a side motion)."""
    return scene_from_dimensionless(2, 0.01, h, 0.1, e0, drive=constant_speed(R),
                                    run=RunSettings(duration=duration, sample_rate=sample_rate, **run),
                                    initial_angles=list(angles))


def test_very_fast_rotor_R200():
    """R_omega = 200 for 300 revolutions (tau = 9.4)."""
    R = 200.0
    tr = simulate(two_balls(R, duration=2 * math.pi * 300 / R, sample_rate=50.0))
    check_outcome(tr)
    assert tr.success, tr.stats.message
    assert tr.stats.method == "DOP853"
    np.testing.assert_allclose(tr.rotor_speed, R, rtol=1e-15)
    np.testing.assert_allclose(tr.rotor_angle, R * tr.t, rtol=1e-12)


def test_huge_weight_drag_is_stiff_and_uses_radau():
    """h = 1e4: weight decay rate h/(1 - eps mu) >> R_omega = 3, so "auto" must pick Radau.

    The balls are then locked to the rotor: their relative speed is at most
    mu |a_K| / h = 2 Rt |z''| / h, with |z''| <= R^2 |z| and |z| <= R^2 (e0 + 1) / |1 - R^2|
    (+ an equal transient) ~ 3 r*, i.e. <= 2*0.01*27/1e4 ~ 5e-5 rad/s, so they move by
    < 2.5e-4 rad in 5 s: 2.5e-3 rad leaves a factor 10 (measured 2.2e-5).  5 s (was 20 s,
    bound 1e-2, 10x the CPU) is > 5e4 weight decay times (rate >= h = 1e4): the stiffness
    test (on the rates, before the first step) and the locking are decided long before.
    """
    sc = two_balls(3.0, h=1e4, duration=5.0, sample_rate=10.0)
    tr = simulate(sc, method="auto")
    check_outcome(tr)
    assert tr.success, tr.stats.message
    assert tr.stats.method == "Radau"
    assert "stiff" in tr.stats.method_reason
    drift = np.angle(np.exp(1j * (tr.relative_angle - sc.balancer.initial_angles)))
    assert np.max(np.abs(drift)) < 2.5e-3


def test_zero_weight_drag():
    tr = simulate(two_balls(3.0, h=0.0, duration=50.0, sample_rate=10.0))
    check_outcome(tr)
    assert tr.success, tr.stats.message
    assert tr.stats.method == "DOP853"


def test_64_identical_balls():
    n, Rt = 64, 0.01
    sc = scene_from_dimensionless(n, Rt, 0.5, 0.1, 0.3, drive=constant_speed(3.0),
                                  run=RunSettings(duration=50.0, sample_rate=10.0),
                                  initial_angles=np.linspace(0.1, 6.0, n))
    d = dimensionless(sc)
    assert d.n == n and d.Rt == pytest.approx(Rt, rel=1e-12)
    # the O(n) compiled right-hand side still equals the full (n+2)-system solve: rounding
    # grows like (n + 2) ulp ~ 1.5e-14 relative, below 1e-13
    md = build_planar_model(sc)
    y = initial_state(sc, md)
    y[md.nq:] += np.random.default_rng(0).normal(size=md.nq)
    dy = np.empty_like(y)
    rhs_planar(1.3, y, dy, md.sp, md.wt, md.prog)
    ref = rhs_planar_numpy(1.3, y, md.sp, md.wt, md.prog)
    np.testing.assert_allclose(dy, ref, rtol=0, atol=1e-13 * np.max(np.abs(ref)))
    tr = simulate(sc)
    check_outcome(tr)
    assert tr.success, tr.stats.message
    assert tr.weight_angle.shape == (len(tr.t), n)


def test_unbalance_twice_the_capacity():
    """e0 = 2 > 1 at R = 3: the balls gather on the light side (digest 4.5: the e0 > 1 main
    motion, all CWs on the light side, is stable above resonance); residual e0 - 1 = 1 of S.

    With both balls at pi + delta_j, |psi|/S = 1 + (delta_1^2 + delta_2^2)/4 + ..., so 1 %
    means |delta| <~ 0.2 rad (the damped steady lag is ~ H R/(R^2 - 1)/2 ~ 0.02 rad).  The
    relative mode decays at ~ 2 Rt R^2 v/h ~ 0.4 per tau (5.140, v = R^2 (e0-1)/(R^2-1)), so
    after 300 tau the balls coincide to round-off: 1e-6 rad is loose.
    """
    e0 = 2.0
    sc = two_balls(3.0, h=0.5, e0=e0, duration=300.0, sample_rate=1.0)
    tr = simulate(sc)
    check_outcome(tr)
    assert tr.success, tr.stats.message
    psi = abs(tr.residual_unbalance()[-1]) / sc.balancer.capacity
    assert psi == pytest.approx(e0 - 1.0, rel=1e-2)
    rel = tr.relative_angle[-1]
    assert np.all(np.abs(np.angle(np.exp(1j * (rel - np.pi)))) < 0.2)
    assert abs(np.angle(np.exp(1j * (rel[0] - rel[1])))) < 1e-6


@pytest.mark.slow
def test_hundred_thousand_revolutions():
    """1e5 revolutions at R = 3 (tau = 2.1e5), sampled every 20 s.

    The main motion decays at 0.0397 per tau (T10), so the initial |psi| ~ 0.3 reaches the
    integration-error floor (atol ~ 1e-10) after ~ 600 tau, long before the end: |psi| < 1e-6 S
    and whirl < 1e-6 r* are loose.  Balls at pi -+ arccos(e0): a ball error delta moves psi by
    e_j |delta| = |delta|/2, so |psi| < 1e-6 S bounds the errors of the pair to ~ 1e-5 rad
    (n = 2: the balancing configuration is isolated); asserted at 1e-4 rad.
    """
    R, e0 = 3.0, 0.3
    sc = two_balls(R, e0=e0, duration=2 * math.pi * 1e5 / R, sample_rate=0.05)
    tr = simulate(sc)
    check_outcome(tr)
    assert tr.success, tr.stats.message
    # the last sample is within one sample interval (20 s = 9.5 revolutions) of the end
    assert tr.rotor_angle[-1] == pytest.approx(R * tr.t[-1], rel=1e-14)
    assert 1e5 - 10 < tr.rotor_angle[-1] / (2 * math.pi) <= 1e5
    assert abs(tr.residual_unbalance()[-1]) < 1e-6 * sc.balancer.capacity
    assert tr.whirl_radius()[-1] < 1e-6 * sc.length_scale
    expected = math.pi - math.acos(e0)
    got = np.sort(tr.relative_angle[-1])
    np.testing.assert_allclose(got, [-expected, expected], atol=1e-4)


# ---------------------------------------------------------------- diverging / non-physical
def negative_damping_scene(balancer=None, **run):
    """Supports with damping -50 N s/m (the scene-file reader rejects it): z'' - 50 z' + z = ...
    grows like e^{50 t} and overflows near t = 708/50 ~ 14 s."""
    run.setdefault("duration", 100.0)
    run.setdefault("sample_rate", 10.0)
    return Scene(rotor=Rotor(mass=1.0, eccentricity=0.004),
                 supports=Supports(1.0, 1.0, damping_x=-50.0, damping_y=-50.0),
                 balancer=balancer or Balancer(), drive=constant_speed(3.0),
                 run=RunSettings(**run))


def two_small_balls():
    m = 0.005
    return Balancer(type="balls", mass=np.full(2, m), radius=np.ones(2), drag=np.full(2, 0.02),
                    inertia=np.full(2, m), initial_angles=np.array([0.3, 2.2]),
                    initial_speeds=np.zeros(2))


def assert_stopped_on_divergence(tr):
    check_outcome(tr)
    st = tr.stats
    assert not st.success
    assert st.status < 0
    msg = st.message.lower()
    assert "non-finite" in msg or "step size" in msg or "diverged" in msg, st.message
    assert len(tr.t) < 1001  # stopped early (the run asked for 1001 samples)


def test_diverging_scene_stops_with_message():
    t0 = time.perf_counter()
    tr = simulate(negative_damping_scene())
    assert time.perf_counter() - t0 < 10.0
    assert_stopped_on_divergence(tr)
    assert tr.stats.method == "DOP853"
    assert tr.t[-1] < 15.0  # overflow of e^{50 t} at t ~ 14 s


def test_diverging_scene_with_weights_stops_promptly():
    tr = simulate(negative_damping_scene(two_small_balls(), max_steps=200_000))
    assert_stopped_on_divergence(tr)


@pytest.mark.parametrize("method", ["numpy-DOP853", "Radau", "BDF", "LSODA"])
def test_diverging_scene_scipy_methods(method):
    tr = simulate(negative_damping_scene(duration=20.0), method=method)
    assert_stopped_on_divergence(tr)


# ---------------------------------------------------------------- step budget
def test_tiny_step_budget_stops_with_message():
    sc = two_balls(3.0, duration=100.0, sample_rate=10.0, max_steps=100)
    tr = simulate(sc)
    check_outcome(tr)
    assert not tr.success
    assert tr.stats.status < 0
    assert "run.max_steps" in tr.stats.message
    assert tr.stats.n_steps + tr.stats.n_rejected <= 100
    assert len(tr.t) < 1001


@pytest.mark.parametrize("method", ["Radau", "BDF", "LSODA", "numpy-DOP853"])
def test_tiny_step_budget_scipy_methods(method):
    # 100 s at R = 3 needs several hundred steps whatever the method
    sc = two_balls(3.0, duration=100.0, sample_rate=10.0, max_steps=100)
    tr = simulate(sc, method=method)
    check_outcome(tr)
    assert not tr.success
    assert "run.max_steps" in tr.stats.message
