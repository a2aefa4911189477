"""``stand fit``: the scene's free values by simulation-based nonlinear least squares on the
recorded channels.

The method (issue 39 item 3):

1. **The record and its drive** (:mod:`stand.fitting.record`): the channels ``stand analyze``
   reads, the rotor angle of the record's keyphasor / encoder / tachometer as a speed
   programme, the simulation starting at the record's first sample.
2. **The objective** (:mod:`stand.fitting.objective`, :mod:`stand.fitting.linear`): the recorded
   ``x + i y`` minus the simulated one, less what is linear in its coefficients (the probes'
   offset and runout, the rotor angle's own error with its prior), scaled by the noise.
3. **Start values**: the template's, and -- where the rotor's own values are free -- those of
   the rigid-rotor fit ``stand analyze`` makes (:func:`dsp.response_fit.fit_unbalance_response`)
   over the first stretch; a free unbalance angle without that start is tried at four
   quarters.  The best of the starts on the first stretch wins (multi-start).
4. **Continuation over the record**: trust-region least squares
   (:func:`scipy.optimize.least_squares`, ``trf`` with the bounds) on the record up to past
   the first resonance, then on two thirds, then on all of it, each from the last.
5. **Uncertainty** (:mod:`stand.fitting.uncertainty`): covariance from the projected Jacobian --
   white and batch-means sandwich, the larger --, the curvature checked along each value's
   profile, and an identifiability verdict per value.
"""
from __future__ import annotations

import copy
import math
import sys
import time
from dataclasses import replace
from pathlib import Path
from typing import Optional

import numpy as np

from stand.fitting.linear import LinearPart, angle_modes
from stand.fitting.model_run import NUISANCE, NUISANCE_UNITS, Setup
from stand.fitting.objective import Objective, executor_for, robust_sigma
from stand.fitting.paths import FitError, parse_free, scene_with, set_value
from stand.fitting.record import fit_record

__all__ = ["fit_scene"]

TWO_PI = 2.0 * math.pi


def _template(scene):
    """``(doc, text, stem, label)`` of a scene given as a path, TOML text or a Scene."""
    from stand.io.tomlfile import read_toml, tomllib

    if hasattr(scene, "text") and hasattr(scene, "kind"):
        if not scene.text:
            raise FitError("the scene has no TOML text (made in Python): give the scene file")
        return tomllib.loads(scene.text), scene.text, scene.name, f"<scene {scene.name}>"
    doc, text, label = read_toml(scene, "scene file")
    stem = Path(scene).stem if label else ""
    return doc, text, stem, (str(scene) if label else "<scene text>")


def _say(progress, msg: str) -> None:
    if progress:
        (progress if callable(progress) else lambda s: print(s, file=sys.stderr, flush=True))(msg)


