"""Issue 30, item 2, a tachometer channel that is not a held display: an analog
tachometer's output (the speed at every sample, with its noise) or a speed column written
to 1 rpm (the speed rounded).  Before, the noisy one was integrated sample by sample with
its noise's angle left out of the ± (z up to 5.2 on f0), and the rounded one was taken for
a held display updated every few samples (f0 +0.13 %, U +2.6 %: z 4.4 and 5.2).  Now the
speed is a least-squares spline, its integral the angle, and the spline's covariance goes
into the fit (:func:`dsp.speed.angle_from_speed`).  The calibration over draws:
``tachometer-analog``, ``tachometer-rounded`` and ``encoder-360`` in
tests/test_uncertainty_lab.py."""
from __future__ import annotations

import math

import numpy as np

from dsp.speed import angle_from_speed

TWO_PI = 2 * math.pi


def test_held_display_and_rounded_speed_are_told_apart():
    """A display updated every 0.5 s with the mean over its gate jumps by the sweep over a
    gate; a speed rounded to 1 rpm changes by one rpm at a time."""
    t = np.arange(0.0, 10.0, 1e-3)
    rpm = 600.0 + 120.0 * t
    gate = np.floor(t / 0.5) * 0.5
    held = np.round(600.0 + 120.0 * (gate - 0.25))
    a = angle_from_speed(t, held * TWO_PI / 60)
    b = angle_from_speed(t, np.round(rpm) * TWO_PI / 60)
    assert not a.covered.all()           # the held display: covered to its last gate's end
    assert b.covered.all() and b.angle_error is not None and b.angle_error.degree == 4
    truth = TWO_PI / 60 * (600.0 * t + 60.0 * t * t)
    assert np.max(np.abs(b.angle_rad - truth)) < 0.05        # rad, 187 revolutions
    assert np.max(np.abs(b.speed_rad_s - TWO_PI / 60 * rpm)) < TWO_PI / 60 * 0.5
