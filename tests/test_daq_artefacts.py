"""A DAQ's artefacts on a run-up record written independently of the simulator (the rigid
rotor's equation through scipy.signal.lsim), each with what the analysis must do about it
(issue 42): a declared filter is fitted through, an undeclared one is found as a delay and
named, clipped samples are censored, hum and drift leave the fit within its ±."""
import functools
import math

import numpy as np
import pytest
from scipy import signal

from dsp.artefacts import ChannelFilter, clipped, delay_allowance, filled
from dsp.response_fit import fit_unbalance_response
from stand.analysis.runup import sweep_identification

F0, ZETA, E, BETA = 8.0, 0.04, 40e-6, math.radians(30.0)   # Hz, -, m, rad
FS, T = 250.0, 4.5                                            # Hz, s
#: the undeclared sensor responses' record [s] (3 -> 15 rev/s): their ± ratios below were
#: measured on it.  On the 4.5 s record the resonance and the high-pass act less (a lower top
#: speed): the freed fit's std ratios are 16 x and 220 x (3.2 x, 77 x on 6 s) and 4.4 x, the
#: bounds 2.5 x, 20 x, 3 x would no longer tell the cut freedom they are there for
T_SENSOR = 6.0
K = 3.0      # |value - truth| <= K std (the issue-30 standard: |z| < 2 in >= 85 %; 3 for one draw)


def _record(seed=1, noise=1.5e-6, start_hz=3.0, duration=T):
    """:func:`_simulated_record`, computed once per argument (0.3 s) and copied."""
    return tuple(v.copy() for v in _simulated_record(seed, noise, start_hz, duration))


@functools.lru_cache(maxsize=None)
def _simulated_record(seed, noise, start_hz=3.0, duration=T):
    """A run-up ``start_hz`` -> + 2 ``duration`` rev/s at 2 rev/s^2 of the rigid rotor (x'' +
    2 zeta w0 x' + w0^2 x = e (phi'^2 cos(phi + beta) + phi'' sin(phi + beta)), same in y),
    probes' white noise.  The artefacts' record: 3 -> 12 rev/s in 4.5 s through 8 Hz (6 s,
    to 15 rev/s, before: the checks within K std are statistical, any length; the delay's
    bound and the clipped share hold on it as on 6 s)."""
    t = np.arange(0.0, duration, 1.0 / (10 * FS))   # lsim's linear forcing: 10x finer, sampled
    w = 2 * math.pi * (start_hz + 2.0 * t)
    phi = 2 * math.pi * (start_hz * t + t * t)
    a = np.full(t.size, 4 * math.pi)
    f = E * (w * w - 1j * a) * np.exp(1j * (phi + BETA))
    w0 = 2 * math.pi * F0
    sys = ([1.0], [1.0, 2 * ZETA * w0, w0 * w0])
    x0 = E * (w[0] / w0) ** 2 / (1 - (w[0] / w0) ** 2) * np.exp(1j * BETA)   # steady start
    zx = signal.lsim(sys, f.real, t, X0=[0.0, x0.real])[1]
    zy = signal.lsim(sys, f.imag, t, X0=[0.0, x0.imag])[1]
    t, w, phi, a, zx, zy = (v[::10] for v in (t, w, phi, a, zx, zy))
    rng = np.random.default_rng(seed)
    z = zx + 1j * zy + noise * (rng.normal(size=t.size) + 1j * rng.normal(size=t.size))
    return t, z, phi, w, a


class _Angle:          # a referenced rotor angle (the encoder's), as dsp.speed.RotorAngle
    def __init__(self, t, phi, w, a):
        self.angle_rad, self.speed_rad_s, self.acceleration_rad_s2 = phi, w, a
        self.covered, self.referenced, self.estimated = np.ones(t.size, bool), True, False
        self.angle_error, self.source, self.pulses_s = None, "angle", None


def _identify(t, z, phi, w, a, **kw):
    notes = []
    sw = sweep_identification(t, z.real, z.imag, _Angle(t, phi, w, a), notes, **kw)
    return sw["model_fit"], notes


