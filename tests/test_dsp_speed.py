"""dsp.speed (pulses -> rotor angle, programme detection) and dsp.response_fit (run-up model fit).

Reference signals are exact: a rotor angle with constant angular acceleration, and the
rigid-rotor response to it solved exactly in its modes (tests/oracles/runup_exact.py).  Tolerances
come from the sample interval (pulse timing), the noise (the fit's standard uncertainty)
or the discretisation of the model (first-order hold, error ~ (omega dt)^2 / 12).
"""
import functools
import math

import numpy as np
import pytest

from dsp.errors import SignalError
from dsp.response_fit import fit_response_without_speed, fit_unbalance_response
from dsp.speed import (angle_from_1x, angle_from_pulses, angle_from_speed, otsu_threshold,
                       pulse_times, repair_pulses, speed_programme)
from dsp.pulse_timing import retime_pulses
from oracles.runup_exact import forced_response

TWO_PI = 2 * math.pi


def _pulse_train(t, phi, width_deg=20.0, high=5.0, low=0.2, invert=False):
    th = np.degrees(np.mod(phi, TWO_PI))
    v = np.where(th < width_deg, high, low)
    return (high + low - v) if invert else v


@pytest.mark.parametrize("invert", [False, True])
@pytest.mark.parametrize("width_deg", [3.0, 20.0, 300.0])
def test_pulse_times_any_duty_cycle_and_polarity(invert, width_deg):
    fs = 20000.0
    t = np.arange(0, 2.0, 1 / fs)
    w = TWO_PI * 10.0
    phi = w * t + 0.1
    v = _pulse_train(t, phi, width_deg, invert=invert) + np.random.default_rng(1).normal(0, 0.05, t.size)
    p = pulse_times(t, v)
    # leading edge of the pulse: the minority state's start
    lead = 0.0 if width_deg < 180 else width_deg
    k = np.arange(p.size)
    first = (TWO_PI * math.ceil((0.1 - math.radians(lead)) / TWO_PI) + math.radians(lead) - 0.1) / w
    if first < t[0] + 1 / fs:
        first += 1 / 10.0
    truth = first + k / 10.0
    # a sampled step: the crossing lies within one sample interval of the true edge
    assert p.size == pytest.approx(20, abs=1)
    assert np.max(np.abs(p - truth[:p.size])) <= 1.0 / fs


def test_otsu_separates_a_one_percent_duty_cycle():
    v = np.r_[np.zeros(990), np.full(10, 5.0)]
    assert 0 < otsu_threshold(v) < 5


def test_repair_fills_missed_and_drops_double_pulses():
    p = np.arange(40) * 0.1
    missed = np.delete(p, [10, 25, 26])
    out, added, dropped = repair_pulses(missed)
    assert added == 3 and dropped == 0 and np.allclose(out, p)
    double = np.sort(np.r_[p, 1.0005])
    out, added, dropped = repair_pulses(double)
    assert dropped == 1 and out.size == p.size


def test_angle_from_pulses_of_a_constant_acceleration():
    """phi = w0 t + a t^2 / 2: pulses at phi = 2 pi k; a cubic spline reproduces the quadratic."""
    w0, a = TWO_PI * 2.0, TWO_PI * 1.0
    k = np.arange(1, 200)
    p = (-w0 + np.sqrt(w0 ** 2 + 2 * a * TWO_PI * k)) / a
    t = np.linspace(p[0], p[-1], 20001)
    for knots in (0.0, 8.0):
        ra = angle_from_pulses(t, p, knot_revolutions=knots)
        phi = w0 * t + 0.5 * a * t * t - TWO_PI
        assert np.max(np.abs(ra.angle_rad - phi)) < 1e-6
        assert np.max(np.abs(ra.speed_rad_s - (w0 + a * t))) < 1e-4
        assert ra.referenced and ra.covered.all()


