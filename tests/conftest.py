"""Test-session hooks.

* Compile ahead, once, before the test processes start: every model kind's kernels
  (numba's cache and the precompiled modules), the screen renderer, the blurred-spot and
  line fits, in as many processes (lanes of about equal cost) as there are cores, so that
  pytest-xdist's workers load them instead of each compiling the same kernels.
* The full sweeps and calibrations are marked ``full`` and left out by default
  (pyproject ``addopts``); ``pytest -m full`` runs them (benchmarks/README.md).
* One BLAS thread per test process (set before numpy is imported).
* Python's bytecode caches are written, even where ``PYTHONDONTWRITEBYTECODE`` is set: else
  every test process and every command-line subprocess compiles the sources of stand/, dsp/
  and vision/ again, and pytest rewrites every test module's asserts again in each worker
  (measured: collection 23 s of CPU per worker against 11 s with the caches).
* The test modules' rewritten asserts and the packages' bytecode compiled once, in the
  controller while the warm-up compiles, instead of by every pytest-xdist worker on a fresh
  clone (~10 s of CPU each).
* A folder for the session's computations shared by the workers (``tests/_shared.py``).
* Print the adversarial harness' table at the end of the run (tests/test_adversarial.py
  records it as a user property; this works under pytest-xdist).
"""
import os
import subprocess
import sys

# One BLAS thread per test process, as the command line has (stand/cli/main.py), set before
# any test module imports numpy: pytest-xdist's parallelism is processes and the tests'
# matrices are small; OpenBLAS' threads spinning on a busy 2-core machine cost a run-up fit
# 6x its CPU (2.0 s instead of 0.32 s).  A value set in the environment is kept.
for _v in ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "BLIS_NUM_THREADS", "VECLIB_MAXIMUM_THREADS"):
    os.environ.setdefault(_v, "1")
# Bytecode caches written (module docstring): in this process (pytest's assertion rewriting
# reads the flag when it rewrites a test module) and in its workers, lanes and subprocesses.
sys.dont_write_bytecode = False
os.environ.pop("PYTHONDONTWRITEBYTECODE", None)

_TABLES = []


def pytest_runtest_logreport(report):
    if report.when == "call":
        for key, value in getattr(report, "user_properties", ()):
            if key == "adversarial_table":
                _TABLES.append(value)


def pytest_terminal_summary(terminalreporter):
    if _TABLES:            # one table per command (one test each): their header once
        terminalreporter.write_sep("-", "adversarial harness")
        head = _TABLES[0].splitlines()[0]
        terminalreporter.write_line(head)
        for table in sorted(_TABLES):
            for line in table.splitlines():
                if line != head:
                    terminalreporter.write_line(line)


#: the warm-up's items: (code, CPU seconds it takes from a cold cache, measured 2026-11-29 on
#: a quiet 2-core machine (load 0.5) by benchmarks/bench_cold_warmup.py --items: the lanes' balance)
_KIND = "from stand.api.warmup import warmup; warmup(kinds=[{k}], say=lambda s: None)"
_RENDER = ("from stand.integrate import precompiled\n"
           "try: precompiled.build('stand.instruments.render:render_frame')\n"
           "except Exception: pass   # no C compiler: numba's JIT on first use")


def _warmup_items(cores: int = 2) -> list:
    """(code, cost) of every item: the model kinds' kernels, the blurred-spot fit, the line
    fit, the screen renderer (else each worker JIT-compiles it and the command line starts a
    background build of it)."""
    from stand.model.kernels import KIND_NAMES

    # on up to 3 cores every kind in one process: they share numba's import, the precompiled
    # modules' C helpers and the small compiled helpers (measured on a fresh clone, 2026-11-30:
    # planar then generic ~73 s CPU in one process, 28.7 + 51.5 = 80.2 in two); on more cores
    # each kind in its own lane (the wall time of the longest, not the CPU, is then the bound)
    costs = {0: 28.7, 1: 51.5}          # planar, generic; another kind: as the generic one
    if cores <= 3:
        kinds = ", ".join(str(k) for k in sorted(KIND_NAMES))
        first = [(_KIND.format(k=kinds), 73.0 + 45.0 * max(len(KIND_NAMES) - 2, 0))]
    else:
        first = [(_KIND.format(k=k), costs.get(k, 60.0)) for k in sorted(KIND_NAMES)]
    return (first
            + [("from vision.blur import warm; warm()", 27.5),   # with the tracker's front
               ("from dsp._line_kernel import warm; warm()", 25.0), (_RENDER, 15.8)])


