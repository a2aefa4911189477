"""The front of :func:`vision.spot.locate` (its steps 1-2): :func:`detect`.

For an integer frame (uint8 / uint16) with numba, one call of compiled loops (:func:`front`)
does what numpy and OpenCV do otherwise (the same numbers, ``tests/test_vision_spot.py``;
about 15 us per region of interest of the video sample instead of ~0.15 ms of small numpy and
OpenCV calls):

* :func:`vision.levels.background_level` of the region's border: the border's pixels
  clipped at +- 5 robust sigma about their median, their mean and standard deviation.
  The median and the MAD are counted on histograms of the (integer) values' high and low
  bytes (no sort); the sums of integers and of their squares are
  exact in float64, so the mean and the sigma are ``cv2.meanStdDev``'s to the bit
  (its formula: ``m = S / n``, ``sd = sqrt(max(Q / n - m^2, 0))`` with ``1 / n``
  multiplied);
* the blank test (all pixels equal), the amplitude test, the threshold of the blurred
  image (compared in float32, as numpy compares a float32 array with a Python float) and
  ``cv2.connectedComponentsWithStats`` (8-connectivity) reduced to what ``locate`` uses:
  the component holding the blurred maximum (grown over the runs of pixels above the cut:
  its pixels labelled 1, its bounding box and area) and whether any other component has
  ``min_area`` pixels or more (the second blob);
* the count of the blob's bounding box's pixels at or above the fit's censoring level.

The blurred image and its maximum stay OpenCV's (``cv2.GaussianBlur``, ``cv2.minMaxLoc``).
Without numba (``STAND_DISABLE_JIT`` / ``NUMBA_DISABLE_JIT``), for float frames and tiny
regions, numpy and OpenCV run.  The compiled loops call nothing outside this file (numba's
cache is invalidated per source file).
"""
from __future__ import annotations

import math
import sys

import cv2
import numpy as np

from ._numba import numba_or_none, once
from .levels import BORDER, background_level

__all__ = ["detect", "front", "border_background", "compiled_front"]

_INT_FRAMES = (np.dtype(np.uint8), np.dtype(np.uint16))   # the frames of the compiled front
_FRONT = None         # (the compiled front or None,) once looked up


def detect(sub, background, threshold, censor, sigma, min_area):
    """Steps 1-2 of :func:`vision.spot.locate` on the searched region ``sub``: the border's
    background and noise (``background`` [DN] imposes the level), the blur (``sigma`` [px]),
    its maximum, the amplitude test (``threshold`` [DN], None: the default) and the blob.

    Returns
    -------
    (flags, level, noise, peak) for a missing (or blank) spot, else (level, noise, amp,
    the region as float32, labels, the spot's label, its bounding box (x, y, w, h) [px],
    its area [px], another blob of ``min_area`` px or more?, the box's pixels >= ``censor``).
    """
    global _FRONT
    if _FRONT is None and "numba" in sys.modules:
        use_compiled()       # (a lone locate, e.g. `stand snapshot`'s check, imports no numba)
    fast = (_FRONT[0] if _FRONT is not None and sub.dtype in _INT_FRAMES
            and min(sub.shape) > 2 * BORDER + 2 else None)
    img = sub.astype(np.float32)
    if fast is not None:
        blur = cv2.GaussianBlur(img, (0, 0), sigma)
        _, bmax, _, (pu, pv) = cv2.minMaxLoc(blur)
        # a region of interest copied contiguous (a few kB): one compiled specialisation per
        # pixel type instead of two (numba types a view's layout apart: ~3 s of compile each)
        (status, level, noise, amp, labels, bx, by, bw, bh, area, second, n_censored) = fast(
            np.ascontiguousarray(sub), blur, pu, pv, bmax,
            math.nan if background is None else float(background),
            math.nan if threshold is None else float(threshold),
            math.inf if censor is None else float(censor), min_area, BORDER)
        if status == 1:
            return {"missing", "blank"}, level, noise, 0.0
        if status == 2:
            return {"missing"}, level, noise, amp
        if status == 0:
            return level, noise, amp, img, labels, 1, (bx, by, bw, bh), area, second, n_censored
    level, noise = background_level(sub)
    if background is not None:
        level = float(background)
    lo_hi = cv2.minMaxLoc(sub if sub.dtype != np.float64 else img)
    if lo_hi[0] == lo_hi[1]:
        return {"missing", "blank"}, level, noise, 0.0
    blur = cv2.GaussianBlur(img, (0, 0), sigma)
    _, bmax, _, (pu, pv) = cv2.minMaxLoc(blur)
    amp = bmax - level
    thr = max(10.0 * noise, 5.0) if threshold is None else float(threshold)
    if not amp >= thr:
        return {"missing"}, level, noise, amp
    cut = level + max(5.0 * noise, 0.05 * amp)
    mask = (blur > cut).astype(np.uint8)
    n, labels, stats, _ = cv2.connectedComponentsWithStats(mask, connectivity=8)
    lab = labels[pv, pu]
    second = False
    if n > 2:
        others = np.delete(np.arange(1, n), lab - 1)
        second = bool(np.any(stats[others, cv2.CC_STAT_AREA] >= min_area))
    bx, by, bw, bh, area = stats[lab]
    n_censored = (0 if censor is None
                  else int(np.count_nonzero(sub[by:by + bh, bx:bx + bw] >= censor)))
    return level, noise, amp, img, labels, lab, (bx, by, bw, bh), area, second, n_censored


