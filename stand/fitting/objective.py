"""The fit's objective: residuals of the record against the simulation, and their Jacobian
by finite differences of the compiled simulator on all cores.

A parameter vector ``theta`` holds the free scene values in the scene file's units, then
(when the record starts away from rest) the shaft's initial state.  :class:`Objective` turns
it into the augmented residual of :class:`stand.fitting.linear.LinearPart` over the record's
first ``n`` samples (the continuation over the record fits growing stretches), caches the
model signal of the last few vectors, and computes the Jacobian's columns as simulations
mapped over a :class:`stand.io.executor.Executor` (process pool, or a Dask cluster).
"""
from __future__ import annotations

import math
from dataclasses import replace
from typing import Optional

import numpy as np

from stand.fitting.model_run import Setup, model_channel
from stand.fitting.paths import FitError

__all__ = ["Objective", "robust_sigma"]


def robust_sigma(r, order: int = 1) -> float:
    """Noise std per component of a complex (or real) sequence from its ``order``-th
    differences (MAD, Gaussian-consistent): a smooth part (model error, slow drift) hardly
    enters the differences of a finely sampled record, white noise does fully."""
    r = np.asarray(r)
    parts = [r.real, r.imag] if np.iscomplexobj(r) else [r]
    norm = math.sqrt(math.comb(2 * order, order))
    vals = []
    for p in parts:
        d = np.diff(p, n=order)
        if d.size:
            vals.append(1.4826 * float(np.median(np.abs(d - np.median(d)))) / norm)
    s = float(np.mean(vals)) if vals else 0.0
    return s


def _column(item):
    """One finite-difference simulation (the executor's mapped function)."""
    setup, theta, end = item
    return model_channel(setup, theta, end)


def _columns(items):
    """Several simulations in one call of the executor (a chunk: the setups they share are
    pickled once, and a pool's per-call overhead is paid once)."""
    return [_column(it) for it in items]


