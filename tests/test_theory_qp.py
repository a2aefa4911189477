"""Quasi-periodic (stuck-ball) motions: frequency equation, thresholds, stability, spot.

Oracles: digest ch5 section 5 (Tables 5.1-A and 5.1-B, asymptotics (5.185),
(5.186), (5.204), stability (5.210)-(5.216) and its Jacobian check, laser-spot
law (5.237)) and tests T7, T8, T11 of section 8.3.
"""
import math
import warnings

import numpy as np
import pytest

from stand.model.planar import COAST_T0, build_planar_model, rhs_planar
from stand.theories.rotating import constant_speed_programme
from stand.scene.model import RunSettings, SpeedDrive
from stand.scene.parse import scene_from_dimensionless
from stand.theories.planar.qp import (QPWarning, dspeed_dOmega, epitrochoid, escape_speed,
                             frequency_polynomial, qp_roots, qp_stability, qp_thresholds,
                             speed_of_precession, spot_law)

from _helpers import match_roots

EX = dict(Rt=0.01, h=0.05, H=0.05)       # the digest's example, R_mH = 0.01, R* = 9


def roots(R, Rt=0.01, h=0.05, H=0.05):
    return qp_roots(R, Rt, h, H)


def _half_unit(printed: str) -> float:
    """Half a unit of the last printed digit (plus float slack)."""
    dec = len(printed.split(".")[1]) if "." in printed else 0
    return 0.5 * 10.0 ** -dec + 1e-9


def brute_brackets(R, Rt, h, H, n=40001):
    """Sign changes of R(Omega) - R on a dense grid over (0, R] (brute force)."""
    g = np.concatenate([np.linspace(0.0, R, n)[1:], 1 + np.linspace(-0.5, 0.5, n) * min(1.0, 40 * H),
                        1 + np.geomspace(1e-13, 1.2, 4000), 1 - np.geomspace(1e-13, 0.99, 4000)])
    g = np.unique(g[(g > 0) & (g <= R)])
    f = speed_of_precession(g, Rt, h, H) - R
    i = np.nonzero(np.sign(f[:-1]) != np.sign(f[1:]))[0]
    return list(zip(g[i], g[i + 1]))


def check_against_brute(R, Rt, h, H):
    r = qp_roots(R, Rt, h, H)
    br = brute_brackets(R, Rt, h, H)
    assert len(r) >= len(br)
    for a, b in br:          # every brute-force bracket holds a returned root
        assert np.any((r >= a) & (r <= b)), (R, Rt, h, H, r, (a, b))
    # every returned root solves the equation
    if r.size:
        res = speed_of_precession(r, Rt, h, H) - R
        slope = np.abs(dspeed_dOmega(r, Rt, h, H))
        assert np.all(np.abs(res) <= 1e-12 * R + 8e-16 * slope * r), res
    return r


# ---------------------------------------------------------------------------
# T7: roots and thresholds
# ---------------------------------------------------------------------------

TABLE_B = {
    "0.5": ["0.49891"], "0.9": ["0.82559"], "1.2": ["0.8988"],
    "1.5": ["0.92418", "1.16104", "1.37761"], "2": ["0.94376", "1.08242", "1.92792"],
    "3": ["0.96135", "1.04953", "2.92502"], "5": ["0.97715", "1.02759", "4.89343"],
    "7": ["0.98689", "1.01598", "6.85685"], "10": ["9.79986"],
}


@pytest.mark.parametrize("R", list(TABLE_B))
def test_T7_table_5_1_B(R):
    r = roots(float(R))
    printed = TABLE_B[R]
    assert len(r) == len(printed)
    for x, p in zip(r, printed):
        assert abs(x - float(p)) < 1e-4
        assert abs(x - float(p)) <= _half_unit(p)      # agrees to the printed digits


@pytest.mark.parametrize("R, printed", [(3.0, [0.91222, 1.15146, 2.64031]),
                                        (10.0, [0.95837, 1.05264, 9.07052])])
