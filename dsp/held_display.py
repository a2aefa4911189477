"""The rotor angle of a held tachometer display, and the uncertainty its readings leave.

A counting tachometer shows, at each update ``u_k``, the pulses of its disc counted
over the gate ``[u_k - g, u_k]`` divided by the gate (the mean speed over it), and
holds the reading until the next update.  With back-to-back gates the angle turned
between two gate starts is the reading times the gate, so the angle at every gate's
start is known (:func:`held_angle`) to the count's quantum, whatever the speed does
inside a gate.  What the readings leave open (:class:`AngleError`):

* the count's quantum: each gate-start angle is a whole number of pulses, off by a
  uniform fraction of one pulse, ``sigma = q g / sqrt 12`` (``q`` one count per gate:
  the greatest common divisor of the readings' steps) -- through the spline's
  least-squares fit, a covariance of its coefficients, not taken to average out over
  the points a coefficient spans (the fractions follow the angle's own progression
  modulo one pulse: in a steady acceleration a sawtooth over many gates);
* the updates' timing: the display is sampled by the DAQ, so an update lies within
  one sample interval ``dt`` before the sample that first shows it.  It is taken at
  that sample (exact when the display updates on the DAQ's clock, as the stand's own
  export does); a display sampled asynchronously is then late by a uniform
  ``delta`` in ``[0, dt)``, common to all the updates when the gate is a whole number
  of samples: an angle error ``phi'(t) delta`` whose RMS about zero, ``dt / sqrt 3``,
  is stated (the mean delay put in the uncertainty, not removed: it is not known
  which of the two a record is).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["AngleError", "held_angle"]


@dataclass(frozen=True)
class AngleError:
    """The uncertainty of a reconstructed rotor angle:
    ``delta phi(t) = sum_j c_j B_j(t) + phi'(t) delta``.

    Attributes
    ----------
    knots : ndarray
        The full knot vector of the B-splines ``B_j`` of the angle [s].
    covariance : ndarray (K, K)
        Covariance of the coefficient errors ``c`` [rad^2].
    delay_std_s : float
        RMS (about zero) of a delay ``delta`` common to the whole angle [s].
    degree : int
        The B-splines' degree (3; 4 for the integral of a cubic speed spline).
    """

    knots: np.ndarray
    covariance: np.ndarray
    delay_std_s: float
    degree: int = 3

    def modes(self, t, speed_rad_s):
        """``(A, C)``: the angle's error at the times ``t`` [s] is ``A xi`` [rad] with
        ``xi ~ N(0, C)``; ``A`` a sparse (N, K + 1) matrix (the splines, then the speed)."""
        from scipy import sparse
        from scipy.interpolate import BSpline

        tk = self.knots
        D = BSpline.design_matrix(np.asarray(t, float), tk, self.degree, extrapolate=True)
        A = sparse.hstack([D, sparse.csr_matrix(np.asarray(speed_rad_s, float)[:, None])],
                          format="csr")
        k = self.covariance.shape[0]
        C = np.zeros((k + 1, k + 1))
        C[:k, :k] = self.covariance
        C[k, k] = self.delay_std_s ** 2
        return A, C


def _quantum(steps) -> float:
    """The greatest common divisor of a display's steps (its count quantum) [rad/s]: every
    reading is a whole number of counts, so every step is (to rounding) a multiple of it."""
    steps = steps[steps > 0]
    if steps.size == 0:
        return 0.0
    tol = 1e-6 * float(np.max(steps))
    q = float(np.min(steps))
    for s in steps:
        a, b = max(q, float(s)), min(q, float(s))
        while b > tol:                          # Euclid's algorithm with a tolerance
            a, b = b, a % b
            if a - b < tol:
                b = 0.0
        q = a
    return q


def held_angle(t, w, change):
    """The angle of a held display, exact at the gates' starts (module docstring).

    Parameters
    ----------
    t : ndarray
        Sample times [s] (uniform).
    w : ndarray
        The displayed speed at every sample [rad/s].
    change : ndarray of int
        The samples where the display changes (at least 2).

    Returns
    -------
    (angle, speed, acceleration, AngleError or None, covered)
        At the samples [rad], [rad/s], [rad/s^2]; the angle from 0 at ``t[0]``; covered:
        up to the end of the last gate (after it the angle is extrapolated, not measured).
        An update at ``u_k`` shows the mean over ``[u_k - g, u_k]`` and a reading repeated
        over several gates is the same mean over each, so
        ``Phi(u_{k+1} - g) - Phi(u_k - g) = r_k (u_{k+1} - u_k)``: a smoothing cubic
        spline through those angles at the quantum's residual gives the angle, speed and
        acceleration.  (Interpolating the speeds
        instead loses ``g^2 a / 8`` of angle at every change of the acceleration.)
    """
    from scipy.interpolate import BSpline, CubicSpline, UnivariateSpline

    dt = float(np.median(np.diff(t)))
    u = t[change].astype(float)                   # each update: at most dt before that
    gate = float(np.median(np.diff(u)))            # the typical hold: one gate
    # the reading shown at the start was updated a whole number of gates before the first
    # change; the last one is the mean over the gate before its update (and over each gate
    # the record shows it for after that)
    n0 = max(1, int(math.ceil((u[0] - t[0]) / gate - 0.05)))
    u = np.concatenate(([u[0] - n0 * gate], u))
    r = w[np.concatenate(([0], change))]
    last = u[-1] + gate * (1 + math.floor((t[-1] - u[-1]) / gate))
    ends = np.concatenate((u[1:], [last]))
    p, phi, at = [], [], 0.0
    for uk, rk, nxt in zip(u, r, ends):
        m = max(int(round((nxt - uk) / gate)), 1)
        step = (nxt - uk) / m
        p.append(uk - gate + step * np.arange(m))
        phi.append(at + rk * step * np.arange(m))
        at += rk * (nxt - uk)
    p = np.concatenate(p + [[ends[-1] - gate]])
    phi = np.concatenate(phi + [[at]])
    # each angle is exact to the count's quantum (sigma = q g / sqrt 12): a smoothing
    # spline with that residual, so the counting's alternation (e.g. 1558 / 1562 rpm at
    # 1560) does not ripple the speed; its coefficients' covariance: that of the
    # least-squares spline on its knots (linear in the angles; the smoothing's penalty only
    # lowers it)
    q = _quantum(np.abs(np.diff(r)))
    sigma = q * gate / math.sqrt(12.0)
    if not (sigma > 0 and p.size > 4):
        spline = CubicSpline(p, phi, bc_type="natural")
        return spline(t) - spline(t[0]), spline(t, 1), spline(t, 2), None, t <= p[-1]
    spline = UnivariateSpline(p, phi, k=3, s=p.size * sigma * sigma)
    inner = spline.get_knots()
    tk = np.concatenate(([inner[0]] * 3, inner, [inner[-1]] * 3))
    D = BSpline.design_matrix(p, tk, 3).toarray()
    S = np.linalg.pinv(D)
    # the errors follow the angle's own progression modulo one pulse (a steady acceleration:
    # a linear sequence mod 1, a sawtooth over many gates), so they are not taken to average
    # out over the points each coefficient spans: (points / coefficients) x the white one
    span = p.size / (tk.size - 4)
    err = AngleError(tk, span * sigma * sigma * (S @ S.T), dt / math.sqrt(3.0))
    # past the last gate nothing is measured (not covered): the end's speed and acceleration
    # go on (the end's cubic, extrapolated, would swing by its third derivative)
    tc = np.minimum(t, tk[-1])
    h = t - tc
    a0, a1, a2 = spline(tc), spline(tc, 1), spline(tc, 2)
    ang = a0 + h * a1 + 0.5 * h * h * a2
    return ang - ang[0], a1 + h * a2, a2, err, t <= tk[-1]