def use_compiled() -> bool:
    """From now on :func:`detect` runs the compiled front (importing numba for it; the same
    numbers as numpy and OpenCV): :func:`vision.spot.track` asks for it, a whole video being
    worth numba's import; a lone :func:`detect` uses it only once numba is imported anyway.
    Returns whether it is available."""
    global _FRONT
    if _FRONT is None:
        _FRONT = (compiled_front(),)
    return _FRONT[0] is not None




def _kth(x, n, k, centre):
    """The value of rank ``k`` (0-based) of ``x[:n]`` (integers in 0..65535), or of their
    distances ``|x - centre|`` when ``centre`` >= 0: a 256-bin count of the high bytes,
    then of the low bytes in the bucket holding rank ``k`` (exact, no sort)."""
    hist = np.zeros(256, np.int64)
    for t in range(n):
        v = x[t] if centre < 0 else abs(x[t] - centre)
        hist[v >> 8] += 1
    c = 0
    top = 0
    for b in range(256):
        if c + hist[b] > k:
            top = b
            break
        c += hist[b]
    for b in range(256):
        hist[b] = 0
    for t in range(n):
        v = x[t] if centre < 0 else abs(x[t] - centre)
        if v >> 8 == top:
            hist[v & 255] += 1
    for b in range(256):
        c += hist[b]
        if c > k:
            return (top << 8) + b
    return (top << 8) + 255


