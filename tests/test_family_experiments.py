"""Experiment programmes of tables 4.2-4.4 and the photo-gate test on rotor-family scenes."""
import math
from pathlib import Path

import numpy as np
import pytest

import stand
from stand.scene import experiments as ex
from stand.cli.main import main
from stand.integrate.coupled import with_locked_weights

SCENES = Path(__file__).resolve().parents[1] / "data_samples" / "scenes"


def test_natural_frequency_test_of_the_two_mass_rotor(tmp_path, capsys):
    """Released from a deflection at rest, the two-mass rotor rings at its lowest natural
    frequency with the weights locked (8.964 Hz): stand analyze identifies it to 0.1 %."""
    scene = SCENES / "family_two_mass.toml"
    out = tmp_path / "nf.h5"
    assert main(["experiment", str(scene), "natural-frequency", "--deflection", "1e-3",
                 "-o", str(out)]) == 0
    sc = stand.load(scene)
    wn = with_locked_weights(sc.linear_rotor(), sc.weights).natural_frequencies(0.0)
    res = stand.analyze(out)
    assert res["natural_frequency_hz"] == pytest.approx(wn[0] / (2 * math.pi), rel=1e-3)
    rec = stand.read(out)
    assert rec.x[0] == pytest.approx(1e-3, rel=1e-12)         # released from the deflection
    assert np.max(np.abs(rec.rotor_speed)) == 0.0


@pytest.mark.parametrize("name,opts", [
    ("run-up", dict(speed=20.0, rate=2.0, hold=5.0)),
    ("run-down", dict(speed=15.0, time=10.0, exponential=True)),
    ("constant", dict(band="super"))])
def test_speed_programmes_on_a_family_rotor(name, opts):
    sc = ex.programme(stand.load(SCENES / "family_two_mass.toml"), name, **opts)
    run = stand.run(sc)
    assert run.success
    if name == "run-up":
        assert run.rotor_speed[-1] == pytest.approx(20.0 * 2 * math.pi, rel=1e-12)
    if name == "run-down":     # exponential coast-down as a programme: omega(t) within 1e-4
        t = run.t
        w = np.where(t < 10.0, 15.0, 15.0 * np.exp(-5.0 * (t - 10.0) / 10.0)) * 2 * math.pi
        assert np.max(np.abs(run.rotor_speed - w)) < 1e-4 * 15.0 * 2 * math.pi
    if name == "constant":     # band "super": 1.5 f0 of the locked structure
        f0 = with_locked_weights(sc.linear_rotor(), sc.weights).natural_frequencies(0.0)[0]
        assert run.rotor_speed[-1] == pytest.approx(1.5 * f0, rel=1e-12)


@pytest.mark.parametrize("name,opts", [("unbalance", "--eccentricity 1e-3"),
                                       ("pressure", "--end 5 --side-force 10")])
def test_perturbation_programmes_say_not_applicable(name, opts, capsys, tmp_path):
    out = tmp_path / "x.h5"
    argv = ["experiment", str(SCENES / "family_two_mass.toml"), name, "--speed", "10", "--at", "2",
            *opts.split(), "-o", str(out)]
    assert main(argv) == 0
    assert "not applicable" in capsys.readouterr().out
    assert not out.exists()


def test_impact_on_the_generic_kernel_matches_the_planar_kernel():
    """A blow to the housing (table 4.6) on the planar rotor with balls: the generic kernel
    (the blow as a jump of its scaled state) and the planar kernel agree to 1e-8."""
    import dataclasses

    from stand.integrate.simulate import simulate

    base = stand.load(SCENES / "ball_runup.toml")
    sc = ex.programme(base, "impact", speed=10.0, at=3.0, velocity=0.02, angle_deg=30.0)
    sc = dataclasses.replace(sc, run=dataclasses.replace(sc.run, duration=8.0))
    a = simulate(sc, rtol=1e-12, atol=1e-14)
    b = simulate(sc, rtol=1e-12, atol=1e-14, kernel="generic")
    assert a.success and b.success
    za, zb = a.x + 1j * a.y, b.x + 1j * b.y
    assert np.max(np.abs(za - zb)) / np.max(np.abs(za)) < 1e-8
    # the blow shows: v = 0.02 m/s over ~1/omega moves the shaft by ~1 mm
    c = simulate(dataclasses.replace(sc, perturbations=()), rtol=1e-12, atol=1e-14)
    zc = c.x + 1j * c.y
    i = np.searchsorted(a.t, 3.0)
    assert np.max(np.abs(za[:i] - zc[:i])) < 1e-12
    assert np.max(np.abs(za[i:] - zc[i:])) > 1e-4


def test_impact_experiment_on_a_family_rotor(tmp_path):
    out = tmp_path / "imp.h5"
    assert main(["experiment", str(SCENES / "family_two_mass.toml"), "impact", "--speed", "14",
                 "--at", "20", "--velocity", "0.01", "-o", str(out)]) == 0
    r = stand.read(out)
    w = np.hypot(r.x, r.y)
    i = np.searchsorted(r.t, 20.0)
    assert w[i + 1:i + 400].max() > 20 * w[i - 5]          # disturbed by the blow
    assert w[-1] < 1e-3 * w[i + 1:i + 400].max()           # and rebalanced by the balls
