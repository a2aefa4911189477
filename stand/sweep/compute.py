"""Compute a chunk of sweep points on a worker: the point's scene, its parameters
(``p.*``), the theory (``theory.*``, :mod:`.theory_points`) and the simulation
(``sim.*``), for every scene kind.

``p.*`` by scene kind:

* planar rotor: the book's dimensionless parameters (5.12)-(5.14), (5.88),
  ``p.R`` = operating speed / omega_1, ``p.f0_hz`` = omega_1 / 2 pi;
* ``[structure]``: ``p.n`` (weights), ``p.e0`` (|the rotor's static unbalance, the
  vector sum over all its planes| / the capacity of all its weights), ``p.f0_hz`` =
  the lowest natural frequency at rest with the weights locked, ``p.R`` = operating
  speed / (2 pi ``p.f0_hz``); Rt, h, H NaN;
* ``[weight_model]``: ``p.n`` only (the model's parameters are its own).

Body weights (two-axis pendulum, coupled pair, damper, liquids) count as
weights: ``p.n`` counts them and ``p.e0`` divides the rotor's static unbalance by
the capacity of all its weights (balls ``sum m l``, bodies
:attr:`~stand.model.rotors.bodies.TiltingWeight.capacity` ...).  A scene with body
weights is classified by :func:`_body_regime` and gets the structure theory
(natural frequencies, critical speeds) whatever its rotor.

A point that fails gets ``status = "error"`` and the message; it never stops
the chunk.

"Balanced" (``sim.regime`` main) of a rotor with several planes is the whole rotor's
balance: its static residual (and couple residual where it has one) against the
capacity of all its weights, with the planar rule's threshold ``balance_tol``
(:func:`_balance`); never a plane alone (the grinding and spatial rotors carry their
unbalance in a plane of its own, the balls in theirs).
"""
from __future__ import annotations

import math
import time
import warnings

import numpy as np

from stand.io.executor import error_text
from stand.integrate.result import whirl_about_centre
from stand.sweep.keys import RATIO_KEYS, SPECIAL_KEYS, point_scene_dict, with_speed
from stand.sweep.theory_points import planar_theory_rows, structure_theory_rows

__all__ = ["compute_chunk", "point_parameters"]

TWO_PI = 2.0 * math.pi


# ---------------------------------------------------------------- parameters
def _reference_frequency(scene) -> float:
    """omega_ref [rad/s]: omega_1 of the planar rotor; the lowest natural frequency at
    rest (weights locked) of a family structure; NaN for a book model."""
    if scene.kind == "planar":
        return scene.natural_frequency
    if scene.kind == "book":
        return math.nan
    from stand.model.rotors.coupled_kernel import with_locked_weights

    wn = with_locked_weights(scene.linear_rotor(), scene.weights).natural_frequencies(0.0)
    wn = np.asarray(wn, float)
    wn = wn[np.isfinite(wn) & (wn > 0)]
    return float(wn.min()) if wn.size else math.nan


def _operating_R(scene, w_ref: float) -> float:
    """The held speed in units of ``w_ref`` (NaN without one)."""
    from stand.theories.planar.speedmap import _operating_speed

    if scene.drive is None or not math.isfinite(w_ref):
        return math.nan
    d0 = scene.drive
    if d0.kind == "torque" and d0.model == "constant":
        return d0.torque / d0.rotor_drag / w_ref if d0.rotor_drag > 0 else math.nan
    return _operating_speed(scene) / w_ref


def _weight_planes(scene) -> list:
    """The planes that carry weights (balls or bodies), in scene order."""
    return list(dict.fromkeys([w.plane for w in scene.weights] + [pb.plane for pb in scene.bodies]))


def _rotor_e0(scene) -> float:
    """|static unbalance of the rotor| / capacity of all its weights: the vector sum of the
    rotor's unbalances over every plane [kg m] (the balls' plane or one of its own) over
    :meth:`Scene.weights_capacity` (structure scenes; any scene with body weights).  A planar
    rotor has one plane: its own unbalance over its weights' capacity."""
    S = scene.weights_capacity()
    U = sum(u.s * complex(math.cos(u.angle), math.sin(u.angle))
            for u in scene.linear_rotor().unbalances)
    return abs(U) / S if S > 0 else math.nan


