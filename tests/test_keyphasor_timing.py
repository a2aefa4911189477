"""Issue 30, item 2: the keyphasor's timing is in the stated ± (the calibration over
draws: ``keyphasor-ttl`` in tests/test_uncertainty_lab.py).

A TTL keyphasor (a sharp 30 deg pulse: no sample on its edge) sampled at 20 per
revolution at the top speed times each mark only to within its sample interval,
``dt / sqrt 12`` RMS: over a run-up those errors follow the rotation against the
sampling and the angle spline averages them only partly.  Before they were in the ±
(:func:`dsp.speed.pulse_timing_std`, ``RotorAngle.angle_error``), the same noise-free
record gave z = 5.1 (f0), 5.2 (critical speed), 1.9 (angle); with a ramp edge, timed in
the angle, the method is exact (tests/test_uncertainty_exact.py).
"""
from __future__ import annotations

import math

import numpy as np

from dsp.pulse_timing import pulse_timing_std
from dsp.speed import pulse_times

TWO_PI = 2 * math.pi


def test_timing_std_of_sharp_and_resolved_edges():
    """A step lies anywhere in its sample interval (dt / sqrt 12 at the middle); a ramp that
    spans several samples is timed to the channel's noise over its slope."""
    fs, f = 1000.0, 10.0
    t = np.arange(0.0, 2.0, 1 / fs)
    phi = TWO_PI * f * t + 0.3
    u = np.mod(phi, TWO_PI)
    step = np.where(u < 0.5, 5.0, 0.0)
    s = pulse_timing_std(t, step, pulse_times(t, step))
    assert np.allclose(s, 1 / fs / math.sqrt(12.0), rtol=1e-9)
    ramp_rad = math.radians(72.0)                    # 20 samples on the edge at 10 rev/s
    noise = 0.01
    ramp = (5.0 * np.clip(np.where(u < math.pi, u / ramp_rad, 0.0), 0.0, 1.0)
            + np.random.default_rng(3).normal(0.0, noise, t.size))
    s = pulse_timing_std(t, ramp, pulse_times(t, ramp))
    slope = 5.0 / (ramp_rad / (TWO_PI * f))          # [V/s]
    assert np.allclose(s, math.sqrt(2.0) * noise / slope, rtol=0.35)


def test_an_edge_crossing_on_a_sample_is_still_on_its_slope():
    """A ramp whose 50 % level falls on a sample (the crossing time rounds onto it, the
    sample a hair below the level): the pair that crosses is the one after, and the edge is
    timed to its (nil) noise, not taken for a missing crossing (dt / sqrt 3: that made the
    keyphasor path's ± 30 to 100 times too wide)."""
    from oracles.runup_exact import exact_runup

    run = exact_runup(fs_hz=500.0, f_start_hz=10.0, f_end_hz=28.0, duration_s=9.0)
    p = pulse_times(run.t, run.kp)
    on = np.isclose(p[:, None], run.t[None, :], rtol=0, atol=1e-12).any(axis=1)
    assert on.any()                                    # the case is there
    assert np.max(pulse_timing_std(run.t, run.kp, p)) < 1e-9
