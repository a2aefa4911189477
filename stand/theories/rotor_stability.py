"""Stability of the main motion of any rotor with its weights: Floquet multipliers.

The theory issue's machinery (the Jacobian of the main motion, digest ch5
sections 3-4) works in rotating axes, where the isotropic planar rotor's main
motion is an equilibrium.  For a general rotor (anisotropic supports,
gyroscopic tilts, a body, modes) the main motion is a *periodic* motion of
period T = 2 pi / Omega in the fixed frame, so its linear stability is given
by the eigenvalues (Floquet multipliers) mu of the monodromy matrix, the
Jacobian of the one-revolution flow map (the same thing: for an equilibrium
in rotating axes mu = exp(lambda T)).  Stable iff every |mu| < 1, apart from
multipliers exactly on the unit circle that belong to a family of main motions
(n >= 3 weights in a plane: the configurations form a continuum).

* :func:`periodic_orbit` -- the main motion by Newton shooting from a guess
  (a converged simulation, :func:`settle`); the monodromy matrix by central
  finite differences of the compiled DOP853 flow (rtol 1e-11);
* :func:`floquet` -- multipliers and the growth rate ``log max|mu| / T`` [1/s];
* :func:`main_motion_stability` -- both, at one speed;
* :func:`main_motion_critical_speeds` -- continuation over a speed grid, the
  speeds where the growth rate changes sign refined by bisection.

Cost: one monodromy matrix is 2 N one-revolution integrations (N = number of
rotor coordinates + weights), about a millisecond each once compiled.
"""
from __future__ import annotations

import math
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Sequence

import numpy as np

from stand.integrate.coupled import CoupledModel, PlaneWeights, build_model, simulate_coupled
from stand.model.rotors.structure import LinearRotor

__all__ = ["settle", "periodic_orbit", "floquet", "MainMotionStability",
           "main_motion_stability", "main_motion_critical_speeds", "step_budget"]

RTOL = 1e-11
ATOL = 1e-13
#: the budget (:class:`stand.errors.Budget`, in state-steps: integration steps x state size)
#: the one-revolution flows spend while a scan runs under :func:`step_budget`; None:
#: unbounded (each flow alone is capped at 1e6 steps)
_BUDGET = None


@contextmanager
def step_budget(budget):
    """Count every one-revolution flow's state-steps against ``budget`` (a
    :class:`stand.errors.Budget`) inside the ``with`` block: a Floquet scan stops with
    :class:`stand.errors.BudgetExceeded` when it is used up."""
    global _BUDGET
    old, _BUDGET = _BUDGET, budget
    try:
        yield budget
    finally:
        _BUDGET = old


def _flow(model: CoupledModel, y0: np.ndarray, T: float) -> np.ndarray:
    """State after the scaled time T from y0 at tau = 0 (compiled DOP853)."""
    from stand.integrate.dop853 import REACHED_END
    from stand.integrate.kernel_set import kernels
    from stand.model.kernels import GENERIC

    ks = kernels(GENERIC)
    y = np.array(y0, dtype=float)
    f = np.empty_like(y)
    ks.evaluate(0.0, y, f, model.sp, model.wt, model.prog)
    ts = np.array([0.0, T])
    out = np.empty((2, y.size))
    cap = np.full(y.size, np.inf)
    st = np.zeros(3, np.int64)
    status, t, _, _ = ks.dop853(model.sp, model.wt, model.prog, 0.0, y, f, T / 50.0, T, RTOL, ATOL,
                                cap, np.inf, ts, 1, out, st, 1_000_000, 1e12)
    if _BUDGET is not None:
        _BUDGET.spend(int(st[0] + st[1]) * y.size)
    if status != REACHED_END or t < T:
        raise RuntimeError("one-revolution flow did not reach its end (diverged or stiff)")
    return out[1]


def _model(rotor, weights, omega):
    return build_model(rotor, weights, [[0.0, float(omega)]])


def settle(rotor: LinearRotor, weights: Sequence[PlaneWeights], omega: float,
           revolutions: int = 400) -> np.ndarray:
    """A state on (or near) the attracting motion at speed omega: the scaled
    state of :mod:`stand.integrate.coupled` after an integer number of
    revolutions from the balancers' initial angles (rotor angle 0 mod 2 pi)."""
    model = _model(rotor, weights, omega)
    T = 2 * math.pi / omega
    run = simulate_coupled(rotor, weights, [[0.0, omega]], revolutions * T, 1.0 / T,
                           rtol=1e-10, atol=1e-12)
    n, nw, w = model.n, model.nw, model.omega_ref
    y = np.concatenate([run.q[-1] / model.scale, run.weight_angle[-1],
                        run.qd[-1] / (model.scale * w),
                        np.zeros(nw + model.n_adhesion)])
    # weight rates: from the last two samples would be coarse; one revolution
    # of flow from here gives a consistent state
    y[2 * n + nw:] = 0.0
    return _flow(model, y, omega and 2 * math.pi / omega * w)


def _jacobian(model, y, T, fy=None):
    N = y.size
    J = np.empty((N, N))
    for k in range(N):
        h = 1e-6 * max(1.0, abs(y[k]))
        yp = y.copy()
        ym = y.copy()
        yp[k] += h
        ym[k] -= h
        J[:, k] = (_flow(model, yp, T) - _flow(model, ym, T)) / (2 * h)
    return J


