"""Run a scene: integrate the planar model and return a sampled trajectory.

One entry point, :func:`simulate`, shaped like ``scipy.integrate.solve_ivp``:
``method=`` by name, a result with ``status``/``message``/``nfev``... plus SI
arrays with units.  Methods:

* ``"DOP853"`` -- compiled explicit 8th-order Runge-Kutta (:mod:`stand.dop853`),
  the default for ordinary scenes;
* ``"Radau"``, ``"BDF"``, ``"LSODA"`` -- scipy's implicit/switching solvers on
  the compiled right-hand side with a compiled finite-difference Jacobian; "auto"
  picks Radau when the scene is stiff (large weight drag, h >> R_omega);
* ``"numpy-DOP853"`` -- scipy's DOP853 on the pure-numpy right-hand side that
  solves the full linear system: the slow reference path for checking.
"""
from __future__ import annotations

import json
import math
import time as _time
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from ._jit import njit
from .dop853 import (DIVERGED, NOT_FINITE, REACHED_END, STEP_BUDGET, STEP_TOO_SMALL,
                     dop853_loop)
from .planar import (D11, D22, H0, K22, N_PROG, WTARGET, PlanarModel, build_planar_model,
                     initial_state, rhs_planar, rhs_planar_numpy)
from .scene import METHODS, Scene, SceneError
from .kernels import PLANAR, rhs
from .weights import EPS, H, MU

#: a scene is stiff when its fastest decay rate exceeds this many times its
#: fastest oscillation (explicit methods would be limited by stability, not accuracy)
STIFFNESS_RATIO = 30.0
CHUNK_STEPS = 200_000
#: a dimensionless state component beyond this (1e12 r*, rad or omega_1) means divergence
DIVERGENCE_LIMIT = 1e12
_DIVERGED = ("State diverged (|state| > 1e12 in units of r*, rad, omega_1: the motion is unbounded, "
             "e.g. negative damping or a non-physical parameter)")


@dataclass
class SolverStats:
    """Solver statistics, as a ``solve_ivp`` result carries them."""

    method: str
    rtol: float
    atol: float
    n_steps: int = 0
    n_rejected: int = 0
    nfev: int = 0
    njev: int = 0
    nlu: int = 0
    wall_time: float = 0.0
    status: int = 0
    message: str = ""
    success: bool = True
    stiffness_ratio: float = 0.0
    method_reason: str = ""

    def to_json(self) -> str:
        return json.dumps(asdict(self))