def _within(fit, k=K):
    e_std = fit["specific_unbalance_m_std"]
    assert abs(fit["natural_frequency_hz"] - F0) <= k * fit["natural_frequency_hz_std"], fit
    assert abs(fit["damping_ratio"] - ZETA) <= k * fit["damping_ratio_std"], fit
    assert abs(fit["specific_unbalance_m"] - E) <= k * e_std, fit
    d = (fit["unbalance_angle_deg"] - 30.0 + 180.0) % 360.0 - 180.0
    assert abs(d) <= k * fit["unbalance_angle_deg_std"], fit


def _lowpass(t, z, kind="butterworth", order=4, cutoff=40.0):
    """The analog filter applied exactly to the sampled signal (scipy's lsim)."""
    ba = (signal.butter if kind == "butterworth" else signal.bessel)(
        order, 2 * math.pi * cutoff, analog=True, **({} if kind == "butterworth" else {"norm": "mag"}))
    zi = z - z[0]
    return z[0] + signal.lsim(ba, zi.real, t)[1] + 1j * signal.lsim(ba, zi.imag, t)[1]


def test_clean_record_no_delay_warning():
    fit, notes = _identify(*_record())
    _within(fit)
    assert fit["delay_s"] is None and not any("delay" in n for n in notes)


def test_filter_response_and_twin_match_scipy():
    t, z, *_ = _record()
    f = ChannelFilter("butterworth", 4, 40.0)
    assert np.max(np.abs(f.apply(t, z - z[0]) - (_lowpass(t, z) - z[0]))) < 1e-12 * np.max(abs(z))
    h = f.response(40.0)           # the cutoff: -3 dB, a 4th-order Butterworth's 180 deg lag
    assert abs(h) == pytest.approx(2 ** -0.5, rel=1e-9)
    assert np.angle(h, deg=True) == pytest.approx(-180.0, abs=1e-6) or \
        np.angle(h, deg=True) == pytest.approx(180.0, abs=1e-6)


@pytest.mark.parametrize("kind", ["butterworth", "bessel"])
def test_declared_filter_is_fitted_through(kind):
    t, z, phi, w, a = _record()
    fit, notes = _identify(t, _lowpass(t, z, kind), phi, w, a,
                           channel_filter=ChannelFilter(kind, 4, 40.0))
    _within(fit)
    assert fit["delay_s"] is None


def test_undeclared_filter_is_found_named_and_covered():
    t, z, phi, w, a = _record()
    zf = _lowpass(t, z)
    plain = ChannelFilter("butterworth", 4, 40.0)
    tau0 = -np.angle(plain.response(0.01)) / (2 * math.pi * 0.01)          # its DC group delay
    fit, notes = _identify(t, zf, phi, w, a)
    note = next(n for n in notes if n.startswith("delay:"))
    assert "undeclared anti-alias filter or channel delay" in note and "declare the filter" in note
    assert abs(fit["delay_s"] - tau0) <= K * fit["delay_s_std"] + 0.02 * tau0
    _within(fit)
    # the allowance is what an unknown low-pass with that delay may hide: gain, phase
    loss, dphi = delay_allowance(tau0, 15.0)
    assert 0 < loss < 0.2 and 0 < dphi < math.radians(10)


def test_clipped_samples_censored_not_cut():
    t, z, phi, w, a = _record()
    level = 0.8 * np.max(np.abs(z.real))
    x = np.clip(z.real, -level, level)
    m = clipped(x)
    assert 0.005 < m.mean() < 0.1 and np.all(np.abs(x[m]) == level)
    assert np.array_equal(clipped(x, rail=(-level, level)), m)
    xf = filled(t, x, m)
    assert np.all(np.isfinite(xf)) and np.array_equal(xf[~m], x[~m])
    fit, notes = _identify(t, xf + 1j * z.imag, phi, w, a, censored=m)
    _within(fit)
    assert fit["samples"] == t.size - m.sum()
    assert any("revolutions with clipped samples left out" in n for n in notes)


