"""stand accuracy -o: the error-against-run-time report (HTML + JSON)."""
import json
import re

import pytest
from _html import body_children

from stand.cli.main import main
from stand.reports.accuracy_report import ROW_SCHEMA, SCHEMA, accuracy_banner, recommend
from stand.reports.html import check_schema

SHORT = open("data_samples/scenes/ball_runup.toml").read().replace("duration = 40.0", "duration = 4.0")


def test_report_files_schema_and_self_contained(tmp_path, capsys):
    scene = tmp_path / "s.toml"
    scene.write_text(SHORT)
    html, js = tmp_path / "a.html", tmp_path / "a.json"
    assert main(["accuracy", str(scene), "-o", str(html), "--json-file", str(js),
                 "--methods", "DOP853,LSODA,RK4", "--rtols", "1e-6,1e-9"]) == 0
    assert "recommended" in capsys.readouterr().out
    doc = json.loads(js.read_text())
    assert check_schema(doc, SCHEMA) == []
    assert all(check_schema(r, ROW_SCHEMA) == [] for r in doc["runs"])
    assert {r["method"] for r in doc["runs"]} == {"DOP853", "LSODA", "RK4"}
    # errors shrink with the tolerance for the adaptive methods
    dop = sorted((r["rtol"], r["relative_error"]) for r in doc["runs"] if r["method"] == "DOP853")
    assert dop[0][1] < dop[1][1]
    text = html.read_text()
    for attr in re.findall(r"(?:src|href)\s*=\s*['\"]([^'\"]*)", text):
        assert attr.startswith("#") or attr.startswith("data:image/png;base64,"), attr
    rec = doc["recommended"]
    assert rec["reached"] and rec["relative_error"] <= 1e-6
    from stand.io.numbers import plain

    assert plain(rec["relative_error"]) in text         # the HTML shows the JSON's numbers (4 digits)
    # the recommendation comes first: the element right after the title is the banner
    h1, banner = body_children(text)[:2]
    assert h1["tag"] == "h1" and banner["tag"] == "div"
    assert banner["attrs"] == {"id": "verdict", "class": "info"}
    headline, target, reference = banner["lines"]
    m = re.fullmatch(r"Use (\S+) at rtol (\S+): (\S+) relative error in (\S+) (m?s)", headline)
    assert m, headline
    assert m[1] == rec["method"] and float(m[2]) == rec["rtol"]
    assert float(m[3]) == pytest.approx(rec["relative_error"], rel=0.34)   # 1 significant digit
    shown_s = float(m[4]) * (1e-3 if m[5] == "ms" else 1.0)
    assert shown_s == pytest.approx(rec["wall_time_s"], rel=0.05)          # 2 significant digits
    assert "1e-6" in target and doc["reference"]["name"] in reference
    assert doc["verdict"]["headline"] == headline                          # the JSON says it too


def test_recommend_picks_the_fastest_good_run():
    rows = [{"method": "A", "relative_error": 1e-8, "wall_time_s": 2.0, "success": True},
            {"method": "B", "relative_error": 1e-7, "wall_time_s": 1.0, "success": True},
            {"method": "C", "relative_error": 1e-9, "wall_time_s": 0.1, "success": False}]
    assert recommend(rows, 1e-6)["method"] == "B"
    r = recommend(rows, 1e-12)
    assert not r["reached"] and r["method"] == "A"


def _doc(rec, runs=3):
    return {"recommended": rec, "runs": [{}] * runs,
            "reference": {"name": "closed form", "own_error_m": None, "scale_m": 0.0108}}


def test_banner_wording_and_rounding():
    b = accuracy_banner(_doc({"target_relative_error": 1e-6, "reached": True, "method": "DOP853",
                              "rtol": 1e-8, "relative_error": 2.3e-9, "wall_time_s": 0.314}))
    assert b["status"] == "info"
    assert b["headline"] == "Use DOP853 at rtol 1e-8: 2e-9 relative error in 0.31 s"
    assert b["lines"][1] == "Reference: closed form; max |r_ref| = 0.011 m."
    rk4 = accuracy_banner(_doc({"target_relative_error": 1e-6, "reached": True, "method": "RK4",
                                "rtol": None, "step_s": 0.0025, "relative_error": 5.1e-7,
                                "wall_time_s": 0.0222}))
    assert rk4["headline"] == "Use RK4 with a fixed step of 0.0025 s: 5e-7 relative error in 22 ms"
    short = accuracy_banner(_doc({"target_relative_error": 1e-12, "reached": False,
                                  "method": "Radau", "rtol": 1e-10, "relative_error": 3.4e-9,
                                  "wall_time_s": 14.6}))
    assert short["status"] == "fail"
    assert short["headline"] == ("No setting reaches 1e-12; the most accurate: Radau at rtol 1e-10: "
                                 "3e-9 relative error in 15 s")
    none = accuracy_banner(_doc({"target_relative_error": 1e-6, "reached": False}))
    assert none["status"] == "fail" and none["headline"].startswith("No run succeeded")


def test_missing_output_directory_fails_before_the_run(tmp_path, capsys):
    scene = tmp_path / "s.toml"
    scene.write_text(SHORT)
    assert main(["accuracy", str(scene), "-o", str(tmp_path / "no" / "a.html")]) != 0
    assert "does not exist" in capsys.readouterr().err
