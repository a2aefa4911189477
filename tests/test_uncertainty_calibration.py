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


#: Six draws per path below.  For a calibrated std, 6 RMS(z)^2 is chi-square with 6
#: degrees of freedom: RMS(z) > 1.9 has probability 0.1 % (chi2_6 at 99.9 % = 22.5); a
#: draw falls outside |z| < 2 with probability 4.6 %, so 3 or more of 6 outside has
#: probability 0.2 % (binomial): the bounds 1.9 and 4 of 6.  The std that was 5 to 10
#: times too small (the tachometer's angle left out, issue 30) fails both by far.
RMS_FAST, COVER_FAST = 1.9, 4 / 6


def _check(table, path, names, draws=6):
    q = table[path]
    assert set(q) == set(names)
    for name, (rms, c1, c2, n) in q.items():
        assert n == draws
        assert rms < RMS_FAST, (path, name, rms)
        assert c2 >= COVER_FAST - 1e-9, (path, name, c2)


def test_stated_std_covers_the_truth_without_a_speed_channel():
    """x, y only: the angle estimated from the whirl, fitted with the model (a shorter
    run-up, 12 -> 25 rev/s in 6 s at 400 samples/s: the angle's fixed point costs ~13
    model fits a draw)."""
    table = calibration(["no-speed"], seeds=6, fs_hz=400.0, f_start_hz=12.0, f_end_hz=25.0,
                        duration_s=6.0)
    _check(table, "no-speed", {"f0", "zeta", "U", "critical"})


def test_stated_std_covers_the_truth_without_a_speed_channel_with_probe_runout():
    """The same with a 2 um 1X runout on the probes, fixed to the rotor at an angle drawn
    per draw: not fitted without a speed channel, allowed for in the ± (before, the DAQ
    sample's 2 um runout put zeta 4.3 and U 3.3 of their stds off)."""
    table = calibration(["no-speed-runout"], seeds=6, fs_hz=400.0, f_start_hz=12.0,
                        f_end_hz=25.0, duration_s=6.0)
    _check(table, "no-speed-runout", {"f0", "zeta", "U", "critical"})


def test_stated_std_covers_the_truth_with_a_held_tachometer():
    """A held tachometer display (60 pulses per revolution, 0.5 s gates, 1 rpm), no
    keyphasor: the display's quantum and timing are in the ±."""
    _check(calibration(["tachometer"], seeds=6), "tachometer", {"f0", "zeta", "U", "critical"})


def test_stated_std_covers_the_truth_on_a_stand_recording():
    """`stand analyze REC.h5` on the stand's own recording: the steady 1X's unbalance and
    its angle (f0 and damping come from the recording's scene, without a ±)."""
    _check(calibration(["recording"], seeds=6), "recording", {"U", "angle"})


def test_stand_recording_critical_speed_uses_the_scenes_damping(tmp_path):
    """On that path no model is fitted: the critical speed is the run-up's 1X peak with
    the sweep lag removed, with the recording's own zeta = 0.04 (with zeta = 0 it removed
    the sweep-limited lag, 11.58 rev/s for 12.02: -3.6 %).  The lag correction's own
    error at 2 rev/s^2 is ~0.1 %: within 0.5 % of f0 / sqrt(1 - 2 zeta^2)."""
    import io
    import json
    import math
    from contextlib import redirect_stdout

    import stand
    from bench_uncertainty import RECORDING_SCENE
    from stand.cli.main import main

    h5 = tmp_path / "rec.h5"
    stand.run(stand.load(RECORDING_SCENE.format(e=40e-6, beta=30.0, seed=1))).write(h5)
    out = io.StringIO()
    with redirect_stdout(out):
        assert main(["analyze", str(h5), "--json"]) == 0
    d = json.loads(out.getvalue())
    k, c, m = 34108.64, 36.1911, 6.0
    zeta = c / (2 * math.sqrt(k * m))
    truth = math.sqrt(k / m) / (2 * math.pi) / math.sqrt(1 - 2 * zeta * zeta)
    assert abs(d["critical_speed_hz"] / truth - 1) < 0.005, d["critical_speed_hz"]
    assert "from the recording's scene" in d["critical_speed_method"]
