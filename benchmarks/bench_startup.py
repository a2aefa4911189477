"""What a user waits for: whole-process times of the commands, as ratios to a baseline.

Baseline: ``python -c "import numpy, scipy.integrate, h5py"`` (what any run needs).
Measured in the same run, best of N (warm caches unless said):

* ``stand --help``;
* ``stand theory`` on data_samples/scenes/ball_runup.toml;
* ``stand run`` on ball_runup.toml (the README's command);
* ``stand analyze`` on data_samples/recordings/stand_cameras.h5;
* the Python API equivalent of ``stand run`` in one process (``stand.run`` + ``write``), and
  its integration alone;
* ``--cold``: the first ``stand run`` after every compiled cache is dropped (numba's and the
  precompiled kernels with their C helper objects: a fresh install), and the same with
  numba's just-in-time compilation only (``STAND_KERNELS=jit``);
* ``--fallback``: the integration of a 2 s ball_runup on the pure-Python/numpy fallback
  (``STAND_DISABLE_JIT=1``) against the compiled kernels, in process.  The two answers are
  checked first (``benchmarks/_peers.py``): the fallback's samples must agree with the
  compiled run's within ``FALLBACK_TOL`` (relative to the largest state component), else
  the row reads "invalid (error X > tolerance Y)" and no ratio is printed.

The warm ``stand run`` uses the precompiled kernels (built by the first run or by
``stand warmup``); "stand run, numba JIT cache" shows the same with ``STAND_KERNELS=jit``.

* ``--kinds``: one warm ``stand run`` per sample scene kind (planar, spatial, flexible,
  platform, bodies; :data:`KIND_SCENES`), whole process minus the run's own integration
  time (printed by the command), as a ratio to the baseline (goal <= 1.0): medians of
  ``--repeat`` rounds, the kinds' and the baseline's (taken between the kinds), with the
  load average beside them.

Usage: ``python benchmarks/bench_startup.py [--repeat 5] [--cold] [--fallback] [--kinds]``
"""
from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _peers import check_peer  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
#: largest max |difference| of the fallback's samples from the compiled run's, relative to
#: the largest |state|: the same steps in another arithmetic order (100 x the scene's rtol)
FALLBACK_TOL = 1e-6
SCENE = ROOT / "data_samples" / "scenes" / "ball_runup.toml"
RECORDING = ROOT / "data_samples" / "recordings" / "stand_cameras.h5"
#: one sample scene per scene kind (--kinds)
KIND_SCENES = ("ball_runup", "family_spatial", "family_flexible", "platform_paper004",
               "body_liquid_float", "body_two_axis_pendulum")


