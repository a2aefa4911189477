"""The HTML page of ``stand stress -o``: the verdict, then one line per case.

Built from the report's JSON document (:data:`stand.reports.stress.SCHEMA`):
:func:`stress_banner` is the verdict banner of :func:`stand.reports.html.render_html`
("12 of 12 cases passed" / "2 of 12 cases failed: NAME1, NAME2");
:func:`case_lines` gives one line per case ("NAME: passed" / "NAME: failed —
why", the reason the report records); :func:`stress_body` is the rest of the
page: that list, the figure, the summary and each case's detail table
(collapsed), with labels in words and units.
"""
from __future__ import annotations

import html
from pathlib import Path
from typing import Mapping, Sequence

__all__ = ["stress_banner", "case_lines", "stress_body", "LABELS"]

#: labels (with units) of the summary's and each case's fields
LABELS = {
    "catalogue": "catalogue", "n_cases": "cases", "n_passed": "passed", "n_failed": "failed",
    "all_passed": "all passed", "total_time_s": "total time [s]", "python": "Python",
    "kind": "kind", "description": "description", "check": "check", "method": "method",
    "method_reason": "why this method", "solver_success": "solver finished",
    "solver_message": "solver message", "converged": "converged", "oracle": "compared with",
    "error": "error", "error_measure": "error measure", "tolerance": "tolerance",
    "reference_error": "reference's own error", "conserved_quantity": "conserved quantity",
    "drift": "drift of the conserved quantity", "nfev": "right-hand-side evaluations",
    "wall_time_s": "solver time [s]", "case_time_s": "case time [s]",
    "time_budget_s": "time budget [s]", "outside_validity": "outside the model's validity",
    "declared_outside_validity": "declared outside validity", "pass": "result",
    "reason": "why", "details": "details", "warm_up_s": "warm-up time [s]",
    "n_steps": "steps", "n_rejected": "rejected steps", "params": "parameters (as in the catalogue)",
    "fast": "fast case",
}


def case_lines(cases: Sequence[Mapping]) -> list:
    """One line per case: ``"NAME: passed"`` or ``"NAME: failed — REASON"``."""
    return [f"{c['name']}: passed" if c["pass"] else f"{c['name']}: failed — {c['reason']}"
            for c in cases]


def stress_banner(doc: Mapping) -> dict:
    """The verdict banner (:func:`stand.reports.html.banner_html`) of a stress report.

    Parameters
    ----------
    doc : mapping
        The report (``summary`` and ``cases``).

    Returns
    -------
    dict
        ``status`` "pass" (every case passed) or "fail", ``headline`` "N of N
        cases passed" or "K of N cases failed: NAME, ...", ``lines`` (catalogue
        file name, total time [s]).
    """
    cases, s = doc["cases"], doc["summary"]
    failed = [c["name"] for c in cases if not c["pass"]]
    n = len(cases)
    if failed:
        headline = f"{len(failed)} of {n} case{'s' if n != 1 else ''} failed: {', '.join(failed)}"
    else:
        headline = f"{n} of {n} case{'s' if n != 1 else ''} passed"
    return {"status": "fail" if failed else "pass", "headline": headline,
            "lines": [f"catalogue {Path(str(s['catalogue'])).name}; {n} cases in "
                      f"{s['total_time_s']:.2g} s (Python {s['python']})"]}


def _value(v) -> str:
    if v is None:
        return "—"
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, float):
        return f"{v:.4g}"
    if isinstance(v, list):
        return ", ".join(_value(x) for x in v)
    return str(v)


def _table(d: Mapping, raw_keys: bool = False) -> str:
    """Rows ``label | value``; ``raw_keys``: the keys as written (a case's catalogue params)."""
    rows = []
    for k, v in d.items():
        cell = _table(v, raw_keys or k == "params") if isinstance(v, Mapping) else html.escape(_value(v))
        label = k if raw_keys else LABELS.get(k, k.replace("_", " "))
        rows.append(f"<tr><th>{html.escape(label)}</th><td>{cell}</td></tr>")
    return "<table>" + "".join(rows) + "</table>"


def stress_body(doc: Mapping, figures: Mapping[str, str] | None = None) -> str:
    """The page after the banner (``body`` of :func:`stand.reports.html.render_html`).

    Parameters
    ----------
    doc : mapping
        The report (plain JSON types).
    figures : mapping of str to str, optional
        ``{caption: PNG data URI}``, shown after the list of cases.

    Returns
    -------
    str
        HTML (text escaped): ``<ul id='case-list'>`` with one ``<li>`` per case
        (:func:`case_lines`), the figures, a summary table and one collapsed
        detail table per case (failed cases open).
    """
    items = []
    for c in doc["cases"]:
        name = html.escape(str(c["name"]))
        if c["pass"]:
            items.append(f"<li>{name}: <span class='pass'>passed</span></li>")
        else:
            items.append(f"<li>{name}: <span class='fail'>failed</span> — "
                         f"{html.escape(str(c['reason']))}</li>")
    parts = ["<ul id='case-list'>" + "".join(items) + "</ul>"]
    for cap, uri in (figures or {}).items():
        parts.append(f"<figure><img alt='{html.escape(cap)}' src='{uri}'>"
                     f"<figcaption>{html.escape(cap)}</figcaption></figure>")
    parts.append("<h2 id='summary' class='first'>Summary</h2>" + _table(doc["summary"]))
    parts.append("<h2 id='cases'>Cases</h2>")
    for c in doc["cases"]:
        rest = {k: v for k, v in c.items() if k != "name"}
        rest["pass"] = "passed" if c["pass"] else "failed"
        state = "passed" if c["pass"] else "failed"
        parts.append(f"<details{'' if c['pass'] else ' open'}><summary>"
                     f"{html.escape(str(c['name']))} — {state}</summary>{_table(rest)}</details>")
    return "\n".join(parts)
