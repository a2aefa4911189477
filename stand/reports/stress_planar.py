"""Runners of the stress cases on the planar rotor (chapter 5): kinds
``dimensionless``, ``scene_file`` and ``qp_threshold`` of ``stand stress``.

Each runner ``kind_<kind>(case, res)`` builds the scene from the case's
validated ``params`` (:mod:`stand.reports.stress_catalogue`), simulates it
(:func:`stand.integrate.simulate.simulate`), fills the result fields of ``res``
(:func:`stand.reports.stress_cases.outcome`) and returns the reasons it found
the case outside the model's validity (empty when inside).  The checks and
oracles are described in :mod:`stand.reports.stress` and
docs/reports_stress.md.  Units: SI; the dimensionless kinds use omega_1 = 1
rad/s, so t [s] = tau, lengths in units of r*.
"""
from __future__ import annotations

import dataclasses
import math
import warnings
from pathlib import Path

import numpy as np

from stand.reports.stress_catalogue import CatalogueError

__all__ = ["PLANAR_KINDS", "kind_dimensionless", "kind_scene_file", "kind_qp", "warm_planar",
           "rel_max"]

REPO_ROOT = Path(__file__).resolve().parents[2]
#: the catalogue's kinds run on the planar rotor (this module's runners)
PLANAR_KINDS = ("dimensionless", "scene_file", "qp_threshold")


# ------------------------------------------------------------------ helpers
def rel_max(a, b) -> float:
    """max |a - b| / max |b| over the common samples (NaN-safe) [-]."""
    k = min(len(a), len(b))
    if k == 0:
        return float("nan")
    scale = float(np.nanmax(np.abs(b[:k]))) or 1.0
    return float(np.nanmax(np.abs(a[:k] - b[:k]))) / scale


def warm_planar(case: dict) -> None:
    """Compile / load the planar kernels of a case outside its timed region.

    Parameters
    ----------
    case : dict
        A case of kind ``dimensionless``, ``qp_threshold`` or ``scene_file``
        (:func:`stand.reports.stress_catalogue.load_catalogue`); its scene is
        run for at most 0.01 s (or tau) at 1 kHz with loose tolerances.
    """
    from stand.scene.model import RunSettings
    from stand.integrate.simulate import simulate

    kind, p = case["kind"], case["params"]
    if kind == "dimensionless":
        scene = dimensionless_scene(p)
    elif kind == "qp_threshold":
        scene = qp_scene(p)[0]
    else:
        from stand.scene.parse import load_scene

        scene = load_scene(scene_path(case))
        scene = dataclasses.replace(scene, run=dataclasses.replace(scene.run, method=p["method"]))
    run = scene.run
    tiny = dataclasses.replace(scene, run=RunSettings(duration=min(run.duration, 1e-2),
                                                      sample_rate=1e3, rtol=1e-6, atol=1e-8,
                                                      method=run.method))
    simulate(tiny)


def _shaft(tr):
    """The shaft's position r = x + i y [m] of a planar run."""
    return tr.x + 1j * tr.y


def _velocity(tr):
    """The shaft's velocity dr/dt [m/s] of a run, from its state (the generic kernel's
    layout through :func:`stand.instruments.timing.shaft_velocity`)."""
    from stand.model.planar import build_planar_model

    if tr.scene.kind != "planar" or tr.scene.generic_kernel:
        from stand.instruments.timing import shaft_velocity

        vx, vy = shaft_velocity(tr)
        return vx + 1j * vy
    model = build_planar_model(tr.scene)
    k = 2 + tr.scene.balancer.count + (1 if model.free else 0)
    return (tr.state[:, k] + 1j * tr.state[:, k + 1]) * model.length * model.omega_1


