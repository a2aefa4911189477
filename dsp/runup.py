"""Resonance of a run-up or run-down with the sweep-rate lag removed.

Papers_001_003_004.md sections 4.3 and 5.4.  Part of :mod:`dsp.frequency`
(re-exported there).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .errors import SignalError, check_times

__all__ = ["RunupResonance", "resonance_from_runup", "resonance_std", "sweep_lag_rad_s", "U_STAR"]

#: Argument of the maximum of |∫_{-∞}^u exp(iπs²/2) ds| (papers digest §4.3).
U_STAR = 1.2172


@dataclass(frozen=True)
class RunupResonance:
    """Resonance peak of a run-up/run-down with the sweep lag removed.

    Attributes
    ----------
    peak_speed_rad_s, peak_frequency_hz : float
        Raw peak of the amplitude curve [rad/s] / [Hz].
    correction_rad_s : float
        Signed correction added to the raw peak [rad/s] (negative on a
        run-up, positive on a run-down); includes the damping shift of the
        steady peak when ``damping_ratio`` is given.
    lag_rad_s : float
        Sweep lag Δω = sqrt(|α|)·s*(κ) [rad/s] (always >= 0).
    corrected_speed_rad_s, corrected_frequency_hz : float
        Estimate of the natural frequency ω0 [rad/s] / f0 [Hz].
    angular_acceleration_rad_s2 : float
        Sweep rate α used [rad/s²] (signed).
    direction : str
        "run-up" or "run-down".
    peak_amplitude : float
        Amplitude at the raw peak.
    """

    peak_speed_rad_s: float
    peak_frequency_hz: float
    correction_rad_s: float
    lag_rad_s: float
    corrected_speed_rad_s: float
    corrected_frequency_hz: float
    angular_acceleration_rad_s2: float
    direction: str
    peak_amplitude: float


def _lag_factor(kappa):
    """Dimensionless peak lag s*(κ) of dA/ds = e^{is²/2} - κA (κ = h/sqrt|α|).

    κ = 0 gives u*·sqrt(π) = 2.1574 (papers digest §4.3).
    """
    if kappa <= 1e-6:
        return U_STAR * math.sqrt(math.pi)
    h = 0.002
    s = np.arange(-60.0, 15.0 + h, h)
    g = np.exp(0.5j * s * s)
    e = math.exp(-kappa * h)
    f = 0.5 * h * (g[1:] + e * g[:-1])
    from scipy import signal as _sig                  # (0.6 s to import: only when needed)

    A0 = g[0] / (kappa + 1j * s[0])                    # quasi-steady start
    A = _sig.lfilter([1.0], [1.0, -e], f, zi=np.array([e * A0]))[0]
    mag = np.abs(A)
    i = int(np.argmax(mag))
    if 0 < i < mag.size - 1:
        y0, y1, y2 = mag[i - 1:i + 2]
        den = y0 - 2 * y1 + y2
        di = 0.5 * (y0 - y2) / den if den != 0 else 0.0
    else:
        di = 0.0
    return float(s[i + 1] + di * h)


def sweep_lag_rad_s(angular_acceleration_rad_s2, damping_ratio=0.0, natural_frequency_rad_s=None):
    """Lag of the resonance peak behind ω0 for a linear sweep [rad/s].

    Undamped (sweep-limited) limit, papers_001_003_004.md §4.3/§5.4:
    ``Δω = u*·sqrt(π·|α|)`` with α = dω/dt [rad/s²] and u* = 1.2172.  (The
    digest writes ``u*·sqrt(2π ε)`` with ε = α/2, i.e. φ = εt²; the paper-001
    example α = 2ε = 20 rad/s² gives 9.65 rad/s.)  With damping h = ζ·ω0 the
    envelope equation dA/ds = e^{is²/2} - κA, κ = h/sqrt|α|, is integrated
    numerically and the lag is ``sqrt|α|·s*(κ)`` (smaller than the undamped
    lag, as the digest says).
    """
    a = abs(float(angular_acceleration_rad_s2))
    kappa = 0.0
    if damping_ratio and natural_frequency_rad_s:
        kappa = float(damping_ratio) * float(natural_frequency_rad_s) / math.sqrt(a)
    return math.sqrt(a) * _lag_factor(kappa)


def resonance_from_runup(t, speed_rad_s, amplitude, angular_acceleration_rad_s2=None,
                         damping_ratio=0.0, forcing="unbalance", fit_fraction=0.98):
    """Natural frequency from the resonance peak of a run-up or run-down.

    The raw peak of the amplitude curve (e.g. the 1X amplitude or the whirl
    envelope vs rotor speed) lags behind ω0 when the speed is swept: it lies
    **above** ω0 on a run-up and **below** on a run-down by
    ``Δω = u*·sqrt(π·|α|)`` in the sweep-limited limit
    (papers_001_003_004.md §4.3 "The peak occurs u*·sqrt(π/a) after ω = Ω,
    i.e. Δω = u*·sqrt(π a)", and §5.4 "Δω = u*·sqrt(2π ε) ≈ 9.65 s⁻¹",
    a = 2ε = α, u* = 1.2172).  With damping the lag is smaller
    (see :func:`sweep_lag_rad_s`) and the steady peak itself is at
    ω0/sqrt(1 - 2ζ²) for unbalance forcing (§5.4), which is also removed.

    Parameters
    ----------
    t : array_like
        Times [s], strictly increasing.
    speed_rad_s : array_like
        Rotor speed ω(t) [rad/s].
    amplitude : array_like
        Response amplitude at each time (≥ 0), e.g. the 1X amplitude.
    angular_acceleration_rad_s2 : float, optional
        Sweep rate α [rad/s²]; default: linear fit of ω(t) over the part of
        the record where the amplitude exceeds half its maximum.
    damping_ratio : float
        ζ if known (e.g. from :func:`free_decay`); 0 gives the §5.4 lag.
    forcing : {"unbalance", "constant", "none"}
        Steady peak position: ω0/sqrt(1-2ζ²) (force ∝ ω², unbalance),
        ω0·sqrt(1-2ζ²) (constant force amplitude), or ω0 (ignore).
    fit_fraction : float
        The raw peak is the vertex of a parabola fitted to amplitude vs speed
        over the samples above ``fit_fraction`` of the maximum.

    Returns
    -------
    RunupResonance
    """
    t = check_times(t, "t", min_samples=16)
    w = np.asarray(speed_rad_s, dtype=float)
    a = np.asarray(amplitude, dtype=float)
    for name, v in (("speed_rad_s", w), ("amplitude", a)):
        if v.shape != t.shape:
            raise SignalError(f"{name}: shape {v.shape} differs from t {t.shape}")
        if not np.isfinite(v).all():
            raise SignalError(f"{name}: contains NaN or inf")
    if np.ptp(a) <= 0:
        raise SignalError("amplitude: constant; no resonance peak")
    if forcing not in ("unbalance", "constant", "none"):
        raise SignalError(f"forcing: must be 'unbalance', 'constant' or 'none', got {forcing!r}")
    if not 0 <= damping_ratio < 1 / math.sqrt(2):
        raise SignalError(f"damping_ratio: {damping_ratio} outside [0, 1/sqrt(2)) (no resonance peak)")
    i = int(np.argmax(a))
    edge = max(2, a.size // 50)
    if i < edge or i > a.size - 1 - edge:
        raise SignalError("amplitude: maximum at the end of the record; the resonance is not "
                          "inside the run-up (extend the sweep)")
    # contiguous region around the peak above fit_fraction * max
    lo = i
    while lo > 0 and a[lo - 1] >= fit_fraction * a[i]:
        lo -= 1
    hi = i
    while hi < a.size - 1 and a[hi + 1] >= fit_fraction * a[i]:
        hi += 1
    if hi - lo < 4:
        lo, hi = max(0, i - 2), min(a.size - 1, i + 2)
    c = np.polyfit(w[lo:hi + 1] - w[i], a[lo:hi + 1], 2)
    w_peak = w[i] - c[1] / (2 * c[0]) if c[0] < 0 else w[i]
    if not min(w[lo], w[hi]) <= w_peak <= max(w[lo], w[hi]):
        w_peak = w[i]
    if angular_acceleration_rad_s2 is None:
        band = a >= 0.5 * a[i]
        j0, j1 = i, i
        while j0 > 0 and band[j0 - 1]:
            j0 -= 1
        while j1 < a.size - 1 and band[j1 + 1]:
            j1 += 1
        if j1 - j0 < 2:
            j0, j1 = max(0, i - 5), min(a.size - 1, i + 5)
        alpha = float(np.polyfit(t[j0:j1 + 1], w[j0:j1 + 1], 1)[0])
    else:
        alpha = float(angular_acceleration_rad_s2)
    if alpha == 0 or not math.isfinite(alpha):
        raise SignalError(f"angular_acceleration_rad_s2: {alpha}; the speed is not swept")
    sign = 1.0 if alpha > 0 else -1.0
    zeta = float(damping_ratio)
    if forcing == "unbalance":
        shift = 1.0 / math.sqrt(1 - 2 * zeta ** 2)
    elif forcing == "constant":
        shift = math.sqrt(1 - 2 * zeta ** 2)
    else:
        shift = 1.0
    w0 = abs(w_peak)
    for _ in range(3):
        lag = sweep_lag_rad_s(alpha, zeta, w0)
        w0 = (abs(w_peak) - sign * lag) / shift
    corr = w0 - abs(w_peak)
    return RunupResonance(
        peak_speed_rad_s=float(abs(w_peak)), peak_frequency_hz=float(abs(w_peak)) / (2 * np.pi),
        correction_rad_s=float(corr), lag_rad_s=float(lag),
        corrected_speed_rad_s=float(w0), corrected_frequency_hz=float(w0) / (2 * np.pi),
        angular_acceleration_rad_s2=alpha, direction="run-up" if alpha > 0 else "run-down",
        peak_amplitude=float(a[i]))


def resonance_std(speed_rad_s, amplitude, result: RunupResonance, damping_ratio: float = 0.0,
                  damping_ratio_std: float = 0.0, damping_known: bool = True,
                  fit_fraction: float = 0.98) -> dict:
    """Standard uncertainty [rad/s] of :func:`resonance_from_runup`'s corrected speed, by parts.

    * ``peak``: the raw peak's statistical part -- the amplitudes' scatter (the residual
      RMS of a quartic through the samples above half the maximum, which also holds the
      curve's misfit: on the safe side) propagated through the parabola's vertex;
    * ``peak_shape``: the vertex's method part -- the vertex of the parabola through the
      samples above ``fit_fraction`` against the maximum of that quartic (a peak sampled
      once per revolution, asymmetric behind a sweep);
    * ``lag_model``: the sweep-lag correction's neglected order -- the envelope equation
      (papers digest 4.3) holds the unbalance force and the damping constant across the
      peak, which move by ~lag / omega0 over it: lag^2 / omega0;
    * ``damping``: the lag's and the steady shift's change with zeta over its std; when
      zeta is not known (``damping_known`` False, 0 used: the sweep-limited lag) the
      damped lag can be anything from 0 up to that: half of it.

    Returns
    -------
    dict
        ``std_rad_s`` and the parts above [rad/s].
    """
    w = np.asarray(speed_rad_s, float)
    a = np.asarray(amplitude, float)
    i = int(np.argmax(a))
    lo = hi = i
    while lo > 0 and a[lo - 1] >= fit_fraction * a[i]:
        lo -= 1
    while hi < a.size - 1 and a[hi + 1] >= fit_fraction * a[i]:
        hi += 1
    if hi - lo < 4:
        lo, hi = max(0, i - 2), min(a.size - 1, i + 2)
    j0 = j1 = i
    while j0 > 0 and a[j0 - 1] >= 0.5 * a[i]:
        j0 -= 1
    while j1 < a.size - 1 and a[j1 + 1] >= 0.5 * a[i]:
        j1 += 1
    j0, j1 = min(j0, lo), max(j1, hi)
    peak = shape = 0.0
    wi = w[i]
    X = np.vander(w[lo:hi + 1] - wi, 3)
    c = np.linalg.lstsq(X, a[lo:hi + 1], rcond=None)[0]
    n4 = j1 - j0 + 1
    if n4 >= 7 and c[0] < 0:
        scale = max(float(np.max(np.abs(w[j0:j1 + 1] - wi))), 1e-12)
        u = (w[j0:j1 + 1] - wi) / scale
        q = np.polyfit(u, a[j0:j1 + 1], 4)
        res = a[j0:j1 + 1] - np.polyval(q, u)
        sa = float(np.sqrt(np.sum(res * res) / (n4 - 5)))
        # vertex -c1 / 2 c0: gradient wrt (c0, c1), covariance sa^2 (X'X)^-1
        J = np.array([c[1] / (2 * c[0] ** 2), -1.0 / (2 * c[0]), 0.0])
        cov = sa * sa * np.linalg.pinv(X.T @ X)
        peak = float(math.sqrt(max(J @ cov @ J, 0.0)))
        uu = np.linspace((w[lo] - wi) / scale, (w[hi] - wi) / scale, 2001)
        w_quartic = wi + scale * float(uu[int(np.argmax(np.polyval(q, uu)))])
        shape = abs(w_quartic - result.peak_speed_rad_s)
    w0 = result.corrected_speed_rad_s
    lag = result.lag_rad_s
    lag_model = lag * lag / w0 if w0 > 0 else 0.0
    alpha = result.angular_acceleration_rad_s2
    sign = 1.0 if alpha > 0 else -1.0

    def corrected(z):
        z = min(max(z, 0.0), 0.7)
        shift = 1.0 / math.sqrt(1 - 2 * z * z)
        x = w0
        for _ in range(3):
            x = (result.peak_speed_rad_s - sign * sweep_lag_rad_s(alpha, z, x)) / shift
        return x

    if not damping_known:
        damping = 0.5 * lag
    elif damping_ratio_std > 0:
        damping = 0.5 * abs(corrected(damping_ratio + damping_ratio_std)
                            - corrected(damping_ratio - damping_ratio_std))
    else:
        damping = 0.0
    parts = {"peak": peak, "peak_shape": shape, "lag_model": lag_model, "damping": damping}
    return {"std_rad_s": float(math.sqrt(sum(v * v for v in parts.values()))),
            **{k: float(v) for k, v in parts.items()}}
