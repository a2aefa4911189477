"""Ball-ball contact (``ball_radius``, ``contact_stiffness``, ``contact_damping`` of a ball
table; stand.model.rotors.coupled_kernel.contact_moments): balls do not pass through each
other.  Checked against closed forms: an elastic bounce on a free rotor (the relative
motion's energy and the momentum about the shaft), and balls pressed together below the
resonance settling at the spacing 2 asin(r / l)."""
from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

import stand
from stand.integrate.coupled import PlaneWeights, simulate_coupled
from stand.model.rotors.coupled_kernel import H_CONTACT, build_model
from stand.model.rotors.planar_supports import planar_rotor
from stand.model.rotors.weight_table import W_NEXT
from stand.scene.model import Balancer, SceneError

m, l, r, k = 0.045, 0.08, 0.01, 1e4        # universal stand's balls, 10 mm radius
GAP = 2.0 * math.asin(r / l)              # their angular spacing when touching [rad]

SCENE = """
[rotor]
mass = 4.45
eccentricity = 8.0899e-4
[supports]
stiffness = 1613.09
damping = 8.5577
[balancer]
type = "balls"
count = 2
mass = 0.045
radius = 0.08
drag = 0.16965
initial_angles = [60.0, 300.0]
{contact}
[drive]
type = "speed"
programme = [[0.0, 0.0], [1.0, 2.0]]
[run]
duration = 20.0
sample_rate = 50.0
"""
CONTACT = "ball_radius = 0.01\ncontact_stiffness = 1e4\ncontact_damping = 2.0"


def test_contact_keys():
    sc = stand.load(SCENE.format(contact=CONTACT))
    b = sc.balancer
    assert (b.ball_radius, b.contact_stiffness, b.contact_damping) == (0.01, 1e4, 2.0)
    assert sc.generic_kernel == "ball-ball contact"
    assert stand.load(SCENE.format(contact="")).balancer.ball_radius == 0.0
    with pytest.raises(SceneError, match="contact_stiffness: missing"):
        stand.load(SCENE.format(contact="ball_radius = 0.01"))
    with pytest.raises(SceneError, match="ball_radius: missing"):
        stand.load(SCENE.format(contact="contact_stiffness = 1e4"))
    with pytest.raises(SceneError, match=r"ball_radius = -0\.01.*m"):
        stand.load(SCENE.format(contact="ball_radius = -0.01\ncontact_stiffness = 1e4"))
    coast = SCENE.format(contact=CONTACT).replace(
        "[1.0, 2.0]]", "[1.0, 2.0]]\ncoast_down = {start = 5.0, time_constant = 2.0}")
    with pytest.raises(SceneError, match=r"ball_radius \(ball-ball contact\) run on the generic"):
        stand.load(coast)
    pend = SCENE.format(contact=CONTACT).replace('"balls"', '"pendulums"')
    with pytest.raises(SceneError, match="only for balls"):
        stand.load(pend)


def _balls(n, angles, speeds, damping=0.0, radius=r):
    return Balancer(type="balls", mass=np.full(n, m), radius=np.full(n, l), drag=np.zeros(n),
                    inertia=np.full(n, m * l * l), initial_angles=np.asarray(angles, float),
                    initial_speeds=np.asarray(speeds, float), ball_radius=radius,
                    contact_stiffness=k, contact_damping=damping)


def test_neighbours_in_the_race_and_no_contact_work_without_it():
    rot = planar_rotor(4.45, 1613.09)
    ring = build_model(rot, [PlaneWeights("balancer", _balls(3, [4.0, 1.0, 2.0], np.zeros(3)))],
                       [[0.0, 10.0]])
    assert list(ring.wt[:, W_NEXT]) == [1.0, 2.0, 0.0]     # 1 -> 2 -> 0 -> 1 around the race
    assert ring.sp[H_CONTACT] == 1.0
    off = build_model(rot, [PlaneWeights("balancer", _balls(3, [4.0, 1.0, 2.0], np.zeros(3),
                                                            radius=0.0))], [[0.0, 10.0]])
    assert off.sp[H_CONTACT] == 0.0 and np.all(off.wt[:, W_NEXT] == -1.0)