def periodic_orbit(model: CoupledModel, y0: np.ndarray, T: float, tol: float = 1e-10,
                   max_iter: int = 20):
    """Newton shooting for Phi_T(y) = y (minimum-norm steps: a family of main
    motions makes the Jacobian singular).  Returns (y, monodromy, residual)."""
    y = np.array(y0, dtype=float)
    for _ in range(max_iter):
        Fy = _flow(model, y, T)
        G = Fy - y
        Mmat = _jacobian(model, y, T)
        res = float(np.max(np.abs(G)))
        if res < tol:
            return y, Mmat, res
        dy = np.linalg.lstsq(Mmat - np.eye(y.size), -G, rcond=1e-10)[0]
        y = y + dy
    Fy = _flow(model, y, T)
    return y, _jacobian(model, y, T), float(np.max(np.abs(Fy - y)))


def floquet(monodromy: np.ndarray, T_s: float, family_tol: float = 1e-5):
    """Multipliers (sorted by modulus, largest first), the growth rate
    ``log max|mu| / T`` [1/s] over the multipliers not within ``family_tol`` of
    1 (those of a family of main motions), and the count of such neutral ones."""
    mu = np.linalg.eigvals(monodromy)
    mu = mu[np.argsort(-np.abs(mu))]
    neutral = np.abs(mu - 1.0) < family_tol
    rest = mu[~neutral]
    rate = math.log(float(np.max(np.abs(rest)))) / T_s if rest.size else -math.inf
    return mu, rate, int(neutral.sum())


@dataclass(frozen=True)
class MainMotionStability:
    """Result of :func:`main_motion_stability`.

    Attributes
    ----------
    omega : float                 rad/s
    multipliers : ndarray         Floquet multipliers
    growth_rate : float           1/s (< 0: stable)
    neutral : int                 multipliers at 1 (family of main motions)
    stable : bool
    residual_unbalance : float    kg m, static residual of the orbit (0 for a main motion)
    orbit_error : float           Newton residual (scaled state)
    weight_angles : ndarray       rad, relative to the mark
    """

    omega: float
    multipliers: np.ndarray
    growth_rate: float
    neutral: int
    stable: bool
    residual_unbalance: float
    orbit_error: float
    weight_angles: np.ndarray


def _residual(model: CoupledModel, y) -> float:
    n, nw = model.n, model.nw
    U = sum(u.s * np.exp(1j * u.angle) for u in model.rotor.unbalances)
    for j in range(nw):
        U = U + model.wt[j, 1] * model.wt[j, 2] * np.exp(1j * y[n + j])
    return float(abs(U))


def main_motion_stability(rotor: LinearRotor, weights: Sequence[PlaneWeights], omega: float,
                          y_guess=None) -> MainMotionStability:
    """Floquet stability of the periodic motion reached from ``y_guess`` (default
    :func:`settle`) at constant spin omega [rad/s].  It is the main motion when
    ``residual_unbalance`` is small; the function does not force that."""
    omega = float(omega)
    if not (math.isfinite(omega) and omega > 0):
        raise ValueError(f"omega = {omega!r}: must be > 0 (rad/s)")
    model = _model(rotor, weights, omega)
    T = 2 * math.pi / omega * model.omega_ref
    y0 = settle(rotor, weights, omega) if y_guess is None else np.asarray(y_guess, float)
    y, Mmat, err = periodic_orbit(model, y0, T)
    mu, rate, neutral = floquet(Mmat, 2 * math.pi / omega)
    return MainMotionStability(omega, mu, rate, neutral, rate < 0, _residual(model, y), err,
                               y[model.n:model.n + model.nw].copy())


def main_motion_critical_speeds(rotor: LinearRotor, weights: Sequence[PlaneWeights], speeds,
                                y_guess=None, xtol: float = 1e-6):
    """Continuation of the main motion over ``speeds`` [rad/s] (increasing or
    decreasing; start where it exists, e.g. from a balanced simulation), its
    growth rate at each, and the speeds where the rate changes sign (bisection
    to ``xtol`` relative).  Returns (list of MainMotionStability, critical speeds)."""
    speeds = np.asarray(speeds, dtype=float)
    out = []
    y = y_guess
    for w in speeds:
        r = main_motion_stability(rotor, weights, w, y_guess=y)
        out.append(r)
        y = _state_guess(rotor, weights, r, w)
    crit = []
    for a, b in zip(out[:-1], out[1:]):
        if a.stable != b.stable:
            lo, hi, ya = a.omega, b.omega, _state_guess(rotor, weights, a, a.omega)
            sa = a.stable
            while abs(hi - lo) > xtol * abs(hi):
                m = 0.5 * (lo + hi)
                rm = main_motion_stability(rotor, weights, m, y_guess=ya)
                if rm.stable == sa:
                    lo, ya = m, _state_guess(rotor, weights, rm, m)
                else:
                    hi = m
            crit.append(0.5 * (lo + hi))
    return out, np.array(crit)


def _state_guess(rotor, weights, r: MainMotionStability, omega):
    """A guess at another speed: the weights' angles of ``r``, rotor at rest."""
    model = _model(rotor, weights, omega)
    y = np.zeros(2 * (model.n + model.nw) + model.n_adhesion)
    y[model.n:model.n + model.nw] = r.weight_angles
    return y
