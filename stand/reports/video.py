"""A recording's screen camera written as a lab video, with its truth beside it.

:func:`write_screen_video` turns the frames of ``instruments/screen`` (or a named
screen) of a recording into the kind of file a lab brings: a video, plus what
the lab knows about its calibration rings -- and, kept apart, the truth to score
a tracker with.  For ``-o NAME.mp4`` it writes

* ``NAME.mp4``: H.264 (8-bit luma, constant quantiser ``qp``, x264 through PyAV;
  ``pip install 'autobalancer-stand[video]'``).  ``.mkv`` / ``.avi``: FFV1,
  lossless, through OpenCV (no extra dependency; about 4x larger).  Either is
  read back by OpenCV's own FFmpeg (``cv2.VideoCapture``), i.e. by ``stand
  track`` on a clean install;
* ``NAME_rings.png``: the calibration-ring image (``instruments/screen/calibration_image``);
* ``NAME_rings.txt``: ``key = value`` lines: ``ring_radii_m`` (the rings' screen
  radii, zones i S/16), ``capacity_gmm`` (S), ``optical_gain``, ``exposure_s``,
  ``frame_rate_hz`` -- what the lab knows of its rings and camera
  (``stand track --ring-radii NAME_rings.txt`` reads the radii);
* ``NAME_truth.csv``: ``# key = value`` lines, then one row per frame: ``frame``,
  ``time_s`` (the exposure's start in the video's clock, as ``cv2`` reports it),
  ``run_time_s`` (the same in the run's clock), ``u_px``, ``v_px`` (the
  exposure-averaged spot centre, ``truth/<screen>/centre_px``), ``in_frame``,
  ``clipped_px`` (pixels at full scale in the frame as rendered), ``blur_px``
  (length of the spot's path during the exposure; the lens's distortion left out),
  ``brightness`` (the lamps' flicker), ``frame_index`` (before frame drops).
  A camera with a lens distortion or JPEG declares them in ``NAME_rings.txt``
  (``lens_k1``, ``lens_k2``, ``lens_focal_px``, ``jpeg_quality``), as a lab knows its camera.

Quantiser.  H.264 at ``qp`` = 10 (the default) keeps the spot's pixels within
~3 DN and the camera's noise in part: 4-5 MB for 500 frames of 256 x 256 px, and
the blurred-spot tracker within 0.01 px RMS of the truth (``tests/test_video_track.py``);
qp 12 halves the file but lets near-still spots "freeze" between frames (inter
prediction drops their sub-pixel motion: up to 0.13 px).  Rate-controlled modes
(x264's ``crf``) were worse at every size: their psycho-visual tuning rings round
the clipped core (30 DN at crf 6).

Every file is written atomically (:mod:`stand.io.atomic`).
"""
from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Optional

import numpy as np

__all__ = ["write_screen_video", "sidecar_paths", "DEFAULT_QP", "VIDEO_SUFFIXES"]

DEFAULT_QP = 10
VIDEO_SUFFIXES = (".mp4", ".mkv", ".avi")


def sidecar_paths(output) -> dict:
    """The files written beside ``output`` (``NAME.mp4`` -> ``NAME_truth.csv``,
    ``NAME_rings.png``, ``NAME_rings.txt``)."""
    out = Path(output)
    stem = out.with_suffix("")
    return {"video": out, "truth": Path(f"{stem}_truth.csv"), "rings_png": Path(f"{stem}_rings.png"),
            "rings_txt": Path(f"{stem}_rings.txt")}


def _encode_h264(frames, path: str, fps: float, qp: int) -> None:
    """H.264 in MP4 through PyAV: constant quantiser, x264 tuned for PSNR (no psycho-visual
    shaping), one thread (reproducible)."""
    try:
        import av
    except ImportError:
        raise ValueError("writing an .mp4 needs PyAV (H.264): pip install "
                         "'autobalancer-stand[video]'; or write a lossless .mkv / .avi (FFV1, "
                         "OpenCV only)") from None
    from fractions import Fraction

    from vision.compression import h264_options

    rate = Fraction(fps).limit_denominator(1000)
    with av.open(path, "w", format="mp4") as out:
        st = out.add_stream("libx264", rate=rate, options=h264_options(qp))
        st.codec_context.thread_count = 1
        first = True
        for img in frames:
            if first:
                st.height, st.width = img.shape
                st.pix_fmt = "yuv420p"
                first = False
            for pkt in st.encode(av.VideoFrame.from_ndarray(np.ascontiguousarray(img),
                                                            format="gray")):
                out.mux(pkt)
        for pkt in st.encode():
            out.mux(pkt)


