"""Every body-weight sample through every command (issue 16 acceptance).

``stand run``, ``stand snapshot --instrument strobe``, ``stand analyze``,
``stand report`` and ``stand accuracy --fast`` succeed on each sample, and the
report's residual unbalance -- identified from the shaft's 1X response with
the structure's receptance, weights locked -- agrees with the recording's
ground truth (rotor unbalance plus each body's mass times its centre-of-mass
offset, rotor frame) within 2 %: at a steady synchronous motion both are the
same quantity, so the bound is the identification's window error only.
"""
import json
from pathlib import Path

import numpy as np
import pytest

import stand
from stand.cli.main import main

SCENES = Path(__file__).resolve().parents[1] / "data_samples" / "scenes"
KINDS = ["two_axis_pendulum", "coupled_pair", "damper", "liquid_float", "liquid_chamber"]


# the JSON the report is rendered from on every kind; the HTML (its seven figures, ~2 s of
# matplotlib) of every kind under `-m full`.  By default the HTML of a body-weight recording's
# report is drawn by tests/test_one_stand_matrix.py::test_every_command_on_every_scene_cli
# [body_two_axis_pendulum] (the same sample, shortened; its report's HTML and JSON)
CASES = ([pytest.param(k, False, id=k) for k in KINDS]
         + [pytest.param(k, True, id=f"{k}-html", marks=pytest.mark.full) for k in KINDS])


@pytest.mark.parametrize("kind, html", CASES)
def test_every_command_on_the_body_sample(kind, html, tmp_path, capsys):
    scene = SCENES / f"body_{kind}.toml"
    rec = tmp_path / "r.h5"
    assert main(["run", str(scene), "-o", str(rec), "--no-progress"]) == 0
    assert main(["snapshot", str(rec), "--instrument", "strobe", "--frame", "-1",
                 "-o", str(tmp_path / "s.png")]) == 0
    assert (tmp_path / "s.png").stat().st_size > 0
    assert main(["analyze", str(rec), "--json"]) == 0
    an = json.loads(_last_json(capsys))
    assert an["speed_hz"] == pytest.approx(30.0, rel=1e-6)
    rj = tmp_path / "rep.json"
    assert main(["report", str(rec), "--json-file", str(rj)]
                + (["-o", str(tmp_path / "rep.html")] if html else [])) == 0
    assert (tmp_path / "rep.html").exists() == html
    rep = json.loads(rj.read_text())
    assert main(["accuracy", str(scene), "--fast"]) == 0
    r = stand.read(rec)
    U = r.truth["residual/balancer"][0][-1]
    truth_gmm = float(np.hypot(*U)) * 1e6
    got = rep["balancing_quality"]["residual_unbalance_gmm"]
    assert truth_gmm > 100.0                      # a residual worth comparing (g mm)
    assert got == pytest.approx(truth_gmm, rel=0.02)
    assert an["unbalance_gmm"] == pytest.approx(truth_gmm, rel=0.02)


def _last_json(capsys):
    out = capsys.readouterr().out
    return out[out.index("{"):]
