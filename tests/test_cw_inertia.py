"""Tables 2.1 / 2.2 (stand.model.rotors.cw_inertia) against independent numerical integration.

Every body is rebuilt from its geometry as a quadrature point cloud (tensor
Gauss-Legendre rules over the body's own coordinates, or scipy.integrate for the
half annulus) and its mass, centre of mass and inertia tensor about the
suspension point K are integrated directly.  Axes: xi normal to the figure,
eta and zeta in it, the centre of mass on -zeta (digest ch2_ch3 section 3.2).
"""
import math

import numpy as np
import pytest
from scipy import integrate

from stand.model.rotors import cw_inertia as cw

RTOL = 1e-6


# ------------------------------------------------------------------ helpers
def gl(lo, hi, n=48):
    x, w = np.polynomial.legendre.leggauss(n)
    return 0.5 * (hi - lo) * x + 0.5 * (hi + lo), 0.5 * (hi - lo) * w


def moments(points, weights):
    """Mass, centre of mass and inertia tensor about K (the origin) of a point cloud."""
    r = np.asarray(points, dtype=float).reshape(-1, 3)
    w = np.asarray(weights, dtype=float).ravel()
    m = w.sum()
    com = (w[:, None] * r).sum(0) / m
    J = np.einsum("k,k->", w, (r * r).sum(1)) * np.eye(3) - np.einsum("k,ki,kj->ij", w, r, r)
    return m, com, J


def half_annulus_cloud(R, a, density, h=None):
    """Half annulus (zeta <= 0) in the (eta, zeta) plane; a plate of thickness h
    along xi if h is given (density per volume), else a thin lamina (per area)."""
    rho, wr = gl(a * R, R)
    th, wt = gl(math.pi, 2 * math.pi)
    xs, wx = (np.array([0.0]), np.array([1.0])) if h is None else gl(-h / 2, h / 2, 8)
    P, W = [], []
    for x, wxx in zip(xs, wx):
        RR, TT = np.meshgrid(rho, th, indexing="ij")
        WW = np.outer(wr, wt) * RR * wxx * density
        P.append(np.stack([np.full(RR.size, x), (RR * np.cos(TT)).ravel(),
                           (RR * np.sin(TT)).ravel()], 1))
        W.append(WW.ravel())
    return np.vstack(P), np.concatenate(W)


def hemisphere_cloud(R, a, density):
    r, wr = gl(a * R, R)
    th, wt = gl(0.0, math.pi / 2)                      # from the -zeta axis
    ps, wp = gl(0.0, 2 * math.pi)
    RR, TT, PP = np.meshgrid(r, th, ps, indexing="ij")
    W = np.einsum("i,j,k->ijk", wr, wt, wp) * RR ** 2 * np.sin(TT) * density
    P = np.stack([(RR * np.sin(TT) * np.cos(PP)).ravel(), (RR * np.sin(TT) * np.sin(PP)).ravel(),
                  (-RR * np.cos(TT)).ravel()], 1)
    return P, W.ravel()


def rot_xi(angle):
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def two_directions():
    """Rotations taking the own pendulum axis -z0 to the two directions at +-45 deg from -zeta."""
    return [rot_xi(math.pi / 4), rot_xi(-math.pi / 4)]


def three_directions():
    """Rotations taking the basis e_1, e_2, e_3 ... here: rotation R_k taking -z0 to e_k,
    where (e_1, e_2, e_3) are mutually perpendicular and symmetric about -zeta."""
    u = np.ones(3) / math.sqrt(3)
    v1 = np.array([1.0, -1.0, 0.0]) / math.sqrt(2)
    v2 = np.cross(u, v1)
    Rg = np.vstack([v1, v2, -u])                      # Rg u = (0, 0, -1)
    e = [Rg @ b for b in np.eye(3)]
    out = []
    for ek in e:                                      # rotation taking (0,0,-1) to ek
        z = -ek
        x = np.cross([0.3, 0.5, 0.7], z)
        x /= np.linalg.norm(x)
        y = np.cross(z, x)
        out.append(np.column_stack([x, y, z]))
    return out


def check(inertia, m, com, J, table2=False):
    assert inertia.m == pytest.approx(m, rel=RTOL)
    assert abs(com[0]) < 1e-9 * inertia.l and abs(com[1]) < 1e-9 * inertia.l
    assert com[2] < 0
    assert inertia.l == pytest.approx(-com[2], rel=RTOL)
    assert inertia.S == pytest.approx(m * -com[2], rel=RTOL)
    scale = abs(J).max()
    if table2:
        np.testing.assert_allclose(J, inertia.A * np.eye(3), rtol=0, atol=RTOL * scale)
    else:
        assert inertia.A == pytest.approx(J[0, 0], rel=RTOL)
        assert inertia.B == pytest.approx(J[1, 1], rel=RTOL)
        assert inertia.B == pytest.approx(J[2, 2], rel=RTOL)
        off = J - np.diag(np.diag(J))
        assert abs(off).max() < RTOL * scale