def _lanes(items, n: int) -> list:
    """The items in ``n`` lanes of about equal cost (longest first, each to the lane with the
    least so far): one process per lane runs its items one after the other, so that numba is
    imported, and its own helpers compiled, once per lane instead of once per item."""
    lanes = [[0.0, []] for _ in range(max(1, n))]
    for code, cost in sorted(items, key=lambda it: -it[1]):
        lane = min(lanes, key=lambda ln: ln[0])
        lane[0] += cost
        lane[1].append(code)
    return [codes for _, codes in lanes if codes]


def pytest_configure(config):
    _one_final_gc(config)
    if hasattr(config, "workerinput"):   # an xdist worker: the controller compiled already
        return
    # the session's folder of computations shared by the workers (tests/_shared.py)
    import tempfile

    config._stand_shared = tempfile.mkdtemp(prefix="stand-tests-shared-")
    os.environ["STAND_TEST_SHARED"] = config._stand_shared
    # as many lanes as there are cores: no faster with more, and each holds ~0.8 GB; a failed
    # item is reported and the lane goes on (the tests then compile what they need)
    running = []
    cores = os.cpu_count() or 1
    for codes in _lanes(_warmup_items(cores), cores):
        lane = ("import traceback\n"
                f"for code in {codes!r}:\n"
                "    try:\n        exec(code, {})\n"
                "    except Exception:\n        traceback.print_exc()\n")
        running.append(subprocess.Popen([sys.executable, "-c", lane]))
    if config.getoption("numprocesses", None):   # workers will start: meanwhile, once here
        _rewrite_test_modules(config)
        _compile_sources()
    for p in running:
        p.wait()


def _one_final_gc(config) -> None:
    """One garbage collection, not five, before pytest reports the unraisable exceptions at
    the end of each test process (its ``gc_collect_iterations_key``, 5 by default, "determined
    experimentally by the Trio project" for objects that need several passes): with the
    compiled kernels and the figures of a whole run in memory each pass costs ~1-2 s of CPU
    per process (measured in a profile of the suite: 5 passes 8.8 s).  The suite's objects
    need no second pass to be reported; anything found still is.  (A pytest without the key:
    nothing changes.)"""
    try:
        from _pytest.unraisableexception import gc_collect_iterations_key
    except ImportError:
        return
    config.stash[gc_collect_iterations_key] = 1


def pytest_unconfigure(config):
    folder = getattr(config, "_stand_shared", None)
    if folder:
        import shutil

        shutil.rmtree(folder, ignore_errors=True)
        os.environ.pop("STAND_TEST_SHARED", None)


def _compile_sources() -> None:
    """Bytecode of every module of the packages and of the tests' helpers, written once here
    (a fresh clone has none: each worker would compile every module the warm-up did not
    import); ``compileall`` writes each file atomically, as an import does."""
    import compileall
    from pathlib import Path

    if sys.dont_write_bytecode:
        return
    tests = Path(__file__).parent
    root = tests.parent
    for pkg in ("stand", "dsp", "vision"):
        compileall.compile_dir(str(root / pkg), quiet=2, workers=1)
    compileall.compile_dir(str(tests / "oracles"), quiet=2)
    for fn in tests.glob("_*.py"):
        compileall.compile_file(str(fn), quiet=2)


def _rewrite_test_modules(config) -> int:
    """Write pytest's cached rewritten-assert bytecode of every test module that has none
    (what each worker would otherwise do in its collection: measured 19.3 s of CPU for a
    whole collection without the caches, 9.3 s with them); returns the number written.
    Uses pytest's own rewriting (``_pytest.assertion.rewrite``: private, so any failure
    leaves the rewriting to the workers, as without this step)."""
    try:
        from pathlib import Path

        from _pytest.assertion import rewrite as rw

        if sys.dont_write_bytecode or config.getini("python_files") != ["test_*.py", "*_test.py"]:
            return 0
        state = config.stash[rw.assertstate_key]
        written = 0
        for fn in sorted(Path(__file__).parent.rglob("test_*.py")):
            pyc = rw.get_cache_dir(fn) / (fn.name[:-3] + rw.PYC_TAIL)
            if rw._read_pyc(fn, pyc) is not None or not rw.try_makedirs(pyc.parent):
                continue
            stat, co = rw._rewrite_test(fn, config)
            written += bool(rw._write_pyc(state, co, stat, pyc))
        return written
    except Exception:   # noqa: BLE001 - an optimisation only
        return 0
