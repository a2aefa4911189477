"""Main-motion stability theory (stand.theories.planar.main_motion) against the digest.

Oracles: digest ch5 sections 4.1-4.4, 6.5 and the tests T1-T5 of section 8.3.
Tables quoted there are reproduced row by row; where the digest prints 5 decimals
the exact numerics are held to 2e-5, elsewhere to the digest's own tolerance.
"""
import math
import warnings

import numpy as np
import numpy.polynomial.polynomial as P
import pytest

from stand.theories.rotating import main_motion_state, rotating_jacobian, rotating_rhs
from stand.theories.planar.main_motion import (
    CriticalSpeed, StabilityWarning, R1_first_order, R1_max_closed_form, R1_max_validity,
    R1_refined, R_window_large_H, balancing_rate, charpoly_coefficients,
    conservative_coefficients, conservative_R1_k1, conservative_R1_parametric,
    conservative_R1_series, conservative_R23_k1, conservative_series_k0, critical_speeds,
    d_from_angles, d_two_balls, high_speed_h_crit, high_speed_h_crit_exact, is_stable,
    jacobian_eigenvalues, main_eigenvalues, spectral_abscissa,
    unbalance_independent_threshold,
)

from _helpers import dimensionless_model, match_roots


def _speeds(cs):
    return [c.R for c in cs]


def _kinds(cs):
    return [c.kind for c in cs]


# ---------------------------------------------------------------------------
# T1: (5.90) is the expansion of the determinant (5.89)
# ---------------------------------------------------------------------------

def _determinant_589(R, Rt, h, H, d):
    """(5.89) expanded with numpy.polynomial; the bar conjugates coefficients only."""
    a11 = np.array([1 - R * R + 1j * H * R, 2j * R + H, 1.0])     # (l+iR)^2 + H(l+iR) + 1
    a13 = np.array([-R * R, 2j * R, 1.0])                          # (l+iR)^2
    a33 = np.array([0.0, h, 1.0])                                  # l^2 + h l
    c = np.conj
    f1 = P.polysub(P.polymul(a11, a33), Rt * P.polymul(a13, a13))
    f2 = P.polysub(P.polymul(c(a11), a33), Rt * P.polymul(c(a13), c(a13)))
    g = Rt * Rt * d * d * P.polymul(P.polymul(a13, a13), P.polymul(c(a13), c(a13)))
    D = P.polysub(P.polymul(f1, f2), g)
    return np.pad(D, (0, 9 - D.size))


@pytest.mark.parametrize("R, Rt, h, H, d", [
    (2.3, 0.04, 0.3, 0.2, 0.3624), (1.7, 0.0099, 0.2, 0.1, 1.0), (0.6, 0.3, 2.0, 0.01, 0.0),
    (12.0, 0.05, 0.75, 0.75, 0.9), (1.15, 0.45, 1e-3, 3.0, 0.5), (3.0, 0.01, 0.0, 0.0, 0.2),
])
def test_T1_coefficients_are_the_determinant(R, Rt, h, H, d):
    D = _determinant_589(R, Rt, h, H, d)
    a = charpoly_coefficients(R, Rt, h, H, d)
    assert np.max(np.abs(D.imag)) <= 1e-12 * np.max(np.abs(D.real))
    for i in range(9):
        assert D.real[i] == pytest.approx(a[i], rel=1e-12, abs=1e-12 * np.max(np.abs(a)))


def test_T1_symbolic_when_sympy_is_there():
    sp = pytest.importorskip("sympy")
    lam, R, Rt, h, H, d = sp.symbols("lam R Rt h H d")
    i = sp.I
    a11 = (lam + i * R) ** 2 + H * (lam + i * R) + 1
    a13 = (lam + i * R) ** 2
    a11b = (lam - i * R) ** 2 + H * (lam - i * R) + 1      # coefficients conjugated
    a13b = (lam - i * R) ** 2
    a33 = lam ** 2 + h * lam
    D = sp.expand((a11 * a33 - Rt * a13 ** 2) * (a11b * a33 - Rt * a13b ** 2)
                  - Rt ** 2 * a13 ** 2 * a13b ** 2 * d ** 2)
    coeffs = sp.Poly(D, lam).all_coeffs()[::-1]
    vals = {R: sp.Rational(23, 10), Rt: sp.Rational(1, 25), h: sp.Rational(3, 10),
            H: sp.Rational(1, 5), d: sp.Rational(2, 5)}
    a = charpoly_coefficients(2.3, 0.04, 0.3, 0.2, 0.4)
    for k in range(9):
        assert float(coeffs[k].subs(vals)) == pytest.approx(a[k], rel=1e-13)


