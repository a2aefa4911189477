"""The compiled line fit (dsp._line_kernel) against the numpy path it replaces, and the rule
that picks between them (dsp.line_fast._compiled_kernel)."""
from __future__ import annotations

import math

import numpy as np
import pytest

from dsp import _line_kernel, line_fast
from dsp.errors import SignalError
from dsp.lines import refine_frequencies

numba_only = pytest.mark.skipif(not _line_kernel._numba_installed() or _line_kernel._disabled(),
                                reason="numba not available or disabled")


@pytest.fixture(autouse=True)
def _engine_state(monkeypatch):
    """Whatever these tests do to the kernel's state is undone after each (the rest of the
    suite sees the state it would have seen without them)."""
    monkeypatch.setattr(_line_kernel, "_compiled", _line_kernel._compiled)
    monkeypatch.setattr(line_fast, "_numpy_seconds", line_fast._numpy_seconds)


def _signal(n, lines_, sigma, seed):
    rng = np.random.default_rng(seed)
    m = np.arange(n) - 0.5 * (n - 1)
    z = sum(a * np.exp(2j * math.pi * nu * m) for nu, a in lines_)
    return z + sigma * (rng.standard_normal(n) + 1j * rng.standard_normal(n)) / math.sqrt(2)


CASES = {
    "two separated": (4096, [(0.11, 1.0), (-0.17, 0.1j)], 0.1),
    "3 bins apart": (4096, [(0.11, 1.0), (0.11 + 3.2 / 4096, 0.1)], 0.1),
    "one line": (2048, [(0.0371, 2.0)], 0.05),
    "three, n not a multiple of the block": (3001, [(0.05, 1.0), (0.2, 0.3), (-0.3, 0.2)], 0.05),
    "noise-free": (1024, [(0.123456, 1.0), (-0.2, 0.5)], 0.0),
}


@numba_only
@pytest.mark.parametrize("case", CASES)
def test_compiled_and_numpy_give_the_same_fit(case):
    n, lines_, sigma = CASES[case]
    z = _signal(n, lines_, sigma, seed=7)
    w = line_fast._hann(n)
    a = line_fast._fast_fit(z, w, len(lines_), 1.0, engine="numpy", hann=True)
    b = line_fast._fast_fit(z, w, len(lines_), 1.0, engine="numba", hann=True)
    assert a is not None and b is not None
    # the same equations: differences are rounding (the compiled sums are reordered), far
    # below the uncertainty -- or, without noise, below 1e-9 of a bin.  (Rounding may move
    # the convergence test's decision by one step, whose effect is below 0.1 x the
    # uncertainty by that test's construction: the tolerance allows 0.01 x.)
    tol = np.maximum(1e-2 * a.frequency_std(), 1e-9 / n)
    assert np.all(np.abs(a.frequency - b.frequency) <= tol)
    assert np.allclose(a.amplitude, b.amplitude, rtol=1e-7, atol=1e-9)
    if sigma > 0:
        assert np.allclose(a.cov, b.cov, rtol=1e-5, atol=1e-12 * np.abs(a.cov).max())
        assert a.noise_var == pytest.approx(b.noise_var, rel=1e-7)


@numba_only
def test_compiled_fit_declines_what_the_numpy_one_declines():
    """Asked for two lines where there is one: the second is noise, too weak to be a line,
    and both paths hand over to the sequential search (None); refine_frequencies still
    finds the one line."""
    n = 4096
    z = _signal(n, [(0.1, 1.0)], 0.1, seed=3)
    w = line_fast._hann(n)
    assert line_fast._fast_fit(z, w, 2, 1.0, engine="numpy", hann=True) is None
    assert line_fast._fast_fit(z, w, 2, 1.0, engine="numba", hann=True) is None
    c = refine_frequencies(np.arange(n, dtype=float), z, 2)
    assert c.frequency_hz[0] == pytest.approx(0.1, abs=3e-3 / n)     # 5x its CRLB


