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


def test_batch_output_is_a_directory_or_a_summary_table(tmp_path, capsys):
    """`stand report FOLDER -o DIR` makes DIR (one HTML per recording, index.html, summary.csv)
    and says so; `-o S.json` / `-o S.csv` is the summary table alone; `-o R.html` is refused."""
    src = tmp_path / "recs"
    src.mkdir()
    for k in range(2):
        shutil.copy(REC, src / f"run{k}.h5")
    out = tmp_path / "new_dir"                         # does not exist yet
    capsys.readouterr()
    assert main(["report", str(src), "-o", str(out), "--workers", "1"]) == 0
    said = capsys.readouterr().out
    assert sorted(p.name for p in out.iterdir()) == ["index.html", "run0.html", "run1.html",
                                                      "summary.csv"]
    assert f"2 HTML reports and index.html in {out}/" in said
    assert f"summary table {out / 'summary.csv'}" in said
    assert list(pd.read_csv(out / "summary.csv")["status"]) == ["ok", "ok"]
    js = tmp_path / "s.json"
    assert main(["report", str(src), "-o", str(js), "--workers", "1"]) == 0
    rows = json.loads(js.read_text())
    assert [r["status"] for r in rows] == ["ok", "ok"] and not rows[0]["report"]
    assert f"summary table {js}" in capsys.readouterr().out
    assert main(["report", str(src), "-o", str(tmp_path / "s.csv"), "--workers", "1"]) == 0
    assert len(pd.read_csv(tmp_path / "s.csv")) == 2
    assert sorted(p.name for p in tmp_path.iterdir()) == ["new_dir", "recs", "s.csv", "s.json"]
    assert main(["report", str(src), "-o", str(tmp_path / "r.html")]) == 2
    assert "give -o DIR" in capsys.readouterr().err
    assert main(["report", str(src), "-o", str(js), "--summary", str(tmp_path / "x.csv")]) == 2
