"""Influence-coefficient balancing (issue 17, part 3): dsp.influence on synthetic
phasors, stand.analysis.influence on the flexible-shaft sample (reference + two trial
runs) against the model's exact correction, bad input, the CLI."""
import json
import math
from pathlib import Path

import numpy as np
import pytest

import stand
from dsp.influence import influence_balance, influence_matrix
from stand.cli.main import main
from stand.analysis.influence import (TrialWeight, influence_from_recordings, model_correction,
                             parse_trial)

ROOT = Path(__file__).resolve().parents[1]
SCENES = ROOT / "data_samples" / "scenes"
RECS = ROOT / "data_samples" / "recordings"
TRIALS = ["balancer1:10:0:100", "balancer2:10:90:100"]
PLANES = ["balancer1", "balancer2"]
SENSORS = ["probe1", "probe2"]


def _synthetic(A, U_true, T):
    """Phasors of a linear rotor: V0 = -A U_true, V_j = V0 + A[:, j] T_j."""
    V0 = -A @ U_true
    V = np.array([V0 + A[:, j] * T[j] for j in range(len(T))])
    return V0, V


A2 = np.array([[2.0e-2 * np.exp(0.3j), 0.7e-2 * np.exp(2.1j)],
               [0.5e-2 * np.exp(-1.2j), 3.0e-2 * np.exp(0.9j)]])   # m / (kg m)
U_TRUE = np.array([1.2e-3 * np.exp(1j * math.radians(40.0)),
                   0.8e-3 * np.exp(1j * math.radians(250.0))])     # kg m
T_TRIAL = np.array([1e-3, 1e-3j])


# ------------------------------------------------------------------ pure dsp
def test_square_system_gives_the_exact_correction():
    V0, V = _synthetic(A2, U_TRUE, T_TRIAL)
    np.testing.assert_allclose(influence_matrix(V0, V, T_TRIAL), A2, rtol=1e-12)
    res = influence_balance(V0, V, T_TRIAL, [0.1, 0.05], planes=PLANES, sensors=SENSORS)
    np.testing.assert_allclose(res.correction_kg_m, U_TRUE, rtol=1e-12)
    np.testing.assert_allclose(res.mass_g, [12.0, 16.0], rtol=1e-12)
    np.testing.assert_allclose(res.angle_deg, [40.0, 250.0], atol=1e-9)
    np.testing.assert_allclose(np.abs(res.residual_m), 0.0, atol=1e-15)
    assert np.all(res.mass_std_g == 0) and res.condition < 10
    df = res.to_frame()
    assert list(df.index) == PLANES
    assert {"mass_g", "mass_std_g", "angle_deg", "angle_std_deg", "radius_mm",
            "correction_gmm"} <= set(df.columns)
    np.testing.assert_allclose(df["correction_gmm"], [1200.0, 800.0], rtol=1e-12)
    json.dumps(res.to_dict())


def test_more_sensors_than_planes_is_least_squares():
    A3 = np.vstack([A2, [[1.1e-2 * np.exp(0.5j), -0.9e-2 * np.exp(0.2j)]]])
    V0, V = _synthetic(A3, U_TRUE, T_TRIAL)
    res = influence_balance(V0, V, T_TRIAL, [0.1, 0.1])
    np.testing.assert_allclose(res.correction_kg_m, U_TRUE, rtol=1e-12)
    assert res.sensors == ("sensor1", "sensor2", "sensor3")
    # inconsistent data: the least-squares solution of A U = -V0 and its residual
    V0n = V0 + np.array([0.0, 0.0, 2e-6])
    Vn = V + np.array([0.0, 0.0, 2e-6])           # same offset: A unchanged
    res = influence_balance(V0n, Vn, T_TRIAL)
    U_ls = -np.linalg.lstsq(A3, V0n, rcond=None)[0]
    np.testing.assert_allclose(res.correction_kg_m, U_ls, rtol=1e-10)
    assert np.abs(res.residual_m).max() > 1e-7


