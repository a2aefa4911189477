"""Two-axis pendulum CW (ch. 6): oracle table of the digest (ch6_two_axis.md section 9.2,
T1 and T3-T13) plus time-domain checks of the steady and QP theory."""
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from stand.model.balancers.two_axis import TwoAxisParams, rotating_to_fixed, fixed_to_rotating
from stand.theories.weights.two_axis_steady import (
    steady_polynomial, first_group, second_group, steady_motions, no_gravity_no_damping,
    r0, eigenvalues, max_real_part)
from stand.theories.weights.two_axis_theory import (
    char_poly_first_group, char_poly_second_group, small_mass_roots,
    fast_rotation_main_roots, fast_rotation_side_roots, R_star_omega1, fold_speeds,
    above_pivot_onset, fast_rotation_u, near_resonance_u, efficiency_approx,
    n_max_estimate, efficiency_curve, efficiency_extremum, qp_motions, qp_state,
    qp_char_poly, qp_polynomial, qp_existence_limit, qp_gravity_allows,
    qp_amplitudes)
from stand.theories.weights.one_model import rotating_form
from oracles.two_axis import (residual_rotating, residual_fixed, rhs_rotating, rhs_fixed,
                              rhs_fixed_variable_speed, linear_ramp, rhs_omega_frame)

SQH = math.sqrt(0.5)


def fig68(R_omega=3.0):
    """Digest 8.1: Fig. 6.8 set (h1 = h2 = 0.2, R_rho^2 = 0.5 chosen by the digest)."""
    return TwoAxisParams(R_m=0.1, R_omega=R_omega, R_g=0.2, R_rho=SQH, h1=0.2, h2=0.2,
                         H=0.2, e0=0.5)


def stand(R_omega=15.0, e0=0.5, H=0.05, R_gm=32.8):
    """Digest 8.3: the ch. 6 stand in dimensionless form (half-disc CW, R_m = 0.0139)."""
    return TwoAxisParams.from_R_gm(0.0139, R_gm, R_omega=R_omega, R_rho=SQH, h1=0.5,
                                   h2=0.5, H=H, e0=e0)


def by_kind(motions):
    return {m.kind: m for m in motions}


# --------------------------------------------------------------------------- model

def test_from_physical_and_errors():
    # two mathematical pendulums (Table 2.1): m = 2 m0, l = l0/sqrt2, A = 2 m0 l0^2, B = m0 l0^2
    m0, l0 = 0.125, 0.0255
    p = TwoAxisParams.from_physical(M=6.21, m=2 * m0, l=l0 / math.sqrt(2), A=2 * m0 * l0 ** 2,
                                    B=m0 * l0 ** 2, c=6.46 * (2 * math.pi * 3.3) ** 2,
                                    omega=15 * 2 * math.pi * 3.3, e=0.5 * 2 * m0 * l0
                                    / math.sqrt(2) / 6.21, H3=0.05 * 6.46 * 2 * math.pi * 3.3)
    assert p.R_rho2 == pytest.approx(0.5)
    assert p.R_omega == pytest.approx(15)
    assert p.e0 == pytest.approx(0.5)
    assert p.H == pytest.approx(0.05)
    S = 2 * m0 * l0 / math.sqrt(2)
    assert p.R_gm == pytest.approx(9.81 * 6.46 / (S * (2 * math.pi * 3.3) ** 2))
    with pytest.raises(ValueError, match="R_m"):
        TwoAxisParams(R_m=0.6, R_omega=1, R_g=0.1, R_rho=SQH)
    with pytest.raises(ValueError, match=r"H .*-"):
        TwoAxisParams(R_m=0.1, R_omega=1, R_g=0.1, H=-1)
    with pytest.raises(ValueError, match=r"A must be >= m l\^2"):
        TwoAxisParams.from_physical(M=1, m=1, l=1, A=0.5, B=1, c=1, omega=1)
    with pytest.raises(ValueError, match=r"c must be > 0 \[N/m\]"):
        TwoAxisParams.from_physical(M=1, m=1, l=1, A=1, B=1, c=0, omega=1)


