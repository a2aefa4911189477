"""Runner of the stress cases on scenes with body weights: kind ``body_scene`` of ``stand stress``.

A ``body_scene`` case names a scene file (``params.path``, any form: the
planar rotor or a ``[structure]`` rotor) whose ``[[weights]]`` carry body
weights (two-axis pendulum, coupled pair, damper, liquid float, liquid chamber;
:mod:`stand.scene.body_tables`), optionally shortened (``params.duration``)
or run at other tolerances.  It runs on the generic compiled kernel
(:func:`stand.integrate.simulate.simulate`) and is judged by one of three checks:

* ``runup_closed_form`` -- the planar rotor with one liquid whose centre of
  mass follows the shaft at once (paper 001's float, or a chamber without
  relaxation) is model M1 of paper 001 itself (``psi = M / (M + m lambda)``):
  run up at constant acceleration from the stationary whirl, the shaft must
  follow the closed form (Fresnel integrals undamped, Faddeeva damped;
  :func:`stand.integrate.accuracy.runup_params`) up to the programme's last node; error
  ``max |r - r_exact| / max |r_exact|`` and, undamped, the drift of the free-whirl
  amplitude ``|c+|`` left after the passage.  A float that touches the chamber
  wall (``max |r| > r1 - r2``) is outside the model.
* ``steady_theory`` -- the planar rotor with one tilting weight or damper
  (the book's stand, :func:`stand.model.balancers.composition.book_params`) held at
  its last speed over the last 30 % of the run: the residual unbalance of the
  plane (truth, rotor frame) divided by the rotor's unbalance ``M e`` at the end
  against the theory's stable main motions (ch. 6 (6.40): efficiency ``n`` of
  :func:`stand.theories.weights.two_axis_steady.steady_motions`; ch. 7.1 (7.7): 0, or
  ``(e0 - 1) / e0`` above capacity; ch. 7.2 (7.54):
  :func:`stand.theories.weights.damper_steady.efficiency` of the stable main motions;
  without gravity 0).  The error is the distance to the nearest stable main
  motion; the drift is the spread of that ratio over the last 30 %.
* ``reference`` -- the run against itself at ``reference_rtol``.

Units: SI (the dimensionless book parameters only inside the oracle).
"""
from __future__ import annotations

import dataclasses

import numpy as np

from stand.reports.stress_catalogue import CatalogueError
from stand.reports.stress_planar import _reference, _run_planar, scene_path

__all__ = ["BODY_CHECKS", "kind_body_scene", "load_body_scene"]

#: the checks of kind ``body_scene``
BODY_CHECKS = ("runup_closed_form", "steady_theory", "reference")
#: fraction of the run at its end that must be steady (check ``steady_theory``)
STEADY_TAIL = 0.3


def load_body_scene(case):
    """The case's scene with the overrides of its params (duration, tolerances, method).

    Raises
    ------
    CatalogueError
        The scene file is invalid, or it carries no body weight.
    """
    from stand.errors import SceneError
    from stand.scene.parse import load_scene

    p = case["params"]
    try:
        scene = load_scene(scene_path(case))
    except SceneError as exc:
        raise CatalogueError(f"case {case['name']!r}: field params.path: {exc}") from None
    if not scene.bodies:
        raise CatalogueError(f"case {case['name']!r}: field params.path: the scene has no body "
                             "weight ([[weights]] of type two_axis_pendulum, coupled_pair, damper, "
                             "liquid_float or liquid_chamber); use kind 'scene_file'")
    run = scene.run
    rtol = p["rtol"] or run.rtol
    atol = p["atol"] or (p["rtol"] * 1e-2 if p["rtol"] else run.atol)
    return dataclasses.replace(scene, run=dataclasses.replace(
        run, rtol=rtol, atol=atol, method=p["method"], duration=p["duration"] or run.duration))


def _runup(scene, tr, res) -> list:
    from stand.integrate.accuracy import runup_params
    from stand.model.rotors.bodies import LiquidWeight
    from stand.reports.stress_planar import runup_check

    invalid = runup_check(scene, tr, res, "the closed-form run-up needs the planar rotor with "
                          "one liquid lever (float, or chamber without relaxation)")
    if invalid:
        return invalid
    prm, _ = runup_params(scene)
    t, z = tr.t, tr.x + 1j * tr.y
    res["details"].update(psi=prm.psi, critical_speed_rad_s=prm.Omega,
                          max_whirl_m=float(np.max(np.abs(z))) if len(t) else 0.0)
    b = scene.bodies[0].body
    if isinstance(b, LiquidWeight) and b.kind == "liquid_float" and len(t):
        top = float(np.max(np.abs(z)))
        if top > b.gap:
            invalid.append(f"the shaft offset reached {top:.3g} m > r1 - r2 = {b.gap:.3g} m: the "
                           "float touched the chamber wall (paper 001 assumes it stays centred in "
                           "the liquid)")
    return invalid


