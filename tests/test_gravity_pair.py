"""Oracles for the gravity-insensitive coupled pair (book 7.1, digest ch7_ch1 sections 0, 1, 5)."""
import math

import numpy as np
import pytest

from stand.model.balancers import gravity_pair as gp
from stand.theories.weights import gravity_pair_qp as gqp
from stand.theories.weights import gravity_pair_steady as gst
from oracles import gravity_pair as book

E2 = dict(R_m=0.05, R_omega=3.0, R_rho=1.0, H=0.1, h1=0.5, h2=0.5, e0=0.5)
E3 = dict(R_m=0.02, R_omega=4.0, R_rho=1.0, H=0.05, h1=0.05, h2=0.05, e0=0.1)


# --- E1: the rotor equations need phi'' and psi'' --------------------------------

def test_e1_rotating_form_matches_fixed_frame_only_when_corrected():
    p = gp.GravityPairParams(**E2)
    rng = np.random.default_rng(1)
    for _ in range(5):
        tau = rng.uniform(0, 10)
        y = rng.normal(size=8) * [1, 3, 0.1, 0.1, 0.5, 1, 0.2, 0.2]
        yr = gp.to_rotating(tau, y, p.R_omega)
        # d/dtau of to_rotating(tau, y(tau)) by the chain rule, numerically
        h = 1e-6
        num = (gp.to_rotating(tau + h, y + h * book.rhs(tau, y, p), p.R_omega)
               - gp.to_rotating(tau - h, y - h * book.rhs(tau, y, p), p.R_omega)) / (2 * h)
        assert np.allclose(book.rhs_rotating(tau, yr, p), num, atol=1e-6)
        printed = book.rhs_rotating(tau, yr, p, printed_e1=True)
        assert np.max(np.abs(printed - num)) > 1e-3


def test_e1_energy_conserved_without_damping():
    p = gp.GravityPairParams(R_m=0.1, R_omega=2.0, R_rho=1.2, h1=0, h2=0, H=0, e0=0)
    y0 = np.array([0.7, 0.3, 0.1, -0.05, 0.4, 1.5, 0.0, 0.2])
    sol = book.simulate(p, y0, 50.0, rtol=1e-11, atol=1e-12)
    E = [gp.energy(sol.y[:, k], p) for k in range(sol.t.size)]
    assert np.ptp(E) < 1e-8 * abs(E[0])


# --- E2: length scale x l / rho1^2 --------------------------------------------------

def test_e2_length_scale_gives_classical_forced_response():
    M, m, A, l, c, H3, e = 6.24, 0.30, 0.30 * 0.02 ** 2, 0.0147, 2700.0, 10.0, 0.5e-3
    omega = 60.0
    p = gp.GravityPairParams.from_physical(M=M, c=c, omega=omega, m=m, A=A, B=A, l=l, H1=0.01,
                                           H2=0.01, H3=H3, e=e)
    Ms = M + m
    # CW on the axis (side motion of the 2nd group): the rotor alone responds
    side = [s for s in gst.steady_motions(p) if s.kind == "side-2"][0]
    x_dimensional = side.deflection / gp.GravityPairParams.length_scale(m, A, l)
    classical = M * e * omega ** 2 / abs(c - Ms * omega ** 2 + 1j * H3 * omega)
    assert x_dimensional == pytest.approx(classical, rel=1e-12)
    # the printed scale xi = x / rho1 would be off by l / rho1
    rho1 = math.sqrt(A / m)
    assert abs(side.deflection * rho1 / classical - 1) > 0.2


def test_from_physical_rejects_bad_input():
    kw = dict(M=6.24, c=2700.0, omega=60.0, m=0.3, A=1e-4, B=1e-4, l=0.0147, H1=0.01, H2=0.01,
              H3=10.0, e=1e-4)
    with pytest.raises(ValueError, match=r"c must be > 0 \[N/m\]"):
        gp.GravityPairParams.from_physical(**{**kw, "c": -1.0})
    with pytest.raises(ValueError, match=r"H3 .*N s/m"):
        gp.GravityPairParams.from_physical(**{**kw, "H3": float("nan")})
    with pytest.raises(ValueError, match="R_m must be <"):
        gp.GravityPairParams(R_m=1.2, R_omega=2)


# --- steady motions and stability (7.6)-(7.28) ---------------------------------------

