"""The rotor's angle at every sample of a record (:class:`RotorAngle`), whatever it came from.

Made by :mod:`dsp.speed` (keyphasor pulses, a tachometer, the 1X line) and
:mod:`dsp.speed_channels` (an encoder, a continuous speed channel); also importable as
``dsp.speed.RotorAngle``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional

import numpy as np

__all__ = ["RotorAngle", "TWO_PI"]

TWO_PI = 2.0 * math.pi


@dataclass(frozen=True)
class RotorAngle:
    """The rotor's angle at every sample of a record.

    Attributes
    ----------
    angle_rad : ndarray
        Unwrapped rotor angle [rad] (NaN where not covered).
    speed_rad_s : ndarray
        d angle / dt [rad/s] (NaN where not covered).
    acceleration_rad_s2 : ndarray
        d speed / dt [rad/s^2] (NaN where not covered).
    covered : ndarray of bool
        Samples where the angle is known (between the first and last pulse).
    source : str
        ``"keyphasor"``, ``"angle"``, ``"tachometer"`` or ``"1X line"``.
    referenced : bool
        The angle is measured from a mark on the rotor (keyphasor, encoder):
        phases (the unbalance angle) are meaningful.
    estimated : bool
        The speed is estimated from the vibration (no speed channel).
    pulses_s : ndarray or None
        The pulse times [s] it was made from.
    angle_error : dsp.held_display.AngleError or None
        What the source leaves open of the angle (a held tachometer display's quantum
        and timing), for the fits that use it.
    pulse_timing_std_s : ndarray or None
        Std [s] of each pulse time of ``pulses_s`` (a keyphasor's edges), when known.
    """

    angle_rad: np.ndarray
    speed_rad_s: np.ndarray
    acceleration_rad_s2: np.ndarray
    covered: np.ndarray
    source: str
    referenced: bool
    estimated: bool = False
    pulses_s: Optional[np.ndarray] = None
    angle_error: Optional[object] = None
    pulse_timing_std_s: Optional[np.ndarray] = None
