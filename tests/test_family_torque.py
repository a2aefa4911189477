"""Torque drives on the generic kernel (issue 17 part 4): the rotor angle and speed are
states of any LinearRotor with weights (stand.model.rotors.coupled_kernel)."""
from __future__ import annotations

import dataclasses
import math
import re
from pathlib import Path

import numpy as np
import pytest

import stand
from stand.scene.model import SceneError, TorqueDrive
from stand.integrate.simulate import simulate

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10
    import tomli as tomllib

SCENES = Path(__file__).resolve().parents[1] / "data_samples" / "scenes"
W15 = 2 * math.pi * 15.0
DRIVES = {
    "constant": TorqueDrive(model="constant", torque=0.4, rotor_drag=0.004, initial_speed=5.0),
    "speed_feedback": TorqueDrive(model="speed_feedback", c1=0.05, target_speed=W15,
                                  rotor_drag=0.001),
    "angle_feedback": TorqueDrive(model="angle_feedback", c1=0.05, c2=0.5, target_speed=W15,
                                  rotor_drag=0.001),
}


def _planar_torque_scene(drive):
    base = stand.load(str(SCENES / "ball_runup.toml"))
    run = dataclasses.replace(base.run, duration=15.0, sample_rate=50.0, rtol=1e-12, atol=1e-14)
    return dataclasses.replace(base, rotor=dataclasses.replace(base.rotor, inertia=0.02),
                               drive=drive, run=run)


@pytest.mark.parametrize("model", sorted(DRIVES))
def test_planar_torque_scene_on_the_generic_kernel_matches_the_planar_kernel(model):
    """Oracle: the planar kernel's free rotor ((5.4)-(5.10), digest ch5) against the generic
    kernel's augmented (n+1) system, two balls, >= 100 revolutions, to 1e-8 relative."""
    scene = _planar_torque_scene(DRIVES[model])
    a = simulate(scene)
    b = simulate(scene, kernel="generic")
    assert a.success and b.success
    assert a.rotor_angle[-1] / (2 * math.pi) >= 100
    scale = np.max(np.hypot(a.x, a.y))
    assert np.max(np.hypot(a.x - b.x, a.y - b.y)) / scale <= 1e-8
    assert np.max(np.abs(a.rotor_angle - b.rotor_angle)) / a.rotor_angle[-1] <= 1e-8
    assert np.max(np.abs(a.rotor_speed - b.rotor_speed)) / np.max(a.rotor_speed) <= 1e-8
    np.testing.assert_allclose(a.weight_angle, b.weight_angle, atol=1e-8)


def _two_mass_torque_text(drive: str, rtol=1e-10, atol=1e-12, duration=8.0) -> str:
    text = (SCENES / "family_two_mass.toml").read_text()
    text = text[:text.index("[instruments")]
    text = re.sub(r"\[drive\].*?\n\n", "[drive]\n" + drive + "\n\n", text, flags=re.S)
    return text.replace("duration = 40.0", f"duration = {duration}\nrtol = {rtol}\natol = {atol}")


def _family(text):
    from stand.scene.parse import parse

    return parse(tomllib.loads(text), text, "family_two_mass_torque")


SPEED_FEEDBACK = ('type = "torque"\nmodel = "speed_feedback"\nc1 = 0.2\ntarget_speed = 42.0\n'
                  'rotor_drag = 1e-4\ninertia = 0.02')


def test_two_mass_torque_runup_passes_its_criticals():
    """Acceptance: the two-mass rotor (2.5.2) driven by a speed-feedback torque to 42 rev/s
    runs through the criticals of its criterion and ends above them; the run agrees with a
    tight reference (rtol 1e-12) to 1e-6."""
    from stand.model.rotors.coupled_kernel import with_locked_weights
    from stand.model.rotors.structure import working_ranges

    sc = _family(_two_mass_torque_text(SPEED_FEEDBACK))
    assert sc.drive.kind == "torque" and sc.drive.inertia == 0.02
    crit, _ = working_ranges(with_locked_weights(sc.linear_rotor(), sc.weights), "balancer",
                             1.0, 2 * math.pi * 60, 4000)
    assert len(crit) == 3 and crit[-1] < 2 * math.pi * 36
    a = simulate(sc)
    assert a.success
    assert a.rotor_speed[-1] > 1.1 * crit[-1]
    # it passes each critical once and for all (the unbalance's torque ripple aside)
    for w in crit:
        k = int(np.argmax(a.rotor_speed > w))
        assert 0 < k < a.t.size // 2 and np.all(a.rotor_speed[k:] > 0.9 * w)
    # the Run's rotor angle and speed are the states (not a programme)
    i = a.state.shape[1] - 2
    np.testing.assert_array_equal(a.rotor_angle, a.state[:, i])
    np.testing.assert_allclose(a.rotor_speed, a.state[:, i + 1] * sc.linear_rotor()
                               .natural_frequencies(0.0)[0], rtol=1e-14)
    ref = simulate(dataclasses.replace(sc, run=dataclasses.replace(sc.run, rtol=1e-12,
                                                                   atol=1e-14)))
    for name in sc.linear_rotor().planes:
        p, q = a.planes[name], ref.planes[name]
        assert np.max(np.hypot(*(p - q).T)) / np.max(np.hypot(*q.T)) <= 1e-6
    assert np.max(np.abs(a.rotor_speed - ref.rotor_speed)) / np.max(ref.rotor_speed) <= 1e-6
    assert np.max(np.abs(a.rotor_angle - ref.rotor_angle)) / ref.rotor_angle[-1] <= 1e-6


