"""Theory of a rotor-family scene (``stand theory``): natural frequencies, Campbell data,
the engineering criterion's working ranges per plane, Floquet critical speeds.

(Runs of every scene go through :func:`stand.run`; recordings through
:mod:`stand.recording.hdf5`.)
"""
from __future__ import annotations

import math

import numpy as np

from stand.integrate.coupled import with_locked_weights
from stand.scene.structure_tables import ROTOR_TYPES
from stand.model.rotors.structure import generalised_working_ranges, working_ranges

__all__ = ["family_theory"]


def _steady(scene, rot) -> dict:
    """1X response of every plane to the rotor's unbalances at the operating speed
    (weights locked, i.e. the rotor as it would run without balancing)."""
    w = scene.operating_speed
    if not (w > 0 and rot.unbalances):
        return {}
    out = {"speed_hz": w / (2 * math.pi), "planes": {}}
    for p in rot.planes:
        XY = sum(rot.unbalance_response(w, u.plane, u.s, u.angle, at=p) for u in rot.unbalances)
        fwd, bwd = (XY[0] + 1j * XY[1]) / 2, np.conj(XY[0] - 1j * XY[1]) / 2
        out["planes"][p] = {"forward_amplitude_m": float(abs(fwd)),
                            "backward_amplitude_m": float(abs(bwd)),
                            "phase_deg": float(np.degrees(np.angle(fwd)))}
    return out


#: work the Floquet scan may spend, in state-steps (integration steps x state size) of its
#: one-revolution flows: the sample scenes need 1e4-5e7 (a ten-mode flexible shaft, ~1 min);
#: an input that would need more stops with BudgetExceeded (exit 1)
FLOQUET_BUDGET = 100_000_000


def _floquet_scan(scene, ranges: dict, lo: float, hi: float, n: int = 14) -> dict:
    """Main-motion critical speeds by Floquet continuation from the operating speed, under
    the work budget :data:`FLOQUET_BUDGET`."""
    from stand.errors import Budget
    from stand.theories.rotor_stability import step_budget

    with step_budget(Budget("the Floquet scan (one-revolution flows of the main motion)",
                            FLOQUET_BUDGET, "state-steps")):
        return _floquet_scan_within(scene, ranges, lo, hi, n)


def _floquet_scan_within(scene, ranges: dict, lo: float, hi: float, n: int) -> dict:
    from stand.errors import BudgetExceeded
    from stand.theories.rotor_stability import _state_guess, main_motion_critical_speeds, main_motion_stability

    w0 = scene.operating_speed
    if not w0 > 0:
        return {"note": "operating speed 0: no main motion to continue"}
    rotor = scene.linear_rotor()
    s = sum(abs(u.s) for u in rotor.unbalances) or 1.0
    try:
        r0 = main_motion_stability(rotor, scene.weights, w0)
    except BudgetExceeded:
        raise
    except (RuntimeError, np.linalg.LinAlgError) as exc:
        return {"note": f"Floquet analysis failed at the operating speed: {exc}"}
    if r0.residual_unbalance > 0.05 * s:
        return {"note": "the weights do not reach a main motion at the operating speed "
                        f"(residual {r0.residual_unbalance:.3g} kg m): Floquet scan skipped"}
    # (with gravity in the balancer plane the "main motion" is the periodic motion
    # near balance: the weights swing once per revolution, the residual is not 0)
    crits = sorted(c * 2 * math.pi for d in ranges.values() for c in d["critical_speeds_hz"])
    lo_s = 0.5 * crits[0] if crits else 0.3 * w0
    hi_s = min(hi, 2.0 * max(crits[-1], w0)) if crits else 3.0 * w0
    g = _state_guess(rotor, scene.weights, r0, w0)
    found, lost = [], []
    for grid in (np.geomspace(w0, max(lo_s, lo), n), np.geomspace(w0, hi_s, n)):
        try:
            out, c = main_motion_critical_speeds(rotor, scene.weights, grid, y_guess=g,
                                                 xtol=1e-5)
        except BudgetExceeded:
            raise
        except (RuntimeError, np.linalg.LinAlgError):
            continue
        found += list(c)
        if len(out) >= 2 and not out[-1].converged:     # the main motion ends there
            lost.append((out[-2].omega + out[-1].omega) / (4 * math.pi))
    return {"operating_speed_hz": w0 / (2 * math.pi),
            "growth_rate_at_operating_speed_per_s": r0.growth_rate,
            "critical_speeds_hz": sorted(f / (2 * math.pi) for f in found),
            "ends_hz": sorted(lost),
            "method": "Floquet multipliers of the one-revolution map, continuation from the "
                      "operating speed (finite weight masses included); ends_hz: where the "
                      "continued main motion ends (no periodic orbit beyond, a fold: the "
                      "growth rate goes to 0 there; the scan stops)"}


