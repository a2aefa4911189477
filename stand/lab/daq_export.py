"""A simulated recording written the way a lab's data-acquisition system would: the DAQ sample.

:func:`daq_export` takes a recording with displacement probes (and optionally a
tachometer) and writes a CSV in a DAQ's style -- header lines before the table,
``;`` delimiters and decimal commas, time in ms, displacements in um with a DC
offset (the probes' gap), a keyphasor as a voltage (a proximity probe over a
notch: a 10 deg pulse with raised-cosine edges, high 5 V, with noise), the
tachometer's held display in rpm -- and beside it the truth (JSON) from the
scene: unbalance, its angle from the keyphasor mark, natural frequency, damping
ratio, critical speed, offsets.  ``stand analyze DAQ.csv --map MAP.toml``
should find the truth again (tests/test_lab_daq.py).
"""
from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path
from typing import Optional

import numpy as np

__all__ = ["daq_export", "daq_truth"]

TWO_PI = 2.0 * math.pi
#: the probes' settings that are DAQ artefacts (written into the truth)
ARTEFACTS = ("noise_rms", "lsb", "hum", "hum_frequency", "drift", "skew", "filter", "filter_order",
             "filter_cutoff", "group_delay", "adc_range", "resonance_frequency", "resonance_q",
             "highpass_cutoff")


def daq_truth(scene) -> dict:
    """What the DAQ sample should give, from a planar scene (SI and lab units); with weights
    the numbers are the rotor's own, which the weights then change."""
    M = float(scene.total_mass)
    s = scene.supports
    if abs(s.stiffness_x - s.stiffness_y) > 1e-9 * s.stiffness_x:
        raise ValueError("daq truth: needs isotropic supports (stiffness_x == stiffness_y)")
    w0 = math.sqrt(s.stiffness_x / M)
    zeta = s.damping_x / (2.0 * math.sqrt(s.stiffness_x * M))
    e = float(scene.rotor.eccentricity) * float(scene.rotor.mass) / M
    return {"scene": scene.name, "mass_kg": M,
            "unbalance_gmm": M * e * 1e6,
            "unbalance_angle_deg": math.degrees(float(scene.rotor.unbalance_angle)) % 360.0,
            "specific_unbalance_um": e * 1e6,
            "natural_frequency_hz": w0 / TWO_PI, "damping_ratio": zeta,
            "critical_speed_hz": w0 / TWO_PI / math.sqrt(1.0 - 2.0 * zeta * zeta),
            "definitions": {"natural_frequency_hz": "sqrt(k / M) / 2 pi",
                            "critical_speed_hz": "speed of the steady 1X maximum, "
                                                 "f0 / sqrt(1 - 2 zeta^2)",
                            "unbalance_angle_deg": "from the keyphasor mark, in the rotation "
                                                   "direction"}}


def _keyphasor_volts(angle, high=5.0, width_deg=10.0, edge_deg=6.0, noise_v=0.01, rng=None):
    """A once-per-revolution pulse: high for ``width_deg`` after the mark, raised-cosine edges
    ``edge_deg`` wide centred on the mark and on its end (the mid-level is crossed exactly at
    the mark)."""
    th = np.degrees(np.mod(angle, TWO_PI))
    th = np.where(th > 180.0, th - 360.0, th)              # -180..180 around the mark

    def ramp(u):                                            # 0 -> 1 over [-edge/2, edge/2]
        x = np.clip(u / edge_deg + 0.5, 0.0, 1.0)
        return 0.5 - 0.5 * np.cos(math.pi * x)

    v = high * (ramp(th) - ramp(th - width_deg))
    if rng is not None and noise_v > 0:
        v = v + rng.normal(0.0, noise_v, v.shape)
    return v


def _sensor_columns(rec, t, quantity, rng, flt=None) -> dict:
    """Velocity [mm/s] or acceleration [g] columns of the rotor centre's recorded motion,
    through the sensor's response ``flt`` (:func:`stand.instruments.probes.channel_filter`)."""
    from scipy.interpolate import CubicSpline

    k, scale, names = {"velocity": (1, 1e3, ("vel_x_mm_s", "vel_y_mm_s")),
                       "acceleration": (2, 1.0 / 9.80665, ("acc_x_g", "acc_y_g"))}[quantity]
    out = {}
    for v, name in zip((rec.x, rec.y), names):
        d = CubicSpline(np.asarray(rec.t, float), np.asarray(v, float))(t, k) * scale
        d = d + rng.normal(0.0, 0.01 * float(np.std(d)), d.shape)
        d = d if flt is None else flt.apply(t, d)
        out[name] = [f"{x:.6g}".replace(".", ",") for x in d]
    return out