def test_rhs_solves_residuals():
    rng = np.random.default_rng(1)
    p = fig68(2.3).with_(e0=0.7)
    for _ in range(5):
        y = rng.normal(size=8)
        a = rhs_rotating(0.0, y, p)[4:]
        assert np.abs(residual_rotating(y[:4], y[4:], a, p)).max() < 1e-12
        tau = rng.uniform(0, 10)
        a = rhs_fixed(tau, y, p)[4:]
        assert np.abs(residual_fixed(tau, y[:4], y[4:], a, p)).max() < 1e-12
    Y = rng.normal(size=(8, 6))          # vectorised call
    assert np.allclose(rhs_rotating(0, Y, p)[:, 2], rhs_rotating(0, Y[:, 2], p))


def test_one_model_rotating_frames_are_the_books():
    """The rotating frame of the one model equals the book's (6.12) (frame at the rotor's
    speed) and the Omega-frame form of (6.15) (6.19)-(6.22) (frame at another speed, e0 = 0)
    on random states, to rounding."""
    rng = np.random.default_rng(11)
    p = fig68(2.3).with_(e0=0.7)
    q = p.with_(e0=0.0)
    for _ in range(4):
        y = rng.normal(size=8) * [1, 3, 0.1, 0.1, 0.5, 1, 0.2, 0.2]
        assert np.allclose(rotating_form("two_axis", p)(y), rhs_rotating(0.0, y, p),
                           rtol=0, atol=1e-13)
        for Om in (0.7, 1.3):
            assert np.allclose(rotating_form("two_axis", q, frame_speed=Om)(y),
                               rhs_omega_frame(0.0, y, q, Om), rtol=0, atol=1e-13)


def test_T1_rotating_vs_fixed_frame():
    """T1: (6.12) and (6.15) trajectories agree after the map (6.13), 1e-8 rel."""
    rng = np.random.default_rng(7)
    p = fig68(2.0)
    y_rot0 = np.r_[rng.uniform(-1, 1, 2), rng.uniform(-0.05, 0.05, 2), rng.uniform(-0.3, 0.3, 4)]
    for tau in (0.0, 1.3):
        yf = rotating_to_fixed(tau, y_rot0, p.R_omega)
        assert np.allclose(fixed_to_rotating(tau, yf, p.R_omega), y_rot0, atol=1e-14)
    T = np.linspace(0, 8, 9)
    kw = dict(method="DOP853", rtol=1e-12, atol=1e-14, t_eval=T)
    s_rot = solve_ivp(rhs_rotating, (0, 8), y_rot0, args=(p,), **kw)
    s_fix = solve_ivp(rhs_fixed, (0, 8), rotating_to_fixed(0.0, y_rot0, p.R_omega),
                      args=(p,), **kw)
    mapped = rotating_to_fixed(T, s_rot.y, p.R_omega)
    scale = np.abs(s_fix.y).max(axis=1, keepdims=True)
    assert np.abs(mapped - s_fix.y).max() / scale.max() < 1e-8
    assert (np.abs(mapped - s_fix.y) / scale).max() < 1e-8