def _generalised(rot, planes, lo: float, hi: float) -> dict:
    """The generalised criterion of several balancer planes (paper 003 (1)/(24)-(26)):
    the revolution-averaged form of the elementary unbalances of all planes,
    :meth:`LinearRotor.criterion_matrix`, must be negative definite (for two planes of
    a rigid rotor: K_xi and K_eta negative definite); its working ranges and the speeds
    where its definiteness changes (the onsets and losses)."""
    crit, rg = generalised_working_ranges(rot, planes, lo, hi)
    edges = sorted({x for r in rg for x in r if math.isfinite(x) and x > lo})
    return {"planes": list(planes),
            "condition": "criterion matrix (paper 003 (24)-(26)) negative definite"
                         + (" <=> K_xi and K_eta negative definite (rigid rotor, two planes)"
                            if rot.n == 4 and len(planes) == 2 else ""),
            "onsets_hz": [e / (2 * math.pi) for e in edges],
            "eigenvalue_sign_changes_hz": [c / (2 * math.pi) for c in crit],
            "working_ranges_hz": [[a / (2 * math.pi), b / (2 * math.pi)] for a, b in rg],
            "method": "inertia of LinearRotor.criterion_matrix on a grid with the synchronous "
                      "poles bracketed on both sides; each change located by bisection to 1e-13"}


def family_theory(scene, max_speed: float | None = None, floquet: bool = True) -> dict:
    """Natural frequencies, Campbell data and the criterion's working ranges per plane;
    with two or more balancer planes also the generalised criterion (``generalised_criterion``:
    working ranges and the speeds where the criterion matrix changes definiteness).

    ``max_speed`` [rad/s]: upper end of the scan (default 4 x the largest of the
    natural frequencies at rest and the programme's top speed).
    """
    rot = with_locked_weights(scene.linear_rotor(), scene.weights, scene.bodies)
    wn0 = rot.natural_frequencies(0.0)
    top = scene.top_speed
    hi = max_speed or 4.0 * max(float(wn0.max()) if wn0.size else 1.0, top)
    lo = 1e-3 * hi
    # the planes with weights; without weights the rotor's balancer (correction) planes, where
    # a balancer would sit (e.g. the two-screen balancing sample), else the main plane
    correction = [p for p in rot.planes if p.startswith("balancer")]
    planes = sorted({w.plane for w in tuple(scene.weights) + tuple(scene.bodies)}
                    or set(correction) or {scene.main_plane})
    ranges = {}
    for p in planes:
        crit, rg = working_ranges(rot, p, lo, hi)
        ranges[p] = {"critical_speeds_hz": [c / (2 * math.pi) for c in crit],
                     "working_ranges_hz": [[a / (2 * math.pi), b / (2 * math.pi)] for a, b in rg]}
    general = _generalised(rot, planes, lo, hi) if len(planes) >= 2 else None
    speeds = np.linspace(0.0, hi, 41)
    camp = rot.campbell(speeds)
    main = _floquet_scan(scene, ranges, lo, hi) if (floquet and scene.weights) else None
    kind = scene.structure_type
    return {
        "scene": scene.name, "rotor_type": kind,
        "source": ROTOR_TYPES[kind][1] if kind in ROTOR_TYPES else "5.1, (5.1)-(5.10)",
        "coords": list(rot.coords),
        "natural_frequencies_hz_at_rest": [w / (2 * math.pi) for w in wn0],
        "engineering_criterion": ranges,
        "generalised_criterion": general,
        "main_motion": main,
        "steady_response_without_weights": _steady(scene, rot),
        "campbell": {"speed_hz": (speeds / (2 * math.pi)).tolist(),
                     "frequencies_hz": (camp / (2 * math.pi)).tolist()},
        "notes": ["weights locked in their planes (their mass included)",
                  "working ranges: engineering criterion (2.15), the m/M -> 0 limit; finite "
                  "weight masses shift the edges (digest ch2_ch3 section 7.4)"],
    }
