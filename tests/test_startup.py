"""Start fast: lazy imports, one compiled kernel per model kind, precompiled kernels, cache keys.

Timings are measured by benchmarks/bench_startup.py, not here; these tests check the
mechanisms the timings rest on (what a command imports, what a run compiles, that the
precompiled and the just-in-time kernels compute the same numbers, that a cache is
dropped exactly when a source it was compiled from changes).
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import stand
from stand import _jit
from stand.integrate import precompiled
from stand.integrate.kernel_set import _Announce

ROOT = Path(__file__).resolve().parents[1]
SCENES = ROOT / "data_samples" / "scenes"
RUNUP = SCENES / "ball_runup.toml"


def _python(code: str, env=None) -> str:
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT,
                       env={**os.environ, **(env or {})}, timeout=600)
    assert r.returncode == 0, r.stderr
    return r.stdout


def _modules_after(argv, *more) -> set:
    """Top-level modules imported by ``stand ARGV`` run in a fresh process (``more``: further
    commands run after it in the same process; a list of sets then, one after each command:
    the modules of the first and all that the later ones added)."""
    code = "import sys, json\nfrom stand.cli.main import main\n"
    for a in (argv, *more):
        code += (f"try:\n    main({list(map(str, a))!r})\nexcept SystemExit:\n    pass\n"
                 "print('@@' + json.dumps(sorted({m.split('.')[0] for m in sys.modules})))\n")
    sets = [set(json.loads(part.splitlines()[0])) for part in _python(code).split("@@")[1:]]
    return sets if more else sets[0]


@pytest.fixture(scope="module")
def built():
    """The precompiled planar and generic kernels and the screen renderer, built once for this
    module (one process, started only if one is missing: the warm-up of tests/conftest.py
    builds them); the reason if this machine cannot build."""
    reason = precompiled.available()
    if reason is None and any(precompiled.load(k) is None
                              for k in (0, 1, "stand.instruments.render:render_frame")):
        _python("from stand.integrate.kernel_set import kernels\nfrom stand.integrate import "
                "precompiled\nkernels(0, build=True)\nkernels(1, build=True)\n"
                "precompiled.build('stand.instruments.render:render_frame')")
    return reason


HEAVY = {"numba", "pandas", "dask", "matplotlib", "cv2", "llvmlite"}


def test_help_imports_nothing_heavy():
    mods = _modules_after(["--help"])
    assert not mods & (HEAVY | {"scipy", "h5py"}), mods & (HEAVY | {"scipy", "h5py"})


def test_theory_and_analyze_import_no_numba_pandas_dask_matplotlib(built):
    """(``stand theory`` evaluates the right-hand side in its residual checks: from the
    precompiled kernel, built here first if this machine can build it.)  One process: analyze
    first (its own modules), then theory (the modules of both)."""
    rec = ROOT / "data_samples" / "recordings" / "stand_cameras.h5"
    analyze, both = _modules_after(["analyze", rec], ["theory", RUNUP])
    assert not analyze & HEAVY
    assert not both & (HEAVY if built is None else HEAVY - {"numba", "llvmlite"})


def test_importing_the_kernels_does_not_import_numba():
    out = _python("import sys\nimport stand.model.planar, stand.integrate.driver, stand.integrate.simulate\n"
                  "from stand._jit import LazyKernel, HAVE_NUMBA\n"
                  "import stand.model.planar as p\n"
                  "print('numba' in sys.modules, isinstance(p.rhs_planar, LazyKernel) or not HAVE_NUMBA)")
    assert out.split() == ["False", "True"]


@pytest.fixture(scope="module")
def jit_process():
    """What one fresh process with numba's JIT (``STAND_KERNELS=jit``) prints: the types of
    the stand-ins after the first call of one of them, then the loop's and the generic
    right-hand side's signatures after a planar run (0.5 s).  One process for the two tests
    below (a Python start with numba and stand, ~1 s of CPU, spared): the first call comes
    before any run, as in a fresh process, and it compiles nothing of the loop nor of the
    generic kernel (a stand-in becomes a dispatcher, compiled at its own first call), so the
    run's signatures are those of a planar run in a fresh process."""
    if not _jit.HAVE_NUMBA:
        pytest.skip("numba not installed")
    out = _python(
        "import numpy as np\nimport stand.model.programme as pr, stand.model.planar as pl\n"
        "from stand._jit import LazyKernel\n"
        "prog = np.array([[0.0, 1.0, 0.0], [1.0, 2.0, 1.5]])\n"
        "v = pr.programme_kinematics(0.5, prog, len(prog))\n"
        "print(type(pr.programme_kinematics).__name__, type(pl.rhs_planar).__name__,\n"
        "      type(pl.programme_kinematics).__name__, v[1])\n"
        "print('@@')\n"
        "import stand\nsc = stand.load(%r)\n"
        "from dataclasses import replace\nsc = replace(sc, run=replace(sc.run, duration=0.5))\n"
        "stand.run(sc)\nfrom stand.integrate.dop853 import dop853_loop\n"
        "from stand.model.rotors import coupled_kernel as ck\n"
        "print(sorted(str(s[0]) for s in dop853_loop.signatures), len(ck.rhs_generic.signatures))"
        % str(RUNUP), env={"STAND_KERNELS": "jit"})
    return out.split("@@\n")