@pytest.mark.parametrize("overlap", [0.001, 0.05])
def test_two_balls_bounce_apart_on_a_free_rotor(overlap):
    """Two balls started overlapping by ``overlap`` of 2 r and closing at 0.5 rev/s each, on
    a free rotor (no torque, no drag, no unbalance) spinning at 2 rev/s; the shaft 1e4
    times the stand's mass, so that the balls meet as on a fixed ring.  Closed form of the
    collision: the contact is internal, so the rotor's speed and the balls' mean speed
    (the momentum about the shaft) do not change, and the relative motion's energy
    (m l^2 / 4) Delta'^2 + k delta^2 / 2 (Delta = alpha_1 - alpha_2, delta the overlap) is
    the same before and after: Delta'_after = sqrt(Delta'_0^2 + 2 k delta_0^2 / (m l^2)).
    The shaft's motion couples them at O(m / M) = 1e-6 (measured 6e-7)."""
    M = 44500.0
    rot = planar_rotor(M, (M + 2 * m) * (2 * math.pi * 3.0) ** 2)
    a0 = 2.0 * math.asin((1.0 - overlap) * r / l)             # chord 2 r (1 - overlap)
    v = 2 * math.pi * 0.5
    balls = _balls(2, [math.pi - a0 / 2, math.pi + a0 / 2], [v, -v])
    drive = SimpleNamespace(kind="torque", model="constant", torque=0.0, c1=0.0, c2=0.0,
                            target_speed=0.0, rotor_drag=0.0, initial_speed=4 * math.pi,
                            inertia=0.05)
    run = simulate_coupled(rot, [PlaneWeights("balancer", balls)], drive, 0.06, 5000.0,
                           rtol=1e-10, atol=1e-12)
    assert run.success
    after = run.t > 0.03                                       # the contact lasts ~5 ms
    s1, s2 = (np.polyfit(run.t[after], run.weight_angle[after, j], 1)[0] for j in (0, 1))
    delta0 = 2 * r * overlap
    expect = math.sqrt(4 * v * v + 2 * k * delta0 ** 2 / (m * l * l))
    assert s1 - s2 == pytest.approx(-expect, rel=2e-6)         # bounced apart
    assert abs(s1 + s2) < 2e-6 * expect                        # mean speed kept
    assert np.ptp(run.speed) < 1e-12 * run.speed[0]            # the rotor feels nothing net
    assert np.min(run.weight_angle[:, 1] - run.weight_angle[:, 0]) > 0.9 * a0   # no pass-through


def test_a_dashpot_loses_energy_in_the_bounce():
    M = 4450.0
    rot = planar_rotor(M, (M + 2 * m) * (2 * math.pi * 3.0) ** 2)
    v = 2 * math.pi * 0.5
    a0 = GAP * (1 - 1e-6)
    runs = [simulate_coupled(rot, [PlaneWeights("balancer", _balls(2, [math.pi - a0 / 2, math.pi + a0 / 2],
                                                                    [v, -v], damping=c))],
                             [[0.0, 4 * math.pi]], 0.06, 5000.0, rtol=1e-10, atol=1e-12)
            for c in (0.0, 3.0)]
    after = runs[0].t > 0.03
    rel = [np.polyfit(x.t[after], x.weight_angle[after, 1] - x.weight_angle[after, 0], 1)[0]
           for x in runs]
    # zeta = c / (2 sqrt(k m / 2)) = 0.1: the restitution of a linear spring-dashpot
    # exp(-pi zeta / sqrt(1 - zeta^2)) = 0.73 if it could pull; it only pushes, so a
    # little more comes back (the balls part when k delta = c delta')
    assert rel[0] == pytest.approx(2 * v, rel=2e-5)          # O(m / M) = 1e-5
    assert 0.73 * 2 * v < rel[1] < 0.8 * 2 * v, rel           # measured 0.746


def test_balls_pressed_together_below_resonance_keep_their_spacing():
    """Below the resonance (2 rev/s, f0 = 3 Hz) the balls run to the heavy side and press
    on each other: they settle touching, at the spacing 2 asin(r / l), short of it by the
    overlap the push needs: the shaft's acceleration Omega^2 R (R: the whirl) pushes a
    ball with at most m Omega^2 R along the track, so the overlap is at most
    m Omega^2 R / (k cos(Delta/2)) and the spacing short by at most
    m Omega^2 R / (k l cos^2(Delta/2)) (1.6e-5 rad here; measured 2.1e-6).  Without the
    contact the two balls end on top of each other."""
    run = stand.run(stand.load(SCENE.format(contact=CONTACT)))
    a = [run.weights[b]["angle"] - run.rotor_angle for b in ("ball1", "ball2")]
    spacing = np.mod(a[1] - a[0], 2 * math.pi)
    spacing = np.minimum(spacing, 2 * math.pi - spacing)
    W = 2 * math.pi * 2.0
    R = np.hypot(run.x[-1], run.y[-1])
    bound = m * W * W * R / (k * l * math.cos(GAP / 2) ** 2)
    assert 0.0 < GAP - spacing[-1] < bound, (GAP - spacing[-1], bound)
    assert np.ptp(spacing[-50:]) < 0.1 * bound                  # settled (the last second)
    assert np.min(spacing) > 0.5 * GAP                          # never through each other
    free = stand.run(stand.load(SCENE.format(contact="")))
    b = [free.weights[x]["angle"] - free.rotor_angle for x in ("ball1", "ball2")]
    d = np.mod(b[1] - b[0], 2 * math.pi)
    assert min(d[-1], 2 * math.pi - d[-1]) < 0.1 * GAP
