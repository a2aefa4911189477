"""Scene-level theory (speed map, ``stand theory``) and theory against the simulator."""
import dataclasses
import json
from pathlib import Path

import numpy as np
import pytest

from stand.analysis.regime import classify
from stand.scene.model import RunSettings, SpeedDrive
from stand.scene.parse import load_scene, scene_from_dimensionless
from stand.integrate.simulate import simulate
from stand.theories.planar import main_motion as mm
from stand.theories.planar import qp
from stand.theories.planar.speedmap import TheoryError, scene_theory
from _verify import at_speed, check_thresholds

from _helpers import stand_stdout, theory_computed_once

SCENES = Path(__file__).resolve().parents[1] / "data_samples" / "scenes"


@pytest.fixture(scope="module")
def runup(tmp_path_factory):
    """ball_runup.toml and its speed map, computed once for the tests that read it, by
    ``stand theory --json --plot`` (the map drawn from the one the JSON was made of); returns
    ``(scene, theory, JSON document, PNG path)``."""
    from stand.theories.planar import speedmap

    sc = load_scene(SCENES / "ball_runup.toml")
    png = tmp_path_factory.mktemp("theory") / "map.png"
    with theory_computed_once() as cache:
        out = stand_stdout("theory", SCENES / "ball_runup.toml", "--json", "--plot", png)
        th = speedmap.scene_theory(sc)          # the command's, from the cache
    assert len(cache) == 1                      # one computation: the JSON, the plot and th
    return sc, th, json.loads(out), png


@pytest.fixture(scope="module")
def stuck():
    """ball_stuck.toml and its speed map (computed once for the tests that read it).  Its
    readers read the bands, the critical speeds and the QP law, not the ``closed_forms``
    section: left out (about half the map's time; scene_theory's docstring: nothing else
    changes, which test_torque_drive_is_analysed_at_its_target_speed checks key by key)."""
    sc = load_scene(SCENES / "ball_stuck.toml")
    return sc, scene_theory(sc, closed_forms=False)


def test_stand_theory_json_ball_runup(runup):
    _, _, doc, png = runup
    assert png.stat().st_size > 1000
    f0 = doc["natural_frequency_hz"]
    assert f0 == pytest.approx(3.0, rel=1e-4)  # the stand's 3 Hz with all masses
    for key in ("critical_speeds_hz", "stable_bands", "qp"):
        assert key in doc
    for c in doc["critical_speeds_hz"]:
        assert {"hz", "motion", "kind"} <= set(c)
    for b in doc["stable_bands"]:
        assert {"from_hz", "to_hz", "motions"} <= set(b)
    for key in ("escape_speed_hz", "roots_hz", "stable_root_hz", "precession_amplitude_m",
                "nutation_amplitude_m", "petals", "shape"):
        assert key in doc["qp"]
    # digest section 6.5, conservative case, M = 4.45 kg, m = 45 g, n = 2 (Rt = 0.0099):
    # small or large unbalance (d = 1): 1.0, 1.0316, 1.4366 f0; balls 90 deg apart (d = 0): 1.3626 f0
    cons = doc["conservative"]
    np.testing.assert_allclose(np.array(cons["small_or_large_unbalance_d1"]["hz"]) / f0,
                               [1.0, 1.0316, 1.4366], atol=1e-3)
    np.testing.assert_allclose(np.array(cons["balls_90deg_apart_d0"]["hz"]) / f0, [1.3626], atol=1e-3)
    # the scene's own unbalance 0.5 S (d = 0.5): the two-balls-vs-S table gives 1.3919
    np.testing.assert_allclose(np.array(cons["scene_configuration"]["hz"]) / f0, [1.3919], atol=1e-3)
    # with the scene's damping the main motion is stable at the operating speed 15 rev/s
    op = doc["operating_speed_hz"]
    band = next(b for b in doc["stable_bands"] if b["from_hz"] <= op <= b["to_hz"])
    assert "main" in band["motions"] and "quasi-periodic" not in band["motions"]


def test_speed_map_edges_are_the_exact_thresholds(stuck):
    sc, th = stuck
    p = th.parameters
    R_star = qp.escape_speed(p["Rt"], p["h"], p["H"])
    assert R_star == pytest.approx(9.0)
    main_c = mm.critical_speeds(p["Rt"], p["h"], p["H"], p["d"], R_min=0.05)
    edges = sorted({b.R_to for b in th.bands[:-1]})
    for R in [R_star] + [c.R for c in main_c]:
        assert min(abs(e - R) for e in edges) < 1e-12 * R
    # quasi-periodic stable throughout (0, R*) and not above (5.226)
    for b in th.bands:
        mid = np.sqrt(b.R_from * b.R_to)
        assert ("quasi-periodic" in b.motions) == (mid < R_star)
    # operating speed R = 3: stable root 0.96135 (Table 5.1-B), curtate spot, k = 3.12
    q = th.qp
    assert q["stable_root_R"] == pytest.approx(0.96135, abs=1e-5)
    assert q["k"] == pytest.approx(3 / 0.96135, rel=1e-4)
    assert q["precession_amplitude_m"] / sc.length_scale == pytest.approx(10.297, abs=2e-3)


