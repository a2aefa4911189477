"""Modal fit of a steady 1X (Bode / polar) table: natural frequency, damping, unbalance.

The steady unbalance response of a mode (the rigid rotor on isotropic supports,
monograph ch. 5) at the speed Omega is, in the complex 1X vector,

    z1(Omega) = q r^2 / (1 - r^2 + 2 i zeta r) + c,      r = Omega / omega_0,

with q = e e^{i beta} the specific unbalance [m] and c a constant vector (the probe's
slow-roll runout).  The fit is a rational fit on the Nyquist (polar) plot: linear in the
complex (q, c), nonlinear in (omega_0, zeta), solved by variable projection; the circle
the response draws on the polar plot is the model's, so it is a circle fit with the
speed along the circle accounted for.  The half-power bandwidth of |z1 - c| / r^2 (the
receptance's magnitude) is the cross-check: zeta_hp = (Omega_2 - Omega_1) / (2 Omega_pk).

A table read on a run-up or run-down: the steady shape is taken at the speed the
response shows (Omega - alpha tau, tau the group delay, alpha the fitted sweep rate),
right to first order in alpha; the rest of the sweep's effect (the ringing through the
resonance) is taken off by simulating the fitted mode's sweep exactly
(:func:`dsp.bode_sweep.sweep_response`) and refitting it (``_sweep_corrected``).

A table of several resonances (split criticals, several modes) is fitted mode by mode:
each peak of |z1| on a window reaching halfway to its neighbours.

Velocity or acceleration tables: the 1X vector divided by (i Omega)^k first
(:func:`to_displacement`): exact for a steady harmonic.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .errors import SignalError

__all__ = ["ModalFit", "modal_fit", "modal_fits", "to_displacement", "half_power_damping"]

TWO_PI = 2.0 * math.pi


@dataclass(frozen=True)
class ModalFit:
    """One mode of a Bode table.

    Attributes
    ----------
    natural_frequency_hz, natural_frequency_hz_std : float
        f0 = omega_0 / 2 pi [Hz].
    damping_ratio, damping_ratio_std : float
        zeta [-].
    critical_speed_hz : float
        Speed of the steady 1X maximum, f0 / sqrt(1 - 2 zeta^2) [rev/s].
    specific_unbalance_m : float
        |q| = U / M [m].
    angle_rad : float
        arg q, the unbalance's angle from the phase reference [rad].
    runout_m : complex
        The constant vector c [m].
    half_power_damping_ratio : float or None
        The half-power cross-check of zeta (None when the peak's half-power points are
        not both inside the table).
    speed_range_hz : (float, float)
        Speeds fitted [rev/s].
    residual_rms_m : float
    points : int
    specific_unbalance_m_std, angle_rad_std, critical_speed_hz_std : float
        Standard uncertainties of |q| [m], arg q [rad] and the critical speed [rev/s].
    sweep_rate_rad_s2 : float
        The sweep rate the table shows [rad/s^2] (0 for a steady table; > 0 a run-up).

    Every std is the larger of the white-residual covariance and the batch-means
    sandwich over contiguous speed blocks (:func:`dsp.response_fit._covariances`): a
    table's residuals follow the speed -- a run-up's sweep lag and ringing through the
    resonance, bins averaged over a curved response, the probe's runout harmonics --
    and those do not average out from point to point.  A swept table's values are
    corrected for the first-order sweep model's bias (module docstring); its std then
    also holds that correction x std(rate) / |rate| (added: a bound of the correlated
    sum) and the bias a second simulation leaves.  ``residual_rms_m`` is then the residual of the exact sweep's table.
    """

    natural_frequency_hz: float
    natural_frequency_hz_std: float
    damping_ratio: float
    damping_ratio_std: float
    critical_speed_hz: float
    specific_unbalance_m: float
    angle_rad: float
    runout_m: complex
    half_power_damping_ratio: float | None
    speed_range_hz: tuple
    residual_rms_m: float
    points: int
    specific_unbalance_m_std: float = math.nan
    angle_rad_std: float = math.nan
    critical_speed_hz_std: float = math.nan
    sweep_rate_rad_s2: float = 0.0


def to_displacement(speed_rad_s, vector, derivative: int):
    """A velocity (``derivative`` 1) or acceleration (2) 1X vector as displacement [m]."""
    w = np.asarray(speed_rad_s, float)
    return np.asarray(vector, complex) / (1j * w) ** int(derivative)


def _lag(w, w0, zeta):
    """The steady response's group delay d(theta)/d(Omega) [s], theta = arg(1 - r^2 + 2 i zeta r)."""
    r = w / w0
    return (2.0 * zeta / w0) * (1.0 + r * r) / ((1.0 - r * r) ** 2 + (2.0 * zeta * r) ** 2)