def test_T7_RmH_005_rows(R, printed):
    r = qp_roots(R, 0.01, 0.01, 0.05)               # R_mH = 0.05, R* = 41
    assert r == pytest.approx(printed, abs=6e-6)


TABLE_A = [  # R_mH, H, one->three exact, (5.191), three->one exact, (5.201), R*
    (0.01, 0.05, "1.44019", "1.3232", "9.01222", "9.0112", "9.0000"),
    (0.05, 0.05, "1.97478", "1.5526", "41.05727", "41.0562", "41.0000"),
    (0.001, 0.02, "1.17177", "1.1500", "6.00128", "6.0011", "6.0000"),
    (0.0099, 0.1, "1.43035", "1.3221", "2.99530", "2.9911", "2.9800"),
]


@pytest.mark.parametrize("row", TABLE_A, ids=lambda r: f"RmH={r[0]},H={r[1]}")
def test_T7_table_5_1_A(row):
    RmH, H, up, a1, down, a2, esc = row
    h = 0.07
    Rt = RmH * h / H
    t = qp_thresholds(Rt, h, H)
    assert t.RmH == pytest.approx(RmH, rel=1e-14)
    for val, p in [(t.one_to_three, up), (t.three_to_one, down)]:
        assert abs(val - float(p)) < 1e-4 and abs(val - float(p)) <= _half_unit(p)
    for val, p in [(t.approx_one_to_three, a1), (t.approx_three_to_one, a2), (t.escape, esc)]:
        assert abs(val - float(p)) <= _half_unit(p)
    assert t.escape == pytest.approx(escape_speed(Rt, h, H)) == pytest.approx(1 + 2 * RmH / H**2)
    # the thresholds are the extrema of R(Omega): double roots there
    assert t.Omega_extrema.size == 2
    assert t.R_extrema == pytest.approx([t.three_to_one, t.one_to_three], rel=1e-15)
    assert dspeed_dOmega(t.Omega_extrema, Rt, h, H) == pytest.approx([0, 0], abs=1e-6)
    assert [t.Omega_three_to_one, t.Omega_one_to_three] == list(t.Omega_extrema)
    # the root count switches exactly there (+-1e-9 relative)
    for thr, below, above in [(t.one_to_three, 1, 3), (t.three_to_one, 3, 1)]:
        assert len(qp_roots(thr * (1 - 1e-9), Rt, h, H)) == below
        assert len(qp_roots(thr * (1 + 1e-9), Rt, h, H)) == above


@pytest.mark.parametrize("RmH, H", [(r[0], r[1]) for r in TABLE_A])
def test_T7_Omega1_is_one_at_escape_speed(RmH, H):
    Rt, h = RmH, H
    Rs = escape_speed(Rt, h, H)
    P = np.poly1d(frequency_polynomial(Rs, Rt, h, H))
    assert abs(P(1.0)) < 1e-12 * Rs                 # P(1) = 2 R_mH - H^2 (R - 1) = 0
    r = qp_roots(Rs, Rt, h, H)
    assert len(r) == 3
    assert abs(r[0] - 1.0) < 1e-9
    assert speed_of_precession(1.0, Rt, h, H) == pytest.approx(Rs, rel=1e-15)


def test_T7_summary_orderings():
    t = qp_thresholds(**EX)
    r = roots(5.0)                                    # R*_w1 < R < R*: 0 < O1 < 1 < O2 < O3 < R
    assert 0 < r[0] < 1 < r[1] < r[2] < 5.0
    r = roots(9.005)                                  # R* < R < R*_w2: 1 < O1 < O2 << O3
    assert 1 < r[0] < r[1] < 1.1 < 8 < r[2]
    assert len(roots(t.three_to_one + 1e-6)) == 1


def test_agrees_with_np_roots_when_well_conditioned():
    for Rt, h, H in [(0.01, 0.05, 0.05), (0.01, 0.01, 0.05), (0.1, 0.3, 0.2), (0.2, 0.5, 1.0)]:
        for R in [0.3, 0.8, 1.3, 2.0, 3.0, 6.0, 12.0]:
            P = frequency_polynomial(R, Rt, h, H)
            z = np.roots(P)
            ref = np.sort(z[np.abs(z.imag) < 1e-9].real)
            ref = ref[(ref > 0) & (ref < R)]
            assert qp_roots(R, Rt, h, H) == pytest.approx(ref, rel=1e-9, abs=1e-12)