def _encode_ffv1(frames, path: str, fps: float) -> None:
    """FFV1 (lossless) through OpenCV's FFmpeg, gray frames."""
    import cv2

    writer = None
    try:
        for img in frames:
            if writer is None:
                h, w = img.shape
                writer = cv2.VideoWriter(path, cv2.CAP_FFMPEG, cv2.VideoWriter_fourcc(*"FFV1"),
                                         float(fps), (w, h), [cv2.VIDEOWRITER_PROP_IS_COLOR, 0])
                if not writer.isOpened():
                    raise ValueError(f"{path}: OpenCV cannot write FFV1 video here")
            writer.write(np.ascontiguousarray(img))
    finally:
        if writer is not None:
            writer.release()


def _frames_8bit(rec, key: str, n: int, max_dn: int, clipped: np.ndarray):
    """The frames one by one as uint8 (deeper frames scaled to 8 bits, rounded); the count of
    each frame's pixels at full scale ``max_dn`` goes into ``clipped`` on the way (one read)."""
    for i in range(n):
        img = np.asarray(rec.dataset(key, i))
        clipped[i] = np.count_nonzero(img >= max_dn)
        if img.dtype != np.uint8:
            img = np.clip(np.floor(img.astype(np.float64) * (255.0 / max_dn) + 0.5), 0, 255
                          ).astype(np.uint8)
        yield img


def _blur_lengths(rec, group: str, settings: dict, exposure_times) -> Optional[np.ndarray]:
    """Length [px] of the spot's path in each exposure, from the run's shaft motion at the
    sub-sample times (cubic interpolation of the recorded samples); None when the screen's
    plane is not among the recorded planes."""
    from scipy.interpolate import CubicSpline

    plane = rec.dataset_attrs(group).get("plane") or rec.main_plane
    if plane not in rec.planes:
        return None
    xy = rec.planes[plane]
    t = np.asarray(rec.t, float)
    T = np.asarray(exposure_times, float)
    x = CubicSpline(t, xy[:, 0])(T)
    y = CubicSpline(t, xy[:, 1])(T)
    phi = CubicSpline(t, np.asarray(rec.rotor_angle, float))(T)
    g = float(settings.get("gain", 1.0))
    a = phi + float(settings.get("misalignment_phase", 0.0))
    mis = float(settings.get("misalignment", 0.0))
    X = g * x + mis * np.cos(a) + float(settings.get("offset_x", 0.0))
    Y = g * y + mis * np.sin(a) + float(settings.get("offset_y", 0.0))
    Hm = np.asarray(settings["homography"], float)
    w = Hm[2, 0] * X + Hm[2, 1] * Y + Hm[2, 2]
    u = (Hm[0, 0] * X + Hm[0, 1] * Y + Hm[0, 2]) / w
    v = (Hm[1, 0] * X + Hm[1, 1] * Y + Hm[1, 2]) / w
    return np.hypot(np.diff(u, axis=1), np.diff(v, axis=1)).sum(axis=1)


def _csv_text(meta: dict, df) -> str:
    head = "".join(f"# {k} = {v}\n" for k, v in meta.items())
    return head + df.to_csv(index=False, float_format="%.6f")


