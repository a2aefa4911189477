"""Self-contained HTML reports built from a JSON document (the source of truth).

A report is a dict (JSON-serialisable, SI units named in the keys, e.g.
``unbalance_gmm``, ``speed_hz``) plus matplotlib figures.  :func:`render_html`
writes one HTML file with the figures embedded as PNG data URIs and every
number taken from the document (no external URL in ``src``/``href`` except
``#anchors``); all text from inputs is escaped.  :func:`write_report` writes
the HTML and the JSON atomically through :mod:`stand.io.atomic` (temporary file
beside the target, then rename; normal file permissions, 0666 minus the
umask), the JSON converted by :mod:`stand.io.jsonable`.
"""
from __future__ import annotations

import base64
import html
import io
import math
import re
from typing import Any, Iterable, Mapping

from stand.io.atomic import write_text
from stand.io.jsonable import dumps, to_jsonable

__all__ = ["figure_png", "render_html", "banner_html", "write_report", "atomic_write_text",
           "jsonable", "check_schema"]

CSS = """body{font-family:sans-serif;max-width:1100px;margin:2em auto;color:#222}
table{border-collapse:collapse;margin:.5em 0}td,th{border:1px solid #bbb;padding:.25em .6em;
text-align:left;vertical-align:top}th{background:#eee}.fail{color:#b00;font-weight:bold}
.pass{color:#070;font-weight:bold}.warn{color:#a60}img{max-width:100%}code{background:#f4f4f4}
#verdict{border:3px solid #888;border-radius:6px;padding:.6em 1em;margin:.5em 0 1em}
#verdict.pass{border-color:#070;background:#eef8ee}#verdict.fail{border-color:#b00;background:#fbeeee}
#verdict.info{border-color:#888;background:#f4f4f4;color:#222;font-weight:normal}
#verdict .headline{font-size:1.5em;margin:0 0 .3em}#verdict p{margin:.2em 0;font-weight:normal;color:#222}
.meta{color:#555;font-size:.9em}figure{margin:.5em 0}.keyfigs{display:flex;flex-wrap:wrap;gap:1em}
.keyfigs figure{flex:1 1 30%;min-width:280px}details{margin:.5em 0}summary{cursor:pointer;font-weight:bold}
td.num{text-align:right;font-variant-numeric:tabular-nums}
@media print{@page{size:A4;margin:14mm}body{max-width:none;margin:0;font-size:10pt}
h2{page-break-before:always}h2.first{page-break-before:avoid}figure,table,#verdict{page-break-inside:avoid}
img{max-width:100%;max-height:120mm}nav{display:none}.keyfigs figure{flex:1 1 45%}
details::details-content{content-visibility:visible;display:block}summary{list-style:none}}"""
#: (the print rule on ``::details-content`` prints the collapsed sections open, without a script:
#: a report page holds no script at all)


_PNG_URI = re.compile(r"data:image/png;base64,[A-Za-z0-9+/]*={0,2}")

#: plain JSON types (numpy to Python, non-finite floats to None): :func:`stand.io.jsonable.to_jsonable`
jsonable = to_jsonable
#: atomic text write, normal permissions: :func:`stand.io.atomic.write_text`
atomic_write_text = write_text


#: resolution of the report figures [pixels per inch of the figure size]
FIGURE_DPI = 90
#: white space drawn around a figure [in], for artists placed outside it (legends anchored
#: beside or under their axes); content reaching it is saved the slow way (tight box)
_MARGIN_IN = 2.0
#: padding kept around the drawn content [in] (matplotlib's ``savefig.pad_inches``)
_PAD_IN = 0.1


def figure_png(fig) -> str:
    """A matplotlib figure as a PNG data URI (a pyplot figure is closed).

    The figure is drawn once, on a canvas ``_MARGIN_IN`` wider on every side, and the image
    is cropped to what was drawn (pixels unlike the background, and every axes' box) plus
    0.1 in: the picture ``savefig(bbox_inches="tight")`` gives (within a few pixels: the
    tight box is that of the text's line boxes, this one that of the ink) for one layout
    pass instead of two.  Content that reaches the margin's edge, or a legend wholly beyond
    it, falls back to the tight box.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        Rendered at ``FIGURE_DPI`` = 90 dpi (pixels per inch of the figure size).

    Returns
    -------
    str
        ``"data:image/png;base64,..."``, for the ``figures`` of :func:`render_html`.
    """
    buf = io.BytesIO()
    if not _cropped_png(fig, buf):
        buf = io.BytesIO()
        fig.savefig(buf, format="png", dpi=FIGURE_DPI, bbox_inches="tight")
    import sys

    if "matplotlib.pyplot" in sys.modules:   # a figure made by a caller through pyplot
        sys.modules["matplotlib.pyplot"].close(fig)
    return "data:image/png;base64," + base64.b64encode(buf.getvalue()).decode("ascii")


