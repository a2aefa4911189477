"""Images to numbers on the stand: spot tracks, ring calibration, ring zones, strobe angles.

The pipelines behind ``stand track`` and ``stand strobe`` as library functions
(the CLI only parses and prints): :mod:`vision` finds the spot (or the circle
a long exposure draws) in each frame, the calibration rings turn pixels into
metres (:mod:`vision.calibration`), and with the balancer's capacity the ring
zone i·S/16 and the interpolated unbalance of each frame follow
(:func:`dsp.unbalance.unbalance_from_rings`, the lab's laser method of §4.3).
Frames, ring images, ring radii and the screen's settings come from an image
or video (vision.io) or from a recording (read through :mod:`stand.recording.hdf5`).
"""
from __future__ import annotations

import math
from pathlib import Path
from typing import Optional

import numpy as np

from vision.camera_artefacts import declared_keys
from stand.recording.layout import STROBOSCOPE, instrument_key, screen_group

__all__ = ["track_frames", "write_track_csv", "parse_roi", "read_ring_file", "strobe_angles",
           "ring_radii_of", "calibration_image", "screen_group", "TRACK_PREAMBLE"]

#: the ``# key = value`` lines a track CSV may start with (:func:`write_track_csv`), in order
TRACK_PREAMBLE = ("source", "screen", "ring_radii_m", "capacity_gmm", "optical_gain", "exposure_s",
                  "roi_px", "background")

SCREEN = screen_group()


def _named_screen(source, screen):
    """``(frame source, recording, group)`` of the named screen of a recording ``source``
    (:func:`stand.recording.read.screen_group_of`: the one helper of ``--screen``)."""
    if ":" in str(source):
        raise ValueError(f"--screen {screen}: give the recording alone (not {source!r}); the "
                         f"frames are {screen_group(screen)}/frames")
    rec = _recording_of(source)
    if rec is None:
        raise ValueError(f"--screen {screen}: {source!r} is not a readable recording (.h5)")
    from stand.recording.read import screen_group_of

    group = screen_group_of(source, screen)
    return f"{source}:{group}/frames", rec, group


def _screen_columns(df, rec, group, optical_gain=None) -> None:
    """Without a ring calibration: the spot through the recorded camera geometry
    (its homography, offsets and optical gain, attrs ``settings`` of ``group``) ->
    ``x_mm``, ``y_mm`` (screen) and ``t_s``, ``x_m``, ``y_m``, ``rotor_angle_rad`` (the
    shaft or axis point the screen shows); with the screen's ``screen``, ``plane`` and
    ``axial_position_m``."""
    import json

    attrs = rec.dataset_attrs(group)
    try:
        st = json.loads(attrs.get("settings", "{}"))
    except (TypeError, ValueError):
        st = {}
    H = st.get("homography")
    if H is not None:
        Hi = np.linalg.inv(np.asarray(H, float))
        u, v = df["u_px"].to_numpy(float), df["v_px"].to_numpy(float)
        w = Hi[2, 0] * u + Hi[2, 1] * v + Hi[2, 2]
        X = (Hi[0, 0] * u + Hi[0, 1] * v + Hi[0, 2]) / w
        Y = (Hi[1, 0] * u + Hi[1, 1] * v + Hi[1, 2]) / w
        X, Y = X - float(st.get("offset_x", 0.0)), Y - float(st.get("offset_y", 0.0))
        df["x_mm"], df["y_mm"] = X * 1e3, Y * 1e3
        gain = float(optical_gain) if optical_gain is not None else float(st.get("gain", 1.0))
        if not gain > 0:
            raise ValueError(f"--optical-gain = {optical_gain}: must be > 0")
        if "time" in df:
            df["t_s"] = df["time"] + 0.5 * float(st.get("exposure", 0.0)) \
                + float(st.get("line_time", 0.0)) * df["v_px"].fillna(0.0)   # the spot's row
        df["x_m"], df["y_m"] = X / gain, Y / gain
        if rec.shape(f"{group}/frame_rotor_angle") is not None:
            phi = np.asarray(rec.dataset(f"{group}/frame_rotor_angle"), float)
            if len(phi) == len(df):
                df["rotor_angle_rad"] = phi               # at the start of each exposure
        if float(st.get("misalignment", 0.0)):
            df.attrs["note"] = "the beam's misalignment circle is in x_m, y_m (a 1X term)"
    df["screen"] = group.split("/", 1)[1]
    df["plane"] = str(attrs.get("plane", ""))
    if "axial_position_m" in attrs:
        df["axial_position_m"] = float(attrs["axial_position_m"])


