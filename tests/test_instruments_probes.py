"""Photo-gate counter, keyphasor, tachometer, displacement probes, and the
timing layer they share (issue 4, items 3 and 4; monograph 4.3.2 item 2.3).

Oracles: the damped period 2 pi / (omega_1 sqrt(1 - zeta^2)) of the free
decay; the analytic rotor angle of a constant-speed and a constant-acceleration
programme; the configured noise, runout and quantisation of the probes
(tolerances from the sample count).
"""
import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

from stand.instruments.photogate import (PhotoGate, damped_period, gate_crossings,
                                         natural_frequency_test, pulse_counter_period)
from stand.instruments.probes import (DisplacementProbes, Keyphasor, Tachometer,
                                      keyphasor_pulses, probe_signals, tachometer_readings)
from stand.instruments.timing import (MeasurementError, crossing_times, hermite,
                                      sample_trajectory, shaft_velocity)
from stand.scene.model import SceneError, SpeedDrive
from stand.scene.parse import Table, load_scene
from stand.integrate.simulate import simulate

SCENES = Path(__file__).resolve().parents[1] / "data_samples" / "scenes"
TWO_PI = 2 * math.pi


@pytest.fixture(scope="module")
def scene():
    return load_scene(SCENES / "ball_runup.toml")


@pytest.fixture(scope="module")
def runup(scene):
    return simulate(scene)


@pytest.fixture(scope="module")
def constant_speed(scene):
    """15 rev/s from t = 0 (phi = omega t), 3 s."""
    sc = dataclasses.replace(scene, drive=SpeedDrive(programme=np.array([[0.0, 15.0 * TWO_PI]])),
                             run=dataclasses.replace(scene.run, duration=3.0))
    return simulate(sc)


# ---------------------------------------------------------------- timing layer
def test_hermite_error_bound():
    """A (2 pi/N)^4 / 384 for A sin at N samples per period (module docstring)."""
    for N in (20, 40):
        t = np.arange(0, 5 * N + 1) / N           # period 1 s, N samples per period
        y, dy = np.sin(TWO_PI * t), TWO_PI * np.cos(TWO_PI * t)
        tq = np.linspace(0, 5, 20001)
        err = np.max(np.abs(hermite(t, y, dy, tq) - np.sin(TWO_PI * tq)))
        bound = (TWO_PI / N) ** 4 / 384
        assert err <= bound and err > 0.5 * bound
    with pytest.raises(ValueError, match="no extrapolation"):
        hermite(t, y, dy, [6.0])


def test_crossing_times_of_a_rippled_angle():
    t = np.linspace(0.0, 10.0, 401)
    ang = 0.3 + 7.3 * t + 0.2 * np.sin(2 * t)
    spd = 7.3 + 0.4 * np.cos(2 * t)
    tc = crossing_times(t, ang, spd, 1.0)
    from scipy.optimize import brentq
    exact = [brentq(lambda x: 0.3 + 7.3 * x + 0.2 * np.sin(2 * x) - 1.0 - TWO_PI * k, 0, 10)
             for k in range(tc.size)]
    assert tc.size == 12
    assert np.max(np.abs(tc - exact)) < 1e-9
    # backwards-running: direction -1 finds the same levels on the reversed signal
    tb = crossing_times(t, -ang, -spd, -1.0, direction=-1)
    assert np.allclose(tb, tc, atol=1e-12)
    assert crossing_times(t, -ang, -spd, -1.0, direction=1).size == 0


