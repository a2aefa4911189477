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
from dataclasses import dataclass
from typing import Optional

import numpy as np

from stand.errors import SceneError
from stand.instruments._settings import (check, integer, keys, number, numbers, read_table, rebased,
                        table_numbers)
from stand.instruments.timing import crossing_times, hermite, sample_trajectory, shaft_velocity, time_window

__all__ = ["Keyphasor", "Tachometer", "DisplacementProbes", "keyphasor_pulses",
           "tachometer_readings", "probe_signals", "KEYPHASOR_KEYS", "TACHOMETER_KEYS",
           "PROBE_KEYS"]

TWO_PI = 2.0 * math.pi
DEG = math.pi / 180.0
MAX_PROBES = 16
MAX_HARMONICS = 64


# ---------------------------------------------------------------- keyphasor
@dataclass(frozen=True)
class Keyphasor:
    """Once-per-revolution pulse sensor.

    Parameters
    ----------
    mark_angle : float
        Rotor angle (of the reference mark) at which the mark faces the
        sensor [rad], i.e. the sensor's angle in the fixed frame; TOML: degrees.
    jitter : float
        Rms timing jitter of the pulses [s] (0: ideal).
    seed : int
        Seed of the jitter.
    """

    mark_angle: float = number(0.0, "rad", toml=("deg", DEG))
    jitter: float = number(0.0, "s", ge=0)
    seed: int = integer(0, 0)

    def __post_init__(self):
        check(self, "instruments.keyphasor")

    @classmethod
    def from_table(cls, t) -> "Keyphasor":
        """``[instruments.keyphasor]``: ``mark_angle`` [deg], ``jitter`` [s], ``seed``."""
        t.allow(KEYPHASOR_KEYS)
        return rebased(cls, read_table(t, cls), "instruments.keyphasor", t.path)


#: keys of ``[instruments.keyphasor]`` (the fields of :class:`Keyphasor`)
KEYPHASOR_KEYS = keys(Keyphasor)


def keyphasor_pulses(traj, kp: Keyphasor, t_start: Optional[float] = None,
                     t_end: Optional[float] = None, seed: Optional[int] = None) -> np.ndarray:
    """Pulse times [s]: the rotor angle passes ``mark_angle + 2 pi k`` going forward.

    Roots of the cubic Hermite interpolant of (rotor_angle, rotor_speed); exact
    to rounding when the angle is at most quadratic in time between samples
    (a prescribed piecewise-linear speed programme, away from its kinks).
    ``jitter`` adds Gaussian noise (seeded by ``seed`` or ``kp.seed``).
    """
    t0, t1 = time_window(traj, t_start, t_end)
    tp = crossing_times(traj.t, traj.rotor_angle, traj.rotor_speed, kp.mark_angle, direction=1)
    tp = tp[(tp >= t0) & (tp <= t1)]
    if kp.jitter > 0 and tp.size:
        rng = np.random.default_rng(kp.seed if seed is None else seed)
        tp = np.sort(tp + rng.normal(0.0, kp.jitter, tp.size))
    return tp


# ---------------------------------------------------------------- tachometer
@dataclass(frozen=True)
class Tachometer:
    """Counter-based digital tachometer.

    Parameters
    ----------
    gate_time : float
        Counting gate [s].
    resolution : float
        Display resolution [rad/s]; TOML: rev/s (1 rpm = 1/60 rev/s).  0: no
        display rounding.
    pulses_per_rev : int
        Marks on the tachometer disc (pulses per revolution).
    update_interval : float or None
        Time between readings [s] (> 0; default gate_time: back-to-back
        gates; shorter than gate_time: overlapping gates).
    """

    gate_time: float = number(1.0, "s", gt=0)
    resolution: float = number(TWO_PI / 60.0, "rad/s", ge=0, toml=("rev/s", TWO_PI))
    pulses_per_rev: int = integer(60, 1, 100_000)
    update_interval: Optional[float] = number(None, "s", gt=0, optional=True)

    def __post_init__(self):
        check(self, "instruments.tachometer")

    @property
    def interval(self) -> float:
        return self.update_interval if self.update_interval is not None else self.gate_time

    @property
    def count_resolution(self) -> float:
        """Speed of one count in the gate, 2 pi / (pulses_per_rev gate_time) [rad/s]."""
        return TWO_PI / (self.pulses_per_rev * self.gate_time)

    @property
    def accuracy(self) -> float:
        """Largest reading error at constant speed: one count plus half the display step [rad/s]."""
        return self.count_resolution + 0.5 * self.resolution

    @classmethod
    def from_table(cls, t) -> "Tachometer":
        """``[instruments.tachometer]``: ``gate_time`` [s], ``resolution`` [rev/s],
        ``pulses_per_rev``, ``update_interval`` [s]."""
        t.allow(TACHOMETER_KEYS)
        return rebased(cls, read_table(t, cls), "instruments.tachometer", t.path)


