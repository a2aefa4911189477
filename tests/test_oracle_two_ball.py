"""The independent two-ball recording (tests/oracles/two_ball_record.py) against the stand.

The oracle is written from the physics digest (ch5 (5.4), (5.7) corrected), in SI, over
the absolute coordinates (x, y, psi_1..psi_n) with the full mass matrix solved at every
call and scipy's DOP853 segment by segment between the programme's nodes; the stand's
planar kernel is dimensionless, over the weights' angles relative to the rotor, with a
Schur complement and its own compiled DOP853.  Two implementations of the same
equations, so they agree to the integrators' global error.

Tolerances.  The stand runs at rtol 1e-12 (atol 1e-14 r*).  A convergence study (largest
shaft difference over the largest whirl, 5-10 mm here; oracle atol tightened below its
rtol's share) gave, for the oracle's rtol 1e-10 / 1e-11 / 1e-12 / 1e-13 (the stand at
1e-13 for the last): 2.5e-10 / 1.3e-11 / 2e-12 / 3e-13 without friction (ball angles
1.7e-9 rad at 1e-10), and 1.2e-8 / - / 4e-11 / 6e-12 with friction mu = 3e-3 (ball
angles 9.5e-8 rad at 1e-10).  The difference falls with the tolerances, to ~1e-12: the
models agree, and what the asserts bound is the oracle's global error at its default
rtol 1e-10: the per-step tolerance accumulated over ~2e3 steps and amplified by the
dynamics -- the resonance passage (balls held near f0 drive a 5-10 mm whirl) and, with
friction, the regularised stick (rate mu psi'^2 / v_s ~ 1300 1/s against the rotor's
94 rad/s), which makes the balls' angles 50x more sensitive to the step errors.  The
asserts take a factor 10-40 above the measured: 1e-8 of the whirl and 2e-8 rad without
friction, 2e-7 and 2e-6 rad with it.
"""
from __future__ import annotations

import json
import math
from dataclasses import replace

import numpy as np
import pytest

import stand
from _helpers import stand_stdout
from oracles.two_ball_record import (UNIVERSAL, family_scene_text, record, scene_text,
                                    template_scene, write_record)

SHORT = ((0.0, 0.0), (3.0, 15.0))     # through f0 = 3 Hz at 0.6 s, then 15 rev/s
VARIED = replace(UNIVERSAL, unbalance_angle=40.0, stiffness_y=2000.0, damping_y=5.0,
                 ball_mass=(0.045, 0.03), radius=(0.08, 0.07), drag=(0.16965, 0.3),
                 initial_angles=(100.0, 250.0))


FAST = 1.5    # s: through the resonance (0.6 s) to 7.5 rev/s, the default suite's length
SLOW = [pytest.param(FAST, id="fast"), pytest.param(5.0, id="5s", marks=pytest.mark.full)]


def _short(p, programme=SHORT, duration=5.0, **kw):
    return record(p, programme, duration=duration, fs=200.0, noise_m=0.0, kp_noise_v=0.0, **kw)


def _compare(rec, run):
    """(largest shaft difference / largest whirl, largest ball-angle difference [rad])."""
    assert np.allclose(run.t, rec.t, rtol=0, atol=1e-12)
    assert np.max(np.abs(run.rotor_angle - rec.phi)) < 1e-9     # both closed forms
    xy = run.planes[run.main_plane]
    z_s, z_o = xy[:, 0] + 1j * xy[:, 1], rec.x_true + 1j * rec.y_true
    names = list(run.weights)
    a_s = np.array([run.weights[k]["angle"] for k in names]) - run.rotor_angle
    return (float(np.max(np.abs(z_s - z_o)) / np.max(np.abs(z_o))),
            float(np.max(np.abs(a_s - rec.alpha))))


