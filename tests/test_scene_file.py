"""Tests for stand.scene.parse: loading, unit conversion, errors."""
import math
import re

import numpy as np
import pytest

from stand.scene.dimensionless import dimensionless
from stand.scene.model import RunSettings, SceneError, SpeedDrive, TorqueDrive
from stand.scene.parse import load_scene, parse_scene, scene_from_dimensionless

from _helpers import toml_text

VALID = """\
[scene]
name = "two balls"
description = "test scene"

[rotor]
mass = 10.0
eccentricity = 1e-4
unbalance_angle = 90
inertia = 0.05

[supports]
stiffness_x = 4.0e5
stiffness_y = 5.0e5
damping = 20.0

[balancer]
type = "balls"
count = 2
mass = [0.045, 0.045]
radius = 0.08
drag = 0.01
initial_angles = [0, 180]
initial_speeds = 0.5

[drive]
type = "speed"
programme = [[0.0, 0.0], [2.0, 25.0]]
coast_down = {start = 5.0, time_constant = 3.0}

[run]
duration = 10.0
sample_rate = 1000.0

[initial]
x = 1e-5
"""


def edit(text, old, new):
    assert old in text, old
    return text.replace(old, new, 1)


def test_load_valid_file(tmp_path):
    path = tmp_path / "my_rig.toml"
    path.write_text(VALID.replace('name = "two balls"\n', ""))
    scene = load_scene(path)
    assert scene.name == "my_rig"
    assert scene.text == path.read_text()
    assert scene.rotor.mass == 10.0 and scene.rotor.inertia == 0.05
    assert scene.supports.stiffness_y == 5.0e5
    assert scene.supports.damping_x == scene.supports.damping_y == 20.0
    b = scene.balancer
    assert b.type == "balls" and b.count == 2
    np.testing.assert_allclose(b.radius, [0.08, 0.08])
    np.testing.assert_allclose(b.inertia, 0.045 * 0.08 ** 2)
    assert isinstance(scene.drive, SpeedDrive)
    assert scene.drive.coast_down_start == 5.0 and scene.drive.coast_down_time_constant == 3.0
    assert scene.run.rtol == 1e-8 and scene.run.method == "auto"
    assert scene.initial.x == 1e-5 and scene.initial.vy == 0.0


def test_load_string_uses_scene_name():
    scene = load_scene(VALID)
    assert scene.name == "two balls"
    assert scene.text == VALID


def test_unit_conversions():
    scene = load_scene(VALID)
    assert scene.rotor.unbalance_angle == pytest.approx(math.pi / 2)
    np.testing.assert_allclose(scene.balancer.initial_angles, [0.0, math.pi])
    np.testing.assert_allclose(scene.balancer.initial_speeds, 2 * math.pi * 0.5)
    np.testing.assert_allclose(scene.drive.programme, [[0.0, 0.0], [2.0, 50 * math.pi]])


def test_default_angles_evenly_spaced():
    scene = load_scene(edit(VALID, "initial_angles = [0, 180]\n", "count = 3\n")
                       .replace("count = 2\n", "").replace("[0.045, 0.045]", "0.045"))
    np.testing.assert_allclose(scene.balancer.initial_angles, [0, 2 * math.pi / 3, 4 * math.pi / 3])


def test_torque_drive_and_pendulums():
    text = edit(VALID, 'type = "balls"', 'type = "pendulums"\ninertia = [3e-4, 2.88e-4]')
    text = edit(text, 'type = "speed"\nprogramme = [[0.0, 0.0], [2.0, 25.0]]\n'
                      'coast_down = {start = 5.0, time_constant = 3.0}',
                'type = "torque"\nmodel = "angle_feedback"\nc1 = 2.0\nc2 = 5.0\n'
                'target_speed = 30\ninitial_speed = 1.0\nrotor_drag = 0.001')
    scene = load_scene(text)
    assert isinstance(scene.drive, TorqueDrive)
    assert scene.drive.target_speed == pytest.approx(60 * math.pi)
    assert scene.drive.initial_speed == pytest.approx(2 * math.pi)
    np.testing.assert_allclose(scene.balancer.inertia, [3e-4, 2.88e-4])