def runup_check(scene, tr, res, needs: str) -> list:
    """Judge a run-up against the closed form of paper 001 (:func:`stand.integrate.accuracy.runup_params`:
    a weight-free rotor, or model M1 itself with one liquid lever); fills ``res`` (oracle,
    error, revolutions, the undamped free-whirl drift) and returns the reasons it does not
    apply (``needs``: what the case kind requires, for the message)."""
    from stand.integrate.accuracy import runup_params
    from stand.model.balancers.runup_closed_form import free_whirl_amplitudes, runup_closed_form_state

    ru = runup_params(scene)
    if ru is None:
        res.update(oracle="none (closed form not applicable)", error_measure="")
        return [f"{needs}, isotropic supports, a two-node speed programme (constant "
                "acceleration) and the stationary whirl as initial state "
                "(stand.integrate.accuracy.runup_params); none applies"]
    prm, t_end = ru
    t = tr.t
    valid = t <= t_end
    Z, Zd = runup_closed_form_state(prm, np.where(valid, t, 0.0))
    z = _shaft(tr)
    err = rel_max(np.where(valid, z, 0), np.where(valid, Z, 0))
    what = f"paper 001's model M1 with psi = {prm.psi:.6g}, " if prm.psi != 1.0 else ""
    res.update(oracle=(f"closed-form run-up ({what}"
                       + ("Fresnel integrals" if prm.n == 0 else "Faddeeva function")
                       + f"), {2 * prm.epsilon:g} rad/s^2 from {prm.omega_0:g} rad/s, up to "
                       f"t = {t_end:g} s"),
               error=err, error_measure="max |r - r_exact| / max |r_exact| [-]", reference_error=0.0)
    res["details"].update(revolutions=float(tr.rotor_angle[-1] / (2 * math.pi)) if len(t) else 0.0)
    if prm.n == 0 and len(t) and valid.any():
        k = int(np.nonzero(valid)[0][-1])
        v = _velocity(tr)
        c_num = free_whirl_amplitudes(prm, t[k:k + 1], z[k:k + 1], v[k:k + 1])[0][0]
        c_ref = free_whirl_amplitudes(prm, t[k:k + 1], Z[k:k + 1], Zd[k:k + 1])[0][0]
        res.update(conserved_quantity="free-whirl amplitude |c+| after the passage (undamped)",
                   drift=float((c_num - c_ref) / c_ref))
        res["_drift_checked"] = True
    return []


def _dot(a, b):
    """Real inner product of complex vectors (x1 x2 + y1 y2)."""
    return (np.conj(a) * b).real


def _mechanics(tr):
    """E_L (energy without the prescribed-rotor cross term) and p_theta, SI.

    Lagrangian of the shaft (total mass M_S, isotropic stiffness c) with the
    rotor's unbalance U turning at the prescribed phi(t) and point-coupled
    weights (m_j, l_j, J_j):  T = M_S |z'|^2/2 + U phi' z'.(i e^{i(phi+beta)})
    + sum [m_j l_j phi_j' z'.(i e^{i phi_j}) + J_j phi_j'^2 / 2],  V = c |z|^2/2.
    """
    sc = tr.scene
    b = sc.balancer
    z, v = _shaft(tr), _velocity(tr)
    Ms, c = sc.total_mass, sc.supports.stiffness_x
    E = 0.5 * Ms * np.abs(v) ** 2 + 0.5 * c * np.abs(z) ** 2
    pz = Ms * v + 1j * sc.rotor.unbalance * tr.rotor_speed * np.exp(
        1j * (tr.rotor_angle + sc.rotor.unbalance_angle))
    ptheta = np.zeros_like(E)
    for j in range(b.count):
        ml, J = b.mass[j] * b.radius[j], b.inertia[j]
        ph, w = tr.weight_angle[:, j], tr.weight_speed[:, j]
        ie = 1j * np.exp(1j * ph)
        cross = ml * w * _dot(v, ie)
        E = E + cross + 0.5 * J * w ** 2
        pz = pz + ml * w * ie
        ptheta = ptheta + ml * _dot(v, ie) + J * w
    ptheta = ptheta + _dot(pz, 1j * z)
    return E, ptheta


