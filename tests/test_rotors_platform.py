"""Paper 004 (Drach) suspended platform + rotor, model M3: oracles O14-O17
(papers digest 5.3) and the paper_exact / corrected switch."""
import dataclasses
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from stand.model.rotors.platform import (
    Hanger, PlatformParams, default_params, quadrifilar_hangers, linkage_coefficients,
    hanger_vector, mass_matrix, gyro_matrix, damping_matrix, stiffness_matrix,
    plane_map, force_amplitude, generalized_force, platform_rotor, modal_frequencies,
    campbell,
)

HALF_PI = 0.5 * math.pi


def generic_params(**kw) -> PlatformParams:
    """Moderate, fully coupled set: inclined rods, offsets, diaphragm off-axis,
    horizontal dampers so that every mode is damped (zeta >~ 0.1)."""
    S, b, h, zk = 0.6, 0.5, 0.5, 0.1
    hangers = quadrifilar_hangers(S, S, b, b, h, zk, c=2.0e4, damping=100.0) + (
        Hanger(0.0, 0.3, -zk, 0.4, HALF_PI, 0.0, 0.0, 60.0),
        Hanger(0.0, -0.3, -zk, 0.4, HALF_PI, 0.0, 0.0, 60.0),
        Hanger(0.3, 0.0, -zk, 0.4, HALF_PI, HALF_PI, 0.0, 60.0),
        Hanger(-0.3, 0.0, -zk, 0.4, HALF_PI, HALF_PI, 0.0, 60.0),
    )
    base = dict(m=20.0, m2=5.0, I_a1=0.8, I_b1=0.9, I_c1=1.0, I_p=0.2,
                S1=S, S2=S, b1=b, b2=b, h=h, z_k=zk, hangers=hangers,
                c2x=300.0, c2y=400.0, c2z=500.0, x_M=0.05, y_M=-0.04, z_M=0.2,
                x_D=0.03, y_D=-0.02, z_D=0.15, e=0.01, g=9.81)
    base.update(kw)
    return PlatformParams(**base)


def vertical_params(b1=0.6, b2=0.6, h=0.8, c=5.0e3, damping=0.0, **kw) -> PlatformParams:
    """Four vertical hangers (S = b) at (+-b1/2, +-b2/2), x_D = y_D = 0,
    no diaphragm (digest 3.8 simple configuration)."""
    zk = 0.1
    base = dict(m=30.0, m2=8.0, I_a1=1.2, I_b1=1.2, I_c1=1.5, I_p=0.3,
                S1=b1, S2=b2, b1=b1, b2=b2, h=h, z_k=zk,
                hangers=quadrifilar_hangers(b1, b2, b1, b2, h, zk, c=c, damping=damping),
                x_D=0.0, y_D=0.0, z_D=0.0, e=1e-3, g=9.81)
    base.update(kw)
    return PlatformParams(**base)


# ----------------------------------------------------------------------- O14
@pytest.mark.parametrize("paper_exact", [False, True])
@pytest.mark.parametrize("make", [default_params, generic_params])
def test_o14_structure(make, paper_exact):
    p = make()
    r = platform_rotor(p, paper_exact=paper_exact)
    for X in (r.M, r.K, r.D):
        assert np.array_equal(X, X.T)
    assert np.array_equal(r.G, -r.G.T)
    assert np.linalg.eigvalsh(r.M).min() > 0
    assert np.linalg.eigvalsh(r.D).min() > -1e-12 * np.abs(r.D).max()
    assert np.linalg.eigvalsh(r.K).min() > 0                  # A > 0 incl. gravity
    assert np.array_equal(r.D, damping_matrix(p))
    assert not damping_matrix(dataclasses.replace(p, hangers=tuple(
        dataclasses.replace(hg, damping=0.0) for hg in p.hangers))).any()
    assert r.coords == ("x [m]", "y [m]", "z [m]", "alpha [rad]", "beta [rad]", "gamma [rad]")
    assert set(r.planes) == {"rotor", "balancer"}
    # G proportional to omega: LinearRotor carries it per unit spin
    assert r.G[3, 4] == pytest.approx((2.0 if paper_exact else 1.0) * p.I_p, rel=0, abs=0)


