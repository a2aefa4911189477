"""Calibration of the stated uncertainties on the other inputs a lab brings (issue 30).

The run-up read through other speed channels than the ramp keyphasor of
:mod:`bench_uncertainty`, a Bode table and a field balancer's readings.  Each function
``path(seed, workdir) -> {quantity: z or None}`` draws one realisation of a closed-form
or independently integrated truth (:mod:`oracles.runup_exact`: the rigid rotor's complex
equation with a prescribed angle, scipy DOP853), runs the stand's estimator as a lab does
and returns z = (estimate − truth) / std of every reported quantity with a ±.
:data:`PATHS` maps the path names to them (merged into ``bench_uncertainty``'s registry).
Every draw also varies what the noise does not: the start speed, the unbalance's angle,
the mark's angle, so that the sampling's phase against the rotation changes.

* ``keyphasor-ttl``: the run-up (10 → 28 rev/s in 9 s, 2 µm probe noise) with a TTL
  keyphasor -- a sharp 30° pulse, 20 samples per revolution at the top speed: no
  sample on its edge, each mark timed only to its sample interval
  (:func:`dsp.speed.pulse_timing_std`);
* ``keyphasor-ttl-steady``: the same keyphasor on a constant 25 rev/s sampled at exactly
  20 per revolution (every mark at the same place in its sample interval: one common
  timing offset, up to 9°), the map's f0 and zeta turning the steady 1X into the
  unbalance and its angle;
* ``tachometer-analog``: 500 samples/s and a speed column [rpm] with 0.2 % white noise
  (an analog tachometer's output);
* ``tachometer-rounded``: the same speed rounded to 1 rpm (every step one rpm: not a
  held display);
* ``encoder-360``: an encoder angle column of 360 lines read as the count of edges
  passed (floor);
* ``bode-steady``: the closed-form steady 1X table (4 → 24 rev/s in 0.2 rev/s steps, f0
  12 Hz, zeta 0.04, 40 µm at 30°, 2 µm runout) with 1 µm complex noise, through
  :func:`dsp.bode.modal_fit`;
* ``field-readings``: a two-plane job (random influence matrix and unbalance, trials
  1.5 g at 0° and 90°) whose readings are written to 1 mm/s and 1° as a balancer's
  display shows them; the truth: the same job from the exact readings.
"""
from __future__ import annotations

import io
import json
import math
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path

import numpy as np

TWO_PI = 2 * math.pi
#: (key of ``stand analyze --json``, truth attribute of :class:`oracles.runup_exact.ExactRunup`)
RUNUP_KEYS = {"f0": ("natural_frequency_hz", "f0_hz"), "zeta": ("damping_ratio", "zeta"),
              "U": ("unbalance_gmm", "unbalance_gmm"),
              "critical": ("critical_speed_hz", "critical_speed_hz")}


def _analyze(csv, rmap) -> dict:
    from stand.cli.main import main

    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        if main(["analyze", str(csv), "--json", "--map", str(rmap)]) != 0:
            raise RuntimeError(err.getvalue())
    return json.loads(out.getvalue())


def _runup_z(d, run, angle=True) -> dict:
    """z of f0, zeta, U, critical (and the unbalance angle) of one analysis."""
    z = {k: (d[key] - getattr(run, attr)) / d[key + "_std"] if d.get(key + "_std") else None
         for k, (key, attr) in RUNUP_KEYS.items()}
    if angle:
        s = d.get("unbalance_angle_deg_std")
        da = (d["unbalance_angle_deg"] - run.beta_deg + 180.0) % 360.0 - 180.0
        z["angle"] = da / s if s else None
    return z


def _runup(seed, fs_hz, base_seed):
    from oracles.runup_exact import exact_runup

    rng = np.random.default_rng(base_seed + seed)
    run = exact_runup(fs_hz=fs_hz, f_start_hz=rng.uniform(9.0, 11.0), f_end_hz=28.0,
                      duration_s=9.0, noise_m=2e-6, seed=seed, beta_deg=rng.uniform(0, 360))
    return run, rng


def keyphasor_ttl_analysis(seed, workdir):
    """(``stand analyze --json`` document, truth) of one ``keyphasor-ttl`` draw (the truth's
    ``beta_deg`` from the mark drawn for it)."""
    from oracles.runup_exact import write_csv

    run, rng = _runup(seed, 20 * 28.0, 100)
    off = rng.uniform(0.0, TWO_PI)                   # the mark, against the unbalance
    run.kp = (np.where(np.mod(run.phi + off, TWO_PI) < math.radians(30.0), 5.0, 0.0)
              + rng.normal(0.0, 0.02, run.t.size))
    run.beta_deg = (run.beta_deg - math.degrees(off)) % 360.0
    return _analyze(*write_csv(run, Path(workdir) / f"ttl{seed}.csv")), run


def keyphasor_ttl(seed, workdir):
    return _runup_z(*keyphasor_ttl_analysis(seed, workdir))


