"""Error against run time on every sample scene: ``stand accuracy SCENE --rtols 1e-6,1e-8``.

The full walk of issue 43's acceptance (tests/test_accuracy_reference.py walks a
representative subset with ``--duration 0.3``).  For each scene in data_samples/scenes it
runs the command in its own process and prints one line: exit code, whole-process wall time
[s], the reference (method, tolerance, why that method), its own estimated error [m] against
max |r_ref| [m], the ladder's relative errors, and the notes (a reference stopped short of the
requested tolerance by the budget or by round-off says so).  Exit 1 if any scene exits
non-zero.

Usage: ``python benchmarks/bench_accuracy_walk.py [--duration S] [--rtols 1e-6,1e-8] [NAME ...]``
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def walk(names, rtols: str, duration) -> int:
    bad = 0
    for p in sorted((ROOT / "data_samples" / "scenes").glob("*.toml")):
        if names and p.stem not in names:
            continue
        cmd = [sys.executable, "-m", "stand", "accuracy", str(p), "--rtols", rtols, "--json"]
        cmd += ["--duration", str(duration)] if duration else []
        t0 = time.perf_counter()
        pr = subprocess.run(cmd, capture_output=True, text=True)
        wall = time.perf_counter() - t0
        if pr.returncode:
            bad += 1
            last = (pr.stderr.strip().splitlines() or ["?"])[-1]
            print(f"{p.stem:32s} exit {pr.returncode} {wall:7.1f} s  {last}", flush=True)
            continue
        d = json.loads(pr.stdout)
        errs = ", ".join(f"{r['method']} {r['rtol']:.0e}: {r['relative_error']:.2e}" for r in d["rows"])
        print(f"{p.stem:32s} exit 0 {wall:7.1f} s  reference {d['reference']}; own error "
              f"{d['reference_error_m']:.2e} m of {d['scale_m']:.3g} m; {errs}", flush=True)
        for n in d["notes"]:
            print(f"{'':32s} note: {n}", flush=True)
    return 1 if bad else 0


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("names", nargs="*", help="scene names (default: every sample scene)")
    ap.add_argument("--rtols", default="1e-6,1e-8")
    ap.add_argument("--duration", type=float, default=None, help="only the first S seconds")
    a = ap.parse_args()
    sys.exit(walk(set(a.names), a.rtols, a.duration))
