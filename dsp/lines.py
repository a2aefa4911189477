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
fit_lines
    Joint (window-weighted) least-squares fit of all frequencies and complex
    amplitudes by Gauss-Newton on the structured normal equations
    (:mod:`dsp.line_gn`: length-N sums, never an N x P Jacobian); sandwich
    covariance with the residual as noise (for uniform weights the inverse
    Fisher information, i.e. the Cramer-Rao bound evaluated at the estimates).
refine_frequencies, Components, crlb_frequency_std
    The public estimator for a fixed number of components.  Usually one FFT
    (:func:`_fast_fit`): the strongest peaks of the Hann-windowed spectrum,
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

import functools
import math
import time
from dataclasses import dataclass

import numpy as np
from .errors import SignalError, check_band, check_signal
from ._line_kernel import MIN_LINE_SNR
from .line_gn import (HANN, MAX_ITER, Sums, _hann, _power_sums, _residual as _residual_of,
                      columns, gauss_newton, hann_delta, hann_peak_nu, normal_matrix, peak_nu,
                      projection_fit, windowed_kernel, wls)

__all__ = ["window_weights", "spectrum", "naff", "LineFit", "fit_lines",
           "Components", "refine_frequencies", "crlb_frequency_std", "WINDOWS"]

WINDOWS = ("hann", "rect")
PAD = 2                    #: zero padding of the search spectrum (FFT length >= PAD x N)
SEARCH_ITER = 1            #: Gauss-Newton steps on the lines found so far, during the search
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
        return _hann(int(n)).copy()
    if kind in ("rect", "none", None):
        return np.ones(n)
    raise SignalError(f"window: must be 'hann' or 'rect', got {kind!r}")


@functools.lru_cache(maxsize=16)
def _hann_sums(n):
    """(sum w, sum w^2) of the Hann window of ``n`` samples."""
    w = _hann(n)
    return float(w.sum()), float(np.dot(w, w))


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

    def amplitude_std_all(self):
        """Standard uncertainties of |a_k| of every line [unit of z] (see
        :meth:`amplitude_std`)."""
        K = self.frequency.size
        j = K + 2 * (np.arange(K) + int(self.has_offset))
        cxx, cyy, cxy = self.cov[j, j], self.cov[j + 1, j + 1], self.cov[j, j + 1]
        a = self.amplitude
        amp2 = np.abs(a) ** 2
        var = np.where(amp2 > 0, (a.real ** 2 * cxx + 2 * a.real * a.imag * cxy
                                  + a.imag ** 2 * cyy) / np.where(amp2 > 0, amp2, 1.0),
                       0.5 * (cxx + cyy))
        return np.sqrt(np.maximum(var, 0.0))

    def amplitude_std(self, k):
        """(std of |a_k|, std of arg a_k [rad]) of line ``k`` (0-based)."""
        s_amp = float(self.amplitude_std_all()[k])
        a = self.amplitude[k]
        amp = abs(a)
        if amp > 0:
            C = self._block(k + int(self.has_offset))
            v = np.array([-a.imag, a.real]) / amp          # the phase direction
            return s_amp, math.sqrt(max(v @ C @ v, 0.0)) / amp
        return s_amp, math.pi


