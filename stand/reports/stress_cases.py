"""The case runners of ``stand stress``: one function per kind of the catalogue.

A runner ``(case, res) -> list`` builds the case's model from its validated
``params`` (:mod:`stand.reports.stress_catalogue`), runs it, fills the result
fields of ``res`` (:func:`outcome`: method and why, solver status, oracle,
error and its measure, conserved quantity and drift, details) and returns the
reasons it found the case outside the model's validity (empty when inside).
:data:`RUNNERS` maps each kind to its runner: the planar-rotor kinds are in
:mod:`stand.reports.stress_planar`, the scenes with body weights in
:mod:`stand.reports.stress_bodies`, the liquid float balancer (paper 001) and
the suspended platform (paper 004) here.  :func:`warm` compiles a case's
kernels before its timed region.

The kinds, checks and oracles are described in :mod:`stand.reports.stress`
and docs/reports_stress.md.  Units: SI, except the dimensionless kinds
(omega_1 = 1 rad/s, so t [s] = tau; lengths in units of r*).
"""
from __future__ import annotations

import math
import time
from typing import Callable

import numpy as np

from stand.integrate.runs import sample_times
from stand.reports.stress_bodies import kind_body_scene
from stand.reports.stress_catalogue import CatalogueError
from stand.reports.stress_planar import (PLANAR_KINDS, kind_dimensionless, kind_qp, kind_scene_file, rel_max,
                            warm_planar)

__all__ = ["RUNNERS", "outcome", "warm"]


# ------------------------------------------------------------------ helpers
def outcome(**kw) -> dict:
    """A case result with the runner's keys of ``CASE_SCHEMA`` (defaults filled in).

    Parameters
    ----------
    **kw
        Values that replace the defaults.

    Returns
    -------
    dict
        ``method``, ``solver_success``, ``error`` ... (see
        :data:`stand.reports.stress.CASE_SCHEMA`), ``checks`` (extra reasons to
        fail, removed by the pass rule) and ``details``.
    """
    base = dict(method="", method_reason="", solver_success=False, solver_message="",
                converged=False, oracle="", error=None, error_measure="", reference_error=None,
                conserved_quantity=None, drift=None, nfev=None, wall_time_s=0.0,
                outside_validity=None, checks=[], details={})
    base.update(kw)
    return base


# ------------------------------------------------------------------ kind: liquid_runup
def _liquid_scene(case, prm):
    """The case as a ``[weight_model]`` scene of the liquid float (paper 001): the one model
    (planar rotor x liquid float body, :mod:`stand.model.balancers.composition`)."""
    from stand.scene.model import BookModel, RunSettings, Scene, SpeedDrive

    p = case["params"]
    run = RunSettings(duration=float(p["t_end"]), sample_rate=float(p["sample_rate"]),
                      rtol=float(p["rtol"]), atol=float(p["rtol"]) * prm.e, method=p["method"])
    return Scene(drive=SpeedDrive(np.array([[0.0, prm.omega_0]])), run=run, name=case["name"],
                 structure=BookModel("liquid_float", prm, "paper 001", {}))


