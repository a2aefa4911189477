"""``stand.theory(scene)``: what the theory says of any scene, and why a part does not apply.

* planar rotor with identical balls or pendulums: chapter 5 (speed bands,
  critical speeds, stuck-ball law; :func:`stand.planar_theory.speedmap.scene_theory`);
* any other structure, and the planar rotor without weights or outside the
  chapter-5 theory: the structure's natural frequencies, Campbell data,
  critical speeds and the engineering criterion's working ranges per plane
  (:func:`stand.rotors.run.family_theory`);
* a book weight model: its steady motions with stability, quasi-periodic
  motions, efficiency or run-up extrema (:func:`stand.balancers.scene.model_theory`).

The result is one JSON-able dict with ``kind`` (``"chapter5"``, ``"structure"``,
``"book_model"``) and ``not_applicable`` (what was left out and why);
:func:`theory_lines` renders it as text.
"""
from __future__ import annotations

import json
import math

from .io.jsonable import to_jsonable

__all__ = ["theory", "theory_lines"]


def theory(scene, max_speed: float | None = None, floquet: bool = True) -> dict:
    """The theory of ``scene`` (module docstring).

    Parameters
    ----------
    scene : stand.scene.Scene
    max_speed : float, optional
        Upper end of the speed scans [rev/s].
    floquet : bool
        Rotor structures with weights: include the Floquet scan of the main
        motion (seconds).
    """
    from .planar_theory.speedmap import TheoryError, scene_theory

    na = []
    if scene.kind == "book":
        from .balancers.scene import model_theory

        doc = model_theory(scene)
        return {"kind": "book_model", **doc, "not_applicable": na}
    if scene.kind == "planar" and scene.n_weights:
        try:
            th = scene_theory(scene, R_max=max_speed * 2 * math.pi / scene.natural_frequency
                              if max_speed else None)
            return {"kind": "chapter5", **to_jsonable(th.to_dict()), "not_applicable": na}
        except TheoryError as exc:
            na.append(f"chapter-5 theory (speed bands, stuck-ball law): {exc}")
    if not scene.n_weights:
        na.append("correction weights: the scene has none, so there are no steady motions of "
                  "weights, no balancing speed bands and no stuck-ball law; the structure's "
                  "natural frequencies and critical speeds follow")
    from .rotors.run import family_theory

    doc = family_theory(scene, max_speed * 2 * math.pi if max_speed else None,
                        floquet=floquet and bool(scene.n_weights))
    return {"kind": "structure", **to_jsonable(doc), "not_applicable": na}


def _hz(v) -> str:
    return "inf" if v is None else f"{v:.5g}"


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
            out.append(f"  {b['from_hz']:9.4g} - {b['to_hz']:9.4g} rev/s  ({b['R_from']:.4g}-"
                       f"{b['R_to']:.4g} f0): " + (", ".join(b["motions"]) or "nothing stable"))
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
                       + (", ".join(f"({_hz(a)}, {_hz(b)})" for a, b in d["working_ranges_hz"])
                          or "none"))
        mm = doc.get("main_motion") or {}
        if mm.get("critical_speeds_hz") is not None:
            out.append("  main motion (Floquet, finite weight masses): critical speeds "
                       + (", ".join(f"{c:.5g}" for c in mm["critical_speeds_hz"]) or "none in the scan")
                       + f" rev/s; growth rate at {mm['operating_speed_hz']:.4g} rev/s: "
                       f"{mm['growth_rate_at_operating_speed_per_s']:.3g} 1/s")
        elif mm.get("note"):
            out.append(f"  main motion: {mm['note']}")
        out += [f"  note: {n}" for n in doc.get("notes", [])]
    else:
        out.append(f"{doc['scene']}: weight model {doc['type']} ({doc['source']})")
        for m in doc.get("steady_motions", []):
            label = m.get("label") or m.get("kind")
            out.append(f"  steady motion {label}: phi = {m.get('phi')}, psi = {m.get('psi')}, "
                       f"{'stable' if m.get('stable') else 'unstable'}")
        for k in ("quasi_periodic", "quasi_periodic_frequency", "quasi_periodic_family_limit",
                  "efficiency", "runup_extrema", "quasi_static_efficiency"):
            if k in doc:
                out.append(f"  {k}: {json.dumps(doc[k])[:400]}")
    out += [f"not applicable: {n}" for n in doc.get("not_applicable", [])]
    return out