def _stage_ends(rec, f0_hz: float) -> list:
    """Sample counts of the continuation's stretches: just past the first resonance (1.2 f0,
    where the scans run), past it (1.5 f0 and half a second), two thirds, all."""
    n = rec.t.size
    w = rec.speed()
    dt = max(float(np.median(np.diff(rec.t))), 1e-9)
    marks = []
    if w is not None and f0_hz > 0:
        for ratio, extra in ((1.2, 0.0), (1.5, 0.5)):
            past = np.flatnonzero(np.abs(w) > TWO_PI * ratio * f0_hz)
            if past.size:
                marks.append(int(past[0]) + int(extra / dt))
    if not marks:
        marks = [n // 6, n // 3]
    ends = [min(max(m, n // 10, 64), n) for m in marks]
    last = ends[-1]
    if last < 0.8 * n:
        ends.append((last + n) // 2)
    ends.append(n)
    return sorted(set(ends))


def _natural_frequency_hz(scene) -> float:
    try:
        if scene.kind == "planar":
            return scene.natural_frequency / TWO_PI
        wn = scene.linear_rotor().natural_frequencies(0.0)
        wn = wn[wn > 0]
        return float(np.min(wn)) / TWO_PI if wn.size else 0.0
    except Exception:            # a structure without one: no staging by resonance
        return 0.0


def _analyze_start(rec, scene, free, n) -> Optional[dict]:
    """Values of the rotor's free keys from the rigid-rotor fit over the first ``n`` samples
    (planar scene, displacement or its derivatives, a referenced angle)."""
    paths = {f.path for f in free}
    wanted = {"supports.stiffness", "supports.damping", "rotor.eccentricity",
              "rotor.unbalance_angle"} & paths
    if not wanted or scene.kind != "planar" or rec.angle is None or not rec.referenced:
        return None
    from dsp.errors import SignalError
    from dsp.response_fit import fit_unbalance_response

    a = rec.angle
    try:
        f = fit_unbalance_response(rec.t[:n], rec.z[:n], a.angle_rad[:n], a.speed_rad_s[:n],
                                   a.acceleration_rad_s2[:n], covariance=False,
                                   derivative=rec.order, tolerance=1e-8)
    except (SignalError, ValueError, np.linalg.LinAlgError):
        return None
    ms = scene.total_mass
    k = ms * (TWO_PI * f.natural_frequency_hz) ** 2
    # the fitted unbalance is the rotor's and the weights' at their start angles together
    # (they hardly move below the resonance): the rotor's own is what is left
    bal = scene.balancer
    u = ms * f.specific_unbalance_m * np.exp(1j * f.angle_rad)
    if bal.count:
        u -= complex(np.sum(bal.mass * bal.radius * np.exp(1j * np.asarray(bal.initial_angles))))
    out = {"supports.stiffness": k, "supports.damping": 2.0 * f.damping_ratio * math.sqrt(k * ms),
           "rotor.eccentricity": abs(u) / scene.rotor.mass,
           "rotor.unbalance_angle": math.degrees(np.angle(u))}
    return {p: v for p, v in out.items() if p in wanted and np.isfinite(v)}


def _cost(obj, theta, n) -> float:
    r = obj.residual(theta, n)[0]
    return float(r @ r)


def _batch_costs(obj, thetas, n) -> np.ndarray:
    """The costs of many parameter vectors on the first ``n`` samples (simulations together
    on the executor; a failed run costs infinity)."""
    outs = obj.simulate_many([(obj.setup, th, obj.end_time(n)) for th in thetas])
    lp = obj.linear(n)
    costs = np.full(len(thetas), np.inf)
    for i, m in enumerate(outs):
        m = np.asarray(m)[:n]
        if m.size == n and np.all(np.isfinite(m)):
            r = lp.solve(obj.z, m)[0]
            costs[i] = float(r @ r)
    return costs


def _weights_value(path: str) -> bool:
    """A value of the correction weights (``balancer.*``, ``weights[i].*``)."""
    return path.startswith("balancer.") or path.startswith("weights")


def _scan(obj, theta, free, n, lo, hi, sweeps: int = 2, points: int = 81):
    """Coordinate scans of the free values on the first ``n`` samples: each value in turn,
    the weights' first -- a factor 4 either side of a positive weights' value (a factor 2 for
    the others: a lab's first guess is 10-50 % off) on a log grid, the whole circle for an
    angle, +-3 scales otherwise -- with the others held, kept where the cost is lowest;
    ``sweeps`` rounds, the simulations of one scan together on the executor.  The
    weights' drag winds their phase at the resonance: the objective has valleys a few per
    cent wide in it, which a local method started 50 % off misses and a dense scan over the
    short first stretch finds (its valley there is the widest)."""
    theta = np.asarray(theta, float).copy()
    best = float(_batch_costs(obj, [theta], n)[0])
    # the weights' values first (their phase winds with them), then the rest over a factor 2
    order = sorted(range(len(free)), key=lambda i: not _weights_value(free[i].path))
    for _ in range(sweeps):
        moved = False
        for i in order:
            f = free[i]
            v = theta[i]
            wide = _weights_value(f.path)
            if f.angle:
                cand = v + np.linspace(-180.0, 180.0, 72, endpoint=False)
            elif f.lower >= 0.0 and v > 0:
                cand = v * (np.geomspace(0.25, 4.0, points) if wide else
                            np.geomspace(0.5, 2.0, points // 2 + 1))
            else:
                cand = v + f.scale * np.linspace(-3.0, 3.0, points)
            cand = np.unique(np.clip(cand, lo[i], hi[i]))
            trials = []
            for c in cand:
                th = theta.copy()
                th[i] = c
                trials.append(th)
            costs = _batch_costs(obj, trials, n)
            j = int(np.argmin(costs))
            if costs[j] < best - 1.0:           # by more than the noise moves it
                best, theta, moved = float(costs[j]), trials[j], True
        if not moved:
            break
    return theta


def _corner_costs(obj, theta, rec, setup, lp, trials):
    """The whole record's cost at ``theta`` with the keyphasor's corners at each of ``trials``
    (lists of times [s]; the angle's error modes left out: a comparison of corner places),
    the simulations together on the executor.  Returns ``(costs, records)``."""
    from stand.fitting.record import with_corners_at

    recs = [with_corners_at(rec, times) for times in trials]
    live = [i for i, r2 in enumerate(recs) if r2 is not None]
    end = float(setup.times[-1])
    outs = obj.simulate_many([(replace(setup, drive=recs[i].drive), theta, end) for i in live])
    costs = np.full(len(trials), np.inf)
    for i, m in zip(live, outs):
        r2 = recs[i]
        m = np.asarray(m)[:r2.t.size]
        if m.size == r2.t.size and np.all(np.isfinite(m)):
            lp2 = LinearPart(r2.phi(), lp.runout, None, lp.sigma)
            r = lp2.solve(r2.z, m)[0]
            costs[i] = float(r @ r) + _pulses_chi2(r2.angle)
    return costs, recs


def _pulses_chi2(angle) -> float:
    """chi^2 of a keyphasor angle's spline at its own pulses (their timing std as the angle's):
    what the pulses say of a corner's place, added to what the vibration says."""
    from scipy.interpolate import make_lsq_spline

    p, st = angle.pulses_s, angle.pulse_timing_std_s
    knots = getattr(angle.angle_error, "knots", None)
    if p is None or st is None or knots is None:
        return 0.0
    k = 2.0 * np.pi * np.arange(p.size)
    try:
        sp = make_lsq_spline(p, k, np.asarray(knots, float), k=3)
    except (ValueError, np.linalg.LinAlgError):
        return 0.0
    sig = np.maximum(np.abs(sp(p, 1)) * st, 1e-12)
    return float(np.sum(((k - sp(p)) / sig) ** 2))


def _place_corners(obj, theta, rec, setup, lp, progress):
    """Move each corner of the keyphasor angle's spline to where the record's vibration fits
    best (a scan of +-1 s in 0.1 s, then +-0.1 s in 0.01 s, at the fitted values); returns
    ``(record, setup, linear part)`` with the corners moved, or None when they stay."""
    from stand.fitting.record import corner_times

    if rec.angle is None or getattr(rec.angle, "pulses_s", None) is None:
        return None
    times = corner_times(rec.angle)
    if not times:
        return None
    _say(progress, "stand fit: placing the keyphasor angle's corner(s) at "
         + ", ".join(f"{c:.3f}" for c in times) + " s by the vibration")
    costs, recs = _corner_costs(obj, theta, rec, setup, lp, [list(times)])
    best, best_rec = float(costs[0]), recs[0]
    start = list(times)
    for i in range(len(times)):
        for half, step in ((1.0, 0.1), (0.1, 0.01)):
            trials = []
            for c in times[i] + np.arange(-half, half + 1e-9, step):
                trial = list(times)
                trial[i] = float(c)
                trials.append(trial)
            costs, recs = _corner_costs(obj, theta, rec, setup, lp, trials)
            j = int(np.argmin(costs))
            if costs[j] < best - 1.0:
                best, best_rec, times = float(costs[j]), recs[j], trials[j]
    if times == start or best_rec is None:
        return None
    best_rec.notes.append("keyphasor angle: corner(s) of the speed programme moved from "
                          + ", ".join(f"{a:.3f}" for a in start) + " s (the pulses' best) to "
                          + ", ".join(f"{b:.3f}" for b in times) + " s, where the vibration "
                          "fits best")
    return (best_rec, replace(setup, drive=best_rec.drive),
            LinearPart(best_rec.phi(), lp.runout, angle_modes(best_rec.angle, best_rec.t),
                       lp.sigma))


def fit_scene(scene, data, free, *, recording_map=None, workers: Optional[int] = None,
              scheduler=None, progress=None, runout: Optional[bool] = None,
              initial_state: Optional[bool] = None, max_nfev: int = 40,
              rtol: float = 1e-9):
    """Fit a scene's free values to a record (module docstring); see :func:`stand.fit`."""
    from scipy.optimize import least_squares

    from stand.fitting.compare import comparison
    from stand.fitting.result import Fit
    from stand.fitting.uncertainty import uncertainty
    from stand.scene.parse import parse

    wall0 = time.perf_counter()
    doc, text, stem, scene_label = _template(scene)
    free = parse_free(free, doc)
    try:
        template = parse(copy.deepcopy(doc), text=text, stem=stem)
    except Exception as exc:          # the template itself: the scene's own message
        raise FitError(f"{scene_label}: {exc}") from None
    rec = fit_record(data, recording_map)
    notes = list(rec.notes)
    if rec.angle is not None and not rec.referenced:
        notes.append("the speed channel has no reference mark: angles (the unbalance's, the "
                     "weights' start) are relative to an arbitrary origin")
    # the record's drive and where the simulation starts
    drive = rec.drive
    top = float(np.max(np.abs(drive.programme[:, 1]))) if drive is not None else 0.0
    start_speed = float(abs(drive.full()[0][0, 1])) if drive is not None else 0.0
    if initial_state is None:
        initial_state = drive is not None and start_speed > 0.1 * top
    lead_in = drive is not None and drive.lead > 0 and drive.rest_until > -drive.lead
    if initial_state:
        notes.append("the record starts with the rotor turning: the shaft's initial state is "
                     "fitted beside the scene values (initial.x, .y, .vx, .vy)")
    setup = Setup(doc=doc, stem=stem, paths=tuple(f.path for f in free),
                  times=rec.t - rec.t_start, drive=drive, order=rec.order, plane=rec.plane,
                  rtol=rtol, atol=rtol * 1e-2, nuisance=bool(initial_state),
                  lead_in=bool(lead_in))
    w = rec.speed()
    sweep = w is not None and np.max(np.abs(w)) > 1.5 * max(np.min(np.abs(w)), 1e-9)
    if runout is None:
        runout = rec.order == 0 and rec.referenced and sweep and rec.runout_m != 0.0
    modes = angle_modes(rec.angle, rec.t)
    sigma0 = robust_sigma(rec.z, 4)
    floor = 1e-9 * float(np.max(np.abs(rec.z - np.mean(rec.z)))) or 1e-12
    lp = LinearPart(rec.phi(), runout, modes, max(sigma0, floor))
    # parameters: free values, then the initial state
    zmax = float(np.max(np.abs(rec.z - np.mean(rec.z)))) or 1.0
    f0 = _natural_frequency_hz(template)
    wref = TWO_PI * max(f0, 1.0)
    n4 = 4 if initial_state else 0
    scales = [f.scale for f in free] + [zmax, zmax, zmax * wref, zmax * wref][:n4]
    lo = [f.lower for f in free] + [-np.inf] * n4
    hi = [f.upper for f in free] + [np.inf] * n4
    start = [f.start for f in free] + [0.0] * n4
    if lead_in:          # where the lead-in starts from rest [s]
        scales.append(max(0.05 * drive.lead, 1e-3))
        lo.append(-10.0 * drive.lead)
        hi.append(drive.lead * (1.0 - 1e-6))
        start.append(min(drive.rest_until, 0.999 * drive.lead))
    scales, lo, hi = (np.asarray(v, float) for v in (scales, lo, hi))
    steps = 1e-5 * scales
    theta0 = np.asarray(start, float)
    ends = _stage_ends(rec, f0)
    log = {"evals": 0, "best": math.inf}

    def on_eval(theta, cost):
        log["evals"] += 1
        log["best"] = min(log["best"], cost)

    ex = executor_for(workers, scheduler, len(scales))
    obj = Objective(setup, rec.z, lambda n: lp, steps, ex, on_eval, record=rec)
    stages = []
    try:
        def solve(th0, n, nfev, label):
            x0 = (th0 - theta0) / scales
            xl, xh = (lo - theta0) / scales, (hi - theta0) / scales
            x0 = np.clip(x0, np.nextafter(xl, np.inf), np.nextafter(xh, -np.inf))
            it = {"k": 0}

            def fun(x):
                return obj.residual(theta0 + scales * x, n)[0]

            def jac(x):
                it["k"] += 1
                th = theta0 + scales * x
                r = obj.residual(th, n)[0]
                _say(progress, f"stand fit: {label}, iteration {it['k']}: cost {0.5 * r @ r:.6g}, "
                     + ", ".join(f"{f.path} = {v:.6g}" for f, v in zip(free, th)))
                return obj.jacobian(th, n) * scales

            # stop when a step lowers chi^2 by less than 0.01 (the cost is about n there):
            # the values then move by a tenth of their std at most
            sol = least_squares(fun, x0, jac=jac, bounds=(xl, xh), method="trf",
                                x_scale=1.0, ftol=max(5e-3 / n, 1e-12), xtol=1e-8,
                                gtol=1e-10, max_nfev=nfev)
            th = theta0 + scales * sol.x
            stages.append({"label": label, "samples": int(n), "end_s": float(rec.t[n - 1]),
                           "cost": float(2 * sol.cost), "iterations": int(sol.nfev),
                           "status": int(sol.status), "message": str(sol.message)})
            return th, float(2 * sol.cost)

        # 3. starts on the first stretches: the template's values and the rigid-rotor fit's,
        # scans around the better one (the weights' drag winds their phase at the resonance:
        # the objective has many valleys), then least squares from the best point
        n0 = ends[0]
        starts = [("template", theta0.copy())]
        an = _analyze_start(rec, template, free, ends[1] if len(ends) > 1 else n0)
        if an:
            th = theta0.copy()
            for i, f in enumerate(free):
                if f.path in an:
                    th[i] = min(max(an[f.path], f.lower), f.upper)
            starts.append(("rigid-rotor fit of the first stretch", th))
        cands = []
        for name, th in starts:          # each start scanned and fitted on the first stretch
            _say(progress, f"stand fit: scanning around the {name}'s values on the first "
                 f"{rec.t[n0 - 1] - rec.t[0]:.3g} s")
            th = _scan(obj, th, free, n0, lo, hi)
            th, cost = solve(th, n0, max_nfev, f"first stretch from the {name}")
            cands.append((th, cost, name))
        if len(cands) > 1 and len(ends) > 1:
            # the first stretch may not tell two valleys apart: each goes on to the second
            # stretch (angle modes left out), the better one there is kept
            n1 = ends[1]
            cands = [(*solve(th, n1, max(10, max_nfev // 2), f"second stretch from the {name}"),
                      name) for th, _, name in cands]
        theta, _, start_name = min(cands, key=lambda c: c[1])
        # the noise from the residual of the first stretch (differences: white part only)
        r, Q, coef, m = obj.residual(theta, n0)
        if coef is not None:
            e = rec.z[:n0] - lp.fitted_signal(m, coef)
            lp.sigma = max(robust_sigma(e, 1), floor)
        # a record that shows no motion above its noise: nothing to continue with (the
        # uncertainty step says so, value by value)
        n_all = rec.t.size
        still = lp.solve(rec.z, np.zeros(n_all, complex))[0]      # offset (and runout) only
        excess = float(still @ still) - 2.0 * n_all                # chi^2 beyond pure noise's
        stretches = ends[1:] if excess > 5.0 * math.sqrt(4.0 * n_all) + 2.0 * theta.size else []
        # 4. continuation, with the rotor angle's error modes (their sensitivities at the
        # stretch's start values)
        last = None                     # the whole record's cost, G as it stands
        for n in stretches:
            if lp.modes is not None:
                # over the whole record at once (kept while the values hardly move)
                if obj.angle_sensitivity(theta, n_all, scales):
                    _say(progress, f"stand fit: the model's sensitivity to the rotor angle's "
                         f"{lp.modes.count} error modes made")
            theta, cost = solve(theta, n, max_nfev, f"stretch to {rec.t[n - 1] - rec.t[0]:.3g} s")
            last = cost if n == rec.t.size else None
        n = rec.t.size
        # the keyphasor spline's corners where the vibration puts them (the pulses alone
        # leave a run-up's end uncertain by a good part of a second), then the record again
        moved = _place_corners(obj, theta, rec, setup, lp, progress)
        if moved is not None:
            kept = (rec, setup, lp, obj, theta)
            if last is None:             # no continuation over the whole record ran
                if lp.modes is not None:
                    obj.angle_sensitivity(theta, n)
                last = _cost(obj, theta, n)
            before = last
            rec, setup, lp = moved
            done = obj.simulations
            obj = Objective(setup, rec.z, lambda n_: lp, steps, ex, on_eval, record=rec)
            obj.simulations = done
            if lp.modes is not None:
                obj.angle_sensitivity(theta, n)
            after = _cost(obj, theta, n)
            if after < before:         # better with the error modes too: least squares there
                theta, after = solve(theta, n, max_nfev, "whole record, corners placed")
            if after < before:
                notes.append(rec.notes[-1])
            else:                      # the moved corner fits worse with its error modes: back
                rec, setup, lp, old_obj, theta = kept
                old_obj.simulations = obj.simulations
                obj = old_obj
        if lp.modes is not None:
            obj.angle_sensitivity(theta, n, scales)
        r, Q, coef, m = obj.residual(theta, n)
        if coef is None:
            raise FitError("the simulation with the fitted values stopped early; the record "
                           "is outside what the scene can reproduce (check the template)")
        e = rec.z - lp.fitted_signal(m, coef)
        lp.sigma = max(robust_sigma(e, 1), floor)
        obj._cache.clear()
        unc = uncertainty(obj, theta, scales, lo, hi, free, rec, lp, progress)
        for _ in range(2):        # the profile found a lower cost: not at the minimum yet
            if unc["better"] is None:
                break
            _say(progress, "stand fit: a lower cost beside the optimum; least squares again")
            theta, _ = solve(unc["better"][0], n, max_nfev, "polish on the whole record")
            if lp.modes is not None:
                obj.angle_sensitivity(theta, n, scales)
            unc = uncertainty(obj, theta, scales, lo, hi, free, rec, lp, progress)
        r, Q, coef, m = obj.residual(theta, n)
        e = rec.z - lp.fitted_signal(m, coef)
    finally:
        if ex is not None:
            ex.close()
    values = {}
    for f, v in zip(free, theta):
        d = unc["parameters"][f.path]
        if not d["identifiable"] and not math.isfinite(d["std"]):
            # the record says nothing of it: the template's value stays (scene and report)
            d["note"] += f"; kept at the template's {f.start:g} {f.unit} (the fit wandered to {v:.4g})"
            d["value"] = f.start
            v = f.start
        values[f.path] = float(v)
    fitted = scene_with(doc, values, stem)
    doc_out = copy.deepcopy(doc)
    for p, v in values.items():
        set_value(doc_out, p, v)
    nuis = {}
    if initial_state:
        nuis.update({k: {"value": float(v), "unit": u} for k, v, u in
                     zip(NUISANCE, theta[len(free):], NUISANCE_UNITS)})
    if lead_in:
        nuis["drive.rest_until"] = {"value": float(theta[-1] + rec.t_start), "unit": "s",
                                    "note": "the rotor starts from rest here (the stretch "
                                    "before the first keyphasor pulse)"}
    nuis["offset"] = {"value": [coef["offset"].real, coef["offset"].imag], "unit": rec.unit}
    if runout:
        nuis["runout"] = {"value": [coef["runout"].real, coef["runout"].imag], "unit": rec.unit}
    dphi = lp.angle_correction(coef, rec.t.size)
    if lp.modes is not None:
        nuis["rotor_angle_correction_rms"] = {"value": float(np.sqrt(np.mean(dphi ** 2))),
                                              "unit": "rad"}
    series = {"t": rec.t, "measured": rec.z, "model": lp.fitted_signal(m, coef),
              "simulated": m, "residual": e, "speed": rec.speed(), "angle_correction": dphi}
    cmp_rows = comparison(obj, theta, unc, rec, fitted, series, progress)
    doc_json = {
        "scene": scene_label, "data": rec.label,
        "parameters": unc["parameters"],
        "correlation": unc["correlation"],
        "nuisance": nuis,
        "fit": dict(unc["fit"], start=start_name, stages=stages,
                    simulations=int(obj.simulations), failed_simulations=int(obj.failed),
                    wall_time_s=time.perf_counter() - wall0, runout_fitted=bool(runout),
                    initial_state_fitted=bool(initial_state), quantity=rec.quantity,
                    rotor_angle=(rec.angle.source if rec.angle is not None else None),
                    angle_misfit_rad=rec.angle_misfit_rad),
        "comparison": cmp_rows,
        "notes": notes + unc["notes"],
    }
    return Fit(doc_json, scene=fitted, document=doc_out, template_text=text, series=series,
               values=values)
