"""stand.reports.pdf: a report as an A4 PDF whose first page holds the verdict (read back with pypdf)."""
import base64
import os
import stat

import pypdf   # the test extra (pip install -e ".[test]")
import pytest

from stand.reports.html import figure_png
from stand.reports.pdf import PAGE_IN, write_pdf

BANNER = {"status": "fail",
          "headline": "FAIL: G6.3 required at 900 rpm, G16 achieved",
          "lines": ["residual 412 g·mm against 304 g·mm permissible (136 %)",
                    "recording rotor_17.h5, software 0.1.0"]}


def _figure(label: str) -> str:
    from matplotlib.figure import Figure

    fig = Figure(figsize=(4, 3))
    ax = fig.subplots()
    ax.plot([0, 1, 2], [0, 1, 4])
    ax.set_title(label)
    return figure_png(fig)


def _pages(path):
    reader = pypdf.PdfReader(str(path))
    return reader, [" ".join(p.extract_text().split()) for p in reader.pages]


def test_first_page_holds_the_verdict_and_two_figures(tmp_path):
    figs = {"orbit with rings": _figure("a"), "1X against speed": _figure("b"),
            "spectrogram of the orbit": _figure("c")}
    out = write_pdf(tmp_path / "r.pdf", "Balancing report: rotor_17", BANNER, figs,
                    [("Balancing quality", [("Residual unbalance", "412 g·mm")])])
    reader, text = _pages(out)
    w, h = (float(v) / 72 for v in reader.pages[0].mediabox.upper_right)
    assert (w, h) == pytest.approx(PAGE_IN, abs=0.01)            # A4 portrait, in
    assert "Balancing report: rotor_17" in text[0]
    assert BANNER["headline"] in text[0]
    for line in BANNER["lines"]:
        assert line in text[0]
    # the first two figures are on page 1, the third after it, the table after the figures
    assert "orbit with rings" in text[0] and "1X against speed" in text[0]
    assert "spectrogram of the orbit" not in text[0] and "spectrogram of the orbit" in text[1]
    assert len(reader.pages) == 3 and "Residual unbalance 412 g·mm" in text[2]


def test_a_long_table_paginates_and_keeps_every_row(tmp_path):
    rows = [(f"label-{i:03d}", f"value {i} " + "wrapped words " * (i % 12)) for i in range(60)]
    long_token = "x" * 150 + "END"
    rows.append(("unbreakable", long_token))
    write_pdf(tmp_path / "t.pdf", "Long table", {"status": "info", "headline": "Table only"},
              tables=[("Detail", rows)])
    reader, text = _pages(tmp_path / "t.pdf")
    # page 1, then ~150 lines (most values wrap to 2-4 lines) at ~60 lines a page: the table
    # breaks across pages at least twice (60 rows, not 200: ~1 s of drawing, not ~4)
    assert len(reader.pages) >= 4
    assert "label-" not in text[0]
    rest = " ".join(text[1:])
    for i in range(60):
        assert rest.count(f"label-{i:03d}") == 1, i
    assert all("Detail" in t for t in text[1:])                 # heading repeated ("continued")
    assert long_token in rest.replace(" ", "")                  # cut, not lost


@pytest.mark.parametrize("uri, why", [
    ("https://example.org/x.png", "not a PNG data URI"),
    ("data:image/png;base64,@@not base64@@", "not valid base64"),
    ("data:image/png;base64," + base64.b64encode(b"GIF89a....").decode(), "does not hold a PNG"),
])
def test_a_bad_figure_is_refused_by_caption(tmp_path, uri, why):
    with pytest.raises(ValueError, match=rf"figure 'bode plot'.*{why}"):
        write_pdf(tmp_path / "x.pdf", "t", BANNER, {"orbit": _figure("o"), "bode plot": uri})
    assert list(tmp_path.iterdir()) == []                       # nothing written, no temporary left


def test_written_with_normal_permissions(tmp_path):
    old = os.umask(0o022)
    try:
        write_pdf(tmp_path / "p.pdf", "t", BANNER)
    finally:
        os.umask(old)
    assert stat.S_IMODE((tmp_path / "p.pdf").stat().st_mode) == 0o644