@pytest.mark.parametrize("rate_hz_s", [6.0, -6.0])
def test_retimed_edges_of_a_ramp_keyphasor_on_a_changing_speed(rate_hz_s):
    """A keyphasor edge linear in the rotor angle (a ramp 90 deg wide, its 50 % level at the
    mark), 10 samples per revolution at the top speed, 6 rev/s^2: interpolated linearly in
    time, each edge is off by about (phi'' / phi') dt^2 / 8 (here up to ~2e-5 rad of angle);
    interpolated in the angle of the spline through the pulses, to the rounding floor."""
    f_top = 40.0
    f_start = 5.0 if rate_hz_s > 0 else f_top
    duration = abs(f_top - 5.0 / 1.0) / abs(rate_hz_s)
    fs = 10 * f_top
    t = np.arange(0.0, duration, 1 / fs)
    phi = TWO_PI * (f_start * t + 0.5 * rate_hz_s * t * t)
    u = np.mod(phi + math.pi, TWO_PI) - math.pi
    ramp = math.pi / 2
    v = 5.0 * np.minimum(np.clip((u + ramp / 2) / ramp, 0, 1),
                         np.clip((3 * math.pi / 4 + ramp / 2 - u) / ramp, 0, 1))
    p = pulse_times(t, v)
    k = np.round(TWO_PI * (f_start * p + 0.5 * rate_hz_s * p * p) / TWO_PI)
    # the truth: phi(p) = 2 pi k, solved for p
    a, b = 0.5 * rate_hz_s, f_start
    truth = (-b + np.sqrt(b * b + 4 * a * k)) / (2 * a)

    def angle_error(q):
        return np.max(np.abs(TWO_PI * (f_start * q + 0.5 * rate_hz_s * q * q) - TWO_PI * k))

    assert angle_error(p) > 1e-6                      # linear in time: visibly late/early
    q = retime_pulses(t, v, p)
    assert angle_error(q) < 1e-10
    assert np.max(np.abs(q - truth)) < 1e-12
    # a pulse with no crossing between its samples (one repair_pulses inserted) keeps its time
    r = retime_pulses(t, v, np.r_[p[:5], 0.5 * (p[5] + p[6]) + 0.3 / fs, p[6:]][: p.size])
    assert r[5] == pytest.approx(0.5 * (p[5] + p[6]) + 0.3 / fs, abs=0)


def test_angle_from_a_held_tachometer_reading():
    t = np.arange(0, 10, 1e-3)
    w = TWO_PI * (5 + t)                                 # 1 rev/s^2
    gate = 0.5
    held = np.array([TWO_PI * (5 + (math.floor(x / gate) * gate) - gate / 2) if x >= gate
                     else TWO_PI * 5 for x in t])       # the mean over the previous gate
    ra = angle_from_speed(t, held)
    assert not ra.referenced
    sel = (t > 1) & (t < 9)
    # the held steps replaced by a line through their middles: within the gate's jitter
    assert np.max(np.abs(ra.speed_rad_s[sel] - w[sel])) < TWO_PI * 0.3


@pytest.mark.parametrize("kind,speeds", [
    ("run-up + constant", lambda t: np.minimum(2 + 2 * t, 12.0)),
    ("constant + run-down", lambda t: np.where(t < 5, 12.0, 12.0 - (t - 5))),
    ("coast-down", lambda t: 12.0 * np.exp(-t / 4.0)),
    ("constant", lambda t: np.full_like(t, 12.0)),
])
def test_speed_programme(kind, speeds):
    t = np.arange(0, 10, 1e-3)
    prog = speed_programme(t, TWO_PI * speeds(t))
    assert prog.kind == kind, [(s.kind, s.t_start_s, s.t_end_s) for s in prog.stretches]


# ------------------------------------------------------------------ the model fit
F0, ZETA, E, BETA = 12.0, 0.04, 40e-6, math.radians(30.0)


@functools.lru_cache(maxsize=None)
def _exact(fs, T, w_start, alpha):
    """Exact response of z'' + 2 zeta w0 z' + w0^2 z = e (phi'^2 - i phi'') e^{i(phi + beta)}
    (in its modes, :func:`oracles.runup_exact.forced_response`: to ~1e-11, as scipy's DOP853
    at rtol 1e-11 that it replaced, in milliseconds)."""
    t = np.arange(0, T, 1 / fs)

    def force(tt):
        ph = w_start * tt + 0.5 * alpha * tt * tt
        w = w_start + alpha * tt
        return E * (w * w - 1j * alpha) * np.exp(1j * (ph + BETA))

    return t, forced_response(t, force, TWO_PI * F0, ZETA)[0]


def _runup_record(fs=1000.0, T=24.0, w_start=TWO_PI * 2, alpha=TWO_PI * 1.0, noise=0.0, seed=0,
                  offset=0j, runout=0j):
    """The exact response (:func:`_exact`) with an offset, a runout and white noise [m]."""
    t, z = _exact(fs, T, w_start, alpha)
    phi = w_start * t + 0.5 * alpha * t * t
    rng = np.random.default_rng(seed)
    z = z + offset + runout * np.exp(1j * phi) + noise * (rng.normal(size=t.size)
                                                          + 1j * rng.normal(size=t.size))
    return t, z, phi, w_start + alpha * t, np.full(t.size, alpha)


def test_fit_recovers_the_model_exactly_without_noise():
    t, z, phi, w, a = _runup_record(offset=3e-5 - 2e-5j, runout=2e-6 + 1e-6j)
    r = fit_unbalance_response(t, z, phi, w, a)
    # first-order-hold discretisation: relative error ~ (omega dt)^2 / 12 at 26 rev/s, 1 kHz
    tol = (TWO_PI * 26 / 1000) ** 2 / 12
    assert r.natural_frequency_hz == pytest.approx(F0, rel=tol)
    assert r.damping_ratio == pytest.approx(ZETA, rel=20 * tol)
    assert r.specific_unbalance_m == pytest.approx(E, rel=tol)
    assert r.angle_rad == pytest.approx(BETA, abs=tol)
    # the linear terms absorb the discretisation error of the ~50 um response
    assert r.offset_m == pytest.approx(3e-5 - 2e-5j, abs=2 * tol * E)
    assert r.runout_m == pytest.approx(2e-6 + 1e-6j, abs=2 * tol * E)
    assert r.critical_speed_hz == pytest.approx(F0 / math.sqrt(1 - 2 * ZETA ** 2), rel=tol)


