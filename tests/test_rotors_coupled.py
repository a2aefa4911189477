"""Weights coupled to the generic LinearRotor (stand.integrate.coupled)."""
import math

import numpy as np
import pytest

from stand.model.rotors import LinearRotor, Unbalance, working_ranges
from stand.integrate.coupled import PlaneWeights, simulate_coupled
from stand.scene.model import Balancer
from stand.scene.parse import load_scene
from stand.integrate.simulate import simulate


def _planar_rotor(sc):
    s = sc.supports
    return LinearRotor("planar", ("x [m]", "y [m]"), np.eye(2) * sc.rotor.mass, np.zeros((2, 2)),
                       np.diag([s.damping_x, s.damping_y]), np.diag([s.stiffness_x, s.stiffness_y]),
                       {"balancer": np.eye(2)},
                       (Unbalance("balancer", sc.rotor.unbalance, sc.rotor.unbalance_angle),))


def test_generic_form_reproduces_the_planar_model():
    """The planar model of the core simulator written as a LinearRotor (M, D, K,
    T = I) with the same two balls: same shaft motion to the tolerance."""
    import dataclasses

    sc = load_scene("data_samples/scenes/ball_runup.toml")
    sc = dataclasses.replace(sc, run=dataclasses.replace(sc.run, duration=15.0, rtol=1e-10,
                                                         atol=1e-12))
    tr = simulate(sc)
    cr = simulate_coupled(_planar_rotor(sc), [PlaneWeights("balancer", sc.balancer)],
                          sc.drive.programme, sc.run.duration, sc.run.sample_rate,
                          rtol=1e-10, atol=1e-12)
    assert cr.success and tr.success
    np.testing.assert_allclose(cr.t, tr.t, atol=1e-12)
    X = np.column_stack([tr.x, tr.y])
    # both integrate the same ODE at rtol 1e-10: agreement far below the 10 mm motion
    assert np.abs(cr.planes["balancer"] - X).max() < 1e-7 * np.abs(X).max()
    assert np.abs(np.angle(np.exp(1j * (cr.weight_angle - tr.relative_angle)))).max() < 1e-6


def _two_mass(M1=2.0, M2=1.0, c1=1.0e4, c2=3.0e4, zeta=0.01, s=2e-3):
    """Rotor M2 on springs c2 in a body M1 on springs c1 (model 2.5.2), light damping."""
    I2 = np.eye(2)
    Z = np.zeros((2, 2))
    M = np.block([[M1 * I2, Z], [Z, M2 * I2]])
    K = np.block([[(c1 + c2) * I2, -c2 * I2], [-c2 * I2, c2 * I2]])
    D = 2 * zeta * math.sqrt(c2 * M2) * K / c2
    T = np.hstack([Z, I2])
    return LinearRotor("two_mass", ("x1 [m]", "y1 [m]", "x2 [m]", "y2 [m]"), M, np.zeros((4, 4)), D,
                       K, {"balancer": T, "body": np.hstack([I2, Z])},
                       (Unbalance("balancer", s, 0.0),))


def _balls(m=0.01, R=0.2, drag=2.0):
    return Balancer(type="balls", mass=np.full(2, m), radius=np.full(2, R), drag=np.full(2, drag),
                    inertia=np.full(2, m * R * R), initial_angles=np.radians([60.0, 250.0]),
                    initial_speeds=np.zeros(2))


def test_two_mass_rotor_balances_inside_its_working_range_only():
    """Model 2.5.2 with two balls: criterion ranges (w1, w2) U (w3, inf); a run held
    inside the first range and one in the gap (w2, w3) end balanced / unbalanced."""
    rot = _two_mass()
    crit, ranges = working_ranges(rot, "balancer", 1.0, 2000.0)
    assert len(crit) == 3 and len(ranges) == 2
    w1, w2, w3 = crit
    # inside the first range (geometric middle) and in the gap between w2 and w3
    for w, expect in ((math.sqrt(w1 * w2), True), (math.sqrt(w2 * w3), False),
                      (2.0 * w3, True)):
        run = simulate_coupled(rot, [PlaneWeights("balancer", _balls())], [[0.0, w]],
                               duration=400 * 2 * math.pi / w1, sample_rate=20 * w / (2 * math.pi))
        assert run.success
        U = np.hypot(*run.residual["balancer"][-1])
        balanced = U < 0.05 * 2e-3
        assert balanced == expect, (w, U)