# --------------------------------------------------------------- Table 2.1
def test_two_point_pendulums():
    m0, l0 = 0.3, 0.07
    P = [Rk @ np.array([0, 0, -l0]) for Rk in two_directions()]
    check(cw.two_point_pendulums(m0, l0), *moments(P, [m0, m0]))


def test_two_rods():
    m0, l0 = 0.3, 0.07
    s, w = gl(0.0, l0)
    P = np.vstack([np.outer(s, Rk @ np.array([0, 0, -1.0])) for Rk in two_directions()])
    W = np.concatenate([w * m0 / l0] * 2)
    check(cw.two_rods(m0, l0), *moments(P, W))


def cuboid_pendulum(d, L, bx, by, rho):
    """A cuboid hanging along -z0 from distance d to d + L below K, section bx x by."""
    x, wx = gl(-bx / 2, bx / 2, 6)
    y, wy = gl(-by / 2, by / 2, 6)
    z, wz = gl(-d - L, -d, 6)
    X, Y, Z = np.meshgrid(x, y, z, indexing="ij")
    return np.stack([X.ravel(), Y.ravel(), Z.ravel()], 1), np.einsum("i,j,k->ijk", wx, wy, wz).ravel() * rho


def test_two_physical_pendulums():
    P1, W1 = cuboid_pendulum(0.02, 0.05, 0.012, 0.03, 7800.0)
    m0, com0, J0 = moments(P1, W1)                  # own principal moments about K
    assert abs(J0 - np.diag(np.diag(J0))).max() < 1e-12 * abs(J0).max()
    P = np.vstack([P1 @ Rk.T for Rk in two_directions()])
    check(cw.two_physical_pendulums(m0, -com0[2], J0[0, 0], J0[1, 1], J0[2, 2]),
          *moments(P, np.concatenate([W1, W1])))


@pytest.mark.parametrize("a", [0.0, 0.3, 0.7])
def test_half_ring_numerical_uses_one_plus_a2(a):
    R, m0 = 0.05, 0.2
    area = 0.5 * math.pi * R ** 2 * (1 - a * a)
    P, W = half_annulus_cloud(R, a, m0 / area)
    ring = cw.half_ring(R, m0, a)
    check(ring, *moments(P, W))
    assert ring.A == pytest.approx(0.5 * m0 * R ** 2 * (1 + a * a), rel=1e-14)
    printed = cw.half_ring(R, m0, a, paper_exact=True)
    assert printed.A == pytest.approx(0.5 * m0 * R ** 2 * (1 - a * a), rel=1e-14)
    if a > 0:       # the printed (1 - a^2) misses the numerical value
        assert abs(printed.A / moments(P, W)[2][0, 0] - 1) > 0.05


def test_half_ring_scipy_dblquad():
    """Same check with adaptive scipy quadrature in polar coordinates (A = polar moment)."""
    R, m0, a = 0.05, 0.2, 0.6
    sigma = m0 / (0.5 * math.pi * R ** 2 * (1 - a * a))
    opts = dict(epsabs=0, epsrel=1e-12)
    mass = integrate.dblquad(lambda r, t: sigma * r, math.pi, 2 * math.pi, a * R, R, **opts)[0]
    A = integrate.dblquad(lambda r, t: sigma * r ** 3, math.pi, 2 * math.pi, a * R, R, **opts)[0]
    B = integrate.dblquad(lambda r, t: sigma * r ** 3 * math.sin(t) ** 2, math.pi, 2 * math.pi,
                          a * R, R, **opts)[0]
    zc = integrate.dblquad(lambda r, t: sigma * r ** 2 * math.sin(t), math.pi, 2 * math.pi,
                           a * R, R, **opts)[0] / mass
    ring = cw.half_ring(R, m0, a)
    assert mass == pytest.approx(m0, rel=1e-10)
    assert ring.A == pytest.approx(A, rel=RTOL)
    assert ring.B == pytest.approx(B, rel=RTOL)
    assert ring.l == pytest.approx(-zc, rel=RTOL)


def test_half_disk():
    R, m0 = 0.05, 0.2
    P, W = half_annulus_cloud(R, 0.0, m0 / (0.5 * math.pi * R ** 2))
    check(cw.half_disk(R, m0), *moments(P, W))


@pytest.mark.parametrize("a", [0.0, 0.4])
def test_hollow_and_solid_half_cylinder(a):
    R, h, g = 0.05, 0.03, 7800.0
    P, W = half_annulus_cloud(R, a, g, h=h)
    body = cw.hollow_half_cylinder(R, h, g, a) if a else cw.solid_half_cylinder(R, h, g)
    check(body, *moments(P, W))
    assert body.V == pytest.approx(W.sum() / g, rel=RTOL)