def test_conservative_form_598_corrected():
    R, Rt, d = 1.7, 0.05, 0.3
    c = conservative_coefficients(R, Rt, d)
    a = charpoly_coefficients(R, Rt, 0.0, 0.0, d)
    assert np.allclose(c, a[0::2], rtol=1e-14)
    assert np.all(a[1::2] == 0.0)
    # the printed (5.98) without the Rt^2 factor is not the h = H = 0 polynomial
    k = 1 - d * d
    printed_c0 = k * R ** 8
    assert abs(printed_c0 - a[0]) > 0.5 * printed_c0


# ---------------------------------------------------------------------------
# T2: the simulator's rotating-frame Jacobian has the roots of (5.90)
# ---------------------------------------------------------------------------

def test_T2_two_balls_printed_numbers():
    W, Rt, h, H, a = 2.3, 0.04, 0.3, 0.2, 0.6
    e0 = math.cos(a)  # balls at pi +- a balance e0 = cos a
    m = dimensionless_model(2, W, Rt, h, H, e0)
    z = main_motion_state(m, [math.pi + a, math.pi - a])
    assert np.max(np.abs(rotating_rhs(m, W, z))) < 1e-14  # an equilibrium (5.50)
    ev = jacobian_eigenvalues(m, W, [math.pi + a, math.pi - a])
    assert ev.size == 8
    printed = [-0.19663 + 0.62607j, -0.11933 + 0.36842j, -0.10419 + 1.29253j, -0.1008 + 3.2967j]
    match_roots(ev, printed + [np.conj(p) for p in printed], 1e-4)
    d = d_two_balls(e0)
    assert d == pytest.approx(0.3624, abs=1e-4)
    assert d == pytest.approx(d_from_angles([math.pi + a, math.pi - a]), abs=1e-15)
    lam = main_eigenvalues(W, Rt, h, H, d)
    match_roots(ev, lam, 1e-6)
    assert np.all(np.diff(lam.real) <= 0)
    assert spectral_abscissa(W, Rt, h, H, d) == pytest.approx(lam[0].real, abs=1e-15)


@pytest.mark.parametrize("n", [3, 4])
def test_T2_family_zero_roots_dropped(n):
    W, Rt, h, H, e0 = 1.8, 0.04, 0.3, 0.2, 0.3
    al = list(np.linspace(2.0, 4.0, n - 2))
    rest = -n * e0 - np.sum(np.exp(1j * np.array(al)))     # e^{ia} + e^{ib} = rest
    th = math.acos(abs(rest) / 2)
    al += [np.angle(rest) + th, np.angle(rest) - th]
    m = dimensionless_model(n, W, Rt, h, H, e0)
    full = np.linalg.eigvals(rotating_jacobian(m, W, main_motion_state(m, al)))
    assert np.sum(np.abs(full) < 1e-9) == n - 2          # the family's zero roots
    ev = jacobian_eigenvalues(m, W, al)
    assert ev.size == 2 * n + 4 - (n - 2)
    left = match_roots(ev, main_eigenvalues(W, Rt, h, H, d_from_angles(al)), 1e-6)
    assert np.allclose(left, -h, atol=1e-6)               # relative weight modes


def test_jacobian_eigenvalues_rejects_unbalanced_configuration():
    m = dimensionless_model(2, 2.0, 0.04, 0.3, 0.2, 0.5)
    with pytest.raises(ValueError):
        jacobian_eigenvalues(m, 2.0, [0.0, 0.0])


