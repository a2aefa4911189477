"""The HTML page of ``stand stress -o``: the verdict, then one line per case.

Built from the report's JSON document (:data:`stand.reports.stress.SCHEMA`):
:func:`stress_banner` is the verdict banner of :func:`stand.reports.html.render_html`
("12 of 12 cases passed" / "2 of 12 cases failed: NAME1, NAME2");
:func:`case_lines` gives one line per case ("NAME: passed" / "NAME: failed —
why", the reason the report records); :func:`stress_body` is the rest of the
page: that list, the figure, the summary and each case's detail table
(collapsed), with the labels and units of :mod:`stand.io.labels`.
"""
from __future__ import annotations

import html
from pathlib import Path
from typing import Mapping, Sequence

__all__ = ["stress_banner", "case_lines", "stress_body"]

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


def _table(d: Mapping) -> str:
    """Rows ``label | value`` (:func:`stand.reports.tables.nested`: the one label table); a
    case's catalogue ``params`` as written."""
    from stand.reports.tables import nested

    return nested(d, raw=("params",))


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
