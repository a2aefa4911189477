"""Quasi-periodic decomposition of the shaft (or laser-spot) orbit.

Issue 5, item 3; digest ch5 section 5.3 and section 8.2.  In a stuck-ball
("quasi-periodic") motion the orbit z = x + i y is, to first order in the
rotor's unbalance, the epitrochoid (5.237)

    Z = A_P e^{i Omega t} + A_N e^{i omega t}

with a slow forward **precession** at the balls' speed Omega (amplitude A_P)
and a fast forward **nutation** at the rotor speed omega (amplitude A_N).
k = omega / Omega; an integer k draws a closed curve with k - 1 petals, a
non-integer k a pattern of about round(k) - 1 petals that drifts; the curve is
curtate (no loops) if A_P Omega > A_N omega, normal (cusps) if equal, prolate
(loops) if smaller.

:func:`decompose` finds the spectral lines of z (signed frequencies: forward
> 0, backward < 0) with the line estimator of :mod:`dsp.lines` (the one behind
:func:`dsp.frequency.refine_frequencies`): the NAFF search
(:func:`dsp.lines.naff`: Hann-windowed spectrum peak, bounded scalar
refinement of the windowed Fourier integral beyond the FFT bin, Gram-Schmidt
subtraction of the lines found so far) with a constant offset and detection
thresholds, followed by the joint Hann-weighted nonlinear least-squares fit of
all frequencies and complex amplitudes (:func:`dsp.lines.fit_lines`, variable
projection), which removes the mutual leakage of the lines; standard
uncertainties come from the sandwich covariance of that fit with the residual
as noise.

:func:`unbalance_from_nutation` and :func:`damping_from_precession` invert the
amplitudes of (5.237) for e0 and H given the model parameters.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .errors import SignalError, check_signal
from .lines import fit_lines, naff, spectrum, window_weights
from .units import DEG_PER_RAD, converted

__all__ = ["Component", "QPDecomposition", "decompose", "unbalance_from_nutation",
           "damping_from_precession"]


@dataclass(frozen=True)
class Component:
    """One spectral line z_k(t) = amplitude e^{2 pi i f (t - t_ref)}.

    Attributes
    ----------
    frequency_hz, frequency_std_hz : float
        Signed frequency (forward > 0, backward < 0) [Hz] and its standard
        uncertainty.
    amplitude : complex
        Complex amplitude at the reference time t_ref [signal unit, e.g. m].
    amplitude_m, amplitude_std_m : float
        |amplitude| and its standard uncertainty.
    phase_rad, phase_std_rad : float
        arg(amplitude) at t_ref and its standard uncertainty.
    direction : str
        "forward" or "backward".
    """

    frequency_hz: float
    frequency_std_hz: float
    amplitude: complex
    amplitude_m: float
    amplitude_std_m: float
    phase_rad: float
    phase_std_rad: float
    direction: str

    phase_deg = converted("phase_rad", DEG_PER_RAD, "arg(amplitude) at t_ref [deg].")


@dataclass(frozen=True)
class QPDecomposition:
    """Result of :func:`decompose`.

    Attributes
    ----------
    components : list of Component
        Lines found, strongest first.
    offset, offset_std : complex, float
        Constant part of z (static deflection / beam offset) and its
        uncertainty (per real component).
    t_ref_s : float
        Reference time of the complex amplitudes (middle of the record) [s].
    precession, nutation : Component or None
        The identified precession (Omega) and nutation (omega) lines.
    precession_hz, precession_std_hz, nutation_hz, nutation_std_hz : float
        Their frequencies [Hz] (nan if not identified).
    precession_amplitude_m, precession_amplitude_std_m,
    nutation_amplitude_m, nutation_amplitude_std_m : float
        A_P and A_N and their uncertainties.
    k, k_std : float
        omega / Omega and its uncertainty.
    petals : int or None
        round(k) - 1 (the petals of the closed or nearly closed pattern).
    stationary : bool or None
        k is an integer within max(3 k_std, k_atol, 1e-9 k) (the last is a
        round-off floor for noise-free data): the pattern stands still;
        otherwise it drifts at ``pattern_drift_hz``.
    pattern_drift_hz : float
        Rotation rate of the petal pattern, Omega - (omega - Omega) / petals,
        in rev/s (0 for a stationary pattern; sign: forward > 0).
    shape_ratio, shape_ratio_std : float
        A_P Omega / (A_N omega) and its uncertainty.
    shape : str or None
        "curtate" (ratio > 1), "normal" (= 1 within 2 sigma or shape_rtol),
        "prolate" (< 1).
    residual_rms : float
        RMS of z minus the fitted lines (unmodelled lines + noise).
    sample_rate_hz, duration_s : float
    window : str
    """

    components: list
    offset: complex
    offset_std: float
    t_ref_s: float
    precession: Component | None
    nutation: Component | None
    precession_hz: float
    precession_std_hz: float
    nutation_hz: float
    nutation_std_hz: float
    precession_amplitude_m: float
    precession_amplitude_std_m: float
    nutation_amplitude_m: float
    nutation_amplitude_std_m: float
    k: float
    k_std: float
    petals: int | None
    stationary: bool | None
    pattern_drift_hz: float
    shape_ratio: float
    shape_ratio_std: float
    shape: str | None
    residual_rms: float
    sample_rate_hz: float
    duration_s: float
    window: str = "hann"
    notes: list = field(default_factory=list)


# ------------------------------------------------------------------ internals

def _component(fit, k):
    """Component of line k (0-based) of a :class:`dsp.lines.LineFit`."""
    f, a = float(fit.frequency[k]), complex(fit.amplitude[k])
    s_amp, s_ph = fit.amplitude_std(k)
    return Component(frequency_hz=f, frequency_std_hz=float(fit.frequency_std()[k]),
                     amplitude=a, amplitude_m=abs(a), amplitude_std_m=s_amp,
                     phase_rad=math.atan2(a.imag, a.real), phase_std_rad=s_ph,
                     direction="forward" if f > 0 else "backward")


# ----------------------------------------------------------------------- API

def decompose(t, z, n_components=4, rotor_speed_hz=None, *, window="hann",
              min_relative_amplitude=1e-5, snr_min=5.0, strong_fraction=0.01,
              k_atol=0.0, shape_rtol=0.0, polish=None):
    """Quasi-periodic decomposition of a complex orbit and precession/nutation analysis.

    Parameters
    ----------
    t : array_like (N,)
        Uniformly spaced sample times [s], strictly increasing.
    z : array_like (N,) complex
        Orbit x + i y [m] (or the spot track on the screen, any length unit).
    n_components : int
        Largest number of lines to extract (fewer if the spectrum runs out of
        lines above ``min_relative_amplitude`` x the strongest and ``snr_min`` x
        the median spectral level).
    rotor_speed_hz : float, optional
        Rotor frequency [Hz] (tachometer, keyphasor).  The nutation is then the
        line nearest to it (within 3 frequency resolutions 1/T or 0.5 %).
        Without it, the nutation is the highest-frequency forward line of at
        least ``strong_fraction`` x the strongest amplitude.
    window : {"hann", "rect"}
        Weighting of the search and of the joint fit.  Hann suppresses leakage
        of unmodelled lines (recommended for simulated or real orbits with
        combination tones); "rect" is the minimum-variance choice for exactly
        the fitted lines in white noise.
    polish : {None, "hann", "rect"}
        Weighting of the final joint fit when it differs from the search's
        (``"rect"``: the lines found above ``snr_min`` are refitted unweighted,
        the maximum-likelihood estimate when they are all the lines there are:
        at the Cramér-Rao bound).  None: the ``window``.
    min_relative_amplitude, snr_min : float
        Line-detection thresholds (see ``n_components``).
    strong_fraction : float
        Relative amplitude of a "strong" line (nutation without a rotor speed).
    k_atol : float
        Extra tolerance for calling k an integer (stationary pattern).
    shape_rtol : float
        Extra tolerance for calling the shape "normal".

    Returns
    -------
    QPDecomposition
        The precession is the strongest forward line other than the nutation.
        Amplitudes are in the unit of ``z``.

    Raises
    ------
    SignalError
        Non-uniform / non-monotonic time, NaN/inf, a constant signal, a rotor
        frequency above the Nyquist frequency, fewer than 2 periods of the
        slowest component (the precession, or the rotor) in the record.
    """
    if int(n_components) < 1:
        raise ValueError(f"n_components = {n_components!r}: must be >= 1")
    t, z, dt = check_signal(t, np.asarray(z).astype(complex), name="z", min_samples=16)
    n = z.size
    T = n * dt
    fs = 1.0 / dt
    notes = []
    if rotor_speed_hz is not None:
        fr = float(rotor_speed_hz)
        if not math.isfinite(fr) or fr <= 0:
            raise SignalError(f"rotor_speed_hz = {rotor_speed_hz!r}: must be a finite frequency > 0")
        if fr >= fs / 2:
            raise SignalError(f"rotor_speed_hz = {fr:.6g} Hz is at or above the Nyquist frequency "
                              f"{fs / 2:.6g} Hz of the sample rate {fs:.6g} Hz: the nutation line "
                              f"is aliased; record faster")
        if fr * T < 2.0:
            raise SignalError(f"record too short: {T:.4g} s holds {fr * T:.3g} rotor revolution(s) "
                              f"(need at least 2)")
    t_ref = 0.5 * (t[0] + t[-1])                   # middle of the record
    tc = t - t_ref
    w = window_weights(n, window)
    # the strongest line must be resolvable from the offset: >= 2 periods
    fgrid, spec = spectrum(z - np.sum(w * z) / w.sum(), w, dt)
    i0 = int(np.argmax(spec))
    if abs(fgrid[i0]) * T < 2.0:
        raise SignalError(f"record too short: the strongest component (about {fgrid[i0]:.3g} Hz) "
                          f"has fewer than 2 periods in {T:.4g} s; record at least 2 periods of "
                          f"the slowest component")
    freqs = naff(tc, z, w, int(n_components), offset=True,
                 min_relative_amplitude=min_relative_amplitude, snr_min=snr_min)
    if not freqs.size:
        raise SignalError("z: no spectral line found above the noise")
    fit = fit_lines(tc, z, w if polish in (None, window) else window_weights(n, polish), freqs,
                    offset=True)
    comps = [_component(fit, k) for k in range(fit.frequency.size)]
    comps.sort(key=lambda q: -q.amplitude_m)
    offset = fit.offset
    offset_std = math.sqrt(max(0.5 * float(np.trace(fit.offset_cov())), 0.0))
    strongest = comps[0].amplitude_m

    # --- identification
    nut = None
    if rotor_speed_hz is not None:
        tol = max(3.0 / T, 0.005 * fr)
        near = [q for q in comps if abs(q.frequency_hz - fr) <= tol]
        if near:
            nut = min(near, key=lambda q: abs(q.frequency_hz - fr))
        else:
            notes.append(f"no line within {tol:.3g} Hz of the rotor frequency {fr:.6g} Hz "
                         f"(no nutation: rotor balanced?)")
    else:
        fw = [q for q in comps if q.frequency_hz > 0 and q.amplitude_m >= strong_fraction * strongest]
        if len(fw) >= 2:
            nut = max(fw, key=lambda q: q.frequency_hz)
    prec_c = [q for q in comps if q.frequency_hz > 0 and q is not nut]
    if nut is not None:
        prec_c = [q for q in prec_c if q.frequency_hz < nut.frequency_hz]
    prec = max(prec_c, key=lambda q: q.amplitude_m) if prec_c else None
    if prec is not None and prec.frequency_hz * T < 2.0:
        raise SignalError(f"record too short: the precession ({prec.frequency_hz:.4g} Hz) has "
                          f"{prec.frequency_hz * T:.3g} period(s) in {T:.4g} s (need at least 2)")
    nan = float("nan")
    fP = prec.frequency_hz if prec else nan
    sP = prec.frequency_std_hz if prec else nan
    fN = nut.frequency_hz if nut else nan
    sN = nut.frequency_std_hz if nut else nan
    AP = prec.amplitude_m if prec else nan
    sAP = prec.amplitude_std_m if prec else nan
    AN = nut.amplitude_m if nut else nan
    sAN = nut.amplitude_std_m if nut else nan
    k = k_std = ratio = ratio_std = drift = nan
    petals = stationary = shape = None
    if prec is not None and nut is not None:
        k = fN / fP
        k_std = k * math.hypot(sN / fN, sP / fP)
        kr = int(round(k))
        petals = kr - 1
        stationary = bool(abs(k - kr) <= max(3.0 * k_std, k_atol, 1e-9 * k))  # round-off floor
        drift = 0.0 if stationary or petals < 1 else fP - (fN - fP) / petals
        ratio = AP * fP / (AN * fN) if AN > 0 else math.inf
        ratio_std = ratio * math.sqrt((sAP / AP) ** 2 + (sP / fP) ** 2 + (sAN / AN) ** 2
                                      + (sN / fN) ** 2) if AN > 0 else nan
        if abs(ratio - 1.0) <= max(2.0 * ratio_std, shape_rtol):
            shape = "normal"
        else:
            shape = "curtate" if ratio > 1.0 else "prolate"
    return QPDecomposition(
        components=comps, offset=offset, offset_std=offset_std, t_ref_s=float(t_ref),
        precession=prec, nutation=nut, precession_hz=fP, precession_std_hz=sP,
        nutation_hz=fN, nutation_std_hz=sN, precession_amplitude_m=AP,
        precession_amplitude_std_m=sAP, nutation_amplitude_m=AN, nutation_amplitude_std_m=sAN,
        k=k, k_std=k_std, petals=petals, stationary=stationary, pattern_drift_hz=drift,
        shape_ratio=ratio, shape_ratio_std=ratio_std, shape=shape,
        residual_rms=float(np.sqrt(np.mean(np.abs(fit.residual) ** 2))), sample_rate_hz=fs,
        duration_s=T, window=str(window), notes=notes)


# ------------------------------------------------------------ inverse models

def _D(w, H):
    return (w * w - 1.0) ** 2 + (H * w) ** 2


def unbalance_from_nutation(nutation_amplitude_m, rotor_speed_hz, natural_frequency_hz,
                            support_damping_H, r_star_m, amplitude_std_m=0.0):
    """Rotor unbalance e0 (units of the capacity) from the nutation amplitude, (5.237).

    A_N = r* e0 R^2 / sqrt(D(R)), D(R) = (R^2 - 1)^2 + H^2 R^2, R = omega / omega_1,
    so e0 = (A_N / r*) sqrt(D(R)) / R^2.  First order in e0: at e0 = 0.3 the
    simulated nutation exceeds it by a few per cent (digest ch5 section 5.3:
    7 %; ball_stuck.toml: 2.6 %), so the estimate is biased high for large e0.

    Parameters
    ----------
    nutation_amplitude_m : float
        A_N [m] (same unit as ``r_star_m``).
    rotor_speed_hz, natural_frequency_hz : float
        omega / 2 pi and omega_1 / 2 pi [Hz].
    support_damping_H : float
        H = H_x / (omega_1 M_Sigma) (= 2 zeta).
    r_star_m : float
        r* = R_m l = n m l / M_Sigma [m] (the length unit of the theory).
    amplitude_std_m : float
        Uncertainty of A_N, propagated.

    Returns
    -------
    (e0, e0_std) : tuple of float
    """
    for name, v in (("nutation_amplitude_m", nutation_amplitude_m), ("rotor_speed_hz", rotor_speed_hz),
                    ("natural_frequency_hz", natural_frequency_hz), ("r_star_m", r_star_m)):
        if not (math.isfinite(float(v)) and float(v) > 0):
            raise ValueError(f"{name} = {v!r}: must be a finite number > 0")
    H = float(support_damping_H)
    if not (math.isfinite(H) and H >= 0):
        raise ValueError(f"support_damping_H = {H!r}: must be finite and >= 0")
    R = float(rotor_speed_hz) / float(natural_frequency_hz)
    g = math.sqrt(_D(R, H)) / (R * R) / float(r_star_m)
    return float(nutation_amplitude_m) * g, float(amplitude_std_m) * g


def damping_from_precession(precession_amplitude_m, precession_hz, natural_frequency_hz,
                            r_star_m):
    """Support damping H from the precession amplitude, (5.237).

    A_P / r* = W^2 / sqrt((1 - W^2)^2 + H^2 W^2), W = Omega / omega_1, so
    H = sqrt((W^2 r* / A_P)^2 - (1 - W^2)^2) / W.  Ill-conditioned away from
    W = 1 (the H term must dominate |1 - W^2|); stuck-ball motions run at
    W slightly below 1, where it works.

    Returns
    -------
    float
        H = H_x / (omega_1 M_Sigma).

    Raises
    ------
    SignalError
        If the amplitude is inconsistent with the model (A_P too large for any
        H >= 0 at this W).
    """
    A = float(precession_amplitude_m) / float(r_star_m)
    W = float(precession_hz) / float(natural_frequency_hz)
    if not (math.isfinite(A) and A > 0 and math.isfinite(W) and W > 0):
        raise ValueError("precession_amplitude_m, precession_hz, natural_frequency_hz, r_star_m: "
                         "must be finite and > 0")
    q = (W * W / A) ** 2 - (1.0 - W * W) ** 2
    if q < 0:
        raise SignalError(f"precession amplitude {A:.4g} r* exceeds the undamped response "
                          f"W^2/|1 - W^2| = {W * W / abs(1 - W * W):.4g} r* at W = {W:.5g}: "
                          f"inconsistent with the model (check r*, f1)")
    return math.sqrt(q) / W
