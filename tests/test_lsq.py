"""dsp.lsq: the covariance of a least-squares fit whose parameters are in units decades apart.

A parameter in small units (a sensor's lag in ms^2 next to a frequency in rad/s) makes
J'J badly scaled, not singular; its inverse must still carry that parameter's freedom into
the others' variance (issue 42: the unscaled pseudo-inverse cut it, and the run-up fit with
a free sensor response gave its natural frequency a std of 1e-13 Hz)."""
import numpy as np
import pytest

from dsp.lsq import covariances, normal_inverse, std_of


def _two_columns(rho, scale, n=400, seed=0):
    """Two unit-norm columns with correlation ``rho``, the second times ``scale``."""
    rng = np.random.default_rng(seed)
    a, b = rng.normal(size=(2, n))
    a /= np.linalg.norm(a)
    b -= (b @ a) * a
    b /= np.linalg.norm(b)
    return np.column_stack((a, scale * (rho * a + np.sqrt(1 - rho * rho) * b)))


@pytest.mark.parametrize("scale", [1.0, 1e-9])
def test_variance_with_a_correlated_nuisance_in_small_units(scale):
    """Closed form: unit columns of correlation rho give var(p0) = 1 / (1 - rho^2) (the
    (0, 0) element of [[1, rho], [rho, 1]]^-1), whatever the second parameter's unit; it
    must not fall to 1, the value with the nuisance cut out (the unscaled pinv's at 1e-9:
    J'J's eigenvalues ~1 and 1e-18 (1 - rho^2), the second below its cut at 1e-13)."""
    rho = 0.9
    J = _two_columns(rho, scale)
    Ai = normal_inverse(J)
    assert Ai[0, 0] == pytest.approx(1.0 / (1.0 - rho * rho), rel=1e-8)
    assert Ai[1, 1] == pytest.approx(1.0 / (1.0 - rho * rho) / scale ** 2, rel=1e-8)


def test_covariances_white_part_is_s2_times_the_inverse():
    """White part s^2 (J'J)^-1, s^2 = |r|^2 / (2N - P): on the badly scaled pair with a
    residual of known size, the first parameter's std is s / sqrt(1 - rho^2)."""
    rho, n = 0.6, 200
    J = _two_columns(rho, 1e-10, n=2 * n)
    r = np.full(n, 0.5 + 0.5j)                       # |r|^2 = 0.5 per sample
    white, _ = covariances(J, r, 2)
    s2 = 0.5 * n / (2 * n - 2)
    assert std_of(white, 0, np.array([1.0])) == pytest.approx(np.sqrt(s2 / (1 - rho * rho)), rel=1e-8)