@numba_only
def test_lines_0_6_bins_apart_are_resolved_by_both_paths():
    n = 4096
    truth = [0.1, 0.1 + 0.6 / n]
    z = _signal(n, [(truth[0], 1.0), (truth[1], 0.8j)], 0.01, seed=3)
    for engine in ("numpy", "numba"):
        fit = line_fast._fast_fit(z, line_fast._hann(n), 2, 1.0, engine=engine, hann=True)
        assert fit is not None
        assert np.sort(fit.frequency) == pytest.approx(truth, abs=5 * fit.frequency_std().max())


@numba_only
def test_lines_merging_across_half_a_cycle_are_declined():
    """Two lines on either side of +-1/2 cycle per sample, nearly one phasor (odd n): the
    fit must not return them as two lines with a zero or negative variance."""
    n = 3001
    z = _signal(n, [(1497.53 / n, 1.0), (1499.65 / n, 1.0)], 0.5, seed=5)
    w = line_fast._hann(n)
    for engine in ("numpy", "numba"):
        fit = line_fast._fast_fit(z, w, 2, 1.0, engine=engine, hann=True)
        if fit is not None:
            assert np.all(fit.frequency_std() > 0)
            assert np.all((-0.5 <= fit.frequency) & (fit.frequency < 0.5))
            d = abs(fit.frequency[0] - fit.frequency[1])
            assert min(d, 1 - d) > 0.5 / n


@numba_only
@pytest.mark.parametrize("engine", ["numpy", "numba"])
def test_both_engines_reach_the_bound_on_close_lines(engine):
    """The estimator's accuracy does not depend on the engine: RMS within 1.5x the joint
    Cramer-Rao bound (12 signals; the bound's std over 12 draws is ~20 %)."""
    n = 4096
    errs, bounds = [], []
    for seed in range(12):
        rng = np.random.default_rng(100 + seed)
        nu1 = rng.uniform(0.05, 0.2)
        truth = np.array([nu1, nu1 + 3.0 / n])
        z = _signal(n, [(truth[0], np.exp(1j * rng.uniform(0, 6))),
                        (truth[1], 0.3 * np.exp(1j * rng.uniform(0, 6)))], 0.1, seed)
        c = refine_frequencies(np.arange(n, dtype=float), z, 2, engine=engine)
        errs.append(np.sort(c.frequency_hz) - truth)
        bounds.append(c.frequency_hz_std[np.argsort(c.frequency_hz)])
    rms = np.sqrt(np.mean(np.square(errs), axis=0))
    bound = np.mean(bounds, axis=0)
    assert np.all(rms < 1.5 * bound), rms / bound


def test_engine_is_checked():
    with pytest.raises(SignalError, match="engine: must be one of auto, numba, numpy"):
        refine_frequencies(np.arange(256.0), np.exp(0.3j * np.arange(256)), 1, engine="fast")


def test_auto_takes_the_kernel_once_it_has_paid_for_itself(monkeypatch):
    """Ski rental: the numpy path until this process has spent what getting the compiled
    kernel would cost, then the kernel."""
    sentinel = object()
    monkeypatch.setattr(_line_kernel, "compiled", lambda: sentinel)
    monkeypatch.setattr(_line_kernel, "load_cost", lambda: 0.4)
    monkeypatch.setattr(line_fast, "_numpy_seconds", 0.39)
    assert line_fast._compiled_kernel("auto") is None
    assert line_fast._compiled_kernel("numba") is sentinel
    assert line_fast._compiled_kernel("numpy") is None
    monkeypatch.setattr(line_fast, "_numpy_seconds", 0.41)
    assert line_fast._compiled_kernel("auto") is sentinel


def test_numpy_path_time_is_counted(monkeypatch):
    monkeypatch.setattr(_line_kernel, "load_cost", lambda: math.inf)
    monkeypatch.setattr(line_fast, "_numpy_seconds", 0.0)
    n = 1024
    refine_frequencies(np.arange(n, dtype=float), _signal(n, [(0.1, 1.0)], 0.1, 1), 1)
    assert 0.0 < line_fast._numpy_seconds < 1.0


