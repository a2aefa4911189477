"""Side motions, main motions and the e0 > 1 main motion: existence and stability.

Oracles: digest ch5 section 3 (steady equations (5.49), main motions (5.50),
side motions (5.51)-(5.75) with the corrected (5.57) and (5.64)), section 4.5
(stability of side motions and of the e0 > 1 main motion, (5.140)-(5.161)),
tests T6 and T6b of section 8.3.  Equilibria are checked against the
simulator's own equations in the rotating frame (stand.theories.rotating).
"""
import math

import numpy as np
import pytest

from stand.model.planar import build_planar_model
from stand.theories.rotating import rotating_rhs
from stand.scene.model import RunSettings, SpeedDrive
from stand.scene.parse import scene_from_dimensionless
from stand.theories.planar.steady import (
    bits_of, identical_side_classes, main_motion_angles, maximally_balanced_motion, net_unbalance,
    side_motions, side_window, steady_deflection, steady_residual,
)
from stand.theories.planar.steady_stability import (
    is_stable, large_unbalance_coefficients, stable_steady_motions, steady_eigenvalues, steady_state,
)

TAU = 2 * math.pi


def _scene(n, Rt, h, H, e0, R=1.0, **kw):
    return scene_from_dimensionless(n, Rt, h, H, e0, drive=SpeedDrive(np.array([[0.0, R]])),
                                    run=RunSettings(1.0, 1.0), **kw)


def _model(n, Rt, h, H, e0, R=1.0, **kw):
    return build_planar_model(_scene(n, Rt, h, H, e0, R, **kw))


def _wrapdiff(a, b):
    return abs(math.remainder(a - b, TAU))


def _rhs_residual(model, R, s, alphas):
    return float(np.max(np.abs(rotating_rhs(model, R, steady_state(model, s, alphas)))))


# ---------------------------------------------------------------- main motions (5.50)

@pytest.mark.parametrize("e0", [0.0, 0.3, 0.5, 0.99, 1.0])
def test_main_motion_two_balls_closed_form(e0):
    mm = main_motion_angles(e0, 2)
    th = math.acos(e0)
    assert len(mm) == (1 if e0 == 1.0 else 2)
    for m in mm:
        assert m.balanced and not (m.family and e0 > 0) and m.s == 0
        assert abs(m.psi) < 1e-15
        assert sorted(_wrapdiff(a, math.pi) for a in m.alphas) == pytest.approx([th, th], abs=1e-12)
    if len(mm) == 2:  # mirror images
        assert mm[0].alphas == pytest.approx(-mm[1].alphas, abs=1e-12)
    model = _model(2, 0.01, 0.1, 0.1, e0)
    assert _rhs_residual(model, 2.0, 0j, mm[0].alphas) < 1e-14


@pytest.mark.parametrize("n,e0", [(3, 0.0), (3, 0.5), (4, 0.2), (4, 0.9), (6, 0.7)])
def test_main_motion_identical_family_representative(n, e0):
    (m,) = main_motion_angles(e0, n)
    assert m.balanced and m.family
    assert abs(m.psi) < 1e-14
    assert _rhs_residual(_model(n, 0.01, 0.1, 0.1, e0), 3.0, 0j, m.alphas) < 1e-13


def test_main_motion_family_gives_zero_eigenvalues():
    # n = 4: a 2-parameter family of balancing configurations -> two zero eigenvalues
    n, e0, R = 4, 0.4, 3.0
    model = _model(n, 0.01, 0.3, 0.1, e0)
    (m,) = main_motion_angles(e0, n)
    ev = steady_eigenvalues(model, R, steady_state(model, 0j, m.alphas))
    small = np.sort(np.abs(ev))[:2]
    assert np.all(small < 1e-6)
    assert np.abs(ev).min() < 1e-6 < np.sort(np.abs(ev))[2]
    assert is_stable(ev, neutral=2) and not is_stable(ev)


@pytest.mark.parametrize("e,e0,count", [([0.5, 0.3, 0.2], 0.0, 1), ([0.5, 0.3, 0.2], 0.6, 1),
                                        ([0.5, 0.3, 0.2], 1.0, 1), ([0.7, 0.3], 0.4, 1),
                                        ([0.7, 0.3], 0.8, 2), ([0.7, 0.3], 1.0, 1),
                                        ([0.4, 0.3, 0.2, 0.1], 0.05, 1),
                                        ([0.6, 0.2, 0.1, 0.1], 0.25, 1)])
