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
    Laskar's NAFF search: windowed spectrum peak, bounded Brent refinement of
    the windowed Fourier integral beyond the FFT bin, Gram-Schmidt (weighted
    least-squares) subtraction of the lines found so far; optional constant
    offset and detection thresholds.
fit_lines
    Joint (window-weighted) nonlinear least-squares fit of all frequencies and
    complex amplitudes by variable projection; sandwich covariance with the
    residual as noise (for uniform weights the inverse Fisher information,
    i.e. the Cramer-Rao bound evaluated at the estimates).
refine_frequencies, Components, crlb_frequency_std
    The public estimator for a fixed number of components: ``naff`` then the
    unweighted ``fit_lines`` polish (maximum likelihood for white Gaussian
    noise).  ``dsp.quasiperiodic.decompose`` uses ``naff`` and ``fit_lines``
    with an offset, detection thresholds and a Hann-weighted fit.

Units: times in s, frequencies in Hz (cycles per unit of the time argument in
the low-level functions), amplitudes in the unit of the signal.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import optimize

from .errors import SignalError, check_band, check_signal

__all__ = ["window_weights", "spectrum", "naff", "LineFit", "fit_lines",
           "Components", "refine_frequencies", "crlb_frequency_std", "WINDOWS"]

WINDOWS = ("hann", "rect")
PAD = 8                    #: zero padding of the NAFF spectrum (FFT length >= PAD x N)
LOBE = 2.0                 #: half-width of the Hann main lobe, in frequency resolutions 1/T


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
        return 0.5 - 0.5 * np.cos(2.0 * math.pi * (np.arange(n) + 0.5) / n)
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


def _design(tc, freqs, offset):
    cols = [np.ones(tc.size, dtype=complex)] if offset else []
    cols += [np.exp(2j * math.pi * f * tc) for f in freqs]
    return np.column_stack(cols) if cols else np.zeros((tc.size, 0), complex)


def _wls(B, z, sw):
    """Weighted linear least squares: coefficients of the columns of B."""
    if B.shape[1] == 0:
        return np.zeros(0, complex)
    return np.linalg.lstsq(B * sw[:, None], z * sw, rcond=None)[0]


def _refine_peak(tc, r, w, f0, half_width):
    """Maximise |sum w r e^{-2 pi i f tc}| over [f0 - hw, f0 + hw] (bounded Brent)."""
    wr = w * r

    def neg(f):
        return -abs(np.dot(wr, np.exp(-2j * math.pi * f * tc)))

    res = optimize.minimize_scalar(neg, bounds=(f0 - half_width, f0 + half_width),
                                   method="bounded", options={"xatol": half_width * 1e-9})
    return float(res.x)


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
    dt = float(tc[-1] - tc[0]) / (n - 1)
    T = n * dt
    sw = np.sqrt(w)
    freqs = []
    B = _design(tc, freqs, offset)
    r = z - B @ _wls(B, z, sw)
    first = None
    for _ in range(int(n_lines)):
        grid, spec = spectrum(r, w, dt, PAD)
        mask = np.abs(grid) < LOBE / T if offset else np.zeros(grid.size, bool)
        for f in freqs:
            mask |= np.abs(grid - f) < LOBE / T
        spec_m = np.where(mask, 0.0, spec)
        i = int(np.argmax(spec_m))
        peak = spec_m[i]
        if first is None:
            first = peak
            if peak == 0.0:
                break
        if peak < min_relative_amplitude * first or peak < snr_min * float(np.median(spec)):
            break
        freqs.append(_refine_peak(tc, r, w, grid[i], grid[1] - grid[0]))
        B = _design(tc, freqs, offset)
        r = z - B @ _wls(B, z, sw)                        # Gram-Schmidt subtraction
    return np.asarray(freqs, dtype=float)


@dataclass(frozen=True)
class LineFit:
    """Result of :func:`fit_lines`.

    Attributes
    ----------
    frequency : numpy.ndarray (K,)
        Frequencies [Hz] (cycles per unit of ``tc``).
    amplitude : numpy.ndarray (K,) complex
        Complex amplitudes at tc = 0 [unit of z].
    offset : complex
        Fitted constant (0 when no offset was fitted).
    residual : numpy.ndarray
        z minus the fitted model.
    cov : numpy.ndarray
        Covariance of the real parameters [f_1..f_K, then (Re, Im) of each
        column of the design: the offset first when fitted, then line 1..K].
    noise_var : float
        Noise variance per real component (window-weighted residual power,
        corrected for the fitted parameters).
    has_offset : bool
    """

    frequency: np.ndarray
    amplitude: np.ndarray
    offset: complex
    residual: np.ndarray
    cov: np.ndarray
    noise_var: float
    has_offset: bool

    def frequency_std(self):
        """Standard uncertainties of the frequencies [Hz]."""
        k = self.frequency.size
        return np.sqrt(np.maximum(np.diag(self.cov)[:k], 0.0))

    def _block(self, col):
        j = self.frequency.size + 2 * col
        return self.cov[j:j + 2, j:j + 2]

    def offset_cov(self):
        """2x2 covariance of (Re, Im) of the offset (NaN without an offset)."""
        return self._block(0) if self.has_offset else np.full((2, 2), np.nan)

    def amplitude_std(self, k):
        """(std of |a_k|, std of arg a_k [rad]) of line ``k`` (0-based)."""
        C = self._block(k + int(self.has_offset))
        a = self.amplitude[k]
        amp = abs(a)
        if amp > 0:
            u = np.array([a.real, a.imag]) / amp
            v = np.array([-a.imag, a.real]) / amp
            return math.sqrt(max(u @ C @ u, 0.0)), math.sqrt(max(v @ C @ v, 0.0)) / amp
        return math.sqrt(max(np.trace(C) / 2, 0.0)), math.pi


