"""Settings of the laser-spot screen's camera (``[instruments.screen]``, monograph 4.3.2) and
the times of its exposures: plain data read with the scene; the drawing is
:mod:`stand.instruments.screen`."""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from functools import cached_property
from typing import Optional

import numpy as np

from stand.errors import SceneError
from stand.scene.instrument_settings import REQUIRED, boolean, check, integer, keys, number, read_table

DEG = math.pi / 180.0
TILT_LIMIT = 0.35             #: rad, largest |tilt| accepted (mild perspective)
DEFAULT_SUBSAMPLES = 16       #: sub-samples per exposure when nothing else is known
MAX_SUBSAMPLES = 1_000_000    #: per exposure
NORMAL_LENS = 1.4             #: default camera distance / imaged screen width (HFOV ~ 39 deg)
FULL_WELL = 10_000.0          #: electrons at saturation for the default electrons_per_dn
SMOOTH_STEP_SIGMAS = 1.0      #: automatic sub-sampling: at most this many sigma between positions
MAX_SIZE = 16384              #: px, largest width or height accepted
_READ_NOISE = {8: 1.0, 10: 2.0, 12: 4.0, 14: 8.0, 16: 16.0}   #: default read noise, DN


def _bad(name, value, text):
    return SceneError(f"{name} = {value!r}: {text}")


