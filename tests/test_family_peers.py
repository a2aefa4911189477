"""The helpers of bench_family.py's parts (b) and (c) (issue 33): the numbalsoda wrapper of the
generic kernel (benchmarks/_family_floor.py; skipped without numbalsoda) and the ROSS
comparison's problem, references and interpreter choice (benchmarks/_family_ross.py; none of
these needs ROSS)."""
import ctypes
import importlib.util
import math
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
BENCH = ROOT / "benchmarks"


def _load(name: str):
    if str(BENCH) not in sys.path:
        sys.path.insert(0, str(BENCH))
    if name in sys.modules:
        return sys.modules[name]
    spec = importlib.util.spec_from_file_location(name, BENCH / f"{name}.py")
    mod = importlib.util.module_from_spec(spec)
    sys.modules[name] = mod
    spec.loader.exec_module(mod)
    return mod


fr = _load("_family_ross")

#: a short Jeffcott run-up (through nothing: 0.3 s from rest at 20 rev/s^2)
SHORT = dict(fr.PROBLEM, duration=0.3)


def _jeffcott_as_ross(m, k, c):
    """ROSS's answer layout for one node of 6 dofs (x, y, z, alpha, beta, theta) carrying the
    Jeffcott rotor (mass m, stiffness k, damping c on x and y; the other dofs free, uncoupled)."""
    M = np.diag([m, m, m, 1.0, 1.0, 1.0])
    K = np.diag([k, k, 0.0, k, k, 0.0])
    C = np.diag([c, c, 0.0, 0.0, 0.0, 0.0])
    Z = np.zeros((6, 6))
    G = Z.copy()
    G[3, 4], G[4, 3] = 0.1, -0.1          # gyroscopic coupling of the tilts only
    return dict(M=M.tolist(), K=K.tolist(), C=C.tolist(), G=G.tolist(), Ksdt=Z.tolist(),
                mass=m, number_dof=6, ix=0, iy=1)


def test_unbalance_force_is_the_oracles_sign_convention():
    # runup_exact: e (phi'^2 - i phi'') e^{i phi}: x = e(w^2 cos + a sin), y = e(w^2 sin - a cos)
    t = np.array([0.0, 0.37, 1.1])
    phi, w, a = fr.kinematics(t, 20.0)
    F = fr.unbalance_force(t, 2e-3, 20.0)
    z = 2e-3 * (w * w - 1j * a) * np.exp(1j * phi)
    np.testing.assert_allclose(F[:, 0] + 1j * F[:, 1], z, rtol=1e-14, atol=1e-14 * np.abs(z).max())
    assert a[0] == pytest.approx(2 * math.pi * 20.0) and phi[2] == pytest.approx(0.5 * a[0] * 1.21)


def test_ross_reference_of_a_jeffcott_node_is_the_closed_equation():
    """The reference of ROSS's matrices, fed one node that *is* the Jeffcott rotor, agrees with
    tests/oracles/runup_exact.py to the two integrations' tolerance (1e-11 each: 1e-8 with a
    thousand steps' margin), so the two references differ only by the models."""
    data = _jeffcott_as_ross(16.0, 2.2e5, 100.0)
    eq = fr.equivalent(dict(mass=16.0), dict(SHORT, kb=1.1e5, cb=50.0))
    assert eq["f0"] == pytest.approx(math.sqrt(2.2e5 / 16.0) / (2 * math.pi))
    assert eq["zeta"] == pytest.approx(100.0 / (2 * math.sqrt(2.2e5 * 16.0)))
    ref = fr.ross_reference(data, SHORT)
    exact = fr.stand_reference(eq, SHORT)
    assert fr.rel_error(ref, exact) < 1e-8


def test_ross_reference_refuses_axial_dofs_coupled_to_lateral_ones():
    data = _jeffcott_as_ross(16.0, 2.2e5, 100.0)
    K = np.array(data["K"])
    K[0, 2] = K[2, 0] = 1.0
    data["K"] = K.tolist()
    with pytest.raises(RuntimeError, match="couple"):
        fr.ross_reference(data, SHORT)


def test_stand_scene_of_the_jeffcott_rotor_follows_the_closed_equation():
    """The stand's planar scene without weights (what part (c) runs) against the oracle: the
    stand's rtol 1e-9 gives about 1e-8; 1e-6 is the part's tolerance of a valid answer."""
    bf = _load("bench_family")
    eq = dict(mass=16.0, stiffness=2.2e5, damping=100.0,
              f0=math.sqrt(2.2e5 / 16.0) / (2 * math.pi), zeta=100.0 / (2 * math.sqrt(2.2e5 * 16)))
    scene = bf.load(fr.stand_scene_text(eq, SHORT))
    r = bf.ours(scene)
    assert fr.rel_error(r.q, fr.stand_reference(eq, SHORT)) < 1e-6


def test_rel_error_and_interpreter_choice(monkeypatch):
    ref = np.array([[3.0, 4.0], [0.0, 0.0]])
    assert fr.rel_error(ref + [[0.0, 0.05], [0.0, 0.0]], ref) == pytest.approx(0.01)
    assert fr.rel_error(ref[:1], ref) == math.inf
    assert fr.rel_error(np.full_like(ref, np.nan), ref) == math.inf
    monkeypatch.setenv("ROSS_PYTHON", "/some/where/python")
    assert fr.ross_python() == "/some/where/python"


def test_a_failing_child_is_an_error_with_its_exit_code():
    with pytest.raises(RuntimeError, match="exited"):
        fr.run_child(sys.executable, {"not": "a problem"}, timeout=60)


# ------------------------------------------------------------------ part (b): numbalsoda
@pytest.fixture(scope="module")
def ff():
    pytest.importorskip("numbalsoda")
    return _load("_family_floor")


def test_cfunc_gives_the_generic_kernels_rhs_and_counts_calls(ff):
    bf = _load("bench_family")
    from stand.integrate.coupled import build_model, initial_state
    from stand.model.rotors.coupled_kernel import rhs_generic

    sc = bf.load(bf.SPATIAL_TWO)
    model = build_model(sc.linear_rotor(), sc.weights, sc.drive.programme)
    y0 = initial_state(model, sc.weights)
    data = ff.pack_model(model)
    assert data[ff.H_SIZE] == model.size and data[ff.H_NW] == model.nw
    f = ff.make_rhs_cfunc().ctypes
    ptr = ctypes.POINTER(ctypes.c_double)
    rng = np.random.default_rng(5)
    for k, tau in enumerate([0.3, 17.0, 1e3]):        # ramp, later, after the programme
        y = y0 + 0.1 * rng.standard_normal(y0.size)
        want = np.empty_like(y)
        rhs_generic(tau, y.copy(), want, model.sp.copy(), model.wt, model.prog)
        got = np.full_like(y, np.nan)
        f(float(tau), y.ctypes.data_as(ptr), got.ctypes.data_as(ptr), data.ctypes.data_as(ptr))
        np.testing.assert_allclose(got, want, rtol=1e-13, atol=1e-13 * np.max(np.abs(want)))
        assert data[ff.H_CALLS] == k + 1