def test_theory_refuses_out_of_scope_scenes():
    with pytest.raises(TheoryError, match="no weights"):
        scene_theory(load_scene(SCENES / "no_balancer.toml"))


def test_stuck_balls_speed_is_the_stable_qp_root(stuck):
    """Acceptance: simulated ball speed of ball_stuck.toml = the stable root of (5.181), 0.1 %."""
    sc, th = stuck
    reg = classify(simulate(sc))
    assert reg.name == "quasi-periodic"
    assert np.allclose(reg.weight_speed, th.qp["stable_root_R"], rtol=1e-3)


def test_run_up_just_above_the_escape_speed_ends_balanced():
    """Acceptance: the ball_stuck run-up taken to 1.1 R* (R* = 9) escapes and balances;
    taken to 0.9 R* it stays stuck (digest 5.3 time-domain table)."""
    sc = load_scene(SCENES / "ball_stuck.toml")
    above = classify(simulate(at_speed(sc, 1.1 * 9.0, hold_tau=900.0)))
    below = classify(simulate(at_speed(sc, 0.9 * 9.0, hold_tau=900.0)))
    assert above.name == "main" and above.residual < 1e-3
    assert below.name == "quasi-periodic"


def test_balancing_decay_rate_is_the_least_damped_eigenvalue():
    """Acceptance: at R = 3 the decay rate of |psi| equals -max Re(lambda) of (5.90) (10 %)."""
    Rt, h, H, e0, R = 0.01, 0.5, 0.1, 0.3, 3.0
    sc = scene_from_dimensionless(2, Rt, h, H, e0, drive=SpeedDrive(np.array([[0.0, R]])),
                                  run=RunSettings(600.0, 1.0, 1e-10, 1e-12),
                                  initial_angles=np.array([2.2, -2.2]))
    tr = simulate(sc)
    psi = np.abs(tr.residual_unbalance()) / sc.balancer.capacity
    sel = (psi < 1e-2) & (psi > 1e-7)
    rate = -np.polyfit(tr.t[sel], np.log(psi[sel]), 1)[0]
    lam = -mm.spectral_abscissa(R, Rt, h, H, mm.d_two_balls(e0))
    assert rate == pytest.approx(lam, rel=0.1)


@pytest.mark.slow
def test_theory_vs_simulation_on_both_sides_of_each_threshold(runup):
    sc, th = runup[:2]
    checks = check_thresholds(sc, th)      # th is scene_theory(sc), what it computes by default
    assert len(checks) == 2 * len(th.critical_speeds)
    bad = [c for c in checks if not c.match]
    assert not bad, bad


def _dimless(n, Rt, h, H, e0, R=3.0):
    return scene_from_dimensionless(n, Rt, h, H, e0, drive=SpeedDrive(np.array([[0.0, R]])),
                                    run=RunSettings(10.0, 1.0))


def test_one_weight_cannot_balance_half_capacity():
    """n = 1, e0 = 0.5: no main motion exists ((5.50): one weight balances only e0 = 1)."""
    th = scene_theory(_dimless(1, 0.01, 0.2, 0.1, 0.5), closed_forms=False)   # (bands only)
    assert all("main" != m for b in th.bands for m in b.motions)
    assert any("cannot balance" in w for w in th.warnings)


def test_band_between_two_close_thresholds_is_kept():
    """Main critical speed 1.00122 and escape speed R* = 1.005 are adjacent: the band between
    them has both the main and the quasi-periodic motion."""
    th = scene_theory(_dimless(2, 0.01, 2.0, 2.0, 0.3), closed_forms=False)   # (bands only)
    R_star = qp.escape_speed(0.01, 2.0, 2.0)
    c = mm.critical_speeds(0.01, 2.0, 2.0, mm.d_two_balls(0.3), R_min=0.05)[-1].R
    assert c < R_star < 1.01
    band = next(b for b in th.bands if b.R_from <= np.sqrt(c * R_star) <= b.R_to)
    assert set(band.motions) == {"main", "quasi-periodic"}
    assert band.R_from == pytest.approx(c, rel=1e-12) and band.R_to == pytest.approx(R_star, rel=1e-12)