def test_variable_speed_extension():
    p = fig68(2.0)
    y = np.random.default_rng(3).normal(size=8)
    const = lambda tau: (p.R_omega * tau, p.R_omega, 0.0)
    assert np.allclose(rhs_fixed_variable_speed(0.7, y, p, const), rhs_fixed(0.7, y, p),
                       rtol=1e-13, atol=1e-13)
    ramp = linear_ramp(0.5, 3.0, 10.0, tau0=2.0)
    th, dth, ddth = ramp(7.0)
    assert dth == pytest.approx(0.5 + 2.5 * 0.5) and ddth == pytest.approx(0.25)
    assert th == pytest.approx(0.5 * 7 + 0.5 * 0.25 * 25)
    # run-down from supercritical speed: the drive torque keeps the CW following the rotor
    # (alpha' tracks theta'), the spot spiral passes through resonance without blowing up
    down = linear_ramp(3.0, 0.5, 100.0)
    q = fig68(3.0)
    y0 = rotating_to_fixed(0.0, [m for m in steady_motions(q, stability=False)
                                 if m.kind == "main_below"][0].state, 3.0)
    sol = solve_ivp(rhs_fixed_variable_speed, (0, 200), y0, args=(q, down), method="DOP853",
                    rtol=1e-8, atol=1e-10, dense_output=True)
    assert sol.success
    assert (sol.sol(200.0)[1] - sol.sol(150.0)[1]) / 50 == pytest.approx(0.5, abs=0.01)
    assert np.abs(sol.y[2] + 1j * sol.y[3]).max() < 1.0


# ------------------------------------------------------------------- steady motions

def test_T3_fig68_steady_states():
    """T3: roots u, efficiencies n, (6.25) residual < 1e-12 (digest 8.1)."""
    p = fig68()
    ms = first_group(p)
    us = sorted(m.u for m in ms)
    assert us == pytest.approx(sorted([0.8781, -0.8515, -0.0790, -0.0266]), abs=1e-4)
    n = {round(m.u, 4): m.n for m in ms}
    for u, nn in ((0.8781, 0.0432), (-0.8515, 0.0488), (-0.0790, 0.9993), (-0.0266, 2.9825)):
        assert n[u] == pytest.approx(nn, abs=1e-4)
    for m in ms + second_group(p):
        res = residual_rotating(m.state[:4], np.zeros(4), np.zeros(4), p)
        assert np.abs(res).max() < 1e-12
    k = by_kind(ms)
    assert k["main_below"].psi == pytest.approx(1.5740, abs=1e-4)
    assert k["main_above"].phi == pytest.approx(2.5897, abs=1e-4)
    assert k["side_light"].psi == pytest.approx(1.4960, abs=1e-4)
    assert k["side_heavy"].psi == pytest.approx(-1.3458, abs=1e-4)
    assert k["side_heavy"].xi == pytest.approx(-0.1631, abs=1e-4)
    assert k["side_heavy"].eta == pytest.approx(-0.0373, abs=1e-4)


def test_T4_jacobian_vs_6_91():
    """T4: eig(Jacobian) = roots of (6.91); max Re -0.0637, -0.0543, +0.614, +1.130."""
    p = fig68()
    expect = {"main_below": -0.0637, "main_above": -0.0543, "side_light": 0.614,
              "side_heavy": 1.130}
    for m in steady_motions(p):
        if m.group != 1:
            continue
        roots = np.sort_complex(np.roots(char_poly_first_group(p, m.phi)))
        assert np.abs(roots - np.sort_complex(m.eig)).max() < 1e-6
        assert m.max_re == pytest.approx(expect[m.kind], abs=1e-3)


def test_T5_second_group_always_unstable():
    """T5: b0 = -R_m^2 e0^2 R_omega^8, b8 = (1 - R_m) R_rho^2, max Re > 0; (6.111) vs Jacobian."""
    rng = np.random.default_rng(5)
    for _ in range(6):
        p = TwoAxisParams(R_m=rng.uniform(0.01, 0.3), R_omega=rng.uniform(0.3, 6),
                          R_g=rng.uniform(0.05, 1), R_rho=SQH, h1=rng.uniform(0.05, 0.5),
                          h2=rng.uniform(0.05, 0.5), H=rng.uniform(0.01, 0.3),
                          e0=rng.uniform(0.1, 1.5))
        for m in second_group(p):
            c = char_poly_second_group(p, m.below)
            assert c[-1] == pytest.approx(-p.R_m ** 2 * p.e0 ** 2 * p.R_omega ** 8, rel=1e-12)
            assert c[0] == pytest.approx((1 - p.R_m) * p.R_rho2, rel=1e-12)
            lam = eigenvalues(p, m.state)
            roots = np.roots(c)
            assert max_real_part(lam) > 0 and max_real_part(roots) > 0
            assert np.abs(np.sort_complex(roots) - np.sort_complex(lam)).max() < 1e-6 * max(
                1, np.abs(roots).max())


