"""A DAQ channel's own artefacts, on plain arrays: its filter, its clipping.

* :class:`ChannelFilter` -- an anti-alias low-pass (analog Butterworth or Bessel of an order
  and a cutoff) or a converter's fixed group delay, and the sensor's own response (a
  mounted resonance, a high-pass): its complex response at a frequency
  (:meth:`ChannelFilter.response`, what divides a 1X phasor) and its action on sampled
  columns (:meth:`ChannelFilter.apply`, what a model's response goes through before it is
  compared with the record: the run-up fit of :mod:`dsp.response_fit`).
* :func:`delay_checked` -- an undeclared filter or channel delay, found by fitting a delay
  in the run-up model (a phase growing as w tau, which a rotor's bounded phase cannot
  make), named in one note, the ± widened by :func:`delay_allowance`;
  :func:`unfiltered` -- a steady 1X with a declared filter divided out;
* :func:`clipped` -- samples at a channel's rail (the probe or the ADC at the end of its
  range): censored, i.e. left out of a fit, not cut out of the time base;
  :func:`filled` bridges them for the steps that need every sample.

Every filter is scipy's (``scipy.signal.butter`` / ``bessel`` with ``analog=True``); the
sampled form is its first-order-hold twin (``cont2discrete(..., method="foh")``: exact for
an input linear between samples, as ``scipy.signal.lsim`` takes it).
"""
from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from dsp.errors import SignalError

__all__ = ["ChannelFilter", "sensor_response", "sensor_checked", "clipped", "filled", "delayed", "delay_allowance", "delay_checked",
           "unfiltered", "KINDS"]

KINDS = ("butterworth", "bessel", "delay", "none")
CLIP_RUN = 4     #: samples at the extreme value that make a rail
#: An undeclared high-pass found in a run-up: the ± allow for this fraction of what it changes
#: (its corner comes from the low-speed phase lead, where the rotor's response is weakest:
#: 0.47 Hz found for 0.5 on a 1.5 -> 13.5 rev/s record, the angle then 0.35 deg off of a 4.7
#: deg correction; calibrated in benchmarks/README.md, "sensor-undeclared")
HIGHPASS_ALLOWANCE = 0.25
#: ... and is named (and allowed for) from this fraction of the record's lowest speed up (a
#: lead of 3 deg there; below, the fit keeps it free but it is the noise's: 0.04 of it was
#: found beside an undeclared 40 Hz resonance on data_samples/daq/daq_runup.csv)
HIGHPASS_MIN = 0.05
#: a fitted resonance's quality factor is taken up to this (a mounted accelerometer's is a few
#: to ~50); a larger fitted Q is its lag gone into the delay, and the resonance is made exact
#: with this Q.  (It once rejected such a resonance: 101 Hz, Q 1000 found on a clean TTL
#: run-up of benchmarks/_uncertainty_lab.py, f0 then 47 sigma off -- the Wald test below
#: rejects that now, and the rejection had left draw 7 of sensor-undeclared-resonance
#: unnamed, U 26 std off)
RESONANCE_Q_MAX = 100.0
#: ... and each sensor part (a resonance's 1 / w_r^2, a high-pass corner) is taken only beyond
#: this many of its own std (a 4.9 Hz high-pass 'found' with 243 of chi^2 on the
#: daq-filter-declared run-up of benchmarks/_uncertainty_lab.py, seed 0, which has none)
WALD_Z = 3.0


