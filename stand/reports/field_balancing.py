"""The field-balancing report a customer receives (``stand balance JOB.toml -o REPORT.html
[--pdf REPORT.pdf]``), from a :class:`~stand.analysis.field_balance.FieldBalance`.

The verdict banner first (PASS / FAIL of each plane's residual unbalance and each sensor's
vibration against its limit, :mod:`stand.analysis.field_verdict`; without limits, the
corrections), then the sections, each a table of several values (a section that would hold
one value or none is left out): the corrections ("put 1.979 ± 0.031 g at 236.17 ± 0.90 °",
the holes) with a drawing of each plane; the verdict per limit; the vibration at the sensors
with a polar plot each; the static and couple parts of a two-plane correction; the influence
matrix with its condition; the runs (each reading with its unit, the trial-validity
verdict); the check run and trim; the ISO 21940-11 grades; the warnings (only if any); the
job.  Numbers are rounded to their ± (:mod:`stand.io.numbers`); a predicted zero is "0
(exactly determined)".  The PDF (:func:`stand.reports.pdf.write_pdf`) holds the same rows.
"""
from __future__ import annotations

import html

from stand.io.numbers import plain, with_uncertainty

__all__ = ["field_sections", "write_field_report"]


def _polar(a, deg, unit="", a_std=None, deg_std=None) -> str:
    """``a ± s unit at deg ± s °``; without the angle when ``deg`` is None (no phase)."""
    text = with_uncertainty(a, a_std or None, unit)
    if deg is None or (deg_std is not None and deg_std >= 90.0):
        return text
    return f"{text} at {with_uncertainty(deg, deg_std or None, '°', resolution=False)}"


def _vib(value, deg, std, unit, exact=False) -> str:
    if exact and value == 0.0:
        return f"0 {unit} (exactly determined" + (f"; ± {plain(std, sig=2)} from the correction's ±)"
                                                  if std else ")")
    return _polar(value, deg, unit, std)


def _banner(res) -> dict:
    mu = res["mass_unit"]
    put = [f"{p}: put {_put(c, mu)}" for p, c in res["corrections"].items()]
    v = res.get("verdict")
    if v:
        head, lines = v["headline"], v["lines"]
        status = "pass" if v["passed"] else "fail"
    else:
        head, lines, status = "No verdict: the job gives no limit (grade, max_vibration, " \
                              "machine_class)", [], "info"
    lines = put + lines + [f"warning: {w}" for w in res["warnings"]]
    return {"status": status, "headline": head, "lines": lines}


def _put(c, mu) -> str:
    text = _polar(c["mass"], c["angle_deg"], mu, c["mass_std"], c["angle_std_deg"])
    if c.get("split"):
        text += (f" (holes {' and '.join(str(h['hole']) for h in c['split'])}: "
                 + " + ".join(plain(h["mass"], mu) for h in c["split"]) + ")")
    return text