def test_torque_drive_is_analysed_at_its_target_speed(runup):
    import dataclasses as dc
    from stand.scene.model import TorqueDrive
    s, a = runup[:2]
    st = dc.replace(s, rotor=dc.replace(s.rotor, inertia=0.05),
                    drive=TorqueDrive("speed_feedback", c1=0.5, target_speed=2 * np.pi * 15))
    b = scene_theory(st, closed_forms=False)
    assert [c.R for c in a.critical_speeds] == pytest.approx([c.R for c in b.critical_speeds])
    assert b.operating_speed_R == pytest.approx(a.operating_speed_R)
    # closed_forms=False (the balancing report's call) leaves that section out, nothing else
    da, db = a.to_dict(), b.to_dict()
    assert db.pop("closed_forms") == {} and da.pop("closed_forms")["unbalance_independent_threshold_R"] > 1
    assert db.pop("warnings") == da.pop("warnings") + [
        "torque drive: the theory assumes the prescribed speed drive.target_speed"]
    assert db == da


def test_anisotropic_supports_give_the_engineering_criterion(capsys):
    import dataclasses as dc
    s = load_scene(SCENES / "ball_runup.toml")
    sa = dc.replace(s, supports=dc.replace(s.supports, stiffness_y=2.0 * s.supports.stiffness_x))
    th = scene_theory(sa)
    Ms = sa.total_mass
    w = [np.sqrt(c / Ms) / (2 * np.pi) for c in (sa.supports.stiffness_x, 1.5 * sa.supports.stiffness_x,
                                                   sa.supports.stiffness_y)]
    np.testing.assert_allclose([c.hz for c in th.critical_speeds], w, rtol=1e-12)  # (2.29)
    doc = th.to_dict()
    assert {"escape_speed_hz", "stable_root_hz", "petals", "shape"} <= set(doc["qp"])
    mid = np.sqrt(w[1] * w[2])
    band = next(b for b in doc["stable_bands"] if b["from_hz"] <= mid <= b["to_hz"])
    assert band["motions"] == []


def test_no_qp_motion_without_damping_and_petals_always_reported(stuck):
    th = scene_theory(_dimless(2, 0.01, 0.0, 0.1, 0.3))
    assert all("quasi-periodic" not in b.motions for b in th.bands)
    qp_stuck = stuck[1].qp
    # k = 3 / 0.96135 = 3.12: about 2 petals, the pattern turns slowly (digest 5.3)
    assert qp_stuck["petals"] == 2 and qp_stuck["pattern_closed"] is False


def test_beyond_capacity_no_spurious_critical_speed_at_resonance():
    """e0 = 1.5: the weights-together branch runs through R = 1 (heavy-side side motion below,
    maximally balanced main motion above) without a change of stability; the map reports the
    band where it is unstable just above resonance (digest 4.5 at finite Rt, side.py notes)."""
    th = scene_theory(_dimless(2, 0.01, 0.1, 0.1, 1.5), closed_forms=False)   # (bands only)
    assert all(abs(c.R - 1.0) > 1e-6 for c in th.critical_speeds)
    lost = [c for c in th.critical_speeds if c.motion == "main (maximally balanced)"]
    assert [c.kind for c in lost] == ["loses", "gains"]
    assert 1.0 < lost[0].R < lost[1].R < 1.6


def test_ranges_are_printed_in_words(runup):
    """`stand theory` prints every range one way, in words: the chapter-5 bands
    ("0.3 rev/s to 2.751 rev/s (0.1 f0 to 0.9171 f0)"), the working ranges ("5.7865 rev/s to
    6.8691 rev/s, from 8.2269 rev/s up": no Python tuple, no inf) and the side-motion gap."""
    import math

    from stand.theories.scene import _range, theory_lines

    assert _range(12.0, None) == _range(12.0, math.inf) == "from 12 rev/s up"
    assert _range(12.0, 40.0) == "12 rev/s to 40 rev/s"
    assert _range(None, 40.0) == "up to 40 rev/s"
    assert _range(0.95762, 1.0443, "", 4) == "from 0.9576 to 1.044"
    _, _, doc, _ = runup
    lines = theory_lines({**doc, "kind": "chapter5"})
    bands = lines[lines.index("stable motions by speed band:") + 1:][:len(doc["stable_bands"])]
    for b, line in zip(doc["stable_bands"], bands):    # each band from its edges, f0 its unit
        assert line.startswith(f"  {b['from_hz']:.4g} rev/s to {b['to_hz']:.4g} rev/s "
                               f"({b['R_from']:.4g} f0 to {b['R_to']:.4g} f0): ")
    # the engineering criterion's ranges start at the critical speeds (planar, (2.15))
    structure = {"kind": "structure", "scene": "s", "rotor_type": "planar", "source": "2.5.1",
                 "natural_frequencies_hz_at_rest": [5.0],
                 "engineering_criterion": {"balancer": {
                     "critical_speeds_hz": [5.7865, 6.8691, 8.2269],
                     "working_ranges_hz": [[5.7865, 6.8691], [8.2269, None]]}}}
    line = theory_lines(structure)[1]
    assert line.endswith("working ranges 5.7865 rev/s to 6.8691 rev/s, from 8.2269 rev/s up")
    assert "inf" not in line and "(" not in line