@dataclass(frozen=True)
class ChannelFilter:
    """A channel's filter.

    Attributes
    ----------
    kind : str
        ``butterworth`` or ``bessel`` (analog low-pass; a Bessel's cutoff is its -3 dB
        frequency, scipy's ``norm="mag"``), ``delay`` (a pure group delay) or ``none`` (no
        low-pass: the sensor's own response below only).
    order : int
        Low-pass order (1-10).
    cutoff_hz : float
        Low-pass cutoff [Hz].
    delay_s : float
        Group delay [s] (``delay``; added to a low-pass too, e.g. a converter's pipeline).
    resonance_hz, resonance_q : float
        The sensor's mounted resonance [Hz] (0: none) and its quality factor [-]: a
        second-order response w_r^2 / (s^2 + s w_r / Q + w_r^2), flat at low frequency, Q at
        w_r (an accelerometer on its mount).
    highpass_hz : float
        The sensor's or its amplifier's first-order high-pass corner [Hz] (0: none; s / (s + w_h)).
    """

    kind: str
    order: int = 0
    cutoff_hz: float = 0.0
    delay_s: float = 0.0
    resonance_hz: float = 0.0
    resonance_q: float = 30.0
    highpass_hz: float = 0.0

    def __post_init__(self):
        if self.kind not in KINDS:
            raise SignalError(f"filter type {self.kind!r}: one of {', '.join(KINDS)}")
        lowpass = self.kind in ("butterworth", "bessel")
        if lowpass and not (isinstance(self.order, int) and 1 <= self.order <= 10):
            raise SignalError(f"filter order {self.order!r}: an integer 1-10")
        for name, v, low in (("resonance", self.resonance_hz, 0.0), ("high-pass", self.highpass_hz, 0.0),
                             ("resonance q", self.resonance_q, 0.5)):
            if not (math.isfinite(v) and v >= low):
                raise SignalError(f"sensor {name} {v!r}{' Hz' if low == 0 else ''}: must be >= {low:g}")
        if lowpass and not (math.isfinite(self.cutoff_hz) and self.cutoff_hz > 0):
            raise SignalError(f"filter cutoff {self.cutoff_hz!r} Hz: must be > 0")
        if not (math.isfinite(self.delay_s) and 0 <= self.delay_s < 1):
            raise SignalError(f"filter delay {self.delay_s!r} s: must be in [0, 1)")

    def analog(self):
        """``(b, a)`` of the analog low-pass times the sensor's resonance and high-pass, in s
        [rad/s], or None for a pure delay."""
        from scipy import signal

        b, a = np.ones(1), np.ones(1)
        if self.kind in ("butterworth", "bessel"):
            wc = 2 * math.pi * self.cutoff_hz
            b, a = (signal.bessel(self.order, wc, analog=True, norm="mag") if self.kind == "bessel"
                    else signal.butter(self.order, wc, analog=True))
        if self.resonance_hz:
            wr = 2 * math.pi * self.resonance_hz
            b, a = b * wr * wr, np.polymul(a, [1.0, wr / self.resonance_q, wr * wr])
        if self.highpass_hz:
            b, a = np.polymul(b, [1.0, 0.0]), np.polymul(a, [1.0, 2 * math.pi * self.highpass_hz])
        return None if a.size == 1 else (b, a)

    def response(self, f_hz):
        """Complex response H(i 2 pi f) at ``f_hz`` [Hz] (gain and phase; a lag is a
        negative angle)."""
        from scipy import signal

        w = 2 * math.pi * np.abs(np.asarray(f_hz, float))
        h = np.exp(-1j * w * self.delay_s)
        ba = _analog(self)
        if ba is not None:
            h = h * signal.freqs(*ba, worN=np.atleast_1d(w))[1].reshape(w.shape)
        h = np.where(np.asarray(f_hz) < 0, np.conj(h), h)
        return h if np.ndim(f_hz) else complex(h)

    def describe(self) -> str:
        parts = [f"{self.kind} low-pass, order {self.order}, cutoff {self.cutoff_hz:g} Hz"
                 if self.kind in ("butterworth", "bessel") else "",
                 f"group delay {self.delay_s * 1e3:g} ms" if self.delay_s else "",
                 f"sensor resonance {self.resonance_hz:g} Hz, Q {self.resonance_q:g}"
                 if self.resonance_hz else "",
                 f"high-pass {self.highpass_hz:g} Hz" if self.highpass_hz else ""]
        return " + ".join(p for p in parts if p)

    def apply(self, t, columns):
        """The sampled columns (N or N x K, real or complex, uniform ``t`` [s]) as the
        channel records them: the low-pass's first-order-hold twin from a steady start
        (the first sample held before the record), then the delay by linear
        interpolation (the first sample held before it)."""
        from scipy import signal

        t = np.asarray(t, float)
        y = np.asarray(columns)
        twin = _discrete(self, float(np.median(np.diff(t))))
        if twin is not None:
            bd, ad, zi = twin
            shape = (-1,) + (1,) * (y.ndim - 1)
            y = signal.lfilter(bd, ad, y, axis=0, zi=zi.reshape(shape) * y[:1])[0]
        if self.delay_s:
            y = delayed(t, y, self.delay_s)
        return y


