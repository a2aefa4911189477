"""Damped natural frequency and damping ratio from a free decay.

Matrix pencil (Hua & Sarkar 1990) on the decimated record for the starting
poles, then a nonlinear least-squares refinement on all samples whose Jacobian
gives the standard uncertainties.  Part of :mod:`dsp.frequency` (re-exported
there); see its docstring for the aliasing check.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import optimize

from .errors import SignalError, check_band, check_signal
from .lines import spectrum, window_weights

__all__ = ["FreeDecay", "free_decay"]


@dataclass(frozen=True)
class FreeDecay:
    """One mode of a free decay ``A e^{-ζω_n t} cos(2π f_d t + φ)``.

    Attributes
    ----------
    frequency_hz, frequency_hz_std : float
        Damped natural frequency f_d [Hz] and its standard uncertainty.
    damping_ratio, damping_ratio_std : float
        Damping ratio ζ [-] and its standard uncertainty.
    natural_frequency_hz, natural_frequency_hz_std : float
        Undamped natural frequency f_n = f_d / sqrt(1 - ζ²) [Hz] and its
        standard uncertainty.
    amplitude : float
        Amplitude at the first sample (units of the signal).
    phase_rad : float
        Phase φ at the first sample [rad] (cosine convention; for complex
        signals the argument of the complex amplitude).
    snr_db : float
        Power of the fitted model over the residual variance [dB].
    n_samples : int
        Number of samples used in the least-squares fit.
    """

    frequency_hz: float
    frequency_hz_std: float
    damping_ratio: float
    damping_ratio_std: float
    natural_frequency_hz: float
    natural_frequency_hz_std: float
    amplitude: float
    phase_rad: float
    snr_db: float
    n_samples: int


def _matrix_pencil(y, order):
    """Poles z_k (per sample) of ``y`` by the matrix pencil method (Hua & Sarkar)."""
    n = y.size
    L = max(order + 1, n // 3)
    rows = n - L
    Y = np.lib.stride_tricks.sliding_window_view(y, L + 1)[:rows]
    _, _, vh = np.linalg.svd(Y, full_matrices=False)
    V = vh[:order].conj().T  # (L+1, order) right singular vectors
    A = np.linalg.pinv(V[:-1]) @ V[1:]
    return np.linalg.eigvals(A)


def _fft_peak_hz(x, fs, n=1):
    """Frequencies [Hz] of the ``n`` strongest bins of the windowed spectrum
    (:func:`dsp.lines.spectrum` with the Hann :func:`dsp.lines.window_weights`);
    non-negative frequencies only for a real ``x``."""
    freqs, spec = spectrum(x - x.mean(), window_weights(x.size), 1.0 / fs)
    if not np.iscomplexobj(x):
        keep = freqs >= 0
        spec, freqs = spec[keep], freqs[keep]
    order = np.argsort(spec)[::-1]
    return freqs[order[:max(n, 1)]]



def free_decay(t, x, n_modes=1, offset=True, max_band_fraction=0.9):
    """Damped frequency, damping ratio, amplitude and phase of a free decay.

    Matrix pencil (Hua & Sarkar) on a decimated copy of the record gives the
    starting poles; a nonlinear least-squares fit
    (:func:`scipy.optimize.least_squares`) of
    ``c0 + Σ e^{-σ_k t}(a_k cos ω_k t + b_k sin ω_k t)`` (real ``x``) or
    ``c0 + Σ c_k e^{(-σ_k + iω_k) t}`` (complex ``x``) to all samples refines
    them.  Standard uncertainties come from ``s² (JᵀJ)⁻¹`` with ``s²`` the
    residual variance (white noise assumed), propagated to ζ and f_n.

    Parameters
    ----------
    t : array_like
        Uniformly sampled times [s].
    x : array_like
        Real or complex signal (a complex x + i·y orbit gives one line per
        whirl direction; the sign of its frequency is lost in ``frequency_hz``,
        which is |f|).
    n_modes : int
        Number of damped modes to fit.
    offset : bool
        Fit a constant offset ``c0`` (recommended for probe signals).
    max_band_fraction : float
        Raise :class:`SignalError` if a mode lies above this fraction of the
        Nyquist frequency (probable aliasing).

    Returns
    -------
    FreeDecay or tuple of FreeDecay
        One :class:`FreeDecay` if ``n_modes == 1``, else a tuple sorted by
        decreasing amplitude.

    Raises
    ------
    SignalError
        Bad input (see :func:`dsp.errors.check_signal`), a line near the band
        edge, or no oscillating mode found.
    """
    n_modes = int(n_modes)
    if n_modes < 1:
        raise SignalError(f"n_modes: must be >= 1, got {n_modes}")
    t, x, dt = check_signal(t, x, "x", min_samples=max(32, 12 * n_modes))
    cplx = np.iscomplexobj(x)
    fs = 1.0 / dt
    N = x.size
    tt = t - t[0]
    f_pk = _fft_peak_hz(x, fs, n_modes)
    check_band(f_pk, fs, max_band_fraction, "x")

    # --- matrix pencil on a decimated copy (starting values only) ---
    f_top = max(float(np.max(np.abs(f_pk))), fs / N)
    q = int(np.clip(fs / (10.0 * f_top), 1, max(1, N // 64)))
    y = x[::q][:1024]
    order = (n_modes + 1) if cplx else (2 * n_modes + 2)
    order = min(order, y.size // 3)
    z = _matrix_pencil(y, order)
    z = z[np.abs(z) > 1e-12]
    s = np.log(z) / (q * dt)                      # continuous poles [1/s]
    V = np.exp(np.outer(np.arange(y.size) * q * dt, s))
    amp = np.abs(np.linalg.lstsq(V, y, rcond=None)[0])
    ok = np.abs(s.imag) > 2 * np.pi * 0.5 / (y.size * q * dt)   # oscillating
    if not cplx:
        ok &= s.imag > 0
    cand = np.flatnonzero(ok)
    if cand.size < n_modes:
        raise SignalError(f"x: found {cand.size} oscillating mode(s), asked for {n_modes}; "
                          f"is this a free decay?")
    cand = cand[np.argsort(amp[cand])[::-1][:n_modes]]
    s0 = s[cand]

    # --- nonlinear least squares on all samples ---
    scale = float(np.max(np.abs(x)))
    xs = x / scale

    def basis(p):
        sig = p[0:4 * n_modes:4]
        om = p[1:4 * n_modes:4]
        return np.exp(-np.outer(tt, sig)), om

    def model_parts(p):
        E, om = basis(p)
        ph = np.outer(tt, om)
        a = p[2:4 * n_modes:4]
        b = p[3:4 * n_modes:4]
        if cplx:
            C = E * np.exp(1j * ph)
            m = C @ (a + 1j * b)
        else:
            cs, sn = E * np.cos(ph), E * np.sin(ph)
            C = (cs, sn)
            m = cs @ a + sn @ b
        if offset:
            m = m + (p[-2] + 1j * p[-1] if cplx else p[-1])
        return m, C

    def resid(p):
        m, _ = model_parts(p)
        r = m - xs
        return np.concatenate([r.real, r.imag]) if cplx else r

    def jac(p):
        _, C = model_parts(p)
        cols = []
        for k in range(n_modes):
            a, b = p[4 * k + 2], p[4 * k + 3]
            if cplx:
                mk = C[:, k] * (a + 1j * b)
                cs = [-tt * mk, 1j * tt * mk, C[:, k], 1j * C[:, k]]
            else:
                c_, s_ = C[0][:, k], C[1][:, k]
                mk = c_ * a + s_ * b
                cs = [-tt * mk, tt * (-a * s_ + b * c_), c_, s_]
            cols.extend(cs)
        if offset:
            if cplx:
                cols += [np.ones(N, complex), 1j * np.ones(N)]
            else:
                cols += [np.ones(N)]
        J = np.column_stack(cols)
        return np.vstack([J.real, J.imag]) if cplx else J

    # linear amplitudes for the starting poles
    E0 = np.exp(np.outer(tt, s0))
    if cplx:
        Vl = np.column_stack([E0] + ([np.ones(N)] if offset else []))
        c = np.linalg.lstsq(Vl, xs.astype(complex), rcond=None)[0]
        lin = [(c[k].real, c[k].imag) for k in range(n_modes)]
        off = [c[-1].real, c[-1].imag] if offset else []
    else:
        Vl = np.column_stack([E0.real, E0.imag] + ([np.ones(N)] if offset else []))
        c = np.linalg.lstsq(Vl, xs, rcond=None)[0]
        # Re(e^{(-σ+iω)t}) = e^{-σt}cos, Im = e^{-σt}sin -> (a, b) = coefficients
        lin = [(c[k], c[n_modes + k]) for k in range(n_modes)]
        off = [c[-1]] if offset else []
    p0 = []
    for k in range(n_modes):
        p0 += [-s0[k].real, abs(s0[k].imag) if not cplx else s0[k].imag, *lin[k]]
    p0 = np.array(p0 + off, dtype=float)
    sol = optimize.least_squares(resid, p0, jac=jac, method="lm", x_scale="jac",
                                 xtol=1e-12, ftol=1e-12, gtol=1e-12)
    p = sol.x
    r = sol.fun
    J = sol.jac
    dof = r.size - p.size
    s2 = float(r @ r) / max(dof, 1)
    try:
        cov = s2 * np.linalg.inv(J.T @ J)
    except np.linalg.LinAlgError:
        cov = np.full((p.size, p.size), np.nan)
    m, _ = model_parts(p)
    if offset:
        m = m - (p[-2] + 1j * p[-1] if cplx else p[-1])
    noise_var = s2 * (2 if cplx else 1)
    snr_db = 10 * math.log10(max(float(np.mean(np.abs(m) ** 2)), 1e-300) / max(noise_var, 1e-300))

    out = []
    for k in range(n_modes):
        sig, om, a, b = p[4 * k:4 * k + 4]
        C = cov[4 * k:4 * k + 2, 4 * k:4 * k + 2]
        wd = abs(om)
        wn = math.hypot(sig, wd)
        zeta = sig / wn
        g_wn = np.array([sig / wn, wd / wn])
        g_z = np.array([wd ** 2 / wn ** 3, -sig * wd / wn ** 3])
        sd = lambda g: float(math.sqrt(max(g @ C @ g, 0.0)))  # noqa: E731
        if cplx:
            A, ph = math.hypot(a, b) * scale, math.atan2(b, a)
        else:
            A, ph = math.hypot(a, b) * scale, math.atan2(-b, a)
        out.append(FreeDecay(
            frequency_hz=wd / (2 * np.pi), frequency_hz_std=sd(np.array([0.0, 1.0])) / (2 * np.pi),
            damping_ratio=zeta, damping_ratio_std=sd(g_z),
            natural_frequency_hz=wn / (2 * np.pi), natural_frequency_hz_std=sd(g_wn) / (2 * np.pi),
            amplitude=A, phase_rad=ph, snr_db=snr_db, n_samples=N))
    check_band([o.frequency_hz for o in out], fs, max_band_fraction, "x")
    out.sort(key=lambda o: -o.amplitude)
    return out[0] if n_modes == 1 else tuple(out)