_GAUSS = np.polynomial.legendre.leggauss(5)


def _shape(w, w0, zeta, alpha=0.0, bins=None):
    """r^2 / (1 - r^2 + 2 i zeta r) at the speed the response shows on a sweep of
    ``alpha`` [rad/s^2] (Omega - alpha tau(Omega), tau the group delay), averaged over
    speed bins ``bins`` [rad/s] wide when given (5-point Gauss-Legendre)."""
    if bins is not None:
        x, g = _GAUSS
        return sum(0.5 * gi * _shape(w + 0.5 * xi * bins, w0, zeta, alpha) for xi, gi in zip(x, g))
    if alpha:
        w = w - alpha * _lag(w, w0, zeta)
    r = w / w0
    return r * r / (1.0 - r * r + 2j * zeta * r)


def _linear(w, z, w0, zeta, alpha=0.0, bins=None):
    B = np.column_stack([_shape(w, w0, zeta, alpha, bins), np.ones_like(w, dtype=complex)])
    c, *_ = np.linalg.lstsq(B, z, rcond=None)
    return c, z - B @ c


def half_power_damping(w, amp):
    """zeta from the half-power points of a peak of ``amp`` against speed ``w``; None
    when a half-power point lies outside the data."""
    w, amp = np.asarray(w, float), np.asarray(amp, float)
    k = int(np.argmax(amp))
    half = amp[k] / math.sqrt(2.0)
    lo = np.flatnonzero(amp[:k] < half)
    hi = np.flatnonzero(amp[k:] < half)
    if lo.size == 0 or hi.size == 0:
        return None
    i, j = lo[-1], k + hi[0]
    w1 = np.interp(half, [amp[i], amp[i + 1]], [w[i], w[i + 1]])
    w2 = np.interp(half, [amp[j], amp[j - 1]], [w[j], w[j - 1]])
    return float((w2 - w1) / (2.0 * w[k]))


def modal_fit(speed_rad_s, vector_m, *, damping_guess=None) -> ModalFit:
    """Fit one mode to a steady 1X table (module docstring).

    Parameters
    ----------
    speed_rad_s : array_like
        Speeds Omega [rad/s] (any order; > 0).
    vector_m : array_like (complex)
        1X displacement vectors amplitude e^{i phase} [m] (phase: lag convention of the
        table's reference, any; it moves only beta).
    damping_guess : float, optional
        Start value of zeta (default: the half-power estimate, else 0.05).

    Raises
    ------
    SignalError
        Fewer than 6 points, or a table whose speeds do not pass the resonance.
    """
    w = np.asarray(speed_rad_s, float)
    z = np.asarray(vector_m, complex)
    if w.shape != z.shape or w.size < 6:
        raise SignalError(f"a Bode table needs >= 6 points of speed and 1X vector; got {w.size}")
    ok = np.isfinite(w) & np.isfinite(z) & (w > 0)
    w, z = w[ok], z[ok]
    o = np.argsort(w)
    w, z = w[o], z[o]
    k = int(np.argmax(np.abs(z)))
    if k == 0 or k == w.size - 1:
        raise SignalError(f"the 1X amplitude peaks at the table's edge ({w[k] / TWO_PI:.4g} rev/s): "
                          "the speeds do not pass the resonance")
    zh = half_power_damping(w, np.abs(z) / (w / w[k]) ** 2)
    z_guess = damping_guess or (zh if zh and 0 < zh < 0.5 else 0.05)
    n = w.size
    # each point a snapshot of the 1X at its speed, or its mean over a speed bin as wide as
    # the table's step (order tracking averages): the better fit is taken, the other one
    # stays in the std by its weight (Akaike: exp(-delta chi^2 / 2))
    fits = [_fit(w, z, w[k], z_guess, sweep=True, bins=b) for b in (None, np.gradient(w))]
    rss = [float(np.sum(np.abs(f["r"]) ** 2)) for f in fits]
    best = int(np.argmin(rss))
    primary, other = fits[best], fits[1 - best]
    s2 = rss[best] / max(2 * n - 7, 1)
    dchi2 = (rss[1 - best] - rss[best]) / s2 if s2 > 0 else math.inf
    w_other = 1.0 / (1.0 + math.exp(min(0.5 * dchi2, 700.0)))
    steady = _fit(w, z, w[k], z_guess, sweep=False, bins=primary["bins"])
    sd = _stds(w, primary["r"], primary["p"], primary["q"], primary["bins"])
    alpha_std = sd["alpha"]   # the rate's statistical std (its method part below is the rate)
    for key in sd:        # the method's part: half the sweep's first-order correction, the bins
        sd[key] = math.hypot(sd[key], 0.5 * _diff(key, primary, steady),
                             _diff(key, other, primary) * math.sqrt(w_other))
    primary = _sweep_corrected(w, z, primary, w[k], z_guess, sd, alpha_std)
    w0, zeta, alpha = primary["p"]
    q, c, r = primary["q"], primary["c"], primary["r"]
    crit = w0 / math.sqrt(1.0 - 2.0 * zeta * zeta) if zeta < 1 / math.sqrt(2) else math.nan
    zhp = half_power_damping(w, np.abs(z - c) / (w / w0) ** 2)
    return ModalFit(natural_frequency_hz=float(w0) / TWO_PI, natural_frequency_hz_std=sd["w0"] / TWO_PI,
                    damping_ratio=zeta, damping_ratio_std=sd["zeta"],
                    critical_speed_hz=float(crit) / TWO_PI, specific_unbalance_m=float(abs(q)),
                    angle_rad=float(np.angle(q)), runout_m=complex(c),
                    half_power_damping_ratio=zhp,
                    speed_range_hz=(float(w[0] / TWO_PI), float(w[-1] / TWO_PI)),
                    residual_rms_m=float(np.sqrt(np.mean(np.abs(r) ** 2))), points=int(n),
                    specific_unbalance_m_std=sd["e"], angle_rad_std=sd["beta"],
                    critical_speed_hz_std=sd["fc"], sweep_rate_rad_s2=float(alpha))