def _expected_ratios(kind, prm) -> tuple:
    """(stable main motions' |U| / (M e) [-], description) of the book model ``kind``."""
    e0 = prm.e0
    over = max(e0 - 1.0, 0.0) / e0 if e0 > 0 else 0.0
    if kind == "gravity_pair" or getattr(prm, "R_g", 1.0) == 0.0:
        return [over], ("main motions (7.7): exact balance" if e0 < 1 else
                        "main motion above capacity: residual (e0 - 1) S")
    if kind == "two_axis":
        from stand.theories.weights.two_axis_steady import steady_motions

        mains = [m for m in steady_motions(prm) if m.kind.startswith("main") and m.stable]
        return ([float(m.n) for m in mains],
                "stable main motions of ch. 6, efficiency n (6.40): "
                + ", ".join(f"{m.kind} n = {m.n:.6g}" for m in mains))
    from stand.theories.weights.damper_steady import efficiency, is_stable, steady_motions

    mains = [m for m in steady_motions(prm) if m.kind == "main" and is_stable(prm, m)]
    ns = [float(efficiency(prm, m.u)) for m in mains]
    return ns, ("stable main motions of ch. 7.2, efficiency (7.54): "
                + ", ".join(f"motion {m.label} n = {n:.6g}" for m, n in zip(mains, ns)))


def _steady(scene, tr, res) -> list:
    from stand.model.balancers.composition import book_params

    invalid = []
    bp = book_params(scene)
    if bp is None or bp[0] not in ("two_axis", "gravity_pair", "damper"):
        invalid.append("the steady-motion theory needs the planar rotor on isotropic supports "
                       "with one tilting weight or damper and no balls (the book's stand, "
                       "stand.model.balancers.composition.book_params)")
        res.update(oracle="none (no book model)", error_measure="")
        return invalid
    kind, prm = bp
    prog = scene.drive.programme
    t = tr.t
    T = scene.run.duration
    if scene.drive.kind != "speed" or scene.drive.coast_down_start is not None or (
            prog[-1, 0] > (1.0 - STEADY_TAIL) * T):
        invalid.append(f"the speed is not held over the last {STEADY_TAIL:.0%} of the run (the "
                       f"programme's last node at {prog[-1, 0]:g} s, duration {T:g} s): no steady "
                       "motion to compare with")
    expected, what = _expected_ratios(kind, prm)
    Me = scene.rotor.unbalance
    if not Me > 0:
        invalid.append("the rotor has no unbalance (M e = 0): the residual ratio is undefined")
        res.update(oracle=f"{kind} book model", error_measure="")
        return invalid
    ratio = np.abs(tr.residual_unbalance()) / Me
    if not len(t):
        return invalid
    final = float(ratio[-1])
    tail = ratio[t >= (1.0 - STEADY_TAIL) * t[-1]]
    spread = float(np.max(tail) - np.min(tail)) if tail.size > 1 else 0.0
    res["details"].update(book_model=kind, book_params=dataclasses.asdict(prm),
                          final_residual_ratio=final, expected_ratios=expected,
                          rotor_unbalance_kg_m=Me)
    if not expected:
        invalid.append(f"no stable main motion at R_omega = {prm.R_omega:.6g}: balancing is not "
                       "predicted")
        res.update(oracle=f"{kind} book model: {what}", error_measure="")
        return invalid
    best = min(expected, key=lambda n: abs(final - n))
    res.update(oracle=f"{kind} book model at R_omega = {prm.R_omega:.6g}: {what}",
               error=abs(final - best),
               error_measure="| |U_end| / (M e) - n | for the nearest stable main motion [-]",
               conserved_quantity=f"residual unbalance |U| / (M e) over the last {STEADY_TAIL:.0%} "
                                  "of the run (max - min; steady motion)",
               drift=spread)
    res["details"]["matched_ratio"] = best
    res["_drift_checked"] = True
    return invalid


def kind_body_scene(case, res):
    """Run a ``body_scene`` case (module docstring); returns its validity violations."""
    scene = load_body_scene(case)
    chk = case["check"]
    tr = _run_planar(case, scene, res)
    res["details"].update(bodies=[pb.kind for pb in scene.bodies],
                          structure=scene.structure_type)
    invalid = []
    if chk == "runup_closed_form":
        invalid = _runup(scene, tr, res)
    elif chk == "steady_theory":
        invalid = _steady(scene, tr, res)
    ref = _reference(case, scene, tr, res)
    if ref is not None and chk != "reference":
        res["reference_error"] = ref[1]
    for note in getattr(tr, "notes", ()) or ():
        invalid.append(f"run note: {note}")
    return invalid
