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
residual is one recursive filter over the record (an exponential integrator
whose step integral is a Gauss rule over the angle interpolated between the
samples: exact to ~1e-9 down to 10 samples per revolution, where a first-order
hold of the sampled forcing was 1 % off).
No quasi-steady assumption: the sweep-rate lag that
:func:`dsp.runup.resonance_from_runup` corrects approximately is part of the
model here.  Uncertainties: the Gauss-Newton covariance of all parameters at
the optimum, scaled by the residual variance.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .errors import SignalError, check_signal
from .lsq import covariances as _covariances, linear_part as _linear, \
    propagated_angle as _propagated, runout_part as _runout_part, std_of as _std

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
    std_parts : dict
        What each std contains: ``{quantity: {part: std}}`` with quantities
        ``natural_frequency_hz``, ``damping_ratio``, ``specific_unbalance_m``,
        ``angle_rad``, ``critical_speed_hz`` and parts ``noise`` (the residuals'
        covariance, the larger of white and batch-means; with the angle estimated from
        the whirl, its spline's coefficients included), ``rotor_angle`` (what the speed
        channel leaves open: a keyphasor's timing, a tachometer's quantum, an encoder's
        count) and ``runout`` (a probe runout allowed for, not fitted); the std is the
        root sum of squares of its parts.
    delay_s, delay_s_std : float
        The channels' delay behind the rotor angle [s], fitted with ``fit_delay`` (else 0).
    sensor, sensor_std, solution : tuple
        With ``fit_sensor``: :func:`dsp.artefacts.sensor_response` fitted (``lag_s2`` [s^2],
        ``lag_s`` [s], ``highpass_hz`` [Hz]), their stds; the search's (scaled) solution.
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
    std_parts: dict = field(default_factory=dict)
    delay_s: float = 0.0
    delay_s_std: float = math.nan
    sensor: tuple = ()
    sensor_std: tuple = ()
    solution: tuple = field(default=(), repr=False)


#: Gauss-Legendre nodes and weights on [0, 1] for the forcing integral over one sample step.
_GL_NODES, _GL_WEIGHTS = (lambda x, w: (0.5 * (x + 1.0), 0.5 * w))(*np.polynomial.legendre.leggauss(6))

# quintic Hermite basis on [0, 1] (value, slope, curvature at each end), highest power first
_HERMITE5 = np.array([[-6, 15, -10, 0, 0, 1], [-3, 8, -6, 0, 1, 0], [-0.5, 1.5, -1.5, 0.5, 0, 0],
                      [6, -15, 10, 0, 0, 0], [-3, 7, -4, 0, 0, 0], [0.5, -1, 0.5, 0, 0, 0]])


def _angle_at_nodes(t, phi, w, a):
    """phi, phi', phi'' at the Gauss nodes of every sample step, shape (N - 1, M).

    Between two samples the angle is the quintic that matches phi, phi', phi'' at
    both (exact for any angle that is a cubic over the step, e.g. a spline through
    keyphasor pulses; error O(dt^6) otherwise).
    """
    h = np.diff(t)[:, None]
    s = _GL_NODES[None, :]
    ends = [phi[:-1, None], h * w[:-1, None], h * h * a[:-1, None],
            phi[1:, None], h * w[1:, None], h * h * a[1:, None]]
    out = []
    for d in range(3):
        acc = 0.0
        for c, v in zip(_HERMITE5, ends):
            acc = acc + v * np.polyval(np.polyder(c, d) if d else c, s)
        out.append(acc / h ** d)
    return out