def _recording_of(source):
    """The recording behind a frame source ``FILE.h5[:dataset]``, or None."""
    from stand.recording.hdf5 import RecordingError, read_recording

    src = str(source).split(":")[0]
    if not src.lower().endswith((".h5", ".hdf5")):
        return None
    try:
        return read_recording(src)
    except (RecordingError, OSError):
        return None


def calibration_image(path) -> np.ndarray:
    """The ring image: an image file, or a recording's ``instruments/screen/calibration_image``."""
    import cv2

    from vision.io import VisionError, read_image

    if str(path).lower().endswith((".h5", ".hdf5")):
        rec = _recording_of(path)
        if rec is None or rec.shape(f"{SCREEN}/calibration_image") is None:
            raise VisionError(f"--calibration {str(path)!r}: not a recording with "
                              f"{SCREEN}/calibration_image")
        return np.asarray(rec.dataset(f"{SCREEN}/calibration_image"))
    return read_image(path, cv2.IMREAD_GRAYSCALE)


def _is_file(text) -> bool:
    """``text`` names an existing file (False for values that cannot be paths)."""
    try:
        return Path(str(text)).is_file()
    except (OSError, ValueError):
        return False


def read_ring_file(path) -> dict:
    """The ``key = value`` lines of a ring file (``stand video`` writes ``NAME_rings.txt``;
    ``#`` before a key is allowed): ``ring_radii_m`` [m, comma-separated] -> array, the
    other values as floats when they are numbers, else strings."""
    out = {}
    try:
        text = Path(path).read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise ValueError(f"--ring-radii {str(path)!r}: cannot read the file ({exc})") from None
    for line in text.splitlines():
        key, sep, value = line.lstrip("#").partition("=")
        if not sep:
            continue
        key, value = key.strip(), value.strip()
        if key == "ring_radii_m":
            try:
                out[key] = np.array([float(v) for v in value.split(",")])
            except ValueError:
                raise ValueError(f"--ring-radii {str(path)!r}: ring_radii_m = {value!r} is not a "
                                 "comma-separated list of radii in m") from None
        else:
            try:
                out[key] = float(value)
            except ValueError:
                out[key] = value
    if "ring_radii_m" not in out:
        raise ValueError(f"--ring-radii {str(path)!r}: no 'ring_radii_m = R1,R2,...' line (m)")
    return out


def ring_radii_of(source, ring_radii: Optional[str] = None, group: str = SCREEN) -> np.ndarray:
    """Ring radii [m]: ``"R1,R2,..."`` as given, a ring file (:func:`read_ring_file`), else
    those stored in the source recording."""
    if ring_radii:
        if _is_file(ring_radii):
            return read_ring_file(ring_radii)["ring_radii_m"]
        try:
            return np.array([float(v) for v in str(ring_radii).split(",")])
        except ValueError:
            raise ValueError(f"--ring-radii = {ring_radii!r}: comma-separated radii in m, or a "
                             "ring file with a 'ring_radii_m = ...' line") from None
    rec = _recording_of(source)
    if rec is None or rec.shape(f"{group}/ring_radius") is None:
        raise ValueError("--calibration needs the rings' radii: give --ring-radii (m, comma-separated, "
                         f"or a ring file) or track a recording that stores {group}/ring_radius")
    return np.asarray(rec.dataset(f"{group}/ring_radius"), float)