@pytest.mark.parametrize("a", [0.0, 0.25, 0.8])
def test_hollow_half_cylinder_consistent_with_half_ring(a):
    """A plate of thickness h is a stack of half-rings: A equal to the half-ring's
    (1 + a^2) value, B plus m h^2/12 -- the printed (1 - a^2) fails this."""
    R, h, g = 0.05, 0.03, 7800.0
    cyl = cw.hollow_half_cylinder(R, h, g, a)
    ring = cw.half_ring(R, cyl.m, a)
    assert cyl.A == pytest.approx(ring.A, rel=1e-13)
    assert cyl.B == pytest.approx(ring.B + cyl.m * h * h / 12, rel=1e-13)
    assert cyl.l == pytest.approx(ring.l, rel=1e-13)
    assert cyl.S == pytest.approx(ring.S, rel=1e-13)
    if a:
        assert cw.half_ring(R, cyl.m, a, paper_exact=True).A != pytest.approx(cyl.A, rel=1e-3)


# --------------------------------------------------------------- Table 2.2
def test_three_point_pendulums():
    m0, l0 = 0.3, 0.07
    P = [Rk @ np.array([0, 0, -l0]) for Rk in three_directions()]
    check(cw.three_point_pendulums(m0, l0), *moments(P, [m0] * 3), table2=True)


def test_three_rods():
    m0, l0 = 0.3, 0.07
    s, w = gl(0.0, l0)
    P = np.vstack([np.outer(s, Rk @ np.array([0, 0, -1.0])) for Rk in three_directions()])
    check(cw.three_rods(m0, l0), *moments(P, np.concatenate([w * m0 / l0] * 3)), table2=True)


def test_three_physical_pendulums():
    """Bodies of revolution: solid cylinders along -z0 from d to d + L."""
    rad, d, L, rho = 0.01, 0.02, 0.05, 7800.0
    r, wr = gl(0.0, rad, 10)
    t, wt = gl(0.0, 2 * math.pi, 24)
    z, wz = gl(-d - L, -d, 10)
    RR, TT, ZZ = np.meshgrid(r, t, z, indexing="ij")
    P1 = np.stack([(RR * np.cos(TT)).ravel(), (RR * np.sin(TT)).ravel(), ZZ.ravel()], 1)
    W1 = (np.einsum("i,j,k->ijk", wr, wt, wz) * RR * rho).ravel()
    m0, com0, J0 = moments(P1, W1)
    assert J0[0, 0] == pytest.approx(J0[1, 1], rel=1e-12)
    P = np.vstack([P1 @ Rk.T for Rk in three_directions()])
    check(cw.three_physical_pendulums(m0, -com0[2], J0[0, 0], J0[2, 2]),
          *moments(P, np.concatenate([W1] * 3)), table2=True)


@pytest.mark.parametrize("a", [0.0, 0.5])
def test_hemispheres(a):
    R, g = 0.04, 7800.0
    P, W = hemisphere_cloud(R, a, g)
    body = cw.hollow_hemisphere(R, g, a) if a else cw.solid_hemisphere(R, g)
    check(body, *moments(P, W), table2=True)
    assert body.V == pytest.approx(W.sum() / g, rel=RTOL)
    if not a:
        assert body.A == pytest.approx(0.4 * body.m * R * R, rel=1e-13)


# ----------------------------------------------------------- (2.14), errors
def test_auxiliary_2_14():
    m0, l0, R, h = 0.3, 0.07, 0.05, 0.02
    s, w = gl(0.0, l0)
    assert cw.rod_moment(m0, l0) == pytest.approx((w * s * s).sum() * m0 / l0, rel=1e-13)
    assert cw.rod_moment(m0, l0) == pytest.approx(m0 * l0 ** 2 / 3, rel=1e-14)
    assert cw.rod_moment(m0, l0, paper_exact=True) == pytest.approx(m0 * l0 ** 2 / 2, rel=1e-14)
    assert cw.two_rods(m0, l0).B == pytest.approx(cw.rod_moment(m0, l0), rel=1e-14)
    assert cw.pendulum_moment(m0, l0) == pytest.approx(m0 * l0 ** 2)
    assert cw.cylinder_volume(R, h) == pytest.approx(math.pi * R * R * h)
    assert cw.cylinder_moment(m0, R) == pytest.approx(m0 * R * R / 2)
    assert cw.half_cylinder_capacity(m0, R) == pytest.approx(cw.half_disk(R, m0).S, rel=1e-14)


@pytest.mark.parametrize("call, word", [
    (lambda: cw.half_ring(0.05, 0.2, 1.0), "a = r/R"),
    (lambda: cw.half_ring(-0.05, 0.2, 0.3), "R"),
    (lambda: cw.two_rods(0.3, 0.0), "l0"),
    (lambda: cw.hollow_hemisphere(0.04, -1.0, 0.3), "gamma"),
])
def test_bad_input_names_parameter(call, word):
    with pytest.raises(ValueError, match=word):
        call()
