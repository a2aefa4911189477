"""Spectral lines of a sampled signal: the one line estimator of ``dsp``.

A *line* is a complex exponential ``c e^{2 pi i f (t - t_ref)}`` of a
complex signal z = x + i y (forward whirl f > 0, backward f < 0) or of a real
one (then lines come in +- pairs).  Every frequency search in ``dsp`` goes
through this module, with its one analysis window:

window_weights
    The analysis window (periodic Hann without zero end samples, or
    rectangular).
spectrum
    Zero-padded windowed amplitude spectrum on its frequency grid [Hz].
naff
    The line search (the role of Laskar's NAFF): the peak of the zero-padded
    windowed spectrum of the residual, interpolated between bins (a parabola
    through the log-magnitudes), then all lines found so far refitted jointly
    (Gauss-Newton, :mod:`dsp.line_gn`) and subtracted before the next peak;
    optional constant offset and detection thresholds.
fit_lines, LineFit
    Joint (window-weighted) least-squares fit of all frequencies and complex
    amplitudes by Gauss-Newton on the structured normal equations
    (:mod:`dsp.line_gn`: length-N sums, never an N x P Jacobian); sandwich
    covariance with the residual as noise (for uniform weights the inverse
    Fisher information, i.e. the Cramer-Rao bound evaluated at the estimates).
    Written in :mod:`dsp.line_fit`, importable from here.
refine_frequencies, Components, crlb_frequency_std
    The public estimator for a fixed number of components.  Usually one FFT
    (:mod:`dsp.line_fast`): the strongest peaks of the Hann-windowed spectrum,
    two-point Hann interpolation (close peaks first freed of each other's side
    lobes), the unweighted Gauss-Newton fit from projections
    (:func:`dsp.line_gn.projection_fit`, maximum likelihood for white Gaussian
    noise; usually one step), and a look at the residual's spectrum near and
    away from the lines.  That fit runs as numpy or compiled
    (:mod:`dsp._line_kernel`, ``engine``).  When it declines (lines closer than
    a main lobe, weak lines, a line left in the residual): ``naff`` then the
    unweighted ``fit_lines`` polish.  ``dsp.quasiperiodic.decompose`` uses ``naff`` and ``fit_lines``
    with an offset, detection thresholds and a Hann-weighted fit.

Units: times in s, frequencies in Hz (cycles per unit of the time argument in
the low-level functions), amplitudes in the unit of the signal.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from .errors import SignalError, check_band, check_signal
from .line_fast import ENGINES, _fast_fit
from .line_fit import LineFit, fit_lines
from .line_gn import LOBE, _hann, gauss_newton, peak_nu

__all__ = ["window_weights", "spectrum", "naff", "LineFit", "fit_lines",
           "Components", "refine_frequencies", "crlb_frequency_std", "WINDOWS"]

WINDOWS = ("hann", "rect")
PAD = 2                    #: zero padding of the search spectrum (FFT length >= PAD x N)
SEARCH_ITER = 1            #: Gauss-Newton steps on the lines found so far, during the search


def window_weights(n, kind="hann"):
    """Analysis window of ``n`` samples.

    Parameters
    ----------
    n : int
        Number of samples.
    kind : {"hann", "rect"}
        "hann": the periodic Hann window sampled at the sample midpoints,
        ``0.5 - 0.5 cos(2 pi (k + 1/2) / n)``, which has no zero samples (every
        sample keeps a positive weight in a weighted fit); "rect" (also
        "none" or None): ones.

    Returns
    -------
    numpy.ndarray
        Weights in (0, 1] [-].

    Raises
    ------
    SignalError
        Unknown ``kind`` (a :class:`ValueError`).
    """
    if kind == "hann":
        return _hann(int(n)).copy()
    if kind in ("rect", "none", None):
        return np.ones(n)
    raise SignalError(f"window: must be 'hann' or 'rect', got {kind!r}")


def spectrum(x, w, dt, pad=1):
    """Windowed amplitude spectrum ``|FFT(w x)| / sum(w)`` on its frequency grid.

    Parameters
    ----------
    x : numpy.ndarray
        Real or complex samples.
    w : numpy.ndarray
        Window (:func:`window_weights`), same length.
    dt : float
        Sampling step [s].
    pad : int
        Zero padding: the FFT length is the power of two >= ``pad`` x N
        (``pad`` = 1: N, no padding).

    Returns
    -------
    freq_hz : numpy.ndarray
        Frequency of each bin [Hz] (``numpy.fft.fftfreq`` order, negative
        frequencies in the second half).
    magnitude : numpy.ndarray
        Amplitude of a line at that frequency [unit of x] (a line of amplitude
        a reads |a| at its own bin).
    """
    n = x.size
    nfft = n if pad <= 1 else 1 << int(math.ceil(math.log2(pad * n)))
    return np.fft.fftfreq(nfft, dt), np.abs(np.fft.fft(w * x, nfft)) / w.sum()


def naff(tc, z, w, n_lines, *, offset=False, min_relative_amplitude=0.0, snr_min=0.0):
    """Frequencies of the strongest lines of ``z`` by Laskar's NAFF search.

    For each line in turn: the peak of the zero-padded windowed spectrum of
    the residual (bins within the Hann main lobe, 2 / T, of a line already
    found -- or of 0 Hz when an ``offset`` is fitted -- are skipped), then a
    bounded Brent search maximising ``|sum w r e^{-2 pi i f tc}|`` within one
    padded bin of it, then all lines found so far (and the offset) are
    re-projected jointly (window-weighted least squares, i.e. Gram-Schmidt
    orthogonalisation) and subtracted from ``z``.

    Parameters
    ----------
    tc : numpy.ndarray
        Uniformly spaced sample times relative to the reference time [s]
        (e.g. centred on the middle of the record).
    z : numpy.ndarray
        Complex (or real) samples.
    w : numpy.ndarray
        Window (:func:`window_weights`).
    n_lines : int
        Largest number of lines to find.
    offset : bool
        Fit a constant offset along with the lines.
    min_relative_amplitude, snr_min : float
        Stop when the next peak is below ``min_relative_amplitude`` x the first
        peak or below ``snr_min`` x the median spectral level of the residual
        (0 and 0: always find ``n_lines``).

    Returns
    -------
    numpy.ndarray
        Frequencies [Hz] (cycles per unit of ``tc``), in the order found
        (possibly fewer than ``n_lines``).
    """
    n = z.size
    z = np.asarray(z, complex)
    dt = float(tc[-1] - tc[0]) / (n - 1)
    m = tc / dt
    m0 = float(m[0])
    nus = []
    r = gauss_newton(m0, m, z, w, [], offset)[3]
    first = None
    lobe = LOBE / n
    for _ in range(int(n_lines)):
        # zero-padded for the first line; the residual's lines are apart from the ones found
        grid, spec = spectrum(r, w, 1.0, 1 if nus else PAD)
        nfft = spec.size
        mask = np.abs(grid) < lobe if offset else np.zeros(nfft, bool)
        for nu in nus:
            mask |= np.abs(grid - nu) < lobe
        spec_m = np.where(mask, 0.0, spec)
        i = int(np.argmax(spec_m))
        peak = spec_m[i]
        if first is None:
            first = peak
            if peak == 0.0:
                break
        if peak < min_relative_amplitude * first or \
                (snr_min > 0 and peak < snr_min * float(np.median(spec))):
            break
        nus.append(peak_nu(spec, i, nfft))
        fit = gauss_newton(m0, m, z, w, nus, offset, max_iter=SEARCH_ITER)   # all lines so far
        nus, r = list(fit[0]), fit[3]
    return np.asarray(nus, dtype=float) / dt


# ---------------------------------------------------------------------------
# the public estimator
# ---------------------------------------------------------------------------

@dataclass(frozen=True)
class Components:
    """Complex-exponential components ``z(t) ≈ Σ a_k e^{2πi f_k (t - t0)}``.

    Attributes
    ----------
    frequency_hz, frequency_hz_std : numpy.ndarray
        Frequencies [Hz] (positive = forward whirl, negative = backward) and
        standard uncertainties (Cramér–Rao bound evaluated at the estimates
        with the residual noise, i.e. the inverse Fisher information of the
        joint fit; for a lone line it equals
        sqrt(6σ²/(|a|² N(N²-1)))·fs/2π).
    amplitude : numpy.ndarray (complex)
        Complex amplitudes at t0 = t[0] [unit of z].
    amplitude_std : numpy.ndarray
        Standard uncertainty of |a_k| [unit of z].
    noise_std : float
        RMS of the complex residual (sqrt(E|n|²)) [unit of z].
    n_samples : int
    """

    frequency_hz: np.ndarray
    frequency_hz_std: np.ndarray
    amplitude: np.ndarray
    amplitude_std: np.ndarray
    noise_std: float
    n_samples: int


def crlb_frequency_std(amplitude, noise_std, n_samples, sample_rate_hz=1.0):
    """Cramér–Rao bound on the std of a lone complex exponential's frequency [Hz].

    ``var(ω̂) ≥ 6σ² / (|A|² N (N² - 1))`` [rad/sample]² for
    ``A e^{i(ωn+φ)} + w[n]``, w complex white Gaussian with E|w|² = σ²
    (Rife & Boorstyn 1974).  Returned in Hz: ``sqrt(var)·fs/(2π)``.
    """
    N = float(n_samples)
    return math.sqrt(6 * noise_std ** 2 / (abs(amplitude) ** 2 * N * (N * N - 1))) * sample_rate_hz / (2 * math.pi)


def refine_frequencies(t, z, n_components, window="hann", polish=True, max_band_fraction=0.9,
                       engine="auto"):
    """Strongest complex-exponential components of ``z = x + i·y`` (NAFF-style).

    With ``polish`` (default) all frequencies and amplitudes are fitted jointly to
    the unwindowed data by Gauss-Newton: the maximum-likelihood estimate for white
    Gaussian noise, which removes the window's leakage bias between close lines
    and reaches the Cramér–Rao bound.  Usually in one FFT (:func:`_fast_fit`: the
    peaks of the ``window``-ed spectrum, interpolated, then the fit from
    projections and a look at the residual's spectrum); when that declines
    (lines closer than a main lobe, weak lines, a line left in the residual),
    the sequential :func:`naff` search with the ``window`` finds the lines and
    :func:`fit_lines` fits them.  Without ``polish``: :func:`naff`, then the fit
    weighted by the window.

    Parameters
    ----------
    t : array_like
        Uniformly sampled times [s].
    z : array_like
        Complex (or real) signal.
    n_components : int
        Number of components to extract.
    window : {"hann", "rect"}
        Window of the peak search (the Hann window also gives the two-point
        interpolation and the compiled fit).
    polish : bool
        Joint least-squares polish.
    max_band_fraction : float
        Raise :class:`SignalError` if a line lies above this fraction of
        Nyquist (probable aliasing, see :mod:`dsp.frequency`).
    engine : {"auto", "numba", "numpy"}
        The fit after the FFT (Hann window, with ``polish``): numpy, or the same
        steps compiled by numba (:mod:`dsp._line_kernel`; the same numbers to
        rounding, about 0.3 ms faster per estimate).  "auto" takes the compiled
        one once it costs next to nothing or has paid for itself in this process
        (:func:`_compiled_kernel`).

    Returns
    -------
    Components
        Sorted by decreasing |amplitude|.
    """
    n_components = int(n_components)
    if engine not in ENGINES:
        raise SignalError(f"engine: must be one of {', '.join(ENGINES)}, got {engine!r}")
    t, z, dt = check_signal(t, z, "z", min_samples=32)
    N = z.size
    if not 1 <= n_components <= N // 8:
        raise SignalError(f"n_components: must be in 1..{N // 8} for {N} samples, got {n_components}")
    z = np.asarray(z, complex)
    w = _hann(N) if window == "hann" else window_weights(N, window)
    t_ref = 0.5 * (t[0] + t[-1])                # centred (decorrelates phase and frequency)
    fit = _fast_fit(z, w, n_components, dt, engine, window == "hann") if polish else None
    if fit is None:                             # the sequential search and the general fit
        tc = t - t_ref
        f = naff(tc, z, w, n_components)
        fit = fit_lines(tc, z, np.ones(N) if polish else w, f, optimise=polish)
    f_hz = fit.frequency
    amp_std = fit.amplitude_std_all()
    a0 = fit.amplitude * np.exp(2j * math.pi * f_hz * (t[0] - t_ref))   # refer to t[0]
    check_band(f_hz, 1.0 / dt, max_band_fraction, "z")
    o = np.argsort(-np.abs(a0))
    return Components(frequency_hz=f_hz[o], frequency_hz_std=fit.frequency_std()[o],
                      amplitude=a0[o], amplitude_std=amp_std[o],
                      noise_std=math.sqrt(2 * fit.noise_var), n_samples=N)
