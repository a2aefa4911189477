"""The fast path of :func:`dsp.lines.refine_frequencies`: a fit of K lines in one FFT.

:func:`_fast_fit` takes the K strongest peaks of the windowed spectrum,
interpolates their frequencies (close peaks first freed of each other's side
lobes), fits all lines jointly from projections
(:func:`dsp.line_gn.projection_fit`, maximum likelihood for white Gaussian
noise; usually one step) and looks at the residual's spectrum near and away
from the lines.  With the Hann window the steps after the peaks run as numpy or
compiled (:mod:`dsp._line_kernel`, the rule of :func:`_compiled_kernel`).  When
it declines (lines closer than a main lobe, weak lines, a line left in the
residual) it returns None and :mod:`dsp.lines` searches sequentially.

Frequencies in cycles per sample inside, Hz in the returned
:class:`dsp.line_fit.LineFit`.
"""
from __future__ import annotations

import functools
import math
import time

import numpy as np

from . import _line_kernel
from ._line_kernel import MIN_LINE_SNR
from .line_fit import LineFit
from .line_gn import (HANN, LOBE, MAX_ITER, _hann, _power_sums, _residual as _residual_of,
                      columns, hann_delta, hann_peak_nu, peak_nu, projection_fit,
                      windowed_kernel)

__all__ = ["ENGINES"]


@functools.lru_cache(maxsize=16)
def _hann_sums(n):
    """(sum w, sum w^2) of the Hann window of ``n`` samples."""
    w = _hann(n)
    return float(w.sum()), float(np.dot(w, w))


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
    the fitted lines' size: :func:`dsp.lines.naff`'s sequential search is then used."""
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
    """Hann-windowed DFT (:func:`dsp.lines.window_weights`) at the FFT ``bins`` of unit lines
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