def test_first_call_turns_every_stand_in_into_a_dispatcher(jit_process):
    a, b, c, speed = jit_process[0].split()
    assert a == b == c == "CPUDispatcher"
    assert float(speed) == pytest.approx(1.5, abs=1e-15)   # 1 + (2 - 1) * 0.5 / 1


def test_planar_run_compiles_only_the_planar_kernel(jit_process):
    """Each model kind has its own compiled loop: a planar run (numba JIT) compiles the loop
    for kind 0 only and never the generic right-hand side."""
    assert jit_process[1].strip() == "['Literal[int](0)'] 0"


def _short(path, duration):
    from dataclasses import replace

    sc = stand.load(path)
    return replace(sc, run=replace(sc.run, duration=duration))


@pytest.mark.parametrize("scene, duration", [("ball_runup.toml", 3.0),
                                             ("body_two_axis_pendulum.toml", 0.5)])
def test_precompiled_and_jit_kernels_agree(scene, duration, monkeypatch):
    """The precompiled module and numba's JIT compile the same source; the samples agree to
    rounding (different code generation may reassociate nothing: we allow 1e-12)."""
    if precompiled.available() is not None:
        pytest.skip(f"precompiling unavailable: {precompiled.available()}")
    from stand.integrate import kernel_set

    sc = _short(SCENES / scene, duration)
    runs = {}
    for mode in ("precompiled", "jit"):
        monkeypatch.setenv("STAND_KERNELS", mode)
        monkeypatch.setattr(kernel_set, "_CACHE", {})
        r = stand.run(sc)
        assert r.stats.success, r.stats.message
        runs[mode] = r
    a, b = runs["precompiled"], runs["jit"]
    assert a.stats.nfev == b.stats.nfev and a.stats.n_steps == b.stats.n_steps
    sa, sb = np.asarray(a.state), np.asarray(b.state)
    assert sa.shape == sb.shape and sa.shape[0] > 100
    scale = np.max(np.abs(sb), axis=0) + 1e-300
    assert np.max(np.abs(sa - sb) / scale) <= 1e-12


WARM_KINDS = ("family_spatial", "body_liquid_float")