def test_d_parameter():
    assert d_two_balls(0.0) == 1.0 and d_two_balls(1.0) == 1.0
    assert d_two_balls(math.sqrt(0.5)) == pytest.approx(0.0, abs=1e-15)
    assert 1 - d_two_balls(0.3) ** 2 == pytest.approx(4 * 0.09 * 0.91)
    assert d_from_angles([0.1, 0.1 + 2 * np.pi / 3, 0.1 + 4 * np.pi / 3]) == pytest.approx(0, abs=1e-15)
    # non-identical weights: w_j = m_j^2 l_j^2 / J_j (point balls: m_j); scale-free
    a = [0.3, 2.0, 4.1]
    m = np.array([1.0, 2.0, 0.5])
    assert d_from_angles(a, m) == pytest.approx(d_from_angles(a, 7 * m))
    assert d_from_angles(a, [1.0, 0.0, 0.0]) == pytest.approx(1.0)
    assert d_from_angles(a, [1.0, 1.0, 0.0]) == pytest.approx(abs(math.cos(a[0] - a[1])))
    with pytest.raises(ValueError):
        d_two_balls(1.2)


# ---------------------------------------------------------------------------
# T3: conservative critical speeds (h = H = 0)
# ---------------------------------------------------------------------------

# Table 4.2-A: Rt, k = 0 (d = 1) crossings, k = 1 (d = 0) R1
TABLE_42A = [
    (0.005, [1.0000, 1.0157, 1.3271], 1.2821),
    (0.0099, [1.0000, 1.0316, 1.4364], 1.3625),
    (0.01, [1.0000, 1.0319, 1.4383], 1.3638),
    (0.02, [1.0000, 1.0666, 1.6042], 1.4716),
    (0.03, [1.0000, 1.1044, 1.7444], 1.5505),
    (0.05, [1.0000, 1.1912, 2.0051], 1.6707),
    (0.10, [1.0000, 1.5110, 2.7352], 1.8827),
    (0.15, [1.0000, 2.1626, 3.9227], 2.0404),
    (0.20, [1.0000, 4.2101, 7.0295], 2.1709),
    (0.24, [1.0000, 22.22, 29.13], 2.2630),
    (0.26, [1.0000], 2.3059),
    (0.30, [1.0000], 2.3867),
    (0.40, [1.0000], 2.5660),
    (0.45, [1.0000], 2.6468),
]


@pytest.mark.parametrize("Rt, k0, k1", TABLE_42A)
def test_T3_table_42A(Rt, k0, k1):
    c0 = critical_speeds(Rt, 0.0, 0.0, 1.0)
    assert _speeds(c0) == pytest.approx(k0, abs=1e-3)
    assert _kinds(c0) == ["gains", "loses", "gains"][:len(k0)]
    c1 = critical_speeds(Rt, 0.0, 0.0, 0.0)
    assert _speeds(c1) == pytest.approx([k1], abs=1e-3)
    assert _kinds(c1) == ["gains"]
    # (5.105) is exact for the k = 1 critical speed
    assert c1[0].R == pytest.approx(conservative_R1_k1(Rt), abs=1e-9)
    assert is_stable(c1[0].R + 1e-6, Rt, 0, 0, 0.0) and not is_stable(c1[0].R - 1e-6, Rt, 0, 0, 0.0)


def test_T3_closed_forms_beside_table_42A():
    ser = {0.005: (1.0156, 1.3235), 0.0099: (1.0315, 1.4266), 0.01: (1.0318, 1.4283),
           0.02: (1.0661, 1.5754), 0.05: (1.1834, 1.8749)}
    for Rt, v in ser.items():
        assert conservative_series_k0(Rt) == pytest.approx(v, abs=1e-4)
    s106 = {0.005: 1.2822, 0.0099: 1.3626, 0.01: 1.3640, 0.02: 1.4720, 0.05: 1.6724,
            0.10: 1.8868, 0.20: 2.1806}
    for Rt, v in s106.items():
        assert conservative_R1_series(Rt) == pytest.approx(v, abs=1e-4)