@dataclass
class Trajectory:
    """Sampled motion of the stand, SI units.

    Attributes
    ----------
    t : ndarray (N,)                time [s]
    x, y : ndarray (N,)             shaft displacement [m]
    rotor_angle : ndarray (N,)      angle of the reference mark [rad]
    rotor_speed : ndarray (N,)      [rad/s]
    weight_angle : ndarray (N, n)   absolute weight angles [rad]
    weight_speed : ndarray (N, n)   absolute weight speeds [rad/s]
    stats : SolverStats
    scene : Scene
    """

    t: np.ndarray
    x: np.ndarray
    y: np.ndarray
    rotor_angle: np.ndarray
    rotor_speed: np.ndarray
    weight_angle: np.ndarray
    weight_speed: np.ndarray
    stats: SolverStats
    scene: Scene
    state: np.ndarray = field(repr=False, default=None)  #: dimensionless samples
    extra: "Trajectory | None" = field(repr=False, default=None)  #: samples at ``extra_times``

    UNITS = {"t": "s", "x": "m", "y": "m", "rotor_angle": "rad", "rotor_speed": "rad/s",
             "weight_angle": "rad", "weight_speed": "rad/s"}

    @property
    def success(self) -> bool:
        return self.stats.success

    @property
    def relative_angle(self) -> np.ndarray:
        """Weight angles relative to the rotor's reference mark, wrapped to (-pi, pi] [rad]."""
        a = self.weight_angle - self.rotor_angle[:, None]
        return np.angle(np.exp(1j * a))

    def residual_unbalance(self) -> np.ndarray:
        """Total unbalance rotor + weights, complex, in the rotor frame [kg*m].

        psi = M e e^{i beta} + sum m_j l_j e^{i alpha_j}  ((5.76)-(5.77) times S),
        with the rotor's unbalance following the scene's unbalance changes.
        """
        from .planar import rotor_unbalance

        b = self.scene.balancer
        psi = rotor_unbalance(self.scene, self.t)
        if b.count:
            psi = psi + np.sum(b.mass * b.radius * np.exp(1j * (self.weight_angle - self.rotor_angle[:, None])), axis=1)
        return psi

    def whirl_radius(self) -> np.ndarray:
        """|r_K| = sqrt(x^2 + y^2) [m]."""
        return np.hypot(self.x, self.y)

    def summary(self, window: float | None = None) -> dict:
        """Final state for reports and ``stand run --json``.

        Parameters
        ----------
        window : float, optional
            Averaging window at the end of the run [s]; default: the last rotor
            revolution (or the last 5 % of the run when the rotor is at rest).
        """
        N = len(self.t)
        out = {"solver": asdict(self.stats)}
        if N == 0:
            out["final"] = None
            return out
        if window is None:
            w = abs(self.rotor_speed[-1])
            window = 2 * np.pi / w if w > 0 else 0.05 * self.t[-1]
        sel = self.t >= self.t[-1] - window
        S = self.scene.balancer.capacity
        psi = abs(self.residual_unbalance()[-1])
        rel = np.degrees(self.relative_angle[-1]) if self.scene.balancer.count else np.zeros(0)
        out["final"] = {
            "time_s": float(self.t[-1]),
            "rotor_speed_rev_per_s": float(self.rotor_speed[-1] / (2 * np.pi)),
            "residual_unbalance": float(psi / S) if S > 0 else None,
            "residual_unbalance_g_mm": float(psi * 1e6),
            "capacity_g_mm": float(S * 1e6),
            "weights_relative_angle_deg": [float(a) for a in rel],
            "whirl_radius_m": float(np.mean(self.whirl_radius()[sel])),
            "whirl_radius_last_m": float(self.whirl_radius()[-1]),
        }
        return out


@njit(cache=True)
def _jac_fd(kind, t, y, f0, sp, wt, prog, J):
    n = y.shape[0]
    yy = y.copy()
    df = np.empty(n)
    for i in range(n):
        dh = 1.5e-8 * max(1.0, abs(y[i]))
        yy[i] = y[i] + dh
        rhs(kind, t, yy, df, sp, wt, prog)
        for k in range(n):
            J[k, i] = (df[k] - f0[k]) / dh
        yy[i] = y[i]


def stiffness(model: PlanarModel) -> float:
    """Ratio of the fastest decay rate to the fastest oscillation frequency.

    Decay rates: weight drag h_j / (1 - eps_j mu_j), support damping, rotor
    drag; oscillation: 1 (omega_1), sqrt(k22), the largest rotor speed.
    """
    sp, wt = model.sp, model.wt
    rates = [sp[D11], sp[D22], abs(sp[H0])]
    if model.n:
        rates.append(float(np.max(wt[:, H] / np.maximum(1.0 - wt[:, EPS] * wt[:, MU], 1e-12))))
    speed = max(1.0, math.sqrt(abs(sp[K22])), float(np.max(np.abs(model.prog[:int(sp[N_PROG]), 1]))),
                abs(sp[WTARGET]))
    return max(rates) / speed


def choose_method(model: PlanarModel, requested: str) -> tuple[str, float, str]:
    ratio = stiffness(model)
    if requested != "auto":
        return requested, ratio, "requested"
    if ratio > STIFFNESS_RATIO:
        return "Radau", ratio, f"stiff: fastest decay rate / fastest frequency = {ratio:.3g} > {STIFFNESS_RATIO:g}"
    return "DOP853", ratio, f"non-stiff: fastest decay rate / fastest frequency = {ratio:.3g} <= {STIFFNESS_RATIO:g}"


