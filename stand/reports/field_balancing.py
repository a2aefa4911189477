"""The field-balancing report (``stand balance JOB.toml -o REPORT.html [--pdf REPORT.pdf]``).

From a :class:`~stand.analysis.field_balance.FieldBalance`: the verdict (corrections, worst
vibration before and predicted after, conditioning, ISO 21940-11 grade when the rotor mass,
speed and radii are known), the runs table, one polar plot per sensor and speed (the
reference vibration, the trial runs and the predicted vibration after correction), the
corrections with the holes to use, and the influence matrix.  HTML through
:func:`stand.reports.html.write_report`, PDF through :func:`stand.reports.pdf.write_pdf`.
"""
from __future__ import annotations

import math

from stand.io.numbers import plain, with_uncertainty

__all__ = ["field_report", "write_field_report"]


def _polar_text(a, deg, unit="", a_std=None, deg_std=None):
    """``a ± s unit at deg ± s °`` with the one formatter (:mod:`stand.io.numbers`); an
    amplitude-only reading (``deg`` None) without the angle."""
    if deg is None:
        return with_uncertainty(a, a_std, unit)
    return (f"{with_uncertainty(a, a_std, unit)} at "
            f"{with_uncertainty(deg, deg_std, '°', resolution=False)}")


def _banner(res) -> dict:
    mu, vu, amp = res["mass_unit"], res["vibration_unit"], res["amplitude"]
    corr = "; ".join(f"{p}: {_polar_text(c['mass'], c['angle_deg'], mu, c.get('mass_std'), c.get('angle_std_deg'))}"
                     for p, c in res["corrections"].items())
    lines = [f"worst vibration {plain(res['worst_before'], f'{vu} {amp}')} before, "
             f"{plain(res['worst_after'], f'{vu} {amp}')} predicted after ({res['method']})",
             f"influence matrix condition {plain(res['condition'], sig=3)}"]
    lines += [f"warning: {w}" for w in res["warnings"]]
    iso = res.get("iso")
    status = "fail" if res["warnings"] else "info"
    if iso:
        lines.append(f"initial unbalance {plain(iso['initial_unbalance_g_mm'], 'g·mm')} "
                     f"({iso['initial_grade']}); after correction within its uncertainty "
                     f"{plain(iso['correction_uncertainty_g_mm'], 'g·mm', sig=3)} ({iso['after_grade']})")
        if iso.get("passed") is not None:
            status = "pass" if iso["passed"] and not res["warnings"] else "fail"
    for p, c in res["corrections"].items():
        if "split" in c:
            lines.append(f"{p} on holes: " + " + ".join(
                f"{plain(h['mass'], mu)} in hole {h['hole']} ({plain(h['angle_deg'], '°')})"
                for h in c["split"]))
    return {"status": status, "headline": f"corrections {corr}", "lines": lines}


def _figures(res) -> dict:
    from matplotlib.figure import Figure

    from stand.reports.html import figure_png

    figs = {}
    vu = res["vibration_unit"]
    for r in res["residuals"]:
        fig = Figure(figsize=(4.2, 4.2))
        ax = fig.add_subplot(projection="polar")
        pts = []
        for run in res["runs"]:
            if run["kind"] == "slow_roll":
                continue
            same = (r["speed_rpm"] is None or run["speed_rpm"] is None
                    or abs(run["speed_rpm"] - r["speed_rpm"]) <= 0.01 * r["speed_rpm"])
            rd = run["readings"].get(r["sensor"])
            if same and rd and run["kind"] == "trial" and rd["angle_deg"] is not None:
                pts.append((math.radians(rd["angle_deg"]), rd["amplitude"], f"run {run['run']}"))
        ax.plot([0, math.radians(r["before_deg"])], [0, r["before"]], "o-", color="#b00",
                label="before")
        ax.plot([0, math.radians(r["after_deg"])], [0, r["after"]], "s-", color="#070",
                label="predicted after")
        for th, a, lab in pts:
            ax.plot([th], [a], "^", color="#888")
            ax.annotate(lab, (th, a), fontsize=7)
        at = f" at {plain(r['speed_rpm'], 'rpm', sig=6)}" if r["speed_rpm"] is not None else ""
        ax.set_title(f"{r['sensor']}{at} [{vu} {res['amplitude']}]", fontsize=9)
        ax.legend(fontsize=7, loc="lower right")
        figs[f"{r['sensor']}{at}: vibration before and predicted after"] = figure_png(fig)
    return figs


