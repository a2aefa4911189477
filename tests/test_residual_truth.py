"""The run's residual unbalance is the static (and couple) residual of the whole rotor, checked
against an independent sum from the scene file and the balls' recorded angles; the whirl
radius is the motion about the orbit's centre; the folder summary fills its grade columns."""
import math
import tomllib
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import stand
from stand.analysis.batch import summary_columns
from stand.integrate.residual import (couple_residual, plane_positions, plane_residuals,
                                      static_residual)
from stand.integrate.result import whirl_about_centre

SCENES = Path("data_samples/scenes")


def _toml(name):
    return tomllib.loads((SCENES / f"{name}.toml").read_text())


def _balls(run, doc, k):
    """Each weight plane's sum m r e^{i (ball angle - rotor angle)} at sample k [kg m], from the
    scene file's masses and radii and the run's recorded angles (weights numbered in file order)."""
    out, j = {}, 0
    for w in doc.get("weights", []):
        for _ in range(w["count"]):
            j += 1
            a = run.weights[f"ball{j}"]["angle"][k] - run.rotor_angle[k]
            out[w["plane"]] = out.get(w["plane"], 0j) + w["mass"] * w["radius"] * np.exp(1j * a)
    return out


def _run(name):
    return stand.run(stand.load(SCENES / f"{name}.toml"))


@pytest.mark.parametrize("name", ["family_grinding", "family_spatial"])
def test_unbalance_in_its_own_plane_counts_with_the_balls(name):
    # the rotor's unbalance sits in plane "unbalance" / "unbalance1", the balls in the balancer
    # plane; before the fix the summary read the balancer plane alone: 2000 g mm = 50 % of S
    run, doc = _run(name), _toml(name)
    st = doc["structure"]
    U = st["unbalance"] + sum(_balls(run, doc, -1).values())   # angle 0: along the mark
    S = sum(w["count"] * w["mass"] * w["radius"] for w in doc["weights"])
    f = run.final
    # the same sum of the same float64 angles: agreement to rounding (1e-12 of S)
    assert f["residual_unbalance_g_mm"] * 1e-6 == pytest.approx(abs(U), abs=1e-12 * S)
    # the balls cancel the unbalance (0.5 S) to the solver's accuracy: the 1X is ~1e-9 m
    assert f["residual_unbalance"] < 1e-5
    assert f["capacity_g_mm"] == pytest.approx(S * 1e6, rel=1e-12)
    # the whole record: the static residual at t = 0 is the unbalance plus the initial balls
    U0 = st["unbalance"] + sum(_balls(run, doc, 0).values())
    assert abs(run.residual_unbalance()[0] - U0) < 1e-12 * S
    assert "residual_couple_g_mm2" not in f      # unbalance and balls in one axial position


def test_couple_residual_of_two_balancer_planes():
    # paper 003: balancers at -0.15 m and 0.2 m from the centre of mass, unbalance at 0.2 m
    name = "paper003_two_balancers"
    run, doc = _run(name), _toml(name)
    st = doc["structure"]
    z = {f"balancer{k + 1}": a for k, a in enumerate(st["balancer_positions"])}
    S = sum(w["count"] * w["mass"] * w["radius"] for w in doc["weights"])
    for k, idx in ((0, slice(0, 1)), (-1, slice(-1, None))):
        balls = _balls(run, doc, k)
        Us = st["unbalance"] + sum(balls.values())
        Uc = st["unbalance"] * st["unbalance_position"] + sum(z[p] * u for p, u in balls.items())
        # the same sums of the same float64 angles: rounding (lever arms below 0.35 m)
        assert abs(static_residual(run, idx)[0] - Us) < 1e-12 * S
        assert abs(couple_residual(run, idx)[0] - Uc) < 1e-12 * S * 0.35
        # the caller's positions (the sweep's, computed once) are used as given: the same
        # positions give the same couple; an origin moved by 0.1 m adds 0.1 U_s
        zp = plane_positions(run.scene, plane_residuals(run, idx))
        assert couple_residual(run, idx, positions=zp) == couple_residual(run, idx)
        moved = {p: v + 0.1 for p, v in zp.items()}
        assert abs(couple_residual(run, idx, positions=moved)[0] - (Uc + 0.1 * Us)) < 1e-12 * S
    # at the start the balls do not cancel: a real couple (independent value of the order S l)
    assert abs(couple_residual(run, slice(0, 1))[0]) > 1e-4
    f = run.final
    assert f["residual_couple_g_mm2"] * 1e-9 == pytest.approx(abs(Uc), abs=1e-12 * S * 0.35)
    assert f["residual_unbalance"] < 1e-6 and f["residual_couple_g_mm2"] < 1e-3


def test_planar_residual_unchanged():
    name = "screen_lab"
    run, doc = _run(name), _toml(name)
    r, b = doc["rotor"], doc["balancer"]
    a = np.array([w["angle"][-1] for w in run.weights.values()]) - run.rotor_angle[-1]
    U = r["mass"] * r["eccentricity"] + np.sum(b["mass"] * b["radius"] * np.exp(1j * a))
    S = b["count"] * b["mass"] * b["radius"]
    assert run.final["residual_unbalance_g_mm"] * 1e-6 == pytest.approx(abs(U), abs=1e-12 * S)


