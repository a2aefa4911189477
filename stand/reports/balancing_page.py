"""The balancing report as an engineer reads it: the verdict first, then the figures that
show it, then labelled tables; built from the report's JSON only.

* :func:`verdict` -- the banner: pass / fail of ISO 21940-11 at the service speed,
  achieved vs required grade, residual vs permissible (g·mm and fraction), per
  plane for two-plane work; the machine, date, software and recording file.
* :func:`page_body` -- the key figures (polar before/after with the permissible
  circle, orbit with the rings, 1X vs speed), the summary tables with human labels
  and units (:mod:`.labels`) and values rounded to their uncertainty
  (:mod:`.numbers`); critical speeds from the theory, from the recording's 1X
  resonance, and the weights' synchrony events in separate tables; the detail
  tables collapsed (``<details>``), every field of the JSON among them.
* :func:`pdf_tables` -- the same rows as text for the PDF.
"""
from __future__ import annotations

import html
from typing import Mapping

from stand.io.labels import label
from stand.io.numbers import plain, with_uncertainty
from stand.reports.tables import details as _details
from stand.reports.tables import figure as _figure
from stand.reports.tables import list_table as _list_table
from stand.reports.tables import nested as _nested
from stand.reports.tables import rows as _rows
from stand.reports.tables import show
from stand.reports.tables import table as _table

__all__ = ["verdict", "page_body", "pdf_tables", "show"]

_MAIN_FIGS = ("polar", "orbit", "1X amplitude")


def _fmt_rpm(rpm):
    return plain(rpm, "rpm", sig=4) if rpm is not None else "the service speed"


def verdict(doc: Mapping) -> dict:
    """The banner dict of :func:`stand.reports.html.banner_html` for a balancing report."""
    bq = doc.get("balancing_quality") or {}
    iso = bq.get("iso_21940_11") or {}
    hd = doc.get("header") or {}
    rep = doc.get("report") or {}
    G = iso.get("required_grade_mm_s")
    rpm = iso.get("service_speed_rpm")
    passed = iso.get("passed")
    two = doc.get("two_plane")
    if two and isinstance(two.get("iso_21940_11"), Mapping):
        passed = two["iso_21940_11"].get("passed")
    where = f"G{plain(G, sig=2)} at {_fmt_rpm(rpm)}" if G else "ISO 21940-11"
    if passed is True:
        status, headline = "pass", f"PASS — {where}: the residual unbalance is within the permissible"
    elif passed is False:
        status, headline = "fail", f"FAIL — {where}: the residual unbalance exceeds the permissible"
    else:
        status, headline = "info", f"No verdict — {where} not evaluated (see the notes)"
    lines = []
    U, sU, Up = bq.get("residual_unbalance_gmm"), bq.get("residual_unbalance_gmm_std"), \
        iso.get("permissible_residual_gmm")
    if iso.get("achieved_grade_mm_s") is not None:
        lines.append(f"Achieved grade {show('achieved_grade_mm_s', iso['achieved_grade_mm_s'], iso.get('achieved_grade_mm_s_std'))}"
                     f" (class {iso.get('achieved_class')}); required G{plain(G, sig=2)} mm/s")
    if U is not None:
        shown = show("residual_unbalance_gmm", U, sU)
        if shown.startswith("below resolution") or not Up:
            frac = "; the permissible is"
        else:
            frac = f" = {plain(100 * U / Up, '%', sig=2)} of the permissible"
        lines.append(f"Residual unbalance {shown}{frac} "
                     f"{plain(Up, 'g·mm', sig=3) if Up else 'not known'}")
    if two:
        for p in two.get("planes", []):
            lines.append(f"Plane {p.get('plane')}: {show('unbalance_gmm', p.get('unbalance_gmm'), p.get('unbalance_gmm_std'))}"
                         f" at {show('angle_deg', p.get('angle_deg'), p.get('angle_deg_std'))}; permissible "
                         f"{plain(p.get('permissible_gmm'), 'g·mm', sig=3)}: "
                         f"{'pass' if p.get('passed') else 'FAIL'}")
    if bq.get("uncertainty_statement"):
        lines.append(bq["uncertainty_statement"])
    rotor = hd.get("scene_name") or "—"
    if hd.get("description"):
        rotor += f" — {hd['description']}"
    if hd.get("rotor_mass_kg") is not None:
        rotor += f"; rotor mass {plain(hd['rotor_mass_kg'], 'kg')}"
    lines.append(f"Rotor: {rotor}")
    lines.append(f"Recording: {rep.get('recording', '—')} · report generated "
                 f"{rep.get('generated', '—')} by {rep.get('generator', 'stand')}")
    return {"status": status, "headline": headline, "lines": lines}


QUALITY_KEYS = ("residual_unbalance_gmm", "residual_unbalance_angle_deg", "specific_unbalance_um",
                "uncertainty_statement",
                "unbalance_method", "residual_zone_label", "initial_unbalance_gmm",
                "initial_unbalance_source",
                "residual_speed_hz", "response_1x_m", "truth_residual_unbalance_gmm")
