"""Event timing and interpolation between the simulator's samples.

The simulator samples the motion at ``run.sample_rate``; the instruments need
values at other instants (the stroboscope's flashes, the keyphasor's pulses,
the probes' own sample clock).  Every sampled quantity of the stand comes with
its time derivative -- angles with speeds, shaft positions with velocities --
so the natural interpolant is the cubic Hermite one, which matches value and
derivative at both ends of each sample interval.

Accuracy
--------
On an interval of length ``h`` the cubic Hermite interpolant of a smooth
signal ``f`` errs by at most ``h**4 / 384 * max|f''''|``.  For a component
``A sin(2 pi t / P)`` sampled ``N`` times per period ``P`` this is
``A (2 pi / N)**4 / 384``: about ``2.5e-5 A`` at ``N = 20``, ``1.6e-6 A`` at
``N = 40``.  So with at least 20 samples per revolution a ripple of 1 rad is
interpolated to ~1e-5 rad, and a whirl of radius ``A`` to ~2.5e-5 ``A``.  The
rotor angle of a prescribed speed programme is piecewise quadratic in time:
its interpolant is exact (to rounding) except on the sample interval that
contains a kink of the programme, where the error is ``O(h**3 * jump of the
acceleration)``.

Crossing times (:func:`crossing_times`) are the roots of the interpolant on
each sample interval, found by a safeguarded Newton iteration (bisection when
a Newton step leaves the bracket) to the floating-point resolution of the
angle.  They are as accurate as the interpolant: ``|dt| <= |d angle| / speed``.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np

__all__ = ["MeasurementError", "hermite", "crossing_times", "level_crossings",
           "shaft_velocity", "TrajectorySample", "sample_trajectory", "wrap", "time_window"]

TWO_PI = 2.0 * np.pi


class MeasurementError(ValueError):
    """An instrument cannot produce its reading from the given motion
    (e.g. the pulse counter never receives its stop pulse)."""


# ---------------------------------------------------------------- Hermite
def _locate(t: np.ndarray, tq: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Interval index ``i`` (``t[i] <= tq <= t[i+1]``), its length and the
    local coordinate ``s`` in [0, 1] for each query time."""
    if t.ndim != 1 or t.size < 2:
        raise ValueError(f"need at least 2 samples to interpolate, got {t.size}")
    span = t[-1] - t[0]
    slack = 1e-12 * max(abs(t[0]), abs(t[-1]), span)
    if tq.size and (np.min(tq) < t[0] - slack or np.max(tq) > t[-1] + slack):
        raise ValueError(f"query times [{np.min(tq):.9g}, {np.max(tq):.9g}] s leave the sampled "
                         f"interval [{t[0]:.9g}, {t[-1]:.9g}] s (no extrapolation)")
    i = np.clip(np.searchsorted(t, tq, side="right") - 1, 0, t.size - 2)
    h = t[i + 1] - t[i]
    s = np.clip((tq - t[i]) / h, 0.0, 1.0)
    return i, h, s


def _basis(s: np.ndarray, h: np.ndarray, derivative: bool):
    s2 = s * s
    s3 = s2 * s
    if not derivative:
        return (2 * s3 - 3 * s2 + 1, (s3 - 2 * s2 + s) * h, -2 * s3 + 3 * s2, (s3 - s2) * h)
    return ((6 * s2 - 6 * s) / h, 3 * s2 - 4 * s + 1, (-6 * s2 + 6 * s) / h, 3 * s2 - 2 * s)


def hermite(t, y, dy, tq, derivative: bool = False) -> np.ndarray:
    """Cubic Hermite interpolation of a sampled signal with known derivative.

    Parameters
    ----------
    t : array_like, shape (N,)
        Strictly increasing sample times [s].
    y : array_like, shape (N,) or (N, m)
        Samples (any unit ``u``); several signals as columns.
    dy : array_like, same shape as ``y``
        Their time derivatives [u/s].
    tq : array_like, shape (M,) or scalar
        Query times [s] inside ``[t[0], t[-1]]`` (no extrapolation).
    derivative : bool
        Return the derivative of the interpolant [u/s] instead of its value.

    Returns
    -------
    ndarray, shape (M,) or (M, m)
        Interpolated values (or derivatives) at ``tq``.  Error bound: see the
        module docstring (about ``2.5e-5 A`` for a harmonic of amplitude ``A``
        sampled 20 times per period).

    Raises
    ------
    ValueError
        Fewer than two samples, mismatched shapes, or a query time outside
        the sampled interval.
    """
    t = np.asarray(t, float)
    y = np.asarray(y, float)
    dy = np.asarray(dy, float)
    if y.shape != dy.shape or y.shape[:1] != t.shape:
        raise ValueError(f"hermite: shapes of t {t.shape}, y {y.shape} and dy {dy.shape} disagree")
    scalar = np.ndim(tq) == 0
    tq = np.atleast_1d(np.asarray(tq, float))
    i, h, s = _locate(t, tq)
    b = _basis(s, h, derivative)
    if y.ndim == 2:
        b = [c[:, None] for c in b]
        h = h[:, None]
    out = b[0] * y[i] + b[1] * dy[i] + b[2] * y[i + 1] + b[3] * dy[i + 1]
    return out[0] if scalar else out