@functools.lru_cache(maxsize=64)
def _analog(flt):
    """:meth:`ChannelFilter.analog`, designed once per filter."""
    return flt.analog()


@functools.lru_cache(maxsize=64)
def _discrete(flt, dt: float):
    """``(bd, ad, zi)`` of a filter's first-order-hold twin at the step ``dt`` [s] (scipy's
    ``cont2discrete``, ``lfilter_zi``; None for a pure delay), computed once per filter and
    step: the run-up fit applies the same declared filter at every step of its search."""
    from scipy import signal

    ba = _analog(flt)
    if ba is None:
        return None
    bd, ad, _ = signal.cont2discrete(ba, dt, method="foh")
    bd = np.ravel(bd)
    return bd, ad, signal.lfilter_zi(bd, ad)


@functools.lru_cache(maxsize=64)
def _highpass_twin(highpass_hz: float, dt: float):
    """``(bd, ad)`` of the first-order-hold twin of w_h / (s + w_h) (scipy's
    ``cont2discrete``), once per corner and step: the run-up fit's search asks for the same
    corner at most of its finite-difference steps (those in the other parameters)."""
    from scipy import signal

    wh = 2 * math.pi * highpass_hz
    bd, ad, _ = signal.cont2discrete(([wh], [1.0, wh]), dt, method="foh")
    return np.ravel(bd), ad


def sensor_response(f_hz, lag_s2: float, lag_s: float, highpass_hz: float = 0.0):
    """H(i 2 pi f) at ``f_hz`` [Hz] of an undeclared sensor's response as the run-up fit
    frees it: a second-order part 1 / (1 + ``lag_s`` s + ``lag_s2`` s^2) (a mounted resonance
    at 1 / (2 pi sqrt(lag_s2)) of Q sqrt(lag_s2) / lag_s, or a low-pass) and a first-order
    high-pass s / (s + 2 pi ``highpass_hz``)."""
    s = 2j * math.pi * np.asarray(f_hz, float)
    return s / (s + 2 * math.pi * highpass_hz) / (1.0 + lag_s * s + lag_s2 * s * s) \
        if highpass_hz else 1.0 / (1.0 + lag_s * s + lag_s2 * s * s)


def highpassed(t, columns, highpass_hz: float, w_start, real=None, dt=None):
    """Complex columns (uniform ``t`` [s]) through a first-order high-pass s / (s + w_h) that
    was in steady state before the record: each column a phasor at ``w_start`` [rad/s] (one
    per column; its low-pass part starts at w_h / (w_h + i w) times the first sample), or where
    ``real`` a real sinusoid there (its phasor from the first samples and their slope); the
    first-order-hold twin, exact for columns linear between samples (``dt``: the sample
    interval [s] when known, else the median of ``t``'s)."""
    from scipy import signal

    wh, dt = 2 * math.pi * highpass_hz, float(np.median(np.diff(t))) if dt is None else dt
    y = np.asarray(columns)
    w = np.asarray(w_start, float)
    h = wh / (wh + 1j * w)
    start = h * y[0]
    if real is not None:        # u = Re(A e^{i w t}), A = u(0) - i u'(0) / w
        r = np.asarray(real, bool)
        slope = (-3 * y[0] + 4 * y[1] - y[2]) / (2 * dt)
        a, b = y[0], -slope / np.where(w > 0, w, 1.0)
        start = np.where(r, h.real * a + h.imag * -b, start)
    bd, ad = _highpass_twin(highpass_hz, dt)
    return y - signal.lfilter(bd, ad, y, axis=0, zi=(start - bd[0] * y[0])[None, :])[0]