def run_minus_integration(argv, repeat):
    """Median over ``repeat`` whole-process ``stand run`` times of the time minus the
    integration time it prints (``[..., 0.05 s]``): (whole, integration) of the median round
    [s] (a median: the machine may be shared and noisy)."""
    import re

    rounds = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        r = subprocess.run(argv, capture_output=True, text=True, cwd=ROOT)
        t = time.perf_counter() - t0
        if r.returncode not in (0, 1):
            raise SystemExit(f"{' '.join(map(str, argv))}: exit {r.returncode}\n{r.stderr}")
        m = re.search(r", ([0-9.]+) s\]", r.stdout)
        rounds.append((t, float(m.group(1)) if m else 0.0))
    rounds.sort(key=lambda w: w[0] - w[1])
    return rounds[len(rounds) // 2]


def wall(argv, repeat, env=None, stat=min):
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        r = subprocess.run(argv, capture_output=True, text=True, cwd=ROOT,
                           env=None if env is None else {**os.environ, **env})
        times.append(time.perf_counter() - t0)
        if r.returncode not in (0, 1):
            raise SystemExit(f"{' '.join(map(str, argv))}: exit {r.returncode}\n{r.stderr}")
    return stat(times)


def drop_compiled_caches():
    """numba's caches and the precompiled kernels (with the cached C helper objects)."""
    for d in (ROOT / "stand").rglob("__pycache__"):
        for f in list(d.glob("*.nbi")) + list(d.glob("*.nbc")):
            f.unlink()
    shutil.rmtree(ROOT / "stand" / "__pycache__" / "precompiled", ignore_errors=True)


FALLBACK = """
import json, os, sys, time
import stand
sc = stand.load({scene!r})
from dataclasses import replace
sc = replace(sc, run=replace(sc.run, duration=2.0))
stand.run(sc)                       # compile / load
runs = [stand.run(sc) for _ in range(3 if os.environ.get("STAND_DISABLE_JIT") != "1" else 1)]
print(json.dumps({{"best": min(r.stats.wall_time for r in runs), "state": runs[-1].state.tolist()}}))
"""


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--cold", action="store_true", help="also time the first run after dropping the caches")
    ap.add_argument("--fallback", action="store_true", help="also time the pure-Python fallback")
    ap.add_argument("--kinds", action="store_true",
                    help="also one stand run per sample scene kind (minus its integration)")
    a = ap.parse_args()
    py = sys.executable
    stand = [py, "-m", "stand"]
    with tempfile.TemporaryDirectory() as d:
        out = Path(d) / "r.h5"
        api = (f"import time, stand; t0 = time.perf_counter(); r = stand.run(stand.load({str(SCENE)!r})); "
               f"stand.save(r, {str(out) + '.api.h5'!r}); print(time.perf_counter() - t0, r.stats.wall_time)")
        wall([*stand, "run", SCENE, "-o", out, "--force"], 1)          # warm the caches
        rows = [("baseline: import numpy, scipy.integrate, h5py",
                 wall([py, "-c", "import numpy, scipy.integrate, h5py"], a.repeat))]
        rows.append(("stand --help", wall([*stand, "--help"], a.repeat)))
        rows.append(("stand theory ball_runup.toml", wall([*stand, "theory", SCENE], a.repeat)))
        rows.append(("stand run ball_runup.toml -o r.h5 (README)",
                     wall([*stand, "run", SCENE, "-o", out, "--force"], a.repeat)))
        jit = {"STAND_KERNELS": "jit"}
        wall([*stand, "run", SCENE, "-o", out, "--force"], 1, jit)     # numba's cache
        rows.append(("stand run, numba JIT cache (STAND_KERNELS=jit)",
                     wall([*stand, "run", SCENE, "-o", out, "--force"], a.repeat, jit)))
        rows.append(("stand analyze stand_cameras.h5", wall([*stand, "analyze", RECORDING], a.repeat)))
        rows.append(("python: stand.run + write (whole process)", wall([py, "-c", api], a.repeat)))
        r = subprocess.run([py, "-c", api], capture_output=True, text=True, cwd=ROOT)
        inproc, integ = (float(v) for v in r.stdout.split())
        if a.cold:
            drop_compiled_caches()
            rows.append(("cold first stand run (all compiled caches dropped)",
                         wall([*stand, "run", SCENE, "-o", out, "--force"], 1)))
            drop_compiled_caches()
            rows.append(("cold first stand run, numba JIT only",
                         wall([*stand, "run", SCENE, "-o", out, "--force"], 1, jit)))
            wall([*stand, "run", SCENE, "-o", out, "--force"], 1)      # leave the caches warm
        kinds = []
        if a.kinds:
            subprocess.run([*stand, "warmup", "--all"], capture_output=True, cwd=ROOT)
            base_runs = []
            for name in KIND_SCENES:
                argv = [*stand, "run", ROOT / "data_samples" / "scenes" / f"{name}.toml", "-o",
                        out, "--force"]
                wall(argv, 1)                                          # warm the caches
                base_runs.append(wall([py, "-c", "import numpy, scipy.integrate, h5py"],
                                      a.repeat, stat=np.median))
                kinds.append((name, *run_minus_integration(argv, a.repeat)))
            kind_base, load = float(np.median(base_runs)), os.getloadavg()
        fallback = None
        if a.fallback:
            code = FALLBACK.format(scene=str(SCENE))
            fast = json.loads(subprocess.run([py, "-c", code], capture_output=True, text=True,
                                             cwd=ROOT, check=True).stdout)
            slow = json.loads(subprocess.run([py, "-c", code], capture_output=True, text=True,
                                             cwd=ROOT, check=True,
                                             env={**os.environ, "STAND_DISABLE_JIT": "1"}).stdout)
            a_, b_ = np.asarray(fast["state"]), np.asarray(slow["state"])
            err = (float(np.max(np.abs(a_ - b_)) / np.max(np.abs(a_))) if a_.shape == b_.shape
                   else float("inf"))
            fallback = (fast["best"], slow["best"], check_peer("fallback", err, FALLBACK_TOL))
    base = rows[0][1]
    print(f"{'what':<48}{'wall [s]':>10}{'/ baseline':>12}")
    for name, t in rows:
        print(f"{name:<48}{t:>10.3f}{t / base:>12.2f}")
    if kinds:
        print(f"\nmedians of {a.repeat}: baseline {kind_base:.3f} s; load average "
              f"{load[0]:.1f} {load[1]:.1f} {load[2]:.1f} on {os.cpu_count()} CPUs")
        print(f"{'stand run <scene> -o r.h5 (warm)':<32}{'whole [s]':>10}{'integration':>12}"
              f"{'(whole - integration) / baseline':>34}")
        for name, t, integ in kinds:
            print(f"{name:<32}{t:>10.3f}{integ:>12.3f}{(t - integ) / kind_base:>34.2f}")
        print()
    print(f"{'in process: stand.run + write':<48}{inproc:>10.3f}")
    print(f"{'in process: integration alone':<48}{integ:>10.4f}")
    if fallback is not None:
        t_c, t_p, peer = fallback
        print(f"{'2 s of ball_runup, compiled kernels':<48}{t_c:>10.4f}")
        if peer.valid:
            print(f"{'2 s of ball_runup, pure-Python fallback':<48}{t_p:>10.3f}{t_p / t_c:>11.0f}x"
                  f"  (samples agree to {peer.error:.1g})")
        else:
            print(f"{'2 s of ball_runup, pure-Python fallback':<48}{peer.verdict}")


if __name__ == "__main__":
    main()