# ---------------------------------------------------------------- crossings
def _roots(t, y, dy, idx, level, max_iter: int = 60) -> np.ndarray:
    """Roots of (Hermite interpolant - level) on the intervals ``idx``.

    Each interval brackets a sign change; safeguarded Newton (bisection when
    the Newton step leaves the bracket), vectorised over the intervals.
    """
    h = t[idx + 1] - t[idx]
    a = y[idx] - level          # value at s = 0, relative to the level (no cancellation)
    b = y[idx + 1] - level      # value at s = 1
    da, db = dy[idx] * h, dy[idx + 1] * h   # derivatives with respect to s
    orient = np.where(b >= a, 1.0, -1.0)  # +1: increasing through the level
    lo = np.zeros_like(a)
    hi = np.ones_like(a)
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.where(b != a, -a / (b - a), 0.5)
    s = np.clip(s, 0.0, 1.0)
    for _ in range(max_iter):
        s2, s3 = s * s, s * s * s
        f = a * (2 * s3 - 3 * s2 + 1) + da * (s3 - 2 * s2 + s) + b * (-2 * s3 + 3 * s2) \
            + db * (s3 - s2)
        fp = a * (6 * s2 - 6 * s) + da * (3 * s2 - 4 * s + 1) + b * (-6 * s2 + 6 * s) \
            + db * (3 * s2 - 2 * s)
        below = orient * f < 0
        lo = np.where(below, s, lo)
        hi = np.where(below, hi, s)
        with np.errstate(divide="ignore", invalid="ignore"):
            sn = s - f / fp
        bad = ~np.isfinite(sn) | (sn <= lo) | (sn >= hi)
        sn = np.where(bad, 0.5 * (lo + hi), sn)
        done = np.abs(sn - s) <= 4e-16 * np.maximum(1.0, np.abs(t[idx]) / h)
        s = np.where(f == 0.0, s, sn)
        if np.all(done | (f == 0.0)) or np.all(hi - lo <= 1e-16):
            break
    return t[idx] + s * h


def level_crossings(t, x, dx, level: float, direction: int = 0) -> np.ndarray:
    """Times where a sampled signal crosses a constant level.

    Parameters
    ----------
    t : array_like (N,)
        Sample times [s], strictly increasing.
    x, dx : array_like (N,)
        Signal [u] and its time derivative [u/s].
    level : float
        Level [u].
    direction : {+1, -1, 0}
        +1: upward crossings only, -1: downward only, 0: both.

    Returns
    -------
    ndarray
        Crossing times [s] in ``(t[0], t[-1]]``, increasing; roots of the cubic
        Hermite interpolant.  An interval whose end samples lie on the same
        side of the level is assumed not to cross it (a signal that touches the
        level and returns between two samples is missed: sample finely enough).
    """
    t = np.asarray(t, float)
    x = np.asarray(x, float)
    dx = np.asarray(dx, float)
    above = x >= level
    up = ~above[:-1] & above[1:]
    down = above[:-1] & ~above[1:]
    sel = up if direction > 0 else down if direction < 0 else (up | down)
    idx = np.flatnonzero(sel)
    if idx.size == 0:
        return np.zeros(0)
    return _roots(t, x, dx, idx, np.full(idx.size, float(level)))