@pytest.fixture(scope="module")
def warm_runs(built, tmp_path_factory):
    """What one fresh process with the precompiled kernels (``STAND_KERNELS=auto``) prints
    after each of: a planar ``stand.run`` + ``stand.save`` (1 s; numba? scipy?), then ``stand
    run`` of each of ``WARM_KINDS`` (numba? scipy.special?).  One process for the three tests
    (two Python starts with stand, numpy and h5py, ~1 s of CPU, spared): each check is of a
    module that must be absent, and ``sys.modules`` only grows, so a module absent after the
    last command was imported by none of them; the planar run comes first, so that its check
    of all of scipy sees what a fresh process sees."""
    if built is not None:
        pytest.skip(f"precompiling unavailable: {built}")
    tmp = tmp_path_factory.mktemp("warm_runs")
    code = ("import sys, tempfile, os, stand\nsc = stand.load(%r)\n"
            "from dataclasses import replace\nsc = replace(sc, run=replace(sc.run, duration=1.0))\n"
            "r = stand.run(sc)\nd = tempfile.mkdtemp()\nstand.save(r, os.path.join(d, 'r.h5'))\n"
            "print('@@', r.stats.success, 'numba' in sys.modules, 'scipy' in sys.modules)\n"
            "from stand.cli.main import main\n" % str(RUNUP))
    for name in WARM_KINDS:
        code += (f"rc = main(['run', {str(SCENES / (name + '.toml'))!r}, '-o', "
                 f"{str(tmp / (name + '.h5'))!r}, '--force'])\n"
                 "print('@@', rc, 'numba' in sys.modules, 'scipy.special' in sys.modules)\n")
    out = _python(code, env={"STAND_KERNELS": "auto"})
    # each line after "@@" (a command's own output follows it)
    return [part.splitlines()[0].split() for part in out.split("@@")[1:]]


def test_warm_run_imports_no_numba(warm_runs):
    """With the precompiled kernel present, a whole `stand run` never imports numba."""
    assert warm_runs[0] == ["True", "False", "False"]


def test_kernel_modes_are_validated(monkeypatch):
    from stand.integrate import kernel_set

    monkeypatch.setenv("STAND_KERNELS", "fast")
    monkeypatch.setattr(kernel_set, "_CACHE", {})
    with pytest.raises(ValueError, match="STAND_KERNELS = 'fast'"):
        kernel_set.kernels(0)


def test_precompiled_module_name_follows_its_sources():
    """Each kind's module is named by the sources it is compiled from: the planar kernel's
    name does not depend on the generic kernel's files, and both depend on the loop."""
    planar = set(precompiled.kernel_modules(0))
    generic = set(precompiled.kernel_modules(1))
    assert "stand.model.planar" in planar and "stand.model.rotors.coupled_kernel" not in planar
    assert {"stand.model.rotors.coupled_kernel", "stand.model.rotors.bodies_kernel"} <= generic
    assert "stand.model.planar" not in generic
    assert {"stand.integrate.dop853", "stand.model.kernels"} <= planar & generic
    assert precompiled.module_name(0) != precompiled.module_name(1)


def test_import_scan_finds_every_import_the_parser_finds():
    import ast

    def by_ast(path, name):
        pkg = name.split(".")[:-1] if path.name != "__init__.py" else name.split(".")
        out = set()
        for node in ast.walk(ast.parse(path.read_bytes())):
            if isinstance(node, ast.ImportFrom):
                base = pkg[: len(pkg) - node.level + 1] if node.level else []
                mod = ".".join(base + (node.module.split(".") if node.module else []))
                if mod.startswith("stand"):
                    out.add(mod)
                    out.update(f"{mod}.{a.name}" for a in node.names)
            elif isinstance(node, ast.Import):
                out.update(a.name for a in node.names if a.name.startswith("stand"))
        return {m for m in out if _jit._module_file(m) is not None}

    checked = 0
    for f in _jit.PACKAGE.rglob("*.py"):
        parts = f.relative_to(_jit.PACKAGE.parent).with_suffix("").parts
        name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
        missing = by_ast(f, name) - _jit._imports(f, name)
        assert not missing, (name, missing)
        checked += 1
    assert checked > 100


def _fake_package(tmp_path):
    pkg = tmp_path / "stand"
    (pkg / "__pycache__").mkdir(parents=True)
    (pkg / "__init__.py").write_text("")
    (pkg / "a.py").write_text("from .b import g\n@njit\ndef f(): pass\n")
    (pkg / "b.py").write_text("@njit\ndef g(): pass\n")
    (pkg / "c.py").write_text("@njit\ndef h(): pass\n")
    (pkg / "d.py").write_text('KERNELS = {0: ("stand.c", "h")}\n@njit\ndef k(): pass\n')
    for stem in "abcd":
        (pkg / "__pycache__" / f"{stem}.f-1.py311.nbi").write_text("x")
        (pkg / "__pycache__" / f"{stem}.f-1.py311.1.nbc").write_text("x")
    return pkg


