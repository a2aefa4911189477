"""Issue 30, item 3 (the fast version of benchmarks/bench_uncertainty.py): the stated
std of the run-up identification covers the truth at its stated rate.

A short exact run-up (:mod:`oracles.runup_exact`, 10 -> 28 rev/s in 9 s through
18.5 Hz, 500 samples/s, 2 µm probe noise) over 8 noise seeds, through ``stand analyze``
with the keyphasor.  With 8 draws the RMS of z = (estimate - truth) / std scatters by
about 1 / sqrt(2 x 8) = 0.25 about 1, so the bound is 1.8 (a std 10 times too small, as
before issue 30, gives RMS(z) ~ 10); the benchmark draws 24 and more.
"""
from __future__ import annotations

import sys
from pathlib import Path

BENCH = Path(__file__).resolve().parents[1] / "benchmarks"
if str(BENCH) not in sys.path:
    sys.path.insert(0, str(BENCH))

from bench_uncertainty import calibration  # noqa: E402


def test_stated_std_covers_the_truth():
    table = calibration(["keyphasor"], seeds=8, fs_hz=500.0, f_start_hz=10.0, f_end_hz=28.0,
                        duration_s=9.0)
    q = table["keyphasor"]
    assert set(q) == {"f0", "zeta", "U", "angle", "critical"}
    for name, (rms, c1, c2, n) in q.items():
        assert n == 8
        assert rms < 1.8, (name, rms)
        assert c2 >= 0.75, (name, c2)
