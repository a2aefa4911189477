"""Oracles for the autobalancer-damper (ABD, book 7.2, digest ch7_ch1 sections 0, 2, 5)."""
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from stand.model.balancers import damper as d
from stand.theories.weights import damper_steady as dst
from stand.theories.weights.one_model import rotating_form
from oracles import damper as book

FIG726 = dict(R_m=0.1, R_omega=3.0, R_g=0.3, h=0.3, H=0.3, e0=0.5)


# --- model consistency --------------------------------------------------------------

def test_fixed_and_rotating_forms_agree():
    p = d.DamperParams(**FIG726)
    rng = np.random.default_rng(3)
    for _ in range(4):
        tau = rng.uniform(0, 5)
        n = rng.normal(size=3); n /= np.linalg.norm(n)
        s = np.concatenate([rng.normal(size=4) * 0.1, n, rng.normal(size=3)])
        f = book.rhs(tau, s, p)
        h = 1e-6
        num = (d.to_rotating(tau + h, s + h * f, p.R_omega)
               - d.to_rotating(tau - h, s - h * f, p.R_omega)) / (2 * h)
        assert np.allclose(book.rhs_rotating(tau, d.to_rotating(tau, s, p.R_omega), p), num, atol=1e-6)


def test_steady_motions_are_equilibria_and_match_7_53():
    p = d.DamperParams(**FIG726)
    ms = dst.steady_motions(p)
    assert [m.label for m in ms] == [1, 2, 3, 4]
    for m in ms:
        assert np.abs(book.rhs_rotating(0.0, m.state(p.R_omega), p)).max() < 1e-12
        assert np.abs(rotating_form("damper", p)(m.state(p.R_omega))).max() < 1e-12
        # (7.62): xi = -(R_g^2/R^2) tg(phi) sin(psi), eta = (R_g^2/R^2) tg(phi) cos(psi)
        k = p.R_g ** 2 / p.R_omega ** 2 * math.tan(m.phi)
        assert (m.xi, m.eta) == pytest.approx((-k * math.sin(m.psi), k * math.cos(m.psi)), abs=1e-12)
    assert ms[0].kind == ms[1].kind == "main" and ms[2].kind == ms[3].kind == "side"
    assert ms[2].phi < 0 < ms[0].u and ms[1].u < 0


def test_from_physical_abd_stand_and_errors():
    # stand (7.85): M = 8.45 kg, m = 0.82 kg, omega0 = 2.87 rev/s, S = 1250 g cm
    m, M = 0.82, 8.45
    w0 = 2 * math.pi * 2.87
    c = (M + m) * w0 ** 2
    l = 0.0125 / m                                       # S = m l
    p = d.DamperParams.from_physical(M=M, c=c, omega=50 * 2 * math.pi, m=m, A=m * l * l, l=l,
                                     H1=1e-3, H2=5.0, e=0.5 * m * l / M, f=0.08, joint_radius=0.3 * l)
    assert p.R_omega == pytest.approx(17.42, abs=0.01)   # digest E0: 50 rev/s -> 17.4
    assert p.e0 == pytest.approx(0.5)
    assert p.R_m == pytest.approx(m / (M + m))
    assert p.friction.R_f == pytest.approx(0.02392, abs=1e-5)
    with pytest.raises(ValueError, match=r"A must be >= m l\^2"):
        d.DamperParams.from_physical(M=M, c=c, omega=1.0, m=m, A=0.5 * m * l * l, l=l, H1=0, H2=0, e=0)
    with pytest.raises(ValueError, match=r"omega must be >= 0 \[rad/s\]"):
        d.DamperParams.from_physical(M=M, c=c, omega=-1.0, m=m, A=m * l * l, l=l, H1=0, H2=0, e=0)
    with pytest.raises(ValueError, match="R_m must be < 1"):
        d.DamperParams(R_m=1.0, R_omega=1.0)


# --- existence (7.56) with E6, efficiency (7.54) ---------------------------------------

def test_e6_critical_speeds_table():
    table = [((0.1, 0.3, 0.5), 0.5001, 0.910, None),
             ((0.1, 0.3, 0.9), 0.5001, 0.991, (1.010, 7.066)),
             ((0.1, 0.6, 0.5), 0.0177, 0.972, (1.035, 3.863))]
    for args, es, r1, r23 in table:
        c = dst.critical_speeds_undamped(*args)
        assert round(c["e0_star"], 4) == es and round(c["R1"], 3) == r1
        if r23 is None:
            assert math.isnan(c["R2"])
        else:
            assert (round(c["R2"], 3), round(c["R3"], 3)) == r23


def test_e6_root_count_changes_at_the_critical_speeds():
    Rm, Rg, e0 = 0.1, 0.3, 0.9
    c = dst.critical_speeds_undamped(Rm, Rg, e0)
    count = lambda R: dst.steady_quartic_roots(d.DamperParams(R_m=Rm, R_omega=R, R_g=Rg, H=0.0, e0=e0)).size
    for Rc in (c["R1"], c["R2"], c["R3"]):
        assert count(Rc * 0.995) != count(Rc * 1.005)
    assert [count(R) for R in (0.5, 1.0005, 3.0, 10.0)] == [2, 4, 2, 4]