def _screen_meta(source, group=SCREEN):
    """(optical gain, exposure [s], frame rotor angles [rad] or None, settings) of a
    recording's screen."""
    import json

    rec = _recording_of(source)
    if rec is None or rec.shape(f"{group}/frames") is None:
        return None, 0.0, None, {}
    try:
        settings = json.loads(rec.dataset_attrs(group).get("settings", "{}"))
    except (TypeError, ValueError):
        settings = {}
    phi = (np.asarray(rec.dataset(f"{group}/frame_rotor_angle"))
           if rec.shape(f"{group}/frame_rotor_angle") is not None else None)
    return float(settings.get("gain", 1.0)), float(settings.get("exposure", 0.0)), phi, settings


def _shaft_columns(df, X, Y, gain, exposure, phi, line_time=0.0) -> None:
    """Columns that ``stand analyze`` reads from a track: ``t_s`` (mid-exposure of the spot's row
    with a rolling shutter's ``line_time`` [s]), ``x_m``, ``y_m`` (shaft displacement = screen
    displacement / optical gain), ``rotor_angle_rad`` (the recording's per frame)."""
    if gain is None:
        return
    if "time" in df:
        df["t_s"] = df["time"] + 0.5 * (exposure or 0.0) + line_time * df["v_px"].fillna(0.0)   # the row's
    df["x_m"], df["y_m"] = X / gain, Y / gain
    if phi is not None and len(phi) == len(df):
        df["rotor_angle_rad"] = phi                                # at the start of each exposure


def parse_roi(roi) -> Optional[tuple]:
    """``"x,y,w,h"`` (or a 4-sequence) [px] -> (x, y, w, h) integers; None stays None.

    Raises
    ------
    ValueError
        Not four integers, x or y < 0, w or h < 8 (one line naming ``--roi``).
    """
    if roi is None:
        return None
    parts = str(roi).replace(" ", "").strip("()[]").split(",") if isinstance(roi, str) else list(roi)
    try:
        vals = tuple(int(str(v)) for v in parts)
    except ValueError:
        vals = ()
    if len(vals) != 4:
        raise ValueError(f"--roi = {roi!r}: expected x,y,w,h (px, four integers: left column, "
                         "top row, width, height)")
    x, y, w, h = vals
    if x < 0 or y < 0 or w < 8 or h < 8:
        raise ValueError(f"--roi = {roi!r}: x and y must be >= 0 and w, h >= 8 (px)")
    return vals


def _cropped(frames, roi):
    """The frames cut to the ROI (x, y, w, h) [px]; it must lie inside them."""
    x, y, w, h = roi
    for rec in frames:
        H, W = rec.image.shape[:2]
        if x + w > W or y + h > H:
            raise ValueError(f"--roi = {x},{y},{w},{h}: reaches outside the {W} x {H} frame (px)")
        yield rec._replace(image=rec.image[y:y + h, x:x + w])


def _full_scale(img) -> float:
    """Full scale [DN] of a frame: 255 for 8 bits, else the smallest 2^b - 1 (b = 10, 12, 14,
    16) at or above its maximum."""
    if img.dtype == np.uint8:
        return 255.0
    top = float(np.max(img))
    for bits in (10, 12, 14, 16):
        if top <= (1 << bits) - 1:
            return float((1 << bits) - 1)
    return top


def _background_image(source, background):
    """``(image, description)``: the per-pixel median of frames spread over the source
    (``"median"`` or ``"median:N"``) or a dark-frame image file."""
    from vision.background import MEDIAN_FRAMES, median_background
    from vision.io import VisionError, iter_frames, read_image

    text = str(background)
    if text == "median" or text.startswith("median:"):
        count = MEDIAN_FRAMES
        if ":" in text:
            try:
                count = int(text.split(":", 1)[1])
            except ValueError:
                count = 0
            if count < 3:
                raise ValueError(f"--background = {text!r}: median:N with N >= 3 frames")
        img = median_background((r.image for r in iter_frames(source)), count)
        return img, f"median of {count} frames spread over the source"
    if not _is_file(text):
        raise ValueError(f"--background = {text!r}: 'median' (per-pixel median of frames), "
                         "'median:N', or a dark-frame image file")
    import cv2

    try:
        img = read_image(text, cv2.IMREAD_GRAYSCALE)
    except VisionError as exc:
        raise ValueError(f"--background: {exc}") from None
    return img.astype(np.float32), f"dark frame {Path(text).name}"