class _Forcing:
    """The unit unbalance forcing (phi'^2 - i phi'') e^{i phi} of a record, sampled finely
    enough to convolve it exactly with the rotor's impulse response.

    The response from rest of z'' + 2 zeta w0 z' + w0^2 z = F is
    g = (G1 - G2) / (l1 - l2) with G_k' = l_k G_k + F (l_k the roots of
    s^2 + 2 zeta w0 s + w0^2), i.e. G_k(t_{n+1}) = e^{l_k dt} G_k(t_n) +
    int_{t_n}^{t_{n+1}} e^{l_k (t_{n+1} - s)} F(s) ds: an exponential integrator
    whose step integral is a 6-point Gauss-Legendre rule over the angle
    interpolated between the samples (:func:`_angle_at_nodes`).  A first-order
    hold of the sampled forcing instead loses (phi' dt)^2 / 12 of the
    amplitude and bends its phase: 1 % at 10 samples per revolution.
    """

    def __init__(self, t, phi, w, a):
        self.dt = float(np.median(np.diff(t)))
        p, pw, pa = _angle_at_nodes(t, phi, w, a)
        self.nodes = (pw * pw - 1j * pa) * np.exp(1j * p)         # (N - 1, M)
        self.samples = (w * w - 1j * a) * np.exp(1j * phi)       # F at the samples

    def response(self, w0, zeta, order=0):
        """g, or its velocity g' (``order`` 1) or acceleration g'' (``order`` 2), from the
        same modal states: g' = (l1 G1 - l2 G2) / (l1 - l2), g'' = (l1^2 G1 - l2^2 G2) /
        (l1 - l2) + F (nothing differentiated numerically)."""
        from scipy import signal

        dt = self.dt
        r = np.roots([1.0, 2.0 * zeta * w0, w0 * w0]).astype(complex)
        if abs(r[0] - r[1]) < 1e-12 * w0:
            r = r + np.array([1e-9, -1e-9]) * w0
        G = []
        for lam in r:
            k = dt * _GL_WEIGHTS * np.exp(lam * dt * (1.0 - _GL_NODES))
            step = self.nodes @ k
            out = np.empty(step.size + 1, complex)
            out[0] = 0.0
            out[1:] = signal.lfilter([1.0], [1.0, -np.exp(lam * dt)], step)
            G.append(out)
        out = (r[0] ** order * G[0] - r[1] ** order * G[1]) / (r[0] - r[1])
        return out + self.samples if order == 2 else out


def _basis(w0, zeta, tt, forcing, rot, order=0):
    """Columns (g, h1, h2, 1, e^{i phi}) of the linear part, differentiated ``order`` times
    (the constant stays: a sensor's DC offset; ``rot`` is given in the channel's quantity)."""
    g = forcing.response(w0, zeta, order)
    sig = zeta * w0
    wd = w0 * math.sqrt(max(1.0 - zeta * zeta, 1e-12))
    env = np.exp(-sig * tt)
    c, s = np.cos(wd * tt), np.sin(wd * tt)
    # d/dt of env (a c + b s) = env ((-sig a + wd b) c + (-sig b - wd a) s)
    h = [(1.0, 0.0), (0.0, 1.0)]
    for _ in range(order):
        h = [(-sig * a + wd * b, -sig * b - wd * a) for a, b in h]
    out = np.empty((tt.size, 5), complex)
    out[:, 0], out[:, 3], out[:, 4] = g, 1.0, rot
    out[:, 1], out[:, 2] = (env * (a * c + b * s) for a, b in h)
    return out