def test_shaft_velocity_scale(scene, runup):
    """The velocities from the dimensionless state make the Hermite interpolant
    agree with a run sampled at the midpoints (a wrong scale would not)."""
    fine = simulate(dataclasses.replace(scene, run=dataclasses.replace(scene.run,
                                                                      sample_rate=400.0)))
    vx, vy = shaft_velocity(runup)
    assert np.allclose(vx, shaft_velocity(fine)[0][::2], rtol=1e-6, atol=1e-9)
    mid = fine.t[1::2][:-1]
    s = sample_trajectory(runup, mid)
    A = np.max(np.hypot(runup.x, runup.y))
    # 200 Hz at 15 rev/s = 13.3 samples per whirl period: A (2 pi / 13.3)^4 / 384 = 1.3e-4 A
    err = np.max(np.abs(s.x - fine.x[1::2][:-1]))
    assert err < 1.5e-4 * A
    assert np.max(np.abs(s.y - fine.y[1::2][:-1])) < 1.5e-4 * A
    s_wrong = hermite(runup.t, runup.x, 2 * vx, mid)
    assert np.max(np.abs(s_wrong - fine.x[1::2][:-1])) > 30 * err


# ---------------------------------------------------------------- photo-gate
def test_photogate_period_is_the_damped_period(scene):
    """FPM-09 method, leading-edge trigger, 0.5 mm detector, 20 mm deflection:
    the damped period of the free decay within 0.1 %."""
    r = natural_frequency_test(scene, 0.02, PhotoGate())
    zeta = scene.supports.damping_x / (2 * math.sqrt(scene.supports.stiffness_x * scene.total_mass))
    w1 = scene.natural_frequency
    T = TWO_PI / (w1 * math.sqrt(1 - zeta ** 2))
    assert r.true_period == pytest.approx(T, rel=1e-14)
    assert zeta == pytest.approx(0.05, rel=1e-4)          # H = 0.1
    assert abs(r.period / T - 1) < 1e-3
    assert r.frequency == pytest.approx(1 / T, rel=1e-3)
    # the counted period is short by the documented leading-edge bias
    assert r.relative_error == pytest.approx(r.bias_estimate, rel=0.05)
    assert r.relative_error < 0
    # the universal stand: f0 = 3 Hz undamped
    assert r.undamped_frequency == pytest.approx(3.0, rel=1e-3)


def test_photogate_centre_trigger_is_exact(scene):
    for axis in ("x", "y", "radial"):
        gate = PhotoGate(trigger="centre", axis=axis, direction=math.radians(30))
        r = natural_frequency_test(scene, -0.01, gate)
        assert abs(r.relative_error) < 1e-8
        assert r.pulses.size >= 3


def test_photogate_weights_options(scene):
    locked = natural_frequency_test(scene, 0.02, PhotoGate(trigger="centre"))
    removed = natural_frequency_test(scene, 0.02, PhotoGate(trigger="centre"), weights="removed")
    assert removed.true_period == pytest.approx(
        damped_period(scene.supports.stiffness_x, scene.supports.damping_x, scene.rotor.mass))
    assert abs(removed.relative_error) < 1e-8
    assert removed.period < locked.period                 # lighter: faster
    free = natural_frequency_test(scene, 0.02, PhotoGate(trigger="centre"), weights="free")
    assert abs(free.relative_error) < 0.02                # balls move: near, not exact


def test_pulse_counter_needs_three_pulses():
    assert pulse_counter_period([0.1, 0.3, 0.5, 0.7]) == pytest.approx(0.4)
    with pytest.raises(MeasurementError, match="needs 3"):
        pulse_counter_period([0.1, 0.3])


def test_gate_crossings_enter_and_centre():
    t = np.linspace(0, 2, 2001)
    X, dX = 0.01 * np.cos(TWO_PI * t), -0.01 * TWO_PI * np.sin(TWO_PI * t)
    g = PhotoGate(size=0.002)
    enter = gate_crossings(t, X, dX, g)
    centre = gate_crossings(t, X, dX, dataclasses.replace(g, trigger="centre"))
    assert np.allclose(centre, [0.25, 0.75, 1.25, 1.75], atol=1e-9)
    shift = math.asin(0.1) / TWO_PI                        # X = +-1 mm before the centre
    assert np.allclose(enter, centre - shift, atol=1e-9)


