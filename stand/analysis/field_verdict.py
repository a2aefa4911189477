"""Verdicts of a field-balancing job against its limits, before and predicted after correction.

* **Residual unbalance per plane** (ISO 21940-11): the permissible residual unbalance
  ``U_per = 1000 G M / omega`` [g mm] (G [mm/s], M [kg], omega [rad/s] at the service speed;
  :func:`dsp.unbalance.iso_21940_permissible`) is shared between the planes: for two planes
  with their axial ``position`` and the job's ``centre_of_mass``, by the standard's lever rule
  about the centre of mass, each share within 30-70 % (ISO 21940-11 7.3,
  :func:`dsp.two_plane.iso_two_plane_allocation`); without that geometry **equally**,
  ``U_per / P`` each.  Before: the
  unbalance the correction cancels, ``m_j r_j`` and its ±; predicted after: 0, with what the
  correction leaves open (the rms length of its error vector, ``r_j sqrt(s_m^2 + (m s_a)^2)``).
* **Vibration per sensor**: against ``max_vibration`` (a contract limit, the job's unit and
  amplitude convention) or, for ``machine_class``, the zone B/C boundary (the limit for
  unrestricted long-term operation) of :data:`ZONES`, velocity RMS [mm/s]: ISO 10816-1
  Annex B Table B.1 (classes I-IV) and ISO 10816-3 Tables A.1 / A.2 (groups 1 and 2, rigid
  or flexible foundation), the boundaries ISO 20816-1 / -3 keep.  The 1X reading is
  converted as a sinusoid: amplitude convention to RMS, displacement times omega,
  acceleration divided by omega at the run's speed (the service speed when the runs give
  none; refused without either).  The zones bound the broadband RMS, of which the 1X part
  is a share: a 1X PASS is necessary, not sufficient (said in the notes).

A limit is met (PASS) when the margin ``limit - value`` is at least twice its standard
uncertainty (guarded acceptance, ISO 14253-1 with k = 2); the margin's ± is the value's.
"""
from __future__ import annotations

import math

from stand.io.numbers import plain, with_uncertainty

__all__ = ["ZONES", "ZONE_SOURCE", "K_GUARD", "field_verdict", "verdict_lines", "iso_grades"]

_RPM = 60.0 / (2.0 * math.pi)
#: guarded acceptance: the margin must be at least K_GUARD standard uncertainties
K_GUARD = 2.0
#: zone boundaries A/B, B/C, C/D of velocity RMS [mm/s] per machine class
ZONES = {"I": (0.71, 1.8, 4.5), "II": (1.12, 2.8, 7.1), "III": (1.8, 4.5, 11.2),
         "IV": (2.8, 7.1, 18.0),
         "group1_rigid": (2.3, 4.5, 7.1), "group1_flexible": (3.5, 7.1, 11.0),
         "group2_rigid": (1.4, 2.8, 4.5), "group2_flexible": (2.3, 4.5, 7.1)}
ZONE_SOURCE = {"I": "ISO 10816-1 Table B.1", "group1": "ISO 10816-3 Table A.1",
               "group2": "ISO 10816-3 Table A.2"}


def _source(cls: str) -> str:
    return ZONE_SOURCE["I" if cls in ("I", "II", "III", "IV") else cls.split("_")[0]]


def _zone(v_mm_s: float, cls: str) -> str:
    return "ABCD"[sum(v_mm_s > b for b in ZONES[cls])]


def _check(limit, value, std) -> dict:
    margin = limit - value
    return {"margin": margin, "margin_std": std, "passed": bool(margin >= K_GUARD * std)}