def test_analyze_truth_of_the_grinding_recording(tmp_path):
    # the recording's truth: the static residual over the stationary stretch (was 2000 g mm)
    name = "family_grinding"
    path = tmp_path / "g.h5"
    stand.save(_run(name), path)
    rec, doc = stand.read(path), _toml(name)
    a = stand.analyze(rec)
    st = a["stationary_stretch"]
    w = np.nonzero((rec.t >= st["t_start_s"] - 1e-9) & (rec.t <= st["t_end_s"] + 1e-9))[0]
    U = np.mean([doc["structure"]["unbalance"] + sum(_balls(rec, doc, k).values()) for k in w])
    assert a["truth_unbalance_gmm"] * 1e-6 == pytest.approx(abs(U), abs=1e-12)
    assert a["truth_unbalance_gmm"] < 1.0          # of an unbalance of 2000 g mm


def test_whirl_radius_is_about_the_orbit_centre():
    # synthetic: a 1 um circle about an offset of 30 mm, one whole revolution
    phi = np.linspace(0, 2 * math.pi, 400, endpoint=False)
    r, c = whirl_about_centre(-0.03 + 1e-6 * np.cos(phi), 1e-6 * np.sin(phi))
    assert c == pytest.approx(-0.03, abs=1e-15)
    np.testing.assert_allclose(r, 1e-6, rtol=1e-8)    # the offset's 1e-17 m rounding / 1e-6 m


def test_fixed_point_stand_gravity_sag_is_not_whirl():
    # x holds -28.586 mm (gravity sag of the hinged rotor), y = 0: before the fix the "whirl
    # radius" was 28584 um, the distance from the origin
    run = _run("family_fixed_point_stand")
    f = run.final
    sel = run.t >= run.t[-1] - 2 * math.pi / abs(run.rotor_speed[-1])
    x, y = run.x[sel], run.y[sel]
    assert f["static_offset_m"] == pytest.approx(abs(np.mean(x + 1j * y)), rel=1e-12)
    assert f["static_offset_m"] == pytest.approx(0.02858, rel=1e-3)
    r = np.abs(x + 1j * y - np.mean(x + 1j * y))
    assert f["whirl_radius_m"] == pytest.approx(np.mean(r), rel=1e-12)
    # the motion about the mean: at most its largest excursion, far below the sag
    assert f["whirl_radius_m"] <= np.max(r) and f["whirl_radius_m"] < 1e-3 * f["static_offset_m"]


def test_summary_columns_fill_grade_and_programme():
    doc = {"speed_hz": 12.0, "iso_grade": {"grade_mm_s": 1.2, "grade_mm_s_std": 0.05,
                                           "class": "G 2.5", "target_mm_s": 6.3, "passed": True,
                                           "permissible_gmm": 370.0, "service_speed_rpm": 720.0,
                                           "mass_kg": 4.45},
           "programme": {"kind": "run-up + constant", "stretches": [{"kind": "run-up"}]},
           "runup": {"bode": {"t_s": [0.1]}}, "reduction": {"factor": 48.0},
           "ring_reading": None, "components": [], "regime": None}
    row = summary_columns(doc)
    assert row["iso_grade"] == "G 2.5" and row["iso_passed"] is True
    assert row["iso_grade_mm_s"] == 1.2 and row["programme"] == "run-up + constant"
    assert row["reduction_factor"] == 48.0 and row["regime"] is None
    assert not {"runup", "ring_reading", "components", "reduction"} & set(row)


def test_folder_summary_grade_programme_and_truth(tmp_path):
    from stand.cli.main import main

    d = tmp_path / "recs"
    d.mkdir()
    for name in ("screen_lab", "family_grinding"):
        stand.save(_run(name), d / f"{name}.h5")
    out = tmp_path / "summary.csv"
    assert main(["analyze", str(d), "-o", str(out), "--workers", "1"]) == 0
    df = pd.read_csv(out).set_index(pd.read_csv(out)["file"].map(lambda f: Path(f).stem))
    single = stand.analyze(d / "screen_lab.h5")
    assert df.loc["screen_lab", "iso_grade"] == single["iso_grade"]["class"]
    assert df.loc["screen_lab", "iso_grade_mm_s"] == pytest.approx(single["iso_grade"]["grade_mm_s"])
    assert (df["programme"] == "run-up + constant").all()
    assert "runup" not in df.columns
    assert df.loc["family_grinding", "truth_unbalance_gmm"] < 1.0


def test_flexible_rotor_static_and_couple_from_the_stored_recording():
    # no weights: the residual is the scene's unbalances, 2 g m at 30 deg and 1 g m at 0 deg at
    # 0.25 m, 1.5 g m at 200 deg at 0.75 m from the left support (before: the main plane's
    # 2000 g mm alone, no couple)
    rec, doc = stand.read("data_samples/recordings/influence_trial1.h5"), _toml("influence_trial1")
    st = doc["structure"]
    U = {p: s * np.exp(1j * math.radians(a)) for p, (s, a) in st["unbalances"].items()}
    Us, Uc = sum(U.values()), sum(st["planes"][p] * u for p, u in U.items())
    f = rec.final
    # the recording's float64 of the same numbers: rounding of the angles (1e-15 rad)
    assert f["residual_unbalance_g_mm"] * 1e-6 == pytest.approx(abs(Us), rel=1e-12)
    assert f["residual_couple_g_mm2"] * 1e-9 == pytest.approx(abs(Uc), rel=1e-12)