def test_T3_series_accuracy():
    # (5.103): error <= 0.7 % at Rt = 0.01, <= 7 % at 0.05
    for Rt, tol in [(0.01, 0.007), (0.05, 0.07)]:
        exact = _speeds(critical_speeds(Rt, 0.0, 0.0, 1.0))[1:]
        approx = conservative_series_k0(Rt)
        assert all(abs(a / e - 1) <= tol for a, e in zip(approx, exact))
    # (5.106): at most 1.08 % over 0 < Rt < 0.5 (largest at Rt -> 0.5)
    Rts = np.linspace(0.001, 0.4999, 60)
    err = [abs(conservative_R1_series(r) / conservative_R1_k1(r) - 1) for r in Rts]
    assert max(err) <= 0.0108 and err[-1] == max(err)


def test_T3_parametric_and_touching_root():
    Rt, R1 = conservative_R1_parametric(0.4062)
    assert Rt == pytest.approx(0.0100, abs=5e-5) and R1 == pytest.approx(1.36385, abs=1e-5)
    assert conservative_R1_k1(0.01) == pytest.approx(1.3638, abs=1e-4)
    assert _speeds(critical_speeds(0.01, 0, 0, 0.0)) == pytest.approx([1.3638], abs=1e-4)
    assert _speeds(critical_speeds(0.01, 0, 0, 1.0))[2] == pytest.approx(1.4383, abs=1e-4)
    # (5.107): all three coincide at Rt = 0.04173
    assert conservative_R23_k1(0.04173) == pytest.approx(1.6252, abs=1e-4)
    assert _speeds(critical_speeds(0.0417, 0, 0, 0.0)) == pytest.approx([1.6249], abs=1e-4)
    # at k = 1 the double root only touches: no band reported at (5.107) ...
    assert len(critical_speeds(0.05, 0, 0, 0.0)) == 1
    assert is_stable(conservative_R23_k1(0.05), 0.05, 0, 0, 0.0)


def test_T3_thin_band_opens_below_k1():
    # ... but for slightly smaller k it opens into a thin unstable band
    cs = critical_speeds(0.05, 0.0, 0.0, 0.02)
    assert _kinds(cs) == ["gains", "loses", "gains"]
    assert _speeds(cs)[1:] == pytest.approx([1.6709, 1.6835], abs=1e-4)
    assert cs[0].R < cs[1].R < conservative_R23_k1(0.05) < cs[2].R
    # thinner still: d = 1e-4 gives a band 6e-5 wide, found on a 0.8 % grid
    cs = critical_speeds(0.05, 0.0, 0.0, 1e-4)
    assert len(cs) == 3 and 0 < cs[2].R - cs[1].R < 1e-4


def _indicator(R, Rt, d):
    """Number of roots x of (5.98) that are non-real or >= 0 (0 <=> stable)."""
    c = conservative_coefficients(R, Rt, d)
    if d == 1.0:
        c = c[1:]                                   # the structural x = 0
    x = np.roots(c[::-1])
    return int(np.sum((np.abs(x.imag) > 1e-9 * np.abs(x)) | (x.real >= 0)))


@pytest.mark.parametrize("Rt, d", [(0.05, 0.02), (0.05, 1.0), (0.0099, 0.0), (0.24, 1.0)])
def test_T3_boundaries_are_indicator_jumps_to_1e10(Rt, d):
    for c in critical_speeds(Rt, 0.0, 0.0, d):
        # 1e-10 near R ~ 1-3; the double-root problem is noise-limited to ~1e-10 R^2
        step = 1e-10 * max(1.0, c.R) ** 2
        below, above = _indicator(c.R - step, Rt, d), _indicator(c.R + step, Rt, d)
        if c.kind == "gains":
            assert below > 0 and above == 0, c
        else:
            assert below == 0 and above > 0, c


@pytest.mark.parametrize("d, expected", [
    (0.1, [1.7105]), (0.5, [1.8458]), (0.9, [1.1884, 1.2283, 1.9741]),
])
def test_T3_intermediate_d(d, expected):
    assert _speeds(critical_speeds(0.05, 0.0, 0.0, d)) == pytest.approx(expected, abs=1e-3)