def test_efficiency_table_digest_e6():
    speeds = (0.9, 0.95, 1.0, 1.05, 1.1, 1.5, 2, 3, 5, 10)
    rows = {(0.3, 0.3): (0.700, 0.413, 0.294, 0.246, 0.229, 0.207, 0.160, 0.091, 0.038, 0.010),
            (0.05, 0.3): (2.80, 0.168, 0.052, 0.088, 0.130, 0.196, 0.157, 0.091, 0.038, 0.010),
            (0.05, 1.0): (1.46, 1.91, 0.486, 0.509, 0.607, 0.714, 0.656, 0.505, 0.291, 0.100)}
    for (H, Rg), vals in rows.items():
        for R, v in zip(speeds, vals):
            n = dst.efficiency(d.DamperParams(R_m=0.1, R_omega=R, R_g=Rg, h=0.3, H=H, e0=0.5))
            assert n == pytest.approx(v, abs=0.0051 if v < 1 else 0.011)
    p = d.DamperParams(**{**FIG726, "R_omega": 1.5})
    assert dst.efficiency_approx(p) == pytest.approx(dst.efficiency(p), rel=0.05)


# --- stability (7.63)-(7.78), E7 --------------------------------------------------------

def test_sign_rule_7_68_small_mass_weak_gravity():
    for R in (0.5, 0.8, 1.3, 2.0, 5.0):
        p = d.DamperParams(R_m=1e-4, R_omega=R, R_g=0.1, h=0.3, H=0.3, e0=0.5)
        for m in dst.steady_motions(p):
            assert dst.is_stable(p, m) == (m.u > 0), (R, m.label)
    above = d.DamperParams(R_m=1e-4, R_omega=3.0, R_g=0.1, h=0.3, H=0.3, e0=0.5)
    assert [m.label for m in dst.steady_motions(above) if dst.is_stable(above, m)] == [1]


def test_e7_fast_rotor_roots_scale_with_R_omega():
    for R in (20.0, 50.0):
        p = d.DamperParams(**{**FIG726, "R_omega": R})
        m1 = dst.steady_motions(p)[0]
        num = dst.eigenvalues(p, m1)
        pred = dst.fast_rotor_roots(p, m1.phi)            # lambda = R_omega * mu (E7)
        for lam in pred:
            assert np.min(np.abs(num - lam)) < 0.02 * max(1.0, abs(lam))
        # the printed mu = lambda / nu gives lambda = mu nu = mu / R: mu^(7/8) = -h nu +- i
        # would be a pair near +-i/R, which the Jacobian does not have (it has -h +- i R)
        printed = pred[2:4] / R ** 2
        for lam in printed:
            assert np.min(np.abs(num - lam)) > 0.5 * abs(lam)
        assert np.min(np.abs(num - complex(-p.h, R))) < 0.01 * R


# --- time domain: steady motion reached, the neutral position crossed --------------------

def test_main_motion_reached_from_nearby_start():
    p = d.DamperParams(**FIG726)
    m1 = dst.steady_motions(p)[0]
    s0 = d.state_from_angles(m1.phi + 0.2, m1.psi - 0.3, p.R_omega, xi=m1.xi, eta=m1.eta)
    sol = book.simulate(p, s0, 150.0, frame="rotating")
    assert np.abs(sol.y[:, -1] - m1.state(p.R_omega)).max() < 1e-5
    # the same in the fixed frame
    solf = book.simulate(p, d.to_fixed(0.0, s0, p.R_omega), 150.0)
    assert np.abs(d.to_rotating(150.0, solf.y[:, -1], p.R_omega) - m1.state(p.R_omega)).max() < 1e-5
    assert abs(np.linalg.norm(solf.y[4:7, -1]) - 1) < 1e-9


def test_neutral_position_crossing_planar_pendulum():
    # R_m = 0, R_omega = 0: the CW is a damped spherical pendulum; a planar swing crosses
    # phi = 0 (the Euler-angle singularity) many times.  Reference: phi'' + h phi' + R_g^2 sin phi = 0.
    Rg, h = 0.8, 0.05
    p = d.DamperParams(R_m=0.0, R_omega=0.0, R_g=Rg, h=h, H=0.1, e0=0.0)
    phi0 = 1.0
    s0 = d.state_from_angles(phi0, 0.0, 0.0)                   # offset along +y
    T = np.linspace(0, 60, 601)
    sol = book.simulate(p, s0, 60.0, t_eval=T, rtol=1e-10, atol=1e-12)
    signed = np.arctan2(sol.y[5], -sol.y[6])                   # angle in the y-z plane
    ref = solve_ivp(lambda t, y: [y[1], -h * y[1] - Rg ** 2 * math.sin(y[0])], (0, 60), [phi0, 0.0],
                    t_eval=T, rtol=1e-11, atol=1e-12)
    assert np.sign(signed[:-1] * signed[1:]).min() < 0          # crossed neutral
    assert np.count_nonzero(np.diff(np.sign(signed))) >= 10
    assert np.max(np.abs(signed - ref.y[0])) < 1e-7
    assert np.max(np.abs(sol.y[4])) < 1e-12                     # stays in its plane
    assert np.max(np.abs(np.linalg.norm(sol.y[4:7], axis=0) - 1)) < 1e-9