def _fit(w, z, w_guess, z_guess, *, sweep, bins=None) -> dict:
    """Variable projection: (omega_0, zeta[, alpha]) by least squares, (q, c) linear."""
    from scipy.optimize import least_squares

    scale = float(np.max(np.abs(z))) or 1.0
    a_unit = (z_guess * w_guess) ** 2            # a sweep whose lag is ~ the half-power width

    def resid(p):
        _, r = _linear(w, z, p[0] * w_guess, p[1], p[2] * a_unit if sweep else 0.0, bins)
        return np.concatenate((r.real, r.imag)) / scale

    x0 = [1.0, z_guess] + ([0.0] if sweep else [])
    lo = [0.3, 1e-5] + ([-2.0] if sweep else [])
    hi = [3.0, 0.7] + ([2.0] if sweep else [])
    sol = least_squares(resid, x0, bounds=(lo, hi), x_scale=[0.01] * len(x0),
                        xtol=1e-14, ftol=1e-14, gtol=1e-14)
    p = (sol.x[0] * w_guess, float(sol.x[1]), float(sol.x[2]) * a_unit if sweep else 0.0)
    (q, c), r = _linear(w, z, p[0], p[1], p[2], bins)
    return {"p": p, "q": complex(q), "c": complex(c), "r": r, "bins": bins}


def _sweep_corrected(w, z, fit, w_guess, z_guess, sd, alpha_std) -> dict:
    """``fit`` less the first-order sweep model's own bias (:mod:`dsp.bode_sweep`).

    The table the fitted mode would give on its fitted sweep is simulated exactly and
    refitted: the refit's difference from the fit is the bias of the first-order lag model
    (through the resonance the sweep also rings), subtracted.  The bias is ~ proportional
    to the rate: its part from the rate's own std (the correction x std(alpha) / |alpha|,
    added to the std: the two are correlated) and the bias left (a second simulation at the corrected values, refitted, against the
    fit) enter ``sd`` (in place).  A rate within its std of 0 (a steady table: the
    correction would be noise) or below 1e-4 (zeta w0)^2 (a lag of 1e-4 of the half-power
    width), or a sweep too slow to simulate, leaves the fit as it is."""
    from .bode_sweep import sweep_response

    def table(f):
        w0, zeta, alpha = f["p"]
        s = sweep_response(w, w0, zeta, alpha, f["q"], f["bins"])
        return None if s is None else s + f["c"]

    def refit(f):
        s = table(f)
        return None if s is None else _fit(w, s, w_guess, z_guess, sweep=True, bins=f["bins"])

    w0, zeta, alpha = fit["p"]
    if not 0 < zeta < 1 or abs(alpha) <= max(alpha_std, 1e-4 * (zeta * w0) ** 2):
        return fit
    once = refit(fit)
    if once is None:
        return fit
    p = tuple(2 * a - b for a, b in zip(fit["p"], once["p"]))
    q, c = 2 * fit["q"] - once["q"], 2 * fit["c"] - once["c"]
    if not (0 < p[1] < 0.7 and p[0] > 0):
        return fit
    out = {"p": p, "q": q, "c": c, "bins": fit["bins"]}
    s = table(out)
    out["r"] = z - s if s is not None else fit["r"]
    twice = refit(out)
    # the correction k alpha moves with the rate's error, correlated with the value's own:
    # std(p - k alpha) <= std(p) + |k| std(alpha) (Cauchy-Schwarz)
    rel = alpha_std / abs(alpha)
    for key in sd:
        sd[key] = math.hypot(sd[key] + _diff(key, once, fit) * rel,
                             _diff(key, twice, fit) if twice is not None else 0.0)
    return out