def _subtracted(frames, offsets, sat: float):
    """Frames minus the background's variation ``offsets``, clipped pixels kept at full
    scale ``sat`` (:func:`vision.background.subtract_offsets`)."""
    from vision.background import subtract_offsets
    from vision.spot import CENSOR_MARGIN

    margin = round(CENSOR_MARGIN * sat)
    for rec in frames:
        yield rec._replace(image=subtract_offsets(rec.image, offsets, sat, margin))


def _setup(source, group, ring_radii, optical_gain, exposure, capacity_gmm):
    """What is known of the setup: ``(optical gain or None, exposure [s] or None, frame rotor
    angles or None, capacity [g mm] or None)`` -- the options first, then a ring file
    (``--ring-radii FILE``: its ``optical_gain``, ``exposure_s``, ``capacity_gmm``), then
    the source recording's camera."""
    gain, expo, phi, settings = _screen_meta(str(source).split(":")[0], group)
    if gain is None:
        expo = None
    if ring_radii and _is_file(ring_radii):
        ring = read_ring_file(ring_radii)
        num = lambda k: ring[k] if isinstance(ring.get(k), float) else None  # noqa: E731
        gain = num("optical_gain") if num("optical_gain") is not None else gain
        expo = num("exposure_s") if num("exposure_s") is not None else expo
        if capacity_gmm is None:
            capacity_gmm = num("capacity_gmm")
    if optical_gain is not None:
        gain = float(optical_gain)
        if not gain > 0:
            raise ValueError(f"--optical-gain = {optical_gain}: must be > 0")
    if exposure is not None:
        expo = float(exposure)
        if not (math.isfinite(expo) and expo >= 0):
            raise ValueError(f"--exposure = {exposure}: must be >= 0 (s)")
    return gain, expo, phi, capacity_gmm, declared_keys(settings)   # the recorded camera's


