"""The light-slot stroboscope of the universal stand (monograph section 4.3.1).

A lamp in the machine body shines through a narrow slot; the rotor has a slot
of its own, so light enters the rotor once per revolution, when the rotor's
slot passes the lamp, and an observer (a camera above the rotor) sees the
weights at one rotor angle (digest ch5 section 6.1).  Reading error (4.1)::

    eta = delta_max / P_min,   P_min = 2 pi slot_radius,

the slot width over the rotor perimeter at the slot, independent of the
speed.  While the slots overlap the rotor turns by ``slot_width /
slot_radius`` rad: this is the angular blur of every image (the light is taken
as uniform over that span: one slot much narrower than the other).

A weight group that runs at Omega while the rotor runs at omega (stuck balls,
digest ch5 section 5.3) moves by ``-2 pi (1 - Omega/omega)`` of relative angle
per flash; an exposure over several flashes then shows several images (the
book's "doubling, tripling" for Omega/omega ~ 1/2, 1/3).

Conventions of the images
-------------------------
The camera looks down the shaft axis and is fixed to the machine body, so the
image is in the fixed frame: pixel column = ``(width - 1)/2 + X / pixel_pitch``,
row = ``(height - 1)/2 - Y / pixel_pitch`` (X right, Y up, angles counter-
clockwise from X).  At a flash the rotor's reference mark points at the flash
angle and each weight at its absolute angle (the reference mark plus its
relative angle), i.e. the rotor frame as the eye sees it through the slot.
With ``shaft_motion`` the rotor is drawn around the displaced shaft centre
(x, y) (the whirl is seen); otherwise around the image centre.

What is drawn (intensities as fractions of full scale, see the ``LEVEL_*``
constants): outside the rotor the housing at ``background``; inside the rotor
outline (radius ``slot_radius``) the lit interior; the rim; the reference mark
(a radial bar at 0.80..0.97 of the rim radius); the weights -- balls as discs,
pendulums as a rod from the shaft axis (the pivot) plus a bob.  Every flash is
the average of sub-images across the slot's angular width; a frame is the mean
of its flashes (a weight seen in one of K flashes shows at 1/K contrast, as a
persistence-of-vision ghost).  Then shot noise (Poisson, ``full_well``
electrons at full scale), read noise (Gaussian, ``read_noise`` of full scale),
clipping and quantisation to ``bit_depth`` bits (uint8 up to 8 bits, else
uint16).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Iterator, Optional

import numpy as np

from ..scene import SceneError
from .timing import (_check_integer, _check_number, _rebased, _table_boolean, crossing_times,
                     sample_trajectory, shaft_velocity, wrap)

__all__ = ["Stroboscope", "StrobeReading", "StrobeFrame", "reading_error", "flash_times",
           "strobe_angles", "render_strobe_frames", "image_multiplicity",
           "multiplicity_for_ratio", "default_ball_radius", "STROBE_KEYS"]

TWO_PI = 2.0 * math.pi
DEG = math.pi / 180.0
PATH = "instruments.stroboscope"
STEEL_DENSITY = 7850.0  #: kg/m^3, for the default drawn ball size

# intensities, fractions of full scale
LEVEL_INTERIOR = 0.20
LEVEL_RIM = 0.45
LEVEL_MARK = 0.50
LEVEL_ROD = 0.70
LEVEL_BALL = 0.95
MARK_SPAN = (0.80, 0.97)   #: reference mark, fractions of the rim radius
MAX_SUBPOSITIONS = 64
MAX_PIXELS = 4096 * 4096

STROBE_KEYS = ("flash_angle", "slot_width", "slot_radius", "exposure_flashes", "frame_every",
               "width", "height", "pixel_pitch", "ball_radius", "track_radius", "shaft_motion",
               "background", "read_noise", "full_well", "bit_depth", "seed")


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

    flash_angle: float = 0.0
    slot_width: float = 0.002
    slot_radius: float = 0.12
    exposure_flashes: int = 1
    frame_every: Optional[int] = None
    width: int = 320
    height: int = 320
    pixel_pitch: float = 1.0e-3
    ball_radius: Optional[float] = None
    track_radius: Optional[float] = None
    shaft_motion: bool = True
    background: float = 0.04
    read_noise: float = 0.004
    full_well: float = 10000.0
    bit_depth: int = 8
    seed: int = 0

    def __post_init__(self):
        p = PATH + "."
        _check_number(p + "flash_angle", self.flash_angle, "rad")
        _check_number(p + "slot_width", self.slot_width, "m", gt=0)
        _check_number(p + "slot_radius", self.slot_radius, "m", gt=0)
        if not self.slot_width < TWO_PI * self.slot_radius:
            raise SceneError(f"{p}slot_width = {self.slot_width!r}: the slot is wider than the "
                             f"rotor perimeter at the slot, 2 pi slot_radius = "
                             f"{TWO_PI * self.slot_radius:.6g} (m)")
        _check_integer(p + "exposure_flashes", self.exposure_flashes, 1)
        _check_integer(p + "frame_every", self.frame_every, 1, optional=True)
        _check_integer(p + "width", self.width, 8, 4096)
        _check_integer(p + "height", self.height, 8, 4096)
        _check_number(p + "pixel_pitch", self.pixel_pitch, "m/px", gt=0)
        _check_number(p + "ball_radius", self.ball_radius, "m", gt=0, optional=True)
        _check_number(p + "track_radius", self.track_radius, "m", gt=0, optional=True)
        if not isinstance(self.shaft_motion, (bool, np.bool_)):
            raise SceneError(f"{p}shaft_motion = {self.shaft_motion!r}: must be true or false")
        _check_number(p + "background", self.background, "fraction of full scale", ge=0, lt=1)
        _check_number(p + "read_noise", self.read_noise, "fraction of full scale", ge=0, lt=1)
        _check_number(p + "full_well", self.full_well, "electrons", ge=0)
        _check_integer(p + "bit_depth", self.bit_depth, 1, 16)
        _check_integer(p + "seed", self.seed, 0)
        if self.ball_radius is not None and self.ball_radius / self.pixel_pitch < 0.5:
            raise SceneError(f"{p}ball_radius = {self.ball_radius!r}: smaller than half a pixel "
                             f"(pixel_pitch = {self.pixel_pitch!r} m/px); the balls would not show")

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
        d = cls()
        kw = dict(
            flash_angle=t.number("flash_angle", "deg", d.flash_angle / DEG) * DEG,
            slot_width=t.number("slot_width", "m", d.slot_width, gt=0),
            slot_radius=t.number("slot_radius", "m", d.slot_radius, gt=0),
            exposure_flashes=t.integer("exposure_flashes", 1, d.exposure_flashes),
            frame_every=t.integer("frame_every", 1, None) if "frame_every" in t else None,
            width=t.integer("width", 8, d.width, maximum=4096),
            height=t.integer("height", 8, d.height, maximum=4096),
            pixel_pitch=t.number("pixel_pitch", "m/px", d.pixel_pitch, gt=0),
            ball_radius=t.number("ball_radius", "m", None, gt=0),
            track_radius=t.number("track_radius", "m", None, gt=0),
            shaft_motion=_table_boolean(t, "shaft_motion", d.shaft_motion),
            background=t.number("background", "fraction of full scale", d.background,
                                ge=0, lt=1),
            read_noise=t.number("read_noise", "fraction of full scale", d.read_noise,
                                ge=0, lt=1),
            full_well=t.number("full_well", "electrons", d.full_well, ge=0),
            bit_depth=t.integer("bit_depth", 1, d.bit_depth, maximum=16),
            seed=t.integer("seed", 0, d.seed),
        )
        return _rebased(cls, kw, PATH, t.path)


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


def _window(traj, t_start, t_end) -> tuple[float, float]:
    t0 = float(traj.t[0]) if t_start is None else max(float(t_start), float(traj.t[0]))
    t1 = float(traj.t[-1]) if t_end is None else min(float(t_end), float(traj.t[-1]))
    if not t1 > t0:
        raise SceneError(f"stroboscope window [{t0:.6g}, {t1:.6g}] s is empty (the run spans "
                         f"[{float(traj.t[0]):.6g}, {float(traj.t[-1]):.6g}] s)")
    return t0, t1


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
    t0, t1 = _window(traj, t_start, t_end)
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


# ---------------------------------------------------------------- rendering
@dataclass
class StrobeFrame:
    """One stroboscope frame and its ground truth.

    Attributes
    ----------
    index : int                 frame number (0, 1, ...) in the rendered sequence
    image : (height, width)     uint8 (bit_depth <= 8) or uint16
    t : (K,)                    flash times in the exposure [s]; ``time`` = t[0]
    rotor_angle : (K,)          rotor angle at the flashes [rad]
    weight_angle : (K, n)       absolute weight angles [rad]
    relative_angle : (K, n)     weight angles from the reference mark, wrapped [rad]
    centre_px : (K, 2)          drawn rotor centre (column, row) [px]
    weight_px : (K, n, 2)       drawn weight centres (column, row) at the flash centre [px]
    """

    index: int
    image: np.ndarray
    t: np.ndarray
    rotor_angle: np.ndarray
    weight_angle: np.ndarray
    relative_angle: np.ndarray
    centre_px: np.ndarray
    weight_px: np.ndarray

    @property
    def time(self) -> float:
        """Timestamp of the frame: its first flash [s]."""
        return float(self.t[0])


def _cov_disk(X, Y, cx, cy, r):
    d = np.hypot(X - cx, Y - cy)
    return np.clip(r - d + 0.5, 0.0, 1.0)


def _cov_ring(X, Y, cx, cy, r, half):
    d = np.abs(np.hypot(X - cx, Y - cy) - r)
    return np.clip(half - d + 0.5, 0.0, 1.0)


def _cov_segment(X, Y, x0, y0, x1, y1, half):
    dx, dy = x1 - x0, y1 - y0
    L2 = dx * dx + dy * dy
    u = np.clip(((X - x0) * dx + (Y - y0) * dy) / L2, 0.0, 1.0) if L2 > 0 else 0.0
    d = np.hypot(X - (x0 + u * dx), Y - (y0 + u * dy))
    return np.clip(half - d + 0.5, 0.0, 1.0)


class _Canvas:
    """Pixel grids and bounding-box helpers for one image size."""

    def __init__(self, width: int, height: int):
        self.W, self.H = width, height
        self.cols = np.arange(width, dtype=float)
        self.rows = np.arange(height, dtype=float)

    def box(self, xs, ys, margin):
        c0 = max(0, int(math.floor(np.min(xs) - margin)))
        c1 = min(self.W, int(math.ceil(np.max(xs) + margin)) + 1)
        r0 = max(0, int(math.floor(np.min(ys) - margin)))
        r1 = min(self.H, int(math.ceil(np.max(ys) + margin)) + 1)
        if c1 <= c0 or r1 <= r0:
            return None
        X, Y = np.meshgrid(self.cols[c0:c1], self.rows[r0:r1])
        return (slice(r0, r1), slice(c0, c1)), X, Y


def _weight_geometry(scene, strobe: Stroboscope, n: int):
    """Per-weight drawn radius of the centres [m], ball radius [m], kind."""
    b = scene.balancer if scene is not None else None
    kind = b.type if (b is not None and b.count == n) else "balls"
    if strobe.track_radius is not None:
        track = np.full(n, strobe.track_radius)
    elif b is not None and b.count == n:
        track = np.asarray(b.radius, float)
    else:
        raise SceneError(f"{PATH}.track_radius: missing; the trajectory carries no balancer "
                         f"geometry for its {n} weights (m)")
    if strobe.ball_radius is not None:
        ball = np.full(n, strobe.ball_radius)
    elif b is not None and b.count == n:
        ball = default_ball_radius(b.mass)
    else:
        raise SceneError(f"{PATH}.ball_radius: missing; the trajectory carries no weight "
                         f"masses to size the balls (m)")
    return track, ball, kind


def render_strobe_frames(traj, strobe: Stroboscope, t_start: Optional[float] = None,
                         t_end: Optional[float] = None,
                         max_frames: Optional[int] = None) -> Iterator[StrobeFrame]:
    """Stroboscope frames of a run, streamed one at a time.

    Frame ``i`` integrates flashes ``i*stride .. i*stride + exposure_flashes - 1``
    of the window (``stride`` = ``frame_every`` or ``exposure_flashes``); an
    incomplete last group is dropped.  The settings are checked before the
    first frame is produced (this function validates eagerly and returns a
    generator).

    Parameters
    ----------
    traj : Trajectory
        Needs ``t, x, y, rotor_angle, rotor_speed, weight_angle, weight_speed``,
        the shaft velocity (:func:`stand.instruments.timing.shaft_velocity`) when
        ``shaft_motion``, and ``scene.balancer`` for the weights' kind and size
        unless ``track_radius`` and ``ball_radius`` are set.
    strobe : Stroboscope
    t_start, t_end : float, optional
        Window [s].
    max_frames : int, optional
        Stop after this many frames.

    Yields
    ------
    StrobeFrame

    Raises
    ------
    SceneError
        ``exposure_flashes > 1`` while the rotor does not turn the
        ``exposure_flashes - 1`` revolutions a frame needs in the window
        ("exposure over flashes with no rotation"); weights drawn outside the
        image; image too large.
    """
    t0, t1 = _window(traj, t_start, t_end)
    K, stride = strobe.exposure_flashes, strobe.stride
    tf = flash_times(traj, strobe, t0, t1)
    if K > 1 and tf.size < K:
        sel = (traj.t >= t0) & (traj.t <= t1)
        turns = float(np.ptp(traj.rotor_angle[sel])) / TWO_PI if np.any(sel) else 0.0
        top = float(np.max(np.abs(traj.rotor_speed[sel]))) / TWO_PI if np.any(sel) else 0.0
        raise SceneError(f"{PATH}.exposure_flashes = {K}: exposure over flashes with no "
                         f"rotation: the rotor turns {turns:.3g} rev in [{t0:.6g}, {t1:.6g}] s "
                         f"(speed at most {top:.3g} rev/s) and gives {tf.size} flash(es); a frame "
                         f"needs {K} flashes ({K - 1} revolutions); use exposure_flashes = 1 or "
                         f"a window in which the rotor runs")
    if strobe.width * strobe.height > MAX_PIXELS:
        raise SceneError(f"{PATH}.width * height = {strobe.width * strobe.height}: more than "
                         f"{MAX_PIXELS} px")
    n = int(np.shape(traj.weight_angle)[1]) if np.ndim(traj.weight_angle) == 2 else 0
    scene = getattr(traj, "scene", None)
    track, ball, kind = _weight_geometry(scene, strobe, n)
    half_w = 0.5 * strobe.width * strobe.pixel_pitch
    half_h = 0.5 * strobe.height * strobe.pixel_pitch
    if n and float(np.max(track + ball)) > min(half_w, half_h):
        raise SceneError(f"{PATH}.pixel_pitch = {strobe.pixel_pitch!r}: the weights (track "
                         f"radius + ball radius = {float(np.max(track + ball)):.4g} m) do not fit "
                         f"in the {strobe.width} x {strobe.height} px image "
                         f"({2 * half_w:.4g} x {2 * half_h:.4g} m); lower pixel_pitch or "
                         f"enlarge width/height (m/px)")
    n_frames = 0 if tf.size < K else (tf.size - K) // stride + 1
    if max_frames is not None:
        n_frames = min(n_frames, int(max_frames))
    velocities = shaft_velocity(traj) if strobe.shaft_motion else None
    return _frames(traj, strobe, tf, n_frames, track, ball, kind, velocities)


def _frames(traj, strobe, tf, n_frames, track, ball, kind, velocities):
    K, stride = strobe.exposure_flashes, strobe.stride
    pitch = strobe.pixel_pitch
    W, H = strobe.width, strobe.height
    cx0, cy0 = 0.5 * (W - 1), 0.5 * (H - 1)
    canvas = _Canvas(W, H)
    Xg, Yg = np.meshgrid(canvas.cols, canvas.rows)
    rng = np.random.default_rng(strobe.seed)
    n = track.size
    R_rot = strobe.slot_radius / pitch
    reach = max(R_rot, float(np.max(track)) / pitch if n else 0.0)
    n_sub = int(np.clip(math.ceil(strobe.blur * reach / 0.25), 1, MAX_SUBPOSITIONS))
    offsets = (np.arange(n_sub) + 0.5) / n_sub - 0.5 if n_sub > 1 else np.zeros(1)
    offsets = offsets * strobe.blur            # rotor angle offsets across the slot [rad]
    track_px, ball_px = track / pitch, ball / pitch
    full = (1 << strobe.bit_depth) - 1
    zeros_v = (np.zeros_like(traj.t), np.zeros_like(traj.t))
    for i in range(n_frames):
        tk = tf[i * stride:i * stride + K]
        # the flash centre and the sub-instants across the slot
        s0 = sample_trajectory(traj, tk, velocities if velocities is not None else zeros_v)
        w = np.where(np.abs(s0.rotor_speed) > 0, s0.rotor_speed, np.inf)
        tsub = (tk[:, None] + offsets[None, :] / w[:, None]).ravel()
        tsub = np.clip(tsub, traj.t[0], traj.t[-1])
        ss = sample_trajectory(traj, tsub, velocities if velocities is not None else zeros_v)
        phi_sub = ss.rotor_angle.reshape(K, n_sub)
        wa_sub = ss.weight_angle.reshape(K, n_sub, n)
        if strobe.shaft_motion:
            cxs = cx0 + s0.x / pitch
            cys = cy0 - s0.y / pitch
        else:
            cxs = np.full(K, cx0)
            cys = np.full(K, cy0)
        acc = np.zeros((H, W))
        for k in range(K):
            cx, cy = cxs[k], cys[k]
            img = np.full((H, W), strobe.background)
            inside = _cov_disk(Xg, Yg, cx, cy, R_rot)
            img += (LEVEL_INTERIOR - img) * inside
            img += (LEVEL_RIM - img) * _cov_ring(Xg, Yg, cx, cy, R_rot, 1.0)
            # reference mark: radial bar at the rotor angle of each sub-instant
            ang = phi_sub[k]
            r_a, r_b = MARK_SPAN[0] * R_rot, MARK_SPAN[1] * R_rot
            xs = np.concatenate([cx + r_a * np.cos(ang), cx + r_b * np.cos(ang)])
            ys = np.concatenate([cy - r_a * np.sin(ang), cy - r_b * np.sin(ang)])
            bx = canvas.box(xs, ys, 3.0)
            if bx is not None:
                sl, X, Y = bx
                cov = np.zeros_like(X)
                for a in ang:
                    cov += _cov_segment(X, Y, cx + r_a * math.cos(a), cy - r_a * math.sin(a),
                                        cx + r_b * math.cos(a), cy - r_b * math.sin(a), 1.5)
                cov /= n_sub
                img[sl] += (LEVEL_MARK - img[sl]) * cov
            for j in range(n):
                th = wa_sub[k, :, j]
                px = cx + track_px[j] * np.cos(th)
                py = cy - track_px[j] * np.sin(th)
                if kind == "pendulums":
                    bx = canvas.box(np.append(px, cx), np.append(py, cy), 3.0)
                    if bx is not None:
                        sl, X, Y = bx
                        cov = np.zeros_like(X)
                        for a, b_ in zip(px, py):
                            cov += _cov_segment(X, Y, cx, cy, a, b_, 1.0)
                        img[sl] += (LEVEL_ROD - img[sl]) * (cov / n_sub)
                bx = canvas.box(px, py, ball_px[j] + 2.0)
                if bx is not None:
                    sl, X, Y = bx
                    cov = np.zeros_like(X)
                    for a, b_ in zip(px, py):
                        cov += _cov_disk(X, Y, a, b_, ball_px[j])
                    img[sl] += (LEVEL_BALL - img[sl]) * (cov / n_sub)
            acc += img
        acc /= K
        if strobe.full_well > 0:
            acc = rng.poisson(np.clip(acc, 0, None) * strobe.full_well) / strobe.full_well
        if strobe.read_noise > 0:
            acc = acc + rng.normal(0.0, strobe.read_noise, acc.shape)
        image = np.rint(np.clip(acc, 0.0, 1.0) * full).astype(strobe.dtype)
        rel = wrap(s0.weight_angle - s0.rotor_angle[:, None])
        wpx = np.stack([cxs[:, None] + track_px[None, :] * np.cos(s0.weight_angle),
                        cys[:, None] - track_px[None, :] * np.sin(s0.weight_angle)], axis=-1)
        yield StrobeFrame(index=i, image=image, t=tk, rotor_angle=s0.rotor_angle,
                          weight_angle=s0.weight_angle, relative_angle=rel,
                          centre_px=np.column_stack([cxs, cys]), weight_px=wpx)
