"""Background subtraction for spot tracking: a static screen image taken out of every frame.

A real screen is not uniformly dark: the room light, a reflection of the lamp,
the rings printed on it.  :func:`median_background` estimates that static part
as the per-pixel median of frames spread over the recording (the spot moves,
so at any pixel it is absent from most of them); a dark frame taken with the
laser off does the same job (:func:`vision.io.read_image`).
:func:`subtract_background` takes it out of a frame while keeping what the
tracker needs to know about clipping.

The median needs a moving spot: where the spot stands still in more than half of
the sampled frames, it becomes part of the "background" and is subtracted.
"""
from __future__ import annotations

import numpy as np

__all__ = ["median_background", "background_offsets", "subtract_offsets", "subtract_background",
           "MEDIAN_FRAMES"]

MEDIAN_FRAMES = 25      #: frames spread over the source for the median background


def median_background(frames, count: int = MEDIAN_FRAMES, total=None) -> np.ndarray:
    """Per-pixel median of ``count`` frames spread evenly over ``frames``.

    Parameters
    ----------
    frames : iterable of 2-D arrays
        The frames (each read once, in order; only the chosen ones are kept).
    count : int
        Frames in the median (all of them when there are fewer).
    total : int, optional
        Number of frames, if known: exactly ``count`` frames evenly spaced.  Else
        they are thinned as they come (every 2^k-th frame kept), ending with
        ``count`` to ``2 count`` frames evenly spread; only those are held in memory.

    Returns
    -------
    float32 array (H, W) [DN]

    Raises
    ------
    ValueError
        No frames, or frames of different sizes.
    """
    if count < 1:
        raise ValueError(f"count = {count}: at least 1 frame")
    if total is not None:
        pick = set(np.unique(np.linspace(0, max(int(total) - 1, 0), count).round().astype(int)))
        kept = [np.asarray(f) for i, f in enumerate(frames) if i in pick]
    else:
        kept = []
        step = 1
        for i, f in enumerate(frames):
            if i % step == 0:
                kept.append(np.asarray(f))
                if len(kept) >= 2 * count:      # thin: every other one, and a wider step
                    kept = kept[::2]
                    step *= 2
    if not kept:
        raise ValueError("no frames for the median background")
    shape = kept[0].shape
    if any(k.shape != shape for k in kept):
        raise ValueError("frames of different sizes for the median background")
    return np.median(np.stack(kept).astype(np.float32), axis=0).astype(np.float32)


def background_offsets(background) -> np.ndarray:
    """The background's variation, ``background - min(background)``, as float32 [DN]: what
    :func:`subtract_offsets` takes out of every frame (computed once per recording; crop it
    with the frames for a region of interest)."""
    b = np.asarray(background, dtype=np.float32)
    return b - float(b.min())


def subtract_offsets(frame, offsets, saturation: float, margin: float = 0.0) -> np.ndarray:
    """``frame - offsets`` as float32, clipped pixels kept clipped (:func:`subtract_background`
    with the offsets of :func:`background_offsets`, same shape as the frame)."""
    f = np.asarray(frame)
    if f.shape != offsets.shape:
        raise ValueError(f"background: size {offsets.shape[1]}x{offsets.shape[0]} (W x H) "
                         f"differs from the frame's {f.shape[1]}x{f.shape[0]}")
    out = f.astype(np.float32) - offsets
    out[f >= saturation - margin] = saturation
    return out


def subtract_background(frame, background, saturation: float, margin: float = 0.0) -> np.ndarray:
    """``frame - (background - min(background))`` as float32, clipped pixels kept clipped.

    Subtracting the background's variation (not its level) keeps every value at or
    below the frame's own, so a pixel below full scale stays below it; a pixel at
    full scale (``>= saturation - margin`` in the frame) is set to ``saturation``,
    so that the tracker still treats it as clipped (censored) -- its true value is
    unknown, whatever the background under it.

    Parameters
    ----------
    frame : 2-D array [DN]
    background : 2-D array [DN], the frame's shape
    saturation : float
        Full scale of the frame [DN] (255 for 8-bit video).
    margin : float
        Values this close to full scale count as clipped (lossy video: 250-255).
    """
    return subtract_offsets(frame, background_offsets(background), saturation, margin)
