"""Natural frequency, damping and spectral lines from signals.

Plain arrays in, frozen dataclasses with standard uncertainties out.  Units are
SI; field names say whether a frequency is in Hz or rad/s.

Contents
--------
free_decay
    Matrix pencil (Hua & Sarkar 1990) on the decimated record, then a
    nonlinear least-squares refinement on all samples whose Jacobian gives the
    standard uncertainties.
photogate_period, frequency_from_crossings
    The pulse-counter / photo-gate method (period from threshold crossings):
    an independent second estimate (ch5_multiball.md "Pulse counter").
resonance_from_runup
    Resonance peak of a run-up/run-down amplitude curve with the sweep-rate
    lag removed (papers_001_003_004.md §4.3 and §5.4).
refine_frequencies
    NAFF-style (Laskar) refinement of complex-exponential components followed
    by a joint maximum-likelihood polish; the core of the quasi-periodic
    decomposition.

Aliasing
--------
A line above the Nyquist frequency folds back into the band and *cannot* be
recognised from the samples alone.  What can be detected is a line near the
band edge (where folded lines land when they are only slightly above Nyquist):
``free_decay`` and ``refine_frequencies`` raise :class:`SignalError` when an
identified frequency lies above ``max_band_fraction`` (default 0.9) of the
Nyquist frequency.  Sample at least ~5x the highest expected frequency.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import optimize, signal as _sig

from .errors import SignalError, check_signal, check_times

__all__ = [
    "FreeDecay", "free_decay",
    "CrossingFrequency", "photogate_period", "frequency_from_crossings", "crossing_times",
    "RunupResonance", "resonance_from_runup", "sweep_lag_rad_s", "U_STAR",
    "Components", "refine_frequencies", "crlb_frequency_std",
]

#: Argument of the maximum of |∫_{-∞}^u exp(iπs²/2) ds| (papers digest §4.3).
U_STAR = 1.2172


def _band_check(freq_hz, fs, max_band_fraction, what):
    nyq = 0.5 * fs
    f = np.atleast_1d(np.abs(np.asarray(freq_hz, dtype=float)))
    if (f > max_band_fraction * nyq).any():
        raise SignalError(
            f"{what}: line at {float(f.max()):.6g} Hz lies within the top "
            f"{100 * (1 - max_band_fraction):.3g} % of the band (Nyquist {nyq:.6g} Hz); "
            f"the signal is probably aliased (a component above Nyquist folds back "
            f"near the band edge) -- sample faster or low-pass filter before sampling")


# ---------------------------------------------------------------------------
# free decay
# ---------------------------------------------------------------------------

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
    """Frequencies [Hz] of the ``n`` strongest local maxima of the Hann spectrum."""
    x = x - x.mean()
    w = np.hanning(x.size)
    spec = np.abs(np.fft.fft(x * w))
    freqs = np.fft.fftfreq(x.size, 1.0 / fs)
    if not np.iscomplexobj(x):
        keep = freqs >= 0
        spec, freqs = spec[keep], freqs[keep]
    order = np.argsort(spec)[::-1]
    return freqs[order[:max(n, 1)]], spec


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
    f_pk, _ = _fft_peak_hz(x, fs, n_modes)
    _band_check(f_pk, fs, max_band_fraction, "x")

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
    _band_check([o.frequency_hz for o in out], fs, max_band_fraction, "x")
    out.sort(key=lambda o: -o.amplitude)
    return out[0] if n_modes == 1 else tuple(out)


# ---------------------------------------------------------------------------
# photo-gate / crossings
# ---------------------------------------------------------------------------

@dataclass(frozen=True)
class CrossingFrequency:
    """Frequency from threshold crossings.

    Attributes
    ----------
    frequency_hz, frequency_hz_std : float
        1/period [Hz] and its standard uncertainty.
    period_s, period_s_std : float
        Period [s] and its standard uncertainty.
    n_crossings : int
        Crossings used.
    crossing_times_s : tuple of float
        All crossing times [s].
    rising : tuple of bool
        Direction of each crossing (True = upward).
    """

    frequency_hz: float
    frequency_hz_std: float
    period_s: float
    period_s_std: float
    n_crossings: int
    crossing_times_s: tuple
    rising: tuple


def photogate_period(crossing_times, start=1, stop=3):
    """Period from the ``start``-th to the ``stop``-th threshold crossing (FPM-09).

    The pulse counter of the stand measures the time between the 1st and 3rd
    crossings of a threshold by a free-decay signal (ch5_multiball.md, "Pulse
    counter"): crossings alternate in direction, so crossings ``start`` and
    ``start + 2`` are one period apart.

    Parameters
    ----------
    crossing_times : array_like
        Crossing times [s], alternating directions, strictly increasing.
    start, stop : int
        1-based crossing numbers; ``stop - start`` must be a positive even
        number (a whole number of periods, ``(stop - start) / 2``).

    Returns
    -------
    float
        Period [s].
    """
    start, stop = int(start), int(stop)
    if start < 1 or stop <= start or (stop - start) % 2:
        raise SignalError(f"start={start}, stop={stop}: need 1 <= start < stop with stop - start even "
                          f"(crossings alternate direction)")
    ct = check_times(crossing_times, "crossing_times", min_samples=stop)
    return float((ct[stop - 1] - ct[start - 1]) / ((stop - start) / 2))


def crossing_times(t, x, level=0.0, hysteresis=0.0, method="fit"):
    """Times at which ``x`` crosses ``level``.

    Parameters
    ----------
    t, x : array_like
        Uniformly sampled real signal.
    level : float
        Threshold.
    hysteresis : float
        Schmitt-trigger half width (units of x): a crossing counts only once
        the signal has moved beyond ``level ± hysteresis``; suppresses noise
        chatter.  The reported time is still the crossing of ``level``.
    method : {"fit", "cubic", "linear"}
        "linear"/"cubic": interpolation through the 2/4 samples around the
        crossing (what a hardware gate sees).  "fit" (default): least-squares
        cubic over ±10 % of the typical crossing spacing, which averages
        broadband noise on densely sampled records; its derivative also gives
        a noise-robust slope for the weights.

    Returns
    -------
    times : numpy.ndarray
        Crossing times [s].
    rising : numpy.ndarray of bool
        Direction of each crossing.
    slopes : numpy.ndarray
        |dx/dt| at each crossing (from the interpolant).
    """
    t, x, dt = check_signal(t, x, "x", min_samples=8, allow_complex=False)
    if method not in ("linear", "cubic", "fit"):
        raise SignalError(f"method: must be 'linear', 'cubic' or 'fit', got {method!r}")
    if hysteresis < 0:
        raise SignalError(f"hysteresis: must be >= 0, got {hysteresis}")
    y = x - level
    sgn = y > 0
    idx = np.flatnonzero(sgn[1:] != sgn[:-1])          # crossing between idx, idx+1
    if hysteresis > 0 and idx.size:
        keep = []
        state = None                                   # True = high
        hi = np.flatnonzero(y > hysteresis)
        lo = np.flatnonzero(y < -hysteresis)
        # walk through trigger events in time order
        ev = np.concatenate([hi, lo])
        kind = np.concatenate([np.ones(hi.size, bool), np.zeros(lo.size, bool)])
        o = np.argsort(ev, kind="stable")
        ev, kind = ev[o], kind[o]
        change = np.flatnonzero(np.concatenate([[True], kind[1:] != kind[:-1]]))
        for j in change:
            new = bool(kind[j])
            if state is not None and new != state:
                # last level crossing before this trigger in that direction
                k = np.searchsorted(idx, ev[j]) - 1
                while k >= 0 and bool(sgn[idx[k] + 1]) != new:
                    k -= 1
                if k >= 0 and (not keep or idx[k] > keep[-1]):
                    keep.append(idx[k])
            state = new
        idx = np.asarray(keep, dtype=int)
    times, slopes = [], []
    if method == "fit":
        gap = np.diff(idx)
        spacing = float(np.median(gap)) if gap.size else float(y.size)
        m = int(max(2, round(0.1 * spacing)))
    for i in idx:
        if method == "fit":
            j0, j1 = max(0, i - m + 1), min(y.size, i + m + 1)
            jj = np.arange(j0, j1) - i
            c1 = np.polyfit(jj, y[j0:j1], 1)
            slope = abs(c1[0]) / dt
            u = -c1[1] / c1[0] if c1[0] != 0 else y[i] / (y[i] - y[i + 1])
            if j1 - j0 >= 8:
                c3 = np.polyfit(jj, y[j0:j1], 3)
                roots = np.roots(c3)
                roots = roots[(np.abs(roots.imag) < 1e-9) & (roots.real >= jj[0]) & (roots.real <= jj[-1])].real
                if roots.size:
                    u = float(roots[np.argmin(np.abs(roots - u))])
            if not jj[0] <= u <= jj[-1]:
                u = y[i] / (y[i] - y[i + 1])
            times.append(t[i] + u * dt)
            slopes.append(slope)
            continue
        if method == "cubic" and 1 <= i and i + 2 < y.size:
            ii = np.arange(i - 1, i + 3)
            c = np.polyfit(ii - i, y[ii], 3)
            roots = np.roots(c)
            roots = roots[(np.abs(roots.imag) < 1e-9) & (roots.real >= -1e-9) & (roots.real <= 1 + 1e-9)].real
            if roots.size:
                u = float(roots[np.argmin(np.abs(roots - y[i] / (y[i] - y[i + 1])))])
                times.append(t[i] + u * dt)
                slopes.append(abs(np.polyval(np.polyder(c), u)) / dt)
                continue
        u = y[i] / (y[i] - y[i + 1])
        times.append(t[i] + u * dt)
        slopes.append(abs(y[i + 1] - y[i]) / dt)
    return np.asarray(times), sgn[idx + 1].astype(bool), np.asarray(slopes)


def frequency_from_crossings(t, x, level=0.0, hysteresis=0.0, method="fit"):
    """Frequency from successive same-direction crossings of ``level``.

    Rising crossings ``t = t_up + k T`` and falling crossings
    ``t = t_down + k T`` are fitted jointly by weighted least squares (common
    period ``T``; weight ∝ slope², since a crossing's timing error is
    noise / |dx/dt|).  The scatter of the residuals gives the standard
    uncertainty.  Independent of :func:`free_decay` (no model of the decay).

    Parameters
    ----------
    t, x : array_like
        Uniformly sampled real signal.
    level, hysteresis, method
        See :func:`crossing_times`.

    Returns
    -------
    CrossingFrequency
    """
    ct, rising, slope = crossing_times(t, x, level, hysteresis, method)
    nu, nd = int(rising.sum()), int((~rising).sum())
    if max(nu, nd) < 2 or ct.size < 3:
        raise SignalError(f"x: only {ct.size} crossing(s) of level {level} "
                          f"({nu} rising, {nd} falling); need two in the same direction")
    k = np.zeros(ct.size)
    k[rising] = np.arange(nu)
    k[~rising] = np.arange(nd)
    cols = [k]
    if nu:
        cols.append(rising.astype(float))
    if nd:
        cols.append((~rising).astype(float))
    A = np.column_stack(cols)
    w = slope / slope.max()
    sol, *_ = np.linalg.lstsq(A * w[:, None], ct * w, rcond=None)
    T = float(sol[0])
    r = (ct - A @ sol) * w
    dof = ct.size - A.shape[1]
    if dof > 0:
        s2 = float(r @ r) / dof
        cov = s2 * np.linalg.inv((A * w[:, None]).T @ (A * w[:, None]))
        Ts = float(math.sqrt(max(cov[0, 0], 0.0)))
    else:
        Ts = float("nan")
    return CrossingFrequency(frequency_hz=1.0 / T, frequency_hz_std=Ts / T ** 2, period_s=T,
                             period_s_std=Ts, n_crossings=int(ct.size),
                             crossing_times_s=tuple(ct.tolist()), rising=tuple(rising.tolist()))


# ---------------------------------------------------------------------------
# run-up resonance with sweep-rate correction
# ---------------------------------------------------------------------------

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


# ---------------------------------------------------------------------------
# NAFF-style refinement of complex exponentials
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
        Complex amplitudes at t0 = t[0].
    amplitude_std : numpy.ndarray
        Standard uncertainty of |a_k|.
    noise_std : float
        RMS of the complex residual (sqrt(E|n|²)).
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


def _window(n, kind):
    if kind in (None, "rect", "none"):
        return np.ones(n)
    if kind == "hann":
        return 0.5 * (1 - np.cos(2 * np.pi * np.arange(n) / (n - 1)))
    raise SignalError(f"window: must be 'hann' or 'rect', got {kind!r}")


def refine_frequencies(t, z, n_components, window="hann", polish=True, max_band_fraction=0.9):
    """Strongest complex-exponential components of ``z = x + i·y`` (NAFF-style).

    For each component in turn (Laskar's NAFF): the peak of the windowed FFT
    of the residual, then a bounded Brent search maximising
    ``|⟨r, e^{iωt}⟩_window|`` within ±1 bin, then all amplitudes found so far
    are re-projected jointly (window-weighted least squares = Gram–Schmidt
    orthogonalisation) and subtracted.  With ``polish`` (default) a joint
    nonlinear least-squares fit of all frequencies and amplitudes to the
    unwindowed data follows (the maximum-likelihood estimate for white
    Gaussian noise; it removes the window's leakage bias between close lines
    and reaches the Cramér–Rao bound).

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
        Nyquist (probable aliasing, see module docstring).

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
    w = _window(N, window)
    n = np.arange(N, dtype=float)
    nc = n - 0.5 * (N - 1)                     # centred index (decorrelates phase and ω)
    nfft = 1 << int(math.ceil(math.log2(2 * N)))
    binw = 2 * np.pi / N
    r = z.copy()
    oms = []
    for _ in range(n_components):
        spec = np.abs(np.fft.fft(r * w, nfft))
        k = int(np.argmax(spec))
        om0 = 2 * np.pi * np.fft.fftfreq(nfft)[k]

        def neg(om, r=r):
            return -abs(np.dot(w * r, np.exp(-1j * om * nc)))

        res = optimize.minimize_scalar(neg, bounds=(om0 - binw, om0 + binw), method="bounded",
                                       options={"xatol": 1e-6 * binw})
        oms.append(float(res.x))
        E = np.exp(1j * np.outer(nc, oms))
        sw = np.sqrt(w)
        amps = np.linalg.lstsq(E * sw[:, None], z * sw, rcond=None)[0]
        r = z - E @ amps
    oms = np.array(oms)
    K = n_components

    def unpack(p):
        return p[:K], p[K:2 * K] + 1j * p[2 * K:]

    def resid(p):
        om, a = unpack(p)
        rr = np.exp(1j * np.outer(nc, om)) @ a - z
        return np.concatenate([rr.real, rr.imag])

    def jac(p):
        om, a = unpack(p)
        E = np.exp(1j * np.outer(nc, om))
        J = np.hstack([1j * nc[:, None] * E * a, E, 1j * E])
        return np.vstack([J.real, J.imag])

    E = np.exp(1j * np.outer(nc, oms))
    amps = np.linalg.lstsq(E, z, rcond=None)[0] if polish else amps
    p = np.concatenate([oms, amps.real, amps.imag])
    if polish:
        sol = optimize.least_squares(resid, p, jac=jac, method="lm", x_scale="jac",
                                     xtol=1e-14, ftol=1e-14, gtol=1e-14)
        p = sol.x
    rr = resid(p)
    J = jac(p)
    dof = rr.size - p.size
    s2 = float(rr @ rr) / max(dof, 1)           # per real component
    try:
        cov = s2 * np.linalg.inv(J.T @ J)
    except np.linalg.LinAlgError:
        cov = np.full((p.size, p.size), np.nan)
    om, a = unpack(p)
    fs = 1.0 / dt
    f_hz = om * fs / (2 * np.pi)
    f_std = np.sqrt(np.maximum(np.diag(cov)[:K], 0)) * fs / (2 * np.pi)
    amp_std = np.empty(K)
    for k in range(K):
        g = np.array([a[k].real, a[k].imag]) / max(abs(a[k]), 1e-300)
        Ck = cov[np.ix_([K + k, 2 * K + k], [K + k, 2 * K + k])]
        amp_std[k] = math.sqrt(max(g @ Ck @ g, 0.0))
    a0 = a * np.exp(-1j * om * 0.5 * (N - 1))   # refer to t[0]
    _band_check(f_hz, fs, max_band_fraction, "z")
    o = np.argsort(-np.abs(a0))
    return Components(frequency_hz=f_hz[o], frequency_hz_std=f_std[o], amplitude=a0[o],
                      amplitude_std=amp_std[o], noise_std=math.sqrt(2 * s2), n_samples=N)