def test_photogate_bad_inputs(scene):
    with pytest.raises(SceneError, match="inside the detector"):
        natural_frequency_test(scene, 1e-4, PhotoGate(size=1e-3))
    with pytest.raises(SceneError, match="deflection = 0"):
        natural_frequency_test(scene, 0.0)
    heavy = dataclasses.replace(scene, supports=dataclasses.replace(scene.supports,
                                                                    damping_x=1e4, damping_y=1e4))
    with pytest.raises(SceneError, match="zeta"):
        natural_frequency_test(heavy, 0.01)
    for data, key in (({"size": 0.0}, "size"), ({"axis": "z"}, "axis"),
                      ({"trigger": "edge"}, "trigger"), ({"stop_pass": 1}, "stop_pass"),
                      ({"sise": 1e-3}, "sise")):
        with pytest.raises(SceneError, match=rf"instruments\.photogate\.{key}"):
            PhotoGate.from_table(Table(data, "instruments.photogate"))


# ---------------------------------------------------------------- keyphasor
def test_keyphasor_constant_speed_analytic(constant_speed):
    mark = math.radians(40.0)
    kp = Keyphasor(mark_angle=mark)
    tp = keyphasor_pulses(constant_speed, kp)
    w = 15.0 * TWO_PI
    exact = (mark + TWO_PI * np.arange(tp.size)) / w
    assert tp.size == 45                                  # 3 s at 15 rev/s
    assert np.max(np.abs(tp - exact)) < 1e-9
    assert np.allclose(np.diff(tp), 1 / 15.0, atol=1e-12)  # once per revolution