def test_derivative_and_monotonic_outside_the_extremum_window():
    Rt, h, H = 0.01, 0.05, 0.05
    w = np.linspace(0.01, 4.0, 4001)
    d = dspeed_dOmega(w, Rt, h, H)
    fd = (speed_of_precession(w + 1e-7, Rt, h, H) - speed_of_precession(w - 1e-7, Rt, h, H)) / 2e-7
    assert d == pytest.approx(fd, rel=1e-5, abs=1e-5)
    neg = w[d < 0]
    assert neg.min() > 1.0 and neg.max() < math.sqrt(5.0)   # extrema only in (1, sqrt 5)
    # H > 0.7136: no window, always one root
    assert qp_thresholds(0.4, 0.01, 0.72).one_to_three is None
    assert np.all(dspeed_dOmega(np.linspace(0, 5, 2001), 0.4, 0.01, 0.72) > 0)


# asymptotics ----------------------------------------------------------------

def test_asymptotic_5_185_slow_rotor():
    RmH, H = 0.01, 0.05
    for R in [0.03, 0.06, 0.1]:
        (W,) = qp_roots(R, RmH, H, H)             # Rt = R_mH when h = H
        err = W - R * (1 - 2 * RmH * R**4)
        lead = -2 * RmH * (2 - H**2) * R**7          # the neglected term of 1/D(R)
        assert err == pytest.approx(lead, rel=0.05)


def test_asymptotic_5_186_fast_rotor():
    RmH, H = 0.01, 0.05
    W = qp_roots(200.0, RmH, H, H)
    assert len(W) == 1 and round(W[0], 3) == 196.078
    for R in [50.0, 200.0, 1000.0]:
        (W,) = qp_roots(R, RmH, H, H)
        err = W - R / (1 + 2 * RmH)
        lead = -2 * RmH * (2 - H**2) / R / (1 + 2 * RmH)   # next term of 2 R_mH W^5 / D
        assert err == pytest.approx(lead, rel=0.05)


def test_asymptotic_5_204_small_RmH():
    H, R = 0.05, 3.0
    D = lambda w: (1 - w * w) ** 2 + H * H * w * w
    g = lambda w: 2 * w**5 / D(w)
    dg = lambda w: (g(w + 1e-6) - g(w - 1e-6)) / 2e-6
    for RmH in [1e-4, 1e-5, 1e-6]:
        W = qp_roots(R, RmH, H, H)[-1]                 # the root near R
        err = W - (R - RmH * g(R))                       # (5.204)
        assert err == pytest.approx(RmH**2 * g(R) * dg(R), rel=0.05)   # next Newton term


# ---------------------------------------------------------------------------
# T8: stability
# ---------------------------------------------------------------------------

def _omega_frame_rhs(model, R, W):
    """d/dtau of the state [u, v, a_1..a_n, u', v', a_1'..a_n'] in a frame turning at W.

    Built from the fixed-frame :func:`stand.model.planar.rhs_planar` at tau = 0, where
    the frame, the rotor (constant speed R) and the fixed axes coincide; with
    e0 = 0 the system is autonomous in this frame.
    """
    n = model.n
    nq = 2 + n
    sp = model.sp.copy()
    sp[COAST_T0] = np.inf
    prog = constant_speed_programme(R)

    def f(z):
        y = np.array(z, dtype=float)
        y[nq] = z[nq] - W * z[1]              # xi' = u' - W v
        y[nq + 1] = z[nq + 1] + W * z[0]      # eta' = v' + W u
        y[nq + 2:] = z[nq + 2:] + W - R       # relative to the rotor
        dy = np.empty_like(y)
        rhs_planar(0.0, y, dy, sp, model.wt, prog)
        out = dy.copy()
        out[:nq] = z[nq:]
        out[nq] = dy[nq] + 2 * W * z[nq + 1] + W * W * z[0]
        out[nq + 1] = dy[nq + 1] - 2 * W * z[nq] + W * W * z[1]
        return out
    return f


