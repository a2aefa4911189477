"""HTML tables of a report's JSON, as a person reads them: one label table (:mod:`.labels`),
values in their display units rounded to their uncertainty (:mod:`.numbers`).

Shared by every report page: the balancing report's page (:mod:`.balancing_page`), the
generic renderer (:func:`stand.reports.html.render_html`) and the stress page.
"""
from __future__ import annotations

import html
from typing import Mapping

from stand.io.labels import label, unit
from stand.io.numbers import plain, with_uncertainty

__all__ = ["show", "rows", "table", "list_table", "nested", "std_parts", "details", "figure"]


def show(key, value, std=None) -> str:
    """A value of ``key`` as text: display unit and factor from :mod:`.labels`, rounded to
    ``std`` when given."""
    u, f = unit(key)
    if isinstance(value, bool) or value is None or isinstance(value, str):
        return plain(value) if not isinstance(value, str) else value
    if isinstance(value, (list, tuple)):
        if all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in value):
            return " – ".join(plain(x * f if isinstance(x, float) else x) for x in value) + \
                (f" {u}" if u else "")
        return ", ".join(show(key, x) if isinstance(x, (list, tuple)) else str(x) for x in value)
    if isinstance(value, (int, float)):
        v = value * f if isinstance(value, float) or f != 1.0 else value
        if std is not None:
            angle = key == "angle_deg" or key.endswith("_angle_deg")
            if angle and std * f >= 90.0:
                return "undefined (its uncertainty is above a quarter turn)"
            return with_uncertainty(v, std * f, u, resolution=not angle)
        return plain(v, u)
    return str(value)


def rows(d: Mapping, keys=None) -> list:
    """(label, text) rows of a flat mapping; ``*_std`` keys merge into their value; the
    angle of a vector below its resolution is not shown as a number."""
    out = []
    for k in (keys or list(d)):
        if k not in d or k.endswith("_std"):
            continue
        v = d[k]
        if isinstance(v, Mapping) or (isinstance(v, list) and v and isinstance(v[0], Mapping)):
            continue
        text = show(k, v, d.get(k + "_std"))
        vec = k.replace("_angle_deg", "_gmm")
        if k.endswith("_angle_deg") and vec in d and d[vec] is not None \
                and show(vec, d[vec], d.get(vec + "_std")).startswith("below resolution"):
            text = "undefined (the unbalance is below resolution)"
        out.append((label(k), text))
    return out


def table(rows) -> str:
    return "<table>" + "".join(f"<tr><th>{html.escape(a)}</th><td>{html.escape(b)}</td></tr>"
                               for a, b in rows) + "</table>"


def list_table(rows: list, keys=None) -> str:
    keys = keys or [k for r in rows[:1] for k in r if not k.endswith("_std")]
    for r in rows:
        for k in r:
            if k not in keys and not k.endswith("_std"):
                keys.append(k)
    head = "".join(f"<th>{html.escape(label(k))}</th>" for k in keys)
    body = []
    for r in rows:
        cells = []
        for k in keys:
            v = r.get(k)
            cls = ""
            if k in ("passed", "settled", "ok") and isinstance(v, bool):
                cls = " class='pass'" if v else " class='fail'"
            elif isinstance(v, (int, float)) and not isinstance(v, bool):
                cls = " class='num'"
            text = nested(v) if isinstance(v, Mapping) else html.escape(show(k, v, r.get(k + "_std")))
            cells.append(f"<td{cls}>{text}</td>")
        body.append("<tr>" + "".join(cells) + "</tr>")
    return f"<table><tr>{head}</tr>{''.join(body)}</table>"


def nested(d: Mapping, raw=()) -> str:
    """Every field of a section, labelled (the collapsed "all fields" tables); the keys inside
    a field named in ``raw`` are shown as written (e.g. a catalogue's parameters)."""
    parts = ["<table>"]
    for k, v in d.items():
        if k.endswith("_std") and k[:-4] in d:
            continue
        if isinstance(v, Mapping) and (k == "std_parts" or k.endswith("_std_parts")):
            cell = std_parts(k, v)
        elif isinstance(v, Mapping):
            cell = nested(v, raw) if k not in raw else nested_raw(v)
        elif isinstance(v, list) and v and all(isinstance(r, Mapping) for r in v):
            cell = list_table(v)
        elif isinstance(v, list) and v and all(isinstance(x, str) for x in v):
            cell = "<ul>" + "".join(f"<li>{html.escape(x)}</li>" for x in v) + "</ul>"
        else:
            cell = html.escape(show(k, v, d.get(k + "_std")))
        parts.append(f"<tr><th>{html.escape(label(k))}</th><td>{cell}</td></tr>")
    parts.append("</table>")
    return "".join(parts)


def std_parts(key: str, d: Mapping) -> str:
    """What a ± contains: ``X_std_parts`` = ``{source: std}`` in the unit of ``X``; ``std_parts``
    = ``{X: {source: std}}``.  Each part is shown in its quantity's display unit."""
    if key != "std_parts":
        base = key[: -len("_std_parts")]
        return "<table>" + "".join(
            f"<tr><th>{html.escape(str(p).replace('_', ' ').capitalize())}</th>"
            f"<td>{html.escape(show(base, v) if isinstance(v, (int, float)) else str(v))}</td></tr>"
            for p, v in d.items()) + "</table>"
    return "<table>" + "".join(
        f"<tr><th>{html.escape(label(q))}</th><td>"
        f"{std_parts(q + '_std_parts', v) if isinstance(v, Mapping) else html.escape(str(v))}</td></tr>"
        for q, v in d.items()) + "</table>"


def nested_raw(d: Mapping) -> str:
    """A mapping whose keys are shown as written (no labels, no display units)."""
    return "<table>" + "".join(
        f"<tr><th>{html.escape(str(k))}</th><td>"
        f"{nested_raw(v) if isinstance(v, Mapping) else html.escape(plain(v) if not isinstance(v, (str, list)) else str(v))}"
        "</td></tr>" for k, v in d.items()) + "</table>"


def details(title, inner, open_=False) -> str:
    return (f"<details{' open' if open_ else ''}><summary>{html.escape(title)}</summary>"
            f"{inner}</details>")


def figure(cap, uri) -> str:
    return f"<figure><img alt='{html.escape(cap)}' src='{uri}'><figcaption>{html.escape(cap)}</figcaption></figure>"