def test_o14_axis_through_O_leaves_only_m15_m24():
    p = generic_params(x_D=0.0, y_D=0.0)
    c = linkage_coefficients(p)
    assert c["d3"] != 0 and c["d4"] != 0
    for paper_exact in (False, True):
        M = mass_matrix(p, paper_exact)
        off = M - np.diag(np.diag(M))
        nz = {tuple(ij) for ij in np.argwhere(off != 0)}
        assert nz == {(0, 4), (4, 0), (1, 3), (3, 1)}
        assert M[0, 4] == p.I_b1 * c["d3"] + p.m2 * p.z_D
        assert M[1, 3] == -p.I_a1 * c["d4"] - p.m2 * p.z_D
        F = force_amplitude(p, 30.0, paper_exact)
        assert F[5] == 0 and F[2] == 0                          # F_gamma = 0 (l. 334)


def test_o14_vertical_hangers_d3_d4_zero():
    p = generic_params(S1=0.5, S2=0.7, b1=0.5, b2=0.7)
    c = linkage_coefficients(p)
    assert c["d3"] == 0.0 and c["d4"] == 0.0
    assert c["delta1"] == pytest.approx(1.0 / p.h, rel=1e-15)
    assert c["delta2"] == pytest.approx(1.0 / p.h, rel=1e-15)
    G = gyro_matrix(p)
    assert {tuple(ij) for ij in np.argwhere(G != 0)} == {(3, 4), (4, 3)}


def test_o14_no_diaphragm_switches_agree_on_A():
    p = generic_params(c2x=0.0, c2y=0.0, c2z=0.0)
    assert np.array_equal(stiffness_matrix(p), stiffness_matrix(p, paper_exact=True))


# ------------------------------------------------- paper_exact vs corrected
def _mask(a, b):
    return {tuple(ij) for ij in np.argwhere(a != b)}


def test_paper_exact_differs_exactly_in_flagged_entries():
    p = generic_params()
    c = linkage_coefficients(p)
    d3, d4 = c["d3"], c["d4"]
    # M: only M_14 = M_41
    Mc, Mp = mass_matrix(p), mass_matrix(p, paper_exact=True)
    assert _mask(Mc, Mp) == {(0, 3), (3, 0)}
    assert Mc[0, 3] == pytest.approx(-p.m2 * p.x_D * p.y_D * d3, rel=1e-15)
    assert Mp[0, 3] == pytest.approx(-p.m2 * p.y_D * d3, rel=1e-15)
    # A: a23, a25, a26, a56, a66
    Ac, Ap = stiffness_matrix(p), stiffness_matrix(p, paper_exact=True)
    flagged = {(1, 2), (1, 4), (1, 5), (4, 5), (5, 5)}
    assert _mask(Ac, Ap) == flagged | {(j, i) for i, j in flagged}
    xm, ym, zm = p.x_M, p.y_M, p.z_M
    dA = Ac - Ap
    assert dA[1, 2] == pytest.approx(-p.c2z * ym * d4 + p.c2x * ym * d4, rel=1e-12)
    assert dA[1, 4] == pytest.approx(p.c2z * xm * ym * d4, rel=1e-12)
    assert dA[1, 5] == pytest.approx(2 * p.c2y * xm * (1 + zm * d4), rel=1e-12)
    assert dA[4, 5] == pytest.approx(-p.c2x * ym * zm + p.c2y * ym * zm, rel=1e-12)
    assert dA[5, 5] == pytest.approx(p.c2x * (ym ** 2 - zm ** 2), rel=1e-12)
    # unflagged A entries bit-identical
    # G: gyro factor 2 in print
    assert np.array_equal(gyro_matrix(p, paper_exact=True), 2.0 * gyro_matrix(p))
    # D and the plane maps do not depend on the switch
    rc, rp = platform_rotor(p), platform_rotor(p, paper_exact=True)
    assert np.array_equal(rc.D, rp.D)
    for name in rc.planes:
        assert np.array_equal(rc.planes[name], rp.planes[name])
    # F: F_beta, F_gamma only
    w = 17.0
    Fc, Fp = force_amplitude(p, w), force_amplitude(p, w, paper_exact=True)
    assert {int(i) for i in np.nonzero(Fc != Fp)[0]} == {4, 5}
    s = p.m2 * p.e * w * w
    assert Fc[4] == pytest.approx(s * p.z_D, rel=1e-15)                      # cos
    assert Fp[4] == pytest.approx(-1j * s * p.z_D, rel=1e-15)                # sin
    assert Fc[5] == pytest.approx(s * (-p.y_D - 1j * p.x_D), rel=1e-15)      # x sin - y cos
    assert Fp[5] == pytest.approx(s * (p.y_D - 1j * p.x_D), rel=1e-15)      # y cos + x sin


