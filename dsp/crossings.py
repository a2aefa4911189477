"""Frequency from threshold crossings: the pulse-counter / photo-gate method.

Period from threshold crossings, an independent second estimate beside the
free-decay fit (ch5_multiball.md "Pulse counter").  Part of
:mod:`dsp.frequency` (re-exported there).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .errors import SignalError, check_signal, check_times

__all__ = ["CrossingFrequency", "photogate_period", "crossing_times", "frequency_from_crossings"]


@dataclass(frozen=True)
class CrossingFrequency:
    """Frequency from threshold crossings.

    Attributes
    ----------
    frequency_hz, frequency_hz_std : float
        1/period [Hz] and its standard uncertainty.
    period_s, period_s_std : float
        Period [s] and its standard uncertainty.
    n_crossings : int
        Crossings used.
    crossing_times_s : tuple of float
        All crossing times [s].
    rising : tuple of bool
        Direction of each crossing (True = upward).
    """

    frequency_hz: float
    frequency_hz_std: float
    period_s: float
    period_s_std: float
    n_crossings: int
    crossing_times_s: tuple
    rising: tuple


def photogate_period(crossing_times, start=1, stop=3):
    """Period from the ``start``-th to the ``stop``-th threshold crossing (FPM-09).

    The pulse counter of the stand measures the time between the 1st and 3rd
    crossings of a threshold by a free-decay signal (ch5_multiball.md, "Pulse
    counter"): crossings alternate in direction, so crossings ``start`` and
    ``start + 2`` are one period apart.

    Parameters
    ----------
    crossing_times : array_like
        Crossing times [s], alternating directions, strictly increasing.
    start, stop : int
        1-based crossing numbers; ``stop - start`` must be a positive even
        number (a whole number of periods, ``(stop - start) / 2``).

    Returns
    -------
    float
        Period [s].
    """
    start, stop = int(start), int(stop)
    if start < 1 or stop <= start or (stop - start) % 2:
        raise SignalError(f"start={start}, stop={stop}: need 1 <= start < stop with stop - start even "
                          f"(crossings alternate direction)")
    ct = check_times(crossing_times, "crossing_times", min_samples=stop)
    return float((ct[stop - 1] - ct[start - 1]) / ((stop - start) / 2))


def crossing_times(t, x, level=0.0, hysteresis=0.0, method="fit"):
    """Times at which ``x`` crosses ``level``.

    Parameters
    ----------
    t, x : array_like
        Uniformly sampled real signal.
    level : float
        Threshold.
    hysteresis : float
        Schmitt-trigger half width (units of x): a crossing counts only once
        the signal has moved beyond ``level ± hysteresis``; suppresses noise
        chatter.  The reported time is still the crossing of ``level``.
    method : {"fit", "cubic", "linear"}
        "linear"/"cubic": interpolation through the 2/4 samples around the
        crossing (what a hardware gate sees).  "fit" (default): least-squares
        cubic over ±10 % of the typical crossing spacing, which averages
        broadband noise on densely sampled records; its derivative also gives
        a noise-robust slope for the weights.

    Returns
    -------
    times : numpy.ndarray
        Crossing times [s].
    rising : numpy.ndarray of bool
        Direction of each crossing.
    slopes : numpy.ndarray
        |dx/dt| at each crossing (from the interpolant).
    """
    t, x, dt = check_signal(t, x, "x", min_samples=8, allow_complex=False)
    if method not in ("linear", "cubic", "fit"):
        raise SignalError(f"method: must be 'linear', 'cubic' or 'fit', got {method!r}")
    if hysteresis < 0:
        raise SignalError(f"hysteresis: must be >= 0, got {hysteresis}")
    y = x - level
    sgn = y > 0
    idx = np.flatnonzero(sgn[1:] != sgn[:-1])          # crossing between idx, idx+1
    if hysteresis > 0 and idx.size:
        keep = []
        state = None                                   # True = high
        hi = np.flatnonzero(y > hysteresis)
        lo = np.flatnonzero(y < -hysteresis)
        # walk through trigger events in time order
        ev = np.concatenate([hi, lo])
        kind = np.concatenate([np.ones(hi.size, bool), np.zeros(lo.size, bool)])
        o = np.argsort(ev, kind="stable")
        ev, kind = ev[o], kind[o]
        change = np.flatnonzero(np.concatenate([[True], kind[1:] != kind[:-1]]))
        for j in change:
            new = bool(kind[j])
            if state is not None and new != state:
                # last level crossing before this trigger in that direction
                k = np.searchsorted(idx, ev[j]) - 1
                while k >= 0 and bool(sgn[idx[k] + 1]) != new:
                    k -= 1
                if k >= 0 and (not keep or idx[k] > keep[-1]):
                    keep.append(idx[k])
            state = new
        idx = np.asarray(keep, dtype=int)
    times, slopes = [], []
    if method == "fit":
        gap = np.diff(idx)
        spacing = float(np.median(gap)) if gap.size else float(y.size)
        m = int(max(2, round(0.1 * spacing)))
    for i in idx:
        if method == "fit":
            j0, j1 = max(0, i - m + 1), min(y.size, i + m + 1)
            jj = np.arange(j0, j1) - i
            c1 = np.polyfit(jj, y[j0:j1], 1)
            slope = abs(c1[0]) / dt
            u = -c1[1] / c1[0] if c1[0] != 0 else y[i] / (y[i] - y[i + 1])
            if j1 - j0 >= 8:
                c3 = np.polyfit(jj, y[j0:j1], 3)
                roots = np.roots(c3)
                roots = roots[(np.abs(roots.imag) < 1e-9) & (roots.real >= jj[0]) & (roots.real <= jj[-1])].real
                if roots.size:
                    u = float(roots[np.argmin(np.abs(roots - u))])
            if not jj[0] <= u <= jj[-1]:
                u = y[i] / (y[i] - y[i + 1])
            times.append(t[i] + u * dt)
            slopes.append(slope)
            continue
        if method == "cubic" and 1 <= i and i + 2 < y.size:
            ii = np.arange(i - 1, i + 3)
            c = np.polyfit(ii - i, y[ii], 3)
            roots = np.roots(c)
            roots = roots[(np.abs(roots.imag) < 1e-9) & (roots.real >= -1e-9) & (roots.real <= 1 + 1e-9)].real
            if roots.size:
                u = float(roots[np.argmin(np.abs(roots - y[i] / (y[i] - y[i + 1])))])
                times.append(t[i] + u * dt)
                slopes.append(abs(np.polyval(np.polyder(c), u)) / dt)
                continue
        u = y[i] / (y[i] - y[i + 1])
        times.append(t[i] + u * dt)
        slopes.append(abs(y[i + 1] - y[i]) / dt)
    return np.asarray(times), sgn[idx + 1].astype(bool), np.asarray(slopes)


def frequency_from_crossings(t, x, level=0.0, hysteresis=0.0, method="fit"):
    """Frequency from successive same-direction crossings of ``level``.

    Rising crossings ``t = t_up + k T`` and falling crossings
    ``t = t_down + k T`` are fitted jointly by weighted least squares (common
    period ``T``; weight ∝ slope², since a crossing's timing error is
    noise / |dx/dt|).  The scatter of the residuals gives the standard
    uncertainty.  Independent of :func:`free_decay` (no model of the decay).

    Parameters
    ----------
    t, x : array_like
        Uniformly sampled real signal.
    level, hysteresis, method
        See :func:`crossing_times`.

    Returns
    -------
    CrossingFrequency
    """
    ct, rising, slope = crossing_times(t, x, level, hysteresis, method)
    nu, nd = int(rising.sum()), int((~rising).sum())
    if max(nu, nd) < 2 or ct.size < 3:
        raise SignalError(f"x: only {ct.size} crossing(s) of level {level} "
                          f"({nu} rising, {nd} falling); need two in the same direction")
    k = np.zeros(ct.size)
    k[rising] = np.arange(nu)
    k[~rising] = np.arange(nd)
    cols = [k]
    if nu:
        cols.append(rising.astype(float))
    if nd:
        cols.append((~rising).astype(float))
    A = np.column_stack(cols)
    w = slope / slope.max()
    sol, *_ = np.linalg.lstsq(A * w[:, None], ct * w, rcond=None)
    T = float(sol[0])
    r = (ct - A @ sol) * w
    dof = ct.size - A.shape[1]
    if dof > 0:
        s2 = float(r @ r) / dof
        cov = s2 * np.linalg.inv((A * w[:, None]).T @ (A * w[:, None]))
        Ts = float(math.sqrt(max(cov[0, 0], 0.0)))
    else:
        Ts = float("nan")
    return CrossingFrequency(frequency_hz=1.0 / T, frequency_hz_std=Ts / T ** 2, period_s=T,
                             period_s_std=Ts, n_crossings=int(ct.size),
                             crossing_times_s=tuple(ct.tolist()), rising=tuple(rising.tolist()))
