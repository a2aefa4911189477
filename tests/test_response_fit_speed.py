"""The run-up fit's faster pieces give what the slower ones gave (issue 43, item 3): the
delay's shared interpolation weights against ``np.interp``, the
low-passes of :func:`dsp.artefacts.delay_allowance` scaled from the 1 Hz one against the
designed ones, the sensor's quasi-steady columns against their formula."""
import math

import numpy as np
import pytest

from dsp.artefacts import ChannelFilter, _unit_lowpass, delayed, sensed_columns


# 0.02, -0.012: whole samples, where rounding puts some rows on the next neighbour
# (delayed() slices the common shift and gathers those); jitter: a non-uniform time base
@pytest.mark.parametrize("tau, jitter", [(1.3e-3, 0), (-2.7e-3, 0), (0.5, 0), (-3.0, 0), (4e-3, 0),
                                         (0.0, 0), (1e-14, 0), (0.02, 0), (-0.012, 0),
                                         (0.01, 1e-3), (-2.7e-3, 1e-3)])
def test_delay_equals_np_interp_per_column(tau, jitter):
    t = 1.3 + 0.004 * np.arange(500)
    rng = np.random.default_rng(0)
    t = t + jitter * rng.uniform(size=t.size)
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