def daq_export(recording, csv_path, *, truth_path: Optional[str] = None,
               offset_um=(35.0, -20.0), keyphasor: bool = True, tachometer: bool = True,
               seed: int = 11, quantity: str = "displacement") -> dict:
    """Write a recording's probes, keyphasor and tachometer as a DAQ-style CSV, and its truth.

    Parameters
    ----------
    recording : str or Recording
        A recording with ``instruments/probes`` at angles 0 and 90 deg (x, y).
    csv_path : str
        The CSV to write (atomically).
    truth_path : str, optional
        The truth JSON (default: ``<csv stem>.truth.json`` beside the CSV).
    offset_um : (float, float)
        DC offsets of the x and y probes [um].
    keyphasor, tachometer : bool
        Write those channels (the tachometer needs ``instruments/tachometer``).
    seed : int
        Seed of the keyphasor's noise.
    quantity : str
        ``displacement`` (the probes, um, with DC offsets), ``velocity`` (velocity
        pickups, mm/s) or ``acceleration`` (accelerometers, g): the rotor centre's
        motion differentiated through a cubic spline of the recorded state (clean, at
        the integrator's output rate), plus the sensors' white noise of 1 % of the
        channel's RMS; no offsets.

    Returns
    -------
    dict
        The truth (also written).
    """
    from stand.io.atomic import write_text
    from stand.recording.hdf5 import Recording, read_recording
    from stand.recording.layout import TACHOMETER, instrument_key
    from stand.recording.probes import probe_channels

    rec = recording if isinstance(recording, Recording) else read_recording(recording)
    pr = probe_channels(rec)
    if pr is None:
        from stand.errors import NotApplicable

        raise NotApplicable(f"{rec.path}: no instruments/probes (add [instruments.probes] with "
                         "angles = [0.0, 90.0] to the scene)")
    ang = pr["angles"]
    if ang.size != 2 or abs(ang[0]) > 1e-9 or abs(ang[1] - math.pi / 2) > 1e-9:
        from stand.errors import NotApplicable

        raise NotApplicable(f"{rec.path}: instruments/probes angles = {np.degrees(ang).tolist()} deg; "
                         "the DAQ export writes an x and a y probe (angles = [0.0, 90.0])")
    t, sig = pr["time"], pr["signal"]
    cols = {"time_ms": [f"{v:.1f}".replace(".", ",") for v in t * 1e3]}
    rng = np.random.default_rng(seed)
    if quantity == "displacement":
        for k, name in enumerate(("disp_x_um", "disp_y_um")):
            cols[name] = [f"{v:.2f}".replace(".", ",") for v in sig[:, k] * 1e6 + offset_um[k]]
    else:
        from stand.instruments.probes import channel_filter

        probes = (getattr(rec.scene, "instruments", None) or {}).get("probes")
        cols.update(_sensor_columns(rec, t, quantity, rng, probes and channel_filter(probes)))
        offset_um = (0.0, 0.0)
    inst = getattr(rec.scene, "instruments", None) or {}
    if keyphasor:
        phi = np.interp(t, np.asarray(rec.t), np.unwrap(np.asarray(rec.rotor_angle)))
        kp = inst.get("keyphasor")
        if kp is not None and kp.jitter > 0:       # each pulse early or late by its own draw
            k = np.rint(phi / TWO_PI).astype(int)
            dt = np.random.default_rng(kp.seed).normal(0.0, kp.jitter, k.max() - k.min() + 1)
            phi = phi - np.gradient(phi, t) * dt[k - k.min()]
        kv = _keyphasor_volts(phi, rng=None if kp is not None and kp.bounce else rng)
        if kp is not None and kp.bounce:           # the contact chatters after each true edge
            from dsp.pulses import bounced

            k = np.arange(math.ceil(phi[0] / TWO_PI), math.floor(phi[-1] / TWO_PI) + 1)
            kv = bounced(t, kv, np.interp(k * TWO_PI, phi, t), kp.bounce, kp.bounce_time, 0.0)
            kv = kv + rng.normal(0.0, 0.01, kv.shape)
        cols["kp_V"] = [f"{v:.3f}".replace(".", ",") for v in kv]
    if tachometer and rec.shape(instrument_key(TACHOMETER, "speed")) is not None:
        tt = np.asarray(rec.dataset(instrument_key(TACHOMETER, "time")), float)
        sp = np.asarray(rec.dataset(instrument_key(TACHOMETER, "speed")), float) * 60.0 / TWO_PI
        i = np.searchsorted(tt, t, side="right") - 1          # the display holds its last reading
        rpm = np.where(i >= 0, sp[np.clip(i, 0, None)], 0.0)
        cols["tacho_rpm"] = [f"{v:.0f}" for v in rpm]
    names = list(cols)
    rate = 1.0 / float(np.median(np.diff(t)))
    lines = [f"DAQ export: {rec.scene.name if rec.scene is not None else Path(str(rec.path)).stem}",
             f"Sample rate: {rate:.0f} Hz",
             f"Channels: {len(names) - 1}",
             "Units: time ms; " + {"displacement": "displacement um (probe gap offset not removed)",
                                   "velocity": "velocity mm/s (pk)",
                                   "acceleration": "acceleration g (pk)"}[quantity]
             + "; keyphasor V; tacho rpm",
             ";".join(names)]
    lines += [";".join(row) for row in zip(*(cols[n] for n in names))]
    write_text(csv_path, "\n".join(lines) + "\n")
    sc = rec.scene
    if sc is not None and getattr(sc, "kind", None) == "planar":
        truth = daq_truth(sc)
    else:
        truth = {"note": "truth written for planar scenes (the rigid rotor of daq_truth) only"}
    truth.update(offset_um=list(offset_um), source_recording=Path(str(rec.path)).name,
                 csv=Path(csv_path).name)
    art = {k: v for k, v in dataclasses.asdict(inst["probes"]).items() if k in ARTEFACTS} \
        if "probes" in inst else {}
    if "keyphasor" in inst and keyphasor:
        art.update(keyphasor_jitter=inst["keyphasor"].jitter, keyphasor_bounce=inst["keyphasor"].bounce,
                   keyphasor_bounce_time=inst["keyphasor"].bounce_time)
    truth["artefacts"] = art       # SI: the probes' DAQ settings, as the scene declared them
    if truth_path is None:
        truth_path = str(Path(csv_path).with_suffix("")) + ".truth.json"
    write_text(truth_path, json.dumps(truth, indent=2) + "\n")
    return truth


