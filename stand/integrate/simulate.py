"""Run a scene: integrate its model and return one :class:`stand.integrate.result.Run`.

One entry point for every scene (:func:`simulate`, also :func:`stand.run`),
shaped like ``scipy.integrate.solve_ivp``: ``method=`` by name, a result with
``status``/``message``/``nfev``... plus SI arrays with units.  The planar rotor
of chapter 5 runs on its own compiled kernel (:mod:`stand.model.planar`); any other
structure, the planar rotor with what its kernel does not have (body weights, dry friction
of the weights: :attr:`stand.scene.model.Scene.generic_kernel`) and the planar rotor with
``kernel="generic"`` on the generic kernel (:mod:`stand.model.rotors.coupled_kernel`); both through the one integrator
path :mod:`stand.integrate.driver`.  A book weight model (``[weight_model]``)
runs its own right-hand side through scipy's solvers
(:mod:`stand.integrate.book_run`, reached through :data:`RUNNERS`).  Methods:

* ``"DOP853"`` -- compiled explicit 8th-order Runge-Kutta (:mod:`stand.integrate.dop853`),
  the default for ordinary scenes;
* ``"Radau"``, ``"BDF"``, ``"LSODA"`` -- scipy's implicit/switching solvers on
  the compiled right-hand side with a compiled finite-difference Jacobian; "auto"
  picks Radau when the scene is stiff (large weight drag, h >> R_omega);
* ``"numpy-DOP853"`` -- scipy's DOP853 on the pure-numpy right-hand side that
  solves the full linear system: the slow reference path for checking.
"""
from __future__ import annotations

import math

import numpy as np

from stand.integrate.driver import CHUNK_STEPS
from stand.integrate.runs import generic_run, integrate_model, merge_times, sample_times
from stand.model.planar import (D11, D22, H0, K22, N_PROG, WTARGET, PlanarModel, build_planar_model,
                     initial_state)
from stand.integrate.result import Run, SolverStats, weight_names
from stand.scene.model import METHODS, Scene, SceneError
from stand.model.registry import resolve
from stand.model.weights import EPS, H, MU

__all__ = ["simulate", "Run", "Trajectory", "SolverStats", "sample_times", "METHODS"]

#: a scene is stiff when its fastest decay rate exceeds this many times its
#: fastest oscillation (explicit methods would be limited by stability, not accuracy)
STIFFNESS_RATIO = 30.0
#: the planar run's result type under its earlier name
Trajectory = Run
#: where the runs of scene kinds with their own run code live (imported when a scene uses them)
RUNNERS = {"book": ("stand.integrate.book_run:run_book", "ch. 6, 7, paper 001, thesis 002")}


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


def generic_stiffness(model) -> float:
    """:func:`stiffness` for the generic kernel: the fastest weight drag rate H_j / J_j and
    the structure's fastest damping rate against its fastest frequency (natural frequencies
    at rest, the programme's top speed), in units of omega_ref."""
    rot = model.rotor
    rates = [0.0]
    if model.nw:
        rates.append(float(np.max(model.wt[:, 4] / model.wt[:, 3])))
    ev = np.linalg.eigvals(np.linalg.solve(rot.M, rot.D)) if rot.n else np.zeros(0)
    if ev.size:
        rates.append(float(np.max(np.abs(ev))))
    wn = rot.natural_frequencies(0.0)
    speed = max([1.0] + [float(np.max(np.abs(model.prog[:, 1])))]
                + ([float(np.max(wn)) / model.omega_ref] if wn.size else []))
    return max(rates) / model.omega_ref / speed


def choose_method(model: PlanarModel, requested: str) -> tuple[str, float, str]:
    ratio = stiffness(model) if isinstance(model, PlanarModel) else generic_stiffness(model)
    if requested != "auto":
        return requested, ratio, "requested"
    if ratio > STIFFNESS_RATIO:
        return "Radau", ratio, f"stiff: fastest decay rate / fastest frequency = {ratio:.3g} > {STIFFNESS_RATIO:g}"
    return "DOP853", ratio, f"non-stiff: fastest decay rate / fastest frequency = {ratio:.3g} <= {STIFFNESS_RATIO:g}"


