"""The light-slot stroboscope: settings, reading error (4.1) and what it shows at each flash.

Monograph section 4.3.1; digest ch5 section 6.1.  A lamp in the machine body
shines through a narrow slot; the rotor has a slot of its own, so light enters
the rotor once per revolution, when the rotor's slot passes the lamp
(:func:`flash_times`), and an observer sees the weights at one rotor angle
(:func:`strobe_angles`).  Reading error (4.1)::

    eta = delta_max / P_min,   P_min = 2 pi slot_radius,

the slot width over the rotor perimeter at the slot, independent of the
speed; while the slots overlap the rotor turns by ``slot_width /
slot_radius`` rad (:attr:`Stroboscope.blur`).  A weight group running at
Omega while the rotor runs at omega shows several images in an exposure over
several flashes (:func:`image_multiplicity`, :func:`multiplicity_for_ratio`).

The frames a camera films through the slot are drawn by
:mod:`stand.instruments.strobe_render`; :mod:`stand.instruments.stroboscope`
gathers both.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional

import numpy as np

from ..scene import SceneError
from ._settings import boolean, check, integer, keys, number, read_table, rebased
from .timing import crossing_times, sample_trajectory, time_window, wrap

__all__ = ["Stroboscope", "StrobeReading", "reading_error", "flash_times", "strobe_angles",
           "image_multiplicity", "multiplicity_for_ratio", "default_ball_radius", "STROBE_KEYS"]

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
        t : stand.scene_file.Table

        Raises
        ------
        SceneError
            Naming the key (dotted path), the value and the unit.
        """
        t.allow(STROBE_KEYS)
        return rebased(cls, read_table(t, cls), PATH, t.path)


#: keys of ``[instruments.stroboscope]`` (the fields of :class:`Stroboscope`)
STROBE_KEYS = keys(Stroboscope)

# ---------------------------------------------------------------- readings
@dataclass
class StrobeReading:
    """What the stroboscope shows at each flash (ground truth, SI units).

    Attributes
    ----------
    t : (K,)                 flash times [s] (the slot's centre passes the lamp)
    rotor_angle : (K,)       rotor angle at the flashes, unwrapped [rad]
                             (= flash_angle + 2 pi k to ~1e-12 rad)
    weight_angle : (K, n)    absolute weight angles [rad]
    relative_angle : (K, n)  weight angles from the reference mark, wrapped to (-pi, pi] [rad]
    x, y : (K,)              shaft displacement [m]
    rotor_speed : (K,)       [rad/s]
    """

    t: np.ndarray
    rotor_angle: np.ndarray
    weight_angle: np.ndarray
    relative_angle: np.ndarray
    x: np.ndarray
    y: np.ndarray
    rotor_speed: np.ndarray


def flash_times(traj, strobe: Stroboscope, t_start: Optional[float] = None,
                t_end: Optional[float] = None) -> np.ndarray:
    """Times [s] at which the slot's centre passes the lamp.

    The rotor angle crosses ``flash_angle + 2 pi k`` (in either direction: the
    light enters whenever the slots align), found by cubic Hermite
    interpolation of (rotor_angle, rotor_speed) and Newton refinement
    (:func:`stand.instruments.timing.crossing_times`).  Flashes whose angular
    blur would reach outside the sampled run are dropped.

    Parameters
    ----------
    traj : Trajectory
    strobe : Stroboscope
    t_start, t_end : float, optional
        Window [s]; default the whole run.
    """
    t0, t1 = time_window(traj, t_start, t_end, "stroboscope")
    tf = crossing_times(traj.t, traj.rotor_angle, traj.rotor_speed, strobe.flash_angle,
                        direction=0)
    tf = tf[(tf >= t0) & (tf <= t1)]
    if tf.size:  # keep the blur window inside the samples
        i = np.clip(np.searchsorted(traj.t, tf), 0, traj.t.size - 1)
        w = np.maximum(np.abs(traj.rotor_speed[i]), 1e-300)
        half = 0.5 * strobe.blur / w
        tf = tf[(tf - half >= traj.t[0]) & (tf + half <= traj.t[-1])]
    return tf


def strobe_angles(traj, strobe: Stroboscope, t_start: Optional[float] = None,
                  t_end: Optional[float] = None) -> StrobeReading:
    """The weights' angles as the stroboscope shows them, one row per flash.

    Weight angles are Hermite-interpolated from (weight_angle, weight_speed),
    the shaft position from (x, y) and the shaft velocity; see
    :mod:`stand.instruments.timing` for the accuracy (~1e-5 rad with 20
    samples per revolution, much better for smooth weight motion).
    """
    tf = flash_times(traj, strobe, t_start, t_end)
    n = int(np.shape(traj.weight_angle)[1]) if np.ndim(traj.weight_angle) == 2 else 0
    if tf.size == 0:
        z = np.zeros(0)
        return StrobeReading(z, z, np.zeros((0, n)), np.zeros((0, n)), z, z, z)
    s = sample_trajectory(traj, tf)
    return StrobeReading(t=tf, rotor_angle=s.rotor_angle, weight_angle=s.weight_angle,
                         relative_angle=wrap(s.weight_angle - s.rotor_angle[:, None]),
                         x=s.x, y=s.y, rotor_speed=s.rotor_speed)


# ---------------------------------------------------------------- multiplicity
def image_multiplicity(angles, blur: float) -> int:
    """Number of distinct images of weights at ``angles`` (a multi-flash exposure).

    Angles on the circle closer than ``blur`` (single linkage: chains of
    neighbours each within ``blur``) merge into one image.  For a rendered
    frame the natural ``blur`` is the angular size of a weight image,
    ``2 ball_radius / track_radius + slot_width / slot_radius``.

    Parameters
    ----------
    angles : array_like
        Relative (or absolute) angles of all weight images in the exposure,
        any shape, e.g. ``StrobeFrame.relative_angle`` (K flashes x n weights) [rad].
    blur : float
        Merging distance [rad], >= 0.

    Returns
    -------
    int
        0 for no angles, else the number of clusters on the circle.
    """
    a = np.sort(np.mod(np.ravel(np.asarray(angles, float)), TWO_PI))
    if a.size == 0:
        return 0
    if not blur >= 0:
        raise ValueError(f"image_multiplicity: blur = {blur!r} rad must be >= 0")
    gaps = np.diff(np.concatenate([a, [a[0] + TWO_PI]]))
    return max(1, int(np.count_nonzero(gaps > blur)))


def multiplicity_for_ratio(ratio: float, flashes: int, blur: float) -> int:
    """Images of one weight group running at Omega = ratio * omega over ``flashes``.

    Successive flashes show it at relative angles ``-2 pi k (1 - ratio)``
    (digest ch5 section 5.3); :func:`image_multiplicity` of those.  For
    ``ratio ~ p/q`` (lowest terms) and enough flashes this is ``q``: doubling
    at 1/2, tripling at 1/3 -- when ``blur`` exceeds the slow drift
    ``2 pi |ratio - p/q| * q`` per cycle; otherwise more images.
    """
    k = np.arange(int(flashes))
    return image_multiplicity(-TWO_PI * k * (1.0 - ratio), blur)

