"""``stand.theory(scene)``: what the theory says of any scene, and why a part does not apply.

* planar rotor with identical balls or pendulums: chapter 5 (speed bands,
  critical speeds, stuck-ball law; :func:`stand.theories.planar.speedmap.scene_theory`);
* any other structure, and the planar rotor without weights or outside the
  chapter-5 theory: the structure's natural frequencies, Campbell data,
  critical speeds and the engineering criterion's working ranges per plane
  (:func:`stand.theories.rotors.family_theory`);
* a book weight model: its steady motions with stability, quasi-periodic
  motions, efficiency or run-up extrema (:func:`model_theory`).

The result is a :class:`stand.theories.result.Theory` (the JSON document ``stand theory
--json`` prints, with attribute access, tables and a picture) with ``kind`` (``"chapter5"``, ``"structure"``,
``"book_model"``) and ``not_applicable`` (what was left out and why);
:func:`theory_lines` renders it as text.
"""
from __future__ import annotations

import math

from stand.io.jsonable import to_jsonable

__all__ = ["theory", "theory_lines"]


def theory(scene, max_speed: float | None = None, floquet: bool = True):
    """The theory of ``scene`` (module docstring).

    Parameters
    ----------
    scene : stand.scene.model.Scene
    max_speed : float, optional
        Upper end of the speed scans [rev/s].
    floquet : bool
        Rotor structures with weights: include the Floquet scan of the main
        motion (seconds).

    Returns
    -------
    stand.theories.result.Theory
        The document of ``stand theory --json``, with attribute access, ``to_frame()``
        and ``plot()``.
    """
    from stand.theories.planar.speedmap import TheoryError, scene_theory
    from stand.theories.result import Theory

    na = _friction_notes(scene)
    if scene.kind == "book":
        doc = model_theory(scene)
        return Theory({"kind": "book_model", **doc, "not_applicable": na})
    if scene.kind == "planar" and scene.n_weights:
        try:
            th = scene_theory(scene, R_max=max_speed * 2 * math.pi / scene.natural_frequency
                              if max_speed else None)
            return Theory({"kind": "chapter5", **to_jsonable(th.to_dict()), "not_applicable": na})
        except TheoryError as exc:
            na.append(f"chapter-5 theory (speed bands, stuck-ball law): {exc}")
    models = _body_models(scene, na)
    if not scene.n_weights and not scene.bodies:
        na.append("correction weights: the scene has none, so there are no steady motions of "
                  "weights, no balancing speed bands and no stuck-ball law; the structure's "
                  "natural frequencies and critical speeds follow")
    from stand.theories.rotors import family_theory

    doc = family_theory(scene, max_speed * 2 * math.pi if max_speed else None,
                        floquet=floquet and bool(scene.n_weights))
    return Theory({"kind": "structure", **to_jsonable(doc), "weight_models": models,
                   "not_applicable": na})