def _kind_liquid(case, res):
    from stand.integrate.book_run import run_book
    from stand.model.balancers.liquid_float import LiquidFloatParams
    from stand.model.balancers.runup_closed_form import free_whirl_amplitudes, runup_closed_form_state

    p = case["params"]
    try:
        prm = LiquidFloatParams(Omega_0=p["Omega_0"], psi=p["psi"], n=p["n"], e=p["e"],
                                omega_0=p["omega_0"], epsilon=0.5 * p["acceleration"])
    except ValueError as exc:
        raise CatalogueError(f"case {case['name']!r}: params: {exc}") from None
    scene = _liquid_scene(case, prm)
    n_samples = sample_times(p["t_end"], p["sample_rate"]).size
    # the state is in m and m/s: atol relative to the eccentricity, as the book's run had it
    # (atol = rtol e); the scenes' default 1e-12 m would be 1e-8 e and limit the error
    run = run_book(scene, method=p["method"], rtol=p["rtol"], atol=p["rtol"] * prm.e)
    Zs = run.planes["balancer"][:, 0] + 1j * run.planes["balancer"][:, 1]
    Zdot = run.coordinates["state/xi'"][0] + 1j * run.coordinates["state/eta'"][0]
    compiled = p["method"] == "DOP853"
    res.update(method=(f"{'compiled' if compiled else 'scipy'} {p['method']} (fixed frame: the one "
                       "model, planar rotor x liquid float body)"),
               method_reason=("the liquid float's run has no automatic choice: model M1 is linear "
                              f"and non-stiff (damping ratio {prm.zeta:.3g}), the explicit "
                              "8th-order method is used"),
               solver_success=bool(run.success and np.all(np.isfinite(Zs))
                                   and len(run.t) == n_samples),
               solver_message="reached the end" if len(run.t) == n_samples else "stopped early",
               nfev=int(run.stats.nfev), wall_time_s=float(run.stats.wall_time))
    res["details"]["frame"] = ("fixed (the one model runs in the fixed frame; the catalogue's "
                               f"frame = {p['frame']!r} named the book's form)")
    Z, Zd = runup_closed_form_state(prm, run.t)
    err = rel_max(Zs, Z)
    res.update(oracle=(f"closed-form run-up of model M1 (psi = {prm.psi:g}: Omega = Omega_0 sqrt(psi) = "
                       f"{prm.Omega:.4g} rad/s, {'Fresnel' if prm.n == 0 else 'Faddeeva'})"),
               error=err, error_measure="max |Z - Z_exact| / max |Z_exact| [-]", reference_error=0.0)
    res["details"].update(critical_speed_rad_s=prm.Omega,
                          final_speed_rad_s=float(run.rotor_speed[-1]),
                          revolutions=float(run.rotor_angle[-1] / (2 * math.pi)))
    if prm.n == 0:
        c_num = free_whirl_amplitudes(prm, run.t[-1:], Zs[-1:], Zdot[-1:])[0][0]
        c_ref = free_whirl_amplitudes(prm, run.t[-1:], Z[-1:], Zd[-1:])[0][0]
        res.update(conserved_quantity="free-whirl amplitude |c+| (undamped)",
                   drift=float((c_num - c_ref) / c_ref))
        res["_drift_checked"] = True
    invalid = []
    if run.rotor_speed[-1] < 1.5 * prm.Omega:
        invalid.append(f"the run ends at {run.rotor_speed[-1]:.4g} rad/s, before 1.5 x the critical speed "
                       f"{prm.Omega:.4g} rad/s: the passage is not completed")
    return invalid


