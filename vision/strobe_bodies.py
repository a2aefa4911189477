"""Stroboscope frames -> the bobs of body weights (two-axis pendulums, coupled pairs, dampers).

A body weight that tilts (or turns about a point) shows in a stroboscope frame
as a bob at its centre of mass on a rod from the pivot on the shaft axis: the
bob's *direction* from the rotor centre is the body's azimuth and its
*distance* the apparent radial offset of the centre of mass (``arm |sin tilt|``
for a tilting weight).  Unlike balls the bobs are on no fixed track, so they
are found as blobs, not on a circle (:func:`vision.strobe.weight_angles`).

Image convention as :mod:`vision.strobe`: u = column (right), v = row (down);
angles anticlockwise from +X (right) with +Y up, a pixel at (u, v) around the
rotor centre (uc, vc) has angle ``atan2(-(v - vc), u - uc)``.

Method (:func:`bob_angles`):

1. rotor disk and reference mark as :func:`vision.strobe.weight_angles`
   (:func:`vision.strobe.rotor_disk`, the mark annulus ``mark``); the centre
   refined by a circle through the rim's outer edge, found to a fraction of
   a pixel along 720 rays (a bob's direction is only as good as the centre:
   0.1 px at 10 px is 0.6 deg);
2. inside the mark annulus, the bobs are the brightest objects: pixels above
   ``level`` of the way from the lit interior to the brightest (lightly
   smoothed) pixel -- the rod, the housing and the mark are dimmer than a bob
   (on the stand's frames the rod is at 2/3 of the bob's contrast);
3. connected components of those pixels; the ``n_bobs`` with the largest
   summed excess are the bobs; each bob's excess-weighted centroid, refined
   by a least-squares circle through the bob's edge (half-way between the
   interior and the bob, found along rays; the rays towards the rotor centre,
   where the rod joins the bob, are left out), gives its direction (relative
   to the mark) and its distance from the rotor centre.

The rod runs radially to the bob, so it could bias the distance (not the
direction); the edge fit leaves it out.  Uncertainties: the edge fit's
residuals (or the centroid's noise propagated from the pixel noise, MAD of the
interior), combined with the centre's (``CENTRE_SIGMA``) and the mark's; they
do not include the stroboscope's reading error (4.1).  A bob
whose distance is below a pixel or two has no meaningful direction: its
``sigma`` says so.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence

import cv2
import numpy as np

from .calibration import VisionError
from .strobe import _find_mark, _gray, _polar, _wrap, rotor_disk

__all__ = ["VisionError", "BobAngles", "bob_angles"]

#: 1-sigma of the rotor centre found from the rim's edge [px] (added to each bob's)
CENTRE_SIGMA = 0.03


@dataclass
class BobAngles:
    """Result of :func:`bob_angles` (angles in rad, anticlockwise from +X; lengths in px).

    mark_angle, mark_sigma : the reference mark's absolute angle and its 1-sigma
    angles, sigma : (m,) each bob's direction from the rotor centre relative to the
        mark (wrapped to (-pi, pi], sorted ascending), 1-sigma
    absolute : (m,) the same, absolute
    radius_px, radius_sigma_px : (m,) each bob centre's distance from the rotor centre
        and its 1-sigma (noise only; the rod may bias it by a fraction of a pixel)
    centre_px : (u, v) rotor centre used;  rim_radius_px
    bob_px : (m, 2) bob centres (u, v)
    area_px : (m,) pixels of each bob above the threshold
    """

    mark_angle: float
    mark_sigma: float
    angles: np.ndarray
    sigma: np.ndarray
    absolute: np.ndarray
    radius_px: np.ndarray
    radius_sigma_px: np.ndarray
    centre_px: tuple
    rim_radius_px: float
    bob_px: np.ndarray
    area_px: np.ndarray


def _refine_centre(img, centre, R, housing, n_rays: int = 720):
    """Rotor centre (u, v) [px] and rim radius [px] from the rim's outer edge.

    Along ``n_rays`` rays the outer flank of the rim (where the profile falls to
    half-way between its peak and the housing) is found to a fraction of a
    pixel (linear interpolation of a bilinear 0.05 px resampling); a
    least-squares circle through those points gives the centre -- a few
    hundredths of a pixel on the stand's frames, where the contour's ellipse
    of :func:`vision.strobe.rotor_disk` is good to a few tenths.
    """
    th = np.arange(n_rays) * (2.0 * math.pi / n_rays)
    r = np.arange(0.85 * R, 1.15 * R + 3.0, 0.05)
    map_u = (centre[0] + np.cos(th)[:, None] * r[None, :]).astype(np.float32)
    map_v = (centre[1] - np.sin(th)[:, None] * r[None, :]).astype(np.float32)
    P = cv2.remap(img, map_u, map_v, interpolation=cv2.INTER_LINEAR,
                  borderMode=cv2.BORDER_REPLICATE)
    xs, ys = [], []
    for k in range(n_rays):
        p = P[k]
        j = int(np.argmax(p))
        mid = 0.5 * (float(p[j]) + housing)
        below = np.nonzero(p[j:] < mid)[0]
        if below.size == 0 or below[0] == 0:
            continue
        i = j + int(below[0])
        f = (float(p[i - 1]) - mid) / (float(p[i - 1]) - float(p[i]))
        rr = r[i - 1] + f * (r[i] - r[i - 1])
        xs.append(rr * math.cos(th[k]))
        ys.append(rr * math.sin(th[k]))
    if len(xs) < n_rays // 2:
        return centre, R
    cx, cy, rad, _ = _circle_fit(np.array(xs), np.array(ys))
    if not (abs(cx) < 2.0 and abs(cy) < 2.0 and rad > 0):
        return centre, R
    return (centre[0] + cx, centre[1] - cy), rad


def _circle_fit(x, y):
    """Least-squares (algebraic) circle through the points: centre (a, b), radius, rms residual."""
    A = np.column_stack([x, y, np.ones_like(x)])
    sol, *_ = np.linalg.lstsq(A, -(x * x + y * y), rcond=None)
    a, b = -0.5 * sol[0], -0.5 * sol[1]
    rad = math.sqrt(max(a * a + b * b - sol[2], 0.0))
    res = np.hypot(x - a, y - b) - rad
    return a, b, rad, float(np.sqrt(np.mean(res * res)))


def _refine_bob(img, guess, centre, base, top, area, n_rays: int = 360):
    """Bob centre (u, v) [px] and its 1-sigma [px] from a circle through the bob's edge.

    Along rays from the blob's centroid ``guess`` the edge is where the profile
    falls to half-way between the interior ``base`` and the bob's ``top``
    (0.05 px resampling, linear interpolation); rays within 40 deg of the
    direction of the rotor centre are left out (the rod joins the bob there).
    None when too few edge points are found.
    """
    r_eq = math.sqrt(area / math.pi)
    th = np.arange(n_rays) * (2.0 * math.pi / n_rays)
    to_centre = math.atan2(-(centre[1] - guess[1]), centre[0] - guess[0])
    keep = np.abs(_wrap(th - to_centre)) > math.radians(40.0)
    if math.hypot(centre[0] - guess[0], centre[1] - guess[1]) < 0.5:
        keep[:] = True                                    # the rod is under the bob
    th = th[keep]
    r = np.arange(0.0, 2.0 * r_eq + 4.0, 0.05)
    map_u = (guess[0] + np.cos(th)[:, None] * r[None, :]).astype(np.float32)
    map_v = (guess[1] - np.sin(th)[:, None] * r[None, :]).astype(np.float32)
    P = cv2.remap(img, map_u, map_v, interpolation=cv2.INTER_LINEAR,
                  borderMode=cv2.BORDER_REPLICATE)
    mid = 0.5 * (base + top)
    xs, ys = [], []
    for k in range(th.size):
        below = np.nonzero(P[k] < mid)[0]
        if below.size == 0 or below[0] == 0:
            continue
        i = int(below[0])
        f = (float(P[k, i - 1]) - mid) / (float(P[k, i - 1]) - float(P[k, i]))
        rr = r[i - 1] + f * (r[i] - r[i - 1])
        xs.append(guess[0] + rr * math.cos(th[k]))
        ys.append(guess[1] - rr * math.sin(th[k]))
    if len(xs) < max(12, th.size // 3):
        return None
    a, b, rad, rms = _circle_fit(np.array(xs), np.array(ys))
    if not (rad > 0 and math.hypot(a - guess[0], b - guess[1]) < max(2.0, 0.5 * r_eq)):
        return None
    return (a, b), rms / math.sqrt(0.5 * len(xs))


def bob_angles(frame, n_bobs: int = 1, *, centre_px=None, mark=(0.80, 0.97),
               level: float = 0.8, min_area_px: int = 3,
               exclude_tracks_px: Sequence = (), refine: bool = True) -> BobAngles:
    """Reference mark and the bobs of body weights in one stroboscope frame.

    Parameters
    ----------
    frame : (H, W) array
    n_bobs : int
        Number of bobs to report (>= 1): the ``n_bobs`` brightest blobs.
    centre_px : (u, v), optional
        Rotor centre [px]; default fitted to the rim's outer edge.
    mark : (lo, hi) or None
        Radial span of the reference mark, fractions of the rim radius; None:
        no mark (angles are then absolute, ``mark_angle`` = 0).
    level : float
        Threshold of the bob pixels, fraction of the way from the lit interior
        to the brightest pixel (0 < level < 1).
    min_area_px : int
        Smallest blob [px] counted.
    exclude_tracks_px : sequence of (track_radius_px, ball_radius_px)
        Blobs centred within ``ball_radius_px + 1`` of one of these radii are
        balls on their track, not bobs (scenes with both).
    refine : bool
        Refine each bob's centre by a circle through its edge (default); False:
        the thresholded blob's weighted centroid.

    Raises
    ------
    VisionError
        Blank frame, no rotor, no mark, fewer bobs than ``n_bobs``.
    """
    n_bobs = int(n_bobs)
    if n_bobs < 1:
        raise VisionError(f"bob_angles: n_bobs = {n_bobs} must be >= 1")
    if not 0.0 < level < 1.0:
        raise VisionError(f"bob_angles: level = {level!r} must be in (0, 1)")
    img = _gray(frame)
    (uc, vc), R, housing, interior = rotor_disk(img)
    if centre_px is not None:
        uc, vc = float(centre_px[0]), float(centre_px[1])
    else:
        (uc, vc), _ = _refine_centre(img, (uc, vc), R, housing)
    r, th, P = _polar(img, (uc, vc), R, int(math.ceil(R)) * 2 + 1)
    inside = P[:, (r > 0.15 * R) & (r < 0.75 * R)]
    base = float(np.median(inside))
    noise = 1.4826 * float(np.median(np.abs(inside - base))) + 1e-6
    mark_angle, mark_sigma, r_in = _find_mark(P, r, th, R, base, mark, "bob_angles")
    H, W = img.shape
    V, U = np.mgrid[0:H, 0:W]
    dist = np.hypot(U - uc, V - vc)
    disk = dist < r_in - 1.0
    smooth = cv2.GaussianBlur(img, (3, 3), 0)
    top = float(np.max(smooth[disk])) if np.any(disk) else base
    if not top - base > 8 * noise:
        raise VisionError("bob_angles: nothing brighter than the rotor inside the mark annulus "
                          "(no bob)")
    thr = base + level * (top - base)
    mask = (disk & (img > thr)).astype(np.uint8)
    k, lab = cv2.connectedComponents(mask, connectivity=8)
    blobs = []
    for j in range(1, k):
        sel = lab == j
        area = int(np.count_nonzero(sel))
        if area < min_area_px:
            continue
        w = (img - thr)[sel]
        s = float(np.sum(w))
        if not s > 0:
            continue
        u, v = U[sel], V[sel]
        cu = float(np.sum(w * u) / s)
        cv = float(np.sum(w * v) / s)
        rad = math.hypot(cu - uc, cv - vc)
        if any(abs(rad - float(tr)) <= float(br) + 1.0 for tr, br in exclude_tracks_px):
            continue
        var_u = float(np.sum((u - cu) ** 2)) * noise ** 2 / s ** 2
        var_v = float(np.sum((v - cv) ** 2)) * noise ** 2 / s ** 2
        sp = math.sqrt(0.5 * (var_u + var_v))
        fit = _refine_bob(img, (cu, cv), (uc, vc), base, top, area) if refine else None
        if fit is not None:
            (cu, cv), sp = fit
            rad = math.hypot(cu - uc, cv - vc)
        blobs.append((s, cu, cv, rad, sp, area))
    if len(blobs) < n_bobs:
        raise VisionError(f"bob_angles: {len(blobs)} bob(s) found inside the mark annulus, "
                          f"{n_bobs} expected")
    blobs = sorted(blobs, key=lambda b: -b[0])[:n_bobs]
    ang, sig, rad, rsig, pos, area = [], [], [], [], [], []
    for s, cu, cv, rd, sp, ar in blobs:
        a = math.atan2(-(cv - vc), cu - uc)
        sp = math.sqrt(sp * sp + CENTRE_SIGMA ** 2)        # with the centre's uncertainty
        ang.append(a)
        sig.append(sp / max(rd, 1e-9) if rd > 0 else math.pi)
        rad.append(rd)
        rsig.append(sp)
        pos.append((cu, cv))
        area.append(ar)
    ang = np.array(ang)
    rel = _wrap(ang - mark_angle)
    o = np.argsort(rel)
    sig = np.sqrt(np.minimum(np.array(sig)[o], math.pi) ** 2 + mark_sigma ** 2)
    return BobAngles(mark_angle=float(_wrap(mark_angle)), mark_sigma=float(mark_sigma),
                     angles=rel[o], sigma=sig, absolute=_wrap(ang[o]),
                     radius_px=np.array(rad)[o], radius_sigma_px=np.array(rsig)[o],
                     centre_px=(float(uc), float(vc)), rim_radius_px=float(R),
                     bob_px=np.array(pos, float).reshape(-1, 2)[o], area_px=np.array(area)[o])