def _friction_notes(scene) -> list:
    """What the theory leaves out of weights with dry friction (stand.model.balancers.friction):
    its steady motions are those of viscous drag only."""
    out = []
    for w in scene.weights if scene.kind != "book" else ():
        f, b = w.friction, w.balancer
        where = "balancer" if scene.kind == "planar" else f"the weights in plane {w.plane}"
        if getattr(b, "ball_radius", 0.0) > 0:
            out.append(f"ball-ball contact of {where} (ball_radius = {b.ball_radius:g} m): outside "
                       "the theory, whose balls are points free to share an angle")
        if getattr(b, "race_eccentricity", 0.0) > 0:
            out.append(f"race eccentricity of {where} ({b.race_eccentricity:g} m): outside the "
                       "theory; above the critical speed the balls hold the race's centre on the "
                       f"axis, a residual whirl of {b.race_eccentricity:g} m "
                       "(stand.model.rotors.weight_table)")
        if getattr(b, "race_out_of_roundness", 0.0) > 0:
            out.append(f"race out-of-roundness of {where} (eps = {b.race_out_of_roundness:g}, "
                       f"{b.race_lobes} lobes): outside the theory, whose race is a circle; the "
                       "race's radius l [1 + eps cos k (a - theta_o)] pulls each ball towards its "
                       "widest points (a = theta_o + 2 pi j / k, potential -m Omega^2 rho^2 / 2 on the "
                       "rotor): above the critical speed each ball rests where q . u_j = "
                       "-rho rho' (q the whirl), so the balls leave a residual whirl of order "
                       f"eps k l = {b.race_out_of_roundness * b.race_lobes * float(max(b.radius)):.3g} m "
                       "instead of balancing, or stay at a widest point when that exceeds the "
                       "unbalance's own whirl (stand.model.rotors.weight_table)")
        if f is None or not (f.kinetic > 0 or f.static > 0):
            continue
        mu_l = max(f.kinetic, 0.0) * float(max(w.balancer.radius))
        out.append(f"dry friction of {where} (friction = {f.kinetic:g}"
                   + (f", static_friction = {f.static:g}" if f.sticks else "")
                   + "): outside the steady-motion theory, whose weights feel viscous drag only "
                   "(the results below are for the frictionless weights); with friction they stop "
                   "where the shaft's push falls below the friction moment, short of balance: a "
                   f"residual whirl of order mu l = {mu_l:.3g} m above the critical speed "
                   "(stand.model.balancers.friction)")
    return out


def _body_models(scene, na: list) -> list:
    """The book theory of each body weight where the scene is the book's stand: a planar
    rotor on isotropic supports with that one body (stand.model.balancers.composition.book_params)."""
    if not scene.bodies:
        return []
    from stand.model.balancers.composition import book_params
    from stand.theories.weights.weight_theory import weight_theory

    speed, basis = _operating_speed(scene)
    bp = book_params(scene, speed)
    if bp is None:
        na.append("weight-model theory (steady motions, efficiency, quasi-periodic motions, "
                  "optimal fill): the books derive it for one body weight on the planar rotor "
                  "with isotropic supports; this scene's "
                  f"{', '.join(b.kind for b in scene.bodies)} on {scene.structure_type} is outside it")
        return []
    kind, params = bp
    liquid = kind.startswith("liquid")
    doc = weight_theory(kind, params, speed if liquid and speed else None)
    if not speed:
        basis = ("half the critical speed (gamma = 0.5), the model's default: the scene's drive "
                 "gives no speed" if kind == "liquid_chamber" else
                 "the run-up's start speed omega_0: the scene's drive gives no other"
                 if kind == "liquid_float" else "at rest: the scene's drive gives no speed")
    return [{"scene": scene.name, "plane": scene.bodies[0].plane, "weight": scene.bodies[0].kind,
             "type": kind, **doc, "speed_basis": basis}]


def _operating_speed(scene) -> tuple:
    """``(speed [rad/s] or None, why)``: where a body weight's book model is evaluated -- the
    scene's operating speed (:attr:`stand.scene.model.Scene.operating_speed`: the speed
    programme's last, held speed, or a torque drive's target), else the drive's top speed
    (a programme that ends at rest), else None."""
    d = scene.drive
    if scene.operating_speed > 0:
        how = ("its speed programme's last (held) speed" if d.kind == "speed" else
               "its torque drive's target speed" if d.target_speed else
               "its torque drive's initial speed")
        w = scene.operating_speed
        return w, f"the scene's operating speed, {how}: {w / (2 * math.pi):.4g} rev/s"
    if scene.top_speed > 0:
        w = scene.top_speed
        return w, (f"the drive's top speed, {w / (2 * math.pi):.4g} rev/s (the programme ends "
                   "at rest)")
    return None, None


def _range(lo, hi, unit: str = "rev/s", digits: int = 5) -> str:
    """A speed range in words, the one form of every range ``stand theory`` prints:
    "12 rev/s to 40 rev/s", "from 12 rev/s up" (no upper end: None or inf), "up to 40 rev/s"
    (no lower end); ``unit`` "" for a dimensionless speed ("R_omega from 1.2 to 3")."""
    def num(v):
        return f"{v:.{digits}g}" + (f" {unit}" if unit else "")

    open_hi = hi is None or hi == math.inf
    if lo is None:
        return "any speed" if open_hi else f"up to {num(hi)}"
    return f"from {num(lo)} up" if open_hi else f"{'from ' if not unit else ''}{num(lo)} to {num(hi)}"


