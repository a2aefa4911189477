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

from ..scene import SceneError
from .timing import (_check_integer, _check_number, _rebased, _table_numbers, crossing_times,
                     hermite, sample_trajectory, shaft_velocity)

__all__ = ["Keyphasor", "Tachometer", "DisplacementProbes", "keyphasor_pulses",
           "tachometer_readings", "probe_signals", "KEYPHASOR_KEYS", "TACHOMETER_KEYS",
           "PROBE_KEYS"]

TWO_PI = 2.0 * math.pi
DEG = math.pi / 180.0
KEYPHASOR_KEYS = ("mark_angle", "jitter", "seed")
TACHOMETER_KEYS = ("gate_time", "resolution", "pulses_per_rev", "update_interval")
PROBE_KEYS = ("sample_rate", "noise_rms", "runout", "runout_phase", "lsb", "angles", "seed")
MAX_PROBES = 16
MAX_HARMONICS = 64


def _window(traj, t_start, t_end) -> tuple[float, float]:
    t0 = float(traj.t[0]) if t_start is None else max(float(t_start), float(traj.t[0]))
    t1 = float(traj.t[-1]) if t_end is None else min(float(t_end), float(traj.t[-1]))
    if not t1 > t0:
        raise SceneError(f"instrument window [{t0:.6g}, {t1:.6g}] s is empty (the run spans "
                         f"[{float(traj.t[0]):.6g}, {float(traj.t[-1]):.6g}] s)")
    return t0, t1


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

    mark_angle: float = 0.0
    jitter: float = 0.0
    seed: int = 0

    def __post_init__(self):
        _check_number("instruments.keyphasor.mark_angle", self.mark_angle, "rad")
        _check_number("instruments.keyphasor.jitter", self.jitter, "s", ge=0)
        _check_integer("instruments.keyphasor.seed", self.seed, 0)

    @classmethod
    def from_table(cls, t) -> "Keyphasor":
        """``[instruments.keyphasor]``: ``mark_angle`` [deg], ``jitter`` [s], ``seed``."""
        t.allow(KEYPHASOR_KEYS)
        kw = dict(mark_angle=t.number("mark_angle", "deg", 0.0) * DEG,
                  jitter=t.number("jitter", "s", 0.0, ge=0),
                  seed=t.integer("seed", 0, 0))
        return _rebased(cls, kw, "instruments.keyphasor", t.path)


def keyphasor_pulses(traj, kp: Keyphasor, t_start: Optional[float] = None,
                     t_end: Optional[float] = None, seed: Optional[int] = None) -> np.ndarray:
    """Pulse times [s]: the rotor angle passes ``mark_angle + 2 pi k`` going forward.

    Roots of the cubic Hermite interpolant of (rotor_angle, rotor_speed); exact
    to rounding when the angle is at most quadratic in time between samples
    (a prescribed piecewise-linear speed programme, away from its kinks).
    ``jitter`` adds Gaussian noise (seeded by ``seed`` or ``kp.seed``).
    """
    t0, t1 = _window(traj, t_start, t_end)
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

    gate_time: float = 1.0
    resolution: float = TWO_PI / 60.0
    pulses_per_rev: int = 60
    update_interval: Optional[float] = None

    def __post_init__(self):
        p = "instruments.tachometer."
        _check_number(p + "gate_time", self.gate_time, "s", gt=0)
        _check_number(p + "resolution", self.resolution, "rad/s", ge=0)
        _check_integer(p + "pulses_per_rev", self.pulses_per_rev, 1, 100_000)
        _check_number(p + "update_interval", self.update_interval, "s", gt=0, optional=True)

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
        d = cls()
        kw = dict(gate_time=t.number("gate_time", "s", d.gate_time, gt=0),
                  resolution=t.number("resolution", "rev/s", d.resolution / TWO_PI, ge=0) * TWO_PI,
                  pulses_per_rev=t.integer("pulses_per_rev", 1, d.pulses_per_rev,
                                           maximum=100_000),
                  update_interval=t.number("update_interval", "s", None, gt=0))
        return _rebased(cls, kw, "instruments.tachometer", t.path)


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
    t0, t1 = _window(traj, t_start, t_end)
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

    sample_rate: float = 1000.0
    noise_rms: float = 1.0e-6
    runout: tuple = (2.0e-6,)
    runout_phase: Optional[tuple] = None
    lsb: float = 0.5e-6
    angles: tuple = (0.0, 0.5 * math.pi)
    seed: int = 0

    def __post_init__(self):
        p = "instruments.probes."
        _check_number(p + "sample_rate", self.sample_rate, "Hz", gt=0)
        _check_number(p + "noise_rms", self.noise_rms, "m", ge=0)
        _check_number(p + "lsb", self.lsb, "m", ge=0)
        _check_integer(p + "seed", self.seed, 0)
        for key, values, unit, lo in (("runout", self.runout, "m", 0.0),
                                      ("runout_phase", self.runout_phase, "rad", None),
                                      ("angles", self.angles, "rad", None)):
            if values is None:
                continue
            if not isinstance(values, (tuple, list)) or not values:
                raise SceneError(f"{p}{key} = {values!r}: must be a non-empty list ({unit})")
            for i, v in enumerate(values):
                _check_number(f"{p}{key}[{i}]", v, unit, ge=lo)
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
            runout = _table_numbers(t, "runout", "m", list(d.runout), ge=0)
        phase = _table_numbers(t, "runout_phase", "deg", None, length=len(runout))
        angles = _table_numbers(t, "angles", "deg", [a / DEG for a in d.angles])
        if not angles:
            raise SceneError(f"{t.name('angles')} = []: give at least one probe direction (deg)")
        kw = dict(sample_rate=t.number("sample_rate", "Hz", d.sample_rate, gt=0),
                  noise_rms=t.number("noise_rms", "m", d.noise_rms, ge=0),
                  runout=tuple(runout),
                  runout_phase=None if phase is None else tuple(v * DEG for v in phase),
                  lsb=t.number("lsb", "m", d.lsb, ge=0),
                  angles=tuple(a * DEG for a in angles),
                  seed=t.integer("seed", 0, d.seed))
        return _rebased(cls, kw, "instruments.probes", t.path)


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
    t0, t1 = _window(traj, t_start, t_end)
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