@pytest.mark.parametrize("duration", SLOW)
@pytest.mark.parametrize("params", [UNIVERSAL, VARIED], ids=["universal", "varied"])
def test_oracle_matches_planar_kernel(params, duration):
    """The planar scene written from the record's truth (scene_text) runs on the planar
    kernel; the varied case turns every convention (anisotropic supports, unequal balls,
    unbalance angle 40 deg, unsymmetric initial angles).  The bounds are the 5-s runs'
    (module docstring); the 1.5-s runs accumulate less."""
    rec = _short(params, duration=duration)
    scene = stand.load(scene_text(rec.truth(), sample_rate=200.0, duration=duration,
                                  rtol=1e-12, atol=1e-14))
    assert scene.kind == "planar"
    dz, da = _compare(rec, stand.run(scene))
    assert dz < 1e-8, dz
    assert da < 2e-8, da


@pytest.mark.parametrize("duration", SLOW)
def test_oracle_friction_matches_generic_kernel(duration):
    """Rolling friction mu = 3e-3 (kinetic = static) on the [structure] planar form."""
    p = replace(VARIED, friction=3e-3)
    rec = _short(p, duration=duration)
    scene = stand.load(family_scene_text(rec.truth(), sample_rate=200.0, duration=duration,
                                         rtol=1e-12, atol=1e-14))
    dz, da = _compare(rec, stand.run(scene))
    assert dz < 2e-7, dz
    assert da < 2e-6, da


def test_rolling_balls_agree_at_constant_speed():
    """Rolling balls (spin inertia 2/5 m l^2 on the angle relative to the rotor) and the
    stand's ``rolling = true`` (J = 7/5 m l^2 on the absolute angle) are the same at
    constant speed."""
    p = replace(UNIVERSAL, rolling=True, friction=2e-3)
    rec = _short(p, programme=((0.0, 10.0),), duration=1.0, rtol=1e-12)
    dz, da = _compare(rec, stand.run(stand.load(family_scene_text(
        rec.truth(), sample_rate=200.0, duration=1.0, rtol=1e-12, atol=1e-14))))
    assert dz < 1e-8 and da < 1e-7, (dz, da)


@pytest.mark.parametrize("duration, rtol, bounds", [
    pytest.param(FAST, 1e-10, (1e-8, 2e-8), id="fast"),
    pytest.param(5.0, 1e-11, (2e-9, 2e-8), id="5s", marks=pytest.mark.full)])
def test_rolling_balls_on_a_ramp(duration, rtol, bounds):
    """On the run-up the ball's spin inertia J_s = 2/5 m l^2 acts on its angle relative to
    the rotor (stand.model.weights): the stand's ball row carries + J_s phi''.  Oracle at
    rtol 1e-11 over 5 s (its no-friction error 1.3e-11 of the whirl, module docstring):
    measured 1.4e-10 of the whirl and 1.3e-9 rad; at rtol 1e-10 over 1.5 s the bounds of
    the point balls (2.5e-10 of the whirl at 1e-10); the asserts take the factor 10-40
    above it.  (With J = 7/5 m l^2 on the absolute angle, the model before, the whirl
    differed by 105 % of itself and the balls by 14 rad over 5 s.)"""
    p = replace(UNIVERSAL, rolling=True)
    rec = _short(p, duration=duration, rtol=rtol)
    dz, da = _compare(rec, stand.run(stand.load(family_scene_text(
        rec.truth(), sample_rate=200.0, duration=duration, rtol=1e-12, atol=1e-14))))
    assert dz < bounds[0] and da < bounds[1], (dz, da)


def _analyze(csv, rmap):
    return json.loads(stand_stdout("analyze", csv, "--json", "--map", rmap))