def test_no_gravity_no_damping_case():
    """Section 6.2.2 (6.46)-(6.51): main phi0, pi - phi0 exactly balanced; sides +-pi/2."""
    p = TwoAxisParams(R_m=0.05, R_omega=3, R_g=0.0, R_rho=SQH, h1=0.1, h2=0.1, H=0.0, e0=0.4)
    ms = no_gravity_no_damping(p)
    for m in ms:
        assert np.abs(residual_rotating(m.state[:4], np.zeros(4), np.zeros(4), p)).max() < 1e-14
    k = by_kind(ms)
    assert k["main_below"].phi == pytest.approx(math.asin(0.4))
    assert k["main_above"].phi == pytest.approx(math.pi - math.asin(0.4))
    assert k["side_heavy"].c == pytest.approx(-1) and k["side_light"].c == pytest.approx(1)
    ms = no_gravity_no_damping(p.with_(e0=1.5))
    assert [m.kind for m in ms] == ["main_light", "side_heavy"]
    with pytest.raises(ValueError, match="R_g"):
        no_gravity_no_damping(fig68())


def test_T6_fast_rotation_roots():
    """T6: R_gm = 0.4, R_omega = 20, H = 0, e0 = 0.5; (6.71) corrected (delta tg^2 phi0)."""
    p = TwoAxisParams.from_R_gm(0.05, 0.4, R_omega=20, H=0.0, e0=0.5)
    r = np.roots(steady_polynomial(p))
    u = np.sort(r.real)
    assert u == pytest.approx(np.sort([0.866357, -0.865692, -0.000665, -0.001995]), abs=1e-6)
    est = fast_rotation_u(0.4, 20, 0.5)
    assert est[:2] == pytest.approx([0.866357, -0.865692], abs=3e-6)   # corrected (6.71)
    assert est[2:] == pytest.approx([-0.000665, -0.001995], abs=1e-5)   # first order
    book = math.sqrt(0.75) + 0.4 / 400 / 0.75                               # print: delta/cos^2
    assert abs(book - 0.866357) > 5e-4


def test_T7_near_resonance():
    """T7: (6.74) at R_omega = 1, R_m = 0.05, R_g^2 = 0.2, H = 0.1, e0 = 0.5 -> |u| = 0.889953."""
    p = TwoAxisParams(R_m=0.05, R_omega=1.0, R_g=math.sqrt(0.2), H=0.1, e0=0.5)
    assert near_resonance_u(p) == pytest.approx(0.889953, abs=1e-6)
    assert sorted(abs(m.u) for m in first_group(p)) == pytest.approx([0.889953] * 2, abs=1e-6)


# ------------------------------------------------------------------------ stability