def test_a_cache_is_dropped_when_a_module_it_imports_changes(tmp_path, monkeypatch):
    pkg = _fake_package(tmp_path)
    monkeypatch.setattr(_jit, "PACKAGE", pkg)
    cache = pkg / "__pycache__"
    _jit.drop_stale_caches()          # first sight: no stamps yet, every cache dropped
    for stem in "abcd":
        (cache / f"{stem}.f-1.py311.nbi").write_text("x")
    _jit.drop_stale_caches()          # nothing changed: all kept
    assert {p.name.split(".")[0] for p in cache.glob("*.nbi")} == {"a", "b", "c", "d"}
    (pkg / "b.py").write_text("@njit\ndef g(): return 1\n")
    _jit.drop_stale_caches()          # b changed: b's and its importer a's caches go, c's stays
    assert {p.name.split(".")[0] for p in cache.glob("*.nbi")} == {"c", "d"}
    (pkg / "c.py").write_text("@njit\ndef h(): return 1\n")
    _jit.drop_stale_caches()          # c changed: c's and d's, which names it in a string, go
    assert {p.name.split(".")[0] for p in cache.glob("*.nbi")} == set()


def test_compilation_is_announced_only_when_it_takes_time(capsys):
    with _Announce("planar kernel", 7, delay=0.0) as a:
        while not a._shown:            # wait for the message (no fixed sleep)
            a._thread.join(0.01)
    err = capsys.readouterr().err
    assert "compiling the planar kernel (one time, about 7 s)" in err
    assert "done in" in err
    with _Announce("planar kernel", 7, delay=5.0):
        pass
    assert capsys.readouterr().err == ""


def test_warmup_command(capsys):
    from stand.cli.main import main

    assert main(["warmup"]) == 0
    out = capsys.readouterr().out
    assert "planar integrator kernel: " in out
    assert any(s in out for s in ("precompiled", "jit", "python"))


def test_programme_in_numpy_equals_the_compiled_scalar_programme():
    """Reading a run's rotor angle and speed needs no compiled code: the numpy version of the
    programme equals the kernel's scalar one exactly, at random times, at the knots and
    before / after the table, with a repeated knot time (a jump in acceleration)."""
    from stand.model.planar import rotor_kinematics_many
    from stand.model.programme import programme_kinematics, programme_kinematics_many, rotor_kinematics

    rng = np.random.default_rng(7)
    for k in (1, 2, 3, 6, 17):
        t = np.sort(rng.uniform(0.0, 10.0, k))
        t[0] = 0.0
        if k > 3:
            t[2] = t[3]
        prog = np.column_stack([t, rng.uniform(0.0, 5.0, k), np.cumsum(rng.uniform(0.0, 1.0, k))])
        taus = np.concatenate([rng.uniform(-1.0, 11.0, 300), t])
        ref = np.array([programme_kinematics(x, prog, len(prog)) for x in taus])
        np.testing.assert_array_equal(programme_kinematics_many(taus, prog), ref)
    sp = np.zeros(64)
    from stand.model.planar import COAST_PHI0, COAST_R0, COAST_T, COAST_T0
    sp[COAST_T0], sp[COAST_T], sp[COAST_R0], sp[COAST_PHI0] = 5.0, 2.0, 3.0, 11.0
    taus = np.linspace(0.0, 9.0, 301)
    phi, R = rotor_kinematics_many(taus, prog, sp)
    ref = np.array([rotor_kinematics(x, prog, len(prog), 5.0, 2.0, 3.0, 11.0) for x in taus])
    # the coast-down's exponential: numpy's vectorised exp and libm's differ by an ulp
    np.testing.assert_allclose(phi, ref[:, 0], rtol=4e-16, atol=0)
    np.testing.assert_allclose(R, ref[:, 1], rtol=4e-16, atol=0)


