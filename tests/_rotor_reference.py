"""An independent reference of the rigid rotor's run-up (issue 31): the exact solution of

    z'' + 2 zeta w0 z' + w0^2 z = e (phi'^2 - i phi'') e^{i (phi + beta)},

in its two modes (:func:`oracles.runup_exact.forced_response`; agrees with scipy's DOP853
at rtol 1e-10, which it replaced, to that tolerance), with the speed programme phi(t) given
in closed form, and the velocity z' (a state) and acceleration z'' (the right-hand side) from
the same solution -- not the stand's simulator, not the fit's discretisation.
"""
import math

import numpy as np

from oracles.runup_exact import forced_response

TWO_PI = 2 * math.pi
TRUTH = dict(f0_hz=12.0, zeta=0.04, e_m=40e-6, beta_rad=math.radians(30.0), mass_kg=6.0)


def programme(f_start=4.0, f_end=24.0, t_ramp=24.0, t_hold=5.0):
    """phi(t), phi'(t), phi''(t) of a linear run-up then a constant speed."""
    a = TWO_PI * (f_end - f_start) / t_ramp

    def phi(t):
        t = np.asarray(t, float)
        tr = np.minimum(t, t_ramp)
        return TWO_PI * f_start * tr + 0.5 * a * tr ** 2 + TWO_PI * f_end * np.maximum(t - t_ramp, 0)

    def w(t):
        return TWO_PI * f_start + a * np.minimum(np.asarray(t, float), t_ramp)

    def acc(t):
        return np.where(np.asarray(t, float) < t_ramp, a, 0.0)

    return phi, w, acc, t_ramp + t_hold


def runup(fs=1000.0, **kw):
    """``dict(t, phi, w, z, v, acc)`` [s, rad, rad/s, m, m/s, m/s²] of the reference run-up
    (started at rest), and the truth."""
    p = TRUTH
    w0, zeta, e, beta = TWO_PI * p["f0_hz"], p["zeta"], p["e_m"], p["beta_rad"]
    phi, w, acc, T = programme(**kw)

    def force(t):
        return e * (w(t) ** 2 - 1j * acc(t)) * np.exp(1j * (phi(t) + beta))

    t = np.arange(0.0, T, 1.0 / fs)
    z, v = forced_response(t, force, w0, zeta)
    a = force(t) - 2 * zeta * w0 * v - w0 * w0 * z
    crit = p["f0_hz"] / math.sqrt(1 - 2 * zeta ** 2)
    return dict(t=t, phi=phi(t), w=w(t), z=z, v=v, acc=a), dict(p, critical_hz=crit)
