"""Natural frequency, damping and unbalance from a run-up / run-down with a known rotor angle.

The rigid rotor on isotropic supports (monograph ch. 5, the rotor of (5.1)
without weights; the model of :func:`dsp.unbalance.unbalance_from_response`)
moves, in the complex plane z = x + i y, as

    z'' + 2 zeta omega_1 z' + omega_1^2 z = e (phi'^2 - i phi'') e^{i (phi + beta)},

with e = U / M_Sigma the specific unbalance [m] and beta its angle from the
rotor's reference mark.  (The unbalance mass sits at z + e e^{i(phi+beta)};
its acceleration's forcing term is -e d^2/dt^2 e^{i phi} = e (phi'^2 - i phi'')
e^{i phi}.)  With the rotor angle phi(t) measured, the whole record --
resonance passage, sweep-rate lag and transients included -- is the response
of this linear equation: z = q g(t) + c1 h1(t) + c2 h2(t) + z0 + r e^{i phi}, where g solves
it for the unit forcing from rest, h1, h2 are the free motions and z0 is the
probes' DC offset.  It is linear in the complex coefficients (q = e e^{i beta},
c1, c2, z0) and nonlinear only in (omega_1, zeta): variable projection
(Golub & Pereyra 1973) -- a 2-parameter least-squares problem whose every
residual is one recursive filter over the record (the equation discretised
exactly for a piecewise-linear forcing, scipy.signal.cont2discrete "foh").
No quasi-steady assumption: the sweep-rate lag that
:func:`dsp.runup.resonance_from_runup` corrects approximately is part of the
model here.  Uncertainties: the Gauss-Newton covariance of all parameters at
the optimum, scaled by the residual variance.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .errors import SignalError, check_signal

__all__ = ["ResponseFit", "fit_unbalance_response", "fit_response_without_speed"]

TWO_PI = 2.0 * math.pi


@dataclass(frozen=True)
class ResponseFit:
    """Fit of the rigid-rotor unbalance response to a swept record.

    Attributes
    ----------
    natural_frequency_hz, natural_frequency_hz_std : float
        f_1 = omega_1 / 2 pi [Hz].
    damping_ratio, damping_ratio_std : float
        zeta [-].
    critical_speed_hz, critical_speed_hz_std : float
        Speed of the steady 1X response's maximum, f_1 / sqrt(1 - 2 zeta^2) [rev/s].
    specific_unbalance_m, specific_unbalance_m_std : float
        e = U / M_Sigma [m] (times the vibrating mass: the unbalance [kg m]).
    angle_rad, angle_rad_std : float
        beta, the unbalance's angle from the reference mark [rad] (meaningful
        only when the rotor angle is referenced to a mark).
    offset_m : complex
        DC offset of the probes (x0 + i y0) [m].
    runout_m : complex
        The probes' 1X runout (a vector fixed to the rotor, seen whatever the
        speed: the slow-roll vector) [m]; fitted, so no slow-roll subtraction
        is needed.
    residual_rms_m : float
        RMS of the complex residual per sample [m].
    samples : int
        Samples fitted.
    """

    natural_frequency_hz: float
    natural_frequency_hz_std: float
    damping_ratio: float
    damping_ratio_std: float
    critical_speed_hz: float
    critical_speed_hz_std: float
    specific_unbalance_m: float
    specific_unbalance_m_std: float
    angle_rad: float
    angle_rad_std: float
    offset_m: complex
    runout_m: complex
    residual_rms_m: float
    samples: int


def _response(w0, zeta, dt, f, order=0):
    """Response from rest of x'' + 2 zeta w0 x' + w0^2 x = f (first-order hold): x, or its
    velocity x' (``order`` 1) or acceleration x'' = f - 2 zeta w0 x' - w0^2 x (``order`` 2),
    read from the same exact discretisation (nothing differentiated numerically)."""
    from scipy import signal

    A = np.array([[0.0, 1.0], [-w0 * w0, -2.0 * zeta * w0]])
    B = np.array([[0.0], [1.0]])
    C = np.array([[1.0, 0.0], [0.0, 1.0], [-w0 * w0, -2.0 * zeta * w0]])[order:order + 1]
    D = np.array([[1.0 if order == 2 else 0.0]])
    Ad, Bd, Cd, Dd, _ = signal.cont2discrete((A, B, C, D), dt, method="foh")
    b, a = signal.ss2tf(Ad, Bd, Cd, Dd)
    return signal.lfilter(np.real(b[0]), np.real(a), f)


def _basis(w0, zeta, tt, dt, f, rot, order=0):
    """Columns (g, h1, h2, 1, e^{i phi}) of the linear part, differentiated ``order`` times
    (the constant stays: a sensor's DC offset; ``rot`` is given in the channel's quantity)."""
    g = _response(w0, zeta, dt, f, order)
    sig = zeta * w0
    wd = w0 * math.sqrt(max(1.0 - zeta * zeta, 1e-12))
    env = np.exp(-sig * tt)
    c, s = np.cos(wd * tt), np.sin(wd * tt)
    # d/dt of env (a c + b s) = env ((-sig a + wd b) c + (-sig b - wd a) s)
    h = [(1.0, 0.0), (0.0, 1.0)]
    for _ in range(order):
        h = [(-sig * a + wd * b, -sig * b - wd * a) for a, b in h]
    h1, h2 = (env * (a * c + b * s) for a, b in h)
    return np.column_stack([g, h1, h2, np.ones_like(tt), rot])


def _linear(B, z):
    keep = np.any(B != 0, axis=0)
    c = np.zeros(B.shape[1], complex)
    c[keep], *_ = np.linalg.lstsq(B[:, keep].astype(complex), z, rcond=None)
    return c, z - B @ c


def fit_unbalance_response(t, z, angle_rad, speed_rad_s=None, acceleration_rad_s2=None, *,
                           natural_frequency_guess_hz=None, damping_guess=0.05, runout=True,
                           derivative: int = 0):
    """Fit omega_1, zeta, the specific unbalance and its angle to a swept record.

    Parameters
    ----------
    t : array_like
        Sample times [s], uniform.
    z : array_like (complex)
        Shaft displacement x + i y [m] (any DC offset is fitted).
    angle_rad : array_like
        Rotor angle phi [rad] at the samples (unwrapped).
    speed_rad_s, acceleration_rad_s2 : array_like, optional
        phi' [rad/s] and phi'' [rad/s^2]; default: numerical derivatives of
        ``angle_rad``.
    natural_frequency_guess_hz : float, optional
        Start value of f_1 [Hz] (e.g. the 1X amplitude's peak speed); default:
        the speed at the largest whirl radius.
    damping_guess : float
        Start value of zeta [-].
    runout : bool
        Fit the probes' 1X runout r e^{i phi} (default).  Off when the angle is
        itself estimated from the whirl (the column would mimic the response).
    derivative : int
        What ``z`` measures: 0 displacement [m], 1 velocity [m/s], 2 acceleration
        [m/s²] (velocity pickups, accelerometers).  The model's response is
        differentiated (its exact discretisation read at the velocity or the
        acceleration), so the record is fitted in its own quantity and nothing is
        integrated through noise or DC drift; e, f_1 and zeta are the same parameters.
        ``offset_m``, ``runout_m`` and ``residual_rms_m`` are then in the channel's
        SI unit, and the runout (a displacement probe's) is not fitted.

    Returns
    -------
    ResponseFit

    Raises
    ------
    SignalError
        Non-uniform or too short record, or a record that does not determine
        omega_1 (no resonance passage: the speed never comes near it).
    """
    from scipy.optimize import least_squares

    t, z, dt = check_signal(t, z, "z", min_samples=64)
    phi = np.asarray(angle_rad, float)
    if phi.shape != t.shape or not np.all(np.isfinite(phi)):
        raise SignalError("angle_rad: needs a finite rotor angle at every sample")
    w = np.gradient(phi, t) if speed_rad_s is None else np.asarray(speed_rad_s, float)
    a = np.gradient(w, t) if acceleration_rad_s2 is None else np.asarray(acceleration_rad_s2, float)
    order = int(derivative)
    if order not in (0, 1, 2):
        raise SignalError(f"derivative = {derivative!r}: 0 (displacement), 1 (velocity) or 2 "
                          "(acceleration)")
    rot = np.exp(1j * phi) if runout and order == 0 else np.zeros(t.size)
    f = (w * w - 1j * a) * np.exp(1j * phi)
    tt = t - t[0]
    zc = z
    if natural_frequency_guess_hz is None:
        k = max(3, t.size // 200)
        ww = np.maximum(np.abs(w), 1e-9 + 1e-3 * np.max(np.abs(w))) ** order
        r = np.convolve(np.abs(z - z.mean()) / ww, np.ones(k) / k, mode="same")
        natural_frequency_guess_hz = abs(w[int(np.argmax(r))]) / TWO_PI
    w_guess = TWO_PI * float(natural_frequency_guess_hz)
    wmax = float(np.max(np.abs(w)))
    if not (w_guess > 0 and np.isfinite(w_guess)):
        raise SignalError("natural frequency: no start value (the rotor does not turn)")
    scale = float(np.std(z)) or 1.0

    def resid(p):
        w0, zeta = p[0] * w_guess, p[1]
        _, r = _linear(_basis(w0, zeta, tt, dt, f, rot, order), zc)
        return np.concatenate((r.real, r.imag)) / scale

    p0 = np.array([1.0, float(damping_guess)])
    sol = least_squares(resid, p0, bounds=([0.2, 1e-5], [5.0, 0.7]), x_scale=[0.01, 0.01],
                        xtol=1e-12, ftol=1e-12, gtol=1e-12)
    w0, zeta = sol.x[0] * w_guess, float(sol.x[1])
    if not (0.95 * float(np.min(np.abs(w))) <= w0 <= 1.05 * wmax):
        raise SignalError(f"natural frequency: the fit gives {w0 / TWO_PI:.4g} Hz, outside the "
                          f"record's speeds ({np.min(np.abs(w)) / TWO_PI:.4g}-{wmax / TWO_PI:.4g} "
                          "rev/s); a record that does not pass the resonance does not determine it")
    B = _basis(w0, zeta, tt, dt, f, rot, order)
    c, r = _linear(B, zc)
    n = t.size
    # covariance of all real parameters: (w0, zeta, Re/Im of the 5 complex coefficients)
    def full(p):
        Bp = _basis(p[0], p[1], tt, dt, f, rot, order)
        cc = p[2::2] + 1j * p[3::2]
        rr = zc - Bp @ cc
        return np.concatenate((rr.real, rr.imag))

    p = np.concatenate(([w0, zeta], np.column_stack((c.real, c.imag)).ravel()))
    J = np.empty((2 * n, p.size))
    for j in range(p.size):
        h = 1e-6 * max(abs(p[j]), 1e-3 * (w0 if j == 0 else 1e-2 if j == 1 else scale))
        pp, pm = p.copy(), p.copy()
        pp[j] += h
        pm[j] -= h
        J[:, j] = (full(pp) - full(pm)) / (2 * h)
    s2 = float(np.sum(np.abs(r) ** 2)) / max(2 * n - p.size, 1)
    live = np.any(J != 0, axis=0)
    try:
        cov = np.zeros((p.size, p.size))
        cov[np.ix_(live, live)] = s2 * np.linalg.inv(J[:, live].T @ J[:, live])
    except np.linalg.LinAlgError:
        cov = np.full((p.size, p.size), np.nan)
    sd = np.sqrt(np.abs(np.diag(cov)))
    q = c[0]
    e = abs(q)
    # e along q, angle across it
    u = np.array([q.real, q.imag]) / e if e > 0 else np.array([1.0, 0.0])
    Cq = cov[2:4, 2:4]
    se = float(math.sqrt(max(u @ Cq @ u, 0.0)))
    v = np.array([-u[1], u[0]])
    sb = float(math.sqrt(max(v @ Cq @ v, 0.0)) / e) if e > 0 else math.pi
    shift = 1.0 / math.sqrt(1.0 - 2.0 * zeta * zeta) if zeta < 1 / math.sqrt(2) else math.nan
    # d(f_c)/d(w0), d(f_c)/d(zeta)
    g = np.array([shift, w0 * 2 * zeta * shift ** 3]) / TWO_PI
    sfc = float(math.sqrt(max(g @ cov[:2, :2] @ g, 0.0)))
    return ResponseFit(natural_frequency_hz=w0 / TWO_PI, natural_frequency_hz_std=float(sd[0]) / TWO_PI,
                       damping_ratio=zeta, damping_ratio_std=float(sd[1]),
                       critical_speed_hz=w0 * shift / TWO_PI, critical_speed_hz_std=sfc,
                       specific_unbalance_m=float(e), specific_unbalance_m_std=se,
                       angle_rad=float(math.atan2(q.imag, q.real)), angle_rad_std=sb,
                       offset_m=complex(c[3]), runout_m=complex(c[4]) if runout and order == 0 else 0j, residual_rms_m=float(np.sqrt(np.mean(np.abs(r) ** 2))),
                       samples=int(n))


def fit_response_without_speed(t, z, *, iterations: int = 6, natural_frequency_guess_hz=None,
                               damping_guess=0.05):
    """The fit of :func:`fit_unbalance_response` when no speed channel was recorded.

    The rotor angle is estimated from the whirl itself
    (:func:`dsp.speed.angle_from_1x`): the forward whirl's phase is
    theta = phi + beta + arg H(phi'), with the receptance's angle arg H turning by
    about pi through the resonance.  Each iteration fits the model with the
    current angle, predicts the lag psi = arg(q g e^{-i phi}) of the response
    behind the rotor, and sets phi = theta - psi (smoothed: a cubic spline every
    20 revolutions), until phi changes by less than 1e-3 rad.

    Returns
    -------
    (ResponseFit, RotorAngle)
        The fit (``angle_rad`` NaN: without a reference mark the unbalance has
        no angle; no runout term: it cannot be told from the response) and the
        estimated rotor angle (``estimated`` True).
    """
    from dataclasses import replace

    from .speed import angle_from_1x, smoothed_phase

    t, z, _ = check_signal(t, z, "z", min_samples=64)
    z0 = complex(np.mean(z))
    ra = angle_from_1x(t, z - z0)
    c = ra.covered
    theta = None
    fit = None
    for _ in range(max(1, iterations)):
        fit = fit_unbalance_response(t[c], z[c], ra.angle_rad[c], ra.speed_rad_s[c],
                                     ra.acceleration_rad_s2[c],
                                     natural_frequency_guess_hz=natural_frequency_guess_hz,
                                     damping_guess=damping_guess, runout=False)
        natural_frequency_guess_hz = fit.natural_frequency_hz
        damping_guess = fit.damping_ratio
        if fit.offset_m != z0:
            z0 = fit.offset_m
        theta = np.unwrap(np.angle(z[c] - z0))
        if theta[-1] < theta[0]:
            theta = -theta
        tt = t[c] - t[c][0]
        w0, zeta = TWO_PI * fit.natural_frequency_hz, fit.damping_ratio
        phi, w = ra.angle_rad[c], ra.speed_rad_s[c]
        dt = float(np.median(np.diff(t)))
        g = _response(w0, zeta, dt, (w * w - 1j * ra.acceleration_rad_s2[c]) * np.exp(1j * phi))
        psi = np.unwrap(np.angle(g * np.exp(-1j * phi)))
        new = smoothed_phase(t, theta - psi, c)
        step = float(np.max(np.abs((new.angle_rad[c] - phi) - np.mean(new.angle_rad[c] - phi))))
        ra = new
        del tt
        if step < 1e-3:
            break
    fit = fit_unbalance_response(t[c], z[c], ra.angle_rad[c], ra.speed_rad_s[c],
                                 ra.acceleration_rad_s2[c],
                                 natural_frequency_guess_hz=natural_frequency_guess_hz,
                                 damping_guess=damping_guess, runout=False)
    return replace(fit, angle_rad=math.nan, angle_rad_std=math.nan), ra