def track_frames(source, *, calibration=None, ring_radii=None, gain=None, threshold=None,
                 trace: bool = False, spot_sigma=None, capacity_gmm=None, optical_gain=None,
                 progress: bool = False, screen=None, roi=None, background=None, exposure=None):
    """Track the laser spot (or, with ``trace``, the circle it draws) in every frame.

    Parameters
    ----------
    source : str
        ``RUN.h5[:dataset]``, a video file (mp4, avi, mov, ...), an image folder or a glob
        (:func:`vision.io.iter_frames`).
    calibration : str, optional
        Ring image, or a recording holding one: adds ``x_mm``, ``y_mm`` (screen) and, for spots,
        ``t_s``, ``x_m``, ``y_m`` (shaft) columns.
    ring_radii : str, optional
        ``"R1,R2,..."`` [m], or a ring file of ``key = value`` lines (``stand video`` writes
        ``NAME_rings.txt``): ``ring_radii_m`` and, used when not given otherwise,
        ``optical_gain``, ``exposure_s``, ``capacity_gmm``; default: the recording's radii.
    gain : float, optional
        Camera gain [electrons/DN] for the uncertainty.
    threshold : float, optional
        Smallest spot amplitude [DN above background].
    trace : bool
        Long exposures: fit the circle (centre, radius) instead of the spot.
    spot_sigma : float, optional
        With ``trace``: the still spot's sigma [px].
    capacity_gmm : float, optional
        The balancer's capacity S [g mm] (with ``calibration``): in the preamble
        (``stand analyze`` reads the ring zones i S/16 from it); with ``trace`` also
        ``zone``, ``unbalance_gmm`` and, for unresolved circles (only a bound),
        ``unbalance_max_gmm`` columns (:mod:`stand.analysis.trace_reading`).
    optical_gain : float, optional
        Spot displacement / shaft displacement (default: the ring file's, the recording's).
    screen : str, optional
        A recording's named screen (``[instruments.screen.<name>]``: ``"front"`` or
        ``"screen.front"``): its frames, rings and settings.  Without ``calibration`` the
        spot goes through the recorded camera geometry to ``x_m``, ``y_m`` (the point
        the screen shows, e.g. the axis point at its axial position), with ``t_s``,
        ``rotor_angle_rad``, ``screen``, ``plane``, ``axial_position_m`` -- the input of
        ``stand analyze --tracks`` (two-plane balancing).
    roi : str or (x, y, w, h), optional
        Search only this rectangle [px] of every frame (:func:`parse_roi`); the centres
        stay in the whole frame's pixels.
    background : str, optional
        ``"median"`` (``"median:N"``): subtract the per-pixel median of N (25) frames
        spread over the source; or a dark-frame image file
        (:mod:`vision.background`).
    exposure : float, optional
        Exposure [s] (default: the ring file's, the recording's): ``t_s`` is mid-exposure.

    Returns
    -------
    pandas.DataFrame
        One row per frame (:func:`vision.spot.track` / :func:`vision.trace.track_traces`
        columns plus the calibrated ones); ``df.attrs["preamble"]``: the ``key -> value``
        lines :func:`write_track_csv` writes before the table (:data:`TRACK_PREAMBLE`).
    """
    from vision.calibration import detect_rings, fit_homography, px_to_m
    from vision.camera_artefacts import declared_camera, dropped_frames, stuck_pixels_repaired
    from vision.io import iter_frames
    from vision.spot import track
    from vision.trace import track_traces

    if capacity_gmm is not None and not (capacity_gmm > 0):
        raise ValueError(f"--capacity = {capacity_gmm}: must be > 0 (g mm)")
    if capacity_gmm is not None and not calibration:
        raise ValueError("--capacity needs --calibration (the rings)")
    roi = parse_roi(roi)
    rec = group = None
    if screen is not None:
        source, rec, group = _named_screen(source, screen)
    elif str(source).lower().endswith((".h5", ".hdf5")):    # the recording's own screen
        from stand.recording.read import screen_group_of

        screen_group_of(source)         # only named screens: which to add, by name
    og, expo, phi, capacity_gmm, keys = _setup(source, group or SCREEN, ring_radii, optical_gain,
                                               exposure, capacity_gmm)
    pre = {"source": str(source)}
    keys.update(read_ring_file(ring_radii) if ring_radii and _is_file(ring_radii) else {})
    lens, quality = declared_camera(keys, calibration_image(calibration).shape   # lens, JPEG
                                    if calibration and "lens_k1" in keys else (1, 1))
    if group is not None:
        pre["screen"] = group.split("/", 1)[1]
    frames, stuck = stuck_pixels_repaired(iter_frames(source, progress=progress))   # first
    pre.update({"stuck_pixels": f"{stuck} (each replaced by its 3 x 3 neighbours' median)"} if stuck else {})
    sat = offsets = None
    if background is not None:
        bg, pre["background"] = _background_image(source, background)
        first = next(iter(iter_frames(source))).image
        if bg.shape != first.shape:
            raise ValueError(f"background: size {bg.shape[1]}x{bg.shape[0]} (W x H) differs from "
                             f"the frames' {first.shape[1]}x{first.shape[0]}")
        from vision.background import background_offsets

        offsets = background_offsets(bg)
        sat = _full_scale(first)      # the subtracted frames are float: the source's full scale
    if roi is not None:               # cut first: the frames and the offsets (once)
        frames = _cropped(frames, roi)
        if offsets is not None:
            x, y, w, h = roi
            offsets = offsets[y:y + h, x:x + w]
        pre["roi_px"] = ",".join(str(v) for v in roi)
    if offsets is not None:
        frames = _subtracted(frames, offsets, sat)
    if trace:
        df = track_traces(frames, gain=gain, threshold=threshold, spot_sigma_px=spot_sigma)
    else:
        df = track(frames, gain=gain, threshold=threshold, saturation=sat, jpeg_quality=quality)
    if roi is not None and len(df):
        df["u_px"] += roi[0]
        df["v_px"] += roi[1]
    if og is not None:
        pre["optical_gain"] = repr(og)
    if expo is not None:
        pre["exposure_s"] = repr(expo)
    df.attrs["preamble"] = pre
    if "time" in df and (drops := dropped_frames(df["time"].to_numpy()))["count"]:
        pre["dropped_frames"] = f"{drops['count']} (after frames {drops['after'].tolist()})"
    if not calibration:
        if rec is not None and not trace and len(df):
            _screen_columns(df, rec, group, optical_gain)
        return df
    radii = ring_radii_of(source, ring_radii, group or SCREEN)
    pre["ring_radii_m"] = ",".join(repr(float(r)) for r in radii)
    if capacity_gmm is not None:
        pre["capacity_gmm"] = repr(float(capacity_gmm))
    cal = fit_homography(detect_rings(calibration_image(calibration)), radii, lens=lens)
    X, Y = (np.asarray(a) for a in px_to_m(df["u_px"].to_numpy(), df["v_px"].to_numpy(), cal))
    df["x_mm"], df["y_mm"] = X * 1e3, Y * 1e3
    df["scale_mm_per_px"] = cal.scale * 1e3
    # the ring scale and its uncertainty: systematic, common to every frame (stand analyze
    # adds it to the circle radius's std)
    pre["scale_mm_per_px"] = repr(float(cal.scale) * 1e3)
    pre["scale_std_mm_per_px"] = repr(float(cal.scale_std) * 1e3)
    if not trace:
        _shaft_columns(df, X, Y, og, expo, phi, float(keys.get("line_time") or 0.0))
        if rec is not None:
            df["screen"] = group.split("/", 1)[1]
        return df
    # the circle's radius on the screen (the mean scale around the circle); an unresolved
    # circle gives only an upper bound (radius_max_mm, unbalance_max_gmm)
    from stand.analysis.trace_reading import trace_ring_columns

    trace_ring_columns(df, cal.scale, cal.scale_std, radii, capacity_gmm)
    return df