def test_uncertainties_match_monte_carlo():
    V0, V = _synthetic(A2, U_TRUE, T_TRIAL)
    s0, sV = 1e-7, 2e-7                           # m, each of Re and Im
    res = influence_balance(V0, V, T_TRIAL, [0.1, 0.1], reference_std=s0, trials_std=sV)
    rng = np.random.default_rng(1)
    n = 4000
    masses, angles = [], []
    for _ in range(n):
        d0 = s0 * (rng.standard_normal(2) + 1j * rng.standard_normal(2))
        dV = sV * (rng.standard_normal((2, 2)) + 1j * rng.standard_normal((2, 2)))
        U = -np.linalg.solve(((V + dV - (V0 + d0)) / T_TRIAL[:, None]).T, V0 + d0)
        masses.append(np.abs(U) / 0.1 * 1e3)
        angles.append(np.degrees(np.angle(U / U_TRUE)))
    np.testing.assert_allclose(res.mass_std_g, np.std(masses, axis=0), rtol=0.08)
    np.testing.assert_allclose(res.angle_std_deg, np.std(angles, axis=0), rtol=0.08)
    assert np.all(res.mass_std_g > 0) and np.all(res.angle_std_deg > 0)


def test_singular_influence_matrix_is_refused():
    A = np.array([[1e-2, 2e-2], [2e-2, 4e-2]], dtype=complex)   # parallel columns
    V0 = np.array([3e-5, 1e-5j])
    V = np.array([V0 + A[:, 0] * 1e-3, V0 + A[:, 1] * 1e-3])
    with pytest.raises(ValueError, match="influence matrix A is singular"):
        influence_balance(V0, V, [1e-3, 1e-3], planes=PLANES)


def test_trial_run_without_change_is_named():
    V0, V = _synthetic(A2, U_TRUE, T_TRIAL)
    V[1] = V0
    with pytest.raises(ValueError, match=r"trial run 2 \(plane balancer2\).*did not change"):
        influence_balance(V0, V, T_TRIAL, planes=PLANES)


def test_mismatched_speeds_are_refused_naming_the_run():
    V0, V = _synthetic(A2, U_TRUE, T_TRIAL)
    w = 2 * math.pi * 40.0
    res = influence_balance(V0, V, T_TRIAL, speeds=[w, w * 1.002, w * 0.998])
    assert res.speed_rad_s == pytest.approx(w)
    with pytest.raises(ValueError, match=r"trial2\.h5.*41 rev/s differs.*40 rev/s"):
        influence_balance(V0, V, T_TRIAL, speeds=[w, w, w * 41 / 40],
                          runs=["ref.h5", "trial1.h5", "trial2.h5"])


@pytest.mark.parametrize("kwargs, match", [
    (dict(trials=np.zeros((2, 1)), reference=np.ones(1)), "sensors: 1 measurement point"),
    (dict(trial_unbalances=[1e-3, 0.0]), r"trial_unbalances\[1\].*zero"),
    (dict(radii=[0.1]), "radii: 1 value"),
    (dict(radii=[0.1, -0.1]), "radii: must be positive"),
    (dict(speeds=[1.0, 1.0]), "speeds: 2 value"),
    (dict(trials=np.zeros((3, 2))), r"trials: shape \(3, 2\), expected \(2, 2\)"),
])
def test_bad_input_is_named(kwargs, match):
    V0, V = _synthetic(A2, U_TRUE, T_TRIAL)
    args = dict(reference=V0, trials=V, trial_unbalances=T_TRIAL)
    args.update(kwargs)
    with pytest.raises(ValueError, match=match):
        influence_balance(**args)


def test_parse_trial():
    w = parse_trial("balancer2:10:90:100")
    assert w == TrialWeight("balancer2", 10.0, 90.0, 100.0)
    assert w.unbalance_kg_m == pytest.approx(1e-3j, abs=1e-18)
    for bad in ("balancer2:10:90", "b:x:0:1", "b:-1:0:100", "b:1:0:0"):
        with pytest.raises(ValueError, match="--trial"):
            parse_trial(bad)


# ------------------------------------------------------------------ the stand sample
def _check_against_model(res, scene):
    exact = model_correction(scene, PLANES)
    m_exact = np.abs(exact) / 0.1 * 1e3
    a_exact = np.degrees(np.angle(exact)) % 360
    np.testing.assert_allclose(m_exact, [20.0, 15.0], rtol=1e-12)     # the scene's comment
    np.testing.assert_allclose(a_exact, [210.0, 20.0], atol=1e-9)
    assert np.all(np.abs(res.mass_g / m_exact - 1) < 0.02)             # acceptance: 2 %
    dang = (res.angle_deg - a_exact + 180.0) % 360.0 - 180.0
    assert np.all(np.abs(dang) < 2.0)                                  # and 2 deg
    return m_exact, dang