def test_side_band_7_8_and_existence():
    p = gp.GravityPairParams(**E2)
    r1, r2 = gst.side_band(p)
    assert (round(r1, 3), round(r2, 3)) == (0.917, 1.090)          # digest section 5, E1
    assert r1 * r2 == pytest.approx(1.0)
    labels = lambda R: {m.label for m in gst.steady_motions(p.with_speed(R))}
    assert labels(1.0) == {1, 2, 5, 6}
    assert labels(r1 - 1e-3) == labels(r2 + 1e-3) == {1, 2, 3, 4, 5, 6}
    for m in gst.steady_motions(p.with_speed(1.5)):
        assert np.allclose(book.rhs_rotating(0.0, m.state, p.with_speed(1.5)), 0.0, atol=1e-12)


def test_stability_summary():
    p = gp.GravityPairParams(**E2)
    stab = lambda R: {m.label: gst.is_stable(p.with_speed(R), m) for m in gst.steady_motions(p.with_speed(R))}
    assert stab(3.0) == {1: True, 2: True, 3: False, 4: False, 5: False, 6: False}
    assert not any(stab(0.95).values())                  # R^(1) < R < 1: nothing stable
    low = stab(0.5)                                      # below R^(1): the heavy side (3)
    assert low[3] and not low[5] and not low[6]
    pe = gp.GravityPairParams(**{**E2, "e0": 1.5})       # capacity insufficient
    assert {m.label: gst.is_stable(pe, m) for m in gst.steady_motions(pe)} == \
        {1: True, 2: False, 3: False, 4: False}


def test_small_oscillation_frequencies_7_19():
    p = gp.GravityPairParams(R_m=0.01, R_omega=20.0, R_rho=1.0, h1=0.2, h2=0.3, H=0.1, e0=0.5)
    m1 = gst.steady_motions(p)[0]
    lam = gst.eigenvalues(p, m1)
    slow = np.sort(np.abs(lam.imag[np.abs(lam.imag) < 5]))
    pred = sorted([p.R_omega * math.sqrt(p.R_m) * math.cos(m1.phi),
                   p.R_omega * math.sqrt(p.R_m) * math.sin(m1.phi) / p.R_rho])
    assert slow[::2] == pytest.approx(pred, rel=0.03)


def test_autobalancing_simulation_digest_e2():
    p = gp.GravityPairParams(**E2)
    sol = book.simulate(p, [0.2, 0.0, 0.0, 0.0, 0.0, 3.0, 0.0, 0.0], 300.0)
    yr = gp.to_rotating(sol.t[-1], sol.y[:, -1], p.R_omega)
    assert math.sin(yr[0]) == pytest.approx(0.5, abs=1e-6)
    assert yr[1] % (2 * math.pi) == pytest.approx(math.pi / 2, abs=1e-6)
    assert math.hypot(yr[2], yr[3]) < 1e-6
    locked = p.R_m * p.R_omega ** 2 * p.e0 / math.sqrt(gqp.D(p.R_omega, p.H))
    assert round(locked, 4) == 0.0281


# --- quasi-periodic motions (7.38)-(7.46): E3, E4, E5 ----------------------------------

def test_e3_qp_amplitudes_against_simulation():
    p = gp.GravityPairParams(**E3)
    Om = gqp.qp_frequency(p)
    Ap, An = gqp.qp_amplitudes(p, Om)
    assert (round(Ap, 4), round(An, 5)) == (0.2498, 0.00213)
    lo, hi = gqp.qp_radius_range(p, Om)
    assert (round(lo, 5), round(hi, 5)) == (0.2477, 0.25196)
    # samples only where they are read (t > 800): the same integration, a third of the output
    sol = book.simulate(p, gqp.qp_initial_state(p), 1200.0, t_eval=np.arange(800, 1200, 0.01))
    slo, shi = gqp.orbit_radius_range(sol, 800.0)
    assert (round(slo, 5), round(shi, 5)) == (0.24767, 0.25199)     # digest's simulation
    assert abs(slo - lo) < 1e-4 and abs(shi - hi) < 1e-4            # corrected theory fits
    # the CW locks at phi = pi/2 and spins at Omega
    k = sol.t > 800
    assert np.mean(sol.y[5, k]) == pytest.approx(Om, abs=2e-5)
    assert np.allclose(sol.y[0, k], math.pi / 2, atol=1e-6)
    # the printed amplitudes (no Omega^2, R_omega^2) do not fit
    pAp, pAn = gqp.qp_amplitudes_printed(p, Om)
    assert abs((pAp + pAn) - shi) > 0.01
    # the shaft law (7.46) itself: nutation at R_omega, precession at Omega
    z = sol.y[2, k] + 1j * sol.y[3, k]
    t = sol.t[k]
    zth = gqp.qp_orbit(p, t, Om, gamma=0.0)
    # align the free precession phase, then compare
    ph = np.angle(np.mean(z * np.exp(-1j * Om * t)) / np.mean(zth * np.exp(-1j * Om * t)))
    zth = gqp.qp_orbit(p, t, Om, gamma=ph)
    assert np.max(np.abs(z - zth)) < 2e-3 * Ap