def simulate(scene: Scene, method: str | None = None, rtol: float | None = None,
             atol: float | None = None, progress: bool = False,
             extra_times=None, checkpoint=None, checkpoint_steps: int = CHUNK_STEPS) -> Trajectory:
    """Integrate a scene.

    Parameters
    ----------
    scene : Scene
    method : str, optional
        Overrides ``scene.run.method``; one of :data:`METHODS`.
    rtol, atol : float, optional
        Override the scene's tolerances (dimensionless state, see docs/scene.md).
    progress : bool
        Show a progress bar (stderr) when the run lasts more than ~2 s.
    extra_times : array_like, optional
        Additional sample times [s], non-decreasing, within [0, duration]
        (e.g. the instruments' exposure and flash times).  They are sampled by
        the same dense output in the same run and returned as
        ``trajectory.extra`` (a Trajectory of its own); the recording grid is
        unchanged.
    checkpoint : path, optional
        Long runs (compiled DOP853 only): the integrator's state and the samples
        so far are saved to this ``.npz`` file after every chunk of steps
        (atomically: temporary file + rename; no pickle).  If the file exists
        when the run starts and belongs to the same scene and settings, the run
        resumes from it (same steps, same samples as an uninterrupted run); it
        is deleted when the run ends.  A killed run loses at most one chunk.
    checkpoint_steps : int
        Steps between checkpoints (default 200 000, a few seconds of work).

    Returns
    -------
    Trajectory
        ``stats.status`` is 0 on success, negative on failure (non-finite state,
        step size collapse, step budget); what was computed until then is kept.
    """
    run = scene.run
    method = method or run.method
    if method not in METHODS:
        raise SceneError(f"run.method = {method!r}: must be one of {', '.join(METHODS)}")
    rtol = run.rtol if rtol is None else rtol
    atol = run.atol if atol is None else atol
    model = build_planar_model(scene)
    method, ratio, reason = choose_method(model, method)
    w1 = model.omega_1
    tau_end = run.duration * w1
    ts_rec = sample_times(run.duration, run.sample_rate) * w1
    ts, rec_idx, ex_idx = _merge_times(ts_rec, extra_times, run.duration, w1)
    n_samples = ts.size
    y0 = initial_state(scene, model)
    out = np.full((n_samples, model.size), np.nan)
    out[0] = y0
    stats = SolverStats(method=method, rtol=rtol, atol=atol, stiffness_ratio=ratio, method_reason=reason)
    _warm_up(model)  # compile / load the kernels outside the timed region
    t0 = _time.perf_counter()
    if method == "DOP853":
        ck = None
        if checkpoint is not None:
            ck = _Checkpoint(checkpoint, _fingerprint(scene, method, rtol, atol, ts, model.size))
        k = _run_dop853(model, y0, tau_end, rtol, atol, ts, out, stats, run.max_steps, progress, ck,
                        int(checkpoint_steps) if ck is not None else CHUNK_STEPS)
        if ck is not None and stats.success:
            ck.remove()
    elif checkpoint is not None:
        raise SceneError(f"checkpoint: only with the compiled DOP853 method (this run uses {method})")
    else:
        k = _run_scipy(model, y0, tau_end, rtol, atol, ts, out, stats, method, run.max_steps)
    stats.wall_time = _time.perf_counter() - t0
    if ex_idx is None:
        return _trajectory(scene, model, out[:k], ts[:k], stats)
    r = rec_idx[rec_idx < k]
    e = ex_idx[ex_idx < k]
    traj = _trajectory(scene, model, out[r], ts[r], stats)
    traj.extra = _trajectory(scene, model, out[e], ts[e], stats)
    return traj


def _merge_times(ts_rec, extra_times, duration, w1):
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


def sample_times(duration: float, sample_rate: float) -> np.ndarray:
    """Sample times [s]: k / sample_rate for k = 0, 1, ...; a last time within
    1e-9 of a sample interval of ``duration`` is set to ``duration`` exactly, so
    that rounding never drops the final sample."""
    n = int(math.floor(duration * sample_rate + 1e-9)) + 1
    t = np.arange(n) / sample_rate
    if abs(t[-1] - duration) <= 1e-9 / sample_rate:
        t[-1] = duration
    return np.minimum(t, duration)


def _segments(model: PlanarModel, tau_end: float) -> list[float]:
    bp = [b for b in model.breakpoints() if b < tau_end]
    return bp + [tau_end]


def _fingerprint(scene, method, rtol, atol, ts, size) -> str:
    import hashlib

    h = hashlib.sha256()
    for part in (scene.text or repr(scene), method, repr(rtol), repr(atol), repr(size)):
        h.update(part.encode("utf-8"))
    h.update(np.ascontiguousarray(ts).tobytes())
    return h.hexdigest()