def test_plane_map_reproduces_corrected_force():
    p = generic_params()
    r = platform_rotor(p)
    T = r.planes["rotor"]
    for w in (3.0, 40.0):
        f = p.m2 * p.e * w * w * (T.T @ np.array([1.0, -1j]))
        assert np.allclose(f, force_amplitude(p, w), rtol=1e-15, atol=0)
    assert r.unbalances[0].plane == "rotor" and r.unbalances[0].s == pytest.approx(p.m2 * p.e)
    # balancer defaults to the rotor disk, z_B moves it along the spin axis
    assert np.array_equal(r.planes["balancer"], T)
    rb = platform_rotor(dataclasses.replace(p, z_B=0.4))
    assert np.array_equal(rb.planes["balancer"], plane_map(p, 0.4))
    assert not np.array_equal(rb.planes["balancer"], T)


@pytest.mark.parametrize("paper_exact", [False, True])
def test_generalized_force_matches_amplitude(paper_exact):
    p = generic_params()
    w = 11.0
    Fh = force_amplitude(p, w, paper_exact)
    for t in (0.0, 0.123, 1.7):
        f = generalized_force(p, w * t, w, 0.0, paper_exact)
        assert np.allclose(f, (Fh * np.exp(1j * w * t)).real, rtol=0, atol=1e-14 * np.abs(Fh).max())


def test_rod_stiffness_is_hessian_of_exact_elongation():
    """(18)-(19) against an independent finite-difference Hessian of the rod
    elongation |l_i + dr_i(q)| - l_i with (5), alpha -> alpha - d4 y, beta -> beta + d3 x."""
    p = generic_params(c2x=0.0, c2y=0.0, c2z=0.0, g=0.0)
    c = linkage_coefficients(p)
    d3, d4 = c["d3"], c["d4"]

    def elong(hg, q):
        x, y, z, a, b, gm = q
        a1, b1 = a - d4 * y, b + d3 * x
        dr = np.array([x + b1 * hg.z - gm * hg.y, y + gm * hg.x - a1 * hg.z, z + a1 * hg.y - b1 * hg.x])
        return np.linalg.norm(hg.rod_vector() + dr) - hg.length

    A = np.zeros((6, 6))
    eps = 1e-6
    for hg in p.hangers:
        grad = np.array([(elong(hg, eps * e) - elong(hg, -eps * e)) / (2 * eps) for e in np.eye(6)])
        A += hg.c * np.outer(grad, grad)
        Dref = hg.damping * np.outer(grad, grad)            # (37), (41): same form
        assert np.allclose(damping_matrix(dataclasses.replace(p, hangers=(hg,))), Dref,
                           rtol=1e-7, atol=1e-7 * (np.abs(Dref).max() + 1e-300))
        assert np.allclose(grad, hanger_vector(hg, d3, d4) / hg.length, atol=1e-8)
    assert np.allclose(stiffness_matrix(p), A, rtol=1e-7, atol=1e-7 * np.abs(A).max())


def test_corrected_diaphragm_is_quadratic_form_of_eq25():
    """Corrected diaphragm part of A = Hessian of (c_2x dx^2 + c_2y dy^2 + c_2z dz^2)/2
    with the displacements (25) of point M."""
    p = generic_params()
    bare = dataclasses.replace(p, c2x=0.0, c2y=0.0, c2z=0.0)
    c = linkage_coefficients(p)
    d3, d4 = c["d3"], c["d4"]
    xm, ym, zm = p.x_M, p.y_M, p.z_M
    P = np.array([[1 + zm * d3, 0, 0, 0, zm, -ym],
                  [0, 1 + zm * d4, 0, -zm, 0, xm],
                  [-xm * d3, -ym * d4, 1, ym, -xm, 0]])
    ref = P.T @ np.diag([p.c2x, p.c2y, p.c2z]) @ P
    dA = stiffness_matrix(p) - stiffness_matrix(bare)
    assert np.allclose(dA, ref, rtol=1e-9, atol=1e-9 * np.abs(ref).max())