def daq_bode(recording, csv_path, *, truth_path: Optional[str] = None, bin_hz: float = 0.2) -> dict:
    """Write a slow run-up's steady 1X Bode table (``rpm;amp_1x_um;phase_1x_deg``, peak, phase
    lagging the keyphasor mark) as a portable analyser exports it, and its truth.

    Order tracking: the x + i y probes' 1X vector of each revolution (the mean of
    z e^{-i phi} over it, phi the recorded rotor angle), averaged over speed bins of
    ``bin_hz`` [rev/s].  A run-up slow enough that the sweep lag is negligible makes it
    the steady response.
    """
    from stand.io.atomic import write_text
    from stand.recording.hdf5 import Recording, read_recording

    from stand.recording.probes import probe_channels

    rec = recording if isinstance(recording, Recording) else read_recording(recording)
    pr = probe_channels(rec)
    if pr is None:
        from stand.errors import NotApplicable

        raise NotApplicable(f"{rec.path}: no instruments/probes (add [instruments.probes] to "
                            "the scene)")
    t, sig = pr["time"], pr["signal"]
    phi = np.interp(t, np.asarray(rec.t), np.unwrap(np.asarray(rec.rotor_angle)))
    z = sig[:, 0] + 1j * sig[:, 1]
    rev = np.floor((phi - phi[0]) / TWO_PI).astype(int)
    n = np.bincount(rev)
    keep = n > 0
    v = (np.bincount(rev, (z * np.exp(-1j * phi)).real) + 1j * np.bincount(rev, (z * np.exp(-1j * phi)).imag))
    w = np.bincount(rev, np.gradient(phi, t))
    v, f = v[keep] / n[keep], w[keep] / n[keep] / TWO_PI
    v, f = v[1:-1], f[1:-1]                  # whole revolutions only
    b = np.floor(f / bin_hz).astype(int)
    b -= b.min()
    m = np.bincount(b)
    ok = m > 0
    fb = np.bincount(b, f)[ok] / m[ok]
    vb = (np.bincount(b, v.real)[ok] + 1j * np.bincount(b, v.imag)[ok]) / m[ok]
    lines = [f"Bode table (order-tracked 1X, peak; phase lags the keyphasor mark): "
             f"{rec.scene.name if rec.scene is not None else Path(str(rec.path)).stem}",
             "rpm;amp_1x_um;phase_1x_deg"]
    lines += [f"{fi * 60:.2f};{abs(vi) * 1e6:.4f};{(-math.degrees(np.angle(vi))) % 360.0:.3f}"
              for fi, vi in zip(fb, vb)]
    write_text(csv_path, "\n".join(lines) + "\n")
    sc = rec.scene
    truth = daq_truth(sc) if sc is not None and getattr(sc, "kind", None) == "planar" else {}
    truth.update(source_recording=Path(str(rec.path)).name, csv=Path(csv_path).name,
                 bin_hz=bin_hz)
    if truth_path is None:
        truth_path = str(Path(csv_path).with_suffix("")) + ".truth.json"
    write_text(truth_path, json.dumps(truth, indent=2) + "\n")
    return truth