def fit_lines(tc, z, w, freqs, *, offset=False, optimise=True):
    """Joint weighted least-squares fit of line frequencies and amplitudes.

    Minimises ``sum w |z - c0 - sum_k c_k e^{2 pi i f_k tc}|^2`` over the
    frequencies and amplitudes by Gauss-Newton on the structured normal
    equations (:mod:`dsp.line_gn`: sums of length N, never an N x P Jacobian;
    a halving line search keeps each step downhill).  With uniform weights this
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
    z = np.asarray(z, complex)
    n = z.size
    dt = float(tc[-1] - tc[0]) / (n - 1)
    m = tc / dt
    m0 = float(m[0])
    nu0 = np.asarray(freqs, dtype=float) * dt
    K = nu0.size
    if optimise:
        nus, c, cols, r, S = gauss_newton(m0, m, z, w, nu0, offset)
    else:
        nus, S = nu0, Sums(m, w)
        cols = columns(m0, n, nus, offset)
        c = wls(cols, z, w)
        r = z - (np.column_stack(cols) @ c if cols else 0)
    j0 = int(offset)
    if S.kind:
        A = normal_matrix(S.gram_nu(nus, offset), c, K, j0)
        Bm = A * w[0] if S.kind == "rect" else normal_matrix(S.gram_nu(nus, offset, True), c, K, j0)
    else:        # the Gram matrix of the final columns: gauss_newton's last one, or new
        A = normal_matrix(S.last_gram if optimise else S.gram(cols), c, K, j0)
        Bm = A * w[0] if np.all(w == w[0]) else normal_matrix(S.gram(cols, weight=w * w), c, K, j0)
    P = A.shape[0]
    dof = max(2 * n - P, 1)
    sigma2 = float(np.sum(w * np.abs(r) ** 2) / (2.0 * np.sum(w))) * (2 * n) / dof
    try:
        Ai = np.linalg.inv(A)
        cov = Ai @ Bm @ Ai * sigma2
    except np.linalg.LinAlgError:
        cov = np.full((P, P), np.nan)
    scale = np.ones(P)
    scale[:K] = 1.0 / dt                            # nu [cycles/sample] -> f [Hz]
    cov = cov * scale[:, None] * scale[None, :]
    return LineFit(frequency=np.asarray(nus, float) / dt, amplitude=c[j0:],
                   offset=complex(c[0]) if offset else 0j, residual=r, cov=cov,
                   noise_var=sigma2, has_offset=bool(offset))


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


ENGINES = ("auto", "numba", "numpy")
_numpy_seconds = 0.0       #: time this process has spent in the numpy fast path [s]


def _compiled_kernel(engine):
    """:func:`dsp._line_kernel.fit_after_peaks` compiled, or None for the numpy path.

    "numpy": never; "numba": whenever numba is available (compiling it the first time,
    about 15 s, then from numba's cache); "auto": when getting it costs next to nothing or
    has paid for itself.  Getting it costs importing numba and starting its compiler
    (about 0.4 s, nothing when the process has already imported numba) plus loading the
    kernel from numba's cache (milliseconds) or compiling it (about 15 s, once per
    install; ``stand warmup`` does it ahead).  It saves about 0.3 ms per estimate, so
    "auto" takes it once the numpy path has spent that cost in this process (the
    ski-rental rule: never more than twice the better choice's time) -- at once when numba
    is already imported and the kernel is in its cache."""
    if engine == "numpy":                       # (refine_frequencies checked ``engine``)
        return None
    from . import _line_kernel

    if engine == "auto" and _numpy_seconds < _line_kernel.load_cost():
        return None
    return _line_kernel.compiled()


def _fast_fit(z, w, K, dt, engine="auto", hann=False):
    """The common case in one FFT: the K strongest peaks of the windowed spectrum, each
    masked a main lobe wide once taken; their frequencies by the Hann two-point
    interpolation (``hann``: ``w`` is :func:`_hann`; else a parabola), close peaks first
    freed of each other's side lobes (:func:`_separate_peaks`); the projection fit
    (:func:`dsp.line_gn.projection_fit`); a look at the residual's spectrum near and away
    from the lines (:func:`_residual_extremes`, :func:`_holds_line`).  With the Hann window
    the steps after the peaks run as numpy or compiled (:func:`_compiled_kernel`, ``engine``).
    None when the fit declines (close or weak lines) or the residual still holds a line of
    the fitted lines' size: :func:`naff`'s sequential search is then used."""
    from scipy import fft as sfft      # pocketfft with SIMD: ~4x numpy.fft here

    n = z.size
    X = sfft.fft(w * z, overwrite_x=True)
    spec = np.abs(X)
    peaks, taken = [], []
    half = int(LOBE)
    for _ in range(K):
        i = int(spec.argmax())
        if spec[i] <= 0:
            return None
        peaks.append(i)
        idx = slice(i - half, i + half + 1) if half <= i < n - half else \
            np.arange(i - half, i + half + 1) % n
        taken.append((idx, spec[idx].copy()))
        spec[idx] = 0.0
    for idx, vals in reversed(taken):               # the spectrum as it was
        spec[idx] = vals
    nus = [(hann_peak_nu if hann else peak_nu)(spec, i, n) for i in peaks]
    separate = hann and K > 1 and _nearest_other(peaks, n) < CLOSE
    out = _fit_after_peaks_compiled(z, X, spec, peaks, nus, separate, engine) if hann else None
    if out is None:
        global _numpy_seconds
        t0 = time.perf_counter()
        if separate:
            nus = _separate_peaks(X, peaks, nus, n)
        fit = projection_fit(z, nus, MAX_ITER, MIN_LINE_SNR)
        out = None if fit is None else \
            fit + ((_residual_extremes(X, spec, fit[0], fit[1], n) if hann else None),)
        _numpy_seconds += time.perf_counter() - t0
    if out is None or out is DECLINED_FIT:
        return None
    nus, c, Ainv, cost, extremes = out
    cost = _honest_cost(z, nus, c, cost)
    if _holds_line(z, w, nus, c, cost, extremes, hann):
        return None
    P = Ainv.shape[0]
    sigma2 = cost / max(2 * n - P, 1)
    scale = np.ones(P)
    scale[:K] = 1.0 / dt                            # nu [cycles/sample] -> f [Hz]
    cov = Ainv * (sigma2 * scale[:, None] * scale[None, :])
    return LineFit(frequency=np.asarray(nus) / dt, amplitude=c, offset=0j,
                   residual=np.zeros(0, complex), cov=cov, noise_var=sigma2, has_offset=False)


DECLINED_FIT = object()     #: what :func:`_fit_after_peaks_compiled` returns for a declined fit


def _fit_after_peaks_compiled(z, X, spec, peaks, nus, separate, engine):
    """:func:`dsp._line_kernel.fit_after_peaks` when :func:`_compiled_kernel` gives it:
    (nus, c, Ainv, cost, (near_max, far_max)) or :data:`DECLINED_FIT`; None for the numpy
    path (no kernel, or it failed otherwise than on a singular or non-finite system: then
    it is disabled for the process, with a warning)."""
    kernel = _compiled_kernel(engine)
    if kernel is None:
        return None
    from . import _line_kernel

    n = z.size
    if not (z.flags.c_contiguous and z.flags.writeable):
        z = z.copy()                # one compiled signature: C-contiguous, writeable
    try:
        status, nus, c, Ainv, cost, near, far = kernel(
            z, X, spec, np.asarray(peaks, np.int64), np.asarray(nus, float), separate,
            np.array(_power_sums(n)), NEAR, MAX_ITER, MIN_LINE_SNR)
    except np.linalg.LinAlgError:                   # singular or non-finite, as the numpy
        return DECLINED_FIT                         # path's projection_fit declines
    except Exception as exc:                        # noqa: BLE001 - numba failing to compile
        _line_kernel.disable(f"{type(exc).__name__}: {exc}")
        return None
    if status != _line_kernel.OK:
        return DECLINED_FIT
    return nus, c, Ainv, cost, (near, far)


#: peaks nearer than this [bins] leak into each other's bins (the Hann window's side lobes
#: fall as 1 / (pi d^3): 2e-3 of the line at 5 bins, 6e-4 at 8)
CLOSE = 8


def _nearest_other(peaks, n):
    """Smallest distance [bins] between two of the ``peaks`` (bin indices, periodic)."""
    p = np.sort(np.asarray(peaks))
    gaps = np.diff(np.concatenate((p, p[:1] + n)))
    return int(gaps.min())


def _hann_response(bins, nus, n):
    """Hann-windowed DFT (:func:`window_weights`) at the FFT ``bins`` of unit lines
    e^{2 pi i nu m} on the centred grid of ``n`` samples: a (bins, lines) complex matrix.

    Each line is compared with its own image of the bin (FFT bins are periodic in j/n, the
    phasors on the centred grid are not): dnu = nu - j/n wrapped to [-1/2, 1/2), and the
    response is e^{2 pi i (nu - dnu) m0} sum_h weight_h S0(2 pi (dnu + h/n))
    (:func:`dsp.line_gn.windowed_kernel`), m0 = -(n-1)/2."""
    m0 = -0.5 * (n - 1)
    dnu = (nus - np.asarray(bins)[:, None] / n + 0.5) % 1.0 - 0.5
    return np.exp(2j * math.pi * (nus - dnu) * m0) * windowed_kernel(dnu, n, HANN)


def _separate_peaks(X, peaks, nus, n):
    """Start frequencies [cycles/sample] of lines whose peaks are close: the three bins around
    each peak of the windowed spectrum ``X`` without the other lines' windowed spectra
    (:func:`_hann_response`; each line's amplitude from its own peak bin), then the Hann
    two-point interpolation (:func:`dsp.line_gn.hann_delta`)."""
    K = len(peaks)
    peaks = np.asarray(peaks)
    bins = (peaks[:, None] + _THREE).ravel() % n                  # (3K,): line k's are 3k..3k+2
    Xb = X[bins]
    own = (np.arange(3 * K), np.repeat(np.arange(K), 3))
    leak = _hann_response(bins, np.asarray(nus, float), n)        # (3K, K)
    leak *= Xb[1::3] / leak[1::3].diagonal()                      # times each line's amplitude
    leak[own] = 0.0                                               # keep each line's own
    mag = np.abs(Xb - leak.sum(axis=1)).reshape(K, 3).tolist()
    nus = (peaks + np.array([hann_delta(*m) for m in mag])) / n
    return np.where(nus >= 0.5, nus - 1.0, nus)


#: bins either side of a fitted line where the residual's spectrum is computed exactly
NEAR = int(LOBE) + 2
_NEAR_BINS = np.arange(-NEAR, NEAR + 1)
_THREE = np.arange(-1, 2)


def _residual_extremes(X, spec, nus, c, n):
    """(Largest |X - the fitted lines' Hann responses| within ``NEAR`` bins of a line,
    largest of ``spec`` farther away), unscaled; ``spec`` is zeroed near the lines.  The
    numpy twin of :func:`dsp._line_kernel.residual_extremes`."""
    near = (np.rint(nus * n).astype(int)[:, None] + _NEAR_BINS).ravel() % n
    near_max = float(np.max(np.abs(X[near] - _hann_response(near, nus, n) @ c)))
    spec[near] = 0.0
    return near_max, float(spec.max())


def _holds_line(z, w, nus, c, cost, extremes, hann):
    """Whether the residual of a fit still holds a line of the fitted lines' size.

    A line taken for another, or one hidden in a stronger one's lobe, shows in the windowed
    spectrum of z minus the fitted lines.  With the Hann window ``extremes`` gives that
    spectrum's largest value near the lines (computed exactly from the FFT of the windowed
    record, the fitted lines' windowed spectra in closed form) and the record's own
    spectrum's largest value away from them (the fitted lines leak less than 1/80 of their
    amplitude there); only when one of them says "a line" is the exact residual
    transformed (one more FFT), so that leakage alone never rejects a fit.  A line counts
    when it exceeds 0.3 x the smallest fitted amplitude and 5 x the median spectral level
    of white noise of the residual's power.
    """
    n = z.size
    sw, sw2 = _hann_sums(n) if hann else (float(w.sum()), float(np.dot(w, w)))
    level = 5.0 * math.sqrt(math.log(2.0) * cost / n * sw2) / sw
    thr = max(0.3 * float(np.abs(c).min()), level)
    if hann and max(extremes) / sw <= thr:
        return False
    return _residual_spectrum_max(z, w, nus, c) > thr


def _residual(z, nus, c):
    """z minus the fitted lines (amplitudes ``c`` referred to the record's middle)."""
    return _residual_of(z, columns(-0.5 * (z.size - 1), z.size, nus, False), c)


#: below this fraction of the record's energy a fit's cost computed as |z|^2 minus the
#: fitted lines' energy has lost most of its digits (a signal-to-noise ratio above 90 dB:
#: a noiseless simulation, a clean synthetic test): it is then recomputed from the residual
CANCELLATION = 1e-9


def _honest_cost(z, nus, c, cost):
    """The fit's cost |z - lines|^2: ``cost`` as the fit computed it (by subtraction, which
    keeps about 14 digits of |z|^2), or from the residual itself when that is below
    :data:`CANCELLATION` x |z|^2 (the noise level and every uncertainty scale with it:
    a noise of 1e-9 on unit lines would otherwise read 0, or 1e-8)."""
    if cost >= CANCELLATION * float(np.vdot(z, z).real):
        return cost
    r = _residual(z, nus, c)
    return float(np.vdot(r, r).real)


def _residual_spectrum_max(z, w, nus, c):
    """Largest amplitude in the windowed spectrum of z minus the lines (one FFT)."""
    from scipy import fft as sfft

    r = _residual(z, nus, c)
    rs = np.abs(sfft.fft(w * r, overwrite_x=True)) / w.sum()
    return float(rs.max()) if rs.max() > 5 * np.median(rs) else 0.0


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
