"""Settings of the light-slot stroboscope and its camera (``[instruments.stroboscope]``,
monograph 4.3) and its reading error (4.1): plain data read with the scene; the readings
are :mod:`stand.instruments.strobe_readings`."""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional

import numpy as np

from stand.errors import SceneError
from stand.scene.instrument_settings import boolean, check, integer, keys, number, read_table, rebased

TWO_PI = 2.0 * math.pi
DEG = math.pi / 180.0
PATH = "instruments.stroboscope"
STEEL_DENSITY = 7850.0  #: kg/m^3, for the default drawn ball size


def reading_error(slot_width: float, slot_radius: float) -> float:
    """Reading error (4.1) of the stroboscope, eta = delta_max / P_min.

    Parameters
    ----------
    slot_width : float
        delta_max, the widest slot (body or rotor) [m].
    slot_radius : float
        Rotor radius at the slot [m]; P_min = 2 pi slot_radius.

    Returns
    -------
    float
        eta as a fraction of a revolution (multiply by 100 for the book's %,
        by 2 pi for radians: ``slot_width / slot_radius``).
    """
    if not (slot_width > 0 and slot_radius > 0):
        raise SceneError(f"reading_error: slot_width = {slot_width!r} m and slot_radius = "
                         f"{slot_radius!r} m must be > 0")
    return float(slot_width) / (TWO_PI * float(slot_radius))


def default_ball_radius(mass) -> np.ndarray:
    """Radius of a steel ball (7850 kg/m^3) of the given mass [kg] -> [m]."""
    return (3.0 * np.asarray(mass, float) / (4.0 * math.pi * STEEL_DENSITY)) ** (1.0 / 3.0)


@dataclass(frozen=True)
class Stroboscope:
    """Settings of the light-slot stroboscope and of the camera that films it.

    Parameters
    ----------
    flash_angle : float
        Rotor angle (of the reference mark) at which the rotor's slot passes
        the lamp [rad]; the flashes happen when ``rotor_angle = flash_angle +
        2 pi k``.  TOML: degrees.
    slot_width : float
        delta_max, the widest of the two slots [m].
    slot_radius : float
        Rotor radius at the slot [m]: P_min = 2 pi slot_radius; also the drawn
        rotor outline.
    exposure_flashes : int
        Flashes integrated per frame (>= 1).
    frame_every : int or None
        Flashes from one frame's first flash to the next's (default:
        ``exposure_flashes``, i.e. back-to-back exposures).
    width, height : int
        Image size [px].
    pixel_pitch : float
        Size of a pixel in the rotor plane [m/px].
    ball_radius : float or None
        Drawn radius of the balls / pendulum bobs [m]; default: a steel ball
        of each weight's mass (:func:`default_ball_radius`).
    track_radius : float or None
        Drawn radius of the weights' centres [m]; default the balancer's
        ``radius`` per weight.
    shaft_motion : bool
        Draw the rotor around the displaced shaft centre (the whirl shows).
    background : float
        Housing brightness outside the rotor, fraction of full scale [0, 1).
    read_noise : float
        Gaussian read noise, rms fraction of full scale [0, 1).
    full_well : float
        Electrons at full scale for the shot noise; 0 disables it.
    bit_depth : int
        1..16 bits; frames are uint8 up to 8 bits, uint16 above.
    seed : int
        Seed of the noise generator (frames are reproducible).
    """

    flash_angle: float = number(0.0, "rad", toml=("deg", DEG))
    slot_width: float = number(0.002, "m", gt=0)
    slot_radius: float = number(0.12, "m", gt=0)
    exposure_flashes: int = integer(1, 1)
    frame_every: Optional[int] = integer(None, 1, optional=True)
    width: int = integer(320, 8, 4096)
    height: int = integer(320, 8, 4096)
    pixel_pitch: float = number(1.0e-3, "m/px", gt=0)
    ball_radius: Optional[float] = number(None, "m", gt=0, optional=True)
    track_radius: Optional[float] = number(None, "m", gt=0, optional=True)
    shaft_motion: bool = boolean(True)
    background: float = number(0.04, "fraction of full scale", ge=0, lt=1)
    read_noise: float = number(0.004, "fraction of full scale", ge=0, lt=1)
    full_well: float = number(10000.0, "electrons", ge=0)
    bit_depth: int = integer(8, 1, 16)
    seed: int = integer(0, 0)

    def __post_init__(self):
        check(self, PATH)
        if not self.slot_width < TWO_PI * self.slot_radius:
            raise SceneError(f"{PATH}.slot_width = {self.slot_width!r}: the slot is wider than "
                             f"the rotor perimeter at the slot, 2 pi slot_radius = "
                             f"{TWO_PI * self.slot_radius:.6g} (m)")
        if self.ball_radius is not None and self.ball_radius / self.pixel_pitch < 0.5:
            raise SceneError(f"{PATH}.ball_radius = {self.ball_radius!r}: smaller than half a "
                             f"pixel (pixel_pitch = {self.pixel_pitch!r} m/px); the balls would "
                             f"not show")

    # ------------------------------------------------------------ derived
    @property
    def blur(self) -> float:
        """Angular blur of each image, slot_width / slot_radius [rad]."""
        return self.slot_width / self.slot_radius

    @property
    def reading_error(self) -> float:
        """(4.1) eta = slot_width / (2 pi slot_radius), fraction of a revolution."""
        return reading_error(self.slot_width, self.slot_radius)

    @property
    def stride(self) -> int:
        """Flashes from one frame's start to the next's."""
        return self.frame_every if self.frame_every is not None else self.exposure_flashes

    @property
    def dtype(self):
        return np.uint8 if self.bit_depth <= 8 else np.uint16

    # ------------------------------------------------------------ TOML
    @classmethod
    def from_table(cls, t) -> "Stroboscope":
        """Build from a validated ``[instruments.stroboscope]`` table.

        Units in the file: ``flash_angle`` in degrees; lengths in m
        (``slot_width``, ``slot_radius``, ``pixel_pitch`` [m/px],
        ``ball_radius``, ``track_radius``); ``width``, ``height`` in px;
        ``background``, ``read_noise`` as fractions of full scale;
        ``full_well`` in electrons.  Every key is optional (defaults of the
        dataclass).

        Parameters
        ----------
        t : stand.scene.parse.Table

        Raises
        ------
        SceneError
            Naming the key (dotted path), the value and the unit.
        """
        t.allow(STROBE_KEYS)
        return rebased(cls, read_table(t, cls), PATH, t.path)


#: keys of ``[instruments.stroboscope]`` (the fields of :class:`Stroboscope`)
STROBE_KEYS = keys(Stroboscope)
