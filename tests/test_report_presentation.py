"""The balancing report as a person reads it (issue 20): verdict first, human labels shared
with docs/reports.md, numbers rounded to their uncertainty, the polar plot, file permissions.
"""
import html
import json
import math
import os
import re
from pathlib import Path

import pytest

from stand.io.labels import LABELS, markdown_table
from stand.io.numbers import plain, with_uncertainty

from _helpers import theory_computed_once

ROOT = Path(__file__).resolve().parents[1]
SAMPLE = ROOT / "data_samples" / "recordings" / "stand_cameras.h5"


@pytest.fixture(scope="module", autouse=True)
def _theory_once_per_scene():
    """The sample's chapter-5 theory, asked for by each report of it (the page, the folder's,
    the PDF's): computed once (tests/_helpers.py, theory_computed_once; issue 43)."""
    with theory_computed_once(shared=True):   # the sample's theory: once per process
        yield


@pytest.fixture(scope="module")
def sample(tmp_path_factory):
    """The sample's report by the command line, the page, its JSON and its PDF made by one
    ``stand report -o --json-file --pdf`` (one analysis and one set of figures for the three;
    the PDF was a second report of the same recording); returns (the JSON document, the page,
    the folder)."""
    from stand.cli.main import main

    d = tmp_path_factory.mktemp("pres")
    old = os.umask(0o022)
    try:
        assert main(["report", str(SAMPLE), "-o", str(d / "r.html"), "--json-file",
                     str(d / "r.json"), "--pdf", str(d / "r.pdf")]) == 0
    finally:
        os.umask(old)
    doc = json.loads((d / "r.json").read_text("utf-8"))
    return doc, (d / "r.html").read_text("utf-8"), d


def _text_nodes(page: str) -> list:
    body = page[page.index("<body>"):]
    body = re.sub(r"<script.*?</script>", "", body, flags=re.S)
    return [html.unescape(t).strip() for t in re.split(r"<[^>]+>", body) if t.strip()]


def _keys(o, out=None):
    out = set() if out is None else out
    if isinstance(o, dict):
        for k, v in o.items():
            out.add(k)
            _keys(v, out)
    elif isinstance(o, list):
        for v in o:
            _keys(v, out)
    return out


# ------------------------------------------------------------------ numbers
@pytest.mark.parametrize("v,u,text", [
    (240.2616, 0.028, "240.262 ± 0.028"),
    (3600.0, 12.3, "3600 ± 12"),
    (-112.94, 49.7, "-113 ± 50"),
    (3.2e-7, 1.1e-8, "(3.20 ± 0.11) × 10⁻⁷"),
    (2.5e9, 3e7, "(2.500 ± 0.030) × 10⁹"),
    (8.1e-6, 1.9e-5, "below resolution (< 1.9 × 10⁻⁵)"),
    # values of 1e-3 .. 1e6 written out however fine their uncertainty (were × 10⁰, × 10¹)
    (4.7750434, 7.8e-6, "4.7750434 ± 0.0000078"),
    (20.0000000012, 1.8e-7, "20.00000000 ± 0.00000018"),
    (210.0, 5.1e-7, "210.00000000 ± 0.00000051"),
    (0.00123456789, 1.2e-10, "0.00123456789 ± 0.00000000012"),
    (0.0005, 2e-5, "0.000500 ± 0.000020"),
    (5e-4, 1e-12, "(5.000000000 ± 0.000000010) × 10⁻⁴"),
    (1234567.0, 12.0, "(1.234567 ± 0.000012) × 10⁶"),
    # an uncertainty of 10 or more: a float, in powers of ten when huge (was a 31-digit int)
    (1e-3, 1.5e30, "below resolution (< 1.5 × 10³⁰)"),
    (3e35, 1e33, "(3.000 ± 0.010) × 10³⁵"),
    (12.0, 8.9e-15, "12"),                # round-off, not a measurement's: as plain()
])
def test_rounding_to_the_uncertainty(v, u, text):
    assert with_uncertainty(v, u) == text


