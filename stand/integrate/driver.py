"""One integrator path for every compiled model: the DOP853 driver and scipy's methods.

A *model* is anything with ``kind`` (the compiled right-hand side's number in
:mod:`stand.model.kernels`), the packed arrays ``sp``, ``wt``, ``prog``, the state
``size``, the time scale ``omega_1`` [rad/s] (time is integrated as
``tau = omega_1 t``), ``angle_mask()``, ``breakpoints()`` (dimensionless times
where the forcing has a kink; the step restarts there) and ``impulses``
(velocity jumps, or None).  A model written in Python instead sets
``python_rhs(tau, y)``; it is stepped by scipy's solvers only.

* :func:`run_dop853` -- the compiled Dormand-Prince 8(5,3) loop
  (:mod:`stand.integrate.dop853`) in chunks, with optional checkpoints and a progress bar;
* :func:`run_scipy` -- one of scipy's ``OdeSolver`` classes (Radau, BDF,
  LSODA, DOP853) stepped one step at a time on the compiled right-hand side
  with a compiled finite-difference Jacobian, sampling by dense output.

Both fill the sample array ``out`` at the times ``ts``, keep what was computed
before a failure, honour a step budget and report in a
:class:`stand.integrate.result.SolverStats` (``status``, ``message``, ``nfev``, ...).
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from stand.integrate.dop853 import DIVERGED, NOT_FINITE, REACHED_END, STEP_BUDGET
from stand.integrate.kernel_set import kernels
from stand.errors import SceneError

__all__ = ["run_dop853", "run_scipy", "warm_up", "Checkpoint", "fingerprint", "segments",
           "CHUNK_STEPS", "DIVERGENCE_LIMIT"]

CHUNK_STEPS = 200_000
#: a dimensionless state component beyond this (1e12 scale units, rad or omega_1) means divergence
DIVERGENCE_LIMIT = 1e12
_DIVERGED = ("State diverged (|state| > 1e12 in units of the length scale, rad, omega_1: the "
             "motion is unbounded, e.g. negative damping or a non-physical parameter)")


def segments(model, tau_end: float) -> list:
    """Integration segments: the model's breakpoints before ``tau_end``, then ``tau_end``."""
    bp = np.asarray(model.breakpoints(), float)
    return bp[bp < tau_end].tolist() + [tau_end]


def fingerprint(scene, method, rtol, atol, ts, size) -> str:
    import hashlib

    h = hashlib.sha256()
    for part in (scene.text or repr(scene), method, repr(rtol), repr(atol), repr(size)):
        h.update(part.encode("utf-8"))
    h.update(np.ascontiguousarray(ts).tobytes())
    return h.hexdigest()


class Checkpoint:
    """State of an interrupted compiled-DOP853 run in an ``.npz`` file (no pickle)."""

    def __init__(self, path, fingerprint: str):
        self.path = Path(path)
        self.fp = fingerprint
        if not self.path.resolve().parent.is_dir():
            raise FileNotFoundError(f"checkpoint directory of {str(self.path)!r} does not exist")

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
        from stand.io.atomic import atomic_path

        with atomic_path(self.path, suffix=".tmp.npz") as tmp:
            np.savez(tmp, fingerprint=np.array(self.fp), t=np.array(t), y=y, h=np.array(h),
                     k_next=np.array(k_next), seg_done=np.array(seg_done), st=st,
                     out=out[:k_next])

    def remove(self):
        if self.path.exists():
            self.path.unlink()



def run_dop853(model, y0, tau_end, rtol, atol, ts, out, stats, max_steps, progress, ck=None,
                chunk=CHUNK_STEPS):
    kind = model.kind
    # the compiled entry points take C-contiguous float64 arrays: made so once here, the
    # checked wrappers are skipped in the loop over the programme's segments (a recorded
    # drive has one per node, a thousand in a 25-s run-up)
    sp, wt, prog = (np.ascontiguousarray(a, dtype=float) for a in (model.sp, model.wt,
                                                                  model.prog))
    ks = kernels(kind)
    cap = np.where(model.angle_mask(), np.pi, np.inf)
    ts = np.ascontiguousarray(ts, dtype=float)
    y = np.array(y0, dtype=float)
    f = np.empty_like(y)
    step = getattr(ks.dop853, "unchecked", None)
    if step is None or not (out.dtype == np.float64 and out.flags.c_contiguous
                            and out.flags.writeable):
        step = ks.dop853
    evaluate = getattr(ks.evaluate, "unchecked", ks.evaluate)   # y, f, sp, wt, prog made so
    try:
        ks.evaluate(0.0, y, f, sp, wt, prog)
    except np.linalg.LinAlgError:       # a singular or non-finite mass matrix
        f[:] = np.nan
    if not (np.all(np.isfinite(y)) and np.all(np.isfinite(f))):
        stats.status, stats.success = -2, False
        stats.message = ("Non-finite initial state or right-hand side at t = 0 s: a scene parameter is "
                         "out of floating-point range; nothing was integrated.")
        return 1
    st = np.zeros(3, np.int64)
    st[2] = 1
    rtol, atol = float(rtol), float(atol)
    h = float(initial_step(model, y, f, rtol, atol, cap))
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
        ks.evaluate(t, y, f, sp, wt, prog)
    bar = _progress_bar(tau_end / model.omega_1) if progress else None
    status = REACHED_END
    for i_seg, seg_end in enumerate(segments(model, tau_end)):
        if i_seg < seg_done:
            continue
        while t < seg_end:
            budget = min(chunk, max_steps - int(st[0] + st[1]))
            if budget <= 0:
                status = STEP_BUDGET
                break
            try:
                status, t, h, k_next = step(sp, wt, prog, t, y, f, h, seg_end, rtol, atol,
                                            cap, np.inf, ts, k_next, out, st, budget,
                                            DIVERGENCE_LIMIT)
            except np.linalg.LinAlgError:   # the compiled solve met a non-finite mass matrix
                status = NOT_FINITE
            if bar is not None:
                bar.update(t / model.omega_1 - bar.n)
            if status not in (REACHED_END, STEP_BUDGET):
                break
            if ck is not None and t < seg_end:
                ck.save(t, y, h, k_next, seg_done, st, out)
        if t < seg_end:
            break
        if seg_end < tau_end:  # restart the derivative after a kink of the programme
            apply_impulses(model, t, y)
            evaluate(t, y, f, sp, wt, prog)
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