def _diff(key, a, b) -> float:
    """|a - b| of one reported quantity of two fits (:func:`_stds`' keys)."""
    def value(f):
        w0, zeta, _ = f["p"]
        return {"w0": w0, "zeta": zeta, "alpha": f["p"][2], "e": abs(f["q"]),
                "beta": float(np.angle(f["q"])),
                "fc": w0 / math.sqrt(1.0 - 2.0 * zeta * zeta) / TWO_PI
                if zeta < 1 / math.sqrt(2) else math.nan}[key]
    d = value(a) - value(b)
    if key == "beta":
        d = (d + math.pi) % TWO_PI - math.pi
    return abs(d)


def _stds(w, r, p, q, bins=None) -> dict:
    """Statistical stds of omega_0 [rad/s], zeta, the sweep rate [rad/s^2], |q| [m], arg q
    [rad] and the critical speed [rev/s] from the full model's Jacobian in (omega_0, zeta, alpha, q, c)."""
    from .response_fit import _covariances

    w0, zeta, alpha = p
    shape = _shape(w, w0, zeta, alpha, bins)
    cols = []
    for j in range(3):
        h = 1e-6 * (w0, max(zeta, 1e-4), max(abs(alpha), 1e-4 * w0 * w0))[j]
        pp, pm = list(p), list(p)
        pp[j] += h
        pm[j] -= h
        cols.append(-q * (_shape(w, *pp, bins) - _shape(w, *pm, bins)) / (2 * h))
    cols += [-shape, -1j * shape, -np.ones_like(shape), -1j * np.ones_like(shape)]
    Jc = np.column_stack(cols)
    J = np.vstack((Jc.real, Jc.imag))
    # contiguous blocks of the speed axis: a few long ones (a residual that follows the
    # whole curve) and many short ones (a run-up's ringing just past the resonance)
    covs = (_covariances(J, r, 7, blocks=8, min_block=8)
            + _covariances(J, r, 7, blocks=w.size, min_block=4)[1:])
    e = abs(q)
    u = np.array([q.real, q.imag]) / e if e > 0 else np.array([1.0, 0.0])
    v = np.array([-u[1], u[0]]) / (e if e > 0 else 1.0)
    shift = 1.0 / math.sqrt(1.0 - 2.0 * zeta * zeta) if zeta < 1 / math.sqrt(2) else math.nan
    gc = np.array([shift, w0 * 2 * zeta * shift ** 3]) / TWO_PI
    grads = {"w0": (0, np.array([1.0])), "zeta": (1, np.array([1.0])),
             "alpha": (2, np.array([1.0])), "e": (3, u),
             "beta": (3, v), "fc": (0, gc)}

    def std(C, i, g):
        k = slice(i, i + g.size)
        return float(math.sqrt(max(g @ C[k, k] @ g, 0.0)))

    return {k: max(std(C, i, g) for C in covs) for k, (i, g) in grads.items()}


def modal_fits(speed_rad_s, vector_m, *, prominence: float = 0.3) -> list:
    """One :class:`ModalFit` per resonance peak of |z1| (peaks whose prominence is at
    least ``prominence`` of the largest amplitude), each on a window reaching halfway to
    the neighbouring peaks."""
    from scipy.signal import find_peaks

    w = np.asarray(speed_rad_s, float)
    z = np.asarray(vector_m, complex)
    o = np.argsort(w)
    w, z = w[o], z[o]
    a = np.abs(z)
    peaks, _ = find_peaks(a, prominence=prominence * float(a.max()))
    if peaks.size <= 1:
        return [modal_fit(w, z)]
    cuts = np.concatenate(([0], (peaks[:-1] + peaks[1:]) // 2, [w.size]))
    return [modal_fit(w[cuts[i]:cuts[i + 1]], z[cuts[i]:cuts[i + 1]]) for i in range(peaks.size)]
