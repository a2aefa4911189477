"""stand report: one recording -> HTML + JSON; a glob -> one HTML per file and a summary."""
import json
import shutil

import pandas as pd

from stand.cli.main import main

REC = "data_samples/recordings/influence_ref.h5"   # no chapter-5 theory to compute (issue 43)


def test_single_and_batch(tmp_path, capsys):
    html, js = tmp_path / "r.html", tmp_path / "r.json"
    assert main(["report", REC, "-o", str(html), "--json-file", str(js), "--grade", "G2.5"]) == 0
    doc = json.loads(js.read_text())
    assert doc["balancing_quality"]["iso_21940_11"]["required_grade_mm_s"] == 2.5
    assert html.read_text().startswith("<!DOCTYPE html>")
    for k in range(2):
        shutil.copy(REC, tmp_path / f"run{k}.h5")
    (tmp_path / "bad.h5").write_bytes(b"x")
    out = tmp_path / "html"
    out.mkdir()
    assert main(["report", str(tmp_path / "*.h5"), "-o", str(out), "--summary",
                 str(tmp_path / "s.csv"), "--workers", "2"]) == 0
    df = pd.read_csv(tmp_path / "s.csv")
    assert list(df["status"]) == ["error", "ok", "ok"]
    assert (out / "run0.html").exists() and (out / "run1.html").exists()
    assert main(["report", REC, "--grade", "G-1", "-o", str(html)]) == 2
    assert "grade" in capsys.readouterr().err