def simulate(scene: Scene, method: str | None = None, rtol: float | None = None,
             atol: float | None = None, progress: bool = False,
             extra_times=None, checkpoint=None, checkpoint_steps: int = CHUNK_STEPS,
             kernel: str = "auto", planes_only: bool = False) -> Run:
    """Integrate a scene (any structure, any weights).

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
    kernel : {"auto", "planar", "generic"}
        The planar rotor runs on its own kernel by default; ``"generic"`` runs it
        through the generic structure + weights kernel (the other structures'
        path; used to check that both agree).  A planar scene with what the planar
        kernel does not have (:attr:`stand.scene.model.Scene.generic_kernel`: body weights,
        dry friction) always runs on the generic kernel (``"planar"`` is refused).
    planes_only : bool
        Return ``(planes, stats)``: every plane's (x, y) [m] at ``extra_times``, no Run (a fit).

    Returns
    -------
    Run
        ``stats.status`` is 0 on success, negative on failure (non-finite state,
        step size collapse, step budget); what was computed until then is kept.
    """
    run = scene.run
    method = method or run.method
    if method not in METHODS:
        raise SceneError(f"run.method = {method!r}: must be one of {', '.join(METHODS)}")
    if kernel not in ("auto", "planar", "generic"):
        raise ValueError(f"kernel = {kernel!r}: one of auto, planar, generic")
    rtol = run.rtol if rtol is None else rtol
    atol = run.atol if atol is None else atol
    if scene.kind == "book":
        run_book = resolve(RUNNERS, "book", "scene.kind", "scene kind")
        return run_book(scene, method=method, rtol=rtol, atol=atol)
    if scene.generic_kernel or kernel == "generic":
        if kernel == "planar" and scene.kind == "planar":
            raise SceneError(f'kernel = "planar": {scene.generic_kernel} run on the generic kernel')
        return _simulate_generic(scene, method, rtol, atol, progress, extra_times, checkpoint,
                                 checkpoint_steps, planes_only)
    model = build_planar_model(scene)
    return _integrated(scene, model, initial_state(scene, model), _trajectory, method, rtol, atol,
                       progress, extra_times, checkpoint, checkpoint_steps, planes_only)


def _integrated(scene, model, y0, answer, method, rtol, atol, progress, extra_times, checkpoint,
                checkpoint_steps, planes_only=False):
    """Integrate a built ``model`` (planar or generic kernel) from ``y0`` over the scene's run,
    sampled at its rate and at ``extra_times`` [s]; ``answer(scene, model, states, tau, stats)``
    makes the Run (of the extra times: ``.extra``; ``planes_only``: ``(planes, stats)`` of them)."""
    run = scene.run
    method, ratio, reason = choose_method(model, method)
    if method == "numpy-DOP853" and not isinstance(model, PlanarModel):
        raise SceneError("run.method = \"numpy-DOP853\": the pure-numpy reference path exists for "
                         "the planar rotor only; use DOP853, Radau, BDF or LSODA")
    w = model.omega_1
    ts_rec = sample_times(run.duration, run.sample_rate) * w
    ts, rec_idx, ex_idx = merge_times(ts_rec, extra_times, run.duration, w)
    out = np.full((ts.size, model.size), np.nan)
    out[0] = y0
    stats = SolverStats(method=method, rtol=rtol, atol=atol, stiffness_ratio=ratio,
                        method_reason=reason)
    k = integrate_model(scene, model, y0, run.duration * w, ts, out, stats, method, progress,
                        checkpoint, checkpoint_steps)
    if planes_only:
        y = out[ex_idx[ex_idx < k]]
        if isinstance(model, PlanarModel):
            return {"balancer": y[:, :2] * model.length}, stats
        q = y[:, :model.n] * model.scale                # as stand.integrate.coupled.samples_si
        return {p: q @ model.rotor.planes[p].T for p in model.plane_names}, stats
    if ex_idx is None:
        return answer(scene, model, out[:k], ts[:k], stats)
    r, e = rec_idx[rec_idx < k], ex_idx[ex_idx < k]
    res = answer(scene, model, out[r], ts[r], stats)
    res.extra = answer(scene, model, out[e], ts[e], stats)
    return res


def auto_method(scene: Scene) -> str:
    """The method ``run.method = "auto"`` picks for ``scene`` (DOP853, or Radau when stiff)."""
    if scene.kind == "book":
        return "DOP853"
    if scene.kind == "planar" and not scene.generic_kernel:
        return choose_method(build_planar_model(scene), "auto")[0]
    return choose_method(_generic_model(scene, scene.linear_rotor()), "auto")[0]