def crossing_times(t, angle, speed, target: float, direction: int = 1) -> np.ndarray:
    """Times where an angle passes ``target + 2 pi k`` for any integer ``k``.

    Parameters
    ----------
    t : array_like (N,)
        Sample times [s], strictly increasing.
    angle : array_like (N,)
        Unwrapped (continuous) angle [rad], e.g. ``Trajectory.rotor_angle``.
    speed : array_like (N,)
        Its time derivative [rad/s].
    target : float
        Angle [rad]; every ``target + 2 pi k`` is a crossing level.
    direction : {+1, -1, 0}
        +1 (default): the angle passes the level while increasing (a
        forward-running rotor); -1: while decreasing; 0: both.

    Returns
    -------
    ndarray
        Crossing times [s] in ``(t[0], t[-1]]``, increasing.  Found on each
        sample interval as roots of the cubic Hermite interpolant of
        (angle, speed); several crossings in one interval (more than a
        revolution per sample) are all found but then the interpolant, not the
        motion, decides them: sample at least ~20 times per revolution for
        ~1e-5 rad (see the module docstring).
    """
    t = np.asarray(t, float)
    angle = np.asarray(angle, float)
    speed = np.asarray(speed, float)
    if not (t.shape == angle.shape == speed.shape) or t.ndim != 1:
        raise ValueError(f"crossing_times: shapes of t {t.shape}, angle {angle.shape}, "
                         f"speed {speed.shape} disagree")
    if t.size < 2:
        return np.zeros(0)
    u = np.floor((angle - target) / TWO_PI)  # level index below or at each sample
    k0, k1 = u[:-1], u[1:]
    idx_parts, lev_parts = [], []
    if direction >= 0:
        for extra in range(int(np.max(k1 - k0, initial=0))):
            sel = np.flatnonzero(k1 - k0 > extra)
            idx_parts.append(sel)
            lev_parts.append(k0[sel] + 1 + extra)
    if direction <= 0:
        for extra in range(int(np.max(k0 - k1, initial=0))):
            sel = np.flatnonzero(k0 - k1 > extra)
            idx_parts.append(sel)
            lev_parts.append(k0[sel] - extra)
    if not idx_parts:
        return np.zeros(0)
    idx = np.concatenate(idx_parts)
    lev = target + TWO_PI * np.concatenate(lev_parts)
    if idx.size == 0:
        return np.zeros(0)
    return np.sort(_roots(t, angle, speed, idx, lev))


# ---------------------------------------------------------------- trajectories
def shaft_velocity(traj) -> tuple[np.ndarray, np.ndarray]:
    """Shaft velocity (vx, vy) [m/s] at the trajectory's samples.

    Attributes ``traj.vx``, ``traj.vy`` are used when present (e.g. an object
    read from a recording that stores them); otherwise taken from the dimensionless state (``traj.state[:, nq]``,
    ``traj.state[:, nq + 1]`` in units of ``L * omega_1``, ``nq`` = half the
    state width, see :mod:`stand.model.planar`), not by differencing.

    Raises
    ------
    ValueError
        The trajectory carries no state (built by hand or read from a
        recording without it).
    """
    vx, vy = getattr(traj, "vx", None), getattr(traj, "vy", None)
    if vx is not None and vy is not None:
        return np.asarray(vx, float), np.asarray(vy, float)
    state = getattr(traj, "state", None)
    if state is None or np.ndim(state) != 2 or state.shape[1] < 4:
        raise ValueError("shaft_velocity: the trajectory has neither vx, vy nor the "
                         "dimensionless state (Trajectory.state); the shaft velocity is unknown "
                         "(record shaft velocities to use the instruments on a recording)")
    generic = _generic_velocity(traj, state)
    if generic is not None:
        return generic
    nq = state.shape[1] // 2
    scale = traj.scene.length_scale * traj.scene.natural_frequency
    return state[:, nq] * scale, state[:, nq + 1] * scale


def _generic_velocity(traj, state):
    """Main-plane velocity (vx, vy) [m/s] of a run of the generic kernel, or None.

    Scenes with body weights or dry friction (and the rotor family) run on the generic kernel
    (:mod:`stand.integrate.coupled`), whose state is ``[q, alpha, q', alpha', body
    states]`` scaled per coordinate: the planar layout (half the state width)
    does not apply.  The model is rebuilt from the scene (cheap: tables only)
    for its layout and scales.
    """
    scene = getattr(traj, "scene", None)
    if scene is None or not getattr(scene, "generic_kernel", ""):
        return None
    from stand.integrate.coupled import build_model

    d = scene.drive
    torque = d.kind != "speed"
    model = build_model(scene.linear_rotor(), scene.weights, d if torque else d.programme,
                        bodies=scene.bodies,
                        inertia=scene.rotor.inertia_about_shaft
                        if torque and scene.kind == "planar" else None)
    n, nw = model.n, model.nw
    if state.shape[1] != model.size:
        return None
    qd = state[:, n + nw:2 * n + nw] * model.scale * model.omega_ref
    plane = getattr(traj, "main_plane", None) or model.plane_names[0]
    v = qd @ np.asarray(model.rotor.planes[plane], float).T
    return v[:, 0], v[:, 1]