def test_a_jit_run_starts_one_background_build(monkeypatch):
    """After a command ran a kind on numba's JIT, the command line starts one detached build
    of that kind's precompiled module, unless the module exists or is being built."""
    import subprocess as sp

    from stand.integrate import kernel_set

    started = []
    monkeypatch.setattr(sp, "Popen", lambda argv, **kw: started.append((argv, kw)))
    monkeypatch.setenv("STAND_KERNELS", "auto")
    monkeypatch.setattr(precompiled, "available", lambda: None)
    monkeypatch.setattr(precompiled, "load", lambda kind: None)
    monkeypatch.setattr(precompiled, "building", lambda kind: kind == 1)
    monkeypatch.setattr(kernel_set, "_JIT_USED", {0, 1})
    assert kernel_set.precompile_in_background(say=False) == ["planar"]
    (argv, kw), = started
    assert argv[1:] == ["-m", "stand.integrate.precompiled", "planar"]
    assert kw["start_new_session"] and kw["stdout"] == sp.DEVNULL
    assert kernel_set.precompile_in_background(say=False) == []      # once per process
    monkeypatch.setattr(kernel_set, "_JIT_USED", {0})
    monkeypatch.setattr(precompiled, "load", lambda kind: object())  # already built
    assert kernel_set.precompile_in_background(say=False) == []
    monkeypatch.setenv("STAND_KERNELS", "jit")
    monkeypatch.setattr(precompiled, "load", lambda kind: None)
    assert kernel_set.precompile_in_background(say=False) == []      # jit: never builds


def test_background_build_entry_point_refuses_unknown_kinds(capsys):
    assert precompiled.main(["spherical"]) == 2
    assert "usage: python -m stand.integrate.precompiled {planar,generic,<module>:<function>}" in \
        capsys.readouterr().err


@pytest.mark.parametrize("mode", ["jit", "precompiled"])
def test_kernel_set_takes_any_array_layout(mode, monkeypatch):
    """The kernel set's entry points take C-contiguous float64 arrays; other layouts (a
    strided output, integer or Fortran-ordered inputs) give the same numbers, through
    C-contiguous copies: numba compiles no other specialisation (seconds each)."""
    if mode == "precompiled" and precompiled.available() is not None:
        pytest.skip(f"precompiling unavailable: {precompiled.available()}")
    from stand.integrate import kernel_set
    from stand.model.planar import build_planar_model, initial_state

    monkeypatch.setenv("STAND_KERNELS", mode)
    monkeypatch.setattr(kernel_set, "_CACHE", {})
    ks = kernel_set.kernels(0)
    assert ks.source == mode
    sc = stand.load(RUNUP)
    m = build_planar_model(sc)
    y = initial_state(sc, m) + 0.01
    ref = np.empty_like(y)
    ks.evaluate(0.3, y, ref, m.sp, m.wt, m.prog)
    strided = np.zeros((y.size, 2))[:, 0]
    ks.evaluate(0.3, list(y), strided, m.sp, np.asfortranarray(m.wt), m.prog)
    np.testing.assert_array_equal(strided, ref)
    J = np.empty((y.size, y.size))
    Jf = np.asfortranarray(np.empty((y.size, y.size)))
    ks.jacobian(0.3, y, ref, m.sp, m.wt, m.prog, J)
    ks.jacobian(0.3, y, ref, m.sp, m.wt, m.prog, Jf)
    np.testing.assert_array_equal(J, Jf)
    assert np.all(np.isfinite(J)) and np.any(J != 0)
    if mode == "jit":
        from stand.integrate.jacobian import jac_fd
        from stand.model.kernels import kernel_of

        layouts = {getattr(a, "layout", None) for f in (kernel_of(0), jac_fd) for sig in f.signatures
                   for a in sig} - {None}
        assert layouts == {"C"}, layouts


