"""Starting values of the blurred-spot fit as loops that numba compiles.

:func:`start_loops` is :func:`vision.blur.initial_guesses` without the amplitude step
(the blob's moments, the third moment's curvature and, for a long blob, the weighted
algebraic circle fit) in one pass of plain loops: the numpy version makes some thirty
numpy calls per blob, about 0.4 ms of Python holding the GIL per video frame, while a
read-ahead thread decodes the next frames (:mod:`vision.io`).  The same numbers to
rounding (``tests/test_vision_spot.py``).  :func:`compiled_start` compiles it (numba,
``cache=True``, ``nogil=True``) or returns None when numba is missing or disabled
(``STAND_DISABLE_JIT`` / ``NUMBA_DISABLE_JIT``): the numpy version then runs.
:func:`blob_inputs` adds what the tracker did around it in numpy (the blob's dilated mask,
its pixels, the clipped ones): one compiled call per fitted blob
(:func:`compiled_blob_inputs`; ``tests/test_video_track.py``).  This module imports
nothing of ``vision`` but :mod:`vision._numba`, which compiles nothing (numba's cache is
invalidated per source file).
"""
from __future__ import annotations

import math

import numpy as np

from ._numba import numba_or_none, once

__all__ = ["start_loops", "blob_inputs", "compiled_start", "compiled_blob_inputs"]



def start_loops(patch, mask, level, sigma, shrink, max_sweep):
    """Starting parameters (rows of (m_u, m_v, h_u, h_v, kappa, a2, a3, 0, ln s), patch
    coordinates [px]) of the blob ``mask`` of ``patch`` [DN] above ``level`` [DN]:
    (1, 9) for a segment, (2, 9) with the circle fit's arc, (0, 9) without signal.
    ``sigma`` [px] replaces the moment estimate of s when > 0; ``shrink``: factor of the
    across-width estimate of s (a clipped core widens the blob)."""
    H, W = patch.shape
    tot = 0.0
    su = 0.0
    sv = 0.0
    # the mask's pixels above the level, once: the later sums run over them alone
    # (the same terms in the same order as over the whole patch)
    ii = np.empty(H * W, np.int64)
    jj = np.empty(H * W, np.int64)
    ww = np.empty(H * W)
    npx = 0
    for i in range(H):
        for j in range(W):
            if mask[i, j]:
                x = patch[i, j] - level
                if x > 0:
                    tot += x
                    su += x * j
                    sv += x * i
                    ii[npx] = i
                    jj[npx] = j
                    ww[npx] = x
                    npx += 1
    if not tot > 0:
        return np.empty((0, 9))
    mu = su / tot
    mv = sv / tot
    cuu = 0.0
    cvv = 0.0
    cuv = 0.0
    for q in range(npx):
        x = ww[q]
        du = jj[q] - mu
        dv = ii[q] - mv
        cuu += x * du * du
        cvv += x * dv * dv
        cuv += x * du * dv
    cuu /= tot
    cvv /= tot
    cuv /= tot
    tr = cuu + cvv
    det = cuu * cvv - cuv * cuv
    disc = math.sqrt(max(0.25 * tr * tr - det, 0.0))
    lam1 = 0.5 * tr + disc
    lam2 = max(0.5 * tr - disc, 0.0)
    ang = 0.5 * math.atan2(2.0 * cuv, cuu - cvv)
    tu = math.cos(ang)
    tv = math.sin(ang)
    s0 = sigma if sigma > 0 else max(math.sqrt(lam2) * shrink, 0.7)
    ell = math.sqrt(max(3.0 * (lam1 - lam2), 0.0))
    kap = 0.0
    if ell > 2.0 * s0:
        m3 = 0.0
        for q in range(npx):
            du = jj[q] - mu
            dv = ii[q] - mv
            t = du * tu + dv * tv
            m3 += ww[q] * (-du * tv + dv * tu) * (t * t - lam1)
        kap = m3 / tot * 45.0 / (2.0 * ell ** 4)
        kap = max(min(kap, 0.5 * max_sweep / ell), -0.5 * max_sweep / ell)
    arc = np.empty(5)
    k = 2 if ell > 5.0 * s0 and _circle(ii, jj, ww, npx, mu, mv, tot, max_sweep, arc) else 1
    out = np.zeros((k, 9))
    out[0, 0] = mu
    out[0, 1] = mv
    out[0, 2] = ell * tu
    out[0, 3] = ell * tv
    out[0, 4] = kap
    out[0, 8] = math.log(s0)
    if k == 2:
        out[1, 0] = mu
        out[1, 1] = mv
        out[1, 2] = arc[0] * arc[1]
        out[1, 3] = arc[0] * arc[2]
        out[1, 4] = arc[3]
        out[1, 8] = math.log(sigma if sigma > 0 else max(arc[4] * shrink, 0.7))
    return out