def _jacobian_eigs(R, W, Rt, h, H, gamma=0.4):
    sc = scene_from_dimensionless(2, Rt, h, H, 0.0, drive=SpeedDrive(np.array([[0.0, R]])),
                                  run=RunSettings(1.0, 1.0))
    f = _omega_frame_rhs(build_planar_model(sc), R, W)
    s = W * W * np.exp(1j * gamma) / (1 - W * W + 1j * H * W)
    z = np.array([s.real, s.imag, gamma, gamma, 0, 0, 0, 0])
    assert np.max(np.abs(f(z))) < 1e-12            # the QP motion is an equilibrium
    J = np.empty((8, 8))
    for i in range(8):
        dz = np.zeros(8)
        dz[i] = 1e-6
        J[:, i] = (f(z + dz) - f(z - dz)) / 2e-6
    return np.linalg.eigvals(J)


def test_T8_digest_example_roots():
    W1 = roots(3.0)[0]
    s = qp_stability(W1, 3.0, **EX)
    assert s.stable and s.abscissa < 0
    match_roots(s.collective_roots, [-0.02514 + 1.96243j, -0.02514 - 1.96243j, -0.02842 + 0.4462j,
                                   -0.02842 - 0.4462j, -0.04492], 1e-5)
    match_roots(s.relative_roots, [-0.025 + 0.40014j, -0.025 - 0.40014j], 1e-5)
    assert abs(s.residual) < 1e-12


def test_T8_roots_equal_omega_frame_jacobian_eigenvalues():
    R = 3.0
    for W in roots(R):
        s = qp_stability(W, R, **EX)
        ev = _jacobian_eigs(R, W, **EX)
        rest = match_roots(ev, np.concatenate([s.collective_roots, s.relative_roots]), 1e-7)
        assert rest == pytest.approx([0.0], abs=1e-7)     # the family in gamma


def test_T8_unstable_branches_digest_numbers():
    W1, W2, W3 = roots(3.0)
    s2 = qp_stability(W2, 3.0, **EX)
    assert round(W2, 4) == 1.0495 and not s2.stable
    assert round(max(s2.relative_roots.real), 2) == 0.41
    assert round(max(s2.collective_roots.real), 3) == 0.367
    s3 = qp_stability(W3, 3.0, **EX)
    assert round(W3, 3) == 2.925 and not s3.stable
    assert round(max(s3.relative_roots.real), 3) == 0.416
    assert max(s3.collective_roots.real) < 0      # only the relative mode is unstable


@pytest.mark.parametrize("Rt, h, H", [(0.01, 0.05, 0.05), (0.01, 0.01, 0.05)])
def test_T8_stable_iff_below_resonance(Rt, h, H):
    for R in [0.5, 0.9, 1.2, 1.5, 2.0, 3.0, 5.0, 7.0, 8.9, 10.0, 30.0]:
        for W in qp_roots(R, Rt, h, H):
            s = qp_stability(W, R, Rt, h, H)
            assert s.stable == (W < 1.0), (R, W, s.abscissa)


def test_stability_warns_for_a_non_root_and_n1():
    with pytest.warns(QPWarning, match="not a QP root"):
        qp_stability(0.5, 3.0, **EX)
    s = qp_stability(roots(3.0)[0], 3.0, **EX, n=1)
    assert s.relative_roots.size == 0 and s.collective_roots.size == 5


# ---------------------------------------------------------------------------
# laser spot (5.237) and T11
# ---------------------------------------------------------------------------

