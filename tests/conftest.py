"""Test-session hooks.

* Compile ahead, once, before the test processes start: every model kind's kernels
  (numba's cache and the precompiled modules), one process per kind in parallel, so
  that pytest-xdist's workers load them instead of each compiling the same kernels.
* Print the adversarial harness' table at the end of the run (tests/test_adversarial.py
  records it as a user property; this works under pytest-xdist).
"""
import subprocess
import sys

_TABLES = []


def pytest_runtest_logreport(report):
    if report.when == "call":
        for key, value in getattr(report, "user_properties", ()):
            if key == "adversarial_table":
                _TABLES.append(value)


def pytest_terminal_summary(terminalreporter):
    for table in _TABLES:
        terminalreporter.write_sep("-", "adversarial harness")
        terminalreporter.write_line(table)


def pytest_configure(config):
    if hasattr(config, "workerinput"):   # an xdist worker: the controller compiled already
        return
    from stand.model.kernels import KIND_NAMES

    code = "from stand.api.warmup import warmup; warmup(kinds=[{k}], say=lambda s: None)"
    procs = [subprocess.Popen([sys.executable, "-c", code.format(k=k)]) for k in sorted(KIND_NAMES)]
    procs.append(subprocess.Popen([sys.executable, "-c", "from vision.blur import warm; warm()"]))
    procs.append(subprocess.Popen([sys.executable, "-c", "from dsp._line_kernel import warm; warm()"]))
    for p in procs:
        p.wait()