def sensed_columns(t, B, w, wd: float, sensor, dt=None):
    """The run-up fit's columns ``B`` (N x 5: forced response, the two free motions, offset,
    runout) as a free sensor response (``sensor``: lag [ms^2], lag [ms], high-pass [Hz]; none
    if empty) records them, with the high-pass's unknown state before the record, e^{-w_h t},
    as a sixth column: :func:`sensor_response`'s second-order part quasi-steady (each column
    times the response at its own frequency, ``w`` [rad/s] the speed, ``wd`` the free motions'),
    the high-pass exact (:func:`highpassed`: its lead changes faster than the sweep)."""
    tt = t - t[0]
    if len(sensor) and any(sensor):    # the DC offset column (3) stays as it is
        s2, s1, fh = sensor[0] * 1e-6, sensor[1] * 1e-3, float(sensor[2])
        if s2 or s1:
            hw = sensor_response(np.abs(w) / (2 * math.pi), s2, s1)
            hd = sensor_response(np.full(1, abs(wd)) / (2 * math.pi), s2, s1)
            B = B * np.column_stack((hw, np.broadcast_to(hd, (w.size, 2)), np.ones(w.size), hw))
        if fh:      # (B is the caller's unless the lags made a new one)
            cols, B = [0, 1, 2, 4], B.copy() if not (s2 or s1) else B
            B[:, cols] = highpassed(t, B[:, cols], fh, [w[0], wd, wd, w[0]], [0, 1, 1, 0], dt)
    if len(sensor):
        B = np.column_stack((B, np.exp(-2 * math.pi * sensor[2] * tt) if sensor[2] > 0 else 0 * tt))
    return B


def delay_weights(t, tau: float):
    """np.interp's indices, slopes' denominators and offsets for ``columns(t - tau)``
    (:func:`delayed`), and where ``t - tau`` lies before ``t[0]`` and from ``t[-1]`` on."""
    t = np.asarray(t, float)
    ts = t - tau
    j = np.clip(np.searchsorted(t, ts, side="right") - 1, 0, t.size - 2)
    return j, (t[j + 1] - t[j])[:, None], (ts - t[j])[:, None], ts < t[0], ts >= t[-1]


