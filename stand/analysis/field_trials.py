"""Trial runs of a field-balancing job: their validity and a suggested trial mass.

A trial run is valid (:data:`TRIAL_RULE`, the field balancers' common rule) when at one
sensor it changes the 1X amplitude by >= 25 % or its phase by >= 30 deg from the run before
its trial; else its influence coefficients are uncertain and it is repeated with a larger
mass.  The suggested trial mass makes a centrifugal force of about 10 % of the rotor weight
carried by the plane: ``m r w^2 = 0.1 M g / P`` [kg, m, rad/s, P planes].
"""
from __future__ import annotations

import math

import numpy as np

__all__ = ["TRIAL_RULE", "trial_validity", "trial_mass"]

#: a trial run is valid when at one sensor it changes the amplitude or the phase this much
TRIAL_AMPLITUDE, TRIAL_PHASE_DEG = 0.25, 30.0
TRIAL_RULE = "amplitude change >= 25 % or phase change >= 30 deg at one sensor"
#: suggested trial mass: its centrifugal force ~10 % of the rotor weight carried by the plane
TRIAL_FORCE = 0.10
G_N = 9.80665                     # standard gravity [m/s^2]


def trial_validity(chain) -> list:
    """Per trial run of a :class:`~stand.analysis.field_balance._Chain` whose influence comes
    from its trial runs: the largest relative amplitude change [%] and phase change [deg] over
    the sensors from the run before its trial, and whether it meets :data:`TRIAL_RULE`."""
    out = []
    for speed, runs, sensors, _, Ak in chain.plan:
        for r, b in chain.baselines(runs) if Ak is None else ():
            da = max(abs(abs(r.readings[s]) - abs(b.readings[s])) / max(abs(b.readings[s]), 1e-300)
                     for s in sensors)
            dp = max(abs(math.degrees(np.angle(r.readings[s] / b.readings[s])))
                     if b.readings[s] != 0 and r.readings[s] != 0 else 180.0 for s in sensors)
            out.append({"run": r.label, "planes": list(r.trial), "amplitude_change_pct": 100 * da,
                        "phase_change_deg": dp,
                        "valid": bool(da >= TRIAL_AMPLITUDE or dp >= TRIAL_PHASE_DEG)})
    return out


def trial_mass(job, groups) -> dict | None:
    """Suggested trial mass per plane [job mass unit]: ``m r w^2 = 0.1 M g / P`` (a
    centrifugal force of 10 % of the rotor weight, shared by the P planes), at the service
    speed (or the highest run speed); None without rotor_mass, a speed and every radius."""
    speeds = [g for g in groups if not math.isnan(g)]
    w = job.service_speed if not math.isnan(job.service_speed) else max(speeds, default=math.nan)
    if math.isnan(job.rotor_mass) or math.isnan(w) or any(p not in job.radius for p in job.planes):
        return None
    P = len(job.planes)
    return {p: TRIAL_FORCE * job.rotor_mass * G_N / P / (job.radius[p] * w * w) / job.mass_factor
            for p in job.planes}