def test_no_power_of_ten_on_values_of_ordinary_size():
    """1e-3 <= |v| < 1e6 as plain(): no "× 10" whatever the uncertainty (before: any ± whose
    last digit was below 1e-6 gave "(4.7750434 ± 0.0000078) × 10⁰")."""
    for v in (-0.0012, 0.00999, 1.0, 4.7750434, 99.5, 12345.678, 543210.9):
        for k in range(-14, 7):
            u = 3.3 * 10.0 ** k
            text = with_uncertainty(v, u, "g")
            if "below resolution" in text:            # u is shown, as plain(u)
                continue
            assert "× 10" not in text, (v, u, text)
            if u < 1e-9 * abs(v):                     # round-off: no ± to check
                continue
            shown, sigma = (float(t.split()[0]) for t in text.split(" ± "))
            # both to the last digit of u's two significant ones (10^(k-1))
            assert abs(shown - v) <= 0.5 * 10.0 ** (k - 1) * (1 + 1e-6), (v, u, text)
            assert sigma == pytest.approx(u, rel=0.02)


def test_plain_numbers_have_four_significant_digits_and_no_trailing_zeros():
    assert plain(899.99981, "rpm") == "900 rpm"
    assert plain(4.45, "kg") == "4.45 kg"
    assert plain(443671133.2) == "4.437 × 10⁸"
    assert plain(12) == "12"


# ------------------------------------------------------------------ the page
def test_verdict_is_the_first_thing_on_the_page(sample):
    doc, page, _ = sample
    body = page[page.index("<body>"):]
    first = re.findall(r"<(h1|div|h2|table|figure)\b", body)[:2]
    assert first == ["h1", "div"] and "id='verdict' class='pass'" in body
    nodes = _text_nodes(page)
    assert nodes[1].startswith("PASS — G6.3 at 900 rpm")
    banner = body[body.index("id='verdict'"):body.index("</div>")]
    # the permissible residual of stand analyze: 1000 G m / Omega, rotor mass 4.45 kg
    for needed in ("Achieved grade", "Residual unbalance", "297 g·mm", "stand_cameras.h5",
                   "stand 0.", "UTC"):
        assert needed in html.unescape(banner), needed
    assert str(SAMPLE.resolve()) not in page          # the file's name, not its path
    assert doc["report"]["recording"] == "stand_cameras.h5"


def test_no_label_is_a_raw_json_key(sample):
    doc, page, _ = sample
    raw = {k for k in _keys(doc) if "_" in k}
    shown = set(_text_nodes(page))
    assert not (raw & shown), sorted(raw & shown)


def test_every_value_with_an_uncertainty_is_rounded_to_it(sample):
    _, page, _ = sample
    text = "\n".join(_text_nodes(page))
    pairs = re.findall(r"\(?(-?\d+(?:\.\d+)?) ± (\d+(?:\.\d+)?)\)?", text)
    assert len(pairs) >= 3, "the sample shows values with uncertainties"
    for v, u in pairs:
        dv = len(v.split(".")[1]) if "." in v else 0
        du = len(u.split(".")[1]) if "." in u else 0
        assert dv == du, f"{v} ± {u}: not the same last digit"
        digits = u.replace(".", "").lstrip("0")
        assert 1 <= len(digits) <= 2 or set(digits[2:]) <= {"0"}, f"{v} ± {u}: uncertainty to 2 digits"
    assert "e-0" not in text and "e+0" not in text         # powers of ten, not exponents


def test_events_are_named_for_what_they_are(sample):
    _, page, _ = sample
    text = "\n".join(_text_nodes(page))
    assert "Critical speeds from the theory" in text
    assert "Weights gaining or losing synchrony during the run" in text
    assert "These are not critical speeds" in text
    # no "difference from theory" next to synchrony events
    sync = page[page.index("Weights gaining or losing"):]
    sync = sync[:sync.index("</table>")]
    assert "Nearest theory critical speed" not in sync


def test_polar_plot_and_key_figures_come_before_the_tables(sample):
    _, page, _ = sample
    i_polar = page.index("polar plot: unbalance before and after")
    assert i_polar < page.index("orbit / laser trace") < page.index("id='quality'")
    assert "<details>" in page                      # detail tables collapsed


def test_report_files_have_normal_permissions(sample):
    _, _, d = sample
    for name in ("r.html", "r.json", "r.pdf"):
        assert (d / name).stat().st_mode & 0o777 == 0o644