def write_track_csv(df, path) -> None:
    """Write a track table atomically: ``# key = value`` lines (``df.attrs["preamble"]``,
    in the order of :data:`TRACK_PREAMBLE`, then any other), then the CSV table
    (read it with ``pandas.read_csv(path, comment="#")``)."""
    from stand.io.atomic import atomic_path

    pre = dict(df.attrs.get("preamble") or {})
    keys = [k for k in TRACK_PREAMBLE if k in pre] + [k for k in pre if k not in TRACK_PREAMBLE]
    with atomic_path(path, suffix=".csv.tmp") as tmp:
        with open(tmp, "w", encoding="utf-8", newline="") as fh:
            for k in keys:
                fh.write(f"# {k} = {' '.join(str(pre[k]).split())}\n")
            df.to_csv(fh, index=False)


STROBE = instrument_key(STROBOSCOPE)


def _strobe_meta(source):
    """(settings, drawn weights, first flash time of each frame [s] or None) of a
    recording's stroboscope (``instruments/stroboscope`` attrs ``settings`` and
    ``weights``, JSON; ``flash_time``), or ``({}, [], None)`` for other sources; the
    drawn weights are ``[]`` for recordings written before that attribute existed."""
    import json

    rec = _recording_of(source)
    if rec is None or rec.shape(f"{STROBE}/frames") is None:
        return {}, [], None
    attrs = rec.dataset_attrs(STROBE)
    out = []
    for key, empty in (("settings", {}), ("weights", [])):
        try:
            v = json.loads(attrs.get(key, "null"))
        except (TypeError, ValueError):
            v = None
        out.append(v if isinstance(v, type(empty)) else empty)
    shape = rec.shape(f"{STROBE}/flash_time")
    times = None
    if shape is not None and len(shape) == 2 and shape[1] >= 1:
        times = np.asarray(rec.dataset(f"{STROBE}/flash_time"), float)[:, 0]
    return out[0], out[1], times