def test_main_motion_non_identical(e, e0, count):
    # n = 2: two mirror images, which coincide at the ends e0 = |e1 - e2|, e1 + e2
    e = np.array(e)
    mm = main_motion_angles(e0, e=e)
    assert len(mm) == count
    for m in mm:
        assert m.balanced
        assert abs(e0 + np.sum(e * np.exp(1j * m.alphas))) < 1e-14


def test_main_motion_existence_polygon_inequality():
    e = np.array([0.7, 0.2, 0.1])
    # e0 >= 2 max e_j - 1 = 0.4 and e0 <= 1 (digest 3.1)
    assert main_motion_angles(0.4, e=e)[0].balanced
    (m,) = main_motion_angles(0.3, e=e, R=2.0, H=0.1)  # one weight too heavy
    assert not m.balanced
    assert m.bits == (1, 0, 0)  # heavy weight to the light side, the rest to the heavy side
    assert steady_residual(2.0, 0.3, 0.1, m.s, m.alphas, e) < 1e-14
    assert abs(m.psi) == pytest.approx(0.1, abs=0.01)
    assert not main_motion_angles(1.0 + 1e-6, e=e)[0].balanced


@pytest.mark.parametrize("R", [0.5, 0.95, 1.0, 1.05, 2.0, 10.0])
@pytest.mark.parametrize("e0", [1.2, 1.5, 3.0])
def test_main_motion_beyond_capacity(e0, R):
    H = 0.1
    (m,) = main_motion_angles(e0, 2, R=R, H=H)
    assert not m.balanced and m.bits == (1, 1)  # the book's k = 2^n - 1
    assert m.alphas[0] == m.alphas[1]
    assert steady_residual(R, e0, H, m.s, m.alphas) < 1e-14 * max(1, R * R)
    assert m.s == pytest.approx(steady_deflection(R, m.psi, H), abs=1e-14 * R * R)
    # it is one of the two side motions of e(k) = -1 and has the smaller |psi|
    other = [s for s in side_motions(R, e0, -1.0, H) if _wrapdiff(s.gamma, m.gamma) > 1e-9]
    assert len(other) == 1
    assert abs(m.psi) <= abs(e0 - np.exp(1j * other[0].gamma)) + 1e-12
    assert abs(m.psi) >= e0 - 1 - 1e-12
    # H = 0 or no speed: all weights at pi exactly
    (m0,) = main_motion_angles(e0, 2)
    assert m0.s is None and np.allclose(np.abs(m0.alphas), math.pi)
    if R != 1.0:
        (m0,) = main_motion_angles(e0, 2, R=R, H=0.0)
        assert m0.s == pytest.approx(R * R * (e0 - 1) / (1 - R * R), rel=1e-14)


def test_maximally_balanced_continuous_through_resonance():
    # the weights' resultant angle follows the branch that is stable above resonance
    e0, H = 1.5, 0.1
    Rs = np.linspace(0.99, 1.01, 41)
    ang = [math.remainder(maximally_balanced_motion(R, e0, H).alphas[0], TAU) for R in Rs]
    above = np.array(ang)[Rs >= 1.0]
    assert np.all(np.abs(np.diff(above)) < 0.05)
    with pytest.raises(ValueError):
        maximally_balanced_motion(1.0, e0, 0.0)


# ---------------------------------------------------------------- side motions (5.51)-(5.75), T6

T6 = dict(e0=0.5, ek=1.0, H=0.2)


def test_T6_existence_window():
    R1, R2 = side_window(**T6)
    assert R1 == pytest.approx(0.84168, abs=5e-6)
    assert R2 == pytest.approx(1.18809, abs=5e-6)
    assert R1 * R2 == pytest.approx(1.0, rel=1e-14)
    for R in (0.85, 0.95, 1.0, 1.1, 1.18):
        assert side_motions(R, **T6) == []
    for R in (0.84, 1.19):
        assert len(side_motions(R, **T6)) == 2


