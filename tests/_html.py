"""Reading a report's HTML in the tests: the elements directly in ``<body>``, in order."""
from __future__ import annotations

from html.parser import HTMLParser

__all__ = ["body_children"]

_VOID = {"area", "base", "br", "col", "embed", "hr", "img", "input", "link", "meta", "source",
         "track", "wbr"}


class _Children(HTMLParser):
    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.depth = None          # depth inside <body>; None outside it
        self.out: list = []

    def handle_starttag(self, tag, attrs):
        if tag == "body":
            self.depth = 0
            return
        if self.depth is None:
            return
        if self.depth == 0:
            self.out.append({"tag": tag, "attrs": dict(attrs), "text": "", "lines": []})
        elif self.out and tag in ("p", "li"):      # a new line of the top-level element
            self.out[-1]["lines"].append("")
        if tag not in _VOID:
            self.depth += 1

    def handle_endtag(self, tag):
        if tag == "body":
            self.depth = None
        elif self.depth and tag not in _VOID:
            self.depth -= 1

    def handle_data(self, data):
        if self.depth and self.out:
            self.out[-1]["text"] += data
            if self.out[-1]["lines"]:
                self.out[-1]["lines"][-1] += data


def body_children(html: str) -> list:
    """The top-level elements of the page's body, in document order.

    Returns
    -------
    list of dict
        ``tag``, ``attrs`` (dict), ``text`` (all text inside) and ``lines``
        (the text of each ``<p>``/``<li>`` inside, in order).
    """
    parser = _Children()
    parser.feed(html)
    parser.close()
    return parser.out