def _g(v, digits: int = 4) -> str:
    """A number of the theory document (``None`` is JSON's NaN: "n/a")."""
    if v is None:
        return "n/a"
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        return str(v)
    return f"{v:.{digits}g}"


def _steady_lines(doc: dict) -> list:
    out = []
    for m in doc.get("steady_motions", []):
        label = m.get("label") or m.get("kind")
        r = m.get("deflection")
        if r is None and m.get("xi") is not None and m.get("eta") is not None:
            r = math.hypot(m["xi"], m["eta"])
        out.append(f"  steady motion {label}: phi = {_g(m.get('phi'))} rad, psi = {_g(m.get('psi'))} rad, "
                   f"deflection {_g(r, 3)}, {'stable' if m.get('stable') else 'unstable'}")
    return out


def _trace_text(tr: dict) -> str:
    return (f"trace: R_omega/Omega = {_g(tr.get('frequency_ratio'))}, {tr.get('petals')} petals, "
            f"{tr.get('shape')}, pattern turning at {_g(tr.get('pattern_rotation'), 3)} omega0; cusps "
            f"from e0 = {_g(tr.get('cusp_unbalance_e0'), 3)}")


def _gravity_pair_lines(doc: dict) -> list:
    out = []
    gap = doc.get("side_motion_gap_R_omega")
    if gap:
        out.append(f"  side motions 3, 4 absent for R_omega {_range(gap[0], gap[1], '', 4)} (7.8)")
    eff = doc.get("balancing_efficiency", {})
    out.append(f"  balancing: deflection {_g(eff.get('deflection'), 3)} on the stable main motion, "
               f"{_g(eff.get('deflection_without_balancer'), 3)} without the balancer "
               f"(n = {_g(eff.get('value'), 3)})")
    qp = doc.get("quasi_periodic", {})
    if qp.get("frequency_Omega") is None:
        out.append("  quasi-periodic family (7.38)-(7.46): none at this speed")
        return out
    out.append(f"  quasi-periodic family (7.38)-(7.46), phi = pi/2: Omega = {_g(qp['frequency_Omega'], 5)} "
               f"omega0 (small-H approximation {_g(qp.get('frequency_small_H_approx'))}); precession "
               f"amplitude {_g(qp.get('precession_amplitude'))}, nutation amplitude "
               f"{_g(qp.get('nutation_amplitude'))}, orbit radius {_g(qp.get('orbit_radius_min'))} to "
               f"{_g(qp.get('orbit_radius_max'))}")
    out.append(f"    stable for 1 < R_omega < {_g(qp.get('family_limit_exact_R_omega'))} ((7.41): "
               f"{_g(qp.get('family_limit_R_omega'))}): "
               + ("exists here, beside the main motions" if qp.get("exists") else "not at this speed"))
    if qp.get("trace"):
        out.append("    " + _trace_text(qp["trace"]))
    return out


def _two_axis_lines(doc: dict) -> list:
    eff = doc.get("balancing_efficiency", {})
    out = [f"  efficiency (6.40): n = {_g(eff.get('value'))} on {eff.get('motion', 'no stable main motion')}"
           f" (approximation (6.114): {_g(eff.get('approx_6_114'))}); deflection without the balancer "
           f"{_g(eff.get('deflection_without_balancer'), 3)}"]
    qps = doc.get("quasi_periodic", [])
    if not qps:
        out.append("  quasi-periodic motions (6.115)-(6.162): none at this speed")
    for q in qps:
        out.append(f"  quasi-periodic ({q.get('family')}): Omega = {_g(q.get('Omega'), 5)} omega0, "
                   f"phi = {_g(q.get('phi'))} rad, precession amplitude {_g(q.get('precession_amplitude'))}, "
                   f"nutation amplitude {_g(q.get('nutation_amplitude'))}, "
                   f"{'stable' if q.get('stable') else 'unstable'}")
        if q.get("stable") and q.get("trace"):
            out.append("    " + _trace_text(q["trace"]))
    return out