def test_T8_fast_rotation_eigenvalues():
    """T8: R_omega = 40, R_m = 2/R_omega^2, R_g^2 = 0.05, h = 0.1, H = 0.05, e0 = 0.5."""
    p = TwoAxisParams(R_m=2 / 1600, R_omega=40, R_g=math.sqrt(0.05), R_rho=SQH, h1=0.1,
                      h2=0.1, H=0.05, e0=0.5)
    k = by_kind(steady_motions(p))
    slow = lambda lam: np.sort_complex(lam[np.abs(lam.imag) < 5])
    main = slow(k["main_below"].eig)
    expect = np.sort_complex(np.array([-0.0505 + 1.2625j, -0.0505 - 1.2625j,
                                       -0.0496 + 0.9825j, -0.0496 - 0.9825j]))
    assert np.abs(main - expect).max() < 1e-3
    approx = fast_rotation_main_roots(p, k["main_below"].u)
    assert np.sort(approx.imag) == pytest.approx(np.sort(expect.imag), abs=0.01)   # (6.100)
    assert approx.real == pytest.approx([-0.05] * 4, abs=1e-3)
    heavy = slow(k["side_heavy"].eig).real
    assert sorted(heavy[heavy > 0]) == pytest.approx([1.367, 1.683], abs=1e-3)
    est = sorted(fast_rotation_side_roots(p, "side_heavy").real)[2:]   # corrected (6.102)
    assert est == pytest.approx([1.416, 1.732], abs=1e-3)
    assert est == pytest.approx(sorted(heavy[heavy > 0]), rel=0.04)
    # rotor roots (6.99) / small-mass roots (6.94)
    rot = small_mass_roots(p, k["main_below"].phi)[:4]
    fast = k["main_below"].eig[np.abs(k["main_below"].eig.imag) > 5]
    assert max(np.abs(fast - r).min() for r in rot) < 0.01
    # (6.101) corrected (R_m^{1/2})
    assert R_star_omega1(p) == pytest.approx(math.sqrt(40) / 0.75 ** 0.75)


def test_small_mass_only_below_pivot_stable():
    """(6.94)/(6.95): R_m << 1, supercritical: only phi~1 (below) stable."""
    p = TwoAxisParams.from_R_gm(0.002, 20.0, R_omega=3, R_rho=SQH, h1=0.2, h2=0.2, H=0.2,
                                e0=0.5)
    for m in steady_motions(p):
        assert m.stable == (m.kind == "main_below")
        if m.group == 1:     # (6.94): same verdict as the full Jacobian
            assert (max_real_part(small_mass_roots(p, m.phi)) < 0) == m.stable


def test_T9_efficiency_curve_stand():
    """T9: stand set R_gm = 32.8, H = 0.05, e0 = 0.5: n(1.41) = 0.892 (max),
    n(15) = 0.1385, n(10) = 0.259, min 0.732 at 1.02 (tol 2e-3)."""
    p = stand()
    Rs = [0.8, 0.95, 1.0, 1.02, 1.2, 1.41, 2, 3, 5, 7, 8.5, 10, 15, 20, 30]
    u, n = efficiency_curve(p, Rs)
    table = [1.036, 1.246, 0.861, 0.732, 0.877, 0.892, 0.861, 0.765, 0.563, 0.407, 0.322,
             0.259, 0.139, 0.084, 0.040]
    assert n == pytest.approx(table, abs=2e-3)
    assert n[Rs.index(15)] == pytest.approx(0.1385, abs=2e-3)
    Rmax, nmax = efficiency_extremum(p, 1.2, 2.0, "max")
    assert Rmax == pytest.approx(1.41, abs=0.01) and nmax == pytest.approx(0.892, abs=2e-3)
    Rmin, nmin = efficiency_extremum(p, 1.004, 1.2, "min")
    assert Rmin == pytest.approx(1.02, abs=0.005) and nmin == pytest.approx(0.732, abs=2e-3)
    assert n_max_estimate(32.8) == pytest.approx(0.891, abs=1e-3)
    # (6.114) overestimates n at large R_gm (digest 5): 0.273 vs 0.259 at R_omega = 10
    assert efficiency_approx(p.with_(R_omega=10)) == pytest.approx(0.273, abs=2e-3)


def test_T10_onset_above_pivot():
    """T10 / key finding 4.4: the stable above-pivot main motion is born at the fold R_omega3
    of (6.62) (12.03, 18.33, 10.09), not at (6.101)."""
    for R_gm, e0, expect in ((32.8, 0.5, 12.03), (32.8, 0.7, 18.33), (10.0, 0.7, 10.09)):
        p = stand(e0=e0, R_gm=R_gm)
        onset = above_pivot_onset(p, step=0.5, tol=1e-3)
        R3 = fold_speeds(R_gm, e0)[2]
        assert R3 == pytest.approx(expect, abs=0.01)
        assert onset == pytest.approx(expect, abs=0.05)
        assert R_star_omega1(p) < onset - 2
    r1, r2, r3 = fold_speeds(32.8, 0.5)
    assert (r1, r2) == pytest.approx((0.9966, 1.0035), abs=1e-4)
    assert math.isnan(fold_speeds(0.4, 0.5)[2])       # (6.66): needs R_gm > 4 c3