def test_keyphasor_during_run_up_analytic(runup):
    """phi = a t^2 / 2 with a = 1.5 rev/s^2 until t = 10 s."""
    mark = 1.0
    tp = keyphasor_pulses(runup, Keyphasor(mark_angle=mark), 0.0, 9.9)
    a = 1.5 * TWO_PI
    exact = np.sqrt(2 * (mark + TWO_PI * np.arange(tp.size)) / a)
    assert tp.size == int((0.5 * a * 9.9 ** 2 - mark) // TWO_PI) + 1
    assert np.max(np.abs(tp - exact)) < 1e-9


def test_keyphasor_jitter(constant_speed):
    clean = keyphasor_pulses(constant_speed, Keyphasor(mark_angle=0.5))
    noisy = keyphasor_pulses(constant_speed, Keyphasor(mark_angle=0.5, jitter=1e-5, seed=3))
    d = noisy - clean
    assert 0.5e-5 < np.std(d) < 2e-5


# ---------------------------------------------------------------- tachometer
@pytest.mark.parametrize("tach", [Tachometer(), Tachometer(gate_time=0.2, pulses_per_rev=1,
                                                           resolution=0.0, update_interval=0.1)])
def test_tachometer_reads_the_speed_within_its_resolution(runup, constant_speed, tach):
    r = tachometer_readings(constant_speed, tach)
    assert r["time"].size >= 2
    assert np.all(np.abs(r["speed"] - 15.0 * TWO_PI) <= tach.accuracy + 1e-9)
    # any motion: the reading is the mean speed over the gate within one count
    # plus half the display step
    r = tachometer_readings(runup, tach)
    assert r["time"].size >= 30
    assert np.all(np.abs(r["speed"] - r["true_speed"]) <= tach.accuracy + 1e-9)
    assert r["true_speed_at_time"][-1] == pytest.approx(15.0 * TWO_PI, rel=1e-9)


def test_tachometer_default_is_one_rpm():
    t = Tachometer()
    assert t.count_resolution == pytest.approx(TWO_PI / 60)   # 60 pulses/rev, 1 s: 1 rpm
    t2 = Tachometer.from_table(Table({"resolution": 0.5, "gate_time": 2.0}, "instruments.tachometer"))
    assert t2.resolution == pytest.approx(0.5 * TWO_PI)
    with pytest.raises(SceneError, match=r"instruments\.tachometer\.gate_time"):
        Tachometer.from_table(Table({"gate_time": -1.0}, "instruments.tachometer"))


# ---------------------------------------------------------------- probes
def test_probe_noise_runout_and_lsb(runup):
    """Noise rms, runout amplitudes/phases and quantisation as configured;
    tolerances: 5 standard errors for M samples."""
    probes = DisplacementProbes(sample_rate=200.0, noise_rms=2e-6, runout=(3e-6, 1e-6),
                                runout_phase=(0.4, -1.0), lsb=1e-9,
                                angles=(0.0, math.pi / 2))
    s = probe_signals(runup, probes, seed=7)
    M = s["time"].size
    assert M == 8001 and s["signal"].shape == (M, 2)
    # the probes see the shaft: x and y
    assert np.allclose(s["displacement"][:, 0], runup.x, atol=1e-12)
    assert np.allclose(s["displacement"][:, 1], runup.y, atol=1e-12)
    resid = s["signal"] - s["displacement"]
    # noise: rms of what remains after removing the runout harmonics (fit)
    phi = s["rotor_angle"]
    for i, a in enumerate(probes.angles):
        psi = a - phi
        basis = np.column_stack([np.cos(psi), np.sin(psi), np.cos(2 * psi), np.sin(2 * psi)])
        coef, *_ = np.linalg.lstsq(basis, resid[:, i], rcond=None)
        se = probes.noise_rms * math.sqrt(2 / M)          # standard error of one amplitude
        A1, p1 = math.hypot(coef[0], coef[1]), math.atan2(-coef[1], coef[0])
        A2, p2 = math.hypot(coef[2], coef[3]), math.atan2(-coef[3], coef[2])
        assert A1 == pytest.approx(3e-6, abs=5 * se)
        assert A2 == pytest.approx(1e-6, abs=5 * se)
        assert p1 == pytest.approx(0.4, abs=5 * se / 3e-6)
        assert p2 == pytest.approx(-1.0, abs=5 * se / 1e-6)
        noise = resid[:, i] - basis @ coef
        assert np.std(noise) == pytest.approx(2e-6, rel=5 / math.sqrt(2 * M))
    # LSB: every value on the grid; with noise spanning several LSB the
    # quantisation error is uniform in +-lsb/2 (std lsb / sqrt(12))
    q = DisplacementProbes(sample_rate=200.0, noise_rms=3e-6, runout=(1e-6,), lsb=1e-6)
    s = probe_signals(runup, q)
    assert np.allclose(s["signal"] / 1e-6, np.rint(s["signal"] / 1e-6), atol=1e-6)
    e = s["signal"] - (s["displacement"] + s["runout"] + s["noise"])
    assert np.max(np.abs(e)) <= 0.5e-6 * (1 + 1e-9)
    M = e.size
    assert np.std(e) == pytest.approx(1e-6 / math.sqrt(12), rel=5 / math.sqrt(1.8 * M))


def test_probe_settings(runup, scene):
    with pytest.raises(SceneError, match=r"instruments\.probes\.sample_rate"):
        probe_signals(runup, DisplacementProbes(sample_rate=1000.0))
    with pytest.raises(SceneError, match=r"instruments\.probes\.sample_rate"):
        DisplacementProbes(sample_rate=1000.0).check_against_run(scene.run)
    p = DisplacementProbes.from_table(Table({"runout": 5e-6, "angles": [45.0, 135.0],
                                             "lsb": 0.0}, "instruments.probes"))
    assert p.runout == (5e-6,) and p.angles == pytest.approx((math.pi / 4, 3 * math.pi / 4))
    for data, key in (({"noise_rms": -1.0}, "noise_rms"), ({"runout": [1e-6, -1e-6]}, r"runout\[1\]"),
                      ({"runout": [1e-6], "runout_phase": [0.0, 1.0]}, "runout_phase"),
                      ({"angles": "x"}, "angles"), ({"seed": -1}, "seed")):
        with pytest.raises(SceneError, match=rf"instruments\.probes\.{key}"):
            DisplacementProbes.from_table(Table(data, "instruments.probes"))
    with pytest.raises(SceneError, match=r"instruments\.keyphasor\.jitter"):
        Keyphasor.from_table(Table({"jitter": -1.0}, "instruments.keyphasor"))


def test_instruments_from_a_scene_file():
    text = (SCENES / "ball_runup.toml").read_text() + """
[instruments.keyphasor]
mark_angle = 90.0
[instruments.tachometer]
gate_time = 0.5
[instruments.photogate]
size = 0.001
[instruments.probes]
sample_rate = 100.0
"""
    sc = load_scene(text)
    assert sc.instruments["keyphasor"].mark_angle == pytest.approx(math.pi / 2)
    assert sc.instruments["tachometer"].gate_time == 0.5
    assert sc.instruments["photogate"].size == 0.001
    assert sc.instruments["probes"].sample_rate == 100.0
    with pytest.raises(SceneError, match=r"instruments\.probes\.sample_rate"):
        load_scene(text.replace("sample_rate = 100.0", "sample_rate = 1000.0"))


def test_probe_daq_artefacts(constant_speed):
    """The DAQ's artefacts as the scene declares them (issue 42), each against what it is:
    hum lines of their amplitude, a linear drift, the anti-alias filter as scipy's lsim of
    the analog Butterworth on the same samples, the channel skew as the 1X phase a linear
    interpolation 1 ms later gives, clipping at the ADC range."""
    from scipy import signal

    base = dict(sample_rate=200.0, noise_rms=0.0, runout=(0.0,), lsb=0.0)
    clean = probe_signals(constant_speed, DisplacementProbes(**base))
    t, s0 = clean["time"], clean["signal"]
    k = t > 1.0                       # 2 s: whole periods of 15, 20 and 60 Hz

    def line(v, f):                   # complex amplitude of a line at f [Hz] over k
        return 2 * np.mean(v[k] * np.exp(-1j * TWO_PI * f * t[k]))

    s = probe_signals(constant_speed, DisplacementProbes(**base, hum=(15e-6, 0.0, 5e-6),
                                                         hum_frequency=20.0, drift=2e-6))["signal"] - s0
    for i in range(2):
        d = s[:, i] - 2e-6 * (t - t[0])
        assert np.max(np.abs(d - 15e-6 * np.sin(TWO_PI * 20 * t) - 5e-6 * np.sin(TWO_PI * 60 * t))) < 1e-15
        assert abs(line(d, 20.0)) == pytest.approx(15e-6, rel=1e-9)
    sf = probe_signals(constant_speed, DisplacementProbes(**base, filter="butterworth",
                                                          filter_cutoff=40.0))["signal"]
    ba = signal.butter(4, TWO_PI * 40.0, analog=True)
    for i in range(2):
        ref = s0[0, i] + signal.lsim(ba, s0[:, i] - s0[0, i], t)[1]
        assert np.max(np.abs(sf[:, i] - ref)) < 1e-9 * np.max(np.abs(s0))
    sk = probe_signals(constant_speed, DisplacementProbes(**base, skew=1e-3))["signal"]
    # probe 1 sampled 1 ms (0.2 of a sample interval) later: between its samples, linearly
    assert np.allclose(sk[:-1, 1], 0.8 * s0[:-1, 1] + 0.2 * s0[1:, 1], rtol=0, atol=1e-9 * np.max(np.abs(s0)))
    assert np.array_equal(sk[:, 0], s0[:, 0])
    r = 0.8 * np.max(np.abs(s0))
    sc = probe_signals(constant_speed, DisplacementProbes(**base, adc_range=r))["signal"]
    assert np.array_equal(sc, np.clip(s0, -r, r)) and np.max(np.abs(sc)) == pytest.approx(r)