def test_spot_law_time_domain_example():
    W = roots(3.0)[0]
    s = spot_law(W, 3.0, 0.3, 0.05, R_m=0.02)
    assert round(s.A_P, 3) == 10.297 and round(s.A_N, 3) == 0.337
    assert s.A_P_l == pytest.approx(0.02 * s.A_P) and s.A_N_l == pytest.approx(0.02 * s.A_N)
    assert s.k == pytest.approx(3.1206, abs=1e-4) and s.petals is None and s.period == math.inf
    # the phases reproduce the zero-order solution (5.229), corrected denominator
    tau, gam = np.linspace(0, 40, 500), 0.7
    s = spot_law(W, 3.0, 0.3, 0.05, gamma=gam)
    z = (W**2 * np.exp(1j * (W * tau + gam)) / (1 - W**2 + 0.05j * W)
         + 0.3 * 9 * np.exp(3j * tau) / (1 - 9 + 0.15j))
    Z = epitrochoid(s.A_P, s.A_N, W, 3.0, tau, s.phase_P, s.phase_N)
    assert np.max(np.abs(Z - z)) < 1e-12
    D = (1 - W**2) ** 2 + 0.0025 * W**2
    assert math.cos(s.gamma1) == pytest.approx((1 - W**2) / math.sqrt(D))
    assert math.sin(s.gamma2) == pytest.approx(0.15 / math.sqrt(64 + 0.0225))


def _turning(Z_prime):
    """Winding number of the velocity over the sampled closed curve."""
    a = np.unwrap(np.angle(Z_prime))
    return (a[-1] - a[0]) / (2 * np.pi)


def _maxima_of_modulus(Z):
    m = np.abs(Z)
    return int(np.count_nonzero((m > np.roll(m, 1)) & (m > np.roll(m, -1))))


@pytest.mark.parametrize("k", [2, 3, 4, 6])
@pytest.mark.parametrize("ratio", [3.0, 0.3])        # curtate, prolate
def test_T11_integer_k_closed_with_k_minus_1_petals(k, ratio):
    W = 0.8
    R = k * W
    AP = 1.0
    AN = AP * W / (R * ratio)
    T = 2 * np.pi / W
    t = np.linspace(0, T, 6000, endpoint=False)
    Z = epitrochoid(AP, AN, W, R, t, 0.3, -1.1)
    assert np.max(np.abs(epitrochoid(AP, AN, W, R, t + T, 0.3, -1.1) - Z)) < 1e-12
    assert _maxima_of_modulus(Z) == k - 1
    tt = np.linspace(0, T, 20001)
    V = 1j * W * AP * np.exp(1j * (W * tt + 0.3)) + 1j * R * AN * np.exp(1j * (R * tt - 1.1))
    loops = round(_turning(V)) - 1
    assert loops == (k - 1 if ratio < 1 else 0)       # prolate: one loop per petal
    e0 = AN / (R * R / math.sqrt((1 - R * R) ** 2 + 0.0025 * R * R))
    s = spot_law(W, R, e0, 0.05, shape_rtol=1e-9)
    # spot_law's own A_P differs; only k, petals and period are compared here
    assert s.p == k and s.q == 1 and s.petals == k - 1 and s.period == pytest.approx(T)


@pytest.mark.parametrize("p, q", [(7, 2), (10, 3), (13, 4), (11, 5)])
def test_T11_rational_closes_after_q_turns(p, q):
    W = 0.9
    R = W * p / q
    AP, AN = 1.0, 0.4
    t = np.linspace(0, 2 * np.pi / W, 997)
    Z = epitrochoid(AP, AN, W, R, t)
    Tq = 2 * np.pi * q / W
    assert np.max(np.abs(epitrochoid(AP, AN, W, R, t + Tq) - Z)) < 1e-11
    for j in range(1, q):                         # not closed after fewer turns
        assert np.max(np.abs(epitrochoid(AP, AN, W, R, t + 2 * np.pi * j / W) - Z)) > 1e-2
    for frac in [0.25, 0.5, 0.9]:                 # nor at any other shift shorter than Tq
        assert np.max(np.abs(epitrochoid(AP, AN, W, R, t + frac * Tq) - Z)) > 1e-2
    tt = np.linspace(0, Tq, 40000, endpoint=False)
    assert _maxima_of_modulus(epitrochoid(AP, AN, W, R, tt)) == p - q
    s = spot_law(W, R, 0.1, 0.05)
    assert (s.p, s.q, s.petals) == (p, q, p - q) and s.period == pytest.approx(Tq)


