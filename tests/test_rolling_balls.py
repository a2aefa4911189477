"""Rolling balls (``rolling = true``): the spin inertia J_s = 2/5 m l^2 turns with the ball's
angle relative to the rotor (stand.model.weights).  The ramp is checked against the
independent oracle (tests/test_oracle_two_ball.py); here the free rotor, where the spin
reacts on the rotor's angle: the conservative stand keeps its energy, and the planar
kernel, its numpy reference and the generic kernel agree."""
from __future__ import annotations


import numpy as np

import stand
from stand.integrate.simulate import simulate

SCENE = """
[rotor]
mass = 4.45
eccentricity = 8.0899e-4
inertia = 0.02                 # kg m^2: J_0 small, so the balls' spin matters
[supports]
stiffness = 1613.09
damping = {damping}
[balancer]
type = "balls"
count = 2
mass = 0.045
radius = 0.08
drag = {drag}
rolling = {rolling}
initial_angles = [150.0, 210.0]
initial_speeds = [1.5, -2.0]   # rev/s relative to the rotor
[drive]
type = "torque"
model = "{model}"
{drive}
initial_speed = 2.0
[run]
duration = {duration}
sample_rate = 400.0
rtol = 1e-11
atol = 1e-13
"""


def _scene(rolling="true", damping=0.0, drag=0.0, model="constant", drive="torque = 0.0",
           duration=1.0):
    return stand.load(SCENE.format(rolling=rolling, damping=damping, drag=drag, model=model,
                                   drive=drive, duration=duration))


def _energy(sc, run):
    """Kinetic + elastic energy [J] from the planar run's state (SI), the rolling spin
    J_s (psi' - phi')^2 / 2 included."""
    L, w1 = sc.length_scale, sc.natural_frequency
    s = run.state
    x, y, vx, vy = L * s[:, 0], L * s[:, 1], L * w1 * s[:, 5], L * w1 * s[:, 6]
    phi, dphi = run.rotor_angle, run.rotor_speed
    r, b = sc.rotor, sc.balancer
    M, e, th = r.mass, r.eccentricity, phi + r.unbalance_angle
    # rotor: centre of mass at K + e (cos, sin)(phi + beta); J_C about it
    T = 0.5 * M * ((vx - e * dphi * np.sin(th)) ** 2 + (vy + e * dphi * np.cos(th)) ** 2)
    T += 0.5 * r.inertia * dphi ** 2
    for j in range(b.count):
        psi, dpsi = phi + s[:, 2 + j], dphi + w1 * s[:, 7 + j]
        m, l = b.mass[j], b.radius[j]
        T += 0.5 * m * ((vx - l * dpsi * np.sin(psi)) ** 2 + (vy + l * dpsi * np.cos(psi)) ** 2)
        T += 0.5 * b.spin_inertia[j] * (dpsi - dphi) ** 2
    return T + 0.5 * (sc.supports.stiffness_x * x ** 2 + sc.supports.stiffness_y * y ** 2)


def test_spin_inertia_of_the_scene():
    sc = _scene()
    m, l = 0.045, 0.08
    np.testing.assert_allclose(sc.balancer.inertia, 1.4 * m * l * l, rtol=1e-15)
    np.testing.assert_allclose(sc.balancer.spin_inertia, 0.4 * m * l * l, rtol=1e-14)
    assert not np.any(_scene(rolling="false").balancer.spin_inertia)


def test_free_rotor_keeps_its_energy():
    """No damping, no drag, no torque: T + V is constant.  The balls' relative motion
    (1.5 and -2 rev/s) exchanges spin with the rotor (J_0 = 0.02 kg m^2; its speed moves
    by 1 %): their spin energy sum J_s alpha'^2 / 2 is 14 mJ, and without the rotor row's
    reaction J_s (phi'' - psi_j'') (or the ball row's J_s phi'') the energy drifts by 14 mJ
    (measured).  The bound is the integrator's: rtol 1e-11 per step over ~1e3 steps of a
    1.66 J total, 2e-10 of it (measured 5.6e-12 J, 3.4e-12 of it)."""
    sc = _scene()
    run = stand.run(sc)
    assert run.stats.status == 0 and sc.kind == "planar" and sc.generic_kernel == ""
    E = _energy(sc, run)
    assert np.ptp(E) < 2e-10 * E[0], (np.ptp(E), E[0])
    # the rotor's speed does change: the coupling is exercised, not idle
    assert np.ptp(run.rotor_speed) > 1e-3 * run.rotor_speed[0]


def test_planar_kernel_matches_its_numpy_reference():
    """The O(n) elimination against the full linear solve at random states."""
    from stand.model.planar import build_planar_model, rhs_planar, rhs_planar_numpy

    for text in (_scene(), _scene(model="speed_feedback", drive="c1 = 0.3\ntarget_speed = 5.0",
                                  drag=0.2)):
        model = build_planar_model(text)
        rng = np.random.default_rng(3)
        for _ in range(5):
            y = rng.normal(size=model.size)
            dy = np.empty_like(y)
            rhs_planar(0.3, y, dy, model.sp, model.wt, model.prog)
            ref = rhs_planar_numpy(0.3, y, model.sp, model.wt, model.prog)
            np.testing.assert_allclose(dy, ref, rtol=1e-12, atol=1e-12)
    # and on a speed ramp (the ball's row only)
    ramp = stand.load(SCENE.format(rolling="true", damping=0.0, drag=0.1, model="", drive="",
                                   duration=1.0).replace('type = "torque"\nmodel = ""\n\n'
                                                         'initial_speed = 2.0',
                                                         'type = "speed"\n'
                                                         'programme = [[0.0, 0.0], [1.0, 9.0]]'))
    model = build_planar_model(ramp)
    y = np.random.default_rng(4).normal(size=model.size)
    dy = np.empty_like(y)
    rhs_planar(0.5, y, dy, model.sp, model.wt, model.prog)
    np.testing.assert_allclose(dy, rhs_planar_numpy(0.5, y, model.sp, model.wt, model.prog),
                               rtol=1e-12, atol=1e-12)


def test_generic_kernel_matches_the_planar_one_on_a_free_rotor():
    """A speed-feedback drive (a torque ramp), damping and drag: the two kernels, each with
    its own elimination of the spin terms, agree to the integration tolerance (rtol 1e-11;
    measured 4e-12 of the whirl, 1e-14 rad of the rotor, 4.5e-13 rad of the balls)."""
    sc = _scene(damping=8.5577, drag=0.16965, model="speed_feedback",
                drive="c1 = 0.3\ntarget_speed = 5.0", duration=1.0)
    a, b = simulate(sc), simulate(sc, kernel="generic")
    za = a.x + 1j * a.y
    zb = b.x + 1j * b.y
    assert np.max(np.abs(za - zb)) < 1e-10 * np.max(np.abs(za))
    assert np.max(np.abs(a.rotor_angle - b.rotor_angle)) < 1e-10
    for k in a.weights:
        assert np.max(np.abs(a.weights[k]["angle"] - b.weights[k]["angle"])) < 1e-10
    # and the rolling balls are not the point balls
    point = simulate(_scene(rolling="false", damping=8.5577, drag=0.16965, model="speed_feedback",
                            drive="c1 = 0.3\ntarget_speed = 5.0", duration=1.0))
    assert np.max(np.abs(point.rotor_angle - a.rotor_angle)) > 1e-4
