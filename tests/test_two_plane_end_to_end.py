"""Two-plane balancing end to end (issue 17 part 2): the paper-003 rotor with two laser
screens -> `stand run` -> `stand track --screen` on each -> `stand analyze --tracks` ->
`stand report --tracks`; the per-plane unbalance within 3 % of the builder's truth."""
import json
import math
from pathlib import Path

import numpy as np
import pytest

from stand.cli.main import main

from _helpers import assert_result_contract, stand_stdout

SAMPLE = Path(__file__).resolve().parents[1] / "data_samples" / "scenes" / "paper003_two_screens.toml"


def _truth():
    """The builder's unbalances moved onto the correction planes a1, a2 (statics, lever rule)."""
    import tomllib

    st = tomllib.loads(SAMPLE.read_text())["structure"]
    a1, a2 = st["balancer_positions"]
    ang = math.radians(st["unbalance_angle"])     # every angle of a scene file is in degrees
    us = [(st["unbalance_position"], st["unbalance"], ang),
          (st["couple_positions"][0], st["couple_unbalance"], ang),
          (st["couple_positions"][1], st["couple_unbalance"], ang + math.pi)]
    U1 = sum(s * np.exp(1j * g) * (a2 - a) / (a2 - a1) for a, s, g in us)
    U2 = sum(s * np.exp(1j * g) * (a - a1) / (a2 - a1) for a, s, g in us)
    return U1, U2


@pytest.fixture(scope="module")
def two_plane_run(tmp_path_factory):
    d = tmp_path_factory.mktemp("two_plane")
    rec = str(d / "run.h5")
    assert main(["run", str(SAMPLE), "-o", rec, "--no-progress"]) == 0
    tracks = []
    for name in ("front", "rear"):
        out = str(d / f"{name}.csv")
        assert main(["track", rec, "--screen", name, "-o", out]) == 0
        tracks.append(out)
    return d, rec, tracks


def test_named_screens_parse_and_record(two_plane_run):
    import h5py
    import pandas as pd

    import stand

    sc = stand.load(str(SAMPLE))
    assert {"screen.front", "screen.rear"} <= set(sc.instruments)
    assert sc.instruments["screen.front"].pixel_pitch == sc.instruments["screen.rear"].pixel_pitch
    d, rec, tracks = two_plane_run
    with h5py.File(rec) as f:
        for name, pos in (("front", -0.5), ("rear", 0.6)):
            g = f[f"instruments/screen.{name}"]
            assert g.attrs["axial_position_m"] == pos
            truth = f[f"truth/screen.{name}/centre_px"][:]
            df = pd.read_csv(d / f"{name}.csv", comment="#")
            assert df["ok"].all() and len(df) == len(truth) >= 20
            err = np.hypot(df["u_px"] - truth[:, 0], df["v_px"] - truth[:, 1])
            assert np.sqrt(np.mean(err ** 2)) < 0.05