def apply_impulses(model, tau, y):
    """Shaft velocity jumps of the blows to the housing that happen at ``tau``.

    ``model.impulses``: rows ``(tau, dvx, dvy)`` on the planar state layout, or rows
    ``(tau, dy_0, ..., dy_{size-1})`` -- a jump of the whole scaled state -- on the
    generic one (:class:`stand.model.rotors.coupled_kernel.CoupledModel`)."""
    imp = model.impulses
    if imp is None or imp.size == 0:
        return
    if imp.shape[1] == y.size + 1:
        for row in imp:
            if row[0] == tau:
                y += row[1:]
        return
    nq = model.nq
    for t_i, dvx, dvy in imp:
        if t_i == tau:
            y[nq] += dvx
            y[nq + 1] += dvy


def initial_step(model, y, f, rtol, atol, cap):
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
        kernels(model.kind).evaluate(float(h0), y + h0 * f, f1, model.sp, model.wt, model.prog)
        d2 = nrm((f1 - f) / scale) / h0
        if d1 <= 1e-15 and d2 <= 1e-15:
            h1 = max(1e-6, h0 * 1e-3)
        else:
            h1 = (0.01 / max(d1, d2)) ** (1 / 8)
        h = float(min(100 * h0, h1))
    return h if (np.isfinite(h) and h > 0) else 1e-6


def warm_up(model):
    """Load (or compile) the integrator's kernels for ``model``'s kind, outside any timing."""
    kernels(model.kind)


def _progress_bar(total_s):
    try:
        from tqdm import tqdm
    except ImportError:  # pragma: no cover
        return None
    return tqdm(total=total_s, unit="s", delay=2.0, desc="simulating", leave=False,
                bar_format="{l_bar}{bar}| {n:.3g}/{total:.3g} s [{elapsed}<{remaining}]")


class _NonFinite(Exception):
    pass


def run_scipy(model, y0, tau_end, rtol, atol, ts_all, out, stats, method, max_steps):
    """Step one of scipy's ``OdeSolver`` classes, sampling by its dense output.

    Stepping the solver object (rather than calling ``solve_ivp``) keeps the
    samples computed before a failure, honours the step budget and checks each
    step for non-finite or diverged states.
    """
    from scipy.integrate import BDF, DOP853, LSODA, Radau

    sp, wt, prog = model.sp, model.wt, model.prog
    kind = getattr(model, "kind", None)
    n_samples = out.shape[0]
    if getattr(model, "python_rhs", None) is not None:   # a model written in Python
        def fun(t, y):
            dy = model.python_rhs(t, y)
            if not np.all(np.isfinite(dy)):
                raise _NonFinite(t)
            return dy

        cls = {"DOP853": DOP853, "numpy-DOP853": DOP853, "Radau": Radau, "BDF": BDF,
               "LSODA": LSODA}[method]
        kw = {}
    elif method == "numpy-DOP853":
        numpy_rhs = getattr(model, "numpy_rhs", None)
        if numpy_rhs is None:
            raise SceneError("run.method = \"numpy-DOP853\": the pure-numpy reference path exists "
                             "for the planar rotor only; use DOP853, Radau, BDF or LSODA")

        def fun(t, y):
            dy = numpy_rhs(t, y, sp, wt, prog)
            if not np.all(np.isfinite(dy)):
                raise _NonFinite(t)
            return dy

        cls, kw = DOP853, {}
    else:
        ks = kernels(kind)
        ev = ks.evaluate

        def fun(t, y):
            dy = np.empty_like(y)
            ev(t, y, dy, sp, wt, prog)
            if not np.all(np.isfinite(dy)):
                raise _NonFinite(t)
            return dy

        def jac(t, y):
            f0 = np.empty_like(y)
            ev(t, y, f0, sp, wt, prog)
            J = np.empty((y.size, y.size))
            ks.jacobian(t, y, f0, sp, wt, prog, J)
            return J

        cls = {"Radau": Radau, "BDF": BDF, "LSODA": LSODA}[method]
        kw = {"jac": jac}
    y = y0.copy()
    t = 0.0
    k_next = 1
    steps = 0
    atol_v = np.full(y.size, atol)
    fail = None
    for seg_end in segments(model, tau_end):
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
        apply_impulses(model, t, y)
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