def _circle(ii, jj, ww, npx, mu, mv, tot, max_sweep, arc):
    """:func:`vision.blur._circle_guess` in loops over the blob's ``npx`` pixels (rows ``ii``,
    columns ``jj``, weights ``ww`` [DN above the level]): ``arc`` = (l, t_u, t_v, kappa,
    radial sd); False when there is no circle (singular system, or practically straight)."""
    a = np.zeros((3, 3))
    r = np.zeros(3)
    for k in range(npx):
        w = ww[k]
        m = (jj[k] - mu, ii[k] - mv, 1.0)
        z = m[0] * m[0] + m[1] * m[1]
        for p in range(3):
            r[p] -= w * m[p] * z
            for q in range(3):
                a[p, q] += w * m[p] * m[q]
    det = (a[0, 0] * (a[1, 1] * a[2, 2] - a[1, 2] * a[2, 1])
           - a[0, 1] * (a[1, 0] * a[2, 2] - a[1, 2] * a[2, 0])
           + a[0, 2] * (a[1, 0] * a[2, 1] - a[1, 1] * a[2, 0]))
    if det == 0.0:
        return False
    x = np.empty(3)
    for c in range(3):        # Cramer's rule
        b = a.copy()
        for p in range(3):
            b[p, c] = r[p]
        x[c] = (b[0, 0] * (b[1, 1] * b[2, 2] - b[1, 2] * b[2, 1])
                - b[0, 1] * (b[1, 0] * b[2, 2] - b[1, 2] * b[2, 0])
                + b[0, 2] * (b[1, 0] * b[2, 1] - b[1, 1] * b[2, 0])) / det
    cu = -0.5 * x[0]
    cv = -0.5 * x[1]
    R2 = cu * cu + cv * cv - x[2]
    if not 0 < R2 < 1e8:
        return False
    R = math.sqrt(R2)
    c0 = 0.0
    s0 = 0.0
    for k in range(npx):      # (cos, sin of the angle about the centre: x / r, y / r)
        x = jj[k] - mu - cu
        y = ii[k] - mv - cv
        rk = math.sqrt(x * x + y * y)
        if rk > 0:
            c0 += ww[k] * x / rk
            s0 += ww[k] * y / rk
        else:
            c0 += ww[k]       # (atan2(0, 0) = 0)
    c0 /= tot
    s0 /= tot
    mid = math.atan2(s0, c0)
    C = min(math.sqrt(c0 * c0 + s0 * s0), 1.0)
    b = half_sweep(C, max_sweep)
    sd = 0.0
    for k in range(npx):
        rad = math.hypot(jj[k] - mu - cu, ii[k] - mv - cv) - R
        sd += ww[k] * rad * rad
    arc[0] = R * b
    arc[1] = -math.sin(mid)
    arc[2] = math.cos(mid)
    arc[3] = 1.0 / R
    arc[4] = math.sqrt(sd / tot)
    return True


