"""Long-exposure images: the circle a whirling laser spot draws on the screen.

With an exposure of several revolutions the spot of a steadily whirling shaft
draws a circle (a ring of the spot's width); its radius is the 1X amplitude on
the screen, read against the calibration rings as an unbalance (zone i ->
i S / 16).  :func:`fit_trace` measures that circle to sub-pixel precision.

Method
------
1. Background level and noise from the frame border (as :func:`vision.spot.locate`).
2. The trace's pixels: the blurred image above ``background + max(5 sigma_bg,
   0.05 x amplitude)``; the component of largest total intensity, dilated by
   ``pad`` px so the spot's wings are included.
3. **Intensity-weighted algebraic (Kasa) circle fit**: ``[a, b, c]`` minimise
   ``sum I (u^2 + v^2 - 2 a u - 2 b v - c)^2`` (one 3 x 3 linear solve, no
   iteration).  The centre is (a, b), and ``M^2 = c + a^2 + b^2`` is exactly the
   intensity-weighted mean of ``|x - centre|^2``.
4. **Spot-width correction.**  A circle of radius R drawn by an isotropic spot
   whose 2-D second moment is ``2 s^2`` (a Gaussian of sigma s) has
   ``<|x - centre|^2> = R^2 + 2 s^2`` exactly, for any R (the average of
   ``|c + n|^2`` over the spot's offsets n).  So ``R^2 = M^2 - 2 s^2``, with s
   given (``spot_sigma_px``, e.g. from a still frame via
   :func:`vision.spot.locate`'s window, or from the camera's specification) or
   estimated from the radial spread ``Var(r) = s^2 (1 + O(s^2 / R^2))``
   (valid when R >> s; flag ``"unresolved"`` when R < 3 s and s was not given:
   then the spot and the circle are not separable from one image).
   Without this correction the fitted radius is biased by ~s^2 / R (0.2 px for
   s = 2 px, R = 10 px: 2 %).
5. **Uncertainty** by propagating pixel noise (background sigma, plus shot
   noise with ``gain``) through ``R^2 = sum I f / sum I``.
6. **Flags**: ``"missing"`` (nothing above the threshold), ``"blank"``,
   ``"saturated"`` (>= 2 pixels at full scale: the clipped profile breaks the
   identity of step 4, bias of order s^2 / R), ``"edge"`` (the trace touches the
   frame border), ``"not_circle"`` (with ``spot_sigma_px`` given, the radial
   spread exceeds what the spot explains by more than 50 %: an epitrochoid or a
   changing radius during the exposure; the radius is then an rms radius).

Pixel convention as :mod:`vision.spot` (u = column, v = row).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Iterable, Optional

import cv2
import numpy as np

from .io import frame_table
from .levels import background_level, saturation_level
from .spot import COARSE_SIGMA

__all__ = ["TraceFit", "fit_trace", "track_traces", "TRACE_COLUMNS", "UNRESOLVED_SIGMAS"]

BAD_FLAGS = frozenset({"missing", "blank", "edge"})
#: a circle of radius R < UNRESOLVED_SIGMAS x the spot's sigma (estimated from the trace) is
#: flagged "unresolved": circle and spot are not separable from one image, the fit's radius
#: (< that many sigmas by the flag) is no measurement, only that bound
UNRESOLVED_SIGMAS = 3.0
#: columns of :func:`track_traces` after frame [and time]
TRACE_COLUMNS = ("u_px", "v_px", "radius_px", "radius_std_px", "spot_sigma_px", "flags", "ok")


@dataclass
class TraceFit:
    """Result of :func:`fit_trace` (pixels)."""

    u_px: float              #: centre, column
    v_px: float              #: centre, row
    radius_px: float         #: radius of the circle drawn by the spot's centre
    radius_std_px: float     #: 1-sigma from pixel noise
    spot_sigma_px: float     #: spot sigma used in the correction (given or estimated)
    rms_radius_px: float     #: sqrt(<|x - centre|^2>) before the correction
    total: float             #: DN, background-subtracted sum over the trace
    flags: set = field(default_factory=set)
    background: float = math.nan
    noise: float = math.nan

    @property
    def ok(self) -> bool:
        return not (self.flags & BAD_FLAGS)


def _nothing(flags, level=math.nan, noise=math.nan) -> TraceFit:
    nan = math.nan
    return TraceFit(nan, nan, nan, nan, nan, nan, nan, set(flags), level, noise)


def fit_trace(frame, *, spot_sigma_px: Optional[float] = None, threshold: Optional[float] = None,
              gain: Optional[float] = None, saturation: Optional[float] = None,
              pad: Optional[float] = None) -> TraceFit:
    """Fit the circle drawn by the spot in one long-exposure frame.

    Parameters
    ----------
    frame : 2-D array (H, W), uint8 / uint16 / float
    spot_sigma_px : float, optional
        Sigma of the (still) spot [px]; default estimated from the trace's
        radial spread (module docstring, step 4).
    threshold : float, optional
        Smallest amplitude [DN above background]; default ``max(10 sigma_bg, 5)``.
    gain : float, optional
        Electrons per DN, for the shot-noise term of the uncertainty.
    saturation : float, optional
        Full-scale value; default 255 for uint8, inferred for uint16.
    pad : float, optional
        Dilation [px] of the thresholded trace; default ``3 spot_sigma_px`` or 6 px.

    Returns
    -------
    TraceFit
        Never raises for a missing trace (NaN and flag ``"missing"``).
    """
    frame = np.asarray(frame)
    if frame.ndim != 2 or frame.size == 0:
        raise ValueError(f"frame: expected a 2-D image, got shape {frame.shape}")
    if spot_sigma_px is not None and not (math.isfinite(spot_sigma_px) and spot_sigma_px > 0):
        raise ValueError(f"spot_sigma_px = {spot_sigma_px!r}: must be a positive number of px")
    H, W = frame.shape
    level, noise = background_level(frame)
    lo, hi, _, _ = cv2.minMaxLoc(frame if frame.dtype != np.float64 else frame.astype(np.float32))
    if lo == hi:
        return _nothing({"missing", "blank"}, level, noise)
    img = frame.astype(np.float32)
    blur = cv2.GaussianBlur(img, (0, 0), COARSE_SIGMA)
    amp = float(blur.max()) - level
    thr = max(10.0 * noise, 5.0) if threshold is None else float(threshold)
    if not amp >= thr:
        return _nothing({"missing"}, level, noise)
    mask = (blur > level + max(5.0 * noise, 0.05 * amp)).astype(np.uint8)
    n, labels, stats, _ = cv2.connectedComponentsWithStats(mask, connectivity=8)
    if n < 2:
        return _nothing({"missing"}, level, noise)
    sums = np.bincount(labels.ravel(), weights=(blur - level).ravel(), minlength=n)[1:]
    lab = 1 + int(np.argmax(sums))
    flags: set = set()
    bx, by, bw, bh = stats[lab, :4]
    if bx <= 0 or by <= 0 or bx + bw >= W or by + bh >= H:
        flags.add("edge")
    p = 3.0 * spot_sigma_px if (pad is None and spot_sigma_px is not None) else (
        6.0 if pad is None else float(pad))
    k = 2 * int(math.ceil(p)) + 1
    sel = cv2.dilate((labels == lab).astype(np.uint8),
                     cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (k, k))) > 0
    vv, uu = np.nonzero(sel)
    raw = frame[vv, uu]
    I = raw.astype(np.float64) - level
    u = uu.astype(np.float64)
    v = vv.astype(np.float64)
    tot = float(I.sum())
    if not tot > 0:
        return _nothing(flags | {"missing"}, level, noise)
    # weighted Kasa fit, centred on the intensity centroid for conditioning
    u0, v0 = float((I * u).sum()) / tot, float((I * v).sum()) / tot
    du, dv = u - u0, v - v0
    q = du * du + dv * dv
    A = np.column_stack([2 * du, 2 * dv, np.ones_like(du)])
    # normal equations with the weights I (noise makes some I < 0: kept, the
    # weighted means stay unbiased)
    AI = A * I[:, None]
    try:
        a, b, c = (float(x) for x in np.linalg.solve(A.T @ AI, AI.T @ q))
    except np.linalg.LinAlgError:
        return _nothing(flags | {"missing"}, level, noise)
    cu, cv = u0 + a, v0 + b
    d2 = (u - cu) ** 2 + (v - cv) ** 2
    M2 = float((I * d2).sum()) / tot
    r = np.sqrt(d2)
    rbar = float((I * r).sum()) / tot
    var_r = float((I * (r - rbar) ** 2).sum()) / tot
    if spot_sigma_px is None:
        s2 = var_r
        f = d2 - 2.0 * (r - rbar) ** 2
    else:
        s2 = float(spot_sigma_px) ** 2
        f = d2
    R2 = M2 - 2.0 * s2
    R = math.sqrt(R2) if R2 > 0 else 0.0
    if spot_sigma_px is None and R < UNRESOLVED_SIGMAS * math.sqrt(max(s2, 0.0)):
        flags.add("unresolved")
    if spot_sigma_px is not None and R > 0 and var_r > 1.5 * s2 + 0.25:
        flags.add("not_circle")
    var = np.full(I.shape, noise * noise + (1.0 / 12.0 if noise < 0.3 else 0.0))
    if gain is not None and gain > 0:
        var = var + np.maximum(I, 0.0) / gain
    sat = saturation_level(frame, saturation)
    if sat is not None:
        hot = raw >= sat
        if np.count_nonzero(hot) >= 2:
            flags.add("saturated")
            var[hot] = 0.0
    var_R2 = float((((f - R2) ** 2) * var).sum()) / (tot * tot)
    R_std = math.sqrt(var_R2) / (2.0 * R) if R > 0 else math.sqrt(math.sqrt(var_R2))
    return TraceFit(cu, cv, R, R_std, math.sqrt(max(s2, 0.0)), math.sqrt(max(M2, 0.0)), tot,
                    flags, level, noise)


def track_traces(frames: Iterable, *, progress: bool = False, **kw):
    """:func:`fit_trace` on every frame; returns a pandas DataFrame.

    ``frames`` as for :func:`vision.spot.track` (arrays or
    :class:`vision.io.FrameRecord`, then a ``time`` column [s] is added).
    Keyword arguments go to :func:`fit_trace`.

    Columns: frame, [time,] u_px, v_px, radius_px, radius_std_px,
    spot_sigma_px, flags (comma-separated, "" when none), ok.
    """
    return frame_table(frames, lambda img: fit_trace(img, **kw), TRACE_COLUMNS,
                       progress=progress)