def test_generic_kernel_allocation_free_matches_a_numpy_solve():
    """The generic right-hand side with its scratch block in sp (issue 33) and its own
    elimination for n > 12: q'' of the flexible shaft with 10 modes (n = 20) against the same
    Schur system assembled and solved by numpy (round-off: 1e-10 of the largest term)."""
    from stand.scene.parse import load_scene
    from stand.integrate.coupled import build_model, initial_state
    from stand.model.rotors.coupled_kernel import (H_OS, rhs_generic, scratch_size, W_J, W_L,
                                                   W_M, W_PLANE)
    from stand.model.programme import programme_kinematics_many

    from pathlib import Path

    sc = load_scene(Path(__file__).resolve().parents[1] / "data_samples" / "scenes"
                    / "stress_flexible_10modes.toml")
    rotor = sc.linear_rotor()
    m = build_model(rotor, sc.weights, sc.drive.programme)
    n, nw = m.n, m.nw
    assert m.sp.size - int(m.sp[H_OS]) == scratch_size(n, nw, len(m.plane_names), False)
    y = initial_state(m, sc.weights) + 1e-3 * np.sin(np.arange(m.size))
    tau = 2.0
    dy = np.empty_like(y)
    params = m.sp[:int(m.sp[H_OS])].copy()
    rhs_generic(tau, y, dy, m.sp, m.wt, m.prog)
    assert np.array_equal(m.sp[:int(m.sp[H_OS])], params)       # parameters untouched
    w = m.omega_ref
    phi, R, dR = programme_kinematics_many(tau, m.prog)[0]
    Om, dOm = R * w, dR * w * w
    q, qd = m.scale * y[:n], w * m.scale * y[n + nw:2 * n + nw]
    A = rotor.M.copy()
    f = -rotor.K @ q - (rotor.D + Om * rotor.G) @ qd + rotor.gravity
    names = m.plane_names
    for u in rotor.unbalances:
        th = phi + u.angle
        F = rotor.force_map(u.plane)
        f += F.T @ (u.s * np.array([Om ** 2 * np.cos(th) + dOm * np.sin(th),
                                    Om ** 2 * np.sin(th) - dOm * np.cos(th)]))
    for j, row in enumerate(m.wt):
        p = names[int(row[W_PLANE])]
        T, F = rotor.planes[p], rotor.force_map(p)
        mj, l, J = row[W_M], row[W_L], row[W_J]
        psi, psid = phi + y[n + j], Om + w * y[2 * n + nw + j]
        e, nv = np.array([np.cos(psi), np.sin(psi)]), np.array([np.sin(psi), -np.cos(psi)])
        k2 = mj * mj * l * l / J
        H = sc.weights[0].balancer.moment_drag[0]
        Mr = H * w * y[2 * n + nw + j]
        A += mj * F.T @ T - k2 * np.outer(F.T @ nv, T.T @ nv)
        f += F.T @ (mj * l * psid ** 2 * e - mj * l * Mr / J * nv)
    qdd = np.linalg.solve(A, f)
    got = dy[n + nw:2 * n + nw] * w * w * m.scale
    assert np.max(np.abs(got - qdd)) <= 1e-10 * np.max(np.abs(qdd))


@pytest.mark.parametrize("torque", [False, True])
@pytest.mark.parametrize("one_plane", [False, True])
def test_plane_space_solve_equals_the_general_elimination(torque, one_plane):
    """The Woodbury solve in the planes' space (stand.model.rotors.coupled_solve, the flexible
    shaft's fast path) against the assembled n x n elimination, on a flexible shaft with 5 modes
    per direction (n = 10), three planes (2P = 6: the small system eliminated) or one (2 x 2:
    Cramer), gravity, three balls and two pendulums, a two-axis pendulum and a lagging liquid
    (its phi''-column under a torque drive): every derivative equal to round-off, for random
    states, compiled and in plain Python."""
    from stand.model.rotors.bodies import LiquidWeight, PlaneBody, TiltingWeight
    from stand.integrate.coupled import build_model, initial_state
    from stand.model.rotors.coupled_kernel import H_FAST, rhs_generic
    from stand.model.rotors.flexible import flexible_shaft
    from stand.scene.model import RotorTorqueDrive

    rng = np.random.default_rng(33)
    planes = {"a": 0.3} if one_plane else {"a": 0.3, "b": 0.7, "u": 0.55}
    rotor = flexible_shaft(1.0, 10.0, 2000.0, n_modes=5, damping_ratio=0.02, planes=planes,
                           unbalances={p: [2e-3 / (k + 1), 0.4 + k] for k, p in enumerate(planes)},
                           g=(0.0, -9.81))
    other = "a" if one_plane else "b"
    balls = Balancer(type="balls", mass=np.array([0.01, 0.012, 0.009]), radius=np.full(3, 0.2),
                     drag=np.full(3, 2.0), inertia=0.2 ** 2 * np.array([0.01, 0.012, 0.009]),
                     initial_angles=np.array([0.3, 2.0, 4.0]), initial_speeds=np.zeros(3))
    pend = Balancer(type="pendulums", mass=np.array([0.02, 0.015]), radius=np.array([0.1, 0.12]),
                    drag=np.array([0.01, 0.02]), inertia=np.array([4e-4, 3e-4]),
                    initial_angles=np.array([1.0, 5.0]), initial_speeds=np.zeros(2))
    bodies = (PlaneBody(other, TiltingWeight("two_axis_pendulum", 0.05, 0.03, 1e-4, 6e-5, 1e-4,
                                           1e-4, 9.81, initial_tilt=0.1, initial_angle=0.7)),
              PlaneBody("a", LiquidWeight("liquid_chamber", 0.4, 0.1, 0.08, height=0.03,
                                          relaxation_time=0.05, volume=4e-4)))
    drive = (RotorTorqueDrive(model="speed_feedback", c1=0.05, target_speed=300.0,
                              rotor_drag=0.004, initial_speed=50.0, inertia=0.02)
             if torque else [[0.0, 0.0], [2.0, 300.0]])
    weights = [PlaneWeights("a", balls), PlaneWeights(other, pend)]
    m = build_model(rotor, weights, drive, bodies=bodies)
    assert m.sp[H_FAST] == 1.0 and m.n == 10
    general = m.sp.copy()
    general[H_FAST] = 0.0
    y0 = initial_state(m, weights)
    for f in (rhs_generic, getattr(rhs_generic, "py_func", rhs_generic)):
        for tau in (0.3, 7.0):
            y = y0 + 0.3 * rng.standard_normal(y0.size)
            fast, slow = np.empty_like(y), np.empty_like(y)
            f(tau, y, fast, m.sp, m.wt, m.prog)
            f(tau, y, slow, general, m.wt, m.prog)
            assert np.all(np.isfinite(fast))
            # the same forces, two solves of one well-conditioned mass-like system (M = m l / 2 I,
            # the weights 1e-3 of it): a few n eps apart (observed <= 7e-16), 1e-13 allowed
            assert np.max(np.abs(fast - slow)) <= 1e-13 * np.max(np.abs(slow))