# ----------------------------------------------------------- time domain: steady motions

def test_T11_time_simulation_converges_to_main_below():
    """T11 (digest 8.5): stand set, R_omega = 15, from phi = 0.05, psi = 2, rotor at the
    no-ABP deflection -> phi 0.4453, psi 1.5713, r/r0 0.1386 (tol 1e-3).

    Span: the slowest mode of main_below decays at Re = -H/2 = -0.025 (asserted below); the
    distance is 8.5e-4 at tau = 50, so e^{-0.025 * 250} = 1.9e-3 of it is left at tau = 300
    (measured 4e-6), 25x inside the 1e-4 bound (tau 400 before: 3e-7)."""
    p = stand()
    sg = second_group(p)[0]
    y0 = np.array([0.05, 2.0, sg.xi, sg.eta, 0, 0, 0, 0])
    mb = by_kind(steady_motions(p))["main_below"]
    assert max(e.real for e in mb.eig) == pytest.approx(-p.H / 2, abs=1e-4)
    sol = solve_ivp(rhs_rotating, (0, 300), y0, args=(p,), method="DOP853", rtol=1e-8,
                    atol=1e-10)
    y = sol.y[:, -1]
    assert y[0] == pytest.approx(0.4453, abs=1e-3)
    assert y[1] == pytest.approx(1.5713, abs=1e-3)
    assert math.hypot(y[2], y[3]) / r0(p) == pytest.approx(0.1386, abs=1e-3)
    assert mb.stable and mb.distance(y) < 1e-4


def test_leaves_unstable_side_motion():
    """Start next to the unstable heavy-side motion (Fig. 6.8 set, R_omega = 3, max Re
    +1.13): the CW leaves it and settles on a stable main motion."""
    p = fig68()
    k = by_kind(steady_motions(p))
    y0 = k["side_heavy"].state + 1e-6 * np.array([1, -1, 0, 0, 0, 0, 0, 0])
    sol = solve_ivp(rhs_rotating, (0, 300), y0, args=(p,), method="DOP853", rtol=1e-9,
                    atol=1e-11, dense_output=True)
    early = sol.sol(15.0)
    assert np.abs(early[:2] - y0[:2]).max() > 1e-2        # departed (growth e^{1.13 tau})
    dist = {kk: m.distance(sol.y[:, -1]) for kk, m in k.items()}
    end = min(dist, key=dist.get)
    assert end in ("main_below", "main_above") and dist[end] < 1e-6
    assert k[end].stable


# ----------------------------------------------------------------------- QP motions