def fit_unbalance_response(t, z, angle_rad, speed_rad_s=None, acceleration_rad_s2=None, *,
                           natural_frequency_guess_hz=None, damping_guess=0.05, runout=True,
                           covariance=True, angle_basis=None, angle_error=None,
                           derivative: int = 0, tolerance: float = 1e-12,
                           runout_allowance_m: float = 0.0, channel_filter=None, censored=None,
                           fit_delay: bool = False, fit_sensor: bool = False, solution=None):
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
        itself estimated from the whirl (not identifiable then: see
        :func:`fit_response_without_speed`; ``runout_allowance_m`` puts its effect in
        the std instead).
    covariance : bool
        Compute the uncertainties (off: the stds are NaN; for inner iterations).
    angle_basis : tuple of 3 ndarray (N, K), optional
        When the rotor angle was itself estimated from ``z`` as a combination of K
        functions of time (a spline's basis; with their first and second derivatives):
        the K coefficients enter the covariance as nuisance parameters (a change of them
        turns the model's motion and changes the speed and acceleration of its forcing:
        :func:`_angle_columns`), so the stds include what the angle's estimate leaves open.
    angle_error : dsp.held_display.AngleError, optional
        When the rotor angle was measured with an uncertainty of its own (a held
        tachometer display): its error modes are propagated into the covariance
        (the fit's sensitivity to each, through the rotation i z a of what turns
        with the angle: the forced response and the runout).
    derivative : int
        What ``z`` measures: 0 displacement [m], 1 velocity [m/s], 2 acceleration
        [m/s²] (velocity pickups, accelerometers).  The model's response is
        differentiated (its exact discretisation read at the velocity or the
        acceleration), so the record is fitted in its own quantity and nothing is
        integrated through noise or DC drift; e, f_1 and zeta are the same parameters.
        ``offset_m``, ``runout_m`` and ``residual_rms_m`` are then in the channel's
        SI unit, and the runout (a displacement probe's) is not fitted.
    tolerance : float
        Relative tolerance of the search over (omega_1, zeta) (scipy's xtol, ftol, gtol).
    runout_allowance_m : float
        With ``runout`` off: a 1X runout r e^{i (phi + gamma)} the fit does not model, of
        magnitude up to this [m] at an unknown angle gamma.  Its effect on the estimate,
        linear in r (-(J'J)^-1 J' r e^{i phi}), enters the covariance as the RMS over a
        uniform gamma at |r| = ``runout_allowance_m`` (the worst angle then moves a
        quantity by sqrt(2) times that part).
    channel_filter : dsp.artefacts.ChannelFilter, optional
        The channels' declared filter (anti-alias low-pass, group delay): the model's
        response goes through it before it meets the record, so f_1, zeta, e and the angle
        are the rotor's.
    censored : array_like of bool, optional
        Samples left out of the fit (clipped), the time base kept whole.
    fit_delay : bool
        Fit a delay tau [s] of the channels behind the rotor angle as well (``delay_s``,
        ``delay_s_std``): an undeclared filter or a channel skew shows as a phase growing
        with the speed, w tau, which the rotor's bounded phase cannot make.
    fit_sensor : bool
        Fit an undeclared sensor response as well (``sensor``: the parameters of
        :func:`dsp.artefacts.sensor_response`, each >= 0, applied quasi-steadily: each
        column times the response at its own frequency): a mounted resonance lifts the
        gain as the speed grows, a high-pass leads the phase as 1 / w at low speed; the
        rotor's own response makes neither.
    solution : tuple, optional
        ``ResponseFit.solution`` of a call with the same arguments: the search is skipped.

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

    keep = np.ones(np.size(t), bool) if censored is None else ~np.asarray(censored, bool)
    if keep.shape != np.shape(t) or keep.sum() < 64:
        raise SignalError(f"censored: {int((~keep).sum())} of {keep.size} samples censored; the "
                          "fit needs 64 others")
    z = np.where(keep, z, np.mean(np.asarray(z)[keep]))
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
    forcing = _Forcing(t, phi, w, a)
    tt = t - t[0]
    zc = np.where(keep, z, 0.0)

    whole = bool(keep.all())
    memo = {}   # the last used stages' columns: a step in the delay or the sensor reuses the rotor's

    def stage(key, make):
        memo[key] = memo.pop(key) if key in memo else make()    # the least recently used goes
        if len(memo) > 8:
            del memo[next(iter(memo))]
        return memo[key]

    def rotor(w0, zeta):
        B = _basis(w0, zeta, tt, forcing, rot, order)
        return B if channel_filter is None else channel_filter.apply(t, B)

    def sensed(w0, zeta, sensor):
        from .artefacts import sensed_columns

        B = stage((w0, zeta), lambda: rotor(w0, zeta))
        return sensed_columns(t, B, w, w0 * math.sqrt(max(1.0 - zeta * zeta, 1e-12)), sensor,
                              forcing.dt)

    def model(w0, zeta, tau=0.0, sensor=()):
        B = stage((w0, zeta, tuple(sensor)), lambda: sensed(w0, zeta, sensor))
        if tau:
            from .artefacts import delay_weights, delayed

            B = delayed(t, B, tau, stage(tau, lambda: delay_weights(t, tau)))
        return B if whole else B * keep[:, None]      # (x 1.0 changes no bit: not done)
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

    ns = 3 * bool(fit_sensor)      # sensor: lag [ms^2], lag [ms], high-pass [Hz], all >= 0

    def resid(p):
        w0, zeta = p[0] * w_guess, p[1]
        _, r = _linear(model(w0, zeta, p[2] * 1e-3 if fit_delay else 0.0, p[p.size - ns:]), zc)
        return np.concatenate((r.real, r.imag)) / scale

    p0 = np.array([1.0, float(damping_guess)] + [0.0] * (fit_delay + ns))
    lo = [0.2, 1e-5] + [-50.0] * fit_delay + [0.0] * ns
    hi = [5.0, 0.7] + [50.0] * fit_delay + [1e3, 50.0, 5.0][:ns]
    x = np.array(solution, float) if solution is not None else least_squares(resid, p0, bounds=(
        lo, hi), x_scale=[0.01, 0.01] + [0.1] * (fit_delay + ns), xtol=tolerance, ftol=tolerance, gtol=tolerance).x
    w0, zeta, tau = x[0] * w_guess, float(x[1]), float(x[2]) * 1e-3 if fit_delay else 0.0
    sensor = tuple(float(v) for v in x[x.size - ns:]) if ns else ()
    if not (0.95 * float(np.min(np.abs(w))) <= w0 <= 1.05 * wmax):
        raise SignalError(f"natural frequency: the fit gives {w0 / TWO_PI:.4g} Hz, outside the "
                          f"record's speeds ({np.min(np.abs(w)) / TWO_PI:.4g}-{wmax / TWO_PI:.4g} "
                          "rev/s); a record that does not pass the resonance does not determine it")
    B = model(w0, zeta, tau, sensor)
    c, r = _linear(B, zc)
    n = int(keep.sum())
    if not covariance:
        nan = math.nan
        shift = 1.0 / math.sqrt(1.0 - 2.0 * zeta * zeta) if zeta < 1 / math.sqrt(2) else nan
        return ResponseFit(w0 / TWO_PI, nan, zeta, nan, w0 * shift / TWO_PI, nan,
                           float(abs(c[0])), nan, float(np.angle(c[0])), nan, complex(c[3]),
                           complex(c[4]) if runout else 0j,
                           float(np.sqrt(np.sum(np.abs(r) ** 2) / n)), int(n), delay_s=tau,
                           sensor=_sensor_si(sensor), solution=tuple(x))
    # covariance of all real parameters: (w0, zeta, Re/Im of the 5 complex coefficients)
    m = 2 + 2 * c.size       # (w0, zeta, coefficients), then the delay [s] and the sensor's

    def full(p):
        Bp = model(p[0], p[1], p[m] if fit_delay else 0.0, p[p.size - ns:])
        cc = p[2:m:2] + 1j * p[3:m:2]
        rr = (zc - Bp @ cc)[keep]
        return np.concatenate((rr.real, rr.imag))

    p = np.concatenate(([w0, zeta], np.column_stack((c.real, c.imag)).ravel(), [tau] * fit_delay,
                        sensor))
    J = np.empty((2 * n, p.size))
    Bk = B[keep]    # the coefficients' columns exactly (the model is linear in them): -B, -i B
    J[:, 2:m:2], J[:, 3:m:2] = -np.vstack((Bk.real, Bk.imag)), np.vstack((Bk.imag, -Bk.real))
    for j in [0, 1] + list(range(m, p.size)):      # the others by central differences
        h = 1e-6 if j >= m else 1e-6 * max(abs(p[j]), 1e-3 * (w0 if j == 0 else 1e-2))
        pp, pm = p.copy(), p.copy()
        pp[j], pm[j] = p[j] + h, p[j] - h
        J[:, j] = (full(pp) - full(pm)) / (2 * h)
    if angle_basis is not None:
        extra = -_angle_columns(t, phi, w, a, w0, zeta, 1.0 if runout and order == 0 else 0.0,
                                c, angle_basis)[keep]
        J = np.hstack((J, np.vstack((extra.real, extra.imag))))
    r = r[keep]

    covs = _covariances(J, r, J.shape[1])
    extra = {}
    if runout_allowance_m and not (runout and order == 0):
        extra["runout"] = _runout_part(J, np.exp(1j * phi[keep]), runout_allowance_m)
    if angle_error is not None:
        extra["rotor_angle"] = _propagated(J, -1j * (B[keep, 0] * c[0] + B[keep, 4] * c[4]),
                                           w[keep], t[keep], angle_error)
    noise_covs = covs
    covs = tuple(C + sum(extra.values()) for C in covs)
    q = c[0]
    e = abs(q)
    # e along q, angle across it
    u = np.array([q.real, q.imag]) / e if e > 0 else np.array([1.0, 0.0])
    v = np.array([-u[1], u[0]])
    shift = 1.0 / math.sqrt(1.0 - 2.0 * zeta * zeta) if zeta < 1 / math.sqrt(2) else math.nan
    # d(f_c)/d(w0), d(f_c)/d(zeta)
    gc = np.array([shift, w0 * 2 * zeta * shift ** 3]) / TWO_PI
    grads = {"w0": (0, np.array([1.0])), "zeta": (1, np.array([1.0])), "e": (2, u),
             "beta": (2, v / e if e > 0 else v), "fc": (0, gc)}
    sd = {k: max(_std(C, i, g) for C in covs) for k, (i, g) in grads.items()}
    if not e > 0:
        sd["beta"] = math.pi
    names = {"w0": "natural_frequency_hz", "zeta": "damping_ratio", "e": "specific_unbalance_m",
             "beta": "angle_rad", "fc": "critical_speed_hz"}
    unit = {"w0": 1 / TWO_PI}
    parts = {names[k]: {"noise": max(_std(C, i, g) for C in noise_covs) * unit.get(k, 1.0),
                        **{p: _std(C, i, g) * unit.get(k, 1.0) for p, C in extra.items()}}
             for k, (i, g) in grads.items()}
    return ResponseFit(natural_frequency_hz=w0 / TWO_PI, natural_frequency_hz_std=sd["w0"] / TWO_PI,
                       damping_ratio=zeta, damping_ratio_std=sd["zeta"],
                       critical_speed_hz=w0 * shift / TWO_PI, critical_speed_hz_std=sd["fc"],
                       specific_unbalance_m=float(e), specific_unbalance_m_std=sd["e"],
                       angle_rad=float(math.atan2(q.imag, q.real)), angle_rad_std=sd["beta"],
                       offset_m=complex(c[3]), runout_m=complex(c[4]) if runout and order == 0 else 0j, residual_rms_m=float(np.sqrt(np.mean(np.abs(r) ** 2))),
                       samples=int(n), std_parts=parts, delay_s=tau, solution=tuple(x),
                       delay_s_std=(max(_std(C, m, np.array([1.0])) for C in covs)
                                    if fit_delay else math.nan), sensor=_sensor_si(sensor),
                       sensor_std=_sensor_si([max(_std(C, p.size - ns + k, np.array([1.0])) for C in covs)
                                              for k in range(ns)]))


def _sensor_si(sensor):
    """The fitted sensor response (lag [ms^2], lag [ms], high-pass [Hz]) in SI (s^2, s, Hz)."""
    return (sensor[0] * 1e-6, sensor[1] * 1e-3, float(sensor[2])) if len(sensor) else ()


def _phase_basis(t, phi, knot_revolutions: float = 20.0):
    """The basis of :func:`dsp.speed.smoothed_phase`'s spline over ``t`` and its first two
    derivatives, each (N, K) (the first function left out: a constant turn is the
    unbalance's angle, which has no reference)."""
    from scipy.interpolate import BSpline

    turns = (phi[-1] - phi[0]) / TWO_PI
    n_int = int(max(1, min(turns / knot_revolutions, t.size / 50)))
    inner = np.linspace(t[0], t[-1], n_int + 1)[1:-1]
    knots = np.concatenate(([t[0]] * 4, inner, [t[-1]] * 4))
    nb = knots.size - 4
    sp = BSpline(knots, np.eye(nb), 3)
    tc = np.clip(t, t[0], t[-1])
    return tuple(np.asarray(sp(tc, d))[:, 1:] for d in range(3))


def _angle_columns(t, phi, w, a, w0, zeta, rot_on, c, basis, h: float = 1e-6):
    """d(model)/d(angle's spline coefficients), (N, K) complex: the model's whole motion
    (forced response, transients, runout c[4] e^{i phi} if ``rot_on``) with its linear
    coefficients ``c`` held, differentiated (central differences of step ``h`` rad)
    through the forcing (phi, phi', phi''): not only its turn i z_model da (the
    quasi-steady part), but the speed and acceleration a change of the angle brings into
    the forced response."""
    B0, B1, B2 = basis
    tt = t - t[0]
    out = np.empty(B0.shape, complex)
    for k in range(B0.shape[1]):
        m = []
        for s_ in (h, -h):
            p_ = phi + s_ * B0[:, k]
            f = _Forcing(t, p_, w + s_ * B1[:, k], a + s_ * B2[:, k])
            m.append(_basis(w0, zeta, tt, f, rot_on * np.exp(1j * p_)) @ c)
        out[:, k] = (m[0] - m[1]) / (2 * h)
    return out


def _extrapolated(new, old, c, gain):
    """``old + gain (new - old)`` on the covered samples (angle, speed and acceleration)."""
    from dataclasses import replace

    out = {}
    for key in ("angle_rad", "speed_rad_s", "acceleration_rad_s2"):
        a, b = getattr(old, key), getattr(new, key).copy()
        b[c] = a[c] + gain * (b[c] - a[c])
        out[key] = b
    return replace(new, **out)


def fit_response_without_speed(t, z, *, iterations: int = 40, natural_frequency_guess_hz=None,
                               damping_guess=0.05, runout_allowance_m: float = 0.0):
    """The fit of :func:`fit_unbalance_response` when no speed channel was recorded.

    The rotor angle is estimated from the whirl itself
    (:func:`dsp.speed.angle_from_1x`): the forward whirl's phase is
    theta = phi + beta + arg H(phi'), with the receptance's angle arg H turning by
    about pi through the resonance.  Each iteration fits the model with the
    current angle, and corrects the angle by the phase of the measured whirl
    against the model's whole motion (forced response and transients),
    phi += arg((z - z0) / z_model) (smoothed: a cubic spline every 20
    revolutions, each sample weighted by |z_model|), until phi changes by less
    than 1e-10 rad or 1e-4 of the phase's noise: at the fixed point the model's
    phase is the whirl's, so noise-free data from the model give its parameters
    back.  The weights make
    each correction the Gauss-Newton step of the joint least-squares fit in the
    spline's coefficients (a phase read off a radius A scatters by sigma / A), so
    the fixed point is the joint fit whose covariance is stated (the spline's
    coefficients as nuisance parameters); unweighted, the slow, small whirl's
    phase noise entered the angle at full weight and zeta, U scattered by
    ~1.5 times their std.

    The probes' 1X runout r e^{i (phi + gamma)} is not fitted: with the angle estimated
    from the whirl, a runout, a slow turn of the angle (which also changes the speed in
    the forcing) and changes of e and zeta make a shallow, curved valley of the joint
    least-squares problem.  Fitted jointly (the runout column and Levenberg-Marquardt
    over (omega_1, zeta) and the angle's spline), noise-free model data without runout
    came back with a fitted runout of 3 um and e 0.16 % off (a local minimum, the
    residual 4e-5 of the signal), and with 2 um of probe noise e was 8 and 18 of its
    linearised stds off: the linearised covariance does not describe that valley.
    Instead the runout's effect, linear in r, is put in the covariance for a runout of
    magnitude ``runout_allowance_m`` at an unknown angle (:func:`_runout_part`): the
    stated std covers a runout up to that size, not a larger one.

    Parameters
    ----------
    t : array_like
        Sample times [s], uniform.
    z : array_like (complex)
        x + i y [m].
    iterations : int
        Most angle corrections.
    natural_frequency_guess_hz, damping_guess : float, optional
        Start values (as :func:`fit_unbalance_response`).
    runout_allowance_m : float
        The largest 1X runout of the probes [m] the stds allow for (0: none).

    Returns
    -------
    (ResponseFit, RotorAngle)
        The fit (``angle_rad`` NaN: without a reference mark the unbalance has
        no angle; ``runout_m`` 0: not fitted) and the
        estimated rotor angle (``estimated`` True).
    """
    from dataclasses import replace

    from .speed import angle_from_1x, smoothed_phase

    t, z, _ = check_signal(t, z, "z", min_samples=64)
    allowance = float(runout_allowance_m)
    if not (math.isfinite(allowance) and allowance >= 0):
        raise SignalError(f"runout_allowance_m = {runout_allowance_m!r} m: the probes' largest "
                          "1X runout must be finite and >= 0")
    z0 = complex(np.mean(z))
    ra = angle_from_1x(t, z - z0)
    c = ra.covered
    fit, prev, jump, step = None, None, False, 1.0
    for _ in range(max(1, iterations)):
        fit = fit_unbalance_response(t[c], z[c], ra.angle_rad[c], ra.speed_rad_s[c],
                                     ra.acceleration_rad_s2[c],
                                     natural_frequency_guess_hz=natural_frequency_guess_hz,
                                     damping_guess=damping_guess, runout=False, covariance=False,
                                     tolerance=float(np.clip(1e-3 * step, 1e-12, 1e-6)))
        natural_frequency_guess_hz = fit.natural_frequency_hz
        damping_guess = fit.damping_ratio
        tt = t[c] - t[c][0]
        w0, zeta = TWO_PI * fit.natural_frequency_hz, fit.damping_ratio
        phi, w = ra.angle_rad[c], ra.speed_rad_s[c]
        forcing = _Forcing(t[c], phi, w, ra.acceleration_rad_s2[c])
        B = _basis(w0, zeta, tt, forcing, np.zeros(tt.size))
        coef, _ = _linear(B, z[c])
        zm = B[:, :3] @ coef[:3]            # the model's motion: forced response + transients
        # the whirl's phase minus the model's: the rotor angle's error (zero at the fixed point)
        ok = np.abs(zm) > 1e-9 * np.max(np.abs(zm))
        corr = np.zeros(tt.size)
        corr[ok] = np.unwrap(np.angle((z[c][ok] - coef[3]) / zm[ok]))
        corr[~ok] = np.interp(np.flatnonzero(~ok), np.flatnonzero(ok), corr[ok])
        new = smoothed_phase(t, phi + corr, c,
                             weights=np.maximum(np.abs(zm), 1e-9 * np.max(np.abs(zm))))
        d = new.angle_rad[c] - phi
        d -= np.mean(d)
        step = float(np.max(np.abs(d)))
        # the corrections shrink geometrically (by ~0.5 per step): every other step jumps
        # to the sequence's limit along the last correction (Aitken), and the iteration
        # stops at a ten-thousandth of the phase's noise (sigma / |z_model|) or 1e-10 rad
        r = float(d @ prev / (prev @ prev)) if prev is not None and jump else 0.0
        ra = _extrapolated(new, ra, c, 1.0 / (1.0 - r)) if 0.1 < r < 0.9 else new
        prev, jump = d, not jump
        noise = float(np.sqrt(np.mean(np.abs(z[c] - coef[3] - zm) ** 2)
                              / np.mean(np.abs(zm) ** 2)))
        if step < max(1e-10, 1e-4 * noise):
            break
    fit = fit_unbalance_response(t[c], z[c], ra.angle_rad[c], ra.speed_rad_s[c],
                                 ra.acceleration_rad_s2[c],
                                 natural_frequency_guess_hz=natural_frequency_guess_hz,
                                 damping_guess=damping_guess, runout=False,
                                 angle_basis=_phase_basis(t[c], ra.angle_rad[c]),
                                 runout_allowance_m=allowance)
    return replace(fit, angle_rad=math.nan, angle_rad_std=math.nan), ra