# ------------------------------------------------------------------ kind: dimensionless
def dimensionless_scene(p):
    """The planar ball-balancer scene of a ``dimensionless`` case (omega_1 = 1 rad/s)."""
    from stand.scene.model import InitialState, RunSettings, SpeedDrive
    from stand.scene.parse import scene_from_dimensionless

    if p["programme"] is not None:
        prog = np.array(p["programme"], float)
    else:
        prog = np.array([[0.0, p["R"]]])
    n = p["n"]
    angles = (np.radians(p["initial_angles_deg"]) if p["initial_angles_deg"] is not None
              else np.linspace(0.1, 6.0, n) if n > 2 else np.array([2.0, 4.0])[:n])
    run = RunSettings(duration=p["duration_tau"], sample_rate=p["sample_rate"], rtol=p["rtol"],
                      atol=p["atol"] if p["atol"] is not None else p["rtol"] * 1e-2,
                      method=p["method"], max_steps=p["max_steps"])
    sc = scene_from_dimensionless(n, p["Rt"], p["h"], p["H"], p["e0"], R_omega2=p["R_omega2"],
                                  drive=SpeedDrive(programme=prog), run=run,
                                  initial_angles=list(angles))
    L = sc.length_scale
    speeds = np.full(n, float(p["initial_speeds"]))  # omega_1 = 1 rad/s
    return dataclasses.replace(sc, initial=InitialState(x=p["initial_x"] * L),
                               balancer=dataclasses.replace(sc.balancer, initial_speeds=speeds))


def _top_speed(p):
    """The case's constant or highest programme speed R_omega [units of omega_1]."""
    return float(p["R"]) if p["R"] is not None else max(r[1] for r in p["programme"])


def _run_planar(case, scene, res):
    """Simulate a planar scene; the method, solver status and step statistics go to ``res``."""
    from stand.integrate.simulate import simulate

    tr = simulate(scene, method=scene.run.method)
    st = tr.stats
    res.update(method=st.method, method_reason=st.method_reason, solver_success=bool(st.success),
               solver_message=st.message, nfev=int(st.nfev), wall_time_s=float(st.wall_time))
    res["details"].update(n_steps=int(st.n_steps), n_rejected=int(st.n_rejected),
                          stiffness_ratio=float(st.stiffness_ratio), rtol=st.rtol, atol=st.atol,
                          samples=int(len(tr.t)))
    return tr


def _reference(case, scene, tr, res):
    """The reference run at ``reference_rtol``: estimated error of the run.

    The reference's method suits the scene (:func:`stand.integrate.simulate.auto_method`: the
    compiled DOP853, or Radau when stiff) and comes from a ladder of tolerances down to
    ``reference_rtol`` (:func:`stand.integrate.accuracy.reference_ladder`; the run itself is its
    first rung when it used that method), which states the reference's own error
    (``details["reference_own_error"]``, relative to max |r_ref|; with check ``"reference"``
    also the case's ``reference_error``) and stops short, with a note in
    ``details["reference_notes"]``, at the step budget or the round-off floor.

    Returns
    -------
    tuple or None
        ``(reference run, max |r - r_ref| / max |r_ref| [-])``, or None when
        the case gives no ``reference_rtol``.  With check ``"reference"`` that
        difference is the case's error.

    Raises
    ------
    CatalogueError
        Check ``"reference"`` without ``reference_rtol``.
    """
    from stand.integrate.accuracy import _LadderBudget, reference_ladder
    from stand.integrate.simulate import auto_method

    rr = case["reference_rtol"]
    if rr is None:
        if case["check"] == "reference":
            raise CatalogueError(f"case {case['name']!r}: check 'reference' needs field reference_rtol")
        return None
    method = "DOP853" if auto_method(scene) == "DOP853" else "Radau"
    seed = (tr.stats.rtol, tr) if tr.stats.method == method else None
    ref, name, own, notes = reference_ladder(_LadderBudget(scene), method, rr, rr * 1e4, seed)
    d = rel_max(_shaft(tr), _shaft(ref))
    own = own / (float(np.nanmax(np.abs(_shaft(ref)))) or 1.0)
    res["details"].update(reference_rtol=rr, reference=name, reference_own_error=own,
                          reference_difference=d,
                          reference_wall_time_s=float(ref.stats.wall_time),
                          reference_success=bool(ref.stats.success), reference_notes=notes)
    if case["check"] == "reference":
        res.update(oracle=f"converged reference: {name}", reference_error=own,
                   error=d, error_measure="max |r - r_ref| / max |r_ref| [-]")
    return ref, d