# ----------------------------------------------------------------------- O15
@pytest.mark.parametrize("b1,b2", [(0.6, 0.6), (0.5, 0.9)])
def test_o15_vertical_hanger_frequencies(b1, b2):
    h = 0.8
    p = vertical_params(b1=b1, b2=b2, h=h)                  # m2 z_D = 0, c_2 = 0
    w = modal_frequencies(p)
    n = len(p.hangers)
    csum = sum(hg.c for hg in p.hangers)
    expected = [
        math.sqrt(p.g / h), math.sqrt(p.g / h),                              # pendulum x, y
        math.sqrt(csum / p.m),                                               # bounce z
        math.sqrt(p.m * p.g * (b1 ** 2 + b2 ** 2) / (4 * h * p.I_c1)),       # torsion gamma
        math.sqrt(sum(hg.c * hg.y ** 2 for hg in p.hangers) / p.I_a1),       # rocking alpha
        math.sqrt(sum(hg.c * hg.x ** 2 for hg in p.hangers) / p.I_b1),       # rocking beta
    ]
    assert n == 4
    assert np.allclose(np.sort(w), np.sort(expected), rtol=1e-10, atol=0)
    # both switches agree here (no diaphragm, x_D = y_D = 0)
    assert np.allclose(modal_frequencies(p, paper_exact=True), w, rtol=1e-12)


def test_o15_pendulum_with_rotor_height_is_2x2_problem():
    """m2 z_D != 0 couples x and beta: M = [[m, m2 zD], [m2 zD, I_b]], K = diag(mg/h, sum c x_i^2)."""
    p = vertical_params(z_D=0.2)
    M2 = np.array([[p.m, p.m2 * p.z_D], [p.m2 * p.z_D, p.I_b1]])
    K2 = np.diag([p.m * p.g / p.h, sum(hg.c * hg.x ** 2 for hg in p.hangers)])
    from scipy.linalg import eigh
    ref = np.sqrt(eigh(K2, M2, eigvals_only=True))
    w = modal_frequencies(p)
    for f in ref:
        assert np.min(np.abs(w - f)) <= 1e-10 * f


# ----------------------------------------------------------------------- O16
@pytest.mark.parametrize("paper_exact", [False, True])
def test_o16_harmonic_steady_state_equals_integration(paper_exact):
    p = generic_params()
    r = platform_rotor(p, paper_exact=paper_exact)
    w = 12.0
    Fh = force_amplitude(p, w, paper_exact)
    Qh = np.linalg.solve(r.K - w * w * r.M + 1j * w * (w * r.G + r.D), Fh)
    # every mode damped; integrate until the transient is below 1e-9
    sigma = -r.eigenvalues(w).real.max()
    assert sigma > 0.5
    period = 2 * math.pi / w
    t_end = period * math.ceil((21.0 / sigma) / period)
    Minv = np.linalg.inv(r.M)
    C = r.D + w * r.G
    # at constant speed the hook's force is Fc cos(w t) + Fs sin(w t): checked at 17 angles
    # (one of them off the grid), then the first-order system y' = A y + b(t) is cheap to
    # evaluate (the integration is the same; ~2x less CPU than calling the hook per stage)
    Fc, Fs = (generalized_force(p, a, w, 0.0, paper_exact) for a in (0.0, 0.5 * math.pi))
    for a in np.append(np.linspace(0.0, 2 * math.pi, 16), 12.345):
        assert np.allclose(generalized_force(p, a, w, 0.0, paper_exact),
                           Fc * math.cos(a) + Fs * math.sin(a), rtol=1e-13,
                           atol=1e-13 * abs(Fc).max())
    A = np.block([[np.zeros((6, 6)), np.eye(6)], [-Minv @ r.K, -Minv @ C]])
    bc, bs = np.concatenate([np.zeros(6), Minv @ Fc]), np.concatenate([np.zeros(6), Minv @ Fs])

    def rhs(t, y):
        return A @ y + math.cos(w * t) * bc + math.sin(w * t) * bs

    t_eval = t_end - period + np.linspace(0.0, period, 17)
    sol = solve_ivp(rhs, (0.0, t_end), np.zeros(12), method="DOP853", rtol=1e-11,
                    atol=1e-13, t_eval=t_eval)
    assert sol.success
    q_ss = (Qh[:, None] * np.exp(1j * w * t_eval)[None, :]).real
    err = np.abs(sol.y[:6] - q_ss).max() / np.abs(Qh).max()
    assert err < 1e-6, err
    # the LinearRotor unbalance response agrees with the hook for the corrected F
    if not paper_exact:
        X = r.unbalance_response(w, "rotor", s=p.m2 * p.e)
        assert np.allclose(X, r.planes["rotor"] @ Qh, rtol=1e-12)