def point_parameters(scene) -> dict:
    """The ``p.*`` columns of a point's scene (module notes).

    Parameters
    ----------
    scene : stand.scene.model.Scene

    Returns
    -------
    dict
    """
    nan = math.nan
    if scene.kind == "planar":
        from stand.scene.dimensionless import dimensionless

        p = dimensionless(scene)
        H = p.H_x if p.H_x == p.H_y else 0.5 * (p.H_x + p.H_y)
        out = {"p.n": p.n, "p.Rt": p.Rt, "p.h": float(p.h[0]) if p.n else nan, "p.H": H,
               "p.e0": p.e0, "p.R": _operating_R(scene, p.omega_1), "p.f0_hz": p.omega_1 / TWO_PI}
        if scene.bodies:
            out.update({"p.n": p.n + len(scene.bodies), "p.e0": _rotor_e0(scene)})
        return out
    out = {"p.n": scene.n_weights + len(scene.bodies), "p.Rt": nan, "p.h": nan, "p.H": nan,
           "p.e0": nan, "p.R": nan, "p.f0_hz": nan}
    if scene.kind == "rotor":
        w = _reference_frequency(scene)
        out.update({"p.e0": _rotor_e0(scene), "p.R": _operating_R(scene, w),
                    "p.f0_hz": w / TWO_PI})
    return out


# ---------------------------------------------------------------- simulation
def _balance(run, opts: dict) -> tuple:
    """``(sim.residual, balanced)`` of a run of a rotor of the family or with body weights.

    "Balanced" is the rotor's balance, not a plane's: the weights cancel the rotor's
    unbalance wherever it sits (in the balls' plane or a plane of its own).  With
    ``tol = balance_tol`` (the planar rule's threshold, :func:`stand.analysis.regime.classify`:
    a fraction of the capacity) and S the capacity of all the weights, every plane:

    * static: the static residual ``U_s = sum_p U_p`` [kg m] at the run's end
      (:func:`stand.integrate.residual.static_residual`) has ``|U_s| / S`` within ``tol``
      of its target, 0, or ``e0 - 1`` beyond capacity (``e0`` = |the rotor's static
      unbalance| / S, :func:`_rotor_e0`: the weights then all lean against it);
    * couple, where the rotor has one (:func:`stand.integrate.residual.couple_residual`
      not None) and the weights lie in at least two axial positions (one balancer plane
      applies no couple: its balanced motion is the static balance): ``|U_c| < tol S L``
      [kg m^2], L the axial span of the weights' planes (``U_c / L``: the pair of opposite
      unbalances at the span's ends that the weights must cancel).  Beyond capacity only
      the static residual is checked.

    One plane (a planar rotor with bodies; unbalance and weights in one plane) reduces to
    the planar rule.  ``sim.residual`` = ``|U_s| / S``; NaN and not balanced when the run
    cannot say.
    """
    from stand.integrate.residual import couple_residual, plane_positions, plane_residuals

    sc = run.scene
    tol = opts.get("balance_tol", 1e-2)
    S, e0 = sc.weights_capacity(), _rotor_e0(sc)
    U = plane_residuals(run, slice(-1, None))     # static residual: their sum
    if not U or not S > 0:
        return math.nan, False
    psi = float(abs(np.asarray(sum(U.values()))[-1])) / S
    balanced = abs(psi - (e0 - 1.0 if e0 > 1 else 0.0)) < tol
    if balanced and not e0 > 1:     # positions of the residual's planes, the weights' among them
        z = plane_positions(sc, U)
        zw = [z[p] for p in _weight_planes(sc) if p in z] if z else []
        span = (max(zw) - min(zw)) if zw else 0.0
        Uc = couple_residual(run, slice(-1, None), positions=z) if span > 0 else None
        if Uc is not None:
            balanced = float(abs(np.asarray(Uc)[-1])) < tol * S * span
    return psi, bool(balanced)


def _structure_regime(run, opts: dict, w_ref: float) -> dict:
    """Regime of a ``[structure]`` run, :func:`dsp.regime.motion_regime` on its mean speeds;
    balanced and ``sim.residual``: the whole rotor's static (and couple) residual against
    the capacity of all its weights (:func:`_balance`)."""
    from dsp.regime import motion_regime

    from stand.analysis.regime import QP_SPREAD_TOL

    sc = run.scene
    window = opts.get("window", 0.2)
    sel = run.t >= run.t[0] + (1 - window) * (run.t[-1] - run.t[0])
    rotor = float(np.mean(run.rotor_speed[sel]))
    out = {"sim.rotor_speed_R": rotor / w_ref}
    if not sc.n_weights:
        return {**out, "sim.regime": "no weights", "sim.residual": math.nan, "sim.spread_rad": 0.0}
    ws = np.mean(run.weight_speed[sel], axis=0)
    rel = run.weight_angle[sel] - run.rotor_angle[sel, None]
    residual, balanced = _balance(run, opts)
    name = motion_regime(rotor, ws - rotor, balanced, sync_tol=opts.get("sync_tol", 1e-3),
                         spread_tol=QP_SPREAD_TOL)
    return {**out, "sim.regime": name, "sim.residual": residual,
            "sim.spread_rad": float(np.max(np.ptp(rel, axis=0)))}