class _Checkpoint:
    """State of an interrupted compiled-DOP853 run in an ``.npz`` file (no pickle)."""

    def __init__(self, path, fingerprint: str):
        import os

        self.path = Path(path)
        self.fp = fingerprint
        if not self.path.resolve().parent.is_dir():
            raise FileNotFoundError(f"checkpoint directory of {str(self.path)!r} does not exist")
        self._os = os

    def load(self):
        if not self.path.exists():
            return None
        try:
            with np.load(self.path, allow_pickle=False) as z:
                d = {k: z[k] for k in z.files}
        except (OSError, ValueError) as exc:
            raise SceneError(f"checkpoint {str(self.path)!r} is not readable ({exc}); delete it "
                             "to start the run afresh") from None
        if str(d.get("fingerprint")) != self.fp:
            raise SceneError(f"checkpoint {str(self.path)!r} belongs to another scene or other "
                             "settings; delete it or choose another file")
        return d

    def save(self, t, y, h, k_next, seg_done, st, out):
        import tempfile

        fd, tmp = tempfile.mkstemp(dir=str(self.path.resolve().parent),
                                   prefix=f".{self.path.name}.", suffix=".tmp.npz")
        self._os.close(fd)
        try:
            np.savez(tmp, fingerprint=np.array(self.fp), t=np.array(t), y=y, h=np.array(h),
                     k_next=np.array(k_next), seg_done=np.array(seg_done), st=st,
                     out=out[:k_next])
            self._os.replace(tmp, self.path)
        finally:
            if self._os.path.exists(tmp):
                self._os.remove(tmp)

    def remove(self):
        if self.path.exists():
            self.path.unlink()


def _run_dop853(model, y0, tau_end, rtol, atol, ts, out, stats, max_steps, progress, ck=None,
                chunk=CHUNK_STEPS):
    sp, wt, prog = model.sp, model.wt, model.prog
    cap = np.where(model.angle_mask(), np.pi, np.inf)
    y = y0.copy()
    f = np.empty_like(y)
    rhs_planar(0.0, y, f, sp, wt, prog)
    if not (np.all(np.isfinite(y)) and np.all(np.isfinite(f))):
        stats.status, stats.success = -2, False
        stats.message = ("Non-finite initial state or right-hand side at t = 0 s: a scene parameter is "
                         "out of floating-point range; nothing was integrated.")
        return 1
    st = np.zeros(3, np.int64)
    st[2] = 1
    h = _initial_step(model, y, f, rtol, atol, cap)
    t = 0.0
    k_next = 1
    seg_done = 0
    saved = ck.load() if ck is not None else None
    if saved is not None:     # resume an interrupted run
        t, h = float(saved["t"]), float(saved["h"])
        y[:] = saved["y"]
        k_next, seg_done = int(saved["k_next"]), int(saved["seg_done"])
        st[:] = saved["st"]
        out[:k_next] = saved["out"]
        rhs_planar(t, y, f, sp, wt, prog)
    bar = _progress_bar(tau_end / model.omega_1) if progress else None
    status = REACHED_END
    for i_seg, seg_end in enumerate(_segments(model, tau_end)):
        if i_seg < seg_done:
            continue
        while t < seg_end:
            budget = min(chunk, max_steps - int(st[0] + st[1]))
            if budget <= 0:
                status = STEP_BUDGET
                break
            status, t, h, k_next = dop853_loop(PLANAR, sp, wt, prog, t, y, f, h, seg_end, rtol,
                                               atol, cap, np.inf, ts, k_next, out, st, budget,
                                               DIVERGENCE_LIMIT)
            if bar is not None:
                bar.update(t / model.omega_1 - bar.n)
            if status not in (REACHED_END, STEP_BUDGET):
                break
            if ck is not None and t < seg_end:
                ck.save(t, y, h, k_next, seg_done, st, out)
        if t < seg_end:
            break
        if seg_end < tau_end:  # restart the derivative after a kink of the programme
            _apply_impulses(model, t, y)
            rhs_planar(t, y, f, sp, wt, prog)
            st[2] += 1
        seg_done = i_seg + 1
        if ck is not None and seg_end < tau_end:
            ck.save(t, y, h, k_next, seg_done, st, out)
    if bar is not None:
        bar.close()
    stats.n_steps, stats.n_rejected, stats.nfev = int(st[0]), int(st[1]), int(st[2])
    t_s = t / model.omega_1
    if t >= tau_end:
        stats.status, stats.success, stats.message = 0, True, "The solver successfully reached the end of the integration interval."
    elif status == STEP_BUDGET or status == REACHED_END:
        stats.status, stats.success = -3, False
        stats.message = f"Step budget run.max_steps = {max_steps} exhausted at t = {t_s:.6g} s; samples up to there are kept."
    elif status == DIVERGED:
        stats.status, stats.success = -2, False
        stats.message = f"{_DIVERGED} at t = {t_s:.6g} s; samples up to there are kept."
    elif status == NOT_FINITE:
        stats.status, stats.success = -2, False
        stats.message = (f"Non-finite state at t = {t_s:.6g} s (the motion diverged or a parameter is "
                         "non-physical); samples up to there are kept.")
    else:
        stats.status, stats.success = -1, False
        stats.message = (f"Step size collapsed at t = {t_s:.6g} s (required step below the time "
                         "resolution; the problem may be stiff: try run.method = \"Radau\"); samples up to there are kept.")
    return k_next