def field_report(res) -> dict:
    """The report's document: verdict, corrections, residuals, runs, influence, ISO grade."""
    mu, vu = res["mass_unit"], res["vibration_unit"]
    corrections = []
    for p, c in res["corrections"].items():
        row = {"plane": p, f"mass_{mu}": c["mass"], f"mass_std_{mu}": c["mass_std"],
               "angle_deg": c["angle_deg"], "angle_std_deg": c["angle_std_deg"]}
        if "radius_mm" in c:
            row["radius_mm"] = c["radius_mm"]
            row["unbalance_g_mm"] = c["unbalance_g_mm"]
        if "split" in c:
            row["holes"] = " + ".join(f"{plain(h['mass'], mu)} in hole {h['hole']} "
                                      f"({plain(h['angle_deg'], '°')})" for h in c["split"])
        if "weights" in c:
            row["weights_at_hand"] = " + ".join(
                f"{'+'.join(plain(x) for x in w['pieces'])} {mu} "
                + (f"in hole {w['hole']} " if w["hole"] is not None else "")
                + f"({plain(w['angle_deg'], '°')})" for w in c["weights"]["placed"]) \
                + f"; off by {plain(c['weights']['error'], mu, sig=3)}"
        corrections.append(row)
    runs = []
    for r in res["runs"]:
        runs.append({"run": r["run"], "kind": r["kind"],
                     "speed_rpm": r["speed_rpm"],
                     "trial": ", ".join(f"{p} {_polar_text(t['mass'], t['angle_deg'], mu)}"
                                        for p, t in r["trial"].items())
                     + ("" if r["removed"] or not r["trial"] else " (left on)"),
                     "readings": ", ".join(f"{s} {_polar_text(v['amplitude'], v['angle_deg'], '', v['std'] or None)}"
                                           for s, v in r["readings"].items())})
    residuals = [{"sensor": r["sensor"], "speed_rpm": r["speed_rpm"],
                  f"before_{vu}": r["before"], "before_deg": r["before_deg"],
                  f"after_{vu}": r["after"], "after_deg": r["after_deg"]}
                 for r in res["residuals"]]
    influence = [{"speed_rpm": e["speed_rpm"], "sensor": e["sensor"], "plane": e["plane"],
                  f"{vu}_per_{mu}": e["amplitude"], "angle_deg": e["angle_deg"]}
                 for e in res["influence"]]
    doc = {"job": res["job"], "method": res["method"], "solver": res["solver"],
           "vibration": f"{vu} {res['amplitude']}", "mass_unit": mu,
           "corrections": corrections, "residuals": residuals, "runs": runs,
           "influence": influence, "condition": res["condition"],
           "warnings": res["warnings"]}
    if res.get("iso"):
        doc["iso_21940_11"] = res["iso"]
    return doc


def write_field_report(res, html_path=None, pdf=None, json_path=None) -> dict:
    """Write the field-balancing report (HTML and/or PDF, JSON); return its document."""
    from stand.reports.html import write_report

    doc = field_report(res)
    banner = _banner(res)
    figs = _figures(res)
    sections = ["corrections", "residuals", "runs", "influence", "iso_21940_11", "condition",
                "warnings", "job", "method", "solver", "vibration", "mass_unit"]
    out = write_report("Field balancing", doc, html_path=html_path, json_path=json_path,
                         figures=figs, sections=[k for k in sections if k in doc], banner=banner)
    if pdf:
        from stand.reports.pdf import write_pdf

        def rows(records):
            return [(f"{k}", ", ".join(f"{kk}={_short(v)}" for kk, v in r.items()))
                    for k, r in ((str(i), r) for i, r in enumerate(records))]

        tables = [("corrections", rows(doc["corrections"])), ("residuals", rows(doc["residuals"])),
                  ("runs", rows(doc["runs"])), ("influence", rows(doc["influence"]))]
        if doc.get("iso_21940_11"):
            tables.append(("ISO 21940-11", [(k, _short(v)) for k, v in doc["iso_21940_11"].items()]))
        write_pdf(pdf, "Field balancing", banner, figs, tables)
    return out


def _short(v) -> str:
    return plain(v, sig=6) if isinstance(v, float) else str(v)
