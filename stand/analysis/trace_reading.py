"""A long-exposure trace's circle read against the calibration rings (``stand track --trace``).

:func:`vision.trace.fit_trace` measures the circle the whirling spot draws.  A circle
flagged ``"unresolved"`` (radius below :data:`vision.trace.UNRESOLVED_SIGMAS` spot sigmas,
the sigma estimated from the trace itself) is not separable from the spot in one image:
its fitted radius is no measurement, the frame only says that the circle's radius is
below that many sigmas.  The spot's width only inflates the intensity moments (their
``R^2 + 2 s^2``), and a clipped (``"saturated"``) profile inflates them further, so the
bound stays an upper bound where the fitted value does not stand for the radius.

Columns written (screen millimetres through the ring scale, unbalances through the ring
zones i S/16, :func:`dsp.unbalance.unbalance_from_rings`):

* ``radius_mm``, ``radius_std_mm``: the resolved circle's radius and its 1-sigma (pixel
  noise and the ring scale's); NaN for an unresolved frame;
* ``radius_max_mm``: an unresolved frame's upper bound ``UNRESOLVED_SIGMAS x
  spot_sigma_px`` on the screen; NaN for a resolved one;
* with the capacity: ``zone`` (-1: no reading), ``unbalance_gmm`` (the interpolated ring
  reading of the measured radius; NaN when the frame gives only a bound) and
  ``unbalance_max_gmm`` (the reading of ``radius_max_mm``: the unresolved frame's bound).

:func:`settled_circles` reads such a table back (``stand analyze``) as a person reads the
screen once the motion has settled.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

__all__ = ["trace_ring_columns", "unresolved", "settled_circles"]

#: the columns that make a table a trace table (what trace_ring_columns and track_traces write)
TRACE_COLUMNS = ("radius_mm", "radius_px", "spot_sigma_px")
SETTLED_REL = 0.02     #: radii within 2 % of the last frames' median (or 3 of their stds) agree


def unresolved(df) -> np.ndarray:
    """Boolean mask of the frames of a trace table flagged ``"unresolved"``."""
    if "flags" not in df:
        return np.zeros(len(df), bool)
    fl = df["flags"].astype(object).fillna("").astype(str)
    return fl.str.split(",").map(lambda f: "unresolved" in f).to_numpy(bool)


def trace_ring_columns(df, scale_m_per_px: float, scale_std_m_per_px: float, radii_m,
                       capacity_gmm=None) -> None:
    """Add the calibrated trace columns (module docstring) to ``df`` in place.

    Parameters
    ----------
    df : pandas.DataFrame
        :func:`vision.trace.track_traces` table (``radius_px``, ``radius_std_px``,
        ``spot_sigma_px``, ``flags``).
    scale_m_per_px, scale_std_m_per_px : float
        The ring calibration's mean scale [m/px] and its 1-sigma.
    radii_m : array_like
        Ring radii [m], zones 0, 1, 2, ...
    capacity_gmm : float, optional
        Balancer capacity S [g mm]: adds ``zone``, ``unbalance_gmm``, ``unbalance_max_gmm``.
    """
    from dsp.unbalance import unbalance_from_rings
    from vision.trace import UNRESOLVED_SIGMAS

    bound = unresolved(df)
    R = df["radius_px"].to_numpy(float) * scale_m_per_px
    sR = np.hypot(df["radius_std_px"].to_numpy(float) * scale_m_per_px,
                  df["radius_px"].to_numpy(float) * scale_std_m_per_px)   # + the ring scale's
    Rmax = np.where(bound, UNRESOLVED_SIGMAS * df["spot_sigma_px"].to_numpy(float)
                    * scale_m_per_px, np.nan)
    R, sR = np.where(bound, np.nan, R), np.where(bound, np.nan, sR)
    df["radius_mm"], df["radius_std_mm"], df["radius_max_mm"] = R * 1e3, sR * 1e3, Rmax * 1e3
    if capacity_gmm is None:
        return
    S = capacity_gmm * 1e-6

    def reading(r):
        return unbalance_from_rings(r, radii_m, S) if np.isfinite(r) else None

    got = [reading(r) for r in df["radius_mm"].to_numpy() * 1e-3]    # the column's metres
    df["zone"] = [-1 if g is None else g.zone for g in got]
    df["unbalance_gmm"] = [np.nan if g is None else g.interpolated_kg_m * 1e6 for g in got]
    df["unbalance_max_gmm"] = [np.nan if g is None else g.interpolated_kg_m * 1e6
                               for g in map(reading, df["radius_max_mm"].to_numpy() * 1e-3)]


def settled_circles(path, rel_scale, notes):
    """``(radius [m], std [m], n)`` of the settled circles of a trace table, or None.

    The trailing frames in the last frame's state: resolved circles (no ``"unresolved"`` nor
    ``"not_circle"`` flag) each agreeing with the median of those after it (within
    ``SETTLED_REL`` or 3 sqrt(2) of its pixel std), or unresolved ones.  The mean radius,
    its std -- the circles' scatter over sqrt(n) or their pixel std over sqrt(n), whichever is
    larger; NaN for one circle without a std -- and how many.  ``rel_scale``: the ring scale's
    relative std (the header's), taken out of ``radius_std_mm``: the caller adds it once (it
    does not average out).  Settled on unresolved circles: a note with their bound
    (``unbalance_max_gmm``), None; fewer than 3 settled circles: a note.  None for any other
    table (not a CSV, or without :data:`TRACE_COLUMNS`)."""
    import pandas as pd
    from vision.trace import UNRESOLVED_SIGMAS

    if Path(path).suffix.lower() not in (".csv", ".txt"):
        return None
    try:
        if not set(TRACE_COLUMNS) <= set(pd.read_csv(path, comment="#", nrows=0).columns):
            return None
        df = pd.read_csv(path, comment="#")
    except (OSError, ValueError, UnicodeDecodeError):
        return None

    def num(name):
        return (pd.to_numeric(df[name], errors="coerce").to_numpy(float) if name in df
                else np.full(len(df), np.nan))

    r, s, bound = num("radius_mm") * 1e-3, num("radius_std_mm") * 1e-3, num("unbalance_max_gmm")
    s = np.sqrt(np.maximum(s * s - (r * (rel_scale or 0.0)) ** 2, 0.0))     # the pixel part
    ok = (df["ok"].astype(str).str.lower().isin(("true", "1")).to_numpy() if "ok" in df
          else np.ones(len(df), bool))
    off = unresolved(df)
    odd = (df["flags"].astype(object).fillna("").astype(str).str.contains("not_circle").to_numpy()
           if "flags" in df else np.zeros(len(df), bool))
    resolved = np.isfinite(r) & (r >= 0) & ~off & ~odd
    idx = np.flatnonzero(ok & (resolved | off))
    if not idx.size:
        return None
    state = bool(off[idx[-1]])
    keep = [idx[-1]]
    for i in idx[-2::-1]:      # back from the last frame while in its state and, resolved, agreeing
        ref = float(np.median(r[keep])) if not state else math.nan
        if off[i] != state or (not state and abs(r[i] - ref) > max(
                3 * math.sqrt(2) * np.nan_to_num(s[i]), SETTLED_REL * ref)):
            break
        keep.append(i)
    keep = np.array(keep[::-1], dtype=int)
    if state:
        b = bound[keep][np.isfinite(bound[keep])]
        notes.append(f"ring reading: the last {keep.size} circles are unresolved (radius below "
                     f"{UNRESOLVED_SIGMAS:g} spot sigmas)" + (
                         f": the unbalance is below {float(b.max()):.4g} g·mm" if b.size else ""))
        return None
    if keep.size < 3:
        notes.append(f"ring reading: only the last {keep.size} circle(s) agree: the motion may "
                     "not have settled")
    rk, sk = r[keep], s[keep]
    own = (float(np.sqrt(np.nanmean(sk * sk) / rk.size)) if np.isfinite(sk).any()
           and np.nanmax(sk) > 0 else math.nan)
    if rk.size < 2:
        return float(rk[0]), own, 1
    return float(np.mean(rk)), float(np.nanmax([np.std(rk, ddof=1) / math.sqrt(rk.size), own])), \
        int(rk.size)
