"""A report as a printable PDF (A4 portrait) through matplotlib's PDF backend.

Page 1 is the answer: the title, the verdict banner (headline large and bold,
green for pass, red for fail; then its lines) and up to two figures scaled to
fit the rest of the page.  The following pages hold the remaining figures (two
per page) and the tables, one ``label  value`` row per line, values wrapped to
the column and rows carried over to new pages as needed.  Text is embedded as
text (TrueType, ``pdf.fonttype`` 42), so a PDF text extractor or a search in a
viewer finds it.  No browser, no network; the file is written atomically with
normal permissions by :func:`stand.io.atomic.atomic_path`.
"""
from __future__ import annotations

import base64
import binascii
import io
from pathlib import Path
from typing import Iterable, Mapping, Sequence

from stand.io.atomic import atomic_path

__all__ = ["write_pdf", "PAGE_IN", "decode_png_uri"]

#: A4 portrait [in]
PAGE_IN = (8.27, 11.69)
_MARGIN = 0.7           # page margin [in]
_PNG_PREFIX = "data:image/png;base64,"
_PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
_COLOURS = {"pass": "#007700", "fail": "#bb0000", "info": "#222222"}
_FRAMES = {"pass": ("#007700", "#eef8ee"), "fail": ("#bb0000", "#fbeeee"), "info": ("#888888", "#f4f4f4")}
_LEADING = 1.3          # line height / font size


def decode_png_uri(caption: str, uri) -> bytes:
    """The PNG bytes of a ``data:image/png;base64,...`` URI.

    Raises
    ------
    ValueError
        Not a PNG data URI, bad base64 or not PNG data; the message names the caption.
    """
    if not isinstance(uri, str) or not uri.startswith(_PNG_PREFIX):
        raise ValueError(f"figure {caption!r}: not a PNG data URI (data:image/png;base64,...)")
    try:
        raw = base64.b64decode(uri[len(_PNG_PREFIX):], validate=True)
    except (binascii.Error, ValueError):
        raise ValueError(f"figure {caption!r}: the data URI is not valid base64") from None
    if not raw.startswith(_PNG_MAGIC):
        raise ValueError(f"figure {caption!r}: the data URI does not hold a PNG image")
    return raw


def _read_png(caption: str, uri):
    """The pixel array of a PNG data URI (ValueError naming the caption if unreadable)."""
    from matplotlib.image import imread

    raw = decode_png_uri(caption, uri)
    try:
        return imread(io.BytesIO(raw), format="png")
    except Exception as exc:
        raise ValueError(f"figure {caption!r}: the PNG cannot be read ({exc})") from None


def _text_width_pt(text: str, size: float, mono: bool, bold: bool = False) -> float:
    """Width of ``text`` set in DejaVu at ``size`` pt [pt] (matplotlib's own font metrics)."""
    from matplotlib.font_manager import FontProperties
    from matplotlib.textpath import TextToPath

    prop = FontProperties(family="DejaVu Sans Mono" if mono else "DejaVu Sans", size=size,
                          weight="bold" if bold else "normal")
    return TextToPath().get_text_width_height_descent(text, prop, ismath=False)[0]


def _wrap(text: str, width_in: float, size: float, mono: bool = False, bold: bool = False) -> list:
    """``text`` broken into lines no wider than ``width_in`` [in] (words, then characters)."""
    limit = width_in * 72.0
    if mono:   # every DejaVu Sans Mono glyph is 0.602 em wide
        per_line = max(1, int(limit / (0.6021 * size)))
        fits = lambda s: len(s) <= per_line  # noqa: E731
    else:
        fits = lambda s: _text_width_pt(s, size, mono, bold) <= limit  # noqa: E731
    lines = []
    for para in str(text).splitlines() or [""]:
        line = ""
        for word in para.split():
            cand = word if not line else f"{line} {word}"
            if fits(cand):
                line = cand
                continue
            if line:
                lines.append(line)
            while not fits(word) and len(word) > 1:   # a word longer than the line: cut it
                cut = len(word) - 1
                while cut > 1 and not fits(word[:cut]):
                    cut -= 1
                lines.append(word[:cut])
                word = word[cut:]
            line = word
        lines.append(line)
    return lines