@dataclass(frozen=True, kw_only=True)
class ScreenCamera:
    """Settings of the laser-spot screen and its camera, SI units (angles in rad).

    Fields given as ``None`` are resolved in ``__post_init__`` (defaults that
    depend on other fields), except ``subsamples`` (None = automatic, see
    :meth:`subsamples_for`).

    Attributes
    ----------
    pixel_pitch : float
        Metres of screen per pixel at the image centre, along the image u axis
        (along v it is pixel_pitch / cos(tilt)).  Required.
    gain : float
        Spot displacement on the screen per shaft displacement (optical lever
        of plane-parallel models); default 1.
    misalignment : float
        Radius [m] of the beam-misalignment circle on the screen: the beam is not
        exactly on the rotation axis, so the spot turns on a circle at the rotor
        frequency even when the shaft is still ("dynamic centring", §4.3.2,
        removes it); default 0.
    misalignment_phase : float
        Angle [rad] of that circle's radius from the rotor's reference mark.
    offset_x, offset_y : float
        Position [m] of the undeflected beam on the screen relative to the image
        centre (static centring error, screen placement); default 0.
    width, height : int
        Image size [px]; default 640 x 480.
    tilt : float
        Camera tilt [rad] about the image u axis (a mild perspective: the
        screen's +Y side is farther from the camera for tilt > 0), |tilt| < 0.35;
        implemented as a homography; default 0.
    camera_distance : float
        Distance [m] from the camera's centre of projection to the screen point
        at the image centre; sets the strength of the perspective (only matters
        with a tilt).  Default: 1.4 x the imaged screen width (a normal lens,
        horizontal field of view about 39 deg).
    frame_rate : float
        Frames per second [Hz]; default 25.
    exposure : float
        Exposure time [s], 0 < exposure <= 1/frame_rate; default half the frame
        period.
    start_time : float
        Start of the first exposure [s]; default 0.
    subsamples : int or None
        Spot positions integrated per exposure (midpoints of equal slices);
        1 = no motion blur.  None (default): automatic -- enough positions that
        consecutive ones are at most one spot sigma apart for a curve as large
        as the image turning at the rotor speed (:meth:`subsamples_for`), at
        least 16.
    spot_diameter : float
        1/e^2 diameter [m] of the Gaussian spot on the screen; default 2 mm.
    peak : float
        DN at the centre of a still spot over the full exposure (above the
        background); default 0.8 of full scale (204 DN at 8 bits).
    background : float
        Mean DN of the lit, spot-free screen over the exposure; default 0.03 of
        full scale (8 DN at 8 bits).
    read_noise : float
        DN rms (1, 2, 4 DN at 8, 10, 12 bits by default).
    shot_noise : bool
        Poisson noise on the signal (background + spot) in electrons; default on.
    electrons_per_dn : float
        Conversion gain; default full well 10 000 e- / (2**bit_depth - 1).
    bit_depth : int
        8 (uint8 frames) or 10, 12, 14, 16 (uint16 frames); saturation at
        2**bit_depth - 1.
    seed : int
        Seed of the noise; frame f uses the stream (seed, f).
    lens_k1, lens_k2 : float
        Radial lens distortion (OpenCV's Brown model about the image centre, radius
        normalised by the focal length camera_distance / pixel_pitch [px];
        ``lens_of`` of the screen instrument); default 0 (a pinhole).
    jpeg_quality : int or None
        Each frame through JPEG at this quality 1..100 (8-bit frames only); default None.
    flicker_depth, mains_frequency : float
        Lamp flicker: each frame's brightness times 1 + depth cos(2 pi 2 f_mains t_mid)
        (t_mid its mid-exposure time [s]); depth 0..1 (default 0), mains [Hz] (default 50).
    hot_pixels : int
        Pixels reading full scale in every frame (fixed by the seed); default 0.
    saturation : float or None
        DN at which the sensor clips, below full scale (default: full scale).
    drop_rate : float
        Probability that a frame is lost (the kept frames keep their timestamps); default 0.
    auto_gain_time : float
        Auto-exposure time constant [s] (0: fixed exposure): the gain follows the frames'
        mean brightness (``vision.camera_artefacts.auto_gain``); default 0.
    h264_qp : int or None
        The frames through H.264 at this constant quantiser 0..51 (x264 through PyAV, the
        optional extra ``video``; 8-bit frames only) and decoded back; default None.
    auto_gain_target : float or None
        The background level [DN] the auto-exposure holds (its set point; the frames' mean is
        the background's plus the spot's small share); default None: the first frame's.
    line_time : float
        Rolling shutter: row r's exposure starts r line_time [s] after row 0's; default 0
        (a global shutter).
    table : str
        Dotted name of the settings table, used in error messages.
    """

    pixel_pitch: float = number(REQUIRED, "m of screen per px", gt=0)
    gain: float = number(1.0, "screen displacement per shaft displacement", gt=0)
    misalignment: float = number(0.0, "m", ge=0)
    misalignment_phase: float = number(0.0, "rad", toml=("deg", DEG))
    offset_x: float = number(0.0, "m")
    offset_y: float = number(0.0, "m")
    width: int = integer(640, 8, MAX_SIZE)
    height: int = integer(480, 8, MAX_SIZE)
    tilt: float = number(0.0, "rad", toml=("deg", DEG))
    camera_distance: Optional[float] = number(None, "m", gt=0)
    frame_rate: float = number(25.0, "Hz", gt=0)
    exposure: Optional[float] = number(None, "s", gt=0)
    start_time: float = number(0.0, "s", ge=0)
    subsamples: Optional[int] = integer(None, 1, MAX_SUBSAMPLES, optional=True)
    spot_diameter: float = number(2e-3, "m, 1/e^2 diameter on the screen", gt=0)
    peak: Optional[float] = number(None, "DN", gt=0)
    background: Optional[float] = number(None, "DN", ge=0)
    read_noise: Optional[float] = number(None, "DN rms", ge=0)
    shot_noise: bool = boolean(True)
    electrons_per_dn: Optional[float] = number(None, "e-/DN", gt=0)
    bit_depth: int = integer(8, 8, 16)
    seed: int = integer(0, 0, 2 ** 63 - 1)
    lens_k1: float = number(0.0, "1")
    lens_k2: float = number(0.0, "1")
    jpeg_quality: Optional[int] = integer(None, 1, 100, optional=True)
    flicker_depth: float = number(0.0, "1", ge=0, lt=1)
    mains_frequency: float = number(50.0, "Hz", gt=0)
    hot_pixels: int = integer(0, 0, 1_000_000)
    saturation: Optional[float] = number(None, "DN", gt=0, optional=True)
    drop_rate: float = number(0.0, "1", ge=0, lt=1)
    auto_gain_time: float = number(0.0, "s", ge=0)
    auto_gain_target: Optional[float] = number(None, "DN", gt=0, optional=True)
    h264_qp: Optional[int] = integer(None, 0, 51, optional=True)
    line_time: float = number(0.0, "s per row", ge=0)
    table: str = field(default="instruments.screen", compare=False, repr=False)

    # ------------------------------------------------------------ validation
    def __post_init__(self):
        n = lambda key: f"{self.table}.{key}"  # noqa: E731

        def default(key, value):  # the fields given as None: defaults from the others
            if getattr(self, key) is None:
                object.__setattr__(self, key, value)

        check(self, self.table, ("bit_depth",))
        if self.bit_depth not in _READ_NOISE:
            raise _bad(n("bit_depth"), self.bit_depth, "must be one of 8, 10, 12, 14, 16 (bits)")
        top = self.max_dn
        check(self, self.table, ("width", "height", "seed", "shot_noise", "pixel_pitch", "gain",
                                 "misalignment", "misalignment_phase", "offset_x", "offset_y",
                                 "tilt"))
        if not abs(self.tilt) < TILT_LIMIT:
            raise _bad(n("tilt"), self.tilt, f"|tilt| must be < {TILT_LIMIT} rad "
                       f"({TILT_LIMIT / DEG:.2f} deg): only a mild perspective is modelled")
        default("camera_distance", NORMAL_LENS * self.width * self.pixel_pitch)
        check(self, self.table, ("camera_distance", "frame_rate"))
        default("exposure", 0.5 / self.frame_rate)
        check(self, self.table, ("exposure",))
        if self.exposure > self.frame_period * (1.0 + 1e-12):
            raise _bad(n("exposure"), self.exposure,
                       f"longer than the frame period 1/frame_rate = {self.frame_period:.6g} s "
                       f"({n('frame_rate')} = {self.frame_rate:g} Hz); must be <= "
                       f"{self.frame_period:.6g} (s)")
        check(self, self.table, ("start_time", "subsamples", "spot_diameter"))
        d_px = self.spot_diameter / self.pixel_pitch
        if not d_px <= min(self.width, self.height):
            raise _bad(n("spot_diameter"), self.spot_diameter,
                       f"the spot ({d_px:.4g} px = spot_diameter / pixel_pitch) is larger than "
                       f"the frame ({self.width} x {self.height} px); must be <= "
                       f"{min(self.width, self.height) * self.pixel_pitch:.4g} (m)")
        default("peak", float(round(0.8 * top)))
        default("background", float(round(0.03 * top)))
        default("read_noise", _READ_NOISE[self.bit_depth])
        default("electrons_per_dn", FULL_WELL / top)
        check(self, self.table, ("peak", "background", "read_noise", "electrons_per_dn",
                                 "lens_k1", "lens_k2", "jpeg_quality", "flicker_depth",
                                 "mains_frequency", "hot_pixels", "saturation", "drop_rate",
                                 "auto_gain_time", "auto_gain_target", "line_time", "h264_qp"))
        if self.auto_gain_target is not None and not self.background > 0:
            raise _bad(n("auto_gain_target"), self.auto_gain_target,
                       f"an auto-exposure set point needs a background > 0 ({n('background')})")
        for key in ("jpeg_quality", "h264_qp"):
            if getattr(self, key) is not None and self.bit_depth != 8:
                raise _bad(n(key), getattr(self, key),
                           f"{key[:4].upper()} needs 8-bit frames ({n('bit_depth')} = {self.bit_depth})")
        # the screen's horizon must stay outside the image
        Hinv = np.linalg.inv(self.homography)
        W1, H1 = self.width - 0.5, self.height - 0.5
        for uu, vv in ((-0.5, -0.5), (W1, -0.5), (-0.5, H1), (W1, H1)):
            X, Y, w = Hinv @ np.array([uu, vv, 1.0])
            if not (w != 0 and 1.0 + math.sin(self.tilt) * (Y / w) / self.camera_distance > 0):
                raise _bad(n("camera_distance"), self.camera_distance,
                           f"too short for {n('tilt')} = {self.tilt:g} rad: the image would "
                           f"reach the screen's horizon; increase it (m)")

    # ------------------------------------------------------------ derived
    @property
    def max_dn(self) -> int:
        """Saturation value 2**bit_depth - 1."""
        return (1 << self.bit_depth) - 1

    @property
    def dtype(self):
        """numpy dtype of the frames: uint8 for 8 bits, else uint16."""
        return np.dtype(np.uint8) if self.bit_depth == 8 else np.dtype(np.uint16)

    @property
    def frame_period(self) -> float:
        return 1.0 / self.frame_rate

    @property
    def sigma(self) -> float:
        """Gaussian sigma of the spot on the screen [m] (1/e^2 diameter / 4)."""
        return self.spot_diameter / 4.0

    @property
    def sigma_px(self) -> tuple[float, float]:
        """Spot sigma in the image [px] along u and v (at the image centre).

        The spot is drawn as an axis-aligned Gaussian of these widths
        everywhere in the image (the perspective's change of scale across a
        mildly tilted image is neglected for the spot's shape; its position is
        exact).
        """
        s = self.sigma / self.pixel_pitch
        return s, s * math.cos(self.tilt)

    @cached_property
    def homography(self) -> np.ndarray:
        """3x3 matrix H: [u w, v w, w] = H [X, Y, 1] (screen m -> image px).

        Pinhole camera at ``camera_distance`` from the image-centre point of the
        screen, rotated by ``tilt`` about the image u axis:
        u = c_u + (X/p) / (1 + s Y/d),  v = c_v - (Y cos(tilt)/p) / (1 + s Y/d),
        s = sin(tilt), p = pixel_pitch, d = camera_distance.
        """
        p, d, s, c = self.pixel_pitch, self.camera_distance, math.sin(self.tilt), math.cos(self.tilt)
        cu, cv = (self.width - 1) / 2.0, (self.height - 1) / 2.0
        return np.array([[1.0 / p, cu * s / d, cu],
                         [0.0, cv * s / d - c / p, cv],
                         [0.0, s / d, 1.0]])

    @cached_property
    def homography_inverse(self) -> np.ndarray:
        return np.linalg.inv(self.homography)

    def subsamples_for(self, max_rotor_speed: Optional[float] = None) -> int:
        """Sub-samples per exposure.

        ``subsamples`` if set; else automatic: consecutive positions at most
        one spot sigma apart for a curve as large as the image (radius = the
        image half-diagonal) traced at ``max_rotor_speed`` [rad/s] (the spot's
        fastest components turn at the rotor speed: synchronous whirl,
        nutation, misalignment circle), at least 16; 16 when the speed is not
        given.
        """
        if self.subsamples is not None:
            return self.subsamples
        if max_rotor_speed is None or not max_rotor_speed > 0:
            return DEFAULT_SUBSAMPLES
        radius_px = 0.5 * math.hypot(self.width, self.height)
        path = self.exposure * float(max_rotor_speed) * radius_px
        k = math.ceil(path / (SMOOTH_STEP_SIGMAS * min(self.sigma_px)))
        return int(min(max(k, DEFAULT_SUBSAMPLES), MAX_SUBSAMPLES))

    def check_against_run(self, run) -> None:
        """Check the camera against the run settings (:class:`stand.scene.model.RunSettings`).

        Raises
        ------
        SceneError
            frame rate above the simulation's sample rate; no complete exposure
            within the run.
        """
        n = lambda key: f"{self.table}.{key}"  # noqa: E731
        if self.frame_rate > run.sample_rate * (1.0 + 1e-12):
            raise SceneError(f"{n('frame_rate')} = {self.frame_rate:g}: above the simulation's "
                             f"sample rate run.sample_rate = {run.sample_rate:g} (Hz); lower "
                             f"{n('frame_rate')} or raise run.sample_rate")
        if self.start_time + self.exposure > run.duration * (1.0 + 1e-12):
            raise SceneError(f"{n('start_time')} + {n('exposure')} = "
                             f"{self.start_time + self.exposure:g}: no complete exposure within "
                             f"run.duration = {run.duration:g} (s)")

    def to_attrs(self) -> dict:
        """All settings (resolved) plus derived values, for storing in a recording.

        Units: SI, angles in rad; ``subsamples`` is -1 when automatic.
        """
        d = {f.name: getattr(self, f.name) for f in dataclasses.fields(self) if f.name != "table"}
        d["subsamples"] = -1 if self.subsamples is None else self.subsamples
        d["sigma_px"] = list(self.sigma_px)
        d["max_dn"] = self.max_dn
        d["dtype"] = self.dtype.name
        d["homography"] = self.homography.tolist()
        d["pixel_convention"] = ("u = column, v = row, pixel centres at integers; "
                                 "screen origin at the image centre, +X right, +Y up")
        return d

    # ------------------------------------------------------------ TOML
    @classmethod
    def from_table(cls, t) -> "ScreenCamera":
        """Settings from a ``[instruments.screen]`` table (:class:`stand.scene.parse.Table`).

        TOML units: SI; ``misalignment_phase`` and ``tilt`` in degrees.  Every
        problem raises :class:`stand.scene.model.SceneError` naming the key, the
        value and the unit.
        """
        t.allow(SCREEN_KEYS)
        kw = read_table(t, cls)
        if "tilt" in kw and not abs(kw["tilt"]) < TILT_LIMIT:
            raise SceneError(f"{t.name('tilt')} = {float(t.data['tilt'])!r}: must be within +-"
                             f"{TILT_LIMIT / DEG:.2f} (deg; |tilt| < {TILT_LIMIT} rad, a mild "
                             f"perspective)")
        return cls(table=t.path, **kw)


