"""Settings of the keyphasor, the tachometer and the displacement probes
(``[instruments.keyphasor]``, ``[instruments.tachometer]``, ``[instruments.probes]``): plain
data read with the scene; the signals are :mod:`stand.instruments.probes`."""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional

import numpy as np

from stand.errors import SceneError
from stand.scene.instrument_settings import (check, choice, integer, keys, number, numbers, read_table,
                                             rebased, table_numbers)

TWO_PI = 2.0 * math.pi
DEG = math.pi / 180.0
MAX_PROBES = 16
MAX_HARMONICS = 64


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
    bounce : int
        Contact bounce: extra pulses after each true edge (0: none).
    bounce_time : float
        Time between the bounce's edges [s] (the k-th extra edge ``k bounce_time`` after the true one).
    """

    mark_angle: float = number(0.0, "rad", toml=("deg", DEG))
    jitter: float = number(0.0, "s", ge=0)
    seed: int = integer(0, 0)
    bounce: int = integer(0, 0, 20)
    bounce_time: float = number(0.002, "s", gt=0, lt=0.1)

    def __post_init__(self):
        check(self, "instruments.keyphasor")

    @classmethod
    def from_table(cls, t) -> "Keyphasor":
        """``[instruments.keyphasor]``: ``mark_angle`` [deg], ``jitter`` [s], ``seed``, ``bounce``,
        ``bounce_time`` [s]."""
        t.allow(KEYPHASOR_KEYS)
        return rebased(cls, read_table(t, cls), "instruments.keyphasor", t.path)


#: keys of ``[instruments.keyphasor]`` (the fields of :class:`Keyphasor`)
KEYPHASOR_KEYS = keys(Keyphasor)


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

    The DAQ's artefacts, each off by default (the analysis is told of them by a recording
    map, or finds them: :mod:`dsp.artefacts`), applied in this order:

    hum : tuple of float
        Mains hum [m] at 1x, 2x, ... ``hum_frequency`` [Hz] (50 or 60), in phase on every
        channel (a ground loop).
    drift : float
        DC drift [m/s], linear from the record's start.
    skew : float
        Channel-to-channel delay [s]: probe i is sampled i skew after probe 0
        (a multiplexed converter).
    filter, filter_order, filter_cutoff, group_delay :
        Anti-alias low-pass (``none``, ``butterworth``, ``bessel``; order; cutoff [Hz];
        scipy's analog filter through its first-order-hold twin) and a converter's group
        delay [s] (:class:`dsp.artefacts.ChannelFilter`); the keyphasor is a digital line,
        not filtered.
    adc_range : float
        The converter's range +-``adc_range`` [m] (0: none): beyond it the signal clips.
    resonance_frequency, resonance_q, highpass_cutoff :
        The sensor's own response, before the DAQ's filter: a mounted resonance [Hz] (0: none)
        of quality factor ``resonance_q`` and a first-order high-pass corner [Hz] (0: none).
    """

    sample_rate: float = number(1000.0, "Hz", gt=0)
    noise_rms: float = number(1.0e-6, "m", ge=0)
    runout: tuple = numbers((2.0e-6,), "m", ge=0)
    runout_phase: Optional[tuple] = numbers(None, "rad", optional=True)
    lsb: float = number(0.5e-6, "m", ge=0)
    angles: tuple = numbers((0.0, 0.5 * math.pi), "rad")
    seed: int = integer(0, 0)
    hum: tuple = numbers((0.0,), "m", ge=0)
    hum_frequency: float = number(50.0, "Hz", gt=0)
    drift: float = number(0.0, "m/s")
    skew: float = number(0.0, "s", ge=0, lt=0.01)
    filter: str = choice("none", ("none", "butterworth", "bessel"))
    filter_order: int = integer(4, 1, 10)
    filter_cutoff: float = number(100.0, "Hz", gt=0)
    group_delay: float = number(0.0, "s", ge=0, lt=0.1)
    adc_range: float = number(0.0, "m", ge=0)
    resonance_frequency: float = number(0.0, "Hz", ge=0)
    resonance_q: float = number(30.0, "1", ge=0.5)
    highpass_cutoff: float = number(0.0, "Hz", ge=0)

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
        hum = (t.number("hum", "m", ge=0),) if "hum" in t and not isinstance(
            t.data["hum"], (list, tuple)) else table_numbers(t, "hum", "m", list(d.hum), ge=0)
        if not angles:
            raise SceneError(f"{t.name('angles')} = []: give at least one probe direction (deg)")
        kw = dict(read_table(t, cls), runout=tuple(runout),
                  runout_phase=None if phase is None else tuple(v * DEG for v in phase),
                  angles=tuple(a * DEG for a in angles), hum=tuple(hum))
        return rebased(cls, kw, "instruments.probes", t.path)


#: keys of ``[instruments.probes]`` (the fields of :class:`DisplacementProbes`)
PROBE_KEYS = keys(DisplacementProbes)