def _body_slips(run, sel, rotor: float) -> list:
    """Mean speed relative to the rotor [rad/s] over ``sel`` of every weight that has an
    azimuth: balls, the tilting weights (``speed``) and the damper (rate of ``angle``);
    a liquid has none (its centre of mass follows the shaft)."""
    slips = []
    t = run.t[sel]
    for name, ch in run.weights.items():
        if "tilt" in ch and "n_z" in ch:          # damper: the azimuth of its direction n
            if len(t) > 1 and t[-1] > t[0]:
                a = np.unwrap(np.asarray(ch["angle"])[sel])
                slips.append(float((a[-1] - a[0]) / (t[-1] - t[0])) - rotor)
        elif "speed" in ch:                        # balls, two-axis pendulum, coupled pair
            slips.append(float(np.mean(np.asarray(ch["speed"])[sel])) - rotor)
    return slips


def _body_regime(run, opts: dict, w_ref: float) -> dict:
    """Regime of a run with body weights (any rotor).

    Synchronous (every weight with an azimuth within ``sync_tol`` of the rotor speed)
    and steady (the residual unbalance of every plane with weights, truth in the rotor
    frame, moves by less than ``balance_tol`` x its capacity over the window):
    ``"main"`` when balanced (the whole rotor, :func:`_balance`), else ``"steady"`` -- a
    synchronous motion that leaves a residual: the
    main motion of a device that cannot balance fully (a pendulum against gravity, a
    liquid, whose correction follows the deflection) or a side motion, which the run
    alone does not tell apart.  Weights slipping back together: ``"quasi-periodic"``;
    otherwise ``"transient"``.  ``sim.residual``: the final |static residual| / S (all planes).
    """
    from dsp.regime import motion_regime

    from stand.analysis.regime import QP_SPREAD_TOL

    sc = run.scene
    window = opts.get("window", 0.2)
    tol = opts.get("balance_tol", 1e-2)
    sel = run.t >= run.t[0] + (1 - window) * (run.t[-1] - run.t[0])
    rotor = float(np.mean(run.rotor_speed[sel]))
    planes = _weight_planes(sc)
    residual, balanced = _balance(run, opts)
    steady = True
    for plane in planes:
        S = sc.weights_capacity(plane)
        U = np.asarray(run.truth[f"residual/{plane}"][0])
        move = float(np.max(np.hypot(*(U[sel] - U[-1]).T))) / S if np.any(sel) else 0.0
        steady &= move < tol
    slips = _body_slips(run, sel, rotor)
    name = motion_regime(rotor, slips, balanced, sync_tol=opts.get("sync_tol", 1e-3),
                         spread_tol=QP_SPREAD_TOL)
    if name in ("main", "side"):
        name = "transient" if not steady else ("main" if name == "main" else "steady")
    out = {"sim.rotor_speed_R": rotor / w_ref, "sim.regime": name, "sim.residual": residual}
    rel = [np.ptp(np.asarray(ch["angle"])[sel] - run.rotor_angle[sel])
           for ch in run.weights.values() if "angle" in ch and np.any(sel)]
    out["sim.spread_rad"] = float(max(rel)) if rel else 0.0
    return out


def _simulate_row(row: dict, scene, opts: dict) -> None:
    """The ``sim.*`` columns: the run, its regime (planar: :func:`stand.analysis.regime.classify`;
    structure: :func:`_structure_regime`; body weights: :func:`_body_regime`; book model:
    not classified) and solver stats."""
    from stand.integrate.simulate import simulate

    t0 = time.perf_counter()
    run = simulate(scene, method=opts.get("method"))
    window = opts.get("window", 0.2)
    if scene.kind in ("planar", "rotor") and scene.bodies:
        row.update(_body_regime(run, opts, TWO_PI * row["p.f0_hz"]))
    elif scene.kind == "planar":
        from stand.analysis.regime import classify

        reg = classify(run, window=window, sync_tol=opts.get("sync_tol", 1e-3),
                       balance_tol=opts.get("balance_tol", 1e-2))
        row.update({"sim.regime": reg.name, "sim.residual": float(reg.residual),
                    "sim.rotor_speed_R": float(reg.rotor_speed), "sim.spread_rad": float(reg.spread)})
    elif scene.kind == "rotor":
        row.update(_structure_regime(run, opts, TWO_PI * row["p.f0_hz"]))
    sel = run.t >= run.t[0] + (1 - window) * (run.t[-1] - run.t[0])
    # about the window's mean position: a static offset (gravity sag) is not whirl
    r, _ = whirl_about_centre(run.x[sel], run.y[sel])
    row.update({"sim.whirl_radius_m": float(np.mean(r)),
                "sim.success": bool(run.stats.success),
                # the solver's message, then the run's notes (e.g. a liquid's free surface that
                # touched the chamber wall: outside the model)
                "sim.message": " | note: ".join((run.stats.message,) + tuple(run.notes or ())),
                "sim.nfev": int(run.stats.nfev), "sim.wall_s": time.perf_counter() - t0})


