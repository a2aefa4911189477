"""The test run's compile warm-up from a cold cache (issue 43): CPU seconds on a fresh clone.

``tests/conftest.py`` compiles every model kind's kernels, the screen renderer and the two
fits before the test processes start.  A fresh ``git clone`` (what CI runs) has no
``__pycache__`` and no precompiled module, so all of it compiles.  This script clones the
committed ``HEAD`` of this repository (and, as the peer measured in the same run, another
revision: ``--against REV``) into a temporary folder and measures, on each clone:

* ``--items``: each warm-up item alone, each on its own fresh clone;
* ``--full`` (default): conftest's whole warm-up (its ``pytest_configure``: the items as many
  at a time as there are cores).

Measured: user + sys CPU seconds of the process and everything it waited for (its
subprocesses and their C compiler, ``resource.getrusage(RUSAGE_CHILDREN)``), and wall
seconds (which count the other work on a shared machine).  ``--profile`` prints, for each
item, the functions numba compiled, by exclusive CPU seconds (numba's ``numba:compile``
events; what is not under one is the precompiled module's own code generation and gcc).

Usage: ``python benchmarks/bench_cold_warmup.py [--items] [--full] [--against REV] [--profile]``
"""
from __future__ import annotations

import argparse
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: the warm-up items of tests/conftest.py, each as the code its subprocess runs
ITEMS = {
    "generic kind": "from stand.api.warmup import warmup; warmup(kinds=[1], say=lambda s: None)",
    "planar kind": "from stand.api.warmup import warmup; warmup(kinds=[0], say=lambda s: None)",
    "blurred-spot fit": "from vision.blur import warm; warm()",
    "line fit": "from dsp._line_kernel import warm; warm()",
    "screen renderer": "from stand.integrate import precompiled\n"
                       "precompiled.build('stand.instruments.render:render_frame')",
}
FULL = ("import sys; sys.path.insert(0, 'tests'); import conftest\n"
        "class _Config: pass\n"
        "conftest.pytest_configure(_Config())")

#: prepended with --profile: numba's compile events, exclusive CPU seconds per function
PROFILE = '''
import atexit, time
from numba.core import event
_stack, _rows = [], {}
class _L(event.Listener):
    def on_start(self, ev):
        _stack.append([time.process_time(), 0.0])
    def on_end(self, ev):
        t0, inner = _stack.pop()
        total = time.process_time() - t0
        if _stack:
            _stack[-1][1] += total
        d = ev.data.get("dispatcher")
        name = getattr(getattr(d, "py_func", None), "__qualname__", str(d))
        mod = getattr(getattr(d, "py_func", None), "__module__", "")
        key = mod + "." + name
        n, s = _rows.get(key, (0, 0.0))
        _rows[key] = (n + 1, s + total - inner)
event.register("numba:compile", _L())
def _show():
    tot = sum(s for _, s in _rows.values())
    print(f"  numba:compile exclusive CPU {tot:.1f} s, of which:")
    for k, (n, s) in sorted(_rows.items(), key=lambda kv: -kv[1][1])[:14]:
        print(f"    {s:6.2f} s  x{n}  {k}")
atexit.register(_show)
'''


def _clone(rev: str | None, into: Path) -> Path:
    into.mkdir(parents=True)
    dest = into / "c"
    subprocess.run(["git", "clone", "-q", str(ROOT), str(dest)], check=True)
    if rev:
        subprocess.run(["git", "-C", str(dest), "checkout", "-q", rev], check=True)
    return dest


def _cpu_run(code: str, cwd: Path) -> tuple[float, float, int]:
    """(user + sys CPU s of ``python -c code`` and all it waited for, wall s, exit code)."""
    env = {k: v for k, v in os.environ.items() if not k.startswith(("NUMBA_", "STAND_"))}
    env["PYTHONPATH"] = str(cwd)
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    rc = subprocess.run([sys.executable, "-c", code], cwd=cwd, env=env).returncode
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return cpu, wall, rc


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--items", action="store_true", help="each warm-up item alone")
    ap.add_argument("--full", action="store_true", help="conftest's whole warm-up (default)")
    ap.add_argument("--against", metavar="REV", help="the peer: this revision, same run")
    ap.add_argument("--profile", action="store_true", help="numba's compiles per item")
    ap.add_argument("--only", metavar="NAME", action="append", help="only these items")
    args = ap.parse_args(argv)
    if not args.items:
        args.full = True
    revs = [("HEAD", None)] + ([(args.against, args.against)] if args.against else [])
    load0 = os.getloadavg()[0]
    print(f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, load {load0:.1f}, "
          f"{os.cpu_count()} cores; CPU = user + sys s (with subprocesses and gcc)")
    results: dict = {}
    with tempfile.TemporaryDirectory(prefix="cold-warmup-") as tmp:
        jobs = []
        if args.items:
            jobs += [(name, code) for name, code in ITEMS.items()
                     if not args.only or name in args.only]
        if args.full:
            jobs.append(("full warm-up (conftest)", FULL))
        for i, (name, code) in enumerate(jobs):
            for label, rev in revs:
                clone = _clone(rev, Path(tmp) / f"{i}-{label}")
                print(f"{name} [{label}]:", flush=True)
                cpu, wall, rc = _cpu_run((PROFILE if args.profile else "") + code, clone)
                results[(name, label)] = cpu
                print(f"  {cpu:7.1f} s CPU, {wall:6.1f} s wall" + ("" if rc == 0 else f", exit {rc}"),
                      flush=True)
                shutil.rmtree(clone, ignore_errors=True)
    if args.against:
        print(f"\n| item | {args.against} [s CPU] | HEAD [s CPU] | ratio |\n|---|---:|---:|---:|")
        for name, _ in jobs:
            a, b = results[(name, args.against)], results[(name, "HEAD")]
            print(f"| {name} | {a:.1f} | {b:.1f} | {b / a:.2f} |")
    print(f"load {load0:.1f} -> {os.getloadavg()[0]:.1f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