def _damper_lines(doc: dict) -> list:
    eff = doc.get("balancing_efficiency", {})
    out = [f"  efficiency (7.54): n = {_g(eff.get('value'))} (u = cos phi = {_g(eff.get('u'))}; deflection "
           f"{_g(eff.get('deflection'), 3)}, without the balancer "
           f"{_g(eff.get('deflection_without_balancer'), 3)}; approximation (6.114): "
           f"{_g(eff.get('approx_6_114'))})"]
    b = doc.get("existence_boundaries_undamped")
    if b:
        out.append(f"  existence boundaries for H = 0 (7.55)-(7.56): e0* = {_g(b.get('e0_star'))}, "
                   f"R_omega1 = {_g(b.get('R1'))}, R_omega2 = {_g(b.get('R2'))}, "
                   f"R_omega3 = {_g(b.get('R3'))}")
    return out


def _liquid_float_lines(doc: dict) -> list:
    st = doc.get("steady", {})
    out = [f"  critical speed with the liquid {_g(doc.get('critical_speed_rad_s'), 5)} rad/s (bare rotor "
           f"{_g(doc.get('critical_speed_bare_rotor_rad_s'), 5)} rad/s)",
           f"  steady at {_g(doc.get('speed_rad_s'))} rad/s: delta/e = {_g(st.get('delta_over_e'))} "
           f"({_g(st.get('deflection_m'), 3)} m), d = {_g(st.get('d'))}"]
    ru = doc.get("runup_extrema")
    if ru:
        out.append(f"  run-up to 2 Omega_0: peak delta*/e = {_g(ru.get('delta_star_over_e'))} at "
                   f"omega/Omega_0 = {_g(ru.get('z_delta'))} (t = {_g(ru.get('t_delta'))} s), peak d* = "
                   f"{_g(ru.get('d_star'))}; at the end delta/e = {_g(ru.get('delta_end_over_e'))}")
    return out


def _liquid_chamber_lines(doc: dict) -> list:
    out = []
    eff = doc.get("balancing_efficiency")
    if eff:
        out.append(f"  efficiency (2.14) at {_g(doc.get('speed_rad_s'))} rad/s "
                   f"(gamma = {_g(doc.get('gamma'), 3)}): "
                   f"lambda0 = {_g(eff.get('lambda0'))} (k = D0/D = {_g(eff.get('k'))}, alpha0 = "
                   f"{_g(eff.get('alpha0_deg'))} deg; at this alpha0 the maximum over k is "
                   f"{_g(eff.get('lambda0_max'))} at k* = {_g(eff.get('k_star'))})"
                   + ("" if eff.get("valid")
                      else " [outside the model: " + "; ".join(eff.get("flags", [])) + "]"))
    rows = doc.get("efficiency_by_speed", [])
    if rows:
        out.append("  lambda0 at the speeds of Table 3.2 (gamma: lambda0, * outside the model): "
                   + ", ".join(f"{_g(r['gamma'], 2)}: {_g(r.get('lambda0'), 3)}"
                               f"{'' if r.get('valid') else '*'}" for r in rows))
    ov = doc.get("optimal_volume")
    if ov:
        ratio = ov.get("liquid_over_optimal")
        out.append(f"  optimal fill (section 3.3): V_opt = {_g(ov.get('V_opt_ml'))} ml "
                   f"({_g(ov.get('V_opt_m3'))} m^3) for D0 = {_g(ov.get('D0_g_cm'))} g cm "
                   f"({_g(ov.get('D0_kg_m'))} kg m); with reserve {_g(ov.get('reserve'))}: "
                   f"{_g((ov.get('V_design_m3') or 0) * 1e6)} ml, layer R - r = "
                   f"{_g((ov.get('layer_m') or 0) * 1e3, 3)} mm; the scene holds "
                   f"{_g((ov.get('liquid_volume_m3') or 0) * 1e6)} ml ({_g(ratio, 3)} x V_opt)")
        out += [f"    {f}" for f in ov.get("flags", [])]
    lc = doc.get("liquid_choice", {})
    liq = lc.get("liquids", {})
    if liq:
        parts = []
        for name, z in liq.items():
            if z.get("keeps_zone"):
                parts.append(f"{name} sin(beta*) = {_g(z.get('sin_beta_star'), 3)} "
                             f"({_g(z.get('beta_star_deg'), 3)} deg)")
            else:
                parts.append(f"{name} no bounded zone")
        out.append(f"  liquid choice (2.15) at {_g(lc.get('speed_rad_s'))} rad/s, each at its V_opt: "
                   + "; ".join(parts) + f" -> {lc.get('chosen') or 'none'}")
    sl = lc.get("scene_liquid")
    if sl:
        out.append(f"  the scene's liquid (nu = {_g(sl.get('nu_m2_per_s'), 3)} m^2/s, V = "
                   f"{_g(sl.get('V_m3'), 3)} m^3): sin(beta*) = {_g(sl.get('sin_beta_star'), 3)}"
                   + ("" if sl.get("keeps_zone") else ", no bounded zone"))
    return out


