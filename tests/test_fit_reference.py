"""``stand fit`` against an independent reference (issue 39 acceptance, fast form).

The records are written by tests/oracles/two_ball_stand.py -- its own equations of the rotor
and the balls, solved by scipy, its own keyphasor -- never by the stand's simulator: a run-up
of the universal stand through its critical speed, a TTL keyphasor and 2 um probe noise at
1 kHz.  The template is the lab's first guess: stiffness +12 %, damping x1.8, eccentricity
x0.7, unbalance angle +35 deg, ball drag x2.5.  The fit must find every value within 2 %
(the angle within 2 deg), each within 3 of its own std (the 24-seed calibration --
RMS(z), coverage -- is benchmarks/bench_fit.py, in benchmarks/README.md) and each to better
than 0.1 % (the record still determines it).  With rolling friction (the balls stop short of
balance) the friction coefficient within 10 %, with its ±.
"""
from __future__ import annotations

import numpy as np
import pytest

import stand

from oracles.two_ball_stand import Stand, record, template_scene, write_record

FREE = "supports.stiffness,supports.damping,rotor.eccentricity,rotor.unbalance_angle,balancer.drag"
#: a shorter run-up than the bench's 25 s (0 -> 12 rev/s in 4 s, held to 7 s): the test's time.
#: f0 = 3.0 Hz is crossed at 1 s, the balls settle in the 3 s held at 12 rev/s.  Against the
#: 10-s record (6-s ramp) the values' std grow by ~1.5 (the information ~ the samples through and
#: after the resonance: 7000 of 10000, a faster passage): seed 1 gives relative std of 2e-6
#: (stiffness) to 2e-5 (damping, drag), the angle's 0.003 deg, every |z| < 1.9 -- the 2 % bounds
#: stay > 1000 std away, the std bound below (1e-3 relative, 0.2 deg) 50 std
SHORT = dict(programme=[[0.0, 0.0], [4.0, 12.0]])
DURATION = 7.0
#: the reference stand's record (test_fit_recovers_the_reference_stand) held 1.5 s at 12 rev/s,
#: not 3 s: the fit's cost goes with the record's duration (its model runs), not its samples.
#: The balls' drag shows while they settle, most of it in the first second at 12 rev/s: over
#: 5.5 s (seeds 1, 2) the relative std are 2.2e-6 (stiffness) to 2.4e-5 (damping), drag's
#: 1.2e-5 (1.1e-5 over 7 s), the angle's 0.004 deg, every |z| < 1.1 -- the std bound STD_MAX
#: still 40 std above each std: the shorter record still determines every value
REF_DURATION = 5.5
#: the largest std a value may have, relative (the angle: deg): the record determines it
STD_MAX = 1e-3


def _check(fit, truth: Stand, z_max=3.0, rel=0.02):
    t = {"supports.stiffness": truth.stiffness, "supports.damping": truth.damping,
         "rotor.eccentricity": truth.eccentricity, "rotor.unbalance_angle": truth.unbalance_angle,
         "balancer.drag": truth.drag, "balancer.friction": truth.friction}
    zs = {}
    for p, d in fit["parameters"].items():
        assert d["identifiable"], (p, d)
        if d["unit"] == "deg":
            err = (d["value"] - t[p] + 180.0) % 360.0 - 180.0
            assert abs(err) < 2.0, (p, d["value"], t[p])
        else:
            err = d["value"] - t[p]
            assert abs(err) < rel * t[p], (p, d["value"], t[p])
        zs[p] = err / d["std"]
        assert d["std"] < (200.0 * STD_MAX if d["unit"] == "deg" else STD_MAX * t[p]), (p, d)
    assert max(abs(z) for z in zs.values()) < z_max, zs
    return zs