@pytest.mark.full    # analyze alone takes 10-20 s on this record (the kernels: the tests above)
def test_record_files_are_read_by_analyze(tmp_path):
    """CSV + map + truth; ``stand analyze`` finds the keyphasor's pulses and the speed."""
    rec = record(UNIVERSAL, SHORT, duration=5.0, fs=1000.0, seed=1)
    csv, rmap, tj = write_record(rec, tmp_path / "two_ball.csv")
    assert csv.read_text().splitlines()[0] == "time_s,x_um,y_um,kp_V"
    truth = json.loads(tj.read_text())
    assert truth["stiffness"] == UNIVERSAL.stiffness_x and truth["unbalance_angle"] == 0.0
    assert truth["balancer"]["initial_angles"] == [150.0, 210.0]
    d = _analyze(csv, rmap)
    assert d["speed_source"].startswith("keyphasor column 'kp_V'")
    # revolutions: 15 * 3 / 2 = 22.5 in the ramp + 30 in 2 s at 15 rev/s; a pulse at
    # every whole one (phi = 2 pi k, k >= 1: the record starts inside the pulse at phi = 0)
    n_pulses = int(d["speed_source"].split("leading edges, ")[1].split(" pulses")[0])
    assert n_pulses == 52
    # the speed: the keyphasor's spline (a knot every 8 revolutions) rounds the programme's
    # kink at 3 s and wobbles by a few 0.01 rev/s there and at the record's end (TTL edges
    # timed to 1 ms = 24 deg at 15 rev/s), which the stretch classifier may call a short
    # run-down: only the speeds are asserted
    st = d["programme"]["stretches"]
    assert st[0]["kind"] == "run-up"
    assert st[0]["speed_start_hz"] == pytest.approx(5.0 * st[0]["t_start_s"], rel=3e-2)  # spline end
    for s in st:
        if s["t_start_s"] > 3.5:
            assert s["speed_start_hz"] == pytest.approx(15.0, rel=5e-3), st
            assert s["speed_end_hz"] == pytest.approx(15.0, rel=5e-3), st


@pytest.mark.full    # analyze alone takes 10-15 s on this record
def test_unbalance_angle_is_measured_from_the_mark(tmp_path, mark=25.0):
    """No balls (a rigid rotor run-up): ``stand analyze`` reads the truth's
    ``unbalance_angle`` (beta + mark_angle) within its std (a TTL edge: ~1 deg)."""
    p = replace(UNIVERSAL, count=0, initial_angles=(), unbalance_angle=70.0, eccentricity=2e-4)
    rec = record(p, ((0.0, 1.0), (8.0, 8.0)), duration=10.0, fs=1000.0, mark_angle_deg=mark,
                 seed=3)
    csv, rmap, tj = write_record(rec, tmp_path / "rigid.csv")
    truth = json.loads(tj.read_text())
    assert truth["unbalance_angle"] == 70.0 + mark
    d = _analyze(csv, rmap)
    da = (d["unbalance_angle_deg"] - truth["unbalance_angle"] + 180.0) % 360.0 - 180.0
    assert abs(da) < 4.0 * d["unbalance_angle_deg_std"], (da, d["unbalance_angle_deg_std"])
    assert d["unbalance_gmm"] == pytest.approx(truth["unbalance_gmm"], rel=0.02)


def test_template_scene(tmp_path):
    rec = _short(UNIVERSAL, duration=1.0)
    truth = rec.truth()
    scene = stand.load(template_scene(truth, tmp_path / "t.toml").read_text())
    assert scene.supports.stiffness_x == pytest.approx(1.12 * UNIVERSAL.stiffness_x, rel=1e-9)
    assert scene.supports.damping_y == pytest.approx(1.8 * UNIVERSAL.damping_x, rel=1e-9)
    assert scene.rotor.eccentricity == pytest.approx(0.7 * UNIVERSAL.eccentricity, rel=1e-9)
    assert scene.rotor.unbalance_angle == pytest.approx(math.radians(35.0), abs=1e-12)
    assert scene.run.duration == 1.0 and scene.run.sample_rate == 200.0
    # with friction the [balancer] gets a friction key (read once [balancer] friction lands)
    text = template_scene(replace(rec, params=replace(UNIVERSAL, friction=3e-3)).truth(),
                          tmp_path / "f.toml", friction=0.5).read_text()
    assert "\nfriction = 0.0015\n" in text
