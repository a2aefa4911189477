"""The parts every run shares: sample grids, the integrator call and the generic kernel's
samples as a :class:`stand.integrate.result.Run`.

Used by :mod:`stand.integrate.simulate` (the scenes' entry point) and by the book weight
models' runs (:mod:`stand.integrate.book_run`), which build their generic composition
and integrate it here -- so neither reaches into the other.  Times handed to the driver are
dimensionless (``tau = omega_1 t``), sample times in seconds.
"""
from __future__ import annotations

import math
import time as _time

import numpy as np

from stand.integrate.driver import CHUNK_STEPS, Checkpoint, fingerprint, run_dop853, run_scipy, warm_up
from stand.integrate.result import Run, weight_names
from stand.errors import SceneError

__all__ = ["sample_times", "merge_times", "integrate_model", "generic_run"]


def sample_times(duration: float, sample_rate: float) -> np.ndarray:
    """Sample times [s]: k / sample_rate for k = 0, 1, ...; a last time within
    1e-9 of a sample interval of ``duration`` is set to ``duration`` exactly, so
    that rounding never drops the final sample."""
    n = int(math.floor(duration * sample_rate + 1e-9)) + 1
    t = np.arange(n) / sample_rate
    if abs(t[-1] - duration) <= 1e-9 / sample_rate:
        t[-1] = duration
    return np.minimum(t, duration)


def merge_times(ts_rec, extra_times, duration, w1):
    """Merge the recording grid with extra sample times (both dimensionless)."""
    if extra_times is None:
        return ts_rec, None, None
    ex = np.asarray(extra_times, dtype=float).ravel()
    if ex.size == 0:
        return ts_rec, np.arange(ts_rec.size), np.zeros(0, int)
    if not np.all(np.isfinite(ex)) or ex[0] < 0 or ex[-1] > duration or np.any(np.diff(ex) < 0):
        raise ValueError(f"extra_times: must be finite, non-decreasing and within [0, {duration:g}] s")
    ex = ex * w1
    ts = np.union1d(ts_rec, ex)
    return ts, np.searchsorted(ts, ts_rec), np.searchsorted(ts, ex)


def integrate_model(scene, model, y0, tau_end, ts, out, stats, method, progress, checkpoint,
               checkpoint_steps) -> int:
    """Run the driver (compiled DOP853, with checkpoints, or a scipy method); returns the
    number of samples computed and sets ``stats.wall_time``."""
    warm_up(model)  # compile / load the kernels outside the timed region
    t0 = _time.perf_counter()
    if method == "DOP853":
        ck = None
        if checkpoint is not None:
            ck = Checkpoint(checkpoint, fingerprint(scene, method, stats.rtol, stats.atol, ts,
                                                    model.size))
        k = run_dop853(model, y0, tau_end, stats.rtol, stats.atol, ts, out, stats,
                       scene.run.max_steps, progress, ck,
                       int(checkpoint_steps) if ck is not None else CHUNK_STEPS)
        if ck is not None and stats.success:
            ck.remove()
    elif checkpoint is not None:
        raise SceneError(f"checkpoint: only with the compiled DOP853 method (this run uses {method})")
    else:
        k = run_scipy(model, y0, tau_end, stats.rtol, stats.atol, ts, out, stats, method,
                      scene.run.max_steps)
    stats.wall_time = _time.perf_counter() - t0
    return k


def generic_run(scene, model, out, tau, stats) -> Run:
    """The generic kernel's samples ``out`` at the dimensionless times ``tau`` as a
    :class:`Run` (SI channels, weights' and bodies' coordinates, residual unbalance truth)."""
    from stand.integrate.coupled import samples_si

    t, q, qd, phi, speed, alpha, planes, residual = samples_si(model, out, tau)
    n, nw, w = model.n, model.nw, model.omega_1
    dalpha = out[:, 2 * n + nw:2 * (n + nw)] * w
    names, wplanes = weight_names(scene.weights)
    weights = {nm: {"angle": phi + alpha[:, j], "speed": speed + dalpha[:, j]}
               for j, nm in enumerate(names)}
    notes = ()
    if model.bodies:
        from stand.model.rotors.bodies import body_channels, body_names, liquid_notes

        bnames, bplanes = body_names(model.bodies)
        bcoords, _ = body_channels(model.bt, model.bodies, out, w, phi, planes)
        weights.update(zip(bnames, bcoords))
        names, wplanes = names + bnames, wplanes + bplanes
        notes = liquid_notes(model.bodies, planes)
    coords = {}
    for i, c in enumerate(model.rotor.coords):
        name, _, unit = c.partition(" [")
        coords[f"structure/{name}"] = (q[:, i], unit.rstrip("]") or "1")
    truth = {f"residual/{p}": (U, "kg*m") for p, U in residual.items()}
    return Run(t=t, planes=planes, main_plane=scene.main_plane, rotor_angle=phi,
               rotor_speed=speed, weights=weights, weight_planes=dict(zip(names, wplanes)),
               stats=stats, scene=scene, coordinates=coords, truth=truth, state=out, notes=notes)
