"""Sub-pixel centre of a spot in a window: the centroid estimators of :func:`vision.spot.locate`.

:func:`recentre` iterates the intensity-weighted centroid in a *soft-edged* window
(pixel weight = the fraction of the pixel inside the window, :func:`soft`, so the
window moves continuously and its fixed point is unbiased for a symmetric spot);
:func:`gauss_centroid` is the Gaussian-weighted centroid (the matched filter) of
width :func:`spot_sigma`, solved by Newton steps (module docstring of
:mod:`vision.spot`, step 4).  Pixel convention as :mod:`vision.spot`: u = column,
v = row, pixel centres at integer coordinates; lengths in px, levels in DN.
"""
from __future__ import annotations

import math

import numpy as np

__all__ = ["soft", "recentre", "gauss_weights", "spot_sigma", "gauss_centroid", "TOL",
           "GAUSS_HALF"]

MAX_ITER = 30
TOL = 1e-4                 #: px
GAUSS_HALF = 3.5           #: window half-width of the Gaussian-weighted centroid [s]
NEWTON_TOL = 3e-3          #: px, last Newton step of the Gaussian-weighted centroid


def soft(x: np.ndarray, h: float) -> np.ndarray:
    """Fraction of pixel [x - 0.5, x + 0.5] inside [-h, h]."""
    w = h + 0.5 - np.abs(x)
    np.minimum(w, 1.0, out=w)
    np.maximum(w, 0.0, out=w)
    return w


def recentre(img, level, cu, cv, hu, hv, sel=None, tol=TOL):
    """Iterate the soft-windowed intensity centroid until it moves < TOL px.

    ``sel`` (same shape as ``img``) restricts the pixels (an arc's neighbourhood).
    Returns the centre (u, v), or None when the window holds no signal.
    """
    Hs, Ws = img.shape
    for _ in range(MAX_ITER):
        i0 = max(int(math.floor(cv - hv - 0.5)), 0)
        i1 = min(int(math.ceil(cv + hv + 0.5)), Hs - 1)
        j0 = max(int(math.floor(cu - hu - 0.5)), 0)
        j1 = min(int(math.ceil(cu + hu + 0.5)), Ws - 1)
        if i1 < i0 or j1 < j0:
            return None
        patch = img[i0:i1 + 1, j0:j1 + 1] - level
        if sel is not None:
            patch = patch * sel[i0:i1 + 1, j0:j1 + 1]
        xu = np.arange(j0, j1 + 1) - cu
        xv = np.arange(i0, i1 + 1) - cv
        pw = patch * soft(xv, hv)[:, None] * soft(xu, hu)[None, :]
        total = float(pw.sum())
        if not total > 0:
            return None
        du = float((pw.sum(axis=0) * xu).sum()) / total
        dv = float((pw.sum(axis=1) * xv).sum()) / total
        cu += du
        cv += dv
        if abs(du) < tol and abs(dv) < tol:
            break
    return cu, cv


def gauss_weights(x: np.ndarray, s: float, h: float) -> np.ndarray:
    """Gaussian weight of width ``s`` times the soft window of half-width ``h``."""
    return np.exp(-0.5 * (x / s) ** 2) * soft(x, h)


def spot_sigma(img, level, cu, cv, h) -> float:
    """Spot sigma [px] from the second moment inside a soft window (``h`` px)."""
    Hs, Ws = img.shape
    i0, i1 = max(int(cv - h - 1), 0), min(int(cv + h + 1) + 1, Hs - 1)
    j0, j1 = max(int(cu - h - 1), 0), min(int(cu + h + 1) + 1, Ws - 1)
    p = img[i0:i1 + 1, j0:j1 + 1] - level
    xu = np.arange(j0, j1 + 1) - cu
    xv = np.arange(i0, i1 + 1) - cv
    pw = p * soft(xv, h)[:, None] * soft(xu, h)[None, :]
    tot = float(pw.sum())
    if not tot > 0:
        return math.nan
    m2 = (float((pw.sum(axis=0) * xu * xu).sum()) + float((pw.sum(axis=1) * xv * xv).sum())) / (2 * tot)
    # a Gaussian cut at +-h has a second moment below sigma^2; for h = 3 sigma by 2.6 %
    return math.sqrt(m2 / 0.974) if m2 > 0 else math.nan


def gauss_centroid(img, level, cu, cv, s):
    """Newton solution of sum g (x - c) I = 0 with Gaussian weights g of width s."""
    Hs, Ws = img.shape
    h = GAUSS_HALF * s
    for _ in range(MAX_ITER):
        i0 = int(math.floor(cv - h - 0.5))
        i1 = int(math.ceil(cv + h + 0.5))
        j0 = int(math.floor(cu - h - 0.5))
        j1 = int(math.ceil(cu + h + 0.5))
        if i0 < 0 or j0 < 0 or i1 > Hs - 1 or j1 > Ws - 1:
            return None
        p = img[i0:i1 + 1, j0:j1 + 1] - level
        xu = np.arange(j0, j1 + 1) - cu
        xv = np.arange(i0, i1 + 1) - cv
        gu = gauss_weights(xu, s, h)
        gv = gauss_weights(xv, s, h)
        pu = (p * gv[:, None]).sum(axis=0) * gu      # = sum over rows of g I
        pv = (p * gu[None, :]).sum(axis=1) * gv
        tot = float(pu.sum())
        if not tot > 0:
            return None
        Du = tot - float((pu * xu * xu).sum()) / (s * s)
        Dv = tot - float((pv * xv * xv).sum()) / (s * s)
        if not (Du > 0 and Dv > 0):
            return None
        du = float((pu * xu).sum()) / Du
        dv = float((pv * xv).sum()) / Dv
        if abs(du) > s or abs(dv) > s:
            return None
        cu += du
        cv += dv
        if abs(du) < NEWTON_TOL and abs(dv) < NEWTON_TOL:   # quadratic: error ~ step^2
            return cu, cv
    return cu, cv