def write_screen_video(recording, output, *, screen: Optional[str] = None,
                       qp: int = DEFAULT_QP) -> dict:
    """Write a recording's screen frames as a video with its rings and truth beside it.

    Parameters
    ----------
    recording : str or os.PathLike
        HDF5 recording with an ``instruments/screen`` (or named screen) camera.
    output : str or os.PathLike
        ``NAME.mp4`` (H.264, needs PyAV) or ``NAME.mkv`` / ``NAME.avi`` (FFV1, lossless).
    screen : str, optional
        A named screen (``[instruments.screen.<name>]``).
    qp : int
        H.264 quantiser, 0 (lossless) ... 51; default 10 (module docstring).

    Returns
    -------
    dict
        ``frames``, ``frame_rate_hz``, the paths written (``video``, ``truth``,
        ``rings_png``, ``rings_txt``; the ring files only when the recording has rings),
        ``bytes`` (of the video), ``codec``.

    Raises
    ------
    ValueError
        Not a recording with that screen's frames, no ``screen`` for a recording with only
        named screens (they are named), an unknown video ending, qp out of
        range, PyAV missing for an .mp4 (one line naming the value).
    """
    import cv2
    import pandas as pd

    from stand.io.atomic import atomic_path, write_text
    from vision.camera_artefacts import declared_keys
    from stand.recording.hdf5 import read_recording
    from stand.recording.layout import INSTRUMENTS, TRUTH, truth_key
    from stand.recording.read import screen_group_of

    paths = sidecar_paths(output)
    suffix = paths["video"].suffix.lower()
    if suffix not in VIDEO_SUFFIXES:
        raise ValueError(f"-o {output}: a video ending {', '.join(VIDEO_SUFFIXES)} "
                         f"(.mp4: H.264; .mkv, .avi: FFV1, lossless)")
    if not (isinstance(qp, (int, np.integer)) and 0 <= int(qp) <= 51):
        raise ValueError(f"--qp = {qp!r}: an H.264 quantiser 0..51 (0 lossless; default {DEFAULT_QP})")
    rec = read_recording(recording)
    group = screen_group_of(recording, screen)     # a named screen, or which to name
    key = f"{group}/frames"
    shape = rec.shape(key)
    if shape is None or len(shape) != 3 or shape[0] == 0:
        from stand.errors import NotApplicable

        raise NotApplicable(f"{recording}: no screen frames {key} (a scene with "
                            f"[instruments.screen] writes them)")
    settings = json.loads(rec.dataset_attrs(group).get("settings", "{}") or "{}")
    fps = float(settings.get("frame_rate", 0.0))
    if not fps > 0:
        raise ValueError(f"{recording}: {group} has no frame_rate in its settings")
    max_dn = int(settings.get("max_dn", 255))
    n = int(shape[0])
    codec = "h264" if suffix == ".mp4" else "ffv1"
    with atomic_path(paths["video"], suffix=suffix) as tmp:
        clipped = np.zeros(n, int)
        frames = _frames_8bit(rec, key, n, max_dn, clipped)
        if codec == "h264":
            _encode_h264(frames, tmp, fps, int(qp))
        else:
            _encode_ffv1(frames, tmp, fps)
    written = {"video": str(paths["video"])}
    # what the lab knows of its rings and camera
    tname = group.replace(INSTRUMENTS, TRUTH, 1)
    exposure = float(settings.get("exposure", 0.0))
    meta = {"source": Path(str(recording)).name, "screen": group.split("/", 1)[1],
            "frame_rate_hz": repr(fps), "exposure_s": repr(exposure),
            "optical_gain": repr(float(settings.get("gain", 1.0))),
            "pixel_pitch_m": repr(float(settings.get("pixel_pitch", math.nan)))}
    if rec.shape(f"{group}/ring_radius") is not None and rec.shape(f"{group}/calibration_image"):
        radii = np.asarray(rec.dataset(f"{group}/ring_radius"), float)
        rings = dict(meta)
        rings["ring_radii_m"] = ",".join(repr(float(r)) for r in radii)
        if rec.shape(truth_key("capacity")) is not None:
            rings["capacity_gmm"] = repr(float(rec.dataset(truth_key("capacity"))) * 1e6)
        rings.update({k: repr(v) for k, v in declared_keys(settings).items()})   # lens, JPEG
        test = rec.dataset_attrs(group).get("ring_test_speed_rad_s")
        if test is not None:
            rings["ring_test_speed_rad_s"] = repr(float(test))
        write_text(paths["rings_txt"], "".join(f"{k} = {v}\n" for k, v in rings.items()))
        with atomic_path(paths["rings_png"], suffix=".png") as tmp:
            if not cv2.imwrite(tmp, np.asarray(rec.dataset(f"{group}/calibration_image"))):
                raise OSError(f"cannot write {paths['rings_png']}")
        written.update(rings_txt=str(paths["rings_txt"]), rings_png=str(paths["rings_png"]))
    # the truth, kept apart
    centre = np.asarray(rec.dataset(f"{tname}/centre_px"), float)[:n]
    inside = np.asarray(rec.dataset(f"{tname}/in_frame"), bool)[:n]
    start = np.asarray(rec.dataset(f"{group}/frame_time"), float)[:n]
    df = pd.DataFrame({"frame": np.arange(n), "time_s": np.arange(n) / fps, "run_time_s": start,
                       "u_px": centre[:, 0], "v_px": centre[:, 1], "in_frame": inside,
                       "clipped_px": clipped})
    for k in ("brightness", "frame_index"):          # flicker's gain, place before drops
        if rec.shape(f"{tname}/{k}") is not None:
            df[k] = np.asarray(rec.dataset(f"{tname}/{k}"))[:n]
    if rec.shape(f"{tname}/exposure_time") is not None:
        blur = _blur_lengths(rec, group, settings, rec.dataset(f"{tname}/exposure_time")[:n])
        if blur is not None:
            df["blur_px"] = blur
    truth_meta = dict(meta, video=paths["video"].name, codec=codec,
                      qp=str(int(qp)) if codec == "h264" else "lossless",
                      sigma_px=repr(float(settings.get("sigma_px", [math.nan])[0])),
                      max_dn=str(max_dn), peak_dn=repr(float(settings.get("peak", math.nan))),
                      centre="exposure-averaged spot centre, truth/" + tname.split("/", 1)[1]
                      + "/centre_px (u = column, v = row, pixel centres at integers)")
    write_text(paths["truth"], _csv_text(truth_meta, df))
    written["truth"] = str(paths["truth"])
    return {"frames": n, "frame_rate_hz": fps, "codec": codec,
            "bytes": paths["video"].stat().st_size, **written}
