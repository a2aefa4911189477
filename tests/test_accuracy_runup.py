"""stand accuracy on the paper-001 run-up: errors against the closed form
(Fresnel integrals) for the compiled DOP853 and fixed-step RK4 (shortened:
40 -> 1400 rad/s at 20 rad/s^2, z up to 1.4, ~8000 revolutions)."""
import dataclasses
import math

import numpy as np
import pytest

from stand.integrate.accuracy import accuracy, runup_params
from stand.cli.main import main
from stand.scene.model import SpeedDrive
from stand.scene.parse import load_scene

SCENE = "data_samples/scenes/paper001_runup.toml"


def _short():
    sc = load_scene(SCENE)
    T = (1400.0 - 40.0) / 20.0
    drive = SpeedDrive(np.array([[0.0, 40.0], [T, 1400.0]]))
    return dataclasses.replace(sc, drive=drive, run=dataclasses.replace(sc.run, duration=T,
                                                                        sample_rate=250.0))


def test_sample_is_a_closed_form_runup():
    p, t_end = runup_params(load_scene(SCENE))
    assert p.Omega_0 == pytest.approx(1000.0) and p.epsilon == pytest.approx(10.0)
    assert p.n == 0.0 and t_end == pytest.approx(248.0)
    # a different initial state: not the stationary whirl, no closed form
    sc = load_scene(SCENE)
    assert runup_params(dataclasses.replace(sc, initial=dataclasses.replace(sc.initial, vy=0.0))) is None


def test_dop853_keeps_the_free_whirl_rk4_damps_it():
    rep = accuracy(_short(), rtols=(1e-10,), methods=["DOP853", "RK4"], rk4_steps=(2 * math.pi / 1400 / 12,))
    assert "closed form run-up" in rep.reference
    dop, rk4 = rep.rows
    # the free whirl after the passage is ~ e Omega sqrt(pi / (4 eps)) = 280 e: scale
    assert rep.scale_m > 200 * 1e-4
    assert dop.success and dop.relative_error < 1e-6 and abs(dop.free_whirl_drift) < 1e-6
    # RK4 (12 steps per revolution): numerical damping, |c+| decreases
    assert rk4.free_whirl_drift < -10 * abs(dop.free_whirl_drift) and rk4.free_whirl_drift < 0


def test_cli_accuracy_runs(capsys, tmp_path):
    text = open(SCENE).read().replace("[248.0, 795.7747154594767]", "[30.0, 101.85916357881302]") \
        .replace("duration = 248.0", "duration = 30.0")
    p = tmp_path / "short.toml"
    p.write_text(text)
    assert main(["accuracy", str(p), "--methods", "DOP853,RK4", "--rtols", "1e-8",
                 "--rk4-steps", "1e-3"]) == 0
    out = capsys.readouterr().out
    assert "Fresnel" in out and "RK4" in out
    assert main(["accuracy", str(p), "--methods", "Euler"]) == 2


def test_header_describes_the_run_compared(capsys):
    """`stand accuracy paper001_runup.toml --duration 20`: the header says the errors are over
    t = 0 to 20 s and its max |r| is that span's -- the stationary whirl e z^2/(1 - z^2) at
    z = 440/1000 (the run ends at 40 + 20 * 20 rad/s, below the critical speed), not the full
    run's passage (~280 e) -- and the closed form's own 248 s as its validity."""
    import json

    e = 1.0e-4
    z = (40.0 + 20.0 * 20.0) / 1000.0
    whirl = e * z * z / (1 - z * z)       # started on the stationary whirl: transients ~ eps/Omega0^2
    assert main(["accuracy", SCENE, "--duration", "20", "--methods", "DOP853", "--rtols", "1e-8"]) == 0
    head = capsys.readouterr().out.splitlines()[1]
    assert "valid to t = 248 s" in head and "up to t = 248 s" not in head
    assert "compared over t = 0 to 20 s: max |r| = " in head
    assert float(head.rsplit("= ", 1)[1].split()[0]) == pytest.approx(whirl, rel=1e-3)
    assert main(["accuracy", SCENE, "--duration", "20", "--methods", "DOP853", "--rtols", "1e-8",
                 "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["compared_to_s"] == pytest.approx(20.0) and doc["scale_m"] == pytest.approx(whirl, rel=1e-3)