# ------------------------------------------------------------------ kind: platform
def _kind_platform(case, res):
    from stand.integrate.coupled import PlaneWeights, simulate_coupled
    from stand.model.rotors.platform import platform_rotor
    from stand.scene.model import Balancer

    p, chk = case["params"], case["check"]
    rot = platform_rotor()
    w = p["speed"]
    u = rot.unbalances[0]
    atol = p["atol"] if p["atol"] is not None else p["rtol"] * 1e-2
    wn = rot.natural_frequencies(0.0)
    wn = wn[wn > 0]
    ratio = float((wn[-1] / wn[0]) ** 2)
    weights = []
    q0 = qd0 = None
    Q = None
    if chk == "steady_response":
        F = u.s * w * w * np.exp(1j * u.angle) * (rot.force_map(u.plane).T @ np.array([1.0, -1j]))
        Q = np.linalg.solve(rot.dynamic_stiffness(w), F)
        q0, qd0 = Q.real, (1j * w * Q).real
    else:
        m, l = p["ball_mass"], p["ball_radius"]
        b = Balancer(type="balls", mass=np.full(2, m), radius=np.full(2, l),
                     drag=np.full(2, p["ball_drag"]), inertia=np.full(2, m * l * l),
                     initial_angles=np.radians(p["initial_angles_deg"]), initial_speeds=np.zeros(2))
        weights = [PlaneWeights("balancer", b)]
    tic = time.perf_counter()
    run = simulate_coupled(rot, weights, [[0.0, w]], p["duration"], p["sample_rate"], rtol=p["rtol"],
                           atol=atol, q0=q0, qd0=qd0)
    wall = time.perf_counter() - tic
    st = run.stats
    res.update(method="DOP853 (compiled, simulate_coupled)",
               method_reason=(f"simulate_coupled integrates with the compiled explicit DOP853 only; "
                              f"stiffness ratio (w_max/w_min)^2 = {ratio:.3g} at rest, so the step is "
                              "bounded by stability at the fastest mode"),
               solver_success=bool(st["success"]), solver_message=str(st["message"]),
               nfev=int(st["nfev"]), wall_time_s=float(wall))
    res["details"].update(stiffness_ratio=ratio, n_steps=st["n_steps"], n_rejected=st["n_rejected"],
                          lowest_mode_rad_s=float(wn[0]), highest_mode_rad_s=float(wn[-1]))
    invalid = []
    rmax = float(np.max(np.abs(run.q[:, 3:]))) if len(run.t) else 0.0
    res["details"]["max_rotation_rad"] = rmax
    if rmax > p["max_rotation"]:
        invalid.append(f"platform rotations reach {rmax:.3g} rad > {p['max_rotation']:g} rad: the "
                       "linearised model (38) of paper 004 assumes small rotations")
    if chk == "steady_response":
        ex = (Q[None, :] * np.exp(1j * w * run.t)[:, None]).real
        scale = np.abs(Q)
        err = float(np.max(np.abs(run.q - ex) / np.maximum(scale, 1e-300 + 1e-12 * scale.max())))
        res.update(oracle=f"exact steady unbalance response at {w:g} rad/s "
                          "((K - w^2 M + i w (D + w G)) Q = F); the run starts on it",
                   error=err, error_measure="max over coordinates of |q - q_exact| / |Q| [-]",
                   reference_error=0.0)
    else:
        resid = np.hypot(run.static_residual[:, 0], run.static_residual[:, 1]) / u.s
        final = float(resid[-1]) if len(resid) else float("nan")
        res.update(oracle="balancing predicted by the engineering criterion (2.15) at this speed "
                          "(working range (2.85, 713) rad/s): static residual -> 0",
                   error=final, error_measure="static residual unbalance / rotor unbalance at the end [-]",
                   conserved_quantity="balanced state's residual", drift=None)
        res["details"]["final_static_residual"] = final
    return invalid


#: kind -> runner ``(case, res) -> list of validity violations``
RUNNERS: dict[str, Callable] = {
    "dimensionless": kind_dimensionless,
    "scene_file": kind_scene_file,
    "liquid_runup": _kind_liquid,
    "platform": _kind_platform,
    "qp_threshold": kind_qp,
    "body_scene": kind_body_scene,
}


# ------------------------------------------------------------------ warm-up
def warm(case: dict) -> None:
    """Compile / load the case's kernels (numba) before its timed region.

    Parameters
    ----------
    case : dict
        One case of :func:`stand.reports.stress_catalogue.load_catalogue`.
    """
    if case["kind"] in PLANAR_KINDS or case["kind"] == "body_scene":
        warm_planar(case)   # a scene file: a tiny run of it compiles its kernels
    elif case["kind"] == "platform":
        from stand.integrate.coupled import PlaneWeights, simulate_coupled
        from stand.model.rotors.platform import platform_rotor
        from stand.scene.model import Balancer

        b = Balancer(type="balls", mass=np.full(2, 0.1), radius=np.full(2, 0.1), drag=np.full(2, 1.0),
                     inertia=np.full(2, 1e-3), initial_angles=np.zeros(2), initial_speeds=np.zeros(2))
        rot = platform_rotor()
        for weights in ([], [PlaneWeights("balancer", b)]):
            simulate_coupled(rot, weights, [[0.0, 10.0]], 1e-3, 1e3, rtol=1e-6, atol=1e-8)