class _Pages:
    """Pages being filled from the top; a cursor ``y`` in inches from the top edge."""

    def __init__(self, pdf, title: str):
        self.pdf, self.title, self.fig, self.y, self.number = pdf, title, None, 0.0, 0

    def new(self):
        from matplotlib.figure import Figure

        self.flush()
        self.number += 1
        self.fig = Figure(figsize=PAGE_IN)
        self.y = _MARGIN
        if self.number > 1:   # running head and page number
            self.text(self.title, 8, color="#666666", y=_MARGIN * 0.5)
            self.fig.text(1 - _MARGIN / PAGE_IN[0], 1 - _MARGIN * 0.5 / PAGE_IN[1],
                          f"page {self.number}", ha="right", va="top", fontsize=8, color="#666666")

    def flush(self):
        if self.fig is not None:
            self.pdf.savefig(self.fig)
            self.fig = None

    @property
    def room(self) -> float:
        """Height left on the page [in]."""
        return PAGE_IN[1] - _MARGIN - self.y

    def text(self, s: str, size: float, x: float = _MARGIN, y: float | None = None, **kw):
        self.fig.text(x / PAGE_IN[0], 1 - (self.y if y is None else y) / PAGE_IN[1], s,
                      fontsize=size, va="top", ha="left", **kw)

    def line(self, s: str, size: float, x: float = _MARGIN, **kw):
        self.text(s, size, x, **kw)
        self.y += size * _LEADING / 72.0

    def image(self, caption: str, img, height: float):
        """The image (pixel array) scaled into the text width x ``height`` [in], its caption below."""
        cap_lines = _wrap(caption, PAGE_IN[0] - 2 * _MARGIN, 9)
        cap_h = len(cap_lines) * 9 * _LEADING / 72.0
        box_w, box_h = PAGE_IN[0] - 2 * _MARGIN, max(height - cap_h - 0.1, 0.5)
        h_px, w_px = img.shape[:2]
        scale = min(box_w / w_px, box_h / h_px)       # in per pixel, aspect kept
        w, h = w_px * scale, h_px * scale
        x0 = (PAGE_IN[0] - w) / 2
        ax = self.fig.add_axes((x0 / PAGE_IN[0], 1 - (self.y + h) / PAGE_IN[1],
                                w / PAGE_IN[0], h / PAGE_IN[1]))
        ax.imshow(img, interpolation="antialiased")
        ax.set_axis_off()
        self.y += h + 0.05
        for s in cap_lines:
            self.line(s, 9, style="italic", color="#333333")
        self.y += 0.15


def _banner(pages: _Pages, banner: Mapping):
    from matplotlib.patches import Rectangle

    status = banner.get("status", "info")
    status = status if status in _COLOURS else "info"
    width = PAGE_IN[0] - 2 * _MARGIN - 0.3
    top = pages.y
    pages.y += 0.15
    for s in _wrap(str(banner.get("headline", "")), width, 18, bold=True):
        pages.line(s, 18, x=_MARGIN + 0.15, weight="bold", color=_COLOURS[status])
    pages.y += 0.05
    for item in banner.get("lines", ()):
        for s in _wrap(str(item), width, 11):
            pages.line(s, 11, x=_MARGIN + 0.15)
    pages.y += 0.1
    edge, face = _FRAMES[status]
    pages.fig.patches.append(Rectangle(
        (_MARGIN / PAGE_IN[0], 1 - pages.y / PAGE_IN[1]), (PAGE_IN[0] - 2 * _MARGIN) / PAGE_IN[0],
        (pages.y - top) / PAGE_IN[1], transform=pages.fig.transFigure, figure=pages.fig,
        edgecolor=edge, facecolor=face, linewidth=2.5, zorder=-1))
    pages.y += 0.25