@pytest.mark.parametrize("seed", [1, pytest.param(2, marks=pytest.mark.full)])  # 2: `-m full`
def test_fit_recovers_the_reference_stand(tmp_path, seed):
    truth = Stand(**SHORT)
    rec = record(truth, duration=REF_DURATION, seed=seed)
    csv, m = write_record(rec, truth, tmp_path / f"ref{seed}.csv")
    tmpl = template_scene(truth, tmp_path / "template.toml", duration=REF_DURATION)
    fit = stand.fit(tmpl, csv, FREE, recording_map=m, workers=1)
    _check(fit, truth)
    assert fit["fit"]["chi2_dof"] < 3.0
    # theory against experiment: the critical speed the record shows, the model predicts
    rows = {r["key"]: r for r in fit["comparison"]}
    assert "critical_speed" in rows and abs(rows["critical_speed"]["difference_sigma"]) < 5


@pytest.mark.full
def test_fit_of_the_sample_as_the_readme_says(tmp_path):
    """data_samples/fit: the reference's 16-s run-up (seed 7) and the lab's template; the
    README's command and numbers.  ``-m full`` (a 16-s record, ~30 s of fitting): the same
    oracle, free values and checks run by default on the shorter record of
    test_fit_recovers_the_reference_stand[1]."""
    import json
    from pathlib import Path

    root = Path(__file__).resolve().parents[1] / "data_samples" / "fit"
    truth = Stand(**{k: v for k, v in json.loads((root / "two_ball_runup.truth.json").read_text())
                     .items()})
    fit = stand.fit(root / "two_ball_template.toml", root / "two_ball_runup.csv", FREE,
                    recording_map=root / "two_ball_runup.map.toml", workers=1)
    _check(fit, truth)
    assert fit["fit"]["chi2_dof"] < 1.5
    out = fit.write_scene(tmp_path / "fitted.toml")
    assert stand.load(out).balancer.drag[0] == pytest.approx(truth.drag, rel=1e-3)


@pytest.mark.parametrize("rotor_free", [False, pytest.param(True, marks=pytest.mark.full)],
                         ids=["weights", "weights_and_rotor"])
def test_fit_finds_the_balls_rolling_friction(tmp_path, rotor_free):
    """Rolling resistance 3e-3: the balls stop short of balance (a residual whirl of order
    mu l); the template's friction 1.5x too large, drag x2.5.  By default the weights' two
    values are free (the rotor's as recorded: ~8 s of fitting); under ``-m full`` also the
    rotor's eccentricity (x0.7) and unbalance angle (+35 deg)."""
    truth = Stand(friction=3e-3, **SHORT)
    # 500 samples/s (the generic kernel's runs and the corner scans cost per sample): seed 3
    # gives the friction's std 1e-6 (3e-4 relative, x3.5 the 10-s 1-kHz record's), |z| < 1.5
    rec = record(truth, duration=DURATION, fs=500.0, seed=3)
    last = rec["t"] > DURATION - 1.0
    # short of balance: 5.8e-4 m over the last second; without friction the 7-s record's balls
    # are still settling there (7e-5 m), hence the bound between them
    assert np.mean(np.hypot(rec["x_true"], rec["y_true"])[last]) > 2e-4
    csv, m = write_record(rec, truth, tmp_path / "fric.csv")
    perturb = {"friction": 1.5, "drag": 2.5}
    free = "balancer.drag,balancer.friction"
    if rotor_free:
        perturb.update(eccentricity=0.7, unbalance_angle=35.0)
        free = "rotor.eccentricity,rotor.unbalance_angle," + free
    tmpl = template_scene(truth, tmp_path / "template.toml", duration=DURATION, perturb=perturb)
    fit = stand.fit(tmpl, csv, free, recording_map=m, workers=1)
    d = fit["parameters"]["balancer.friction"]
    assert d["identifiable"] and np.isfinite(d["std"]) and d["std"] > 0
    assert abs(d["value"] - truth.friction) < 0.1 * truth.friction, d
    # its ± is the covariance's: the stick-slip at the run-up's end leaves a misfit the model
    # of the angle's error does not absorb (chi2/dof above 1 there), a bias of a few std
    assert abs(d["value"] - truth.friction) < 6 * d["std"], (d, fit["fit"]["chi2_dof"])