ISO_KEYS = ("required_grade_mm_s", "service_speed_rpm", "permissible_residual_gmm",
            "permissible_specific_unbalance_um", "achieved_grade_mm_s", "achieved_class", "passed")


def _given(rows: list) -> list:
    """The summary rows that hold a value (what was not obtained is under All fields and in
    the notes, not a column of dashes)."""
    return [r for r in rows if r[1] != "—"]


def vibration_rows(bq: Mapping) -> list:
    """The 1X as the sensors measure it (their unit and amplitude convention) and as ISO 20816
    vibration velocity (``vibration_1x`` of the analysis); the displacement is the
    ``response_1x_m`` row."""
    v = bq.get("vibration_1x") or {}
    out = []
    if v.get("unit") and v.get("quantity") != "displacement" and v.get("value") is not None:
        std = v.get("value_std")
        out.append((f"1X {v['quantity']} as the sensors measure it ({v.get('convention')})",
                    plain(v["value"], v["unit"]) if std is None
                    else with_uncertainty(v["value"], std, v["unit"])))
    if v.get("velocity_rms_mm_s") is not None:
        out.append((label("velocity_rms_mm_s"), show("velocity_rms_mm_s", v["velocity_rms_mm_s"],
                                                      v.get("velocity_rms_mm_s_std"))))
    return out


def _critical_speeds(rows: list) -> str:
    """Three tables: theory, the recording's 1X resonance, the weights' synchrony events."""
    theory = [r for r in rows if str(r.get("source", "")).startswith("theory")]
    resonance = [r for r in rows if "resonance" in str(r.get("source", ""))]
    sync = [r for r in rows if "synchrony" in str(r.get("source", ""))]
    other = [r for r in rows if r not in theory and r not in resonance and r not in sync]
    parts = []
    if theory:
        parts.append("<h3>Critical speeds from the theory</h3>" + _list_table(
            [{k: v for k, v in r.items() if k not in ("nearest_theory_hz", "difference_hz")}
             for r in theory]))
    if resonance:
        parts.append("<h3>Critical speed from the recording (1X resonance of the run)</h3>"
                     + _list_table([{k: v for k, v in r.items()
                                     if k not in ("nearest_theory_hz", "difference_hz")}
                                    for r in resonance]))
    if sync:
        parts.append("<h3>Weights gaining or losing synchrony during the run</h3>"
                     "<p>These are not critical speeds: during a run-up the weights lag and "
                     "gain synchrony above the critical speed of a slow speed change.</p>"
                     + _list_table([{k: v for k, v in r.items()
                                     if k not in ("nearest_theory_hz", "difference_hz")}
                                    for r in sync]))
    if other:
        parts.append(_list_table(other))
    return "".join(parts)


def single_plane_applies(doc: Mapping) -> bool:
    """False for two-plane work where the single-plane quality was not identified (its table
    would be dashes): the report leaves that section out."""
    bq = doc.get("balancing_quality") or {}
    return not (doc.get("two_plane") and bq.get("residual_unbalance_gmm") is None)