def delayed(t, columns, tau: float, weights=None):
    """``columns(t - tau)`` by linear interpolation (the first sample held before ``t[0]``),
    every column (real and imaginary parts alike) with the same weights (``weights``:
    :func:`delay_weights`' when known) and np.interp's arithmetic, to the last bit."""
    y = np.asarray(columns)
    j, dx, off, before, after = delay_weights(t, tau) if weights is None else weights
    flat = np.ascontiguousarray(y.reshape(np.size(t), -1))
    re = flat.view(float) if np.iscomplexobj(flat) else flat.astype(float, copy=False)
    # the rows where j is the row's index shifted by the median row's shift (the rest: the
    # clipped ends, a rounding's other neighbour) from slices, in place, the others gathered:
    # the same arithmetic, without copying most of the columns
    d = j - np.arange(j.size)
    m = int(d[j.size // 2])
    same = d == m
    a, b = int(np.argmax(same)), j.size - int(np.argmax(same[::-1]))
    out = np.empty_like(re)
    o, lo = out[a:b], re[a + m:b + m]
    np.subtract(re[a + m + 1:b + m + 1], lo, out=o)
    o /= dx[a:b]
    o *= off[a:b]
    o += lo
    r = np.flatnonzero(~same)
    out[r] = (re[j[r] + 1] - re[j[r]]) / dx[r] * off[r] + re[j[r]]
    out[before], out[after] = re[0], re[-1]
    return (out.view(complex) if np.iscomplexobj(flat) else out).reshape(y.shape)


def delay_allowance(tau_s: float, f_hz: float, orders=range(2, 9)):
    """What a pure delay leaves out of an unknown low-pass that has it.

    A delay ``tau_s`` [s] found between the vibration channels and the rotor angle is the
    low-frequency group delay of some filter; over the Butterworth and Bessel low-passes of
    ``orders`` whose group delay at DC is ``tau_s``, the largest gain loss and phase
    departure from ``-2 pi f tau`` at ``f_hz`` [Hz].

    Returns
    -------
    (float, float)
        Gain loss 1 - |H| [-] and phase departure [rad], both >= 0.
    """
    if not tau_s > 0:
        return 0.0, 0.0
    loss, dphi = 0.0, 0.0
    for kind in ("butterworth", "bessel"):
        for n in orders:
            unit, tau1 = _unit_lowpass(kind, int(n))
            h = unit.response(f_hz * tau_s / tau1)      # the low-pass of cutoff tau1 / tau_s
            loss = max(loss, 1.0 - abs(h))
            dphi = max(dphi, abs(np.angle(h * np.exp(2j * math.pi * f_hz * tau_s))))
    return float(loss), float(dphi)


@functools.lru_cache(maxsize=None)
def _unit_lowpass(kind: str, order: int):
    """The low-pass of cutoff 1 Hz and its group delay at DC [s]: the one of cutoff f_c
    is it at f / f_c (H(s / w_c)), its delay 1 / f_c times."""
    unit = ChannelFilter(kind, order, 1.0)
    return unit, float(-np.angle(unit.response(1e-4)) / (2 * math.pi * 1e-4))


def delay_checked(fit, refit, w_top: float, channel_filter, notes: list):
    """The delay test: ``refit`` fits a delay of the probes behind the rotor angle as well
    (:attr:`dsp.response_fit.ResponseFit.delay_s`); beyond 3 std -- a phase growing as
    w tau through the run-up, which the rotor's own bounded phase cannot make -- that fit
    is taken and the delay named in one note; the ± then allow for an unknown low-pass of that
    delay (:func:`dsp.artefacts.delay_allowance`: its gain loss in e at the top speed, its
    phase departure in the angle, both at the critical speed in zeta and f_1).  Not found,
    the plain fit is kept with the two fits' difference of angle and e in their ±."""
    import dataclasses

    fd = refit()
    if not (math.isfinite(fd.delay_s_std) and abs(fd.delay_s) > 3 * fd.delay_s_std):
        # not found: what a delay of that size would change stays in the ± (model choice)
        da = abs((fd.angle_rad - fit.angle_rad + math.pi) % (2 * math.pi) - math.pi)
        return dataclasses.replace(
            fit, angle_rad_std=math.hypot(fit.angle_rad_std, da),
            specific_unbalance_m_std=math.hypot(fit.specific_unbalance_m_std,
                                                fd.specific_unbalance_m - fit.specific_unbalance_m))
    fit = fd
    f_top, fc = w_top / (2 * math.pi), fit.critical_speed_hz
    loss, dphi = delay_allowance(abs(fit.delay_s), f_top)
    loss_c, dphi_c = delay_allowance(abs(fit.delay_s), fc)
    z0, f0 = fit.damping_ratio, fit.natural_frequency_hz
    fit = dataclasses.replace(
        fit, specific_unbalance_m_std=math.hypot(fit.specific_unbalance_m_std,
                                                 loss * fit.specific_unbalance_m),
        angle_rad_std=math.hypot(fit.angle_rad_std, dphi),
        damping_ratio_std=math.hypot(fit.damping_ratio_std, loss_c * z0),
        natural_frequency_hz_std=math.hypot(fit.natural_frequency_hz_std, dphi_c * z0 * f0),
        critical_speed_hz_std=math.hypot(fit.critical_speed_hz_std, dphi_c * z0 * fc))
    beyond = f" beyond the declared {channel_filter.describe()}" if channel_filter else ""
    notes.append(
        f"delay: the probes lag the rotor angle by {fit.delay_s * 1e3:.3g} ± "
        f"{fit.delay_s_std * 1e3:.2g} ms{beyond} (a phase growing as w tau through the run-up, "
        f"which the rotor's own phase cannot make) -- an undeclared anti-alias filter or channel "
        f"delay (or a sensor's mounted resonance, which also lifts the gain: not in the ±); fitted as a "
        f"delay ({math.degrees(2 * math.pi * fc * fit.delay_s):.3g} deg at the critical speed), the ± "
        f"allow for a Butterworth or Bessel low-pass of order 2-8 with that delay (gain "
        f"-{100 * loss:.2g} %, phase {math.degrees(dphi):.2g} deg at {f_top:.3g} rev/s); declare "
        "the filter in the recording map (x, y: filter = {type, order, cutoff}, {group_delay} or "
        "{resonance, q})")
    return fit


#: the run-up fit's values that an undeclared sensor moves (and the angle, wrapped)
_SENSOR_KEYS = ("natural_frequency_hz", "damping_ratio", "critical_speed_hz", "specific_unbalance_m")


def _differences(a, b, scale=1.0) -> dict:
    """``scale`` x |a - b| of two response fits' values (the angle wrapped to +-pi)."""
    d = {k: scale * abs(getattr(a, k) - getattr(b, k)) for k in _SENSOR_KEYS}
    d["angle_rad"] = scale * abs((a.angle_rad - b.angle_rad + math.pi) % (2 * math.pi) - math.pi)
    return d


def _widened(fit, d: dict, floor=None):
    """``fit`` with each std of ``d``'s values combined in quadrature with ``d``'s amount;
    ``floor``: a second fit whose std, when larger, is the one widened."""
    import dataclasses

    std = {k: getattr(fit, k + "_std") if floor is None
           else max(getattr(fit, k + "_std"), getattr(floor, k + "_std")) for k in d}
    return dataclasses.replace(fit, **{k + "_std": math.hypot(std[k], v) for k, v in d.items()})


def sensor_checked(fit, refit, speeds_hz, channel_filter, notes: list, threshold: float = 16.3):
    """The sensor test: ``refit(**kw)`` refits with the keywords of
    :func:`dsp.response_fit.fit_unbalance_response` changed.  Freeing an undeclared sensor
    response (``fit_sensor``: a second-order part, quasi-steady, and a high-pass, with the
    delay) lowers the residuals' chi^2 by more than ``threshold`` (3 sigma for its 4
    parameters) when the record has one -- a gain rising with the speed, a phase leading as
    1 / w at low speed, neither of which the rotor makes -- and the part it names (a
    resonance's 1 / w_r^2, a high-pass corner) lies beyond :data:`WALD_Z` of its own std (a
    Wald test with the fit's batch-means covariance, which a misfit correlated along the
    record does not fool as it does the chi^2 drop).  That fit is then taken; a resonance
    in it (Q >= 0.5, below 20 times the top speed) is made exact (the record refitted through
    it as a declared filter, the high-pass free again), the ± the larger of the two fits'
    (the quasi-steady one's holds the resonance's own freedom) widened by their difference; one note names it (replacing the delay note it explains).  The test's fit
    is made without its covariance, completed (its search not repeated) only when the chi^2
    drop passes (the Wald test needs it; a record whose drop does not pass saves 2/5 of the
    test's CPU).  ``speeds_hz``
    (lowest, highest) [Hz] of the record; ``channel_filter`` the declared one or None."""
    import dataclasses

    fs = refit(fit_delay=True, fit_sensor=True, covariance=False)     # its ± only when needed
    gain = fs.samples * (fit.residual_rms_m ** 2 / fs.residual_rms_m ** 2 - 1.0)
    if not gain > threshold:
        return fit
    fs = refit(fit_delay=True, fit_sensor=True, solution=fs.solution)   # the Wald test's std
    lo, hi = speeds_hz
    s2, s1, fh = fs.sensor
    # each part also beyond WALD_Z of its own std (the covariance's larger of white and batch
    # means, with the other parts and the delay free): the chi^2 drop takes the residuals
    # for white, and a misfit that follows the speed (a keyphasor's interpolated angle)
    # lowers it by hundreds on a record with no sensor
    z2, zh = (v / sd if sd > 0 else 0.0 for v, sd in zip((s2, fh), fs.sensor_std[::2]))
    # Q is sqrt(s2) / s1, but below the resonance s1 lags as the delay does (-w s1 vs -w tau):
    # a Q above RESONANCE_Q_MAX is that lag gone into the delay (s1 at its bound 0, U 26 std
    # off with no note on draw 7 of sensor-undeclared-resonance), taken as RESONANCE_Q_MAX; the
    # exact refit keeps the quasi-steady lag and the delay free, its covariance their freedom
    fr, q = 1 / (2 * math.pi * math.sqrt(s2)) if s2 > 0 else math.inf, math.sqrt(s2) / s1 if s1 else 1e3
    res = (dict(resonance_hz=fr, resonance_q=min(q, RESONANCE_Q_MAX))
           if fr < 20 * hi and q >= 0.5 and z2 > WALD_Z else {})
    # a high-pass (with the delay) is taken for one only when the phase it makes changes
    # through the record more than its mean: a constant phase is the unbalance angle's own
    # freedom (a 4.9 Hz high-pass + a -1 ms delay, +28 to +20 deg, 'found' with 258 of chi^2
    # on a clean TTL run-up of benchmarks/_uncertainty_lab.py moved the angle 22 deg)
    lead = [math.atan2(fh, f) - 2 * math.pi * f * fs.delay_s for f in (lo, hi)]
    varies = abs(lead[0] - lead[1]) >= abs(lead[0] + lead[1]) / 2
    if not (res or (fh > HIGHPASS_MIN * lo and varies and zh > WALD_Z)):
        return fit
    out = fs
    if res:
        flt = (dataclasses.replace(channel_filter, **res) if channel_filter is not None
               else ChannelFilter("none", **res))
        fx = refit(channel_filter=flt, fit_delay=True, fit_sensor=True)
        out = _widened(fx, _differences(fx, fs), floor=fs)
    fh_out = out.sensor[2] if out.sensor[2] > max(HIGHPASS_MIN * lo, WALD_Z * out.sensor_std[2]) else 0.0
    shown = ChannelFilter("none", **res, highpass_hz=fh_out)
    if shown.highpass_hz:       # its corner comes from where the rotor's response is weakest
        out = _widened(out, _differences(out, fit, HIGHPASS_ALLOWANCE))
    h = [complex(shown.response(f) * np.exp(-2j * math.pi * f * out.delay_s)) for f in (lo, hi)]
    notes[:] = [m for m in notes if not m.startswith("delay:")]
    notes.append(
        f"sensor: the 1X departs from the rotor's response as an undeclared sensor response "
        f"would (chi^2 lower by {gain:.3g} with one fitted): {shown.describe()}"
        f"{f' + delay {out.delay_s * 1e3:.2g} ms' if out.delay_s else ''} (gain x{abs(h[1]):.3g}, "
        f"phase {math.degrees(np.angle(h[1])):+.2g} deg at {hi:.3g} rev/s; x{abs(h[0]):.3g}, "
        f"{math.degrees(np.angle(h[0])):+.2g} deg at {lo:.3g} rev/s); the values are fitted "
        f"through it (U {fit.specific_unbalance_m / out.specific_unbalance_m - 1:+.1%}, angle "
        f"{math.degrees(fit.angle_rad - out.angle_rad):+.2g} deg without), the ± widened for "
        f"{'the resonance fit quasi-steady' if res else ''}{' and ' if res and shown.highpass_hz else ''}"
        f"{f'a quarter of what the high-pass changes' if shown.highpass_hz else ''}; "
        "declare the sensor in the recording map (x, y: filter = {resonance, q, highpass})")
    return out


def unfiltered(sc1, flt, notes):
    """The steady 1X with the channels' declared filter divided out: H(i w) at the 1X
    speed (its gain and its phase lag)."""
    import dataclasses

    h = flt.response(sc1.speed_rad_s / (2 * math.pi))
    v = sc1.vector_m / h
    notes.append(f"declared filter ({flt.describe()}): the 1X divided by its response at "
                 f"{sc1.speed_rad_s / (2 * math.pi):.4g} rev/s (gain {abs(h):.4g}, phase "
                 f"{math.degrees(np.angle(h)):.3g} deg); the run-up model is fitted through it")
    return dataclasses.replace(sc1, vector_m=v, amplitude_m=abs(v),
                               amplitude_std_m=sc1.amplitude_std_m / abs(h),
                               vector_std_m=sc1.vector_std_m / abs(h),
                               phase_rad=math.atan2(v.imag, v.real))


def clipped(v, run: int = CLIP_RUN, rail=None) -> np.ndarray:
    """Samples of a channel at its rail: its extreme value held for >= ``run`` samples
    somewhere (then every sample at that value is at the rail), or outside a declared
    ``rail = (low, high)`` (in the channel's unit; at or beyond it is censored)."""
    v = np.asarray(v, float)
    bad = np.zeros(v.size, bool)
    fin = np.isfinite(v)
    if rail is not None:
        lo, hi = rail
        return fin & ((v <= lo) | (v >= hi))
    if fin.sum() < run or np.nanmax(v) == np.nanmin(v):     # a constant channel is not clipped
        return bad
    for level in (np.nanmax(v), np.nanmin(v)):
        at = np.concatenate(([0], (v == level).astype(np.int8), [0]))
        d = np.flatnonzero(np.diff(at))
        if np.any(d[1::2] - d[::2] >= run):
            bad |= v == level
    return bad


def filled(t, v, mask):
    """``v`` with its ``mask``-ed samples bridged linearly from their neighbours (for the
    steps that need every sample; a fit leaves them out instead)."""
    v = np.asarray(v, float)
    mask = np.asarray(mask, bool)
    if not mask.any():
        return v
    if mask.all():
        raise SignalError("every sample is censored")
    out = v.copy()
    out[mask] = np.interp(np.asarray(t)[mask], np.asarray(t)[~mask], v[~mask])
    return out
