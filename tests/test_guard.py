"""Inputs are never outputs: a typo in a shell command must not destroy a scene or a recording."""
import hashlib
import io
import os
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path

import pytest

from stand.cli.main import main
from stand.io.guard import OutputRefused, check_outputs

SCENES = Path(__file__).resolve().parents[1] / "data_samples" / "scenes"


def _cli(*argv):
    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        code = main([str(a) for a in argv])
    return code, out.getvalue(), err.getvalue()


def _digest(p: Path) -> str:
    return hashlib.sha256(p.read_bytes()).hexdigest()


@pytest.fixture()
def scene(tmp_path):
    p = tmp_path / "scene.toml"
    p.write_text((SCENES / "no_balancer.toml").read_text().replace("duration = 40.0", "duration = 1.0"))
    return p


@pytest.mark.parametrize("spelling", ["same", "dot", "symlink", "absolute"])
def test_run_onto_its_own_scene_is_refused(scene, tmp_path, spelling, monkeypatch):
    monkeypatch.chdir(tmp_path)
    before = _digest(scene)
    src, out = "scene.toml", "scene.toml"
    if spelling == "dot":
        out = "./scene.toml"
    elif spelling == "symlink":
        os.symlink("scene.toml", tmp_path / "link.toml")
        src = "link.toml"
    elif spelling == "absolute":
        out = str(scene)
    code, out_text, err = _cli("run", src, "-o", out)
    assert code == 2 and err.count("\n") == 1
    assert "is the input" in err and "scene.toml" in err
    assert _digest(scene) == before


def test_report_onto_its_own_recording_is_refused(scene, tmp_path):
    rec = tmp_path / "run.h5"
    assert _cli("run", scene, "-o", rec)[0] == 0
    before = _digest(rec)
    code, _, err = _cli("report", rec, "-o", rec)
    assert code == 2 and "is the input" in err and str(rec) in err
    code, _, err = _cli("report", rec, "-o", tmp_path / "r.html", "--json-file", rec)
    assert code == 2 and "is the input" in err
    assert _digest(rec) == before


def test_output_of_another_kind_needs_force(scene, tmp_path):
    table = tmp_path / "table.csv"
    table.write_text("t_s,x_m,y_m\n0,0,0\n")
    before = _digest(table)
    code, _, err = _cli("run", scene, "-o", table)
    assert code == 2 and "--force" in err and "csv" in err and "hdf5" in err
    assert _digest(table) == before
    assert _cli("run", scene, "-o", table, "--force")[0] == 0
    assert table.read_bytes().startswith(b"\x89HDF")


def test_a_scene_file_is_never_replaced_even_with_force(scene, tmp_path):
    other = tmp_path / "other.toml"
    other.write_text("[scene]\nname = 'keep me'\n")
    before = _digest(other)
    code, _, err = _cli("run", scene, "-o", other, "--force")
    assert code == 2 and "source file" in err
    assert _digest(other) == before


def test_check_outputs_allows_new_files_and_same_kind(tmp_path):
    a = tmp_path / "a.h5"
    check_outputs([tmp_path / "in.toml"], [(a, "hdf5"), (None, "json")])
    a.write_bytes(b"\x89HDF\r\n\x1a\n" + b"\0" * 8)
    check_outputs([], [(a, "hdf5")])
    with pytest.raises(OutputRefused, match="not html"):
        check_outputs([], [(a, "html")])