def fit_lines(tc, z, w, freqs, *, offset=False, optimise=True):
    """Joint weighted least-squares fit of line frequencies and amplitudes.

    Minimises ``sum w |z - c0 - sum_k c_k e^{2 pi i f_k tc}|^2`` over the
    frequencies (Levenberg-Marquardt) with the complex amplitudes solved
    linearly at each step (variable projection).  With uniform weights this
    is the maximum-likelihood estimate for white Gaussian noise (it removes
    the window's leakage bias between close lines); Hann weights suppress the
    leakage of lines that are not modelled.

    Standard uncertainties: sandwich covariance ``A^-1 B A^-1`` with
    ``A = J^T W J``, ``B = s^2 J^T W^2 J`` (J: Jacobian of the model in the
    real parameters, s^2 the weighted residual power per real component with
    a degrees-of-freedom correction); for uniform weights ``s^2 (J^T J)^-1``.

    Parameters
    ----------
    tc : numpy.ndarray
        Sample times relative to the reference time [s].
    z : numpy.ndarray
        Complex samples.
    w : numpy.ndarray
        Weights (:func:`window_weights`).
    freqs : array_like
        Starting frequencies [Hz] (e.g. from :func:`naff`).
    offset : bool
        Fit a constant offset.
    optimise : bool
        False: keep ``freqs`` and only solve the amplitudes (and covariance).

    Returns
    -------
    LineFit
    """
    sw = np.sqrt(w)
    f0 = np.asarray(freqs, dtype=float)
    n = z.size
    T = n * float(tc[-1] - tc[0]) / (n - 1)

    def resid(p):
        B = _design(tc, f0 + p / T, offset)
        r = sw * (z - B @ _wls(B, z, sw))
        return np.concatenate([r.real, r.imag])

    f = f0
    if optimise and f0.size:
        sol = optimize.least_squares(resid, np.zeros(f0.size), method="lm", xtol=1e-14,
                                     ftol=1e-14, gtol=1e-14, max_nfev=200 * (f0.size + 1))
        f = f0 + sol.x / T
    B = _design(tc, f, offset)
    c = _wls(B, z, sw)
    r = z - B @ c
    j0 = int(offset)
    cols = [2j * math.pi * tc * c[j0 + k] * B[:, j0 + k] for k in range(f.size)]
    for j in range(B.shape[1]):
        cols += [B[:, j], 1j * B[:, j]]
    Jc = np.column_stack(cols)
    J = np.vstack([Jc.real, Jc.imag])
    W = np.concatenate([w, w])
    dof = max(2 * n - J.shape[1], 1)
    sigma2 = float(np.sum(w * np.abs(r) ** 2) / (2.0 * np.sum(w))) * (2 * n) / dof
    A = J.T @ (J * W[:, None])
    Bm = J.T @ (J * (W ** 2)[:, None]) * sigma2
    try:
        Ai = np.linalg.inv(A)
        cov = Ai @ Bm @ Ai
    except np.linalg.LinAlgError:
        cov = np.full((J.shape[1], J.shape[1]), np.nan)
    return LineFit(frequency=f, amplitude=c[j0:], offset=complex(c[0]) if offset else 0j,
                   residual=r, cov=cov, noise_var=sigma2, has_offset=bool(offset))


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


def refine_frequencies(t, z, n_components, window="hann", polish=True, max_band_fraction=0.9):
    """Strongest complex-exponential components of ``z = x + i·y`` (NAFF-style).

    :func:`naff` (Laskar's NAFF with the ``window``) finds ``n_components``
    lines; with ``polish`` (default) :func:`fit_lines` then fits all
    frequencies and amplitudes jointly to the unwindowed data (the
    maximum-likelihood estimate for white Gaussian noise; it removes the
    window's leakage bias between close lines and reaches the Cramér–Rao
    bound).  Without ``polish`` the amplitudes are the window-weighted
    least-squares ones at the NAFF frequencies.

    Parameters
    ----------
    t : array_like
        Uniformly sampled times [s].
    z : array_like
        Complex (or real) signal.
    n_components : int
        Number of components to extract.
    window : {"hann", "rect"}
        Window for the NAFF stage.
    polish : bool
        Joint least-squares polish.
    max_band_fraction : float
        Raise :class:`SignalError` if a line lies above this fraction of
        Nyquist (probable aliasing, see :mod:`dsp.frequency`).

    Returns
    -------
    Components
        Sorted by decreasing |amplitude|.
    """
    n_components = int(n_components)
    t, z, dt = check_signal(t, z, "z", min_samples=32)
    N = z.size
    if not 1 <= n_components <= N // 8:
        raise SignalError(f"n_components: must be in 1..{N // 8} for {N} samples, got {n_components}")
    z = z.astype(complex)
    w = window_weights(N, window)
    t_ref = 0.5 * (t[0] + t[-1])
    tc = t - t_ref                              # centred (decorrelates phase and frequency)
    f = naff(tc, z, w, n_components)
    fit = fit_lines(tc, z, np.ones(N) if polish else w, f, optimise=polish)
    f_hz = fit.frequency
    amp_std = np.array([fit.amplitude_std(k)[0] for k in range(f_hz.size)])
    a0 = fit.amplitude * np.exp(2j * math.pi * f_hz * (t[0] - t_ref))   # refer to t[0]
    check_band(f_hz, 1.0 / dt, max_band_fraction, "z")
    o = np.argsort(-np.abs(a0))
    return Components(frequency_hz=f_hz[o], frequency_hz_std=fit.frequency_std()[o],
                      amplitude=a0[o], amplitude_std=amp_std[o],
                      noise_std=math.sqrt(2 * fit.noise_var), n_samples=N)
