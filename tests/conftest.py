"""Test-session hooks.

* Compile ahead, once, before the test processes start: every model kind's kernels
  (numba's cache and the precompiled modules), the screen renderer, the blurred-spot and
  line fits, one process each, as many at a time as there are cores, so that
  pytest-xdist's workers load them instead of each compiling the same kernels.
* The full sweeps and calibrations are marked ``full`` and left out by default
  (pyproject ``addopts``); ``pytest -m full`` runs them (benchmarks/README.md).
* One BLAS thread per test process (set before numpy is imported).
* Print the adversarial harness' table at the end of the run (tests/test_adversarial.py
  records it as a user property; this works under pytest-xdist).
"""
import os
import subprocess
import sys
import time

# One BLAS thread per test process, as the command line has (stand/cli/main.py), set before
# any test module imports numpy: pytest-xdist's parallelism is processes and the tests'
# matrices are small; OpenBLAS' threads spinning on a busy 2-core machine cost a run-up fit
# 6x its CPU (2.0 s instead of 0.32 s).  A value set in the environment is kept.
for _v in ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "BLIS_NUM_THREADS", "VECLIB_MAXIMUM_THREADS"):
    os.environ.setdefault(_v, "1")

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


def pytest_configure(config):
    if hasattr(config, "workerinput"):   # an xdist worker: the controller compiled already
        return
    import os

    from stand.model.kernels import KIND_NAMES

    kind = "from stand.api.warmup import warmup; warmup(kinds=[{k}], say=lambda s: None)"
    # longest first (CPU seconds from a cold cache, 2026-11-29, benchmarks/README.md): the
    # generic kind, the planar kind, the blurred-spot fit, the line fit, the screen renderer
    # (else each worker JIT-compiles it and the command line starts a background build of it)
    codes = [kind.format(k=k) for k in sorted(KIND_NAMES, reverse=True)]
    codes += ["from vision.blur import warm; warm()", "from dsp._line_kernel import warm; warm()",
              "from stand.integrate import precompiled\n"
              "try: precompiled.build('stand.instruments.render:render_frame')\n"
              "except Exception: pass   # no C compiler: numba's JIT on first use"]
    # as many at a time as there are cores: no faster with more, and each holds ~0.8 GB
    at_once, running = max(1, os.cpu_count() or 1), []
    for code in codes:
        while len(running) >= at_once:
            running = [p for p in running if p.poll() is None]
            time.sleep(0.05)
        running.append(subprocess.Popen([sys.executable, "-c", code]))
    for p in running:
        p.wait()