def test_fit_uncertainty_matches_the_scatter_over_noise_seeds():
    """The stated standard uncertainty of f0 is the scatter of the estimates (within the
    chi-square spread of 8 seeds: a factor 0.5-2)."""
    est, sds = [], []
    for seed in range(8):
        # 400 samples/s (25 per revolution at the top speed), 6 -> 16 rev/s through 12 Hz in
        # 10 s (2 -> 18 rev/s in 16 s before): the std and the scatter both grow as
        # 1 / sqrt(samples), their ratio is what is checked (1.09 here, 1.16 before)
        t, z, phi, w, a = _runup_record(fs=400.0, noise=3e-6, seed=seed, T=10.0,
                                        w_start=TWO_PI * 6)
        r = fit_unbalance_response(t, z, phi, w, a)
        est.append(r.natural_frequency_hz)
        sds.append(r.natural_frequency_hz_std)
    scatter = np.std(est, ddof=1)
    assert 0.4 < scatter / np.mean(sds) < 2.5
    assert abs(np.mean(est) - F0) < 4 * np.mean(sds) / math.sqrt(8) + 1e-4 * F0


def test_fit_without_speed_gets_the_magnitude():
    # 400 samples/s (22 per revolution at the top speed), 6 -> 18 rev/s in 12 s (2 -> 26 in
    # 24 s before): the errors (1.1e-4 of U, 8e-6 of f0; before 1.6e-4 and 3e-5, at 1 kHz
    # 1.5e-5 and 2e-6) stay far inside the bounds
    t, z, phi, w, a = _runup_record(fs=400.0, noise=1e-6, offset=2e-5, w_start=TWO_PI * 6,
                                    T=12.0)
    r, ra = fit_response_without_speed(t, z)
    assert ra.estimated and not ra.referenced
    assert math.isnan(r.angle_rad)
    assert r.specific_unbalance_m == pytest.approx(E, rel=0.01)
    assert r.natural_frequency_hz == pytest.approx(F0, rel=0.002)


def test_fit_without_speed_refuses_a_negative_runout_allowance():
    t, z, phi, w, a = _runup_record(noise=1e-6)
    with pytest.raises(SignalError, match="runout_allowance_m = -2e-06 m"):
        fit_response_without_speed(t, z, runout_allowance_m=-2e-6)


def test_fit_refuses_a_record_that_misses_the_resonance():
    t, z, phi, w, a = _runup_record(w_start=TWO_PI * 16, alpha=TWO_PI * 0.5, T=12.0)
    with pytest.raises(SignalError, match="does not pass the resonance|outside the record"):
        fit_unbalance_response(t, z, phi, w, a, natural_frequency_guess_hz=17.0)


def test_angle_from_1x_follows_a_forward_whirl():
    t = np.arange(0, 5, 1e-3)
    phi = TWO_PI * (10 * t + 0.5 * t * t)
    z = 1e-4 * np.exp(1j * (phi + 0.7))
    ra = angle_from_1x(t, z)
    assert np.max(np.abs(ra.speed_rad_s - TWO_PI * (10 + t))) < 1e-3


def test_run_down_through_the_resonance():
    """A run-down (18 -> 5 rev/s at -1 rev/s^2): the fit and the sweep-corrected peak (lag
    below f0 on a run-down) give f0 and the critical speed back."""
    from dsp.speed import RotorAngle
    from stand.analysis.runup import sweep_identification

    # 400 samples/s (22 per revolution at 18 rev/s), 18 -> 5 rev/s in 13 s (26 -> 3 in 23 s
    # before): the errors (2.9e-3 of fc, 1e-5 of f0, 3e-5 of e; before 2.8e-3, 4e-6, 1e-4,
    # those at 1 kHz) inside the bounds; fc's is the sweep-rate lag correction's, the same
    # rate, the same error
    t, z, phi, w, a = _runup_record(fs=400.0, w_start=TWO_PI * 18, alpha=-TWO_PI * 1.0, T=13.0,
                                    noise=1e-6)
    ra = RotorAngle(phi, w, a, np.ones(t.size, bool), "angle", referenced=True)
    notes = []
    out = sweep_identification(t, z.real, z.imag, ra, notes)
    assert out["programme"]["kind"] == "run-down", out["programme"]
    assert out["resonance"]["direction"] == "run-down"
    fc = F0 / math.sqrt(1 - 2 * ZETA ** 2)
    assert out["resonance"]["critical_speed_hz"] == pytest.approx(fc, rel=0.005)
    assert out["model_fit"]["natural_frequency_hz"] == pytest.approx(F0, rel=1e-3)
    assert out["model_fit"]["specific_unbalance_m"] == pytest.approx(E, rel=5e-3)