def test_kernel_set_dop853_takes_lists_and_checks_its_workspace():
    """The loop's fallback call (a state that is not C-contiguous float64) converts the other
    inputs too, and the compiled loop refuses a scratch array too small for the state."""
    from stand.integrate import kernel_set
    from stand.integrate.dop853 import WORK_ROWS, dop853_loop
    from stand.model.planar import build_planar_model, initial_state

    sc = stand.load(RUNUP)
    m = build_planar_model(sc)
    ks = kernel_set.kernels(0)
    runs = []
    for as_list in (False, True):
        y = initial_state(sc, m)
        y = np.asfortranarray(np.stack([y, y], axis=1))[:, 0] if as_list else y.copy()
        f = np.empty(y.size)
        ks.evaluate(0.0, np.ascontiguousarray(y), f, m.sp, m.wt, m.prog)
        out = np.full((3, y.size), np.nan)
        st = np.zeros(3, np.int64)
        ts = [0.0, 0.5, 1.0]
        conv = list if as_list else np.asarray
        status = ks.dop853(m.sp, m.wt, m.prog, 0.0, y, f, 1e-3, 1.0, 1e-8, 1e-10,
                           conv(np.full(y.size, np.inf)), np.inf, conv(ts), 1, out, st, 10**6,
                           1e9)
        assert status[0] == 0 and status[3] == 3
        runs.append(out[1:])
    np.testing.assert_array_equal(runs[0], runs[1])
    y = initial_state(sc, m)
    with pytest.raises(ValueError, match="workspace"):
        dop853_loop(0, m.sp, m.wt, m.prog, 0.0, y, f.copy(), 1e-3, 1.0, 1e-8, 1e-10,
                    np.full(y.size, np.inf), np.inf, np.array(ts), 1, out, st, 10**6, 1e9,
                    np.empty((WORK_ROWS - 1, y.size)))


@pytest.mark.parametrize("name", WARM_KINDS)
def test_warm_run_of_every_kind_imports_no_numba(name, warm_runs):
    """A generic-kernel scene with a screen camera (frames rendered) and bodies: with the
    precompiled generic kernel and renderer, the whole `stand run` imports neither numba nor
    scipy.special (issue 33).  (The run's own process: ``warm_runs``.)"""
    assert warm_runs[1 + WARM_KINDS.index(name)] == ["0", "False", "False"]


def test_precompiled_renderer_equals_the_jit_one():
    """The precompiled screen renderer (an extra of stand.integrate.precompiled) draws the same frame bit for bit."""
    if precompiled.available() is not None:
        pytest.skip(f"precompiling unavailable: {precompiled.available()}")
    from stand.instruments import render

    mod = precompiled.build("stand.instruments.render:render_frame")
    r = render._Renderer.__new__(render._Renderer)
    thr, guide, kmin = render.background_table(8.0, 2.0, True, 10.0, 255)
    u = np.array([30.2, 31.0, 31.7])
    v = np.array([20.1, 20.4, 20.9])
    w = np.full(3, 1.0 / 3.0)
    frames = []
    for f in (mod.render_frame, render.render_frame):
        acc = np.zeros((48, 64))
        out = np.zeros((48, 64), np.uint16)
        touched = f(u, v, w, 2.5, 2.0, 200.0, 8.0, 2.0, 10.0, True, 255, True,
                    np.uint64(12345), thr, guide, kmin, 4.0, acc, out)
        frames.append((touched, out))
    assert frames[0][0] == frames[1][0] > 0
    assert np.array_equal(frames[0][1], frames[1][1])
    del r


def test_background_table_without_scipy_equals_scipy():
    """The small-table path (math.lgamma / math.erf) gives scipy's tables exactly."""
    from stand.instruments import render

    table = render.background_table.__wrapped__
    for args in [(8.0, 2.0, True, 10.0, 255), (100.0, 3.0, True, 2.0, 4095),
                 (500.0, 5.0, True, 1.0, 65535)]:
        a = table(*args)
        old, render._SMALL_TABLE = render._SMALL_TABLE, -1
        try:
            b = table(*args)
        finally:
            render._SMALL_TABLE = old
        assert np.array_equal(a[0], b[0]) and np.array_equal(a[1], b[1]) and a[2] == b[2]