def test_labels_table_is_the_one_in_the_docs():
    docs = (ROOT / "docs" / "reports.md").read_text()
    block = docs[docs.index("<!-- labels:begin -->") + len("<!-- labels:begin -->"):
                 docs.index("<!-- labels:end -->")]
    assert block.strip() == markdown_table().strip(), \
        "docs/reports.md: regenerate the table with `python -m stand.io.labels`"


def test_every_schema_key_has_a_label():
    from stand.reports.balancing_schema import SCHEMA

    missing = sorted(k for k in _keys(SCHEMA) if k not in LABELS)
    assert not missing, missing


#: a valid 1 x 1 PNG, the picture of a figure that is built but not drawn
_PNG_1PX = ("data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAQAAAC1HAwCAAAAC0lEQVR42mNk"
            "YAAAAAYAAjCB0C8AAAAASUVORK5CYII=")


def _figures_built_not_drawn(monkeypatch):
    """The reports' figures built (every plotting call made) but not drawn to PNG (~0.3 s of
    matplotlib text layout each, seven per report): for a test that reads the page's order,
    links and verdict, never its pictures, which are base64 data and cannot carry text.  The
    drawn figures are checked on the sample's page (test_polar_plot_and_key_figures_come_before
    _the_tables, the PDF's test) and in test_report_balancing.py (eight <img> of the sample)."""
    from matplotlib.figure import Figure

    from stand.reports import balancing_figures, html

    def built(fig):
        assert isinstance(fig, Figure) and fig.axes, fig
        return _PNG_1PX
    monkeypatch.setattr(html, "figure_png", built)
    monkeypatch.setattr(balancing_figures, "figure_png", built)


def test_folder_summary_links_each_report_failures_first(tmp_path, monkeypatch):
    import dataclasses
    import shutil

    from stand.cli.main import main
    from stand.integrate.simulate import simulate
    from stand.recording.hdf5 import write_recording
    from stand.scene.parse import load_scene

    src = tmp_path / "in"
    src.mkdir()
    shutil.copy(SAMPLE, src / "b_cameras.h5")                       # passes G6.3
    (src / "a_broken.h5").write_bytes(b"not a recording")            # cannot be reported
    # fails G6.3: the rotor without its balancer (3600 g·mm); run up and held 1 s (a lab
    # table's run-up fit would take ~5 s: test_report_chain.py)
    nb = load_scene(ROOT / "data_samples" / "scenes" / "no_balancer.toml")
    nb = dataclasses.replace(nb, run=dataclasses.replace(nb.run, duration=11.0))
    write_recording(simulate(nb), src / "c_daq.h5")
    _figures_built_not_drawn(monkeypatch)    # the pages' order, links and verdicts are read
    out = tmp_path / "out"
    out.mkdir()
    code = main(["report", str(src), "-o", str(out), "--summary", str(tmp_path / "s.csv"),
                 "--map", str(ROOT / "data_samples" / "daq" / "daq_runup.map.toml"), "--workers", "1"])
    assert code == 0
    page = (out / "index.html").read_text()
    order = [page.index(n) for n in ("a_broken.h5", "c_daq.h5", "b_cameras.h5")]
    assert order == sorted(order)                                     # unreadable, failed, passed
    assert "href='c_daq.html'" in page and "href='b_cameras.html'" in page
    assert (out / "c_daq.html").exists() and "id='verdict' class='fail'" in page
    import pandas as pd

    s = pd.read_csv(tmp_path / "s.csv")
    assert [Path(f).name for f in s["file"]] == ["a_broken.h5", "c_daq.h5", "b_cameras.h5"]


def test_pdf_first_page_holds_the_verdict(sample):
    pypdf = pytest.importorskip("pypdf")
    reader = pypdf.PdfReader(str(sample[2] / "r.pdf"))      # stand report --pdf (the fixture)
    first = " ".join(reader.pages[0].extract_text().split())
    assert "PASS — G6.3 at 900 rpm" in first
    assert "297 g·mm" in first or "297 g" in first
    rest = " ".join(" ".join(p.extract_text().split()) for p in reader.pages[1:])
    assert "Residual unbalance" in rest and "Critical speeds" in rest