_BOOK_LINES = {"gravity_pair": _gravity_pair_lines, "two_axis": _two_axis_lines,
               "damper": _damper_lines, "liquid_float": _liquid_float_lines,
               "liquid_chamber": _liquid_chamber_lines}


def _book_model_lines(doc: dict) -> list:
    """Lines of a book weight model (:func:`stand.theories.weights.weight_theory.weight_theory`)."""
    head = f"{doc['scene']}: weight model {doc['type']} ({doc['source']})"
    if doc.get("speed_R_omega") is not None:
        head += (f" at R_omega = {_g(doc['speed_R_omega'])} (speeds in omega0, deflections "
                 "dimensionless, angles in rad)")
    elif doc.get("speed_rad_s") is not None:
        w = doc["speed_rad_s"]
        head += f" at {_g(w)} rad/s = {_g(w / (2 * math.pi))} rev/s (SI)"
    out = [head] + ([f"  speed: {doc['speed_basis']}"] if doc.get("speed_basis") else [])
    out += _steady_lines(doc)
    out += _BOOK_LINES.get(doc["type"], lambda d: [])(doc)
    out += [f"  note: {n}" for n in doc.get("notes", [])]
    return out


def theory_lines(doc: dict) -> list:
    """The theory document as lines of text (what ``stand theory`` prints)."""
    kind = doc["kind"]
    out = []
    if kind == "chapter5":
        f0 = doc["natural_frequency_hz"]
        out.append(f"{doc.get('scene', '')}: natural frequency f0 = {f0:.4g} Hz; operating speed "
                   f"{doc['operating_speed_hz']:.4g} rev/s")
        out.append("stable motions by speed band:")
        for b in doc["stable_bands"]:
            out.append(f"  {_range(b['from_hz'], b['to_hz'], digits=4)} "
                       f"({_range(b['R_from'], b['R_to'], 'f0', 4)}): "
                       + (", ".join(b["motions"]) or "nothing stable"))
        out.append("critical speeds:")
        for c in doc["critical_speeds_hz"]:
            out.append(f"  {c['hz']:9.4g} rev/s ({c['R']:.5g} f0): {c['motion']} {c['kind']} "
                       f"stability [{c['source']}]")
        q = doc["qp"]
        if q.get("escape_speed_hz"):
            out.append(f"stuck balls (quasi-periodic) possible below {q['escape_speed_hz']:.4g} "
                       "rev/s (escape speed)")
        if q.get("stable_root_hz"):
            out.append(f"  at the operating speed: balls at {q['stable_root_hz']:.4g} rev/s, "
                       f"precession {q['precession_amplitude_m']:.3g} m, nutation "
                       f"{q['nutation_amplitude_m']:.3g} m, {q['shape']}")
        out += [f"note: {w}" for w in doc.get("warnings", [])]
    elif kind == "structure":
        out.append(f"{doc['scene']}: rotor type {doc['rotor_type']} (section {doc['source']}), "
                   "natural frequencies at rest: "
                   + (", ".join(f"{f:.4g}" for f in doc["natural_frequencies_hz_at_rest"]) or "none")
                   + " Hz")
        for p, d in doc["engineering_criterion"].items():
            out.append(f"  plane {p}: critical speeds "
                       + (", ".join(f"{c:.5g}" for c in d["critical_speeds_hz"]) or "none")
                       + " rev/s; working ranges "
                       + (", ".join(_range(a, b) for a, b in d["working_ranges_hz"])
                          or "none"))
        gc = doc.get("generalised_criterion")
        if gc:
            out.append(f"  generalised criterion, planes {', '.join(gc['planes'])} "
                       f"({gc['condition']}): onsets/losses "
                       + (", ".join(f"{c:.6g}" for c in gc["onsets_hz"]) or "none")
                       + " rev/s; working ranges "
                       + (", ".join(_range(a, b) for a, b in gc["working_ranges_hz"])
                          or "none"))
        mm = doc.get("main_motion") or {}
        if mm.get("critical_speeds_hz") is not None:
            out.append("  main motion (Floquet, finite weight masses): critical speeds "
                       + (", ".join(f"{c:.5g}" for c in mm["critical_speeds_hz"]) + " rev/s"
                          if mm["critical_speeds_hz"] else "none in the scan")
                       + f"; growth rate at {mm['operating_speed_hz']:.4g} rev/s: "
                       f"{mm['growth_rate_at_operating_speed_per_s']:.3g} 1/s"
                       + "".join(f"; the main motion ends at {f:.5g} rev/s (no periodic "
                                 "orbit beyond: the scan stops there)"
                                 for f in mm.get("ends_hz", ())))
        elif mm.get("note"):
            out.append(f"  main motion: {mm['note']}")
        out += [f"  note: {n}" for n in doc.get("notes", [])]
        for wm in doc.get("weight_models", []):
            out.append(f"weight {wm['weight']} in plane {wm['plane']} as the book's model:")
            out += _book_model_lines(wm)
    else:
        out += _book_model_lines(doc)
    out += [f"not applicable: {n}" for n in doc.get("not_applicable", [])]
    return out