@dataclass
class TrajectorySample:
    """A trajectory interpolated at arbitrary times (SI units).

    Attributes
    ----------
    t : (M,) [s]
    x, y : (M,) shaft displacement [m]
    vx, vy : (M,) shaft velocity [m/s] (derivative of the interpolant)
    rotor_angle : (M,) [rad]
    rotor_speed : (M,) [rad/s] (derivative of the interpolant)
    weight_angle : (M, n) absolute weight angles [rad]
    """

    t: np.ndarray
    x: np.ndarray
    y: np.ndarray
    vx: np.ndarray
    vy: np.ndarray
    rotor_angle: np.ndarray
    rotor_speed: np.ndarray
    weight_angle: np.ndarray

    @property
    def relative_angle(self) -> np.ndarray:
        """Weight angles from the rotor's reference mark, wrapped to (-pi, pi] [rad]."""
        return wrap(self.weight_angle - self.rotor_angle[:, None])


def wrap(a):
    """Angle(s) wrapped to (-pi, pi] [rad]."""
    return np.angle(np.exp(1j * np.asarray(a, float)))


def sample_trajectory(traj, tq, velocities: Optional[tuple] = None) -> TrajectorySample:
    """Interpolate a :class:`stand.integrate.simulate.Trajectory` at times ``tq`` [s].

    Shaft position from (x, y) and :func:`shaft_velocity`; rotor angle from
    (rotor_angle, rotor_speed); weight angles from (weight_angle,
    weight_speed); all cubic Hermite (:func:`hermite`).

    Parameters
    ----------
    traj : Trajectory
    tq : array_like
        Times inside the trajectory's time span [s].
    velocities : (vx, vy), optional
        Precomputed :func:`shaft_velocity` (saves recomputing for many calls).
    """
    tq = np.atleast_1d(np.asarray(tq, float))
    vx, vy = velocities if velocities is not None else shaft_velocity(traj)
    xy = hermite(traj.t, np.column_stack([traj.x, traj.y]), np.column_stack([vx, vy]), tq)
    dxy = hermite(traj.t, np.column_stack([traj.x, traj.y]), np.column_stack([vx, vy]), tq,
                  derivative=True)
    phi = hermite(traj.t, traj.rotor_angle, traj.rotor_speed, tq)
    dphi = hermite(traj.t, traj.rotor_angle, traj.rotor_speed, tq, derivative=True)
    wa = np.asarray(traj.weight_angle, float)
    if wa.ndim == 2 and wa.shape[1]:
        w = hermite(traj.t, wa, np.asarray(traj.weight_speed, float), tq)
    else:
        w = np.zeros((tq.size, 0))
    return TrajectorySample(t=tq, x=xy[:, 0], y=xy[:, 1], vx=dxy[:, 0], vy=dxy[:, 1],
                            rotor_angle=phi, rotor_speed=dphi, weight_angle=w)


# ---------------------------------------------------------------- windows
def time_window(traj, t_start: Optional[float], t_end: Optional[float],
                what: str = "instrument") -> tuple[float, float]:
    """The part ``[t0, t1]`` [s] of ``[t_start, t_end]`` that the run covers.

    ``None`` means the run's first (last) sample time.

    Raises
    ------
    SceneError
        The window is empty; the message names ``what`` (e.g. "stroboscope")
        and the run's time span.
    """
    from stand.errors import SceneError

    t0 = float(traj.t[0]) if t_start is None else max(float(t_start), float(traj.t[0]))
    t1 = float(traj.t[-1]) if t_end is None else min(float(t_end), float(traj.t[-1]))
    if not t1 > t0:
        raise SceneError(f"{what} window [{t0:.6g}, {t1:.6g}] s is empty (the run spans "
                         f"[{float(traj.t[0]):.6g}, {float(traj.t[-1]):.6g}] s)")
    return t0, t1