# ---------------------------------------------------------------- a chunk
def _point_scene(payload: dict, vals, speed: list, cache: dict):
    """(scene, ``p.*`` columns) of one point.  Theory-only sweeps with a speed axis parse
    the scene of the non-speed inputs once (``cache``) and apply the speed to the
    validated drive (the same scaling as :func:`point_scene_dict`)."""
    from stand.scene.parse import parse

    keys, base = payload["keys"], payload["base"]
    if not speed:
        sc = parse(point_scene_dict(base, keys, vals))
        return sc, point_parameters(sc)
    j = speed[0]
    other = tuple(v for i, v in enumerate(vals) if i != j)
    if other not in cache:
        try:
            ks = [k for i, k in enumerate(keys) if i != j]
            s0 = parse(point_scene_dict(base, ks, other))
            cache[other] = (s0, point_parameters(s0), _reference_frequency(s0))
        except Exception as exc:
            cache[other] = exc
    got = cache[other]
    if isinstance(got, Exception):
        raise got
    s0, params, w_ref = got
    sc = with_speed(s0, keys[j], float(vals[j]), w_ref if keys[j] in RATIO_KEYS else None)
    return sc, {**params, "p.R": _operating_R(sc, w_ref)}


def compute_chunk(payload: dict, indices: list, ids: list, points: list) -> list:
    """Compute one chunk of points; runs on a worker (local process or Dask).

    Parameters
    ----------
    payload : dict
        :meth:`SweepSpec.to_payload`: plain data only (base scene document,
        axis keys, compute list, options).
    indices : list of int
        Point indices (row order of the final table).
    ids : list of str
        Point ids.
    points : list of list of float
        Input values, one list per point, in the order of ``payload["keys"]``.

    Returns
    -------
    list of dict
        One row per point (see :data:`stand.sweep.schema.RESULT_SCHEMA`);
        failures are rows with ``status = "error"``.
    """
    keys, compute = payload["keys"], payload["compute"]
    rows, scenes = [], []
    t_start = time.perf_counter()
    speed = [j for j, k in enumerate(keys) if k in SPECIAL_KEYS] if compute == ["theory"] else []
    cache: dict = {}
    for idx, pid, vals in zip(indices, ids, points):
        row = {"point_index": int(idx), "point_id": pid, "status": "ok", "error": ""}
        row.update({k: float(v) for k, v in zip(keys, vals)})
        sc = None
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                sc, params = _point_scene(payload, vals, speed, cache)
            row.update(params)
        except Exception as exc:
            row["status"], row["error"] = "error", error_text(exc)
        rows.append(row)
        scenes.append(sc)
    t_setup = (time.perf_counter() - t_start) / max(len(rows), 1)
    shared = [t_setup] * len(rows)
    if "theory" in compute:
        t0 = time.perf_counter()
        by_kind = {"planar": planar_theory_rows, "rotor": structure_theory_rows}
        for kind, fill in by_kind.items():
            # body weights: the structure theory (the chapter-5 theory is that of balls)
            sel = [i for i, sc in enumerate(scenes) if sc is not None and
                   ("rotor" if sc.bodies else sc.kind) == kind]
            if sel:
                fill([rows[i] for i in sel], [scenes[i] for i in sel], payload.get("theory", {}))
        dt = (time.perf_counter() - t0) / max(len(rows), 1)
        shared = [s + dt for s in shared]
    for row, sc, s in zip(rows, scenes, shared):
        t0 = time.perf_counter()
        if "simulate" in compute and row["status"] == "ok":
            try:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    _simulate_row(row, sc, payload.get("simulate", {}))
            except Exception as exc:
                row["status"], row["error"] = "error", error_text(exc)
        row["wall_time_s"] = s + time.perf_counter() - t0
    return rows
