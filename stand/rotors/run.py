"""Run and theory of a rotor-family scene (``stand run`` / ``stand theory``).

The recording is an HDF5 file written atomically (temporary file in the same
directory, then ``os.replace``): ``time`` [s], ``rotor/angle`` [rad],
``rotor/speed`` [rad/s], ``structure/q`` (one column per coordinate; names and
units in the attribute ``coords``), ``planes/<name>`` (fixed-frame x, y [m]),
``weights/relative_angle`` [rad], ``truth/residual/<plane>`` (rotor frame
[kg m]), the scene text and the solver statistics.  ``shaft/x`` and
``shaft/y`` are the balancer plane's translation, so ``stand analyze`` reads
it like any recording.
"""
from __future__ import annotations

import json
import math
import os
import tempfile
from pathlib import Path

import numpy as np

from .coupled import CoupledRun, simulate_coupled, with_locked_weights
from .scene import ROTOR_TYPES, FamilyScene
from .structure import working_ranges

__all__ = ["run_family", "write_family_recording", "family_theory"]


def run_family(scene: FamilyScene) -> CoupledRun:
    """Integrate the scene (compiled DOP853, :func:`stand.rotors.coupled.simulate_coupled`)."""
    r = scene.run
    return simulate_coupled(scene.rotor, scene.weights, scene.programme, r.duration, r.sample_rate,
                            rtol=r.rtol, atol=r.atol, max_steps=r.max_steps)


def _main_plane(scene: FamilyScene) -> str:
    if scene.weights:
        return scene.weights[0].plane
    return "balancer" if "balancer" in scene.rotor.planes else next(iter(scene.rotor.planes))


def write_family_recording(scene: FamilyScene, run: CoupledRun, path) -> Path:
    import h5py

    path = Path(path)
    fd, tmp = tempfile.mkstemp(dir=str(path.resolve().parent), prefix=f".{path.name}.", suffix=".tmp")
    os.close(fd)
    try:
        with h5py.File(tmp, "w") as f:
            f.attrs["format"] = "autobalancer-stand rotor-family recording 1"
            f.attrs["scene_text"] = scene.text
            f.attrs["rotor_type"] = scene.rotor_type
            f.attrs["solver"] = json.dumps(run.stats)

            def ds(name, a, units, desc=""):
                d = f.create_dataset(name, data=np.asarray(a, dtype=float))
                d.attrs["units"] = units
                if desc:
                    d.attrs["description"] = desc

            ds("time", run.t, "s", "sample time")
            ds("rotor/angle", run.rotor_angle, "rad", "angle of the reference mark")
            ds("rotor/speed", run.speed, "rad/s", "rotor spin")
            q = f.create_dataset("structure/q", data=run.q)
            q.attrs["coords"] = json.dumps(list(scene.rotor.coords))
            q.attrs["units"] = "per coordinate (see coords)"
            for p, xy in run.planes.items():
                ds(f"planes/{p}", xy, "m", f"fixed-frame translation of plane {p}")
            main = _main_plane(scene)
            ds("shaft/x", run.planes[main][:, 0], "m", f"plane {main}, fixed X")
            ds("shaft/y", run.planes[main][:, 1], "m", f"plane {main}, fixed Y")
            ds("weights/relative_angle", run.weight_angle, "rad", "weights' angles from the mark")
            for p, U in run.residual.items():
                ds(f"truth/residual/{p}", U, "kg*m", f"total unbalance in plane {p}, rotor frame")
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)
    return path


def _steady(scene: FamilyScene, rot) -> dict:
    """1X response of every plane to the rotor's unbalances at the operating speed
    (weights locked, i.e. the rotor as it would run without balancing)."""
    w = float(scene.programme[-1, 1])
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


def _floquet_scan(scene: FamilyScene, ranges: dict, lo: float, hi: float, n: int = 14) -> dict:
    """Main-motion critical speeds by Floquet continuation from the operating speed."""
    from .stability import _state_guess, main_motion_critical_speeds, main_motion_stability

    w0 = float(scene.programme[-1, 1])
    if not w0 > 0:
        return {"note": "operating speed 0: no main motion to continue"}
    s = sum(abs(u.s) for u in scene.rotor.unbalances) or 1.0
    try:
        r0 = main_motion_stability(scene.rotor, scene.weights, w0)
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
    g = _state_guess(scene.rotor, scene.weights, r0, w0)
    found = []
    for grid in (np.geomspace(w0, max(lo_s, lo), n), np.geomspace(w0, hi_s, n)):
        try:
            _, c = main_motion_critical_speeds(scene.rotor, scene.weights, grid, y_guess=g,
                                               xtol=1e-5)
        except (RuntimeError, np.linalg.LinAlgError):
            continue
        found += list(c)
    return {"operating_speed_hz": w0 / (2 * math.pi),
            "growth_rate_at_operating_speed_per_s": r0.growth_rate,
            "critical_speeds_hz": sorted(f / (2 * math.pi) for f in found),
            "method": "Floquet multipliers of the one-revolution map, continuation from the "
                      "operating speed (finite weight masses included)"}


def family_theory(scene: FamilyScene, max_speed: float | None = None,
                  floquet: bool = True) -> dict:
    """Natural frequencies, Campbell data and the criterion's working ranges per plane.

    ``max_speed`` [rad/s]: upper end of the scan (default 4 x the largest of the
    natural frequencies at rest and the programme's top speed).
    """
    rot = with_locked_weights(scene.rotor, scene.weights)
    wn0 = rot.natural_frequencies(0.0)
    top = float(np.max(scene.programme[:, 1]))
    hi = max_speed or 4.0 * max(float(wn0.max()) if wn0.size else 1.0, top)
    lo = 1e-3 * hi
    planes = sorted({w.plane for w in scene.weights} or {_main_plane(scene)})
    ranges = {}
    for p in planes:
        crit, rg = working_ranges(rot, p, lo, hi)
        ranges[p] = {"critical_speeds_hz": [c / (2 * math.pi) for c in crit],
                     "working_ranges_hz": [[a / (2 * math.pi), b / (2 * math.pi)] for a, b in rg]}
    speeds = np.linspace(0.0, hi, 41)
    camp = rot.campbell(speeds)
    main = _floquet_scan(scene, ranges, lo, hi) if (floquet and scene.weights) else None
    return {
        "scene": scene.name, "rotor_type": scene.rotor_type,
        "source": ROTOR_TYPES[scene.rotor_type][2], "coords": list(rot.coords),
        "natural_frequencies_hz_at_rest": [w / (2 * math.pi) for w in wn0],
        "engineering_criterion": ranges,
        "main_motion": main,
        "steady_response_without_weights": _steady(scene, rot),
        "campbell": {"speed_hz": (speeds / (2 * math.pi)).tolist(),
                     "frequencies_hz": (camp / (2 * math.pi)).tolist()},
        "notes": ["weights locked in their planes (their mass included)",
                  "working ranges: engineering criterion (2.15), the m/M -> 0 limit; finite "
                  "weight masses shift the edges (digest ch2_ch3 section 7.4)"],
    }
