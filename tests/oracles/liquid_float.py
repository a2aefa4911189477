"""The paper's own equations of the liquid float balancer, model M1 of paper 001: test oracle.

The model, its parameters and speed laws are described in
:mod:`stand.model.balancers.liquid_float`; the package runs it on the one model (the
generic composition, planar rotor x liquid float body).  Here, as the independent check:

* right-hand sides: the corrected fixed-frame (4)
  ``m Z'' + chi Z' + c Z = m1 e (beta'^2 - i beta'') e^{i beta}`` and the rotating-frame
  (9) as printed, with their Jacobians for the implicit solvers;
* :func:`simulate`: :func:`scipy.integrate.solve_ivp` (any of its methods) or a fixed-step
  classical Runge-Kutta 4 (``method="RK4"``, the paper's class of method, l. 77) that shows
  the numerical damping of the free whirl (digest 1.6 / 5.2 item 4).  A speed step is
  crossed with the velocity jump that keeps the system COM velocity
  ``W' = Z' + i psi e omega e^{i beta}`` continuous.  Outputs are those of (11):
  ``delta = |Z|`` [m] and ``d = |z/(e psi) + 1|`` [-], in both frames;
* :func:`accuracy_against_closed_form`: an integrator's error against the closed-form
  run-up (:mod:`stand.model.balancers.runup_closed_form`, digest 5.2 item 1, oracle O3).
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Callable

import numpy as np
from scipy.integrate import solve_ivp

from stand.model.balancers._params import PAPER
from stand.model.balancers.liquid_float_motion import (LinearSpeed, _check_frame, _speed_for,
                                                       initial_state)
from stand.model.balancers.liquid_float_params import LiquidFloatParams
from stand.model.balancers.runup_closed_form import runup_closed_form, runup_closed_form_state

__all__ = [
    "rhs_fixed", "rhs_rotating", "jac_fixed", "jac_rotating", "SCIPY_METHODS", "LiquidFloatRun",
    "outputs_from_fixed", "outputs_from_rotating", "simulate", "accuracy_against_closed_form",
    "AccuracyResult",
]


# ---------------------------------------------------------------------------
# right-hand sides
# ---------------------------------------------------------------------------

def _speed_law(sp):
    """``(beta, omega, alpha)`` of the speed law ``sp``; the linear law (6) written out
    here on floats (its ``omega_0 t + epsilon t^2``, ``omega_0 + 2 epsilon t``,
    ``2 epsilon``), any other law its own methods."""
    if not isinstance(sp, LinearSpeed):
        return sp.beta, sp.omega, sp.alpha
    w0, eps = float(sp.omega_0), float(sp.epsilon)
    return (lambda t: w0 * t + eps * t * t, lambda t: w0 + 2.0 * eps * t,
            lambda t: 2.0 * eps + 0.0 * t)


def rhs_fixed(params: LiquidFloatParams, speed=None) -> Callable:
    """Right-hand side ``f(t, y)`` of the corrected fixed-frame equations (4).

    ``y = [xi, eta, xi', eta']`` [m, m, m/s, m/s]; ``y`` may also be ``(4, k)``
    (``vectorized=True`` in solve_ivp).  Digest correction of the printed (4):
    the forcing is ``m1 e (beta'^2 cos beta + beta'' sin beta)`` and
    ``m1 e (beta'^2 sin beta - beta'' cos beta)`` (re-derived from (2)-(3)).
    """
    sp = _speed_for(params, speed)
    O2, h2, q = params.Omega ** 2, 2.0 * params.h, params.q
    beta, omega, alpha = _speed_law(sp)

    def f(t, y):
        if y.ndim == 1:       # plain floats: ~3x cheaper than numpy scalars for 4 states
            xi, eta, vxi, veta = y.tolist()
            t = float(t)
            b, w, a = float(beta(t)), float(omega(t)), float(alpha(t))
            cb, sb = math.cos(b), math.sin(b)
            w2 = w * w
            return np.array([vxi, veta,
                             -h2 * vxi - O2 * xi + q * (w2 * cb + a * sb),
                             -h2 * veta - O2 * eta + q * (w2 * sb - a * cb)])
        xi, eta, vxi, veta = y[0], y[1], y[2], y[3]
        b, w, a = beta(t), omega(t), alpha(t)
        cb, sb = np.cos(b), np.sin(b)
        w2 = w * w
        return np.array([vxi, veta,
                         -h2 * vxi - O2 * xi + q * (w2 * cb + a * sb),
                         -h2 * veta - O2 * eta + q * (w2 * sb - a * cb)])
    return f


def rhs_rotating(params: LiquidFloatParams, speed=None) -> Callable:
    """Right-hand side ``f(t, y)`` of the rotating-frame equations (9) (as printed).

    ``y = [x, y, x', y']`` [m, m, m/s, m/s] in the frame ``O2xy`` turning with
    the rotor (x along O1P); ``y`` may be ``(4, k)``.  Divided by ``m``:
    ``x'' = 2 w y' + a y + w^2 x - Omega^2 x - 2h (x' - w y) + q w^2`` and
    ``y'' = -2 w x' - a x + w^2 y - Omega^2 y - 2h (y' + w x) - q a``.
    """
    sp = _speed_for(params, speed)
    O2, h2, q = params.Omega ** 2, 2.0 * params.h, params.q
    _, omega, alpha = _speed_law(sp)

    def f(t, y):
        if y.ndim == 1:       # plain floats: ~3x cheaper than numpy scalars for 4 states
            x, yy, vx, vy = y.tolist()
            t = float(t)
            w, a = float(omega(t)), float(alpha(t))
        else:
            x, yy, vx, vy = y[0], y[1], y[2], y[3]
            w, a = omega(t), alpha(t)
        w2 = w * w
        return np.array([vx, vy,
                         2.0 * w * vy + a * yy + (w2 - O2) * x - h2 * (vx - w * yy) + q * w2,
                         -2.0 * w * vx - a * x + (w2 - O2) * yy - h2 * (vy + w * x) - q * a])
    return f


def jac_fixed(params: LiquidFloatParams, speed=None) -> Callable:
    """Jacobian ``J(t, y)`` of :func:`rhs_fixed` (constant) for Radau/BDF/LSODA."""
    O2, h2 = params.Omega ** 2, 2.0 * params.h
    J = np.array([[0, 0, 1, 0], [0, 0, 0, 1], [-O2, 0, -h2, 0], [0, -O2, 0, -h2]], float)
    return lambda t, y: J


def jac_rotating(params: LiquidFloatParams, speed=None) -> Callable:
    """Jacobian ``J(t, y)`` of :func:`rhs_rotating` for Radau/BDF/LSODA."""
    sp = _speed_for(params, speed)
    O2, h2 = params.Omega ** 2, 2.0 * params.h

    def J(t, y):
        w, a = float(sp.omega(t)), float(sp.alpha(t))
        k = w * w - O2
        return np.array([[0, 0, 1, 0], [0, 0, 0, 1],
                         [k, a + h2 * w, -h2, 2 * w],
                         [-a - h2 * w, k, -2 * w, -h2]], float)
    return J


SCIPY_METHODS = ("RK45", "RK23", "DOP853", "Radau", "BDF", "LSODA")


# fixed-step RK4
# ---------------------------------------------------------------------------

def rk4_fixed_step(fun: Callable, t0: float, y0, dt: float, n_steps: int,
                   record_every: int = 1):
    """Classical 4th-order Runge-Kutta with a fixed step on a Python right-hand side
    (paper 001's method class, l. 77, without its step control).

    Parameters
    ----------
    fun : callable
        ``fun(t, y) -> dy/dt`` on a 1-D numpy array.
    t0 : float
        Start time [s].
    y0 : array_like
        Initial state.
    dt : float
        Step [s], > 0.
    n_steps : int
        Number of steps.
    record_every : int
        Keep every ``record_every``-th state (the first and the last are
        always kept).

    Returns
    -------
    t : ndarray, y : ndarray (len(y0), k), nfev : int
    """
    dt = float(dt)
    if not (np.isfinite(dt) and dt > 0):
        raise ValueError(f"dt = {dt!r}: must be > 0 (s)")
    n_steps = int(n_steps)
    if n_steps < 0:
        raise ValueError(f"n_steps = {n_steps!r}: must be >= 0")
    if record_every < 1:
        raise ValueError(f"record_every = {record_every!r}: must be >= 1")
    y = np.array(y0, dtype=float)
    ts, ys = [t0], [y.copy()]
    half = 0.5 * dt
    for k in range(1, n_steps + 1):
        t = t0 + (k - 1) * dt
        k1 = fun(t, y)
        k2 = fun(t + half, y + half * k1)
        k3 = fun(t + half, y + half * k2)
        k4 = fun(t + dt, y + dt * k3)
        y = y + (dt / 6.0) * (k1 + 2.0 * (k2 + k3) + k4)
        if k % record_every == 0 or k == n_steps:
            ts.append(t0 + k * dt)
            ys.append(y.copy())
    return np.array(ts), np.array(ys).T, 4 * n_steps


def _rk4_linear_m1(params: LiquidFloatParams, frame: str, omega_0: float, epsilon: float,
                   t0: float, y0, dt: float, n_steps: int, record_every: int):
    """RK4 fast path for M1 with the linear speed law: the same arithmetic as
    :func:`rk4_fixed_step` on :func:`rhs_rotating`/:func:`rhs_fixed` but on
    Python floats (about 4x faster than 4-element numpy arrays)."""
    O2, h2, q = params.Omega ** 2, 2.0 * params.h, params.q
    a = 2.0 * epsilon
    cos, sin = math.cos, math.sin
    if frame == "rotating":
        def f(t, x, y, vx, vy):
            w = omega_0 + a * t
            w2 = w * w
            return (vx, vy,
                    2.0 * w * vy + a * y + (w2 - O2) * x - h2 * (vx - w * y) + q * w2,
                    -2.0 * w * vx - a * x + (w2 - O2) * y - h2 * (vy + w * x) - q * a)
    else:
        def f(t, x, y, vx, vy):
            w = omega_0 + a * t
            b = (omega_0 + epsilon * t) * t
            cb, sb = cos(b), sin(b)
            w2 = w * w
            return (vx, vy, -h2 * vx - O2 * x + q * (w2 * cb + a * sb),
                    -h2 * vy - O2 * y + q * (w2 * sb - a * cb))
    x, y, vx, vy = (float(v) for v in y0)
    ts, ys = [t0], [(x, y, vx, vy)]
    half, sixth = 0.5 * dt, dt / 6.0
    for k in range(1, n_steps + 1):
        t = t0 + (k - 1) * dt
        a1, b1, c1, d1 = f(t, x, y, vx, vy)
        a2, b2, c2, d2 = f(t + half, x + half * a1, y + half * b1, vx + half * c1, vy + half * d1)
        a3, b3, c3, d3 = f(t + half, x + half * a2, y + half * b2, vx + half * c2, vy + half * d2)
        a4, b4, c4, d4 = f(t + dt, x + dt * a3, y + dt * b3, vx + dt * c3, vy + dt * d3)
        x += sixth * (a1 + 2.0 * (a2 + a3) + a4)
        y += sixth * (b1 + 2.0 * (b2 + b3) + b4)
        vx += sixth * (c1 + 2.0 * (c2 + c3) + c4)
        vy += sixth * (d1 + 2.0 * (d2 + d3) + d4)
        if k % record_every == 0 or k == n_steps:
            ts.append(t0 + k * dt)
            ys.append((x, y, vx, vy))
    return np.array(ts), np.array(ys).T, 4 * n_steps


# ---------------------------------------------------------------------------
# simulation driver and outputs
# ---------------------------------------------------------------------------

@dataclass
class LiquidFloatRun:
    """Result of :func:`simulate`; all arrays have the length of ``t``.

    Attributes
    ----------
    t : time [s];  beta : rotation angle [rad];  omega : speed [rad/s]
    z : speed ratio ``omega/Omega_0`` [-] (l. 79)
    x, y, vx, vy : rotating-frame position [m] and velocity [m/s] of O1
    xi, eta, vxi, veta : fixed-frame position [m] and velocity [m/s] of O1
    delta : shaft deflection ``|Z|`` [m] (11);  d : system unbalance [-] (11)
    nfev : right-hand-side evaluations;  wall_time_s : integration time [s]
    """

    params: LiquidFloatParams
    frame: str
    method: str
    t: np.ndarray
    beta: np.ndarray
    omega: np.ndarray
    z: np.ndarray
    x: np.ndarray
    y: np.ndarray
    vx: np.ndarray
    vy: np.ndarray
    xi: np.ndarray
    eta: np.ndarray
    vxi: np.ndarray
    veta: np.ndarray
    delta: np.ndarray
    d: np.ndarray
    nfev: int
    wall_time_s: float

    @property
    def Z(self) -> np.ndarray:
        """Complex fixed-frame deflection ``xi + i eta`` [m]."""
        return self.xi + 1j * self.eta

    @property
    def Zdot(self) -> np.ndarray:
        """Complex fixed-frame velocity [m/s]."""
        return self.vxi + 1j * self.veta

    @property
    def W(self) -> np.ndarray:
        """COM variable ``Z + psi e e^{i beta}`` [m] (digest 1.2)."""
        return self.Z + self.params.q * np.exp(1j * self.beta)

    @property
    def Wdot(self) -> np.ndarray:
        """``W'`` [m/s]."""
        return self.Zdot + 1j * self.params.q * self.omega * np.exp(1j * self.beta)


def _outputs(params, speed, t, Z, Zd, frame, method, nfev, wall):
    beta = np.asarray(speed.beta(t), float) + 0.0 * t
    omega = np.asarray(speed.omega(t), float) + 0.0 * t
    rot = np.exp(-1j * beta)
    zr = Z * rot
    zrd = (Zd - 1j * omega * Z) * rot
    return LiquidFloatRun(
        params=params, frame=frame, method=method, t=t, beta=beta, omega=omega,
        z=omega / params.Omega_0, x=zr.real, y=zr.imag, vx=zrd.real, vy=zrd.imag,
        xi=Z.real, eta=Z.imag, vxi=Zd.real, veta=Zd.imag, delta=np.abs(Z),
        d=np.abs(zr / params.q + 1.0), nfev=int(nfev), wall_time_s=float(wall))


def outputs_from_rotating(params, t, state, speed=None, *, method="", nfev=0, wall=0.0):
    """All outputs from a rotating-frame state history ``state`` (4, k) at ``t`` [s]."""
    sp = _speed_for(params, speed)
    t = np.asarray(t, float)
    beta, omega = np.asarray(sp.beta(t)) + 0.0 * t, np.asarray(sp.omega(t)) + 0.0 * t
    zr, zrd = state[0] + 1j * state[1], state[2] + 1j * state[3]
    e = np.exp(1j * beta)
    return _outputs(params, sp, t, zr * e, (zrd + 1j * omega * zr) * e, "rotating",
                    method, nfev, wall)


def outputs_from_fixed(params, t, state, speed=None, *, method="", nfev=0, wall=0.0):
    """All outputs from a fixed-frame state history ``state`` (4, k) at ``t`` [s]."""
    sp = _speed_for(params, speed)
    t = np.asarray(t, float)
    return _outputs(params, sp, t, state[0] + 1j * state[1], state[2] + 1j * state[3],
                    "fixed", method, nfev, wall)


def _apply_speed_jump(params, frame, speed, t, y, d_omega):
    """State just after an instantaneous speed change ``d_omega`` [rad/s] at ``t``:
    ``W'`` is continuous, so ``Z'`` jumps by ``-i psi e d_omega e^{i beta}``
    (rotating frame: ``z'`` jumps by ``-i d_omega (z + psi e)``)."""
    y = np.array(y, float)
    if frame == "fixed":
        b = float(speed.beta(t))
        dv = -1j * params.q * d_omega * complex(math.cos(b), math.sin(b))
    else:
        dv = -1j * d_omega * (complex(y[0], y[1]) + params.q)
    y[2] += dv.real
    y[3] += dv.imag
    return y


def simulate(params: LiquidFloatParams, t_end: float | None = None, *, t_eval=None,
             frame: str = "rotating", method: str = "DOP853", rtol: float = 1e-10,
             atol=None, step: float | None = None, speed=None, t0: float = 0.0,
             y0=None, record_every: int = 1, max_step: float = np.inf) -> LiquidFloatRun:
    """Integrate model M1 in the fixed (corrected (4)) or rotating ((9)) frame.

    Parameters
    ----------
    params : LiquidFloatParams
    t_end : float, optional
        Final time [s]; default ``t_eval[-1]``.
    t_eval : array_like, optional
        Output times [s] for the scipy methods (default: the solver's steps).
        Ignored by ``"RK4"``, which returns every ``record_every``-th step.
    frame : {"rotating", "fixed"}
    method : str
        A :func:`scipy.integrate.solve_ivp` method (``"RK45"``, ``"DOP853"``,
        ``"Radau"``, ``"LSODA"``, ...) or ``"RK4"`` (fixed step ``step``).
    rtol : float
        Relative tolerance (scipy methods).
    atol : float or array_like, optional
        Absolute tolerance; default ``rtol * e * [1, 1, Omega_0, Omega_0]``
        (the state is in m and m/s).
    step : float, optional
        RK4 step [s] (required for ``"RK4"``).
    speed : LinearSpeed, StepSpeed or GeneralSpeed, optional
        Default: the linear law (6) of ``params``.
    t0 : float
        Start time [s] (the speed law is evaluated at absolute times).
    y0 : array_like, optional
        Initial state in ``frame``; default (7)/(10) (stationary orbit at
        ``speed.omega(t0)``).
    record_every : int
        RK4 output decimation.
    max_step : float
        Passed to solve_ivp [s].

    Returns
    -------
    LiquidFloatRun
        Outputs in both frames plus ``nfev`` and the wall time.
    """
    frame = _check_frame(frame)
    sp = _speed_for(params, speed)
    t0 = PAPER.finite("t0", t0, "s")
    if t_eval is not None:
        t_eval = np.asarray(t_eval, float)
        if t_eval.ndim != 1 or t_eval.size < 1:
            raise ValueError("t_eval must be a non-empty 1-D array of times [s]")
        if t_end is None:
            t_end = float(t_eval[-1])
    if t_end is None:
        raise ValueError("t_end [s] or t_eval must be given")
    t_end = PAPER.finite("t_end", t_end, "s")
    if t_end <= t0:
        raise ValueError(f"t_end = {t_end!r} [s]: must be > t0 = {t0!r} s")
    if y0 is None:
        # stationary orbit at the speed just before t0 (a step at t0 is applied after)
        w_pre = float(sp.omega(t0)) - sum(dw for tj, dw in sp.jumps if tj == t0)
        y0 = initial_state(params, frame, omega=w_pre)
    y0 = np.asarray(y0, float)
    if y0.shape != (4,):
        raise ValueError(f"y0 has shape {y0.shape}: must be (4,) [m, m, m/s, m/s]")
    if atol is None:
        atol = rtol * params.e * np.array([1.0, 1.0, params.Omega_0, params.Omega_0])
    fun = rhs_rotating(params, sp) if frame == "rotating" else rhs_fixed(params, sp)

    # split at speed steps; the jump at a segment start is applied before it
    jumps = {tj: dw for tj, dw in sp.jumps if t0 <= tj < t_end}
    edges = sorted(set([t0, t_end] + list(jumps)))
    ts, ys, nfev = [], [], 0
    y = y0.copy()
    tic = time.perf_counter()
    for i, (a, b) in enumerate(zip(edges[:-1], edges[1:])):
        if a in jumps:
            y = _apply_speed_jump(params, frame, sp, a, y, jumps[a])
        if method == "RK4":
            if step is None:
                raise ValueError("step [s] is required for method = 'RK4'")
            PAPER.positive("step", step, "s")
            n = max(1, int(round((b - a) / step)))
            dt = (b - a) / n
            if isinstance(sp, LinearSpeed):
                tt, yy, nf = _rk4_linear_m1(params, frame, sp.omega_0, sp.epsilon, a, y, dt, n,
                                            record_every)
            else:
                tt, yy, nf = rk4_fixed_step(fun, a, y, dt, n, record_every)
            keep = np.ones(tt.size, bool)
        elif method in SCIPY_METHODS:
            te, keep = None, None
            if t_eval is not None:
                last = i == len(edges) - 2
                sel = t_eval[(t_eval >= a) & ((t_eval <= b) if last else (t_eval < b))]
                te = np.unique(np.concatenate([[a], sel, [b]]))
                keep = np.isin(te, sel)
            extra = {}
            if method in ("Radau", "BDF", "LSODA"):
                extra["jac"] = (jac_rotating if frame == "rotating" else jac_fixed)(params, sp)
            sol = solve_ivp(fun, (a, b), y, method=method, t_eval=te, rtol=rtol, atol=atol,
                            max_step=max_step, **extra)
            if sol.status != 0:
                raise RuntimeError(f"solve_ivp({method}) failed: {sol.message}")
            tt, yy, nf = sol.t, sol.y, sol.nfev
            if keep is None:
                keep = np.ones(tt.size, bool)
        else:
            raise ValueError(f"method = {method!r}: must be 'RK4' or one of {SCIPY_METHODS}")
        nfev += nf
        y = yy[:, -1].copy()
        if i < len(edges) - 2:
            keep[-1] = False          # the next segment reports this time (after the jump)
        ts.append(tt[keep])
        ys.append(yy[:, keep])
    wall = time.perf_counter() - tic
    t = np.concatenate(ts)
    Y = np.concatenate(ys, axis=1)
    out = outputs_from_rotating if frame == "rotating" else outputs_from_fixed
    return out(params, t, Y, sp, method=method, nfev=nfev, wall=wall)


# ---------------------------------------------------------------------------
# accuracy against the closed form
# ---------------------------------------------------------------------------

@dataclass
class AccuracyResult:
    """Error of a numerical run against :func:`runup_closed_form`.

    Attributes
    ----------
    method, frame : str
    rtol : float or None;  step : float or None [s]
    t_end : float [s];  z_end : float [-]
    max_error_over_e : max over the evaluation grid of ``|Z_num - Z_exact|/e`` [-]
    peak_rel_error : relative error of ``max delta`` on the grid [-]
    end_error_over_e : ``|Z_num - Z_exact|/e`` at ``t_end`` [-]
    wall_time_s : integration time [s] (excludes the closed form)
    nfev : right-hand-side evaluations
    """

    method: str
    frame: str
    rtol: float | None
    step: float | None
    t_end: float
    z_end: float
    max_error_over_e: float
    peak_rel_error: float
    end_error_over_e: float
    wall_time_s: float
    nfev: int


def accuracy_against_closed_form(params: LiquidFloatParams, method: str = "DOP853", *,
                                 rtol: float | None = 1e-10, step: float | None = None,
                                 t_end: float | None = None, z_end: float | None = None,
                                 frame: str = "rotating", n_eval: int = 20001,
                                 t_start: float = 0.0) -> AccuracyResult:
    """Integrate M1 with ``method`` and compare with the exact run-up.

    Parameters
    ----------
    params : LiquidFloatParams
    method : str
        ``"RK45"``, ``"DOP853"``, ``"Radau"``, ``"LSODA"`` (any solve_ivp
        method) or ``"RK4"`` (fixed step ``step`` [s]).
    rtol : float
        Relative tolerance of the scipy methods (atol = rtol e [1, 1, Omega_0, Omega_0]).
    step : float
        RK4 step [s].
    t_end, z_end : float
        End of the run: a time [s] or a speed ratio ``omega/Omega_0`` [-].
        E.g. the long benchmark 40 -> 5000 rad/s at 20 rad/s^2 is
        ``z_end = 5`` (t_end = 248 s, about 1e5 revolutions).
    frame : {"rotating", "fixed"}
    n_eval : int
        Number of comparison times (uniform; for RK4 the recorded steps are
        decimated to about this many).
    t_start : float
        Start time [s]; the initial state is then the closed-form state at
        ``t_start`` (short windows around the resonance).

    Returns
    -------
    AccuracyResult

    Notes
    -----
    The long benchmark (paper parameters, psi = 1, n = 0, rotating frame,
    z 0.04 -> 5, t_end = 248 s, about 1e5 revolutions), measured on the
    development machine (2 cores, one thread, numpy RHS), n_eval = 200001:

    ========  =========  ==========  ============  ===========  ========
    method    rtol/step  nfev        max err / e   peak rel     wall [s]
    ========  =========  ==========  ============  ===========  ========
    RK4       2.5e-4 s   3.97e6      407           2.0e-8       4
    RK4       1e-4 s     9.92e6      436           4.4e-9       10
    DOP853    1e-8       9.28e6      0.084         1.1e-8       215
    ========  =========  ==========  ============  ===========  ========

    RK4 gets the peak right but its numerical damping (plus phase error) removes the whole
    residual free whirl (about 280 e) by z = 5: the rotating-frame free
    mode runs at ``omega - Omega`` (up to 4000 rad/s), and RK4 damps
    ``(theta^6)/144`` per step, ``theta = |omega - Omega| dt``.  DOP853 at
    rtol 1e-10 costs about 2-3x the 1e-8 run (several minutes); the closed
    form itself takes 0.3-0.4 s for the 200001 points.  Use short runs
    (``t_start`` near the resonance, or a faster sweep) in tests.
    """
    if (t_end is None) == (z_end is None):
        raise ValueError("give exactly one of t_end [s] and z_end [-]")
    if t_end is None:
        t_end = params.time_at_z(z_end)
    t_end = PAPER.positive("t_end", t_end, "s")
    t_start = PAPER.finite("t_start", t_start, "s")
    if not 0.0 <= t_start < t_end:
        raise ValueError(f"t_start = {t_start!r} [s]: must be in [0, t_end = {t_end} s)")
    y0 = None
    if t_start > 0.0:
        Z0, Zd0 = runup_closed_form_state(params, np.array([t_start]))
        y0 = _state_in_frame(params, frame, t_start, Z0[0], Zd0[0])
    if method == "RK4":
        if step is None:
            raise ValueError("step [s] is required for method = 'RK4'")
        step = PAPER.positive("step", step, "s")
        n_steps = max(1, int(round((t_end - t_start) / step)))
        every = max(1, n_steps // max(1, n_eval - 1))
        run = simulate(params, t_end, method="RK4", step=step, frame=frame, t0=t_start,
                       y0=y0, record_every=every)
        rt = None
    elif method in SCIPY_METHODS:
        rt = PAPER.positive("rtol", rtol, "-")
        t_eval = np.linspace(t_start, t_end, n_eval)
        run = simulate(params, t_end, t_eval=t_eval, method=method, rtol=rt, frame=frame,
                       t0=t_start, y0=y0)
    else:
        raise ValueError(f"method = {method!r}: must be 'RK4' or one of {SCIPY_METHODS}")
    Zx = runup_closed_form(params, run.t)
    err = np.abs(run.Z - Zx) / params.e
    with np.errstate(invalid="ignore"):
        pk_num = np.nanmax(run.delta) if np.all(np.isfinite(run.delta)) else np.inf
    pk_ex = np.max(np.abs(Zx))
    return AccuracyResult(method=method, frame=frame, rtol=rt, step=step, t_end=float(t_end),
                          z_end=float((params.omega_0 + 2 * params.epsilon * t_end) / params.Omega_0),
                          max_error_over_e=float(np.max(err)) if np.all(np.isfinite(err)) else np.inf,
                          peak_rel_error=float(abs(pk_num - pk_ex) / pk_ex),
                          end_error_over_e=float(err[-1]), wall_time_s=run.wall_time_s,
                          nfev=run.nfev)


def _state_in_frame(params, frame, t, Z, Zd):
    """4-vector state in ``frame`` from the complex fixed-frame Z [m], Z' [m/s] at ``t`` [s]."""
    if frame == "fixed":
        return np.array([Z.real, Z.imag, Zd.real, Zd.imag])
    if frame != "rotating":
        raise ValueError(f"frame = {frame!r}: must be 'rotating' or 'fixed'")
    b = params.omega_0 * t + params.epsilon * t * t
    w = params.omega_0 + 2 * params.epsilon * t
    r = complex(math.cos(b), -math.sin(b))
    zr, zrd = Z * r, (Zd - 1j * w * Z) * r
    return np.array([zr.real, zr.imag, zrd.real, zrd.imag])
