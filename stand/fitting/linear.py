"""The fit's linear nuisance: what the record adds to the model that is linear in its
coefficients, solved in closed form at every trial of the scene values (variable projection,
Golub & Pereyra 1973).

* the sensors' DC offset ``c0`` (complex; a probe's gap voltage);
* a probe's 1X runout ``c1 e^{i phi}`` (complex; a vector fixed to the rotor), when the record
  can tell it from the unbalance response (a sweep);
* the measured rotor angle's own error ``delta phi(t) = A(t) xi`` (a keyphasor's timing, an
  encoder's count, a tachometer's quantum: :class:`dsp.held_display.AngleError`), with its
  Gaussian prior ``xi ~ N(0, C)``.  The model's signal changes by ``G eta`` (``eta = C^-1/2
  xi``, whitened), ``G`` the simulation's own sensitivity to each error mode of the drive
  (finite differences of simulations driven by the perturbed angle:
  :meth:`stand.fitting.objective.Objective.angle_sensitivity`) -- not the quasi-static turn
  ``i m delta phi``: near a resonance the shaft does not follow a wobble of the drive's phase
  within its own time constant.  The coefficients are estimated with the prior (one prior
  row per mode), so the residual left for the scene values is white noise when the model is
  right, and their covariance contains what the angle leaves open.

:class:`LinearPart` builds the design for one model signal; :meth:`LinearPart.solve` returns
the augmented residual ``[(z - m - D c) / sigma; eta]`` and the orthonormal basis that projects
the scene values' Jacobian.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np

__all__ = ["AngleModes", "angle_modes", "LinearPart"]


@dataclass(frozen=True)
class AngleModes:
    """The measured angle's error modes at the fitted samples, whitened:
    ``delta phi = W eta`` with ``eta ~ N(0, I)`` (W (N, K) dense)."""

    W: np.ndarray

    @property
    def count(self) -> int:
        return self.W.shape[1]


def angle_modes(angle, t) -> Optional[AngleModes]:
    """The whitened modes of a :class:`dsp.speed.RotorAngle`'s ``angle_error`` at the samples
    ``t`` (None when the source states none)."""
    err = getattr(angle, "angle_error", None) if angle is not None else None
    if err is None:
        return None
    A, C = err.modes(np.asarray(t, float), np.asarray(angle.speed_rad_s, float))
    lam, V = np.linalg.eigh(0.5 * (C + C.T))
    keep = lam > 1e-14 * max(float(lam.max(initial=0.0)), 1e-300)
    if not keep.any():
        return None
    L = V[:, keep] * np.sqrt(lam[keep])              # C = L L'
    W = np.asarray(A @ L)
    corners = _corner_modes(angle, err.knots, np.asarray(t, float))
    if corners is not None:
        W = np.hstack([W, corners])
    live = np.any(W != 0.0, axis=0)
    return AngleModes(W[:, live]) if live.any() else None


def _corner_modes(angle, knots, t):
    """One mode per corner of the speed programme (a double knot of the keyphasor's spline,
    :func:`dsp.speed.angle_from_pulses` ``corners=True``): where the corner lies between two
    pulses is not known to better than the pulses' spacing, and the angle's shape near it
    follows its place.  The mode is the angle's change when the corner moves by its prior std,
    half the local pulse interval (the spline refitted to the pulses with the knot moved)."""
    from scipy.interpolate import make_lsq_spline

    p = getattr(angle, "pulses_s", None)
    if p is None or knots is None:
        return None
    inner = np.asarray(knots, float)[4:-4]
    vals, counts = np.unique(inner, return_counts=True)
    doubles = vals[counts >= 2]
    if not doubles.size:
        return None
    k = 2.0 * np.pi * np.arange(p.size)
    base = make_lsq_spline(p, k, np.asarray(knots, float), k=3)
    cols = []
    for c in doubles:
        i = int(np.clip(np.searchsorted(p, c), 1, p.size - 1))
        sd = 0.5 * float(p[i] - p[i - 1])
        moved = np.where(np.asarray(knots) == c, c + sd, knots)
        try:
            sp = make_lsq_spline(p, k, np.sort(moved), k=3)
        except (ValueError, np.linalg.LinAlgError):
            continue
        tc = np.clip(t, p[0], p[-1])
        cols.append(sp(tc) - base(tc))
    return np.column_stack(cols) if cols else None


class LinearPart:
    """The linear nuisance of one fit (module docstring).

    Parameters
    ----------
    phi : ndarray (N,) or None   the rotor angle at the fitted samples [rad] (runout basis)
    runout : bool                fit a 1X runout
    modes : AngleModes or None   the angle's error modes
    sigma : float                the noise std per component [record's SI unit]

    Attributes
    ----------
    G : ndarray (N, K) complex or None
        The model's sensitivity to the whitened modes (set by the objective; None: the
        modes are left out, e.g. while the starts are compared).
    """

    def __init__(self, phi, runout: bool, modes: Optional[AngleModes], sigma: float):
        self.phi = None if phi is None else np.asarray(phi, float)
        self.runout = bool(runout) and self.phi is not None
        self.modes = modes
        self._sigma = float(sigma)
        self._G = None
        self._qr: dict = {}

    # the design depends on the samples, G and sigma only, not on the model signal: its QR is
    # made once per stretch and reused by every trial of the scene values (setting G or sigma
    # forgets it)
    @property
    def sigma(self) -> float:
        return self._sigma

    @sigma.setter
    def sigma(self, value: float) -> None:
        self._sigma = float(value)
        self._qr.clear()

    @property
    def G(self):
        return self._G

    @G.setter
    def G(self, value) -> None:
        self._G = value
        self._qr.clear()

    def _factored(self, n: int):
        """``(D, Q, R, n_lin)`` of the design of ``n`` samples (cached)."""
        if n not in self._qr:
            if len(self._qr) > 2:
                self._qr.pop(next(iter(self._qr)))
            D, nl = self.design(np.zeros(n))
            Q, R = np.linalg.qr(D)
            self._qr[n] = (D, Q, R, nl)
        return self._qr[n]

    @property
    def k(self) -> int:
        """The number of angle modes in the design."""
        return 0 if self.G is None else self.G.shape[1]

    def design(self, m):
        """Real design (2N + K, L) of the model signal ``m`` (N,): offset, runout, angle modes,
        the data rows divided by sigma, the modes' prior rows below."""
        n = m.size
        cols = [np.concatenate([np.ones(n), np.zeros(n)]),
                np.concatenate([np.zeros(n), np.ones(n)])]
        if self.runout:
            c, s = np.cos(self.phi[:n]), np.sin(self.phi[:n])
            cols += [np.concatenate([c, s]), np.concatenate([-s, c])]
        k = self.k
        D = np.zeros((2 * n + k, len(cols) + k))
        for j, col in enumerate(cols):
            D[:2 * n, j] = col / self.sigma
        if k:
            G = self.G[:n]
            D[:n, len(cols):] = G.real / self.sigma
            D[n:2 * n, len(cols):] = G.imag / self.sigma
            D[2 * n:, len(cols):] = np.eye(k)
        return D, len(cols)

    def solve(self, z, m):
        """``(r, Q, coef, n_lin)``: the augmented residual (2N + K,), an orthonormal basis Q of
        the design's columns, the coefficients (offset, runout as complex; eta) and the
        number of offset/runout real columns."""
        n = m.size
        k = self.k
        D, Q, R, nl = self._factored(n)
        y = np.zeros(2 * n + k)
        d = z[:n] - m
        y[:n], y[n:2 * n] = d.real / self.sigma, d.imag / self.sigma
        c = np.linalg.solve(R, Q.T @ y) if np.all(np.abs(np.diag(R)) > 0) else \
            np.linalg.lstsq(D, y, rcond=None)[0]
        r = y - D @ c
        coef = {"offset": complex(c[0], c[1]),
                "runout": complex(c[2], c[3]) if self.runout else 0j,
                "eta": c[nl:]}
        return r, Q, coef, nl

    def fitted_signal(self, m, coef):
        """The model signal with its fitted nuisance: m + offset + runout + i m delta phi."""
        n = m.size
        out = m + coef["offset"]
        if self.runout:
            out = out + coef["runout"] * np.exp(1j * self.phi[:n])
        if self.G is not None and coef["eta"].size:
            out = out + self.G[:n] @ coef["eta"]
        return out

    def angle_correction(self, coef, n):
        """delta phi at the first ``n`` samples [rad] (zeros without modes)."""
        if self.G is None or not coef["eta"].size:
            return np.zeros(n)
        return self.modes.W[:n] @ coef["eta"]