def border_background(a, b):
    """(level, sigma) [DN] of the border (``b`` px) of the image ``a`` (integers in
    0..65535, both sides > 2 b + 2 px), as :func:`vision.levels.background_level`."""
    H, W = a.shape
    n = 2 * b * W + 2 * b * (H - 2 * b)
    x = np.empty(n, np.int64)
    k = 0
    for i in range(H):
        if i < b or i >= H - b:
            for j in range(W):
                x[k] = a[i, j]
                k += 1
        else:
            for j in range(b):
                x[k] = a[i, j]
                x[k + 1] = a[i, W - b + j]
                k += 2
    med = _kth(x, n, n // 2, -1)
    lim = max(5.0 * (1.4826 * float(_kth(x, n, n // 2, med))), 3.0)
    nk = 0
    s = 0
    q = 0
    for t in range(n):
        if float(abs(x[t] - med)) <= lim:
            nk += 1
            s += x[t]
            q += x[t] * x[t]
    if nk < 4:
        nk = 0
        s = 0
        q = 0
        for t in range(n):
            nk += 1
            s += x[t]
            q += x[t] * x[t]
    scale = 1.0 / nk
    m = float(s) * scale
    return m, math.sqrt(max(float(q) * scale - m * m, 0.0))


def front(sub, blur, pu, pv, bmax, background, threshold, censor, min_area, border):
    """``locate``'s steps 1-2 (module docstring) on the region ``sub`` (integer, both sides
    > 2 ``border`` + 2 px; ``border`` [px] the background's) and its blur ``blur`` (float32)
    whose maximum ``bmax`` lies at column ``pu``, row ``pv``; ``background``, ``threshold``
    [DN] NaN when not imposed; ``censor`` [DN] the fit's censoring level (inf: none).

    Returns
    -------
    (status, level, noise, amp, labels, bx, by, bw, bh, area, second, n_censored):
    status 0 found, 1 blank, 2 missing (amplitude below the threshold), 3 the maximum not
    above the cut (an imposed threshold below it: the OpenCV path decides); labels (uint8,
    sub's shape) 1 on the spot's component; its bounding box [px], area [px]; second: another
    component of at least ``min_area`` px; n_censored: pixels >= ``censor`` in the box.
    """
    H, W = sub.shape
    level, noise = border_background(sub, border)
    if background == background:
        level = background
    labels = np.zeros((H, W), np.uint8)
    lo = sub[0, 0]
    hi = sub[0, 0]
    for i in range(H):
        for j in range(W):
            lo = min(lo, sub[i, j])
            hi = max(hi, sub[i, j])
    if lo == hi:
        return 1, level, noise, 0.0, labels, 0, 0, 0, 0, 0, False, 0
    amp = bmax - level
    thr = max(10.0 * noise, 5.0) if threshold != threshold else threshold
    if not amp >= thr:
        return 2, level, noise, amp, labels, 0, 0, 0, 0, 0, False, 0
    cut = np.float32(level + max(5.0 * noise, 0.05 * amp))
    if not blur[pv, pu] > cut:
        return 3, level, noise, amp, labels, 0, 0, 0, 0, 0, False, 0
    # the runs of pixels above the cut, row by row (row i's: first[i] to first[i + 1] - 1)
    rs = np.empty(H * (W // 2 + 1), np.int64)
    re = np.empty(rs.size, np.int64)
    first = np.empty(H + 1, np.int64)
    nr = 0
    for i in range(H):
        first[i] = nr
        j = 0
        while j < W:
            if blur[i, j] > cut:
                rs[nr] = j
                while j < W and blur[i, j] > cut:
                    j += 1
                re[nr] = j - 1
                nr += 1
            j += 1
    first[H] = nr
    comp = np.zeros(nr, np.uint8)     # 1: the spot's component, 2: another
    stack = np.empty(nr, np.int64)
    k0 = first[pv]
    while re[k0] < pu:
        k0 += 1
    area, i0, i1, j0, j1 = _grow(k0, 1, rs, re, first, comp, stack)
    second = False
    row = 0
    for k in range(nr):
        while first[row + 1] <= k:
            row += 1
        if comp[k] == 1:
            for j in range(rs[k], re[k] + 1):
                labels[row, j] = 1
        elif comp[k] == 0 and not second:
            second = _grow(k, 2, rs, re, first, comp, stack)[0] >= min_area
    n_cens = 0
    for i in range(i0, i1 + 1):
        for j in range(j0, j1 + 1):
            if sub[i, j] >= censor:
                n_cens += 1
    return 0, level, noise, amp, labels, j0, i0, j1 - j0 + 1, i1 - i0 + 1, area, second, n_cens


def _grow(k0, lab, rs, re, first, comp, stack):
    """Mark ``lab`` in ``comp`` on the runs 8-connected to run ``k0`` (runs of rows i and
    i +- 1 touch when their column spans, widened by one, overlap); returns (area, first
    row, last row, first column, last column) of that component."""
    H = first.size - 1
    comp[k0] = lab
    stack[0] = k0
    top = 1
    area = 0
    i0 = H
    i1 = -1
    j0 = rs[k0]
    j1 = re[k0]
    while top > 0:
        top -= 1
        k = stack[top]
        lo = 0
        hi = H
        while hi - lo > 1:                 # the run's row: first[row] <= k < first[row + 1]
            mid = (lo + hi) // 2
            if first[mid] <= k:
                lo = mid
            else:
                hi = mid
        i = lo
        area += re[k] - rs[k] + 1
        i0 = min(i0, i)
        i1 = max(i1, i)
        j0 = min(j0, rs[k])
        j1 = max(j1, re[k])
        for r in range(max(i - 1, 0), min(i + 2, H)):
            if r == i:
                continue
            for m in range(first[r], first[r + 1]):
                if comp[m] == 0 and rs[m] <= re[k] + 1 and re[m] >= rs[k] - 1:
                    comp[m] = lab
                    stack[top] = m
                    top += 1
    return area, i0, i1, j0, j1


@once
def compiled_front():
    """:func:`front` compiled by numba (``cache=True``, ``nogil=True``; numba imported on
    the first call), or None when numba is missing or disabled."""
    numba = numba_or_none()
    if numba is None:
        return None
    jit = numba.njit(cache=True, error_model="numpy", nogil=True)
    mod = globals()
    for name in ("_kth", "border_background", "_grow"):
        mod[name] = jit(mod[name])
    return jit(front)