def test_T3_region_B_opens_near_0142():
    # region B = (R1(Rt, k=1), R2(Rt, k=0)) is non-empty only for Rt >~ 0.142
    def width(Rt):
        loses = [c.R for c in critical_speeds(Rt, 0, 0, 1.0, R_max=50) if c.kind == "loses"]
        return loses[0] - conservative_R1_k1(Rt)
    assert width(0.141) < 0 < width(0.143)
    assert width(0.10) < 0 < width(0.15)


M_STAND, M_BALL = 4.45, 0.045     # universal stand, digest 6.1 (5.247)


@pytest.mark.parametrize("n, Rt, k0, k1", [
    (2, 0.00991, [1.0, 1.0316, 1.4366], 1.3626),
    (3, 0.01472, [1.0, 1.0479, 1.5219], 1.4202),
    (4, 0.01944, [1.0, 1.0645, 1.5958], 1.4665),
    (5, 0.02406, [1.0, 1.0815, 1.6629], 1.5058),
    (6, 0.02860, [1.0, 1.0989, 1.7255], 1.5403),
])
def test_T3_universal_stand_n_balls(n, Rt, k0, k1):
    Rt_exact = n * M_BALL / (2 * (M_STAND + n * M_BALL))
    assert Rt_exact == pytest.approx(Rt, abs=5e-6)
    assert _speeds(critical_speeds(Rt_exact, 0, 0, 1.0)) == pytest.approx(k0, abs=1e-3)
    assert _speeds(critical_speeds(Rt_exact, 0, 0, 0.0)) == pytest.approx([k1], abs=1e-3)


def test_T3_universal_stand_rolling_inertia_row():
    Rt = 5 / 7 * 2 * M_BALL / (2 * (M_STAND + 2 * M_BALL))   # j = 5/7
    assert Rt == pytest.approx(0.00708, abs=5e-6)
    assert _speeds(critical_speeds(Rt, 0, 0, 1.0)) == pytest.approx([1.0, 1.0224, 1.3779], abs=1e-3)
    assert _speeds(critical_speeds(Rt, 0, 0, 0.0)) == pytest.approx([1.3203], abs=1e-3)


@pytest.mark.parametrize("S, expected", [
    (0.05, [1.018, 1.033, 1.436]), (0.1, [1.0345, 1.0378, 1.4346]), (0.3, [1.4202]),
    (0.5, [1.3919]), (0.707, [1.3624]), (0.8, [1.3744]), (0.9, [1.4024]), (0.95, [1.4189]),
    (1.0, [1.0, 1.0316, 1.4364]),
])
def test_T3_two_balls_vs_unbalance(S, expected):
    cs = critical_speeds(0.0099, 0.0, 0.0, d_two_balls(S))
    assert _speeds(cs) == pytest.approx(expected, abs=1e-3)
    assert _kinds(cs) == ["gains", "loses", "gains"][:len(expected)]


def test_T3_conservative_unbalance_independent_threshold():
    # digest: 1.4365; the sup is reached at d = 1 where the exact value is 1.43637
    thr = unbalance_independent_threshold(0.0099, 0.0, 0.0, n_d=11)   # sup at d = 1 (as T4)
    assert thr == pytest.approx(1.4365, abs=1e-3)
    assert thr == pytest.approx(critical_speeds(0.0099, 0, 0, 1.0)[-1].R, abs=1e-6)


# ---------------------------------------------------------------------------
# T4: damped critical speeds
# ---------------------------------------------------------------------------

@pytest.mark.parametrize("d, exact, first, refined", [
    (0.0, 1.15378, 1.13333, 1.15210),
    (0.3, 1.13582, 1.12133, 1.13428),
    (0.5, 1.10625, 1.10000, 1.10463),
    (0.7, 1.06695, 1.06800, 1.06498),
    (0.9, 1.02263, 1.02533, 1.02115),
    (0.99, 1.00226, 1.00265, 1.00204),
])
def test_T4_table_44A(d, exact, first, refined):
    Rt, h, H = 0.05, 0.75, 0.75
    cs = critical_speeds(Rt, h, H, d)
    assert _kinds(cs) == ["gains"]
    assert cs[0].R == pytest.approx(exact, abs=2e-5)
    assert R1_first_order(Rt, h, H, d) == pytest.approx(first, abs=5e-6)
    assert R1_refined(Rt, h, H, d) == pytest.approx(refined, abs=5e-6)


