"""Sub-pixel laser-spot location and tracking.

Pixel convention (OpenCV's): u = column (to the right), v = row (downwards),
pixel centres at integer coordinates, (0, 0) the centre of the top-left pixel.

Algorithm of :func:`locate`
---------------------------
1. **Background and noise.**  The pixels of the border (2 px wide) of the
   searched region (the whole frame, or the ROI) are clipped around their
   median (+- 5 robust sigma) and give the background level (their mean, which
   is not quantised like a median) and the background noise sigma_bg (their
   standard deviation, read + background shot + quantisation noise;
   :mod:`vision.levels`).  Pass ``background=`` to impose the level.
2. **Coarse detection** (OpenCV): ``cv2.GaussianBlur`` (sigma 1 px) then
   ``cv2.minMaxLoc`` gives the brightest point; its height above the
   background is the amplitude.  Amplitude below ``threshold`` (default
   ``max(10 sigma_bg, 5)`` DN) -> flag ``"missing"``, NaN centre, no exception.
   The blurred image thresholded at ``background + max(5 sigma_bg, 0.05 x
   amplitude)`` is split by ``cv2.connectedComponentsWithStats``; the component
   holding the brightest point is the spot (the brightest blob), any other
   component of at least ``MIN_BLOB_AREA`` px is a second (weaker) blob, e.g. a
   reflection -> flag ``"second_blob"`` (the spot itself is still located).
   Steps 1-2 are :func:`vision._spot_front.detect`: for integer frames one compiled
   call with numba (border statistics, threshold and the spot's component in loops,
   the same numbers), else numpy and OpenCV as written here.
3. **Window.**  Half-widths ``window`` [px] (u, v) if given, else 1.25 x the
   half-extent of the spot's component + 1 px (that component is cut at 5 % of
   the amplitude, i.e. at ~2.45 sigma for a Gaussian, so the window is about
   +-3 sigma); for asymmetric blobs (motion-blurred arcs) it is widened until,
   centred on the centroid, it covers the whole blob plus that padding.
4. **Sub-pixel refinement, two stages, or a model fit** (the centroids (a) and (b):
   :mod:`vision.centroid`).
   (a) *Iteratively re-centred intensity-weighted centroid* of the
   background-subtracted image in a *soft-edged* window (pixel weight = the
   fraction of the pixel inside the window, so the window moves continuously
   and its fixed point is unbiased for a symmetric spot; a hard pixel-aligned
   window "pixel-locks"), iterated to 1e-4 px.  Unclipped, this is the
   exposure-averaged centre of any shape; clipping biases it (0.2-1 px on
   clipped motion-blurred arcs), so saturated or elongated blobs go to the
   blurred-spot fit (c) first.
   (b) For a compact, round, unsaturated spot (``refine="auto"``), a
   *Gaussian-weighted centroid* (the matched filter): pixel weight
   ``g = exp(-|x - c|^2 / (2 s^2))`` with ``s`` the spot's own sigma (from its
   weighted second moment), solved for ``sum g I (x - c) = 0`` by Newton
   steps.  Any symmetric weight gives an unbiased fixed point; the matched
   one minimises the read-noise variance (the far pixels, which carry mostly
   noise, are down-weighted).  Measured in ``benchmarks/bench_vision.py``
   (sigma = 2 px, default noise, 8 bit): RMS 0.0075 px vs 0.016 px for (a)
   alone, the same as a least-squares Gaussian fit (0.0074 px) at ~1/10 of
   its cost, and better than ``trackpy.locate`` (0.012 px).
   Used only when it lands within ``AGREE_PX`` (0.1 px) of (a): a blob that
   is not a symmetric spot (a ring-shaped long-exposure trace, an uneven arc)
   keeps (a).  ``refine="centroid"`` keeps (a) only; ``refine="gaussian"`` forces (b)
   (still not for arcs, where it would pull towards the brightest part).
   (c) A blob that is saturated (>= 2 pixels within ``CENSOR_MARGIN`` of full
   scale) or elongated (its bounding box not square within 25 %, or less than
   ``FILL_ROUND`` of it filled) is fitted with the motion-blurred, clipped spot
   model of :mod:`vision.blur` (``refine="blur"``: every blob), clipped pixels
   censored; method "blur", its uncertainty the fit's.  The fit is kept when it
   converged to a plausible spot (sigma, a centre on the blob), its residual
   variance is at most ``MAX_FIT_CHI2`` times the noise's (else the path is one
   the model cannot draw, e.g. several turns in one exposure) and, for an
   unclipped blob, it agrees with the centroid (a) within 4 sigma; otherwise the
   blob keeps (a) with the flag ``"fit_failed"``: no frame falls back silently.
5. **Saturation**: pixels at the full-scale value (255 for uint8, 2**b - 1 for
   uint16 frames whose maximum is such a value, or ``saturation=``) -- if at
   least 2 -> flag ``"saturated"``.  The plateau enters the centroid with its
   (clipped) values: a clipped symmetric spot is still symmetric, so the
   centre is unbiased; those pixels carry no noise (variance 0).
6. **Uncertainty** by propagating pixel noise through the fixed point of the
   centroid: ``var(u) = sum w_i^2 (u_i - u)^2 var(I_i) / D_u^2`` with
   ``D_u = sum w_i I_i - sum_edge |u_i - u| I_i`` (the window's own motion),
   ``var(I_i) = sigma_bg^2 + max(I_i, 0) / gain`` (shot noise only when
   ``gain`` [electrons per DN] is given).
   For the Gaussian-weighted centroid the same formula holds with the
   weights ``w = g x window`` and ``D_u = sum w I (1 - (u_i - u)^2 / s^2)``
   (the weight moves with the centre).
7. **Flags**: ``"missing"``, ``"blank"`` (all pixels equal, e.g. all zero),
   ``"saturated"``, ``"second_blob"``, ``"edge"`` (the spot's blob touches
   the frame border: the centre is biased), ``"fit_failed"`` (step 4c),
   ``"not_refined"`` (a compact round spot whose Gaussian-weighted centre (b) was
   not used because it disagreed with (a) by more than ``AGREE_PX`` or failed: the
   centroid is kept and half the disagreement joins its uncertainty).  ``ok``
   is False for missing/blank/edge.  No frame falls back silently.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Iterable, Optional

import cv2
import numpy as np

from .centroid import GAUSS_HALF, TOL, gauss_centroid, gauss_weights, recentre, soft, spot_sigma
from .io import frame_table
from ._spot_front import detect, use_compiled
from .levels import saturation_level

__all__ = ["SpotResult", "locate", "track", "MIN_BLOB_AREA", "TRACK_COLUMNS"]

MIN_BLOB_AREA = 4          #: px, smallest component counted as a second blob
COARSE_SIGMA = 1.0         #: px, blur of the coarse detection
ARC_PAD = 4                #: px, dilation of a sparse blob (arc) before its centroid
#: px, dilation of the blob into the blurred-spot fit's pixels: the blob reaches ~2.4 sigma
#: of the spot (5 % of its peak), the margin adds ~1 sigma where the model is < 0.3 % of
#: it (ARC_PAD's wider margin held 27 % more pixels, ~no information: the same RMS error)
FIT_PAD = 2
_PAD_KERNEL = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * FIT_PAD + 1,) * 2)
MIN_FIT_SIGMA = 0.4        #: px, smallest spot sigma a blurred-spot fit may return
#: largest residual variance of an accepted blurred-spot fit, in units of the background's
#: noise variance (at least 1 DN^2: quantisation and rendering leave ~1 DN^2 on noiseless
#: frames); good fits: 1.0-2.6 on the stand's cameras and the H.264 sample, shot noise
#: included; a path of several turns in one exposure: 4-150
MAX_FIT_CHI2 = 3.5
#: fraction of full scale below it still taken as clipped by the blurred-spot fit (8 DN at
#: 8 bits): lossy video (H.264 at qp 10) turns a clipped 255 into 248-255, and a clipped
#: pixel read as an ordinary 249 would pull the fit down (0.04 px RMS, 0.26 px at worst on
#: the video sample with a 3 DN margin; 0.014 px RMS, as the lossless frames, with 8 DN)
CENSOR_MARGIN = 0.03
REFINE = ("auto", "centroid", "gaussian", "blur")
WIDE_MARGIN = 4            #: x margin: the rectangle tried before the whole frame in track
FILL_ROUND = 0.6           #: a round blob fills >= this fraction of its bounding box (a disc: 0.785)
AGREE_PX = 0.1             #: px, largest centroid / Gaussian-centroid difference of a spot
COARSE_TOL = 2e-2          #: px, soft-window centroid tolerance when stage (b) follows
_BLUR = None      # (the compiled blob_inputs or None, vision.blur) once imported
BAD_FLAGS = frozenset({"missing", "blank", "edge"})
#: flag of a saturated or elongated blob whose blurred-spot fit failed (the centroid is kept)
FIT_FAILED = "fit_failed"
NOT_REFINED = "not_refined"   #: a round spot whose Gaussian-weighted refinement was not used
#: columns of :func:`track` after frame [and time]
TRACK_COLUMNS = ("u_px", "v_px", "u_std_px", "v_std_px", "peak", "method", "flags", "ok")


@dataclass
class SpotResult:
    """Result of :func:`locate` (pixels, u = column, v = row)."""

    u_px: float
    v_px: float
    u_std_px: float
    v_std_px: float
    peak: float              #: DN above background at the (blurred) maximum
    total: float             #: DN, background-subtracted sum in the window
    flags: set = field(default_factory=set)
    background: float = math.nan
    noise: float = math.nan  #: background noise sigma [DN]
    window: tuple = (math.nan, math.nan)   #: half-widths (u, v) [px]
    method: str = ""         #: "centroid", "gaussian" or "blur" (the refinement used)
    blur: Optional[object] = None   #: the :class:`vision.blur.BlurFit` when method is "blur"

    @property
    def ok(self) -> bool:
        return self.flags.isdisjoint(BAD_FLAGS)


def _missing(flags, background=math.nan, noise=math.nan, peak=math.nan):
    return SpotResult(math.nan, math.nan, math.nan, math.nan, peak, math.nan, set(flags),
                      background, noise)


def locate(frame, *, background: Optional[float] = None, threshold: Optional[float] = None,
           window=None, roi=None, gain: Optional[float] = None,
           saturation: Optional[float] = None, refine: str = "auto",
           blur_start=None, _inside_only: bool = False) -> SpotResult:
    """Locate the laser spot in one frame (see the module docstring).

    Parameters
    ----------
    frame : 2-D array (H, W), uint8 / uint16 / float
    background : float, optional
        Background level [DN]; default estimated on the border of the searched
        region (the noise is estimated there in any case).
    threshold : float, optional
        Smallest amplitude [DN above background] of a spot; default
        ``max(10 sigma_bg, 5)``.
    window : float or (float, float), optional
        Half-widths [px] of the centroid window along u and v; default from
        the spot's extent (about +-3 sigma).
    roi : (x, y, w, h), optional
        Search only this rectangle (OpenCV rect, clipped to the frame);
        coordinates returned are still those of the full frame.
    gain : float, optional
        Electrons per DN, for the shot-noise term of the uncertainty.
    saturation : float, optional
        Full-scale value; default 255 for uint8, inferred for uint16.
    refine : {"auto", "centroid", "gaussian", "blur"}
        Sub-pixel refinement (module docstring, step 4): "auto" fits the
        blurred-spot model (:mod:`vision.blur`) to saturated or elongated blobs
        and uses the Gaussian-weighted centroid for compact, round, unsaturated
        spots; "centroid" keeps the plain centroid; "blur" fits every blob.
    blur_start : (float, float) or (float, float, (float, float, float)), optional
        Starting amplitude [DN] and sigma [px] of the blurred-spot fit (the
        previous frame's, when tracking a video); default from the blob's moments.
        A third item (h_u, h_v, kappa) [px, px, 1/px]: a further starting path
        (:func:`vision.blur.fit_blurred_spot`'s ``warm``).

    Returns
    -------
    SpotResult
        Never raises for a missing spot: NaN centre and flag ``"missing"``.
    """
    if refine not in REFINE:
        raise ValueError(f"refine: expected one of {REFINE}, got {refine!r}")
    frame = np.asarray(frame)
    if frame.ndim != 2 or frame.size == 0:
        raise ValueError(f"frame: expected a 2-D image, got shape {frame.shape}")
    H, W = frame.shape
    x0 = y0 = 0
    sub = frame
    if roi is not None:
        rx, ry, rw, rh = (int(round(r)) for r in roi)
        x0, y0 = max(rx, 0), max(ry, 0)
        x1, y1 = min(rx + rw, W), min(ry + rh, H)
        if x1 - x0 < 8 or y1 - y0 < 8:
            return _missing({"missing"})
        sub = frame[y0:y1, x0:x1]
    late = saturation is None and frame.dtype == np.uint16   # full scale from frame.max()
    sat = None if late else saturation_level(frame, saturation)
    censor = None if sat is None else sat - round(CENSOR_MARGIN * sat)
    found = detect(sub, background, threshold, censor, COARSE_SIGMA, MIN_BLOB_AREA)
    if len(found) == 4:       # missing (or blank): flags, level, noise, peak
        return _missing(*found)
    level, noise, amp, img, labels, lab, (bx, by, bw, bh), area, second, n_censored = found
    flags: set = {"second_blob"} if second else set()

    def near_roi_border(pad):   # within pad px of the ROI's border inside the frame
        return _inside_only and (bx <= pad and x0 > 0 or by <= pad and y0 > 0
                                 or bx + bw + pad >= sub.shape[1] and x0 + sub.shape[1] < W
                                 or by + bh + pad >= sub.shape[0] and y0 + sub.shape[0] < H)

    if near_roi_border(0):
        return None       # the blob reaches the ROI's border inside the frame: search it all
    if late:              # (a uint16 frame's maximum: read only for a blob)
        sat = saturation_level(frame, saturation)
        censor = None if sat is None else sat - round(CENSOR_MARGIN * sat)
    if window is None:
        hu = 1.25 * 0.5 * bw + 1.0
        hv = 1.25 * 0.5 * bh + 1.0
    else:
        hu, hv = (float(window), float(window)) if np.isscalar(window) else map(float, window)
    cu = bx + 0.5 * (bw - 1)
    cv = by + 0.5 * (bh - 1)
    Hs, Ws = sub.shape
    # saturated or elongated (motion-blurred) blob: the blurred-spot model fit
    if refine in ("auto", "blur") and window is None:
        if late and censor is not None:
            n_censored = int(np.count_nonzero(sub[by:by + bh, bx:bx + bw] >= censor))
        clipped = censor is not None and n_censored >= 2
        elongated = (abs(int(bw) - int(bh)) > max(2, 0.25 * max(bw, bh))
                     or area < FILL_ROUND * bw * bh)
        if refine == "blur" or clipped or elongated:
            if near_roi_border(FIT_PAD + 1):   # its fit's window would reach the border
                return None                    # (_locate_near): not worth fitting here
            r = _blur_locate(sub, labels, lab, (bx, by, bw, bh), level, noise, censor, amp, flags,
                             (x0, y0, W, H), blur_start)
            if r is not None:
                return r
            flags.add(FIT_FAILED)
    total = math.nan
    hu0, hv0 = hu, hv
    tol = TOL if refine == "centroid" else COARSE_TOL   # re-done at TOL if (b) is not used
    for _grow in range(4):
        c = recentre(img, level, cu, cv, hu, hv, tol=tol)
        if c is None:
            return _missing(flags | {"missing"}, level, noise, amp)
        cu, cv = c
        if window is not None:
            break
        # an asymmetric blob (motion-blurred arc): the window centred on the
        # centroid must still cover the whole blob plus the padding
        need_u = max(cu - bx, bx + bw - 1 - cu) + 0.125 * bw + 1.0
        need_v = max(cv - by, by + bh - 1 - cv) + 0.125 * bh + 1.0
        if need_u <= hu + 1e-9 and need_v <= hv + 1e-9:
            break
        hu, hv = max(hu, need_u), max(hv, need_v)
    grown = hu > 1.25 * hu0 or hv > 1.25 * hv0    # an asymmetric blob (arc), not noise
    # sparse blob (an arc): only the pixels near the blob count (less noise)
    sel = None
    if window is None and 4.0 * hu * hv > 4.0 * area + 400.0:
        near = cv2.dilate((labels == lab).astype(np.uint8),
                          cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * ARC_PAD + 1,) * 2))
        sel = near.astype(np.float64)
        c = recentre(img, level, cu, cv, hu, hv, sel)
        if c is None:
            return _missing(flags | {"missing"}, level, noise, amp)
        cu, cv = c
    # stage (b): Gaussian-weighted centroid of a compact, round, unsaturated spot
    gs = None
    disagree = 0.0            # px: the Gaussian-weighted centre that was not kept, vs (a)
    if refine != "centroid" and sel is None and not grown:
        blob = sub[by:by + bh, bx:bx + bw]
        saturated = sat is not None and np.count_nonzero(blob >= sat) >= 2
        round_ = abs(int(bw) - int(bh)) <= max(2, 0.25 * max(bw, bh))
        if refine == "gaussian" or (round_ and not saturated):
            s = spot_sigma(img, level, cu, cv, min(hu, hv))
            if math.isfinite(s) and s >= 0.5:
                c = gauss_centroid(img, level, cu, cv, s)
                # a symmetric spot gives the same centre both ways (to the
                # noise, ~0.02 px); a non-Gaussian blob (a ring-shaped trace,
                # an uneven arc) does not: keep the exposure-averaged centroid
                if c is not None and math.hypot(c[0] - cu, c[1] - cv) <= AGREE_PX:
                    cu, cv = c
                    gs = s
                else:         # the refined locator was not used: said, and in the uncertainty
                    flags.add(NOT_REFINED)
                    if c is not None:
                        disagree = math.hypot(c[0] - cu, c[1] - cv)
                    else:
                        disagree = math.nan
    if gs is None and sel is None and tol > TOL:
        c = recentre(img, level, cu, cv, hu, hv)
        if c is None:
            return _missing(flags | {"missing"}, level, noise, amp)
        cu, cv = c
    # final geometry at the converged centre
    if gs is None:
        eh_u, eh_v = hu, hv
    else:
        eh_u = eh_v = GAUSS_HALF * gs
    i0, i1 = max(int(math.floor(cv - eh_v - 0.5)), 0), min(int(math.ceil(cv + eh_v + 0.5)), Hs - 1)
    j0, j1 = max(int(math.floor(cu - eh_u - 0.5)), 0), min(int(math.ceil(cu + eh_u + 0.5)), Ws - 1)
    raw = sub[i0:i1 + 1, j0:j1 + 1]
    patch = raw.astype(np.float64) - level
    xu = np.arange(j0, j1 + 1) - cu
    xv = np.arange(i0, i1 + 1) - cv
    if gs is None:
        wu, wv = soft(xu, hu), soft(xv, hv)
    else:
        wu, wv = gauss_weights(xu, gs, eh_u), gauss_weights(xv, gs, eh_v)
    w2 = wv[:, None] * wu[None, :]
    if sel is not None:
        w2 = w2 * sel[i0:i1 + 1, j0:j1 + 1]
        wu = wu * 0.0 + 1.0   # (edge terms of the window are irrelevant for a masked arc)
        wv = wv * 0.0 + 1.0
    total = float((patch * w2).sum())
    if sel is not None:
        patch = patch * sel[i0:i1 + 1, j0:j1 + 1]
    # cut by the frame border? (the spot's blob reaches the border)
    if x0 + bx <= 0 or y0 + by <= 0 or x0 + bx + bw >= W or y0 + by + bh >= H:
        flags.add("edge")
    var = np.full(patch.shape, noise * noise + 1.0 / 12.0 * (noise < 0.3))
    if gain is not None and gain > 0:
        var = var + np.maximum(patch, 0.0) / gain
    if sat is not None:
        hot = raw >= sat
        if np.count_nonzero(hot) >= 2:
            flags.add("saturated")
            var[hot] = 0.0
    # denominators including the window's own motion (soft-edge pixels)
    if gs is None:
        eu = (wu > 0) & (wu < 1)
        ev = (wv > 0) & (wv < 1)
        Du = total - float((patch * wv[:, None] * (np.abs(xu) * eu)[None, :]).sum())
        Dv = total - float((patch * wu[None, :] * (np.abs(xv) * ev)[:, None]).sum())
    else:   # the Gaussian weight moves with the centre (its soft edge is negligible)
        pw = patch * w2
        Du = total - float((pw * (xu * xu)[None, :]).sum()) / (gs * gs)
        Dv = total - float((pw * (xv * xv)[:, None]).sum()) / (gs * gs)
    vu = float((w2 * w2 * (xu * xu)[None, :] * var).sum())
    vv = float((w2 * w2 * (xv * xv)[:, None] * var).sum())
    su = math.sqrt(vu) / Du if Du > 0 else math.inf
    sv = math.sqrt(vv) / Dv if Dv > 0 else math.inf
    if NOT_REFINED in flags and math.isfinite(disagree):
        # the two locators disagree: the spot is not the symmetric one the refinement
        # assumes; half the disagreement, per axis, joins the uncertainty
        su = math.hypot(su, 0.5 * disagree)
        sv = math.hypot(sv, 0.5 * disagree)
    return SpotResult(x0 + cu, y0 + cv, su, sv, float(amp), total, flags, level, noise,
                      (hu, hv), "centroid" if gs is None else "gaussian")


def _blur_locate(sub, labels, lab, box, level, noise, sat, amp, flags, frame_geom, start):
    """The blurred-spot fit (:func:`vision.blur.fit_blurred_spot`) of the blob ``lab``
    (pixels >= ``sat`` censored); a :class:`SpotResult` with method "blur", or None when
    the fit fails (module docstring, step 4c)."""
    global _BLUR
    if _BLUR is None:     # (imported once: a per-frame import costs as much as a small fit)
        from . import blur
        from ._blur_start import compiled_blob_inputs

        _BLUR = (compiled_blob_inputs(), blur)
    fast, blur = _BLUR
    bx, by, bw, bh = (int(a) for a in box)
    x0, y0, W, H = frame_geom
    Hs, Ws = sub.shape
    i0, i1 = max(by - FIT_PAD, 0), min(by + bh + FIT_PAD, Hs)
    j0, j1 = max(bx - FIT_PAD, 0), min(bx + bw + FIT_PAD, Ws)
    amp0, sig0 = (None, None) if start is None else start[:2]
    warm = None if start is None or len(start) < 3 else start[2]
    try:
        if fast is not None:    # mask, pixels, starting values, moments in one compiled call
            patch = sub[i0:i1, j0:j1].astype(np.float64)
            mask, pi, pj, clip, starts, (tot, mu, mv, nm) = fast(
                patch, labels, int(lab), i0, j0, _PAD_KERNEL, math.inf if sat is None else float(sat),
                float(level), float(sig0 or 0.0), blur.MAX_SWEEP)
            f = blur.fit_prepared(patch, mask, pi, pj, clip, starts, level, sat, amp0, warm)
        else:
            comp = (labels[i0:i1, j0:j1] == lab).astype(np.uint8)
            mask = cv2.dilate(comp, _PAD_KERNEL).astype(bool)
            patch = sub[i0:i1, j0:j1]
            f = blur.fit_blurred_spot(patch, mask, level, saturation=sat, sigma=sig0,
                                      amplitude=amp0, warm=warm)
    except ValueError:
        return None
    size = max(bw, bh)
    inside = (-0.5 <= f.u <= j1 - j0 - 0.5) and (-0.5 <= f.v <= i1 - i0 - 0.5)
    if not (f.converged and inside and math.isfinite(f.u_std) and math.isfinite(f.v_std)
            and MIN_FIT_SIGMA < f.sigma < 0.5 * size + 2.0):
        return None
    # a misfit (a path the model cannot draw: several turns in one exposure, a second
    # spot): residuals well above the noise
    if not f.chi2 <= MAX_FIT_CHI2 * max(noise * noise, 1.0):
        return None
    # the fit against the plain centroid of the blob: without clipping the centroid is
    # the exposure average too, so they must agree within the noise; with clipping they
    # differ by the centroid's bias (< 1 px)
    if fast is not None:      # blob_inputs' (start_loops') centroid and moments: the
        cu, cv = mu, mv       # numpy ones below to rounding
    else:
        w = np.where(mask, np.maximum(patch.astype(np.float64) - level, 0.0), 0.0)
        tot = float(w.sum())
        xs = np.arange(w.shape[1], dtype=np.float64)
        ys = np.arange(w.shape[0], dtype=np.float64)
        cu = float(w.sum(axis=0) @ xs) / tot
        cv = float(w.sum(axis=1) @ ys) / tot
        nm = mask.sum(axis=0) @ (xs - cu) ** 2 + mask.sum(axis=1) @ (ys - cv) ** 2
    d = math.hypot(f.u - cu, f.v - cv)
    if f.n_clipped >= 2:
        if d > 1.0 + 0.05 * size:
            return None
    else:
        sd = math.sqrt(float(nm) * max(noise * noise, 0.25)) / tot     # the centroid's noise
        if d > 4.0 * math.hypot(sd, f.u_std, f.v_std) + 0.02:
            return None
    flags = set(flags)
    if f.n_clipped >= 2:
        flags.add("saturated")
    if x0 + bx <= 0 or y0 + by <= 0 or x0 + bx + bw >= W or y0 + by + bh >= H:
        flags.add("edge")
    u, v = j0 + f.u, i0 + f.v
    hu = max(u - j0, j1 - 1 - u) + 1.0
    hv = max(v - i0, i1 - 1 - v) + 1.0
    flux = f.amplitude * 2.0 * math.pi * f.sigma ** 2
    return SpotResult(x0 + u, y0 + v, f.u_std, f.v_std, float(amp), flux, flags, level, noise,
                      (hu, hv), "blur", f)


def track(frames: Iterable, *, background=None, threshold=None, window=None, gain=None,
          saturation=None, refine: str = "auto", margin: float = 16.0,
          progress: bool = False, jpeg_quality: Optional[int] = None):
    """Locate the spot in every frame; returns a pandas DataFrame.

    ``frames``: an iterable of 2-D arrays, or of :class:`vision.io.FrameRecord`
    (as yielded by :func:`vision.io.iter_frames`; then a ``time`` column [s] is
    added, NaN when the source has no timestamps).

    ROI tracking: after a located spot, the next frame is searched only in a
    rectangle around the previous centre (the previous window + ``margin`` px
    on each side) -- first around the position a whirl predicts (the circle
    through the last three centres, stepped on by the last step's angle) --; if
    the spot is missing there, or its window reaches the ROI's border, in a
    rectangle ``WIDE_MARGIN`` times wider, then the whole frame is searched again
    (on a 1280 x 1024 frame the whole-frame search costs ~50 ROI searches).  Consequence: a second
    blob (reflection) is flagged only when it lies inside the ROI (or when the
    frame was searched in full).

    A saturated or elongated blob is fitted with the blurred-spot model
    (:mod:`vision.blur`), started from the previous fit's amplitude and sigma and,
    for a short blob, first from the previous path turned by the whirl's step (4.6 -> 3.9
    iterations per fit on the video sample).

    Columns: frame, [time,] u_px, v_px, u_std_px, v_std_px, peak, method ("gaussian",
    "centroid" or "blur": the refinement used), flags (comma-separated sorted string,
    "" when none; "fit_failed": the blurred-spot fit was tried and the centroid kept), ok.

    ``jpeg_quality``: the frames were JPEG-compressed at this quality (or H.264 at
    ``("h264", qp)``); each centre's std gets the compression's share
    (:func:`vision.compression.widen_for_jpeg`).
    """
    use_compiled()       # the compiled front of locate (vision._spot_front): many frames
    kw = dict(background=background, threshold=threshold, window=window, gain=gain,
              saturation=saturation, refine=refine)
    prev = None
    start = None         # the last blurred-spot fit's amplitude and sigma
    seen = []            # the last three located centres, for the whirl's prediction

    def measure(img):
        nonlocal prev, start
        kw["blur_start"] = start
        r = None
        if prev is not None:
            guess = _whirl_prediction(seen)
            if guess is not None:
                if start is not None and prev.blur is not None:
                    kw["blur_start"] = start + (_warm_path(prev, guess[2]),)
                guess = guess[:2]
                r = _locate_near(img, prev, margin, kw, at=guess)
            else:   # (no prediction; after one that failed, this rectangle found the spot
                r = _locate_near(img, prev, margin, kw)   # in 1 of 43 frames of the sample)
            if r is None:     # a wider rectangle before the whole frame (large frames)
                r = _locate_near(img, prev, WIDE_MARGIN * margin, kw, at=guess)
        if r is None:
            r = locate(img, **kw)
        prev = r if r.ok else None
        if r.ok:
            seen.append((r.u_px, r.v_px))
            del seen[:-3]
        else:
            seen.clear()
        if r.blur is not None:
            start = (r.blur.amplitude, r.blur.sigma)
        if jpeg_quality is not None:
            from .compression import widen_for_jpeg

            r = widen_for_jpeg(r, img, jpeg_quality)
        return r

    return frame_table(frames, measure, TRACK_COLUMNS, progress=progress)


def _warm_path(prev: SpotResult, step: float) -> tuple:
    """The previous frame's fitted path turned by the whirl's ``step`` [rad]
    (:func:`_whirl_prediction`): (h_u, h_v, kappa) [px, px, 1/px], a starting path of the
    next blurred-spot fit (:func:`vision.blur.fit_blurred_spot`'s ``warm``)."""
    f = prev.blur
    c, s = math.cos(step), math.sin(step)
    hu, hv = f.half_path
    return c * hu - s * hv, s * hu + c * hv, f.curvature


def _whirl_prediction(seen) -> Optional[tuple]:
    """Where a whirling spot will be next: the circle through its last three centres
    (u, v) [px], the last step's angle repeated about its centre (after two centres: the
    last step repeated); (u, v, step) with the step's angle [rad] (0 after two centres);
    None for fewer than two centres, a straight or still track, or a step of more than
    120 deg."""
    if len(seen) == 2:    # two centres: the last step repeated
        (x1, y1), (x2, y2) = seen
        return 2.0 * x2 - x1, 2.0 * y2 - y1, 0.0
    if len(seen) < 3:
        return None
    (x1, y1), (x2, y2), (x3, y3) = seen
    d = 2.0 * (x1 * (y2 - y3) + x2 * (y3 - y1) + x3 * (y1 - y2))
    s1, s2, s3 = x1 * x1 + y1 * y1, x2 * x2 + y2 * y2, x3 * x3 + y3 * y3
    if abs(d) < 1e-9:
        return None
    cx = (s1 * (y2 - y3) + s2 * (y3 - y1) + s3 * (y1 - y2)) / d
    cy = (s1 * (x3 - x2) + s2 * (x1 - x3) + s3 * (x2 - x1)) / d
    a2 = math.atan2(y2 - cy, x2 - cx)
    a3 = math.atan2(y3 - cy, x3 - cx)
    step = (a3 - a2 + math.pi) % (2.0 * math.pi) - math.pi
    r = math.hypot(x3 - cx, y3 - cy)
    if not (r < 1e4 and 1e-3 < abs(step) < 2.1):
        return None
    return cx + r * math.cos(a3 + step), cy + r * math.sin(a3 + step), step


def _locate_near(img, prev: SpotResult, margin: float, kw: dict,
                 at: Optional[tuple] = None) -> Optional[SpotResult]:
    """:func:`locate` in a rectangle around the previous spot (its window +
    ``margin`` px; centred ``at`` (u, v) [px] when given, a predicted position);
    None when the whole frame must be searched (spot missing there, or its window
    reaching the rectangle's border)."""
    hu, hv = prev.window
    ru, rv = hu + margin, hv + margin
    cu, cv = (prev.u_px, prev.v_px) if at is None else at
    roi = (int(math.floor(cu - ru)), int(math.floor(cv - rv)),
           int(math.ceil(2 * ru)) + 1, int(math.ceil(2 * rv)) + 1)
    r = locate(img, roi=roi, _inside_only=True, **kw)
    if r is None:
        return None   # the blob reaches the rectangle's border: search the whole frame
    if "missing" in r.flags:   # (a flat rectangle, e.g. a JPEG's background, too)
        return None
    hu2, hv2 = r.window
    if (r.u_px - hu2 - 1 < roi[0] or r.u_px + hu2 + 1 > roi[0] + roi[2] - 1
            or r.v_px - hv2 - 1 < roi[1] or r.v_px + hv2 + 1 > roi[1] + roi[3] - 1):
        return None   # window may be cut by the ROI: search the whole frame
    return r