def field_sections(res) -> list:
    """``[(id, title, columns, rows)]``: the report's tables as text cells (module docstring);
    sections with fewer than two values are left out."""
    mu, vu, amp = res["mass_unit"], res["vibration_unit"], res["amplitude"]
    unit = f"{vu} {amp}"
    out = []
    rows = []
    for p, c in res["corrections"].items():
        rows.append([p, "put " + _put(c, mu),
                     plain(c["radius_mm"], "mm") if "radius_mm" in c else "",
                     with_uncertainty(c["unbalance_g_mm"], c["mass_std"] * c["radius_mm"],
                                      "g·mm") if "radius_mm" in c else "",
                     " + ".join(f"{'+'.join(plain(x) for x in w['pieces'])} {mu} "
                                + (f"in hole {w['hole']}" if w["hole"] is not None else "")
                                for w in c["weights"]["placed"])
                     + f" (off by {plain(c['weights']['error'], mu, sig=3)})"
                     if "weights" in c else ""])
    out.append(("corrections", "Corrections", ["Plane", "Correction", "Radius", "Unbalance",
                                               "Weights at hand"], rows))
    v = res.get("verdict")
    if v:
        rows = []
        for x in v["unbalance"] + v["vibration"]:
            u = "g·mm" if "plane" in x else x["unit"]
            key = "_g_mm" if "plane" in x else "_value"
            what = (f"{x['plane']} residual unbalance" if "plane" in x
                    else f"{x['sensor']} vibration ({x['limit_source']})")
            cells = [what, plain(x.get("permissible_g_mm", x.get("limit")), u)]
            for k in ("before", "after"):
                val = x[k + key]
                cells.append(("0 (predicted) ± " + plain(x[k + key + "_std"], u, sig=2))
                             if k == "after" and val == 0.0 else
                             with_uncertainty(val, x[k + key + "_std"] or None, u)
                             + (f", zone {x[k]['zone']}" if x[k].get("zone") else ""))
                cells.append(("PASS" if x[k]["passed"] else "FAIL") + ", margin "
                             + with_uncertainty(x[k]["margin"], x[k]["margin_std"] or None, u,
                                                resolution=False))
            rows.append(cells)
        out.append(("verdict_table", "Verdict", ["Limit of", "Limit", "Before", "Before: verdict",
                                                  "Predicted after", "After: verdict"], rows))
    exact = res.get("exactly_determined", False)
    rows = [[r["sensor"], plain(r["speed_rpm"], "rpm", sig=6) if r["speed_rpm"] else "",
             _vib(r["before"], r["before_deg"], r.get("before_std"), unit),
             _vib(r["after"], r["after_deg"], r.get("after_std"), unit, exact)]
            for r in res["residuals"]]
    out.append(("vibration", "Vibration at the sensors", ["Sensor", "Speed", "Before",
                                                           "Predicted after"], rows))
    sc = res.get("static_couple")
    if sc:
        p1, p2 = list(res["corrections"])
        out.append(("static_couple", "Static and couple parts", ["Part", "Correction"], [
            [f"static (the same in {p1} and {p2})", _put(sc["static"], mu)],
            [f"couple (in {p1}; the opposite in {p2})", _put(sc["couple"], mu)]]))
    planes = list(res["corrections"])
    cells = {}
    for e in res["influence"]:
        at = f" at {plain(e['speed_rpm'], 'rpm', sig=6)}" if e["speed_rpm"] else ""
        cells.setdefault(e["sensor"] + at, []).append(
            _polar(e["amplitude"], e["angle_deg"], "", e.get("std")))
    rows = [[s] + c for s, c in cells.items()]
    rows.append(["condition number", plain(res["condition"], sig=3)] + [""] * (len(planes) - 1))
    out.append(("influence", f"Influence matrix [{unit} per {mu}]", ["Sensor"] + planes, rows))
    valid = {t["run"]: t for t in res.get("trial_validity") or []}
    rows = []
    for r in res["runs"]:
        label = f"run[{r['run']}] ({r['kind']})"
        t = valid.get(label)
        rows.append([str(r["run"]), r["kind"],
                     plain(r["speed_rpm"], "rpm", sig=6) if r["speed_rpm"] else "",
                     ", ".join(f"{p} {_polar(m['mass'], m['angle_deg'], mu)}"
                               for p, m in r["trial"].items())
                     + ("" if r["removed"] or not r["trial"] else " (left on)"),
                     "; ".join(f"{s} {_polar(x['amplitude'], x['angle_deg'], unit, x['std'])}"
                               for s, x in r["readings"].items()),
                     "" if t is None else (("valid" if t["valid"] else "NOT valid")
                                           + f": amplitude {plain(t['amplitude_change_pct'], '%', 3)}, "
                                             f"phase {plain(t['phase_change_deg'], '°', 3)}")])
    out.append(("runs", "Runs", ["Run", "Kind", "Speed", "Masses put on", "Readings",
                                 "Trial validity"], rows))
    ck = res.get("check")
    if ck:
        rows = [[r["sensor"], _polar(r["measured"], r["measured_deg"], unit),
                 _polar(r["predicted"], r["predicted_deg"], unit),
                 _vib(r["after_trim"], r["after_trim_deg"], None, unit, True)]
                for r in ck["sensors"]]
        rows.append(["trim"] + ["; ".join(f"{p} {_put(c | {'angle_std_deg': None}, mu)}"
                                          for p, c in ck["trim"].items()), "", ""])
        out.append(("check", f"Check run {ck['run']} and trim", ["Sensor", "Measured",
                                                                   "Predicted", "After trim"], rows))
    iso = res.get("iso")
    if iso:
        out.append(("iso", "ISO 21940-11 grade", ["Quantity", "Value"], [
            ["initial unbalance", f"{plain(iso['initial_unbalance_g_mm'], 'g·mm')} "
                                  f"({iso['initial_grade']})"],
            ["left open by the correction's ±",
             f"{plain(iso['correction_uncertainty_g_mm'], 'g·mm', 2)} ({iso['after_grade']})"],
            ["permissible (whole rotor)", plain(iso["permissible_g_mm"], "g·mm")
             if iso["permissible_g_mm"] else ""]]))
    if res["warnings"]:
        out.append(("warnings", "Warnings", ["No.", "Warning"],
                    [[str(k + 1), w] for k, w in enumerate(res["warnings"])]))
    tm = res.get("trial_mass") or {}
    out.append(("job", "Job", ["Item", "Value"], [
        ["job file", str(res["job"])], ["influence measured by", str(res["influence_measured_by"])]
        if res.get("influence_measured_by") not in (None, res["job"]) else ["", ""],
        ["method, solver", f"{res['method']}, {res['solver']}"],
        ["units", f"vibration {unit}, masses {mu}, angles in degrees ({res['phase']})"],
        ["suggested trial mass", ", ".join(f"{p} {plain(m, mu, 2)}" for p, m in tm.items())]]
        + [["verdict rule", n] for n in (v or {}).get("notes", [])]))
    kept = []
    for sid, title, cols, rows in out:
        keep = [i for i in range(len(cols)) if any(r[i] for r in rows)]
        rows = [[r[i] for i in keep] for r in rows if any(r[i] for i in keep[1:])]
        if sum(bool(x) for r in rows for x in r[1:]) >= 2:
            kept.append((sid, title, [cols[i] for i in keep], rows))
    return kept