def kind_dimensionless(case, res):
    from stand.integrate.accuracy import closed_form_no_balancer
    from stand.scene.model import Balancer, Rotor
    from stand.theories.planar.main_motion import StabilityWarning, d_from_angles, d_two_balls, is_stable

    p, chk = case["params"], case["check"]
    scene = dimensionless_scene(p)
    tr = _run_planar(case, scene, res)
    S = scene.balancer.capacity     # the balls' alone, deliberately: the book's dimensionless cases
    invalid = []
    if chk == "balanced":
        psi = np.abs(tr.residual_unbalance()) / S
        R = _top_speed(p)
        expected = max(p["e0"] - 1.0, 0.0)
        if p["e0"] > 1.0:
            invalid.append(f"e0 = {p['e0']:g} > 1: the unbalance exceeds the balancer's capacity S, so "
                           "no balancing main motion exists (the main motion needs e0 <= 1, (5.50)); "
                           f"oracle used instead: all weights on the light side, residual (e0 - 1) S = "
                           f"{expected:g} S (digest 4.5)")
        d = (d_two_balls(min(p["e0"], 1.0)) if p["n"] == 2
             else d_from_angles(tr.relative_angle[-1]) if len(tr.t) else 0.0)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", StabilityWarning)
            stable = is_stable(R, p["Rt"], p["h"], p["H"], d) if p["e0"] <= 1 else None
        if stable is False:
            invalid.append(f"the main motion is not asymptotically stable at R_omega = {R:g} "
                           f"(Rt = {p['Rt']:g}, h = {p['h']:g}, H = {p['H']:g}, d = {d:.3g}; "
                           "stand.theories.planar.main_motion.is_stable): balancing is not predicted")
        final = float(psi[-1]) if len(psi) else float("nan")
        res.update(oracle=f"main motion of the theory: residual {expected:g} S at R_omega = {R:g}"
                   + ("" if stable is None else ", where it is asymptotically stable" if stable
                      else ", where it is not asymptotically stable"),
                   error=abs(final - expected),
                   error_measure="|residual unbalance / S - expected| at the end of the run [-]",
                   conserved_quantity="balanced state's residual |psi|/S (constant once balanced)",
                   drift=float(np.max(psi[-max(2, len(psi) // 10):]) - np.min(psi[-max(2, len(psi) // 10):]))
                   if len(psi) > 1 else None)
        res["details"].update(final_residual=final, expected_residual=expected, d=float(d))
        res["_drift_checked"] = False
    elif chk == "locked":
        b = scene.balancer
        U = scene.rotor.unbalance * np.exp(1j * scene.rotor.unbalance_angle) + np.sum(
            b.mass * b.radius * np.exp(1j * b.initial_angles))
        locked = dataclasses.replace(scene, balancer=Balancer(),
                                     rotor=Rotor(mass=scene.total_mass, eccentricity=abs(U) / scene.total_mass,
                                                 unbalance_angle=float(np.angle(U))))
        ref = closed_form_no_balancer(locked, tr.t)
        if ref is None:
            raise CatalogueError(f"case {case['name']!r}: check 'locked' needs a constant speed and "
                                 "isotropic supports (params.R, params.R_omega2 = 1)")
        R = _top_speed(p)
        bound = 2 * p["Rt"] * R ** 2 / max(p["h"], 1e-300)
        if p["h"] < 100 * R:
            invalid.append(f"h = {p['h']:g} is not >> R_omega = {R:g}: the locked-weight limit "
                           "(h -> inf) is not a valid oracle")
        err = rel_max(_shaft(tr), ref)
        slip = np.max(np.abs(np.angle(np.exp(1j * (tr.relative_angle - b.initial_angles)))))
        res.update(oracle="closed form of the rotor with the weights locked at their initial angles "
                   f"(limit h -> inf; model error of order mu R^2/h ~ {bound:.1g})",
                   error=err, error_measure="max |r - r_locked| / max |r_locked| [-]",
                   conserved_quantity="weight angles relative to the rotor (locked)", drift=float(slip))
        res["details"].update(max_weight_slip_rad=float(slip))
        res["_drift_checked"] = False
    elif chk in ("energy", "jacobi"):
        if p["h"] != 0 or p["H"] != 0:
            invalid.append(f"h = {p['h']:g}, H = {p['H']:g}: with damping there is no conserved "
                           f"{'energy' if chk == 'energy' else 'Jacobi integral'}")
        if p["R_omega2"] != 1.0:
            invalid.append(f"R_omega2 = {p['R_omega2']:g}: anisotropic supports break the rotation "
                           "invariance the conserved quantity rests on")
        if chk == "energy" and p["e0"] != 0:
            invalid.append(f"e0 = {p['e0']:g}: the unbalanced rotor, turned at a prescribed speed, "
                           "does work on the shaft: energy is not conserved (use check = 'jacobi')")
        E, pt = _mechanics(tr)
        w = p["R"] * 1.0  # omega_1 = 1 rad/s
        Q = E if chk == "energy" else E - w * pt
        scale = float(np.max(np.abs(E)) + (0 if chk == "energy" else w * np.max(np.abs(pt)))) or 1.0
        drift = float(np.max(np.abs(Q - Q[0])) / scale)
        res.update(oracle=("conservation of the total energy (h = H = 0, no unbalance)" if chk == "energy"
                           else "conservation of the Jacobi integral E - omega p_theta (h = H = 0, "
                                "constant speed, isotropic supports)"),
                   error=drift, error_measure="max |Q(t) - Q(0)| / max scale of Q's terms [-]",
                   conserved_quantity=("total energy" if chk == "energy" else "Jacobi integral"),
                   drift=drift)
        res["details"].update(initial_value_J=float(Q[0]), scale_J=scale)
        res["_drift_checked"] = False
    ref = _reference(case, scene, tr, res)
    if ref is not None and chk != "reference":
        res["reference_error"] = ref[1]
    return invalid


# ------------------------------------------------------------------ kind: scene_file
def scene_path(case) -> Path:
    """``params.path``; a relative one from the catalogue's folder, else from the repository."""
    path = Path(case["params"]["path"])
    if not path.is_absolute():
        cand = [Path(case.get("_dir", ".")) / path, REPO_ROOT / path]
        path = next((c for c in cand if c.exists()), cand[-1])
    return path


def kind_scene_file(case, res):
    from stand.integrate.accuracy import closed_form_no_balancer
    from stand.errors import SceneError
    from stand.scene.parse import load_scene

    p, chk = case["params"], case["check"]
    try:
        scene = load_scene(scene_path(case))
    except SceneError as exc:
        raise CatalogueError(f"case {case['name']!r}: field params.path: {exc}") from None
    run = scene.run
    scene = dataclasses.replace(scene, run=dataclasses.replace(
        run, rtol=p["rtol"] or run.rtol, atol=p["atol"] or (p["rtol"] * 1e-2 if p["rtol"] else run.atol),
        method=p["method"], duration=p.get("duration") or run.duration))
    tr = _run_planar(case, scene, res)
    invalid = []
    if chk == "runup_closed_form":
        invalid += runup_check(scene, tr, res, "the closed-form run-up needs no weights")
        if invalid:
            return invalid
    elif chk == "closed_form":
        ref = closed_form_no_balancer(scene, tr.t)
        if ref is None:
            invalid.append("the constant-speed closed form needs no weights, one programme node and "
                           "isotropic supports (stand.integrate.accuracy.closed_form_no_balancer)")
            res.update(oracle="none (closed form not applicable)")
            return invalid
        res.update(oracle="closed form (no weights, constant speed, isotropic supports)",
                   error=rel_max(_shaft(tr), ref), error_measure="max |r - r_exact| / max |r_exact| [-]",
                   reference_error=0.0)
    _reference(case, scene, tr, res)
    return invalid


# ------------------------------------------------------------------ kind: qp_threshold
def qp_scene(p):
    """The stuck-ball (QP) motion of the theory as an initial state, e0 = 0."""
    from stand.scene.model import InitialState, RunSettings, SpeedDrive
    from stand.scene.parse import scene_from_dimensionless
    from stand.theories.planar.qp import escape_speed, qp_roots

    Rt, h, H = p["Rt"], p["h"], p["H"]
    Rs = escape_speed(Rt, h, H)
    R = Rs + p["offset"]
    roots = qp_roots(R, Rt, h, H)
    Om = float(roots[0])
    s = Om ** 2 / (1 - Om ** 2 + 1j * H * Om)
    sep = p["separation"]
    run = RunSettings(duration=p["duration_tau"], sample_rate=p["sample_rate"], rtol=p["rtol"],
                      atol=p["atol"] if p["atol"] is not None else p["rtol"] * 1e-2, method=p["method"])
    sc = scene_from_dimensionless(2, Rt, h, H, 0.0, drive=SpeedDrive(programme=np.array([[0.0, R]])),
                                  run=run, initial_angles=[-sep / 2, sep / 2])
    L = sc.length_scale
    v = 1j * Om * s * L
    sc = dataclasses.replace(sc, initial=InitialState(x=L * s.real, y=L * s.imag, vx=v.real, vy=v.imag),
                             balancer=dataclasses.replace(sc.balancer,
                                                          initial_speeds=np.full(2, Om - R)))
    return sc, Rs, R, roots, Om, s


def kind_qp(case, res):
    from stand.theories.planar.qp import qp_stability

    p, chk = case["params"], case["check"]
    Rt, h, H = p["Rt"], p["h"], p["H"]
    sc, Rs, R, roots, Om, s = qp_scene(p)
    sep = p["separation"]
    L = sc.length_scale
    tr = _run_planar(case, sc, res)
    stab = qp_stability(Om, R, Rt, h, H)
    res["details"].update(escape_speed=Rs, R_omega=R, Omega_1=Om, qp_roots=[float(r) for r in roots],
                          qp_stable=bool(getattr(stab, "stable", False)))
    invalid = []
    if chk == "qp_persists" and p["offset"] >= 0:
        invalid.append(f"offset = {p['offset']:g} >= 0: above R*_omega the QP motion is unstable (5.226)")
    if chk == "escape" and p["offset"] <= 0:
        invalid.append(f"offset = {p['offset']:g} <= 0: below R*_omega the stable QP motion exists (5.226)")
    if not len(tr.t):
        return invalid
    if chk == "qp_persists":
        k = len(tr.t) // 2
        ang = np.unwrap(tr.weight_angle[k:].mean(axis=1))
        slope = float(np.polyfit(tr.t[k:], ang, 1)[0])
        rad = np.abs(_shaft(tr)) / L
        err_w = abs(slope - Om) / Om
        err_r = float(np.max(np.abs(rad - abs(s)))) / abs(s)
        gap = float(np.max(np.abs(np.angle(np.exp(1j * (tr.weight_angle[:, 0] - tr.weight_angle[:, 1]))))))
        res.update(oracle=f"stable QP motion of the theory: precession Omega_1 = {Om:.10g} (root of (5.181)), "
                          f"whirl radius |s| = {abs(s):.6g} r*",
                   error=max(err_w, err_r),
                   error_measure="max(|Omega_run - Omega_1| / Omega_1 over the 2nd half, "
                                 "max | |r|/r* - |s| | / |s|) [-]",
                   conserved_quantity="separation of the stuck balls [rad] (max over the run; starts at "
                                      f"{sep:g})", drift=gap)
        res["details"].update(Omega_run=slope, precession_error=err_w, radius_error=err_r,
                              max_separation_rad=gap)
        if gap > max(10 * sep, 1e-2):
            res["checks"].append(f"the balls separated by {gap:.3g} rad: the QP motion did not persist")
    else:
        psi = np.abs(tr.residual_unbalance()) / sc.balancer.capacity
        res.update(oracle="above R*_omega the QP motion is unstable; the balls escape and balance "
                          "(residual -> 0, main motion with e0 = 0)",
                   error=float(psi[-1]), error_measure="residual unbalance / S at the end [-]",
                   conserved_quantity="balanced state's residual |psi|/S")
        res["details"]["final_residual"] = float(psi[-1])
        above = np.nonzero(psi < 0.5)[0]
        res["details"]["escape_time_tau"] = float(tr.t[above[0]]) if above.size else None
    return invalid
