"""The joint least-squares fit of line frequencies and amplitudes, and its result.

:func:`fit_lines` fits all frequencies and complex amplitudes of a sum of
complex exponentials (and optionally a constant offset) by Gauss-Newton on the
structured normal equations of :mod:`dsp.line_gn` (length-N sums, never an
N x P Jacobian), with a sandwich covariance; :class:`LineFit` holds the answer.
Used by :mod:`dsp.lines` (after the :func:`dsp.lines.naff` search) and by
:mod:`dsp.quasiperiodic`; the fast path :mod:`dsp.line_fast` returns a
:class:`LineFit` too.

Units: frequencies in Hz (cycles per unit of the time argument), amplitudes in
the unit of the signal.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .line_gn import Sums, columns, gauss_newton, normal_matrix, wls

__all__ = ["LineFit", "fit_lines"]


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
        Weights (:func:`dsp.lines.window_weights`).
    freqs : array_like
        Starting frequencies [Hz] (e.g. from :func:`dsp.lines.naff`).
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