@numba_only
def test_warm_compiles_the_signature_the_fast_fit_uses():
    """The kernel's own warm-up (which imports nothing above it) calls the kernel with the
    argument types of :func:`dsp.line_fast._fast_fit`: the fit then compiles nothing new."""
    assert _line_kernel.warm() == "numba"
    kernel = _line_kernel.compiled()
    before = set(kernel.signatures)
    n = 4096
    z = _signal(n, [(0.11, 1.0), (0.11 + 3.2 / n, 0.1)], 0.1, seed=7)
    assert line_fast._fast_fit(z, line_fast._hann(n), 2, 1.0, engine="numba", hann=True) is not None
    assert set(kernel.signatures) == before and len(before) == 1


@pytest.mark.parametrize("var", ["STAND_DISABLE_JIT", "NUMBA_DISABLE_JIT"])
def test_disabled_jit_means_the_numpy_path(monkeypatch, var):
    monkeypatch.setenv(var, "1")
    monkeypatch.setattr(_line_kernel, "_compiled", None)
    assert _line_kernel.load_cost() == math.inf
    assert _line_kernel.compiled() is None


def test_engine_is_checked_on_every_path():
    t, z = np.arange(256.0), np.exp(0.3j * np.arange(256))
    for kw in ({"window": "rect"}, {"polish": False}):
        with pytest.raises(SignalError, match="engine"):
            refine_frequencies(t, z, 1, engine="fast", **kw)


def test_a_failing_kernel_is_dropped_for_numpy_with_a_warning(monkeypatch):
    """A kernel that fails otherwise than on a singular system (numba failing to compile
    after an upgrade, say) does not break the estimator: it warns once and uses numpy."""
    def broken(*args):
        raise TypeError("no matching definition")

    monkeypatch.setattr(_line_kernel, "_compiled", broken)
    n = 1024
    z = _signal(n, [(0.1, 1.0)], 0.1, 1)
    with pytest.warns(RuntimeWarning, match="compiled line fit failed.*TypeError"):
        c = refine_frequencies(np.arange(n, dtype=float), z, 1, engine="numba")
    assert c.frequency_hz[0] == pytest.approx(0.1, abs=6e-3 / n)      # 5x its CRLB
    assert _line_kernel.compiled() is None


def test_cache_folders_are_numbas_own(monkeypatch, tmp_path):
    """The folders looked in for the kernel's cache (without importing numba) are the ones
    numba's cache locators use: $NUMBA_CACHE_DIR, the in-tree __pycache__, the user-wide
    cache; an index file written after the source's last edit in $NUMBA_CACHE_DIR counts."""
    caching = pytest.importorskip("numba.core.caching")
    import os
    import sys

    src = os.path.abspath(_line_kernel.__file__)
    func = _line_kernel.fit_after_peaks
    func = getattr(func, "py_func", func)
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path))
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    env_dir, in_tree, user_wide = _line_kernel._cache_folders()
    assert env_dir == str(tmp_path / caching._CacheLocator.get_suitable_cache_subpath(src))
    assert in_tree == caching.InTreeCacheLocator(func, src).get_cache_path()
    assert user_wide == caching.UserWideCacheLocator(func, src).get_cache_path()
    assert user_wide.startswith(str(tmp_path / "xdg"))

    # only $NUMBA_CACHE_DIR may hold it: point the other two at empty folders
    monkeypatch.setattr(_line_kernel, "_cache_folders", lambda: [env_dir, str(tmp_path / "a"),
                                                                 str(tmp_path / "b")])
    _line_kernel._in_cache.cache_clear()
    try:
        assert not _line_kernel._in_cache()
        os.makedirs(env_dir)
        name = (f"_line_kernel.fit_after_peaks-{func.__code__.co_firstlineno}.py"
                f"{sys.version_info.major}{sys.version_info.minor}.nbi")
        with open(os.path.join(env_dir, name), "wb"):
            pass
        _line_kernel._in_cache.cache_clear()
        assert _line_kernel._in_cache()
    finally:
        _line_kernel._in_cache.cache_clear()
