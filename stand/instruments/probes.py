"""Keyphasor, tachometer and displacement probes (issue 4, item 4).

* :class:`Keyphasor` -- a once-per-revolution pulse when the rotor's mark
  passes the sensor: the crossing times of the rotor angle through
  ``mark_angle + 2 pi k`` (cubic Hermite + Newton, exact to rounding for a
  constant-speed programme).
* :class:`Tachometer` -- a counter-based digital tachometer (the stand's
  TsAT-3M): it counts the pulses of a disc with ``pulses_per_rev`` marks during
  a gate of ``gate_time`` seconds and displays count / (pulses_per_rev *
  gate_time), rounded to its display ``resolution``.  Reading error: +-1 count
  (2 pi / (pulses_per_rev * gate_time) rad/s) plus half the resolution.
* :class:`DisplacementProbes` -- non-contact probes measuring the shaft
  displacement along their directions, with runout (a surface profile of the
  rotor seen by each probe, harmonics of the rotor angle), white Gaussian
  noise and quantisation.

An accelerometer on the housing is not modelled (the planar model's housing is
fixed; a housing degree of freedom comes with a later model).
"""
from __future__ import annotations

import math
from typing import Optional

import numpy as np

from stand.errors import SceneError
from stand.instruments.timing import crossing_times, hermite, sample_trajectory, shaft_velocity, time_window
from stand.scene.probe_settings import (  # noqa: F401 (settings read with the scene)
    Keyphasor, KEYPHASOR_KEYS, Tachometer, TACHOMETER_KEYS, DisplacementProbes, PROBE_KEYS)

__all__ = ["Keyphasor", "Tachometer", "DisplacementProbes", "keyphasor_pulses",
           "tachometer_readings", "probe_signals", "KEYPHASOR_KEYS", "TACHOMETER_KEYS",
           "PROBE_KEYS"]


# ---------------------------------------------------------------- keyphasor


def keyphasor_pulses(traj, kp: Keyphasor, t_start: Optional[float] = None,
                     t_end: Optional[float] = None, seed: Optional[int] = None) -> np.ndarray:
    """Pulse times [s]: the rotor angle passes ``mark_angle + 2 pi k`` going forward.

    Roots of the cubic Hermite interpolant of (rotor_angle, rotor_speed); exact
    to rounding when the angle is at most quadratic in time between samples
    (a prescribed piecewise-linear speed programme, away from its kinks).
    ``jitter`` adds Gaussian noise (seeded by ``seed`` or ``kp.seed``); ``bounce`` adds that
    many pulses ``k bounce_time`` after each (a chattering contact).
    """
    t0, t1 = time_window(traj, t_start, t_end)
    tp = crossing_times(traj.t, traj.rotor_angle, traj.rotor_speed, kp.mark_angle, direction=1)
    tp = tp[(tp >= t0) & (tp <= t1)]
    if kp.jitter > 0 and tp.size:
        rng = np.random.default_rng(kp.seed if seed is None else seed)
        tp = np.sort(tp + rng.normal(0.0, kp.jitter, tp.size))
    if kp.bounce:
        tp = np.sort((tp[:, None] + kp.bounce_time * np.arange(kp.bounce + 1)).ravel())
    return tp


# ---------------------------------------------------------------- tachometer


def tachometer_readings(traj, tach: Tachometer, t_start: Optional[float] = None,
                        t_end: Optional[float] = None) -> dict:
    """Readings of the tachometer over a run.

    Gate ``k`` is ``[t_k - gate_time, t_k)`` with ``t_k = t_start + gate_time +
    k * update_interval`` (while ``t_k <= t_end``); the disc's pulses are the
    forward crossings of the rotor angle through ``2 pi j / pulses_per_rev``.

    Returns
    -------
    dict of ndarrays
        ``time`` (end of each gate) [s], ``speed`` (displayed reading) [rad/s],
        ``counts`` (pulses in the gate), ``true_speed`` (mean rotor speed over
        the gate: angle change / gate_time) [rad/s], ``true_speed_at_time``
        (rotor speed at ``time``) [rad/s].
    """
    t0, t1 = time_window(traj, t_start, t_end)
    P = tach.pulses_per_rev
    if t1 - t0 < tach.gate_time:
        z = np.zeros(0)
        return dict(time=z, speed=z, counts=np.zeros(0, int), true_speed=z,
                    true_speed_at_time=z)
    tk = t0 + tach.gate_time + tach.interval * np.arange(
        int(math.floor((t1 - t0 - tach.gate_time) / tach.interval + 1e-9)) + 1)
    tk = tk[tk <= t1 + 1e-12]
    # all pulses: crossings of P equally spaced marks, in angle units scaled by P
    tp = crossing_times(traj.t, traj.rotor_angle * P, traj.rotor_speed * P, 0.0, direction=1)
    lo = np.searchsorted(tp, tk - tach.gate_time, side="left")
    hi = np.searchsorted(tp, tk, side="left")
    counts = hi - lo
    raw = counts * tach.count_resolution
    speed = np.rint(raw / tach.resolution) * tach.resolution if tach.resolution > 0 else raw
    phi = hermite(traj.t, traj.rotor_angle, traj.rotor_speed,
                  np.concatenate([tk - tach.gate_time, tk]))
    m = tk.size
    true = (phi[m:] - phi[:m]) / tach.gate_time
    at = hermite(traj.t, traj.rotor_angle, traj.rotor_speed, tk, derivative=True)
    return dict(time=tk, speed=speed, counts=counts, true_speed=true, true_speed_at_time=at)


