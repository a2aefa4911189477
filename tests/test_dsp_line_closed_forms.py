"""The closed forms behind the fast line fit (dsp.line_gn, dsp.line_fast), against direct sums.

Each is a formula that replaces a length-N sum; the test evaluates the sum itself at
frequencies chosen to exercise every branch (the Taylor series near 0, lines exactly on a
bin, lines a bin apart, the wrap at +-1/2 cycle per sample).
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import fft as sfft

from dsp import line_fast as fast
from dsp import line_gn as gn
from dsp import lines as dl

N = 1000
M = np.arange(N) - 0.5 * (N - 1)                   # the centred grid
HANN_W = dl.window_weights(N, "hann")


_BRANCH = 2 * math.pi * N          # n |theta| = _BRANCH |dnu|: series below 0.2, closed form above


@pytest.mark.parametrize("dnu", [0.0, 1e-7, 0.19 / _BRANCH, 0.21 / _BRANCH, 0.999 / _BRANCH,
                                 -0.5 / _BRANCH, 0.3 / N, 1.0 / N, -1.0 / N, 2.7 / N, 0.37,
                                 -0.49])
def test_dirichlet_sums_match_direct_sums(dnu):
    c, s = np.cos(2 * math.pi * dnu * M), np.sin(2 * math.pi * dnu * M)
    direct = [math.fsum(c), 1j * math.fsum(M * s), math.fsum(M * M * c)]   # S1 is imaginary
    got = gn.dirichlet_sums(2 * math.pi * dnu, N)
    for p in range(3):
        # relative to the sum itself where it is not a cancellation (near dnu = 0: all of
        # them), else to the sum of magnitudes
        scale = max(abs(direct[p]), 1e-3 * np.sum(np.abs(M) ** p))
        assert abs(got[p] - direct[p]) < 1e-12 * scale, (p, got[p], direct[p])


@pytest.mark.parametrize("dnu", [0.0, 1.0 / N, -1.0 / N, 2.0 / N, 0.37 / N, 3.2 / N, -0.4])
def test_windowed_kernel_is_the_hann_weighted_sum(dnu):
    direct = np.sum(HANN_W * np.exp(2j * math.pi * dnu * M))
    got = gn.windowed_kernel(np.array([dnu]), N, gn.HANN)[0]
    assert abs(got - direct) < 1e-9 * N


def test_gram_sums_in_closed_form_match_the_columns():
    nus = [0.1, 0.1 + 3.0 / N, -0.2, 0.1 + 0.2 / N]      # close, far and sub-bin pairs
    for w, S in ((np.ones(N), gn.Sums(M, np.ones(N))), (HANN_W, gn.Sums(M, HANN_W))):
        assert S.kind is not None
        cols = gn.columns(M[0], N, nus, True)
        direct = S.gram(cols)                              # the length-N dot products
        G = S.gram_nu(nus, True)
        scale = np.array([N, N * N / 2, N ** 3 / 4])[:, None, None]
        assert np.all(np.abs(G - direct) < 1e-9 * scale)


@pytest.mark.parametrize("delta", [0.0, 0.1, 0.25, 0.49, -0.3])
def test_hann_two_point_interpolation_is_exact_for_a_lone_line(delta):
    n = 4096
    k0 = 300
    nu = (k0 + delta) / n
    z = np.exp(2j * math.pi * nu * (np.arange(n) - 0.5 * (n - 1)))
    spec = np.abs(sfft.fft(dl.window_weights(n, "hann") * z))
    i = int(spec.argmax())
    # O(1/n) from the finite window: far below the noise of any real record
    assert gn.hann_peak_nu(spec, i, n) == pytest.approx(nu, abs=1e-3 / n)


def test_hann_response_is_the_windowed_dft_of_a_line():
    n = 512
    nus = np.array([0.123 + 0.3 / n, -0.25, 37.0 / n])      # off-bin, negative, on a bin
    m = np.arange(n) - 0.5 * (n - 1)
    w = dl.window_weights(n, "hann")
    bins = np.array([0, 1, 37, 38, 63, 64, 65, 384, 511])
    for k, nu in enumerate(nus):
        X = sfft.fft(w * np.exp(2j * math.pi * nu * m))
        got = fast._hann_response(bins, nus, n)[:, k]
        assert np.max(np.abs(got - X[bins])) < 1e-9 * n


def test_separating_close_peaks_removes_the_leakage_bias():
    """Lines 3 bins apart, 10:1: the weak line's peak bins carry the strong one's side lobe;
    taken out, the two-point start is within 2e-3 bin of the truth (no noise; what is left is
    the leakage estimated from the biased start, second order)."""
    n = 4096
    m = np.arange(n) - 0.5 * (n - 1)
    nus = np.array([0.1 + 0.31 / n, 0.1 + 3.31 / n])
    z = np.exp(2j * math.pi * nus[0] * m) + 0.1 * np.exp(2j * math.pi * nus[1] * m + 1.0)
    X = sfft.fft(dl.window_weights(n, "hann") * z)
    spec = np.abs(X)
    peaks = [int(np.rint(nu * n)) for nu in nus]
    raw = np.array([gn.hann_peak_nu(spec, i, n) for i in peaks])
    sep = fast._separate_peaks(X, peaks, raw, n)
    assert abs(raw[1] - nus[1]) * n > 5e-3                   # the bias being removed
    assert np.all(np.abs(sep - nus) * n < 2e-3)


@pytest.mark.parametrize("engine", ["numpy", "numba"])
@pytest.mark.parametrize("sigma", [0.0, 1e-11, 1e-9])
def test_clean_records_get_their_true_noise_and_uncertainty(engine, sigma):
    """Above 90 dB the fit's cost, |z|^2 minus the lines' energy, has lost its digits (a
    noise of 1e-9 read 0, one of 1e-12 read 1e-8): it is then taken from the residual, so
    the noise level and the frequency's standard deviation follow the true noise (the
    Cramer-Rao bound std(nu) = sqrt(6 sigma^2 / (4 pi^2 |a|^2 n (n^2 - 1))) for a lone
    line, complex noise E|w|^2 = sigma^2), and a noiseless record reads the synthesis
    floor, not zero."""
    if engine == "numba":
        pytest.importorskip("numba")
    n, fs = 4096, 1000.0
    t = np.arange(n) / fs
    rng = np.random.default_rng(7)
    w = sigma * (rng.standard_normal(n) + 1j * rng.standard_normal(n)) / math.sqrt(2)
    z = np.exp(2j * math.pi * 37.123 * t + 0.3j) + 0.3 * np.exp(2j * math.pi * 81.77 * t) + w
    r = dl.refine_frequencies(t, z, 2, engine=engine)
    np.testing.assert_allclose(r.frequency_hz, [37.123, 81.77], atol=max(1e-9, 1e4 * sigma))
    if sigma == 0.0:
        assert 0.0 < r.noise_std < 1e-12
        return
    assert r.noise_std == pytest.approx(sigma, rel=0.05)     # n = 4096: 1.6 % scatter
    crlb = fs * math.sqrt(6 * sigma ** 2 / (4 * math.pi ** 2 * n * (n * n - 1.0)))
    assert r.frequency_hz_std[0] == pytest.approx(crlb, rel=0.06)
    assert r.frequency_hz_std[1] == pytest.approx(crlb / 0.3, rel=0.06)