#: keys of ``[instruments.screen]`` (TOML units: SI, angles in degrees)
SCREEN_KEYS = keys(ScreenCamera)


def frame_times(duration: float, cam: ScreenCamera) -> np.ndarray:
    """Start times [s] of the exposures that end within [0, duration]:
    ``start_time + f / frame_rate``."""
    if not duration >= 0:
        raise ValueError(f"duration = {duration!r}: must be >= 0 (s)")
    span = duration - cam.start_time - cam.exposure
    if span < -1e-12 * max(duration, 1.0):
        return np.zeros(0)
    count = int(math.floor(max(span, 0.0) * cam.frame_rate * (1.0 + 1e-12) + 1e-9)) + 1
    starts = cam.start_time + np.arange(count) / cam.frame_rate
    # never let rounding push the last exposure past the end of the run
    return starts[starts + cam.exposure <= duration * (1.0 + 1e-12) + 1e-15]


def exposure_times(starts, cam: ScreenCamera, max_rotor_speed: Optional[float] = None) -> np.ndarray:
    """Sub-sample times (F, K) [s]: midpoints of K equal slices of each exposure.

    K = :meth:`ScreenCamera.subsamples_for` ``(max_rotor_speed)`` (``cam.subsamples``
    when set; ``max_rotor_speed`` [rad/s] is the largest rotor speed of the run,
    used by the automatic choice).  Each sub-sample stands for 1/K of the
    exposure.  Flattened in C order the times are increasing (exposure <= frame
    period) and lie strictly inside the exposures, as
    ``simulate(extra_times=times.ravel())`` requires.
    """
    starts = np.asarray(starts, dtype=float).reshape(-1)
    K = cam.subsamples_for(max_rotor_speed)
    return starts[:, None] + (np.arange(K) + 0.5) / K * cam.exposure
