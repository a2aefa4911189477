"""Coverage of the ± of ``stand analyze`` on a Bode table (dsp.bode.modal_fit): does
|estimate - truth| <= k std hold at the normal rates (68 % for k = 1, 95 % for k = 2)?

A script, not a test::

    python benchmarks/bench_bode_coverage.py [--draws 1000] [--sweep-draws 300]

The tables are written here, independently of the stand (own formulas, no dsp/stand
function):

* ``steady_table`` -- the closed-form steady unbalance response of the rigid rotor,
  z1 = e e^{i beta} r^2 / (1 - r^2 + 2 i zeta r) + c, r = f / f0, at the speeds of
  data_samples/daq/bode_table.csv, with complex white noise.
* ``sweep_table`` -- the Jeffcott rotor M z'' + C z' + K z = M e (phi'^2 - i phi'')
  e^{i(phi + beta)} on a linear run-up (phi'' = 2 pi rate), integrated by its two modes
  (scipy.signal.lfilter, 0.1-ms steps), order tracked per revolution (mean of z e^{-i phi})
  and averaged in 0.2-Hz bins: the sample's own recipe (``stand daq --bode`` of
  bode_runup.toml).  With the sample's truth it reproduces the sample to 0.033 um RMS,
  which is the probes' noise through the tracking (1.5 um at 1 kHz over 4-s bins: 0.034).

Parts: (1) steady tables, noise 0.03 um and 0.56 um per component (the probes' noise and
the sample's old residual RMS / sqrt 2); (2) run-up tables: the sample's truth (f0 12 Hz,
zeta 0.04, 0.05 rev/s^2) and a sharper, faster one (f0 10 Hz, zeta 0.02, 0.1 rev/s^2),
noise 0.023 um per component; each with the first-order sweep model alone ("before",
``dsp.bode._sweep_corrected`` bypassed) and with the exact-sweep bias correction ("after").
Printed per quantity: the share within 1 and 2 std and the mean and SD of z = error / std.

Measured (1000 steady draws, 200 run-up draws; binomial SD of a 68 % share 0.015 / 0.033):
steady, 0.56 um: within 1 std f0 0.74, zeta 0.70, U 0.71, angle 0.70; within 2 std
1.00, 0.97, 0.96, 0.97; mean z |.| <= 0.04 (0.03 um: the same).  Run-up, the sample's
truth: before, z = +0.84, -0.05, -0.39, -2.81 (f0, zeta, U, angle; SD 0.01-0.03: the
noise does not matter, the bias does; angle within 2 std in 0 % of the draws); after,
+0.05, +0.00, +0.05, -0.10 (100 % within 1 std).  10 Hz / zeta 0.02 / 0.1 rev/s^2:
before +1.85, +1.22, +0.57, -2.37; after +0.59, +0.74, +0.54, -0.56.
"""
from __future__ import annotations

import argparse
import math
from pathlib import Path

import numpy as np

TWO_PI = 2 * math.pi
SAMPLE = Path(__file__).resolve().parents[1] / "data_samples" / "daq" / "bode_table.csv"


def sample_speeds():
    """The speeds of the sample table [rad/s]."""
    d = np.loadtxt(SAMPLE, delimiter=";", skiprows=2)
    return d[:, 0] / 60.0 * TWO_PI


def steady_table(w, f0, zeta, e, beta_deg, c=2e-6):
    """The noiseless steady 1X vector [m] at the speeds ``w`` [rad/s]."""
    r = w / (TWO_PI * f0)
    return e * np.exp(1j * math.radians(beta_deg)) * r * r / (1 - r * r + 2j * zeta * r) + c