def test_start_exactly_at_neutral_reaches_main_motion():
    p = d.DamperParams(**FIG726)
    s0 = d.state_from_angles(0.0, 0.0, p.R_omega)              # n = -e_z: Euler-singular start
    sol = book.simulate(p, s0, 200.0, frame="rotating", rtol=1e-9, atol=1e-11)
    m1 = dst.steady_motions(p)[0]
    assert np.abs(sol.y[:, -1] - m1.state(p.R_omega)).max() < 1e-5
    assert np.all(np.isfinite(sol.y))


# --- dry friction (7.80)-(7.84), E9 -------------------------------------------------------

def test_e9_friction_residual_exact_vs_printed_cubic():
    Rf = d.R_f_cardan(0.3, 0.08)
    assert round(Rf, 4) == 0.0239
    assert Rf == pytest.approx(d.R_f_ball_joint(0.3, 0.3, math.pi / 6, 0.08))   # first branch
    s = [0.17, 0.34, 0.50, 0.67, 0.83, 0.99]
    exact = d.residual_unbalance(s, 0.1, Rf)
    assert np.round(exact, 3).tolist() == [0.034, 0.069, 0.105, 0.150, 0.200, 0.263] or \
        np.allclose(exact, [0.034, 0.068, 0.106, 0.149, 0.199, 0.263], atol=1.5e-3)
    a1 = Rf / (0.1 + Rf * 0.9)
    assert round(a1, 3) == 0.197
    printed = d.residual_cubic(s, 0.1, Rf)
    assert np.allclose(printed, [0.034, 0.070, 0.112, 0.162, 0.222, 0.296], atol=1.5e-3)
    err = np.max(np.abs(printed / exact - 1))
    assert err > 0.10                                              # not the claimed 3 %
    # Taylor a3/2: smaller but still above 3 % over s <= 1
    ss = np.linspace(0.01, 1.0, 200)
    ex = d.residual_unbalance(ss, 0.1, Rf)
    assert np.max(np.abs(d.residual_cubic(ss, 0.1, Rf, printed=False) / ex - 1)) == \
        pytest.approx(0.067, abs=0.01)
    assert np.max(np.abs(d.residual_cubic(ss, 0.1, Rf) / ex - 1)) == pytest.approx(0.128, abs=0.01)
    # ball joint, second branch: phi > theta + gamma_f = 0.603 -> large residual
    ph = 0.9
    Rf2 = d.R_f_ball_joint(ph, 0.3, math.pi / 6, 0.08)
    s2, sres2 = d.residual_parametric(ph, 0.1, Rf2)
    assert sres2 > 0.5 * s2


@pytest.mark.parametrize("factor, moves", [(0.9, False), (1.2, True)])
def test_dry_friction_band_edge_in_simulation(factor, moves):
    """Regularised Coulomb (eps = 1e-5) at R_omega = 10, R_g ~ 0: a CW released with a
    residual inside the (7.80) band stays, one outside moves back into it."""
    Rm, e0 = 0.1, 0.5
    Rf = d.R_f_cardan(0.3, 0.08)
    bound = d.residual_unbalance(e0, Rm, Rf)
    p = d.DamperParams(R_m=Rm, R_omega=10.0, R_g=0.01, h=0.3, H=0.3, e0=e0,
                       friction=d.DryFriction(R_f=Rf, eps=1e-5))
    r0 = factor * bound
    phi = math.asin(e0 - r0)                   # CW short of the balanced angle, opposite gamma = 0
    K = complex(p.R_omega ** 2 - 1, -p.H * p.R_omega)
    zeta = -Rm * p.R_omega ** 2 * r0 / K
    s0 = d.state_from_angles(phi, math.pi / 2, p.R_omega, xi=zeta.real, eta=zeta.imag)
    sol = book.simulate(p, s0, 20.0, frame="rotating", method="LSODA", rtol=1e-7, atol=1e-9,
                     t_eval=[20.0])
    r_end = d.residual_unbalance_now(sol.y[:, -1], p)
    if moves:
        assert r_end < bound < r0
        assert r_end > 0.5 * bound                 # stops inside the band, not at balance
    else:
        assert r_end == pytest.approx(r0, rel=0.02)
    # without friction it balances
    if moves:
        q = d.DamperParams(R_m=Rm, R_omega=10.0, R_g=0.01, h=0.3, H=0.3, e0=e0)
        sol = book.simulate(q, s0, 100.0, frame="rotating", t_eval=[100.0])
        assert d.residual_unbalance_now(sol.y[:, -1], q) < 0.01 * bound