def _corrected_557(R, e0, ek, H, g, v):
    return ((1 - R * R) * v - R * R * (ek + e0 * math.cos(g)),
            H * R * v + R * R * e0 * math.sin(g),
            (1 - R * R) * e0 * math.sin(g) + H * R * (ek + e0 * math.cos(g)))


@pytest.mark.parametrize("R", [0.2, 0.5, 0.8, 0.84, 1.19, 1.5, 3.0, 10.0])
def test_T6_roots_566_are_equilibria(R):
    e0, ek, H = T6["e0"], T6["ek"], T6["H"]
    model = _model(2, 0.01, 0.1, H, e0, R)
    sm = side_motions(R, e0, ek, H, bits=(0, 0))
    assert [m.root for m in sm] == [1, 2]
    for m in sm:
        # the book's literal (5.66)
        sq = math.sqrt(e0 ** 2 * (R * R - 1) ** 2 + H * H * R * R * (e0 ** 2 - ek ** 2))
        t = (-e0 * (R * R - 1) + (sq if m.root == 1 else -sq)) / (H * R * (e0 - ek))
        assert _wrapdiff(m.gamma, 2 * math.atan(t)) < 1e-12
        # corrected (5.57) / (5.64): machine precision
        assert np.max(np.abs(_corrected_557(R, e0, ek, H, m.gamma, m.v))) < 1e-14 * max(1, R * R)
        assert m.s == pytest.approx(m.v * np.exp(1j * m.gamma), abs=1e-15)
        assert m.s == pytest.approx(steady_deflection(R, e0 + ek * np.exp(1j * m.gamma), H),
                                    abs=1e-14 * max(1, R * R))
        assert steady_residual(R, e0, H, m.s, m.alphas) < 1e-14 * max(1, R * R)
        # the simulator's equations in the rotating frame: u + i v = v~ e^{i gamma},
        # both balls at alpha_j = gamma + k_j pi = gamma, zero velocities
        assert _rhs_residual(model, R, m.s, m.alphas) < 1e-12


@pytest.mark.parametrize("R", [0.5, 2.0])
def test_printed_564a_is_not_an_equilibrium(R):
    """The printed (5.64a) has '- H R [...]': its roots are those of the corrected
    equation with H -> -H; they leave O(0.1) residuals (digest section 3.2)."""
    e0, ek, H = T6["e0"], T6["ek"], T6["H"]
    model = _model(2, 0.01, 0.1, H, e0, R)
    A, B, C = (1 - R * R) * e0, -H * R * e0, H * R * ek  # printed: A sin g + B cos g = C
    r, p = math.hypot(A, B), math.atan2(B, A)
    for g in (math.asin(C / r) - p, math.pi - math.asin(C / r) - p):
        assert abs(A * math.sin(g) + B * math.cos(g) - C) < 1e-15
        v = R * R * (ek + e0 * math.cos(g)) / (1 - R * R)  # second equation of (5.64)
        s = v * np.exp(1j * g)
        # the force balance on the shaft fails by O(0.1) of the unbalance force R^2
        assert steady_residual(R, e0, H, s, [g, g]) / R ** 2 > 0.1
        assert _rhs_residual(model, R, s, [g, g]) > 1e-2  # vs < 1e-12 corrected


@pytest.mark.parametrize("e0,ek,H", [(0.5, 1.0, 0.2), (0.3, 0.7, 0.5), (0.5, -1.0, 0.2),
                                     (0.1, 0.9, 1.0), (0.2, 1.0, 0.05)])