@pytest.mark.parametrize("args, tol", [
    ((0.05, 0.75, 0.75, 0.0), 1e-10), ((0.0099, 0.2, 0.1, 1.0), 1e-10),
    ((0.0099, 0.05, 0.05, 0.999), 1e-10), ((0.05, 1e-3, 1e-3, 0.02), 1e-10),
    ((0.01, 0.5, 1000.0, 0.0), 1e-4),      # H = 1000: abscissa ~1e-8 near R = 1
])
def test_T4_crossings_satisfy_the_split_5123(args, tol):
    """At each damped crossing l = +-i mu: x = mu^2 is a common positive root of
    the even and odd halves of (5.123) (except the real root through 0 at d = 1)."""
    cs = critical_speeds(*args)
    assert cs
    for c in cs:
        if args[3] == 1.0 and c.R == pytest.approx(1.0, abs=1e-9):
            assert c.mu == 0.0
            continue
        a = charpoly_coefficients(c.R, *args)
        x = c.mu ** 2
        assert x > 0
        re = np.array([a[0], -a[2] * x, a[4] * x ** 2, -a[6] * x ** 3, a[8] * x ** 4])
        im = np.array([a[1], -a[3] * x, a[5] * x ** 2, -a[7] * x ** 3])
        assert abs(re.sum()) <= tol * np.abs(re).sum()
        assert abs(im.sum()) <= tol * np.abs(im).sum()


# Table 4.4-B: Rt, h, H, exact R1max (d = 0), (5.127), Rt/(2 h^2 H)
TABLE_44B = [
    (0.05, 0.20, 0.75, 3.28104, 3.9505, 0.83),
    (0.05, 0.30, 0.75, 1.83995, 1.9552, 0.37),
    (0.05, 0.50, 0.75, 1.31684, 1.3083, 0.13),
    (0.05, 1.00, 0.75, 1.09924, 1.0989, 0.033),
    (0.05, 2.00, 0.75, 1.04036, 1.0403, 0.008),
    (0.05, 0.10, 0.75, None, 31.04, 3.3),
    (0.05, 0.75, 0.05, 1.75817, 2.5625, 0.89),
    (0.05, 0.75, 0.10, 1.54094, 1.8069, 0.44),
    (0.05, 0.75, 0.20, 1.36405, 1.4291, 0.22),
    (0.05, 0.75, 0.50, 1.19971, 1.2025, 0.089),
    (0.05, 0.75, 1.00, 1.12955, 1.1269, 0.044),
    (0.05, 0.75, 2.00, 1.09194, 1.0891, 0.022),
    (0.01, 0.75, 0.75, 1.02743, 1.0274, 0.012),
    (0.02, 0.75, 0.75, 1.05646, 1.0563, 0.024),
    (0.10, 0.75, 0.75, 1.35022, 1.3417, 0.12),
    (0.20, 0.75, 0.75, 1.81211, 1.8336, 0.24),
]


def _printed_tol(x):
    """Half a unit in the last printed digit of a table entry (given as float)."""
    s = repr(x)
    return 0.5 * 10.0 ** -(len(s.split(".")[1]) if "." in s else 0)


@pytest.mark.parametrize("Rt, h, H, exact, closed, ratio", TABLE_44B)
def test_T4_table_44B(Rt, h, H, exact, closed, ratio):
    assert R1_max_closed_form(Rt, h, H) == pytest.approx(closed, abs=_printed_tol(closed) + 1e-12)
    assert R1_max_validity(Rt, h, H) == pytest.approx(ratio, abs=_printed_tol(ratio) + 1e-12)
    assert R1_max_closed_form(Rt, h, H) == pytest.approx(R1_refined(Rt, h, H, 0.0), rel=1e-14)
    cs = critical_speeds(Rt, h, H, 0.0, R_min=0.5, R_max=316.0)
    if exact is None:
        # unstable at all speeds: h < H sqrt(Rt) = 0.168 (5.96)
        assert h < high_speed_h_crit(Rt, H) == pytest.approx(0.168, abs=5e-4)
        assert cs == []
        assert not is_stable(316.0, Rt, h, H, 0.0) and not is_stable(2.0, Rt, h, H, 0.0)
    else:
        assert _kinds(cs) == ["gains"]
        assert cs[0].R == pytest.approx(exact, abs=2e-5)