def test_T11_irrational_ratio_never_closes():
    s = spot_law(1.0, math.pi, 0.1, 0.05)
    assert s.p is None and s.petals is None and s.period == math.inf


def test_T11_shape_switches_at_AP_W_equals_AN_R():
    W, R, H = 0.9, 3.6, 0.05                       # k = 4
    DR = (1 - R * R) ** 2 + H * H * R * R
    AP = W * W / math.sqrt((1 - W * W) ** 2 + H * H * W * W)
    e0c = AP * W / R / (R * R / math.sqrt(DR))     # A_P W = A_N R
    shapes = {f: spot_law(W, R, e0c * f, H).shape for f in [0.9, 1.0, 1.1]}
    assert shapes == {0.9: "curtate", 1.0: "normal", 1.1: "prolate"}
    T = 2 * np.pi / W
    tt = np.linspace(0, T, 40001)
    for f, loops in [(0.98, 0), (1.02, 3)]:
        s = spot_law(W, R, e0c * f, H)
        V = 1j * W * s.A_P * np.exp(1j * W * tt) + 1j * R * s.A_N * np.exp(1j * R * tt)
        assert round(_turning(V)) - 1 == loops
    s = spot_law(W, R, e0c, H)                     # normal: cusps, the velocity vanishes
    V = 1j * W * s.A_P * np.exp(1j * W * tt) + 1j * R * s.A_N * np.exp(1j * R * tt)
    assert np.min(np.abs(V)) < 1e-3 * W * s.A_P
    assert spot_law(W, R, 0.0, H).shape == "curtate"   # e0 = 0: a circle


def test_spot_amplitude_limits_5_244_5_246():
    H = 0.05
    assert spot_law(1.0, 9.0, 0.0, H).A_P == pytest.approx(1 / H)
    assert spot_law(0.9, 1e4, 0.3, H).A_N == pytest.approx(0.3, rel=1e-6)
    w = np.linspace(0.01, 0.999, 500)
    AP = [spot_law(x, 3.0, 0.1, H).A_P for x in w]
    assert np.all(np.diff(AP) > 0)                 # monotonic on (0, 1)


# ---------------------------------------------------------------------------
# robustness
# ---------------------------------------------------------------------------

@pytest.mark.parametrize("Rt, h, H", [(0.01, 0.05, 0.05), (0.01, 1e-6, 0.05), (0.01, 0.05, 1e-6),
                                      (0.01, 1e-6, 1e-6), (0.3, 0.02, 0.3), (1e-5, 0.05, 0.01)])
def test_threshold_switch_is_exact(Rt, h, H):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        t = qp_thresholds(Rt, h, H)
        for thr, below, above in [(t.one_to_three, 1, 3), (t.three_to_one, 3, 1)]:
            lo = check_against_brute(thr * (1 - 1e-9), Rt, h, H)
            hi = check_against_brute(thr * (1 + 1e-9), Rt, h, H)
            assert (len(lo), len(hi)) == (below, above)


def test_nearly_double_roots_are_found():
    t = qp_thresholds(**EX)
    for thr, Wd in [(t.one_to_three, t.Omega_one_to_three), (t.three_to_one, t.Omega_three_to_one)]:
        for d in [1e-6, 1e-10, 1e-13]:
            R = thr * (1 + d) if thr == t.one_to_three else thr * (1 - d)
            r = roots(R)
            assert len(r) == 3
            near = r[np.abs(r - Wd) < 1e-2]
            assert len(near) == 2 and near[0] < Wd < near[1]
    # a pair of extrema just past the cusp (5.202): the three roots lie in a 1e-4 window
    H, h = 0.1, 1.0
    RmH = 0.00043576434687699 * (1 + 1e-6)
    t = qp_thresholds(RmH * h / H, h, H)
    assert t.Omega_extrema.size == 2 and np.diff(t.Omega_extrema)[0] < 1e-4
    r = qp_roots(0.5 * (t.one_to_three + t.three_to_one), RmH * h / H, h, H)
    assert len(r) == 3 and r[-1] - r[0] < 2e-4