def test_window_product_and_saddle_node(e0, ek, H):
    R1, R2 = side_window(e0, ek, H)
    assert 0 < R1 < 1 < R2 and R1 * R2 == pytest.approx(1.0, rel=1e-13)
    gstar = math.pi - math.acos(e0 / abs(ek))  # (5.69)
    for R, sign in ((R1, -1), (R2, +1)):
        sm = side_motions(R, e0, ek, H)
        assert len(sm) == 2 and _wrapdiff(sm[0].gamma, sm[1].gamma) < 1e-7  # merged
        g = sign * gstar if ek > 0 else sign * gstar + math.pi
        assert _wrapdiff(sm[0].gamma, g) < 1e-7
        # just inside the window nothing, just outside two distinct roots
        inside = R * (1 + 1e-6) if sign < 0 else R * (1 - 1e-6)
        outside = R * (1 - 1e-6) if sign < 0 else R * (1 + 1e-6)
        assert side_motions(inside, e0, ek, H) == []
        out = side_motions(outside, e0, ek, H)
        assert len(out) == 2 and _wrapdiff(out[0].gamma, out[1].gamma) > 1e-5
    assert side_window(e0, 0.9 * e0, H) is None
    assert side_window(e0, ek, 0.0) == (1.0, 1.0)


def test_window_matches_discriminant_of_565():
    e0, ek, H = 0.4, 0.8, 0.3
    R1, R2 = side_window(e0, ek, H)
    for R in np.linspace(0.05, 5, 400):
        D = e0 ** 2 * (R * R - 1) ** 2 + H * H * R * R * (e0 ** 2 - ek ** 2)
        assert (len(side_motions(R, e0, ek, H)) == 2) == (D >= 0)
        assert (D >= 0) == (R <= R1 or R >= R2)


def test_merges_with_main_motion_when_e0_equals_ek():
    """Fig. 5.2 b: e0 = |e(k)| -- one root is the main motion psi = 0 at every
    speed (tan(gamma/2) = inf in (5.66)); the other joins it at R = 1, gamma = -pi."""
    e0 = ek = 0.5
    H = 0.2
    for R in (0.3, 0.9, 1.2, 4.0):
        sm = side_motions(R, e0, ek, H)
        assert len(sm) == 2
        main = [m for m in sm if _wrapdiff(m.gamma, math.pi) < 1e-14]
        assert len(main) == 1 and main[0].v == 0.0
        other = [m for m in sm if m is not main[0]][0]
        assert _wrapdiff(other.gamma, math.pi) > 1e-3
    sm = side_motions(1.0, e0, ek, H)
    assert all(_wrapdiff(m.gamma, math.pi) < 1e-14 and abs(m.v) < 1e-15 for m in sm)
    near = side_motions(1.0 - 1e-4, e0, ek, H)
    assert max(_wrapdiff(m.gamma, math.pi) for m in near) < 1e-2


def test_small_net_unbalance_two_branches_swap_places():
    """Fig. 5.2 c: |e(k)| < e0 -- two branches at every speed; following one
    from gamma ~ 0 at low speed it ends at gamma ~ pi at high speed (clockwise)."""
    e0, ek, H = 0.5, 0.2, 0.2
    Rs = np.geomspace(0.02, 50, 3000)
    g = 0.0
    path = []
    for R in Rs:
        sm = side_motions(R, e0, ek, H)
        assert len(sm) == 2
        g = min((m.gamma for m in sm), key=lambda x: _wrapdiff(x, g))
        path.append(g)
    path = np.unwrap(path)
    assert abs(path[0]) < 0.05 and abs(path[-1] + math.pi) < 0.05
    assert np.all(np.diff(path) < 1e-12)  # turns clockwise as R increases


def test_side_motions_lag_below_resonance():
    # "as R increases the common centre turns clockwise: gamma < 0 below resonance"
    for R in (0.2, 0.5, 0.8):
        sm = side_motions(R, 0.5, 1.0, 0.2)
        near0 = min(sm, key=lambda m: abs(m.gamma))
        assert near0.gamma < 0


def test_undamped_cases_561_563():
    R, e0, ek = 0.7, 0.4, 1.0
    sm = side_motions(R, e0, ek, 0.0)
    assert [m.gamma for m in sm] == [0.0, math.pi]
    assert sm[0].v == pytest.approx(R * R * (e0 + ek) / (1 - R * R), rel=1e-15)  # (5.61)
    # gamma = pi is the complementary motion 2^n - 1 - k at gamma = 0
    assert sm[1].s == pytest.approx(R * R * (e0 - ek) / (1 - R * R), rel=1e-15)
    (f,) = side_motions(R, 0.0, ek, 0.0)  # (5.63): a family, gamma arbitrary
    assert f.family and f.v == pytest.approx(R * R * ek / (1 - R * R))
    model = _model(2, 0.01, 0.1, 0.0, 0.0, R)
    for g in (0.0, 1.0, -2.5):  # every member of the family is an equilibrium
        assert _rhs_residual(model, R, f.v * np.exp(1j * g), [g, g]) < 1e-15
    assert side_motions(R, 0.0, 0.0, 0.0) == []
    assert side_motions(R, 0.0, ek, 0.1) == []  # no analogue of (5.63) with damping
    with pytest.raises(ValueError):
        side_motions(1.0, e0, ek, 0.0)