def _cropped_png(fig, out) -> bool:
    """Draw ``fig`` once with margins, crop to its content + pad, write the PNG to ``out``;
    False (nothing written) when the content comes within the pad of the canvas' edge or a
    legend lies beyond the margin (the tight box would be larger than the canvas)."""
    import numpy as np
    from matplotlib.image import imsave
    from matplotlib.transforms import Affine2D, Bbox, TransformedBbox

    dpi, m = FIGURE_DPI, _MARGIN_IN
    w_in, h_in = fig.get_size_inches()
    raw, box = io.BytesIO(), Bbox.from_extents(-m, -m, w_in + m, h_in + m)
    fig.savefig(raw, format="rgba", dpi=dpi, bbox_inches=box)
    # the canvas [px], as matplotlib sizes it (matplotlib._tight_bbox.adjust_bbox, then
    # FigureCanvasBase.get_width_height: truncated, up when within 1e-8 px of the next pixel)
    wf, hf = TransformedBbox(Bbox.from_bounds(0, 0, *box.size), Affine2D().scale(dpi)).size
    shape = (int(hf + 1e-8), int(wf + 1e-8))
    if shape[0] * shape[1] * 4 != len(raw.getbuffer()):
        return False
    px = np.frombuffer(raw.getbuffer(), np.uint32).reshape(shape)       # RGBA as one word
    ink = px != px[0, 0]                                                 # not the background
    rows, cols = np.flatnonzero(ink.any(axis=1)), np.flatnonzero(ink.any(axis=0))
    pad = int(round(_PAD_IN * dpi))
    if rows.size == 0:
        return False
    r0, r1, c0, c1 = rows[0], rows[-1] + 1, cols[0], cols[-1] + 1
    for ax in fig.axes:                      # the axes' boxes (an image's white border)
        if ax.get_visible():
            (x0, y0), (x1, y1) = ax.get_position().get_points() * (w_in * dpi, h_in * dpi) + m * dpi
            r0, r1 = min(r0, int(shape[0] - y1)), max(r1, int(math.ceil(shape[0] - y0)))
            c0, c1 = min(c0, int(x0)), max(c1, int(math.ceil(x1)))
    if r0 < pad or c0 < pad or r1 > shape[0] - pad or c1 > shape[1] - pad:
        return False
    out_of_reach = fig.bbox.expanded(1.0, 1.0).padded((m - _PAD_IN) * fig.dpi)
    for leg in fig.legends + [ax.get_legend() for ax in fig.axes]:   # wholly beyond the margin
        if leg is not None and leg.get_visible():
            bb = leg.get_window_extent()
            if not (out_of_reach.contains(bb.x0, bb.y0) and out_of_reach.contains(bb.x1, bb.y1)):
                return False
    rgba = np.frombuffer(raw.getbuffer(), np.uint8).reshape(*shape, 4)
    imsave(out, np.ascontiguousarray(rgba[r0 - pad:r1 + pad, c0 - pad:c1 + pad]), format="png",
           dpi=dpi)
    return True


def _fmt(v: Any) -> str:
    if v is None:
        return "—"
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, float):
        return f"{v:.6g}"
    if isinstance(v, (list, tuple)):
        return ", ".join(_fmt(x) for x in v)
    return str(v)


def _table(d: Mapping) -> str:
    """A section as labelled rows (:func:`stand.reports.tables.nested`)."""
    from stand.reports.tables import nested

    return nested(d)


def _rows_table(rows: Iterable[Mapping]) -> str:
    """A list of records as one table with labelled columns (:func:`stand.reports.tables.list_table`)."""
    from stand.reports.tables import list_table

    return list_table(list(rows))


def banner_html(banner) -> str:
    """The verdict banner: ``{"status": "pass"|"fail"|"info", "headline": str,
    "lines": [str, ...]}`` -> ``<div id="verdict" class="STATUS">`` (text escaped)."""
    status = banner.get("status", "info")
    status = status if status in ("pass", "fail", "info") else "info"
    lines = "".join(f"<p>{html.escape(str(x))}</p>" for x in banner.get("lines", ()))
    return (f"<div id='verdict' class='{status}'><p class='headline'>"
            f"{html.escape(str(banner.get('headline', '')))}</p>{lines}</div>")


