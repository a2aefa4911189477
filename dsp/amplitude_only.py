"""Balancing one plane without a phase reference: the four-run method, by least squares.

A plain vibration meter shows amplitudes only.  The classic *four-run method* (a reference
run and the same trial mass at three angles, usually 0, 120 and 240 deg; V. Wowk,
*Machinery Vibration: Balancing*, McGraw-Hill 1995, "balancing without phase"; the
"three trial runs" circle construction of field-balancing texts) finds the correction from
the amplitudes alone.  For one sensor and one plane with influence coefficient ``h`` (per
unit mass, complex) and the reference vibration taken as the phase origin (``a0`` real,
> 0), the run with trial mass ``T_k`` at angle ``theta_k`` shows

    A_k = |a0 + T_k exp(i theta_k) h|,       k = 1..n,      A_0 = a0.

Solved here as a weighted least-squares problem in ``(a0, Re h, Im h)`` per sensor
(scipy.optimize.least_squares, residuals ``(model - reading) / sigma``), started from the
exact linear solution of the expanded circle equations
``A_k^2 - A_0^2 = T_k^2 |h|^2 + 2 A_0 T_k Re(exp(i theta_k) h)`` (linear in |h|^2, Re h,
Im h) and from corrections all round the weight plane (the best minimum is kept).  The correction ``U = -a0 / h`` (one sensor) or, for several sensors, the least
squares ``U = -sum conj(h_s) a0_s / sum |h_s|^2``; its angle is in the weights' sense, from
the trial mass's zero.  Geometrically ``U`` is the point of the weight plane whose distances
to the origin and to the trial positions are proportional to ``A_0`` and ``A_k``.

Uncertainty: each amplitude reading's standard uncertainty ``sigma`` (a meter's rounding to
resolution ``r``: ``sigma = r / sqrt 12``) is propagated to first order (Gauss-Newton
covariance ``(J^T J)^-1`` of the weighted residuals, then the Jacobian of ``U``).

Ambiguity: fewer than three distinct trial angles leave two mirror solutions (refused);
trial positions bunched together leave a second minimum (near the mirror image of ``U``
across their axis) fitting nearly as well: a warning naming it, with the chi-square
difference.

Units are the caller's (any consistent set); angles in radians.  numpy/scipy only.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

__all__ = ["FourRun", "four_run", "resolution_sigma"]

#: a trial must change the vibration by more than this many reading sigmas
MIN_EFFECT_SIGMA = 2.0
#: a mirror solution within this chi-square of the best one is warned about (2 sigma)
MIRROR_CHI2 = 4.0


def resolution_sigma(resolution: float) -> float:
    """Standard uncertainty of a reading rounded to ``resolution`` (uniform): r / sqrt 12."""
    return float(resolution) / math.sqrt(12.0)


@dataclass
class FourRun:
    """The four-run answer (units of the inputs): correction ``U`` (complex: mass at the angle
    in the weights' sense), its ``mass`` / ``angle_rad`` and their standard uncertainties,
    per sensor the influence coefficient ``h`` (complex, relative to that sensor's reference
    vibration) with its magnitude's std, the reference vibration ``a0`` as fitted, the
    predicted amplitude after the correction, the weighted rms residual and warnings."""

    U: complex
    mass: float
    angle_rad: float
    mass_std: float
    angle_std_rad: float
    h: np.ndarray
    h_abs_std: np.ndarray
    a0: np.ndarray
    after: np.ndarray
    rms_residual: float
    warnings: list = field(default_factory=list)


def _as_2d(x, n_sensors, n, what):
    a = np.asarray(x, dtype=float)
    if a.ndim == 0:
        a = np.full((n_sensors, n), float(a))
    a = a.reshape(n_sensors, -1) if a.ndim == 1 and n_sensors == 1 else a
    if a.shape != (n_sensors, n):
        raise ValueError(f"{what}: shape {a.shape}, expected ({n_sensors}, {n})")
    return a


def _correction(a0, h):
    return complex(-np.sum(np.conj(h) * a0) / np.sum(np.abs(h) ** 2))


def four_run(reference, amplitudes, trial_mass, trial_angle_rad, sigma=0.0,
             sensors=None) -> FourRun:
    """One plane's correction from amplitude-only readings (the module docstring).

    Parameters
    ----------
    reference : float or array (S,)
        Reference-run amplitude per sensor [vibration unit].
    amplitudes : array (n,) or (S, n)
        Amplitude of each trial run per sensor [vibration unit].
    trial_mass : float or array (n,)
        Trial mass of each run [mass unit] (the same one at each angle, classically).
    trial_angle_rad : array (n,)
        Angle of the trial mass in each run [rad], in the weights' sense.
    sigma : float or array (S, n + 1)
        Standard uncertainty of each reading [vibration unit], reference first (0: exact).
    sensors : list of str, optional
        Sensor names for the messages (default "sensor 0", ...).

    Returns
    -------
    FourRun

    Raises
    ------
    ValueError
        Fewer than three distinct trial angles, a trial with no measurable effect, bad values.
    """
    ref = np.atleast_1d(np.asarray(reference, dtype=float))
    S = ref.size
    th = np.atleast_1d(np.asarray(trial_angle_rad, dtype=float))
    n = th.size
    amp = _as_2d(amplitudes, S, n, "amplitudes")
    T = np.broadcast_to(np.asarray(trial_mass, dtype=float), (n,)).copy()
    sig = _as_2d(sigma, S, n + 1, "sigma")
    for name, v, unit in (("reference", ref, "vibration unit"), ("amplitudes", amp, "vibration unit"),
                          ("sigma", sig, "vibration unit")):
        if not np.all(np.isfinite(v)) or np.any(v < 0):
            raise ValueError(f"{name} = {v.tolist()}: must be finite and >= 0 ({unit})")
    if not np.all(np.isfinite(T)) or np.any(T <= 0):
        raise ValueError(f"trial_mass = {T.tolist()}: must be finite and > 0 (mass unit)")
    if not np.all(np.isfinite(th)):
        raise ValueError(f"trial_angle_rad = {th.tolist()}: must be finite (rad)")
    q = T * np.exp(1j * th)                                   # trial positions (weight plane)
    distinct = {round(math.degrees(a) % 360.0, 6) % 360.0 for a in th}
    if len(distinct) < 3:
        raise ValueError(f"trial angles {', '.join(f'{d:g}' for d in sorted(distinct))} deg: the "
                         f"amplitude-only (four-run) method needs the trial at 3 or more distinct "
                         f"angles (e.g. 0, 120, 240 deg); with fewer, two mirror corrections fit")
    exact = not np.any(sig > 0)
    w = np.where(sig > 0, sig, 1.0) if not exact else np.ones_like(sig)
    if not exact and np.any(sig <= 0):
        w = np.where(sig > 0, sig, np.min(sig[sig > 0]))

    from scipy.optimize import least_squares as _lsq

    params, covs, warns, rms = [], [], [], []
    names = list(sensors) if sensors is not None else [f"sensor {k}" for k in range(S)]
    for s in range(S):
        A0, Ak = ref[s], amp[s]
        # exact linear start: A_k^2 - A_0^2 = T_k^2 u + 2 A0 T_k (hr cos - hi sin)
        M = np.column_stack([T ** 2, 2 * A0 * T * np.cos(th), -2 * A0 * T * np.sin(th)])
        sol = np.linalg.lstsq(M, Ak ** 2 - A0 ** 2, rcond=None)[0]
        h_lin = complex(sol[1], sol[2])
        if A0 == 0:                          # u alone: |h| known, its angle is irrelevant
            h_lin = complex(math.sqrt(max(sol[0], 0.0)), 0.0)

        def res(p, A0=A0, Ak=Ak, ws=w[s]):
            model = np.abs(p[0] + q * complex(p[1], p[2]))
            return np.concatenate([[p[0] - A0], model - Ak]) / ws

        # multi-start: the linear start, and corrections c = -a0/h all round the weight plane
        # (bunched trial positions leave several local minima; the best one is kept)
        R = [A0 / abs(h_lin)] if abs(h_lin) > 0 else []
        R.append(A0 * float(np.mean(T)) / max(float(np.mean(np.abs(Ak - A0))), 1e-300))
        starts = [np.array([A0, h_lin.real, h_lin.imag])]
        for r_ in R:
            for phi in np.radians(np.arange(0.0, 360.0, 30.0)):
                h0 = -A0 / (r_ * np.exp(1j * phi)) if A0 > 0 and r_ > 0 else h_lin
                starts.append(np.array([A0, h0.real, h0.imag]))
        sols = []
        for p0 in starts:
            f = _lsq(res, p0, method="lm", xtol=1e-14, ftol=1e-14, gtol=1e-14)
            pf = -f.x if f.x[0] < 0 else f.x      # (a0, h) and (-a0, -h) show the same amplitudes
            sols.append((float(np.sum(f.fun ** 2)), pf, f.jac))
        sols.sort(key=lambda x: x[0])
        chi2, p, J = sols[0]
        h = complex(p[1], p[2])
        effect = float(np.max(T)) * abs(h)
        floor = MIN_EFFECT_SIGMA * float(np.max(sig[s])) if not exact else 1e-9 * max(A0, 1e-300)
        if effect <= floor:
            raise ValueError(f"{names[s]}: the trial runs change the amplitude by at most "
                             f"{float(np.max(np.abs(Ak - A0))):.3g} (reading resolution sigma "
                             f"{float(np.max(sig[s])):.3g}): trial mass too small, no measurable "
                             f"effect; repeat with a larger trial mass")
        cov = np.zeros((3, 3)) if exact else np.linalg.pinv(J.T @ J)
        rms.append(chi2)
        c = -p[0] / h
        thresh = MIRROR_CHI2 if not exact else 1e-12 * (1 + chi2)
        for chi2_m, pm, _ in sols[1:]:
            hm = complex(pm[1], pm[2])
            if hm == 0 or chi2_m - chi2 >= thresh:
                continue
            cm = -pm[0] / hm
            if abs(cm - c) > 0.05 * abs(c):
                warns.append(f"{names[s]}: ambiguous trial positions: a second correction "
                             f"{abs(cm):.4g} @ {math.degrees(np.angle(cm)) % 360:.1f} deg (a mirror "
                             f"of {abs(c):.4g} @ {math.degrees(np.angle(c)) % 360:.1f} deg) fits the "
                             f"readings nearly as well (chi-square {chi2_m - chi2:.2g} more); "
                             f"spread the trial angles (e.g. 0, 120, 240 deg)")
                break
        params.append(p)
        covs.append(cov)
    a0 = np.array([p[0] for p in params])
    h = np.array([complex(p[1], p[2]) for p in params])
    U = _correction(a0, h)
    # first-order propagation: dU / d(params), params' covariance block-diagonal over sensors
    cU = np.zeros((2, 2))
    for s in range(S):
        g = np.zeros((2, 3))
        for j in range(3):
            step = 1e-7 * max(abs(params[s][j]), abs(a0[s]), 1e-300)
            pp, pm_ = [x.copy() for x in params], [x.copy() for x in params]
            pp[s][j] += step
            pm_[s][j] -= step
            d = (_correction(np.array([x[0] for x in pp]), np.array([complex(x[1], x[2]) for x in pp]))
                 - _correction(np.array([x[0] for x in pm_]),
                               np.array([complex(x[1], x[2]) for x in pm_]))) / (2 * step)
            g[:, j] = [d.real, d.imag]
        cU += g @ covs[s] @ g.T
    m = abs(U)
    if m > 0:
        gr = np.array([U.real, U.imag]) / m
        gn = np.array([-U.imag, U.real]) / m ** 2
        m_std = math.sqrt(max(float(gr @ cU @ gr), 0.0))
        a_std = math.sqrt(max(float(gn @ cU @ gn), 0.0))
    else:
        m_std, a_std = math.sqrt(max(np.trace(cU) / 2, 0.0)), math.pi
    h_std = np.array([math.sqrt(max(float(np.array([x.real, x.imag]) @ c[1:, 1:]
                                          @ np.array([x.real, x.imag])), 0.0)) / abs(x)
                      for x, c in zip(h, covs)])
    return FourRun(U=U, mass=m, angle_rad=float(np.angle(U)) % (2 * math.pi), mass_std=m_std,
                   angle_std_rad=a_std, h=h, h_abs_std=h_std, a0=a0, after=np.abs(a0 + h * U),
                   rms_residual=math.sqrt(sum(rms) / (S * (n + 1))), warnings=warns)
