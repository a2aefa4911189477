"""Benchmarks that cannot lie (issue 21, item 5): the shared peer check of benchmarks/_peers.py,
and the numbalsoda wrapper of benchmarks/bench_core.py on a speed programme of any length."""
import ctypes
import importlib.util
import math
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
BENCH = ROOT / "benchmarks"


def _load(name: str):
    """A benchmarks/ script as a module (benchmarks/ is not a package)."""
    if str(BENCH) not in sys.path:
        sys.path.insert(0, str(BENCH))
    modname = name if name.startswith("_") else f"_bench_{name}"
    if modname in sys.modules:
        return sys.modules[modname]
    spec = importlib.util.spec_from_file_location(modname, BENCH / f"{name}.py")
    mod = importlib.util.module_from_spec(spec)
    sys.modules[modname] = mod          # dataclasses look their module up
    spec.loader.exec_module(mod)
    return mod


peers = _load("_peers")


def test_over_tolerance_peer_is_invalid_and_gets_no_time_or_ratio():
    bad = peers.check_peer("numbalsoda LSODA", 10.6, 6.8e-6)
    assert not bad.valid
    assert bad.verdict == "invalid (error 10.6 > tolerance 6.8e-06)"
    assert bad.cells("6.62 ms", "1.26") == ["invalid (error 10.6 > tolerance 6.8e-06)", "-"]
    assert bad.line("6.62 ms, ratio 1.26") == "numbalsoda LSODA: invalid (error 10.6 > tolerance 6.8e-06)"
    assert "ms" not in bad.line("6.62 ms") and "1.26" not in " ".join(bad.cells("6.62 ms", "1.26"))


def test_peer_within_tolerance_keeps_its_row_and_no_answer_is_invalid():
    ok = peers.check_peer("stand DOP853", 1.9e-7, 6.8e-6)
    assert ok.valid and ok.verdict == "ok"
    assert ok.cells("3.4 ms", "1") == ["3.4 ms", "1"]
    assert ok.line("3.4 ms") == "stand DOP853: 3.4 ms"
    assert peers.check_peer("at the limit", 6.8e-6, 6.8e-6).valid
    for missing in (math.nan, math.inf):          # a solver that stopped: no answer
        p = peers.check_peer("stopped", missing, 1.0)
        assert not p.valid and p.verdict == "invalid (error inf > tolerance 1)"
    with pytest.raises(ValueError, match="tolerance = 0"):
        peers.check_peer("x", 0.0, 0.0)


@pytest.fixture(scope="module")
def core():
    pytest.importorskip("numbalsoda")
    return _load("bench_core")


def _runup_model(core):
    """ball_runup.toml with a 5-row speed programme (run-up, hold, slow down, run-up again)."""
    import stand
    from stand.model.planar import build_planar_model, initial_state

    sc = stand.load(ROOT / "data_samples" / "scenes" / "ball_runup.toml")
    w = 2 * np.pi
    prog = np.array([[0.0, 0.0], [4.0, 8.0 * w], [6.0, 8.0 * w], [8.0, 4.0 * w], [12.0, 15.0 * w]])
    sc = replace(sc, drive=replace(sc.drive, programme=prog))
    model = build_planar_model(sc)
    return model, initial_state(sc, model)


def test_packed_model_gives_the_rhs_of_the_model_for_a_multi_row_programme(core):
    from stand.model.planar import N_PROG, rhs_planar

    model, y0 = _runup_model(core)
    npg = int(model.sp[N_PROG])
    assert npg == 5 and model.prog.shape[1] != 3          # the old wrapper assumed (k, 3)
    data = core.pack_model(model)
    hdr = data[:core.HDR]
    assert (hdr[core.H_ROWS], hdr[core.H_COLS]) == model.prog.shape
    f = core.make_rhs_cfunc().ctypes
    ptr = ctypes.POINTER(ctypes.c_double)
    rng = np.random.default_rng(3)
    knots = model.prog[:npg, 0]
    taus = np.append(0.5 * (knots[:-1] + knots[1:]), knots[-1] + 7.0)   # every segment, and after
    for k, tau in enumerate(taus):
        y = y0 + 0.1 * rng.standard_normal(y0.size)
        want = np.empty_like(y)
        rhs_planar(tau, y.copy(), want, model.sp, model.wt, model.prog)
        got = np.full_like(y, np.nan)
        f(float(tau), y.ctypes.data_as(ptr), got.ctypes.data_as(ptr), data.ctypes.data_as(ptr))
        np.testing.assert_allclose(got, want, rtol=1e-14, atol=1e-14 * np.max(np.abs(want)))
        assert data[core.H_CALLS] == k + 1                          # the call counter