@pytest.mark.parametrize("artefact", ["hum", "drift"])
def test_hum_and_drift_within_the_std(artefact):
    t, z, phi, w, a = _record()
    if artefact == "hum":    # 50 + 150 Hz, in phase on both channels (a ground loop)
        h = 15e-6 * np.sin(2 * math.pi * 50 * t) + 5e-6 * np.sin(2 * math.pi * 150 * t)
        z = z + h * (1 + 1j)
    else:                    # 3 um/s on x, -2 um/s on y
        z = z + (3e-6 - 2e-6j) * t
    fit, _ = _identify(t, z, phi, w, a)
    _within(fit)


# ---------------------------------------------------------------- undeclared sensor response


def test_undeclared_sensor_resonance_is_found_fitted_through_and_named():
    """A 40 Hz Q 5 mounted resonance, undeclared (gain x1.16, -4.3 deg at 15 rev/s): the
    rotor-only fit's U is 24 std high; freed, the sensor's response lowers chi^2 by hundreds,
    the record is refitted through it: every value within 3 std, one note naming it.  The ±
    keep the unknown resonance's freedom (f_r, Q, with the delay): U's std at least 2.5 x and
    the angle's 20 x those of the same record with the resonance declared (measured 3.2 x and
    77 x; 1.8 x and 11 x when dsp.lsq's unscaled inverse cut that freedom out, and U's z then
    had RMS 1.73 over 8 draws)."""
    t, z, phi, w, a = _record(duration=T_SENSOR)
    flt = ChannelFilter("none", resonance_hz=40.0, resonance_q=5.0)
    fit, notes = _identify(t, flt.apply(t, z), phi, w, a)
    _within(fit)
    known = fit_unbalance_response(t, flt.apply(t, z), phi, w, a, channel_filter=flt)
    assert fit["specific_unbalance_m_std"] >= 2.5 * known.specific_unbalance_m_std
    assert fit["unbalance_angle_deg_std"] >= 20 * math.degrees(known.angle_rad_std)
    (note,) = [n for n in notes if n.startswith(("sensor:", "delay:"))]
    assert note.startswith("sensor:") and "declare the sensor" in note
    assert abs(float(note.split("sensor resonance ")[1].split(" Hz")[0]) - 40.0) < 4.0


def test_undeclared_high_pass_is_found_fitted_through_and_named():
    """A 0.5 Hz high-pass in steady state (a phase lead atan(0.5 / f): 18 deg at 1.5 rev/s,
    2.1 deg at 13.5), undeclared on a run-up from 1.5 rev/s: the rotor-only fit's angle is
    biased by tens of std with no note; freed, the lead that grows as 1 / f at low speed is
    found and fitted through: every value within 3 std, one note naming a high-pass.  The ±
    keep the corner's freedom: f0's std at least 3 x that of the record with the high-pass
    declared (measured 7 x; 1.0 x when dsp.lsq's unscaled inverse cut it, and f0's z then had
    75 % within 2 over 8 draws)."""
    t, z, phi, w, a = _record(noise=0.3e-6, start_hz=1.5, duration=T_SENSOR)
    wh = 2 * math.pi * 0.5
    x0 = z[0] / (1j * w[0] + wh)               # the high-pass's state in steady state
    hp = ([1.0, 0.0], [1.0, wh])
    zf = signal.lsim(hp, z.real, t, X0=[x0.real])[1] + 1j * signal.lsim(hp, z.imag, t, X0=[x0.imag])[1]
    plain = fit_unbalance_response(t, zf, phi, w, a, fit_delay=True)
    assert abs(math.degrees(plain.angle_rad) - 30.0) > 3 * math.degrees(plain.angle_rad_std)
    fit, notes = _identify(t, zf, phi, w, a)
    _within(fit)
    (note,) = [n for n in notes if n.startswith(("sensor:", "delay:"))]
    assert note.startswith("sensor:") and "high-pass" in note
    known = fit_unbalance_response(t, zf, phi, w, a, channel_filter=ChannelFilter("none", highpass_hz=0.5))
    assert fit["natural_frequency_hz_std"] >= 3 * known.natural_frequency_hz_std