def blob_inputs(patch, labels, lab, i0, j0, kernel, censor, level, sigma, max_sweep):
    """The blurred-spot fit's inputs for the blob ``lab`` of ``labels`` whose rows i0..,
    columns j0.. ``patch`` [DN] covers, in one pass (what :func:`vision.spot._blur_locate`
    and :func:`vision.blur.fit_blurred_spot` do with some twenty numpy calls): the mask
    (the blob dilated by ``kernel``, as ``cv2.dilate``), its pixels (rows, columns;
    ``np.nonzero``'s order), which of them are clipped (>= ``censor``),
    :func:`start_loops`' rows and the blob's centroid moments: (tot, m_u, m_v, nm) the
    weights' sum [DN] and centre [px] (``start_loops``' first row's) and the pixels'
    squared distances from it summed [px^2] (0s without signal).
    Returns (mask, pi, pj, clipped, starts, moments)."""
    H, W = patch.shape
    mask = _dilate(labels, lab, i0, j0, H, W, kernel)
    n = 0
    for i in range(H):
        for j in range(W):
            if mask[i, j]:
                n += 1
    pi = np.empty(n, np.int64)
    pj = np.empty(n, np.int64)
    clipped = np.zeros(n, np.bool_)
    k = 0
    shrink = 1.0
    for i in range(H):
        for j in range(W):
            if mask[i, j]:
                pi[k] = i
                pj[k] = j
                if patch[i, j] >= censor:
                    clipped[k] = True
                    shrink = 0.8       # a clipped core widens the blob (initial_guesses)
                k += 1
    starts = start_loops(patch, mask, level, sigma, shrink, max_sweep)
    tot = 0.0
    nu = 0.0
    nv = 0.0
    if starts.shape[0]:
        mu = starts[0, 0]
        mv = starts[0, 1]
        for q in range(n):
            x = patch[pi[q], pj[q]] - level
            if x > 0:
                tot += x
            nu += (pj[q] - mu) ** 2
            nv += (pi[q] - mv) ** 2
    else:
        mu = mv = 0.0
    return mask, pi, pj, clipped, starts, (tot, mu, mv, nu + nv)


def _dilate(labels, lab, i0, j0, H, W, kernel):
    """``cv2.dilate`` of the pixels ``lab`` of ``labels[i0:i0 + H, j0:j0 + W]`` by ``kernel``
    (bool, H x W).  A kernel whose rows are runs (an ellipse, a rectangle): a pixel that
    follows one of the blob on its row adds only its runs' right ends."""
    kh, kw = kernel.shape
    kr = kh // 2
    kc = kw // 2
    first = np.full(kh, -1, np.int64)
    last = np.full(kh, -1, np.int64)
    runs = True
    for a in range(kh):
        for b in range(kw):
            if kernel[a, b]:
                if first[a] < 0:
                    first[a] = b
                elif last[a] != b - 1:
                    runs = False
                last[a] = b
    mask = np.zeros((H, W), np.bool_)
    for i in range(H):
        prev = False
        for j in range(W):
            inside = labels[i0 + i, j0 + j] == lab
            if inside:
                for a in range(kh):
                    ii = i - a + kr
                    if first[a] < 0 or ii < 0 or ii >= H:
                        continue
                    if not runs:
                        for b in range(kw):
                            jj = j - b + kc
                            if kernel[a, b] and 0 <= jj < W:
                                mask[ii, jj] = True
                    elif prev:               # the run of (i, j - 1) moved on by one
                        jj = j - first[a] + kc
                        if 0 <= jj < W:
                            mask[ii, jj] = True
                    else:
                        for jj in range(max(j - last[a] + kc, 0),
                                        min(j - first[a] + kc, W - 1) + 1):
                            mask[ii, jj] = True
            prev = inside
    return mask


def compiled_blob_inputs():
    """:func:`blob_inputs` compiled (as :func:`compiled_start`), or None."""
    return _compiled_pair()[1]


def compiled_start():
    """:func:`start_loops` compiled by numba (``cache=True``, ``nogil=True``; numba
    imported on the first call), or None when numba is missing or disabled."""
    return _compiled_pair()[0]


def half_sweep(C, max_sweep):
    """Half the arc's angular sweep b [rad] from the mean resultant length C (1) of its points'
    angles about the circle's centre: sin(b)/b = C by Newton from the small-angle start,
    clipped to ``max_sweep`` [rad] (plain floats: the numpy path calls it as Python)."""
    b = min(math.sqrt(max(6.0 * (1.0 - C), 0.0)), max_sweep)
    for _ in range(8):
        if b < 1e-6:
            break
        fp = (b * math.cos(b) - math.sin(b)) / (b * b)
        if fp == 0:
            break
        b = min(max(b - (math.sin(b) / b - C) / fp, 1e-6), max_sweep)
    return b


@once
def _compiled_pair():
    """(start_loops, blob_inputs) compiled, or (None, None)."""
    numba = numba_or_none()
    if numba is None:
        return (None, None)
    jit = numba.njit(cache=True, error_model="numpy", nogil=True)
    mod = globals()
    for name in ("half_sweep", "_circle", "start_loops", "_dilate"):
        mod[name] = jit(mod[name])
    return (mod["start_loops"], jit(blob_inputs))
