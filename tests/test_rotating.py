"""Rotating-frame Jacobian at a main motion vs the book's characteristic polynomial.

Oracles: digest ch5 section 4.1 and test T2 of section 8.3 -- the corrected
model linearised at a balanced state has for n = 3 the 8 roots of (5.90) plus
0 (motion along the family) and -h as eigenvalues.  The n = 2 case of T2 (the
digest's printed eigenvalues) is checked in tests/test_theory_main.py.
"""
import numpy as np
import pytest

from stand.theories.rotating import main_motion_state, rotating_jacobian, rotating_rhs
from stand.theories.planar.main_motion import main_eigenvalues

from _helpers import dimensionless_model, match_roots


@pytest.mark.parametrize("W", [1.5, 3.0, 7.0])
def test_three_balls_roots_plus_zero_and_minus_h(W):
    Rt, h, H = 0.04, 0.3, 0.2
    # a balanced configuration of 3 equal balls for e0 = 0.5 (5.50):
    # sum e^{i alpha_j} = -3 e0; put ball 1 at pi and choose alpha_2 so that the
    # remainder has unit length, then ball 3 closes the polygon.
    from scipy.optimize import brentq
    e0 = 0.5
    f = lambda a2: abs(-3 * e0 - np.exp(1j * np.pi) - np.exp(1j * a2)) - 1
    a2 = brentq(f, 0.5, np.pi, xtol=1e-15)
    a3 = np.angle(-3 * e0 - np.exp(1j * np.pi) - np.exp(1j * a2))
    alphas = [np.pi, a2, a3]
    m = dimensionless_model(3, W, Rt, h, H, e0)
    z = main_motion_state(m, alphas)
    # equilibrium up to the root-finder's angle error times R^2
    assert np.max(np.abs(rotating_rhs(m, W, z))) < 1e-12 * W ** 2
    ev = np.linalg.eigvals(rotating_jacobian(m, W, z))
    d = abs(np.mean(np.exp(2j * np.array(alphas))))  # (5.88) for identical point balls
    rest = match_roots(ev, main_eigenvalues(W, Rt, h, H, d), 1e-6)
    assert sorted(rest, key=lambda x: x.real) == pytest.approx([-h, 0.0], abs=1e-6)


def test_planar_jacobian_is_the_column_by_column_central_difference():
    """The planar Jacobian (all 2 x 8 + 1 evaluations in one kernel loop, shaft conversions on
    whole columns) is, bit for bit, column i = (rhs(z + dz_i) - rhs(z - dz_i)) / (2 dz_i) of
    :func:`rotating_rhs` one state at a time: the same floating-point operations."""
    from stand.theories.rotating import rotating_rhs_and_jacobian

    m = dimensionless_model(2, 2.5, 0.04, 0.3, 0.2, 0.5)
    rng = np.random.default_rng(7)
    for R in (0.4, 1.0, 2.5, 40.0):
        z = rng.normal(size=8) * 3.0
        z[[2, 5]] = 0.0
        J = np.empty((8, 8))
        for i in range(8):
            dz = np.zeros(8)
            dz[i] = 1e-7 * max(1.0, abs(z[i]))
            J[:, i] = (rotating_rhs(m, R, z + dz) - rotating_rhs(m, R, z - dz)) / (2 * dz[i])
        f, J2 = rotating_rhs_and_jacobian(m, R, z)
        assert np.array_equal(J2, J) and np.array_equal(rotating_jacobian(m, R, z), J)
        assert np.array_equal(f, rotating_rhs(m, R, z))