def iso_grades(job, corrections, speed) -> dict | None:
    """ISO 21940-11 grade of the initial unbalance (the corrections' sum of ``m_j r_j``) and of
    the correction's uncertainty, when the rotor mass, a speed [rad/s] and every plane's
    radius are known; None otherwise."""
    from dsp.unbalance import iso_21940_grade

    if math.isnan(job.rotor_mass) or math.isnan(speed) or any(p not in job.radius
                                                               for p in job.planes):
        return None
    mf = job.mass_factor
    U = sum(corrections[p]["mass"] * mf * job.radius[p] * 1e6 for p in job.planes)
    sU = math.sqrt(sum((corrections[p]["mass_std"] * mf * job.radius[p] * 1e6) ** 2
                       for p in job.planes))
    target = None if math.isnan(job.grade) else job.grade
    before = iso_21940_grade(U, job.rotor_mass, speed, target)
    after = iso_21940_grade(sU, job.rotor_mass, speed, target)
    return {"rotor_mass_kg": job.rotor_mass, "service_speed_rpm": speed * _RPM,
            "initial_unbalance_g_mm": U, "initial_grade_mm_s": before.grade_mm_s,
            "initial_grade": before.label,
            "correction_uncertainty_g_mm": sU, "after_grade_mm_s": after.grade_mm_s,
            "after_grade": after.label, "target_grade_mm_s": target,
            "permissible_g_mm": before.permissible_gmm, "passed": after.passed}


def _unbalance(job, corrections, speed) -> list:
    from dsp.unbalance import iso_21940_permissible

    if math.isnan(job.grade):
        return []
    for what, bad in (("job.rotor_mass", math.isnan(job.rotor_mass)),
                      ("job.service_speed", math.isnan(speed))):
        if bad:
            raise ValueError(f"{what}: needed with job.grade = G{job.grade:g} for the ISO "
                             f"21940-11 verdict (give it, e.g. rotor_mass = \"120 kg\", "
                             f"service_speed = \"3000 rpm\")")
    U_per = iso_21940_permissible(job.grade, job.rotor_mass, speed)
    shares = [U_per / len(job.planes)] * len(job.planes)
    if _lever(job):
        from dsp.two_plane import iso_two_plane_allocation

        if len(set(job.position.values())) < 2:
            raise ValueError(f"planes.{job.planes[1]}.position: the same as "
                             f"planes.{job.planes[0]}.position; two planes lie apart")

        shares = iso_two_plane_allocation(U_per, *(job.position[p] for p in job.planes),
                                          centre=job.centre_of_mass)
    out = []
    for p, share in zip(job.planes, shares):
        if p not in job.radius:
            raise ValueError(f"planes.{p}.radius: needed with job.grade for the ISO 21940-11 "
                             f"verdict (the radius the correction mass sits at, e.g. \"150 mm\")")
        c, k = corrections[p], job.mass_factor * job.radius[p] * 1e6     # g mm per mass unit
        after_std = k * math.hypot(c["mass_std"], c["mass"] * math.radians(
            min(c["angle_std_deg"], 180.0)))
        out.append({"plane": p, "permissible_g_mm": share,
                    "before_g_mm": c["mass"] * k, "before_g_mm_std": c["mass_std"] * k,
                    "before": _check(share, c["mass"] * k, c["mass_std"] * k),
                    "after_g_mm": 0.0, "after_g_mm_std": after_std,
                    "after": _check(share, 0.0, after_std)})
    return out


def _lever(job) -> bool:
    """Whether the lever rule applies: two planes with positions and a centre of mass."""
    return (len(job.planes) == 2 and all(p in job.position for p in job.planes)
            and not math.isnan(job.centre_of_mass))


def _vibration(job, residuals, service_speed) -> list:
    vu, amp = job.vibration_unit, job.amplitude
    out = []
    for r in residuals:
        s = r["sensor"]
        cls = job.zone_class.get(s)
        if s not in job.cap and cls is None:
            continue
        w = r["speed_rpm"] / _RPM if r["speed_rpm"] is not None else service_speed
        row = {"sensor": s, "speed_rpm": r["speed_rpm"]}
        zf = None                  # display -> velocity RMS [mm/s] of the 1X sinusoid
        if cls is not None:
            if job.quantity != "velocity" and math.isnan(w):
                raise ValueError(f"sensors.{s}.machine_class = {cls!r}: the zones are in velocity "
                                 f"(mm/s RMS) and the readings in {vu}; give the runs' speed or "
                                 f"job.service_speed to convert the 1X amplitude")
            zf = job.vib_factor * job.amp_factor / math.sqrt(2.0) * 1e3 * {
                "velocity": 1.0, "displacement": w, "acceleration": 1.0 / w}[job.quantity]
        if s in job.cap:
            f, row["unit"] = 1.0, f"{vu} {amp}"
            row["limit"], row["limit_source"] = float(job.to_display(job.cap[s])), "max_vibration"
        else:
            f, row["unit"] = zf, "mm/s RMS"
            row["limit"], row["limit_source"] = ZONES[cls][1], f"{_source(cls)}, {cls}: zone B/C"
        for key in ("before", "after"):
            v, sd = r[key] * f, r.get(f"{key}_std", 0.0) * f
            row[f"{key}_value"], row[f"{key}_value_std"] = v, sd
            row[key] = _check(row["limit"], v, sd)
            if zf is not None:
                row[key]["zone"] = _zone(r[key] * zf, cls)
        out.append(row)
    return out