def _apply_impulses(model, tau, y):
    """Shaft velocity jumps of the blows to the housing that happen at ``tau``."""
    imp = model.impulses
    if imp is None or imp.size == 0:
        return
    nq = model.nq
    for t_i, dvx, dvy in imp:
        if t_i == tau:
            y[nq] += dvx
            y[nq + 1] += dvy


def _initial_step(model, y, f, rtol, atol, cap):
    """scipy's ``select_initial_step`` (Hairer's algorithm) with the capped scale.

    Returns a finite positive step (1e-6 when the estimate is not finite)."""
    with np.errstate(all="ignore"):
        mag = np.minimum(np.abs(y), cap)
        scale = atol + mag * rtol
        nrm = lambda v: np.float64(np.linalg.norm(v) / math.sqrt(v.size))
        d0, d1 = nrm(y / scale), nrm(f / scale)
        h0 = np.float64(1e-6) if (d0 < 1e-5 or d1 < 1e-5) else 0.01 * d0 / d1
        if not (np.isfinite(h0) and h0 > 0):
            return 1e-6
        f1 = np.empty_like(y)
        rhs_planar(float(h0), y + h0 * f, f1, model.sp, model.wt, model.prog)
        d2 = nrm((f1 - f) / scale) / h0
        if d1 <= 1e-15 and d2 <= 1e-15:
            h1 = max(1e-6, h0 * 1e-3)
        else:
            h1 = (0.01 / max(d1, d2)) ** (1 / 8)
        h = float(min(100 * h0, h1))
    return h if (np.isfinite(h) and h > 0) else 1e-6


def _warm_up(model):
    y = np.zeros(model.size)
    out = np.zeros((1, model.size))
    dop853_loop(PLANAR, model.sp, model.wt, model.prog, 0.0, y, y.copy(), 1.0, 0.0, 1e-8, 1e-10,
                np.full(model.size, np.inf), np.inf, np.zeros(1), 1, out, np.zeros(3, np.int64), 1, 1e12)


def _progress_bar(total_s):
    try:
        from tqdm import tqdm
    except ImportError:  # pragma: no cover
        return None
    return tqdm(total=total_s, unit="s", delay=2.0, desc="simulating", leave=False,
                bar_format="{l_bar}{bar}| {n:.3g}/{total:.3g} s [{elapsed}<{remaining}]")


class _NonFinite(Exception):
    pass