def test_analyze_two_plane_within_3_percent(two_plane_run, capsys):
    d, rec, tracks = two_plane_run
    capsys.readouterr()
    assert main(["analyze", rec, "--tracks", *tracks, "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    for row, U in zip(doc["planes"], _truth()):
        assert abs(row["unbalance_gmm"] - abs(U) * 1e6) < 0.03 * abs(U) * 1e6
        dang = (row["angle_deg"] - math.degrees(np.angle(U)) + 180) % 360 - 180
        assert abs(dang) < 2.0
        assert 0 < row["unbalance_gmm_std"] < 0.03 * row["unbalance_gmm"]


def test_two_plane_result_contract(two_plane_run):
    """The Python face of `stand analyze --tracks`: a TwoPlane result, the CLI's JSON."""
    from stand.analysis.two_plane import two_plane

    d, rec, tracks = two_plane_run
    res = two_plane(rec, tracks)
    assert_result_contract(res, cli_doc=json.loads(stand_stdout("analyze", rec, "--tracks",
                                                                *tracks, "--json")))


def test_report_two_plane_section(two_plane_run):
    d, rec, tracks = two_plane_run
    js, html = d / "report.json", d / "report.html"
    assert main(["report", rec, "--tracks", *tracks, "-o", str(html), "--json-file", str(js)]) == 0
    doc = json.loads(js.read_text())
    tp = doc["two_plane"]
    U_per = tp["iso_21940_11"]["permissible_gmm"]
    # G6.3, 10 kg at 30 rev/s: 1000 G m / Omega; lever rule over the planes -0.15, +0.2 m
    assert U_per == pytest.approx(1000 * 6.3 * 10.0 / (30 * 2 * math.pi))
    shares = [r["permissible_gmm"] for r in tp["planes"]]
    assert shares == pytest.approx([U_per * 0.2 / 0.35, U_per * 0.15 / 0.35])
    for row, U in zip(tp["planes"], _truth()):
        assert row["unbalance_gmm"] == pytest.approx(abs(U) * 1e6, rel=0.03)
        assert row["passed"] is (row["unbalance_gmm"] <= row["permissible_gmm"])
    assert tp["iso_21940_11"]["passed"] is False
    assert any(w["code"] == "two_plane_iso_failed" for w in doc["warnings"])
    assert "two_plane" in html.read_text()


def test_single_screen_form_still_parses():
    import stand

    sc = stand.load(str(SAMPLE.parent / "family_spatial.toml"))
    assert "screen" in sc.instruments and not any(k.startswith("screen.") for k in sc.instruments)


def test_named_instances_only_for_screens(tmp_path):
    import stand
    from stand.scene.model import SceneError

    text = SAMPLE.read_text() + "\n[instruments.keyphasor.extra]\nmark_angle = 0.0\n"
    p = tmp_path / "bad.toml"
    p.write_text(text.replace("[instruments.keyphasor]\nmark_angle = 0.0\n", ""))
    with pytest.raises(SceneError, match="no named sub-tables"):
        stand.load(str(p))


def test_report_tracks_the_screens_itself(two_plane_run):
    """Issue 32, item 5: `stand report` on the recording alone gives the two-plane verdict
    (the report tracks both screens) and leaves the single-plane table of dashes out."""
    d, rec, tracks = two_plane_run
    js, html = d / "auto.json", d / "auto.html"
    assert main(["report", rec, "-o", str(html), "--json-file", str(js)]) == 0
    doc = json.loads(js.read_text())
    tp = doc["two_plane"]
    for row, U in zip(tp["planes"], _truth()):
        assert row["unbalance_gmm"] == pytest.approx(abs(U) * 1e6, rel=0.03)
    assert tp["iso_21940_11"]["passed"] is False
    page = html.read_text()
    assert "No verdict" not in page and "FAIL" in page
    assert "id='two_plane'" in page and "id='quality'" not in page
    assert any("tracked by the report" in n for n in doc["notes"])


def test_screen_commands_name_the_screens(two_plane_run, capsys):
    """Without --screen, `stand snapshot`, `video` and `track` on a recording with only named
    screens stop (exit 2) naming them and the option to add; snapshot takes --screen as
    track and video do: the PNG is the screen's recorded frame, bit for bit."""
    import cv2
    import h5py

    d, rec, _ = two_plane_run
    png = d / "front.png"
    for argv in (["snapshot", rec, "--instrument", "screen", "-o", str(png)],
                 ["snapshot", rec, "--instrument", "rings", "-o", str(png)],
                 ["video", rec, "-o", str(d / "v.mkv")],
                 ["track", rec, "-o", str(d / "t.csv")]):
        capsys.readouterr()
        assert main(argv) == 2
        err = capsys.readouterr().err
        assert "two screens, front and rear" in err and "add --screen front or --screen rear" in err
    assert not png.exists() and not (d / "v.mkv").exists() and not (d / "t.csv").exists()
    assert main(["snapshot", rec, "--screen", "side", "-o", str(png)]) == 2
    assert "give --screen front or --screen rear" in capsys.readouterr().err
    assert main(["snapshot", rec, "--screen", "front", "--instrument", "strobe", "-o", str(png)]) == 2
    for name, frame in (("front", 3), ("rear", -1)):
        capsys.readouterr()
        assert main(["snapshot", rec, "--screen", name, "--frame", str(frame), "-o", str(png)]) == 0
        assert f"of screen {name}" in capsys.readouterr().out
        with h5py.File(rec) as f:
            want = f[f"instruments/screen.{name}/frames"][frame]
        got = cv2.imread(str(png), cv2.IMREAD_UNCHANGED)
        assert got.dtype == want.dtype and np.array_equal(got, want)
