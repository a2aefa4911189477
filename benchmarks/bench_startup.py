"""What a user waits for: whole-process times of the commands, as ratios to a baseline.

Baseline: ``python -c "import numpy, scipy.integrate, h5py"`` (what any run needs).
Measured in the same run, best of N (warm caches unless said):

* ``stand --help``;
* ``stand theory`` on data_samples/scenes/ball_runup.toml;
* ``stand run`` on ball_runup.toml (the README's command);
* ``stand analyze`` on data_samples/recordings/stand_cameras.h5;
* the Python API equivalent of ``stand run`` in one process (``stand.run`` + ``write``), and
  its integration alone;
* ``--cold``: the first ``stand run`` after the numba caches are dropped (compilation).

Usage: ``python benchmarks/bench_startup.py [--repeat 5] [--cold]``
"""
from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SCENE = ROOT / "data_samples" / "scenes" / "ball_runup.toml"
RECORDING = ROOT / "data_samples" / "recordings" / "stand_cameras.h5"


def wall(argv, repeat):
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        r = subprocess.run(argv, capture_output=True, text=True, cwd=ROOT)
        best = min(best, time.perf_counter() - t0)
        if r.returncode not in (0, 1):
            raise SystemExit(f"{' '.join(map(str, argv))}: exit {r.returncode}\n{r.stderr}")
    return best


def drop_numba_caches():
    for d in (ROOT / "stand").rglob("__pycache__"):
        for f in list(d.glob("*.nbi")) + list(d.glob("*.nbc")):
            f.unlink()


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--cold", action="store_true", help="also time the first run after dropping the caches")
    a = ap.parse_args()
    py = sys.executable
    stand = [py, "-m", "stand"]
    with tempfile.TemporaryDirectory() as d:
        out = Path(d) / "r.h5"
        api = (f"import time, stand; t0 = time.perf_counter(); r = stand.run(stand.load({str(SCENE)!r})); "
               f"r.write({str(out) + '.api.h5'!r}, ); print(time.perf_counter() - t0, r.stats.wall_time)")
        wall([*stand, "run", SCENE, "-o", out, "--force"], 1)          # warm the caches
        rows = [("baseline: import numpy, scipy.integrate, h5py",
                 wall([py, "-c", "import numpy, scipy.integrate, h5py"], a.repeat))]
        rows.append(("stand --help", wall([*stand, "--help"], a.repeat)))
        rows.append(("stand theory ball_runup.toml", wall([*stand, "theory", SCENE], a.repeat)))
        rows.append(("stand run ball_runup.toml -o r.h5 (README)",
                     wall([*stand, "run", SCENE, "-o", out, "--force"], a.repeat)))
        rows.append(("stand analyze stand_cameras.h5", wall([*stand, "analyze", RECORDING], a.repeat)))
        rows.append(("python: stand.run + write (whole process)", wall([py, "-c", api], a.repeat)))
        r = subprocess.run([py, "-c", api], capture_output=True, text=True, cwd=ROOT)
        inproc, integ = (float(v) for v in r.stdout.split())
        if a.cold:
            drop_numba_caches()
            rows.append(("cold first stand run (caches dropped)",
                         wall([*stand, "run", SCENE, "-o", out, "--force"], 1)))
    base = rows[0][1]
    print(f"{'what':<48}{'wall [s]':>10}{'/ baseline':>12}")
    for name, t in rows:
        print(f"{name:<48}{t:>10.3f}{t / base:>12.2f}")
    print(f"{'in process: stand.run + write':<48}{inproc:>10.3f}")
    print(f"{'in process: integration alone':<48}{integ:>10.4f}")


if __name__ == "__main__":
    main()