def _body(sections, figures) -> str:
    parts = ["<nav class='meta'>" + " · ".join(
        f"<a href='#{sid}'>{html.escape(t)}</a>" for sid, t, _, _ in sections) + "</nav>"]
    figs = {k: [(c, u) for c, u in figures.items() if c.startswith(k)]
            for k in ("plane", "sensor")}
    for sid, title, cols, rows in sections:
        head = "".join(f"<th>{html.escape(c)}</th>" for c in cols)
        body = "".join("<tr>" + "".join(f"<td>{html.escape(x)}</td>" for x in r) + "</tr>"
                       for r in rows)
        parts.append(f"<h2 id='{sid}'>{html.escape(title)}</h2><table><tr>{head}</tr>{body}</table>")
        shown = figs["plane"] if sid == "corrections" else figs["sensor"] if sid == "vibration" else []
        if shown:
            parts.append("<div class='keyfigs'>" + "".join(
                f"<figure><img alt='{html.escape(c)}' src='{u}'><figcaption>{html.escape(c)}"
                f"</figcaption></figure>" for c, u in shown) + "</div>")
    return "\n".join(parts)


def write_field_report(res, html_path=None, pdf=None, json_path=None) -> dict:
    """Write the field-balancing report (HTML and/or PDF, and the answer as JSON); return the
    plain JSON document (the answer's ``to_dict()``)."""
    from stand.reports.field_figures import field_figures
    from stand.reports.html import write_report

    banner = _banner(res)
    figs = field_figures(res)
    sections = field_sections(res)
    out = write_report("Field balancing", res.to_dict(), html_path=html_path,
                       json_path=json_path, figures=figs, banner=banner,
                       body=_body(sections, figs))
    if pdf:
        from stand.reports.pdf import write_pdf

        tables = [(title, [(r[0], "; ".join(f"{c}: {x}" if len(cols) > 2 else x
                                             for c, x in zip(cols[1:], r[1:]) if x))
                           for r in rows]) for _, title, cols, rows in sections]
        write_pdf(pdf, "Field balancing", banner, figs, tables)
    return out
