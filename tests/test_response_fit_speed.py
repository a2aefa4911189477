"""The run-up fit's faster pieces give what the slower ones gave (issue 43, item 3): the
first-order high-pass's first-order-hold twin in closed form against scipy's
``cont2discrete``, the delay's shared interpolation weights against ``np.interp``, the
low-passes of :func:`dsp.artefacts.delay_allowance` scaled from the 1 Hz one against the
designed ones, the sensor's quasi-steady columns against their formula."""
import math

import numpy as np
import pytest
from scipy import signal

from dsp.artefacts import ChannelFilter, _first_order_foh, _unit_lowpass, delayed, sensed_columns


@pytest.mark.parametrize("x", [1e-2, 0.126, 0.49, 0.51, 2.0, 20.0])
def test_first_order_hold_twin_of_the_high_pass_in_closed_form(x):
    """Where scipy's matrix exponential is accurate (w_h dt >= 0.01: its error ~1e-16 / x,
    measured 7e-15 at 0.0126 against 40-digit arithmetic) the two agree to 1e-13."""
    bd, ad, _ = signal.cont2discrete(([1.0], [1.0, 1.0]), x, method="foh")
    b, a = _first_order_foh(x)
    assert b == pytest.approx(np.ravel(bd), rel=1e-13)
    assert a == pytest.approx(ad, rel=1e-15)
    assert (b.sum() / a.sum()) == pytest.approx(1.0, rel=1e-13)       # unit gain at DC


def test_first_order_hold_twin_keeps_its_accuracy_at_small_steps():
    """Its series below x = 0.5: b0 = x / 2 - x^2 / 6 + ..., b1 = x / 2 - x^2 / 3 + ...
    to rounding at x = 1e-6 (where x + e^{-x} - 1 in floating point loses 10 digits)."""
    x = 1e-6
    b, _ = _first_order_foh(x)
    assert b[0] == pytest.approx(x / 2 - x * x / 6 + x ** 3 / 24, rel=1e-15)
    assert b[1] == pytest.approx(x / 2 - x * x / 3 + x ** 3 / 8, rel=1e-15)


@pytest.mark.parametrize("tau", [1.3e-3, -2.7e-3, 0.5, -3.0, 4e-3, 0.0, 1e-14])
def test_delay_equals_np_interp_per_column(tau):
    t = 1.3 + 0.004 * np.arange(500)
    rng = np.random.default_rng(0)
    y = rng.normal(size=(500, 3)) + 1j * rng.normal(size=(500, 3))
    ref = np.column_stack([np.interp(t - tau, t, c.real) + 1j * np.interp(t - tau, t, c.imag)
                           for c in y.T])
    assert np.array_equal(delayed(t, y, tau), ref)             # np.interp's arithmetic, bit for bit
    assert np.array_equal(delayed(t, y[:, 0].real, tau), ref[:, 0].real)


@pytest.mark.parametrize("kind", ["butterworth", "bessel"])
@pytest.mark.parametrize("order", [2, 5, 8])
def test_scaled_unit_low_pass_is_the_designed_one(kind, order):
    unit, tau1 = _unit_lowpass(kind, order)
    cutoff = 37.0
    f = np.array([0.5, 8.0, 30.0, 90.0])
    assert unit.response(f / cutoff) == pytest.approx(ChannelFilter(kind, order, cutoff).response(f),
                                                      rel=1e-10, abs=1e-13)
    assert tau1 / cutoff == pytest.approx(
        -np.angle(ChannelFilter(kind, order, cutoff).response(1e-4)) / (2 * math.pi * 1e-4), rel=1e-6)


def test_sensor_columns_are_the_response_at_each_columns_frequency():
    """Columns 0 and 4 (the forced response and the runout) times H at the speed, 1 and 2 (the
    free motions) times H at w_d, the offset (3) as it is; a sixth column for the high-pass's
    state (zero without a high-pass)."""
    t = np.arange(400) * 2e-3
    w = 2 * math.pi * (3.0 + 2.0 * t)
    rng = np.random.default_rng(1)
    B = rng.normal(size=(400, 5)) + 1j * rng.normal(size=(400, 5))
    s2, s1, wd = 2.0, 0.5, 40.0                           # ms^2, ms, rad/s
    out = sensed_columns(t, B, w, wd, (s2, s1, 0.0))
    h = lambda f: 1.0 / (1.0 + 1e-3 * s1 * 2j * math.pi * f + 1e-6 * s2 * (2j * math.pi * f) ** 2)
    assert out.shape == (400, 6) and not out[:, 5].any()
    for k in (0, 4):
        assert out[:, k] == pytest.approx(B[:, k] * h(w / (2 * math.pi)), rel=1e-14)
    for k in (1, 2):
        assert out[:, k] == pytest.approx(B[:, k] * h(wd / (2 * math.pi)), rel=1e-14)
    assert np.array_equal(out[:, 3], B[:, 3])