def model_theory(scene) -> dict:
    """Steady motions (with stability) and the model's characteristic numbers of a
    ``[weight_model]`` scene.

    The content is :func:`stand.theories.weights.weight_theory.weight_theory` of the
    scene's model at the scene's speed (the parameters' own speed; for the
    liquid chamber ``run.speed``, default half the critical speed), merged
    under ``scene``, ``type``, ``source`` and ``parameters``; ``speed_basis`` says
    which speed and why (a body weight of a rotor scene is evaluated at the scene's
    operating speed instead: :func:`_operating_speed`).  The earlier keys
    stay: ``quasi_periodic_frequency`` and ``quasi_periodic_family_limit``
    (gravity pair) and ``efficiency`` (damper, (7.54)).
    """
    from stand.io.jsonable import to_jsonable
    from stand.scene.book_tables import MODEL_TYPES, _speed
    from stand.theories.weights.weight_theory import weight_theory

    bm = scene.structure
    kind, p = bm.type, bm.params
    speed = _speed(kind, p, bm.options) if kind == "liquid_chamber" else None
    wt = weight_theory(kind, p, speed)
    out = {"scene": scene.name, "type": kind, "source": MODEL_TYPES[kind][1],
           "parameters": to_jsonable(p)}
    out |= {k: v for k, v in wt.items() if k not in ("model", "source", "parameters")}
    out["speed_basis"] = (("the scene's run.speed" if "speed" in bm.options else
                           "half the critical speed (gamma = 0.5), the default when the scene "
                           "gives no run.speed") if kind == "liquid_chamber" else
                          "the parameters' omega_0 (the run-up's start speed)"
                          if kind == "liquid_float" else "the parameters' R_omega")
    if kind == "gravity_pair":
        out["quasi_periodic_frequency"] = wt["quasi_periodic"].get("frequency_Omega")
        out["quasi_periodic_family_limit"] = wt["quasi_periodic"].get("family_limit_R_omega")
    elif kind == "damper":
        out["efficiency"] = wt["balancing_efficiency"].get("value")
    return out
