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
"""
from __future__ import annotations

import numpy as np

__all__ = ["trace_ring_columns", "unresolved"]


def unresolved(df) -> np.ndarray:
    """Boolean mask of the frames of a trace table flagged ``"unresolved"``."""
    if "flags" not in df:
        return np.zeros(len(df), bool)
    fl = df["flags"].fillna("").astype(str)
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