def test_two_mass_constant_torque_balanced_rotor_spins_up_as_a_rigid_body():
    """No unbalance, no weights: J_p Omega' = M - H0 Omega exactly (the translations stay 0)."""
    text = _two_mass_torque_text('type = "torque"\nmodel = "constant"\ntorque = 0.3\n'
                                 "rotor_drag = 0.01\ninertia = 0.05", duration=3.0)
    text = text.replace("unbalance = 2.0e-3", "unbalance = 0.0")
    text = text[:text.index("[[weights]]")] + text[text.index("[drive]"):]
    a = simulate(_family(text))
    w = 0.3 / 0.01 * (1 - np.exp(-0.01 * a.t / 0.05))
    np.testing.assert_allclose(a.rotor_speed, w, rtol=1e-8, atol=1e-9)


def test_torque_drive_with_a_body_weight_runs():
    """Body weights (here a two-axis pendulum) take a torque drive too; their turn drag
    acts back on the rotor (the run is finite and spins up)."""
    text = _two_mass_torque_text(SPEED_FEEDBACK, rtol=1e-8, atol=1e-10, duration=1.0)
    text = text.replace('type = "balls"\ncount = 2\nmass = 0.01\nradius = 0.2\ndrag = 0.5\n'
                        'initial_angles = [60.0, 250.0]\n',
                        'type = "two_axis_pendulum"\nmass = 0.02\narm = 0.05\n'
                        'inertia_tilt = 1e-4\ninertia_axial = 6e-5\ntilt_drag = 1e-4\n'
                        'turn_drag = 1e-3\ninitial_tilt = 0.1\n')
    sc = _family(text)
    assert sc.bodies
    a = simulate(sc)
    assert a.success and a.rotor_speed[-1] > 2 * math.pi * 10


def test_family_torque_drive_keys():
    with pytest.raises(SceneError, match="inertia"):
        _family(_two_mass_torque_text('type = "torque"\nmodel = "constant"\ntorque = 0.3'))
    with pytest.raises(SceneError, match="torque"):
        _family(_two_mass_torque_text('type = "speed"\nprogramme = [[0.0, 0.0], [3.0, 14.0]]\n'
                                      "inertia = 0.02"))
    with pytest.raises(SceneError, match="c1"):
        _family(_two_mass_torque_text('type = "torque"\nmodel = "constant"\ntorque = 0.3\n'
                                      "c1 = 0.1\ninertia = 0.02"))


def test_commands_on_a_torque_driven_family_scene(tmp_path, capsys):
    """theory, run (with a stroboscope), analyze and report take a torque-driven [structure]
    scene (the drive has no programme: its operating speed is the target speed)."""
    from stand.cli.main import main

    text = _two_mass_torque_text(SPEED_FEEDBACK, duration=3.0) + (
        "\n[instruments.stroboscope]\nflash_angle = 90.0\nslot_width = 0.003\n"
        "slot_radius = 0.12\nframe_every = 40\nwidth = 96\nheight = 96\npixel_pitch = 5e-3\n")
    p = tmp_path / "t.toml"
    p.write_text(text)
    assert main(["theory", str(p)]) == 0
    assert "two_mass" in capsys.readouterr().out
    rec = tmp_path / "t.h5"
    assert main(["run", str(p), "-o", str(rec), "--no-progress"]) == 0
    assert stand.read(rec).shape("instruments/stroboscope/frames")[0] >= 1
    assert main(["analyze", str(rec)]) == 0
    assert main(["report", str(rec), "-o", str(tmp_path / "r")]) == 0
