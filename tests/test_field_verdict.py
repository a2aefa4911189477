"""Verdicts of a field-balancing job (issue 41 item 5) and the report a customer receives
(item 6), on the B&K 17-227 job with rotor data (data_samples/balance/bk_17_227_verdict.toml).

Oracles: ISO 21940-11 U_per = 1000 G M / omega written out here, the ISO 10816 zone
boundaries as printed in the standards' tables, the sinusoid's RMS = peak / sqrt(2) and
v = omega x; the published corrections of the note.
"""
from __future__ import annotations

import math
import re
from html.parser import HTMLParser
from pathlib import Path

import pytest

from stand.analysis.field_balance import balance_job
from stand.analysis.field_job import parse_job
from stand.cli.main import main
from stand.io.tomlfile import tomllib

ROOT = Path(__file__).resolve().parents[1]
BKV = ROOT / "data_samples" / "balance" / "bk_17_227_verdict.toml"
W = 1500 * 2 * math.pi / 60                     # service speed [rad/s]


def _job(tmp_path, old, new):
    text = BKV.read_text()
    assert old in text
    f = tmp_path / "job.toml"
    f.write_text(text.replace(old, new))
    return f


def test_bk_verdict_numbers_and_published_corrections():
    res = balance_job(BKV)
    c = res["corrections"]                        # the note's answer is kept
    assert c["P1"]["mass"] == pytest.approx(1.979, abs=0.0015)
    assert c["P1"]["angle_deg"] == pytest.approx(236.2, abs=0.06)
    assert c["P2"]["mass"] == pytest.approx(1.071, abs=0.0015)
    assert c["P2"]["angle_deg"] == pytest.approx(121.8, abs=0.06)
    v = res["verdict"]
    share = 1000 * 6.3 * 8 / W / 2                # g mm, equal split over 2 planes
    u1, u2 = v["unbalance"]
    assert u1["permissible_g_mm"] == pytest.approx(share, rel=1e-12)
    assert u1["before_g_mm"] == pytest.approx(c["P1"]["mass"] * 100, rel=1e-12)
    assert u1["before"]["margin"] == pytest.approx(share - 100 * c["P1"]["mass"], rel=1e-12)
    assert u1["before"]["margin_std"] == pytest.approx(100 * c["P1"]["mass_std"], rel=1e-12)
    assert u1["before"]["passed"] is False and u2["before"]["passed"] is True   # 198 > 160 > 107
    # after: what the correction's error vector leaves, r sqrt(s_m^2 + (m s_a)^2)
    e1 = 100 * math.hypot(c["P1"]["mass_std"], c["P1"]["mass"] * math.radians(c["P1"]["angle_std_deg"]))
    assert u1["after_g_mm"] == 0.0 and u1["after_g_mm_std"] == pytest.approx(e1, rel=1e-12)
    assert u1["after"]["passed"] is True
    s1, s2 = v["vibration"]
    # S1: ISO 10816-1 class III, zone B/C 4.5 mm/s RMS; 170 mm/s pk -> 120.2 mm/s RMS, zone D
    assert s1["limit"] == 4.5 and s1["before_value"] == pytest.approx(170 / math.sqrt(2), rel=1e-9)
    assert s1["before"]["zone"] == "D" and s1["before"]["passed"] is False
    assert s1["after_value"] == 0.0 and s1["after"]["zone"] == "A"
    r1 = res["residuals"][0]
    assert s1["after_value_std"] == pytest.approx(r1["after_std"] / math.sqrt(2), rel=1e-12)
    # the after ± is of the order of the readings' rounding (integer mm/s, whole degrees)
    assert 0.3 < r1["after_std"] < 5.0
    # S2: the contract's 4 mm/s pk
    assert s2["limit"] == 4.0 and s2["before"]["margin"] == pytest.approx(-49.0, rel=1e-12)
    assert s2["after"]["margin"] == 4.0 and s2["after"]["passed"] is (4.0 >= 2 * s2["after_value_std"])
    assert v["passed"] is True


def test_lever_rule_shares_with_plane_positions(tmp_path):
    """ISO 21940-11 7.3: U1 = U b2 / b, U2 = U b1 / b about the centre of mass, 30-70 %."""
    f = _job(tmp_path, 'grade = "G6.3"', 'grade = "G6.3"\ncentre_of_mass = "150 mm"')
    f.write_text(f.read_text().replace('holes = 12', 'holes = 12\nposition = "0 mm"')
                 .replace('[planes.P2]', '[planes.P2]\nposition = "400 mm"'))
    U = 1000 * 6.3 * 8 / W
    u1, u2 = balance_job(f)["verdict"]["unbalance"]
    assert u1["permissible_g_mm"] == pytest.approx(U * 250 / 400, rel=1e-12)
    assert u2["permissible_g_mm"] == pytest.approx(U * 150 / 400, rel=1e-12)
    f.write_text(f.read_text().replace('"150 mm"', '"50 mm"'))          # 87.5 % -> 70 %
    u1, u2 = balance_job(f)["verdict"]["unbalance"]
    assert (u1["permissible_g_mm"], u2["permissible_g_mm"]) == pytest.approx((0.7 * U, 0.3 * U))


def test_tight_contract_limit_fails_naming_the_sensor(tmp_path, capsys):
    f = _job(tmp_path, 'max_vibration = "4 mm/s"', 'max_vibration = "1 mm/s"')
    res = balance_job(f)
    s2 = res["verdict"]["vibration"][1]
    assert 0 < s2["after"]["margin"] < 2 * s2["after_value_std"]      # 1 ± 0.92: not proven
    assert res["verdict"]["passed"] is False
    assert main(["balance", str(f)]) == 0
    first = capsys.readouterr().out.splitlines()[0]
    assert first.startswith("FAIL") and "S2" in first