# ---------------------------------------------------------------- probes


def channel_filter(probes: DisplacementProbes):
    """The probes' DAQ filter and sensor response as a :class:`dsp.artefacts.ChannelFilter`, or None."""
    from dsp.artefacts import ChannelFilter

    p = probes
    if p.filter == "none" and not (p.group_delay or p.resonance_frequency or p.highpass_cutoff):
        return None
    return ChannelFilter(p.filter, p.filter_order, p.filter_cutoff, p.group_delay,
                         p.resonance_frequency, p.resonance_q, p.highpass_cutoff)


def probe_signals(traj, probes: DisplacementProbes, seed: Optional[int] = None,
                  t_start: Optional[float] = None, t_end: Optional[float] = None) -> dict:
    """Sampled probe signals of a run.

    Samples at ``t_start + k / sample_rate``; the shaft position is Hermite-
    interpolated from (x, y) and the shaft velocity (error ~2.5e-5 of the whirl
    radius with 20 run samples per whirl period, see
    :mod:`stand.instruments.timing`).

    Parameters
    ----------
    traj : Trajectory
    probes : DisplacementProbes
    seed : int, optional
        Overrides ``probes.seed``.
    t_start, t_end : float, optional
        Window [s].

    Returns
    -------
    dict of ndarrays
        ``time`` (M,) [s]; ``signal`` (M, p) measured [m] (what the probes
        record); ``displacement`` (M, p) true shaft displacement along each
        probe [m]; ``runout`` (M, p) [m]; ``noise`` (M, p) [m] (before
        quantisation); ``rotor_angle`` (M,) [rad]; ``angles`` (p,) [rad].

    Raises
    ------
    SceneError
        ``sample_rate`` above the run's sample rate.
    """
    t0, t1 = time_window(traj, t_start, t_end)
    dt = np.diff(traj.t)
    run_rate = 1.0 / float(np.median(dt)) if dt.size else 0.0
    if probes.sample_rate > run_rate * (1 + 1e-6):
        raise SceneError(f"instruments.probes.sample_rate = {probes.sample_rate:g}: above the "
                         f"run's sample rate {run_rate:.6g} (Hz); the probes sample the "
                         f"simulated motion -- raise run.sample_rate")
    n = int(math.floor((t1 - t0) * probes.sample_rate + 1e-9)) + 1
    tq = np.minimum(t0 + np.arange(n) / probes.sample_rate, t1)
    s = sample_trajectory(traj, tq, shaft_velocity(traj))
    a = np.asarray(probes.angles, float)
    disp = s.x[:, None] * np.cos(a)[None, :] + s.y[:, None] * np.sin(a)[None, :]
    psi = a[None, :] - s.rotor_angle[:, None]          # rotor-frame angle facing each probe
    run = np.zeros_like(disp)
    for k, (amp, ph) in enumerate(zip(probes.runout, probes.phases), start=1):
        if amp:
            run += amp * np.cos(k * psi + ph)
    rng = np.random.default_rng(probes.seed if seed is None else seed)
    noise = rng.normal(0.0, probes.noise_rms, disp.shape) if probes.noise_rms > 0 \
        else np.zeros_like(disp)
    sig = disp + run + noise + probes.drift * (tq - tq[0])[:, None]
    for k, amp in enumerate(probes.hum, start=1):
        sig += amp * np.sin(2 * math.pi * k * probes.hum_frequency * tq)[:, None]
    if probes.skew:
        from dsp.artefacts import delayed

        sig = np.column_stack([delayed(tq, sig[:, i], -i * probes.skew) for i in range(a.size)])
    flt = channel_filter(probes)
    if flt is not None:
        sig = flt.apply(tq, sig)
    if probes.adc_range > 0:
        sig = np.clip(sig, -probes.adc_range, probes.adc_range)
    if probes.lsb > 0:
        sig = np.rint(sig / probes.lsb) * probes.lsb
    return dict(time=tq, signal=sig, displacement=disp, runout=run, noise=noise,
                rotor_angle=s.rotor_angle, angles=a)
