"""Motion regime over sliding windows, and critical speeds from a run-down or run-up.

Plain arrays in (times, rotor angle or speed, weight angles when a stroboscope
or weight channel exists, the shaft orbit), results with evidence out.

Regimes (monograph ch. 5; digest ch5 section 0.1):

* ``"main"``           -- weights synchronous with the rotor, rotor balanced
  (the 1X whirl small compared with the reference);
* ``"side"``           -- weights synchronous, rotor left unbalanced;
* ``"quasi-periodic"`` -- weights slipping at a steady mean speed below the
  rotor's (stuck balls);
* ``"transient"``      -- none of these within the window.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .errors import SignalError

__all__ = ["WindowRegime", "motion_regime", "classify_windows", "RegimeChange",
           "critical_speeds", "BANDS", "speed_band"]


@dataclass(frozen=True)
class WindowRegime:
    """The regime of one window, with its evidence."""

    t_start: float
    t_end: float
    regime: str
    rotor_speed_rad_s: float
    weight_slip_rad_s: np.ndarray      #: mean weight speed relative to the rotor, per weight
    slip_spread_rad_s: float           #: spread of the weights' slip speeds
    whirl_m: float                     #: RMS shaft whirl radius in the window
    evidence: dict = field(default_factory=dict)


def motion_regime(rotor_speed, weight_slip, balanced, *, sync_tol: float = 1e-3,
                  spread_tol: float = 1e-2) -> str:
    """The regime from the mean speeds over a window (the one regime rule of the stand).

    * every weight's mean slip below ``sync_tol`` x |rotor speed|: the weights
      are synchronous -> ``"main"`` if ``balanced``, else ``"side"``;
    * else every weight slipping backwards (behind the rotor) with slips that
      differ by less than ``spread_tol`` x |rotor speed|, the rotor turning:
      ``"quasi-periodic"`` (the weights stuck together at a common speed below
      the rotor's);
    * else ``"transient"``.

    Parameters
    ----------
    rotor_speed : float
        Mean rotor speed over the window (rad/s, or any unit, e.g. omega_1).
    weight_slip : array_like (n,)
        Mean speed of each weight relative to the rotor, same unit.
    balanced : bool or callable
        Whether the rotor counts as balanced (e.g. whirl radius below a ring,
        or the residual unbalance at its target); a zero-argument callable is
        evaluated only when the weights are synchronous.
    sync_tol : float
        Relative synchrony tolerance [-].
    spread_tol : float
        Relative spread of the slips of a stuck group [-].

    Returns
    -------
    str
        "main", "side", "quasi-periodic" or "transient".
    """
    slip = np.atleast_1d(np.asarray(weight_slip, dtype=float))
    w = abs(float(rotor_speed))
    scale = max(w, 1e-12)
    if np.all(np.abs(slip) < sync_tol * scale):
        ok = balanced() if callable(balanced) else balanced
        return "main" if ok else "side"
    if np.all(slip < 0) and np.ptp(slip) < spread_tol * scale and w > 0:
        return "quasi-periodic"
    return "transient"


def _check(t, name="t"):
    t = np.asarray(t, float)
    if t.ndim != 1 or t.size < 3:
        raise SignalError(f"{name}: need a 1-D array of at least 3 samples, got shape {t.shape}")
    if not np.all(np.isfinite(t)):
        raise SignalError(f"{name}: contains NaN or inf")
    if np.any(np.diff(t) <= 0):
        raise SignalError(f"{name}: time must be strictly increasing")
    return t


def classify_windows(t, rotor_angle, weight_angle, x, y, window_s: float,
                     balanced_whirl_m: float, sync_tol: float = 1e-3,
                     step_s: float | None = None) -> list:
    """Classify sliding windows of a recording.

    Parameters
    ----------
    t : (N,) s
    rotor_angle : (N,) rad, unwrapped
    weight_angle : (N, n) rad, absolute, unwrapped (stroboscope or weight channel)
    x, y : (N,) m, shaft (or spot / gain) displacement
    window_s : float
        Window length [s]; should cover several revolutions.
    balanced_whirl_m : float
        Whirl radius [m] below which the rotor counts as balanced (e.g. the
        ring of zone 1, S/16, or a fraction of the no-balancer whirl).
    sync_tol : float
        Weights are synchronous when their mean slip is below ``sync_tol`` x
        the rotor speed.
    step_s : float, optional
        Window step [s]; default half a window.

    Each window's regime is :func:`motion_regime` of the mean rotor speed and
    weight slips (from the angle changes over the window), balanced when the
    RMS whirl is below ``balanced_whirl_m``.

    Returns
    -------
    list of WindowRegime
    """
    t = _check(t)
    phi = np.asarray(rotor_angle, float)
    wa = np.asarray(weight_angle, float)
    if wa.ndim == 1:
        wa = wa[:, None]
    for name, a in (("rotor_angle", phi), ("x", np.asarray(x)), ("y", np.asarray(y))):
        if a.shape[0] != t.size or not np.all(np.isfinite(a)):
            raise SignalError(f"{name}: must have {t.size} finite samples (one per time)")
    if wa.shape[0] != t.size or not np.all(np.isfinite(wa)):
        raise SignalError(f"weight_angle: must have {t.size} finite rows (one per time)")
    if not window_s > 0 or window_s > t[-1] - t[0]:
        raise SignalError(f"window_s = {window_s!r}: must be > 0 and at most the record length "
                          f"{t[-1] - t[0]:.6g} s")
    step = window_s / 2 if step_s is None else step_s
    r = np.hypot(np.asarray(x, float), np.asarray(y, float))
    out = []
    t0 = t[0]
    while t0 + window_s <= t[-1] + 1e-12:
        sel = (t >= t0) & (t <= t0 + window_s)
        ts = t[sel]
        dur = ts[-1] - ts[0]
        w = (phi[sel][-1] - phi[sel][0]) / dur
        rel = wa[sel] - phi[sel, None]
        slip = (rel[-1] - rel[0]) / dur
        spread = float(np.ptp(slip))
        whirl = float(np.sqrt(np.mean(r[sel] ** 2)))
        regime = motion_regime(w, slip, whirl < balanced_whirl_m, sync_tol=sync_tol)
        out.append(WindowRegime(float(ts[0]), float(ts[-1]), regime, float(w), slip, spread, whirl,
                                {"sync_tol": sync_tol, "balanced_whirl_m": balanced_whirl_m}))
        t0 += step
    return out


@dataclass(frozen=True)
class RegimeChange:
    """A speed where the regime changes during a run-up or run-down."""

    time_s: float
    speed_hz: float
    speed_hz_uncertainty: float   #: half the speed change over the transition (window resolution)
    before: str
    after: str


def critical_speeds(windows: list, criterion: str = "synchrony") -> list:
    """Speeds where autobalancing is gained or lost along a run-up or run-down.

    Parameters
    ----------
    windows : list of WindowRegime
    criterion : {"synchrony", "balance"}
        "synchrony" (the book's run-down observation, section 5.6: the balls
        fall out of synchrony with the rotor): a change between a synchronous
        regime (main, side) and a slipping one (quasi-periodic, transient).
        "balance": a change between "main" and anything else (the laser circle
        reappears; during a sweep the residual whirl grows before synchrony is
        lost, so this speed is higher on a run-down).

    A change is reported at the mean of the two windows' speeds, with half
    their difference as the uncertainty (run the same rotor up and down to see
    the hysteresis).
    """
    if criterion not in ("synchrony", "balance"):
        raise SignalError(f"criterion = {criterion!r}: must be 'synchrony' or 'balance'")
    good = ({"main", "side"} if criterion == "synchrony" else {"main"})
    out = []
    for a, b in zip(windows[:-1], windows[1:]):
        if (a.regime in good) != (b.regime in good):
            f_a, f_b = a.rotor_speed_rad_s / (2 * np.pi), b.rotor_speed_rad_s / (2 * np.pi)
            out.append(RegimeChange(0.5 * (a.t_end + b.t_start), 0.5 * (f_a + f_b),
                                    0.5 * abs(f_b - f_a), a.regime, b.regime))
    return out


#: speed bands of the monograph's table 4.2, in units of f0
BANDS = (("sub-resonant", 0.0, 0.9), ("near-resonant", 0.9, 1.1), ("supercritical", 1.1, np.inf))


def speed_band(speed_hz: float, f0_hz: float) -> str:
    """Band of table 4.2 for a speed: < 0.9 f0, 0.9-1.1 f0, > 1.1 f0."""
    if not f0_hz > 0:
        raise SignalError(f"f0_hz = {f0_hz!r}: must be > 0")
    r = speed_hz / f0_hz
    return next(name for name, lo, hi in BANDS if lo <= r < hi)
