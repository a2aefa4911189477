"""CPU of the run-up fit (:func:`dsp.response_fit.fit_unbalance_response`, with the delay and
sensor tests of ``stand analyze``) on the records of tests/test_daq_artefacts.py and
tests/test_dsp_speed.py, and its results, to compare two versions of the code.

    python benchmarks/bench_runup_fit.py [--repeats 3] [--save FILE] [--compare FILE] [--only TEXT]

Each case's CPU is the least of ``--repeats`` runs (``time.process_time``; run with
OPENBLAS_NUM_THREADS=1).  ``--save`` pickles the results; ``--compare`` prints, per case,
the largest relative difference of f_1, zeta, f_c, U and the angle and of their stds
against a saved run (the older code run with PYTHONPATH pointing at its checkout).
"""
import argparse
import math
import pickle
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "tests")]

VALUES = ("natural_frequency_hz", "damping_ratio", "critical_speed_hz", "specific_unbalance_m",
          "unbalance_angle_deg", "angle_rad")


def cases():
    from test_daq_artefacts import ChannelFilter, _identify, _lowpass, _record
    import test_dsp_speed as tds
    from dsp.response_fit import fit_response_without_speed, fit_unbalance_response

    t, z, phi, w, a = _record()
    t2, z2, phi2, w2, a2 = _record(start_hz=1.5)
    bessel = ChannelFilter("bessel", 4, 40.0)
    res = ChannelFilter("none", resonance_hz=40.0, resonance_q=5.0)
    hp = ChannelFilter("none", highpass_hz=0.5)
    r = tds._runup_record(offset=3e-5 - 2e-5j, runout=2e-6 + 1e-6j, fs=400.0, noise=1e-6, T=16.0)
    return {
        "analyze, clean": lambda: _identify(t, z, phi, w, a)[0],
        "analyze, declared Bessel": lambda: _identify(t, bessel.apply(t, z), phi, w, a,
                                                      channel_filter=bessel)[0],
        "analyze, undeclared low-pass": lambda: _identify(t, _lowpass(t, z), phi, w, a)[0],
        "analyze, sensor resonance": lambda: _identify(t, res.apply(t, z), phi, w, a)[0],
        "analyze, high-pass": lambda: _identify(t2, hp.apply(t2, z2), phi2, w2, a2)[0],
        "fit": lambda: vars_of(fit_unbalance_response(*r)),
        "fit with delay": lambda: vars_of(fit_unbalance_response(*r, fit_delay=True)),
        "fit without speed": lambda: vars_of(fit_response_without_speed(r[0], r[1])[0]),
    }


def vars_of(fit):
    import dataclasses

    return {f.name: getattr(fit, f.name) for f in dataclasses.fields(fit)}


def largest(a: dict, b: dict, std: bool):
    out = (0.0, "")
    for k in VALUES:
        k = k + "_std" if std else k
        u, v = a.get(k), b.get(k)
        if isinstance(u, float) and math.isfinite(u) and u != 0 and v is not None:
            out = max(out, (abs(u - v) / abs(u), k))
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--save")
    ap.add_argument("--compare")
    ap.add_argument("--only", default="", help="the cases whose name contains this")
    args = ap.parse_args()
    old = pickle.load(open(args.compare, "rb")) if args.compare else None
    out, total = {}, 0.0
    head = " values: largest rel. diff | stds: largest rel. diff |" if old else ""
    print("| case | CPU [s] |" + head)
    print("|---|---|" + ("---|---|" if old else ""))
    for name, run in cases().items():
        if args.only not in name:
            continue
        cpu = []
        for _ in range(args.repeats):
            t0 = time.process_time()
            out[name] = run()
            cpu.append(time.process_time() - t0)
        total += min(cpu)
        row = f"| {name} | {min(cpu):.3f} |"
        if old:
            (dv, kv), (ds, ks) = (largest(old[name], out[name], std) for std in (False, True))
            row += f" {dv:.1e} ({kv}) | {ds:.1e} ({ks}) |"
        print(row)
    print(f"| total | {total:.2f} |" + (" | |" if old else ""))
    if args.save:
        pickle.dump(out, open(args.save, "wb"))


if __name__ == "__main__":
    main()