def field_verdict(job, doc: dict, speed: float) -> dict | None:
    """The verdict of a field-balancing answer ``doc`` (its ``corrections`` and ``residuals``
    with their ±) for ``job`` at the service ``speed`` [rad/s] (NaN: unknown): per plane the
    residual unbalance and per sensor the vibration, before and predicted after, each against
    its limit (module docstring); None when the job gives no limit.  ``passed``: every
    predicted-after check met; ``headline`` and ``lines``: :func:`verdict_lines`."""
    unb = _unbalance(job, doc["corrections"], speed)
    vib = _vibration(job, doc["residuals"], speed)
    if not unb and not vib:
        return None
    after = [x["after"]["passed"] for x in unb + vib]
    notes = [f"PASS: the margin (limit - value) is at least {K_GUARD:g} times its standard "
             f"uncertainty (guarded acceptance, ISO 14253-1)"]
    if unb:
        notes.append(f"ISO 21940-11 G{job.grade:g}: U_per = 1000 G M / omega shared " + (
            "by the lever rule about the centre of mass, each plane 30-70 % (7.3)" if _lever(job)
            else f"equally by the {len(job.planes)} plane(s) (no plane positions and centre of "
                 f"mass in the job)"))
    if any(not r["limit_source"] == "max_vibration" for r in vib):
        notes.append("zones judge the broadband velocity RMS; the 1X vibration is part of it, "
                     "so a 1X PASS is necessary, not sufficient")
    v = {"passed": all(after), "unbalance": unb, "vibration": vib, "notes": notes}
    v["headline"], v["lines"] = verdict_lines(v)
    return v


def verdict_lines(v: dict) -> tuple:
    """(headline, lines) of a verdict as a person reads it: each limit, the value before and
    predicted after with its ±, the margin with its ± and PASS / FAIL."""
    def one(x, key, value, unit):
        c = x[key]
        ok = "PASS" if c["passed"] else "FAIL"
        zone = f", zone {c['zone']}" if c.get("zone") else ""
        val = ("0 (predicted) ± " + plain(x[f"{value}_std"], sig=2) if key == "after"
               and x[value] == 0.0 else with_uncertainty(x[value], x[f"{value}_std"] or None))
        return (f"{key} {val} {unit}{zone}: {ok}, margin "
                f"{with_uncertainty(c['margin'], c['margin_std'] or None, unit, resolution=False)}")

    lines, failed = [], []
    for x in v["unbalance"]:
        lines.append(f"{x['plane']} residual unbalance (limit {plain(x['permissible_g_mm'])} g·mm): "
                     + "; ".join(one(x, k, f"{k}_g_mm", "g·mm") for k in ("before", "after")))
        failed += [x["plane"]] if not x["after"]["passed"] else []
    for x in v["vibration"]:
        at = f" at {plain(x['speed_rpm'], 'rpm', 6)}" if x["speed_rpm"] is not None else ""
        lines.append(f"{x['sensor']}{at} vibration (limit {plain(x['limit'], x['unit'])}, "
                     f"{x['limit_source']}): "
                     + "; ".join(one(x, k, f"{k}_value", x["unit"]) for k in ("before", "after")))
        failed += [x["sensor"]] if not x["after"]["passed"] else []
    head = ("PASS — after correction every plane and sensor is within its limit" if v["passed"]
            else f"FAIL — after correction {', '.join(failed)} not within the limit")
    return head, lines
