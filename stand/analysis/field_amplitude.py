"""Field balancing of a job whose readings have no phase (``S1 = "170"``): the four-run method.

One plane; a reference run and trial runs with the trial mass at three or more distinct
angles (each trial removed before the next); one or more sensors.  The solve is
:func:`dsp.amplitude_only.four_run`
(weighted least squares on the circle equations, ± from the readings' resolution).  Vibration
angles in the answer are relative to each sensor's reference vibration (no phase measured).
"""
from __future__ import annotations

import math

import numpy as np

from dsp.amplitude_only import four_run
from dsp.influence_solve import split_onto_holes

from .field_job import FieldJob, reference_sensors

__all__ = ["balance_amplitude_only"]


def balance_amplitude_only(job: FieldJob, method: str = "least_squares") -> dict:
    """The :class:`~stand.analysis.field_balance.FieldBalance` document of an amplitude-only
    job (SI inside, the job's display units out); ``method`` other than the default is
    not used (a warning says so).

    Raises
    ------
    ValueError
        A job the four-run method cannot solve: several planes, slow-roll runs, a trial left
        on, an influence table, not one reference run, fewer than three trial angles.
    """
    if len(job.planes) != 1:
        raise ValueError(f"planes: {', '.join(job.planes)}: amplitude-only readings (no '@ angle') "
                         f"balance one plane (four-run method); for several planes give the "
                         f"readings' phase (\"amplitude @ angle\")")
    plane = job.planes[0]
    if job.influence:
        raise ValueError("influence: a known influence matrix needs phase readings "
                         "(\"amplitude @ angle\"); an amplitude-only job measures its own")
    bad = [r.label for r in job.runs if r.kind == "slow_roll"]
    if bad:
        raise ValueError(f"{bad[0]}: a slow-roll vector cannot be subtracted from amplitude-only "
                         f"readings; remove the run or give phases (\"amplitude @ angle\")")
    trials = [r for r in job.runs if r.kind == "trial"]
    ref, sensors = reference_sensors([r for r in job.runs if r.kind in ("reference", "trial")],
                                     job.sensors, need="the four-run method needs exactly one "
                                     "kind = \"reference\"")
    kept = [r.label for r in trials if not r.removed]
    if kept:
        raise ValueError(f"{kept[0]}.removed = false: the four-run method moves one trial mass; "
                         f"remove it before the next run")
    T = np.array([abs(r.trial[plane]) for r in trials])
    th = np.array([np.angle(r.trial[plane]) for r in trials])
    runs = [ref] + trials
    A = np.array([[r.readings[s].real for r in runs] for s in sensors])
    sig = np.array([[r.std[s] for r in runs] for s in sensors])
    fr = four_run(A[:, 0], A[:, 1:], T, th, sig, sensors=sensors)

    mf = job.mass_factor
    deg = math.degrees
    c = {"mass": fr.mass / mf, "angle_deg": deg(fr.angle_rad) % 360.0,
         "mass_std": fr.mass_std / mf, "angle_std_deg": deg(fr.angle_std_rad)}
    if plane in job.radius:
        c["radius_mm"] = job.radius[plane] * 1e3
        c["unbalance_g_mm"] = fr.mass * job.radius[plane] * 1e6
    if plane in job.holes:
        c["split"] = [{"hole": k, "angle_deg": deg(a), "mass": m / mf}
                      for k, a, m in split_onto_holes(fr.U, job.holes[plane])]
    residuals = [{"sensor": s, "speed_rpm": None, "before": float(job.to_display(fr.a0[i])),
                  "before_deg": 0.0, "after": float(job.to_display(fr.after[i])),
                  "after_deg": deg(np.angle(fr.a0[i] + fr.h[i] * fr.U)) % 360.0}
                 for i, s in enumerate(sensors)]
    scale = job.vib_factor * job.amp_factor / mf
    infl = [{"speed_rpm": None, "sensor": s, "plane": plane,
             "amplitude": float(abs(fr.h[i]) / scale),
             "amplitude_std": float(fr.h_abs_std[i] / scale),
             "angle_deg": deg(np.angle(fr.h[i])) % 360.0} for i, s in enumerate(sensors)]

    return {"job": job.source, "method": "four_run", "solver": "scipy least_squares (amplitudes)",
            "phase": "none", "vibration_unit": job.vibration_unit, "amplitude": job.amplitude,
            "mass_unit": job.mass_unit, "corrections": {plane: c}, "residuals": residuals,
            "worst_before": max(r["before"] for r in residuals),
            "worst_after": max(r["after"] for r in residuals),
            "influence": infl, "condition": 1.0,
            "ill_conditioned": {"planes": [], "sensors": []},
            "warnings": fr.warnings + ([f"method = \"{method}\" not used: amplitude-only readings "
                                        f"are solved by the four-run method"]
                                       if method != "least_squares" else []),
            "runs": [{"run": r.index, "kind": r.kind, "speed_rpm": None,
                      "trial": {p: {"mass": abs(t) / mf, "angle_deg": deg(np.angle(t)) % 360.0}
                                for p, t in r.trial.items()}, "removed": r.removed,
                      "readings": {s: {"amplitude": float(job.to_display(r.readings[s].real)),
                                       "angle_deg": None,     # not measured
                                       "std": float(job.to_display(r.std[s]))}
                                   for s in sensors}}
                     for r in runs],
            "iso": None}