def sweep_table(f0, zeta, e, beta_deg, *, f_start=4.0, f_end=24.0, rate=0.05, h=1e-4,
                bin_hz=0.2, c=2e-6):
    """(speeds [rad/s], 1X vectors [m]) of a linear run-up (module docstring), noiseless."""
    from scipy.signal import lfilter

    w0 = TWO_PI * f0
    wd = w0 * math.sqrt(1 - zeta ** 2)
    l1, l2 = complex(-zeta * w0, wd), complex(-zeta * w0, -wd)
    t = np.arange(0.0, (f_end - f_start) / rate, h)
    alpha, W0 = TWO_PI * rate, TWO_PI * f_start
    tm = t + h / 2
    q = e * np.exp(1j * math.radians(beta_deg))
    F = q * ((W0 + alpha * tm) ** 2 - 1j * alpha) * np.exp(1j * (W0 * tm + 0.5 * alpha * tm ** 2))
    r = W0 / w0
    z0 = q * r * r / (1 - r * r + 2j * zeta * r)
    y1 = (1j * W0 * z0 - l2 * z0) / (l1 - l2)
    z = 0
    for lam, y0, sgn in ((l1, y1, 1), (l2, z0 - y1, -1)):
        a = np.exp(lam * h)
        y = lfilter([1.0], [1.0, -a], (a - 1) / lam * sgn / (l1 - l2) * F[:-1], zi=[a * y0])[0]
        z = z + np.concatenate(([y0], y))
    phi = W0 * t + 0.5 * alpha * t ** 2
    v = z * np.exp(-1j * phi) + c
    rev = np.floor(phi / TWO_PI).astype(int)
    n = np.bincount(rev)
    vm = (np.bincount(rev, v.real) + 1j * np.bincount(rev, v.imag)) / n
    fm = np.bincount(rev, (W0 + alpha * t) / TWO_PI) / n
    vm, fm = vm[1:-1], fm[1:-1]
    b = np.floor(fm / bin_hz).astype(int)
    b -= b.min()
    m = np.bincount(b)
    ok = m > 0
    return (TWO_PI * np.bincount(b, fm)[ok] / m[ok],
            (np.bincount(b, vm.real)[ok] + 1j * np.bincount(b, vm.imag)[ok]) / m[ok])


def z_scores(w, z, f0, zeta, e, beta_deg):
    """z = (estimate - truth) / std of f0, zeta, |U| and the angle of one fit."""
    from dsp.bode import modal_fit

    m = modal_fit(w, z)
    db = math.remainder(m.angle_rad - math.radians(beta_deg), TWO_PI)
    return np.array([(m.natural_frequency_hz - f0) / m.natural_frequency_hz_std,
                     (m.damping_ratio - zeta) / m.damping_ratio_std,
                     (m.specific_unbalance_m - e) / m.specific_unbalance_m_std,
                     db / m.angle_rad_std])


def coverage(w, z_clean, truth, sigma, draws, seed=0):
    """z scores (draws x 4) of ``draws`` noisy copies of one table (noise ``sigma`` [m]
    per component)."""
    rng = np.random.default_rng(seed)
    return np.array([z_scores(w, z_clean + sigma * (rng.standard_normal(w.size)
                                                     + 1j * rng.standard_normal(w.size)), *truth)
                     for _ in range(draws)])


def summary(Z):
    """Rows (quantity, share |z| <= 1, share |z| <= 2, mean z, SD z)."""
    return [(k, float(np.mean(np.abs(Z[:, j]) <= 1)), float(np.mean(np.abs(Z[:, j]) <= 2)),
             float(Z[:, j].mean()), float(Z[:, j].std())) for j, k in enumerate(("f0", "zeta", "U", "angle"))]


def _print(title, Z):
    n = Z.shape[0]
    print(f"\n{title} ({n} draws; binomial SD of a 68 % share {math.sqrt(0.68 * 0.32 / n):.3f}, "
          f"of a 95 % share {math.sqrt(0.95 * 0.05 / n):.3f})")
    print("| quantity | within 1 std | within 2 std | mean z | SD z |\n|---|---|---|---|---|")
    for k, a, b, mu, sd in summary(Z):
        print(f"| {k} | {a:.3f} | {b:.3f} | {mu:+.2f} | {sd:.2f} |")


def main(argv=None):
    import dsp.bode as bode

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--draws", type=int, default=1000)
    ap.add_argument("--sweep-draws", type=int, default=300)
    a = ap.parse_args(argv)
    w = sample_speeds()
    truth = (12.0, 0.04, 40e-6, 30.0)
    for sig in (0.03e-6, 0.56e-6):
        _print(f"steady tables, noise {sig * 1e6:.2f} um per component",
               coverage(w, steady_table(w, *truth), truth, sig, a.draws))
    keep = bode._sweep_corrected
    for truth, rate in (((12.0, 0.04, 40e-6, 30.0), 0.05), ((10.0, 0.02, 30e-6, 200.0), 0.1)):
        ws, zs = sweep_table(*truth, rate=rate)
        for label, corr in (("before", lambda w, z, fit, *_: fit), ("after", keep)):
            bode._sweep_corrected = corr
            try:
                _print(f"run-up tables f0 {truth[0]} Hz, zeta {truth[1]}, {rate} rev/s^2, noise "
                       f"0.023 um, {label}", coverage(ws, zs, truth, 0.023e-6, a.sweep_draws))
            finally:
                bode._sweep_corrected = keep


if __name__ == "__main__":
    main()