def test_cli_prints_the_verdict_first(capsys):
    assert main(["balance", str(BKV)]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0].startswith("PASS")
    assert out[1].startswith("  P1 residual unbalance (limit 160.4 g·mm): before 197.9 ± 3.1 g·mm: FAIL")


def test_zone_of_a_displacement_reading_at_its_speed():
    text = """
[job]
vibration_unit = "um"
amplitude = "pp"
[sensors.S1]
machine_class = "group2_rigid"
[[run]]
kind = "reference"
speed = "3000 rpm"
readings = { S1 = "100 @ 0" }
[[run]]
kind = "trial"
speed = "3000 rpm"
trial = { P1 = "1 @ 0" }
readings = { S1 = "60 @ 30" }
"""
    res = balance_job(parse_job(tomllib.loads(text)))
    x = res["verdict"]["vibration"][0]
    v_rms = 100e-6 / 2 * (3000 * 2 * math.pi / 60) / math.sqrt(2) * 1e3     # mm/s RMS
    assert x["before_value"] == pytest.approx(v_rms, rel=1e-9)             # 11.1 mm/s
    assert x["limit"] == 2.8 and x["before"]["zone"] == "D"                # ISO 10816-3 A.2
    assert "ISO 10816-3 Table A.2" in x["limit_source"]
    with pytest.raises(ValueError, match=r"sensors\.S1\.machine_class.*speed"):
        balance_job(parse_job(tomllib.loads(text.replace('speed = "3000 rpm"\n', ""))))


@pytest.mark.parametrize("old, new, words", [
    ('rotor_mass = "8 kg"', 'rotor_mass = "-8 kg"', "job.rotor_mass"),
    ('grade = "G6.3"', 'grade = "G7"', "job.grade = 'G7': not an ISO 21940-11 grade"),
    ('machine_class = "III"', 'machine_class = "V"', "sensors.S1.machine_class = 'V'"),
    ('radius = "100 mm"\nholes = 12', 'holes = 12', "planes.P1.radius: needed with job.grade"),
    ('rotor_mass = "8 kg"\n', '', "job.rotor_mass: needed with job.grade"),
])
def test_bad_verdict_values_one_line_exit_2(tmp_path, capsys, old, new, words):
    f = _job(tmp_path, old, new)
    assert main(["balance", str(f)]) == 2
    err = capsys.readouterr().err.strip()
    assert words in err and "\n" not in err and "Traceback" not in err


class _Page(HTMLParser):
    """Sections (h2 -> the texts of their cells and images), the banner and the images."""

    def __init__(self):
        super().__init__()
        self.sections, self.imgs, self.banner, self._in = {}, [], None, None
        self._cell, self._text = None, []

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "div" and a.get("id") == "verdict":
            self.banner, self._in = {"class": a.get("class"), "text": ""}, "banner"
        elif tag == "h2":
            self._in = "h2"
            self._text = []
        elif tag == "td":
            self._cell = []
        elif tag == "img":
            self.imgs.append(a.get("alt", ""))
            if self.sections:
                list(self.sections.values())[-1].append("figure")

    def handle_endtag(self, tag):
        if tag == "h2":
            self.sections["".join(self._text)] = []
            self._in = None
        elif tag == "td" and self._cell is not None and self.sections:
            list(self.sections.values())[-1].append("".join(self._cell).strip())
            self._cell = None
        elif tag == "div" and self._in == "banner":
            self._in = None

    def handle_data(self, data):
        if self._in == "h2":
            self._text.append(data)
        elif self._in == "banner":
            self.banner["text"] += data + "\n"
        if self._cell is not None:
            self._cell.append(data)


def test_field_report_banner_figures_and_no_thin_section(tmp_path):
    out, pdf = tmp_path / "r.html", tmp_path / "r.pdf"
    assert main(["balance", str(BKV), "-o", str(out), "--pdf", str(pdf)]) == 0
    page = _Page()
    page.feed(out.read_text())
    assert page.banner["class"] == "pass" and page.banner["text"].startswith("PASS")
    assert "P1: put 1.979 ± 0.031 g at 236.17 ± 0.90 ° (holes 7 and 8: 0.2644 g + 1.746 g)" \
        in page.banner["text"]
    assert sorted(a.split(":")[0] for a in page.imgs) == ["plane P1", "plane P2", "sensor S1",
                                                         "sensor S2"]
    for title, cells in page.sections.items():        # no empty or single-value section
        assert sum(bool(c) for c in cells) >= 2, (title, cells)
    assert "Warnings" not in page.sections            # none: no section
    assert "Static and couple parts" in page.sections
    infl = [t for t in page.sections if t.startswith("Influence matrix")]
    assert infl and "condition number" in page.sections[infl[0]]
    assert any(c.startswith("0 mm/s pk (exactly determined") for c in
               page.sections["Vibration at the sensors"])
    text = re.sub(r"data:image/png;base64,[A-Za-z0-9+/=]*", "", out.read_text())
    assert not re.search(r"\de[-+]\d", text)          # no round-off like 2.776e-14
    assert "valid: amplitude 38.2 %, phase 18 °" in page.sections["Runs"]
    assert pdf.read_bytes()[:4] == b"%PDF"
    pypdf = pytest.importorskip("pypdf")
    first = pypdf.PdfReader(str(pdf)).pages[0].extract_text()
    assert first.index("PASS") < first.index("P1: put 1.979 ± 0.031 g") < first.index("plane P1")