def test_identical_side_classes_575():
    for n in range(1, 8):
        cls = identical_side_classes(n)
        assert [c.k for c in cls] == list(range(n // 2 + 1))
        essentially_different = 0
        for c in cls:
            assert c.ek == pytest.approx(1 - 2 * c.k / n)
            assert c.multiplicity == math.comb(n, c.k) == len(set(c.patterns))
            for i, p in enumerate(c.patterns):
                b = bits_of(p, n)
                assert sum(b) == c.k and c.bits(i) == b
                assert net_unbalance(b) == pytest.approx(c.ek, abs=1e-15)
                comp = 2 ** n - 1 - p  # (5.55)
                assert net_unbalance(bits_of(comp, n)) == pytest.approx(-c.ek, abs=1e-15)
            essentially_different += 1 if 2 * c.k == n else 2
        assert essentially_different == n + 1


def test_unbalance_angle_is_respected():
    # heavy side at beta from the reference mark: the state is rotated by beta
    R, e0, H = 0.6, 0.5, 0.2
    model = _model(2, 0.01, 0.1, H, e0, R, unbalance_angle=0.7)
    for m in side_motions(R, e0, 1.0, H, bits=(0, 0)):
        assert _rhs_residual(model, R, m.s, m.alphas) < 1e-14


# ---------------------------------------------------------------- stability, T6b

def _config_state(model, R, e0, H, bits):
    """Exact equilibrium with the given bit pattern: of the two roots (5.66) the
    one with the weights of k_j = 0 nearer the heavy side (larger cos gamma)."""
    sm = side_motions(R, e0, net_unbalance(bits), H, bits=bits)
    m = max(sm, key=lambda x: math.cos(x.gamma))
    z = steady_state(model, m.s, m.alphas)
    assert np.max(np.abs(rotating_rhs(model, R, z))) < 1e-12
    return m, z


T6B_R = (0.3, 0.7, 1.5, 3.0, 10.0)
T6B = [  # (name, e0, bits, expected stability at T6B_R)
    ("heavy side", 0.5, (0, 0), (True, True, False, False, False)),
    ("light side", 0.5, (1, 1), (False,) * 5),
    ("light side", 1.5, (1, 1), (False, False, True, True, True)),
    ("opposite", 0.5, (0, 1), (False,) * 5),
    ("opposite", 1.5, (0, 1), (False,) * 5),
]


@pytest.mark.parametrize("name,e0,bits,expected", T6B)
def test_T6b_stability_table(name, e0, bits, expected):
    Rt, h, H = 0.01, 0.1, 0.1
    model = _model(2, Rt, h, H, e0)
    for R, stable in zip(T6B_R, expected):
        m, z = _config_state(model, R, e0, H, bits)
        ev = steady_eigenvalues(model, R, z)
        assert is_stable(ev) == stable, (name, e0, R, ev[:2])
        if name == "light side" and e0 == 1.5 and R in (1.5, 3.0):
            assert ev[0].real == pytest.approx({1.5: -0.036, 3.0: -0.050}[R], abs=0.002)
        if name == "light side" and e0 == 1.5 and R == 10.0:
            # the digest's equilibrium solver failed here; the closed form gives it
            assert ev[0].real == pytest.approx(-H / 2, abs=2e-3)
        if stable and bits[0] == bits[1]:
            # necessary condition (5.141): (-1)^k v~ > 0 for all weights on one side
            assert (-1) ** bits[0] * m.v > 0


def test_relative_mode_5140_and_cubic_5155_match_jacobian():
    """Conservative case H = h = 0, e0 > 1, x = R^2 > 1: the Jacobian's lambda^2
    are the roots of b3 y^3 + b2 y^2 + b1 y + b0 (5.155)-(5.158) plus the relative
    mode (5.140), lambda^2 = -(-1)^k 2 Rt R^2 v~ (k = 2^n - 1)."""
    for Rt, R, e0 in [(0.01, 1.5, 1.5), (0.01, 3.0, 1.2), (0.01, 2.0, 3.0), (0.05, 3.0, 1.2)]:
        model = _model(2, Rt, 0.0, 0.0, e0)
        (m,) = main_motion_angles(e0, 2, R=R, H=0.0)
        z = steady_state(model, m.s, m.alphas)
        assert np.max(np.abs(rotating_rhs(model, R, z))) < 1e-14
        lam2 = np.sort((steady_eigenvalues(model, R, z) ** 2).real)
        b = large_unbalance_coefficients(R, e0, Rt)
        assert np.all(b > 0)
        y = np.roots(b[::-1])
        assert np.all(np.abs(y.imag) < 1e-12) and np.all(y.real < 0)  # conservatively stable
        delta = -(-1) ** 3 * 2 * Rt * R * R * m.v
        ref = np.sort(np.concatenate([y.real, y.real, [delta, delta]]))
        assert lam2 == pytest.approx(ref, abs=1e-6)


def test_large_unbalance_coefficients_positive_and_stable_with_damping():
    """(5.155)-(5.161): all b_i > 0 for x > 1, e0 > 1; for Rt << 1 the e0 > 1
    main motion is stable above resonance -- with damping asymptotically."""
    for Rt in (0.001, 0.01, 0.1, 0.3, 0.49):
        for x in (1.001, 1.5, 4.0, 100.0):
            for e0 in (1.0001, 1.5, 5.0):
                assert np.all(large_unbalance_coefficients(math.sqrt(x), e0, Rt) > 0)
    Rt, h, H = 0.01, 0.1, 0.1
    for e0 in (1.1, 2.0):
        model = _model(2, Rt, h, H, e0)
        for R in (2.0, 3.0, 5.0):  # above the flutter band, see the next test
            (m,) = main_motion_angles(e0, 2, R=R, H=H)
            ev = steady_eigenvalues(model, R, steady_state(model, m.s, m.alphas))
            assert is_stable(ev), (e0, R, ev[0])


def test_flutter_band_just_above_resonance():
    """Not in the book: (5.160) makes the discriminant negative only as Rt -> 0.
    At finite Rt the cubic (5.155) has complex roots in a band just above
    resonance (Rt = 0.01, e0 = 1.5: about 1.146 < R < 1.495), and with damping
    the e0 > 1 main motion is unstable there -- like the main motion below its
    critical speed.  The band shrinks towards R = 1 as Rt -> 0."""
    def flutter(R, e0, Rt):
        return np.max(np.abs(np.roots(large_unbalance_coefficients(R, e0, Rt)[::-1]).imag)) > 1e-9

    assert flutter(1.3, 1.5, 0.01) and not flutter(1.1, 1.5, 0.01) and not flutter(1.52, 1.5, 0.01)
    assert flutter(1.8, 1.5, 0.05) and not flutter(1.3, 1.5, 0.05)  # band 1.48-2.23
    assert flutter(1.1, 1.5, 0.001) and not flutter(1.25, 1.5, 0.001)
    model = _model(2, 0.01, 0.1, 0.1, 1.5)
    for R, stable in ((1.02, True), (1.3, False), (2.0, True)):
        (m,) = main_motion_angles(1.5, 2, R=R, H=0.1)
        assert is_stable(steady_eigenvalues(model, R, steady_state(model, m.s, m.alphas))) == stable


# ---------------------------------------------------------------- the speed-map helper

def _labels(rs):
    return {r.label: r.stable for r in rs}


def test_stable_steady_motions_two_balls():
    Rt, h, H = 0.01, 0.1, 0.1
    model = _model(2, Rt, h, H, 0.5)
    low = _labels(stable_steady_motions(model, 0.5, 0.5, 2))
    assert low == {"main": False, "side k=0": True, "side k=2": False, "side k=1": False}
    win = _labels(stable_steady_motions(model, 1.0))  # inside the window of e_0 = 1
    assert win == {"main": False, "side k=1": False}
    high = stable_steady_motions(model, 3.0)
    assert _labels(high) == {"main": True, "side k=0": False, "side k=2": False,
                             "side k=1": False}
    for r in high:
        assert r.residual < 1e-12 and r.state.shape == (8,)
        assert abs(r.psi - (0.5 + np.sum(0.5 * np.exp(1j * r.alphas)))) < 1e-15
    main = high[0]
    assert abs(main.psi) < 1e-14 and main.max_re == pytest.approx(main.eigenvalues[0].real)
    big = _labels(stable_steady_motions(_scene(2, Rt, h, H, 1.5), 3.0))  # a Scene works too
    assert big == {"main (maximally balanced)": True, "side k=0": False, "side k=1": False}


def test_stable_steady_motions_three_balls():
    model = _model(3, 0.01, 0.1, 0.1, 0.3)
    low = stable_steady_motions(model, 0.5)
    assert [r.label for r in low] == ["main", "side k=0", "side k=3", "side k=1", "side k=2"]
    assert [r.label for r in low if r.stable] == ["side k=0"]  # section 4.5, conclusions 1-2
    assert low[0].family and low[0].neutral == 1
    high = stable_steady_motions(model, 3.0)
    assert [r.label for r in high if r.stable] == ["main"]
    # the weights of "side k=K": K of them at the light end of the line
    for r in high[1:]:
        far = sum(math.cos(a - r.gamma) < 0 for a in r.alphas)
        assert far == r.k and math.cos(r.gamma) > 0


def test_stable_steady_motions_single_weight():
    # one weight balances only e0 = 1; otherwise the main motion is the weight on the light side
    lab = stable_steady_motions(_model(1, 0.01, 0.1, 0.1, 0.5), 3.0)
    assert [(r.label, r.stable) for r in lab] == [("main (maximally balanced)", True),
                                                  ("side k=0", False)]
    assert abs(lab[0].psi) == pytest.approx(0.5, abs=1e-2)
    # |e(k)| = 1 > e0: inside the window (5.70) neither the weight on the light
    # side nor on the heavy side is a steady motion
    R1, R2 = side_window(0.5, 1.0, 0.1)
    assert stable_steady_motions(_model(1, 0.01, 0.1, 0.1, 0.5), 0.5 * (R1 + R2)) == []
    assert maximally_balanced_motion(1.0, 0.5, 0.1, n=1) is None
    assert main_motion_angles(0.5, 1, R=1.0, H=0.1) == []


@pytest.mark.parametrize("n, e0", [(2, 0.5), (3, 0.3), (2, 1.5)])
def test_stable_steady_motions_at_many_speeds_is_each_speed_alone(n, e0):
    """The batch (one stacked eigenvalue call, the balanced main motion found once) gives
    each speed's reports exactly: the same Jacobians, eigenvalues and verdicts."""
    from stand.theories.planar.steady_stability import stable_steady_motions_at

    model = _model(n, 0.01, 0.1, 0.1, e0)
    Rs = [0.5, 0.97, 1.3, 3.0]
    for R, batch in zip(Rs, stable_steady_motions_at(model, Rs)):
        alone = stable_steady_motions(model, R)
        assert [r.label for r in batch] == [r.label for r in alone]
        for a, b in zip(batch, alone):
            ev = steady_eigenvalues(model, R, a.state)
            assert np.array_equal(a.eigenvalues, ev) and np.array_equal(b.eigenvalues, ev)
            assert (a.stable, a.max_re, a.residual) == (b.stable, b.max_re, b.residual)
            assert a.stable == is_stable(ev, 1e-6, a.neutral)


def test_stable_steady_motions_rejects_inconsistent_input():
    model = _model(2, 0.01, 0.1, 0.1, 0.5)
    with pytest.raises(ValueError):
        stable_steady_motions(model, 1.0, e0=0.4)
    with pytest.raises(ValueError):
        stable_steady_motions(model, 1.0, n=3)
    with pytest.raises(ValueError):
        stable_steady_motions(_model(2, 0.01, 0.1, 0.1, 0.5, R_omega2=1.2), 1.0)