def _run_scipy(model, y0, tau_end, rtol, atol, ts_all, out, stats, method, max_steps):
    """Step one of scipy's ``OdeSolver`` classes, sampling by its dense output.

    Stepping the solver object (rather than calling ``solve_ivp``) keeps the
    samples computed before a failure, honours the step budget and checks each
    step for non-finite or diverged states.
    """
    from scipy.integrate import BDF, DOP853, LSODA, Radau

    sp, wt, prog = model.sp, model.wt, model.prog
    n_samples = out.shape[0]
    if method == "numpy-DOP853":
        def fun(t, y):
            dy = rhs_planar_numpy(t, y, sp, wt, prog)
            if not np.all(np.isfinite(dy)):
                raise _NonFinite(t)
            return dy

        cls, kw = DOP853, {}
    else:
        def fun(t, y):
            dy = np.empty_like(y)
            rhs_planar(t, y, dy, sp, wt, prog)
            if not np.all(np.isfinite(dy)):
                raise _NonFinite(t)
            return dy

        def jac(t, y):
            f0 = np.empty_like(y)
            rhs_planar(t, y, f0, sp, wt, prog)
            J = np.empty((y.size, y.size))
            _jac_fd(PLANAR, t, y, f0, sp, wt, prog, J)
            return J

        cls = {"Radau": Radau, "BDF": BDF, "LSODA": LSODA}[method]
        kw = {"jac": jac}
    y = y0.copy()
    t = 0.0
    k_next = 1
    steps = 0
    atol_v = np.full(y.size, atol)
    fail = None
    for seg_end in _segments(model, tau_end):
        try:
            with np.errstate(all="ignore"):
                solver = cls(fun, t, y, seg_end, rtol=rtol, atol=atol_v, **kw)
                while solver.status == "running":
                    if steps >= max_steps:
                        fail = (-3, f"Step budget run.max_steps = {max_steps} exhausted")
                        break
                    msg = solver.step()
                    steps += 1
                    if solver.status == "failed":
                        fail = (-1, f"{method} failed: {msg}")
                        break
                    if not np.all(np.isfinite(solver.y)):
                        fail = (-2, "Non-finite state (the motion diverged or a parameter is non-physical)")
                        break
                    if np.max(np.abs(solver.y)) > DIVERGENCE_LIMIT:
                        fail = (-2, _DIVERGED)
                        break
                    if k_next < n_samples and ts_all[k_next] <= solver.t:
                        dense = solver.dense_output()
                        k_end = int(np.searchsorted(ts_all, solver.t, side="right"))
                        ts = ts_all[k_next:k_end]
                        if ts.size:
                            out[k_next:k_next + ts.size] = np.atleast_2d(dense(ts)).T
                            k_next += ts.size
        except _NonFinite:
            fail = (-2, "Non-finite right-hand side (the motion diverged or a parameter is non-physical)")
        except (ValueError, np.linalg.LinAlgError) as exc:
            fail = (-1, f"{method} failed: {exc}")
        stats.nfev += int(solver.nfev) if "solver" in locals() else 0
        stats.njev += int(getattr(solver, "njev", 0)) if "solver" in locals() else 0
        stats.nlu += int(getattr(solver, "nlu", 0)) if "solver" in locals() else 0
        if fail is not None:
            break
        t = seg_end
        y = solver.y.copy()
        _apply_impulses(model, t, y)
    stats.n_steps = steps
    if fail is None:
        stats.status, stats.success = 0, True
        stats.message = "The solver successfully reached the end of the integration interval."
    else:
        good = np.all(np.isfinite(out[:k_next]), axis=1)
        if not good.all():
            k_next = int(np.argmin(good))
        t_stop = (solver.t if "solver" in locals() else t) / model.omega_1
        stats.status, stats.success = fail[0], False
        stats.message = f"{fail[1]} at t = {t_stop:.6g} s; samples up to there are kept."
    return k_next


def _trajectory(scene: Scene, model: PlanarModel, out: np.ndarray, tau: np.ndarray,
                stats: SolverStats) -> Trajectory:
    nq, n, L, w1 = model.nq, model.n, model.length, model.omega_1
    phi, R = model.rotor(tau, out)
    alpha = out[:, 2:2 + n]
    dalpha = out[:, nq + 2:nq + 2 + n]
    return Trajectory(
        t=tau / w1,
        x=out[:, 0] * L,
        y=out[:, 1] * L,
        rotor_angle=np.asarray(phi, float).copy(),
        rotor_speed=np.asarray(R, float) * w1,
        weight_angle=phi[:, None] + alpha,
        weight_speed=(R[:, None] + dalpha) * w1,
        stats=stats,
        scene=scene,
        state=out,
    )
