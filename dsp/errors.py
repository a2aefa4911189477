"""Errors and input checks shared by the ``dsp`` package.

Every identifier in ``dsp`` validates its inputs before computing anything, so
that a bad recording gives a clear :class:`SignalError` (naming the argument
and what is wrong) instead of a silently wrong number.
"""
from __future__ import annotations

import numpy as np

__all__ = ["SignalError", "check_signal", "check_times", "check_band"]


class SignalError(ValueError):
    """A signal (or its time base) cannot be analysed as requested.

    Subclass of :class:`ValueError`; the message names the argument and what
    is wrong with it.
    """


def _check_length(a, name, min_samples):
    """Raise unless ``a`` is 1-D with at least ``min_samples`` entries."""
    if a.ndim != 1:
        raise SignalError(f"{name}: must be a 1-D array, got shape {a.shape}")
    if a.size < min_samples:
        raise SignalError(f"{name}: too short, {a.size} samples (need at least {min_samples})")


def _check_finite(a, name, what):
    """Raise naming the count and the first index of NaN/inf entries of ``a`` (one pass,
    ``a.sum()``, when they are all finite and their sum does not overflow)."""
    with np.errstate(over="ignore", invalid="ignore"):
        if np.isfinite(np.sum(a)):
            return
    bad = ~np.isfinite(a)
    if bad.any():
        raise SignalError(f"{name}: {int(bad.sum())} non-finite {what}(s) (NaN/inf), "
                          f"first at index {int(np.argmax(bad))}")


def check_times(t, name="t", min_samples=2):
    """Check a strictly increasing, finite 1-D array of times [s].

    Parameters
    ----------
    t : array_like
        Times in seconds.
    name : str
        Argument name used in error messages.
    min_samples : int
        Minimum number of entries.

    Returns
    -------
    numpy.ndarray
        ``t`` as a float64 array.

    Raises
    ------
    SignalError
        If ``t`` is not 1-D, too short, non-finite or not strictly increasing.
    """
    return _times_and_steps(t, name, min_samples)[0]


def _times_and_steps(t, name, min_samples):
    """:func:`check_times`, also returning the steps ``diff(t)`` and their extremes [s]."""
    t = np.asarray(t, dtype=float)
    _check_length(t, name, min_samples)
    d = np.diff(t)
    if d.size == 0:                          # one sample: nothing to be increasing
        _check_finite(t, name, "value")
        return t, d, np.inf, np.inf
    lo, hi = float(d.min()), float(d.max())
    if not (np.isfinite(t[0]) and np.isfinite(lo) and np.isfinite(hi)):
        _check_finite(t, name, "value")     # a NaN/inf time makes a step NaN/inf
    if lo <= 0:
        i = int(np.argmax(d <= 0))
        raise SignalError(f"{name}: must be strictly increasing, but {name}[{i + 1}] = {t[i + 1]!r}"
                          f" <= {name}[{i}] = {t[i]!r}")
    return t, d, lo, hi