def test_small_h_and_small_H():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        r = check_against_brute(3.0, 0.01, 1e-6, 0.05)       # R_mH = 500: (5.203) regime
        assert len(r) == 1 and r[0] == pytest.approx((3.0 / 1000) ** 0.2, rel=0.1)
        r = check_against_brute(3.0, 0.01, 0.05, 1e-6)       # R* = 4e5, sharp resonance
        a = math.sqrt(0.01 * 1e-6 / 0.05 / (2 * (3 - 1)))   # (5.187)
        assert r[:2] == pytest.approx([1 - a, 1 + a], rel=1e-6) and r[2] == pytest.approx(3.0)
        t = qp_thresholds(0.01, 0.05, 1e-6)
        assert t.three_to_one == pytest.approx(t.approx_three_to_one, rel=1e-12)
        assert t.one_to_three == pytest.approx(t.approx_one_to_three, rel=0.02)
        for R in [1e5, 4e5, 4.1e5]:
            check_against_brute(R, 0.01, 0.05, 1e-6)


def test_random_parameters_against_brute_force():
    rng = np.random.default_rng(7)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for _ in range(40):
            Rt = 10 ** rng.uniform(-4, math.log10(0.45))
            h = 10 ** rng.uniform(-3, 0.5)
            H = 10 ** rng.uniform(-3, 0)
            for R in 10 ** rng.uniform(-1, 1.5, 2):
                check_against_brute(R, Rt, h, H)


def test_degenerate_inputs():
    with pytest.warns(QPWarning, match="h = 0"):
        assert qp_roots(3.0, 0.01, 0.0, 0.05).size == 0
    with pytest.warns(QPWarning, match="neutral"):
        assert qp_roots(3.0, 0.0, 0.0, 0.05).size == 0
    with pytest.warns(QPWarning, match="H = 0"):
        assert list(qp_roots(3.0, 0.01, 0.05, 0.0)) == [1.0, 1.0, 3.0]
    with pytest.warns(QPWarning, match="H = 0"):
        assert list(qp_roots(0.7, 0.01, 0.05, 0.0)) == [0.7]
    # H -> 0+ approaches those limits
    assert qp_roots(3.0, 0.01, 0.05, 1e-9) == pytest.approx([1, 1, 3], abs=1e-5)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert list(qp_roots(2.5, 0.0, 0.05, 0.05)) == [2.5]       # Rt = 0: carried along
        assert qp_roots(0.0, 0.01, 0.05, 0.05).size == 0
        assert qp_thresholds(0.0, 0.05, 0.05).one_to_three is None
    assert speed_of_precession(np.array([0.5, 1.0]), 0.01, 0.05, 0.0).tolist() == [0.5, math.inf]
    with pytest.warns(QPWarning):
        t = qp_thresholds(0.01, 0.0, 0.05)
    assert t.one_to_three is None and t.escape == math.inf
    with pytest.warns(QPWarning):
        t = qp_thresholds(0.01, 0.05, 0.0)
    assert t.one_to_three == 1.0 and t.three_to_one == math.inf


@pytest.mark.parametrize("name, args", [("R", (-1.0, 0.01, 0.05, 0.05)), ("Rt", (3.0, -0.01, 0.05, 0.05)),
                                        ("h", (3.0, 0.01, -0.05, 0.05)), ("H", (3.0, 0.01, 0.05, np.nan)),
                                        ("Rt", (3.0, 0.5, 0.05, 0.05))])
def test_invalid_inputs_name_the_parameter(name, args):
    with pytest.raises(ValueError, match=f"^{name} "):
        qp_roots(*args)
    if name != "R":
        with pytest.raises(ValueError, match=f"^{name} "):
            qp_thresholds(*args[1:])


def test_docstring_examples():
    import doctest
    import stand.theories.planar.qp as qp
    res = doctest.testmod(qp, optionflags=doctest.NORMALIZE_WHITESPACE)
    assert res.failed == 0 and res.attempted >= 5