def test_T4_closed_form_baseline_within_02_percent():
    exact = critical_speeds(0.05, 0.75, 0.75, 0.0)[0].R
    assert abs(R1_max_closed_form(0.05, 0.75, 0.75) / exact - 1) < 0.002


@pytest.mark.parametrize("Rt, h, H, d, expected", [
    (0.0099, 0.2, 0.1, 0.0, [1.30359]),
    (0.0099, 0.2, 0.1, 1.0, [1.00000, 1.03795, 1.35478]),
    (0.0099, 0.05, 0.05, 0.0, [1.36467]),
    (0.0099, 0.05, 0.05, 1.0, [1.0000, 1.0247, 1.42887]),
])
def test_T4_low_damping_warning_table(Rt, h, H, d, expected):
    cs = critical_speeds(Rt, h, H, d)
    assert _speeds(cs) == pytest.approx(expected, abs=2e-5)
    assert _kinds(cs) == ["gains", "loses", "gains"][:len(expected)]


def test_T4_unbalance_independent_threshold_low_damping():
    # an 11-point d grid (default 41) and the points clustered at d = 1, where the sup is:
    # the same value to the last digit (checked 2026-11-29), in half the time
    thr = unbalance_independent_threshold(0.0099, 0.2, 0.1, n_d=11)
    assert thr == pytest.approx(1.35478, abs=2e-5)
    # d = 0 (the book's worst case, (5.127)) is not the worst case here
    assert thr > critical_speeds(0.0099, 0.2, 0.1, 0.0)[-1].R + 0.05


def test_T4_threshold_infinite_when_high_speed_unstable():
    assert unbalance_independent_threshold(0.05, 0.1, 0.75, n_d=5) == math.inf


def test_T4_large_H_window_597():
    lo, hi = R_window_large_H(0.01, 0.5)
    assert hi == pytest.approx(4.949, abs=1e-3)
    cs = critical_speeds(0.01, 0.5, 1000.0, 0.0)
    assert _kinds(cs) == ["gains", "loses"]
    assert cs[0].R == pytest.approx(1.0, abs=0.03)            # "effectively 1"
    assert cs[1].R == pytest.approx(4.897, abs=1e-3)
    assert R_window_large_H(0.01, 0.1) is None                # p >= 1


def test_T4_balancing_rate():
    # digest 4.3: exact -0.003772, -0.001363; formula -0.003767, -0.001361
    l78 = balancing_rate(2.0, 0.001, 2.0, 0.3, 0.5)
    assert np.sort(l78.real) == pytest.approx([-0.003767, -0.001361], abs=1e-6)
    lam = main_eigenvalues(2.0, 0.001, 2.0, 0.3, 0.5)
    assert np.sort(lam.real)[-2:] == pytest.approx([-0.003772, -0.001363], abs=1e-6)
    # T10: n = 2, Rt = 0.01, h = 0.5, H = 0.1, e0 = 0.3, R = 3: exact -0.03968, formula -0.0365
    d = d_two_balls(0.3)
    assert max(balancing_rate(3.0, 0.01, 0.5, 0.1, d).real) == pytest.approx(-0.0365, abs=1e-4)
    assert spectral_abscissa(3.0, 0.01, 0.5, 0.1, d) == pytest.approx(-0.03968, abs=1e-5)


# ---------------------------------------------------------------------------
# T5: loss of stability at high speed, h < H sqrt(Rt) (5.96)
# ---------------------------------------------------------------------------

@pytest.mark.parametrize("Rt, H", [(0.05, 0.75), (0.01, 0.2)])
@pytest.mark.parametrize("R", [100.0, 1000.0])
def test_T5_h_crit_d0(Rt, H, R):
    hc = high_speed_h_crit_exact(Rt, H, 0.0, R=R)
    assert hc == pytest.approx(high_speed_h_crit(Rt, H), rel=3e-3)
    assert is_stable(R, Rt, 1.01 * hc, H, 0.0) and not is_stable(R, Rt, 0.99 * hc, H, 0.0)