def page_body(doc: Mapping, figures: Mapping | None = None) -> str:
    """The HTML after the banner (module docstring); ``figures`` = ``{caption: PNG data URI}``."""
    figures = dict(figures or {})
    parts = ["<nav class='meta'>" + " · ".join(
        f"<a href='#{a}'>{t}</a>" for a, t in (("figures", "Figures"),
                                              ("quality", "Balancing quality")
                                              if single_plane_applies(doc) else
                                              ("two_plane", "Two-plane balancing"),
                                              ("analysis", "Identification"),
                                              ("dynamics", "Dynamics"), ("warnings", "Warnings and notes"),
                                              ("details", "All fields"))) + "</nav>"]
    main = [(c, u) for c, u in figures.items() if any(c.startswith(m) for m in _MAIN_FIGS)]
    if main:
        parts.append("<h2 id='figures' class='first'>Key figures</h2><div class='keyfigs'>"
                     + "".join(_figure(c, u) for c, u in main) + "</div>")
    bq = doc.get("balancing_quality") or {}
    iso = bq.get("iso_21940_11") or {}
    if single_plane_applies(doc):
        parts.append("<h2 id='quality'>Balancing quality</h2>")
        parts.append(_table(_given(_rows(bq, QUALITY_KEYS)) + vibration_rows(bq)))
        parts.append("<h3>ISO 21940-11</h3>" + _table(_given(_rows(iso, ISO_KEYS))))
    red = bq.get("reduction") or {}
    if red.get("applicable"):
        f, lb = red.get("factor"), red.get("factor_lower_bound")
        pct = red.get("percent")
        pct_text = "> 99.99 %" if pct is not None and pct > 99.99 else plain(pct, "%", sig=4)
        parts.append("<h3>Unbalance reduction by the balancer</h3>" + _table([
            ("Reduction factor", show("factor", f, red.get("factor_std"))
             + (f" (at least {plain(lb, sig=2)})" if lb else "")),
            ("Reduction", pct_text + " · " + plain(red.get("decibel"), "dB", sig=3)),
            ("Basis", str(red.get("basis", "")))]))
    if bq.get("seed_criteria"):
        parts.append("<h3>Criteria of the seed documents</h3>" + _list_table(bq["seed_criteria"]))
    if bq.get("ring_reading"):
        parts.append(_details("Reading against the calibration rings", _table(_rows(bq["ring_reading"]))))
    two = doc.get("two_plane")
    if two:
        parts.append("<h2 id='two_plane'>Two-plane balancing</h2>"
                     + _list_table(two.get("planes", []),
                                   ["plane", "unbalance_gmm", "angle_deg", "correction_angle_deg",
                                    "permissible_gmm", "passed", "passed_with_uncertainty"])
                     + _details("Screens and method", _nested({k: v for k, v in two.items()
                                                               if k != "planes"})))
    a = doc.get("analysis") or {}
    parts.append("<h2 id='analysis'>Identification (stand analyze)</h2>"
                 "<p>Every identified number of this report is stand analyze's; its whole "
                 "document is under All fields.</p>" + _table(_given(_rows(a, (
                     "speed_source", "natural_frequency_method", "critical_speed_method")))))
    if a.get("modes"):
        parts.append("<h3>Resonances fitted in the table</h3>" + _list_table(a["modes"]))
    excluded = (a.get("input") or {}).get("excluded")
    if excluded:
        parts.append("<h3>Rows left out of the analysis</h3>" + _list_table(excluded))
    dyn = doc.get("dynamics") or {}
    parts.append("<h2 id='dynamics'>Dynamics</h2>")
    nf = dyn.get("natural_frequency") or {}
    parts.append(_table(_given(_rows(nf) + [(label("final_regime"),
                                             show("final_regime", dyn.get("final_regime")))])))
    if dyn.get("critical_speeds"):
        parts.append(_critical_speeds(dyn["critical_speeds"]))
    if dyn.get("regime_timeline"):
        parts.append(_details(label("regime_timeline"), _list_table(dyn["regime_timeline"])))
    if dyn.get("settling"):
        parts.append(_details(label("settling"), _list_table(dyn["settling"])))
    parts.append("<h2 id='warnings'>Warnings and notes</h2>")
    warns = doc.get("warnings") or []
    parts.append(_list_table(warns, ["severity", "message", "code"]) if warns else "<p>No warnings.</p>")
    notes = doc.get("notes") or []
    if notes:
        parts.append(_details(f"Notes ({len(notes)})", "<ul>" + "".join(
            f"<li>{html.escape(str(n))}</li>" for n in notes) + "</ul>"))
    rest = [(c, u) for c, u in figures.items() if (c, u) not in main]
    if rest:
        parts.append(_details("More figures", "".join(_figure(c, u) for c, u in rest), open_=True))
    parts.append("<h2 id='details'>All fields</h2>")
    for k, v in doc.items():
        if k == "analysis":           # the file's name, as the header gives it, not its path
            v = {**v, "recording": (doc.get("report") or {}).get("recording")}
        if isinstance(v, Mapping):
            parts.append(_details(label(k), _nested(v)))
    return "\n".join(parts)


def pdf_tables(doc: Mapping) -> list:
    """``[(section title, [(label, text), ...]), ...]`` for :func:`stand.reports.pdf.write_pdf`."""
    bq = doc.get("balancing_quality") or {}
    out = [("Balancing quality", _rows(bq, QUALITY_KEYS) + vibration_rows(bq)),
           ("ISO 21940-11", _rows(bq.get("iso_21940_11") or {}, ISO_KEYS))] \
        if single_plane_applies(doc) else []
    for row in (doc.get("two_plane") or {}).get("planes", []):
        out.append((f"Two-plane: {row.get('plane')}",
                    [(k, show(k, row.get(k), row.get(k + "_std"))) for k in ("unbalance_gmm", "angle_deg",
                                                        "correction_angle_deg", "permissible_gmm",
                                                        "passed")]))
    out += [("Machine and run", _rows(doc.get("header") or {})),
           ("Natural frequency and damping", _rows((doc.get("dynamics") or {}).get("natural_frequency") or {}))]
    crit = (doc.get("dynamics") or {}).get("critical_speeds") or []
    if crit:
        out.append(("Critical speeds", [(str(r.get("source")), show("speed_hz", r.get("speed_hz"),
                                                                      r.get("speed_hz_std")))
                                         for r in crit]))
    if doc.get("warnings"):
        out.append(("Warnings", [(w.get("severity", ""), w.get("message", "")) for w in doc["warnings"]]))
    if doc.get("notes"):
        out.append(("Notes", [("", str(n)) for n in doc["notes"]]))
    return out
