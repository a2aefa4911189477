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


def to_displacement(speed_rad_s, vector, derivative: int):
    """A velocity (``derivative`` 1) or acceleration (2) 1X vector as displacement [m]."""
    w = np.asarray(speed_rad_s, float)
    return np.asarray(vector, complex) / (1j * w) ** int(derivative)


def _shape(w, w0, zeta):
    r = w / w0
    return r * r / (1.0 - r * r + 2j * zeta * r)


def _linear(w, z, w0, zeta):
    B = np.column_stack([_shape(w, w0, zeta), np.ones_like(w, dtype=complex)])
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
    from scipy.optimize import least_squares

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
    w_guess = w[k]
    scale = float(np.max(np.abs(z))) or 1.0

    def resid(p):
        _, r = _linear(w, z, p[0] * w_guess, p[1])
        return np.concatenate((r.real, r.imag)) / scale

    sol = least_squares(resid, [1.0, z_guess], bounds=([0.3, 1e-5], [3.0, 0.7]),
                        x_scale=[0.01, 0.01], xtol=1e-14, ftol=1e-14, gtol=1e-14)
    w0, zeta = sol.x[0] * w_guess, float(sol.x[1])
    (q, c), r = _linear(w, z, w0, zeta)
    n = w.size
    s2 = float(np.sum(np.abs(r) ** 2)) / max(2 * n - 6, 1)
    J = sol.jac * scale / np.array([w_guess, 1.0])        # d r / d(omega_0, zeta)
    try:
        cov = s2 * np.linalg.inv(J.T @ J)
        sd = np.sqrt(np.abs(np.diag(cov)))
    except np.linalg.LinAlgError:
        sd = np.array([math.nan, math.nan])
    crit = w0 / math.sqrt(1.0 - 2.0 * zeta * zeta) if zeta < 1 / math.sqrt(2) else math.nan
    zhp = half_power_damping(w, np.abs(z - c) / (w / w0) ** 2)
    return ModalFit(natural_frequency_hz=float(w0) / TWO_PI, natural_frequency_hz_std=float(sd[0]) / TWO_PI,
                    damping_ratio=zeta, damping_ratio_std=float(sd[1]),
                    critical_speed_hz=float(crit) / TWO_PI, specific_unbalance_m=float(abs(q)),
                    angle_rad=float(np.angle(q)), runout_m=complex(c),
                    half_power_damping_ratio=zhp,
                    speed_range_hz=(float(w[0] / TWO_PI), float(w[-1] / TWO_PI)),
                    residual_rms_m=float(np.sqrt(np.mean(np.abs(r) ** 2))), points=int(n))


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