def test_T5_printed_values():
    assert high_speed_h_crit_exact(0.05, 0.75, 0.0, R=1000) == pytest.approx(0.16771, abs=5e-6)
    assert high_speed_h_crit(0.05, 0.75) == pytest.approx(0.16771, abs=5e-6)
    assert high_speed_h_crit_exact(0.05, 0.75, 0.5, R=1000) == pytest.approx(0.0773, abs=5e-5)
    assert high_speed_h_crit_exact(0.05, 0.75, 0.9, R=1000) == pytest.approx(0.0119, abs=5e-5)


# ---------------------------------------------------------------------------
# robustness
# ---------------------------------------------------------------------------

def _brute_force(Rt, h, H, d, R):
    ab = spectral_abscissa(R, Rt, h, H, d)
    s = ab > 16 * np.finfo(float).eps * (1 + R) ** 2
    return R[1:][s[:-1] != s[1:]]


@pytest.mark.parametrize("args", [
    (0.05, 1e-3, 1e-3, 0.02), (0.0099, 0.05, 0.05, 0.999), (0.2, 0.02, 0.3, 0.7),
])
def test_scan_agrees_with_brute_force(args):
    R = np.geomspace(0.5, 6.0, 60001)
    ref = _brute_force(*args, R)
    got = _speeds(critical_speeds(*args, R_max=6.0))
    assert len(got) == len(ref) and np.allclose(got, ref, rtol=1e-4)


def test_tiny_damping_is_correct():
    # H -> 1e-6: stability returns only far above resonance
    cs = critical_speeds(0.05, 0.3, 1e-6, 0.3)
    assert _kinds(cs) == ["gains"] and cs[0].R == pytest.approx(26.094, abs=1e-3)
    assert not is_stable(cs[0].R * 0.999, 0.05, 0.3, 1e-6, 0.3)
    assert is_stable(cs[0].R * 1.001, 0.05, 0.3, 1e-6, 0.3)
    # h -> 1e-6 < H sqrt(Rt): unstable at all speeds
    assert critical_speeds(0.05, 1e-6, 0.3, 0.3) == []
    # h = H = 1e-6 (h > H sqrt(Rt)): a single critical speed, d = 1 keeps three
    assert _kinds(critical_speeds(0.05, 1e-6, 1e-6, 0.3)) == ["gains"]
    assert _kinds(critical_speeds(0.05, 1e-6, 1e-6, 1.0)) == ["gains", "loses", "gains"]


def test_unresolvable_damping_warns():
    with pytest.warns(StabilityWarning, match="round-off"):
        cs = critical_speeds(0.05, 0.3, 1e-9, 0.3)
    assert len(cs) == 1                                   # no chatter of crossings


@pytest.mark.parametrize("h, H", [(0.0, 0.3), (0.3, 0.0)])
def test_exactly_one_damping_zero_warns(h, H):
    with pytest.warns(StabilityWarning):
        assert critical_speeds(0.05, h, H, 0.3) == []
    with pytest.warns(StabilityWarning):
        assert not is_stable(5.0, 0.05, h, H, 0.3)
    # the numbers behind it: a positive abscissa well above round-off
    assert spectral_abscissa(5.0, 0.05, h, H, 0.3) > 1e-6


def test_no_warning_in_ordinary_cases():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        critical_speeds(0.05, 0.75, 0.75, 0.0)
        critical_speeds(0.05, 0.0, 0.0, 0.5)


def test_input_checks():
    with pytest.raises(ValueError):
        critical_speeds(0.5, 0.1, 0.1, 0.0)
    with pytest.raises(ValueError):
        critical_speeds(0.05, 0.1, 0.1, 1.5)
    with pytest.raises(ValueError):
        critical_speeds(0.05, -0.1, 0.1, 0.0)
    with pytest.raises(ValueError):
        critical_speeds(0.05, 0.1, 0.1, 0.0, R_min=2.0, R_max=1.0)
    assert isinstance(critical_speeds(0.05, 0.75, 0.75, 0.0)[0], CriticalSpeed)
