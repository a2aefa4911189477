"""stand accuracy -o: the error-against-run-time report (HTML + JSON)."""
import json
import re

from stand.cli import main
from stand.reports.accuracy_report import ROW_SCHEMA, SCHEMA, recommend
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
    assert f"{rec['relative_error']:.6g}" in text      # the HTML shows the JSON's numbers


def test_recommend_picks_the_fastest_good_run():
    rows = [{"method": "A", "relative_error": 1e-8, "wall_time_s": 2.0, "success": True},
            {"method": "B", "relative_error": 1e-7, "wall_time_s": 1.0, "success": True},
            {"method": "C", "relative_error": 1e-9, "wall_time_s": 0.1, "success": False}]
    assert recommend(rows, 1e-6)["method"] == "B"
    r = recommend(rows, 1e-12)
    assert not r["reached"] and r["method"] == "A"


def test_missing_output_directory_fails_before_the_run(tmp_path, capsys):
    scene = tmp_path / "s.toml"
    scene.write_text(SHORT)
    assert main(["accuracy", str(scene), "-o", str(tmp_path / "no" / "a.html")]) != 0
    assert "does not exist" in capsys.readouterr().err
