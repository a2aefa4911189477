"""A real camera's imperfections, to draw and to undo: lens distortion, JPEG compression,
lamp flicker, hot pixels, frame drops.

One idea: what a lab camera does to the ideal image of the screen.  The stand draws them
(``[instruments.screen]`` keys, docs/scene.md) through these functions, and the analysis
undoes or allows for them with the same ones, so the two sides cannot disagree on a model.

* Lens distortion: the radial Brown model of OpenCV (k1, k2; no tangential terms), about
  the principal point ``centre_px`` with the focal length ``focal_px`` [px]:
  x = (u - c_u) / f, r^2 = x^2 + y^2, x_d = x (1 + k1 r^2 + k2 r^4) -- so that
  ``cv2.undistortPoints`` inverts it (:func:`undistort_points`).
* JPEG at a quality 1..100 (``cv2.imencode`` / ``cv2.imdecode``, 8-bit frames).
* Flicker: the room lamps' light modulated at twice the mains frequency; a frame's
  brightness gain ``1 + depth cos(2 pi 2 f_mains t_mid + phase)`` at its mid-exposure time.
* Auto-gain: the camera's exposure/gain follows the frames' mean brightness with a time
  constant (:func:`auto_gain`), chasing the flicker a frame late.
* Hot pixels: a fixed set of pixels (the same in every frame) reading full scale;
  :func:`hot_pixel_map` finds them in the per-pixel median of frames
  (:func:`vision.background.median_background`) and :func:`repair_hot_pixels` replaces
  them by their neighbours' median (else the tracker may take one for a dim spot).
* Frame drops: :func:`dropped_frames` finds them in the frames' timestamps.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["Lens", "distort_points", "undistort_points", "jpeg", "flicker_gain", "auto_gain", "hot_pixels",
           "sensor_artefacts", "hot_pixel_map", "repair_hot_pixels", "stuck_pixels_repaired", "dropped_frames",
           "declared_camera", "declared_keys"]


@dataclass(frozen=True)
class Lens:
    """Radial lens distortion (OpenCV's k1, k2) of a camera.

    Attributes
    ----------
    k1, k2 : float
        Radial coefficients (1); k1 < 0 barrel, k1 > 0 pincushion.
    focal_px : float
        Focal length [px] that normalises the image radius (camera distance / pixel pitch).
    centre_px : (float, float)
        Principal point (u, v) [px]; the image centre ((W - 1)/2, (H - 1)/2) by convention.
    """

    k1: float
    k2: float
    focal_px: float
    centre_px: tuple

    @property
    def matrix(self) -> np.ndarray:
        """OpenCV's camera matrix K (3 x 3)."""
        f, (cu, cv) = self.focal_px, self.centre_px
        return np.array([[f, 0.0, cu], [0.0, f, cv], [0.0, 0.0, 1.0]])

    @property
    def coefficients(self) -> np.ndarray:
        """OpenCV's distortion vector (k1, k2, p1, p2) with no tangential terms."""
        return np.array([self.k1, self.k2, 0.0, 0.0])


def distort_points(u, v, lens: Lens):
    """Ideal (pinhole) pixel positions -> where the distorting lens puts them [px]."""
    u, v = np.asarray(u, float), np.asarray(v, float)
    (cu, cv), f = lens.centre_px, lens.focal_px
    x, y = (u - cu) / f, (v - cv) / f
    r2 = x * x + y * y
    g = 1.0 + lens.k1 * r2 + lens.k2 * r2 * r2
    return cu + f * x * g, cv + f * y * g


def undistort_points(u, v, lens: Lens):
    """Distorted pixel positions -> ideal (pinhole) ones [px] (``cv2.undistortPoints``,
    iterated to 1e-10 of the normalised radius)."""
    import cv2   # (imported when used: a stand run without these artefacts does not need it)

    u, v = np.broadcast_arrays(np.asarray(u, float), np.asarray(v, float))
    pts = np.stack([u.ravel(), v.ravel()], axis=-1).reshape(-1, 1, 2)
    if pts.shape[0] == 0:
        return u.copy(), v.copy()
    crit = (cv2.TERM_CRITERIA_COUNT | cv2.TERM_CRITERIA_EPS, 100, 1e-12)
    K = lens.matrix
    out = cv2.undistortPoints(pts, K, lens.coefficients, None, None, K, crit).reshape(-1, 2)
    return out[:, 0].reshape(u.shape)[()], out[:, 1].reshape(u.shape)[()]


def jpeg(image, quality: int) -> np.ndarray:
    """An 8-bit image through JPEG at ``quality`` (1..100) and back."""
    import cv2

    img = np.asarray(image)
    if img.dtype != np.uint8:
        raise ValueError(f"jpeg: an 8-bit image is needed, got {img.dtype}")
    ok, buf = cv2.imencode(".jpg", img, [cv2.IMWRITE_JPEG_QUALITY, int(quality)])
    if not ok:
        raise ValueError(f"jpeg: OpenCV cannot encode at quality {quality!r}")
    return cv2.imdecode(buf, cv2.IMREAD_UNCHANGED)


def flicker_gain(t_mid, mains_hz: float, depth: float, phase: float = 0.0):
    """Brightness gain (1) of frames at mid-exposure times ``t_mid`` [s]: the lamps' light
    at twice the mains frequency ``mains_hz`` [Hz], modulation ``depth`` (0..1)."""
    return 1.0 + depth * np.cos(2.0 * math.pi * 2.0 * mains_hz * np.asarray(t_mid, float) + phase)


def auto_gain(light, frame_period: float, time_constant: float, set_point=None) -> np.ndarray:
    """The gain (1) an auto-exposure gives frames of relative scene ``light`` (1): it meters
    each frame's mean brightness (light times gain; the mean of a frame is proportional to
    its light) and moves its gain in the log domain toward its ``set_point`` (a brightness
    relative to light 1 at gain 1; default None: the first frame's), by
    ``1 - exp(-frame_period / time_constant)`` of the way per frame (``frame_period``,
    ``time_constant`` [s]; 0: no auto-gain, all ones).  The first frame has gain 1."""
    light = np.asarray(light, float)
    g = np.ones(light.size)
    if not time_constant > 0:
        return g
    alpha = 1.0 - math.exp(-frame_period / time_constant)
    ref = light[0] if set_point is None else float(set_point)
    for f in range(1, light.size):
        g[f] = g[f - 1] * (light[f - 1] * g[f - 1] / ref) ** -alpha
    return g


def hot_pixels(shape, count: int, seed: int) -> tuple:
    """(rows, cols) of ``count`` hot pixels of a sensor of ``shape`` (H, W), fixed by ``seed``
    (the same in every frame)."""
    H, W = shape
    idx = np.random.default_rng([int(seed), 0x407]).choice(H * W, size=int(count), replace=False)
    return np.unravel_index(np.sort(idx), (H, W))


def sensor_artefacts(frame, *, saturation=None, hot=None, jpeg_quality=None, full_scale=255):
    """``frame`` after the exposure, in place: clipped at ``saturation`` [DN] (a sensor that
    clips below the full scale), the ``hot`` pixels (rows, cols) at ``full_scale``, then
    JPEG at ``jpeg_quality``; each skipped when None."""
    if saturation is not None:
        np.minimum(frame, int(round(saturation)), out=frame)
    if hot is not None and len(hot[0]):
        frame[hot] = full_scale
    if jpeg_quality is not None:
        frame[...] = jpeg(frame, jpeg_quality)
    return frame


def hot_pixel_map(median, excess: float = 0.5) -> tuple:
    """(rows, cols) of the hot pixels of a per-pixel median of frames [DN]: pixels above
    their 3 x 3 neighbourhood's median by more than ``excess`` of the frame's range (a
    moving spot is not in the median; a hot pixel is in every frame)."""
    import cv2

    m = np.asarray(median, np.float32)
    span = float(m.max() - np.percentile(m, 50))
    return np.nonzero(m - cv2.medianBlur(m, 3) > excess * span) if span > 0 else (
        np.zeros(0, int), np.zeros(0, int))


def repair_hot_pixels(frame, hot) -> np.ndarray:
    """A copy of ``frame`` with the pixels ``hot`` (rows, cols) set to their 3 x 3
    neighbourhood's median."""
    import cv2

    f = np.array(frame)
    if len(hot[0]):
        f[hot] = cv2.medianBlur(f if f.dtype == np.uint8 else f.astype(np.float32), 3)[hot]
    return f


def stuck_pixels_repaired(frames, lookahead: int = 9):
    """``(frames, count)``: the frames (arrays or records with ``.image``) with their stuck
    pixels replaced by their 3 x 3 neighbourhood's median (:func:`repair_hot_pixels`), and how
    many there are.  A stuck pixel is constant over frames: the same value in each of the
    first ``lookahead`` frames (the read noise moves every live pixel), above its 3 x 3
    neighbourhood's median by half the frames' brightest above the median there (a moving
    spot is not held; a spot wider than a pixel is never a 3 x 3 outlier)."""
    import itertools

    it = iter(frames)
    head = list(itertools.islice(it, lookahead))
    hot = (np.zeros(0, int),) * 2
    if len(head) >= 3:
        import cv2

        stack = np.array([getattr(f, "image", f) for f in head])
        m = stack.min(axis=0).astype(np.float32)      # half the brightest's height, held
        hot = np.nonzero((m - cv2.medianBlur(m, 3) > 0.5 * (float(stack.max()) - np.median(m)))
                         & (np.ptp(stack, axis=0) == 0))
    if not len(hot[0]):
        return itertools.chain(head, it), 0
    fix = lambda f: (f._replace(image=repair_hot_pixels(f.image, hot)) if hasattr(f, "image")  # noqa: E731
                     else repair_hot_pixels(f, hot))
    return map(fix, itertools.chain(head, it)), int(len(hot[0]))


def dropped_frames(times, frame_rate: float | None = None, tol: float = 0.25) -> dict:
    """Frame drops in a sequence of frame timestamps [s].

    The frame period is ``1 / frame_rate`` [Hz] or, not given, the median interval; a gap of
    n periods (within ``tol`` of a period) after a frame means n - 1 frames dropped there.

    Returns
    -------
    dict
        ``count`` (frames dropped), ``after`` (indices of the frames followed by a gap),
        ``missing`` (the dropped frames' times [s]), ``period_s``.
    """
    t = np.asarray(times, float)
    t = t[np.isfinite(t)]
    if t.size < 3:
        return {"count": 0, "after": np.zeros(0, int), "missing": np.zeros(0), "period_s": math.nan}
    d = np.diff(t)
    T = 1.0 / float(frame_rate) if frame_rate else float(np.median(d))
    n = np.rint(d / T).astype(int)
    gap = (n >= 2) & (np.abs(d / T - n) < tol)
    after = np.flatnonzero(gap)
    missing = np.concatenate([t[i] + T * np.arange(1, n[i]) for i in after]) if after.size \
        else np.zeros(0)
    return {"count": int(np.sum(n[gap] - 1)), "after": after, "missing": missing, "period_s": T}


def declared_camera(keys: dict, shape) -> tuple:
    """``(lens or None, compression or None)`` that a lab declares for its camera in a ring
    file (``key = value``): ``lens_k1``, ``lens_k2`` (1), ``lens_focal_px`` [px] and
    optionally ``lens_centre_u_px``, ``lens_centre_v_px`` (default the centre of an image of
    ``shape`` (H, W)); ``jpeg_quality`` (1..100: the compression is that int) or ``h264_qp``
    (0..51: ``("h264", qp)``; :func:`vision.compression.compressed`).

    Raises
    ------
    ValueError
        A value out of range, or k1/k2 without the focal length (naming the key).
    """
    def num(key):
        v = keys.get(key)
        if v is None:
            return None
        try:
            return float(v)
        except (TypeError, ValueError):
            raise ValueError(f"{key} = {v!r}: not a number") from None

    q, qp = num("jpeg_quality"), num("h264_qp")
    if q is not None and not (q == int(q) and 1 <= q <= 100):
        raise ValueError(f"jpeg_quality = {q!r}: an integer 1..100")
    if qp is not None and not (qp == int(qp) and 0 <= qp <= 51):
        raise ValueError(f"h264_qp = {qp!r}: an integer 0..51")
    quality = ("h264", int(qp)) if qp is not None else None if q is None else int(q)
    k1, k2, f = num("lens_k1"), num("lens_k2"), num("lens_focal_px")
    if k1 is None and k2 is None:
        return None, quality
    if f is None or not f > 0:
        raise ValueError(f"lens_focal_px = {f!r}: the focal length [px] > 0 is needed with "
                         "lens_k1, lens_k2")
    H, W = shape[:2]
    cu, cv = num("lens_centre_u_px"), num("lens_centre_v_px")
    centre = ((W - 1) / 2.0 if cu is None else cu, (H - 1) / 2.0 if cv is None else cv)
    return Lens(k1 or 0.0, k2 or 0.0, f, centre), quality


def declared_keys(settings: dict) -> dict:
    """The ring-file keys (:func:`declared_camera`) of a camera described by its settings
    (``lens_k1``, ``lens_k2``, ``camera_distance`` [m], ``pixel_pitch`` [m/px],
    ``jpeg_quality``, ``line_time`` [s per row]; the stand's screen camera stores them): what a
    lab declares."""
    out = {}
    if settings.get("lens_k1") or settings.get("lens_k2"):
        out.update({k: float(settings.get(k) or 0.0) for k in ("lens_k1", "lens_k2")},
                   lens_focal_px=settings["camera_distance"] / settings["pixel_pitch"])
    if settings.get("jpeg_quality"):
        out["jpeg_quality"] = int(settings["jpeg_quality"])
    if settings.get("h264_qp") is not None:      # the frames went through H.264 at this qp
        out["h264_qp"] = int(settings["h264_qp"])
    if settings.get("line_time"):            # a rolling shutter: each spot timed by its row
        out["line_time"] = float(settings["line_time"])
    return out