def _generic_model(scene, rotor):
    """The generic kernel's model of a scene's ``rotor`` (its LinearRotor) with its weights."""
    from stand.integrate.coupled import build_model

    d = scene.drive
    torque = d.kind == "torque"
    return build_model(rotor, scene.weights, d if torque else d.programme, bodies=scene.bodies,
                       inertia=scene.rotor.inertia_about_shaft
                       if torque and scene.kind == "planar" else None)


def _simulate_generic(scene, method, rtol, atol, progress, extra_times, checkpoint,
                      checkpoint_steps, planes_only=False) -> Run:
    """Any LinearRotor with its weights (stand.model.rotors.coupled_kernel) -> Run."""
    from stand.integrate.coupled import initial_state as generic_initial

    torque = scene.drive.kind == "torque"
    blows = [p for p in scene.perturbations if p.kind == "impulse"]
    if len(blows) != len(scene.perturbations):
        raise SceneError("kernel = \"generic\": of the perturbations the generic kernel takes "
                         "the blows to the housing (impact) only; an unbalance change or a side "
                         "pressure runs on the planar kernel")
    if scene.kind == "planar":
        if not torque and scene.drive.coast_down_start is not None:
            raise SceneError("kernel = \"generic\": no exponential coast-down on the generic kernel")
        if torque and scene.rotor.inertia_about_shaft is None:
            raise SceneError("drive.type = \"torque\": rotor.inertia is required")
    rotor = scene.linear_rotor()
    try:
        model = _generic_model(scene, rotor)
    except ValueError as exc:
        raise SceneError(str(exc)) from None
    if blows:
        model = _with_blows(model, scene, blows)
    if not torque and scene.drive.initial_angle:
        model.prog[:, 2] += scene.drive.initial_angle     # the programme's angle column
    q0 = qd0 = None
    ini = scene.initial
    if scene.kind == "planar":
        q0 = [ini.x, ini.y]
        qd0 = [ini.vx, ini.vy]
    elif any((ini.x, ini.y, ini.vx, ini.vy)):
        # the main plane's displacement and velocity: the least-norm coordinates giving them
        Tp = np.linalg.pinv(rotor.planes[scene.main_plane])
        q0, qd0 = Tp @ [ini.x, ini.y], Tp @ [ini.vx, ini.vy]
    return _integrated(scene, model, generic_initial(model, scene.weights, q0, qd0), generic_run, method,
                       rtol, atol, progress, extra_times, checkpoint, checkpoint_steps, planes_only)


def _with_blows(model, scene, blows):
    """The model with the blows to the housing (table 4.6) as jumps of its scaled state: the
    main plane's velocity jumps by (velocity_x, velocity_y) [m/s], carried by the least-norm
    coordinate rates."""
    import dataclasses

    T = model.rotor.planes[scene.main_plane]
    n, nw = model.n, model.nw
    rows = []
    for b in blows:
        row = np.zeros(1 + model.size)
        row[0] = b.start * model.omega_1
        dqd = np.linalg.pinv(T) @ [b.velocity_x, b.velocity_y]
        row[1 + n + nw:1 + 2 * n + nw] = dqd / (model.scale * model.omega_ref)
        rows.append(row)
    m = dataclasses.replace(model)
    object.__setattr__(m, "impulses", np.array(rows))
    return m


def _trajectory(scene: Scene, model: PlanarModel, out: np.ndarray, tau: np.ndarray,
                stats: SolverStats) -> Run:
    nq, n, L, w1 = model.nq, model.n, model.length, model.omega_1
    phi, R = model.rotor(tau, out)
    phi = np.asarray(phi, float).copy()
    R = np.asarray(R, float)
    alpha = out[:, 2:2 + n]
    dalpha = out[:, nq + 2:nq + 2 + n]
    names, wplanes = weight_names(scene.weights)
    weights = {nm: {"angle": phi + alpha[:, j], "speed": (R + dalpha[:, j]) * w1}
               for j, nm in enumerate(names)}
    return Run(t=tau / w1, planes={"balancer": out[:, :2] * L}, main_plane="balancer",
               rotor_angle=phi, rotor_speed=R * w1, weights=weights,
               weight_planes=dict(zip(names, wplanes)), stats=stats, scene=scene, state=out)
