"""The API of the commands on the instruments' images (``stand snapshot``, ``track``, ``video``,
``strobe``): one frame as PNG, tracks as CSV, the screen as a lab video."""
from __future__ import annotations

__all__ = ["snapshot", "write_track", "spot_fit_compiles", "video"]

#: the instrument a snapshot is of -> (its dataset in the recording, its scene table)
_IMAGES = {"screen": (("screen", "frames"), "screen"),
           "strobe": (("stroboscope", "frames"), "stroboscope"),
           "rings": (("screen", "calibration_image"), "screen")}


def snapshot(recording, output, *, instrument: str = "screen", frame: int = 0,
             screen=None) -> dict:
    """Write one recorded instrument frame as PNG.

    Parameters
    ----------
    recording : str or os.PathLike
        An HDF5 recording written by ``stand run``.
    output : str or os.PathLike
        The PNG to write (atomically).
    instrument : {"screen", "strobe", "rings"}
        The screen camera's frames, the stroboscope's, or the screen's calibration-ring image.
    frame : int
        Frame index (negative: from the end); ignored for the single ring image.
    screen : str, optional
        A named screen (``[instruments.screen.<name>]``: ``"front"``) for ``"screen"`` and
        ``"rings"``, as ``stand track --screen`` / ``stand video --screen``
        (:func:`stand.recording.read.screen_group_of`).

    Returns
    -------
    dict
        ``instrument``, ``frame``, ``frames`` (how many the recording holds), ``time_s``
        (start of the frame's exposure [s], None when not recorded), ``output``, ``warnings``
        (sentences; a screen frame whose brightest point is below the spot threshold of
        ``stand track`` says that the spot is off the screen).

    Raises
    ------
    stand.errors.NotApplicable
        The recording holds no images of that instrument.
    ValueError
        ``frame`` outside the recording's frames; ``screen`` with the stroboscope, a named
        screen the recording does not hold, or none for a recording with only named screens
        (the message names them).
    """
    import cv2

    from stand.api import read
    from stand.errors import NotApplicable
    from stand.io.atomic import atomic_path
    from stand.recording.layout import instrument_key, truth_key
    from stand.recording.read import screen_group_of

    parts, table = _IMAGES[instrument]
    if table == "screen":
        group = screen_group_of(recording, screen)
        name, table = f"{group}/{parts[1]}", group.split("/", 1)[1]
    elif screen is not None:
        raise ValueError(f"--screen {screen}: a screen's option; the {instrument} images are "
                         f"{instrument_key(*parts)}")
    else:
        name = instrument_key(*parts)
    rec = read(recording)
    shape = rec.shape(name)
    if shape is None:
        why = (f"its scene had no [instruments.{table}]" if not rec.members(name.rpartition("/")[0])
               else "its screen has no calibration rings (a scene without a balancing capacity "
                    "or speed has none)")
        raise NotApplicable(f"{recording} holds no {instrument} images (dataset {name!r}): {why}")
    doc = {"instrument": instrument, "frame": frame, "frames": 1, "time_s": None,
           "output": str(output), "warnings": []}
    if len(shape) == 3:
        if not -shape[0] <= frame < shape[0]:
            raise ValueError(f"frame = {frame}: the recording has {shape[0]} {instrument} frames "
                             f"(0 .. {shape[0] - 1}, or negative from the end)")
        img = rec.dataset(name, frame)
        doc["frames"] = int(shape[0])
        times = name.rpartition("/")[0] + "/frame_time"
        if rec.shape(times) is not None:
            doc["time_s"] = float(rec.dataset(times, frame % shape[0]))
    else:
        img = rec.dataset(name)
    if instrument == "screen":
        inside = None       # the simulator's truth: the spot's path within the image
        in_frame = truth_key(table, "in_frame")
        if len(shape) == 3 and rec.shape(in_frame) is not None:
            inside = bool(rec.dataset(in_frame, frame % shape[0]))
        doc["warnings"] += _spot_warnings(img, frame, doc["time_s"], inside)
    with atomic_path(output, suffix=".png") as tmp:
        if not cv2.imwrite(tmp, img):
            raise ValueError(f"could not encode {output}")
    return doc


def _spot_warnings(img, frame: int, time_s, inside=None) -> list:
    """A sentence when the screen frame shows no spot (:func:`vision.spot.locate`'s criterion,
    as ``stand track``) or, by the simulator's truth (``inside``), the spot's path leaves the
    image during the exposure."""
    import math

    from vision.spot import locate

    spot = locate(img, refine="centroid")
    at = f" (t = {time_s:.4g} s)" if time_s is not None else ""
    off = ("the spot is off the screen during the exposure (simulator truth)" if inside is False
           else "the spot is off the screen (the shaft's whirl is larger than the screen "
                "shows) or the laser is dark")
    if "missing" in spot.flags:
        peak = spot.peak if math.isfinite(spot.peak) else 0.0
        thr = max(10 * spot.noise, 5.0) if math.isfinite(spot.noise) else 5.0
        return [f"frame {frame}{at} shows no spot: its brightest point is {peak:.0f} DN above "
                f"the background, below the spot threshold of {thr:.0f} DN; {off}"]
    if inside is False:
        return [f"frame {frame}{at}: the spot's path runs past the image border during the "
                "exposure (simulator truth): what the frame shows of it is cut"]
    return []


def write_track(track, path) -> None:
    """Write a :func:`stand.track` result as CSV, atomically: its ``# key = value`` preamble
    (calibration, units), then one row per frame (``pandas.read_csv(path, comment="#")``)."""
    from stand.analysis.tracking import write_track_csv

    write_track_csv(track.frame, path)


def spot_fit_compiles() -> bool:
    """Whether the first blurred-spot fit of this process will compile (about 10 s; ``stand
    warmup`` does it ahead)."""
    from vision.blur import compile_needed

    return compile_needed()


def video(recording, output, *, screen=None, qp: int = 10, force: bool = False) -> dict:
    """A recording's screen frames as a lab video (``NAME.mp4``: H.264; ``.mkv`` / ``.avi``:
    FFV1, lossless) with ``NAME_truth.csv``, ``NAME_rings.png`` and ``NAME_rings.txt`` beside it
    (:func:`stand.reports.video.write_screen_video`).  An existing video is replaced only with
    ``force`` (it may be a lab's own recording).  ``qp``: the H.264 quantiser 0..51.

    Returns the document: ``frames``, ``frame_rate_hz`` [Hz], ``codec``, ``bytes``, and the
    paths written.  Raises :class:`stand.errors.NotApplicable` for a recording without a screen."""
    from stand.io.guard import check_outputs
    from stand.reports.video import sidecar_paths, write_screen_video

    side = sidecar_paths(output)
    check_outputs([recording], [(side["video"], side["video"].suffix.lstrip(".").lower()),
                                (side["truth"], "csv"), (side["rings_png"], "png"),
                                (side["rings_txt"], "csv")], force=force)
    if side["video"].exists() and not force:
        raise ValueError(f"output {output!r} exists: a video may be a recording nothing "
                         "can replace; give --force to overwrite it, or choose another output")
    return write_screen_video(recording, output, screen=screen, qp=qp)