# ----------------------------------------------------------------------- O17
@pytest.mark.parametrize("paper_exact,factor", [(False, 1.0), (True, 2.0)])
def test_o17_campbell_tilt_pair_split(paper_exact, factor):
    p = vertical_params(I_a1=1.1, I_b1=1.1, I_p=0.9)         # d3 = d4 = 0, x_D = y_D = 0, z_D = 0
    I, Ip = p.I_a1, p.I_p
    k = sum(hg.c * hg.y ** 2 for hg in p.hangers)
    assert k == pytest.approx(sum(hg.c * hg.x ** 2 for hg in p.hangers), rel=1e-15)
    speeds = np.array([0.0, 20.0, 80.0, 250.0])
    data = campbell(p, speeds, paper_exact=paper_exact)
    assert data.shape == (4, 6)
    wrong = 2.0 / factor                                       # the other convention
    for om, row in zip(speeds, data):
        b = factor * Ip * om
        fwd = (b + math.sqrt(b * b + 4 * I * k)) / (2 * I)     # I W^2 - f Ip w W - k = 0
        bwd = (-b + math.sqrt(b * b + 4 * I * k)) / (2 * I)    # I W^2 + f Ip w W - k = 0
        for W in (fwd, bwd):
            assert I * W * W - b * W - k == pytest.approx(0, abs=1e-9 * k) or \
                I * W * W + b * W - k == pytest.approx(0, abs=1e-9 * k)
            assert np.min(np.abs(row - W)) <= 1e-9 * W
        if om > 0:
            bw = wrong * Ip * om
            W_wrong = (bw + math.sqrt(bw * bw + 4 * I * k)) / (2 * I)
            assert np.min(np.abs(row - W_wrong)) > 1e-3 * W_wrong


# ----------------------------------------------------------------------- misc
def test_default_params_stiff_ratio_and_modal():
    p = default_params()
    w = modal_frequencies(p)
    assert np.all(w > 0) and np.all(np.diff(w) >= 0)
    assert 1.5 < w[0] < 4.0                                    # pendulum ~2-3 rad/s
    assert 400 < w[3] < 600                                    # axial springs ~500 rad/s
    w2, U = modal_frequencies(p, return_modes=True)
    assert np.allclose(U.T @ mass_matrix(p) @ U, np.eye(6), atol=1e-10)
    # default rotor: the criterion is finite and the Campbell data have 6 columns
    r = platform_rotor()
    assert np.isfinite(r.criterion(100.0, "balancer"))
    assert r.campbell([0.0, 50.0]).shape == (2, 6)


@pytest.mark.parametrize("field,value,unit", [
    ("m", -1.0, "kg"), ("h", 0.0, "m"), ("c2x", -5.0, "N/m"), ("e", float("nan"), "m"),
    ("I_p", -0.1, "kg m^2"),
])
def test_bad_input_names_parameter_value_unit(field, value, unit):
    with pytest.raises(ValueError) as ei:
        generic_params(**{field: value})
    msg = str(ei.value)
    assert field in msg and unit in msg and repr(value) in msg


def test_bad_hanger_and_singular_linkage():
    with pytest.raises(ValueError, match=r"Hanger.length.*\[m\]"):
        Hanger(0, 0, 0, -1.0)
    with pytest.raises(ValueError, match=r"Hanger.damping.*N s/m"):
        Hanger(0, 0, 0, 1.0, damping=-2.0)
    # b1 h + z_k (S1 - b1) = 0: geometric singularity of d_3
    with pytest.raises(ValueError, match=r"b1\*h \+ z_k\*\(S1 - b1\)"):
        generic_params(S1=1.0, b1=0.5, h=0.5, z_k=-0.5)
    with pytest.raises(ValueError, match=r"m2 = .*kg"):
        generic_params(m2=50.0)