def render_html(title: str, doc: Mapping, figures: Mapping[str, str] | None = None,
                sections: Iterable[str] | None = None, banner: Mapping | None = None,
                body: str | None = None) -> str:
    """The HTML text of a report.

    Parameters
    ----------
    title : str
        Page title and heading (escaped).
    doc : mapping
        Plain JSON document; one section per top-level key, its values as
        tables (numbers with 6 significant digits, units as named in the keys).
    figures : mapping of str to str, optional
        ``{caption: data URI}``; only embedded PNG data URIs are accepted.
    sections : iterable of str, optional
        The top-level keys to show, in this order (default: all, in ``doc`` order).
    banner : mapping, optional
        The verdict shown first (:func:`banner_html`).
    body : str, optional
        Ready HTML (already escaped) that replaces the generic section tables
        (a report with its own presentation, e.g. the balancing report's).

    Returns
    -------
    str
        One self-contained HTML page (no external URL).

    Raises
    ------
    ValueError
        A figure is not an embedded PNG data URI.
    """
    parts = [f"<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'>"
             f"<meta name='viewport' content='width=device-width, initial-scale=1'>"
             f"<title>{html.escape(title)}</title><style>{CSS}</style></head><body>"
             f"<h1>{html.escape(title)}</h1>"]
    if banner:
        parts.append(banner_html(banner))
    if body is not None:
        if figures:
            for cap, uri in figures.items():
                if not _PNG_URI.fullmatch(str(uri)):
                    raise ValueError(f"figure {cap!r}: only embedded PNG data URIs "
                                     "(data:image/png;base64,...) are allowed")
        parts.append(body)
        parts.append("</body></html>")
        return "\n".join(parts)
    keys = list(sections) if sections is not None else list(doc)
    from stand.io.labels import label as _label

    parts.append("<p>" + " · ".join(f"<a href='#{html.escape(k)}'>{html.escape(_label(k))}</a>" for k in keys)
                 + (" · <a href='#figures'>figures</a>" if figures else "") + "</p>")
    for k in keys:
        if k not in doc:
            continue
        v = doc[k]
        from stand.io.labels import label

        parts.append(f"<h2 id='{html.escape(k)}'>{html.escape(label(k))}</h2>")
        if isinstance(v, Mapping):
            parts.append(_table(v))
        elif isinstance(v, list) and v and all(isinstance(r, Mapping) for r in v):
            parts.append(_rows_table(v))
        elif isinstance(v, list):
            parts.append("<ul>" + "".join(f"<li>{html.escape(_fmt(x))}</li>" for x in v) + "</ul>")
        else:
            parts.append(f"<p>{html.escape(_fmt(v))}</p>")
    if figures:
        parts.append("<h2 id='figures'>figures</h2>")
        for cap, uri in figures.items():
            if not _PNG_URI.fullmatch(str(uri)):
                raise ValueError(f"figure {cap!r}: only embedded PNG data URIs "
                                 "(data:image/png;base64,...) are allowed")
            parts.append(f"<figure><img alt='{html.escape(cap)}' src='{uri}'>"
                         f"<figcaption>{html.escape(cap)}</figcaption></figure>")
    parts.append("</body></html>")
    return "\n".join(parts)


def write_report(title: str, doc: Mapping, html_path=None, json_path=None, figures=None,
                 sections=None, banner=None, body=None) -> dict:
    """Write the HTML and/or the JSON of a report; return the plain JSON document.

    Parameters
    ----------
    title : str
        Title of the HTML page.
    doc : mapping
        The report (any values :func:`stand.io.jsonable.to_jsonable` converts;
        units named in the keys).
    html_path, json_path : str or os.PathLike, optional
        Where to write the self-contained HTML and the JSON (indented, strict:
        no NaN).  Each is written atomically by :func:`stand.io.atomic.write_text`
        with normal file permissions (0666 minus the umask, or the replaced
        file's).
    figures : mapping of str to str, optional
        ``{caption: PNG data URI}`` (:func:`figure_png`).
    sections : iterable of str, optional
        Order of the top-level keys in the HTML.
    banner, body : optional
        As :func:`render_html` (``body`` may be a callable of the plain document
        returning the HTML, so it is built from the converted JSON).

    Returns
    -------
    dict
        ``doc`` as plain JSON types (non-finite floats as ``None``).

    Raises
    ------
    FileNotFoundError
        The directory of an output path does not exist.
    """
    plain = to_jsonable(doc)
    if json_path:
        write_text(json_path, dumps(plain, indent=2))
    if html_path:
        b = body(plain) if callable(body) else body
        write_text(html_path, render_html(title, plain, figures, sections, banner, b))
    return plain


def check_schema(doc: Mapping, schema: Mapping, where: str = "") -> list:
    """Minimal structural check of a JSON document.

    Parameters
    ----------
    doc : mapping
        The document (plain JSON types).
    schema : mapping
        Required keys to a type name ("number", "string", "bool", "list",
        "object", alternatives joined by "|" such as "number|null") or to a
        nested schema (dict).
    where : str
        Prefix of the key paths in the messages (e.g. ``"cases[3]."``).

    Returns
    -------
    list of str
        The problems (missing key, wrong type), empty when ``doc`` is valid.
    """
    problems = []
    types = {"number": (int, float), "string": (str,), "bool": (bool,), "list": (list,),
             "object": (dict,)}
    for k, t in schema.items():
        if k not in doc:
            problems.append(f"{where}{k}: missing")
            continue
        v = doc[k]
        if isinstance(t, Mapping):
            if not isinstance(v, Mapping):
                problems.append(f"{where}{k}: expected an object")
            else:
                problems += check_schema(v, t, f"{where}{k}.")
            continue
        opts = t.split("|")
        ok = any((o == "null" and v is None) or (o in types and isinstance(v, types[o])
                 and not (o == "number" and isinstance(v, bool))) for o in opts)
        if not ok:
            problems.append(f"{where}{k}: expected {t}, got {type(v).__name__}")
    return problems