def test_e5_qp_frequency():
    p = gp.GravityPairParams(**E3)
    assert round(gqp.qp_frequency(p), 5) == 0.97070
    assert round(gqp.qp_frequency_approx(p), 4) == 0.9677               # corrected asymptotics
    assert round(gqp.qp_frequency_approx_printed(p), 3) == 0.918        # printed (7.42)
    assert abs(gqp.qp_frequency_approx(p) - gqp.qp_frequency(p)) < abs(
        gqp.qp_frequency_approx_printed(p) - gqp.qp_frequency(p)) / 10
    table = {2: (0.944, 1.082), 4: (0.971, 1.036), 8: (0.992, 1.011), 8.9: (0.998, 1.004)}
    for R, (o1, o2) in table.items():
        r = gqp.qp_roots(p.with_speed(R))
        near = r[(r > 0.9) & (r < 1.1)]
        assert np.round(near, 3).tolist() == [o1, o2]
    r = gqp.qp_roots(p.with_speed(9.1))
    assert not np.any((r > 0.9) & (r < 1.1))


def test_e4_qp_family_limit():
    p = gp.GravityPairParams(**E3)
    assert p.R_mH == pytest.approx(0.02)
    assert gqp.qp_family_limit(p) == pytest.approx(9.0)                 # 1 + R_mH/H^2
    R_exact, Om_star = gqp.qp_family_limit_exact(p)
    assert 8.9 < R_exact < 9.1 and abs(Om_star - 1) < 0.01
    # printed (7.41) uses R_rho, not R_rho^2: differs once R_rho != 1
    q = gp.GravityPairParams(**{**E3, "R_rho": 1.5})
    assert gqp.qp_family_limit(q) == pytest.approx(gqp.qp_family_limit_exact(q)[0], rel=0.02)
    printed = 1 + q.R_m / (q.h2 * q.H * q.R_rho)
    assert abs(printed - gqp.qp_family_limit_exact(q)[0]) > 1.0


def test_qp_family_coexists_below_and_vanishes_above_limit():
    """Span: 500 tau, not 1500.  Measured (|sin phi| - 0.1, |z|) at tau = 300 / 400 / 500 /
    600: R = 4 (4.2e-5, 2.2e-5) / (2.1e-6, 4.9e-7) / (1.8e-7, 6.1e-8) / (7.7e-9, 1.0e-8);
    R = 12 (2.1e-4, 1.6e-4) / (7.8e-5, 1.5e-5) / (1.4e-6, 1.0e-6) / (4.3e-7, 8.9e-8): a
    decay of ~10x per 100 tau, so at 500 tau the 1e-4 bounds are 70x (R = 12) and 550x
    (R = 4) above what is left, ~1e-8 at 1500 tau (the run's own error at rtol 1e-7)."""
    p = gp.GravityPairParams(**E3)
    # near-neutral synchronous start at R = 4 balances (coexistence)
    sol = book.simulate(p, [0.05, 0, 0, 0, 0, 4.0, 0, 0], 500.0, rtol=1e-7, atol=1e-9)
    yr = gp.to_rotating(sol.t[-1], sol.y[:, -1], 4.0)
    assert abs(math.sin(yr[0])) == pytest.approx(0.1, abs=1e-4) and math.hypot(yr[2], yr[3]) < 1e-4
    # above R* = 9 the precessing start also balances
    q = p.with_speed(12.0)
    sol = book.simulate(q, gqp.qp_initial_state(p), 500.0, rtol=1e-7, atol=1e-9)
    yr = gp.to_rotating(sol.t[-1], sol.y[:, -1], 12.0)
    assert abs(math.sin(yr[0])) == pytest.approx(0.1, abs=1e-4) and math.hypot(yr[2], yr[3]) < 1e-4