def check_signal(t, x, name="x", min_samples=16, uniform_rtol=1e-3, allow_complex=True):
    """Validate a uniformly sampled signal ``x(t)``.

    Checks, in this order: ``t`` and ``x`` are 1-D and of equal length, at least
    ``min_samples`` samples, all finite (no NaN/inf), ``t`` strictly increasing
    and uniformly sampled (every step within ``uniform_rtol`` of the median
    step), and ``x`` not constant.

    Parameters
    ----------
    t : array_like
        Sample times [s].
    x : array_like
        Samples (real, or complex if ``allow_complex``).
    name : str
        Name of the signal argument used in error messages.
    min_samples : int
        Minimum number of samples.
    uniform_rtol : float
        Relative tolerance on the sampling step.
    allow_complex : bool
        Whether complex samples are accepted.

    Returns
    -------
    t : numpy.ndarray
        float64 times.
    x : numpy.ndarray
        float64 or complex128 samples (the caller's array itself when it already
        has that type: read, never modified, by the identifiers).
    dt : float
        Sampling step [s] (mean step).

    Raises
    ------
    SignalError
        With a message naming the argument and the problem.
    """
    x = np.asarray(x)
    if x.ndim != 1:
        raise SignalError(f"{name}: must be a 1-D array, got shape {x.shape}")
    if np.iscomplexobj(x):
        if not allow_complex:
            raise SignalError(f"{name}: must be real, got complex samples")
        x = x.astype(complex, copy=False)
    else:
        try:
            x = x.astype(float, copy=False)
        except (TypeError, ValueError) as exc:
            raise SignalError(f"{name}: must be numeric ({exc})") from None
    tt = np.asarray(t)
    if tt.ndim != 1:
        raise SignalError(f"t: must be a 1-D array, got shape {tt.shape}")
    if tt.size != x.size:
        raise SignalError(f"t and {name}: lengths differ ({tt.size} vs {x.size})")
    _check_length(x, name, min_samples)
    _check_finite(x, name, "sample")
    t, d, lo, hi = _times_and_steps(tt, "t", min_samples)
    if hi - lo > uniform_rtol * lo:        # else every step is within the tolerance of every
        dt = float(np.median(d))           # other, so of the median: no median needed
        dev = np.abs(d - dt) / dt
        if dev.max() > uniform_rtol:
            i = int(np.argmax(dev))
            raise SignalError(f"t: not uniformly sampled: step {d[i]:.6g} s at index {i} differs "
                              f"from the median step {dt:.6g} s by {100 * dev[i]:.3g} % "
                              f"(tolerance {100 * uniform_rtol:.3g} %); resample first")
    _not_constant(x, name)
    return t, x, float((t[-1] - t[0]) / (t.size - 1))


def _not_constant(x, name, head=64):
    """Raise :class:`SignalError` for a constant signal: the spread of the samples (of the
    real and the imaginary part each) at most 1e-12 of their largest magnitude.

    The first ``head`` samples usually decide it: a spread above 2e-12 of their own
    largest magnitude is above 1e-12 of the whole signal's (if the largest magnitude is
    more than twice theirs, the spread is more than half of it), so the whole record is
    read only for a (nearly) constant start."""
    if _spread_ratio(x[:head]) > 2e-12:
        return
    if _spread_ratio(x) <= 1e-12:
        raise SignalError(f"{name}: signal is constant (value {x[0]!r}); nothing to identify")


def _spread_ratio(x):
    """Largest spread (max - min) of the real or imaginary part over the largest magnitude
    of either (no temporary arrays)."""
    parts = (x.real, x.imag) if np.iscomplexobj(x) else (x,)
    lo = [float(p.min()) for p in parts]
    hi = [float(p.max()) for p in parts]
    scale = max(max(abs(v) for v in lo), max(abs(v) for v in hi))
    return max(h - l for l, h in zip(lo, hi)) / max(scale, np.finfo(float).tiny)


def check_band(freq_hz, sample_rate_hz, max_band_fraction, name):
    """Raise when an identified line lies near the top of the band (probable aliasing).

    A line above the Nyquist frequency folds back into the band and cannot be
    recognised from the samples alone; what can be detected is a line near the
    band edge, where lines only slightly above Nyquist land.

    Parameters
    ----------
    freq_hz : float or array_like
        Identified frequencies [Hz] (the sign is ignored).
    sample_rate_hz : float
        Sample rate fs [Hz]; the Nyquist frequency is fs / 2.
    max_band_fraction : float
        Largest accepted |f| as a fraction of the Nyquist frequency [-].
    name : str
        Name of the signal argument used in the message.

    Raises
    ------
    SignalError
        If any |f| > ``max_band_fraction`` x fs / 2.
    """
    nyq = 0.5 * sample_rate_hz
    f = np.atleast_1d(np.abs(np.asarray(freq_hz, dtype=float)))
    if (f > max_band_fraction * nyq).any():
        raise SignalError(
            f"{name}: line at {float(f.max()):.6g} Hz lies within the top "
            f"{100 * (1 - max_band_fraction):.3g} % of the band (Nyquist {nyq:.6g} Hz); "
            f"the signal is probably aliased (a component above Nyquist folds back "
            f"near the band edge) -- sample faster or low-pass filter before sampling")