class Objective:
    """Residuals and Jacobian of the fit (module docstring).

    Parameters
    ----------
    setup : Setup
    z : ndarray (N,) complex     the record at the fitted samples
    linear : callable(n) -> LinearPart
        The linear nuisance of the first ``n`` samples.
    steps : ndarray (P,)         finite-difference steps of the parameters [their units]
    executor : Executor or None  where the Jacobian's simulations run (None: here)
    """

    def __init__(self, setup: Setup, z, linear, steps, executor=None, on_eval=None,
                 record=None):
        self.setup = setup
        self.record = record
        self._mode_setups = None
        self._G_at = None      #: (theta, n) where the angle sensitivity G was last made
        self.z = np.asarray(z)
        self.linear = linear
        self.steps = np.asarray(steps, float)
        self.executor = executor
        self.on_eval = on_eval
        self._cache: dict = {}
        self.simulations = 0
        self.failed = 0

    def end_time(self, n: int) -> float:
        return float(self.setup.times[n - 1])

    def signal(self, theta, n: int) -> np.ndarray:
        """The model signal over the first ``n`` samples (cached)."""
        key = (np.asarray(theta, float).tobytes(), n)
        if key not in self._cache:
            if len(self._cache) > 8:
                self._cache.pop(next(iter(self._cache)))
            self.simulations += 1
            try:
                m = model_channel(self.setup, np.asarray(theta, float), self.end_time(n))[:n]
            except FitError:                  # values the scene refuses (e.g. a zero stiffness)
                m = np.full(n, np.nan + 0j)
            self._cache[key] = m
        return self._cache[key]

    def residual(self, theta, n: int):
        """``(r, Q, coef, m)``: the augmented residual over the first ``n`` samples."""
        m = self.signal(theta, n)
        if m.size < n or not np.all(np.isfinite(m)):
            self.failed += 1
            big = np.full(2 * n + self.linear(n).k, 1e6)   # a run that stopped: far from the data
            return big, None, None, m
        r, Q, coef, _ = self.linear(n).solve(self.z, m)
        if self.on_eval is not None:
            self.on_eval(theta, float(r @ r))
        return r, Q, coef, m

    def simulate_many(self, items) -> list:
        """Model signals of ``items`` = ``[(setup, theta, end time)]``, on the executor when there
        is one (one chunk per worker) and more than one item; in order."""
        self.simulations += len(items)
        if self.executor is not None and len(items) > 1:
            k = min(len(items), self.executor.workers)
            chunks = [items[i::k] for i in range(k)]          # as even as the items are
            done = self.executor.map(_columns, chunks)
            out = [None] * len(items)
            for i, part in enumerate(done):
                out[i::k] = part
            return out
        return [_column(it) for it in items]

    def columns(self, theta, n: int) -> np.ndarray:
        """d(model signal)/d(theta) (n, P) complex by forward differences."""
        theta = np.asarray(theta, float)
        base = self.signal(theta, n)
        items = []
        for j, h in enumerate(self.steps):
            tp = theta.copy()
            tp[j] += h
            items.append((self.setup, tp, self.end_time(n)))
        outs = self.simulate_many(items)
        J = np.empty((n, len(items)), complex)
        for j, (o, h) in enumerate(zip(outs, self.steps)):
            o = np.asarray(o)[:n]
            if o.size < n or not np.all(np.isfinite(o)):
                o = base                                  # a failed neighbour: no information
            J[:, j] = (o - base) / h
        return J

    def angle_sensitivity(self, theta, n: int, scales=None, moved: float = 1e-3) -> bool:
        """Set the linear part's ``G``: the model signal's change per unit of each whitened
        error mode of the measured rotor angle, by simulations driven by the angle perturbed
        along the mode (a step of 1e-3 rad at its largest), over the first ``n`` samples.

        With ``scales`` (the parameters' scales), a ``G`` made over at least ``n`` samples at
        values within ``moved`` scales of ``theta`` is kept: the sensitivity changes with the
        values in proportion (1e-3 of it at most then), and the simulations are causal, so
        the first ``n`` rows of a longer run's ``G`` are the shorter run's.  Returns whether ``G``
        was made now (False: kept, or no angle modes)."""
        from stand.fitting.record import angle_programme

        lp, rec = self.linear(n), self.record
        if lp.modes is None or rec is None or rec.angle is None:
            lp.G = None
            return False
        theta = np.asarray(theta, float)
        at = self._G_at
        if (scales is not None and at is not None and lp.G is not None and at[1] >= n
                and np.all(np.abs(theta - at[0]) <= moved * np.asarray(scales, float))):
            return False
        W = lp.modes.W
        if self._mode_setups is None:
            a = rec.angle
            self._mode_setups = []
            for k in range(W.shape[1]):
                h = 1e-3 / max(float(np.max(np.abs(W[:, k]))), 1e-300)
                dW = np.gradient(W[:, k], rec.t)
                # the acceleration too: before the first pulse the drive is extrapolated with
                # it, and the weights' lag over that stretch follows
                drive, _ = angle_programme(rec.t, a.angle_rad + h * W[:, k],
                                           a.speed_rad_s + h * dW,
                                           a.acceleration_rad_s2 + h * np.gradient(dW, rec.t),
                                           rec.t_start)
                self._mode_setups.append((replace(self.setup, drive=replace(
                    drive, rest_until=self.setup.drive.rest_until)), h))
        base = self.signal(theta, n)
        outs = self.simulate_many([(s_, theta, self.end_time(n)) for s_, _ in self._mode_setups])
        G = np.zeros((rec.t.size, W.shape[1]), complex)
        for k, (o, (_, h)) in enumerate(zip(outs, self._mode_setups)):
            o = np.asarray(o)[:n]
            if o.size == n and np.all(np.isfinite(o)):
                G[:n, k] = (o - base) / h
        lp.G = G
        self._G_at = (theta.copy(), n)
        return True

    def jacobian(self, theta, n: int):
        """The augmented residual's Jacobian (2n + K, P), projected off the linear nuisance."""
        r, Q, coef, m = self.residual(theta, n)
        lp = self.linear(n)
        k = lp.k
        dm = self.columns(theta, n)
        J = np.zeros((2 * n + k, dm.shape[1]))
        J[:n] = -dm.real / lp.sigma
        J[n:2 * n] = -dm.imag / lp.sigma
        if Q is not None:
            J -= Q @ (Q.T @ J)
        return J


def executor_for(workers: Optional[int], scheduler, n_columns: int):
    """The executor of the Jacobian's simulations (None: run them here)."""
    from stand.io.executor import Executor
    import os

    if scheduler is None and (workers == 1 or (workers is None and (os.cpu_count() or 1) < 2)
                              or n_columns < 2):
        return None
    return Executor(workers=workers, scheduler=scheduler)

