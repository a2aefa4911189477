"""The 1X vector of a linear run-up (or run-down) through one mode: the exact response.

:func:`dsp.bode.modal_fit` fits a table with the steady shape taken at the lagged speed
(Omega - alpha tau(Omega), tau the group delay): right to first order in the sweep rate
alpha, but through the resonance the response of a sweep also rings, and what is left
biased the unbalance's angle of ``data_samples/daq/bode_table.csv`` (0.05 rev/s^2, zeta
0.04) by 0.5 deg, 2.8 of its std.  :func:`sweep_response` integrates the mode exactly on
a linear sweep so that the fit's bias can be measured on its own model and taken off
(``modal_fit``: fit, simulate the fitted sweep, refit, subtract the difference).

The mode: z'' + 2 zeta w0 z' + w0^2 z = q (Omega^2 - i alpha) e^{i phi}, phi' = Omega,
Omega' = alpha, z the complex (x + i y) displacement [m], q = e e^{i beta} [m]; the
table's 1X vector is z e^{-i phi} (steady: q r^2 / (1 - r^2 + 2 i zeta r)).
"""
from __future__ import annotations

import math

import numpy as np

__all__ = ["sweep_response"]

TWO_PI = 2.0 * math.pi


def sweep_response(speed_rad_s, w0, zeta, alpha, q, bins=None, *, steps_per_width: int = 200,
                   max_steps: int = 200_000):
    """The 1X vector of a sweep at ``alpha`` through one mode, at the table's speeds.

    Each of the mode's two complex coordinates (z = y1 + y2, y' = lambda y + f) is
    integrated as its envelope u = y e^{-i phi}, u' = (lambda - i Omega) u + f e^{-i phi},
    on steps of equal speed increment: exponential steps with the coefficient at the
    step's middle (its integral is exact, Omega being linear in time) and the forcing held.
    The steps resolve the half-power width zeta w0 and the bins, whatever the rate.

    Parameters
    ----------
    speed_rad_s : array_like
        The table's speeds Omega [rad/s], increasing, > 0.
    w0 : float
        Natural frequency [rad/s].
    zeta : float
        Damping ratio [-], 0 < zeta < 1.
    alpha : float
        Sweep rate dOmega/dt [rad/s^2]; > 0 a run-up, < 0 a run-down, != 0.
    q : complex
        Specific unbalance e e^{i beta} [m].
    bins : array_like, optional
        Width of each point's speed bin [rad/s]: the point is the mean of the 1X vector
        over its bin (order tracking averages; 5-point Gauss-Legendre, as dsp.bode's
        model); None: the 1X vector at the speed.
    steps_per_width : int
        Steps per half-power width zeta w0 (and per bin).
    max_steps : int
        More steps are not made (None returned).

    Returns
    -------
    ndarray (complex) or None
        The 1X vectors [m]; None when the sweep would need more than ``max_steps`` steps.
    """
    w = np.asarray(speed_rad_s, float)
    half = 0.5 * np.asarray(bins, float) if bins is not None else np.zeros_like(w)
    # start early enough that the start (steady) state's error has decayed: 6 time constants
    margin = 6.0 * abs(alpha) / (zeta * w0)
    lo = max(float(np.min(w - half)) - margin, 0.5 * float(w[0]))
    hi = float(np.max(w + half)) + margin
    dw = zeta * w0 / steps_per_width
    if bins is not None and np.any(half > 0):
        dw = min(dw, 2.0 * float(np.min(half[half > 0])) / steps_per_width)
    n = max(int(math.ceil((hi - lo) / dw)), 2)
    if n > max_steps:
        return None
    om = np.linspace(lo, hi, n + 1) if alpha > 0 else np.linspace(hi, lo, n + 1)
    fine = np.linspace(om[0], om[-1], 2 * n + 1)
    # the held coefficient and forcing lag by half a step (first order in the step):
    # Richardson's extrapolation of the steps' halving takes that off
    v = 2.0 * _envelope(fine, w0, zeta, alpha, q)[::2] - _envelope(om, w0, zeta, alpha, q)
    if alpha < 0:
        om, v = om[::-1], v[::-1]
    def at(x):
        return np.interp(x, om, v.real) + 1j * np.interp(x, om, v.imag)

    if bins is None:
        return at(w)
    # the bin mean as dsp.bode's model takes it (5-point Gauss-Legendre): the refit of
    # this table differs from the table's own fit by the sweep only
    x, g = np.polynomial.legendre.leggauss(5)
    return sum(0.5 * gi * at(w + xi * half) for xi, gi in zip(x, g))

def _envelope(om, w0, zeta, alpha, q):
    """The 1X vector z e^{-i phi} [m] at the speeds ``om`` [rad/s] (equal steps in the
    direction of the sweep), from the steady state at ``om[0]`` (:func:`sweep_response`)."""
    n = om.size - 1
    h = abs(om[1] - om[0]) / abs(alpha)          # time step [s]
    mid = 0.5 * (om[1:] + om[:-1])
    wd = w0 * math.sqrt(1.0 - zeta * zeta)
    lam = (complex(-zeta * w0, wd), complex(-zeta * w0, -wd))
    force = q * (mid * mid - 1j * alpha) / (lam[0] - lam[1])   # f e^{-i phi}, mode 1; - for 2
    r = om[0] / w0
    z0 = q * r * r / (1.0 - r * r + 2j * zeta * r)
    y1 = (1j * om[0] * z0 - lam[1] * z0) / (lam[0] - lam[1])
    v = np.zeros(n + 1, complex)
    for lk, u, sign in ((lam[0], y1, 1.0), (lam[1], z0 - y1, -1.0)):
        mu = lk - 1j * mid
        a = np.exp(mu * h)
        g = (sign * force * (a - 1.0) / mu).tolist()
        a = a.tolist()
        out = [u]
        for k in range(n):
            u = a[k] * u + g[k]
            out.append(u)
        v += np.asarray(out)
    return v
