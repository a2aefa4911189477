"""Background level, noise and full scale of a camera frame, as the spot and trace locators
read them (:func:`vision.spot.locate` step 1, :func:`vision.trace.fit_trace`).

The background is read on the border of the searched region, where the spot is not:
its pixels clipped around their median (+- 5 robust sigma) give the level (their mean,
not quantised like a median) and the noise sigma (their standard deviation: read +
background shot + quantisation noise).  Levels in DN.
"""
from __future__ import annotations

from typing import Optional

import cv2
import numpy as np

__all__ = ["border_pixels", "background_level", "saturation_level", "BORDER"]

BORDER = 2                 #: px, width of the border used for the background


def border_pixels(a: np.ndarray) -> np.ndarray:
    """The pixels of the border of image ``a`` (``BORDER`` px wide; 1 px for tiny images),
    flattened."""
    b = BORDER if min(a.shape) > 2 * BORDER + 2 else 1
    return np.concatenate([a[:b].ravel(), a[-b:].ravel(), a[b:-b, :b].ravel(),
                           a[b:-b, -b:].ravel()])


def background_level(a: np.ndarray) -> tuple[float, float]:
    """(level, sigma) from the border pixels, clipped around the median."""
    x = border_pixels(a).astype(np.float64)
    x.sort()
    med = float(x[x.size // 2])
    d = np.abs(x - med)
    mad = 1.4826 * float(np.partition(d, d.size // 2)[d.size // 2])
    keep = x[d <= max(5.0 * mad, 3.0)]
    if keep.size < 4:
        keep = x
    m, sd = cv2.meanStdDev(keep)     # (one call: small-array numpy overhead dominates here)
    return float(m[0, 0]), float(sd[0, 0])


def saturation_level(frame: np.ndarray, saturation) -> Optional[float]:
    """Full-scale value [DN]: ``saturation`` when given, 255 for uint8 frames, 2**b - 1 for
    uint16 frames whose maximum is such a value (b = 10, 12, 14, 16), else None."""
    if saturation is not None:
        return float(saturation)
    if frame.dtype == np.uint8:
        return 255.0
    if frame.dtype == np.uint16:
        m = int(frame.max())
        for bits in (10, 12, 14, 16):
            if m == (1 << bits) - 1:
                return float(m)
    return None