def test_sample_recordings_give_the_exact_correction():
    files = [RECS / f"influence_{k}.h5" for k in ("ref", "trial1", "trial2")]
    for f in files:
        assert f.stat().st_size < 1_000_000
    res = influence_from_recordings(files[0], files[1:], TRIALS, SENSORS)
    m_exact, dang = _check_against_model(res, SCENES / "influence_reference.toml")
    # noise-free simulation: far better than the acceptance
    np.testing.assert_allclose(res.mass_g, m_exact, rtol=1e-4)
    assert np.all(np.abs(dang) < 0.01)
    assert res.speed_rad_s == pytest.approx(2 * math.pi * 40.0, rel=1e-9)
    assert res.planes == tuple(PLANES) and res.sensors == tuple(SENSORS)
    assert np.all(np.isfinite(res.mass_std_g)) and np.all(res.mass_std_g < 0.01)
    # the recording carries its scene: the same exact correction from it
    np.testing.assert_allclose(model_correction(files[0], PLANES),
                               model_correction(SCENES / "influence_reference.toml", PLANES))


def test_runs_from_the_sample_scenes():
    runs = [stand.run(SCENES / f"influence_{k}.toml")
            for k in ("reference", "trial1", "trial2")]
    res = influence_from_recordings(runs[0], runs[1:], [parse_trial(t) for t in TRIALS],
                                    SENSORS, radii_mm=[100.0, 100.0])
    _check_against_model(res, runs[0])
    # the trial runs hold the reference's rotor plus the trial weight alone
    for k, r in enumerate(runs[1:], start=1):
        ub = {u.plane: u for u in r.scene.structure.rotor.unbalances}
        assert ub[f"trial{k}"].s == pytest.approx(1e-3)
        np.testing.assert_allclose(model_correction(r, PLANES), model_correction(runs[0], PLANES))


def test_recordings_at_different_speeds_are_refused(tmp_path):
    text = (SCENES / "influence_trial2.toml").read_text()
    fast = tmp_path / "trial2_fast.h5"
    stand.save(stand.run(stand.load(text.replace("[1.5, 40.0]", "[1.5, 41.0]"))), fast)
    with pytest.raises(ValueError, match=r"trial run 2 .*trial2_fast\.h5.*41 rev/s differs"):
        influence_from_recordings(RECS / "influence_ref.h5",
                                  [RECS / "influence_trial1.h5", fast], TRIALS, SENSORS)


def test_missing_sensor_plane_is_named():
    with pytest.raises(ValueError, match="no plane 'probe3'"):
        influence_from_recordings(RECS / "influence_ref.h5",
                                  [RECS / "influence_trial1.h5", RECS / "influence_trial2.h5"],
                                  TRIALS, ["probe1", "probe3"])


# ------------------------------------------------------------------ CLI
def _cli(capsys, *extra):
    files = [str(RECS / f"influence_{k}.h5") for k in ("ref", "trial1", "trial2")]
    argv = ["influence", *files, "--trial", TRIALS[0], "--trial", TRIALS[1],
            "--sensors", ",".join(SENSORS), *extra]
    rc = main(argv)
    return rc, capsys.readouterr()


def test_cli_text_and_json(capsys):
    from stand.io.numbers import with_uncertainty

    rc, text = _cli(capsys)
    assert rc == 0
    rc, out = _cli(capsys, "--json")
    assert rc == 0
    doc = json.loads(out.out)
    got = {p["plane"]: p for p in doc["planes"]}
    # the text: each value with its ± by the one formatter (stand.io.numbers), never "+-"
    b1 = got["balancer1"]
    assert (f"balancer1: correction {with_uncertainty(b1['mass_g'], b1['mass_std_g'], 'g')} at "
            f"{with_uncertainty(b1['angle_deg'], b1['angle_std_deg'], '°', resolution=False)}"
            in text.out), text.out
    assert "+-" not in text.out
    assert got["balancer1"]["mass_g"] == pytest.approx(20.0, rel=1e-4)
    assert got["balancer2"]["angle_deg"] == pytest.approx(20.0, abs=0.01)
    assert doc["speed_rev_s"] == pytest.approx(40.0)


def test_cli_bad_input_exits_2(capsys):
    rc = main(["influence", str(RECS / "influence_ref.h5"), str(RECS / "influence_trial1.h5"),
               str(RECS / "influence_ref.h5"), "--trial", TRIALS[0], "--trial", TRIALS[1],
               "--sensors", "probe1,probe2"])
    err = capsys.readouterr().err
    assert rc == 2 and "trial run 2" in err and "did not change" in err