def _bob_columns(row, image, bobs, balls, pitch) -> None:
    """Read the bobs of the body weights ``bobs`` (drawn-weight dicts) into ``row``."""
    from vision.strobe_bodies import bob_angles

    b = bob_angles(image, n_bobs=len(bobs),
                   exclude_tracks_px=[(w["track_radius_px"], w["ball_radius_px"]) for w in balls])
    row.setdefault("mark_deg", math.degrees(b.mark_angle))
    for w, ang, sd, rad, rsd in zip(bobs, b.angles, b.sigma, b.radius_px, b.radius_sigma_px):
        nm = w["name"]
        row[f"{nm}_deg"] = math.degrees(float(ang))
        row[f"{nm}_std_deg"] = math.degrees(float(sd))
        if pitch:
            r = float(rad) * pitch
            row[f"{nm}_radius_mm"] = r * 1e3
            row[f"{nm}_radius_std_mm"] = float(rsd) * pitch * 1e3
            arm = float(w.get("arm_m", 0.0))
            if arm > 0:
                row[f"{nm}_tilt_deg"] = math.degrees(math.asin(min(1.0, r / arm)))


def strobe_angles(source, n_weights: Optional[int] = None):
    """The weights' angles from the mark [deg] in each stroboscope frame (:func:`vision.strobe.weight_angles`).

    ``source``: a recording (default dataset ``instruments/stroboscope/frames``), a video or images.
    Returns a DataFrame: ``frame``, ``time`` [s] (a recording's frames: the first flash of
    each frame), ``ok``, ``images``, ``mark_deg``,
    ``weight<j>_deg``, ``weight<j>_std_deg`` (a ``note`` where a frame is not read).

    Body weights drawn as a bob on a rod (two-axis pendulums, coupled pairs, dampers;
    known from the recording's ``instruments/stroboscope`` attrs ``weights``) are read
    as blobs (:func:`vision.strobe_bodies.bob_angles`): columns ``<name>_deg`` (the bob's
    direction from the rotor centre, relative to the mark, i.e. the body's centre-of-mass
    azimuth), ``<name>_std_deg``, ``<name>_radius_mm`` (its apparent radial offset, with
    the recording's ``pixel_pitch``), ``<name>_radius_std_mm`` and ``<name>_tilt_deg``
    (``asin(radius / arm)``, folded to [0, 90] deg).  Several bobs are named in the order
    of their angles.  Liquids' crescents are not read.  Balls are read as before, on the
    track radius the attrs give when the frames also hold bobs.
    """
    import pandas as pd

    from vision.io import VisionError, iter_frames
    from vision.strobe import reference_mark, weight_angles

    src = source if ":" in str(source) or not str(source).endswith(".h5") \
        else (source, f"{STROBE}/frames")
    settings, drawn, flash_t = _strobe_meta(source)
    own = ":" not in str(source)          # the recording's own frames: their flash times
    bobs = [w for w in drawn if w.get("drawn") == "pendulum" and "arm_px" in w]
    balls = [w for w in drawn if "track_radius_px" in w]
    pitch = float(settings.get("pixel_pitch", 0.0) or 0.0)
    rows = []
    for rec in iter_frames(src):
        t = rec.time
        if own and flash_t is not None and not (t == t) and 0 <= rec.index < flash_t.size:
            t = float(flash_t[rec.index])        # the frame's first flash
        row = {"frame": rec.index, "time": t, "ok": True}
        try:
            if drawn and not bobs and not balls:     # liquids only: their crescents are not read
                mark, _ = reference_mark(rec.image)
                row.update({"mark_deg": math.degrees(mark),
                            "note": "liquid crescents are not read; mark only"})
            elif not bobs or balls:
                kw = {}
                if bobs:   # the bobs would confuse the track's search: the drawn track
                    kw = {"track_radius_px": balls[0]["track_radius_px"],
                          "ball_radius_px": balls[0]["ball_radius_px"]}
                a = weight_angles(rec.image, n_weights=n_weights, **kw)
                row.update({"images": a.n_images, "mark_deg": math.degrees(a.mark_angle)})
                for j, (ang, sd) in enumerate(zip(a.angles, a.sigma), start=1):
                    row[f"weight{j}_deg"] = math.degrees(float(ang))
                    row[f"weight{j}_std_deg"] = math.degrees(float(sd))
            if bobs:
                _bob_columns(row, rec.image, bobs, balls, pitch)
        except VisionError as exc:
            rows.append({"frame": rec.index, "time": t, "ok": False, "note": str(exc)})
            continue
        rows.append(row)
    return pd.DataFrame(rows)