def _table(pages: _Pages, title: str, rows: Sequence):
    size = 9
    lh = size * _LEADING / 72.0
    width = PAGE_IN[0] - 2 * _MARGIN
    label_w = 0.38 * width
    value_x = _MARGIN + label_w + 0.15
    value_w = width - label_w - 0.15

    def heading(cont: bool):
        pages.y += 0.1
        for s in _wrap(title + (" (continued)" if cont else ""), width, 13, bold=True):
            pages.line(s, 13, weight="bold")
        pages.y += 0.05

    if pages.room < 13 * _LEADING / 72.0 + 0.15 + 2 * lh:   # no lone heading at a page's foot
        pages.new()
    heading(False)
    for label, value in rows:
        left = _wrap(str(label), label_w, size, mono=True)
        right = _wrap("—" if value is None else str(value), value_w, size, mono=True)
        for i in range(max(len(left), len(right))):
            if pages.room < lh:
                pages.new()
                heading(True)
            if i < len(left):
                pages.text(left[i], size, family="DejaVu Sans Mono", weight="bold")
            if i < len(right):
                pages.text(right[i], size, x=value_x, family="DejaVu Sans Mono")
            pages.y += lh
        pages.y += 0.03


def write_pdf(path, title: str, banner: Mapping, figures: Mapping[str, str] | None = None,
              tables: Iterable = ()) -> Path:
    """Write a report as an A4 PDF: verdict and key figures first, then the tables.

    Parameters
    ----------
    path : str or os.PathLike
        The PDF to write (its directory must exist); replaced atomically.
    title : str
        Title on page 1, running head of the following pages, PDF metadata.
    banner : mapping
        ``{"status": "pass"|"fail"|"info", "headline": str, "lines": [str, ...]}``
        (as :func:`stand.reports.html.banner_html`).
    figures : mapping of str to str, optional
        ``{caption: "data:image/png;base64,..."}``; the first two go on page 1,
        the others two per page after it, each scaled to fit (aspect kept).
    tables : iterable of (str, sequence of (str, str))
        ``(section title, [(label, value text), ...])``: aligned rows, long
        values wrapped, continued over as many pages as needed.

    Returns
    -------
    Path
        ``path``.

    Raises
    ------
    ValueError
        A figure is not a readable PNG data URI (the message names its caption),
        or ``banner`` has no headline.
    FileNotFoundError
        The directory of ``path`` does not exist.
    """
    import matplotlib
    from matplotlib.backends.backend_pdf import PdfPages

    if not isinstance(banner, Mapping) or not str(banner.get("headline", "")).strip():
        raise ValueError("write_pdf: banner must be a mapping with a non-empty 'headline'")
    figs = [(str(cap), _read_png(str(cap), uri)) for cap, uri in (figures or {}).items()]
    tables = [(str(t), list(rows)) for t, rows in tables]
    with matplotlib.rc_context({"pdf.fonttype": 42, "font.family": "DejaVu Sans"}):
        with atomic_path(path, suffix=".pdf") as tmp:
            with PdfPages(tmp, metadata={"Title": title, "Creator": "autobalancer-stand"}) as pdf:
                pages = _Pages(pdf, title)
                pages.new()
                for s in _wrap(title, PAGE_IN[0] - 2 * _MARGIN, 16, bold=True):
                    pages.line(s, 16, weight="bold")
                pages.y += 0.15
                _banner(pages, banner)
                first, rest = figs[:2], figs[2:]
                for i, (cap, img) in enumerate(first):   # share the room left on page 1
                    pages.image(cap, img, pages.room / (len(first) - i))
                full = PAGE_IN[1] - 2 * _MARGIN - 0.2
                for i in range(0, len(rest), 2):
                    pages.new()
                    pair = rest[i:i + 2]
                    for cap, img in pair:
                        pages.image(cap, img, full / len(pair))
                if tables:
                    pages.new()
                    for t, rows in tables:
                        _table(pages, t, rows)
                pages.flush()
    return Path(path)
