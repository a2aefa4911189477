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
  (a converged simulation, :func:`settle`), each step halved until it lowers the
  residual (a full step that overshoots into a violent motion is not flown to its
  end: a flow may take at most :data:`FLOW_STEP_FACTOR` times the steps of the
  guess's own revolution); the monodromy matrix by central finite differences of
  the compiled DOP853 flow (rtol 1e-11);
* :func:`floquet` -- multipliers and the growth rate ``log max|mu| / T`` [1/s];
* :func:`main_motion_stability` -- both, at one speed;
* :func:`main_motion_critical_speeds` -- continuation over a speed grid, the
  speeds where the growth rate changes sign refined by bisection.  Only converged
  orbits (residual <= :data:`ORBIT_TOL`) count: where Newton does not find the
  orbit the step is halved (:data:`CONTINUATION_HALVINGS` times), then the
  continuation stops there (the main motion is lost: a fold, or out of reach of
  the guess) -- a growth rate of a point that is not a periodic orbit means nothing.

Cost: one monodromy matrix is 2 N one-revolution integrations (N = number of
rotor coordinates + weights), about a millisecond each once compiled.
"""
from __future__ import annotations

import math
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Sequence

import numpy as np

from stand.errors import BudgetExceeded
from stand.integrate.coupled import CoupledModel, PlaneWeights, build_model, simulate_coupled
from stand.model.rotors.structure import LinearRotor

__all__ = ["settle", "periodic_orbit", "floquet", "MainMotionStability",
           "main_motion_stability", "main_motion_critical_speeds", "step_budget"]

RTOL = 1e-11
ATOL = 1e-13
#: [scaled state] a periodic orbit counts as found when one revolution returns within this
#: (Newton aims at 1e-10; converged orbits reach 1e-15-1e-11, lost ones stay at 1e-3-10)
ORBIT_TOL = 1e-8
#: a flow from a Newton trial point may take at most this many times the steps of the flow
#: from the current point (at least :data:`MIN_FLOW_STEPS`): a trial that overshoots into a
#: violent motion is rejected (the step halved) instead of being integrated for a million
#: steps (the fixed-point stand sample: ~12 s per such flow, 88 s to the budget)
FLOW_STEP_FACTOR = 20
MIN_FLOW_STEPS = 20_000
#: halvings of a continuation step after which a main motion not found stops the continuation
CONTINUATION_HALVINGS = 3
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


def _flow(model: CoupledModel, y0: np.ndarray, T: float, max_steps: int = 1_000_000):
    """State after the scaled time T from y0 at tau = 0 (compiled DOP853)."""
    return _flow_steps(model, y0, T, max_steps)[0]


def _flow_steps(model: CoupledModel, y0: np.ndarray, T: float, max_steps: int = 1_000_000):
    """(:func:`_flow`, the steps it took); RuntimeError when it does not reach T within
    ``max_steps`` steps."""
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
                                cap, np.inf, ts, 1, out, st, int(max_steps), 1e12)
    if _BUDGET is not None:
        _BUDGET.spend(int(st[0] + st[1]) * y.size)
    if status != REACHED_END or t < T:
        raise RuntimeError("one-revolution flow did not reach its end (diverged or stiff)")
    return out[1], int(st[0] + st[1])


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
    motions makes the Jacobian singular), each step halved (up to 6 times) until the
    residual max|Phi_T(y) - y| goes down; stops when it reaches ``tol`` or no halving
    lowers it.  Returns (y, monodromy, residual) at the best point.  RuntimeError when
    the flow from ``y0`` itself does not reach the end of the revolution."""
    y = np.array(y0, dtype=float)
    Fy, n0 = _flow_steps(model, y, T)
    res = float(np.max(np.abs(Fy - y)))
    for _ in range(max_iter):
        Mmat = _jacobian(model, y, T)
        if res < tol:
            return y, Mmat, res
        dy = np.linalg.lstsq(Mmat - np.eye(y.size), y - Fy, rcond=1e-10)[0]
        cap = max(FLOW_STEP_FACTOR * n0, MIN_FLOW_STEPS)
        for _half in range(7):
            yt = y + dy
            try:
                Ft, nt = _flow_steps(model, yt, T, cap)
                rt = float(np.max(np.abs(Ft - yt)))
            except BudgetExceeded:
                raise
            except RuntimeError:          # the trial overshot into a violent motion
                rt = math.inf
            if rt < res:
                break
            dy = 0.5 * dy
        else:
            return y, Mmat, res           # no step lowers the residual: Newton stalls here
        y, Fy, res, n0 = yt, Ft, rt, nt
    return y, _jacobian(model, y, T), res


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
    orbit_error : float           Newton residual (scaled state); inf: the flow from the
                                  guess did not reach the end of a revolution
    weight_angles : ndarray       rad, relative to the mark
    state : ndarray               the orbit's scaled state at the mark (the guess of a
                                  continuation's next speed)

    ``converged`` (orbit_error <= :data:`ORBIT_TOL`): a periodic orbit was found; when not,
    the multipliers and the growth rate are those of the last Newton point, no orbit's.
    """

    omega: float
    multipliers: np.ndarray
    growth_rate: float
    neutral: int
    stable: bool
    residual_unbalance: float
    orbit_error: float
    weight_angles: np.ndarray
    state: np.ndarray | None = None

    @property
    def converged(self) -> bool:
        return self.orbit_error <= ORBIT_TOL


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
    try:
        y, Mmat, err = periodic_orbit(model, y0, T)
    except BudgetExceeded:
        raise
    except RuntimeError:       # the guess itself runs away: no orbit near it
        nan = np.full(y0.size, math.nan)
        return MainMotionStability(omega, nan, math.nan, 0, False, math.nan, math.inf,
                                   y0[model.n:model.n + model.nw].copy())
    mu, rate, neutral = floquet(Mmat, 2 * math.pi / omega)
    return MainMotionStability(omega, mu, rate, neutral, rate < 0, _residual(model, y), err,
                               y[model.n:model.n + model.nw].copy(), y.copy())


def main_motion_critical_speeds(rotor: LinearRotor, weights: Sequence[PlaneWeights], speeds,
                                y_guess=None, xtol: float = 1e-6):
    """Continuation of the main motion over ``speeds`` [rad/s] (increasing or
    decreasing; start where it exists, e.g. from a balanced simulation), its
    growth rate at each, and the speeds where the rate changes sign between two
    found orbits (bisection to ``xtol`` relative).  Where the orbit is not found, the
    step from the last found one is halved up to :data:`CONTINUATION_HALVINGS` times
    (the points found on the way are kept); still not found, the continuation stops
    there (module docstring), the speed where the orbit ends bisected to ``xtol`` (a
    fold: the growth rate goes to 0 there).  Returns (list of MainMotionStability: the
    found orbits in order, the first one not found last, within ``xtol`` of the last
    found; critical speeds)."""
    speeds = np.asarray(speeds, dtype=float)
    out = []
    y = y_guess
    for w in speeds:
        r = main_motion_stability(rotor, weights, w, y_guess=y)
        if not r.converged and out:
            r = _approach(rotor, weights, out, w, y)
        out.append(r)
        if not r.converged:
            break
        y = _state_guess(rotor, weights, r, r.omega)
    if len(out) >= 2 and not out[-1].converged:      # where the orbit ends, to xtol
        a = out[-2]
        while abs(out[-1].omega - a.omega) > xtol * abs(out[-1].omega):
            rm = main_motion_stability(rotor, weights, 0.5 * (a.omega + out[-1].omega),
                                       y_guess=_state_guess(rotor, weights, a, a.omega))
            if rm.converged:
                out.insert(len(out) - 1, rm)
                a = rm
            else:
                out[-1] = rm
    crit = []
    for a, b in zip(out[:-1], out[1:]):
        if a.converged and b.converged and a.stable != b.stable:
            lo, hi, ya = a.omega, b.omega, _state_guess(rotor, weights, a, a.omega)
            sa = a.stable
            while abs(hi - lo) > xtol * abs(hi):
                m = 0.5 * (lo + hi)
                rm = main_motion_stability(rotor, weights, m, y_guess=ya)
                if not rm.converged:
                    break          # (the orbit lost inside the bracket: no edge to state)
                if rm.stable == sa:
                    lo, ya = m, _state_guess(rotor, weights, rm, m)
                else:
                    hi = m
            else:
                crit.append(0.5 * (lo + hi))
    return out, np.array(crit)


def _approach(rotor, weights, out: list, w: float, y):
    """The orbit at ``w`` [rad/s], not found from the last found one (``out[-1]``, guess
    ``y``), approached in halved steps (geometric midpoints: the grids are geometric),
    :data:`CONTINUATION_HALVINGS` halvings in all; the orbits found on the way are appended
    to ``out``.  Returns the result at ``w``, or (not converged) the one nearest the last
    found orbit where none was found."""
    target, r = w, None
    for _ in range(CONTINUATION_HALVINGS):
        mid = math.sqrt(out[-1].omega * target)
        rm = main_motion_stability(rotor, weights, mid, y_guess=y)
        if not rm.converged:
            target, r = mid, rm            # closer to the last found orbit
            continue
        out.append(rm)
        y = _state_guess(rotor, weights, rm, mid)
        r = main_motion_stability(rotor, weights, w, y_guess=y)
        if r.converged:
            return r
        target = w
    return r


def _state_guess(rotor, weights, r: MainMotionStability, omega):
    """A guess at another speed: the orbit of ``r`` when it was found (the scaled state
    does not depend on the speed: its time scale is the rotor's lowest natural frequency),
    else the weights' angles of ``r`` with the rotor at rest."""
    if r.converged and r.state is not None:
        return r.state.copy()
    model = _model(rotor, weights, omega)
    y = np.zeros(2 * (model.n + model.nw) + model.n_adhesion)
    y[model.n:model.n + model.nw] = r.weight_angles
    return y