def keyphasor_ttl_steady(seed, workdir, f_hz=25.0):
    """A constant speed sampled at exactly 20 per revolution (the marks fall at the same
    place in their sample intervals all along: one common timing offset), the map's f0
    and zeta turning the steady 1X into the unbalance."""
    from oracles.runup_exact import exact_runup, write_csv

    rng = np.random.default_rng(500 + seed)
    run = exact_runup(fs_hz=20 * f_hz, f_start_hz=f_hz, f_end_hz=f_hz, duration_s=8.0,
                      noise_m=2e-6, seed=seed, beta_deg=rng.uniform(0, 360))
    off = rng.uniform(0.0, TWO_PI)
    run.kp = (np.where(np.mod(run.phi + off, TWO_PI) < math.radians(30.0), 5.0, 0.0)
              + rng.normal(0.0, 0.02, run.t.size))
    run.beta_deg = (run.beta_deg - math.degrees(off)) % 360.0
    csv, rmap = write_csv(run, Path(workdir) / f"ttl_steady{seed}.csv")
    rmap.write_text(rmap.read_text() + f'natural_frequency = "{run.f0_hz} Hz"\n'
                    f'damping_ratio = {run.zeta}\n')
    d = _analyze(csv, rmap)
    da = (d["unbalance_angle_deg"] - run.beta_deg + 180.0) % 360.0 - 180.0
    return {"U": (d["unbalance_gmm"] - run.unbalance_gmm) / d["unbalance_gmm_std"],
            "angle": da / d["unbalance_angle_deg_std"]}


def _tachometer(kind):
    def path(seed, workdir):
        from oracles.runup_exact import write_csv

        run, rng = _runup(seed, 500.0, 200)
        rpm = np.gradient(run.phi, run.t) / TWO_PI * 60.0
        rpm = (np.round(rpm) if kind == "rounded"
               else rpm * (1 + 0.002 * rng.standard_normal(rpm.size)))
        d = _analyze(*write_csv(run, Path(workdir) / f"tacho{seed}.csv", tacho_rpm=rpm))
        assert d["speed_source"].startswith("tachometer"), d["speed_source"]
        return _runup_z(d, run, angle=False)
    return path


def encoder_360(seed, workdir, lines=360):
    run, _ = _runup(seed, 500.0, 300)
    q = TWO_PI / lines
    p = Path(workdir) / f"enc{seed}.csv"
    np.savetxt(p, np.column_stack((run.t, run.x * 1e6, run.y * 1e6, np.floor(run.phi / q) * q)),
               delimiter=",", fmt="%.15g", header="time_s,x_um,y_um,ang", comments="")
    m = p.with_suffix(".map.toml")
    m.write_text('[columns]\ntime = "time_s [s]"\nx = "x_um [um]"\ny = "y_um [um]"\n'
                 f'angle = "ang [rad]"\n\n[rotor]\nmass = "{run.mass_kg} kg"\n')
    return _runup_z(_analyze(p, m), run)


#: the steady table of ``bode-steady``
BODE = {"f0_hz": 12.0, "zeta": 0.04, "e_m": 40e-6, "beta_deg": 30.0}


def steady_table(seed, noise_m=1e-6, step_hz=0.2):
    """(speed [rad/s], 1X vector [m]) of the closed-form steady response, with complex
    white noise of ``noise_m`` RMS (seed ``seed``)."""
    rng = np.random.default_rng(seed)
    f = np.arange(4.0, 24.0, step_hz)
    r = f / BODE["f0_hz"]
    z = (BODE["e_m"] * np.exp(1j * math.radians(BODE["beta_deg"])) * r * r
         / (1 - r * r + 2j * BODE["zeta"] * r) + 2e-6 * np.exp(0.7j))
    z = z + noise_m * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)) / math.sqrt(2)
    return TWO_PI * f, z


def bode_steady(seed, workdir=None):
    from dsp.bode import modal_fit

    m = modal_fit(*steady_table(seed))
    f0, zeta = BODE["f0_hz"], BODE["zeta"]
    beta = math.radians(BODE["beta_deg"])
    return {"f0": (m.natural_frequency_hz - f0) / m.natural_frequency_hz_std,
            "zeta": (m.damping_ratio - zeta) / m.damping_ratio_std,
            "e": (m.specific_unbalance_m - BODE["e_m"]) / m.specific_unbalance_m_std,
            "angle": math.remainder(m.angle_rad - beta, TWO_PI) / m.angle_rad_std,
            "critical": (m.critical_speed_hz - f0 / math.sqrt(1 - 2 * zeta * zeta))
            / m.critical_speed_hz_std}


