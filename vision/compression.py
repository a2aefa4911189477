"""The spot centre's uncertainty on JPEG-compressed frames.

JPEG quantises each 8 x 8 block's cosine coefficients; on a spot of a few px the lost
coefficients move its centroid by a deterministic amount that depends on where the spot
sits in the block grid (0.1 px RMS at quality 30 for sigma = 2 px; 0.01 px at 80) -- far
more than the pixel noise, which the compression smooths away together with the
background's noise that :func:`vision.spot.locate` measures.  :func:`jpeg_centre_std`
estimates it for one located spot: the ideal spot (a Gaussian of the located amplitude and
width over the located background, quantised and clipped as the camera does) is drawn at
2 x 2 sub-pixel shifts about the located centre in the frame's own block grid, put
through JPEG at the declared quality, and the Gaussian-weighted centroid (the locator's
own, or its soft-window centroid when that was used) is read before and after; the RMS
of the shifts' differences is the compression's standard uncertainty, added in
quadrature to the noise's (:func:`widen_for_jpeg`).  Checked in
``benchmarks/bench_uncertainty.py --paths camera`` (benchmarks/README.md).
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np

from .camera_artefacts import jpeg
from .centroid import gauss_centroid, recentre, spot_sigma

__all__ = ["jpeg_centre_std", "widen_for_jpeg", "h264_options", "h264", "compressed", "SHIFTS"]

SHIFTS = 2          #: sub-pixel shifts per axis (a SHIFTS x SHIFTS grid over one pixel)
BLOCK = 8           #: px, JPEG's block


def jpeg_centre_std(shape, u, v, amplitude, sigma, level, quality, max_dn=255, window=None):
    """Standard uncertainty [px] (u, v) that JPEG at ``quality`` (or H.264 at ``("h264",
    qp)``: :func:`compressed`) adds to the centre of a spot at (u, v) [px] of ``amplitude``
    [DN above ``level``] and Gaussian ``sigma`` [px] in a frame of ``shape`` (H, W) (module
    docstring), read with the Gaussian-weighted centroid or, given its half-widths
    ``window`` (u, v) [px], the soft-window one; NaN when the spot is too near the border to
    be drawn."""
    H, W = shape
    half = 4.0 * sigma + BLOCK
    j0, i0 = (max(0, int(math.floor((c - half) / BLOCK)) * BLOCK) for c in (u, v))
    j1 = min(W, int(math.ceil((u + half) / BLOCK)) * BLOCK)
    i1 = min(H, int(math.ceil((v + half) / BLOCK)) * BLOCK)
    jj, ii = np.arange(j0, j1) - j0, np.arange(i0, i1) - i0
    errs = []
    for du in (np.arange(SHIFTS) + 0.5) / SHIFTS - 0.5:
        for dv in (np.arange(SHIFTS) + 0.5) / SHIFTS - 0.5:
            cu, cv = u - j0 + du, v - i0 + dv
            m = level + amplitude * np.exp(-((jj[None, :] - cu) ** 2 + (ii[:, None] - cv) ** 2)
                                           / (2.0 * sigma * sigma))
            ideal = np.clip(np.floor(m + 0.5), 0, max_dn).astype(np.uint8)
            a, b = (gauss_centroid(img, level, cu, cv, sigma) if window is None
                    else recentre(img, level, cu, cv, *window)
                    for img in (ideal.astype(np.float32), compressed(ideal, quality).astype(np.float32)))
            if a is None or b is None:
                return math.nan, math.nan
            errs.append((b[0] - a[0], b[1] - a[1]))
    e = np.asarray(errs)
    su, sv = np.sqrt(np.mean(e * e, axis=0))
    return float(su), float(sv)


def compressed(img, quality):
    """``img`` (8-bit) through JPEG at ``quality`` (int) or, for ``("h264", qp)``, through
    H.264 as an intra frame (:func:`h264`; the spot's share of an inter frame is no larger:
    a moving spot is predicted from its last intra coding at best), padded to even sizes."""
    if not isinstance(quality, tuple):
        return jpeg(img, quality)
    H, W = img.shape
    padded = np.pad(img, ((0, H % 2), (0, W % 2)), mode="edge")
    return next(h264([padded], quality[1]))[:H, :W]


def widen_for_jpeg(result, frame, quality):
    """A :class:`vision.spot.SpotResult` with the compression's uncertainty
    (:func:`jpeg_centre_std`; JPEG at ``quality`` or H.264 at ``("h264", qp)``) added in
    quadrature; unchanged when not located."""
    if quality is None or not result.ok:
        return result
    img = np.asarray(frame)
    blur = getattr(result, "blur", None)
    if blur is not None:
        s = float(blur.sigma)
    else:
        s = spot_sigma(img.astype(np.float64), result.background, result.u_px, result.v_px,
                       max(result.window))
    if not (math.isfinite(s) and s > 0.3):
        return result
    amp = result.peak * (s * s + 1.0) / (s * s)     # the coarse peak is blurred by 1 px
    ju, jv = jpeg_centre_std(img.shape, result.u_px, result.v_px, amp, s, result.background,
                             quality if isinstance(quality, tuple) else int(quality), 255,
                             None if result.method == "gaussian" else result.window)
    if not (math.isfinite(ju) and math.isfinite(jv)):
        return result
    return dataclasses.replace(result, u_std_px=math.hypot(result.u_std_px, ju),
                               v_std_px=math.hypot(result.v_std_px, jv))


def h264_options(qp: int) -> dict:
    """x264's options for a lab-like H.264: constant quantiser ``qp`` (0..51, 0 lossless),
    tuned for PSNR (no psycho-visual shaping)."""
    return {"qp": str(int(qp)), "tune": "psnr"}


def h264(frames, qp: int, fps: float = 25.0):
    """8-bit gray frames (an iterable of (H, W) uint8) through H.264 at constant quantiser
    ``qp`` (:func:`h264_options`, 4:2:0, one thread: reproducible) and decoded back: a
    generator, one frame out per frame in, in order (x264 through PyAV; ``fps`` [Hz] only
    sets the stream's clock).

    Raises
    ------
    ImportError
        PyAV is not installed (``pip install av``).
    """
    import av
    from fractions import Fraction

    enc = dec = None
    for img in frames:
        img = np.ascontiguousarray(img, np.uint8)
        if enc is None:
            enc = av.CodecContext.create("libx264", "w")
            enc.height, enc.width = img.shape
            enc.pix_fmt, enc.time_base = "yuv420p", 1 / Fraction(fps).limit_denominator(1000)
            enc.options, enc.thread_count = h264_options(qp), 1
            dec = av.CodecContext.create("h264", "r")
            dec.thread_count = 1
        f = av.VideoFrame.from_ndarray(img, format="gray").reformat(format="yuv420p")
        for pkt in enc.encode(f):
            yield from (d.to_ndarray(format="gray") for d in dec.decode(pkt))
    if enc is not None:
        for pkt in enc.encode(None):
            yield from (d.to_ndarray(format="gray") for d in dec.decode(pkt))
        yield from (d.to_ndarray(format="gray") for d in dec.decode(None))
