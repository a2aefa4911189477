"""Stroboscope frames -> weight angles (issue 6, item 4).

Image convention (the stand's stroboscope camera looks down the shaft):
u = column (right), v = row (down); physical angles are anticlockwise from +X
(right) with +Y up, so a pixel at (u, v) around the rotor centre (uc, vc) has
angle ``atan2(-(v - vc), u - uc)``.

Method (:func:`weight_angles`):

1. rotor disk: pixels brighter than half-way between the housing and the lit
   interior; the outer contour of the largest component gets an ellipse fit
   -> rotor centre (unless ``centre_px`` is given) and rim radius;
2. a polar resampling (cv2.remap) around the centre;
3. the reference mark: the angular profile of the mark annulus (``mark`` =
   radial span as fractions of the rim radius) minus the interior level; its
   peak, refined by an intensity-weighted circular centroid;
4. the weights: the angular profile of a band around the track radius; runs
   of bins above threshold are the weight images (a multi-flash exposure shows
   one image per distinct position: ghosts of 1/K contrast count too);
   each run's weighted centroid is one image's angle; runs wider than one ball
   image (touching balls) are split into equal parts when ``n_weights`` asks
   for more images than runs.

Uncertainties: the centroid noise propagated from the profile noise (MAD
outside the images), combined with the centre's uncertainty (0.1 px / track
radius) -- they do not include the stroboscope's own reading error (4.1).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Optional

import cv2
import numpy as np

from .calibration import VisionError

__all__ = ["VisionError", "StrobeAngles", "weight_angles", "rotor_disk", "reference_mark"]

TWO_PI = 2.0 * math.pi
N_ANGLES = 1440          #: angular bins of the polar resampling (0.25 deg)


def _wrap(a):
    return (np.asarray(a, float) + math.pi) % TWO_PI - math.pi


@dataclass
class StrobeAngles:
    """Result of :func:`weight_angles` (angles in rad, anticlockwise from +X).

    mark_angle, mark_sigma : the reference mark's absolute angle and its 1-sigma
    angles, sigma : (m,) each weight image's angle relative to the mark (wrapped
        to (-pi, pi], sorted ascending), 1-sigma
    absolute : (m,) the same, absolute
    n_images : number of distinct weight images on the track (clusters)
    images_per_weight : n_images / n_weights when n_weights is given (a
        multi-flash exposure of a stuck group shows each weight that many
        times), else NaN
    centre_px : (u, v) rotor centre used;  rim_radius_px, track_radius_px
    widths : (m,) angular width of each image [rad]
    """
    mark_angle: float
    mark_sigma: float
    angles: np.ndarray
    sigma: np.ndarray
    absolute: np.ndarray
    n_images: int
    images_per_weight: float
    centre_px: tuple
    rim_radius_px: float
    track_radius_px: float
    widths: np.ndarray = field(default_factory=lambda: np.zeros(0))


def _gray(frame) -> np.ndarray:
    img = np.asarray(frame)
    if img.ndim == 3 and img.shape[2] in (3, 4):
        img = cv2.cvtColor(img[..., :3].astype(np.float32), cv2.COLOR_BGR2GRAY)
    if img.ndim != 2 or min(img.shape) < 8:
        raise VisionError(f"frame: expected a 2-D grey image of at least 8 x 8 px, got shape "
                          f"{np.shape(frame)}")
    img = img.astype(np.float32)
    if not np.all(np.isfinite(img)):
        raise VisionError("frame: contains non-finite values")
    return img


def rotor_disk(frame):
    """Rotor centre (u, v) [px] and rim radius [px] from the lit disk.

    Raises VisionError for a blank frame or when no disk-like region is found.
    """
    img = _gray(frame)
    lo, hi = np.percentile(img, [1.0, 99.9])
    if not hi - lo > 0:
        raise VisionError("rotor_disk: blank frame (no contrast)")
    # housing level: the darkest mode; lit interior: the median of the brighter pixels
    housing = float(np.percentile(img, 5.0))
    brighter = img[img > housing + 0.1 * (hi - housing)]
    if brighter.size < 50:
        raise VisionError("rotor_disk: no lit rotor disk in the frame")
    interior = float(np.median(brighter))
    thr = 0.5 * (housing + interior)
    mask = (img > thr).astype(np.uint8)
    mask = cv2.morphologyEx(mask, cv2.MORPH_CLOSE, np.ones((5, 5), np.uint8))
    contours, _ = cv2.findContours(mask, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
    if not contours:
        raise VisionError("rotor_disk: no lit rotor disk in the frame")
    c = max(contours, key=cv2.contourArea)
    area = cv2.contourArea(c)
    if c.shape[0] < 20 or area < 100:
        raise VisionError("rotor_disk: no lit rotor disk in the frame")
    (u, v), (a, b), _ = cv2.fitEllipse(c)
    R = 0.25 * (a + b)
    if not (0.8 < a / b < 1.25) or abs(math.pi * R * R - area) > 0.15 * area:
        raise VisionError("rotor_disk: the lit region is not a disk (no rotor seen)")
    # the contour runs along the outer pixel centres: add half a pixel
    return (float(u), float(v)), float(R + 0.5), housing, interior


def _polar(img, centre, r_max, n_r):
    r = np.linspace(0.0, r_max, n_r)
    th = np.arange(N_ANGLES) * (TWO_PI / N_ANGLES)
    map_u = (centre[0] + np.cos(th)[:, None] * r[None, :]).astype(np.float32)
    map_v = (centre[1] - np.sin(th)[:, None] * r[None, :]).astype(np.float32)
    P = cv2.remap(img, map_u, map_v, interpolation=cv2.INTER_LINEAR,
                  borderMode=cv2.BORDER_REPLICATE)
    return r, th, P                       # P[angle, radius]


def _circ_centroid(th, w):
    s = float(np.sum(w))
    if not s > 0:
        return float("nan"), float("nan")
    c = np.sum(w * np.cos(th)) / s
    d = np.sum(w * np.sin(th)) / s
    return math.atan2(d, c), s


def _runs(above):
    """Circular runs of True: list of index arrays."""
    n = above.size
    if not np.any(above):
        return []
    if np.all(above):
        return [np.arange(n)]
    start = int(np.argmin(above))           # a False bin: start the scan after it
    idx = (np.arange(n) + start) % n
    a = above[idx]
    runs, cur = [], []
    for k, flag in zip(idx, a):
        if flag:
            cur.append(k)
        elif cur:
            runs.append(np.array(cur))
            cur = []
    if cur:
        runs.append(np.array(cur))
    return runs


def _find_mark(P, r, th, R, base, mark, who):
    """Reference mark in the polar image ``P[angle, radius]``.

    Returns ``(mark_angle, mark_sigma, r_in)``: the mark's absolute angle and its
    1-sigma [rad], and the inner radius of the mark annulus [px] (weights are
    looked for inside it); ``mark`` None: ``(0, 0, 0.97 R)``.
    """
    if mark is None:
        return 0.0, 0.0, 0.97 * R
    m0, m1 = mark
    band = (r >= (m0 + 0.02) * R) & (r <= (m1 - 0.02) * R)
    prof = np.median(P[:, band], axis=1) - base
    noise_m = 1.4826 * float(np.median(np.abs(prof - np.median(prof)))) + 1e-6
    k = int(np.argmax(prof))
    if not prof[k] > 8 * noise_m:
        raise VisionError(f"{who}: no reference mark found in the mark annulus")
    above = prof > 0.5 * prof[k]
    run = next(rr for rr in _runs(above) if k in rr)
    ext = np.concatenate([run, (run[[0]] - np.arange(1, 3)) % N_ANGLES,
                          (run[[-1]] + np.arange(1, 3)) % N_ANGLES])
    w = np.clip(prof[ext], 0, None)
    mark_angle, s = _circ_centroid(th[ext], w)
    rm = 0.5 * (m0 + m1) * R
    d = _wrap(th[ext] - mark_angle)
    mark_sigma = math.sqrt(float(np.sum(d * d)) * noise_m ** 2 / s ** 2 + (0.1 / rm) ** 2)
    return mark_angle, mark_sigma, m0 * R


def reference_mark(frame, *, centre_px=None, mark=(0.80, 0.97)) -> tuple:
    """The reference mark alone: ``(mark_angle, mark_sigma)`` [rad], absolute, anticlockwise
    from +X (frames whose weights are not read here, e.g. a liquid's crescent).

    Parameters as :func:`weight_angles`; ``mark`` must not be None.

    Raises
    ------
    VisionError
        Blank frame, no rotor, no mark.
    """
    if mark is None:
        raise VisionError("reference_mark: mark = None (no mark to find)")
    img = _gray(frame)
    (uc, vc), R, _, _ = rotor_disk(img)
    if centre_px is not None:
        uc, vc = float(centre_px[0]), float(centre_px[1])
    r, th, P = _polar(img, (uc, vc), R, int(math.ceil(R)) * 2 + 1)
    base = float(np.median(P[:, (r > 0.15 * R) & (r < 0.75 * R)]))
    a, s, _ = _find_mark(P, r, th, R, base, mark, "reference_mark")
    return float(_wrap(a)), float(s)


def weight_angles(frame, *, centre_px=None, track_radius_px=None, mark=(0.80, 0.97),
                  n_weights: Optional[int] = None, ball_radius_px: Optional[float] = None,
                  min_contrast: float = 0.08) -> StrobeAngles:
    """Reference mark and weight angles in one stroboscope frame.

    Parameters
    ----------
    frame : (H, W) array
    centre_px : (u, v), optional
        Rotor centre [px]; default fitted to the lit rotor disk.
    track_radius_px : float, optional
        Radius of the weights' centres [px]; default: the radius of the
        brightest weight pixels inside ``mark[0]`` of the rim.
    mark : (lo, hi) or None
        Radial span of the reference mark, fractions of the rim radius; None:
        no mark (angles are then absolute, ``mark_angle`` = 0).
    n_weights : int, optional
        Number of weights; when the track shows fewer separate images than
        this in a single-flash frame, the widest runs are split (touching balls).
    ball_radius_px : float, optional
        Drawn ball radius [px] (width of the track band); default estimated.
    min_contrast : float
        Smallest image contrast accepted, fraction of the brightest weight's.

    Raises
    ------
    VisionError
        Blank frame, no rotor, no mark, no weight on the track.
    """
    img = _gray(frame)
    (uc, vc), R, housing, interior = rotor_disk(img)
    if centre_px is not None:
        uc, vc = float(centre_px[0]), float(centre_px[1])
    r, th, P = _polar(img, (uc, vc), R, int(math.ceil(R)) * 2 + 1)
    dr = r[1] - r[0]
    inside = P[:, (r > 0.15 * R) & (r < 0.75 * R)]
    base = float(np.median(inside))
    # ---- the mark
    mark_angle, mark_sigma, r_in = _find_mark(P, r, th, R, base, mark, "weight_angles")
    # ---- the track
    ok = (r > 0.05 * R) & (r < r_in - 1.0)
    if track_radius_px is None:
        sub = P[:, ok]
        excess = sub - base
        top = float(excess.max())
        if not top > 0:
            raise VisionError("weight_angles: no weights on the rotor")
        wr = np.clip(excess - 0.5 * top, 0, None)
        track = float(np.sum(wr * r[ok][None, :]) / np.sum(wr)) if wr.sum() > 0 else 0.0
    else:
        track = float(track_radius_px)
    if not 0 < track < R:
        raise VisionError(f"weight_angles: track radius {track:.3g} px outside the rotor "
                          f"(rim radius {R:.3g} px)")
    if ball_radius_px is None:
        # radial half-width of the brightest image at the track
        line = P[:, int(round(track / dr))] - base
        kk = int(np.argmax(line))
        radial = P[kk] - base
        half = radial > 0.5 * radial[int(round(track / dr))]
        j0 = int(round(track / dr))
        j1 = j0
        while j1 + 1 < r.size and half[j1 + 1]:
            j1 += 1
        j2 = j0
        while j2 - 1 >= 0 and half[j2 - 1]:
            j2 -= 1
        ball = max(1.0, 0.5 * (j1 - j2 + 1) * dr)
    else:
        ball = float(ball_radius_px)
    band = np.abs(r - track) <= max(1.0, 0.5 * ball)
    prof = P[:, band].mean(axis=1) - base
    noise = 1.4826 * float(np.median(np.abs(prof - np.median(prof)))) + 1e-6
    top = float(prof.max())
    if not top > 8 * noise:
        raise VisionError("weight_angles: no weights found on the track")
    thr = max(6 * noise, min_contrast * top)
    runs = [rr for rr in _runs(prof > thr) if rr.size >= 2]
    if not runs:
        raise VisionError("weight_angles: no weights found on the track")
    ang, sig, wid = [], [], []
    one = 2.0 * ball / track                         # angular size of one ball image
    n_runs = len(runs)
    extra = 0 if n_weights is None else max(0, int(n_weights) - n_runs)
    # width at half of each run's own peak (a disc image is ~one ball wide there)
    widths = [np.count_nonzero(prof[rr] > 0.5 * prof[rr].max()) * TWO_PI / N_ANGLES
              for rr in runs]
    order = np.argsort(widths)[::-1]
    split = {int(i): 1 for i in range(n_runs)}
    for i in order:                                   # split the widest runs first
        if extra <= 0:
            break
        m = max(1, int(math.floor(widths[i] / max(one, 1e-9) + 0.25)))
        add = min(extra, m - 1)
        split[int(i)] += add
        extra -= add
    for i, rr in enumerate(runs):
        parts = np.array_split(rr, split[i])
        for pp in parts:
            w = np.clip(prof[pp], 0, None)
            a, s = _circ_centroid(th[pp], w)
            d = _wrap(th[pp] - a)
            sa = math.sqrt(float(np.sum(d * d)) * noise ** 2 / s ** 2 + (0.1 / track) ** 2)
            ang.append(a)
            sig.append(sa)
            wid.append(pp.size * TWO_PI / N_ANGLES)
    ang = np.array(ang)
    rel = _wrap(ang - mark_angle)
    o = np.argsort(rel)
    rel, sig, wid = rel[o], np.array(sig)[o], np.array(wid)[o]
    sig = np.sqrt(sig ** 2 + mark_sigma ** 2)
    n_img = n_runs
    ipw = n_img / n_weights if n_weights else float("nan")
    return StrobeAngles(mark_angle=float(_wrap(mark_angle)), mark_sigma=float(mark_sigma),
                        angles=rel, sigma=sig, absolute=_wrap(ang[o]), n_images=int(n_img),
                        images_per_weight=float(ipw), centre_px=(uc, vc), rim_radius_px=R,
                        track_radius_px=track, widths=wid)