def test_T12_qp_no_gravity():
    """T12 (digest 8.7): kappa = 0.1; Omega1(3) = 0.9205, Omega1(8) = 0.9726 stable;
    the family ends near 1 + kappa/H^2 = 11; the Omega = 1 family is unstable."""
    p = TwoAxisParams(R_m=0.05, R_omega=3, R_g=0.0, R_rho=SQH, h1=0.1, h2=0.1, H=0.1, e0=0.0)
    assert p.kappa == pytest.approx(0.1)
    assert qp_existence_limit(p) == pytest.approx(11.0)
    for R, Om in ((3, 0.9205), (8, 0.9726)):
        q = p.with_(R_omega=R)
        ms = qp_motions(q)
        st = [m for m in ms if m.stable]
        assert len(st) == 1 and st[0].Omega == pytest.approx(Om, abs=1e-4)
        assert st[0].phi == pytest.approx(math.pi / 2)
        assert all(not m.stable for m in ms if m.family == "omega1") and any(
            m.family == "omega1" for m in ms)
        for m in ms:   # (6.178) with (6.176) vs Omega-frame Jacobian; neutral phase
            roots = np.sort_complex(np.roots(qp_char_poly(q, m.Omega, m.phi)))
            assert np.abs(roots - np.sort_complex(m.eig)).max() < 1e-6
            assert np.abs(m.eig).min() < 1e-6
            assert np.abs(rhs_omega_frame(0.0, qp_state(q, m.Omega, m.phi), q, m.Omega)).max() < 1e-12
            one = rotating_form("two_axis", q, frame_speed=m.Omega)
            assert np.abs(one(qp_state(q, m.Omega, m.phi))).max() < 1e-12
    grid = np.arange(9.0, 13.01, 0.1)
    alive = [R for R in grid if any(m.Omega < 1 for m in qp_motions(p.with_(R_omega=R),
                                                                    stability=False))]
    assert max(alive) == pytest.approx(11.0, abs=0.3)


def test_T13_qp_with_gravity_and_time_domain():
    """T13 (digest 8.6): stand with H = 0.005, R_omega = 2: Omega = 0.99339, phi = 1.0389
    stable; a fixed-frame run started on it keeps alpha' -> 0.99338 (tol 1e-4)."""
    p = stand(R_omega=2.0, e0=0.02, H=0.005)
    ms = qp_motions(p)
    st = [m for m in ms if m.stable]
    assert len(st) == 1
    m = st[0]
    assert m.Omega == pytest.approx(0.99339, abs=1e-4)
    # digest prints 1.0389; the exact (6.123) root for R_gm = 32.8 is 1.03901 (see report)
    assert m.phi == pytest.approx(1.0389, abs=2e-4)
    assert sorted(x.Omega for x in ms) == pytest.approx([0.99339, 0.99956, 1.00044, 1.00690],
                                                        abs=1e-5)
    for x in ms:
        roots = np.sort_complex(np.roots(qp_char_poly(p.with_(e0=0), x.Omega, x.phi)))
        assert np.abs(roots - np.sort_complex(x.eig)).max() < 1e-6
    # (6.145) corrected polynomial has the same roots
    b = qp_polynomial(p)
    for x in ms:
        assert abs(np.polynomial.polynomial.polyval(x.Omega, b)) < 1e-8 * np.abs(b).max()
    Ap, An = qp_amplitudes(p, m.Omega, m.phi)
    assert (Ap, An) == pytest.approx((0.8392, 0.00037), abs=1e-4)
    # time domain in the fixed frame (6.15), with e0 = 0.02, started on the QP state
    q = complex(*qp_state(p, m.Omega, m.phi)[2:4])
    dz = 1j * m.Omega * q
    y0 = np.array([m.phi, 0.0, q.real, q.imag, 0.0, m.Omega, dz.real, dz.imag])
    sol = solve_ivp(rhs_fixed, (0, 600), y0, args=(p,), method="DOP853", rtol=1e-9,
                    atol=1e-11, dense_output=True)
    tt = np.linspace(300, 600, 20001)
    Y = sol.sol(tt)
    rate = (Y[1, -1] - Y[1, 0]) / (tt[-1] - tt[0])
    assert rate == pytest.approx(0.99338, abs=1e-4)
    r = np.abs(Y[2] + 1j * Y[3])
    assert r.min() > Ap - An - 1e-3 and r.max() < Ap + An + 1e-3


def test_qp_gravity_suppression():
    """Digest 6.3 / T14 spot check: stand with H = 0.05 (2 H R_gm > 1): no Omega < 1 QP."""
    p = stand(H=0.05, e0=0.0)
    assert not qp_gravity_allows(p)
    for R in (0.9, 1.5, 3.0, 8.0):
        assert not [m for m in qp_motions(p.with_(R_omega=R), stability=False) if m.Omega < 1]
    assert qp_gravity_allows(stand(H=0.005))