#: keys of ``[instruments.tachometer]`` (the fields of :class:`Tachometer`)
TACHOMETER_KEYS = keys(Tachometer)


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
@dataclass(frozen=True)
class DisplacementProbes:
    """Non-contact displacement probes around the shaft (x, y by default).

    Probe ``i`` at direction ``angles[i]`` (from the fixed X axis) reads::

        s_i = x cos(a_i) + y sin(a_i)
              + sum_k runout[k] cos((k+1) (a_i - phi) + runout_phase[k])
              + noise,   quantised to lsb

    ``phi`` the rotor angle: the runout is a profile fixed to the rotor (the
    surface the probe looks at), so it repeats every revolution, harmonics of
    the rotor frequency, and both probes see it with the phase of their
    direction.

    Parameters
    ----------
    sample_rate : float
        Probe sampling rate [Hz]; at most the run's sample rate.
    noise_rms : float
        White Gaussian noise, rms [m].
    runout : tuple of float
        Amplitudes of the runout harmonics 1x, 2x, ... of the rotor frequency [m].
    runout_phase : tuple of float
        Their phases [rad] (TOML: degrees); default zeros.
    lsb : float
        Quantisation step [m]; 0: none.
    angles : tuple of float
        Probe directions [rad] (TOML: degrees); default (0, 90 deg) = x, y.
    seed : int
        Seed of the noise.
    """

    sample_rate: float = number(1000.0, "Hz", gt=0)
    noise_rms: float = number(1.0e-6, "m", ge=0)
    runout: tuple = numbers((2.0e-6,), "m", ge=0)
    runout_phase: Optional[tuple] = numbers(None, "rad", optional=True)
    lsb: float = number(0.5e-6, "m", ge=0)
    angles: tuple = numbers((0.0, 0.5 * math.pi), "rad")
    seed: int = integer(0, 0)

    def __post_init__(self):
        check(self, "instruments.probes")
        p = "instruments.probes."
        if len(self.runout) > MAX_HARMONICS:
            raise SceneError(f"{p}runout: {len(self.runout)} harmonics, at most {MAX_HARMONICS}")
        if self.runout_phase is not None and len(self.runout_phase) != len(self.runout):
            raise SceneError(f"{p}runout_phase = {list(self.runout_phase)!r}: expected "
                             f"{len(self.runout)} phases, one per runout harmonic (rad)")
        if len(self.angles) > MAX_PROBES:
            raise SceneError(f"{p}angles: {len(self.angles)} probes, at most {MAX_PROBES}")

    @property
    def phases(self) -> np.ndarray:
        return (np.zeros(len(self.runout)) if self.runout_phase is None
                else np.asarray(self.runout_phase, float))

    def check_against_run(self, run) -> None:
        """The probes sample the simulated motion: not faster than ``run.sample_rate``."""
        if self.sample_rate > run.sample_rate * (1 + 1e-9):
            raise SceneError(f"instruments.probes.sample_rate = {self.sample_rate:g}: above "
                             f"run.sample_rate = {run.sample_rate:g} (Hz); the probes sample the "
                             f"simulated motion -- raise run.sample_rate")

    @classmethod
    def from_table(cls, t) -> "DisplacementProbes":
        """``[instruments.probes]``: ``sample_rate`` [Hz], ``noise_rms`` [m],
        ``runout`` [m] (a number = the 1x amplitude, or a list 1x, 2x, ...),
        ``runout_phase`` [deg] (list, one per harmonic), ``lsb`` [m],
        ``angles`` [deg] (list, one per probe), ``seed``."""
        t.allow(PROBE_KEYS)
        d = cls()
        if "runout" in t and not isinstance(t.data["runout"], (list, tuple)):
            runout = (t.number("runout", "m", ge=0),)
        else:
            runout = table_numbers(t, "runout", "m", list(d.runout), ge=0)
        phase = table_numbers(t, "runout_phase", "deg", None, length=len(runout))
        angles = table_numbers(t, "angles", "deg", [a / DEG for a in d.angles])
        if not angles:
            raise SceneError(f"{t.name('angles')} = []: give at least one probe direction (deg)")
        kw = dict(read_table(t, cls), runout=tuple(runout),
                  runout_phase=None if phase is None else tuple(v * DEG for v in phase),
                  angles=tuple(a * DEG for a in angles))
        return rebased(cls, kw, "instruments.probes", t.path)


#: keys of ``[instruments.probes]`` (the fields of :class:`DisplacementProbes`)
PROBE_KEYS = keys(DisplacementProbes)


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
    sig = disp + run + noise
    if probes.lsb > 0:
        sig = np.rint(sig / probes.lsb) * probes.lsb
    return dict(time=tq, signal=sig, displacement=disp, runout=run, noise=noise,
                rotor_angle=s.rotor_angle, angles=a)