def field_job(V0, A, trials, digits_amp=0, digits_deg=0):
    """A two-plane job whose readings are the exact ``V0 + A T`` [mm/s] written to the
    given digits (a field balancer's display), trials [g, complex]."""
    from stand.analysis.field_job import parse_job
    from stand.io.tomlfile import tomllib

    def polar(z):
        return f"{abs(z):.{digits_amp}f} @ {np.degrees(np.angle(z)) % 360:.{digits_deg}f}"

    text = ('[job]\nvibration_unit = "mm/s"\namplitude = "pk"\nmass_unit = "g"\n\n'
            '[planes.P1]\n[planes.P2]\n')
    runs = [("reference", None, V0)]
    for j, T in enumerate(trials):
        w = np.zeros(2, complex)
        w[j] = T
        runs.append(("trial", j, V0 + A @ w))
    for kind, j, R in runs:
        text += f'\n[[run]]\nkind = "{kind}"\n'
        if j is not None:
            text += (f'trial = {{ P{j + 1} = "{abs(trials[j]):g} @ '
                     f'{np.degrees(np.angle(trials[j])) % 360:g}" }}\n')
        text += f'readings = {{ S1 = "{polar(R[0])}", S2 = "{polar(R[1])}" }}\n'
    return parse_job(tomllib.loads(text))


def field_readings(seed, workdir=None):
    from stand.analysis.field_balance import balance_job

    rng = np.random.default_rng(7000 + seed)
    A = (rng.normal(0, 40, (2, 2)) + 1j * rng.normal(0, 40, (2, 2))) + np.diag([60, 60])
    V0 = rng.normal(0, 80, 2) + 1j * rng.normal(0, 80, 2)
    trials = [1.5 * np.exp(1j * np.radians(d)) for d in (0, 90)]
    exact = balance_job(field_job(V0, A, trials, 9, 9))
    shown = balance_job(field_job(V0, A, trials))
    out = {}
    for k, p in enumerate(("P1", "P2"), 1):
        c, t = shown["corrections"][p], exact["corrections"][p]
        out[f"mass{k}"] = (c["mass"] - t["mass"]) / c["mass_std"]
        out[f"angle{k}"] = ((c["angle_deg"] - t["angle_deg"] + 180) % 360 - 180) / c["angle_std_deg"]
    return out


def _daq(kind):
    """The ``keyphasor-ttl`` run-up (500 samples/s) through one DAQ artefact (issue 42),
    drawn with scipy, not the stand: ``daq-filter-declared`` / ``daq-filter-undeclared``
    (the analog 4th-order 100 Hz Butterworth applied exactly by ``scipy.signal.lsim``,
    declared in the map or not), ``daq-clipping`` (both channels clipped at 85 % of their
    peak), ``daq-hum`` (15 um at 50 Hz + 5 um at 150 Hz on both), ``daq-drift`` (3 and
    -2 um/s), ``daq-jitter`` (each keyphasor edge moved by its own N(0, 50 us))."""
    def path(seed, workdir):
        from scipy import signal

        from oracles.runup_exact import write_csv

        run, rng = _runup(seed, 500.0, 600)
        off = rng.uniform(0.0, TWO_PI)
        kp_phi = run.phi + off
        if kind == "jitter":
            k = np.rint(kp_phi / TWO_PI).astype(int)
            kp_phi = kp_phi - np.gradient(run.phi, run.t) * rng.normal(0.0, 50e-6, k.max() + 1)[k]
        run.kp = (np.where(np.mod(kp_phi, TWO_PI) < math.radians(30.0), 5.0, 0.0)
                  + rng.normal(0.0, 0.02, run.t.size))
        run.beta_deg = (run.beta_deg - math.degrees(off)) % 360.0
        if kind.startswith("filter"):
            ba = signal.butter(4, TWO_PI * 100.0, analog=True)
            run.x, run.y = (v[0] + signal.lsim(ba, v - v[0], run.t)[1] for v in (run.x, run.y))
        elif kind == "clipping":
            run.x, run.y = (np.clip(v, -0.85 * np.max(np.abs(v)), 0.85 * np.max(np.abs(v)))
                            for v in (run.x, run.y))
        elif kind == "hum":
            h = 15e-6 * np.sin(TWO_PI * 50 * run.t) + 5e-6 * np.sin(TWO_PI * 150 * run.t)
            run.x, run.y = run.x + h, run.y + h
        elif kind == "drift":
            run.x, run.y = run.x + 3e-6 * run.t, run.y - 2e-6 * run.t
        csv, rmap = write_csv(run, Path(workdir) / f"daq_{kind}{seed}.csv")
        if kind == "filter-declared":
            flt = 'filter = {type = "butterworth", order = 4, cutoff = "100 Hz"}'
            rmap.write_text(rmap.read_text().replace(
                'x = "x_um [um]"', f'x = {{column = "x_um", unit = "um", {flt}}}').replace(
                'y = "y_um [um]"', f'y = {{column = "y_um", unit = "um", {flt}}}'))
        return _runup_z(_analyze(csv, rmap), run)
    return path


PATHS = {"keyphasor-ttl": keyphasor_ttl, "keyphasor-ttl-steady": keyphasor_ttl_steady,
         **{f"daq-{k}": _daq(k) for k in ("filter-declared", "filter-undeclared", "clipping",
                                          "hum", "drift", "jitter")},
         "tachometer-analog": _tachometer("analog"),
         "tachometer-rounded": _tachometer("rounded"), "encoder-360": encoder_360,
         "bode-steady": bode_steady, "field-readings": field_readings}