def test_programme_dimensionless():
    text = edit(VALID, "programme = [[0.0, 0.0], [2.0, 25.0]]",
                "programme_dimensionless = [[0.0, 0.0], [10.0, 2.0]]")
    scene = load_scene(text)
    w1 = math.sqrt(4.0e5 / 10.09)
    np.testing.assert_allclose(scene.drive.programme, [[0.0, 0.0], [10.0 / w1, 2.0 * w1]])


def test_dimensionless_round_trip():
    drive = SpeedDrive(programme=np.array([[0.0, 3.0]]))
    run = RunSettings(duration=1.0, sample_rate=100.0)
    scene = scene_from_dimensionless(3, 0.02, 0.1, 0.2, 0.7, drive=drive, run=run,
                                     R_omega2=1.3, natural_frequency=12.5,
                                     total_mass=7.0, track_radius=0.09)
    d = dimensionless(scene)
    assert d.n == 3
    for got, want in ((d.Rt, 0.02), (d.H_x, 0.2), (d.H_y, 0.2), (d.e0, 0.7),
                      (d.R_omega2, 1.3), (d.R_m, 0.04), (d.omega_1, 2 * math.pi * 12.5)):
        assert got == pytest.approx(want, rel=1e-12, abs=1e-12)
    np.testing.assert_allclose(d.h, 0.1, rtol=1e-12)
    np.testing.assert_allclose(d.j, 1.0, rtol=1e-12)
    assert scene.total_mass == pytest.approx(7.0, rel=1e-12)


def test_dimensionless_table():
    scene = load_scene(toml_text(
        dimensionless=dict(n=2, Rt=0.01, h=0.05, H=0.1, e0=0.5, unbalance_angle=90,
                           initial_angles=[0, 90]),
        drive=dict(type="speed", programme_dimensionless=[[0, 0], [100, 3]]),
        run=dict(duration=50, sample_rate=20)))
    d = dimensionless(scene)
    assert (d.n, d.Rt, d.h[0], d.H, d.e0) == pytest.approx((2, 0.01, 0.05, 0.1, 0.5), rel=1e-12)
    assert d.omega_1 == pytest.approx(1.0)
    assert scene.rotor.unbalance_angle == pytest.approx(math.pi / 2)
    np.testing.assert_allclose(scene.balancer.initial_angles, [0, math.pi / 2])
    np.testing.assert_allclose(scene.drive.programme, [[0, 0], [100, 3]])


def test_parse_scene_dict():
    try:
        import tomllib
    except ModuleNotFoundError:  # Python 3.10
        import tomli as tomllib
    scene = parse_scene(tomllib.loads(VALID), text="x")
    assert scene.text == "x" and scene.balancer.count == 2


# ------------------------------------------------------------------ errors
def check(text, *fragments):
    """The scene must fail with a SceneError containing all fragments."""
    with pytest.raises(SceneError, match=re.escape(fragments[0])) as info:
        load_scene(text)
    for frag in fragments[1:]:
        assert frag in str(info.value), str(info.value)
    return str(info.value)


def test_unknown_key_suggests():
    msg = check(edit(VALID, "radius = 0.08", "radus = 0.08"), "balancer.radus")
    assert "'radius'" in msg


def test_unknown_table_suggests():
    msg = check(VALID + "\n[suports]\nx = 1\n", "[suports]")
    assert "'supports'" in msg


def test_missing_key():
    check(edit(VALID, "duration = 10.0\n", ""), "run.duration", "missing")


def test_missing_table():
    check(VALID.split("[run]")[0], "[run]", "missing")


def test_wrong_type():
    check(edit(VALID, "mass = 10.0", 'mass = "heavy"'), "rotor.mass", '"heavy"', "kg")


def test_bool_is_not_a_number():
    check(edit(VALID, "eccentricity = 1e-4", "eccentricity = true"),
          "rotor.eccentricity = true", "number")


def test_negative_mass():
    check(edit(VALID, "[0.045, 0.045]", "[0.045, -0.045]"),
          "balancer.mass[1] = -0.045: must be > 0 (kg)")


def test_zero_stiffness():
    check(edit(VALID, "stiffness_x = 4.0e5", "stiffness_x = 0"), "supports.stiffness_x = 0", "N/m")


def test_nan():
    check(edit(VALID, "damping = 20.0", "damping = nan"), "supports.damping = nan", "finite")


def test_inf():
    check(edit(VALID, "duration = 10.0", "duration = inf"), "run.duration = inf", "finite")


def test_list_wrong_length():
    check(edit(VALID, "initial_angles = [0, 180]", "initial_angles = [0, 90, 180]"),
          "balancer.initial_angles", "[0, 90, 180]", "expected 2")


def test_dimensionless_mixed_with_rotor():
    check(VALID + "\n[dimensionless]\nn = 2\n", "[dimensionless]", "[rotor]")


def test_pendulum_inertia_below_point_mass():
    text = edit(VALID, 'type = "balls"', 'type = "pendulums"\ninertia = [3e-4, 1e-4]')
    check(text, "balancer.inertia[1] = 0.0001", "m l^2")


def test_ball_inertia_not_allowed():
    check(edit(VALID, 'type = "balls"', 'type = "balls"\ninertia = 1e-3'),
          "balancer.inertia", "balls")


def test_torque_drive_needs_rotor_inertia():
    text = edit(VALID, "inertia = 0.05\n", "")
    text = edit(text, 'type = "speed"\nprogramme = [[0.0, 0.0], [2.0, 25.0]]\n'
                      'coast_down = {start = 5.0, time_constant = 3.0}',
                'type = "torque"\nmodel = "constant"\ntorque = 0.5')
    check(text, "rotor.inertia", "torque")


def test_irrelevant_drive_key():
    text = edit(VALID, 'type = "speed"\nprogramme = [[0.0, 0.0], [2.0, 25.0]]\n'
                       'coast_down = {start = 5.0, time_constant = 3.0}',
                'type = "torque"\nmodel = "constant"\ntorque = 0.5\nc2 = 5.0')
    check(text, "drive.c2 = 5.0", '"constant"')


def test_too_many_samples():
    check(edit(VALID, "sample_rate = 1000.0", "sample_rate = 1e7"), "run.sample_rate", "memory")


def test_both_stiffness_forms():
    check(edit(VALID, "damping = 20.0", "damping = 20.0\nstiffness = 1e5"),
          "supports.stiffness", "stiffness_x")


def test_non_increasing_programme():
    check(edit(VALID, "[2.0, 25.0]", "[0.0, 25.0]"), "drive.programme[1][0] = 0.0", "increasing")


def test_toml_syntax_error(tmp_path):
    path = tmp_path / "broken.toml"
    path.write_text("[rotor\nmass = 1\n")
    check(path, str(path), "TOML syntax error")


def test_missing_file(tmp_path):
    check(tmp_path / "nope.toml", "not found", "nope.toml")


def test_error_prefixed_with_file_name(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text(edit(VALID, "mass = 10.0", "mass = -1"))
    check(path, str(path), "rotor.mass = -1: must be > 0 (kg)")


def test_scene_from_dimensionless_validates():
    drive = TorqueDrive(model="constant", torque=1.0)
    run = RunSettings(duration=1.0, sample_rate=10.0)
    with pytest.raises(SceneError, match=r"dimensionless\.Rt = 0\.6"):
        scene_from_dimensionless(2, 0.6, 0.1, 0.1, 0.5, drive=drive, run=run, rotor_inertia=1.0)
    with pytest.raises(SceneError, match=r"dimensionless\.rotor_inertia"):
        scene_from_dimensionless(2, 0.1, 0.1, 0.1, 0.5, drive=drive, run=run)
